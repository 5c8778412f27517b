/* kelp IvP: ZAIC_PEAK, ZAIC_LEQ, ZAIC_HEQ (seed 004 ch. 7).
 *
 * ZAIC_PEAK values follow the seed's distance form (section 7.1.2, which MOOS-IvP's evalPoint
 * implements); pieces are cut from the sampled values with MOOS-IvP's rule (linear runs within
 * 0.001, a break where the slope changes sign) so piece counts and pointwise values agree with
 * MOOS-IvP. LEQ/HEQ are built as MOOS-IvP's ZAIC_LEQ/ZAIC_HEQ build them: the summit is kept
 * where it is given (outside the domain only earns a warning); the summit and the ramp's far
 * end snap to the nearest index, clipped to the domain; the ramp's slope comes from the whole
 * base width, and its line passes through the summit's utility at the summit index, or, when
 * the summit is at or below index 0 (LEQ) / its ramp start is (HEQ), through the other end's
 * utility at the other end, so a ramp cut by the domain keeps its slope. One difference: indices
 * are measured from the domain low (upstream divides the raw value by delta, which only agrees
 * when low is 0). */
#include <string.h>
#include <math.h>
#include "ivp_int.h"

#define ZAIC_TOLERANCE 0.001 /* MOOS-IvP ZAIC_PEAK::setPDMap default tolerance */

static int one_var(kelp_ivp_domain *out, const kelp_ivp_domain *dom, const char *var)
{
    kelp_ivp_domain_init(out);
    if (!dom || !var)
        return KELP_ERR_ARG;
    int ix = kelp_ivp_domain_index(dom, var);
    if (ix < 0)
        return KELP_ERR_NOTFOUND;
    return kelp_ivp_domain_add(out, var, dom->var[ix].low, dom->var[ix].high, dom->var[ix].points);
}

/* ------------------------------------------------------------------ ZAIC_PEAK */

int kelp_ivp_zaic_peak_init(kelp_ivp_zaic_peak *z, const kelp_ivp_domain *dom, const char *var)
{
    memset(z, 0, sizeof *z);
    z->ok = true;
    z->insist = true;
    z->wrap = false;
    z->ncomp = 1;
    z->comp[0].maxutil = 100;
    int rc = one_var(&z->dom, dom, var);
    if (rc) {
        z->ok = false;
        ivp_warn(z->warn, "ZAIC_PEAK: variable not in domain");
    }
    return rc;
}

int kelp_ivp_zaic_peak_add_component(kelp_ivp_zaic_peak *z)
{
    if (z->ncomp >= KELP_IVP_MAX_COMPONENTS) {
        z->ok = false;
        ivp_warn(z->warn, "addComponent: too many components");
        return KELP_ERR_NOSPACE;
    }
    kelp_ivp_zaic_comp *c = &z->comp[z->ncomp];
    memset(c, 0, sizeof *c);
    c->summitdelta = 50; /* seed 004 section 7.1.6 */
    c->maxutil = 100;
    return (int)z->ncomp++;
}

static int bad_index(kelp_ivp_zaic_peak *z, unsigned idx, const char *what)
{
    if (idx < z->ncomp)
        return 0;
    z->ok = false;
    ivp_warn(z->warn, what);
    return KELP_ERR_RANGE;
}

int kelp_ivp_zaic_peak_set_summit(kelp_ivp_zaic_peak *z, double v, unsigned idx)
{
    if (bad_index(z, idx, "setSummit: index out of range"))
        return KELP_ERR_RANGE;
    if (!isfinite(v)) {
        z->ok = false;
        ivp_warn(z->warn, "setSummit: value not finite");
        return KELP_ERR_RANGE;
    }
    if (z->dom.dim == 1 && (v < z->dom.var[0].low || v > z->dom.var[0].high))
        ivp_warn(z->warn, "setSummit: summit outside the domain");
    z->comp[idx].summit = v;
    return 0;
}

static int set_width(kelp_ivp_zaic_peak *z, double v, unsigned idx, double *dst, const char *name)
{
    if (bad_index(z, idx, name))
        return KELP_ERR_RANGE;
    if (!isfinite(v)) {
        z->ok = false;
        ivp_warn(z->warn, "width: value not finite");
        return KELP_ERR_RANGE;
    }
    if (v < 0) {
        v = 0;
        ivp_warn(z->warn, "width: value less than zero, clipped to 0");
    }
    *dst = v;
    return 0;
}

int kelp_ivp_zaic_peak_set_peakwidth(kelp_ivp_zaic_peak *z, double v, unsigned idx)
{
    return set_width(z, v, idx, idx < z->ncomp ? &z->comp[idx].peakwidth : NULL, "setPeakWidth: index out of range");
}

int kelp_ivp_zaic_peak_set_basewidth(kelp_ivp_zaic_peak *z, double v, unsigned idx)
{
    return set_width(z, v, idx, idx < z->ncomp ? &z->comp[idx].basewidth : NULL, "setBaseWidth: index out of range");
}

int kelp_ivp_zaic_peak_set_summitdelta(kelp_ivp_zaic_peak *z, double v, unsigned idx)
{
    if (bad_index(z, idx, "setSummitDelta: index out of range"))
        return KELP_ERR_RANGE;
    if (!(v >= 0) || !isfinite(v)) {
        z->ok = false; /* seed 004 section 7.1.3: fatal */
        ivp_warn(z->warn, "setSummitDelta: value less than zero");
        return KELP_ERR_RANGE;
    }
    double range = z->comp[idx].maxutil - z->comp[idx].minutil;
    if (v > range) {
        v = range;
        ivp_warn(z->warn, "setSummitDelta: delta greater than util range, clipped");
    }
    z->comp[idx].summitdelta = v;
    return 0;
}

int kelp_ivp_zaic_peak_set_minmaxutil(kelp_ivp_zaic_peak *z, double min, double max, unsigned idx)
{
    if (bad_index(z, idx, "setMinMaxUtil: index out of range"))
        return KELP_ERR_RANGE;
    if (!(min < max) || !isfinite(min) || !isfinite(max)) {
        z->ok = false;
        ivp_warn(z->warn, "setMinMaxUtil: min>=max");
        return KELP_ERR_RANGE;
    }
    kelp_ivp_zaic_comp *c = &z->comp[idx];
    c->minutil = min;
    c->maxutil = max;
    if (c->summitdelta > max - min) {
        c->summitdelta = max - min;
        ivp_warn(z->warn, "setMinMaxUtil: summitdelta clipped to util range");
    }
    return 0;
}

int kelp_ivp_zaic_peak_set_params(kelp_ivp_zaic_peak *z, double summit, double pwidth, double bwidth,
                                  double sdelta, double minutil, double maxutil, unsigned idx)
{
    int rc = kelp_ivp_zaic_peak_set_summit(z, summit, idx);
    int r2 = kelp_ivp_zaic_peak_set_basewidth(z, bwidth, idx);
    int r3 = kelp_ivp_zaic_peak_set_peakwidth(z, pwidth, idx);
    int r4 = kelp_ivp_zaic_peak_set_minmaxutil(z, minutil, maxutil, idx);
    int r5 = kelp_ivp_zaic_peak_set_summitdelta(z, sdelta, idx);
    if (rc)
        return rc;
    if (r2)
        return r2;
    if (r3)
        return r3;
    if (r4)
        return r4;
    return r5;
}

/* Value of component c at native value x (seed 004 section 7.1.2 in distance form). */
static double comp_value(const kelp_ivp_zaic_peak *z, const kelp_ivp_zaic_comp *c, double x)
{
    double s = c->summit, pw = c->peakwidth, bw = c->basewidth;
    double maxu = c->maxutil, minu = c->minutil;
    double sd = pw <= 0 ? 0 : c->summitdelta;
    double dist;
    if (!z->wrap) {
        dist = s >= x ? s - x : x - s;
    } else {
        /* the domain is a circle of period high-low+delta */
        const kelp_ivp_var *v = &z->dom.var[0];
        double l, r;
        if (s > x) {
            r = s - x;
            l = (x - v->low) + (v->high - s) + v->delta;
        } else {
            l = x - s;
            r = (v->high - x) + (s - v->low) + v->delta;
        }
        dist = l < r ? l : r;
    }
    double val;
    if (dist <= pw) {
        if (sd <= 0)
            val = maxu;
        else
            val = maxu - (sd / pw) * dist;
    } else if (dist <= pw + bw) {
        double edge = maxu - sd;
        double slope = (edge - minu) / bw;
        val = edge - slope * (dist - pw);
    } else {
        val = minu;
    }
    if (val > maxu)
        val = maxu;
    return val;
}

double kelp_ivp_zaic_peak_value(const kelp_ivp_zaic_peak *z, uint32_t ix, bool use_max)
{
    double x = ((double)ix * z->dom.var[0].delta) + z->dom.var[0].low;
    double best = 0, total = 0;
    for (unsigned k = 0; k < z->ncomp; k++) {
        double v = comp_value(z, &z->comp[k], x);
        if (k == 0 || v > best)
            best = v;
        total += v;
    }
    return use_max ? best : total;
}

size_t kelp_ivp_zaic_peak_max_pieces(const kelp_ivp_zaic_peak *z)
{
    return z->dom.dim == 1 ? z->dom.var[0].points : 0;
}

size_t kelp_ivp_zaic_peak_work_len(const kelp_ivp_zaic_peak *z)
{
    return kelp_ivp_zaic_peak_max_pieces(z);
}

static void insist_summit(const kelp_ivp_zaic_peak *z, const kelp_ivp_zaic_comp *c, double *vals, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++)
        if (vals[i] != c->minutil)
            return;
    const kelp_ivp_var *v = &z->dom.var[0];
    if (c->summit < v->low) {
        vals[0] = c->maxutil;
        return;
    }
    if (c->summit > v->high) {
        vals[n - 1] = c->maxutil;
        return;
    }
    double best = 0;
    uint32_t bi = 0;
    for (uint32_t i = 0; i < n; i++) {
        double d = (((double)i * v->delta) + v->low) - c->summit;
        if (d < 0)
            d = -d;
        if (i == 0 || d < best) {
            best = d;
            bi = i;
        }
    }
    vals[bi] = c->maxutil;
}

static int push1(kelp_ivp_func *f, int32_t lo, int32_t hi, double slope, double cst)
{
    if (f->n >= f->cap)
        return KELP_ERR_NOSPACE;
    kelp_ivp_piece *p = &f->pcs[f->n++];
    p->lo[0] = lo;
    p->hi[0] = hi;
    p->slope[0] = slope;
    p->cst = cst;
    for (unsigned d = 1; d < KELP_IVP_MAX_DIM; d++) {
        p->lo[d] = p->hi[d] = 0;
        p->slope[d] = 0;
    }
    return 0;
}

/* Piece for the run [a,b] through (a, va) and (b, vb): MOOS-IvP's slope/intercept arithmetic. */
static int push_run(kelp_ivp_func *f, uint32_t a, uint32_t b, double va, double vb)
{
    double run = (double)b - (double)a;
    double slope = run > 0 ? (vb - va) / run : 0.0;
    double cst = va - slope * (double)a;
    return push1(f, (int32_t)a, (int32_t)b, slope, cst);
}

/* Cut vals[0..n) (n >= 2) into pieces with MOOS-IvP's rule (ZAIC_PEAK::setPDMap): a run grows
 * while each value stays within the tolerance of the line through the run's first two points and
 * does not step against that line's slope. A run's second point always follows its first, so the
 * line's slope is (v1 - v0) / 1 == v1 - v0. A break at the domain's last point stores that point's
 * own piece before the run it ends (as MOOS-IvP does). */
static int cut_all(const double *vals, uint32_t n, kelp_ivp_func *out)
{
    uint32_t first = 0, i = 1;
    double first_val = vals[0];
    for (;;) {
        /* point i = first + 1 sets the run's line */
        double vi = vals[i], di = (double)i, prev = first_val;
        double s_m = vi - first_val;
        double s_b = vi - s_m * di;
        /* step against the slope: (vi - prev) * sg < 0 is loc_m < 0 for s_m > 0, loc_m > 0 for
         * s_m < 0, never for s_m == 0 */
        double sg = s_m > 0 ? 1.0 : (s_m < 0 ? -1.0 : 0.0);
        bool brk;
        for (;;) {
            brk = fabs((s_m * di + s_b) - vi) > ZAIC_TOLERANCE || (vi - prev) * sg < 0;
            if (brk || i == n - 1)
                break;
            prev = vi;
            i++;
            di += 1.0;
            vi = vals[i];
        }
        int rc;
        if (i == n - 1) {
            if (!brk)
                return push_run(out, first, i, first_val, vi);
            if ((rc = push1(out, (int32_t)i, (int32_t)i, 0.0, vi)) != 0)
                return rc;
            return push_run(out, first, i - 1, first_val, prev);
        }
        if ((rc = push_run(out, first, i - 1, first_val, prev)) != 0)
            return rc;
        first = i;
        first_val = vi;
        i++;
    }
}

/* ---- one component, by index ranges
 *
 * For a single component, comp_value's branches are fixed over a few index ranges: x = i*delta+low
 * is nondecreasing in i (rounding is monotone), so are x-low and x-s, and s-x, high-x are
 * nonincreasing; every distance form is one of those plus constants, so each branch condition
 * holds on a prefix (or suffix) of a range where the others are fixed. The ranges are found by
 * binary search on those exact conditions, then each range is evaluated with the operations
 * comp_value uses for that branch: the same bits, without the per-point branching. */

typedef struct peak1 {
    double s, pw, pwbw, maxu, minu, slope1, edge, slope2, low, delta, high, s_top, s_bot;
} peak1;

static inline double p1_x(const peak1 *k, uint32_t i)
{
    return ((double)i * k->delta) + k->low;
}

/* The distance forms of comp_value: 0 s-x, 1 x-s, 2 around the low end, 3 around the high end. */
static inline double p1_dist(const peak1 *k, int form, double x)
{
    switch (form) {
    case 0:
        return k->s - x;
    case 1:
        return x - k->s;
    case 2:
        return (x - k->low) + k->s_top + k->delta;
    default:
        return (k->high - x) + k->s_bot + k->delta;
    }
}

/* Condition of range split c at index i: 0 (s > x), 1 (s >= x), 2 the low-end wrap distance is
 * the shorter (s > x), 3 x-s is the shorter (x >= s). Each is true on a prefix. */
static inline bool p1_cond(const peak1 *k, int c, uint32_t i)
{
    double x = p1_x(k, i);
    switch (c) {
    case 0:
        return k->s > x;
    case 1:
        return k->s >= x;
    case 2:
        return p1_dist(k, 2, x) < p1_dist(k, 0, x);
    default:
        return p1_dist(k, 1, x) < p1_dist(k, 3, x);
    }
}

/* First index in [a, b) where condition c (true on a prefix) is false; b if none. */
static uint32_t p1_split(const peak1 *k, int c, uint32_t a, uint32_t b)
{
    while (a < b) {
        uint32_t m = a + (b - a) / 2;
        if (p1_cond(k, c, m))
            a = m + 1;
        else
            b = m;
    }
    return a;
}

/* First index in [a, b) where d[i] <= t is false (true on a prefix: d nondecreasing) or, with
 * down, where d[i] <= t is true (false on a prefix: d nonincreasing); b if none. */
static uint32_t p1_thresh(const double *d, double t, bool down, uint32_t a, uint32_t b)
{
    while (a < b) {
        uint32_t m = a + (b - a) / 2;
        if ((d[m] <= t) != down)
            a = m + 1;
        else
            b = m;
    }
    return a;
}

static void p1_peak(const peak1 *k, double *v, uint32_t a, uint32_t b)
{
    const double maxu = k->maxu, sl = k->slope1;
    for (uint32_t i = a; i < b; i++) {
        double val = maxu - sl * v[i]; /* sd <= 0: slope1 == 0 and maxu - 0*dist == maxu */
        v[i] = maxu < val ? maxu : val;
    }
}

static void p1_ramp(const peak1 *k, double *v, uint32_t a, uint32_t b)
{
    const double maxu = k->maxu, edge = k->edge, sl = k->slope2, pw = k->pw;
    for (uint32_t i = a; i < b; i++) {
        double val = edge - sl * (v[i] - pw);
        v[i] = maxu < val ? maxu : val;
    }
}

static void p1_flat(const peak1 *k, double *v, uint32_t a, uint32_t b)
{
    const double val = k->maxu < k->minu ? k->maxu : k->minu;
    for (uint32_t i = a; i < b; i++)
        v[i] = val;
}

/* Values over [a, b) where distance form `form` applies; down: that distance is nonincreasing. */
static void p1_range(const peak1 *k, int form, bool down, double *v, uint32_t a, uint32_t b)
{
    if (a >= b)
        return;
    double di = (double)a;
    switch (form) { /* the distances, in place */
    case 0:
        for (uint32_t i = a; i < b; i++, di += 1.0)
            v[i] = k->s - ((di * k->delta) + k->low);
        break;
    case 1:
        for (uint32_t i = a; i < b; i++, di += 1.0)
            v[i] = ((di * k->delta) + k->low) - k->s;
        break;
    case 2:
        for (uint32_t i = a; i < b; i++, di += 1.0)
            v[i] = ((((di * k->delta) + k->low) - k->low) + k->s_top) + k->delta;
        break;
    default:
        for (uint32_t i = a; i < b; i++, di += 1.0)
            v[i] = ((k->high - ((di * k->delta) + k->low)) + k->s_bot) + k->delta;
        break;
    }
    /* comp_value: dist <= pw -> peak; else dist <= pw+bw -> ramp; else minutil */
    if (!down) {
        uint32_t e1 = p1_thresh(v, k->pw, false, a, b);
        uint32_t e2 = p1_thresh(v, k->pwbw, false, e1, b);
        p1_peak(k, v, a, e1);
        p1_ramp(k, v, e1, e2);
        p1_flat(k, v, e2, b);
    } else {
        uint32_t e1 = p1_thresh(v, k->pwbw, true, a, b);
        uint32_t e2 = p1_thresh(v, k->pw, true, e1, b);
        p1_flat(k, v, a, e1);
        p1_ramp(k, v, e1, e2);
        p1_peak(k, v, e2, b);
    }
}

/* false when a parameter is too large or not finite for the range method (then per point). */
static bool peak1_values(const kelp_ivp_zaic_peak *z, double *vals, uint32_t n)
{
    const kelp_ivp_zaic_comp *c = &z->comp[0];
    const kelp_ivp_var *v = &z->dom.var[0];
    const double lim = 1e150;
    if (!(fabs(c->summit) < lim && fabs(c->peakwidth) < lim && fabs(c->basewidth) < lim && fabs(c->maxutil) < lim &&
          fabs(c->minutil) < lim && fabs(c->summitdelta) < lim && fabs(v->low) < lim && fabs(v->high) < lim &&
          fabs(v->delta) * (double)n < lim))
        return false;
    peak1 k;
    k.s = c->summit;
    k.pw = c->peakwidth;
    k.pwbw = c->peakwidth + c->basewidth;
    k.maxu = c->maxutil;
    k.minu = c->minutil;
    double sd = k.pw <= 0 ? 0 : c->summitdelta;
    k.slope1 = sd > 0 ? sd / k.pw : 0.0;
    k.edge = k.maxu - sd;
    /* comp_value computes (edge - minu) / bw only on the ramp, which is empty when bw == 0 */
    k.slope2 = c->basewidth != 0 ? (k.edge - k.minu) / c->basewidth : 0.0;
    k.low = v->low;
    k.delta = v->delta;
    k.high = v->high;
    k.s_top = v->high - k.s;
    k.s_bot = k.s - v->low;
    if (!z->wrap) { /* dist = s >= x ? s - x : x - s */
        uint32_t a = p1_split(&k, 1, 0, n);
        p1_range(&k, 0, true, vals, 0, a);
        p1_range(&k, 1, false, vals, a, n);
    } else { /* s > x: min(low-end wrap, s - x); else min(x - s, high-end wrap) */
        uint32_t a = p1_split(&k, 0, 0, n);
        uint32_t a1 = p1_split(&k, 2, 0, a);
        uint32_t b1 = p1_split(&k, 3, a, n);
        p1_range(&k, 2, false, vals, 0, a1);
        p1_range(&k, 0, true, vals, a1, a);
        p1_range(&k, 1, false, vals, a, b1);
        p1_range(&k, 3, true, vals, b1, n);
    }
    return true;
}

int kelp_ivp_zaic_peak_extract(const kelp_ivp_zaic_peak *z, bool use_max, double *work, size_t work_len,
                               kelp_ivp_piece *store, size_t cap, kelp_ivp_func *out)
{
    if (!z->ok || z->dom.dim != 1)
        return KELP_ERR_STATE;
    uint32_t n = z->dom.var[0].points;
    if (!work || work_len < n)
        return KELP_ERR_NOSPACE;
    int rc = kelp_ivp_func_init(out, &z->dom, store, cap);
    if (rc)
        return rc;
    double *vals = work;
    if (z->ncomp == 1) { /* one component: its own value (no 0 + v of the sum) */
        if (!peak1_values(z, vals, n)) {
            const kelp_ivp_var *v = &z->dom.var[0];
            for (uint32_t i = 0; i < n; i++)
                vals[i] = comp_value(z, &z->comp[0], ((double)i * v->delta) + v->low);
        }
    } else {
        for (uint32_t i = 0; i < n; i++)
            vals[i] = kelp_ivp_zaic_peak_value(z, i, use_max);
    }
    if (z->insist)
        for (unsigned k = 0; k < z->ncomp; k++)
            insist_summit(z, &z->comp[k], vals, n);

    if (n == 1) /* upstream makes no piece here; one point is one piece */
        return push1(out, 0, 0, 0.0, vals[0]);
    return cut_all(vals, n, out);
}

/* ------------------------------------------------------------------ ZAIC_LEQ / ZAIC_HEQ */

int kelp_ivp_zaic_hleq_init(kelp_ivp_zaic_hleq *z, kelp_ivp_zaic_kind kind, const kelp_ivp_domain *dom, const char *var)
{
    memset(z, 0, sizeof *z);
    z->kind = kind;
    z->ok = true;
    z->maxutil = 100;
    int rc = one_var(&z->dom, dom, var);
    if (rc) {
        z->ok = false;
        ivp_warn(z->warn, "ZAIC_LEQ/HEQ: variable not in domain");
    } else {
        z->summit = z->dom.var[0].low;
    }
    return rc;
}

int kelp_ivp_zaic_hleq_set_summit(kelp_ivp_zaic_hleq *z, double v)
{
    if (z->dom.dim != 1)
        return 0;
    if (!isfinite(v)) {
        ivp_warn(z->warn, "setSummit: value not finite, ignored");
        return 0;
    }
    /* kept as given: the function is defined beyond the domain and cut by it */
    if (v < z->dom.var[0].low || v > z->dom.var[0].high)
        ivp_warn(z->warn, "setSummit: summit out of the domain's range (suspicious)");
    z->summit = v;
    return 0;
}

int kelp_ivp_zaic_hleq_set_basewidth(kelp_ivp_zaic_hleq *z, double v)
{
    if (!(v >= 0) || !isfinite(v)) {
        z->ok = false;
        ivp_warn(z->warn, "setBaseWidth: val<0");
        return KELP_ERR_RANGE;
    }
    z->basewidth = v;
    return 0;
}

int kelp_ivp_zaic_hleq_set_minmaxutil(kelp_ivp_zaic_hleq *z, double min, double max)
{
    if (!(min < max) || !isfinite(min) || !isfinite(max)) {
        z->ok = false;
        ivp_warn(z->warn, "setMinMaxUtil: min>=max");
        return KELP_ERR_RANGE;
    }
    z->minutil = min;
    z->maxutil = max;
    return 0;
}

int kelp_ivp_zaic_hleq_set_summitdelta(kelp_ivp_zaic_hleq *z, double v)
{
    if (!(v >= 0) || !isfinite(v)) {
        ivp_warn(z->warn, "setSummitDelta: value less than zero, clipped to 0");
        v = 0;
    }
    z->summitdelta = v;
    return 0;
}

/* Index nearest native value v (MOOS-IvP's (int)(x/delta+0.5), measured from low), clipped. */
static int32_t hleq_index(const kelp_ivp_var *var, double v)
{
    if (var->points <= 1 || var->delta <= 0)
        return 0;
    double x = (v - var->low) / var->delta + 0.5;
    if (x < 0)
        return 0;
    if (x > (double)(var->points - 1))
        return (int32_t)var->points - 1;
    return (int32_t)x;
}

int kelp_ivp_zaic_hleq_extract(const kelp_ivp_zaic_hleq *z, kelp_ivp_piece *store, size_t cap, kelp_ivp_func *out)
{
    if (!z->ok || z->dom.dim != 1)
        return KELP_ERR_STATE;
    int rc = kelp_ivp_func_init(out, &z->dom, store, cap);
    if (rc)
        return rc;
    const kelp_ivp_var *v = &z->dom.var[0];
    int32_t hi = (int32_t)v->points - 1;
    double maxu = z->maxutil, minu = z->minutil, sd = z->summitdelta;
    int32_t ibw = 0;
    if (v->delta > 0)
        ibw = (int32_t)((z->basewidth + v->delta / 2) / v->delta);
    double run = ibw >= 1 ? (double)ibw : 1.0; /* upstream divides by 0 here for tiny widths */
    if (z->kind == KELP_IVP_ZAIC_LEQ) {
        /* [0,i1] max (the summit index alone at max+delta when i1 > 1), ramp (i1,i2], (i2,hi] min */
        int32_t i1 = hleq_index(v, z->summit);
        int32_t i2 = hleq_index(v, z->summit + z->basewidth);
        if (i1 > i2)
            i1 = i2;
        if (sd > 0 && i1 > 1) {
            if ((rc = push1(out, 0, i1 - 1, 0.0, maxu)) || (rc = push1(out, i1, i1, 0.0, maxu + sd)))
                return rc;
        } else if ((rc = push1(out, 0, i1, 0.0, maxu))) {
            return rc;
        }
        if (i1 < i2) {
            double slope = -(maxu - minu) / run;
            double cst = i1 > 0 ? maxu - slope * (double)i1 : minu - slope * (double)i2;
            if ((rc = push1(out, i1 + 1, i2, slope, cst)))
                return rc;
        }
        if (i2 < hi && (rc = push1(out, i2 + 1, hi, 0.0, minu)))
            return rc;
        return 0;
    }
    /* HEQ: [i2,hi] max (the summit index alone at max+delta when i2 < hi-1), ramp [i1,i2), [0,i1)
     * min. A summit at or above the domain's last index leaves that index without a piece, as
     * MOOS-IvP's ZAIC_HEQ does (the solver never picks it). */
    int32_t i2 = hleq_index(v, z->summit);
    int32_t i1 = hleq_index(v, z->summit - z->basewidth);
    if (i1 > i2)
        i1 = i2;
    if (i2 < hi) {
        if (sd > 0 && i2 < hi - 1) {
            if ((rc = push1(out, i2 + 1, hi, 0.0, maxu)) || (rc = push1(out, i2, i2, 0.0, maxu + sd)))
                return rc;
        } else if ((rc = push1(out, i2, hi, 0.0, maxu))) {
            return rc;
        }
    }
    if (i1 < i2) {
        double slope = (maxu - minu) / run;
        double cst = i1 > 0 ? minu - slope * (double)i1 : maxu - slope * (double)i2;
        if ((rc = push1(out, i1, i2 - 1, slope, cst)))
            return rc;
    }
    if (i1 > 0 && (rc = push1(out, 0, i1 - 1, 0.0, minu)))
        return rc;
    return 0;
}