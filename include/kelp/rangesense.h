/* kelp range sensors, part 0: what the beacon and contact range sensors share (kelp_rangesense_*:
 * node table, per-vehicle parameter maps, range noise, the kelp or glibc random draws). The
 * sensors are in kelp/beaconrange.h and kelp/contactrange.h; the range model and the glibc
 * mode are described in kelp/beaconrange.h. */
#ifndef KELP_RANGESENSE_H
#define KELP_RANGESENSE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/field.h>
#include <kelp/util.h>
#include <kelp/geo.h>
#include <kelp/rng.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ shared */

#ifndef KELP_RSENSE_MAX_NODES
#define KELP_RSENSE_MAX_NODES 128   /**< vehicles known from node reports */
#endif
#ifndef KELP_RSENSE_MAX_VCFG
#define KELP_RSENSE_MAX_VCFG 32     /**< per-vehicle entries of one parameter (REACH_DISTANCE = henry = 40) */
#endif
#define KELP_RSENSE_NAME KELP_NODEREPORT_MAX_FIELD
#define KELP_RSENSE_LEDGER_WHO 4    /**< names in the AppCast's ledger line (24.8's getSummary) */
/** A request is in time once ping_wait x (1 - KELP_RSENSE_LATE) has passed since the last paid
 *  one. 24.8 stamps a request with the MOOS time of its previous iteration, and its iterations
 *  run about 0.5 ms over their 250 ms period (AppTick 4: 0.2 %), so its clock reads ping_wait
 *  when an on-time clock reads 0.2 % less: a request scripted exactly ping_wait after the last
 *  paid one is honoured (brs_d1_nonoise: 10.02 s apart; crs_n1_uniform: 12.01-12.02 s). kelp's
 *  runner iterates on time, give or take the host's scheduling. What 24.8 does when its own
 *  loop stalls a whole period (crs_n1_uniform at 37 s, brs_d1_nonoise at 115 s: a request then
 *  comes 0.25 s short and is refused) no rule can foresee. */
#define KELP_RSENSE_LATE 0.002

typedef enum kelp_rangesense_noise_alg {
    KELP_RSENSE_NOISE_NONE = 0,
    KELP_RSENSE_NOISE_UNIFORM,   /**< r + U(-pct r, +pct r) */
    KELP_RSENSE_NOISE_GAUSSIAN   /**< r + N(0, sigma) */
} kelp_rangesense_noise_alg;

typedef enum kelp_rangesense_vars {
    KELP_RSENSE_SHORT = 0,       /**< <PFX>_RANGE_REPORT with vname= */
    KELP_RSENSE_LONG,            /**< <PFX>_RANGE_REPORT_<VNAME> */
    KELP_RSENSE_BOTH
} kelp_rangesense_vars;

/** One parameter given per vehicle: `default = v`, `<vname> = v`, or a bare `v`. A negative
 *  value is "nolimit". */
typedef struct kelp_rangesense_vmap {
    double dflt;
    char name[KELP_RSENSE_MAX_VCFG][KELP_RSENSE_NAME];
    double v[KELP_RSENSE_MAX_VCFG];
    unsigned n;
} kelp_rangesense_vmap;

/** The random source (in the tool's struct; no global state). */
typedef struct kelp_rangesense_rand {
    bool glibc;                  /**< RAND_MODE = glibc */
    kelp_rng rng;
    kelp_rng_glibc g;
    bool have_gset;              /**< MOOSWhiteNoise's cached second deviate */
    double gset;
    unsigned long draws;         /**< values drawn so far */
} kelp_rangesense_rand;

typedef struct kelp_rangesense_noise {
    kelp_rangesense_noise_alg alg;
    double pct;                  /**< uniform: fraction of the range in [0,1] */
    double sigma;                /**< gaussian: metres */
} kelp_rangesense_noise;

typedef struct kelp_rangesense_node {
    char name[KELP_RSENSE_NAME]; /**< as it arrived (compared exactly, as 24.8's ledger) */
    char type[KELP_RSENSE_NAME];
    double x, y, hdg;
    double clock;                /**< ping-wait clock: the last paid request (valid once pinged) */
    bool pinged;                 /**< 24.8's clock starts at 0: a first request is always in time */
    unsigned long reports, pings, denied, accepted, heard;
    unsigned long unsol;         /**< unsolicited reports received (BRS) */
    unsigned long replied;       /**< replies received (BRS Rep'd) */
    unsigned long too_far;       /**< beacons or contacts out of range of an honoured request */
    unsigned long echoes_sent;   /**< CRS: times this vehicle was reported to a pinger */
} kelp_rangesense_node;

/** Verbose console lines (may be NULL): the 12.2 manual's event output. */
typedef void (*kelp_rangesense_log_fn)(void *ctx, const char *line);

/** The parameters both sensors take. */
typedef struct kelp_rangesense_common {
    kelp_rangesense_vmap ping_wait;  /**< PING_WAIT 30 s */
    kelp_rangesense_vars report_vars;/**< REPORT_VARS (short) */
    kelp_rangesense_noise noise;     /**< RN_ALGORITHM, RN_UNIFORM_PCT, RN_GAUSSIAN_SIGMA (none) */
    bool ground_truth;           /**< GROUND_TRUTH (false) */
    bool verbose;                /**< VERBOSE (false) */
    bool glibc;                  /**< RAND_MODE = glibc (default kelp) */
    kelp_rangesense_noise_alg alg248; /**< the algorithm 24.8 would keep: only uniform is one of its */
    bool pct248;                 /**< glibc mode: the uniform fraction was given (24.8 reads the block
                                      last line first, so the first of RN_UNIFORM_PCT and
                                      RN_ALGORITHM's pct= in the file is the one it keeps) */
    uint64_t seed;               /**< SEED_RANDOM (1) */
    kelp_geo geo;                /**< datum for reports with only LAT,LON */
    bool have_geo;
    kelp_rangesense_log_fn log;      /**< verbose lines (NULL: none) */
    void *log_ctx;
} kelp_rangesense_common;

void kelp_rangesense_common_default(kelp_rangesense_common *c);
/** RAND_MODE = glibc runs as MOOS-IvP 24.8, whose rn_algorithm knows only "uniform": once the
 *  mode is set, kelp_rangesense_common_config returns 0 (not a parameter: the app's unhandled
 *  line warning, as 24.8's) for any other RN_ALGORITHM, so the noise stays what 24.8 keeps. A
 *  gaussian line read before RAND_MODE is dropped here (uniform if a uniform line was given,
 *  else none): call once the block is read. @return true when it dropped one (the app warns). */
bool kelp_rangesense_common_as_248(kelp_rangesense_common *c);
/** PING_WAIT, REPORT_VARS, RN_ALGORITHM, RN_UNIFORM_PCT, RN_GAUSSIAN_SIGMA, GROUND_TRUTH,
 *  VERBOSE, RAND_MODE, SEED_RANDOM (v already trimmed). @return 1, 0 not one, <0 (reason in d). */
KELP_MUST_CHECK int kelp_rangesense_common_config(kelp_rangesense_common *c, const char *key, const char *v, kelp_diag *d);

/** Value of name in m (default when not listed). */
double kelp_rangesense_vmap_get(const kelp_rangesense_vmap *m, const char *name);
/** Apply "default = v", "<vname> = v" or "v" (v a number, or nolimit/unlimited = -1 when
 *  allow_nolimit). @return 1, or <0 (reason in d). */
KELP_MUST_CHECK int kelp_rangesense_vmap_set(kelp_rangesense_vmap *m, const char *val, bool allow_nolimit, kelp_diag *d);
/** RN_ALGORITHM: "uniform,pct=0.12", "gaussian,sigma=1.5" (also "gauss"), "none".
 *  @return 1 or <0 (reason in d). */
KELP_MUST_CHECK int kelp_rangesense_noise_set(kelp_rangesense_noise *n, const char *val, kelp_diag *d);
void kelp_rangesense_rand_init(kelp_rangesense_rand *r, bool glibc, uint64_t seed);
/** Bytes of the workspace a range report is built in (the sensor's, off the stack). */
#define KELP_RSENSE_POST_WS (320 + KELP_MAX_NAME + KELP_RSENSE_NAME)
/** The time step rule: move the vehicles' ping-wait clocks back by a backward clock step. */
void kelp_rangesense_nodes_back(kelp_rangesense_node *node, unsigned n, double back);
/** The noisy range (draws one value for uniform, MOOSWhiteNoise's pattern for gaussian,
 *  nothing for none). */
double kelp_rangesense_noisy(kelp_rangesense_rand *r, const kelp_rangesense_noise *n, double range);
/** Uniform in [lo, hi] as the mode draws it (glibc: lo + (rand()%1000)/1000*(hi-lo)). */
double kelp_rangesense_interval(kelp_rangesense_rand *r, double lo, double hi);
/** Uniform in [0,1) (glibc: (rand()%10000)/10000). */
double kelp_rangesense_unit(kelp_rangesense_rand *r);

#ifdef __cplusplus
}
#endif

#endif
