/* kelp IvP: IvPDomain. */
#include <string.h>
#include <math.h>
#include "ivp_int.h"

void kelp_ivp_domain_init(kelp_ivp_domain *d)
{
    memset(d, 0, sizeof *d);
}

int kelp_ivp_domain_add(kelp_ivp_domain *d, const char *name, double low, double high, uint32_t points)
{
    if (!d || !name || !name[0] || strlen(name) >= KELP_IVP_MAX_VARNAME)
        return KELP_ERR_ARG;
    if (kelp_ivp_domain_index(d, name) >= 0)
        return KELP_ERR_EXISTS;
    if (!isfinite(low) || !isfinite(high) || low > high || points < 1 || (points == 1 && high != low))
        return KELP_ERR_RANGE;
    if (points > 0x7fffffffu)
        return KELP_ERR_RANGE;
    if (d->dim >= KELP_IVP_MAX_DIM)
        return KELP_ERR_NOSPACE;
    kelp_ivp_var *v = &d->var[d->dim];
    memset(v, 0, sizeof *v);
    memcpy(v->name, name, strlen(name) + 1);
    v->low = low;
    v->high = high;
    v->points = points;
    v->delta = points > 1 ? (high - low) / ((double)points - 1.0) : 0.0;
    d->dim++;
    return 0;
}

int kelp_ivp_domain_index(const kelp_ivp_domain *d, const char *name)
{
    for (unsigned i = 0; i < d->dim; i++)
        if (strcmp(d->var[i].name, name) == 0)
            return (int)i;
    return -1;
}

double kelp_ivp_domain_value(const kelp_ivp_domain *d, unsigned v, uint32_t ix)
{
    return ((double)ix * d->var[v].delta) + d->var[v].low;
}

uint32_t kelp_ivp_domain_snap(const kelp_ivp_domain *d, unsigned v, double val, kelp_ivp_snap mode)
{
    const kelp_ivp_var *x = &d->var[v];
    if (!(val > x->low))
        return 0;
    if (val >= x->high)
        return x->points - 1;
    if (mode == KELP_IVP_SNAP_FLOOR)
        return (uint32_t)((val - x->low) / x->delta);
    if (mode == KELP_IVP_SNAP_NEAREST)
        val -= x->delta / 2.0;
    double dv = (val - x->low) / x->delta;
    if (dv < 0)
        return 0;
    uint32_t iv = (uint32_t)dv;
    return dv > (double)iv ? iv + 1 : iv;
}

double kelp_ivp_domain_total(const kelp_ivp_domain *d)
{
    double t = 1;
    for (unsigned i = 0; i < d->dim; i++)
        t *= (double)d->var[i].points;
    return t;
}

int kelp_ivp_domain_sub(const kelp_ivp_domain *d, const char *names, kelp_ivp_domain *out)
{
    kelp_ivp_domain r;
    kelp_ivp_domain_init(&r);
    const char *p = names;
    for (;;) {
        const char *c = strchr(p, ',');
        size_t n = c ? (size_t)(c - p) : strlen(p);
        const char *t = p;
        ivp_trim(&t, &n);
        if (n > 0) {
            char nm[KELP_IVP_MAX_VARNAME];
            int ix = -1;
            if (n < sizeof nm) {
                memcpy(nm, t, n);
                nm[n] = '\0';
                ix = kelp_ivp_domain_index(d, nm);
            }
            if (ix < 0) {
                kelp_ivp_domain_init(out);
                return KELP_ERR_NOTFOUND;
            }
            int rc = kelp_ivp_domain_add(&r, nm, d->var[ix].low, d->var[ix].high, d->var[ix].points);
            if (rc && rc != KELP_ERR_EXISTS) {
                kelp_ivp_domain_init(out);
                return rc;
            }
        }
        if (!c)
            break;
        p = c + 1;
    }
    *out = r;
    return 0;
}

bool kelp_ivp_domain_is_sub(const kelp_ivp_domain *sub, const kelp_ivp_domain *d)
{
    if (sub->dim == 0)
        return false;
    for (unsigned i = 0; i < sub->dim; i++) {
        int j = kelp_ivp_domain_index(d, sub->var[i].name);
        if (j < 0)
            return false;
        if (d->var[j].low != sub->var[i].low || d->var[j].high != sub->var[i].high ||
            d->var[j].points != sub->var[i].points)
            return false;
    }
    return true;
}

int kelp_ivp_domain_parse(kelp_ivp_domain *d, const char *s, kelp_diag *diag)
{
    return kelp_ivp_domain_parse_n(d, s, s ? strlen(s) : 0, diag);
}

int kelp_ivp_domain_parse_n(kelp_ivp_domain *d, const char *s, size_t len, kelp_diag *diag)
{
    kelp_ivp_domain_init(d);
    if (!s)
        return ivp_fail(diag, KELP_ERR_ARG, "domain: no text", NULL, 0);
    const char *p = s, *end = s + len;
    for (;;) {
        const char *c = memchr(p, ',', (size_t)(end - p));
        size_t n = c ? (size_t)(c - p) : (size_t)(end - p);
        const char *t = p;
        ivp_trim(&t, &n);
        if (n == 0)
            return ivp_fail(diag, KELP_ERR_PARSE, "domain: empty variable in", s, len);
        /* name:low:high:points */
        const char *f[4];
        size_t fl[4];
        unsigned nf = 0;
        size_t st = 0;
        for (size_t i = 0; i <= n; i++) {
            if (i == n || t[i] == ':') {
                if (nf < 4) {
                    f[nf] = t + st;
                    fl[nf] = i - st;
                    ivp_trim(&f[nf], &fl[nf]);
                }
                nf++;
                st = i + 1;
            }
        }
        if (nf != 4)
            return ivp_fail(diag, KELP_ERR_PARSE, "domain: expected name:low:high:points, got", t, n);
        if (fl[0] == 0 || fl[0] >= KELP_IVP_MAX_VARNAME)
            return ivp_fail(diag, KELP_ERR_PARSE, "domain: bad variable name in", t, n);
        for (size_t i = 0; i < fl[0]; i++) {
            char ch = f[0][i];
            if (ch == ' ' || ch == '@' || ch == '=' || ch == '(' || ch == ')')
                return ivp_fail(diag, KELP_ERR_PARSE, "domain: bad variable name", f[0], fl[0]);
        }
        double lo, hi;
        long pts;
        if (ivp_parse_double(f[1], fl[1], &lo))
            return ivp_fail(diag, KELP_ERR_PARSE, "domain: bad low", f[1], fl[1]);
        if (ivp_parse_double(f[2], fl[2], &hi))
            return ivp_fail(diag, KELP_ERR_PARSE, "domain: bad high", f[2], fl[2]);
        if (ivp_parse_long(f[3], fl[3], &pts) || pts < 1 || pts > 100000000L)
            return ivp_fail(diag, KELP_ERR_PARSE, "domain: bad points", f[3], fl[3]);
        char nm[KELP_IVP_MAX_VARNAME];
        memcpy(nm, f[0], fl[0]);
        nm[fl[0]] = '\0';
        int rc = kelp_ivp_domain_add(d, nm, lo, hi, (uint32_t)pts);
        if (rc == KELP_ERR_EXISTS)
            return ivp_fail(diag, rc, "domain: duplicate variable", f[0], fl[0]);
        if (rc == KELP_ERR_NOSPACE)
            return ivp_fail(diag, rc, "domain: too many variables at", t, n);
        if (rc)
            return ivp_fail(diag, rc, "domain: bad extents (need low<=high, points>=1, points=1 only if low=high) in", t, n);
        if (!c)
            break;
        p = c + 1;
    }
    return 0;
}
