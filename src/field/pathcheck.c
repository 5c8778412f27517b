/* uFldPathCheck's logic: odometry and speed from node reports (include/kelp/pathcheck.h). */
#include <math.h>
#include <string.h>
#include <kelp/pathcheck.h>
#include <kelp/kv.h>
#include <kelp/util.h>
#include "field_int.h"

void kelp_field_upc_cfg_default(kelp_field_upc_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->history = KELP_UPC_DEFAULT_HISTORY;
}

int kelp_field_upc_config(kelp_field_upc_cfg *cfg, const char *key, const char *val, kelp_diag *d)
{
    size_t kl = strlen(key);
    if (!kelp_strieq_n(key, kl, "HISTORY") && !kelp_strieq_n(key, kl, "HISTORY_LENGTH")) return 0;
    size_t vl = strlen(val);
    /* the seed's own example writes "HISTORY = 10 (Default)": read the leading number */
    size_t e = 0;
    while (e < vl && val[e] != ' ' && val[e] != '\t' && val[e] != '(' && val[e] != ';') e++;
    long h;
    if (kelp_parse_long(val, e, &h) < 0 || h < 2 || h > KELP_UPC_MAX_HISTORY) {
        return kelp_fail(d, KELP_ERR_ARG, "HISTORY: an integer from 2 to KELP_UPC_MAX_HISTORY");
    }
    cfg->history = (unsigned)h;
    return 1;
}

int kelp_field_upc_init(kelp_field_upc *p, const kelp_field_upc_cfg *cfg)
{
    memset(p, 0, sizeof *p);
    if (cfg->history < 2 || cfg->history > KELP_UPC_MAX_HISTORY) return KELP_ERR_ARG;
    p->cfg = *cfg;
    return KELP_OK;
}

const char *kelp_field_upc_subscription(unsigned i)
{
    static const char *const subs[] = { "NODE_REPORT", "NODE_REPORT_LOCAL", "UPC_TRIP_RESET", "UPC_ODOMETRY_RESET" };
    return i < sizeof subs / sizeof subs[0] ? subs[i] : NULL;
}

int kelp_field_upc_find(const kelp_field_upc *p, const char *name)
{
    size_t nl = strlen(name);
    for (unsigned i = 0; i < p->nnodes; i++)
        if (kelp_strieq_n(name, nl, p->node[i].name)) return (int)i;
    return -1;
}

static void warn(const kelp_field_sink *out, const char *msg)
{
    if (out && out->warn) out->warn(out->ctx, msg);
}

double kelp_field_upc_speed(const kelp_upc_node *n)
{
    if (n->n < 2) return 0;
    unsigned cap = KELP_UPC_MAX_HISTORY;
    const kelp_upc_point *first = &n->hist[n->head];
    const kelp_upc_point *last = &n->hist[(n->head + n->n - 1) % cap];
    double dist = 0;
    for (unsigned i = 1; i < n->n; i++) dist += n->hist[(n->head + i) % cap].d;
    double dt = last->t - first->t;
    return dt > 0 ? dist / dt : 0;
}

static int node_report(kelp_field_upc *p, const char *s, kelp_time now, const kelp_field_sink *out)
{
    kelp_nodereport r;
    if (kelp_nodereport_parse(s, strlen(s), &r, NULL) < 0 || !(r.fields & KELP_NR_X) || !(r.fields & KELP_NR_Y)) {
        p->bad++;
        warn(out, "uFldPathCheck: invalid NODE_REPORT (NAME, X and Y required)");
        return KELP_ERR_PARSE;
    }
    int i = kelp_field_upc_find(p, r.name);
    if (i < 0) {
        if (p->nnodes >= KELP_UPC_MAX_NODES) {
            p->full++;
            warn(out, "uFldPathCheck: too many vehicles (KELP_UPC_MAX_NODES)");
            return KELP_ERR_NOSPACE;
        }
        i = (int)p->nnodes++;
        memcpy(p->node[i].name, r.name, sizeof r.name);
    }
    kelp_upc_node *n = &p->node[i];
    double t = (r.fields & KELP_NR_TIME) ? r.time : now;
    n->last_recv = now;
    unsigned cap = KELP_UPC_MAX_HISTORY;
    kelp_upc_point pt = { r.x, r.y, t, 0 };
    if (n->n > 0) {
        const kelp_upc_point *prev = &n->hist[(n->head + n->n - 1) % cap];
        /* the time step rule: a report KELP_TIME_STEP_MAX behind the previous one (the
         * vehicle's clock stepped back) or ahead of it (stepped forward, or a long silence)
         * starts the speed history again, so reports are not ignored for the length of the step
         * and no speed is averaged over it; the distance still counts */
        bool step = t < prev->t - KELP_TIME_STEP_MAX || t > prev->t + KELP_TIME_STEP_MAX;
        if (!step && !(t > prev->t)) { /* a repeat or out of order: not a new position */
            n->ignored++;
            return 1;
        }
        pt.d = hypot(r.x - prev->x, r.y - prev->y);
        if (step) n->n = 0, n->head = 0;
    }
    p->good++;
    n->reports++;
    n->total += pt.d;
    n->trip += pt.d;
    if (n->n == p->cfg.history) { /* drop the oldest */
        n->head = (n->head + 1) % cap;
        n->n--;
    }
    n->hist[(n->head + n->n) % cap] = pt;
    n->n++;
    n->updated = true;
    return 1;
}

int kelp_field_upc_mail(kelp_field_upc *p, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out)
{
    if (kelp_strieq(var, "NODE_REPORT") || kelp_strieq(var, "NODE_REPORT_LOCAL")) {
        if (!is_string || !sval || !kelp_time_ok(now)) return KELP_ERR_ARG;
        return node_report(p, sval, now, out);
    }
    if (kelp_strieq(var, "UPC_TRIP_RESET") || kelp_strieq(var, "UPC_ODOMETRY_RESET")) {
        if (!is_string || !sval) return KELP_ERR_ARG;
        /* the vehicle's name, or a "vname=alpha" pair */
        char name[KELP_NODEREPORT_MAX_FIELD];
        const char *s = sval;
        if (strchr(sval, '=')) {
            if (kelp_kv_get(sval, ',', "vname", name, sizeof name) != 1) name[0] = 0;
            s = name;
        }
        size_t a = 0, b = strlen(s);
        while (a < b && (s[a] == ' ' || s[a] == '\t' || s[a] == '"')) a++;
        while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t' || s[b - 1] == '"')) b--;
        for (unsigned i = 0; i < p->nnodes; i++) {
            if (kelp_strieq_n(s + a, b - a, p->node[i].name)) {
                p->node[i].trip = 0;
                p->node[i].updated = true;
                p->resets++;
                return 1;
            }
        }
        p->bad_resets++;
        warn(out, "uFldPathCheck: trip reset for an unknown vehicle");
        return KELP_ERR_NOTFOUND;
    }
    return 0;
}

unsigned kelp_field_upc_iterate(kelp_field_upc *p, kelp_time now, const kelp_field_sink *out)
{
    (void)now;
    unsigned posts = 0;
    for (unsigned i = 0; i < p->nnodes; i++) {
        kelp_upc_node *n = &p->node[i];
        if (!n->updated) continue;
        n->updated = false;
        char buf[160];
        size_t k = 0;
        field_putf(buf, sizeof buf, &k, "vname=%s,total_dist=", n->name);
        int rc = field_put_fixed(buf, sizeof buf, &k, n->total, 1, false);
        if (rc == 0) rc = field_put_str(buf, sizeof buf, &k, ",trip_dist=");
        if (rc == 0) rc = field_put_fixed(buf, sizeof buf, &k, n->trip, 1, false);
        if (rc == 0 && out) {
            out->publish(out->ctx, "UPC_ODOMETRY_REPORT", true, buf, 0);
            posts++;
        }
        k = 0;
        field_putf(buf, sizeof buf, &k, "vname=%s,avg_speed=", n->name);
        rc = field_put_fixed(buf, sizeof buf, &k, kelp_field_upc_speed(n), 2, false);
        if (rc == 0 && out) {
            out->publish(out->ctx, "UPC_SPEED_REPORT", true, buf, 0);
            posts++;
        }
    }
    return posts;
}

int kelp_field_upc_report(const kelp_field_upc *p, kelp_time now, char *buf, size_t cap)
{
    size_t k = 0;
    if (cap) buf[0] = 0;
    field_putf(buf, cap, &k, " Node Reports Recd (good): %lu\n Node Reports Recd (bad):  %lu\n", p->good, p->bad);
    field_putf(buf, cap, &k, " Trip resets: %lu (unknown vehicle: %lu)\n\n", p->resets, p->bad_resets);
    field_putf(buf, cap, &k, "Node          TripDist   Distance  ReportAge  AvgSpeed\n");
    field_putf(buf, cap, &k, "----------  ----------  ---------  ---------  --------\n");
    for (unsigned i = 0; i < p->nnodes; i++) {
        const kelp_upc_node *n = &p->node[i];
        field_putf(buf, cap, &k, "%-10s  %10.1f  %9.1f  %9.1f  %8.2f\n", n->name, n->trip, n->total, fmax(0.0, now - n->last_recv),
                   kelp_field_upc_speed(n));
    }
    return k + 1 >= cap ? KELP_ERR_NOSPACE : KELP_OK;
}
