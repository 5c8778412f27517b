/* BHV_Loiter against MOOS-IvP 24.8's (BHV_Loiter.cpp, LoiterEngine.cpp, WaypointEngine.cpp):
 * the entry vertex from outside and inside, clockwise = best, capture and nonmono hits, the
 * status reports and their number rules, the idle reports, BHV_SETTINGS, the function (speed
 * peak, patience), the parameters, the centre assignments, the slingshot and the drawings.
 * Expected values are worked out by hand in the comments. Uses the ht_* harness of check_helm.c. */
#include <check.h>
#include "check_diag.h"
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/helm.h>
#include "check_ht.h"

#define DOM2 "course:0:359:360,speed:0:4:21"
/* a 20 m square, given clockwise (east along the top, then south) */
#define SQUARE " polygon = 0,0:20,0:20,-20:0,-20\n"

static void nav(double x, double y, double hdg, double spd)
{
    kelp_helm_mail_double(ht_helm(), "NAV_X", x);
    kelp_helm_mail_double(ht_helm(), "NAV_Y", y);
    kelp_helm_mail_double(ht_helm(), "NAV_HEADING", hdg);
    kelp_helm_mail_double(ht_helm(), "NAV_SPEED", spd);
}

/* a loiter (with condition GO = true) idle for one iteration at the pose, then running */
static void run_after_idle(const char *bhv, double x, double y, double hdg)
{
    ht_setup(DOM2, NULL);
    ht_load(bhv);
    nav(x, y, hdg, 1);
    ht_iter(0);
    kelp_helm_mail_string(ht_helm(), "GO", "true");
    ht_iter(1);
}

static const char *str(const char *var)
{
    const ht_post *p = ht_last(var);
    ck_assert_msg(p != NULL, "%s not posted", var);
    ck_assert_msg(p->is_str, "%s is a number", var);
    return p->sval;
}

static bool starts(const char *s, const char *prefix)
{
    return strncmp(s, prefix, strlen(prefix)) == 0;
}

/* From outside, 24.8 takes the viewable vertex whose next edge turns most in the loiter's
 * direction, not the nearest one. Radial, 4 points: (7.1,7.1) (7.1,-7.1) (-7.1,-7.1)
 * (-7.1,7.1) (45 degrees first, snapped to 0.1 m). From (0,50) only the two top vertices are
 * viewable; clockwise: vertex 0 turns +9.4 (the edge south), vertex 3 turns -99.4 -> vertex 0,
 * course relAng((0,50),(7.1,7.1)) = 170.6. Counter-clockwise the order is reversed and the
 * left turn wins: (-7.1,7.1) at 189.4. (kelp before: the nearest vertex (0,10), 180.) */
START_TEST(loiter_entry_vertex_outside)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.4\n"
            " polygon = format=radial, x=0, y=0, radius=10, pts=4\n}\n");
    kelp_bhv *b = ht_find("lo");
    ck_assert_uint_eq(b->u.loiter.npts, 4);
    ck_assert(fabs(b->u.loiter.pts[0].x - 7.1) < 1e-9 && fabs(b->u.loiter.pts[0].y - 7.1) < 1e-9);
    nav(0, 50, 180, 1);
    ht_iter(0);
    ck_assert(ht_num("LOITER_INDEX") == 0);
    ck_assert(ht_num("DESIRED_HEADING") == 171);

    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.4\n clockwise = false\n"
            " polygon = format=radial, x=0, y=0, radius=10, pts=4\n}\n");
    b = ht_find("lo");
    ck_assert(fabs(b->u.loiter.pts[0].x + 7.1) < 1e-9 && fabs(b->u.loiter.pts[0].y - 7.1) < 1e-9);
    nav(0, 50, 180, 1);
    ht_iter(0);
    ck_assert(ht_num("LOITER_INDEX") == 0);
    ck_assert(ht_num("DESIRED_HEADING") == 189);
}
END_TEST

/* The square from (30,10): (0,0), (20,0) and (20,-20) are viewable, (0,-20) is behind the
 * square. Turns onto the next edge: (0,0) -161.6, (20,0) -45, (20,-20) +71.6 -> clockwise the
 * entry is (20,-20), course 198.4, although (20,0) is the nearest (14.1 m, course 225). */
START_TEST(loiter_entry_vertex_not_nearest)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.4\n" SQUARE "}\n");
    nav(30, 10, 180, 1);
    ht_iter(0);
    ck_assert(ht_num("LOITER_INDEX") == 2);
    ck_assert(ht_num("DESIRED_HEADING") == 198);
    ck_assert_str_eq(str("LOITER_REPORT"), "index=2,capture_hits=0,nonmono_hits=0,acquire_mode=true");
    ck_assert(fabs(ht_num("LOITER_DIST_TO_VERT") - hypot(10, 30)) < 1e-9);
}
END_TEST

/* From inside (on the idle -> running transition) every vertex of the square seen from its
 * centre turns 135 degrees; the vertex nearest the heading (100: (20,-20) at 135) gets the
 * spiral bonus (-2) -> index 2, course 135. The distance -10 is not beyond acquire_dist: stable. */
START_TEST(loiter_entry_vertex_inside)
{
    run_after_idle("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.4\n condition = GO = true\n" SQUARE "}\n", 10, -10, 100);
    ck_assert(ht_num("LOITER_INDEX") == 2);
    ck_assert(ht_num("DESIRED_HEADING") == 135);
    ck_assert_str_eq(str("LOITER_MODE"), "stable");
    ck_assert(ht_num("LOITER_ACQUIRE") == 0);
    ck_assert(fabs(ht_num("LOITER_DIST_TO_POLY") + 10) < 1e-9);
    /* heading 300: (0,0) at 315 is ahead -> index 0, course 315 */
    run_after_idle("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.4\n condition = GO = true\n" SQUARE "}\n", 10, -10, 300);
    ck_assert_uint_eq(ht_find("lo")->u.loiter.index, 0); /* (LOITER_INDEX 0 as in idle: not posted again) */
    ck_assert(ht_num("DESIRED_HEADING") == 315);
}
END_TEST

/* The waypoint engine's hits: capture within capture_radius (3), nonmono when the distance
 * grows after coming within slip_radius (15); the report counts both. */
START_TEST(loiter_capture_and_nonmono_hits)
{
    /* index 2 (20,-20), 14.1 m; 10 m inside is not acquire mode */
    run_after_idle("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.4\n condition = GO = true\n" SQUARE "}\n", 10, -10, 100);
    ck_assert_str_eq(str("LOITER_REPORT"), "index=2,capture_hits=0,nonmono_hits=0,acquire_mode=false");
    nav(12, -12, 135, 1);
    ht_iter(2); /* 11.3 m: closer (the report is unchanged: filtered) */
    ck_assert(ht_last("LOITER_REPORT") == NULL);
    ck_assert(fabs(ht_num("LOITER_DIST_TO_VERT") - hypot(8, 8)) < 1e-9);
    nav(11, -11, 135, 1);
    ht_iter(3); /* 12.7 m: farther again within 15 -> nonmono hit, next (0,-20) */
    ck_assert_str_eq(str("LOITER_REPORT"), "index=3,capture_hits=0,nonmono_hits=1,acquire_mode=false");
    ck_assert(ht_num("LOITER_INDEX") == 3);
    nav(1, -18, 225, 1);
    ht_iter(4); /* 2.2 m from (0,-20): captured, the list cycles to 0 */
    ck_assert_str_eq(str("LOITER_REPORT"), "index=0,capture_hits=1,nonmono_hits=1,acquire_mode=false");
    ck_assert(ht_num("DESIRED_HEADING") == 357); /* relAng((1,-18),(0,0)) = 356.8 */
}
END_TEST

/* LOITER_DIST_TO_POLY: rounded (v + 0.5, truncated) above 10, else as it is (negative inside);
 * LOITER_ETA_TO_POLY: rounded above 10 or when 0, else as it is. ETA = distance / speed, set only
 * when the heading (24.8 tests the heading) is above 0.001; at speed 0 it is infinite, which
 * 24.8's int conversion turns into INT_MIN on x86-64. */
START_TEST(loiter_dist_eta_int_or_double)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.4\n" SQUARE "}\n");
    nav(30, 10, 90, 2);
    ht_iter(0); /* 14.14 m, 7.07 s */
    ck_assert(ht_num("LOITER_DIST_TO_POLY") == 14);
    ck_assert(fabs(ht_num("LOITER_ETA_TO_POLY") - sqrt(200) / 2) < 1e-9);
    nav(25, -10, 270, 1);
    ht_iter(1); /* 5 m, 5 s */
    ck_assert(ht_num("LOITER_DIST_TO_POLY") == 5);
    ck_assert(ht_num("LOITER_ETA_TO_POLY") == 5);
    nav(25.25, -10, 270, 0.4);
    ht_iter(2); /* 5.25 m, 13.125 s */
    ck_assert(fabs(ht_num("LOITER_DIST_TO_POLY") - 5.25) < 1e-9);
    ck_assert(ht_num("LOITER_ETA_TO_POLY") == 13);
    nav(40.5, -10, 270, 0.5);
    ht_iter(3); /* 20.5 m -> 21 (a tie rounds up), 41 s */
    ck_assert(ht_num("LOITER_DIST_TO_POLY") == 21);
    ck_assert(ht_num("LOITER_ETA_TO_POLY") == 41);
    nav(40.5, -10, 270, 0);
    ht_iter(4);
    ck_assert(ht_num("LOITER_ETA_TO_POLY") == (double)INT_MIN);
    nav(40.5, -10, 0, 1);
    ht_iter(5); /* heading 0: no ETA */
    ck_assert(ht_num("LOITER_ETA_TO_POLY") == 0);
    nav(10, -12.5, 0, 1);
    ht_iter(6); /* inside, 7.5 m from the bottom edge */
    ck_assert(fabs(ht_num("LOITER_DIST_TO_POLY") + 7.5) < 1e-9);
}
END_TEST

/* Idle: the erasing drawings, then the reports with LOITER_MODE idle, in 24.8's order; the
 * transition to running posts BHV_SETTINGS; the mode follows updateLoiterMode. */
START_TEST(loiter_idle_reports_and_modes)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = Lo\n speed = 1.4\n condition = GO = true\n" SQUARE "}\n");
    nav(30, 10, 180, 1);
    ht_iter(0);
    ck_assert_str_eq(str("VIEW_POINT"), "x=0,y=0,active=false,label=alder_waypoint");
    ck_assert_str_eq(str("VIEW_POLYGON"), "pts={0,0:20,0:20,-20:0,-20},active=false,label=alder_lo");
    ck_assert_str_eq(str("LOITER_REPORT"), "index=0,capture_hits=0,nonmono_hits=0,acquire_mode=true");
    ck_assert_str_eq(str("LOITER_MODE"), "idle");
    ck_assert(ht_num("LOITER_INDEX") == 0 && ht_num("LOITER_ACQUIRE") == 1);
    ck_assert(ht_num("LOITER_DIST_TO_POLY") == 0 && ht_num("LOITER_ETA_TO_POLY") == 0);
    const char *order[] = {"VIEW_POINT", "VIEW_POLYGON", "LOITER_REPORT", "LOITER_INDEX", "LOITER_MODE",
                           "LOITER_ACQUIRE", "LOITER_DIST_TO_POLY", "LOITER_ETA_TO_POLY"};
    for (unsigned i = 1; i < sizeof order / sizeof order[0]; i++)
        ck_assert_msg(ht_last(order[i - 1]) < ht_last(order[i]), "%s after %s", order[i - 1], order[i]);
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 1); /* the start-up settings, with the first engaged iteration */
    kelp_helm_mail_string(ht_helm(), "GO", "true");
    ht_iter(1);
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 1);
    ck_assert_str_eq(str("LOITER_MODE"), "acquiring_external");
    nav(10, -1, 180, 1);
    ht_iter(2);
    ck_assert_str_eq(str("LOITER_MODE"), "stable");
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 0);
    nav(10, 15, 0, 1);
    ht_iter(3);
    ck_assert_str_eq(str("LOITER_MODE"), "recovering_external");
    kelp_helm_mail_string(ht_helm(), "GO", "false");
    ht_iter(4);
    ck_assert_str_eq(str("LOITER_MODE"), "idle");
    ck_assert_str_eq(str("VIEW_POLYGON"), "pts={0,0:20,0:20,-20:0,-20},active=false,label=alder_lo");
    kelp_helm_mail_string(ht_helm(), "GO", "true");
    ht_iter(5);
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 1);
    ck_assert_str_eq(str("LOITER_MODE"), "acquiring_external");
}
END_TEST

/* BHV_SETTINGS: the centre (bounding box) with 2 decimals, the speed with 1 (clamped to the
 * domain), the polygon in its loiter order with at most 1 decimal. */
START_TEST(loiter_settings_text)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 9\n clockwise = false\n"
            " polygon = 0,0:40,0:40,-30:0.04,-30.06\n}\n");
    nav(0, 50, 180, 1);
    ht_iter(0);
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 1);
    ck_assert_str_eq(str("BHV_SETTINGS"), "type=BHV_Loiter,name=lo,x=20.00,y=-15.05,clockwise=false,"
                                          "dynamic_clockwise=false,center_activate=false,desired_speed=4.0,"
                                          "polygon=\"pts={0,-30.1:40,-30:40,0:0,0}\"");
    /* the spec's own label goes with the polygon */
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.25\n"
            " polygon = format=radial, x=0, y=0, radius=10, pts=4, label=home\n}\n");
    nav(0, 50, 180, 1);
    ht_iter(0);
    ck_assert_str_eq(str("BHV_SETTINGS"), "type=BHV_Loiter,name=lo,x=0.00,y=0.00,clockwise=true,"
                                          "dynamic_clockwise=false,center_activate=false,desired_speed=1.2,"
                                          "polygon=\"pts={7.1,7.1:7.1,-7.1:-7.1,-7.1:-7.1,7.1},label=home\"");
}
END_TEST

/* The function: a course peak (base 180) coupled with a speed peak of base width 0.3 (peak
 * width and summit delta 0), the course weighted by patience. At the course, speed 0 scores
 * the course's share alone; 180 degrees off at the speed, the speed's share. */
START_TEST(loiter_function_speed_peak_and_patience)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.4\n patience = 80\n" SQUARE "}\n");
    nav(30, 10, 180, 1);
    ht_iter(0); /* course 198.43 */
    const kelp_ivp_func *f = &ht_helm()->fn[0];
    double top = ht_eval2(f, 198, 7);
    ck_assert(top > 99);
    ck_assert(top - ht_eval2(f, 198, 6) > 10); /* 0.2 off a base of 0.3: a third of the speed share (20) */
    ck_assert(fabs(ht_eval2(f, 198, 0) - 80) < 0.5);
    ck_assert(fabs(ht_eval2(f, 18, 7) - 20) < 0.5);
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.4\n" SQUARE "}\n");
    nav(30, 10, 180, 1);
    ht_iter(0);
    ck_assert(fabs(ht_eval2(&ht_helm()->fn[0], 198, 0) - 50) < 0.5);
    /* ipf_type = zaic_spd: speed points (index: utility) 0:0, 1:85 (0.1 m/s), 7:100 (1.4),
     * 9:20 (1.8), 20:0, straight lines between; each half of the coupling 50 */
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1.4\n ipf_type = zaic_spd\n" SQUARE "}\n");
    nav(30, 10, 180, 1);
    ht_iter(0);
    f = &ht_helm()->fn[0];
    ck_assert(fabs(ht_eval2(f, 198, 7) - 100) < 0.5);
    ck_assert(fabs(ht_eval2(f, 198, 8) - 80) < 0.5);
    ck_assert(fabs(ht_eval2(f, 198, 4) - (50 + 92.5 / 2)) < 0.5);
    ck_assert(fabs(ht_eval2(f, 198, 1) - (50 + 85.0 / 2)) < 0.5);
    ck_assert(fabs(ht_eval2(f, 198, 20) - 50) < 0.5);
    ck_assert(fabs(ht_eval2(f, 198, 14) - (50 + 20.0 * 6 / 11 / 2)) < 0.5);
}
END_TEST

/* The parameters 24.8 takes and refuses. */
static const struct {
    const char *line;
    bool ok;
} g_params[] = {
    {"acquire_distance = 5", true},
    {"patience = 80", true},
    {"patience = 0", false},
    {"patience = 100", false},
    {"slingshot = 360", true},
    {"slingshot = -1", false},
    {"ipf_type = zaic_spd", true},
    {"ipf-type = anything", true},
    {"clockwise = best", true},
    {"clockwise = yes", true},
    {"clockwise = maybe", false},
    {"use_alt_speed = true", true},
    {"speed_alt = -2", true},
    {"center_assign = 5,5", true},
    {"xcenter_assign = 5", true},
    {"ycenter_assign = 5", true},
    {"mod_poly_rad = 5", true},
    {"mod_poly_rad = x", false},
    {"spiral_factor = 50", true},
    {"center_activate = TRUE", true},
    {"center_activate = yes", false},
    {"points = 0,0:20,0:20,-20", false},
    {"polygon = x=0, y=0, radius=10, pts=4", false},
    {"polygon = radial: 0, 0, 10, 6", true},
    {"polygon = 0,0:10,10:10,0:0,10", false}, /* crossed: not convex */
    {"polygon = 0,0:10,0:20,0", false},       /* on one line */
    {"speed = -1", false},
};

START_TEST(loiter_params)
{
    char text[512];
    ht_setup(DOM2, NULL);
    snprintf(text, sizeof text, "Behavior = BHV_Loiter\n{\n name = lo\n" SQUARE " %s\n}\n", g_params[_i].line);
    int rc = ht_load_rc(text);
    ck_assert_msg((rc == 0) == g_params[_i].ok, "%s: %d", g_params[_i].line, rc);
}
END_TEST

/* center_assign moves the polygon at once (its bounding-box centre); xcenter_assign waits for
 * the next run iteration; center_activate centres it on the vehicle after an idle spell. */
START_TEST(loiter_center_assignments)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1\n" SQUARE " center_assign = 100,50\n}\n");
    nav(0, 50, 180, 1);
    ht_iter(0); /* the start-up settings go out with the first engaged iteration (24.8) */
    ck_assert(strstr(str("BHV_SETTINGS"), "x=100.00,y=50.00,") != NULL);
    ck_assert(strstr(str("BHV_SETTINGS"), "pts={90,60:110,60:110,40:90,40}") != NULL);

    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1\n" SQUARE " xcenter_assign = 0\n}\n");
    nav(0, 50, 180, 1);
    ht_iter(0); /* the settings (posted before the run) still show the polygon where it was */
    ck_assert(strstr(str("BHV_SETTINGS"), "x=10.00,y=-10.00,") != NULL);
    ck_assert(starts(str("VIEW_POLYGON"), "pts={-10,0:10,0:10,-20:-10,-20},"));

    run_after_idle("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1\n condition = GO = true\n center_activate = true\n"
                   SQUARE "}\n", 100, 100, 0);
    ck_assert(starts(str("VIEW_POLYGON"), "pts={90,110:110,110:110,90:90,90},"));
}
END_TEST

/* clockwise = best (on idle -> running, outside): the direction whose entry vertex is the
 * smaller turn from the heading. From (30,10): clockwise entry (20,-20) at 198.4, counter-
 * clockwise entry (0,0) at 251.6. Heading 180 keeps clockwise; heading 0 turns less to 251.6. */
START_TEST(loiter_clockwise_best)
{
    run_after_idle("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1\n condition = GO = true\n clockwise = best\n" SQUARE
            "}\n", 30, 10, 180);
    ck_assert(ht_num("DESIRED_HEADING") == 198);
    ck_assert(ht_find("lo")->u.loiter.clockwise);

    run_after_idle("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1\n condition = GO = true\n clockwise = best\n" SQUARE
            "}\n", 30, 10, 0);
    ck_assert(!ht_find("lo")->u.loiter.clockwise);
    ck_assert(ht_num("LOITER_INDEX") == 3); /* (0,-20):(20,-20):(20,0):(0,0) */
    ck_assert(ht_num("DESIRED_HEADING") == 252);
}
END_TEST

/* slingshot: while loitering, the bearing to the centre is summed; past the limit the
 * behaviour completes and posts LOITER_COMPLETE. */
START_TEST(loiter_slingshot)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1\n slingshot = 100\n" SQUARE "}\n");
    nav(2, -2, 90, 1);
    ht_iter(0); /* bearing to (10,-10): 135 */
    ck_assert(ht_last("LOITER_BNG_TOTAL") == NULL);
    nav(18, -2, 180, 1);
    ht_iter(1); /* 225: +90 */
    ck_assert(ht_num("LOITER_BNG_TOTAL") == 90 && ht_num("LOITER_BNG_DELTA") == 90);
    ck_assert(ht_last("LOITER_COMPLETE") == NULL);
    nav(18, -18, 270, 1);
    ht_iter(2); /* 315: 180 > 100 */
    ck_assert(ht_num("LOITER_BNG_TOTAL") == 180);
    ck_assert_str_eq(str("LOITER_COMPLETE"), "true");
    ck_assert(ht_find("lo")->completed);
    /* any completion (here the duration) runs onCompleteState: the drawings erased, LOITER_COMPLETE */
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1\n duration = 5\n" SQUARE "}\n");
    nav(30, 10, 180, 1);
    ht_iter(0);
    ck_assert(ht_last("LOITER_COMPLETE") == NULL);
    ht_iter(10);
    ck_assert(ht_find("lo")->completed);
    ck_assert_str_eq(str("LOITER_COMPLETE"), "true");
    ck_assert_str_eq(str("VIEW_POLYGON"), "pts={0,0:20,0:20,-20:0,-20},active=false,label=alder_lo");
    ck_assert_str_eq(str("VIEW_POINT"), "x=20,y=-20,active=false,label=alder_waypoint");
}
END_TEST

/* The drawings while running, post_suffix upper-cased, a missing heading is an error. */
START_TEST(loiter_drawings_suffix_errors)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1\n post_suffix = east\n" SQUARE "}\n");
    nav(30, 10, 180, 1);
    ht_iter(0);
    ck_assert_str_eq(str("VIEW_POLYGON"), "pts={0,0:20,0:20,-20:0,-20},label=alder_lo,edge_color=white,"
                                          "vertex_color=dodger_blue,vertex_size=1,edge_size=1");
    ck_assert_str_eq(str("VIEW_POINT"), "x=20,y=-20,label=alder_waypoint,label_color=aqua,vertex_color=yellow,"
                                        "vertex_size=5");
    ck_assert(ht_last("LOITER_INDEX_EAST") != NULL && ht_last("LOITER_INDEX") == NULL);
    ck_assert(ht_last("LOITER_MODE_EAST") != NULL && ht_last("LOITER_DIST_TO_VERT") != NULL);

    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Loiter\n{\n name = lo\n speed = 1\n" SQUARE "}\n");
    kelp_helm_mail_double(ht_helm(), "NAV_X", 30);
    kelp_helm_mail_double(ht_helm(), "NAV_Y", 10);
    ht_iter(0);
    ck_assert(ht_has_str("BHV_ERROR", "lo: No ownship heading info in info_buffer."));
    ck_assert(ht_has_str("VIEW_POINT", "x=0,y=0,active=false,label=alder_waypoint"));
}
END_TEST

Suite *kelp_bhv_loiter_suite(void);
Suite *kelp_bhv_loiter_suite(void)
{
    Suite *s = suite_create("bhv_loiter");
    TCase *tc = tcase_create("loiter");
    tcase_set_timeout(tc, 30);
    tcase_add_test(tc, loiter_entry_vertex_outside);
    tcase_add_test(tc, loiter_entry_vertex_not_nearest);
    tcase_add_test(tc, loiter_entry_vertex_inside);
    tcase_add_test(tc, loiter_capture_and_nonmono_hits);
    tcase_add_test(tc, loiter_dist_eta_int_or_double);
    tcase_add_test(tc, loiter_idle_reports_and_modes);
    tcase_add_test(tc, loiter_settings_text);
    tcase_add_test(tc, loiter_function_speed_peak_and_patience);
    tcase_add_loop_test(tc, loiter_params, 0, (int)(sizeof g_params / sizeof g_params[0]));
    tcase_add_test(tc, loiter_center_assignments);
    tcase_add_test(tc, loiter_clockwise_best);
    tcase_add_test(tc, loiter_slingshot);
    tcase_add_test(tc, loiter_drawings_suffix_errors);
    suite_add_tcase(s, tc);
    return s;
}
