/* Geodesy: UTM (MOOS-IvP 24.8's default) and MOOS's local grid; see include/kelp/geo.h. */
#include <math.h>
#include <stdbool.h>
#include <kelp/geo.h>

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define RAD2DEG (180.0 / 3.14159265358979323846)

/* UTM as MOOS's geodesy computes it: WGS-84 with MOOS's eccentricity, scale 0.9996, the
 * transverse Mercator by the series of USGS Bulletin 1532 / Snyder (Professional Paper 1395,
 * eqs. 3-21, 8-9, 8-10), no false easting/northing (they cancel in local coordinates) */
#define UTM_A KELP_GEO_WGS84_A
#define UTM_E2 0.00669438
#define UTM_K0 0.9996

static void tm_forward(double lat_deg, double lon_c_deg, double lon_deg, double *east, double *north)
{
    const double e2 = UTM_E2, e4 = e2 * e2, e6 = e4 * e2, ep2 = e2 / (1.0 - e2);
    double phi = lat_deg * DEG2RAD, s = sin(phi), c = cos(phi), t = tan(phi);
    double N = UTM_A / sqrt(1.0 - e2 * s * s);
    double T = t * t, C = ep2 * c * c;
    double A = c * (lon_deg - lon_c_deg) * DEG2RAD;
    double M = UTM_A * ((1 - e2 / 4 - 3 * e4 / 64 - 5 * e6 / 256) * phi -
                        (3 * e2 / 8 + 3 * e4 / 32 + 45 * e6 / 1024) * sin(2 * phi) +
                        (15 * e4 / 256 + 45 * e6 / 1024) * sin(4 * phi) - (35 * e6 / 3072) * sin(6 * phi));
    double A2 = A * A, A3 = A2 * A, A4 = A3 * A, A5 = A4 * A, A6 = A5 * A;
    *east = UTM_K0 * N * (A + (1 - T + C) * A3 / 6 + (5 - 18 * T + T * T + 72 * C - 58 * ep2) * A5 / 120);
    *north = UTM_K0 * (M + N * t * (A2 / 2 + (5 - T + 9 * C + 4 * C * C) * A4 / 24 +
                                    (61 - 58 * T + T * T + 600 * C - 330 * ep2) * A6 / 720));
}

/* the local grid's conversion from the datum (no range check: callers check) */
static void grid_to_latlon(const kelp_geo *g, double x, double y, double *lat, double *lon)
{
    *lat = g->lat0 + asin(y / g->radius) * RAD2DEG;
    *lon = g->lon0 + asin(x / (g->radius * g->coslat0)) * RAD2DEG;
}

static bool grid_in_range(const kelp_geo *g, double x, double y)
{
    double sy = y / g->radius, sx = x / (g->radius * g->coslat0);
    return sy >= -1.0 && sy <= 1.0 && sx >= -1.0 && sx <= 1.0;
}

int kelp_geo_utm_zone(double lat, double lon)
{
    double l = lon - 360.0 * floor((lon + 180.0) / 360.0); /* [-180, 180) */
    int zone = (int)floor((l + 180.0) / 6.0) + 1;
    if (zone > 60) zone = 60;
    if (lat >= 56.0 && lat < 64.0 && l >= 3.0 && l < 12.0) zone = 32;
    if (lat >= 72.0 && lat < 84.0) {
        if (l >= 0.0 && l < 9.0) zone = 31;
        else if (l >= 9.0 && l < 21.0) zone = 33;
        else if (l >= 21.0 && l < 33.0) zone = 35;
        else if (l >= 33.0 && l < 42.0) zone = 37;
    }
    return zone;
}

double kelp_geo_radius(double lat_deg)
{
    const double a = KELP_GEO_WGS84_A, b = KELP_GEO_MOOS_B;
    double t = tan(lat_deg * DEG2RAD);
    double t2 = t * t;
    return b * sqrt(1.0 + t2) / sqrt((b * b) / (a * a) + t2);
}

int kelp_geo_init_grid(kelp_geo *g, double lat_origin, double lon_origin)
{
    if (!g || !isfinite(lat_origin) || !isfinite(lon_origin) || lat_origin <= -90.0 || lat_origin >= 90.0 ||
        lon_origin < -180.0 || lon_origin > 180.0)
        return KELP_ERR_RANGE;
    *g = (kelp_geo){.lat0 = lat_origin, .lon0 = lon_origin};
    g->radius = kelp_geo_radius(lat_origin);
    g->coslat0 = cos(lat_origin * DEG2RAD);
    return KELP_OK;
}

int kelp_geo_init(kelp_geo *g, double lat_origin, double lon_origin)
{
    if (!g || !isfinite(lat_origin) || !isfinite(lon_origin) || lat_origin < -80.0 || lat_origin > 84.0 ||
        lon_origin < -180.0 || lon_origin > 180.0)
        return KELP_ERR_RANGE;
    *g = (kelp_geo){.lat0 = lat_origin, .lon0 = lon_origin};
    g->radius = kelp_geo_radius(lat_origin); /* kept for callers that scale by it */
    g->coslat0 = cos(lat_origin * DEG2RAD);
    g->utm_zone = kelp_geo_utm_zone(lat_origin, lon_origin);
    g->lon_c = -183.0 + 6.0 * g->utm_zone;
    tm_forward(lat_origin, g->lon_c, lon_origin, &g->e0, &g->n0);
    return KELP_OK;
}


int kelp_geo_to_latlon(const kelp_geo *g, double x, double y, double *lat, double *lon)
{
    if (!g || !lat || !lon || !isfinite(x) || !isfinite(y)) return KELP_ERR_RANGE;
    if (g->utm_zone) {
        /* MOOS's inverse: start from the local grid's answer and move the grid point by the UTM
         * residual until the residual is within 1 m, then take the grid's answer once more
         * (so a point is placed within a metre, and MOOS-IvP's printed LAT/LON are
         * reproduced to the last digit). Bounded: 16 steps (it converges in 1-3). */
        double gx = x, gy = y, err = INFINITY;
        for (int i = 0; i < 16 && err > 1.0; i++) {
            if (!grid_in_range(g, gx, gy)) return KELP_ERR_RANGE;
            double la, lo, e, n;
            grid_to_latlon(g, gx, gy, &la, &lo);
            tm_forward(la, g->lon_c, lo, &e, &n);
            double dx = e - g->e0 - x, dy = n - g->n0 - y;
            gx -= dx;
            gy -= dy;
            err = hypot(dx, dy);
            if (!isfinite(err)) return KELP_ERR_RANGE;
        }
        if (err > 1.0 || !grid_in_range(g, gx, gy)) return KELP_ERR_RANGE;
        grid_to_latlon(g, gx, gy, lat, lon);
        return KELP_OK;
    }
    if (!grid_in_range(g, x, y)) return KELP_ERR_RANGE;
    grid_to_latlon(g, x, y, lat, lon);
    return KELP_OK;
}

int kelp_geo_to_local(const kelp_geo *g, double lat, double lon, double *x, double *y)
{
    if (!g || !x || !y || !isfinite(lat) || !isfinite(lon) || lat <= -90.0 || lat >= 90.0 || lon < -360.0 ||
        lon > 360.0)
        return KELP_ERR_RANGE;
    if (g->utm_zone) {
        double e, n;
        tm_forward(lat, g->lon_c, lon, &e, &n);
        *x = e - g->e0;
        *y = n - g->n0;
        return KELP_OK;
    }
    *y = g->radius * sin((lat - g->lat0) * DEG2RAD);
    *x = g->radius * g->coslat0 * sin((lon - g->lon0) * DEG2RAD);
    return KELP_OK;
}
