/* uFldBeaconRangeSensor's logic (include/kelp/beaconrange.h; ufield.md section 10): fixed
 * beacons answer a vehicle's range request, or report on their own schedule, to every
 * vehicle within their report range, with optional noise. */
#include <math.h>
#include <string.h>
#include <kelp/beaconrange.h>
#include <kelp/kv.h>
#include <kelp/util.h>
#include "field_int.h"
#include "rangesense_int.h"

#define BRS_REQ_RADIUS 50.0   /* the request pulse at the vehicle (the Indigo log) */
#define BRS_REQ_DURATION 6.0
#define BRS_REPLY_RADIUS 40.0 /* a beacon's pulse */
#define BRS_REPLY_DURATION 15.0

void kelp_field_brs_cfg_default(kelp_field_brs_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    kelp_brs_beacon *d = &cfg->dflt;
    rs_copy(d->shape, sizeof d->shape, "circle", 6);
    rs_copy(d->color, sizeof d->color, "orange", 6); /* A50 */
    d->width = 4;
    d->freq_lo = d->freq_hi = -1; /* never */
    d->push = 100;                /* DEFAULT_BEACON_REPORT_RANGE */
    d->pull = 0;
    d->next = -1;
    cfg->reach.dflt = 100;        /* A61 */
    cfg->node_pull.dflt = 0;
    kelp_rsense_common_default(&cfg->com);
    cfg->payments = KELP_BRS_UPON_ACCEPT; /* A51 */
}

/* "never", "<s>" or "<a>:<b>"; a period <= 0 is never (A84) */
static int parse_freq(const char *v, size_t n, double *lo, double *hi)
{
    if (kelp_strieq_n(v, n, "never")) {
        *lo = *hi = -1;
        return KELP_OK;
    }
    const char *c = memchr(v, ':', n);
    double a, b;
    if (!c) {
        if (kelp_parse_double(v, n, &a) < 0 || !isfinite(a)) return KELP_ERR_PARSE;
        b = a;
    } else if (kelp_parse_double(v, (size_t)(c - v), &a) < 0 || kelp_parse_double(c + 1, n - (size_t)(c - v) - 1, &b) < 0 ||
               !isfinite(a) || !isfinite(b) || a > b) {
        return KELP_ERR_PARSE;
    }
    if (a < 0) return KELP_ERR_PARSE;
    if (b <= 0) a = b = -1;
    *lo = a;
    *hi = b;
    return KELP_OK;
}

static int parse_dist(const char *v, size_t n, double *out)
{
    if (kelp_strieq_n(v, n, "nolimit") || kelp_strieq_n(v, n, "unlimited")) {
        *out = -1;
        return KELP_OK;
    }
    double d;
    if (kelp_parse_double(v, n, &d) < 0 || !isfinite(d)) return KELP_ERR_PARSE;
    *out = d;
    return KELP_OK;
}

static int put_text(char *dst, size_t cap, const char *v, size_t n)
{
    if (n == 0 || n >= cap || memchr(v, ',', n) || memchr(v, '=', n)) return KELP_ERR_PARSE;
    rs_copy(dst, cap, v, n);
    return KELP_OK;
}

/* one beacon property (BEACON pairs and DEFAULT_BEACON_*). @return 1 taken, 2 taken with a
 * warning, 0 unknown key, <0 bad value */
static int beacon_prop(kelp_brs_beacon *b, const char *k, size_t kl, const char *v, size_t vl, bool *have_xy,
                       kelp_diag *d)
{
    double dv;
    if (kelp_strieq_n(k, kl, "x") || kelp_strieq_n(k, kl, "y")) {
        if (kelp_parse_double(v, vl, &dv) < 0 || !isfinite(dv)) return kelp_fail(d, KELP_ERR_PARSE, "x and y must be numbers");
        if (*k == 'x' || *k == 'X') b->x = dv, have_xy[0] = true;
        else b->y = dv, have_xy[1] = true;
        return 1;
    }
    if (kelp_strieq_n(k, kl, "freq")) {
        if (parse_freq(v, vl, &b->freq_lo, &b->freq_hi) < 0)
            return kelp_fail(d, KELP_ERR_PARSE, "freq must be never, <secs> or <a>:<b> with 0 <= a <= b");
        b->freq_set = true;
        return 1;
    }
    if (kelp_strieq_n(k, kl, "report_range") || kelp_strieq_n(k, kl, "push_dist")) {
        if (parse_dist(v, vl, &b->push) < 0) return kelp_fail(d, KELP_ERR_PARSE, "report_range must be a number or nolimit");
        return 1;
    }
    if (kelp_strieq_n(k, kl, "pull_dist")) {
        if (parse_dist(v, vl, &b->pull) < 0) return kelp_fail(d, KELP_ERR_PARSE, "pull_dist must be a number or nolimit");
        return 1;
    }
    if (kelp_strieq_n(k, kl, "width")) {
        if (kelp_parse_double(v, vl, &dv) < 0 || !isfinite(dv) || dv < 0)
            return kelp_fail(d, KELP_ERR_PARSE, "width must be a number >= 0");
        b->width = dv;
        return 1;
    }
    if (kelp_strieq_n(k, kl, "label")) {
        if (put_text(b->label, sizeof b->label, v, vl) < 0) return kelp_fail(d, KELP_ERR_PARSE, "bad label");
        return 1;
    }
    if (kelp_strieq_n(k, kl, "color")) {
        if (put_text(b->color, sizeof b->color, v, vl) < 0) return kelp_fail(d, KELP_ERR_PARSE, "bad color");
        return 1;
    }
    if (kelp_strieq_n(k, kl, "shape") || kelp_strieq_n(k, kl, "type")) {
        if (put_text(b->shape, sizeof b->shape, v, vl) < 0) return kelp_fail(d, KELP_ERR_PARSE, "bad shape");
        return 1;
    }
    if (kelp_strieq_n(k, kl, "query_range")) { /* A52: listed, never described */
        return 2; /* A52: the caller warns KELP_BRS_WARN_QUERY_RANGE */
    }
    return 0;
}

/* parse a BEACON line onto b (a copy of the defaults). @return 1, 2 (warning), <0 */
static int parse_beacon(kelp_brs_beacon *b, const char *s, kelp_diag *d)
{
    size_t pos = 0;
    const char *k, *v;
    size_t kl, vl;
    int rc, res = 1;
    bool have_xy[2] = { false, false };
    b->label[0] = 0;
    b->freq_set = false;
    while ((rc = kelp_kv_next(s, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        int r = beacon_prop(b, k, kl, v, vl, have_xy, d);
        if (r < 0) return r;
        if (r == 0) return kelp_fail(d, KELP_ERR_PARSE, "unknown beacon property (x, y, label, freq, shape, width, color, report_range, "
                                  "push_dist, pull_dist)");
        if (r == 2) res = 2;
    }
    if (rc < 0) return kelp_fail(d, KELP_ERR_PARSE, "expected key=value pairs");
    if (!have_xy[0] || !have_xy[1]) return kelp_fail(d, KELP_ERR_PARSE, "a beacon needs x and y");
    return res;
}

int kelp_field_brs_config(kelp_field_brs_cfg *cfg, const char *key, const char *val, kelp_diag *d)
{
    char *v = cfg->ws_val;
    int nv = rs_value(val, v, sizeof cfg->ws_val, d);
    if (nv < 0) return nv;
    size_t n = (size_t)nv, kl = strlen(key);
    bool have_xy[2];
    if (kelp_strieq_n(key, kl, "BEACON")) {
        kelp_brs_beacon t = cfg->dflt;
        int rc = parse_beacon(&t, v, d);
        if (rc < 0) return rc;
        if (cfg->nspec >= KELP_BRS_MAX_BEACONS) return kelp_fail(d, KELP_ERR_NOSPACE, "too many BEACON lines");
        memcpy(cfg->spec[cfg->nspec++], v, n + 1);
        return rc;
    }
    static const char *const dflt_keys[][2] = {
        { "DEFAULT_BEACON_FREQ", "freq" },          { "DEFAULT_BEACON_REPORT_RANGE", "report_range" },
        { "DEFAULT_BEACON_PUSH_DIST", "push_dist" }, { "DEFAULT_BEACON_PULL_DIST", "pull_dist" },
        { "DEFAULT_BEACON_WIDTH", "width" },        { "DEFAULT_BEACON_COLOR", "color" },
        { "DEFAULT BEACON_COLOR", "color" },        /* 24.8's --example spells it so */
        { "DEFAULT_BEACON_SHAPE", "shape" },
    };
    for (size_t i = 0; i < sizeof dflt_keys / sizeof dflt_keys[0]; i++)
        if (kelp_strieq_n(key, kl, dflt_keys[i][0])) {
            int rc = beacon_prop(&cfg->dflt, dflt_keys[i][1], strlen(dflt_keys[i][1]), v, n, have_xy, d);
            return rc < 0 ? rc : 1;
        }
    if (kelp_strieq_n(key, kl, "REACH_DISTANCE") || kelp_strieq_n(key, kl, "NODE_PUSH_DIST"))
        return kelp_rsense_vmap_set(&cfg->reach, v, true, d);
    if (kelp_strieq_n(key, kl, "NODE_PULL_DIST")) return kelp_rsense_vmap_set(&cfg->node_pull, v, true, d);
    if (kelp_strieq_n(key, kl, "PING_PAYMENTS")) {
        if (kelp_strieq_n(v, n, "upon_accept") || kelp_strieq_n(v, n, "upon_receipt")) cfg->payments = KELP_BRS_UPON_ACCEPT;
        else if (kelp_strieq_n(v, n, "upon_request")) cfg->payments = KELP_BRS_UPON_REQUEST;
        else if (kelp_strieq_n(v, n, "upon_response")) cfg->payments = KELP_BRS_UPON_RESPONSE;
        else return kelp_fail(d, KELP_ERR_PARSE, "must be upon_accept, upon_request or upon_response");
        return 1;
    }
    if (kelp_strieq_n(key, kl, "REPORT_XY")) {
        if (kelp_parse_bool(v, n, &cfg->report_xy) < 0) return kelp_fail(d, KELP_ERR_PARSE, "must be true or false");
        return 1;
    }
    if (kelp_strieq_n(key, kl, "BEACON_ORDER")) {
        if (kelp_strieq_n(v, n, "config")) cfg->config_order = true;
        else if (kelp_strieq_n(v, n, "reverse")) cfg->config_order = false;
        else return kelp_fail(d, KELP_ERR_PARSE, "must be reverse or config");
        return 1;
    }
    return kelp_rsense_common_config(&cfg->com, key, v, d);
}

int kelp_field_brs_find(const kelp_field_brs *b, const char *label)
{
    for (unsigned i = 0; i < b->nbeacons; i++)
        if (strcmp(b->beacon[i].label, label) == 0) return (int)i;
    return -1;
}

int kelp_field_brs_init(kelp_field_brs *b, const kelp_field_brs_cfg *cfg, kelp_time now, kelp_diag *d)
{
    memset(b, 0, sizeof *b);
    b->cfg = *cfg;
    b->start = now;
    kelp_rsense_rand_init(&b->rand, cfg->com.glibc, cfg->com.seed);
    /* 24.8 draws an interval when a freq is configured: the default's line, then each beacon's */
    if (cfg->dflt.freq_set && cfg->dflt.freq_lo >= 0) (void)kelp_rsense_interval(&b->rand, 0, 1);
    for (unsigned i = 0; i < cfg->nspec; i++) {
        kelp_brs_beacon t = cfg->dflt;
        if (parse_beacon(&t, cfg->spec[i], d) < 0) return KELP_ERR_PARSE;
        if (t.freq_set && t.freq_lo >= 0) (void)kelp_rsense_interval(&b->rand, 0, 1);
        t.next = -1;
        if (!t.label[0]) kelp_snprintf(t.label, sizeof t.label, "%u", b->nbeacons); /* A42: 0-based index */
        int at = kelp_field_brs_find(b, t.label);
        if (at >= 0) {
            b->beacon[at] = t; /* the same label overwrites */
            continue;
        }
        b->beacon[b->nbeacons++] = t;
    }
    if (!cfg->config_order) /* A58: the seed's listings go 03, 02, 01 */
        for (unsigned i = 0; i < b->nbeacons / 2; i++) {
            kelp_brs_beacon t = b->beacon[i];
            b->beacon[i] = b->beacon[b->nbeacons - 1 - i];
            b->beacon[b->nbeacons - 1 - i] = t;
        }
    return KELP_OK;
}

static const char *const subs[] = { "NODE_REPORT", "NODE_REPORT_LOCAL", "BRS_RANGE_REQUEST" };

const char *kelp_field_brs_subscription(unsigned i)
{
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

static void log_line(const kelp_field_brs *b, const char *a, const char *c, const char *d, const char *e)
{
    if (b->cfg.com.verbose) rs_log(b->cfg.com.log, b->cfg.com.log_ctx, a, c, d, e, RS_END);
}

/* every vehicle within B's report range gets a report. @return reports to `to` (or all) */
static unsigned long broadcast(kelp_field_brs *b, kelp_brs_beacon *bc, kelp_time now, const kelp_field_sink *out, int to,
                               const char *indent)
{
    unsigned long got = 0;
    for (unsigned u = 0; u < b->nnodes; u++) {
        kelp_rsense_node *v = &b->node[u];
        double r = hypot(v->x - bc->x, v->y - bc->y);
        if (!rs_trans(bc->push, kelp_rsense_vmap_get(&b->cfg.node_pull, v->name), r)) continue;
        double noisy = kelp_rsense_noisy(&b->rand, &b->cfg.com.noise, r);
        double xy[2] = { bc->x, bc->y };
        const double *pxy = b->cfg.report_xy ? xy : NULL;
        rs_post_report(out, "BRS", false, b->cfg.com.report_vars, v->name, noisy, "id", bc->label, pxy, now);
        if (b->cfg.com.ground_truth) rs_post_report(out, "BRS", true, b->cfg.com.report_vars, v->name, r, "id", bc->label, pxy, now);
        v->heard++;
        b->reports++;
        if (b->cfg.com.verbose)
            rs_log(b->cfg.com.log, b->cfg.com.log_ctx, indent, "Range report sent from beacon[", bc->label, "] to vehicle[",
                   v->name, "]", RS_END);
        if (to < 0 || (unsigned)to == u) got++;
    }
    return got;
}

static void reset_timer(kelp_field_brs *b, kelp_brs_beacon *bc, kelp_time now)
{
    if (bc->freq_lo < 0) return;
    bc->next = now + kelp_rsense_interval(&b->rand, bc->freq_lo, bc->freq_hi);
}

KELP_NOINLINE static void log_elapsed(kelp_field_brs *b, double elapsed)
{
    char e[64];
    size_t n = 0;
    (void)field_put_fixed(e, sizeof e, &n, elapsed, 5, false);
    log_line(b, "  Elapsed time: ", e, NULL, NULL);
}

static int request(kelp_field_brs *b, const char *s, kelp_time now, const kelp_field_sink *out)
{
    char name[KELP_RSENSE_NAME];
    b->requests++;
    if (rs_request_name(s, name, sizeof name) < 0) {
        b->bad_mail++;
        rs_warn(out, "BRS_RANGE_REQUEST without name=: ", s, RS_END);
        return KELP_ERR_PARSE;
    }
    log_line(b, "Range request received from: ", name, NULL, NULL);
    int i = rs_find(b->node, b->nnodes, name);
    if (i < 0) { /* no node report: nothing to measure from (A, 10.5.15) */
        b->unknown++;
        b->denied++;
        log_line(b, "  Denied: no node report from ", name, NULL, NULL);
        rs_warn(out, "range request from a vehicle with no node report: ", name, RS_END);
        return 1;
    }
    kelp_rsense_node *v = &b->node[i];
    v->pings++;
    double elapsed = now - v->clock;
    if (b->cfg.com.verbose) log_elapsed(b, elapsed);
    if (elapsed < kelp_rsense_vmap_get(&b->cfg.com.ping_wait, v->name)) {
        if (b->cfg.payments == KELP_BRS_UPON_REQUEST) v->clock = now;
        v->denied++;
        b->denied++;
        log_line(b, "  Denied: Range Request exceeds maximum ping frequency.", NULL, NULL, NULL);
        return 1;
    }
    v->accepted++;
    b->accepted++;
    if (b->cfg.payments != KELP_BRS_UPON_RESPONSE) v->clock = now;
    log_line(b, "    Query accepted by uFldBeaconRangeSensor.", NULL, NULL, NULL);
    char *label = b->ws_label;
    kelp_snprintf(label, sizeof b->ws_label, "%s_ping", v->name);
    rs_pulse(out, v->x, v->y, BRS_REQ_RADIUS, BRS_REQ_DURATION, label, "white", now, true);
    double reach = kelp_rsense_vmap_get(&b->cfg.reach, v->name);
    unsigned long got = 0;
    for (unsigned k = 0; k < b->nbeacons; k++) {
        kelp_brs_beacon *bc = &b->beacon[k];
        if (!rs_trans(reach, bc->pull, hypot(v->x - bc->x, v->y - bc->y))) continue;
        bc->heard++;
        bc->replies++;
        got += broadcast(b, bc, now, out, i, "    ");
        char *bl = b->ws_label;
        kelp_snprintf(bl, sizeof b->ws_label, "%s_reply", bc->label);
        rs_pulse(out, bc->x, bc->y, BRS_REPLY_RADIUS, BRS_REPLY_DURATION, bl, "pink", now, true);
        reset_timer(b, bc, now);
    }
    if (b->cfg.payments == KELP_BRS_UPON_RESPONSE && got > 0) v->clock = now;
    return 1;
}

int kelp_field_brs_mail(kelp_field_brs *b, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out)
{
    bool nr = strcmp(var, "NODE_REPORT") == 0 || strcmp(var, "NODE_REPORT_LOCAL") == 0;
    bool rq = strcmp(var, "BRS_RANGE_REQUEST") == 0;
    if (!nr && !rq) return 0;
    if (!is_string || !sval) {
        b->bad_mail++;
        rs_warn(out, var, " must be a string", RS_END);
        return KELP_ERR_PARSE;
    }
    if (rq) return request(b, sval, now, out);
    int idx;
    bool first;
    kelp_diag_clear(&b->diag);
    int rc = rs_node_report(b->node, &b->nnodes, sval, &b->cfg.com.geo, b->cfg.com.have_geo, NULL, b->start, &idx, &first, &b->diag);
    if (rc < 0) {
        b->bad_mail++;
        rs_warn(out, "bad ", var, ": ", kelp_diag_text(&b->diag), RS_END);
        return rc;
    }
    if (first) log_line(b, "Received first NODE_REPORT for: ", b->node[idx].name, NULL, NULL);
    return 1;
}

static void marker(const kelp_brs_beacon *bc, char *buf, size_t cap)
{
    size_t n = 0;
    int rc = field_put_str(buf, cap, &n, "x=");
    if (rc == 0) rc = field_put_fixed(buf, cap, &n, bc->x, 2, true);
    if (rc == 0) rc = field_put_str(buf, cap, &n, ",y=");
    if (rc == 0) rc = field_put_fixed(buf, cap, &n, bc->y, 2, true);
    if (rc == 0) field_putf(buf, cap, &n, ",label=%s,color=%s,type=%s", bc->label, bc->color, bc->shape);
    if (rc == 0 && bc->width > 0) {
        rc = field_put_str(buf, cap, &n, ",width=");
        if (rc == 0) rc = field_put_fixed(buf, cap, &n, bc->width, 2, true);
    }
    if (rc < 0 && cap) buf[0] = 0;
}

/* the first iteration: markers posted, timers drawn (its marker buffer stays off the report
 * path's stack) */
KELP_NOINLINE static void start_beacons(kelp_field_brs *b, const kelp_field_sink *out)
{
    b->started = true;
    for (unsigned k = 0; k < b->nbeacons; k++) {
        char buf[256];
        marker(&b->beacon[k], buf, sizeof buf);
        if (buf[0]) out->publish(out->ctx, "VIEW_MARKER", true, buf, 0);
        reset_timer(b, &b->beacon[k], b->start);
    }
}

unsigned long kelp_field_brs_iterate(kelp_field_brs *b, kelp_time now, const kelp_field_sink *out)
{
    unsigned long before = b->reports;
    if (!b->started) start_beacons(b, out);
    bool said = false;
    for (unsigned k = 0; k < b->nbeacons; k++) {
        kelp_brs_beacon *bc = &b->beacon[k];
        if (bc->freq_lo < 0 || bc->next < 0 || now < bc->next) continue;
        reset_timer(b, bc, now);
        bc->unsol++;
        if (!said) log_line(b, "Unsolicited beacon reports:", NULL, NULL, NULL);
        said = true;
        (void)broadcast(b, bc, now, out, -1, "  ");
        char *bl = b->ws_label;
        kelp_snprintf(bl, sizeof b->ws_label, "%s_reply", bc->label);
        rs_pulse(out, bc->x, bc->y, BRS_REPLY_RADIUS, BRS_REPLY_DURATION, bl, "green", now, true);
    }
    return b->reports - before;
}

int kelp_field_brs_summary(const kelp_field_brs *b, char *buf, size_t cap)
{
    size_t n = 0;
    if (!cap) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    field_putf(buf, cap, &n, "SRS Model - # Beacons: %u\n", b->nbeacons);
    for (unsigned k = 0; k < b->nbeacons; k++) {
        char m[256];
        marker(&b->beacon[k], m, sizeof m);
        field_putf(buf, cap, &n, "  [%u]:%s\n", k, m);
    }
    char w[64];
    size_t wn = 0;
    (void)field_put_fixed(w, sizeof w, &wn, b->cfg.dflt.width, 2, true);
    field_putf(buf, cap, &n, "Default Beacon Color: %s\nDefault Beacon Shape: %s\nDefault Beacon Width: %s\n",
               b->cfg.dflt.color, b->cfg.dflt.shape, w);
    field_putf(buf, cap, &n, "NodeRecords:: %u\n", b->nnodes);
    field_putf(buf, cap, &n, "Requests: %lu (accepted %lu, denied %lu), range reports: %lu, random draws: %lu\n",
               b->requests, b->accepted, b->denied, b->reports, b->rand.draws);
    return n + 1 >= cap ? KELP_ERR_NOSPACE : KELP_OK;
}
