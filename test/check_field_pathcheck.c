/* uFldPathCheck's state machine (src/field/pathcheck.c): ufield.md 8.6 and the rules of 8.4. */
#include <check.h>
#include <stdio.h>
#include <string.h>
#include <kelp/pathcheck.h>

typedef struct rec {
    int n, warns;
    char var[64][32];
    char val[64][160];
} rec;

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    (void)dval;
    if (r->n >= 64 || !is_string) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    snprintf(r->val[r->n], sizeof r->val[0], "%s", sval);
    r->n++;
}

static void wrn(void *ctx, const char *msg)
{
    (void)msg;
    ((rec *)ctx)->warns++;
}

/* the last post of var whose value starts with prefix */
static const char *get(const rec *r, const char *var, const char *prefix)
{
    for (int i = r->n; i-- > 0;)
        if (!strcmp(r->var[i], var) && !strncmp(r->val[i], prefix, strlen(prefix))) return r->val[i];
    return NULL;
}

static kelp_field_upc P;

static void setup(unsigned history)
{
    kelp_field_upc_cfg c;
    kelp_field_upc_cfg_default(&c);
    c.history = history;
    ck_assert_int_eq(kelp_field_upc_init(&P, &c), 0);
}

static void report(const char *name, double x, double y, double t, const kelp_field_sink *s)
{
    char buf[128];
    snprintf(buf, sizeof buf, "NAME=%s,TYPE=UUV,TIME=%.2f,X=%.2f,Y=%.2f,SPD=9,HDG=0", name, t, x, y);
    ck_assert_int_eq(kelp_field_upc_mail(&P, "NODE_REPORT", true, buf, t, s), 1);
}

START_TEST(upc_three_reports)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    setup(10);
    report("alpha", 0, 0, 0, &s);
    report("alpha", 3, 4, 1, &s);
    report("alpha", 6, 8, 2, &s);
    ck_assert_uint_eq(kelp_field_upc_iterate(&P, 2, &s), 2);
    ck_assert_str_eq(get(&r, "UPC_ODOMETRY_REPORT", "vname=alpha"), "vname=alpha,total_dist=10.0,trip_dist=10.0");
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=alpha"), "vname=alpha,avg_speed=5.00");
    /* nothing new: nothing posted */
    ck_assert_uint_eq(kelp_field_upc_iterate(&P, 3, &s), 0);
}
END_TEST

START_TEST(upc_single_report)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    setup(10);
    report("bravo", 5, 5, 100, &s);
    ck_assert_uint_eq(kelp_field_upc_iterate(&P, 100, &s), 2);
    ck_assert_str_eq(get(&r, "UPC_ODOMETRY_REPORT", "vname=bravo"), "vname=bravo,total_dist=0.0,trip_dist=0.0");
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=bravo"), "vname=bravo,avg_speed=0.00");
}
END_TEST

START_TEST(upc_trip_reset)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    setup(10);
    report("alpha", 0, 0, 0, &s);
    report("alpha", 3, 4, 1, &s);
    report("alpha", 6, 8, 2, &s);
    (void)kelp_field_upc_iterate(&P, 2, &s);
    ck_assert_int_eq(kelp_field_upc_mail(&P, "UPC_TRIP_RESET", true, "alpha", 2.5, &s), 1);
    report("alpha", 6, 18, 3, &s);
    (void)kelp_field_upc_iterate(&P, 3, &s);
    ck_assert_str_eq(get(&r, "UPC_ODOMETRY_REPORT", "vname=alpha"), "vname=alpha,total_dist=20.0,trip_dist=10.0");
    /* the 24.8/seed-8.2 synonym and the vname= form, case-insensitively */
    ck_assert_int_eq(kelp_field_upc_mail(&P, "UPC_ODOMETRY_RESET", true, "vname=ALPHA", 4, &s), 1);
    (void)kelp_field_upc_iterate(&P, 4, &s);
    ck_assert_str_eq(get(&r, "UPC_ODOMETRY_REPORT", "vname=alpha"), "vname=alpha,total_dist=20.0,trip_dist=0.0");
    /* unknown vehicle: a warning, nothing else */
    int w = r.warns;
    ck_assert_int_lt(kelp_field_upc_mail(&P, "UPC_TRIP_RESET", true, "zulu", 5, &s), 0);
    ck_assert_int_eq(r.warns, w + 1);
}
END_TEST

START_TEST(upc_history_window)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    setup(2);
    report("alpha", 0, 0, 0, &s);
    report("alpha", 10, 0, 1, &s);
    report("alpha", 10, 1, 2, &s);
    (void)kelp_field_upc_iterate(&P, 2, &s);
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=alpha"), "vname=alpha,avg_speed=1.00");
    /* with the default history the same reports average over the whole path: 11 m / 2 s */
    setup(10);
    report("alpha", 0, 0, 0, &s);
    report("alpha", 10, 0, 1, &s);
    report("alpha", 10, 1, 2, &s);
    (void)kelp_field_upc_iterate(&P, 2, &s);
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=alpha"), "vname=alpha,avg_speed=5.50");
}
END_TEST

START_TEST(upc_independent_vehicles)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    setup(10);
    report("alpha", 0, 0, 0, &s);
    report("bravo", 100, 100, 0, &s);
    report("alpha", 0, 2, 1, &s);
    report("bravo", 100, 130, 1, &s);
    ck_assert_uint_eq(kelp_field_upc_iterate(&P, 1, &s), 4);
    ck_assert_str_eq(get(&r, "UPC_ODOMETRY_REPORT", "vname=alpha"), "vname=alpha,total_dist=2.0,trip_dist=2.0");
    ck_assert_str_eq(get(&r, "UPC_ODOMETRY_REPORT", "vname=bravo"), "vname=bravo,total_dist=30.0,trip_dist=30.0");
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=alpha"), "vname=alpha,avg_speed=2.00");
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=bravo"), "vname=bravo,avg_speed=30.00");
    /* only bravo updated: only bravo posted */
    r.n = 0;
    report("bravo", 100, 131, 2, &s);
    ck_assert_uint_eq(kelp_field_upc_iterate(&P, 2, &s), 2);
    ck_assert_ptr_null(get(&r, "UPC_ODOMETRY_REPORT", "vname=alpha"));
    ck_assert_ptr_nonnull(get(&r, "UPC_ODOMETRY_REPORT", "vname=bravo"));
}
END_TEST

START_TEST(upc_same_time_ignored)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    setup(10);
    report("alpha", 0, 0, 0, &s);
    report("alpha", 3, 4, 1, &s);
    report("alpha", 30, 40, 1, &s); /* same TIME: ignored */
    report("alpha", 30, 40, 0.5, &s); /* older: ignored */
    (void)kelp_field_upc_iterate(&P, 1, &s);
    ck_assert_str_eq(get(&r, "UPC_ODOMETRY_REPORT", "vname=alpha"), "vname=alpha,total_dist=5.0,trip_dist=5.0");
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=alpha"), "vname=alpha,avg_speed=5.00");
}
END_TEST

START_TEST(upc_receive_time_and_bad_mail)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    setup(10);
    /* no TIME: the arrival time stands in */
    ck_assert_int_eq(kelp_field_upc_mail(&P, "NODE_REPORT_LOCAL", true, "NAME=c,X=0,Y=0", 10, &s), 1);
    ck_assert_int_eq(kelp_field_upc_mail(&P, "NODE_REPORT_LOCAL", true, "NAME=c,X=8,Y=6", 12, &s), 1);
    ck_assert_int_lt(kelp_field_upc_mail(&P, "NODE_REPORT", true, "NAME=c,X=junk,Y=1", 13, &s), 0);
    ck_assert_int_lt(kelp_field_upc_mail(&P, "NODE_REPORT", true, "X=1,Y=1", 13, &s), 0);
    ck_assert_int_eq(r.warns, 2);
    ck_assert_int_eq(kelp_field_upc_mail(&P, "OTHER", true, "x", 13, &s), 0);
    (void)kelp_field_upc_iterate(&P, 13, &s);
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=c"), "vname=c,avg_speed=5.00");
    char buf[1024];
    ck_assert_int_eq(kelp_field_upc_report(&P, 13, buf, sizeof buf), 0);
    ck_assert_ptr_nonnull(strstr(buf, "Node Reports Recd (bad):  2"));
}
END_TEST

START_TEST(upc_config)
{
    kelp_field_upc_cfg c;
    kelp_diag why = { 0 };
    kelp_field_upc_cfg_default(&c);
    ck_assert_uint_eq(c.history, 10);
    ck_assert_int_eq(kelp_field_upc_config(&c, "history_length", "25", &why), 1);
    ck_assert_uint_eq(c.history, 25);
    ck_assert_int_eq(kelp_field_upc_config(&c, "HISTORY", "10 (Default)", &why), 1);
    ck_assert_uint_eq(c.history, 10);
    ck_assert_int_lt(kelp_field_upc_config(&c, "HISTORY", "1", &why), 0);
    ck_assert_int_lt(kelp_field_upc_config(&c, "HISTORY", "x", &why), 0);
    ck_assert_int_eq(kelp_field_upc_config(&c, "FOO", "1", &why), 0);
}
END_TEST

Suite *kelp_field_pathcheck_suite(void);
Suite *kelp_field_pathcheck_suite(void)
{
    Suite *s = suite_create("field_pathcheck");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, upc_three_reports);
    tcase_add_test(tc, upc_single_report);
    tcase_add_test(tc, upc_trip_reset);
    tcase_add_test(tc, upc_history_window);
    tcase_add_test(tc, upc_independent_vehicles);
    tcase_add_test(tc, upc_same_time_ignored);
    tcase_add_test(tc, upc_receive_time_and_bad_mail);
    tcase_add_test(tc, upc_config);
    suite_add_tcase(s, tc);
    return s;
}
