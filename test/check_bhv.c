/* Behaviour unit tests: BHV_SimpleWaypoint against seed 004 chapter 5 (parameters, the ZAIC
 * pieces of Figure 5, the coupled function, the Reflector's underlying function, postings,
 * the Alder mission flown against a kinematic vehicle), BHV_Waypoint and the
 * constant behaviours. Uses the ht_* harness of check_helm.c. */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/helm.h>
#include "../src/helm/helm_int.h"
#include "check_ht.h"

#define DOM2 "course:0:359:360,speed:0:4:21"

static void nav(double x, double y)
{
    kelp_helm_mail_double(ht_helm(), "NAV_X", x);
    kelp_helm_mail_double(ht_helm(), "NAV_Y", y);
    kelp_helm_mail_double(ht_helm(), "NAV_HEADING", 0); /* 24.8's waypoint needs a heading */
}

/* ---------------------------------------------------------------- relAng */

START_TEST(relang_examples)
{
    ck_assert(kelp_helm_relang(0, 0, 0, 10) == 0);
    ck_assert(fabs(kelp_helm_relang(0, 0, 10, 0) - 90) < 1e-9);
    ck_assert(fabs(kelp_helm_relang(0, 0, 0, -10) - 180) < 1e-9);
    ck_assert(fabs(kelp_helm_relang(0, 0, -10, 0) - 270) < 1e-9);
    ck_assert(fabs(kelp_helm_relang(0, 0, 60, -40) - 123.690068) < 1e-6);
    ck_assert(kelp_helm_relang(5, 5, 5, 5) == 0);
    ck_assert(fabs(kelp_helm_relang(58, -38, 0, 0) - 303.2317) < 1e-3);
}
END_TEST

/* ---------------------------------------------------------------- SimpleWaypoint */

START_TEST(swpt_zaic_pieces_figure5)
{
    /* Listing 13 over the Alder domain: speed function 6 pieces, course function 3 pieces
     * (Figure 5), coupled 50/50 into 18 pieces normalised to [0,100] (Figure 6). */
    kelp_helm *h = ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_SimpleWaypoint\n{\n speed = 2.0\n ptx = 60\n pty = -40\n}\n");
    kelp_bhv *b = ht_find("simple_waypoint");
    kelp_helm_work w = {h->mem.pool, h->mem.pool_cap, h->mem.tmp, h->mem.tmp_cap, h->mem.dwork, h->mem.dwork_cap,
                        h->mem.pq, h->mem.pq_cap};
    kelp_ivp_func spd, crs, cp;
    ck_assert_int_eq(bhv_zaic1(b, &w, "speed", 2.0, 0.5, 1.0, 0.8, false, &spd), 0);
    ck_assert_uint_eq(spd.n, 6);
    kelp_helm_work w2 = w;
    w2.out += 100;
    w2.out_cap -= 100;
    double rel = kelp_helm_relang(0, 0, 60, -40);
    ck_assert_int_eq(bhv_zaic1(b, &w2, "course", rel, 0, 180, 0, true, &crs), 0);
    ck_assert_uint_eq(crs.n, 3);
    kelp_helm_work w3 = w;
    w3.out += 1000;
    w3.out_cap -= 1000;
    ck_assert_int_eq(bhv_course_speed_zaic(b, &w3, rel, 2.0, 0.5, 1.0, 0.8, &cp), 0);
    ck_assert_uint_eq(cp.n, 18);
    double mn, mx;
    ck_assert_int_eq(kelp_ivp_func_range(&cp, &mn, &mx), 0);
    ck_assert(fabs(mx - 100) < 1e-9 && fabs(mn) < 1e-9);
    /* peak: course 124 (nearest point to 123.69), speed 2.0 (index 10) */
    ck_assert(fabs(ht_eval2(&cp, 124, 10) - 100) < 0.6);
    ck_assert(ht_eval2(&cp, 124, 10) > ht_eval2(&cp, 123, 10));
    ck_assert(ht_eval2(&cp, 124, 10) > ht_eval2(&cp, 124, 9));
    ck_assert(ht_eval2(&cp, 124, 10) > ht_eval2(&cp, 124, 11));
    /* course 180 degrees off (304) at speed 0: the minimum */
    ck_assert(fabs(ht_eval2(&cp, 304, 0)) < 1.0);
}
END_TEST

START_TEST(swpt_reflector_aof_values)
{
    /* AOF_SimpleWaypoint: 0.75 rate-of-closure + 0.2 rate-of-detour + 0.05 speed deviation */
    kelp_bhv_swpt_aof a = {2.0, 0, 0, 60, -40, 0, 0, 4, 0, 1};
    a.angle_to_wpt = kelp_helm_relang(0, 0, 60, -40);
    double on[2] = {a.angle_to_wpt, 2.0};
    ck_assert(fabs(kelp_helm_bhv_swpt_aof_eval(on, &a) - 100) < 1e-9);
    double back[2] = {a.angle_to_wpt + 180, 2.0};
    /* roc -2: diff 4 -> 50; rod 180*2 -> 50; speed exact -> 100: 37.5 + 10 + 5 */
    ck_assert(fabs(kelp_helm_bhv_swpt_aof_eval(back, &a) - 52.5) < 1e-9);
    double slow[2] = {a.angle_to_wpt, 0.0};
    /* roc 0: diff 2 -> 75; rod 0 -> 100; speed diff 2 of range 2 -> 0: 56.25 + 20 + 0 */
    ck_assert(fabs(kelp_helm_bhv_swpt_aof_eval(slow, &a) - 76.25) < 1e-9);
    double fast[2] = {a.angle_to_wpt, 4.0};
    /* roc 4: diff -2 -> *-0.5 = 1 -> 87.5; rod 0 -> 100; speed diff 2 -> 0: 65.625 + 20 */
    ck_assert(fabs(kelp_helm_bhv_swpt_aof_eval(fast, &a) - 85.625) < 1e-9);
}
END_TEST

START_TEST(swpt_reflector_function)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_SimpleWaypoint\n{\n name = waypt_return\n speed = 2.0\n ptx = 0\n pty = 0\n ipf_type = reflector\n}\n");
    nav(58, -38);
    ht_iter(0);
    kelp_helm *h = ht_helm();
    ck_assert_int_eq(ht_find("waypt_return")->state, KELP_BHV_ACTIVE);
    ck_assert(h->fn[0].n >= 500 && h->fn[0].n <= 1100); /* ~1000 requested pieces */
    double crs = ht_num("DESIRED_HEADING");
    ck_assert_msg(fabs(crs - 303.23) <= 3.0, "heading %g", crs);
    /* the 1000-piece approximation of the peak at 2.0 m/s peaks one 0.2 step away at most */
    ck_assert_msg(fabs(ht_num("DESIRED_SPEED") - 2.0) <= 0.21, "speed %g", ht_num("DESIRED_SPEED"));
}
END_TEST

START_TEST(swpt_no_nav_warning)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_SimpleWaypoint\n{\n name = transit\n speed = 2.0\n ptx = 60\n pty = -40\n}\n");
    ht_iter(0);
    ck_assert(ht_has_str("BHV_WARNING", "transit: No ownship X/Y info in info_buffer."));
    ck_assert_int_eq(ht_find("transit")->state, KELP_BHV_RUNNING); /* running, not active */
    ck_assert_str_eq(ht_helm()->rep.allstop, "NothingToDo");
    ck_assert_uint_eq(ht_count("DESIRED_SPEED"), 0); /* no zeros on the first such iteration */
    ht_iter(1);
    ck_assert(ht_num("DESIRED_SPEED") == 0);
}
END_TEST

START_TEST(swpt_view_point_and_arrival)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_SimpleWaypoint\n{\n name = transit\n condition = DEPLOY = true\n endflag = RETURN = true\n"
            " speed = 2.0\n radius = 8.0\n ptx = 60\n pty = -40\n}\n");
    ht_iter(0);
    ck_assert(ht_has_str("VIEW_POINT", "label=alder's next waypoint,type=waypoint,source=transit,x=60,y=-40,active=false"));
    nav(0, 0);
    kelp_helm_mail_string(ht_helm(), "DEPLOY", "true");
    ht_iter(1);
    ck_assert(ht_has_str("VIEW_POINT", "label=alder's next waypoint,type=waypoint,source=transit,x=60,y=-40,active=true"));
    ck_assert(ht_num("DESIRED_HEADING") == 124 && ht_num("DESIRED_SPEED") == 2);
    ht_iter(2);
    ck_assert_uint_eq(ht_count("VIEW_POINT"), 0); /* unchanged: duplicate filter */
    nav(60, -31.9); /* 8.1 m: not yet */
    ht_iter(3);
    ck_assert_int_eq(ht_find("transit")->state, KELP_BHV_ACTIVE);
    ck_assert(ht_num("DESIRED_HEADING") == 180);
    nav(60, -32); /* exactly 8 m: arrived (dist <= radius) */
    ht_iter(4);
    ck_assert(ht_has_str("RETURN", "true"));
    ck_assert(ht_has_str("VIEW_POINT", "label=alder's next waypoint,type=waypoint,source=transit,x=60,y=-40,active=false"));
    ck_assert_int_eq(ht_find("transit")->state, KELP_BHV_RUNNING);
    ht_iter(5);
    ck_assert_int_eq(ht_find("transit")->state, KELP_BHV_COMPLETED);
}
END_TEST

/* The Alder mission (seed 5.3) against a kinematic vehicle that turns and changes speed
 * instantly: reaches (60,-40) within 8 m, RETURN=true, returns within 8 m of (0,0). */
START_TEST(alder_mission_flown)
{
    static const char *alder =
        "initialize  DEPLOY = false\ninitialize  RETURN = false\n"
        "Behavior = BHV_SimpleWaypoint\n{\n name = transit_to_point\n pwt = 100\n condition = RETURN = false\n"
        " condition = DEPLOY = true\n endflag = RETURN = true\n speed = 2.0\n radius = 8.0\n ptx = 60\n pty = -40\n"
        " ipf_type = zaic\n}\n"
        "Behavior = BHV_SimpleWaypoint\n{\n name = waypt_return\n pwt = 100\n condition = RETURN = true\n"
        " condition = DEPLOY = true\n speed = 2.0\n radius = 8.0\n ptx = 0\n pty = 0\n ipf_type = reflector\n}\n";
    kelp_helm *h = ht_setup(DOM2, NULL);
    ht_load(alder);
    double x = 0, y = 0, dt = 0.25, closest = 1e9, t_return = -1, hd = 0, sp = 0;
    kelp_helm_mail_string(h, "DEPLOY", "true");
    int i;
    for (i = 0; i < 2000; i++) {
        nav(x, y);
        if (t_return < 0)
            closest = fmin(closest, hypot(x - 60, y + 40));
        ht_iter(i * dt);
        if (t_return < 0 && ht_has_str("RETURN", "true"))
            t_return = i * dt;
        if (ht_find("waypt_return")->state == KELP_BHV_COMPLETED)
            break;
        /* the vehicle keeps the last desired values through an iteration with none (the one
         * between the two legs: nothing to do, no zeros posted the first time) */
        if (ht_last("DESIRED_HEADING")) hd = ht_num("DESIRED_HEADING") / 57.29577951308232;
        if (ht_last("DESIRED_SPEED")) sp = ht_num("DESIRED_SPEED");
        x += sp * dt * sin(hd);
        y += sp * dt * cos(hd);
    }
    ck_assert_msg(closest <= 8.0, "closest approach to (60,-40): %g", closest);
    ck_assert_msg(t_return > 30 && t_return < 40, "RETURN at %g s (72 m at 2 m/s is 36 s)", t_return);
    ck_assert_int_eq(ht_find("transit_to_point")->state, KELP_BHV_COMPLETED);
    ck_assert_int_eq(ht_find("waypt_return")->state, KELP_BHV_COMPLETED);
    ck_assert_msg(hypot(x, y) <= 8.0, "final (%g,%g)", x, y);
    ck_assert_msg(i * dt < 80, "took %g s", i * dt);
    /* the zeros come once, with the second iteration of NothingToDo (postAllStop holds one):
     * the last speed posted is 0 */
    if (ht_last("DESIRED_SPEED"))
        sp = ht_num("DESIRED_SPEED");
    ht_iter(i * dt + dt);
    ck_assert_str_eq(h->rep.allstop, "NothingToDo");
    if (ht_last("DESIRED_SPEED"))
        sp = ht_num("DESIRED_SPEED");
    ck_assert(sp == 0);
}
END_TEST

/* ---------------------------------------------------------------- points */

typedef struct pts_case {
    const char *s;
    int n;        /* <0: error */
    double x0, y0, xl, yl;
} pts_case;

#define R45 7.0710678118654755 /* 10 sin 45 */
#define S22 0.38268343236508978  /* sin 22.5 */
#define C22 0.92387953251128674  /* cos 22.5 */

static const pts_case g_pts[] = {
    {"60,-40:60,-100:150,-100", 3, 60, -40, 150, -100},
    {"pts={0,0:10,0}", 2, 0, 0, 10, 0},
    {"{1,2:3,4}", 2, 1, 2, 3, 4},
    {"(50,50)", 1, 50, 50, 50, 50},
    {"0,0", 1, 0, 0, 0, 0},
    {"x=5,y=6", 1, 5, 6, 5, 6},
    /* radial as 24.8 lays it out: the first vertex half a step clockwise of north */
    {"format=radial, x=0, y=0, radius=10, pts=4", 4, R45, R45, -R45, R45},
    {"radial:: x=100, y=-50, radius=20, pts=8", 8, 100 + 20 * S22, -50 + 20 * C22, 100 - 20 * S22, -50 + 20 * C22},
    {"format=radial, x=0, y=0, radius=10, pts=6, snap=1", 6, 5, 9, -5, 9},
    {"radial: 0, 0, 10, 4", 4, R45, R45, -R45, R45},
    {"radial: 0, 0, 10, 4, 1, lbl", 4, 7, 7, -7, 7},
    {"radial: 0, 0, 10", -1, 0, 0, 0, 0},
    {"", -1, 0, 0, 0, 0},
    {"1,2,3", -1, 0, 0, 0, 0},
    {"a,b", -1, 0, 0, 0, 0},
    {"1,2:", -1, 0, 0, 0, 0},
    {"format=ellipse, x=0, y=0, radius=10, pts=4", -1, 0, 0, 0, 0},
    {"format=radial, x=0, y=0, radius=-1, pts=4", -1, 0, 0, 0, 0},
    {"format=radial, x=0, radius=5, pts=4", -1, 0, 0, 0, 0},
    {"format=radial, x=0, y=0, radius=5, pts=2", -1, 0, 0, 0, 0},
    {"x=5", -1, 0, 0, 0, 0},
    /* keys read in place: a radius without format=radial is no polygon (24.8's string2Poly),
     * keys and format any case, the first wins */
    {"x=0, y=0, radius=10, pts=4", -1, 0, 0, 0, 0},
    {"FORMAT=Radial, X=0, Y=0, RADIUS=10, PTS=4", 4, R45, R45, -R45, R45},
    {"format=radial, x=0, y=0, radius=10, pts=4, x=99", 4, R45, R45, -R45, R45},
    /* a number's text: 63 bytes read, 64 refused */
    {"x=5.0000000000000000000000000000000000000000000000000000000000000,y=6", 1, 5, 6, 5, 6},
    {"x=5.00000000000000000000000000000000000000000000000000000000000000,y=6", -1, 0, 0, 0, 0},
};

START_TEST(points_formats)
{
    const pts_case *c = &g_pts[_i];
    kelp_bhv_pt p[KELP_HELM_MAX_PTS];
    unsigned n = 0;
    int rc = kelp_helm_parse_points(c->s, p, KELP_HELM_MAX_PTS, &n);
    if (c->n < 0) {
        ck_assert_msg(rc < 0, "'%s' accepted", c->s);
        return;
    }
    ck_assert_msg(rc == 0, "'%s' rejected (%d)", c->s, rc);
    ck_assert_int_eq((int)n, c->n);
    ck_assert_msg(fabs(p[0].x - c->x0) < 1e-6 && fabs(p[0].y - c->y0) < 1e-6, "first (%g,%g)", p[0].x, p[0].y);
    ck_assert_msg(fabs(p[n - 1].x - c->xl) < 1e-6 && fabs(p[n - 1].y - c->yl) < 1e-6, "last (%g,%g)", p[n - 1].x,
                  p[n - 1].y);
}
END_TEST

START_TEST(number_text)
{
    char b[40];
    hx_fmt_double(b, sizeof b, 123.456);
    ck_assert_str_eq(b, "123.456");
    hx_fmt_double(b, sizeof b, -0.0000001);
    ck_assert_str_eq(b, "0");
    hx_fmt_double(b, sizeof b, -40);
    ck_assert_str_eq(b, "-40");
    hx_fmt_double(b, sizeof b, 0.1 + 0.2);
    ck_assert_str_eq(b, "0.3");
    hx_fmt_double(b, sizeof b, 2.5e13);
    ck_assert_str_eq(b, "2.5e+13");
    hx_fmt_fixed(b, sizeof b, 9.456, 2);
    ck_assert_str_eq(b, "9.46");
    hx_fmt_fixed(b, sizeof b, -1, 0);
    ck_assert_str_eq(b, "-1");
    hx_fmt_fixed(b, sizeof b, 124, 2);
    ck_assert_str_eq(b, "124.00");
    hx_fmt_ulong(b, sizeof b, 4294967295ul);
    ck_assert_str_eq(b, "4294967295");
    ck_assert_uint_eq(hx_cat(b, 6, "abc", "def", HX_END), 5);
    ck_assert_str_eq(b, "abcde");
}
END_TEST

START_TEST(points_capacity)
{
    kelp_bhv_pt p[2];
    unsigned n;
    ck_assert_int_eq(kelp_helm_parse_points("0,0:1,1:2,2", p, 2, &n), KELP_ERR_NOSPACE);
}
END_TEST

/* ---------------------------------------------------------------- Waypoint */

START_TEST(waypoint_sequence_flags_end)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = survey\n speed = 1.0\n capture_radius = 2\n slip_radius = 0\n"
            " points = 0,10:10,10\n wptflag = HIT = 1\n endflag = DONE = true\n}\n");
    nav(0, 0);
    ht_iter(0);
    ck_assert(ht_num("WPT_INDEX") == 0);
    ck_assert(ht_num("DESIRED_HEADING") == 0 && ht_num("DESIRED_SPEED") == 1);
    /* eta: the distance over NAV_SPEED (24.8), "inf" while none came or the vehicle is stopped */
    ck_assert(ht_has_str("WPT_STAT", "vname=alder,behavior-name=survey,index=0,hits=0/0,cycles=0,dist=10,eta=inf"));
    /* 24.8's drawings: the seglist labelled <us>_<name>; the next point (key wpt); the track
     * point only when more than 5 m from it (here the lead puts it on the next point: erased) */
    ck_assert(ht_has_str("VIEW_SEGLIST", "pts={0,10:10,10},label=alder_survey,label_color=white,edge_color=white,vertex_color=dodger_blue,vertex_size=3,edge_size=1"));
    ck_assert(ht_has_str("VIEW_POINT", "x=0,y=10,active=true,label=alder's nextpt,label_color=aqua,vertex_color=yellow,vertex_size=5"));
    ck_assert(ht_has_str("VIEW_POINT", "x=0,y=0,active=false,label=alder's trackpt"));
    kelp_helm_mail_double(ht_helm(), "NAV_SPEED", 0.5);
    ht_iter(0.5);
    ck_assert(ht_has_str("WPT_STAT", "vname=alder,behavior-name=survey,index=0,hits=0/0,cycles=0,dist=10,eta=20"));
    nav(0, 8.5);
    ht_iter(1); /* 1.5 m: captured, next point (10,10) */
    ck_assert(ht_num("HIT") == 1);
    ck_assert(ht_num("WPT_INDEX") == 1);
    ck_assert(ht_num("DESIRED_HEADING") == 81); /* relAng((0,8.5),(10,10)) = 81.47 */
    nav(9, 10.5);
    ht_iter(2);
    ck_assert(ht_has_str("DONE", "true"));
    /* 24.8 posts the wptflags again at completion, through the duplicate filter: HIT = 1 again
     * is not repeated */
    ck_assert_uint_eq(ht_count("HIT"), 0);
    /* the pass ends: 24.8's feedback, not a status line */
    ck_assert_str_eq(ht_last("WPT_STAT")->sval, "behavior-name=survey,completed");
    ck_assert_uint_eq(ht_count("WPT_STAT"), 1);
    /* 24.8 at completion: the route erased, a death event, one completed this iteration, the
     * behaviour listed neither active nor running; counted out of the set the next iteration */
    ck_assert(ht_has_str("VIEW_SEGLIST", "pts={0,10:10,10},active=false,label=alder_survey"));
    ck_assert(ht_has_sub("IVPHELM_LIFE_EVENT", ", bname=survey, btype=BHV_Waypoint, event=death,iter=4")); /* the fourth decision */
    ck_assert(ht_num("IVPHELM_COMPLETED_COUNT") == 1);
    ck_assert(ht_has_str("IVPHELM_BHV_ACTIVE", ""));
    ck_assert_uint_eq(ht_count("IVPHELM_BHV_RUNNING"), 0);
    ck_assert_uint_eq(ht_count("IVPHELM_BHV_CNT"), 0);
    ht_iter(3);
    ck_assert_int_eq(ht_find("survey")->state, KELP_BHV_COMPLETED);
    ck_assert(ht_num("IVPHELM_COMPLETED_COUNT") == 0);
    ck_assert(ht_num("IVPHELM_BHV_CNT") == 0);
    ck_assert_uint_eq(ht_count("IVPHELM_LIFE_EVENT"), 0);
}
END_TEST

/* 24.8: a waypoint behaviour without points loads with a warning and makes no function;
 * points = empty is silent; points = start takes the vehicle's position once it is known */
START_TEST(waypoint_no_points_empty_start)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n updates = W_UPD\n}\n"
            "Behavior = BHV_Waypoint\n{\n name = e\n speed = 1\n points = empty\n}\n"
            "Behavior = BHV_Waypoint\n{\n name = s\n speed = 1\n pwt = 50\n points = start\n}\n");
    ht_iter(0); /* the start-up messages go out with the first engaged iteration (24.8) */
    ck_assert(ht_has_str("BHV_WARNING", "w: No waypts given. Set val to empty if intentional"));
    ck_assert(!ht_has_sub("BHV_WARNING", "e: "));
    ck_assert(!ht_has_sub("BHV_WARNING", "s: "));
    ck_assert_uint_eq(ht_find("s")->u.wpt.npts, 0);
    nav(3.25, -4.5);
    ht_iter(0);
    ck_assert_uint_eq(ht_find("w")->u.wpt.npts, 0);
    ck_assert_uint_eq(ht_find("e")->u.wpt.npts, 0);
    ck_assert_uint_eq(ht_find("s")->u.wpt.npts, 1);
    ck_assert(ht_find("s")->u.wpt.pts[0].x == 3.25 && ht_find("s")->u.wpt.pts[0].y == -4.5);
    /* points given later by an update: the behaviour drives */
    kelp_helm_mail_string(ht_helm(), "W_UPD", "points = 3.25,20");
    nav(3.25, 0);
    ht_iter(1);
    ck_assert_uint_eq(ht_find("w")->u.wpt.npts, 1);
    ck_assert(ht_num("DESIRED_HEADING") == 0);
}
END_TEST

START_TEST(waypoint_repeat_and_order)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n radius = 1\n points = 0,10:0,20\n repeat = 1\n"
            " order = reverse\n cycleflag = LAP = 1\n endflag = DONE = 1\n}\n");
    nav(0, 0);
    ht_iter(0);
    ck_assert(ht_num("DESIRED_HEADING") == 0);
    ck_assert_uint_eq(ht_count("CYCLE_INDEX"), 0); /* BHV_Waypoint: only when the count changes */
    ck_assert(ht_has_str("VIEW_SEGLIST", "pts={0,20:0,10},label=alder_w,label_color=white,edge_color=white,vertex_color=dodger_blue,vertex_size=3,edge_size=1")); /* reversed */
    nav(0, 20);
    ht_iter(1);
    ck_assert(ht_num("WPT_INDEX") == 1);
    ck_assert(ht_num("DESIRED_HEADING") == 180);
    nav(0, 10);
    ht_iter(2); /* end of the first pass: repeat once */
    ck_assert(ht_num("LAP") == 1);
    ck_assert(ht_num("CYCLE_INDEX") == 1 && ht_num("WPT_INDEX") == 0);
    ck_assert(ht_has_str("WPT_STAT", "behavior-name=w,cycled")); /* and the status line after it */
    ck_assert_uint_eq(ht_count("WPT_STAT"), 2);
    ck_assert_uint_eq(ht_count("DONE"), 0);
    nav(0, 20);
    ht_iter(3);
    nav(0, 10);
    ht_iter(4);
    ck_assert(ht_num("DONE") == 1 && ht_num("LAP") == 1);
    ck_assert(ht_num("CYCLE_INDEX") == 2);
    ht_iter(5);
    ck_assert_uint_eq(ht_count("CYCLE_INDEX"), 0);
    ck_assert_int_eq(ht_find("w")->state, KELP_BHV_COMPLETED);
}
END_TEST

START_TEST(waypoint_slip_radius)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n capture_radius = 1\n slip_radius = 5\n points = 0,10:0,50\n}\n");
    nav(2, 0);
    ht_iter(0);
    nav(3, 7); /* 4.24 m */
    ht_iter(1);
    ck_assert_uint_eq(ht_find("w")->u.wpt.index, 0);
    nav(3.5, 8); /* 4.03 m, closer */
    ht_iter(2);
    ck_assert_uint_eq(ht_find("w")->u.wpt.index, 0);
    nav(4, 11); /* 4.12 m: inside slip radius and moving away: counts as arrived */
    ht_iter(3);
    ck_assert(ht_num("WPT_INDEX") == 1);
    ck_assert_ptr_nonnull(strstr(ht_last("WPT_STAT")->sval, "hits=0/1"));
}
END_TEST

START_TEST(waypoint_lead)
{
    /* MOOS-IvP: no leg before the first point, so no lead on it unless lead_to_start */
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n points = 0,100\n lead = 10\n}\n");
    nav(0, 0);
    ht_iter(0);
    nav(5, 20);
    ht_iter(1); /* straight at (0,100): relAng((5,20),(0,100)) = 356.4; 24.8's course function also
                 * leans toward ownship's heading (0 here: peak width 30, 5 of 20): 357 */
    ck_assert_msg(ht_num("DESIRED_HEADING") == 357, "heading %g", ht_num("DESIRED_HEADING"));

    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n points = 0,100\n lead = 10\n lead_to_start = true\n}\n");
    nav(0, 0);
    ht_iter(0); /* leg (0,0) -> (0,100) from where the vehicle started */
    nav(5, 20);
    ht_iter(1); /* track point (0, 20 + 10): relAng((5,20),(0,30)) = 333.43, 334 with the heading lean */
    ck_assert_msg(ht_num("DESIRED_HEADING") == 334, "heading %g", ht_num("DESIRED_HEADING"));
    ck_assert_int_eq(kelp_helm_bhv_set_param(ht_find("w"), "lead", "0"), 0);
    nav(5, 21);
    ht_iter(2); /* lead off: straight at (0,100): 356.4, 357 with the heading lean */
    ck_assert(ht_num("DESIRED_HEADING") == 357);
}
END_TEST

START_TEST(waypoint_lead_second_leg_and_damper)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n points = 0,0:0,100\n lead = 10\n}\n");
    nav(0, 1);
    ht_iter(0); /* captured (0,0); second leg (0,0)->(0,100) */
    nav(5, 20);
    ht_iter(1); /* lead point (0,30): 333.43, 334 with the heading lean */
    ck_assert_msg(ht_num("DESIRED_HEADING") == 334, "heading %g", ht_num("DESIRED_HEADING"));
    nav(-20, 120); /* beyond the leg's end: projection clipped to (0,100), no lead past it */
    ht_iter(2);
    ck_assert_msg(ht_num("DESIRED_HEADING") == 135, "heading %g", ht_num("DESIRED_HEADING"));

    /* damper 20 m, vehicle 5 m off the line: lead x (1 + 2 x (1 - 5/20)) = 25 m */
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n points = 0,0:0,100\n lead = 10\n"
            " lead_damper = 20\n}\n");
    nav(0, 1);
    ht_iter(0);
    nav(5, 20);
    ht_iter(1); /* track point (0,45): relAng((5,20),(0,45)) = 348.7 */
    ck_assert_msg(ht_num("DESIRED_HEADING") == 349, "heading %g", ht_num("DESIRED_HEADING"));
}
END_TEST

START_TEST(waypoint_capture_line)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n capture_radius = 1\n slip_radius = 0\n"
            " points = 0,10:0,50\n capture_line = true\n}\n");
    nav(0, 0);
    ht_iter(0);
    nav(6, 9);
    ht_iter(1); /* before the line y = 10 */
    ck_assert_uint_eq(ht_find("w")->u.wpt.index, 0);
    nav(8, 10.5); /* 8 m away but past the line */
    ht_iter(2);
    ck_assert_uint_eq(ht_find("w")->u.wpt.index, 1);
    /* 24.8's WaypointEngine counts a line crossing neither as a capture nor as a slip */
    ck_assert_ptr_nonnull(strstr(ht_last("WPT_STAT")->sval, "hits=0/0"));
    /* absolute: radii zero, only the line counts */
    ck_assert_int_eq(kelp_helm_bhv_set_param(ht_find("w"), "capture_line", "absolute"), 0);
    ck_assert(ht_find("w")->u.wpt.capture_radius == 0 && ht_find("w")->u.wpt.slip_radius == 0);
    ck_assert_int_lt(kelp_helm_bhv_set_param(ht_find("w"), "capture_line", "maybe"), 0);
}
END_TEST

START_TEST(waypoint_reports_and_hints)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n points = 0,10:0,20\n post_suffix = A\n"
            " wpt_index_var = silent\n wpt_status_var = MY_STAT\n wpt_dist_to_next = DNEXT\n"
            " visual_hints = vertex_size=5, edge_color=red, nextpt_color=green, bogus=1\n"
            " efficiency_measure = all\n crs_spd_zaic_ratio = 80\n order = toggle\n}\n");
    nav(0, 0);
    ht_iter(0);
    ck_assert_uint_eq(ht_count("WPT_INDEX_A") + ht_count("WPT_INDEX"), 0);
    ck_assert_ptr_nonnull(ht_last("MY_STAT_A"));
    ck_assert(ht_num("DNEXT") == 20); /* order toggled: (0,20) first */
    ck_assert_ptr_nonnull(strstr(ht_last("VIEW_SEGLIST")->sval, "edge_color=red"));
    ck_assert_ptr_nonnull(strstr(ht_last("VIEW_SEGLIST")->sval, "vertex_size=5"));
    ck_assert(ht_has_sub("VIEW_POINT", "active=true,label=alder's nextpt,label_color=aqua,vertex_color=green"));
    ck_assert(ht_find("w")->u.wpt.course_pct == 80);
    nav(0, 8);
    ht_iter(1);
    nav(0, 16);
    ht_iter(2);
    nav(0, 19.5);
    ht_iter(3); /* the first point: 24.8's first leg mark only marks (nothing posted) */
    ck_assert_uint_eq(ht_count("WPT_EFF_SUMM_LEG_A"), 0);
    ck_assert(ht_num("WPT_ODO_A") < 1e-9); /* the next leg's odometry starts over */
    nav(0, 15);
    ht_iter(3.5);
    nav(0, 10.5);
    ht_iter(4); /* the second: 9 m straight, 9 m travelled, in 1 s (9 s at cruise speed 1) */
    ck_assert_str_eq(ht_last("WPT_EFF_SUMM_LEG_A")->sval, "vname=alder, bhv_name=w, linear_dist=9, odo_dist=9, "
                     "efficiency_dist=1, linear_time=9, odo_time=1, efficiency_time=9");
    ck_assert_str_eq(ht_last("WPT_EFF_SUMM_ALL_A")->sval, "vname=alder, bhv_name=w, linear_dist=9, odo_dist=9, "
                     "efficiency_dist=1, linear_time=9, odo_time=1, efficiency_time=9");
    ck_assert(ht_num("WPT_EFF_DIST_LEG_A") == 1 && ht_num("WPT_EFF_DIST_ALL_A") == 1);
    ck_assert(ht_num("WPT_EFF_TIME_LEG_A") == 9 && ht_num("WPT_EFF_TIME_ALL_A") == 9);
    ck_assert_int_lt(kelp_helm_bhv_set_param(ht_find("w"), "crs_spd_zaic_ratio", "100"), 0);
    ck_assert_int_lt(kelp_helm_bhv_set_param(ht_find("w"), "wpt_status_var", "A B"), 0);
    ck_assert_int_lt(kelp_helm_bhv_set_param(ht_find("w"), "capture_radius", "0"), 0);
}
END_TEST

/* 24.8's wptflags: macros of the behaviour ($(PX),$(PY): the point just left; $(NX),$(NY):
 * the next; $(NI), $(PI), $(CYCLES), $(WPTS_HIT), $[SPEED] ...), posted on the first run with
 * wptflag_on_start, at each point and at completion, through the duplicate filter */
START_TEST(waypoint_flag_macros_on_start)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1.5\n capture_radius = 2\n slip_radius = 0\n"
            " points = 0,10:20,10\n wptflag_on_start = true\n wptflag = PREV=$(PX),$(PY)\n"
            " wptflag = NEXT=$(NX),$(NY)\n wptflag = IX=$(NI)/$(PI)/$(WPTS_HIT)/$(WPTS)/$(OSX),$(OSY),$(OSV)\n"
            " wptflag = N=$(NI)\n"
            " configflag = CRUISE = $[SPEED]\n endflag = DONE = $(CYCLES)\n}\n");
    nav(0, 0);
    ht_iter(0); /* first run: the flags at once; the point just left is the first point itself */
    ck_assert(ht_has_str("PREV", "0,10"));
    ck_assert(ht_has_str("NEXT", "0,10"));
    ck_assert(ht_has_str("IX", "0/-1/0/2/0,0,0"));
    ck_assert(ht_num("N") == 0);           /* a lone macro that expands to a number: a number */
    ck_assert(ht_num("CRUISE") == 1.5);
    nav(0, 5);
    ht_iter(1);
    ck_assert_uint_eq(ht_count("PREV"), 0); /* nothing changed */
    nav(0, 9);
    ht_iter(2); /* captured (0,10): next (20,10); PREV=0,10 again is a duplicate (filtered) */
    ck_assert_uint_eq(ht_count("PREV"), 0);
    ck_assert(ht_has_str("NEXT", "20,10"));
    ck_assert(ht_has_str("IX", "1/0/1/2/0,9,0"));
    nav(19, 10.5);
    ht_iter(3); /* completed: the flags once more; NEXT unchanged, so filtered as a duplicate */
    ck_assert(ht_has_str("PREV", "20,10"));
    ck_assert_uint_eq(ht_count("NEXT"), 0);
    ck_assert(ht_has_str("IX", "0/1/2/2/19,10.5,0"));
    ck_assert(ht_num("DONE") == 1); /* a waypoint's endflags expand its macros too (24.8's virtual expandMacros) */
}
END_TEST

/* 24.8 (IvPBehavior::updatePlatformInfo): a waypoint that runs without ownship's position or
 * heading posts a BHV_ERROR, which halts the helm; without points it stays quiet */
START_TEST(waypoint_no_nav_is_error)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n points = 0,10\n}\n"
            "Behavior = BHV_Waypoint\n{\n name = e\n speed = 1\n points = start\n}\n");
    ht_iter(0);
    ck_assert(ht_has_str("BHV_ERROR", "w: No ownship X/Y info in info_buffer."));
    ck_assert(!ht_has_sub("BHV_ERROR", "e: "));
    ck_assert(!ht_find("w")->state_ok);
    kelp_helm_mail_double(ht_helm(), "NAV_X", 0);
    kelp_helm_mail_double(ht_helm(), "NAV_Y", 0);
    ht_iter(1);
    ck_assert(ht_has_str("BHV_ERROR", "w: No ownship heading info in info_buffer."));
}
END_TEST

/* end_spd (24.8's setEndSpeed, buildOF): the cruise speed scaled down over the last slow_dist
 * metres of the list, zero within stop_dist of its end */
START_TEST(waypoint_end_speed)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 2\n capture_radius = 1\n slip_radius = 0\n"
            " points = 0,100\n end_spd = slow_dist=20, stop_dist=5\n}\n");
    nav(0, 50);
    ht_iter(0);
    ck_assert(ht_num("DESIRED_SPEED") == 2);
    nav(0, 88.75); /* 11.25 m to go: (11.25 - 5) / 15 of 2 = 0.833 */
    ht_iter(1);
    ck_assert_msg(ht_num("DESIRED_SPEED") > 0.5 && ht_num("DESIRED_SPEED") < 1.2, "speed %g", ht_num("DESIRED_SPEED"));
    nav(0, 96); /* 4 m: stopped */
    ht_iter(2);
    ck_assert(ht_num("DESIRED_SPEED") == 0);
    ck_assert_int_lt(kelp_helm_bhv_set_param(ht_find("w"), "end_spd", "slow_dist=5, stop_dist=10"), 0);
    ck_assert_int_lt(kelp_helm_bhv_set_param(ht_find("w"), "end_spd", "slow_dist=5"), 0);
    ck_assert_int_lt(kelp_helm_bhv_set_param(ht_find("w"), "end_spd", "slow_dist=5, fast=1"), 0);
}
END_TEST

/* greedy_tour: the points reordered nearest-first from where the vehicle is when it first runs */
START_TEST(waypoint_greedy_tour)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n points = 100,0:10,0:50,0:0,40\n"
            " greedy_tour = true\n}\n");
    nav(0, 0);
    ht_iter(0);
    ck_assert(ht_has_sub("BHV_SETTINGS", ",greedy_tour=true,")); /* from (0,0): (10,0); from it (50,0) at 40 m before (0,40) at 41.2; then (100,0), (0,40) */
    const kelp_bhv_wpt *s = &ht_find("w")->u.wpt;
    ck_assert(s->pts[0].x == 10 && s->pts[1].x == 50 && s->pts[2].x == 100 && s->pts[3].x == 0);
    ck_assert(!s->greedy_pending);
    ck_assert(ht_num("DESIRED_HEADING") == 90);
}
END_TEST

/* lead_condition: lead steering only while its condition holds ("VAR,val" read as VAR=val) */
START_TEST(waypoint_lead_condition)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n points = 0,0:0,100\n lead = 10\n"
            " lead_condition = LEAD_OK,true\n}\n");
    nav(0, 1);
    ht_iter(0); /* captured (0,0) */
    nav(5, 20);
    ht_iter(1); /* LEAD_OK unknown: straight at (0,100): 356.4, 357 with the heading lean */
    ck_assert_msg(ht_num("DESIRED_HEADING") == 357, "heading %g", ht_num("DESIRED_HEADING"));
    kelp_helm_mail_string(ht_helm(), "LEAD_OK", "true");
    nav(5, 20);
    ht_iter(2); /* lead point (0,30): 333.4, 334 */
    ck_assert_msg(ht_num("DESIRED_HEADING") == 334, "heading %g", ht_num("DESIRED_HEADING"));
    ck_assert_int_lt(kelp_helm_bhv_set_param(ht_find("w"), "lead_condition", "A = = 1"), 0);
    ck_assert_int_eq(kelp_helm_bhv_set_param(ht_find("w"), "ipf_type", "zaic"), 0);
    ck_assert_int_lt(kelp_helm_bhv_set_param(ht_find("w"), "ipf_type", "roc"), 0); /* not built here: refused */
    ck_assert_int_eq(kelp_helm_bhv_set_param(ht_find("w"), "patience", "70"), 0);
    ck_assert(ht_find("w")->u.wpt.course_pct == 70);
}
END_TEST

/* a perpetual waypoint starts over from its first point after completing; reset_on_idle goes
 * back to it when the behaviour idles; newpt adds a point, xpoints replaces them, index kept */
START_TEST(waypoint_perpetual_reset_newpt)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = w\n speed = 1\n perpetual = true\n condition = GO = true\n"
            " capture_radius = 2\n slip_radius = 0\n points = 0,10:0,20\n reset_on_idle = true\n"
            " updates = W_UPD\n}\n");
    kelp_helm_mail_string(ht_helm(), "GO", "true");
    nav(0, 9);
    ht_iter(0);
    ck_assert_uint_eq(ht_find("w")->u.wpt.index, 1);
    kelp_helm_mail_string(ht_helm(), "GO", "false");
    ht_iter(1); /* idle: reset_on_idle */
    ck_assert_uint_eq(ht_find("w")->u.wpt.index, 0);
    kelp_helm_mail_string(ht_helm(), "GO", "true");
    nav(0, 9);
    ht_iter(2);
    nav(0, 19);
    ht_iter(3); /* completed, perpetual: ready at the first point again */
    ck_assert(ht_has_str("WPT_STAT", "behavior-name=w,completed"));
    ck_assert_uint_eq(ht_find("w")->u.wpt.index, 0);
    ck_assert_int_ne(ht_find("w")->state, KELP_BHV_COMPLETED);
    kelp_helm_mail_string(ht_helm(), "W_UPD", "newpt = 5,5");
    ht_iter(4);
    ck_assert_uint_eq(ht_find("w")->u.wpt.npts, 3);
    ck_assert_int_lt(kelp_helm_bhv_set_param(ht_find("w"), "xpoints", "1,1:2,2"), 0); /* a different count */
    ck_assert_int_eq(kelp_helm_bhv_set_param(ht_find("w"), "xpoints", "1,1:2,2:3,3"), 0);
    ck_assert(ht_find("w")->u.wpt.pts[2].x == 3);
}
END_TEST

/* BHV_SETTINGS as 24.8 wrote it for the recorded vehicle's return waypoint */
START_TEST(waypoint_settings_string)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = waypt_return\n speed = 2.0\n capture_radius = 2.0\n"
            " slip_radius = 8.0\n points = 0,-20\n}\n");
    ht_iter(0); /* posted with the first engaged iteration */
    ck_assert(ht_has_str("BHV_SETTINGS", "type=BHV_Waypoint,name=waypt_return,points=pts={0,-20},speed=2,speed_alt=-1,"
                         "currix=0,greedy_tour=false,use_alt_speed=false,wpt_status=WPT_STAT,wpt_dist_to_prev=,"
                         "wpt_dist_to_next=,wpt_index=WPT_INDEX,cycle_index_var=CYCLE_INDEX,post_suffix=,post_suffix=,"
                         "ipf_type=zaic,lead=-1,lead_damper=-1,lead_to_start=false,order=normal,repeats=0,"
                         "efficiency_measure=off,capture_radius=2,slip_radius=8,crs_spd_zaic_ratio=50"));
}
END_TEST

START_TEST(waypoint_updates_points)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = WAYPT_RETURN\n priority = 100\n speed = 2.0\n radius = 8.0\n"
            " points = 0,0\n UPDATES = RETURN_UPDATES\n condition = RETURN = true\n condition = DEPLOY = true\n}\n");
    nav(0, -100);
    kelp_helm_mail_string(ht_helm(), "RETURN", "true");
    kelp_helm_mail_string(ht_helm(), "DEPLOY", "true");
    ht_iter(0);
    ck_assert(ht_num("DESIRED_HEADING") == 0);
    /* Listing 6's poke: both parameters change in the same iteration */
    kelp_helm_mail_string(ht_helm(), "RETURN_UPDATES", "points = (50,50) # speed = 1.5");
    ht_iter(1);
    kelp_bhv *b = ht_find("WAYPT_RETURN");
    ck_assert(b->u.wpt.npts == 1 && b->u.wpt.pts[0].x == 50 && b->u.wpt.pts[0].y == 50);
    ck_assert(b->u.wpt.speed == 1.5);
    ck_assert(ht_num("DESIRED_HEADING") == 18); /* relAng((0,-100),(50,50)) = 18.43 */
}
END_TEST

/* (BHV_Loiter: check_bhv_loiter.c) */

START_TEST(constant_mismatch_and_complete_thresh)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_ConstantHeading\n{\n name = ch\n heading = 350\n heading_mismatch_var = HDG_DIFF\n"
            " complete_thresh = 5\n}\nBehavior = BHV_ConstantSpeed\n{\n name = cs\n speed = 1\n"
            " speed_mismatch_var = SPD_DIFF\n}\n");
    kelp_helm_mail_double(ht_helm(), "NAV_HEADING", 20);
    kelp_helm_mail_double(ht_helm(), "NAV_SPEED", 1.5);
    ht_iter(0);
    ck_assert(fabs(ht_num("HDG_DIFF") - 30) < 1e-9); /* across north */
    ck_assert(fabs(ht_num("SPD_DIFF") - 0.5) < 1e-9);
    ck_assert(ht_find("ch")->state != KELP_BHV_COMPLETED);
    kelp_helm_mail_double(ht_helm(), "NAV_HEADING", 353);
    ht_iter(1);
    ck_assert(ht_find("ch")->completed); /* within 5 degrees */
    ht_iter(2);
    ck_assert_int_eq(ht_find("ch")->state, KELP_BHV_COMPLETED);
}
END_TEST

/* ---------------------------------------------------------------- constant behaviours */

START_TEST(constant_depth_speed_heading)
{
    ht_setup(DOM2 ",depth:0:100:101", NULL);
    ht_load("Behavior = BHV_ConstantDepth\n{\n name = cd\n depth = 20\n}\n"
            "Behavior = BHV_ConstantSpeed\n{\n name = cs\n speed = 1.2\n}\n"
            "Behavior = BHV_ConstantHeading\n{\n name = ch\n heading = 270\n}\n");
    kelp_bhv *b = ht_find("cd");
    ck_assert(b->u.c1.peakwidth == 3 && b->u.c1.basewidth == 100 && b->u.c1.summitdelta == 50);
    ht_iter(0);
    ck_assert_str_eq(ht_helm()->rep.allstop, "clear");
    ck_assert(ht_num("DESIRED_DEPTH") == 20);
    ck_assert(fabs(ht_num("DESIRED_SPEED") - 1.2) < 1e-9);
    ck_assert(ht_num("DESIRED_HEADING") == 270);
    kelp_helm_mail_string(ht_helm(), "X", "y");
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "depth", "55"), 0);
    ht_iter(1);
    ck_assert(ht_num("DESIRED_DEPTH") == 55);
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "depth", "-3"), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "peakwidth", "abc"), KELP_ERR_PARSE);
}
END_TEST

/* ---------------------------------------------------------------- hierarchical modes */

START_TEST(hierarchical_modes)
{
    ht_setup(DOM2, NULL);
    ht_load("initialize DEPLOY = false\ninitialize RETURN = false\n"
            "set MODE = ACTIVE {\n  DEPLOY = true\n} INACTIVE\n"
            "set MODE = SURVEYING {\n  MODE = ACTIVE\n  RETURN != true\n} RETURNING\n"
            "Behavior = BHV_ConstantSpeed\n{\n name = survey\n speed = 2\n condition = MODE == ACTIVE:SURVEYING\n}\n"
            "Behavior = BHV_ConstantSpeed\n{\n name = ret\n speed = 1\n condition = MODE == ACTIVE:RETURNING\n}\n"
            "Behavior = BHV_ConstantHeading\n{\n name = h\n heading = 90\n}\n");
    ck_assert_uint_eq(ht_helm()->nmodes, 2);
    /* posted at start */
    ck_assert_ptr_nonnull(ht_last("IVPHELM_MODESET"));
    ck_assert_str_eq(ht_last("IVPHELM_MODESET")->sval, "MODE#---,ACTIVE#---,INACTIVE#ACTIVE,SURVEYING#ACTIVE,RETURNING");
    ht_iter(0);
    ck_assert_str_eq(ht_last("MODE")->sval, "INACTIVE");
    ck_assert_uint_eq(ht_count("DESIRED_SPEED"), 0); /* no speed behaviour: MissingDecVars, no zeros the first time */
    ck_assert_str_ne(ht_helm()->rep.allstop, "clear");
    kelp_helm_mail_string(ht_helm(), "DEPLOY", "true");
    ht_iter(1);
    ck_assert_str_eq(ht_last("MODE")->sval, "ACTIVE:SURVEYING");
    ck_assert(ht_num("DESIRED_SPEED") == 2);
    ck_assert_ptr_nonnull(strstr(ht_last("IVPHELM_SUMMARY")->sval, ",modes=MODE@ACTIVE:SURVEYING"));
    ht_iter(2);
    ck_assert_uint_eq(ht_count("MODE"), 0); /* posted on change only */
    kelp_helm_mail_string(ht_helm(), "RETURN", "true");
    ht_iter(3);
    ck_assert_str_eq(ht_last("MODE")->sval, "ACTIVE:RETURNING");
    ck_assert(ht_num("DESIRED_SPEED") == 1);
    kelp_helm_mail_string(ht_helm(), "DEPLOY", "false");
    ht_iter(4);
    ck_assert_str_eq(ht_last("MODE")->sval, "INACTIVE");

    /* errors name the line */
    ht_setup(DOM2, NULL);
    ck_assert_int_eq(ht_load_rc("\nset MODE = TWO WORDS {\n  A = 1\n}\n"), KELP_ERR_PARSE);
    ck_assert_int_eq(ht_helm()->diag.code, KELP_ERR_PARSE);
    ck_assert_int_eq(ht_helm()->diag.line, 2);
    ck_diag_msg(&ht_helm()->diag, "mode declaration: mode value must be one word");
}
END_TEST

/* fake CPU clock: 1 ms per reading */
static double fake_cpu(void *user)
{
    static double t;
    (void)user;
    return t += 0.001;
}

START_TEST(helm_interface_publications)
{
    kelp_helm *h = ht_setup(DOM2, NULL);
    h->cfg.cpu_clock = fake_cpu;
    ht_load("set MODE = ACTIVE {\n  DEPLOY = true\n} INACTIVE\n"
            "Behavior = BHV_Waypoint\n{\n name = wpt\n speed = 1\n points = 0,50\n updates = WPT_UPDATES\n}\n"
            "Behavior = BHV_ConstantHeading\n{\n name = ch\n heading = 90\n condition = MODE == INACTIVE\n}\n");
    ck_assert_str_eq(ht_last("IVPHELM_DOMAIN")->sval, "course,0,359,360:speed,0,4,21");
    ck_assert_uint_eq(ht_count("IVPHELM_LIFE_EVENT"), 0); /* 24.8: by the first decision */
    /* what the behaviours listen to: posted by the first drive iteration, not at start */
    ck_assert_uint_eq(ht_count("IVPHELM_UPDATEVARS") + ht_count("IVPHELM_STATEVARS"), 0);
    nav(0, 0);
    ht_iter(0);
    ck_assert_str_eq(ht_last("IVPHELM_UPDATEVARS")->sval, "wpt=WPT_UPDATES");
    ck_assert_str_eq(ht_last("IVPHELM_STATEVARS")->sval, "MODE");
    ck_assert(ht_num("IVPHELM_BHV_CNT") == 2 && ht_num("IVPHELM_BHV_CNT_EVER") == 2);
    ck_assert(ht_num("IVPHELM_BHV_RUNNING_CNT") + ht_num("IVPHELM_BHV_ACTIVE_CNT") == 2);
    ck_assert(ht_num("IVPHELM_BHV_DISABLED_CNT") == 0);
    ck_assert_str_eq(ht_last("IVPHELM_STATE")->sval, "DRIVE");
    ck_assert_uint_eq(ht_count("IVPHELM_LIFE_EVENT"), 2);
    ck_assert_str_eq(ht_last("IVPHELM_LIFE_EVENT")->sval,
                     "iter=0, bname=ch, btype=BHV_ConstantHeading, event=spawn, seed=helm_startup,iter=1");
    ck_assert_uint_eq(ht_count("IVPHELM_ENGAGED"), 0); /* the seed era's heartbeat: 24.8 has none */
    ck_assert(fabs(ht_num("IVPHELM_CREATE_CPU") - 0.001) < 1e-9);
    ck_assert(fabs(ht_num("IVPHELM_LOOP_CPU") - 0.002) < 1e-9);
    const char *sum = ht_last("IVPHELM_SUMMARY")->sval;
    /* the first summary is whole (24.8's HelmReport): CPU times in 10 ms steps, 2 decimals */
    ck_assert_ptr_nonnull(strstr(sum, ",utc_time=1000.00,"));
    ck_assert_msg(strstr(sum, ",solve_time=0.00,create_time=0.00,max_create_time=0.00,max_solve_time=0.00,"
                              "max_loop_time=0.00,loop_time=0.00,") != NULL, "%s", sum);
    ck_assert_ptr_nonnull(strstr(sum, ",total_pcs_formed="));
    ck_assert_ptr_nonnull(strstr(sum, ",modes=MODE@INACTIVE"));
    ht_iter(0.5);
    ck_assert_uint_eq(ht_count("IVPHELM_BHV_CNT"), 0);  /* unchanged: not posted */
    ck_assert_uint_eq(ht_count("IVPHELM_STATE"), 1);  /* every iteration */
}
END_TEST

START_TEST(constant_depth_needs_depth)
{
    ht_setup(DOM2 ",depth:0:100:101", NULL);
    ck_assert_int_lt(ht_load_rc("Behavior = BHV_ConstantDepth\n{\n name = cd\n}\n"), 0);
    ck_diag_has(&ht_helm()->diag, "depth not set");
    ck_assert_int_eq(ht_helm()->diag.code, KELP_ERR_PARSE);
    ht_setup(DOM2, NULL); /* no depth variable: null domain */
    ck_assert_int_lt(ht_load_rc("Behavior = BHV_ConstantDepth\n{\n depth = 5\n}\n"), 0);
}
END_TEST

START_TEST(priority_weights_trade_off)
{
    /* two constant-heading behaviours: the heavier one wins */
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_ConstantHeading\n{\n name = a\n heading = 90\n pwt = 100\n basewidth = 90\n}\n"
            "Behavior = BHV_ConstantHeading\n{\n name = b\n heading = 180\n pwt = 300\n basewidth = 90\n}\n"
            "Behavior = BHV_ConstantSpeed\n{\n name = s\n speed = 1\n}\n");
    ht_iter(0);
    ck_assert(ht_num("DESIRED_HEADING") == 180);
    ck_assert_int_eq(kelp_helm_bhv_set_param(ht_find("a"), "pwt", "500"), 0);
    ht_iter(1);
    ck_assert(ht_num("DESIRED_HEADING") == 90);
    ck_assert_int_eq(kelp_helm_bhv_set_param(ht_find("a"), "pwt", "0"), 0); /* weight 0: no function */
    ht_iter(2);
    ck_assert(ht_num("DESIRED_HEADING") == 180);
    ck_assert_int_eq(ht_find("a")->state, KELP_BHV_RUNNING);
}
END_TEST

/* ---------------------------------------------------------------- BHV_StationKeep (24.8) */

/* the station from station_pt; the first run only takes the station (24.8's updateInfoIn
 * returns before measuring: speed 0 that time); then extra_speed beyond the outer radius,
 * outer_speed scaled between the radii, 0 inside the inner one; the course toward the station;
 * BHV_SETTINGS at the first run, the three circles, PSKEEP_MODE, DIST_TO_STATION */
START_TEST(stationkeep_speeds_and_posts)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_StationKeep\n{\n name = sk\n station_pt = 0,-40\n inner_radius = 4\n"
            " outer_radius = 15\n outer_speed = 1.2\n transit_speed = 2.5\n visual_hints = vertex_size=2, edge_color=gray\n}\n");
    nav(0, 0); /* 40 m north of the station */
    ht_iter(0);
    ck_assert(ht_has_str("BHV_SETTINGS", "type=BHV_StationKeep,name=sk,x=0.00,y=-40.00,inner_radius=4.0,outer_radius=15.0,"
                                         "hibernation_radius=-1.0,outer_speed=1.2,center_activate=false"));
    ck_assert(ht_num("DESIRED_SPEED") == 0);
    ck_assert(ht_has_str("VIEW_POLYGON", "radial:: x=0.0,y=-40.0,source=alder:sk,pts=32,edge_size=1,vertex_size=2,"
                                         "edge_color=gray,label_color=white,vertex_color=red,label=alder"
                                         ":station-keep-in,radius=4.0"));
    ck_assert_uint_eq(ht_count("VIEW_POLYGON"), 2); /* no hibernation circle: its radius is not beyond the outer */
    nav(0, 0);
    ht_iter(0.25);
    ck_assert(ht_num("DIST_TO_STATION") == 40);
    ck_assert(ht_has_str("PSKEEP_MODE", "SEEKING_STATION"));
    ck_assert_msg(fabs(ht_num("DESIRED_SPEED") - 2.4) < 1e-9 || fabs(ht_num("DESIRED_SPEED") - 2.6) < 1e-9, "%g",
                  ht_num("DESIRED_SPEED")); /* 2.5 lies between two points of the 0.2 grid */
    ck_assert(ht_num("DESIRED_HEADING") == 180);
    ck_assert_uint_eq(ht_count("VIEW_POLYGON"), 0); /* unchanged: the duplicate filter keeps them */
    nav(9.5, -40); /* between the radii: (9.5 - 4) / 11 x 1.2 = 0.6, course west */
    ht_iter(0.5);
    ck_assert(fabs(ht_num("DESIRED_SPEED") - 0.6) < 1e-9);
    ck_assert(ht_num("DESIRED_HEADING") == 270);
    nav(0, -37); /* inside the inner radius */
    ht_iter(0.75);
    ck_assert(ht_num("DESIRED_SPEED") == 0);
    ck_assert(ht_has_str("PSKEEP_MODE", "HIBERNATING")); /* inside: hibernating (24.8 even without a radius) */
}
END_TEST

/* hibernation_radius: drifting inside it (speed 0, HIBERNATING), seeking once beyond it, back to
 * hibernating inside the inner radius; the circles made inactive when it stops running */
START_TEST(stationkeep_hibernation)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_StationKeep\n{\n name = sk\n condition = GO = true\n station_pt = 0,0\n"
            " hibernation_radius = 20\n}\n");
    kelp_helm_mail_string(ht_helm(), "GO", "true");
    nav(0, 10);
    ht_iter(0);
    ck_assert(ht_has_str("PSKEEP_MODE", "HIBERNATING"));
    ck_assert(ht_has_sub("VIEW_POLYGON", "station-keep-hiber,radius=20.0"));
    nav(0, 10);
    ht_iter(0.25); /* inside the hibernation radius: still drifting */
    ck_assert_uint_eq(ht_count("PSKEEP_MODE"), 0);
    ck_assert(ht_num("DESIRED_SPEED") == 0);
    nav(0, 21);
    ht_iter(0.5);
    ck_assert(ht_has_str("PSKEEP_MODE", "SEEKING_STATION"));
    ck_assert(ht_num("DESIRED_SPEED") > 2);
    nav(0, 3);
    ht_iter(0.75);
    ck_assert(ht_has_str("PSKEEP_MODE", "HIBERNATING"));
    kelp_helm_mail_string(ht_helm(), "GO", "false");
    ht_iter(1.0);
    ck_assert(ht_has_sub("VIEW_POLYGON", "station-keep-out,radius=15.0,active=false"));
}
END_TEST

/* center_activate: the station is where the vehicle is when it starts running */
START_TEST(stationkeep_center_activate)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_StationKeep\n{\n name = sk\n center_activate = true\n}\n");
    nav(30, 40);
    ht_iter(0);
    nav(30, 60);
    ht_iter(0.25);
    ck_assert(ht_num("DIST_TO_STATION") == 20);
    ck_assert(ht_num("DESIRED_HEADING") == 180);
    ck_assert_int_eq(ht_load_rc("Behavior = BHV_StationKeep\n{\n name = bad\n outer_radius = -3\n}\n") < 0, 1);
}
END_TEST

Suite *kelp_bhv_suite(void);
Suite *kelp_bhv_suite(void)
{
    Suite *s = suite_create("bhv");
    TCase *tc = tcase_create("behaviours");
    tcase_set_timeout(tc, 30);
    tcase_add_test(tc, relang_examples);
    tcase_add_test(tc, stationkeep_speeds_and_posts);
    tcase_add_test(tc, stationkeep_hibernation);
    tcase_add_test(tc, stationkeep_center_activate);
    tcase_add_test(tc, swpt_zaic_pieces_figure5);
    tcase_add_test(tc, swpt_reflector_aof_values);
    tcase_add_test(tc, swpt_reflector_function);
    tcase_add_test(tc, swpt_no_nav_warning);
    tcase_add_test(tc, swpt_view_point_and_arrival);
    tcase_add_test(tc, alder_mission_flown);
    tcase_add_loop_test(tc, points_formats, 0, (int)(sizeof g_pts / sizeof g_pts[0]));
    tcase_add_test(tc, points_capacity);
    tcase_add_test(tc, number_text);
    tcase_add_test(tc, waypoint_sequence_flags_end);
    tcase_add_test(tc, waypoint_no_points_empty_start);
    tcase_add_test(tc, waypoint_repeat_and_order);
    tcase_add_test(tc, waypoint_slip_radius);
    tcase_add_test(tc, waypoint_lead);
    tcase_add_test(tc, waypoint_lead_second_leg_and_damper);
    tcase_add_test(tc, waypoint_capture_line);
    tcase_add_test(tc, waypoint_reports_and_hints);
    tcase_add_test(tc, waypoint_updates_points);
    tcase_add_test(tc, waypoint_flag_macros_on_start);
    tcase_add_test(tc, waypoint_lead_condition);
    tcase_add_test(tc, waypoint_no_nav_is_error);
    tcase_add_test(tc, waypoint_end_speed);
    tcase_add_test(tc, waypoint_greedy_tour);
    tcase_add_test(tc, waypoint_perpetual_reset_newpt);
    tcase_add_test(tc, waypoint_settings_string);
    tcase_add_test(tc, constant_mismatch_and_complete_thresh);
    tcase_add_test(tc, constant_depth_speed_heading);
    tcase_add_test(tc, constant_depth_needs_depth);
    tcase_add_test(tc, hierarchical_modes);
    tcase_add_test(tc, helm_interface_publications);
    tcase_add_test(tc, priority_weights_trade_off);
    suite_add_tcase(s, tc);
    return s;
}
