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
    double gmax;              /* max over all pieces */
    double *proj[D];          /* per variable: per cell, max over the slab of that cell */
    bool rel[D];              /* the function varies along this variable */
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

typedef struct gshape {
    int32_t cellw[D];
    uint32_t ncell[D];
    size_t total;
} gshape;

static void grid_shape(const kelp_ivp_domain *dom, gshape *g)
{
    g->total = 0;
    for (unsigned d = 0; d < dom->dim; d++) {
        uint32_t pts = dom->var[d].points;
        uint32_t w = (pts + GRID_CELLS - 1) / GRID_CELLS;
        if (w < 1)
            w = 1;
        g->cellw[d] = (int32_t)w;
        g->ncell[d] = (pts + w - 1) / w;
        g->total += g->ncell[d];
    }
}

size_t kelp_ivp_solve_work_size(const kelp_ivp_problem *p)
{
    size_t sz = align8(sizeof(sfunc) * (p->nf + 1));
    sz += align8(sizeof(snode) * (p->nf + 1));
    sz += align8(sizeof(double) * (p->nf + 2));
    gshape g;
    grid_shape(&p->dom, &g);
    for (unsigned i = 0; i < p->nf; i++) {
        sz += align8(sizeof(spiece) * p->f[i]->n);
        sz += align8(sizeof(double) * g.total);
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

/* Upper bound of function sf over the box [lo,hi]: per varying variable, the best cell of the
 * projection over the box's range; the smallest of those. */
static double proj_bound(const sfunc *sf, const gshape *g, const int32_t *lo, const int32_t *hi, unsigned dim)
{
    double b = sf->gmax;
    for (unsigned d = 0; d < dim; d++) {
        if (!sf->rel[d])
            continue;
        uint32_t a = (uint32_t)lo[d] / (uint32_t)g->cellw[d], e = (uint32_t)hi[d] / (uint32_t)g->cellw[d];
        const double *q = sf->proj[d];
        double m = q[a];
        for (uint32_t c = a + 1; c <= e; c++)
            if (q[c] > m)
                m = q[c];
        if (m < b)
            b = m;
    }
    return b;
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
    gshape gs;
    grid_shape(&p->dom, &gs);

    /* Prepare: normalise (range > 100), weight, align to the problem's variable order. */
    for (unsigned i = 0; i < k; i++) {
        const kelp_ivp_func *f = p->f[i];
        sfunc *s = &sf[i];
        s->p = (spiece *)(void *)w;
        w += align8(sizeof(spiece) * f->n);
        double *proj = (double *)(void *)w;
        w += align8(sizeof(double) * gs.total);
        s->n = (uint32_t)f->n;
        for (unsigned e = 0; e < dim; e++) {
            s->proj[e] = proj;
            proj += gs.ncell[e];
            s->rel[e] = false;
        }
        int map[D] = {0};
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
        /* projections: per variable and cell, the best piece max over the piece's part in that slab */
        s->gmax = -INFINITY;
        for (unsigned e = 0; e < dim; e++) {
            for (uint32_t c = 0; c < gs.ncell[e]; c++)
                s->proj[e][c] = -INFINITY;
        }
        for (size_t j = 0; j < f->n; j++) {
            const spiece *t = &s->p[j];
            double m = box_max(t->lo, t->hi, t->s, t->c, dim);
            if (m > s->gmax)
                s->gmax = m;
            for (unsigned e = 0; e < dim; e++)
                if (t->s[e] != 0 || t->lo[e] != 0 || t->hi[e] != (int32_t)p->dom.var[e].points - 1)
                    s->rel[e] = true;
        }
        for (size_t j = 0; j < f->n; j++) {
            const spiece *t = &s->p[j];
            for (unsigned e = 0; e < dim; e++) {
                if (!s->rel[e])
                    continue;
                uint32_t a = (uint32_t)t->lo[e] / (uint32_t)gs.cellw[e], b = (uint32_t)t->hi[e] / (uint32_t)gs.cellw[e];
                int32_t clo[D], chi[D];
                memcpy(clo, t->lo, sizeof clo);
                memcpy(chi, t->hi, sizeof chi);
                for (uint32_t c = a; c <= b; c++) {
                    int32_t cl = (int32_t)c * gs.cellw[e], ch = cl + gs.cellw[e] - 1;
                    clo[e] = t->lo[e] > cl ? t->lo[e] : cl;
                    chi[e] = t->hi[e] < ch ? t->hi[e] : ch;
                    double v = box_max(clo, chi, t->s, t->c, dim);
                    if (v > s->proj[e][c])
                        s->proj[e][c] = v;
                }
            }
        }
    }
    /* suffix[i] = sum of the global maxima of functions i..k-1 (a cheap first test) */
    suffix[k] = 0;
    for (unsigned i = k; i-- > 0;)
        suffix[i] = suffix[i + 1] + sf[i].gmax;

    /* A lower bound on the optimum from the objective at each function's own best point. It only
     * prunes nodes whose bound is strictly below it (with a margin for rounding), so the first
     * optimum in depth-first order is still found and still wins. */
    double floor_v = -INFINITY;
    for (unsigned i = 0; i < k; i++) {
        const sfunc *s = &sf[i];
        const spiece *bp = NULL;
        for (uint32_t j = 0; j < s->n; j++)
            if (box_max(s->p[j].lo, s->p[j].hi, s->p[j].s, s->p[j].c, dim) == s->gmax) {
                bp = &s->p[j];
                break;
            }
        if (!bp)
            continue;
        int32_t x[D];
        for (unsigned e = 0; e < dim; e++)
            x[e] = bp->s[e] < 0 ? bp->lo[e] : bp->hi[e];
        double tot = 0;
        bool covered = true;
        for (unsigned j = 0; j < k && covered; j++) {
            const sfunc *t = &sf[j];
            covered = false;
            for (uint32_t m = 0; m < t->n; m++) {
                const spiece *q = &t->p[m];
                unsigned e;
                for (e = 0; e < dim; e++)
                    if (x[e] < q->lo[e] || x[e] > q->hi[e])
                        break;
                if (e == dim) {
                    double v = q->c;
                    for (e = 0; e < dim; e++)
                        v += q->s[e] * (double)x[e];
                    tot += v;
                    covered = true;
                    break;
                }
            }
        }
        if (covered && tot > floor_v)
            floor_v = tot;
    }
    if (isfinite(floor_v))
        floor_v -= 1e-9 * (fabs(floor_v) + 1.0);

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
            if (v < floor_v)
                continue;
            if (!found || v > best) {
                found = true;
                best = v;
                memcpy(blo, nx->lo, sizeof blo);
                memcpy(bhi, nx->hi, sizeof bhi);
                memcpy(bs, nx->s, sizeof bs);
            }
            continue;
        }
        {
            double tb = v + suffix[l + 1];
            if (tb < floor_v || (found && !(tb > best)))
                continue;
            double bound = v;
            unsigned i;
            for (i = l + 1; i < k; i++) {
                bound += proj_bound(&sf[i], &gs, nx->lo, nx->hi, dim);
                tb = bound + suffix[i + 1];
                if (tb < floor_v || (found && !(tb > best)))
                    break;
            }
            if (i < k)
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
