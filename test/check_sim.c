/* Vehicle simulator (uSimMarine role): rate limits, integration against closed-form
 * kinematics, START_POS parsing, time handling. */
#include <check.h>
#include <math.h>
#include <kelp/sim.h>

static kelp_sim S;

static void start(double x, double y, double hdg, double spd, double dep, double turn, double acc, double dec,
                  double drate)
{
    kelp_sim_params p;
    kelp_sim_params_default(&p);
    p.turn_rate = turn;
    p.turn_speed = 0; /* turning at any speed: the closed forms below assume it */
    p.max_accel = acc;
    p.max_decel = dec;
    p.max_depth_rate = drate;
    kelp_sim_state st = {x, y, hdg, spd, dep};
    ck_assert_int_eq(kelp_sim_init(&S, &p, &st, 1000.0), KELP_OK);
}

START_TEST(test_defaults)
{
    kelp_sim_params p;
    kelp_sim_params_default(&p);
    ck_assert(p.turn_rate == 20.0 && p.turn_speed == 0.5 && p.max_accel == 0.5 && p.max_decel == 0.5 && p.max_depth_rate == 0.5);
    ck_assert(p.step == 0.05 && p.max_speed == 0.0 && p.max_depth_rate_speed == 0.0);
}
END_TEST

START_TEST(test_hold_course)
{
    /* no desired values yet: the vehicle keeps its start heading and speed */
    start(0, 0, 90, 2.0, 0, 20, 0.5, 0.5, 0.5);
    ck_assert_int_eq(kelp_sim_step(&S, 1010.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.x, 20.0, 1e-9);
    ck_assert_double_eq_tol(S.s.y, 0.0, 1e-9);
    ck_assert_double_eq_tol(S.odometer, 20.0, 1e-9);
    ck_assert(S.time == 1010.0);
}
END_TEST

START_TEST(test_straight_south_west)
{
    start(10, -5, 225, 1.0, 0, 20, 0.5, 0.5, 0.5);
    ck_assert_int_eq(kelp_sim_step(&S, 1000.0 + 2.0 * sqrt(2.0)), KELP_OK);
    ck_assert_double_eq_tol(S.s.x, 8.0, 1e-9);
    ck_assert_double_eq_tol(S.s.y, -7.0, 1e-9);
}
END_TEST

START_TEST(test_turn_rate)
{
    start(0, 0, 0, 0, 0, 10, 0.5, 0.5, 0.5);
    ck_assert_int_eq(kelp_sim_set_heading(&S, 90), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1004.5), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 45.0, 1e-9);
    ck_assert_int_eq(kelp_sim_step(&S, 1009.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 90.0, 1e-9);
    ck_assert_int_eq(kelp_sim_step(&S, 1020.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 90.0, 1e-9); /* no overshoot */
    /* the short way round: 10 -> 350 turns left through north (20 deg, 2 s) */
    start(0, 0, 10, 0, 0, 10, 0.5, 0.5, 0.5);
    ck_assert_int_eq(kelp_sim_set_heading(&S, -10), KELP_OK); /* = 350 */
    ck_assert_double_eq_tol(S.des_heading, 350.0, 1e-12);
    ck_assert_int_eq(kelp_sim_step(&S, 1001.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 0.0, 1e-9);
    ck_assert_int_eq(kelp_sim_step(&S, 1002.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 350.0, 1e-9);
    /* turn_rate 0: at once */
    start(0, 0, 10, 0, 0, 0, 0.5, 0.5, 0.5);
    ck_assert_int_eq(kelp_sim_set_heading(&S, 200), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1000.05), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 200.0, 1e-9);
}
END_TEST

START_TEST(test_turn_speed)
{
    /* stopped: no turn at all (an all-stop's DESIRED_HEADING 0 does not spin the vehicle) */
    start(0, 0, 180, 0, 0, 10, 0.5, 0.5, 0.5);
    S.p.turn_speed = 0.5;
    ck_assert_int_eq(kelp_sim_set_heading(&S, 0), KELP_OK);
    ck_assert_int_eq(kelp_sim_set_speed(&S, 0), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1010.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 180.0, 1e-12);
    /* at 0.25 m/s (half of turn_speed) the turn rate is halved: 5 deg/s */
    start(0, 0, 0, 0.25, 0, 10, 0.5, 0.5, 0.5);
    S.p.turn_speed = 0.5;
    ck_assert_int_eq(kelp_sim_set_heading(&S, 90), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1004.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 20.0, 1e-9);
    /* at or above turn_speed: the full rate */
    start(0, 0, 0, 0.5, 0, 10, 0.5, 0.5, 0.5);
    S.p.turn_speed = 0.5;
    ck_assert_int_eq(kelp_sim_set_heading(&S, 90), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1004.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 40.0, 1e-9);
    /* accelerating from rest: 0.5 m/s^2 reaches 0.5 m/s at 1 s; the heading change over the
     * first second is the integral of 10 * v/0.5 = 10 * t -> 5 degrees */
    start(0, 0, 0, 0.0, 0, 10, 0.5, 0.5, 0.5);
    S.p.turn_speed = 0.5;
    ck_assert_int_eq(kelp_sim_set_heading(&S, 90), KELP_OK);
    ck_assert_int_eq(kelp_sim_set_speed(&S, 2), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1001.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 5.0, 1e-9);
}
END_TEST

START_TEST(test_accel_decel)
{
    /* 0 -> 2 m/s at 0.5 m/s^2: 4 s and 4 m (v^2 / 2a) */
    start(0, 0, 0, 0, 0, 20, 0.5, 0.25, 0.5);
    ck_assert_int_eq(kelp_sim_set_speed(&S, 2.0), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1002.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.speed, 1.0, 1e-9);
    ck_assert_double_eq_tol(S.s.y, 1.0, 1e-9);
    ck_assert_int_eq(kelp_sim_step(&S, 1004.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.speed, 2.0, 1e-9);
    ck_assert_double_eq_tol(S.s.y, 4.0, 1e-9);
    ck_assert_int_eq(kelp_sim_step(&S, 1005.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.y, 6.0, 1e-9);
    /* stop (all-stop): 2 -> 0 at 0.25 m/s^2 takes 8 s and 8 m */
    ck_assert_int_eq(kelp_sim_set_speed(&S, 0.0), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1013.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.speed, 0.0, 1e-9);
    ck_assert_double_eq_tol(S.s.y, 14.0, 1e-9);
    ck_assert_int_eq(kelp_sim_step(&S, 1100.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.y, 14.0, 1e-9);
    ck_assert_double_eq_tol(S.odometer, 14.0, 1e-9);
    /* negative desired speed is clipped to 0, max_speed clips the top */
    ck_assert_int_eq(kelp_sim_set_speed(&S, -3.0), KELP_OK);
    ck_assert(S.des_speed == 0.0);
    S.p.max_speed = 1.5;
    ck_assert_int_eq(kelp_sim_set_speed(&S, 3.0), KELP_OK);
    ck_assert(S.des_speed == 1.5);
    ck_assert_int_eq(kelp_sim_set_speed(&S, NAN), KELP_ERR_ARG);
    ck_assert(S.des_speed == 1.5);
}
END_TEST

START_TEST(test_depth_rate)
{
    start(0, 0, 0, 1.0, 0, 20, 0.5, 0.5, 0.5);
    ck_assert_int_eq(kelp_sim_set_depth(&S, 10.0), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1010.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.depth, 5.0, 1e-9);
    ck_assert_int_eq(kelp_sim_step(&S, 1030.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.depth, 10.0, 1e-9);
    /* back to the surface, never above it */
    ck_assert_int_eq(kelp_sim_set_depth(&S, -4.0), KELP_OK);
    ck_assert(S.des_depth == 0.0);
    ck_assert_int_eq(kelp_sim_step(&S, 1100.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.depth, 0.0, 1e-12);
    /* speed-scaled rate: at 1 m/s with max_depth_rate_speed 2, half of 0.5 m/s */
    start(0, 0, 0, 1.0, 0, 20, 0.5, 0.5, 0.5);
    S.p.max_depth_rate_speed = 2.0;
    ck_assert_int_eq(kelp_sim_set_depth(&S, 10.0), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1010.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.depth, 2.5, 1e-9);
    /* no way on: no depth change */
    start(0, 0, 0, 0.0, 0, 20, 0.5, 0.5, 0.5);
    S.p.max_depth_rate_speed = 2.0;
    ck_assert_int_eq(kelp_sim_set_depth(&S, 10.0), KELP_OK);
    ck_assert_int_eq(kelp_sim_step(&S, 1010.0), KELP_OK);
    ck_assert_double_eq_tol(S.s.depth, 0.0, 1e-12);
}
END_TEST

START_TEST(test_circle)
{
    /* turning right at 10 deg/s at 2 m/s: radius v/w = 11.4592 m; half a circle (18 s) puts
     * the vehicle 2R east of the start, the full circle (36 s) back at the start */
    start(0, 0, 0, 2.0, 0, 10, 0.5, 0.5, 0.5);
    double R = 2.0 / (10.0 * 3.14159265358979323846 / 180.0);
    for (int t = 1; t <= 36; t++) {
        ck_assert_int_eq(kelp_sim_set_heading(&S, S.s.heading + 90.0), KELP_OK);
        ck_assert_int_eq(kelp_sim_step(&S, 1000.0 + t), KELP_OK);
        if (t == 9) {
            ck_assert_double_eq_tol(S.s.x, R, 1e-3);
            ck_assert_double_eq_tol(S.s.y, R, 1e-3);
            ck_assert_double_eq_tol(S.s.heading, 90.0, 1e-9);
        }
        if (t == 18) {
            ck_assert_double_eq_tol(S.s.x, 2 * R, 1e-3);
            ck_assert_double_eq_tol(S.s.y, 0.0, 1e-3);
        }
    }
    ck_assert_double_eq_tol(S.s.x, 0.0, 1e-3);
    ck_assert_double_eq_tol(S.s.y, 0.0, 1e-3);
    ck_assert_double_eq_tol(S.odometer, 72.0, 1e-9);
}
END_TEST

START_TEST(test_step_independence)
{
    /* one big step and many small ones land on the same state */
    kelp_sim a, b;
    start(0, 0, 30, 0.0, 0, 15, 0.4, 0.5, 0.5);
    ck_assert_int_eq(kelp_sim_set_heading(&S, 250), KELP_OK);
    ck_assert_int_eq(kelp_sim_set_speed(&S, 2.2), KELP_OK);
    ck_assert_int_eq(kelp_sim_set_depth(&S, 3), KELP_OK);
    a = S;
    b = S;
    ck_assert_int_eq(kelp_sim_step(&a, 1030.0), KELP_OK);
    for (int i = 1; i <= 600; i++) ck_assert_int_eq(kelp_sim_step(&b, 1000.0 + i * 0.05), KELP_OK);
    ck_assert_double_eq_tol(a.s.x, b.s.x, 1e-6);
    ck_assert_double_eq_tol(a.s.y, b.s.y, 1e-6);
    ck_assert_double_eq_tol(a.s.heading, b.s.heading, 1e-9);
    ck_assert_double_eq_tol(a.s.depth, 3.0, 1e-9);
    /* deterministic: the same inputs give bit-identical results */
    kelp_sim c = S;
    ck_assert_int_eq(kelp_sim_step(&c, 1030.0), KELP_OK);
    ck_assert(c.s.x == a.s.x && c.s.y == a.s.y);
}
END_TEST

START_TEST(test_time_errors)
{
    start(0, 0, 0, 1.0, 0, 20, 0.5, 0.5, 0.5);
    ck_assert_int_eq(kelp_sim_step(&S, 999.0), KELP_ERR_RANGE);
    ck_assert(S.time == 1000.0 && S.s.y == 0.0);
    ck_assert_int_eq(kelp_sim_step(&S, NAN), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_sim_step(&S, 1000.0 + 1e9), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_sim_step(&S, 1000.0), KELP_OK);
    ck_assert(S.s.y == 0.0);
}
END_TEST

START_TEST(test_init_errors)
{
    kelp_sim_params p;
    kelp_sim_params_default(&p);
    kelp_sim_state st = {0, 0, 0, 0, 0};
    p.turn_rate = -1;
    ck_assert_int_eq(kelp_sim_init(&S, &p, &st, 0), KELP_ERR_ARG);
    kelp_sim_params_default(&p);
    p.step = 0;
    ck_assert_int_eq(kelp_sim_init(&S, &p, &st, 0), KELP_ERR_ARG);
    kelp_sim_params_default(&p);
    st.speed = -1;
    ck_assert_int_eq(kelp_sim_init(&S, &p, &st, 0), KELP_ERR_ARG);
    st.speed = 0;
    st.x = INFINITY;
    ck_assert_int_eq(kelp_sim_init(&S, &p, &st, 0), KELP_ERR_ARG);
    st.x = 0;
    st.heading = -90;
    ck_assert_int_eq(kelp_sim_init(&S, &p, &st, 0), KELP_OK);
    ck_assert_double_eq_tol(S.s.heading, 270.0, 1e-12);
}
END_TEST

START_TEST(test_start_pos)
{
    kelp_sim_state st = {1, 2, 3, 4, 5};
    /* MOOS-IvP positional order: x, y, heading, speed, depth */
    ck_assert_int_eq(kelp_sim_parse_start("0,-10,180,0", &st), KELP_OK);
    ck_assert(st.x == 0 && st.y == -10 && st.heading == 180 && st.speed == 0 && st.depth == 5);
    ck_assert_int_eq(kelp_sim_parse_start(" 5 , 10 ", &st), KELP_OK);
    ck_assert(st.x == 5 && st.y == 10 && st.heading == 180);
    ck_assert_int_eq(kelp_sim_parse_start("x=20, y=-35, speed=2.2, heading=-90, depth=20", &st), KELP_OK);
    ck_assert(st.x == 20 && st.y == -35 && st.speed == 2.2 && st.heading == 270 && st.depth == 20);
    ck_assert_int_eq(kelp_sim_parse_start("HDG=45,SPD=1,DEP=2", &st), KELP_OK);
    ck_assert(st.x == 20 && st.heading == 45 && st.speed == 1 && st.depth == 2);
    kelp_sim_state keep = st;
    ck_assert_int_eq(kelp_sim_parse_start("x=1,colour=red", &st), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_sim_parse_start("x=abc", &st), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_sim_parse_start("x=1,speed=-2", &st), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_sim_parse_start("1", &st), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_sim_parse_start("1,2,3,4,5,6", &st), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_sim_parse_start("1,,3", &st), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_sim_parse_start("1,2,nan", &st), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_sim_parse_start("", &st), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_sim_parse_start("x", &st), KELP_ERR_PARSE);
    ck_assert(st.x == keep.x && st.y == keep.y && st.speed == keep.speed); /* unchanged on error */
}
END_TEST

START_TEST(test_angles)
{
    ck_assert_double_eq_tol(kelp_sim_angle360(-90), 270, 1e-12);
    ck_assert_double_eq_tol(kelp_sim_angle360(720.5), 0.5, 1e-12);
    ck_assert_double_eq_tol(kelp_sim_angle180(270), -90, 1e-12);
    ck_assert_double_eq_tol(kelp_sim_angle180(180), 180, 1e-12);
    /* relAng examples (moosapp_helm.md 2.10) */
    ck_assert_double_eq_tol(kelp_sim_bearing(0, 0, 0, 10), 0, 1e-9);
    ck_assert_double_eq_tol(kelp_sim_bearing(0, 0, 10, 0), 90, 1e-9);
    ck_assert_double_eq_tol(kelp_sim_bearing(0, 0, 0, -10), 180, 1e-9);
    ck_assert_double_eq_tol(kelp_sim_bearing(0, 0, -10, 0), 270, 1e-9);
    ck_assert_double_eq_tol(kelp_sim_bearing(0, 0, 60, -40), 123.690068, 1e-6);
    ck_assert(kelp_sim_bearing(3, 3, 3, 3) == 0.0);
}
END_TEST

Suite *kelp_sim_suite(void)
{
    Suite *s = suite_create("sim");
    TCase *tc = tcase_create("model");
    tcase_add_test(tc, test_defaults);
    tcase_add_test(tc, test_hold_course);
    tcase_add_test(tc, test_straight_south_west);
    tcase_add_test(tc, test_turn_rate);
    tcase_add_test(tc, test_turn_speed);
    tcase_add_test(tc, test_accel_decel);
    tcase_add_test(tc, test_depth_rate);
    tcase_add_test(tc, test_circle);
    tcase_add_test(tc, test_step_independence);
    tcase_add_test(tc, test_time_errors);
    tcase_add_test(tc, test_init_errors);
    tcase_add_test(tc, test_start_pos);
    tcase_add_test(tc, test_angles);
    suite_add_tcase(s, tc);
    return s;
}
