/* kelp-viewer's model (see include/kelp/viewer.h). */
#include <math.h>
#include <string.h>
#include <kelp/util.h>
#include <kelp/appcast.h>
#include <kelp/viewer.h>

/* ------------------------------------------------------------------ JSON writer */

typedef struct jw {
    char *buf;
    size_t cap, len;
    bool full; /* out of room: the rest is dropped */
} jw;

static void jw_raw(jw *w, const char *s, size_t n)
{
    if (w->full) return;
    if (w->len + n + 1 > w->cap) {
        w->full = true;
        return;
    }
    memcpy(w->buf + w->len, s, n);
    w->len += n;
    w->buf[w->len] = '\0';
}

static void jw_lit(jw *w, const char *s)
{
    jw_raw(w, s, strlen(s));
}

static void jw_str(jw *w, const char *s)
{
    static const char hex[] = "0123456789abcdef";
    char tmp[64];
    size_t k = 0;
    tmp[k++] = '"';
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (k + 7 > sizeof tmp) {
            jw_raw(w, tmp, k);
            k = 0;
        }
        unsigned char c = *p;
        if (c == '"' || c == '\\') {
            tmp[k++] = '\\';
            tmp[k++] = (char)c;
        } else if (c < 0x20 || c == 0x7f || c >= 0x80) {
            /* control bytes and anything not ASCII (bus strings are not promised to be UTF-8) */
            tmp[k++] = '\\';
            tmp[k++] = 'u';
            tmp[k++] = '0';
            tmp[k++] = '0';
            tmp[k++] = hex[c >> 4];
            tmp[k++] = hex[c & 15];
        } else {
            tmp[k++] = (char)c;
        }
    }
    tmp[k++] = '"';
    jw_raw(w, tmp, k);
}

static void jw_num(jw *w, double v, unsigned dec)
{
    char tmp[40];
    int n = isfinite(v) ? kelp_util_fmt_fixed(tmp, sizeof tmp, v, dec, true) : -1;
    if (n < 0 || (size_t)n >= sizeof tmp) jw_lit(w, "null");
    else jw_raw(w, tmp, (size_t)n);
}

static void jw_uint(jw *w, unsigned long v)
{
    char tmp[24];
    int n = kelp_util_snprintf(tmp, sizeof tmp, "%lu", v);
    if (n > 0) jw_raw(w, tmp, (size_t)n);
}

/* ,"key": */
static void jw_key(jw *w, bool *first, const char *key)
{
    if (!*first) jw_raw(w, ",", 1);
    *first = false;
    jw_raw(w, "\"", 1);
    jw_lit(w, key);
    jw_raw(w, "\":", 2);
}

static void jw_kstr(jw *w, bool *first, const char *key, const char *val)
{
    jw_key(w, first, key);
    jw_str(w, val);
}

static void jw_knum(jw *w, bool *first, const char *key, double val, unsigned dec)
{
    jw_key(w, first, key);
    jw_num(w, val, dec);
}

/* ------------------------------------------------------------------ text helpers */

static bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

static void trim(const char **s, size_t *n)
{
    while (*n && is_space(**s)) (*s)++, (*n)--;
    while (*n && is_space((*s)[*n - 1])) (*n)--;
}

static int copy_text(char *dst, size_t cap, const char *s, size_t n)
{
    if (n >= cap) return KELP_ERR_RANGE;
    memcpy(dst, s, n);
    dst[n] = '\0';
    return KELP_OK;
}

static bool starts_with_ci(const char *s, const char *prefix)
{
    size_t n = strlen(prefix);
    return strlen(s) >= n && kelp_util_strieq_n(s, n, prefix);
}

/* ------------------------------------------------------------------ set-up */

void kelp_viewer_init(kelp_viewer *v)
{
    memset(v, 0, sizeof *v);
    v->stale_report_thresh = KELP_VIEWER_STALE_DEFAULT;
    v->stale_remove_thresh = KELP_VIEWER_REMOVE_DEFAULT;
    v->trails_length = KELP_VIEWER_TRAIL_DEFAULT;
}

int kelp_viewer_set_datum(kelp_viewer *v, double lat0, double lon0)
{
    int rc = kelp_geo_init(&v->geo, lat0, lon0);
    if (rc < 0) return rc;
    v->have_datum = true;
    return KELP_OK;
}

int kelp_viewer_set_image(kelp_viewer *v, const char *url, double lat_n, double lat_s, double lon_e, double lon_w)
{
    if (!url || !isfinite(lat_n) || !isfinite(lat_s) || !isfinite(lon_e) || !isfinite(lon_w) || lat_n <= lat_s ||
        lon_e <= lon_w)
        return KELP_ERR_ARG;
    if (copy_text(v->image_url, sizeof v->image_url, url, strlen(url)) < 0) return KELP_ERR_RANGE;
    v->img_n = lat_n;
    v->img_s = lat_s;
    v->img_e = lon_e;
    v->img_w = lon_w;
    return KELP_OK;
}

int kelp_viewer_poke_parse(const char *s, size_t len, kelp_viewer_poke *out)
{
    memset(out, 0, sizeof *out);
    trim(&s, &len);
    const char *eq = memchr(s, '=', len);
    if (!eq) return KELP_ERR_PARSE;
    const char *var = s, *val = eq + 1;
    size_t vn = (size_t)(eq - s), n = len - vn - 1;
    trim(&var, &vn);
    trim(&val, &n);
    if (vn == 0) return KELP_ERR_PARSE;
    for (size_t i = 0; i < vn; i++)
        if (is_space(var[i]) || var[i] == '#' || var[i] == ',') return KELP_ERR_PARSE;
    if (copy_text(out->var, sizeof out->var, var, vn) < 0) return KELP_ERR_RANGE;
    if (n >= 2 && val[0] == '"' && val[n - 1] == '"') {
        out->is_string = true;
        return copy_text(out->sval, sizeof out->sval, val + 1, n - 2);
    }
    if (n > 0 && kelp_util_parse_finite(val, n, &out->dval) == 0) {
        out->is_string = false;
        return KELP_OK;
    }
    out->is_string = true;
    return copy_text(out->sval, sizeof out->sval, val, n);
}

/* the next '#'-separated part of s[*pos..n); 1 while one is produced */
static int next_part(const char *s, size_t n, size_t *pos, const char **part, size_t *plen)
{
    if (*pos > n) return 0;
    const char *start = s + *pos;
    const char *hash = memchr(start, '#', n - *pos);
    size_t k = hash ? (size_t)(hash - start) : n - *pos;
    *part = start;
    *plen = k;
    *pos += k + 1;
    trim(part, plen);
    return 1;
}

static const char *const button_words[] = {
    "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
    "eleven", "twelve", "thirteen", "fourteen", "fifteen", "sixteen", "seventeen", "eighteen", "nineteen", "twenty",
};

/* button_one..button_twenty, button_1..button_20 -> 1..20; 0 otherwise */
static unsigned button_slot(const char *key)
{
    if (!starts_with_ci(key, "button_")) return 0;
    const char *w = key + 7;
    for (unsigned i = 0; i < 20; i++)
        if (kelp_util_strieq(w, button_words[i])) return i + 1;
    long k;
    if (kelp_util_parse_long(w, strlen(w), &k) == 0 && k >= 1 && k <= 20) return (unsigned)k;
    return 0;
}

static kelp_viewer_cmd *cmd_new(kelp_viewer *v)
{
    if (v->ncmds >= KELP_VIEWER_MAX_CMDS) return NULL;
    kelp_viewer_cmd *c = &v->cmds[v->ncmds];
    memset(c, 0, sizeof *c);
    return c;
}

/* button_N: a part without '=' is the label (the last one wins), color=C the button's colour,
 * every other part a poke; a later line for the same button adds its pokes (and relabels it),
 * as pMarineViewer does */
static int config_button(kelp_viewer *v, unsigned slot, const char *val, kelp_diag *d)
{
    size_t n = strlen(val), pos = 0, pl;
    const char *p;
    kelp_viewer_cmd *c = NULL;
    for (unsigned i = 0; i < v->ncmds && !c; i++)
        if (v->cmds[i].kind == KELP_VIEWER_BUTTON && v->cmds[i].slot == slot) c = &v->cmds[i];
    kelp_viewer_cmd *nc = &v->ws_cmd;
    if (c) *nc = *c;
    else {
        memset(nc, 0, sizeof *nc);
        nc->kind = KELP_VIEWER_BUTTON;
        nc->slot = slot;
    }
    while (next_part(val, n, &pos, &p, &pl)) {
        if (pl == 0) continue;
        if (!memchr(p, '=', pl)) {
            if (copy_text(nc->label, sizeof nc->label, p, pl) < 0) return kelp_fail(d, KELP_ERR_RANGE, "label too long");
            continue;
        }
        kelp_viewer_poke pk;
        int rc = kelp_viewer_poke_parse(p, pl, &pk);
        if (rc < 0) return kelp_fail(d, rc, "a poke is VAR=value");
        if (kelp_util_strieq(pk.var, "color")) {
            const char *cv = pk.is_string ? pk.sval : "";
            if (copy_text(nc->color, sizeof nc->color, cv, strlen(cv)) < 0) return kelp_fail(d, KELP_ERR_RANGE, "colour too long");
            continue;
        }
        if (nc->npokes >= KELP_VIEWER_MAX_POKES) return kelp_fail(d, KELP_ERR_NOSPACE, "too many pokes");
        nc->pokes[nc->npokes++] = pk;
    }
    if (!nc->label[0]) return kelp_fail(d, KELP_ERR_PARSE, "a button needs a label: LABEL # VAR=value # ...");
    if (!c) {
        c = cmd_new(v);
        if (!c) return kelp_fail(d, KELP_ERR_NOSPACE, "too many buttons and actions");
        v->ncmds++;
    }
    *c = *nc;
    return 1;
}

/* action / action+: every VAR=value pair is a menu entry of its own, labelled "VAR=value"; a
 * menu_key=KEY part gives them a key, and choosing any entry with a key posts every pair of
 * every action line with that key (pMarineViewer's rule); action+ puts a separator after each
 * entry of its line */
static int config_action(kelp_viewer *v, const char *val, bool separator, kelp_diag *d)
{
    size_t n = strlen(val), pos = 0, pl;
    const char *p;
    kelp_viewer_poke pk;
    char key[KELP_VIEWER_LABEL_LEN] = "";
    unsigned pairs = 0;
    while (next_part(val, n, &pos, &p, &pl)) {
        if (pl == 0) continue;
        int rc = kelp_viewer_poke_parse(p, pl, &pk);
        if (rc < 0) return kelp_fail(d, rc, "an action is VAR=value # VAR=value ...");
        if (!kelp_util_strieq(pk.var, "menu_key")) {
            pairs++;
            continue;
        }
        char num[32];
        const char *kv = pk.sval;
        if (!pk.is_string) {
            (void)kelp_util_fmt_fixed(num, sizeof num, pk.dval, 6, true);
            kv = num;
        }
        if (copy_text(key, sizeof key, kv, strlen(kv)) < 0 || !key[0]) return kelp_fail(d, KELP_ERR_PARSE, "bad menu_key");
    }
    if (pairs == 0) return kelp_fail(d, KELP_ERR_PARSE, "an action needs at least one VAR=value");
    if (v->ncmds + pairs > KELP_VIEWER_MAX_CMDS) return kelp_fail(d, KELP_ERR_NOSPACE, "too many buttons and actions");
    pos = 0;
    while (next_part(val, n, &pos, &p, &pl)) {
        if (pl == 0 || kelp_viewer_poke_parse(p, pl, &pk) < 0 || kelp_util_strieq(pk.var, "menu_key")) continue;
        kelp_viewer_cmd *c = cmd_new(v);
        c->kind = KELP_VIEWER_ACTION;
        c->separator = separator;
        memcpy(c->key, key, sizeof c->key);
        char num[40];
        if (!pk.is_string) (void)kelp_util_fmt_fixed(num, sizeof num, pk.dval, 9, true);
        (void)kelp_util_snprintf(c->label, sizeof c->label, "%s=%s", pk.var, pk.is_string ? pk.sval : num); /* cut if long */
        c->pokes[0] = pk;
        c->npokes = 1;
        v->ncmds++;
    }
    return 1;
}

unsigned kelp_viewer_press(const kelp_viewer *v, unsigned i, const kelp_viewer_poke **out, unsigned max)
{
    const kelp_viewer_cmd *c = kelp_viewer_cmd_get(v, i);
    unsigned k = 0;
    if (!c) return 0;
    if (c->kind == KELP_VIEWER_BUTTON || !c->key[0]) {
        for (unsigned j = 0; j < c->npokes && k < max; j++) out[k++] = &c->pokes[j];
        return k;
    }
    for (unsigned m = 0; m < v->ncmds; m++) {
        const kelp_viewer_cmd *e = &v->cmds[m];
        if (e->kind != KELP_VIEWER_ACTION || strcmp(e->key, c->key) != 0) continue;
        for (unsigned j = 0; j < e->npokes && k < max; j++) out[k++] = &e->pokes[j];
    }
    return k;
}

int kelp_viewer_config(kelp_viewer *v, const char *key, const char *val, kelp_diag *d)
{
    if (!key || !val) return 0;
    double dv;
    if (kelp_util_strieq(key, "stale_report_thresh") || kelp_util_strieq(key, "stale_remove_thresh") ||
        kelp_util_strieq(key, "trails_length")) {
        if (kelp_util_parse_finite(val, strlen(val), &dv) < 0 || dv < 0)
            return kelp_fail(d, KELP_ERR_PARSE, "expected a number >= 0");
        if (kelp_util_strieq(key, "stale_report_thresh")) v->stale_report_thresh = dv < KELP_VIEWER_STALE_MIN ? KELP_VIEWER_STALE_MIN : dv;
        else if (kelp_util_strieq(key, "stale_remove_thresh")) v->stale_remove_thresh = dv;
        else v->trails_length = dv < 1 ? 1 : dv > KELP_VIEWER_MAX_TRAIL ? KELP_VIEWER_MAX_TRAIL : (unsigned)dv;
        return 1;
    }
    unsigned slot = button_slot(key);
    if (slot) return config_button(v, slot, val, d);
    if (kelp_util_strieq(key, "action")) return config_action(v, val, false, d);
    if (kelp_util_strieq(key, "action+")) return config_action(v, val, true, d);
    return 0;
}

const kelp_viewer_cmd *kelp_viewer_cmd_get(const kelp_viewer *v, unsigned i)
{
    return i < v->ncmds ? &v->cmds[i] : NULL;
}

uint32_t kelp_viewer_seq(const kelp_viewer *v)
{
    return v->seq;
}

void kelp_viewer_clear(kelp_viewer *v)
{
    memset(v->veh, 0, sizeof v->veh);
    memset(v->art, 0, sizeof v->art);
    memset(v->casts, 0, sizeof v->casts);
    v->nveh = 0;
    v->seq++;
    v->floor = v->seq; /* every page that saw less needs a snapshot */
}

/* ------------------------------------------------------------------ mail */

static uint32_t bump(kelp_viewer *v)
{
    return ++v->seq;
}

static kelp_viewer_vehicle *vehicle_slot(kelp_viewer *v, const char *name)
{
    kelp_viewer_vehicle *freeslot = NULL, *tomb = NULL;
    for (unsigned i = 0; i < v->nveh; i++) {
        kelp_viewer_vehicle *e = &v->veh[i];
        if (e->used && e->rep.name[0] == name[0] && strcmp(e->rep.name, name) == 0) return e;
        if (!e->used && !freeslot) freeslot = e;
        if (e->used && e->gone && (!tomb || e->seq < tomb->seq)) tomb = e;
    }
    if (!freeslot && v->nveh < KELP_VIEWER_MAX_VEHICLES) freeslot = &v->veh[v->nveh++];
    if (!freeslot && tomb) {
        /* a removed vehicle's slot: a page that has not seen the removal needs a snapshot */
        if (tomb->seq > v->floor) v->floor = tomb->seq;
        freeslot = tomb;
    }
    if (!freeslot) return NULL;
    memset(freeslot, 0, sizeof *freeslot);
    return freeslot;
}

static int mail_report(kelp_viewer *v, const char *s, size_t len, kelp_time now)
{
    kelp_nodereport *r = &v->ws_report;
    if (kelp_nodereport_parse(s, len, r, NULL) < 0) {
        v->stats.reports_bad++;
        return KELP_ERR_PARSE;
    }
    if (v->have_datum && kelp_nodereport_complete(r, &v->geo) < 0) {
        v->stats.reports_bad++;
        return KELP_ERR_RANGE;
    }
    if (!(r->fields & KELP_NR_X) || !(r->fields & KELP_NR_Y) || !isfinite(r->x) || !isfinite(r->y) ||
        fabs(r->x) > 1e8 || fabs(r->y) > 1e8) {
        v->stats.reports_bad++; /* LAT/LON only and no datum: nowhere to draw it */
        return KELP_ERR_RANGE;
    }
    kelp_viewer_vehicle *e = vehicle_slot(v, r->name);
    if (!e) {
        v->stats.vehicles_full++;
        return KELP_ERR_NOSPACE;
    }
    v->stats.reports++;
    r->extra = NULL;
    if (e->gone) e->head = e->count = 0; /* back after a removal: a new trail */
    e->rep = *r;
    e->used = true;
    e->gone = false;
    e->stale = false;
    e->t_rx = now;
    e->nreports++;
    e->seq = bump(v);
    unsigned cap = v->trails_length;
    if (e->count > cap) e->count = (uint16_t)cap; /* (trails_length is fixed after start-up) */
    /* a window of count <= cap points in a ring of KELP_VIEWER_MAX_TRAIL: write after the newest,
     * and when the window is full drop the oldest */
    unsigned idx = (e->head + e->count) % KELP_VIEWER_MAX_TRAIL;
    if (e->count == cap) e->head = (uint16_t)((e->head + 1) % KELP_VIEWER_MAX_TRAIL);
    else e->count++;
    e->trail[idx][0] = (float)r->x;
    e->trail[idx][1] = (float)r->y;
    e->trail_seq[idx] = e->seq;
    return 1;
}

static bool is_pulse(kelp_view_kind k)
{
    return k == KELP_VIEW_COMMS_PULSE || k == KELP_VIEW_RANGE_PULSE;
}

static kelp_viewer_artifact *artifact_find(kelp_viewer *v, kelp_view_kind kind, const char *label)
{
    for (unsigned i = 0; i < KELP_VIEWER_MAX_ARTIFACTS; i++) {
        kelp_viewer_artifact *a = &v->art[i];
        if (a->used && a->view.kind == kind && strcmp(a->view.label, label) == 0) return a;
    }
    return NULL;
}

static kelp_viewer_artifact *artifact_room(kelp_viewer *v)
{
    kelp_viewer_artifact *oldest_tomb = NULL, *oldest_pulse = NULL, *oldest = NULL;
    for (unsigned i = 0; i < KELP_VIEWER_MAX_ARTIFACTS; i++) {
        kelp_viewer_artifact *a = &v->art[i];
        if (!a->used) return a;
        if (a->gone) {
            if (!oldest_tomb || a->seq < oldest_tomb->seq) oldest_tomb = a;
        } else if (is_pulse(a->view.kind)) {
            if (!oldest_pulse || a->seq < oldest_pulse->seq) oldest_pulse = a;
        } else if (!oldest || a->seq < oldest->seq) {
            oldest = a;
        }
    }
    if (oldest_tomb) {
        if (oldest_tomb->seq > v->floor) v->floor = oldest_tomb->seq;
        return oldest_tomb;
    }
    kelp_viewer_artifact *a = oldest_pulse ? oldest_pulse : oldest;
    /* a live artifact goes without a tombstone: every page needs a snapshot */
    v->stats.evicted++;
    v->floor = v->seq + 1; /* the posting about to be stored takes seq + 1: a page needs to have seen it */
    return a;
}

static int mail_view(kelp_viewer *v, kelp_view_kind kind, const char *s, size_t len, kelp_time now)
{
    kelp_view *pv = &v->ws_view;
    memset(pv, 0, sizeof *pv);
    if (kelp_nodereport_view_parse(kind, s, len, pv, NULL) < 0) {
        v->stats.views_bad++;
        return KELP_ERR_PARSE;
    }
    v->stats.views++;
    kelp_viewer_artifact *a = artifact_find(v, kind, pv->label);
    if (!pv->active) {
        if (!a || a->gone) return 0;
        a->gone = true;
        a->seq = bump(v);
        return 1;
    }
    if (!a) a = artifact_room(v);
    a->view = *pv;
    a->used = true;
    a->gone = false;
    a->t_rx = now;
    a->seq = bump(v);
    return 1;
}

static int mail_cast(kelp_viewer *v, const char *s, size_t len, kelp_time now)
{
    char node[KELP_NODEREPORT_MAX_FIELD] = "", proc[KELP_NODEREPORT_MAX_FIELD];
    if (len >= KELP_MAX_SVAL || memchr(s, '\0', len) || !kelp_appcast_field(s, len, "proc", proc, sizeof proc) || !proc[0]) {
        v->stats.casts_bad++;
        return KELP_ERR_PARSE;
    }
    (void)kelp_appcast_field(s, len, "node", node, sizeof node);
    kelp_viewer_cast *c = NULL, *freeslot = NULL, *oldest = NULL;
    for (unsigned i = 0; i < KELP_VIEWER_MAX_CASTS && !c; i++) {
        kelp_viewer_cast *e = &v->casts[i];
        if (!e->used) {
            if (!freeslot) freeslot = e;
        } else if (strcmp(e->node, node) == 0 && strcmp(e->proc, proc) == 0) {
            c = e;
        } else if (!oldest || e->seq < oldest->seq) {
            oldest = e;
        }
    }
    if (!c && !(c = freeslot)) {
        c = oldest; /* dropped without a tombstone: pages that had it get a snapshot */
        v->floor = v->seq + 1;
    }
    v->stats.casts++;
    memcpy(c->node, node, sizeof node);
    memcpy(c->proc, proc, sizeof proc);
    memcpy(c->text, s, len);
    c->text[len] = '\0';
    c->t_rx = now;
    c->used = true;
    c->seq = bump(v);
    return 1;
}

int kelp_viewer_mail(kelp_viewer *v, const char *var, const char *sval, size_t len, kelp_time now)
{
    if (!v || !var || !sval) return 0;
    if (!kelp_util_time_ok(now)) return KELP_ERR_ARG; /* a NaN arrival would never turn stale */
    /* (not NODE_REPORT_<VEHICLE>: uFldNodeComms's relayed copies, older than the originals) */
    if (kelp_util_strieq(var, "NODE_REPORT") || kelp_util_strieq(var, "NODE_REPORT_LOCAL")) return mail_report(v, sval, len, now);
    kelp_view_kind kind;
    if (kelp_nodereport_view_kind_of(var, &kind) == 0) return mail_view(v, kind, sval, len, now);
    if (kelp_util_strieq(var, "APPCAST")) return mail_cast(v, sval, len, now);
    return 0;
}

int kelp_viewer_tick(kelp_viewer *v, kelp_time now)
{
    int changed = 0;
    if (!kelp_util_time_ok(now)) return 0;
    for (unsigned i = 0; i < v->nveh; i++) {
        kelp_viewer_vehicle *e = &v->veh[i];
        if (!e->used || e->gone) continue;
        /* the time step rule: a report received "after" now (the clock stepped back) ages from
         * now, so a vehicle gone silent turns stale one threshold later, not the step later */
        if (e->t_rx > now) e->t_rx = now;
        double age = now - e->t_rx;
        if (v->stale_remove_thresh > 0 && age > v->stale_remove_thresh) {
            e->gone = true;
            e->seq = bump(v);
            changed = 1;
        } else if (age > v->stale_report_thresh && !e->stale) {
            e->stale = true;
            e->seq = bump(v);
            changed = 1;
        }
    }
    for (unsigned i = 0; i < KELP_VIEWER_MAX_ARTIFACTS; i++) {
        kelp_viewer_artifact *a = &v->art[i];
        if (!a->used || a->gone || !is_pulse(a->view.kind)) continue;
        if (now - a->t_rx > a->view.duration || now < a->t_rx - 1.0) { /* expired, or time went back (replay) */
            a->gone = true;
            a->seq = bump(v);
            changed = 1;
        }
    }
    return changed;
}

/* ------------------------------------------------------------------ JSON out */

static const char *const kind_names[KELP_VIEW_NKINDS] = {
    "point", "circle", "polygon", "seglist", "marker", "comms_pulse", "range_pulse",
};

static void json_cfg(const kelp_viewer *v, jw *w)
{
    bool f = true;
    jw_lit(w, "\"cfg\":{");
    jw_knum(w, &f, "datum", v->have_datum ? 1 : 0, 0);
    jw_knum(w, &f, "lat0", v->have_datum ? v->geo.lat0 : 0, 8);
    jw_knum(w, &f, "lon0", v->have_datum ? v->geo.lon0 : 0, 8);
    /* the page converts as kelp_geo does (UTM as MOOS): the local grid's radius, the zone's
     * central meridian and the datum's easting/northing */
    jw_knum(w, &f, "R", v->have_datum ? v->geo.radius : 0, 3);
    jw_knum(w, &f, "lonc", v->have_datum ? v->geo.lon_c : 0, 1);
    jw_knum(w, &f, "e0", v->have_datum ? v->geo.e0 : 0, 4);
    jw_knum(w, &f, "n0", v->have_datum ? v->geo.n0 : 0, 4);
    jw_knum(w, &f, "stale", v->stale_report_thresh, 3);
    jw_knum(w, &f, "trails", v->trails_length, 0);
    if (v->image_url[0]) {
        bool g = true;
        jw_key(w, &f, "image");
        jw_lit(w, "{");
        jw_kstr(w, &g, "url", v->image_url);
        jw_knum(w, &g, "n", v->img_n, 8);
        jw_knum(w, &g, "s", v->img_s, 8);
        jw_knum(w, &g, "e", v->img_e, 8);
        jw_knum(w, &g, "w", v->img_w, 8);
        jw_lit(w, "}");
    }
    jw_key(w, &f, "cmds");
    jw_lit(w, "[");
    for (unsigned i = 0; i < v->ncmds; i++) {
        const kelp_viewer_cmd *c = &v->cmds[i];
        bool g = true;
        if (i) jw_lit(w, ",");
        jw_lit(w, "{");
        jw_knum(w, &g, "i", i, 0);
        jw_kstr(w, &g, "kind", c->kind == KELP_VIEWER_BUTTON ? "button" : "action");
        jw_knum(w, &g, "slot", c->slot, 0);
        jw_knum(w, &g, "sep", c->separator ? 1 : 0, 0);
        jw_kstr(w, &g, "label", c->label);
        if (c->key[0]) jw_kstr(w, &g, "key", c->key);
        if (c->color[0]) jw_kstr(w, &g, "color", c->color);
        jw_key(w, &g, "pokes");
        jw_lit(w, "[");
        for (unsigned k = 0; k < c->npokes; k++) {
            const kelp_viewer_poke *p = &c->pokes[k];
            char txt[KELP_MAX_NAME + KELP_VIEWER_MAX_POKE_VAL + 8], num[40];
            if (!p->is_string) (void)kelp_util_fmt_fixed(num, sizeof num, p->dval, 9, true);
            (void)kelp_util_snprintf(txt, sizeof txt, "%s=%s", p->var, p->is_string ? p->sval : num);
            if (k) jw_lit(w, ",");
            jw_str(w, txt);
        }
        jw_lit(w, "]}");
    }
    jw_lit(w, "]}");
}

static void json_vehicle(const kelp_viewer_vehicle *e, jw *w, uint32_t since)
{
    const kelp_nodereport *r = &e->rep;
    bool f = true;
    jw_lit(w, "{");
    jw_kstr(w, &f, "name", r->name);
    if (e->gone) {
        jw_lit(w, ",\"gone\":1}");
        return;
    }
    jw_kstr(w, &f, "type", (r->fields & KELP_NR_TYPE) ? r->type : "");
    jw_knum(w, &f, "x", r->x, 3);
    jw_knum(w, &f, "y", r->y, 3);
    jw_knum(w, &f, "hdg", (r->fields & KELP_NR_HDG) ? r->hdg : 0, 2);
    if (r->fields & KELP_NR_SPD) jw_knum(w, &f, "spd", r->spd, 2);
    if (r->fields & KELP_NR_DEPTH) jw_knum(w, &f, "dep", r->depth, 2);
    if (r->fields & KELP_NR_LAT) jw_knum(w, &f, "lat", r->lat, 7);
    if (r->fields & KELP_NR_LON) jw_knum(w, &f, "lon", r->lon, 7);
    if (r->fields & KELP_NR_LENGTH) jw_knum(w, &f, "len", r->length, 2);
    if (r->fields & KELP_NR_TIME) jw_knum(w, &f, "rtime", r->time, 2);
    if (r->fields & KELP_NR_MODE) jw_kstr(w, &f, "mode", r->mode);
    if (r->fields & KELP_NR_GROUP) jw_kstr(w, &f, "group", r->group);
    if (r->fields & KELP_NR_COLOR) jw_kstr(w, &f, "color", r->color);
    if (r->fields & KELP_NR_ALLSTOP) jw_kstr(w, &f, "allstop", r->allstop);
    jw_knum(w, &f, "t", e->t_rx, 2);
    jw_knum(w, &f, "n", e->nreports, 0);
    jw_knum(w, &f, "stale", e->stale ? 1 : 0, 0);
    jw_key(w, &f, "trail");
    jw_lit(w, "[");
    bool first = true;
    for (unsigned k = 0; k < e->count; k++) {
        unsigned idx = (e->head + k) % KELP_VIEWER_MAX_TRAIL;
        if (e->trail_seq[idx] <= since) continue;
        if (!first) jw_lit(w, ",");
        first = false;
        jw_lit(w, "[");
        jw_num(w, e->trail[idx][0], 2);
        jw_lit(w, ",");
        jw_num(w, e->trail[idx][1], 2);
        jw_lit(w, "]");
    }
    jw_lit(w, "]}");
}

static void json_artifact(const kelp_viewer_artifact *a, jw *w)
{
    const kelp_view *x = &a->view;
    bool f = true;
    jw_lit(w, "{");
    jw_kstr(w, &f, "kind", (unsigned)x->kind < KELP_VIEW_NKINDS ? kind_names[x->kind] : "?");
    jw_kstr(w, &f, "label", x->label);
    if (a->gone) {
        jw_lit(w, ",\"gone\":1}");
        return;
    }
    jw_knum(w, &f, "t", a->t_rx, 2);
    switch (x->kind) {
    case KELP_VIEW_POLYGON:
    case KELP_VIEW_SEGLIST:
        jw_key(w, &f, "pts");
        jw_lit(w, "[");
        for (size_t k = 0; k < x->npts; k++) {
            if (k) jw_lit(w, ",");
            jw_lit(w, "[");
            jw_num(w, x->pts[k][0], 2);
            jw_lit(w, ",");
            jw_num(w, x->pts[k][1], 2);
            jw_lit(w, "]");
        }
        jw_lit(w, "]");
        break;
    case KELP_VIEW_COMMS_PULSE:
        jw_knum(w, &f, "x", x->x, 2);
        jw_knum(w, &f, "y", x->y, 2);
        jw_knum(w, &f, "tx", x->tx, 2);
        jw_knum(w, &f, "ty", x->ty, 2);
        jw_knum(w, &f, "beam", x->beam_width, 2);
        break;
    default:
        jw_knum(w, &f, "x", x->x, 2);
        jw_knum(w, &f, "y", x->y, 2);
        break;
    }
    if (x->kind == KELP_VIEW_CIRCLE || x->kind == KELP_VIEW_RANGE_PULSE) jw_knum(w, &f, "radius", x->radius, 2);
    if (is_pulse(x->kind)) jw_knum(w, &f, "duration", x->duration, 2);
    jw_knum(w, &f, "fill", x->fill, 3);
    jw_knum(w, &f, "edge_size", x->edge_size, 2);
    if (x->fields & KELP_VF_VERTEX_SIZE) jw_knum(w, &f, "vertex_size", x->vertex_size, 2);
    if (x->kind == KELP_VIEW_MARKER) jw_knum(w, &f, "width", x->width, 2);
    if (x->type[0]) jw_kstr(w, &f, "type", x->type);
    if (x->msg[0]) jw_kstr(w, &f, "msg", x->msg);
    if (x->edge_color[0]) jw_kstr(w, &f, "edge_color", x->edge_color);
    if (x->fill_color[0]) jw_kstr(w, &f, "fill_color", x->fill_color);
    if (x->vertex_color[0]) jw_kstr(w, &f, "vertex_color", x->vertex_color);
    if (x->label_color[0]) jw_kstr(w, &f, "label_color", x->label_color);
    jw_lit(w, "}");
}

static int json_out(const kelp_viewer *v, uint32_t since, bool full, kelp_time now, double rate, char *buf, size_t cap,
                    size_t *len)
{
    jw w = {buf, cap, 0, false};
    if (!buf || cap == 0) return KELP_ERR_NOSPACE;
    buf[0] = '\0';
    jw_lit(&w, "{\"seq\":");
    jw_uint(&w, v->seq);
    jw_lit(&w, ",\"now\":");
    jw_num(&w, now, 3);
    jw_lit(&w, ",\"rate\":");
    jw_num(&w, rate, 3);
    jw_lit(&w, full ? ",\"full\":1," : ",\"full\":0,");
    if (full) {
        json_cfg(v, &w);
        jw_lit(&w, ",");
    }
    jw_lit(&w, "\"veh\":[");
    bool first = true;
    for (unsigned i = 0; i < v->nveh; i++) {
        const kelp_viewer_vehicle *e = &v->veh[i];
        if (!e->used || e->seq <= since || (full && e->gone)) continue;
        if (!first) jw_lit(&w, ",");
        first = false;
        json_vehicle(e, &w, full ? 0 : since);
    }
    jw_lit(&w, "],\"art\":[");
    first = true;
    for (unsigned i = 0; i < KELP_VIEWER_MAX_ARTIFACTS; i++) {
        const kelp_viewer_artifact *a = &v->art[i];
        if (!a->used || a->seq <= since || (full && a->gone)) continue;
        if (!first) jw_lit(&w, ",");
        first = false;
        json_artifact(a, &w);
    }
    jw_lit(&w, "],\"cast\":[");
    first = true;
    for (unsigned i = 0; i < KELP_VIEWER_MAX_CASTS; i++) {
        const kelp_viewer_cast *c = &v->casts[i];
        if (!c->used || c->seq <= since) continue;
        bool f = true;
        jw_lit(&w, first ? "{" : ",{");
        first = false;
        jw_kstr(&w, &f, "node", c->node);
        jw_kstr(&w, &f, "proc", c->proc);
        jw_knum(&w, &f, "t", c->t_rx, 2);
        jw_kstr(&w, &f, "text", c->text);
        jw_lit(&w, "}");
    }
    jw_lit(&w, "]}");
    if (len) *len = w.len;
    return w.full ? KELP_ERR_NOSPACE : KELP_OK;
}

int kelp_viewer_json_snapshot(const kelp_viewer *v, kelp_time now, double rate, char *buf, size_t cap, size_t *len)
{
    return json_out(v, 0, true, now, rate, buf, cap, len);
}

int kelp_viewer_json_changes(const kelp_viewer *v, uint32_t since, kelp_time now, double rate, char *buf, size_t cap,
                             size_t *len)
{
    if (since == 0 || since < v->floor || since > v->seq) return json_out(v, 0, true, now, rate, buf, cap, len);
    return json_out(v, since, false, now, rate, buf, cap, len);
}

int kelp_viewer_json_vehicle(const kelp_viewer *v, const char *name, char *buf, size_t cap, size_t *len)
{
    for (unsigned i = 0; i < v->nveh; i++) {
        const kelp_viewer_vehicle *e = &v->veh[i];
        if (!e->used || e->gone || strcmp(e->rep.name, name) != 0) continue;
        jw w = {buf, cap, 0, false};
        if (!buf || cap == 0) return KELP_ERR_NOSPACE;
        json_vehicle(e, &w, UINT32_MAX);
        if (len) *len = w.len;
        return w.full ? KELP_ERR_NOSPACE : KELP_OK;
    }
    return KELP_ERR_NOTFOUND;
}
