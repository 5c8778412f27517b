/* uFldHazardSensor's logic (include/kelp/hazardsensor.h): the hazard field, sensor settings on
 * ROC curves, swaths, detection and classification draws, and the reports. */
#include <math.h>
#include <string.h>
#include <kelp/hazardsensor.h>
#include <kelp/kv.h>
#include <kelp/util.h>
#include "field_int.h"

#define DEG2RAD 0.017453292519943295

static void copyn(char *dst, size_t cap, const char *s, size_t n)
{
    if (n >= cap) n = cap - 1;
    memcpy(dst, s, n);
    dst[n] = 0;
}

void kelp_field_uhz_cfg_default(kelp_field_uhz_cfg *c)
{
    memset(c, 0, sizeof *c);
    copyn(c->hazard_shape, sizeof c->hazard_shape, "triangle", 8);
    copyn(c->benign_shape, sizeof c->benign_shape, "triangle", 8);
    copyn(c->hazard_color, sizeof c->hazard_color, "green", 5);
    copyn(c->benign_color, sizeof c->benign_color, "light_blue", 10);
    c->hazard_width = c->benign_width = 8;
    c->swath_transparency = 0.25;
    c->swath_length = 5;
    c->options_summary_interval = 10;
    c->show_reports = -1;
    c->min_reset_interval = 300; /* MOOS-IvP's default, 2012 and 24.8 alike */
    c->min_classify_interval = 30;
    c->show_hazards = c->show_swath = c->show_pd = c->show_pfa = true;
    c->seed = 1;
}

/* The value up to a "//" comment, a "(default)" note or a ';', trimmed. */
static size_t clean_len(const char *v)
{
    size_t n = 0;
    while (v[n] && !(v[n] == '/' && v[n + 1] == '/') && v[n] != '(' && v[n] != ';') n++;
    while (n && (v[n - 1] == ' ' || v[n - 1] == '\t')) n--;
    return n;
}

static int num(const char *v, size_t n, double *out)
{
    return kelp_parse_finite(v, n, out) < 0 ? KELP_ERR_PARSE : KELP_OK;
}

int kelp_field_uhz_add_setting(kelp_field_uhz_cfg *cfg, const char *spec, kelp_diag *d)
{
    double w = NAN, e = NAN, pc = NAN, mx = 0;
    size_t pos = 0;
    const char *k, *v;
    size_t kl, vl;
    int rc;
    while ((rc = kelp_kv_next(spec, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        double *dst = kelp_strieq_n(k, kl, "width")    ? &w
                      : kelp_strieq_n(k, kl, "exp")    ? &e
                      : kelp_strieq_n(k, kl, "pclass") ? &pc
                      : kelp_strieq_n(k, kl, "class")  ? &pc
                      : kelp_strieq_n(k, kl, "max")    ? &mx
                                                       : NULL;
        if (dst && num(v, vl, dst) < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "sensor_config: a bad number");
        }
    }
    if (rc < 0 || isnan(w) || isnan(e) || isnan(pc)) {
        return kelp_fail(d, KELP_ERR_PARSE, "sensor_config: width, exp and pclass required");
    }
    if (cfg->nsettings >= KELP_UHZ_MAX_SETTINGS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "sensor_config: too many (KELP_UHZ_MAX_SETTINGS)");
    }
    kelp_uhz_setting *s = &cfg->setting[cfg->nsettings++];
    s->width = w < 0 ? 0 : w;
    s->exp = e < 1 ? 1 : e;
    s->pclass = pc < 0 ? 0 : pc > 1 ? 1 : pc;
    s->max = mx < 1 ? 0u : mx > 1e6 ? 1000000u : (unsigned)mx;
    return KELP_OK;
}

int kelp_field_uhz_hazard_line(kelp_field_uhz_cfg *cfg, const char *line, kelp_diag *d)
{
    const char *s = line;
    while (*s == ' ' || *s == '\t') s++;
    if (!*s || *s == '\r' || *s == '\n' || (s[0] == '/' && s[1] == '/') || *s == '#') return 0;
    /* "hazard = x=..": drop the prefix; another "key = ..." line is not an object */
    const char *eq = strchr(s, '=');
    if (!eq) {
        return kelp_fail(d, KELP_ERR_PARSE, "hazard: not a key=value list");
    }
    size_t kl = (size_t)(eq - s);
    while (kl && (s[kl - 1] == ' ' || s[kl - 1] == '\t')) kl--;
    if (kelp_strieq_n(s, kl, "hazard")) s = eq + 1;
    else if (!kelp_strieq_n(s, kl, "x") && !kelp_strieq_n(s, kl, "y") && !kelp_strieq_n(s, kl, "type") &&
             !kelp_strieq_n(s, kl, "label"))
        return 0;
    kelp_uhz_object o;
    memset(&o, 0, sizeof o);
    o.width = -1;
    bool hx = false, hy = false, ht = false;
    size_t pos = 0;
    const char *k, *v;
    size_t vl;
    int rc;
    while ((rc = kelp_kv_next(s, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        while (vl && (v[vl - 1] == '\r' || v[vl - 1] == '\n')) vl--;
        if (kelp_strieq_n(k, kl, "x") || kelp_strieq_n(k, kl, "y") || kelp_strieq_n(k, kl, "width")) {
            double dv;
            if (sim_number(v, vl, &dv) < 0) {
                return kelp_fail(d, KELP_ERR_PARSE, "hazard: a bad number");
            }
            if (kelp_strieq_n(k, kl, "x")) o.x = dv, hx = true;
            else if (kelp_strieq_n(k, kl, "y")) o.y = dv, hy = true;
            else o.width = dv < 0 ? 0 : dv;
        } else if (kelp_strieq_n(k, kl, "type")) {
            if (kelp_strieq_n(v, vl, "hazard")) o.hazard = true;
            else if (!kelp_strieq_n(v, vl, "benign")) {
                return kelp_fail(d, KELP_ERR_PARSE, "hazard: type is hazard or benign");
            }
            ht = true;
        } else {
            char *dst = kelp_strieq_n(k, kl, "label")   ? o.label
                        : kelp_strieq_n(k, kl, "color") ? o.color
                        : kelp_strieq_n(k, kl, "shape") ? o.shape
                                                        : NULL;
            if (!dst) continue; /* hr=, aspect=... of 24.8: not simulated */
            if (vl >= KELP_UHZ_LABEL_LEN || memchr(v, ',', vl) || memchr(v, '=', vl)) {
                return kelp_fail(d, KELP_ERR_RANGE, "hazard: a label, color or shape too long");
            }
            copyn(dst, KELP_UHZ_LABEL_LEN, v, vl);
        }
    }
    if (rc < 0 || !hx || !hy || !ht) {
        return kelp_fail(d, KELP_ERR_PARSE, "hazard: x, y and type (hazard or benign) required");
    }
    if (cfg->nobjects >= KELP_UHZ_MAX_OBJECTS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "hazard: too many objects (KELP_UHZ_MAX_OBJECTS)");
    }
    if (!o.label[0]) kelp_snprintf(o.label, sizeof o.label, "%u", cfg->nobjects);
    for (unsigned i = 0; i < cfg->nobjects; i++)
        if (strcmp(cfg->object[i].label, o.label) == 0) {
            return kelp_fail(d, KELP_ERR_ARG, "hazard: a duplicate label");
        }
    cfg->object[cfg->nobjects++] = o;
    if (o.hazard) cfg->nhazard++;
    else cfg->nbenign++;
    return 1;
}

static int set_bool(bool *dst, const char *v, size_t n, kelp_diag *d)
{
    if (kelp_parse_bool(v, n, dst) < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "true or false");
    }
    return 1;
}

static int set_num(double *dst, const char *v, size_t n, double lo, double hi, kelp_diag *d)
{
    double dv;
    if (num(v, n, &dv) < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "a number");
    }
    *dst = dv < lo ? lo : dv > hi ? hi : dv;
    return 1;
}

static int set_text(char *dst, const char *v, size_t n, kelp_diag *d)
{
    if (n == 0 || n >= KELP_UHZ_LABEL_LEN || memchr(v, ',', n) || memchr(v, '=', n)) {
        return kelp_fail(d, KELP_ERR_ARG, "a short name");
    }
    copyn(dst, KELP_UHZ_LABEL_LEN, v, n);
    return 1;
}

int kelp_field_uhz_config(kelp_field_uhz_cfg *c, const char *key, const char *val, kelp_diag *d)
{
    size_t kl = strlen(key);
    size_t n = clean_len(val);
#define K(name) kelp_strieq_n(key, kl, name)
    if (K("SENSOR_CONFIG")) {
        char spec[160];
        if (n >= sizeof spec) {
            return kelp_fail(d, KELP_ERR_RANGE, "sensor_config too long");
        }
        copyn(spec, sizeof spec, val, n);
        int rc = kelp_field_uhz_add_setting(c, spec, d);
        return rc < 0 ? rc : 1;
    }
    if (K("HAZARD")) {
        int rc = kelp_field_uhz_hazard_line(c, val, d);
        if (rc == 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "hazard: x, y and type required");
        }
        return rc;
    }
    if (K("DEFAULT_HAZARD_SHAPE")) return set_text(c->hazard_shape, val, n, d);
    if (K("DEFAULT_HAZARD_COLOR")) return set_text(c->hazard_color, val, n, d);
    if (K("DEFAULT_BENIGN_SHAPE")) return set_text(c->benign_shape, val, n, d);
    if (K("DEFAULT_BENIGN_COLOR")) return set_text(c->benign_color, val, n, d);
    if (K("DEFAULT_HAZARD_WIDTH")) return set_num(&c->hazard_width, val, n, 0, 1e6, d);
    if (K("DEFAULT_BENIGN_WIDTH")) return set_num(&c->benign_width, val, n, 0, 1e6, d);
    if (K("SWATH_TRANSPARENCY")) return set_num(&c->swath_transparency, val, n, 0, 1, d);
    if (K("SWATH_LENGTH")) return set_num(&c->swath_length, val, n, 1, 1e6, d);
    if (K("OPTIONS_SUMMARY_INTERVAL")) return set_num(&c->options_summary_interval, val, n, 0, 120, d);
    if (K("MIN_RESET_INTERVAL")) return set_num(&c->min_reset_interval, val, n, 0, 1e9, d);
    if (K("MIN_CLASSIFY_INTERVAL") || K("CLASSIFY_PERIOD"))
        return set_num(&c->min_classify_interval, val, n, 0, 1e9, d);
    if (K("SHOW_REPORTS") || K("SHOW_DETECTIONS")) {
        if (kelp_strieq_n(val, n, "unlimited") || kelp_strieq_n(val, n, "nolimit")) {
            c->show_reports = -1;
            return 1;
        }
        return set_num(&c->show_reports, val, n, 0, 1e9, d);
    }
    if (K("SHOW_HAZARDS")) return set_bool(&c->show_hazards, val, n, d);
    if (K("SHOW_SWATH")) return set_bool(&c->show_swath, val, n, d);
    if (K("SHOW_PD")) return set_bool(&c->show_pd, val, n, d);
    if (K("SHOW_PFA")) return set_bool(&c->show_pfa, val, n, d);
    if (K("VERBOSE")) return set_bool(&c->verbose, val, n, d);
    if (K("SEED_RANDOM")) return set_bool(&c->seed_random, val, n, d);
    if (K("RANDOM_SEED")) {
        long long s;
        if (kelp_parse_llong(val, n, &s) < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "an integer");
        }
        c->seed = (uint64_t)s;
        return 1;
    }
#undef K
    return 0;
}

int kelp_field_uhz_init(kelp_field_uhz *h, const kelp_field_uhz_cfg *cfg)
{
    memset(h, 0, sizeof *h);
    h->cfg = *cfg;
    /* insertion sort by width (stable: equal widths keep their order) */
    kelp_uhz_setting *s = h->cfg.setting;
    for (unsigned i = 1; i < h->cfg.nsettings; i++) {
        kelp_uhz_setting t = s[i];
        unsigned j = i;
        while (j > 0 && s[j - 1].width > t.width) {
            s[j] = s[j - 1];
            j--;
        }
        s[j] = t;
    }
    kelp_rng_seed(&h->rng, cfg->seed);
    h->markers_due = true;
    return KELP_OK;
}

const char *kelp_field_uhz_subscription(unsigned i)
{
    static const char *const subs[] = { "NODE_REPORT",        "NODE_REPORT_LOCAL",    "UHZ_SENSOR_REQUEST",
                                        "UHZ_CONFIG_REQUEST", "UHZ_SENSOR_CONFIG",    "UHZ_CLASSIFY_REQUEST",
                                        "PMV_CONNECT" };
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

int kelp_field_uhz_find(const kelp_field_uhz *h, const char *name)
{
    size_t nl = strlen(name);
    for (unsigned i = 0; i < h->nnodes; i++)
        if (kelp_strieq_n(name, nl, h->node[i].name)) return (int)i;
    return -1;
}

int kelp_field_uhz_default_setting(const kelp_field_uhz_cfg *cfg)
{
    if (cfg->nsettings == 0) return -1;
    double lo = cfg->setting[0].width;
    double hi = lo;
    for (unsigned i = 1; i < cfg->nsettings; i++) {
        if (cfg->setting[i].width < lo) lo = cfg->setting[i].width;
        if (cfg->setting[i].width > hi) hi = cfg->setting[i].width;
    }
    double avg = (lo + hi) / 2;
    int best = -1;
    for (unsigned i = 0; i < cfg->nsettings; i++)
        if (cfg->setting[i].width <= avg && (best < 0 || cfg->setting[i].width > cfg->setting[best].width))
            best = (int)i;
    return best;
}

bool kelp_field_uhz_in_swath(double vx, double vy, double hdg, double width, double length, double ox, double oy)
{
    double h = hdg * DEG2RAD, dx = ox - vx, dy = oy - vy;
    double along = dx * sin(h) + dy * cos(h);
    double across = dx * cos(h) - dy * sin(h);
    return fabs(along) <= length / 2 && fabs(across) <= width / 2;
}

/* ---- memos and trace ---- */

/* a memo: text then arg, counted when repeated */
static void memo(kelp_field_uhz *h, const char *text, const char *arg)
{
    char t[KELP_UHZ_MEMO_LEN];
    kelp_snprintf(t, sizeof t, "%s%s", text, arg);
    for (unsigned i = 0; i < h->nmemo; i++)
        if (strcmp(h->memo[i].text, t) == 0) {
            h->memo[i].count++;
            return;
        }
    if (h->nmemo >= KELP_UHZ_MAX_MEMOS) return;
    memcpy(h->memo[h->nmemo].text, t, sizeof t);
    h->memo[h->nmemo++].count = 1;
}

static void trace(kelp_field_uhz *h, char c)
{
    if (h->ntrace + 1 < KELP_UHZ_TRACE_LEN) {
        h->trace[h->ntrace++] = c;
        h->trace[h->ntrace] = 0;
    }
}

static void warn(const kelp_field_sink *out, const char *msg)
{
    if (out && out->warn) out->warn(out->ctx, msg);
}

static void post(const kelp_field_sink *out, const char *var, const char *val)
{
    if (out) out->publish(out->ctx, var, true, val, 0);
}

/* post var and var_<NAME> (upper case): "vname=<v>,<body>" and "<body>" */
static void post_pair(kelp_field_uhz *h, const kelp_field_sink *out, const char *var, const char *vname,
                      const char *body)
{
    char v[KELP_MAX_NAME + KELP_NODEREPORT_MAX_FIELD], *s = h->ws; /* (body is never h->ws) */
    size_t k = 0; /* no printf on this path (it runs under every request) */
    if (field_put_str(v, sizeof v, &k, var) < 0 || field_put_str(v, sizeof v, &k, "_") < 0) return;
    for (const char *p = vname; *p && k + 1 < sizeof v; p++) v[k++] = (*p >= 'a' && *p <= 'z') ? (char)(*p - 32) : *p;
    v[k] = 0;
    post(out, v, body);
    size_t n = 0;
    if (field_put_str(s, sizeof h->ws, &n, "vname=") == 0 && field_put_str(s, sizeof h->ws, &n, vname) == 0 &&
        field_put_str(s, sizeof h->ws, &n, ",") == 0 && field_put_str(s, sizeof h->ws, &n, body) == 0)
        post(out, var, s);
}

static void put_num(char *buf, size_t cap, size_t *k, double v, int dec, bool strip)
{
    if (field_put_fixed(buf, cap, k, v, dec, strip) < 0) (void)field_put_str(buf, cap, k, "nan");
}

/* ---- vehicles ---- */

static kelp_uhz_node *node_get(kelp_field_uhz *h, const char *name, size_t nl, const kelp_field_sink *out)
{
    for (unsigned i = 0; i < h->nnodes; i++)
        if (kelp_strieq_n(name, nl, h->node[i].name)) return &h->node[i];
    if (nl == 0 || nl >= KELP_NODEREPORT_MAX_FIELD) return NULL;
    if (h->nnodes >= KELP_UHZ_MAX_NODES) {
        warn(out, "uFldHazardSensor: too many vehicles (KELP_UHZ_MAX_NODES)");
        return NULL;
    }
    kelp_uhz_node *n = &h->node[h->nnodes++];
    memset(n, 0, sizeof *n);
    copyn(n->name, sizeof n->name, name, nl);
    n->last_reset = -1;
    return n;
}

/* other vehicles holding setting s */
static unsigned holders(const kelp_field_uhz *h, unsigned s, const kelp_uhz_node *except)
{
    unsigned c = 0;
    for (unsigned i = 0; i < h->nnodes; i++)
        if (&h->node[i] != except && h->node[i].have_setting && h->node[i].setting == s) c++;
    return c;
}

static void post_ack(kelp_field_uhz *h, const kelp_uhz_node *n, const kelp_field_sink *out)
{
    const kelp_uhz_setting *s = &h->cfg.setting[n->setting];
    char b[200];
    size_t k = 0;
    field_putf(b, sizeof b, &k, "width=");
    put_num(b, sizeof b, &k, s->width, 3, true);
    field_putf(b, sizeof b, &k, ",pd=");
    put_num(b, sizeof b, &k, n->pd, 3, true);
    field_putf(b, sizeof b, &k, ",pfa=");
    put_num(b, sizeof b, &k, n->pfa, 2, false);
    field_putf(b, sizeof b, &k, ",pclass=");
    put_num(b, sizeof b, &k, s->pclass, 3, true);
    post_pair(h, out, "UHZ_CONFIG_ACK", n->name, b);
}

static void apply(kelp_field_uhz *h, kelp_uhz_node *n, unsigned s, double pd)
{
    n->setting = s;
    n->have_setting = true;
    n->pd = pd;
    n->pfa = pow(pd, h->cfg.setting[s].exp);
    memo(h, "Setting sensor settings for:", n->name);
}

static bool ensure_setting(kelp_field_uhz *h, kelp_uhz_node *n, const kelp_field_sink *out)
{
    if (n->have_setting) return true;
    int d = kelp_field_uhz_default_setting(&h->cfg);
    if (d < 0) return false;
    apply(h, n, (unsigned)d, KELP_UHZ_DEFAULT_PD);
    post_ack(h, n, out);
    return true;
}

KELP_NOINLINE static int config_request(kelp_field_uhz *h, const char *s, kelp_time now, const kelp_field_sink *out)
{
    char vname[KELP_NODEREPORT_MAX_FIELD] = "", ws[64] = "", ps[64] = "";
    if (kelp_kv_get(s, ',', "vname", vname, sizeof vname) < 0 || kelp_kv_get(s, ',', "width", ws, sizeof ws) < 0 ||
        kelp_kv_get(s, ',', "pd", ps, sizeof ps) < 0) {
        trace(h, 'X');
        memo(h, "Bad config request (value too long)", "");
        return KELP_ERR_PARSE;
    }
    kelp_uhz_node *n = vname[0] ? node_get(h, vname, strlen(vname), out) : NULL;
    if (!n || !n->have_report) {
        trace(h, 'x');
        memo(h, "Bad config request (unknown vehicle): ", vname);
        warn(out, "uFldHazardSensor: config request without a vehicle name or its node report");
        return KELP_ERR_NOTFOUND;
    }
    double width = NAN, pd = NAN;
    if ((ws[0] && (num(ws, strlen(ws), &width) < 0 || width < 0)) ||
        (ps[0] && (num(ps, strlen(ps), &pd) < 0 || pd < 0 || pd > 1))) {
        trace(h, 'X');
        memo(h, "Bad config request (out-of-range value) from: ", n->name);
        warn(out, "uFldHazardSensor: config request with a bad width or a pd outside [0,1]");
        return KELP_ERR_RANGE;
    }
    if (h->cfg.nsettings == 0) {
        trace(h, '!');
        memo(h, "Config request failed, no settings to choose from: ", n->name);
        return KELP_ERR_NOTFOUND;
    }
    if (n->last_reset >= 0 && now - n->last_reset < h->cfg.min_reset_interval) {
        n->reset_denied++;
        memo(h, "Sensor reset denied (too soon) for vehicle: ", n->name);
        return KELP_ERR_DENIED;
    }
    bool had = n->have_setting;
    int d = kelp_field_uhz_default_setting(&h->cfg); /* >= 0: there are settings */
    unsigned pick = had ? n->setting : (unsigned)(d < 0 ? 0 : d);
    if (!isnan(width)) {
        int below = -1, lowest = -1;
        for (unsigned i = 0; i < h->cfg.nsettings; i++) {
            const kelp_uhz_setting *st = &h->cfg.setting[i];
            if (st->max && holders(h, i, n) >= st->max) continue; /* full */
            if (lowest < 0 || st->width < h->cfg.setting[lowest].width) lowest = (int)i;
            if (st->width <= width && (below < 0 || st->width >= h->cfg.setting[below].width)) below = (int)i;
        }
        if (lowest < 0) {
            trace(h, '!');
            memo(h, "Config request failed, every setting at its max: ", n->name);
            return KELP_ERR_DENIED;
        }
        pick = (unsigned)(below >= 0 ? below : lowest);
    }
    apply(h, n, pick, isnan(pd) ? (had ? n->pd : KELP_UHZ_DEFAULT_PD) : pd);
    n->resets++;
    n->last_reset = now;
    post_ack(h, n, out);
    return 1;
}

static void post_circle(kelp_field_uhz *h, const kelp_uhz_node *n, const kelp_uhz_object *o, bool said_hazard,
                        kelp_time now, const kelp_field_sink *out)
{
    if (h->cfg.show_reports == 0) return; /* shown for no time: not posted (MOOS-IvP: unlimited or > 0 only) */
    const char *c = said_hazard ? "yellow" : "white";
    char *b = h->ws; /* workspace (free here: post_pair is done with it) */
    const size_t cap = 320; /* the circle's limit as before */
    size_t k = 0;
    field_putf(b, cap, &k, "x=");
    put_num(b, cap, &k, o->x, 2, true);
    field_putf(b, cap, &k, ",y=");
    put_num(b, cap, &k, o->y, 2, true);
    field_putf(b, cap, &k, ",radius=%g,label=%s_%s,edge_color=%s,fill_color=%s,fill=0.3,edge_size=1,time=",
               KELP_UHZ_CIRCLE_RADIUS, n->name, o->label, c, c);
    put_num(b, cap, &k, now, 2, true);
    if (h->cfg.show_reports >= 0) {
        field_putf(b, cap, &k, ",duration=");
        put_num(b, cap, &k, h->cfg.show_reports, 2, true);
    }
    post(out, "VIEW_CIRCLE", b);
}

static void put_xy_label(char *b, size_t cap, size_t *k, const kelp_uhz_object *o)
{
    field_putf(b, cap, k, "x=");
    put_num(b, cap, k, o->x, 2, true);
    field_putf(b, cap, k, ",y=");
    put_num(b, cap, k, o->y, 2, true);
}

KELP_NOINLINE static void detect(kelp_field_uhz *h, kelp_uhz_node *n, unsigned oi, kelp_time now, const kelp_field_sink *out)
{
    const kelp_uhz_object *o = &h->cfg.object[oi];
    const kelp_uhz_setting *st = &h->cfg.setting[n->setting];
    double roll = kelp_rng_uniform(&h->rng);
    double roll_c = kelp_rng_uniform(&h->rng); /* drawn always: one object, two draws */
    if (!(roll < (o->hazard ? n->pd : n->pfa))) return;
    bool said = roll_c < st->pclass ? o->hazard : !o->hazard;
    char b[200];
    size_t k = 0;
    put_xy_label(b, sizeof b, &k, o);
    field_putf(b, sizeof b, &k, ",label=%s", o->label);
    post_pair(h, out, "UHZ_DETECTION_REPORT", n->name, b);
    k = 0;
    put_xy_label(b, sizeof b, &k, o);
    field_putf(b, sizeof b, &k, ",hazard=%s,label=%s", said ? "true" : "false", o->label);
    post_pair(h, out, "UHZ_HAZARD_REPORT", n->name, b);
    post_circle(h, n, o, said, now, out);
    n->detects++;
    n->passes++;
    memo(h, "Detect/Classify report sent to vehicle: ", n->name);
}

KELP_NOINLINE static void post_swath(kelp_field_uhz *h, const kelp_uhz_node *n, const kelp_field_sink *out)
{
    double hr = n->hdg * DEG2RAD, L = h->cfg.swath_length / 2, W = h->cfg.setting[n->setting].width / 2;
    static const double sa[4] = { 1, 1, -1, -1 }, sc[4] = { 1, -1, -1, 1 };
    char *b = h->ws; /* workspace (the detections that follow use it after this post) */
    const size_t cap = 400; /* the polygon's limit as before */
    size_t k = 0;
    field_putf(b, cap, &k, "pts={");
    for (int i = 0; i < 4; i++) {
        double a = sa[i] * L, c = sc[i] * W;
        if (i) field_putf(b, cap, &k, ":");
        put_num(b, cap, &k, n->x + a * sin(hr) + c * cos(hr), 2, true);
        field_putf(b, cap, &k, ",");
        put_num(b, cap, &k, n->y + a * cos(hr) - c * sin(hr), 2, true);
    }
    field_putf(b, cap, &k,
               "},label=sensor_swath_%s,edge_color=white,fill_color=white,edge_size=0,vertex_size=0,fill=", n->name);
    put_num(b, cap, &k, h->cfg.swath_transparency, 3, true);
    if (h->cfg.show_pd || h->cfg.show_pfa) {
        field_putf(b, cap, &k, ",msg=");
        if (h->cfg.show_pd) put_num(b, cap, &k, n->pd, 2, false);
        if (h->cfg.show_pd && h->cfg.show_pfa) field_putf(b, cap, &k, "/");
        else if (h->cfg.show_pfa) field_putf(b, cap, &k, "pfa="); /* 24.8: pfa alone is named */
        if (h->cfg.show_pfa) put_num(b, cap, &k, n->pfa, 2, false);
    }
    post(out, "VIEW_POLYGON", b);
}

KELP_NOINLINE static int sensor_request(kelp_field_uhz *h, const char *s, kelp_time now, const kelp_field_sink *out)
{
    char vname[KELP_NODEREPORT_MAX_FIELD] = "";
    trace(h, '$');
    if (kelp_kv_get(s, ',', "vname", vname, sizeof vname) != 1 || !vname[0]) {
        warn(out, "uFldHazardSensor: sensor request without vname");
        return KELP_ERR_PARSE;
    }
    kelp_uhz_node *n = node_get(h, vname, strlen(vname), out);
    if (!n) return KELP_ERR_NOSPACE;
    n->sensor_reqs++;
    memo(h, "Sensor request received from: ", n->name);
    if (!n->have_report) {
        warn(out, "uFldHazardSensor: sensor request from a vehicle with no NODE_REPORT yet");
        return 1;
    }
    if (!ensure_setting(h, n, out)) {
        memo(h, "No sensor settings to choose from for: ", n->name);
        return 1;
    }
    if (h->cfg.show_swath) post_swath(h, n, out);
    double w = h->cfg.setting[n->setting].width;
    for (unsigned i = 0; i < h->cfg.nobjects; i++) {
        const kelp_uhz_object *o = &h->cfg.object[i];
        bool in = kelp_field_uhz_in_swath(n->x, n->y, n->hdg, w, h->cfg.swath_length, o->x, o->y);
        uint8_t bit = (uint8_t)(1u << (i & 7));
        bool was = (n->inside[i >> 3] & bit) != 0;
        if (in) n->inside[i >> 3] |= bit;
        else n->inside[i >> 3] &= (uint8_t)~bit;
        if (in && !was) detect(h, n, i, now, out);
    }
    return 1;
}

KELP_NOINLINE static int classify_request(kelp_field_uhz *h, const char *s, kelp_time now, const kelp_field_sink *out)
{
    char vname[KELP_NODEREPORT_MAX_FIELD] = "", label[KELP_UHZ_LABEL_LEN] = "", pr[32] = "", act[16] = "";
    if (kelp_kv_get(s, ',', "vname", vname, sizeof vname) < 0 || kelp_kv_get(s, ',', "label", label, sizeof label) < 0 ||
        kelp_kv_get(s, ',', "priority", pr, sizeof pr) < 0 || kelp_kv_get(s, ',', "action", act, sizeof act) < 0 ||
        !vname[0]) {
        warn(out, "uFldHazardSensor: classify request without vname (or a value too long)");
        return KELP_ERR_PARSE;
    }
    int ni = kelp_field_uhz_find(h, vname);
    kelp_uhz_node *n = ni < 0 ? NULL : &h->node[ni];
    if (n && kelp_strieq(act, "clear")) {
        n->nqueue = 0;
        memo(h, "Classify queue cleared for: ", n->name);
        return 1;
    }
    if (n) n->classify_reqs++;
    double priority = 50;
    if (!n || !n->have_setting || (pr[0] && num(pr, strlen(pr), &priority) < 0)) {
        warn(out, "uFldHazardSensor: classify request from an unknown vehicle or with a bad priority");
        return KELP_ERR_ARG;
    }
    unsigned oi = h->cfg.nobjects;
    for (unsigned i = 0; i < h->cfg.nobjects; i++)
        if (strcmp(h->cfg.object[i].label, label) == 0) oi = i;
    if (oi == h->cfg.nobjects) {
        warn(out, "uFldHazardSensor: classify request for an unknown label");
        return KELP_ERR_NOTFOUND;
    }
    if (n->passes == 0 || n->nqueue >= KELP_UHZ_MAX_QUEUE) {
        memo(h, "Sensor classify request saturated: ", n->name);
        return KELP_ERR_DENIED;
    }
    n->passes--;
    bool truth = h->cfg.object[oi].hazard;
    kelp_uhz_entry e = { oi, kelp_rng_uniform(&h->rng) < h->cfg.setting[n->setting].pclass ? truth : !truth,
                         priority };
    if (n->nqueue == 0) n->last_classify = now; /* the interval runs from the first request queued */
    if (kelp_strieq(act, "top")) {
        e.priority = INFINITY;
        n->last_classify = now;
    }
    /* keep the queue sorted by priority, highest first, FIFO among equals */
    unsigned j = n->nqueue++;
    while (j > 0 && n->queue[j - 1].priority < e.priority) {
        n->queue[j] = n->queue[j - 1];
        j--;
    }
    n->queue[j] = e;
    return 1;
}

KELP_NOINLINE static int node_report(kelp_field_uhz *h, const char *s, const kelp_field_sink *out)
{
    kelp_nodereport *r = &h->ws_report; /* workspace: no report on the stack */
    trace(h, 'N');
    if (kelp_nodereport_parse(s, strlen(s), r, NULL) < 0 || !(r->fields & KELP_NR_X) || !(r->fields & KELP_NR_Y)) {
        warn(out, "uFldHazardSensor: invalid NODE_REPORT (NAME, X and Y required)");
        return KELP_ERR_PARSE;
    }
    kelp_uhz_node *n = node_get(h, r->name, strlen(r->name), out);
    if (!n) return KELP_ERR_NOSPACE;
    h->node_reports++;
    n->have_report = true;
    n->x = r->x;
    n->y = r->y;
    n->hdg = (r->fields & KELP_NR_HDG) ? r->hdg : 0;
    return 1;
}

int kelp_field_uhz_mail(kelp_field_uhz *h, const char *var, const char *sval, kelp_time now, const kelp_field_sink *out)
{
    int rc = 0;
    if (kelp_strieq(var, "PMV_CONNECT")) {
        h->markers_due = true;
        return 1;
    }
    if (!sval) return 0;
    if (kelp_strieq(var, "NODE_REPORT") || kelp_strieq(var, "NODE_REPORT_LOCAL")) rc = node_report(h, sval, out);
    else if (kelp_strieq(var, "UHZ_SENSOR_REQUEST")) rc = sensor_request(h, sval, now, out);
    else if (kelp_strieq(var, "UHZ_CONFIG_REQUEST") || kelp_strieq(var, "UHZ_SENSOR_CONFIG"))
        rc = config_request(h, sval, now, out);
    else if (kelp_strieq(var, "UHZ_CLASSIFY_REQUEST")) rc = classify_request(h, sval, now, out);
    else return 0;
    if (rc < 0) h->bad_mail++;
    return rc;
}

static void post_markers(kelp_field_uhz *h, const kelp_field_sink *out)
{
    const kelp_field_uhz_cfg *c = &h->cfg;
    for (unsigned i = 0; i < c->nobjects; i++) {
        const kelp_uhz_object *o = &c->object[i];
        char b[256];
        size_t k = 0;
        put_xy_label(b, sizeof b, &k, o);
        field_putf(b, sizeof b, &k, ",label=%s,color=%s,type=%s,width=", o->label,
                   o->color[0] ? o->color : o->hazard ? c->hazard_color : c->benign_color,
                   o->shape[0] ? o->shape : o->hazard ? c->hazard_shape : c->benign_shape);
        put_num(b, sizeof b, &k, o->width >= 0 ? o->width : o->hazard ? c->hazard_width : c->benign_width, 2, true);
        post(out, "VIEW_MARKER", b);
    }
}

static void post_summary(kelp_field_uhz *h, const kelp_field_sink *out)
{
    char *b = h->ws;
    size_t k = 0;
    b[0] = 0;
    for (unsigned i = 0; i < h->cfg.nsettings; i++) {
        const kelp_uhz_setting *s = &h->cfg.setting[i];
        field_putf(b, sizeof h->ws, &k, "%swidth=", i ? ":" : "");
        put_num(b, sizeof h->ws, &k, s->width, 2, true);
        field_putf(b, sizeof h->ws, &k, ",exp=");
        put_num(b, sizeof h->ws, &k, s->exp, 2, true);
        field_putf(b, sizeof h->ws, &k, ",pclass=");
        put_num(b, sizeof h->ws, &k, s->pclass, 2, true);
        if (s->max) field_putf(b, sizeof h->ws, &k, ",max=%u", s->max);
    }
    post(out, "UHZ_OPTIONS_SUMMARY", b);
}

void kelp_field_uhz_iterate(kelp_field_uhz *h, kelp_time now, const kelp_field_sink *out)
{
    h->iterations++;
    trace(h, '*');
    if (h->markers_due) {
        h->markers_due = false;
        if (h->cfg.show_hazards) post_markers(h, out);
    }
    if (!h->started) {
        h->started = true;
        char t[24];
        kelp_snprintf(t, sizeof t, "%u", h->cfg.nobjects);
        memo(h, "Total hazards: ", t);
        post_summary(h, out);
        h->last_summary = now;
    } else if (now - h->last_summary >= h->cfg.options_summary_interval) {
        post_summary(h, out);
        h->last_summary = now;
    }
    for (unsigned i = 0; i < h->nnodes; i++) {
        kelp_uhz_node *n = &h->node[i];
        if (n->nqueue == 0 || now - n->last_classify < h->cfg.min_classify_interval) continue;
        kelp_uhz_entry e = n->queue[0];
        memmove(&n->queue[0], &n->queue[1], (n->nqueue - 1) * sizeof n->queue[0]);
        n->nqueue--;
        n->last_classify = now;
        const kelp_uhz_object *o = &h->cfg.object[e.obj];
        char b[200];
        size_t k = 0;
        put_xy_label(b, sizeof b, &k, o);
        field_putf(b, sizeof b, &k, ",type=%s,label=%s", e.said_hazard ? "hazard" : "benign", o->label);
        post_pair(h, out, "UHZ_HAZARD_REPORT", n->name, b);
        post_circle(h, n, o, e.said_hazard, now, out);
        n->classify_answ++;
        memo(h, "Classify report sent to vehicle: ", n->name);
    }
}

int kelp_field_uhz_report(kelp_field_uhz *h, kelp_time now, char *buf, size_t cap)
{
    size_t k = 0;
    if (cap) buf[0] = 0;
    if (!h->cfg.verbose) {
        field_putf(buf, cap, &k, "%s\n", h->trace);
        h->ntrace = 0;
        h->trace[0] = 0;
        return k + 1 >= cap ? KELP_ERR_NOSPACE : KELP_OK;
    }
    field_putf(buf, cap, &k, "****\nuFldHazardSensor Summary:(%lu)\n****\n\n", h->iterations);
    field_putf(buf, cap, &k, "Sensor Configuration Options\n=====\n  Width   Exp  Classify   Max\n  -----  -----\n");
    for (unsigned i = 0; i < h->cfg.nsettings; i++) {
        const kelp_uhz_setting *s = &h->cfg.setting[i];
        field_putf(buf, cap, &k, "  %6.1f  %5.1f  %6.3f  %4u\n", s->width, s->exp, s->pclass, s->max);
    }
    field_putf(buf, cap, &k, "\nSensor Settings for known vehicles:\n=====\n");
    field_putf(buf, cap, &k, "VName      Width     Pd      Pfa  Pclass      Resets  Detects  Requests  Classify\n");
    field_putf(buf, cap, &k, "-----  -----  -----  -----  -----  -----  -----  -----  -----\n");
    for (unsigned i = 0; i < h->nnodes; i++) {
        const kelp_uhz_node *n = &h->node[i];
        if (!n->have_setting) continue;
        const kelp_uhz_setting *s = &h->cfg.setting[n->setting];
        char rs[48];
        kelp_snprintf(rs, sizeof rs, "%lu(%.0f)", n->resets, n->last_reset >= 0 ? now - n->last_reset : 0.0);
        field_putf(buf, cap, &k, "%-10s %5.1f  %7.3f  %6.3f  %6.3f  %10s  %7lu  %8lu  %lu/%lu\n", n->name, s->width,
                   n->pd, n->pfa, s->pclass, rs, n->detects, n->sensor_reqs, n->classify_answ, n->classify_reqs);
    }
    field_putf(buf, cap, &k, "\nInternal Memos:\n=====\n");
    for (unsigned i = 0; i < h->nmemo; i++)
        field_putf(buf, cap, &k, "(%lu) %s\n", h->memo[i].count, h->memo[i].text);
    return k + 1 >= cap ? KELP_ERR_NOSPACE : KELP_OK;
}

/* ---- gen_hazards ---- */

bool kelp_field_uhz_in_convex(const double (*pts)[2], size_t n, double x, double y)
{
    int sign = 0;
    for (size_t i = 0; i < n; i++) {
        const double *a = pts[i], *b = pts[(i + 1) % n];
        double cr = (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
        int s = cr > 0 ? 1 : cr < 0 ? -1 : 0;
        if (s == 0) continue;
        if (sign == 0) sign = s;
        else if (s != sign) return false;
    }
    return true;
}

#define GEN_MAX_TRIES 100000

int kelp_field_uhz_random_point(const double (*pts)[2], size_t n, kelp_rng *rng, double *x, double *y)
{
    if (n < 3) return KELP_ERR_ARG;
    double x0 = pts[0][0], x1 = x0, y0 = pts[0][1], y1 = y0, area = 0;
    for (size_t i = 0; i < n; i++) {
        const double *a = pts[i], *b = pts[(i + 1) % n];
        if (!isfinite(a[0]) || !isfinite(a[1])) return KELP_ERR_ARG;
        x0 = fmin(x0, a[0]), x1 = fmax(x1, a[0]), y0 = fmin(y0, a[1]), y1 = fmax(y1, a[1]);
        area += a[0] * b[1] - b[0] * a[1];
    }
    if (!(fabs(area) > 0)) return KELP_ERR_ARG;
    for (int t = 0; t < GEN_MAX_TRIES; t++) {
        double px = kelp_rng_range(rng, x0, x1), py = kelp_rng_range(rng, y0, y1);
        if (kelp_field_uhz_in_convex(pts, n, px, py)) {
            *x = px;
            *y = py;
            return KELP_OK;
        }
    }
    return KELP_ERR_INFEASIBLE;
}
