/* kelp CPA: the closest point of approach of two vessels on straight legs (core: pure
 * arithmetic, no allocation). Positions in local metres, headings in degrees true (0 north,
 * clockwise), speeds in m/s; both vessels hold course and speed from the moment given.
 *
 * Conventions of the evaluation below (kelp_cpa_eval), for every degenerate family:
 *  - Headings outside [0,360) are taken modulo 360 (-90 is 270, 450 is 90).
 *  - A negative speed is taken as 0 (a vessel is not driven astern by a report).
 *  - Non-finite input: KELP_ERR_ARG and a zeroed result.
 *  - No relative motion (both still, or identical velocities): cpa = range, tcpa = 0, roc = 0,
 *    bearing_rate = 0 (crossings and passings: see below).
 *  - Opening: cpa = range, tcpa = 0 (the closest point is now).
 *  - Horizon tol > 0: the CPA is sought in [0, tol]; tol <= 0 means no limit. Crossings and
 *    passings are not limited by the horizon.
 *  - Contact on ownship (range 0): cpa = 0, tcpa = 0, roc = 0, bearing_rate = 0, bearings 0,
 *    fore/aft/port/starboard all false.
 *  - Sides, crossings and passings answer as MOOS-IvP 24.8's CPAEngine (lib_geometry) does, in
 *    every degenerate case (test/cpa_moos248.inc holds 400 of its answers). "A about B" (os_*
 *    is ownship about the contact, cn_* the contact about ownship) is 24.8's engine built on B
 *    with A as ownship, evaluated at A's heading and speed:
 *    - A's side of B from A's bearing relative to B's heading r (exact on the axes): fore
 *      unless 90 < r < 270, aft if 90 <= r <= 270, port if r == 0 or r >= 180, starboard if
 *      r <= 180 (on the bow-stern line both port and starboard, abeam both fore and aft).
 *    - A's heading counts in whole degrees (truncated) for crossings and passings.
 *    - crosses bow / stern: A on B's stern line crosses both; else A must move (speed > 0)
 *      towards B's heading line, and the sign of the bearing rate picks bow or stern (a zero
 *      rate is both). The distance is where A's track meets the line, ahead of (bow) or behind
 *      (stern) B, at A's speed towards the line; A on B's bow (stern) line: the range is the
 *      bow (stern) distance. Flag and distance are separate answers (24.8's two functions):
 *      one may say "no" while the other gives a distance.
 *    - passes port / starboard: A passes if it is abeam of B or on B, or closes B's beam along
 *      B's heading; on B's port (starboard) beam it passes port (starboard) at the range;
 *      otherwise the side is from the sign of the bearing rate (aft of B: positive is port;
 *      fore of B: negative is port), starboard if not port. On B: neither.
 *    - A distance is 0 where the event does not happen.
 *    A negative speed is taken as 0 here too (24.8 takes a negative ownship speed as given).
 *  - roc (rate of closure) = -d(range)/dt now, positive when closing (m/s).
 *  - bearing_rate = d(abs_bearing)/dt now, degrees per second, positive clockwise.
 *  - rel_bearing: bearing of the contact from ownship relative to ownship's heading;
 *    abs_bearing: true bearing of the contact from ownship; cn_rel_bearing: bearing of ownship
 *    from the contact relative to the contact's heading. All in [0,360). */
#ifndef KELP_CPA_H
#define KELP_CPA_H

#include <stdbool.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The CPA range between contact (cnx, cny, cnh, cnv) and ownship (osx, osy, osh, osv)
 *  within tol seconds from now (tol <= 0: no time limit). If the two are opening, or do not
 *  move relative to each other, the CPA is the present range at time 0. *tcpa (if not NULL)
 *  receives the time of the CPA, in [0, tol]. */
double kelp_cpa_range(double cnx, double cny, double cnh, double cnv, double osx, double osy, double osh,
                      double osv, double tol, double *tcpa);

/** One vessel on a straight leg. */
typedef struct kelp_cpa_vessel {
    double x, y, hdg, spd;
} kelp_cpa_vessel;

/** Everything kelp_cpa_eval knows about a contact/ownship pair (see the conventions above). */
typedef struct kelp_cpa_result {
    double cpa, tcpa;                  /**< closest range within the horizon, and when (s) */
    double roc;                        /**< rate of closure, m/s, > 0 closing */
    double range;                      /**< present range */
    double bearing_rate;               /**< deg/s, > 0 clockwise */
    double rel_bearing, abs_bearing;   /**< of the contact from ownship */
    double cn_rel_bearing;             /**< of ownship from the contact, relative to its heading */
    bool cn_fore_of_os, cn_aft_of_os, cn_port_of_os, cn_star_of_os;
    bool os_fore_of_cn, os_aft_of_cn, os_port_of_cn, os_star_of_cn;
    bool os_crosses_cn_bow, os_crosses_cn_stern;
    double os_crosses_cn_bow_dist, os_crosses_cn_stern_dist;   /**< 0 when not crossing */
    bool os_passes_cn_port, os_passes_cn_star;
    double os_passes_cn_port_dist, os_passes_cn_star_dist;     /**< 0 when not passing */
    bool cn_crosses_os_bow, cn_crosses_os_stern;
    double cn_crosses_os_bow_dist, cn_crosses_os_stern_dist;
    bool cn_passes_os_port, cn_passes_os_star;
    double cn_passes_os_port_dist, cn_passes_os_star_dist;
} kelp_cpa_result;

/** Evaluate the pair within horizon tol (<= 0: none). KELP_OK, or KELP_ERR_ARG (non-finite
 *  input or NULL; *out zeroed). */
KELP_MUST_CHECK int kelp_cpa_eval(const kelp_cpa_vessel *cn, const kelp_cpa_vessel *os, double tol,
                                  kelp_cpa_result *out);

/** A contact and ownship's position prepared for many candidate (course, speed) pairs of
 *  ownship, as an objective function over the helm's decision space asks. */
typedef struct kelp_cpa_fast {
    double dx, dy;                     /**< contact minus ownship */
    double cvx, cvy;                   /**< contact velocity */
    double tol;
} kelp_cpa_fast;

/** Prepare (same conventions: headings modulo 360, negative speed 0). KELP_ERR_ARG for
 *  non-finite input. */
KELP_MUST_CHECK int kelp_cpa_fast_init(kelp_cpa_fast *f, const kelp_cpa_vessel *cn, double osx, double osy,
                                       double tol);
/** CPA range if ownship takes course osh at speed osv now (negative osv taken as 0);
 *  *tcpa (if not NULL) gets its time. Equal to kelp_cpa_eval's cpa for the same pair. */
double kelp_cpa_fast_eval(const kelp_cpa_fast *f, double osh, double osv, double *tcpa);
/** The unit heading vector (east, north) of heading h in degrees, as the CPA engine turns a
 *  heading into a velocity (exact at the quadrant headings). */
void kelp_cpa_unit(double hdg, double *ux, double *uy);
/** kelp_cpa_fast_eval with ownship's heading given as its unit vector from kelp_cpa_unit,
 *  without the trigonometry (a caller evaluating many speeds per course takes the unit vectors
 *  once per course): the same closest approach, its length within an ulp of
 *  kelp_cpa_fast_eval's (a square root in place of hypot). */
double kelp_cpa_fast_eval_unit(const kelp_cpa_fast *f, double ux, double uy, double osv, double *tcpa);

#ifdef __cplusplus
}
#endif

#endif
