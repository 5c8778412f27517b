/* uSimMarine: a single-vehicle simulator (the MOOS-IvP uSimMarine / iMarineSim role).
 * Follows DESIRED_HEADING/SPEED/DEPTH within turn-rate, acceleration/deceleration and
 * depth-rate limits (the kelp_sim model, include/kelp/sim.h) and publishes the navigation
 * solution every iteration. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/geo.h>
#include <kelp/sim.h>

typedef struct usim {
    kelp_sim sim;
    kelp_geo geo;
    bool have_geo;
    char prefix[32];
    char v_x[48], v_y[48], v_hdg[48], v_spd[48], v_dep[48], v_lat[48], v_lon[48];
    unsigned long des_mail[3], bad_mail, resets;
    double last_des_time;
} usim;

/* A numeric parameter that must be >= lo: 0 absent, 1 set, <0 fatal (reported). */
static int num_param(kelp_app *app, const char *key, double lo, double *out)
{
    const kelp_mission_node *n = kelp_app_param(app, key);
    if (!n) return 0;
    double d;
    if (kelp_mission_double(n, &d) < 0 || !isfinite(d))
        return kelp_app_config_error(app, n, "%s = '%.*s' is not a number", key, (int)n->vlen, n->val);
    if (d < lo) return kelp_app_config_error(app, n, "%s = %g must be >= %g", key, d, lo);
    *out = d;
    return 1;
}

static int startup(kelp_app *app, void *st)
{
    usim *u = st;
    kelp_sim_params p;
    kelp_sim_params_default(&p);
    kelp_sim_state s = {0, 0, 0, 0, 0};
    /* START_POS first, then the single START_* parameters override */
    const kelp_mission_node *n = kelp_app_param(app, "START_POS");
    if (n) {
        char buf[256];
        if (kelp_mission_copy(n, buf, sizeof buf) < 0 || kelp_sim_parse_start(buf, &s) < 0)
            return kelp_app_config_error(app, n,
                                         "START_POS = '%.*s': expected x,y[,heading[,speed[,depth]]] or "
                                         "x=..,y=..,heading=..,speed=..,depth=..",
                                         (int)n->vlen, n->val);
    }
    int rc = 0;
    if ((rc = num_param(app, "START_X", -INFINITY, &s.x)) < 0) return rc;
    if ((rc = num_param(app, "START_Y", -INFINITY, &s.y)) < 0) return rc;
    if ((rc = num_param(app, "START_HEADING", -INFINITY, &s.heading)) < 0) return rc;
    if ((rc = num_param(app, "START_SPEED", 0, &s.speed)) < 0) return rc;
    if ((rc = num_param(app, "START_DEPTH", 0, &s.depth)) < 0) return rc;
    if ((rc = num_param(app, "TURN_RATE", 0, &p.turn_rate)) < 0) return rc;
    if ((rc = num_param(app, "TURN_SPEED", 0, &p.turn_speed)) < 0) return rc;
    if ((rc = num_param(app, "MAX_ACCELERATION", 0, &p.max_accel)) < 0) return rc;
    if ((rc = num_param(app, "MAX_DECELERATION", 0, &p.max_decel)) < 0) return rc;
    if ((rc = num_param(app, "MAX_DEPTH_RATE", 0, &p.max_depth_rate)) < 0) return rc;
    if ((rc = num_param(app, "MAX_DEPTH_RATE_SPEED", 0, &p.max_depth_rate_speed)) < 0) return rc;
    if ((rc = num_param(app, "MAX_SPEED", 0, &p.max_speed)) < 0) return rc;
    if ((rc = num_param(app, "SIM_STEP", 1e-4, &p.step)) < 0) return rc;
    snprintf(u->prefix, sizeof u->prefix, "NAV");
    n = kelp_app_param(app, "PREFIX");
    if (n && (n->vlen == 0 || kelp_mission_copy(n, u->prefix, 24) < 0))
        return kelp_app_config_error(app, n, "PREFIX must be 1..23 characters");
    snprintf(u->v_x, sizeof u->v_x, "%s_X", u->prefix);
    snprintf(u->v_y, sizeof u->v_y, "%s_Y", u->prefix);
    snprintf(u->v_hdg, sizeof u->v_hdg, "%s_HEADING", u->prefix);
    snprintf(u->v_spd, sizeof u->v_spd, "%s_SPEED", u->prefix);
    snprintf(u->v_dep, sizeof u->v_dep, "%s_DEPTH", u->prefix);
    snprintf(u->v_lat, sizeof u->v_lat, "%s_LAT", u->prefix);
    snprintf(u->v_lon, sizeof u->v_lon, "%s_LONG", u->prefix);
    if (kelp_sim_init(&u->sim, &p, &s, kelp_app_time(app)) < 0)
        return kelp_app_config_error(app, NULL, "bad start pose or limits");
    double lat0, lon0;
    int a = kelp_app_global_double(app, "LatOrigin", &lat0), b = kelp_app_global_double(app, "LongOrigin", &lon0);
    if (a == 1 && b == 1) {
        if (kelp_geo_init(&u->geo, lat0, lon0) < 0)
            return kelp_app_config_error(app, NULL, "LatOrigin/LongOrigin %g, %g out of range", lat0, lon0);
        u->have_geo = true;
    } else if (a < 0 || b < 0) {
        return kelp_app_config_error(app, NULL, "LatOrigin/LongOrigin must be numbers");
    } else {
        kelp_app_config_warning(app, "no LatOrigin/LongOrigin globals: %s and %s are not published", u->v_lat,
                                u->v_lon);
    }
    kelp_app_event(app, "start x=%.2f y=%.2f heading=%.1f speed=%.2f depth=%.2f", s.x, s.y, u->sim.s.heading,
                   s.speed, s.depth);
    if (kelp_app_register(app, "DESIRED_HEADING", 0) < 0 || kelp_app_register(app, "DESIRED_SPEED", 0) < 0 ||
        kelp_app_register(app, "DESIRED_DEPTH", 0) < 0 || kelp_app_register(app, "USM_RESET", 0) < 0)
        return kelp_app_config_error(app, NULL, "cannot register");
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    usim *u = st;
    if (strcmp(v->name, "USM_RESET") == 0) {
        kelp_sim_state s = u->sim.s;
        if (v->kind != KELP_VAR_STRING || kelp_sim_parse_start(v->sval, &s) < 0) {
            kelp_app_run_warning(app, "bad USM_RESET '%.60s'", v->kind == KELP_VAR_STRING ? v->sval : "(not a string)");
            return;
        }
        kelp_sim_params p = u->sim.p;
        if (kelp_sim_init(&u->sim, &p, &s, u->sim.time) == 0) {
            u->resets++;
            kelp_app_event(app, "reset to x=%.2f y=%.2f heading=%.1f", s.x, s.y, u->sim.s.heading);
        }
        return;
    }
    double d = v->dval;
    if (v->kind == KELP_VAR_STRING && kelp_parse_double(v->sval, v->slen, &d) < 0) d = NAN;
    if (v->kind == KELP_VAR_BINARY) d = NAN;
    int rc = KELP_ERR_ARG, k = -1;
    if (strcmp(v->name, "DESIRED_HEADING") == 0) rc = kelp_sim_set_heading(&u->sim, d), k = 0;
    else if (strcmp(v->name, "DESIRED_SPEED") == 0) rc = kelp_sim_set_speed(&u->sim, d), k = 1;
    else if (strcmp(v->name, "DESIRED_DEPTH") == 0) rc = kelp_sim_set_depth(&u->sim, d), k = 2;
    if (k < 0) return;
    if (rc < 0) {
        u->bad_mail++;
        kelp_app_run_warning(app, "%s is not a finite number; ignored", v->name);
        return;
    }
    u->des_mail[k]++;
    u->last_des_time = v->time;
}

static int iterate(kelp_app *app, void *st, double now)
{
    usim *u = st;
    int rc = kelp_sim_step(&u->sim, now);
    if (rc < 0) {
        kelp_app_run_warning(app, "time step to %.3f failed (%s)", now, kelp_strerror(rc));
        if (rc == KELP_ERR_RANGE && now > u->sim.time) u->sim.time = now; /* a jump: resume from now */
    }
    const kelp_sim_state *s = &u->sim.s;
    int e = 0;
    e |= kelp_app_notify_double(app, u->v_x, s->x);
    e |= kelp_app_notify_double(app, u->v_y, s->y);
    e |= kelp_app_notify_double(app, u->v_hdg, s->heading);
    e |= kelp_app_notify_double(app, u->v_spd, s->speed);
    e |= kelp_app_notify_double(app, u->v_dep, s->depth);
    if (u->have_geo) {
        double lat, lon;
        if (kelp_geo_to_latlon(&u->geo, s->x, s->y, &lat, &lon) == 0) {
            e |= kelp_app_notify_double(app, u->v_lat, lat);
            e |= kelp_app_notify_double(app, u->v_lon, lon);
        } else {
            kelp_app_run_warning(app, "position too far from the datum for lat/lon");
        }
    }
    if (e) kelp_app_run_warning(app, "publish failed");
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    usim *u = st;
    (void)app;
    const kelp_sim_state *s = &u->sim.s;
    fprintf(out, "  %-8s %10s %10s %9s %8s %8s\n", "", "x", "y", "heading", "speed", "depth");
    fprintf(out, "  %-8s %10.2f %10.2f %9.2f %8.2f %8.2f\n", "state", s->x, s->y, s->heading, s->speed, s->depth);
    fprintf(out, "  %-8s %10s %10s %9.2f %8.2f %8.2f\n", "desired", "", "", u->sim.des_heading, u->sim.des_speed,
            u->sim.des_depth);
    fprintf(out, "Limits: turn %g deg/s (full from %g m/s), accel %g m/s^2, decel %g m/s^2, depth rate %g m/s (0 = none)\n",
            u->sim.p.turn_rate, u->sim.p.turn_speed, u->sim.p.max_accel, u->sim.p.max_decel, u->sim.p.max_depth_rate);
    fprintf(out, "Odometer %.1f m; DESIRED_* mail: heading %lu, speed %lu, depth %lu; bad %lu; resets %lu\n",
            u->sim.odometer, u->des_mail[0], u->des_mail[1], u->des_mail[2], u->bad_mail, u->resets);
    if (u->have_geo) fprintf(out, "Datum: LatOrigin %.6f LongOrigin %.6f\n", u->geo.lat0, u->geo.lon0);
}

static const kelp_app_def def = {
    .name = "uSimMarine",
    .purpose = "Simulate one marine vehicle following DESIRED_HEADING/SPEED/DEPTH; publish NAV_*.",
    .params = (const kelp_app_param_info[]){
        { "START_POS", "x=0, y=0, heading=0, speed=0, depth=0", "or x,y[,heading[,speed[,depth]]]", NULL },
        { "START_X", "0", "meters; overrides START_POS", NULL },
        { "START_Y", "0", "meters; overrides START_POS", NULL },
        { "START_HEADING", "0", "degrees; overrides START_POS", NULL },
        { "START_SPEED", "0", "m/s, >= 0; overrides START_POS", NULL },
        { "START_DEPTH", "0", "meters, >= 0; overrides START_POS", NULL },
        { "PREFIX", "NAV", "published variables are <PREFIX>_X, _Y, ...", NULL },
        { "TURN_RATE", "20", "deg/s at full speed, >= 0 (0 = turn at once)", NULL },
        { "TURN_SPEED", "0.5", "m/s: below it the turn rate scales with speed (0 = off)", NULL },
        { "MAX_ACCELERATION", "0.5", "m/s^2 (0 = no limit)", NULL },
        { "MAX_DECELERATION", "0.5", "m/s^2 (0 = no limit)", NULL },
        { "MAX_DEPTH_RATE", "0.5", "m/s (0 = no limit)", NULL },
        { "MAX_DEPTH_RATE_SPEED", "0", "m/s: depth rate scaled by speed/this (0 = off)", NULL },
        { "MAX_SPEED", "0", "m/s, clip on the desired speed (0 = none)", NULL },
        { "SIM_STEP", "0.05", "s, integration sub-step, >= 0.0001", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "DESIRED_HEADING", "118.8", "degrees" },
        { "DESIRED_SPEED", "2.0", "m/s" },
        { "DESIRED_DEPTH", "4.6", "meters" },
        { "USM_RESET", "x=10, y=-20, heading=90", "a START_POS value: jump to that pose" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "NAV_X", "112.3", "every iteration (NAV = PREFIX)" },
        { "NAV_Y", "-99.1", NULL },
        { "NAV_HEADING", "118.8", NULL },
        { "NAV_SPEED", "2.0", NULL },
        { "NAV_DEPTH", "4.6", NULL },
        { "NAV_LAT", "43.824981", "with LatOrigin/LongOrigin" },
        { "NAV_LONG", "-70.329755", "with LatOrigin/LongOrigin" },
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
