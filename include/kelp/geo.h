/* kelp geodesy: local x/y (metres east/north of a datum) <-> latitude/longitude.
 *
 * The MOOS convention: a community's mission file names its datum with the global parameters
 * LatOrigin and LongOrigin; local x grows east, y grows north, in metres.
 *
 * kelp_geo_init selects what MOOS-IvP 24.8 does (built with USE_UTM, its default; the recorded
 * runs of the real apps show MOOS's own geodesy, not PROJ): local x/y are UTM easting/northing
 * minus the datum's, in the datum's zone (6-degree zones with the Norway and Svalbard
 * exceptions), WGS-84, scale 0.9996, by the series of USGS Bulletin 1532 (Snyder). Local ->
 * geodetic is MOOS's: the local grid's answer (below) corrected by the UTM residual until that
 * is within 1 m; so it places a point within a metre (a round trip moves a point up to
 * that much at tens of kilometres, a few millimetres within a kilometre) and reproduces the
 * LAT/LON 24.8 prints to the last of its 8 decimals. A datum must lie in [-80, 84] degrees.
 *
 * kelp_geo_init_grid selects MOOS's older "local grid" (CMOOSGeodesy::LocalGrid2LatLong, used
 * by builds without USE_UTM):
 *
 *   R(phi) = b * sqrt(1 + tan^2 phi) / sqrt(b^2/a^2 + tan^2 phi),  a = 6378137, b = 6356752
 *   local -> geodetic:  lat = lat0 + deg(asin(y / R(lat0)))
 *                       lon = lon0 + deg(asin(x / (R(lat0) * cos lat0)))
 *   geodetic -> local:  y = R(lat0) * sin(rad(lat - lat0))
 *                       x = R(lat0) * cos lat0 * sin(rad(lon - lon0))
 *
 * Here geodetic -> local is the exact inverse of local -> geodetic (MOOS's own LatLong2LocalGrid
 * is not: it takes the radius at the point's latitude). Core: allocation-free, no I/O; angles
 * in degrees.
 */
#ifndef KELP_GEO_H
#define KELP_GEO_H

#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_GEO_WGS84_A 6378137.0   /**< semi-major axis used by MOOS (m) */
#define KELP_GEO_MOOS_B 6356752.0    /**< semi-minor axis used by MOOS (m) */

/** A datum (the MOOS LatOrigin/LongOrigin pair) and its projection's cached constants. */
typedef struct kelp_geo {
    double lat0, lon0;   /**< datum, degrees */
    int utm_zone;        /**< the datum's UTM zone (1..60); 0 for the local grid */
    /* private */
    double radius;       /**< local grid: R(lat0), metres */
    double coslat0;
    double lon_c;        /**< UTM: the zone's central meridian, degrees */
    double e0, n0;       /**< UTM: the datum's easting/northing (no false origin), metres */
} kelp_geo;

/** Set the datum, UTM as MOOS-IvP 24.8 (see above). @return 0, KELP_ERR_RANGE if lat is not in
 *  [-80, 84], lon not in [-180, 180], or either is not finite. */
KELP_MUST_CHECK int kelp_geo_init(kelp_geo *g, double lat_origin, double lon_origin);

/** Set the datum, MOOS's local grid. @return 0, KELP_ERR_RANGE if lat is not in (-90, 90),
 *  lon not in [-180, 180], or either is not finite. */
KELP_MUST_CHECK int kelp_geo_init_grid(kelp_geo *g, double lat_origin, double lon_origin);

/** The UTM zone MOOS uses for a point (6-degree zones, Norway's 32V and Svalbard's 31X-37X). */
int kelp_geo_utm_zone(double lat, double lon);

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
