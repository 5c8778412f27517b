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
                "solve [--repeat=N] FILE\n"
                "cpa CNX CNY CNH CNV OSX OSY OSH OSV [TOL]",
    .opts = (const kelp_cli_opt[]){
        { "repeat", required_argument, 'r', "N", "solve: solve N times (timing)" },
        { NULL, 0, 0, NULL, NULL } },
    .more = "DOMAIN: name:low:high:points[,name:low:high:points]...\n"
            "SPEC:   peak(summit=S,peakwidth=P,basewidth=B,summitdelta=D,minutil=m,maxutil=M[,wrap][,insist][,sum])\n"
            "        [+peak(...)]... | leq(summit=S,basewidth=B,minutil=m,maxutil=M[,summitdelta=D]) | heq(...)\n"
            "CPA:    contact and ownship x, y (m), heading (deg), speed (m/s); TOL horizon s (default 120,\n"
            "        <= 0 none); prints name=value lines (cpa, tcpa, roc, range, bearing_rate, ...)\n"
            "Put -- before arguments that begin with '-'.\n",
};

int kivp_usage(void)
{
    kelp_cli_usage(&cli, stderr);
    return kelp_cli_error(&cli, "wrong arguments");
}

int kivp_fail(const char *where, const kelp_diag *d, int rc)
{
    fprintf(stderr, "kelp-ivp: %s%s%s\n", where ? where : "", where ? ": " : "",
            d && d->code != KELP_OK ? kelp_diag_text(d) : kelp_err_str(rc));
    return 1;
}

void *kivp_xcalloc(size_t n, size_t sz)
{
    void *p = calloc(n ? n : 1, sz ? sz : 1);
    if (!p) {
        fprintf(stderr, "kelp-ivp: out of memory\n");
        exit(1);
    }
    return p;
}

/* Build one spec over var of dom into freshly allocated storage. */
int kivp_build_spec(const kelp_ivp_spec *sp, const kelp_ivp_domain *dom, const char *var, kelp_ivp_func *f,
                      kelp_diag *d)
{
    size_t cap = kelp_ivp_spec_max_pieces(sp, dom, var);
    int ix = kelp_ivp_domain_index(dom, var);
    size_t wl = ix >= 0 ? dom->var[ix].points : 1;
    kelp_ivp_piece *st = kivp_xcalloc(cap, sizeof *st);
    double *work = kivp_xcalloc(wl, sizeof *work);
    kelp_ivp_spec_ws *zws = kivp_xcalloc(1, sizeof *zws);
    int rc = kelp_ivp_spec_build(sp, dom, var, work, wl, zws, st, cap, f, d);
    free(zws);
    free(work);
    if (rc)
        free(st);
    return rc;
}

int kivp_print_points(const kelp_ivp_func *f)
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
        return kivp_usage();
    kelp_diag err = {0};
    kelp_ivp_domain dom;
    kelp_ivp_spec sp;
    int rc = kelp_ivp_domain_parse(&dom, argv[2], &err);
    if (rc)
        return kivp_fail("DOMAIN", &err, rc);
    if (dom.dim != 1) {
        fprintf(stderr, "kelp-ivp: eval needs a one-variable DOMAIN, got '%s'\n", argv[2]);
        return 1;
    }
    if ((rc = kelp_ivp_spec_parse(&sp, argv[3], &err)))
        return kivp_fail("SPEC", &err, rc);
    kelp_ivp_func f;
    if ((rc = kivp_build_spec(&sp, &dom, dom.var[0].name, &f, &err)))
        return kivp_fail("SPEC", &err, rc);
    kivp_print_points(&f);
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
int kivp_build_couple(const kelp_ivp_domain *dom, const kelp_ivp_spec *a, const kelp_ivp_spec *b, double wc, double ws,
                        kelp_ivp_func *out, kelp_diag *d)
{
    int vc, vs;
    if (kelp_ivp_couple_vars(dom, &vc, &vs)) {
        (void)kelp_fail(d, KELP_ERR_RANGE, "couple needs a domain with two variables");
        return KELP_ERR_RANGE;
    }
    kelp_ivp_func fc, fs;
    int rc = kivp_build_spec(a, dom, dom->var[vc].name, &fc, d);
    if (rc)
        return rc;
    if ((rc = kivp_build_spec(b, dom, dom->var[vs].name, &fs, d))) {
        free(fc.pcs);
        return rc;
    }
    size_t cap = fc.n * fs.n;
    kelp_ivp_piece *st = kivp_xcalloc(cap, sizeof *st);
    rc = kelp_ivp_couple(&fc, wc, &fs, ws, true, 0, 100, st, cap, out);
    free(fc.pcs);
    free(fs.pcs);
    if (rc) {
        free(st);
        (void)kelp_failf(d, rc, "couple failed: %s", kelp_err_str(rc));
    }
    return rc;
}

static int cmd_couple(int argc, char **argv)
{
    if (argc != 7)
        return kivp_usage();
    kelp_diag err = {0};
    kelp_ivp_domain dom;
    kelp_ivp_spec a, b;
    double wc, ws;
    int rc = kelp_ivp_domain_parse(&dom, argv[2], &err);
    if (rc)
        return kivp_fail("DOMAIN2", &err, rc);
    if (dom.dim != 2) {
        fprintf(stderr, "kelp-ivp: couple needs a two-variable DOMAIN2, got '%s'\n", argv[2]);
        return 1;
    }
    if ((rc = kelp_ivp_spec_parse(&a, argv[3], &err)))
        return kivp_fail("CRS_SPEC", &err, rc);
    if ((rc = kelp_ivp_spec_parse(&b, argv[4], &err)))
        return kivp_fail("SPD_SPEC", &err, rc);
    if (parse_weight(argv[5], &wc, "WC") || parse_weight(argv[6], &ws, "WS"))
        return 1;
    kelp_ivp_func f;
    if ((rc = kivp_build_couple(&dom, &a, &b, wc, ws, &f, &err)))
        return kivp_fail("couple", &err, rc);
    /* print in DOMAIN2 order: the coupled function's variables are crs then spd */
    kelp_ivp_func g = f;
    if ((rc = kelp_ivp_func_align(&g, &dom)))
        return kivp_fail("couple", NULL, rc);
    kivp_print_points(&g);
    free(f.pcs);
    return 0;
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
        return kivp_usage();
    if (strcmp(argv[1], "eval") == 0)
        return cmd_eval(argc, argv);
    if (strcmp(argv[1], "couple") == 0)
        return cmd_couple(argc, argv);
    if (strcmp(argv[1], "solve") == 0)
        return kivp_cmd_solve(argc, argv, repeat);
    if (strcmp(argv[1], "cpa") == 0)
        return kivp_cmd_cpa(argc, argv);
    return kelp_cli_error(&cli, "unknown command '%s'", argv[1]);
}
