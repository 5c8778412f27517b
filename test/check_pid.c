/* Unit tests: the scalar PID (MOOS-IvP ScalarPID's rules), the marine PID engine (pMarinePID's
 * iteration) and the simulator's rudder/thrust model (uSimMarine's). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/pid.h>
#include <kelp/sim.h>
#include <kelp/usim.h>

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
    char s[32][256];
    double v[32];
    int n;
} rec;

static void sink(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    if (r->n >= 32) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    snprintf(r->s[r->n], sizeof r->s[0], "%s", is_string ? sval : "");
    r->v[r->n++] = is_string ? (strcmp(sval, "true") == 0) : dval;
}

static const char *last_s(const rec *r, const char *var)
{
    for (int i = r->n; i-- > 0;)
        if (!strcmp(r->var[i], var)) return r->s[i];
    return NULL;
}

static double last(const rec *r, const char *var)
{
    for (int i = r->n; i-- > 0;)
        if (!strcmp(r->var[i], var)) return r->v[i];
    return NAN;
}

START_TEST(marine_pid_iteration)
{
    kelp_pid_marine_cfg c;
    kelp_pid_marine_cfg_default(&c);
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "yaw_pid_kp", "0.5", &why), 1);
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "YAW_PID_KI_LIMIT", "0.2", &why), 1);
    ck_assert(c.yaw[3] == 0.2);
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "MAXRUDDER", "30", &why), 1);
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "speed_factor", "20", &why), 1);
    ck_assert_int_lt(kelp_pid_marine_cfg_set(&c, "speed_factor", "101", &why), 0);
    ck_assert_int_lt(kelp_pid_marine_cfg_set(&c, "depth_control", "maybe", &why), 0);
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "NAV_X", "1", &why), 0);
    kelp_pid_marine m;
    rec r = { 0 };
    ck_assert_int_eq(kelp_pid_marine_init(&m, &c, 0), 0);
    /* not in control: one all-stop, then silence */
    kelp_pid_marine_iterate(&m, 0.1, sink, &r);
    kelp_pid_marine_iterate(&m, 0.2, sink, &r);
    ck_assert_int_eq(r.n, 2);
    ck_assert(last(&r, "DESIRED_RUDDER") == 0 && last(&r, "DESIRED_THRUST") == 0);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "MOOS_MANUAL_OVERRIDE", true, "false", 0, 0.3), 1);
    /* in control (PID_HAS_CONTROL), but no helm yet: rudder and thrust 0 */
    r.n = 0;
    kelp_pid_marine_iterate(&m, 0.4, sink, &r);
    ck_assert_int_eq(r.n, 3);
    ck_assert_str_eq(r.var[0], "PID_HAS_CONTROL");
    ck_assert(r.v[0] == 1);
    ck_assert(last(&r, "DESIRED_RUDDER") == 0 && last(&r, "DESIRED_THRUST") == 0);
    /* heading 350, desired 10: the error wraps to 20 degrees: rudder +10 (right), thrust 2 x 20 */
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_HEADING", false, NULL, 350, 1), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_SPEED", false, NULL, 1, 1), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_HEADING", false, NULL, 10, 1), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_SPEED", false, NULL, 2, 1), 1);
    r.n = 0;
    kelp_pid_marine_iterate(&m, 1.1, sink, &r);
    ck_assert(fabs(last(&r, "DESIRED_RUDDER") - 10) < 1e-9);
    ck_assert(last(&r, "DESIRED_THRUST") == 40);
    ck_assert(isnan(last(&r, "PID_MAX_SAT_HDG")) && isnan(last(&r, "PID_HDG_DEBUG"))); /* 24.8 never posts it */
    /* a big error: clipped to maxrudder 30; NAV_YAW gives the heading as -yaw in degrees */
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_YAW", false, NULL, 3.14159265358979 / 2, 1.2), 1);
    ck_assert(fabs(m.heading - 270) < 1e-6);
    r.n = 0;
    kelp_pid_marine_iterate(&m, 1.3, sink, &r);
    ck_assert(fabs(last(&r, "DESIRED_RUDDER") - 30) < 1e-9);
    /* desired speed 0: thrust 0 and rudder 0 */
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_SPEED", false, NULL, 0, 1.4), 1);
    r.n = 0;
    kelp_pid_marine_iterate(&m, 1.5, sink, &r);
    ck_assert(last(&r, "DESIRED_THRUST") == 0 && last(&r, "DESIRED_RUDDER") == 0);
    /* helm and nav quiet for more than 2 s: a PID_STALE for each of the four, rudder and thrust 0 */
    r.n = 0;
    kelp_pid_marine_iterate(&m, 4.0, sink, &r);
    ck_assert_int_eq(r.n, 6);
    ck_assert_str_eq(r.var[0], "PID_STALE");
    ck_assert(last(&r, "DESIRED_THRUST") == 0 && last(&r, "DESIRED_RUDDER") == 0);
    ck_assert_uint_eq(m.tardy_helm_n, 2);
    ck_assert_uint_eq(m.tardy_nav_n, 2);
    /* override again: PID_HAS_CONTROL false; the all-stop zeros came with the staleness, so
     * none again (MarinePID::postPengineResults posts them once per loss of control) */
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "MOOS_MANUAL_OVERIDE", true, "true", 0, 4.1), 1);
    ck_assert_int_lt(kelp_pid_marine_mail(&m, "MOOS_MANUAL_OVERRIDE", true, "perhaps", 0, 4.1), 0);
    r.n = 0;
    kelp_pid_marine_iterate(&m, 4.2, sink, &r);
    kelp_pid_marine_iterate(&m, 4.3, sink, &r);
    /* PID_HAS_CONTROL, then at each iteration the four stale inputs again (24.8 checks them
     * with or without control), no output */
    ck_assert_int_eq(r.n, 9);
    ck_assert_str_eq(r.var[0], "PID_HAS_CONTROL");
    ck_assert(r.v[0] == 0);
    for (int i = 1; i < 9; i++)
        ck_assert_str_eq(r.var[i], "PID_STALE");
}
END_TEST

/* heading_debug / speed_debug (PIDEngine's): the want/current/difference lines every
 * iteration with thrust, and a saturated loop's steps as ScalarPID writes them */
START_TEST(marine_pid_debug_postings)
{
    kelp_pid_marine_cfg c;
    kelp_pid_marine_cfg_default(&c);
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "yaw_pid_kp", "0.5", &why), 1);
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "MAXRUDDER", "30", &why), 1);
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "speed_factor", "20", &why), 1);
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "heading_debug", "True", &why), 1);
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "SPEED_DEBUG", " TRUE ", &why), 1);
    ck_assert_int_eq(kelp_pid_marine_cfg_set(&c, "depth_debug", "yes", &why), 1); /* only "true" counts */
    ck_assert(c.debug[0] && c.debug[1] && !c.debug[2]);
    c.active_start = true;
    kelp_pid_marine m;
    rec r = { 0 };
    ck_assert_int_eq(kelp_pid_marine_init(&m, &c, 0), 0);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_HEADING", false, NULL, 350, 1), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_SPEED", false, NULL, 1, 1), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_HEADING", false, NULL, 10, 1), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_SPEED", false, NULL, 2, 1), 1);
    kelp_pid_marine_iterate(&m, 1.1, sink, &r);
    ck_assert_str_eq(last_s(&r, "PID_SPD_DEBUG"),
                     "PID_SPEED:  (Want):2.00000 (Curr):1.00000 (Diff):1.00000 (Fctr):20.00000 THRUST:40.00000");
    ck_assert_str_eq(last_s(&r, "PID_HDG_DEBUG"),
                     "PID_COURSE:  (Want):10.00000 (Curr):350.00000 (Diff):-20.00000 RUDDER:10.00000");
    ck_assert(last_s(&r, "PID_MAX_SAT_HDG_DEBUG") == NULL); /* 10 is inside maxrudder 30 */
    /* the engine's postings follow the outputs */
    ck_assert_str_eq(r.var[r.n - 2], "PID_SPD_DEBUG");
    /* heading 270: error -100, 0.5 x -100 = -50, the loop's limit is maxrudder (30): saturated */
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_HEADING", false, NULL, 270, 1.2), 1);
    r.n = 0;
    kelp_pid_marine_iterate(&m, 1.3, sink, &r);
    ck_assert_str_eq(last_s(&r, "PID_MAX_SAT_HDG_DEBUG"),
                     "dfeIn=-100.00000, dfErrorTime=1.30000, m_dfDT=0.20000, dfDiffNow=-400.00000, DiffHistSize=1, "
                     "mdfeDiff(1)=-400.00000, mdfeDiff(2)=-400.00000, m_dfOut(1)-50, m_dfOut(1)-30");
    ck_assert_str_eq(last_s(&r, "PID_HDG_DEBUG"),
                     "PID_COURSE:  (Want):10.00000 (Curr):270.00000 (Diff):-100.00000 RUDDER:30.00000");
    ck_assert(last(&r, "DESIRED_RUDDER") == 30);
    /* thrust 0: no heading line (the loop does not run) */
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_SPEED", false, NULL, 0, 1.4), 1);
    r.n = 0;
    kelp_pid_marine_iterate(&m, 1.5, sink, &r);
    ck_assert(last_s(&r, "PID_HDG_DEBUG") == NULL && last_s(&r, "PID_SPD_DEBUG") != NULL);
    /* the integral's steps: ki > 0 and its limit */
    kelp_pid p;
    double out;
    char t[KELP_PID_DEBUG_MAX];
    kelp_pid_init(&p, 1, 0, 0.5, 0.25, 100);
    ck_assert_int_eq(kelp_pid_run(&p, 2, 10, &out), 0);
    ck_assert_int_gt(kelp_pid_debug_text(&p, t, sizeof t), 0);
    ck_assert_str_eq(t, "dfeIn=2.00000, dfErrorTime=10.00000, m_dfKi0.50000, m_dfeSum(1)0.00000, "
                        "m_dfIntegralLimit0.25000, m_dfOut(1)2");
    ck_assert_int_eq(kelp_pid_run(&p, 2, 10.5, &out), 0);
    ck_assert_int_gt(kelp_pid_debug_text(&p, t, sizeof t), 0);
    ck_assert_str_eq(t, "dfeIn=2.00000, dfErrorTime=10.50000, m_dfDT=0.50000, dfDiffNow=0.00000, DiffHistSize=1, "
                        "mdfeDiff(1)=0.00000, mdfeDiff(2)=0.00000, m_dfKi0.50000, m_dfeSum(1)0.50000, "
                        "m_dfIntegralLimit0.25000, m_dfeSum(2)0.25000, m_dfOut(1)2.25");
    ck_assert_int_eq(kelp_pid_run(&p, 2, 10.5, &out), 0); /* dt 0: stops after the time step */
    ck_assert_int_gt(kelp_pid_debug_text(&p, t, sizeof t), 0);
    ck_assert_str_eq(t, "dfeIn=2.00000, dfErrorTime=10.50000, m_dfDT=0.00000");
}
END_TEST

START_TEST(marine_pid_speed_and_depth_loops)
{
    kelp_pid_marine_cfg c;
    kelp_pid_marine_cfg_default(&c);
    c.active_start = true;
    c.speed[0] = 10; /* speed PID: thrust grows by 10 per m/s of error each run */
    c.depth_control = true;
    c.z_to_pitch[0] = 0.1;
    c.pitch[0] = 1;
    snprintf(c.suffix, sizeof c.suffix, "_PID");
    kelp_pid_marine m;
    rec r = { 0 };
    ck_assert_int_eq(kelp_pid_marine_init(&m, &c, 0), 0);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_SPEED", false, NULL, 2, 0), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_HEADING", false, NULL, 0, 0), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_DEPTH", false, NULL, 10, 0), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_SPEED", false, NULL, 1, 0), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_DEPTH", false, NULL, 0, 0), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_HEADING", false, NULL, 0, 0), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_PITCH", false, NULL, 0, 0), 1);
    kelp_pid_marine_iterate(&m, 0.5, sink, &r);
    kelp_pid_marine_iterate(&m, 1.0, sink, &r);
    ck_assert(last(&r, "DESIRED_THRUST_PID") == 20); /* 10 + 10: incremental on the last thrust */
    /* 10 m too shallow: pitch wanted -1 rad, clipped to -15 degrees; elevator +15 deg -> 13 */
    ck_assert(fabs(last(&r, "DESIRED_ELEVATOR_PID") - 13) < 1e-9);
    ck_assert(isnan(last(&r, "PID_MAX_SAT_DEP")) && isnan(last(&r, "PID_MAX_SAT_DEP_DEBUG"))); /* no depth_debug */
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
    /* no acceleration limit: 2 m/s at once; one step per call (uSimMarineV22 propagates once
     * per iteration): moved at the mean of 0 and 2 m/s for 1 s, and that mean, 1 m/s, is the
     * vehicle's speed after the step */
    ck_assert(fabs(sim.s.speed - 1) < 1e-9 && fabs(sim.s.y - 1) < 1e-9);
    /* full rudder: speed drops by turn_spd_loss to 1 m/s; the turn rate at 1 m/s is 70 x 1/5
     * percent: 100 x 0.14 x (40/50) = 11.2 deg/s */
    ck_assert_int_eq(kelp_sim_set_rudder(&sim, 100), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 2), 0);
    ck_assert(fabs(sim.s.speed - 1) < 1e-9);
    ck_assert(fabs(sim.s.heading - 11.2) < 1e-6);
    /* no way on: the rudder does nothing; positive buoyancy rises */
    sim.p.buoyancy_rate = 0.1;
    sim.s.depth = 5;
    ck_assert_int_eq(kelp_sim_set_thrust(&sim, 0), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 3), 0);
    ck_assert(fabs(sim.s.speed - 0.5) < 1e-9); /* (1 + 0) / 2: the mean halves each step */
    double h = sim.s.heading;
    ck_assert(fabs(h - 11.2) < 1e-6);          /* the new speed is 0: no turn */
    ck_assert_int_eq(kelp_sim_step(&sim, 4), 0);
    ck_assert(sim.s.heading == h);
    ck_assert(fabs(sim.s.speed - 0.25) < 1e-9);
    ck_assert(fabs(sim.s.depth - 4.8) < 1e-6);
    /* elevator dives with way on, limited by max_depth_rate x sqrt(speed share) */
    sim.p.buoyancy_rate = 0;
    sim.p.max_depth_rate = 0.5;
    sim.p.max_depth_rate_speed = 4;
    ck_assert_int_eq(kelp_sim_set_rudder(&sim, 0), 0);
    ck_assert_int_eq(kelp_sim_set_thrust(&sim, 20), 0); /* 1 m/s: sqrt(1/4) = 0.5 */
    ck_assert_int_eq(kelp_sim_set_elevator(&sim, 100), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 5), 0);
    ck_assert(fabs(sim.s.depth - (4.8 + 0.25)) < 1e-6); /* at the new speed, 1 m/s */
    ck_assert(fabs(sim.s.speed - 0.625) < 1e-9);
    ck_assert(sim.pitch < 0); /* nose down */
    /* over ground: a drift adds to the track */
    sim.p.drift_x = 1;
    ck_assert_int_eq(kelp_sim_set_elevator(&sim, 0), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 6), 0);
    ck_assert(sim.sog > 1.0);
    /* acceleration limits apply in this model too */
    sim.p.act_max_accel = 0.1;
    ck_assert_int_eq(kelp_sim_set_thrust(&sim, 100), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 7), 0);
    /* from (0.625 + 1) / 2 = 0.8125 (the drift's step) up 0.1 to 0.9125: their mean */
    ck_assert(fabs(sim.s.speed - 0.8625) < 1e-9);
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

/* uSimMarineV22's turn model (SimEngine::propagateSpeed/propagateHeading, TurnSpeedMap), by
 * hand: speed = thrust/20 x (1 - |rudder|/100 x 0.85); rate% = 70 x speed/5 (full from 5 m/s);
 * deg/s = rudder x rate%/100 x thrust/50. Each case starts at its in-turn speed. */
static const struct {
    double thrust, rudder, null_speed, null_rate, speed, degps;
} v22_turns[] = {
    { 40, 10, 0, 0, 1.83, 2.0496 },       /* 2 m/s x 0.915; 25.62%; 10 x .2562 x .8 */
    { 40, -30, 0, 0, 1.49, -5.0064 },     /* 2 x .745; 20.86%; -30 x .2086 x .8 */
    { 100, 50, 0, 0, 2.875, 40.25 },      /* 5 x .575; 40.25%; 50 x .4025 x 2 */
    { 60, 20, 0, 0, 2.49, 8.3664 },       /* 3 x .83; 34.86%; 20 x .3486 x 1.2 */
    { 20, 100, 0, 0, 0.15, 0.84 },        /* 1 x .15; 2.1%; 100 x .021 x .4 */
    { 40, 10, 1, 20, 1.83, 2.43 },        /* null 1 m/s at 20%: 20 + .83/4 x 50 = 30.375% */
    { 40, 10, 2, 20, 1.83, 1.6 },         /* below the null speed: 20%; 10 x .2 x .8 */
};

START_TEST(sim_v22_turn_rate)
{
    kelp_sim_params p;
    kelp_sim_params_default(&p);
    ck_assert(p.act_max_accel == 0 && p.max_decel == 0.5 && p.act_turn_rate == 70 && p.turn_spd_loss == 0.85);
    p.control = KELP_SIM_ACTUATED;
    p.tsm_null_speed = v22_turns[_i].null_speed;
    p.tsm_null_rate = v22_turns[_i].null_rate;
    kelp_sim_state st = { 0, 0, 90, v22_turns[_i].speed, 0 };
    kelp_sim sim;
    ck_assert_int_eq(kelp_sim_init(&sim, &p, &st, 100), 0);
    ck_assert_int_eq(kelp_sim_set_thrust(&sim, v22_turns[_i].thrust), 0);
    ck_assert_int_eq(kelp_sim_set_rudder(&sim, v22_turns[_i].rudder), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 102), 0);
    ck_assert_double_eq_tol(sim.s.speed, v22_turns[_i].speed, 1e-9);
    ck_assert_double_eq_tol(kelp_sim_angle180(sim.s.heading - 90), 2 * v22_turns[_i].degps, 1e-6);
}
END_TEST

/* speed loss in a turn, V22's limits: no acceleration limit, deceleration 0.5 m/s^2; the
 * turn-speed map keys; the thrust map from (0, 0) */
START_TEST(sim_v22_speed)
{
    kelp_sim_params p;
    kelp_sim_params_default(&p);
    kelp_diag why = { 0 };
    kelp_sim_state st = { 0, 0, 0, 2, 0 };
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "turn_spd_map_null_speed", "0.5", &why), 1);
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "TURN_SPD_MAP_NULL_RATE", "10", &why), 1);
    ck_assert_int_lt(kelp_sim_config_set(&p, &st, "TURN_SPD_MAP_NULL_RATE", "101", &why), 0);
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "TURN_SPD_MAP_FULL_SPEED", "1", &why), 1);
    ck_assert(p.tsm_null_speed == 0.5 && p.tsm_null_rate == 10);
    /* full speed stays 5 m/s whatever the key says: at 2.75 m/s halfway from 10% to 70% */
    ck_assert_double_eq_tol(kelp_sim_turn_rate_at(&p, 2.75), 40, 1e-9);
    ck_assert_double_eq_tol(kelp_sim_turn_rate_at(&p, 0.4), 10, 1e-9);
    ck_assert_double_eq_tol(kelp_sim_turn_rate_at(&p, 7), 70, 1e-9);
    /* a map without 0:0 interpolates from (0, 0); flat after its last point */
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "thrust_map", "50:2, 80:3", &why), 1);
    ck_assert_double_eq_tol(kelp_sim_thrust_speed(&p, 25), 1, 1e-12);
    ck_assert_double_eq_tol(kelp_sim_thrust_speed(&p, 65), 2.5, 1e-12);
    ck_assert_double_eq_tol(kelp_sim_thrust_speed(&p, 95), 3, 1e-12);
    ck_assert(kelp_sim_thrust_speed(&p, 0) == 0);
    p.nmap = 0;
    p.control = KELP_SIM_ACTUATED;
    kelp_sim sim;
    ck_assert_int_eq(kelp_sim_init(&sim, &p, &st, 0), 0);
    ck_assert_int_eq(kelp_sim_set_thrust(&sim, 40), 0);
    ck_assert_int_eq(kelp_sim_set_rudder(&sim, 100), 0);
    /* target 2 x 0.15 = 0.3 m/s; slowing at 0.5 m/s^2: 1.5 m/s after 1 s; the speed is the
     * step's mean, 1.75 */
    ck_assert_int_eq(kelp_sim_step(&sim, 1), 0);
    ck_assert_double_eq_tol(sim.s.speed, 1.75, 1e-9);
    /* rudder back to 0: no acceleration limit, 2 m/s at once */
    ck_assert_int_eq(kelp_sim_set_rudder(&sim, 0), 0);
    ck_assert_int_eq(kelp_sim_step(&sim, 1.05), 0);
    ck_assert_double_eq_tol(sim.s.speed, 1.875, 1e-9); /* (1.75 + 2) / 2 */
    /* MAX_ACCELERATION sets the limit of both models */
    ck_assert_int_eq(kelp_sim_config_set(&p, &st, "MAX_ACCELERATION", "0.2", &why), 1);
    ck_assert(p.act_max_accel == 0.2 && p.max_accel == 0.2);
}
END_TEST

typedef struct srec {
    char text[8][96];
    int n;
} srec;

static void ssink(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    srec *r = ctx;
    (void)dval;
    if (is_string && r->n < 8) snprintf(r->text[r->n++], sizeof r->text[0], "%s=%s", var, sval);
}

/* pMarinePIDV22's first command after the helm takes over (PIDEngine::setDesiredValues runs
 * the heading loop only with thrust, ScalarPID::Run has no derivative on its first run): the
 * heading error of the helm's first DESIRED_HEADING gives kp x error, not a derivative kick */
START_TEST(marine_pid_first_command)
{
    kelp_pid_marine_cfg c;
    kelp_pid_marine_cfg_default(&c);
    c.active_start = true;
    c.yaw[0] = 0.5;
    c.yaw[1] = 10;
    c.speed_factor = 20;
    kelp_pid_marine m;
    rec r = { 0 };
    ck_assert_int_eq(kelp_pid_marine_init(&m, &c, 0), 0);
    /* parked: desired speed 0, the vehicle's heading wanders */
    for (int i = 0; i <= 10; i++) {
        double t = i * 0.1;
        ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_SPEED", false, NULL, 0, t), 1);
        ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_HEADING", false, NULL, 0, t), 1);
        ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_HEADING", false, NULL, i * 2.0, t), 1);
        ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_SPEED", false, NULL, 0, t), 1);
        kelp_pid_marine_iterate(&m, t, sink, &r);
        ck_assert(last(&r, "DESIRED_RUDDER") == 0 && last(&r, "DESIRED_THRUST") == 0);
    }
    /* DEPLOY: heading 20, desired 110 at 2 m/s: rudder 0.5 x 90 = 45, thrust 40 */
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_SPEED", false, NULL, 2, 1.1), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_HEADING", false, NULL, 110, 1.1), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_HEADING", false, NULL, 20, 1.1), 1);
    kelp_pid_marine_iterate(&m, 1.1, sink, &r);
    ck_assert_double_eq_tol(last(&r, "DESIRED_RUDDER"), 45, 1e-9);
    ck_assert(last(&r, "DESIRED_THRUST") == 40);
    /* the next run has a derivative: error -80, slope +100/s: 0.5 x -80 + 10 x 100, rudder clipped to -100 */
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_HEADING", false, NULL, 30, 1.2), 1);
    kelp_pid_marine_iterate(&m, 1.2, sink, &r);
    ck_assert_double_eq_tol(last(&r, "DESIRED_RUDDER"), -100, 1e-9);
}
END_TEST

/* PID_STALE's text (PIDEngine::checkForStaleness): the input and its age to 3 decimals */
START_TEST(marine_pid_stale_text)
{
    kelp_pid_marine_cfg c;
    kelp_pid_marine_cfg_default(&c);
    c.active_start = true;
    kelp_pid_marine m;
    ck_assert_int_eq(kelp_pid_marine_init(&m, &c, 0), 0);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_SPEED", false, NULL, 1, 1), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_HEADING", false, NULL, 0, 0.5), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_HEADING", false, NULL, 0, 3), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_SPEED", false, NULL, 0, 3), 1);
    srec r = { 0 };
    kelp_pid_marine_iterate(&m, 3.125, ssink, &r);
    ck_assert_int_eq(r.n, 2);
    ck_assert_str_eq(r.text[0], "PID_STALE=Stale DesHdg:2.625");
    ck_assert_str_eq(r.text[1], "PID_STALE=Stale DesSpd:2.125");
}
END_TEST

/* without control (before DEPLOY, MOOS_MANUAL_OVERRIDE unset) PIDEngine::setDesiredValues still
 * checks its inputs once each has come: 24.8's s1_alpha run posts "Stale DesSpd:2.936" 5 s
 * before its DEPLOY; the outputs stay the one all-stop */
START_TEST(marine_pid_stale_without_control)
{
    kelp_pid_marine_cfg c;
    kelp_pid_marine_cfg_default(&c);
    kelp_pid_marine m;
    ck_assert_int_eq(kelp_pid_marine_init(&m, &c, 0), 0);
    srec r = { 0 };
    kelp_pid_marine_iterate(&m, 0.5, ssink, &r); /* nothing yet: the all-stop zeros only */
    unsigned zeros = r.n;
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_SPEED", false, NULL, 0, 1), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_HEADING", false, NULL, 0, 1), 1);
    kelp_pid_marine_iterate(&m, 3.5, ssink, &r); /* the nav has not come: waiting, no staleness */
    ck_assert_uint_eq(r.n, zeros);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_HEADING", false, NULL, 0, 3.5), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_SPEED", false, NULL, 0, 3.5), 1);
    kelp_pid_marine_iterate(&m, 3.75, ssink, &r);
    ck_assert_uint_eq(r.n, zeros + 2);
    ck_assert_str_eq(r.text[zeros], "PID_STALE=Stale DesHdg:2.75");
    ck_assert_str_eq(r.text[zeros + 1], "PID_STALE=Stale DesSpd:2.75");
}
END_TEST

/* a stale helm takes control away (PIDEngine::hasControl): pMarinePIDV22 posts the zeros
 * once (MarinePID::postPengineResults), nothing more while stale, its outputs again when the
 * helm is back */
START_TEST(marine_pid_stale_allstop)
{
    kelp_pid_marine_cfg c;
    kelp_pid_marine_cfg_default(&c);
    c.active_start = true;
    c.speed_factor = 20;
    c.yaw[0] = 1;
    kelp_pid_marine m;
    ck_assert_int_eq(kelp_pid_marine_init(&m, &c, 0), 0);
    rec r = { 0 };
    for (int i = 0; i <= 40; i++) {
        double t = i * 0.25;
        if (t <= 1 || t >= 8) { /* the helm from 0 to 1 s and from 8 s */
            ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_SPEED", false, NULL, 2, t), 1);
            ck_assert_int_eq(kelp_pid_marine_mail(&m, "DESIRED_HEADING", false, NULL, 10, t), 1);
        }
        ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_HEADING", false, NULL, 0, t), 1);
        ck_assert_int_eq(kelp_pid_marine_mail(&m, "NAV_SPEED", false, NULL, 2, t), 1);
        r.n = 0;
        kelp_pid_marine_iterate(&m, t, sink, &r);
        unsigned posted = 0;
        for (int k = 0; k < r.n; k++)
            posted += !strncmp(r.var[k], "DESIRED_", 8);
        if (t <= 3) /* fresh (up to 2 s old) */
            ck_assert(posted == 2 && last(&r, "DESIRED_THRUST") == 40 && last(&r, "DESIRED_RUDDER") == 10);
        else if (t == 3.25) /* stale: the zeros once */
            ck_assert(posted == 2 && last(&r, "DESIRED_THRUST") == 0 && last(&r, "DESIRED_RUDDER") == 0);
        else if (t < 8)
            ck_assert_uint_eq(posted, 0);
        else
            ck_assert(posted == 2 && last(&r, "DESIRED_THRUST") == 40);
    }
}
END_TEST

/* uSimMarineV22 posts SIMULATION_MODE (with its PID engine's depth control, on by default)
 * and USM_DRIFT_SUMMARY at its first iteration and when drift arrives (USM_MOOSApp) */
START_TEST(usim_v22_postings)
{
    static kelp_usim u;
    kelp_usim_defaults(&u, NULL, NULL);
    ck_assert_int_eq(kelp_usim_start(&u, NULL, 10), 0);
    srec r = { 0 };
    ck_assert_int_eq(kelp_usim_iterate(&u, 10.25, ssink, &r), 0);
    ck_assert_int_eq(r.n, 1);
    ck_assert_str_eq(r.text[0], "USM_DRIFT_SUMMARY=ang=0, mag=0, xmag=0, ymag=0");
    r.n = 0;
    ck_assert_int_eq(kelp_usim_iterate(&u, 10.5, ssink, &r), 0);
    ck_assert_int_eq(r.n, 1);
    ck_assert_str_eq(r.text[0], "SIMULATION_MODE=TRUE");
    ck_assert_int_eq(kelp_usim_mail(&u, "DRIFT_X", false, NULL, 0.5, 10.6), 1);
    r.n = 0;
    ck_assert_int_eq(kelp_usim_iterate(&u, 10.75, ssink, &r), 0);
    ck_assert_int_eq(r.n, 1);
    ck_assert_str_eq(r.text[0], "USM_DRIFT_SUMMARY=ang=90, mag=0.5, xmag=0.5, ymag=0");
}
END_TEST

typedef struct nrec {
    int n_nav;
    double speed;
} nrec;

static void navsink(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    nrec *r = ctx;
    (void)sval;
    if (!is_string && !strcmp(var, "NAV_X")) r->n_nav++;
    if (!is_string && !strcmp(var, "NAV_SPEED")) r->speed = dval;
}

/* USM_MOOSApp::postNodeRecordUpdate: the navigation every 2nd iteration (m_nav_modulo), from
 * the second; NAV_SPEED snapped to 0.01 and at most max_speed (5 by default) */
START_TEST(usim_v22_nav_modulo)
{
    static kelp_usim u;
    kelp_usim_defaults(&u, NULL, NULL);
    u.start.speed = 1.234;
    ck_assert_int_eq(kelp_usim_start(&u, NULL, 10), 0);
    nrec r = { 0, -1 };
    for (int i = 1; i <= 4; i++) {
        ck_assert_int_eq(kelp_usim_iterate(&u, 10 + 0.25 * i, navsink, &r), 0);
        ck_assert_int_eq(r.n_nav, i / 2);
    }
    ck_assert_double_eq_tol(r.speed, 1.23, 1e-12);
    u.sim.s.speed = 7.5;
    ck_assert_int_eq(kelp_usim_iterate(&u, 11.25, navsink, &r), 0);
    ck_assert_int_eq(kelp_usim_iterate(&u, 11.5, navsink, &r), 0);
    ck_assert_double_eq_tol(r.speed, 5, 1e-12);
}
END_TEST

Suite *kelp_pid_suite(void)
{
    Suite *s = suite_create("pid");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, scalar_pid_rules);
    tcase_add_test(tc, marine_pid_iteration);
    tcase_add_test(tc, marine_pid_speed_and_depth_loops);
    tcase_add_test(tc, marine_pid_debug_postings);
    tcase_add_test(tc, sim_rudder_thrust_model);
    tcase_add_loop_test(tc, sim_v22_turn_rate, 0, (int)(sizeof v22_turns / sizeof v22_turns[0]));
    tcase_add_test(tc, sim_v22_speed);
    tcase_add_test(tc, usim_v22_postings);
    tcase_add_test(tc, usim_v22_nav_modulo);
    tcase_add_test(tc, marine_pid_first_command);
    tcase_add_test(tc, marine_pid_stale_text);
    tcase_add_test(tc, marine_pid_stale_without_control);
    tcase_add_test(tc, marine_pid_stale_allstop);
    suite_add_tcase(s, tc);
    return s;
}
