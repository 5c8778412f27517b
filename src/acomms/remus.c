/* REMUS CCL messages (see include/kelp/remus.h for the layouts and where the facts came from).
 *
 * The arithmetic mirrors the WHOI helpers' order of operations and float/double mix (Goby 1.x
 * src/moos/pREMUSCodec/WhoiUtil.cpp) so codes and decoded values agree exactly; every input
 * that is undefined behaviour there (NaN, out-of-range casts) has a defined result here. */
#include <kelp/remus.h>

#include <math.h>

#include <kelp/util.h>

#define LATLON_FULL 8388607.0 /* 0x7FFFFF: +180 degrees */

kelp_remus_kind kelp_remus_identify(const uint8_t *frame, size_t len)
{
    if (!frame || len == 0) return KELP_REMUS_UNKNOWN;
    switch (frame[0]) {
    case KELP_REMUS_ID_REDIRECT: return KELP_REMUS_REDIRECT;
    case KELP_REMUS_ID_POSITION: return KELP_REMUS_POSITION;
    case KELP_REMUS_ID_STATE: return KELP_REMUS_STATE;
    case KELP_REMUS_ID_RANGER: return KELP_REMUS_RANGER;
    case KELP_REMUS_ID_OASIS: return KELP_REMUS_OASIS;
    default: return KELP_REMUS_UNKNOWN;
    }
}

/* ---------------------------------------------------------------- byte packing */

static void put24(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)((v >> 8) & 0xFFu);
    p[2] = (uint8_t)((v >> 16) & 0xFFu);
}

static uint32_t get24(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16);
}

static int32_t sext24(uint32_t v)
{
    v &= 0xFFFFFFu;
    return (v & 0x800000u) ? (int32_t)v - 0x1000000 : (int32_t)v;
}

static void put16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)(v >> 8);
}

static uint16_t get16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

static int fits24(int32_t v)
{
    return v >= -0x800000 && v <= 0x7FFFFF;
}

/* ---------------------------------------------------------------- field helpers */

int32_t kelp_remus_latlon_encode(double deg)
{
    if (!isfinite(deg)) return 0;
    double e = deg * (LATLON_FULL / 180.0);
    if (!isfinite(e)) return 0; /* |deg| near DBL_MAX overflows */
    e += (e > 0.0) ? 0.5 : -0.5;
    /* truncate toward zero, then keep the low 24 bits as a 24-bit signed code (Goby's long ->
     * 3-byte copy); |e| beyond 2^52 has no fraction left, so reduce it modulo 2^24 first */
    double r = fmod(trunc(e), 16777216.0);
    int64_t t = (int64_t)r;
    return sext24((uint32_t)(t & 0xFFFFFF));
}

double kelp_remus_latlon_decode(int32_t code)
{
    return (double)sext24((uint32_t)code) * (180.0 / LATLON_FULL);
}

double kelp_remus_latlon_decode_goby1(int32_t code)
{
    double v = (double)((uint32_t)code & 0xFFFFFFu) * (180.0 / LATLON_FULL);
    if (v > 180.0) v -= 360.0;
    return v;
}

uint8_t kelp_remus_heading_encode(double deg)
{
    if (!isfinite(deg)) return 0;
    double h = fmod(deg, 360.0);
    if (h < 0) h += 360.0;
    float f = (float)h;
    if (f >= 360.0f) f = 0.0f; /* a tiny negative wrapped to 360 */
    double c = (double)f * 255.0 / 360.0 + 0.5;
    return (uint8_t)c; /* c < 255.5 */
}

double kelp_remus_heading_decode(uint8_t code)
{
    return (double)code * 360.0 / 255.0;
}

uint16_t kelp_remus_depth_encode(double m)
{
    float d = (float)m;
    if (d < 0) return 0;
    if (d < 100) return (uint16_t)(((double)d + .05) * 1.0 / 0.1);
    if (d < 200) return (uint16_t)(((double)(d - 100.0f) + 0.1) * 1.0 / 0.2 + 1000);
    if (d < 1000) return (uint16_t)(((double)(d - 200.0f) + 0.25) * 1.0 / 0.5 + 1500);
    if (d < 6000) return (uint16_t)(((double)(d - 1000.0f) + 0.5) * 1.0 / 1.0 + 3100);
    return 8100; /* 6000 m and beyond, and NaN */
}

double kelp_remus_depth_decode(uint16_t code)
{
    unsigned c = code & 0x1FFFu;
    double v;
    if (c <= 1000) v = c * 0.1 / 1.0;
    else if (c <= 1500) v = 100 + (c - 1000) * 0.2 / 1.0;
    else if (c <= 3100) v = 200 + (c - 1500) * 0.5 / 1.0;
    else if (c <= 8100) v = 1000 + (c - 3100) * 1.0 / 1.0;
    else v = 6000;
    return (double)(float)v;
}

static int8_t clamp_s8(double v, double lo, double hi)
{
    if (!(v == v)) return 0; /* NaN */
    if (v > hi) v = hi;
    if (v < lo) v = lo;
    return (int8_t)v; /* truncation toward zero */
}

int8_t kelp_remus_velocity_encode(double mps)
{
    return clamp_s8((double)(float)mps * 25.0, -128.0, 127.0);
}

double kelp_remus_velocity_decode(int8_t code)
{
    return (double)(float)(code / 25.0);
}

int8_t kelp_remus_speed_encode(double mps)
{
    float s = (float)mps * 30; /* float arithmetic, as the helper's float parameter */
    return clamp_s8((double)s, -127.0, 127.0);
}

double kelp_remus_speed_decode(int8_t code)
{
    return (double)(float)((float)code / 30.0);
}

uint8_t kelp_remus_watts_encode(double watts)
{
    float w = (float)watts / 4;
    if (!(w == w)) return 0;
    if (w > 255) w = 255;
    else if (w < 0) w = 0;
    return (uint8_t)w;
}

double kelp_remus_watts_decode(uint8_t code)
{
    return (double)(float)((float)code * 4.0);
}

uint8_t kelp_remus_fix_age_encode(double seconds)
{
    if (!(seconds > 0)) return 0;
    double c = seconds / 4;
    return c >= 255 ? 255 : (uint8_t)c;
}

unsigned kelp_remus_fix_age_decode(uint8_t code)
{
    return 4u * code;
}

uint16_t kelp_remus_gfi_pitch_oil_encode(double gfi_in, double pitch_in, double oil_in)
{
    float gfi = (float)gfi_in, pitch = (float)pitch_in, oil = (float)oil_in;
    if (!(gfi == gfi)) gfi = 0;
    if (!(oil == oil)) oil = 0;
    if (!(pitch == pitch)) pitch = 0;
    if (gfi < 0) gfi = 0;
    else if (gfi > 100) gfi = 100;
    unsigned result = (unsigned)((double)gfi * 31.0 / 100.0);
    if (oil < 0) oil = 0;
    else if (oil > 100) oil = 100;
    oil = (float)((double)oil * (31.0 / 100.0));
    result |= (unsigned)oil << 5;
    if (pitch > 90) pitch = 90;
    else if (pitch < -90) pitch = -90;
    pitch = (float)((double)pitch * (63.0 / 180.0));
    if (pitch > 0.0f) pitch = (float)((double)pitch + 0.5);
    else if (pitch < 0) pitch = (float)((double)pitch - 0.5);
    int p = (int)pitch;
    if (p > 31) p = 31; /* kelp: +90 would wrap to -32 in 6 bits */
    result |= ((unsigned)p << 10) & 0xFC00u;
    return (uint16_t)result;
}

void kelp_remus_gfi_pitch_oil_decode(uint16_t code, double *gfi, double *pitch, double *oil)
{
    unsigned g = (unsigned)((code & 0x001Fu) * 100.0 / 31.0);
    unsigned o = (code & 0x03E0u) >> 5;
    int p = (int)(code >> 10);
    if (p >= 32) p -= 64;
    if (gfi) *gfi = (double)(float)g;
    if (oil) *oil = (double)(float)(o * 100.0 / 31.0);
    if (pitch) *pitch = (double)(float)(p * 180.0 / 63.0);
}

uint32_t kelp_remus_time_date_encode(int64_t unix_s)
{
    int64_t days = kelp_util_floor_div(unix_s, 86400);
    int64_t sod = unix_s - days * 86400;
    int64_t year;
    unsigned mon, mday;
    kelp_util_civil_from_days(days, &year, &mon, &mday);
    uint32_t hour = (uint32_t)(sod / 3600), min = (uint32_t)(sod / 60 % 60),
             sec = (uint32_t)(sod % 60);
    return (sec >> 2) | (min << 4) | (hour << 10) | ((uint32_t)mday << 15) | ((uint32_t)mon << 20);
}

void kelp_remus_time_date_decode(uint32_t code, kelp_remus_time *out)
{
    out->month = (code >> 20) & 0x0Fu;
    out->day = (code >> 15) & 0x1Fu;
    out->hour = (code >> 10) & 0x1Fu;
    out->minute = (code >> 4) & 0x3Fu;
    out->second = (code & 0x0Fu) * 4;
}

int kelp_remus_time_date_to_unix(uint32_t code, int64_t year, int64_t *unix_s)
{
    kelp_remus_time t;
    kelp_remus_time_date_decode(code, &t);
    if (t.month < 1 || t.month > 12 || t.day < 1 || t.hour > 23 || t.minute > 59 ||
        t.second > 59)
        return KELP_ERR_RANGE;
    int64_t d = kelp_util_days_from_civil(year, t.month, t.day);
    int64_t y2;
    unsigned m2, d2;
    kelp_util_civil_from_days(d, &y2, &m2, &d2);
    if (y2 != year || m2 != t.month || d2 != t.day) return KELP_ERR_RANGE; /* e.g. Feb 30 */
    *unix_s = d * 86400 + t.hour * 3600 + t.minute * 60 + t.second;
    return KELP_OK;
}

/* ---------------------------------------------------------------- State */

int kelp_remus_state_encode(const kelp_remus_state *s, uint8_t *out, size_t cap, size_t *len)
{
    if (!s || !out) return KELP_ERR_ARG;
    if (!fits24(s->lat) || !fits24(s->lon) || !fits24(s->lat_goal) || !fits24(s->lon_goal) ||
        s->time_date > 0xFFFFFFu || s->mission_mode > 7 || s->depth > 0x1FFF)
        return KELP_ERR_RANGE;
    if (cap < KELP_REMUS_FRAME_LEN) return KELP_ERR_NOSPACE;
    out[0] = KELP_REMUS_ID_STATE;
    put24(out + 1, (uint32_t)s->lat);
    put24(out + 4, (uint32_t)s->lon);
    out[7] = s->fix_age;
    put24(out + 8, s->time_date);
    out[11] = s->heading;
    put16(out + 12, (uint16_t)(((unsigned)s->mission_mode << 13) | s->depth));
    put16(out + 14, (uint16_t)(s->faults & 0xFFFFu));
    put16(out + 16, (uint16_t)(s->faults >> 16));
    out[18] = s->faults_2;
    out[19] = s->mission_leg;
    out[20] = (uint8_t)s->est_velocity;
    out[21] = s->objective_index;
    out[22] = s->watts;
    put24(out + 23, (uint32_t)s->lat_goal);
    put24(out + 26, (uint32_t)s->lon_goal);
    out[29] = s->battery_percent;
    put16(out + 30, s->gfi_pitch_oil);
    if (len) *len = KELP_REMUS_FRAME_LEN;
    return KELP_OK;
}

static int check_frame(const uint8_t *in, size_t len, uint8_t id)
{
    if (!in) return KELP_ERR_ARG;
    if (len < KELP_REMUS_FRAME_LEN) return KELP_ERR_TRUNCATED;
    if (len > KELP_REMUS_FRAME_LEN) return KELP_ERR_RANGE;
    if (in[0] != id) return KELP_ERR_PARSE;
    return KELP_OK;
}

int kelp_remus_state_decode(const uint8_t *in, size_t len, kelp_remus_state *out)
{
    if (!out) return KELP_ERR_ARG;
    int rc = check_frame(in, len, KELP_REMUS_ID_STATE);
    if (rc) return rc;
    out->lat = sext24(get24(in + 1));
    out->lon = sext24(get24(in + 4));
    out->fix_age = in[7];
    out->time_date = get24(in + 8);
    out->heading = in[11];
    uint16_t md = get16(in + 12);
    out->mission_mode = (uint8_t)(md >> 13);
    out->depth = (uint16_t)(md & 0x1FFFu);
    out->faults = (uint32_t)get16(in + 14) | ((uint32_t)get16(in + 16) << 16);
    out->faults_2 = in[18];
    out->mission_leg = in[19];
    out->est_velocity = (int8_t)in[20];
    out->objective_index = in[21];
    out->watts = in[22];
    out->lat_goal = sext24(get24(in + 23));
    out->lon_goal = sext24(get24(in + 26));
    out->battery_percent = in[29];
    out->gfi_pitch_oil = get16(in + 30);
    return KELP_OK;
}

void kelp_remus_state_from_nav(kelp_remus_state *s, double lat, double lon, int64_t unix_s,
                               double heading, double depth, double speed)
{
    *s = (kelp_remus_state){0};
    s->lat = kelp_remus_latlon_encode(lat);
    s->lon = kelp_remus_latlon_encode(lon);
    s->time_date = kelp_remus_time_date_encode(unix_s);
    s->heading = kelp_remus_heading_encode(heading);
    s->depth = kelp_remus_depth_encode(depth);
    s->est_velocity = kelp_remus_velocity_encode(speed);
}

/* ---------------------------------------------------------------- Redirect */

static unsigned clamp_trunc(double v, double hi)
{
    if (!(v > 0)) return 0;
    return v >= hi ? (unsigned)hi : (unsigned)v;
}

int kelp_remus_redirect_encode(const kelp_remus_redirect *r, uint8_t *out, size_t cap, size_t *len)
{
    if (!r || !out) return KELP_ERR_ARG;
    if (cap < KELP_REMUS_FRAME_LEN) return KELP_ERR_NOSPACE;
    for (size_t i = 0; i < KELP_REMUS_FRAME_LEN; i++) out[i] = 0;
    out[0] = KELP_REMUS_ID_REDIRECT;
    put24(out + 2, (uint32_t)kelp_remus_latlon_encode(r->lat));
    put24(out + 5, (uint32_t)kelp_remus_latlon_encode(r->lon));
    out[8] = r->speed_depth_flags;
    put16(out + 9, kelp_remus_depth_encode(r->transit_depth));
    out[11] = (uint8_t)kelp_remus_speed_encode(r->transit_speed);
    out[12] = r->transit_command;
    put16(out + 13, kelp_remus_depth_encode(r->survey_depth));
    out[15] = (uint8_t)kelp_remus_speed_encode(r->survey_speed);
    out[16] = r->survey_command;
    out[17] = r->rows;
    put16(out + 18, (uint16_t)clamp_trunc(r->row_length, 65535));
    out[20] = (uint8_t)clamp_trunc(r->row_spacing_0, 255);
    out[21] = (uint8_t)clamp_trunc(r->row_spacing_1, 255);
    out[22] = kelp_remus_heading_encode(r->row_heading);
    put24(out + 23, (uint32_t)kelp_remus_latlon_encode(r->start_lat));
    put24(out + 26, (uint32_t)kelp_remus_latlon_encode(r->start_lon));
    if (len) *len = KELP_REMUS_FRAME_LEN;
    return KELP_OK;
}

/* ---------------------------------------------------------------- Ranger */

static double bcd_ll(const uint8_t *c)
{
    double deg = (c[0] >> 4) * 100.0 + (c[0] & 0x0F) * 10.0 + (c[1] >> 4) * 1.0;
    unsigned sign = c[1] & 0x0Fu;
    double s = (sign == 0x0C || sign == 0x0D) ? -1.0 : 1.0;
    double min = (c[2] >> 4) * 10.0 + (c[2] & 0x0F) * 1.0 + (c[3] >> 4) * 0.1 +
                 (c[3] & 0x0F) * 0.01 + (c[4] >> 4) * 0.001 + (c[4] & 0x0F) * 0.0001;
    return (deg + (min / 60.0)) * s;
}

static double bcd2(uint8_t a, uint8_t b)
{
    return (a >> 4) * 1000.0 + (a & 0x0F) * 100.0 + (b >> 4) * 10.0 + (b & 0x0F) * 1.0;
}

static double bcd1(uint8_t a)
{
    return (a >> 4) * 10.0 + (a & 0x0F) * 1.0;
}

int kelp_remus_ranger_decode(const uint8_t *in, size_t len, kelp_remus_ranger *out)
{
    if (!out) return KELP_ERR_ARG;
    int rc = check_frame(in, len, KELP_REMUS_ID_RANGER);
    if (rc) return rc;
    out->lat = bcd_ll(in + 1);
    out->lon = bcd_ll(in + 6);
    out->speed = bcd1(in[18]) * 0.1;
    out->heading = bcd2(in[19], in[20]) * 0.1;
    out->depth = bcd2(in[28], in[23]);
    return KELP_OK;
}
