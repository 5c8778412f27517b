/* kelp IvP: the Reflector (seed 004 ch. 8-9): uniform pieces from a piece count (Listing 26,
 * integer ratio, which reproduces Tables 3 and 4) or an explicit shape, directed refinement,
 * smart refinement and auto-peak refinement, over an AOF callback.
 *
 * Regression (section 9.4.2): the AOF is sampled at the 2^k corners of a piece and at its centre
 * (when some edge spans more than two points). Per dimension the slope is the mean difference
 * between corners that differ only in that dimension divided by the edge run; the constant is the
 * mean residual, clamped with strict_range so the piece stays within the sampled range (the
 * method of MOOS-IvP's Regressor). The score is eq. (4): sqrt(sum of squared residuals).
 * Splits (smart and auto-peak) halve the longest edge (lowest dimension on ties), the first half
 * getting the extra point. Stored order: uniform tiles with the last variable varying fastest;
 * a refined piece keeps its slot for its first fragment, further fragments and tiles are
 * appended; a split piece keeps its slot for its first half and appends the second.
 *
 * With a line sampler (kelp_ivp_reflector_set_line), the uniform pieces of a 2-D build without
 * scores take the same samples a row of tiles at a time (uniform2_line): an AOF that does part
 * of its work once per line (AvoidCollision: the course's unit vector) then costs less per
 * point, and a piece whose samples are all equal is fitted without the arithmetic (its slopes
 * and constant are what the fit gives). */
#include <string.h>
#include <math.h>
#include "ivp_int.h"

#define D KELP_IVP_MAX_DIM

int kelp_ivp_reflector_init(kelp_ivp_reflector *r, const kelp_ivp_domain *dom, kelp_ivp_aof_fn aof, void *user)
{
    memset(r, 0, sizeof *r);
    r->ok = true;
    r->strict_range = true;
    r->uniform_amount = -1;
    r->smart_amount = -1;
    r->smart_percent = -1;
    r->auto_peak_max_pcs = -1;
    if (!dom || !aof || dom->dim == 0) {
        r->ok = false;
        ivp_warn(r->warn, "Reflector: null domain or AOF");
        return KELP_ERR_ARG;
    }
    r->dom = *dom;
    r->aof = aof;
    r->aof_user = user;
    return 0;
}

void kelp_ivp_reflector_set_line(kelp_ivp_reflector *r, kelp_ivp_aof_line_fn line)
{
    r->aof_line = line;
}

static int fatal(kelp_ivp_reflector *r, int code, const char *name, const char *what)
{
    char buf[KELP_IVP_MAX_WARN];
    buf[0] = '\0';
    ivp_strcat(buf, sizeof buf, name);
    ivp_strcat(buf, sizeof buf, ": ");
    ivp_strcat(buf, sizeof buf, what);
    ivp_warn(r->warn, buf);
    r->ok = false;
    return code;
}

static int set_int(kelp_ivp_reflector *r, const char *name, double v, int min, int *dst)
{
    if (!isfinite(v) || v != floor(v) || v < (double)min || v > 100000000.0)
        return fatal(r, KELP_ERR_RANGE, name, min >= 1 ? "value must be an integer >= 1" : "value must be an integer >= 0");
    *dst = (int)v;
    return 0;
}

int kelp_ivp_reflector_set_paramf(kelp_ivp_reflector *r, const char *name, double v)
{
    size_t n = strlen(name);
    const char *s = name;
    ivp_trim(&s, &n);
    if (ivp_word_eq(s, n, "uniform_amount"))
        return set_int(r, "uniform_amount", v, 1, &r->uniform_amount);
    if (ivp_word_eq(s, n, "smart_amount"))
        return set_int(r, "smart_amount", v, 0, &r->smart_amount);
    if (ivp_word_eq(s, n, "smart_percent"))
        return set_int(r, "smart_percent", v, 0, &r->smart_percent);
    if (ivp_word_eq(s, n, "auto_peak_max_pcs"))
        return set_int(r, "auto_peak_max_pcs", v, 1, &r->auto_peak_max_pcs);
    if (ivp_word_eq(s, n, "smart_thresh")) {
        if (!isfinite(v) || v < 0)
            return fatal(r, KELP_ERR_RANGE, "smart_thresh", "value must be >= 0");
        r->smart_thresh = v;
        r->have_smart_thresh = true;
        return 0;
    }
    return fatal(r, KELP_ERR_NOTFOUND, name, "unhandled parameter");
}

int kelp_ivp_reflector_set_param(kelp_ivp_reflector *r, const char *name, const char *value)
{
    size_t n = strlen(name), vn = strlen(value);
    const char *s = name, *v = value;
    ivp_trim(&s, &n);
    ivp_trim(&v, &vn);
    kelp_diag *diag = &r->ws_diag; /* in the Reflector, not on the stack */
    kelp_diag_clear(diag);
    int rc;
    if (ivp_word_eq(s, n, "uniform_amount") || ivp_word_eq(s, n, "smart_amount") || ivp_word_eq(s, n, "smart_percent") ||
        ivp_word_eq(s, n, "smart_thresh") || ivp_word_eq(s, n, "auto_peak_max_pcs")) {
        double x;
        if (ivp_parse_double(v, vn, &x))
            return fatal(r, KELP_ERR_PARSE, name, "value is not a number");
        return kelp_ivp_reflector_set_paramf(r, name, x);
    }
    if (ivp_word_eq(s, n, "strict_range") || ivp_word_eq(s, n, "auto_peak")) {
        bool b;
        if (ivp_word_eq(v, vn, "true"))
            b = true;
        else if (ivp_word_eq(v, vn, "false"))
            b = false;
        else
            return fatal(r, KELP_ERR_PARSE, name, "value must be true or false");
        if (ivp_word_eq(s, n, "auto_peak"))
            r->auto_peak = b;
        else
            r->strict_range = b;
        return 0;
    }
    if (ivp_word_eq(s, n, "uniform_piece")) {
        rc = kelp_ivp_parse_shape(&r->dom, value, r->uniform_piece, diag);
        if (rc)
            return fatal(r, rc, "uniform_piece", kelp_diag_text(diag));
        r->have_uniform_piece = true;
        return 0;
    }
    if (ivp_word_eq(s, n, "refine_region")) {
        if (r->refine_pending)
            return fatal(r, KELP_ERR_STATE, "refine_region", "refine_region and refine_piece must be added in pairs");
        if (r->nrefine >= KELP_IVP_MAX_REFINE)
            return fatal(r, KELP_ERR_NOSPACE, "refine_region", "too many refine regions");
        rc = kelp_ivp_parse_region(&r->dom, value, r->refine_lo[r->nrefine], r->refine_hi[r->nrefine], diag);
        if (rc)
            return fatal(r, rc, "refine_region", kelp_diag_text(diag));
        r->refine_pending = true;
        return 0;
    }
    if (ivp_word_eq(s, n, "refine_piece")) {
        if (!r->refine_pending)
            return fatal(r, KELP_ERR_STATE, "refine_piece", "refine_region and refine_piece must be added in pairs");
        rc = kelp_ivp_parse_shape(&r->dom, value, r->refine_piece[r->nrefine], diag);
        if (rc)
            return fatal(r, rc, "refine_piece", kelp_diag_text(diag));
        r->refine_pending = false;
        r->nrefine++;
        return 0;
    }
    if (ivp_word_eq(s, n, "refine_point")) {
        uint32_t ix[D];
        rc = kelp_ivp_parse_point(&r->dom, value, ix, diag);
        if (rc)
            return fatal(r, rc, "refine_point", kelp_diag_text(diag));
        return 0;
    }
    return fatal(r, KELP_ERR_NOTFOUND, name, "unhandled parameter");
}

void kelp_ivp_uniform_piece(const kelp_ivp_domain *d, int amount, uint32_t *edge)
{
    uint32_t pcs[D], pts[D];
    bool maxed[D];
    unsigned dim = d->dim;
    if (amount < 1)
        amount = 1;
    for (unsigned i = 0; i < dim; i++) {
        pcs[i] = 1;
        pts[i] = d->var[i].points;
        maxed[i] = pts[i] <= 1;
    }
    for (;;) {
        unsigned aug = dim;
        uint32_t biggest = 0;
        for (unsigned i = 0; i < dim; i++) {
            if (maxed[i])
                continue;
            uint32_t ratio = pts[i] / pcs[i]; /* integer division, as Listing 26 */
            if (aug == dim || ratio > biggest) {
                biggest = ratio;
                aug = i;
            }
        }
        if (aug == dim)
            break;
        pcs[aug]++;
        double total = 1;
        for (unsigned i = 0; i < dim; i++)
            total *= (double)pcs[i];
        if (total > (double)amount) {
            maxed[aug] = true;
            pcs[aug]--;
        }
        if (pcs[aug] >= pts[aug])
            maxed[aug] = true;
    }
    for (unsigned i = 0; i < dim; i++)
        edge[i] = (uint32_t)ceil((double)pts[i] / (double)pcs[i]);
}

static uint32_t tiles_on(uint32_t len, uint32_t e)
{
    return (len + e - 1) / e;
}

static size_t uniform_count(const kelp_ivp_domain *d, const uint32_t *edge)
{
    size_t n = 1;
    for (unsigned i = 0; i < d->dim; i++)
        n *= tiles_on(d->var[i].points, edge[i]);
    return n;
}

static void choose_uniform(const kelp_ivp_reflector *r, int amount, uint32_t *edge)
{
    if (r->have_uniform_piece) {
        memcpy(edge, r->uniform_piece, sizeof(uint32_t) * r->dom.dim);
    } else if (amount >= 1) {
        kelp_ivp_uniform_piece(&r->dom, amount, edge);
    } else {
        for (unsigned i = 0; i < r->dom.dim; i++)
            edge[i] = r->dom.var[i].points; /* one piece */
    }
}

static size_t region_tiles(const kelp_ivp_reflector *r, unsigned k)
{
    size_t n = 1;
    for (unsigned i = 0; i < r->dom.dim; i++)
        n *= tiles_on((uint32_t)(r->refine_hi[k][i] - r->refine_lo[k][i] + 1), r->refine_piece[k][i]);
    return n;
}

size_t kelp_ivp_reflector_max_pieces(const kelp_ivp_reflector *r, int uniform_amount, int smart_amount)
{
    uint32_t edge[D] = {0};
    int amount = uniform_amount >= 1 ? uniform_amount : r->uniform_amount;
    choose_uniform(r, amount, edge);
    size_t n = uniform_count(&r->dom, edge);
    for (unsigned k = 0; k < r->nrefine; k++)
        n = n * (2 * r->dom.dim + 1) + region_tiles(r, k);
    int sa = smart_amount >= 0 ? smart_amount : r->smart_amount;
    size_t extra = sa > 0 ? (size_t)sa : 0;
    if (r->smart_percent > 0) {
        size_t pe = n * (size_t)r->smart_percent / 100u;
        if (pe > extra)
            extra = pe;
    }
    n += extra;
    if (r->auto_peak) {
        if (r->auto_peak_max_pcs > 0) {
            n += (size_t)r->auto_peak_max_pcs;
        } else {
            double t = kelp_ivp_domain_total(&r->dom);
            if (t > (double)n)
                n = t > 1e9 ? (size_t)1000000000u : (size_t)t;
        }
    }
    return n;
}

size_t kelp_ivp_reflector_work_len(size_t cap)
{
    return cap;
}

/* ------------------------------------------------------------------ regression */

static double eval_ix(const kelp_ivp_reflector *r, const int32_t *ix)
{
    double pt[D];
    for (unsigned d = 0; d < r->dom.dim; d++) /* kelp_ivp_domain_value, inline */
        pt[d] = ((double)(uint32_t)ix[d] * r->dom.var[d].delta) + r->dom.var[d].low;
    return r->aof(pt, r->aof_user);
}

#if defined(__GNUC__)
#define IVP_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define IVP_ALWAYS_INLINE inline
#endif

/* Fit p's interior to the AOF; returns the regression score (eq. 4), or 0 without `score`.
 * Inlined with a constant dim for the common domains (the same arithmetic, in the same order,
 * unrolled: a 2-D piece costs a fifth of the generic loop). */
static IVP_ALWAYS_INLINE double regress_n(const kelp_ivp_reflector *r, kelp_ivp_piece *p, unsigned dim, bool score)
{
    unsigned nc = 1u << dim;
    double cv[1u << D] = {0};
    int32_t pt[D];
    for (unsigned i = 0; i < nc; i++) {
        unsigned dup = dim;
        for (unsigned d = 0; d < dim; d++)
            if (((i >> d) & 1u) && p->lo[d] == p->hi[d]) {
                dup = d;
                break;
            }
        if (dup < dim) {
            cv[i] = cv[i ^ (1u << dup)]; /* same point: evaluate the AOF once */
            continue;
        }
        for (unsigned d = 0; d < dim; d++)
            pt[d] = ((i >> d) & 1u) ? p->hi[d] : p->lo[d];
        cv[i] = eval_ix(r, pt);
    }
    bool center = false;
    int32_t cp[D];
    for (unsigned d = 0; d < dim; d++) {
        cp[d] = (p->lo[d] + p->hi[d]) / 2;
        if (p->hi[d] - p->lo[d] >= 2)
            center = true;
    }
    double cval = center ? eval_ix(r, cp) : 0.0;
    double hv = cv[0], lv = cv[0];
    for (unsigned i = 1; i < nc; i++) {
        if (cv[i] > hv)
            hv = cv[i];
        if (cv[i] < lv)
            lv = cv[i];
    }
    if (center) {
        if (cval > hv)
            hv = cval;
        if (cval < lv)
            lv = cval;
    }
    for (unsigned d = 0; d < dim; d++) {
        double run = (double)(p->hi[d] - p->lo[d]);
        if (run == 0) {
            p->slope[d] = 0;
            continue;
        }
        double rise = 0;
        for (unsigned i = 0; i < nc; i++)
            if ((i >> d) & 1u)
                rise += cv[i] - cv[i ^ (1u << d)];
        rise /= (double)nc / 2.0;
        p->slope[d] = rise / run;
    }
    double total = 0, maxi = 0, mini = 0;
    unsigned ns = nc + (center ? 1u : 0u);
    for (unsigned i = 0; i < ns; i++) {
        double plane = 0, val;
        for (unsigned d = 0; d < dim; d++) {
            double x = i < nc ? (double)(((i >> d) & 1u) ? p->hi[d] : p->lo[d]) : (double)cp[d];
            plane += p->slope[d] * x;
        }
        val = i < nc ? cv[i] : cval;
        total += val - plane;
        double imax = hv - plane, imin = lv - plane;
        if (i == 0 || imax < maxi)
            maxi = imax;
        if (i == 0 || imin > mini)
            mini = imin;
    }
    double c = total / (double)ns;
    if (r->strict_range) {
        if (c > maxi)
            c = maxi;
        if (c < mini)
            c = mini;
    }
    p->cst = c;
    if (!score)
        return 0;
    double err = 0;
    for (unsigned i = 0; i < ns; i++) {
        double lin = c;
        for (unsigned d = 0; d < dim; d++) {
            double x = i < nc ? (double)(((i >> d) & 1u) ? p->hi[d] : p->lo[d]) : (double)cp[d];
            lin += p->slope[d] * x;
        }
        double dv = lin - (i < nc ? cv[i] : cval);
        err += dv * dv;
    }
    return sqrt(err);
}

/* one out-of-line scored fit per dimension count (as fit below: only the one called is on the
 * stack) */
static KELP_NOINLINE double regress1(const kelp_ivp_reflector *r, kelp_ivp_piece *p)
{
    return regress_n(r, p, 1, true);
}

static KELP_NOINLINE double regress2(const kelp_ivp_reflector *r, kelp_ivp_piece *p)
{
    return regress_n(r, p, 2, true);
}

static KELP_NOINLINE double regress3(const kelp_ivp_reflector *r, kelp_ivp_piece *p)
{
    return regress_n(r, p, 3, true);
}

static KELP_NOINLINE double regressn(const kelp_ivp_reflector *r, kelp_ivp_piece *p)
{
    return regress_n(r, p, r->dom.dim, true);
}

static double regress(const kelp_ivp_reflector *r, kelp_ivp_piece *p)
{
    switch (r->dom.dim) {
    case 1: return regress1(r, p);
    case 2: return regress2(r, p);
    case 3: return regress3(r, p);
    default: return regressn(r, p);
    }
}

/* fit2's fit from its samples: the corners cv (index bit 0: variable 0 high, bit 1: variable 1
 * high) and, with `center`, the value at the centre point (c0, c1). */
static IVP_ALWAYS_INLINE void fit2_from(bool strict, kelp_ivp_piece *p, const double *cv, double cval, bool center,
                                        int32_t c0, int32_t c1)
{
    const int32_t l0 = p->lo[0], h0 = p->hi[0], l1 = p->lo[1], h1 = p->hi[1];
    if (strict && cv[0] - cv[0] == 0 && cv[1] == cv[0] && cv[2] == cv[0] && cv[3] == cv[0] &&
        (!center || cval == cv[0])) {
        /* a flat piece (common: a utility at its cap): the fit below gives slopes +0 and a
         * constant clamped into [cv[0], cv[0]], so cv[0] itself (a zero as +0, as the sum gives) */
        p->slope[0] = 0.0;
        p->slope[1] = 0.0;
        p->cst = cv[0] + 0.0;
        return;
    }
    double hv = cv[0], lv = cv[0];
    for (unsigned i = 1; i < 4; i++) {
        if (cv[i] > hv)
            hv = cv[i];
        if (cv[i] < lv)
            lv = cv[i];
    }
    if (center) {
        if (cval > hv)
            hv = cval;
        if (cval < lv)
            lv = cval;
    }
    double s0 = 0, s1 = 0, run0 = (double)(h0 - l0), run1 = (double)(h1 - l1);
    if (run0 != 0) {
        double rise = 0;
        rise += cv[1] - cv[0];
        rise += cv[3] - cv[2];
        rise /= 2.0;
        s0 = rise / run0;
    }
    if (run1 != 0) {
        double rise = 0;
        rise += cv[2] - cv[0];
        rise += cv[3] - cv[1];
        rise /= 2.0;
        s1 = rise / run1;
    }
    p->slope[0] = s0;
    p->slope[1] = s1;
    const double xs0[5] = {(double)l0, (double)h0, (double)l0, (double)h0, (double)c0};
    const double xs1[5] = {(double)l1, (double)l1, (double)h1, (double)h1, (double)c1};
    const double val[5] = {cv[0], cv[1], cv[2], cv[3], cval};
    unsigned ns = center ? 5u : 4u;
    /* regress_n's bounds min_i (hv - plane_i) and max_i (lv - plane_i) taken as hv - max plane
     * and lv - min plane: rounding is monotonic, so the same values */
    double total = 0, pmax = 0, pmin = 0;
    for (unsigned i = 0; i < ns; i++) {
        double plane = 0;
        plane += s0 * xs0[i];
        plane += s1 * xs1[i];
        total += val[i] - plane;
        if (i == 0 || plane > pmax)
            pmax = plane;
        if (i == 0 || plane < pmin)
            pmin = plane;
    }
    double c = total / (double)ns, maxi = hv - pmax, mini = lv - pmin;
    if (strict) {
        if (c > maxi)
            c = maxi;
        if (c < mini)
            c = mini;
    }
    p->cst = c;
}

/* regress_n's fit for two variables written out: the same samples, the same arithmetic in the
 * same order (so the same bits), without the loops over corner masks. */
static KELP_NOINLINE void fit2(const kelp_ivp_reflector *r, kelp_ivp_piece *p)
{
    const int32_t l0 = p->lo[0], h0 = p->hi[0], l1 = p->lo[1], h1 = p->hi[1];
    const int32_t c0 = (l0 + h0) / 2, c1 = (l1 + h1) / 2;
    const kelp_ivp_var *v0 = &r->dom.var[0], *v1 = &r->dom.var[1];
    /* native values as kelp_ivp_domain_value */
    double a0 = ((double)(uint32_t)l0 * v0->delta) + v0->low, b0 = ((double)(uint32_t)h0 * v0->delta) + v0->low;
    double a1 = ((double)(uint32_t)l1 * v1->delta) + v1->low, b1 = ((double)(uint32_t)h1 * v1->delta) + v1->low;
    double pt[2];
    double cv[4];
    pt[0] = a0, pt[1] = a1;
    cv[0] = r->aof(pt, r->aof_user);
    if (l0 == h0) {
        cv[1] = cv[0];
    } else {
        pt[0] = b0, pt[1] = a1;
        cv[1] = r->aof(pt, r->aof_user);
    }
    if (l1 == h1) {
        cv[2] = cv[0];
    } else {
        pt[0] = a0, pt[1] = b1;
        cv[2] = r->aof(pt, r->aof_user);
    }
    if (l0 == h0) {
        cv[3] = cv[2];
    } else if (l1 == h1) {
        cv[3] = cv[1];
    } else {
        pt[0] = b0, pt[1] = b1;
        cv[3] = r->aof(pt, r->aof_user);
    }
    bool center = h0 - l0 >= 2 || h1 - l1 >= 2;
    double cval = 0.0;
    if (center) {
        pt[0] = ((double)(uint32_t)c0 * v0->delta) + v0->low;
        pt[1] = ((double)(uint32_t)c1 * v1->delta) + v1->low;
        cval = r->aof(pt, r->aof_user);
    }
    fit2_from(r->strict_range, p, cv, cval, center, c0, c1);
}

/* uniform2_line's pieces of one row of tiles: nt tiles from b[2] along variable 1 (tile b[3]
 * points, n1 points in all), variable 0 from b[0] to b[1]; samples ya (low end of variable 0),
 * yb (high end), each tile's low and high ends of variable 1 in turn, and yc (the centres;
 * wrow: every tile has one, else only a tile three points wide along variable 1). Out of line,
 * with its fit's locals: they are not on the stack while the line sampler runs. */
static KELP_NOINLINE void fit_row(bool strict, kelp_ivp_piece *p, uint32_t nt, const int32_t *b, int32_t n1,
                                  const double *ya, const double *yb, bool wrow, const double *yc)
{
    const int32_t a0 = b[0], h0 = b[1], e1 = b[3], c0 = (a0 + h0) / 2;
    for (uint32_t t = 0; t < nt; t++, p++) {
        const int32_t a1 = b[2] + (int32_t)t * e1, h1 = a1 + e1 - 1 < n1 ? a1 + e1 - 1 : n1 - 1;
        memset(p, 0, sizeof *p);
        p->lo[0] = a0, p->hi[0] = h0, p->lo[1] = a1, p->hi[1] = h1;
        double cv[4] = {ya[2 * t], yb[2 * t], ya[2 * t + 1], yb[2 * t + 1]};
        bool center = wrow || h1 - a1 >= 2;
        fit2_from(strict, p, cv, center ? yc[t] : 0.0, center, c0, (a1 + h1) / 2);
    }
}

/* Uniform pieces of a 2-D domain sampled a row at a time through the line sampler: per row of
 * tiles (variable 0 from a0 to h0) and up to KELP_IVP_LINE_CHUNK tiles along variable 1, one
 * line at a0 and one at h0 through the tiles' low and high ends, one at the centre c0 through
 * the tiles' centres; then fit2's fit from those samples. The points and values are fit2's (a
 * point met twice, as a tile one point wide, is sampled twice: the AOF gives the same value;
 * a centre no piece needs may be sampled and not used), the pieces are in tile's order. */
static KELP_NOINLINE int uniform2_line(kelp_ivp_reflector *r, kelp_ivp_func *out, const uint32_t *edge)
{
    const kelp_ivp_var *v0 = &r->dom.var[0], *v1 = &r->dom.var[1];
    const int32_t n0 = (int32_t)v0->points, n1 = (int32_t)v1->points, e0 = (int32_t)edge[0], e1 = (int32_t)edge[1];
    const uint32_t T0 = tiles_on((uint32_t)n0, (uint32_t)e0), T1 = tiles_on((uint32_t)n1, (uint32_t)e1);
    if (out->cap - out->n < (size_t)T0 * T1)
        return KELP_ERR_NOSPACE;
    const uint32_t C = KELP_IVP_LINE_CHUNK;
    double *xe = r->ws_line, *ya = xe + 2 * C, *yb = ya + 2 * C, *xc = yb + 2 * C, *yc = xc + C;
    kelp_ivp_piece *row = out->pcs + out->n;
    const bool strict = r->strict_range;
    double pt[2];
    for (uint32_t s = 0; s < T1; s += C) {
        uint32_t nt = T1 - s; /* at least 1: s < T1 */
        if (nt > C) nt = C;
        bool wide = false; /* some tile of the chunk spans three points or more of variable 1 */
        for (uint32_t t = 0; t < nt; t++) {
            const int32_t a1 = (int32_t)(s + t) * e1, h1 = a1 + e1 - 1 < n1 ? a1 + e1 - 1 : n1 - 1;
            xe[2 * t] = ((double)(uint32_t)a1 * v1->delta) + v1->low;
            xe[2 * t + 1] = ((double)(uint32_t)h1 * v1->delta) + v1->low;
            xc[t] = ((double)(uint32_t)((a1 + h1) / 2) * v1->delta) + v1->low;
            wide = wide || h1 - a1 >= 2;
        }
        for (uint32_t r0 = 0; r0 < T0; r0++) {
            const int32_t a0 = (int32_t)r0 * e0, h0 = a0 + e0 - 1 < n0 ? a0 + e0 - 1 : n0 - 1, c0 = (a0 + h0) / 2;
            pt[1] = 0.0;
            pt[0] = ((double)(uint32_t)a0 * v0->delta) + v0->low;
            r->aof_line(pt, 1, xe, 2 * nt, ya, r->aof_user);
            if (h0 != a0) {
                pt[0] = ((double)(uint32_t)h0 * v0->delta) + v0->low;
                r->aof_line(pt, 1, xe, 2 * nt, yb, r->aof_user);
            }
            const bool wrow = h0 - a0 >= 2;
            if (wrow || wide) {
                pt[0] = ((double)(uint32_t)c0 * v0->delta) + v0->low;
                r->aof_line(pt, 1, xc, nt, yc, r->aof_user);
            }
            const int32_t b[4] = {a0, h0, (int32_t)s * e1, e1};
            fit_row(strict, row + (size_t)r0 * T1 + s, nt, b, n1, ya, h0 != a0 ? yb : ya, wrow, yc);
        }
    }
    out->n += (size_t)T0 * T1;
    return 0;
}

/* The fit alone (no score): pieces whose score nobody reads. */
/* one out-of-line fit per dimension count: each inlines regress_n with its own locals, and
 * only the one called is on the stack (inlined together they summed to 400 B on Cortex-M4) */
static KELP_NOINLINE void fit1(const kelp_ivp_reflector *r, kelp_ivp_piece *p)
{
    (void)regress_n(r, p, 1, false);
}

static KELP_NOINLINE void fit3(const kelp_ivp_reflector *r, kelp_ivp_piece *p)
{
    (void)regress_n(r, p, 3, false);
}

static KELP_NOINLINE void fitn(const kelp_ivp_reflector *r, kelp_ivp_piece *p)
{
    (void)regress_n(r, p, r->dom.dim, false);
}

static void fit(const kelp_ivp_reflector *r, kelp_ivp_piece *p)
{
    switch (r->dom.dim) {
    case 1: fit1(r, p); break;
    case 2: fit2(r, p); break;
    case 3: fit3(r, p); break;
    default: fitn(r, p); break;
    }
}

/* ------------------------------------------------------------------ heap of (key, piece) */

static void heap_up(kelp_ivp_pq_entry *h, size_t i)
{
    while (i > 0) {
        size_t pa = (i - 1) / 2;
        if (!(h[i].key > h[pa].key))
            break;
        kelp_ivp_pq_entry t = h[i];
        h[i] = h[pa];
        h[pa] = t;
        i = pa;
    }
}

static void heap_down(kelp_ivp_pq_entry *h, size_t n, size_t i)
{
    for (;;) {
        size_t l = 2 * i + 1, m = i;
        if (l < n && h[l].key > h[m].key)
            m = l;
        if (l + 1 < n && h[l + 1].key > h[m].key)
            m = l + 1;
        if (m == i)
            return;
        kelp_ivp_pq_entry t = h[i];
        h[i] = h[m];
        h[m] = t;
        i = m;
    }
}

static void heapify(kelp_ivp_pq_entry *h, size_t n)
{
    for (size_t i = n / 2; i-- > 0;)
        heap_down(h, n, i);
}

/* Split p along its longest edge: p keeps the first half, q gets the rest. false if p is a point. */
static bool split(unsigned dim, kelp_ivp_piece *p, kelp_ivp_piece *q)
{
    unsigned best = dim;
    int32_t len = 1;
    for (unsigned d = 0; d < dim; d++) {
        int32_t l = p->hi[d] - p->lo[d] + 1;
        if (l > len) {
            len = l;
            best = d;
        }
    }
    if (best == dim)
        return false;
    *q = *p;
    int32_t first = (len + 1) / 2;
    p->hi[best] = p->lo[best] + first - 1;
    q->lo[best] = p->hi[best] + 1;
    return true;
}

static bool is_point(unsigned dim, const kelp_ivp_piece *p)
{
    for (unsigned d = 0; d < dim; d++)
        if (p->lo[d] != p->hi[d])
            return false;
    return true;
}

/* ------------------------------------------------------------------ create */

static int add_box(kelp_ivp_func *f, const int32_t *lo, const int32_t *hi)
{
    if (f->n >= f->cap)
        return KELP_ERR_NOSPACE;
    kelp_ivp_piece *p = &f->pcs[f->n++];
    memset(p, 0, sizeof *p);
    memcpy(p->lo, lo, sizeof(int32_t) * f->dom.dim);
    memcpy(p->hi, hi, sizeof(int32_t) * f->dom.dim);
    return 0;
}

/* Tile [lo,hi] with edge-sized boxes from its low corner (last variable fastest). */
static int tile(kelp_ivp_func *f, const int32_t *lo, const int32_t *hi, const uint32_t *edge)
{
    unsigned dim = f->dom.dim;
    int32_t a[D], b[D], cur[D];
    memcpy(cur, lo, sizeof(int32_t) * dim);
    for (;;) {
        for (unsigned d = 0; d < dim; d++) {
            a[d] = cur[d];
            b[d] = cur[d] + (int32_t)edge[d] - 1;
            if (b[d] > hi[d])
                b[d] = hi[d];
        }
        int rc = add_box(f, a, b);
        if (rc)
            return rc;
        int d = (int)dim - 1;
        for (; d >= 0; d--) {
            cur[d] += (int32_t)edge[d];
            if (cur[d] <= hi[d])
                break;
            cur[d] = lo[d];
        }
        if (d < 0)
            return 0;
    }
}

static bool overlaps(unsigned dim, const kelp_ivp_piece *p, const int32_t *lo, const int32_t *hi)
{
    for (unsigned d = 0; d < dim; d++)
        if (p->hi[d] < lo[d] || p->lo[d] > hi[d])
            return false;
    return true;
}

/* Directed refinement of region k (out of line, as the two stages after it: each stage's
 * piece copies are on the stack only while it runs) */
static KELP_NOINLINE int refine_region(const kelp_ivp_reflector *r, kelp_ivp_func *out, kelp_ivp_pq_entry *work, unsigned k)
{
    unsigned dim = r->dom.dim;
    int rc;
    const int32_t *rlo = r->refine_lo[k], *rhi = r->refine_hi[k];
    size_t n0 = out->n;
    for (size_t i = 0; i < n0; i++) {
        kelp_ivp_piece *p = &out->pcs[i];
        if (!overlaps(dim, p, rlo, rhi))
            continue;
        kelp_ivp_piece rest = *p;
        bool first = true;
        for (unsigned d = 0; d < dim; d++) {
            for (int side = 0; side < 2; side++) {
                bool above = side == 0 && rest.hi[d] > rhi[d], below = side == 1 && rest.lo[d] < rlo[d];
                if (!above && !below)
                    continue;
                size_t at;
                if (first) {
                    at = i; /* p itself: rest holds its copy */
                } else {
                    if (out->n >= out->cap)
                        return KELP_ERR_NOSPACE;
                    at = out->n++;
                }
                /* the fragment cut off rest, built in place (no second piece on the stack) */
                kelp_ivp_piece *dst = &out->pcs[at];
                *dst = rest;
                if (above) {
                    dst->lo[d] = rhi[d] + 1;
                    rest.hi[d] = rhi[d];
                } else {
                    dst->hi[d] = rlo[d] - 1;
                    rest.lo[d] = rlo[d];
                }
                work[at].key = regress(r, dst);
                first = false;
            }
        }
        if (first)
            p->lo[0] = -1; /* wholly inside the region: dead, removed below */
    }
    size_t w = 0;
    for (size_t i = 0; i < out->n; i++) {
        if (out->pcs[i].lo[0] < 0)
            continue;
        out->pcs[w] = out->pcs[i];
        work[w] = work[i];
        w++;
    }
    out->n = w;
    size_t t0 = out->n;
    if ((rc = tile(out, rlo, rhi, r->refine_piece[k])))
        return rc;
    for (size_t i = t0; i < out->n; i++)
        work[i].key = regress(r, &out->pcs[i]);
    return 0;
}

/* Smart refinement: split the worst-fitting pieces, up to sa more (or smart_percent) */
static KELP_NOINLINE int smart_refine(const kelp_ivp_reflector *r, kelp_ivp_func *out, kelp_ivp_pq_entry *work, int sa,
                                      double sthresh)
{
    unsigned dim = r->dom.dim;
    size_t extra = sa > 0 ? (size_t)sa : 0;
    if (r->smart_percent > 0) {
        size_t pe = out->n * (size_t)r->smart_percent / 100u;
        if (pe > extra)
            extra = pe;
    }
    if (extra > 0) {
        size_t hn = out->n;
        for (size_t i = 0; i < hn; i++)
            work[i].piece = (uint32_t)i;
        heapify(work, hn);
        size_t made = 0;
        while (made < extra && hn > 0) {
            if (work[0].key < sthresh)
                break;
            uint32_t pi = work[0].piece;
            kelp_ivp_piece q;
            if (!split(dim, &out->pcs[pi], &q)) {
                work[0].key = -1.0; /* a single point cannot be split; sink it */
                heap_down(work, hn, 0);
                if (work[0].key < 0)
                    break;
                continue;
            }
            if (out->n >= out->cap)
                return KELP_ERR_NOSPACE;
            size_t qi = out->n++;
            out->pcs[qi] = q;
            work[0].key = regress(r, &out->pcs[pi]);
            heap_down(work, hn, 0);
            work[hn].key = regress(r, &out->pcs[qi]);
            work[hn].piece = (uint32_t)qi;
            heap_up(work, hn);
            hn++;
            made++;
        }
    }
    return 0;
}

/* Auto-peak: split the pieces holding the maximum until it is a point */
static KELP_NOINLINE int auto_peak(const kelp_ivp_reflector *r, kelp_ivp_func *out, kelp_ivp_pq_entry *work)
{
    unsigned dim = r->dom.dim;
    size_t hn = out->n;
    for (size_t i = 0; i < hn; i++) {
        work[i].key = kelp_ivp_piece_max(&out->pcs[i], dim);
        work[i].piece = (uint32_t)i;
    }
    heapify(work, hn);
    size_t made = 0;
    for (;;) {
        uint32_t pi = work[0].piece;
        if (is_point(dim, &out->pcs[pi]))
            break;
        if (r->auto_peak_max_pcs > 0 && made >= (size_t)r->auto_peak_max_pcs)
            break;
        kelp_ivp_piece q;
        if (!split(dim, &out->pcs[pi], &q))
            break;
        if (out->n >= out->cap)
            return KELP_ERR_NOSPACE;
        size_t qi = out->n++;
        out->pcs[qi] = q;
        fit(r, &out->pcs[pi]);
        fit(r, &out->pcs[qi]);
        work[0].key = kelp_ivp_piece_max(&out->pcs[pi], dim);
        heap_down(work, hn, 0);
        work[hn].key = kelp_ivp_piece_max(&out->pcs[qi], dim);
        work[hn].piece = (uint32_t)qi;
        heap_up(work, hn);
        hn++;
        made++;
    }
    return 0;
}

int kelp_ivp_reflector_create(kelp_ivp_reflector *r, int uniform_amount, int smart_amount, double smart_thresh,
                              kelp_ivp_piece *store, size_t cap, kelp_ivp_pq_entry *work, size_t work_len,
                              kelp_ivp_func *out)
{
    if (!r->ok)
        return KELP_ERR_STATE;
    if (r->refine_pending) {
        fatal(r, KELP_ERR_STATE, "refine_region", "refine_region without refine_piece");
        return KELP_ERR_STATE;
    }
    unsigned dim = r->dom.dim;
    int rc = kelp_ivp_func_init(out, &r->dom, store, cap);
    if (rc)
        return rc;
    if (!work || work_len < cap)
        return KELP_ERR_NOSPACE;
    int amount = uniform_amount >= 1 ? uniform_amount : r->uniform_amount;
    int sa = smart_amount >= 0 ? smart_amount : r->smart_amount;
    double sthresh = smart_amount >= 0 ? smart_thresh : r->smart_thresh;

    /* 1. uniform */
    uint32_t edge[D] = {0};
    choose_uniform(r, amount, edge);
    int32_t lo[D] = {0}, hi[D] = {0};
    for (unsigned d = 0; d < dim; d++) {
        lo[d] = 0;
        hi[d] = (int32_t)r->dom.var[d].points - 1;
    }
    /* scores are read only by smart refinement */
    bool scored = sa > 0 || r->smart_percent > 0;
    if (r->aof_line && dim == 2 && !scored) {
        if ((rc = uniform2_line(r, out, edge)))
            return rc;
    } else {
        if ((rc = tile(out, lo, hi, edge)))
            return rc;
        for (size_t i = 0; i < out->n; i++) {
            if (scored)
                work[i].key = regress(r, &out->pcs[i]);
            else
                fit(r, &out->pcs[i]);
        }
    }

    /* 2. directed refinement */
    for (unsigned k = 0; k < r->nrefine; k++)
        if ((rc = refine_region(r, out, work, k)))
            return rc;

    /* 3. smart refinement */
    if ((rc = smart_refine(r, out, work, sa, sthresh)))
        return rc;

    /* 4. auto-peak */
    if (r->auto_peak && (rc = auto_peak(r, out, work)))
        return rc;
    return (int)out->n;
}
