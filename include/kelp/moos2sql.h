/* kelp moos2sql: the iMOOS2SQL role (Goby 1.1's topside recorder and geov feed), core part.
 *
 * A posting on the bus is classified into one record of three kinds:
 *   status   NODE_REPORT, NODE_REPORT_LOCAL (STATUS_VAR adds more): a node report, parsed
 *            with kelp_nodereport_parse; the vehicle is its NAME.
 *   contact  pContactMgrV20's reports (CONTACT_VAR adds more): CONTACTS_LIST, CONTACTS_ALERTED,
 *            CONTACTS_UNALERTED, CONTACTS_RETIRED, CONTACTS_RECAP, CONTACTS_COUNT,
 *            CONTACT_CLOSEST, CONTACT_CLOSEST_RANGE, CONTACT_RANGES; the vehicle is the
 *            community that posted it (the ownship); count = the items listed (names, ranges,
 *            recap entries, alerted pairs; the value of CONTACTS_COUNT).
 *   track    decoded acoustic status messages (pAcommsHandler's on_receipt publishes with
 *            <all/>, TRACK_VAR adds more): STATUS_REPORT (missions/fleet), STATUS_SUMMARY
 *            (missions/acomms_e2e), STATUS_REPORT_IN (the SIMPLE_STATUS example); "key=value"
 *            text whose vehicle is the value of name, vname or node (any case; "" if none) and
 *            whose position is nav_x/x, nav_y/y, nav_lat/lat, nav_long/nav_lon/lon/long, with
 *            heading/hdg/nav_heading, speed/spd/nav_speed, depth/dep/nav_depth.
 *
 * The database (SCHEMA below, applied by the app with SQLite; PRAGMA user_version holds the
 * number of migrations applied, each one runs once, in order, in its own transaction):
 *   status(id, time, name, community, type, mode, x, y, lat, lon, spd, hdg, depth, report)
 *   contact(id, time, name, community, var, count, value)
 *   track(id, time, name, community, var, x, y, lat, lon, hdg, spd, depth, value)
 * time is the posting's MOOS time; community the community it was heard in; a number absent
 * from the posting is NULL. Each table has an index on (name, time).
 *
 * The fleet: the latest position of each vehicle (status or track with a position; x/y turned
 * into lat/lon with the datum when given), written as a KML document with one Placemark per
 * vehicle (name, description, TimeStamp, heading, Point lon,lat), and the NetworkLink file a
 * Google Earth display opens, which reloads that document every refresh seconds.
 *
 * Core: allocation-free, no I/O. The classifier is safe on arbitrary bytes (fuzzed).
 */
#ifndef KELP_MOOS2SQL_H
#define KELP_MOOS2SQL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/geo.h>
#include <kelp/nodereport.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_M2S_MAX_VARS 24      /**< variables per kind */
#define KELP_M2S_MAX_VEHICLES 64  /**< vehicles in the fleet (KML) */
#define KELP_M2S_PATH 256         /**< bytes of a path parameter, with NUL */

typedef enum kelp_moos2sql_kind { KELP_M2S_NONE = 0, KELP_M2S_STATUS, KELP_M2S_CONTACT, KELP_M2S_TRACK } kelp_moos2sql_kind;

typedef struct kelp_moos2sql_cfg {
    char vars[3][KELP_M2S_MAX_VARS][KELP_MAX_NAME]; /**< [kind - 1]: the variables recorded */
    unsigned nvars[3];
    char database[KELP_M2S_PATH];  /**< DATABASE (default moos2sql.db) */
    char kml[KELP_M2S_PATH];       /**< KML_FILE (default fleet.kml; "" none) */
    char kml_link[KELP_M2S_PATH];  /**< KML_LINK_FILE (default fleet_link.kml; "" none) */
    double kml_period;             /**< KML_PERIOD: s between rewrites of the KML (default 2) */
    double commit_period;          /**< COMMIT_PERIOD: s between commits (default 0.25, <= 0.5) */
    bool have_datum;
    kelp_geo datum;                /**< for x/y-only positions */
} kelp_moos2sql_cfg;

/** Defaults: the variables listed above, the paths, 2 s, 0.25 s, no datum. */
void kelp_moos2sql_cfg_default(kelp_moos2sql_cfg *c);

/** One ProcessConfig parameter: DATABASE, KML_FILE, KML_LINK_FILE, KML_PERIOD (> 0),
 *  COMMIT_PERIOD (in (0, 0.5]), STATUS_VAR, CONTACT_VAR, TRACK_VAR (repeatable; comma lists
 *  too; a variable names one kind only, the last word wins).
 *  @return 1 taken, 0 not ours, <0 (reason in d). */
KELP_MUST_CHECK int kelp_moos2sql_config(kelp_moos2sql_cfg *c, const char *key, const char *val, kelp_diag *d);

/** The kind recorded for a variable (exact name). */
kelp_moos2sql_kind kelp_moos2sql_kind_of(const kelp_moos2sql_cfg *c, const char *var);

typedef struct kelp_moos2sql_record {
    kelp_moos2sql_kind kind;
    const char *var;               /**< the posting's variable (the caller's string) */
    const char *community;         /**< where it was heard (the caller's string) */
    double time;
    char name[KELP_NODEREPORT_MAX_FIELD]; /**< the vehicle */
    const char *value;             /**< the posting's text ("" for a number: see dval) */
    size_t value_len;
    bool is_number;
    double dval;
    kelp_nodereport nr;            /**< status: the report; track: the position fields found
                                        (fields bits KELP_NR_X.. KELP_NR_DEPTH, name in name) */
    long count;                    /**< contact: items listed */
} kelp_moos2sql_record;

/** Classify one posting. sval/slen is the text of a string posting (a NUL at sval[slen] and
 *  none before, as in kelp_var), dval the value of a number posting (is_string false).
 *  @return 1 (out filled), 0 (not a recorded variable), KELP_ERR_PARSE / KELP_ERR_RANGE
 *  (a recorded variable whose value cannot be read: d says why; not recorded). */
KELP_MUST_CHECK int kelp_moos2sql_classify(const kelp_moos2sql_cfg *c, const char *var, const char *community, double time,
                                      bool is_string, const char *sval, size_t slen, double dval, kelp_moos2sql_record *out,
                                      kelp_diag *d);

/* ------------------------------------------------------------------ the fleet and KML */

typedef struct kelp_moos2sql_vehicle {
    char name[KELP_NODEREPORT_MAX_FIELD];
    char type[KELP_NODEREPORT_MAX_FIELD];
    char mode[KELP_NODEREPORT_MAX_FIELD];
    double time, lat, lon, hdg, spd, depth; /**< hdg, spd, depth NaN when unknown */
    unsigned long reports;
} kelp_moos2sql_vehicle;

typedef struct kelp_moos2sql_fleet {
    kelp_moos2sql_vehicle v[KELP_M2S_MAX_VEHICLES];
    unsigned n;
    bool changed;                  /**< a position arrived since the last kelp_moos2sql_kml */
    unsigned long dropped;         /**< positions of vehicles beyond KELP_M2S_MAX_VEHICLES */
} kelp_moos2sql_fleet;

void kelp_moos2sql_fleet_init(kelp_moos2sql_fleet *f);
/** Take the position of a status or track record (with a name and a position; x/y need the
 *  datum). @return 1 taken, 0 not a position. */
int kelp_moos2sql_fleet_update(kelp_moos2sql_fleet *f, const kelp_moos2sql_cfg *c, const kelp_moos2sql_record *r);

/** The KML document (UTF-8, XML text escaped), vehicles in name order. title may be NULL.
 *  @return its length, or KELP_ERR_NOSPACE when cap is too small (buf then holds nothing
 *  usable). Clears f->changed. */
KELP_MUST_CHECK int kelp_moos2sql_kml(kelp_moos2sql_fleet *f, const char *title, char *buf, size_t cap);

/** The NetworkLink document: href (escaped) reloaded every refresh s. @return as kelp_moos2sql_kml. */
KELP_MUST_CHECK int kelp_moos2sql_kml_link(const char *title, const char *href, double refresh, char *buf, size_t cap);

/** Append s (n bytes) to buf at *len as XML character data (&amp; &lt; &gt; &quot; &apos;;
 *  control bytes other than tab/newline dropped). @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_moos2sql_xml_escape(char *buf, size_t cap, size_t *len, const char *s, size_t n);

/* ------------------------------------------------------------------ the schema */

/** The migrations, in order; migration i (0-based) brings user_version from i to i + 1. */
extern const char *const kelp_moos2sql_migrations[];
extern const unsigned kelp_moos2sql_nmigrations;

#ifdef __cplusplus
}
#endif

#endif
