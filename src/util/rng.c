/* kelp util: caller-seeded random numbers (see include/kelp/rng.h). */
#include <math.h>
#include <kelp/rng.h>

void kelp_rng_seed(kelp_rng *r, uint64_t seed)
{
    r->s = seed;
}

uint64_t kelp_rng_next(kelp_rng *r)
{
    uint64_t z = (r->s += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

double kelp_rng_uniform(kelp_rng *r)
{
    return (double)(kelp_rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

double kelp_rng_range(kelp_rng *r, double lo, double hi)
{
    return lo + (hi - lo) * kelp_rng_uniform(r);
}

double kelp_rng_gauss(kelp_rng *r, double mean, double sigma)
{
    double u1 = 1.0 - kelp_rng_uniform(r); /* (0, 1]: log() stays finite */
    double u2 = kelp_rng_uniform(r);
    return mean + sigma * sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* ---- glibc rand() ----
 * Fill: r0 = seed, r[i] = 16807 * r[i-1] mod (2^31 - 1) for i = 1..30 (signed, Schrage's
 * method), r[31..33] = r[0..2]; then r[i] = r[i-3] + r[i-31] mod 2^32, the first 310 of
 * these discarded, each later one giving an output r[i] >> 1. The ring keeps 34 words. */

static int32_t park_miller(int32_t x)
{
    int32_t hi = x / 127773, lo = x % 127773;
    int32_t w = 16807 * lo - 2836 * hi;
    return w < 0 ? w + 2147483647 : w;
}

static uint32_t step(kelp_rng_glibc *g)
{
    /* the new word r[n] = r[n-3] + r[n-31]; with the ring's oldest at i (= r[n-34]) */
    unsigned i = g->i;
    uint32_t v = (uint32_t)g->r[(i + 31) % 34] + (uint32_t)g->r[(i + 3) % 34];
    g->r[i] = (int32_t)v;
    g->i = (i + 1) % 34;
    return v;
}

void kelp_rng_glibc_seed(kelp_rng_glibc *g, uint32_t seed)
{
    g->r[0] = (int32_t)(seed ? seed : 1);
    for (int k = 1; k < 31; k++) g->r[k] = park_miller(g->r[k - 1]);
    for (int k = 31; k < 34; k++) g->r[k] = g->r[k - 31];
    g->i = 0;
    for (int k = 0; k < 310; k++) (void)step(g);
}

int32_t kelp_rng_glibc_next(kelp_rng_glibc *g)
{
    return (int32_t)(step(g) >> 1);
}
