/* uFldPathCheck's logic: odometry and speed from node reports (include/kelp/pathcheck.h). */
#include <math.h>
#include <string.h>
#include <kelp/pathcheck.h>
#include <kelp/kv.h>
#include <kelp/nodereport.h>
#include <kelp/util.h>
#include "field_int.h"

void kelp_pathcheck_cfg_default(kelp_pathcheck_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->history = KELP_UPC_DEFAULT_HISTORY;
}

int kelp_pathcheck_config(kelp_pathcheck_cfg *cfg, const char *key, const char *val, kelp_diag *d)
{
    /* 24.8 takes HISTORY_LENGTH only (an integer above 1); "history" and the rest are
     * unhandled lines */
    if (!kelp_util_strieq(key, "HISTORY_LENGTH")) return 0;
    long h;
    if (kelp_util_parse_long(val, strlen(val), &h) < 0 || h < 2 || h > KELP_UPC_MAX_HISTORY) {
        return kelp_fail(d, KELP_ERR_ARG, "HISTORY_LENGTH: an integer from 2 to KELP_UPC_MAX_HISTORY");
    }
    cfg->history = (unsigned)h;
    return 1;
}

int kelp_pathcheck_init(kelp_pathcheck *p, const kelp_pathcheck_cfg *cfg)
{
    memset(p, 0, sizeof *p);
    if (cfg->history < 2 || cfg->history > KELP_UPC_MAX_HISTORY) return KELP_ERR_ARG;
    p->cfg = *cfg;
    return KELP_OK;
}

const char *kelp_pathcheck_subscription(unsigned i)
{
    static const char *const subs[] = { "NODE_REPORT", "NODE_REPORT_LOCAL", "UPC_TRIP_RESET" };
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

int kelp_pathcheck_find(const kelp_pathcheck *p, const char *name)
{
    for (unsigned i = 0; i < p->nnodes; i++)
        if (strcmp(name, p->node[i].name) == 0) return (int)i;
    return -1;
}

/* "<what><text>" through the sink's warn, the text cut to the workspace */
static void warn2(kelp_pathcheck *p, const kelp_field_sink *out, const char *what, const char *text)
{
    if (!out || !out->warn) return;
    size_t k = 0;
    p->ws[0] = 0;
    (void)field_put_str(p->ws, sizeof p->ws, &k, what);
    size_t room = sizeof p->ws - 1 - k, tl = strlen(text);
    memcpy(p->ws + k, text, tl < room ? tl : room);
    p->ws[k + (tl < room ? tl : room)] = 0;
    out->warn(out->ctx, p->ws);
}

double kelp_pathcheck_speed(const kelp_upc_node *n)
{
    /* the mean of the per-leg speeds along the queue (24.8's computeAndPostSpeeds); a leg
     * whose time difference is not positive is left out (24.8 divides by it) */
    unsigned cap = KELP_UPC_MAX_HISTORY, legs = 0;
    double sum = 0;
    for (unsigned i = 1; i < n->n; i++) {
        const kelp_upc_point *a = &n->hist[(n->head + i - 1) % cap];
        const kelp_upc_point *b = &n->hist[(n->head + i) % cap];
        double dt = b->t - a->t;
        if (!(dt > 0)) continue;
        sum += hypot(b->x - a->x, b->y - a->y) / dt;
        legs++;
    }
    return legs ? sum / legs : 0;
}

/* NodeRecord::valid(): NAME, X, Y, SPD and HDG, or NAME, LAT, LON, SPD and HDG */
static bool record_valid(const kelp_nodereport *r)
{
    unsigned need = KELP_NR_NAME | KELP_NR_SPD | KELP_NR_HDG;
    if ((r->fields & need) != need || !r->name[0]) return false;
    return (r->fields & (KELP_NR_X | KELP_NR_Y)) == (KELP_NR_X | KELP_NR_Y) ||
           (r->fields & (KELP_NR_LAT | KELP_NR_LON)) == (KELP_NR_LAT | KELP_NR_LON);
}

static int node_report(kelp_pathcheck *p, const char *s, kelp_time now, const kelp_field_sink *out)
{
    kelp_nodereport r;
    if (kelp_nodereport_parse(s, strlen(s), &r, NULL) < 0 || !record_valid(&r)) {
        p->bad++;
        warn2(p, out, "Invalid NODE_REPORT: ", s);
        return KELP_ERR_PARSE;
    }
    int i = kelp_pathcheck_find(p, r.name);
    if (i < 0) {
        if (p->nnodes >= KELP_UPC_MAX_NODES) {
            p->full++;
            warn2(p, out, "uFldPathCheck: too many vehicles (KELP_UPC_MAX_NODES): ", r.name);
            return KELP_ERR_NOSPACE;
        }
        unsigned at = 0; /* 24.8 keeps its vehicles in a std::map: strcmp order */
        while (at < p->nnodes && strcmp(p->node[at].name, r.name) < 0) at++;
        memmove(&p->node[at + 1], &p->node[at], (p->nnodes - at) * sizeof p->node[0]);
        memset(&p->node[at], 0, sizeof p->node[at]);
        memcpy(p->node[at].name, r.name, sizeof r.name);
        p->nnodes++;
        i = (int)at;
    }
    p->good++;
    kelp_upc_node *n = &p->node[i];
    n->last_recv = now;
    n->reports++;
    unsigned cap = KELP_UPC_MAX_HISTORY;
    double x = (r.fields & KELP_NR_X) ? r.x : 0, y = (r.fields & KELP_NR_Y) ? r.y : 0;
    if (n->n > 1) { /* 24.8: the odometer runs once two records are held */
        const kelp_upc_point *prev = &n->hist[(n->head + n->n - 1) % cap];
        double d = hypot(prev->x - x, prev->y - y);
        n->total += d;
        n->trip += d;
        n->has_dist = true;
        n->changed = true;
    }
    n->hist[(n->head + n->n) % cap] = (kelp_upc_point){ x, y, (r.fields & KELP_NR_TIME) ? r.time : now };
    n->n++;
    if (n->n > p->cfg.history) { /* drop the oldest */
        n->head = (n->head + 1) % cap;
        n->n--;
    }
    return 1;
}

int kelp_pathcheck_mail(kelp_pathcheck *p, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out)
{
    if (strcmp(var, "NODE_REPORT") == 0 || strcmp(var, "NODE_REPORT_LOCAL") == 0) {
        if (!is_string || !sval || !kelp_util_time_ok(now)) return KELP_ERR_ARG;
        return node_report(p, sval, now, out);
    }
    if (strcmp(var, "UPC_TRIP_RESET") == 0) {
        if (!is_string || !sval) return KELP_ERR_ARG;
        /* 24.8: the value is the name, exactly; only a vehicle with odometry has a trip */
        int i = kelp_pathcheck_find(p, sval);
        if (i >= 0 && p->node[i].has_dist) {
            p->node[i].trip = 0;
            p->resets++;
            return 1;
        }
        p->bad_resets++;
        warn2(p, out, "Invalid TRIP_RESET: ", sval);
        return KELP_ERR_NOTFOUND;
    }
    return 0;
}

unsigned kelp_pathcheck_iterate(kelp_pathcheck *p, kelp_time now, const kelp_field_sink *out)
{
    (void)now;
    unsigned posts = 0;
    char buf[160];
    for (unsigned i = 0; i < p->nnodes; i++) {
        const kelp_upc_node *n = &p->node[i];
        if (n->n < 2) continue;
        size_t k = 0;
        /* 24.8's doubleToString is printf's "%.2f" (an exact tie rounds to even) */
        field_putf(buf, sizeof buf, &k, "vname=%s,avg_spd=%.2f", n->name, kelp_pathcheck_speed(n));
        if (k + 1 < sizeof buf && out) {
            out->publish(out->ctx, "UPC_SPEED_REPORT", true, buf, 0);
            posts++;
        }
    }
    for (unsigned i = 0; i < p->nnodes; i++) {
        kelp_upc_node *n = &p->node[i];
        if (!n->changed) continue;
        n->changed = false;
        size_t k = 0;
        field_putf(buf, sizeof buf, &k, "vname=%s,total_dist=%.1f,trip_dist=%.1f", n->name, n->total, n->trip);
        if (k + 1 < sizeof buf && out) {
            out->publish(out->ctx, "UPC_ODOMETRY_REPORT", true, buf, 0);
            posts++;
        }
    }
    return posts;
}

typedef struct upc_table {
    const kelp_pathcheck *p;
    kelp_time now;
} upc_table;

/* the index of the row-th vehicle with odometry (24.8's table lists those) */
static unsigned upc_row(const kelp_pathcheck *p, unsigned row)
{
    unsigned i = 0;
    for (; i < p->nnodes; i++)
        if (p->node[i].has_dist && row-- == 0) break;
    return i;
}

static const char *upc_cell(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap)
{
    static const char *const hdr[] = { "Node", "TripDist", "Distance", "ReportAge", "Speed", "AvgSpeed" };
    const upc_table *t = ctx;
    if (row == 0) return hdr[col];
    const kelp_upc_node *n = &t->p->node[upc_row(t->p, row - 1)];
    double v;
    switch (col) {
    case 0: return n->name;
    case 1: v = n->trip; break;
    case 2: v = n->total; break;
    case 3: v = t->now - n->last_recv; break;
    default: return "n/a"; /* 24.8 shows n/a for both speeds */
    }
    size_t k = 0;
    field_putf(tmp, cap, &k, "%.1f", v);
    return tmp;
}

int kelp_pathcheck_report(const kelp_pathcheck *p, kelp_time now, double warp, char *buf, size_t cap)
{
    size_t k = 0;
    bool full = false;
    if (!cap) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    char w[40];
    size_t wn = 0;
    if (field_put_fixed(w, sizeof w, &wn, warp, 6, true) < 0) w[0] = 0; /* ostream's 1, 2.5 */
    broker_put(buf, cap, &k, &full, " Node Reports Recd (good): %lu\n Node Reports Recd (bad):  %lu\n", p->good, p->bad);
    broker_put(buf, cap, &k, &full, " MOOS Time Warp:           %s\n\n", w);
    upc_table tab = { p, now };
    unsigned rows = 0;
    for (unsigned i = 0; i < p->nnodes; i++) rows += p->node[i].has_dist;
    field_actable(buf, cap, &k, &full, 6, rows + 1, 1, 3, 0, upc_cell, &tab);
    broker_put(buf, cap, &k, &full, "\n");
    return full ? KELP_ERR_NOSPACE : KELP_OK;
}
