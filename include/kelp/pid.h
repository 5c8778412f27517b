/* kelp marine PID controller (the pMarinePID role): desired heading, speed and depth in,
 * rudder, thrust and elevator out, through MOOS-IvP's scalar PID loops.
 *
 * One loop (kelp_pid) follows MOOS-IvP's ScalarPID: the first run has no derivative and
 * no integral step; later runs take dt from the previous run (dt == 0 repeats the last
 * output); the derivative is the mean of the last 9 error slopes; with ki > 0 the integral
 * grows by ki * e * dt and is clipped to +-integral_limit (ki <= 0 clears it); the output
 * kp*e + kd*de/dt + integral is clipped to +-output_limit, which sets `saturated`.
 *
 * The engine (kelp_pid_marine) runs pMarinePID's iteration: without control (before
 * MOOS_MANUAL_OVERRIDE=false, unless active_start) it posts one all-stop (rudder, thrust
 * and, with depth control, elevator 0); in control it posts rudder, thrust (and elevator)
 * every iteration, as pMarinePIDV22: all 0 until every input (desired heading and speed, nav
 * heading and speed; with depth control desired depth, nav depth and pitch) has come since
 * control was taken, and all 0 with one PID_STALE ("Stale DesHdg:2.5", DesSpd, NavHdg,
 * NavSpd, DesDepth, NavDep, NavPitch) per input older than its tardy threshold; otherwise
 *   thrust   = desired speed * speed_factor, or (speed_factor 0) last thrust +
 *              PID_speed(desired - speed); below 0.01 it is 0; clipped to maxthrust
 *   rudder   = -PID_yaw(angle180(heading - desired)), clipped to maxrudder, only with
 *              thrust > 0 (else 0 and the loop does not run: its next run is a first run)
 *   elevator = degrees(PID_pitch(pitch - clip(PID_z(depth - desired), maxpitch))),
 *              clipped to maxelevator (depth control and thrust > 0 only)
 * PID_HAS_CONTROL = true on each MOOS_MANUAL_OVERRIDE = false, false when control is lost.
 * Every loop's output limit is 100; maxrudder etc. clip after. Outputs go to
 * DESIRED_RUDDER/THRUST/ELEVATOR + output_suffix. With heading_debug / speed_debug /
 * depth_debug = true, as pMarinePIDV22, each control iteration also posts PID_SPD_DEBUG,
 * PID_HDG_DEBUG, PID_DEP_DEBUG, and PID_MAX_SAT_<HDG|SPD|DEP>_DEBUG (the loop's steps, ScalarPID's
 * debug text) when a loop saturated; without them nothing (24.8 never posts PID_MAX_SAT_HDG).
 * Core: no heap, no clock, no I/O.
 */
#ifndef KELP_PID_H
#define KELP_PID_H

#include <stdbool.h>
#include <stddef.h>
#include <kelp/config.h>
#include <kelp/util.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_PID_HISTORY 9 /**< error slopes averaged for the derivative */
#define KELP_PID_NSTAMP 7  /**< inputs timed: desired heading/speed/depth, nav heading/speed/depth/pitch */
#define KELP_PID_DEBUG_MAX 400 /**< a PID_*_DEBUG text */
#define KELP_PID_MIN_THRUST 0.01 /**< a thrust below this is 0 (PIDEngine::setDesiredThrust) */

typedef struct kelp_pid {
    double kp, kd, ki, integral_limit, output_limit;
    /* state */
    double e_old, t_old, out, sum, dt;
    double hist[KELP_PID_HISTORY];
    unsigned nhist, head;
    unsigned long runs;
    bool saturated;
    /* the last run's steps, for kelp_pid_debug_text: its input and time, the time step and
     * the derivative's slope, sum and mean, the integral before and after its limit, the
     * output before its limit; stage: 0 first run, 1 stopped at a zero dt, 2 a full run */
    struct {
        double e, t, dt, slope, dsum, dmean, sum1, out1;
        unsigned nhist;
        unsigned char stage;
        bool sum_clipped;
    } last;
} kelp_pid;

/** Gains and limits; clears the state. */
void kelp_pid_init(kelp_pid *p, double kp, double kd, double ki, double integral_limit, double output_limit);
/** One run with error e at time t. @return 0 and *out; KELP_ERR_RANGE when t goes back
 *  (nothing changes). */
KELP_MUST_CHECK int kelp_pid_run(kelp_pid *p, double e, double t, double *out);
/** The last run's steps as ScalarPID's debug text ("dfeIn=.., dfErrorTime=.., m_dfDT=..,
 *  dfDiffNow=.., DiffHistSize=.., mdfeDiff(1)=.., mdfeDiff(2)=.., m_dfOut(1).."), 5 decimals.
 *  @return its length (as snprintf). */
int kelp_pid_debug_text(const kelp_pid *p, char *buf, size_t cap);

typedef struct kelp_pid_marine_cfg {
    double yaw[4], speed[4], z_to_pitch[4], pitch[4]; /**< kp, kd, ki, integral limit */
    double max_rudder, max_thrust, max_pitch_deg, max_elevator;
    double speed_factor;           /**< 0: the speed PID sets thrust */
    bool depth_control;
    bool active_start;             /**< in control from the start */
    double tardy_helm, tardy_nav;  /**< seconds (2, 2) */
    double sim_instability;        /**< rudder bias amplitude, alternating every 10 s */
    char suffix[16];               /**< output_suffix */
    bool ignore_nav_yaw;
    bool debug[3];                 /**< heading_debug, speed_debug, depth_debug */
} kelp_pid_marine_cfg;

/** Publication: one variable, a number or (flags/debug) a string. */
typedef void (*kelp_pid_marine_sink)(void *ctx, const char *var, bool is_string, const char *sval, double dval);

typedef struct kelp_pid_marine {
    kelp_pid_marine_cfg cfg;
    kelp_pid yaw, speed, z_to_pitch, pitch;
    bool has_control, allstop_posted, paused;
    double des_heading, des_speed, des_depth;
    double heading, speed_now, depth, pitch_now;
    double last_helm, last_nav;    /**< -1: never */
    double thrust;                 /**< last thrust posted (the speed PID's base) */
    double bias_t0;
    int bias_side;
    double rudder_out, thrust_out, elevator_out;
    unsigned long iterations, tardy_helm_n, tardy_nav_n;
    kelp_clock clock;              /**< previous `now` of iterate (the time step rule) */
    double stamp[KELP_PID_NSTAMP]; /**< when each input last came; -1: not since control */
    int say_control;               /**< PID_HAS_CONTROL due: 1 true, -1 false, 0 none */
    char work[48];                 /**< scratch: a PID_STALE text */
    char dbg[KELP_PID_DEBUG_MAX];  /**< scratch: a *_DEBUG text */
} kelp_pid_marine;

/** pMarinePID's defaults: gains 0, limits 100, maxpitch 15 deg, maxelevator 13 deg,
 *  speed_factor 0 (the speed PID), tardy thresholds 2 s, no depth control, not active. */
void kelp_pid_marine_cfg_default(kelp_pid_marine_cfg *c);
/** One configuration key (MOOS-IvP's names, any case): YAW_PID_, SPEED_PID_, Z_TO_PITCH_PID_,
 *  PITCH_PID_ + KP/KD/KI/INTEGRAL_LIMIT/KI_LIMIT, MAXRUDDER, MAXTHRUST, MAXPITCH,
 *  MAXELEVATOR, SPEED_FACTOR, TARDY_HELM_THRESHOLD, TARDY_NAV_THRESHOLD, SIM_INSTABILITY,
 *  DEPTH_CONTROL, ACTIVE_START, IGNORE_NAV_YAW, OUTPUT_SUFFIX, HEADING_DEBUG, SPEED_DEBUG,
 *  DEPTH_DEBUG (as 24.8: "true" in any case turns it on, any other value is taken and ignored).
 *  @return 1 taken, 0 not a PID key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_pid_marine_cfg_set(kelp_pid_marine_cfg *c, const char *key, const char *val, kelp_diag *d);
/** @return 0, KELP_ERR_ARG for a negative or non-finite limit or threshold. */
KELP_MUST_CHECK int kelp_pid_marine_init(kelp_pid_marine *m, const kelp_pid_marine_cfg *cfg, kelp_time now);
/** Mail: DESIRED_HEADING/SPEED/DEPTH, NAV_HEADING/YAW/SPEED/DEPTH/PITCH, SPEED_FACTOR,
 *  MOOS_MANUAL_OVERRIDE (and OVERIDE) "true"/"false". @return 1 used, 0 not ours, <0 bad. */
KELP_MUST_CHECK int kelp_pid_marine_mail(kelp_pid_marine *m, const char *var, bool is_string, const char *sval, double dval,
                                         kelp_time now);
/** One iteration at `now`, publishing through sink. */
void kelp_pid_marine_iterate(kelp_pid_marine *m, kelp_time now, kelp_pid_marine_sink sink, void *ctx);

#ifdef __cplusplus
}
#endif

#endif
