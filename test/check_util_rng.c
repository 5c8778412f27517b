/* kelp util: the caller-seeded generators. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <kelp/rng.h>

/* The first 1,000 values of rand() from its default state (a program that never calls
 * srand) and after srand() of a few seeds, against the C library on this machine. */
START_TEST(glibc_rand_sequence)
{
    const unsigned seeds[] = {1, 0, 42, 20250101, 0xFFFFFFFFu};
    for (size_t k = 0; k < sizeof seeds / sizeof seeds[0]; k++) {
        kelp_rng_glibc g;
        kelp_rng_glibc_seed(&g, seeds[k]);
        srand(seeds[k]);
        for (int i = 0; i < 1000; i++) {
            int want = rand();
            int32_t got = kelp_rng_glibc_next(&g);
            if (got != want) ck_abort_msg("seed %u value %d: libc %d, kelp %d", seeds[k], i, want, (int)got);
        }
    }
    ck_assert_int_eq(RAND_MAX, KELP_GLIBC_RAND_MAX);
}
END_TEST

START_TEST(rng_reproducible_and_uniform)
{
    kelp_rng a, b;
    kelp_rng_seed(&a, 7);
    kelp_rng_seed(&b, 7);
    for (int i = 0; i < 100; i++) ck_assert(kelp_rng_next(&a) == kelp_rng_next(&b));
    kelp_rng_seed(&b, 8);
    ck_assert(kelp_rng_next(&a) != kelp_rng_next(&b));
    double sum = 0, lo = 1, hi = 0;
    int bins[10] = {0};
    const int n = 100000;
    for (int i = 0; i < n; i++) {
        double u = kelp_rng_uniform(&a);
        ck_assert(u >= 0.0 && u < 1.0);
        sum += u;
        lo = fmin(lo, u);
        hi = fmax(hi, u);
        bins[(int)(u * 10)]++;
    }
    ck_assert(fabs(sum / n - 0.5) < 0.005);
    for (int i = 0; i < 10; i++) {
        ck_assert_int_gt(bins[i], n / 10 - 600);
        ck_assert_int_lt(bins[i], n / 10 + 600);
    }
    double r = kelp_rng_range(&a, -3, 5);
    ck_assert(r >= -3 && r < 5);
}
END_TEST

START_TEST(rng_gauss_moments)
{
    kelp_rng a;
    kelp_rng_seed(&a, 12345);
    const int n = 100000;
    double s = 0, s2 = 0;
    int within1 = 0;
    for (int i = 0; i < n; i++) {
        double g = kelp_rng_gauss(&a, 10.0, 2.0);
        ck_assert(isfinite(g));
        s += g;
        s2 += g * g;
        within1 += fabs(g - 10.0) < 2.0;
    }
    double mean = s / n, sd = sqrt(s2 / n - mean * mean);
    ck_assert(fabs(mean - 10.0) < 0.03);
    ck_assert(fabs(sd - 2.0) < 0.03);
    ck_assert(fabs((double)within1 / n - 0.6827) < 0.01); /* one sigma */
}
END_TEST

Suite *kelp_util_rng_suite(void);
Suite *kelp_util_rng_suite(void)
{
    Suite *s = suite_create("util_rng");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, glibc_rand_sequence);
    tcase_add_test(tc, rng_reproducible_and_uniform);
    tcase_add_test(tc, rng_gauss_moments);
    suite_add_tcase(s, tc);
    return s;
}
