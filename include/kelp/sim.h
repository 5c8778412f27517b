/* kelp marine vehicle simulator (the uSimMarine role; the tool itself is kelp/usim.h): a
 * deterministic kinematic model.
 *
 * The vehicle follows its desired heading, speed and depth (DESIRED_HEADING/SPEED/DEPTH from
 * the helm) within rate limits:
 *   heading  turns the short way round at up to turn_rate deg/s; below turn_speed m/s that
 *            rate is scaled by speed / turn_speed (a vehicle without way on does not turn,
 *            as a rudder needs flow; so an all-stop's DESIRED_HEADING = 0 does not spin a
 *            stopped vehicle)
 *   speed    rises at up to max_accel m/s^2 and falls at up to max_decel m/s^2
 *   depth    changes at up to max_depth_rate m/s; with max_depth_rate_speed > 0 that limit
 *            is scaled by min(1, speed / max_depth_rate_speed) (a vehicle needs way on to
 *            dive or climb); depth never goes above the surface (0)
 * A limit of 0 means "no limit" (the value jumps to the desired one).
 * Actuated mode (the rudder/thrust model of MOOS-IvP 24.8's uSimMarineV22, used once
 * DESIRED_RUDDER, DESIRED_THRUST or DESIRED_ELEVATOR arrive, or always with control =
 * actuated): ONE step per kelp_sim_step call, h = the whole time since the last (V22
 * propagates once per iteration, and its speed is a mean over the step, so the step is part
 * of the model), in this order
 *   speed    v1 = thrust_map(thrust) * (1 - |rudder|/100 * turn_spd_loss), then the
 *            acceleration limit act_max_accel (default 0 = none) and the deceleration limit
 *            max_decel (0 = none) from the speed v0 before the step. The map interpolates
 *            from (0, 0) to its first point of positive thrust and stays flat after its last;
 *            without a map thrust / thrust_factor; 0 for thrust <= 0 (no reverse).
 *   heading  with v1 != 0: += rudder * (rate/100) * h * (1 + (thrust - 50)/50), rudder
 *            clipped to +-100, where rate (a percent) comes from the turn-speed map at v1: tsm_null_rate up to tsm_null_speed, act_turn_rate (turn_rate clipped
 *            to [0, 100]) from KELP_SIM_TSM_FULL_SPEED (5 m/s) up, linear in between
 *   drift    heading += rotate_speed * h; position += (drift_x, drift_y) * h
 *   depth    v1 <= 0: -= buoyancy_rate * h; else += (-buoyancy_rate + elevator/100 *
 *            max_depth_rate * sqrt(min(1, v1 / max_depth_rate_speed))) * h
 *   position moves at the mean speed (v0 + v1) / 2 along the mean heading, and that mean is
 *            the vehicle's speed after the step (so a step to a new target covers half the
 *            change: the speed approaches its target by halves, step by step)
 * and the pitch is the angle of the last sub-step's climb (radians, nose up positive).
 * Direct mode keeps the drift too. Over-ground speed and heading come from the position's
 * change over the step.
 * Position integrates over each sub-step with the mean heading (of the headings' unit
 * vectors, in the actuated model) and mean speed of the sub-step: x += v sin(h) dt, y += v cos(h) dt (compass heading: 0 = north = +y, 90 = east
 * = +x). Time is an argument: kelp_sim_step(sim, now) advances from the last time to `now`
 * in equal sub-steps of at most `step` seconds, so results do not depend on how often the
 * caller steps beyond that resolution. Core: no heap, no clock, no I/O.
 */
#ifndef KELP_SIM_H
#define KELP_SIM_H

#include <stdbool.h>
#include <stddef.h>
#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/geo.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kelp_sim_params {
    double turn_rate;            /**< deg/s (default 20); 0 = turn at once */
    double turn_speed;           /**< m/s (default 0.5): full turn rate from this speed up; 0 = always */
    double max_accel;            /**< m/s^2 (default 0.5); 0 = no limit */
    double max_decel;            /**< m/s^2 (default 0.5); 0 = no limit */
    double max_depth_rate;       /**< m/s (default 0.5); 0 = no limit */
    double max_depth_rate_speed; /**< m/s (default 0 = depth rate does not depend on speed) */
    double max_speed;            /**< m/s, desired speeds above are clipped (default 0 = none) */
    double step;                 /**< integration sub-step, s (default 0.05) */
    /* actuated mode (MOOS-IvP uSimMarine) */
    int control;                 /**< KELP_SIM_AUTO (default), KELP_SIM_DIRECT, KELP_SIM_ACTUATED */
    double act_turn_rate;        /**< percent [0, 100] (default 70) */
    double thrust_factor;        /**< speed = thrust / thrust_factor without a map (default 20) */
    double turn_spd_loss;        /**< [0, 1] (default 0.85) */
    double act_max_accel;        /**< m/s^2 (default 0 = no limit, as uSimMarineV22) */
    double tsm_null_speed;       /**< turn-speed map: m/s at and below which ... (default 0) */
    double tsm_null_rate;        /**< ... the turn rate is this percent (default 0) */
    double tsm_full_speed;       /**< accepted (default 1); V22 turns at full rate from 5 m/s */
    double tsm_full_rate;        /**< percent (default 100), used only when turn_rate is 0 */
    double buoyancy_rate;        /**< m/s, positive rises (default 0) */
    double map_thrust[KELP_SIM_MAX_MAP], map_speed[KELP_SIM_MAX_MAP];
    unsigned nmap;               /**< thrust_map points, thrust ascending */
    double drift_x, drift_y;     /**< m/s */
    double rotate_speed;         /**< deg/s */
} kelp_sim_params;

enum { KELP_SIM_AUTO = 0, KELP_SIM_DIRECT, KELP_SIM_ACTUATED };

/** m/s from which the actuated model turns at its full rate (uSimMarineV22 fixes it at 5,
 *  whatever turn_spd_map_full_speed says) */
#define KELP_SIM_TSM_FULL_SPEED 5.0

/** Turn rate (percent) of the actuated model at `speed` through the turn-speed map. */
double kelp_sim_turn_rate_at(const kelp_sim_params *p, double speed);

/** Vehicle state. heading in [0, 360). */
typedef struct kelp_sim_state {
    double x, y;                 /**< metres east / north of the datum */
    double heading;              /**< degrees, compass */
    double speed;                /**< m/s, >= 0 */
    double depth;                /**< m, >= 0 */
} kelp_sim_state;

typedef struct kelp_sim {
    kelp_sim_params p;
    kelp_sim_state s;
    double time;                 /**< time of s */
    double des_heading, des_speed, des_depth;
    double odometer;             /**< metres travelled (horizontal) since init */
    bool actuated;               /**< the actuated model is in use */
    double rudder, thrust, elevator; /**< actuator inputs */
    double pitch;                /**< radians, nose up positive */
    double sog, hog;             /**< speed and heading over ground of the last step */
} kelp_sim;

/** Defaults as documented on kelp_sim_params. */
void kelp_sim_params_default(kelp_sim_params *p);

/** Start at `start` at time `now`; the desired values start equal to the start pose (the
 *  vehicle holds its course and speed until told otherwise).
 *  @return 0, KELP_ERR_ARG for a negative/non-finite parameter or state (negative speed or
 *  depth, step <= 0). */
KELP_MUST_CHECK int kelp_sim_init(kelp_sim *sim, const kelp_sim_params *p, const kelp_sim_state *start, kelp_time now);

/** Desired values. Heading is taken modulo 360; speed is clipped to [0, max_speed];
 *  depth to >= 0. @return 0, KELP_ERR_ARG if the value is not finite (ignored). */
KELP_MUST_CHECK int kelp_sim_set_heading(kelp_sim *sim, double deg);
KELP_MUST_CHECK int kelp_sim_set_speed(kelp_sim *sim, double mps);
KELP_MUST_CHECK int kelp_sim_set_depth(kelp_sim *sim, double m);

/** Actuator inputs (rudder and elevator clipped to +-100, thrust to [-100, 100]); in AUTO
 *  control they switch the model to actuated. @return 0, KELP_ERR_ARG if not finite. */
KELP_MUST_CHECK int kelp_sim_set_rudder(kelp_sim *sim, double v);
KELP_MUST_CHECK int kelp_sim_set_thrust(kelp_sim *sim, double v);
KELP_MUST_CHECK int kelp_sim_set_elevator(kelp_sim *sim, double v);
/** thrust_map "0:0, 20:1, 40:2" (thrust:speed pairs, thrust ascending, in [-100, 100]).
 *  @return 0, KELP_ERR_PARSE, KELP_ERR_NOSPACE beyond KELP_SIM_MAX_MAP points. */
KELP_MUST_CHECK int kelp_sim_parse_thrust_map(const char *s, kelp_sim_params *p);
/** Speed for a thrust through the map (or thrust_factor). */
double kelp_sim_thrust_speed(const kelp_sim_params *p, double thrust);

/** One configuration key of the simulator (MOOS-IvP's uSimMarine names, any case):
 *  START_POS, START_X/Y/HEADING/SPEED/DEPTH (into *st when st), TURN_RATE, TURN_SPEED,
 *  MAX_ACCELERATION, MAX_DECELERATION, MAX_DEPTH_RATE, MAX_DEPTH_RATE_SPEED, MAX_SPEED,
 *  SIM_STEP, THRUST_FACTOR, THRUST_MAP, TURN_SPD_LOSS, BUOYANCY_RATE, DRIFT_X, DRIFT_Y,
 *  DRIFT_VECTOR, ROTATE_SPEED, CONTROL, TURN_SPD_MAP_NULL_SPEED/_NULL_RATE/_FULL_SPEED/_FULL_RATE
 *  (MAX_ACCELERATION sets both models' limits). @return 1 taken, 0 not a simulator key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_sim_config_set(kelp_sim_params *p, kelp_sim_state *st, const char *key, const char *val,
                                        kelp_diag *d);

/** Advance to `now`. @return 0; KELP_ERR_RANGE if `now` is before the last step (state
 *  unchanged) or more than KELP_SIM_MAX_SUBSTEPS sub-steps away; KELP_ERR_ARG if not
 *  finite. */
KELP_MUST_CHECK int kelp_sim_step(kelp_sim *sim, kelp_time now);

/** Parse a START_POS value: either "x=.., y=.., heading=.., speed=.., depth=.." (any order,
 *  keys case-insensitive, hdg/deg and spd/dep accepted) or the older positional form
 *  "x,y[,heading[,speed[,depth]]]" (MOOS-IvP uSimMarine order). Fields not given keep the
 *  values already in *st. @return 0, KELP_ERR_PARSE (unknown key, bad number, too many
 *  fields), KELP_ERR_ARG for a negative speed/depth. */
KELP_MUST_CHECK int kelp_sim_parse_start(const char *s, kelp_sim_state *st);

/** Angle helpers: a in [0, 360) and in (-180, 180]. */
double kelp_sim_angle360(double deg);
double kelp_sim_angle180(double deg);
/** Compass bearing from (x0,y0) to (x1,y1) in [0, 360); 0 when the points coincide. */
double kelp_sim_bearing(double x0, double y0, double x1, double y1);

#ifdef __cplusplus
}
#endif

#endif
