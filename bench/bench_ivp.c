/* IvP build benchmarks for bench/ivp.sh:
 *   bench_ivp zaic N       build one ZAIC_PEAK on course:0:359:360 N times
 *   bench_ivp reflector N  build a 2-D Reflector function of ~1000 pieces N times
 * Prints the median wall time per build (ns). Instruction counts come from callgrind in ivp.sh. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/ivp.h>

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double aof(const double *pt, void *user)
{
    (void)user;
    double dx = pt[0] - 50, dy = pt[1] + 150;
    return 150.0 * exp(-(dx * dx + dy * dy) / (2 * 32.4 * 32.4));
}

static kelp_ivp_piece store[4096];
static kelp_ivp_pq_entry pq[4096];
static double work[4096];

int main(int argc, char **argv)
{
    if (argc != 3)
        return 2;
    long n = atol(argv[2]);
    if (n < 1)
        return 2;
    double *t = calloc((size_t)n, sizeof *t);
    kelp_ivp_domain d;
    kelp_diag e;
    kelp_diag_clear(&e);
    size_t pieces = 0;
    bool zaic = strcmp(argv[1], "zaic") == 0;
    if (kelp_ivp_domain_parse(&d, zaic ? "course:0:359:360" : "x:-250:249:500,y:-250:249:500", &e))
        return 1;
    for (long i = 0; i < n; i++) {
        double t0 = now_ns();
        kelp_ivp_func f;
        if (zaic) {
            kelp_ivp_zaic_peak z;
            KELP_IGNORE(kelp_ivp_zaic_peak_init(&z, &d, "course"));
            KELP_IGNORE(kelp_ivp_zaic_peak_set_params(&z, 123.69, 10, 150, 20, 0, 100, 0));
            z.wrap = true;
            if (kelp_ivp_zaic_peak_extract(&z, true, work, 4096, store, 4096, &f))
                return 1;
        } else {
            kelp_ivp_reflector r;
            KELP_IGNORE(kelp_ivp_reflector_init(&r, &d, aof, NULL));
            if (kelp_ivp_reflector_create(&r, 1000, -1, 0, store, 4096, pq, 4096, &f) < 0)
                return 1;
        }
        t[i] = now_ns() - t0;
        pieces = f.n;
    }
    qsort(t, (size_t)n, sizeof *t, cmp);
    printf("pieces %zu median_ns %.0f\n", pieces, t[n / 2]);
    free(t);
    return 0;
}
