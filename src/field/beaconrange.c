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

#define BRS_REQ_RADIUS 40.0   /* the request pulse at the vehicle (24.8's handleRangeRequest) */
#define BRS_REQ_DURATION 6.0
#define BRS_REPLY_RADIUS 40.0 /* a beacon's pulse */
#define BRS_REPLY_DURATION 15.0

void kelp_beaconrange_cfg_default(kelp_beaconrange_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    kelp_brs_beacon *d = &cfg->dflt;
    rs_copy(d->shape, sizeof d->shape, "circle", 6);
    rs_copy(d->color, sizeof d->color, "orange", 6); /* A50 */
    d->width = 4;
    d->freq_lo = d->freq_hi = -1; /* never */
    d->push = 50;                 /* 24.8's BRS_App(): the default beacon's push and pull 50 */
    d->pull = 50;
    d->ts = 0;
    d->cur = -1;
    cfg->reach.dflt = 100;        /* node push 100, pull 100 (24.8) */
    cfg->node_pull.dflt = 100;
    kelp_rangesense_common_default(&cfg->com);
    cfg->com.ground_truth = true; /* 24.8: true (posted only with noise) */
    cfg->payments = KELP_BRS_UPON_RESPONSE; /* 24.8's default */
}

/* 24.8's BeaconBuoy refuses "<a>:<b>" when the text a sorts after the text b (it compares the two
 * strings, not the numbers: "6:14" is refused, "5:8" taken); blanks around each are trimmed */
static bool freq_text_refused(const char *v, size_t n)
{
    const char *c = memchr(v, ':', n);
    if (!c) return false;
    size_t la = (size_t)(c - v), lb = n - la - 1;
    const char *a = v, *b = c + 1;
    while (la && (*a == ' ' || *a == '\t')) a++, la--;
    while (la && (a[la - 1] == ' ' || a[la - 1] == '\t')) la--;
    while (lb && (*b == ' ' || *b == '\t')) b++, lb--;
    while (lb && (b[lb - 1] == ' ' || b[lb - 1] == '\t')) lb--;
    int cmp = memcmp(a, b, la < lb ? la : lb);
    return cmp > 0 || (cmp == 0 && la > lb);
}

/* "never", "<s>" or "<a>:<b>"; a period <= 0 is never (A84) */
static int parse_freq(const char *v, size_t n, double *lo, double *hi)
{
    if (kelp_util_strieq_n(v, n, "never")) {
        *lo = *hi = -1;
        return KELP_OK;
    }
    const char *c = memchr(v, ':', n);
    double a, b;
    if (!c) {
        if (kelp_util_parse_double(v, n, &a) < 0 || !isfinite(a)) return KELP_ERR_PARSE;
        b = a;
    } else if (kelp_util_parse_double(v, (size_t)(c - v), &a) < 0 || kelp_util_parse_double(c + 1, n - (size_t)(c - v) - 1, &b) < 0 ||
               !isfinite(a) || !isfinite(b) || a > b) {
        return KELP_ERR_PARSE;
    }
    if (a < 0) return KELP_ERR_PARSE;
    *lo = a;
    *hi = b;
    return KELP_OK;
}

static int parse_dist(const char *v, size_t n, double *out)
{
    if (kelp_util_strieq_n(v, n, "nolimit") || kelp_util_strieq_n(v, n, "unlimited")) {
        *out = -1;
        return KELP_OK;
    }
    double d;
    if (kelp_util_parse_double(v, n, &d) < 0 || !isfinite(d)) return KELP_ERR_PARSE;
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
static int beacon_prop(kelp_brs_beacon *b, const char *k, size_t kl, const char *v, size_t vl, bool *have_xy, bool as248,
                       kelp_diag *d)
{
    double dv;
    if (kelp_util_strieq_n(k, kl, "x") || kelp_util_strieq_n(k, kl, "y")) {
        if (kelp_util_parse_double(v, vl, &dv) < 0 || !isfinite(dv)) return kelp_fail(d, KELP_ERR_PARSE, "x and y must be numbers");
        if (*k == 'x' || *k == 'X') b->x = dv, have_xy[0] = true;
        else b->y = dv, have_xy[1] = true;
        return 1;
    }
    if (kelp_util_strieq_n(k, kl, "freq")) {
        if (as248 && freq_text_refused(v, vl)) return 1; /* 24.8 keeps what it had, silently */
        if (parse_freq(v, vl, &b->freq_lo, &b->freq_hi) < 0)
            return kelp_fail(d, KELP_ERR_PARSE, "freq must be never, <secs> or <a>:<b> with 0 <= a <= b");
        b->freq_set = true;
        return 1;
    }
    if (kelp_util_strieq_n(k, kl, "report_range") || kelp_util_strieq_n(k, kl, "push_dist")) {
        if (parse_dist(v, vl, &b->push) < 0) return kelp_fail(d, KELP_ERR_PARSE, "report_range must be a number or nolimit");
        return 1;
    }
    if (kelp_util_strieq_n(k, kl, "pull_dist")) {
        if (parse_dist(v, vl, &b->pull) < 0) return kelp_fail(d, KELP_ERR_PARSE, "pull_dist must be a number or nolimit");
        return 1;
    }
    if (kelp_util_strieq_n(k, kl, "width")) {
        if (kelp_util_parse_double(v, vl, &dv) < 0 || !isfinite(dv) || dv < 0)
            return kelp_fail(d, KELP_ERR_PARSE, "width must be a number >= 0");
        b->width = dv;
        return 1;
    }
    if (kelp_util_strieq_n(k, kl, "label")) {
        if (put_text(b->label, sizeof b->label, v, vl) < 0) return kelp_fail(d, KELP_ERR_PARSE, "bad label");
        return 1;
    }
    if (kelp_util_strieq_n(k, kl, "color")) {
        if (put_text(b->color, sizeof b->color, v, vl) < 0) return kelp_fail(d, KELP_ERR_PARSE, "bad color");
        return 1;
    }
    if (kelp_util_strieq_n(k, kl, "shape") || kelp_util_strieq_n(k, kl, "type")) {
        if (put_text(b->shape, sizeof b->shape, v, vl) < 0) return kelp_fail(d, KELP_ERR_PARSE, "bad shape");
        return 1;
    }
    if (kelp_util_strieq_n(k, kl, "query_range")) { /* A52: listed, never described */
        return 2; /* A52: the caller warns KELP_BRS_WARN_QUERY_RANGE */
    }
    return 0;
}

/* parse a BEACON line onto b (a copy of the defaults). @return 1, 2 (warning), <0 */
static int parse_beacon(kelp_brs_beacon *b, const char *s, bool as248, kelp_diag *d)
{
    size_t pos = 0;
    const char *k, *v;
    size_t kl, vl;
    int rc, res = 1;
    bool have_xy[2] = { false, false };
    b->label[0] = 0;
    b->freq_set = false;
    while ((rc = kelp_kv_next(s, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        int r = beacon_prop(b, k, kl, v, vl, have_xy, as248, d);
        if (r < 0) return r;
        if (r == 0) return kelp_fail(d, KELP_ERR_PARSE, "unknown beacon property (x, y, label, freq, shape, width, color, report_range, "
                                  "push_dist, pull_dist)");
        if (r == 2) res = 2;
    }
    if (rc < 0) return kelp_fail(d, KELP_ERR_PARSE, "expected key=value pairs");
    if (!have_xy[0] || !have_xy[1]) return kelp_fail(d, KELP_ERR_PARSE, "a beacon needs x and y");
    return res;
}

int kelp_beaconrange_config(kelp_beaconrange_cfg *cfg, const char *key, const char *val, kelp_diag *d)
{
    char *v = cfg->ws_val;
    int nv = rs_value(val, v, sizeof cfg->ws_val, d);
    if (nv < 0) return nv;
    size_t n = (size_t)nv, kl = strlen(key);
    bool have_xy[2];
    if (kelp_util_strieq_n(key, kl, "BEACON")) {
        kelp_brs_beacon t = cfg->dflt;
        int rc = parse_beacon(&t, v, cfg->com.glibc, d);
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
        if (kelp_util_strieq_n(key, kl, dflt_keys[i][0])) {
            /* glibc mode (24.8's behaviour): a refused default freq is an unhandled line */
            if (cfg->com.glibc && i == 0 && freq_text_refused(v, n)) return 0;
            int rc = beacon_prop(&cfg->dflt, dflt_keys[i][1], strlen(dflt_keys[i][1]), v, n, have_xy, false, d);
            return rc < 0 ? rc : 1;
        }
    if (kelp_util_strieq_n(key, kl, "REACH_DISTANCE") || kelp_util_strieq_n(key, kl, "NODE_PUSH_DIST"))
        return kelp_rangesense_vmap_set(&cfg->reach, v, true, d);
    if (kelp_util_strieq_n(key, kl, "NODE_PULL_DIST")) return kelp_rangesense_vmap_set(&cfg->node_pull, v, true, d);
    if (kelp_util_strieq_n(key, kl, "PING_PAYMENTS")) {
        if (kelp_util_strieq_n(v, n, "upon_accept") || kelp_util_strieq_n(v, n, "upon_receipt")) cfg->payments = KELP_BRS_UPON_ACCEPT;
        else if (kelp_util_strieq_n(v, n, "upon_request")) cfg->payments = KELP_BRS_UPON_REQUEST;
        else if (kelp_util_strieq_n(v, n, "upon_response")) cfg->payments = KELP_BRS_UPON_RESPONSE;
        else return kelp_fail(d, KELP_ERR_PARSE, "must be upon_accept, upon_request or upon_response");
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "REPORT_XY")) {
        if (kelp_util_parse_bool(v, n, &cfg->report_xy) < 0) return kelp_fail(d, KELP_ERR_PARSE, "must be true or false");
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "BEACON_ORDER")) {
        if (kelp_util_strieq_n(v, n, "config")) cfg->config_order = true;
        else if (kelp_util_strieq_n(v, n, "reverse")) cfg->config_order = false;
        else return kelp_fail(d, KELP_ERR_PARSE, "must be reverse or config");
        return 1;
    }
    return kelp_rangesense_common_config(&cfg->com, key, v, d);
}

int kelp_beaconrange_find(const kelp_beaconrange *b, const char *label)
{
    for (unsigned i = 0; i < b->nbeacons; i++)
        if (strcmp(b->beacon[i].label, label) == 0) return (int)i;
    return -1;
}

int kelp_beaconrange_init(kelp_beaconrange *b, const kelp_beaconrange_cfg *cfg, kelp_time now, kelp_diag *d)
{
    memset(b, 0, sizeof *b);
    b->cfg = *cfg;
    b->start = now;
    kelp_rangesense_rand_init(&b->rand, cfg->com.glibc, cfg->com.seed);
    /* 24.8 draws an interval when a freq is configured: the default's line, then each beacon's */
    if (cfg->dflt.freq_set && cfg->dflt.freq_lo >= 0) (void)kelp_rangesense_interval(&b->rand, 0, 1);
    for (unsigned i = 0; i < cfg->nspec; i++) {
        kelp_brs_beacon t = cfg->dflt;
        if (parse_beacon(&t, cfg->spec[i], cfg->com.glibc, d) < 0) return KELP_ERR_PARSE;
        if (t.freq_set && t.freq_lo >= 0) (void)kelp_rangesense_interval(&b->rand, 0, 1);
        t.ts = 0;
        if (!t.label[0]) kelp_util_snprintf(t.label, sizeof t.label, "%u", b->nbeacons); /* A42: 0-based index */
        int at = kelp_beaconrange_find(b, t.label);
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

const char *kelp_beaconrange_subscription(unsigned i)
{
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}


/* one range report from beacon bc to vehicle v (24.8's postBeaconRangeReport): the noise is
 * drawn here; the ground truth only with noise and GROUND_TRUTH */
static void brs_report(kelp_beaconrange *b, const kelp_brs_beacon *bc, const kelp_rangesense_node *v, double r, kelp_time now,
                       const kelp_field_sink *out)
{
    const kelp_rangesense_common *c = &b->cfg.com;
    double noisy = kelp_rangesense_noisy(&b->rand, &c->noise, r);
    double xy[2] = { bc->x, bc->y };
    const double *pxy = b->cfg.report_xy ? xy : NULL;
    rs_post_report(out, "BRS", false, c->report_vars, v->name, noisy, "id", bc->label, pxy, now, b->ws_post);
    if (c->noise.alg != KELP_RSENSE_NOISE_NONE && c->ground_truth) {
        /* 24.8 upper-cases its vname for the long form and keeps it for the short GT report */
        char *un = b->ws_label;
        rs_copy(un, sizeof b->ws_label, v->name, strlen(v->name));
        if (c->report_vars == KELP_RSENSE_BOTH) rs_upper(un);
        rs_post_report(out, "BRS", true, c->report_vars, un, r, "id", bc->label, pxy, now, b->ws_post);
    }
    b->reports++;
}

/* the beacon's time stamp (24.8's setTimeStamp: a new period is drawn when it has a freq) */
static void reset_timer(kelp_beaconrange *b, kelp_brs_beacon *bc, kelp_time now)
{
    bc->ts = now;
    if (bc->freq_lo < 0) return;
    bc->cur = kelp_rangesense_interval(&b->rand, bc->freq_lo, bc->freq_hi);
}

static void ev(kelp_beaconrange *b, bool verbose_only, const char *a, const char *c, const char *d, const char *e)
{
    if (!verbose_only || b->cfg.com.verbose) rs_log(b->cfg.com.log, b->cfg.com.log_ctx, a, c, d, e, RS_END);
}

static int request(kelp_beaconrange *b, const char *s, kelp_time now, const kelp_field_sink *out)
{
    char name[KELP_RSENSE_NAME];
    b->requests++;
    /* 24.8 reads name= only; an empty or unknown name is refused and answered by nothing */
    if (rs_request_name(s, name, sizeof name) < 0) name[0] = 0;
    int i = name[0] ? rs_find(b->node, b->nnodes, name) : -1;
    if (i < 0) {
        b->unknown++;
        b->denied++;
        b->bad_mail++;
        rs_warn(out, "Failed Range Request: Unknown vehicle[", name, "]", RS_END);
        ev(b, false, "Failed Range Request: Unknown vehicle[", name, "]", NULL);
        rs_warn(out, "Bad Mail: BRS_RANGE_REQUEST", RS_END);
        return KELP_ERR_NOTFOUND;
    }
    kelp_rangesense_node *v = &b->node[i];
    v->pings++;
    double elapsed = now - v->clock;
    bool allowed = rs_in_time(v, now, kelp_rangesense_vmap_get(&b->cfg.com.ping_wait, v->name));
    if (b->cfg.payments == KELP_BRS_UPON_REQUEST) v->clock = now, v->pinged = true;
    if (!allowed) {
        v->denied++;
        b->denied++;
        rs_warn(out, "Failed Range Req from ", v->name, ": exceeds query freq.", RS_END);
        if (b->cfg.com.verbose) {
            char e[64];
            size_t n = 0;
            (void)field_put_fixed(e, sizeof e, &n, elapsed, 5, false);
            ev(b, true, "Failed Range Req from ", v->name, ": exceeds query frequency.", NULL);
            ev(b, true, "  Elapsed time for ", v->name, ": ", e);
        }
        return 1;
    }
    v->accepted++;
    b->accepted++;
    ev(b, false, "Valid Range Req from ", v->name, ". Checking beacon ranges...", NULL);
    if (b->cfg.payments == KELP_BRS_UPON_ACCEPT) {
        ev(b, true, "  Range Request resets the clock for vehicle ", v->name, NULL, NULL);
        v->clock = now, v->pinged = true;
    }
    char *label = b->ws_label;
    kelp_util_snprintf(label, sizeof b->ws_label, "%s_range_req", v->name);
    rs_pulse(out, v->x, v->y, BRS_REQ_RADIUS, BRS_REQ_DURATION, label, "white", now, b->ws_post);
    double reach = kelp_rangesense_vmap_get(&b->cfg.reach, v->name);
    double pull = kelp_rangesense_vmap_get(&b->cfg.node_pull, v->name);
    for (unsigned k = 0; k < b->nbeacons; k++) {
        kelp_brs_beacon *bc = &b->beacon[k];
        double r = hypot(v->x - bc->x, v->y - bc->y);
        bool replied = false;
        if (rs_trans(reach, bc->pull, r)) {
            bc->heard++;
            ev(b, false, "Beacon[", bc->label, "]  <----  Ping from ", v->name);
            if (rs_trans(bc->push, pull, r)) { /* only the requester hears the reply */
                bc->replies++;
                v->replied++;
                if (b->cfg.payments == KELP_BRS_UPON_RESPONSE) v->clock = now, v->pinged = true;
                ev(b, false, "Beacon[", bc->label, "]    -->  Range Reply to ", v->name);
                brs_report(b, bc, v, r, now, out);
                rs_pulse(out, bc->x, bc->y, BRS_REPLY_RADIUS, BRS_REPLY_DURATION, bc->label, "pink", now, b->ws_post);
                reset_timer(b, bc, now);
                replied = true;
            }
        }
        if (!replied) v->too_far++;
    }
    return 1;
}

/* The time step rule: a `now` that is no time is refused; on a step back the ping-wait clocks,
 * the beacons' time stamps and the start move back with it, so no wait outlasts its period */
static bool brs_clock(kelp_beaconrange *b, kelp_time now)
{
    if (!kelp_util_time_ok(now)) return false;
    double back = kelp_util_clock_back(&b->clk, now);
    if (back > 0) {
        kelp_rangesense_nodes_back(b->node, b->nnodes, back);
        for (unsigned k = 0; k < b->nbeacons; k++) b->beacon[k].ts -= back;
        b->start -= back;
    }
    return true;
}

int kelp_beaconrange_mail(kelp_beaconrange *b, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out)
{
    bool nr = strcmp(var, "NODE_REPORT") == 0 || strcmp(var, "NODE_REPORT_LOCAL") == 0;
    bool rq = strcmp(var, "BRS_RANGE_REQUEST") == 0;
    if (!nr && !rq) return 0;
    if (!brs_clock(b, now)) return KELP_ERR_ARG;
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
        rs_warn(out, "Bad Mail: ", var, " ", kelp_diag_text(&b->diag), RS_END);
        return rc;
    }
    (void)idx, (void)first;
    return 1;
}

static void marker(const kelp_brs_beacon *bc, char *buf, size_t cap)
{
    /* 24.8's postVisuals: an XYMarker with no label: x, y, width, primary_color, type */
    size_t n = 0;
    int rc = field_put_str(buf, cap, &n, "x=");
    if (rc == 0) rc = field_put_fixed(buf, cap, &n, bc->x, 2, true);
    if (rc == 0) rc = field_put_str(buf, cap, &n, ",y=");
    if (rc == 0) rc = field_put_fixed(buf, cap, &n, bc->y, 2, true);
    if (rc == 0 && bc->width > 0) {
        rc = field_put_str(buf, cap, &n, ",width=");
        if (rc == 0) rc = field_put_fixed(buf, cap, &n, bc->width, 2, true);
    }
    if (rc == 0) field_putf(buf, cap, &n, ",primary_color=%s,type=%s", bc->color, bc->shape);
    if (rc < 0 && cap) buf[0] = 0;
}

/* the first iteration: markers posted, timers drawn (its marker buffer stays off the report
 * path's stack) */
KELP_NOINLINE static void start_beacons(kelp_beaconrange *b, const kelp_field_sink *out)
{
    b->started = true;
    for (unsigned k = 0; k < b->nbeacons; k++) {
        char buf[256];
        marker(&b->beacon[k], buf, sizeof buf);
        if (buf[0]) out->publish(out->ctx, "VIEW_MARKER", true, buf, 0);
    }
}

unsigned long kelp_beaconrange_iterate(kelp_beaconrange *b, kelp_time now, const kelp_field_sink *out)
{
    unsigned long before = b->reports;
    if (!brs_clock(b, now)) return 0;
    if (!b->started) { /* 24.8's first iteration stamps every beacon */
        start_beacons(b, out);
        for (unsigned k = 0; k < b->nbeacons; k++) reset_timer(b, &b->beacon[k], now);
    }
    for (unsigned k = 0; k < b->nbeacons; k++) {
        kelp_brs_beacon *bc = &b->beacon[k];
        if (!(bc->freq_lo >= 0 && bc->cur > 0 && now - bc->ts > bc->cur)) continue;
        reset_timer(b, bc, now);
        rs_pulse(out, bc->x, bc->y, BRS_REPLY_RADIUS, BRS_REPLY_DURATION, bc->label, "pink", now, b->ws_post);
        bc->unsol++;
        for (unsigned u = 0; u < b->nnodes; u++) { /* every vehicle in the beacon's reach */
            kelp_rangesense_node *v = &b->node[u];
            double r = hypot(v->x - bc->x, v->y - bc->y);
            if (rs_trans(bc->push, kelp_rangesense_vmap_get(&b->cfg.node_pull, v->name), r)) {
                v->unsol++;
                ev(b, false, "Beacon[", bc->label, "]  ))-->  Range Broadcast to ", v->name);
                brs_report(b, bc, v, r, now, out);
            } else {
                ev(b, true, "Beacon[", bc->label, "]  XX-->  Failed Range Brdcast to ", v->name);
            }
        }
    }
    return b->reports - before;
}

int kelp_beaconrange_summary(const kelp_beaconrange *b, char *buf, size_t cap)
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

/* ------------------------------------------------------------------ the AppCast */

typedef struct brs_tab {
    // cppcheck-suppress unusedStructMember ; read through the table callbacks' context pointer
    const kelp_beaconrange *b;
} brs_tab;

/* doubleToStringX(v, 1), or "inf" for a negative distance when inf */
static const char *num1(double v, bool inf, char *tmp, size_t cap)
{
    if (inf && v < 0) return "inf";
    size_t k = 0;
    if (field_put_fixed(tmp, cap, &k, v, 1, true) < 0) return "?";
    return tmp;
}

static const char *count(unsigned long v, char *tmp, size_t cap)
{
    kelp_util_snprintf(tmp, cap, "%lu", v);
    return tmp;
}

static const char *beacon_cell(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap)
{
    static const char *const h0[] = { "", "", "", "", "Pings", "Pings", "Pings", "", "Push", "Pull" };
    static const char *const h1[] = { "ID", "X", "Y", "Freq", "Unsol", "Recvd", "Gen'd", "Noise", "Dist", "Dist" };
    if (row == 0) return h0[col];
    if (row == 1) return h1[col];
    const kelp_brs_beacon *bc = &((const brs_tab *)ctx)->b->beacon[row - 2];
    size_t k = 0;
    switch (col) {
    case 0: return bc->label;
    case 1: return num1(bc->x, false, tmp, cap);
    case 2: return num1(bc->y, false, tmp, cap);
    case 3: /* 24.8's getFreqSetting */
        if (bc->freq_lo < 0) return "poll";
        if (bc->freq_lo == bc->freq_hi) {
            if (field_put_fixed(tmp, cap, &k, bc->cur, 1, false) < 0) return "?";
            return tmp;
        }
        (void)field_put_str(tmp, cap, &k, "[");
        (void)field_put_fixed(tmp, cap, &k, bc->freq_lo, 1, true);
        (void)field_put_str(tmp, cap, &k, ":");
        (void)field_put_fixed(tmp, cap, &k, bc->freq_hi, 1, true);
        (void)field_put_str(tmp, cap, &k, "]");
        return tmp;
    case 4: return count(bc->unsol, tmp, cap);
    case 5: return count(bc->heard, tmp, cap);
    case 6: return count(bc->replies, tmp, cap);
    case 7: return "0";
    case 8: return num1(bc->push, false, tmp, cap);
    default: return num1(bc->pull, false, tmp, cap);
    }
}

static const char *vehicle_cell(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap)
{
    static const char *const h0[] = { "", "Push", "Pull", "Unsol", "Pings", "Pings", "Too", "Too" };
    static const char *const h1[] = { "VName", "Dist", "Dist", "Rec'd", "Gen'd", "Rep'd", "Freq", "Far" };
    if (row == 0) return h0[col];
    if (row == 1) return h1[col];
    const kelp_beaconrange *b = ((const brs_tab *)ctx)->b;
    const kelp_rangesense_node *v = &b->node[row - 2];
    switch (col) {
    case 0:
        rs_copy(tmp, cap, v->name, strlen(v->name));
        rs_lower(tmp);
        return tmp;
    case 1: return num1(kelp_rangesense_vmap_get(&b->cfg.reach, v->name), true, tmp, cap);
    case 2: return num1(kelp_rangesense_vmap_get(&b->cfg.node_pull, v->name), true, tmp, cap);
    case 3: return count(v->unsol, tmp, cap);
    case 4: return count(v->pings, tmp, cap);
    case 5: return count(v->replied, tmp, cap);
    case 6: return count(v->denied, tmp, cap);
    default: return count(v->too_far, tmp, cap);
    }
}

int kelp_beaconrange_report(const kelp_beaconrange *b, char *buf, size_t cap)
{
    size_t n = 0;
    bool full = false;
    if (!cap) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    brs_tab t = { b };
    broker_put(buf, cap, &n, &full, "Beacons(%u):\n", b->nbeacons);
    field_actable(buf, cap, &n, &full, 10, b->nbeacons + 2, 2, 2, 0x6u, beacon_cell, &t);
    broker_put(buf, cap, &n, &full, "\n\nVehicles(%u):\n", b->nnodes);
    field_actable(buf, cap, &n, &full, 8, b->nnodes + 2, 2, 2, 0, vehicle_cell, &t);
    unsigned long reps = 0;
    for (unsigned u = 0; u < b->nnodes; u++) reps += b->node[u].reports;
    broker_put(buf, cap, &n, &full, "\n\nLedger: now:%u, reps:%lu, who:", b->nnodes, reps);
    for (unsigned u = 0; u < b->nnodes && u < KELP_RSENSE_LEDGER_WHO; u++)
        broker_put(buf, cap, &n, &full, "%s%s", u ? "," : "", b->node[u].name);
    broker_put(buf, cap, &n, &full, "\n");
    return full ? KELP_ERR_NOSPACE : KELP_OK;
}
