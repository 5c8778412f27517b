/* kelp util: random numbers for the core, always caller-seeded and held in the caller's
 * struct (no global state), so a run is reproducible from its seed.
 *
 *   kelp_rng        splitmix64: the generator for simulation noise, drops and draws.
 *   kelp_rng_glibc the sequence glibc's rand() gives after srand(seed) (seed 1 is what a
 *                   program that never calls srand gets), so a kelp run can be set beside a
 *                   MOOS-IvP tool that calls rand() unseeded. The recurrence is glibc's
 *                   documented TYPE_3 additive feedback generator (r[i] = r[i-3] + r[i-31]
 *                   after a Park-Miller fill of 31 words and 310 discarded outputs).
 */
#ifndef KELP_RNG_H
#define KELP_RNG_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kelp_rng {
    uint64_t s;
} kelp_rng;

void kelp_rng_seed(kelp_rng *r, uint64_t seed);
uint64_t kelp_rng_next(kelp_rng *r);
/** Uniform in [0, 1), 53 random bits. */
double kelp_rng_uniform(kelp_rng *r);
/** Uniform in [lo, hi). */
double kelp_rng_range(kelp_rng *r, double lo, double hi);
/** Gaussian (Box-Muller; two uniform draws per call, nothing cached). */
double kelp_rng_gauss(kelp_rng *r, double mean, double sigma);

#define KELP_GLIBC_RAND_MAX 2147483647

typedef struct kelp_rng_glibc {
    int32_t r[34]; /* the last 34 words of the recurrence, a ring */
    unsigned i;    /* index of the oldest */
} kelp_rng_glibc;

/** As srand(seed); seed 0 acts as 1, as glibc's does. */
void kelp_rng_glibc_seed(kelp_rng_glibc *g, uint32_t seed);
/** As rand(): 0 .. KELP_GLIBC_RAND_MAX. */
int32_t kelp_rng_glibc_next(kelp_rng_glibc *g);

#ifdef __cplusplus
}
#endif

#endif
