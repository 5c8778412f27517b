/* uFldHazardSensor's state machine (src/field/hazardsensor.c) against MOOS-IvP 24.8's build of
 * the app: swath geometry, the draws on glibc's rand() sequence, config requests, the options
 * summary, the swath and PSR every iteration, markers, the classify queue and the report. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/hazardsensor.h>

#define NREC 512

typedef struct rec {
    int n, warns, events, cfgw;
    char var[NREC][40];
    char val[NREC][400];
    char warn[8][200];
    char cfg[4][200];
} rec;

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    (void)dval;
    if (r->n >= NREC || !is_string) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    snprintf(r->val[r->n], sizeof r->val[0], "%s", sval);
    r->n++;
}

static void wrn(void *ctx, const char *msg)
{
    rec *r = ctx;
    if (r->warns < 8) snprintf(r->warn[r->warns], sizeof r->warn[0], "%s", msg);
    r->warns++;
}

static void evt(void *ctx, const char *msg)
{
    (void)msg;
    ((rec *)ctx)->events++;
}

static void cfgw(void *ctx, const char *msg)
{
    rec *r = ctx;
    if (r->cfgw < 4) snprintf(r->cfg[r->cfgw], sizeof r->cfg[0], "%s", msg);
    r->cfgw++;
}

static const char *get(const rec *r, const char *var)
{
    for (int i = r->n; i-- > 0;)
        if (!strcmp(r->var[i], var)) return r->val[i];
    return NULL;
}

static int count(const rec *r, const char *var)
{
    int c = 0;
    for (int i = 0; i < r->n; i++) c += !strcmp(r->var[i], var);
    return c;
}

static kelp_hazardsensor_cfg C;
static kelp_hazardsensor H;
static rec R;
static kelp_field_sink S = { &R, pub, wrn };

/* the recorded scenario's block (hazard_f1_fixedseed) */
static void scenario(const char *const *objects)
{
    static const char *const lines[] = { "sensor_config", "width=5,  exp=8, pclass=0.88, max=1",
                                         "sensor_config", "width=10, exp=6, pclass=0.70",
                                         "sensor_config", "width=25, exp=4, pclass=0.63",
                                         "sensor_config", "width=50, exp=2, pclass=0.55",
                                         "swath_length", "5", "default_benign_shape", "square",
                                         "min_classify_interval", "5", "min_reset_interval", "100",
                                         "seed_random", "false", NULL };
    kelp_diag why = { 0 };
    memset(&R, 0, sizeof R);
    kelp_hazardsensor_cfg_default(&C);
    for (int i = 0; lines[i]; i += 2) ck_assert_int_eq(kelp_hazardsensor_config(&C, lines[i], lines[i + 1], &why), 1);
    for (int i = 0; objects && objects[i]; i++) ck_assert_int_eq(kelp_hazardsensor_config(&C, "hazard", objects[i], &why), 1);
    ck_assert_int_eq(kelp_hazardsensor_init(&H, &C), 0);
    kelp_hazardsensor_set_log(&H, evt, cfgw, &R);
}

static void nr(const char *name, double x, double y, double hdg, double now)
{
    char b[160];
    snprintf(b, sizeof b, "NAME=%s,TYPE=UUV,TIME=1.00,X=%.3f,Y=%.3f,SPD=2,HDG=%.3f", name, x, y, hdg);
    ck_assert_int_eq(kelp_hazardsensor_mail(&H, "NODE_REPORT", b, "archie", now, &S), 1);
}

static int mail(const char *var, const char *val, const char *community, double now)
{
    return kelp_hazardsensor_mail(&H, var, val, community, now, &S);
}

/* archie at the origin heading east, width 25 at `pd`, one sensor request and one iteration at t=1 */
static void sweep_once(const char *const *objects, const char *pd_request)
{
    scenario(objects);
    nr("archie", 0, 0, 90, 1);
    ck_assert_int_eq(mail("UHZ_CONFIG_REQUEST", pd_request, "archie", 1), 1);
    ck_assert_int_eq(mail("UHZ_SENSOR_REQUEST", "vname=archie", "archie", 1), 1);
    kelp_hazardsensor_iterate(&H, 1, &S);
}

/* 24.8's swath: swath_length ahead and behind, the width to each side */
START_TEST(uhz_swath_each_side)
{
    ck_assert(kelp_hazardsensor_in_swath(0, 0, 90, 25, 5, 0, -20));  /* 20 m abeam: inside 25 m */
    ck_assert(kelp_hazardsensor_in_swath(0, 0, 90, 25, 5, 4.5, 24)); /* 4.5 m ahead */
    ck_assert(kelp_hazardsensor_in_swath(0, 0, 90, 25, 5, 4.99, 24.99)); /* near the corner */
    ck_assert(!kelp_hazardsensor_in_swath(0, 0, 90, 25, 5, 0, 26));
    ck_assert(!kelp_hazardsensor_in_swath(0, 0, 90, 25, 5, 5.5, 0));
    ck_assert(kelp_hazardsensor_in_swath(0, 0, 0, 25, 5, 24, 4));
}
END_TEST

/* the swath polygon and PSR every iteration while the request holds; 24.8's spec */
START_TEST(uhz_swath_every_iteration)
{
    scenario(NULL);
    nr("archie", -6, -10, 90, 1);
    ck_assert_int_eq(mail("UHZ_CONFIG_REQUEST", "vname=archie,width=25,pd=0.9", "archie", 1), 1);
    ck_assert_int_eq(mail("UHZ_SENSOR_REQUEST", "vname=archie", "archie", 2), 1);
    R.n = 0;
    for (int i = 0; i < 3; i++) kelp_hazardsensor_iterate(&H, 2 + 0.25 * i, &S);
    ck_assert_int_eq(count(&R, "PSR"), 3);
    ck_assert_int_eq(count(&R, "VIEW_POLYGON"), 3);
    ck_assert_str_eq(get(&R, "PSR"), "archie");
    ck_assert_str_eq(get(&R, "VIEW_POLYGON"), "pts={-1,-35:-11,-35:-11,15:-1,15},label=sensor_swath_archie,"
                                              "msg=0.90/0.66,edge_color=green,fill_color=white,vertex_size=0,"
                                              "edge_size=0,fill_transparency=0.2");
    /* 600 s after the last request the sensor is off: no more PSR */
    R.n = 0;
    kelp_hazardsensor_iterate(&H, 602.5, &S);
    ck_assert_int_eq(count(&R, "PSR"), 0);
}
END_TEST

/* corners at a tie print as 24.8's do (recorded: gus at 16.25,-12 heading 90, width 20, swath
 * length 4 drew x 20.3 and 12.2: its arithmetic lands a hair above and below the halves) */
START_TEST(uhz_swath_corner_digits)
{
    kelp_diag why = { 0 };
    memset(&R, 0, sizeof R);
    kelp_hazardsensor_cfg_default(&C);
    ck_assert_int_eq(kelp_hazardsensor_config(&C, "sensor_config", "width=20, exp=5, pclass=0.75", &why), 1);
    ck_assert_int_eq(kelp_hazardsensor_config(&C, "swath_length", "4", &why), 1);
    ck_assert_int_eq(kelp_hazardsensor_init(&H, &C), 0);
    nr("gus", 16.25, -12, 90, 1);
    ck_assert_int_eq(mail("UHZ_CONFIG_REQUEST", "vname=gus,width=20,pd=0.8", "gus", 1), 1);
    ck_assert_int_eq(mail("UHZ_SENSOR_REQUEST", "vname=gus", "gus", 1), 1);
    kelp_hazardsensor_iterate(&H, 1, &S);
    ck_assert_ptr_nonnull(get(&R, "VIEW_POLYGON"));
    static const char want[] = "pts={20.3,-32:12.2,-32:12.2,8:20.3,8},label=sensor_swath_gus,";
    ck_assert_msg(!strncmp(get(&R, "VIEW_POLYGON"), want, sizeof want - 1), "%s", get(&R, "VIEW_POLYGON"));
}
END_TEST

/* a request from a vehicle with no node report: PSR and 24.8's run warning */
START_TEST(uhz_psr_unknown_vehicle)
{
    scenario(NULL);
    ck_assert_int_eq(mail("UHZ_SENSOR_REQUEST", "vname=nobody", "archie", 1), 1);
    kelp_hazardsensor_iterate(&H, 1, &S);
    ck_assert_str_eq(get(&R, "PSR"), "nobody");
    ck_assert_str_eq(R.warn[0], "No NODE_REPORT received for nobody");
}
END_TEST

/* config requests only from the vehicle's own community; 24.8's ack, no UHZ_CONFIG_ACK */
START_TEST(uhz_config_community_and_ack)
{
    scenario(NULL);
    nr("archie", 0, 0, 90, 1);
    ck_assert_int_lt(mail("UHZ_CONFIG_REQUEST", "vname=archie,width=10,pd=0.9", "betty", 1), 0);
    ck_assert_int_eq(R.cfgw, 1);
    ck_assert_str_eq(R.cfg[0], "Bad sensor config request from: archie src: betty");
    ck_assert_str_eq(R.warn[0], "Unhandled mail: UHZ_CONFIG_REQUEST");
    ck_assert_int_eq(count(&R, "UHZ_CONFIG_ACK_ARCHIE"), 0);
    ck_assert_int_eq(mail("UHZ_CONFIG_REQUEST", "vname=archie,width=25,pd=0.9", "archie", 1), 1);
    ck_assert_str_eq(get(&R, "UHZ_CONFIG_ACK_ARCHIE"), "vname=archie,width=25,pd=0.9,pfa=0.656,pclass=0.63");
    ck_assert_int_eq(count(&R, "UHZ_CONFIG_ACK"), 0);
    /* too soon (min_reset_interval 100): denied */
    ck_assert_int_lt(mail("UHZ_CONFIG_REQUEST", "vname=archie,width=10,pd=0.5", "archie", 3), 0);
    ck_assert_int_eq(count(&R, "UHZ_CONFIG_ACK_ARCHIE"), 1);
    /* a pd-only request keeps the width */
    ck_assert_int_eq(mail("UHZ_CONFIG_REQUEST", "vname=archie,pd=0.6", "archie", 4), 1);
    ck_assert_str_eq(get(&R, "UHZ_CONFIG_ACK_ARCHIE"), "vname=archie,width=25,pd=0.6,pfa=0.13,pclass=0.63");
    /* nearest width: 30 -> 25 (not 50) */
    ck_assert_int_eq(mail("UHZ_CONFIG_REQUEST", "vname=archie,width=30,pd=0.9", "archie", 200), 1);
    ck_assert_str_eq(get(&R, "UHZ_CONFIG_ACK_ARCHIE"), "vname=archie,width=25,pd=0.9,pfa=0.656,pclass=0.63");
}
END_TEST

/* a vehicle that never asked gets the width nearest the middle, pd 0.9 */
START_TEST(uhz_default_setting)
{
    scenario(NULL);
    nr("betty", 45, -28, 90, 1);
    ck_assert_int_eq(mail("UHZ_SENSOR_REQUEST", "vname=betty", "archie", 6), 1);
    kelp_hazardsensor_iterate(&H, 6, &S);
    ck_assert_str_eq(get(&R, "UHZ_CONFIG_ACK_BETTY"), "vname=betty,width=25,pd=0.9,pfa=0.656,pclass=0.63");
}
END_TEST

/* UHZ_OPTIONS_SUMMARY: 24.8's keys, values as written, the last line first */
START_TEST(uhz_options_summary)
{
    scenario(NULL);
    kelp_hazardsensor_iterate(&H, 0, &S);
    ck_assert_str_eq(get(&R, "UHZ_OPTIONS_SUMMARY"),
                     "width=50,exp=2,class=0.55:width=25,exp=4,class=0.63:width=10,exp=6,class=0.70:width=5,exp=8,class=0.88,max=1");
    R.n = 0;
    kelp_hazardsensor_iterate(&H, 9, &S);
    ck_assert_int_eq(count(&R, "UHZ_OPTIONS_SUMMARY"), 0);
    kelp_hazardsensor_iterate(&H, 10, &S);
    ck_assert_int_eq(count(&R, "UHZ_OPTIONS_SUMMARY"), 1);
}
END_TEST

/* markers in label order with 24.8's keys and colours */
START_TEST(uhz_markers)
{
    static const char *const objs[] = { "x=15, y=-12, label=h1, type=hazard", "x=30, y=-8,  label=b1, type=benign", NULL };
    scenario(objs);
    kelp_hazardsensor_iterate(&H, 0, &S);
    ck_assert_str_eq(R.var[0], "VIEW_MARKER");
    ck_assert_str_eq(R.val[0], "x=30,y=-8,width=8,primary_color=light_blue,type=square,label=b1,fill_transparency=0.5");
    ck_assert_str_eq(R.val[1], "x=15,y=-12,width=8,primary_color=red,type=triangle,label=h1");
    R.n = 0;
    ck_assert_int_eq(mail("PMV_CONNECT", "true", "archie", 1), 1);
    ck_assert_int_eq(count(&R, "VIEW_MARKER"), 2);
}
END_TEST

/* an object with an aspect gets 24.8's line through it: 15 m each way, or 5 + 25 x the mean of
 * aspect_min and aspect_max over 90; on an axis exactly without sin/cos; none at aspect 0 */
START_TEST(uhz_aspect_line)
{
    static const char *const objs[] = { "x=40, y=-25, label=a2, type=hazard, aspect=45",
                                        "x=30, y=-65, label=c4, type=benign, aspect=90",
                                        "x=0, y=0, label=z0, type=hazard, aspect=0",
                                        "x=10, y=10, label=m1, type=hazard, aspect=30, aspect_min=20, aspect_max=40", NULL };
    scenario(objs);
    kelp_hazardsensor_iterate(&H, 0, &S);
    ck_assert_int_eq(count(&R, "VIEW_MARKER"), 4);
    ck_assert_int_eq(count(&R, "VIEW_SEGLIST"), 3);
    /* in label order, each after its marker: a2, c4, m1 (z0 has aspect 0) */
    ck_assert_str_eq(R.val[1], "pts={50.6,-14.4:29.4,-35.6},edge_color=gray70,vertex_size=0,edge_size=1");
    ck_assert_str_eq(R.val[3], "pts={45,-65:15,-65},edge_color=gray70,vertex_size=0,edge_size=1");
    /* 5 + 25 x (30 / 90) = 13.33 m at 30 degrees */
    ck_assert_str_eq(R.val[5], "pts={16.7,21.5:3.3,-1.5},edge_color=gray70,vertex_size=0,edge_size=1");
}
END_TEST

/* detection: one draw per object newly in the swath, glibc's rand() % 10000 / 10000 unseeded:
 * 0.9383 (h1: missed at pd 0.9), then 0.0886 (h2: detected) */
START_TEST(uhz_detection_fixed_seed)
{
    static const char *const objs[] = { "x=0,y=-5,label=h1,type=hazard", "x=0,y=5,label=h2,type=hazard", NULL };
    sweep_once(objs, "vname=archie,width=25,pd=0.9");
    ck_assert_int_eq(count(&R, "UHZ_DETECTION_REPORT"), 1);
    ck_assert_str_eq(get(&R, "UHZ_DETECTION_REPORT"), "x=0,y=5,label=h2,vname=archie");
    ck_assert_str_eq(get(&R, "UHZ_DETECTION_REPORT_ARCHIE"), "x=0,y=5,label=h2");
    ck_assert_int_eq(count(&R, "UHZ_HAZARD_REPORT"), 0); /* classified only on request */
    ck_assert_int_eq(count(&R, "VIEW_CIRCLE"), 1);
    /* still inside: no new draw */
    R.n = 0;
    kelp_hazardsensor_iterate(&H, 1.25, &S);
    ck_assert_int_eq(count(&R, "UHZ_DETECTION_REPORT"), 0);
}
END_TEST

/* turning faster than max_turn_rate: the swath is red and nothing is detected */
START_TEST(uhz_sensor_off_turning)
{
    static const char *const objs[] = { "x=0,y=5,label=h2,type=hazard", NULL };
    scenario(objs);
    nr("archie", 0, 0, 90, 1);
    nr("archie", 0, 0, 100, 1.5); /* 20 deg/s */
    ck_assert_int_eq(mail("UHZ_SENSOR_REQUEST", "vname=archie", "archie", 1.5), 1);
    kelp_hazardsensor_iterate(&H, 1.5, &S);
    ck_assert(strstr(get(&R, "VIEW_POLYGON"), "fill_color=red") != NULL);
    ck_assert_int_eq(count(&R, "UHZ_DETECTION_REPORT"), 0);
}
END_TEST

/* classify requests: one per detection, the dice on rand() % 10001, served first the active
 * entry, then by priority, one every min_classify_interval; 24.8's report spec */
START_TEST(uhz_classify_queue)
{
    static const char *const objs[] = { "x=0,y=5,label=h2,type=hazard", "x=0,y=-5,label=h1,type=hazard",
                                        "x=1,y=5,label=h3,type=hazard", "x=1,y=-5,label=h4,type=hazard", NULL };
    sweep_once(objs, "vname=archie,width=25,pd=1");
    ck_assert_int_eq(count(&R, "UHZ_DETECTION_REPORT"), 4);
    R.n = 0;
    ck_assert_int_eq(mail("UHZ_CLASSIFY_REQUEST", "vname=archie,label=h1", "archie", 10), 1);
    ck_assert_int_eq(mail("UHZ_CLASSIFY_REQUEST", "vname=archie,label=h2", "archie", 10), 1);
    ck_assert_int_eq(mail("UHZ_CLASSIFY_REQUEST", "vname=archie,label=h3,priority=90", "archie", 10), 1);
    ck_assert_int_lt(mail("UHZ_CLASSIFY_REQUEST", "vname=archie,label=h4,priority=abc", "archie", 10), 0);
    ck_assert_str_eq(R.warn[0], "Classify request with bad priority:abc");
    ck_assert_int_lt(mail("UHZ_CLASSIFY_REQUEST", "vname=archie,label=zz", "archie", 10), 0);
    ck_assert_str_eq(R.warn[2], "archie class req for unknown haz label:zz");
    kelp_hazardsensor_iterate(&H, 14.75, &S);
    ck_assert_int_eq(count(&R, "UHZ_HAZARD_REPORT"), 0);
    const char *order[3] = { "label=h1", "label=h3", "label=h2" };
    for (int i = 0; i < 3; i++) {
        R.n = 0;
        kelp_hazardsensor_iterate(&H, 15 + 5 * i, &S);
        ck_assert_int_eq(count(&R, "UHZ_HAZARD_REPORT"), 1);
        ck_assert(strstr(get(&R, "UHZ_HAZARD_REPORT_ARCHIE"), order[i]) != NULL);
    }
}
END_TEST

START_TEST(uhz_classify_dice)
{
    static const char *const objs[] = { "x=0,y=5,label=h2,type=hazard", "x=0,y=-5,label=b1,type=benign", NULL };
    sweep_once(objs, "vname=archie,width=25,pd=1"); /* rand #1 (b1: 0.9383 < pfa 1), #2 (h2: 0.0886) */
    ck_assert_int_eq(count(&R, "UHZ_DETECTION_REPORT"), 2);
    ck_assert_int_eq(mail("UHZ_CLASSIFY_REQUEST", "vname=archie,label=h2", "archie", 2), 1);
    ck_assert_int_eq(mail("UHZ_CLASSIFY_REQUEST", "vname=archie,label=b1", "archie", 2), 1);
    ck_assert_int_lt(mail("UHZ_CLASSIFY_REQUEST", "vname=archie,label=b1", "archie", 2), 0);
    ck_assert_str_eq(R.warn[0], "Sensor classify request saturated: archie");
    R.n = 0;
    kelp_hazardsensor_iterate(&H, 7, &S);
    kelp_hazardsensor_iterate(&H, 12, &S);
    /* rand #3 1681692777 % 10001 / 10000 = 0.4625 < 0.63: h2 said hazard; #4 1714636915 % 10001
     * / 10000 = 0.5469 < 0.63: b1 said benign */
    int first = 0;
    while (first < R.n && strcmp(R.var[first], "UHZ_HAZARD_REPORT_ARCHIE")) first++;
    ck_assert_int_lt(first, R.n - 1);
    ck_assert_str_eq(R.val[first], "x=0,y=5,label=h2,type=hazard");
    ck_assert_str_eq(R.var[first + 1], "UHZ_HAZARD_REPORT");
    ck_assert_str_eq(R.val[first + 1], "vname=archie,x=0,y=5,label=h2,type=hazard");
    ck_assert_str_eq(get(&R, "UHZ_HAZARD_REPORT"), "vname=archie,x=0,y=-5,label=b1,type=benign");
    ck_assert(strstr(get(&R, "VIEW_CIRCLE"), "vertices=5,edge_color=white,fill_color=white") != NULL);
}
END_TEST

/* the AppCast's tables */
START_TEST(uhz_report_tables)
{
    static const char *const objs[] = { "x=0,y=5,label=h2,type=hazard", NULL };
    scenario(objs);
    nr("archie", 0, 0, 90, 1);
    ck_assert_int_eq(mail("UHZ_CONFIG_REQUEST", "vname=archie,width=25,pd=0.9", "archie", 7), 1);
    ck_assert_int_eq(mail("UHZ_SENSOR_REQUEST", "vname=archie", "archie", 8), 1);
    kelp_hazardsensor_iterate(&H, 8, &S);
    char buf[4096];
    ck_assert_int_eq(kelp_hazardsensor_report(&H, NULL, 0, buf, sizeof buf), 0);
    ck_assert(strstr(buf, "Hazard File: (None provided.) \n     Hazard: 1\n     Benign: 0\n") == buf);
    ck_assert(strstr(buf, "Width  Exp  Classify  Max\n-----  ---  --------  ---\n5.0    8.0  0.880     1\n") != NULL);
    ck_assert(strstr(buf, "archie   25.0   0.900  0.656  0.630   1          1(7)    0(0)\n\n\n") != NULL);
    /* the one draw, 0.9383, missed h2 at pd 0.9 */
    ck_assert(strstr(buf, "archie   1       0           n/a   0.00  0         0\n") != NULL);
}
END_TEST

START_TEST(uhz_gen_points)
{
    static const double sq[4][2] = { { 0, 0 }, { 50, 0 }, { 50, 50 }, { 0, 50 } };
    static const double line[3][2] = { { 0, 0 }, { 1, 1 }, { 2, 2 } };
    kelp_rng g;
    kelp_rng_seed(&g, 7);
    double x, y;
    for (int i = 0; i < 1000; i++) {
        ck_assert_int_eq(kelp_hazardsensor_random_point(sq, 4, &g, &x, &y), 0);
        ck_assert(x >= 0 && x <= 50 && y >= 0 && y <= 50);
    }
    ck_assert(kelp_hazardsensor_in_convex(sq, 4, 50, 25)); /* on an edge */
    ck_assert_int_eq(kelp_hazardsensor_random_point(line, 3, &g, &x, &y), KELP_ERR_ARG);
}
END_TEST

/* hazard lines: 24.8 needs a type and a label */
START_TEST(uhz_hazard_lines)
{
    kelp_diag why = { 0 };
    kelp_hazardsensor_cfg_default(&C);
    ck_assert_int_eq(kelp_hazardsensor_hazard_line(&C, "hazard = x=1,y=2,type=hazard,label=a", &why), 1);
    ck_assert_int_lt(kelp_hazardsensor_hazard_line(&C, "hazard = x=1,y=2,label=b", &why), 0);
    ck_assert_int_lt(kelp_hazardsensor_hazard_line(&C, "hazard = x=1,y=2,type=benign", &why), 0);
    ck_assert_int_lt(kelp_hazardsensor_hazard_line(&C, "hazard = x=1,y=2,type=benign,label=a", &why), 0);
    ck_assert_int_eq(kelp_hazardsensor_hazard_line(&C, "// comment", &why), 0);
    ck_assert_int_eq(C.nobjects, 1u);
}
END_TEST

Suite *kelp_field_hazard_suite(void);
Suite *kelp_field_hazard_suite(void)
{
    Suite *s = suite_create("field_hazard");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, uhz_swath_each_side);
    tcase_add_test(tc, uhz_swath_every_iteration);
    tcase_add_test(tc, uhz_psr_unknown_vehicle);
    tcase_add_test(tc, uhz_config_community_and_ack);
    tcase_add_test(tc, uhz_default_setting);
    tcase_add_test(tc, uhz_options_summary);
    tcase_add_test(tc, uhz_markers);
    tcase_add_test(tc, uhz_aspect_line);
    tcase_add_test(tc, uhz_swath_corner_digits);
    tcase_add_test(tc, uhz_detection_fixed_seed);
    tcase_add_test(tc, uhz_sensor_off_turning);
    tcase_add_test(tc, uhz_classify_queue);
    tcase_add_test(tc, uhz_classify_dice);
    tcase_add_test(tc, uhz_report_tables);
    tcase_add_test(tc, uhz_gen_points);
    tcase_add_test(tc, uhz_hazard_lines);
    suite_add_tcase(s, tc);
    return s;
}
