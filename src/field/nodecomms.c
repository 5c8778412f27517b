/* uFldNodeComms's logic: node reports and node messages relayed between vehicles by range,
 * stealth, earange, groups, staleness, message rate and length (include/kelp/field.h;
 * ufield.md section 5). Node reports are relayed through a uniform grid so that one report
 * costs work in proportion to its sender's neighbours, not to the fleet. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>
#include <kelp/kv.h>
#include <kelp/mission.h>
#include "field_int.h"
#include <kelp/util.h>

#define NC_MIN_STEALTH 0.1   /* 24.8's floor: a stealth of 0 would hide a vehicle entirely */
#define NC_MAX_EARANGE 10.0  /* the seed's table range [1,10] */
#define NC_BEAM_WIDTH 7      /* seed 1.5 example */
#define NC_RPT_FILL 0.35     /* seed 1.5 example */
#define NC_MSG_FILL 0.6      /* 24.8's message pulses */
#define NC_SHARE_TRUE 0.1    /* s of real time between NODE_REPORT_UNC posts (24.8 "true") */
#define NC_CELL_CLAMP 1073741824.0 /* grid cell coordinates are clamped to +-2^30 */
#define NC_PAIR_PROBES 32    /* linear probes of the pair table before giving up */

static const char *const palette[] = { "orange", "green", "blue", "red", "purple", "yellow", "cyan", "magenta" };
#define NC_PALETTE (sizeof palette / sizeof palette[0])

/* ------------------------------------------------------------------ small helpers */

static void copy_z(char *dst, size_t cap, const char *src, size_t n)
{
    if (n >= cap) n = cap - 1;
    memcpy(dst, src, n);
    dst[n] = 0;
}

static char up(char ch) { return (char)(ch >= 'a' && ch <= 'z' ? ch - 'a' + 'A' : ch); }

/* upper-case copy; KELP_ERR_RANGE when it does not fit */
static int upcopy(char *dst, size_t cap, const char *src, size_t n)
{
    if (n + 1 > cap) return KELP_ERR_RANGE;
    for (size_t i = 0; i < n; i++) dst[i] = up(src[i]);
    dst[n] = 0;
    return KELP_OK;
}


static int parse_num(const char *v, double *out)
{
    double d;
    if (kelp_parse_double(v, strlen(v), &d) < 0 || !isfinite(d)) return KELP_ERR_PARSE;
    *out = d;
    return KELP_OK;
}

/* a run warning made of three pieces (no format strings from data) */
static void warn3(const kelp_field_sink *out, const char *a, const char *b, const char *c)
{
    if (!out || !out->warn) return;
    char buf[200];
    size_t n = 0;
    const char *p[3] = { a, b, c };
    for (int i = 0; i < 3; i++) {
        size_t l = strlen(p[i]);
        if (l > sizeof buf - 1 - n) l = sizeof buf - 1 - n;
        memcpy(buf + n, p[i], l);
        n += l;
    }
    buf[n] = 0;
    out->warn(out->ctx, buf);
}

/* case-insensitive equality of two counted strings */
static bool ieq_nn(const char *a, size_t an, const char *b, size_t bn)
{
    if (an != bn) return false;
    for (size_t i = 0; i < an; i++)
        if (up(a[i]) != up(b[i])) return false;
    return true;
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

/* "vname=alpha, stealth=0.8" / "vname=alpha, earange=4.5" (also 24.8's "earrange") */
static int parse_factor(const char *val, bool stealth, char *vname, size_t cap, double *f, kelp_diag *d)
{
    char num[64];
    int a = kelp_kv_get(val, ',', "vname", vname, cap);
    int b = kelp_kv_get(val, ',', stealth ? "stealth" : "earange", num, sizeof num);
    if (b == 0 && !stealth) b = kelp_kv_get(val, ',', "earrange", num, sizeof num);
    if (a != 1 || !vname[0] || strpbrk(vname, " ,=")) {
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
    if (kelp_strieq(v, "true")) *out = NC_SHARE_TRUE; /* a number is seconds, not a bool ("1" = 1 s) */
    else if (kelp_strieq(v, "false")) *out = -1;
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
    if (kelp_strieq_n(key, kl, "COMMS_RANGE") && kelp_strieq_n(v, n, "nolimit")) {
        cfg->comms_range = -1;
        return 1;
    }
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++)
        if (kelp_strieq_n(key, kl, nums[i].k)) {
            if (parse_num(v, &dv) < 0 || dv < nums[i].lo) {
                return kelp_fail(d, KELP_ERR_PARSE, nums[i].lo == 0 ? "must be a number >= 0" : "must be a number");
            }
            if (nums[i].dst == &cfg->drop_pct && dv > 100) {
                return kelp_fail(d, KELP_ERR_PARSE, "must be a percentage in [0,100]");
            }
            *nums[i].dst = dv;
            return 1;
        }
    if (kelp_strieq_n(key, kl, "MAX_MSG_LENGTH")) {
        long l;
        if (kelp_parse_long(v, n, &l) < 0 || l < 0) {
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
        if (kelp_strieq_n(key, kl, bools[i].k)) {
            if (kelp_parse_bool(v, n, &b) < 0) {
                return kelp_fail(d, KELP_ERR_PARSE, "must be true or false");
            }
            *bools[i].dst = b;
            return 1;
        }
    if (kelp_strieq_n(key, kl, "SHARED_NODE_REPORTS")) {
        if (parse_share(v, &cfg->share_interval) < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "must be true, false or seconds >= 0");
        }
        return 1;
    }
    if (kelp_strieq_n(key, kl, "MSG_COLOR")) return set_color(cfg->msg_color, sizeof cfg->msg_color, v, d);
    if (kelp_strieq_n(key, kl, "MSG_REPEAT_COLOR"))
        return set_color(cfg->msg_repeat_color, sizeof cfg->msg_repeat_color, v, d);
    bool st = kelp_strieq_n(key, kl, "STEALTH");
    if (st || kelp_strieq_n(key, kl, "EARANGE")) {
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

static uint32_t name_hash(const char *s, size_t n)
{
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < n; i++) h = (h ^ (uint8_t)up(s[i])) * 16777619u;
    return h;
}

static int find_n(const kelp_field_ncomms *c, const char *s, size_t n)
{
    uint32_t h = name_hash(s, n);
    for (uint32_t i = 0; i < KELP_NCOMMS_NAME_SLOTS; i++) {
        int16_t slot = c->name_slot[(h + i) & (KELP_NCOMMS_NAME_SLOTS - 1)];
        if (slot == 0) return -1;
        const char *nm = c->node[slot - 1].name;
        if (kelp_strieq_n(s, n, nm)) return slot - 1;
    }
    return -1;
}

int kelp_field_ncomms_find(const kelp_field_ncomms *c, const char *name)
{
    return find_n(c, name, strlen(name));
}

/* find or add; -1 when the table is full or the name does not fit */
static int node_get(kelp_field_ncomms *c, const char *s, size_t n)
{
    int i = find_n(c, s, n);
    if (i >= 0) return i;
    if (c->nnodes >= KELP_NCOMMS_MAX_NODES || n == 0) return -1;
    kelp_ncomms_node *nd = &c->node[c->nnodes];
    if (upcopy(nd->name, sizeof nd->name, s, n) < 0) return -1;
    nd->group[0] = 0;
    nd->report[0] = 0;
    nd->stealth = 1;
    nd->earange = 1;
    nd->last_msg_rcvd = nd->last_msg_sent = nd->last_share = -1;
    nd->color = c->nnodes % NC_PALETTE;
    kelp_ncomms_hot *h = &c->hot[c->nnodes];
    h->bucket = -1;
    h->next = h->prev = -1;
    uint32_t hh = name_hash(s, n);
    for (uint32_t k = 0;; k++) {
        int16_t *slot = &c->name_slot[(hh + k) & (KELP_NCOMMS_NAME_SLOTS - 1)];
        if (*slot == 0) {
            *slot = (int16_t)(c->nnodes + 1);
            break;
        }
    }
    return (int)c->nnodes++;
}

static bool has_report(const kelp_field_ncomms *c, int i) { return c->hot[i].bucket >= 0; }

static bool stale(const kelp_field_ncomms *c, int i, kelp_time now)
{
    return c->cfg.stale_time >= 0 && now - c->hot[i].t_recv > c->cfg.stale_time;
}

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
    c->comms_range = cfg->comms_range;
    c->drop_pct = cfg->drop_pct;
    c->view_rpt_pulses = cfg->view_node_rpt_pulses;
    c->share_interval = cfg->share_interval;
    kelp_rng_seed(&c->rng, cfg->seed); /* the caller seeds it through cfg.seed */
    c->max_earange = 1;
    grid_rebuild(c);
    for (unsigned i = 0; i < cfg->nfactor; i++) {
        const kelp_ncomms_factor *f = &cfg->factor[i];
        int k = node_get(c, f->vname, strlen(f->vname));
        if (k < 0) return KELP_ERR_NOSPACE;
        if (f->stealth > 0) c->node[k].stealth = f->stealth;
        if (f->earange > 0) c->node[k].earange = f->earange;
    }
    update_max_earange(c);
    return KELP_OK;
}

static const char *const subs[] = { "NODE_REPORT",     "NODE_REPORT_LOCAL",   "NODE_MESSAGE",
                                    "MEDIATED_MESSAGE", "ACK_MESSAGE",        "UNC_STEALTH",
                                    "UNC_EARANGE",      "UNC_COMMS_RANGE",    "UNC_DROP_PCT",
                                    "UNC_VIEW_NODE_RPT_PULSES", "UNC_SHARED_NODE_REPORTS",
                                    "UNC_FULL_REPORT_REQ" };

const char *kelp_field_ncomms_subscription(unsigned i)
{
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

/* ------------------------------------------------------------------ node messages */

/* the fields of a NODE_MESSAGE (pointers into the text) */
typedef struct mfields {
    const char *src, *dest, *group, *var, *sval, *dval, *color, *id;
    size_t srcl, destl, groupl, varl, svall, dvall, colorl, idl;
    bool has_sval, has_dval, ack;
} mfields;

static void take(const char **p, size_t *pl, const char *v, size_t vl, bool *seen)
{
    if (*seen) return; /* the first of a repeated key wins */
    *p = v;
    *pl = vl;
    *seen = true;
}

/* src_node, dest_node (dest_name; the seed's "dest_node;bravo" typo too), dest_group,
 * var_name (src_var), string_val, double_val, ack, ack_id (24.8's key; msg_id and id too),
 * color. Unknown keys and items without '=' are ignored. */
static void msg_fields(const char *s, size_t len, mfields *f)
{
    memset(f, 0, sizeof *f);
    bool seen[9] = { false };
    const char *var2 = NULL;
    size_t var2l = 0;
    bool seen2 = false;
    size_t pos = 0;
    const char *it;
    size_t il;
    while (field_next_item(s, len, &pos, ',', &it, &il) == 1) {
        const char *eq = memchr(it, '=', il);
        const char *k = it, *v;
        size_t kl, vl;
        if (eq) {
            kl = (size_t)(eq - it);
            v = eq + 1;
            vl = il - kl - 1;
        } else {
            const char *semi = memchr(it, ';', il);
            if (!semi) continue;
            kl = (size_t)(semi - it);
            if (!kelp_strieq_n(k, kl, "dest_node") && !kelp_strieq_n(k, kl, "dest_name")) continue;
            v = semi + 1;
            vl = il - kl - 1;
        }
        while (kl && (k[kl - 1] == ' ' || k[kl - 1] == '\t')) kl--;
        while (vl && (*v == ' ' || *v == '\t')) v++, vl--;
        if (kelp_strieq_n(k, kl, "src_node")) take(&f->src, &f->srcl, v, vl, &seen[0]);
        else if (kelp_strieq_n(k, kl, "dest_node") || kelp_strieq_n(k, kl, "dest_name"))
            take(&f->dest, &f->destl, v, vl, &seen[1]);
        else if (kelp_strieq_n(k, kl, "dest_group")) take(&f->group, &f->groupl, v, vl, &seen[2]);
        else if (kelp_strieq_n(k, kl, "var_name")) take(&f->var, &f->varl, v, vl, &seen[3]);
        else if (kelp_strieq_n(k, kl, "src_var")) take(&var2, &var2l, v, vl, &seen2);
        else if (kelp_strieq_n(k, kl, "string_val")) take(&f->sval, &f->svall, v, vl, &seen[4]);
        else if (kelp_strieq_n(k, kl, "double_val")) take(&f->dval, &f->dvall, v, vl, &seen[5]);
        else if (kelp_strieq_n(k, kl, "color")) take(&f->color, &f->colorl, v, vl, &seen[6]);
        else if (kelp_strieq_n(k, kl, "ack_id") || kelp_strieq_n(k, kl, "msg_id") || kelp_strieq_n(k, kl, "id"))
            take(&f->id, &f->idl, v, vl, &seen[7]);
        else if (kelp_strieq_n(k, kl, "ack") && !seen[8]) {
            seen[8] = true;
            f->ack = kelp_strieq_n(v, vl, "true");
        }
    }
    if (!seen[3] && seen2) f->var = var2, f->varl = var2l; /* var_name wins over src_var (A7) */
    f->has_sval = seen[4];
    f->has_dval = seen[5];
    /* a quoted string value: its characters are those inside the quotes */
    if (f->has_sval && f->svall >= 2 && f->sval[0] == '"' && f->sval[f->svall - 1] == '"') f->svall -= 2;
}

static bool msg_valid(const mfields *f)
{
    if (f->srcl == 0 || (f->destl == 0 && f->groupl == 0) || f->varl == 0) return false;
    if (f->has_sval == f->has_dval) return false;
    double d;
    if (f->has_dval && (kelp_parse_double(f->dval, f->dvall, &d) < 0 || !isfinite(d))) return false;
    return f->srcl < KELP_NODEREPORT_MAX_FIELD;
}

static void remember_last(kelp_field_ncomms *c, const char *s)
{
    copy_z(c->last_msgs[c->last_head], KELP_NCOMMS_MSG_LEN, s, strlen(s));
    c->last_head = (c->last_head + 1) % KELP_NCOMMS_LAST_MSGS;
    if (c->nlast < KELP_NCOMMS_LAST_MSGS) c->nlast++;
}

static int queue_msg(kelp_field_ncomms *c, const char *s, bool is_ack, kelp_time now, const kelp_field_sink *out)
{
    size_t len = strlen(s);
    remember_last(c, s);
    if (is_ack) c->acks_rcvd++;
    else c->msgs_rcvd++;
    if (c->nmsg >= KELP_NCOMMS_MAX_MSGS) {
        c->msgs_queue_full++;
        warn3(out, is_ack ? "ACK_MESSAGE" : "NODE_MESSAGE", ": more than the pending messages kept between iterations; dropped", "");
        return KELP_ERR_NOSPACE;
    }
    kelp_ncomms_msg *m = &c->msg[c->nmsg++];
    memset(m, 0, sizeof *m);
    m->is_ack = is_ack;
    m->overflow = len + 1 > sizeof m->text;
    if (!m->overflow) memcpy(m->text, s, len + 1);
    const char *src;
    size_t srcl;
    if (is_ack) {
        char a[KELP_NODEREPORT_MAX_FIELD], b[KELP_NODEREPORT_MAX_FIELD], id[KELP_NODEREPORT_MAX_FIELD];
        m->valid = kelp_kv_get(s, ',', "src", a, sizeof a) == 1 && kelp_kv_get(s, ',', "dest", b, sizeof b) == 1 &&
                   kelp_kv_get(s, ',', "id", id, sizeof id) == 1 && a[0] && b[0] && id[0] && !m->overflow;
        src = a;
        srcl = m->valid ? strlen(a) : 0;
        if (srcl) (void)upcopy(m->src, sizeof m->src, src, srcl);
    } else {
        mfields f;
        msg_fields(s, len, &f);
        m->valid = msg_valid(&f);
        m->length = f.has_sval ? f.svall : 0;
        m->ack = f.ack;
        src = f.src;
        srcl = f.srcl < KELP_NODEREPORT_MAX_FIELD ? f.srcl : 0;
        if (srcl) (void)upcopy(m->src, sizeof m->src, src, srcl);
    }
    if (m->src[0] && !is_ack) {
        int k = node_get(c, m->src, strlen(m->src));
        if (k >= 0) {
            c->node[k].msgs_rcvd++;
            c->node[k].last_msg_rcvd = now;
        }
    }
    if (!m->valid) warn3(out, is_ack ? "ACK_MESSAGE" : "NODE_MESSAGE", ": invalid: ", s);
    return m->valid ? 1 : KELP_ERR_PARSE;
}

/* ------------------------------------------------------------------ publications */

static void publish_to(const kelp_field_sink *out, const char *prefix, const char *name, const char *val)
{
    char var[KELP_MAX_NAME + KELP_NODEREPORT_MAX_FIELD];
    size_t n = 0;
    var[0] = 0;
    (void)field_put_str(var, sizeof var, &n, prefix);
    (void)field_put_str(var, sizeof var, &n, name);
    out->publish(out->ctx, var, true, val, 0);
}

/* VIEW_COMMS_PULSE (seed 1.5): sx,sy,tx,ty,beam_width,duration,fill,label,edge_color,
 * fill_color,time,edge_size; label <SRC>2<DST> (reports) or <SRC>2<DST>_MSG (messages) */
static void pulse(kelp_field_ncomms *c, int s, int d, const char *color, double fill, bool msg, kelp_time now,
                  const kelp_field_sink *out)
{
    if (!(c->cfg.pulse_duration > 0) || kelp_strieq(color, "off") || kelp_strieq(color, "invisible")) return;
    char *b = c->ws_pulse;
    size_t n = 0;
    int rc = 0;
    const kelp_ncomms_hot *hs = &c->hot[s], *hd = &c->hot[d];
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, "sx=");
    rc |= field_put_fixed(b, sizeof c->ws_pulse, &n, hs->x, 2, true);
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, ",sy=");
    rc |= field_put_fixed(b, sizeof c->ws_pulse, &n, hs->y, 2, true);
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, ",tx=");
    rc |= field_put_fixed(b, sizeof c->ws_pulse, &n, hd->x, 2, true);
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, ",ty=");
    rc |= field_put_fixed(b, sizeof c->ws_pulse, &n, hd->y, 2, true);
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, ",beam_width=7,duration=");
    rc |= field_put_fixed(b, sizeof c->ws_pulse, &n, c->cfg.pulse_duration, 2, true);
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, ",fill=");
    rc |= field_put_fixed(b, sizeof c->ws_pulse, &n, fill, 2, true);
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, ",label=");
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, c->node[s].name);
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, "2");
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, c->node[d].name);
    if (msg) rc |= field_put_str(b, sizeof c->ws_pulse, &n, "_MSG");
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, ",edge_color=");
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, color);
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, ",fill_color=");
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, color);
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, ",time=");
    rc |= field_put_fixed(b, sizeof c->ws_pulse, &n, now, 2, true);
    rc |= field_put_str(b, sizeof c->ws_pulse, &n, ",edge_size=1");
    if (rc != 0) return; /* a position too large to print: no pulse */
    out->publish(out->ctx, "VIEW_COMMS_PULSE", true, b, 0);
    c->pulses++;
}

static bool drop(kelp_field_ncomms *c)
{
    return c->drop_pct > 0 && kelp_rng_uniform(&c->rng) * 100.0 < c->drop_pct;
}

static uint32_t pair_key(int s, int d) { return ((uint32_t)(s + 1) << 16) | (uint32_t)(d + 1); }

/* min_rpt_interval: true when S -> D may be sent now (and stamps it) */
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

static unsigned long send_report(kelp_field_ncomms *c, int s, int d, kelp_time now, const kelp_field_sink *out)
{
    publish_to(out, "NODE_REPORT_", c->node[d].name, c->node[s].report);
    if (c->view_rpt_pulses) pulse(c, s, d, palette[c->node[s].color], NC_RPT_FILL, false, now, out);
    c->rpts_sent++;
    c->node[d].rpts_sent++;
    if (c->cfg.min_rpt_interval > 0) (void)pair_ok(c, s, d, now, true);
    return 1;
}

static bool in_comms_range(const kelp_field_ncomms *c, int s, int d, double r2)
{
    if (c->comms_range < 0) return true;
    double lim = c->comms_range * c->node[s].stealth * c->node[d].earange;
    return r2 < lim * lim;
}

/* seed 5.4: stale receiver -> skip; r < CRITICAL -> send; groups -> skip; r < COMMS*stealth*
 * earange -> send (24.8: unless dropped or within MIN_RPT_INTERVAL of the last S -> D) */
static unsigned long relay_pair(kelp_field_ncomms *c, int s, int d, kelp_time now, bool full, const kelp_field_sink *out)
{
    c->scanned++;
    if (stale(c, d, now)) return 0;
    double dx = c->hot[s].x - c->hot[d].x, dy = c->hot[s].y - c->hot[d].y;
    double r2 = dx * dx + dy * dy;
    double cr = c->cfg.critical_range;
    if (r2 < cr * cr) return send_report(c, s, d, now, out);
    if (c->cfg.groups && strcmp(c->node[s].group, c->node[d].group) != 0) return 0;
    if (!in_comms_range(c, s, d, r2)) return 0;
    if (!full && drop(c)) {
        c->rpts_dropped++;
        return 0;
    }
    if (!full && c->cfg.min_rpt_interval > 0 && !pair_ok(c, s, d, now, false)) {
        c->rpts_held++;
        return 0;
    }
    return send_report(c, s, d, now, out);
}

/* every receiver of S's report: the grid cells within S's largest effective range */
static unsigned long relay_from(kelp_field_ncomms *c, int s, kelp_time now, const kelp_field_sink *out)
{
    unsigned long sent = 0;
    double reach = c->comms_range * c->node[s].stealth * c->max_earange;
    if (reach < c->cfg.critical_range) reach = c->cfg.critical_range;
    double k = ceil(reach / c->cell);
    if (c->comms_range < 0 || (2 * k + 1) * (2 * k + 1) >= (double)c->nreporting) {
        for (unsigned d = 0; d < c->nnodes; d++)
            if ((int)d != s && has_report(c, (int)d)) sent += relay_pair(c, s, (int)d, now, false, out);
        return sent;
    }
    int32_t kk = (int32_t)k, cx = c->hot[s].cx, cy = c->hot[s].cy;
    for (int32_t gx = cx - kk; gx <= cx + kk; gx++)
        for (int32_t gy = cy - kk; gy <= cy + kk; gy++)
            for (int32_t d = c->grid[bucket_of(gx, gy)]; d >= 0; d = c->hot[d].next) {
                const kelp_ncomms_hot *h = &c->hot[d];
                if (h->cx != gx || h->cy != gy || d == s) continue; /* another cell in this bucket */
                sent += relay_pair(c, s, d, now, false, out);
            }
    return sent;
}

/* ------------------------------------------------------------------ message routing */

static bool msg_in_range(const kelp_field_ncomms *c, int s, int d)
{
    if (c->comms_range == 0) return false;
    double dx = c->hot[s].x - c->hot[d].x, dy = c->hot[s].y - c->hot[d].y;
    return in_comms_range(c, s, d, dx * dx + dy * dy);
}

typedef struct route {
    int src;
    const kelp_ncomms_msg *m;
    const char *color;
    unsigned long sent;
} route;

static void deliver(kelp_field_ncomms *c, route *r, int d, kelp_time now, const kelp_field_sink *out)
{
    if (c->cfg.msg_groups && strcmp(c->node[r->src].group, c->node[d].group) != 0) {
        c->blocked[KELP_NCOMMS_BLK_GROUP]++;
        return;
    }
    if (!has_report(c, d) || stale(c, d, now)) {
        c->blocked[KELP_NCOMMS_BLK_STALE]++;
        return;
    }
    if (!msg_in_range(c, r->src, d)) {
        c->blocked[KELP_NCOMMS_BLK_TOO_FAR]++;
        return;
    }
    if (drop(c)) {
        c->blocked[KELP_NCOMMS_BLK_DROPPED]++;
        return;
    }
    publish_to(out, r->m->ack ? "MEDIATED_MESSAGE_" : "NODE_MESSAGE_", c->node[d].name, r->m->text);
    pulse(c, r->src, d, r->color, NC_MSG_FILL, true, now, out);
    c->msgs_sent++;
    c->node[d].msgs_sent++;
    r->sent++;
}

static bool recent_id(const kelp_field_ncomms *c, const char *id, size_t n)
{
    for (unsigned i = 0; i < c->nrecent; i++)
        if (kelp_strieq_n(id, n, c->recent_id[i]) && strlen(c->recent_id[i]) == n) return true;
    return false;
}

/* the destinations of a message, each once, never its source */
static void route_msg(kelp_field_ncomms *c, const kelp_ncomms_msg *m, kelp_time now, const kelp_field_sink *out)
{
    int src = m->valid ? find_n(c, m->src, strlen(m->src)) : -1;
    if (src < 0 || !has_report(c, src)) {
        c->blocked[KELP_NCOMMS_BLK_INVALID]++;
        return;
    }
    if (m->overflow || (c->cfg.max_msg_length > 0 && m->length > c->cfg.max_msg_length)) {
        c->blocked[KELP_NCOMMS_BLK_TOO_LONG]++;
        return;
    }
    if (c->node[src].last_msg_sent >= 0 && now - c->node[src].last_msg_sent < c->cfg.min_msg_interval) {
        c->blocked[KELP_NCOMMS_BLK_TOO_RECENT]++;
        return;
    }
    mfields f;
    msg_fields(m->text, strlen(m->text), &f);
    char color[KELP_VIEW_MAX_FIELD];
    if (f.colorl) copy_z(color, sizeof color, f.color, f.colorl);
    else copy_z(color, sizeof color, c->cfg.msg_color, strlen(c->cfg.msg_color));
    if (f.idl && recent_id(c, f.id, f.idl)) copy_z(color, sizeof color, c->cfg.msg_repeat_color, strlen(c->cfg.msg_repeat_color));
    route r = { src, m, color, 0 };
    unsigned long mark = ++c->mark;
    c->node[src].mark = mark;
    bool all = (f.destl && kelp_strieq_n(f.dest, f.destl, "all")) || (f.groupl && kelp_strieq_n(f.group, f.groupl, "all"));
    if (all) {
        for (unsigned d = 0; d < c->nnodes; d++)
            if (has_report(c, (int)d) && c->node[d].mark != mark) c->node[d].mark = mark, deliver(c, &r, (int)d, now, out);
    } else {
        size_t pos = 0;
        const char *it;
        size_t il;
        while (field_next_item(f.dest, f.destl, &pos, ':', &it, &il) == 1) {
            int d = find_n(c, it, il);
            if (d < 0 || !has_report(c, d)) {
                /* never heard from: Stale Receiver (A11), once per distinct name */
                bool dup = false;
                size_t p2 = 0;
                const char *it2;
                size_t il2;
                while (!dup && field_next_item(f.dest, f.destl, &p2, ':', &it2, &il2) == 1 && it2 < it)
                    dup = ieq_nn(it2, il2, it, il);
                if (!dup) c->blocked[KELP_NCOMMS_BLK_STALE]++;
                continue;
            }
            if (c->node[d].mark == mark) continue;
            c->node[d].mark = mark;
            deliver(c, &r, d, now, out);
        }
        if (f.groupl) {
            char g[KELP_NODEREPORT_MAX_FIELD];
            if (upcopy(g, sizeof g, f.group, f.groupl) == 0)
                for (unsigned d = 0; d < c->nnodes; d++)
                    if (has_report(c, (int)d) && c->node[d].mark != mark && strcmp(c->node[d].group, g) == 0) {
                        c->node[d].mark = mark;
                        deliver(c, &r, (int)d, now, out);
                    }
        }
    }
    if (f.idl && f.idl < KELP_NODEREPORT_MAX_FIELD) {
        copy_z(c->recent_id[c->recent_head], KELP_NODEREPORT_MAX_FIELD, f.id, f.idl);
        c->recent_head = (c->recent_head + 1) % KELP_NCOMMS_RECENT_IDS;
        if (c->nrecent < KELP_NCOMMS_RECENT_IDS) c->nrecent++;
    }
    if (r.sent) c->node[src].last_msg_sent = now;
}

/* ACK_MESSAGE "src=henry, dest=ike, id=ike_21" -> ACK_MESSAGE_<DEST> (24.8) */
static void route_ack(kelp_field_ncomms *c, const kelp_ncomms_msg *m, kelp_time now, const kelp_field_sink *out)
{
    char dest[KELP_NODEREPORT_MAX_FIELD];
    int s = m->valid ? find_n(c, m->src, strlen(m->src)) : -1;
    if (s < 0 || !has_report(c, s) || kelp_kv_get(m->text, ',', "dest", dest, sizeof dest) != 1) {
        c->blocked[KELP_NCOMMS_BLK_INVALID]++;
        return;
    }
    int d = find_n(c, dest, strlen(dest));
    if (d < 0 || d == s || !has_report(c, d) || stale(c, d, now) || stale(c, s, now)) {
        c->blocked[KELP_NCOMMS_BLK_STALE]++;
        return;
    }
    if (!msg_in_range(c, s, d)) {
        c->blocked[KELP_NCOMMS_BLK_TOO_FAR]++;
        return;
    }
    if (drop(c)) {
        c->blocked[KELP_NCOMMS_BLK_DROPPED]++;
        return;
    }
    publish_to(out, "ACK_MESSAGE_", c->node[d].name, m->text);
    c->acks_sent++;
    c->node[d].acks_sent++;
}

/* ------------------------------------------------------------------ mail */

static int mail_report(kelp_field_ncomms *c, const char *s, kelp_time now, const kelp_field_sink *out)
{
    kelp_nodereport r;
    kelp_diag *d = &c->diag;
    kelp_diag_clear(d);
    size_t len = strlen(s);
    bool bad = true;
    if (len + 1 > KELP_NODEREPORT_MAX_LEN) (void)kelp_fail(d, KELP_ERR_PARSE, "longer than KELP_NODEREPORT_MAX_LEN");
    else if (kelp_nodereport_parse(s, len, &r, d) < 0) (void)kelp_fail(d, KELP_ERR_PARSE, "malformed");
    else if ((!(r.fields & KELP_NR_X) || !(r.fields & KELP_NR_Y)) &&
             (!c->cfg.have_geo || kelp_nodereport_complete(&r, &c->cfg.geo) < 0 || !(r.fields & KELP_NR_X)))
        (void)kelp_fail(d, KELP_ERR_PARSE, "no X,Y (and LAT,LON need the LatOrigin/LongOrigin datum)");
    else bad = false;
    if (bad) {
        c->rpts_bad++;
        warn3(out, "NODE_REPORT: ", kelp_diag_text(d), "");
        return KELP_ERR_PARSE;
    }
    int i = node_get(c, r.name, strlen(r.name));
    if (i < 0) {
        c->rpts_full++;
        warn3(out, "NODE_REPORT: more than KELP_NCOMMS_MAX_NODES vehicles; ignored: ", r.name, "");
        return KELP_ERR_NOSPACE;
    }
    kelp_ncomms_node *nd = &c->node[i];
    kelp_ncomms_hot *h = &c->hot[i];
    memcpy(nd->report, s, len + 1);
    if (r.fields & KELP_NR_GROUP) (void)upcopy(nd->group, sizeof nd->group, r.group, strlen(r.group));
    else nd->group[0] = 0;
    h->x = r.x;
    h->y = r.y;
    h->t_recv = now;
    if (h->bucket < 0) c->nreporting++;
    int32_t cx = cell_of(r.x, c->cell), cy = cell_of(r.y, c->cell);
    if (h->bucket < 0 || cx != h->cx || cy != h->cy) {
        grid_remove(c, i);
        grid_insert(c, i);
    }
    nd->rpts_rcvd++;
    c->rpts_rcvd++;
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
        warn3(out, var, ": ", kelp_diag_text(&c->diag));
        return KELP_ERR_PARSE;
    }
    int i = node_get(c, vname, strlen(vname));
    if (i < 0) {
        warn3(out, var, ": no room for vehicle ", vname);
        return KELP_ERR_NOSPACE;
    }
    if (stealth) c->node[i].stealth = f;
    else c->node[i].earange = f;
    update_max_earange(c);
    return 1;
}

static int mail_number(const char *var, bool is_string, const char *sval, double dval, double *out,
                       const kelp_field_sink *sink)
{
    if (is_string ? parse_num(sval, out) < 0 : !isfinite(dval)) {
        warn3(sink, var, ": not a number: ", is_string ? sval : "");
        return KELP_ERR_PARSE;
    }
    if (!is_string) *out = dval;
    return KELP_OK;
}

int kelp_field_ncomms_mail(kelp_field_ncomms *c, const char *var, bool is_string, const char *sval, double dval,
                           kelp_time now, const kelp_field_sink *out)
{
    static const char *const strvars[] = { "NODE_REPORT", "NODE_REPORT_LOCAL", "NODE_MESSAGE", "MEDIATED_MESSAGE",
                                           "ACK_MESSAGE", "UNC_STEALTH", "UNC_EARANGE", "UNC_VIEW_NODE_RPT_PULSES",
                                           "UNC_SHARED_NODE_REPORTS", "UNC_FULL_REPORT_REQ" };
    bool wants_string = false, ours = false;
    if (!var) return 0;
    for (size_t i = 0; i < sizeof subs / sizeof subs[0]; i++)
        if (strcmp(var, subs[i]) == 0) ours = true;
    if (!ours) return 0;
    for (size_t i = 0; i < sizeof strvars / sizeof strvars[0]; i++)
        if (strcmp(var, strvars[i]) == 0) wants_string = true;
    if (wants_string && (!is_string || !sval)) {
        warn3(out, var, ": a string is expected", "");
        return KELP_ERR_PARSE;
    }
    if (!strcmp(var, "NODE_REPORT") || !strcmp(var, "NODE_REPORT_LOCAL")) return mail_report(c, sval, now, out);
    if (!strcmp(var, "NODE_MESSAGE") || !strcmp(var, "MEDIATED_MESSAGE")) return queue_msg(c, sval, false, now, out);
    if (!strcmp(var, "ACK_MESSAGE")) return queue_msg(c, sval, true, now, out);
    if (!strcmp(var, "UNC_STEALTH")) return mail_factor(c, var, sval, true, out);
    if (!strcmp(var, "UNC_EARANGE")) return mail_factor(c, var, sval, false, out);
    if (!strcmp(var, "UNC_VIEW_NODE_RPT_PULSES")) {
        if (kelp_parse_bool(sval, strlen(sval), &c->view_rpt_pulses) < 0) {
            warn3(out, var, ": must be true or false", "");
            return KELP_ERR_PARSE;
        }
        return 1;
    }
    if (!strcmp(var, "UNC_SHARED_NODE_REPORTS")) {
        if (parse_share(sval, &c->share_interval) < 0) {
            warn3(out, var, ": must be true, false or seconds", "");
            return KELP_ERR_PARSE;
        }
        return 1;
    }
    if (!strcmp(var, "UNC_FULL_REPORT_REQ")) {
        size_t n = strlen(sval);
        while (n && sval[n - 1] == ' ') n--;
        while (n && *sval == ' ') sval++, n--;
        int i = find_n(c, sval, n);
        if (i < 0) {
            warn3(out, var, ": unknown vehicle ", sval);
            return KELP_ERR_NOTFOUND;
        }
        if (c->nfull_req < KELP_NCOMMS_MAX_FULL_REQ) c->full_req[c->nfull_req++] = (uint16_t)i;
        return 1;
    }
    double d;
    if (mail_number(var, is_string, sval, dval, &d, out) < 0) return KELP_ERR_PARSE;
    if (!strcmp(var, "UNC_DROP_PCT")) {
        if (d < 0 || d > 100) {
            warn3(out, var, ": must be in [0,100]", "");
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
    c->now = now;
    for (unsigned u = 0; u < c->nupd; u++) {
        int s = c->upd[u];
        c->node[s].updated = false;
        posts += relay_from(c, s, now, out);
        kelp_ncomms_node *nd = &c->node[s];
        if (c->share_interval >= 0 &&
            (nd->last_share < 0 || (now - nd->last_share) / c->cfg.warp >= c->share_interval)) {
            nd->last_share = now;
            out->publish(out->ctx, "NODE_REPORT_UNC", true, nd->report, 0);
        }
    }
    c->nupd = 0;
    for (unsigned q = 0; q < c->nfull_req; q++) {
        int d = c->full_req[q];
        if (!has_report(c, d)) continue;
        for (unsigned s = 0; s < c->nnodes; s++)
            if ((int)s != d && has_report(c, (int)s)) posts += relay_pair(c, (int)s, d, now, true, out);
    }
    c->nfull_req = 0;
    unsigned long before = c->msgs_sent + c->acks_sent;
    for (unsigned i = 0; i < c->nmsg; i++) {
        if (c->msg[i].is_ack) route_ack(c, &c->msg[i], now, out);
        else route_msg(c, &c->msg[i], now, out);
    }
    c->nmsg = 0;
    return posts + (c->msgs_sent + c->acks_sent - before);
}

/* ------------------------------------------------------------------ terminal report */

typedef struct rbuf {
    char *b;
    size_t cap, n;
    bool full;
} rbuf;

static void put(rbuf *r, const char *s)
{
    if (field_put_str(r->b, r->cap, &r->n, s) < 0) r->full = true;
}

static void put_count(rbuf *r, const char *indent, const char *label, unsigned long v)
{
    char line[160];
    kelp_snprintf(line, sizeof line, "%s%s: %lu\n", indent, label, v);
    put(r, line);
}

/* names in order (shell sort; no allocation) */
static void sort_names(const kelp_field_ncomms *c, uint16_t *idx, unsigned n)
{
    for (unsigned gap = n / 2; gap > 0; gap /= 2)
        for (unsigned i = gap; i < n; i++) {
            uint16_t t = idx[i];
            unsigned j = i;
            for (; j >= gap && strcmp(c->node[idx[j - gap]].name, c->node[t].name) > 0; j -= gap) idx[j] = idx[j - gap];
            idx[j] = t;
        }
}

static void per_vehicle(rbuf *r, const kelp_field_ncomms *c, const uint16_t *idx, unsigned n, int what, kelp_time now)
{
    for (unsigned k = 0; k < n; k++) {
        const kelp_ncomms_node *nd = &c->node[idx[k]];
        unsigned long v = what == 0 ? nd->rpts_rcvd : what == 1 ? nd->rpts_sent : what == 2 ? nd->msgs_rcvd : nd->msgs_sent;
        if (v == 0) continue;
        char line[160];
        kelp_snprintf(line, sizeof line, "            %s: %lu", nd->name, v);
        put(r, line);
        if (what == 0 || what == 2) {
            double t = what == 0 ? c->hot[idx[k]].t_recv : nd->last_msg_rcvd;
            char e[48];
            size_t en = 0;
            if (field_put_fixed(e, sizeof e, &en, now - t, 1, false) < 0) kelp_snprintf(e, sizeof e, "?");
            kelp_snprintf(line, sizeof line, "      (%s)", e);
            put(r, line);
        }
        put(r, "\n");
    }
}

int kelp_field_ncomms_report(kelp_field_ncomms *c, kelp_time now, char *buf, size_t cap)
{
    rbuf r = { buf, cap, 0, false };
    if (cap == 0) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    uint16_t *idx = c->ws_idx;
    const unsigned nn = c->nnodes;
    for (unsigned i = 0; i < nn; i++) idx[i] = (uint16_t)i;
    sort_names(c, idx, nn);
    put(&r, "****\nuFldNodeCommsSummary:\n****\n\nNode Report Summary\n=====\n");
    put_count(&r, "    ", "Total Received", c->rpts_rcvd);
    per_vehicle(&r, c, idx, nn, 0, now);
    put(&r, "-----\n");
    put_count(&r, "    ", "Total Sent", c->rpts_sent);
    per_vehicle(&r, c, idx, nn, 1, now);
    if (c->rpts_dropped || c->rpts_held || c->rpts_bad || c->rpts_full) {
        put_count(&r, "    ", "Dropped (drop_percentage)", c->rpts_dropped);
        put_count(&r, "    ", "Held (min_rpt_interval)", c->rpts_held);
        put_count(&r, "    ", "Malformed", c->rpts_bad);
        put_count(&r, "    ", "No room (vehicles)", c->rpts_full);
    }
    put(&r, "\n\nNode Message Summary\n=====\n");
    put_count(&r, "    ", "Total Msgs Received", c->msgs_rcvd);
    per_vehicle(&r, c, idx, nn, 2, now);
    put(&r, "-----\n");
    put_count(&r, "          ", "Total Sent", c->msgs_sent);
    per_vehicle(&r, c, idx, nn, 3, now);
    put(&r, "  -----\n");
    unsigned long total = 0;
    for (int i = 0; i < KELP_NCOMMS_BLK_N; i++) total += c->blocked[i];
    put_count(&r, "      ", "Total Blocked Msgs", total);
    static const char *const reason[KELP_NCOMMS_BLK_N] = { "Invalid",      "Stale Receiver", "Too Recent",
                                                           "Msg Too Long", "Range Too Far",  "Dropped",
                                                           "Group Mismatch" };
    for (int i = 0; i < KELP_NCOMMS_BLK_N; i++)
        if (i < KELP_NCOMMS_BLK_DROPPED || c->blocked[i]) put_count(&r, "          ", reason[i], c->blocked[i]);
    if (c->acks_rcvd) {
        put_count(&r, "      ", "Ack Msgs Received", c->acks_rcvd);
        put_count(&r, "      ", "Ack Msgs Sent", c->acks_sent);
    }
    put(&r, "  -----\n      Last Msgs:\n");
    for (unsigned k = 0; k < c->nlast; k++) {
        unsigned i = (c->last_head + KELP_NCOMMS_LAST_MSGS - c->nlast + k) % KELP_NCOMMS_LAST_MSGS;
        put(&r, "  ");
        put(&r, c->last_msgs[i]);
        put(&r, "\n");
    }
    return r.full ? KELP_ERR_NOSPACE : KELP_OK;
}
