/* kelp range sensors, part 2: uFldContactRangeSensor's logic (kelp_contactrange_*), uField Toolbox
 * manual (MOOS-IvP 12.2) chapter 11, with MOOS-IvP 24.8's names accepted as aliases
 * (push_dist = REACH_DISTANCE, pull_dist = REPLY_DISTANCE, echo_color = REPLY_COLOR).
 *
 * A ping from R (CRS_RANGE_REQUEST = name=R; an empty or unknown name is refused with 24.8's
 * warnings and answered by nothing), honoured at most every PING_WAIT(R) seconds (a first ping
 * always: 24.8's clock starts at 0; the clock restarts only when a ping is honoured), reports
 * the range to every other known vehicle T of an allowed type with |RT| < reach(R) + reply(T),
 * or either nolimit; beyond that with probability exp(3 (max - r) / max), one random draw per
 * target (24.8's rule; ECHO_FALLOFF = false, kelp's, turns it off); only R gets the reports.
 * allow_echo_types (target types), sensor_arc (relative bearings R hears in, from R's HDG),
 * display_pulses as 24.8. 24.8 has no IGNORE_GROUP (an unhandled line) and takes
 * RN_GAUSSIAN_SIGMA without using it. Randomness as in kelp/beaconrange.h (RAND_MODE).
 */
#ifndef KELP_CONTACTRANGE_H
#define KELP_CONTACTRANGE_H

#include <kelp/config.h>
#include <kelp/beaconrange.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_CRS_MAX_TYPES 8     /**< allow_echo_types entries */
#define KELP_CRS_MAX_ARCS 8      /**< sensor_arc intervals */

typedef struct kelp_contactrange_cfg {
    kelp_rangesense_vmap reach;      /**< REACH_DISTANCE (push_dist) 100 */
    kelp_rangesense_vmap reply;      /**< REPLY_DISTANCE (pull_dist) 100 */
    kelp_rangesense_common com;
    bool display_pulses;         /**< DISPLAY_PULSES (true) */
    bool echo_falloff;           /**< ECHO_FALLOFF (true, 24.8's rule) */
    char ping_color[KELP_VIEW_MAX_FIELD];   /**< PING_COLOR (white) */
    char reply_color[KELP_VIEW_MAX_FIELD];  /**< REPLY_COLOR / ECHO_COLOR (chartreuse) */
    char types[KELP_CRS_MAX_TYPES][KELP_RSENSE_NAME]; /**< ALLOW_ECHO_TYPES (none: all) */
    unsigned ntypes;
    double arc[KELP_CRS_MAX_ARCS][2];       /**< SENSOR_ARC "a:b" relative bearings (none: all) */
    unsigned narcs;
    char ws_val[256];            /**< workspace: the value being read by kelp_contactrange_config */
} kelp_contactrange_cfg;

typedef struct kelp_contactrange {
    kelp_contactrange_cfg cfg;
    kelp_rangesense_node node[KELP_RSENSE_MAX_NODES]; /**< sorted by name (strcmp) */
    unsigned nnodes;
    kelp_rangesense_rand rand;
    double start;
    kelp_clock clk;              /**< the newest `now` (the time step rule) */
    unsigned long requests, denied, accepted, reports, bad_mail, unknown, too_far, node_reports;
    kelp_diag diag; /**< workspace: why the last node report was refused */
    char ws_post[KELP_RSENSE_POST_WS]; /**< workspace: a range report being built */
} kelp_contactrange;

void kelp_contactrange_cfg_default(kelp_contactrange_cfg *cfg);
/** One block parameter: REACH_DISTANCE (push_dist, push_distance), REPLY_DISTANCE (pull_dist,
 *  pull_distance), PING_WAIT, REPORT_VARS, GROUND_TRUTH, VERBOSE, DISPLAY_PULSES, PING_COLOR,
 *  REPLY_COLOR (echo_color), RN_ALGORITHM, RN_UNIFORM_PCT, RN_GAUSSIAN_SIGMA,
 *  ALLOW_ECHO_TYPES, IGNORE_GROUP, SENSOR_ARC, ECHO_FALLOFF, RAND_MODE, SEED_RANDOM.
 *  @return 1 taken, 0 not its key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_contactrange_config(kelp_contactrange_cfg *cfg, const char *key, const char *val, kelp_diag *d);
void kelp_contactrange_init(kelp_contactrange *c, const kelp_contactrange_cfg *cfg, kelp_time now);
const char *kelp_contactrange_subscription(unsigned i);
/** NODE_REPORT, NODE_REPORT_LOCAL, CRS_RANGE_REQUEST. @return 1 used, 0 not ours, <0 bad. */
int kelp_contactrange_mail(kelp_contactrange *c, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out);
/** The AppCast report as 24.8's buildReport lays it out: the settings (Default Ping Wait,
 *  noise, colours, ground truth, Ignore Group, Total Node Reports) and "Vehicles(N):" with the
 *  table VName, Ping Wait, Push/Pull Dist, Pings Gen'd, Echos Rec'd, Too Freq/Far, Echos Sent,
 *  Pos. @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_contactrange_report(const kelp_contactrange *c, char *buf, size_t cap);
/** The startup block of Listing 29 ("Default Reach Distance: ..."). @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_contactrange_summary(const kelp_contactrange *c, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
