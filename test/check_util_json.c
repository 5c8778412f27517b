#include <check.h>
#include <string.h>
#include <kelp/util.h>

START_TEST(json_quote_escapes)
{
    char buf[64];
    const char in[] = "a\"b\\c\n\x01\x7f\xe9 ok";
    size_t n = kelp_util_json_quote(buf, sizeof buf, in, sizeof in - 1);
    ck_assert_str_eq(buf, "\"a\\\"b\\\\c\\u000a\\u0001\\u007f\\u00e9 ok\"");
    ck_assert_uint_eq(n, strlen(buf));
    ck_assert_uint_eq(kelp_util_json_quote(buf, sizeof buf, "x\0y", 3), 10);
    ck_assert_str_eq(buf, "\"x\\u0000y\"");
}
END_TEST

START_TEST(json_quote_truncates_like_snprintf)
{
    char buf[5];
    ck_assert_uint_eq(kelp_util_json_quote(buf, sizeof buf, "abcdef", 6), 8);
    ck_assert_str_eq(buf, "\"abc");
    ck_assert_uint_eq(kelp_util_json_quote(NULL, 0, "ab", 2), 4);
}
END_TEST

Suite *kelp_util_json_suite(void)
{
    Suite *s = suite_create("util_json");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, json_quote_escapes);
    tcase_add_test(tc, json_quote_truncates_like_snprintf);
    suite_add_tcase(s, tc);
    return s;
}
