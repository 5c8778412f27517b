/* pNodeReporter's logic: NAV_* and the helm's state in, NODE_REPORT_LOCAL out (see
 * include/kelp/field.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>
#include <kelp/kv.h>
#include <kelp/mission.h>
#include <kelp/util.h>

static const char *const nav_suffix[KELP_NREP_NAV] = { "_X",     "_Y",       "_LAT",   "_LONG", "_SPEED",
                                                       "_HEADING", "_DEPTH", "_YAW", "_HEADING_OVER_GROUND" };
static const char *const helm_vars[] = { "IVPHELM_STATE", "IVPHELM_SUMMARY", "IVPHELM_ALLSTOP", "NODE_COLOR_CHANGE" };
#define NHELM (sizeof helm_vars / sizeof helm_vars[0])
#define NREP_PI 3.14159265358979323846

static void set_text(char *dst, size_t cap, const char *src)
{
    size_t n = strlen(src);
    if (n >= cap) n = cap - 1;
    memcpy(dst, src, n);
    dst[n] = '\0';
}

void kelp_field_nrep_cfg_default(kelp_field_nrep_cfg *cfg, const char *community)
{
    memset(cfg, 0, sizeof *cfg);
    set_text(cfg->name, sizeof cfg->name, community ? community : "");
    set_text(cfg->type, sizeof cfg->type, "UUV");
    set_text(cfg->out_var, sizeof cfg->out_var, "NODE_REPORT_LOCAL");
    set_text(cfg->plat_var, sizeof cfg->plat_var, "PLATFORM_REPORT_LOCAL");
    set_text(cfg->prefix, sizeof cfg->prefix, "NAV");
    cfg->nohelm_threshold = 5;
    cfg->dep_key = true; /* NodeRecord::getSpec (24.8) writes DEP= */
    cfg->nav_grace_period = -1;
    cfg->extrap_pos = 0.25;
    cfg->extrap_hdg = 1;
    cfg->extrap_gap = 5;
}

static bool usable(const char *s)
{
    return !strpbrk(s, ",=");
}

/* The "K=V" items of a comma list are read in place (spans, no copies: these run in the
 * firmware's configuration path). @return the count, or KELP_ERR_RANGE when there are more
 * than cap or a key or value does not fit a name. */
static int items_check(const char *spec, int cap)
{
    int n = 0;
    size_t pos = 0;
    const char *k, *v;
    size_t kl, vl;
    int rc;
    while ((rc = kelp_kv_next(spec, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        if (n >= cap || kl >= KELP_MAX_NAME || vl >= KELP_MAX_NAME) return KELP_ERR_RANGE;
        n++;
    }
    return rc < 0 ? rc : n;
}

/* the next item of a list that items_check() passed; val "" when the item has no '=' */
static bool item_next(const char *spec, size_t *pos, const char **k, size_t *kl, const char **v, size_t *vl)
{
    if (kelp_kv_next(spec, ',', pos, k, kl, v, vl) != 1) return false;
    if (!*v) *v = "", *vl = 0;
    return true;
}

static void span_text(char *dst, size_t cap, const char *v, size_t vl)
{
    if (vl >= cap) vl = cap - 1;
    memcpy(dst, v, vl);
    dst[vl] = '\0';
}

static bool span_usable(const char *v, size_t vl)
{
    return vl > 0 && !memchr(v, ',', vl) && !memchr(v, '=', vl);
}

static bool span_num(const char *v, size_t vl, double *d)
{
    return kelp_util_parse_double(v, vl, d) == KELP_OK && isfinite(*d);
}

int kelp_field_nrep_add_plat(kelp_field_nrep_cfg *cfg, const char *spec, kelp_diag *d)
{
    kelp_nrep_plat p;
    memset(&p, 0, sizeof p);
    /* "VAR" first (a bare name), then gap=, alias= pairs */
    const char *comma = strchr(spec, ','), *end = comma ? comma : spec + strlen(spec);
    while (*spec == ' ' || *spec == '\t') spec++;
    while (end > spec && (end[-1] == ' ' || end[-1] == '\t')) end--;
    if (end == spec || (size_t)(end - spec) >= sizeof p.var || memchr(spec, '=', (size_t)(end - spec)) ||
        memchr(spec, ' ', (size_t)(end - spec))) {
        return kelp_fail(d, KELP_ERR_PARSE, "expected VAR, gap=S, alias=A");
    }
    memcpy(p.var, spec, (size_t)(end - spec));
    int n = comma ? items_check(comma + 1, 3) : 0;
    if (n < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "expected VAR, gap=S, alias=A");
    }
    size_t pos = 0, kl, vl;
    const char *k, *v;
    while (n > 0 && item_next(comma + 1, &pos, &k, &kl, &v, &vl)) {
        if (kelp_util_strieq_n(k, kl, "gap") && span_num(v, vl, &p.gap)) {
            if (p.gap < 0) p.gap = 0;
        } else if (kelp_util_strieq_n(k, kl, "alias") && span_usable(v, vl)) {
            span_text(p.alias, sizeof p.alias, v, vl);
        } else {
            return kelp_fail(d, KELP_ERR_PARSE, "unknown or bad item (gap=S, alias=A)");
        }
    }
    for (unsigned i = 0; i < cfg->nplat; i++)
        if (!strcmp(cfg->plat[i].var, p.var)) {
            return kelp_fail(d, KELP_ERR_EXISTS, "variable given twice");
        }
    if (cfg->nplat >= KELP_NREP_MAX_PLAT) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many plat_report_input entries");
    }
    cfg->plat[cfg->nplat++] = p;
    return KELP_OK;
}

int kelp_field_nrep_add_rider(kelp_field_nrep_cfg *cfg, const char *spec, kelp_diag *d)
{
    int n = items_check(spec, 6);
    kelp_nrep_rider r;
    memset(&r, 0, sizeof r);
    r.prec = -1;
    size_t pos = 0, kl, vl;
    const char *k, *v;
    while (n > 0 && item_next(spec, &pos, &k, &kl, &v, &vl)) {
        double dv;
        if (kelp_util_strieq_n(k, kl, "var") && vl > 0) {
            span_text(r.var, sizeof r.var, v, vl);
        } else if (kelp_util_strieq_n(k, kl, "rfld") && span_usable(v, vl)) {
            span_text(r.field, sizeof r.field, v, vl);
        } else if (kelp_util_strieq_n(k, kl, "policy") && (kelp_util_strieq_n(v, vl, "always") || kelp_util_strieq_n(v, vl, "updated"))) {
            r.updated_only = kelp_util_strieq_n(v, vl, "updated");
        } else if (kelp_util_strieq_n(k, kl, "prec") && span_num(v, vl, &dv) && dv >= 0 && dv <= 9 && dv == (int)dv) {
            r.prec = (int)dv;
        } else {
            return kelp_fail(d, KELP_ERR_PARSE, "expected var=V, policy=always|updated, rfld=F, prec=0..9");
        }
    }
    if (n <= 0 || !r.var[0]) {
        return kelp_fail(d, KELP_ERR_PARSE, "a rider needs var=");
    }
    if (!r.field[0]) set_text(r.field, sizeof r.field, r.var);
    if (cfg->nriders >= KELP_NREP_MAX_RIDERS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many riders");
    }
    cfg->rider[cfg->nriders++] = r;
    return KELP_OK;
}

int kelp_field_nrep_parse_fill(const char *s, kelp_nrep_fill *out)
{
    static const char *const names[] = { "literal", "fill-empty", "use-latest", "global", "local" };
    char t[16];
    size_t n = strlen(s);
    if (n >= sizeof t) return KELP_ERR_PARSE;
    for (size_t i = 0; i <= n; i++) t[i] = s[i] == '_' ? '-' : s[i];
    for (int i = 0; i < 5; i++)
        if (kelp_util_strieq(t, names[i])) {
            *out = (kelp_nrep_fill)i;
            return KELP_OK;
        }
    return KELP_ERR_PARSE;
}

int kelp_field_nrep_init(kelp_field_nrep *r, const kelp_field_nrep_cfg *cfg, kelp_time now)
{
    memset(r, 0, sizeof *r);
    if (!cfg->name[0] || !usable(cfg->name) || !usable(cfg->type) || !usable(cfg->group) || !usable(cfg->color) ||
        !cfg->out_var[0] || !cfg->prefix[0] || (cfg->have_length && !(cfg->length >= 0 && isfinite(cfg->length))) ||
        !(cfg->blackout_interval >= 0) || !(cfg->blackout_variance >= 0) || !(cfg->nohelm_threshold > 0))
        return KELP_ERR_ARG;
    r->cfg = *cfg;
    for (int k = 0; k < 2; k++) {
        const char *pre = k ? cfg->alt_prefix : cfg->prefix;
        r->nav[k].last = -1;
        for (int i = 0; i < KELP_NREP_NAV && pre[0]; i++) {
            int n = kelp_util_snprintf(r->nav[k].var[i], sizeof r->nav[k].var[i], "%s%s", pre, nav_suffix[i]);
            if (n < 0 || (size_t)n >= sizeof r->nav[k].var[i]) return KELP_ERR_RANGE;
        }
    }
    if (!usable(cfg->alt_name) || !usable(cfg->alt_group)) return KELP_ERR_ARG;
    memcpy(r->color, cfg->color, sizeof r->color);
    r->start = now;
    r->helm_last = -1;
    r->last_post = -1;
    set_text(r->allstop, sizeof r->allstop, "unknown"); /* NodeReporter: ALLSTOP=unknown until the helm says */
    r->blackout = cfg->blackout_interval;
    for (unsigned i = 0; i < KELP_NREP_MAX_PLAT; i++) r->plat_sent[i] = -1;
    kelp_rng_seed(&r->rng, cfg->seed ^ 0x6a09e667f3bcc909ull);
    return KELP_OK;
}

const char *kelp_field_nrep_subscription(const kelp_field_nrep *r, unsigned i)
{
    if (i < KELP_NREP_NAV) return r->nav[0].var[i];
    i -= KELP_NREP_NAV;
    if (r->cfg.alt_prefix[0]) {
        if (i < KELP_NREP_NAV) return r->nav[1].var[i];
        i -= KELP_NREP_NAV;
    }
    if (i < NHELM) return helm_vars[i];
    i -= (unsigned)NHELM;
    if (i < r->cfg.nplat) return r->cfg.plat[i].var;
    i -= r->cfg.nplat;
    if (i < r->cfg.nriders) return r->cfg.rider[i].var;
    i -= r->cfg.nriders;
    if (i == 0 && r->cfg.mode_var[0]) return r->cfg.mode_var;
    return NULL;
}

/* strings go into a report field: drop separators, bound the length */
static void copy_field(char *dst, const char *src)
{
    size_t j = 0;
    for (size_t i = 0; src[i] && j + 1 < KELP_NODEREPORT_MAX_FIELD; i++)
        if (src[i] != ',' && src[i] != '=' && (unsigned char)src[i] >= 0x20) dst[j++] = src[i];
    dst[j] = 0;
}

static void warn(const kelp_field_sink *out, const char *msg)
{
    if (out && out->warn) out->warn(out->ctx, msg);
}

static void value_text(char *dst, bool is_string, const char *sval, double dval, int prec)
{
    if (is_string) {
        copy_field(dst, sval ? sval : "");
    } else {
        char b[64];
        if (prec >= 0) kelp_util_snprintf(b, sizeof b, "%.*f", prec, dval);
        else kelp_util_snprintf(b, sizeof b, "%.6g", dval);
        copy_field(dst, b);
    }
}

static int nav_mail(kelp_field_nrep *r, kelp_nrep_nav *nv, int i, const char *var, bool is_string, const char *sval, double dval,
                    const kelp_field_sink *out)
{
    double d = dval;
    if (is_string && (!sval || kelp_util_parse_double(sval, strlen(sval), &d) < 0)) d = NAN;
    if (!isfinite(d)) {
        char msg[KELP_MAX_NAME + 48];
        kelp_util_snprintf(msg, sizeof msg, "%s is not a finite number; ignored", var);
        r->bad_mail++;
        warn(out, msg);
        return KELP_ERR_RANGE;
    }
    nv->v[i] = d;
    nv->have[i] = true;
    nv->mail = true;
    r->nav_mail++;
    if (i == KELP_NREP_X || i == KELP_NREP_Y) nv->xy_seq = r->nav_mail;
    if (i == KELP_NREP_LAT || i == KELP_NREP_LON) nv->ll_seq = r->nav_mail;
    return 1;
}

int kelp_field_nrep_mail(kelp_field_nrep *r, const char *var, bool is_string, const char *sval, double dval,
                         const kelp_field_sink *out)
{
    int used = 0;
    for (int k = 0; k < (r->cfg.alt_prefix[0] ? 2 : 1); k++)
        for (int i = 0; i < KELP_NREP_NAV; i++)
            if (strcmp(var, r->nav[k].var[i]) == 0) return nav_mail(r, &r->nav[k], i, var, is_string, sval, dval, out);
    for (unsigned i = 0; i < r->cfg.nplat; i++)
        if (strcmp(var, r->cfg.plat[i].var) == 0) {
            value_text(r->plat_val[i], is_string, sval, dval, -1);
            r->plat_new[i] = true;
            used = 1;
        }
    for (unsigned i = 0; i < r->cfg.nriders; i++)
        if (strcmp(var, r->cfg.rider[i].var) == 0) {
            value_text(r->rider_val[i], is_string, sval, dval, r->cfg.rider[i].prec);
            r->rider_have[i] = r->rider_new[i] = true;
            used = 1;
        }
    if (!is_string || !sval) return used;
    if (strcmp(var, "IVPHELM_STATE") == 0) {
        copy_field(r->helm_state, sval);
        r->helm_mail = true;
        if (!strncmp(sval, "MALCONFIG", 9)) copy_field(r->allstop, "n/a");
    } else if (strcmp(var, "IVPHELM_ALLSTOP") == 0) {
        copy_field(r->allstop, sval);
    } else if (strcmp(var, "IVPHELM_SUMMARY") == 0) {
        /* the helm's modes ("modes=MODE@ACTIVE:LOITERING"; "none" without modes) */
        char modes[KELP_NODEREPORT_MAX_FIELD * 2];
        if (kelp_kv_get(sval, ',', "modes", modes, sizeof modes) == 1) copy_field(r->helm_modes, modes);
        r->helm_mail = true;
    } else if (strcmp(var, "NODE_COLOR_CHANGE") == 0) {
        if (r->cfg.allow_color_change && sval[0]) copy_field(r->color, sval);
    } else if (r->cfg.mode_var[0] && strcmp(var, r->cfg.mode_var) == 0) {
        copy_field(r->mode, sval);
    } else {
        return used;
    }
    return 1;
}

static double wrap180(double a)
{
    a = fmod(a, 360.0);
    if (a > 180) a -= 360;
    if (a <= -180) a += 360;
    return a;
}

/* Could a receiver have extrapolated this report from the last one? */
static bool extrapolable(const kelp_field_nrep *r, const kelp_nodereport *n, kelp_time now)
{
    double dt = now - r->posted_at.time;
    if (!r->cfg.extrap || r->posted == 0 || !(dt > 0) || dt >= r->cfg.extrap_gap) return false;
    double a = (90.0 - r->posted_at.hdg) * NREP_PI / 180.0;
    double ex = r->posted_at.x + cos(a) * r->posted_at.spd * dt, ey = r->posted_at.y + sin(a) * r->posted_at.spd * dt;
    return hypot(n->x - ex, n->y - ey) < r->cfg.extrap_pos && fabs(wrap180(n->hdg - r->posted_at.hdg)) < r->cfg.extrap_hdg;
}

static void mode_of(const kelp_field_nrep *r, kelp_time now, char *mode, size_t cap)
{
    if (r->mode[0]) {
        set_text(mode, cap, r->mode);
    } else if (r->helm_last < 0) {
        set_text(mode, cap, "NOHELM-EVER");
    } else if (now - r->helm_last > r->cfg.nohelm_threshold) {
        kelp_util_snprintf(mode, cap, "NOHELM-%.0f", now - r->helm_last);
    } else if (!strncmp(r->helm_state, "DRIVE", 5) && r->helm_modes[0] && strcmp(r->helm_modes, "none") != 0) {
        set_text(mode, cap, r->helm_modes);
    } else {
        set_text(mode, cap, r->helm_state);
    }
}

/* extra "K=V" pairs: the platform aspect, then the riders due */
static void extras(kelp_field_nrep *r, char *buf, size_t cap)
{
    size_t o = 0;
    buf[0] = 0;
    if (r->cfg.aspect[0]) o = (size_t)kelp_util_snprintf(buf, cap, "%s", r->cfg.aspect);
    for (unsigned i = 0; i < r->cfg.nriders && o < cap; i++) {
        if (!r->rider_have[i] || (r->cfg.rider[i].updated_only && !r->rider_new[i])) continue;
        o += (size_t)kelp_util_snprintf(buf + o, cap - o, "%s%s=%s", o ? "," : "", r->cfg.rider[i].field, r->rider_val[i]);
        r->rider_new[i] = false;
    }
    if (o >= cap) buf[0] = 0; /* would not fit: none rather than half a pair */
}

/* the report as JSON: {"NAME":"alpha","X":51.71,...}, numbers as the text report has them */
static int to_json(const char *csp, char *buf, size_t cap)
{
    size_t o = 0, pos = 0;
    const char *k, *v;
    size_t kl, vl;
    int rc;
    if (cap < 3) return KELP_ERR_NOSPACE;
    buf[o++] = '{';
    while ((rc = kelp_kv_next(csp, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        double d;
        bool num = v && kelp_util_parse_double(v, vl, &d) == KELP_OK && isfinite(d);
        int w = kelp_util_snprintf(buf + o, cap - o, "%s\"%.*s\":%s%.*s%s", o > 1 ? "," : "", (int)kl, k, num ? "" : "\"",
                         (int)(v ? vl : 0), v ? v : "", num ? "" : "\"");
        if (w < 0 || (size_t)w >= cap - o) return KELP_ERR_NOSPACE;
        o += (size_t)w;
    }
    if (rc < 0 || o + 2 > cap) return KELP_ERR_NOSPACE;
    buf[o++] = '}';
    buf[o] = 0;
    return KELP_OK;
}

static void platform_report(kelp_field_nrep *r, kelp_time now, const kelp_field_sink *out)
{
    char *buf = r->ws.text;
    const size_t cap = sizeof r->ws.text;
    int o = kelp_util_snprintf(buf, cap, "platform=%s,utc_time=%.2f", r->cfg.name, now);
    bool any = false;
    for (unsigned i = 0; i < r->cfg.nplat; i++) {
        if (!r->plat_new[i] || (r->plat_sent[i] >= 0 && now - r->plat_sent[i] <= r->cfg.plat[i].gap)) continue;
        const char *nm = r->cfg.plat[i].alias[0] ? r->cfg.plat[i].alias : r->cfg.plat[i].var;
        int w = kelp_util_snprintf(buf + o, cap - (size_t)o, ",%s=%s", nm, r->plat_val[i]);
        if (w < 0 || (size_t)w >= cap - (size_t)o) break;
        o += w;
        r->plat_new[i] = false;
        r->plat_sent[i] = now;
        any = true;
    }
    if (any) out->publish(out->ctx, r->cfg.plat_var, true, buf, 0);
}

/* The report of one navigation solution; false when it is not valid (and no grace). */
static bool build(kelp_field_nrep *r, const kelp_nrep_nav *nv, const char *name, const char *group, kelp_time now,
                  const kelp_field_sink *out, kelp_nodereport *n)
{
    kelp_nodereport_init(n);
    n->x = nv->v[KELP_NREP_X], n->y = nv->v[KELP_NREP_Y], n->lat = nv->v[KELP_NREP_LAT], n->lon = nv->v[KELP_NREP_LON];
    bool xy = nv->have[KELP_NREP_X] && nv->have[KELP_NREP_Y], ll = nv->have[KELP_NREP_LAT] && nv->have[KELP_NREP_LON];
    if (xy) n->fields |= KELP_NR_X | KELP_NR_Y;
    if (ll) n->fields |= KELP_NR_LAT | KELP_NR_LON;
    if (r->cfg.have_geo && r->cfg.fill != KELP_NREP_FILL_LITERAL) {
        kelp_nrep_fill f = r->cfg.fill;
        /* drop the pair the policy recomputes; complete() then fills it from the other */
        if (ll && (f == KELP_NREP_FILL_GLOBAL || (f == KELP_NREP_FILL_LATEST && nv->ll_seq > nv->xy_seq)))
            n->fields &= ~(uint32_t)(KELP_NR_X | KELP_NR_Y);
        else if (xy && (f == KELP_NREP_FILL_LOCAL || (f == KELP_NREP_FILL_LATEST && nv->xy_seq >= nv->ll_seq)))
            n->fields &= ~(uint32_t)(KELP_NR_LAT | KELP_NR_LON);
        if (kelp_nodereport_complete(n, &r->cfg.geo) < 0) warn(out, "datum conversion failed");
    }
    bool pos = (n->fields & (KELP_NR_X | KELP_NR_Y)) == (KELP_NR_X | KELP_NR_Y) ||
               (n->fields & (KELP_NR_LAT | KELP_NR_LON)) == (KELP_NR_LAT | KELP_NR_LON);
    bool valid = pos && nv->have[KELP_NREP_SPD] && nv->have[KELP_NREP_HDG];
    if (!valid && !(r->cfg.nav_grace_period > 0 && now - r->start > r->cfg.nav_grace_period)) return false;
    set_text(n->name, sizeof n->name, name);
    memcpy(n->type, r->cfg.type, sizeof n->type);
    n->fields |= KELP_NR_NAME | KELP_NR_TYPE | KELP_NR_TIME | KELP_NR_SPD | KELP_NR_HDG | KELP_NR_DEPTH | KELP_NR_MODE;
    n->time = now;
    n->spd = nv->v[KELP_NREP_SPD];
    n->hdg = nv->v[KELP_NREP_HDG];
    if (r->cfg.hdg_error != 0) n->hdg = fmod(fmod(n->hdg + r->cfg.hdg_error, 360.0) + 360.0, 360.0);
    n->depth = nv->v[KELP_NREP_DEP];
    n->dep_key = r->cfg.dep_key;
    n->moos248 = !r->cfg.seed_format;
    if (nv->have[KELP_NREP_YAW]) {
        /* MOOS-IvP reports the heading as radians counter-clockwise from east in [-pi, pi] */
        double a = (90.0 - n->hdg) * NREP_PI / 180.0;
        n->yaw = atan2(sin(a), cos(a));
        n->fields |= KELP_NR_YAW;
    }
    if (r->cfg.have_length) n->length = r->cfg.length, n->fields |= KELP_NR_LENGTH;
    if (r->color[0]) memcpy(n->color, r->color, sizeof n->color), n->fields |= KELP_NR_COLOR;
    mode_of(r, now, n->mode, sizeof n->mode);
    if (!n->mode[0]) n->fields &= ~(uint32_t)KELP_NR_MODE;
    if (r->allstop[0]) memcpy(n->allstop, r->allstop, sizeof n->allstop), n->fields |= KELP_NR_ALLSTOP;
    if (group[0]) set_text(n->group, sizeof n->group, group), n->fields |= KELP_NR_GROUP;
    return true;
}

/* extra pairs: the platform aspect, COG, then the riders due */
static void extras_with_cog(kelp_field_nrep *r, const kelp_nrep_nav *nv, char *buf, size_t cap)
{
    extras(r, buf, cap);
    if (!r->cfg.report_cog || !nv->have[KELP_NREP_COG]) return;
    size_t o = strlen(buf);
    int w = kelp_util_snprintf(buf + o, cap - o, "%sCOG=%.2f", o ? "," : "", nv->v[KELP_NREP_COG]);
    if (w < 0 || (size_t)w >= cap - o) buf[o] = 0;
}

static int post(kelp_field_nrep *r, kelp_nodereport *n, const char *extra, bool first, const kelp_field_sink *out,
                char *text, size_t cap)
{
    n->extra = extra;
    size_t len;
    int rc = kelp_nodereport_format(n, text, cap, &len);
    if (rc < 0) {
        warn(out, "cannot format the report");
        return rc;
    }
    char *json = r->ws.json;
    bool want_json = r->cfg.json_only || r->cfg.json_var[0];
    if (want_json && to_json(text, json, sizeof r->ws.json) < 0) {
        warn(out, "cannot format the JSON report");
        want_json = false;
    }
    const char *main_text = r->cfg.json_only && want_json ? json : text;
    if (first) {
        char v[KELP_MAX_NAME + 8];
        kelp_util_snprintf(v, sizeof v, "%.*s_FIRST", KELP_MAX_NAME - 1, r->cfg.out_var);
        out->publish(out->ctx, v, true, main_text, 0);
    }
    out->publish(out->ctx, r->cfg.out_var, true, main_text, 0);
    if (want_json && r->cfg.json_var[0]) out->publish(out->ctx, r->cfg.json_var, true, json, 0);
    return KELP_OK;
}

int kelp_field_nrep_iterate(kelp_field_nrep *r, kelp_time now, const kelp_field_sink *out)
{
    if (!kelp_util_time_ok(now)) return 0;
    /* the time step rule (docs/ARCHITECTURE.md): after a backward step no time of our own clock
     * lies ahead of now, so the blackout and platform gaps last at most their length and no gap
     * or NOHELM age is negative */
    if (r->last_post > now) r->last_post = now;
    if (r->posted_at.time > now) r->posted_at.time = now;
    if (r->helm_last > now) r->helm_last = now;
    for (unsigned i = 0; i < KELP_NREP_MAX_PLAT; i++)
        if (r->plat_sent[i] > now) r->plat_sent[i] = now;
    if (r->helm_mail) r->helm_last = now, r->helm_mail = false;
    for (int k = 0; k < 2; k++)
        if (r->nav[k].mail) r->nav[k].last = now, r->nav[k].mail = false;
    if (r->cfg.paused) return 0;
    kelp_nodereport *n = &r->ws.main; /* (workspace) */
    if (!build(r, &r->nav[0], r->cfg.name, r->cfg.group, now, out, n)) return 0;
    if (r->last_post >= 0 && r->blackout > 0 && !(now - r->last_post > r->blackout)) return 0;
    if (extrapolable(r, n, now)) {
        r->extrap_skipped++;
        return 0;
    }
    n->index = (long)r->posted;
    if (r->posted) n->fields |= KELP_NR_INDEX;
    double px = n->x, py = n->y;
    if (r->cfg.coord_global && (n->fields & KELP_NR_LAT)) n->fields &= ~(uint32_t)(KELP_NR_X | KELP_NR_Y);
    char *extra = r->ws.extra;
    extras_with_cog(r, &r->nav[0], extra, sizeof r->ws.extra);
    int rc = post(r, n, extra, r->posted == 0, out, r->last, sizeof r->last);
    if (rc < 0) return rc;
    out->publish(out->ctx, "PNR_POST_GAP", false, NULL, r->posted ? now - r->posted_at.time : 0);
    r->posted_at.x = px, r->posted_at.y = py, r->posted_at.hdg = n->hdg, r->posted_at.spd = n->spd;
    r->posted_at.time = now;
    r->posted++;
    r->last_post = now;
    r->blackout = r->cfg.blackout_interval;
    if (r->cfg.blackout_variance > 0)
        r->blackout += r->cfg.blackout_variance * kelp_rng_range(&r->rng, -1.0, 1.0);
    if (r->blackout < 0) r->blackout = 0;
    /* the alternate solution (e.g. ground truth), while it is being updated */
    if (r->cfg.alt_prefix[0] && r->nav[1].last >= 0 && now - r->nav[1].last < 5) {
        char name[KELP_NODEREPORT_MAX_FIELD * 2];
        const char *an = r->cfg.alt_name[0] ? r->cfg.alt_name : "_GT";
        kelp_util_snprintf(name, sizeof name, "%s%s", an[0] == '_' ? r->cfg.name : "", an);
        kelp_nodereport *g = &r->ws.alt;
        if (build(r, &r->nav[1], name, r->cfg.alt_group[0] ? r->cfg.alt_group : r->cfg.group, now, out, g)) {
            g->index = (long)r->posted;
            g->fields |= KELP_NR_INDEX;
            if (r->cfg.coord_global && (g->fields & KELP_NR_LAT)) g->fields &= ~(uint32_t)(KELP_NR_X | KELP_NR_Y);
            extras_with_cog(r, &r->nav[1], extra, sizeof r->ws.extra);
            if (post(r, g, extra, false, out, r->ws.text, sizeof r->ws.text) == KELP_OK) r->alt_posted++;
        }
    }
    platform_report(r, now, out);
    return 1;
}
