/* kelp uFldPathCheck: speed and odometry of every vehicle, computed on the shoreside from the
 * positions and time stamps of its node reports, as MOOS-IvP 24.8's uFldPathCheck does
 * (ivp/src/uFldPathCheck/PathCheck_MOOSApp.cpp).
 *
 *   in:  NODE_REPORT, NODE_REPORT_LOCAL (NAME, X, Y, SPD, HDG, TIME), UPC_TRIP_RESET = alpha
 *   out: UPC_SPEED_REPORT    = vname=alpha,avg_spd=2.21                        (2 decimals)
 *        UPC_ODOMETRY_REPORT = vname=alpha,total_dist=4205.4,trip_dist=1105.2   (1 decimal)
 *
 * Per vehicle (names compared exactly, kept in strcmp order), every valid report (NAME, X, Y,
 * SPD and HDG; or NAME, LAT, LON, SPD, HDG) joins a queue of the last HISTORY_LENGTH records
 * (x, y, TIME; the arrival time when TIME is missing); a report's TIME is data, never checked
 * against the clock. Once the queue already holds two records, the step from its newest record
 * is added to total_dist and trip_dist (so the leg from the first report to the second is never
 * counted) and the vehicle's odometry is marked changed. Each iteration posts UPC_SPEED_REPORT
 * for every vehicle with two records or more: the mean of the per-leg speeds along the queue
 * (leg distance over leg TIME difference; a leg whose TIME difference is not positive is left
 * out, where 24.8 divides by it: docs/CONFORMANCE.md), then UPC_ODOMETRY_REPORT for every
 * vehicle marked changed. UPC_TRIP_RESET = <vname> zeroes the trip of a vehicle with a counted
 * leg (posted with the next change); otherwise the warning "Invalid TRIP_RESET: <vname>".
 * A bad report warns "Invalid NODE_REPORT: <report>".
 *
 * Core: no allocation, no I/O, no clock; time comes in as an argument.
 */
#ifndef KELP_PATHCHECK_H
#define KELP_PATHCHECK_H

#include <stdbool.h>
#include <stddef.h>
#include <kelp/config.h>
#include <kelp/field.h>

#ifdef __cplusplus
extern "C" {
#endif

#ifndef KELP_UPC_MAX_NODES
#define KELP_UPC_MAX_NODES 256   /**< vehicles tracked */
#endif
#ifndef KELP_UPC_MAX_HISTORY
#define KELP_UPC_MAX_HISTORY 100 /**< largest HISTORY accepted (points per vehicle) */
#endif
#define KELP_UPC_DEFAULT_HISTORY 10
#define KELP_UPC_WARN_LEN 600    /**< bytes of one warning (the report it quotes is cut) */

typedef struct kelp_upc_point {
    double x, y, t;              /**< position and the report's TIME */
} kelp_upc_point;

typedef struct kelp_upc_node {
    char name[KELP_NODEREPORT_MAX_FIELD]; /**< exactly as received */
    kelp_upc_point hist[KELP_UPC_MAX_HISTORY]; /**< ring of the last `history` records */
    unsigned head, n;            /**< oldest index, count */
    double total, trip;          /**< metres */
    double last_recv;            /**< arrival time of the last report */
    unsigned long reports;       /**< valid reports taken */
    bool has_dist;               /**< a leg was counted (24.8: the vehicle has odometry) */
    bool changed;                /**< odometry to be posted at the next iteration */
} kelp_upc_node;

typedef struct kelp_pathcheck_cfg {
    unsigned history;            /**< HISTORY_LENGTH: records in the speed queue (10), 2..KELP_UPC_MAX_HISTORY */
} kelp_pathcheck_cfg;

typedef struct kelp_pathcheck {
    kelp_pathcheck_cfg cfg;
    /* private */
    kelp_upc_node node[KELP_UPC_MAX_NODES]; /**< sorted by name (strcmp) */
    unsigned nnodes;
    unsigned long good, bad, resets, bad_resets, full;
    char ws[KELP_UPC_WARN_LEN];  /**< workspace: a warning being built */
} kelp_pathcheck;

void kelp_pathcheck_cfg_default(kelp_pathcheck_cfg *cfg);
/** One block parameter: HISTORY_LENGTH (an integer 2..KELP_UPC_MAX_HISTORY). Any other key
 *  is not taken (24.8 warns "Unhandled config line: <line>"; the app does).
 *  @return 1 taken, 0 not its key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_pathcheck_config(kelp_pathcheck_cfg *cfg, const char *key, const char *val, kelp_diag *d);
/** Start empty with cfg (copied). @return 0 or KELP_ERR_ARG (history out of range). */
KELP_MUST_CHECK int kelp_pathcheck_init(kelp_pathcheck *p, const kelp_pathcheck_cfg *cfg);
/** The variables to subscribe to, one per call (i from 0) until NULL. */
const char *kelp_pathcheck_subscription(unsigned i);
/** One mail at `now`. @return 1 used, 0 not ours, <0 bad value (a warning through
 *  out->warn, which may be NULL as may out: "Invalid NODE_REPORT: ..", "Invalid TRIP_RESET: ..").
 *  A bad `now` (kelp_util_time_ok) is refused with KELP_ERR_ARG. */
int kelp_pathcheck_mail(kelp_pathcheck *p, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out);
/** Post UPC_SPEED_REPORT for every vehicle with two records or more, then UPC_ODOMETRY_REPORT
 *  for each vehicle whose odometry changed since the last call. @return posts made. */
unsigned kelp_pathcheck_iterate(kelp_pathcheck *p, kelp_time now, const kelp_field_sink *out);
/** avg_spd of a vehicle (m/s) by the rule above (0 with fewer than two records). */
double kelp_pathcheck_speed(const kelp_upc_node *n);
/** Index of a vehicle (exact name), or -1. */
int kelp_pathcheck_find(const kelp_pathcheck *p, const char *name);
/** The AppCast report as 24.8 lays it out: the good and bad report counts, "MOOS Time Warp"
 *  (warp), and the table Node | TripDist | Distance | ReportAge | Speed | AvgSpeed (ACTable,
 *  three blanks apart) with one row per vehicle with odometry; 24.8 writes those rows outside
 *  its table, run together (docs/CONFORMANCE.md). @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_pathcheck_report(const kelp_pathcheck *p, kelp_time now, double warp, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
