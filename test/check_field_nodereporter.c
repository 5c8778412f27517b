/* pNodeReporter's state machine (src/field/nodereporter.c) driven with a recording sink. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>

typedef struct rec {
    int n, warnings;
    char var[16][KELP_MAX_NAME];
    char val[16][KELP_NODEREPORT_MAX_LEN + 128];
} rec;

static void rec_publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    if (r->n < 16) {
        snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
        if (is_string) snprintf(r->val[r->n], sizeof r->val[0], "%s", sval);
        else snprintf(r->val[r->n], sizeof r->val[0], "%.17g", dval);
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

static kelp_field_sink g_sink;

static int find_var(const rec *r, const char *var)
{
    for (int i = r->n < 16 ? r->n : 16; i-- > 0;)
        if (!strcmp(r->var[i], var)) return i;
    return -1;
}

static void nav(kelp_field_nrep *nr, double x, double y, double spd, double hdg)
{
    mail_d(nr, "NAV_X", x, &g_sink);
    mail_d(nr, "NAV_Y", y, &g_sink);
    mail_d(nr, "NAV_SPEED", spd, &g_sink);
    mail_d(nr, "NAV_HEADING", hdg, &g_sink);
}

START_TEST(nrep_report_from_nav_and_helm)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, rec_publish, rec_warn };
    g_sink = sink;
    kelp_field_nrep_cfg cfg;
    kelp_field_nrep_cfg_default(&cfg, "alpha");
    cfg.length = 3.8;
    cfg.have_length = true;
    ck_assert_int_eq(kelp_geo_init(&cfg.geo, 43.825300, -70.330400), 0);
    cfg.have_geo = true;
    cfg.fill = KELP_NREP_FILL_EMPTY;
    kelp_field_nrep nr;
    ck_assert_int_eq(kelp_field_nrep_init(&nr, &cfg, 1252348070), 0);
    /* subscriptions: the NAV_* variables and the helm's */
    ck_assert_str_eq(kelp_field_nrep_subscription(&nr, 0), "NAV_X");
    ck_assert_str_eq(kelp_field_nrep_subscription(&nr, 3), "NAV_LONG");
    ck_assert_str_eq(kelp_field_nrep_subscription(&nr, 7), "NAV_YAW");
    ck_assert_str_eq(kelp_field_nrep_subscription(&nr, 8), "NAV_HEADING_OVER_GROUND");
    ck_assert_str_eq(kelp_field_nrep_subscription(&nr, 9), "IVPHELM_STATE");
    ck_assert_str_eq(kelp_field_nrep_subscription(&nr, 12), "NODE_COLOR_CHANGE");
    ck_assert_ptr_null(kelp_field_nrep_subscription(&nr, 13));
    /* nothing before a position, a speed and a heading */
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1252348071, &sink), 0);
    mail_d(&nr, "NAV_X", 51.71, &sink);
    mail_d(&nr, "NAV_Y", -35.5, &sink);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1252348072, &sink), 0);
    nav(&nr, 51.71, -35.5, 2, 118.85);
    mail_d(&nr, "NAV_DEPTH", 4.63, &sink);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "IVPHELM_STATE", true, "DRIVE", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "IVPHELM_SUMMARY", true, "iter=3,modes=MODE@ACTIVE:LOITERING", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "IVPHELM_ALLSTOP", true, "clear", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "OTHER", true, "x", 0, &sink), 0);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1252348077.59, &sink), 1);
    /* the first report goes to <OUT>_FIRST too, then PNR_POST_GAP */
    ck_assert_int_eq(r.n, 3);
    ck_assert_str_eq(r.var[0], "NODE_REPORT_LOCAL_FIRST");
    ck_assert_str_eq(r.var[1], "NODE_REPORT_LOCAL");
    ck_assert_str_eq(r.var[2], "PNR_POST_GAP");
    ck_assert_str_eq(r.val[0], r.val[1]);
    /* MOOS-IvP 24.8's layout (NodeRecord::getSpec): its order, DEP=, trailing zeros trimmed,
     * LAT/LON to 8 decimals (UTM, kelp/geo.h) */
    ck_assert_str_eq(r.val[1], "NAME=alpha,X=51.71,Y=-35.5,SPD=2,HDG=118.85,DEP=4.63,LAT=43.82498787,LON=-70.32974981,"
                               "TYPE=UUV,MODE=MODE@ACTIVE:LOITERING,ALLSTOP=clear,TIME=1252348077.59,LENGTH=3.8");
    /* reported every iteration (MOOS-IvP), fresh mail or not; INDEX counts the earlier ones */
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1252348078, &sink), 1);
    ck_assert_int_eq(r.n, 5);
    ck_assert_ptr_nonnull(strstr(r.val[3], ",INDEX=1"));
    ck_assert_str_eq(r.var[4], "PNR_POST_GAP");
    /* bad navigation is refused with a warning and loses nothing else */
    ck_assert_int_lt(kelp_field_nrep_mail(&nr, "NAV_X", true, "abc", 0, &sink), 0);
    ck_assert_int_lt(kelp_field_nrep_mail(&nr, "NAV_Y", false, NULL, INFINITY, &sink), 0);
    ck_assert_int_eq(r.warnings, 2);
    mail_d(&nr, "NAV_DEPTH", 5, &sink);
    mail_d(&nr, "NAV_YAW", 0.1, &sink);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1252348079, &sink), 1);
    kelp_nodereport back;
    ck_assert_int_eq(kelp_nodereport_parse(r.val[5], strlen(r.val[5]), &back, NULL), 0);
    ck_assert(fabs(back.x - 51.71) < 0.006 && back.depth == 5 && back.index == 2);
    /* YAW: the heading as radians counter-clockwise from east, 7 decimals (MOOS-IvP's rule) */
    ck_assert_msg(strstr(r.val[5], ",HDG=118.85,DEP=5,") != NULL, "%s", r.val[5]);
    ck_assert_msg(strstr(r.val[5], ",INDEX=2,YAW=-0.5035275,TIME=1252348079,") != NULL, "%s", r.val[5]);
    /* the helm goes quiet: NOHELM-<seconds> after the threshold (5 s) */
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1252348090, &sink), 1);
    ck_assert_ptr_nonnull(strstr(r.val[7], "MODE=NOHELM-12"));
}
END_TEST

START_TEST(nrep_mode_sources_and_config)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, rec_publish, NULL };
    g_sink = sink;
    kelp_field_nrep_cfg cfg;
    kelp_field_nrep_cfg_default(&cfg, "bravo");
    cfg.seed_format = true; /* the seed's layout, fixed decimals */
    snprintf(cfg.prefix, sizeof cfg.prefix, "GPS");
    snprintf(cfg.group, sizeof cfg.group, "red");
    snprintf(cfg.color, sizeof cfg.color, "green");
    snprintf(cfg.aspect, sizeof cfg.aspect, "ID=439,FUEL_TYPE=diesel");
    snprintf(cfg.out_var, sizeof cfg.out_var, "MY_REPORT");
    cfg.dep_key = true;
    cfg.allow_color_change = true;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_nrep_add_rider(&cfg, "var=DB_UPTIME, policy=updated, rfld=upt, prec=3", &why), 0);
    ck_assert_int_lt(kelp_field_nrep_add_rider(&cfg, "policy=always", &why), 0);
    ck_assert_int_lt(kelp_field_nrep_add_rider(&cfg, "var=X, policy=sometimes", &why), 0);
    kelp_field_nrep nr;
    ck_assert_int_eq(kelp_field_nrep_init(&nr, &cfg, 0), 0);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "NAV_X", false, NULL, 1, &sink), 0); /* not our prefix */
    mail_d(&nr, "GPS_LAT", 43.8, &sink);
    mail_d(&nr, "GPS_LONG", -70.3, &sink);
    mail_d(&nr, "GPS_SPEED", 1, &sink);
    mail_d(&nr, "GPS_HEADING", 90, &sink);
    /* never a helm: NOHELM-EVER */
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1, &sink), 1);
    ck_assert_str_eq(r.var[0], "MY_REPORT_FIRST");
    ck_assert_ptr_nonnull(strstr(r.val[1], "MODE=NOHELM-EVER"));
    ck_assert_ptr_nonnull(strstr(r.val[1], "ALLSTOP=unknown")); /* NodeReporter: until the helm says */
    ck_assert_ptr_nonnull(strstr(r.val[1], "TIME=1.00,COLOR=green,LAT="));
    ck_assert_ptr_nonnull(strstr(r.val[1], ",DEP=0.00,"));
    ck_assert_ptr_nonnull(strstr(r.val[1], "GROUP=red,ID=439,FUEL_TYPE=diesel"));
    ck_assert_ptr_null(strstr(r.val[1], "X="));   /* literal: no X/Y from LAT/LON */
    /* a helm in DRIVE without modes reports DRIVE; PARK as PARK; riders once per change */
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "IVPHELM_STATE", true, "DRIVE", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "DB_UPTIME", false, NULL, 12.34567, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "NODE_COLOR_CHANGE", true, "red", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 2, &sink), 1);
    int k = find_var(&r, "MY_REPORT");
    ck_assert_ptr_nonnull(strstr(r.val[k], "MODE=DRIVE,"));
    ck_assert_ptr_nonnull(strstr(r.val[k], "COLOR=red"));
    ck_assert_ptr_nonnull(strstr(r.val[k], ",upt=12.346"));
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "IVPHELM_STATE", true, "PARK", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 3, &sink), 1);
    k = find_var(&r, "MY_REPORT");
    ck_assert_ptr_nonnull(strstr(r.val[k], "MODE=PARK,"));
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "IVPHELM_STATE", true, "MALCONFIG", 0, &sink), 1);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 4, &sink), 1);
    ck_assert_ptr_nonnull(strstr(r.val[find_var(&r, "MY_REPORT")], "ALLSTOP=n/a"));
    ck_assert_ptr_null(strstr(r.val[k], "upt="));
    /* bad configuration */
    snprintf(cfg.name, sizeof cfg.name, "a,b");
    ck_assert_int_lt(kelp_field_nrep_init(&nr, &cfg, 0), 0);
    kelp_field_nrep_cfg_default(&cfg, "");
    ck_assert_int_lt(kelp_field_nrep_init(&nr, &cfg, 0), 0);
}
END_TEST

START_TEST(nrep_blackout_extrap_fill_json_platform)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, rec_publish, NULL };
    g_sink = sink;
    kelp_field_nrep_cfg cfg;
    kelp_field_nrep_cfg_default(&cfg, "charlie");
    cfg.blackout_interval = 2;
    kelp_field_nrep nr;
    ck_assert_int_eq(kelp_field_nrep_init(&nr, &cfg, 0), 0);
    nav(&nr, 0, 0, 1, 0);
    int posts = 0;
    for (int t = 1; t <= 10; t++) posts += kelp_field_nrep_iterate(&nr, t, &sink);
    ck_assert_int_eq(posts, 4); /* 1, 4, 7, 10: more than 2 s apart */

    /* extrapolation: a vehicle doing what it said is not reported again within max_gap */
    memset(&r, 0, sizeof r);
    kelp_field_nrep_cfg_default(&cfg, "delta");
    cfg.extrap = true;
    ck_assert_int_eq(kelp_field_nrep_init(&nr, &cfg, 0), 0);
    nav(&nr, 0, 0, 2, 90); /* east at 2 m/s */
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1, &sink), 1);
    nav(&nr, 2, 0, 2, 90);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 2, &sink), 0);
    nav(&nr, 4, 0, 2, 90);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 3, &sink), 0);
    nav(&nr, 6, 0, 2, 100); /* turned: reported */
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 4, &sink), 1);
    nav(&nr, 6, 5, 2, 100); /* off the line: reported */
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 5, &sink), 1);
    ck_assert_uint_eq(nr.extrap_skipped, 2);

    /* use-latest: the pair updated last fills the other; JSON to its own variable */
    memset(&r, 0, sizeof r);
    kelp_field_nrep_cfg_default(&cfg, "echo");
    cfg.seed_format = true;
    ck_assert_int_eq(kelp_geo_init(&cfg.geo, 43.825300, -70.330400), 0);
    cfg.have_geo = true;
    cfg.fill = KELP_NREP_FILL_LATEST;
    snprintf(cfg.json_var, sizeof cfg.json_var, "NODE_REPORT_JSON");
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_nrep_add_plat(&cfg, "COMPASS_HEADING, gap=5, alias=CH", &why), 0);
    ck_assert_int_lt(kelp_field_nrep_add_plat(&cfg, "COMPASS_HEADING", &why), 0);
    ck_assert_int_lt(kelp_field_nrep_add_plat(&cfg, "A, gap=x", &why), 0);
    ck_assert_int_eq(kelp_field_nrep_init(&nr, &cfg, 0), 0);
    nav(&nr, 100, 0, 1, 0);
    mail_d(&nr, "NAV_LAT", 43.8253, &g_sink);
    mail_d(&nr, "NAV_LONG", -70.3304, &g_sink); /* latest: the datum itself, so X/Y = 0,0 */
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "COMPASS_HEADING", false, NULL, 181, &g_sink), 1);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1, &sink), 1);
    int k = find_var(&r, "NODE_REPORT_LOCAL");
    ck_assert_ptr_nonnull(strstr(r.val[k], "X=0.00,Y=0.00,"));
    k = find_var(&r, "NODE_REPORT_JSON");
    ck_assert_int_ge(k, 0);
    ck_assert_ptr_nonnull(strstr(r.val[k], "{\"NAME\":\"echo\",\"TYPE\":\"UUV\",\"TIME\":1.00,\"X\":0.00,"));
    k = find_var(&r, "PLATFORM_REPORT_LOCAL");
    ck_assert_int_ge(k, 0);
    ck_assert_str_eq(r.val[k], "platform=echo,utc_time=1.00,CH=181");
    mail_d(&nr, "NAV_X", 100, &g_sink);
    ck_assert_int_eq(kelp_field_nrep_mail(&nr, "COMPASS_HEADING", false, NULL, 182, &g_sink), 1);
    memset(&r, 0, sizeof r);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 2, &sink), 1);
    k = find_var(&r, "NODE_REPORT_LOCAL");
    ck_assert_ptr_nonnull(strstr(r.val[k], "X=100.00,Y=0.00,"));
    ck_assert_int_lt(find_var(&r, "PLATFORM_REPORT_LOCAL"), 0); /* gap 5 s */
    /* an alternate solution (ground truth) reported under NAME_GT and its own group; COG */
    memset(&r, 0, sizeof r);
    kelp_field_nrep_cfg_default(&cfg, "fox");
    cfg.seed_format = true;
    snprintf(cfg.alt_prefix, sizeof cfg.alt_prefix, "NAV_GT");
    snprintf(cfg.alt_group, sizeof cfg.alt_group, "blue");
    cfg.report_cog = true;
    ck_assert_int_eq(kelp_field_nrep_init(&nr, &cfg, 0), 0);
    ck_assert_str_eq(kelp_field_nrep_subscription(&nr, 9), "NAV_GT_X");
    nav(&nr, 1, 2, 1, 10);
    mail_d(&nr, "NAV_HEADING_OVER_GROUND", 12.5, &g_sink);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 1, &sink), 1);
    ck_assert_int_eq(r.n, 3); /* _FIRST, report, gap: no ground truth yet */
    ck_assert_ptr_nonnull(strstr(r.val[1], ",COG=12.50"));
    mail_d(&nr, "NAV_GT_X", 1.5, &g_sink);
    mail_d(&nr, "NAV_GT_Y", 2.5, &g_sink);
    mail_d(&nr, "NAV_GT_SPEED", 1, &g_sink);
    mail_d(&nr, "NAV_GT_HEADING", 11, &g_sink);
    memset(&r, 0, sizeof r);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 2, &sink), 1);
    ck_assert_int_eq(r.n, 3);
    ck_assert_ptr_nonnull(strstr(r.val[0], "NAME=fox,"));
    ck_assert_str_eq(r.var[2], "NODE_REPORT_LOCAL");
    ck_assert_ptr_nonnull(strstr(r.val[2], "NAME=fox_GT,TYPE=UUV,TIME=2.00,X=1.50,Y=2.50,"));
    ck_assert_ptr_nonnull(strstr(r.val[2], "GROUP=blue"));
    memset(&r, 0, sizeof r);
    ck_assert_int_eq(kelp_field_nrep_iterate(&nr, 8, &sink), 1); /* ground truth silent for 6 s */
    ck_assert_int_eq(r.n, 2);
    kelp_nrep_fill f;
    ck_assert_int_eq(kelp_field_nrep_parse_fill("fill_empty", &f), 0);
    ck_assert_int_eq(f, KELP_NREP_FILL_EMPTY);
    ck_assert_int_lt(kelp_field_nrep_parse_fill("sometimes", &f), 0);
}
END_TEST

Suite *kelp_field_nodereporter_suite(void)
{
    Suite *s = suite_create("field_nodereporter");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, nrep_report_from_nav_and_helm);
    tcase_add_test(tc, nrep_mode_sources_and_config);
    tcase_add_test(tc, nrep_blackout_extrap_fill_json_platform);
    suite_add_tcase(s, tc);
    return s;
}
