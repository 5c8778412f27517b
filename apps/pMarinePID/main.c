/* pMarinePID: heading, speed and depth PID loops from the helm's DESIRED_* to
 * DESIRED_RUDDER/THRUST/ELEVATOR (the MOOS-IvP pMarinePID / pMarinePIDV22 role). The logic is
 * the core engine kelp_pid_marine (include/kelp/pid.h); this file reads the block and wires
 * the engine to the bus. */
#include <stdio.h>
#include <string.h>
#include <kelp/edge/app.h>
#include <kelp/pid.h>

typedef struct mpid {
    kelp_app *app;
    kelp_pid_marine m;
    kelp_pid_marine_cfg cfg;
    unsigned long bad_mail;
} mpid;

static void sink(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    mpid *p = ctx;
    int rc = is_string ? kelp_app_notify_string(p->app, var, sval) : kelp_app_notify_double(p->app, var, dval);
    if (rc < 0) kelp_app_run_warning(p->app, "cannot publish %s", var);
}

/* every key of the block: the engine's, or one accepted for MOOS-IvP compatibility */
static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    mpid *p = ctx;
    int rc = kelp_pid_marine_cfg_set(&p->cfg, key, val, d);
    if (rc != 0) return rc;
    static const char *const accepted[] = { "VERBOSE", "MAX_SAT_HDG_DEBUG", "MAX_SAT_SPD_DEBUG", "MAX_SAT_DEP_DEBUG",
                                            "AppTick", "CommsTick" };
    for (size_t i = 0; i < sizeof accepted / sizeof accepted[0]; i++)
        if (kelp_util_strieq_n(key, strlen(key), accepted[i])) return 1;
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    mpid *p = st;
    p->app = app;
    kelp_pid_marine_cfg_default(&p->cfg);
    int rc = kelp_app_param_foreach(app, param, p);
    if (rc < 0) return rc;
    if (kelp_pid_marine_init(&p->m, &p->cfg, kelp_app_time(app)) < 0)
        return kelp_app_config_error(app, NULL, "limits and thresholds must be numbers >= 0");
    static const char *const subs[] = { "DESIRED_HEADING", "DESIRED_SPEED", "DESIRED_DEPTH",       "NAV_HEADING",
                                        "NAV_YAW",         "NAV_SPEED",     "NAV_DEPTH",           "NAV_PITCH",
                                        "SPEED_FACTOR",    "PID_VERBOSE",   "MOOS_MANUAL_OVERIDE", "MOOS_MANUAL_OVERRIDE" };
    for (size_t i = 0; i < sizeof subs / sizeof subs[0]; i++)
        if (kelp_app_register(app, subs[i], 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", subs[i]);
    kelp_app_event(app, "depth control %s, %s, %s", p->cfg.depth_control ? "on" : "off",
                   p->cfg.speed_factor > 0 ? "thrust = speed x SPEED_FACTOR" : "speed PID",
                   p->cfg.active_start ? "active from the start" : "waiting for MOOS_MANUAL_OVERRIDE=false");
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    mpid *p = st;
    if (v->kind == KELP_VAR_BINARY || !strcmp(v->name, "PID_VERBOSE")) return;
    int rc = kelp_pid_marine_mail(&p->m, v->name, v->kind == KELP_VAR_STRING, v->sval, v->dval, kelp_app_time(app));
    if (rc < 0) {
        p->bad_mail++;
        kelp_app_run_warning(app, "%s: not a usable value; ignored", v->name);
    }
}

static int iterate(kelp_app *app, void *st, double now)
{
    mpid *p = st;
    (void)app;
    kelp_pid_marine_iterate(&p->m, now, sink, p);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    const kelp_pid_marine *m = &((mpid *)st)->m;
    (void)app;
    fprintf(out, "Control: %s%s   iterations %lu   tardy helm %lu   tardy nav %lu\n",
            m->has_control ? "ACTIVE" : "OVERRIDDEN (all stop)", m->paused ? " (paused)" : "", m->iterations,
            m->tardy_helm_n, m->tardy_nav_n);
    fprintf(out, "  %-8s %10s %10s %10s\n", "", "heading", "speed", "depth");
    fprintf(out, "  %-8s %10.2f %10.2f %10.2f\n", "desired", m->des_heading, m->des_speed, m->des_depth);
    fprintf(out, "  %-8s %10.2f %10.2f %10.2f   pitch %.3f rad\n", "current", m->heading, m->speed_now, m->depth,
            m->pitch_now);
    fprintf(out, "Out: rudder %.2f  thrust %.2f  elevator %.2f   speed factor %g\n", m->rudder_out, m->thrust_out,
            m->elevator_out, m->cfg.speed_factor);
}

static const kelp_app_def def = {
    .name = "pMarinePID",
    .purpose = "PID loops from DESIRED_HEADING/SPEED/DEPTH to DESIRED_RUDDER/THRUST/ELEVATOR.",
    .params = (const kelp_app_param_info[]){
        { "SPEED_FACTOR", "20", "thrust = desired speed x this; 0: the speed PID (range [0, 100])", NULL },
        { "SIM_INSTABILITY", "0", "a rudder bias alternating every 10 s (testing)", NULL },
        { "ACTIVE_START", "false", "true: in control from the start (else after MOOS_MANUAL_OVERRIDE=false)", NULL },
        { "TARDY_HELM_THRESHOLD", "2.0", "seconds without DESIRED_HEADING/SPEED before thrust 0", NULL },
        { "TARDY_NAV_THRESHOLD", "2.0", "seconds without NAV_* before thrust 0", NULL },
        { "OUTPUT_SUFFIX", "_PID", "appended to DESIRED_RUDDER/THRUST/ELEVATOR", NULL },
        { "VERBOSE", "terse", "accepted (the status report shows the loops)", NULL },
        { "HEADING_DEBUG", "false", "true: PID_HDG_DEBUG each iteration, PID_MAX_SAT_HDG_DEBUG when saturated", NULL },
        { "SPEED_DEBUG", "false", "true: PID_SPD_DEBUG, PID_MAX_SAT_SPD_DEBUG", NULL },
        { "DEPTH_DEBUG", "false", "true: PID_DEP_DEBUG, PID_MAX_SAT_DEP_DEBUG", NULL },
        { "MAX_SAT_HDG_DEBUG", "false", "accepted, no effect (24.8's --example lists it; HEADING_DEBUG is the switch)", NULL },
        { "MAX_SAT_SPD_DEBUG", "false", "accepted, no effect (SPEED_DEBUG)", NULL },
        { "MAX_SAT_DEP_DEBUG", "false", "accepted, no effect (DEPTH_DEBUG)", NULL },
        { "YAW_PID_KP", "0.5", NULL, NULL },
        { "YAW_PID_KD", "0.1", NULL, NULL },
        { "YAW_PID_KI", "0.012", NULL, NULL },
        { "YAW_PID_INTEGRAL_LIMIT", "0.07", NULL, NULL },
        { "YAW_PID_KI_LIMIT", "0.2", "same as YAW_PID_INTEGRAL_LIMIT", "YAW_PID_INTEGRAL_LIMIT" },
        { "MAXRUDDER", "100", NULL, NULL },
        { "SPEED_PID_KP", "0.8", NULL, NULL },
        { "SPEED_PID_KD", "0.1", NULL, NULL },
        { "SPEED_PID_KI", "0.11", NULL, NULL },
        { "SPEED_PID_INTEGRAL_LIMIT", "0.07", NULL, NULL },
        { "SPEED_PID_KI_LIMIT", "0.07", "same as SPEED_PID_INTEGRAL_LIMIT", "SPEED_PID_INTEGRAL_LIMIT" },
        { "MAXTHRUST", "100", NULL, NULL },
        { "DEPTH_CONTROL", "true", "run the depth loops (DESIRED_ELEVATOR)", NULL },
        { "Z_TO_PITCH_PID_KP", "0.12", NULL, NULL },
        { "Z_TO_PITCH_PID_KD", "1.0", NULL, NULL },
        { "Z_TO_PITCH_PID_KI", "0.004", NULL, NULL },
        { "Z_TO_PITCH_PID_INTEGRAL_LIMIT", "0.05", NULL, NULL },
        { "MAXPITCH", "15", "degrees", NULL },
        { "PITCH_PID_KP", "0.5", NULL, NULL },
        { "PITCH_PID_KD", "1.0", NULL, NULL },
        { "PITCH_PID_KI", "0", NULL, NULL },
        { "PITCH_PID_INTEGRAL_LIMIT", "0", NULL, NULL },
        { "MAXELEVATOR", "13", "degrees", NULL },
        { "IGNORE_NAV_YAW", "false", "true: NAV_YAW is not read as the heading", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "DESIRED_HEADING", "189", NULL },
        { "DESIRED_SPEED", "3.2", NULL },
        { "DESIRED_DEPTH", "15", NULL },
        { "NAV_HEADING", "182", NULL },
        { "NAV_YAW", "0.12", "radians: heading = -yaw in degrees" },
        { "NAV_SPEED", "3.4", NULL },
        { "NAV_DEPTH", "22", NULL },
        { "NAV_PITCH", "-1.9", "radians" },
        { "SPEED_FACTOR", "20", NULL },
        { "PID_VERBOSE", "verbose/quiet/terse", "accepted" },
        { "MOOS_MANUAL_OVERIDE", "false", "and MOOS_MANUAL_OVERRIDE: true stops, false takes control" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "DESIRED_RUDDER", "-22", "+ OUTPUT_SUFFIX; also DESIRED_THRUST, DESIRED_ELEVATOR (depth control)" },
        { "DESIRED_THRUST", "60", NULL },
        { "DESIRED_ELEVATOR", "-1.2", "degrees" },
        { "PID_HDG_DEBUG", "PID_COURSE:  (Want):90.00000 (Curr):88.50000 (Diff):-1.50000 RUDDER:0.75000",
          "HEADING_DEBUG = true, each iteration with thrust; PID_SPD_DEBUG (SPEED_DEBUG), PID_DEP_DEBUG (DEPTH_DEBUG)" },
        { "PID_SPD_DEBUG", "PID_SPEED:  (Want):2.00000 (Curr):1.80000 (Diff):0.20000 (Delt):0.16000 THRUST:40.16000", NULL },
        { "PID_DEP_DEBUG", "PID_DEPTH:  (Want):10.00000 (Curr):9.00000 (Diff):-1.00000 ELEVATOR:-2.10000", NULL },
        { "PID_MAX_SAT_HDG_DEBUG", "dfeIn=145.88560, dfErrorTime=..., m_dfOut(1)218.84885, m_dfOut(1)100",
          "the loop's steps when it saturated (HEADING_DEBUG); PID_MAX_SAT_SPD_DEBUG, PID_MAX_SAT_DEP_DEBUG (Z: or P:)" },
        { "PID_MAX_SAT_SPD_DEBUG", "dfeIn=...", NULL },
        { "PID_MAX_SAT_DEP_DEBUG", "Z:dfeIn=...", NULL },
        { "PID_HAS_CONTROL", "true", "on MOOS_MANUAL_OVERRIDE = false; false when control is lost" },
        { "PID_STALE", "Stale DesHdg:2.25", "per stale input (DesHdg, DesSpd, NavHdg, NavSpd, DesDepth, NavDep, NavPitch)" },
        { NULL, NULL, NULL } },
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static mpid p;
    return kelp_app_run(argc, argv, &def, &p);
}
