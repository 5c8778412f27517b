/* MOOS .alog lines (src/bus/alog.c): pLogger's layout written and read back. */
#include <check.h>
#include <string.h>
#include <kelp/alog.h>

static bool eq(const char *p, size_t n, const char *z) { return strlen(z) == n && memcmp(p, z, n) == 0; }

START_TEST(alog_format_as_plogger)
{
    char b[512];
    int n = kelp_alog_format_line(b, sizeof b, 100.846, "NAV_X", "uSimMarine", false, NULL, -99.371, 5, false);
    ck_assert_int_gt(n, 0);
    ck_assert_str_eq(b, "100.84600       NAV_X                uSimMarine      -99.37100    \n");
    ck_assert_int_eq(n, (int)strlen(b));
    n = kelp_alog_format_line(b, sizeof b, 0.5, "BRS_RANGE_REPORT", "uFldBeaconRangeSensor", true,
                              "vname=indigo,range=166.7446,id=03", 0, 5, false);
    ck_assert_str_eq(b, "0.50000         BRS_RANGE_REPORT     uFldBeaconRangeSensor vname=indigo,range=166.7446,id=03 \n");
    n = kelp_alog_format_line(b, sizeof b, 1, "A", "src@bravo", true, "12", 0, 5, true);
    ck_assert_str_eq(b, "1.00000         A                    src@bravo       S:12 \n");
    n = kelp_alog_format_line(b, sizeof b, 1, "A", "s", false, NULL, 0.1, -1, true);
    ck_assert_str_eq(b, "1               A                    s               D:0.10000000000000001 \n");
    n = kelp_alog_format_line(b, sizeof b, 2, "BIG", "s", false, NULL, 1e20, 5, false); /* beyond fixed decimals */
    ck_assert_str_eq(b, "2.00000         BIG                  s               1e+20        \n");
    /* refused: a line break in a value, white space in a name, no room */
    ck_assert_int_eq(kelp_alog_format_line(b, sizeof b, 1, "A", "s", true, "a\nb", 0, 5, false), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_alog_format_line(b, sizeof b, 1, "A B", "s", true, "x", 0, 5, false), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_alog_format_line(b, sizeof b, 1, "A", "", true, "x", 0, 5, false), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_alog_format_line(b, 20, 1, "A", "s", true, "x", 0, 5, false), KELP_ERR_NOSPACE);
}
END_TEST

START_TEST(alog_parse_lines)
{
    kelp_alog_line l;
    const char *s = "100.847 BRS_RANGE_REPORT     uFldBeaconRangeSensor vname=indigo, range=304.6305 \r";
    ck_assert_int_eq(kelp_alog_parse_line(s, strlen(s), &l), 1);
    ck_assert_double_eq(l.time, 100.847);
    ck_assert(eq(l.var, l.var_len, "BRS_RANGE_REPORT"));
    ck_assert(eq(l.src, l.src_len, "uFldBeaconRangeSensor"));
    ck_assert(eq(l.val, l.val_len, "vname=indigo, range=304.6305"));
    s = "3.5\tX\tsrc\t";
    ck_assert_int_eq(kelp_alog_parse_line(s, strlen(s), &l), 1);
    ck_assert_int_eq((int)l.val_len, 0);
    const char *comments[] = { "%% LOGSTART 12", "", "   ", "%%%%%" };
    for (int i = 0; i < 4; i++) ck_assert_int_eq(kelp_alog_parse_line(comments[i], strlen(comments[i]), &l), 0);
    const char *bad[] = { "abc X src v", "1.5", "1.5 X", "nan X s v" };
    for (int i = 0; i < 4; i++) ck_assert_int_eq(kelp_alog_parse_line(bad[i], strlen(bad[i]), &l), KELP_ERR_PARSE);
    double t;
    s = "%% LOGSTART           23371445284.8  ";
    ck_assert_int_eq(kelp_alog_parse_logstart(s, strlen(s), &t), 1);
    ck_assert_double_eq(t, 23371445284.8);
    s = "% LOGSTART      23371445284.8"; /* the seed's one-% banner */
    ck_assert_int_eq(kelp_alog_parse_logstart(s, strlen(s), &t), 1);
    s = "%% LOGSTART x";
    ck_assert_int_eq(kelp_alog_parse_logstart(s, strlen(s), &t), KELP_ERR_PARSE);
    s = "%% LOG FILE: a";
    ck_assert_int_eq(kelp_alog_parse_logstart(s, strlen(s), &t), 0);
    ck_assert(kelp_alog_is_marking("%% DATATYPE MARKING ON", 22));
    ck_assert(!kelp_alog_is_marking("%% LOGSTART 1", 13));
}
END_TEST

START_TEST(alog_values_and_round_trip)
{
    double d = 0;
    const char *s = NULL;
    size_t sl = 0;
    ck_assert_int_eq(kelp_alog_value("-99.37100", 9, false, &d, &s, &sl), 1);
    ck_assert_double_eq(d, -99.371);
    ck_assert_int_eq(kelp_alog_value("name=x", 6, false, &d, &s, &sl), 0);
    ck_assert(eq(s, sl, "name=x"));
    ck_assert_int_eq(kelp_alog_value("S:12", 4, true, &d, &s, &sl), 0);
    ck_assert(eq(s, sl, "12"));
    ck_assert_int_eq(kelp_alog_value("D:12", 4, true, &d, &s, &sl), 1);
    ck_assert_double_eq(d, 12);
    ck_assert_int_eq(kelp_alog_value("D:x", 3, true, &d, &s, &sl), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_alog_value("", 0, false, &d, &s, &sl), 0);
    /* exact: every double reads back bit for bit */
    const double v[] = { 0.1, -1e-300, 1795603462.3530001, 3.141592653589793, 1e22 };
    for (int i = 0; i < 5; i++) {
        char b[256];
        kelp_alog_line l;
        ck_assert_int_gt(kelp_alog_format_line(b, sizeof b, v[i], "V", "s", false, NULL, v[i], -1, true), 0);
        ck_assert_int_eq(kelp_alog_parse_line(b, strlen(b), &l), 1);
        ck_assert_int_eq(kelp_alog_value(l.val, l.val_len, true, &d, &s, &sl), 1);
        ck_assert(d == v[i] && l.time == v[i]);
    }
    /* strings keep inner and one trailing space */
    char b[256];
    kelp_alog_line l;
    ck_assert_int_gt(kelp_alog_format_line(b, sizeof b, 1, "N", "s", true, "two  spaces ", 0, 5, false), 0);
    ck_assert_int_eq(kelp_alog_parse_line(b, strlen(b) - 1, &l), 1);
    ck_assert(eq(l.val, l.val_len, "two  spaces "));
}
END_TEST

Suite *kelp_alog_suite(void)
{
    Suite *s = suite_create("alog");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, alog_format_as_plogger);
    tcase_add_test(tc, alog_parse_lines);
    tcase_add_test(tc, alog_values_and_round_trip);
    suite_add_tcase(s, tc);
    return s;
}
