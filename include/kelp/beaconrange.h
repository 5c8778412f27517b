/* kelp range sensors, part 1: uFldBeaconRangeSensor's logic (kelp_beaconrange_*), the uField Toolbox manual (MOOS-IvP 12.2)
 * chapter 10, with MOOS-IvP 24.8's names accepted as aliases.
 *
 * Range model. A request from vehicle V reaches beacon B when
 *     reach(V) + pull(B) >= |VB|    (REACH_DISTANCE, alias 24.8's node_push_dist; beacon pull_dist, 0)
 * and B's report reaches vehicle U when
 *     report_range(B) + pull(U) >= |UB|   (report_range, alias 24.8's push_dist; node_pull_dist, 0)
 * where a negative distance ("nolimit") always passes (24.8's pingTrans; its defaults: node push
 * and pull 100, beacon push and pull 50). A solicited reply goes to the requester only; an
 * unsolicited one (a beacon with a freq, more than its period after its last report) to every
 * vehicle in reach. A vehicle's ping-wait clock starts at 0 (24.8): its first request is in time;
 * one at ping_wait x (1 - KELP_RSENSE_LATE) after the last paid one is in time (24.8's late clock).
 * A request is "name=V" (24.8 reads name= only); an empty or unknown V is refused with 24.8's
 * run warnings ("Failed Range Request: Unknown vehicle[V]", "Bad Mail: BRS_RANGE_REQUEST");
 * V must be the name exactly as the vehicle reports it (24.8's ledger: "INDIGO" is unknown).
 * The ground-truth reports come only with noise (RN_ALGORITHM) and GROUND_TRUTH (true).
 *
 * Randomness: RAND_MODE = kelp (the default; kelp_rng seeded by SEED_RANDOM) or glibc
 * (kelp_rng_glibc seeded 1, i.e. the rand() sequence of a program that never calls srand).
 * In glibc mode the values are drawn where and as MOOS-IvP 24.8 draws them, with its
 * arithmetic: uniform noise (rand() % 10000) / 5000 - 1, one per report; an unsolicited
 * interval lo + (rand() % 1000) / 1000 * (hi - lo) (drawn when a beacon's freq is configured,
 * on the first iteration, when an unsolicited broadcast stamps the beacon, before its reports,
 * and after each solicited reply, also for a fixed freq); gaussian noise (kelp's RN_ALGORITHM
 * = gaussian) MOOSWhiteNoise's polar method with its cached second value, except in glibc mode,
 * which drops a gaussian RN_ALGORITHM as 24.8 does (kelp_rangesense_common_as_248). RN_UNIFORM_PCT alone
 * sets the fraction, not the algorithm (24.8). Beacons go in 24.8's order by default (its
 * mission reader hands the block over last line first: BEACON_ORDER = reverse).
 */
#ifndef KELP_BEACONRANGE_H
#define KELP_BEACONRANGE_H

#include <stdbool.h>
#include <stddef.h>
#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/field.h>
#include <kelp/util.h>
#include <kelp/geo.h>
#include <kelp/rng.h>
#include <kelp/rangesense.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ uFldBeaconRangeSensor */

#ifndef KELP_BRS_MAX_BEACONS
#define KELP_BRS_MAX_BEACONS 64
#endif
#define KELP_BRS_SPEC_LEN 256    /**< bytes of one BEACON line, with NUL */
#define KELP_BRS_LABEL 32
/** The warning of kelp_beaconrange_config's result 2 (a BEACON's query_range). */
#define KELP_BRS_WARN_QUERY_RANGE "query_range is not used (report_range is): ignored"

typedef enum kelp_brs_payments {
    KELP_BRS_UPON_ACCEPT = 0,    /**< the clock restarts when a request is honoured (default) */
    KELP_BRS_UPON_REQUEST,       /**< ... at every request, honoured or not */
    KELP_BRS_UPON_RESPONSE       /**< ... only when the requester got a report */
} kelp_brs_payments;

typedef struct kelp_brs_beacon {
    char label[KELP_BRS_LABEL];
    char shape[KELP_BRS_LABEL];
    char color[KELP_BRS_LABEL];
    double x, y, width;
    double freq_lo, freq_hi;     /**< unsolicited period s, fixed (lo == hi) or uniform; < 0 never */
    double push;                 /**< report_range m (< 0 nolimit) */
    double pull;                 /**< 24.8 pull_dist m, added to reach (0) */
    double ts;                   /**< time stamp of its last report (24.8's setTimeStamp) */
    double cur;                  /**< the period drawn at the last time stamp (-1 never) */
    bool freq_set;               /**< freq given on its own line (24.8 draws then) */
    unsigned long heard, replies, unsol;
} kelp_brs_beacon;

typedef struct kelp_beaconrange_cfg {
    kelp_brs_beacon dflt;        /**< DEFAULT_BEACON_* (orange circle 4 m, report range 100, never) */
    char spec[KELP_BRS_MAX_BEACONS][KELP_BRS_SPEC_LEN]; /**< BEACON lines, applied after the defaults */
    unsigned nspec;
    kelp_rangesense_vmap reach;      /**< REACH_DISTANCE (node_push_dist) 100 */
    kelp_rangesense_vmap node_pull;  /**< 24.8 node_pull_dist (0) */
    kelp_rangesense_common com;
    kelp_brs_payments payments;
    bool report_xy;              /**< REPORT_XY (false): x=,y= of the beacon in each report */
    bool config_order;           /**< BEACON_ORDER = config (24.8); default reverse (the 12.2 manual's listings) */
    char ws_val[KELP_BRS_SPEC_LEN]; /**< workspace: the value being read by kelp_beaconrange_config */
} kelp_beaconrange_cfg;

typedef struct kelp_beaconrange {
    kelp_beaconrange_cfg cfg;
    kelp_brs_beacon beacon[KELP_BRS_MAX_BEACONS]; /**< in iteration order */
    unsigned nbeacons;
    kelp_rangesense_node node[KELP_RSENSE_MAX_NODES]; /**< sorted by name (strcmp), as 24.8's map */
    unsigned nnodes;
    kelp_rangesense_rand rand;
    double start;
    kelp_clock clk;              /**< the newest `now` (the time step rule) */
    bool started;                /**< markers posted, timers drawn (first iterate) */
    unsigned long requests, denied, accepted, reports, bad_mail, unknown;
    kelp_diag diag; /**< workspace: why the last node report was refused */
    char ws_label[KELP_RSENSE_NAME + KELP_BRS_LABEL + 8]; /**< workspace: a pulse's label */
    char ws_post[KELP_RSENSE_POST_WS]; /**< workspace: a range report being built */
} kelp_beaconrange;

/** The defaults of the uField Toolbox manual (MOOS-IvP 12.2), section 10.1. */
void kelp_beaconrange_cfg_default(kelp_beaconrange_cfg *cfg);
/** One block parameter (case-insensitive, a trailing ';' ignored): BEACON,
 *  DEFAULT_BEACON_FREQ/_REPORT_RANGE/_WIDTH/_COLOR/_SHAPE (24.8: _PUSH_DIST, _PULL_DIST,
 *  and its example's "default beacon_color"), REACH_DISTANCE (node_push_dist),
 *  NODE_PULL_DIST, PING_WAIT, PING_PAYMENTS, REPORT_VARS, GROUND_TRUTH, RN_ALGORITHM,
 *  RN_UNIFORM_PCT, RN_GAUSSIAN_SIGMA, VERBOSE, REPORT_XY, BEACON_ORDER, RAND_MODE,
 *  SEED_RANDOM. @return 1 taken, 2 taken with the warning KELP_BRS_WARN_QUERY_RANGE, 0 not its key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_beaconrange_config(kelp_beaconrange_cfg *cfg, const char *key, const char *val, kelp_diag *d);
/** Build the beacons and start at `now`. @return@return 0, or <0 (reason in d) (a bad BEACON). */
KELP_MUST_CHECK int kelp_beaconrange_init(kelp_beaconrange *b, const kelp_beaconrange_cfg *cfg, kelp_time now, kelp_diag *d);
const char *kelp_beaconrange_subscription(unsigned i);
/** NODE_REPORT, NODE_REPORT_LOCAL, BRS_RANGE_REQUEST. @return 1 used, 0 not ours, <0 bad
 *  (a warning through out->warn). */
KELP_MUST_CHECK int kelp_beaconrange_mail(kelp_beaconrange *b, const char *var, bool is_string, const char *sval, kelp_time now,
                                        const kelp_field_sink *out);
/** First call: VIEW_MARKER per beacon, unsolicited timers drawn. Then unsolicited reports.
 *  @return the range reports posted. */
unsigned long kelp_beaconrange_iterate(kelp_beaconrange *b, kelp_time now, const kelp_field_sink *out);
/** The startup block of Listing 25 ("SRS Model - # Beacons: ..."). @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_beaconrange_summary(const kelp_beaconrange *b, char *buf, size_t cap);
/** The AppCast report as 24.8's buildReport lays it out: "Beacons(N):" and the beacon table
 *  (ID, X, Y, Freq, Pings Unsol/Recvd/Gen'd, Noise, Push/Pull Dist), "Vehicles(N):" and the
 *  vehicle table (VName, Push/Pull Dist, Unsol Rec'd, Pings Gen'd/Rep'd, Too Freq/Far), then
 *  "Ledger: now:N, reps:R, who:a,b,..". @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_beaconrange_report(const kelp_beaconrange *b, char *buf, size_t cap);
/** Index of a beacon by label, or -1. */
int kelp_beaconrange_find(const kelp_beaconrange *b, const char *label);

#ifdef __cplusplus
}
#endif

#endif
