/* The uSimMarine-role kinematic model (see include/kelp/sim.h). */
#include <math.h>
#include <string.h>
#include <kelp/sim.h>
#include <kelp/kv.h>
#include <kelp/mission.h>

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define RAD2DEG (180.0 / 3.14159265358979323846)

double kelp_sim_angle360(double deg)
{
    if (!isfinite(deg)) return 0.0;
    double a = fmod(deg, 360.0);
    if (a < 0) a += 360.0;
    if (a >= 360.0) a = 0.0; /* -tiny + 360 rounds to 360 */
    return a;
}

double kelp_sim_angle180(double deg)
{
    double a = kelp_sim_angle360(deg);
    return a > 180.0 ? a - 360.0 : a;
}

double kelp_sim_bearing(double x0, double y0, double x1, double y1)
{
    double dx = x1 - x0, dy = y1 - y0;
    if (dx == 0.0 && dy == 0.0) return 0.0;
    return kelp_sim_angle360(atan2(dx, dy) * RAD2DEG);
}

void kelp_sim_params_default(kelp_sim_params *p)
{
    p->turn_rate = 20.0;
    p->turn_speed = 0.5;
    p->max_accel = 0.5;
    p->max_decel = 0.5;
    p->max_depth_rate = 0.5;
    p->max_depth_rate_speed = 0.0;
    p->max_speed = 0.0;
    p->step = 0.05;
    p->control = KELP_SIM_AUTO;
    p->act_turn_rate = 70.0;
    p->thrust_factor = 20.0;
    p->turn_spd_loss = 0.85;
    p->act_max_accel = 0.0;
    p->tsm_null_speed = 0.0;
    p->tsm_null_rate = 0.0;
    p->tsm_full_speed = 1.0;
    p->tsm_full_rate = 100.0;
    p->buoyancy_rate = 0.0;
    p->nmap = 0;
    p->drift_x = p->drift_y = p->rotate_speed = 0.0;
}

static bool nonneg(double v) { return isfinite(v) && v >= 0.0; }

int kelp_sim_init(kelp_sim *sim, const kelp_sim_params *p, const kelp_sim_state *start, kelp_time now)
{
    if (!sim || !p || !start || !isfinite(now)) return KELP_ERR_ARG;
    if (!nonneg(p->turn_rate) || !nonneg(p->turn_speed) || !nonneg(p->max_accel) || !nonneg(p->max_decel) || !nonneg(p->max_depth_rate) ||
        !nonneg(p->max_depth_rate_speed) || !nonneg(p->max_speed) || !isfinite(p->step) || p->step <= 0.0 ||
        !nonneg(p->act_turn_rate) || !nonneg(p->thrust_factor) || !nonneg(p->turn_spd_loss) || p->turn_spd_loss > 1 ||
        !nonneg(p->act_max_accel) || !nonneg(p->tsm_null_speed) || !nonneg(p->tsm_null_rate) || p->tsm_null_rate > 100 ||
        !isfinite(p->tsm_full_speed) || p->tsm_full_speed <= 0 || !nonneg(p->tsm_full_rate) || p->tsm_full_rate > 100 ||
        !isfinite(p->buoyancy_rate) || !isfinite(p->drift_x) || !isfinite(p->drift_y) || !isfinite(p->rotate_speed) ||
        p->nmap > KELP_SIM_MAX_MAP || p->control < KELP_SIM_AUTO || p->control > KELP_SIM_ACTUATED)
        return KELP_ERR_ARG;
    if (!isfinite(start->x) || !isfinite(start->y) || !isfinite(start->heading) || !nonneg(start->speed) ||
        !nonneg(start->depth))
        return KELP_ERR_ARG;
    memset(sim, 0, sizeof *sim);
    sim->p = *p;
    sim->s = *start;
    sim->s.heading = kelp_sim_angle360(start->heading);
    sim->time = now;
    sim->des_heading = sim->s.heading;
    sim->des_speed = sim->s.speed;
    sim->des_depth = sim->s.depth;
    sim->actuated = p->control == KELP_SIM_ACTUATED;
    sim->sog = sim->s.speed;
    sim->hog = sim->s.heading;
    return KELP_OK;
}

static int actuator(kelp_sim *sim, double *dst, double v, double lo)
{
    if (!isfinite(v)) return KELP_ERR_ARG;
    *dst = v < lo ? lo : (v > 100.0 ? 100.0 : v);
    if (sim->p.control == KELP_SIM_AUTO) sim->actuated = true;
    return KELP_OK;
}

int kelp_sim_set_rudder(kelp_sim *sim, double v) { return actuator(sim, &sim->rudder, v, -100.0); }
int kelp_sim_set_thrust(kelp_sim *sim, double v) { return actuator(sim, &sim->thrust, v, -100.0); }
int kelp_sim_set_elevator(kelp_sim *sim, double v) { return actuator(sim, &sim->elevator, v, -100.0); }

int kelp_sim_parse_thrust_map(const char *s, kelp_sim_params *p)
{
    unsigned n = 0;
    const char *c = s;
    while (*c) {
        while (*c == ' ' || *c == '\t' || *c == ',') c++;
        if (!*c) break;
        const char *colon = strchr(c, ':'), *end = strchr(c, ',');
        if (!end) end = c + strlen(c);
        if (!colon || colon > end) return KELP_ERR_PARSE;
        double t, v;
        if (kelp_util_parse_double(c, (size_t)(colon - c), &t) < 0 || kelp_util_parse_double(colon + 1, (size_t)(end - colon - 1), &v) < 0 ||
            !isfinite(t) || !isfinite(v) || t < -100 || t > 100 || (n && t <= p->map_thrust[n - 1]))
            return KELP_ERR_PARSE;
        if (n >= KELP_SIM_MAX_MAP) return KELP_ERR_NOSPACE;
        p->map_thrust[n] = t, p->map_speed[n] = v, n++;
        c = end;
    }
    if (n == 0) return KELP_ERR_PARSE;
    p->nmap = n;
    return KELP_OK;
}

/* uSimMarineV22's thrust map (ThrustMap::getSpeedValue): positive thrust interpolates over
 * the points of positive thrust, from (0, 0) to the first and flat after the last; zero or
 * negative thrust gives no forward speed (kelp has no reverse) */
double kelp_sim_thrust_speed(const kelp_sim_params *p, double thrust)
{
    if (thrust <= 0) return 0.0;
    if (p->nmap == 0) return p->thrust_factor <= 0 ? 0.0 : thrust / p->thrust_factor;
    double t0 = 0.0, v0 = 0.0;
    for (unsigned i = 0; i < p->nmap; i++) {
        if (p->map_thrust[i] <= 0) continue;
        if (thrust <= p->map_thrust[i]) return v0 + (thrust - t0) / (p->map_thrust[i] - t0) * (p->map_speed[i] - v0);
        t0 = p->map_thrust[i], v0 = p->map_speed[i];
    }
    return v0;
}

/* uSimMarineV22's turn-speed map (SimEngine::propagateHeading, TurnSpeedMap::getTurnRate):
 * the full rate is turn_rate (the configured full rate when turn_rate is 0, which V22 does not
 * take), the full speed 5 m/s; a null value above its full value is lowered to it */
double kelp_sim_turn_rate_at(const kelp_sim_params *p, double speed)
{
    double full_rate = p->act_turn_rate > 0 ? (p->act_turn_rate > 100 ? 100 : p->act_turn_rate) : p->tsm_full_rate;
    double null_rate = p->tsm_null_rate > full_rate ? full_rate : p->tsm_null_rate;
    double null_speed = p->tsm_null_speed > KELP_SIM_TSM_FULL_SPEED ? KELP_SIM_TSM_FULL_SPEED : p->tsm_null_speed;
    if (speed <= null_speed) return null_rate;
    if (speed >= KELP_SIM_TSM_FULL_SPEED) return full_rate;
    return null_rate + (speed - null_speed) / (KELP_SIM_TSM_FULL_SPEED - null_speed) * (full_rate - null_rate);
}

int kelp_sim_set_heading(kelp_sim *sim, double deg)
{
    if (!isfinite(deg)) return KELP_ERR_ARG;
    sim->des_heading = kelp_sim_angle360(deg);
    return KELP_OK;
}

int kelp_sim_set_speed(kelp_sim *sim, double mps)
{
    if (!isfinite(mps)) return KELP_ERR_ARG;
    if (mps < 0.0) mps = 0.0;
    if (sim->p.max_speed > 0.0 && mps > sim->p.max_speed) mps = sim->p.max_speed;
    sim->des_speed = mps;
    return KELP_OK;
}

int kelp_sim_set_depth(kelp_sim *sim, double m)
{
    if (!isfinite(m)) return KELP_ERR_ARG;
    sim->des_depth = m < 0.0 ? 0.0 : m;
    return KELP_OK;
}

/* Move `v` toward `target` by at most `lim` (lim <= 0: no limit). */
static double approach(double v, double target, double lim)
{
    double d = target - v;
    if (lim > 0.0 && fabs(d) > lim) d = d > 0 ? lim : -lim;
    return v + d;
}

/* uSimMarineV22's rudder/thrust model, one step of h (SimEngine::propagateSpeed,
 * propagateHeading, propagateDepth, then propagate): the new speed comes from the thrust map,
 * the rudder's speed loss and the acceleration limits; the heading turns at the turn-speed
 * map's rate for that new speed; the position moves at the mean of the previous and the new
 * speed along the mean heading, and that mean becomes the vehicle's speed */
static void substep_actuated(kelp_sim *sim, double h)
{
    const kelp_sim_params *p = &sim->p;
    kelp_sim_state *s = &sim->s;
    double v0 = s->speed, h0 = s->heading;
    double target = kelp_sim_thrust_speed(p, sim->thrust);
    if (p->max_speed > 0.0 && target > p->max_speed) target = p->max_speed;
    target *= 1.0 - fabs(sim->rudder) / 100.0 * p->turn_spd_loss;
    double lim = target > v0 ? p->act_max_accel : p->max_decel;
    double v1 = approach(v0, target, lim > 0.0 ? lim * h : 0.0);
    double rate = kelp_sim_turn_rate_at(p, v1);
    double dh = v1 != 0.0 ? sim->rudder * (rate / 100.0) * h * (1.0 + (sim->thrust - 50.0) / 50.0) : 0.0;
    dh += p->rotate_speed * h;
    s->heading = kelp_sim_angle360(s->heading + dh);
    double rate_z = -p->buoyancy_rate;
    if (v1 > 0.0) {
        double pct = 1.0;
        if (p->max_depth_rate_speed > 0.0) pct = v1 / p->max_depth_rate_speed < 1.0 ? v1 / p->max_depth_rate_speed : 1.0;
        rate_z += sim->elevator / 100.0 * p->max_depth_rate * sqrt(pct);
        sim->pitch = -atan2(rate_z, v1);
    } else {
        sim->pitch = 0.0;
    }
    s->depth += rate_z * h;
    if (s->depth < 0.0) s->depth = 0.0;
    double vmid = (v0 + v1) / 2.0;
    double hmid = atan2(sin(h0 * DEG2RAD) + sin(s->heading * DEG2RAD), cos(h0 * DEG2RAD) + cos(s->heading * DEG2RAD));
    s->x += vmid * sin(hmid) * h;
    s->y += vmid * cos(hmid) * h;
    s->speed = vmid;
    sim->odometer += vmid * h;
}

static void substep(kelp_sim *sim, double h)
{
    const kelp_sim_params *p = &sim->p;
    kelp_sim_state *s = &sim->s;
    /* speed: separate acceleration and deceleration limits */
    double v0 = s->speed;
    double lim = sim->des_speed > v0 ? p->max_accel : p->max_decel;
    s->speed = approach(v0, sim->des_speed, lim > 0.0 ? lim * h : 0.0);
    if (s->speed < 0.0) s->speed = 0.0;
    double vmid = (v0 + s->speed) / 2.0;
    /* heading: the short way round, at most turn_rate*h, scaled down below turn_speed */
    double dh = kelp_sim_angle180(sim->des_heading - s->heading);
    if (p->turn_rate > 0.0) {
        double rate = p->turn_rate;
        if (p->turn_speed > 0.0 && vmid < p->turn_speed) rate *= vmid / p->turn_speed;
        double maxdh = rate * h;
        if (fabs(dh) > maxdh) dh = dh > 0 ? maxdh : -maxdh;
    } else if (p->turn_speed > 0.0 && vmid <= 0.0) {
        dh = 0.0;
    }
    double hmid = s->heading + dh / 2.0;
    s->heading = kelp_sim_angle360(s->heading + dh);
    /* depth: rate limit, optionally scaled by speed; never above the surface */
    if (p->max_depth_rate > 0.0) {
        double rate = p->max_depth_rate;
        if (p->max_depth_rate_speed > 0.0) {
            double f = vmid / p->max_depth_rate_speed;
            rate *= f < 1.0 ? f : 1.0;
        }
        double d = sim->des_depth - s->depth;
        double m = rate * h;
        if (fabs(d) > m) d = d > 0 ? m : -m;
        s->depth += d;
    } else {
        s->depth = sim->des_depth;
    }
    if (s->depth < 0.0) s->depth = 0.0;
    /* position: mean heading and mean speed over the sub-step */
    double r = hmid * DEG2RAD;
    s->x += vmid * sin(r) * h;
    s->y += vmid * cos(r) * h;
    sim->odometer += vmid * h;
}

int kelp_sim_step(kelp_sim *sim, kelp_time now)
{
    if (!sim || !isfinite(now)) return KELP_ERR_ARG;
    double dt = now - sim->time;
    if (dt < 0.0) return KELP_ERR_RANGE;
    if (dt == 0.0) return KELP_OK;
    /* the actuated model steps once per call, as uSimMarineV22 once per iteration (its speed
     * is a mean over the step, so the step is part of the model) */
    double nd = sim->actuated ? 1.0 : ceil(dt / sim->p.step - 1e-9);
    if (nd < 1.0) nd = 1.0;
    if (nd > (double)KELP_SIM_MAX_SUBSTEPS) return KELP_ERR_RANGE;
    long n = (long)nd;
    double h = dt / (double)n;
    double x0 = sim->s.x, y0 = sim->s.y;
    for (long i = 0; i < n; i++) {
        if (sim->actuated) substep_actuated(sim, h);
        else substep(sim, h);
        if (!sim->actuated) sim->pitch = 0.0;
        sim->s.heading = kelp_sim_angle360(sim->s.heading + (sim->actuated ? 0.0 : sim->p.rotate_speed * h));
        sim->s.x += sim->p.drift_x * h;
        sim->s.y += sim->p.drift_y * h;
    }
    sim->sog = hypot(sim->s.x - x0, sim->s.y - y0) / dt;
    sim->hog = sim->sog > 0 ? kelp_sim_bearing(x0, y0, sim->s.x, sim->s.y) : sim->s.heading;
    sim->time = now;
    return KELP_OK;
}

/* ------------------------------------------------------------------ START_POS */

static int set_field(kelp_sim_state *st, const char *k, size_t kl, double v)
{
    if (kelp_util_strieq_n(k, kl, "x")) st->x = v;
    else if (kelp_util_strieq_n(k, kl, "y")) st->y = v;
    else if (kelp_util_strieq_n(k, kl, "heading") || kelp_util_strieq_n(k, kl, "hdg") || kelp_util_strieq_n(k, kl, "deg"))
        st->heading = kelp_sim_angle360(v);
    else if (kelp_util_strieq_n(k, kl, "speed") || kelp_util_strieq_n(k, kl, "spd")) {
        if (v < 0.0) return KELP_ERR_ARG;
        st->speed = v;
    } else if (kelp_util_strieq_n(k, kl, "depth") || kelp_util_strieq_n(k, kl, "dep")) {
        if (v < 0.0) return KELP_ERR_ARG;
        st->depth = v;
    } else
        return KELP_ERR_PARSE;
    return KELP_OK;
}

int kelp_sim_parse_start(const char *s, kelp_sim_state *st)
{
    if (!s || !st) return KELP_ERR_ARG;
    kelp_sim_state tmp = *st;
    if (strchr(s, '=')) {
        size_t pos = 0;
        const char *k, *v;
        size_t kl, vl;
        int rc, n = 0;
        while ((rc = kelp_kv_next(s, ',', &pos, &k, &kl, &v, &vl)) == 1) {
            double d;
            if (kelp_util_parse_double(v, vl, &d) < 0 || !isfinite(d)) return KELP_ERR_PARSE;
            rc = set_field(&tmp, k, kl, d);
            if (rc < 0) return rc;
            n++;
        }
        if (rc < 0) return KELP_ERR_PARSE;
        if (n == 0) return KELP_ERR_PARSE;
    } else {
        static const char *const order[] = {"x", "y", "heading", "speed", "depth"};
        const char *p = s;
        int i = 0;
        for (;;) {
            const char *e = strchr(p, ',');
            size_t len = e ? (size_t)(e - p) : strlen(p);
            double d;
            if (i >= 5) return KELP_ERR_PARSE;
            if (kelp_util_parse_double(p, len, &d) < 0 || !isfinite(d)) return KELP_ERR_PARSE;
            int rc = set_field(&tmp, order[i], strlen(order[i]), d);
            if (rc < 0) return rc;
            i++;
            if (!e) break;
            p = e + 1;
        }
        if (i < 2) return KELP_ERR_PARSE;
    }
    *st = tmp;
    return KELP_OK;
}
