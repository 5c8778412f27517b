/* kelp launch (edge): the pAntler role's pieces. A mission's ProcessConfig = ANTLER block
 * becomes a plan (the apps to start, in order, and the pause between them); each app is a
 * child process "prog MISSION.moos MOOSName" with its output in DIR/<MOOSName>.log. */
#ifndef KELP_EDGE_LAUNCH_H
#define KELP_EDGE_LAUNCH_H

#include <limits.h>
#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>
#include <kelp/config.h>
#include <kelp/mission.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_LAUNCH_MAX_APPS 64

typedef struct kelp_launch_child {
    char prog[128];                 /**< as written in the Run line */
    char alias[KELP_MAX_NAME];      /**< MOOS name (after '~'), else prog */
    char path[PATH_MAX];            /**< the program run (kelp's name for MOOS programs) */
    pid_t pid;                      /**< 0 until started */
    int status;
    bool exited, stopped_by_us;
    double started, ended;
} kelp_launch_child;

typedef struct kelp_launch_plan {
    kelp_launch_child kids[KELP_LAUNCH_MAX_APPS];
    int nkids;
    double ms_between;              /**< MSBetweenLaunches */
    int skipped_moosdb;             /**< Run = MOOSDB lines (kelp has no broker) */
} kelp_launch_plan;

/** kelp's program for a MOOS one (uXMS -> kelp-scope, uPokeDB -> kelp-poke, pMOOSBridge ->
 *  kelp-bridge, pAntler -> kelp-launch, iMarineSim -> uSimMarine, pMarineViewer -> kelp-plot);
 *  others unchanged. */
const char *kelp_launch_map_prog(const char *prog);

/** Read the ANTLER block of m. Programs are looked up in bindir first, then on PATH.
 *  0, or <0 with the reason in d (d->line: the line; the message names the file). */
KELP_MUST_CHECK int kelp_launch_plan_read(kelp_launch_plan *p, const kelp_mission *m, const char *mission_path, const char *bindir,
                          kelp_diag *d);

/** Start one child (fork + exec) with stdout/stderr to logpath. 0, or <0 (errno set). */
KELP_MUST_CHECK int kelp_launch_start(kelp_launch_child *c, const char *mission_path, const char *logpath, double now);

/** Signal every started child that has not exited (marking them stopped by us). */
void kelp_launch_signal_all(kelp_launch_plan *p, int sig);

/** Reap children that exited (never blocks); calls on_exit for each one that ended on its
 *  own. Returns how many started children are still running. */
KELP_MUST_CHECK int kelp_launch_reap(kelp_launch_plan *p, double now, void (*on_exit)(const kelp_launch_child *c, void *ctx),
                     void *ctx);

/** True when a child ended cleanly: exit 0, or killed by the SIGTERM we sent. */
bool kelp_launch_clean(const kelp_launch_child *c);

#ifdef __cplusplus
}
#endif

#endif
