/* What the beacon and contact range sensors share (include/kelp/beaconrange.h): per-vehicle
 * parameters, the noise models and their random draws, the vehicle table, and the report
 * and pulse strings (ufield.md 1.6, 1.9). */
#include <math.h>
#include <stdarg.h>
#include <string.h>
#include <kelp/beaconrange.h>
#include <kelp/kv.h>
#include <kelp/nodereport.h>
#include <kelp/util.h>
#include "field_int.h"
#include "rangesense_int.h"

void rs_copy(char *dst, size_t cap, const char *src, size_t n)
{
    if (!cap) return;
    if (n >= cap) n = cap - 1;
    memcpy(dst, src, n);
    dst[n] = 0;
}

static bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

int rs_value(const char *val, char *v, size_t cap, kelp_diag *d)
{
    while (*val && blank(*val)) val++;
    size_t n = strlen(val);
    if (n >= cap) {
        return kelp_fail(d, KELP_ERR_RANGE, "value too long");
    }
    memcpy(v, val, n + 1);
    while (n && (v[n - 1] == ';' || blank(v[n - 1]))) v[--n] = 0; /* "ping_wait = 30;" (A3) */
    return (int)n;
}

bool rs_trans(double push, double pull, double d)
{
    if (push < 0 || pull < 0) return true;
    return d <= push + pull;
}

/* ------------------------------------------------------------------ per-vehicle values */

double kelp_rangesense_vmap_get(const kelp_rangesense_vmap *m, const char *name)
{
    for (unsigned i = 0; i < m->n; i++)
        if (kelp_util_strieq(m->name[i], name)) return m->v[i];
    return m->dflt;
}

static int parse_dist(const char *s, size_t n, bool allow_nolimit, double *out)
{
    if (allow_nolimit && (kelp_util_strieq_n(s, n, "nolimit") || kelp_util_strieq_n(s, n, "unlimited"))) {
        *out = -1;
        return KELP_OK;
    }
    double d;
    if (kelp_util_parse_double(s, n, &d) < 0 || !isfinite(d)) return KELP_ERR_PARSE;
    *out = d;
    return KELP_OK;
}

int kelp_rangesense_vmap_set(kelp_rangesense_vmap *m, const char *val, bool allow_nolimit, kelp_diag *d)
{
    const char *eq = strchr(val, '=');
    const char *name = NULL;
    size_t nl = 0;
    const char *num = val;
    if (eq) {
        name = val;
        nl = (size_t)(eq - val);
        while (nl && blank(name[nl - 1])) nl--;
        while (nl && blank(*name)) name++, nl--;
        num = eq + 1;
    }
    while (*num && blank(*num)) num++;
    size_t vl = strlen(num);
    while (vl && blank(num[vl - 1])) vl--;
    double dv;
    if (parse_dist(num, vl, allow_nolimit, &dv) < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, allow_nolimit ? "must be [<vname>|default =] <number or nolimit>" : "must be [<vname>|default =] <number>");
    }
    if (!allow_nolimit && dv < 0) dv = 0; /* a negative ping wait: no wait */
    if (!name || kelp_util_strieq_n(name, nl, "default")) {
        m->dflt = dv;
        return 1;
    }
    if (nl == 0 || nl >= KELP_RSENSE_NAME || memchr(name, ',', nl)) {
        return kelp_fail(d, KELP_ERR_PARSE, "bad vehicle name");
    }
    for (unsigned i = 0; i < m->n; i++)
        if (kelp_util_strieq_n(name, nl, m->name[i])) {
            m->v[i] = dv;
            return 1;
        }
    if (m->n >= KELP_RSENSE_MAX_VCFG) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many vehicles named for this parameter");
    }
    rs_copy(m->name[m->n], KELP_RSENSE_NAME, name, nl);
    m->v[m->n++] = dv;
    return 1;
}

/* ------------------------------------------------------------------ common parameters */

void kelp_rangesense_common_default(kelp_rangesense_common *c)
{
    memset(c, 0, sizeof *c);
    c->ping_wait.dflt = 30; /* A63 */
    c->report_vars = KELP_RSENSE_SHORT;
    c->seed = 1;
}

bool kelp_rangesense_common_as_248(kelp_rangesense_common *c)
{
    if (!c->glibc || c->noise.alg != KELP_RSENSE_NOISE_GAUSSIAN) return false;
    c->noise.alg = c->alg248;
    return true;
}

/* one pct= (clipped to [0,1] as 24.8 does) or sigma= (at least 0) value into t */
static int noise_value(kelp_rangesense_noise *t, bool pct, const char *v, size_t vl, kelp_diag *d)
{
    double dv;
    if (kelp_util_parse_double(v, vl, &dv) < 0 || !isfinite(dv)) return kelp_fail(d, KELP_ERR_PARSE, "bad number");
    if (pct) t->pct = dv < 0 ? 0 : dv > 1 ? 1 : dv;
    else t->sigma = dv < 0 ? 0 : dv;
    return 1;
}

/* the algorithm word of an RN_ALGORITHM value (before the first ',', blanks trimmed) is exactly
 * "uniform": the only one 24.8 takes (case-sensitive, as its comparison) */
static bool word_is_uniform(const char *v, size_t n)
{
    const char *comma = memchr(v, ',', n);
    size_t e = comma ? (size_t)(comma - v) : n, b = 0;
    while (b < e && (v[b] == ' ' || v[b] == '\t')) b++;
    while (e > b && (v[e - 1] == ' ' || v[e - 1] == '\t')) e--;
    static const char word[] = "uniform";
    return e - b == sizeof word - 1 && memcmp(v + b, word, sizeof word - 1) == 0;
}

int kelp_rangesense_common_config(kelp_rangesense_common *c, const char *key, const char *v, kelp_diag *d)
{
    size_t kl = strlen(key), n = strlen(v);
    if (kelp_util_strieq_n(key, kl, "PING_WAIT")) return kelp_rangesense_vmap_set(&c->ping_wait, v, false, d);
    if (kelp_util_strieq_n(key, kl, "REPORT_VARS")) {
        if (kelp_util_strieq_n(v, n, "short")) c->report_vars = KELP_RSENSE_SHORT;
        else if (kelp_util_strieq_n(v, n, "long")) c->report_vars = KELP_RSENSE_LONG;
        else if (kelp_util_strieq_n(v, n, "both")) c->report_vars = KELP_RSENSE_BOTH;
        else return kelp_fail(d, KELP_ERR_PARSE, "must be short, long or both");
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "RN_ALGORITHM")) {
        if (c->glibc && !word_is_uniform(v, n)) return 0; /* 24.8's rn_algorithm: an unhandled line */
        double pct = c->noise.pct;
        int rc = kelp_rangesense_noise_set(&c->noise, v, d);
        if (rc == 1 && c->noise.alg == KELP_RSENSE_NOISE_UNIFORM) c->alg248 = KELP_RSENSE_NOISE_UNIFORM;
        if (rc == 1 && c->glibc && strstr(v, "pct=")) { /* 24.8 reads the block last line first */
            if (c->pct248) c->noise.pct = pct;
            c->pct248 = true;
        }
        return rc;
    }
    if (kelp_util_strieq_n(key, kl, "RN_UNIFORM_PCT") || kelp_util_strieq_n(key, kl, "RN_GAUSSIAN_SIGMA")) {
        /* 24.8 sets the value only: the noise is on only with RN_ALGORITHM */
        bool uni = kelp_util_strieq_n(key, kl, "RN_UNIFORM_PCT");
        kelp_rangesense_noise t = c->noise;
        int rc = noise_value(&t, uni, v, n, d);
        if (rc < 0) return rc;
        if (uni && c->glibc) { /* 24.8 reads the block last line first: the first fraction stays */
            if (c->pct248) return 1;
            c->pct248 = true;
        }
        c->noise = t;
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "GROUND_TRUTH") || kelp_util_strieq_n(key, kl, "VERBOSE")) {
        bool f;
        if (kelp_util_parse_bool(v, n, &f) < 0) return kelp_fail(d, KELP_ERR_PARSE, "must be true or false");
        if (kelp_util_strieq_n(key, kl, "VERBOSE")) c->verbose = f;
        else c->ground_truth = f;
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "RAND_MODE")) {
        if (kelp_util_strieq_n(v, n, "glibc")) c->glibc = true;
        else if (kelp_util_strieq_n(v, n, "kelp")) c->glibc = false;
        else return kelp_fail(d, KELP_ERR_PARSE, "must be kelp or glibc");
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "SEED_RANDOM")) {
        long long s;
        if (kelp_util_parse_llong(v, n, &s) < 0) return kelp_fail(d, KELP_ERR_PARSE, "must be an integer");
        c->seed = (uint64_t)s;
        return 1;
    }
    return 0;
}

/* ------------------------------------------------------------------ noise */

int kelp_rangesense_noise_set(kelp_rangesense_noise *n, const char *val, kelp_diag *d)
{
    const char *c = strchr(val, ',');
    size_t al = c ? (size_t)(c - val) : strlen(val);
    while (al && blank(val[al - 1])) al--;
    while (al && blank(*val)) val++, al--;
    kelp_rangesense_noise t = *n;
    if (kelp_util_strieq_n(val, al, "uniform")) {
        t.alg = KELP_RSENSE_NOISE_UNIFORM;
    } else if (kelp_util_strieq_n(val, al, "gaussian") || kelp_util_strieq_n(val, al, "gauss")) {
        t.alg = KELP_RSENSE_NOISE_GAUSSIAN;
    } else if (kelp_util_strieq_n(val, al, "none") && !c) {
        n->alg = KELP_RSENSE_NOISE_NONE;
        return 1;
    } else {
        return kelp_fail(d, KELP_ERR_PARSE, "algorithm must be uniform (pct=) or gaussian (sigma=)");
    }
    if (c) {
        size_t pos = 0;
        const char *k, *v;
        size_t kl, vl;
        int rc;
        while ((rc = kelp_kv_next(c + 1, ',', &pos, &k, &kl, &v, &vl)) == 1) {
            bool pct = kelp_util_strieq_n(k, kl, "pct");
            if (!pct && !kelp_util_strieq_n(k, kl, "sigma")) {
                double dv;
                if (kelp_util_parse_double(v, vl, &dv) < 0 || !isfinite(dv)) return kelp_fail(d, KELP_ERR_PARSE, "bad number");
                return kelp_fail(d, KELP_ERR_PARSE, "unknown noise parameter (pct or sigma)");
            }
            int vr = noise_value(&t, pct, v, vl, d);
            if (vr < 0) return vr;
        }
        if (rc < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "expected key=value after the algorithm");
        }
    }
    *n = t;
    return 1;
}

void kelp_rangesense_nodes_back(kelp_rangesense_node *node, unsigned n, double back)
{
    for (unsigned i = 0; i < n; i++) node[i].clock -= back;
}

void kelp_rangesense_rand_init(kelp_rangesense_rand *r, bool glibc, uint64_t seed)
{
    memset(r, 0, sizeof *r);
    r->glibc = glibc;
    kelp_rng_seed(&r->rng, seed);
    kelp_rng_glibc_seed(&r->g, 1); /* a program that never calls srand */
}

static int32_t grand(kelp_rangesense_rand *r)
{
    r->draws++;
    return kelp_rng_glibc_next(&r->g);
}

static double kuni(kelp_rangesense_rand *r)
{
    r->draws++;
    return kelp_rng_uniform(&r->rng);
}

/* MOOSWhiteNoise: Marsaglia's polar method on rand()/RAND_MAX, the second deviate kept for
 * the next call */
static double white_noise(kelp_rangesense_rand *r, double sigma)
{
    if (r->have_gset) {
        r->have_gset = false;
        return r->gset * sigma;
    }
    double v1, v2, s;
    do {
        v1 = 2.0 * ((double)grand(r) / KELP_GLIBC_RAND_MAX) - 1.0;
        v2 = 2.0 * ((double)grand(r) / KELP_GLIBC_RAND_MAX) - 1.0;
        s = v1 * v1 + v2 * v2;
    } while (s > 1.0 || s == 0.0);
    double fac = sqrt(-2.0 * log(s) / s);
    r->gset = v1 * fac;
    r->have_gset = true;
    return v2 * fac * sigma;
}

double kelp_rangesense_noisy(kelp_rangesense_rand *r, const kelp_rangesense_noise *n, double range)
{
    switch (n->alg) {
    case KELP_RSENSE_NOISE_UNIFORM: {
        double u = r->glibc ? (double)(grand(r) % 10000) / 5000.0 - 1.0 : 2.0 * kuni(r) - 1.0;
        return range + u * n->pct * range;
    }
    case KELP_RSENSE_NOISE_GAUSSIAN:
        if (r->glibc) return range + white_noise(r, n->sigma);
        r->draws += 2;
        return range + kelp_rng_gauss(&r->rng, 0.0, n->sigma);
    case KELP_RSENSE_NOISE_NONE:
    default:
        return range;
    }
}

double kelp_rangesense_interval(kelp_rangesense_rand *r, double lo, double hi)
{
    double u = r->glibc ? (double)(grand(r) % 1000) / 1000.0 : kuni(r);
    return lo + u * (hi - lo);
}

double kelp_rangesense_unit(kelp_rangesense_rand *r)
{
    return r->glibc ? (double)(grand(r) % 10000) / 10000.0 : kuni(r);
}

/* ------------------------------------------------------------------ vehicles */

/* 24.8's ledger keys vehicles by their name as reported: "INDIGO" is not "indigo" */
int rs_find(const kelp_rangesense_node *nodes, unsigned n, const char *name)
{
    for (unsigned i = 0; i < n; i++)
        if (strcmp(nodes[i].name, name) == 0) return (int)i;
    return -1;
}

bool rs_in_time(const kelp_rangesense_node *v, double now, double wait)
{
    return !v->pinged || now - v->clock >= wait * (1 - KELP_RSENSE_LATE);
}

/* The vehicle types 24.8's ledger knows (MBUtils' isKnownVehicleType, compared lower-case). */
static const char *const KNOWN_TYPES[] = { "auv",   "kayak", "uuv",    "usv",   "glider",  "asv",  "ship",      "mokai",
                                           "longship", "buoy", "heron", "swimmer", "cray", "bcray", "crayx", "wamv",
                                           "bcrayx", "smr",   "smrx",   "skyw",  "skywalker", "quad", "quadcopter" };

/* 24.8's ledger fixes a report's type before anyone reads it: "uuv" is "auv" and a type it does
 * not know (an absent one too) is "ship"; a known type keeps its spelling */
static const char *ledger_type(const kelp_nodereport *r)
{
    const char *t = (r->fields & KELP_NR_TYPE) ? r->type : "";
    if (strcmp(t, "uuv") == 0) return "auv";
    for (size_t k = 0; k < sizeof KNOWN_TYPES / sizeof KNOWN_TYPES[0]; k++)
        if (kelp_util_strieq(t, KNOWN_TYPES[k])) return t;
    return "ship";
}

int rs_node_report(kelp_rangesense_node *nodes, unsigned *n, const char *s, const kelp_geo *geo, bool have_geo,
                   const char *ignore_group, double start, int *idx, bool *first, kelp_diag *d)
{
    kelp_nodereport r;
    *first = false;
    int rc = kelp_nodereport_parse(s, strlen(s), &r, d);
    if (rc < 0) return rc;
    if (!(r.fields & KELP_NR_X) || !(r.fields & KELP_NR_Y)) {
        if (!have_geo || kelp_nodereport_complete(&r, geo) < 0 || !(r.fields & KELP_NR_X)) {
            return kelp_fail(d, KELP_ERR_PARSE, "no X,Y (and no datum for LAT,LON)");
        }
    }
    const char *type = ledger_type(&r);
    if ((strcmp(type, "auv") == 0 || strcmp(type, "glider") == 0) && !(r.fields & KELP_NR_DEPTH))
        return kelp_fail(d, KELP_ERR_PARSE, "underwater vehicle type with no depth reported"); /* 24.8's words */
    int i = rs_find(nodes, *n, r.name);
    if (ignore_group && *ignore_group && (r.fields & KELP_NR_GROUP) && kelp_util_strieq(r.group, ignore_group)) {
        if (i >= 0) { /* 24.8 ignore_group: the vehicle is forgotten */
            memmove(&nodes[i], &nodes[i + 1], (*n - (unsigned)i - 1) * sizeof nodes[0]);
            (*n)--;
        }
        return 0;
    }
    if (i < 0) {
        if (*n >= KELP_RSENSE_MAX_NODES) {
            return kelp_fail(d, KELP_ERR_NOSPACE, "too many vehicles");
        }
        unsigned at = 0;
        while (at < *n && strcmp(nodes[at].name, r.name) < 0) at++;
        memmove(&nodes[at + 1], &nodes[at], (*n - at) * sizeof nodes[0]);
        memset(&nodes[at], 0, sizeof nodes[at]);
        rs_copy(nodes[at].name, sizeof nodes[at].name, r.name, strlen(r.name));
        nodes[at].clock = start; /* unused until pinged: 24.8's clock starts at 0 */
        (*n)++;
        i = (int)at;
        *first = true;
    }
    kelp_rangesense_node *v = &nodes[i];
    v->x = r.x;
    v->y = r.y;
    if (r.fields & KELP_NR_HDG) v->hdg = r.hdg;
    rs_copy(v->type, sizeof v->type, type, strlen(type));
    v->reports++;
    *idx = i;
    return 1;
}

int rs_request_name(const char *s, char *name, size_t cap)
{
    int rc = kelp_kv_get(s, ',', "name", name, cap); /* 24.8 reads name= only (vname= is no name) */
    if (rc <= 0 || !*name) return KELP_ERR_PARSE;
    return KELP_OK;
}

/* ------------------------------------------------------------------ posts */

void rs_upper(char *s)
{
    for (; *s; s++)
        if (*s >= 'a' && *s <= 'z') *s = (char)(*s - 'a' + 'A');
}

void rs_lower(char *s)
{
    for (; *s; s++)
        if (*s >= 'A' && *s <= 'Z') *s = (char)(*s - 'A' + 'a');
}

#define RS_REPORT_BODY 256 /* bytes of a report body, terminator included */

/* rs_post_report's posts; KELP_ERR_NOSPACE when the report does not fit (the caller warns:
 * its message buffer is not stacked on this one) */
KELP_NOINLINE static int post_report(const kelp_field_sink *out, const char *pfx, bool gt, kelp_rangesense_vars vars,
                                     const char *vname, double range, const char *key, const char *id,
                                     const double *xy, kelp_time now, char *ws)
{
    /* one buffer, "vname=<vname>," then the body: the short form posts it all, the long form
     * the body alone (no printf on this path: it runs under every mail); both in the caller's
     * workspace, off the stack */
    char *full = ws, *var = ws + 320;
    size_t n = 0;
    int rc = field_put_str(full, (size_t)320, &n, "vname=");
    if (rc == 0) rc = field_put_str(full, (size_t)320, &n, vname);
    if (rc == 0) rc = field_put_str(full, (size_t)320, &n, ",");
    const size_t b = n;
    if (rc == 0) rc = field_put_str(full, (size_t)320, &n, "range=");
    if (rc == 0) rc = field_put_fixed(full, (size_t)320, &n, range, 4, true);
    if (rc == 0 && key) {
        rc = field_put_str(full, (size_t)320, &n, ",");
        if (rc == 0) rc = field_put_str(full, (size_t)320, &n, key);
        if (rc == 0) rc = field_put_str(full, (size_t)320, &n, "=");
        if (rc == 0) rc = field_put_str(full, (size_t)320, &n, id);
        if (rc == 0 && xy) {
            rc = field_put_str(full, (size_t)320, &n, ",x=");
            if (rc == 0) rc = field_put_fixed(full, (size_t)320, &n, xy[0], 2, true);
            if (rc == 0) rc = field_put_str(full, (size_t)320, &n, ",y=");
            if (rc == 0) rc = field_put_fixed(full, (size_t)320, &n, xy[1], 2, true);
        }
    }
    if (rc == 0) rc = field_put_str(full, (size_t)320, &n, ",time=");
    if (rc == 0) rc = field_put_fixed(full, (size_t)320, &n, now, 3, true);
    if (rc < 0 || n - b >= RS_REPORT_BODY) return KELP_ERR_NOSPACE; /* the body's limit as before */
    size_t v = 0;
    rc = field_put_str(var, (size_t)(KELP_MAX_NAME + KELP_RSENSE_NAME), &v, pfx);
    if (rc == 0) rc = field_put_str(var, (size_t)(KELP_MAX_NAME + KELP_RSENSE_NAME), &v, gt ? "_RANGE_REPORT_GT" : "_RANGE_REPORT");
    if (rc == 0 && vars != KELP_RSENSE_LONG) out->publish(out->ctx, var, true, full, 0);
    if (rc == 0) rc = field_put_str(var, (size_t)(KELP_MAX_NAME + KELP_RSENSE_NAME), &v, "_");
    if (rc == 0) rc = field_put_str(var, (size_t)(KELP_MAX_NAME + KELP_RSENSE_NAME), &v, vname);
    if (rc == 0 && vars != KELP_RSENSE_SHORT) {
        rs_upper(var);
        out->publish(out->ctx, var, true, full + b, 0);
    }
    return KELP_OK;
}

void rs_post_report(const kelp_field_sink *out, const char *pfx, bool gt, kelp_rangesense_vars vars, const char *vname,
                    double range, const char *key, const char *id, const double *xy, kelp_time now,
                    char ws[KELP_RSENSE_POST_WS])
{
    if (post_report(out, pfx, gt, vars, vname, range, key, id, xy, now, ws) < 0)
        rs_warn(out, "cannot format a range report for ", vname, RS_END);
}

void rs_pulse(const kelp_field_sink *out, double x, double y, double radius, double duration, const char *label,
              const char *color, kelp_time now, char ws[KELP_RSENSE_POST_WS])
{
    char *buf = ws; /* the caller's workspace, off the stack */
    size_t n = 0;
    int rc = field_put_str(buf, (size_t)320, &n, "x=");
    if (rc == 0) rc = field_put_fixed(buf, (size_t)320, &n, x, 2, true);
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, ",y=");
    if (rc == 0) rc = field_put_fixed(buf, (size_t)320, &n, y, 2, true);
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, ",radius=");
    if (rc == 0) rc = field_put_fixed(buf, (size_t)320, &n, radius, 2, true);
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, ",fill=0.9,label=");
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, label);
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, ",edge_color=");
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, color);
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, ",fill_color=");
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, color);
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, ",time=");
    if (rc == 0) rc = field_put_fixed(buf, (size_t)320, &n, now, 2, true);
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, ",duration=");
    if (rc == 0) rc = field_put_fixed(buf, (size_t)320, &n, duration, 2, true);
    if (rc == 0) rc = field_put_str(buf, (size_t)320, &n, ",edge_size=1");
    if (rc < 0) {
        rs_warn(out, "cannot format a range pulse ", label, RS_END);
        return;
    }
    out->publish(out->ctx, "VIEW_RANGE_PULSE", true, buf, 0);
}

static void join(char *buf, size_t cap, const char *a, va_list ap)
{
    size_t n = 0;
    buf[0] = 0;
    for (const char *p = a; p; p = va_arg(ap, const char *))
        if (field_put_str(buf, cap, &n, p) < 0) break;
}

void rs_log(kelp_rangesense_log_fn fn, void *ctx, const char *a, ...)
{
    if (!fn) return;
    char buf[256];
    va_list ap;
    va_start(ap, a);
    join(buf, sizeof buf, a, ap);
    va_end(ap);
    fn(ctx, buf);
}

void rs_warn(const kelp_field_sink *out, const char *a, ...)
{
    if (!out || !out->warn) return;
    char buf[256];
    va_list ap;
    va_start(ap, a);
    join(buf, sizeof buf, a, ap);
    va_end(ap);
    out->warn(out->ctx, buf);
}
