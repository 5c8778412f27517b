/* kelp IvP: the IvP solver (branch and bound over pieces; seed 004 section 6.1.5).
 *
 * Decisions are bit-identical to MOOS-IvP's IvPProblem::solve (as used by its helm):
 *  - a function is normalised to [0,100] only when its range exceeds 100, then every
 *    coefficient is multiplied by the priority weight (Problem::addOF);
 *  - depth-first search: the first function's pieces in stored order, at each deeper level the
 *    next function's pieces that intersect the node box, in stored order (MOOS-IvP functions
 *    built by ZAIC/Coupler keep a one-cell grid, so its grid returns stored order);
 *  - node coefficients are accumulated level by level (node[l+1] = node[l] + piece), and a
 *    box's max takes per dimension the high end when the summed slope is >= 0, else the low end;
 *  - a leaf replaces the incumbent only when strictly greater, so the first optimum wins.
 * Pruning only removes nodes whose upper bound is <= the incumbent, which can never hold a
 * strictly better leaf, so a tighter bound changes speed and never the answer. kelp bounds a
 * node by its own max plus, for each remaining function, the best piece max over the node box
 * read from a small per-function grid of cell maxima (MOOS-IvP uses each function's global max). */
#include <string.h>
#include <math.h>
#include "ivp_int.h"

#define D KELP_IVP_MAX_DIM
#define GRID_CELLS 8 /* bound grid cells per variable (at most) */

typedef struct spiece {
    int32_t lo[D], hi[D];
    double s[D];
    double c;
} spiece;

typedef struct sfunc {
    spiece *p;
    uint32_t n;
    double *cellmax;          /* grid of per-cell maxima */
    int32_t cellw[D];         /* points per cell per variable */
    uint32_t ncell[D];
    uint32_t cstride[D];
} sfunc;

typedef struct snode {
    int32_t lo[D], hi[D];
    double s[D];
    double c;
    uint32_t next;            /* next piece index of the following level to try */
} snode;

void kelp_ivp_problem_init(kelp_ivp_problem *p, const kelp_ivp_domain *dom)
{
    memset(p, 0, sizeof *p);
    p->dom = *dom;
}

int kelp_ivp_problem_add(kelp_ivp_problem *p, const kelp_ivp_func *f)
{
    if (!f)
        return KELP_ERR_ARG;
    if (!(f->pwt > 0))
        return 0; /* Problem::addOF ignores non-positive weights */
    for (unsigned d = 0; d < f->dom.dim; d++) {
        int j = kelp_ivp_domain_index(&p->dom, f->dom.var[d].name);
        if (j < 0)
            return ivp_fail(&p->err, KELP_ERR_NOTFOUND, "solver: function variable not in problem domain:",
                            f->dom.var[d].name, strlen(f->dom.var[d].name));
        const kelp_ivp_var *a = &p->dom.var[j], *b = &f->dom.var[d];
        if (a->low != b->low || a->high != b->high || a->points != b->points)
            return ivp_fail(&p->err, KELP_ERR_RANGE, "solver: variable extents differ from the problem domain:",
                            b->name, strlen(b->name));
    }
    if (p->nf >= KELP_IVP_MAX_FUNCS)
        return ivp_fail(&p->err, KELP_ERR_NOSPACE, "solver: too many functions", NULL, 0);
    p->f[p->nf++] = f;
    return 0;
}

static size_t align8(size_t n)
{
    return (n + 7u) & ~(size_t)7u;
}

static void grid_shape(const kelp_ivp_domain *dom, sfunc *sf)
{
    for (unsigned d = 0; d < dom->dim; d++) {
        uint32_t pts = dom->var[d].points;
        uint32_t w = (pts + GRID_CELLS - 1) / GRID_CELLS;
        if (w < 1)
            w = 1;
        sf->cellw[d] = (int32_t)w;
        sf->ncell[d] = (pts + w - 1) / w;
    }
    uint32_t st = 1;
    for (unsigned d = 0; d < dom->dim; d++) {
        sf->cstride[d] = st;
        st *= sf->ncell[d];
    }
}

static size_t grid_len(const kelp_ivp_domain *dom)
{
    sfunc sf;
    grid_shape(dom, &sf);
    size_t n = 1;
    for (unsigned d = 0; d < dom->dim; d++)
        n *= sf.ncell[d];
    return n;
}

size_t kelp_ivp_solve_work_size(const kelp_ivp_problem *p)
{
    size_t sz = align8(sizeof(sfunc) * (p->nf + 1));
    sz += align8(sizeof(snode) * (p->nf + 1));
    sz += align8(sizeof(double) * (p->nf + 2));
    size_t g = grid_len(&p->dom);
    for (unsigned i = 0; i < p->nf; i++) {
        sz += align8(sizeof(spiece) * p->f[i]->n);
        sz += align8(sizeof(double) * g);
    }
    return sz;
}

static inline double box_max(const int32_t *lo, const int32_t *hi, const double *s, double c, unsigned dim)
{
    double v = c;
    for (unsigned d = 0; d < dim; d++)
        v += s[d] < 0 ? s[d] * (double)lo[d] : s[d] * (double)hi[d];
    return v;
}

/* Max of function sf over the box [lo,hi] (an upper bound: cell maxima of the touched cells). */
static double grid_bound(const sfunc *sf, const int32_t *lo, const int32_t *hi, unsigned dim)
{
    uint32_t a[D], b[D], k[D];
    size_t base = 0;
    for (unsigned d = 0; d < dim; d++) {
        a[d] = (uint32_t)lo[d] / (uint32_t)sf->cellw[d];
        b[d] = (uint32_t)hi[d] / (uint32_t)sf->cellw[d];
        k[d] = a[d];
        base += a[d] * sf->cstride[d];
    }
    double best = -INFINITY;
    for (;;) {
        size_t ix = 0;
        for (unsigned d = 0; d < dim; d++)
            ix += k[d] * sf->cstride[d];
        double v = sf->cellmax[ix];
        if (v > best)
            best = v;
        unsigned d = 0;
        while (d < dim) {
            if (k[d] < b[d]) {
                k[d]++;
                break;
            }
            k[d] = a[d];
            d++;
        }
        if (d == dim)
            break;
    }
    (void)base;
    return best;
}

int kelp_ivp_solve(kelp_ivp_problem *p, void *work, size_t work_size, kelp_ivp_result *res)
{
    if (!p || !res)
        return KELP_ERR_ARG;
    memset(res, 0, sizeof *res);
    unsigned k = p->nf, dim = p->dom.dim;
    if (k == 0)
        return ivp_fail(&p->err, KELP_ERR_EMPTY, "solver: no functions with positive weight", NULL, 0);
    if (dim == 0)
        return ivp_fail(&p->err, KELP_ERR_ARG, "solver: null domain", NULL, 0);
    size_t need = kelp_ivp_solve_work_size(p);
    if (!work || work_size < need)
        return ivp_fail(&p->err, KELP_ERR_NOSPACE, "solver: work storage too small", NULL, 0);

    unsigned char *w = (unsigned char *)work;
    sfunc *sf = (sfunc *)(void *)w;
    w += align8(sizeof(sfunc) * (k + 1));
    snode *node = (snode *)(void *)w;
    w += align8(sizeof(snode) * (k + 1));
    double *suffix = (double *)(void *)w;
    w += align8(sizeof(double) * (k + 2));
    size_t glen = grid_len(&p->dom);

    /* Prepare: normalise (range > 100), weight, align to the problem's variable order. */
    for (unsigned i = 0; i < k; i++) {
        const kelp_ivp_func *f = p->f[i];
        sfunc *s = &sf[i];
        s->p = (spiece *)(void *)w;
        w += align8(sizeof(spiece) * f->n);
        s->cellmax = (double *)(void *)w;
        w += align8(sizeof(double) * glen);
        s->n = (uint32_t)f->n;
        grid_shape(&p->dom, s);
        int map[D];
        for (unsigned d = 0; d < f->dom.dim; d++)
            map[d] = kelp_ivp_domain_index(&p->dom, f->dom.var[d].name);
        double lo = 0, hi = 0;
        bool norm = false;
        if (f->n && kelp_ivp_func_range(f, &lo, &hi) == 0 && hi - lo > 100)
            norm = true;
        double badj = 0.0 - lo, radj = norm ? 100.0 / (hi - lo) : 1.0, pwt = f->pwt;
        for (size_t j = 0; j < f->n; j++) {
            const kelp_ivp_piece *q = &f->pcs[j];
            spiece *t = &s->p[j];
            for (unsigned e = 0; e < dim; e++) {
                t->lo[e] = 0;
                t->hi[e] = (int32_t)p->dom.var[e].points - 1;
                t->s[e] = 0.0;
            }
            double c = q->cst;
            if (norm)
                c = (c + badj) * radj;
            t->c = c * pwt;
            for (unsigned d = 0; d < f->dom.dim; d++) {
                double sl = q->slope[d];
                if (norm)
                    sl *= radj;
                t->lo[map[d]] = q->lo[d];
                t->hi[map[d]] = q->hi[d];
                t->s[map[d]] = sl * pwt;
            }
        }
        /* cell maxima: each piece's max over its intersection with each cell it touches */
        for (size_t g = 0; g < glen; g++)
            s->cellmax[g] = -INFINITY;
        for (uint32_t j = 0; j < s->n; j++) {
            const spiece *t = &s->p[j];
            uint32_t a[D], b[D], c[D];
            for (unsigned d = 0; d < dim; d++) {
                a[d] = (uint32_t)t->lo[d] / (uint32_t)s->cellw[d];
                b[d] = (uint32_t)t->hi[d] / (uint32_t)s->cellw[d];
                c[d] = a[d];
            }
            for (;;) {
                int32_t clo[D], chi[D];
                size_t ix = 0;
                for (unsigned d = 0; d < dim; d++) {
                    int32_t cl = (int32_t)c[d] * s->cellw[d], ch = cl + s->cellw[d] - 1;
                    clo[d] = t->lo[d] > cl ? t->lo[d] : cl;
                    chi[d] = t->hi[d] < ch ? t->hi[d] : ch;
                    ix += c[d] * s->cstride[d];
                }
                double v = box_max(clo, chi, t->s, t->c, dim);
                if (v > s->cellmax[ix])
                    s->cellmax[ix] = v;
                unsigned d = 0;
                while (d < dim) {
                    if (c[d] < b[d]) {
                        c[d]++;
                        break;
                    }
                    c[d] = a[d];
                    d++;
                }
                if (d == dim)
                    break;
            }
        }
    }
    (void)suffix;

    /* Depth-first branch and bound. node[l] is the box after intersecting functions 0..l-1. */
    bool found = false;
    double best = 0;
    int32_t blo[D], bhi[D];
    double bs[D];
    unsigned long leaves = 0;
    for (unsigned e = 0; e < dim; e++) {
        node[0].lo[e] = 0;
        node[0].hi[e] = (int32_t)p->dom.var[e].points - 1;
        node[0].s[e] = 0;
    }
    node[0].c = 0;
    node[0].next = 0;
    unsigned l = 0;
    for (;;) {
        snode *cur = &node[l];
        const sfunc *F = &sf[l];
        if (cur->next >= F->n) {
            if (l == 0)
                break;
            l--;
            continue;
        }
        const spiece *q = &F->p[cur->next++];
        snode *nx = &node[l + 1];
        unsigned e;
        for (e = 0; e < dim; e++) {
            int32_t a = cur->lo[e] > q->lo[e] ? cur->lo[e] : q->lo[e];
            int32_t b = cur->hi[e] < q->hi[e] ? cur->hi[e] : q->hi[e];
            if (a > b)
                break;
            nx->lo[e] = a;
            nx->hi[e] = b;
        }
        if (e < dim)
            continue;
        if (l == 0) {
            for (e = 0; e < dim; e++)
                nx->s[e] = q->s[e];
            nx->c = q->c;
        } else {
            for (e = 0; e < dim; e++)
                nx->s[e] = cur->s[e] + q->s[e];
            nx->c = cur->c + q->c;
        }
        double v = box_max(nx->lo, nx->hi, nx->s, nx->c, dim);
        if (l + 1 == k) {
            leaves++;
            if (!found || v > best) {
                found = true;
                best = v;
                memcpy(blo, nx->lo, sizeof blo);
                memcpy(bhi, nx->hi, sizeof bhi);
                memcpy(bs, nx->s, sizeof bs);
            }
            continue;
        }
        if (found) {
            double bound = v;
            for (unsigned i = l + 1; i < k; i++)
                bound += grid_bound(&sf[i], nx->lo, nx->hi, dim);
            if (!(bound > best))
                continue;
        }
        nx->next = 0;
        l++;
    }
    res->leaves = leaves;
    if (!found)
        return ivp_fail(&p->err, KELP_ERR_INFEASIBLE, "solver: no point is covered by every function", NULL, 0);
    for (unsigned e = 0; e < dim; e++) {
        uint32_t ix = (uint32_t)(bs[e] < 0 ? blo[e] : bhi[e]);
        res->ix[e] = ix;
        res->val[e] = kelp_ivp_domain_value(&p->dom, e, ix);
    }
    res->value = best;
    return 0;
}
