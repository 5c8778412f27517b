#include <check.h>
#include <string.h>
#include <kelp/err.h>

START_TEST(strerror_known_and_unknown)
{
    ck_assert_str_eq(kelp_err_str(KELP_OK), "ok");
    ck_assert_str_eq(kelp_err_str(KELP_ERR_NOSPACE), "storage too small");
    ck_assert_str_eq(kelp_err_str(12345), "unknown error");
}
END_TEST

START_TEST(diag_first_error_wins)
{
    kelp_diag d;
    kelp_diag_clear(&d);
    ck_assert_str_eq(kelp_diag_text(&d), "");
    ck_assert_int_eq(kelp_diag_where(&d, 3, 4), KELP_OK); /* no failure: no place either */
    ck_assert_int_eq(d.line, 0);
    ck_assert_int_eq(kelp_fail(&d, KELP_ERR_PARSE, "inner reason"), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_failf(&d, KELP_ERR_RANGE, "outer %d", 7), KELP_ERR_RANGE);
    ck_assert_int_eq(d.code, KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_diag_where(&d, 0, 9), KELP_ERR_PARSE); /* inner layer knows the column */
    ck_assert_int_eq(kelp_diag_where(&d, 12, 1), KELP_ERR_PARSE); /* outer knows the line */
    ck_assert_int_eq(d.line, 12);
    ck_assert_int_eq(d.col, 9);
#ifdef KELP_NO_ERRMSG
    ck_assert_str_eq(kelp_diag_text(&d), "parse error");
#else
    ck_assert_str_eq(kelp_diag_text(&d), "inner reason");
#endif
    kelp_diag_clear(&d);
    ck_assert_int_eq(kelp_failf(&d, KELP_ERR_RANGE, "value %d of %s", 42, "speed"), KELP_ERR_RANGE);
#ifdef KELP_NO_ERRMSG
    ck_assert_str_eq(kelp_diag_text(&d), "value out of range");
#else
    ck_assert_str_eq(kelp_diag_text(&d), "value 42 of speed");
#endif
    kelp_diag_clear(&d);
    (void)kelp_fail(&d, KELP_ERR_NOSPACE, (const char *)0); /* no message: the code's text */
    ck_assert_str_eq(kelp_diag_text(&d), "storage too small");
    ck_assert_int_eq(kelp_fail((kelp_diag *)0, KELP_ERR_ARG, "x"), KELP_ERR_ARG); /* NULL record */
    ck_assert_str_eq(kelp_diag_text((const kelp_diag *)0), "");
    kelp_diag_clear(&d);
    ck_assert_int_eq(kelp_fail(&d, KELP_OK, "not a failure"), KELP_OK);
    ck_assert_int_eq(d.code, KELP_OK);
}
END_TEST

START_TEST(diag_long_message_truncated)
{
    kelp_diag d;
    char big[400];
    memset(big, 'x', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    kelp_diag_clear(&d);
    (void)kelp_fail(&d, KELP_ERR_PARSE, big);
#ifndef KELP_NO_ERRMSG
    ck_assert_uint_eq(strlen(kelp_diag_text(&d)), KELP_DIAG_MSG_MAX - 1);
#endif
    kelp_diag_clear(&d);
    (void)kelp_failf(&d, KELP_ERR_PARSE, "%s", big);
#ifndef KELP_NO_ERRMSG
    ck_assert_uint_eq(strlen(kelp_diag_text(&d)), KELP_DIAG_MSG_MAX - 1);
#endif
}
END_TEST

Suite *kelp_err_suite(void)
{
    Suite *s = suite_create("err");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, strerror_known_and_unknown);
    tcase_add_test(tc, diag_first_error_wins);
    tcase_add_test(tc, diag_long_message_truncated);
    suite_add_tcase(s, tc);
    return s;
}
