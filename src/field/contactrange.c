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

void kelp_field_crs_cfg_default(kelp_field_crs_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->reach.dflt = 100;
    cfg->reply.dflt = 100;
    kelp_rsense_common_default(&cfg->com);
    cfg->display_pulses = true;
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
static int set_arcs(kelp_field_crs_cfg *cfg, const char *v, size_t n, kelp_diag *d)
{
    if (kelp_strieq_n(v, n, "360")) {
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
        if (!c || k >= KELP_CRS_MAX_ARCS || kelp_parse_finite(it, (size_t)(c - it), &arc[k][0]) < 0 ||
            kelp_parse_finite(c + 1, il - (size_t)(c - it) - 1, &arc[k][1]) < 0)
            return kelp_fail(d, KELP_ERR_PARSE, "must be 360 or <left>:<right>[,<left>:<right>...] in degrees");
        k++;
    }
    if (rc < 0 || k == 0) return kelp_fail(d, KELP_ERR_PARSE, "must be 360 or <left>:<right>[,...]");
    memcpy(cfg->arc, arc, sizeof arc);
    cfg->narcs = k;
    return 1;
}

static int set_types(kelp_field_crs_cfg *cfg, const char *v, size_t n, kelp_diag *d)
{
    size_t pos = 0;
    const char *it;
    size_t il;
    int rc;
    while ((rc = field_next_item(v, n, &pos, ',', &it, &il)) == 1) {
        bool dup = false;
        for (unsigned i = 0; i < cfg->ntypes; i++) dup = dup || kelp_strieq_n(it, il, cfg->types[i]);
        if (dup) continue;
        if (cfg->ntypes >= KELP_CRS_MAX_TYPES) return kelp_fail(d, KELP_ERR_NOSPACE, "too many types");
        if (put_word(cfg->types[cfg->ntypes], KELP_RSENSE_NAME, it, il, d) < 0) return KELP_ERR_PARSE;
        cfg->ntypes++;
    }
    return rc < 0 ? kelp_fail(d, KELP_ERR_PARSE, "bad list") : 1;
}

int kelp_field_crs_config(kelp_field_crs_cfg *cfg, const char *key, const char *val, kelp_diag *d)
{
    char *v = cfg->ws_val;
    int nv = rs_value(val, v, sizeof cfg->ws_val, d);
    if (nv < 0) return nv;
    size_t n = (size_t)nv, kl = strlen(key);
    if (kelp_strieq_n(key, kl, "REACH_DISTANCE") || kelp_strieq_n(key, kl, "PUSH_DIST") ||
        kelp_strieq_n(key, kl, "PUSH_DISTANCE"))
        return kelp_rsense_vmap_set(&cfg->reach, v, true, d);
    if (kelp_strieq_n(key, kl, "REPLY_DISTANCE") || kelp_strieq_n(key, kl, "PULL_DIST") ||
        kelp_strieq_n(key, kl, "PULL_DISTANCE"))
        return kelp_rsense_vmap_set(&cfg->reply, v, true, d);
    if (kelp_strieq_n(key, kl, "PING_COLOR")) return put_word(cfg->ping_color, sizeof cfg->ping_color, v, n, d);
    if (kelp_strieq_n(key, kl, "REPLY_COLOR") || kelp_strieq_n(key, kl, "ECHO_COLOR"))
        return put_word(cfg->reply_color, sizeof cfg->reply_color, v, n, d);
    if (kelp_strieq_n(key, kl, "IGNORE_GROUP")) return put_word(cfg->ignore_group, sizeof cfg->ignore_group, v, n, d);
    if (kelp_strieq_n(key, kl, "ALLOW_ECHO_TYPES")) return set_types(cfg, v, n, d);
    if (kelp_strieq_n(key, kl, "SENSOR_ARC")) return set_arcs(cfg, v, n, d);
    if (kelp_strieq_n(key, kl, "DISPLAY_PULSES") || kelp_strieq_n(key, kl, "ECHO_FALLOFF")) {
        bool f;
        if (kelp_parse_bool(v, n, &f) < 0) return kelp_fail(d, KELP_ERR_PARSE, "must be true or false");
        if (kelp_strieq_n(key, kl, "ECHO_FALLOFF")) cfg->echo_falloff = f;
        else cfg->display_pulses = f;
        return 1;
    }
    return kelp_rsense_common_config(&cfg->com, key, v, d);
}

void kelp_field_crs_init(kelp_field_crs *c, const kelp_field_crs_cfg *cfg, kelp_time now)
{
    memset(c, 0, sizeof *c);
    c->cfg = *cfg;
    c->start = now;
    kelp_rsense_rand_init(&c->rand, cfg->com.glibc, cfg->com.seed);
}

static const char *const subs[] = { "NODE_REPORT", "NODE_REPORT_LOCAL", "CRS_RANGE_REQUEST" };

const char *kelp_field_crs_subscription(unsigned i)
{
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

static bool type_allowed(const kelp_field_crs *c, const kelp_rsense_node *t)
{
    if (c->cfg.ntypes == 0) return true;
    for (unsigned i = 0; i < c->cfg.ntypes; i++)
        if (kelp_strieq(c->cfg.types[i], t->type)) return true;
    return false;
}

/* the target's bearing relative to R's heading within a sensor arc (none: all around) */
static bool in_arc(const kelp_field_crs *c, const kelp_rsense_node *r, const kelp_rsense_node *t)
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

static void say(const kelp_field_crs *c, const char *a, const char *b, const char *d, const char *e)
{
    if (c->cfg.com.verbose) rs_log(c->cfg.com.log, c->cfg.com.log_ctx, a, b, d, e, RS_END);
}

static int request(kelp_field_crs *c, const char *s, kelp_time now, const kelp_field_sink *out)
{
    char name[KELP_RSENSE_NAME];
    c->requests++;
    if (rs_request_name(s, name, sizeof name) < 0) {
        c->bad_mail++;
        rs_warn(out, "CRS_RANGE_REQUEST without name=: ", s, RS_END);
        return KELP_ERR_PARSE;
    }
    say(c, "Range request received from: ", name, NULL, NULL);
    int ri = rs_find(c->node, c->nnodes, name);
    if (ri < 0) { /* 11.5.12: no reports and no pulse */
        c->unknown++;
        c->denied++;
        say(c, "  Denied: no node report from ", name, NULL, NULL);
        rs_warn(out, "range request from a vehicle with no node report: ", name, RS_END);
        return 1;
    }
    kelp_rsense_node *r = &c->node[ri];
    r->pings++;
    double elapsed = now - r->clock;
    if (c->cfg.com.verbose) {
        char e[64];
        size_t n = 0;
        (void)field_put_fixed(e, sizeof e, &n, elapsed, 5, false);
        say(c, "  Elapsed time: ", e, NULL, NULL);
    }
    if (elapsed < kelp_rsense_vmap_get(&c->cfg.com.ping_wait, r->name)) { /* ignored: no reset */
        r->denied++;
        c->denied++;
        say(c, "  Denied: Range Request exceeds maximum ping frequency.", NULL, NULL, NULL);
        return 1;
    }
    r->accepted++;
    c->accepted++;
    r->clock = now;
    say(c, "  Range Request accepted by uFldContactRangeSensor.", NULL, NULL, NULL);
    say(c, "  Range Request resets the clock for vehicle.", NULL, NULL, NULL);
    char label[KELP_RSENSE_NAME + 8];
    if (c->cfg.display_pulses) {
        kelp_snprintf(label, sizeof label, "%s_ping", r->name);
        rs_pulse(out, r->x, r->y, CRS_PING_RADIUS, CRS_PING_DURATION, label, c->cfg.ping_color, now, true);
    }
    double reach = kelp_rsense_vmap_get(&c->cfg.reach, r->name);
    for (unsigned ti = 0; ti < c->nnodes; ti++) {
        const kelp_rsense_node *t = &c->node[ti];
        if ((int)ti == ri || !type_allowed(c, t)) continue;
        double d = hypot(t->x - r->x, t->y - r->y);
        double reply = kelp_rsense_vmap_get(&c->cfg.reply, t->name);
        bool heard = rs_trans(reach, reply, d); /* A65 */
        if (!heard && c->cfg.echo_falloff && reach + reply > 0) /* 24.8: exp(3 (max - r) / max) */
            heard = kelp_rsense_unit(&c->rand) <= exp((reach + reply - d) * 3.0 / (reach + reply));
        if (!heard || !in_arc(c, r, t)) {
            c->too_far++;
            continue;
        }
        double noisy = kelp_rsense_noisy(&c->rand, &c->cfg.com.noise, d);
        if (c->cfg.com.verbose)
            rs_log(c->cfg.com.log, c->cfg.com.log_ctx, "  Range Report sent from targ vehicle[", t->name,
                   "] to receiver vehicle[", r->name, "]", RS_END);
        rs_post_report(out, "CRS", false, c->cfg.com.report_vars, r->name, noisy, "target", t->name, NULL, now);
        if (c->cfg.com.ground_truth)
            rs_post_report(out, "CRS", true, c->cfg.com.report_vars, r->name, d, "target", t->name, NULL, now);
        c->reports++;
        r->heard++;
        if (c->cfg.display_pulses) {
            kelp_snprintf(label, sizeof label, "%s_reply", t->name);
            rs_pulse(out, t->x, t->y, CRS_REPLY_RADIUS, CRS_REPLY_DURATION, label, c->cfg.reply_color, now, false);
        }
    }
    return 1;
}

int kelp_field_crs_mail(kelp_field_crs *c, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out)
{
    bool nr = strcmp(var, "NODE_REPORT") == 0 || strcmp(var, "NODE_REPORT_LOCAL") == 0;
    bool rq = strcmp(var, "CRS_RANGE_REQUEST") == 0;
    if (!nr && !rq) return 0;
    if (!is_string || !sval) {
        c->bad_mail++;
        rs_warn(out, var, " must be a string", RS_END);
        return KELP_ERR_PARSE;
    }
    if (rq) return request(c, sval, now, out);
    int idx;
    bool first;
    kelp_diag_clear(&c->diag);
    int rc = rs_node_report(c->node, &c->nnodes, sval, &c->cfg.com.geo, c->cfg.com.have_geo, c->cfg.ignore_group,
                            c->start, &idx, &first, &c->diag);
    if (rc < 0) {
        c->bad_mail++;
        rs_warn(out, "bad ", var, ": ", kelp_diag_text(&c->diag), RS_END);
        return rc;
    }
    if (rc > 0 && first) say(c, "Received first NODE_REPORT for: ", c->node[idx].name, NULL, NULL);
    return 1;
}

static void put_map(char *buf, size_t cap, size_t *n, const char *title, const kelp_rsense_vmap *m, const char *what)
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

int kelp_field_crs_summary(const kelp_field_crs *c, char *buf, size_t cap)
{
    size_t n = 0;
    if (!cap) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    const kelp_rsense_common *k = &c->cfg.com;
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
