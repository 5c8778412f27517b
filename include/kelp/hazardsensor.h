/* kelp uFldHazardSensor: a simulated side-looking sonar hazard detector and classifier for
 * many vehicles over a field of hazard and benign objects (the uField Toolbox
 * manual, MOOS-IvP 12.2, chapter 9, with MOOS-IvP 24.8's additions).
 *
 * Field: objects "x=..,y=..,type=hazard|benign[,label=..,color=..,shape=..,width=..]", from
 * HAZARD lines of the block or a hazard file (lines with or without "hazard =", as gen_hazards
 * writes them; blank and // lines skipped). An object without a label gets its index (0-based).
 *
 * Settings: SENSOR_CONFIG = width=<m>, exp=<e>, pclass=<p>[, max=<n>] (24.8 also "class="),
 * sorted by width. On the ROC curve of a setting P_FA = P_D^exp. max: at most n other vehicles
 * may hold that setting at once (0, the default: no limit).
 *
 * A vehicle's setting: UHZ_CONFIG_REQUEST (or UHZ_SENSOR_CONFIG) "vname=archie,width=32,pd=0.9"
 * picks the setting of that width, else the next lower, else the lowest (among those not at
 * their max); a request without width keeps the width and sets pd, one without pd keeps pd.
 * Without any request, the first sensor request gives the default: the widest setting not
 * wider than (min + max) / 2, pd 0.9. Accepted requests are acknowledged:
 *   UHZ_CONFIG_ACK_<V> = width=30,pd=0.9,pfa=0.28,pclass=0.93
 *   UHZ_CONFIG_ACK     = vname=archie,width=30,pd=0.9,pfa=0.28,pclass=0.93
 * (width, pd, pclass: up to 3 decimals; pfa: 2 fixed). Refused: no name or no node report of
 * the vehicle ('x'), pd outside [0,1] or a bad number ('X'), no settings ('!'), or within
 * MIN_RESET_INTERVAL s of the vehicle's last accepted request.
 *
 * UHZ_SENSOR_REQUEST "vname=archie" (the sensor is on): with the vehicle's last node report,
 * the swath is the rectangle centred on the vehicle, SWATH_LENGTH along its heading and the
 * setting's width across. Each object newly inside it (it was not inside at the vehicle's
 * previous request) is detected with P_D (hazard) or P_FA (benign); a detection is classified
 * correctly with P_C, and posts
 *   UHZ_DETECTION_REPORT_<V> = x=51,y=11.3,label=12        UHZ_DETECTION_REPORT = vname=archie,x=..
 *   UHZ_HAZARD_REPORT_<V>    = x=51,y=11.3,hazard=true,label=12   (the classification)
 *   UHZ_HAZARD_REPORT        = vname=archie,x=51,y=11.3,hazard=true,label=12
 *   VIEW_CIRCLE (yellow: classified hazard, white: benign; duration = SHOW_REPORTS)
 * and the swath as VIEW_POLYGON label=sensor_swath_<v> (SHOW_SWATH). Each detection also earns the vehicle one 24.8
 * UHZ_CLASSIFY_REQUEST "vname=archie,label=12[,priority=50][,action=top|clear]": queued, and one
 * answered per vehicle every MIN_CLASSIFY_INTERVAL s with a fresh classification in 24.8's form
 * UHZ_HAZARD_REPORT_<V> = x=51,y=11.3,type=hazard,label=12 (and UHZ_HAZARD_REPORT with vname).
 *
 * Also: VIEW_MARKER per object at the first iteration (SHOW_HAZARDS) and again on PMV_CONNECT,
 * UHZ_OPTIONS_SUMMARY "width=10,exp=6,pclass=0.93:width=25,..." at the first iteration and
 * every OPTIONS_SUMMARY_INTERVAL s, and the terminal report (Listing 21, or the 12.2 manual's
 * one-character trace when VERBOSE is false).
 *
 * Randomness: a kelp_rng in the state seeded from cfg.seed (the app: a fixed seed unless
 * SEED_RANDOM = true, or RANDOM_SEED = n). Two draws per object entering a swath.
 *
 * Core: no allocation, no I/O, no clock.
 */
#ifndef KELP_HAZARDSENSOR_H
#define KELP_HAZARDSENSOR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/field.h>
#include <kelp/rng.h>

#ifdef __cplusplus
extern "C" {
#endif

#ifndef KELP_UHZ_MAX_OBJECTS
#define KELP_UHZ_MAX_OBJECTS 1024   /**< objects in the hazard field */
#endif
#ifndef KELP_UHZ_MAX_SETTINGS
#define KELP_UHZ_MAX_SETTINGS 16    /**< SENSOR_CONFIG lines */
#endif
#ifndef KELP_UHZ_MAX_NODES
#define KELP_UHZ_MAX_NODES 64       /**< vehicles known */
#endif
#ifndef KELP_UHZ_MAX_QUEUE
#define KELP_UHZ_MAX_QUEUE 16       /**< pending classify requests per vehicle */
#endif
#define KELP_UHZ_MAX_MEMOS 24       /**< distinct memos of the terminal report */
#define KELP_UHZ_MEMO_LEN 96        /**< bytes of a memo, with NUL */
#define KELP_UHZ_TRACE_LEN 256      /**< one-character trace kept between reports */
#define KELP_UHZ_LABEL_LEN 32       /**< bytes of an object label / colour / shape, with NUL */
#define KELP_UHZ_DEFAULT_PD 0.9
#define KELP_UHZ_CIRCLE_RADIUS 10.0 /**< m, VIEW_CIRCLE around a reported object */

typedef struct kelp_uhz_object {
    double x, y;
    bool hazard;                        /**< ground truth */
    double width;                       /**< marker width; < 0: the default of its type */
    char label[KELP_UHZ_LABEL_LEN];
    char color[KELP_UHZ_LABEL_LEN];     /**< "" default */
    char shape[KELP_UHZ_LABEL_LEN];     /**< "" default */
} kelp_uhz_object;

typedef struct kelp_uhz_setting {
    double width, exp, pclass;
    unsigned max;                       /**< vehicles besides the asker allowed on it; 0 no limit */
} kelp_uhz_setting;

typedef struct kelp_field_uhz_cfg {
    char hazard_shape[KELP_UHZ_LABEL_LEN], hazard_color[KELP_UHZ_LABEL_LEN];  /**< triangle, green */
    char benign_shape[KELP_UHZ_LABEL_LEN], benign_color[KELP_UHZ_LABEL_LEN];  /**< triangle, light_blue */
    double hazard_width, benign_width;  /**< 8, 8 */
    double swath_transparency;          /**< 0.25 */
    double swath_length;                /**< 5 m (at least 1) */
    double options_summary_interval;    /**< 10 s */
    double show_reports;                /**< s of a VIEW_CIRCLE; < 0 unlimited (the default); 0 none posted */
    double min_reset_interval;          /**< s between accepted config requests of a vehicle (0) */
    double min_classify_interval;       /**< s between classify answers to a vehicle (30) */
    bool show_hazards, show_swath;      /**< true, true */
    bool show_pd, show_pfa;             /**< 24.8: the swath's msg shows pd/pfa (true, true) */
    bool verbose;                       /**< false: the one-character trace */
    bool seed_random;                   /**< SEED_RANDOM (the app seeds from the clock) */
    uint64_t seed;                      /**< the generator's seed */
    kelp_uhz_setting setting[KELP_UHZ_MAX_SETTINGS];
    unsigned nsettings;
    kelp_uhz_object object[KELP_UHZ_MAX_OBJECTS];
    unsigned nobjects, nhazard, nbenign;
} kelp_field_uhz_cfg;

typedef struct kelp_uhz_entry {
    unsigned obj;                       /**< object index */
    bool said_hazard;                   /**< the classification rolled on request */
    double priority;
} kelp_uhz_entry;

typedef struct kelp_uhz_node {
    char name[KELP_NODEREPORT_MAX_FIELD];   /**< as first received */
    bool have_report, have_setting;
    double x, y, hdg;                   /**< last node report (hdg: degrees, compass) */
    unsigned setting;                   /**< index into cfg.setting */
    double pd, pfa;
    double last_reset;                  /**< time of the last accepted config request; -1 never */
    unsigned long resets, reset_denied, sensor_reqs, detects, classify_reqs, classify_answ;
    unsigned long passes;               /**< classify requests it may still make */
    double last_classify;               /**< time of the last answer (or of the queue's start) */
    kelp_uhz_entry queue[KELP_UHZ_MAX_QUEUE];
    unsigned nqueue;
    uint8_t inside[(KELP_UHZ_MAX_OBJECTS + 7) / 8]; /**< object in the swath at the last request */
} kelp_uhz_node;

typedef struct kelp_uhz_memo {
    char text[KELP_UHZ_MEMO_LEN];
    unsigned long count;
} kelp_uhz_memo;

typedef struct kelp_field_uhz {
    kelp_field_uhz_cfg cfg;             /**< settings sorted by width */
    /* private */
    kelp_uhz_node node[KELP_UHZ_MAX_NODES];
    unsigned nnodes;
    kelp_rng rng;
    bool started;                       /**< markers and first summary posted */
    bool markers_due;
    double last_summary;
    unsigned long iterations, node_reports, bad_mail;
    kelp_uhz_memo memo[KELP_UHZ_MAX_MEMOS];
    unsigned nmemo;
    char trace[KELP_UHZ_TRACE_LEN];     /**< the one-character trace since the last report */
    size_t ntrace;
    char ws[KELP_UHZ_MAX_SETTINGS * 64];   /**< workspace of one call (keeps the stack under 1 KB) */
    kelp_nodereport ws_report;             /**< workspace: the node report being read */
} kelp_field_uhz;

/** Defaults of the uField Toolbox manual (12.2, section 9.1). */
void kelp_field_uhz_cfg_default(kelp_field_uhz_cfg *cfg);
/** One block parameter (key case-insensitive): DEFAULT_{HAZARD,BENIGN}_{SHAPE,COLOR,WIDTH},
 *  SWATH_TRANSPARENCY, SWATH_LENGTH, OPTIONS_SUMMARY_INTERVAL, SHOW_HAZARDS, SHOW_SWATH,
 *  SHOW_REPORTS (24.8: SHOW_DETECTIONS; seconds, or unlimited/nolimit), SHOW_PD, SHOW_PFA,
 *  SEED_RANDOM, RANDOM_SEED, VERBOSE, MIN_RESET_INTERVAL, MIN_CLASSIFY_INTERVAL
 *  (CLASSIFY_PERIOD), SENSOR_CONFIG, HAZARD. Not HAZARD_FILE: the app reads the file and
 *  gives each line to kelp_field_uhz_hazard_line. A value may end in "// comment" or
 *  "(default)". @return 1 taken, 0 not its key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_field_uhz_config(kelp_field_uhz_cfg *cfg, const char *key, const char *val,
                                          kelp_diag *d);
/** One line of a hazard file: "hazard = x=..,y=..,type=.." or "x=..,y=..,type=..".
 *  @return 1 object added, 0 a blank/comment line or another key (skipped), <0 (reason in d)
 *  (missing x, y or type, a bad number, a duplicate label, KELP_ERR_NOSPACE when full). */
KELP_MUST_CHECK int kelp_field_uhz_hazard_line(kelp_field_uhz_cfg *cfg, const char *line, kelp_diag *d);
/** One "width=..,exp=..,pclass=..[,max=..]" setting. @return 0 or <0 (reason in d). */
KELP_MUST_CHECK int kelp_field_uhz_add_setting(kelp_field_uhz_cfg *cfg, const char *spec, kelp_diag *d);
/** Start with cfg (copied; settings sorted by width). @return 0. */
KELP_MUST_CHECK int kelp_field_uhz_init(kelp_field_uhz *h, const kelp_field_uhz_cfg *cfg);
/** The variables to subscribe to, one per call (i from 0) until NULL. */
const char *kelp_field_uhz_subscription(unsigned i);
/** One mail at `now`: NODE_REPORT, NODE_REPORT_LOCAL, UHZ_SENSOR_REQUEST, UHZ_CONFIG_REQUEST,
 *  UHZ_SENSOR_CONFIG, UHZ_CLASSIFY_REQUEST, PMV_CONNECT. @return 1 used, 0 not ours, <0 bad
 *  (a warning through out->warn). */
int kelp_field_uhz_mail(kelp_field_uhz *h, const char *var, const char *sval, kelp_time now, const kelp_field_sink *out);
/** Iterate at `now`: markers and the options summary when due, classify answers. */
void kelp_field_uhz_iterate(kelp_field_uhz *h, kelp_time now, const kelp_field_sink *out);
/** The default setting index (the 12.2 manual's section 9.3), or -1 with no settings. */
int kelp_field_uhz_default_setting(const kelp_field_uhz_cfg *cfg);
/** Index of a vehicle (case-insensitive), or -1. */
int kelp_field_uhz_find(const kelp_field_uhz *h, const char *name);
/** Whether (ox, oy) lies in the swath of a vehicle at (vx, vy) heading hdg degrees. */
bool kelp_field_uhz_in_swath(double vx, double vy, double hdg, double width, double length, double ox, double oy);
/** gen_hazards: whether (x, y) lies in the convex polygon pts[0..n) (either winding; on an
 *  edge counts as inside). */
bool kelp_field_uhz_in_convex(const double (*pts)[2], size_t n, double x, double y);
/** gen_hazards: a point uniformly at random in the convex polygon pts[0..n) (rejection in
 *  its bounding box, at most 100,000 tries). @return 0, KELP_ERR_ARG (fewer than 3 vertices,
 *  or no area), KELP_ERR_INFEASIBLE (no point found). */
KELP_MUST_CHECK int kelp_field_uhz_random_point(const double (*pts)[2], size_t n, kelp_rng *rng, double *x, double *y);
/** The terminal report at `now`: Listing 21 when verbose, else the one-character trace since
 *  the last call (which it clears). @return 0 or KELP_ERR_NOSPACE (truncated). */
KELP_MUST_CHECK int kelp_field_uhz_report(kelp_field_uhz *h, kelp_time now, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
