/* kelp DCCL: values and Goby's conversions between them (message_val.cpp). */
#include <math.h>
#include <string.h>

#include <kelp/util.h>

#include "dccl_int.h"
#if KELP_DCCL_LIBC_NUM
#include <stdio.h>
#endif

/* 10^p for |p| <= 22: every one of these is exact or correctly rounded, as
 * glibc's pow(10.0, p) returns them. */
static const double POS10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
static const double NEG10[23] = {1e-0,  1e-1,  1e-2,  1e-3,  1e-4,  1e-5,  1e-6,  1e-7,  1e-8,  1e-9,  1e-10, 1e-11,
                                 1e-12, 1e-13, 1e-14, 1e-15, 1e-16, 1e-17, 1e-18, 1e-19, 1e-20, 1e-21, 1e-22};

double dccl_pow10(int p)
{
    if (p >= 0 && p <= 22) return POS10[p];
    if (p < 0 && p >= -22) return NEG10[-p];
    return pow(10.0, (double)p);
}

bool dccl_ieq(const char *a, size_t an, const char *b)
{
    return kelp_util_strieq_n(a, an, b);
}

/* ------------------------------------------------------------------ setters */
void kelp_dccl_val_clear(kelp_dccl_val *v)
{
    v->kind = KELP_DCCL_V_EMPTY;
    v->precision = KELP_DCCL_MAX_DBL_PRECISION;
    v->d = 0;
    v->l = 0;
    v->b = false;
    v->cut = false;
    v->len = 0;
    v->s[0] = '\0';
}

void kelp_dccl_val_set_strn(kelp_dccl_val *v, const char *s, size_t n)
{
    size_t k = n > KELP_DCCL_MAX_STRLEN ? KELP_DCCL_MAX_STRLEN : n;
    v->kind = KELP_DCCL_V_STRING;
    v->precision = KELP_DCCL_MAX_DBL_PRECISION;
    v->d = 0;
    v->l = 0;
    v->b = false;
    v->cut = k < n;
    if (k) memmove(v->s, s, k);
    v->s[k] = '\0';
    v->len = (uint16_t)k;
}

void kelp_dccl_val_set_str(kelp_dccl_val *v, const char *s)
{
    kelp_dccl_val_set_strn(v, s, strlen(s));
}

void kelp_dccl_val_set_double(kelp_dccl_val *v, double d, int precision)
{
    v->len = 0;
    v->s[0] = '\0';
    v->cut = false;
    v->kind = KELP_DCCL_V_DOUBLE;
    v->d = d;
    v->l = 0;
    v->b = false;
    v->precision = precision;
}

void kelp_dccl_val_set_long(kelp_dccl_val *v, int64_t l)
{
    v->len = 0;
    v->s[0] = '\0';
    v->cut = false;
    v->kind = KELP_DCCL_V_LONG;
    v->d = 0;
    v->b = false;
    v->l = l;
    v->precision = KELP_DCCL_MAX_DBL_PRECISION;
}

void kelp_dccl_val_set_bool(kelp_dccl_val *v, bool b)
{
    v->len = 0;
    v->s[0] = '\0';
    v->cut = false;
    v->kind = KELP_DCCL_V_BOOL;
    v->d = 0;
    v->l = 0;
    v->b = b;
    v->precision = KELP_DCCL_MAX_DBL_PRECISION;
}

/* ------------------------------------------------------------------ string -> double */
/* Accept what boost::lexical_cast<double> accepts: the whole string, no white
 * space, optional sign, then inf/infinity/nan[(...)] in any case, or a decimal
 * number with optional exponent (at least one mantissa digit, exponent digits
 * required after e/E). Overflow to infinity is a failure (libstdc++). */
static bool ieq_prefix(const char *s, size_t n, const char *w)
{
    size_t k = strlen(w);
    return n == k && dccl_ieq(s, n, w);
}


bool kelp_dccl_parse_double(const char *s, size_t n, double *out)
{
    size_t i = 0, digits = 0;
    bool neg = false;
    if (n == 0) return false;
    if (s[0] == '+' || s[0] == '-') { neg = s[0] == '-'; i = 1; }
    if (i < n && (s[i] == 'i' || s[i] == 'I' || s[i] == 'n' || s[i] == 'N')) {
        const char *w = s + i;
        size_t wn = n - i;
        if (ieq_prefix(w, wn, "inf") || ieq_prefix(w, wn, "infinity")) {
            *out = neg ? -HUGE_VAL : HUGE_VAL;
            return true;
        }
        if (ieq_prefix(w, wn, "nan") || (wn > 4 && dccl_ieq(w, 4, "nan(") && w[wn - 1] == ')')) {
            *out = neg ? -NAN : NAN;
            return true;
        }
        return false;
    }
    for (; i < n && s[i] >= '0' && s[i] <= '9'; i++) digits++;
    if (i < n && s[i] == '.') for (i++; i < n && s[i] >= '0' && s[i] <= '9'; i++) digits++;
    if (!digits) return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        size_t ed = 0;
        i++;
        if (i < n && (s[i] == '+' || s[i] == '-')) i++;
        for (; i < n && s[i] >= '0' && s[i] <= '9'; i++) ed++;
        if (!ed) return false;
    }
    if (i != n) return false;
#if KELP_DCCL_LIBC_NUM
    {
        char buf[128];
        double v;
        if (n < sizeof buf) {
            memcpy(buf, s, n);
            buf[n] = '\0';
            v = strtod(buf, NULL);
        } else {
            return false; /* a 128-digit number: not a value any field can hold */
        }
        if (isinf(v)) return false;
        *out = v;
    }
#else
    /* the util parser: exact for what DCCL values carry, no allocation */
    {
        double v;
        if (kelp_util_parse_double(s, n, &v) != KELP_OK || isinf(v)) return false;
        *out = v;
    }
#endif
    return true;
}

/* ------------------------------------------------------------------ conversions */
bool kelp_dccl_val_to_double(const kelp_dccl_val *v, double *out)
{
    switch (v->kind) {
    case KELP_DCCL_V_STRING:
        if (kelp_dccl_parse_double(v->s, v->len, out)) return true;
        if (dccl_ieq(v->s, v->len, "true")) { *out = 1; return true; }
        if (dccl_ieq(v->s, v->len, "false")) { *out = 0; return true; }
        return false;
    case KELP_DCCL_V_DOUBLE: *out = v->d; return true;
    case KELP_DCCL_V_LONG: *out = (double)v->l; return true;
    case KELP_DCCL_V_BOOL: *out = v->b ? 1 : 0; return true;
    default: return false;
    }
}

/* Goby sci_round(d, 0): round half away from zero; boost::numeric_cast<long>
 * fails outside the range of long (64-bit). */
static bool dbl_to_long(double d, int64_t *out)
{
    double r;
    if (isnan(d)) return false;
    r = d < 0 ? ceil(d - 0.5) : floor(d + 0.5);
    if (!(r >= -9223372036854775808.0 && r < 9223372036854775808.0)) return false;
    *out = (int64_t)r;
    return true;
}

bool kelp_dccl_val_to_long(const kelp_dccl_val *v, int64_t *out)
{
    double d;
    switch (v->kind) {
    case KELP_DCCL_V_STRING:
        if (kelp_dccl_parse_double(v->s, v->len, &d)) {
            if (dbl_to_long(d, out)) return true;
        }
        if (dccl_ieq(v->s, v->len, "true")) { *out = 1; return true; }
        if (dccl_ieq(v->s, v->len, "false")) { *out = 0; return true; }
        return false;
    case KELP_DCCL_V_DOUBLE: return dbl_to_long(v->d, out);
    case KELP_DCCL_V_LONG: *out = v->l; return true;
    case KELP_DCCL_V_BOOL: *out = v->b ? 1 : 0; return true;
    default: return false;
    }
}

bool kelp_dccl_val_to_bool(const kelp_dccl_val *v, bool *out)
{
    switch (v->kind) {
    case KELP_DCCL_V_STRING:
        if (dccl_ieq(v->s, v->len, "true") || dccl_ieq(v->s, v->len, "1")) { *out = true; return true; }
        if (dccl_ieq(v->s, v->len, "false") || dccl_ieq(v->s, v->len, "0")) { *out = false; return true; }
        return false;
    case KELP_DCCL_V_DOUBLE:
        /* boost::numeric_cast<bool>: in range if -1 < d < 2, then truncation */
        if (!(v->d > -1.0 && v->d < 2.0)) return false;
        *out = (int)v->d != 0;
        return true;
    case KELP_DCCL_V_LONG:
        if (v->l != 0 && v->l != 1) return false;
        *out = v->l == 1;
        return true;
    case KELP_DCCL_V_BOOL: *out = v->b; return true;
    default: return false;
    }
}

/* ------------------------------------------------------------------ number formatting */
static size_t put(char *out, size_t cap, const char *s, size_t n)
{
    if (cap) {
        size_t k = n < cap ? n : cap - 1;
        memcpy(out, s, k);
        out[k] = '\0';
    }
    return n;
}

size_t dccl_fmt_long(int64_t l, char *out, size_t cap)
{
    char buf[24];
    size_t i = sizeof buf;
    uint64_t u = l < 0 ? (uint64_t)0 - (uint64_t)l : (uint64_t)l;
    do {
        buf[--i] = (char)('0' + (int)(u % 10u));
        u /= 10u;
    } while (u);
    if (l < 0) buf[--i] = '-';
    return put(out, cap, buf + i, sizeof buf - i);
}

#if KELP_DCCL_LIBC_NUM
size_t dccl_fmt_fixed(double d, int prec, char *out, size_t cap)
{
    char buf[DCCL_NUMBUF];
    int n = kelp_util_snprintf(buf, sizeof buf, "%.*f", prec < 0 ? 6 : prec, d);
    if (n < 0) n = 0;
    if ((size_t)n >= sizeof buf) n = (int)sizeof buf - 1;
    return put(out, cap, buf, (size_t)n);
}

size_t dccl_fmt_g(double d, int prec, char *out, size_t cap)
{
    char buf[DCCL_NUMBUF];
    int n = kelp_util_snprintf(buf, sizeof buf, "%.*g", prec < 0 ? 6 : prec, d);
    if (n < 0) n = 0;
    if ((size_t)n >= sizeof buf) n = (int)sizeof buf - 1;
    return put(out, cap, buf, (size_t)n);
}
#else
/* Approximate conversions for newlib targets (no allocation). Correct for the
 * ranges DCCL fields use; the last digit may differ from glibc in rare
 * half-way cases. */
static size_t fmt_special(double d, char *out, size_t cap)
{
    if (isnan(d)) return put(out, cap, signbit(d) ? "-nan" : "nan", signbit(d) ? 4 : 3);
    return put(out, cap, d < 0 ? "-inf" : "inf", d < 0 ? 4 : 3);
}

size_t dccl_fmt_fixed(double d, int prec, char *out, size_t cap)
{
    char buf[64];
    size_t n = 0;
    double a, scale, v;
    uint64_t iv, ip, fp;
    if (prec < 0) prec = 6;
    if (isnan(d) || isinf(d)) return fmt_special(d, out, cap);
    a = fabs(d);
    if (prec > 17) prec = 17;
    scale = dccl_pow10(prec);
    v = floor(a * scale + 0.5);
    if (!(v < 1.8e19)) return dccl_fmt_g(d, 17, out, cap);
    iv = (uint64_t)v;
    ip = iv / (uint64_t)scale;
    fp = iv % (uint64_t)scale;
    if (signbit(d)) buf[n++] = '-';
    n += dccl_fmt_long((int64_t)ip, buf + n, sizeof buf - n);
    if (prec > 0) {
        int k;
        buf[n++] = '.';
        for (k = prec - 1; k >= 0; k--) {
            buf[n + (size_t)k] = (char)('0' + (int)(fp % 10u));
            fp /= 10u;
        }
        n += (size_t)prec;
    }
    return put(out, cap, buf, n);
}

size_t dccl_fmt_g(double d, int prec, char *out, size_t cap)
{
    char buf[64], dig[24];
    size_t n = 0;
    int e, i, nd;
    double a, m;
    uint64_t u;
    if (prec < 0) prec = 6;
    if (prec == 0) prec = 1;
    if (prec > 17) prec = 17;
    if (isnan(d) || isinf(d)) return fmt_special(d, out, cap);
    if (signbit(d)) buf[n++] = '-';
    a = fabs(d);
    if (a == 0) { buf[n++] = '0'; return put(out, cap, buf, n); }
    e = (int)floor(log10(a));
    m = floor(a * dccl_pow10(prec - 1 - e) + 0.5);
    if (m >= dccl_pow10(prec)) { e++; m = floor(a * dccl_pow10(prec - 1 - e) + 0.5); }
    u = (uint64_t)m;
    for (i = prec - 1; i >= 0; i--) { dig[i] = (char)('0' + (int)(u % 10u)); u /= 10u; }
    nd = prec;
    while (nd > 1 && dig[nd - 1] == '0') nd--;
    if (e < -4 || e >= prec) {
        buf[n++] = dig[0];
        if (nd > 1) { buf[n++] = '.'; for (i = 1; i < nd; i++) buf[n++] = dig[i]; }
        buf[n++] = 'e';
        buf[n++] = e < 0 ? '-' : '+';
        if (e < 0) e = -e;
        if (e < 10) buf[n++] = '0';
        n += dccl_fmt_long(e, buf + n, sizeof buf - n);
    } else if (e >= 0) {
        for (i = 0; i <= e; i++) buf[n++] = i < nd ? dig[i] : '0';
        if (nd > e + 1) { buf[n++] = '.'; for (i = e + 1; i < nd; i++) buf[n++] = dig[i]; }
    } else {
        buf[n++] = '0';
        buf[n++] = '.';
        for (i = 0; i < -e - 1; i++) buf[n++] = '0';
        for (i = 0; i < nd; i++) buf[n++] = dig[i];
    }
    return put(out, cap, buf, n);
}
#endif

/* MessageVal::get(std::string&) for doubles: fixed with `precision` decimals when
 * log10(|d|) + precision <= 15, else %.{precision}g. A negative precision comes back as a
 * negative stream precision, which the C++ library takes as its default, 6, in either
 * notation: 0 -> "0.000000", 1230 -> "1230.000000", 1e20 -> "1e+20". */
static size_t dbl_to_str(double d, int p, char *out, size_t cap)
{
    if (p < 0)
        return log10(fabs(d)) + p <= KELP_DCCL_MAX_DBL_PRECISION ? dccl_fmt_fixed(d, 6, out, cap)
                                                                 : dccl_fmt_g(d, 6, out, cap);
    if (log10(fabs(d)) + p <= KELP_DCCL_MAX_DBL_PRECISION) return dccl_fmt_fixed(d, p, out, cap);
    return dccl_fmt_g(d, p, out, cap);
}

void dccl_val_set_double_str(kelp_dccl_val *v, double d, int p)
{
    size_t n = dbl_to_str(d, p, v->s, sizeof v->s);
#if KELP_DCCL_LIBC_NUM
    if (n > DCCL_NUMBUF - 1) n = DCCL_NUMBUF - 1; /* what a DCCL_NUMBUF buffer kept */
#endif
    v->kind = KELP_DCCL_V_STRING;
    v->precision = KELP_DCCL_MAX_DBL_PRECISION;
    v->d = 0;
    v->l = 0;
    v->b = false;
    v->len = (uint16_t)(n > KELP_DCCL_MAX_STRLEN ? KELP_DCCL_MAX_STRLEN : n);
    v->cut = v->len < n;
    v->s[v->len] = '\0';
}

char *dccl_val_str_inplace(kelp_dccl_val *v, size_t *n)
{
    size_t k = 0;
    switch (v->kind) {
    case KELP_DCCL_V_STRING: k = v->len; break;
    case KELP_DCCL_V_DOUBLE: k = dbl_to_str(v->d, v->precision, v->s, sizeof v->s); break;
    case KELP_DCCL_V_LONG: k = dccl_fmt_long(v->l, v->s, sizeof v->s); break;
    case KELP_DCCL_V_BOOL: k = put(v->s, sizeof v->s, v->b ? "true" : "false", v->b ? 4 : 5); break;
    default: v->s[0] = '\0'; break;
    }
    *n = k > KELP_DCCL_MAX_STRLEN ? KELP_DCCL_MAX_STRLEN : k;
    return v->s;
}

bool kelp_dccl_val_to_str(const kelp_dccl_val *v, char *out, size_t cap, size_t *len)
{
    size_t n;
    switch (v->kind) {
    case KELP_DCCL_V_STRING: n = put(out, cap, v->s, v->len); break;
    case KELP_DCCL_V_DOUBLE: n = dbl_to_str(v->d, v->precision, out, cap); break;
    case KELP_DCCL_V_LONG: n = dccl_fmt_long(v->l, out, cap); break;
    case KELP_DCCL_V_BOOL: n = put(out, cap, v->b ? "true" : "false", v->b ? 4 : 5); break;
    default:
        (void)put(out, cap, "", 0);
        if (len) *len = 0;
        return false;
    }
    if (len) *len = n;
    return true;
}

/* util/sci.h unbiased_round: x = v*10^p; f = floor(x); s = x - f; round half even
 * on the parity of (unsigned long)f. */
double kelp_dccl_unbiased_round(double v, int p)
{
    double scale = dccl_pow10(p);
    double x = v * scale;
    double f = floor(x);
    double s = x - f;
    bool even;
    if (isnan(x) || isinf(x)) return v;
    /* (unsigned long)f & 1 for negative f is the parity of the two's complement */
    if (f >= 0 && f < 18446744073709551616.0) even = (((uint64_t)f) & 1u) == 0;
    else if (f < 0 && f > -9223372036854775808.0) even = (((uint64_t)(int64_t)f) & 1u) == 0;
    else even = true;
    if (s < 0.5 || (s == 0.5 && even)) return f / scale;
    return (f + 1) / scale;
}
