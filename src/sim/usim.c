/* uSimMarine's logic around the simulator model (see include/kelp/sim.h, kelp_usim). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/mission.h>
#include <kelp/pid.h>
#include <kelp/sim.h>
#include <kelp/util.h>

#define PI 3.14159265358979323846

void kelp_usim_defaults(kelp_usim *u, struct kelp_pid_marine *pid, struct kelp_pid_marine_cfg *pid_cfg)
{
    memset(u, 0, sizeof *u);
    kelp_sim_params_default(&u->p);
    u->pid = pid;
    u->pid_cfg = pid_cfg;
    if (pid_cfg) {
        kelp_pid_marine_cfg_default(pid_cfg);
        pid_cfg->active_start = true; /* embedded: no override handshake */
    }
    memcpy(u->prefix, "NAV", 4);
}

int kelp_usim_config(kelp_usim *u, const char *key, const char *val, kelp_diag *d)
{
    int rc = kelp_sim_config_set(&u->p, &u->start, key, val, d);
    if (rc != 0) return rc;
    if (u->pid_cfg && (rc = kelp_pid_marine_cfg_set(u->pid_cfg, key, val, d)) != 0) {
        if (rc > 0 && kelp_util_strieq_n(key, 7, "YAW_PID")) u->embedded_pid = true;
        if (rc > 0 && kelp_util_strieq(key, "DEPTH_CONTROL")) u->no_sim_mode = !u->pid_cfg->depth_control;
        return rc;
    }
    if (kelp_util_strieq(key, "PREFIX")) {
        size_t n = strlen(val);
        while (n && val[n - 1] == '_') n--; /* MOOS-IvP 24.8 writes "NAV_" */
        if (n == 0 || n >= sizeof u->prefix) {
            return kelp_fail(d, KELP_ERR_RANGE, "must be 1..23 characters");
        }
        memcpy(u->prefix, val, n);
        u->prefix[n] = 0;
        return 1;
    }
    if (kelp_util_strieq(key, "SIM_PAUSE") || kelp_util_strieq(key, "POST_NAVPOS_SUMMARY")) {
        bool b = kelp_util_strieq(val, "true");
        if (!b && !kelp_util_strieq(val, "false")) {
            return kelp_fail(d, KELP_ERR_PARSE, "must be true or false");
        }
        *(kelp_util_strieq(key, "SIM_PAUSE") ? &u->paused : &u->navpos_summary) = b;
        return 1;
    }
    char *dst = kelp_util_strieq(key, "POST_DES_RUDDER") ? u->post_rudder : kelp_util_strieq(key, "POST_DES_THRUST") ? u->post_thrust : NULL;
    if (dst) {
        if (strlen(val) >= KELP_MAX_NAME || !strcmp(val, "DESIRED_RUDDER") || !strcmp(val, "DESIRED_THRUST")) {
            return kelp_fail(d, KELP_ERR_PARSE, "a variable name other than DESIRED_RUDDER/DESIRED_THRUST");
        }
        memcpy(dst, val, strlen(val) + 1);
        return 1;
    }
    return 0;
}

int kelp_usim_start(kelp_usim *u, const kelp_geo *geo, kelp_time now)
{
    if (u->embedded_pid) u->p.control = KELP_SIM_ACTUATED;
    if (kelp_sim_init(&u->sim, &u->p, &u->start, now) < 0) return KELP_ERR_ARG;
    if (u->embedded_pid && (!u->pid || kelp_pid_marine_init(u->pid, u->pid_cfg, now) < 0)) return KELP_ERR_ARG;
    u->drift_fresh = true;
    u->have_geo = geo != NULL;
    if (geo) u->geo = *geo;
    return KELP_OK;
}

static const char *const subs[] = { "DESIRED_HEADING", "DESIRED_SPEED", "DESIRED_DEPTH", "DESIRED_RUDDER",
                                    "DESIRED_THRUST",  "DESIRED_ELEVATOR", "DRIFT_X",     "DRIFT_Y",
                                    "ROTATE_SPEED",    "BUOYANCY_RATE",    "USM_RESET",   "USM_SIM_PAUSED" };

const char *kelp_usim_subscription(unsigned i)
{
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

int kelp_usim_mail(kelp_usim *u, const char *var, bool is_string, const char *sval, double dval, kelp_time now)
{
    int k = -1;
    for (int i = 0; i < (int)(sizeof subs / sizeof subs[0]); i++)
        if (!strcmp(var, subs[i])) k = i;
    if (k < 0) return 0;
    if (k == 10) { /* USM_RESET: a START_POS value */
        kelp_sim_state s = u->sim.s;
        if (!is_string || !sval || kelp_sim_parse_start(sval, &s) < 0) return KELP_ERR_PARSE;
        kelp_sim_params p = u->sim.p;
        if (kelp_sim_init(&u->sim, &p, &s, u->sim.time) < 0) return KELP_ERR_RANGE;
        u->resets++;
        return 1;
    }
    if (k == 11) {
        u->paused = is_string && sval && kelp_util_strieq(sval, "true");
        return 1;
    }
    double d = dval;
    if (is_string && (!sval || kelp_util_parse_double(sval, strlen(sval), &d) < 0)) d = NAN;
    if (!isfinite(d)) {
        u->bad_mail++;
        return KELP_ERR_ARG;
    }
    int rc = KELP_OK;
    if (k < 3 && u->embedded_pid) rc = kelp_pid_marine_mail(u->pid, var, false, NULL, d, now) < 0 ? KELP_ERR_ARG : KELP_OK;
    else if (k == 0) rc = kelp_sim_set_heading(&u->sim, d);
    else if (k == 1) rc = kelp_sim_set_speed(&u->sim, d);
    else if (k == 2) rc = kelp_sim_set_depth(&u->sim, d);
    else if (k == 3) rc = kelp_sim_set_rudder(&u->sim, d);
    else if (k == 4) rc = kelp_sim_set_thrust(&u->sim, d);
    else if (k == 5) rc = kelp_sim_set_elevator(&u->sim, d);
    else {
        double *f[4] = { &u->sim.p.drift_x, &u->sim.p.drift_y, &u->sim.p.rotate_speed, &u->sim.p.buoyancy_rate };
        *f[k - 6] = d;
        if (k < 8) u->drift_fresh = true;
    }
    if (rc < 0) {
        u->bad_mail++;
        return rc;
    }
    if (k < 6) u->mail[k]++;
    return 1;
}

typedef struct pid_ctx {
    kelp_usim *u;
    kelp_usim_sink sink;
    void *ctx;
} pid_ctx;

/* the embedded PID's outputs drive the simulator (and are posted when asked) */
static void pid_out(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    pid_ctx *c = ctx;
    if (is_string) { /* the engine's own notes, as uSimMarineV22 posts them */
        if (!strcmp(var, "PID_STALE") || !strcmp(var, "PID_HAS_CONTROL")) c->sink(c->ctx, var, true, sval, 0);
        return;
    }
    int rc = 0;
    const char *post = NULL;
    if (!strncmp(var, "DESIRED_RUDDER", 14)) rc = kelp_sim_set_rudder(&c->u->sim, dval), post = c->u->post_rudder;
    else if (!strncmp(var, "DESIRED_THRUST", 14)) rc = kelp_sim_set_thrust(&c->u->sim, dval), post = c->u->post_thrust;
    else if (!strncmp(var, "DESIRED_ELEVATOR", 16)) rc = kelp_sim_set_elevator(&c->u->sim, dval);
    if (rc == 0 && post && post[0]) c->sink(c->ctx, post, false, NULL, dval);
}

/* USM_DRIFT_SUMMARY as uSimMarineV22 (USM_Model::getDriftSummary): the drift's direction and
 * size to 2 decimals, its components to 3, trailing zeros trimmed */
static void drift_summary(kelp_usim *u, kelp_usim_sink sink, void *ctx)
{
    double dx = u->sim.p.drift_x, dy = u->sim.p.drift_y;
    double v[4] = { kelp_sim_bearing(0, 0, dx, dy), hypot(dx, dy), dx, dy };
    static const char *const key[4] = { "ang=", ", mag=", ", xmag=", ", ymag=" };
    char *b = u->work, *end = u->work + sizeof u->work;
    for (int i = 0; i < 4 && b < end; i++) {
        size_t kl = strlen(key[i]);
        if ((size_t)(end - b) <= kl) break;
        memcpy(b, key[i], kl + 1);
        b += kl;
        int n = kelp_util_fmt_fixed(b, (size_t)(end - b), v[i], i < 2 ? 2 : 3, true);
        if (n < 0 || n >= end - b) break;
        b += n;
    }
    sink(ctx, "USM_DRIFT_SUMMARY", true, u->work, 0);
}

/* NAV_SPEED as uSimMarineV22 posts it: to the nearest 0.01 m/s (ties up), at most max_speed
 * (5 m/s unless set) */
static double nav_speed(const kelp_usim *u)
{
    double lim = u->sim.p.max_speed > 0 ? u->sim.p.max_speed : KELP_USIM_NAV_MAX_SPEED;
    double v = floor(u->sim.s.speed / 0.01 + 0.5) * 0.01;
    return v > lim ? lim : v;
}

int kelp_usim_iterate(kelp_usim *u, kelp_time now, kelp_usim_sink sink, void *ctx)
{
    const kelp_sim_state *s = &u->sim.s;
    if (!kelp_util_time_ok(now)) return KELP_ERR_ARG;
    /* the time step rule: a clock step back, or forward beyond KELP_TIME_STEP_MAX, is not a dt
     * (no dead reckoning over an hour the vehicle did not move): the simulation resumes from now */
    if (now < u->sim.time || now - u->sim.time > KELP_TIME_STEP_MAX) u->sim.time = now;
    if (u->embedded_pid) {
        (void)kelp_pid_marine_mail(u->pid, "NAV_HEADING", false, NULL, s->heading, now);
        (void)kelp_pid_marine_mail(u->pid, "NAV_SPEED", false, NULL, s->speed, now);
        (void)kelp_pid_marine_mail(u->pid, "NAV_DEPTH", false, NULL, s->depth, now);
        (void)kelp_pid_marine_mail(u->pid, "NAV_PITCH", false, NULL, u->sim.pitch, now);
        pid_ctx c = { u, sink, ctx };
        kelp_pid_marine_iterate(u->pid, now, pid_out, &c);
    }
    int rc = u->paused ? KELP_OK : kelp_sim_step(&u->sim, now);
    if (u->paused || (rc == KELP_ERR_RANGE && now > u->sim.time))
        u->sim.time = now; /* paused, or a jump: resume from now */
    /* uSimMarineV22 (postNodeRecordUpdate) posts the navigation every KELP_USIM_NAV_MODULO-th
     * iteration, from the second */
    if (u->drift_fresh) {
        drift_summary(u, sink, ctx);
        u->drift_fresh = false;
    }
    if (++u->iterations % KELP_USIM_NAV_MODULO != 0) return rc;
    static const char *const suffix[] = { "_X", "_Y", "_HEADING", "_SPEED", "_DEPTH", "_Z", "_YAW", "_PITCH",
                                          "_SPEED_OVER_GROUND", "_HEADING_OVER_GROUND" };
    double v[10] = { s->x, s->y, s->heading, nav_speed(u), s->depth, -s->depth, -kelp_sim_angle180(s->heading) * PI / 180.0,
                     u->sim.pitch, u->sim.sog, u->sim.hog };
    char name[48];
    for (int i = 0; i < 10; i++) {
        kelp_util_snprintf(name, sizeof name, "%s%s", u->prefix, suffix[i]);
        sink(ctx, name, false, NULL, v[i]);
    }
    if (!u->no_sim_mode) sink(ctx, "SIMULATION_MODE", true, "TRUE", 0);
    sink(ctx, "TRUE_X", false, NULL, s->x);
    sink(ctx, "TRUE_Y", false, NULL, s->y);
    double lat = 0, lon = 0;
    if (u->have_geo && kelp_geo_to_latlon(&u->geo, s->x, s->y, &lat, &lon) == 0) {
        kelp_util_snprintf(name, sizeof name, "%s_LAT", u->prefix);
        sink(ctx, name, false, NULL, lat);
        kelp_util_snprintf(name, sizeof name, "%s_LONG", u->prefix);
        sink(ctx, name, false, NULL, lon);
    } else if (u->have_geo && rc == KELP_OK) {
        rc = KELP_ERR_RANGE; /* too far from the datum */
    }
    if (u->navpos_summary) {
        char buf[160];
        kelp_util_snprintf(buf, sizeof buf, "x=%.3f,y=%.3f,lat=%.7f,lon=%.7f", s->x, s->y, lat, lon);
        sink(ctx, "USM_NAVPOS_SUMMARY", true, buf, 0);
    }
    return rc;
}
