/* kelp IvP: string and number helpers. Own number parser: strtod in newlib allocates, and the
 * core must link into firmware without the heap. */
#include <string.h>
#include <math.h>
#include "ivp_int.h"

void ivp_strncat(char *dst, size_t cap, const char *src, size_t n)
{
    if (!dst || cap == 0)
        return;
    size_t len = strlen(dst);
    while (n > 0 && *src && len + 1 < cap) {
        dst[len++] = *src++;
        n--;
    }
    dst[len] = '\0';
}

void ivp_strcat(char *dst, size_t cap, const char *src)
{
    ivp_strncat(dst, cap, src, (size_t)-1);
}

void ivp_warn(char *warn, const char *text)
{
    if (warn[0])
        ivp_strcat(warn, KELP_IVP_MAX_WARN, " # ");
    ivp_strcat(warn, KELP_IVP_MAX_WARN, text);
}

int ivp_fail(kelp_ivp_errbuf *err, int code, const char *what, const char *tok, size_t toklen)
{
    if (err && err->msg[0] == '\0') {
        ivp_strcat(err->msg, sizeof err->msg, what);
        if (tok) {
            ivp_strcat(err->msg, sizeof err->msg, " '");
            ivp_strncat(err->msg, sizeof err->msg, tok, toklen > 60 ? 60 : toklen);
            ivp_strcat(err->msg, sizeof err->msg, "'");
        }
    }
    return code;
}

const char *ivp_skip_ws(const char *s)
{
    while (*s == ' ' || *s == '\t' || *s == '\r')
        s++;
    return s;
}

void ivp_trim(const char **s, size_t *n)
{
    while (*n > 0 && (**s == ' ' || **s == '\t' || **s == '\r' || **s == '\n')) {
        (*s)++;
        (*n)--;
    }
    while (*n > 0 && ((*s)[*n - 1] == ' ' || (*s)[*n - 1] == '\t' || (*s)[*n - 1] == '\r' || (*s)[*n - 1] == '\n'))
        (*n)--;
}

int ivp_word_eq(const char *s, size_t n, const char *word)
{
    size_t wl = strlen(word);
    if (wl != n)
        return 0;
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != word[i])
            return 0;
    }
    return 1;
}

/* Exact powers of ten representable in a double (10^0 .. 10^22). */
static const double pow10_exact[23] = {
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
};

int ivp_parse_double(const char *s, size_t n, double *out)
{
    size_t i = 0;
    int neg = 0;
    if (n == 0)
        return KELP_ERR_PARSE;
    if (s[i] == '+' || s[i] == '-') {
        neg = s[i] == '-';
        i++;
    }
    uint64_t mant = 0;
    int ndig = 0, sig = 0, exp10 = 0, any = 0;
    /* integer part */
    while (i < n && s[i] >= '0' && s[i] <= '9') {
        any = 1;
        if (mant == 0 && s[i] == '0') {
            i++;
            continue;
        }
        if (sig < 19) {
            mant = mant * 10u + (uint64_t)(s[i] - '0');
            sig++;
        } else {
            exp10++;
        }
        ndig++;
        i++;
    }
    if (i < n && s[i] == '.') {
        i++;
        while (i < n && s[i] >= '0' && s[i] <= '9') {
            any = 1;
            if (mant == 0 && s[i] == '0') {
                exp10--;
                i++;
                continue;
            }
            if (sig < 19) {
                mant = mant * 10u + (uint64_t)(s[i] - '0');
                sig++;
                exp10--;
            }
            i++;
        }
    }
    if (!any)
        return KELP_ERR_PARSE;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        int eneg = 0;
        long ev = 0;
        if (i < n && (s[i] == '+' || s[i] == '-')) {
            eneg = s[i] == '-';
            i++;
        }
        if (i >= n || s[i] < '0' || s[i] > '9')
            return KELP_ERR_PARSE;
        while (i < n && s[i] >= '0' && s[i] <= '9') {
            if (ev < 100000)
                ev = ev * 10 + (s[i] - '0');
            i++;
        }
        exp10 += (int)(eneg ? -ev : ev);
    }
    if (i != n)
        return KELP_ERR_PARSE;
    (void)ndig;
    double v;
    if (mant == 0) {
        v = 0.0;
    } else if (mant < (1ull << 53) && exp10 >= -22 && exp10 <= 22) {
        /* both operands exact: one correctly rounded operation */
        v = exp10 >= 0 ? (double)mant * pow10_exact[exp10] : (double)mant / pow10_exact[-exp10];
    } else {
        long double lv = (long double)mant;
        int e = exp10;
        if (e > 400 || e < -400) {
            lv = e > 0 ? (long double)INFINITY : 0.0L;
        } else {
            long double p = 1.0L;
            int ae = e < 0 ? -e : e;
            long double b = 10.0L;
            while (ae) {
                if (ae & 1)
                    p *= b;
                b *= b;
                ae >>= 1;
            }
            lv = e < 0 ? lv / p : lv * p;
        }
        v = (double)lv;
    }
    if (!isfinite(v))
        return KELP_ERR_PARSE;
    *out = neg ? -v : v;
    return 0;
}

int ivp_parse_long(const char *s, size_t n, long *out)
{
    size_t i = 0;
    int neg = 0;
    long v = 0;
    if (n == 0)
        return KELP_ERR_PARSE;
    if (s[i] == '+' || s[i] == '-') {
        neg = s[i] == '-';
        i++;
    }
    if (i >= n)
        return KELP_ERR_PARSE;
    for (; i < n; i++) {
        if (s[i] < '0' || s[i] > '9')
            return KELP_ERR_PARSE;
        if (v > 100000000L)
            return KELP_ERR_RANGE;
        v = v * 10 + (s[i] - '0');
    }
    *out = neg ? -v : v;
    return 0;
}
