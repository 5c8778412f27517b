#include <check.h>
#include <string.h>
#include <kelp/err.h>

START_TEST(strerror_known_and_unknown)
{
    ck_assert_str_eq(kelp_strerror(KELP_OK), "ok");
    ck_assert_str_eq(kelp_strerror(KELP_ERR_NOSPACE), "storage too small");
    ck_assert_str_eq(kelp_strerror(12345), "unknown error");
}
END_TEST

Suite *kelp_err_suite(void)
{
    Suite *s = suite_create("err");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, strerror_known_and_unknown);
    suite_add_tcase(s, tc);
    return s;
}
