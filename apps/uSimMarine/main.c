/* uSimMarine: a single-vehicle simulator (the MOOS-IvP uSimMarine / uSimMarineV22 role). Two models
 * (include/kelp/sim.h): DESIRED_HEADING/SPEED/DEPTH followed within rate limits, or rudder/thrust/
 * elevator as MOOS-IvP's (from pMarinePID, or its loops embedded); the logic is kelp_usim in the
 * core, this file reads the block and wires it to the bus. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/geo.h>
#include <kelp/pid.h>
#include <kelp/sim.h>

typedef struct usim {
    kelp_app *app;
    kelp_usim u;
    kelp_pid_marine pid;
    kelp_pid_marine_cfg pid_cfg;
    bool pass_start;
} usim;

/* one block key: START_POS in the first pass, the rest in the second (START_X etc. override) */
static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    usim *a = ctx;
    bool is_pos = kelp_util_strieq_n(key, strlen(key), "START_POS");
    if (a->pass_start != is_pos) return is_pos ? 1 : 0;
    int rc = kelp_usim_config(&a->u, key, val, d);
    if (rc != 0) return rc;
    /* MOOS-IvP 24.8 keys for what kelp does not simulate (sailing, a second state, reverse
     * thrust): accepted so a 24.8 block loads, and reported as events */
    static const char *const accepted[] = { "WIND_CONDITIONS", "POLAR_PLOT", "DUAL_STATE", "THRUST_REFLECT", "APP_LOGGING" };
    for (size_t i = 0; i < sizeof accepted / sizeof accepted[0]; i++)
        if (kelp_util_strieq_n(key, strlen(key), accepted[i])) {
            kelp_app_event(a->app, "%s accepted, not simulated", accepted[i]);
            return 1;
        }
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    usim *a = st;
    a->app = app;
    kelp_usim_defaults(&a->u, &a->pid, &a->pid_cfg);
    for (int pass = 0; pass < 2; pass++) {
        a->pass_start = pass == 0;
        int rc = kelp_app_param_foreach(app, param, a);
        if (rc < 0) return rc;
    }
    double lat0, lon0;
    kelp_geo geo;
    bool have_geo = false;
    int x = kelp_app_global_double(app, "LatOrigin", &lat0), y = kelp_app_global_double(app, "LongOrigin", &lon0);
    if (x == 1 && y == 1) {
        if (kelp_geo_init(&geo, lat0, lon0) < 0)
            return kelp_app_config_error(app, NULL, "LatOrigin/LongOrigin %g, %g out of range", lat0, lon0);
        have_geo = true;
    } else if (x < 0 || y < 0) {
        return kelp_app_config_error(app, NULL, "LatOrigin/LongOrigin must be numbers");
    } else {
        kelp_app_config_warning(app, "no LatOrigin/LongOrigin globals: %s_LAT and %s_LONG are not published",
                                a->u.prefix, a->u.prefix);
    }
    if (kelp_usim_start(&a->u, have_geo ? &geo : NULL, kelp_app_time(app)) < 0)
        return kelp_app_config_error(app, NULL, "bad start pose, limits or embedded PID settings");
    const kelp_sim_state *s = &a->u.start;
    kelp_app_event(app, "start x=%.2f y=%.2f heading=%.1f speed=%.2f depth=%.2f%s", s->x, s->y, a->u.sim.s.heading,
                   s->speed, s->depth, a->u.embedded_pid ? " (embedded PID)" : "");
    const char *v;
    for (unsigned i = 0; (v = kelp_usim_subscription(i)) != NULL; i++)
        if (kelp_app_register(app, v, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", v);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    usim *a = st;
    if (v->kind == KELP_VAR_BINARY) return;
    unsigned long resets = a->u.resets;
    int rc = kelp_usim_mail(&a->u, v->name, v->kind == KELP_VAR_STRING, v->sval, v->dval, kelp_app_time(app));
    if (rc < 0) kelp_app_run_warning(app, "%s: not a usable value ('%.40s'); ignored", v->name, v->kind == KELP_VAR_STRING ? v->sval : "");
    if (a->u.resets != resets)
        kelp_app_event(app, "reset to x=%.2f y=%.2f heading=%.1f", a->u.sim.s.x, a->u.sim.s.y, a->u.sim.s.heading);
}

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    usim *a = ctx;
    int rc = is_string ? kelp_app_notify_string(a->app, var, sval) : kelp_app_notify_double(a->app, var, dval);
    if (rc < 0) kelp_app_run_warning(a->app, "cannot publish %s", var);
}

static int iterate(kelp_app *app, void *st, double now)
{
    usim *a = st;
    int rc = kelp_usim_iterate(&a->u, now, publish, a);
    if (rc < 0) kelp_app_run_warning(app, "step to %.3f: %s", now, kelp_err_str(rc));
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    kelp_usim *u = &((usim *)st)->u;
    (void)app;
    const kelp_sim_state *s = &u->sim.s;
    fprintf(out, "  %-8s %10s %10s %9s %8s %8s\n", "", "x", "y", "heading", "speed", "depth");
    fprintf(out, "  %-8s %10.2f %10.2f %9.2f %8.2f %8.2f\n", "state", s->x, s->y, s->heading, s->speed, s->depth);
    fprintf(out, "  %-8s %10s %10s %9.2f %8.2f %8.2f\n", "desired", "", "", u->sim.des_heading, u->sim.des_speed,
            u->sim.des_depth);
    fprintf(out, "Limits: turn %g deg/s (full from %g m/s), accel %g m/s^2, decel %g m/s^2, depth rate %g m/s (0 = none)\n",
            u->sim.p.turn_rate, u->sim.p.turn_speed, u->sim.p.max_accel, u->sim.p.max_decel, u->sim.p.max_depth_rate);
    fprintf(out, "Odometer %.1f m; DESIRED_* mail: heading %lu, speed %lu, depth %lu, rudder %lu, thrust %lu, "
                 "elevator %lu; bad %lu; resets %lu\n",
            u->sim.odometer, u->mail[0], u->mail[1], u->mail[2], u->mail[3], u->mail[4], u->mail[5], u->bad_mail,
            u->resets);
    fprintf(out, "Model: %s%s%s; actuators rudder %.1f thrust %.1f elevator %.1f; pitch %.3f rad\n",
            u->sim.actuated ? "rudder/thrust" : "direct (DESIRED_HEADING/SPEED/DEPTH)",
            u->embedded_pid ? " with the embedded PID" : "", u->paused ? " (paused)" : "", u->sim.rudder,
            u->sim.thrust, u->sim.elevator, u->sim.pitch);
    if (u->have_geo) fprintf(out, "Datum: LatOrigin %.6f LongOrigin %.6f\n", u->geo.lat0, u->geo.lon0);
}

static const kelp_app_def def = {
    .name = "uSimMarine",
    .purpose = "Simulate one marine vehicle (DESIRED_HEADING/SPEED/DEPTH, or rudder/thrust/elevator); publish NAV_*.",
    .params = (const kelp_app_param_info[]){
        { "START_POS", "x=0, y=0, heading=0, speed=0, depth=0", "or x,y[,heading[,speed[,depth]]]", NULL },
        { "START_X", "0", "meters; overrides START_POS", NULL },
        { "START_Y", "0", "meters; overrides START_POS", NULL },
        { "START_HEADING", "0", "degrees; overrides START_POS", NULL },
        { "START_SPEED", "0", "m/s, >= 0; overrides START_POS", NULL },
        { "START_DEPTH", "0", "meters, >= 0; overrides START_POS", NULL },
        { "PREFIX", "NAV", "published variables are <PREFIX>_X, _Y, ... (\"NAV_\" too)", NULL },
        { "CONTROL", "auto", "auto: DESIRED_RUDDER/THRUST/ELEVATOR switch to the rudder/thrust model; direct; actuated",
          NULL },
        { "TURN_RATE", "20", "direct model: deg/s at full speed; rudder/thrust model: percent [0,100] (70)", NULL },
        { "TURN_SPEED", "0.5", "m/s: below it the direct model's turn rate scales with speed (0 = off)", NULL },
        { "MAX_ACCELERATION", "0", "m/s^2 (0 = no limit; default 0 in the rudder/thrust model, 0.5 in the direct one)",
          NULL },
        { "MAX_DECELERATION", "0.5", "m/s^2 (0 = no limit)", NULL },
        { "MAX_DEPTH_RATE", "0.5", "m/s (0 = no limit)", NULL },
        { "MAX_DEPTH_RATE_SPEED", "0", "m/s: depth rate scaled by speed/this (0 = off)", NULL },
        { "MAX_SPEED", "0", "m/s, clip on the desired speed (0 = none)", NULL },
        { "SIM_STEP", "0.05", "s, integration sub-step, >= 0.0001", NULL },
        { "THRUST_MAP", "0:0, 20:1, 40:2, 60:3, 80:5, 100:5", "thrust:speed pairs (rudder/thrust model)", NULL },
        { "THRUST_FACTOR", "20", "speed = thrust / this without a THRUST_MAP", NULL },
        { "TURN_SPD_LOSS", "0.85", "[0,1]: speed lost at full rudder", NULL },
        { "BUOYANCY_RATE", "0.025", "m/s the vehicle rises without way on", NULL },
        { "DRIFT_X", "0", "m/s east", NULL },
        { "DRIFT_Y", "0", "m/s north", NULL },
        { "DRIFT_VECTOR", "0,0", "heading, magnitude (m/s)", NULL },
        { "ROTATE_SPEED", "0", "deg/s", NULL },
        { "SIM_PAUSE", "false", "true: the vehicle stands still", NULL },
        { "POST_NAVPOS_SUMMARY", "false", "true: USM_NAVPOS_SUMMARY every iteration", NULL },
        { "POST_DES_RUDDER", "DESIRED_RUDDERX", "embedded PID: post its rudder here", NULL },
        { "POST_DES_THRUST", "DESIRED_THRUSTX", "embedded PID: post its thrust here", NULL },
        { "YAW_PID_KP", "0.4", "any YAW_PID_ key embeds pMarinePID's loops (all its keys apply, see pMarinePID)",
          NULL },
        { "SPEED_FACTOR", "20", "embedded PID: thrust = speed x this", NULL },
        { "YAW_PID_KD", "0.1", "embedded PID (as pMarinePID)", NULL },
        { "YAW_PID_KI", "0.0", "embedded PID (as pMarinePID)", NULL },
        { "YAW_PID_INTEGRAL_LIMIT", "0.07", "embedded PID (as pMarinePID)", NULL },
        { "YAW_PID_KI_LIMIT", "0.07", "embedded PID (as pMarinePID)", "YAW_PID_INTEGRAL_LIMIT" },
        { "SPEED_PID_KP", "1.0", "embedded PID (as pMarinePID)", NULL },
        { "SPEED_PID_KD", "0.0", "embedded PID (as pMarinePID)", NULL },
        { "SPEED_PID_KI", "0.0", "embedded PID (as pMarinePID)", NULL },
        { "SPEED_PID_INTEGRAL_LIMIT", "0.07", "embedded PID (as pMarinePID)", NULL },
        { "SPEED_PID_KI_LIMIT", "0.07", "embedded PID (as pMarinePID)", "SPEED_PID_INTEGRAL_LIMIT" },
        { "MAXRUDDER", "100", "embedded PID (as pMarinePID)", NULL },
        { "MAXTHRUST", "100", "embedded PID (as pMarinePID)", NULL },
        { "DEPTH_CONTROL", "false", "embedded PID (as pMarinePID)", NULL },
        { "Z_TO_PITCH_PID_KP", "0.12", "embedded PID (as pMarinePID)", NULL },
        { "Z_TO_PITCH_PID_KD", "1.0", "embedded PID (as pMarinePID)", NULL },
        { "Z_TO_PITCH_PID_KI", "0.004", "embedded PID (as pMarinePID)", NULL },
        { "Z_TO_PITCH_PID_INTEGRAL_LIMIT", "0.05", "embedded PID (as pMarinePID)", NULL },
        { "MAXPITCH", "15", "embedded PID (as pMarinePID)", NULL },
        { "PITCH_PID_KP", "0.5", "embedded PID (as pMarinePID)", NULL },
        { "PITCH_PID_KD", "1.0", "embedded PID (as pMarinePID)", NULL },
        { "PITCH_PID_KI", "0", "embedded PID (as pMarinePID)", NULL },
        { "PITCH_PID_INTEGRAL_LIMIT", "0", "embedded PID (as pMarinePID)", NULL },
        { "MAXELEVATOR", "13", "embedded PID (as pMarinePID)", NULL },
        { "TARDY_HELM_THRESHOLD", "2.0", "embedded PID (as pMarinePID)", NULL },
        { "TARDY_NAV_THRESHOLD", "2.0", "embedded PID (as pMarinePID)", NULL },
        { "SIM_INSTABILITY", "0", "embedded PID (as pMarinePID)", NULL },
        { "OUTPUT_SUFFIX", "_PID", "embedded PID (as pMarinePID)", NULL },
        { "IGNORE_NAV_YAW", "false", "embedded PID (as pMarinePID)", NULL },
        { "TURN_SPD_MAP_NULL_SPEED", "0", "m/s: at and below it the rudder/thrust model turns at the null rate", NULL },
        { "TURN_SPD_MAP_NULL_RATE", "0", "[0,100]: turn rate at the null speed (full: TURN_RATE from 5 m/s)", NULL },
        { "TURN_SPD_MAP_FULL_RATE", "100", "[0,100]: used only with TURN_RATE = 0 (as uSimMarineV22)", NULL },
        { "TURN_SPD_MAP_FULL_SPEED", "1", "accepted; uSimMarineV22 turns at the full rate from 5 m/s", NULL },
        { "POLAR_PLOT", "0,0: 90,80: 180,50", "accepted, not simulated", "WIND_CONDITIONS" },
        { "WIND_CONDITIONS", "spd=3.3, dir=180", "accepted, not simulated (sailing; also POLAR_PLOT)", NULL },
        { "DUAL_STATE", "false", "accepted, not simulated", NULL },
        { "THRUST_REFLECT", "false", "accepted, not simulated (no reverse)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "DESIRED_HEADING", "118.8", "degrees (direct model, or the embedded PID)" },
        { "DESIRED_SPEED", "2.0", "m/s" },
        { "DESIRED_DEPTH", "4.6", "meters" },
        { "DESIRED_RUDDER", "-22", "[-100,100] (rudder/thrust model, e.g. from pMarinePID)" },
        { "DESIRED_THRUST", "60", "[-100,100]" },
        { "DESIRED_ELEVATOR", "-1.2", "[-100,100]" },
        { "DRIFT_X", "0.2", "m/s; also DRIFT_Y, ROTATE_SPEED (deg/s), BUOYANCY_RATE" },
        { "USM_RESET", "x=10, y=-20, heading=90", "a START_POS value: jump to that pose" },
        { "USM_SIM_PAUSED", "true", NULL },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "NAV_X", "112.3", "every iteration (NAV = PREFIX)" },
        { "NAV_Y", "-99.1", NULL },
        { "NAV_HEADING", "118.8", NULL },
        { "NAV_SPEED", "2.0", NULL },
        { "NAV_DEPTH", "4.6", NULL },
        { "NAV_Z", "-4.6", "minus the depth" },
        { "NAV_YAW", "-2.07", "radians, minus the heading" },
        { "NAV_PITCH", "-0.02", "radians, nose up positive" },
        { "NAV_SPEED_OVER_GROUND", "2.09", "with drift" },
        { "NAV_HEADING_OVER_GROUND", "192", NULL },
        { "NAV_LAT", "43.824981", "with LatOrigin/LongOrigin" },
        { "NAV_LONG", "-70.329755", "with LatOrigin/LongOrigin" },
        { "TRUE_X", "112.3", "also TRUE_Y" },
        { "SIMULATION_MODE", "TRUE", "every iteration (not with DEPTH_CONTROL = false)" },
        { "USM_DRIFT_SUMMARY", "ang=90, mag=1.5, xmag=1.5, ymag=0", "first iteration and after drift mail" },
        { "USM_NAVPOS_SUMMARY", "x=68.932,y=-60.32,lat=43.824767,lon=-70.3295309", "with POST_NAVPOS_SUMMARY" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: LatOrigin, LongOrigin (for NAV_LAT/NAV_LONG).\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static usim u;
    return kelp_app_run(argc, argv, &def, &u);
}
