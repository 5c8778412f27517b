/* uFldHazardSensor's logic (include/kelp/hazardsensor.h), as MOOS-IvP 24.8's build of the app
 * behaves: the hazard field, sensor settings on ROC curves, swaths, detection and
 * classification draws on glibc's rand() sequence, the classify queue and the AppCast report. */
#include <math.h>
#include <stdarg.h>
#include <string.h>
#include <kelp/hazardsensor.h>
#include <kelp/kv.h>
#include <kelp/util.h>
#include "field_int.h"

#define RULE "============================================"
/* 24.8's classify queue orders equal priorities first come, first served by taking
 * n / 1e6 off the n-th entry's priority */
#define QUEUE_ORDER_SCALE 1000000.0

static void copyn(char *dst, size_t cap, const char *s, size_t n)
{
    if (n >= cap) n = cap - 1;
    memcpy(dst, s, n);
    dst[n] = 0;
}

void kelp_hazardsensor_cfg_default(kelp_hazardsensor_cfg *c)
{
    memset(c, 0, sizeof *c);
    copyn(c->hazard_shape, sizeof c->hazard_shape, "triangle", 8);
    copyn(c->benign_shape, sizeof c->benign_shape, "triangle", 8);
    copyn(c->hazard_color, sizeof c->hazard_color, "red", 3);
    copyn(c->benign_color, sizeof c->benign_color, "light_blue", 10);
    c->hazard_width = c->benign_width = 8;
    c->swath_transparency = 0.2;
    c->swath_length = 5;
    c->options_summary_interval = 10;
    c->show_reports = -1;
    c->min_reset_interval = 300;
    c->min_classify_interval = 30;
    c->max_turn_rate = 1.5;
    c->max_vehicle_speed = 2.05;
    c->show_hazards = c->show_swath = c->show_pd = c->show_pfa = true;
    c->seed_random = true;
    c->seed = 1;
}

/* The value up to a "//" comment, trimmed. */
static size_t clean_len(const char *v)
{
    size_t n = 0;
    while (v[n] && !(v[n] == '/' && v[n + 1] == '/')) n++;
    while (n && (v[n - 1] == ' ' || v[n - 1] == '\t' || v[n - 1] == '\r' || v[n - 1] == '\n')) n--;
    return n;
}

static int num(const char *v, size_t n, double *out)
{
    return kelp_util_parse_finite(v, n, out) < 0 ? KELP_ERR_PARSE : KELP_OK;
}

/* a summary piece: "width=<w>,exp=<e>,class=<c>[,max=<n>]" with the numbers as written */
static void summary_prepend(kelp_hazardsensor_cfg *cfg, const char *w, size_t wl, const char *e, size_t el,
                            const char *c, size_t cl, unsigned mx)
{
    char piece[128]; /* "width=..,exp=..,class=..,max=..": numbers from one config line */
    size_t k = 0;
    field_putf(piece, sizeof piece, &k, "width=%.*s,exp=%.*s,class=%.*s", (int)wl, w, (int)el, e, (int)cl, c);
    if (mx) field_putf(piece, sizeof piece, &k, ",max=%u", mx);
    size_t old = strlen(cfg->summary), add = k + (old ? 1 : 0);
    if (old + add + 1 > sizeof cfg->summary) return; /* full: the summary keeps what fits */
    memmove(cfg->summary + add, cfg->summary, old + 1);
    memcpy(cfg->summary, piece, k);
    if (old) cfg->summary[k] = ':';
}

int kelp_hazardsensor_add_setting(kelp_hazardsensor_cfg *cfg, const char *spec, kelp_diag *d)
{
    const char *sw = NULL, *se = NULL, *sc = NULL, *sm = "0";
    size_t wl = 0, el = 0, cl = 0, ml = 1;
    size_t pos = 0;
    const char *k, *v;
    size_t kl, vl;
    int rc;
    while ((rc = kelp_kv_next(spec, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        if (kelp_util_strieq_n(k, kl, "width")) sw = v, wl = vl;
        else if (kelp_util_strieq_n(k, kl, "exp")) se = v, el = vl;
        else if (kelp_util_strieq_n(k, kl, "class") || kelp_util_strieq_n(k, kl, "pclass")) sc = v, cl = vl;
        else if (kelp_util_strieq_n(k, kl, "max")) sm = v, ml = vl;
    }
    double w, e, pc, mx;
    if (rc < 0 || !sw || !se || !sc || num(sw, wl, &w) < 0 || num(se, el, &e) < 0 || num(sc, cl, &pc) < 0 ||
        num(sm, ml, &mx) < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "sensor_config: width, exp and class numbers required");
    }
    if (cfg->nsettings >= KELP_UHZ_MAX_SETTINGS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "sensor_config: too many (KELP_UHZ_MAX_SETTINGS)");
    }
    kelp_uhz_setting *s = &cfg->setting[cfg->nsettings++];
    s->width = w < 0 ? 0 : w;
    s->exp = e < 1 ? 1 : e;
    s->pclass = pc < 0 ? 0 : pc > 1 ? 1 : pc;
    s->max = mx < 1 ? 0u : mx > 1e6 ? 1000000u : (unsigned)mx;
    /* 24.8 reads a block's lines last first: the last line leads the summary */
    summary_prepend(cfg, sw, wl, se, el, sc, cl, s->max);
    return KELP_OK;
}

static bool known_shape(const char *v, size_t n)
{
    static const char *const shapes[] = { "circle", "diamond", "square", "triangle", "efield", "gateway" };
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++)
        if (kelp_util_strieq_n(v, n, shapes[i])) return true;
    return false;
}

/* one "x=..,y=..,..." object (24.8's string2Hazard: a bad number or value leaves its field unset) */
static int parse_object(kelp_uhz_object *o, const char *s, kelp_diag *d)
{
    memset(o, 0, sizeof *o);
    o->width = -1;
    o->hr = 0.5;
    bool hx = false, hy = false;
    char hazard_field[8] = "";
    size_t pos = 0, kl, vl;
    const char *k, *v;
    int rc;
    while ((rc = kelp_kv_next(s, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        while (vl && (v[vl - 1] == '\r' || v[vl - 1] == '\n')) vl--;
        double dv = 0;
        bool isnum = num(v, vl, &dv) == KELP_OK;
        if (kelp_util_strieq_n(k, kl, "x") && isnum) o->x = dv, hx = true;
        else if (kelp_util_strieq_n(k, kl, "y") && isnum) o->y = dv, hy = true;
        else if (kelp_util_strieq_n(k, kl, "hr") && isnum) o->hr = dv, o->has_hr = true;
        else if (kelp_util_strieq_n(k, kl, "aspect") && isnum) {
            if (dv >= 0 && dv < 360) o->aspect = dv, o->has_aspect = true;
        } else if (kelp_util_strieq_n(k, kl, "aspect_min") && isnum) {
            if (dv >= 0 && dv <= 90 && (!o->has_aspect_max || (dv <= o->aspect_max && dv + o->aspect_max <= 90)))
                o->aspect_min = dv, o->has_aspect_min = true;
        } else if (kelp_util_strieq_n(k, kl, "aspect_max") && isnum) {
            if (dv >= 0 && dv <= 90 && (!o->has_aspect_min || (dv >= o->aspect_min && dv + o->aspect_min <= 90)))
                o->aspect_max = dv, o->has_aspect_max = true;
        } else if (kelp_util_strieq_n(k, kl, "width")) {
            if (isnum && dv >= 0) o->width = dv;
        } else if (kelp_util_strieq_n(k, kl, "hazard")) {
            copyn(hazard_field, sizeof hazard_field, v, vl);
        } else {
            char *dst = kelp_util_strieq_n(k, kl, "type")    ? o->type
                        : kelp_util_strieq_n(k, kl, "label") ? o->label
                        : kelp_util_strieq_n(k, kl, "color") ? o->color
                        : kelp_util_strieq_n(k, kl, "shape") ? o->shape
                                                        : NULL;
            if (!dst) continue; /* source= and others: not used */
            if (dst == o->shape && !known_shape(v, vl)) continue;
            if (vl >= KELP_UHZ_LABEL_LEN) {
                return kelp_fail(d, KELP_ERR_RANGE, "hazard: a label, type, color or shape too long");
            }
            copyn(dst, KELP_UHZ_LABEL_LEN, v, vl);
            if (dst == o->shape)
                for (char *p = o->shape; *p; p++) *p = (*p >= 'A' && *p <= 'Z') ? (char)(*p + 32) : *p;
        }
    }
    if (!o->type[0] && hazard_field[0]) copyn(o->type, sizeof o->type, strcmp(hazard_field, "true") == 0 ? "hazard" : "benign", 6);
    if (rc < 0 || !hx || !hy) {
        return kelp_fail(d, KELP_ERR_PARSE, "hazard: x and y required");
    }
    return KELP_OK;
}

/* bare: a hazard file's line without "hazard =" (kelp's extension: gen_hazards' output), whose
 * object may go without a label (it gets its index) */
static int add_object(kelp_hazardsensor_cfg *cfg, const char *s, bool bare, kelp_diag *d)
{
    kelp_uhz_object o;
    int rc = parse_object(&o, s, d);
    if (rc < 0) return rc;
    if (bare && !o.label[0]) kelp_util_snprintf(o.label, sizeof o.label, "%u", cfg->nobjects);
    if (!o.type[0]) {
        return kelp_failf(d, KELP_ERR_PARSE, "Hazard specified with no type: %s", s);
    }
    if (!o.label[0]) {
        return kelp_failf(d, KELP_ERR_PARSE, "Hazard specified with no label: %s", s);
    }
    for (unsigned i = 0; i < cfg->nobjects; i++)
        if (strcmp(cfg->object[i].label, o.label) == 0) {
            return kelp_failf(d, KELP_ERR_ARG, "Duplicated hazard label detected:%s", o.label);
        }
    if (cfg->nobjects >= KELP_UHZ_MAX_OBJECTS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "hazard: too many objects (KELP_UHZ_MAX_OBJECTS)");
    }
    cfg->object[cfg->nobjects++] = o;
    if (strcmp(o.type, "hazard") == 0) cfg->nhazard++;
    else cfg->nbenign++;
    return 1;
}

int kelp_hazardsensor_hazard_line(kelp_hazardsensor_cfg *cfg, const char *line, kelp_diag *d)
{
    const char *s = line;
    while (*s == ' ' || *s == '\t') s++;
    if (!*s || *s == '\r' || *s == '\n' || (s[0] == '/' && s[1] == '/') || *s == '#') return 0;
    const char *eq = strchr(s, '=');
    if (!eq) return 0; /* 24.8 skips a line that is not "hazard = ..." */
    size_t kl = (size_t)(eq - s);
    while (kl && (s[kl - 1] == ' ' || s[kl - 1] == '\t')) kl--;
    bool bare = !kelp_util_strieq_n(s, kl, "hazard");
    if (!bare) s = eq + 1;
    else if (!kelp_util_strieq_n(s, kl, "x") && !kelp_util_strieq_n(s, kl, "y") && !kelp_util_strieq_n(s, kl, "type") &&
             !kelp_util_strieq_n(s, kl, "label"))
        return 0;
    return add_object(cfg, s, bare, d);
}

static int set_bool(bool *dst, const char *v, size_t n, kelp_diag *d)
{
    if (kelp_util_parse_bool(v, n, dst) < 0) {
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

int kelp_hazardsensor_config(kelp_hazardsensor_cfg *c, const char *key, const char *val, kelp_diag *d)
{
    size_t kl = strlen(key);
    size_t n = clean_len(val);
    char text[256];
    if (n >= sizeof text) {
        return kelp_fail(d, KELP_ERR_RANGE, "value too long");
    }
    copyn(text, sizeof text, val, n);
#define K(name) kelp_util_strieq_n(key, kl, name)
    if (K("SENSOR_CONFIG")) {
        int rc = kelp_hazardsensor_add_setting(c, text, d);
        return rc < 0 ? rc : 1;
    }
    if (K("HAZARD")) return add_object(c, text, false, d);
    if (K("DEFAULT_HAZARD_SHAPE")) return set_text(c->hazard_shape, text, n, d);
    if (K("DEFAULT_HAZARD_COLOR")) return set_text(c->hazard_color, text, n, d);
    if (K("DEFAULT_BENIGN_SHAPE")) return set_text(c->benign_shape, text, n, d);
    if (K("DEFAULT_BENIGN_COLOR")) return set_text(c->benign_color, text, n, d);
    if (K("DEFAULT_HAZARD_WIDTH")) return set_num(&c->hazard_width, text, n, -1e9, 1e9, d);
    if (K("DEFAULT_BENIGN_WIDTH")) return set_num(&c->benign_width, text, n, -1e9, 1e9, d);
    if (K("SWATH_TRANSPARENCY")) return set_num(&c->swath_transparency, text, n, 0, 1, d);
    if (K("SWATH_LENGTH")) return set_num(&c->swath_length, text, n, 1, 1e9, d);
    if (K("OPTIONS_SUMMARY_INTERVAL")) return set_num(&c->options_summary_interval, text, n, 0, 120, d);
    if (K("MIN_RESET_INTERVAL")) return set_num(&c->min_reset_interval, text, n, -1e9, 1e9, d);
    if (K("MAX_TURN_RATE")) return set_num(&c->max_turn_rate, text, n, -1e9, 1e9, d);
    if (K("MAX_VEHICLE_SPEED")) return set_num(&c->max_vehicle_speed, text, n, -1e9, 1e9, d);
    if (K("MIN_CLASSIFY_INTERVAL") || K("CLASSIFY_PERIOD"))
        return set_num(&c->min_classify_interval, text, n, -1e9, 1e9, d);
    if (K("SHOW_REPORTS") || K("SHOW_DETECTIONS")) {
        if (kelp_util_strieq_n(text, n, "unlimited") || kelp_util_strieq_n(text, n, "nolimit")) {
            c->show_reports = -1;
            return 1;
        }
        return set_num(&c->show_reports, text, n, -1e9, 1e9, d);
    }
    if (K("SHOW_HAZARDS")) return set_bool(&c->show_hazards, text, n, d);
    if (K("SHOW_SWATH")) return set_bool(&c->show_swath, text, n, d);
    if (K("SHOW_PD")) return set_bool(&c->show_pd, text, n, d);
    if (K("SHOW_PFA")) return set_bool(&c->show_pfa, text, n, d);
    if (K("IGNORE_RESEMBLANCES")) return set_bool(&c->ignore_resemblances, text, n, d);
    if (K("SEED_RANDOM")) return set_bool(&c->seed_random, text, n, d);
    if (K("RN_UNIFORM_PCT")) {
        double unused;
        return set_num(&unused, text, n, 0, 1, d);
    }
    if (K("RN_ALGORITHM")) { /* 24.8 takes "uniform[,pct=..]" and never applies it */
        if (n < 7 || !kelp_util_strieq_n(text, 7, "uniform") || (n > 7 && text[7] != ',')) {
            return kelp_fail(d, KELP_ERR_PARSE, "uniform[,pct=..]");
        }
        return 1;
    }
    if (K("RANDOM_SEED")) {
        long long s;
        if (kelp_util_parse_llong(text, n, &s) < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "an integer");
        }
        c->seed = (uint32_t)s;
        return 1;
    }
#undef K
    return 0;
}

int kelp_hazardsensor_init(kelp_hazardsensor *h, const kelp_hazardsensor_cfg *cfg)
{
    memset(h, 0, sizeof *h);
    h->cfg = *cfg;
    /* insertion sorts: settings by width (24.8: the first of equal widths first), objects by label */
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
    kelp_uhz_object *o = h->cfg.object;
    for (unsigned i = 1; i < h->cfg.nobjects; i++) {
        kelp_uhz_object t = o[i];
        unsigned j = i;
        while (j > 0 && strcmp(o[j - 1].label, t.label) > 0) {
            o[j] = o[j - 1];
            j--;
        }
        o[j] = t;
    }
    kelp_rng_glibc_seed(&h->rand, cfg->seed);
    h->markers_due = true;
    return KELP_OK;
}

void kelp_hazardsensor_set_log(kelp_hazardsensor *h, kelp_uhz_log_fn event, kelp_uhz_log_fn cfg_warning, void *ctx)
{
    h->event = event;
    h->cfg_warning = cfg_warning;
    h->log_ctx = ctx;
}

const char *kelp_hazardsensor_subscription(unsigned i)
{
    static const char *const subs[] = { "NODE_REPORT", "UHZ_SENSOR_REQUEST", "UHZ_CLASSIFY_REQUEST",
                                        "UHZ_CONFIG_REQUEST", "PMV_CONNECT" };
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

int kelp_hazardsensor_find(const kelp_hazardsensor *h, const char *name)
{
    for (unsigned i = 0; i < h->nnodes; i++)
        if (strcmp(name, h->node[i].name) == 0) return (int)i;
    return -1;
}

/* The swath's corners as 24.8 builds them: from the vehicle, at hdg + 90 -/+ phi and the
 * opposites, hypot = width / cos(phi) away, phi = atan(length / width). */
#define UHZ_PI 3.14159265358979323846 /* M_PI's value (strict C11 has no M_PI) */

/* the point dist away from (cx, cy) at compass angle deg, in 24.8's order of operations (so
 * it prints to the same digit at a tie): the angle brought into [0, 360) by whole turns, a
 * point exactly on an axis without sin/cos, else radians as (deg / 180) x pi */
static void project(double deg, double dist, double cx, double cy, double *x, double *y)
{
    if (!(fabs(deg) < 1e6)) deg = isfinite(deg) ? fmod(deg, 360.0) : 0; /* a wild angle: no long loop */
    while (deg >= 360.0) deg -= 360.0;
    while (deg < 0.0) deg += 360.0;
    if (deg == 0 || deg == 90 || deg == 180 || deg == 270) {
        *x = cx + (deg == 90 ? dist : deg == 270 ? -dist : 0);
        *y = cy + (deg == 0 ? dist : deg == 180 ? -dist : 0);
        return;
    }
    double r = (deg / 180.0) * UHZ_PI;
    *x = cx + sin(r) * dist;
    *y = cy + cos(r) * dist;
}

static void swath_corners(double vx, double vy, double hdg, double width, double length, double c[4][2])
{
    double phi = atan(length / width), hyp = width / cos(phi);
    phi = (phi / UHZ_PI) * 180; /* 24.8's degrees */
    const double a[4] = { hdg + (90 - phi), hdg + (90 + phi), hdg + (90 - phi) + 180, hdg + (90 + phi) + 180 };
    for (int i = 0; i < 4; i++) project(a[i], hyp, vx, vy, &c[i][0], &c[i][1]);
}

bool kelp_hazardsensor_in_swath(double vx, double vy, double hdg, double width, double length, double ox, double oy)
{
    if (!(width > 0) || !(length > 0)) return false; /* no area: 24.8's polygon is not convex */
    double c[4][2];
    swath_corners(vx, vy, hdg, width, length, c);
    return kelp_hazardsensor_in_convex((const double(*)[2])c, 4, ox, oy);
}

/* ---- logging ---- */

/* a formatted line to fn (events, configuration and run warnings); nothing when fn is NULL */
static void vline(void (*fn)(void *, const char *), void *ctx, char *t, const char *fmt, va_list ap) KELP_PRINTF(4, 0);
static void vline(void (*fn)(void *, const char *), void *ctx, char *t, const char *fmt, va_list ap)
{
    if (!fn) return;
    (void)kelp_util_vsnprintf(t, KELP_UHZ_MSG_LEN, fmt, ap); /* t: the sensor's workspace, off the stack */
    fn(ctx, t);
}

static void event(kelp_hazardsensor *h, const char *fmt, ...) KELP_PRINTF(2, 3);
static void event(kelp_hazardsensor *h, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vline(h->event, h->log_ctx, h->ws_msg, fmt, ap);
    va_end(ap);
}

static void cfg_warning(kelp_hazardsensor *h, const char *fmt, ...) KELP_PRINTF(2, 3);
static void cfg_warning(kelp_hazardsensor *h, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vline(h->cfg_warning, h->log_ctx, h->ws_msg, fmt, ap);
    va_end(ap);
}

static void warn(kelp_hazardsensor *h, const kelp_field_sink *out, const char *fmt, ...) KELP_PRINTF(3, 4);
static void warn(kelp_hazardsensor *h, const kelp_field_sink *out, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vline(out ? out->warn : NULL, out ? out->ctx : NULL, h->ws_msg, fmt, ap);
    va_end(ap);
}

static void post(const kelp_field_sink *out, const char *var, const char *val)
{
    if (out) out->publish(out->ctx, var, true, val, 0);
}

/* 24.8's doubleToString (dec fixed) and doubleToStringX (trailing zeros dropped) */
static void put_num(char *buf, size_t cap, size_t *k, double v, int dec, bool strip)
{
    if (field_put_fixed(buf, cap, k, v, dec, strip) < 0) (void)field_put_str(buf, cap, k, "nan");
}

/* "<VAR>_<VNAME>" with the name in upper case */
static void var_for(char *v, size_t cap, const char *var, const char *vname)
{
    size_t k = 0;
    field_putf(v, cap, &k, "%s_", var);
    for (const char *p = vname; *p && k + 1 < cap; p++) v[k++] = (*p >= 'a' && *p <= 'z') ? (char)(*p - 32) : *p;
    v[k] = 0;
}

/* the first value of `key` after 24.8's parse (pairs split at ',', the last of a key wins) */
static bool value_of(const char *s, const char *key, char *out, size_t cap)
{
    size_t pos = 0, kl, vl;
    const char *k, *v;
    bool found = false;
    out[0] = 0;
    while (kelp_kv_next(s, ',', &pos, &k, &kl, &v, &vl) == 1)
        if (kelp_util_strieq_n(k, kl, key)) {
            copyn(out, cap, v, vl);
            found = true;
        }
    return found;
}

/* ---- vehicles ---- */

/* the vehicle named `name`, made (in name order) when new; NULL when there is no room */
static kelp_uhz_node *node_get(kelp_hazardsensor *h, const char *name, const kelp_field_sink *out)
{
    unsigned i = 0;
    while (i < h->nnodes && strcmp(h->node[i].name, name) < 0) i++;
    if (i < h->nnodes && strcmp(h->node[i].name, name) == 0) return &h->node[i];
    if (!name[0] || strlen(name) >= KELP_NODEREPORT_MAX_FIELD) return NULL;
    if (h->nnodes >= KELP_UHZ_MAX_NODES) {
        warn(h, out, "uFldHazardSensor: too many vehicles (KELP_UHZ_MAX_NODES)");
        return NULL;
    }
    memmove(&h->node[i + 1], &h->node[i], (h->nnodes - i) * sizeof h->node[0]);
    h->nnodes++;
    kelp_uhz_node *n = &h->node[i];
    memset(n, 0, sizeof *n);
    copyn(n->name, sizeof n->name, name, strlen(name));
    return n;
}

/* 24.8's heading history: a heading joins when its time is later than the newest */
static void hist_add(kelp_uhz_node *n, double hdg, double now)
{
    if (n->hist_n && !(now > n->hist_t[n->hist_i])) return;
    n->hist_i = (n->hist_i + 1) % KELP_UHZ_HDG_HIST;
    n->hist_t[n->hist_i] = now;
    n->hist_h[n->hist_i] = hdg;
    if (n->hist_n < KELP_UHZ_HDG_HIST) n->hist_n++;
}

static double angle180(double a)
{
    a = fmod(a, 360.0);
    if (a > 180) a -= 360;
    else if (a <= -180) a += 360;
    return a;
}

/* degrees per second over the headings within `window` s of the newest */
static double turn_rate(const kelp_uhz_node *n, double window)
{
    if (!n->hist_n) return 0;
    double t0 = n->hist_t[n->hist_i], prev = n->hist_h[n->hist_i], dh = 0, dt = 0;
    for (unsigned j = 0; j < n->hist_n; j++) {
        unsigned i = (n->hist_i + KELP_UHZ_HDG_HIST - j) % KELP_UHZ_HDG_HIST;
        if (!(t0 - n->hist_t[i] < window)) break;
        dh += fabs(angle180(n->hist_h[i] - prev));
        dt = t0 - n->hist_t[i];
        prev = n->hist_h[i];
    }
    return dt == 0 ? 0 : dh / dt;
}

/* other vehicles holding a setting of this width */
static unsigned holders(const kelp_hazardsensor *h, double width, const kelp_uhz_node *except)
{
    unsigned c = 0;
    for (unsigned i = 0; i < h->nnodes; i++)
        if (&h->node[i] != except && h->node[i].have_setting && h->node[i].width == width) c++;
    return c;
}

static void post_ack(kelp_hazardsensor *h, const kelp_uhz_node *n, const kelp_field_sink *out)
{
    char *b = h->ws_line, *var = h->ws_var; /* workspace (the stack stays under 1 KB) */
    const size_t bc = sizeof h->ws_line;
    size_t k = 0;
    field_putf(b, bc, &k, "vname=%s,width=", n->name);
    put_num(b, bc, &k, n->width, 1, true);
    field_putf(b, bc, &k, ",pd=");
    put_num(b, bc, &k, n->pd, 3, true);
    field_putf(b, bc, &k, ",pfa=");
    put_num(b, bc, &k, n->pfa, 3, true);
    field_putf(b, bc, &k, ",pclass=");
    put_num(b, bc, &k, n->pclass, 3, true);
    var_for(var, sizeof h->ws_var, "UHZ_CONFIG_ACK", n->name);
    post(out, var, b);
}

/* 24.8's setVehicleSensorSetting: the setting nearest `width` (guess: the middle width, pd 0.9) */
static bool set_setting(kelp_hazardsensor *h, kelp_uhz_node *n, double width, double pd, bool guess, kelp_time now,
                        const kelp_field_sink *out)
{
    event(h, "Setting sensor settings for: %s", n->name);
    unsigned ns = h->cfg.nsettings;
    if (ns == 0) {
        event(h, "No sensor properties to set settings for: %s", n->name);
        return false;
    }
    if (guess) {
        width = (h->cfg.setting[0].width + h->cfg.setting[ns - 1].width) / 2;
        pd = KELP_UHZ_DEFAULT_PD;
    }
    width = width < 0 ? 0 : width;
    pd = pd < 0 ? 0 : pd > 1 ? 1 : pd;
    n->reset_tries++;
    if (n->have_reset_time && now - n->reset_time < h->cfg.min_reset_interval) {
        event(h, "Sensor reset denied (too soon) for vehicle: %s", n->name);
        return false;
    }
    unsigned pick = 0;
    bool found = false;
    double best = 0;
    for (unsigned j = 0; j < ns; j++) {
        const kelp_uhz_setting *st = &h->cfg.setting[j];
        if (st->max && holders(h, st->width, n) >= st->max) continue;
        double delta = fabs(width - st->width);
        if (!found || delta < best) found = true, best = delta, pick = j;
    }
    const kelp_uhz_setting *st = &h->cfg.setting[pick]; /* all full: 24.8 takes the first */
    n->have_setting = true;
    n->width = st->width;
    n->exp = st->exp;
    n->pclass = st->pclass;
    n->pd = pd;
    n->pfa = pow(pd, st->exp);
    post_ack(h, n, out);
    n->resets++;
    n->have_reset_time = true;
    n->reset_time = now;
    return true;
}

static bool set_pd(kelp_hazardsensor *h, kelp_uhz_node *n, double pd, kelp_time now, const kelp_field_sink *out)
{
    event(h, "Setting sensor PD settings for: %s", n->name);
    if (!n->have_setting) (void)set_setting(h, n, 0, 0, true, now, out);
    if (!n->have_setting) {
        warn(h, out, "Failed Configuration Ack for Unknown Vehicle: %s", n->name);
        return true;
    }
    n->pd = pd < 0 ? 0 : pd > 1 ? 1 : pd;
    n->pfa = pow(n->pd, n->exp);
    n->pd_resets++;
    n->pd_reset_time = now;
    post_ack(h, n, out);
    return true;
}

static int config_request(kelp_hazardsensor *h, const char *s, const char *community, kelp_time now,
                          const kelp_field_sink *out)
{
    char vname[KELP_NODEREPORT_MAX_FIELD], ws[64], ps[64];
    (void)value_of(s, "vname", vname, sizeof vname);
    bool has_w = value_of(s, "width", ws, sizeof ws) && ws[0];
    (void)value_of(s, "pd", ps, sizeof ps);
    if (!vname[0] || strcmp(vname, community ? community : "") != 0) {
        cfg_warning(h, "Bad sensor config request from: %s src: %s", vname, community ? community : "");
        return KELP_ERR_DENIED;
    }
    double width = 0, pd = 0;
    if ((has_w && num(ws, strlen(ws), &width) < 0) || num(ps, strlen(ps), &pd) < 0) {
        cfg_warning(h, "Bad sensor config request from: %s", vname);
        return KELP_ERR_PARSE;
    }
    kelp_uhz_node *n = node_get(h, vname, out);
    if (!n) return KELP_ERR_NOSPACE;
    if (!has_w) return set_pd(h, n, pd, now, out) ? 1 : KELP_ERR_DENIED;
    return set_setting(h, n, width, pd, false, now, out) ? 1 : KELP_ERR_DENIED;
}

/* ---- the sensor ---- */

static bool is_hazard(const kelp_uhz_object *o)
{
    return strcmp(o->type, "hazard") == 0;
}

/* 24.8's XYHazard::getSpec leaving out what `detection` leaves out (hr, type, color, width, shape) */
static void object_spec(char *b, size_t cap, size_t *k, const kelp_uhz_object *o, const char *type, bool detection)
{
    field_putf(b, cap, k, "x=");
    put_num(b, cap, k, o->x, 2, true);
    field_putf(b, cap, k, ",y=");
    put_num(b, cap, k, o->y, 2, true);
    field_putf(b, cap, k, ",label=%s", o->label);
    if (!detection) {
        field_putf(b, cap, k, ",type=%s", type);
        if (o->color[0]) field_putf(b, cap, k, ",color=%s", o->color);
        if (o->shape[0]) field_putf(b, cap, k, ",shape=%s", o->color); /* 24.8 writes the colour here */
        if (o->width >= 0) {
            field_putf(b, cap, k, ",width=");
            put_num(b, cap, k, o->width, 5, true);
        }
    }
    if (o->has_aspect) {
        field_putf(b, cap, k, ",aspect=");
        put_num(b, cap, k, o->aspect, 5, true);
    }
    if (o->has_aspect_min) {
        field_putf(b, cap, k, ",aspect_min=");
        put_num(b, cap, k, o->aspect_min, 5, true);
    }
    if (o->has_aspect_max) {
        field_putf(b, cap, k, ",aspect_max=");
        put_num(b, cap, k, o->aspect_max, 5, true);
    }
}

/* 24.8's XYCircle spec of a report: radius 10, `vertices`, edge and fill colours, time,
 * duration (detections), vertex size 0, edge size, transparency */
static void post_circle(kelp_hazardsensor *h, const kelp_uhz_object *o, unsigned vertices, const char *edge,
                        const char *fill, double edge_size, double transparency, bool duration, kelp_time now,
                        const kelp_field_sink *out)
{
    char *b = h->ws_circle; /* workspace: posted from detection reports and classify answers */
    const size_t bcap = sizeof h->ws_circle;
    size_t k = 0;
    field_putf(b, bcap, &k, "x=");
    put_num(b, bcap, &k, o->x, 2, true);
    field_putf(b, bcap, &k, ",y=");
    put_num(b, bcap, &k, o->y, 2, true);
    field_putf(b, bcap, &k, ",radius=");
    put_num(b, bcap, &k, KELP_UHZ_CIRCLE_RADIUS, 2, true);
    field_putf(b, bcap, &k, ",vertices=%u,edge_color=%s,fill_color=%s,time=", vertices, edge, fill);
    put_num(b, bcap, &k, now, 2, true);
    if (duration) {
        field_putf(b, bcap, &k, ",duration=");
        put_num(b, bcap, &k, h->cfg.show_reports < 0 ? -1 : h->cfg.show_reports, 2, true);
    }
    field_putf(b, bcap, &k, ",vertex_size=0,edge_size=");
    put_num(b, bcap, &k, edge_size, 1, true);
    field_putf(b, bcap, &k, ",fill_transparency=");
    put_num(b, bcap, &k, transparency, 2, true);
    post(out, "VIEW_CIRCLE", b);
}

static bool circles_shown(const kelp_hazardsensor *h)
{
    return h->cfg.show_reports == -1 || h->cfg.show_reports > 0;
}

static void detection_report(kelp_hazardsensor *h, kelp_uhz_node *n, const kelp_uhz_object *o, kelp_time now,
                             const kelp_field_sink *out)
{
    char *b = h->ws_line, *var = h->ws_var; /* workspace (the stack stays under 1 KB) */
    size_t k = 0;
    object_spec(b, sizeof h->ws_line, &k, o, NULL, true);
    size_t body = k;
    field_putf(b, sizeof h->ws_line, &k, ",vname=%s", n->name);
    post(out, "UHZ_DETECTION_REPORT", b);
    b[body] = 0;
    var_for(var, sizeof h->ws_var, "UHZ_DETECTION_REPORT", n->name);
    post(out, var, b);
    if (n->passes < KELP_UHZ_MAX_PASSES) n->pass_hdg[(n->pass_i + n->passes) % KELP_UHZ_MAX_PASSES] = n->hdg;
    n->passes++;
    event(h, "Detection report sent to vehicle: %s", n->name);
    n->detects++;
    if (circles_shown(h)) post_circle(h, o, 12, "white", "white", 1, 0.3, true, now, out);
}

/* the aspect's degradation in [0, 1] for a vehicle heading hdg */
static double aspect_diff(double hdg, double aspect)
{
    double diff = fabs(angle180(hdg - aspect));
    return diff > 90 ? 180 - diff : diff; /* 24.8's aspectDiff: the aspect is a line, both ends count */
}

static double degrade(const kelp_uhz_object *o, double hdg)
{
    double diff = aspect_diff(hdg, o->aspect);
    if (diff <= o->aspect_min) return 0;
    if (diff >= o->aspect_max) return 1;
    double p = (diff - o->aspect_min) / (o->aspect_max - o->aspect_min);
    return p < 0 ? 0 : p > 1 ? 1 : p;
}

static bool roll_normal(kelp_hazardsensor *h, const kelp_uhz_node *n, const kelp_uhz_object *o, double roll)
{
    if (is_hazard(o)) return roll < n->pd;
    if (h->event) {
        char a[40], b[40];
        size_t ka = 0, kb = 0;
        put_num(a, sizeof a, &ka, n->pd, 5, false);
        put_num(b, sizeof b, &kb, n->pfa, 5, false);
        event(h, "DetectionNormal: pd: %s pfa:%s", a, b);
    }
    double thresh = n->pfa;
    if (!h->cfg.ignore_resemblances && o->has_hr) thresh = (n->pfa + o->hr) / 2;
    return roll < thresh;
}

static bool roll_aspect(kelp_hazardsensor *h, const kelp_uhz_node *n, const kelp_uhz_object *o, double roll)
{
    if (!o->has_aspect || !o->has_aspect_min || !o->has_aspect_max) return roll_normal(h, n, o, roll);
    double dp = degrade(o, n->hdg), new_exp = n->exp - dp * (n->exp - 1);
    double pfa = pow(n->pd, new_exp);
    if (h->event) {
        char a[48], b[48];
        size_t ka = 0, kb = 0;
        put_num(a, sizeof a, &ka, n->exp, 5, true);
        put_num(b, sizeof b, &kb, new_exp, 5, true);
        event(h, "cur_exp=%snew_exp=%s", a, b);
        ka = kb = 0;
        put_num(a, sizeof a, &ka, aspect_diff(n->hdg, o->aspect), 5, false);
        put_num(b, sizeof b, &kb, dp, 5, false);
        event(h, "aspect_diff=%s degrade_pct=%s", a, b);
        ka = kb = 0;
        put_num(a, sizeof a, &ka, n->pd, 5, false);
        put_num(b, sizeof b, &kb, pfa, 5, false);
        event(h, "DetectionAspect: pd: %s pfa:%s", a, b);
    }
    if (is_hazard(o)) return roll < n->pd;
    double thresh = pfa;
    if (!h->cfg.ignore_resemblances && o->has_hr) thresh = (pfa + o->hr) / 2;
    return roll < thresh;
}

static void post_swath(kelp_hazardsensor *h, const kelp_uhz_node *n, bool on, const kelp_field_sink *out)
{
    double c[4][2];
    swath_corners(n->x, n->y, n->hdg, n->width, h->cfg.swath_length, c);
    char *b = h->ws;
    const size_t cap = sizeof h->ws;
    size_t k = 0;
    field_putf(b, cap, &k, "pts={");
    for (int i = 0; i < 4; i++) {
        if (i) field_putf(b, cap, &k, ":");
        put_num(b, cap, &k, c[i][0], 1, true);
        field_putf(b, cap, &k, ",");
        put_num(b, cap, &k, c[i][1], 1, true);
    }
    field_putf(b, cap, &k, "},label=sensor_swath_%s,msg=", n->name);
    if (h->cfg.show_pd || h->cfg.show_pfa) {
        if (h->cfg.show_pfa && !h->cfg.show_pd) field_putf(b, cap, &k, "pfa=");
        if (h->cfg.show_pd) put_num(b, cap, &k, n->pd, 2, false);
        if (h->cfg.show_pd && h->cfg.show_pfa) field_putf(b, cap, &k, "/");
        if (h->cfg.show_pfa) put_num(b, cap, &k, n->pfa, 2, false);
    } else {
        field_putf(b, cap, &k, "_null_"); /* 24.8's polygon keeps its placeholder msg */
    }
    field_putf(b, cap, &k, ",edge_color=green,fill_color=%s,vertex_size=0,edge_size=0,fill_transparency=",
               on ? "white" : "red");
    put_num(b, cap, &k, h->cfg.swath_transparency, 2, true);
    post(out, "VIEW_POLYGON", b);
}

KELP_NOINLINE static void sense(kelp_hazardsensor *h, kelp_uhz_node *n, kelp_time now, const kelp_field_sink *out)
{
    post(out, "PSR", n->name);
    if (!n->have_report) {
        warn(h, out, "No NODE_REPORT received for %s", n->name);
        return;
    }
    if (!n->have_setting) (void)set_setting(h, n, 0, 0, true, now, out);
    bool on = !(turn_rate(n, KELP_UHZ_TURN_WINDOW) > h->cfg.max_turn_rate) && !(n->spd > h->cfg.max_vehicle_speed);
    if (!n->have_setting) {
        warn(h, out, "Cant update poly for: %s. swath_wid unknown", n->name);
        return;
    }
    if (h->cfg.show_swath) post_swath(h, n, on, out);
    if (!on) return;
    for (unsigned i = 0; i < h->cfg.nobjects; i++) {
        const kelp_uhz_object *o = &h->cfg.object[i];
        bool in = kelp_hazardsensor_in_swath(n->x, n->y, n->hdg, n->width, h->cfg.swath_length, o->x, o->y);
        uint8_t bit = (uint8_t)(1u << (i & 7));
        bool was = (n->inside[i >> 3] & bit) != 0;
        if (in) n->inside[i >> 3] |= bit;
        else n->inside[i >> 3] &= (uint8_t)~bit;
        if (!in || was) continue;
        if (is_hazard(o)) n->haz_chances++;
        else n->ben_chances++;
        double roll = (double)(kelp_rng_glibc_next(&h->rand) % 10000) / 10000;
        bool normal = roll_normal(h, n, o, roll);
        bool aspect = roll_aspect(h, n, o, roll); /* 24.8 rolls both, always */
        if (normal) {
            if (is_hazard(o)) n->haz_reports++;
            else n->ben_reports++;
            detection_report(h, n, o, now, out);
        } else if (aspect && circles_shown(h)) {
            post_circle(h, o, 12, "pink", "pink", 1, 0.3, true, now, out);
        }
    }
}

static int sensor_request(kelp_hazardsensor *h, const char *s, kelp_time now, const kelp_field_sink *out)
{
    char vname[KELP_NODEREPORT_MAX_FIELD];
    (void)value_of(s, "vname", vname, sizeof vname);
    if (!vname[0]) {
        warn(h, out, "Sensor detect request with null node name");
        return KELP_ERR_PARSE;
    }
    kelp_uhz_node *n = node_get(h, vname, out);
    if (!n) return KELP_ERR_NOSPACE;
    n->sensor_reqs++;
    n->have_request = true;
    n->last_request = now;
    return 1;
}

/* 24.8's ClassifyQueue: [0] is the active entry (served next, whatever its priority); the rest
 * wait highest priority first */
static void queue_insert(kelp_uhz_node *n, kelp_uhz_entry e)
{
    unsigned j = n->nqueue++;
    while (j > 1 && n->queue[j - 1].priority < e.priority) {
        n->queue[j] = n->queue[j - 1];
        j--;
    }
    n->queue[j] = e;
}

static void queue_push(kelp_uhz_node *n, kelp_uhz_entry e, bool top)
{
    if (top && n->nqueue > 0) { /* the active entry waits again, its priority kept */
        kelp_uhz_entry was = n->queue[0];
        n->queue[0] = e;
        queue_insert(n, was);
        return;
    }
    e.priority -= (double)n->queued_ever / QUEUE_ORDER_SCALE;
    n->queued_ever++;
    if (n->nqueue == 0) n->queue[n->nqueue++] = e;
    else queue_insert(n, e);
}

KELP_NOINLINE static int classify_request(kelp_hazardsensor *h, const char *s, kelp_time now,
                                          const kelp_field_sink *out)
{
    if (!h || !s) return KELP_ERR_ARG;
    char *vname = h->ws_vname, *label = h->ws_label, pr[32] = "50", act[16]; /* workspace: the stack */
    (void)value_of(s, "vname", vname, sizeof h->ws_vname);
    (void)value_of(s, "label", label, sizeof h->ws_label);
    if (!value_of(s, "priority", pr, sizeof pr)) copyn(pr, sizeof pr, "50", 2);
    (void)value_of(s, "action", act, sizeof act);
    int ni = kelp_hazardsensor_find(h, vname);
    kelp_uhz_node *n = ni < 0 ? NULL : &h->node[ni];
    if (n && n->have_queue && strcmp(act, "clear") == 0) {
        n->nqueue = 0;
        event(h, "Classify Queue cleared for %s", n->name);
        return 1;
    }
    if (h->ws_vname[0] && !n) n = node_get(h, h->ws_vname, out);
    if (n) n->classify_reqs++;
    double priority;
    if (!h->ws_vname[0]) {
        warn(h, out, "Classify request with null vehicle name");
        return KELP_ERR_PARSE;
    }
    if (!label[0]) {
        warn(h, out, "Classify request with null label");
        return KELP_ERR_PARSE;
    }
    if (num(pr, strlen(pr), &priority) < 0) {
        warn(h, out, "Classify request with bad priority:%s", pr);
        return KELP_ERR_PARSE;
    }
    unsigned oi = h->cfg.nobjects;
    for (unsigned i = 0; i < h->cfg.nobjects; i++)
        if (strcmp(h->cfg.object[i].label, label) == 0) oi = i;
    if (oi == h->cfg.nobjects) {
        warn(h, out, "%s class req for unknown haz label:%s", vname, label);
        return KELP_ERR_NOTFOUND;
    }
    if (!n || !n->have_setting) {
        warn(h, out, "Error: No classifier config info for: %s", vname);
        return KELP_ERR_NOTFOUND;
    }
    if (n->passes == 0) {
        warn(h, out, "Sensor classify request saturated: %s", n->name);
        return KELP_ERR_DENIED;
    }
    if (n->nqueue >= KELP_UHZ_MAX_QUEUE) {
        warn(h, out, "uFldHazardSensor: classify queue full for %s (KELP_UHZ_MAX_QUEUE)", n->name);
        return KELP_ERR_NOSPACE;
    }
    double hdg = n->pass_hdg[n->pass_i];
    n->pass_i = (n->pass_i + 1) % KELP_UHZ_MAX_PASSES;
    n->passes--;
    const kelp_uhz_object *o = &h->cfg.object[oi];
    bool truth = is_hazard(o);
    double pc = n->pclass, pcp = pc;
    if (!truth && o->has_hr && !h->cfg.ignore_resemblances) pcp += (1 - pc) * (1 - o->hr);
    double pcdp = pcp;
    if (o->has_aspect && o->has_aspect_min && o->has_aspect_max) pcdp = 0.5 + (1 - degrade(o, hdg)) * (pcp - 0.5);
    double dice = (double)(kelp_rng_glibc_next(&h->rand) % 10001) / 10000;
    bool said = truth, affected = false;
    if (dice > pcdp) {
        said = !truth;
        if (dice <= pcp) affected = true;
    }
    if (h->event) {
        char t[160];
        size_t k = 0;
        field_putf(t, sizeof t, &k, "pc=");
        put_num(t, sizeof t, &k, pc, 5, false);
        field_putf(t, sizeof t, &k, ", pcp=");
        put_num(t, sizeof t, &k, pcp, 5, false);
        field_putf(t, sizeof t, &k, ", pcdb=");
        put_num(t, sizeof t, &k, pcdp, 5, false);
        field_putf(t, sizeof t, &k, ", dice=");
        put_num(t, sizeof t, &k, dice, 5, false);
        field_putf(t, sizeof t, &k, ", aff=%s", affected ? "true" : "false");
        event(h, "%s", t);
    }
    kelp_uhz_entry e = { oi, said, affected, priority };
    bool top = strcmp(act, "top") == 0;
    bool reset = n->nqueue == 0 || top;
    n->have_queue = true;
    queue_push(n, e, top);
    if (reset) n->last_classify = now;
    return 1;
}

KELP_NOINLINE static int node_report(kelp_hazardsensor *h, const char *s, kelp_time now, const kelp_field_sink *out)
{
    kelp_nodereport *r = &h->ws_report; /* workspace: no report on the stack */
    if (kelp_nodereport_parse(s, strlen(s), r, NULL) < 0 || !(r->fields & KELP_NR_X) || !(r->fields & KELP_NR_Y)) {
        post(out, "UHZ_DEBUG", "Invalid incoming node report");
        warn(h, out, "ERROR: Unhandled node record");
        return KELP_ERR_PARSE;
    }
    kelp_uhz_node *n = node_get(h, r->name, out);
    if (!n) return KELP_ERR_NOSPACE;
    n->have_report = true;
    n->x = r->x;
    n->y = r->y;
    n->hdg = (r->fields & KELP_NR_HDG) ? r->hdg : 0;
    n->spd = (r->fields & KELP_NR_SPD) ? r->spd : 0;
    hist_add(n, n->hdg, now);
    return 1;
}

/* An object's aspect as 24.8 draws it: a gray line through it along the aspect, 15 m each way,
 * or 5 + 25 x (mean of aspect_min and aspect_max) / 90 when both are given. */
KELP_NOINLINE static void post_aspect_line(kelp_hazardsensor *h, const kelp_uhz_object *o, const kelp_field_sink *out)
{
    double len = 15;
    if (o->has_aspect_min && o->has_aspect_max) len = 5 + ((o->aspect_min + o->aspect_max) / 2.0 / 90) * 25;
    double e[2][2];
    project(o->aspect, len, o->x, o->y, &e[0][0], &e[0][1]);
    project(o->aspect + 180, len, o->x, o->y, &e[1][0], &e[1][1]);
    char *b = h->ws;
    const size_t cap = sizeof h->ws;
    size_t k = 0;
    field_putf(b, cap, &k, "pts={");
    for (int i = 0; i < 2; i++) {
        field_putf(b, cap, &k, i ? ":" : "");
        put_num(b, cap, &k, e[i][0], 1, true);
        field_putf(b, cap, &k, ",");
        put_num(b, cap, &k, e[i][1], 1, true);
    }
    field_putf(b, cap, &k, "},edge_color=gray70,vertex_size=0,edge_size=1");
    post(out, "VIEW_SEGLIST", b);
}

static void post_markers(kelp_hazardsensor *h, const kelp_field_sink *out)
{
    const kelp_hazardsensor_cfg *c = &h->cfg;
    if (!c->show_hazards) return;
    for (unsigned i = 0; i < c->nobjects; i++) {
        const kelp_uhz_object *o = &c->object[i];
        bool hz = is_hazard(o);
        char *b = h->ws;
        const size_t bcap = sizeof h->ws;
        size_t k = 0;
        field_putf(b, bcap, &k, "x=");
        put_num(b, bcap, &k, o->x, 2, true);
        field_putf(b, bcap, &k, ",y=");
        put_num(b, bcap, &k, o->y, 2, true);
        field_putf(b, bcap, &k, ",width=");
        put_num(b, bcap, &k, o->width >= 0 ? o->width : hz ? c->hazard_width : c->benign_width, 2, true);
        field_putf(b, bcap, &k, ",primary_color=%s,type=%s,label=%s",
                   o->color[0] ? o->color : hz ? c->hazard_color : c->benign_color,
                   o->shape[0] ? o->shape : hz ? c->hazard_shape : c->benign_shape, o->label);
        if (!hz) { /* a benign marker shows its resemblance (0.5 unless hr given) */
            double t = 1 - o->hr;
            field_putf(b, bcap, &k, ",fill_transparency=");
            put_num(b, bcap, &k, t < 0 ? 0 : t > 1 ? 1 : t, 2, true);
        }
        post(out, "VIEW_MARKER", b);
        if (o->has_aspect && o->aspect > 0) post_aspect_line(h, o, out);
    }
}

/* The time step rule: a `now` that is no time is refused; on a step back the sensor's own times
 * (the summary, each vehicle's last reset, request and classify answer) move back with it, so
 * min_reset_interval, a request's life and min_classify_interval last no longer than set */
static bool uhz_clock(kelp_hazardsensor *h, kelp_time now)
{
    if (!kelp_util_time_ok(now)) return false;
    double back = kelp_util_clock_back(&h->clk, now);
    if (back > 0) {
        h->last_summary -= back;
        for (unsigned i = 0; i < h->nnodes; i++) {
            kelp_uhz_node *n = &h->node[i];
            n->reset_time -= back, n->pd_reset_time -= back;
            n->last_request -= back, n->last_classify -= back;
        }
    }
    return true;
}

int kelp_hazardsensor_mail(kelp_hazardsensor *h, const char *var, const char *sval, const char *community, kelp_time now,
                        const kelp_field_sink *out)
{
    int rc;
    if (!uhz_clock(h, now)) return KELP_ERR_ARG;
    if (strcmp(var, "PMV_CONNECT") == 0) {
        post_markers(h, out);
        return 1;
    }
    if (!sval) sval = "";
    if (strcmp(var, "NODE_REPORT") == 0) rc = node_report(h, sval, now, out);
    else if (strcmp(var, "UHZ_SENSOR_REQUEST") == 0) rc = sensor_request(h, sval, now, out);
    else if (strcmp(var, "UHZ_CONFIG_REQUEST") == 0) rc = config_request(h, sval, community, now, out);
    else if (strcmp(var, "UHZ_CLASSIFY_REQUEST") == 0) rc = classify_request(h, sval, now, out);
    else return 0;
    if (rc < 0) warn(h, out, "Unhandled mail: %s", var);
    return rc;
}

void kelp_hazardsensor_iterate(kelp_hazardsensor *h, kelp_time now, const kelp_field_sink *out)
{
    if (!uhz_clock(h, now)) return;
    if (h->markers_due) {
        h->markers_due = false;
        post_markers(h, out);
    }
    if (!h->summary_posted || now - h->last_summary >= h->cfg.options_summary_interval) {
        post(out, "UHZ_OPTIONS_SUMMARY", h->cfg.summary);
        h->summary_posted = true;
        h->last_summary = now;
    }
    for (unsigned i = 0; i < h->nnodes; i++) {
        kelp_uhz_node *n = &h->node[i];
        if (n->have_request && now - n->last_request < KELP_UHZ_REQUEST_LIFE) sense(h, n, now, out);
    }
    for (unsigned i = 0; i < h->nnodes; i++) {
        kelp_uhz_node *n = &h->node[i];
        if (!n->have_queue) continue;
        if (now - n->last_classify < h->cfg.min_classify_interval || n->nqueue == 0) continue;
        n->last_classify = now;
        kelp_uhz_entry e = n->queue[0];
        memmove(&n->queue[0], &n->queue[1], (n->nqueue - 1) * sizeof n->queue[0]);
        n->nqueue--;
        const kelp_uhz_object *o = &h->cfg.object[e.obj];
        char *b = h->ws_line, *var = h->ws_var;
        size_t k = 0;
        field_putf(b, sizeof h->ws_line, &k, "vname=%s,", n->name);
        size_t body = k;
        object_spec(b, sizeof h->ws_line, &k, o, e.said_hazard ? "hazard" : "benign", false);
        var_for(var, sizeof h->ws_var, "UHZ_HAZARD_REPORT", n->name);
        post(out, var, b + body);
        n->classify_answ++;
        post(out, "UHZ_HAZARD_REPORT", b);
        if (circles_shown(h)) {
            const char *c = e.said_hazard ? "red" : "white";
            post_circle(h, o, 5, c, e.aspect_affected ? "pink" : c, e.aspect_affected ? 2 : 1,
                        e.aspect_affected ? 0.5 : 0.3, false, now, out);
        }
    }
}

/* ---- the AppCast report ---- */

typedef struct report_ctx {
    const kelp_hazardsensor *h;
    kelp_time start;
    unsigned *rows; /* vehicles with a setting, by name */
} report_ctx;

static const char *settings_cell(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap)
{
    static const char *const head[4] = { "Width", "Exp", "Classify", "Max" };
    const kelp_hazardsensor *h = ctx;
    if (row == 0) return head[col];
    const kelp_uhz_setting *s = &h->cfg.setting[row - 1];
    size_t k = 0;
    if (col == 3) field_putf(tmp, cap, &k, "%u", s->max);
    else put_num(tmp, cap, &k, col == 0 ? s->width : col == 1 ? s->exp : s->pclass, col == 2 ? 3 : 1, false);
    return tmp;
}

static const char *vehicle_cell(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap)
{
    static const char *const head[2][8] = {
        { "Vehicle", "Swath", "", "", "", "Try Swath", "Swath", "Pd" },
        { "Name", "Width", "Pd", "Pfa", "Pclass", "Resets", "Resets", "Resets" } };
    const report_ctx *c = ctx;
    if (row < 2) return head[row][col];
    const kelp_uhz_node *n = &c->h->node[c->rows[row - 2]];
    size_t k = 0;
    tmp[0] = 0;
    switch (col) {
    case 0: return n->name;
    case 1: put_num(tmp, cap, &k, n->width, 1, false); break;
    case 2: put_num(tmp, cap, &k, n->pd, 3, false); break;
    case 3: put_num(tmp, cap, &k, n->pfa, 3, false); break;
    case 4: put_num(tmp, cap, &k, n->pclass, 3, false); break;
    case 5: field_putf(tmp, cap, &k, "%lu", n->reset_tries); break;
    case 6:
        field_putf(tmp, cap, &k, "%lu(", n->resets);
        put_num(tmp, cap, &k, n->resets ? n->reset_time - c->start : 0, 0, false);
        field_putf(tmp, cap, &k, ")");
        break;
    default:
        field_putf(tmp, cap, &k, "%lu(", n->pd_resets);
        put_num(tmp, cap, &k, n->pd_resets ? n->pd_reset_time - c->start : 0, 0, false);
        field_putf(tmp, cap, &k, ")");
        break;
    }
    return tmp;
}

static const char *stats_cell(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap)
{
    static const char *const head[2][7] = {
        { "Vehicle", "Sensor", "", "FA", "Det", "Classify", "Classify" },
        { "Name", "Reqs", "Detections", "Rate", "Rate", "Requests", "Answers" } };
    const report_ctx *c = ctx;
    if (row < 2) return head[row][col];
    const kelp_uhz_node *n = &c->h->node[c->rows[row - 2]];
    size_t k = 0;
    tmp[0] = 0;
    unsigned long hits = 0, chances = 0;
    switch (col) {
    case 0: return n->name;
    case 1: field_putf(tmp, cap, &k, "%lu", n->sensor_reqs); return tmp;
    case 2: field_putf(tmp, cap, &k, "%lu", n->detects); return tmp;
    case 3: hits = n->ben_reports, chances = n->ben_chances; break;
    case 4: hits = n->haz_reports, chances = n->haz_chances; break;
    case 5: field_putf(tmp, cap, &k, "%lu", n->classify_reqs); return tmp;
    default: field_putf(tmp, cap, &k, "%lu", n->classify_answ); return tmp;
    }
    if (!chances) return "n/a";
    put_num(tmp, cap, &k, (double)hits / (double)chances, 2, false);
    return tmp;
}

int kelp_hazardsensor_report(const kelp_hazardsensor *h, const char *file, kelp_time start, char *buf, size_t cap)
{
    size_t n = 0;
    bool full = false;
    unsigned rows[KELP_UHZ_MAX_NODES], nrows = 0;
    if (cap) buf[0] = 0;
    for (unsigned i = 0; i < h->nnodes; i++)
        if (h->node[i].have_setting) rows[nrows++] = i;
    report_ctx c = { h, start, rows };
    broker_put(buf, cap, &n, &full, "Hazard File: (%s) \n     Hazard: %u\n     Benign: %u\n\n", file ? file : "None provided.",
               h->cfg.nhazard, h->cfg.nbenign);
    broker_put(buf, cap, &n, &full, RULE "\nSensor Configuration Options\n" RULE "\n");
    broker_table(buf, cap, &n, &full, 4, 1 + h->cfg.nsettings, 1, settings_cell, h);
    broker_put(buf, cap, &n, &full, "\n\n" RULE "\nSensor Settings / Stats for known vehicles: \n" RULE "\n");
    broker_table(buf, cap, &n, &full, 8, 2 + nrows, 2, vehicle_cell, &c);
    broker_put(buf, cap, &n, &full, "\n\n\n");
    broker_table(buf, cap, &n, &full, 7, 2 + nrows, 2, stats_cell, &c);
    broker_put(buf, cap, &n, &full, "\n");
    return full ? KELP_ERR_NOSPACE : KELP_OK;
}

/* ---- gen_hazards ---- */

bool kelp_hazardsensor_in_convex(const double (*pts)[2], size_t n, double x, double y)
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

int kelp_hazardsensor_random_point(const double (*pts)[2], size_t n, kelp_rng *rng, double *x, double *y)
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
        if (kelp_hazardsensor_in_convex(pts, n, px, py)) {
            *x = px;
            *y = py;
            return KELP_OK;
        }
    }
    return KELP_ERR_INFEASIBLE;
}
