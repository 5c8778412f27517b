/* kelp util: the one number formatter and parser every module uses. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/util.h>
#include <kelp/kv.h>
#include <kelp/rng.h>

static const char *fx(double v, unsigned dec, bool strip)
{
    static char buf[64];
    ck_assert_int_ge(kelp_util_fmt_fixed(buf, sizeof buf, v, dec, strip), 0);
    return buf;
}

START_TEST(fmt_fixed_rounding_and_sign)
{
    /* as printf rounds (MOOS-IvP's and Goby's number strings): on the exact binary value, an
     * exact half to the even digit */
    ck_assert_str_eq(fx(2.5, 0, false), "2");
    ck_assert_str_eq(fx(3.5, 0, false), "4");
    ck_assert_str_eq(fx(-2.5, 0, false), "-2");
    ck_assert_str_eq(fx(1309.5, 0, false), "1310");
    ck_assert_str_eq(fx(1.005, 2, false), "1.00");   /* 1.005 is 1.00499999999999989... */
    ck_assert_str_eq(fx(0.125, 2, false), "0.12");   /* exact half: even */
    ck_assert_str_eq(fx(0.375, 2, false), "0.38");
    ck_assert_str_eq(fx(0.35, 1, false), "0.3");     /* 0.34999999999999997... */
    ck_assert_str_eq(fx(12.25, 1, false), "12.2");
    ck_assert_str_eq(fx(2.675, 2, false), "2.67");
    ck_assert_str_eq(fx(0.45, 1, false), "0.5");     /* 0.45000000000000001... */
    ck_assert_str_eq(fx(-0.0004, 3, false), "0.000"); /* never "-0" */
    ck_assert_str_eq(fx(-0.0, 0, false), "0");
    ck_assert_str_eq(fx(123.456, 1, false), "123.5");
    ck_assert_str_eq(fx(7, 3, false), "7.000");
    ck_assert_str_eq(fx(1e12 + 0.25, 2, false), "1000000000000.25");
}
END_TEST

/* against the C library's %.*f on values that sit on or near a half (decimal steps of a
 * half unit, binary fractions, random): the same text, every decimal count */
START_TEST(fmt_fixed_as_printf)
{
    kelp_rng r;
    kelp_rng_seed(&r, 29);
    unsigned long n = 0, bad = 0;
    char first[256] = "";
    for (int i = 0; i < 20000; i++) {
        double v;
        switch (i % 4) {
        case 0: v = (double)((long)(kelp_rng_next(&r) % 200001) - 100000) / 1000.0; break;
        case 1: v = (double)((long)(kelp_rng_next(&r) % 2000001) - 1000000) / 200.0; break;
        case 2: v = ldexp((double)(kelp_rng_next(&r) % 1000000007), -(int)(kelp_rng_next(&r) % 40)); break;
        default: v = ((double)(kelp_rng_next(&r) % 2000001) - 1000000.0) * 1e-3 * (double)(kelp_rng_next(&r) % 1000); break;
        }
        for (unsigned d = 0; d <= 9; d++) {
            char want[64], got[64];
            snprintf(want, sizeof want, "%.*f", (int)d, v);
            const char *w = want;
            if (want[0] == '-' && strspn(want + 1, "0.") == strlen(want + 1)) w = want + 1; /* kelp: never -0 */
            if (kelp_util_fmt_fixed(got, sizeof got, v, d, false) < 0 || strcmp(got, w) != 0) {
                if (bad++ == 0) snprintf(first, sizeof first, "%.17g at %u: kelp %s, printf %s", v, d, got, w);
            }
            n++;
        }
    }
    /* one assertion at the end (200,000 of them each cost the runner a message) */
    ck_assert_msg(bad == 0, "%lu differ; the first: %s", bad, first);
    ck_assert_uint_eq(n, 200000);
}
END_TEST

START_TEST(fmt_fixed_strip_special_and_space)
{
    ck_assert_str_eq(fx(2.50, 2, true), "2.5");
    ck_assert_str_eq(fx(3.0, 6, true), "3");
    ck_assert_str_eq(fx(-1.2345004, 6, true), "-1.2345");
    ck_assert_str_eq(fx(NAN, 2, false), "nan");
    ck_assert_str_eq(fx(-INFINITY, 2, false), "-inf");
    ck_assert_str_eq(fx(0.1234567891, 12, false), "0.123456789"); /* at most 9 decimals */
    char small[4];
    ck_assert_int_eq(kelp_util_fmt_fixed(small, sizeof small, 12345.5, 1, false), 7); /* needed length */
    ck_assert_str_eq(small, "123");                                              /* truncated, NUL */
    char b[32] = "untouched";
    ck_assert_int_eq(kelp_util_fmt_fixed(b, sizeof b, 1e19, 2, false), KELP_ERR_RANGE);
    ck_assert_str_eq(b, "untouched");
    /* whole and fraction kept apart: exact where |v| * 10^dec would pass 2^53 */
    ck_assert_str_eq(fx(1e18, 2, false), "1000000000000000000.00");
    ck_assert_str_eq(fx(80356666743.824981, 6, false), "80356666743.824982");
    ck_assert_str_eq(fx(0.9999996, 6, false), "1.000000"); /* the fraction carries */
}
END_TEST

START_TEST(parse_finite_and_strieq)
{
    double v = 0;
    ck_assert_int_eq(kelp_util_parse_finite(" 12.5e1 ", 8, &v), KELP_OK);
    ck_assert(v == 125.0);
    ck_assert_int_eq(kelp_util_parse_finite("inf", 3, &v), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_util_parse_finite("nan", 3, &v), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_util_parse_finite("1e400", 5, &v), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_util_parse_double("1e400", 5, &v), KELP_OK);
    ck_assert(isinf(v));
    ck_assert_int_eq(kelp_util_parse_finite("0.1", 3, &v), KELP_OK);
    ck_assert(v == 0.1);
    ck_assert(kelp_util_strieq("Waypoint", "WAYPOINT"));
    ck_assert(!kelp_util_strieq("Waypoint", "WAYPOINTS"));
    ck_assert(!kelp_util_strieq("", "a"));
    ck_assert(kelp_util_strieq("", ""));
    ck_assert(kelp_util_strieq_n("SPEEDx", 5, "speed"));
    ck_assert(!kelp_util_strieq_n("SPE", 3, "speed"));
}
END_TEST

/* xorshift: the same inputs every run */
static unsigned long long rng_state = 88172645463325252ULL;
static unsigned long long rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

/* The parser is correctly rounded: it agrees bit for bit with the C library's strtod
 * (glibc's is exact) on random doubles printed with 1 to 17 digits, on long digit strings
 * with exponents from -350 to 350, and on subnormals. */
START_TEST(parse_double_agrees_with_strtod)
{
    char buf[128];
    long n = 0;
    for (int it = 0; it < 200000; it++) {
        int len;
        double d;
        switch (it % 3) {
        case 0: {
            unsigned long long u = rnd();
            memcpy(&d, &u, sizeof d);
            if (!isfinite(d)) continue;
            len = snprintf(buf, sizeof buf, "%.*g", (int)(rnd() % 17) + 1, d);
            break;
        }
        case 1: {
            int nd = (int)(rnd() % 45) + 1, p = 0;
            for (int j = 0; j < nd; j++) buf[p++] = (char)('0' + rnd() % 10);
            if (rnd() % 2) {
                int at = (int)(rnd() % (unsigned)(p + 1));
                memmove(buf + at + 1, buf + at, (size_t)(p - at));
                buf[at] = '.';
                p++;
            }
            len = p + snprintf(buf + p, sizeof buf - (size_t)p, "e%d", (int)(rnd() % 700) - 350);
            break;
        }
        default:
            len = snprintf(buf, sizeof buf, "%.17g", ldexp((double)(rnd() >> 11), (int)(rnd() % 2100) - 1100));
        }
        double want = strtod(buf, NULL), got = -1;
        ck_assert_int_eq(kelp_util_parse_double(buf, (size_t)len, &got), KELP_OK);
        if (memcmp(&want, &got, sizeof got) != 0)
            ck_abort_msg("%s: strtod %.17g, kelp %.17g", buf, want, got);
        n++;
    }
    ck_assert_int_gt(n, 190000);
}
END_TEST

/* A fuzz finding: a node report's LAT=80356666743.824981 printed with 6 decimals did not
 * read back as the same double (17 significant digits, past the exact fast path). */
START_TEST(parse_format_parse_is_stable)
{
    const char *in[] = {"80356666743.824981", "-732.90755", "9007199254740993", "4.9e-324",
                        "2.2250738585072011e-308", "1.7976931348623157e308", "0.1", "123456.654321"};
    for (size_t i = 0; i < sizeof in / sizeof in[0]; i++) {
        double a, b;
        char t[64];
        ck_assert_int_eq(kelp_util_parse_double(in[i], strlen(in[i]), &a), KELP_OK);
        ck_assert(a == strtod(in[i], NULL));
        int n = kelp_util_fmt_fixed(t, sizeof t, a, 6, false);
        if (n < 0 || n >= (int)sizeof t) continue; /* beyond the formatter's range */
        ck_assert_int_eq(kelp_util_parse_double(t, (size_t)n, &b), KELP_OK);
        char u[64];
        ck_assert_int_eq(kelp_util_fmt_fixed(u, sizeof u, b, 6, false), n);
        ck_assert_str_eq(t, u);
    }
}
END_TEST

START_TEST(kv_walk_bounded)
{
    const char text[] = "a=1, b = two,c=3"; /* walked only to "a=1, b = two" */
    size_t pos = 0, kl, vl;
    const char *k, *v;
    ck_assert_int_eq(kelp_kv_next_n(text, 12, ',', &pos, &k, &kl, &v, &vl), 1);
    ck_assert(kl == 1 && k[0] == 'a' && vl == 1 && v[0] == '1');
    ck_assert_int_eq(kelp_kv_next_n(text, 12, ',', &pos, &k, &kl, &v, &vl), 1);
    ck_assert(kl == 1 && k[0] == 'b' && vl == 3 && memcmp(v, "two", 3) == 0);
    ck_assert_int_eq(kelp_kv_next_n(text, 12, ',', &pos, &k, &kl, &v, &vl), 0);
    pos = 0;
    ck_assert_int_eq(kelp_kv_next_n("x", 1, ',', &pos, &k, &kl, &v, &vl), KELP_ERR_PARSE);
}
END_TEST

START_TEST(big_endian_bytes)
{
    uint8_t b[8];
    kelp_util_be_put64(b, 0x0102030405060708ull);
    ck_assert_uint_eq(b[0], 1);
    ck_assert_uint_eq(b[7], 8);
    ck_assert(kelp_util_be_get64(b) == 0x0102030405060708ull);
    kelp_util_be_put32(b, 0xdeadbeefu);
    ck_assert_uint_eq(b[0], 0xde);
    ck_assert_uint_eq(b[3], 0xef);
    ck_assert_uint_eq(kelp_util_be_get32(b), 0xdeadbeefu);
    long l;
    ck_assert_int_eq(kelp_util_parse_long(" -42 ", 5, &l), KELP_OK);
    ck_assert_int_eq(l, -42);
    ck_assert_int_eq(kelp_util_parse_long("99999999999999999999", 20, &l), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_util_parse_long("4x", 2, &l), KELP_ERR_PARSE);
}
END_TEST

Suite *kelp_util_num_suite(void);
Suite *kelp_util_num_suite(void)
{
    Suite *s = suite_create("util_num");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, fmt_fixed_rounding_and_sign);
    tcase_add_test(tc, fmt_fixed_strip_special_and_space);
    tcase_add_test(tc, fmt_fixed_as_printf);
    tcase_add_test(tc, parse_finite_and_strieq);
    tcase_add_test(tc, parse_format_parse_is_stable);
    tcase_add_test(tc, big_endian_bytes);
    tcase_add_test(tc, kv_walk_bounded);
    suite_add_tcase(s, tc);
    /* 200,000 numbers: a second under -O2, 5-10 s under ASan/UBSan on a loaded two-core CI
     * machine (it timed out at Check's 4 s there), minutes under qemu (cross.sh scales it) */
    TCase *big = tcase_create("strtod");
    tcase_set_timeout(big, 60);
    tcase_add_test(big, parse_double_agrees_with_strtod);
    suite_add_tcase(s, big);
    return s;
}
