/* kelp viewer: the model behind kelp-viewer (the pMarineViewer role in a browser).
 *
 * Mail in (NODE_REPORT / NODE_REPORT_LOCAL and the VIEW_* artifacts) with `now` (MOOS time),
 * JSON out into a caller buffer: a whole snapshot, or the changes since a sequence number the
 * page last saw. Every change bumps the model's sequence number and stamps what changed, so a
 * page polled (or pushed to) every 100-250 ms receives each changed vehicle once (its latest
 * report: updates are coalesced per vehicle) plus the trail points added since.
 *
 *  - vehicles: keyed by NAME; X/Y from LAT/LON with the datum when the report has no X/Y
 *    (kelp_nodereport_complete); a bounded trail ring per vehicle (trails_length points, one
 *    per report); stale after stale_report_thresh seconds without a report, removed after
 *    stale_remove_thresh (pMarineViewer's parameters and defaults as MOOS-IvP's current
 *    VPlug_VehiSettings has them: 60 s, at least 2; 180 s; here 0 means never).
 *  - artifacts: keyed by (kind, label); a posting with active=false erases; a pulse
 *    (VIEW_COMMS_PULSE, VIEW_RANGE_PULSE) is dropped `duration` seconds after it arrived.
 *    When the table is full the oldest pulse, else the oldest artifact, makes room.
 *  - AppCasts: the last APPCAST string of each (node, proc) (MOOS-IvP's AppCasting, see
 *    kelp/appcast.h), for the page's AppCast pane; the oldest makes room when the table is full.
 *  - commands: pMarineViewer's button_one..button_twenty (also button_1..button_20) and
 *    action / action+ lines, with pMarineViewer's rules. A button is "LABEL # VAR=value # ...":
 *    the part without '=' is its label, color=C its colour, the rest its pokes; another line
 *    for the same button adds pokes. An action line "VAR=value # VAR=value ..." makes one menu
 *    entry per pair, labelled "VAR=value"; with a "menu_key=KEY" part the entries share KEY,
 *    and choosing one posts every pair with that KEY (from any action line); action+ puts a
 *    separator after its entries. A value is a number if the whole of it parses as one, else
 *    a string; a double-quoted value is a string without its quotes ("3" posts "3"). The page
 *    names a command only by its index, so it can post nothing else.
 *
 * JSON (numbers with fixed decimals, strings escaped):
 *   {"seq":N,"now":T,"full":1|0,"cfg":{...},            (cfg only in a snapshot)
 *    "veh":[{"name":..,"type":..,"x":..,"y":..,"hdg":..,"spd":..,"dep":..,"lat":..,"lon":..,
 *            "mode":..,"len":..,"group":..,"color":..,"allstop":..,"rtime":..,"t":T_RECEIVED,
 *            "stale":0|1,"trail":[[x,y],...]}  or {"name":..,"gone":1}, ...],
 *    "art":[{"kind":"polygon","label":..,"t":T_RECEIVED, the kind's fields} or
 *           {"kind":..,"label":..,"gone":1}, ...],
 *    "cast":[{"node":..,"proc":..,"t":T_RECEIVED,"text":THE_APPCAST_STRING}, ...]}
 *   A change list holds the trail points added since the sequence number asked for; when the
 *   model has forgotten something the page needs (a slot reused), it answers a snapshot.
 *
 * Core: no allocation, no I/O, no clock reads. Safe on arbitrary mail (fuzzed).
 */
#ifndef KELP_VIEWER_H
#define KELP_VIEWER_H

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

#define KELP_VIEWER_STALE_DEFAULT 60.0  /**< s: pMarineViewer's stale_report_thresh default (older releases: 5) */
#define KELP_VIEWER_REMOVE_DEFAULT 180.0 /**< s: pMarineViewer's stale_remove_thresh default */
#define KELP_VIEWER_STALE_MIN 2.0       /**< s: pMarineViewer clips stale_report_thresh to at least 2 */
#define KELP_VIEWER_TRAIL_DEFAULT 100u  /**< trail points per vehicle unless trails_length says */
#define KELP_VIEWER_LABEL_LEN 64        /**< bytes of a command label, with NUL */

typedef struct kelp_viewer_vehicle {
    kelp_nodereport rep;      /**< the last report (X/Y completed from LAT/LON) */
    double t_rx;              /**< MOOS time it arrived */
    uint32_t seq;             /**< model sequence number of its last change */
    uint32_t nreports;
    bool used, gone, stale;
    /* private: the trail ring */
    uint16_t head, count;
    float trail[KELP_VIEWER_MAX_TRAIL][2];
    uint32_t trail_seq[KELP_VIEWER_MAX_TRAIL];
} kelp_viewer_vehicle;

typedef struct kelp_viewer_artifact {
    kelp_view view;
    double t_rx;
    uint32_t seq;
    bool used, gone;
} kelp_viewer_artifact;

typedef struct kelp_viewer_cast {
    char node[KELP_NODEREPORT_MAX_FIELD];
    char proc[KELP_NODEREPORT_MAX_FIELD];
    char text[KELP_MAX_SVAL];     /**< the APPCAST string as posted */
    double t_rx;
    uint32_t seq;
    bool used;
} kelp_viewer_cast;

typedef struct kelp_viewer_poke {
    char var[KELP_MAX_NAME];
    bool is_string;
    double dval;
    char sval[KELP_VIEWER_MAX_POKE_VAL];
} kelp_viewer_poke;

typedef enum kelp_viewer_cmd_kind { KELP_VIEWER_BUTTON = 0, KELP_VIEWER_ACTION = 1 } kelp_viewer_cmd_kind;

typedef struct kelp_viewer_cmd {
    kelp_viewer_cmd_kind kind;
    unsigned slot;            /**< buttons: 1..20 (button_one = 1); actions: 0 */
    bool separator;           /**< actions: a separator follows (action+) */
    char label[KELP_VIEWER_LABEL_LEN];
    char key[KELP_VIEWER_LABEL_LEN];   /**< actions: menu_key, "" for none */
    char color[KELP_VIEWER_LABEL_LEN]; /**< buttons: color=, "" for none */
    unsigned npokes;
    kelp_viewer_poke pokes[KELP_VIEWER_MAX_POKES];
} kelp_viewer_cmd;

typedef struct kelp_viewer_stats {
    unsigned long reports, reports_bad, views, views_bad, evicted, vehicles_full, casts, casts_bad;
} kelp_viewer_stats;

typedef struct kelp_viewer {
    /* configuration (kelp_viewer_config; defaults from kelp_viewer_init) */
    double stale_report_thresh;   /**< s */
    double stale_remove_thresh;   /**< s, 0 = never */
    unsigned trails_length;       /**< points, 1..KELP_VIEWER_MAX_TRAIL */
    bool have_datum;
    kelp_geo geo;
    char image_url[128];          /**< background image as the page loads it, "" for none */
    double img_n, img_s, img_e, img_w; /**< its lat_north, lat_south, lon_east, lon_west */
    unsigned ncmds;
    kelp_viewer_cmd cmds[KELP_VIEWER_MAX_CMDS];
    kelp_viewer_stats stats;
    /* private */
    uint32_t seq;                 /**< last sequence number given out */
    uint32_t floor;               /**< a page that saw less than this needs a snapshot */
    unsigned nveh;                /**< slots in use or tombstoned (high-water mark) */
    kelp_viewer_vehicle veh[KELP_VIEWER_MAX_VEHICLES];
    kelp_viewer_artifact art[KELP_VIEWER_MAX_ARTIFACTS];
    kelp_viewer_cast casts[KELP_VIEWER_MAX_CASTS];
    /* workspace of one call (keeps the stack under 1 KB) */
    kelp_viewer_cmd ws_cmd;       /**< a button line applied to a copy first */
    kelp_view ws_view;            /**< a VIEW_* posting as parsed */
    kelp_nodereport ws_report;    /**< a NODE_REPORT as parsed */
} kelp_viewer;

/** Empty model with pMarineViewer's defaults. */
void kelp_viewer_init(kelp_viewer *v);

/** The datum (LatOrigin / LongOrigin). @return 0 or KELP_ERR_RANGE. */
KELP_MUST_CHECK int kelp_viewer_set_datum(kelp_viewer *v, double lat0, double lon0);

/** The background image: url as the page fetches it, and its georeference (the .info file's
 *  lat_north, lat_south, lon_east, lon_west). @return 0, KELP_ERR_ARG (bad box), KELP_ERR_RANGE (url too long). */
KELP_MUST_CHECK int kelp_viewer_set_image(kelp_viewer *v, const char *url, double lat_n, double lat_s, double lon_e,
                                          double lon_w);

/** One mission parameter: stale_report_thresh, stale_remove_thresh, trails_length,
 *  button_one..button_twenty (button_1..button_20), action, action+ (case-insensitive keys).
 *  @return 1 taken, 0 not a viewer key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_viewer_config(kelp_viewer *v, const char *key, const char *val, kelp_diag *d);

/** Parse one "VAR=value" poke (trimmed; a number if the value parses as one, a quoted value
 *  stays a string without its quotes). @return 0 or KELP_ERR_PARSE / KELP_ERR_RANGE. */
KELP_MUST_CHECK int kelp_viewer_poke_parse(const char *s, size_t len, kelp_viewer_poke *out);

/** Mail: NODE_REPORT, NODE_REPORT_LOCAL, VIEW_*, APPCAST (other variables are not the viewer's: 0).
 *  @return 1 the model changed, 0 not a viewer variable, <0 the value was refused (counted). */
KELP_MUST_CHECK int kelp_viewer_mail(kelp_viewer *v, const char *var, const char *sval, size_t len, kelp_time now);

/** Time passes: stale flags, stale removal, pulse expiry. @return 1 if anything changed.
 *  The time step rule (docs/ARCHITECTURE.md): after a backward step a vehicle's last report
 *  ages from `now`; a NaN or infinite `now` changes nothing (and kelp_viewer_mail refuses it,
 *  KELP_ERR_ARG). */
int kelp_viewer_tick(kelp_viewer *v, kelp_time now);

/** Current sequence number (0 before any change). */
uint32_t kelp_viewer_seq(const kelp_viewer *v);

/** The JSON of everything ("full":1, with "cfg"). rate: MOOS seconds per wall second the page
 *  should advance its clock by between updates (MOOSTimeWarp live, the replay speed, 0 paused).
 *  @return 0, KELP_ERR_NOSPACE (buf holds a cut, terminated text). len may be NULL. */
KELP_MUST_CHECK int kelp_viewer_json_snapshot(const kelp_viewer *v, kelp_time now, double rate, char *buf, size_t cap,
                                              size_t *len);

/** The JSON of what changed after sequence number since (a snapshot if since is older than
 *  what the model remembers, or 0). @return as kelp_viewer_json_snapshot. */
KELP_MUST_CHECK int kelp_viewer_json_changes(const kelp_viewer *v, uint32_t since, kelp_time now, double rate, char *buf,
                                             size_t cap, size_t *len);

/** The JSON of one vehicle's last report fields, or KELP_ERR_NOTFOUND. */
KELP_MUST_CHECK int kelp_viewer_json_vehicle(const kelp_viewer *v, const char *name, char *buf, size_t cap,
                                             size_t *len);

/** Command i (0..ncmds-1), or NULL. */
const kelp_viewer_cmd *kelp_viewer_cmd_get(const kelp_viewer *v, unsigned i);

/** What pressing command i posts, in order, into out[0..max): its pokes, or for an action with
 *  a menu_key every action poke with that key. @return how many (0 for no such command). */
unsigned kelp_viewer_press(const kelp_viewer *v, unsigned i, const kelp_viewer_poke **out, unsigned max);

/** Forget every vehicle and artifact (replay seeks); keeps configuration and commands. */
void kelp_viewer_clear(kelp_viewer *v);

#ifdef __cplusplus
}
#endif

#endif
