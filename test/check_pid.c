/* Unit tests: the scalar PID (MOOS-IvP ScalarPID's rules), the marine PID engine (pMarinePID's
 * iteration) and the simulator's rudder/thrust model (uSimMarine's). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/pid.h>
#include <kelp/sim.h>

START_TEST(scalar_pid_rules)
{
    kelp_pid p;
    double out;
    /* P only; the first run has no derivative or integral */
    kelp_pid_init(&p, 2, 0, 0, 0, 100);
    ck_assert_int_eq(kelp_pid_run(&p, 10, 0, &out), 0);
    ck_assert(out == 20);
    /* the output limit clips and flags saturation */
    ck_assert_int_eq(kelp_pid_run(&p, 80, 1, &out), 0);
    ck_assert(out == 100 && p.saturated);
    ck_assert_int_eq(kelp_pid_run(&p, -80, 2, &out), 0);
    ck_assert(out == -100 && p.saturated);
    /* dt == 0 repeats the output; time going back is refused */
    ck_assert_int_eq(kelp_pid_run(&p, 1, 2, &out), 0);
    ck_assert(out == -100);
    ck_assert_int_eq(kelp_pid_run(&p, 1, 1, &out), KELP_ERR_RANGE);
    /* I: ki * e * dt accumulates, clipped to the integral limit */
    kelp_pid_init(&p, 0, 0, 0.5, 3, 100);
    ck_assert_int_eq(kelp_pid_run(&p, 2, 0, &out), 0);
    ck_assert(out == 0); /* dt 0 on the first run */
    ck_assert_int_eq(kelp_pid_run(&p, 2, 1, &out), 0);
    ck_assert(fabs(out - 1) < 1e-12);
    ck_assert_int_eq(kelp_pid_run(&p, 2, 2, &out), 0);
    ck_assert(fabs(out - 2) < 1e-12);
    ck_assert_int_eq(kelp_pid_run(&p, 2, 4, &out), 0);
    ck_assert(fabs(out - 3) < 1e-12); /* 4 clipped to 3 */
    /* D: the mean of the last 9 slopes */
    kelp_pid_init(&p, 0, 1, 0, 0, 100);
    ck_assert_int_eq(kelp_pid_run(&p, 0, 0, &out), 0);
    ck_assert_int_eq(kelp_pid_run(&p, 1, 1, &out), 0);
    ck_assert(fabs(out - 1) < 1e-12);
    ck_assert_int_eq(kelp_pid_run(&p, 1, 2, &out), 0);
    ck_assert(fabs(out - 0.5) < 1e-12); /* slopes 1, 0 */
    for (int t = 3; t < 20; t++) ck_assert_int_eq(kelp_pid_run(&p, 1, t, &out), 0);
    ck_assert(out == 0); /* the slope of 1 has left the 9-deep history */
}
END_TEST

typedef struct rec {
    char var[32][32];
    double v[32];
    int n;
} rec;

static void sink(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    if (r->n >= 32) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    r->v[r->n++] = is_string ? (strcmp(sval, "true") == 0) : dval;
}

static double last(const rec *r, const char *var)
{
    for (int i = r->n; i-- > 0;)
        if (!strcmp(r->var[i], var)) return r->v[i];
    return NAN;
}

START_TEST(marine_pid_iteration)
{
    kelp_marine_pid_cfg c;
    kelp_marine_pid_cfg_default(&c);
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_marine_pid_cfg_set(&c, "yaw_pid_kp", "0.5", &why), 1);
    ck_assert_int_eq(kelp_marine_pid_cfg_set(&c, "YAW_PID_KI_LIMIT", "0.2", &why), 1);
    ck_assert(c.yaw[3] == 0.2);
    ck_assert_int_eq(kelp_marine_pid_cfg_set(&c, "MAXRUDDER", "30", &why), 1);
    ck_assert_int_eq(kelp_marine_pid_cfg_set(&c, "speed_factor", "20", &why), 1);
    ck_assert_int_lt(kelp_marine_pid_cfg_set(&c, "speed_factor", "101", &why), 0);
    ck_assert_int_lt(kelp_marine_pid_cfg_set(&c, "depth_control", "maybe", &why), 0);
    ck_assert_int_eq(kelp_marine_pid_cfg_set(&c, "NAV_X", "1", &why), 0);
    kelp_marine_pid m;
    rec r = { 0 };
    ck_assert_int_eq(kelp_marine_pid_init(&m, &c, 0), 0);
    /* not in control: one all-stop, then silence */
    kelp_marine_pid_iterate(&m, 0.1, sink, &r);
    kelp_marine_pid_iterate(&m, 0.2, sink, &r);
    ck_assert_int_eq(r.n, 2);
    ck_assert(last(&r, "DESIRED_RUDDER") == 0 && last(&r, "DESIRED_THRUST") == 0);
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "MOOS_MANUAL_OVERRIDE", true, "false", 0, 0.3), 1);
    /* in control, but no helm yet: thrust 0 (tardy) */
    r.n = 0;
    kelp_marine_pid_iterate(&m, 0.4, sink, &r);
    ck_assert_int_eq(r.n, 1);
    ck_assert_str_eq(r.var[0], "DESIRED_THRUST");
    /* heading 350, desired 10: the error wraps to 20 degrees: rudder +10 (right), thrust 2 x 20 */
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "NAV_HEADING", false, NULL, 350, 1), 1);
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "NAV_SPEED", false, NULL, 1, 1), 1);
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "DESIRED_HEADING", false, NULL, 10, 1), 1);
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "DESIRED_SPEED", false, NULL, 2, 1), 1);
    r.n = 0;
    kelp_marine_pid_iterate(&m, 1.1, sink, &r);
    ck_assert(fabs(last(&r, "DESIRED_RUDDER") - 10) < 1e-9);
    ck_assert(last(&r, "DESIRED_THRUST") == 40);
    ck_assert(last(&r, "PID_MAX_SAT_HDG") == 0);
    /* a big error: clipped to maxrudder 30; NAV_YAW gives the heading as -yaw in degrees */
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "NAV_YAW", false, NULL, 3.14159265358979 / 2, 1.2), 1);
    ck_assert(fabs(m.heading - 270) < 1e-6);
    r.n = 0;
    kelp_marine_pid_iterate(&m, 1.3, sink, &r);
    ck_assert(fabs(last(&r, "DESIRED_RUDDER") - 30) < 1e-9);
    /* desired speed 0: thrust 0 and rudder 0 */
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "DESIRED_SPEED", false, NULL, 0, 1.4), 1);
    r.n = 0;
    kelp_marine_pid_iterate(&m, 1.5, sink, &r);
    ck_assert(last(&r, "DESIRED_THRUST") == 0 && last(&r, "DESIRED_RUDDER") == 0);
    /* the helm goes quiet for more than 2 s: thrust 0 only */
    r.n = 0;
    kelp_marine_pid_iterate(&m, 4.0, sink, &r);
    ck_assert_int_eq(r.n, 1);
    ck_assert(last(&r, "DESIRED_THRUST") == 0);
    ck_assert_uint_eq(m.tardy_helm_n, 2); /* before any helm mail, and now */
    /* override again: one all-stop */
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "MOOS_MANUAL_OVERIDE", true, "true", 0, 4.1), 1);
    ck_assert_int_lt(kelp_marine_pid_mail(&m, "MOOS_MANUAL_OVERRIDE", true, "perhaps", 0, 4.1), 0);
    r.n = 0;
    kelp_marine_pid_iterate(&m, 4.2, sink, &r);
    kelp_marine_pid_iterate(&m, 4.3, sink, &r);
    ck_assert_int_eq(r.n, 2);
}
END_TEST

START_TEST(marine_pid_speed_and_depth_loops)
{
    kelp_marine_pid_cfg c;
    kelp_marine_pid_cfg_default(&c);
    c.active_start = true;
    c.speed[0] = 10; /* speed PID: thrust grows by 10 per m/s of error each run */
    c.depth_control = true;
    c.z_to_pitch[0] = 0.1;
    c.pitch[0] = 1;
    snprintf(c.suffix, sizeof c.suffix, "_PID");
    kelp_marine_pid m;
    rec r = { 0 };
    ck_assert_int_eq(kelp_marine_pid_init(&m, &c, 0), 0);
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "DESIRED_SPEED", false, NULL, 2, 0), 1);
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "DESIRED_HEADING", false, NULL, 0, 0), 1);
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "DESIRED_DEPTH", false, NULL, 10, 0), 1);
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "NAV_SPEED", false, NULL, 1, 0), 1);
    ck_assert_int_eq(kelp_marine_pid_mail(&m, "NAV_DEPTH", false, NULL, 0, 0), 1);
    kelp_marine_pid_iterate(&m, 0.5, sink, &r);
    kelp_marine_pid_iterate(&m, 1.0, sink, &r);
    ck_assert(last(&r, "DESIRED_THRUST_PID") == 20); /* 10 + 10: incremental on the last thrust */
    /* 10 m too shallow: pitch wanted -1 rad, clipped to -15 degrees; elevator +15 deg -> 13 */
    ck_assert(fabs(last(&r, "DESIRED_ELEVATOR_PID") - 13) < 1e-9);
    ck_assert(last(&r, "PID_MAX_SAT_DEP") == 0);
}
END_TEST

START_TEST(sim_rudder_thrust_model)
{
    kelp_sim_params p;
    kelp_sim_params_default(&p);
    kelp_diag why = { 0 };
    kelp_sim_state st = { 0, 0, 0, 0, 0 };
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "thrust_map", "0:0, 20:1, 40:2, 60:3, 80:5, 100:5", &why), 1);
    ck_assert(kelp_sim_thrust_speed(&p, 30) == 1.5 && kelp_sim_thrust_speed(&p, 90) == 5 &&
              kelp_sim_thrust_speed(&p, -10) == 0);
    ck_assert_int_lt(kelp_sim_config_set(&p, &st, "THRUST_MAP", "0:0, 20:1, 10:2", &why), 0);
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "TURN_SPD_LOSS", "0.5", &why), 1);
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "MAX_ACCELERATION", "0", &why), 1);
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "MAX_DECELERATION", "0", &why), 1);
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "TURN_RATE", "70", &why), 1);
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "drift_vector", "90, 0.5", &why), 1);
    ck_assert(fabs(p.drift_x - 0.5) < 1e-12 && fabs(p.drift_y) < 1e-12);
    p.drift_x = 0;
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "start_heading", "-90", &why), 1);
    ck_assert(st.heading == 270);
    st.heading = 0;
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "NO_SUCH", "1", &why), 0);
    kelp_sim sim;
    ck_assert_int_eq(kelp_sim_init(&sim, &p, &st, 0), 0);
    ck_assert(!sim.actuated);
    /* thrust 40: 2 m/s, straight north */
    ck_assert_int_eq(kelp_sim_set_thrust(&sim, 40), 0);
    ck_assert(sim.actuated);
    ck_assert_int_eq(kelp_sim_step(&sim, 1), 0);
    ck_assert(fabs(sim.s.speed - 2) < 1e-9 && fabs(sim.s.y - 2) < 1e-6);
    /* full rudder: speed drops by turn_spd_loss; heading turns at 100 * 0.7 * (thrust/50) deg/s */
    ck_assert_int_eq(kelp_sim_set_rudder(&sim, 100), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 2), 0);
    ck_assert(fabs(sim.s.speed - 1) < 1e-9);
    ck_assert(fabs(sim.s.heading - 56) < 1e-6);
    /* no way on: the rudder does nothing; positive buoyancy rises */
    sim.p.buoyancy_rate = 0.1;
    sim.s.depth = 5;
    ck_assert_int_eq(kelp_sim_set_thrust(&sim, 0), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 3), 0);
    ck_assert(sim.s.speed == 0);
    double h = sim.s.heading;
    ck_assert_int_eq(kelp_sim_step(&sim, 4), 0);
    ck_assert(sim.s.heading == h);
    ck_assert(fabs(sim.s.depth - 4.8) < 1e-6);
    /* elevator dives with way on, limited by max_depth_rate x sqrt(speed share) */
    sim.p.buoyancy_rate = 0;
    sim.p.max_depth_rate = 0.5;
    sim.p.max_depth_rate_speed = 4;
    ck_assert_int_eq(kelp_sim_set_rudder(&sim, 0), 0);
    ck_assert_int_eq(kelp_sim_set_thrust(&sim, 20), 0); /* 1 m/s: sqrt(1/4) = 0.5 */
    ck_assert_int_eq(kelp_sim_set_elevator(&sim, 100), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 5), 0);
    ck_assert(fabs(sim.s.depth - (4.8 + 0.25)) < 1e-6);
    ck_assert(sim.pitch < 0); /* nose down */
    /* over ground: a drift adds to the track */
    sim.p.drift_x = 1;
    ck_assert_int_eq(kelp_sim_set_elevator(&sim, 0), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 6), 0);
    ck_assert(sim.sog > 1.0);
    /* acceleration limits apply in this model too */
    sim.p.max_accel = 0.1;
    ck_assert_int_eq(kelp_sim_set_thrust(&sim, 100), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 7), 0);
    ck_assert(fabs(sim.s.speed - 1.1) < 1e-6);
    /* CONTROL = direct ignores the actuators */
    kelp_sim_params d;
    kelp_sim_params_default(&d);
    ck_assert_int_eq(kelp_sim_config_set(&d, NULL, "control", "direct", &why), 1);
    ck_assert_int_lt(kelp_sim_config_set(&d, NULL, "control", "sideways", &why), 0);
    ck_assert_int_eq(kelp_sim_init(&sim, &d, &st, 0), 0);
    ck_assert_int_eq(kelp_sim_set_thrust(&sim, 100), 0);
    ck_assert(!sim.actuated);
}
END_TEST

Suite *kelp_pid_suite(void)
{
    Suite *s = suite_create("pid");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, scalar_pid_rules);
    tcase_add_test(tc, marine_pid_iteration);
    tcase_add_test(tc, marine_pid_speed_and_depth_loops);
    tcase_add_test(tc, sim_rudder_thrust_model);
    suite_add_tcase(s, tc);
    return s;
}
