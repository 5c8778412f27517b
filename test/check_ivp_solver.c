/* IvP unit tests: the solver's pruning and the ZAIC_PEAK fast path against plain references.
 *
 * The solver prunes with bounds (separable rows, coupled-function splitting, a floor) that must
 * never remove the first optimum. Here random problems full of exact ties and of values that
 * differ only by rounding are solved and compared, bit for bit, with a reference that walks every
 * leaf in MOOS-IvP's depth-first order (first function's pieces in stored order, then the next
 * function's intersecting pieces, strictly better replaces). ZAIC_PEAK pieces are compared with a
 * per-point evaluation of the seed's distance form cut by the plain MOOS-IvP loop. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/ivp.h>

/* ---------------------------------------------------------------- helpers */

static unsigned long long g_rs;

static void rseed(unsigned long long s)
{
    g_rs = s * 2654435761ULL + 17u;
}

static unsigned rnd(void)
{
    g_rs = g_rs * 6364136223846793005ULL + 1442695040888963407ULL;
    return (unsigned)(g_rs >> 33);
}

static int rn(int n)
{
    return (int)(rnd() % (unsigned)n);
}

static double rr(double a, double b)
{
    return a + (b - a) * (double)(rnd() % 1000003u) / 1000003.0;
}

static kelp_ivp_domain mkdom(const char *s)
{
    kelp_ivp_domain d;
    kelp_diag e = {0};
    ck_assert_int_eq(kelp_ivp_domain_parse(&d, s, &e), 0);
    return d;
}

#define NF 10
#define CAP 4096
static kelp_ivp_piece s_store[NF][CAP];
static kelp_ivp_piece s_tmpa[CAP], s_tmpb[CAP];
static double s_zw[CAP];
static kelp_ivp_spec_ws s_zws;
static kelp_ivp_pq_entry s_pq[CAP];
static unsigned char s_work[1 << 21];

/* ---------------------------------------------------------------- reference walk */

typedef struct refw {
    const kelp_ivp_domain *dom;
    const kelp_ivp_func *f[NF];
    int map[NF][KELP_IVP_MAX_DIM];
    double badj[NF], radj[NF], w[NF];
    bool norm[NF];
    unsigned k;
    bool found;
    double best;
    uint32_t ix[KELP_IVP_MAX_DIM];
} refw;

/* Problem::addOF: normalise to [0,100] when the range exceeds 100, then weight. */
static void ref_add(refw *s, const kelp_ivp_func *f)
{
    if (!(f->pwt > 0))
        return;
    unsigned j = s->k++;
    s->f[j] = f;
    s->w[j] = f->pwt;
    for (unsigned d = 0; d < f->dom.dim; d++)
        s->map[j][d] = kelp_ivp_domain_index(s->dom, f->dom.var[d].name);
    double lo, hi;
    s->norm[j] = false;
    s->radj[j] = 1.0;
    if (kelp_ivp_func_range(f, &lo, &hi) == 0 && hi - lo > 100) {
        s->norm[j] = true;
        s->badj[j] = 0.0 - lo;
        s->radj[j] = 100.0 / (hi - lo);
    }
}

static void ref_rec(refw *s, unsigned l, const int32_t *lo, const int32_t *hi, const double *sl, double c)
{
    unsigned dim = s->dom->dim;
    if (l == s->k) {
        double v = c;
        for (unsigned d = 0; d < dim; d++)
            v += sl[d] < 0 ? sl[d] * (double)lo[d] : sl[d] * (double)hi[d];
        if (!s->found || v > s->best) {
            s->found = true;
            s->best = v;
            for (unsigned d = 0; d < dim; d++)
                s->ix[d] = (uint32_t)(sl[d] < 0 ? lo[d] : hi[d]);
        }
        return;
    }
    const kelp_ivp_func *f = s->f[l];
    for (size_t i = 0; i < f->n; i++) {
        const kelp_ivp_piece *q = &f->pcs[i];
        int32_t plo[KELP_IVP_MAX_DIM], phi[KELP_IVP_MAX_DIM], a[KELP_IVP_MAX_DIM], b[KELP_IVP_MAX_DIM];
        double ps[KELP_IVP_MAX_DIM], ns[KELP_IVP_MAX_DIM];
        for (unsigned e = 0; e < dim; e++) {
            plo[e] = 0;
            phi[e] = (int32_t)s->dom->var[e].points - 1;
            ps[e] = 0;
        }
        double pc = q->cst;
        if (s->norm[l])
            pc = (pc + s->badj[l]) * s->radj[l];
        pc *= s->w[l];
        for (unsigned d = 0; d < f->dom.dim; d++) {
            double x = q->slope[d];
            if (s->norm[l])
                x *= s->radj[l];
            int m = s->map[l][d];
            plo[m] = q->lo[d];
            phi[m] = q->hi[d];
            ps[m] = x * s->w[l];
        }
        unsigned d;
        for (d = 0; d < dim; d++) {
            a[d] = lo[d] > plo[d] ? lo[d] : plo[d];
            b[d] = hi[d] < phi[d] ? hi[d] : phi[d];
            if (a[d] > b[d])
                break;
            ns[d] = l == 0 ? ps[d] : sl[d] + ps[d];
        }
        if (d < dim)
            continue;
        ref_rec(s, l + 1, a, b, ns, l == 0 ? pc : c + pc);
    }
}

/* Solve with kelp and with the reference; both must agree exactly (index, value bits, status). */
static void check_same(const kelp_ivp_domain *d, kelp_ivp_func *f, unsigned k)
{
    refw s;
    memset(&s, 0, sizeof s);
    s.dom = d;
    kelp_ivp_problem p;
    kelp_ivp_problem_init(&p, d);
    for (unsigned i = 0; i < k; i++) {
        ck_assert_int_eq(kelp_ivp_problem_add(&p, &f[i]), 0);
        ref_add(&s, &f[i]);
    }
    kelp_ivp_result r, rg;
    size_t ws = kelp_ivp_solve_work_size(&p), wg = kelp_ivp_solve_grid_work_size(&p);
    ck_assert_uint_le(ws, sizeof s_work);
    ck_assert_uint_ge(wg, ws);
    /* the grid path (when the domain allows it) must answer as the search alone */
    int rcg = wg <= sizeof s_work ? kelp_ivp_solve(&p, s_work, wg, &rg) : 1;
    int rc = kelp_ivp_solve(&p, s_work, ws, &r);
    if (rcg != 1) {
        ck_assert_int_eq(rcg, rc);
        if (rc == 0) {
            ck_assert_msg(rg.value == r.value, "grid value %a, search %a", rg.value, r.value);
            for (unsigned v = 0; v < d->dim; v++)
                ck_assert_uint_eq(rg.ix[v], r.ix[v]);
        }
    }
    if (s.k == 0) {
        ck_assert_int_eq(rc, KELP_ERR_EMPTY);
        return;
    }
    int32_t lo[KELP_IVP_MAX_DIM] = {0}, hi[KELP_IVP_MAX_DIM] = {0};
    double z[KELP_IVP_MAX_DIM] = {0};
    for (unsigned v = 0; v < d->dim; v++) {
        lo[v] = 0;
        hi[v] = (int32_t)d->var[v].points - 1;
    }
    ref_rec(&s, 0, lo, hi, z, 0);
    if (!s.found) {
        ck_assert_int_eq(rc, KELP_ERR_INFEASIBLE);
        return;
    }
    ck_assert_int_eq(rc, 0);
    ck_assert_msg(r.value == s.best, "value %a, reference %a", r.value, s.best);
    for (unsigned v = 0; v < d->dim; v++)
        ck_assert_msg(r.ix[v] == s.ix[v], "var %u: index %u, reference %u", v, r.ix[v], s.ix[v]);
}

/* ---------------------------------------------------------------- random functions */

/* A ZAIC_PEAK on var; tie: summit on a grid point, widths in whole steps, round utilities. */
static void mk_peak(kelp_ivp_func *out, kelp_ivp_piece *store, const kelp_ivp_domain *d, const char *var, bool tie)
{
    kelp_ivp_zaic_peak z;
    const kelp_ivp_var *v = &d->var[kelp_ivp_domain_index(d, var)];
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&z, d, var), 0);
    double span = v->high - v->low;
    double summit = tie ? v->low + v->delta * rn((int)v->points) : rr(v->low, v->high);
    double pw = tie ? v->delta * rn(4) * 2 : rr(0, span / 10);
    double bw = tie ? v->delta * (1 + rn(8)) * 4 : rr(span / 300, span / 3);
    double sd = tie ? (rn(2) ? 0 : 10 * rn(3)) : rr(0, 50);
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_params(&z, summit, pw, bw, sd, tie ? 0 : rn(20), 100, 0), 0);
    z.wrap = strcmp(var, "course") == 0 ? rn(4) != 0 : rn(4) == 0;
    z.insist = rn(2);
    if (rn(5) == 0) {
        int c = kelp_ivp_zaic_peak_add_component(&z);
        ck_assert_int_eq(c, 1);
        ck_assert_int_eq(kelp_ivp_zaic_peak_set_params(&z, v->low + v->delta * rn((int)v->points), pw, bw, 0, 0, 80, 1), 0);
    }
    ck_assert_int_eq(kelp_ivp_zaic_peak_extract(&z, rn(3) != 0, s_zw, CAP, store, CAP, out), 0);
}

static void mk_hleq(kelp_ivp_func *out, kelp_ivp_piece *store, const kelp_ivp_domain *d, const char *var)
{
    kelp_ivp_zaic_hleq z;
    const kelp_ivp_var *v = &d->var[kelp_ivp_domain_index(d, var)];
    ck_assert_int_eq(kelp_ivp_zaic_hleq_init(&z, rn(2) ? KELP_IVP_ZAIC_LEQ : KELP_IVP_ZAIC_HEQ, d, var), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_summit(&z, v->low + v->delta * rn((int)v->points)), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_basewidth(&z, v->delta * rn(20)), 0);
    if (rn(3) == 0)
        ck_assert_int_eq(kelp_ivp_zaic_hleq_set_summitdelta(&z, rn(20)), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_extract(&z, store, CAP, out), 0);
}

static void mk_couple(kelp_ivp_func *out, kelp_ivp_piece *store, const kelp_ivp_domain *d, const char *v1, const char *v2,
                      bool tie)
{
    kelp_ivp_func a, b;
    mk_peak(&a, s_tmpa, d, v1, tie);
    mk_peak(&b, s_tmpb, d, v2, tie);
    double wa = tie ? 25 * (1 + rn(3)) : 1 + rn(99), wb = tie ? 25 * (1 + rn(3)) : 1 + rn(99);
    ck_assert_int_eq(kelp_ivp_couple(&a, wa, &b, wb, rn(6) != 0, 0, 100, store, CAP, out), 0);
}

/* A tiling of axis-aligned slabs (the first variable's slabs innermost); sep 0: every piece its
 * own slopes and constant; 1: slopes and constants add per axis (a product of 1-D parts, split
 * exactly by the solver); 2: slopes per axis but constants not additive (the product's pieces
 * look coupled, the residual must carry the difference). real: non-integer coefficients (sums
 * that differ only by rounding). */
static void mk_tiling(kelp_ivp_func *f, kelp_ivp_piece *store, const kelp_ivp_domain *d, int sep, bool real)
{
    ck_assert_int_eq(kelp_ivp_func_init(f, d, store, CAP), 0);
    int32_t cuts[KELP_IVP_MAX_DIM][24];
    unsigned nc[KELP_IVP_MAX_DIM];
    double sv[KELP_IVP_MAX_DIM][24], cv[KELP_IVP_MAX_DIM][24];
    for (unsigned v = 0; v < d->dim; v++) {
        nc[v] = 0;
        int32_t x = 0;
        while (x < (int32_t)d->var[v].points) {
            sv[v][nc[v]] = (rn(5) - 2) * 0.5;
            cv[v][nc[v]] = rn(7) * 2;
            cuts[v][nc[v]++] = x;
            x += 1 + rn(d->var[v].points > 20 ? 12 : 4);
            if (nc[v] >= 22)
                x = (int32_t)d->var[v].points;
        }
        cuts[v][nc[v]] = (int32_t)d->var[v].points;
    }
    unsigned idx[KELP_IVP_MAX_DIM] = {0};
    for (;;) {
        int32_t lo[KELP_IVP_MAX_DIM], hi[KELP_IVP_MAX_DIM];
        double sl[KELP_IVP_MAX_DIM], c = sep == 1 ? 0 : rn(7) * 2;
        for (unsigned v = 0; v < d->dim; v++) {
            lo[v] = cuts[v][idx[v]];
            hi[v] = cuts[v][idx[v] + 1] - 1;
            sl[v] = sep ? sv[v][idx[v]] : (rn(5) - 2) * 0.5;
            if (real)
                sl[v] *= 1.0 + rn(1000) / 997.0;
            if (sep == 1)
                c += cv[v][idx[v]];
        }
        if (real)
            c += rn(1000) / 313.0;
        ck_assert_int_eq(kelp_ivp_func_add(f, lo, hi, sl, c), 0);
        unsigned v = 0;
        while (v < d->dim && ++idx[v] >= nc[v])
            idx[v++] = 0;
        if (v == d->dim)
            break;
    }
}

/* Random boxes: overlaps and holes (several leaves per point, uncovered points). */
static void mk_boxes(kelp_ivp_func *f, kelp_ivp_piece *store, const kelp_ivp_domain *d, int n)
{
    ck_assert_int_eq(kelp_ivp_func_init(f, d, store, CAP), 0);
    for (int i = 0; i < n; i++) {
        int32_t lo[KELP_IVP_MAX_DIM], hi[KELP_IVP_MAX_DIM];
        double sl[KELP_IVP_MAX_DIM];
        for (unsigned v = 0; v < d->dim; v++) {
            int32_t pts = (int32_t)d->var[v].points;
            lo[v] = rn(pts);
            hi[v] = lo[v] + rn(pts - lo[v]);
            sl[v] = (rn(5) - 2) * 0.5;
        }
        ck_assert_int_eq(kelp_ivp_func_add(f, lo, hi, sl, rn(7) * 2), 0);
    }
}

typedef struct gauss {
    double xc, yc, s, r;
} gauss;

static double aof_gauss(const double *pt, void *u)
{
    const gauss *g = u;
    double dx = pt[0] - g->xc, dy = pt[1] - g->yc;
    return g->r * exp(-(dx * dx + dy * dy) / (2 * g->s * g->s));
}

static gauss s_gs[NF];

/* ---------------------------------------------------------------- solver vs reference */

START_TEST(solver_random_vs_reference)
{
    rseed(1000u + (unsigned)_i);
    int fam = _i % 8;
    kelp_ivp_domain d;
    kelp_ivp_func f[NF];
    unsigned k = 0;
    bool tie = rn(3) != 0;
    switch (fam) {
    case 0: /* random tilings, small integer coefficients, 1 to 4 variables */
        d = mkdom((const char *[]){"a:0:9:10", "a:0:9:10,b:0:7:8", "a:0:9:10,b:0:7:8,c:0:4:5",
                                   "a:0:5:6,b:0:4:5,c:0:3:4,d:0:2:3"}[rn(4)]);
        k = 1 + (unsigned)rn(5);
        for (unsigned i = 0; i < k; i++)
            mk_tiling(&f[i], s_store[i], &d, 0, false);
        break;
    case 1: /* coupled ZAICs over course x speed (the helm's usual problem) */
        d = mkdom(rn(2) ? "course:0:359:360,speed:0:5:41" : "course:0:35:36,speed:0:5:11");
        k = 1 + (unsigned)rn(10);
        for (unsigned i = 0; i < k; i++)
            mk_couple(&f[i], s_store[i], &d, "course", "speed", tie);
        break;
    case 2: /* course x speed x depth: coupled plus depth/speed functions */
        d = mkdom(rn(2) ? "course:0:359:360,speed:0:5:41,depth:0:100:101" : "course:0:35:36,speed:0:5:11,depth:0:20:21");
        k = 2 + (unsigned)rn(8);
        for (unsigned i = 0; i < k; i++) {
            int t = rn(4);
            if (t == 0)
                mk_peak(&f[i], s_store[i], &d, "depth", tie);
            else if (t == 1)
                mk_hleq(&f[i], s_store[i], &d, rn(2) ? "depth" : "speed");
            else
                mk_couple(&f[i], s_store[i], &d, "course", "speed", tie);
        }
        break;
    case 3: /* non-separable Reflector functions among coupled ones */
        d = mkdom("course:0:59:60,speed:0:5:21");
        k = 1 + (unsigned)rn(5);
        for (unsigned i = 0; i < k; i++) {
            if (rn(2)) {
                gauss *g = &s_gs[i];
                *g = (gauss){rn(60), rn(6), 3 + rn(20), tie ? 100 : 50 + rn(100)};
                kelp_ivp_reflector r;
                ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, g), 0);
                ck_assert_int_gt(kelp_ivp_reflector_create(&r, 20 + rn(200), -1, 0, s_store[i], CAP, s_pq, CAP, &f[i]), 0);
            } else {
                mk_couple(&f[i], s_store[i], &d, "course", "speed", tie);
            }
        }
        break;
    case 4: /* overlapping boxes with holes: several leaves per point, sometimes infeasible */
        d = mkdom(rn(2) ? "a:0:9:10,b:0:7:8" : "a:0:9:10,b:0:7:8,c:0:3:4");
        k = 1 + (unsigned)rn(4);
        for (unsigned i = 0; i < k; i++)
            mk_boxes(&f[i], s_store[i], &d, 1 + rn(12));
        break;
    case 5: /* coupled with either variable outer, exact duplicates (ties everywhere) */
        d = mkdom("course:0:359:360,speed:0:5:41");
        k = 1 + (unsigned)rn(8);
        for (unsigned i = 0; i < k; i++) {
            if (rn(2))
                mk_couple(&f[i], s_store[i], &d, "speed", "course", tie);
            else
                mk_couple(&f[i], s_store[i], &d, "course", "speed", tie);
            if (rn(3) == 0 && i + 1 < k) {
                f[i + 1] = f[i];
                i++;
            }
        }
        break;
    case 6: /* problem variables in another order than the functions' */
        d = mkdom(rn(2) ? "speed:0:5:21,course:0:59:60" : "depth:0:20:21,course:0:59:60,speed:0:5:11");
        k = 1 + (unsigned)rn(6);
        for (unsigned i = 0; i < k; i++) {
            int t = rn(3);
            if (t == 0 && d.dim == 3)
                mk_peak(&f[i], s_store[i], &d, "depth", tie);
            else if (t == 1)
                mk_hleq(&f[i], s_store[i], &d, "speed");
            else
                mk_couple(&f[i], s_store[i], &d, "course", "speed", tie);
        }
        break;
    default: /* separable and non-separable tilings with non-integer coefficients */
        d = mkdom(rn(2) ? "a:0:59:60,b:0:19:20" : "a:0:19:20,b:0:9:10,c:0:9:10");
        k = 1 + (unsigned)rn(5);
        for (unsigned i = 0; i < k; i++)
            mk_tiling(&f[i], s_store[i], &d, rn(3), rn(3) == 0);
        break;
    }
    for (unsigned i = 0; i < k; i++) {
        f[i].pwt = tie ? 50.0 * (1 + rn(4)) : 1 + rn(300);
        if (rn(15) == 0)
            f[i].pwt = 0; /* ignored by the solver */
    }
    check_same(&d, f, k);
}
END_TEST

/* Ties: the first piece in stored order wins, not the lowest index; the high end of a flat box. */
START_TEST(solver_tie_stored_order)
{
    static kelp_ivp_piece st[2][4];
    kelp_ivp_domain d = mkdom("x:0:9:10");
    kelp_ivp_func f, g;
    const int32_t lo1[1] = {5}, hi1[1] = {9}, lo0[1] = {0}, hi0[1] = {4};
    const double s0[1] = {0};
    ck_assert_int_eq(kelp_ivp_func_init(&f, &d, st[0], 4), 0);
    ck_assert_int_eq(kelp_ivp_func_add(&f, lo1, hi1, s0, 10), 0);
    ck_assert_int_eq(kelp_ivp_func_add(&f, lo0, hi0, s0, 10), 0);
    kelp_ivp_problem p;
    kelp_ivp_result r;
    kelp_ivp_problem_init(&p, &d);
    ck_assert_int_eq(kelp_ivp_problem_add(&p, &f), 0);
    ck_assert_int_eq(kelp_ivp_solve(&p, s_work, sizeof s_work, &r), 0);
    ck_assert_uint_eq(r.ix[0], 9);
    /* the same pieces the other way round */
    ck_assert_int_eq(kelp_ivp_func_init(&g, &d, st[1], 4), 0);
    ck_assert_int_eq(kelp_ivp_func_add(&g, lo0, hi0, s0, 10), 0);
    ck_assert_int_eq(kelp_ivp_func_add(&g, lo1, hi1, s0, 10), 0);
    kelp_ivp_problem_init(&p, &d);
    ck_assert_int_eq(kelp_ivp_problem_add(&p, &g), 0);
    ck_assert_int_eq(kelp_ivp_solve(&p, s_work, sizeof s_work, &r), 0);
    ck_assert_uint_eq(r.ix[0], 4);
    ck_assert_double_eq(r.value, 1000);
    /* both functions: the leaves tie, the first (g's first piece inside f's first) wins */
    ck_assert_int_eq(kelp_ivp_problem_add(&p, &f), 0);
    ck_assert_int_eq(kelp_ivp_solve(&p, s_work, sizeof s_work, &r), 0);
    ck_assert_uint_eq(r.ix[0], 4);
    ck_assert_double_eq(r.value, 2000);
}
END_TEST

/* A later leaf better by rounding alone must replace the incumbent: leaf B sums
 * (0.1 + 0.2) + 0.15 = 0.45000000000000007 while the separable bound of its branch rounds to
 * 0.1 + (0.2 + 0.15) = 0.44999999999999996, below the incumbent A = 0.45. Pruning on the bound
 * without a rounding margin would keep A. */
START_TEST(solver_rounding_better_leaf_wins)
{
    static kelp_ivp_piece st[3][2];
    kelp_ivp_domain d = mkdom("x:0:1:2");
    kelp_ivp_func f[3];
    const double ca[3] = {0.45, 0, 0}, cb[3] = {0.1, 0.2, 0.15}, s0[1] = {0};
    const int32_t p0[1] = {0}, p1[1] = {1};
    kelp_ivp_problem p;
    kelp_ivp_problem_init(&p, &d);
    for (int i = 0; i < 3; i++) {
        ck_assert_int_eq(kelp_ivp_func_init(&f[i], &d, st[i], 2), 0);
        ck_assert_int_eq(kelp_ivp_func_add(&f[i], p0, p0, s0, ca[i]), 0);
        ck_assert_int_eq(kelp_ivp_func_add(&f[i], p1, p1, s0, cb[i]), 0);
        f[i].pwt = 1;
        ck_assert_int_eq(kelp_ivp_problem_add(&p, &f[i]), 0);
    }
    volatile double b0 = 0.1, b1 = 0.2, b2 = 0.15, a0 = 0.45;
    double leaf_b = (b0 + b1) + b2, bound_b = b0 + (b1 + b2);
    ck_assert(leaf_b > a0 && bound_b < a0); /* the premise of this test */
    kelp_ivp_result r;
    ck_assert_int_eq(kelp_ivp_solve(&p, s_work, sizeof s_work, &r), 0);
    ck_assert_uint_eq(r.ix[0], 1);
    ck_assert(r.value == leaf_b);
    check_same(&d, f, 3);
}
END_TEST

/* The 10-function bench problem of bench/ivp_2d.txt (coupled ZAICs on 360 x 41), rebuilt here
 * with the same specs, and variants with a shifted summit: every decision equals the walk's. */
START_TEST(solver_bench_problem_vs_reference)
{
    static const char *const lines[10] = {
        "pwt 120 couple 50 50 peak(summit=84.741,peakwidth=10,basewidth=90,summitdelta=0,minutil=0,maxutil=100,wrap) peak(summit=0.91,peakwidth=0.5,basewidth=1.5,summitdelta=20,minutil=0,maxutil=100)",
        "pwt 100 couple 50 50 peak(summit=23.879,peakwidth=0,basewidth=90,summitdelta=10,minutil=0,maxutil=100,wrap) peak(summit=2.11,peakwidth=0.5,basewidth=1.5,summitdelta=20,minutil=0,maxutil=100)",
        "pwt 50 couple 50 50 peak(summit=99.329,peakwidth=10,basewidth=90,summitdelta=0,minutil=0,maxutil=100,wrap) peak(summit=1.19,peakwidth=0.5,basewidth=1.5,summitdelta=20,minutil=0,maxutil=100)",
        "pwt 100 couple 50 50 peak(summit=297.582,peakwidth=0,basewidth=90,summitdelta=10,minutil=0,maxutil=100,wrap) peak(summit=3.73,peakwidth=0.5,basewidth=1.5,summitdelta=20,minutil=0,maxutil=100)",
        "pwt 100 couple 50 50 peak(summit=103.981,peakwidth=0,basewidth=180,summitdelta=10,minutil=0,maxutil=100,wrap) peak(summit=3.97,peakwidth=0.5,basewidth=1.5,summitdelta=20,minutil=0,maxutil=100)",
        "pwt 80 couple 50 50 peak(summit=241.141,peakwidth=0,basewidth=120,summitdelta=10,minutil=0,maxutil=100,wrap) peak(summit=2.52,peakwidth=0.5,basewidth=1.5,summitdelta=20,minutil=0,maxutil=100)",
        "pwt 200 couple 50 50 peak(summit=32.075,peakwidth=10,basewidth=90,summitdelta=10,minutil=0,maxutil=100,wrap) peak(summit=4.24,peakwidth=0.5,basewidth=1.5,summitdelta=20,minutil=0,maxutil=100)",
        "pwt 200 couple 50 50 peak(summit=205.480,peakwidth=0,basewidth=120,summitdelta=10,minutil=0,maxutil=100,wrap) peak(summit=4.03,peakwidth=0.5,basewidth=1.5,summitdelta=20,minutil=0,maxutil=100)",
        "pwt 80 couple 50 50 peak(summit=215.010,peakwidth=0,basewidth=120,summitdelta=10,minutil=0,maxutil=100,wrap) peak(summit=2.22,peakwidth=0.5,basewidth=1.5,summitdelta=20,minutil=0,maxutil=100)",
        "pwt 50 couple 50 50 peak(summit=291.721,peakwidth=10,basewidth=180,summitdelta=10,minutil=0,maxutil=100,wrap) peak(summit=0.67,peakwidth=0.5,basewidth=1.5,summitdelta=20,minutil=0,maxutil=100)",
    };
    kelp_ivp_domain d;
    kelp_diag e = {0};
    ck_assert_int_eq(kelp_ivp_file_domain("domain course:0:359:360,speed:0:5:41", &d, &e), 0);
    kelp_ivp_func f[NF];
    int vc, vs;
    ck_assert_int_eq(kelp_ivp_couple_vars(&d, &vc, &vs), 0);
    for (unsigned i = 0; i < 10; i++) {
        kelp_ivp_fileline fl;
        ck_assert_int_eq(kelp_ivp_file_line(lines[i], &d, &fl, &e), 0);
        ck_assert_int_eq(fl.kind, KELP_IVP_LINE_COUPLE);
        if (_i > 0) /* variants: move every course summit by _i degrees */
            fl.a.comp[0].summit = fmod(fl.a.comp[0].summit + 37.0 * _i, 360.0);
        kelp_ivp_func a, b;
        ck_assert_int_eq(kelp_ivp_spec_build(&fl.a, &d, d.var[vc].name, s_zw, CAP, &s_zws, s_tmpa, CAP, &a, &e), 0);
        ck_assert_int_eq(kelp_ivp_spec_build(&fl.b, &d, d.var[vs].name, s_zw, CAP, &s_zws, s_tmpb, CAP, &b, &e), 0);
        ck_assert_int_eq(kelp_ivp_couple(&a, fl.wc, &b, fl.ws, true, 0, 100, s_store[i], CAP, &f[i]), 0);
        f[i].pwt = fl.pwt;
    }
    if (_i == 0) { /* the figures bench/ivp.sh prints */
        kelp_ivp_problem p;
        kelp_ivp_result r;
        kelp_ivp_problem_init(&p, &d);
        for (unsigned i = 0; i < 10; i++)
            ck_assert_int_eq(kelp_ivp_problem_add(&p, &f[i]), 0);
        ck_assert_int_eq(kelp_ivp_solve(&p, s_work, sizeof s_work, &r), 0);
        ck_assert_uint_eq(r.ix[0], 32);
        ck_assert_uint_eq(r.ix[1], 32);
        ck_assert_double_eq_tol(r.value, 53124.323316980553, 1e-9);
    }
    check_same(&d, f, 10);
}
END_TEST

/* ---------------------------------------------------------------- ZAIC_PEAK vs a plain reference */

/* Seed 004 section 7.1.2, distance form, one component, evaluated point by point. */
static double ref_comp(const kelp_ivp_zaic_peak *z, const kelp_ivp_zaic_comp *c, double x)
{
    const kelp_ivp_var *v = &z->dom.var[0];
    double s = c->summit, pw = c->peakwidth, bw = c->basewidth, sd = pw <= 0 ? 0 : c->summitdelta, dist;
    if (!z->wrap) {
        dist = s >= x ? s - x : x - s;
    } else if (s > x) {
        double r = s - x, l = (x - v->low) + (v->high - s) + v->delta;
        dist = l < r ? l : r;
    } else {
        double l = x - s, r = (v->high - x) + (s - v->low) + v->delta;
        dist = l < r ? l : r;
    }
    double val;
    if (dist <= pw)
        val = sd <= 0 ? c->maxutil : c->maxutil - (sd / pw) * dist;
    else if (dist <= pw + bw)
        val = (c->maxutil - sd) - ((c->maxutil - sd - c->minutil) / bw) * (dist - pw);
    else
        val = c->minutil;
    return val > c->maxutil ? c->maxutil : val;
}

static int ref_push(kelp_ivp_piece *p, size_t *n, uint32_t a, uint32_t b, double slope, double cst)
{
    memset(&p[*n], 0, sizeof p[*n]);
    p[*n].lo[0] = (int32_t)a;
    p[*n].hi[0] = (int32_t)b;
    p[*n].slope[0] = slope;
    p[*n].cst = cst;
    (*n)++;
    return 0;
}

static void ref_run(kelp_ivp_piece *p, size_t *n, uint32_t a, uint32_t b, double va, double vb)
{
    double run = (double)b - (double)a, slope = run > 0 ? (vb - va) / run : 0.0;
    ref_push(p, n, a, b, slope, va - slope * (double)a);
}

/* extractIvPFunction: values, summit insist, then the greedy cut (tolerance 0.001, break on a
 * step against the run's slope; a break at the last point stores that point first). */
static size_t ref_peak(const kelp_ivp_zaic_peak *z, bool use_max, double *vals, kelp_ivp_piece *p)
{
    const kelp_ivp_var *v = &z->dom.var[0];
    uint32_t n = v->points;
    for (uint32_t i = 0; i < n; i++) {
        double x = ((double)i * v->delta) + v->low;
        if (z->ncomp == 1) {
            vals[i] = ref_comp(z, &z->comp[0], x);
            continue;
        }
        double best = 0, tot = 0;
        for (unsigned k = 0; k < z->ncomp; k++) {
            double c = ref_comp(z, &z->comp[k], x);
            best = k == 0 || c > best ? c : best;
            tot += c;
        }
        vals[i] = use_max ? best : tot;
    }
    for (unsigned k = 0; z->insist && k < z->ncomp; k++) {
        const kelp_ivp_zaic_comp *c = &z->comp[k];
        uint32_t i;
        for (i = 0; i < n && vals[i] == c->minutil; i++)
            ;
        if (i < n)
            continue;
        uint32_t bi = 0;
        double bd = 0;
        for (i = 0; i < n; i++) {
            double dd = fabs((((double)i * v->delta) + v->low) - c->summit);
            if (i == 0 || dd < bd) {
                bd = dd;
                bi = i;
            }
        }
        if (c->summit < v->low)
            bi = 0;
        else if (c->summit > v->high)
            bi = n - 1;
        vals[bi] = c->maxutil;
    }
    size_t np = 0;
    if (n == 1) {
        ref_push(p, &np, 0, 0, 0.0, vals[0]);
        return np;
    }
    uint32_t first = 0;
    bool trend = false;
    double s_m = 0, s_b = 0;
    for (uint32_t i = 1; i < n; i++) {
        double di = (double)i, vi = vals[i];
        if (!trend) {
            trend = true;
            s_m = (vi - vals[first]) / (double)(i - first);
            s_b = vi - s_m * di;
        }
        double loc_m = vi - vals[i - 1];
        bool brk = fabs((s_m * di + s_b) - vi) > 0.001 || (loc_m < 0 && s_m > 0) || (loc_m > 0 && s_m < 0);
        if (i == n - 1) {
            if (brk)
                ref_push(p, &np, i, i, 0.0, vi);
            else
                ref_run(p, &np, first, i, vals[first], vi);
        }
        if (brk) {
            ref_run(p, &np, first, i - 1, vals[first], vals[i - 1]);
            trend = false;
            first = i;
        }
    }
    return np;
}

static kelp_ivp_piece z_got[CAP], z_want[CAP];
static double z_vals[CAP];

START_TEST(zaic_peak_random_vs_reference)
{
    rseed(77000u + (unsigned)_i);
    for (int t = 0; t < 200; t++) {
        char ds[128];
        double low, high;
        unsigned pts;
        switch (rn(7)) {
        case 0: low = 0; high = 359; pts = 360; break;
        case 1: low = 0; high = 35.9; pts = 360; break;
        case 2: low = -rn(500); high = low + rn(1000) + 1; pts = 2 + (unsigned)rn(1200); break;
        case 3: low = rr(-10, 10); high = low + rr(0.001, 50); pts = 2 + (unsigned)rn(300); break;
        case 4: low = 3; high = 3; pts = 1 + (unsigned)rn(6); break;
        case 5: low = -1; high = 1; pts = 3 + (unsigned)rn(400); break;
        default: low = 0; high = 1; pts = 1 + (unsigned)rn(6); if (pts == 1) high = 0; break;
        }
        snprintf(ds, sizeof ds, "x:%.17g:%.17g:%u", low, high, pts);
        kelp_ivp_domain d = mkdom(ds);
        kelp_ivp_zaic_peak z;
        ck_assert_int_eq(kelp_ivp_zaic_peak_init(&z, &d, "x"), 0);
        unsigned nc = rn(4) == 0 ? 1 + (unsigned)rn(3) : 1;
        double span = high - low, delta = d.var[0].delta, period = span + delta;
        for (unsigned c = 0; c < nc; c++) {
            if (c > 0)
                ck_assert_int_eq(kelp_ivp_zaic_peak_add_component(&z), (int)c);
            int grid = rn(4); /* 0/3: on grid points and exact multiples of delta (exact ties) */
            double summit = grid == 0   ? low + delta * rn((int)pts)
                            : grid == 3 ? low + delta * rn((int)pts) + period / 2 * (rn(2) ? 1 : -1)
                                        : rr(low - span * 0.2, high + span * 0.2);
            bool g = grid == 0 || grid == 3;
            double pw = rn(4) == 0 ? 0 : (g ? delta * rn(10) : rr(0, span / 3));
            double bw = rn(5) == 0 ? 0 : (g ? delta * rn(40) : rr(0, span));
            double mn = rn(3) == 0 ? (rn(2) ? -0.0 : 0.0) : rr(-50, 50), mx = mn + (rn(3) == 0 ? 100 : rr(1e-6, 200));
            double sd = rn(3) == 0 ? 0 : rr(0, mx - mn);
            ck_assert_int_eq(kelp_ivp_zaic_peak_set_params(&z, summit, pw, bw, sd, mn, mx, c), 0);
            if (rn(10) == 0)
                z.comp[c].summitdelta = rr(0, 3 * (mx - mn)); /* past the setter's clip */
        }
        z.wrap = rn(2);
        z.insist = rn(2);
        bool use_max = rn(3) != 0;
        kelp_ivp_func f;
        ck_assert_int_eq(kelp_ivp_zaic_peak_extract(&z, use_max, z_vals, CAP, z_got, CAP, &f), 0);
        size_t nw = ref_peak(&z, use_max, z_vals, z_want);
        ck_assert_msg(f.n == nw, "%s: %zu pieces, reference %zu", ds, f.n, nw);
        for (size_t i = 0; i < nw; i++) {
            ck_assert_int_eq(f.pcs[i].lo[0], z_want[i].lo[0]);
            ck_assert_int_eq(f.pcs[i].hi[0], z_want[i].hi[0]);
            ck_assert_msg(memcmp(&f.pcs[i].slope[0], &z_want[i].slope[0], sizeof(double)) == 0, "%s piece %zu slope %a vs %a",
                          ds, i, f.pcs[i].slope[0], z_want[i].slope[0]);
            ck_assert_msg(memcmp(&f.pcs[i].cst, &z_want[i].cst, sizeof(double)) == 0, "%s piece %zu cst %a vs %a", ds, i,
                          f.pcs[i].cst, z_want[i].cst);
        }
        if (nw > 1) /* one piece short: a clear error, never a truncated function */
            ck_assert_int_eq(kelp_ivp_zaic_peak_extract(&z, use_max, z_vals, CAP, z_got, nw - 1, &f), KELP_ERR_NOSPACE);
    }
}
END_TEST

/* The grid path against brute force over the grid: 21 random functions over course x speed
 * (360 x 21, the helm's domain), each a tiling of random boxes with random planes (values in
 * [0,100], many plateaus at 0 and 100 as an avoidance function has). The optimum must be the
 * brute-force maximum of the weighted sum at every point, the decision a point reaching it, and
 * the answer the plain search's, bit for bit. Deterministic seeds. */
static kelp_ivp_piece bf_store[21][2560];

static void bf_tiling(kelp_ivp_func *f, kelp_ivp_piece *store, const kelp_ivp_domain *d)
{
    ck_assert_int_eq(kelp_ivp_func_init(f, d, store, 2560), 0);
    int32_t e0 = 3 + rn(30), e1 = 1 + rn(7);
    for (int32_t a = 0; a < (int32_t)d->var[0].points; a += e0)
        for (int32_t b = 0; b < (int32_t)d->var[1].points; b += e1) {
            int32_t lo[2] = {a, b}, hi[2] = {a + e0 - 1, b + e1 - 1};
            if (hi[0] >= (int32_t)d->var[0].points) hi[0] = (int32_t)d->var[0].points - 1;
            if (hi[1] >= (int32_t)d->var[1].points) hi[1] = (int32_t)d->var[1].points - 1;
            double sl[2] = {0, 0}, c;
            int kind = rn(4);
            if (kind == 0) {
                c = 0;
            } else if (kind == 1) {
                c = 100;
            } else { /* a plane from 0..100 at the low corner, staying in [0,100] over the box */
                double v0 = rr(0, 100), r0 = hi[0] - lo[0], r1 = hi[1] - lo[1];
                double room = (100 - v0) / 2, s0 = r0 > 0 ? rr(-v0 / 2, room) / r0 : 0, s1 = r1 > 0 ? rr(-v0 / 2, room) / r1 : 0;
                sl[0] = s0, sl[1] = s1;
                c = v0 - s0 * lo[0] - s1 * lo[1];
            }
            ck_assert_int_eq(kelp_ivp_func_add(f, lo, hi, sl, c), 0);
        }
}

START_TEST(solver_grid_vs_brute_force)
{
    rseed(9100u + (unsigned)_i);
    kelp_ivp_domain d = mkdom("course:0:359:360,speed:0:4:21");
    static kelp_ivp_func f[21];
    unsigned k = 21;
    kelp_ivp_problem p;
    kelp_ivp_problem_init(&p, &d);
    for (unsigned i = 0; i < k; i++) {
        bf_tiling(&f[i], bf_store[i], &d);
        f[i].pwt = i == 0 ? 100 : 50 + 10 * rn(16);
        ck_assert(kelp_ivp_func_tiles(&f[i]));
        ck_assert_int_eq(kelp_ivp_problem_add(&p, &f[i]), 0);
    }
    size_t wg = kelp_ivp_solve_grid_work_size(&p), ws = kelp_ivp_solve_work_size(&p);
    ck_assert_uint_gt(wg, ws);
    ck_assert_uint_le(wg, sizeof s_work);
    kelp_ivp_result rg, r;
    ck_assert_int_eq(kelp_ivp_solve(&p, s_work, wg, &rg), 0);
    /* brute force: every point, every function */
    double best = -INFINITY, at = 0;
    for (uint32_t a = 0; a < d.var[0].points; a++)
        for (uint32_t b = 0; b < d.var[1].points; b++) {
            uint32_t ix[2] = {a, b};
            double tot = 0;
            for (unsigned i = 0; i < k; i++) {
                double v;
                ck_assert_int_eq(kelp_ivp_func_eval(&f[i], ix, &v), 0);
                tot += v * f[i].pwt;
            }
            if (tot > best) best = tot;
            if (a == rg.ix[0] && b == rg.ix[1]) at = tot;
        }
    ck_assert_double_eq_tol(rg.value, best, 1e-7);
    ck_assert_double_eq_tol(at, best, 1e-7);
    if (_i < 3) { /* the plain search on these is slow (exponential in plateaus): a few only */
        ck_assert_int_eq(kelp_ivp_solve(&p, s_work, ws, &r), 0);
        ck_assert_msg(rg.value == r.value, "grid value %a, search %a", rg.value, r.value);
        ck_assert_uint_eq(rg.ix[0], r.ix[0]);
        ck_assert_uint_eq(rg.ix[1], r.ix[1]);
    }
}
END_TEST

Suite *kelp_ivp_solver_suite(void)
{
    Suite *s = suite_create("ivp_solver");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 60);
    tcase_add_loop_test(tc, solver_random_vs_reference, 0, 800);
    tcase_add_test(tc, solver_tie_stored_order);
    tcase_add_test(tc, solver_rounding_better_leaf_wins);
    tcase_add_loop_test(tc, solver_bench_problem_vs_reference, 0, 10);
    tcase_add_loop_test(tc, zaic_peak_random_vs_reference, 0, 50);
    tcase_add_loop_test(tc, solver_grid_vs_brute_force, 0, 20);
    suite_add_tcase(s, tc);
    return s;
}
