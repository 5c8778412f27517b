/* kelp IvP: an IvP function as the IPF string MOOS-IvP's helm posts in BHV_IPF (its
 * FunctionEncoder, read in MOOS-IvP 24.8's lib_ivpbuild: facts only). The layout:
 *
 *   H,<len>,<context>,<dim>,<pieces>,<degree>,<pwt>,D,<domain>,G,<gel>...,F,<piece>...
 *
 * context "<iteration>:<behaviour>"; domain "name;low;high;points" joined by ':'; the grid
 * element ("gel") box's upper index per dimension (the domain's last index for a function
 * built by ZAICs and the coupler, the uniform piece's extent minus one for one the Reflector
 * built); each piece its bounds per dimension (an exclusive bound, never made here, would carry
 * an X) and its weights: one slope per dimension, then the constant (degree 1). Numbers: pwt
 * and domain bounds to five decimals with trailing zeros cut (and the point, "100"); weights to
 * four decimals, trailing zeros cut but the point kept ("2.", "0.5", "-0.0625"), an exact zero
 * as "0" and a non-zero value under 0.00005 as "0.0000". */
#include <stdio.h>
#include <string.h>
#include <kelp/ivp.h>
#include <kelp/util.h>

typedef struct ipf_out {
    char *buf;
    size_t cap, n;
    bool full;
} ipf_out;

static void put(ipf_out *o, const char *s, size_t len)
{
    if (o->full || o->n + len >= o->cap) {
        o->full = true;
        return;
    }
    memcpy(o->buf + o->n, s, len);
    o->n += len;
    o->buf[o->n] = '\0';
}

static void puts_(ipf_out *o, const char *s)
{
    put(o, s, strlen(s));
}

/* v in decimal at d (up to 20 digits); returns the length */
static size_t fmt_ulong(char *d, unsigned long v)
{
    if (v < 1000) { /* the common case: piece bounds */
        size_t n = v < 10 ? 1 : v < 100 ? 2 : 3;
        for (size_t k = n; k-- > 0; v /= 10)
            d[k] = (char)('0' + v % 10);
        return n;
    }
    char t[24];
    size_t k = sizeof t;
    do {
        t[--k] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    memcpy(d, t + k, sizeof t - k);
    return sizeof t - k;
}

static void put_ulong(ipf_out *o, unsigned long v)
{
    char d[24];
    put(o, d, fmt_ulong(d, v));
}

static void put_compact(ipf_out *o, double v)
{
    char b[48];
    if (kelp_util_fmt_fixed(b, sizeof b, v, 5, true) < 0) {
        o->full = true;
        return;
    }
    puts_(o, b);
}

/* a weight as the encoder writes it (see the file's comment) */
/* a weight at d (at most WEIGHT_MAX characters); returns the length, 0 for a weight beyond
 * the encoder's integer (not a value a function holds) */
#define WEIGHT_MAX 24
static size_t fmt_weight(char *d, double w)
{
    if (w == 0) {
        d[0] = '0';
        return 1;
    }
    size_t n = 0;
    if (w < 0) {
        d[n++] = '-';
        w = -w;
    }
    if (w > 9e14)
        return 0;
    unsigned long long iv = (unsigned long long)(w * 10000 + 0.5);
    n += fmt_ulong(d + n, (unsigned long)(iv / 10000));
    d[n++] = '.';
    unsigned frac = (unsigned)(iv % 10000);
    if (iv == 0) {
        for (int z = 0; z < 4; z++) d[n++] = '0';
    } else if (frac) {
        char f[4];
        unsigned len = 4;
        for (int k = 3; k >= 0; k--, frac /= 10) f[k] = (char)('0' + frac % 10);
        while (len > 0 && f[len - 1] == '0') len--;
        memcpy(d + n, f, len);
        n += len;
    }
    return n;
}

static void put_weight(ipf_out *o, double w)
{
    char d[WEIGHT_MAX];
    size_t n = fmt_weight(d, w);
    if (n == 0) {
        o->full = true;
        return;
    }
    put(o, d, n);
}

/* One piece written straight into the buffer when it surely fits (bounds of at most 20
 * digits, weights of at most WEIGHT_MAX characters, the separators, the terminating NUL);
 * false (nothing written) otherwise, and the caller writes it piece by piece. */
static bool put_piece_fast(ipf_out *o, const kelp_ivp_piece *p, unsigned dim, bool last)
{
    size_t need = (size_t)dim * 2 * 21 + ((size_t)dim + 1) * (WEIGHT_MAX + 1) + 1;
    if (o->full || o->n + need >= o->cap)
        return false;
    char *d = o->buf + o->n, *d0 = d;
    for (unsigned k = 0; k < dim; k++) {
        d += fmt_ulong(d, (unsigned long)(p->lo[k] > 0 ? p->lo[k] : 0));
        *d++ = ',';
        d += fmt_ulong(d, (unsigned long)(p->hi[k] > 0 ? p->hi[k] : 0));
        *d++ = ',';
    }
    for (unsigned k = 0; k <= dim; k++) {
        size_t n = fmt_weight(d, k < dim ? p->slope[k] : p->cst);
        if (n == 0)
            return false; /* written past o->n only: the slow path redoes it and fails */
        d += n;
        if (!last || k < dim) *d++ = ',';
    }
    *d = '\0';
    o->n += (size_t)(d - d0);
    return true;
}

int kelp_ivp_func_to_ipf(const kelp_ivp_func *f, const char *context, const int32_t *gel, char *buf, size_t cap)
{
    if (!f || !buf || cap == 0) return KELP_ERR_ARG;
    if (!context) context = "";
    ipf_out o = { buf, cap, 0, false };
    buf[0] = '\0';
    unsigned dim = f->dom.dim;
    puts_(&o, "H,");
    put_ulong(&o, strlen(context));
    put(&o, ",", 1);
    puts_(&o, context);
    put(&o, ",", 1);
    put_ulong(&o, dim);
    put(&o, ",", 1);
    put_ulong(&o, (unsigned long)f->n);
    puts_(&o, ",1,");
    put_compact(&o, f->pwt);
    puts_(&o, ",D,");
    for (unsigned d = 0; d < dim; d++) {
        const kelp_ivp_var *v = &f->dom.var[d];
        if (d) put(&o, ":", 1);
        puts_(&o, v->name);
        put(&o, ";", 1);
        put_compact(&o, v->low);
        put(&o, ";", 1);
        put_compact(&o, v->high);
        put(&o, ";", 1);
        put_ulong(&o, v->points);
    }
    puts_(&o, ",G,");
    for (unsigned d = 0; d < dim; d++) {
        long g = gel ? (long)gel[d] : (long)f->dom.var[d].points - 1;
        put_ulong(&o, (unsigned long)(g > 0 ? g : 0));
        put(&o, ",", 1);
    }
    put(&o, "F,", 2);
    for (size_t i = 0; i < f->n && !o.full; i++) {
        const kelp_ivp_piece *p = &f->pcs[i];
        if (put_piece_fast(&o, p, dim, i + 1 == f->n))
            continue;
        for (unsigned d = 0; d < dim; d++) {
            put_ulong(&o, (unsigned long)(p->lo[d] > 0 ? p->lo[d] : 0));
            put(&o, ",", 1);
            put_ulong(&o, (unsigned long)(p->hi[d] > 0 ? p->hi[d] : 0));
            put(&o, ",", 1);
        }
        for (unsigned d = 0; d <= dim; d++) {
            put_weight(&o, d < dim ? p->slope[d] : p->cst);
            if (i + 1 < f->n || d < dim) put(&o, ",", 1);
        }
    }
    return o.full ? KELP_ERR_NOSPACE : (int)o.n;
}
