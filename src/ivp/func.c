/* kelp IvP: piecewise-linear IvP functions (PDMap). Arithmetic order mirrors MOOS-IvP's IvPBox
 * (cst first, then dimensions in order) so that values and ties agree bit for bit. */
#include <string.h>
#include <math.h>
#include "ivp_int.h"

int kelp_ivp_func_init(kelp_ivp_func *f, const kelp_ivp_domain *dom, kelp_ivp_piece *store, size_t cap)
{
    if (!f || !dom || (!store && cap))
        return KELP_ERR_ARG;
    memset(f, 0, sizeof *f);
    f->dom = *dom;
    f->pcs = store;
    f->cap = cap;
    f->pwt = 100.0;
    return 0;
}

int kelp_ivp_func_add(kelp_ivp_func *f, const int32_t *lo, const int32_t *hi, const double *slope, double cst)
{
    if (f->n >= f->cap)
        return KELP_ERR_NOSPACE;
    kelp_ivp_piece *p = &f->pcs[f->n];
    memset(p, 0, sizeof *p);
    for (unsigned d = 0; d < f->dom.dim; d++) {
        if (lo[d] < 0 || hi[d] < lo[d] || (uint32_t)hi[d] >= f->dom.var[d].points)
            return KELP_ERR_RANGE;
        if (!isfinite(slope[d]))
            return KELP_ERR_RANGE;
        p->lo[d] = lo[d];
        p->hi[d] = hi[d];
        p->slope[d] = slope[d];
    }
    if (!isfinite(cst))
        return KELP_ERR_RANGE;
    p->cst = cst;
    f->n++;
    return 0;
}

double kelp_ivp_piece_max(const kelp_ivp_piece *p, unsigned dim)
{
    double v = p->cst;
    for (unsigned d = 0; d < dim; d++)
        v += p->slope[d] < 0 ? p->slope[d] * (double)p->lo[d] : p->slope[d] * (double)p->hi[d];
    return v;
}

double kelp_ivp_piece_min(const kelp_ivp_piece *p, unsigned dim)
{
    double v = p->cst;
    for (unsigned d = 0; d < dim; d++)
        v += p->slope[d] < 0 ? p->slope[d] * (double)p->hi[d] : p->slope[d] * (double)p->lo[d];
    return v;
}

int kelp_ivp_func_eval(const kelp_ivp_func *f, const uint32_t *ix, double *out)
{
    unsigned dim = f->dom.dim;
    for (unsigned d = 0; d < dim; d++)
        if (ix[d] >= f->dom.var[d].points)
            return KELP_ERR_RANGE;
    for (size_t i = 0; i < f->n; i++) {
        const kelp_ivp_piece *p = &f->pcs[i];
        unsigned d;
        for (d = 0; d < dim; d++)
            if ((int32_t)ix[d] < p->lo[d] || (int32_t)ix[d] > p->hi[d])
                break;
        if (d == dim) {
            double v = p->cst;
            for (d = 0; d < dim; d++)
                v += p->slope[d] * (double)ix[d];
            *out = v;
            return 0;
        }
    }
    return KELP_ERR_NOTFOUND;
}

/* min and max over pieces 1.. (kelp_ivp_piece_min / _max in one pass, inline); inlined with a
 * constant dim for 2-D functions (the same arithmetic) */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void range_rest(const kelp_ivp_func *f, unsigned dim, double *lo, double *hi)
{
    for (size_t i = 1; i < f->n; i++) {
        const kelp_ivp_piece *p = &f->pcs[i];
        double a = p->cst, b = p->cst;
        for (unsigned d = 0; d < dim; d++) {
            double s = p->slope[d], l = s * (double)p->lo[d], h = s * (double)p->hi[d];
            a += s < 0 ? h : l;
            b += s < 0 ? l : h;
        }
        if (a < *lo)
            *lo = a;
        if (b > *hi)
            *hi = b;
    }
}

int kelp_ivp_func_range(const kelp_ivp_func *f, double *min, double *max)
{
    if (f->n == 0)
        return KELP_ERR_EMPTY;
    unsigned dim = f->dom.dim;
    double lo = kelp_ivp_piece_min(&f->pcs[0], dim);
    double hi = kelp_ivp_piece_max(&f->pcs[0], dim);
    if (dim == 2)
        range_rest(f, 2, &lo, &hi);
    else
        range_rest(f, dim, &lo, &hi);
    *min = lo;
    *max = hi;
    return 0;
}

int kelp_ivp_func_normalize(kelp_ivp_func *f, double base, double range)
{
    double lo, hi;
    int rc = kelp_ivp_func_range(f, &lo, &hi);
    if (rc)
        return rc;
    double er = hi - lo;
    if (er <= 0)
        return 0;
    double badj = base - lo;
    double radj = range / er;
    if (badj == 0 && radj == 1)
        return 0; /* already on [base, base + range]: every coefficient would stay as it is */
    for (size_t i = 0; i < f->n; i++) {
        kelp_ivp_piece *p = &f->pcs[i];
        p->cst += badj;
        for (unsigned d = 0; d < f->dom.dim; d++)
            p->slope[d] *= radj;
        p->cst *= radj;
    }
    return 0;
}

void kelp_ivp_func_scale(kelp_ivp_func *f, double w)
{
    for (size_t i = 0; i < f->n; i++) {
        kelp_ivp_piece *p = &f->pcs[i];
        for (unsigned d = 0; d < f->dom.dim; d++)
            p->slope[d] *= w;
        p->cst *= w;
    }
}

int kelp_ivp_func_align(kelp_ivp_func *f, const kelp_ivp_domain *big)
{
    int map[KELP_IVP_MAX_DIM] = {0};
    for (unsigned d = 0; d < f->dom.dim; d++) {
        int j = kelp_ivp_domain_index(big, f->dom.var[d].name);
        if (j < 0)
            return KELP_ERR_NOTFOUND;
        if (big->var[j].low != f->dom.var[d].low || big->var[j].high != f->dom.var[d].high ||
            big->var[j].points != f->dom.var[d].points)
            return KELP_ERR_RANGE;
        map[d] = j;
    }
    for (size_t i = 0; i < f->n; i++) {
        kelp_ivp_piece *p = &f->pcs[i];
        kelp_ivp_piece q;
        memset(&q, 0, sizeof q);
        for (unsigned e = 0; e < big->dim; e++)
            q.hi[e] = (int32_t)big->var[e].points - 1;
        for (unsigned d = 0; d < f->dom.dim; d++) {
            q.lo[map[d]] = p->lo[d];
            q.hi[map[d]] = p->hi[d];
            q.slope[map[d]] = p->slope[d];
        }
        q.cst = p->cst;
        *p = q;
    }
    f->dom = *big;
    return 0;
}

/* Every grid point covered exactly once, told without visiting the points: each piece lies in
 * the domain, no two pieces share a point, and their volumes add up to the domain's. Disjoint
 * boxes inside the domain whose volumes sum to its volume cover it. */
static bool pieces_overlap(const kelp_ivp_piece *a, const kelp_ivp_piece *b, unsigned dim)
{
    for (unsigned d = 0; d < dim; d++)
        if (a->hi[d] < b->lo[d] || b->hi[d] < a->lo[d])
            return false;
    return true;
}

bool kelp_ivp_func_tiles(const kelp_ivp_func *f)
{
    if (f->dom.dim == 0)
        return false;
    uint64_t total = 1, sum = 0;
    for (unsigned d = 0; d < f->dom.dim; d++) {
        uint64_t pts = f->dom.var[d].points;
        if (pts == 0 || total > UINT64_MAX / pts)
            return false;
        total *= pts;
    }
    for (size_t i = 0; i < f->n; i++) {
        const kelp_ivp_piece *p = &f->pcs[i];
        uint64_t vol = 1;
        for (unsigned d = 0; d < f->dom.dim; d++) {
            if (p->lo[d] < 0 || p->lo[d] > p->hi[d] || (uint64_t)p->hi[d] >= f->dom.var[d].points)
                return false;
            vol *= (uint64_t)(p->hi[d] - p->lo[d]) + 1; /* within total: the piece is in the domain */
        }
        sum += vol;
        if (sum > total)
            return false;
    }
    if (sum != total)
        return false;
    for (size_t i = 0; i < f->n; i++)
        for (size_t j = i + 1; j < f->n; j++)
            if (pieces_overlap(&f->pcs[i], &f->pcs[j], f->dom.dim))
                return false;
    return true;
}
