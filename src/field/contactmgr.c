/* pContactMgrV20's state machine: contacts, alerts, filters, retirement, summaries
 * (include/kelp/contactmgr.h; shared/spec/contactmgr.md). */
#include <math.h>
#include <string.h>
#include <kelp/contactmgr.h>
#include <kelp/cpa.h>
#include <kelp/kv.h>
#include <kelp/nodereport.h>
#include <kelp/util.h>
#include "field_int.h"

#define PI 3.14159265358979323846

/* a warning formatted in the manager's workspace (c->ws_warn: no message buffer on the stack) */
static void warnf(kelp_contactmgr *c, const kelp_field_sink *out, const char *fmt, ...) KELP_PRINTF(3, 4);
static void warnf(kelp_contactmgr *c, const kelp_field_sink *out, const char *fmt, ...)
{
    if (!out || !out->warn) return;
    va_list ap;
    va_start(ap, fmt);
    (void)kelp_util_vsnprintf(c->ws_warn, sizeof c->ws_warn, fmt, ap);
    va_end(ap);
    out->warn(out->ctx, c->ws_warn);
}

static void post_s(const kelp_field_sink *out, const char *var, const char *s)
{
    if (out && out->publish) out->publish(out->ctx, var, true, s, 0);
}

static void post_d(const kelp_field_sink *out, const char *var, double d)
{
    if (out && out->publish) out->publish(out->ctx, var, false, NULL, d);
}

static void event(kelp_contactmgr *c, kelp_time now, const char *fmt, ...) KELP_PRINTF(3, 4);
static void event(kelp_contactmgr *c, kelp_time now, const char *fmt, ...)
{
    unsigned i = c->event_head;
    va_list ap;
    va_start(ap, fmt);
    (void)kelp_util_vsnprintf(c->event[i], sizeof c->event[i], fmt, ap);
    va_end(ap);
    c->event_time[i] = now - (c->t_start < 0 ? now : c->t_start);
    c->event_head = (i + 1) % KELP_CMGR_MAX_EVENTS;
    if (c->nevents < KELP_CMGR_MAX_EVENTS) c->nevents++;
    c->events_made++;
}

const char *kelp_contactmgr_event(const kelp_contactmgr *c, unsigned long seq)
{
    if (seq >= c->events_made || c->events_made - seq > c->nevents) return NULL;
    unsigned back = (unsigned)(c->events_made - seq); /* 1 = the newest */
    return c->event[(c->event_head + KELP_CMGR_MAX_EVENTS - back) % KELP_CMGR_MAX_EVENTS];
}

static void copyz(char *dst, size_t cap, const char *s, size_t n)
{
    if (n >= cap) n = cap - 1;
    memcpy(dst, s, n);
    dst[n] = 0;
}


static void unquote(const char **p, size_t *n)
{
    if (*n >= 2 && (*p)[0] == '"' && (*p)[*n - 1] == '"') (*p)++, *n -= 2;
}

static bool keyis(const char *k, size_t kl, const char *a, const char *b)
{
    return kelp_util_strieq_n(k, kl, a) || (b && kelp_util_strieq_n(k, kl, b));
}

/* ------------------------------------------------------------------ text lists */

typedef struct sbuf {
    char *b;
    size_t cap, n;
    bool cut;
} sbuf;

static void sb_init(sbuf *s, char *b, size_t cap)
{
    s->b = b, s->cap = cap, s->n = 0, s->cut = false;
    b[0] = 0;
}

/* append sep (when not first) + item, whole or not at all */
static bool sb_item(sbuf *s, const char *sep, const char *item)
{
    if (s->cut) return false;
    size_t sl = s->n ? strlen(sep) : 0, il = strlen(item);
    if (s->n + sl + il + 1 > s->cap) {
        s->cut = true;
        return false;
    }
    memcpy(s->b + s->n, sep, sl);
    memcpy(s->b + s->n + sl, item, il + 1);
    s->n += sl + il;
    return true;
}

static void fmtx(char *buf, size_t cap, double v, unsigned dec)
{
    if (kelp_util_fmt_fixed(buf, cap, v, dec, true) < 0) copyz(buf, cap, "nan", 3);
}

static void fmtf(char *buf, size_t cap, double v, unsigned dec)
{
    if (kelp_util_fmt_fixed(buf, cap, v, dec, false) < 0) copyz(buf, cap, "nan", 3);
}

/* $[KEY] replaced by val throughout buf (in place, cut at cap) */
static void macro_sub(char *buf, size_t cap, const char *key, const char *val)
{
    for (int form = 0; form < 2; form++) { /* $(KEY), then $[KEY], as 24.8's macroExpand */
        char pat[40];
        int pl = kelp_util_snprintf(pat, sizeof pat, form ? "$[%s]" : "$(%s)", key);
        size_t vl = strlen(val);
        char *p = buf;
        while (pl > 0 && (p = strstr(p, pat)) != NULL) {
            size_t tail = strlen(p + pl);
            if ((size_t)(p - buf) + vl + tail + 1 > cap) return;
            memmove(p + vl, p + pl, tail + 1);
            memcpy(p, val, vl);
            p += vl;
        }
    }
}

/* a manager-level flag "VAR=value": its variable into c->ws_flag[0]; a number is posted as a
 * double (its event with 4 decimals at most, as 24.8's postFlags). @return true when posted. */
static bool flag_number(kelp_contactmgr *c, const char *flag, kelp_time now, const kelp_field_sink *out)
{
    const char *eq = strchr(flag, '=');
    char *var = c->ws_flag[0];
    copyz(var, KELP_CMGR_MAX_FLAG, flag, (size_t)(eq - flag));
    double d;
    if (kelp_util_parse_finite(eq + 1, strlen(eq + 1), &d) < 0) return false;
    char num[48];
    fmtx(num, sizeof num, d, 4);
    post_d(out, var, d);
    event(c, now, "%s=%s", var, num);
    return true;
}

/* ------------------------------------------------------------------ init */

static void filter_init(kelp_contactmgr_filter *f)
{
    memset(f, 0, sizeof *f);
    f->strict_ignore = true;
}

void kelp_contactmgr_init(kelp_contactmgr *c, const char *ownship)
{
    memset(c, 0, sizeof *c);
    copyz(c->ownship, sizeof c->ownship, ownship ? ownship : "", ownship ? strlen(ownship) : 0);
    c->contact_max_age = 60; /* 24.8's ContactMgrV20 constructor */
    c->reject_range = 2000;
    c->decay[0] = 15, c->decay[1] = 30;
    c->recap_interval = 1;
    c->coords = KELP_CMGR_LAZY_LATLON; /* 24.8's ledger derives x/y from LAT/LON */
    c->range_report_timeout = 10;
    c->max_contacts = 500;
    c->max_retired = 5;
    c->range_report_maxsize = 20;
    memcpy(c->alert_color, "gray65", 7);
    memcpy(c->ewarn_color, "green", 6);
    filter_init(&c->filter);
    c->prev_closest_range = NAN;
    c->prev_relbng = NAN;
    c->last_recap = -INFINITY;
    c->t_start = -1;
    c->early_warning_time = -1;
    for (unsigned i = 0; i < KELP_CMGR_MAX_CONTACTS; i++) c->spare[i] = (uint16_t)(KELP_CMGR_MAX_CONTACTS - 1 - i);
    c->nspare = KELP_CMGR_MAX_CONTACTS;
}

double kelp_contactmgr_cpa_range(const kelp_contactmgr_alert *a)
{
    return a->cpa_range;
}

/* ------------------------------------------------------------------ filters */

/* "a,b, c" or "{a,b}" into a list (case kept; compared case-insensitively) */
static int filter_add_list(kelp_contactmgr *c, kelp_contactmgr_filter *f, int kind, int ign, const char *v, size_t vl,
                           const kelp_field_sink *out, bool quiet)
{
    kelp_util_trim(&v, &vl);
    if (vl >= 2 && v[0] == '{' && v[vl - 1] == '}') v++, vl -= 2;
    size_t pos = 0;
    const char *it;
    size_t il;
    int rc;
    while ((rc = field_next_item(v, vl, &pos, ',', &it, &il)) == 1) {
        unquote(&it, &il);
        if (il == 0) continue;
        if (il >= KELP_CMGR_NAME) {
            warnf(c, out, "filter entry too long: %.*s", (int)il, it);
            return KELP_ERR_RANGE;
        }
        bool dup = false;
        for (unsigned i = 0; i < f->nlist[kind][ign]; i++)
            if (kelp_util_strieq_n(it, il, f->list[kind][ign][i]) && strlen(f->list[kind][ign][i]) == il) dup = true;
        if (dup) continue;
        for (unsigned i = 0; i < f->nlist[kind][!ign]; i++)
            if (!quiet && kelp_util_strieq_n(it, il, f->list[kind][!ign][i]) && strlen(f->list[kind][!ign][i]) == il)
                warnf(c, out, "%.*s is both matched and ignored: ignored", (int)il, it);
        if (f->nlist[kind][ign] >= KELP_CMGR_MAX_FILTER) {
            warnf(c, out, "more than %d filter entries", KELP_CMGR_MAX_FILTER);
            return KELP_ERR_NOSPACE;
        }
        char *e = f->list[kind][ign][f->nlist[kind][ign]++];
        copyz(e, KELP_CMGR_NAME, it, il);
        for (char *q = e; *q; q++)
            if (*q >= 'A' && *q <= 'Z') *q = (char)(*q - 'A' + 'a');
    }
    return rc < 0 ? KELP_ERR_PARSE : 1;
}

static double cross(const double *o, const double *a, const double *b)
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

static int parse_poly(const char *v, size_t vl, kelp_contactmgr_poly *p, kelp_view *view)
{
    if (kelp_nodereport_view_parse(KELP_VIEW_POLYGON, v, vl, view, NULL) < 0 || view->npts < 3 ||
        view->npts > KELP_CMGR_MAX_REGION_PTS)
        return KELP_ERR_PARSE;
    p->n = (unsigned)view->npts;
    memcpy(p->pts, view->pts, sizeof(double) * 2 * view->npts);
    int sign = 0;
    for (unsigned i = 0; i < p->n; i++) {
        double z = cross(p->pts[i], p->pts[(i + 1) % p->n], p->pts[(i + 2) % p->n]);
        int s = z > 1e-9 ? 1 : z < -1e-9 ? -1 : 0;
        if (s && sign && s != sign) return KELP_ERR_ARG; /* not convex */
        if (s) sign = s;
    }
    return sign ? KELP_OK : KELP_ERR_ARG;
}

static bool in_poly(const kelp_contactmgr_poly *p, double x, double y)
{
    int sign = 0;
    double pt[2] = { x, y };
    for (unsigned i = 0; i < p->n; i++) {
        double z = cross(p->pts[i], p->pts[(i + 1) % p->n], pt);
        int s = z > 0 ? 1 : z < 0 ? -1 : 0;
        if (s && sign && s != sign) return false;
        if (s) sign = s;
    }
    return true;
}

static int filter_add_region(kelp_contactmgr *c, kelp_contactmgr_filter *f, int ign, const char *v, size_t vl,
                             const kelp_field_sink *out)
{
    kelp_view *ws = &c->ws.view;
    if (f->nregion[ign] >= KELP_CMGR_MAX_REGIONS) {
        warnf(c, out, "more than %d regions", KELP_CMGR_MAX_REGIONS);
        return KELP_ERR_NOSPACE;
    }
    int rc = parse_poly(v, vl, &f->region[ign][f->nregion[ign]], ws);
    if (rc < 0) {
        warnf(c, out, "%s: %.*s", rc == KELP_ERR_ARG ? "non-convex region" : "bad region", (int)vl, v);
        return rc;
    }
    f->nregion[ign]++;
    return 1;
}

static bool listed(const kelp_contactmgr_filter *f, int kind, int ign, const char *s)
{
    /* 24.8's ExFilterSet: entries are kept in lower case; a name is compared in lower case, a
     * type or group as reported (so "KAYAK" never matches match_type=KAYAK) */
    for (unsigned i = 0; i < f->nlist[kind][ign]; i++)
        if (kind == 0 ? kelp_util_strieq(f->list[kind][ign][i], s) : strcmp(f->list[kind][ign][i], s) == 0) return true;
    return false;
}

/* contactmgr.md 4.9: every kind must pass; any ignore hit rejects */
static bool filter_ok(const kelp_contactmgr_filter *f, const char *name, const char *type, const char *group, double x,
                      double y)
{
    const char *val[3] = { name, type, group };
    for (int k = 0; k < 3; k++) {
        if (f->nlist[k][0] && !listed(f, k, 0, val[k])) return false;
        if (f->nlist[k][1]) {
            if (k > 0 && f->strict_ignore && !val[k][0]) return false;
            if (listed(f, k, 1, val[k])) return false;
        }
    }
    if (f->nregion[0]) {
        bool in = false;
        for (unsigned i = 0; i < f->nregion[0] && !in; i++) in = in_poly(&f->region[0][i], x, y);
        if (!in) return false;
    }
    for (unsigned i = 0; i < f->nregion[1]; i++)
        if (in_poly(&f->region[1][i], x, y)) return false;
    return true;
}

/* a filter key of either level: 1 taken, 0 not a filter key, <0 bad value */
static int filter_param(kelp_contactmgr *c, kelp_contactmgr_filter *f, const char *k, size_t kl, const char *v, size_t vl,
                        const kelp_field_sink *out, bool *is_strict)
{
    static const char *const kinds[3] = { "name", "type", "group" };
    *is_strict = false;
    for (int ign = 0; ign < 2; ign++) {
        const char *pre = ign ? "ignore_" : "match_";
        size_t pl = strlen(pre);
        if (kl <= pl || !kelp_util_strieq_n(k, pl, pre)) continue;
        for (int kind = 0; kind < 3; kind++)
            if (kelp_util_strieq_n(k + pl, kl - pl, kinds[kind])) return filter_add_list(c, f, kind, ign, v, vl, out, false);
        if (kelp_util_strieq_n(k + pl, kl - pl, "region")) return filter_add_region(c, f, ign, v, vl, out);
    }
    if (kelp_util_strieq_n(k, kl, "strict_ignore")) {
        *is_strict = true;
        bool b;
        if (kelp_util_parse_bool(v, vl, &b) < 0) {
            warnf(c, out, "strict_ignore must be true or false: %.*s", (int)vl, v);
            return KELP_ERR_PARSE;
        }
        f->strict_ignore = b;
        return 1;
    }
    return 0;
}

/* ------------------------------------------------------------------ alerts */

static int alert_find(const kelp_contactmgr *c, const char *id, size_t il)
{
    for (unsigned i = 0; i < c->nalerts; i++)
        if (strlen(c->alert[i].id) == il && memcmp(c->alert[i].id, id, il) == 0) return (int)i;
    return -1;
}

/* alert indices in ascending id order (24.8 keeps its alerts in a map by id) */
static unsigned sorted_alerts(const kelp_contactmgr *c, unsigned *ids)
{
    unsigned n = 0;
    for (unsigned i = 0; i < c->nalerts; i++) {
        unsigned j = n++;
        while (j > 0 && strcmp(c->alert[ids[j - 1]].id, c->alert[i].id) > 0) ids[j] = ids[j - 1], j--;
        ids[j] = i;
    }
    return n;
}

/* 24.8's CMAlert::valid: an alert range given and a flag */
static bool alert_valid(const kelp_contactmgr_alert *a)
{
    return a->alert_range >= 0 && (a->non + a->noff) > 0;
}

/* an id disabled by action=disable (24.8 keeps these ids apart from the alerts) */
static bool alert_is_off(const kelp_contactmgr *c, const char *id)
{
    for (unsigned i = 0; i < c->nalert_off; i++)
        if (strcmp(c->alert_off[i], id) == 0) return true;
    return false;
}

static void alert_set_off(kelp_contactmgr *c, const char *id, bool off)
{
    for (unsigned i = 0; i < c->nalert_off; i++)
        if (strcmp(c->alert_off[i], id) == 0) {
            if (!off) memmove(c->alert_off[i], c->alert_off[i + 1], (size_t)(--c->nalert_off - i) * KELP_CMGR_MAX_ID);
            return;
        }
    if (off && c->nalert_off < KELP_CMGR_MAX_ALERTS) copyz(c->alert_off[c->nalert_off++], KELP_CMGR_MAX_ID, id, strlen(id));
}

/* "VAR=value" (value quotes stripped) into a flag list, unless there already */
static int add_flag(char (*list)[KELP_CMGR_MAX_FLAG], unsigned *n, const char *v, size_t vl)
{
    kelp_util_trim(&v, &vl);
    unquote(&v, &vl);
    const char *eq = memchr(v, '=', vl);
    if (!eq) return KELP_ERR_PARSE;
    const char *var = v, *val = eq + 1;
    size_t varl = (size_t)(eq - v), vall = vl - varl - 1;
    kelp_util_trim(&var, &varl);
    kelp_util_trim(&val, &vall);
    unquote(&val, &vall);
    if (varl == 0 || vall == 0 || varl + vall + 2 > KELP_CMGR_MAX_FLAG) return KELP_ERR_PARSE;
    char f[KELP_CMGR_MAX_FLAG];
    memcpy(f, var, varl);
    f[varl] = '=';
    memcpy(f + varl + 1, val, vall);
    f[varl + 1 + vall] = 0;
    for (unsigned i = 0; i < *n; i++)
        if (strcmp(list[i], f) == 0) return 1;
    if (*n >= KELP_CMGR_MAX_FLAGS) return KELP_ERR_NOSPACE;
    memcpy(list[(*n)++], f, varl + vall + 2);
    return 1;
}

/* an off_flag value: flags separated by '#' (24.8's addAlertOffFlag; an on_flag is one flag) */
static int add_off_flags(kelp_contactmgr_alert *a, const char *v, size_t vl)
{
    size_t s = 0;
    for (size_t i = 0; i <= vl; i++)
        if (i == vl || v[i] == '#') {
            int rc = add_flag(a->off, &a->noff, v + s, i - s);
            if (rc < 0) return rc;
            s = i + 1;
        }
    return 1;
}

#define MAX_COMPS KELP_CMGR_MAX_COMPS
typedef kelp_contactmgr_comp comp;

/* the components of a spec, split at commas outside quotes and braces (24.8's parseStringQ);
 * a component without '=' is a key with an empty value */
static int split_comps(const char *spec, comp *cp, unsigned *ncp)
{
    size_t len = strlen(spec), s = 0;
    bool q = false;
    unsigned brace = 0;
    *ncp = 0;
    for (size_t i = 0; i <= len; i++) {
        if (i < len) {
            char ch = spec[i];
            if (ch == '"') q = !q;
            else if (ch == '{') brace++;
            else if (ch == '}' && brace) brace--;
            if (ch != ',' || q || brace) continue;
        }
        const char *it = spec + s;
        size_t il = i - s;
        s = i + 1;
        if (i == len && il == 0) break;
        if (*ncp >= MAX_COMPS) return KELP_ERR_NOSPACE;
        comp *p = &cp[(*ncp)++];
        const char *eq = memchr(it, '=', il);
        p->k = it, p->kl = eq ? (size_t)(eq - it) : il;
        kelp_util_trim(&p->k, &p->kl);
        const char *v = eq ? eq + 1 : it + il;
        size_t vl = eq ? il - (size_t)(v - it) : 0;
        kelp_util_trim(&v, &vl);
        unquote(&v, &vl);
        if (vl + 1 > sizeof p->v) return KELP_ERR_RANGE;
        memcpy(p->v, v, vl);
        p->v[vl] = 0;
        p->vl = vl;
    }
    return KELP_OK;
}

static int num_ge0(const char *v, size_t vl, double *out)
{
    return kelp_util_parse_finite(v, vl, out) < 0 || *out < 0 ? KELP_ERR_PARSE : KELP_OK;
}

/* 24.8's isNumber and atof for a range value */
static bool range_num(const char *v, size_t vl, double *d)
{
    return kelp_util_parse_finite(v, vl, d) == 0;
}

/* a component 24.8 does not take: its two warnings (the component, then for mail the request) */
static int spec_reject(kelp_contactmgr *c, const kelp_field_sink *out, bool from_mail, const char *spec, const char *k,
                       size_t kl)
{
    char low[KELP_CMGR_MAX_ID];
    size_t n = 0;
    for (; n < kl && n + 1 < sizeof low; n++) low[n] = (k[n] >= 'A' && k[n] <= 'Z') ? (char)(k[n] + 32) : k[n];
    low[n] = 0;
    warnf(c, out, "unhandled alert config component: %s", low);
    if (from_mail) warnf(c, out, "Unhandled Alert Request: %s", spec);
    return KELP_ERR_PARSE;
}

/* the seed's var=/val= pair as one on_flag "VAR=val" (its buffer off the component path) */
KELP_NOINLINE static int legacy_flag(kelp_contactmgr_alert *a, const char *var, const char *val)
{
    char f[KELP_CMGR_MAX_FLAG];
    int fl = kelp_util_snprintf(f, sizeof f, "%s=%s", var, val ? val : "");
    if (fl < 0 || (size_t)fl >= sizeof f) return KELP_ERR_NOSPACE;
    return add_flag(a->on, &a->non, f, (size_t)fl);
}

/* 24.8's handleConfigAlert: the id (no id: "no_id"); "action=disable"/"action=enable" anywhere
 * in the spec turns the id off or on and is all; else the alert is made (or found) and its
 * components applied in order, in place, until one is not taken: that one is warned and the
 * rest dropped (the components before it stay, the alert stays) */
int kelp_contactmgr_alert_spec(kelp_contactmgr *c, const char *spec, bool from_mail, const char *src, kelp_time now,
                         const kelp_field_sink *out)
{
    comp *cp = c->ws.comp;
    unsigned n;
    (void)now; /* (kept in the interface: the request's time) */
    if (split_comps(spec, cp, &n) < 0) {
        warnf(c, out, "alert too long or with too many components: %s", spec);
        return KELP_ERR_RANGE;
    }
    char *id = c->ws_flag[1]; /* (a workspace) */
    memcpy(id, "no_id", 6);
    for (unsigned i = 0; i < n; i++)
        if (kelp_util_strieq_n(cp[i].k, cp[i].kl, "id") && cp[i].vl) {
            copyz(id, KELP_CMGR_MAX_ID, cp[i].v, cp[i].vl);
            break;
        }
    char *low = c->ws.str;
    size_t sl = strlen(spec);
    if (sl >= sizeof c->ws.str) sl = sizeof c->ws.str - 1;
    for (size_t i = 0; i < sl; i++) low[i] = (spec[i] >= 'A' && spec[i] <= 'Z') ? (char)(spec[i] + 32) : spec[i];
    low[sl] = 0;
    bool dis = strstr(low, "action=disable") != NULL;
    if (dis || strstr(low, "action=enable")) {
        if (strcmp(id, "no_id") != 0) alert_set_off(c, id, dis); /* (no event of its own, as 24.8) */
        return 1;
    }
    int ai = alert_find(c, id, strlen(id));
    if (ai < 0) {
        if (c->nalerts >= KELP_CMGR_MAX_ALERTS) {
            warnf(c, out, "more than %d alerts: %s dropped", KELP_CMGR_MAX_ALERTS, id);
            return KELP_ERR_NOSPACE;
        }
        ai = (int)c->nalerts++;
        kelp_contactmgr_alert *na = &c->alert[ai];
        memset(na, 0, sizeof *na);
        filter_init(&na->filter);
        na->alert_range = na->cpa_range = -1;
        copyz(na->id, sizeof na->id, id, strlen(id));
        for (unsigned k = 0; k < KELP_CMGR_MAX_CONTACTS; k++) c->contact[k].alerted &= ~(1u << ai);
    }
    kelp_contactmgr_alert *a = &c->alert[ai];
    if (src && src[0]) copyz(a->source, sizeof a->source, src, strlen(src));
    const char *legacy_var = NULL, *legacy_val = NULL;
    for (unsigned i = 0; i < n; i++) {
        const char *k = cp[i].k, *v = cp[i].v;
        size_t kl = cp[i].kl, vl = cp[i].vl;
        double d;
        bool strict;
        int rc = 1;
        if (keyis(k, kl, "id", NULL)) continue;
        if (keyis(k, kl, "var", NULL))
            legacy_var = v;
        else if (keyis(k, kl, "val", "pattern"))
            legacy_val = v;
        else if (keyis(k, kl, "on_flag", "onflag"))
            rc = add_flag(a->on, &a->non, v, vl);
        else if (keyis(k, kl, "off_flag", "offflag"))
            rc = add_off_flags(a, v, vl);
        else if (keyis(k, kl, "alert_range", NULL)) {
            if (!range_num(v, vl, &d) || d < 0) rc = KELP_ERR_PARSE;
            else {
                a->alert_range = d;
                if (a->cpa_range < d) a->cpa_range = d;
            }
        } else if (keyis(k, kl, "cpa_range", NULL)) {
            if (!range_num(v, vl, &d) || d < 0) rc = KELP_ERR_PARSE;
            else {
                a->cpa_range = d;
                if (a->alert_range > d) a->alert_range = d;
            }
        } else {
            rc = filter_param(c, &a->filter, k, kl, v, vl, out, &strict);
            if (rc == 0) rc = KELP_ERR_PARSE;
        }
        if (rc < 0) return spec_reject(c, out, from_mail, spec, k, kl);
    }
    if (legacy_var && legacy_val && legacy_var[0] && legacy_val[0] && legacy_flag(a, legacy_var, legacy_val) < 0)
        warnf(c, out, "alert %s: var/val flag too long", a->id);
    return 1;
}

/* ------------------------------------------------------------------ configuration */

/* a value 24.8 does not take (why: what it takes): the line is not handled, the default stays
 * (the app warns as 24.8's reportUnhandledConfigWarning: "Unhandled config line: key=value") */
static int cfg_bad(kelp_contactmgr *c, const kelp_field_sink *out, const char *key, const char *val, const char *why)
{
    (void)c, (void)out, (void)key, (void)val, (void)why;
    return 0;
}

#define CONFIG_FILTER 2 /* config_other: not one of its parameters */
KELP_NOINLINE static int config_other(kelp_contactmgr *c, const char *key, const char *val, const kelp_field_sink *out);
KELP_NOINLINE static int config_filter(kelp_contactmgr *c, const char *key, const char *val, const kelp_field_sink *out);

int kelp_contactmgr_config(kelp_contactmgr *c, const char *key, const char *val, const kelp_field_sink *out)
{
    if (keyis(key, strlen(key), "alert", NULL)) /* a bad component: warned, and the line is unhandled (24.8) */
        return kelp_contactmgr_alert_spec(c, val, false, NULL, 0, out) < 0 ? 0 : 1;
    /* 24.8's handleConfigDeprecations: the older names are warned, then taken */
    static const char *const renamed[3][2] = { { "default_alert_range_color", "alert_range_color" },
                                               { "default_cpa_range_color", "cpa_range_color" },
                                               { "contacts_recap_interval", "recap_interval" } };
    for (int i = 0; i < 3; i++)
        if (kelp_util_strieq(key, renamed[i][0]))
            warnf(c, out, "%s is deprecated. Use instead: %s", renamed[i][0], renamed[i][1]);
    int rc = config_other(c, key, val, out); /* (its locals off the alert path) */
    return rc == CONFIG_FILTER ? config_filter(c, key, val, out) : rc;
}

static int config_other(kelp_contactmgr *c, const char *key, const char *val, const kelp_field_sink *out)
{
    size_t kl = strlen(key), vl = strlen(val);
    const char *v = val;
    kelp_util_trim(&v, &vl);
    double d;
    bool b;
    if (keyis(key, kl, "contact_max_age", "max_contact_age")) {
        if (num_ge0(v, vl, &d) < 0) return cfg_bad(c, out, key, val, "must be a number >= 0");
        c->contact_max_age = d;
        return 1;
    }
    if (keyis(key, kl, "reject_range", NULL)) {
        if (kelp_util_strieq_n(v, vl, "off")) c->reject_range = -1;
        else if (kelp_util_parse_finite(v, vl, &d) < 0 || d <= 0) return cfg_bad(c, out, key, val, "must be > 0 or off");
        else c->reject_range = d;
        return 1;
    }
    if (keyis(key, kl, "recap_interval", "contacts_recap_interval")) {
        if (kelp_util_strieq_n(v, vl, "off")) c->recap_interval = -1;
        else if (num_ge0(v, vl, &d) < 0) return cfg_bad(c, out, key, val, "must be >= 0 or off");
        else c->recap_interval = d;
        return 1;
    }
    if (keyis(key, kl, "range_report_timeout", NULL)) {
        if (num_ge0(v, vl, &d) < 0) return cfg_bad(c, out, key, val, "must be a number >= 0");
        c->range_report_timeout = d;
        return 1;
    }
    if (keyis(key, kl, "decay", NULL)) {
        const char *comma = memchr(v, ',', vl);
        double d2;
        if (!comma || num_ge0(v, (size_t)(comma - v), &d) < 0 ||
            num_ge0(comma + 1, vl - (size_t)(comma - v) - 1, &d2) < 0 || d2 < d)
            return cfg_bad(c, out, key, val, "must be a,b with 0 <= a <= b");
        c->decay[0] = d, c->decay[1] = d2;
        return 1;
    }
    long l;
    if (keyis(key, kl, "max_contacts", NULL)) {
        if (kelp_util_parse_long(v, vl, &l) < 0 || l < 1) return cfg_bad(c, out, key, val, "must be an integer >= 1");
        if (l > KELP_CMGR_MAX_CONTACTS) {
            warnf(c, out, "max_contacts %ld above this build's %d: clamped", l, KELP_CMGR_MAX_CONTACTS);
            l = KELP_CMGR_MAX_CONTACTS;
        }
        c->max_contacts = (unsigned)l;
        return 1;
    }
    if (keyis(key, kl, "max_retired_history", "max_retired_hist")) {
        if (kelp_util_parse_long(v, vl, &l) < 0) return cfg_bad(c, out, key, val, "must be an integer in [1,50]");
        if (l < 1 || l > 50) {
            warnf(c, out, "max_retired_hist should be in range [1,50]");
            l = l < 1 ? 1 : 50;
        }
        c->max_retired = (unsigned)l;
        return 1;
    }
    if (keyis(key, kl, "range_report_maxsize", NULL)) {
        if (kelp_util_parse_long(v, vl, &l) < 0 || l < 1) return cfg_bad(c, out, key, val, "must be an integer >= 1");
        c->range_report_maxsize = (unsigned)l; /* (storage holds KELP_CMGR_MAX_REPORTS) */
        return 1;
    }
    struct { const char *k, *alias; bool *dst; } bools[] = {
        { "alert_verbose", NULL, &c->alert_verbose },       { "display_radii", NULL, &c->display_radii },
        { "post_all_ranges", NULL, &c->post_all_ranges },   { "post_closest_range", NULL, &c->post_closest_range },
        { "post_closest_relbng", NULL, &c->post_closest_relbng },
        { "hold_alerts_for_helm", NULL, &c->hold_alerts_for_helm },
        { "early_warning_radii", NULL, &c->early_warning_radii },
    };
    for (size_t i = 0; i < sizeof bools / sizeof bools[0]; i++)
        if (keyis(key, kl, bools[i].k, bools[i].alias)) {
            if (kelp_util_parse_bool(v, vl, &b) < 0) return cfg_bad(c, out, key, val, "must be true or false");
            *bools[i].dst = b;
            return 1;
        }
    if (keyis(key, kl, "cpa_range_color", "default_cpa_range_color") || keyis(key, kl, "display_radii_id", NULL))
        return 1; /* 24.8 takes these and uses neither */
    struct { const char *k, *alias; char *dst; } strs[] = {
        { "alert_range_color", "default_alert_range_color", c->alert_color },
        { "ewarn_radii_color", NULL, c->ewarn_color },
        { "ownship_group", NULL, c->ownship_group },
        { "ownship_type", NULL, c->ownship_type },
    };
    for (size_t i = 0; i < sizeof strs / sizeof strs[0]; i++)
        if (keyis(key, kl, strs[i].k, strs[i].alias)) {
            copyz(strs[i].dst, KELP_CMGR_MAX_ID, v, vl);
            return 1;
        }
    if (keyis(key, kl, "contact_local_coords", NULL)) {
        if (kelp_util_strieq_n(v, vl, "verbatim")) c->coords = KELP_CMGR_VERBATIM;
        else if (kelp_util_strieq_n(v, vl, "lazy_lat_lon")) c->coords = KELP_CMGR_LAZY_LATLON;
        else if (kelp_util_strieq_n(v, vl, "force_lat_lon")) c->coords = KELP_CMGR_FORCE_LATLON;
        return 1; /* (24.8 takes any value and ignores it) */
    }
    if (keyis(key, kl, "alert_range", "alert_cpa_range")) { /* 24.8: warned, then unhandled */
        warnf(c, out, "%s is deprecated", kelp_util_strieq(key, "alert_range") ? "alert_range" : "alert_cpa_range");
        return 0;
    }
    struct { const char *k; char *dst; } vars[] = {
        { "disable_var", c->disable_var }, { "enable_var", c->enable_var }, { "expunge_var", c->expunge_var } };
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
        if (keyis(key, kl, vars[i].k, NULL)) {
            for (size_t j = 0; j < vl; j++)
                if (v[j] == ' ' || v[j] == '\t') return cfg_bad(c, out, key, val, "must be a variable name");
            copyz(vars[i].dst, KELP_CMGR_MAX_ID, v, vl);
            return 1;
        }
    struct { const char *k; char (*list)[KELP_CMGR_MAX_FLAG]; unsigned *n; } flags[] = {
        { "able_flag", c->able_flag, &c->nable_flag },       { "disable_flag", c->disable_flag, &c->ndisable_flag },
        { "enable_flag", c->enable_flag, &c->nenable_flag }, { "retire_flag", c->retire_flag, &c->nretire_flag },
        { "early_warning_flag", c->ewarn_flag, &c->newarn_flag }, { "cease_warning_flag", c->cwarn_flag, &c->ncwarn_flag } };
    for (size_t i = 0; i < sizeof flags / sizeof flags[0]; i++)
        if (keyis(key, kl, flags[i].k, NULL)) {
            if (add_flag(flags[i].list, flags[i].n, v, vl) < 0) return cfg_bad(c, out, key, val, "must be VAR=value");
            return 1;
        }
    if (keyis(key, kl, "early_warning_time", NULL)) {
        if (num_ge0(v, vl, &d) < 0) return cfg_bad(c, out, key, val, "must be a number >= 0");
        c->early_warning_time = d;
        return 1;
    }
    /* 24.8 features kelp does not implement yet: accepted so a 24.8 block loads */
    static const char *const later[] = { "app_logging" };
    for (size_t i = 0; i < sizeof later / sizeof later[0]; i++)
        if (keyis(key, kl, later[i], NULL)) return 1;
    return CONFIG_FILTER; /* a filter parameter or none: config_filter, off this frame */
}

/* the contact filter's parameters (match_*, ignore_*, strict_ignore) */
KELP_NOINLINE static int config_filter(kelp_contactmgr *c, const char *key, const char *val, const kelp_field_sink *out)
{
    size_t kl = strlen(key), vl = strlen(val);
    const char *v = val;
    bool strict;
    kelp_util_trim(&v, &vl);
    int rc = filter_param(c, &c->filter, key, kl, v, vl, out, &strict);
    return rc < 0 ? 0 : rc; /* a refused entry: the line is unhandled, as 24.8's */
}

void kelp_contactmgr_config_done(kelp_contactmgr *c, bool have_lat, double lat0, bool have_lon, double lon0,
                           const kelp_field_sink *out)
{
    for (unsigned i = 0; i < c->nalerts; i++)
        if (!alert_valid(&c->alert[i])) warnf(c, out, "Invalid alert config:%s", c->alert[i].id);
    c->have_geo = false;
    if (c->coords == KELP_CMGR_VERBATIM) return; /* (kelp's option: 24.8 always derives) */
    /* 24.8's OnStartUp and its ledger: x/y from LAT/LON for a report without X/Y */
    if (!have_lat || !have_lon) {
        warnf(c, out, "Lat or Lon Origin not set in *.moos file.");
        return;
    }
    if (kelp_geo_init(&c->geo, lat0, lon0) == 0) c->have_geo = true;
    else warnf(c, out, "Geodesy failed to initialize");
}

const char *kelp_contactmgr_subscription(unsigned i)
{
    static const char *const subs[] = { "NODE_REPORT", "NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED",
                                        "BCM_ALERT_REQUEST", "BCM_REPORT_REQUEST", "BCM_DISPLAY_RADII",
                                        "IVPHELM_STATE" };
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

/* ------------------------------------------------------------------ contacts */

int kelp_contactmgr_find(const kelp_contactmgr *c, const char *name)
{
    unsigned lo = 0, hi = c->ncontacts;
    while (lo < hi) {
        unsigned mid = (lo + hi) / 2;
        int r = strcmp(c->contact[c->order[mid]].name, name);
        if (r == 0) return c->order[mid];
        if (r < 0) lo = mid + 1;
        else hi = mid;
    }
    return -1;
}

static unsigned order_pos(const kelp_contactmgr *c, const char *name)
{
    unsigned lo = 0, hi = c->ncontacts;
    while (lo < hi) {
        unsigned mid = (lo + hi) / 2;
        if (strcmp(c->contact[c->order[mid]].name, name) < 0) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

static void retired_remove(kelp_contactmgr *c, const char *name)
{
    for (unsigned i = 0; i < c->nretired; i++)
        if (strcmp(c->retired[i], name) == 0) {
            memmove(c->retired[i], c->retired[i + 1], (size_t)(c->nretired - i - 1) * KELP_CMGR_NAME);
            c->nretired--;
            return;
        }
}

/* a name the filters refused since the last iteration (ascending, once; 24.8 retires it and
 * posts the retire flags for it at the next iteration, in the ledger or not) */
static void filtered_add(kelp_contactmgr *c, const char *name)
{
    unsigned i = 0;
    while (i < c->nfiltered && strcmp(c->filtered[i], name) < 0) i++;
    if ((i < c->nfiltered && strcmp(c->filtered[i], name) == 0) || c->nfiltered == KELP_CMGR_MAX_FILTERED) return;
    memmove(c->filtered[i + 1], c->filtered[i], (size_t)(c->nfiltered - i) * KELP_CMGR_NAME);
    copyz(c->filtered[i], KELP_CMGR_NAME, name, strlen(name));
    c->nfiltered++;
}

static int bad_report(kelp_contactmgr *c, const kelp_field_sink *out, const char *why)
{
    c->reports_bad++;
    warnf(c, out, "Bad Mail: NODE_REPORT:%s", why);
    return KELP_ERR_PARSE;
}

KELP_NOINLINE static int node_report(kelp_contactmgr *c, const char *s, kelp_time now, const kelp_field_sink *out)
{
    kelp_nodereport *r = &c->ws_report; /* workspace: no report on the stack */
    c->reports_in++;
    kelp_diag_clear(&c->diag);
    if (kelp_nodereport_parse(s, strlen(s), r, &c->diag) < 0) {
        /* 24.8 reads any text as a record: only a missing name is refused ("Empty vname") */
        const char *nm = strstr(kelp_diag_text(&c->diag), "no NAME") ? "Empty vname" : kelp_diag_text(&c->diag);
        return bad_report(c, out, nm);
    }
    if (kelp_util_strieq(r->name, c->ownship)) return 1;
    bool have_xy = (r->fields & (KELP_NR_X | KELP_NR_Y)) == (KELP_NR_X | KELP_NR_Y);
    bool have_ll = (r->fields & (KELP_NR_LAT | KELP_NR_LON)) == (KELP_NR_LAT | KELP_NR_LON);
    if (c->have_geo && have_ll && (c->coords == KELP_CMGR_FORCE_LATLON || !have_xy)) {
        if (kelp_geo_to_local(&c->geo, r->lat, r->lon, &r->x, &r->y) < 0) return bad_report(c, out, "bad LAT/LON");
        have_xy = true;
    }
    if (!have_xy) return bad_report(c, out, "no X/Y (LAT/LON are not used with contact_local_coords = verbatim)");
    if (!have_ll && c->have_geo && kelp_geo_to_latlon(&c->geo, r->x, r->y, &r->lat, &r->lon) == 0) have_ll = true;
    int ci = kelp_contactmgr_find(c, r->name);
    if (!filter_ok(&c->filter, r->name, r->type, r->group, r->x, r->y)) {
        if (ci >= 0) c->contact[ci].filtered = true;
        filtered_add(c, r->name);
        return 1;
    }
    /* the contact ledger (24.8's ContactLedger::processNodeRecord), after the manager's filter:
     * uuv becomes auv, an unknown type ship; an auv or glider without depth is refused with
     * 24.8's "1:<name>2:" (the name the ledger returned: none) */
    bool had_ll = (r->fields & (KELP_NR_LAT | KELP_NR_LON)) == (KELP_NR_LAT | KELP_NR_LON);
    if (kelp_nodereport_ledger(r, NULL, &c->diag) < 0) {
        char why[KELP_CMGR_NAME + 8];
        (void)kelp_util_snprintf(why, sizeof why, "1:%s2:", r->name);
        return bad_report(c, out, why);
    }
    if (ci < 0) {
        if (c->ncontacts >= KELP_CMGR_MAX_CONTACTS) {
            warnf(c, out, "more than %d contacts: %s dropped", KELP_CMGR_MAX_CONTACTS, r->name);
            return KELP_ERR_NOSPACE;
        }
        ci = c->spare[--c->nspare];
        unsigned pos = order_pos(c, r->name);
        memmove(&c->order[pos + 1], &c->order[pos], (c->ncontacts - pos) * sizeof c->order[0]);
        c->order[pos] = (uint16_t)ci;
        c->ncontacts++;
        kelp_contactmgr_contact *k = &c->contact[ci];
        memset(k, 0, sizeof *k);
        k->used = true;
        k->warned_range = -1;
        memcpy(k->name, r->name, sizeof k->name);
        k->range = k->range_extrap = k->range_cpa = hypot(c->osx - r->x, c->osy - r->y);
        if (c->alert_verbose) {
            char m[KELP_CMGR_NAME + 16];
            (void)kelp_util_snprintf(m, sizeof m, "new_contact=%s", r->name);
            post_s(out, "ALERT_VERBOSE", m);
        }
    }
    retired_remove(c, r->name); /* 24.8: at every accepted report */
    kelp_contactmgr_contact *k = &c->contact[ci];
    memcpy(k->type, r->type, sizeof k->type);
    memcpy(k->group, r->group, sizeof k->group);
    k->x = r->x, k->y = r->y;
    k->has_ll = have_ll;
    /* $[LAT]/$[LON] are the record's: 0 unless the report gave them (24.8 derives none) */
    k->lat = had_ll ? r->lat : 0, k->lon = had_ll ? r->lon : 0;
    k->hdg = r->fields & KELP_NR_HDG ? r->hdg : 0;
    k->spd = r->fields & KELP_NR_SPD ? r->spd : 0;
    k->dep = r->fields & KELP_NR_DEPTH ? r->depth : 0;
    k->time = r->fields & KELP_NR_TIME ? r->time : now;
    k->filtered = false;
    return 1;
}

/* ------------------------------------------------------------------ requests */

/* (out of line, here and below: their locals stay off kelp_contactmgr_mail's alert path) */
KELP_NOINLINE static int report_request(kelp_contactmgr *c, const char *s, kelp_time now, const char *src, const kelp_field_sink *out)
{
    size_t len = strlen(s), pos = 0, kl, vl;
    const char *p = s, *k, *v;
    kelp_util_trim(&p, &len);
    unquote(&p, &len);
    char *str = c->ws.str; /* (a workspace) */
    copyz(str, sizeof c->ws.str, p, len);
    char var[KELP_CMGR_MAX_ID] = "", group[KELP_CMGR_NAME] = "", type[KELP_CMGR_NAME] = "";
    double range = -1;
    bool refresh = false, bad = false;
    int rc;
    while (!bad && (rc = kelp_kv_next(str, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        unquote(&v, &vl);
        if (keyis(k, kl, "var", NULL)) {
            bad = vl == 0 || vl >= sizeof var;
            for (size_t i = 0; i < vl && !bad; i++) bad = v[i] == ' ' || v[i] == '\t';
            if (!bad) copyz(var, sizeof var, v, vl);
        } else if (keyis(k, kl, "range", NULL))
            bad = num_ge0(v, vl, &range) < 0;
        else if (keyis(k, kl, "group", NULL))
            copyz(group, sizeof group, v, vl);
        else if (keyis(k, kl, "type", NULL))
            copyz(type, sizeof type, v, vl);
        else if (keyis(k, kl, "refresh", NULL))
            refresh = kelp_util_strieq_n(v, vl, "true");
        else if (!keyis(k, kl, "reason", NULL))
            bad = true;
    }
    if (bad || rc < 0 || !var[0] || range < 0) {
        warnf(c, out, "Failed REPORT_REQUEST: %s", str);
        event(c, now, "Failed REPORT_REQUEST: %.*s", KELP_CMGR_MAX_FLAG, str);
        return KELP_ERR_PARSE;
    }
    event(c, now, "New BCM_REPORT_REQUEST (src=%s): %.*s", src ? src : "", KELP_CMGR_MAX_FLAG, str);
    kelp_contactmgr_report *r = NULL;
    for (unsigned i = 0; i < c->nreports; i++)
        if (strcmp(c->report[i].var, var) == 0) r = &c->report[i];
    if (!r) {
        if (c->nreports >= KELP_CMGR_MAX_REPORTS) { /* storage full (24.8 has none): the least recently requested goes */
            unsigned old = 0;
            for (unsigned i = 1; i < c->nreports; i++)
                if (c->report[i].req_time < c->report[old].req_time) old = i;
            c->report[old] = c->report[--c->nreports];
        }
        r = &c->report[c->nreports++];
        memset(r, 0, sizeof *r);
        memcpy(r->var, var, sizeof var);
        r->range = -1;
    }
    /* 24.8: a new variable or a new range starts the report afresh (group, type, an empty last
     * list); the same variable and range only renews the request time (and refresh) */
    if (r->range != range) {
        r->range = range;
        r->last[0] = 0;
        r->count = 0;
        memcpy(r->group, group, sizeof group);
        memcpy(r->type, type, sizeof type);
    }
    r->req_time = now;
    r->force = refresh;
    return 1;
}

/* BCM_DISPLAY_RADII: true/on/yes, false/off/no or toggle (24.8's setBooleanOnString); else
 * "Bad Mail: BCM_DISPLAY_RADII:" */
KELP_NOINLINE static int display_radii(kelp_contactmgr *c, const char *s, const kelp_field_sink *out)
{
    size_t n = strlen(s);
    if (kelp_util_strieq_n(s, n, "true") || kelp_util_strieq_n(s, n, "on") || kelp_util_strieq_n(s, n, "yes"))
        c->display_radii = true;
    else if (kelp_util_strieq_n(s, n, "false") || kelp_util_strieq_n(s, n, "off") || kelp_util_strieq_n(s, n, "no"))
        c->display_radii = false;
    else if (kelp_util_strieq_n(s, n, "toggle")) c->display_radii = !c->display_radii;
    else {
        warnf(c, out, "Bad Mail: BCM_DISPLAY_RADII:");
        return KELP_ERR_ARG;
    }
    return 1;
}

/* the able/disable/enable flags: a number is posted as a double; a string with 24.8's macros
 * $[RECENT_DISABLED] $[RECENT_ENABLED] $[TOTAL_DISABLED] $[ALL_DISABLED] expanded */
static void post_able_flags(kelp_contactmgr *c, char (*flags)[KELP_CMGR_MAX_FLAG], unsigned n, kelp_time now,
                            const kelp_field_sink *out)
{
    for (unsigned i = 0; i < n; i++) {
        const char *eq = strchr(flags[i], '=');
        char *var = c->ws_flag[0], *val = c->ws.str;
        if (flag_number(c, flags[i], now, out)) continue;
        copyz(val, sizeof c->ws.str, eq + 1, strlen(eq + 1));
        if (c->ndisabled_c) macro_sub(val, sizeof c->ws.str, "RECENT_DISABLED", c->disabled_c[0]);
        if (c->nenabled_c) macro_sub(val, sizeof c->ws.str, "RECENT_ENABLED", c->enabled_c[0]);
        char num[16];
        (void)kelp_util_snprintf(num, sizeof num, "%u", c->ndisabled_c);
        macro_sub(val, sizeof c->ws.str, "TOTAL_DISABLED", num);
        if (strstr(val, "$[ALL_DISABLED]")) {
            sbuf sb;
            sb_init(&sb, c->text, sizeof c->text);
            for (unsigned j = 0; j < c->ndisabled_c; j++) (void)sb_item(&sb, ",", c->disabled_c[j]);
            macro_sub(val, sizeof c->ws.str, "ALL_DISABLED", c->text);
        }
        if (val[0]) post_s(out, var, val);
        event(c, now, "%s=%.*s", var, KELP_CMGR_MAX_FLAG, val);
    }
}

/* name to the front of list (newest first), out of other; at most KELP_CMGR_MAX_ABLE kept */
static void able_list_add(char (*list)[KELP_CMGR_NAME], unsigned *n, char (*other)[KELP_CMGR_NAME], unsigned *no,
                          const char *name)
{
    for (unsigned i = 0; i < *no; i++)
        if (strcmp(other[i], name) == 0) {
            memmove(other[i], other[i + 1], (size_t)(*no - i - 1) * KELP_CMGR_NAME);
            (*no)--;
            break;
        }
    for (unsigned i = 0; i < *n; i++)
        if (strcmp(list[i], name) == 0) {
            memmove(list[i], list[i + 1], (size_t)(*n - i - 1) * KELP_CMGR_NAME);
            (*n)--;
            break;
        }
    if (*n == KELP_CMGR_MAX_ABLE) (*n)--;
    memmove(list[1], list[0], (size_t)*n * KELP_CMGR_NAME);
    copyz(list[0], KELP_CMGR_NAME, name, strlen(name));
    (*n)++;
}

/* disable_var / enable_var / expunge_var mail (24.8's handleMailModEnableContact): a bare
 * contact name, or contact=<name>, or vsource=<source>, goes to the helm as BHV_ABLE_FILTER =
 * "contact=<name>,action=<action>"; only the contact= form records the contact and posts the
 * able flag and the disable or enable flags. @return 1, or <0 when the value names nothing. */
KELP_NOINLINE static int able_mail(kelp_contactmgr *c, const char *s, const char *action, kelp_time now,
                                   const kelp_field_sink *out)
{
    char id[KELP_CMGR_NAME] = "", vsrc[KELP_CMGR_NAME] = "";
    char *m = c->ws_view;
    if (!strchr(s, '=') && !strchr(s, ',')) {
        const char *p = s;
        size_t n = strlen(s);
        kelp_util_trim(&p, &n);
        if (n == 0 || n >= KELP_CMGR_NAME) return KELP_ERR_ARG;
        (void)kelp_util_snprintf(m, sizeof c->ws_view, "contact=%.*s", (int)n, p);
    } else if (kelp_kv_get(s, ',', "contact", id, sizeof id) == 1 && id[0])
        (void)kelp_util_snprintf(m, sizeof c->ws_view, "contact=%s", id);
    else if (kelp_kv_get(s, ',', "vsource", vsrc, sizeof vsrc) == 1 && vsrc[0])
        (void)kelp_util_snprintf(m, sizeof c->ws_view, "vsource=%s", vsrc);
    else
        return KELP_ERR_ARG;
    size_t ml = strlen(m);
    (void)kelp_util_snprintf(m + ml, sizeof c->ws_view - ml, ",action=%s", action);
    post_s(out, "BHV_ABLE_FILTER", m);
    if (!id[0] || action[0] == 'x' || strcmp(action, "expunge") == 0) return 1;
    bool dis = strcmp(action, "disable") == 0;
    if (dis) able_list_add(c->disabled_c, &c->ndisabled_c, c->enabled_c, &c->nenabled_c, id);
    else able_list_add(c->enabled_c, &c->nenabled_c, c->disabled_c, &c->ndisabled_c, id);
    post_able_flags(c, c->able_flag, c->nable_flag, now, out);
    if (dis) post_able_flags(c, c->disable_flag, c->ndisable_flag, now, out);
    else post_able_flags(c, c->enable_flag, c->nenable_flag, now, out);
    return 1;
}

/* The time step rule: a `now` that is no time is refused; on a step back, the manager's own
 * times (recap, custom report requests, the start its events count from) move back with it.
 * Contact report times are the contacts' data and stay. */
static bool clock_in(kelp_contactmgr *c, kelp_time now)
{
    if (!kelp_util_time_ok(now)) return false;
    double back = kelp_util_clock_back(&c->clock, now);
    if (back > 0) {
        c->clock_steps++;
        if (c->t_start >= 0) c->t_start -= back;
        c->last_recap -= back;
        for (unsigned i = 0; i < c->nreports; i++) c->report[i].req_time -= back;
    }
    if (c->t_start < 0) c->t_start = now;
    return true;
}

int kelp_contactmgr_mail(kelp_contactmgr *c, const char *var, bool is_string, const char *sval, double dval, kelp_time now,
                   const char *src, const kelp_field_sink *out)
{
    if (!clock_in(c, now)) return KELP_ERR_ARG;
    double *nav[4] = { &c->osx, &c->osy, &c->osh, &c->osv };
    static const char *const navn[4] = { "NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED" };
    for (int i = 0; i < 4; i++)
        if (strcmp(var, navn[i]) == 0) {
            if (is_string || !isfinite(dval)) {
                warnf(c, out, "%s must be a finite number", var);
                return KELP_ERR_ARG;
            }
            *nav[i] = dval;
            return 1;
        }
    if ((c->disable_var[0] && strcmp(var, c->disable_var) == 0) || (c->enable_var[0] && strcmp(var, c->enable_var) == 0) ||
        (c->expunge_var[0] && strcmp(var, c->expunge_var) == 0)) {
        const char *action = strcmp(var, c->disable_var) == 0 ? "disable" : strcmp(var, c->enable_var) == 0 ? "enable"
                                                                                                          : "expunge";
        if (!is_string || !sval || able_mail(c, sval, action, now, out) < 0) {
            warnf(c, out, "Bad Mail: %s:", var);
            return KELP_ERR_ARG;
        }
        return 1;
    }
    if (strcmp(var, "IVPHELM_STATE") == 0) {
        if (is_string && kelp_util_strieq(sval, "DRIVE")) c->helm_drive = true; /* latched, as MOOS-IvP */
        return 1;
    }
    bool ours = strcmp(var, "NODE_REPORT") == 0 || strcmp(var, "BCM_ALERT_REQUEST") == 0 ||
                strcmp(var, "BCM_REPORT_REQUEST") == 0 || strcmp(var, "BCM_DISPLAY_RADII") == 0;
    if (!ours) return 0;
    if (!is_string || !sval) {
        warnf(c, out, "%s must be a string", var);
        return KELP_ERR_ARG;
    }
    if (var[0] == 'N') return node_report(c, sval, now, out);
    if (strcmp(var, "BCM_ALERT_REQUEST") == 0) {
        c->alert_requests++;
        event(c, now, "New BCM_ALERT_REQUEST (src=%s): %.*s", src ? src : "", KELP_CMGR_MAX_FLAG, sval);
        return kelp_contactmgr_alert_spec(c, sval, true, src, now, out);
    }
    if (strcmp(var, "BCM_REPORT_REQUEST") == 0) return report_request(c, sval, now, src, out);
    return display_radii(c, sval, out);
}

/* ------------------------------------------------------------------ iterate */

double kelp_contactmgr_extrap_dist(double v, double dt, double d1, double d2)
{
    if (!(dt > 0)) return 0;
    if (dt <= d1) return v * dt;
    if (d2 > d1 && dt <= d2) return v * d1 + ((v + v * (1 - (dt - d1) / (d2 - d1))) / 2) * (dt - d1);
    return v * d1 + (d2 > d1 ? (v / 2) * (d2 - d1) : 0);
}

/* the rate of closure of contact k at (ex, ey) (out of line: the CPA result off the iteration's frame) */
KELP_NOINLINE static double closure_rate(const kelp_contactmgr *c, const kelp_contactmgr_contact *k, double ex, double ey)
{
    kelp_cpa_vessel cn = { ex, ey, k->hdg, k->spd }, os = { c->osx, c->osy, c->osh, c->osv };
    kelp_cpa_result res;
    return kelp_cpa_eval(&cn, &os, KELP_CMGR_CPA_HORIZON, &res) == KELP_OK ? res.roc : 0;
}

static void ranges(kelp_contactmgr *c, kelp_contactmgr_contact *k, kelp_time now)
{
    k->range = hypot(c->osx - k->x, c->osy - k->y);
    double dist = kelp_contactmgr_extrap_dist(k->spd, now - k->time, c->decay[0], c->decay[1]);
    double h = k->hdg * PI / 180;
    double ex = k->x + dist * sin(h), ey = k->y + dist * cos(h);
    k->range_extrap = hypot(c->osx - ex, c->osy - ey);
    k->range_cpa = kelp_cpa_range(ex, ey, k->hdg, k->spd, c->osx, c->osy, c->osh, c->osv, KELP_CMGR_CPA_HORIZON, NULL);
    /* the rate of closure only feeds the early warnings */
    k->roc = c->early_warning_time > 0 ? closure_rate(c, k, ex, ey) : 0;
}

/* 24.8's postAlert macros, exactly (case and all): in a flag's variable $[X] $[Y] $[LAT] $[LON]
 * $[HDG] $[DEP] $[VNAME] $[VTYPE] $[UTIME] $[UTC] %[VNAME] %[VTYPE]; in its value $[X] $[Y]
 * $[LAT] $[LON] $[HDG] $[DEP] $[VNAME] $[VTYPE] $[GROUP] $[UTIME] %[VNAME] %[VTYPE] %[GROUP].
 * %[VNAME] keeps the name's case, %[VTYPE] and %[GROUP] are lower-cased. 24.8 never expands
 * $[SPD] (its code looks for "$[SPD}"), nor $[TIME], $[RANGE], $[UTC] in a value: they stay. */
static void expand(const kelp_contactmgr_contact *k, bool is_var, const char *s, char *out, size_t cap)
{
    static const char *const nm[] = { "$[X]", "$[Y]", "$[LAT]", "$[LON]", "$[HDG]", "$[DEP]", "$[UTIME]",
                                      "$[UTC]", "$[VNAME]", "$[VTYPE]", "$[GROUP]", "%[VNAME]", "%[VTYPE]",
                                      "%[GROUP]" };
    size_t n = 0;
    while (*s && n + 1 < cap) {
        size_t i = 0, ml = 0;
        if (s[0] == '$' || s[0] == '%')
            for (; i < sizeof nm / sizeof nm[0]; i++)
                if (strncmp(s, nm[i], ml = strlen(nm[i])) == 0) break;
        bool skip = i >= sizeof nm / sizeof nm[0] || (is_var && (i == 10 || i == 13)) || (!is_var && i == 7);
        if (s[0] != '$' && s[0] != '%') skip = true;
        if (skip) {
            out[n++] = *s++;
            continue;
        }
        char num[48];
        const char *val = num;
        switch (i) {
        case 0: fmtx(num, sizeof num, k->x, 2); break;
        case 1: fmtx(num, sizeof num, k->y, 2); break;
        case 2: fmtx(num, sizeof num, k->lat, 8); break;
        case 3: fmtx(num, sizeof num, k->lon, 8); break;
        case 4: fmtx(num, sizeof num, k->hdg, 2); break;
        case 5: fmtx(num, sizeof num, k->dep, 2); break;
        case 6:
        case 7: fmtx(num, sizeof num, k->time, 2); break;
        case 8:
        case 11: val = k->name; break;
        case 9:
        case 12: val = k->type; break;
        default: val = k->group; break;
        }
        bool lower = i == 12 || i == 13;
        for (; *val && n + 1 < cap; val++)
            out[n++] = lower && *val >= 'A' && *val <= 'Z' ? (char)(*val - 'A' + 'a') : *val;
        s += ml;
    }
    out[n] = 0;
}

static void post_flags(kelp_contactmgr *c, const kelp_contactmgr_contact *k, char (*flags)[KELP_CMGR_MAX_FLAG], unsigned n,
                       kelp_time now, const kelp_field_sink *out)
{
    for (unsigned i = 0; i < n; i++) {
        const char *eq = strchr(flags[i], '=');
        if (!eq) continue;
        char *var = c->ws_flag[0], *raw = c->ws_flag[1], *val = c->ws.str; /* (workspaces) */
        copyz(raw, KELP_CMGR_MAX_FLAG, flags[i], (size_t)(eq - flags[i]));
        expand(k, true, raw, var, KELP_CMGR_MAX_FLAG);
        double d;
        if (kelp_util_parse_finite(eq + 1, strlen(eq + 1), &d) == 0) {
            char num[48];
            fmtx(num, sizeof num, d, 3);
            post_d(out, var, d);
            event(c, now, "%s=%s", var, num);
            continue;
        }
        expand(k, false, eq + 1, val, sizeof c->ws.str);
        post_s(out, var, val);
        event(c, now, "%s=%.*s", var, KELP_CMGR_MAX_FLAG, val);
    }
}

KELP_NOINLINE static void verbose(kelp_contactmgr *c, const kelp_contactmgr_alert *a, const kelp_contactmgr_contact *k,
                                  bool on, kelp_time now, const kelp_field_sink *out)
{
    char r[32], cr[32], ra[32], rc[48], aw[48], *m = c->ws_view;
    fmtx(r, sizeof r, a->alert_range, 1);
    fmtx(cr, sizeof cr, a->cpa_range, 1);
    fmtf(ra, sizeof ra, k->range, 1);
    rc[0] = aw[0] = 0;
    if (on) {
        memcpy(rc, ",range_cpa=", 12);
        fmtf(rc + 11, sizeof rc - 11, k->range_cpa, 1);
        /* 24.8: after_warning, the time since this contact's early warning, when alerted */
        if (c->early_warning_time > 0 && k->warned_range >= 0) {
            memcpy(aw, ",after_warning=", 16);
            fmtx(aw + 15, sizeof aw - 15, now - k->warned_time, 2);
        }
    }
    (void)kelp_util_snprintf(m, sizeof c->ws_view, "contact=%s,alert_id=%s,%s,alert_range=%s,alert_range_cpa=%s,"
                        "range_actual=%s%s%s", k->name, a->id, on ? "off-->alerted" : "alerted-->off", r, cr, ra, rc, aw);
    post_s(out, "ALERT_VERBOSE", m);
}

/* the alert counts of a name (lower case) */
static int tally_find(const kelp_contactmgr *c, const char *name)
{
    for (unsigned i = 0; i < c->ntally; i++)
        if (strcmp(c->tally[i].name, name) == 0) return (int)i;
    return -1;
}

static void tally_count(kelp_contactmgr *c, const char *name, bool on)
{
    char low[KELP_CMGR_NAME];
    size_t i;
    for (i = 0; name[i] && i + 1 < sizeof low; i++) low[i] = (name[i] >= 'A' && name[i] <= 'Z') ? (char)(name[i] + 32) : name[i];
    low[i] = 0;
    int t = tally_find(c, low);
    if (t < 0) {
        if (!on || c->ntally == KELP_CMGR_MAX_TALLY) return;
        t = (int)c->ntally++;
        memcpy(c->tally[t].name, low, i + 1);
        c->tally[t].total = c->tally[t].active = 0;
    }
    if (on) c->tally[t].total++, c->tally[t].active++;
    else if (c->tally[t].active > 0) c->tally[t].active--;
}

KELP_NOINLINE static void check_alerts(kelp_contactmgr *c, kelp_contactmgr_contact *k, kelp_time now, const kelp_field_sink *out)
{
    unsigned ids[KELP_CMGR_MAX_ALERTS];
    unsigned nids = sorted_alerts(c, ids); /* 24.8 checks its alerts in id order */
    for (unsigned j = 0; j < nids; j++) {
        unsigned ai = ids[j];
        kelp_contactmgr_alert *a = &c->alert[ai];
        if (alert_is_off(c, a->id)) continue;
        double cpa = a->cpa_range;
        bool was = (k->alerted >> ai) & 1u;
        bool base = alert_valid(a) && now - k->time <= c->contact_max_age &&
                    filter_ok(&a->filter, k->name, k->type, k->group, k->x, k->y);
        /* 24.8 (ContactMgrV20::checkAlertApplies): with alert_range > 0 a pair applies while the
         * contact is within cpa_range and either within alert_range or its CPA is; the same
         * test turns a pair on and off (an opening contact goes off once beyond alert_range).
         * alert_range 0: the range criterion is off, the alert applies on its filters. */
        bool ranged = a->alert_range > 0;
        bool now_on = base && (!ranged || (k->range <= cpa && (k->range <= a->alert_range ||
                                                                k->range_cpa <= a->alert_range)));
        if (now_on == was) continue;
        if (now_on) {
            k->alerted |= 1u << ai;
            k->total++, k->active++;
            tally_count(c, k->name, true);
            post_flags(c, k, a->on, a->non, now, out);
        } else {
            k->alerted &= ~(1u << ai);
            k->active--;
            tally_count(c, k->name, false);
            post_flags(c, k, a->off, a->noff, now, out);
        }
        if (c->alert_verbose) verbose(c, a, k, now_on, now, out);
    }
}

/* a VIEW_CIRCLE as 24.8's XYCircle spec: x, y, radius, [active=false,] label, [label_color,]
 * edge_color, time, duration, vertex_size, edge_size */
static void circle(kelp_contactmgr *c, double r, const char *label, const char *label2, const char *label_color,
                   const char *color, bool active, kelp_time now, const kelp_field_sink *out)
{
    char x[32], y[32], rad[32], t[32], *m = c->ws_view;
    /* 24.8's XYCircle refuses a negative radius and keeps its zeros (recorded: a ring with all
     * alerts off is "x=0,y=0,radius=0,active=false,...") */
    fmtx(x, sizeof x, r < 0 ? 0 : c->osx, 2);
    fmtx(y, sizeof y, r < 0 ? 0 : c->osy, 2);
    fmtx(rad, sizeof rad, r < 0 ? 0 : r, 2);
    fmtx(t, sizeof t, now, 2);
    (void)kelp_util_snprintf(m, sizeof c->ws_view, "x=%s,y=%s,radius=%s%s,label=%s%.*s%s%s,edge_color=%s,time=%s,"
                        "duration=3,vertex_size=0,edge_size=1", x, y, rad, active ? "" : ",active=false", label,
                        KELP_CMGR_NAME, label2, label_color ? ",label_color=" : "", label_color ? label_color : "", color, t);
    post_s(out, "VIEW_CIRCLE", m);
}

/* 24.8's getMaxAlertRange: the largest cpa_range of the alerts not turned off (-1: none) */
static double max_alert_range(const kelp_contactmgr *c)
{
    double m = -1;
    for (unsigned i = 0; i < c->nalerts; i++)
        if (!alert_is_off(c, c->alert[i].id) && c->alert[i].cpa_range > m) m = c->alert[i].cpa_range;
    return m;
}

/* 24.8's postRadii: one ring, "alert_<ownship>", at the largest alert range, each iteration
 * while display_radii is on and an alert exists; inactive when that range is not positive or
 * the colour is invisible or empty */
KELP_NOINLINE static void visuals(kelp_contactmgr *c, kelp_time now, const kelp_field_sink *out)
{
    if (!c->display_radii || c->nalerts == 0) return;
    double r = max_alert_range(c);
    const char *col = c->alert_color;
    bool active = r > 0 && col[0] && strcmp(col, "invisible") != 0 && strcmp(col, "empty") != 0;
    circle(c, r, "alert_", c->ownship, NULL, col, active, now, out);
}

/* the early and cease warning flags with 24.8's macros $[CONTACT] $[RNG_EXT] $[RNG] $[CPA]
 * $[ROC] $[UTC] (3 decimals); a number is posted as a double */
static void warning_flags(kelp_contactmgr *c, const kelp_contactmgr_contact *k, char (*flags)[KELP_CMGR_MAX_FLAG],
                          unsigned n, kelp_time now, const kelp_field_sink *out)
{
    for (unsigned i = 0; i < n; i++) {
        const char *eq = strchr(flags[i], '=');
        char *var = c->ws_flag[0], *val = c->ws.str;
        if (flag_number(c, flags[i], now, out)) continue;
        copyz(val, sizeof c->ws.str, eq + 1, strlen(eq + 1));
        char num[48];
        macro_sub(val, sizeof c->ws.str, "CONTACT", k->name);
        const double v[5] = { k->range_extrap, k->range, k->range_cpa, k->roc, now };
        static const char *const m[5] = { "RNG_EXT", "RNG", "CPA", "ROC", "UTC" };
        for (int j = 0; j < 5; j++) {
            fmtx(num, sizeof num, v[j], 3);
            macro_sub(val, sizeof c->ws.str, m[j], num);
        }
        if (val[0]) post_s(out, var, val);
        event(c, now, "%s=%.*s", var, KELP_CMGR_MAX_FLAG, val);
    }
}

/* 24.8's checkForEarlyWarnings, checkForCeaseWarnings and postEarlyWarningRadii: a closing
 * contact not yet warned is warned once its extrapolated range is below the largest alert
 * range plus early_warning_time x its rate of closure; the warning ceases once that range is
 * beyond 1.05 x the range it was warned at; the warning range is drawn until then */
KELP_NOINLINE static void early_warnings(kelp_contactmgr *c, kelp_time now, const kelp_field_sink *out)
{
    if (c->early_warning_time > 0) {
        double maxr = max_alert_range(c);
        for (unsigned i = 0; i < c->ncontacts; i++) {
            kelp_contactmgr_contact *k = &c->contact[c->order[i]];
            if (k->warned_range >= 0) continue;
            k->will_warn = 0;
            if (k->roc <= 0 || maxr <= 0) continue;
            double ewr = maxr + k->roc * c->early_warning_time;
            k->will_warn = ewr;
            if (k->range_extrap < ewr) {
                warning_flags(c, k, c->ewarn_flag, c->newarn_flag, now, out);
                k->warned_range = k->range_extrap;
                k->warned_time = now;
                k->will_warn = 0;
            }
        }
    }
    for (unsigned i = 0; i < c->ncontacts; i++) {
        kelp_contactmgr_contact *k = &c->contact[c->order[i]];
        if (k->warned_range >= 0 && k->range_extrap > k->warned_range * 1.05) {
            k->warned_range = -1;
            warning_flags(c, k, c->cwarn_flag, c->ncwarn_flag, now, out);
        }
    }
    if (!c->early_warning_radii || !(c->early_warning_time > 0)) return;
    for (unsigned i = 0; i < c->ncontacts; i++) {
        const kelp_contactmgr_contact *k = &c->contact[c->order[i]];
        if (k->will_warn > 0) circle(c, k->will_warn, "xewarn_", k->name, "gray50", c->ewarn_color, true, now, out);
    }
}

/* heap sort of idx[0..n) by key (descending when desc), ties by position in idx (stable
 * enough: the key is made unique by the index's list position) */


static bool before(kelp_contactmgr_sortkey a, kelp_contactmgr_sortkey b)
{
    return a.v < b.v || (a.v == b.v && a.pos < b.pos);
}

static void sift(kelp_contactmgr_sortkey *a, unsigned i, unsigned n)
{
    for (;;) {
        unsigned l = 2 * i + 1, big = i;
        if (l < n && before(a[big], a[l])) big = l;
        if (l + 1 < n && before(a[big], a[l + 1])) big = l + 1;
        if (big == i) return;
        kelp_contactmgr_sortkey t = a[i];
        a[i] = a[big], a[big] = t;
        i = big;
    }
}

static void heapsort(kelp_contactmgr_sortkey *a, unsigned n)
{
    for (unsigned i = n / 2; i-- > 0;) sift(a, i, n);
    for (unsigned end = n; end-- > 1;) {
        kelp_contactmgr_sortkey t = a[0];
        a[0] = a[end], a[end] = t;
        sift(a, 0, end);
    }
}

/* the retire flags for one name: $[CONTACT] and $[UTC] expanded (24.8's postRetireFlags) */
static void retire_flags(kelp_contactmgr *c, const char *name, kelp_time now, const kelp_field_sink *out)
{
    for (unsigned i = 0; i < c->nretire_flag; i++) {
        const char *f = c->retire_flag[i], *eq = strchr(f, '=');
        char *var = c->ws_flag[0], *val = c->ws.str;
        if (flag_number(c, f, now, out)) continue;
        char t[48];
        fmtx(t, sizeof t, now, 3);
        copyz(val, sizeof c->ws.str, eq + 1, strlen(eq + 1));
        macro_sub(val, sizeof c->ws.str, "CONTACT", name);
        macro_sub(val, sizeof c->ws.str, "UTC", t);
        if (val[0]) post_s(out, var, val);
        event(c, now, "%s=%.*s", var, KELP_CMGR_MAX_FLAG, val);
    }
}

KELP_NOINLINE static void retire(kelp_contactmgr *c, kelp_time now, const kelp_field_sink *out)
{
    /* 24.8 counts the refused names that are not in the ledger with those to retire when it
     * decides whether max_contacts calls for culling */
    unsigned nr = 0;
    for (unsigned i = 0; i < c->nfiltered; i++) nr += kelp_contactmgr_find(c, c->filtered[i]) < 0;
    for (unsigned i = 0; i < c->ncontacts; i++) {
        kelp_contactmgr_contact *k = &c->contact[c->order[i]];
        k->retire = k->filtered || now - k->time > c->contact_max_age ||
                    (c->reject_range > 0 && k->range > c->reject_range * KELP_CMGR_REJECT_MARGIN);
        nr += k->retire;
    }
    if (c->ncontacts > nr + c->max_contacts)
        for (unsigned i = 0; i < c->ncontacts; i++) {
            kelp_contactmgr_contact *k = &c->contact[c->order[i]];
            if (!k->retire && now - k->time > c->contact_max_age / 2) k->retire = true, nr++;
        }
    if (c->ncontacts > nr + c->max_contacts) {
        /* keep the max_contacts closest: sort the rest by range (farthest, then later, last) */
        kelp_contactmgr_sortkey *sk = c->sortbuf;
        unsigned m = 0;
        for (unsigned i = 0; i < c->ncontacts; i++)
            if (!c->contact[c->order[i]].retire) sk[m++] = (kelp_contactmgr_sortkey){ c->contact[c->order[i]].range, i };
        heapsort(sk, m);
        for (unsigned j = m; j-- > 0 && c->ncontacts > nr + c->max_contacts;)
            c->contact[c->order[sk[j].pos]].retire = true, nr++;
    }
    /* retire flags, in name order over the retired contacts and the refused names */
    if (c->nretire_flag) {
        unsigned f = 0;
        for (unsigned i = 0; i <= c->ncontacts; i++) {
            const kelp_contactmgr_contact *k = i < c->ncontacts ? &c->contact[c->order[i]] : NULL;
            for (; f < c->nfiltered && (!k || strcmp(c->filtered[f], k->name) <= 0); f++)
                if (!k || strcmp(c->filtered[f], k->name) < 0) retire_flags(c, c->filtered[f], now, out);
            if (k && k->retire) retire_flags(c, k->name, now, out);
        }
    }
    c->nfiltered = 0;
    if (!nr) return;
    unsigned w = 0;
    for (unsigned i = 0; i < c->ncontacts; i++) {
        uint16_t ci = c->order[i];
        kelp_contactmgr_contact *k = &c->contact[ci];
        if (!k->retire) {
            c->order[w++] = ci;
            continue;
        }
        retired_remove(c, k->name);
        if (c->nretired >= KELP_CMGR_MAX_RETIRED) { /* cannot happen: pruned each iteration */
            memmove(c->retired[0], c->retired[1], (size_t)(c->nretired - 1) * KELP_CMGR_NAME);
            c->nretired--;
        }
        memcpy(c->retired[c->nretired++], k->name, KELP_CMGR_NAME);
        k->used = false;
        c->spare[c->nspare++] = ci;
    }
    c->ncontacts = w;
}

static bool changed(char *prev, const char *now_s)
{
    if (strcmp(prev, now_s) == 0) return false;
    copyz(prev, KELP_CMGR_MAX_TEXT, now_s, strlen(now_s));
    return true;
}

static void post_text(kelp_contactmgr *c, const char *var, sbuf *sb, char *prev, bool always, const kelp_field_sink *out)
{
    if (sb->cut) c->truncations++;
    if (changed(prev, sb->b) || always) post_s(out, var, sb->b);
}

KELP_NOINLINE static void custom_reports(kelp_contactmgr *c, kelp_time now, const kelp_field_sink *out)
{
    /* 24.8's pruneRangeReports: beyond range_report_maxsize, the oldest request at least
     * range_report_timeout old goes, one per iteration */
    if (c->nreports > c->range_report_maxsize) {
        int old = -1;
        for (unsigned i = 0; i < c->nreports; i++) {
            double age = now - c->report[i].req_time;
            double oa = old < 0 ? 0 : now - c->report[old].req_time; /* ties: the first by name */
            if (age >= c->range_report_timeout &&
                (old < 0 || age > oa || (age == oa && strcmp(c->report[i].var, c->report[old].var) < 0)))
                old = (int)i;
        }
        if (old >= 0) c->report[old] = c->report[--c->nreports];
    }
    /* ascending var name: a selection over at most KELP_CMGR_MAX_REPORTS */
    bool done[KELP_CMGR_MAX_REPORTS] = { false };
    for (unsigned round = 0; round < c->nreports; round++) {
        unsigned r = KELP_CMGR_MAX_REPORTS;
        for (unsigned i = 0; i < c->nreports; i++)
            if (!done[i] && (r == KELP_CMGR_MAX_REPORTS || strcmp(c->report[i].var, c->report[r].var) < 0)) r = i;
        if (r == KELP_CMGR_MAX_REPORTS) break;
        done[r] = true;
        kelp_contactmgr_report *rp = &c->report[r];
        sbuf sb;
        sb_init(&sb, c->text, sizeof c->text);
        unsigned count = 0;
        for (unsigned j = 0; j < c->ncontacts; j++) {
            const kelp_contactmgr_contact *k = &c->contact[c->order[j]];
            if (!(k->range_extrap < rp->range)) continue;
            if (rp->group[0] && !kelp_util_strieq(rp->group, k->group)) continue;
            if (rp->type[0] && !kelp_util_strieq(rp->type, k->type)) continue;
            count += sb_item(&sb, ",", k->name);
        }
        if (sb.cut) c->truncations++;
        if (rp->force || strcmp(rp->last, sb.b) != 0) {
            post_s(out, rp->var, sb.b);
            memcpy(rp->last, sb.b, sb.n + 1);
            rp->force = false;
        }
        rp->count = count;
    }
}

KELP_NOINLINE static void summaries(kelp_contactmgr *c, kelp_time now, const kelp_field_sink *out)
{
    sbuf sb;
    /* CONTACTS_RETIRED, newest first, then prune */
    sb_init(&sb, c->text, sizeof c->text);
    for (unsigned i = c->nretired; i-- > 0;) (void)sb_item(&sb, ",", c->retired[i]);
    post_text(c, "CONTACTS_RETIRED", &sb, c->prev_retired, false, out);
    if (c->nretired > c->max_retired) {
        unsigned drop = c->nretired - c->max_retired;
        memmove(c->retired[0], c->retired[drop], (size_t)c->max_retired * KELP_CMGR_NAME);
        c->nretired = c->max_retired;
    }
    /* CONTACTS_LIST; the closest */
    sb_init(&sb, c->text, sizeof c->text);
    const kelp_contactmgr_contact *close = NULL;
    for (unsigned i = 0; i < c->ncontacts; i++) {
        const kelp_contactmgr_contact *k = &c->contact[c->order[i]];
        (void)sb_item(&sb, ",", k->name);
        if (!close || k->range < close->range) close = k;
    }
    post_text(c, "CONTACTS_LIST", &sb, c->prev_list, false, out);
    if (close) {
        if (strcmp(close->name, c->prev_closest) != 0) {
            memcpy(c->prev_closest, close->name, sizeof c->prev_closest);
            post_s(out, "CONTACT_CLOSEST", close->name);
            post_d(out, "CONTACT_CLOSEST_TIME", now);
        }
        double r = trunc(close->range); /* 24.8 truncates to an integer */
        if (c->post_closest_range && r != c->prev_closest_range) {
            c->prev_closest_range = r;
            post_d(out, "CONTACT_CLOSEST_RANGE", r);
        }
        if (c->post_closest_relbng) {
            double b = atan2(close->x - c->osx, close->y - c->osy) * 180 / PI - c->osh;
            b = fmod(fmod(b, 360) + 360, 360);
            b = floor(b);
            if (b != c->prev_relbng) {
                c->prev_relbng = b;
                post_d(out, "CONTACT_CLOSEST_RELBNG", b);
            }
        }
    }
    /* CONTACTS_COUNT, ALERTED, UNALERTED */
    double count = 0;
    for (unsigned i = 0; i < c->ncontacts; i++) {
        uint32_t m = c->contact[c->order[i]].alerted;
        for (unsigned ai = 0; ai < c->nalerts; ai++) count += (m >> ai) & 1u;
    }
    if (count != c->prev_count) {
        c->prev_count = count;
        post_d(out, "CONTACTS_COUNT", count);
    }
    /* CONTACTS_ALERTED: (name in lower case, alert id) pairs, ids in ascending order (24.8's
     * PlatformAlertRecord); 24.8 posts no list of the unalerted pairs */
    {
        sb_init(&sb, c->text, sizeof c->text);
        char pair[KELP_CMGR_NAME + KELP_CMGR_MAX_ID + 4];
        unsigned ids[KELP_CMGR_MAX_ALERTS];
        unsigned nids = sorted_alerts(c, ids);
        for (unsigned i = 0; i < c->ncontacts && !sb.cut; i++) {
            const kelp_contactmgr_contact *k = &c->contact[c->order[i]];
            for (unsigned j = 0; j < nids; j++)
                if ((k->alerted >> ids[j]) & 1u) {
                    int pl = kelp_util_snprintf(pair, sizeof pair, "(%s,%s)", k->name, c->alert[ids[j]].id);
                    for (int q = 1; q < pl && pair[q] != ','; q++)
                        if (pair[q] >= 'A' && pair[q] <= 'Z') pair[q] = (char)(pair[q] - 'A' + 'a');
                    (void)sb_item(&sb, "", pair);
                }
        }
        post_text(c, "CONTACTS_ALERTED", &sb, c->prev_alerted, false, out);
    }
    /* CONTACTS_RECAP: 24.8 posts once more than recap_interval has passed; its iterations run
     * a little over their period, kelp's on time, so the test allows a millisecond (as the app
     * runner's status test) to post every interval, not every interval plus one iteration */
    if (c->recap_interval > 0 && now - c->last_recap > c->recap_interval - 1e-3) {
        c->last_recap = now;
        sb_init(&sb, c->text, sizeof c->text);
        for (unsigned i = 0; i < c->ncontacts && !sb.cut; i++) {
            const kelp_contactmgr_contact *k = &c->contact[c->order[i]];
            char r[32], a[32], e[KELP_CMGR_NAME + 80];
            fmtf(r, sizeof r, k->range, 2);
            fmtf(a, sizeof a, now - k->time, 2);
            (void)kelp_util_snprintf(e, sizeof e, "vname=%s,range=%s,age=%s", k->name, r, a);
            (void)sb_item(&sb, " # ", e);
        }
        post_text(c, "CONTACTS_RECAP", &sb, c->prev_recap, true, out);
    }
    /* CONTACT_RANGES */
    if (c->post_all_ranges && c->ncontacts) {
        kelp_contactmgr_sortkey *sk = c->sortbuf;
        for (unsigned i = 0; i < c->ncontacts; i++) sk[i] = (kelp_contactmgr_sortkey){ c->contact[c->order[i]].range, i };
        heapsort(sk, c->ncontacts);
        sb_init(&sb, c->text, sizeof c->text);
        for (unsigned i = 0; i < c->ncontacts && !sb.cut; i++) {
            char r[32];
            fmtx(r, sizeof r, sk[i].v, 1);
            (void)sb_item(&sb, ",", r);
        }
        post_text(c, "CONTACT_RANGES", &sb, c->prev_ranges, true, out); /* every iteration, as 24.8 */
    }
}

void kelp_contactmgr_iterate(kelp_contactmgr *c, kelp_time now, const kelp_field_sink *out)
{
    if (!clock_in(c, now)) return;
    c->iterations++;
    for (unsigned i = 0; i < c->ncontacts; i++) ranges(c, &c->contact[c->order[i]], now);
    early_warnings(c, now, out);
    if (!c->hold_alerts_for_helm || c->helm_drive)
        for (unsigned i = 0; i < c->ncontacts; i++) check_alerts(c, &c->contact[c->order[i]], now, out);
    visuals(c, now, out);
    retire(c, now, out);
    custom_reports(c, now, out);
    summaries(c, now, out);
}

/* ------------------------------------------------------------------ report */

int kelp_contactmgr_report_text(const kelp_contactmgr *c, kelp_time now, char *buf, size_t cap)
{
    size_t n = 0;
    char a[32], b[32];
    (void)now;
    buf[0] = 0;
    /* 24.8's buildReport: header, alert configurations (in id order), status, tables */
    field_putf(buf, cap, &n, "Ownship Group:      %s\n", c->ownship_group[0] ? c->ownship_group : "not specified");
    field_putf(buf, cap, &n, "Ownship Type:       %s\n", c->ownship_type[0] ? c->ownship_type : "not specified");
    fmtx(a, sizeof a, c->contact_max_age, 2);
    field_putf(buf, cap, &n, "Contact Max Age:    %s\n", a);
    fmtx(a, sizeof a, c->reject_range, 2);
    field_putf(buf, cap, &n, "Reject Range:       %s\n", c->reject_range > 0 ? a : "off");
    field_putf(buf, cap, &n, "Early Warning Time: %g\n", c->early_warning_time);
    if (c->early_warning_time > 0) {
        /* 24.8 labels the cease flags' count EWFlags and the early flags' CWFlags */
        field_putf(buf, cap, &n, "EarlyWarn Radii:    %s\n", c->early_warning_radii ? "true" : "false");
        field_putf(buf, cap, &n, "EarlyWarn EWFlags:  %u\nEarlyWarn CWFlags:  %u\nAlertsDisabled:     ", c->ncwarn_flag,
                   c->newarn_flag);
        bool done_id[KELP_CMGR_MAX_ALERTS] = { false };
        for (unsigned r = 0; r < c->nalert_off; r++) { /* ascending, comma-separated */
            int best = -1;
            for (unsigned i = 0; i < c->nalert_off; i++)
                if (!done_id[i] && (best < 0 || strcmp(c->alert_off[i], c->alert_off[best]) < 0)) best = (int)i;
            if (best < 0) break;
            done_id[best] = true;
            field_putf(buf, cap, &n, "%s%s", r ? "," : "", c->alert_off[best]);
        }
        fmtx(a, sizeof a, max_alert_range(c), 2);
        field_putf(buf, cap, &n, "\nmax_alert_range:    %s\n", a);
    }
    if (c->disable_var[0]) field_putf(buf, cap, &n, "Disable Var:        %s\n", c->disable_var);
    if (c->enable_var[0]) field_putf(buf, cap, &n, "Enable Var:         %s\n", c->enable_var);
    field_putf(buf, cap, &n, "BCM_ALERT_REQUESTs: %lu\n", c->alert_requests);
    field_putf(buf, cap, &n, "DisplayRadii:       %s\n\n", c->display_radii ? "true" : "false");
    field_putf(buf, cap, &n, "Alert Configurations (%u):\n---------------------\n", c->nalerts);
    static const char *const kinds[3] = { "name", "type", "group" };
    unsigned ids[KELP_CMGR_MAX_ALERTS];
    unsigned nids = sorted_alerts(c, ids);
    for (unsigned j = 0; j < nids; j++) {
        const kelp_contactmgr_alert *al = &c->alert[ids[j]];
        field_putf(buf, cap, &n, "%u ID: %s\n", j + 1, al->id);
        fmtx(a, sizeof a, al->alert_range, 2);
        fmtx(b, sizeof b, al->cpa_range, 2);
        field_putf(buf, cap, &n, "  Alert Ranges: %s/%s\n", al->alert_range >= 0 ? a : "unspecified",
                   al->cpa_range >= 0 ? b : "unspecified");
        field_putf(buf, cap, &n, "  Source: %s\n", al->source[0] ? al->source : "general");
        /* 24.8 labels the off flags "OnFlag" too */
        for (unsigned f = 0; f < al->non; f++) field_putf(buf, cap, &n, "  OnFlag: %s\n", al->on[f]);
        for (unsigned f = 0; f < al->noff; f++) field_putf(buf, cap, &n, "  OnFlag: %s\n", al->off[f]);
        /* the filter summary in 24.8's order: groups, names, types (ignore before match), regions */
        static const int korder[3] = { 2, 0, 1 };
        for (int kk = 0; kk < 3; kk++)
            for (int ign = 1; ign >= 0; ign--)
                for (unsigned e = 0; e < al->filter.nlist[korder[kk]][ign]; e++)
                    field_putf(buf, cap, &n, "  %s_%s=%s\n", ign ? "ignore" : "match", kinds[korder[kk]],
                               al->filter.list[korder[kk]][ign][e]);
        for (int ign = 1; ign >= 0; ign--)
            for (unsigned r = 0; r < al->filter.nregion[ign]; r++) {
                const kelp_contactmgr_poly *pg = &al->filter.region[ign][r];
                field_putf(buf, cap, &n, "  %s_region=pts={", ign ? "ignore" : "match");
                for (unsigned v = 0; v < pg->n; v++) {
                    fmtx(a, sizeof a, pg->pts[v][0], 2);
                    fmtx(b, sizeof b, pg->pts[v][1], 2);
                    field_putf(buf, cap, &n, "%s%s,%s", v ? ":" : "", a, b);
                }
                field_putf(buf, cap, &n, "}\n");
            }
        if (al->filter.nlist[1][1] || al->filter.nlist[2][1])
            field_putf(buf, cap, &n, "  strict_ignore=%s\n", al->filter.strict_ignore ? "true" : "false");
    }
    field_putf(buf, cap, &n, "\nAlert Status Summary: \n----------------------\n");
    field_putf(buf, cap, &n, "       List: %.300s\n    Alerted: %.300s\n    Retired: %.300s\n      Recap: %.300s\n\n",
               c->prev_list, c->prev_alerted, c->prev_retired, c->prev_recap);
    field_putf(buf, cap, &n, "Contact Status Summary:\n-----------------------\n");
    /* 24.8's table: columns 4 spaces apart, as wide as their widest cell, the range
     * right-justified, the last column not padded; the first 7 contacts */
    unsigned rows = c->ncontacts;
    if (rows > 7) rows = 7;
    size_t w0 = 7, w1 = 6, w2 = 6;
    char rng[7][20], tot[7][16]; /* a range to 0.1 m: up to 1e17 m fits */
    uint32_t act[7];
    for (unsigned i = 0; i < rows; i++) {
        const kelp_contactmgr_contact *k = &c->contact[c->order[i]];
        fmtf(rng[i], sizeof rng[i], k->range, 1);
        /* 24.8 looks the counts up by the name as reported, kept by the lower-case name: a name
         * with capitals shows 0 */
        int t = tally_find(c, k->name);
        act[i] = t < 0 ? 0 : c->tally[t].active;
        (void)kelp_util_snprintf(tot[i], sizeof tot[i], "%u", t < 0 ? 0u : (unsigned)c->tally[t].total);
        if (strlen(k->name) > w0) w0 = strlen(k->name);
        if (strlen(rng[i]) > w1) w1 = strlen(rng[i]);
        if (strlen(tot[i]) > w2) w2 = strlen(tot[i]);
    }
    int W0 = (int)w0, W1 = (int)w1, W2 = (int)w2;
    static const char dash[] = "----------------------------------------------------------------";
    field_putf(buf, cap, &n, "%-*s    %*s    %-*s    %s\n", W0, "Contact", W1, "Range", W2, "Alerts", "Alerts");
    field_putf(buf, cap, &n, "%-*s    %*s    %-*s    %s\n", W0, "", W1, "Actual", W2, "Total", "Active");
    field_putf(buf, cap, &n, "%.*s    %.*s    %.*s    ------\n", W0, dash, W1, dash, W2, dash);
    for (unsigned i = 0; i < rows; i++) {
        const kelp_contactmgr_contact *k = &c->contact[c->order[i]];
        field_putf(buf, cap, &n, "%-*s    %*s    %-*s    %u\n", W0, k->name, W1, rng[i], W2, tot[i], (unsigned)act[i]);
    }
    field_putf(buf, cap, &n, "\nCustom Contact Reports:\n-----------------------\n");
    /* columns 5 spaces apart, in variable name order */
    size_t cw[5] = { 7, 5, 5, 5, 8 };
    bool done[KELP_CMGR_MAX_REPORTS] = { false };
    for (unsigned i = 0; i < c->nreports; i++) {
        const kelp_contactmgr_report *r = &c->report[i];
        fmtx(a, sizeof a, r->range, 2);
        const size_t l[3] = { strlen(r->var), strlen(a), strlen(r->group) };
        for (int q = 0; q < 3; q++)
            if (l[q] > cw[q]) cw[q] = l[q];
        if (strlen(r->type) > cw[3]) cw[3] = strlen(r->type);
    }
    field_putf(buf, cap, &n, "%-*s     %*s     %-*s     %-*s     Contacts\n", (int)cw[0], "VarName", (int)cw[1], "Range",
               (int)cw[2], "Group", (int)cw[3], "VType");
    field_putf(buf, cap, &n, "%.*s     %.*s     %.*s     %.*s     --------\n", (int)cw[0], dash, (int)cw[1], dash,
               (int)cw[2], dash, (int)cw[3], dash);
    for (unsigned round = 0; round < c->nreports; round++) {
        unsigned r = KELP_CMGR_MAX_REPORTS;
        for (unsigned i = 0; i < c->nreports; i++)
            if (!done[i] && (r == KELP_CMGR_MAX_REPORTS || strcmp(c->report[i].var, c->report[r].var) < 0)) r = i;
        if (r >= KELP_CMGR_MAX_REPORTS) break; /* every report shown */
        done[r] = true;
        const kelp_contactmgr_report *rp = &c->report[r];
        fmtx(a, sizeof a, rp->range, 2);
        field_putf(buf, cap, &n, "%-*s     %*s     %-*s     %-*s     %u\n", (int)cw[0], rp->var, (int)cw[1], a,
                   (int)cw[2], rp->group, (int)cw[3], rp->type, rp->count);
    }
    return n + 1 >= cap ? KELP_ERR_NOSPACE : (int)n;
}
