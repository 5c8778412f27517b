/* kelp-ivp command implementation (apps may allocate: storage is sized with the core's queries). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/edge/cli.h>
#include <kelp/ivp.h>
#include "cli.h"

static const kelp_cli cli = {
    .name = "kelp-ivp",
    .purpose = "Build, inspect and solve IvP functions from the command line.",
    .synopsis = "eval DOMAIN SPEC\n"
                "couple DOMAIN2 CRS_SPEC SPD_SPEC WC WS\n"
                "solve [--repeat=N] FILE",
    .opts = (const kelp_cli_opt[]){
        { "repeat", required_argument, 'r', "N", "solve: solve N times (timing)" },
        { NULL, 0, 0, NULL, NULL } },
    .more = "DOMAIN: name:low:high:points[,name:low:high:points]...\n"
            "SPEC:   peak(summit=S,peakwidth=P,basewidth=B,summitdelta=D,minutil=m,maxutil=M[,wrap][,insist][,sum])\n"
            "        [+peak(...)]... | leq(summit=S,basewidth=B,minutil=m,maxutil=M[,summitdelta=D]) | heq(...)\n"
            "Put -- before arguments that begin with '-'.\n",
};

static int usage(void)
{
    kelp_cli_usage(&cli, stderr);
    return kelp_cli_error(&cli, "wrong arguments");
}

static int fail(const char *where, const kelp_ivp_errbuf *e, int rc)
{
    fprintf(stderr, "kelp-ivp: %s%s%s\n", where ? where : "", where ? ": " : "",
            e && e->msg[0] ? e->msg : kelp_strerror(rc));
    return 1;
}

static void *xcalloc(size_t n, size_t sz)
{
    void *p = calloc(n ? n : 1, sz ? sz : 1);
    if (!p) {
        fprintf(stderr, "kelp-ivp: out of memory\n");
        exit(1);
    }
    return p;
}

/* Build one spec over var of dom into freshly allocated storage. */
static int build_spec(const kelp_ivp_spec *sp, const kelp_ivp_domain *dom, const char *var, kelp_ivp_func *f,
                      kelp_ivp_errbuf *err)
{
    size_t cap = kelp_ivp_spec_max_pieces(sp, dom, var);
    int ix = kelp_ivp_domain_index(dom, var);
    size_t wl = ix >= 0 ? dom->var[ix].points : 1;
    kelp_ivp_piece *st = xcalloc(cap, sizeof *st);
    double *work = xcalloc(wl, sizeof *work);
    int rc = kelp_ivp_spec_build(sp, dom, var, work, wl, st, cap, f, err);
    free(work);
    if (rc)
        free(st);
    return rc;
}

static int print_points(const kelp_ivp_func *f)
{
    printf("pieces %zu\n", f->n);
    const kelp_ivp_domain *d = &f->dom;
    uint32_t ix[KELP_IVP_MAX_DIM] = {0};
    for (;;) {
        double v;
        int rc = kelp_ivp_func_eval(f, ix, &v);
        for (unsigned e = 0; e < d->dim; e++)
            printf("%u ", ix[e]);
        if (rc == 0)
            printf("%.17g\n", v);
        else
            printf("-\n");
        int e = (int)d->dim - 1;
        for (; e >= 0; e--) {
            if (++ix[e] < d->var[e].points)
                break;
            ix[e] = 0;
        }
        if (e < 0)
            break;
    }
    return 0;
}

static int cmd_eval(int argc, char **argv)
{
    if (argc != 4)
        return usage();
    kelp_ivp_errbuf err = {""};
    kelp_ivp_domain dom;
    kelp_ivp_spec sp;
    int rc = kelp_ivp_domain_parse(&dom, argv[2], &err);
    if (rc)
        return fail("DOMAIN", &err, rc);
    if (dom.dim != 1) {
        fprintf(stderr, "kelp-ivp: eval needs a one-variable DOMAIN, got '%s'\n", argv[2]);
        return 1;
    }
    if ((rc = kelp_ivp_spec_parse(&sp, argv[3], &err)))
        return fail("SPEC", &err, rc);
    kelp_ivp_func f;
    if ((rc = build_spec(&sp, &dom, dom.var[0].name, &f, &err)))
        return fail("SPEC", &err, rc);
    print_points(&f);
    free(f.pcs);
    return 0;
}

static int parse_weight(const char *s, double *w, const char *what)
{
    char *end;
    *w = strtod(s, &end);
    if (end == s || *end != '\0' || !(*w > 0)) {
        fprintf(stderr, "kelp-ivp: %s must be a number > 0, got '%s'\n", what, s);
        return 1;
    }
    return 0;
}

/* Couple crs (over var vc) and spd (over vs) with weights, normalised to [0,100]. */
static int build_couple(const kelp_ivp_domain *dom, const kelp_ivp_spec *a, const kelp_ivp_spec *b, double wc, double ws,
                        kelp_ivp_func *out, kelp_ivp_errbuf *err)
{
    int vc, vs;
    if (kelp_ivp_couple_vars(dom, &vc, &vs)) {
        snprintf(err->msg, sizeof err->msg, "couple needs a domain with two variables");
        return KELP_ERR_RANGE;
    }
    kelp_ivp_func fc, fs;
    int rc = build_spec(a, dom, dom->var[vc].name, &fc, err);
    if (rc)
        return rc;
    if ((rc = build_spec(b, dom, dom->var[vs].name, &fs, err))) {
        free(fc.pcs);
        return rc;
    }
    size_t cap = fc.n * fs.n;
    kelp_ivp_piece *st = xcalloc(cap, sizeof *st);
    rc = kelp_ivp_couple(&fc, wc, &fs, ws, true, 0, 100, st, cap, out);
    free(fc.pcs);
    free(fs.pcs);
    if (rc) {
        free(st);
        snprintf(err->msg, sizeof err->msg, "couple failed: %s", kelp_strerror(rc));
    }
    return rc;
}

static int cmd_couple(int argc, char **argv)
{
    if (argc != 7)
        return usage();
    kelp_ivp_errbuf err = {""};
    kelp_ivp_domain dom;
    kelp_ivp_spec a, b;
    double wc, ws;
    int rc = kelp_ivp_domain_parse(&dom, argv[2], &err);
    if (rc)
        return fail("DOMAIN2", &err, rc);
    if (dom.dim != 2) {
        fprintf(stderr, "kelp-ivp: couple needs a two-variable DOMAIN2, got '%s'\n", argv[2]);
        return 1;
    }
    if ((rc = kelp_ivp_spec_parse(&a, argv[3], &err)))
        return fail("CRS_SPEC", &err, rc);
    if ((rc = kelp_ivp_spec_parse(&b, argv[4], &err)))
        return fail("SPD_SPEC", &err, rc);
    if (parse_weight(argv[5], &wc, "WC") || parse_weight(argv[6], &ws, "WS"))
        return 1;
    kelp_ivp_func f;
    if ((rc = build_couple(&dom, &a, &b, wc, ws, &f, &err)))
        return fail("couple", &err, rc);
    /* print in DOMAIN2 order: the coupled function's variables are crs then spd */
    kelp_ivp_func g = f;
    if ((rc = kelp_ivp_func_align(&g, &dom)))
        return fail("couple", NULL, rc);
    print_points(&g);
    free(f.pcs);
    return 0;
}

static char *read_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        fprintf(stderr, "kelp-ivp: cannot open '%s'\n", path);
        return NULL;
    }
    size_t cap = 65536, len = 0;
    char *buf = xcalloc(cap + 1, 1);
    for (;;) {
        size_t n = fread(buf + len, 1, cap - len, fp);
        len += n;
        if (len < cap)
            break;
        cap *= 2;
        char *nb = realloc(buf, cap + 1);
        if (!nb) {
            free(buf);
            fclose(fp);
            fprintf(stderr, "kelp-ivp: out of memory\n");
            return NULL;
        }
        buf = nb;
    }
    fclose(fp);
    buf[len] = '\0';
    if (memchr(buf, '\0', len)) {
        fprintf(stderr, "kelp-ivp: '%s' is not a text file\n", path);
        free(buf);
        return NULL;
    }
    return buf;
}

/* Next meaningful line (skips blank and #-comment lines); NUL-terminates it in place. */
static char *next_line(char **cur, unsigned *lineno)
{
    while (**cur) {
        char *s = *cur;
        char *nl = strchr(s, '\n');
        if (nl) {
            *nl = '\0';
            *cur = nl + 1;
        } else {
            *cur = s + strlen(s);
        }
        (*lineno)++;
        char *t = s;
        while (*t == ' ' || *t == '\t' || *t == '\r')
            t++;
        if (*t == '\0' || *t == '#')
            continue;
        return s;
    }
    return NULL;
}

static int cmd_solve(int argc, char **argv, long repeat)
{
    const char *path = NULL;
    for (int i = 2; i < argc; i++) {
        if (!path) {
            path = argv[i];
        } else {
            fprintf(stderr, "kelp-ivp: unexpected argument '%s'\n", argv[i]);
            return 1;
        }
    }
    if (!path)
        return usage();
    char *text = read_file(path);
    if (!text)
        return 1;
    char *cur = text;
    unsigned lineno = 0;
    char where[512];
    kelp_ivp_errbuf err = {""};
    kelp_ivp_domain dom;
    int rc, status = 1;
    size_t nf = 0;
    kelp_ivp_func *fs = xcalloc(KELP_IVP_MAX_FUNCS, sizeof *fs);
    char *line = next_line(&cur, &lineno);
    if (!line) {
        fprintf(stderr, "kelp-ivp: %s: empty file\n", path);
        goto out;
    }
    snprintf(where, sizeof where, "%s:%u", path, lineno);
    if ((rc = kelp_ivp_file_domain(line, &dom, &err))) {
        fail(where, &err, rc);
        goto out;
    }
    while ((line = next_line(&cur, &lineno))) {
        snprintf(where, sizeof where, "%s:%u", path, lineno);
        if (nf >= KELP_IVP_MAX_FUNCS) {
            fprintf(stderr, "kelp-ivp: %s: more than %d functions\n", where, KELP_IVP_MAX_FUNCS);
            goto out;
        }
        kelp_ivp_fileline fl;
        if ((rc = kelp_ivp_file_line(line, &dom, &fl, &err))) {
            fail(where, &err, rc);
            goto out;
        }
        kelp_ivp_func *f = &fs[nf];
        if (fl.kind == KELP_IVP_LINE_COUPLE) {
            rc = build_couple(&dom, &fl.a, &fl.b, fl.wc, fl.ws, f, &err);
        } else if (fl.kind == KELP_IVP_LINE_SPEC) {
            rc = build_spec(&fl.a, &dom, fl.var, f, &err);
        } else {
            kelp_ivp_domain sub;
            kelp_ivp_domain_init(&sub);
            for (unsigned v = 0; v < fl.nvars; v++) {
                const kelp_ivp_var *x = &dom.var[fl.vars[v]];
                if (kelp_ivp_domain_add(&sub, x->name, x->low, x->high, x->points))
                    break;
            }
            if (fl.npieces > 10000000ul) {
                fprintf(stderr, "kelp-ivp: %s: too many raw pieces %lu\n", where, fl.npieces);
                goto out;
            }
            kelp_ivp_piece *st = xcalloc(fl.npieces, sizeof *st);
            if ((rc = kelp_ivp_func_init(f, &sub, st, fl.npieces))) {
                free(st);
                fail(where, NULL, rc);
                goto out;
            }
            for (unsigned long k = 0; k < fl.npieces; k++) {
                char *pl = next_line(&cur, &lineno);
                snprintf(where, sizeof where, "%s:%u", path, lineno);
                if (!pl) {
                    fprintf(stderr, "kelp-ivp: %s: file ends after %lu of %lu raw piece lines\n", where, k, fl.npieces);
                    free(st);
                    goto out;
                }
                if ((rc = kelp_ivp_file_piece(pl, fl.nvars, f, &err))) {
                    free(st);
                    fail(where, &err, rc);
                    goto out;
                }
            }
            rc = 0;
        }
        if (rc) {
            fail(where, &err, rc);
            goto out;
        }
        f->pwt = fl.pwt;
        nf++;
    }
    {
        kelp_ivp_problem *prob = xcalloc(1, sizeof *prob);
        kelp_ivp_result res = {0};
        void *work = NULL;
        size_t wsz = 0;
        for (long r = 0; r < repeat; r++) {
            kelp_ivp_problem_init(prob, &dom);
            for (size_t i = 0; i < nf; i++) {
                if ((rc = kelp_ivp_problem_add(prob, &fs[i]))) {
                    fail(path, &prob->err, rc);
                    free(prob);
                    free(work);
                    goto out;
                }
            }
            if (!work) {
                wsz = kelp_ivp_solve_work_size(prob);
                work = xcalloc(wsz, 1);
            }
            if ((rc = kelp_ivp_solve(prob, work, wsz, &res))) {
                fail(path, &prob->err, rc);
                free(prob);
                free(work);
                goto out;
            }
        }
        printf("decision");
        for (unsigned e = 0; e < dom.dim; e++)
            printf(" %s=%.17g", dom.var[e].name, res.val[e]);
        printf(" value=%.17g\n", res.value);
        printf("index");
        for (unsigned e = 0; e < dom.dim; e++)
            printf(" %s=%u", dom.var[e].name, res.ix[e]);
        printf("\n");
        free(prob);
        free(work);
        status = 0;
    }
out:
    for (size_t i = 0; i < nf; i++)
        free(fs[i].pcs);
    free(fs);
    free(text);
    return status;
}

int kelp_ivp_cli(int argc, char **argv)
{
    long repeat = 1;
    int opt, status;
    while ((opt = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        if (opt == KELP_CLI_EXIT) return status;
        if (opt == 'r') {
            char *end;
            repeat = strtol(optarg, &end, 10);
            if (*end || end == optarg || repeat < 1) return kelp_cli_error(&cli, "bad --repeat count '%s'", optarg);
        }
    }
    argc -= optind - 1; /* from here argv[1] is the command */
    argv += optind - 1;
    if (argc < 2)
        return usage();
    if (strcmp(argv[1], "eval") == 0)
        return cmd_eval(argc, argv);
    if (strcmp(argv[1], "couple") == 0)
        return cmd_couple(argc, argv);
    if (strcmp(argv[1], "solve") == 0)
        return cmd_solve(argc, argv, repeat);
    return kelp_cli_error(&cli, "unknown command '%s'", argv[1]);
}
