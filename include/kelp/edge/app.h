/* kelp app runner (edge): the MOOS application model over the LCM bus.
 *
 * An app is a kelp_app_def: OnStartUp (read the ProcessConfig block, register), OnNewMail
 * (one call per message, just before Iterate, only when mail arrived) and Iterate (at up
 * to AppTick Hz of MOOS time, so MOOSTimeWarp speeds it up). kelp_app_run() handles the
 * MOOS command line (through kelp_cli_next):
 *
 *   app [--alias=NAME] [--verbose] mission.moos [NAME]
 *   app --help | --example | --interface | --version    (-h, -e, -i, -v)
 *
 * (--example and --interface are generated from the def's parameter and variable tables),
 * prints an AppCast-style status report (iteration, mail counts, configuration and run
 * warnings) to stdout, publishes <NAME>_STATUS, and exits cleanly on SIGINT/SIGTERM.
 *
 * Time: MOOS time = epoch + (unix time - epoch) * MOOSTimeWarp, where epoch is
 * $KELP_WARP_EPOCH (optional, inherited by every app a launcher starts) or 0, so by default
 * every process computes the same warped clock without coordination, as MOOS does.
 */
#ifndef KELP_EDGE_APP_H
#define KELP_EDGE_APP_H

#include <stdio.h>
#include <stdbool.h>
#include <kelp/config.h>
#include <kelp/bus.h>
#include <kelp/edge/cli.h>
#include <kelp/mission.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the MOOS application model ---- */
typedef struct kelp_app kelp_app;

/** One parameter of the app's ProcessConfig block (names compare case-insensitively). The
 *  table is what --example prints, and a parameter the app reads that is not in it is
 *  reported as a configuration warning, so the two cannot drift apart. */
typedef struct kelp_app_param_info {
    const char *name;   /**< as written in the block, e.g. "PLATFORM_TYPE" */
    const char *value;  /**< its default, or a sample value when it has none */
    const char *help;   /**< one line: meaning, unit, range; say "required" or "optional" */
    const char *alt;    /**< NULL, or the parameter this one stands in for (an older name, or a
                             choice excluding it): --example shows it commented out */
} kelp_app_param_info;

/** One subscription or publication, for --interface. */
typedef struct kelp_app_var_info {
    const char *name;   /**< the MOOS variable; <PARAM> when a parameter names it */
    const char *sample; /**< a sample value */
    const char *help;   /**< one line, or NULL */
} kelp_app_var_info;

typedef struct kelp_app_def {
    const char *name;        /**< the program's name, e.g. "pXRelay"; also the default MOOS name */
    const char *moos_name;   /**< a different default MOOS name (the role, e.g. "uXMS"), or NULL */
    const char *purpose;     /**< one line for --help and the --interface synopsis */
    const char *synopsis;    /**< a longer --interface synopsis, or NULL for purpose */
    const kelp_app_param_info *params;    /**< every ProcessConfig parameter, NULL-name terminated */
    const kelp_app_var_info *subscribes;  /**< every subscription, NULL-name terminated */
    const kelp_app_var_info *publishes;   /**< every publication, NULL-name terminated */
    const char *notes;       /**< extra --example lines (globals used, repeats), or NULL */
    bool textformat;         /**< a Goby TextFormat block: --example prints "name: value" */
    bool ignore_own_posts;   /**< the app never registers for what it posts: its own datagrams are
                                  dropped in the kernel (a relay app then does not read back its posts) */
    /** The app's own command-line options (added to the MOOS ones), NULL-name terminated, or NULL. */
    const kelp_cli_opt *opts;
    /** What may follow the mission file on the command line ("[VAR ...]"), or NULL for the MOOS
     *  NAME. When set, each such argument goes to on_arg with val 0 (except one starting with the
     *  MOOS name, which is taken as NAME, as uXMS does under pAntler). */
    const char *args;
    /** Called, before startup, for each of the app's options (val, optarg) and arguments (0, arg).
     *  Return <0 with *why for a usage error. */
    int (*on_arg)(void *state, int val, const char *arg, kelp_diag *d);
    /** OnStartUp: read parameters (kelp_app_param*), register. Return <0 to stop the app
     *  (after kelp_app_config_error). */
    int (*startup)(kelp_app *app, void *state);
    /** OnNewMail, one call per message in arrival order. */
    void (*on_mail)(kelp_app *app, void *state, const kelp_var *v);
    /** Iterate. Return <0 to stop the app. */
    int (*iterate)(kelp_app *app, void *state, kelp_time now);
    /** App-specific lines of the status report. */
    void (*report)(kelp_app *app, void *state, FILE *out);
    /** Called once on exit. */
    void (*shutdown)(kelp_app *app, void *state);
    /** The variable the app posts its process id to at start-up, where MOOS-IvP 24.8's app
     *  does (e.g. "PHELMIVP_PID"), or NULL. */
    const char *pid_var;
    /** When set, a parameter nobody read warns as MOOS-IvP 24.8's app does: this prefix, then
     *  "<key>=<value>" (e.g. "Unhandled config line: "), instead of kelp's "unknown parameter". */
    const char *unhandled_prefix;
} kelp_app_def;

/** Run the app; returns the process exit status. */
KELP_MUST_CHECK int kelp_app_run(int argc, char **argv, const kelp_app_def *def, void *state);

/* ---- publish / subscribe (MOOS Notify / Register) ---- */
KELP_MUST_CHECK int kelp_app_notify_double(kelp_app *app, const char *name, double value);
KELP_MUST_CHECK int kelp_app_notify_string(kelp_app *app, const char *name, const char *value);
KELP_MUST_CHECK int kelp_app_notify_stringf(kelp_app *app, const char *name, const char *fmt, ...) KELP_PRINTF(3, 4);
KELP_MUST_CHECK int kelp_app_notify_binary(kelp_app *app, const char *name, const void *data, size_t len);
/** A double (is_string false) or a string with a MOOS source-aux, e.g. the node a relayed
 *  message came from (aux NULL or "" for none). */
KELP_MUST_CHECK int kelp_app_notify_aux(kelp_app *app, const char *name, bool is_string, const char *sval, double dval,
                                        const char *aux);
KELP_MUST_CHECK int kelp_app_register(kelp_app *app, const char *pattern, double min_interval);
/** A raw LCM message (e.g. an lcm-gen'd structure, fingerprint first) on its own channel,
 *  through the app's LCM socket; not a bus variable.  @return 0 or <0. */
KELP_MUST_CHECK int kelp_app_publish_raw(kelp_app *app, const char *channel, const void *data, size_t len);

/* ---- identity and time ---- */
const char *kelp_app_name(const kelp_app *app);      /**< MOOS name (alias) */
const char *kelp_app_community(const kelp_app *app);
double kelp_app_time(const kelp_app *app);           /**< MOOS time now */
double kelp_app_start_time(const kelp_app *app);
double kelp_app_warp(const kelp_app *app);
unsigned long kelp_app_iteration(const kelp_app *app);
/** This process's CPU use, percent of one core, as of the last <APP>_STATUS (cpuload=). */
double kelp_app_cpu_load(const kelp_app *app);
kelp_bus *kelp_app_bus(kelp_app *app);
const char *kelp_app_mission_path(const kelp_app *app);

/* ---- configuration (this app's ProcessConfig block; keys case-insensitive) ---- */
const kelp_mission *kelp_app_mission(const kelp_app *app);
int kelp_app_block(const kelp_app *app);             /**< node index of our block, -1 if none */
/** First parameter `key` in our block (marked as used); NULL if absent. */
const kelp_mission_node *kelp_app_param(kelp_app *app, const char *key);
/** Iterate repeated parameters: pass the previous node (or NULL); marks them used. */
const kelp_mission_node *kelp_app_param_next(kelp_app *app, const char *key, const kelp_mission_node *prev);
/** Typed getters: 1 if found and converted, 0 if absent, <0 (and a config warning) if malformed. */
KELP_MUST_CHECK int kelp_app_param_str(kelp_app *app, const char *key, char *buf, size_t cap);
KELP_MUST_CHECK int kelp_app_param_double(kelp_app *app, const char *key, double *out);
KELP_MUST_CHECK int kelp_app_param_bool(kelp_app *app, const char *key, bool *out);
/** Global (top-of-file) parameter. */
KELP_MUST_CHECK int kelp_app_global_str(kelp_app *app, const char *key, char *buf, size_t cap);
KELP_MUST_CHECK int kelp_app_global_double(kelp_app *app, const char *key, double *out);
/** Call fn for each parameter of our block, in file order: fn returns 1 (taken: marked
 *  used), 0 (not its key) or <0 with *why (a fatal "file:line: KEY = value: why").
 *  @return 0 or the error. */
typedef int (*kelp_app_param_fn)(void *ctx, const char *key, const char *val, kelp_diag *d);
KELP_MUST_CHECK int kelp_app_param_foreach(kelp_app *app, kelp_app_param_fn fn, void *ctx);
/** Mark a node as handled (for parameters read through kelp_mission_* directly). */
void kelp_app_param_used(kelp_app *app, const kelp_mission_node *n);

/* ---- warnings and events, shown in the status report ---- */
void kelp_app_config_warning(kelp_app *app, const char *fmt, ...) KELP_PRINTF(2, 3);
/** A fatal configuration error: printed as "file:line: reason"; the app exits non-zero. */
KELP_MUST_CHECK int kelp_app_config_error(kelp_app *app, const kelp_mission_node *at, const char *fmt, ...) KELP_PRINTF(3, 4);
void kelp_app_run_warning(kelp_app *app, const char *fmt, ...) KELP_PRINTF(2, 3);
void kelp_app_event(kelp_app *app, const char *fmt, ...) KELP_PRINTF(2, 3);
/** The AppCast header as a terminal shows it (MOOS-IvP's AppCasting: a rule, "NAME COMMUNITY"
 *  and "cfg/run(iter)", a rule, then any configuration and run warnings), for an app that
 *  draws its own report under it (kelp-scope). @return its length (cut at cap-1). */
size_t kelp_app_cast_banner(kelp_app *app, char *buf, size_t cap);
/** Watch an extra file descriptor: cb runs (between iterations) when it is readable.
 *  At most 8 per app. */
typedef void (*kelp_app_fd_cb)(kelp_app *app, void *state, int fd);
KELP_MUST_CHECK int kelp_app_watch_fd(kelp_app *app, int fd, kelp_app_fd_cb cb);

/** Ask the loop to end after this iteration. */
void kelp_app_quit(kelp_app *app);

#ifdef __cplusplus
}
#endif

#endif
