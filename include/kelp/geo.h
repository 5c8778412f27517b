/* kelp geodesy: local x/y (metres east/north of a datum) <-> latitude/longitude.
 *
 * The MOOS convention: a community's mission file names its datum with the global parameters
 * LatOrigin and LongOrigin; local x grows east, y grows north, in metres. The conversion is
 * MOOS's "local grid" one (CMOOSGeodesy::LocalGrid2LatLong / LatLong2LocalGrid), good for
 * areas up to a few hundred kilometres:
 *
 *   R(phi) = b * sqrt(1 + tan^2 phi) / sqrt(b^2/a^2 + tan^2 phi),  a = 6378137, b = 6356752
 *   local -> geodetic:  lat = lat0 + deg(asin(y / R(lat0)))
 *                       lon = lon0 + deg(asin(x / (R(lat0) * cos lat0)))
 *   geodetic -> local:  y = R(lat0) * sin(rad(lat - lat0))
 *                       x = R(lat0) * cos lat0 * sin(rad(lon - lon0))
 *
 * The geodetic -> local direction is the exact inverse of the other, so a round trip is the
 * identity. (MOOS's LatLong2LocalGrid uses the radius and cosine at the point's own latitude
 * instead, which is not an exact inverse: about 15 cm apart at 1 km from the datum.)
 * Core: allocation-free, no I/O; angles in degrees.
 */
#ifndef KELP_GEO_H
#define KELP_GEO_H

#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_GEO_WGS84_A 6378137.0   /**< semi-major axis used by MOOS (m) */
#define KELP_GEO_MOOS_B 6356752.0    /**< semi-minor axis used by MOOS (m) */

/** A datum (the MOOS LatOrigin/LongOrigin pair) with its cached radius. */
typedef struct kelp_geo {
    double lat0, lon0;   /**< datum, degrees */
    /* private */
    double radius;       /**< R(lat0), metres */
    double coslat0;
} kelp_geo;

/** Set the datum. @return 0, KELP_ERR_RANGE if lat is not in (-90, 90), lon not in
 *  [-180, 180], or either is not finite. */
KELP_MUST_CHECK int kelp_geo_init(kelp_geo *g, double lat_origin, double lon_origin);

/** Earth radius R(phi) of the MOOS local grid at latitude phi (degrees). */
double kelp_geo_radius(double lat_deg);

/** Local x (east) / y (north) in metres -> latitude/longitude in degrees.
 *  @return 0, KELP_ERR_RANGE when the point is too far from the datum for the model (or
 *  not finite). */
KELP_MUST_CHECK int kelp_geo_to_latlon(const kelp_geo *g, double x, double y, double *lat, double *lon);

/** Latitude/longitude in degrees -> local x/y in metres. @return 0, KELP_ERR_RANGE for a
 *  non-finite or out-of-range latitude/longitude. */
KELP_MUST_CHECK int kelp_geo_to_local(const kelp_geo *g, double lat, double lon, double *x, double *y);

#ifdef __cplusplus
}
#endif

#endif
