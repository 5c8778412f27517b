/* pNodeReporter's state machine (src/field/nodereporter.c) driven with a recording sink. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>

typedef struct rec {
    int n, warnings;
    char var[8][KELP_MAX_NAME];
    char val[8][KELP_NODEREPORT_MAX_LEN];
} rec;

static void rec_publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    (void)dval;
    ck_assert(is_string);
    if (r->n < 8) {
        snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
        snprintf(r->val[r->n], sizeof r->val[0], "%s", sval);
    }
    r->n++;
}

static void rec_warn(void *ctx, const char *msg)
{
    (void)msg;
    ((rec *)ctx)->warnings++;
}

static void mail_d(kelp_field_nrep *nr, const char *var, double d, const kelp_field_sink *s)
{
    ck_assert_int_eq(kelp_field_nrep_mail(nr, var, false, NULL, d, s), 1);
}

START_TEST(nrep_report_from_nav_and_helm)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, rec_publish, rec_warn };
    kelp_field_nrep_cfg cfg;
    kelp_field_nrep_cfg_default(&cfg, "alpha");
    cfg.length = 3.8;
    cfg.have_length = true;
    ck_assert_int_eq(kelp_geo_init(&cfg.geo, 43.825300, -70.330400), 0);
    cfg.have_geo = true;
    kelp_field_nrep nr;
    ck_assert_int_eq(kelp_field_nrep_init(&nr, &cfg), 0);
    /* subscriptions: the NAV_* variables and the helm's */
    ck_assert_str_eq(kelp_field_nrep_subscription(&nr, 0), "NAV_X");
    ck_assert_str_eq(kelp_field_nrep_subscription(&nr, 3), "NAV_LONG");
    ck_assert_str_eq(kelp_field_nrep_subscription(&nr, 7), "IVPHELM_STATE");
    ck_assert_ptr_null(kelp_field_nrep_subscription(&nr, 10));
    /* nothing before a position */
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 100, &sink), 0);
    mail_d(&nr, "NAV_X", 51.71, &sink);
    mail_d(&nr, "NAV_Y", -35.5, &sink);
    mail_d(&nr, "NAV_SPEED", 2, &sink);
    mail_d(&nr, "NAV_HEADING", 118.85, &sink);
    mail_d(&nr, "NAV_DEPTH", 4.63, &sink);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "IVPHELM_SUMMARY", true, "iter=3,modes=MODE@ACTIVE:LOITERING", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "IVPHELM_ALLSTOP", true, "clear", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "OTHER", true, "x", 0, &sink), 0);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1252348077.59, &sink), 1);
    ck_assert_int_eq(r.n, 1);
    ck_assert_str_eq(r.var[0], "NODE_REPORT_LOCAL");
    kelp_nodereport back;
    ck_assert_int_eq(kelp_nodereport_parse(r.val[0], strlen(r.val[0]), &back, NULL), 0);
    ck_assert_str_eq(back.name, "alpha");
    ck_assert_str_eq(back.type, "UUV");
    ck_assert_str_eq(back.mode, "MODE@ACTIVE:LOITERING");
    ck_assert(fabs(back.x - 51.71) < 0.006 && fabs(back.y + 35.5) < 0.006);
    ck_assert(fabs(back.lat - 43.824981) < 2e-6 && fabs(back.lon + 70.329755) < 2e-6); /* from LatOrigin */
    ck_assert(back.length == 3.8 && back.spd == 2 && fabs(back.hdg - 118.85) < 0.006);
    ck_assert_ptr_nonnull(strstr(r.val[0], "NAME=alpha,"));
    /* one report per fresh navigation */
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1252348078, &sink), 0);
    /* bad navigation is refused with a warning and loses nothing else */
    ck_assert_int_lt(kelp_field_nrep_mail(&nr, "NAV_X", true, "abc", 0, &sink), 0);
    ck_assert_int_lt(kelp_field_nrep_mail(&nr, "NAV_Y", false, NULL, INFINITY, &sink), 0);
    ck_assert_int_eq(r.warnings, 2);
    mail_d(&nr, "NAV_DEPTH", 5, &sink);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1252348079, &sink), 1);
    ck_assert_int_eq(kelp_nodereport_parse(r.val[1], strlen(r.val[1]), &back, NULL), 0);
    ck_assert(fabs(back.x - 51.71) < 0.006 && back.depth == 5);
}
END_TEST

START_TEST(nrep_mode_sources_and_config)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, rec_publish, NULL };
    kelp_field_nrep_cfg cfg;
    kelp_field_nrep_cfg_default(&cfg, "bravo");
    snprintf(cfg.prefix, sizeof cfg.prefix, "GPS");
    snprintf(cfg.group, sizeof cfg.group, "red");
    snprintf(cfg.out_var, sizeof cfg.out_var, "MY_REPORT");
    kelp_field_nrep nr;
    ck_assert_int_eq(kelp_field_nrep_init(&nr, &cfg), 0);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "NAV_X", false, NULL, 1, &sink), 0); /* not our prefix */
    mail_d(&nr, "GPS_LAT", 43.8, &sink);
    mail_d(&nr, "GPS_LONG", -70.3, &sink);
    /* kelp's helm without modes: state@active behaviours */
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "IVPHELM_STATE", true, "DRIVE", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "IVPHELM_SUMMARY", true, "iter=1,active_bhvs=survey", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 10, &sink), 1);
    ck_assert_str_eq(r.var[0], "MY_REPORT");
    ck_assert_ptr_nonnull(strstr(r.val[0], "MODE=DRIVE@survey"));
    ck_assert_ptr_nonnull(strstr(r.val[0], "GROUP=red"));
    ck_assert_ptr_null(strstr(r.val[0], "X="));   /* no origin: no X/Y from LAT/LON */
    /* bad configuration */
    snprintf(cfg.name, sizeof cfg.name, "a,b");
    ck_assert_int_lt(kelp_field_nrep_init(&nr, &cfg), 0);
    kelp_field_nrep_cfg_default(&cfg, "");
    ck_assert_int_lt(kelp_field_nrep_init(&nr, &cfg), 0);
}
END_TEST

Suite *kelp_field_nodereporter_suite(void)
{
    Suite *s = suite_create("field_nodereporter");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, nrep_report_from_nav_and_helm);
    tcase_add_test(tc, nrep_mode_sources_and_config);
    suite_add_tcase(s, tc);
    return s;
}
