/* kelp usim: uSimMarine's logic (core) around the vehicle simulation of kelp/sim.h and the
 * marine PID of kelp/pid.h: configuration keys, mail, and each iteration's publications. */
#ifndef KELP_USIM_H
#define KELP_USIM_H

#include <stdbool.h>
#include <stddef.h>
#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/geo.h>
#include <kelp/sim.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ the uSimMarine tool */

/** Publication of the tool: a number or a string. */
typedef void (*kelp_usim_sink)(void *ctx, const char *var, bool is_string, const char *sval, double dval);

/** uSimMarine's logic around kelp_sim: configuration keys, mail, and each iteration's
 *  navigation publications (<PREFIX>_X, _Y, _HEADING, _SPEED, _DEPTH, _Z, _YAW (radians,
 *  -heading), _PITCH, _SPEED_OVER_GROUND, _HEADING_OVER_GROUND, _LAT, _LONG with a datum,
 *  TRUE_X, TRUE_Y, SIMULATION_MODE = TRUE (not with DEPTH_CONTROL = false, as uSimMarineV22),
 *  USM_NAVPOS_SUMMARY when asked, USM_DRIFT_SUMMARY on the first iteration and after drift
 *  mail). With any YAW_PID_ key the embedded PID
 *  (kelp_pid_marine) turns DESIRED_HEADING/SPEED/DEPTH into the actuators itself. */
typedef struct kelp_usim {
    kelp_sim sim;
    kelp_sim_params p;
    kelp_sim_state start;
    struct kelp_pid_marine *pid;       /**< caller storage for the embedded PID (may be NULL) */
    struct kelp_pid_marine_cfg *pid_cfg;
    bool embedded_pid, paused, navpos_summary, have_geo;
    bool no_sim_mode;                  /**< DEPTH_CONTROL = false: no SIMULATION_MODE */
    unsigned long iterations;          /**< kelp_usim_iterate calls */
    bool drift_fresh;                  /**< USM_DRIFT_SUMMARY due (start, drift mail) */
    char work[96];                     /**< scratch: USM_DRIFT_SUMMARY */
    kelp_geo geo;
    char prefix[24];
    char post_rudder[KELP_MAX_NAME], post_thrust[KELP_MAX_NAME];
    unsigned long mail[6], bad_mail, resets;
} kelp_usim;

#define KELP_USIM_NAV_MODULO 2        /**< navigation posted every 2nd iteration (uSimMarineV22) */
#define KELP_USIM_NAV_MAX_SPEED 5.0   /**< m/s: NAV_SPEED's cap without MAX_SPEED (uSimMarineV22) */

/** Defaults (prefix NAV); pid/pid_cfg may be NULL (no embedded PID possible). */
void kelp_usim_defaults(kelp_usim *u, struct kelp_pid_marine *pid, struct kelp_pid_marine_cfg *pid_cfg);
/** One block key (the simulator's, the embedded PID's, PREFIX, SIM_PAUSE,
 *  POST_NAVPOS_SUMMARY, POST_DES_RUDDER, POST_DES_THRUST). START_POS should come before
 *  START_X etc. @return 1 taken, 0 not ours, <0 (reason in d). */
KELP_MUST_CHECK int kelp_usim_config(kelp_usim *u, const char *key, const char *val, kelp_diag *d);
/** Start at `now` (geo may be NULL). @return 0 or KELP_ERR_ARG. */
KELP_MUST_CHECK int kelp_usim_start(kelp_usim *u, const kelp_geo *geo, kelp_time now);
/** The variables to register, one per call until NULL. */
const char *kelp_usim_subscription(unsigned i);
/** Mail: DESIRED_*, USM_RESET, USM_SIM_PAUSED, DRIFT_X/Y, ROTATE_SPEED, BUOYANCY_RATE.
 *  @return 1 used, 0 not ours, <0 bad (a warning's worth). */
KELP_MUST_CHECK int kelp_usim_mail(kelp_usim *u, const char *var, bool is_string, const char *sval, double dval, kelp_time now);
/** Step to `now` and publish. @return 0, or <0 when the step failed (resumed from now). */
KELP_MUST_CHECK int kelp_usim_iterate(kelp_usim *u, kelp_time now, kelp_usim_sink sink, void *ctx);

#ifdef __cplusplus
}
#endif

#endif
