/* Geodesy: UTM (MOOS-IvP 24.8) against PROJ 9.1.1, the MOOS local grid against the uField
 * seed's node report, round trips and bad input. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <kelp/geo.h>

START_TEST(test_seed_report)
{
    /* seed 000: NODE_REPORT X=51.71,Y=-35.50,LAT=43.824981,LON=-70.329755 with the Alder
     * datum LatOrigin=43.825300, LongOrigin=-70.330400 */
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init_grid(&g, 43.8253, -70.3304), KELP_OK);
    double lat, lon;
    ck_assert_int_eq(kelp_geo_to_latlon(&g, 51.71, -35.50, &lat, &lon), KELP_OK);
    ck_assert_double_eq_tol(lat, 43.824981, 5e-7);
    ck_assert_double_eq_tol(lon, -70.329755, 5e-7);
    double x, y;
    ck_assert_int_eq(kelp_geo_to_local(&g, 43.824981, -70.329755, &x, &y), KELP_OK);
    ck_assert_double_eq_tol(x, 51.71, 0.05); /* 6 printed decimals of a degree ~ 5 cm */
    ck_assert_double_eq_tol(y, -35.50, 0.06);
}
END_TEST

START_TEST(test_radius)
{
    /* R(0) = a, R(90-) -> b; R(43.8253) = 6367855.93 m */
    ck_assert_double_eq_tol(kelp_geo_radius(0), 6378137.0, 1e-6);
    ck_assert_double_eq_tol(kelp_geo_radius(89.9999), 6356752.0, 0.01);
    ck_assert_double_eq_tol(kelp_geo_radius(43.8253), 6367855.93, 0.01);
}
END_TEST

START_TEST(test_origin_and_axes)
{
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init_grid(&g, 43.8253, -70.3304), KELP_OK);
    double lat, lon;
    ck_assert_int_eq(kelp_geo_to_latlon(&g, 0, 0, &lat, &lon), KELP_OK);
    ck_assert(lat == 43.8253 && lon == -70.3304);
    /* 1 km north: asin(1000/R) deg; 1 km east: asin(1000/(R cos lat0)) deg (values from an
     * independent double-precision computation of the same formulas) */
    ck_assert_int_eq(kelp_geo_to_latlon(&g, 0, 1000, &lat, &lon), KELP_OK);
    ck_assert_double_eq_tol(lat - 43.8253, 0.0089976564, 1e-9);
    ck_assert_double_eq_tol(lon, -70.3304, 1e-12);
    ck_assert_int_eq(kelp_geo_to_latlon(&g, 1000, 0, &lat, &lon), KELP_OK);
    ck_assert_double_eq_tol(lon + 70.3304, 0.0124715503, 1e-9);
    ck_assert_double_eq_tol(lat, 43.8253, 1e-12);
}
END_TEST

/* MOOS-IvP 24.8 (USE_UTM): the LAT/LON its uFldNodeComms printed (8 decimals) for reports at
 * these X/Y, datum 42.358456, -71.087589 (the recorded conformance runs) */
START_TEST(test_utm_as_recorded)
{
    static const struct { double x, y; const char *lat, *lon; } c[] = {
        {50, 0, "42.35846706", "-71.08698225"},  {0, -100, "42.35755599", "-71.08755918"},
        {0, -1, "42.35844699", "-71.08758870"},   {0, -13, "42.35833893", "-71.08758512"},
        {-100, 0, "42.35843388", "-71.08880250"}, {-100.63, 0, "42.35843374", "-71.08881014"},
        {70, 0, "42.35847148", "-71.08673955"},   {0, 150, "42.35980602", "-71.08763373"},
    };
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init(&g, 42.358456, -71.087589), KELP_OK);
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        double lat, lon;
        char a[32], b[32];
        ck_assert_int_eq(kelp_geo_to_latlon(&g, c[i].x, c[i].y, &lat, &lon), KELP_OK);
        snprintf(a, sizeof a, "%.8f", lat);
        snprintf(b, sizeof b, "%.8f", lon);
        ck_assert_str_eq(a, c[i].lat);
        ck_assert_str_eq(b, c[i].lon);
    }
}
END_TEST

/* against PROJ 9.1.1 (cs2cs +proj=latlong +ellps=WGS84 +to +proj=utm +zone=Z [+south]): the
 * datum's easting/northing, then the inverse of those plus x/y. MOOS's series agree with PROJ
 * to a millimetre here; its inverse stops within 1 m of the UTM point, so lat/lon within a
 * metre (checked here at 1e-5 deg and 2 m back). */
START_TEST(test_utm_against_proj)
{
    static const struct { double lat0, lon0, x, y, lat, lon; } c[] = {
        {43.8253, -70.3304, 51.71, -35.50, 43.8249879354, -70.3297499916},
        {43.8253, -70.3304, 0, 1000, 43.8343013471, -70.3305999921},
        {43.8253, -70.3304, 1000, 0, 43.8254440816, -70.3179668912},
        {43.8253, -70.3304, -25000, 40000, 44.1812499841, -70.6511519041},
        {-33.9, 151.2, -1234.5, 987.25, -33.8909046100, 151.1868427782},
        {42.358456, -71.087589, 50, 0, 42.3584670505, -71.0869822479},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        kelp_geo g;
        ck_assert_int_eq(kelp_geo_init(&g, c[i].lat0, c[i].lon0), KELP_OK);
        double lat, lon, x, y;
        ck_assert_int_eq(kelp_geo_to_local(&g, c[i].lat, c[i].lon, &x, &y), KELP_OK);
        ck_assert_double_eq_tol(x, c[i].x, 1e-3);
        ck_assert_double_eq_tol(y, c[i].y, 1e-3);
        ck_assert_int_eq(kelp_geo_to_latlon(&g, c[i].x, c[i].y, &lat, &lon), KELP_OK);
        ck_assert_double_eq_tol(lat, c[i].lat, 1e-5);
        ck_assert_double_eq_tol(lon, c[i].lon, 1.4e-5);
        ck_assert_int_eq(kelp_geo_to_local(&g, lat, lon, &x, &y), KELP_OK);
        ck_assert_double_eq_tol(hypot(x - c[i].x, y - c[i].y), 0, 1.0);
    }
    /* the datum itself */
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init(&g, 42.358456, -71.087589), KELP_OK);
    double lat, lon;
    ck_assert_int_eq(kelp_geo_to_latlon(&g, 0, 0, &lat, &lon), KELP_OK);
    ck_assert_double_eq_tol(lat, 42.358456, 1e-11);
    ck_assert_double_eq_tol(lon, -71.087589, 1e-11);
}
END_TEST

START_TEST(test_utm_zones)
{
    ck_assert_int_eq(kelp_geo_utm_zone(42.36, -71.09), 19);
    ck_assert_int_eq(kelp_geo_utm_zone(0, -180), 1);
    ck_assert_int_eq(kelp_geo_utm_zone(0, 179.9), 60);
    ck_assert_int_eq(kelp_geo_utm_zone(60, 5), 32);  /* Norway */
    ck_assert_int_eq(kelp_geo_utm_zone(55.9, 5), 31);
    ck_assert_int_eq(kelp_geo_utm_zone(78, 10), 33); /* Svalbard */
    ck_assert_int_eq(kelp_geo_utm_zone(78, 8), 31);
    ck_assert_int_eq(kelp_geo_utm_zone(78, 40), 37);
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init(&g, 84.5, 0), KELP_ERR_RANGE); /* MOOS: UTM ends at 84 N, 80 S */
    ck_assert_int_eq(kelp_geo_init(&g, -80.5, 0), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_init_grid(&g, 84.5, 0), KELP_OK);
    /* a datum near a zone edge: points in the next zone stay in the datum's zone, continuous */
    ck_assert_int_eq(kelp_geo_init(&g, 42.0, -72.0001), KELP_OK);
    ck_assert_int_eq(g.utm_zone, 18);
    double x1, y1, x2, y2;
    ck_assert_int_eq(kelp_geo_to_local(&g, 42.0, -71.9999, &x1, &y1), KELP_OK);
    ck_assert_int_eq(kelp_geo_to_local(&g, 42.0, -71.9998, &x2, &y2), KELP_OK);
    ck_assert_double_eq_tol(x2 - x1, 8.28, 0.02);
}
END_TEST

START_TEST(test_round_trip)
{
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init(&g, -33.9, 151.2), KELP_OK);
    const double pts[][2] = {{0, 0}, {60, -40}, {-1234.5, 987.25}, {25000, -40000}};
    kelp_geo grid;
    ck_assert_int_eq(kelp_geo_init_grid(&grid, -33.9, 151.2), KELP_OK);
    for (size_t i = 0; i < 2 * (sizeof pts / sizeof pts[0]); i++) {
        const kelp_geo *gg = i % 2 ? &grid : &g;
        double lat, lon, x, y;
        const double *p = pts[i / 2];
        ck_assert_int_eq(kelp_geo_to_latlon(gg, p[0], p[1], &lat, &lon), KELP_OK);
        ck_assert_int_eq(kelp_geo_to_local(gg, lat, lon, &x, &y), KELP_OK);
        /* the grid exactly; UTM within MOOS's 1 m */
        ck_assert_double_eq_tol(hypot(x - p[0], y - p[1]), 0, i % 2 ? 1e-6 : 1.0);
    }
}
END_TEST

START_TEST(test_errors)
{
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init(&g, 90, 0), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_init_grid(&g, 90, 0), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_init(&g, -91, 0), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_init(&g, 0, 181), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_init(&g, NAN, 0), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_init(&g, 10, -70), KELP_OK);
    double a, b;
    ck_assert_int_eq(kelp_geo_to_latlon(&g, 7e6, 0, &a, &b), KELP_ERR_RANGE); /* beyond the series */
    kelp_geo grid;
    ck_assert_int_eq(kelp_geo_init_grid(&grid, 10, -70), KELP_OK);
    ck_assert_int_eq(kelp_geo_to_latlon(&grid, 7e6, 0, &a, &b), KELP_ERR_RANGE); /* beyond the grid model */
    ck_assert_int_eq(kelp_geo_to_latlon(&g, NAN, 0, &a, &b), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_to_local(&g, 95, 0, &a, &b), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_to_local(&g, 0, INFINITY, &a, &b), KELP_ERR_RANGE);
}
END_TEST

Suite *kelp_geo_suite(void)
{
    Suite *s = suite_create("geo");
    TCase *tc = tcase_create("local_grid");
    tcase_add_test(tc, test_seed_report);
    tcase_add_test(tc, test_radius);
    tcase_add_test(tc, test_origin_and_axes);
    tcase_add_test(tc, test_utm_as_recorded);
    tcase_add_test(tc, test_utm_against_proj);
    tcase_add_test(tc, test_utm_zones);
    tcase_add_test(tc, test_round_trip);
    tcase_add_test(tc, test_errors);
    suite_add_tcase(s, tc);
    return s;
}
