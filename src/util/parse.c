/* kelp util: strict number parsing without libc's strtod.
 *
 * Why not strtod: newlib's strtod allocates (Balloc), and the core must not. This parser is
 * exact (correctly rounded) whenever the decimal significand has at most 19 digits, fits
 * 2^53 and the power of ten is at most 22 -- every number in a mission file or a MOOS
 * string in practice -- and within a few ulp otherwise.
 */
#include <math.h>
#include <stdint.h>
#include <limits.h>
#include <kelp/util.h>

static const double pow10_exact[] = { 1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                      1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                      1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22 };

static bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

static char lower(char c)
{
    return (c >= 'A' && c <= 'Z') ? (char)(c - 'A' + 'a') : c;
}

bool kelp_strieq_n(const char *s, size_t len, const char *z)
{
    size_t i = 0;
    for (; i < len; i++) {
        if (z[i] == 0 || lower(s[i]) != lower(z[i])) return false;
    }
    return z[i] == 0;
}

int kelp_parse_double(const char *s, size_t len, double *out)
{
    size_t i = 0;
    while (i < len && is_space(s[i])) i++;
    while (len > i && is_space(s[len - 1])) len--;
    if (i >= len) return KELP_ERR_PARSE;
    bool neg = false;
    if (s[i] == '+' || s[i] == '-') neg = s[i++] == '-';
    if (i < len && (len - i == 3 || len - i == 8) &&
        (kelp_strieq_n(s + i, len - i, "inf") || kelp_strieq_n(s + i, len - i, "infinity"))) {
        *out = neg ? -INFINITY : INFINITY;
        return KELP_OK;
    }
    if (i < len && len - i == 3 && kelp_strieq_n(s + i, 3, "nan")) {
        *out = NAN;
        return KELP_OK;
    }
    uint64_t mant = 0;
    int ndig = 0, dropped = 0, e10 = 0;
    bool any = false;
    for (; i < len && s[i] >= '0' && s[i] <= '9'; i++) {
        any = true;
        if (ndig < 19) {
            if (mant || s[i] != '0') { mant = mant * 10 + (uint64_t)(s[i] - '0'); ndig += mant ? 1 : 0; }
        } else {
            dropped++;
        }
    }
    if (i < len && s[i] == '.') {
        i++;
        for (; i < len && s[i] >= '0' && s[i] <= '9'; i++) {
            any = true;
            if (ndig < 19) {
                mant = mant * 10 + (uint64_t)(s[i] - '0');
                if (mant) ndig++;
                e10--;
            }
        }
    }
    if (!any) return KELP_ERR_PARSE;
    if (i < len && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        bool eneg = false;
        if (i < len && (s[i] == '+' || s[i] == '-')) eneg = s[i++] == '-';
        if (i >= len || s[i] < '0' || s[i] > '9') return KELP_ERR_PARSE;
        long ex = 0;
        for (; i < len && s[i] >= '0' && s[i] <= '9'; i++)
            if (ex < 100000) ex = ex * 10 + (s[i] - '0');
        e10 += (int)(eneg ? -ex : ex);
    }
    if (i != len) return KELP_ERR_PARSE;
    e10 += dropped;
    double v;
    if (mant == 0) {
        v = 0.0;
    } else if (mant < (UINT64_C(1) << 53) && e10 >= -22 && e10 <= 22) {
        v = (double)mant;
        v = e10 < 0 ? v / pow10_exact[-e10] : v * pow10_exact[e10];
    } else {
        v = (double)mant * pow(10.0, (double)e10);
    }
    *out = neg ? -v : v;
    return KELP_OK;
}

int kelp_parse_finite(const char *s, size_t len, double *out)
{
    double v;
    int rc = kelp_parse_double(s, len, &v);
    if (rc != KELP_OK) return rc;
    if (!isfinite(v)) return KELP_ERR_PARSE;
    *out = v;
    return KELP_OK;
}

int kelp_parse_bool(const char *s, size_t len, bool *out)
{
    while (len && is_space(*s)) s++, len--;
    while (len && is_space(s[len - 1])) len--;
    if (kelp_strieq_n(s, len, "true") || kelp_strieq_n(s, len, "yes") || kelp_strieq_n(s, len, "1")) *out = true;
    else if (kelp_strieq_n(s, len, "false") || kelp_strieq_n(s, len, "no") || kelp_strieq_n(s, len, "0")) *out = false;
    else return KELP_ERR_PARSE;
    return KELP_OK;
}

bool kelp_strieq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (lower(*a) != lower(*b)) return false;
    return *a == *b;
}

int kelp_parse_llong(const char *s, size_t len, long long *out)
{
    size_t i = 0;
    while (i < len && is_space(s[i])) i++;
    while (len > i && is_space(s[len - 1])) len--;
    if (i >= len) return KELP_ERR_PARSE;
    bool neg = false;
    if (s[i] == '+' || s[i] == '-') neg = s[i++] == '-';
    if (i >= len) return KELP_ERR_PARSE;
    long long v = 0;
    for (; i < len; i++) {
        if (s[i] < '0' || s[i] > '9') return KELP_ERR_PARSE;
        if (v > (LLONG_MAX - (s[i] - '0')) / 10) return KELP_ERR_RANGE;
        v = v * 10 + (s[i] - '0');
    }
    *out = neg ? -v : v;
    return KELP_OK;
}

int kelp_parse_long(const char *s, size_t len, long *out)
{
    size_t i = 0;
    while (i < len && is_space(s[i])) i++;
    while (len > i && is_space(s[len - 1])) len--;
    if (i >= len) return KELP_ERR_PARSE;
    bool neg = false;
    if (s[i] == '+' || s[i] == '-') neg = s[i++] == '-';
    if (i >= len) return KELP_ERR_PARSE;
    long v = 0;
    for (; i < len; i++) {
        if (s[i] < '0' || s[i] > '9') return KELP_ERR_PARSE;
        if (v > (LONG_MAX - (s[i] - '0')) / 10) return KELP_ERR_RANGE;
        v = v * 10 + (s[i] - '0');
    }
    *out = neg ? -v : v;
    return KELP_OK;
}
