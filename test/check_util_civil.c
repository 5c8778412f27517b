/* util: civil dates and hex (src/util/civil.c, src/util/hex.c). */
#include <check.h>
#include <string.h>
#include <kelp/util.h>

START_TEST(civil_dates)
{
    ck_assert_int_eq(kelp_util_days_from_civil(1970, 1, 1), 0);
    ck_assert_int_eq(kelp_util_days_from_civil(2000, 3, 1), 11017);
    ck_assert_int_eq(kelp_util_days_from_civil(1969, 12, 31), -1);
    ck_assert_int_eq(kelp_util_days_from_civil(2026, 11, 25), 20782);
    ck_assert_int_eq(kelp_util_floor_div(-1, 86400), -1);
    ck_assert_int_eq(kelp_util_floor_div(86399, 86400), 0);
    for (int64_t d = -800000; d <= 800000; d += 97) {
        int64_t y;
        unsigned m, dd;
        kelp_util_civil_from_days(d, &y, &m, &dd);
        ck_assert(m >= 1 && m <= 12 && dd >= 1 && dd <= 31);
        ck_assert_int_eq(kelp_util_days_from_civil(y, m, dd), d);
    }
    int64_t y;
    unsigned m, dd;
    kelp_util_civil_from_days(11016, &y, &m, &dd); /* a leap day */
    ck_assert(y == 2000 && m == 2 && dd == 29);
}
END_TEST

START_TEST(hex_digits_and_bytes)
{
    ck_assert_int_eq(kelp_util_hex_digit('0'), 0);
    ck_assert_int_eq(kelp_util_hex_digit('f'), 15);
    ck_assert_int_eq(kelp_util_hex_digit('F'), 15);
    ck_assert_int_eq(kelp_util_hex_digit('g'), -1);
    uint8_t b[4];
    size_t n = 0;
    ck_assert_int_eq(kelp_util_hex_decode("00aBff", 6, b, sizeof b, &n), 0);
    ck_assert(n == 3 && b[0] == 0 && b[1] == 0xab && b[2] == 0xff);
    ck_assert_int_eq(kelp_util_hex_decode("abc", 3, b, sizeof b, &n), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_util_hex_decode("zz", 2, b, sizeof b, &n), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_util_hex_decode("0011223344", 10, b, sizeof b, &n), KELP_ERR_NOSPACE);
}
END_TEST

Suite *kelp_util_civil_suite(void)
{
    Suite *s = suite_create("util_civil");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, civil_dates);
    tcase_add_test(tc, hex_digits_and_bytes);
    suite_add_tcase(s, tc);
    return s;
}
