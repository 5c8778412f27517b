/* The simulator's and the marine PID's configuration keys (MOOS-IvP names, any case). */
#include <math.h>
#include <string.h>
#include <kelp/mission.h>
#include <kelp/pid.h>
#include <kelp/sim.h>

static bool key_is(const char *key, const char *name)
{
    return kelp_util_strieq_n(key, strlen(key), name);
}

static int number(const char *val, double lo, double hi, double *out, kelp_diag *d, const char *msg)
{
    double x;
    (void)msg; /* unused with KELP_NO_ERRMSG */
    if (kelp_util_parse_double(val, strlen(val), &x) < 0 || !isfinite(x) || x < lo || x > hi) {
        return kelp_fail(d, KELP_ERR_RANGE, msg);
    }
    *out = x;
    return 1;
}

static int boolean(const char *val, bool *out, kelp_diag *d)
{
    size_t n = strlen(val);
    if (kelp_util_strieq_n(val, n, "true") || kelp_util_strieq_n(val, n, "yes") || !strcmp(val, "1")) *out = true;
    else if (kelp_util_strieq_n(val, n, "false") || kelp_util_strieq_n(val, n, "no") || !strcmp(val, "0")) *out = false;
    else {
        return kelp_fail(d, KELP_ERR_PARSE, "must be true or false");
    }
    return 1;
}

int kelp_sim_config_set(kelp_sim_params *p, kelp_sim_state *st, const char *key, const char *val, kelp_diag *d)
{
    static const struct { const char *key; size_t off; double lo; } nums[] = {
        { "TURN_SPEED", offsetof(kelp_sim_params, turn_speed), 0 },
        { "MAX_DECELERATION", offsetof(kelp_sim_params, max_decel), 0 },
        { "MAX_DEPTH_RATE", offsetof(kelp_sim_params, max_depth_rate), 0 },
        { "MAX_DEPTH_RATE_SPEED", offsetof(kelp_sim_params, max_depth_rate_speed), 0 },
        { "MAX_SPEED", offsetof(kelp_sim_params, max_speed), 0 },
        { "SIM_STEP", offsetof(kelp_sim_params, step), 1e-4 },
        { "THRUST_FACTOR", offsetof(kelp_sim_params, thrust_factor), 0 },
        { "BUOYANCY_RATE", offsetof(kelp_sim_params, buoyancy_rate), -HUGE_VAL },
        { "DRIFT_X", offsetof(kelp_sim_params, drift_x), -HUGE_VAL },
        { "DRIFT_Y", offsetof(kelp_sim_params, drift_y), -HUGE_VAL },
        { "ROTATE_SPEED", offsetof(kelp_sim_params, rotate_speed), -HUGE_VAL },
    };
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++)
        if (key_is(key, nums[i].key))
            return number(val, nums[i].lo, HUGE_VAL, (double *)(void *)((char *)p + nums[i].off), d,
                          nums[i].lo > -HUGE_VAL ? "must be a number >= its minimum (see --example)" : "must be a number");
    double num;
    if (key_is(key, "TURN_RATE")) {
        /* deg/s in the direct model; a percent [0, 100] in the actuated one (MOOS-IvP) */
        int rc = number(val, 0, HUGE_VAL, &num, d, "must be a number >= 0");
        if (rc > 0) p->turn_rate = num, p->act_turn_rate = num > 100 ? 100 : num;
        return rc;
    }
    if (key_is(key, "MAX_ACCELERATION")) {
        int rc = number(val, 0, HUGE_VAL, &num, d, "must be a number >= 0");
        if (rc > 0) p->max_accel = p->act_max_accel = num;
        return rc;
    }
    static const struct { const char *key; size_t off; double lo, hi; } tsm[] = {
        { "TURN_SPD_MAP_NULL_SPEED", offsetof(kelp_sim_params, tsm_null_speed), 0, HUGE_VAL },
        { "TURN_SPD_MAP_FULL_SPEED", offsetof(kelp_sim_params, tsm_full_speed), 1e-9, HUGE_VAL },
        { "TURN_SPD_MAP_NULL_RATE", offsetof(kelp_sim_params, tsm_null_rate), 0, 100 },
        { "TURN_SPD_MAP_FULL_RATE", offsetof(kelp_sim_params, tsm_full_rate), 1e-9, 100 },
    };
    for (size_t i = 0; i < sizeof tsm / sizeof tsm[0]; i++)
        if (key_is(key, tsm[i].key))
            return number(val, tsm[i].lo, tsm[i].hi, (double *)(void *)((char *)p + tsm[i].off), d,
                          "out of range (speeds > 0 m/s, rates in [0,100])");
    if (key_is(key, "TURN_SPD_LOSS")) return number(val, 0, 1, &p->turn_spd_loss, d, "must be in [0, 1]");
    if (key_is(key, "THRUST_MAP")) {
        int rc = kelp_sim_parse_thrust_map(val, p);
        if (rc < 0) return kelp_fail(d, rc, "expected thrust:speed pairs, thrust ascending in [-100, 100] (at most 16)");
        return 1;
    }
    if (key_is(key, "DRIFT_VECTOR")) { /* "heading, magnitude" */
        const char *c = strchr(val, ',');
        double h, m;
        if (!c || kelp_util_parse_double(val, (size_t)(c - val), &h) < 0 || kelp_util_parse_double(c + 1, strlen(c + 1), &m) < 0 ||
            !isfinite(h) || !isfinite(m)) {
            return kelp_fail(d, KELP_ERR_PARSE, "expected heading,magnitude");
        }
        p->drift_x = m * sin(h * 3.14159265358979323846 / 180.0);
        p->drift_y = m * cos(h * 3.14159265358979323846 / 180.0);
        return 1;
    }
    if (key_is(key, "CONTROL")) {
        size_t n = strlen(val);
        if (kelp_util_strieq_n(val, n, "auto")) p->control = KELP_SIM_AUTO;
        else if (kelp_util_strieq_n(val, n, "direct")) p->control = KELP_SIM_DIRECT;
        else if (kelp_util_strieq_n(val, n, "actuated") || kelp_util_strieq_n(val, n, "rudder")) p->control = KELP_SIM_ACTUATED;
        else {
            return kelp_fail(d, KELP_ERR_PARSE, "must be auto, direct or actuated");
        }
        return 1;
    }
    if (st && key_is(key, "START_POS")) {
        int rc = kelp_sim_parse_start(val, st);
        if (rc < 0) return kelp_fail(d, rc, "expected x,y[,heading[,speed[,depth]]] or x=..,y=..,heading=..,speed=..,depth=..");
        return 1;
    }
    static const char *const starts[] = { "START_X", "START_Y", "START_HEADING", "START_SPEED", "START_DEPTH" };
    for (int i = 0; st && i < 5; i++)
        if (key_is(key, starts[i])) {
            int rc = number(val, i >= 3 ? 0 : -HUGE_VAL, HUGE_VAL, &num, d, i >= 3 ? "must be a number >= 0" : "must be a number");
            if (rc < 0) return rc;
            double *f[5] = { &st->x, &st->y, &st->heading, &st->speed, &st->depth };
            *f[i] = i == 2 ? kelp_sim_angle360(num) : num;
            return 1;
        }
    return 0;
}

int kelp_pid_marine_cfg_set(kelp_pid_marine_cfg *c, const char *key, const char *val, kelp_diag *d)
{
    static const struct { const char *prefix; size_t off; } loops[] = {
        { "YAW_PID_", offsetof(kelp_pid_marine_cfg, yaw) },
        { "SPEED_PID_", offsetof(kelp_pid_marine_cfg, speed) },
        { "Z_TO_PITCH_PID_", offsetof(kelp_pid_marine_cfg, z_to_pitch) },
        { "PITCH_PID_", offsetof(kelp_pid_marine_cfg, pitch) },
    };
    static const char *const gains[] = { "KP", "KD", "KI", "INTEGRAL_LIMIT", "KI_LIMIT" };
    size_t kl = strlen(key);
    for (size_t i = 0; i < 4; i++) {
        size_t pl = strlen(loops[i].prefix);
        if (kl <= pl || !kelp_util_strieq_n(key, pl, loops[i].prefix)) continue;
        for (int g = 0; g < 5; g++)
            if (key_is(key + pl, gains[g])) {
                double *v = (double *)(void *)((char *)c + loops[i].off);
                return number(val, -HUGE_VAL, HUGE_VAL, &v[g < 4 ? g : 3], d, "must be a number");
            }
    }
    static const struct { const char *key; size_t off; double hi; } nums[] = {
        { "MAXRUDDER", offsetof(kelp_pid_marine_cfg, max_rudder), HUGE_VAL },
        { "MAXTHRUST", offsetof(kelp_pid_marine_cfg, max_thrust), HUGE_VAL },
        { "MAXPITCH", offsetof(kelp_pid_marine_cfg, max_pitch_deg), 90 },
        { "MAXELEVATOR", offsetof(kelp_pid_marine_cfg, max_elevator), HUGE_VAL },
        { "SPEED_FACTOR", offsetof(kelp_pid_marine_cfg, speed_factor), 100 },
        { "TARDY_HELM_THRESHOLD", offsetof(kelp_pid_marine_cfg, tardy_helm), HUGE_VAL },
        { "TARDY_NAV_THRESHOLD", offsetof(kelp_pid_marine_cfg, tardy_nav), HUGE_VAL },
        { "SIM_INSTABILITY", offsetof(kelp_pid_marine_cfg, sim_instability), 100 },
    };
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++)
        if (key_is(key, nums[i].key))
            return number(val, 0, nums[i].hi, (double *)(void *)((char *)c + nums[i].off), d,
                          "must be a number >= 0 (within its range, see --example)");
    if (key_is(key, "DEPTH_CONTROL")) return boolean(val, &c->depth_control, d);
    if (key_is(key, "ACTIVE_START")) return boolean(val, &c->active_start, d);
    if (key_is(key, "IGNORE_NAV_YAW")) return boolean(val, &c->ignore_nav_yaw, d);
    static const char *const dbg[3] = { "HEADING_DEBUG", "SPEED_DEBUG", "DEPTH_DEBUG" };
    for (int i = 0; i < 3; i++)
        if (key_is(key, dbg[i])) {
            size_t n = strlen(val);
            kelp_util_trim(&val, &n);
            if (kelp_util_strieq_n(val, n, "true")) c->debug[i] = true;
            return 1;
        }
    if (key_is(key, "OUTPUT_SUFFIX")) {
        size_t n = strlen(val);
        if (n >= sizeof c->suffix || strpbrk(val, " ,=")) {
            return kelp_fail(d, KELP_ERR_RANGE, "must be at most 15 characters, no spaces");
        }
        memcpy(c->suffix, val, n + 1);
        return 1;
    }
    return 0;
}
