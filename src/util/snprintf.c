/* kelp util: snprintf for the core.
 *
 * On a hosted C library kelp_util_snprintf is the library's vsnprintf. On newlib (vehicle
 * firmware) it is kelp_util_vsnprintf_own below: newlib's snprintf links malloc (its string sink
 * can grow a buffer) and newlib nano prints no floating point at all, while the core both
 * must not allocate and prints numbers ("%.1f", "%g"). The own formatter does what the core
 * uses: flags - 0 + space #, width and precision (also *), lengths hh h l ll z j t, and
 * d i u x X o c s p % f F e E g G. Integers and strings are exact; %f with up to 9 decimals
 * rounds as printf (an exact tie to even); %e, %g and longer %f are correct to 15
 * significant digits (a 16th or 17th digit may differ from printf's exact expansion: "%.17g"
 * of 0.1 gives "0.1", which still reads back as the same double).
 */
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <kelp/config.h>
#include <kelp/util.h>

typedef struct out {
    char *buf;
    size_t cap, n;
} out;

static void put(out *o, char c)
{
    if (o->n + 1 < o->cap) o->buf[o->n] = c;
    o->n++;
}

static void puts_n(out *o, const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++) put(o, s[i]);
}

static void pad(out *o, char c, int n)
{
    for (; n > 0; n--) put(o, c);
}

/* a converted field: sign/prefix, zero padding, `zeros` leading zeros (an integer's precision),
 * the body, right or left justified */
static void field_z(out *o, const char *pre, int zeros, const char *body, size_t blen, int width, bool left, bool zero)
{
    size_t plen = pre[0] ? (pre[1] ? 2 : 1) : 0; /* a sign, "0", "0x" */
    int len = (int)(plen + blen) + zeros;
    int fill = width > len ? width - len : 0;
    if (!left && !zero) pad(o, ' ', fill);
    puts_n(o, pre, plen);
    if (!left && zero) pad(o, '0', fill);
    pad(o, '0', zeros);
    puts_n(o, body, blen);
    if (left) pad(o, ' ', fill);
}

static void field(out *o, const char *pre, const char *body, size_t blen, int width, bool left, bool zero)
{
    field_z(o, pre, 0, body, blen, width, left, zero);
}

/* an integer's digits with the precision's leading zeros (the 0 flag is off with a precision) */
static void int_field(out *o, const char *pre, const char *dig, size_t n, int prec, int width, bool left, bool zero)
{
    int z = prec - (int)n;
    if (z > 40) z = 40;
    field_z(o, pre, z > 0 ? z : 0, dig, n, width, left, zero && prec < 0);
}

static size_t utoa(uintmax_t v, unsigned base, bool upper, char *tmp)
{
    const char *dig = upper ? "0123456789ABCDEF" : "0123456789abcdef";
    size_t n = 0;
    do { tmp[n++] = dig[v % base]; v /= base; } while (v);
    for (size_t i = 0; i < n / 2; i++) { char c = tmp[i]; tmp[i] = tmp[n - 1 - i]; tmp[n - 1 - i] = c; }
    return n;
}

/* significant digits of a > 0: d[0..prec) and the decimal exponent of d[0] */
static int digits(double a, int prec, char *d)
{
    if (prec < 1) prec = 1;
    if (prec > 17) prec = 17;
    int e = (int)floor(log10(a));
    double m = a / pow(10.0, e - (prec - 1));
    double r = floor(m + 0.5);
    if (r >= pow(10.0, prec)) { e++; r = floor(a / pow(10.0, e - (prec - 1)) + 0.5); }
    if (r < pow(10.0, prec - 1)) { e--; r = floor(a / pow(10.0, e - (prec - 1)) + 0.5); }
    uint64_t u = (uint64_t)r;
    for (int i = prec - 1; i >= 0; i--) { d[i] = (char)('0' + (int)(u % 10)); u /= 10; }
    return e;
}

/* the digits of a finite v >= 0 in %e or %f (c is 'e' or 'f') into body (96 bytes); returns the length */
static size_t fmt_ef(char *body, size_t cap, double v, char c, bool upper, int prec, bool alt)
{
    size_t n = 0;
    if (c == 'f' && v >= 1e40) c = 'e'; /* %f of a value past 1e40 prints as %e (firmware stacks are small) */
    char d[24];
    if (c == 'e') {
        int sig = prec + 1 > 17 ? 17 : prec + 1;
        int e = 0;
        if (v == 0) memset(d, '0', (size_t)sig);
        else e = digits(v, sig, d);
        body[n++] = d[0];
        if (prec > 0 || alt) body[n++] = '.';
        for (int i = 1; i <= prec && n < cap - 8; i++) body[n++] = i < sig ? d[i] : '0';
        body[n++] = upper ? 'E' : 'e';
        body[n++] = e < 0 ? '-' : '+';
        unsigned ae = (unsigned)(e < 0 ? -e : e);
        if (ae < 10) body[n++] = '0';
        n += utoa(ae, 10, false, body + n);
    } else if (prec > 9 || v >= 9e18 / pow(10.0, prec)) { /* beyond kelp_util_fmt_fixed: digit by digit */
        int e0 = v == 0 ? 0 : (int)floor(log10(v));
        int sig = e0 + 1 + prec, e = 0;
        if (sig > 17) sig = 17;
        if (v == 0 || sig < 1) sig = 0; /* below the last decimal: zeros */
        else e = digits(v, sig, d);
        for (int i = e < 0 ? 0 : e; i >= 0 && n < cap - 2; i--) body[n++] = (e - i >= 0 && e - i < sig) ? d[e - i] : '0';
        if (prec > 0 || alt) body[n++] = '.';
        for (int i = 1; i <= prec && n < cap - 1; i++) body[n++] = (e + i >= 0 && e + i < sig) ? d[e + i] : '0';
    } else { /* rounded as printf does: from the value, an exact tie to even */
        /* the product's rounding error (fma) tells a true tie from a value just off it */
        double p10 = pow(10.0, prec), sc = v * p10, err = fma(v, p10, -sc), r = floor(sc), fr = sc - r;
        if (fr > 0.5 || (fr == 0.5 && (err > 0 || (err == 0 && fmod(r, 2.0) != 0)))) r += 1;
        size_t nd = utoa((uintmax_t)r, 10, false, d);
        size_t ip = nd > (size_t)prec ? nd - (size_t)prec : 0;
        if (ip == 0) body[n++] = '0';
        for (size_t i = 0; i < ip; i++) body[n++] = d[i];
        if (prec > 0 || alt) body[n++] = '.';
        for (int i = prec; i > 0; i--) body[n++] = (size_t)i > nd ? '0' : d[nd - (size_t)i];
    }
    return n;
}

KELP_NOINLINE static void fmt_float(out *o, double v, char conv, int prec, int width, bool left, bool zero, bool alt, const char *sign)
{
    char body[96];
    bool upper = conv == 'F' || conv == 'E' || conv == 'G';
    char pre[2] = "";
    if (signbit(v) && !isnan(v)) pre[0] = '-', v = -v;
    else if (*sign) pre[0] = *sign;
    if (!isfinite(v)) {
        const char *w = isnan(v) ? (upper ? "NAN" : "nan") : (upper ? "INF" : "inf");
        field(o, pre, w, 3, width, left, false);
        return;
    }
    if (prec < 0) prec = 6;
    char c = (char)(conv | 0x20);
    bool trim = false;
    if (c == 'g') {
        if (prec == 0) prec = 1;
        int e = v == 0 ? 0 : (int)floor(log10(v));
        if (v != 0) e = digits(v, prec > 17 ? 17 : prec, body); /* (body as scratch: filled below) */
        if (e < -4 || e >= prec) { c = 'e'; prec -= 1; }
        else { c = 'f'; prec = prec - 1 - e; }
        trim = !alt; /* %g drops trailing zeros: format, then trim */
    }
    size_t n = fmt_ef(body, sizeof body, v, c, upper, prec, alt);
    if (trim) {
        body[n < sizeof body ? n : sizeof body - 1] = 0;
        char *ep = strpbrk(body, "eE");
        size_t mant = ep ? (size_t)(ep - body) : n;
        if (memchr(body, '.', mant)) {
            size_t k = mant;
            while (k > 0 && body[k - 1] == '0') k--;
            if (k > 0 && body[k - 1] == '.') k--;
            memmove(body + k, body + mant, n - mant + 1);
            n -= mant - k;
        }
    }
    field(o, pre, body, n, width, left, zero);
}

int kelp_util_vsnprintf_own(char *buf, size_t cap, const char *fmt, va_list ap)
{
    out o = { buf, cap, 0 };
    for (const char *p = fmt; *p; p++) {
        if (*p != '%') { put(&o, *p); continue; }
        p++;
        bool left = false, zero = false, alt = false;
        const char *sign = "";
        for (;; p++) {
            if (*p == '-') left = true;
            else if (*p == '0') zero = true;
            else if (*p == '+') sign = "+";
            else if (*p == ' ') { if (!*sign) sign = " "; }
            else if (*p == '#') alt = true;
            else break;
        }
        int width = 0, prec = -1;
        if (*p == '*') {
            width = va_arg(ap, int);
            if (width < 0) left = true, width = -width;
            p++;
        } else
            while (*p >= '0' && *p <= '9') width = width * 10 + (*p++ - '0');
        if (*p == '.') {
            p++;
            prec = 0;
            if (*p == '*') { prec = va_arg(ap, int); p++; }
            else while (*p >= '0' && *p <= '9') prec = prec * 10 + (*p++ - '0');
        }
        int len = 0; /* 1 hh, 2 h, 3 l, 4 ll, 5 z, 6 j, 7 t */
        if (*p == 'h') { len = 2; if (p[1] == 'h') { len = 1; p++; } p++; }
        else if (*p == 'l') { len = 3; if (p[1] == 'l') { len = 4; p++; } p++; }
        else if (*p == 'z') { len = 5; p++; }
        else if (*p == 'j') { len = 6; p++; }
        else if (*p == 't') { len = 7; p++; }
        else if (*p == 'L') p++;
        char conv = *p, tmp[24]; /* 64 bits in octal: 22 digits */
        if (!conv) break;
        switch (conv) {
        case 'd': case 'i': {
            intmax_t v = len == 3 ? va_arg(ap, long) : len == 4 ? va_arg(ap, long long) : len == 5 ? (intmax_t)va_arg(ap, size_t)
                       : len == 6 ? va_arg(ap, intmax_t) : len == 7 ? va_arg(ap, ptrdiff_t) : va_arg(ap, int);
            if (len == 1) { unsigned char uc = (unsigned char)v; v = uc > 127 ? (intmax_t)uc - 256 : (intmax_t)uc; }
            if (len == 2) v = (short)v;
            uintmax_t u = v < 0 ? (uintmax_t)0 - (uintmax_t)v : (uintmax_t)v;
            size_t n = (prec == 0 && u == 0) ? 0 : utoa(u, 10, false, tmp);
            char pre[2] = { v < 0 ? '-' : *sign, 0 };
            int_field(&o, pre, tmp, n, prec, width, left, zero);
            break;
        }
        case 'u': case 'x': case 'X': case 'o': case 'p': {
            uintmax_t u;
            if (conv == 'p') u = (uintptr_t)va_arg(ap, void *), alt = true;
            else u = len == 3 ? va_arg(ap, unsigned long) : len == 4 ? va_arg(ap, unsigned long long) : len == 5 ? va_arg(ap, size_t)
                   : len == 6 ? va_arg(ap, uintmax_t) : len == 7 ? (uintmax_t)va_arg(ap, ptrdiff_t) : va_arg(ap, unsigned);
            if (len == 1) u = (unsigned char)u;
            if (len == 2) u = (unsigned short)u;
            unsigned base = conv == 'o' ? 8 : conv == 'u' ? 10 : 16;
            size_t n = (prec == 0 && u == 0) ? 0 : utoa(u, base, conv == 'X', tmp);
            const char *pre = (alt && (base == 16) && (u || conv == 'p')) ? (conv == 'X' ? "0X" : "0x") : "";
            if (alt && base == 8 && u && prec <= (int)n) pre = "0";
            int_field(&o, pre, tmp, n, prec, width, left, zero);
            break;
        }
        case 'c': tmp[0] = (char)va_arg(ap, int); field(&o, "", tmp, 1, width, left, false); break;
        case 's': {
            const char *s = va_arg(ap, const char *);
            if (!s) s = "(null)";
            size_t n = 0;
            while (s[n] && (prec < 0 || n < (size_t)prec)) n++;
            field(&o, "", s, n, width, left, false);
            break;
        }
        case 'f': case 'F': case 'e': case 'E': case 'g': case 'G':
            fmt_float(&o, va_arg(ap, double), conv, prec, width, left, zero, alt, sign);
            break;
        case '%': put(&o, '%'); break;
        default: put(&o, '%'); put(&o, conv); break;
        }
    }
    if (cap) o.buf[o.n < cap ? o.n : cap - 1] = '\0';
    return o.n > INT_MAX ? INT_MAX : (int)o.n;
}

int kelp_util_vsnprintf(char *buf, size_t cap, const char *fmt, va_list ap)
{
#if defined(__NEWLIB__) || defined(KELP_OWN_PRINTF)
    return kelp_util_vsnprintf_own(buf, cap, fmt, ap);
#else
    return vsnprintf(buf, cap, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized): the caller's va_start */
#endif
}

int kelp_util_snprintf(char *buf, size_t cap, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = kelp_util_vsnprintf(buf, cap, fmt, ap);
    va_end(ap);
    return n;
}
