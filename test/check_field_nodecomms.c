/* uFldNodeComms's state machine (src/field/nodecomms.c): ufield.md 5.6, every routing rule
 * of 5.4, and MOOS-IvP 24.8's additions. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/field.h>

#define REC_MAX 4096

typedef struct rec {
    int n, warns;
    char var[REC_MAX][48];
    char val[REC_MAX][256];
} rec;

static rec *R;
static kelp_field_ncomms *C;
static kelp_field_sink S;

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    if (r->n >= REC_MAX) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    if (is_string) snprintf(r->val[r->n], sizeof r->val[0], "%s", sval);
    else snprintf(r->val[r->n], sizeof r->val[0], "%g", dval);
    r->n++;
}

static void warn(void *ctx, const char *msg)
{
    (void)msg;
    ((rec *)ctx)->warns++;
}

static int count(const char *var)
{
    int k = 0;
    for (int i = 0; i < R->n; i++) k += strcmp(R->var[i], var) == 0;
    return k;
}

static const char *last(const char *var)
{
    for (int i = R->n; i-- > 0;)
        if (!strcmp(R->var[i], var)) return R->val[i];
    return NULL;
}

/* number of posts of var whose value contains s */
static int count_with(const char *var, const char *s)
{
    int k = 0;
    for (int i = 0; i < R->n; i++) k += strcmp(R->var[i], var) == 0 && strstr(R->val[i], s) != NULL;
    return k;
}

static void setup(void)
{
    R = calloc(1, sizeof *R);
    C = malloc(sizeof *C);
    S = (kelp_field_sink){ R, pub, warn };
}

static void teardown(void)
{
    free(R);
    free(C);
}

static void start(const kelp_field_ncomms_cfg *cfg)
{
    kelp_field_ncomms_cfg d;
    if (!cfg) {
        kelp_field_ncomms_cfg_default(&d);
        cfg = &d;
    }
    ck_assert_int_eq(kelp_field_ncomms_init(C, cfg), 0);
}

static void cfgset(kelp_field_ncomms_cfg *cfg, const char *k, const char *v)
{
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_ncomms_config(cfg, k, v, &why), 1);
}

static int mail(const char *var, const char *val, double now)
{
    return kelp_field_ncomms_mail(C, var, true, val, 0, now, &S);
}

static void rpt(const char *name, double x, double y, const char *group, double now)
{
    char b[256];
    snprintf(b, sizeof b, "NAME=%s,TYPE=UUV,TIME=%.2f,X=%.2f,Y=%.2f,SPD=1.00,HDG=90.00,DEPTH=0.00%s%s", name, now, x, y,
             group ? ",GROUP=" : "", group ? group : "");
    ck_assert_int_eq(mail("NODE_REPORT", b, now), 1);
}

static void iter(double now)
{
    (void)kelp_field_ncomms_iterate(C, now, &S);
}

static void two(double d, const char *ga, const char *gb)
{
    rpt("alpha", 0, 0, ga, 1000);
    rpt("bravo", d, 0, gb, 1000);
    R->n = 0;
    iter(1000);
}

/* 5.6.1 */
START_TEST(nc_in_range_relayed)
{
    start(NULL);
    two(90, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 1);
    ck_assert_ptr_nonnull(strstr(last("NODE_REPORT_BRAVO"), "NAME=alpha,"));
    ck_assert_ptr_nonnull(strstr(last("NODE_REPORT_ALPHA"), "NAME=bravo,"));
    ck_assert_int_eq(count("VIEW_COMMS_PULSE"), 2);
}
END_TEST

/* 5.6.2 (and out of range) */
START_TEST(nc_exact_range_not)
{
    start(NULL);
    two(100, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 0);
    two(250, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 0);
    two(99.99, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 2);
}
END_TEST

/* 5.6.3 */
START_TEST(nc_stealth_shrinks)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "STEALTH", "vname=alpha, stealth=0.5");
    start(&cfg);
    two(60, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 1);
}
END_TEST

/* 5.6.4: the critical range overrides stealth */
START_TEST(nc_critical_overrides_stealth)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "stealth", "vname=alpha, stealth=0.5");
    start(&cfg);
    two(25, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
    two(55, NULL, NULL); /* 55 >= max(50, 30) */
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 1);
}
END_TEST

/* 5.6.5 */
START_TEST(nc_earange_grows)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "EARANGE", "vname=bravo, earange=2");
    start(&cfg);
    two(150, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 0);
    two(200, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
}
END_TEST

/* 5.6.6 */
START_TEST(nc_factors_cancel)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "STEALTH", "vname=alpha, stealth=0.5");
    cfgset(&cfg, "EARANGE", "vname=bravo, earange=2");
    start(&cfg);
    two(99, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
    two(101, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
}
END_TEST

/* 5.6.7 */
START_TEST(nc_groups)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "GROUPS", "true");
    start(&cfg);
    two(50, "red", "blue");
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 0);
    two(25, "red", "blue");
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 1);
    two(50, "red", "RED"); /* same group, case-insensitive */
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 2);
}
END_TEST

/* 5.6.8: a stale receiver gets neither reports (even inside the critical range) nor messages */
START_TEST(nc_stale_receiver)
{
    start(NULL);
    rpt("bravo", 20, 0, NULL, 994);
    rpt("alpha", 0, 0, NULL, 1000);
    mail("NODE_MESSAGE", "src_node=alpha,dest_node=bravo,var_name=FOOBAR,string_val=hello", 1000);
    R->n = 0;
    iter(1000);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 0);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_STALE], 1);
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 1); /* alpha is fresh and gets bravo's (updated) report */
}
END_TEST

/* 5.6.9 */
START_TEST(nc_not_updated)
{
    start(NULL);
    two(50, NULL, NULL);
    rpt("bravo", 50, 0, NULL, 1001);
    R->n = 0;
    iter(1001);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0); /* alpha's report did not change */
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 1);
    R->n = 0;
    iter(1001.25);
    ck_assert_int_eq(R->n, 0);
}
END_TEST

/* 5.6.10 */
START_TEST(nc_unc_stealth)
{
    start(NULL);
    ck_assert_int_eq(mail("UNC_STEALTH", "vname=alpha, stealth=0.75", 1000), 1);
    two(70, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
    two(80, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 1);
    ck_assert_int_eq(mail("UNC_EARANGE", "vname=bravo, earange=1.5", 1000), 1);
    two(110, NULL, NULL); /* 100 * 0.75 * 1.5 = 112.5 */
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
    ck_assert_int_lt(mail("UNC_STEALTH", "vname=alpha", 1000), 0);
    ck_assert_int_lt(mail("UNC_EARANGE", "earange=2", 1000), 0);
    ck_assert_int_eq(R->warns, 2);
    ck_assert_double_eq_tol(C->node[kelp_field_ncomms_find(C, "ALPHA")].stealth, 0.75, 1e-12);
}
END_TEST

static const char *HELLO = "src_node=alpha,dest_node=bravo,var_name=FOOBAR,string_val=hello";

/* 5.6.11 */
START_TEST(nc_message_delivered)
{
    start(NULL);
    rpt("alpha", 0, 0, NULL, 1000);
    rpt("bravo", 50, 0, NULL, 1000);
    iter(1000);
    ck_assert_int_eq(mail("NODE_MESSAGE", HELLO, 1000.5), 1);
    R->n = 0;
    iter(1000.5);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 1);
    ck_assert_str_eq(last("NODE_MESSAGE_BRAVO"), HELLO);
    const char *p = last("VIEW_COMMS_PULSE");
    ck_assert_ptr_nonnull(p);
    ck_assert_ptr_nonnull(strstr(p, "label=ALPHA2BRAVO_MSG,edge_color=white,fill_color=white"));
    ck_assert_uint_eq(C->msgs_sent, 1);
}
END_TEST

/* 5.6.12 */
START_TEST(nc_msg_too_long)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "MAX_MSG_LENGTH", "4");
    start(&cfg);
    two(50, NULL, NULL);
    mail("NODE_MESSAGE", HELLO, 1000);
    mail("NODE_MESSAGE", "src_node=alpha,dest_node=bravo,var_name=X,double_val=123456.5", 1000);
    R->n = 0;
    iter(1000);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_LONG], 1);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 1); /* a double_val has length 0 */
    ck_assert_ptr_nonnull(strstr(last("NODE_MESSAGE_BRAVO"), "double_val"));
}
END_TEST

/* 5.6.13 */
START_TEST(nc_min_msg_interval)
{
    start(NULL);
    double t0 = 1000;
    for (double t = t0; t <= t0 + 31; t += 1) {
        rpt("alpha", 0, 0, NULL, t);
        rpt("bravo", 50, 0, NULL, t);
        if (t == t0 || t == t0 + 10 || t == t0 + 31) mail("NODE_MESSAGE", HELLO, t);
        iter(t);
    }
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 2);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_RECENT], 1);
}
END_TEST

/* the interval starts at a successful send: a blocked message does not start it */
START_TEST(nc_interval_starts_at_success)
{
    start(NULL);
    rpt("alpha", 0, 0, NULL, 1000);
    rpt("bravo", 500, 0, NULL, 1000);
    mail("NODE_MESSAGE", HELLO, 1000);
    iter(1000);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_FAR], 1);
    rpt("alpha", 0, 0, NULL, 1001);
    rpt("bravo", 50, 0, NULL, 1001);
    mail("NODE_MESSAGE", HELLO, 1001);
    R->n = 0;
    iter(1001);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 1);
}
END_TEST

/* 5.6.14 */
START_TEST(nc_msg_no_critical_range)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "STEALTH", "vname=alpha, stealth=0.2");
    start(&cfg);
    two(25, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1); /* reports: critical range */
    mail("NODE_MESSAGE", HELLO, 1000);
    R->n = 0;
    iter(1000);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 0);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_FAR], 1);
}
END_TEST

/* 5.6.15 */
START_TEST(nc_groups_not_for_messages)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "GROUPS", "true");
    start(&cfg);
    two(50, "red", "blue");
    mail("NODE_MESSAGE", HELLO, 1000);
    R->n = 0;
    iter(1000);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 1);
}
END_TEST

/* 24.8 msg_groups: messages only within a group */
START_TEST(nc_msg_groups)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "msg_groups", "true");
    start(&cfg);
    two(50, "red", "blue");
    mail("NODE_MESSAGE", HELLO, 1000);
    R->n = 0;
    iter(1000);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 0);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_GROUP], 1);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0); /* reports untouched by msg_groups */
}
END_TEST

/* 5.6.16 */
START_TEST(nc_dest_list_and_group)
{
    start(NULL);
    rpt("alpha", 0, 0, NULL, 1000);
    rpt("bravo", 10, 40, "red_team", 1000);
    rpt("charlie", -40, 0, "blue", 1000);
    rpt("gilda", 0, -40, "red_team", 1000);
    rpt("henry", 40, 0, "blue", 1000);
    mail("NODE_MESSAGE", "src_node=alpha,dest_node=bravo:charlie:bravo,dest_group=red_team,var_name=FOOBAR,string_val=hello",
         1000);
    R->n = 0;
    iter(1000);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 1);
    ck_assert_int_eq(count("NODE_MESSAGE_CHARLIE"), 1);
    ck_assert_int_eq(count("NODE_MESSAGE_GILDA"), 1);
    ck_assert_int_eq(count("NODE_MESSAGE_HENRY"), 0);
    ck_assert_int_eq(count("NODE_MESSAGE_ALPHA"), 0);
    ck_assert_uint_eq(C->msgs_sent, 3);
    /* the seed's typo "dest_name;..." and dest_node=all (every known vehicle but the source) */
    mail("NODE_MESSAGE", "src_node=henry,dest_name;alpha:gilda,var_name=FOOBAR,string_val=74", 1000.5);
    R->n = 0;
    iter(1000.5);
    ck_assert_int_eq(count("NODE_MESSAGE_ALPHA"), 1);
    ck_assert_int_eq(count("NODE_MESSAGE_GILDA"), 1); /* 56.6 m from henry */
    mail("NODE_MESSAGE", "src_node=charlie,dest_node=all,var_name=FOOBAR,string_val=74", 1000.5);
    R->n = 0;
    iter(1000.5);
    ck_assert_int_eq(count("NODE_MESSAGE_CHARLIE"), 0);
    ck_assert_int_eq(count("NODE_MESSAGE_ALPHA") + count("NODE_MESSAGE_BRAVO") + count("NODE_MESSAGE_GILDA"), 3);
    ck_assert_int_eq(count("NODE_MESSAGE_HENRY"), 1); /* 80 m: in range too */
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_FAR], 0);
}
END_TEST

/* 5.6.17 and the other Invalid cases */
START_TEST(nc_invalid)
{
    start(NULL);
    two(50, NULL, NULL);
    const char *bad[] = {
        "src_node=alpha,dest_node=bravo,string_val=hello",                       /* no var_name */
        "dest_node=bravo,var_name=X,string_val=hello",                           /* no source */
        "src_node=alpha,var_name=X,string_val=hello",                            /* no destination */
        "src_node=alpha,dest_node=bravo,var_name=X",                             /* no value */
        "src_node=alpha,dest_node=bravo,var_name=X,string_val=a,double_val=2",   /* both values */
        "src_node=alpha,dest_node=bravo,var_name=X,double_val=abc",              /* not a number */
        "src_node=zulu,dest_node=bravo,var_name=X,string_val=hi",                /* source never reported */
    };
    for (int i = 0; i < 7; i++) mail("NODE_MESSAGE", bad[i], 1000);
    R->n = 0;
    iter(1000);
    ck_assert_int_eq(R->n, 0);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_INVALID], 7);
    ck_assert_uint_eq(C->msgs_rcvd, 7);
    /* src_var stands for var_name (A7) */
    mail("NODE_MESSAGE", "src_node=alpha,dest_node=bravo,src_var=SPEED,double_val=2.5", 1000);
    iter(1000);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 1);
}
END_TEST

/* 5.6.18 and 1.5 */
START_TEST(nc_pulse_string)
{
    start(NULL);
    rpt("james", 109.63, -60.06, NULL, 2652414456.59);
    rpt("ike", 30.96, -60.22, NULL, 2652414456.59);
    R->n = 0;
    iter(2652414456.59);
    const char *p = NULL;
    for (int i = 0; i < R->n; i++)
        if (!strcmp(R->var[i], "VIEW_COMMS_PULSE") && strstr(R->val[i], "label=JAMES2IKE")) p = R->val[i];
    ck_assert_ptr_nonnull(p);
    ck_assert_str_eq(p, "sx=109.63,sy=-60.06,tx=30.96,ty=-60.22,beam_width=7,duration=10,fill=0.35,label=JAMES2IKE,"
                        "edge_color=orange,fill_color=orange,time=2652414456.59,edge_size=1");
    kelp_view v;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_view_parse(KELP_VIEW_COMMS_PULSE, p, strlen(p), &v, &why), 0);
    ck_assert_double_eq_tol(v.x, 109.63, 1e-9);
    ck_assert_double_eq_tol(v.ty, -60.22, 1e-9);
    ck_assert_double_eq_tol(v.duration, 10, 1e-9);
    ck_assert_str_ne(v.fill_color, "white"); /* white is for messages */
    /* VIEW_NODE_RPT_PULSES off (and by mail), PULSE_DURATION 0: no pulses */
    ck_assert_int_eq(mail("UNC_VIEW_NODE_RPT_PULSES", "false", 2652414457), 1);
    rpt("james", 109.63, -60.06, NULL, 2652414457);
    R->n = 0;
    iter(2652414457);
    ck_assert_int_eq(count("NODE_REPORT_IKE"), 1);
    ck_assert_int_eq(count("VIEW_COMMS_PULSE"), 0);
}
END_TEST

/* 5.6.19 and the block: every seed and 24.8 parameter */
START_TEST(nc_config)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    ck_assert(cfg.verbose);
    cfgset(&cfg, "VERBOSE", "false");
    ck_assert(!cfg.verbose);
    cfgset(&cfg, "PULSE_DURATION", "12;");
    ck_assert_double_eq(cfg.pulse_duration, 12);
    cfgset(&cfg, "comms_range", "nolimit");
    ck_assert_double_eq(cfg.comms_range, -1);
    cfgset(&cfg, "min_rpt_interval", "-1");
    cfgset(&cfg, "drop_percentage", "10");
    ck_assert_double_eq(cfg.drop_pct, 10);
    cfgset(&cfg, "shared_node_reports", "false");
    ck_assert_double_eq(cfg.share_interval, -1);
    cfgset(&cfg, "shared_node_reports", "true");
    ck_assert_double_eq(cfg.share_interval, 0.1);
    cfgset(&cfg, "msg_repeat_color", "light_green");
    cfgset(&cfg, "DEBUG", "true");
    cfgset(&cfg, "earange", "vname=alpha, earange=40"); /* clipped to 10 */
    ck_assert_double_eq(cfg.factor[0].earange, 10);
    cfgset(&cfg, "stealth", "vname=alpha, stealth=0");  /* clipped to 0.1 */
    ck_assert_double_eq(cfg.factor[1].stealth, 0.1);
    kelp_diag why = { 0 };
    ck_assert_int_lt(kelp_field_ncomms_config(&cfg, "DROP_PERCENTAGE", "101", &why), 0);
    ck_assert_int_ne(why.code, 0);
    ck_assert_int_lt(kelp_field_ncomms_config(&cfg, "GROUPS", "maybe", &why), 0);
    ck_assert_int_lt(kelp_field_ncomms_config(&cfg, "MAX_MSG_LENGTH", "-3", &why), 0);
    ck_assert_int_lt(kelp_field_ncomms_config(&cfg, "CRITICAL_RANGE", "x", &why), 0);
    ck_assert_int_lt(kelp_field_ncomms_config(&cfg, "STEALTH", "stealth=0.5", &why), 0);
    ck_assert_int_eq(kelp_field_ncomms_config(&cfg, "APPTICK", "4", &why), 0);
}
END_TEST

/* the 24.8 report format (DEP, JSON-free, fields in any order) is parsed and relayed verbatim */
START_TEST(nc_248_report_format)
{
    start(NULL);
    const char *a = "NAME=alpha,X=-5.2,Y=3,SPD=2,HDG=118.8,DEP=4.6,LAT=43.824981,LON=-70.329755,TYPE=kayak,"
                    "COLOR=yellow,MODE=MODE@ACTIVE:LOITERING,ALLSTOP=clear,INDEX=12,YAW=1.2,TIME=1252348077.59,LENGTH=3.8";
    const char *b = "TIME=1252348077.59,LENGTH=3.8,GROUP=red,Y=40,X=20,NAME=bravo,DEPTH=1";
    ck_assert_int_eq(mail("NODE_REPORT_LOCAL", a, 1000), 1);
    ck_assert_int_eq(mail("NODE_REPORT", b, 1000), 1);
    R->n = 0;
    iter(1000);
    ck_assert_str_eq(last("NODE_REPORT_BRAVO"), a);
    ck_assert_str_eq(last("NODE_REPORT_ALPHA"), b);
    /* malformed reports: a warning, counted, nothing else lost */
    ck_assert_int_lt(mail("NODE_REPORT", "NAME=charlie,X=abc,Y=2", 1001), 0);
    ck_assert_int_lt(mail("NODE_REPORT", "X=1,Y=2", 1001), 0);
    ck_assert_int_lt(kelp_field_ncomms_mail(C, "NODE_REPORT", false, NULL, 3, 1001, &S), 0);
    ck_assert_uint_eq(C->rpts_bad, 2);
    ck_assert_int_eq(R->warns, 3);
    ck_assert_int_eq(kelp_field_ncomms_find(C, "charlie"), -1);
    ck_assert_uint_eq(C->rpts_rcvd, 2);
    ck_assert_int_eq(kelp_field_ncomms_mail(C, "DB_UPTIME", false, NULL, 3, 1001, &S), 0);
    /* LAT,LON only: rejected without a datum, placed with one */
    ck_assert_int_lt(mail("NODE_REPORT", "NAME=delta,LAT=43.825,LON=-70.33", 1001), 0);
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    ck_assert_int_eq(kelp_geo_init(&cfg.geo, 43.825, -70.33), 0);
    cfg.have_geo = true;
    start(&cfg);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=delta,LAT=43.825,LON=-70.33", 1001), 1);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=echo,LAT=43.8254,LON=-70.33", 1001), 1); /* ~44 m north */
    R->n = 0;
    iter(1001);
    ck_assert_int_eq(count("NODE_REPORT_ECHO"), 1);
    ck_assert_double_eq_tol(C->hot[kelp_field_ncomms_find(C, "echo")].y, 44.5, 1.0);
}
END_TEST

/* 24.8 drop_percentage: a seeded RNG; the count of drops is within bounds */
START_TEST(nc_drops)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "drop_percentage", "30");
    cfg.seed = 12345;
    start(&cfg);
    int sent = 0;
    for (int i = 0; i < 2000; i++) {
        double t = 1000 + i * 0.25;
        rpt("alpha", 0, 0, NULL, t);
        rpt("bravo", 50, 0, NULL, t);
        R->n = 0;
        iter(t);
        sent += count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA");
    }
    /* 4000 relays at p = 0.7: mean 2800, sd 29 */
    ck_assert_int_gt(sent, 2800 - 150);
    ck_assert_int_lt(sent, 2800 + 150);
    ck_assert_uint_eq(C->rpts_dropped + (unsigned long)sent, 4000);
    /* inside the critical range nothing is dropped */
    ck_assert_int_eq(mail("UNC_DROP_PCT", "100", 2000), 1);
    two(20, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 2);
    two(50, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 0);
    ck_assert_int_lt(mail("UNC_DROP_PCT", "120", 2000), 0);
    ck_assert_double_eq(C->drop_pct, 100);
}
END_TEST

/* 24.8 min_rpt_interval: S -> D at most every interval */
START_TEST(nc_min_rpt_interval)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "min_rpt_interval", "2");
    start(&cfg);
    int sent = 0;
    for (int i = 0; i < 40; i++) { /* 10 s at 4 Hz */
        double t = 1000 + i * 0.25;
        rpt("alpha", 0, 0, NULL, t);
        rpt("bravo", 50, 0, NULL, t);
        R->n = 0;
        iter(t);
        sent += count("NODE_REPORT_BRAVO");
    }
    ck_assert_int_eq(sent, 5); /* t = 0, 2, 4, 6, 8 */
    ck_assert_uint_eq(C->rpts_held, 70);
}
END_TEST

/* the blocked counters, one per reason, and the terminal report (Listing 11) */
START_TEST(nc_blocked_and_report)
{
    start(NULL);
    rpt("gilda", 0, 0, NULL, 1000);
    rpt("henry", 60, 0, NULL, 1000);
    rpt("ike", 0, 50, "GROUP12", 1000);
    rpt("james", 500, 0, "GROUP12", 1000);
    iter(1000);
    mail("NODE_MESSAGE", "src_node=ike,dest_group=GROUP12,var_name=FOOBAR,string_val=hello", 1000); /* far */
    mail("NODE_MESSAGE", "src_node=ike,dest_node=gilda:henry,var_name=FOOBAR,string_val=hello", 1000);
    mail("NODE_MESSAGE", "src_node=ike,dest_node=henry,var_name=FOOBAR,string_val=hello", 1000);     /* too recent */
    mail("NODE_MESSAGE", "src_node=gilda,dest_node=nobody,var_name=FOOBAR,string_val=hello", 1000);
    mail("NODE_MESSAGE", "src_node=gilda", 1000);
    iter(1000);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_FAR], 1);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_RECENT], 1);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_STALE], 1);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_INVALID], 1);
    ck_assert_uint_eq(C->msgs_sent, 2);
    static char buf[8192];
    ck_assert_int_eq(kelp_field_ncomms_report(C, 1049.3, buf, sizeof buf), 0);
    const char *want[] = { "****\nuFldNodeCommsSummary:\n****\n\nNode Report Summary\n=====\n    Total Received: 4\n",
                           "            GILDA: 1      (49.3)\n",
                           "Node Message Summary\n=====\n    Total Msgs Received: 5\n",
                           "            IKE: 3      (49.3)\n",
                           "          Total Sent: 2\n            GILDA: 1\n            HENRY: 1\n",
                           "      Total Blocked Msgs: 4\n          Invalid: 1\n          Stale Receiver: 1\n"
                           "          Too Recent: 1\n          Msg Too Long: 0\n          Range Too Far: 1\n  -----\n",
                           "      Last Msgs:\n  src_node=ike,dest_group=GROUP12,var_name=FOOBAR,string_val=hello\n" };
    for (int i = 0; i < 7; i++) ck_assert_msg(strstr(buf, want[i]) != NULL, "missing [%s] in\n%s", want[i], buf);
    ck_assert_ptr_null(strstr(buf, "Dropped"));
    ck_assert_int_eq(kelp_field_ncomms_report(C, 1049.3, buf, 64), KELP_ERR_NOSPACE);
    ck_assert_uint_eq(strlen(buf), 63);
}
END_TEST

/* COMMS_RANGE nolimit / 0 and UNC_COMMS_RANGE */
START_TEST(nc_comms_range_mail)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "comms_range", "nolimit");
    start(&cfg);
    two(5000, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 2);
    ck_assert_int_eq(kelp_field_ncomms_mail(C, "UNC_COMMS_RANGE", false, NULL, 250, 1000, &S), 1);
    two(240, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 2);
    two(260, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 0);
    ck_assert_int_eq(mail("UNC_COMMS_RANGE", "0", 1000), 1);
    two(40, NULL, NULL); /* nothing but the critical range */
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
    two(20, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
    ck_assert_int_lt(mail("UNC_COMMS_RANGE", "far", 1000), 0);
}
END_TEST

/* MEDIATED_MESSAGE / ack=true -> MEDIATED_MESSAGE_<V>; ACK_MESSAGE -> ACK_MESSAGE_<DEST>;
 * a repeated message id is drawn in msg_repeat_color */
START_TEST(nc_mediated_and_ack)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "min_msg_interval", "0");
    start(&cfg);
    two(50, NULL, NULL);
    const char *m = "src_node=alpha,dest_node=bravo,var_name=X,string_val=go,ack=true,msg_id=alpha_7";
    mail("MEDIATED_MESSAGE", m, 1000);
    R->n = 0;
    iter(1000);
    ck_assert_str_eq(last("MEDIATED_MESSAGE_BRAVO"), m);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 0);
    ck_assert_ptr_nonnull(strstr(last("VIEW_COMMS_PULSE"), "fill_color=white"));
    mail("NODE_MESSAGE", m, 1000.25);
    R->n = 0;
    iter(1000.25);
    ck_assert_ptr_nonnull(strstr(last("VIEW_COMMS_PULSE"), "fill_color=light_green"));
    ck_assert_int_eq(mail("ACK_MESSAGE", "src=bravo, dest=alpha, id=alpha_7", 1000.5), 1);
    ck_assert_int_lt(mail("ACK_MESSAGE", "src=bravo, id=alpha_7", 1000.5), 0);
    R->n = 0;
    iter(1000.5);
    ck_assert_str_eq(last("ACK_MESSAGE_ALPHA"), "src=bravo, dest=alpha, id=alpha_7");
    ck_assert_uint_eq(C->acks_sent, 1);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_INVALID], 1);
}
END_TEST

/* MOOS-IvP 24.8 names a message's id ack_id (lib_mbutil NodeMessage: string2NodeMessage and
 * getSpec, as pMediator writes it): a repeated ack_id is drawn in msg_repeat_color */
START_TEST(nc_ack_id_repeat_color)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "min_msg_interval", "0");
    start(&cfg);
    two(50, NULL, NULL);
    const char *m = "ack_id=alpha_12,ack=true,src_node=alpha,dest_node=bravo,var_name=X,string_val=go";
    mail("MEDIATED_MESSAGE", m, 1000);
    R->n = 0;
    iter(1000);
    ck_assert_str_eq(last("MEDIATED_MESSAGE_BRAVO"), m);
    ck_assert_ptr_nonnull(strstr(last("VIEW_COMMS_PULSE"), "fill_color=white"));
    mail("MEDIATED_MESSAGE", m, 1000.25);
    R->n = 0;
    iter(1000.25);
    ck_assert_ptr_nonnull(strstr(last("VIEW_COMMS_PULSE"), "fill_color=light_green"));
}
END_TEST

/* shared_node_reports: NODE_REPORT_UNC at most every interval of real time */
START_TEST(nc_shared_reports)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "shared_node_reports", "1");
    cfg.warp = 2;
    start(&cfg);
    for (int i = 0; i < 16; i++) {
        rpt("alpha", 0, 0, NULL, 1000 + i * 0.5);
        iter(1000 + i * 0.5);
    }
    ck_assert_int_eq(count("NODE_REPORT_UNC"), 4); /* 8 s of MOOS time = 4 s real at warp 2 */
    ck_assert_int_eq(mail("UNC_SHARED_NODE_REPORTS", "false", 1010), 1);
    R->n = 0;
    rpt("alpha", 0, 0, NULL, 1010);
    iter(1010);
    ck_assert_int_eq(count("NODE_REPORT_UNC"), 0);
}
END_TEST

/* UNC_FULL_REPORT_REQ: the named vehicle gets the reports of every vehicle it may hear */
START_TEST(nc_full_report_req)
{
    start(NULL);
    rpt("alpha", 0, 0, NULL, 1000);
    rpt("bravo", 50, 0, NULL, 1000);
    rpt("charlie", 0, 60, NULL, 1000);
    rpt("delta", 900, 0, NULL, 1000);
    iter(1000);
    ck_assert_int_eq(mail("UNC_FULL_REPORT_REQ", "alpha", 1001), 1);
    ck_assert_int_lt(mail("UNC_FULL_REPORT_REQ", "zulu", 1001), 0);
    R->n = 0;
    iter(1001);
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 2);
    ck_assert_int_eq(count_with("NODE_REPORT_ALPHA", "NAME=charlie"), 1);
}
END_TEST

/* the grid gives exactly the brute-force set of relays, with stealth/earange and staleness */
START_TEST(nc_grid_matches_brute_force)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    start(&cfg);
    enum { N = 400 };
    static double x[N], y[N], st[N], ea[N], tr[N];
    uint64_t s = 99;
    for (int i = 0; i < N; i++) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        x[i] = (double)((s >> 33) % 4000) - 2000.0;
        y[i] = (double)((s >> 13) % 4000) - 2000.0;
        st[i] = i % 7 == 0 ? 0.5 : 1;
        ea[i] = i % 11 == 0 ? 3 : 1;
        tr[i] = i % 13 == 0 ? 990 : 1000;
        char nm[16], f[64];
        snprintf(nm, sizeof nm, "v%d", i);
        if (st[i] != 1) snprintf(f, sizeof f, "vname=%s,stealth=%g", nm, st[i]), mail("UNC_STEALTH", f, 990);
        if (ea[i] != 1) snprintf(f, sizeof f, "vname=%s,earange=%g", nm, ea[i]), mail("UNC_EARANGE", f, 990);
        rpt(nm, x[i], y[i], NULL, tr[i]);
    }
    R->n = 0;
    iter(1000);
    long owed = 0;
    for (int a = 0; a < N; a++)
        for (int b = 0; b < N; b++) {
            if (a == b || tr[b] < 995) continue;
            double r = hypot(x[a] - x[b], y[a] - y[b]);
            if (r < 30 || r < 100 * st[a] * ea[b]) owed++;
        }
    ck_assert_int_gt(owed, 50);
    int got = 0;
    for (int i = 0; i < R->n; i++) got += strncmp(R->var[i], "NODE_REPORT_", 12) == 0;
    ck_assert_int_eq(got, owed);
    ck_assert_uint_eq(C->rpts_sent, (unsigned long)owed);
    ck_assert_uint_lt(C->scanned, (unsigned long)N * 40); /* not N * N */
}
END_TEST

Suite *kelp_field_nodecomms_suite(void);
Suite *kelp_field_nodecomms_suite(void)
{
    Suite *s = suite_create("field_nodecomms");
    TCase *t = tcase_create("nodecomms");
    tcase_add_checked_fixture(t, setup, teardown);
    tcase_add_test(t, nc_in_range_relayed);
    tcase_add_test(t, nc_exact_range_not);
    tcase_add_test(t, nc_stealth_shrinks);
    tcase_add_test(t, nc_critical_overrides_stealth);
    tcase_add_test(t, nc_earange_grows);
    tcase_add_test(t, nc_factors_cancel);
    tcase_add_test(t, nc_groups);
    tcase_add_test(t, nc_stale_receiver);
    tcase_add_test(t, nc_not_updated);
    tcase_add_test(t, nc_unc_stealth);
    tcase_add_test(t, nc_message_delivered);
    tcase_add_test(t, nc_msg_too_long);
    tcase_add_test(t, nc_min_msg_interval);
    tcase_add_test(t, nc_interval_starts_at_success);
    tcase_add_test(t, nc_msg_no_critical_range);
    tcase_add_test(t, nc_groups_not_for_messages);
    tcase_add_test(t, nc_msg_groups);
    tcase_add_test(t, nc_dest_list_and_group);
    tcase_add_test(t, nc_invalid);
    tcase_add_test(t, nc_pulse_string);
    tcase_add_test(t, nc_config);
    tcase_add_test(t, nc_248_report_format);
    tcase_add_test(t, nc_drops);
    tcase_add_test(t, nc_min_rpt_interval);
    tcase_add_test(t, nc_blocked_and_report);
    tcase_add_test(t, nc_comms_range_mail);
    tcase_add_test(t, nc_mediated_and_ack);
    tcase_add_test(t, nc_ack_id_repeat_color);
    tcase_add_test(t, nc_shared_reports);
    tcase_add_test(t, nc_full_report_req);
    tcase_add_test(t, nc_grid_matches_brute_force);
    suite_add_tcase(s, t);
    return s;
}
