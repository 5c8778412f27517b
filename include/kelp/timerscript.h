/* kelp uTimerScript (core): a script of timed postings, with random times and values,
 * macros, conditions, pause / fast-forward / reset commands and a status variable.
 *
 * A script is a list of events (`event = var=NAME, val=VALUE, time=T` or `time=A:B`, a
 * time drawn uniformly in [A,B] each time the script is scheduled when shuffle is on).
 * Script time is ((now - start) + skipped - paused) * time_warp; an event posts once its
 * time plus the current delay (delay_start on the first pass, delay_reset after a reset)
 * has passed, while the script is not paused, its conditions hold and no block_on app is
 * missing. After every event has posted (reset_time = all-posted) or at script time N
 * (reset_time = N), or on <reset_var> = reset|true, the script starts over, at most
 * reset_max times.
 *
 * Values: "$[DBTIME]", "$[UTCTIME]" (or $[UTC]), "$[COUNT]", "$[TCOUNT]" alone post a number
 * (the time itself, full precision);
 * inside text they expand (times with 2 decimals), as do $[VNAME], $[NAV_X], $[NAV_Y],
 * $[<rand_var>] and $(1)..$(20) (that many random digits); every macro may also be written
 * $(NAME). $[IDX] (the event's index, 3 digits) expands when the event is configured.
 * Then "{a op b}" (op one of * / + -, innermost first) is replaced by its value. A value
 * that is a number and was not written in double quotes posts as a double.
 *
 * Status (<status_var>, default UTS_STATUS; "silent" for none), on an iteration that posts an
 * event, sees the conditions change or makes a reset, and after 5 s without one (a command by
 * mail alone does not bring one, as in MOOS-IvP):
 *   name=unnamed, elapsed_time=2.00, posted=1, pending=4, paused=false, conditions_ok=true,
 *   time_warp=1, delay_start=0, delay_reset=0, shuffle=true, upon_awake=n/a, resets=0/any
 *
 * Allocation-free; randomness from a kelp_rng seeded by the caller; conditions through the
 * helm's evaluator (kelp_helm_cond_*) over an information buffer of the mail received. */
#ifndef KELP_TIMERSCRIPT_H
#define KELP_TIMERSCRIPT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/field.h>
#include <kelp/helm.h>
#include <kelp/rng.h>
#include <kelp/util.h>

#ifdef __cplusplus
extern "C" {
#endif

#ifndef KELP_TS_MAX_EVENTS
#define KELP_TS_MAX_EVENTS 64     /**< events in a script (each amt= copy counts) */
#endif
#ifndef KELP_TS_MAX_VAL
#define KELP_TS_MAX_VAL 256       /**< bytes of an event value, before and after expansion, with NUL */
#endif
#ifndef KELP_TS_MAX_RANDVARS
#define KELP_TS_MAX_RANDVARS 16   /**< rand_var lines */
#endif
#ifndef KELP_TS_MAX_CONDS
#define KELP_TS_MAX_CONDS 8       /**< condition lines */
#endif
#ifndef KELP_TS_MAX_BLOCK
#define KELP_TS_MAX_BLOCK 8       /**< block_on apps */
#endif
#define KELP_TS_MAX_SUBS (8 + KELP_TS_MAX_BLOCK + 16) /**< subscriptions (commands, blocks, condition variables) */
#define KELP_TS_LOG 8             /**< recent postings kept for the status report */
#define KELP_TS_STATUS_PERIOD 5.0 /**< seconds between status posts when nothing changes */
#define KELP_TS_MATH_PASSES 11    /**< {a op b} groups evaluated per posting, at most */

enum { KELP_TS_AWAKE_NA, KELP_TS_AWAKE_RESET, KELP_TS_AWAKE_RESTART };
enum { KELP_TS_RV_AT_START, KELP_TS_RV_AT_RESET, KELP_TS_RV_AT_POST };
enum { KELP_TS_RV_UNIFORM, KELP_TS_RV_GAUSSIAN };

/** A value drawn uniformly in [min, max] each time the script is scheduled. */
typedef struct kelp_timerscript_span {
    double min, max;
} kelp_timerscript_span;

typedef struct kelp_timerscript_event {
    char var[KELP_MAX_NAME];
    char val[KELP_TS_MAX_VAL];
    bool quoted;          /**< the value was in double quotes: always posted as a string */
    bool quit;            /**< a `quit` event: posts EXITED_NORMALLY = <app name>, then the app ends */
    double tmin, tmax;    /**< script seconds */
} kelp_timerscript_event;

typedef struct kelp_timerscript_randvar {
    char name[KELP_MAX_NAME];
    int type;             /**< KELP_TS_RV_UNIFORM or _GAUSSIAN */
    int key;              /**< KELP_TS_RV_AT_START, _AT_RESET or _AT_POST: when a new value is drawn */
    double min, max, mu, sigma, snap;
} kelp_timerscript_randvar;

typedef struct kelp_timerscript_cfg {
    char app_name[KELP_MAX_NAME];   /**< for quit events (EXITED_NORMALLY's value) */
    char community[KELP_MAX_NAME];  /**< $[VNAME] */
    char script_name[KELP_MAX_NAME];
    char var_forward[KELP_MAX_NAME], var_pause[KELP_MAX_NAME], var_reset[KELP_MAX_NAME];
    char var_status[KELP_MAX_NAME], var_next[KELP_MAX_NAME];
    kelp_timerscript_event ev[KELP_TS_MAX_EVENTS];
    unsigned nev;
    kelp_timerscript_randvar rv[KELP_TS_MAX_RANDVARS];
    unsigned nrv;
    char cond[KELP_TS_MAX_CONDS][KELP_HELM_MAX_COND_LEN];
    unsigned ncond;
    char block[KELP_TS_MAX_BLOCK][KELP_MAX_NAME];
    unsigned nblock;
    bool paused, atomic, shuffle, verbose;
    int upon_awake;                 /**< KELP_TS_AWAKE_* */
    bool time_zero_db;              /**< time_zero = db_start */
    long reset_max;                 /**< -1: no limit */
    double reset_time;              /**< -1 none, 0 all-posted, >0 at that script time */
    kelp_timerscript_span warp, delay_start, delay_reset;
} kelp_timerscript_cfg;

/** Defaults: UTS_* variables, script_name unnamed, shuffle on, verbose on, no limit, warp 1. */
void kelp_timerscript_cfg_default(kelp_timerscript_cfg *c, const char *app_name, const char *community);

/** One configuration line. @return 1 taken, 0 not a uTimerScript parameter, <0 (KELP_ERR_PARSE,
 *  KELP_ERR_NOSPACE) with the reason in d when the value is bad. */
KELP_MUST_CHECK int kelp_timerscript_cfg_set(kelp_timerscript_cfg *c, const char *key, const char *val, kelp_diag *d);
/** The event parser alone (`var=..., val=..., time=..., amt=..., quit`): appends amt events. */
KELP_MUST_CHECK int kelp_timerscript_cfg_add_event(kelp_timerscript_cfg *c, const char *spec, kelp_diag *d);
/** The random-variable parser alone (`varname=X, min=0, max=1, key=at_post[, type=gaussian,
 *  mu=.., sigma=..][, snap=..]`). */
KELP_MUST_CHECK int kelp_timerscript_cfg_add_randvar(kelp_timerscript_cfg *c, const char *spec, kelp_diag *d);

typedef struct kelp_timerscript_logline {
    unsigned long total;
    unsigned local;
    double db_time, script_time;
    char text[96];                  /**< "VAR = value" (cut) */
} kelp_timerscript_logline;

typedef struct kelp_timerscript {
    kelp_timerscript_cfg cfg;
    /* read-only for callers */
    double t[KELP_TS_MAX_EVENTS];   /**< each event's time this pass, script seconds */
    bool posted[KELP_TS_MAX_EVENTS];
    double rv_val[KELP_TS_MAX_RANDVARS];
    char rv_text[KELP_TS_MAX_RANDVARS][32];
    double warp, delay_start, delay_reset;  /**< this pass's draws */
    double elapsed;                 /**< script time at the last iteration */
    unsigned posted_local;          /**< this pass */
    unsigned long posted_total;
    unsigned long resets;
    bool paused, conds_ok, blocked_any;
    bool block_seen[KELP_TS_MAX_BLOCK];
    bool quit;                      /**< a quit event posted: the app should end */
    double nav_x, nav_y;
    char sub[KELP_TS_MAX_SUBS][KELP_MAX_NAME];
    unsigned nsub;
    kelp_timerscript_logline log[KELP_TS_LOG];
    unsigned nlog;                  /**< postings logged (ring index nlog % KELP_TS_LOG) */
    unsigned long bad_mail;
    /* private */
    kelp_rng rng;
    kelp_helm_ib ib;
    bool started, drawn, status_due, status_ever;
    double start, prev, skip, pause_time, status_time;
    double db_start;
    bool db_set, db_from_mail;
    kelp_clock clock;               /**< previous `now` of iterate (the time step rule) */
} kelp_timerscript;

/** Take a configuration (copied) and a seed. Draws at_start (and at_reset, at_post) random
 *  variables. @return 0, or KELP_ERR_PARSE when a condition does not parse. */
KELP_MUST_CHECK int kelp_timerscript_init(kelp_timerscript *r, const kelp_timerscript_cfg *c, uint64_t seed);
/** i-th variable to register for (commands, DB_UPTIME, DB_CLIENTS, <APP>_STATUS of block_on
 *  apps, NAV_X/NAV_Y when a value uses them, condition variables), or NULL past the end. */
const char *kelp_timerscript_subscription(const kelp_timerscript *r, unsigned i);
/** When the DB started, MOOS time ($[DBTIME]'s origin and time_zero = db_start's); else the
 *  first iteration's time (or a DB_UPTIME mail) is used. */
void kelp_timerscript_set_db_start(kelp_timerscript *r, double t);
/** One mail. @return 1 used, 0 not for this tool, <0 (and a warning) when bad. */
int kelp_timerscript_mail(kelp_timerscript *r, const char *var, bool is_string, const char *sval, double dval, kelp_time now,
                 const kelp_field_sink *out);
/** One iteration at MOOS time `now`: conditions, schedule, postings, resets, status.
 *  A clock step back, or forward beyond KELP_TIME_STEP_MAX, is not script time (the time step
 *  rule, docs/ARCHITECTURE.md).  @return the number of events posted, or KELP_ERR_ARG for a NaN,
 *  infinite or absurd `now` (nothing done). */
int kelp_timerscript_iterate(kelp_timerscript *r, kelp_time now, const kelp_field_sink *out);
/** Expand the macros and {a op b} groups of `val` as a posting would (the event machinery's
 *  text step, also the fuzz entry): @return 1 when the result is a lone number (*dval set),
 *  0 for text, KELP_ERR_NOSPACE when it does not fit. */
KELP_MUST_CHECK int kelp_timerscript_expand(kelp_timerscript *r, const char *val, kelp_time now, char *out, size_t cap, double *dval);
/** The status string. @return its length or KELP_ERR_NOSPACE. */
int kelp_timerscript_status(const kelp_timerscript *r, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
