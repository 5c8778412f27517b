/* uFldContactRangeSensor's logic (include/kelp/contactrange.h; ufield.md section 11): a
 * vehicle's ping is answered with the range to each other vehicle within reach + reply. */
#include <math.h>
#include <string.h>
#include <kelp/contactrange.h>
#include <kelp/util.h>
#include "field_int.h"
#include "rangesense_int.h"

#define CRS_PING_RADIUS 50.0  /* the Hugo log */
#define CRS_PING_DURATION 6.0
#define CRS_REPLY_RADIUS 40.0
#define CRS_REPLY_DURATION 15.0
#define CRS_PI 3.14159265358979323846

void kelp_contactrange_cfg_default(kelp_contactrange_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->reach.dflt = 100;
    cfg->reply.dflt = 100;
    kelp_rangesense_common_default(&cfg->com);
    cfg->display_pulses = true;
    cfg->echo_falloff = true;     /* 24.8: echoes beyond push + pull are probabilistic */
    cfg->com.ground_truth = true; /* 24.8: true (posted only with noise) */
    rs_copy(cfg->ping_color, sizeof cfg->ping_color, "white", 5);
    rs_copy(cfg->reply_color, sizeof cfg->reply_color, "chartreuse", 10);
}

static int put_word(char *dst, size_t cap, const char *v, size_t n, kelp_diag *d)
{
    if (n == 0 || n >= cap || memchr(v, ',', n) || memchr(v, '=', n)) return kelp_fail(d, KELP_ERR_PARSE, "bad name");
    rs_copy(dst, cap, v, n);
    return 1;
}

/* "45:135,225:315", "315:45" or "360" (the full circle) */
static int set_arcs(kelp_contactrange_cfg *cfg, const char *v, size_t n, kelp_diag *d)
{
    if (kelp_util_strieq_n(v, n, "360")) {
        cfg->narcs = 0;
        return 1;
    }
    size_t pos = 0;
    const char *it;
    size_t il;
    int rc;
    unsigned k = 0;
    double arc[KELP_CRS_MAX_ARCS][2];
    while ((rc = field_next_item(v, n, &pos, ',', &it, &il)) == 1) {
        const char *c = memchr(it, ':', il);
        if (!c || k >= KELP_CRS_MAX_ARCS || kelp_util_parse_finite(it, (size_t)(c - it), &arc[k][0]) < 0 ||
            kelp_util_parse_finite(c + 1, il - (size_t)(c - it) - 1, &arc[k][1]) < 0)
            return kelp_fail(d, KELP_ERR_PARSE, "must be 360 or <left>:<right>[,<left>:<right>...] in degrees");
        k++;
    }
    if (rc < 0 || k == 0) return kelp_fail(d, KELP_ERR_PARSE, "must be 360 or <left>:<right>[,...]");
    memcpy(cfg->arc, arc, sizeof arc);
    cfg->narcs = k;
    return 1;
}

static int set_types(kelp_contactrange_cfg *cfg, const char *v, size_t n, kelp_diag *d)
{
    size_t pos = 0;
    const char *it;
    size_t il;
    int rc;
    while ((rc = field_next_item(v, n, &pos, ',', &it, &il)) == 1) {
        bool dup = false;
        for (unsigned i = 0; i < cfg->ntypes; i++) dup = dup || kelp_util_strieq_n(it, il, cfg->types[i]);
        if (dup) continue;
        if (cfg->ntypes >= KELP_CRS_MAX_TYPES) return kelp_fail(d, KELP_ERR_NOSPACE, "too many types");
        if (put_word(cfg->types[cfg->ntypes], KELP_RSENSE_NAME, it, il, d) < 0) return KELP_ERR_PARSE;
        cfg->ntypes++;
    }
    return rc < 0 ? kelp_fail(d, KELP_ERR_PARSE, "bad list") : 1;
}

int kelp_contactrange_config(kelp_contactrange_cfg *cfg, const char *key, const char *val, kelp_diag *d)
{
    char *v = cfg->ws_val;
    int nv = rs_value(val, v, sizeof cfg->ws_val, d);
    if (nv < 0) return nv;
    size_t n = (size_t)nv, kl = strlen(key);
    if (kelp_util_strieq_n(key, kl, "REACH_DISTANCE") || kelp_util_strieq_n(key, kl, "PUSH_DIST") ||
        kelp_util_strieq_n(key, kl, "PUSH_DISTANCE"))
        return kelp_rangesense_vmap_set(&cfg->reach, v, true, d);
    if (kelp_util_strieq_n(key, kl, "REPLY_DISTANCE") || kelp_util_strieq_n(key, kl, "PULL_DIST") ||
        kelp_util_strieq_n(key, kl, "PULL_DISTANCE"))
        return kelp_rangesense_vmap_set(&cfg->reply, v, true, d);
    if (kelp_util_strieq_n(key, kl, "PING_COLOR")) return put_word(cfg->ping_color, sizeof cfg->ping_color, v, n, d);
    if (kelp_util_strieq_n(key, kl, "REPLY_COLOR") || kelp_util_strieq_n(key, kl, "ECHO_COLOR"))
        return put_word(cfg->reply_color, sizeof cfg->reply_color, v, n, d);
    if (kelp_util_strieq_n(key, kl, "ALLOW_ECHO_TYPES")) return set_types(cfg, v, n, d);
    if (kelp_util_strieq_n(key, kl, "SENSOR_ARC")) return set_arcs(cfg, v, n, d);
    if (kelp_util_strieq_n(key, kl, "DISPLAY_PULSES") || kelp_util_strieq_n(key, kl, "ECHO_FALLOFF")) {
        bool f;
        if (kelp_util_parse_bool(v, n, &f) < 0) return kelp_fail(d, KELP_ERR_PARSE, "must be true or false");
        if (kelp_util_strieq_n(key, kl, "ECHO_FALLOFF")) cfg->echo_falloff = f;
        else cfg->display_pulses = f;
        return 1;
    }
    return kelp_rangesense_common_config(&cfg->com, key, v, d);
}

void kelp_contactrange_init(kelp_contactrange *c, const kelp_contactrange_cfg *cfg, kelp_time now)
{
    memset(c, 0, sizeof *c);
    c->cfg = *cfg;
    c->start = now;
    kelp_rangesense_rand_init(&c->rand, cfg->com.glibc, cfg->com.seed);
}

static const char *const subs[] = { "NODE_REPORT", "NODE_REPORT_LOCAL", "CRS_RANGE_REQUEST" };

const char *kelp_contactrange_subscription(unsigned i)
{
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

static bool type_allowed(const kelp_contactrange *c, const kelp_rangesense_node *t)
{
    if (c->cfg.ntypes == 0) return true;
    for (unsigned i = 0; i < c->cfg.ntypes; i++)
        if (kelp_util_strieq(c->cfg.types[i], t->type)) return true;
    return false;
}

/* the target's bearing relative to R's heading within a sensor arc (none: all around) */
static bool in_arc(const kelp_contactrange *c, const kelp_rangesense_node *r, const kelp_rangesense_node *t)
{
    if (c->cfg.narcs == 0) return true;
    double brg = atan2(t->x - r->x, t->y - r->y) * 180.0 / CRS_PI;
    double rel = fmod(brg - r->hdg, 360.0);
    if (rel < 0) rel += 360.0;
    for (unsigned i = 0; i < c->cfg.narcs; i++) {
        double a = c->cfg.arc[i][0], b = c->cfg.arc[i][1];
        if (a < b ? (rel >= a && rel <= b) : (rel >= a || rel <= b)) return true;
    }
    return false;
}

static void ev(const kelp_contactrange *c, const char *a, const char *b, const char *d, const char *e)
{
    rs_log(c->cfg.com.log, c->cfg.com.log_ctx, a, b, d, e, RS_END);
}

/* whether T hears R's ping (24.8's handleRangeRequest): always with a nolimit, surely within
 * push + pull (strictly), beyond it with probability exp(3 (max - r) / max) (one draw) */
static bool heard(kelp_contactrange *c, double push, double pull, double d)
{
    if (push < 0 || pull < 0) return true;
    double max = push + pull;
    if (max > d) return true;
    if (!c->cfg.echo_falloff) return false;
    double u = kelp_rangesense_unit(&c->rand);
    return max > 0 && u <= exp((max - d) * 3.0 / max); /* max 0: 24.8 divides by it */
}

static int request(kelp_contactrange *c, const char *s, kelp_time now, const kelp_field_sink *out)
{
    char name[KELP_RSENSE_NAME];
    c->requests++;
    if (rs_request_name(s, name, sizeof name) < 0) name[0] = 0; /* 24.8 reads name= only */
    int ri = name[0] ? rs_find(c->node, c->nnodes, name) : -1;
    if (ri < 0) { /* refused, answered by nothing */
        c->unknown++;
        c->denied++;
        c->bad_mail++;
        rs_warn(out, "Failed Range Request: Unknown vehicle[", name, "]", RS_END);
        ev(c, "Failed Range Request: Unknown vehicle[", name, "]", NULL);
        rs_warn(out, "Bad Mail: CRS_RANGE_REQUEST", RS_END);
        return KELP_ERR_NOTFOUND;
    }
    kelp_rangesense_node *r = &c->node[ri];
    r->pings++;
    double elapsed = now - r->clock;
    if (!rs_in_time(r, now, kelp_rangesense_vmap_get(&c->cfg.com.ping_wait, r->name))) { /* ignored: no reset */
        char e[64];
        size_t n = 0;
        (void)field_put_fixed(e, sizeof e, &n, elapsed, 2, false);
        r->denied++;
        c->denied++;
        ev(c, r->name, "  ----))  XXX too frequent. (", e, ")");
        return 1;
    }
    r->accepted++;
    c->accepted++;
    ev(c, r->name, "  ----))  ", NULL, NULL);
    r->clock = now;
    r->pinged = true;
    char label[KELP_RSENSE_NAME + 8];
    if (c->cfg.display_pulses) {
        kelp_util_snprintf(label, sizeof label, "%s_ping", r->name);
        rs_pulse(out, r->x, r->y, CRS_PING_RADIUS, CRS_PING_DURATION, label, c->cfg.ping_color, now, c->ws_post);
    }
    double reach = kelp_rangesense_vmap_get(&c->cfg.reach, r->name);
    for (unsigned ti = 0; ti < c->nnodes; ti++) {
        kelp_rangesense_node *t = &c->node[ti];
        if ((int)ti == ri || !type_allowed(c, t)) continue;
        double d = hypot(t->x - r->x, t->y - r->y);
        bool h = heard(c, reach, kelp_rangesense_vmap_get(&c->cfg.reply, t->name), d);
        if (!h || !in_arc(c, r, t)) {
            r->too_far++;
            c->too_far++;
            continue;
        }
        r->heard++;
        t->echoes_sent++;
        char ru[KELP_RSENSE_NAME], tu[KELP_RSENSE_NAME];
        rs_copy(ru, sizeof ru, r->name, strlen(r->name));
        rs_copy(tu, sizeof tu, t->name, strlen(t->name));
        rs_upper(ru);
        rs_upper(tu);
        ev(c, ru, "  <--   ", tu, NULL);
        double noisy = kelp_rangesense_noisy(&c->rand, &c->cfg.com.noise, d);
        rs_post_report(out, "CRS", false, c->cfg.com.report_vars, r->name, noisy, "target", t->name, NULL, now, c->ws_post);
        if (c->cfg.com.noise.alg != KELP_RSENSE_NOISE_NONE && c->cfg.com.ground_truth)
            rs_post_report(out, "CRS", true, c->cfg.com.report_vars, r->name, d, "target", t->name, NULL, now, c->ws_post);
        c->reports++;
        if (c->cfg.display_pulses) {
            kelp_util_snprintf(label, sizeof label, "%s_echo", t->name);
            rs_pulse(out, t->x, t->y, CRS_REPLY_RADIUS, CRS_REPLY_DURATION, label, c->cfg.reply_color, now, c->ws_post);
        }
    }
    return 1;
}

int kelp_contactrange_mail(kelp_contactrange *c, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out)
{
    bool nr = strcmp(var, "NODE_REPORT") == 0 || strcmp(var, "NODE_REPORT_LOCAL") == 0;
    bool rq = strcmp(var, "CRS_RANGE_REQUEST") == 0;
    if (!nr && !rq) return 0;
    /* the time step rule: no time refused; a step back moves the ping-wait clocks with it */
    if (!kelp_util_time_ok(now)) return KELP_ERR_ARG;
    double back = kelp_util_clock_back(&c->clk, now);
    if (back > 0) {
        kelp_rangesense_nodes_back(c->node, c->nnodes, back);
        c->start -= back;
    }
    if (!is_string || !sval) {
        c->bad_mail++;
        rs_warn(out, var, " must be a string", RS_END);
        return KELP_ERR_PARSE;
    }
    if (rq) return request(c, sval, now, out);
    int idx;
    bool first;
    kelp_diag_clear(&c->diag);
    int rc = rs_node_report(c->node, &c->nnodes, sval, &c->cfg.com.geo, c->cfg.com.have_geo, NULL, c->start, &idx,
                            &first, &c->diag);
    if (rc < 0) {
        c->bad_mail++;
        rs_warn(out, "Bad Mail: ", var, " ", kelp_diag_text(&c->diag), RS_END);
        return rc;
    }
    c->node_reports++;
    (void)idx, (void)first;
    return 1;
}

static void put_map(char *buf, size_t cap, size_t *n, const char *title, const kelp_rangesense_vmap *m, const char *what)
{
    field_putf(buf, cap, n, "%s\n", title);
    for (unsigned i = 0; i < m->n; i++) {
        field_putf(buf, cap, n, "  VName: %s %s: ", m->name[i], what);
        if (m->v[i] < 0) (void)field_put_str(buf, cap, n, "nolimit");
        else (void)field_put_fixed(buf, cap, n, m->v[i], 2, true);
        (void)field_put_str(buf, cap, n, "\n");
    }
}

static void put_dist(char *buf, size_t cap, size_t *n, const char *title, double v)
{
    (void)field_put_str(buf, cap, n, title);
    if (v < 0) (void)field_put_str(buf, cap, n, "nolimit");
    else (void)field_put_fixed(buf, cap, n, v, 2, true);
    (void)field_put_str(buf, cap, n, "\n");
}

int kelp_contactrange_summary(const kelp_contactrange *c, char *buf, size_t cap)
{
    size_t n = 0;
    if (!cap) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    const kelp_rangesense_common *k = &c->cfg.com;
    static const char *const alg[] = { "none", "uniform", "gaussian" };
    field_putf(buf, cap, &n, "Acoustic Sonar Simulator Model:\n-----\n");
    put_dist(buf, cap, &n, "Default Reach Distance: ", c->cfg.reach.dflt);
    put_dist(buf, cap, &n, "Default Reply Distance: ", c->cfg.reply.dflt);
    put_dist(buf, cap, &n, "Default Ping Wait: ", k->ping_wait.dflt);
    field_putf(buf, cap, &n, "Random Noise Algorithm: %s\n", alg[k->noise.alg]);
    put_dist(buf, cap, &n, "Random Noise Uniform Pct: ", k->noise.pct);
    put_dist(buf, cap, &n, "Random Noise Gaussian Sigma: ", k->noise.sigma);
    field_putf(buf, cap, &n, "Ping Color: %s\nReply Color: %s\nGround Truth Reporting: %s\n", c->cfg.ping_color,
               c->cfg.reply_color, k->ground_truth ? "true" : "false");
    put_map(buf, cap, &n, "ReachMap:", &c->cfg.reach, "Dist");
    put_map(buf, cap, &n, "ReplyMap:", &c->cfg.reply, "Dist");
    put_map(buf, cap, &n, "PingWaitMap:", &k->ping_wait, "PingWait");
    field_putf(buf, cap, &n, "Contact Records: %u\n", c->nnodes);
    field_putf(buf, cap, &n, "Requests: %lu (accepted %lu, denied %lu), range reports: %lu, random draws: %lu\n",
               c->requests, c->accepted, c->denied, c->reports, c->rand.draws);
    return n + 1 >= cap ? KELP_ERR_NOSPACE : KELP_OK;
}

/* ------------------------------------------------------------------ the AppCast */

/* ostream's << double for the settings: up to 6 decimals, trailing zeros dropped */
static void put_g(char *buf, size_t cap, size_t *n, bool *full, const char *label, double v)
{
    char t[48];
    size_t k = 0;
    if (field_put_fixed(t, sizeof t, &k, v, 6, true) < 0) t[0] = 0;
    broker_put(buf, cap, n, full, "%s%s\n", label, t);
}

static const char *crs_cell(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap)
{
    static const char *const h0[] = { "", "Ping", "Push", "Pull", "Pings", "Echos", "Too", "Too", "Echos", "Pos" };
    static const char *const h1[] = { "VName", "Wait", "Dist", "Dist", "Gen'd", "Rec'd", "Freq", "Far", "Sent", "" };
    if (row == 0) return h0[col];
    if (row == 1) return h1[col];
    const kelp_contactrange *c = ctx;
    const kelp_rangesense_node *v = &c->node[row - 2];
    size_t k = 0;
    double dv;
    unsigned long uv;
    switch (col) {
    case 0: return v->name;
    case 1: dv = kelp_rangesense_vmap_get(&c->cfg.com.ping_wait, v->name); break;
    case 2: dv = kelp_rangesense_vmap_get(&c->cfg.reach, v->name); break;
    case 3: dv = kelp_rangesense_vmap_get(&c->cfg.reply, v->name); break;
    case 4: uv = v->pings; goto count;
    case 5: uv = v->heard; goto count;
    case 6: uv = v->denied; goto count;
    case 7: uv = v->too_far; goto count;
    case 8: uv = v->echoes_sent; goto count;
    default:
        field_putf(tmp, cap, &k, "%.1f,%.1f", v->x, v->y);
        return tmp;
    }
    if (col > 1 && dv < 0) return "inf";
    if (field_put_fixed(tmp, cap, &k, dv, 1, true) < 0) return "?";
    return tmp;
count:
    kelp_util_snprintf(tmp, cap, "%lu", uv);
    return tmp;
}

int kelp_contactrange_report(const kelp_contactrange *c, char *buf, size_t cap)
{
    size_t n = 0;
    bool full = false;
    if (!cap) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    const kelp_rangesense_common *k = &c->cfg.com;
    static const char *const alg[] = { "", "uniform", "gaussian" };
    put_g(buf, cap, &n, &full, "Default Ping Wait:        ", k->ping_wait.dflt);
    broker_put(buf, cap, &n, &full, "Random Noise Algorithm:   %s\n", alg[k->noise.alg]);
    put_g(buf, cap, &n, &full, "Random Noise Uniform Pct: ", k->noise.pct);
    put_g(buf, cap, &n, &full, "Gaussian Noise:           ", k->noise.sigma);
    broker_put(buf, cap, &n, &full, "Ping Color:               %s\nEcho Color:               %s\n", c->cfg.ping_color,
               c->cfg.reply_color);
    broker_put(buf, cap, &n, &full, "Ground Truth Reporting:   %s\nIgnore Group:             \n",
               k->ground_truth ? "true" : "false");
    /* 24.8 never counts its node reports (always 0): kelp counts them (docs/CONFORMANCE.md) */
    broker_put(buf, cap, &n, &full, "Total Node Reports:       %lu\n\nVehicles(%u):\n", c->node_reports, c->nnodes);
    field_actable(buf, cap, &n, &full, 10, c->nnodes + 2, 2, 2, 0, crs_cell, c);
    broker_put(buf, cap, &n, &full, "\n");
    return full ? KELP_ERR_NOSPACE : KELP_OK;
}
