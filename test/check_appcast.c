/* kelp AppCast: the APPCAST string, its terminal form, APPCAST_REQ. */
#include <check.h>
#include "check_diag.h"
#include <string.h>
#include <kelp/appcast.h>

static kelp_appcast ac, back;
static char buf[8192];

static void sample(void)
{
    memset(&ac, 0, sizeof ac);
    strcpy(ac.proc, "pHostInfo");
    strcpy(ac.node, "alpha");
    ac.iter = 12;
    strcpy(ac.messages, "Host IP 10.0.0.1\nDB port 9000");
    ac.ncfg = 2;
    strcpy(ac.cfg[0], "line 4: unknown parameter FOO");
    strcpy(ac.cfg[1], "second");
    ac.nevents = 1;
    strcpy(ac.events[0], "[3.20]: 2 address(es) found");
    ac.nrun = 2;
    strcpy(ac.run[0], "zebra warning");
    ac.run_count[0] = 1;
    strcpy(ac.run[1], "no route");
    ac.run_count[1] = 3;
    ac.run_total = 4;
}

START_TEST(format_as_moos)
{
    sample();
    size_t len;
    ck_assert_int_eq(kelp_appcast_format(&ac, buf, sizeof buf, &len), KELP_OK);
    ck_assert_str_eq(buf, "proc=pHostInfo!@#iter=12!@#node=alpha!@#iter=12!@#messages=Host IP 10.0.0.1!@DB port 9000!@!@#"
                          "config_warnings=line 4: unknown parameter FOO!@second!@#events_total=1!@#"
                          "events=[3.20]: 2 address(es) found!@#run_warning_total=4!@#run_warnings=3:no route!@1:zebra warning");
    ck_assert_uint_eq(len, strlen(buf));
    /* no warnings, no events: the empty parts stay, as MOOS-IvP writes them */
    memset(&ac, 0, sizeof ac);
    strcpy(ac.proc, "uX");
    ck_assert_int_eq(kelp_appcast_format(&ac, buf, sizeof buf, &len), KELP_OK);
    ck_assert_str_eq(buf, "proc=uX!@#iter=0!@#iter=0!@#messages=!@#!@#events_total=0!@#!@#run_warning_total=0!@#");
    /* too small: cut, NUL-terminated, and said */
    char small[20];
    ck_assert_int_eq(kelp_appcast_format(&ac, small, sizeof small, &len), KELP_ERR_NOSPACE);
    ck_assert_uint_eq(strlen(small), sizeof small - 1);
}
END_TEST

START_TEST(parse_round_trip_and_separators)
{
    sample();
    strcpy(ac.messages, "a!@b\nline two");  /* a separator inside the text */
    size_t len;
    ck_assert_int_eq(kelp_appcast_format(&ac, buf, sizeof buf, &len), KELP_OK);
    kelp_diag why;
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_appcast_parse(buf, len, &back, &why), KELP_OK);
    ck_assert_str_eq(back.proc, "pHostInfo");
    ck_assert_str_eq(back.node, "alpha");
    ck_assert_uint_eq(back.iter, 12);
    ck_assert_str_eq(back.messages, "a!_b\nline two\n");
    ck_assert_uint_eq(back.ncfg, 2);
    ck_assert_str_eq(back.cfg[1], "second");
    ck_assert_uint_eq(back.nevents, 1);
    ck_assert_str_eq(back.events[0], "[3.20]: 2 address(es) found");
    ck_assert_uint_eq(back.nrun, 2);
    ck_assert_str_eq(back.run[0], "no route");
    ck_assert_uint_eq(back.run_count[0], 3);
    ck_assert_uint_eq(back.run_total, 4);
    /* unknown parts are ignored; a part without '=' and a cast without proc= are errors */
    ck_assert_int_eq(kelp_appcast_parse("proc=a!@#colour=red", 19, &back, &why), KELP_OK);
    ck_assert_int_eq(kelp_appcast_parse("proc=a!@#junk", 13, &back, &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_appcast_parse("iter=3", 6, &back, &why), KELP_ERR_PARSE);
    ck_assert_int_eq(why.code, KELP_ERR_PARSE);
#ifndef KELP_NO_ERRMSG
    ck_assert_str_eq(kelp_diag_text(&why), "a part without '='"); /* the first failure is kept */
#endif
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_appcast_parse("iter=3", 6, &back, &why), KELP_ERR_PARSE);
    ck_diag_msg(&why, "no proc=");
}
END_TEST

START_TEST(render_like_umac)
{
    sample();
    size_t len;
    ck_assert_int_eq(kelp_appcast_render(&ac, buf, sizeof buf, &len), KELP_OK);
    ck_assert_ptr_nonnull(strstr(buf, "\npHostInfo alpha                                        2/4(12)\n"));
    ck_assert_ptr_nonnull(strstr(buf, "Configuration Warnings: 2\n [1 of 2]: line 4: unknown parameter FOO\n"));
    ck_assert_ptr_nonnull(strstr(buf, "Runtime Warnings: 4\n [1]: zebra warning\n [3]: no route\n"));
    ck_assert_ptr_nonnull(strstr(buf, "Host IP 10.0.0.1\nDB port 9000\n"));
    ck_assert_ptr_nonnull(strstr(buf, "Most Recent Events (1):\n"));
}
END_TEST

START_TEST(request)
{
    kelp_appcast_req r;
    const char *s = "node=alpha, app=pHostInfo, duration=45, key=uMAC_438";
    ck_assert_int_eq(kelp_appcast_req_parse(s, strlen(s), &r), KELP_OK);
    ck_assert(r.duration == 30); /* clamped */
    ck_assert_str_eq(r.thresh, "any");
    ck_assert(kelp_appcast_req_matches(&r, "alpha", "pHostInfo"));
    ck_assert(!kelp_appcast_req_matches(&r, "bravo", "pHostInfo"));
    ck_assert(!kelp_appcast_req_matches(&r, "alpha", "pHelmIvP"));
    s = "node=all,app=all,duration=-2,key=k,thresh=run_warning";
    ck_assert_int_eq(kelp_appcast_req_parse(s, strlen(s), &r), KELP_OK);
    ck_assert(r.duration == 0);
    ck_assert_str_eq(r.thresh, "run_warning");
    ck_assert(kelp_appcast_req_matches(&r, "x", "y"));
    s = "node=all,app=all,duration=3";
    ck_assert_int_eq(kelp_appcast_req_parse(s, strlen(s), &r), KELP_ERR_PARSE); /* no key */
}
END_TEST

/* one field without parsing the rest: the same reading as kelp_appcast_parse */
START_TEST(field_lookup)
{
    const char *c = "proc=pHelmIvP!@#iter=12!@# Node = alpha !@#messages=a!@#b!@#events_total=0!@#";
    char v[16];
    ck_assert_int_eq(kelp_appcast_field(c, strlen(c), "proc", v, sizeof v), 1);
    ck_assert_str_eq(v, "pHelmIvP");
    ck_assert_int_eq(kelp_appcast_field(c, strlen(c), "node", v, sizeof v), 1);
    ck_assert_str_eq(v, "alpha");
    ck_assert_int_eq(kelp_appcast_field(c, strlen(c), "iter", v, 3), 1);
    ck_assert_str_eq(v, "12");
    ck_assert_int_eq(kelp_appcast_field(c, strlen(c), "nod", v, sizeof v), 0);
    ck_assert_int_eq(kelp_appcast_field(c, strlen(c), "warnings", v, sizeof v), 0);
    ck_assert_int_eq(kelp_appcast_field("", 0, "proc", v, sizeof v), 0);
}
END_TEST

Suite *kelp_appcast_suite(void);
Suite *kelp_appcast_suite(void)
{
    Suite *s = suite_create("appcast");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, format_as_moos);
    tcase_add_test(tc, parse_round_trip_and_separators);
    tcase_add_test(tc, render_like_umac);
    tcase_add_test(tc, field_lookup);
    tcase_add_test(tc, request);
    suite_add_tcase(s, tc);
    return s;
}
