/* Geodesy: the MOOS local grid against the uField seed's node report and round trips. */
#include <check.h>
#include <math.h>
#include <kelp/geo.h>

START_TEST(test_seed_report)
{
    /* seed 000: NODE_REPORT X=51.71,Y=-35.50,LAT=43.824981,LON=-70.329755 with the Alder
     * datum LatOrigin=43.825300, LongOrigin=-70.330400 */
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init(&g, 43.8253, -70.3304), KELP_OK);
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
    ck_assert_int_eq(kelp_geo_init(&g, 43.8253, -70.3304), KELP_OK);
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

START_TEST(test_round_trip)
{
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init(&g, -33.9, 151.2), KELP_OK);
    const double pts[][2] = {{0, 0}, {60, -40}, {-1234.5, 987.25}, {25000, -40000}};
    for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++) {
        double lat, lon, x, y;
        ck_assert_int_eq(kelp_geo_to_latlon(&g, pts[i][0], pts[i][1], &lat, &lon), KELP_OK);
        ck_assert_int_eq(kelp_geo_to_local(&g, lat, lon, &x, &y), KELP_OK);
        ck_assert_double_eq_tol(x, pts[i][0], 1e-6);
        ck_assert_double_eq_tol(y, pts[i][1], 1e-6);
    }
}
END_TEST

START_TEST(test_errors)
{
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init(&g, 90, 0), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_init(&g, -91, 0), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_init(&g, 0, 181), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_init(&g, NAN, 0), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_geo_init(&g, 10, -70), KELP_OK);
    double a, b;
    ck_assert_int_eq(kelp_geo_to_latlon(&g, 7e6, 0, &a, &b), KELP_ERR_RANGE); /* beyond the grid model */
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
    tcase_add_test(tc, test_round_trip);
    tcase_add_test(tc, test_errors);
    suite_add_tcase(s, tc);
    return s;
}
