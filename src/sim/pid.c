/* kelp marine PID controller (see include/kelp/pid.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/mission.h>
#include <kelp/pid.h>
#include <kelp/sim.h>
#include <kelp/util.h>

#define RAD2DEG (180.0 / 3.14159265358979323846)
#define BIAS_PERIOD 10.0 /* seconds each way of the sim_instability rudder bias */

void kelp_pid_init(kelp_pid *p, double kp, double kd, double ki, double integral_limit, double output_limit)
{
    memset(p, 0, sizeof *p);
    p->kp = kp, p->kd = kd, p->ki = ki;
    p->integral_limit = integral_limit, p->output_limit = output_limit;
}

static double clip_abs(double v, double lim, bool *hit)
{
    lim = fabs(lim);
    if (fabs(v) >= lim) {
        if (hit) *hit = true;
        return v < 0 ? -lim : (v > 0 ? lim : 0.0);
    }
    return v;
}

int kelp_pid_run(kelp_pid *p, double e, double t, double *out)
{
    p->saturated = false;
    p->last.e = e, p->last.t = t, p->last.stage = 0, p->last.sum_clipped = false;
    double diff = 0;
    if (p->runs > 0) {
        p->dt = t - p->t_old;
        if (p->dt < 0) return KELP_ERR_RANGE;
        p->last.dt = p->dt, p->last.stage = 1;
        if (p->dt == 0) {
            *out = p->out;
            return KELP_OK;
        }
        double slope = (e - p->e_old) / p->dt;
        p->hist[p->head] = slope;
        p->head = (p->head + 1) % KELP_PID_HISTORY;
        if (p->nhist < KELP_PID_HISTORY) p->nhist++;
        for (unsigned i = 0; i < p->nhist; i++) diff += p->hist[i];
        p->last.slope = slope, p->last.dsum = diff, p->last.nhist = p->nhist, p->last.stage = 2;
        diff /= p->nhist;
        p->last.dmean = diff;
    }
    p->runs++;
    if (p->ki > 0) {
        p->sum += p->ki * e * p->dt;
        p->last.sum1 = p->sum;
        if (fabs(p->sum) >= fabs(p->integral_limit)) {
            p->sum = p->sum < 0 ? -fabs(p->integral_limit) : fabs(p->integral_limit);
            p->last.sum_clipped = true;
        }
    } else {
        p->sum = 0;
    }
    p->last.out1 = p->kp * e + p->kd * diff + p->sum;
    p->out = clip_abs(p->last.out1, p->output_limit, &p->saturated);
    p->e_old = e;
    p->t_old = t;
    *out = p->out;
    return KELP_OK;
}

/* one ", name" + value step of the debug text, appended in place (no formatter call: the
 * firmware's stack bound): fixed 5 decimals, or trimmed (x) */
static void dbg_put(char *buf, size_t cap, size_t *k, const char *name, double v, bool x)
{
    size_t n = strlen(name);
    if (n > cap - 1 - *k) n = cap - 1 - *k;
    memcpy(buf + *k, name, n);
    *k += n;
    buf[*k] = 0;
    int w = kelp_util_fmt_fixed(buf + *k, cap - *k, v, 5, x);
    if (w > 0) *k = *k + (size_t)w < cap ? *k + (size_t)w : cap - 1;
}

int kelp_pid_debug_text(const kelp_pid *p, char *buf, size_t cap)
{
    if (!cap) return 0;
    size_t k = 0;
    buf[0] = 0;
    dbg_put(buf, cap, &k, "dfeIn=", p->last.e, false);
    dbg_put(buf, cap, &k, ", dfErrorTime=", p->last.t, false);
    if (p->last.stage >= 1) dbg_put(buf, cap, &k, ", m_dfDT=", p->last.dt, false);
    if (p->last.stage == 1) return (int)k;
    if (p->last.stage == 2) {
        dbg_put(buf, cap, &k, ", dfDiffNow=", p->last.slope, false);
        dbg_put(buf, cap, &k, ", DiffHistSize=", (double)p->last.nhist, true);
        dbg_put(buf, cap, &k, ", mdfeDiff(1)=", p->last.dsum, false);
        dbg_put(buf, cap, &k, ", mdfeDiff(2)=", p->last.dmean, false);
    }
    if (p->ki > 0) {
        dbg_put(buf, cap, &k, ", m_dfKi", p->ki, false);
        dbg_put(buf, cap, &k, ", m_dfeSum(1)", p->last.sum1, false);
        dbg_put(buf, cap, &k, ", m_dfIntegralLimit", p->integral_limit, false);
        if (p->last.sum_clipped) dbg_put(buf, cap, &k, ", m_dfeSum(2)", p->sum, false);
    }
    dbg_put(buf, cap, &k, ", m_dfOut(1)", p->last.out1, true);
    if (p->saturated) dbg_put(buf, cap, &k, ", m_dfOut(1)", p->out, true);
    return (int)k;
}

void kelp_pid_marine_cfg_default(kelp_pid_marine_cfg *c)
{
    memset(c, 0, sizeof *c);
    c->max_rudder = c->max_thrust = 100;
    c->max_pitch_deg = 15;
    c->max_elevator = 13;
    c->tardy_helm = c->tardy_nav = 2;
}

static bool lim_ok(double v)
{
    return isfinite(v) && v >= 0;
}

int kelp_pid_marine_init(kelp_pid_marine *m, const kelp_pid_marine_cfg *cfg, kelp_time now)
{
    if (!lim_ok(cfg->max_rudder) || !lim_ok(cfg->max_thrust) || !lim_ok(cfg->max_pitch_deg) ||
        !lim_ok(cfg->max_elevator) || !lim_ok(cfg->speed_factor) || !lim_ok(cfg->tardy_helm) ||
        !lim_ok(cfg->tardy_nav) || !lim_ok(cfg->sim_instability))
        return KELP_ERR_ARG;
    const double *g[4] = { cfg->yaw, cfg->speed, cfg->z_to_pitch, cfg->pitch };
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 4; k++)
            if (!isfinite(g[i][k])) return KELP_ERR_ARG;
    memset(m, 0, sizeof *m);
    m->cfg = *cfg;
    /* each loop's output limit as PIDEngine sets it: maxrudder, maxthrust, maxpitch (radians),
     * maxelevator (on the pitch loop's radians, as 24.8 does) */
    kelp_pid_init(&m->yaw, cfg->yaw[0], cfg->yaw[1], cfg->yaw[2], cfg->yaw[3], cfg->max_rudder);
    kelp_pid_init(&m->speed, cfg->speed[0], cfg->speed[1], cfg->speed[2], cfg->speed[3], cfg->max_thrust);
    kelp_pid_init(&m->z_to_pitch, cfg->z_to_pitch[0], cfg->z_to_pitch[1], cfg->z_to_pitch[2], cfg->z_to_pitch[3],
                  cfg->max_pitch_deg / RAD2DEG);
    kelp_pid_init(&m->pitch, cfg->pitch[0], cfg->pitch[1], cfg->pitch[2], cfg->pitch[3], cfg->max_elevator);
    m->has_control = cfg->active_start;
    m->last_helm = m->last_nav = -1;
    for (int i = 0; i < KELP_PID_NSTAMP; i++) m->stamp[i] = -1;
    m->bias_t0 = now;
    m->bias_side = 1;
    return KELP_OK;
}

static bool num_of(bool is_string, const char *sval, double dval, double *out)
{
    if (is_string) return sval && kelp_util_parse_double(sval, strlen(sval), out) == KELP_OK && isfinite(*out);
    *out = dval;
    return isfinite(dval);
}

int kelp_pid_marine_mail(kelp_pid_marine *m, const char *var, bool is_string, const char *sval, double dval,
                         kelp_time now)
{
    if (!strcmp(var, "MOOS_MANUAL_OVERRIDE") || !strcmp(var, "MOOS_MANUAL_OVERIDE")) {
        if (!is_string || !sval) return KELP_ERR_PARSE;
        /* PIDEngine::setPIDOverride: lifting an override forgets every input's time (each must
         * come anew); PID_HAS_CONTROL says true on each lift, false when control is lost */
        if (kelp_util_strieq_n(sval, strlen(sval), "false")) {
            if (!m->has_control)
                for (int i = 0; i < KELP_PID_NSTAMP; i++) m->stamp[i] = -1;
            m->has_control = true;
            m->say_control = 1;
        } else if (kelp_util_strieq_n(sval, strlen(sval), "true")) {
            if (m->has_control) m->say_control = -1;
            m->has_control = false;
        } else {
            return KELP_ERR_PARSE;
        }
        return 1;
    }
    static const char *const names[] = { "DESIRED_HEADING", "DESIRED_SPEED", "DESIRED_DEPTH", "NAV_HEADING", "NAV_YAW",
                                         "NAV_SPEED",       "NAV_DEPTH",     "NAV_PITCH",     "SPEED_FACTOR" };
    int k = -1;
    for (int i = 0; i < 9; i++)
        if (!strcmp(var, names[i])) k = i;
    if (k < 0) return 0;
    double v;
    if (!num_of(is_string, sval, dval, &v)) return KELP_ERR_PARSE;
    static const signed char stamp_of[] = { 0, 1, 2, 3, 3, 4, 5, 6, -1 };
    if (stamp_of[k] >= 0 && !(k == 4 && m->cfg.ignore_nav_yaw)) m->stamp[stamp_of[k]] = now;
    switch (k) {
    case 0: m->des_heading = v, m->last_helm = now; break;
    case 1: m->des_speed = v, m->last_helm = now; break;
    case 2: m->des_depth = v; break;
    case 3: m->heading = kelp_sim_angle360(v); break;
    case 4:
        if (m->cfg.ignore_nav_yaw) return 1;
        m->heading = kelp_sim_angle360(-v * RAD2DEG);
        break;
    case 5: m->speed_now = v; break;
    case 6: m->depth = v; break;
    case 7: m->pitch_now = v; break;
    default:
        if (v < 0) return KELP_ERR_RANGE;
        m->cfg.speed_factor = v > 100 ? 100 : v;
        return 1;
    }
    if (k >= 3) m->last_nav = now;
    return 1;
}

static void out_num(const kelp_pid_marine *m, kelp_pid_marine_sink sink, void *ctx, const char *base, double v)
{
    char var[KELP_MAX_NAME];
    size_t a = strlen(base), b = strlen(m->cfg.suffix); /* base is a short literal */
    if (a + b >= sizeof var) b = sizeof var - 1 - a;
    memcpy(var, base, a);
    memcpy(var + a, m->cfg.suffix, b);
    var[a + b] = 0;
    sink(ctx, var, false, NULL, v);
}

/* PIDEngine's debug postings (heading_debug etc.): a loop's steps when it saturated, and one
 * line of want/current/difference/output, doubleToString's 5 decimals */
static void post_debug_sat(kelp_pid_marine *m, kelp_pid_marine_sink sink, void *ctx, const char *var,
                           const char *pre, const kelp_pid *p)
{
    if (!p->saturated) return;
    size_t n = strlen(pre);
    memcpy(m->dbg, pre, n + 1);
    (void)kelp_pid_debug_text(p, m->dbg + n, sizeof m->dbg - n);
    sink(ctx, var, true, m->dbg, 0);
}

static void post_debug_line(kelp_pid_marine *m, kelp_pid_marine_sink sink, void *ctx, const char *var,
                            const char *head, const char *const *names, const double *v, unsigned nv)
{
    size_t k = strlen(head); /* a short literal */
    memcpy(m->dbg, head, k + 1);
    for (unsigned i = 0; i < nv; i++)
        dbg_put(m->dbg, sizeof m->dbg, &k, names[i], v[i], false);
    sink(ctx, var, true, m->dbg, 0);
}

KELP_NOINLINE static void post_debug(kelp_pid_marine *m, kelp_pid_marine_sink sink, void *ctx, double r, double t,
                                     double el, double speed_delta)
{
    if (m->cfg.debug[1]) {
        if (m->cfg.speed_factor == 0) post_debug_sat(m, sink, ctx, "PID_MAX_SAT_SPD_DEBUG", "", &m->speed);
        static const char *const fct[5] = { " (Want):", " (Curr):", " (Diff):", " (Fctr):", " THRUST:" };
        static const char *const dlt[5] = { " (Want):", " (Curr):", " (Diff):", " (Delt):", " THRUST:" };
        double v[5] = { m->des_speed, m->speed_now, m->des_speed - m->speed_now,
                        m->cfg.speed_factor != 0 ? m->cfg.speed_factor : speed_delta, t };
        post_debug_line(m, sink, ctx, "PID_SPD_DEBUG", "PID_SPEED: ", m->cfg.speed_factor != 0 ? fct : dlt, v, 5);
    }
    if (!(t > 0)) return;
    if (m->cfg.debug[0]) {
        post_debug_sat(m, sink, ctx, "PID_MAX_SAT_HDG_DEBUG", "", &m->yaw);
        static const char *const nm[4] = { " (Want):", " (Curr):", " (Diff):", " RUDDER:" };
        double want = kelp_sim_angle180(m->des_heading);
        double v[4] = { want, m->heading, kelp_sim_angle180(m->heading - want), r };
        post_debug_line(m, sink, ctx, "PID_HDG_DEBUG", "PID_COURSE: ", nm, v, 4);
    }
    if (m->cfg.debug[2] && m->cfg.depth_control) {
        post_debug_sat(m, sink, ctx, "PID_MAX_SAT_DEP_DEBUG", "Z:", &m->z_to_pitch);
        post_debug_sat(m, sink, ctx, "PID_MAX_SAT_DEP_DEBUG", "P:", &m->pitch);
        static const char *const nm[4] = { " (Want):", " (Curr):", " (Diff):", " ELEVATOR:" };
        double v[4] = { m->des_depth, m->depth, m->depth - m->des_depth, el };
        post_debug_line(m, sink, ctx, "PID_DEP_DEBUG", "PID_DEPTH: ", nm, v, 4);
    }
}

static void post_outputs(kelp_pid_marine *m, kelp_pid_marine_sink sink, void *ctx, double r, double t, double el)
{
    m->rudder_out = r, m->thrust_out = t, m->elevator_out = el;
    out_num(m, sink, ctx, "DESIRED_RUDDER", r);
    out_num(m, sink, ctx, "DESIRED_THRUST", t);
    m->thrust = t;
    if (m->cfg.depth_control) out_num(m, sink, ctx, "DESIRED_ELEVATOR", el);
    m->allstop_posted = false;
}

/* PIDEngine::checkForStaleness: one PID_STALE per input older than its threshold, with its age
 * to 3 decimals (trailing zeros trimmed). @return the inputs found stale (0: none). */
static int stale_inputs(kelp_pid_marine *m, kelp_time now, kelp_pid_marine_sink sink, void *ctx)
{
    static const char *const what[KELP_PID_NSTAMP] = { "DesHdg", "DesSpd", "DesDepth", "NavHdg",
                                                       "NavSpd", "NavDep",  "NavPitch" };
    static const int order[KELP_PID_NSTAMP] = { 0, 1, 3, 4, 2, 5, 6 };
    int n = 0;
    for (int j = 0; j < KELP_PID_NSTAMP; j++) {
        int i = order[j];
        if (i == 2 && !m->cfg.depth_control) break;
        double age = now - m->stamp[i];
        if (age <= (i == 0 || i == 1 || i == 2 ? m->cfg.tardy_helm : m->cfg.tardy_nav)) continue;
        int len = kelp_util_snprintf(m->work, sizeof m->work, "Stale %s:", what[i]);
        if (len > 0 && (size_t)len < sizeof m->work &&
            kelp_util_fmt_fixed(m->work + len, sizeof m->work - (size_t)len, age, 3, true) >= 0)
            sink(ctx, "PID_STALE", true, m->work, 0);
        n++;
        if (i <= 2) m->tardy_helm_n++;
        else m->tardy_nav_n++;
    }
    return n;
}

void kelp_pid_marine_iterate(kelp_pid_marine *m, kelp_time now, kelp_pid_marine_sink sink, void *ctx)
{
    if (!kelp_util_time_ok(now)) return; /* the time step rule: no NaN reaches an actuator */
    double step = kelp_util_clock_step(&m->clock, now, KELP_TIME_STEP_MAX);
    if (step != 0.0) {
        /* a clock step (back, or forward beyond KELP_TIME_STEP_MAX: not the nav timeout, which a
         * warped mission's iterations may exceed) is not a dt: each loop's previous run moves
         * with it, so the next run sees dt 0 (its previous output) */
        m->yaw.t_old += step;
        m->speed.t_old += step;
        m->z_to_pitch.t_old += step;
        m->pitch.t_old += step;
        m->bias_t0 += step;
    }
    /* mail stamped before a backward step is not from the future: it counts from now */
    if (m->last_helm > now) m->last_helm = now;
    if (m->last_nav > now) m->last_nav = now;
    m->iterations++;
    if (m->say_control) sink(ctx, "PID_HAS_CONTROL", true, m->say_control > 0 ? "true" : "false", 0);
    m->say_control = 0;
    bool waiting = m->stamp[0] < 0 || m->stamp[1] < 0 || m->stamp[3] < 0 || m->stamp[4] < 0 ||
                   (m->cfg.depth_control && (m->stamp[2] < 0 || m->stamp[5] < 0 || m->stamp[6] < 0));
    if (!m->has_control) {
        /* PIDEngine::setDesiredValues runs at every iteration, control or not: once each input
         * has come, a stale one is posted (24.8 before DEPLOY and after the helm's last
         * decision) */
        if (!waiting) (void)stale_inputs(m, now, sink, ctx);
        if (m->allstop_posted) return;
        out_num(m, sink, ctx, "DESIRED_RUDDER", 0);
        out_num(m, sink, ctx, "DESIRED_THRUST", 0);
        if (m->cfg.depth_control) out_num(m, sink, ctx, "DESIRED_ELEVATOR", 0);
        m->allstop_posted = true;
        return;
    }
    /* PIDEngine::setDesiredValues: all zero until each input has come once, and while one is
     * stale */
    if (waiting) {
        m->paused = true;
        post_outputs(m, sink, ctx, 0, 0, 0);
        return;
    }
    /* a stale input takes control away as an override does (PIDEngine::hasControl): the zeros
     * once (MarinePID::postPengineResults), then nothing until the inputs are fresh again */
    if (stale_inputs(m, now, sink, ctx) > 0) {
        m->paused = true;
        m->thrust = 0;
        if (m->allstop_posted) return;
        post_outputs(m, sink, ctx, 0, 0, 0);
        m->allstop_posted = true;
        return;
    }
    double r = 0, t = 0, el = 0, speed_delta = 0;
    if (m->cfg.speed_factor != 0) {
        t = m->des_speed * m->cfg.speed_factor;
    } else {
        if (kelp_pid_run(&m->speed, m->des_speed - m->speed_now, now, &speed_delta) < 0) return;
        t = m->thrust + speed_delta;
    }
    if (t < KELP_PID_MIN_THRUST) t = 0;
    if (t > m->cfg.max_thrust) t = m->cfg.max_thrust;
    /* the heading and depth loops run only with thrust: their first run after a stop is a
     * ScalarPID first run (no derivative), so a new DESIRED_HEADING gives no kick */
    if (t > 0) {
        double e = kelp_sim_angle180(m->heading - kelp_sim_angle180(m->des_heading));
        if (kelp_pid_run(&m->yaw, e, now, &r) < 0) return;
        r = -r;
        if (m->cfg.sim_instability > 0) {
            double d = now - m->bias_t0;
            if (d > BIAS_PERIOD) d = 0, m->bias_t0 = now, m->bias_side = -m->bias_side;
            r += m->bias_side * (d / BIAS_PERIOD) * m->cfg.sim_instability;
        }
        if (fabs(r) > m->cfg.max_rudder) r = r < 0 ? -m->cfg.max_rudder : m->cfg.max_rudder;
    }
    if (t > 0 && m->cfg.depth_control) {
        double want_pitch = 0, max_pitch = m->cfg.max_pitch_deg / RAD2DEG;
        if (kelp_pid_run(&m->z_to_pitch, m->depth - m->des_depth, now, &want_pitch) < 0) return;
        if (fabs(want_pitch) > max_pitch) want_pitch = want_pitch < 0 ? -max_pitch : max_pitch;
        if (kelp_pid_run(&m->pitch, m->pitch_now - want_pitch, now, &el) < 0) return;
        el *= RAD2DEG;
        if (fabs(el) > m->cfg.max_elevator) el = el < 0 ? -m->cfg.max_elevator : m->cfg.max_elevator;
    }
    m->paused = false;
    post_outputs(m, sink, ctx, r, t, el);
    post_debug(m, sink, ctx, r, t, el, speed_delta);
}
