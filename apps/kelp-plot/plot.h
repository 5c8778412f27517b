/* kelp-plot internals: a scene (vehicle tracks and VIEW_* artifacts gathered from bus
 * writes) and its rendering with cairo. Edge code: allocates, does I/O. */
#ifndef KELP_PLOT_INT_H
#define KELP_PLOT_INT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <kelp/bus.h>
#include <kelp/nodereport.h>

typedef struct plot_pt {
    double t, x, y, hdg, spd;
} plot_pt;

typedef enum plot_src { PLOT_SRC_REPORT = 0, PLOT_SRC_NAV = 1 } plot_src;

typedef struct plot_track {
    char name[KELP_NODEREPORT_MAX_FIELD];   /* vehicle (report NAME, or the community) */
    plot_src src;
    plot_pt *pts;
    size_t n, cap;
    double dist;                            /* metres along the track (after finishing) */
    kelp_nodereport last;                   /* last report (PLOT_SRC_REPORT) */
    unsigned long reports;
    /* NAV_X/NAV_Y pairing */
    double nav_x, nav_hdg, nav_spd;
    bool have_x;
} plot_track;

typedef struct plot_view {
    kelp_view v;
    char community[KELP_MAX_NAME];
    double t_first, t_last;
    unsigned long posts;
} plot_view;

typedef struct plot_scene {
    plot_track *tracks;
    size_t ntracks, tcap;
    plot_view *views;
    size_t nviews, vcap;
    double t0, t1;                          /* MOOS time span of what was seen */
    unsigned long vars, bad_reports, bad_views;
    char last_bad[160];
} plot_scene;

void scene_init(plot_scene *s);
void scene_free(plot_scene *s);
/** Take one bus write into the scene (NODE_REPORT*, NAV_X/NAV_Y/NAV_HEADING/NAV_SPEED,
 *  VIEW_*; anything else is ignored). */
void scene_add_var(plot_scene *s, const kelp_var *v);
/** Sort each track by time, drop duplicates (the same report logged twice), drop NAV
 *  tracks of vehicles that also have reports, compute distances. */
void scene_finish(plot_scene *s);
/** The track of vehicle `name` (case-insensitive), or NULL. */
plot_track *scene_track(plot_scene *s, const char *name);

typedef struct plot_opts {
    int width, height;
    const char *title;
    const char *subtitle;
    bool show_pulses;
} plot_opts;

/** Render to a PNG (path ends .png) or SVG (any other path): 0 or -1 with a message on
 *  stderr. */
int plot_render(const plot_scene *s, const plot_opts *o, const char *path);

/** Free the drawing libraries' caches (call once, at exit). */
void plot_release(void);

/** MOOS colour names ("dark_green", "DodgerBlue", "hex:ff8800", "#ff8800"): 0 and rgb in
 *  [0,1], or -1 when unknown. "invisible"/"off"/"none" give 1 (do not draw). */
int plot_color(const char *name, double rgb[3]);

/** The summary table (per vehicle: distance, duration, points, start/end). */
void plot_print_summary(const plot_scene *s, FILE *out);

#endif
