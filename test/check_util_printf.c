/* kelp util: the core's own snprintf (the one firmware uses) against the C library's. */
#include <check.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <kelp/util.h>

static int own(char *buf, size_t cap, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = kelp_util_vsnprintf_own(buf, cap, fmt, ap);
    va_end(ap);
    return n;
}

#define SAME(...)                                                                                       \
    do {                                                                                                \
        char a[256], b[256];                                                                            \
        int na = own(a, sizeof a, __VA_ARGS__), nb = snprintf(b, sizeof b, __VA_ARGS__);                \
        ck_assert_msg(na == nb && strcmp(a, b) == 0, "%s: own \"%s\" (%d), libc \"%s\" (%d)", #__VA_ARGS__, a, \
                      na, b, nb);                                                                       \
    } while (0)

START_TEST(integers_and_strings)
{
    SAME("%d|%i|%u|%x|%X|%o", -42, 7, 4000000000u, 0xbeefu, 0xbeefu, 8u);
    SAME("%5d|%-5d|%05d|%+d|% d|%.3d|%.0d|", 42, 42, -42, 42, 42, 7, 0);
    SAME("%ld %lu %lld %llu %zu", -1234567890L, 4294967295UL, -9223372036854775807LL - 1, 18446744073709551615ULL,
         (size_t)12345);
    SAME("%hhd %hd %hhu %hu", 300, 70000, 300, 70000);
    SAME("%02x%02x %#x %#o %06ld %04d", 0xa, 0xbc, 255u, 8u, -42L, 7);
    SAME("%s|%10s|%-10s|%.3s|%.*s|%*d|%-*d|", "kelp", "kelp", "kelp", "kelpie", 2, "abc", 6, 5, 6, 5);
    SAME("%c%c%% done %s", 'o', 'k', "");
    SAME("%lu: %s%s", 7UL, "Total", " received");
}
END_TEST

START_TEST(fixed_point)
{
    SAME("%.1f %.0f %.2f %.3f %.4f %.7f", 12.25, 1234.4, -0.004, 3.14159, 2.5e-5, 43.8252991);
    SAME("%f %10.2f %-10.2f| %010.3f %+.1f", 1.5, -3.25, 3.25, -7.125, 0.04);
    SAME("%.*f %.*f", 2, 1e6 + 0.123, 0, 0.4);
    SAME("%.1f %.1f %.1f", 0.05, 0.15, 0.95); /* no exact ties in binary: rounded from the value */
    SAME("%.2f %.2f %.1f %.0f %.0f %.0f", 0.125, 0.375, 12.25, 0.5, 1.5, 2.5); /* exact ties: to even */
    SAME("%.12f %.15f", 1.0 / 3.0, 2.0 / 3.0);
    SAME("%.2f %.0f %f", 1.23e15, 9.99e18, 123456789012.5);
    SAME("%.3f %f %F", NAN, INFINITY, -INFINITY);
}
END_TEST

START_TEST(exponent_and_general)
{
    SAME("%e %.3e %E %.0e", 12345.678, -0.000123456, 6.02e23, 5e-7);
    SAME("%g %g %g %g %g %g", 100000.0, 1e6, 1e-4, 1e-5, 0.0, -2.5);
    SAME("%.6g %.3g %.10g %G", 43.825299123, 1234.5, 1.0 / 7.0, 1e-10);
    SAME("%.15g %.15g %.15g", 0.1, 1.0 / 3.0, 12345.6789);
    SAME("%.17g", 1e22);
    char rb[40]; /* beyond 15 digits: not printf's exact expansion, but the same double back */
    double back = 0;
    ck_assert_int_gt(own(rb, sizeof rb, "%.17g", 0.1), 0);
    ck_assert_int_eq(kelp_util_parse_double(rb, strlen(rb), &back), 0);
    ck_assert(back == 0.1);
    SAME("%#g %#.3g", 1.0, 2.5);
    SAME("%g|%8.3g|%-8.3g|", 1e100, 3.14159, 3.14159);
}
END_TEST

START_TEST(truncation_and_return)
{
    char b[8];
    ck_assert_int_eq(kelp_util_snprintf(b, sizeof b, "%s=%d", "speed", 12345), 11);
    ck_assert_str_eq(b, "speed=1");
    char z[1] = "x";
    ck_assert_int_eq(own(z, 0, "%d", 5), 1); /* cap 0: nothing written */
    ck_assert_int_eq(z[0], 'x');
    ck_assert_int_eq(own(b, sizeof b, "%q"), 2); /* an unknown conversion prints itself */
    ck_assert_str_eq(b, "%q");
}
END_TEST

Suite *kelp_util_printf_suite(void);
Suite *kelp_util_printf_suite(void)
{
    Suite *s = suite_create("util_printf");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, integers_and_strings);
    tcase_add_test(tc, fixed_point);
    tcase_add_test(tc, exponent_and_general);
    tcase_add_test(tc, truncation_and_return);
    suite_add_tcase(s, tc);
    return s;
}
