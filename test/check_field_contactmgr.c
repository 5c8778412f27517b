/* pContactMgrV20's state machine (src/field/contactmgr.c): the testable behaviours of
 * shared/spec/contactmgr.md section 6 (numbers in the comments), through a recording sink. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/contactmgr.h>
#include <kelp/cpa.h>

#define REC_MAX 4096

typedef struct rec {
    int n, nwarn;
    char var[REC_MAX][64];
    char val[REC_MAX][KELP_CMGR_MAX_TEXT];
    bool str[REC_MAX];
    double d[REC_MAX];
    char warn[64][256];
} rec;

static rec *R;
static kelp_contactmgr *C;
static double NOW = 1000;

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    if (r->n >= REC_MAX) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    r->str[r->n] = is_string;
    r->d[r->n] = dval;
    if (is_string) snprintf(r->val[r->n], sizeof r->val[0], "%s", sval);
    else snprintf(r->val[r->n], sizeof r->val[0], "%g", dval);
    r->n++;
}

static void wrn(void *ctx, const char *msg)
{
    rec *r = ctx;
    if (r->nwarn < 64) snprintf(r->warn[r->nwarn++], sizeof r->warn[0], "%s", msg);
}

static kelp_field_sink S;

static const char *last(const char *var)
{
    for (int i = R->n; i-- > 0;)
        if (!strcmp(R->var[i], var)) return R->val[i];
    return NULL;
}

static int count(const char *var)
{
    int k = 0;
    for (int i = 0; i < R->n; i++) k += !strcmp(R->var[i], var);
    return k;
}

static int index_of(const char *var, const char *val)
{
    for (int i = 0; i < R->n; i++)
        if (!strcmp(R->var[i], var) && (!val || !strcmp(R->val[i], val))) return i;
    return -1;
}

static bool warned(const char *sub)
{
    for (int i = 0; i < R->nwarn; i++)
        if (strstr(R->warn[i], sub)) return true;
    return false;
}

static void clear(void)
{
    R->n = 0;
    R->nwarn = 0;
}

static void setup(void)
{
    if (!C) C = malloc(sizeof *C);
    if (!R) R = malloc(sizeof *R);
    ck_assert_ptr_nonnull(C);
    ck_assert_ptr_nonnull(R);
    kelp_contactmgr_init(C, "abe");
    clear();
    S = (kelp_field_sink){ R, pub, wrn };
    NOW = 1000;
}

static void teardown(void) {}

/* "key = value" */
static void cfg(const char *line)
{
    const char *eq = strchr(line, '=');
    ck_assert_ptr_nonnull(eq);
    char key[64];
    size_t kl = (size_t)(eq - line);
    while (kl && line[kl - 1] == ' ') kl--;
    memcpy(key, line, kl);
    key[kl] = 0;
    const char *v = eq + 1;
    while (*v == ' ') v++;
    ck_assert_int_eq(kelp_contactmgr_config(C, key, v, &S), 1);
}

static void done(void)
{
    kelp_contactmgr_config_done(C, true, 43.8253, true, -70.3304, &S); /* a mission with its datum */
}

static void fixture_f(void)
{
    cfg("alert = id=avd, on_flag=CONTACT_INFO=name=avd_$[VNAME] # contact=$[VNAME]");
    cfg("alert = id=avd, off_flag=CONTACT_DONE=$[VNAME]");
    cfg("alert = id=avd, alert_range=20, cpa_range=30");
    done();
}

static int mail_s(const char *var, const char *val)
{
    return kelp_contactmgr_mail(C, var, true, val, 0, NOW, "pHelmIvP", &S);
}

static void nav(double x, double y, double h, double v)
{
    ck_assert_int_eq(kelp_contactmgr_mail(C, "NAV_X", false, NULL, x, NOW, NULL, &S), 1);
    ck_assert_int_eq(kelp_contactmgr_mail(C, "NAV_Y", false, NULL, y, NOW, NULL, &S), 1);
    ck_assert_int_eq(kelp_contactmgr_mail(C, "NAV_HEADING", false, NULL, h, NOW, NULL, &S), 1);
    ck_assert_int_eq(kelp_contactmgr_mail(C, "NAV_SPEED", false, NULL, v, NOW, NULL, &S), 1);
}

/* report n@(x,y); extra pairs come first, so they win over the defaults */
static void rptx(const char *n, double x, double y, const char *extra)
{
    char b[512];
    snprintf(b, sizeof b, "NAME=%s,%s%sTYPE=kayak,TIME=%.2f,X=%.2f,Y=%.2f,SPD=0,HDG=0", n, extra ? extra : "",
             extra ? "," : "", NOW, x, y);
    ck_assert_int_eq(mail_s("NODE_REPORT", b), 1);
}

static void rpt(const char *n, double x, double y)
{
    rptx(n, x, y, NULL);
}

static void it(void)
{
    kelp_contactmgr_iterate(C, NOW, &S);
}

static const char *report(void)
{
    static char buf[32768];
    ck_assert_int_ge(kelp_contactmgr_report_text(C, NOW, buf, sizeof buf), 0);
    return buf;
}

/* ------------------------------------------------------------------ configuration and alerts */

START_TEST(cm_config_report_1)
{
    cfg("alert = id=K8, on_flag=SAY_MOOS=alarm, off_flag=SAY_MOOS=ok, alert_range=20, cpa_range=30");
    done();
    char one[32768];
    snprintf(one, sizeof one, "%s", report());
    ck_assert_ptr_nonnull(strstr(one, "1 ID: K8\n"));
    ck_assert_ptr_nonnull(strstr(one, "Alert Ranges: 20/30\n"));
    ck_assert_ptr_nonnull(strstr(one, "OnFlag: SAY_MOOS=alarm\n"));
    /* 24.8 (CMAlert::getSummary) labels an off flag "OnFlag" too; its report starts with the
     * ownship group (ContactMgrV20::buildReport) and names a mission alert's source "general" */
    ck_assert_ptr_nonnull(strstr(one, "OnFlag: SAY_MOOS=ok\n"));
    ck_assert_ptr_nonnull(strstr(one, "  Source: general\n"));
    ck_assert_int_eq(strncmp(one, "Ownship Group:      not specified\nOwnship Type:       not specified\n", 66), 0);
    ck_assert_ptr_nonnull(strstr(one, "Early Warning Time: -1\n"));
    ck_assert_int_eq(R->nwarn, 0);
    setup();
    cfg("alert = id=K8, on_flag=SAY_MOOS=alarm");
    cfg("alert = id=K8, off_flag=SAY_MOOS=ok");
    cfg("alert = id=K8, alert_range=20");
    cfg("alert = id=K8, cpa_range=30");
    done();
    ck_assert_str_eq(report(), one);
}
END_TEST

START_TEST(cm_cpa_default_2_3)
{
    cfg("alert = id=K8, on_flag=SAY_MOOS=alarm, alert_range=20");
    done();
    ck_assert_ptr_nonnull(strstr(report(), "Alert Ranges: 20/20\n"));
    rptx("gus", 0, 25, "HDG=180,SPD=1");
    it();
    ck_assert_int_eq(count("SAY_MOOS"), 0);
    /* 24.8's CMAlert: a cpa_range below alert_range lowers alert_range to it; an alert_range
     * above cpa_range raises cpa_range to it: the later component wins, silently */
    setup();
    cfg("alert = id=K8, on_flag=SAY_MOOS=alarm, alert_range=20, cpa_range=10");
    done();
    ck_assert_int_eq(R->nwarn, 0);
    ck_assert_ptr_nonnull(strstr(report(), "Alert Ranges: 10/10\n"));
    setup();
    cfg("alert = id=K8, on_flag=SAY_MOOS=alarm, cpa_range=10, alert_range=20");
    done();
    ck_assert_ptr_nonnull(strstr(report(), "Alert Ranges: 20/20\n"));
    setup(); /* only a cpa_range: the alert has no range and is invalid */
    cfg("alert = id=K8, on_flag=SAY_MOOS=alarm, cpa_range=10");
    done();
    ck_assert(warned("Invalid alert config:K8"));
    ck_assert_ptr_nonnull(strstr(report(), "Alert Ranges: unspecified/10\n"));
}
END_TEST

START_TEST(cm_invalid_4_6_7)
{
    cfg("alert = id=K8, alert_range=20");
    done();
    ck_assert(warned("Invalid alert config:K8"));
    rpt("gus", 0, 5);
    it();
    ck_assert_ptr_null(strstr(last("CONTACTS_UNALERTED") ? last("CONTACTS_UNALERTED") : "", "never"));
    ck_assert_int_eq(count("CONTACTS_ALERTED"), 0);
    /* 6: an unknown component: 24.8 warns, drops it and the rest, keeps the alert */
    clear();
    ck_assert_int_lt(mail_s("BCM_ALERT_REQUEST", "id=k9, foo=bar, on_flag=X=1, alert_range=5"), 0);
    ck_assert(warned("unhandled alert config component: foo"));
    ck_assert(warned("Unhandled Alert Request: id=k9, foo=bar, on_flag=X=1, alert_range=5"));
    ck_assert_ptr_nonnull(strstr(report(), "ID: k9\n  Alert Ranges: unspecified/unspecified\n  Source: pHelmIvP\n"));
    /* 7: no flags: not warned (24.8 checks validity at start-up only), never fires */
    clear();
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=k9, alert_range=20"), 1);
    ck_assert_int_eq(R->nwarn, 0);
    rpt("gus", 0, 4);
    it();
    ck_assert_ptr_null(last("CONTACTS_ALERTED"));
}
END_TEST

START_TEST(cm_request_5_8)
{
    fixture_f();
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=k8, on_flag=SAY_MOOS=alert, alert_range=20, cpa_range=40"), 1);
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=k8, on_flag=SAY_MOOS=alert, alert_range=20, cpa_range=40"), 1);
    rpt("gus", 0, 10);
    it();
    ck_assert_str_eq(last("SAY_MOOS"), "alert");
    ck_assert_int_eq(count("SAY_MOOS"), 1);
    ck_assert_str_eq(last("CONTACT_INFO"), "name=avd_gus # contact=gus");
    ck_assert_str_eq(last("CONTACTS_ALERTED"), "(gus,avd)(gus,k8)");
    ck_assert_str_eq(last("CONTACTS_COUNT"), "2");
    ck_assert_ptr_nonnull(strstr(report(), "BCM_ALERT_REQUESTs: 2\n"));
    ck_assert_ptr_nonnull(strstr(report(), "Source: pHelmIvP\n"));
}
END_TEST

START_TEST(cm_flags_9_10_11)
{
    cfg("alert = id=n, on_flag=ALERT_HITS=1, alert_range=20");
    cfg("alert = id=m, on_flag=A=first, on_flag=B=second, alert_range=20");
    cfg("alert = id=avd, onflag=CONTACT_INFO=\"name=avd_$[VNAME] # contact=$[VNAME]\", alert_range=20");
    done();
    rpt("vessel_023", 0, 10);
    it();
    int i = index_of("ALERT_HITS", NULL);
    ck_assert_int_ge(i, 0);
    ck_assert(!R->str[i]);
    ck_assert(R->d[i] == 1);
    ck_assert_int_lt(index_of("A", "first"), index_of("B", "second"));
    ck_assert_int_ge(index_of("A", "first"), 0);
    ck_assert_str_eq(last("CONTACT_INFO"), "name=avd_vessel_023 # contact=vessel_023");
}
END_TEST

START_TEST(cm_helm_request_12)
{
    done();
    /* the alert sees the ledger's type: cargo (unknown) is a ship there */
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=avoid, alert_range=20, cpa_range=40, ignore_type=ship, "
                                                 "on_flag=CONTACT_INFO=name=avd_$[VNAME] # contact=$[VNAME]"),
                     1);
    mail_s("NODE_REPORT", "NAME=vessel_023,TYPE=cargo,TIME=1000,X=0,Y=10");
    it();
    ck_assert_int_eq(count("CONTACT_INFO"), 0);
    ck_assert_str_eq(last("CONTACTS_LIST"), "vessel_023");
    mail_s("NODE_REPORT", "NAME=vessel_023,TYPE=kayak,TIME=1000,X=0,Y=10");
    it();
    ck_assert_str_eq(last("CONTACT_INFO"), "name=avd_vessel_023 # contact=vessel_023");
    /* BHV_AvoidCollision's own request string, filter summary and all */
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],"
                                                 "alert_range=50, cpa_range=75,match_name=abe, match_name=zed, "
                                                 "ignore_type=cargo, ignore_type=tug, match_type=kayak, "
                                                 "strict_ignore=true"),
                     1);
    ck_assert_int_eq(R->nwarn, 0);
    ck_assert_uint_eq(C->nalerts, 2);
    ck_assert_double_eq(C->alert[1].alert_range, 50);
    ck_assert_double_eq(kelp_contactmgr_cpa_range(&C->alert[1]), 75);
    ck_assert_uint_eq(C->alert[1].filter.nlist[0][0], 2);
    ck_assert_uint_eq(C->alert[1].filter.nlist[1][1], 2);
    ck_assert_str_eq(C->alert[1].on[0], "CONTACT_INFO=name=$[VNAME] # contact=$[VNAME]");
}
END_TEST

START_TEST(cm_action_disable)
{
    fixture_f();
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=avd, action=disable"), 1);
    rpt("gus", 0, 15);
    it();
    ck_assert_int_eq(count("CONTACT_INFO"), 0);
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=avd, action=enable"), 1);
    it();
    ck_assert_str_eq(last("CONTACT_INFO"), "name=avd_gus # contact=gus");
}
END_TEST

/* ------------------------------------------------------------------ triggering */

START_TEST(cm_trigger_13_14)
{
    fixture_f();
    rpt("gus", 0, 15);
    it();
    ck_assert_str_eq(last("CONTACT_INFO"), "name=avd_gus # contact=gus");
    ck_assert_str_eq(last("CONTACTS_LIST"), "gus");
    ck_assert_str_eq(last("CONTACTS_ALERTED"), "(gus,avd)");
    ck_assert_str_eq(last("CONTACTS_COUNT"), "1");
    clear();
    NOW += 0.25;
    it();
    ck_assert_int_eq(count("CONTACT_INFO") + count("CONTACTS_LIST") + count("CONTACTS_ALERTED") +
                         count("CONTACTS_COUNT"), 0);
}
END_TEST

/* one contact report, one iteration: was the on_flag posted? */
static bool alerts_once(const char *extra, double x, double y)
{
    setup();
    fixture_f();
    rptx("gus", x, y, extra);
    it();
    return count("CONTACT_INFO") == 1;
}

START_TEST(cm_trigger_15_to_20)
{
    ck_assert(!alerts_once(NULL, 0, 25)); /* 15 */
    ck_assert_int_eq(count("CONTACTS_UNALERTED"), 0); /* 24.8 posts no such list */
    ck_assert_int_eq(count("CONTACTS_ALERTED"), 0);
    ck_assert(alerts_once(NULL, 0, 20));                /* 16 */
    ck_assert(alerts_once("HDG=180,SPD=1", 0, 25));     /* 17 contact B */
    ck_assert(!alerts_once("HDG=0,SPD=2", 0, 25));      /* 18 contact C */
    ck_assert(!alerts_once("HDG=180,SPD=5", 0, 35));    /* 19 contact D */
    ck_assert(alerts_once("HDG=180,SPD=1", 0, 30));     /* 20 */
}
END_TEST

START_TEST(cm_off_21_22_23)
{
    fixture_f();
    rpt("gus", 0, 15);
    it();
    clear();
    rptx("gus", 0, 19, "HDG=0,SPD=2"); /* opening, inside alert_range: stays on */
    it();
    ck_assert_int_eq(count("CONTACT_DONE"), 0);
    /* 22: opening beyond alert_range but inside cpa_range: 24.8 (checkAlertApplies) ends the
     * alert, its CPA (now) being beyond alert_range too */
    rptx("gus", 0, 25, "HDG=0,SPD=2");
    it();
    ck_assert_str_eq(last("CONTACT_DONE"), "gus");
    rpt("gus", 0, 15);
    it();
    clear();
    rpt("gus", 0, 31); /* 21 */
    it();
    ck_assert_str_eq(last("CONTACT_DONE"), "gus");
    ck_assert_str_eq(last("CONTACTS_ALERTED"), "");
    ck_assert_str_eq(last("CONTACTS_COUNT"), "0");
    rpt("gus", 0, 15); /* 23 */
    it();
    ck_assert_int_eq(count("CONTACT_INFO"), 1);
    const char *r = report();
    ck_assert_ptr_nonnull(strstr(r, "gus          15.0    3         1\n"));
}
END_TEST

START_TEST(cm_age_24_25)
{
    cfg("contact_max_age = 600");
    fixture_f();
    rpt("gus", 0, 15);
    it();
    clear();
    NOW = 1600;
    it();
    ck_assert_int_eq(count("CONTACT_DONE"), 0);
    ck_assert_ptr_null(last("CONTACTS_LIST"));
    NOW = 1601;
    it();
    ck_assert_str_eq(last("CONTACT_DONE"), "gus");
    ck_assert_str_eq(last("CONTACTS_RETIRED"), "gus");
    ck_assert_str_eq(last("CONTACTS_LIST"), "");
    ck_assert_int_lt(index_of("CONTACT_DONE", NULL), index_of("CONTACTS_RETIRED", NULL));
    clear();
    NOW = 1602;
    rpt("gus", 0, 15);
    it();
    ck_assert_str_eq(last("CONTACTS_RETIRED"), "");
    ck_assert_str_eq(last("CONTACTS_LIST"), "gus");
    ck_assert_str_eq(last("CONTACT_INFO"), "name=avd_gus # contact=gus");
}
END_TEST

START_TEST(cm_ownship_bad_26_27)
{
    fixture_f();
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=abe,TIME=1000,X=0,Y=5"), 1);
    it();
    ck_assert_ptr_null(last("CONTACTS_LIST"));
    ck_assert_int_lt(mail_s("NODE_REPORT", "TYPE=kayak,X=0,Y=5"), 0);
    ck_assert_int_gt(R->nwarn, 0);
    ck_assert_int_eq(count("CONTACT_MGR_WARNING"), 0); /* not 24.8's */
    ck_assert(warned("Bad Mail: NODE_REPORT:"));
    it();
    ck_assert_ptr_null(last("CONTACTS_LIST"));
    ck_assert_int_eq(C->ncontacts, 0);
}
END_TEST

/* ------------------------------------------------------------------ macros */

START_TEST(cm_macros_28_29)
{
    cfg("alert = id=mac, on_flag=INFO=$[VNAME];$[X];$[Y];$[HDG];$[SPD];$[DEP];$[VTYPE];$[UTIME];$[LAT];$[LON], "
        "alert_range=20");
    cfg("alert = id=g, on_flag=GRP_$[VNAME]=$[VNAME], alert_range=20");
    cfg("alert = id=x, on_flag=MORE=%[VNAME]/%[VTYPE]/$[GROUP]/%[GROUP]/$[RANGE]/$[TIME]/$[BOGUS], alert_range=20");
    done();
    NOW = 1252348077.59;
    nav(50, -30, 0, 0);
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,LAT=43.824981,"
                                           "LON=-70.329755,SPD=2.00,HDG=118.85,DEPTH=4.63,LENGTH=3.8,MODE=LOITERING,"
                                           "GROUP=Blue"),
                     1);
    it();
    /* 24.8's postAlert: $[SPD] never expands (it looks for "$[SPD}"), nor $[RANGE] or $[TIME];
     * %[VNAME] keeps the case, %[VTYPE] and %[GROUP] are lower-cased */
    ck_assert_str_eq(last("INFO"), "alpha;51.71;-35.5;118.85;$[SPD];4.63;UUV;1252348077.59;43.824981;-70.329755");
    ck_assert_str_eq(last("GRP_alpha"), "alpha");
    ck_assert_str_eq(last("MORE"), "alpha/uuv/Blue/blue/$[RANGE]/$[TIME]/$[BOGUS]");
}
END_TEST

/* ------------------------------------------------------------------ global filters */

START_TEST(cm_filter_names_30_31_35)
{
    cfg("ignore_name = abe,ben, cal");
    fixture_f();
    rpt("ben", 0, 10), rpt("cal", 0, 11), rpt("deb", 0, 12);
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "deb");
    ck_assert_str_eq(last("CONTACT_INFO"), "name=avd_deb # contact=deb");
    ck_assert_int_eq(count("CONTACT_INFO"), 1);
    setup();
    cfg("match_name = henry");
    fixture_f();
    rpt("gus", 0, 10), rpt("henry", 0, 11);
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "henry");
    setup();
    cfg("match_name = Henry");
    fixture_f();
    rpt("henry", 0, 11);
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "henry");
}
END_TEST

START_TEST(cm_filter_types_32_33_34_36)
{
    cfg("match_type = motor_boat, crew_shell");
    done();
    mail_s("NODE_REPORT", "NAME=a,TYPE=sail_boat,TIME=1000,X=0,Y=5");
    mail_s("NODE_REPORT", "NAME=b,TYPE=crew_shell,TIME=1000,X=0,Y=5");
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "b");
    setup(); /* 33 */
    cfg("ignore_type = sail_boat");
    done();
    mail_s("NODE_REPORT", "NAME=a,TIME=1000,X=0,Y=5");
    it();
    ck_assert_ptr_null(last("CONTACTS_LIST"));
    setup();
    cfg("ignore_type = sail_boat");
    cfg("strict_ignore = false");
    done();
    mail_s("NODE_REPORT", "NAME=a,TIME=1000,X=0,Y=5");
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "a");
    setup(); /* 34 */
    cfg("match_group = blue_team");
    done();
    mail_s("NODE_REPORT", "NAME=a,GROUP=red_team,TIME=1000,X=0,Y=5");
    mail_s("NODE_REPORT", "NAME=b,TIME=1000,X=0,Y=5");
    mail_s("NODE_REPORT", "NAME=c,GROUP=blue_team,TIME=1000,X=0,Y=5");
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "c");
    setup(); /* 36 */
    cfg("match_type = sail_boat");
    cfg("ignore_type = sail_boat");
    done();
    ck_assert_int_gt(R->nwarn, 0);
    mail_s("NODE_REPORT", "NAME=a,TYPE=sail_boat,TIME=1000,X=0,Y=5");
    it();
    ck_assert_ptr_null(last("CONTACTS_LIST"));
}
END_TEST

#define MREG "pts={10,-40:-50,-80:-30,-140:50,-100}"
#define IREG "pts={50,-60:80,-70:120,-110:100,-150:60,-160:30,-110}"

START_TEST(cm_filter_regions_37_38_39)
{
    cfg("match_region = " MREG);
    cfg("reject_range = off");
    done();
    rpt("a", 0, -80), rpt("b", 100, 100);
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "a");
    setup();
    cfg("ignore_region = " IREG);
    done();
    rpt("a", 60, -100), rpt("b", 0, -80);
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "b");
    setup();
    cfg("match_region = " MREG);
    cfg("ignore_region = " IREG);
    done();
    rpt("c", 40, -100), rpt("d", 0, -80);
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "d");
    setup(); /* non-convex: warned, rejected */
    ck_assert_int_eq(kelp_contactmgr_config(C, "match_region", "pts={0,0:10,0:1,1:0,10}", &S), 0); /* not taken */
    ck_assert(warned("non-convex"));
    ck_assert_uint_eq(C->filter.nregion[0], 0);
}
END_TEST

START_TEST(cm_filter_retire_40)
{
    cfg("match_region = " MREG);
    cfg("reject_range = off");
    fixture_f();
    nav(0, -70, 0, 0);
    rpt("a", 0, -80);
    it();
    ck_assert_str_eq(last("CONTACT_INFO"), "name=avd_a # contact=a");
    clear();
    rpt("a", 100, 100);
    it();
    ck_assert_str_eq(last("CONTACTS_RETIRED"), "a");
    ck_assert_str_eq(last("CONTACTS_LIST"), "");
    ck_assert_int_eq(count("CONTACT_DONE"), 0);
}
END_TEST

/* ------------------------------------------------------------------ alert-level filters */

START_TEST(cm_alert_filters_41_42)
{
    cfg("alert = id=K8, on_flag=SAY_MOOS=alarm, off_flag=SAY_MOOS=ok, ignore_name=hal, alert_range=20, cpa_range=30, "
        "match_group=blue_team");
    done();
    mail_s("NODE_REPORT", "NAME=hal,GROUP=blue_team,TIME=1000,X=0,Y=10");
    it();
    ck_assert_int_eq(count("SAY_MOOS"), 0);
    ck_assert_str_eq(last("CONTACTS_LIST"), "hal");
    ck_assert_ptr_null(last("CONTACTS_ALERTED")); /* empty from the start: not posted */
    mail_s("NODE_REPORT", "NAME=ike,GROUP=blue_team,TIME=1000,X=0,Y=10");
    mail_s("NODE_REPORT", "NAME=jon,GROUP=red_team,TIME=1000,X=0,Y=10");
    it();
    ck_assert_int_eq(count("SAY_MOOS"), 1);
    ck_assert_str_eq(last("SAY_MOOS"), "alarm");
    ck_assert_str_eq(last("CONTACTS_ALERTED"), "(ike,K8)");
    setup(); /* 42 */
    done();
    nav(0, -70, 0, 0);
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=k8, onflag=SAY_MOOS=alert, alert_range=20, cpa_range=40, "
                                                 "match_region=" MREG),
                     1);
    rpt("a", 0, -80);
    it();
    ck_assert_str_eq(last("SAY_MOOS"), "alert");
    ck_assert_str_eq(last("CONTACTS_ALERTED"), "(a,k8)");
    rpt("a", 0, -35);
    it();
    ck_assert_str_eq(last("CONTACTS_ALERTED"), "");
    ck_assert_str_eq(last("CONTACTS_LIST"), "a");
}
END_TEST

/* ------------------------------------------------------------------ reject range, retired list */

START_TEST(cm_reject_43_44_45)
{
    fixture_f();
    /* 24.8 (checkForNewRetiredContacts) takes a far contact in and retires it at the next
     * iteration, beyond reject_range x 1.05 */
    rpt("far", 0, 2500);
    it();
    ck_assert_str_eq(last("CONTACTS_RETIRED"), "far");
    rpt("near", 0, 2050); /* beyond reject_range, within its margin */
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "near");
    rpt("near", 0, 2200);
    it();
    ck_assert_str_eq(last("CONTACTS_RETIRED"), "near,far");
    ck_assert_str_eq(last("CONTACTS_LIST"), "");
    setup();
    cfg("reject_range = off");
    fixture_f();
    rpt("far", 0, 5000);
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "far");
    ck_assert_ptr_nonnull(strstr(report(), "Reject Range:       off\n"));
}
END_TEST

START_TEST(cm_retired_46_47_48)
{
    cfg("contact_max_age = 600");
    cfg("max_retired_history = 2");
    fixture_f();
    const char *names[] = { "bravo", "foxtrot", "kilroy", "zulu" };
    for (int i = 0; i < 4; i++) {
        NOW = 1000 + i;
        rpt(names[i], 0, 100);
    }
    const char *want[] = { "bravo", "foxtrot,bravo", "kilroy,foxtrot,bravo", "zulu,kilroy,foxtrot" };
    for (int i = 0; i < 4; i++) {
        clear();
        NOW = 1601 + i;
        it();
        ck_assert_str_eq(last("CONTACTS_RETIRED"), want[i]);
    }
    setup(); /* 47 */
    cfg("contact_max_age = 600");
    fixture_f();
    rpt("kilroy", 0, 100), rpt("bravo", 0, 100), rpt("foxtrot", 0, 100);
    NOW = 1601;
    it();
    ck_assert_str_eq(last("CONTACTS_RETIRED"), "kilroy,foxtrot,bravo");
    setup(); /* 48 */
    cfg("max_retired_history = 0");
    ck_assert_int_eq(R->nwarn, 1);
    ck_assert_uint_eq(C->max_retired, 1);
    cfg("max_retired_history = 99");
    ck_assert_int_eq(R->nwarn, 2);
    ck_assert_uint_eq(C->max_retired, 50);
}
END_TEST

START_TEST(cm_forced_49_50_51)
{
    cfg("max_contacts = 2");
    cfg("alert = id=w, on_flag=W_ON=$[VNAME], off_flag=W_OFF=$[VNAME], alert_range=40");
    done();
    rpt("a", 0, 10), rpt("b", 0, 20), rpt("c", 0, 30);
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "a,b");
    ck_assert_str_eq(last("CONTACTS_RETIRED"), "c");
    ck_assert_int_eq(count("W_ON"), 3);
    it();
    ck_assert_int_eq(count("W_OFF"), 0);
    setup(); /* 50 */
    cfg("contact_max_age = 600");
    cfg("max_contacts = 2");
    done();
    mail_s("NODE_REPORT", "NAME=a,TIME=1000,X=0,Y=10");
    mail_s("NODE_REPORT", "NAME=b,TIME=1300,X=0,Y=50");
    mail_s("NODE_REPORT", "NAME=c,TIME=1350,X=0,Y=60");
    NOW = 1400;
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "b,c");
    ck_assert_str_eq(last("CONTACTS_RETIRED"), "a");
}
END_TEST

/* ------------------------------------------------------------------ custom reports */

START_TEST(cm_reports_52_to_55_60)
{
    done();
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=CONTACTS_050, range=50"), 1);
    rpt("ben", 0, 30), rpt("cal", 0, 70), rpt("dan", 0, 50);
    it();
    ck_assert_str_eq(last("CONTACTS_050"), "ben"); /* 60: dan at exactly 50 is out */
    clear();
    it();
    ck_assert_int_eq(count("CONTACTS_050"), 0);
    rpt("cal", 0, 40);
    it();
    ck_assert_str_eq(last("CONTACTS_050"), "ben,cal");
    clear(); /* 54 */
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=CONTACTS_010, range=10"), 1);
    it(); /* 24.8: a new report is posted when its list differs from "" (or on refresh) */
    it();
    ck_assert_int_eq(count("CONTACTS_010"), 0);
    clear(); /* 55 */
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=CONTACTS_050, range=50, refresh=true"), 1);
    it();
    ck_assert_str_eq(last("CONTACTS_050"), "ben,cal");
    ck_assert_int_eq(count("CONTACTS_050"), 1);
}
END_TEST

START_TEST(cm_reports_56_57_58)
{
    done();
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=CONTACTS_050, range=50, group=blueteam"), 1);
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "\"var=CONTACTS_200, range=200, type=sailboat, refresh=true\""), 1);
    rptx("ben", 0, 30, "GROUP=blueteam"), rptx("cal", 0, 20, "GROUP=red");
    rptx("a", 0, 100, "TYPE=sailboat"), rptx("b", 0, 100, "TYPE=kayak");
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=CONTACTS_SHIP, range=200, type=ship"), 1);
    it();
    ck_assert_str_eq(last("CONTACTS_050"), "ben");
    /* the ledger's types: the sailboat is a ship there */
    ck_assert_str_eq(last("CONTACTS_200"), "");
    ck_assert_str_eq(last("CONTACTS_SHIP"), "a");
    clear();
    ck_assert_int_lt(mail_s("BCM_REPORT_REQUEST", "var=CONTACTS_050"), 0);
    ck_assert(warned("Failed REPORT_REQUEST: var=CONTACTS_050"));
    ck_assert_int_lt(mail_s("BCM_REPORT_REQUEST", "var=X, range=5, colour=red"), 0);
    it();
    ck_assert_int_eq(count("CONTACTS_050"), 0);
}
END_TEST

/* 24.8's pruneRangeReports: a report outlives range_report_timeout while there are no more
 * than range_report_maxsize of them */
START_TEST(cm_reports_timeout_59)
{
    for (int variant = 0; variant < 3; variant++) {
        setup();
        if (variant == 2) cfg("range_report_timeout = 60");
        done();
        ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=CONTACTS_050, range=50"), 1);
        rpt("ben", 0, 30);
        it();
        ck_assert_str_eq(last("CONTACTS_050"), "ben");
        clear();
        NOW = variant == 0 ? 1005 : variant == 1 ? 1011 : 1030;
        rpt("ben", 0, 70);
        it();
        ck_assert_str_eq(last("CONTACTS_050"), "");
    }
}
END_TEST

/* ------------------------------------------------------------------ closest */

START_TEST(cm_closest_61_62_63)
{
    cfg("post_closest_range = true");
    cfg("post_all_ranges = true");
    done();
    rpt("a", 0, 48.32), rpt("b", 0, 56.3), rpt("c", 0, 112.08);
    it();
    ck_assert_str_eq(last("CONTACT_CLOSEST"), "a");
    ck_assert_str_eq(last("CONTACT_CLOSEST_TIME"), "1000");
    ck_assert_str_eq(last("CONTACT_CLOSEST_RANGE"), "48");
    ck_assert_str_eq(last("CONTACT_RANGES"), "48.3,56.3,112.1"); /* 24.8: one decimal, every iteration */
    clear();
    NOW = 1005;
    rpt("z", 0, 10);
    it();
    ck_assert_str_eq(last("CONTACT_CLOSEST"), "z");
    ck_assert_str_eq(last("CONTACT_CLOSEST_TIME"), "1005");
    ck_assert_str_eq(last("CONTACT_CLOSEST_RANGE"), "10");
    ck_assert_str_eq(last("CONTACT_RANGES"), "10,48.3,56.3,112.1");
    clear();
    rpt("a", 0, 48.9);
    it();
    ck_assert_int_eq(count("CONTACT_CLOSEST"), 0);
    setup(); /* 62 */
    done();
    rpt("a", 0, 48.32);
    it();
    ck_assert_str_eq(last("CONTACT_CLOSEST"), "a");
    ck_assert_int_eq(count("CONTACT_CLOSEST_TIME"), 1);
    ck_assert_int_eq(count("CONTACT_CLOSEST_RANGE") + count("CONTACT_RANGES"), 0);
}
END_TEST

/* ------------------------------------------------------------------ recap, order */

START_TEST(cm_recap_64_65_66)
{
    done();
    mail_s("NODE_REPORT", "NAME=cal,TIME=999.17,X=0,Y=82.72");
    mail_s("NODE_REPORT", "NAME=ben,TIME=999.17,X=0,Y=82.72");
    mail_s("NODE_REPORT", "NAME=deb,TIME=999.17,X=0,Y=10");
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "ben,cal,deb");
    ck_assert_str_eq(last("CONTACTS_RECAP"), "vname=ben,range=82.72,age=0.83 # vname=cal,range=82.72,age=0.83 # "
                                             "vname=deb,range=10.00,age=0.83");
    setup();
    cfg("recap_interval = off");
    done();
    for (int i = 0; i < 5; i++, NOW++) it();
    ck_assert_int_eq(count("CONTACTS_RECAP"), 0);
    setup();
    cfg("recap_interval = 5");
    done();
    for (int i = 0; i < 10; i++, NOW++) it();
    ck_assert_int_eq(count("CONTACTS_RECAP"), 2);
    setup(); /* default 1 s: every iteration at 1 Hz, posted even unchanged */
    done();
    for (int i = 0; i < 3; i++, NOW++) it();
    ck_assert_int_eq(count("CONTACTS_RECAP"), 3);
}
END_TEST

/* ------------------------------------------------------------------ extrapolation */

START_TEST(cm_decay_67_68_69)
{
    for (int variant = 0; variant < 2; variant++) {
        setup();
        if (variant) cfg("decay = 0,0");
        done();
        ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=NEAR, range=101"), 1);
        mail_s("NODE_REPORT", "NAME=c,TIME=1000,X=0,Y=100,HDG=90,SPD=2");
        it();
        ck_assert_str_eq(last("NEAR"), "c");
        clear();
        NOW = 1010;
        ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=NEAR, range=101"), 1);
        it();
        if (variant == 0) {
            ck_assert_str_eq(last("NEAR"), "");
            ck_assert_str_eq(last("CONTACTS_RECAP"), "vname=c,range=100.00,age=10.00");
        } else
            ck_assert_int_eq(count("NEAR"), 0);
    }
    const double dt[] = { 10, 15, 20, 25, 30, 100 }, want[] = { 20, 30, 38.333333, 43.333333, 45, 45 };
    for (int i = 0; i < 6; i++) ck_assert_double_eq_tol(kelp_contactmgr_extrap_dist(2, dt[i], 15, 30), want[i], 1e-5);
    ck_assert_double_eq(kelp_contactmgr_extrap_dist(2, 10, 0, 0), 0);
    ck_assert_double_eq(kelp_contactmgr_extrap_dist(2, -5, 15, 30), 0);
}
END_TEST

/* ------------------------------------------------------------------ CPA geometry */

typedef struct geo_case {
    double o[4], c[4], range, cpa;
    double a1, c1;
    bool yes1;
    double a2, c2;
    bool yes2;
} geo_case;

static bool alert_case(const double *o, const double *k, double a, double cr, double *cpa)
{
    setup();
    char line[128];
    snprintf(line, sizeof line, "alert = id=t, on_flag=T=$[VNAME], alert_range=%g, cpa_range=%g", a, cr);
    cfg(line);
    done();
    nav(o[0], o[1], o[2], o[3]);
    char b[256];
    snprintf(b, sizeof b, "NAME=k,TIME=1000,X=%g,Y=%g,HDG=%g,SPD=%g", k[0], k[1], k[2], k[3]);
    ck_assert_int_eq(mail_s("NODE_REPORT", b), 1);
    it();
    int ci = kelp_contactmgr_find(C, "k");
    ck_assert_int_ge(ci, 0);
    *cpa = C->contact[ci].range_cpa;
    return count("T") == 1;
}

START_TEST(cm_cpa_geometry_70_to_79)
{
    const geo_case g[] = {
        { { 0, 0, 0, 2 }, { 0, 100, 180, 3 }, 100, 0, 20, 150, true, 20, 80, false },
        { { 0, 0, 0, 5 }, { 100, 120, 270, 5 }, 156.205, 14.142136, 15, 200, true, 14, 200, false },
        { { 0, 0, 0, 0 }, { -100, 30, 90, 4 }, 104.403, 30, 31, 120, true, 29, 120, false },
        { { 0, 0, 0, 2 }, { 10, -100, 0, 4 }, 100.499, 10, 12, 120, true, 12, 120, true },
        { { 0, 0, 90, 2 }, { 100, 10, 0, 0 }, 100.499, 10, 12, 120, true, 12, 120, true },
        { { 0, 0, 0, 2 }, { 0, 50, 0, 5 }, 50, 50, 20, 100, false, 20, 100, false },
        { { 0, 0, 0, 0 }, { 30, 40, 0, 0 }, 50, 50, 60, 60, true, 40, 100, false },
        { { 0, 0, 90, 3 }, { 0, 25, 90, 3 }, 25, 25, 20, 50, false, 30, 30, true },
        { { 0, 0, 0, 5 }, { 100, 100, 270, 5 }, 141.421, 0, 20, 150, true, 20, 150, true },
    };
    for (size_t i = 0; i < sizeof g / sizeof g[0]; i++) {
        double cpa;
        bool y1 = alert_case(g[i].o, g[i].c, g[i].a1, g[i].c1, &cpa);
        ck_assert_msg(y1 == g[i].yes1, "case %zu first outcome", i + 70);
        ck_assert_msg(fabs(cpa - g[i].cpa) < 1e-3, "case %zu cpa %f", i + 70, cpa);
        ck_assert_double_eq_tol(C->contact[kelp_contactmgr_find(C, "k")].range, g[i].range, 1e-3);
        bool y2 = alert_case(g[i].o, g[i].c, g[i].a2, g[i].c2, &cpa);
        ck_assert_msg(y2 == g[i].yes2, "case %zu second outcome", i + 70);
    }
    double t = 0;
    ck_assert_double_eq_tol(kelp_cpa_range(0, 100000, 180, 1, 0, 0, 0, 0, KELP_CMGR_CPA_HORIZON, &t), 64000, 1e-6);
    ck_assert_double_eq_tol(t, 36000, 1e-6);
}
END_TEST

/* ------------------------------------------------------------------ coordinates */

static void geo_setup(const char *mode, bool origin)
{
    setup();
    char line[64];
    snprintf(line, sizeof line, "contact_local_coords = %s", mode);
    cfg(line);
    kelp_contactmgr_config_done(C, origin, 43.825300, origin, -70.330400, &S);
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=R_HI, range=100.5"), 1);
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=R_LO, range=99.5"), 1);
}

START_TEST(cm_coords_80_to_85)
{
    geo_setup("lazy_lat_lon", true);
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=ben,TIME=1000,LAT=43.8262,LON=-70.3304"), 1);
    it();
    ck_assert_str_eq(last("R_HI"), "ben");
    ck_assert_ptr_null(last("R_LO")); /* a new report's empty list is not posted */
    geo_setup("lazy_lat_lon", true); /* 81 */
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=ben,TIME=1000,X=0,Y=10,LAT=43.8262,LON=-70.3304"), 1);
    it();
    ck_assert_double_eq_tol(C->contact[kelp_contactmgr_find(C, "ben")].range, 10, 1e-9);
    geo_setup("force_lat_lon", true); /* 82 */
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=ben,TIME=1000,X=0,Y=10,LAT=43.8262,LON=-70.3304"), 1);
    it();
    /* UTM as 24.8 (PROJ: 1.6075 m east, 99.9591 m north of the datum in zone 19) */
    ck_assert_double_eq_tol(C->contact[kelp_contactmgr_find(C, "ben")].range, 99.972, 0.001);
    geo_setup("verbatim", true); /* 83 */
    ck_assert_int_lt(mail_s("NODE_REPORT", "NAME=ben,TIME=1000,LAT=43.8262,LON=-70.3304"), 0);
    ck_assert_int_eq(count("CONTACT_MGR_WARNING"), 0); /* not 24.8's */
    ck_assert(warned("Bad Mail: NODE_REPORT:"));
    it();
    ck_assert_ptr_null(last("CONTACTS_LIST"));
    geo_setup("lazy_lat_lon", false); /* 84 */
    ck_assert(warned("Lat or Lon Origin not set in *.moos file."));
    ck_assert_int_lt(mail_s("NODE_REPORT", "NAME=ben,TIME=1000,LAT=43.8262,LON=-70.3304"), 0);
    geo_setup("lazy_lat_lon", true); /* 85 */
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=ben,TIME=1000,LAT=43.8253,LON=-70.3292"), 1);
    int ci = kelp_contactmgr_find(C, "ben");
    /* UTM as 24.8 (PROJ: the datum's parallel curves 1.55 m south of grid east at 96 m) */
    ck_assert_double_eq_tol(C->contact[ci].x, 96.4919, 0.001);
    ck_assert_double_eq_tol(C->contact[ci].y, -1.5511, 0.001);
}
END_TEST

/* ------------------------------------------------------------------ visuals, verbose, report */

/* 24.8's postRadii (recorded: "x=0,y=0,radius=80,label=alert_abe,edge_color=gray65,time=..,
 * duration=3,vertex_size=0,edge_size=1"): one ring per iteration at the largest cpa_range of the
 * alerts not turned off, labelled alert_<ownship>; BCM_DISPLAY_RADII takes 24.8's booleans */
START_TEST(cm_visuals_86_87_88)
{
    cfg("display_radii = true");
    fixture_f();
    cfg("alert = id=big, on_flag=B=1, alert_range=25, cpa_range=45");
    nav(10, 5, 0, 0);
    it();
    ck_assert_int_eq(count("VIEW_CIRCLE"), 1);
    ck_assert_str_eq(last("VIEW_CIRCLE"),
                     "x=10,y=5,radius=45,label=alert_abe,edge_color=gray65,time=1000,duration=3,vertex_size=0,edge_size=1");
    clear(); /* the alert turned off no longer counts */
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=big, action=disable"), 1);
    it();
    ck_assert_ptr_nonnull(strstr(last("VIEW_CIRCLE"), "radius=30,label=alert_abe,"));
    clear(); /* 88 */
    ck_assert_int_eq(mail_s("BCM_DISPLAY_RADII", "false"), 1);
    it();
    ck_assert_int_eq(count("VIEW_CIRCLE"), 0);
    ck_assert_int_eq(mail_s("BCM_DISPLAY_RADII", "toggle"), 1);
    it();
    ck_assert_int_eq(count("VIEW_CIRCLE"), 1);
    ck_assert_int_eq(mail_s("BCM_DISPLAY_RADII", "no"), 1);
    ck_assert(!C->display_radii);
    ck_assert_int_eq(mail_s("BCM_DISPLAY_RADII", "yes"), 1);
    ck_assert(C->display_radii);
    clear();
    ck_assert_int_lt(mail_s("BCM_DISPLAY_RADII", "avd"), 0); /* an alert id is no boolean in 24.8 */
    ck_assert(warned("Bad Mail: BCM_DISPLAY_RADII:"));
    ck_assert(C->display_radii);
    setup(); /* 87: an invisible colour, or no range: the ring is posted inactive */
    cfg("display_radii = true");
    cfg("alert_range_color = invisible");
    cfg("alert = id=q, on_flag=Q=1, alert_range=20");
    done();
    it();
    ck_assert_str_eq(last("VIEW_CIRCLE"), "x=0,y=0,radius=20,active=false,label=alert_abe,edge_color=invisible,"
                                          "time=1000,duration=3,vertex_size=0,edge_size=1");
    setup();
    cfg("display_radii = true");
    cfg("alert = id=q, on_flag=Q=1");
    done();
    it();
    ck_assert_ptr_nonnull(strstr(last("VIEW_CIRCLE"), "x=0,y=0,radius=0,active=false,label=alert_abe,edge_color=gray65,"));
    setup(); /* every alert off: the same zero ring, wherever ownship is */
    cfg("display_radii = true");
    cfg("alert = id=q, on_flag=Q=1, alert_range=20");
    done();
    nav(7, 8, 0, 0);
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=q, action=disable"), 1);
    it();
    ck_assert_str_eq(last("VIEW_CIRCLE"), "x=0,y=0,radius=0,active=false,label=alert_abe,edge_color=gray65,"
                                          "time=1000,duration=3,vertex_size=0,edge_size=1");
}
END_TEST

/* 24.8's checkForEarlyWarnings / checkForCeaseWarnings (recorded: "EW=c1|100.499|98.873|10|4.974|..",
 * after_warning=4.76 in ALERT_VERBOSE, the cease flag once the extrapolated range opened
 * beyond 1.05 x the range warned at) */
START_TEST(cm_early_cease_warnings)
{
    cfg("early_warning_time = 4");
    cfg("early_warning_flag = EW=$[CONTACT]|$[RNG]|$[RNG_EXT]|$[CPA]|$[ROC]|$(UTC)");
    cfg("early_warning_flag = EWN=3");
    cfg("cease_warning_flag = CW=$[CONTACT]|$[RNG]");
    cfg("alert_verbose = true");
    cfg("alert = id=avd, alert_range=50, cpa_range=80, on_flag=ON=$[VNAME]");
    done();
    /* closing at 5 m/s along y = 10: warned below 80 + 4 x roc */
    double x = 110;
    rptx("c1", x, 10, "HDG=270,SPD=5");
    it();
    ck_assert_int_eq(count("EW"), 0); /* range 110.5 > 80 + 4 x 4.98 */
    ck_assert_double_eq_tol(C->contact[kelp_contactmgr_find(C, "c1")].will_warn, 80 + 4 * 5 * 110 / hypot(110, 10),
                            1e-9);
    NOW += 2, x -= 10; /* 100.499 > 80 + 4 x 4.975: not yet */
    rptx("c1", x, 10, "HDG=270,SPD=5");
    it();
    ck_assert_int_eq(count("EW"), 0);
    NOW += 1, x -= 5; /* 95.525 < 80 + 4 x 4.973 */
    rptx("c1", x, 10, "HDG=270,SPD=5");
    it();
    ck_assert_str_eq(last("EW"), "c1|95.525|95.525|10|4.973|1003");
    ck_assert_str_eq(last("EWN"), "3");
    ck_assert(!R->str[index_of("EWN", NULL)]);
    NOW += 1, x -= 5;
    rptx("c1", x, 10, "HDG=270,SPD=5");
    it();
    ck_assert_int_eq(count("EW"), 1); /* once */
    while (index_of("ON", NULL) < 0) { /* alerted within cpa_range 80 (its CPA 10 is within 50) */
        NOW += 1, x -= 5;
        rptx("c1", x, 10, "HDG=270,SPD=5");
        it();
    }
    char v[256];
    snprintf(v, sizeof v, "contact=c1,alert_id=avd,off-->alerted,alert_range=50,alert_range_cpa=80,range_actual=%.1f,"
             "range_cpa=10.0,after_warning=%g", hypot(x, 10), NOW - 1003);
    ck_assert_str_eq(last("ALERT_VERBOSE"), v);
    ck_assert_double_eq_tol(x, 75, 1e-9);
    ck_assert_int_eq(count("CW"), 0);
    while (x > -100) { /* past ownship and opening */
        NOW += 1, x -= 5;
        rptx("c1", x, 10, "HDG=270,SPD=5");
        it();
        if (count("CW")) break;
    }
    /* ceased at the first extrapolated range beyond 1.05 x 95.525 = 100.3 */
    ck_assert_double_eq_tol(x, -100, 1e-9);
    snprintf(v, sizeof v, "c1|%.3f", hypot(x, 10));
    ck_assert_str_eq(last("CW"), v);
    ck_assert_int_eq(count("EW"), 1);
    /* the report's early-warning lines (24.8 swaps the two counts' labels) */
    ck_assert_ptr_nonnull(strstr(report(), "Early Warning Time: 4\nEarlyWarn Radii:    false\nEarlyWarn EWFlags:  1\n"
                                          "EarlyWarn CWFlags:  2\nAlertsDisabled:     \nmax_alert_range:    80\n"));
}
END_TEST

/* 24.8's postEarlyWarningRadii: "x=0,y=0,radius=99.97,label=xewarn_c1,label_color=gray50,
 * edge_color=green,time=..,duration=3,vertex_size=0,edge_size=1" until the warning */
START_TEST(cm_early_warning_radii)
{
    cfg("early_warning_time = 4");
    cfg("early_warning_radii = true");
    cfg("alert = id=avd, alert_range=50, cpa_range=80, on_flag=ON=$[VNAME]");
    done();
    rptx("c1", 0, 200, "HDG=180,SPD=5");
    rptx("still", 0, 100, NULL);
    it();
    ck_assert_int_eq(count("VIEW_CIRCLE"), 1);
    ck_assert_str_eq(last("VIEW_CIRCLE"), "x=0,y=0,radius=100,label=xewarn_c1,label_color=gray50,edge_color=green,"
                                          "time=1000,duration=3,vertex_size=0,edge_size=1");
    clear();
    NOW += 1;
    rptx("c1", 0, 99, "HDG=180,SPD=5");
    it();
    ck_assert_int_eq(count("VIEW_CIRCLE"), 0); /* warned: no ring */
}
END_TEST

/* types through 24.8's contact ledger (recorded: a sailboat fires match_type=ship and not
 * match_type=sailboat, uuv becomes auv, UUV stays as given, a glider without depth is refused
 * as "Bad Mail: NODE_REPORT:1:g12:", a KAYAK never matches match_type=KAYAK: entries are kept
 * in lower case and compared with the type as reported) */
START_TEST(cm_ledger_types)
{
    cfg("alert = id=ships, alert_range=40, match_type=ship, on_flag=SHIP_ON=$[VNAME]/$[VTYPE]/%[VTYPE]");
    cfg("alert = id=sb, alert_range=40, match_type=sailboat, on_flag=SB_ON=$[VNAME]");
    cfg("alert = id=auvs, alert_range=40, match_type=auv, on_flag=AUV_ON=$[VNAME]/$[VTYPE]");
    cfg("alert = id=bigk, alert_range=40, match_type=KAYAK, on_flag=K_ON=$[VNAME]/$[VTYPE]");
    cfg("alert = id=blue, alert_range=40, match_group=BLUE, on_flag=G_ON=$[VNAME]");
    done();
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=Sail,TYPE=sailboat,GROUP=BLUE,TIME=1000,X=30,Y=0"), 1);
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=u1,TYPE=uuv,TIME=1000,X=0,Y=35,DEP=2"), 1);
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=U2,TYPE=UUV,TIME=1000,X=0,Y=-36"), 1);
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=k9,TYPE=KAYAK,GROUP=blue,TIME=1000,X=-38,Y=0"), 1);
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=c1,TYPE=kayak,TIME=1000,X=-20,Y=0"), 1);
    ck_assert_int_lt(mail_s("NODE_REPORT", "NAME=g1,TYPE=glider,TIME=1000,X=0,Y=-37"), 0);
    ck_assert(warned("Bad Mail: NODE_REPORT:1:g12:"));
    ck_assert_int_lt(mail_s("NODE_REPORT", "TYPE=kayak,X=1,Y=1"), 0);
#ifndef KELP_NO_ERRMSG /* the parser's reason is diagnostic text */
    ck_assert(warned("Bad Mail: NODE_REPORT:Empty vname"));
#endif
    it();
    ck_assert_str_eq(last("SHIP_ON"), "Sail/ship/ship");
    ck_assert_int_eq(count("SB_ON"), 0);
    ck_assert_str_eq(last("AUV_ON"), "u1/auv");
    ck_assert_int_eq(count("AUV_ON"), 1);
    ck_assert_str_eq(last("K_ON"), "c1/kayak");
    ck_assert_int_eq(count("K_ON"), 1);
    ck_assert_str_eq(last("G_ON"), "k9"); /* group blue matches BLUE's lower-case entry, BLUE does not */
    ck_assert_int_eq(count("G_ON"), 1);
    ck_assert_str_eq(last("CONTACTS_LIST"), "Sail,U2,c1,k9,u1");
}
END_TEST

/* 24.8's handleConfigAlert on a request with a bad component (recorded: req1 "id=req1,
 * alert_range=30, on_flag=REQ_ON=.., bogus=3" alerts; req5 "alert_range=off" is unhandled;
 * off_flag "A=a # B=b" is two flags, an on_flag is one) */
START_TEST(cm_bad_request_keeps_alert)
{
    done();
    ck_assert_int_lt(mail_s("BCM_ALERT_REQUEST", "id=req1, alert_range=30, on_flag=REQ_ON=$[VNAME], bogus=3"), 0);
    ck_assert(warned("unhandled alert config component: bogus"));
    ck_assert(warned("Unhandled Alert Request: id=req1, alert_range=30, on_flag=REQ_ON=$[VNAME], bogus=3"));
    ck_assert_int_lt(mail_s("BCM_ALERT_REQUEST", "id=req5, alert_range=off, on_flag=R5=1"), 0);
    ck_assert(warned("unhandled alert config component: alert_range"));
    ck_assert_int_eq(mail_s("BCM_ALERT_REQUEST", "id=req4, alert_range=25, on_flag=ON4=x # y=z, "
                                                 "off_flag=REQ4_OFF=a # REQ4_OFF2=b"), 1);
    ck_assert_uint_eq(C->alert[2].non, 1);
    ck_assert_uint_eq(C->alert[2].noff, 2);
    rpt("gus", 0, 20);
    it();
    ck_assert_str_eq(last("REQ_ON"), "gus");
    ck_assert_int_eq(count("R5"), 0);
    ck_assert_str_eq(last("ON4"), "x # y=z");
    rpt("gus", 0, 40);
    it();
    ck_assert_str_eq(last("REQ4_OFF"), "a");
    ck_assert_str_eq(last("REQ4_OFF2"), "b");
    const char *r = report();
    ck_assert_ptr_nonnull(strstr(r, "ID: req5\n  Alert Ranges: unspecified/unspecified\n  Source: pHelmIvP\n"));
    ck_assert_ptr_nonnull(strstr(r, "  OnFlag: REQ4_OFF=a\n  OnFlag: REQ4_OFF2=b\n"));
}
END_TEST

/* 24.8's handleMailReportRequest: the same variable and range renews the request only (the
 * group given first stays); refresh posts the list once even when unchanged */
START_TEST(cm_report_request_renewal)
{
    done();
    rptx("ben", 0, 30, "GROUP=alpha");
    rptx("cal", 0, 20, "GROUP=beta");
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=NEAR, range=40, group=alpha"), 1);
    it();
    ck_assert_str_eq(last("NEAR"), "ben");
    clear();
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=NEAR, range=40, group=beta"), 1);
    it();
    ck_assert_int_eq(count("NEAR"), 0);
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=NEAR, range=40, refresh=TRUE"), 1);
    it();
    ck_assert_str_eq(last("NEAR"), "ben");
    it();
    ck_assert_int_eq(count("NEAR"), 1);
    clear(); /* a new range starts the report afresh, with the group given now */
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=NEAR, range=41, group=beta"), 1);
    it();
    ck_assert_str_eq(last("NEAR"), "cal");
}
END_TEST

START_TEST(cm_verbose_89_report_91)
{
    cfg("alert_verbose = true");
    fixture_f();
    rpt("gus", 0, 15);
    it();
    int a = index_of("ALERT_VERBOSE", "new_contact=gus");
    int b = index_of("ALERT_VERBOSE", "contact=gus,alert_id=avd,off-->alerted,alert_range=20,alert_range_cpa=30,"
                                      "range_actual=15.0,range_cpa=15.0");
    ck_assert_int_ge(a, 0);
    ck_assert_int_gt(b, a);
    const char *r = report();
    ck_assert_ptr_nonnull(strstr(r, "gus          15.0    1         1\n"));
    ck_assert_str_eq(kelp_contactmgr_event(C, C->events_made - 1), "CONTACT_INFO=name=avd_gus # contact=gus");
    ck_assert_ptr_nonnull(strstr(r, "       List: gus\n"));
    ck_assert_ptr_nonnull(strstr(r, "    Alerted: (gus,avd)\n"));
}
END_TEST

/* 24.8 (ContactMgrV20::handleMailModEnableContact): disable_var/enable_var/expunge_var */
START_TEST(cm_able_vars)
{
    cfg("disable_var = CMGR_DISABLE");
    cfg("enable_var = CMGR_ENABLE");
    cfg("expunge_var = CMGR_EXPUNGE");
    cfg("able_flag = ABLE_CHANGED = true");
    cfg("disable_flag = DISABLED_CONTACT = $[RECENT_DISABLED]/$[TOTAL_DISABLED]");
    cfg("enable_flag = ENABLED_CONTACT = 1");
    ck_assert_int_eq(R->nwarn, 0);
    done();
    ck_assert_int_eq(mail_s("CMGR_DISABLE", "contact=k2"), 1);
    ck_assert_str_eq(last("BHV_ABLE_FILTER"), "contact=k2,action=disable");
    ck_assert_str_eq(last("ABLE_CHANGED"), "true");
    ck_assert_str_eq(last("DISABLED_CONTACT"), "k2/1");
    ck_assert_int_eq(mail_s("CMGR_ENABLE", "contact=k2"), 1);
    ck_assert_str_eq(last("BHV_ABLE_FILTER"), "contact=k2,action=enable");
    ck_assert_str_eq(last("ENABLED_CONTACT"), "1");
    ck_assert_int_eq(count("ABLE_CHANGED"), 2);
    /* a bare name goes to the helm, with no flags */
    ck_assert_int_eq(mail_s("CMGR_DISABLE", "k1"), 1);
    ck_assert_str_eq(last("BHV_ABLE_FILTER"), "contact=k1,action=disable");
    ck_assert_int_eq(count("ABLE_CHANGED"), 2);
    ck_assert_int_eq(mail_s("CMGR_EXPUNGE", "vsource=ais"), 1);
    ck_assert_str_eq(last("BHV_ABLE_FILTER"), "vsource=ais,action=expunge");
    ck_assert_int_lt(mail_s("CMGR_EXPUNGE", "foo=bar"), 0);
    ck_assert(warned("Bad Mail: CMGR_EXPUNGE:"));
}
END_TEST

/* 24.8 (checkForNewRetiredContacts): retire flags for each retired contact, and for each name
 * the filters refused since the last iteration, in the ledger or not */
START_TEST(cm_retire_flags)
{
    cfg("ignore_group = red");
    cfg("contact_max_age = 5");
    cfg("retire_flag = RETIRED = $[CONTACT]");
    fixture_f();
    mail_s("NODE_REPORT", "NAME=r1,GROUP=red,TIME=1000,X=0,Y=10");
    mail_s("NODE_REPORT", "NAME=b1,GROUP=blue,TIME=1000,X=0,Y=10");
    it();
    ck_assert_str_eq(last("RETIRED"), "r1");
    ck_assert_int_eq(count("RETIRED"), 1);
    mail_s("NODE_REPORT", "NAME=r1,GROUP=red,TIME=1000,X=0,Y=10");
    it();
    ck_assert_int_eq(count("RETIRED"), 2); /* while it stays refused */
    it();
    ck_assert_int_eq(count("RETIRED"), 2);
    NOW = 1006;
    it();
    ck_assert_str_eq(last("RETIRED"), "b1");
    ck_assert_str_eq(last("CONTACTS_RETIRED"), "b1");
}
END_TEST

/* 24.8 (PlatformAlertRecord): a contact's alert counts survive its retirement */
START_TEST(cm_counts_survive_retirement)
{
    cfg("contact_max_age = 5");
    fixture_f();
    rpt("gus", 0, 15);
    it();
    NOW = 1006;
    it();
    ck_assert_str_eq(last("CONTACTS_RETIRED"), "gus");
    mail_s("NODE_REPORT", "NAME=gus,TIME=1006,X=0,Y=15");
    it();
    ck_assert_int_eq(count("CONTACT_INFO"), 2);
    const char *r = report();
    ck_assert_msg(strstr(r, "gus          15.0    2         1\n") != NULL, "%s", r);
}
END_TEST

/* ------------------------------------------------------------------ scale and limits */

START_TEST(cm_many_contacts_cut)
{
    cfg("max_contacts = 2000");
    fixture_f();
    char name[32];
    for (int i = 0; i < 2000; i++) {
        snprintf(name, sizeof name, "vehicle_%04d", 1999 - i);
        rpt(name, (i % 40) * 40.0 - 800, (i / 40) * 30.0 - 700);
    }
    it();
    ck_assert_uint_eq(C->ncontacts, 2000);
    const char *l = last("CONTACTS_LIST");
    ck_assert_ptr_nonnull(l);
    ck_assert_uint_le(strlen(l), KELP_MAX_SVAL);
    ck_assert(strncmp(l, "vehicle_0000,vehicle_0001,", 26) == 0);
    ck_assert_uint_eq(strlen(l) % 13, 12); /* whole names only */
    ck_assert_int_gt(C->truncations, 0);
    /* ascending order throughout */
    for (unsigned i = 1; i < C->ncontacts; i++)
        ck_assert_int_lt(strcmp(C->contact[C->order[i - 1]].name, C->contact[C->order[i]].name), 0);
    /* lookups find every one */
    ck_assert_int_ge(kelp_contactmgr_find(C, "vehicle_1234"), 0);
    ck_assert_int_lt(kelp_contactmgr_find(C, "vehicle_9999"), 0);
}
END_TEST

START_TEST(cm_bad_config_values)
{
    /* a value 24.8 refuses: the line is not taken (the app warns "Unhandled config line: ..."),
     * the default stays; alert_range is warned deprecated, then not taken */
    ck_assert_int_eq(kelp_contactmgr_config(C, "contact_max_age", "-3", &S), 0);
    ck_assert_int_eq(kelp_contactmgr_config(C, "decay", "30,15", &S), 0);
    ck_assert_int_eq(kelp_contactmgr_config(C, "reject_range", "far", &S), 0);
    cfg("contact_local_coords = sideways"); /* 24.8 takes any value and ignores it */
    ck_assert_int_eq(R->nwarn, 0);
    ck_assert_int_eq(kelp_contactmgr_config(C, "alert_range", "40", &S), 0);
    ck_assert(warned("alert_range is deprecated"));
    ck_assert_int_eq(R->nwarn, 1);
    ck_assert_double_eq(C->contact_max_age, 60); /* 24.8's default */
    ck_assert_double_eq(C->decay[0], 15);
    ck_assert_double_eq(C->reject_range, 2000);
    ck_assert_int_eq(kelp_contactmgr_config(C, "no_such_param", "1", &S), 0);
    cfg("max_contact_age = 60");
    cfg("contacts_recap_interval = 2");
    ck_assert(warned("contacts_recap_interval is deprecated. Use instead: recap_interval"));
    cfg("max_retired_hist = 7");
    ck_assert_double_eq(C->contact_max_age, 60);
    ck_assert_double_eq(C->recap_interval, 2);
    ck_assert_uint_eq(C->max_retired, 7);
    /* alert without id: 24.8 names it no_id */
    clear();
    cfg("alert = on_flag=A=1, alert_range=5");
    ck_assert_int_eq(R->nwarn, 0);
    ck_assert_uint_eq(C->nalerts, 1);
    ck_assert_str_eq(C->alert[0].id, "no_id");
    /* a braced list and legacy var/val */
    cfg("alert = id=avd, alert_range=80, match_group={usv,ship}, var=CONTACT_INFO, val=\"name=$[VNAME]\"");
    ck_assert_uint_eq(C->nalerts, 2);
    ck_assert_uint_eq(C->alert[1].filter.nlist[2][0], 2);
    ck_assert_str_eq(C->alert[1].filter.list[2][0][1], "ship");
    ck_assert_str_eq(C->alert[1].on[0], "CONTACT_INFO=name=$[VNAME]");
    ck_assert_double_eq(C->alert[1].alert_range, 80);
    /* an unbraced list: its second entry is a component of its own, unhandled; "range" is
     * not an alert component in 24.8 */
    clear();
    ck_assert_int_eq(kelp_contactmgr_config(C, "alert", "id=b, alert_range=70, match_group=usv,ship, on_flag=B=1", &S), 0);
    ck_assert(warned("unhandled alert config component: ship"));
    ck_assert_double_eq(C->alert[2].alert_range, 70);
    ck_assert_uint_eq(C->alert[2].non, 0);
    ck_assert_int_eq(kelp_contactmgr_config(C, "alert", "id=b, range=80", &S), 0);
    ck_assert(warned("unhandled alert config component: range"));
}
END_TEST

START_TEST(cm_hold_relbng_maxsize)
{
    cfg("hold_alerts_for_helm = true");
    cfg("post_closest_relbng = true");
    cfg("range_report_maxsize = 2");
    fixture_f();
    nav(0, 0, 90, 0);
    rpt("gus", 0, 15); /* due north of an east-heading ownship: relative bearing 270 */
    it();
    ck_assert_int_eq(count("CONTACT_INFO"), 0);
    ck_assert_str_eq(last("CONTACT_CLOSEST_RELBNG"), "270");
    ck_assert_int_eq(mail_s("IVPHELM_STATE", "DRIVE"), 1);
    it();
    ck_assert_str_eq(last("CONTACT_INFO"), "name=avd_gus # contact=gus");
    /* three report variables with room for two: 24.8 keeps all three until one is
     * range_report_timeout old, then drops the oldest, one per iteration */
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=R1, range=50"), 1);
    NOW += 1;
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=R3, range=50"), 1);
    ck_assert_int_eq(mail_s("BCM_REPORT_REQUEST", "var=R2, range=50"), 1);
    clear();
    it();
    ck_assert_str_eq(last("R1"), "gus");
    ck_assert_str_eq(last("R2"), "gus");
    ck_assert_str_eq(last("R3"), "gus");
    ck_assert_int_lt(index_of("R2", NULL), index_of("R3", NULL)); /* ascending var name */
    NOW += 9.5; /* R1 10.5 s old, R2 and R3 9.5 */
    rpt("gus", 0, 60);
    clear();
    it();
    ck_assert_int_eq(count("R1"), 0);
    ck_assert_str_eq(last("R2"), "");
    ck_assert_str_eq(last("R3"), "");
    ck_assert_uint_eq(C->nreports, 2);
}
END_TEST

/* hold_alerts_for_helm waits until IVPHELM_STATE=DRIVE has been seen once (MOOS-IvP
 * ContactMgrV20::handleMailHelmState latches it): a later PARK does not stop the alerts */
START_TEST(cm_hold_latches_drive)
{
    cfg("hold_alerts_for_helm = true");
    fixture_f();
    ck_assert_int_eq(mail_s("IVPHELM_STATE", "DRIVE"), 1);
    ck_assert_int_eq(mail_s("IVPHELM_STATE", "PARK"), 1);
    rpt("gus", 0, 15);
    it();
    ck_assert_str_eq(last("CONTACT_INFO"), "name=avd_gus # contact=gus");
}
END_TEST

/* an alert with alert_range 0 has its range criterion off: it alerts on its filters alone
 * (MOOS-IvP ContactMgrV20::checkAlertApplies, "alert_range > 0") */
START_TEST(cm_alert_range_zero_filters_only)
{
    cfg("alert = id=reg, on_flag=IN_REG=$[VNAME], off_flag=OUT_REG=$[VNAME], alert_range=0, "
        "match_region=pts={0,100:100,100:100,200:0,200}");
    done();
    ck_assert_ptr_nonnull(strstr(report(), "Alert Ranges: 0/0\n"));
    rpt("far", 50, 150);  /* range 158, inside the region */
    rpt("out", 50, 250);  /* outside the region */
    it();
    ck_assert_str_eq(last("IN_REG"), "far");
    ck_assert_int_eq(count("IN_REG"), 1);
    ck_assert_str_eq(last("CONTACTS_ALERTED"), "(far,reg)");
    rpt("far", 50, 300);  /* leaves the region: off */
    it();
    ck_assert_str_eq(last("OUT_REG"), "far");
}
END_TEST

/* 24.8's defaults: contact_max_age 60 (its constructor), x/y derived from LAT/LON for a report
 * without X/Y (its ledger, with the mission's datum), $[LAT]/$[LON] only as reported (0 else) */
START_TEST(cm_defaults_24_8)
{
    ck_assert_double_eq(C->contact_max_age, 60);
    cfg("alert = id=a, alert_range=200, on_flag=LL=$[LAT]/$[LON]/$[X]");
    done();
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=ben,TIME=1000,LAT=43.8262,LON=-70.3304"), 1);
    ck_assert_int_eq(mail_s("NODE_REPORT", "NAME=cal,TIME=1000,X=5,Y=5"), 1);
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "ben,cal");
    ck_assert_int_ge(index_of("LL", "0/0/5"), 0);
    ck_assert_int_ge(index_of("LL", "43.8262/-70.3304/1.61"), 0); /* x in UTM as 24.8 (PROJ: 1.6075 m) */
    NOW += 61;
    it();
    ck_assert_str_eq(last("CONTACTS_LIST"), "");
}
END_TEST

Suite *kelp_field_contactmgr_suite(void)
{
    Suite *s = suite_create("field_contactmgr");
    TCase *tc = tcase_create("core");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_set_timeout(tc, 30);
    tcase_add_test(tc, cm_config_report_1);
    tcase_add_test(tc, cm_cpa_default_2_3);
    tcase_add_test(tc, cm_invalid_4_6_7);
    tcase_add_test(tc, cm_request_5_8);
    tcase_add_test(tc, cm_flags_9_10_11);
    tcase_add_test(tc, cm_helm_request_12);
    tcase_add_test(tc, cm_action_disable);
    tcase_add_test(tc, cm_trigger_13_14);
    tcase_add_test(tc, cm_trigger_15_to_20);
    tcase_add_test(tc, cm_off_21_22_23);
    tcase_add_test(tc, cm_age_24_25);
    tcase_add_test(tc, cm_ownship_bad_26_27);
    tcase_add_test(tc, cm_macros_28_29);
    tcase_add_test(tc, cm_filter_names_30_31_35);
    tcase_add_test(tc, cm_filter_types_32_33_34_36);
    tcase_add_test(tc, cm_filter_regions_37_38_39);
    tcase_add_test(tc, cm_filter_retire_40);
    tcase_add_test(tc, cm_alert_filters_41_42);
    tcase_add_test(tc, cm_reject_43_44_45);
    tcase_add_test(tc, cm_retired_46_47_48);
    tcase_add_test(tc, cm_forced_49_50_51);
    tcase_add_test(tc, cm_reports_52_to_55_60);
    tcase_add_test(tc, cm_reports_56_57_58);
    tcase_add_test(tc, cm_reports_timeout_59);
    tcase_add_test(tc, cm_closest_61_62_63);
    tcase_add_test(tc, cm_recap_64_65_66);
    tcase_add_test(tc, cm_decay_67_68_69);
    tcase_add_test(tc, cm_cpa_geometry_70_to_79);
    tcase_add_test(tc, cm_coords_80_to_85);
    tcase_add_test(tc, cm_visuals_86_87_88);
    tcase_add_test(tc, cm_verbose_89_report_91);
    tcase_add_test(tc, cm_many_contacts_cut);
    tcase_add_test(tc, cm_bad_config_values);
    tcase_add_test(tc, cm_hold_relbng_maxsize);
    tcase_add_test(tc, cm_hold_latches_drive);
    tcase_add_test(tc, cm_alert_range_zero_filters_only);
    tcase_add_test(tc, cm_able_vars);
    tcase_add_test(tc, cm_retire_flags);
    tcase_add_test(tc, cm_counts_survive_retirement);
    tcase_add_test(tc, cm_early_cease_warnings);
    tcase_add_test(tc, cm_early_warning_radii);
    tcase_add_test(tc, cm_ledger_types);
    tcase_add_test(tc, cm_bad_request_keeps_alert);
    tcase_add_test(tc, cm_report_request_renewal);
    tcase_add_test(tc, cm_defaults_24_8);
    suite_add_tcase(s, tc);
    return s;
}
