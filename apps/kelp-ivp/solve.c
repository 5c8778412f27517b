/* kelp-ivp solve: a problem file (a domain and weighted functions) solved by the IvP solver. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/edge/cli.h>
#include <kelp/ivp.h>
#include "cli.h"

static char *read_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        fprintf(stderr, "kelp-ivp: cannot open '%s'\n", path);
        return NULL;
    }
    size_t cap = 65536, len = 0;
    char *buf = kivp_xcalloc(cap + 1, 1);
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

int kivp_cmd_solve(int argc, char **argv, long repeat)
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
        return kivp_usage();
    char *text = read_file(path);
    if (!text)
        return 1;
    char *cur = text;
    unsigned lineno = 0;
    char where[512];
    kelp_diag err = {0};
    kelp_ivp_domain dom;
    int rc, status = 1;
    size_t nf = 0;
    kelp_ivp_func *fs = kivp_xcalloc(KELP_IVP_MAX_FUNCS, sizeof *fs);
    char *line = next_line(&cur, &lineno);
    if (!line) {
        fprintf(stderr, "kelp-ivp: %s: empty file\n", path);
        goto out;
    }
    snprintf(where, sizeof where, "%s:%u", path, lineno);
    if ((rc = kelp_ivp_file_domain(line, &dom, &err))) {
        kivp_fail(where, &err, rc);
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
            kivp_fail(where, &err, rc);
            goto out;
        }
        kelp_ivp_func *f = &fs[nf];
        if (fl.kind == KELP_IVP_LINE_COUPLE) {
            rc = kivp_build_couple(&dom, &fl.a, &fl.b, fl.wc, fl.ws, f, &err);
        } else if (fl.kind == KELP_IVP_LINE_SPEC) {
            rc = kivp_build_spec(&fl.a, &dom, fl.var, f, &err);
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
            kelp_ivp_piece *st = kivp_xcalloc(fl.npieces, sizeof *st);
            if ((rc = kelp_ivp_func_init(f, &sub, st, fl.npieces))) {
                free(st);
                kivp_fail(where, NULL, rc);
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
                    kivp_fail(where, &err, rc);
                    goto out;
                }
            }
            rc = 0;
        }
        if (rc) {
            kivp_fail(where, &err, rc);
            goto out;
        }
        f->pwt = fl.pwt;
        nf++;
    }
    {
        kelp_ivp_problem *prob = kivp_xcalloc(1, sizeof *prob);
        kelp_ivp_result res = {0};
        void *work = NULL;
        size_t wsz = 0;
        for (long r = 0; r < repeat; r++) {
            kelp_ivp_problem_init(prob, &dom);
            for (size_t i = 0; i < nf; i++) {
                if ((rc = kelp_ivp_problem_add(prob, &fs[i]))) {
                    kivp_fail(path, &prob->diag, rc);
                    free(prob);
                    free(work);
                    goto out;
                }
            }
            if (!work) {
                wsz = kelp_ivp_solve_work_size(prob);
                work = kivp_xcalloc(wsz, 1);
            }
            if ((rc = kelp_ivp_solve(prob, work, wsz, &res))) {
                kivp_fail(path, &prob->diag, rc);
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

