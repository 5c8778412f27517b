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
 *
 * Pruning only removes a node when no leaf below it can be strictly greater than the incumbent
 * (or than a value known to be reached), so a tighter bound changes speed, never the answer.
 * The comparisons keep a margin well above the rounding error of any leaf value or bound, so a
 * leaf that is better by rounding alone is never pruned either. A node is bounded by its own
 * max plus an upper bound on the remaining functions that is separable by variable:
 *     f_i(x) <= k_i + sum_d a_id(x_d)
 * with a_id sampled at every index. A function of one variable is its own upper envelope; a
 * coupled function (pieces that are the cross product of a course part and a speed part, as
 * the Coupler makes them) splits exactly into its two parts (k_i takes the rounding residual);
 * any other function uses the mean of its projections. Per level the rows are summed over the
 * remaining functions, so a node's bound costs one range maximum per variable (a sparse table).
 * An initial floor comes from the objective at the bound's own maximiser. */
#include <string.h>
#include <math.h>
#include "ivp_int.h"

#define D KELP_IVP_MAX_DIM

typedef struct spiece {
    int32_t lo[D], hi[D];
    double s[D];
    double c;
} spiece;

typedef struct sfunc {
    spiece *p;
    uint32_t n;
    double gmax;              /* max over all pieces */
    double mag;               /* max over pieces of |c| + sum |s_d| * (points_d - 1) */
    bool tiled;               /* the grid path: the pieces tile the grid (tiles_grid) ... */
    int32_t edge[D];          /* ... with this tile */
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
            return ivp_fail(&p->diag, KELP_ERR_NOTFOUND, "solver: function variable not in problem domain:",
                            f->dom.var[d].name, strlen(f->dom.var[d].name));
        const kelp_ivp_var *a = &p->dom.var[j], *b = &f->dom.var[d];
        if (a->low != b->low || a->high != b->high || a->points != b->points)
            return ivp_fail(&p->diag, KELP_ERR_RANGE, "solver: variable extents differ from the problem domain:",
                            b->name, strlen(b->name));
    }
    if (p->nf >= KELP_IVP_MAX_FUNCS)
        return ivp_fail(&p->diag, KELP_ERR_NOSPACE, "solver: too many functions", NULL, 0);
    p->f[p->nf++] = f;
    return 0;
}

static size_t align8(size_t n)
{
    return (n + 7u) & ~(size_t)7u;
}

/* Doubles for the bound rows: each function adds a row only for variables of its own domain
 * (it is constant along the others), one double per index. */
static size_t rows_len(const kelp_ivp_problem *p)
{
    size_t t = 0;
    for (unsigned i = 0; i < p->nf; i++)
        for (unsigned d = 0; d < p->f[i]->dom.dim; d++)
            t += p->f[i]->dom.var[d].points;
    return t;
}

static size_t max_pieces(const kelp_ivp_problem *p)
{
    size_t m = 1;
    for (unsigned i = 0; i < p->nf; i++)
        if (p->f[i]->n > m)
            m = p->f[i]->n;
    return m;
}

/* The bound on functions l..k-1 along one variable (level l shares level l+1's row when
 * function l does not depend on the variable). */
typedef struct brow {
    const double *v;          /* per index */
    double all;               /* max over the whole row, once have_all */
    bool have_all;
} brow;

/* One linear segment of a function's bound along one variable. */
typedef struct seg {
    int32_t lo, hi;
    double base, slope;
} seg;

/* The grid path (see kelp_ivp_solve_grid_work_size): points of the problem domain, or 0 when
 * the domain has more than KELP_IVP_SOLVE_GRID_MAX points. */
static size_t grid_points(const kelp_ivp_problem *p, size_t *padded)
{
    size_t g = 1, gp = 1;
    if (padded)
        *padded = 0;
    for (unsigned e = 0; e < p->dom.dim; e++) {
        g *= p->dom.var[e].points;
        gp *= (size_t)p->dom.var[e].points + 1u;
        if (g > KELP_IVP_SOLVE_GRID_MAX)
            return 0;
    }
    if (padded)
        *padded = gp;
    return p->dom.dim ? g : 0;
}

static size_t total_pieces(const kelp_ivp_problem *p)
{
    size_t t = 0;
    for (unsigned i = 0; i < p->nf; i++)
        t += p->f[i]->n;
    return t;
}

/* Optimal points kept as a list (checked one by one) before the summed-area table takes over. */
#define GRID_LIST 8

/* Bytes of the grid path on top of the search's own storage. */
static size_t grid_size(const kelp_ivp_problem *p)
{
    size_t gp = 0, g = grid_points(p, &gp);
    if (!g)
        return 0;
    size_t sz = 2 * align8(sizeof(double) * g);            /* total, the function's value */
    sz += align8(sizeof(uint16_t) * g);                     /* functions covering, in order */
    sz += align8(sizeof(uint32_t) * gp);                    /* optimal points, summed area */
    sz += align8(sizeof(uint32_t) * (total_pieces(p) + p->nf + 1)); /* candidates per function */
    sz += align8(sizeof(int32_t) * D * GRID_LIST);          /* a few optimal points, listed */
    return sz;
}

size_t kelp_ivp_solve_grid_work_size(const kelp_ivp_problem *p)
{
    size_t g = grid_size(p);
    return kelp_ivp_solve_work_size(p) + (g ? g + 8u : 0u);
}

size_t kelp_ivp_solve_work_size(const kelp_ivp_problem *p)
{
    size_t k = p->nf;
    size_t sz = align8(sizeof(sfunc) * (k + 1));
    sz += align8(sizeof(snode) * (k + 1));
    sz += 2 * align8(sizeof(double) * (k + 2));
    sz += align8(sizeof(brow *) * D * (k + 1));
    sz += align8(sizeof(brow) * D * k);
    sz += align8(sizeof(double) * rows_len(p));
    sz += align8(sizeof(seg) * max_pieces(p));
    for (unsigned i = 0; i < k; i++)
        sz += align8(sizeof(spiece) * p->f[i]->n);
    return sz;
}

#if defined(__GNUC__)
#define IVP_SOLVE_INLINE inline __attribute__((always_inline))
#else
#define IVP_SOLVE_INLINE inline
#endif

static IVP_SOLVE_INLINE double box_max(const int32_t *lo, const int32_t *hi, const double *s, double c, unsigned dim)
{
    double v = c;
    for (unsigned d = 0; d < dim; d++)
        v += s[d] < 0 ? s[d] * (double)lo[d] : s[d] * (double)hi[d];
    return v;
}

/* Row of one level along one variable with `pts` indices:
 *     row[x] = next[x] + max over the segments covering x of (base + slope * x)
 * (no next: 0; no covering segment: -inf). */
static void fill_row(double *row, uint32_t pts, const brow *next, const seg *sg, uint32_t ns)
{
    bool tiles = sg[0].lo == 0 && sg[ns - 1].hi == (int32_t)pts - 1;
    for (uint32_t j = 1; j < ns && tiles; j++)
        tiles = sg[j].lo == sg[j - 1].hi + 1;
    const double *nx = next ? next->v : NULL;
    if (tiles) { /* segments in order, no gap, no overlap: one pass */
        for (uint32_t j = 0; j < ns; j++) {
            double b = sg[j].base, s = sg[j].slope;
            if (nx) {
                for (int32_t i = sg[j].lo; i <= sg[j].hi; i++)
                    row[i] = (b + s * (double)i) + nx[i];
            } else {
                for (int32_t i = sg[j].lo; i <= sg[j].hi; i++)
                    row[i] = b + s * (double)i;
            }
        }
        return;
    }
    for (uint32_t i = 0; i < pts; i++)
        row[i] = -INFINITY;
    for (uint32_t j = 0; j < ns; j++) {
        double b = sg[j].base, s = sg[j].slope;
        for (int32_t i = sg[j].lo; i <= sg[j].hi; i++) {
            double v = b + s * (double)i;
            if (v > row[i])
                row[i] = v;
        }
    }
    if (nx)
        for (uint32_t i = 0; i < pts; i++)
            row[i] += nx[i];
}

/* Max of a level's row over [lo, hi]. */
static inline double row_max(brow *b, int32_t lo, int32_t hi, int32_t last)
{
    const double *r = b->v;
    if (lo == 0 && hi == last) {
        if (b->have_all)
            return b->all;
        b->have_all = true;
    }
    double m = r[lo];
    for (int32_t i = lo + 1; i <= hi; i++)
        if (r[i] > m)
            m = r[i];
    if (lo == 0 && hi == last)
        b->all = m;
    return m;
}

static bool same_var(const spiece *a, const spiece *b, unsigned d)
{
    return a->lo[d] == b->lo[d] && a->hi[d] == b->hi[d] && a->s[d] == b->s[d];
}

/* A coupled function: piece j*nb+m has variable u as piece j*nb and variable v as piece m. Then
 * f <= alpha_j + beta_m + r with alpha_j = c[j*nb], beta_m = c[m] - c[0], r the largest
 * residual. Returns nb (0: not coupled over u, v) and r. */
static uint32_t coupled(const sfunc *sf, unsigned u, unsigned v, double *res)
{
    const spiece *p = sf->p;
    uint32_t n = sf->n, nb = 1;
    while (nb < n && same_var(&p[nb], &p[0], u))
        nb++;
    if (n % nb)
        return 0;
    for (uint32_t j = 0; j < n; j += nb)
        for (uint32_t m = 0; m < nb; m++)
            if (!same_var(&p[j + m], &p[j], u) || !same_var(&p[j + m], &p[m], v))
                return 0;
    double r = -INFINITY, c0 = p[0].c;
    for (uint32_t j = 0; j < n; j += nb) {
        double alpha = p[j].c;
        for (uint32_t m = 0; m < nb; m++) {
            double e = p[j + m].c - (alpha + (p[m].c - c0));
            if (e > r)
                r = e;
        }
    }
    *res = r;
    return nb;
}

/* Level l's rows (cur) from level l+1's (next) and function sf's separable bound. Storage for new
 * rows comes from *store. Returns the bound's constant part k_l. */
static double majorant(const sfunc *sf, const kelp_ivp_domain *dom, brow *const *next, brow **cur, brow **owner, double **store,
                       seg *sg)
{
    unsigned dim = dom->dim, m = 0, rv[D];
    bool rel[D];
    for (unsigned e = 0; e < dim; e++)
        rel[e] = false;
    for (uint32_t j = 0; j < sf->n; j++) {
        const spiece *t = &sf->p[j];
        for (unsigned e = 0; e < dim; e++)
            if (t->s[e] != 0 || t->lo[e] != 0 || t->hi[e] != (int32_t)dom->var[e].points - 1)
                rel[e] = true;
    }
    for (unsigned e = 0; e < dim; e++) {
        cur[e] = next[e];
        if (rel[e])
            rv[m++] = e;
    }
    if (m == 0)
        return sf->gmax;
    const spiece *p = sf->p;
    double res = 0.0;
    uint32_t nb = 0;
    unsigned u = 0, v = 0;
    if (m == 2) {
        u = rv[0];
        v = rv[1];
        nb = coupled(sf, u, v, &res);
        if (!nb) {
            u = rv[1];
            v = rv[0];
            nb = coupled(sf, u, v, &res);
        }
    }
    for (unsigned a = 0; a < m; a++) {
        unsigned d = rv[a];
        uint32_t ns = 0, pts = dom->var[d].points;
        if (nb && d == u) {
            for (uint32_t j = 0; j < sf->n; j += nb, ns++)
                sg[ns] = (seg){p[j].lo[u], p[j].hi[u], p[j].c, p[j].s[u]};
        } else if (nb) {
            for (uint32_t j = 0; j < nb; j++, ns++)
                sg[ns] = (seg){p[j].lo[v], p[j].hi[v], p[j].c - p[0].c, p[j].s[v]};
        } else { /* f <= the mean of its projections (m == 1: its upper envelope) */
            double w = m == 1 ? 1.0 : 1.0 / (double)m;
            for (uint32_t j = 0; j < sf->n; j++, ns++) {
                const spiece *t = &p[j];
                double base = t->c;
                for (unsigned e = 0; e < dim; e++)
                    if (e != d)
                        base += t->s[e] < 0 ? t->s[e] * (double)t->lo[e] : t->s[e] * (double)t->hi[e];
                sg[ns] = (seg){t->lo[d], t->hi[d], w * base, w * t->s[d]};
            }
        }
        double *row = *store;
        *store = row + pts;
        fill_row(row, pts, next[d], sg, ns);
        brow *o = (*owner)++;
        o->v = row;
        o->have_all = false;
        cur[d] = o;
    }
    return res;
}

/* ------------------------------------------------------------------ the grid path
 *
 * When the problem domain has at most KELP_IVP_SOLVE_GRID_MAX points and the caller gives the
 * storage (kelp_ivp_solve_grid_work_size), the objective is first evaluated at every point:
 * each function paints its pieces onto the grid (where pieces overlap, the larger value: a leaf
 * may combine any intersecting pieces), so total[x] is the best leaf value at x and its maximum
 * G is the optimum. The search then walks the same depth-first order as above but keeps only
 * nodes whose box holds a point within tol of G (a summed-area table of those points answers
 * in 2^dim reads), and at each level only the pieces that hold such a point. The first optimum
 * lies in such a box (its value at its maximising corner is G up to rounding, far below tol),
 * and so does every leaf that could tie with it or beat it, so the answer is the exhaustive
 * search's. Cost: one pass over the grid per function (about the pieces' points) plus, per
 * level, the few pieces near the optimum; with a plateau of optimal points the search visits
 * the leaves over the plateau. A function whose pieces tile the grid (the Reflector's uniform
 * pieces) needs no coverage count: it adds its value at each point, and the functions sharing a
 * tile are summed plane by plane and added once; the pieces holding the listed optimal points
 * are found by their tile index. */

typedef struct gridw {
    double *total, *fval;
    uint16_t *cover;
    uint32_t *sat;
    uint32_t *cand;
    int32_t *list;            /* na <= GRID_LIST: the optimal points, D coordinates each */
    uint32_t na;
    size_t g, gp;
    size_t stride[D], pstride[D];
} gridw;

/* Paint function i (pieces aligned to the problem domain) onto the grid. The grid's arrays are
 * held in locals so the stores do not make the compiler reload them (or the piece) per point. */
/* One row of a piece along the last variable, indices t0..t1 (arrays from the row's start). */
static IVP_SOLVE_INLINE void paint_row(double *total, double *fval, uint16_t *cover, int32_t t0, int32_t t1, double base,
                                       double sl, uint16_t mine, uint16_t done)
{
    for (int32_t t = t0; t <= t1; t++) {
        double v = base + sl * (double)t;
        uint16_t c = cover[t];
        if (c == mine) { /* covered by every earlier function, first piece of this one */
            cover[t] = done;
            fval[t] = v;
            total[t] += v;
        } else if (c == done && v > fval[t]) { /* an overlapping piece, larger */
            total[t] += v - fval[t];
            fval[t] = v;
        }
    }
}

/* grid_paint for two variables (the same values: base = c + s0 x, then base + s1 t) */
static void grid_paint2(gridw *gw, const sfunc *F, unsigned i)
{
    double *total = gw->total, *fval = gw->fval;
    uint16_t *cover = gw->cover;
    const uint16_t mine = (uint16_t)i, done = (uint16_t)(i + 1);
    const size_t st0 = gw->stride[0];
    for (uint32_t j = 0; j < F->n; j++) {
        const spiece *q = &F->p[j];
        const int32_t t0 = q->lo[1], t1 = q->hi[1], x1 = q->hi[0];
        const double c0 = q->c, s0 = q->s[0], sl = q->s[1];
        for (int32_t x = q->lo[0]; x <= x1; x++) {
            double base = c0;
            base += s0 * (double)x;
            size_t off = st0 * (size_t)x;
            paint_row(total + off, fval + off, cover + off, t0, t1, base, sl, mine, done);
        }
    }
}

static KELP_NOINLINE void grid_paint(gridw *gw, const sfunc *F, unsigned i, unsigned dim)
{
    if (dim == 2) {
        grid_paint2(gw, F, i);
        return;
    }
    unsigned last = dim - 1;
    double *total = gw->total, *fval = gw->fval;
    uint16_t *cover = gw->cover;
    const uint16_t mine = (uint16_t)i, done = (uint16_t)(i + 1);
    for (uint32_t j = 0; j < F->n; j++) {
        const spiece *q = &F->p[j];
        int32_t x[D] = {0}; /* dim <= D: every coordinate used is set below */
        for (unsigned e = 0; e < dim; e++)
            x[e] = q->lo[e];
        const int32_t t0 = q->lo[last], t1 = q->hi[last];
        const double sl = q->s[last];
        for (;;) {
            double base = q->c;
            size_t off = 0;
            for (unsigned e = 0; e < last; e++) {
                base += q->s[e] * (double)x[e];
                off += gw->stride[e] * (size_t)x[e];
            }
            paint_row(total + off, fval + off, cover + off, t0, t1, base, sl, mine, done);
            unsigned e = last;
            while (e-- > 0) {
                if (++x[e] <= q->hi[e])
                    break;
                x[e] = q->lo[e];
            }
            if (e == (unsigned)-1)
                break;
        }
    }
}

static bool tiles_walk(sfunc *F, const kelp_ivp_domain *dom, unsigned dim);

/* Whether F's pieces tile the grid in tile order (the Reflector's uniform pieces: equal boxes
 * from the low corner, the last variable fastest, clipped at the domain's end): then every
 * point lies in exactly one piece. */
static bool tiles_grid(sfunc *F, const kelp_ivp_domain *dom, unsigned dim)
{
    F->tiled = tiles_walk(F, dom, dim);
    return F->tiled;
}

/* (tiles_grid's walk; F->edge gets the tile) */
static bool tiles_walk(sfunc *F, const kelp_ivp_domain *dom, unsigned dim)
{
    if (F->n == 0)
        return false;
    int32_t *edge = F->edge, cur[D];
    for (unsigned e = 0; e < dim; e++) {
        edge[e] = F->p[0].hi[e] - F->p[0].lo[e] + 1;
        cur[e] = 0;
        if (edge[e] < 1)
            return false;
    }
    if (dim == 2) { /* the same walk, unrolled */
        const int32_t n0 = (int32_t)dom->var[0].points, n1 = (int32_t)dom->var[1].points;
        const spiece *q = F->p, *end = F->p + F->n;
        for (int32_t a = 0; a < n0; a += edge[0]) {
            const int32_t h0 = a + edge[0] - 1 < n0 ? a + edge[0] - 1 : n0 - 1;
            for (int32_t b = 0; b < n1; b += edge[1], q++) {
                if (q == end || q->lo[0] != a || q->hi[0] != h0 || q->lo[1] != b ||
                    q->hi[1] != (b + edge[1] - 1 < n1 ? b + edge[1] - 1 : n1 - 1))
                    return false;
            }
        }
        return q == end;
    }
    for (uint32_t j = 0; j < F->n; j++) {
        const spiece *q = &F->p[j];
        for (unsigned e = 0; e < dim; e++) {
            int32_t last = (int32_t)dom->var[e].points - 1, hi = cur[e] + edge[e] - 1;
            if (q->lo[e] != cur[e] || q->hi[e] != (hi < last ? hi : last))
                return false;
        }
        unsigned e = dim;
        while (e-- > 0) {
            cur[e] += edge[e];
            if (cur[e] < (int32_t)dom->var[e].points)
                break;
            cur[e] = 0;
        }
        if (e == (unsigned)-1) /* wrapped: the grid is covered */
            return j + 1 == F->n;
    }
    return false;
}

/* The piece of a tiled function (tiles_grid) holding point x. */
static uint32_t tile_index(const sfunc *F, const kelp_ivp_domain *dom, const int32_t *x, unsigned dim)
{
    uint32_t j = 0;
    for (unsigned e = 0; e < dim; e++) {
        uint32_t across = ((uint32_t)dom->var[e].points + (uint32_t)F->edge[e] - 1) / (uint32_t)F->edge[e];
        j = j * across + (uint32_t)(x[e] / F->edge[e]);
    }
    return j;
}

/* Add a function that tiles the grid (tiles_grid): each point's one value, no coverage to
 * count and no overlap to resolve; the values are grid_paint's. */
/* (two variables: grid_paint2's loops) */
static KELP_NOINLINE void grid_add2(gridw *gw, const sfunc *F, const double *co)
{
    double *total = gw->total;
    {
        const size_t st0 = gw->stride[0];
        for (uint32_t j = 0; j < F->n; j++) {
            const spiece *q = &F->p[j];
            const int32_t t0 = q->lo[1], t1 = q->hi[1], x1 = q->hi[0];
            const double c0 = co ? co[3 * j + 2] : q->c, s0 = co ? co[3 * j] : q->s[0], sl = co ? co[3 * j + 1] : q->s[1];
            for (int32_t x = q->lo[0]; x <= x1; x++) {
                double base = c0;
                base += s0 * (double)x;
                double *row = total + st0 * (size_t)x + t0, td = (double)t0; /* td: t, exactly */
                for (int32_t m = t1 - t0; m >= 0; m--, row++, td += 1.0)
                    *row += base + sl * td;
            }
        }
    }
}

static KELP_NOINLINE void grid_add_n(gridw *gw, const sfunc *F, const double *co, unsigned dim)
{
    double *total = gw->total;
    unsigned last = dim - 1, nco = dim + 1;
    for (uint32_t j = 0; j < F->n; j++) {
        const spiece *q = &F->p[j];
        const double *cs = co ? co + (size_t)nco * j : q->s, cc = co ? co[(size_t)nco * j + dim] : q->c;
        const int32_t t0 = q->lo[last], t1 = q->hi[last];
        const double sl = cs[last];
        int32_t x[D] = {0};
        for (unsigned e = 0; e < dim; e++)
            x[e] = q->lo[e];
        for (;;) {
            double base = cc;
            size_t off = 0;
            for (unsigned e = 0; e < last; e++) {
                base += cs[e] * (double)x[e];
                off += gw->stride[e] * (size_t)x[e];
            }
            double *row = total + off;
            for (int32_t t = t0; t <= t1; t++)
                row[t] += base + sl * (double)t;
            unsigned e = last;
            while (e-- > 0) {
                if (++x[e] <= q->hi[e])
                    break;
                x[e] = q->lo[e];
            }
            if (e == (unsigned)-1)
                break;
        }
    }
}

/* Add a function that tiles the grid (co: its coefficients, dim + 1 per piece, in place of the
 * pieces' own) */
static void grid_add(gridw *gw, const sfunc *F, const double *co, unsigned dim)
{
    if (dim == 2)
        grid_add2(gw, F, co);
    else
        grid_add_n(gw, F, co, dim);
}

static bool same_tile(const sfunc *a, const sfunc *b, unsigned dim)
{
    for (unsigned e = 0; e < dim; e++)
        if (a->edge[e] != b->edge[e])
            return false;
    return true;
}

/* Optimal points in box [lo, hi] (summed-area table, inclusion-exclusion over the corners);
 * with a short list, whether there is one. */
static uint32_t grid_count(const gridw *gw, const int32_t *lo, const int32_t *hi, unsigned dim)
{
    if (gw->na <= GRID_LIST) {
        for (uint32_t a = 0; a < gw->na; a++) {
            const int32_t *x = &gw->list[a * D];
            unsigned e = 0;
            while (e < dim && x[e] >= lo[e] && x[e] <= hi[e])
                e++;
            if (e == dim)
                return 1;
        }
        return 0;
    }
    if (dim == 2) {
        size_t s0 = gw->pstride[0];
        size_t a = s0 * (size_t)lo[0], b = s0 * (size_t)(hi[0] + 1);
        return gw->sat[b + (size_t)hi[1] + 1] - gw->sat[a + (size_t)hi[1] + 1] - gw->sat[b + (size_t)lo[1]] +
               gw->sat[a + (size_t)lo[1]];
    }
    uint32_t n = 0;
    for (unsigned m = 0; m < (1u << dim); m++) {
        size_t o = 0;
        unsigned low = 0;
        for (unsigned e = 0; e < dim; e++) {
            if ((m >> e) & 1u) {
                o += gw->pstride[e] * (size_t)(hi[e] + 1);
            } else {
                o += gw->pstride[e] * (size_t)lo[e];
                low++;
            }
        }
        n += (low & 1u) ? (uint32_t)0 - gw->sat[o] : gw->sat[o];
    }
    return n;
}

static int grid_solve(kelp_ivp_problem *p, sfunc *sf, snode *node, double margin, unsigned char *w,
                      kelp_ivp_result *res)
{
    unsigned k = p->nf, dim = p->dom.dim;
    gridw gw;
    gw.g = grid_points(p, &gw.gp);
    gw.total = (double *)(void *)w;
    w += align8(sizeof(double) * gw.g);
    gw.fval = (double *)(void *)w;
    w += align8(sizeof(double) * gw.g);
    gw.cover = (uint16_t *)(void *)w;
    w += align8(sizeof(uint16_t) * gw.g);
    gw.sat = (uint32_t *)(void *)w;
    w += align8(sizeof(uint32_t) * gw.gp);
    uint32_t *cstart = (uint32_t *)(void *)w;
    gw.cand = cstart + k + 1;
    w += align8(sizeof(uint32_t) * (total_pieces(p) + k + 1));
    gw.list = (int32_t *)(void *)w;
    gw.na = 0;
    size_t st = 1, pst = 1;
    for (unsigned e = dim; e-- > 0;) {
        gw.stride[e] = st;
        gw.pstride[e] = pst;
        st *= p->dom.var[e].points;
        pst *= (size_t)p->dom.var[e].points + 1u;
    }
    memset(gw.cover, 0, sizeof(uint16_t) * gw.g);
    for (size_t o = 0; o < gw.g; o++)
        gw.total[o] = 0.0;
    /* Functions that tile the grid add each point's one value (no coverage to count); those
     * sharing the first one's tile are summed plane by plane first (the coefficients in fval,
     * free until a function is painted, when it holds dim + 1 doubles per tile) and added at
     * once. A point's total then differs from the sum of its values by rounding only, far below
     * the tolerance the search keeps around G, so the answer is the same. */
    unsigned g0 = k, painted = 0; /* functions painted with coverage counted */
    for (unsigned i = 0; i < k; i++)
        if (tiles_grid(&sf[i], &p->dom, dim) && g0 == k)
            g0 = i;
    const unsigned nco = dim + 1;
    bool grouped = g0 < k && (size_t)nco * sf[g0].n <= gw.g;
    if (grouped) {
        double *co = gw.fval;
        for (uint32_t j = 0; j < sf[g0].n; j++) {
            for (unsigned e = 0; e < dim; e++)
                co[(size_t)nco * j + e] = sf[g0].p[j].s[e];
            co[(size_t)nco * j + dim] = sf[g0].p[j].c;
        }
        for (unsigned i = g0 + 1; i < k; i++) {
            if (!sf[i].tiled || !same_tile(&sf[i], &sf[g0], dim))
                continue;
            for (uint32_t j = 0; j < sf[i].n; j++) {
                for (unsigned e = 0; e < dim; e++)
                    co[(size_t)nco * j + e] += sf[i].p[j].s[e];
                co[(size_t)nco * j + dim] += sf[i].p[j].c;
            }
        }
        grid_add(&gw, &sf[g0], co, dim);
    }
    for (unsigned i = 0; i < k; i++) {
        if (sf[i].tiled) {
            if (!grouped || !same_tile(&sf[i], &sf[g0], dim))
                grid_add(&gw, &sf[i], NULL, dim);
        } else {
            grid_paint(&gw, &sf[i], painted++, dim);
        }
    }
    const uint16_t all = (uint16_t)painted;
    double G = -INFINITY;
    for (size_t o = 0; o < gw.g; o++)
        if (gw.cover[o] == all && gw.total[o] > G)
            G = gw.total[o];
    if (G == -INFINITY)
        return ivp_fail(&p->diag, KELP_ERR_INFEASIBLE, "solver: no point is covered by every function", NULL, 0);
    /* summed-area table of the points within tol of G, padded by one on the low side */
    double lim = G - 4.0 * margin;
    memset(gw.sat, 0, sizeof(uint32_t) * gw.gp);
    {
        int32_t x[D] = {0};
        for (size_t o = 0; o < gw.g; o++) {
            size_t po = 0;
            for (unsigned e = 0; e < dim; e++)
                po += gw.pstride[e] * (size_t)(x[e] + 1);
            bool opt = gw.cover[o] == all && gw.total[o] >= lim;
            gw.sat[po] = opt;
            if (opt && gw.na++ < GRID_LIST)
                memcpy(&gw.list[(gw.na - 1) * D], x, sizeof x);
            for (unsigned e = dim; e-- > 0;) {
                if (++x[e] < (int32_t)p->dom.var[e].points)
                    break;
                x[e] = 0;
            }
        }
        for (unsigned e = 0; e < dim && gw.na > GRID_LIST; e++) /* prefix sums along each variable */
            for (size_t po = 0; po < gw.gp; po++)
                if ((po / gw.pstride[e]) % ((size_t)p->dom.var[e].points + 1u) != 0)
                    gw.sat[po] += gw.sat[po - gw.pstride[e]];
    }
    /* per function, the pieces (stored order) holding an optimal point */
    uint32_t nc = 0;
    for (unsigned i = 0; i < k; i++) {
        cstart[i] = nc;
        if (sf[i].tiled && gw.na <= GRID_LIST) { /* the tiles holding the listed points, in order */
            for (uint32_t a = 0; a < gw.na; a++) {
                uint32_t j = tile_index(&sf[i], &p->dom, &gw.list[a * D], dim), at = nc;
                while (at > cstart[i] && gw.cand[at - 1] > j)
                    at--;
                if (at > cstart[i] && gw.cand[at - 1] == j)
                    continue;
                memmove(&gw.cand[at + 1], &gw.cand[at], sizeof(uint32_t) * (nc - at));
                gw.cand[at] = j;
                nc++;
            }
            continue;
        }
        for (uint32_t j = 0; j < sf[i].n; j++)
            if (grid_count(&gw, sf[i].p[j].lo, sf[i].p[j].hi, dim))
                gw.cand[nc++] = j;
    }
    cstart[k] = nc;

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
    node[0].next = cstart[0];
    unsigned l = 0;
    for (;;) {
        snode *cur = &node[l];
        if (cur->next >= cstart[l + 1]) {
            if (l == 0)
                break;
            l--;
            continue;
        }
        const spiece *q = &sf[l].p[gw.cand[cur->next++]];
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
        if (e < dim || !grid_count(&gw, nx->lo, nx->hi, dim))
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
        if (l + 1 == k) {
            double v = box_max(nx->lo, nx->hi, nx->s, nx->c, dim);
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
        nx->next = cstart[l + 1];
        l++;
    }
    res->leaves = leaves;
    if (!found) /* cannot happen: a point within tol of G lies in some leaf */
        return ivp_fail(&p->diag, KELP_ERR_INFEASIBLE, "solver: no point is covered by every function", NULL, 0);
    for (unsigned e = 0; e < dim; e++) {
        uint32_t ix = (uint32_t)(bs[e] < 0 ? blo[e] : bhi[e]);
        res->ix[e] = ix;
        res->val[e] = kelp_ivp_domain_value(&p->dom, e, ix);
    }
    res->value = best;
    return 0;
}

/* A function's pieces, normalised (norm), weighted and aligned to the problem's variables
 * (map), with its global max and magnitude. Inlined with constant dimensions for the common
 * 2-D case (the same arithmetic in the same order). */
static IVP_SOLVE_INLINE void prep_func(sfunc *s, const kelp_ivp_func *f, const kelp_ivp_domain *pd, const int *map, bool norm,
                                       double badj, double radj, double pwt, unsigned dim, unsigned fdim)
{
    s->gmax = -INFINITY;
    s->mag = 0;
    for (size_t j = 0; j < f->n; j++) {
        const kelp_ivp_piece *q = &f->pcs[j];
        spiece *t = &s->p[j];
        for (unsigned e = 0; e < dim; e++) {
            t->lo[e] = 0;
            t->hi[e] = (int32_t)pd->var[e].points - 1;
            t->s[e] = 0.0;
        }
        double c = q->cst;
        if (norm)
            c = (c + badj) * radj;
        t->c = c * pwt;
        for (unsigned d = 0; d < fdim; d++) {
            double sl = q->slope[d];
            if (norm)
                sl *= radj;
            t->lo[map[d]] = q->lo[d];
            t->hi[map[d]] = q->hi[d];
            t->s[map[d]] = sl * pwt;
        }
        double m = box_max(t->lo, t->hi, t->s, t->c, dim);
        if (m > s->gmax)
            s->gmax = m;
        double g = fabs(t->c);
        for (unsigned e = 0; e < dim; e++)
            g += fabs(t->s[e]) * (double)(pd->var[e].points - 1);
        if (g > s->mag)
            s->mag = g;
    }
}

/* prep_func, out of line (its locals are not on the stack while the search runs) */
static KELP_NOINLINE void prep(sfunc *s, const kelp_ivp_func *f, const kelp_ivp_domain *pd, const int *map, bool norm,
                               double badj, double radj, double pwt)
{
    if (pd->dim == 2 && f->dom.dim == 2 && map[0] == 0 && map[1] == 1)
        prep_func(s, f, pd, map, norm, badj, radj, pwt, 2, 2);
    else
        prep_func(s, f, pd, map, norm, badj, radj, pwt, pd->dim, f->dom.dim);
}

int kelp_ivp_solve(kelp_ivp_problem *p, void *work, size_t work_size, kelp_ivp_result *res)
{
    if (!p || !res)
        return KELP_ERR_ARG;
    memset(res, 0, sizeof *res);
    unsigned k = p->nf, dim = p->dom.dim;
    if (k == 0)
        return ivp_fail(&p->diag, KELP_ERR_EMPTY, "solver: no functions with positive weight", NULL, 0);
    if (dim == 0)
        return ivp_fail(&p->diag, KELP_ERR_ARG, "solver: null domain", NULL, 0);
    size_t need = kelp_ivp_solve_work_size(p);
    if (!work || work_size < need)
        return ivp_fail(&p->diag, KELP_ERR_NOSPACE, "solver: work storage too small", NULL, 0);

    unsigned char *w = (unsigned char *)work;
    sfunc *sf = (sfunc *)(void *)w;
    w += align8(sizeof(sfunc) * (k + 1));
    snode *node = (snode *)(void *)w;
    w += align8(sizeof(snode) * (k + 1));
    double *suffix = (double *)(void *)w;
    w += align8(sizeof(double) * (k + 2));
    double *sk = (double *)(void *)w;
    w += align8(sizeof(double) * (k + 2));
    brow **br = (brow **)(void *)w; /* br[l * D + e]: NULL when no function l.. depends on e */
    w += align8(sizeof(brow *) * D * (k + 1));
    brow *owner = (brow *)(void *)w;
    w += align8(sizeof(brow) * D * k);
    double *rowstore = (double *)(void *)w;
    w += align8(sizeof(double) * rows_len(p));
    seg *sg = (seg *)(void *)w;
    w += align8(sizeof(seg) * max_pieces(p));

    /* Prepare: normalise (range > 100), weight, align to the problem's variable order. */
    double magsum = 0;
    for (unsigned i = 0; i < k; i++) {
        const kelp_ivp_func *f = p->f[i];
        sfunc *s = &sf[i];
        s->p = (spiece *)(void *)w;
        w += align8(sizeof(spiece) * f->n);
        s->n = (uint32_t)f->n;
        int map[D] = {0};
        for (unsigned d = 0; d < f->dom.dim; d++)
            map[d] = kelp_ivp_domain_index(&p->dom, f->dom.var[d].name);
        double lo = 0, hi = 0;
        bool norm = false;
        if (f->n && kelp_ivp_func_range(f, &lo, &hi) == 0 && hi - lo > 100)
            norm = true;
        double badj = 0.0 - lo, radj = norm ? 100.0 / (hi - lo) : 1.0, pwt = f->pwt;
        prep(s, f, &p->dom, map, norm, badj, radj, pwt);
        magsum += s->mag;
    }
    if (grid_size(p) && work_size >= kelp_ivp_solve_grid_work_size(p)) {
        double gmargin = 1e-12 * (double)(k + dim + 8) * (4.0 * magsum + 1.0);
        return grid_solve(p, sf, node, gmargin, (unsigned char *)(((uintptr_t)w + 7u) & ~(uintptr_t)7u), res);
    }
    /* suffix[i]: sum of the global maxima of functions i..k-1; br[i*D+e] and sk[i]: the separable
     * bound of functions i..k-1. */
    suffix[k] = 0;
    sk[k] = 0;
    for (unsigned e = 0; e < D; e++)
        br[(size_t)k * D + e] = NULL;
    for (unsigned i = k; i-- > 0;) {
        suffix[i] = suffix[i + 1] + sf[i].gmax;
        sk[i] = sk[i + 1] + majorant(&sf[i], &p->dom, &br[(size_t)(i + 1) * D], &br[(size_t)i * D], &owner, &rowstore,
                                   sg);
    }
    /* Margin: far above the rounding error of any leaf value or bound computed here. */
    double margin = 1e-12 * (double)(k + dim + 8) * (4.0 * magsum + 1.0);

    /* Floor: the objective at the maximiser of the level-0 bound is reached by some leaf. */
    double thr = -INFINITY;
    {
        int32_t x[D];
        for (unsigned e = 0; e < dim; e++) {
            const double *r = br[e] ? br[e]->v : NULL;
            uint32_t bi = 0;
            for (uint32_t i = 1; r && i < p->dom.var[e].points; i++)
                if (r[i] > r[bi])
                    bi = i;
            x[e] = (int32_t)bi;
        }
        double tot_v = 0;
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
                    tot_v += v;
                    covered = true;
                    break;
                }
            }
        }
        if (covered)
            thr = tot_v - margin;
    }

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
    int32_t last[D];
    for (unsigned e = 0; e < dim; e++)
        last[e] = (int32_t)p->dom.var[e].points - 1;
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
                if (best - margin > thr)
                    thr = best - margin;
                memcpy(blo, nx->lo, sizeof blo);
                memcpy(bhi, nx->hi, sizeof bhi);
                memcpy(bs, nx->s, sizeof bs);
            }
            continue;
        }
        if (v + suffix[l + 1] < thr)
            continue;
        {
            brow *const *b = &br[(size_t)(l + 1) * D];
            double bound = v + sk[l + 1];
            for (e = 0; e < dim; e++)
                if (b[e])
                    bound += row_max(b[e], nx->lo[e], nx->hi[e], last[e]);
            if (bound < thr)
                continue;
        }
        nx->next = 0;
        l++;
    }
    res->leaves = leaves;
    if (!found)
        return ivp_fail(&p->diag, KELP_ERR_INFEASIBLE, "solver: no point is covered by every function", NULL, 0);
    for (unsigned e = 0; e < dim; e++) {
        uint32_t ix = (uint32_t)(bs[e] < 0 ? blo[e] : bhi[e]);
        res->ix[e] = ix;
        res->val[e] = kelp_ivp_domain_value(&p->dom, e, ix);
    }
    res->value = best;
    return 0;
}
