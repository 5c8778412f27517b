/* kelp util: the one number formatter and parser every module uses. */
#include <check.h>
#include <math.h>
#include <string.h>
#include <kelp/util.h>

static const char *fx(double v, unsigned dec, bool strip)
{
    static char buf[64];
    ck_assert_int_ge(kelp_fmt_fixed(buf, sizeof buf, v, dec, strip), 0);
    return buf;
}

START_TEST(fmt_fixed_rounding_and_sign)
{
    ck_assert_str_eq(fx(2.5, 0, false), "3");        /* half away from zero */
    ck_assert_str_eq(fx(-2.5, 0, false), "-3");
    ck_assert_str_eq(fx(1.005, 2, false), "1.00");   /* 1.005 is 1.00499999999999989... */
    ck_assert_str_eq(fx(0.125, 2, false), "0.13");
    ck_assert_str_eq(fx(-0.0004, 3, false), "0.000"); /* never "-0" */
    ck_assert_str_eq(fx(-0.0, 0, false), "0");
    ck_assert_str_eq(fx(123.456, 1, false), "123.5");
    ck_assert_str_eq(fx(7, 3, false), "7.000");
    ck_assert_str_eq(fx(1e12 + 0.25, 2, false), "1000000000000.25");
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
    ck_assert_int_eq(kelp_fmt_fixed(small, sizeof small, 12345.5, 1, false), 7); /* needed length */
    ck_assert_str_eq(small, "123");                                              /* truncated, NUL */
    char b[32] = "untouched";
    ck_assert_int_eq(kelp_fmt_fixed(b, sizeof b, 1e18, 2, false), KELP_ERR_RANGE);
    ck_assert_str_eq(b, "untouched");
}
END_TEST

START_TEST(parse_finite_and_strieq)
{
    double v = 0;
    ck_assert_int_eq(kelp_parse_finite(" 12.5e1 ", 8, &v), KELP_OK);
    ck_assert(v == 125.0);
    ck_assert_int_eq(kelp_parse_finite("inf", 3, &v), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_parse_finite("nan", 3, &v), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_parse_finite("1e400", 5, &v), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_parse_double("1e400", 5, &v), KELP_OK);
    ck_assert(isinf(v));
    ck_assert_int_eq(kelp_parse_finite("0.1", 3, &v), KELP_OK);
    ck_assert(v == 0.1);
    ck_assert(kelp_strieq("Waypoint", "WAYPOINT"));
    ck_assert(!kelp_strieq("Waypoint", "WAYPOINTS"));
    ck_assert(!kelp_strieq("", "a"));
    ck_assert(kelp_strieq("", ""));
    ck_assert(kelp_strieq_n("SPEEDx", 5, "speed"));
    ck_assert(!kelp_strieq_n("SPE", 3, "speed"));
}
END_TEST

Suite *kelp_util_num_suite(void);
Suite *kelp_util_num_suite(void)
{
    Suite *s = suite_create("util_num");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, fmt_fixed_rounding_and_sign);
    tcase_add_test(tc, fmt_fixed_strip_special_and_space);
    tcase_add_test(tc, parse_finite_and_strieq);
    suite_add_tcase(s, tc);
    return s;
}
