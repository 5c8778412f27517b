/* Helm templates and spawning (seed 003 section 4) and BHV_AvoidCollision: the template's
 * alert request, spawning on a new name=, routing of later updates, removal on completion,
 * the instance limit, the avoidance objective in crossing / head-on / overtaking set-ups,
 * priority by range and completion. Uses the ht_* harness of check_helm.c. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/cpa.h>
#include <kelp/helm.h>
#include "check_ht.h"

#define DOM2 "course:0:359:360,speed:0:4:21"

static const char *TEMPLATE = "Behavior = BHV_AvoidCollision\n"
                              "{\n"
                              "  name = avd_\n"
                              "  pwt = 200\n"
                              "  updates = CONTACT_INFO\n"
                              "  templating = spawn\n"
                              "  contact = to-be-set\n"
                              "  on_no_contact_ok = true\n"
                              "  extrapolate = true\n"
                              "  decay = 30,60\n"
                              "  pwt_outer_dist = 50\n"
                              "  pwt_inner_dist = 20\n"
                              "  completed_dist = 75\n"
                              "  min_util_cpa_dist = 8\n"
                              "  max_util_cpa_dist = 25\n"
                              "  pwt_grade = linear\n"
                              "  bearing_lines = white:0, green:0.65, yellow:0.8, red:1.0\n"
                              "  match_type = kayak\n"
                              "}\n";

static void own(double x, double y, double h, double v)
{
    kelp_helm *hp = ht_helm();
    kelp_helm_mail_double(hp, "NAV_X", x);
    kelp_helm_mail_double(hp, "NAV_Y", y);
    kelp_helm_mail_double(hp, "NAV_HEADING", h);
    kelp_helm_mail_double(hp, "NAV_SPEED", v);
}

/* a contact report at MOOS time 1000 + t */
static void report(const char *name, double t, double x, double y, double h, double v)
{
    char buf[256];
    snprintf(buf, sizeof buf, "NAME=%s,TYPE=kayak,TIME=%.2f,X=%.2f,Y=%.2f,SPD=%.2f,HDG=%.2f", name, 1000 + t, x, y, v, h);
    kelp_helm_mail_string(ht_helm(), "NODE_REPORT", buf);
}

START_TEST(template_posts_alert_request_and_does_not_run)
{
    kelp_helm *h = ht_setup(DOM2, NULL);
    ht_load(TEMPLATE);
    ck_assert_uint_eq(h->nbhv, 0);
    ck_assert_uint_eq(h->ntmpl, 1);
    ck_assert_ptr_nonnull(kelp_helm_find_template(h, "avd_"));
    /* MOOS-IvP's exact string: no space before alert_range, the filter summary joined by "," */
    ck_assert(ht_has_str("BCM_ALERT_REQUEST", "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],"
                                              "alert_range=50, cpa_range=75,match_type=kayak"));
    /* a template is no behaviour of the set: its update variable is in no IVPHELM_UPDATEVARS */
    ck_assert_uint_eq(ht_count("IVPHELM_UPDATEVARS"), 0);
    own(0, 0, 90, 2);
    ht_iter(1);
    ck_assert_uint_eq(h->rep.ofnum, 0);
    ck_assert_uint_eq(ht_count("IVPHELM_BHV_CNT"), 0); /* 0: 24.8 posts the count when it changes from 0 */
    ck_assert_str_eq(ht_last("IVPHELM_ALLSTOP")->sval, "NothingToDo");
    /* no_alert_request silences it; a non-template posts none */
    ht_setup(DOM2, NULL);
    char text[2048];
    snprintf(text, sizeof text, "%s", TEMPLATE);
    char *brace = strrchr(text, '}');
    snprintf(brace, sizeof text - (size_t)(brace - text), "  no_alert_request = true\n}\n");
    ht_load(text);
    ck_assert_uint_eq(ht_count("BCM_ALERT_REQUEST"), 0);
}
END_TEST

START_TEST(spawn_route_and_remove)
{
    kelp_helm *h = ht_setup(DOM2, NULL);
    ht_load(TEMPLATE);
    own(0, 0, 90, 2);
    report("henry", 1, 40, 0, 270, 1);
    kelp_helm_mail_string(h, "CONTACT_INFO", "name=henry # contact=henry");
    ht_iter(1);
    kelp_bhv *b = kelp_helm_find(h, "avd_henry");
    ck_assert_ptr_nonnull(b);
    ck_assert(b->spawned);
    ck_assert_str_eq(b->u.avoid.contact, "HENRY"); /* MOOS-IvP keeps the contact upper-case */
    ck_assert_double_eq(b->u.avoid.completed_dist, 75);   /* the template's configuration */
    ck_assert_uint_eq(h->nspawned, 1);
    ck_assert(ht_has_sub("IVPHELM_LIFE_EVENT", "bname=avd_henry, btype=BHV_AvoidCollision, event=spawn, "
                                               "seed=name=henry # contact=henry"));
    ck_assert_double_eq(ht_num("IVPHELM_BHV_CNT"), 1);
    ck_assert_double_eq(ht_num("IVPHELM_BHV_CNT_EVER"), 1);
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 0); /* MOOS-IvP's BHV_AvoidCollision posts none */
    ck_assert_uint_eq(h->rep.ofnum, 1);   /* 40 m away: inside pwt_outer_dist */
    /* MOOS-IvP's XYSegList spec for the bearing line (relevance 1/3: green) */
    ck_assert(ht_has_str("VIEW_SEGLIST", "pts={0,0:40,0},label=alder_avd_henry,label_color=pink,edge_color=green,"
                                         "time=1001,duration=100"));
    /* the full name is accepted too, and a second contact spawns a second instance */
    kelp_helm_mail_string(h, "CONTACT_INFO", "name=avd_henry # pwt_outer_dist=60");
    kelp_helm_mail_string(h, "CONTACT_INFO", "name=ike # contact=ike");
    report("henry", 2, 38, 0, 270, 1);
    ht_iter(2);
    ck_assert_uint_eq(h->nspawned, 2);
    b = kelp_helm_find(h, "avd_henry");
    kelp_bhv *c = kelp_helm_find(h, "avd_ike");
    ck_assert_ptr_nonnull(c);
    ck_assert_double_eq(b->u.avoid.pwt_outer_dist, 60);
    ck_assert_double_eq(c->u.avoid.pwt_outer_dist, 50);
    ck_assert(ht_has_sub("IVPHELM_UPDATE_RESULT", "bhv=avd_ike,var=CONTACT_INFO,time=2.00,result=name_mismatch"));
    ck_assert(ht_has_sub("IVPHELM_UPDATE_RESULT", "bhv=avd_henry,var=CONTACT_INFO,time=2.00,result=success,"
                                                  "val=name=avd_henry # pwt_outer_dist=60"));
    /* the same alert again spawns nothing new */
    kelp_helm_mail_string(h, "CONTACT_INFO", "name=henry # contact=henry");
    ht_iter(3);
    ck_assert_uint_eq(h->nspawned, 2);
    ck_assert_uint_eq(ht_count("IVPHELM_LIFE_EVENT"), 0);
    /* henry goes past 1.1 x completed_dist: completes and is removed that iteration */
    report("henry", 4, 90, 0, 90, 1);
    ht_iter(4);
    ck_assert_ptr_null(kelp_helm_find(h, "avd_henry"));
    ck_assert_uint_eq(h->nspawned, 1);
    ck_assert(ht_has_sub("IVPHELM_LIFE_EVENT", "bname=avd_henry, btype=BHV_AvoidCollision, event=death"));
    ck_assert_double_eq(ht_num("IVPHELM_COMPLETED_COUNT"), 1);
    ht_iter(5);
    ck_assert_double_eq(ht_num("IVPHELM_BHV_CNT"), 1);
    ck_assert_uint_eq(ht_count("IVPHELM_BHV_CNT_EVER"), 0); /* unchanged: not posted */
    ck_assert_uint_eq(h->bhv_cnt_ever, 2);
    ck_assert_ptr_nonnull(kelp_helm_find(h, "avd_ike"));
    /* a later alert for henry spawns a fresh instance, whose posts are not filtered as repeats */
    report("henry", 6, 45, 0, 270, 1);
    kelp_helm_mail_string(h, "CONTACT_INFO", "name=henry # contact=henry");
    ht_iter(6);
    b = kelp_helm_find(h, "avd_henry");
    ck_assert_ptr_nonnull(b);
    ck_assert_double_eq(b->u.avoid.pwt_outer_dist, 50);
    ck_assert(ht_has_sub("BHV_STATUS", "name=avd_henry,"));
    ck_assert_double_eq(ht_num("IVPHELM_BHV_CNT_EVER"), 3);
}
END_TEST

START_TEST(spawn_bad_params_and_limits)
{
    kelp_helm *h = ht_setup(DOM2, NULL);
    char text[2048];
    snprintf(text, sizeof text, "%s", TEMPLATE);
    char *brace = strrchr(text, '}');
    snprintf(brace, sizeof text - (size_t)(brace - text), "  max_spawnings = 30\n}\n");
    ht_load(text);
    own(0, 0, 90, 2);
    kelp_helm_mail_string(h, "CONTACT_INFO", "name=bad # contact=bad # pwt_grade=steep");
    ht_iter(1);
    ck_assert_ptr_null(kelp_helm_find(h, "avd_bad"));
    ck_assert(ht_has_sub("IVPHELM_LIFE_EVENT", "bname=avd_bad, btype=BHV_AvoidCollision, event=abort"));
    ck_assert(ht_has_sub("BHV_WARNING", "Failed to spawn avd_bad"));
    ck_assert_uint_eq(h->nspawned, 0);
    /* one update message per iteration (a contact manager alert each) up to the limit and past it */
    for (int i = 0; i < KELP_HELM_MAX_SPAWNED + 2; i++) {
        char msg[64];
        snprintf(msg, sizeof msg, "name=c%02d # contact=c%02d", i, i);
        kelp_helm_mail_string(h, "CONTACT_INFO", msg);
        ht_iter(2 + i);
        if (i < KELP_HELM_MAX_SPAWNED) ck_assert_uint_eq(h->nspawned, (unsigned)i + 1);
    }
    ck_assert_uint_eq(h->nspawned, KELP_HELM_MAX_SPAWNED);
    ck_assert_uint_eq(h->spawn_refused, 2);
    ck_assert(ht_has_sub("BHV_WARNING", "refused: KELP_HELM_MAX_SPAWNED instances alive"));
    ck_assert_ptr_null(kelp_helm_find(h, "avd_c25"));
    ck_assert_uint_eq(kelp_helm_find_template(h, "avd_")->spawns_made, KELP_HELM_MAX_SPAWNED);
}
END_TEST

START_TEST(template_max_spawnings)
{
    kelp_helm *h = ht_setup(DOM2, NULL);
    char text[2048];
    snprintf(text, sizeof text, "%s", TEMPLATE);
    char *brace = strrchr(text, '}');
    snprintf(brace, sizeof text - (size_t)(brace - text), "  max_spawnings = 1\n}\n");
    ht_load(text);
    own(0, 0, 90, 2);
    kelp_helm_mail_string(h, "CONTACT_INFO", "name=a # contact=a");
    kelp_helm_mail_string(h, "CONTACT_INFO", "name=b # contact=b");
    ht_iter(1);
    ck_assert_ptr_nonnull(kelp_helm_find(h, "avd_a"));
    ck_assert_ptr_null(kelp_helm_find(h, "avd_b"));
    ck_assert(ht_has_sub("BHV_WARNING", "max_spawnings reached"));
    ck_assert_int_eq(ht_load_rc("Behavior = BHV_AvoidCollision\n{\n  max_spawnings = -1\n}\n") < 0, 1);
}
END_TEST

/* ------------------------------------------------------------ the avoidance behaviour */

static const char *STATIC_AVD = "Behavior = BHV_AvoidCollision\n"
                                "{\n"
                                "  name = avd\n"
                                "  pwt = 200\n"
                                "  contact = v1\n"
                                "  extrapolate = false\n"
                                "}\n";

static double decided_cpa(double cnx, double cny, double cnh, double cnv)
{
    kelp_helm *h = ht_helm();
    ck_assert(h->rep.decided[0] && h->rep.decided[1]);
    return kelp_cpa_range(cnx, cny, cnh, cnv, 0, 0, h->rep.decision[0], h->rep.decision[1], 120, NULL);
}

static void encounter(const char *extra, double cnx, double cny, double cnh, double cnv, double osh, double osv,
                      double want)
{
    char text[2048];
    snprintf(text, sizeof text, "%s%s", STATIC_AVD, extra);
    ht_setup(DOM2, NULL);
    ht_load(text);
    own(0, 0, osh, osv);
    report("v1", 1, cnx, cny, cnh, cnv);
    ck_assert(kelp_cpa_range(cnx, cny, cnh, cnv, 0, 0, osh, osv, 120, NULL) < 1); /* staying on is a collision */
    ht_iter(1);
    ck_assert_uint_eq(ht_helm()->rep.ofnum, extra[0] ? 2 : 1);
    double cpa = decided_cpa(cnx, cny, cnh, cnv);
    ck_assert_msg(cpa >= want, "decision %.1f deg %.2f m/s: cpa %.2f m < %.1f", ht_helm()->rep.decision[0],
                  ht_helm()->rep.decision[1], cpa, want);
}

static const char *WPT_EAST = "Behavior = BHV_Waypoint\n{\n  name = transit\n  pwt = 100\n  speed = 2\n"
                              "  points = 400,0\n}\n";
static const char *WPT_NORTH = "Behavior = BHV_Waypoint\n{\n  name = transit\n  pwt = 100\n  speed = 3\n"
                               "  points = 0,400\n}\n";

START_TEST(of_clears_crossing_headon_overtaking)
{
    /* alone, the avoidance objective picks a (course, speed) with a CPA near max_util_cpa_dist */
    encounter("", 60, -60, 0, 2, 90, 2, 60);      /* crossing from starboard */
    encounter("", 100, 0, 270, 2, 90, 2, 60);     /* head-on */
    encounter("", 0, 60, 0, 1, 0, 3, 55);         /* overtaking a slower vessel */
    /* with a waypoint pulling straight through the contact, the decision still clears it */
    encounter(WPT_EAST, 60, -60, 0, 2, 90, 2, 10);
    encounter(WPT_EAST, 100, 0, 270, 2, 90, 2, 10);
    encounter(WPT_NORTH, 0, 60, 0, 1, 0, 3, 10);
}
END_TEST

START_TEST(of_values_and_relevance)
{
    /* the objective: 0 below min_util, 25..100 linear between, 100 above max_util */
    kelp_bhv_avoid_aof f = {.min_util = 10, .max_util = 75, .icrs = 0, .ispd = 1};
    kelp_cpa_vessel cn = {100, 0, 270, 2};
    ck_assert_int_eq(kelp_cpa_fast_init(&f.cpa, &cn, 0, 0, 120), KELP_OK);
    double p[2] = {90, 2};
    ck_assert_double_eq(kelp_helm_bhv_avoid_aof_eval(p, &f), 0);         /* straight at it */
    p[1] = 0;                                                       /* stop: CPA = 0 as it comes on */
    ck_assert_double_eq(kelp_helm_bhv_avoid_aof_eval(p, &f), 0);
    p[0] = 0, p[1] = 2;                                             /* north at 2: CPA = 100/sqrt2 */
    ck_assert_double_eq_tol(kelp_helm_bhv_avoid_aof_eval(p, &f), 25 + 75 * (100 / sqrt(2) - 10) / 65, 1e-9);
    kelp_cpa_vessel far = {0, 200, 0, 0};
    ck_assert_int_eq(kelp_cpa_fast_init(&f.cpa, &far, 0, 0, 120), KELP_OK);
    p[0] = 180;
    ck_assert_double_eq(kelp_helm_bhv_avoid_aof_eval(p, &f), 100);
    /* relevance by grade */
    ck_assert_double_eq(kelp_helm_bhv_avoid_relevance(250, 50, 200, 0), 0);
    ck_assert_double_eq(kelp_helm_bhv_avoid_relevance(200, 50, 200, 0), 0);
    ck_assert_double_eq_tol(kelp_helm_bhv_avoid_relevance(125, 50, 200, 0), 0.5, 1e-12);
    ck_assert_double_eq_tol(kelp_helm_bhv_avoid_relevance(125, 50, 200, 1), 0.25, 1e-12);
    ck_assert_double_eq_tol(kelp_helm_bhv_avoid_relevance(125, 50, 200, 2), pow(0.5, 1.5), 1e-12);
    ck_assert_double_eq(kelp_helm_bhv_avoid_relevance(50, 50, 200, 2), 1);
    /* inside the inner ring MOOS-IvP's getRelevance keeps grading past 1 (it does not cap) */
    ck_assert_double_eq_tol(kelp_helm_bhv_avoid_relevance(5, 50, 200, 1), 1.3 * 1.3, 1e-12);
    ck_assert_double_eq_tol(kelp_helm_bhv_avoid_relevance(20, 50, 200, 0), 1.2, 1e-12);
    ck_assert_double_eq(kelp_helm_bhv_avoid_relevance(5, 50, 50, 0), 1); /* degenerate rings: 1 */
}
END_TEST

static double pwt_at(double range, const char *grade)
{
    char text[1024];
    snprintf(text, sizeof text, "Behavior = BHV_AvoidCollision\n{\n  name = avd\n  pwt = 100\n  contact = v1\n"
                                "  extrapolate = false\n  pwt_grade = %s\n}\n", grade);
    kelp_helm *h = ht_setup(DOM2, NULL);
    ht_load(text);
    own(0, 0, 90, 2);
    report("v1", 1, range, 0, 270, 1);
    ht_iter(1);
    if (h->rep.ofnum == 0) return 0;
    return h->fn[0].pwt;
}

START_TEST(priority_by_range)
{
    ck_assert_double_eq(pwt_at(250, "linear"), 0);
    ck_assert_double_eq(pwt_at(200, "linear"), 0);
    ck_assert_double_eq_tol(pwt_at(125, "linear"), 50, 1e-9);
    ck_assert_double_eq_tol(pwt_at(125, "quadratic"), 25, 1e-9);
    ck_assert_double_eq_tol(pwt_at(125, "quasi"), 100 * pow(0.5, 1.5), 1e-9);
    ck_assert_double_eq_tol(pwt_at(50, "quasi"), 100, 1e-9);
    ck_assert_double_eq_tol(pwt_at(20, "linear"), 120, 1e-9); /* MOOS-IvP: no cap inside the inner ring */
}
END_TEST

START_TEST(completion_and_extrapolation)
{
    kelp_helm *h = ht_setup(DOM2, NULL);
    ht_load(STATIC_AVD);
    own(0, 0, 90, 2);
    report("v1", 1, 540, 0, 90, 1); /* inside 1.1 x 500 */
    ht_iter(1);
    kelp_bhv *b = kelp_helm_find(h, "avd");
    ck_assert(!b->completed);
    report("v1", 2, 551, 0, 90, 1);
    ht_iter(2);
    ck_assert(b->completed);
    ht_iter(3);
    ck_assert_int_eq(b->state, KELP_BHV_COMPLETED);
    ck_assert_ptr_nonnull(kelp_helm_find(h, "avd")); /* a .bhv behaviour stays listed */
    /* extrapolation: a 2 m/s contact last heard 10 s ago moved 20 m (decay 15,30) */
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_AvoidCollision\n{\n  name = avd\n  contact = v1\n}\n");
    own(0, 0, 90, 2);
    report("v1", 0, 100, 0, 0, 2);
    ht_iter(10);
    b = kelp_helm_find(ht_helm(), "avd");
    ck_assert_double_eq_tol(b->u.avoid.cn.y, 20, 1e-9);
    ck_assert_double_eq_tol(b->u.avoid.range, hypot(100, 20), 1e-9);
    /* ownship's own report is not a contact; a malformed one is dropped */
    ck_assert_int_eq(kelp_helm_ledger_report(ht_helm(), "NAME=alder,X=1,Y=2"), 0);
    ck_assert_ptr_null(kelp_helm_contact_get(ht_helm(), "alder"));
    ck_assert_int_eq(kelp_helm_ledger_report(ht_helm(), "NAME=x,X=abc"), KELP_ERR_PARSE);
    /* no contact report: a warning with on_no_contact_ok (default), an error without it */
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_AvoidCollision\n{\n  name = avd\n  contact = ghost\n  on_no_contact_ok = false\n}\n");
    own(0, 0, 90, 2);
    ht_iter(1);
    ck_assert(ht_has_sub("BHV_ERROR", "GHOST x/y/heading/speed info not found"));
    /* with on_no_contact_ok (the default) MOOS-IvP says nothing and builds no function */
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_AvoidCollision\n{\n  name = avd\n  contact = ghost\n}\n");
    own(0, 0, 90, 2);
    ht_iter(1);
    ck_assert(!ht_has_sub("BHV_WARNING", "info not found"));
    ck_assert(!ht_has_sub("BHV_ERROR", "info not found"));
    ck_assert_uint_eq(ht_helm()->rep.ofnum, 0);
}
END_TEST

START_TEST(avoid_params)
{
    ht_setup(DOM2, NULL);
    ck_assert_int_eq(ht_load_rc("Behavior = BHV_AvoidCollision\n{\n  name = a\n  contact = v\n"
                                "  pwt_outer_dist = 300\n  pwt_inner_dist = 400\n  min_util_cpa_dist = 5\n"
                                "  max_util_cpa_dist = 50\n  completed_dist = 100\n  roc_max_heighten = 3\n"
                                "  roc_max_dampen = 1\n  bearing_line_show = true\n  bearing_line_label_show = false\n"
                                "  bearing_lines = white:0, red:1.0, info:range\n  decay = 5,10\n  time_on_leg = 60\n"
                                "  ignore_name = v9\n  match_group = blue\n  ignore_group = red\n  strict_ignore = false\n"
                                "  match_region = pts={0,0:100,0:100,100}\n  exit_on_filter_vtype = true\n"
                                "  exit_on_filter_group = true\n  exit_on_filter_region = true\n"
                                "  post_per_contact_info = true\n  cnflag = <20 CLOSE=true\n  use_refinery = true\n"
                                "  check_plateaus = false\n  check_validity = false\n  pcheck_thresh = 0.01\n"
                                "  verbose = false\n  can_disable = true\n  use_plat_model = false\n"
                                "  contact_type_required = kayak\n  no_alert_request = false\n  decay_end = 12\n}\n"),
                     0);
    kelp_bhv *b = kelp_helm_find(ht_helm(), "a");
    ck_assert_double_eq(b->u.avoid.pwt_inner_dist, 400);
    ck_assert_double_eq(b->u.avoid.pwt_outer_dist, 400); /* raised with the inner one */
    /* kept as given: MOOS-IvP's "completed_dist >= pwt_outer_dist" safety check sits after
     * every handled parameter has returned, so a valid configuration never reaches it */
    ck_assert_double_eq(b->u.avoid.completed_dist, 100);
    ck_assert_uint_eq(b->u.avoid.nlines, 2);
    ck_assert(b->u.avoid.bearing_info_range);
    ck_assert_str_eq(b->u.avoid.match_type[0], "kayak");
    ht_setup(DOM2, NULL);
    ck_assert_int_lt(ht_load_rc("Behavior = BHV_AvoidCollision\n{\n  pwt_grade = steep\n}\n"), 0);
    ht_setup(DOM2, NULL);
    ck_assert_int_lt(ht_load_rc("Behavior = BHV_AvoidCollision\n{\n  completed_dist = -1\n}\n"), 0);
    /* bearing_lines never fails (MOOS-IvP): a bad component stops further colours */
    ht_setup(DOM2, NULL);
    ck_assert_int_eq(ht_load_rc("Behavior = BHV_AvoidCollision\n{\n  name = bl\n  bearing_lines = white\n}\n"), 0);
    b = kelp_helm_find(ht_helm(), "bl");
    ck_assert(!b->u.avoid.bearing_line_show);
    ht_setup(DOM2, NULL);
    ck_assert_int_eq(ht_load_rc("Behavior = BHV_AvoidCollision\n{\n  name = bl\n"
                                "  bearing_lines = White:0, junk, red:1, info:range\n}\n"), 0);
    b = kelp_helm_find(ht_helm(), "bl");
    ck_assert_uint_eq(b->u.avoid.nlines, 1);
    ck_assert_str_eq(b->u.avoid.line_color[0], "white");
    ck_assert(b->u.avoid.bearing_info_range);
    ht_setup("depth:0:100:101", NULL); /* no course/speed: refused */
    ck_assert_int_lt(ht_load_rc("Behavior = BHV_AvoidCollision\n{\n  contact = v\n}\n"), 0);
}
END_TEST

/* IvPContactBehavior's filter lists (ExFilterSet): lower-cased, comma lists split, braces
 * stripped, kept sorted; the alert request carries them in that order, ignore before match,
 * name/group/type kinds as MOOS-IvP's getSummary, strict_ignore only with ignore_type/_group */
START_TEST(avoid_filter_lists_and_request)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_AvoidCollision\n{\n  name = avd_\n  updates = CONTACT_INFO\n"
            "  templating = spawn\n  contact = to-be-set\n  pwt_outer_dist = 50\n  completed_dist = 75\n"
            "  match_name = {Zed,abe}\n  ignore_type = Tug, cargo\n  match_type = kayak\n}\n");
    ck_assert(ht_has_str("BCM_ALERT_REQUEST", "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],"
                                              "alert_range=50, cpa_range=75,match_name=abe, match_name=zed, "
                                              "ignore_type=cargo, ignore_type=tug, match_type=kayak, "
                                              "strict_ignore=true"));
    /* a comma list of types in a running behaviour: each one matches */
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_AvoidCollision\n{\n  name = a\n  contact = Henry\n  match_type = kayak, Cargo\n"
            "  exit_on_filter_vtype = true\n  post_per_contact_info = true\n}\n");
    kelp_bhv *b = kelp_helm_find(ht_helm(), "a");
    ck_assert_uint_eq(b->u.avoid.nmatch_type, 2);
    ck_assert_str_eq(b->u.avoid.match_type[0], "cargo");
    own(0, 0, 90, 2);
    kelp_helm_mail_string(ht_helm(), "NODE_REPORT", "NAME=henry,TYPE=cargo,TIME=1001,X=40,Y=0,SPD=1,HDG=270");
    ht_iter(1);
    ck_assert_uint_eq(ht_helm()->rep.ofnum, 1);  /* the filter holds: the behaviour runs */
    ck_assert(ht_last("RANGE_AVD_HENRY") != NULL); /* MOOS-IvP posts with the upper-case contact */
    /* the same entry matched and ignored is a bad parameter */
    ht_setup(DOM2, NULL);
    ck_assert_int_lt(ht_load_rc("Behavior = BHV_AvoidCollision\n{\n  match_type = kayak\n  ignore_type = Kayak\n}\n"),
                     0);
}
END_TEST

/* cnflag tags as IvPContactBehavior: "<R" / ">R" posted while within / beyond R, "@<R" / "@>R"
 * once when the range crosses R inward / outward; $[CN_NAME], $[RANGE] expanded, a value of
 * just $[RANGE] posted as a number; an unknown tag is a bad parameter */
START_TEST(avoid_cnflag_transitions)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_AvoidCollision\n{\n  name = a\n  contact = henry\n  extrapolate = false\n"
            "  cnflag = @<30 NEAR=$[CN_NAME] at $[RANGE]\n  cnflag = @>30 FAR=$[RANGE]\n"
            "  cnflag = <30 IN=$[CN_NAME]\n}\n");
    own(0, 0, 90, 0);
    report("henry", 1, 40, 0, 270, 1);
    ht_iter(1);
    ck_assert_uint_eq(ht_count("NEAR"), 0);
    ck_assert_uint_eq(ht_count("FAR"), 0);   /* no crossing on the first update */
    report("henry", 2, 25, 0, 270, 1);
    ht_iter(2);
    ck_assert_uint_eq(ht_count("NEAR"), 1);
    ck_assert_str_eq(ht_last("NEAR")->sval, "HENRY at 25");
    ck_assert_str_eq(ht_last("IN")->sval, "HENRY");
    report("henry", 3, 24, 0, 270, 1);
    ht_iter(3);
    ck_assert_uint_eq(ht_count("NEAR"), 0);  /* still inside: no new crossing (posts are per iteration) */
    ck_assert_uint_eq(ht_count("IN"), 1);    /* "<" posts every time */
    report("henry", 4, 35.5, 0, 270, 1);
    ht_iter(4);
    ck_assert_uint_eq(ht_count("FAR"), 1);
    ck_assert(!ht_last("FAR")->is_str);
    ck_assert_double_eq_tol(ht_last("FAR")->dval, 35.5, 1e-9);
    ht_setup(DOM2, NULL);
    ck_assert_int_lt(ht_load_rc("Behavior = BHV_AvoidCollision\n{\n  cnflag = @near X=1\n}\n"), 0);
}
END_TEST

/* flag macros as IvPBehavior::expandMacros (and IvPContactBehavior's): $[CONTACT] (upper-case),
 * $[BHVNAME], $[OWNSHIP], $[BHVTYPE], $[PWT]; a flag whose value is one macro expanding to a
 * number is posted as a number; unknown macros stay as written */
START_TEST(avoid_flag_macros)
{
    kelp_helm *h = ht_setup(DOM2, NULL);
    char text[2048];
    snprintf(text, sizeof text, "%s", TEMPLATE);
    char *brace = strrchr(text, '}');
    snprintf(brace, sizeof text - (size_t)(brace - text),
             "  endflag = CONTACT_RESOLVED = $[CONTACT]\n  spawnflag = SPAWNED = $[BHVNAME] of $[OWNSHIP] "
             "($[BHVTYPE]) $[NOPE]\n  spawnflag = SPWT = $[PWT]\n}\n");
    ht_load(text);
    own(0, 0, 90, 2);
    report("henry", 1, 40, 0, 270, 1);
    kelp_helm_mail_string(h, "CONTACT_INFO", "name=henry # contact=henry");
    ht_iter(1);
    ck_assert_ptr_nonnull(kelp_helm_find(h, "avd_henry"));
    ck_assert_str_eq(ht_last("SPAWNED")->sval, "avd_henry of alder (BHV_AvoidCollision) $[NOPE]");
    ck_assert(!ht_last("SPWT")->is_str);
    ck_assert_double_eq(ht_last("SPWT")->dval, 200);
    report("henry", 2, 90, 0, 90, 1);
    ht_iter(2);
    ck_assert_ptr_null(kelp_helm_find(h, "avd_henry"));
    ck_assert_str_eq(ht_last("CONTACT_RESOLVED")->sval, "HENRY");
}
END_TEST

Suite *kelp_helm_spawn_suite(void)
{
    Suite *s = suite_create("helm_spawn");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, template_posts_alert_request_and_does_not_run);
    tcase_add_test(tc, spawn_route_and_remove);
    tcase_add_test(tc, spawn_bad_params_and_limits);
    tcase_add_test(tc, template_max_spawnings);
    tcase_add_test(tc, of_clears_crossing_headon_overtaking);
    tcase_add_test(tc, of_values_and_relevance);
    tcase_add_test(tc, priority_by_range);
    tcase_add_test(tc, completion_and_extrapolation);
    tcase_add_test(tc, avoid_params);
    tcase_add_test(tc, avoid_filter_lists_and_request);
    tcase_add_test(tc, avoid_cnflag_transitions);
    tcase_add_test(tc, avoid_flag_macros);
    suite_add_tcase(s, tc);
    return s;
}
