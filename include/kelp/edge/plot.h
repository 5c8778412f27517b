/* kelp plot (edge, libkelp_plot): a scene (vehicle tracks and VIEW_* artifacts gathered from bus
 * writes) and its rendering with cairo. Edge code: allocates, does I/O. */
#ifndef KELP_EDGE_PLOT_H
#define KELP_EDGE_PLOT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <kelp/bus.h>
#include <kelp/nodereport.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kelp_plot_pt {
    double t, x, y, hdg, spd;
} kelp_plot_pt;

typedef enum kelp_plot_src { KELP_PLOT_SRC_REPORT = 0, KELP_PLOT_SRC_NAV = 1 } kelp_plot_src;

typedef struct kelp_plot_track {
    char name[KELP_NODEREPORT_MAX_FIELD];   /* vehicle (report NAME, or the community) */
    kelp_plot_src src;
    kelp_plot_pt *pts;
    size_t n, cap;
    double dist;                            /* metres along the track (after finishing) */
    kelp_nodereport last;                   /* last report (KELP_PLOT_SRC_REPORT) */
    unsigned long reports;
    /* NAV_X/NAV_Y pairing */
    double nav_x, nav_hdg, nav_spd;
    bool have_x;
} kelp_plot_track;

typedef struct kelp_plot_view {
    kelp_view v;
    char community[KELP_MAX_NAME];
    double t_first, t_last;
    unsigned long posts;
} kelp_plot_view;

typedef struct kelp_plot_scene {
    kelp_plot_track *tracks;
    size_t ntracks, tcap;
    kelp_plot_view *views;
    size_t nviews, vcap;
    double t0, t1;                          /* MOOS time span of what was seen */
    unsigned long vars, bad_reports, bad_views;
    char last_bad[160];
} kelp_plot_scene;

void kelp_plot_scene_init(kelp_plot_scene *s);
void kelp_plot_scene_free(kelp_plot_scene *s);
/** Take one bus write into the scene (NODE_REPORT*, NAV_X/NAV_Y/NAV_HEADING/NAV_SPEED,
 *  VIEW_*; anything else is ignored). */
void kelp_plot_scene_add_var(kelp_plot_scene *s, const kelp_var *v);
/** Sort each track by time, drop duplicates (the same report logged twice), drop NAV
 *  tracks of vehicles that also have reports, compute distances. */
void kelp_plot_scene_finish(kelp_plot_scene *s);
/** Add every kelp.var_t event of an LCM log (lcm-logger's format) to the scene; events that
 *  do not decode are counted in *undecoded. 0, or -1 with a message on stderr (unreadable,
 *  not a log, no events). */
KELP_MUST_CHECK int kelp_plot_scene_read_log(kelp_plot_scene *s, const char *path, unsigned long *events, unsigned long *undecoded);
/** The track of vehicle `name` (case-insensitive), or NULL. */
kelp_plot_track *kelp_plot_scene_track(kelp_plot_scene *s, const char *name);

/** The closest approach of two tracks: when (MOOS time), how close, and where each was. */
typedef struct kelp_plot_cpa {
    double t, d;
    double ax, ay, bx, by;
} kelp_plot_cpa;

/** The closest approach of tracks a and b over the time both are known, positions linear
 *  between fixes (exact on each stretch where both move linearly). 0, or -1 when the two
 *  tracks do not overlap in time. */
KELP_MUST_CHECK int kelp_plot_closest(const kelp_plot_track *a, const kelp_plot_track *b, kelp_plot_cpa *out);

typedef struct kelp_plot_opts {
    int width, height;
    const char *title;
    const char *subtitle;
    bool show_pulses;
    bool show_closest;   /**< mark every pair's closest approach (line, distance, time) */
} kelp_plot_opts;

/** Render to a PNG (path ends .png) or SVG (any other path): 0 or -1 with a message on
 *  stderr. */
KELP_MUST_CHECK int kelp_plot_render(const kelp_plot_scene *s, const kelp_plot_opts *o, const char *path);

/** Free the drawing libraries' caches (call once, at exit). */
void kelp_plot_release(void);

/** MOOS colour names ("dark_green", "DodgerBlue", "hex:ff8800", "#ff8800"): 0 and rgb in
 *  [0,1], or -1 when unknown. "invisible"/"off"/"none" give 1 (do not draw). */
KELP_MUST_CHECK int kelp_plot_color(const char *name, double rgb[3]);

/** The summary table (per vehicle: distance, duration, points, start/end). */
void kelp_plot_print_summary(const kelp_plot_scene *s, FILE *out);
/** One line per pair of tracks: "closest NAME NAME D m at T s (x,y) (x,y)". */
void kelp_plot_print_closest(const kelp_plot_scene *s, FILE *out);

#ifdef __cplusplus
}
#endif

#endif
