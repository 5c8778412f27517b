/* kelp util: the one fixed-point number formatter (no printf: newlib's allocates for
 * doubles, and a locale could change the decimal point). */
#include <math.h>
#include <stdint.h>
#include <kelp/util.h>

/* frac x p rounded to an integer as printf rounds: on the exact value of the double (0.35 is
 * 0.34999.. and gives 0.3 at one decimal), an exact half to the even neighbour. fma gives
 * frac x p - c with one rounding, so its sign is exact. 0 <= frac < 1, p <= 1e9; whole_odd:
 * the whole part is odd (the digit that decides a half when there are no decimals). */
static uint64_t round_exact(double frac, double p, bool whole_odd)
{
    double t = frac * p, c = floor(t), r = t - c;
    /* away from a half and from the integers the product's rounding (< 1e-7 here) cannot
     * change the answer: most numbers end here, without fma */
    if (r > 1e-6 && r < 1 - 1e-6 && fabs(r - 0.5) > 1e-6) return (uint64_t)c + (r > 0.5);
    if (fma(frac, p, -c) < 0) c -= 1;         /* the product rounded up past an integer */
    else if (fma(frac, p, -(c + 1)) >= 0) c += 1;
    double h = fma(frac, p, -(c + 0.5));
    bool odd = p == 1 ? whole_odd : ((uint64_t)c & 1) != 0; /* no decimals: the units digit decides */
    if (h > 0 || (h == 0 && odd)) c += 1;
    return (uint64_t)c;
}

int kelp_util_fmt_fixed(char *buf, size_t cap, double v, unsigned dec, bool strip)
{
    static const double pow10[] = {1, 10, 100, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
    char t[32]; /* sign, 19 digits, point, 9 decimals */
    size_t n = 0;
    if (dec > 9) dec = 9;
    if (!isfinite(v)) {
        const char *w = isnan(v) ? "nan" : v > 0 ? "inf" : "-inf";
        while (*w) t[n++] = *w++;
    } else {
        /* whole and fraction apart: |v| * 10^dec overflows the 53-bit mantissa long
         * before |v| does, and the digits printed must read back as the same double */
        double w = floor(fabs(v));
        if (w >= 9.0e18) return KELP_ERR_RANGE;
        uint64_t ipart = (uint64_t)w;
        uint64_t scale = (uint64_t)pow10[dec];
        uint64_t f = round_exact(fabs(v) - w, pow10[dec], (ipart & 1) != 0);
        if (f >= scale) { f -= scale; ipart++; }
        bool any = ipart != 0 || f != 0;
        uint64_t u = f;
        char r[9]; /* the decimals, least significant first */
        size_t k = 0;
        for (unsigned i = 0; i < dec; i++, u /= 10) r[k++] = (char)('0' + u % 10);
        u = ipart;
        size_t skip = 0;
        if (strip) {
            while (skip < dec && r[skip] == '0') skip++;
        }
        if (v < 0 && any) t[n++] = '-';
        char ip[20];
        size_t m = 0;
        do { ip[m++] = (char)('0' + u % 10); u /= 10; } while (u);
        while (m) t[n++] = ip[--m];
        if (skip < dec) {
            t[n++] = '.';
            for (size_t i = dec; i-- > skip;) t[n++] = r[i];
        }
    }
    if (cap) {
        size_t w = n < cap ? n : cap - 1;
        for (size_t i = 0; i < w; i++) buf[i] = t[i];
        buf[w] = '\0';
    }
    return (int)n;
}
