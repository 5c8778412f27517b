/* Geodesy: the MOOS local-grid conversion (see include/kelp/geo.h for the formulas). */
#include <math.h>
#include <kelp/geo.h>

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define RAD2DEG (180.0 / 3.14159265358979323846)

double kelp_geo_radius(double lat_deg)
{
    const double a = KELP_GEO_WGS84_A, b = KELP_GEO_MOOS_B;
    double t = tan(lat_deg * DEG2RAD);
    double t2 = t * t;
    return b * sqrt(1.0 + t2) / sqrt((b * b) / (a * a) + t2);
}

int kelp_geo_init(kelp_geo *g, double lat_origin, double lon_origin)
{
    if (!g || !isfinite(lat_origin) || !isfinite(lon_origin) || lat_origin <= -90.0 || lat_origin >= 90.0 ||
        lon_origin < -180.0 || lon_origin > 180.0)
        return KELP_ERR_RANGE;
    g->lat0 = lat_origin;
    g->lon0 = lon_origin;
    g->radius = kelp_geo_radius(lat_origin);
    g->coslat0 = cos(lat_origin * DEG2RAD);
    return KELP_OK;
}

int kelp_geo_to_latlon(const kelp_geo *g, double x, double y, double *lat, double *lon)
{
    if (!g || !lat || !lon || !isfinite(x) || !isfinite(y)) return KELP_ERR_RANGE;
    double sy = y / g->radius;
    double sx = x / (g->radius * g->coslat0);
    if (sy < -1.0 || sy > 1.0 || sx < -1.0 || sx > 1.0) return KELP_ERR_RANGE;
    *lat = g->lat0 + asin(sy) * RAD2DEG;
    *lon = g->lon0 + asin(sx) * RAD2DEG;
    return KELP_OK;
}

int kelp_geo_to_local(const kelp_geo *g, double lat, double lon, double *x, double *y)
{
    if (!g || !x || !y || !isfinite(lat) || !isfinite(lon) || lat <= -90.0 || lat >= 90.0 || lon < -360.0 ||
        lon > 360.0)
        return KELP_ERR_RANGE;
    *y = g->radius * sin((lat - g->lat0) * DEG2RAD);
    *x = g->radius * g->coslat0 * sin((lon - g->lon0) * DEG2RAD);
    return KELP_OK;
}
