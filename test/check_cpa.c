/* kelp CPA engine: every degenerate family and a brute-force cross-check. */
#include <check.h>
#include <math.h>
#include <kelp/cpa.h>
#include <kelp/rng.h>

#define NEAR(a, b, tol) ck_assert_msg(fabs((a) - (b)) <= (tol), "%s = %.12g, want %.12g", #a, (double)(a), (double)(b))

static kelp_cpa_result eval(double cnx, double cny, double cnh, double cnv, double osx, double osy, double osh,
                            double osv, double tol)
{
    kelp_cpa_vessel cn = {cnx, cny, cnh, cnv}, os = {osx, osy, osh, osv};
    kelp_cpa_result r;
    ck_assert_int_eq(kelp_cpa_eval(&cn, &os, tol, &r), KELP_OK);
    return r;
}

START_TEST(still_and_identical)
{
    /* both still: cpa is the range now */
    kelp_cpa_result r = eval(30, 40, 10, 0, 0, 0, 200, 0, 60);
    NEAR(r.cpa, 50, 1e-12);
    NEAR(r.tcpa, 0, 0);
    NEAR(r.roc, 0, 0);
    NEAR(r.bearing_rate, 0, 0);
    ck_assert(!r.os_crosses_cn_bow && !r.os_crosses_cn_stern && !r.os_passes_cn_port && !r.os_passes_cn_star);
    ck_assert(!r.cn_crosses_os_bow && !r.cn_crosses_os_stern && !r.cn_passes_os_port && !r.cn_passes_os_star);
    /* identical velocities: nothing changes */
    r = eval(30, 40, 33, 3.5, 0, 0, 33, 3.5, 0);
    NEAR(r.cpa, 50, 1e-9);
    NEAR(r.tcpa, 0, 0);
    NEAR(r.roc, 0, 1e-12);
    NEAR(r.bearing_rate, 0, 1e-12);
    ck_assert(!r.os_crosses_cn_bow && !r.os_crosses_cn_stern && !r.os_passes_cn_port && !r.os_passes_cn_star);
    ck_assert(!r.cn_crosses_os_bow && !r.cn_crosses_os_stern && !r.cn_passes_os_port && !r.cn_passes_os_star);
}
END_TEST

START_TEST(head_on)
{
    /* ownship east at 2, contact 100 m east heading west at 2 */
    kelp_cpa_result r = eval(100, 0, 270, 2, 0, 0, 90, 2, 120);
    NEAR(r.cpa, 0, 1e-12);
    NEAR(r.tcpa, 25, 1e-12);
    NEAR(r.roc, 4, 1e-12);
    NEAR(r.range, 100, 0);
    NEAR(r.bearing_rate, 0, 1e-12);
    NEAR(r.rel_bearing, 0, 1e-12);
    NEAR(r.abs_bearing, 90, 1e-12);
    NEAR(r.cn_rel_bearing, 0, 1e-12);
    /* as MOOS-IvP 24.8: on the contact's bow line, moving square to nothing: no crossing (the
     * bearing rate is 0 and ownship has no speed across the line), the bow distance is the
     * range; the beam is passed to starboard at distance 0 */
    ck_assert(!r.os_crosses_cn_bow && !r.os_crosses_cn_stern);
    NEAR(r.os_crosses_cn_bow_dist, 100, 0);
    ck_assert(!r.os_passes_cn_port && r.os_passes_cn_star);
    NEAR(r.os_passes_cn_star_dist, 0, 0);
    ck_assert(!r.cn_crosses_os_bow && !r.cn_passes_os_port && r.cn_passes_os_star);
    /* on each other's bow-stern line: both port and starboard, fore only */
    ck_assert(r.cn_fore_of_os && !r.cn_aft_of_os && r.cn_port_of_os && r.cn_star_of_os);
    ck_assert(r.os_fore_of_cn && !r.os_aft_of_cn && r.os_port_of_cn && r.os_star_of_cn);
    /* within a short horizon the CPA is where ownship is at the horizon */
    r = eval(100, 0, 270, 2, 0, 0, 90, 2, 10);
    NEAR(r.cpa, 60, 1e-12);
    NEAR(r.tcpa, 10, 0);
    /* head-on, offset 10 m to starboard: pass starboard to starboard */
    r = eval(100, -10, 270, 2, 0, 0, 90, 2, 0);
    NEAR(r.cpa, 10, 1e-12);
    ck_assert(r.os_passes_cn_star && !r.os_passes_cn_port);
    NEAR(r.os_passes_cn_star_dist, 10, 1e-9);
    ck_assert(r.cn_passes_os_star);
    NEAR(r.cn_passes_os_star_dist, 10, 1e-9);
    ck_assert(!r.os_crosses_cn_bow && !r.os_crosses_cn_stern);
}
END_TEST

START_TEST(crossing)
{
    /* contact 100 m east and 100 m south heading north at 2; ownship east at 2: both reach
     * (100,0) at t = 50 (collision); then the contact 1 s later: ownship crosses its bow */
    kelp_cpa_result r = eval(100, -100, 0, 2, 0, 0, 90, 2, 0);
    NEAR(r.cpa, 0, 1e-9);
    NEAR(r.tcpa, 50, 1e-9);
    ck_assert(r.os_crosses_cn_bow);
    NEAR(r.os_crosses_cn_bow_dist, 0, 1e-9);
    r = eval(100, -110, 0, 2, 0, 0, 90, 2, 0);
    ck_assert(r.os_crosses_cn_bow && !r.os_crosses_cn_stern);
    NEAR(r.os_crosses_cn_bow_dist, 10, 1e-9);
    /* the contact crosses ownship's stern by the same */
    ck_assert(r.cn_crosses_os_stern && !r.cn_crosses_os_bow);
    NEAR(r.cn_crosses_os_stern_dist, 10, 1e-9);
    /* having crossed ahead, ownship comes abeam on the contact's starboard side, 10 m off */
    ck_assert(r.os_passes_cn_star && !r.os_passes_cn_port);
    NEAR(r.os_passes_cn_star_dist, 10, 1e-9);
    ck_assert(r.cn_fore_of_os && r.cn_star_of_os && !r.cn_aft_of_os && !r.cn_port_of_os);
    ck_assert(r.os_fore_of_cn && r.os_port_of_cn);
    NEAR(r.abs_bearing, 180 - atan2(100, 110) * 180 / M_PI, 1e-9);
    /* closing: roc > 0; the contact draws aft (bearing increasing clockwise) */
    ck_assert(r.roc > 0);
    ck_assert(r.bearing_rate > 0);
    /* the contact 10 m behind instead: ownship crosses its stern */
    r = eval(100, -90, 0, 2, 0, 0, 90, 2, 0);
    ck_assert(r.os_crosses_cn_stern && !r.os_crosses_cn_bow);
    NEAR(r.os_crosses_cn_stern_dist, 10, 1e-9);
    ck_assert(r.os_passes_cn_port && !r.os_passes_cn_star);
}
END_TEST

START_TEST(overtaking)
{
    /* ownship 50 m behind a slower contact on the same track, both north */
    kelp_cpa_result r = eval(0, 50, 0, 1, 0, 0, 0, 3, 0);
    NEAR(r.cpa, 0, 1e-12);
    NEAR(r.tcpa, 25, 1e-12);
    NEAR(r.roc, 2, 1e-12);
    ck_assert(r.cn_fore_of_os && r.os_aft_of_cn && !r.os_fore_of_cn);
    ck_assert(r.os_crosses_cn_bow); /* a collision course */
    /* 20 m to the east: ownship passes the contact's starboard side at 20 m */
    r = eval(-20, 50, 0, 1, 0, 0, 0, 3, 0);
    NEAR(r.cpa, 20, 1e-12);
    ck_assert(r.os_passes_cn_star);
    NEAR(r.os_passes_cn_star_dist, 20, 1e-9);
    ck_assert(!r.os_crosses_cn_bow && !r.os_crosses_cn_stern); /* parallel tracks never cross */
    ck_assert(r.cn_passes_os_port);
    NEAR(r.cn_passes_os_port_dist, 20, 1e-9);
}
END_TEST

START_TEST(contact_on_ownship_and_opening)
{
    kelp_cpa_result r = eval(5, 5, 45, 2, 5, 5, 90, 3, 60);
    NEAR(r.cpa, 0, 0);
    NEAR(r.tcpa, 0, 0);
    NEAR(r.range, 0, 0);
    NEAR(r.roc, 0, 0);
    NEAR(r.bearing_rate, 0, 0);
    NEAR(r.rel_bearing, 0, 0);
    NEAR(r.abs_bearing, 0, 0);
    ck_assert(!r.cn_fore_of_os && !r.cn_aft_of_os && !r.cn_port_of_os && !r.cn_star_of_os);
    ck_assert(!r.os_fore_of_cn && !r.os_aft_of_cn && !r.os_port_of_cn && !r.os_star_of_cn);
    ck_assert(!r.os_crosses_cn_bow && !r.os_crosses_cn_stern && !r.os_passes_cn_port && !r.os_passes_cn_star);
    /* opening: CPA now */
    r = eval(0, 100, 0, 3, 0, 0, 180, 1, 0);
    NEAR(r.cpa, 100, 0);
    NEAR(r.tcpa, 0, 0);
    NEAR(r.roc, -4, 1e-12);
}
END_TEST

START_TEST(negative_speed_and_wrapped_headings)
{
    /* negative speed is still */
    kelp_cpa_result a = eval(100, 0, 270, -2, 0, 0, 90, 2, 0), b = eval(100, 0, 270, 0, 0, 0, 90, 2, 0);
    NEAR(a.cpa, b.cpa, 0);
    NEAR(a.tcpa, 50, 1e-12);
    NEAR(a.roc, 2, 1e-12);
    a = eval(100, 0, 270, 2, 0, 0, 90, -1, 0);
    NEAR(a.tcpa, 50, 1e-12);
    /* headings outside [0,360) wrap */
    a = eval(100, -110, 360, 2, 0, 0, -270, 2, 0);
    b = eval(100, -110, 0, 2, 0, 0, 90, 2, 0);
    NEAR(a.cpa, b.cpa, 1e-9);
    NEAR(a.tcpa, b.tcpa, 1e-9);
    NEAR(a.rel_bearing, b.rel_bearing, 1e-9);
    ck_assert(a.rel_bearing >= 0 && a.rel_bearing < 360);
    ck_assert(a.os_crosses_cn_bow == b.os_crosses_cn_bow);
    NEAR(a.os_crosses_cn_bow_dist, b.os_crosses_cn_bow_dist, 1e-9);
    a = eval(10, 10, 765, 1, 0, 0, -45.5, 1.5, 0);
    b = eval(10, 10, 45, 1, 0, 0, 314.5, 1.5, 0);
    NEAR(a.cpa, b.cpa, 1e-9);
    NEAR(a.cn_rel_bearing, b.cn_rel_bearing, 1e-9);
    NEAR(a.bearing_rate, b.bearing_rate, 1e-9);
    /* non-finite input is refused with a zeroed result */
    kelp_cpa_vessel cn = {NAN, 0, 0, 0}, os = {0, 0, 0, 0};
    kelp_cpa_result r;
    ck_assert_int_eq(kelp_cpa_eval(&cn, &os, 0, &r), KELP_ERR_ARG);
    NEAR(r.range, 0, 0);
    cn.x = 0;
    cn.hdg = INFINITY;
    ck_assert_int_eq(kelp_cpa_eval(&cn, &os, 0, &r), KELP_ERR_ARG);
    kelp_cpa_fast f;
    ck_assert_int_eq(kelp_cpa_fast_init(&f, &cn, 0, 0, 0), KELP_ERR_ARG);
}
END_TEST

/* distance at time t, positions advanced independently along each leg */
static double dist_at(const kelp_cpa_vessel *cn, const kelp_cpa_vessel *os, double t)
{
    double cx = cn->x + cn->spd * sin(cn->hdg * M_PI / 180) * t, cy = cn->y + cn->spd * cos(cn->hdg * M_PI / 180) * t;
    double ox = os->x + os->spd * sin(os->hdg * M_PI / 180) * t, oy = os->y + os->spd * cos(os->hdg * M_PI / 180) * t;
    return hypot(cx - ox, cy - oy);
}

/* minimum over [0, tmax]: 1000 samples, then ternary search around the best (convex) */
static double brute(const kelp_cpa_vessel *cn, const kelp_cpa_vessel *os, double tmax)
{
    const int n = 1000;
    int best = 0;
    double bd = dist_at(cn, os, 0);
    for (int i = 1; i <= n; i++) {
        double d = dist_at(cn, os, tmax * i / n);
        if (d < bd) bd = d, best = i;
    }
    double lo = tmax * (best > 0 ? best - 1 : 0) / n, hi = tmax * (best < n ? best + 1 : n) / n;
    for (int k = 0; k < 200 && hi - lo > 1e-12; k++) {
        double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
        if (dist_at(cn, os, m1) <= dist_at(cn, os, m2)) hi = m2;
        else lo = m1;
    }
    double d = dist_at(cn, os, (lo + hi) / 2);
    return d < bd ? d : bd;
}

START_TEST(brute_force_10000)
{
    kelp_rng g;
    kelp_rng_seed(&g, 20261125);
    double worst = 0;
    for (int i = 0; i < 10000; i++) {
        kelp_cpa_vessel cn = {kelp_rng_range(&g, -2000, 2000), kelp_rng_range(&g, -2000, 2000),
                              kelp_rng_range(&g, 0, 360), kelp_rng_range(&g, 0, 10)};
        kelp_cpa_vessel os = {kelp_rng_range(&g, -2000, 2000), kelp_rng_range(&g, -2000, 2000),
                              kelp_rng_range(&g, 0, 360), kelp_rng_range(&g, 0, 10)};
        if (i % 10 == 0) os.spd = 0;                   /* some still vessels */
        double tol = i % 4 == 0 ? 0 : kelp_rng_range(&g, 1, 1000);
        double tmax = tol > 0 ? tol : 1e6;
        kelp_cpa_result r;
        ck_assert_int_eq(kelp_cpa_eval(&cn, &os, tol, &r), KELP_OK);
        if (tol <= 0 && r.tcpa > tmax) continue;      /* beyond the brute-force window */
        double b = brute(&cn, &os, tmax);
        double err = fabs(r.cpa - b);
        if (err > worst) worst = err;
        ck_assert_msg(err <= 1e-6, "encounter %d: engine %.12f, brute force %.12f", i, r.cpa, b);
        ck_assert(r.tcpa >= 0 && (tol <= 0 || r.tcpa <= tol));
        NEAR(dist_at(&cn, &os, r.tcpa), r.cpa, 1e-6);
        /* the per-candidate evaluator and the legacy call agree */
        kelp_cpa_fast f;
        ck_assert_int_eq(kelp_cpa_fast_init(&f, &cn, os.x, os.y, tol), KELP_OK);
        NEAR(kelp_cpa_fast_eval(&f, os.hdg, os.spd, NULL), r.cpa, 1e-9);
        NEAR(kelp_cpa_range(cn.x, cn.y, cn.hdg, cn.spd, os.x, os.y, os.hdg, os.spd, tol, NULL), r.cpa, 1e-9);
        /* roc is minus the range rate: check by a small step */
        double h = 1e-4, dr = (dist_at(&cn, &os, h) - r.range) / h;
        if (r.range > 1) NEAR(r.roc, -dr, 1e-3);
    }
    ck_assert(worst <= 1e-6);
}
END_TEST

START_TEST(bearing_rate_numeric)
{
    kelp_cpa_vessel cn = {300, 200, 250, 4}, os = {0, 0, 30, 3};
    kelp_cpa_result r;
    ck_assert_int_eq(kelp_cpa_eval(&cn, &os, 0, &r), KELP_OK);
    double h = 1e-3;
    kelp_cpa_vessel cn2 = cn, os2 = os;
    cn2.x += 4 * sin(250 * M_PI / 180) * h, cn2.y += 4 * cos(250 * M_PI / 180) * h;
    os2.x += 3 * sin(30 * M_PI / 180) * h, os2.y += 3 * cos(30 * M_PI / 180) * h;
    kelp_cpa_result r2;
    ck_assert_int_eq(kelp_cpa_eval(&cn2, &os2, 0, &r2), KELP_OK);
    NEAR(r.bearing_rate, (r2.abs_bearing - r.abs_bearing) / h, 1e-4);
    NEAR(r.rel_bearing, fmod(r.abs_bearing - 30 + 360, 360), 1e-9);
}
END_TEST

/* MOOS-IvP 24.8's CPAEngine on 400 degenerate encounters (test/cpa_moos248.inc says how the
 * table was made): every side, crossing and passing flag as 24.8 answers it, and the distances. */
typedef struct cpa_fact {
    double in[8];
    const char *flags;
    double dist[8];
} cpa_fact;

static const cpa_fact CPA_MOOS248[] = {
#include "cpa_moos248.inc"
};
#define N_CPA_MOOS248 ((int)(sizeof CPA_MOOS248 / sizeof CPA_MOOS248[0]))

START_TEST(moos248_degenerate)
{
    const cpa_fact *f = &CPA_MOOS248[_i];
    kelp_cpa_result r = eval(f->in[0], f->in[1], f->in[2], f->in[3], f->in[4], f->in[5], f->in[6], f->in[7], 0);
    const bool got[16] = {r.os_fore_of_cn, r.os_aft_of_cn, r.os_port_of_cn, r.os_star_of_cn,
                          r.cn_fore_of_os, r.cn_aft_of_os, r.cn_port_of_os, r.cn_star_of_os,
                          r.os_crosses_cn_bow, r.os_crosses_cn_stern, r.os_passes_cn_port, r.os_passes_cn_star,
                          r.cn_crosses_os_bow, r.cn_crosses_os_stern, r.cn_passes_os_port, r.cn_passes_os_star};
    const double dist[8] = {r.os_crosses_cn_bow_dist, r.os_crosses_cn_stern_dist, r.os_passes_cn_port_dist,
                            r.os_passes_cn_star_dist, r.cn_crosses_os_bow_dist, r.cn_crosses_os_stern_dist,
                            r.cn_passes_os_port_dist, r.cn_passes_os_star_dist};
    static const char *const names[16] = {"os_fore", "os_aft", "os_port", "os_star", "cn_fore", "cn_aft",
                                          "cn_port", "cn_star", "os_x_bow", "os_x_stern", "os_p_port",
                                          "os_p_star", "cn_x_bow", "cn_x_stern", "cn_p_port", "cn_p_star"};
    for (int k = 0; k < 16; k++)
        ck_assert_msg(got[k] == (f->flags[k] == '1'), "row %d (%g %g %g %g / %g %g %g %g): %s is %d, 24.8 says %c",
                      _i, f->in[0], f->in[1], f->in[2], f->in[3], f->in[4], f->in[5], f->in[6], f->in[7],
                      names[k], got[k], f->flags[k]);
    for (int k = 0; k < 8; k++)
        ck_assert_msg(fabs(dist[k] - f->dist[k]) <= 1e-9 * (1 + fabs(f->dist[k])),
                      "row %d: distance %d is %.17g, 24.8 says %.17g", _i, k, dist[k], f->dist[k]);
}
END_TEST

Suite *kelp_cpa_suite(void)
{
    Suite *s = suite_create("cpa");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, still_and_identical);
    tcase_add_test(tc, head_on);
    tcase_add_test(tc, crossing);
    tcase_add_test(tc, overtaking);
    tcase_add_test(tc, contact_on_ownship_and_opening);
    tcase_add_test(tc, negative_speed_and_wrapped_headings);
    tcase_add_test(tc, brute_force_10000);
    tcase_add_test(tc, bearing_rate_numeric);
    tcase_add_loop_test(tc, moos248_degenerate, 0, N_CPA_MOOS248);
    suite_add_tcase(s, tc);
    return s;
}
