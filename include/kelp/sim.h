/* kelp marine vehicle simulator (the uSimMarine role): a deterministic kinematic model.
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
 * Position integrates over each sub-step with the mean heading and mean speed of the
 * sub-step: x += v sin(h) dt, y += v cos(h) dt (compass heading: 0 = north = +y, 90 = east
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
} kelp_sim_params;

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
} kelp_sim;

/** Defaults as documented on kelp_sim_params. */
void kelp_sim_params_default(kelp_sim_params *p);

/** Start at `start` at time `now`; the desired values start equal to the start pose (the
 *  vehicle holds its course and speed until told otherwise).
 *  @return 0, KELP_ERR_ARG for a negative/non-finite parameter or state (negative speed or
 *  depth, step <= 0). */
KELP_MUST_CHECK int kelp_sim_init(kelp_sim *sim, const kelp_sim_params *p, const kelp_sim_state *start, double now);

/** Desired values. Heading is taken modulo 360; speed is clipped to [0, max_speed];
 *  depth to >= 0. @return 0, KELP_ERR_ARG if the value is not finite (ignored). */
KELP_MUST_CHECK int kelp_sim_set_heading(kelp_sim *sim, double deg);
KELP_MUST_CHECK int kelp_sim_set_speed(kelp_sim *sim, double mps);
KELP_MUST_CHECK int kelp_sim_set_depth(kelp_sim *sim, double m);

/** Advance to `now`. @return 0; KELP_ERR_RANGE if `now` is before the last step (state
 *  unchanged) or more than KELP_SIM_MAX_SUBSTEPS sub-steps away; KELP_ERR_ARG if not
 *  finite. */
KELP_MUST_CHECK int kelp_sim_step(kelp_sim *sim, double now);

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
