/* kelp helm: small text helpers (trim, case, numbers, variable-value pairs, hashing). */
#include <math.h>
#include <stdio.h>
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
    for (; *a && *b; a++, b++)
        if (hx_lower(*a) != hx_lower(*b))
            return false;
    return *a == *b;
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
    if (kelp_parse_double(s, n, &v) != 0 || !isfinite(v))
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

void hx_fmt_double(char *buf, size_t cap, double v)
{
    if (v == 0)
        v = 0; /* -0 -> 0 */
    snprintf(buf, cap, "%.10g", v);
}
