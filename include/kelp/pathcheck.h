/* kelp uFldPathCheck: speed and odometry of every vehicle, computed on the shoreside from the
 * positions and time stamps of its node reports (the uField Toolbox manual (MOOS-IvP 12.2),
 * chapter 8).
 *
 *   in:  NODE_REPORT, NODE_REPORT_LOCAL (NAME, X, Y, TIME), UPC_TRIP_RESET = alpha
 *        (UPC_ODOMETRY_RESET, named in the 12.2 manual's section 8.2, is a synonym)
 *   out: UPC_ODOMETRY_REPORT = vname=alpha,total_dist=4205.4,trip_dist=1105.2   (1 decimal)
 *        UPC_SPEED_REPORT    = vname=alpha,avg_speed=2.21                        (2 decimals)
 *
 * Per vehicle, each report (x, y, t = TIME, or the arrival time without TIME) older than or
 * as old as the last one is ignored; otherwise the step from the last position is added to
 * total_dist and trip_dist and the point joins a queue of the last HISTORY points. avg_speed
 * is the distance along the queue over its time span (0 with one point). Each iteration
 * posts both reports for every vehicle updated (or trip-reset) since the last one.
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

typedef struct kelp_upc_point {
    double x, y, t;
    double d;                    /**< distance from the point before (0 for the first) */
} kelp_upc_point;

typedef struct kelp_upc_node {
    char name[KELP_NODEREPORT_MAX_FIELD]; /**< as first received */
    kelp_upc_point hist[KELP_UPC_MAX_HISTORY]; /**< ring of the last `history` points */
    unsigned head, n;            /**< oldest index, count */
    double total, trip;          /**< metres */
    double last_recv;            /**< arrival time of the last report */
    unsigned long reports, ignored;
    bool updated;                /**< to be posted at the next iteration */
} kelp_upc_node;

typedef struct kelp_field_upc_cfg {
    unsigned history;            /**< HISTORY (HISTORY_LENGTH in 24.8): points in the speed queue (10), 2.. */
} kelp_field_upc_cfg;

typedef struct kelp_field_upc {
    kelp_field_upc_cfg cfg;
    /* private */
    kelp_upc_node node[KELP_UPC_MAX_NODES];
    unsigned nnodes;
    unsigned long good, bad, resets, bad_resets, full;
} kelp_field_upc;

void kelp_field_upc_cfg_default(kelp_field_upc_cfg *cfg);
/** One block parameter: HISTORY or HISTORY_LENGTH (an integer 2..KELP_UPC_MAX_HISTORY).
 *  @return 1 taken, 0 not its key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_field_upc_config(kelp_field_upc_cfg *cfg, const char *key, const char *val, kelp_diag *d);
/** Start empty with cfg (copied). @return 0 or KELP_ERR_ARG (history out of range). */
KELP_MUST_CHECK int kelp_field_upc_init(kelp_field_upc *p, const kelp_field_upc_cfg *cfg);
/** The variables to subscribe to, one per call (i from 0) until NULL. */
const char *kelp_field_upc_subscription(unsigned i);
/** One mail at `now`. @return 1 used, 0 not ours, <0 bad value (a warning through
 *  out->warn, which may be NULL as may out). */
int kelp_field_upc_mail(kelp_field_upc *p, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out);
/** Post the reports of the vehicles updated since the last call. @return posts made. */
unsigned kelp_field_upc_iterate(kelp_field_upc *p, kelp_time now, const kelp_field_sink *out);
/** avg_speed of a vehicle (m/s) by the rule above. */
double kelp_field_upc_speed(const kelp_upc_node *n);
/** Index of a vehicle (case-insensitive), or -1. */
int kelp_field_upc_find(const kelp_field_upc *p, const char *name);
/** The terminal report (counts and one row per vehicle). @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_field_upc_report(const kelp_field_upc *p, kelp_time now, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
