/* kelp helm: small text helpers (trim, case, numbers, variable-value pairs, hashing). */
#include <math.h>
#include <stdarg.h>
#include <string.h>
#include <kelp/mission.h>
#include "helm_int.h"

bool hx_is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

char hx_lower(char c)
{
    return (c >= 'A' && c <= 'Z') ? (char)(c - 'A' + 'a') : c;
}

bool hx_ieq(const char *a, const char *b)
{
    return kelp_util_strieq(a, b);
}

void hx_trim(const char **s, size_t *n)
{
    while (*n && hx_is_space(**s)) {
        (*s)++;
        (*n)--;
    }
    while (*n && hx_is_space((*s)[*n - 1]))
        (*n)--;
}

bool hx_copy(char *dst, size_t cap, const char *s, size_t n)
{
    if (n + 1 > cap)
        return false;
    memcpy(dst, s, n);
    dst[n] = '\0';
    return true;
}

bool hx_number(const char *s, size_t n, double *out)
{
    hx_trim(&s, &n);
    if (n == 0)
        return false;
    double v;
    if (kelp_util_parse_double(s, n, &v) != 0 || !isfinite(v))
        return false;
    *out = v;
    return true;
}

uint64_t hx_hash(uint64_t h, const void *p, size_t n)
{
    const unsigned char *c = p;
    for (size_t i = 0; i < n; i++) {
        h ^= c[i];
        h *= UINT64_C(0x100000001b3);
    }
    return h;
}

bool hx_varname(const char *s, size_t n)
{
    if (n == 0 || n >= KELP_MAX_NAME)
        return false;
    for (size_t i = 0; i < n; i++)
        if (hx_is_space(s[i]) || s[i] == '=' || s[i] == ',')
            return false;
    return true;
}

bool hx_pair_value(const char *v, size_t n, kelp_helm_pair *out)
{
    hx_trim(&v, &n);
    if (n >= 2 && v[0] == '"' && v[n - 1] == '"') {
        out->is_str = true;
        out->dval = 0;
        return hx_copy(out->sval, sizeof out->sval, v + 1, n - 2);
    }
    double d;
    if (hx_number(v, n, &d)) {
        out->is_str = false;
        out->dval = d;
        out->sval[0] = '\0';
        return true;
    }
    out->is_str = true;
    out->dval = 0;
    return hx_copy(out->sval, sizeof out->sval, v, n);
}

bool hx_pair(const char *s, kelp_helm_pair *out)
{
    const char *eq = strchr(s, '=');
    if (!eq)
        return false;
    const char *k = s;
    size_t kn = (size_t)(eq - s);
    hx_trim(&k, &kn);
    if (!hx_varname(k, kn))
        return false;
    memcpy(out->var, k, kn);
    out->var[kn] = '\0';
    return hx_pair_value(eq + 1, strlen(eq + 1), out);
}

void hx_fmt_ulong(char *buf, size_t cap, unsigned long v)
{
    char t[24];
    size_t n = 0;
    do {
        t[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v && n < sizeof t);
    size_t i = 0;
    for (; i < n && i + 1 < cap; i++)
        buf[i] = t[n - 1 - i];
    if (cap)
        buf[i < cap ? i : cap - 1] = '\0';
}

/* v with exactly dec decimals (|v| < 1e12), or shortest up to 6 decimals when strip: the
 * util formatter, with fewer decimals where a large value leaves no room for them */
static void fmt_fixed(char *buf, size_t cap, double v, unsigned dec, bool strip)
{
    while (kelp_util_fmt_fixed(buf, cap, v, dec, strip) < 0 && dec > 0)
        dec--;
}

void hx_fmt_fixed(char *buf, size_t cap, double v, unsigned dec)
{
    if (fabs(v) >= 1e12) {
        hx_fmt_double(buf, cap, v);
        return;
    }
    fmt_fixed(buf, cap, v, dec > 9 ? 9 : dec, false);
}

void hx_fmt_x(char *buf, size_t cap, double v, unsigned dec)
{
    hx_fmt_fixed(buf, cap, v, dec);
    if (!strchr(buf, '.') || strchr(buf, 'e'))
        return;
    size_t n = strlen(buf);
    while (n > 0 && buf[n - 1] == '0')
        buf[--n] = '\0';
    if (n > 0 && buf[n - 1] == '.')
        buf[--n] = '\0';
    if (!strcmp(buf, "-0"))
        buf[0] = '0', buf[1] = '\0';
}

/* |v| >= 1e12 as mantissa (up to 6 decimals) "e+" exponent (its buffers off the common path) */
KELP_NOINLINE static void fmt_sci(char *buf, size_t cap, double v)
{
    int e = (int)floor(log10(fabs(v)));
    double m = v / pow(10, e);
    char mb[32], eb[16];
    fmt_fixed(mb, sizeof mb, m, 6, true);
    hx_fmt_ulong(eb, sizeof eb, (unsigned long)e);
    hx_cat(buf, cap, mb, "e+", eb, HX_END);
}

void hx_fmt_double(char *buf, size_t cap, double v)
{
    if (isfinite(v) && fabs(v) >= 1e12) {
        fmt_sci(buf, cap, v);
        return;
    }
    fmt_fixed(buf, cap, v, 6, true);
}

size_t hx_cat(char *buf, size_t cap, ...)
{
    va_list ap;
    size_t n = 0;
    va_start(ap, cap);
    for (const char *s = va_arg(ap, const char *); s; s = va_arg(ap, const char *))
        for (; *s && n + 1 < cap; s++)
            buf[n++] = *s;
    va_end(ap);
    if (cap)
        buf[n] = '\0';
    return n;
}
