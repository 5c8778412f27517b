/* The beacon and contact range sensors (src/field/beaconrange.c, contactrange.c,
 * rangesense.c): ufield.md 10.5 and 11.5, the noise models' statistics, and the glibc draws. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/beaconrange.h>
#include <kelp/contactrange.h>
#include <kelp/kv.h>

#define REC_MAX 256
typedef struct rec {
    int n, warns;
    char var[REC_MAX][48];
    char val[REC_MAX][320];
} rec;

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    (void)dval;
    if (r->n >= REC_MAX) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    snprintf(r->val[r->n], sizeof r->val[0], "%s", is_string ? sval : "");
    r->n++;
}

static char last_warn[256];

static void wrn(void *ctx, const char *msg)
{
    snprintf(last_warn, sizeof last_warn, "%s", msg);
    ((rec *)ctx)->warns++;
}

static int count(const rec *r, const char *var)
{
    int k = 0;
    for (int i = 0; i < r->n; i++) k += strcmp(r->var[i], var) == 0;
    return k;
}

/* the k-th value posted on var, or NULL */
static const char *nth(const rec *r, const char *var, int k)
{
    for (int i = 0; i < r->n; i++)
        if (strcmp(r->var[i], var) == 0 && k-- == 0) return r->val[i];
    return NULL;
}

static double num(const char *s, const char *key)
{
    char v[64];
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(kelp_kv_get(s, ',', key, v, sizeof v), 1);
    return atof(v);
}

static void brs_cfg(kelp_beaconrange_cfg *c, const char *const *lines)
{
    kelp_beaconrange_cfg_default(c);
    for (; *lines; lines += 2) {
        kelp_diag why = { 0 };
        int rc = kelp_beaconrange_config(c, lines[0], lines[1], &why);
        ck_assert_msg(rc >= 1, "%s = %s: %s", lines[0], lines[1], kelp_diag_text(&why));
    }
}

static void brs_start(kelp_beaconrange *b, const char *const *lines, double start)
{
    kelp_beaconrange_cfg c;
    brs_cfg(&c, lines);
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_beaconrange_init(b, &c, start, &why), 0);
}

static void nrep(kelp_beaconrange *b, kelp_contactrange *c, const char *name, double x, double y, double now, rec *r)
{
    char s[200];
    kelp_field_sink sink = { r, pub, wrn };
    snprintf(s, sizeof s, "NAME=%s,TYPE=UUV,TIME=%.2f,X=%.2f,Y=%.2f,SPD=1,HDG=90,DEPTH=0", name, now, x, y);
    if (b) ck_assert_int_eq(kelp_beaconrange_mail(b, "NODE_REPORT", true, s, now, &sink), 1);
    if (c) ck_assert_int_eq(kelp_contactrange_mail(c, "NODE_REPORT_LOCAL", true, s, now, &sink), 1);
}

static void breq(kelp_beaconrange *b, const char *name, double now, rec *r)
{
    char s[64];
    kelp_field_sink sink = { r, pub, wrn };
    snprintf(s, sizeof s, "name=%s", name);
    ck_assert_int_eq(kelp_beaconrange_mail(b, "BRS_RANGE_REQUEST", true, s, now, &sink), 1);
}

static const char *const listing24[] = {
    "reach_distance", "default = nolimit", "ping_wait", "30", "ping_payments", "upon_accept",
    "default_beacon_report_range", "nolimit", "beacon", "label=01, x=200, y=0", "beacon", "label=02, x=400, y=-200",
    "beacon", "label=03, x=0,   y=-200", NULL,
};

/* 10.5.1, 10.5.2: the Indigo log's ranges, order 03 02 01, the pulses */
static kelp_beaconrange B; /* large: not on the stack */
static kelp_contactrange C;

START_TEST(brs_indigo_ranges)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, wrn };
    brs_start(&B, listing24, 0);
    (void)kelp_beaconrange_iterate(&B, 0, &sink);
    r.n = 0;
    nrep(&B, NULL, "indigo", -97.65, -64.84, 100, &r);
    breq(&B, "indigo", 100.846, &r);
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), 3);
    ck_assert_str_eq(nth(&r, "BRS_RANGE_REPORT", 0), "vname=indigo,range=166.7446,id=03,time=100.846");
    ck_assert_str_eq(nth(&r, "BRS_RANGE_REPORT", 1), "vname=indigo,range=515.6779,id=02,time=100.846");
    ck_assert_str_eq(nth(&r, "BRS_RANGE_REPORT", 2), "vname=indigo,range=304.6305,id=01,time=100.846");
    ck_assert_int_eq(count(&r, "VIEW_RANGE_PULSE"), 4);
    /* 24.8's pulses: <v>_range_req (radius 40, 6 s), the beacon's label (40, 15 s), fill 0.9 */
    ck_assert_str_eq(nth(&r, "VIEW_RANGE_PULSE", 0), "x=-97.65,y=-64.84,radius=40,fill=0.9,label=indigo_range_req,"
                                                     "edge_color=white,fill_color=white,time=100.85,duration=6,edge_size=1");
    ck_assert_str_eq(nth(&r, "VIEW_RANGE_PULSE", 1), "x=0,y=-200,radius=40,fill=0.9,label=03,"
                                                     "edge_color=pink,fill_color=pink,time=100.85,duration=15,edge_size=1");
    ck_assert_str_eq(r.var[1], "BRS_RANGE_REPORT"); /* report, then its beacon's pulse */
    ck_assert_str_eq(r.var[2], "VIEW_RANGE_PULSE");
    ck_assert(strncmp(nth(&r, "VIEW_RANGE_PULSE", 3), "x=200,y=0,radius=40,fill=0.9,label=01,", 38) == 0);
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT_GT"), 0);
    r.n = 0;
    nrep(&B, NULL, "indigo", -197.96, -129.16, 160, &r);
    breq(&B, "indigo", 160.597, &r);
    ck_assert_double_eq_tol(num(nth(&r, "BRS_RANGE_REPORT", 0), "range"), 210.2533, 1e-9);
    ck_assert_double_eq_tol(num(nth(&r, "BRS_RANGE_REPORT", 1), "range"), 602.1416, 1e-9);
    ck_assert_double_eq_tol(num(nth(&r, "BRS_RANGE_REPORT", 2), "range"), 418.3951, 1e-9);
}
END_TEST

static const char *const waits[][12] = {
    { "ping_wait", "60", "ping_payments", "upon_accept", "beacon", "x=0,y=0,label=01", NULL },
    { "ping_wait", "default = 60", "ping_payments", "upon_request", "beacon", "x=0,y=0,label=01", NULL },
    { "ping_wait", "60", "ping_payments", "upon_response", "beacon", "x=0,y=0,label=01", NULL },
    { "ping_wait", "60", "ping_payments", "upon_receipt", "beacon", "x=0,y=0,label=01", NULL },
};

/* accepted requests among those at the times given (ping pulses count the accepted ones) */
static int accepted(const char *const *cfg, double vx, const double *t, int n, unsigned *mask)
{
    rec r = { 0 };
    brs_start(&B, cfg, -1000);
    nrep(&B, NULL, "v", vx, 0, -1000, &r);
    int k = 0;
    *mask = 0;
    for (int i = 0; i < n; i++) {
        int before = count(&r, "VIEW_RANGE_PULSE");
        unsigned long acc = B.accepted;
        breq(&B, "v", t[i], &r);
        if (B.accepted > acc) {
            k++;
            *mask |= 1u << i;
            ck_assert_int_gt(count(&r, "VIEW_RANGE_PULSE"), before);
        }
    }
    return k;
}

/* 10.5.3 to 10.5.5: ping payments */
START_TEST(brs_ping_payments)
{
    unsigned m;
    const double t3[] = { 0, 40, 61 };
    ck_assert_int_eq(accepted(waits[0], 10, t3, 3, &m), 2);
    ck_assert_uint_eq(m, 0x5u); /* 0 yes, 40 no, 61 yes */
    ck_assert_int_eq(accepted(waits[3], 10, t3, 3, &m), 2); /* upon_receipt = upon_accept */
    const double t4[] = { 0, 40, 61, 101, 161 };
    ck_assert_int_eq(accepted(waits[1], 10, t4, 5, &m), 2);
    ck_assert_uint_eq(m, 0x11u); /* 0 and 161 */
    /* upon_response: out of every beacon's report range (100 m), the clock never restarts */
    const double t5[] = { 100, 110 };
    ck_assert_int_eq(accepted(waits[2], 500, t5, 2, &m), 2);
    ck_assert_int_eq(accepted(waits[0], 500, t5, 2, &m), 1);
    /* upon_response with a report: the clock restarts */
    ck_assert_int_eq(accepted(waits[2], 10, t5, 2, &m), 1);
    /* 24.8: a vehicle's clock starts at 0, not at the start: its first request is honoured
     * however soon after the start, and the next one ping_wait after it */
    rec r = { 0 };
    brs_start(&B, waits[0], 20);
    nrep(&B, NULL, "v", 10, 0, 20, &r);
    breq(&B, "v", 30, &r);
    ck_assert_uint_eq(B.accepted, 1);
    breq(&B, "v", 89, &r);
    breq(&B, "v", 90, &r);
    ck_assert_uint_eq(B.accepted, 2);
}
END_TEST

/* reach per vehicle, report range; only the requester hears the replies (24.8) */
START_TEST(brs_reach_and_report_range)
{
    static const char *const cfg[] = { "reach_distance", "henry = 40", "reach_distance", "default = 1000",
                                       "default_beacon_pull_dist", "0", "node_pull_dist", "default = 0",
                                       "ping_wait", "0", "beacon", "x=0,y=0,label=01",
                                       "beacon", "x=80,y=0,label=02,report_range=nolimit", NULL };
    rec r = { 0 };
    brs_start(&B, cfg, 0);
    nrep(&B, NULL, "henry", 50, 0, 0, &r); /* 50 m from 01, 30 m from 02 */
    breq(&B, "henry", 1, &r);
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), 1);
    ck_assert_str_eq(nth(&r, "BRS_RANGE_REPORT", 0), "vname=henry,range=30,id=02,time=1");
    static const char *const cfg7[] = { "reach_distance", "default = nolimit", "ping_wait", "0", "node_pull_dist", "0",
                                        "beacon", "x=0,y=0,label=03,report_range=80", NULL };
    brs_start(&B, cfg7, 0);
    r.n = 0;
    nrep(&B, NULL, "henry", 50, 0, 0, &r);
    nrep(&B, NULL, "gilda", 0, 90, 0, &r);
    nrep(&B, NULL, "ike", 0, -60, 0, &r);
    breq(&B, "henry", 1, &r);
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), 1); /* ike is in range but did not ask */
    ck_assert_str_eq(nth(&r, "BRS_RANGE_REPORT", 0), "vname=henry,range=50,id=03,time=1");
    /* 24.8's pulls: a node pull lets gilda hear, a beacon pull extends henry's reach */
    static const char *const cfg8[] = { "reach_distance", "default = 10", "node_pull_dist", "default = 0",
                                        "ping_wait", "0", "beacon", "x=0,y=0,label=03,report_range=80,pull_dist=45",
                                        NULL };
    brs_start(&B, cfg8, 0);
    r.n = 0;
    nrep(&B, NULL, "henry", 50, 0, 0, &r);
    nrep(&B, NULL, "gilda", 0, 90, 0, &r);
    breq(&B, "henry", 1, &r);
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), 1);
    ck_assert_uint_eq(B.node[1].too_far, 0);
}
END_TEST

/* 10.5.8, 10.5.9: report variables and ground truth */
START_TEST(brs_report_vars_ground_truth)
{
    const char *modes[] = { "short", "long", "both" };
    int want_s[] = { 1, 0, 1 }, want_l[] = { 0, 1, 1 };
    for (int m = 0; m < 3; m++) {
        const char *cfg[] = { "report_vars", modes[m], "ground_truth", "true", "rn_algorithm", "uniform,pct=0.12",
                              "ping_wait", "0", "reach_distance", "nolimit", "beacon", "x=0,y=0,label=01,report_range=nolimit", NULL };
        rec r = { 0 };
        brs_start(&B, cfg, 0);
        nrep(&B, NULL, "indigo", 300, 400, 0, &r);
        breq(&B, "indigo", 1, &r);
        ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), want_s[m]);
        ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT_INDIGO"), want_l[m]);
        ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT_GT"), want_s[m]);
        ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT_GT_INDIGO"), want_l[m]);
        const char *gt = want_s[m] ? nth(&r, "BRS_RANGE_REPORT_GT", 0) : nth(&r, "BRS_RANGE_REPORT_GT_INDIGO", 0);
        const char *rp = want_s[m] ? nth(&r, "BRS_RANGE_REPORT", 0) : nth(&r, "BRS_RANGE_REPORT_INDIGO", 0);
        ck_assert_double_eq_tol(num(gt, "range"), 500, 1e-9);
        ck_assert(fabs(num(rp, "range") - 500) <= 0.12 * 500 + 1e-9);
        ck_assert(fabs(num(rp, "range") - 500) > 1e-6); /* noisy */
        if (want_l[m]) ck_assert_str_eq(nth(&r, "BRS_RANGE_REPORT_GT_INDIGO", 0), "range=500,id=01,time=1");
        /* 24.8 upper-cases the name for the long form first: the short GT report of "both" */
        if (m == 2) ck_assert_str_eq(nth(&r, "BRS_RANGE_REPORT_GT", 0), "vname=INDIGO,range=500,id=01,time=1");
        if (m == 0) ck_assert_str_eq(nth(&r, "BRS_RANGE_REPORT_GT", 0), "vname=indigo,range=500,id=01,time=1");
    }
    /* ground truth without noise: none (24.8 posts it only with an rn_algorithm) */
    const char *cfg0[] = { "ground_truth", "true", "rn_uniform_pct", "0.5", "ping_wait", "0", "reach_distance", "nolimit",
                           "beacon", "x=0,y=0,label=01,push_dist=nolimit", NULL };
    rec r = { 0 };
    brs_start(&B, cfg0, 0);
    nrep(&B, NULL, "indigo", 300, 400, 0, &r);
    breq(&B, "indigo", 1, &r);
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT_GT"), 0);
    ck_assert_str_eq(nth(&r, "BRS_RANGE_REPORT", 0), "vname=indigo,range=500,id=01,time=1"); /* pct alone: no noise */
}
END_TEST

/* 10.5.10 to 10.5.12: unsolicited reports */
START_TEST(brs_unsolicited)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, wrn };
    brs_start(&B, listing24, 0);
    nrep(&B, NULL, "indigo", 10, 10, 0, &r);
    for (double t = 0; t < 1000; t += 0.25) (void)kelp_beaconrange_iterate(&B, t, &sink);
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), 0); /* never */
    static const char *const cfg[] = { "ping_wait", "0", "reach_distance", "default = nolimit",
                                       "beacon", "x=0,y=0,label=01", "beacon", "x=0,y=0,label=02,freq=90", NULL };
    brs_start(&B, cfg, 0);
    r.n = 0;
    nrep(&B, NULL, "indigo", 10, 10, 0, &r);
    nrep(&B, NULL, "ike", 20, 10, 0, &r);
    (void)kelp_beaconrange_iterate(&B, 0, &sink);
    ck_assert_int_eq(count(&r, "VIEW_MARKER"), 2);
    (void)kelp_beaconrange_iterate(&B, 90, &sink); /* 24.8: more than freq after the stamp */
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), 0);
    ck_assert_uint_eq(kelp_beaconrange_iterate(&B, 90.25, &sink), 2); /* both vehicles */
    ck_assert_str_eq(nth(&r, "BRS_RANGE_REPORT", 0), "vname=ike,range=22.3607,id=02,time=90.25");
    ck_assert(strstr(nth(&r, "VIEW_RANGE_PULSE", 0), "label=02,edge_color=pink") != NULL);
    breq(&B, "indigo", 100, &r); /* solicited at 100: the next unsolicited after 190 */
    ck_assert_uint_eq(kelp_beaconrange_iterate(&B, 190, &sink), 0);
    ck_assert_uint_eq(kelp_beaconrange_iterate(&B, 190.25, &sink), 2);
    /* 60:120: every interval in [60,120], and not all the same */
    static const char *const cfg2[] = { "default_beacon_freq", "60:120", "beacon", "x=0,y=0,label=01", NULL };
    brs_start(&B, cfg2, 0);
    r.n = 0;
    nrep(&B, NULL, "indigo", 10, 10, 0, &r);
    double last = 0, lo = 1e9, hi = 0;
    int posts = 0;
    for (double t = 0; t < 20000; t += 0.5)
        if (kelp_beaconrange_iterate(&B, t, &sink) > 0) {
            double d = t - last;
            lo = d < lo ? d : lo;
            hi = d > hi ? d : hi;
            last = t;
            posts++;
        }
    ck_assert_int_gt(posts, 150);
    ck_assert(lo >= 60 && hi <= 120.5 && hi - lo > 30);
    /* freq <= 0 is never (A84) */
    static const char *const cfg3[] = { "default_beacon_freq", "0", "beacon", "x=0,y=0,label=01", NULL };
    brs_start(&B, cfg3, 0);
    r.n = 0;
    nrep(&B, NULL, "indigo", 10, 10, 0, &r);
    for (double t = 0; t < 100; t += 0.25) (void)kelp_beaconrange_iterate(&B, t, &sink);
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), 0);
}
END_TEST

/* 10.5.13 to 10.5.15: labels, markers, unknown requester; bad config and mail */
START_TEST(brs_beacons_markers)
{
    static const char *const cfg[] = { "default_beacon_color", "orange", "default_beacon_shape", "circle",
                                       "default_beacon_width", "4", "beacon", "label=01, x=200, y=0",
                                       "beacon", "label=02, x=400, y=-200", "beacon", "label=03, x=0, y=-200",
                                       "beacon", "label=02, x=401, y=-200", "beacon", "x=5, y=5", NULL };
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, wrn };
    brs_start(&B, cfg, 0);
    ck_assert_uint_eq(B.nbeacons, 4);
    (void)kelp_beaconrange_iterate(&B, 0, &sink);
    ck_assert_int_eq(count(&r, "VIEW_MARKER"), 4);
    /* 24.8's XYMarker spec: no label */
    ck_assert_str_eq(nth(&r, "VIEW_MARKER", 0), "x=5,y=5,width=4,primary_color=orange,type=circle");
    ck_assert_str_eq(nth(&r, "VIEW_MARKER", 1), "x=0,y=-200,width=4,primary_color=orange,type=circle");
    ck_assert_str_eq(nth(&r, "VIEW_MARKER", 2), "x=401,y=-200,width=4,primary_color=orange,type=circle");
    ck_assert_str_eq(nth(&r, "VIEW_MARKER", 3), "x=200,y=0,width=4,primary_color=orange,type=circle");
    (void)kelp_beaconrange_iterate(&B, 1, &sink);
    ck_assert_int_eq(count(&r, "VIEW_MARKER"), 4); /* once */
    char buf[2048];
    ck_assert_int_eq(kelp_beaconrange_summary(&B, buf, sizeof buf), 0);
    ck_assert(strstr(buf, "SRS Model - # Beacons: 4\n  [0]:x=5,y=5,width=4,") != NULL);
    ck_assert(strstr(buf, "Default Beacon Color: orange\nDefault Beacon Shape: circle\nDefault Beacon Width: 4\n"));
    /* beacon_order = config */
    static const char *const cfgc[] = { "beacon_order", "config", "beacon", "label=01, x=200, y=0",
                                        "beacon", "label=02, x=400, y=-200", NULL };
    brs_start(&B, cfgc, 0);
    ck_assert_str_eq(B.beacon[0].label, "01");
    /* unknown requester, or vname= (24.8 reads name= only): refused, nothing posted, warned
     * "Failed Range Request: Unknown vehicle[..]" and "Bad Mail" */
    brs_start(&B, listing24, 0);
    nrep(&B, NULL, "indigo", 0, 0, 1, &r);
    r.n = r.warns = 0;
    ck_assert_int_lt(kelp_beaconrange_mail(&B, "BRS_RANGE_REQUEST", true, "name=nobody", 100, &sink), 0);
    ck_assert_str_eq(last_warn, "Bad Mail: BRS_RANGE_REQUEST");
    ck_assert_int_lt(kelp_beaconrange_mail(&B, "BRS_RANGE_REQUEST", true, "vname=indigo", 100, &sink), 0);
    ck_assert_int_eq(r.n, 0);
    ck_assert_int_eq(r.warns, 4);
    /* bad mail: a warning, no crash, state kept */
    ck_assert_int_lt(kelp_beaconrange_mail(&B, "BRS_RANGE_REQUEST", true, "garbage", 1, &sink), 0);
    ck_assert_int_lt(kelp_beaconrange_mail(&B, "NODE_REPORT", true, "NAME=x", 1, &sink), 0);
    ck_assert_int_lt(kelp_beaconrange_mail(&B, "NODE_REPORT", false, NULL, 1, &sink), 0);
    ck_assert_int_eq(kelp_beaconrange_mail(&B, "OTHER", true, "x", 1, &sink), 0);
    ck_assert_uint_eq(B.nbeacons, 3);
    /* config errors and warnings */
    kelp_beaconrange_cfg c;
    kelp_beaconrange_cfg_default(&c);
    kelp_diag why = { 0 };
    ck_assert_int_lt(kelp_beaconrange_config(&c, "beacon", "y=3, label=01", &why), 0); /* no x */
    ck_assert_int_lt(kelp_beaconrange_config(&c, "beacon", "x=1,y=3,freq=9:3", &why), 0);
    ck_assert_int_lt(kelp_beaconrange_config(&c, "ping_payments", "sometimes", &why), 0);
    ck_assert_int_lt(kelp_beaconrange_config(&c, "rn_algorithm", "pink", &why), 0);
    ck_assert_int_eq(kelp_beaconrange_config(&c, "beacon", "x=1,y=3,query_range=40", &why), 2); /* A52 */
    ck_assert_int_eq(kelp_beaconrange_config(&c, "ping_wait", "henry = 120;", &why), 1);
    ck_assert_double_eq(kelp_rangesense_vmap_get(&c.com.ping_wait, "HENRY"), 120);
    ck_assert_double_eq(kelp_rangesense_vmap_get(&c.com.ping_wait, "ike"), 30);
    ck_assert_int_eq(kelp_beaconrange_config(&c, "default beacon_color", "blue", &why), 1);
    ck_assert_str_eq(c.dflt.color, "blue");
    ck_assert_int_eq(kelp_beaconrange_config(&c, "nonsense", "1", &why), 0);
}
END_TEST

/* ------------------------------------------------------------------ contact */

static void crs_start(const char *const *lines, double start)
{
    kelp_contactrange_cfg c;
    kelp_contactrange_cfg_default(&c);
    for (; *lines; lines += 2) {
        kelp_diag why = { 0 };
        int rc = kelp_contactrange_config(&c, lines[0], lines[1], &why);
        ck_assert_msg(rc == 1, "%s = %s: %s", lines[0], lines[1], kelp_diag_text(&why));
    }
    kelp_contactrange_init(&C, &c, start);
}

static void creq(const char *name, double now, rec *r)
{
    char s[64];
    kelp_field_sink sink = { r, pub, wrn };
    snprintf(s, sizeof s, "name=%s", name);
    ck_assert_int_eq(kelp_contactrange_mail(&C, "CRS_RANGE_REQUEST", true, s, now, &sink), 1);
}

/* kelp's ECHO_FALLOFF = false: no echo beyond reach + reply (24.8's chance: crs_echo_falloff) */
static const char *const none[] = { "ping_wait", "0", "echo_falloff", "false", NULL };

/* 11.5.1 to 11.5.5: reach + reply */
START_TEST(crs_reach_reply)
{
    rec r = { 0 };
    crs_start(none, 0);
    nrep(NULL, &C, "archie", 0, 0, 0, &r);
    nrep(NULL, &C, "jackal", 150, 0, 0, &r);
    creq("archie", 1, &r);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT"), 1);
    ck_assert_str_eq(nth(&r, "CRS_RANGE_REPORT", 0), "vname=archie,range=150,target=jackal,time=1");
    nrep(NULL, &C, "jackal", 250, 0, 2, &r);
    r.n = 0;
    creq("archie", 3, &r);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT"), 0);
    ck_assert_int_eq(count(&r, "VIEW_RANGE_PULSE"), 1); /* accepted: the ping pulse */
    static const char *const c3[] = { "ping_wait", "0", "reach_distance", "default = 120", "reply_distance",
                                      "default = 80.01", "echo_falloff", "false", NULL };
    crs_start(c3, 0);
    r.n = 0;
    nrep(NULL, &C, "archie", 0, 0, 0, &r);
    nrep(NULL, &C, "jackal", 200, 0, 0, &r);
    creq("archie", 1, &r);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT"), 1);
    static const char *const c4[] = { "ping_wait", "0", "push_dist", "victor = 250", "pull_dist", "victor = 20",
                                      "echo_falloff", "false", NULL };
    crs_start(c4, 0);
    r.n = 0;
    nrep(NULL, &C, "victor", 0, 0, 0, &r);
    nrep(NULL, &C, "jackal", 340, 0, 0, &r);
    creq("victor", 1, &r);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT"), 1);
    nrep(NULL, &C, "jackal", 130, 0, 2, &r);
    r.n = 0;
    creq("jackal", 3, &r);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT"), 0);
    static const char *const c5[] = { "ping_wait", "0", "reach_distance", "default = nolimit", NULL };
    crs_start(c5, 0);
    r.n = 0;
    nrep(NULL, &C, "a", 0, 0, 0, &r);
    nrep(NULL, &C, "b", 1e5, 0, 0, &r);
    nrep(NULL, &C, "c", -1e5, 0, 0, &r);
    creq("a", 1, &r);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT"), 2);
}
END_TEST

/* 11.5.6, 11.5.11: the Hugo log's accept/deny pattern; per-vehicle ping wait */
START_TEST(crs_ping_wait)
{
    rec r = { 0 };
    crs_start((const char *const[]){ NULL }, 0);
    nrep(NULL, &C, "archie", 0, 0, 0, &r);
    const double t[] = { 76.758, 104.761, 130.417, 163.599, 190.192, 216.311, 245.493, 273.729 };
    const char *want = "ADAADADA";
    for (int i = 0; i < 8; i++) {
        unsigned long a = C.accepted;
        creq("archie", t[i], &r);
        ck_assert_msg((C.accepted > a) == (want[i] == 'A'), "request %d at %g", i, t[i]);
    }
    static const char *const c11[] = { "ping_wait", "henry = 90", NULL };
    crs_start(c11, 0);
    nrep(NULL, &C, "henry", 0, 0, 0, &r);
    nrep(NULL, &C, "ike", 0, 0, 0, &r);
    creq("henry", 100, &r);
    creq("henry", 160, &r);
    creq("ike", 100, &r);
    creq("ike", 131, &r);
    ck_assert_uint_eq(C.accepted, 3);
    ck_assert_uint_eq(C.denied, 1);
}
END_TEST

/* 11.5.7 to 11.5.10, 11.5.12: the report, GT, pulses, long names, unknown requester */
START_TEST(crs_reports_pulses)
{
    static const char *const c7[] = { "ping_wait", "0", "ground_truth", "true", "rn_algorithm", "uniform,pct=0.04",
                                      "reach_distance", "default = nolimit", NULL };
    rec r = { 0 };
    crs_start(c7, 0);
    nrep(NULL, &C, "archie", -49.31, -38.86, 0, &r);
    nrep(NULL, &C, "jackal", -187.67, -144.6, 0, &r);
    creq("archie", 23588509131.764, &r);
    ck_assert_str_eq(nth(&r, "CRS_RANGE_REPORT_GT", 0), "vname=archie,range=174.1391,target=jackal,time=23588509131.764");
    double v = num(nth(&r, "CRS_RANGE_REPORT", 0), "range");
    ck_assert(v >= 167.1735 && v <= 181.1047);
    ck_assert_str_eq(nth(&r, "VIEW_RANGE_PULSE", 0), "x=-49.31,y=-38.86,radius=50,fill=0.9,label=archie_ping,"
                                                     "edge_color=white,fill_color=white,time=23588509131.76,duration=6,edge_size=1");
    ck_assert_str_eq(nth(&r, "VIEW_RANGE_PULSE", 1), "x=-187.67,y=-144.6,radius=40,fill=0.9,label=jackal_echo,"
                                                     "edge_color=chartreuse,fill_color=chartreuse,time=23588509131.76,"
                                                     "duration=15,edge_size=1");
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT_JACKAL"), 0); /* only the requester */
    const double pairs[][5] = { { -141.97, -94.55, -191.18, -215.82, 130.8741 },
                                { -197.98, -128.86, -161.42, -250.59, 127.1016 },
                                { -168.48, -226, -112.19, -306.23, 98.0072 },
                                { -125.38, -332.68, -39.7, -325.58, 85.9737 } };
    for (int i = 0; i < 4; i++) {
        r.n = 0;
        nrep(NULL, &C, "archie", pairs[i][0], pairs[i][1], i + 1, &r);
        nrep(NULL, &C, "jackal", pairs[i][2], pairs[i][3], i + 1, &r);
        creq("archie", 23588509131.764 + i + 1, &r);
        ck_assert_double_eq_tol(num(nth(&r, "CRS_RANGE_REPORT_GT", 0), "range"), pairs[i][4], 1e-9);
    }
    static const char *const c9[] = { "ping_wait", "0", "ground_truth", "true", "rn_algorithm", "uniform,pct=0",
                                      "report_vars", "long", NULL };
    crs_start(c9, 0);
    r.n = 0;
    nrep(NULL, &C, "archie", 0, 0, 0, &r);
    nrep(NULL, &C, "jackal", 30, 40, 0, &r);
    creq("archie", 1, &r);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT"), 0);
    ck_assert_str_eq(nth(&r, "CRS_RANGE_REPORT_ARCHIE", 0), "range=50,target=jackal,time=1");
    ck_assert_str_eq(nth(&r, "CRS_RANGE_REPORT_GT_ARCHIE", 0), "range=50,target=jackal,time=1");
    r.n = r.warns = 0;
    kelp_field_sink sk = { &r, pub, wrn };
    ck_assert_int_lt(kelp_contactrange_mail(&C, "CRS_RANGE_REQUEST", true, "name=ghost", 2, &sk), 0);
    ck_assert_int_eq(r.n, 0); /* refused, answered by nothing */
    ck_assert_int_eq(r.warns, 2);
    ck_assert_str_eq(last_warn, "Bad Mail: CRS_RANGE_REQUEST");
    /* 24.8: allowed echo types, ignored group, sensor arcs, no pulses */
    static const char *const c24[] = { "ping_wait", "0", "allow_echo_types", "kayak", "display_pulses", "false", NULL };
    crs_start(c24, 0);
    r.n = 0;
    nrep(NULL, &C, "archie", 0, 0, 0, &r);
    nrep(NULL, &C, "jackal", 30, 40, 0, &r); /* a UUV */
    creq("archie", 1, &r);
    ck_assert_int_eq(r.n, 0);
    static const char *const carc[] = { "ping_wait", "0", "sensor_arc", "45:135", NULL };
    crs_start(carc, 0);
    r.n = 0;
    nrep(NULL, &C, "archie", 0, 0, 0, &r);  /* heading 90 */
    nrep(NULL, &C, "jackal", 0, 50, 0, &r); /* bearing 0: relative 270 */
    nrep(NULL, &C, "kilo", 50, 0, 0, &r);   /* bearing 90: relative 0 */
    nrep(NULL, &C, "lima", 0, -50, 0, &r);  /* bearing 180: relative 90 */
    creq("archie", 1, &r);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT"), 1);
    ck_assert(strstr(nth(&r, "CRS_RANGE_REPORT", 0), "target=lima") != NULL);
    kelp_contactrange_cfg cc;
    kelp_contactrange_cfg_default(&cc);
    kelp_diag why = { 0 };
    /* 24.8 has no ignore_group (an unhandled line): the vehicle stays */
    ck_assert_int_eq(kelp_contactrange_config(&cc, "ignore_group", "red", &why), 0);
    kelp_contactrange_init(&C, &cc, 0);
    kelp_field_sink sink = { &r, pub, wrn };
    ck_assert_int_eq(kelp_contactrange_mail(&C, "NODE_REPORT", true, "NAME=a,X=1,Y=2,GROUP=red", 0, &sink), 1);
    ck_assert_uint_eq(C.nnodes, 1);
    ck_assert_int_lt(kelp_contactrange_config(&cc, "sensor_arc", "45", &why), 0);
    ck_assert_int_lt(kelp_contactrange_config(&cc, "reach_distance", "far", &why), 0);
    char buf[2048];
    ck_assert_int_eq(kelp_contactrange_summary(&C, buf, sizeof buf), 0);
    ck_assert(strstr(buf, "Default Reach Distance: 100\nDefault Reply Distance: 100\nDefault Ping Wait: 30\n"));
}
END_TEST


/* 24.8's rules of a request: a too-frequent one is warned; events as 24.8 reports them; the
 * AppCast's beacon and vehicle tables */
static char events[16][128];
static int nevents;

static void event_log(void *ctx, const char *line)
{
    (void)ctx;
    if (nevents < 16) snprintf(events[nevents++], sizeof events[0], "%s", line);
}

START_TEST(brs_request_warnings_and_table)
{
    static const char *const cfg[] = { "ping_payments", "upon_accept", "node_push_dist", "default = nolimit",
                                       "ping_wait", "default = 10", "default_beacon_push_dist", "100",
                                       "default_beacon_pull_dist", "100", "beacon", "label=01, x=200, y=0",
                                       "beacon", "label=03, x=0, y=-200, push_dist=20", NULL };
    kelp_beaconrange_cfg c;
    brs_cfg(&c, cfg);
    c.com.log = event_log;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_beaconrange_init(&B, &c, 0, &why), 0);
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, wrn };
    nevents = 0;
    nrep(&B, NULL, "indigo", 23.76, 0, 5, &r);
    breq(&B, "indigo", 5, &r);
    ck_assert_str_eq(events[0], "Valid Range Req from indigo. Checking beacon ranges...");
    ck_assert_str_eq(events[1], "Beacon[03]  <----  Ping from indigo");
    ck_assert_str_eq(events[2], "Beacon[01]  <----  Ping from indigo");
    ck_assert_str_eq(events[3], "Beacon[01]    -->  Range Reply to indigo");
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), 1);
    breq(&B, "indigo", 10, &r);
    ck_assert_str_eq(last_warn, "Failed Range Req from indigo: exceeds query freq.");
    ck_assert_int_lt(kelp_beaconrange_mail(&B, "BRS_RANGE_REQUEST", true, "name=zed", 11, &sink), 0);
    char buf[2048];
    ck_assert_int_eq(kelp_beaconrange_report(&B, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "Beacons(2):\n"
                          "                     Pings  Pings  Pings         Push  Pull\n"
                          "ID    X     Y  Freq  Unsol  Recvd  Gen'd  Noise  Dist  Dist\n"
                          "--  ---  ----  ----  -----  -----  -----  -----  ----  ----\n"
                          "03    0  -200  poll  0      1      0      0      20    100\n"
                          "01  200     0  poll  0      1      1      0      100   100\n"
                          "\n"
                          "Vehicles(1):\n"
                          "        Push  Pull  Unsol  Pings  Pings  Too   Too\n"
                          "VName   Dist  Dist  Rec'd  Gen'd  Rep'd  Freq  Far\n"
                          "------  ----  ----  -----  -----  -----  ----  ---\n"
                          "indigo  inf   100   0      2      1      1     1\n"
                          "\n"
                          "Ledger: now:1, reps:1, who:indigo\n");
}
END_TEST

/* 24.8's draws in order: a freq'd beacon's broadcast stamps (one interval draw) before its
 * reports (one noise draw each, vehicles in name order); values as rand() after srand(1) */
START_TEST(brs_glibc_unsolicited_order)
{
    static const char *const cfg[] = { "rand_mode", "glibc", "rn_algorithm", "uniform,pct=0.1",
                                       "default_beacon_push_dist", "nolimit", "beacon", "x=0,y=0,label=01,freq=50", NULL };
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, wrn };
    brs_start(&B, cfg, 0);
    nrep(&B, NULL, "bob", 0, 30, 0, &r);
    nrep(&B, NULL, "al", 0, 40, 0, &r);
    (void)kelp_beaconrange_iterate(&B, 0, &sink); /* the first stamp: draw 2 */
    srand(1);
    (void)rand();
    double period = 50; /* freq 50: 50 + pct x 0 */
    (void)rand();
    ck_assert_uint_eq(kelp_beaconrange_iterate(&B, period, &sink), 0);
    ck_assert_uint_eq(kelp_beaconrange_iterate(&B, period + 0.25, &sink), 2);
    (void)rand(); /* the new stamp's draw comes first */
    double w_al = 40 + (((double)(rand() % 10000) / 5000) - 1) * 0.1 * 40;
    double w_bob = 30 + (((double)(rand() % 10000) / 5000) - 1) * 0.1 * 30;
    ck_assert(strncmp(nth(&r, "BRS_RANGE_REPORT", 0), "vname=al,", 9) == 0);
    ck_assert_double_eq_tol(num(nth(&r, "BRS_RANGE_REPORT", 0), "range"), w_al, 1e-4);
    ck_assert_double_eq_tol(num(nth(&r, "BRS_RANGE_REPORT", 1), "range"), w_bob, 1e-4);
    ck_assert_uint_eq(B.rand.draws, 5);
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT_GT"), 2); /* noise and ground_truth (24.8's default true) */
}
END_TEST

/* 24.8's echo beyond push + pull: one draw per such target, heard with probability
 * exp(3 (max - r) / max); within, strictly less than max, no draw */
START_TEST(crs_echo_falloff)
{
    static const char *const cfg[] = { "ping_wait", "0", "rand_mode", "glibc", NULL };
    rec r = { 0 };
    crs_start(cfg, 0);
    nrep(NULL, &C, "archie", 0, 0, 0, &r);
    nrep(NULL, &C, "gilda", 250, 0, 0, &r); /* max 200: p = exp(-0.75) */
    int heard = 0;
    srand(1);
    int want = 0;
    for (int i = 0; i < 2000; i++) {
        unsigned long before = C.reports;
        creq("archie", i + 1, &r);
        heard += C.reports > before;
        want += ((double)(rand() % 10000) / 10000) <= exp(-0.75);
    }
    ck_assert_int_eq(heard, want);
    ck_assert_uint_eq(C.rand.draws, 2000);
    ck_assert(fabs(heard / 2000.0 - exp(-0.75)) < 0.04);
    /* at exactly push + pull: not surely heard (24.8 compares strictly), one draw */
    nrep(NULL, &C, "gilda", 200, 0, 3000, &r);
    creq("archie", 3001, &r);
    ck_assert_uint_eq(C.rand.draws, 2001);
    /* 24.8's clock starts at 0: the first ping is honoured even right after the start */
    crs_start((const char *const[]){ NULL }, 100);
    nrep(NULL, &C, "archie", 0, 0, 100, &r);
    creq("archie", 101, &r);
    ck_assert_uint_eq(C.accepted, 1);
    creq("archie", 130, &r);
    ck_assert_uint_eq(C.accepted, 1);
}
END_TEST

START_TEST(crs_appcast_table)
{
    static const char *const cfg[] = { "push_distance", "archie = 190", "ping_wait", "archie = 32",
                                       "rn_gaussian_sigma", "50", NULL };
    rec r = { 0 };
    crs_start(cfg, 0);
    const double at[2][2] = { { -185.91, -155.84 }, { -59.5, -40 } }; /* the recording's t=5 */
    nrep(NULL, &C, "jackal", at[0][0], at[0][1], 0, &r);
    nrep(NULL, &C, "archie", at[1][0], at[1][1], 0, &r);
    for (int k = 0; k < 2; k++) creq("archie", 5 + 10 * k, &r);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT"), 1);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT_GT"), 0); /* rn_gaussian_sigma alone: no noise */
    char buf[2048];
    ck_assert_int_eq(kelp_contactrange_report(&C, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "Default Ping Wait:        30\n"
                          "Random Noise Algorithm:   \n"
                          "Random Noise Uniform Pct: 0\n"
                          "Gaussian Noise:           50\n"
                          "Ping Color:               white\n"
                          "Echo Color:               chartreuse\n"
                          "Ground Truth Reporting:   true\n"
                          "Ignore Group:             \n"
                          "Total Node Reports:       2\n"
                          "\n"
                          "Vehicles(2):\n"
                          "        Ping  Push  Pull  Pings  Echos  Too   Too  Echos  Pos\n"
                          "VName   Wait  Dist  Dist  Gen'd  Rec'd  Freq  Far  Sent\n"
                          "------  ----  ----  ----  -----  -----  ----  ---  -----  -------------\n"
                          "archie  32    190   100   2      1      1     0    0      -59.5,-40.0\n"
                          "jackal  30    100   100   0      0      0     0    1      -185.9,-155.8\n");
}
END_TEST

/* ------------------------------------------------------------------ noise and draws */

static void stats(bool glibc, kelp_rangesense_noise_alg alg, double par, double *mean, double *sd, double *lo, double *hi)
{
    kelp_rangesense_rand rr;
    kelp_rangesense_rand_init(&rr, glibc, 12345);
    kelp_rangesense_noise n = { alg, par, par };
    double s = 0, s2 = 0;
    *lo = 1e300;
    *hi = -1e300;
    for (int i = 0; i < 10000; i++) {
        double v = kelp_rangesense_noisy(&rr, &n, 100.0);
        s += v;
        s2 += v * v;
        *lo = v < *lo ? v : *lo;
        *hi = v > *hi ? v : *hi;
    }
    *mean = s / 10000;
    *sd = sqrt(s2 / 10000 - *mean * *mean);
}

START_TEST(noise_statistics)
{
    for (int g = 0; g < 2; g++) {
        double m, sd, lo, hi;
        stats(g, KELP_RSENSE_NOISE_UNIFORM, 0.1, &m, &sd, &lo, &hi); /* U(90, 110): sd 10/sqrt(3) */
        ck_assert(lo >= 90 && hi <= 110);
        ck_assert(lo < 90.2 && hi > 109.8);
        ck_assert_double_eq_tol(m, 100, 0.25);
        ck_assert_double_eq_tol(sd, 10 / sqrt(3.0), 0.15);
        stats(g, KELP_RSENSE_NOISE_GAUSSIAN, 2.0, &m, &sd, &lo, &hi);
        ck_assert_double_eq_tol(m, 100, 0.08);
        ck_assert_double_eq_tol(sd, 2.0, 0.08);
    }
}
END_TEST

/* glibc mode: rand()'s values after srand(1), MOOS-IvP's arithmetic, one draw per value */
START_TEST(glibc_draws_match_rand)
{
    kelp_rangesense_rand rr;
    kelp_rangesense_rand_init(&rr, true, 99);
    kelp_rangesense_noise n = { KELP_RSENSE_NOISE_UNIFORM, 0.12, 0 };
    srand(1);
    for (int i = 0; i < 1000; i++) {
        double want = 250.0 + (((double)(rand() % 10000) / 5000) - 1) * 0.12 * 250.0;
        ck_assert_double_eq(kelp_rangesense_noisy(&rr, &n, 250.0), want);
        double iv = 60 + ((double)(rand() % 1000) / 1000) * 60;
        ck_assert_double_eq(kelp_rangesense_interval(&rr, 60, 120), iv);
    }
    ck_assert_uint_eq(rr.draws, 2000);
    /* gaussian: the polar method on rand()/RAND_MAX, second deviate cached */
    kelp_rangesense_rand_init(&rr, true, 0);
    kelp_rangesense_noise gn = { KELP_RSENSE_NOISE_GAUSSIAN, 0, 1.5 };
    srand(1);
    for (int i = 0; i < 200; i++) {
        double v1, v2, s;
        do {
            v1 = 2.0 * ((double)rand() / RAND_MAX) - 1;
            v2 = 2.0 * ((double)rand() / RAND_MAX) - 1;
            s = v1 * v1 + v2 * v2;
        } while (s > 1 || s == 0);
        double fac = sqrt(-2 * log(s) / s);
        ck_assert_double_eq_tol(kelp_rangesense_noisy(&rr, &gn, 10), 10 + v2 * fac * 1.5, 1e-12);
        ck_assert_double_eq_tol(kelp_rangesense_noisy(&rr, &gn, 10), 10 + v1 * fac * 1.5, 1e-12);
    }
    /* the beacon sensor in glibc mode: a freq'd beacon draws at config, at the first
     * iteration, and on each reply; each report one noise value */
    static const char *const cfg[] = { "rand_mode", "glibc", "beacon_order", "config", "rn_algorithm",
                                       "uniform,pct=0.1", "ping_wait", "0", "reach_distance", "default = nolimit",
                                       "default_beacon_report_range", "nolimit", "beacon", "x=0,y=0,label=01,freq=50",
                                       "beacon", "x=100,y=0,label=02", NULL };
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, wrn };
    brs_start(&B, cfg, 0);
    ck_assert_uint_eq(B.rand.draws, 1);
    (void)kelp_beaconrange_iterate(&B, 0, &sink);
    ck_assert_uint_eq(B.rand.draws, 2);
    nrep(&B, NULL, "v", 0, 50, 0, &r);
    breq(&B, "v", 1, &r);
    ck_assert_uint_eq(B.rand.draws, 5); /* 01: noise, timer; 02: noise */
    srand(1);
    for (int i = 0; i < 2; i++) (void)rand();
    double w1 = 50 + (((double)(rand() % 10000) / 5000) - 1) * 0.1 * 50;
    (void)rand();
    double w2 = hypot(100, 50);
    w2 += (((double)(rand() % 10000) / 5000) - 1) * 0.1 * w2;
    ck_assert_double_eq_tol(num(nth(&r, "BRS_RANGE_REPORT", 0), "range"), w1, 1e-4);
    ck_assert_double_eq_tol(num(nth(&r, "BRS_RANGE_REPORT", 1), "range"), w2, 1e-4);
}
END_TEST

/* 24.8's ledger keys vehicles by their reported name (ContactLedger::hasVName is a map
 * lookup): a request from "INDIGO" when "indigo" reports is an unknown vehicle, refused with
 * both run warnings and answered by nothing (brs_n1_uniform: "Unknown vehicle[INDIGO]") */
START_TEST(request_name_exact)
{
    static const char *const cfg[] = { "node_push_dist", "default = nolimit", "beacon", "label=01, x=200, y=0", NULL };
    brs_start(&B, cfg, 0);
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, wrn };
    nrep(&B, NULL, "indigo", 150, 0, 1, &r);
    int w = r.warns;
    ck_assert_int_lt(kelp_beaconrange_mail(&B, "BRS_RANGE_REQUEST", true, "name=INDIGO", 2, &sink), 0);
    ck_assert_int_eq(r.warns - w, 2);
    ck_assert_str_eq(last_warn, "Bad Mail: BRS_RANGE_REQUEST");
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), 0);
    ck_assert_uint_eq(B.node[0].pings, 0);
    breq(&B, "indigo", 3, &r);
    ck_assert_int_eq(count(&r, "BRS_RANGE_REPORT"), 1);
    /* two vehicles whose names differ in case are two vehicles */
    nrep(&B, NULL, "Indigo", 160, 0, 4, &r);
    ck_assert_uint_eq(B.nnodes, 2);

    crs_start((const char *const[]){ NULL }, 0);
    nrep(NULL, &C, "archie", 0, 0, 0, &r);
    nrep(NULL, &C, "jackal", 10, 0, 0, &r);
    w = r.warns;
    ck_assert_int_lt(kelp_contactrange_mail(&C, "CRS_RANGE_REQUEST", true, "name=Archie", 1, &sink), 0);
    ck_assert_int_eq(r.warns - w, 2);
    ck_assert_uint_eq(C.accepted, 0);
}
END_TEST

/* ping_wait at its boundary: 24.8 stamps a request with its previous iteration's time and its
 * iterations run 0.2 % late, so a request scripted exactly ping_wait after the last paid one is
 * honoured (KELP_RSENSE_LATE); one 30 ms short of 10 s (0.3 %) is still too frequent */
START_TEST(ping_wait_boundary)
{
    static const char *const cfg[] = { "node_push_dist", "default = nolimit", "ping_wait", "default = 10",
                                       "ping_payments", "upon_accept", "beacon", "label=01, x=200, y=0", NULL };
    brs_start(&B, cfg, 0);
    rec r = { 0 };
    nrep(&B, NULL, "indigo", 150, 0, 1, &r);
    breq(&B, "indigo", 5.25, &r);
    breq(&B, "indigo", 15.2496, &r); /* 9.9996 s: kelp's on-time iteration just short of 10 */
    ck_assert_uint_eq(B.accepted, 2);
    breq(&B, "indigo", 25.2196, &r); /* 9.97 s */
    ck_assert_uint_eq(B.accepted, 2);
    ck_assert_str_eq(last_warn, "Failed Range Req from indigo: exceeds query freq.");

    static const char *const c2[] = { "ping_wait", "archie = 12", NULL };
    crs_start(c2, 0);
    nrep(NULL, &C, "archie", 0, 0, 0, &r);
    creq("archie", 5, &r);
    creq("archie", 16.9997, &r);
    ck_assert_uint_eq(C.accepted, 2);
    creq("archie", 28.95, &r); /* 11.95 s */
    ck_assert_uint_eq(C.accepted, 2);
    ck_assert_uint_eq(C.denied, 1);
}
END_TEST

/* 24.8's rn_algorithm takes "uniform" only: gaussian is an unhandled line and no noise
 * (brs_n2_gauss, crs_n2_gauss); kelp keeps its gaussian unless RAND_MODE = glibc */
START_TEST(gaussian_as_248)
{
    kelp_rangesense_common c;
    kelp_diag d = { 0 };
    kelp_rangesense_common_default(&c);
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "rn_algorithm", "gaussian,sigma=3", &d), 1);
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "rn_uniform_pct", "0.2", &d), 1);
    ck_assert(!kelp_rangesense_common_as_248(&c)); /* kelp mode: its own gaussian */
    ck_assert_int_eq(c.noise.alg, KELP_RSENSE_NOISE_GAUSSIAN);
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "RAND_MODE", "glibc", &d), 1);
    ck_assert(kelp_rangesense_common_as_248(&c));
    ck_assert_int_eq(c.noise.alg, KELP_RSENSE_NOISE_NONE);
    /* glibc mode set first: any algorithm but "uniform" (24.8 compares the word exactly) is not
     * a parameter (the app's unhandled-line warning) and a uniform line before it stays */
    kelp_rangesense_common_default(&c);
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "RAND_MODE", "glibc", &d), 1);
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "rn_algorithm", " uniform ,pct=0.1", &d), 1);
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "rn_algorithm", "gaussian", &d), 0);
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "rn_algorithm", "Uniform,pct=0.3", &d), 0);
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "rn_algorithm", "none", &d), 0);
    ck_assert(!kelp_rangesense_common_as_248(&c));
    ck_assert_int_eq(c.noise.alg, KELP_RSENSE_NOISE_UNIFORM);
    ck_assert(fabs(c.noise.pct - 0.1) < 1e-12);
    /* 24.8 reads the block last line first: the first fraction in the file is the one it keeps
     * (brs_n3_unsol: rn_algorithm = uniform,pct=0.05 then rn_uniform_pct = 0.25 drew with 0.05) */
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "rn_uniform_pct", "0.25", &d), 1);
    ck_assert(fabs(c.noise.pct - 0.1) < 1e-12);
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "rn_algorithm", "uniform,pct=0.3", &d), 1);
    ck_assert(fabs(c.noise.pct - 0.1) < 1e-12);
    kelp_rangesense_common_default(&c); /* kelp mode: the last line wins */
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "rn_algorithm", "uniform,pct=0.05", &d), 1);
    ck_assert_int_eq(kelp_rangesense_common_config(&c, "rn_uniform_pct", "0.25", &d), 1);
    ck_assert(fabs(c.noise.pct - 0.25) < 1e-12);
}
END_TEST

/* 24.8's ledger fixes types before the echo test reads them (ContactLedger::processNodeRecord):
 * "uuv" is "auv", an unknown or absent type is "ship"; an auv or glider with no depth is
 * refused (crs_n3_uniform: jackal, a uuv, never echoes for allow_echo_types = uuv,kayak,glider) */
static void crs_raw(const char *report, rec *r, int want)
{
    kelp_field_sink sink = { r, pub, wrn };
    if (want > 0) ck_assert_int_eq(kelp_contactrange_mail(&C, "NODE_REPORT", true, report, 1, &sink), 1);
    else ck_assert_int_lt(kelp_contactrange_mail(&C, "NODE_REPORT", true, report, 1, &sink), 0);
}

START_TEST(ledger_types)
{
    static const char *const cfg[] = { "ping_wait", "0", "allow_echo_types", "uuv,ship", "display_pulses", "false", NULL };
    crs_start(cfg, 0);
    rec r = { 0 };
    crs_raw("NAME=archie,TYPE=kayak,X=0,Y=0,SPD=0,HDG=0,DEP=0,TIME=1", &r, 1);
    crs_raw("NAME=jackal,TYPE=uuv,X=10,Y=0,SPD=0,HDG=0,DEP=0,TIME=1", &r, 1);  /* auv: not listed */
    crs_raw("NAME=boaty,TYPE=raft,X=20,Y=0,SPD=0,HDG=0,DEP=0,TIME=1", &r, 1);  /* ship */
    crs_raw("NAME=plain,X=30,Y=0,SPD=0,HDG=0,DEP=0,TIME=1", &r, 1);            /* no type: ship */
    int w = r.warns;
    crs_raw("NAME=gilda,TYPE=glider,X=5,Y=5,SPD=0,HDG=0,TIME=1", &r, -1);
    ck_assert_int_eq(r.warns - w, 1);
#ifndef KELP_NO_ERRMSG /* the ledger's reason is diagnostic text */
    ck_assert_ptr_nonnull(strstr(last_warn, "underwater vehicle type with no depth reported"));
#endif
    crs_raw("NAME=otto,TYPE=UUV,X=5,Y=5,SPD=0,HDG=0,TIME=1", &r, 1); /* "UUV" is not "uuv": kept, no depth needed */
    creq("archie", 2, &r);
    ck_assert_int_eq(count(&r, "CRS_RANGE_REPORT"), 3);
    ck_assert_ptr_null(strstr(r.val[0], "jackal"));
    for (int k = 0; k < 3; k++) ck_assert_ptr_null(strstr(nth(&r, "CRS_RANGE_REPORT", k), "target=jackal"));
}
END_TEST

/* 24.8's BeaconBuoy compares a freq range's two texts, not its numbers: "6:14" is refused
 * (brs_n3_unsol: default_beacon_freq = 6:14 left every beacon without one, "Unhandled config
 * line"), "5:8" taken; in glibc mode kelp refuses as 24.8 does, a beacon's own freq silently */
START_TEST(freq_text_order)
{
    kelp_beaconrange_cfg c;
    kelp_diag d = { 0 };
    kelp_beaconrange_cfg_default(&c);
    ck_assert_int_eq(kelp_beaconrange_config(&c, "default_beacon_freq", "6:14", &d), 1); /* kelp mode: numbers */
    ck_assert(c.dflt.freq_lo == 6 && c.dflt.freq_hi == 14);
    kelp_beaconrange_cfg_default(&c);
    ck_assert_int_eq(kelp_beaconrange_config(&c, "rand_mode", "glibc", &d), 1);
    ck_assert_int_eq(kelp_beaconrange_config(&c, "default_beacon_freq", "6:14", &d), 0);
    ck_assert(c.dflt.freq_lo < 0);
    ck_assert_int_eq(kelp_beaconrange_config(&c, "default_beacon_freq", "5:8", &d), 1);
    ck_assert_int_eq(kelp_beaconrange_config(&c, "beacon", "label=a, x=0, y=0, freq=20:100", &d), 1);
    ck_assert_int_eq(kelp_beaconrange_config(&c, "beacon", "label=b, x=9, y=0, freq=12:30", &d), 1);
    ck_assert_int_eq(kelp_beaconrange_init(&B, &c, 0, &d), 0);
    int ia = kelp_beaconrange_find(&B, "a"), ib = kelp_beaconrange_find(&B, "b");
    ck_assert(ia >= 0 && ib >= 0);
    ck_assert(B.beacon[ia].freq_lo == 5 && B.beacon[ia].freq_hi == 8); /* kept the default */
    ck_assert(B.beacon[ib].freq_lo == 12 && B.beacon[ib].freq_hi == 30);
}
END_TEST

Suite *kelp_field_rangesensors_suite(void)
{
    Suite *s = suite_create("field_rangesensors");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, brs_indigo_ranges);
    tcase_add_test(tc, brs_ping_payments);
    tcase_add_test(tc, brs_reach_and_report_range);
    tcase_add_test(tc, brs_report_vars_ground_truth);
    tcase_add_test(tc, brs_unsolicited);
    tcase_add_test(tc, brs_beacons_markers);
    tcase_add_test(tc, crs_reach_reply);
    tcase_add_test(tc, brs_request_warnings_and_table);
    tcase_add_test(tc, brs_glibc_unsolicited_order);
    tcase_add_test(tc, crs_echo_falloff);
    tcase_add_test(tc, crs_appcast_table);
    tcase_add_test(tc, crs_ping_wait);
    tcase_add_test(tc, crs_reports_pulses);
    tcase_add_test(tc, noise_statistics);
    tcase_add_test(tc, glibc_draws_match_rand);
    tcase_add_test(tc, request_name_exact);
    tcase_add_test(tc, ping_wait_boundary);
    tcase_add_test(tc, gaussian_as_248);
    tcase_add_test(tc, ledger_types);
    tcase_add_test(tc, freq_text_order);
    suite_add_tcase(s, tc);
    return s;
}
