/* kelp uFldHazardSensor: a simulated side-looking sonar hazard detector and classifier for
 * many vehicles over a field of hazard and benign objects, as MOOS-IvP 24.8's build of the
 * app (its last in-tree version, 2021) behaves.
 *
 * Field: objects "x=..,y=..,type=..,label=..[,hr=..,aspect=..,aspect_min=..,aspect_max=..,
 * color=..,shape=..,width=..]" from HAZARD lines of the block or the "hazard = ..." lines of a
 * hazard file (kelp also takes a file's bare "x=..,y=.." lines, gen_hazards' output, where an
 * object without a label gets its index). x, y, a type and a label are required; a type other
 * than "hazard" is benign. Objects are visited in
 * label order (byte-wise), as 24.8 keeps them.
 *
 * Settings: SENSOR_CONFIG = width=<m>, exp=<e>, class|pclass=<p>[, max=<n>], sorted by width.
 * On the ROC curve of a setting P_FA = P_D^exp. max: at most n other vehicles may hold that
 * width at once (0, the default: no limit). UHZ_OPTIONS_SUMMARY carries the settings as written
 * ("width=..,exp=..,class=..[,max=n]", ':' apart), the last SENSOR_CONFIG line first (24.8
 * reads a block bottom up), at the first iteration and every OPTIONS_SUMMARY_INTERVAL s.
 *
 * A vehicle's setting: UHZ_CONFIG_REQUEST "vname=archie,width=32,pd=0.9" is taken only when
 * vname is the community the mail came from (else a configuration warning "Bad sensor config
 * request from: <v> src: <community>"); pd is required. The setting of the nearest width
 * (first on a tie, among those not at their max) with that pd; a request without width keeps
 * the width and sets pd. A width request within MIN_RESET_INTERVAL s of the vehicle's last
 * accepted one is denied. A vehicle that makes sensor requests without any setting gets the
 * width nearest (min + max) / 2 with pd 0.9. Each setting made is acknowledged:
 *   UHZ_CONFIG_ACK_<V> = vname=archie,width=25,pd=0.9,pfa=0.656,pclass=0.63
 *
 * UHZ_SENSOR_REQUEST "vname=archie" keeps the vehicle's sensor on for 600 s: every iteration,
 * for each such vehicle (by name), PSR = <vname>, the swath polygon (VIEW_POLYGON
 * label=sensor_swath_<v>: SWATH_LENGTH ahead and behind, the setting's width to each side;
 * fill red while the sensor is off: turning faster than MAX_TURN_RATE deg/s over the last 2 s
 * or faster than MAX_VEHICLE_SPEED), and, while on, for each object newly inside it one draw
 * of glibc's rand() % 10000 / 10000 against P_D (hazard) or P_FA (benign; with hr, the mean of
 * P_FA and hr). A detection posts
 *   UHZ_DETECTION_REPORT_<V> = x=51,y=11.3,label=12     UHZ_DETECTION_REPORT = x=..,label=12,vname=archie
 *   VIEW_CIRCLE (white, 12 vertices, duration SHOW_REPORTS)
 * and earns one UHZ_CLASSIFY_REQUEST "vname=archie,label=12[,priority=50][,action=top|clear]":
 * classified on request (rand() % 10001 / 10000 against P_C), queued by priority, one answer
 * per vehicle every MIN_CLASSIFY_INTERVAL s:
 *   UHZ_HAZARD_REPORT_<V> = x=51,y=11.3,label=12,type=hazard   (UHZ_HAZARD_REPORT: vname= first)
 *   VIEW_CIRCLE (red: said hazard, white: benign; 5 vertices)
 *
 * Also: VIEW_MARKER per object at the first iteration (SHOW_HAZARDS) and on PMV_CONNECT; the
 * AppCast report (kelp_hazardsensor_report) with 24.8's tables; events and configuration
 * warnings through kelp_hazardsensor_set_log, run warnings through the sink's warn, each with
 * 24.8's text (a mail 24.8 does not handle also warns "Unhandled mail: <VAR>").
 *
 * Randomness: glibc's rand() sequence (kelp_rng_glibc) seeded with cfg.seed (1 is what a
 * program that never calls srand gets: SEED_RANDOM = false), so a run draws what 24.8 draws.
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
#include <kelp/util.h>
#include <kelp/nodereport.h>

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
#define KELP_UHZ_MAX_NODES 64       /**< vehicles known (node reports or requests) */
#endif
#ifndef KELP_UHZ_MAX_QUEUE
#define KELP_UHZ_MAX_QUEUE 16       /**< pending classify requests per vehicle */
#endif
#define KELP_UHZ_HDG_HIST 32        /**< newest headings kept for the turn rate (2 s of them) */
#define KELP_UHZ_MAX_PASSES 32      /**< headings of detections kept for classify requests */
#define KELP_UHZ_LABEL_LEN 32       /**< bytes of an object label / type / colour / shape, with NUL */
#define KELP_UHZ_SUMMARY_LEN 1024   /**< bytes of UHZ_OPTIONS_SUMMARY, with NUL */
#define KELP_UHZ_MSG_LEN 200        /**< bytes of an event or warning line, with NUL */
#define KELP_UHZ_DEFAULT_PD 0.9
#define KELP_UHZ_CIRCLE_RADIUS 10.0 /**< m, VIEW_CIRCLE around a reported object */
#define KELP_UHZ_REQUEST_LIFE 600.0 /**< s a sensor request keeps the sensor on */
#define KELP_UHZ_TURN_WINDOW 2.0    /**< s of heading history behind the turn rate */

typedef struct kelp_uhz_object {
    double x, y;
    double hr, aspect, aspect_min, aspect_max; /**< each meaningful when its has_ flag is set */
    bool has_hr, has_aspect, has_aspect_min, has_aspect_max;
    double width;                       /**< marker width; < 0: the default of its type */
    char type[KELP_UHZ_LABEL_LEN];      /**< "hazard" or anything else (benign) */
    char label[KELP_UHZ_LABEL_LEN];
    char color[KELP_UHZ_LABEL_LEN];     /**< "" default */
    char shape[KELP_UHZ_LABEL_LEN];     /**< "" default */
} kelp_uhz_object;

typedef struct kelp_uhz_setting {
    double width, exp, pclass;
    unsigned max;                       /**< vehicles besides the asker allowed on it; 0 no limit */
} kelp_uhz_setting;

typedef struct kelp_hazardsensor_cfg {
    char hazard_shape[KELP_UHZ_LABEL_LEN], hazard_color[KELP_UHZ_LABEL_LEN];  /**< triangle, red */
    char benign_shape[KELP_UHZ_LABEL_LEN], benign_color[KELP_UHZ_LABEL_LEN];  /**< triangle, light_blue */
    double hazard_width, benign_width;  /**< 8, 8 */
    double swath_transparency;          /**< 0.2 */
    double swath_length;                /**< 5 m ahead and behind (at least 1) */
    double options_summary_interval;    /**< 10 s (0..120) */
    double show_reports;                /**< s of a VIEW_CIRCLE; -1 unlimited (the default); 0 none posted */
    double min_reset_interval;          /**< s between accepted width requests of a vehicle (300) */
    double min_classify_interval;       /**< s between classify answers to a vehicle (30) */
    double max_turn_rate;               /**< deg/s above which the sensor is off (1.5) */
    double max_vehicle_speed;           /**< m/s above which the sensor is off (2.05) */
    bool show_hazards, show_swath;      /**< true, true */
    bool show_pd, show_pfa;             /**< the swath's msg shows pd/pfa (true, true) */
    bool ignore_resemblances;           /**< false */
    bool seed_random;                   /**< SEED_RANDOM (true; the app then seeds from the clock) */
    uint32_t seed;                      /**< glibc srand seed (1) */
    kelp_uhz_setting setting[KELP_UHZ_MAX_SETTINGS];
    unsigned nsettings;
    char summary[KELP_UHZ_SUMMARY_LEN]; /**< UHZ_OPTIONS_SUMMARY, built as lines arrive */
    kelp_uhz_object object[KELP_UHZ_MAX_OBJECTS];
    unsigned nobjects, nhazard, nbenign;
} kelp_hazardsensor_cfg;

typedef struct kelp_uhz_entry {
    unsigned obj;                       /**< object index */
    bool said_hazard, aspect_affected;  /**< the classification rolled on request */
    double priority;                    /**< as 24.8 orders them (FIFO among equals) */
} kelp_uhz_entry;

typedef struct kelp_uhz_node {
    char name[KELP_NODEREPORT_MAX_FIELD];   /**< exact (24.8 compares names as written) */
    bool have_report, have_setting, have_request, have_queue;
    double x, y, hdg, spd;              /**< last node report (hdg: degrees, compass) */
    double hist_t[KELP_UHZ_HDG_HIST], hist_h[KELP_UHZ_HDG_HIST]; /**< headings, newest at hist_i */
    unsigned hist_i, hist_n;
    double width, exp, pd, pfa, pclass; /**< its setting (have_setting) */
    bool have_reset_time;
    double reset_time, pd_reset_time;   /**< times of the last accepted width / pd request */
    unsigned long reset_tries, resets, pd_resets;
    double last_request;                /**< time of its last sensor request */
    unsigned long sensor_reqs, detects, classify_reqs, classify_answ;
    unsigned long haz_chances, ben_chances, haz_reports, ben_reports;
    unsigned long passes;               /**< classify requests it may still make */
    double pass_hdg[KELP_UHZ_MAX_PASSES]; /**< headings of the oldest pending passes */
    unsigned pass_i;
    double last_classify;               /**< time of the last answer (or of the queue's start) */
    kelp_uhz_entry queue[KELP_UHZ_MAX_QUEUE]; /**< [0] the active entry, the rest by priority */
    unsigned nqueue;
    unsigned long queued_ever;
    uint8_t inside[(KELP_UHZ_MAX_OBJECTS + 7) / 8]; /**< object in the swath at the last look */
} kelp_uhz_node;

/** Events and configuration warnings of 24.8's AppCast (either may be NULL). */
typedef void (*kelp_uhz_log_fn)(void *ctx, const char *msg);

typedef struct kelp_hazardsensor {
    kelp_hazardsensor_cfg cfg;             /**< settings sorted by width, objects by label */
    /* private */
    kelp_uhz_node node[KELP_UHZ_MAX_NODES]; /**< by name */
    unsigned nnodes;
    kelp_rng_glibc rand;
    bool markers_due, summary_posted;
    double last_summary;
    kelp_clock clk;                     /**< the newest `now` (the time step rule) */
    kelp_uhz_log_fn event, cfg_warning;
    void *log_ctx;
    char ws[KELP_UHZ_SUMMARY_LEN];         /**< workspace of one call (keeps the stack under 1 KB) */
    char ws_line[320];                     /**< workspace: a detection or hazard report */
    char ws_var[KELP_MAX_NAME + 24];       /**< workspace: its per-vehicle variable */
    char ws_circle[320];                   /**< workspace: a VIEW_CIRCLE */
    char ws_msg[KELP_UHZ_MSG_LEN];         /**< workspace: an event or warning line */
    char ws_vname[KELP_NODEREPORT_MAX_FIELD]; /**< workspace: a classify request's vehicle */
    char ws_label[KELP_UHZ_LABEL_LEN];     /**< and its object */
    kelp_nodereport ws_report;             /**< workspace: the node report being read */
} kelp_hazardsensor;

/** 24.8's defaults. */
void kelp_hazardsensor_cfg_default(kelp_hazardsensor_cfg *cfg);
/** One block parameter (key case-insensitive): DEFAULT_{HAZARD,BENIGN}_{SHAPE,COLOR,WIDTH},
 *  SWATH_TRANSPARENCY, SWATH_LENGTH, OPTIONS_SUMMARY_INTERVAL, SHOW_HAZARDS, SHOW_SWATH,
 *  SHOW_REPORTS / SHOW_DETECTIONS (seconds, or unlimited/nolimit), SHOW_PD, SHOW_PFA,
 *  SEED_RANDOM, RANDOM_SEED (kelp: the srand seed), MIN_RESET_INTERVAL, MIN_CLASSIFY_INTERVAL
 *  (CLASSIFY_PERIOD), MAX_TURN_RATE, MAX_VEHICLE_SPEED, IGNORE_RESEMBLANCES, RN_ALGORITHM,
 *  RN_UNIFORM_PCT (taken, unused, as in 24.8), SENSOR_CONFIG, HAZARD. Not HAZARD_FILE: the
 *  app reads the file and gives each line to kelp_hazardsensor_hazard_line. A value may end in
 *  "// comment". @return 1 taken, 0 not its key, <0 (24.8's warning text in d). */
KELP_MUST_CHECK int kelp_hazardsensor_config(kelp_hazardsensor_cfg *cfg, const char *key, const char *val,
                                          kelp_diag *d);
/** One line of a hazard file: "hazard = x=..,y=..,type=..,label=.." (or a bare "x=..,..").
 *  @return 1 object added, 0 a blank/comment line or another key (skipped), <0 (reason in d)
 *  (missing x, y, type or label, a duplicate label, KELP_ERR_NOSPACE when full). */
KELP_MUST_CHECK int kelp_hazardsensor_hazard_line(kelp_hazardsensor_cfg *cfg, const char *line, kelp_diag *d);
/** One "width=..,exp=..,class=..[,max=..]" setting. @return 0 or <0 (reason in d). */
KELP_MUST_CHECK int kelp_hazardsensor_add_setting(kelp_hazardsensor_cfg *cfg, const char *spec, kelp_diag *d);
/** Start with cfg (copied; settings sorted by width, objects by label). @return 0. */
KELP_MUST_CHECK int kelp_hazardsensor_init(kelp_hazardsensor *h, const kelp_hazardsensor_cfg *cfg);
/** Where events and configuration warnings go (NULL: dropped). */
void kelp_hazardsensor_set_log(kelp_hazardsensor *h, kelp_uhz_log_fn event, kelp_uhz_log_fn cfg_warning, void *ctx);
/** The variables to subscribe to, one per call (i from 0) until NULL. */
const char *kelp_hazardsensor_subscription(unsigned i);
/** One mail at `now` from `community` (the mail's, "" when unknown): NODE_REPORT,
 *  UHZ_SENSOR_REQUEST, UHZ_CONFIG_REQUEST, UHZ_CLASSIFY_REQUEST, PMV_CONNECT.
 *  @return 1 handled, 0 not ours, <0 not handled (warned "Unhandled mail: <VAR>"). */
int kelp_hazardsensor_mail(kelp_hazardsensor *h, const char *var, const char *sval, const char *community, kelp_time now,
                        const kelp_field_sink *out);
/** Iterate at `now`: markers when due, the options summary, every live sensor request,
 *  classify answers. */
void kelp_hazardsensor_iterate(kelp_hazardsensor *h, kelp_time now, const kelp_field_sink *out);
/** Index of a vehicle (exact name), or -1. */
int kelp_hazardsensor_find(const kelp_hazardsensor *h, const char *name);
/** Whether (ox, oy) lies in the swath of a vehicle at (vx, vy) heading hdg degrees: width m
 *  to each side, length m ahead and behind (edges included). */
bool kelp_hazardsensor_in_swath(double vx, double vy, double hdg, double width, double length, double ox, double oy);
/** gen_hazards: whether (x, y) lies in the convex polygon pts[0..n) (either winding; on an
 *  edge counts as inside). */
bool kelp_hazardsensor_in_convex(const double (*pts)[2], size_t n, double x, double y);
/** gen_hazards: a point uniformly at random in the convex polygon pts[0..n) (rejection in
 *  its bounding box, at most 100,000 tries). @return 0, KELP_ERR_ARG (fewer than 3 vertices,
 *  or no area), KELP_ERR_INFEASIBLE (no point found). */
KELP_MUST_CHECK int kelp_hazardsensor_random_point(const double (*pts)[2], size_t n, kelp_rng *rng, double *x, double *y);
/** 24.8's AppCast report: the hazard file (`file`, NULL: "None provided."), the settings
 *  table, each vehicle's setting and statistics (times relative to `start`).
 *  @return 0 or KELP_ERR_NOSPACE (truncated). */
KELP_MUST_CHECK int kelp_hazardsensor_report(const kelp_hazardsensor *h, const char *file, kelp_time start, char *buf,
                                          size_t cap);

#ifdef __cplusplus
}
#endif

#endif
