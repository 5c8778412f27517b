/* uFldPathCheck's state machine (src/field/pathcheck.c): MOOS-IvP 24.8's rules
 * (ivp/src/uFldPathCheck/PathCheck_MOOSApp.cpp). */
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

static char last_warn[256];

static void wrn(void *ctx, const char *msg)
{
    snprintf(last_warn, sizeof last_warn, "%s", msg);
    ((rec *)ctx)->warns++;
}

/* how many posts of var */
static int count(const rec *r, const char *var)
{
    int k = 0;
    for (int i = 0; i < r->n; i++) k += !strcmp(r->var[i], var);
    return k;
}

/* the last post of var whose value starts with prefix */
static const char *get(const rec *r, const char *var, const char *prefix)
{
    for (int i = r->n; i-- > 0;)
        if (!strcmp(r->var[i], var) && !strncmp(r->val[i], prefix, strlen(prefix))) return r->val[i];
    return NULL;
}

static kelp_pathcheck P;

/* a recording sink s over r, and the tool started with history h */
#define FIXTURE(h)                                                                                                     \
    rec r = { 0 };                                                                                                     \
    kelp_field_sink s = { &r, pub, wrn };                                                                              \
    setup(h)

static void setup(unsigned history)
{
    kelp_pathcheck_cfg c;
    kelp_pathcheck_cfg_default(&c);
    c.history = history;
    ck_assert_int_eq(kelp_pathcheck_init(&P, &c), 0);
}

static void report(const char *name, double x, double y, double t, const kelp_field_sink *s)
{
    char buf[128];
    snprintf(buf, sizeof buf, "NAME=%s,TYPE=UUV,TIME=%.2f,X=%.2f,Y=%.2f,SPD=9,HDG=0", name, t, x, y);
    ck_assert_int_eq(kelp_pathcheck_mail(&P, "NODE_REPORT", true, buf, t, s), 1);
}

/* 24.8's odometer runs once two records are held: the leg from the first report to the
 * second is never counted; avg_spd is the mean of the leg speeds */
START_TEST(upc_first_leg_not_counted)
{
    FIXTURE(10);
    report("alpha", 0, 0, 0, &s);
    report("alpha", 3, 4, 1, &s);
    (void)kelp_pathcheck_iterate(&P, 1, &s);
    ck_assert_int_eq(count(&r, "UPC_ODOMETRY_REPORT"), 0);
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=alpha"), "vname=alpha,avg_spd=5.00");
    report("alpha", 6, 8, 2, &s);
    (void)kelp_pathcheck_iterate(&P, 2, &s);
    ck_assert_str_eq(get(&r, "UPC_ODOMETRY_REPORT", "vname=alpha"), "vname=alpha,total_dist=5.0,trip_dist=5.0");
}
END_TEST

/* UPC_SPEED_REPORT every iteration for every vehicle with two records, changed or not; a
 * vehicle with one record gets none; odometry only after a change */
START_TEST(upc_speed_every_iteration)
{
    FIXTURE(10);
    report("bravo", 5, 5, 100, &s);
    ck_assert_uint_eq(kelp_pathcheck_iterate(&P, 100, &s), 0);
    report("bravo", 5, 7, 101, &s);
    report("bravo", 5, 9, 102, &s);
    ck_assert_uint_eq(kelp_pathcheck_iterate(&P, 102, &s), 2);
    ck_assert_uint_eq(kelp_pathcheck_iterate(&P, 102.25, &s), 1);
    ck_assert_uint_eq(kelp_pathcheck_iterate(&P, 102.5, &s), 1);
    ck_assert_int_eq(count(&r, "UPC_SPEED_REPORT"), 3);
    ck_assert_int_eq(count(&r, "UPC_ODOMETRY_REPORT"), 1);
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=bravo"), "vname=bravo,avg_spd=2.00");
}
END_TEST

/* the speed is the mean of the per-leg speeds, not the path over the time span */
START_TEST(upc_mean_of_leg_speeds)
{
    FIXTURE(10);
    report("alpha", 0, 0, 0, &s);
    report("alpha", 10, 0, 1, &s); /* 10 m/s */
    report("alpha", 10, 2, 3, &s); /* 1 m/s */
    (void)kelp_pathcheck_iterate(&P, 3, &s);
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=alpha"), "vname=alpha,avg_spd=5.50");
    /* history_length 2: only the last leg */
    setup(2);
    report("alpha", 0, 0, 0, &s);
    report("alpha", 10, 0, 1, &s);
    report("alpha", 10, 1, 2, &s);
    (void)kelp_pathcheck_iterate(&P, 2, &s);
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=alpha"), "vname=alpha,avg_spd=1.00");
}
END_TEST

/* a report's TIME is data: an old or repeated TIME is still a record; a leg with no positive
 * time difference is left out of the mean (24.8 divides by zero) */
START_TEST(upc_zero_time_leg_finite)
{
    FIXTURE(10);
    report("alpha", 0, 0, 0, &s);
    report("alpha", 3, 4, 1, &s);
    report("alpha", 6, 8, 1, &s); /* same TIME: counted by the odometer, not by the speed */
    (void)kelp_pathcheck_iterate(&P, 1, &s);
    ck_assert_str_eq(get(&r, "UPC_ODOMETRY_REPORT", "vname=alpha"), "vname=alpha,total_dist=5.0,trip_dist=5.0");
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=alpha"), "vname=alpha,avg_spd=5.00");
    ck_assert_int_eq(P.node[0].reports, 3);
}
END_TEST

START_TEST(upc_trip_reset)
{
    FIXTURE(10);
    report("alpha", 0, 0, 0, &s);
    report("alpha", 3, 4, 1, &s);
    /* two records, no leg counted yet: 24.8 has no trip for alpha */
    ck_assert_int_lt(kelp_pathcheck_mail(&P, "UPC_TRIP_RESET", true, "alpha", 1.5, &s), 0);
    ck_assert_str_eq(last_warn, "Invalid TRIP_RESET: alpha");
    report("alpha", 6, 8, 2, &s);
    report("alpha", 9, 12, 3, &s);
    (void)kelp_pathcheck_iterate(&P, 3, &s);
    ck_assert_int_eq(kelp_pathcheck_mail(&P, "UPC_TRIP_RESET", true, "alpha", 3.5, &s), 1);
    /* a reset alone posts nothing */
    int before = count(&r, "UPC_ODOMETRY_REPORT");
    (void)kelp_pathcheck_iterate(&P, 3.5, &s);
    ck_assert_int_eq(count(&r, "UPC_ODOMETRY_REPORT"), before);
    report("alpha", 9, 22, 4, &s);
    (void)kelp_pathcheck_iterate(&P, 4, &s);
    ck_assert_str_eq(get(&r, "UPC_ODOMETRY_REPORT", "vname=alpha"), "vname=alpha,total_dist=20.0,trip_dist=10.0");
    /* the name exactly: another case is another vehicle; unknown: a warning */
    ck_assert_int_lt(kelp_pathcheck_mail(&P, "UPC_TRIP_RESET", true, "ALPHA", 5, &s), 0);
    ck_assert_int_lt(kelp_pathcheck_mail(&P, "UPC_TRIP_RESET", true, "nobody", 5, &s), 0);
    ck_assert_str_eq(last_warn, "Invalid TRIP_RESET: nobody");
    /* the seed's synonym is not a 24.8 variable */
    ck_assert_int_eq(kelp_pathcheck_mail(&P, "UPC_ODOMETRY_RESET", true, "alpha", 5, &s), 0);
    ck_assert_ptr_null(kelp_pathcheck_subscription(3));
}
END_TEST

/* vehicles in strcmp order (24.8's std::map): all speeds first, then the odometry */
START_TEST(upc_vehicle_order)
{
    FIXTURE(10);
    for (int k = 0; k < 3; k++) {
        report("charlie", 0, k, k, &s);
        report("Bravo", 100, 100 + 3 * k, k, &s);
        report("alpha", 0, 2 * k, k, &s);
    }
    ck_assert_uint_eq(kelp_pathcheck_iterate(&P, 2, &s), 6);
    ck_assert_str_eq(r.val[0], "vname=Bravo,avg_spd=3.00");
    ck_assert_str_eq(r.val[1], "vname=alpha,avg_spd=2.00");
    ck_assert_str_eq(r.val[2], "vname=charlie,avg_spd=1.00");
    ck_assert_str_eq(r.val[3], "vname=Bravo,total_dist=3.0,trip_dist=3.0");
    ck_assert_str_eq(r.val[5], "vname=charlie,total_dist=1.0,trip_dist=1.0");
}
END_TEST

START_TEST(upc_bad_mail)
{
    FIXTURE(10);
    /* no TIME: the arrival time stands in (24.8: 0, and a division by zero) */
    ck_assert_int_eq(kelp_pathcheck_mail(&P, "NODE_REPORT_LOCAL", true, "NAME=c,X=0,Y=0,SPD=1,HDG=0", 10, &s), 1);
    ck_assert_int_eq(kelp_pathcheck_mail(&P, "NODE_REPORT_LOCAL", true, "NAME=c,X=8,Y=6,SPD=1,HDG=0", 12, &s), 1);
    ck_assert_int_lt(kelp_pathcheck_mail(&P, "NODE_REPORT", true, "NAME=bad,Y=5,SPD=1,HDG=0,TIME=3", 13, &s), 0);
    ck_assert_str_eq(last_warn, "Invalid NODE_REPORT: NAME=bad,Y=5,SPD=1,HDG=0,TIME=3");
    /* NodeRecord::valid() wants SPD and HDG too */
    ck_assert_int_lt(kelp_pathcheck_mail(&P, "NODE_REPORT", true, "NAME=c,X=1,Y=1,TIME=13", 13, &s), 0);
    ck_assert_int_eq(r.warns, 2);
    ck_assert_int_eq(kelp_pathcheck_mail(&P, "OTHER", true, "x", 13, &s), 0);
    (void)kelp_pathcheck_iterate(&P, 13, &s);
    ck_assert_str_eq(get(&r, "UPC_SPEED_REPORT", "vname=c"), "vname=c,avg_spd=5.00");
}
END_TEST

/* the AppCast: counts, time warp, and the table of the vehicles with odometry */
START_TEST(upc_report_table)
{
    FIXTURE(10);
    for (int k = 0; k < 3; k++) report("v1", 0, 10 * k, k, &s);
    report("v22", 0, 0, 0, &s);
    ck_assert_int_lt(kelp_pathcheck_mail(&P, "NODE_REPORT", true, "NAME=x,Y=1", 2, &s), 0);
    char buf[1024];
    ck_assert_int_eq(kelp_pathcheck_report(&P, 4.5, 1, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, " Node Reports Recd (good): 4\n"
                          " Node Reports Recd (bad):  1\n"
                          " MOOS Time Warp:           1\n"
                          "\n"
                          "Node   TripDist   Distance   ReportAge   Speed   AvgSpeed\n"
                          "----   --------   --------   ---------   -----   --------\n"
                          "v1     10.0       10.0       2.5         n/a     n/a\n");
}
END_TEST

START_TEST(upc_config)
{
    kelp_pathcheck_cfg c;
    kelp_diag why = { 0 };
    kelp_pathcheck_cfg_default(&c);
    ck_assert_uint_eq(c.history, 10);
    ck_assert_int_eq(kelp_pathcheck_config(&c, "history_length", "25", &why), 1);
    ck_assert_uint_eq(c.history, 25);
    /* 24.8 reads HISTORY_LENGTH only: "history" is an unhandled line */
    ck_assert_int_eq(kelp_pathcheck_config(&c, "HISTORY", "10", &why), 0);
    ck_assert_uint_eq(c.history, 25);
    ck_assert_int_lt(kelp_pathcheck_config(&c, "HISTORY_LENGTH", "1", &why), 0);
    ck_assert_int_lt(kelp_pathcheck_config(&c, "HISTORY_LENGTH", "x", &why), 0);
    ck_assert_int_eq(kelp_pathcheck_config(&c, "FOO", "1", &why), 0);
}
END_TEST

Suite *kelp_field_pathcheck_suite(void);
Suite *kelp_field_pathcheck_suite(void)
{
    Suite *s = suite_create("field_pathcheck");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, upc_first_leg_not_counted);
    tcase_add_test(tc, upc_speed_every_iteration);
    tcase_add_test(tc, upc_mean_of_leg_speeds);
    tcase_add_test(tc, upc_zero_time_leg_finite);
    tcase_add_test(tc, upc_trip_reset);
    tcase_add_test(tc, upc_vehicle_order);
    tcase_add_test(tc, upc_bad_mail);
    tcase_add_test(tc, upc_report_table);
    tcase_add_test(tc, upc_config);
    suite_add_tcase(s, tc);
    return s;
}
