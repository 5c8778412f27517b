/* kelp util: strict number parsing without libc's strtod.
 *
 * Why not strtod: newlib's strtod allocates (Balloc), and the core must not. This parser is
 * correctly rounded (as strtod) for up to 40 significant digits: short numbers take one
 * exact division or product; longer ones or large exponents are estimated and then
 * settled by comparing exact big integers with the halfway points around the estimate
 * (one big integer of 196 bytes on the stack). Beyond 40 digits the rest only breaks ties.
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

bool kelp_util_strieq_n(const char *s, size_t len, const char *z)
{
    size_t i = 0;
    for (; i < len; i++) {
        if (z[i] == 0 || lower(s[i]) != lower(z[i])) return false;
    }
    return z[i] == 0;
}

/* ---- exact decimal -> double: the slow path's big integers ------------------------------
 * A candidate double z is checked against the decimal D * 10^e10 by comparing the decimal
 * with the halfway points between z and its neighbours, all as exact integers. 10^n is
 * 5^n * 2^n and the 2^n goes into the shift, so the big side is at most 5^365 * 2^54 (902 bits)
 * or D * 5^e (760 bits) within the exponent limits below: 29 words of 32 bits. */
enum { BIG_WORDS = 29, DEC_MAX = 40 };
typedef struct { uint32_t w[BIG_WORDS]; int n; } big;

static bool big_mul_add(big *b, uint32_t m, uint32_t a)
{
    uint64_t carry = a;
    for (int i = 0; i < b->n; i++) {
        uint64_t t = (uint64_t)b->w[i] * m + carry;
        b->w[i] = (uint32_t)t;
        carry = t >> 32;
    }
    if (carry) {
        if (b->n == BIG_WORDS) return false;
        b->w[b->n++] = (uint32_t)carry;
    }
    return true;
}

static bool big_mul_pow5(big *b, int e)
{
    for (; e >= 13; e -= 13)
        if (!big_mul_add(b, 1220703125u, 0)) return false; /* 5^13 */
    static const uint32_t p5[] = {1, 5, 25, 125, 625, 3125, 15625, 78125, 390625, 1953125, 9765625, 48828125, 244140625};
    return big_mul_add(b, p5[e], 0);
}

static bool big_shl(big *b, int bits)
{
    int words = bits / 32, r = bits % 32;
    if (b->n == 0) return true;
    if (b->n + words + 1 > BIG_WORDS) return false;
    b->w[b->n] = 0;
    for (int i = b->n; i >= 0; i--) {
        uint32_t hi = b->w[i] << r;
        uint32_t lo = (r && i > 0) ? b->w[i - 1] >> (32 - r) : 0;
        b->w[i + words] = hi | lo;
    }
    for (int i = 0; i < words; i++) b->w[i] = 0;
    b->n += words + 1;
    while (b->n && b->w[b->n - 1] == 0) b->n--;
    return true;
}

/* word i of the small number s[0..ns) shifted left by bits */
static uint32_t shl_word(const uint32_t *s, int ns, int bits, int i)
{
    int j = i - bits / 32, r = bits % 32;
    uint32_t hi = (j >= 0 && j < ns) ? s[j] << r : 0;
    uint32_t lo = (r && j >= 1 && j - 1 < ns) ? s[j - 1] >> (32 - r) : 0;
    return hi | lo;
}

/* sign of a - (s << bits), without building the shifted number */
static int big_cmp_shl(const big *a, const uint32_t *s, int ns, int bits)
{
    int n = ns + bits / 32 + 1;
    for (int i = a->n > n ? a->n : n; i-- > 0;) {
        uint32_t x = i < a->n ? a->w[i] : 0, y = shl_word(s, ns, bits, i);
        if (x != y) return x < y ? -1 : 1;
    }
    return 0;
}

/* Significand and exponent of a finite z >= 0: z = m * 2^k, m < 2^53, k >= -1074. */
static void split_double(double z, uint64_t *m, int *k)
{
    int e;
    (void)frexp(z, &e);
    *k = e - 53;
    if (z == 0.0 || *k < -1074) *k = -1074;
    *m = (uint64_t)ldexp(z, -*k);
}

/* Sign of D * 10^e10 - (the point halfway above z); 2 when the integers would not fit.
 * One side is always a small number shifted left (the digits D, or 2m+1): only the other
 * side is built as a big integer (the stack holds one, not two). */
/* The significant digits in the text: from the first nonzero digit, skipping the '.' (no copy). */
typedef struct { const char *p, *dot; } digs;

static int dig_at(const digs *g, int k)
{
    const char *c = g->p + k;
    if (g->dot && c >= g->dot) c++;
    return *c - '0';
}

static int cmp_halfway(const digs *dig, int nd, int e10, double z)
{
    uint64_t m;
    int k;
    split_double(z, &m, &k);
    uint32_t d[5] = {0}; /* D: at most DEC_MAX (40) digits, 133 bits */
    int dn = 1;
    for (int i = 0; i < nd; i++) {
        uint64_t carry = (uint32_t)dig_at(dig, i);
        for (int j = 0; j < dn; j++) {
            uint64_t t = (uint64_t)d[j] * 10 + carry;
            d[j] = (uint32_t)t;
            carry = t >> 32;
        }
        if (carry) d[dn++] = (uint32_t)carry;
    }
    uint64_t hv = 2 * m + 1; /* halfway = hv * 2^(k-1) */
    uint32_t hs[2] = { (uint32_t)hv, (uint32_t)(hv >> 32) };
    int hn = hs[1] ? 2 : 1;
    big b = {{0}, 0};
    if (e10 >= 0) { /* D * 5^e10 against hv * 2^(k-1-e10) */
        for (int j = 0; j < dn; j++) b.w[j] = d[j];
        b.n = dn;
        while (b.n && b.w[b.n - 1] == 0) b.n--;
        if (!big_mul_pow5(&b, e10)) return 2;
        int sh = k - 1 - e10;
        if (sh >= 0) return big_cmp_shl(&b, hs, hn, sh);
        if (!big_shl(&b, -sh)) return 2;
        return big_cmp_shl(&b, hs, hn, 0);
    }
    /* times 10^-e10: D against hv * 5^-e10 * 2^(k-1-e10) */
    b.w[0] = hs[0], b.w[1] = hs[1], b.n = hn;
    if (!big_mul_pow5(&b, -e10)) return 2;
    int sh = k - 1 - e10;
    if (sh < 0) return -big_cmp_shl(&b, d, dn, -sh);
    if (!big_shl(&b, sh)) return 2;
    return -big_cmp_shl(&b, d, dn, 0);
}

/* Round the estimate z to the double nearest D * 10^e10 (ties to even; sticky: nonzero
 * digits were dropped past the kept ones, so the decimal is a little above D * 10^e10). */
static double refine(const digs *dig, int nd, int e10, bool sticky, double z)
{
    for (int step = 0; step < 64 && isfinite(z); step++) {
        uint64_t m;
        int k;
        split_double(z, &m, &k);
        int up = cmp_halfway(dig, nd, e10, z);
        if (up == 2) break;
        if (up > 0 || (up == 0 && (sticky || (m & 1)))) {
            z = nextafter(z, INFINITY);
            continue;
        }
        if (z == 0.0) break;
        double zl = nextafter(z, 0.0);
        int dn = cmp_halfway(dig, nd, e10, zl);
        if (dn == 2) break;
        if (dn < 0 || (dn == 0 && !sticky && (m & 1))) {
            z = zl;
            continue;
        }
        break;
    }
    return z;
}

int kelp_util_parse_double(const char *s, size_t len, double *out)
{
    size_t i = 0;
    while (i < len && is_space(s[i])) i++;
    while (len > i && is_space(s[len - 1])) len--;
    if (i >= len) return KELP_ERR_PARSE;
    bool neg = false;
    if (s[i] == '+' || s[i] == '-') neg = s[i++] == '-';
    if (i < len && (len - i == 3 || len - i == 8) &&
        (kelp_util_strieq_n(s + i, len - i, "inf") || kelp_util_strieq_n(s + i, len - i, "infinity"))) {
        *out = neg ? -INFINITY : INFINITY;
        return KELP_OK;
    }
    if (i < len && len - i == 3 && kelp_util_strieq_n(s + i, 3, "nan")) {
        *out = NAN;
        return KELP_OK;
    }
    /* significant digits (leading zeros skipped), at most DEC_MAX kept, the rest sticky */
    digs dig = { NULL, NULL };
    uint64_t mant = 0; /* the first 19 of them */
    int nd = 0, e10 = 0;
    bool any = false, sticky = false;
    for (; i < len && s[i] >= '0' && s[i] <= '9'; i++) {
        any = true;
        if (nd == 0 && s[i] == '0') continue;
        if (nd == 0) dig.p = s + i;
        if (nd < 19) mant = mant * 10 + (uint64_t)(s[i] - '0');
        if (nd < DEC_MAX) nd++;
        else { e10++; sticky |= s[i] != '0'; }
    }
    if (i < len && s[i] == '.') {
        if (nd > 0) dig.dot = s + i;
        i++;
        for (; i < len && s[i] >= '0' && s[i] <= '9'; i++) {
            any = true;
            if (nd == 0 && s[i] == '0') { e10--; continue; }
            if (nd == 0) dig.p = s + i;
            if (nd < 19) mant = mant * 10 + (uint64_t)(s[i] - '0');
            if (nd < DEC_MAX) { nd++; e10--; }
            else sticky |= s[i] != '0';
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
    while (nd > 0 && dig_at(&dig, nd - 1) == 0 && !sticky) { /* 1.500 is 15e-1 */
        if (nd <= 19) mant /= 10;
        nd--;
        e10++;
    }
    double v;
    if (nd == 0 || nd + e10 < -325) {
        v = 0.0; /* zero, or below half the least subnormal (4.9e-324) */
    } else if (nd + e10 > 310) {
        v = INFINITY; /* above DBL_MAX (1.8e308) */
    } else if (nd <= 15 && e10 >= -22 && e10 <= 22) {
        /* both operands exact, one rounding: correctly rounded */
        v = (double)mant;
        v = e10 < 0 ? v / pow10_exact[-e10] : v * pow10_exact[e10];
    } else {
        int shown = nd < 19 ? nd : 19;
        int e = e10 + nd - shown, eh = e / 2; /* two factors: 10^e alone may be subnormal */
        v = (double)mant * pow(10.0, (double)eh) * pow(10.0, (double)(e - eh));
        if (v > 1.7976931348623157e308) v = 1.7976931348623157e308;
        v = refine(&dig, nd, e10, sticky, v);
    }
    *out = neg ? -v : v;
    return KELP_OK;
}

int kelp_util_parse_finite(const char *s, size_t len, double *out)
{
    double v;
    int rc = kelp_util_parse_double(s, len, &v);
    if (rc != KELP_OK) return rc;
    if (!isfinite(v)) return KELP_ERR_PARSE;
    *out = v;
    return KELP_OK;
}

int kelp_util_parse_bool(const char *s, size_t len, bool *out)
{
    while (len && is_space(*s)) s++, len--;
    while (len && is_space(s[len - 1])) len--;
    if (kelp_util_strieq_n(s, len, "true") || kelp_util_strieq_n(s, len, "yes") || kelp_util_strieq_n(s, len, "1")) *out = true;
    else if (kelp_util_strieq_n(s, len, "false") || kelp_util_strieq_n(s, len, "no") || kelp_util_strieq_n(s, len, "0")) *out = false;
    else return KELP_ERR_PARSE;
    return KELP_OK;
}

bool kelp_util_strieq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (lower(*a) != lower(*b)) return false;
    return *a == *b;
}

int kelp_util_parse_llong(const char *s, size_t len, long long *out)
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

int kelp_util_parse_long(const char *s, size_t len, long *out)
{
    long long v;
    int rc = kelp_util_parse_llong(s, len, &v);
    if (rc != KELP_OK) return rc;
    if (v < LONG_MIN || v > LONG_MAX) return KELP_ERR_RANGE;
    *out = (long)v;
    return KELP_OK;
}
