/* kelp DCCL: algorithm registry and the algorithms pAcommsHandler 1.1 registers
 * (pAcommsHandler.cpp alg_*), the MOOS geodesy they use (CMOOSGeodesy: WGS-84,
 * Gantz/USGS UTM formulas, PI = 3.14159265) and the modem-id lookup table. */
#include <math.h>
#include <string.h>

#include "dccl_int.h"

/* ------------------------------------------------------------------ registry */
void kelp_dccl_algs_init(kelp_dccl_algs *algs, kelp_dccl_alg_entry *storage, size_t cap)
{
    algs->entries = storage;
    algs->n = 0;
    algs->cap = cap;
}

int kelp_dccl_algs_add(kelp_dccl_algs *algs, const char *name, kelp_dccl_alg_fn fn, void *user)
{
    size_t i;
    if (!algs || !name || !fn) return KELP_ERR_ARG;
    for (i = 0; i < algs->n; i++) {
        if (strcmp(algs->entries[i].name, name) == 0) {
            algs->entries[i].fn = fn;
            algs->entries[i].user = user;
            return KELP_OK;
        }
    }
    if (algs->n >= algs->cap) return KELP_ERR_NOSPACE;
    algs->entries[algs->n].name = name;
    algs->entries[algs->n].fn = fn;
    algs->entries[algs->n].user = user;
    algs->n++;
    return KELP_OK;
}

const kelp_dccl_alg_entry *kelp_dccl_algs_find(const kelp_dccl_algs *algs, const char *name)
{
    size_t i;
    if (!algs || !name) return NULL;
    for (i = 0; i < algs->n; i++)
        if (strcmp(algs->entries[i].name, name) == 0) return &algs->entries[i];
    return NULL;
}

/* ------------------------------------------------------------------ helpers */
static double as_double(const kelp_dccl_val *v)
{
    double d;
    return kelp_dccl_val_to_double(v, &d) ? d : NAN;
}

static void set_dbl(kelp_dccl_val *v, double d)
{
    /* assigning a double to a DCCLMessageVal: MAX_DBL_PRECISION */
    kelp_dccl_val_set_double(v, d, KELP_DCCL_MAX_DBL_PRECISION);
}

/* x86-64 int(double): out of range or NaN gives INT_MIN (cvttsd2si) */
static long x86_int(double d)
{
    if (!(d > -2147483649.0 && d < 2147483648.0)) return (long)(-2147483647 - 1);
    return (long)(int)d;
}

/* s may point into v->s (kelp_dccl_val_set_strn moves with memmove); longer text is cut
 * without the cut flag */
static void set_str_from(kelp_dccl_val *v, const char *s, size_t n)
{
    if (n > KELP_DCCL_MAX_STRLEN) n = KELP_DCCL_MAX_STRLEN;
    kelp_dccl_val_set_strn(v, s, n);
}

/* ------------------------------------------------------------------ simple algorithms */
static void alg_power_to_db(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    set_dbl(v, 10 * log10(as_double(v)));
}

static void alg_db_to_power(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    set_dbl(v, pow(10.0, as_double(v) / 10.0));
}

double kelp_dccl_mackenzie(double t, double s, double d)
{
    /* K.V. Mackenzie (1981), nine-term equation, evaluated left to right */
    return 1448.96 + 4.591 * t - 5.304e-2 * t * t + 2.374e-4 * t * t * t + 1.340 * (s - 35) + 1.630e-2 * d +
           1.675e-7 * d * d - 1.025e-2 * t * (s - 35) - 7.139e-13 * t * d * d * d;
}

static void alg_tsd(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)u;
    kelp_dccl_val_set_double(v, kelp_dccl_mackenzie(as_double(v), nr > 0 ? as_double(r[0]) : NAN,
                                                     nr > 1 ? as_double(r[1]) : NAN), 3);
}

static void alg_add(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    double d = as_double(v);
    size_t i;
    (void)u;
    for (i = 0; i < nr; i++) d += as_double(r[i]);
    kelp_dccl_val_set_double(v, d, v->precision);
}

static void alg_subtract(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    double d = as_double(v);
    size_t i;
    (void)u;
    for (i = 0; i < nr; i++) d -= as_double(r[i]);
    kelp_dccl_val_set_double(v, d, v->precision);
}

static void alg_abs(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    set_dbl(v, fabs(as_double(v)));
}

static void change_case(kelp_dccl_val *v, bool upper)
{
    size_t n, i;
    char *buf = dccl_val_str_inplace(v, &n); /* v is replaced below */
    for (i = 0; i < n; i++) {
        char c = buf[i];
        if (upper && c >= 'a' && c <= 'z') buf[i] = (char)(c - 'a' + 'A');
        if (!upper && c >= 'A' && c <= 'Z') buf[i] = (char)(c - 'A' + 'a');
    }
    kelp_dccl_val_set_strn(v, buf, n);
}

static void alg_to_upper(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    change_case(v, true);
}

static void alg_to_lower(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    change_case(v, false);
}

/* Goby loops `while (a < lo) a += 360; while (a >= hi) a -= 360`. That never
 * ends for infinities or values whose ulp exceeds 360; those are reduced with
 * fmod first (the loop result for any value Goby can finish on is unchanged). */
static double wrap(double a, double lo)
{
    double hi = lo + 360;
    if (isnan(a)) return a;
    if (isinf(a)) return NAN;
    if (fabs(a) > 1e9) a = fmod(a, 360.0);
    while (a < lo) a += 360;
    while (a >= hi) a -= 360;
    return a;
}

static void alg_angle_0_360(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    set_dbl(v, wrap(as_double(v), 0));
}

static void alg_angle_180(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    set_dbl(v, wrap(as_double(v), -180));
}

static void alg_lat_hemi(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    kelp_dccl_val_set_str(v, as_double(v) < 0 ? "S" : "N");
}

static void alg_lon_hemi(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    kelp_dccl_val_set_str(v, as_double(v) < 0 ? "W" : "E");
}

/* printf("%0*d") for the NMEA algorithms */
static size_t put_int(char *out, long v, int width)
{
    char tmp[24];
    size_t n = dccl_fmt_long(v, tmp, sizeof tmp), i = 0, k;
    if (v < 0) {
        out[i++] = '-';
        width--;
        memmove(tmp, tmp + 1, n);
        n--;
    }
    for (k = n; (int)k < width; k++) out[i++] = '0';
    memcpy(out + i, tmp, n);
    return i + n;
}

static void nmea_latlon(kelp_dccl_val *v, int degwidth)
{
    char buf[80];
    size_t n = 0;
    double x = as_double(v);
    long deg = x86_int(floor(x));
    long min = x86_int(floor((x - (double)deg) * 60));
    long tenk = x86_int(floor(((x - (double)deg) * 60 - (double)min) * 10000));
    n += put_int(buf + n, deg, degwidth);
    n += put_int(buf + n, min, 2);
    buf[n++] = '.';
    n += put_int(buf + n, tenk, 4);
    kelp_dccl_val_set_strn(v, buf, n);
}

static void alg_lat2nmea(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    nmea_latlon(v, 2);
}

static void alg_lon2nmea(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    (void)r; (void)nr; (void)u;
    nmea_latlon(v, 3);
}

static void alg_time2nmea(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    /* HHMMSS.ffffff of unix_double2ptime(t).time_of_day() */
    char buf[40];
    size_t n = 0;
    double t = as_double(v), s, tod;
    long us;
    (void)r; (void)nr; (void)u;
    if (isnan(t) || isinf(t)) t = 0;
    s = floor(t);
    us = (long)((t - s) * 1e6);
    tod = fmod(s, 86400.0);
    if (tod < 0) tod += 86400.0;
    n += put_int(buf + n, (long)(tod / 3600), 2);
    n += put_int(buf + n, (long)fmod(tod / 60, 60), 2);
    n += put_int(buf + n, (long)fmod(tod, 60), 2);
    buf[n++] = '.';
    n += put_int(buf + n, us, 6);
    kelp_dccl_val_set_strn(v, buf, n);
}

/* ------------------------------------------------------------------ modem id lookup */
void kelp_dccl_builtin_init(kelp_dccl_builtin *ctx, kelp_dccl_modem_entry *storage, size_t cap)
{
    memset(ctx, 0, sizeof *ctx);
    ctx->modems = storage;
    ctx->cap_modems = cap;
}

static int atoi_c(const char *s, size_t n)
{
    size_t i = 0;
    int neg = 0;
    int64_t v = 0;
    while (i < n && (s[i] == ' ' || (s[i] >= '\t' && s[i] <= '\r'))) i++;
    if (i < n && (s[i] == '+' || s[i] == '-')) neg = s[i++] == '-';
    for (; i < n && s[i] >= '0' && s[i] <= '9'; i++) {
        v = v * 10 + (s[i] - '0');
        if (v > 2147483648LL) v = 2147483648LL;
    }
    v = neg ? -v : v;
    if (v > 2147483647LL) v = 2147483647LL;
    return (int)v;
}

static void copy_field(char *dst, const char *s, size_t n)
{
    if (n >= KELP_DCCL_MAX_MODEM_NAME) n = KELP_DCCL_MAX_MODEM_NAME - 1;
    memcpy(dst, s, n);
    dst[n] = '\0';
}

int kelp_dccl_builtin_parse_modems(kelp_dccl_builtin *ctx, const char *text, size_t len)
{
    size_t p = 0;
    while (p < len) {
        char line[256];
        size_t e = p, n = 0, i, cut;
        const char *parts[4];
        size_t plen[4];
        unsigned np = 0;
        while (e < len && text[e] != '\n') e++;
        for (i = p; i < e && n < sizeof line - 1; i++)
            if (text[i] != ' ') line[n++] = text[i]; /* only spaces are removed */
        line[n] = '\0';
        p = e + 1;
        for (cut = 0; cut < n; cut++) {
            if (line[cut] == '#' || (line[cut] == '/' && cut + 1 < n && line[cut + 1] == '/')) break;
        }
        n = cut;
        if (n == 0) continue;
        parts[0] = line;
        plen[0] = 0;
        for (i = 0; i < n; i++) {
            if (line[i] == ',') {
                if (np < 3) {
                    np++;
                    parts[np] = line + i + 1;
                    plen[np] = 0;
                    continue;
                }
                break;
            }
            plen[np]++;
        }
        if (np < 2) continue; /* "invalid line": fewer than 3 fields */
        {
            int id = atoi_c(parts[0], plen[0]);
            size_t k, at = ctx->n_modems;
            for (k = 0; k < ctx->n_modems; k++) {
                if (ctx->modems[k].id == id) { at = k; break; }
                if (ctx->modems[k].id > id) {
                    if (ctx->n_modems >= ctx->cap_modems) return KELP_ERR_NOSPACE;
                    memmove(&ctx->modems[k + 1], &ctx->modems[k], (ctx->n_modems - k) * sizeof ctx->modems[0]);
                    ctx->n_modems++;
                    at = k;
                    break;
                }
            }
            if (at == ctx->n_modems) {
                if (ctx->n_modems >= ctx->cap_modems) return KELP_ERR_NOSPACE;
                ctx->n_modems++;
            }
            ctx->modems[at].id = id;
            copy_field(ctx->modems[at].name, parts[1], plen[1]);
            copy_field(ctx->modems[at].type, parts[2], plen[2]);
        }
    }
    return KELP_OK;
}

static const kelp_dccl_modem_entry *modem_by_id(const kelp_dccl_builtin *ctx, long id)
{
    size_t i;
    for (i = 0; i < ctx->n_modems; i++)
        if (ctx->modems[i].id == id) return &ctx->modems[i];
    return NULL;
}

/* true and the id if every character is a digit (and it fits lexical_cast<unsigned>) */
static bool digits_id(const kelp_dccl_val *v, long *id)
{
    /* a string is read where it is; another value's text (no leading zeros) has at most 10
     * digits when it is an id, so a short buffer decides it */
    char num[24];
    const char *buf = num;
    size_t n, i;
    unsigned long x = 0;
    if (v->kind == KELP_DCCL_V_STRING) {
        buf = v->s;
        n = v->len;
    } else {
        (void)kelp_dccl_val_to_str(v, num, sizeof num, &n);
        if (n >= sizeof num) return false;
    }
    if (n == 0 || n > KELP_DCCL_MAX_STRLEN) return false;
    for (i = 0; i < n; i++) {
        if (buf[i] < '0' || buf[i] > '9') return false;
        x = x * 10u + (unsigned long)(buf[i] - '0');
        if (x > 4294967295UL) return false;
    }
    *id = (long)(int)(unsigned)x; /* get_name_from_id(int) */
    return true;
}

static void alg_id2name(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    const kelp_dccl_builtin *ctx = u;
    const kelp_dccl_modem_entry *m;
    long id;
    (void)r; (void)nr;
    if (!digits_id(v, &id)) return;
    m = modem_by_id(ctx, id);
    if (m) {
        kelp_dccl_val_set_str(v, m->name);
    } else {
        char buf[24];
        size_t n = dccl_fmt_long(id, buf, sizeof buf);
        set_str_from(v, buf, n);
    }
}

static void alg_id2type(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    const kelp_dccl_builtin *ctx = u;
    const kelp_dccl_modem_entry *m;
    long id;
    (void)r; (void)nr;
    if (!digits_id(v, &id)) return;
    m = modem_by_id(ctx, id);
    kelp_dccl_val_set_str(v, m ? m->type : "unknown_type");
}

static void alg_name2id(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    const kelp_dccl_builtin *ctx = u;
    char out[24];
    size_t n, i, k;
    long id;
    double d;
    (void)r; (void)nr;
    const char *buf = dccl_val_str_inplace(v, &n); /* v is replaced below */
    for (i = 0; i < ctx->n_modems; i++)
        if (dccl_ieq(buf, n, ctx->modems[i].name)) break;
    if (i < ctx->n_modems) {
        id = ctx->modems[i].id;
    } else {
        /* int(as<double>(name)): NaN when not a number */
        id = x86_int(kelp_dccl_parse_double(buf, n, &d) ? d : NAN);
    }
    k = dccl_fmt_long(id, out, sizeof out);
    set_str_from(v, out, k);
}

/* ------------------------------------------------------------------ geodesy (CMOOSGeodesy) */
#define GEO_PI 3.14159265
#define GEO_DEG2RAD (GEO_PI / 180)
#define GEO_RAD2DEG (180.0 / GEO_PI)
#define GEO_A 6378137.0
#define GEO_ECC2 0.00669438

static void ll2utm(double lat, double lon, double *north, double *east)
{
    const double k0 = 0.9996, ecc = GEO_ECC2, a = GEO_A;
    double longtemp = (lon + 180) - (double)(int)((lon + 180) / 360) * 360 - 180;
    double latrad = lat * GEO_DEG2RAD, longrad = longtemp * GEO_DEG2RAD;
    double n, t, c, aa, m, eccp, lonorigin;
    int zone = (int)((longtemp + 180) / 6) + 1;
    if (lat >= 56.0 && lat < 64.0 && longtemp >= 3.0 && longtemp < 12.0) zone = 32;
    if (lat >= 72.0 && lat < 84.0) {
        if (longtemp >= 0.0 && longtemp < 9.0) zone = 31;
        else if (longtemp >= 9.0 && longtemp < 21.0) zone = 33;
        else if (longtemp >= 21.0 && longtemp < 33.0) zone = 35;
        else if (longtemp >= 33.0 && longtemp < 42.0) zone = 37;
    }
    lonorigin = (zone - 1) * 6 - 180 + 3;
    eccp = ecc / (1 - ecc);
    n = a / sqrt(1 - ecc * sin(latrad) * sin(latrad));
    t = tan(latrad) * tan(latrad);
    c = eccp * cos(latrad) * cos(latrad);
    aa = cos(latrad) * (longrad - lonorigin * GEO_DEG2RAD);
    m = a * ((1 - ecc / 4 - 3 * ecc * ecc / 64 - 5 * ecc * ecc * ecc / 256) * latrad -
             (3 * ecc / 8 + 3 * ecc * ecc / 32 + 45 * ecc * ecc * ecc / 1024) * sin(2 * latrad) +
             (15 * ecc * ecc / 256 + 45 * ecc * ecc * ecc / 1024) * sin(4 * latrad) -
             (35 * ecc * ecc * ecc / 3072) * sin(6 * latrad));
    *east = k0 * n * (aa + (1 - t + c) * aa * aa * aa / 6 + (5 - 18 * t + t * t + 72 * c - 58 * eccp) * aa * aa * aa * aa * aa / 120) +
            500000.0;
    *north = k0 * (m + n * tan(latrad) * (aa * aa / 2 + (5 - t + 9 * c + 4 * c * c) * aa * aa * aa * aa / 24 +
                                          (61 - 58 * t + t * t + 600 * c - 330 * eccp) * aa * aa * aa * aa * aa * aa / 720));
    if (lat < 0) *north += 10000000.0;
}

void kelp_dccl_builtin_set_origin(kelp_dccl_builtin *ctx, double lat, double lon)
{
    ctx->have_origin = true;
    ctx->lat_origin = lat;
    ctx->lon_origin = lon;
    ll2utm(lat, lon, &ctx->origin_north, &ctx->origin_east);
    ctx->north = ctx->east = 0;
    ctx->step_after_init = true;
}

void kelp_dccl_geo_latlon2local(kelp_dccl_builtin *ctx, double lat, double lon, double *north, double *east)
{
    double tn, te;
    if (!ctx->have_origin) {
        *north = *east = NAN;
        return;
    }
    ll2utm(lat, lon, &tn, &te);
    if (ctx->step_after_init) {
        ctx->north = tn - ctx->origin_north;
        ctx->east = te - ctx->origin_east;
        ctx->step_after_init = false;
    } else {
        /* MOOS accumulates the increment: (total - previous) + previous */
        double dn = (tn - ctx->origin_north) - ctx->north;
        double de = (te - ctx->origin_east) - ctx->east;
        ctx->north = dn + ctx->north;
        ctx->east = de + ctx->east;
    }
    *north = ctx->north;
    *east = ctx->east;
}

static void grid2ll(const kelp_dccl_builtin *ctx, double east, double north, double *lat, double *lon)
{
    const double a = 6378137, b = 6356752;
    double tanlat2 = pow(tan(ctx->lat_origin * GEO_DEG2RAD), 2);
    double radius = b * sqrt(1 + tanlat2) / sqrt((pow(b, 2) / pow(a, 2)) + tanlat2);
    double yarc = asin(north / radius) * GEO_RAD2DEG;
    double xarc = asin(east / (radius * cos(ctx->lat_origin * GEO_DEG2RAD))) * GEO_RAD2DEG;
    *lat = yarc + ctx->lat_origin;
    *lon = xarc + ctx->lon_origin;
}

void kelp_dccl_geo_local2latlon(kelp_dccl_builtin *ctx, double x, double y, double *lat, double *lon)
{
    /* Henrik Schmidt's iteration to 1 m. Goby would loop forever when it does
     * not converge; we stop after 200 rounds. */
    double err = 1e20, fx = x, fy = y;
    unsigned it = 0;
    if (!ctx->have_origin) {
        *lat = *lon = NAN;
        return;
    }
    while (err > 1.0 && it++ < 200) {
        double la, lo, nx, ny;
        grid2ll(ctx, fx, fy, &la, &lo);
        kelp_dccl_geo_latlon2local(ctx, la, lo, &ny, &nx);
        fx -= nx - x;
        fy -= ny - y;
        err = hypot(nx - x, ny - y);
    }
    grid2ll(ctx, fx, fy, lat, lon);
}

static void alg_lat2utm_y(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    double lat = as_double(v), lon = nr ? as_double(r[0]) : NAN, y = NAN, x = NAN;
    if (!isnan(lat) && !isnan(lon)) kelp_dccl_geo_latlon2local(u, lat, lon, &y, &x);
    set_dbl(v, y);
}

static void alg_lon2utm_x(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    double lon = as_double(v), lat = nr ? as_double(r[0]) : NAN, y = NAN, x = NAN;
    if (!isnan(lat) && !isnan(lon)) kelp_dccl_geo_latlon2local(u, lat, lon, &y, &x);
    set_dbl(v, x);
}

static void alg_utm_x2lon(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    double x = as_double(v), y = nr ? as_double(r[0]) : NAN, lat = NAN, lon = NAN;
    if (!isnan(x) && !isnan(y)) kelp_dccl_geo_local2latlon(u, x, y, &lat, &lon);
    set_dbl(v, lon);
}

static void alg_utm_y2lat(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    double y = as_double(v), x = nr ? as_double(r[0]) : NAN, lat = NAN, lon = NAN;
    if (!isnan(x) && !isnan(y)) kelp_dccl_geo_local2latlon(u, x, y, &lat, &lon);
    set_dbl(v, lat);
}

int kelp_dccl_algs_add_builtin(kelp_dccl_algs *algs, kelp_dccl_builtin *ctx)
{
    static const struct {
        const char *name;
        kelp_dccl_alg_fn fn;
        bool ctx;
    } T[] = {
        {"power_to_dB", alg_power_to_db, false},
        {"dB_to_power", alg_db_to_power, false},
        {"TSD_to_soundspeed", alg_tsd, false},
        {"alg_TSD_to_soundspeed", alg_tsd, false},
        {"add", alg_add, false},
        {"subtract", alg_subtract, false},
        {"abs", alg_abs, false},
        {"to_upper", alg_to_upper, false},
        {"to_lower", alg_to_lower, false},
        {"angle_0_360", alg_angle_0_360, false},
        {"angle_-180_180", alg_angle_180, false},
        {"lat2hemisphere_initial", alg_lat_hemi, false},
        {"lon2hemisphere_initial", alg_lon_hemi, false},
        {"lat2nmea_lat", alg_lat2nmea, false},
        {"lon2nmea_lon", alg_lon2nmea, false},
        {"unix_time2nmea_time", alg_time2nmea, false},
        {"modem_id2name", alg_id2name, true},
        {"modem_id2type", alg_id2type, true},
        {"name2modem_id", alg_name2id, true},
        {"lat2utm_y", alg_lat2utm_y, true},
        {"lon2utm_x", alg_lon2utm_x, true},
        {"utm_x2lon", alg_utm_x2lon, true},
        {"utm_y2lat", alg_utm_y2lat, true},
    };
    size_t i;
    if (!ctx) return KELP_ERR_ARG;
    for (i = 0; i < sizeof T / sizeof T[0]; i++) {
        int rc = kelp_dccl_algs_add(algs, T[i].name, T[i].fn, T[i].ctx ? ctx : NULL);
        if (rc) return rc;
    }
    return KELP_OK;
}
