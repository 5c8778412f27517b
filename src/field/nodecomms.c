/* uFldNodeComms's logic as MOOS-IvP 24.8 runs it: node reports taken through 24.8's contact
 * ledger and relayed re-serialised, node messages and acks routed by range, stealth, earange,
 * groups, staleness, message rate and length (include/kelp/field.h). Node reports are relayed
 * through a uniform grid so that one report costs work in proportion to its sender's
 * neighbours, not to the fleet. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>
#include <kelp/kv.h>
#include <kelp/mission.h>
#include "field_int.h"
#include <kelp/util.h>

#define NC_MIN_STEALTH 0.1   /* 24.8's floor: a stealth of 0 would hide a vehicle entirely */
#define NC_MAX_EARANGE 10.0  /* 24.8's ceiling */
#define NC_RPT_FILL 0.35     /* 24.8's report pulses */
#define NC_MSG_FILL 0.6      /* 24.8's message pulses */
#define NC_MIN_BEAM 5.0      /* 24.8: a pulse is a tenth of its length wide, 5 m at least */
#define NC_SHARE_TRUE 0.1    /* s of real time between NODE_REPORT_UNC posts (24.8 "true") */
#define NC_FORGET 20.0       /* 24.8 forgets a vehicle after 20 x STALE_TIME */
#define NC_CELL_CLAMP 1073741824.0 /* grid cell coordinates are clamped to +-2^30 */
#define NC_PAIR_PROBES 32    /* linear probes of the pair table before giving up */

/* ------------------------------------------------------------------ small helpers */

static void copy_z(char *dst, size_t cap, const char *src, size_t n)
{
    if (n >= cap) n = cap - 1;
    memcpy(dst, src, n);
    dst[n] = 0;
}

static char up(char ch) { return (char)(ch >= 'a' && ch <= 'z' ? ch - 'a' + 'A' : ch); }

static int parse_num(const char *v, double *out)
{
    double d;
    if (kelp_util_parse_double(v, strlen(v), &d) < 0 || !isfinite(d)) return KELP_ERR_PARSE;
    *out = d;
    return KELP_OK;
}

/* byte order of two counted strings (std::map<std::string> order) */
static int keycmp(const char *a, size_t al, const char *b, size_t bl)
{
    int c = memcmp(a, b, al < bl ? al : bl);
    return c ? c : (al < bl ? -1 : al > bl);
}

static bool eq_n(const char *a, size_t al, const char *z) { return strlen(z) == al && memcmp(a, z, al) == 0; }

/* 24.8's run warning: "Bad Mail: <VAR>" and, for a report, why */
static void bad_mail(kelp_field_ncomms *c, const kelp_field_sink *out, const char *var, const char *why)
{
    if (!out || !out->warn) return;
    size_t n = 0;
    char *b = c->ws_line;
    b[0] = 0;
    (void)field_put_str(b, sizeof c->ws_line, &n, "Bad Mail: ");
    (void)field_put_str(b, sizeof c->ws_line, &n, var);
    if (why && why[0]) {
        (void)field_put_str(b, sizeof c->ws_line, &n, " ");
        (void)field_put_str(b, sizeof c->ws_line, &n, why);
    }
    out->warn(out->ctx, b);
}

/* ------------------------------------------------------------------ configuration */

void kelp_field_ncomms_cfg_default(kelp_field_ncomms_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->comms_range = 100;
    cfg->critical_range = 30;
    cfg->stale_time = 5;
    cfg->min_msg_interval = 30;
    cfg->min_rpt_interval = -1;
    cfg->max_msg_length = 1000;
    cfg->verbose = true;
    cfg->view_node_rpt_pulses = true;
    cfg->pulse_duration = 10;
    cfg->share_interval = -1;
    cfg->warp = 1;
    copy_z(cfg->msg_color, sizeof cfg->msg_color, "white", 5);
    copy_z(cfg->msg_repeat_color, sizeof cfg->msg_repeat_color, "light_green", 11);
    cfg->seed = 0x853c49e6748fea9bull;
}

static double clip(double v, double lo, double hi) { return v < lo ? lo : v > hi ? hi : v; }

/* "vname=alpha, stealth=0.8" / "vname=alpha, earange=4.5" (also 24.8's "earrange"): stealth
 * clamped to [0.1,1], earange to [1,10] */
static int parse_factor(const char *val, bool stealth, char *vname, size_t cap, double *f, kelp_diag *d)
{
    char num[64];
    int a = kelp_kv_get(val, ',', "vname", vname, cap);
    int b = kelp_kv_get(val, ',', stealth ? "stealth" : "earange", num, sizeof num);
    if (b == 0 && !stealth) b = kelp_kv_get(val, ',', "earrange", num, sizeof num);
    if (a != 1) vname[0] = 0; /* 24.8 takes a line without vname (and it applies to nobody) */
    if (a < 0 || strpbrk(vname, " ,=")) {
        return kelp_fail(d, KELP_ERR_PARSE, "needs vname=<one word>");
    }
    if (b != 1 || parse_num(num, f) < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, stealth ? "needs stealth=<number>" : "needs earange=<number>");
    }
    *f = stealth ? clip(*f, NC_MIN_STEALTH, 1) : clip(*f, 1, NC_MAX_EARANGE);
    return KELP_OK;
}

/* SHARED_NODE_REPORTS / UNC_SHARED_NODE_REPORTS: true, false or seconds */
static int parse_share(const char *v, double *out)
{
    double d;
    if (kelp_util_strieq(v, "true")) *out = NC_SHARE_TRUE; /* a number is seconds, not a bool ("1" = 1 s) */
    else if (kelp_util_strieq(v, "false")) *out = -1;
    else if (parse_num(v, &d) == 0 && d >= 0) *out = d;
    else return KELP_ERR_PARSE;
    return KELP_OK;
}

static int set_color(char *dst, size_t cap, const char *v, kelp_diag *d)
{
    size_t n = strlen(v);
    if (n == 0 || n >= cap || strpbrk(v, " ,=")) {
        return kelp_fail(d, KELP_ERR_PARSE, "must be one colour name");
    }
    copy_z(dst, cap, v, n);
    return 1;
}

int kelp_field_ncomms_config(kelp_field_ncomms_cfg *cfg, const char *key, const char *val, kelp_diag *d)
{
    char *v = cfg->ws_val;
    size_t n = strlen(val);
    if (n >= sizeof cfg->ws_val) {
        return kelp_fail(d, KELP_ERR_RANGE, "value too long");
    }
    memcpy(v, val, n + 1);
    while (n && (v[n - 1] == ';' || v[n - 1] == ' ')) v[--n] = 0; /* "PULSE_DURATION = 10;" (A3) */
    size_t kl = strlen(key);
    double dv = 0;
    bool b;
    struct { const char *k; double *dst; double lo; } nums[] = {
        { "COMMS_RANGE", &cfg->comms_range, -INFINITY },   { "CRITICAL_RANGE", &cfg->critical_range, 0 },
        { "STALE_TIME", &cfg->stale_time, -INFINITY },     { "MIN_MSG_INTERVAL", &cfg->min_msg_interval, 0 },
        { "MIN_RPT_INTERVAL", &cfg->min_rpt_interval, -INFINITY }, { "PULSE_DURATION", &cfg->pulse_duration, -INFINITY },
        { "DROP_PERCENTAGE", &cfg->drop_pct, 0 },
    };
    if (kelp_util_strieq_n(key, kl, "COMMS_RANGE") && kelp_util_strieq_n(v, n, "nolimit")) {
        cfg->comms_range = -1;
        return 1;
    }
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++)
        if (kelp_util_strieq_n(key, kl, nums[i].k)) {
            if (parse_num(v, &dv) < 0 || dv < nums[i].lo) {
                return kelp_fail(d, KELP_ERR_PARSE, nums[i].lo == 0 ? "must be a number >= 0" : "must be a number");
            }
            if (nums[i].dst == &cfg->drop_pct && dv > 100) {
                return kelp_fail(d, KELP_ERR_PARSE, "must be a percentage in [0,100]");
            }
            *nums[i].dst = dv;
            return 1;
        }
    if (kelp_util_strieq_n(key, kl, "MAX_MSG_LENGTH")) {
        long l;
        if (kelp_util_parse_long(v, n, &l) < 0 || l < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "must be a count of characters >= 0");
        }
        cfg->max_msg_length = (unsigned long)l;
        return 1;
    }
    struct { const char *k; bool *dst; } bools[] = {
        { "VERBOSE", &cfg->verbose },       { "DEBUG", &cfg->debug },
        { "GROUPS", &cfg->groups },         { "MSG_GROUPS", &cfg->msg_groups },
        { "VIEW_NODE_RPT_PULSES", &cfg->view_node_rpt_pulses },
    };
    for (size_t i = 0; i < sizeof bools / sizeof bools[0]; i++)
        if (kelp_util_strieq_n(key, kl, bools[i].k)) {
            if (kelp_util_parse_bool(v, n, &b) < 0) {
                return kelp_fail(d, KELP_ERR_PARSE, "must be true or false");
            }
            *bools[i].dst = b;
            return 1;
        }
    if (kelp_util_strieq_n(key, kl, "SHARED_NODE_REPORTS")) {
        if (parse_share(v, &cfg->share_interval) < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "must be true, false or seconds >= 0");
        }
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "MSG_COLOR")) return set_color(cfg->msg_color, sizeof cfg->msg_color, v, d);
    if (kelp_util_strieq_n(key, kl, "MSG_REPEAT_COLOR"))
        return set_color(cfg->msg_repeat_color, sizeof cfg->msg_repeat_color, v, d);
    bool st = kelp_util_strieq_n(key, kl, "STEALTH");
    if (st || kelp_util_strieq_n(key, kl, "EARANGE")) {
        kelp_ncomms_factor f;
        memset(&f, 0, sizeof f);
        int rc = parse_factor(v, st, f.vname, sizeof f.vname, st ? &f.stealth : &f.earange, d);
        if (rc < 0) return rc;
        if (cfg->nfactor >= KELP_NCOMMS_MAX_FACTORS) {
            return kelp_fail(d, KELP_ERR_NOSPACE, "too many STEALTH/EARANGE lines");
        }
        cfg->factor[cfg->nfactor++] = f;
        return 1;
    }
    return 0;
}

/* ------------------------------------------------------------------ the vehicle table */

/* a vehicle by its exact name (24.8's maps are keyed by the name as written) */
static int find_n(const kelp_field_ncomms *c, const char *s, size_t n)
{
    uint32_t h = kelp_util_hash(s, n);
    for (uint32_t i = 0; i < KELP_NCOMMS_NAME_SLOTS; i++) {
        int16_t slot = c->name_slot[(h + i) & (KELP_NCOMMS_NAME_SLOTS - 1)];
        if (slot == 0) return -1;
        if (eq_n(s, n, c->node[slot - 1].name)) return slot - 1;
    }
    return -1;
}

int kelp_field_ncomms_find(const kelp_field_ncomms *c, const char *name)
{
    return find_n(c, name, strlen(name));
}

/* find or add; -1 when the table is full or the name is empty or does not fit */
static int node_get(kelp_field_ncomms *c, const char *s, size_t n)
{
    int i = find_n(c, s, n);
    if (i >= 0) return i;
    if (c->nnodes >= KELP_NCOMMS_MAX_NODES || n == 0 || n >= KELP_NODEREPORT_MAX_FIELD) return -1;
    kelp_ncomms_node *nd = &c->node[c->nnodes];
    memset(nd, 0, sizeof *nd);
    copy_z(nd->name, sizeof nd->name, s, n);
    nd->stealth = 1;
    nd->earange = 1;
    kelp_ncomms_hot *h = &c->hot[c->nnodes];
    h->bucket = -1;
    h->next = h->prev = -1;
    uint32_t hh = kelp_util_hash(s, n);
    for (uint32_t k = 0;; k++) {
        int16_t *slot = &c->name_slot[(hh + k) & (KELP_NCOMMS_NAME_SLOTS - 1)];
        if (*slot == 0) {
            *slot = (int16_t)(c->nnodes + 1);
            break;
        }
    }
    /* the name-ordered index: binary search, then shift */
    unsigned lo = 0, hi = c->nnodes;
    while (lo < hi) {
        unsigned mid = (lo + hi) / 2;
        const char *m = c->node[c->sorted[mid]].name;
        if (keycmp(m, strlen(m), s, n) < 0) lo = mid + 1;
        else hi = mid;
    }
    memmove(&c->sorted[lo + 1], &c->sorted[lo], (c->nnodes - lo) * sizeof c->sorted[0]);
    c->sorted[lo] = (uint16_t)c->nnodes;
    return (int)c->nnodes++;
}

/* in the ledger: a report received and not forgotten (then it is in the grid) */
#define LEDGER(c, i) ((c)->hot[i].bucket >= 0)

/* ------------------------------------------------------------------ the grid */

static int32_t cell_of(double v, double cell)
{
    double q = floor(v / cell);
    return (int32_t)clip(q, -NC_CELL_CLAMP, NC_CELL_CLAMP);
}

static int32_t bucket_of(int32_t cx, int32_t cy)
{
    uint32_t h = (uint32_t)cx * 0x9E3779B1u ^ (uint32_t)cy * 0x85EBCA77u;
    h ^= h >> 15;
    return (int32_t)(h & (KELP_NCOMMS_GRID_BUCKETS - 1));
}

static void grid_remove(kelp_field_ncomms *c, int i)
{
    kelp_ncomms_hot *h = &c->hot[i];
    if (h->bucket < 0) return;
    if (h->prev >= 0) c->hot[h->prev].next = h->next;
    else c->grid[h->bucket] = h->next;
    if (h->next >= 0) c->hot[h->next].prev = h->prev;
    h->next = h->prev = -1;
    h->bucket = -1;
}

static void grid_insert(kelp_field_ncomms *c, int i)
{
    kelp_ncomms_hot *h = &c->hot[i];
    h->cx = cell_of(h->x, c->cell);
    h->cy = cell_of(h->y, c->cell);
    h->bucket = bucket_of(h->cx, h->cy);
    h->prev = -1;
    h->next = c->grid[h->bucket];
    if (h->next >= 0) c->hot[h->next].prev = i;
    c->grid[h->bucket] = i;
}

/* cell = the larger base range; rebuilt when COMMS_RANGE changes */
static void grid_rebuild(kelp_field_ncomms *c)
{
    double cell = c->comms_range > c->cfg.critical_range ? c->comms_range : c->cfg.critical_range;
    if (!(cell > 0)) cell = 1;
    c->cell = cell;
    for (unsigned b = 0; b < KELP_NCOMMS_GRID_BUCKETS; b++) c->grid[b] = -1;
    for (unsigned i = 0; i < c->nnodes; i++)
        if (c->hot[i].bucket >= 0) {
            c->hot[i].bucket = -1;
            grid_insert(c, (int)i);
        }
}

static void update_max_earange(kelp_field_ncomms *c)
{
    double m = 1;
    for (unsigned i = 0; i < c->nnodes; i++)
        if (c->node[i].earange > m) m = c->node[i].earange;
    c->max_earange = m;
}

int kelp_field_ncomms_init(kelp_field_ncomms *c, const kelp_field_ncomms_cfg *cfg)
{
    memset(c, 0, sizeof *c);
    c->cfg = *cfg;
    if (!(c->cfg.warp > 0)) c->cfg.warp = 1;
    if (!c->cfg.have_geo && kelp_geo_init(&c->cfg.geo, 0, 0) < 0) return KELP_ERR_ARG; /* 24.8 without a datum */
    c->comms_range = cfg->comms_range;
    c->drop_pct = cfg->drop_pct;
    c->view_rpt_pulses = cfg->view_node_rpt_pulses;
    c->share_interval = cfg->share_interval;
    kelp_rng_seed(&c->rng, cfg->seed); /* the caller seeds it through cfg.seed */
    c->max_earange = 1;
    grid_rebuild(c);
    for (unsigned i = 0; i < cfg->nfactor; i++) {
        const kelp_ncomms_factor *f = &cfg->factor[i];
        if (!f->vname[0]) continue; /* a line without vname: nobody */
        int k = node_get(c, f->vname, strlen(f->vname));
        if (k < 0) return KELP_ERR_NOSPACE;
        if (f->stealth > 0) c->node[k].stealth = f->stealth;
        if (f->earange > 0) c->node[k].earange = f->earange;
    }
    update_max_earange(c);
    return KELP_OK;
}

static const char *const subs[] = { "NODE_REPORT",     "NODE_REPORT_LOCAL", "NODE_MESSAGE",
                                    "MEDIATED_MESSAGE", "ACK_MESSAGE",      "UNC_COMMS_RANGE",
                                    "UNC_STEALTH",      "UNC_EARANGE",      "UNC_DROP_PCT",
                                    "UNC_SHARED_NODE_REPORTS", "UNC_VIEW_NODE_RPT_PULSES" };

const char *kelp_field_ncomms_subscription(unsigned i)
{
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

/* ------------------------------------------------------------------ node and ack messages */

/* A NODE_MESSAGE as 24.8's NodeMessage reads it: pairs split at ',' outside quotes, keys in any
 * case, the last of a repeated key wins; pointers into the text. */
typedef struct nmsg {
    const char *src, *app, *bhv, *dest, *group, *var, *sval, *color, *id, *dval;
    size_t srcl, appl, bhvl, destl, groupl, varl, svall, colorl, idl, dvall;
    bool ack, has_dval, sval_unquote;
} nmsg;

/* the next key=value item of s: 1 with the trimmed key and value, 0 at the end */
static int next_pair(const char *s, size_t len, size_t *pos, const char **k, size_t *kl, const char **v, size_t *vl)
{
    const char *it;
    size_t il;
    if (field_next_item(s, len, pos, ',', &it, &il) != 1) return 0;
    const char *eq = memchr(it, '=', il);
    *k = it;
    *kl = eq ? (size_t)(eq - it) : il;
    *v = eq ? eq + 1 : it + il;
    *vl = eq ? il - *kl - 1 : 0;
    while (*kl && ((*k)[*kl - 1] == ' ' || (*k)[*kl - 1] == '\t')) (*kl)--;
    while (*vl && (**v == ' ' || **v == '\t')) (*v)++, (*vl)--;
    while (*vl && ((*v)[*vl - 1] == ' ' || (*v)[*vl - 1] == '\t')) (*vl)--;
    return 1;
}

static bool quoted(const char *v, size_t n) { return n >= 2 && v[0] == '"' && v[n - 1] == '"'; }

static void nm_parse(const char *s, size_t len, nmsg *m)
{
    memset(m, 0, sizeof *m);
    size_t pos = 0, kl, vl;
    const char *k, *v;
    bool sval_quoted = false;
    while (next_pair(s, len, &pos, &k, &kl, &v, &vl) == 1) {
        if (kelp_util_strieq_n(k, kl, "src_node")) m->src = v, m->srcl = vl;
        else if (kelp_util_strieq_n(k, kl, "src_app")) m->app = v, m->appl = vl;
        else if (kelp_util_strieq_n(k, kl, "src_bhv")) m->bhv = v, m->bhvl = vl;
        else if (kelp_util_strieq_n(k, kl, "dest_node")) m->dest = v, m->destl = vl;
        else if (kelp_util_strieq_n(k, kl, "dest_group")) m->group = v, m->groupl = vl;
        else if (kelp_util_strieq_n(k, kl, "var_name")) m->var = v, m->varl = vl;
        else if (kelp_util_strieq_n(k, kl, "string_val")) m->sval = v, m->svall = vl;
        else if (kelp_util_strieq_n(k, kl, "color")) {
            if (vl && !memchr(v, ' ', vl)) m->color = v, m->colorl = vl; /* a colour name */
        } else if (kelp_util_strieq_n(k, kl, "ack_id")) m->id = v, m->idl = vl;
        else if (kelp_util_strieq_n(k, kl, "string_val_quoted") && kelp_util_strieq_n(v, vl, "true")) sval_quoted = true;
        else if (kelp_util_strieq_n(k, kl, "ack") && kelp_util_strieq_n(v, vl, "true")) m->ack = true;
        else if (kelp_util_strieq_n(k, kl, "double_val")) m->dval = v, m->dvall = vl, m->has_dval = true;
    }
    /* quotes added to hide separators come off, unless the value still holds one */
    m->sval_unquote = sval_quoted && quoted(m->sval, m->svall) && !memchr(m->sval + 1, ',', m->svall - 2);
    if (m->sval_unquote) m->sval++, m->svall -= 2;
}

static bool nm_valid(const nmsg *m)
{
    return m->srcl && (m->destl || m->groupl) && m->varl && !(m->svall && m->has_dval);
}

/* 24.8's NodeMessage::length(): the string value's characters, 2 at least */
static size_t nm_length(const nmsg *m) { return m->svall > 2 ? m->svall : 2; }

static int put_pair(char *b, size_t cap, size_t *n, const char *key, const char *v, size_t vl)
{
    if (!vl) return KELP_OK;
    if (*n + 1 + strlen(key) + 1 + vl >= cap) return KELP_ERR_NOSPACE;
    if (*n) b[(*n)++] = ',';
    int rc = field_put_str(b, cap, n, key);
    b[(*n)++] = '=';
    memcpy(b + *n, v, vl), *n += vl;
    b[*n] = 0;
    return rc;
}

/* NodeMessage::getSpec: ack_id, ack, src_node, dest_node, dest_group, src_app, src_bhv,
 * var_name, color, double_val (6 decimals, trailing zeros stripped), string_val */
static int nm_spec(const nmsg *m, const char *app, char *b, size_t cap)
{
    size_t n = 0;
    int rc = KELP_OK;
    b[0] = 0;
    rc |= put_pair(b, cap, &n, "ack_id", m->id, m->idl);
    if (m->ack) rc |= put_pair(b, cap, &n, "ack", "true", 4);
    rc |= put_pair(b, cap, &n, "src_node", m->src, m->srcl);
    rc |= put_pair(b, cap, &n, "dest_node", m->dest, m->destl);
    rc |= put_pair(b, cap, &n, "dest_group", m->group, m->groupl);
    if (m->appl) rc |= put_pair(b, cap, &n, "src_app", m->app, m->appl);
    else if (app) rc |= put_pair(b, cap, &n, "src_app", app, strlen(app));
    rc |= put_pair(b, cap, &n, "src_bhv", m->bhv, m->bhvl);
    rc |= put_pair(b, cap, &n, "var_name", m->var, m->varl);
    rc |= put_pair(b, cap, &n, "color", m->color, m->colorl);
    if (m->has_dval) {
        double d = 0; /* atof: what does not read as a number is 0 */
        if (kelp_util_parse_double(m->dval, m->dvall, &d) < 0 || !isfinite(d)) d = 0;
        if (rc == KELP_OK) {
            if (n) rc = field_put_str(b, cap, &n, ",");
            if (rc == KELP_OK) rc = field_put_str(b, cap, &n, "double_val=");
            if (rc == KELP_OK) rc = field_put_fixed(b, cap, &n, d, 6, true);
        }
    }
    rc |= put_pair(b, cap, &n, "string_val", m->sval, m->svall);
    return rc == KELP_OK ? KELP_OK : KELP_ERR_NOSPACE;
}

/* An ACK_MESSAGE as 24.8's AckMessage reads it: src, dest, id (a name holding white space, or
 * naming the other end, is not taken). */
typedef struct amsg {
    const char *src, *dest, *id;
    size_t srcl, destl, idl;
} amsg;

static bool has_white(const char *v, size_t n) { return memchr(v, ' ', n) || memchr(v, '\t', n); }

static bool am_parse(const char *s, size_t len, amsg *m)
{
    memset(m, 0, sizeof *m);
    size_t pos = 0, kl, vl;
    const char *k, *v;
    while (next_pair(s, len, &pos, &k, &kl, &v, &vl) == 1) {
        if (kelp_util_strieq_n(k, kl, "src")) {
            if (!has_white(v, vl) && !(vl == m->destl && !memcmp(v, m->dest ? m->dest : "", vl))) m->src = v, m->srcl = vl;
        } else if (kelp_util_strieq_n(k, kl, "dest")) {
            if (!has_white(v, vl) && !(vl == m->srcl && !memcmp(v, m->src ? m->src : "", vl))) m->dest = v, m->destl = vl;
        } else if (kelp_util_strieq_n(k, kl, "id")) {
            m->id = v, m->idl = vl;
        }
    }
    return m->srcl && m->destl && m->idl;
}

static int am_spec(const amsg *m, char *b, size_t cap)
{
    if (m->idl + m->srcl + m->destl + 20 >= cap) return KELP_ERR_NOSPACE;
    size_t n = 0;
    int rc = field_put_str(b, cap, &n, "id=");
    memcpy(b + n, m->id, m->idl), n += m->idl;
    b[n] = 0;
    rc |= field_put_str(b, cap, &n, ", src=");
    memcpy(b + n, m->src, m->srcl), n += m->srcl;
    b[n] = 0;
    rc |= field_put_str(b, cap, &n, ", dest=");
    memcpy(b + n, m->dest, m->destl), n += m->destl;
    b[n] = 0;
    return rc;
}

static int queue_msg(kelp_field_ncomms *c, const char *var, const char *s, const char *source, bool is_ack,
                     const kelp_field_sink *out)
{
    size_t len = strlen(s);
    int src = -1;
    nmsg m;
    amsg a;
    bool valid = is_ack ? am_parse(s, len, &a) : (nm_parse(s, len, &m), nm_valid(&m));
    if (!valid) {
        bad_mail(c, out, var, NULL);
        return KELP_ERR_PARSE;
    }
    src = is_ack ? node_get(c, a.src, a.srcl) : node_get(c, m.src, m.srcl);
    if (src < 0 || c->nmsg >= KELP_NCOMMS_MAX_MSGS) {
        c->msgs_queue_full++;
        bad_mail(c, out, var, src < 0 ? "(no room for its source)" : "(more pending messages than kept)");
        return KELP_ERR_NOSPACE;
    }
    kelp_ncomms_msg *q = &c->msg[c->nmsg];
    q->is_ack = is_ack;
    q->src = (uint16_t)src;
    if ((is_ack ? am_spec(&a, q->text, sizeof q->text) : nm_spec(&m, source, q->text, sizeof q->text)) < 0) {
        bad_mail(c, out, var, "(too long)");
        return KELP_ERR_NOSPACE;
    }
    c->nmsg++;
    if (is_ack) {
        c->acks_rcvd++;
        c->node[src].acks_rcvd++;
    } else {
        c->msgs_rcvd++;
        c->node[src].msgs_rcvd++;
    }
    return 1;
}

/* ------------------------------------------------------------------ publications */

static void publish_to(const kelp_field_sink *out, const char *prefix, const char *name, bool upper, const char *val)
{
    char var[KELP_MAX_NAME + KELP_NODEREPORT_MAX_FIELD];
    size_t n = 0;
    var[0] = 0;
    (void)field_put_str(var, sizeof var, &n, prefix);
    for (const char *p = name; *p && n + 1 < sizeof var; p++) var[n++] = upper ? up(*p) : *p;
    var[n] = 0;
    out->publish(out->ctx, var, true, val, 0);
}

/* VIEW_COMMS_PULSE as 24.8's XYCommsPulse::get_spec writes it: sx,sy,tx,ty,beam_width (a tenth
 * of the range, 5 at least),fill,ptype,label (<src>2<dest>, then the colour unless it is the
 * report pulses' "auto"),fill_color,time,duration,edge_size */
static void pulse(kelp_field_ncomms *c, int s, int d, const char *ptype, const char *color, double fill,
                  kelp_time now, const kelp_field_sink *out)
{
    bool autoc = color == NULL;
    if (!(c->cfg.pulse_duration > 0) || s == d) return;
    if (!autoc && (kelp_util_strieq(color, "off") || kelp_util_strieq(color, "invisible"))) return;
    char *b = c->ws_pulse;
    const size_t cap = sizeof c->ws_pulse;
    size_t n = 0;
    int rc = 0;
    double sx = LEDGER(c, s) ? c->hot[s].x : 0, sy = LEDGER(c, s) ? c->hot[s].y : 0;
    double tx = LEDGER(c, d) ? c->hot[d].x : 0, ty = LEDGER(c, d) ? c->hot[d].y : 0;
    double bw = 0.1 * hypot(sx - tx, sy - ty);
    if (bw < NC_MIN_BEAM) bw = NC_MIN_BEAM;
    const double num[5] = { sx, sy, tx, ty, bw };
    static const char *const key[5] = { "sx=", ",sy=", ",tx=", ",ty=", ",beam_width=" };
    for (int i = 0; i < 5; i++) {
        rc |= field_put_str(b, cap, &n, key[i]);
        rc |= field_put_fixed(b, cap, &n, num[i], 5, true);
    }
    rc |= field_put_str(b, cap, &n, ",fill=");
    rc |= field_put_fixed(b, cap, &n, fill, 5, true);
    rc |= field_put_str(b, cap, &n, ",ptype=");
    rc |= field_put_str(b, cap, &n, ptype);
    rc |= field_put_str(b, cap, &n, ",label=");
    rc |= field_put_str(b, cap, &n, c->node[s].name);
    rc |= field_put_str(b, cap, &n, "2");
    rc |= field_put_str(b, cap, &n, c->node[d].name);
    if (!autoc) rc |= field_put_str(b, cap, &n, color);
    rc |= field_put_str(b, cap, &n, ",fill_color=");
    rc |= field_put_str(b, cap, &n, autoc ? "orange" : color);
    rc |= field_put_str(b, cap, &n, ",time=");
    rc |= field_put_fixed(b, cap, &n, now, 2, true);
    rc |= field_put_str(b, cap, &n, ",duration=");
    rc |= field_put_fixed(b, cap, &n, c->cfg.pulse_duration, 2, true);
    rc |= field_put_str(b, cap, &n, ",edge_size=0");
    if (rc != 0) return; /* a position too large to print: no pulse */
    out->publish(out->ctx, "VIEW_COMMS_PULSE", true, b, 0);
    c->pulses++;
}

/* 24.8: rand() % 100 < drop_percentage */
static bool drop(kelp_field_ncomms *c)
{
    return c->drop_pct > 0 && (double)(kelp_rng_next(&c->rng) % 100) < c->drop_pct;
}

static uint32_t pair_key(int s, int d) { return ((uint32_t)(s + 1) << 16) | (uint32_t)(d + 1); }

/* MIN_RPT_INTERVAL: may S -> D go now? A pair met for the first time may, and is stamped
 * (24.8's meetsReportRateThresh); stamp_only: a relay went (postNodeReport stamps it). */
static bool pair_ok(kelp_field_ncomms *c, int s, int d, kelp_time now, bool stamp_only)
{
    double iv = c->cfg.min_rpt_interval;
    uint32_t key = pair_key(s, d);
    uint32_t h = key * 0x9E3779B1u;
    h ^= h >> 16;
    int free_slot = -1;
    for (uint32_t i = 0; i < NC_PAIR_PROBES; i++) {
        uint32_t k = (h + i) & (KELP_NCOMMS_PAIR_SLOTS - 1);
        kelp_ncomms_pair *p = &c->pair[k];
        if (p->key == key) {
            if (!stamp_only && now - p->t < iv) return false;
            p->t = now;
            return true;
        }
        if (free_slot < 0 && (p->key == 0 || now - p->t >= iv)) free_slot = (int)k; /* empty or expired */
        if (p->key == 0) break;
    }
    if (free_slot < 0) {
        c->pair_full++; /* the table is full of live stamps: send (never withhold by accident) */
        return true;
    }
    c->pair[free_slot].key = key;
    c->pair[free_slot].t = now;
    return true;
}

static void send_report(kelp_field_ncomms *c, int s, int d, kelp_time now, const kelp_field_sink *out)
{
    publish_to(out, "NODE_REPORT_", c->node[d].name, true, c->node[s].report);
    if (c->view_rpt_pulses) pulse(c, s, d, "nrep", NULL, NC_RPT_FILL, now, out);
    c->rpts_sent++;
    c->node[d].rpts_sent++;
    if (c->cfg.min_rpt_interval >= 0) (void)pair_ok(c, s, d, now, true);
}

static double range_of(const kelp_field_ncomms *c, int s, int d)
{
    return hypot(c->hot[s].x - c->hot[d].x, c->hot[s].y - c->hot[d].y);
}

/* 24.8's meetsRangeThresh: range <= COMMS_RANGE * stealth(s) * earange(d), both reports valid */
static bool range_ok(const kelp_field_ncomms *c, int s, int d)
{
    if (c->comms_range < 0) return true;
    if (c->comms_range == 0) return false;
    if (!c->node[s].valid || !c->node[d].valid) return false;
    return !(range_of(c, s, d) > c->comms_range * c->node[s].stealth * c->node[d].earange);
}

/* 24.8's order of criteria: within CRITICAL_RANGE always; else D heard from recently, in
 * range, same group (GROUPS), not dropped, MIN_RPT_INTERVAL passed */
static unsigned long relay_pair(kelp_field_ncomms *c, int s, int d, kelp_time now, const kelp_field_sink *out)
{
    c->scanned++;
    if (c->node[s].valid && c->node[d].valid && range_of(c, s, d) <= c->cfg.critical_range) {
        send_report(c, s, d, now, out);
        return 1;
    }
    if (c->cfg.stale_time >= 0 && now - c->hot[d].t_recv >= c->cfg.stale_time) return 0;
    if (!range_ok(c, s, d)) return 0;
    if (c->cfg.groups && strcmp(c->node[s].group, c->node[d].group) != 0) return 0;
    if (drop(c)) return 0;
    if (c->cfg.min_rpt_interval >= 0 && !pair_ok(c, s, d, now, false)) return 0;
    send_report(c, s, d, now, out);
    return 1;
}

/* node indices in name order (shell sort; stable enough: names are unique) */
static void sort_by_name(const kelp_field_ncomms *c, uint16_t *idx, unsigned n)
{
    for (unsigned gap = n / 2; gap > 0; gap /= 2)
        for (unsigned i = gap; i < n; i++) {
            uint16_t t = idx[i];
            unsigned j = i;
            for (; j >= gap && strcmp(c->node[idx[j - gap]].name, c->node[t].name) > 0; j -= gap) idx[j] = idx[j - gap];
            idx[j] = t;
        }
}

/* every receiver of S's report, in name order: the fleet, or the grid cells within S's
 * largest effective range */
static unsigned long relay_from(kelp_field_ncomms *c, int s, kelp_time now, const kelp_field_sink *out)
{
    unsigned long sent = 0;
    double reach = c->comms_range * c->node[s].stealth * c->max_earange;
    if (reach < c->cfg.critical_range) reach = c->cfg.critical_range;
    double k = ceil(reach / c->cell);
    if (c->comms_range < 0 || (2 * k + 1) * (2 * k + 1) >= (double)c->nreporting) {
        for (unsigned j = 0; j < c->nnodes; j++) {
            int d = c->sorted[j];
            if (d != s && LEDGER(c, d)) sent += relay_pair(c, s, d, now, out);
        }
        return sent;
    }
    unsigned n = 0;
    int32_t kk = (int32_t)k, cx = c->hot[s].cx, cy = c->hot[s].cy;
    for (int32_t gx = cx - kk; gx <= cx + kk; gx++)
        for (int32_t gy = cy - kk; gy <= cy + kk; gy++)
            for (int32_t d = c->grid[bucket_of(gx, gy)]; d >= 0; d = c->hot[d].next) {
                const kelp_ncomms_hot *h = &c->hot[d];
                if (h->cx != gx || h->cy != gy || d == s) continue; /* another cell in this bucket */
                c->ws_idx[n++] = (uint16_t)d;
            }
    sort_by_name(c, c->ws_idx, n);
    for (unsigned j = 0; j < n; j++) sent += relay_pair(c, s, c->ws_idx[j], now, out);
    return sent;
}

/* SHARED_NODE_REPORTS: NODE_REPORT_UNC at most every share_interval s of real time (24.8 posts
 * the real time elapsed as RTE each time it looks) */
static void share(kelp_field_ncomms *c, int s, kelp_time now, const kelp_field_sink *out)
{
    kelp_ncomms_node *nd = &c->node[s];
    if (!LEDGER(c, s) || c->share_interval < 0) return;
    if (nd->has_share_time) {
        double rte = (now - nd->share_time) / c->cfg.warp;
        out->publish(out->ctx, "RTE", false, NULL, rte);
        if (rte < c->share_interval) return;
    }
    nd->share_time = now;
    nd->has_share_time = true;
    out->publish(out->ctx, "NODE_REPORT_UNC", true, nd->report, 0);
}

/* ------------------------------------------------------------------ message routing */

static bool recent_id(const kelp_field_ncomms *c, const char *id, size_t n)
{
    for (unsigned i = 0; i < c->nrecent; i++)
        if (eq_n(id, n, c->recent_id[i])) return true;
    return false;
}

static void remember_id(kelp_field_ncomms *c, const char *id, size_t n)
{
    if (n >= KELP_NODEREPORT_MAX_FIELD) return;
    if (c->nrecent < KELP_NCOMMS_RECENT_IDS) c->nrecent++;
    memmove(c->recent_id[1], c->recent_id[0], (c->nrecent - 1) * sizeof c->recent_id[0]);
    copy_z(c->recent_id[0], sizeof c->recent_id[0], id, n);
}

/* a destination's report: valid, and not older than STALE_TIME by its TIME (24.8's
 * hasVNameValidNotStale) */
static bool fresh(const kelp_field_ncomms *c, int d, kelp_time now)
{
    if (!LEDGER(c, d) || !c->node[d].valid) return false;
    return !(c->cfg.stale_time > 0 && now - c->node[d].rpt_time > c->cfg.stale_time);
}

static unsigned long deliver_msg(kelp_field_ncomms *c, const kelp_ncomms_msg *q, kelp_time now,
                                 const kelp_field_sink *out)
{
    nmsg m;
    int s = q->src;
    nm_parse(q->text, strlen(q->text), &m);
    if (!nm_valid(&m)) {
        c->blocked[KELP_NCOMMS_BLK_INVALID]++;
        return 0;
    }
    if (c->cfg.max_msg_length > 0 && nm_length(&m) > c->cfg.max_msg_length) {
        c->blocked[KELP_NCOMMS_BLK_TOO_LONG]++;
        return 0;
    }
    if (!LEDGER(c, s) || !c->node[s].valid) return 0; /* 24.8: a source without a report, silently */
    char color[KELP_VIEW_MAX_FIELD];
    if (m.colorl) copy_z(color, sizeof color, m.color, m.colorl);
    else copy_z(color, sizeof color, c->cfg.msg_color, strlen(c->cfg.msg_color));
    /* the destinations: all, or the dest_node list and the dest_group's members, never S */
    unsigned long mark = ++c->mark, sent = 0;
    bool all = eq_n(m.dest, m.destl, "ALL") || eq_n(m.dest, m.destl, "all") || eq_n(m.group, m.groupl, "ALL") ||
               eq_n(m.group, m.groupl, "all");
    const char *g = m.group;
    size_t gl = m.groupl;
    while (gl && (*g == ' ' || *g == '\t')) g++, gl--;
    while (gl && (g[gl - 1] == ' ' || g[gl - 1] == '\t')) gl--;
    for (unsigned i = 0; i < c->nnodes; i++)
        if (LEDGER(c, i) && (all || (gl && eq_n(g, gl, c->node[i].group)))) c->node[i].mark = mark;
    if (!all) {
        size_t pos = 0, il;
        const char *it;
        while (field_next_item(m.dest, m.destl, &pos, ':', &it, &il) == 1) {
            int d = find_n(c, it, il);
            if (d >= 0 && LEDGER(c, d)) c->node[d].mark = mark;
        }
    }
    c->node[s].mark = 0;
    for (unsigned j = 0; j < c->nnodes; j++) {
        int d = c->sorted[j];
        if (c->node[d].mark != mark) continue;
        if (c->cfg.msg_groups && strcmp(c->node[s].group, c->node[d].group) != 0) continue;
        if (!fresh(c, d, now)) {
            c->blocked[KELP_NCOMMS_BLK_NOINFO]++;
            continue;
        }
        if (!range_ok(c, s, d)) {
            c->blocked[KELP_NCOMMS_BLK_TOO_FAR]++;
            continue;
        }
        if (drop(c)) continue;
        publish_to(out, m.ack ? "MEDIATED_MESSAGE_" : "NODE_MESSAGE_", c->node[d].name, true, q->text);
        bool repeat = m.idl && recent_id(c, m.id, m.idl);
        pulse(c, s, d, "msg", repeat ? c->cfg.msg_repeat_color : color, NC_MSG_FILL, now, out);
        if (m.idl) remember_id(c, m.id, m.idl);
        c->msgs_sent++;
        c->node[d].msgs_sent++;
        sent++;
    }
    return sent;
}

static unsigned long deliver_ack(kelp_field_ncomms *c, const kelp_ncomms_msg *q, kelp_time now,
                                 const kelp_field_sink *out)
{
    amsg a;
    int s = q->src;
    if (!am_parse(q->text, strlen(q->text), &a)) {
        c->blocked[KELP_NCOMMS_BLK_INVALID]++;
        return 0;
    }
    int d = find_n(c, a.dest, a.destl);
    if (!LEDGER(c, s) || !c->node[s].valid || d < 0 || !LEDGER(c, d) || !c->node[d].valid) {
        c->blocked[KELP_NCOMMS_BLK_NOINFO]++;
        return 0;
    }
    if (!fresh(c, s, now) || !fresh(c, d, now)) {
        c->blocked[KELP_NCOMMS_BLK_STALE]++;
        return 0;
    }
    if (!range_ok(c, s, d)) {
        c->blocked[KELP_NCOMMS_BLK_TOO_FAR]++;
        return 0;
    }
    if (drop(c)) return 0;
    publish_to(out, "ACK_MESSAGE_", c->node[d].name, false, q->text);
    c->acks_sent++;
    c->node[d].acks_sent++;
    return 1;
}

/* each source's messages (or acks) in arrival order, sources in name order; one goes only
 * MIN_MSG_INTERVAL after the source's previous one went out, delivered or not */
static unsigned long route(kelp_field_ncomms *c, bool acks, kelp_time now, const kelp_field_sink *out)
{
    uint16_t *idx = c->ws_idx;
    unsigned n = 0;
    unsigned long sent = 0;
    for (unsigned i = 0; i < c->nmsg; i++)
        if (c->msg[i].is_ack == acks) idx[n++] = (uint16_t)i;
    for (unsigned i = 1; i < n; i++) { /* insertion sort by source name: stable */
        uint16_t t = idx[i];
        unsigned j = i;
        for (; j > 0 && strcmp(c->node[c->msg[idx[j - 1]].src].name, c->node[c->msg[t].src].name) > 0; j--)
            idx[j] = idx[j - 1];
        idx[j] = t;
    }
    for (unsigned i = 0; i < n; i++) {
        const kelp_ncomms_msg *q = &c->msg[idx[i]];
        kelp_ncomms_node *sn = &c->node[q->src];
        double *last = acks ? &sn->ack_time : &sn->msg_time;
        bool *has = acks ? &sn->has_ack_time : &sn->has_msg_time;
        if (*has && now - *last < c->cfg.min_msg_interval) {
            c->blocked[KELP_NCOMMS_BLK_TOO_RECENT]++;
            continue;
        }
        sent += acks ? deliver_ack(c, q, now, out) : deliver_msg(c, q, now, out);
        *last = now;
        *has = true;
    }
    return sent;
}

/* 24.8's clearStaleNodes: a vehicle silent for 20 x STALE_TIME leaves the ledger, with its
 * report counts and message times */
static void forget_stale(kelp_field_ncomms *c, kelp_time now)
{
    double forget = c->cfg.stale_time * NC_FORGET;
    if (forget < 0) return;
    for (unsigned i = 0; i < c->nnodes; i++) {
        if (!LEDGER(c, i) || now - c->hot[i].t_recv < forget) continue;
        kelp_ncomms_node *nd = &c->node[i];
        grid_remove(c, (int)i);
        c->nreporting--;
        nd->valid = nd->updated = false;
        nd->rpts_rcvd = nd->rpts_sent = nd->msgs_rcvd = nd->msgs_sent = 0;
        nd->has_msg_time = nd->has_share_time = false;
        c->stale_dropped++;
    }
}

/* ------------------------------------------------------------------ mail */

static int mail_report(kelp_field_ncomms *c, const char *var, const char *s, kelp_time now,
                       const kelp_field_sink *out)
{
    kelp_nodereport *r = &c->ws_rec;
    kelp_diag *d = &c->diag;
    kelp_diag_clear(d);
    size_t len = strlen(s);
    const char *why = NULL;
    if (len + 1 > KELP_NODEREPORT_MAX_LEN) why = "longer than KELP_NODEREPORT_MAX_LEN";
    else if (kelp_nodereport_parse(s, len, r, d) < 0) {
        const char *t = kelp_diag_text(d);
        why = !strcmp(t, "no NAME") ? "Missing vname." : !strncmp(t, "no position", 11) ? "Missing both x/y and lat/lon." : t;
    } else if (!(r->fields & KELP_NR_TIME)) why = "Missing timestamp.";
    else if (kelp_nodereport_complete(r, &c->cfg.geo) < 0) why = "datum conversion failed";
    if (why) {
        c->rpts_bad++;
        bad_mail(c, out, var, why);
        return KELP_ERR_PARSE;
    }
    c->rpts_rcvd++; /* 24.8 counts a report here, an underwater one without depth included */
    int i = node_get(c, r->name, strlen(r->name));
    if (i < 0) {
        c->rpts_full++;
        bad_mail(c, out, var, "(more vehicles than KELP_NCOMMS_MAX_NODES)");
        return KELP_ERR_NOSPACE;
    }
    kelp_ncomms_node *nd = &c->node[i];
    kelp_ncomms_hot *h = &c->hot[i];
    const double prev[2] = { h->x, h->y };
    r->extra = s; /* the keys kelp does not read pass on, as 24.8's properties */
    if (kelp_nodereport_ledger(r, LEDGER(c, i) ? prev : NULL, d) < 0 ||
        kelp_nodereport_format_record(r, c->ws_report, sizeof c->ws_report, NULL) < 0) {
        c->rpts_bad++;
        bad_mail(c, out, var, d->code ? kelp_diag_text(d) : "(too long to relay)");
        return KELP_ERR_PARSE;
    }
    memcpy(nd->report, c->ws_report, sizeof nd->report);
    copy_z(nd->group, sizeof nd->group, r->group, (r->fields & KELP_NR_GROUP) ? strlen(r->group) : 0);
    nd->rpt_time = r->time;
    nd->valid = (r->fields & (KELP_NR_SPD | KELP_NR_HDG)) == (KELP_NR_SPD | KELP_NR_HDG);
    h->x = r->x;
    h->y = r->y;
    h->t_recv = now;
    if (h->bucket < 0) c->nreporting++;
    int32_t cx = cell_of(r->x, c->cell), cy = cell_of(r->y, c->cell);
    if (h->bucket < 0 || cx != h->cx || cy != h->cy) {
        grid_remove(c, i);
        grid_insert(c, i);
    }
    nd->rpts_rcvd++;
    if (!nd->updated) {
        nd->updated = true;
        c->upd[c->nupd++] = (uint16_t)i;
    }
    return 1;
}

static int mail_factor(kelp_field_ncomms *c, const char *var, const char *s, bool stealth, const kelp_field_sink *out)
{
    char vname[KELP_NODEREPORT_MAX_FIELD];
    double f = 1;
    kelp_diag_clear(&c->diag);
    if (parse_factor(s, stealth, vname, sizeof vname, &f, &c->diag) < 0) {
        bad_mail(c, out, var, NULL);
        return KELP_ERR_PARSE;
    }
    if (!vname[0]) return 1; /* 24.8 takes it, for nobody */
    int i = node_get(c, vname, strlen(vname));
    if (i < 0) {
        bad_mail(c, out, var, "(no room for the vehicle)");
        return KELP_ERR_NOSPACE;
    }
    if (stealth) c->node[i].stealth = f;
    else c->node[i].earange = f;
    update_max_earange(c);
    return 1;
}

/* The time step rule (docs/ARCHITECTURE.md), where the tool acts (iterate, report): after a
 * backward step no time this tool stamped with its own clock lies ahead of `now`; each is
 * brought to `now`, so an interval (MIN_RPT_INTERVAL, MIN_MSG_INTERVAL, SHARED_NODE_REPORTS)
 * blocks for at most its own length instead of the step, and no age in the report is negative.
 * (Mail may arrive stamped out of order; it is not where a step is told.)  A report's own TIME is
 * the sender's clock and stays.  A forward step is elapsed time: reports go stale until the next. */
static bool clock_guard(kelp_field_ncomms *c, kelp_time now)
{
    if (!kelp_util_time_ok(now)) return false;
    if (c->started && c->start > now) c->start = now;
    for (unsigned i = 0; i < c->nnodes; i++) {
        kelp_ncomms_node *nd = &c->node[i];
        if (c->hot[i].t_recv > now) c->hot[i].t_recv = now;
        if (nd->msg_time > now) nd->msg_time = now;
        if (nd->ack_time > now) nd->ack_time = now;
        if (nd->share_time > now) nd->share_time = now;
    }
    for (unsigned k = 0; k < KELP_NCOMMS_PAIR_SLOTS; k++)
        if (c->pair[k].key && c->pair[k].t > now) c->pair[k].t = now;
    return true;
}

int kelp_field_ncomms_mail(kelp_field_ncomms *c, const char *var, bool is_string, const char *sval, double dval,
                           const char *source, kelp_time now, const kelp_field_sink *out)
{
    bool ours = false;
    if (!var) return 0;
    for (size_t i = 0; i < sizeof subs / sizeof subs[0]; i++)
        if (strcmp(var, subs[i]) == 0) ours = true;
    if (!ours) return 0;
    if (!kelp_util_time_ok(now)) return KELP_ERR_ARG;
    if (!c->started) c->start = now, c->started = true;
    const char *s = is_string && sval ? sval : ""; /* a double where a string is read: "" (as 24.8) */
    if (!strcmp(var, "NODE_REPORT") || !strcmp(var, "NODE_REPORT_LOCAL")) return mail_report(c, var, s, now, out);
    if (!strcmp(var, "NODE_MESSAGE") || !strcmp(var, "MEDIATED_MESSAGE")) return queue_msg(c, var, s, source, false, out);
    if (!strcmp(var, "ACK_MESSAGE")) return queue_msg(c, var, s, source, true, out);
    if (!strcmp(var, "UNC_STEALTH")) return mail_factor(c, var, s, true, out);
    if (!strcmp(var, "UNC_EARANGE")) return mail_factor(c, var, s, false, out);
    if (!strcmp(var, "UNC_VIEW_NODE_RPT_PULSES")) {
        if (kelp_util_parse_bool(s, strlen(s), &c->view_rpt_pulses) < 0) {
            bad_mail(c, out, var, NULL);
            return KELP_ERR_PARSE;
        }
        return 1;
    }
    if (!strcmp(var, "UNC_SHARED_NODE_REPORTS")) {
        if (parse_share(s, &c->share_interval) < 0) {
            bad_mail(c, out, var, NULL);
            return KELP_ERR_PARSE;
        }
        return 1;
    }
    double d = dval;
    if (is_string ? parse_num(s, &d) < 0 : !isfinite(dval)) {
        bad_mail(c, out, var, NULL);
        return KELP_ERR_PARSE;
    }
    if (!strcmp(var, "UNC_DROP_PCT")) {
        if (d < 0 || d > 100) {
            bad_mail(c, out, var, NULL);
            return KELP_ERR_RANGE;
        }
        c->drop_pct = d;
        return 1;
    }
    /* UNC_COMMS_RANGE: the grid follows */
    c->comms_range = d;
    grid_rebuild(c);
    return 1;
}

/* ------------------------------------------------------------------ iterate */

unsigned long kelp_field_ncomms_iterate(kelp_field_ncomms *c, kelp_time now, const kelp_field_sink *out)
{
    unsigned long posts = 0;
    if (!clock_guard(c, now)) return 0;
    c->now = now;
    if (!c->started) c->start = now, c->started = true;
    /* the senders in name order (24.8's map of new records): from the fleet's name order when
     * many reported (a shoreside of thousands: linear), else sorted in place */
    if ((unsigned long)c->nupd * c->nupd > c->nnodes) {
        unsigned k = 0;
        for (unsigned i = 0; i < c->nnodes && k < c->nupd; i++)
            if (c->node[c->sorted[i]].updated) c->upd[k++] = c->sorted[i];
    } else for (unsigned i = 1; i < c->nupd; i++) {
        uint16_t t = c->upd[i];
        unsigned j = i;
        for (; j > 0 && strcmp(c->node[c->upd[j - 1]].name, c->node[t].name) > 0; j--) c->upd[j] = c->upd[j - 1];
        c->upd[j] = t;
    }
    for (unsigned u = 0; u < c->nupd; u++) {
        int s = c->upd[u];
        c->node[s].updated = false;
        if (!LEDGER(c, s)) continue;
        posts += relay_from(c, s, now, out);
        share(c, s, now, out);
    }
    c->nupd = 0;
    posts += route(c, false, now, out);
    posts += route(c, true, now, out);
    c->nmsg = 0;
    forget_stale(c, now);
    return posts;
}

/* ------------------------------------------------------------------ report */

typedef struct rbuf {
    char *b;
    size_t cap, n;
    bool full;
} rbuf;

static void put(rbuf *r, const char *s)
{
    if (field_put_str(r->b, r->cap, &r->n, s) < 0) r->full = true;
}

/* s padded with blanks to w characters, in front (right-aligned) or behind */
static void put_pad(rbuf *r, const char *s, size_t w, bool front)
{
    size_t l = strlen(s);
    for (size_t i = l; front && i < w; i++) put(r, " ");
    put(r, s);
    for (size_t i = l; !front && i < w; i++) put(r, " ");
}

/* doubleToStringX / doubleToString: dec decimals, stripped or not */
static void put_num(rbuf *r, double v, int dec, bool strip)
{
    char t[48];
    size_t n = 0;
    if (field_put_fixed(t, sizeof t, &n, v, dec, strip) < 0) kelp_util_snprintf(t, sizeof t, "%g", v);
    put(r, t);
}

static void put_ul(rbuf *r, unsigned long v)
{
    char t[24];
    kelp_util_snprintf(t, sizeof t, "%lu", v);
    put(r, t);
}

/* "(<v to 1 decimal>)" or "[<v to 2 decimals>]" padded in front to w */
static void put_paren(rbuf *r, const char *open, double v, int dec, const char *close, size_t w)
{
    char t[64];
    size_t n = 0;
    (void)field_put_str(t, sizeof t, &n, open);
    if (field_put_fixed(t, sizeof t, &n, v, dec, false) < 0) (void)field_put_str(t, sizeof t, &n, "?");
    (void)field_put_str(t, sizeof t, &n, close);
    put_pad(r, t, w, true);
}

/* the vehicles with a count, in name order: reports sent to (what 0), messages received from
 * (1, with the time since its last one went out) and sent to (2) */
static void per_vehicle(rbuf *r, const kelp_field_ncomms *c, int what, kelp_time now)
{
    for (unsigned j = 0; j < c->nnodes; j++) {
        const kelp_ncomms_node *nd = &c->node[c->sorted[j]];
        unsigned long v = what == 0 ? nd->rpts_sent : what == 1 ? nd->msgs_rcvd : nd->msgs_sent;
        if (!v) continue;
        put(r, "  ");
        put_pad(r, nd->name, what == 0 ? 17 : 20, true);
        put(r, ": ");
        put_ul(r, v);
        if (what == 1) put_paren(r, "(", nd->has_msg_time ? now - nd->msg_time : now, 1, ")", 12);
        put(r, "\n");
    }
}

static void put_cfg(rbuf *r, const char *label, double v, int dec)
{
    put(r, label);
    put_num(r, v, dec, true);
    put(r, "\n");
}

int kelp_field_ncomms_report(kelp_field_ncomms *c, kelp_time now, char *buf, size_t cap)
{
    rbuf r = { buf, cap, 0, false };
    if (cap == 0) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    if (!clock_guard(c, now)) return KELP_ERR_ARG;
    /* 24.8 prints "Share Reports" from min_rpt_interval (sic) */
    bool share_on = c->cfg.min_rpt_interval > 0;
    put(&r, "Configuration:  \n");
    put_cfg(&r, "       Comms Range: ", c->comms_range, 5);
    put_cfg(&r, "    Critical Range: ", c->cfg.critical_range, 5);
    put_cfg(&r, "        Stale Drop: ", c->cfg.stale_time, 5);
    put_cfg(&r, "       Stale Foget: ", c->cfg.stale_time * NC_FORGET, 5);
    put_cfg(&r, "   Max Message Len: ", (double)c->cfg.max_msg_length, 5);
    put_cfg(&r, "   Min Message Int: ", c->cfg.min_msg_interval, 5);
    put_cfg(&r, "   Min Report  Int: ", c->cfg.min_rpt_interval, 2);
    put_cfg(&r, "          Drop Pct: ", c->drop_pct, 2);
    put(&r, "Apply Group (reps): ");
    put(&r, c->cfg.groups ? "true\n" : "false\n");
    put(&r, "Apply Group (msgs): ");
    put(&r, c->cfg.msg_groups ? "true\n" : "false\n");
    put(&r, "     Share Reports: ");
    put(&r, share_on ? "true (" : "false");
    if (share_on) {
        put_num(&r, c->share_interval, 2, true);
        put(&r, ")");
    }
    put(&r, "\n\n");

    double elapsed_app = now - c->start;
    char cnt[24];
    put(&r, "Node Report Summary\n======================================\n     Total Received: ");
    kelp_util_snprintf(cnt, sizeof cnt, "%lu", c->rpts_rcvd);
    put_pad(&r, cnt, 10, false);
    put(&r, "Elapsed      Rate\n");
    for (unsigned j = 0; j < c->nnodes; j++) {
        int i = c->sorted[j];
        const kelp_ncomms_node *nd = &c->node[i];
        if (!LEDGER(c, i)) continue;
        put(&r, "  ");
        put_pad(&r, nd->name, 17, true);
        put(&r, ": ");
        kelp_util_snprintf(cnt, sizeof cnt, "%lu", nd->rpts_rcvd);
        put_pad(&r, cnt, 7, false);
        put_paren(&r, "(", now - c->hot[i].t_recv, 1, ")", 8);
        if (elapsed_app > 0) put_paren(&r, "[", (double)nd->rpts_rcvd / elapsed_app, 2, "]", 12);
        else put_pad(&r, "[n/a]", 12, true);
        put(&r, "\n");
    }
    put(&r, "     --------------- \n         Total Sent: ");
    put_ul(&r, c->rpts_sent);
    put(&r, "\n");
    per_vehicle(&r, c, 0, now);
    put(&r, "     --------------- \n     Stale Vehicles: ");
    put_ul(&r, c->stale_dropped);
    put(&r, "\n\nNode Message Summary\n======================================\n    Total Msgs Received: ");
    put_ul(&r, c->msgs_rcvd);
    put(&r, "\n");
    per_vehicle(&r, c, 1, now);
    put(&r, "     ------------------ \n            Total Sent: ");
    put_ul(&r, c->msgs_sent);
    put(&r, "\n");
    per_vehicle(&r, c, 2, now);
    unsigned long total = 0;
    for (int i = 0; i < KELP_NCOMMS_BLK_N; i++) total += c->blocked[i];
    put(&r, "     ------------------ \n    Total Blocked Msgs: ");
    put_ul(&r, total);
    static const struct {
        const char *label;
        kelp_ncomms_block b;
    } lines[] = { { "\n               Invalid: ", KELP_NCOMMS_BLK_INVALID },
                  { "\n          Missing Info: ", KELP_NCOMMS_BLK_NOINFO },
                  { "\n        Stale Receiver: ", KELP_NCOMMS_BLK_STALE },
                  { "\n            Too Recent: ", KELP_NCOMMS_BLK_TOO_RECENT },
                  { "\n          Msg Too Long: ", KELP_NCOMMS_BLK_TOO_LONG },
                  { "\n         Range Too Far: ", KELP_NCOMMS_BLK_TOO_FAR } };
    for (size_t i = 0; i < sizeof lines / sizeof lines[0]; i++) {
        put(&r, lines[i].label);
        put_ul(&r, c->blocked[lines[i].b]);
    }
    put(&r, "\n\n");
    return r.full ? KELP_ERR_NOSPACE : KELP_OK;
}
