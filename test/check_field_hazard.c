/* uFldHazardSensor's state machine (src/field/hazardsensor.c): ufield.md 9.8 and the rules of
 * 9.2 to 9.6, with statistical checks of the detection and classification draws. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/hazardsensor.h>

#define NREC 256

typedef struct rec {
    int n, warns;
    char var[NREC][40];
    char val[NREC][400];
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
    (void)msg;
    ((rec *)ctx)->warns++;
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

static kelp_field_uhz_cfg C;
static kelp_field_uhz H;

static void cfg(const char *const *lines)
{
    kelp_diag why = { 0 };
    kelp_field_uhz_cfg_default(&C);
    for (int i = 0; lines && lines[i]; i += 2) ck_assert_int_eq(kelp_field_uhz_config(&C, lines[i], lines[i + 1], &why), 1);
}

static void start(void)
{
    ck_assert_int_eq(kelp_field_uhz_init(&H, &C), 0);
}

static const char *const FIVE[] = { "sensor_config", "width=80, exp=2, pclass=0.60",
                                    "sensor_config", "width=65, exp=4, pclass=0.75",
                                    "sensor_config", "width=50, exp=6, pclass=0.85",
                                    "sensor_config", "width=30, exp=12, pclass=0.93",
                                    "sensor_config", "width=18, exp=20, pclass=0.97",
                                    NULL };

static void nr(const char *name, double x, double y, double hdg, const kelp_field_sink *s)
{
    char b[160];
    snprintf(b, sizeof b, "NAME=%s,TYPE=UUV,TIME=1.00,X=%.3f,Y=%.3f,SPD=2.00,HDG=%.3f", name, x, y, hdg);
    ck_assert_int_eq(kelp_field_uhz_mail(&H, "NODE_REPORT", b, 0, s), 1);
}

static void req(const char *name, double now, const kelp_field_sink *s)
{
    char b[64];
    snprintf(b, sizeof b, "vname=%s", name);
    ck_assert_int_eq(kelp_field_uhz_mail(&H, "UHZ_SENSOR_REQUEST", b, now, s), 1);
}

START_TEST(uhz_default_setting_five)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    cfg(FIVE);
    start();
    ck_assert_int_eq(kelp_field_uhz_default_setting(&H.cfg), 1); /* sorted: 18, 30, 50, 65, 80 */
    nr("archie", 0, 0, 0, &s);
    req("archie", 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=30,pd=0.9,pfa=0.28,pclass=0.93");
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK"), "vname=archie,width=30,pd=0.9,pfa=0.28,pclass=0.93");
}
END_TEST

START_TEST(uhz_default_setting_listing20)
{
    static const char *const L20[] = { "sensor_config", "width=25, exp=4, pclass=0.85", "sensor_config",
                                       "width=50, exp=2, pclass=0.60", "sensor_config",
                                       "width=10, exp=6, pclass=0.93", NULL };
    cfg(L20);
    start();
    int d = kelp_field_uhz_default_setting(&H.cfg);
    ck_assert_int_ge(d, 0);
    ck_assert_double_eq(H.cfg.setting[d].width, 25);
    kelp_field_uhz_cfg_default(&C);
    ck_assert_int_eq(kelp_field_uhz_default_setting(&C), -1);
    ck_assert_double_eq(C.min_reset_interval, 300); /* MOOS-IvP's default (2012 and 24.8) */
}
END_TEST

static void config(const char *spec, double now, int want, const kelp_field_sink *s)
{
    ck_assert_int_eq(kelp_field_uhz_mail(&H, "UHZ_CONFIG_REQUEST", spec, now, s) == 1, want == 1);
}

START_TEST(uhz_config_request_widths)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    cfg(FIVE);
    C.min_reset_interval = 0; /* back-to-back requests (MOOS-IvP's default 300 s would refuse them) */
    start();
    nr("archie", 0, 0, 0, &s);
    config("vname=archie, width=32, pd=0.9", 1, 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=30,pd=0.9,pfa=0.28,pclass=0.93");
    config("vname=archie, width=10, pd=0.9", 2, 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=18,pd=0.9,pfa=0.12,pclass=0.97");
    config("vname=archie, width=100, pd=0.9", 3, 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=80,pd=0.9,pfa=0.81,pclass=0.6");
    config("vname=archie, width=65, pd=0.9", 4, 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=65,pd=0.9,pfa=0.66,pclass=0.75");
    /* UHZ_SENSOR_CONFIG is the same request; a request without width keeps the width */
    ck_assert_int_eq(kelp_field_uhz_mail(&H, "UHZ_SENSOR_CONFIG", "vname=archie,pd=0.5", 5, &s), 1);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=65,pd=0.5,pfa=0.06,pclass=0.75");
    ck_assert_uint_eq(H.node[0].resets, 5);
}
END_TEST

START_TEST(uhz_pfa_values)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    static const char *const L[] = { "sensor_config", "width=25, exp=4, pclass=0.85", "sensor_config",
                                     "width=20, exp=6, pclass=0.91", "sensor_config", "width=10, exp=6, pclass=0.93",
                                     "verbose", "true", "min_reset_interval", "0", NULL };
    cfg(L);
    start();
    nr("archie", 0, 0, 0, &s);
    config("vname=archie,width=25,pd=0.9", 1, 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=25,pd=0.9,pfa=0.66,pclass=0.85");
    ck_assert_double_eq_tol(H.node[0].pfa, 0.6561, 1e-12);
    char buf[4096];
    ck_assert_int_eq(kelp_field_uhz_report(&H, 1, buf, sizeof buf), 0);
    ck_assert_ptr_nonnull(strstr(buf, "0.656"));
    ck_assert_ptr_nonnull(strstr(buf, "archie      25.0    0.900   0.656   0.850"));
    config("vname=archie,width=10,pd=0.9", 2, 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=10,pd=0.9,pfa=0.53,pclass=0.93");
    config("vname=archie,width=20,pd=0.9", 3, 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK"), "vname=archie,width=20,pd=0.9,pfa=0.53,pclass=0.91");
}
END_TEST

START_TEST(uhz_config_rejections)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    cfg(FIVE);
    C.verbose = false;
    start();
    nr("archie", 0, 0, 0, &s);
    config("vname=archie,width=30,pd=0.9", 1, 1, &s);
    r.n = 0;
    config("vname=archie,width=80,pd=1.5", 2, 0, &s); /* X */
    config("vname=archie,width=abc,pd=0.5", 2, 0, &s); /* X */
    config("width=80,pd=0.5", 2, 0, &s);               /* x: no name */
    config("vname=zed,width=80,pd=0.5", 2, 0, &s);     /* x: no node report */
    ck_assert_int_eq(r.n, 0);                           /* no ack */
    ck_assert_double_eq(H.cfg.setting[H.node[0].setting].width, 30);
    ck_assert_double_eq(H.node[0].pd, 0.9);
    char buf[256];
    ck_assert_int_eq(kelp_field_uhz_report(&H, 2, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "NXXxx\n");
    /* no settings: '!' */
    kelp_field_uhz_cfg_default(&C);
    start();
    nr("archie", 0, 0, 0, &s);
    config("vname=archie,width=30,pd=0.9", 1, 0, &s);
    ck_assert_int_eq(kelp_field_uhz_report(&H, 2, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "N!\n");
}
END_TEST

START_TEST(uhz_reset_interval_and_max)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    static const char *const L[] = { "sensor_config", "width=25, exp=4, class=0.80", "sensor_config",
                                     "width=50, exp=2, class=0.60", "sensor_config",
                                     "width=10, exp=6, class=0.93,max=1", "min_reset_interval", "300 // default",
                                     NULL };
    cfg(L);
    start();
    nr("archie", 0, 0, 0, &s);
    nr("betty", 0, 0, 0, &s);
    config("vname=archie,width=10,pd=0.9", 100, 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=10,pd=0.9,pfa=0.53,pclass=0.93");
    config("vname=archie,width=50,pd=0.9", 200, 0, &s); /* too soon */
    ck_assert_uint_eq(H.node[0].reset_denied, 1);
    /* width 10 is held by archie (max=1): betty gets the lowest free one */
    config("vname=betty,width=10,pd=0.9", 200, 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_BETTY"), "width=25,pd=0.9,pfa=0.66,pclass=0.8");
    config("vname=archie,width=50,pd=0.8", 400, 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=50,pd=0.8,pfa=0.64,pclass=0.6");
}
END_TEST

START_TEST(uhz_options_summary)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    static const char *const L[] = { "sensor_config", "width=25, exp=4, pclass=0.85", "sensor_config",
                                     "width=50, exp=2, pclass=0.60", "sensor_config",
                                     "width=10, exp=6, pclass=0.93", NULL };
    cfg(L);
    start();
    for (int t = 0; t <= 40; t++) kelp_field_uhz_iterate(&H, 100 + t * 0.5, &s);
    ck_assert_str_eq(get(&r, "UHZ_OPTIONS_SUMMARY"),
                     "width=10,exp=6,pclass=0.93:width=25,exp=4,pclass=0.85:width=50,exp=2,pclass=0.6");
    ck_assert_int_eq(count(&r, "UHZ_OPTIONS_SUMMARY"), 3); /* at 100, 110, 120 */
    r.n = 0;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_uhz_config(&C, "options_summary_interval", "5", &why), 1);
    start();
    for (int t = 0; t <= 40; t++) kelp_field_uhz_iterate(&H, 100 + t * 0.5, &s);
    ck_assert_int_eq(count(&r, "UHZ_OPTIONS_SUMMARY"), 5);
}
END_TEST

/* one object, a sure sensor (pd=1, pclass=1) */
static void sure(const char *obj1, const char *obj2)
{
    static const char *const L[] = { "sensor_config", "width=25, exp=4, pclass=1", NULL };
    kelp_diag why = { 0 };
    cfg(L);
    if (obj1) ck_assert_int_eq(kelp_field_uhz_config(&C, "hazard", obj1, &why), 1);
    if (obj2) ck_assert_int_eq(kelp_field_uhz_config(&C, "hazard", obj2, &why), 1);
    start();
}

START_TEST(uhz_detection_in_swath)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    sure("x=12,y=0,type=hazard,label=12", "x=0,y=3,type=benign");
    nr("archie", 0, 0, 0, &s);
    config("vname=archie,width=25,pd=1", 0, 1, &s);
    req("archie", 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_HAZARD_REPORT_ARCHIE"), "x=12,y=0,hazard=true,label=12");
    ck_assert_str_eq(get(&r, "UHZ_HAZARD_REPORT"), "vname=archie,x=12,y=0,hazard=true,label=12");
    ck_assert_str_eq(get(&r, "UHZ_DETECTION_REPORT_ARCHIE"), "x=12,y=0,label=12");
    ck_assert_int_eq(count(&r, "UHZ_HAZARD_REPORT"), 1); /* not the benign at along 3 > 2.5 */
    ck_assert_uint_eq(H.node[0].detects, 1);
    /* staying inside: no further report over 10 requests */
    for (int i = 0; i < 10; i++) req("archie", 2 + i, &s);
    ck_assert_int_eq(count(&r, "UHZ_HAZARD_REPORT"), 1);
    /* leave (100 m south) and come back */
    nr("archie", 0, -100, 0, &s);
    req("archie", 20, &s);
    ck_assert_int_eq(count(&r, "UHZ_HAZARD_REPORT"), 1);
    nr("archie", 0, 0, 0, &s);
    req("archie", 21, &s);
    ck_assert_int_eq(count(&r, "UHZ_HAZARD_REPORT"), 2);
    /* the swath polygon: corners at +-2.5 along, +-12.5 across; labelled as MOOS-IvP 24.8's
     * (--interface: label=sensor_swath_archie) */
    ck_assert_str_eq(get(&r, "VIEW_POLYGON"), "pts={12.5,2.5:-12.5,2.5:-12.5,-2.5:12.5,-2.5},label=sensor_swath_archie,"
                                              "edge_color=white,fill_color=white,edge_size=0,vertex_size=0,fill=0.25,"
                                              "msg=1.00/1.00");
}
END_TEST

START_TEST(uhz_swath_geometry)
{
    /* heading 90 (east): length runs along x, width along y */
    ck_assert(kelp_field_uhz_in_swath(0, 0, 90, 25, 5, 2.4, 12.4));
    ck_assert(!kelp_field_uhz_in_swath(0, 0, 90, 25, 5, 2.6, 0));
    ck_assert(!kelp_field_uhz_in_swath(0, 0, 90, 25, 5, 0, 12.6));
    ck_assert(kelp_field_uhz_in_swath(100, 100, 45, 20, 5, 100 + 7, 100 - 7)); /* 9.9 m abeam */
    ck_assert(!kelp_field_uhz_in_swath(100, 100, 45, 20, 5, 100 + 7.1, 100 - 7.1));
    ck_assert(kelp_field_uhz_in_swath(0, 0, 0, 25, 5, 0, 2.5)); /* on the edge */
}
END_TEST

START_TEST(uhz_pd_zero)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    sure("x=12,y=0,type=hazard", "x=-5,y=0,type=benign");
    nr("archie", 0, 0, 0, &s);
    config("vname=archie,width=25,pd=0", 0, 1, &s);
    for (int i = 0; i < 50; i++) { /* in and out 50 times */
        nr("archie", 0, 0, (i % 2) ? 90 : 0, &s);
        req("archie", 1 + i, &s);
    }
    ck_assert_int_eq(count(&r, "UHZ_HAZARD_REPORT"), 0);
    ck_assert_int_eq(count(&r, "VIEW_CIRCLE"), 0);
}
END_TEST

START_TEST(uhz_classification_colours)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    sure("x=0,y=0,type=benign,label=b", NULL);
    nr("archie", 0, 0, 0, &s);
    config("vname=archie,width=25,pd=1", 0, 1, &s);
    req("archie", 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_HAZARD_REPORT_ARCHIE"), "x=0,y=0,hazard=false,label=b");
    ck_assert_ptr_nonnull(strstr(get(&r, "VIEW_CIRCLE"), "edge_color=white,fill_color=white"));
    ck_assert_ptr_null(strstr(get(&r, "VIEW_CIRCLE"), "duration="));
    sure("x=0,y=0,type=hazard,label=h", NULL);
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_uhz_config(&C, "show_reports", "60", &why), 1);
    start();
    nr("archie", 0, 0, 0, &s);
    config("vname=archie,width=25,pd=1", 0, 1, &s);
    req("archie", 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_HAZARD_REPORT_ARCHIE"), "x=0,y=0,hazard=true,label=h");
    ck_assert_ptr_nonnull(strstr(get(&r, "VIEW_CIRCLE"), "edge_color=yellow,fill_color=yellow"));
    ck_assert_ptr_nonnull(strstr(get(&r, "VIEW_CIRCLE"), ",duration=60"));
    /* pclass 0: always the wrong class */
    static const char *const L[] = { "sensor_config", "width=25, exp=4, pclass=0", "hazard", "x=0,y=0,type=hazard",
                                     NULL };
    cfg(L);
    start();
    nr("archie", 0, 0, 0, &s);
    config("vname=archie,width=25,pd=1", 0, 1, &s);
    req("archie", 1, &s);
    ck_assert_str_eq(get(&r, "UHZ_HAZARD_REPORT_ARCHIE"), "x=0,y=0,hazard=false,label=0");
}
END_TEST

static const char *const JAKE[] = {
    "// The seed's 18-object Jake field (uField seed section 9.2.1)\n",
    "hazard = x=-151,y=-217.3,type=hazard\n",
    "hazard = x=263.20001,y=-8.5,type=hazard\n",
    "hazard = x=48.5,y=-195.7,type=hazard\n",
    "hazard = x=165.90001,y=-116.4,type=hazard\n",
    "hazard = x=101.3,y=-159.3,type=hazard\n",
    "hazard = x=257.60001,y=-131.3,type=hazard\n",
    "hazard = x=217.3,y=-16.7,type=hazard\n",
    "hazard = x=-14.2,y=-293.60001,type=hazard\n",
    "hazard = x=260.20001,y=-66.2,type=hazard\n",
    "hazard = x=-65.8,y=-125.2,type=hazard\n",
    "hazard = x=171.90001,y=-253.7,type=benign\n",
    "hazard = x=-150.3,y=-117.5,type=benign\n",
    "hazard = x=-59.8,y=-294.10001,type=benign\n",
    "hazard = x=98.2,y=-127.7,type=benign\n",
    "hazard = x=-178.8,y=-234,type=benign\n",
    "hazard = x=24,y=-61,type=benign\n",
    "hazard = x=250.3,y=-214.6,type=benign\n",
    "hazard = x=97.7,y=-245.5,type=benign\n",
    NULL };

START_TEST(uhz_markers)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    kelp_diag why = { 0 };
    cfg(FIVE);
    int added = 0;
    for (int i = 0; JAKE[i]; i++) { /* test/data/moos-24.8/hazards.txt: a comment, then 18 lines */
        int rc = kelp_field_uhz_hazard_line(&C, JAKE[i], &why);
        ck_assert_int_ge(rc, 0);
        added += rc;
    }
    ck_assert_int_eq(added, 18);
    ck_assert_uint_eq(C.nhazard, 10);
    ck_assert_uint_eq(C.nbenign, 8);
    for (unsigned i = 0; i < 18; i++) {
        char want[8];
        snprintf(want, sizeof want, "%u", i);
        ck_assert_str_eq(C.object[i].label, want);
    }
    C.verbose = true;
    start();
    kelp_field_uhz_iterate(&H, 0, &s);
    ck_assert_int_eq(count(&r, "VIEW_MARKER"), 18);
    ck_assert_str_eq(r.val[0], "x=-151,y=-217.3,label=0,color=green,type=triangle,width=8");
    ck_assert_str_eq(get(&r, "VIEW_MARKER"), "x=97.7,y=-245.5,label=17,color=light_blue,type=triangle,width=8");
    char buf[4096];
    ck_assert_int_eq(kelp_field_uhz_report(&H, 0, buf, sizeof buf), 0);
    ck_assert_ptr_nonnull(strstr(buf, "(1) Total hazards: 18"));
    /* PMV_CONNECT: again */
    ck_assert_int_eq(kelp_field_uhz_mail(&H, "PMV_CONNECT", "true", 1, &s), 1);
    kelp_field_uhz_iterate(&H, 1, &s);
    ck_assert_int_eq(count(&r, "VIEW_MARKER"), 36);
    /* show_hazards = false: none */
    r.n = 0;
    ck_assert_int_eq(kelp_field_uhz_config(&C, "show_hazards", "false", &why), 1);
    start();
    kelp_field_uhz_iterate(&H, 0, &s);
    ck_assert_int_eq(count(&r, "VIEW_MARKER"), 0);
}
END_TEST

START_TEST(uhz_hazard_lines)
{
    kelp_diag why = { 0 };
    kelp_field_uhz_cfg_default(&C);
    ck_assert_int_eq(kelp_field_uhz_hazard_line(&C, "x=20.1,y=13.8,type=hazard\n", &why), 1);
    ck_assert_int_eq(kelp_field_uhz_hazard_line(&C, "  hazard = x=1,y=2,type=benign,label=b7,color=red,width=3", &why),
                     1);
    ck_assert_int_eq(kelp_field_uhz_hazard_line(&C, "", &why), 0);
    ck_assert_int_eq(kelp_field_uhz_hazard_line(&C, "// comment", &why), 0);
    ck_assert_int_eq(kelp_field_uhz_hazard_line(&C, "search_region = pts={0,0:1,1}", &why), 0);
    ck_assert_int_lt(kelp_field_uhz_hazard_line(&C, "x=1,y=2", &why), 0);               /* no type */
    ck_assert_int_lt(kelp_field_uhz_hazard_line(&C, "x=1,y=2,type=rock", &why), 0);     /* bad type */
    ck_assert_int_lt(kelp_field_uhz_hazard_line(&C, "x=1,y=zz,type=hazard", &why), 0);  /* bad y */
    ck_assert_int_lt(kelp_field_uhz_hazard_line(&C, "x=1,y=2,type=hazard,label=b7", &why), 0); /* duplicate */
    ck_assert_uint_eq(C.nobjects, 2);
    ck_assert_str_eq(C.object[0].label, "0");
    ck_assert(C.object[0].hazard);
    ck_assert_str_eq(C.object[1].label, "b7");
    ck_assert_str_eq(C.object[1].color, "red");
    ck_assert_double_eq(C.object[1].width, 3);
    ck_assert_int_lt(kelp_field_uhz_config(&C, "sensor_config", "width=10", &why), 0);
    ck_assert_int_lt(kelp_field_uhz_config(&C, "show_swath", "maybe", &why), 0);
    ck_assert_int_eq(kelp_field_uhz_config(&C, "show_detections", "unlimited", &why), 1);
    ck_assert_double_eq(C.show_reports, -1);
    ck_assert_int_eq(kelp_field_uhz_config(&C, "nonsense", "1", &why), 0);
}
END_TEST

START_TEST(uhz_trace_and_no_report)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    sure("x=0,y=0,type=hazard", NULL);
    kelp_field_uhz_iterate(&H, 0, &s);
    req("archie", 1, &s); /* no node report: nothing */
    ck_assert_int_eq(count(&r, "UHZ_HAZARD_REPORT"), 0);
    ck_assert_int_eq(count(&r, "VIEW_POLYGON"), 0);
    ck_assert_int_eq(r.warns, 1);
    nr("archie", 0, 0, 0, &s);
    kelp_field_uhz_iterate(&H, 1, &s);
    char buf[256];
    ck_assert_int_eq(kelp_field_uhz_report(&H, 1, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "*$N*\n");
    ck_assert_int_eq(kelp_field_uhz_report(&H, 1, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "\n"); /* drained */
    ck_assert_int_lt(kelp_field_uhz_mail(&H, "UHZ_SENSOR_REQUEST", "name=archie", 2, &s), 0);
    ck_assert_int_lt(kelp_field_uhz_mail(&H, "NODE_REPORT", "NAME=x,X=1", 2, &s), 0);
    ck_assert_int_eq(kelp_field_uhz_mail(&H, "OTHER", "x", 2, &s), 0);
}
END_TEST

START_TEST(uhz_classify_requests)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    sure("x=0,y=0,type=hazard,label=h1", "x=5,y=0,type=benign,label=b1");
    nr("archie", 0, 0, 0, &s);
    config("vname=archie,width=25,pd=1", 0, 1, &s);
    /* no detection yet: saturated */
    ck_assert_int_lt(kelp_field_uhz_mail(&H, "UHZ_CLASSIFY_REQUEST", "vname=archie,label=h1", 1, &s), 0);
    req("archie", 1, &s); /* two detections: two credits */
    ck_assert_int_eq(kelp_field_uhz_mail(&H, "UHZ_CLASSIFY_REQUEST", "vname=archie,label=b1,priority=10", 2, &s), 1);
    ck_assert_int_eq(kelp_field_uhz_mail(&H, "UHZ_CLASSIFY_REQUEST", "vname=archie,label=h1,priority=90", 3, &s), 1);
    ck_assert_int_lt(kelp_field_uhz_mail(&H, "UHZ_CLASSIFY_REQUEST", "vname=archie,label=h1", 4, &s), 0);
    ck_assert_int_lt(kelp_field_uhz_mail(&H, "UHZ_CLASSIFY_REQUEST", "vname=archie,label=zz", 4, &s), 0);
    r.n = 0;
    kelp_field_uhz_iterate(&H, 20, &s); /* interval 30 from the first request at 2 */
    ck_assert_ptr_null(get(&r, "UHZ_HAZARD_REPORT_ARCHIE"));
    kelp_field_uhz_iterate(&H, 32, &s); /* the higher priority first */
    ck_assert_str_eq(get(&r, "UHZ_HAZARD_REPORT_ARCHIE"), "x=0,y=0,type=hazard,label=h1");
    kelp_field_uhz_iterate(&H, 50, &s);
    ck_assert_int_eq(count(&r, "UHZ_HAZARD_REPORT_ARCHIE"), 1);
    kelp_field_uhz_iterate(&H, 62, &s);
    ck_assert_str_eq(get(&r, "UHZ_HAZARD_REPORT_ARCHIE"), "x=5,y=0,type=benign,label=b1");
    ck_assert_str_eq(get(&r, "UHZ_HAZARD_REPORT"), "vname=archie,x=5,y=0,type=benign,label=b1");
    ck_assert_uint_eq(H.node[0].classify_answ, 2);
}
END_TEST

/* Statistics: over many objects entering the swath, detections come at P_D (hazards) and P_FA
 * (benign), and correct classifications at P_C. Each trial: the vehicle turns away and back. */
static void rates(bool hazard, double pd, double exp, double pclass, int trials, double *det, double *correct)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, NULL, NULL };
    char sc[96], obj[64];
    kelp_diag why = { 0 };
    snprintf(sc, sizeof sc, "width=25, exp=%g, pclass=%g", exp, pclass);
    snprintf(obj, sizeof obj, "x=0,y=0,type=%s", hazard ? "hazard" : "benign");
    kelp_field_uhz_cfg_default(&C);
    C.show_swath = false;
    C.seed = 12345;
    ck_assert_int_eq(kelp_field_uhz_config(&C, "sensor_config", sc, &why), 1);
    ck_assert_int_eq(kelp_field_uhz_config(&C, "hazard", obj, &why), 1);
    start();
    kelp_field_sink quiet = { &r, pub, NULL };
    (void)s;
    nr("archie", 100, 100, 0, &quiet);
    char cr[64];
    snprintf(cr, sizeof cr, "vname=archie,width=25,pd=%g", pd);
    ck_assert_int_eq(kelp_field_uhz_mail(&H, "UHZ_CONFIG_REQUEST", cr, 0, &quiet), 1);
    unsigned long n_det = 0, n_ok = 0;
    for (int i = 0; i < trials; i++) {
        nr("archie", 100, 100, 0, &quiet); /* away */
        req("archie", i, &quiet);
        nr("archie", 0, 0, 0, &quiet); /* over the object */
        r.n = 0;
        req("archie", i, &quiet);
        const char *rep = get(&r, "UHZ_HAZARD_REPORT_ARCHIE");
        if (rep) {
            n_det++;
            n_ok += (strstr(rep, "hazard=true") != NULL) == hazard;
        }
    }
    *det = (double)n_det / trials;
    *correct = n_det ? (double)n_ok / (double)n_det : 0;
}

START_TEST(uhz_stat_detection_pd)
{
    double det, ok;
    rates(true, 0.9, 4, 0.85, 10000, &det, &ok);
    ck_assert_double_eq_tol(det, 0.9, 0.02);
    ck_assert_double_eq_tol(ok, 0.85, 0.02);
    rates(true, 0.5, 4, 0.6, 10000, &det, &ok);
    ck_assert_double_eq_tol(det, 0.5, 0.02);
    ck_assert_double_eq_tol(ok, 0.6, 0.02);
}
END_TEST

START_TEST(uhz_stat_false_alarm_pfa)
{
    double det, ok;
    rates(false, 0.9, 4, 0.93, 10000, &det, &ok); /* pfa = 0.6561 */
    ck_assert_double_eq_tol(det, 0.6561, 0.02);
    ck_assert_double_eq_tol(ok, 0.93, 0.02);
    rates(false, 0.9, 12, 0.93, 10000, &det, &ok); /* pfa = 0.2824 */
    ck_assert_double_eq_tol(det, 0.2824, 0.02);
}
END_TEST

START_TEST(uhz_seed_repeatable)
{
    double d1, o1, d2, o2;
    rates(true, 0.7, 4, 0.7, 500, &d1, &o1);
    rates(true, 0.7, 4, 0.7, 500, &d2, &o2);
    ck_assert_double_eq(d1, d2);
    ck_assert_double_eq(o1, o2);
}
END_TEST

START_TEST(uhz_gen_points)
{
    static const double sq[4][2] = { { 0, 0 }, { 50, 0 }, { 50, 50 }, { 0, 50 } };
    static const double tri[3][2] = { { 0, 0 }, { 0, 40 }, { 40, 0 } }; /* clockwise */
    static const double line[3][2] = { { 0, 0 }, { 1, 1 }, { 2, 2 } };
    kelp_rng g;
    kelp_rng_seed(&g, 7);
    double sx = 0, sy = 0, x, y;
    int n = 10000, upper = 0;
    for (int i = 0; i < n; i++) {
        ck_assert_int_eq(kelp_field_uhz_random_point(sq, 4, &g, &x, &y), 0);
        ck_assert(x >= 0 && x <= 50 && y >= 0 && y <= 50);
        sx += x, sy += y;
        ck_assert_int_eq(kelp_field_uhz_random_point(tri, 3, &g, &x, &y), 0);
        ck_assert(kelp_field_uhz_in_convex(tri, 3, x, y));
        ck_assert(x + y <= 40 + 1e-9);
        upper += y > 20;
    }
    ck_assert_double_eq_tol(sx / n, 25, 0.5); /* uniform: the centre on average */
    ck_assert_double_eq_tol(sy / n, 25, 0.5);
    ck_assert_double_eq_tol((double)upper / n, 0.25, 0.02); /* area above y=20 is a quarter */
    ck_assert(!kelp_field_uhz_in_convex(tri, 3, 30, 30));
    ck_assert(kelp_field_uhz_in_convex(sq, 4, 50, 25)); /* on an edge */
    ck_assert_int_eq(kelp_field_uhz_random_point(line, 3, &g, &x, &y), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_field_uhz_random_point(sq, 2, &g, &x, &y), KELP_ERR_ARG);
}
END_TEST

START_TEST(uhz_visual_options)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    kelp_diag why = { 0 };
    sure("x=0,y=0,type=hazard,label=h,color=red,shape=square,width=3", "x=40,y=0,type=benign");
    ck_assert_int_eq(kelp_field_uhz_config(&C, "default_benign_shape", "circle // default", &why), 1);
    ck_assert_int_eq(kelp_field_uhz_config(&C, "default_benign_width", "5", &why), 1);
    ck_assert_int_eq(kelp_field_uhz_config(&C, "show_pfa", "false", &why), 1);
    ck_assert_int_eq(kelp_field_uhz_config(&C, "swath_transparency", "0.6", &why), 1);
    start();
    kelp_field_uhz_iterate(&H, 0, &s);
    ck_assert_str_eq(r.val[0], "x=0,y=0,label=h,color=red,type=square,width=3");
    ck_assert_str_eq(r.val[1], "x=40,y=0,label=1,color=light_blue,type=circle,width=5");
    nr("archie", 0, 0, 0, &s);
    req("archie", 1, &s); /* the default setting, acknowledged */
    ck_assert_str_eq(get(&r, "UHZ_CONFIG_ACK_ARCHIE"), "width=25,pd=0.9,pfa=0.66,pclass=1");
    ck_assert_ptr_nonnull(strstr(get(&r, "VIEW_POLYGON"), ",fill=0.6,msg=0.90"));
    ck_assert_ptr_null(strstr(get(&r, "VIEW_POLYGON"), "/"));
    /* pfa alone is written "pfa=0.66" (24.8's msg), as pd alone is the bare number */
    r.n = 0;
    ck_assert_int_eq(kelp_field_uhz_config(&C, "show_pd", "false", &why), 1);
    ck_assert_int_eq(kelp_field_uhz_config(&C, "show_pfa", "true", &why), 1);
    start();
    nr("archie", 0, 0, 0, &s);
    req("archie", 1, &s);
    ck_assert_ptr_nonnull(strstr(get(&r, "VIEW_POLYGON"), ",msg=pfa=0.66"));
    ck_assert_int_eq(kelp_field_uhz_config(&C, "show_pfa", "false", &why), 1);
    /* show_swath = false: no polygon */
    r.n = 0;
    ck_assert_int_eq(kelp_field_uhz_config(&C, "show_swath", "false", &why), 1);
    start();
    nr("archie", 0, 0, 0, &s);
    req("archie", 1, &s);
    ck_assert_int_eq(count(&r, "VIEW_POLYGON"), 0);
    ck_assert_int_eq(count(&r, "UHZ_HAZARD_REPORT"), 1); /* the hazard; the benign at 40 m is abeam outside */
    /* show_reports = 0: circles shown for no time are not posted at all (MOOS-IvP posts a
     * VIEW_CIRCLE only when the duration is unlimited or > 0); the reports still go out */
    r.n = 0;
    ck_assert_int_eq(kelp_field_uhz_config(&C, "show_reports", "0", &why), 1);
    start();
    nr("archie", 0, 0, 0, &s);
    req("archie", 1, &s);
    ck_assert_int_eq(count(&r, "UHZ_HAZARD_REPORT"), 1);
    ck_assert_int_eq(count(&r, "VIEW_CIRCLE"), 0);
    r.n = 0;
    ck_assert_int_eq(kelp_field_uhz_config(&C, "show_reports", "60", &why), 1);
    start();
    nr("archie", 0, 0, 0, &s);
    req("archie", 1, &s);
    ck_assert_ptr_nonnull(strstr(get(&r, "VIEW_CIRCLE"), ",duration=60"));
}
END_TEST

START_TEST(uhz_verbose_report)
{
    rec r = { 0 };
    kelp_field_sink s = { &r, pub, wrn };
    sure("x=0,y=0,type=hazard", NULL);
    H.cfg.verbose = true;
    kelp_field_uhz_iterate(&H, 0, &s);
    nr("archie", 0, 0, 0, &s);
    config("vname=archie,width=25,pd=0.9", 10, 1, &s);
    for (int i = 0; i < 3; i++) req("archie", 11 + i, &s);
    kelp_field_uhz_iterate(&H, 177, &s);
    char buf[4096];
    ck_assert_int_eq(kelp_field_uhz_report(&H, 177, buf, sizeof buf), 0);
    ck_assert_ptr_nonnull(strstr(buf, "uFldHazardSensor Summary:(2)"));
    ck_assert_ptr_nonnull(strstr(buf, "    25.0    4.0   1.000"));
    ck_assert_ptr_nonnull(strstr(buf, "1(167)"));
    ck_assert_ptr_nonnull(strstr(buf, "(3) Sensor request received from: archie"));
    ck_assert_ptr_nonnull(strstr(buf, "(1) Setting sensor settings for:archie"));
    ck_assert_ptr_nonnull(strstr(buf, "(1) Total hazards: 1"));
    ck_assert_int_eq(kelp_field_uhz_report(&H, 177, buf, 40), KELP_ERR_NOSPACE);
    ck_assert_uint_eq(strlen(buf), 39);
}
END_TEST

Suite *kelp_field_hazard_suite(void);
Suite *kelp_field_hazard_suite(void)
{
    Suite *s = suite_create("field_hazard");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, uhz_default_setting_five);
    tcase_add_test(tc, uhz_default_setting_listing20);
    tcase_add_test(tc, uhz_config_request_widths);
    tcase_add_test(tc, uhz_pfa_values);
    tcase_add_test(tc, uhz_config_rejections);
    tcase_add_test(tc, uhz_reset_interval_and_max);
    tcase_add_test(tc, uhz_options_summary);
    tcase_add_test(tc, uhz_detection_in_swath);
    tcase_add_test(tc, uhz_swath_geometry);
    tcase_add_test(tc, uhz_pd_zero);
    tcase_add_test(tc, uhz_classification_colours);
    tcase_add_test(tc, uhz_markers);
    tcase_add_test(tc, uhz_hazard_lines);
    tcase_add_test(tc, uhz_trace_and_no_report);
    tcase_add_test(tc, uhz_classify_requests);
    tcase_add_test(tc, uhz_stat_detection_pd);
    tcase_add_test(tc, uhz_stat_false_alarm_pfa);
    tcase_add_test(tc, uhz_seed_repeatable);
    tcase_add_test(tc, uhz_gen_points);
    tcase_add_test(tc, uhz_visual_options);
    tcase_add_test(tc, uhz_verbose_report);
    suite_add_tcase(s, tc);
    return s;
}
