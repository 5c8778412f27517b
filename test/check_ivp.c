/* IvP unit tests: every numeric example of seed 004 chapters 6-9 (spec/ivp.md section 7). */
#include <check.h>
#include <math.h>
#include <string.h>
#include <kelp/ivp.h>

#define TOL 1e-4

static kelp_ivp_domain dom1(const char *s)
{
    kelp_ivp_domain d;
    kelp_diag e = {0};
    ck_assert_int_eq(kelp_ivp_domain_parse(&d, s, &e), 0);
    return d;
}

static kelp_ivp_piece g_store[4096];
static double g_work[4096];
static kelp_ivp_spec_ws g_zws; /* spec_build's ZAIC_PEAK workspace */

static double fval(const kelp_ivp_func *f, uint32_t ix)
{
    double v = NAN;
    ck_assert_int_eq(kelp_ivp_func_eval(f, &ix, &v), 0);
    return v;
}

/* build a spec string over a one-variable domain */
static kelp_ivp_func spec_func(const char *dom, const char *spec)
{
    kelp_ivp_domain d = dom1(dom);
    kelp_ivp_spec sp;
    kelp_diag e = {0};
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_spec_parse(&sp, spec, &e), 0);
    ck_assert_int_eq(kelp_ivp_spec_build(&sp, &d, d.var[0].name, g_work, 4096, &g_zws, g_store, 4096, &f, &e), 0);
    ck_assert(kelp_ivp_func_tiles(&f));
    return f;
}

/* ---------------------------------------------------------------- domain (tests 1-4) */
/* the tiling check answers no to a gap, an overlap, a piece outside the domain */
START_TEST(tiles_gap_overlap_outside)
{
    kelp_ivp_domain d;
    kelp_diag e = {0};
    ck_assert_int_eq(kelp_ivp_domain_parse(&d, "x:0:9:10,y:0:4:5", &e), 0);
    kelp_ivp_piece store[8];
    kelp_ivp_func f;
    const double sl[2] = {0, 0};
    const int32_t lo1[2] = {0, 0}, hi1[2] = {4, 4}, lo2[2] = {5, 0}, hi2[2] = {9, 4};
    ck_assert_int_eq(kelp_ivp_func_init(&f, &d, store, 8), 0);
    ck_assert_int_eq(kelp_ivp_func_add(&f, lo1, hi1, sl, 1), 0);
    ck_assert(!kelp_ivp_func_tiles(&f)); /* half the domain */
    ck_assert_int_eq(kelp_ivp_func_add(&f, lo2, hi2, sl, 2), 0);
    ck_assert(kelp_ivp_func_tiles(&f)); /* two halves */
    /* an overlap that keeps the volume: x 0..5 and 5..9 on row 0 miss (4,0)... as bounds */
    store[0].hi[0] = 5;
    store[1].lo[0] = 5, store[1].hi[1] = 3; /* volumes 30 + 20 = 50, (5,0) twice, (5..9,4) never */
    ck_assert(!kelp_ivp_func_tiles(&f));
    store[0].hi[0] = 4, store[1].lo[0] = 5, store[1].hi[1] = 4;
    ck_assert(kelp_ivp_func_tiles(&f));
    store[1].hi[0] = 10; /* outside the domain */
    ck_assert(!kelp_ivp_func_tiles(&f));
}
END_TEST

START_TEST(domain_listing16)
{
    kelp_ivp_domain d;
    kelp_ivp_domain_init(&d);
    ck_assert_int_eq(kelp_ivp_domain_add(&d, "course", 0, 359, 360), 0);
    ck_assert_int_eq(kelp_ivp_domain_add(&d, "speed", 0, 3, 16), 0);
    ck_assert_int_eq(kelp_ivp_domain_add(&d, "depth", 0, 500, 101), 0);
    ck_assert_uint_eq(d.dim, 3);
    ck_assert_double_eq(kelp_ivp_domain_total(&d), 581760);
    ck_assert_double_eq_tol(d.var[1].delta, 0.2, 1e-12);
    ck_assert_double_eq_tol(d.var[2].delta, 5, 1e-12);
    ck_assert_int_eq(kelp_ivp_domain_add(&d, "speed", 0, 3, 16), KELP_ERR_EXISTS);
    kelp_ivp_domain e;
    kelp_ivp_domain_init(&e);
    ck_assert_int_eq(kelp_ivp_domain_add(&e, "x", 5, 4, 3), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_ivp_domain_add(&e, "x", 0, 4, 0), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_ivp_domain_add(&e, "x", 0, 4, 1), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_ivp_domain_add(&e, "x", 4, 4, 1), 0);
    /* sub-domains */
    kelp_ivp_domain s;
    ck_assert_int_eq(kelp_ivp_domain_sub(&d, "depth", &s), 0);
    ck_assert_uint_eq(s.dim, 1);
    ck_assert_str_eq(s.var[0].name, "depth");
    ck_assert_uint_eq(s.var[0].points, 101);
    ck_assert_int_eq(kelp_ivp_domain_sub(&d, "depth,foo", &s), KELP_ERR_NOTFOUND);
    ck_assert_uint_eq(s.dim, 0);
    ck_assert_int_eq(kelp_ivp_domain_sub(&d, "course,speed,depth", &s), 0);
    ck_assert_uint_eq(s.dim, 3);
    ck_assert(kelp_ivp_domain_is_sub(&s, &d));
    kelp_ivp_domain bad = dom1("depth:0:100:101");
    ck_assert(!kelp_ivp_domain_is_sub(&bad, &d));
    kelp_ivp_domain ok = dom1("depth:0:500:101");
    ck_assert(kelp_ivp_domain_is_sub(&ok, &d));
}
END_TEST

START_TEST(domain_values_and_snap)
{
    kelp_ivp_domain d = dom1("x:0:30:31,y:-50:50:21");
    ck_assert_double_eq_tol(kelp_ivp_domain_value(&d, 1, 12), 10.0, 1e-12);
    ck_assert_double_eq_tol(kelp_ivp_domain_value(&d, 0, 22), 22.0, 1e-12);
    /* IvPDomain::getDiscreteVal examples: x:0:20:41, y:2:7:11 */
    kelp_ivp_domain g = dom1("x:0:20:41,y:2:7:11");
    ck_assert_uint_eq(kelp_ivp_domain_snap(&g, 0, 2.1, KELP_IVP_SNAP_FLOOR), 4);
    ck_assert_uint_eq(kelp_ivp_domain_snap(&g, 0, 2.1, KELP_IVP_SNAP_CEIL), 5);
    ck_assert_uint_eq(kelp_ivp_domain_snap(&g, 0, 2.1, KELP_IVP_SNAP_NEAREST), 4);
    ck_assert_uint_eq(kelp_ivp_domain_snap(&g, 1, 2.1, KELP_IVP_SNAP_FLOOR), 0);
    ck_assert_uint_eq(kelp_ivp_domain_snap(&g, 1, 2.1, KELP_IVP_SNAP_CEIL), 1);
    ck_assert_uint_eq(kelp_ivp_domain_snap(&g, 1, 2.3, KELP_IVP_SNAP_NEAREST), 1);
    ck_assert_uint_eq(kelp_ivp_domain_snap(&g, 0, -5, KELP_IVP_SNAP_NEAREST), 0);
    ck_assert_uint_eq(kelp_ivp_domain_snap(&g, 0, 99, KELP_IVP_SNAP_NEAREST), 40);
}
END_TEST

static const char *bad_domains[] = {"", "x:0:1", "x:a:1:2", "x:0:1:2,x:0:1:2", "x:1:0:2", "x:0:1:0", ":0:1:2",
                                    "x:0:1:2,", "x:0:1:2.5", "a:0:1:2,b:0:1:2,c:0:1:2,d:0:1:2,e:0:1:2"};
START_TEST(domain_bad_text)
{
    kelp_ivp_domain d;
    kelp_diag e = {0};
    ck_assert_int_lt(kelp_ivp_domain_parse(&d, bad_domains[_i], &e), 0);
    ck_assert_int_ne(e.code, KELP_OK);
}
END_TEST

/* ---------------------------------------------------------------- strings (tests 5-7) */
START_TEST(strings_shape_point_region)
{
    kelp_ivp_domain d = dom1("x:0:30:31,y:-50:50:21");
    kelp_diag e = {0};
    uint32_t a[4], b[4];
    ck_assert_int_eq(kelp_ivp_parse_shape(&d, "discrete @ x:5,y:5", a, &e), 0);
    ck_assert_int_eq(kelp_ivp_parse_shape(&d, "native @ x:5,y:25", b, &e), 0);
    ck_assert_uint_eq(a[0], 5);
    ck_assert_uint_eq(a[1], 5);
    ck_assert_uint_eq(b[0], 5);
    ck_assert_uint_eq(b[1], 5);
    ck_assert_int_eq(kelp_ivp_parse_shape(&d, "native @ x:5,y:22.6", b, &e), 0);
    ck_assert_uint_eq(b[1], 5);
    ck_assert_int_eq(kelp_ivp_parse_shape(&d, "native @ x:5,y:22.4", b, &e), 0);
    ck_assert_uint_eq(b[1], 4);
    ck_assert_int_eq(kelp_ivp_parse_shape(&d, "native @ x:5,y:22.5", b, &e), 0);
    ck_assert_uint_eq(b[1], 5);
    ck_assert_int_eq(kelp_ivp_parse_shape(&d, "discrete @ x:6,y:4", a, &e), 0);
    ck_assert_int_eq(kelp_ivp_parse_shape(&d, "native @ x:6,y:20", b, &e), 0);
    ck_assert_uint_eq(a[0], b[0]);
    ck_assert_uint_eq(a[1], b[1]);
    ck_assert_int_eq(kelp_ivp_parse_point(&d, "discrete @ x:22,y:12", a, &e), 0);
    ck_assert_int_eq(kelp_ivp_parse_point(&d, "native @ x:22,y:10", b, &e), 0);
    ck_assert_uint_eq(a[0], 22);
    ck_assert_uint_eq(a[1], 12);
    ck_assert_uint_eq(b[0], 22);
    ck_assert_uint_eq(b[1], 12);
    int32_t lo[4], hi[4];
    const char *same[] = {"native @ x:10:24,y:-25:20", "discrete @ x:10:24,y:5:14", "native @ x:9.01:24.99, y:-29.99:24.99"};
    for (int i = 0; i < 3; i++) {
        ck_assert_int_eq(kelp_ivp_parse_region(&d, same[i], lo, hi, &e), 0);
        ck_assert_int_eq(lo[0], 10);
        ck_assert_int_eq(hi[0], 24);
        ck_assert_int_eq(lo[1], 5);
        ck_assert_int_eq(hi[1], 14);
    }
    ck_assert_int_eq(kelp_ivp_parse_region(&d, "native @ x:10:24, y:-25:50", lo, hi, &e), 0);
    ck_assert_int_eq(hi[1], 20);
    ck_assert_int_eq(kelp_ivp_parse_region(&d, "native @ x:10:24, y:-25:50000", lo, hi, &e), 0);
    ck_assert_int_eq(lo[1], 5);
    ck_assert_int_eq(hi[1], 20);
    /* clear errors naming the token */
    ck_assert_int_lt(kelp_ivp_parse_shape(&d, "discrete @ x:5,z:5", a, &e), 0);
#ifndef KELP_NO_ERRMSG
    ck_assert(strstr(e.msg, "'z'") != NULL);
#endif
    kelp_diag_clear(&e);
    ck_assert_int_lt(kelp_ivp_parse_shape(&d, "fuzzy @ x:5,y:5", a, &e), 0);
#ifndef KELP_NO_ERRMSG
    ck_assert(strstr(e.msg, "fuzzy") != NULL);
#endif
    kelp_diag_clear(&e);
    ck_assert_int_lt(kelp_ivp_parse_shape(&d, "discrete @ x:5", a, &e), 0);
    kelp_diag_clear(&e);
    ck_assert_int_lt(kelp_ivp_parse_point(&d, "discrete @ x:31,y:0", a, &e), 0);
    kelp_diag_clear(&e);
    ck_assert_int_lt(kelp_ivp_parse_region(&d, "native @ x:31:40,y:0:1", lo, hi, &e), 0);
}
END_TEST

/* ---------------------------------------------------------------- ZAIC_PEAK (tests 25-33) */
START_TEST(peak_tp1_fig13)
{
    kelp_ivp_func f = spec_func("x:0:359:360", "peak(summit=180,peakwidth=85,basewidth=70,summitdelta=40,minutil=25,maxutil=150)");
    ck_assert_uint_eq(f.n, 6);
    const uint32_t x[] = {0, 24, 25, 60, 94, 95, 137, 180, 181, 222, 265, 266, 300, 335, 336, 359};
    const double v[] = {25, 25, 25, 67.5, 108.7857, 110, 129.7647, 150, 149.5294, 130.2353, 110, 108.7857, 67.5, 25, 25, 25};
    for (int i = 0; i < 16; i++)
        ck_assert_double_eq_tol(fval(&f, x[i]), v[i], TOL);
    /* upstream piecing [0,25] [26,95] [96,180] [181,265] [266,335] [336,359] */
    ck_assert_int_eq(f.pcs[0].hi[0], 25);
    ck_assert_int_eq(f.pcs[1].hi[0], 95);
    ck_assert_int_eq(f.pcs[2].hi[0], 180);
    ck_assert_int_eq(f.pcs[3].hi[0], 265);
}
END_TEST

START_TEST(peak_tp2_fig12)
{
    kelp_ivp_func f = spec_func("depth:0:200:201", "peak(summit=100,peakwidth=20,basewidth=20,summitdelta=0)");
    ck_assert_uint_eq(f.n, 5);
    const uint32_t x[] = {59, 60, 70, 79, 80, 100, 120, 121, 130, 140, 141};
    const double v[] = {0, 0, 50, 95, 100, 100, 100, 95, 50, 0, 0};
    for (int i = 0; i < 11; i++)
        ck_assert_double_eq_tol(fval(&f, x[i]), v[i], TOL);
}
END_TEST

START_TEST(peak_tp3_speed)
{
    kelp_ivp_func f = spec_func("speed:0:4:21", "peak(summit=2,peakwidth=0.5,basewidth=1,summitdelta=0.8)");
    const double v[] = {0, 0, 0, 9.92, 29.76, 49.6, 69.44, 89.28, 99.36, 99.68, 100,
                        99.68, 99.36, 89.28, 69.44, 49.6, 29.76, 9.92, 0, 0, 0};
    ck_assert_uint_eq(f.n, 6);
    for (uint32_t i = 0; i < 21; i++)
        ck_assert_double_eq_tol(fval(&f, i), v[i], TOL);
    kelp_ivp_func g = spec_func("speed:0:3:31", "peak(summit=2,peakwidth=0.5,basewidth=1,summitdelta=0.8)");
    ck_assert_uint_eq(g.n, 5);
}
END_TEST

START_TEST(peak_tp4_course_wrap)
{
    kelp_ivp_func f = spec_func("course:0:359:360", "peak(summit=123.690068,peakwidth=0,basewidth=180,summitdelta=0,wrap)");
    ck_assert_uint_eq(f.n, 3);
    ck_assert_double_eq_tol(fval(&f, 123), 99.6166, TOL);
    ck_assert_double_eq_tol(fval(&f, 124), 99.8278, TOL);
    ck_assert_double_eq_tol(fval(&f, 125), 99.2723, TOL);
    ck_assert_int_eq(f.pcs[0].hi[0], 123);
    ck_assert_int_eq(f.pcs[1].hi[0], 303);
    kelp_ivp_func g = spec_func("course:0:359:360", "peak(summit=90,peakwidth=0,basewidth=180,summitdelta=0,wrap)");
    ck_assert_uint_eq(g.n, 3);
    ck_assert_double_eq_tol(fval(&g, 0), 50, TOL);
    ck_assert_double_eq_tol(fval(&g, 90), 100, TOL);
    ck_assert_double_eq_tol(fval(&g, 180), 50, TOL);
    ck_assert_double_eq_tol(fval(&g, 270), 0, TOL);
    ck_assert_double_eq_tol(fval(&g, 359), 49.444, 1e-3);
    kelp_ivp_func h = spec_func("course:0:359:360", "peak(summit=0,peakwidth=0,basewidth=180,summitdelta=0,wrap)");
    ck_assert_uint_eq(h.n, 2);
    kelp_ivp_func k = spec_func("course:0:359:360", "peak(summit=180,peakwidth=0,basewidth=180,summitdelta=0,wrap)");
    ck_assert_uint_eq(k.n, 2);
}
END_TEST

START_TEST(peak_wrap_derived)
{
    kelp_ivp_func f = spec_func("c:0:359:360", "peak(summit=350,peakwidth=0,basewidth=30,summitdelta=0,minutil=0,maxutil=100,wrap)");
    ck_assert_double_eq_tol(fval(&f, 10), 100.0 * (1 - 20.0 / 30.0), TOL);
    ck_assert_double_eq_tol(fval(&f, 350), 100, TOL);
    ck_assert_double_eq_tol(fval(&f, 20), 0, TOL);
    kelp_ivp_func g = spec_func("c:0:359:360", "peak(summit=350,peakwidth=0,basewidth=30,summitdelta=0,minutil=0,maxutil=100)");
    ck_assert_double_eq_tol(fval(&g, 10), 0, TOL);
}
END_TEST

START_TEST(peak_tp5_insist)
{
    /* case 1: 90.25 on 0..359, widths 0 */
    kelp_ivp_func f = spec_func("h:0:359:360", "peak(summit=90.25,peakwidth=0,basewidth=0,insist)");
    ck_assert_uint_eq(f.n, 3);
    ck_assert_double_eq_tol(fval(&f, 90), 100, TOL);
    ck_assert_double_eq_tol(fval(&f, 89), 0, TOL);
    ck_assert_double_eq_tol(fval(&f, 91), 0, TOL);
    kelp_ivp_func g = spec_func("h:0:359:360", "peak(summit=90.25,peakwidth=0,basewidth=0)");
    for (uint32_t i = 0; i < 360; i++)
        ck_assert_double_eq(fval(&g, i), 0);
    /* case 2: 4.0 on 0..3 (31 points), widths 0.25 */
    kelp_ivp_func h = spec_func("s:0:3:31", "peak(summit=4,peakwidth=0.25,basewidth=0.25,insist)");
    ck_assert_uint_eq(h.n, 2);
    ck_assert_double_eq_tol(fval(&h, 30), 100, TOL);
    ck_assert_double_eq_tol(fval(&h, 29), 0, TOL);
    kelp_ivp_func k = spec_func("s:0:3:31", "peak(summit=4,peakwidth=0.25,basewidth=0.25)");
    for (uint32_t i = 0; i < 31; i++)
        ck_assert_double_eq(fval(&k, i), 0);
}
END_TEST

START_TEST(peak_tp6_multimodal)
{
    const uint32_t x[] = {0, 120, 121, 200, 220, 300, 380, 381, 450, 470, 471, 500, 600, 730, 750, 765, 766};
    const double mx[] = {0, 0, 0.85, 68, 85, 100, 85, 84.15, 50.142857, 117, 117.230769, 123.923077, 147, 117, 50.142857, 0, 0};
    const double sm[] = {0, 0, 0.85, 68, 85, 100, 85, 84.15, 75.642857, 125.5, 124.880769, 123.923077, 147, 117, 50.142857, 0, 0};
    kelp_ivp_domain d = dom1("x:0:1000:1001");
    kelp_ivp_zaic_peak z;
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&z, &d, "x"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_params(&z, 300, 80, 100, 15, 0, 100, 0), 0);
    int idx = kelp_ivp_zaic_peak_add_component(&z);
    ck_assert_int_eq(idx, 1);
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_params(&z, 600, 130, 35, 30, 0, 147, (unsigned)idx), 0);
    z.wrap = false;
    z.insist = true;
    kelp_ivp_func f, g;
    ck_assert_int_eq(kelp_ivp_zaic_peak_extract(&z, true, g_work, 4096, g_store, 2048, &f), 0);
    for (int i = 0; i < 17; i++)
        ck_assert_double_eq_tol(fval(&f, x[i]), mx[i], TOL);
    ck_assert_uint_eq(f.n, 10);
    ck_assert_int_eq(kelp_ivp_zaic_peak_extract(&z, false, g_work, 4096, g_store + 2048, 2048, &g), 0);
    for (int i = 0; i < 17; i++)
        ck_assert_double_eq_tol(fval(&g, x[i]), sm[i], TOL);
    ck_assert_uint_eq(g.n, 11);
    /* the same through the text form */
    kelp_ivp_func h = spec_func("x:0:1000:1001",
                                "peak(summit=300,peakwidth=80,basewidth=100,summitdelta=15,minutil=0,maxutil=100,insist,sum)"
                                "+peak(summit=600,peakwidth=130,basewidth=35,summitdelta=30,minutil=0,maxutil=147)");
    for (int i = 0; i < 17; i++)
        ck_assert_double_eq_tol(fval(&h, x[i]), sm[i], TOL);
}
END_TEST

START_TEST(peak_tp8_listing17)
{
    kelp_ivp_domain d;
    kelp_ivp_domain_init(&d);
    ck_assert_int_eq(kelp_ivp_domain_add(&d, "depth", 0, 600, 601), 0);
    kelp_ivp_zaic_peak z;
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&z, &d, "depth"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_summit(&z, 150, 0), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_minmaxutil(&z, 20, 120, 0), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_basewidth(&z, 60, 0), 0);
    ck_assert(z.ok);
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_zaic_peak_extract(&z, true, g_work, 4096, g_store, 4096, &f), 0);
    const uint32_t x[] = {0, 90, 120, 149, 150, 151, 180, 210, 600};
    const double v[] = {20, 20, 70, 118.3333, 120, 118.3333, 70, 20, 20};
    for (int i = 0; i < 9; i++)
        ck_assert_double_eq_tol(fval(&f, x[i]), v[i], TOL);
    ck_assert_uint_eq(f.n, 4);
}
END_TEST

START_TEST(peak_defaults_and_errors)
{
    kelp_ivp_domain d = dom1("x:0:359:360");
    kelp_ivp_zaic_peak z;
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&z, &d, "x"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_add_component(&z), 1);
    ck_assert_int_eq(kelp_ivp_zaic_peak_add_component(&z), 2);
    ck_assert_double_eq(z.comp[1].summitdelta, 50);
    ck_assert_double_eq(z.comp[1].maxutil, 100);
    /* a default component on a domain containing 0: max at 0, min elsewhere (sdelta ignored, pw=0) */
    kelp_ivp_zaic_peak y;
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&y, &d, "x"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_add_component(&y), 1);
    ck_assert_double_eq(kelp_ivp_zaic_peak_value(&y, 0, true), 100);
    ck_assert_double_eq(kelp_ivp_zaic_peak_value(&y, 1, true), 0);
    /* T-P7 */
    kelp_ivp_zaic_peak w;
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&w, &d, "x"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_summit(&w, 550, 0), 0);
    ck_assert(w.ok);
    ck_assert(w.warn[0] != '\0');
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_minmaxutil(&w, 0, 100, 0), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_summitdelta(&w, 200, 0), 0);
    ck_assert_double_eq(w.comp[0].summitdelta, 100);
    ck_assert(w.ok);
    ck_assert_int_lt(kelp_ivp_zaic_peak_set_summitdelta(&w, -1, 0), 0);
    ck_assert(!w.ok);
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_zaic_peak_extract(&w, true, g_work, 4096, g_store, 4096, &f), KELP_ERR_STATE);
    kelp_ivp_zaic_peak u;
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&u, &d, "x"), 0);
    ck_assert_int_lt(kelp_ivp_zaic_peak_set_minmaxutil(&u, 50, 50, 0), 0);
    ck_assert(!u.ok);
    kelp_ivp_zaic_peak t;
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&t, &d, "x"), 0);
    ck_assert_int_lt(kelp_ivp_zaic_peak_set_summit(&t, 10, 5), 0);
    ck_assert(!t.ok);
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&t, &d, "nope"), KELP_ERR_NOTFOUND);
    ck_assert(!t.ok);
    /* too little storage: an error, never a truncated function */
    kelp_ivp_zaic_peak s;
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&s, &d, "x"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_params(&s, 180, 85, 70, 40, 25, 150, 0), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_extract(&s, true, g_work, 4096, g_store, 5, &f), KELP_ERR_NOSPACE);
    ck_assert_int_eq(kelp_ivp_zaic_peak_extract(&s, true, g_work, 100, g_store, 100, &f), KELP_ERR_NOSPACE);
}
END_TEST

/* ---------------------------------------------------------------- LEQ / HEQ (tests 34-35) */
START_TEST(leq_heq_fig18_19)
{
    kelp_ivp_func f = spec_func("depth:0:600:601", "leq(summit=150,basewidth=60,minutil=20,maxutil=120)");
    ck_assert_uint_eq(f.n, 3);
    const uint32_t x[] = {0, 150, 151, 160, 180, 200, 209, 210, 211, 600};
    const double v[] = {120, 120, 118.3333, 103.3333, 70, 36.6667, 21.6667, 20, 20, 20};
    for (int i = 0; i < 10; i++)
        ck_assert_double_eq_tol(fval(&f, x[i]), v[i], TOL);
    kelp_ivp_func g = spec_func("depth:0:600:601", "leq(summit=150,basewidth=0,minutil=20,maxutil=120)");
    ck_assert_uint_eq(g.n, 2);
    ck_assert_int_eq(g.pcs[0].hi[0], 150);
    ck_assert_double_eq(fval(&g, 150), 120);
    ck_assert_double_eq(fval(&g, 151), 20);
    kelp_ivp_func h = spec_func("depth:0:600:601", "heq(summit=150,basewidth=60,minutil=20,maxutil=120)");
    ck_assert_uint_eq(h.n, 3);
    const uint32_t hx[] = {0, 89, 90, 100, 120, 140, 149, 150, 600};
    const double hv[] = {20, 20, 20, 36.6667, 70, 103.3333, 118.3333, 120, 120};
    for (int i = 0; i < 9; i++)
        ck_assert_double_eq_tol(fval(&h, hx[i]), hv[i], TOL);
    kelp_ivp_func k = spec_func("depth:0:600:601", "heq(summit=150,basewidth=0,minutil=20,maxutil=120)");
    ck_assert_uint_eq(k.n, 2);
    ck_assert_double_eq(fval(&k, 150), 120); /* seed: x >= summit gets maxutil */
    ck_assert_double_eq(fval(&k, 149), 20);
    /* a domain whose low is not 0 (upstream ignores low) */
    kelp_ivp_func m = spec_func("d:100:700:601", "leq(summit=250,basewidth=60,minutil=20,maxutil=120)");
    ck_assert_double_eq(fval(&m, 150), 120);
    ck_assert_double_eq_tol(fval(&m, 180), 70, TOL);
    /* tiny base width: no NaN */
    kelp_ivp_func n = spec_func("d:0:600:601", "leq(summit=150.4,basewidth=0.2,minutil=0,maxutil=100)");
    for (uint32_t i = 0; i < 601; i++)
        ck_assert(isfinite(fval(&n, i)));
    /* summit at the domain low: every point covered */
    kelp_ivp_func o = spec_func("d:0:600:601", "heq(summit=0,basewidth=0,minutil=0,maxutil=100)");
    ck_assert_double_eq(fval(&o, 0), 100);
    kelp_ivp_func q = spec_func("d:0:600:601", "leq(summit=0,basewidth=30,minutil=0,maxutil=100)");
    ck_assert_double_eq(fval(&q, 0), 100);
}
END_TEST

/* ZAIC_LEQ/HEQ at the domain's edges, as MOOS-IvP builds them (ZAIC_LEQ/ZAIC_HEQ
 * setPointLocations/setPDMap): summit and ramp end snapped to indices and clipped, slope from
 * the whole base width, line through the summit utility at the summit index unless that index
 * is 0 (then through the other end's utility at the other end). Domain x:0:10:11, util 0..100.
 * NAN in a table = no piece covers the point (HEQ with its summit at or beyond the last index). */
static void hleq_expect(kelp_ivp_zaic_kind kind, double summit, double bw, double sd, const double want[11])
{
    kelp_ivp_domain d = dom1("x:0:10:11");
    kelp_ivp_zaic_hleq z;
    ck_assert_int_eq(kelp_ivp_zaic_hleq_init(&z, kind, &d, "x"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_summit(&z, summit), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_basewidth(&z, bw), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_minmaxutil(&z, 0, 100), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_summitdelta(&z, sd), 0);
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_zaic_hleq_extract(&z, g_store, 8, &f), 0);
    for (uint32_t i = 0; i < 11; i++) {
        double v = NAN;
        int rc = kelp_ivp_func_eval(&f, &i, &v);
        if (isnan(want[i])) {
            ck_assert_msg(rc == KELP_ERR_NOTFOUND, "%s summit=%g bw=%g sd=%g: point %u should have no piece, has %g",
                          kind == KELP_IVP_ZAIC_LEQ ? "LEQ" : "HEQ", summit, bw, sd, i, v);
        } else {
            ck_assert_msg(rc == 0 && fabs(v - want[i]) < 1e-6, "%s summit=%g bw=%g sd=%g: point %u is %g, want %g",
                          kind == KELP_IVP_ZAIC_LEQ ? "LEQ" : "HEQ", summit, bw, sd, i, rc ? NAN : v, want[i]);
        }
    }
}

START_TEST(leq_heq_edges)
{
    const double N = NAN, t = 100.0 / 3, s = 100.0 / 6;
    /* LEQ, summit below the domain: index 0 at max, the ramp keeps its 6-wide slope and ends at 3 */
    hleq_expect(KELP_IVP_ZAIC_LEQ, -3, 6, 0, (const double[11]){ 100, 2 * s, s, 0, 0, 0, 0, 0, 0, 0, 0 });
    /* ... and with a summit delta (no summit point inside the domain: no spike) */
    hleq_expect(KELP_IVP_ZAIC_LEQ, -3, 6, 10, (const double[11]){ 100, 2 * s, s, 0, 0, 0, 0, 0, 0, 0, 0 });
    /* LEQ, base width past both ends: slope 100/20, line through (10, 0) */
    hleq_expect(KELP_IVP_ZAIC_LEQ, -2, 20, 0, (const double[11]){ 100, 45, 40, 35, 30, 25, 20, 15, 10, 5, 0 });
    /* LEQ, summit on the low end */
    hleq_expect(KELP_IVP_ZAIC_LEQ, 0, 4, 0, (const double[11]){ 100, 75, 50, 25, 0, 0, 0, 0, 0, 0, 0 });
    /* LEQ, summit next to the low end with a delta: index 1 gets no spike */
    hleq_expect(KELP_IVP_ZAIC_LEQ, 1, 3, 10, (const double[11]){ 100, 100, 2 * t, t, 0, 0, 0, 0, 0, 0, 0 });
    /* LEQ, summit just inside with a delta: the spike */
    hleq_expect(KELP_IVP_ZAIC_LEQ, 2, 4, 10, (const double[11]){ 100, 100, 110, 75, 50, 25, 0, 0, 0, 0, 0 });
    /* LEQ, ramp past the high end: cut, slope kept */
    hleq_expect(KELP_IVP_ZAIC_LEQ, 8, 5, 0, (const double[11]){ 100, 100, 100, 100, 100, 100, 100, 100, 100, 80, 60 });
    /* LEQ, summit above the domain: all max, the clipped summit index takes the delta */
    hleq_expect(KELP_IVP_ZAIC_LEQ, 12, 5, 10, (const double[11]){ 100, 100, 100, 100, 100, 100, 100, 100, 100, 100, 110 });
    hleq_expect(KELP_IVP_ZAIC_LEQ, 12, 5, 0, (const double[11]){ 100, 100, 100, 100, 100, 100, 100, 100, 100, 100, 100 });
    /* LEQ, zero base width */
    hleq_expect(KELP_IVP_ZAIC_LEQ, 5, 0, 0, (const double[11]){ 100, 100, 100, 100, 100, 100, 0, 0, 0, 0, 0 });
    /* HEQ, summit above the domain: ramp 7..9 on its 6-wide slope, the last index has no piece */
    hleq_expect(KELP_IVP_ZAIC_HEQ, 13, 6, 0, (const double[11]){ 0, 0, 0, 0, 0, 0, 0, 0, s, 2 * s, N });
    /* HEQ, summit on the high end with a delta */
    hleq_expect(KELP_IVP_ZAIC_HEQ, 10, 4, 5, (const double[11]){ 0, 0, 0, 0, 0, 0, 0, 25, 50, 75, N });
    /* HEQ, summit next to the high end with a delta: no spike */
    hleq_expect(KELP_IVP_ZAIC_HEQ, 9, 2, 5, (const double[11]){ 0, 0, 0, 0, 0, 0, 0, 0, 50, 100, 100 });
    /* HEQ, summit just inside with a delta: the spike */
    hleq_expect(KELP_IVP_ZAIC_HEQ, 8, 3, 5, (const double[11]){ 0, 0, 0, 0, 0, 0, t, 2 * t, 105, 100, 100 });
    /* HEQ, ramp past the low end: line through (2, 100) */
    hleq_expect(KELP_IVP_ZAIC_HEQ, 2, 5, 0, (const double[11]){ 60, 80, 100, 100, 100, 100, 100, 100, 100, 100, 100 });
    /* HEQ, summit below the domain: all max, the clipped summit index takes the delta */
    hleq_expect(KELP_IVP_ZAIC_HEQ, -4, 3, 5, (const double[11]){ 105, 100, 100, 100, 100, 100, 100, 100, 100, 100, 100 });
    hleq_expect(KELP_IVP_ZAIC_HEQ, -4, 3, 0, (const double[11]){ 100, 100, 100, 100, 100, 100, 100, 100, 100, 100, 100 });
    /* HEQ, base width past both ends: slope 100/30, line through (10, 100); index 10 has no piece */
    hleq_expect(KELP_IVP_ZAIC_HEQ, 15, 30, 0,
                (const double[11]){ 100 - 1000.0 / 30 * 1, 100 - 900.0 / 30, 100 - 800.0 / 30, 100 - 700.0 / 30,
                                    100 - 600.0 / 30, 100 - 500.0 / 30, 100 - 400.0 / 30, 100 - 300.0 / 30,
                                    100 - 200.0 / 30, 100 - 100.0 / 30, N });
}
END_TEST

START_TEST(leq_errors)
{
    kelp_ivp_domain d = dom1("depth:0:600:601");
    kelp_ivp_zaic_hleq z;
    ck_assert_int_eq(kelp_ivp_zaic_hleq_init(&z, KELP_IVP_ZAIC_LEQ, &d, "depth"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_summit(&z, 650), 0);
    ck_assert_double_eq(z.summit, 650); /* kept; the domain cuts the function, not the summit */
    ck_assert(z.ok);
    ck_assert(z.warn[0] != '\0');
    ck_assert_int_lt(kelp_ivp_zaic_hleq_set_basewidth(&z, -1), 0);
    ck_assert(!z.ok);
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_zaic_hleq_extract(&z, g_store, 4, &f), KELP_ERR_STATE);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_init(&z, KELP_IVP_ZAIC_LEQ, &d, "depth"), 0);
    ck_assert_int_lt(kelp_ivp_zaic_hleq_set_minmaxutil(&z, 120, 20), 0);
    ck_assert(!z.ok);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_init(&z, KELP_IVP_ZAIC_HEQ, &d, "x"), KELP_ERR_NOTFOUND);
    ck_assert(!z.ok);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_init(&z, KELP_IVP_ZAIC_LEQ, &d, "depth"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_summit(&z, 150), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_set_basewidth(&z, 60), 0);
    ck_assert_int_eq(kelp_ivp_zaic_hleq_extract(&z, g_store, 2, &f), KELP_ERR_NOSPACE);
}
END_TEST

static const char *bad_specs[] = {"", "peak", "peak(", "peak(summit=1", "pk(summit=1)", "peak(summit=x)",
                                  "peak(summit=1,summit=2)", "peak(foo=1)", "leq(peakwidth=3)", "leq(summit=1,wrap)",
                                  "peak(summit=1) junk", "peak(summit=1)+leq(summit=2)", "peak(summit=1,)",
                                  "peak(summit=1e999)", "peak(wrap,wrap)"};
START_TEST(spec_bad_text)
{
    kelp_ivp_spec sp;
    kelp_diag e = {0};
    ck_assert_int_lt(kelp_ivp_spec_parse(&sp, bad_specs[_i], &e), 0);
    ck_assert_int_ne(e.code, KELP_OK);
}
END_TEST

/* ---------------------------------------------------------------- function ops */
START_TEST(func_normalize_align)
{
    kelp_ivp_func f = spec_func("x:0:359:360", "peak(summit=180,peakwidth=85,basewidth=70,summitdelta=40,minutil=25,maxutil=150)");
    double lo, hi;
    ck_assert_int_eq(kelp_ivp_func_range(&f, &lo, &hi), 0);
    ck_assert_double_eq_tol(lo, 25, TOL);
    ck_assert_double_eq_tol(hi, 150, TOL);
    ck_assert_int_eq(kelp_ivp_func_normalize(&f, 0, 100), 0);
    ck_assert_double_eq_tol(fval(&f, 180), 100, 1e-9);
    ck_assert_double_eq_tol(fval(&f, 0), 0, 1e-9);
    ck_assert_double_eq_tol(fval(&f, 60), 34, 1e-9); /* (67.5-25)/125*100 */
    kelp_ivp_domain big = dom1("speed:0:5:41,x:0:359:360");
    ck_assert_int_eq(kelp_ivp_func_align(&f, &big), 0);
    uint32_t ix[2] = {7, 60};
    double v;
    ck_assert_int_eq(kelp_ivp_func_eval(&f, ix, &v), 0);
    ck_assert_double_eq_tol(v, 34, 1e-9);
    ck_assert(kelp_ivp_func_tiles(&f));
    kelp_ivp_domain other = dom1("x:0:100:360");
    ck_assert_int_eq(kelp_ivp_func_align(&f, &other), KELP_ERR_NOTFOUND);
}
END_TEST

/* ---------------------------------------------------------------- coupler (tests 36-37) */
static kelp_ivp_piece c_store[4096];

START_TEST(coupler_argmax_and_range)
{
    kelp_ivp_domain d = dom1("course:0:359:360,speed:0:4:21");
    kelp_ivp_spec a, b;
    kelp_diag e = {0};
    kelp_ivp_func fc, fs, out;
    ck_assert_int_eq(kelp_ivp_spec_parse(&a, "peak(summit=90,peakwidth=0,basewidth=180,summitdelta=0,wrap)", &e), 0);
    ck_assert_int_eq(kelp_ivp_spec_parse(&b, "peak(summit=2,peakwidth=0.5,basewidth=1,summitdelta=0.8)", &e), 0);
    ck_assert_int_eq(kelp_ivp_spec_build(&a, &d, "course", g_work, 4096, &g_zws, g_store, 2048, &fc, &e), 0);
    ck_assert_int_eq(kelp_ivp_spec_build(&b, &d, "speed", g_work, 4096, &g_zws, g_store + 2048, 2048, &fs, &e), 0);
    ck_assert_uint_eq(fc.n, 3);
    ck_assert_uint_eq(fs.n, 6);
    const double w[3][2] = {{50, 50}, {75, 25}, {25, 75}};
    for (int t = 0; t < 3; t++) {
        ck_assert_int_eq(kelp_ivp_couple(&fc, w[t][0], &fs, w[t][1], true, 0, 100, c_store, 4096, &out), 0);
        ck_assert_uint_eq(out.n, 18);
        ck_assert(kelp_ivp_func_tiles(&out));
        double lo, hi;
        ck_assert_int_eq(kelp_ivp_func_range(&out, &lo, &hi), 0);
        ck_assert_double_eq_tol(lo, 0, 1e-9);
        ck_assert_double_eq_tol(hi, 100, 1e-9);
        kelp_ivp_problem p;
        kelp_ivp_problem_init(&p, &d);
        ck_assert_int_eq(kelp_ivp_problem_add(&p, &out), 0);
        static unsigned char work[1 << 16];
        kelp_ivp_result r;
        ck_assert_uint_le(kelp_ivp_solve_work_size(&p), sizeof work);
        ck_assert_int_eq(kelp_ivp_solve(&p, work, sizeof work, &r), 0);
        ck_assert_uint_eq(r.ix[0], 90);
        ck_assert_uint_eq(r.ix[1], 10);
        ck_assert_double_eq_tol(r.value, 100.0 * 100.0, 1e-6);
    }
    /* 50/50: value = 50*f1/100 + 50*f2/100, normalised: at (0 deg, 2 kn) f1=50 f2=100 -> 75/100 of range */
    ck_assert_int_eq(kelp_ivp_couple(&fc, 50, &fs, 50, true, 0, 100, c_store, 4096, &out), 0);
    uint32_t ix[2] = {0, 10};
    double v;
    ck_assert_int_eq(kelp_ivp_func_eval(&out, ix, &v), 0);
    ck_assert_double_eq_tol(v, 75, 1e-9);
    ck_assert_int_eq(kelp_ivp_couple(&fc, 50, &fs, 50, true, 0, 100, c_store, 17, &out), KELP_ERR_NOSPACE);
    ck_assert_int_eq(kelp_ivp_couple(&fc, 0, &fs, 50, true, 0, 100, c_store, 4096, &out), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_ivp_couple(&fc, 50, &fc, 50, true, 0, 100, c_store, 4096, &out), KELP_ERR_ARG);
}
END_TEST

/* BHV_IPF's string (MOOS-IvP 24.8's FunctionEncoder layout), worked by hand: two pieces over
 * course x speed, weights slope per variable then the constant, four decimals with the point
 * kept ("2."), an exact zero "0", a tiny value "0.0000"; pwt and bounds compacted */
START_TEST(func_to_ipf)
{
    kelp_ivp_domain d;
    kelp_ivp_domain_init(&d);
    ck_assert_int_eq(kelp_ivp_domain_add(&d, "course", 0, 359, 360), 0);
    ck_assert_int_eq(kelp_ivp_domain_add(&d, "speed", 0, 4, 21), 0);
    kelp_ivp_piece store[2];
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_func_init(&f, &d, store, 2), 0);
    ck_assert_int_eq(kelp_ivp_func_add(&f, (const int32_t[]){ 0, 0 }, (const int32_t[]){ 179, 20 },
                                       (const double[]){ 0.5, 0 }, 2), 0);
    ck_assert_int_eq(kelp_ivp_func_add(&f, (const int32_t[]){ 180, 0 }, (const int32_t[]){ 359, 20 },
                                       (const double[]){ -0.0625, 0.00001 }, 112.34567), 0);
    f.pwt = 150;
    char buf[512];
    int n = kelp_ivp_func_to_ipf(&f, "12:waypt_survey", NULL, buf, sizeof buf);
    const char *want = "H,15,12:waypt_survey,2,2,1,150,D,course;0;359;360:speed;0;4;21,G,359,20,F,"
                       "0,179,0,20,0.5,0,2.,180,359,0,20,-0.0625,0.0000,112.3457";
    ck_assert_str_eq(buf, want);
    ck_assert_int_eq(n, (int)strlen(want));
    int32_t gel[2] = { 2, 2 };
    f.pwt = 87.5;
    ck_assert_int_gt(kelp_ivp_func_to_ipf(&f, "3:avd_ben", gel, buf, sizeof buf), 0);
    ck_assert_ptr_nonnull(strstr(buf, ",1,87.5,D,"));
    ck_assert_ptr_nonnull(strstr(buf, ",G,2,2,F,"));
    /* too small: refused, not truncated silently */
    ck_assert_int_eq(kelp_ivp_func_to_ipf(&f, "3:avd_ben", gel, buf, 40), KELP_ERR_NOSPACE);
    ck_assert_int_eq(kelp_ivp_func_to_ipf(NULL, "x", NULL, buf, sizeof buf), KELP_ERR_ARG);
}
END_TEST

Suite *kelp_ivp_suite(void)
{
    Suite *s = suite_create("ivp");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, domain_listing16);
    tcase_add_test(tc, tiles_gap_overlap_outside);
    tcase_add_test(tc, domain_values_and_snap);
    tcase_add_loop_test(tc, domain_bad_text, 0, (int)(sizeof bad_domains / sizeof bad_domains[0]));
    tcase_add_test(tc, strings_shape_point_region);
    tcase_add_test(tc, peak_tp1_fig13);
    tcase_add_test(tc, peak_tp2_fig12);
    tcase_add_test(tc, peak_tp3_speed);
    tcase_add_test(tc, peak_tp4_course_wrap);
    tcase_add_test(tc, peak_wrap_derived);
    tcase_add_test(tc, peak_tp5_insist);
    tcase_add_test(tc, peak_tp6_multimodal);
    tcase_add_test(tc, peak_tp8_listing17);
    tcase_add_test(tc, peak_defaults_and_errors);
    tcase_add_test(tc, leq_heq_fig18_19);
    tcase_add_test(tc, leq_errors);
    tcase_add_test(tc, leq_heq_edges);
    tcase_add_loop_test(tc, spec_bad_text, 0, (int)(sizeof bad_specs / sizeof bad_specs[0]));
    tcase_add_test(tc, func_normalize_align);
    tcase_add_test(tc, coupler_argmax_and_range);
    tcase_add_test(tc, func_to_ipf);
    suite_add_tcase(s, tc);
    return s;
}
