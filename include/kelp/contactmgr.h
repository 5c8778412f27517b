/* kelp pContactMgrV20: the contact manager's state machine (MOOS-IvP's pContactMgrV20:
 * parameters, alert requests, reports and macros as that app documents them).
 *
 * Contacts come from NODE_REPORT mail; ownship from NAV_X/Y/HEADING/SPEED. Alerts (mission
 * "alert = ..." lines and BCM_ALERT_REQUEST mail, "id=..,alert_range=..,cpa_range=..,
 * on_flag=VAR=val,off_flag=..,<filters>") post their flags on the off->on and on->off
 * transitions of each (contact, alert) pair, with MOOS-IvP 24.8's macros expanded exactly as
 * it does ($[VNAME] $[VTYPE] $[GROUP] $[LAT] $[LON] $[X] $[Y] $[HDG] $[DEP] $[UTIME], %[VNAME]
 * %[VTYPE] %[GROUP]; never $[SPD]). Early and cease warnings (early_warning_time, _flag,
 * cease_warning_flag), summaries CONTACTS_LIST/ALERTED/COUNT/RETIRED/RECAP, CONTACT_CLOSEST*,
 * CONTACT_RANGES, custom BCM_REPORT_REQUEST reports, VIEW_CIRCLE rings (alert_<ownship>,
 * xewarn_<contact>). Contacts pass 24.8's contact ledger (uuv -> auv, unknown type -> ship).
 *
 * Core: allocation-free, no I/O, no clock: `now` comes in; posts and warnings go out through
 * a kelp_field_sink. The state is large (about 1.2 MB with the capacities below): keep it
 * static or on the heap. Contacts are kept in ascending byte-wise name order (an index array,
 * binary search), so one report costs O(log N) to find and an iteration O(N x alerts).
 * Text values are cut at the last whole entry within KELP_MAX_SVAL bytes (the bus limit).
 */
#ifndef KELP_CONTACTMGR_H
#define KELP_CONTACTMGR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/field.h>
#include <kelp/geo.h>
#include <kelp/nodereport.h>
#include <kelp/util.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_CMGR_MAX_CONTACTS 2048  /**< contacts held at once (max_contacts is clamped to it) */
#define KELP_CMGR_MAX_ALERTS 16      /**< alert ids */
#define KELP_CMGR_MAX_FLAGS 8        /**< on_flags, and off_flags, per alert */
#define KELP_CMGR_MAX_FLAG 192       /**< bytes of one "VAR=value" flag, with NUL */
#define KELP_CMGR_MAX_ID 64          /**< bytes of an alert id, report var, source, colour */
#define KELP_CMGR_NAME KELP_NODEREPORT_MAX_FIELD /**< bytes of a contact name, type, group */
#define KELP_CMGR_MAX_FILTER 16      /**< entries of one match_/ignore_ name/type/group list */
#define KELP_CMGR_MAX_REGIONS 4      /**< match (or ignore) polygons of one filter set */
#define KELP_CMGR_MAX_REGION_PTS 16  /**< vertices of one region polygon */
#define KELP_CMGR_MAX_REPORTS 32     /**< custom range reports held (24.8 prunes beyond range_report_maxsize, default 20) */
#define KELP_CMGR_MAX_RETIRED (KELP_CMGR_MAX_CONTACTS + 50) /**< retired names before pruning */
#define KELP_CMGR_MAX_EVENTS 8       /**< events kept for the report */
#define KELP_CMGR_MAX_TEXT (KELP_MAX_SVAL + 1) /**< bytes of one summary value, with NUL */
#define KELP_CMGR_CPA_HORIZON 36000.0 /**< s: CPA is sought within 10 hours (as MOOS-IvP 24.8's pContactMgrV20) */
#define KELP_CMGR_REJECT_MARGIN 1.05 /**< a contact is retired beyond reject_range x this (24.8's margin) */
#define KELP_CMGR_MAX_ABLE 25        /**< recently disabled (and enabled) contact names kept */
#define KELP_CMGR_MAX_TALLY KELP_CMGR_MAX_CONTACTS /**< names whose alert counts are kept (beyond: not counted) */
#define KELP_CMGR_MAX_FILTERED 64    /**< names refused by the filters between two iterations (retire flags) */

KELP_STATIC_ASSERT(KELP_CMGR_MAX_ALERTS <= 32, "alert cells are bits of a uint32_t");
KELP_STATIC_ASSERT(KELP_CMGR_MAX_CONTACTS <= 65535, "contact slots are uint16_t");

enum { KELP_CMGR_VERBATIM = 0, KELP_CMGR_LAZY_LATLON, KELP_CMGR_FORCE_LATLON };

typedef struct kelp_contactmgr_poly {
    unsigned n;
    double pts[KELP_CMGR_MAX_REGION_PTS][2];
} kelp_contactmgr_poly;

/** One filter set (global or per alert). Lists: [kind: 0 name, 1 type, 2 group][0 match, 1 ignore]. */
typedef struct kelp_contactmgr_filter {
    char list[3][2][KELP_CMGR_MAX_FILTER][KELP_CMGR_NAME];
    unsigned nlist[3][2];
    kelp_contactmgr_poly region[2][KELP_CMGR_MAX_REGIONS];
    unsigned nregion[2];
    bool strict_ignore;
} kelp_contactmgr_filter;

typedef struct kelp_contactmgr_alert {
    char id[KELP_CMGR_MAX_ID];
    char source[KELP_CMGR_MAX_ID];       /**< "" for the mission file */
    /** 24.8's CMAlert ranges: -1 unset; alert_range sets cpa_range up to it when below, cpa_range
     *  sets alert_range down to it when above (the last given wins) */
    double alert_range, cpa_range;
    char on[KELP_CMGR_MAX_FLAGS][KELP_CMGR_MAX_FLAG], off[KELP_CMGR_MAX_FLAGS][KELP_CMGR_MAX_FLAG];
    unsigned non, noff;
    kelp_contactmgr_filter filter;
} kelp_contactmgr_alert;

typedef struct kelp_contactmgr_contact {
    char name[KELP_CMGR_NAME], type[KELP_CMGR_NAME], group[KELP_CMGR_NAME];
    double x, y, lat, lon, hdg, spd, dep, time;  /**< the last report */
    double range, range_extrap, range_cpa, roc;  /**< this iteration's */
    double warned_range, warned_time;            /**< early warning: range_extrap and time when warned (<0: not) */
    double will_warn;                            /**< early warning range to draw (0: none) */
    uint32_t alerted;                            /**< bit a: the pair (this, alert a) is on */
    uint32_t total, active;                      /**< alerts posted ever / now */
    bool used, has_ll, retire, filtered;
} kelp_contactmgr_contact;

typedef struct kelp_contactmgr_report {
    char var[KELP_CMGR_MAX_ID], group[KELP_CMGR_NAME], type[KELP_CMGR_NAME];
    double range, req_time;
    bool force;
    unsigned count;                  /**< names in the last list posted */
    char last[KELP_CMGR_MAX_TEXT];
} kelp_contactmgr_report;

typedef struct kelp_contactmgr_sortkey {
    double v;
    unsigned pos;
} kelp_contactmgr_sortkey;

/** One key=value component of an alert request (a workspace entry). */
typedef struct kelp_contactmgr_comp {
    const char *k;
    size_t kl;
    char v[KELP_CMGR_MAX_FLAG];
    size_t vl;
} kelp_contactmgr_comp;
#define KELP_CMGR_MAX_COMPS 24          /**< components of one alert request */

typedef struct kelp_contactmgr {
    /* configuration */
    char ownship[KELP_CMGR_MAX_ID], ownship_group[KELP_CMGR_MAX_ID], ownship_type[KELP_CMGR_MAX_ID];
    double contact_max_age, reject_range;   /**< reject_range < 0: off */
    double decay[2], recap_interval;        /**< recap_interval < 0: off */
    double range_report_timeout;
    unsigned max_contacts, max_retired, range_report_maxsize;
    bool alert_verbose, display_radii, post_all_ranges, post_closest_range, post_closest_relbng;
    bool hold_alerts_for_helm, helm_drive;
    char alert_color[KELP_CMGR_MAX_ID];     /**< the ring's colour (24.8's default gray65) */
    int coords;                             /**< KELP_CMGR_VERBATIM ... */
    kelp_geo geo;
    bool have_geo;                          /**< geodesy usable (a non-verbatim mode and a datum) */
    kelp_contactmgr_filter filter;
    kelp_contactmgr_alert alert[KELP_CMGR_MAX_ALERTS];
    unsigned nalerts;
    /* ownship */
    double osx, osy, osh, osv;
    /* contacts: slots, and their indices in ascending name order */
    kelp_contactmgr_contact contact[KELP_CMGR_MAX_CONTACTS];
    uint16_t order[KELP_CMGR_MAX_CONTACTS], spare[KELP_CMGR_MAX_CONTACTS];
    unsigned ncontacts, nspare;
    kelp_contactmgr_sortkey sortbuf[KELP_CMGR_MAX_CONTACTS]; /**< scratch */
    /* retired names, oldest first */
    char retired[KELP_CMGR_MAX_RETIRED][KELP_CMGR_NAME];
    unsigned nretired;
    /* disable/enable/expunge (24.8's BHV_ABLE_FILTER), retire flags */
    char disable_var[KELP_CMGR_MAX_ID], enable_var[KELP_CMGR_MAX_ID], expunge_var[KELP_CMGR_MAX_ID];
    char able_flag[KELP_CMGR_MAX_FLAGS][KELP_CMGR_MAX_FLAG], disable_flag[KELP_CMGR_MAX_FLAGS][KELP_CMGR_MAX_FLAG];
    char enable_flag[KELP_CMGR_MAX_FLAGS][KELP_CMGR_MAX_FLAG], retire_flag[KELP_CMGR_MAX_FLAGS][KELP_CMGR_MAX_FLAG];
    unsigned nable_flag, ndisable_flag, nenable_flag, nretire_flag;
    char disabled_c[KELP_CMGR_MAX_ABLE][KELP_CMGR_NAME], enabled_c[KELP_CMGR_MAX_ABLE][KELP_CMGR_NAME]; /**< newest first */
    unsigned ndisabled_c, nenabled_c;
    char filtered[KELP_CMGR_MAX_FILTERED][KELP_CMGR_NAME]; /**< refused since the last iteration, ascending */
    unsigned nfiltered;
    double early_warning_time;
    bool early_warning_radii;
    char ewarn_color[KELP_CMGR_MAX_ID];
    char ewarn_flag[KELP_CMGR_MAX_FLAGS][KELP_CMGR_MAX_FLAG], cwarn_flag[KELP_CMGR_MAX_FLAGS][KELP_CMGR_MAX_FLAG];
    unsigned newarn_flag, ncwarn_flag;
    char alert_off[KELP_CMGR_MAX_ALERTS][KELP_CMGR_MAX_ID]; /**< ids disabled by action=disable (known or not) */
    unsigned nalert_off;
    /** alerts posted ever / active per lower-case name; kept across retirement (24.8's
     *  PlatformAlertRecord keeps them when a contact leaves) */
    struct { char name[KELP_CMGR_NAME]; uint32_t total, active; } tally[KELP_CMGR_MAX_TALLY];
    unsigned ntally;
    unsigned long events_made;              /**< events ever made (kelp_contactmgr_event) */
    kelp_contactmgr_report report[KELP_CMGR_MAX_REPORTS];
    unsigned nreports;
    /* what was last posted */
    char prev_list[KELP_CMGR_MAX_TEXT], prev_alerted[KELP_CMGR_MAX_TEXT], prev_unalerted[KELP_CMGR_MAX_TEXT];
    char prev_retired[KELP_CMGR_MAX_TEXT], prev_recap[KELP_CMGR_MAX_TEXT], prev_ranges[KELP_CMGR_MAX_TEXT];
    char prev_closest[KELP_CMGR_NAME];
    double prev_closest_range, prev_count, prev_relbng, last_recap;
    /* counters and events */
    unsigned long alert_requests, iterations, truncations, reports_in, reports_bad;
    double t_start;
    kelp_clock clock;                       /**< the newest `now` (the time step rule) */
    unsigned long clock_steps;              /**< clock steps back taken out of own times */
    char event[KELP_CMGR_MAX_EVENTS][KELP_CMGR_MAX_FLAG + 64];
    double event_time[KELP_CMGR_MAX_EVENTS];
    unsigned nevents, event_head;
    char text[KELP_CMGR_MAX_TEXT];          /**< scratch */
    struct {                                /* workspace of one call (keeps the stack under 1 KB) */
        kelp_contactmgr_alert alert;              /**< an alert request applied to a copy first */
        kelp_contactmgr_comp comp[KELP_CMGR_MAX_COMPS]; /**< its components */
        kelp_view view;                     /**< a region parsed as a polygon */
        char str[KELP_CMGR_MAX_TEXT];       /**< a report request's text, a flag's expanded value */
    } ws;
    kelp_diag diag; /**< workspace: why the last node report was refused (read by bad_report) */
    kelp_nodereport ws_report; /**< workspace: the node report being read (keeps the stack under 1 KB) */
    char ws_warn[KELP_CMGR_MAX_FLAG + 128]; /**< workspace: a warning being formatted */
    char ws_flag[2][KELP_CMGR_MAX_FLAG]; /**< workspace: a flag's variable, raw and expanded */
    /** workspace: a VIEW_CIRCLE or ALERT_VERBOSE being formatted */
    char ws_view[(3 * KELP_CMGR_MAX_ID + 160) > (KELP_CMGR_NAME + KELP_CMGR_MAX_ID + 200)
                     ? (3 * KELP_CMGR_MAX_ID + 160) : (KELP_CMGR_NAME + KELP_CMGR_MAX_ID + 200)];
} kelp_contactmgr;

/** Defaults (the pContactMgrV20 documentation's) for ownship `ownship` (the community; its reports are dropped). */
void kelp_contactmgr_init(kelp_contactmgr *c, const char *ownship);

/** One mission parameter (name case-insensitive). @return 1 taken (also when warned), 0 not
 *  taken: not a parameter of ours, a value 24.8 refuses (the default stays) or an alert line
 *  with a component 24.8 does not take (warned through out->warn; the components before it
 *  stay): the app reports such a line as 24.8 does ("Unhandled config line: key=value"). */
KELP_MUST_CHECK int kelp_contactmgr_config(kelp_contactmgr *c, const char *key, const char *val, const kelp_field_sink *out);

/** After the block: the datum (have_* false when LatOrigin/LongOrigin are missing), then alert
 *  validity ("Invalid alert config:<id>") and the geodesy warnings. */
void kelp_contactmgr_config_done(kelp_contactmgr *c, bool have_lat, double lat0, bool have_lon, double lon0,
                           const kelp_field_sink *out);

/** The variables to subscribe to: i = 0, 1, ... until NULL. */
const char *kelp_contactmgr_subscription(unsigned i);

/** One mail at `now` from app `src` (may be NULL). @return 1 handled, 0 not ours,
 *  <0 bad mail (already warned through out). */
KELP_MUST_CHECK int kelp_contactmgr_mail(kelp_contactmgr *c, const char *var, bool is_string, const char *sval, double dval, kelp_time now,
                                   const char *src, const kelp_field_sink *out);

/** Apply an alert spec (as an "alert" line when from_mail is false, else BCM_ALERT_REQUEST).
 *  @return 1 applied, <0 rejected (warned). */
KELP_MUST_CHECK int kelp_contactmgr_alert_spec(kelp_contactmgr *c, const char *spec, bool from_mail, const char *src, kelp_time now,
                                         const kelp_field_sink *out);

/** One iteration at `now`, in 24.8's order. */
void kelp_contactmgr_iterate(kelp_contactmgr *c, kelp_time now, const kelp_field_sink *out);

/** The terminal report (24.8's, from "X/Y from Lat/Lon:" on). @return the length,
 *  or KELP_ERR_NOSPACE when cut. */
KELP_MUST_CHECK int kelp_contactmgr_report_text(const kelp_contactmgr *c, kelp_time now, char *buf, size_t cap);

/** The CPA range of an alert (24.8's "far" range; -1 unset). */
double kelp_contactmgr_cpa_range(const kelp_contactmgr_alert *a);

/** Event number `seq` (0, 1, ... up to events_made - 1) while still kept, else NULL: an app
 *  forwards the events it has not shown yet to its AppCast. */
const char *kelp_contactmgr_event(const kelp_contactmgr *c, unsigned long seq);

/** Contact index by name (binary search), or -1. */
int kelp_contactmgr_find(const kelp_contactmgr *c, const char *name);

/** Distance a contact at speed v has run dt s after its report, with decay (d1, d2). */
double kelp_contactmgr_extrap_dist(double v, double dt, double d1, double d2);

#ifdef __cplusplus
}
#endif

#endif
