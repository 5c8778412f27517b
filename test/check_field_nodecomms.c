/* uFldNodeComms's state machine (src/field/nodecomms.c) as MOOS-IvP 24.8 runs it: the
 * expected strings and sequences are rows of the recorded 24.8 runs
 * (test/conformance/moos-ivp-24.8, scenarios nodecomms_a2_groups, _a3_messages, _a4_rates). */
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

static char last_warn[256];

static void warn(void *ctx, const char *msg)
{
    snprintf(last_warn, sizeof last_warn, "%s", msg);
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
    return kelp_field_ncomms_mail(C, var, true, val, 0, "driver", now, &S);
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

/* ------------------------------------------------------------------ range, stealth, earange, groups */

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

/* 24.8: range <= comms_range passes (range > comms_range does not) */
START_TEST(nc_exact_range_passes)
{
    start(NULL);
    two(100, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 2);
    two(100.01, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 0);
    two(250, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 0);
}
END_TEST

START_TEST(nc_stealth_earange)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "STEALTH", "vname=alpha, stealth=0.5");
    start(&cfg);
    two(60, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 1);
    two(30, NULL, NULL); /* the critical range (<= 30) overrides stealth */
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
    ck_assert_int_eq(mail("UNC_EARANGE", "vname=bravo, earrange=2", 1000), 1);
    two(100, NULL, NULL); /* 100 * 0.5 * 2 */
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
    two(101, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
    /* a2's run time changes: stealth clamped to 0.1, earange to 10, a non-number refused */
    ck_assert_int_eq(mail("UNC_STEALTH", "vname=alpha,stealth=0.01", 1000), 1);
    ck_assert_double_eq_tol(C->node[kelp_field_ncomms_find(C, "alpha")].stealth, 0.1, 1e-12);
    ck_assert_int_eq(mail("UNC_EARANGE", "vname=bravo,earange=25", 1000), 1);
    ck_assert_double_eq_tol(C->node[kelp_field_ncomms_find(C, "bravo")].earange, 10, 1e-12);
    ck_assert_int_lt(mail("UNC_STEALTH", "vname=blue2,stealth=abc", 1000), 0);
    ck_assert_str_eq(last_warn, "Bad Mail: UNC_STEALTH");
}
END_TEST

/* GROUPS: group names match exactly (case too); the critical range ignores groups */
START_TEST(nc_groups)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "GROUPS", "true");
    start(&cfg);
    two(50, "red", "blue");
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 0);
    two(25, "red", "blue");
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 2);
    two(50, "red", "RED");
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 0);
    two(50, "red", "red");
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 2);
}
END_TEST

/* a receiver not heard from for STALE_TIME gets no report, unless within the critical range */
START_TEST(nc_stale_receiver)
{
    start(NULL);
    rpt("bravo", 20, 0, NULL, 994);
    rpt("charlie", 80, 0, NULL, 994);
    rpt("alpha", 0, 0, NULL, 1000);
    R->n = 0;
    iter(1000);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);   /* 20 m: critical */
    ck_assert_int_eq(count("NODE_REPORT_CHARLIE"), 0); /* 80 m and stale */
}
END_TEST

/* only a vehicle with a new report is relayed */
START_TEST(nc_not_updated)
{
    start(NULL);
    two(50, NULL, NULL);
    rpt("bravo", 50, 0, NULL, 1001);
    R->n = 0;
    iter(1001);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 1);
    R->n = 0;
    iter(1001.25);
    ck_assert_int_eq(R->n, 0);
}
END_TEST

/* names keep their case (24.8's maps): "abe" and "ABE" are two vehicles, both NODE_REPORT_ABE */
START_TEST(nc_names_keep_case)
{
    start(NULL);
    rpt("abe", 0, 0, NULL, 1000);
    rpt("ABE", 10, 0, NULL, 1000);
    R->n = 0;
    iter(1000);
    ck_assert_int_eq(count("NODE_REPORT_ABE"), 2);
    ck_assert_int_eq(count_with("VIEW_COMMS_PULSE", "label=abe2ABE,"), 1);
    ck_assert_int_eq(count_with("VIEW_COMMS_PULSE", "label=ABE2abe,"), 1);
    ck_assert_int_ge(kelp_field_ncomms_find(C, "ABE"), 0);
    ck_assert_int_ne(kelp_field_ncomms_find(C, "ABE"), kelp_field_ncomms_find(C, "abe"));
}
END_TEST

START_TEST(nc_comms_range_mail)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "comms_range", "nolimit");
    start(&cfg);
    two(5000, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO") + count("NODE_REPORT_ALPHA"), 2);
    ck_assert_int_eq(kelp_field_ncomms_mail(C, "UNC_COMMS_RANGE", false, NULL, 250, NULL, 1000, &S), 1);
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
    ck_assert_str_eq(last_warn, "Bad Mail: UNC_COMMS_RANGE");
}
END_TEST

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
    cfgset(&cfg, "earange", "vname=alpha, earange=40"); /* clamped to 10 */
    ck_assert_double_eq(cfg.factor[0].earange, 10);
    cfgset(&cfg, "stealth", "vname=alpha, stealth=0");  /* clamped to 0.1 */
    ck_assert_double_eq(cfg.factor[1].stealth, 0.1);
    cfgset(&cfg, "stealth", "stealth=0.5");             /* 24.8 takes it, for nobody */
    kelp_diag why = { 0 };
    ck_assert_int_lt(kelp_field_ncomms_config(&cfg, "DROP_PERCENTAGE", "101", &why), 0);
    ck_assert_int_ne(why.code, 0);
    ck_assert_int_lt(kelp_field_ncomms_config(&cfg, "GROUPS", "maybe", &why), 0);
    ck_assert_int_lt(kelp_field_ncomms_config(&cfg, "MAX_MSG_LENGTH", "-3", &why), 0);
    ck_assert_int_lt(kelp_field_ncomms_config(&cfg, "CRITICAL_RANGE", "x", &why), 0);
    ck_assert_int_lt(kelp_field_ncomms_config(&cfg, "STEALTH", "vname=a,stealth=x", &why), 0);
    ck_assert_int_eq(kelp_field_ncomms_config(&cfg, "APPTICK", "4", &why), 0);
    start(&cfg);
    for (unsigned i = 0; kelp_field_ncomms_subscription(i); i++)
        ck_assert_str_ne(kelp_field_ncomms_subscription(i), "UNC_FULL_REPORT_REQ"); /* not 24.8's */
}
END_TEST

/* ------------------------------------------------------------------ the relayed report */

static void datum(kelp_field_ncomms_cfg *cfg)
{
    kelp_field_ncomms_cfg_default(cfg);
    ck_assert_int_eq(kelp_geo_init(&cfg->geo, 42.358456, -71.087589), 0);
    cfg->have_geo = true;
}

/* a3 t=0.08: the report re-serialised by 24.8's node record: COG, LAT/LON, TIME to 2 decimals,
 * LENGTH last */
START_TEST(nc_golden_record)
{
    kelp_field_ncomms_cfg cfg;
    datum(&cfg);
    start(&cfg);
    const double t = 1795284022.41;
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=abe,X=0,Y=0,SPD=0,HDG=0,DEP=0,TYPE=kayak,GROUP=g1,LENGTH=4,TIME=1795284022.406", t), 1);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=ben,X=50,Y=0,SPD=0,HDG=0,DEP=0,TYPE=kayak,GROUP=g1,LENGTH=4,TIME=1795284022.406", t), 1);
    R->n = 0;
    iter(t);
    ck_assert_str_eq(last("NODE_REPORT_BEN"), "NAME=abe,X=0,Y=0,SPD=0,HDG=0,COG=0,DEP=0,LAT=42.358456,LON=-71.087589,"
                                             "TYPE=kayak,GROUP=g1,TIME=1795284022.41,LENGTH=4");
    /* the recording's line, LAT/LON by UTM as 24.8 */
    ck_assert_str_eq(last("NODE_REPORT_ABE"), "NAME=ben,X=50,Y=0,SPD=0,HDG=0,COG=0,DEP=0,LAT=42.35846706,LON=-71.08698225,"
                                             "TYPE=kayak,GROUP=g1,TIME=1795284022.41,LENGTH=4");
}
END_TEST

/* a4: COG from the last position (v1 heading 45 moves 1.06,1.06: COG=45); the ledger's type
 * rules; the reader takes DEPTH= as well as DEP=; keys kelp does not read pass on in key order */
START_TEST(nc_record_ledger)
{
    kelp_field_ncomms_cfg cfg;
    datum(&cfg);
    cfgset(&cfg, "comms_range", "nolimit");
    start(&cfg);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=v1,X=0,Y=0,SPD=1.5,HDG=40,DEP=0,TYPE=kayak,LENGTH=4,TIME=10", 10), 1);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=v2,X=100,Y=0,SPD=2,HDG=90,DEPTH=2.5,TYPE=uuv,TIME=10,ZZ=1,AA=x,AA=y", 10), 1);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=v3,X=0,Y=100,SPD=1,HDG=180,TYPE=frigate,TIME=10", 10), 1);
    R->n = 0;
    iter(10);
    ck_assert_int_eq(count_with("NODE_REPORT_V2", "NAME=v1,X=0,Y=0,SPD=1.5,HDG=40,COG=40,DEP=0,"), 1); /* first: COG = HDG */
    ck_assert_int_eq(count_with("NODE_REPORT_V1", "NAME=v2,X=100,Y=0,SPD=2,HDG=90,COG=90,DEP=2.5,"), 1);
    ck_assert_int_eq(count_with("NODE_REPORT_V1", ",TYPE=auv,TIME=10,LENGTH=3,AA=y,ZZ=1"), 1);
    ck_assert_int_eq(count_with("NODE_REPORT_V1", ",TYPE=ship,TIME=10,LENGTH=12"), 1);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=v1,X=1.06,Y=1.06,SPD=1.5,HDG=40,DEP=0,TYPE=KAYAK,LENGTH=0,TIME=11", 11), 1);
    R->n = 0;
    iter(11);
    ck_assert_ptr_nonnull(strstr(last("NODE_REPORT_V2"), "NAME=v1,X=1.06,Y=1.06,SPD=1.5,HDG=40,COG=45,DEP=0,"));
    ck_assert_ptr_nonnull(strstr(last("NODE_REPORT_V2"), ",TYPE=KAYAK,TIME=11,LENGTH=0")); /* known in any case */
    /* refused, with 24.8's run warnings */
    ck_assert_int_lt(mail("NODE_REPORT", "NAME=v4,X=0,Y=0,SPD=1,HDG=0,TYPE=uuv,TIME=11", 11), 0);
#ifndef KELP_NO_ERRMSG
    ck_assert_str_eq(last_warn, "Bad Mail: NODE_REPORT underwater vehicle type with no depth reported");
#else
    ck_assert_str_eq(last_warn, "Bad Mail: NODE_REPORT parse error"); /* the reason text is compiled out */
#endif
    ck_assert_int_lt(mail("NODE_REPORT", "NAME=v4,X=0,Y=0,SPD=1,HDG=0,TYPE=kayak", 11), 0);
    ck_assert_str_eq(last_warn, "Bad Mail: NODE_REPORT Missing timestamp.");
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=v5,LAT=42.358456,LON=-71.087589,SPD=1,HDG=0,TIME=11", 11), 1);
    R->n = 0;
    iter(11);
    ck_assert_ptr_nonnull(strstr(last("NODE_REPORT_V1"), "NAME=v5,X=0,Y=0,SPD=1,HDG=0,COG=0,LAT=42.358456,LON=-71.087589,TYPE=ship,"));
}
END_TEST

/* ------------------------------------------------------------------ pulses */

/* a4 t=0.09 and a3 t=5.10: 24.8's VIEW_COMMS_PULSE, a tenth of the range wide (5 at least) */
START_TEST(nc_golden_pulse)
{
    kelp_field_ncomms_cfg cfg;
    datum(&cfg);
    cfgset(&cfg, "comms_range", "nolimit");
    cfgset(&cfg, "msg_color", "yellow");
    cfgset(&cfg, "min_msg_interval", "5");
    start(&cfg);
    const double t = 1795284094.08;
    mail("NODE_REPORT", "NAME=v1,X=0,Y=0,SPD=1.5,HDG=45,DEP=0,TYPE=kayak,LENGTH=4,TIME=1795284093.982", t);
    mail("NODE_REPORT", "NAME=v2,X=100,Y=0,SPD=2,HDG=90,DEP=0,TYPE=kayak,LENGTH=4,TIME=1795284093.982", t);
    mail("NODE_REPORT", "NAME=v6,X=300,Y=300,SPD=1,HDG=225,DEP=0,TYPE=kayak,LENGTH=4,TIME=1795284093.982", t);
    R->n = 0;
    iter(t);
    ck_assert_int_eq(count_with("VIEW_COMMS_PULSE", "sx=0,sy=0,tx=100,ty=0,beam_width=10,fill=0.35,ptype=nrep,label=v12v2,"
                                                    "fill_color=orange,time=1795284094.08,duration=10,edge_size=0"), 1);
    ck_assert_int_eq(count_with("VIEW_COMMS_PULSE", "sx=0,sy=0,tx=300,ty=300,beam_width=42.42641,fill=0.35,ptype=nrep,"
                                                    "label=v12v6,fill_color=orange,time=1795284094.08,duration=10,edge_size=0"), 1);
    ck_assert_int_eq(count_with("VIEW_COMMS_PULSE", "edge_color"), 0);
    mail("NODE_REPORT", "NAME=v7,X=50,Y=0,SPD=1,HDG=0,DEP=0,TYPE=kayak,LENGTH=4,TIME=1795284093.982", t);
    ck_assert_int_eq(mail("NODE_MESSAGE", "src_node=v1,dest_node=v7,var_name=M_A,string_val=hi", t), 1);
    R->n = 0;
    iter(1795284094.5);
    ck_assert_str_eq(last("VIEW_COMMS_PULSE"), "sx=0,sy=0,tx=50,ty=0,beam_width=5,fill=0.6,ptype=msg,label=v12v7yellow,"
                                              "fill_color=yellow,time=1795284094.5,duration=10,edge_size=0");
}
END_TEST

/* ------------------------------------------------------------------ messages */

static void a3_fleet(double t)
{
    char b[200];
    static const struct { const char *n; double x; const char *g; } v[] = {
        { "abe", 0, "g1" }, { "ben", 50, "g1" }, { "cal", 120, "g2" }, { "deb", 400, "g1" } };
    for (int i = 0; i < 4; i++) {
        snprintf(b, sizeof b, "NAME=%s,X=%g,Y=0,SPD=0,HDG=0,DEP=0,TYPE=kayak,GROUP=%s,LENGTH=4,TIME=%.3f", v[i].n, v[i].x,
                 v[i].g, t);
        ck_assert_int_eq(mail("NODE_REPORT", b, t), 1);
    }
}

static void a3_start(void)
{
    kelp_field_ncomms_cfg cfg;
    datum(&cfg);
    cfgset(&cfg, "comms_range", "200");
    cfgset(&cfg, "critical_range", "30");
    cfgset(&cfg, "min_msg_interval", "5");
    cfgset(&cfg, "max_msg_length", "30");
    cfgset(&cfg, "view_node_rpt_pulses", "false");
    cfgset(&cfg, "shared_node_reports", "true");
    cfgset(&cfg, "msg_color", "yellow");
    start(&cfg);
}

/* the whole message script of a3, iterating every 0.25 s: what went where, re-serialised, and
 * 24.8's counters */
START_TEST(nc_golden_a3_messages)
{
    static const struct { double t; const char *var, *val; } in[] = {
        { 5, "NODE_MESSAGE", "src_node=abe,dest_node=ben,var_name=M_A,string_val=hi" },
        { 6, "NODE_MESSAGE", "src_node=abe,dest_node=cal,var_name=M_B,string_val=tooquick" },
        { 11, "NODE_MESSAGE", "src_node=abe,dest_node=ben:cal:deb,var_name=M_C,string_val=list" },
        { 17, "NODE_MESSAGE", "src_node=abe,dest_group=g1,var_name=M_D,string_val=group" },
        { 23, "NODE_MESSAGE", "src_node=abe,dest_node=all,var_name=M_E,double_val=3.14159265" },
        { 29, "NODE_MESSAGE", "src_node=abe,dest_node=ben,var_name=M_F,string_val=0123456789012345678901234567890123456789" },
        { 35, "NODE_MESSAGE", "src_node=ben,dest_node=abe,var_name=M_G,string_val=\"x,y\"" },
        { 36, "NODE_MESSAGE", "src_node=cal,dest_node=abe,var_name=M_H,string_val=needack,ack=true,ack_id=cal_1" },
        { 37, "ACK_MESSAGE", "src=abe,dest=cal,id=cal_1" },
        { 41, "NODE_MESSAGE", "src_node=ben,dest_node=abe,var_name=M_I,string_val=both,double_val=2" },
        { 47, "NODE_MESSAGE", "src_node=deb,dest_node=abe,var_name=M_J,string_val=far" },
        { 48, "NODE_MESSAGE", "src_node=abe,dest_node=zed,var_name=M_K,string_val=unknown" },
        { 50, "NODE_MESSAGE", "src_node=ben,dest_node=ALL,var_name=M_L,string_val=upperall" },
        { 56, "NODE_MESSAGE", "src_node=ben,dest_group=G1,var_name=M_M,string_val=uppergroup" },
        { 58, "NODE_MESSAGE", "src_node=cal,dest_node=abe,var_name=M_N1,string_val=first" },
        { 58.01, "NODE_MESSAGE", "src_node=cal,dest_node=ben,var_name=M_N2,string_val=second" },
        { 60, "NODE_MESSAGE", "src_node=abe,dest_node=ben,var_name=M_O,string_val=colored,color=red" },
    };
    a3_start();
    const double t0 = 1795284022.4025;
    size_t k = 0;
    int bad = 0;
    for (int step = 0; step <= 4 * 64; step++) {
        double s = step * 0.25;
        a3_fleet(t0 + s);
        for (; k < sizeof in / sizeof in[0] && in[k].t <= s + 0.02; k++)
            bad += mail(in[k].var, in[k].val, t0 + s) < 0;
        iter(t0 + s);
    }
    ck_assert_int_eq(bad, 1);
    ck_assert_str_eq(last_warn, "Bad Mail: NODE_MESSAGE"); /* M_I: both a string and a double */
    /* the rows of the recording, in order, per destination */
    static const char *const ben[] = {
        "src_node=abe,dest_node=ben,src_app=driver,var_name=M_A,string_val=hi",
        "src_node=abe,dest_node=ben:cal:deb,src_app=driver,var_name=M_C,string_val=list",
        "src_node=abe,dest_group=g1,src_app=driver,var_name=M_D,string_val=group",
        "src_node=abe,dest_node=all,src_app=driver,var_name=M_E,double_val=3.141593",
        "src_node=abe,dest_node=ben,src_app=driver,var_name=M_O,color=red,string_val=colored" };
    static const char *const abe[] = {
        "src_node=ben,dest_node=abe,src_app=driver,var_name=M_G,string_val=\"x,y\"",
        "src_node=ben,dest_node=ALL,src_app=driver,var_name=M_L,string_val=upperall",
        "src_node=cal,dest_node=abe,src_app=driver,var_name=M_N1,string_val=first" };
    static const char *const cal[] = {
        "src_node=abe,dest_node=ben:cal:deb,src_app=driver,var_name=M_C,string_val=list",
        "src_node=abe,dest_node=all,src_app=driver,var_name=M_E,double_val=3.141593",
        "src_node=ben,dest_node=ALL,src_app=driver,var_name=M_L,string_val=upperall" };
    struct { const char *var; const char *const *rows; int n; } want[] = {
        { "NODE_MESSAGE_BEN", ben, 5 }, { "NODE_MESSAGE_ABE", abe, 3 }, { "NODE_MESSAGE_CAL", cal, 3 } };
    for (int w = 0; w < 3; w++) {
        int j = 0;
        for (int i = 0; i < R->n; i++)
            if (!strcmp(R->var[i], want[w].var)) {
                ck_assert_int_lt(j, want[w].n);
                ck_assert_str_eq(R->val[i], want[w].rows[j]);
                j++;
            }
        ck_assert_int_eq(j, want[w].n);
    }
    ck_assert_int_eq(count("NODE_MESSAGE_DEB"), 0);
    ck_assert_int_eq(count("MEDIATED_MESSAGE_ABE"), 1);
    ck_assert_str_eq(last("MEDIATED_MESSAGE_ABE"),
                     "ack_id=cal_1,ack=true,src_node=cal,dest_node=abe,src_app=driver,var_name=M_H,string_val=needack");
    ck_assert_int_eq(count("ACK_MESSAGE_cal"), 1);
    ck_assert_str_eq(last("ACK_MESSAGE_cal"), "id=cal_1, src=abe, dest=cal");
    ck_assert_int_eq(count_with("VIEW_COMMS_PULSE", "label=abe2benred,fill_color=red,"), 1);
    ck_assert_int_eq(count_with("VIEW_COMMS_PULSE", "label=ben2calyellow,"), 1);
    ck_assert_int_eq(count("VIEW_COMMS_PULSE"), 12);
    ck_assert_uint_eq(C->msgs_rcvd, 15);
    ck_assert_uint_eq(C->msgs_sent, 12);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_RECENT], 2); /* M_B, M_N2 */
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_LONG], 1);   /* M_F */
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_FAR], 5);    /* deb for M_C, M_D, M_E, M_L; M_J */
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_NOINFO] + C->blocked[KELP_NCOMMS_BLK_STALE] +
                          C->blocked[KELP_NCOMMS_BLK_INVALID], 0);
    /* the report's message part, as the recording's APPCAST at t=64.5 shows it */
    static char rep[8192];
    ck_assert_int_eq(kelp_field_ncomms_report(C, t0 + 64.5, rep, sizeof rep), 0);
    const char *m = strstr(rep, "Node Message Summary");
    ck_assert_ptr_nonnull(m);
    ck_assert_str_eq(m, "Node Message Summary\n"
                        "======================================\n"
                        "    Total Msgs Received: 15\n"
                        "                   abe: 8       (4.5)\n"
                        "                   ben: 3       (8.5)\n"
                        "                   cal: 3       (6.5)\n"
                        "                   deb: 1      (17.5)\n"
                        "     ------------------ \n"
                        "            Total Sent: 12\n"
                        "                   abe: 4\n"
                        "                   ben: 5\n"
                        "                   cal: 3\n"
                        "     ------------------ \n"
                        "    Total Blocked Msgs: 8\n"
                        "               Invalid: 0\n"
                        "          Missing Info: 0\n"
                        "        Stale Receiver: 0\n"
                        "            Too Recent: 2\n"
                        "          Msg Too Long: 1\n"
                        "         Range Too Far: 5\n\n");
    ck_assert_ptr_nonnull(strstr(rep, "     Share Reports: false\n\n")); /* 24.8 reads min_rpt_interval there */
    ck_assert_int_gt(count("NODE_REPORT_UNC"), 0);
    ck_assert_int_gt(count("RTE"), 0);
}
END_TEST

/* min_msg_interval restarts on a message that went nowhere: the next one inside the interval is
 * blocked as Too Recent */
START_TEST(nc_interval_restarts_on_undelivered)
{
    a3_start();
    a3_fleet(1000);
    iter(1000);
    ck_assert_int_eq(mail("NODE_MESSAGE", "src_node=abe,dest_node=zed,var_name=X,string_val=nobody", 1000), 1);
    iter(1000.25);
    a3_fleet(1002);
    ck_assert_int_eq(mail("NODE_MESSAGE", "src_node=abe,dest_node=ben,var_name=Y,string_val=blocked", 1002), 1);
    R->n = 0;
    iter(1002);
    ck_assert_int_eq(count("NODE_MESSAGE_BEN"), 0);
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_RECENT], 1);
    a3_fleet(1005.5);
    ck_assert_int_eq(mail("NODE_MESSAGE", "src_node=abe,dest_node=ben,var_name=Z,string_val=ok", 1005.5), 1);
    iter(1005.5);
    ck_assert_int_eq(count("NODE_MESSAGE_BEN"), 1);
}
END_TEST

/* a2: red1 (stealth 0.5) to dest_group=blue: both too far; blue1 to dest_group=red: three */
START_TEST(nc_golden_a2_groups)
{
    kelp_field_ncomms_cfg cfg;
    datum(&cfg);
    cfgset(&cfg, "critical_range", "20");
    cfgset(&cfg, "min_msg_interval", "2");
    cfgset(&cfg, "groups", "true");
    cfgset(&cfg, "stealth", "vname=red1, stealth=0.5");
    cfgset(&cfg, "earange", "vname=blue2, earange=1.8");
    start(&cfg);
    static const struct { const char *n; double x, y; const char *g; } v[] = {
        { "red1", 0, 0, "red" }, { "red2", 70, 0, "red" }, { "blue1", 0, 60, "blue" }, { "blue2", 0, 150, "blue" },
        { "red3", 0, -30, "red" } }; /* red3 as it was at t=35 */
    char b[160];
    for (int i = 0; i < 5; i++) {
        snprintf(b, sizeof b, "NAME=%s,X=%g,Y=%g,SPD=0,HDG=0,DEP=0,TYPE=kayak,GROUP=%s,LENGTH=4,TIME=1000", v[i].n, v[i].x,
                 v[i].y, v[i].g);
        ck_assert_int_eq(mail("NODE_REPORT", b, 1000), 1);
    }
    mail("NODE_MESSAGE", "src_node=red1,dest_group=blue,var_name=M1,string_val=r1_to_blue", 1000);
    mail("NODE_MESSAGE", "src_node=blue1,dest_group=red,var_name=M2,string_val=b1_to_red", 1000);
    R->n = 0;
    iter(1000);
    ck_assert_int_eq(count("NODE_MESSAGE_BLUE1") + count("NODE_MESSAGE_BLUE2"), 0);
    ck_assert_int_eq(count("NODE_MESSAGE_RED1") + count("NODE_MESSAGE_RED2") + count("NODE_MESSAGE_RED3"), 3);
    ck_assert_str_eq(last("NODE_MESSAGE_RED2"), "src_node=blue1,dest_group=red,src_app=driver,var_name=M2,string_val=b1_to_red");
    ck_assert_uint_eq(C->blocked[KELP_NCOMMS_BLK_TOO_FAR], 2);
    /* reports with groups: only within a group (or within 20 m) */
    ck_assert_int_eq(count_with("NODE_REPORT_RED2", "NAME=blue1,"), 0);
    ck_assert_int_eq(count_with("NODE_REPORT_RED1", "NAME=red2,"), 1);
    ck_assert_int_eq(count_with("NODE_REPORT_BLUE2", "NAME=blue1,"), 1);  /* 90 <= 100 * 1 * 1.8 */
    ck_assert_int_eq(count_with("NODE_REPORT_RED2", "NAME=red1,"), 0);    /* 70 > 100 * 0.5 */
}
END_TEST

/* drop_percentage drops are not blocked messages */
START_TEST(nc_drops_not_counted)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "drop_percentage", "100");
    start(&cfg);
    two(50, NULL, NULL);
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 0);
    mail("NODE_MESSAGE", "src_node=alpha,dest_node=bravo,var_name=A,string_val=b", 1000);
    R->n = 0;
    iter(1000);
    ck_assert_int_eq(count("NODE_MESSAGE_BRAVO"), 0);
    unsigned long blocked = 0;
    for (int i = 0; i < KELP_NCOMMS_BLK_N; i++) blocked += C->blocked[i];
    ck_assert_uint_eq(blocked, 0);
    two(20, NULL, NULL); /* the critical range is never dropped */
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 1);
}
END_TEST

/* min_rpt_interval: exactly one relay per pair per interval (reports and iterations every 0.25 s) */
START_TEST(nc_min_rpt_interval)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "min_rpt_interval", "2");
    start(&cfg);
    R->n = 0;
    for (int k = 0; k < 80; k++) {
        double t = 1000 + k * 0.25;
        rpt("alpha", 0, 0, NULL, t);
        rpt("bravo", 60, 0, NULL, t);
        iter(t);
    }
    ck_assert_int_eq(count("NODE_REPORT_BRAVO"), 10); /* t = 0, 2, ..., 18 */
    ck_assert_int_eq(count("NODE_REPORT_ALPHA"), 10);
}
END_TEST

/* SHARED_NODE_REPORTS: NODE_REPORT_UNC, and RTE (a double: real seconds since the last one) */
START_TEST(nc_shared_reports)
{
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfgset(&cfg, "shared_node_reports", "1");
    start(&cfg);
    R->n = 0;
    for (int k = 0; k < 8; k++) {
        rpt("alpha", 0, 0, NULL, 1000 + k * 0.25);
        iter(1000 + k * 0.25);
    }
    ck_assert_int_eq(count("NODE_REPORT_UNC"), 2); /* t = 0 and t = 1 */
    ck_assert_int_eq(count("RTE"), 7);
    ck_assert_str_eq(last("RTE"), "0.75");
}
END_TEST

/* 20 x STALE_TIME without a report: forgotten ("Stale Vehicles"), and no longer listed */
START_TEST(nc_forget_stale)
{
    start(NULL);
    two(50, NULL, NULL);
    rpt("alpha", 0, 0, NULL, 1099);
    iter(1099);
    ck_assert_uint_eq(C->stale_dropped, 0);
    iter(1100);
    ck_assert_uint_eq(C->stale_dropped, 1);
    static char rep[4096];
    ck_assert_int_eq(kelp_field_ncomms_report(C, 1100, rep, sizeof rep), 0);
    ck_assert_ptr_null(strstr(rep, "bravo"));
    ck_assert_ptr_nonnull(strstr(rep, "     Stale Vehicles: 1\n"));
}
END_TEST

/* a4's report: 24.8's configuration lines and node report table */
START_TEST(nc_golden_report_layout)
{
    kelp_field_ncomms_cfg cfg;
    datum(&cfg);
    cfgset(&cfg, "comms_range", "nolimit");
    start(&cfg);
    iter(1000);
    mail("NODE_REPORT", "NAME=v1,X=0,Y=0,SPD=1.5,HDG=45,DEP=0,TYPE=kayak,LENGTH=4,TIME=1000", 1000);
    mail("NODE_REPORT", "NAME=v2,X=100,Y=0,SPD=2,HDG=90,DEP=0,TYPE=kayak,LENGTH=4,TIME=1000", 1000);
    iter(1000);
    static char rep[4096];
    ck_assert_int_eq(kelp_field_ncomms_report(C, 1000.5, rep, sizeof rep), 0);
    const char *want = "Configuration:  \n"
                       "       Comms Range: -1\n"
                       "    Critical Range: 30\n"
                       "        Stale Drop: 5\n"
                       "       Stale Foget: 100\n"
                       "   Max Message Len: 1000\n"
                       "   Min Message Int: 30\n"
                       "   Min Report  Int: -1\n"
                       "          Drop Pct: 0\n"
                       "Apply Group (reps): false\n"
                       "Apply Group (msgs): false\n"
                       "     Share Reports: false\n"
                       "\n"
                       "Node Report Summary\n"
                       "======================================\n"
                       "     Total Received: 2         Elapsed      Rate\n"
                       "                 v1: 1         (0.5)      [2.00]\n"
                       "                 v2: 1         (0.5)      [2.00]\n"
                       "     --------------- \n"
                       "         Total Sent: 2\n"
                       "                 v1: 1\n"
                       "                 v2: 1\n"
                       "     --------------- \n"
                       "     Stale Vehicles: 0\n"
                       "\n"
                       "Node Message Summary\n";
    char *end = strstr(rep, "Node Message Summary\n");
    ck_assert_ptr_nonnull(end);
    end[21] = 0;
    ck_assert_str_eq(rep, want);
}
END_TEST

/* the grid visits exactly the receivers a full scan would */
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
            if (a == b) continue;
            double r = hypot(x[a] - x[b], y[a] - y[b]);
            if (r <= 30 || (tr[b] >= 995 && r <= 100 * st[a] * ea[b])) owed++;
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
    tcase_add_test(t, nc_exact_range_passes);
    tcase_add_test(t, nc_stealth_earange);
    tcase_add_test(t, nc_groups);
    tcase_add_test(t, nc_stale_receiver);
    tcase_add_test(t, nc_not_updated);
    tcase_add_test(t, nc_names_keep_case);
    tcase_add_test(t, nc_comms_range_mail);
    tcase_add_test(t, nc_config);
    tcase_add_test(t, nc_golden_record);
    tcase_add_test(t, nc_record_ledger);
    tcase_add_test(t, nc_golden_pulse);
    tcase_add_test(t, nc_golden_a3_messages);
    tcase_add_test(t, nc_interval_restarts_on_undelivered);
    tcase_add_test(t, nc_golden_a2_groups);
    tcase_add_test(t, nc_drops_not_counted);
    tcase_add_test(t, nc_min_rpt_interval);
    tcase_add_test(t, nc_shared_reports);
    tcase_add_test(t, nc_forget_stale);
    tcase_add_test(t, nc_golden_report_layout);
    tcase_add_test(t, nc_grid_matches_brute_force);
    suite_add_tcase(s, t);
    return s;
}
