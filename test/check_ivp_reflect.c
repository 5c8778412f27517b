/* IvP unit tests: Reflector (seed 004 ch. 8-9 tables) and solver (ties against a reference). */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <string.h>
#include <stdlib.h>
#include <stdio.h>
#include <kelp/ivp.h>

static kelp_ivp_domain mkdom(const char *s)
{
    kelp_ivp_domain d;
    kelp_diag e = {0};
    ck_assert_int_eq(kelp_ivp_domain_parse(&d, s, &e), 0);
    return d;
}

typedef struct gauss {
    double xc, yc, sigma, range;
} gauss;

static double aof_gauss(const double *pt, void *user)
{
    const gauss *g = user;
    double dist = hypot(pt[0] - g->xc, pt[1] - g->yc);
    return g->range * exp(-(dist * dist) / (2 * g->sigma * g->sigma));
}

typedef struct lin {
    double m, n, b;
} lin;

static double aof_lin(const double *pt, void *user)
{
    const lin *l = user;
    return l->m * pt[0] + l->n * pt[1] + l->b;
}

static double aof_zero(const double *pt, void *user)
{
    (void)pt;
    (void)user;
    return 0;
}

#define BIG 40000
static kelp_ivp_piece r_store[BIG];
static kelp_ivp_pq_entry r_work[BIG];

static int create(kelp_ivp_reflector *r, int amount, kelp_ivp_func *f)
{
    return kelp_ivp_reflector_create(r, amount, -1, 0, r_store, BIG, r_work, BIG, f);
}

static size_t pcs_on(const kelp_ivp_domain *d, unsigned v, uint32_t e)
{
    return (d->var[v].points + e - 1) / e;
}

/* Table 3: x:200:299:1000, y:0:999:1000 */
START_TEST(uniform_table3)
{
    kelp_ivp_domain d = mkdom("x:200:299:1000,y:0:999:1000");
    const int req[] = {63, 64, 500, 512, 1000, 1024, 1025, 4000};
    const uint32_t ex[] = {112, 125, 46, 44, 32, 32, 32, 16}, ey[] = {143, 125, 46, 46, 33, 32, 32, 16};
    const size_t act[] = {63, 64, 484, 506, 992, 1024, 1024, 3969};
    const size_t px[] = {9, 8, 22, 23, 32, 32, 32, 63}, py[] = {7, 8, 22, 22, 31, 32, 32, 63};
    for (int i = 0; i < 8; i++) {
        uint32_t e[4];
        kelp_ivp_uniform_piece(&d, req[i], e);
        ck_assert_uint_eq(e[0], ex[i]);
        ck_assert_uint_eq(e[1], ey[i]);
        ck_assert_uint_eq(pcs_on(&d, 0, e[0]), px[i]);
        ck_assert_uint_eq(pcs_on(&d, 1, e[1]), py[i]);
        ck_assert_uint_eq(pcs_on(&d, 0, e[0]) * pcs_on(&d, 1, e[1]), act[i]);
    }
}
END_TEST

/* Table 4: x:200:299:1000, y:0:999:1000, z:0:99:100 */
START_TEST(uniform_table4)
{
    kelp_ivp_domain d = mkdom("x:200:299:1000,y:0:999:1000,z:0:99:100");
    const int req[] = {100, 200, 1000, 7500};
    const uint32_t sh[4][3] = {{100, 100, 100}, {72, 72, 100}, {46, 46, 50}, {23, 24, 25}}; /* row 1000: A21 */
    const size_t act[] = {100, 196, 968, 7392};
    const size_t pe[4][3] = {{10, 10, 1}, {14, 14, 1}, {22, 22, 2}, {44, 42, 4}};
    for (int i = 0; i < 4; i++) {
        uint32_t e[4];
        kelp_ivp_uniform_piece(&d, req[i], e);
        size_t n = 1;
        for (unsigned v = 0; v < 3; v++) {
            ck_assert_uint_eq(e[v], sh[i][v]);
            ck_assert_uint_eq(pcs_on(&d, v, e[v]), pe[i][v]);
            n *= pcs_on(&d, v, e[v]);
        }
        ck_assert_uint_eq(n, act[i]);
    }
}
END_TEST

START_TEST(uniform_fig24_26)
{
    kelp_ivp_domain d = mkdom("x:0:30:31,y:-50:50:21");
    gauss g = {15, 0, 10, 100};
    kelp_ivp_reflector r;
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "uniform_piece", "discrete @ x:5,y:5"), 0);
    ck_assert_int_eq(create(&r, -1, &f), 35);
    ck_assert(kelp_ivp_func_tiles(&f));
    /* the last column/row of tiles has one point */
    int last = 0;
    for (size_t i = 0; i < f.n; i++)
        if (f.pcs[i].lo[0] == 30 && f.pcs[i].hi[0] == 30)
            last++;
    ck_assert_int_eq(last, 5);
    for (int req = 35; req <= 39; req++) {
        ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
        ck_assert_int_eq(create(&r, req, &f), 35);
    }
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
    ck_assert_int_eq(create(&r, 40, &f), 40);
    uint32_t e[4];
    kelp_ivp_uniform_piece(&d, 40, e);
    ck_assert_uint_eq(e[0], 4);
    ck_assert_uint_eq(e[1], 5);
    /* 34: Listing 26 with the integer ratio stops at 8x4 pieces on the edges -> 8*4 = 32 */
    ck_assert_int_eq(create(&r, 34, &f), 32);
    /* Fig 26: explicit 6x4 -> 36 pieces; create(36) alone -> 35 */
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "uniform_piece", "native @ x:6,y:20"), 0);
    ck_assert_int_eq(create(&r, -1, &f), 36);
    ck_assert_int_eq(create(&r, 36, &f), 36); /* explicit piece wins over a count */
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
    ck_assert_int_eq(create(&r, 36, &f), 35);
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
    ck_assert_int_eq(create(&r, -1, &f), 1); /* neither: one piece */
    /* storage too small is an error */
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
    ck_assert_int_eq(kelp_ivp_reflector_create(&r, 35, -1, 0, r_store, 34, r_work, 34, &f), KELP_ERR_NOSPACE);
    ck_assert_uint_ge(kelp_ivp_reflector_max_pieces(&r, 35, -1), 35);
}
END_TEST

/* Table 2 layouts on a 500-point axis (A27) */
START_TEST(uniform_table2)
{
    kelp_ivp_domain d = mkdom("x:-250:249:500,y:-250:249:500");
    gauss g = {50, -150, 32.4, 150};
    const int edge[] = {3, 5, 7, 10, 15, 20, 25, 30, 40, 50, 75, 100};
    const int lay[] = {167, 100, 72, 50, 34, 25, 20, 17, 13, 10, 7, 5};
    for (int i = 0; i < 12; i++) {
        kelp_ivp_reflector r;
        kelp_ivp_func f;
        char s[64];
        ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
        snprintf(s, sizeof s, "discrete @ x:%d,y:%d", edge[i], edge[i]);
        ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "uniform_piece", s), 0);
        ck_assert_int_eq(create(&r, -1, &f), lay[i] * lay[i]);
    }
}
END_TEST

/* Table 5: directed refinement of -50..150 x -250..-50 on a 2x2 initial function (A28) */
START_TEST(directed_table5)
{
    kelp_ivp_domain d = mkdom("x:-250:249:500,y:-250:249:500");
    gauss g = {50, -150, 32.4, 150};
    const int edge[] = {4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    const int total[] = {2607, 1687, 1162, 847, 682, 535, 447, 367, 295, 262, 231, 202};
    for (int i = 0; i < 12; i++) {
        kelp_ivp_reflector r;
        kelp_ivp_func f;
        char s[64];
        ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
        ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "refine_region", "native @ x:-50:150,y:-250:-50"), 0);
        snprintf(s, sizeof s, "discrete @ x:%d,y:%d", edge[i], edge[i]);
        ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "refine_piece", s), 0);
        ck_assert_int_eq(create(&r, 4, &f), total[i]);
        ck_assert(kelp_ivp_func_tiles(&f));
    }
    /* Listing 27 on the Fig 25 domain */
    kelp_ivp_domain d25 = mkdom("x:0:30:31,y:-50:50:21");
    kelp_ivp_reflector r;
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d25, aof_gauss, &g), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "uniform_piece", "discrete @ x:5,y:5"), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "refine_region", "native @ x:10:24,y:-25:20"), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "refine_piece", "discrete @ x:2,y:2"), 0);
    ck_assert_int_gt(create(&r, -1, &f), 35);
    ck_assert(kelp_ivp_func_tiles(&f));
    for (size_t i = 0; i < f.n; i++)
        if (f.pcs[i].lo[0] >= 10 && f.pcs[i].hi[0] <= 24 && f.pcs[i].lo[1] >= 5 && f.pcs[i].hi[1] <= 14)
            ck_assert_int_le(f.pcs[i].hi[0] - f.pcs[i].lo[0], 1);
    /* pairing errors are fatal */
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d25, aof_gauss, &g), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "refine_piece", "discrete @ x:2,y:2"), KELP_ERR_STATE);
    ck_assert(!r.ok);
    ck_assert(r.warn[0] != '\0');
    ck_assert_int_eq(create(&r, 10, &f), KELP_ERR_STATE);
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d25, aof_gauss, &g), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "bogus", "1"), KELP_ERR_NOTFOUND);
    ck_assert(!r.ok);
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d25, aof_gauss, &g), 0);
    ck_assert_int_lt(kelp_ivp_reflector_set_paramf(&r, "uniform_amount", 0), 0);
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d25, aof_gauss, &g), 0);
    ck_assert_int_lt(kelp_ivp_reflector_set_param(&r, "uniform_piece", "discrete @ x:0,y:2"), 0);
}
END_TEST

/* Table 6: +75% smart pieces; smart_thresh; create(1000, 400, 0.5) */
START_TEST(smart_table6)
{
    kelp_ivp_domain d = mkdom("x:-250:249:500,y:-250:249:500");
    gauss g = {50, -150, 32.4, 150};
    const int edge[] = {15, 20, 25, 30, 40, 50, 75, 100};
    const int before[] = {1156, 625, 400, 289, 169, 100, 49, 25};
    const int after[] = {2023, 1093, 700, 505, 295, 175, 85, 43};
    for (int i = 0; i < 8; i++) {
        kelp_ivp_reflector r;
        kelp_ivp_func f;
        char s[64];
        ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
        snprintf(s, sizeof s, "discrete @ x:%d,y:%d", edge[i], edge[i]);
        ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "uniform_piece", s), 0);
        ck_assert_int_eq(create(&r, -1, &f), before[i]);
        ck_assert_int_eq(kelp_ivp_reflector_set_paramf(&r, "smart_percent", 75), 0);
        ck_assert_int_eq(create(&r, -1, &f), after[i]);
        ck_assert(kelp_ivp_func_tiles(&f));
    }
    kelp_ivp_reflector r;
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "smart_amount", "200"), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "smart_thresh", "1e9"), 0);
    ck_assert_int_eq(create(&r, 25, &f), 25);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "smart_thresh", "0"), 0);
    ck_assert_int_eq(create(&r, 25, &f), 225); /* Fig 30 */
    kelp_ivp_domain d1k = mkdom("x:0:999:1000,y:0:999:1000");
    g.xc = 500;
    g.yc = 400;
    g.sigma = 100;
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d1k, aof_gauss, &g), 0);
    int n = kelp_ivp_reflector_create(&r, 1000, 400, 0.5, r_store, BIG, r_work, BIG, &f);
    ck_assert_int_gt(n, 992);
    ck_assert_int_le(n, 992 + 400);
    kelp_ivp_reflector r2;
    kelp_ivp_func f2;
    ck_assert_int_eq(kelp_ivp_reflector_init(&r2, &d1k, aof_gauss, &g), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_paramf(&r2, "uniform_amount", 1000), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_paramf(&r2, "smart_amount", 400), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_paramf(&r2, "smart_thresh", 0.5), 0);
    ck_assert_int_eq(kelp_ivp_reflector_create(&r2, -1, -1, 0, r_store + 20000, 20000, r_work, 20000, &f2), n);
}
END_TEST

START_TEST(autopeak_linear_strict)
{
    kelp_ivp_domain d = mkdom("x:-250:249:500,y:-250:249:500");
    gauss g = {50, -150, 32.4, 150};
    kelp_ivp_reflector r;
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "auto_peak", "true"), 0);
    int n = create(&r, 100, &f);
    ck_assert_int_gt(n, 100);
    ck_assert(kelp_ivp_func_tiles(&f));
    size_t bi = 0;
    for (size_t i = 1; i < f.n; i++)
        if (kelp_ivp_piece_max(&f.pcs[i], 2) > kelp_ivp_piece_max(&f.pcs[bi], 2))
            bi = i;
    ck_assert_int_eq(f.pcs[bi].lo[0], f.pcs[bi].hi[0]);
    ck_assert_int_eq(f.pcs[bi].lo[1], f.pcs[bi].hi[1]);
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "auto_peak", "true"), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_paramf(&r, "auto_peak_max_pcs", 5), 0);
    ck_assert_int_eq(create(&r, 100, &f), 105);
    /* AOF_Linear: exact with any piece count, even one */
    lin l = {2.5, -1.25, 7};
    const int counts[] = {1, 4, 35, 100};
    for (int c = 0; c < 4; c++) {
        ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_lin, &l), 0);
        ck_assert_int_gt(create(&r, counts[c], &f), 0);
        for (uint32_t x = 0; x < 500; x += 7)
            for (uint32_t y = 0; y < 500; y += 11) {
                uint32_t ix[2] = {x, y};
                double v, pt[2] = {kelp_ivp_domain_value(&d, 0, x), kelp_ivp_domain_value(&d, 1, y)};
                ck_assert_int_eq(kelp_ivp_func_eval(&f, ix, &v), 0);
                ck_assert_double_eq_tol(v, aof_lin(pt, &l), 1e-9);
            }
    }
    /* strict_range: every piece stays within its sampled range */
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_gauss, &g), 0);
    ck_assert_int_gt(create(&r, 49, &f), 0);
    for (size_t i = 0; i < f.n; i++) {
        const kelp_ivp_piece *p = &f.pcs[i];
        double lo = INFINITY, hi = -INFINITY;
        for (unsigned c = 0; c < 4; c++) {
            double pt[2] = {kelp_ivp_domain_value(&d, 0, (uint32_t)((c & 1) ? p->hi[0] : p->lo[0])),
                            kelp_ivp_domain_value(&d, 1, (uint32_t)((c & 2) ? p->hi[1] : p->lo[1]))};
            double v = aof_gauss(pt, &g);
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
        double ct[2] = {kelp_ivp_domain_value(&d, 0, (uint32_t)((p->lo[0] + p->hi[0]) / 2)),
                        kelp_ivp_domain_value(&d, 1, (uint32_t)((p->lo[1] + p->hi[1]) / 2))};
        double cv = aof_gauss(ct, &g);
        lo = cv < lo ? cv : lo;
        hi = cv > hi ? cv : hi;
        ck_assert(kelp_ivp_piece_max(p, 2) <= hi + 1e-9);
        ck_assert(kelp_ivp_piece_min(p, 2) >= lo - 1e-9);
    }
    (void)aof_zero;
}
END_TEST

/* ---------------------------------------------------------------- solver */

/* Reference: enumerate every tuple in depth-first order with MOOS-IvP's arithmetic, keep the
 * first strictly best. Also the brute-force maximum over all points. */
typedef struct refstate {
    const kelp_ivp_func *f[8];
    unsigned k, dim;
    double w[8];
    bool found;
    double best;
    uint32_t ix[4];
} refstate;

static void ref_rec(refstate *s, unsigned l, const int32_t *lo, const int32_t *hi, const double *sl, double c)
{
    if (l == s->k) {
        double v = c;
        for (unsigned d = 0; d < s->dim; d++)
            v += sl[d] < 0 ? sl[d] * lo[d] : sl[d] * hi[d];
        if (!s->found || v > s->best) {
            s->found = true;
            s->best = v;
            for (unsigned d = 0; d < s->dim; d++)
                s->ix[d] = (uint32_t)(sl[d] < 0 ? lo[d] : hi[d]);
        }
        return;
    }
    const kelp_ivp_func *f = s->f[l];
    for (size_t i = 0; i < f->n; i++) {
        const kelp_ivp_piece *p = &f->pcs[i];
        int32_t a[4], b[4];
        double ns[4];
        unsigned d;
        for (d = 0; d < s->dim; d++) {
            a[d] = lo[d] > p->lo[d] ? lo[d] : p->lo[d];
            b[d] = hi[d] < p->hi[d] ? hi[d] : p->hi[d];
            if (a[d] > b[d])
                break;
            ns[d] = l == 0 ? p->slope[d] * s->w[l] : sl[d] + p->slope[d] * s->w[l];
        }
        if (d < s->dim)
            continue;
        ref_rec(s, l + 1, a, b, ns, l == 0 ? p->cst * s->w[l] : c + p->cst * s->w[l]);
    }
}

static kelp_ivp_piece s_store[8][512];
static unsigned char s_work[1 << 20];

START_TEST(solver_matches_reference)
{
    srand(1234u + (unsigned)_i);
    kelp_ivp_domain d = mkdom(_i % 2 ? "a:0:9:10,b:0:7:8" : "a:0:9:10,b:0:7:8,c:0:4:5");
    refstate s;
    memset(&s, 0, sizeof s);
    s.dim = d.dim;
    s.k = 2 + (unsigned)(rand() % 3);
    kelp_ivp_func f[8];
    for (unsigned i = 0; i < s.k; i++) {
        ck_assert_int_eq(kelp_ivp_func_init(&f[i], &d, s_store[i], 512), 0);
        /* random tiling: cut each axis into random slabs; small integer coefficients so ties happen */
        int32_t cuts[4][12];
        unsigned nc[4];
        for (unsigned v = 0; v < d.dim; v++) {
            nc[v] = 0;
            int32_t x = 0;
            while (x < (int32_t)d.var[v].points) {
                int32_t len = 1 + rand() % 4;
                cuts[v][nc[v]++] = x;
                x += len;
            }
            cuts[v][nc[v]] = (int32_t)d.var[v].points;
        }
        unsigned idx[4] = {0, 0, 0, 0};
        for (;;) {
            int32_t lo[4], hi[4];
            double sl[4];
            for (unsigned v = 0; v < d.dim; v++) {
                lo[v] = cuts[v][idx[v]];
                hi[v] = cuts[v][idx[v] + 1] - 1;
                if (hi[v] >= (int32_t)d.var[v].points)
                    hi[v] = (int32_t)d.var[v].points - 1;
                sl[v] = (double)(rand() % 5 - 2) * 0.5;
            }
            ck_assert_int_eq(kelp_ivp_func_add(&f[i], lo, hi, sl, (double)(rand() % 7) * 2), 0);
            unsigned v = 0;
            while (v < d.dim && ++idx[v] >= nc[v])
                idx[v++] = 0;
            if (v == d.dim)
                break;
        }
        f[i].pwt = (double)(1 + rand() % 3) * 10;
        s.f[i] = &f[i];
        s.w[i] = f[i].pwt;
    }
    for (unsigned i = 0; i < s.k; i++)
        ck_assert(kelp_ivp_func_tiles(&f[i]));
    int32_t lo[4], hi[4];
    double z[4] = {0, 0, 0, 0};
    for (unsigned v = 0; v < d.dim; v++) {
        lo[v] = 0;
        hi[v] = (int32_t)d.var[v].points - 1;
    }
    ref_rec(&s, 0, lo, hi, z, 0);
    kelp_ivp_problem p;
    kelp_ivp_problem_init(&p, &d);
    for (unsigned i = 0; i < s.k; i++)
        ck_assert_int_eq(kelp_ivp_problem_add(&p, &f[i]), 0);
    kelp_ivp_result r;
    ck_assert_uint_le(kelp_ivp_solve_work_size(&p), sizeof s_work);
    ck_assert_int_eq(kelp_ivp_solve(&p, s_work, sizeof s_work, &r), 0);
    ck_assert(s.found);
    ck_assert_double_eq(r.value, s.best);
    for (unsigned v = 0; v < d.dim; v++)
        ck_assert_uint_eq(r.ix[v], s.ix[v]);
    /* brute force over every point: same maximum */
    double bmax = -INFINITY;
    uint32_t ix[4] = {0, 0, 0, 0};
    for (;;) {
        double tot = 0;
        for (unsigned i = 0; i < s.k; i++) {
            double v;
            ck_assert_int_eq(kelp_ivp_func_eval(&f[i], ix, &v), 0);
            tot += v * f[i].pwt;
        }
        bmax = tot > bmax ? tot : bmax;
        unsigned v = 0;
        while (v < d.dim && ++ix[v] >= d.var[v].points)
            ix[v++] = 0;
        if (v == d.dim)
            break;
    }
    ck_assert_double_eq_tol(r.value, bmax, 1e-9);
    ck_assert_int_eq(kelp_ivp_solve(&p, s_work, kelp_ivp_solve_work_size(&p) - 1, &r), KELP_ERR_NOSPACE);
}
END_TEST

START_TEST(solver_plateau_weights_normalise)
{
    static kelp_ivp_piece st[16];
    kelp_ivp_domain d = mkdom("depth:0:600:601");
    kelp_ivp_zaic_hleq z;
    kelp_ivp_func f, g;
    ck_assert_int_eq(kelp_ivp_zaic_hleq_init(&z, KELP_IVP_ZAIC_LEQ, &d, "depth"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_summit(&z, 150), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_basewidth(&z, 60), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_extract(&z, st, 4, &f), 0);
    kelp_ivp_problem p;
    kelp_ivp_result r;
    kelp_ivp_problem_init(&p, &d);
    ck_assert_int_eq(kelp_ivp_problem_add(&p, &f), 0);
    for (int t = 0; t < 3; t++) { /* deterministic: the high end of the plateau */
        ck_assert_int_eq(kelp_ivp_solve(&p, s_work, sizeof s_work, &r), 0);
        ck_assert_uint_eq(r.ix[0], 150);
        ck_assert_double_eq_tol(r.val[0], 150, 1e-12);
        ck_assert_double_eq_tol(r.value, 100 * 100, 1e-9);
    }
    /* a function with pwt <= 0 does not count */
    ck_assert_int_eq(kelp_ivp_zaic_hleq_init(&z, KELP_IVP_ZAIC_HEQ, &d, "depth"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_summit(&z, 400), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_extract(&z, st + 4, 4, &g), 0);
    g.pwt = 0;
    ck_assert_int_eq(kelp_ivp_problem_add(&p, &g), 0);
    ck_assert_uint_eq(p.nf, 1);
    ck_assert_int_eq(kelp_ivp_solve(&p, s_work, sizeof s_work, &r), 0);
    ck_assert_uint_eq(r.ix[0], 150);
    /* range > 100 is normalised to [0,100] before the weight: LEQ 20..500 */
    ck_assert_int_eq(kelp_ivp_zaic_hleq_init(&z, KELP_IVP_ZAIC_LEQ, &d, "depth"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_summit(&z, 150), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_minmaxutil(&z, 20, 500), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_extract(&z, st + 8, 4, &g), 0);
    g.pwt = 50;
    kelp_ivp_problem_init(&p, &d);
    ck_assert_int_eq(kelp_ivp_problem_add(&p, &g), 0);
    ck_assert_int_eq(kelp_ivp_solve(&p, s_work, sizeof s_work, &r), 0);
    ck_assert_double_eq_tol(r.value, 50 * 100, 1e-9);
    kelp_ivp_problem_init(&p, &d);
    ck_assert_int_eq(kelp_ivp_solve(&p, s_work, sizeof s_work, &r), KELP_ERR_EMPTY);
    kelp_ivp_domain other = mkdom("depth:0:500:101");
    kelp_ivp_problem_init(&p, &other);
    ck_assert_int_eq(kelp_ivp_problem_add(&p, &f), KELP_ERR_RANGE);
    ck_assert_int_ne(p.diag.code, KELP_OK);
}
END_TEST

/* FILE lines */
START_TEST(file_lines)
{
    kelp_ivp_domain d;
    kelp_diag e = {0};
    kelp_ivp_fileline fl;
    ck_assert_int_eq(kelp_ivp_file_domain("domain course:0:359:360,speed:0:5:41", &d, &e), 0);
    ck_assert_int_eq(kelp_ivp_file_line("pwt 100 couple 50 50 peak(summit=90,basewidth=180,wrap) peak(summit=2, basewidth=1)", &d, &fl, &e), 0);
    ck_assert_int_eq(fl.kind, KELP_IVP_LINE_COUPLE);
    ck_assert(fl.a.wrap);
    ck_assert_double_eq(fl.b.comp[0].basewidth, 1);
    ck_assert_int_eq(kelp_ivp_file_line("pwt 50 speed leq(summit=3,basewidth=1)", &d, &fl, &e), 0);
    ck_assert_int_eq(fl.kind, KELP_IVP_LINE_SPEC);
    ck_assert_int_eq(kelp_ivp_file_line("pwt 50 raw speed,course 2", &d, &fl, &e), 0);
    ck_assert_uint_eq(fl.nvars, 2);
    ck_assert_int_eq(fl.vars[0], 1);
    ck_assert_uint_eq(fl.npieces, 2);
    static kelp_ivp_piece st[4];
    kelp_ivp_domain sub;
    ck_assert_int_eq(kelp_ivp_domain_sub(&d, "speed,course", &sub), 0);
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_func_init(&f, &sub, st, 2), 0);
    ck_assert_int_eq(kelp_ivp_file_piece("0 40 0 179 0.5 0 10", 2, &f, &e), 0);
    ck_assert_int_eq(kelp_ivp_file_piece("0 40 180 359 -0.5 0.25 3", 2, &f, &e), 0);
    ck_assert_int_eq(kelp_ivp_file_piece("0 40 180 359 -0.5 0.25 3", 2, &f, &e), KELP_ERR_NOSPACE);
    const char *bad[] = {"pwt x speed leq(summit=1)", "weight 5 speed leq(summit=1)", "pwt 5 depth leq(summit=1)",
                         "pwt 5 couple 0 50 peak(summit=1) peak(summit=1)", "pwt 5 raw speed,speed 1",
                         "pwt 5 raw speed 0", "pwt 5 speed leq(summit=1) extra", "pwt 5 couple 50 50 peak(summit=1)"};
    for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        kelp_diag_clear(&e);
        ck_assert_int_lt(kelp_ivp_file_line(bad[i], &d, &fl, &e), 0);
        ck_assert_int_ne(e.code, KELP_OK);
    }
    kelp_diag_clear(&e);
    ck_assert_int_lt(kelp_ivp_file_line("pwt 5 depth leq(summit=1)", &d, &fl, &e), 0);
#ifndef KELP_NO_ERRMSG
    ck_assert(strstr(e.msg, "'depth'") != NULL);
#endif
    /* the diagnostic: code, the place a caller adds, and the token-naming message (first wins) */
    kelp_diag_clear(&e);
    ck_assert_int_eq(kelp_ivp_file_line("pwt x speed leq(summit=1)", &d, &fl, &e), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_ivp_file_line("pwt 5 depth leq(summit=1)", &d, &fl, &e), KELP_ERR_NOTFOUND);
    ck_assert_int_eq(kelp_diag_where(&e, 3, 0), KELP_ERR_PARSE);
    ck_assert_int_eq(e.code, KELP_ERR_PARSE);
    ck_assert_int_eq(e.line, 3);
#ifndef KELP_NO_ERRMSG
    ck_assert_str_eq(kelp_diag_text(&e), "file: bad pwt 'x'");
#else
    ck_assert_str_eq(kelp_diag_text(&e), kelp_err_str(KELP_ERR_PARSE));
#endif
    kelp_diag_clear(&e);
    ck_assert_int_eq(kelp_ivp_spec_parse(&fl.a, "peak(summit=1,summit=2)", &e), KELP_ERR_PARSE);
    ck_diag_msg(&e, "spec: repeated parameter 'summit'");
    ck_assert_int_eq(kelp_ivp_spec_parse(&fl.a, "peak(summit=1)", NULL), 0);
    ck_assert_int_eq(kelp_ivp_spec_parse(&fl.a, "peak(", NULL), KELP_ERR_PARSE);
    const char *badp[] = {"0 40 0", "0 41 0 1 0 0 0", "5 4 0 1 0 0 0", "0 40 0 1 a 0 0", "0 40 0 1 0 0 0 9"};
    ck_assert_int_eq(kelp_ivp_func_init(&f, &sub, st, 4), 0);
    for (unsigned i = 0; i < sizeof badp / sizeof badp[0]; i++)
        ck_assert_int_lt(kelp_ivp_file_piece(badp[i], 2, &f, &e), 0);
    ck_assert_uint_eq(f.n, 0);
}
END_TEST

/* A capped bump (flat at both caps, sloped between), for the line sampler's test. */
static double aof_capped(const double *pt, void *user)
{
    const gauss *g = user;
    double v = aof_gauss(pt, user);
    return v > 0.8 * g->range ? 0.8 * g->range : v < 0.1 * g->range ? 0.1 * g->range : v;
}

static unsigned line_calls;

static void line_capped(const double *pt, unsigned d, const double *x, unsigned n, double *out, void *user)
{
    double q[2] = {pt[0], pt[1]};
    line_calls++;
    for (unsigned i = 0; i < n; i++) {
        q[d] = x[i];
        out[i] = aof_capped(q, user);
    }
}

/* The line sampler gives the point-by-point build's pieces, bit for bit: uniform pieces of
 * several shapes (tiles clipped at the domain's end, one point wide, more tiles per row than
 * one chunk), strict and not; a scored build (smart refinement) does not use it. */
START_TEST(line_sampler_same_pieces)
{
    static kelp_ivp_piece a[4096], b[4096];
    static kelp_ivp_pq_entry w[4096];
    const char *doms[] = {"x:0:359:360,y:0:4:21", "x:-10:10:41,y:0:1:7", "x:0:3:4,y:0:30:31"};
    const char *shapes[] = {"discrete @ x:3,y:3", "discrete @ x:1,y:2", "discrete @ x:4,y:1", "discrete @ x:2,y:5"};
    for (unsigned di = 0; di < 3; di++)
        for (unsigned si = 0; si < 4; si++)
            for (int strict = 0; strict < 2; strict++) {
                kelp_ivp_domain d = mkdom(doms[di]);
                gauss g = {d.var[0].low + 0.3 * (d.var[0].high - d.var[0].low), 2.0, 0.2 * (d.var[0].high - d.var[0].low), 100};
                kelp_ivp_reflector r;
                kelp_ivp_func fa, fb;
                ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_capped, &g), 0);
                ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "uniform_piece", shapes[si]), 0);
                ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "strict_range", strict ? "true" : "false"), 0);
                int na = kelp_ivp_reflector_create(&r, -1, -1, 0, a, 4096, w, 4096, &fa);
                kelp_ivp_reflector_set_line(&r, line_capped);
                line_calls = 0;
                int nb = kelp_ivp_reflector_create(&r, -1, -1, 0, b, 4096, w, 4096, &fb);
                ck_assert_int_gt(na, 0);
                ck_assert_int_eq(na, nb);
                ck_assert_uint_gt(line_calls, 0);
                for (int i = 0; i < na; i++) {
                    ck_assert_msg(a[i].lo[0] == b[i].lo[0] && a[i].hi[0] == b[i].hi[0] && a[i].lo[1] == b[i].lo[1] &&
                                      a[i].hi[1] == b[i].hi[1],
                                  "%s %s piece %d: bounds differ", doms[di], shapes[si], i);
                    ck_assert_msg(memcmp(a[i].slope, b[i].slope, sizeof a[i].slope) == 0 && memcmp(&a[i].cst, &b[i].cst, sizeof a[i].cst) == 0,
                                  "%s %s piece %d: %.17g %.17g %.17g vs %.17g %.17g %.17g", doms[di], shapes[si], i,
                                  a[i].slope[0], a[i].slope[1], a[i].cst, b[i].slope[0], b[i].slope[1], b[i].cst);
                }
            }
    /* a scored build samples point by point */
    kelp_ivp_domain d = mkdom("x:0:20:21,y:0:20:21");
    gauss g = {5, 5, 4, 100};
    kelp_ivp_reflector r;
    kelp_ivp_func fb;
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &d, aof_capped, &g), 0);
    kelp_ivp_reflector_set_line(&r, line_capped);
    line_calls = 0;
    ck_assert_int_gt(kelp_ivp_reflector_create(&r, 20, 10, 0, b, 4096, w, 4096, &fb), 0);
    ck_assert_uint_eq(line_calls, 0);
}
END_TEST

Suite *kelp_ivp_reflect_suite(void)
{
    Suite *s = suite_create("ivp_reflect");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 180); /* seconds under -O2; ASan on a loaded machine took over 60 */
    tcase_add_test(tc, uniform_table3);
    tcase_add_test(tc, uniform_table4);
    tcase_add_test(tc, uniform_fig24_26);
    tcase_add_test(tc, uniform_table2);
    tcase_add_test(tc, directed_table5);
    tcase_add_test(tc, smart_table6);
    tcase_add_test(tc, autopeak_linear_strict);
    tcase_add_loop_test(tc, solver_matches_reference, 0, 60);
    tcase_add_test(tc, solver_plateau_weights_normalise);
    tcase_add_test(tc, file_lines);
    tcase_add_test(tc, line_sampler_same_pieces);
    suite_add_tcase(s, tc);
    return s;
}
