/* NODE_REPORT formatting and parsing (see include/kelp/nodereport.h). */
#include <math.h>
#include <stddef.h>
#include <string.h>
#include <kelp/helm.h>
#include <kelp/nodereport.h>
#include <kelp/mission.h>
#include <kelp/util.h>
#include "field_int.h"

void kelp_nodereport_init(kelp_nodereport *r)
{
    memset(r, 0, sizeof *r);
}

static bool text_ok(const char *s)
{
    for (; *s; s++)
        if (*s == ',' || *s == '=') return false;
    return true;
}

/* a report that can be written: a name, text fields terminated and free of ',' and '=' */
static bool writable(const kelp_nodereport *r)
{
    if (!r || !(r->fields & KELP_NR_NAME) || !r->name[0]) return false;
    const char *texts[] = {r->name, r->type, r->mode, r->allstop, r->group, r->color};
    const uint32_t tbits[] = {KELP_NR_NAME, KELP_NR_TYPE, KELP_NR_MODE, KELP_NR_ALLSTOP, KELP_NR_GROUP, KELP_NR_COLOR};
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++)
        if ((r->fields & tbits[i]) && (!memchr(texts[i], 0, KELP_NODEREPORT_MAX_FIELD) || !text_ok(texts[i])))
            return false;
    return true;
}

/* ",KEY=value" (no comma first): a text, or a number with dec decimals */
static int put_field(char *buf, size_t cap, size_t *n, const char *key, const char *text, double num, int dec,
                     bool strip)
{
    int rc = *n > 0 ? field_put_str(buf, cap, n, ",") : KELP_OK;
    if (rc == KELP_OK) rc = field_put_str(buf, cap, n, key);
    if (rc == KELP_OK) rc = field_put_str(buf, cap, n, "=");
    if (rc == KELP_OK) rc = text ? field_put_str(buf, cap, n, text) : field_put_fixed(buf, cap, n, num, dec, strip);
    return rc;
}

int kelp_nodereport_format(const kelp_nodereport *r, char *buf, size_t cap, size_t *len)
{
    size_t n = 0;
    if (buf && cap) buf[0] = 0;
    if (!buf || !writable(r)) return KELP_ERR_ARG;
    /* the fields in the order written: a constant table of offsets (no table on the stack) */
    static const struct {
        const char *key;
        size_t off;   /* of the text (char[]) or the number (double) in kelp_nodereport */
        uint32_t bit;
        bool text;
        unsigned char dec;
        bool strip;
    } f[] = {
        {"NAME", offsetof(kelp_nodereport, name), KELP_NR_NAME, true, 0, false},
        {"TYPE", offsetof(kelp_nodereport, type), KELP_NR_TYPE, true, 0, false},
        {"TIME", offsetof(kelp_nodereport, time), KELP_NR_TIME, false, 2, false},
        {"COLOR", offsetof(kelp_nodereport, color), KELP_NR_COLOR, true, 0, false},
        {"X", offsetof(kelp_nodereport, x), KELP_NR_X, false, 2, false},
        {"Y", offsetof(kelp_nodereport, y), KELP_NR_Y, false, 2, false},
        {"LAT", offsetof(kelp_nodereport, lat), KELP_NR_LAT, false, 6, false},
        {"LON", offsetof(kelp_nodereport, lon), KELP_NR_LON, false, 6, false},
        {"SPD", offsetof(kelp_nodereport, spd), KELP_NR_SPD, false, 2, false},
        {"HDG", offsetof(kelp_nodereport, hdg), KELP_NR_HDG, false, 2, false},
        {"YAW", offsetof(kelp_nodereport, yaw), KELP_NR_YAW, false, 7, true},
        {"DEPTH", offsetof(kelp_nodereport, depth), KELP_NR_DEPTH, false, 2, false},
        {"LENGTH", offsetof(kelp_nodereport, length), KELP_NR_LENGTH, false, 2, true},
        {"MODE", offsetof(kelp_nodereport, mode), KELP_NR_MODE, true, 0, false},
        {"ALLSTOP", offsetof(kelp_nodereport, allstop), KELP_NR_ALLSTOP, true, 0, false},
        {"GROUP", offsetof(kelp_nodereport, group), KELP_NR_GROUP, true, 0, false},
        {"INDEX", 0, KELP_NR_INDEX, false, 0, false},
    };
    /* NodeRecord::getSpec (MOOS-IvP 24.8): its order, every number trimmed */
    static const unsigned char order248[] = { 0, 4, 5, 8, 9, 11, 6, 7, 1, 3, 15, 13, 14, 16, 10, 2, 12 };
    _Static_assert(sizeof order248 == sizeof f / sizeof f[0], "every field in the 24.8 order");
    int rc = KELP_OK;
    const char *base = (const char *)r;
    for (size_t j = 0; j < sizeof f / sizeof f[0] && rc == KELP_OK; j++) {
        size_t i = r->moos248 ? order248[j] : j;
        if (!(r->fields & f[i].bit)) continue;
        bool index = f[i].bit == KELP_NR_INDEX;
        if (index && !r->index) continue;
        const char *key = f[i].bit == KELP_NR_DEPTH && r->dep_key ? "DEP" : f[i].key;
        double num = 0;
        if (index) num = (double)r->index;
        else if (!f[i].text) memcpy(&num, base + f[i].off, sizeof num);
        unsigned dec = r->moos248 && (f[i].bit == KELP_NR_LAT || f[i].bit == KELP_NR_LON) ? 8 : f[i].dec;
        rc = put_field(buf, cap, &n, key, f[i].text ? base + f[i].off : NULL, num, (int)dec, f[i].strip || r->moos248);
    }
    if (rc == KELP_OK && r->extra && r->extra[0]) {
        rc = field_put_str(buf, cap, &n, ",");
        if (rc == KELP_OK) rc = field_put_str(buf, cap, &n, r->extra);
    }
    if (rc < 0) {
        if (cap) buf[0] = 0;
        return rc;
    }
    if (len) *len = n;
    return KELP_OK;
}

/* the keys a report may hold (any case) and the field each sets */
static const struct {
const char *key;
uint32_t bit;
} nr_keys[] = {
    {"NAME", KELP_NR_NAME},   {"VNAME", KELP_NR_NAME},     {"TYPE", KELP_NR_TYPE},   {"TIME", KELP_NR_TIME},
    {"X", KELP_NR_X},         {"Y", KELP_NR_Y},            {"LAT", KELP_NR_LAT},     {"LON", KELP_NR_LON},
    {"LONG", KELP_NR_LON},    {"SPD", KELP_NR_SPD},        {"SPEED", KELP_NR_SPD},   {"HDG", KELP_NR_HDG},
    {"HEADING", KELP_NR_HDG}, {"DEPTH", KELP_NR_DEPTH},    {"DEP", KELP_NR_DEPTH},   {"LENGTH", KELP_NR_LENGTH},
    {"MODE", KELP_NR_MODE},   {"ALLSTOP", KELP_NR_ALLSTOP}, {"GROUP", KELP_NR_GROUP},
    {"YAW", KELP_NR_YAW},     {"INDEX", KELP_NR_INDEX},    {"COLOR", KELP_NR_COLOR},
    {"COG", KELP_NR_COG},     {"UTC_TIME", KELP_NR_TIME},  {"LEN", KELP_NR_LENGTH},
};

/* the field of a key, 0 when kelp does not read it */
static uint32_t nr_key_bit(const char *k, size_t kl)
{
    for (size_t i = 0; i < sizeof nr_keys / sizeof nr_keys[0]; i++)
        if (kelp_util_strieq_n(k, kl, nr_keys[i].key)) return nr_keys[i].bit;
    return 0;
}

/* Two passes over the pairs: the first (r NULL) checks every value and which keys are there,
 * the second writes them into the caller's report. No report-sized copy on the stack (this
 * parser runs under every NODE_REPORT of the uField tools), and the output is still untouched
 * when the text is refused. */
typedef struct nrparse {
    kelp_nodereport *r; /**< NULL in the checking pass */
    kelp_diag *d;
    uint32_t seen;      /**< keys met (the first of a repeated key wins) */
    bool name_empty;
} nrparse;

static int on_pair(void *ctx, const char *k, size_t kl, const char *v, size_t vl)
{
    nrparse *p = ctx;
    kelp_nodereport *r = p->r;
    uint32_t bit = nr_key_bit(k, kl);
    if (!bit || (p->seen & bit)) return KELP_OK; /* unknown key, or a repeat: first wins */
    p->seen |= bit;
    bool is_text = bit == KELP_NR_NAME || bit == KELP_NR_TYPE || bit == KELP_NR_MODE || bit == KELP_NR_ALLSTOP ||
                   bit == KELP_NR_GROUP || bit == KELP_NR_COLOR;
    double x = 0;
    if (is_text) {
        /* a text field must survive format -> parse: no quote, brace, separator or control
         * byte (a fuzz finding: name=char"lie parsed, but its report could not be re-read) */
        for (size_t i = 0; i < vl; i++) {
            unsigned char c = (unsigned char)v[i];
            if (c < 0x20 || c == 0x7f || c == '"' || c == '{' || c == '}' || c == ',' || c == '=') {
                return kelp_fail(p->d, KELP_ERR_PARSE, "text field holds a quote, brace, ',', '=' or control character");
            }
        }
        if (vl + 1 > KELP_NODEREPORT_MAX_FIELD) {
            return kelp_fail(p->d, KELP_ERR_RANGE, "text field too long");
        }
        if (bit == KELP_NR_NAME) p->name_empty = vl == 0;
    } else if (sim_number(v, vl, &x) < 0) {
        return kelp_fail(p->d, KELP_ERR_PARSE, "bad number");
    }
    if (bit == KELP_NR_INDEX && (!(x >= 0 && x <= 2e9) || x != (double)(long)x)) {
        return kelp_fail(p->d, KELP_ERR_PARSE, "INDEX is not a count");
    }
    if (!r) return KELP_OK; /* the checking pass */
    char *text = NULL;
    double *num = NULL;
    switch (bit) {
    case KELP_NR_NAME: text = r->name; break;
    case KELP_NR_TYPE: text = r->type; break;
    case KELP_NR_MODE: text = r->mode; break;
    case KELP_NR_ALLSTOP: text = r->allstop; break;
    case KELP_NR_GROUP: text = r->group; break;
    case KELP_NR_COLOR: text = r->color; break;
    case KELP_NR_YAW: num = &r->yaw; break;
    case KELP_NR_INDEX: r->index = (long)x; break;
    case KELP_NR_TIME: num = &r->time; break;
    case KELP_NR_X: num = &r->x; break;
    case KELP_NR_Y: num = &r->y; break;
    case KELP_NR_LAT: num = &r->lat; break;
    case KELP_NR_LON: num = &r->lon; break;
    case KELP_NR_SPD: num = &r->spd; break;
    case KELP_NR_HDG: num = &r->hdg; break;
    case KELP_NR_DEPTH: num = &r->depth; break;
    case KELP_NR_COG: num = &r->cog; break;
    default: num = &r->length; break;
    }
    if (text) (void)field_copy_text(text, KELP_NODEREPORT_MAX_FIELD, v, vl); /* fits: checked above */
    if (num) *num = x;
    r->fields |= bit;
    return KELP_OK;
}

int kelp_nodereport_parse(const char *s, size_t len, kelp_nodereport *out, kelp_diag *d)
{
    if (!s || !out) {
        return kelp_fail(d, KELP_ERR_ARG, "no input");
    }
    /* a report quoted as a whole ("NAME=...") */
    while (len && (s[len - 1] == ' ' || s[len - 1] == '\n' || s[len - 1] == '\r')) len--;
    while (len && *s == ' ') s++, len--;
    if (len >= 2 && s[0] == '"' && s[len - 1] == '"') s++, len -= 2;
    nrparse p = {NULL, d, 0, false};
    int rc = field_for_pairs(s, len, ',', on_pair, &p, d);
    if (rc < 0) return rc;
    if (!(p.seen & KELP_NR_NAME) || p.name_empty) {
        return kelp_fail(d, KELP_ERR_PARSE, "no NAME");
    }
    bool xy = (p.seen & (KELP_NR_X | KELP_NR_Y)) == (KELP_NR_X | KELP_NR_Y);
    bool ll = (p.seen & (KELP_NR_LAT | KELP_NR_LON)) == (KELP_NR_LAT | KELP_NR_LON);
    if (!xy && !ll) {
        return kelp_fail(d, KELP_ERR_PARSE, "no position (X,Y or LAT,LON)");
    }
    kelp_nodereport_init(out);
    p = (nrparse){out, d, 0, false};
    return field_for_pairs(s, len, ',', on_pair, &p, d); /* 0: the same text passed the check */
}

int kelp_nodereport_complete(kelp_nodereport *r, const kelp_geo *g)
{
    const uint32_t XY = KELP_NR_X | KELP_NR_Y, LL = KELP_NR_LAT | KELP_NR_LON;
    if ((r->fields & XY) != XY && (r->fields & LL) == LL) {
        if (kelp_geo_to_local(g, r->lat, r->lon, &r->x, &r->y) < 0) return KELP_ERR_RANGE;
        r->fields |= XY;
    } else if ((r->fields & LL) != LL && (r->fields & XY) == XY) {
        if (kelp_geo_to_latlon(g, r->x, r->y, &r->lat, &r->lon) < 0) return KELP_ERR_RANGE;
        r->fields |= LL;
    }
    return KELP_OK;
}

/* ------------------------------------------------------------------ MOOS-IvP 24.8's node record */

/* byte order of two counted keys (std::map<std::string, ...>) */
static int keycmp(const char *a, size_t al, const char *b, size_t bl)
{
    int c = memcmp(a, b, al < bl ? al : bl);
    return c ? c : (al < bl ? -1 : al > bl);
}

/* The pairs of s whose keys kelp does not read, in key order: each pass writes the smallest key
 * above the one written before, with the value of its last occurrence (no table: a report has
 * a few pairs, and this runs once per report received). */
static int put_properties(const char *s, char *buf, size_t cap, size_t *n)
{
    const char *prev = NULL;
    size_t prevl = 0, len = strlen(s);
    for (;;) {
        const char *best = NULL, *bv = NULL, *it;
        size_t bl = 0, bvl = 0, il, pos = 0;
        while (field_next_item(s, len, &pos, ',', &it, &il) == 1) {
            const char *eq = memchr(it, '=', il);
            if (!eq) continue;
            size_t kl = (size_t)(eq - it), vl = il - kl - 1;
            const char *v = eq + 1;
            while (kl && (it[kl - 1] == ' ' || it[kl - 1] == '\t')) kl--;
            while (vl && (*v == ' ' || *v == '\t')) v++, vl--;
            if (kl == 0 || nr_key_bit(it, kl) || (prev && keycmp(it, kl, prev, prevl) <= 0)) continue;
            int c = best ? keycmp(it, kl, best, bl) : -1;
            if (c <= 0) {
                if (c < 0) best = it, bl = kl;
                bv = v, bvl = vl; /* the last of a repeated key */
            }
        }
        if (!best) return KELP_OK;
        if (*n + 2 + bl + bvl >= cap) return KELP_ERR_NOSPACE;
        buf[(*n)++] = ',';
        memcpy(buf + *n, best, bl), *n += bl;
        buf[(*n)++] = '=';
        memcpy(buf + *n, bv, bvl), *n += bvl;
        buf[*n] = 0;
        prev = best, prevl = bl;
    }
}

int kelp_nodereport_format_record(const kelp_nodereport *r, char *buf, size_t cap, size_t *len)
{
    size_t n = 0;
    if (buf && cap) buf[0] = 0;
    if (!buf || !writable(r)) return KELP_ERR_ARG;
    /* NodeRecord::getSpec's order; numbers with trailing zeros stripped (doubleToStringX) */
    static const struct {
        const char *key;
        size_t off;
        uint32_t bit;
        bool text;
        unsigned char dec;
    } f[] = {
        {"NAME", offsetof(kelp_nodereport, name), KELP_NR_NAME, true, 0},
        {"X", offsetof(kelp_nodereport, x), KELP_NR_X, false, 2},
        {"Y", offsetof(kelp_nodereport, y), KELP_NR_Y, false, 2},
        {"SPD", offsetof(kelp_nodereport, spd), KELP_NR_SPD, false, 2},
        {"HDG", offsetof(kelp_nodereport, hdg), KELP_NR_HDG, false, 2},
        {"COG", offsetof(kelp_nodereport, cog), KELP_NR_COG, false, 2},
        {"DEP", offsetof(kelp_nodereport, depth), KELP_NR_DEPTH, false, 2},
        {"LAT", offsetof(kelp_nodereport, lat), KELP_NR_LAT, false, 8},
        {"LON", offsetof(kelp_nodereport, lon), KELP_NR_LON, false, 8},
        {"TYPE", offsetof(kelp_nodereport, type), KELP_NR_TYPE, true, 0},
        {"COLOR", offsetof(kelp_nodereport, color), KELP_NR_COLOR, true, 0},
        {"GROUP", offsetof(kelp_nodereport, group), KELP_NR_GROUP, true, 0},
        {"MODE", offsetof(kelp_nodereport, mode), KELP_NR_MODE, true, 0},
        {"ALLSTOP", offsetof(kelp_nodereport, allstop), KELP_NR_ALLSTOP, true, 0},
        {"INDEX", 0, KELP_NR_INDEX, false, 0},
        {"YAW", offsetof(kelp_nodereport, hdg), KELP_NR_YAW, false, 7},
        {"TIME", offsetof(kelp_nodereport, time), KELP_NR_TIME, false, 2},
        {"LENGTH", offsetof(kelp_nodereport, length), KELP_NR_LENGTH, false, 2},
    };
    int rc = KELP_OK;
    const char *base = (const char *)r;
    for (size_t i = 0; i < sizeof f / sizeof f[0] && rc == KELP_OK; i++) {
        if (!(r->fields & f[i].bit)) continue;
        if (f[i].text && !base[f[i].off]) continue; /* an empty text is not written */
        double num = 0;
        if (f[i].bit == KELP_NR_INDEX) {
            if (!r->index) continue;
            num = (double)r->index;
        } else if (!f[i].text) {
            memcpy(&num, base + f[i].off, sizeof num);
        }
        if (f[i].bit == KELP_NR_YAW) { /* 24.8 writes the heading in radians, east, wrapped once */
            num = (90.0 - r->hdg) * 3.14159265358979323846 / 180.0;
            if (num > 3.14159265358979323846) num -= 2 * 3.14159265358979323846;
            else if (num < -3.14159265358979323846) num += 2 * 3.14159265358979323846;
        }
        rc = put_field(buf, cap, &n, f[i].key, f[i].text ? base + f[i].off : NULL, num, f[i].dec, true);
    }
    if (rc == KELP_OK && r->extra) rc = put_properties(r->extra, buf, cap, &n);
    if (rc < 0) {
        if (cap) buf[0] = 0;
        return rc;
    }
    if (len) *len = n;
    return KELP_OK;
}

static void set_type(kelp_nodereport *r, const char *t)
{
    (void)field_copy_text(r->type, sizeof r->type, t, strlen(t));
    r->fields |= KELP_NR_TYPE;
}

int kelp_nodereport_ledger(kelp_nodereport *r, const double *prev_xy, kelp_diag *d)
{
    static const char *const known[] = {"auv",  "kayak", "uuv",   "usv",  "glider", "asv",   "ship",      "mokai",
                                        "longship", "buoy", "heron", "swimmer", "cray", "bcray", "crayx", "wamv",
                                        "bcrayx", "smr", "smrx",  "skyw", "skywalker", "quad", "quadcopter"};
    if (!(r->fields & KELP_NR_TYPE)) r->type[0] = 0;
    bool is_known = false;
    for (size_t i = 0; i < sizeof known / sizeof known[0] && !is_known; i++) is_known = kelp_util_strieq(r->type, known[i]);
    if (strcmp(r->type, "uuv") == 0) set_type(r, "auv");
    else if (!is_known) set_type(r, "ship");
    if ((!strcmp(r->type, "auv") || !strcmp(r->type, "glider")) && !(r->fields & KELP_NR_DEPTH))
        return kelp_fail(d, KELP_ERR_PARSE, "underwater vehicle type with no depth reported");
    if (!(r->fields & KELP_NR_LENGTH) || r->length <= 0) {
        static const struct {
            const char *type;
            double len;
        } dflt[] = {{"auv", 3},  {"kayak", 3},   {"heron", 3}, {"glider", 2}, {"cray", 1.5}, {"bcray", 1.5},
                    {"crayx", 1.5}, {"bcrayx", 1.5}, {"ship", 12}, {"longship", 15}, {"wamv", 6}, {"smr", 6}};
        if (!(r->fields & KELP_NR_LENGTH)) r->length = 0;
        for (size_t i = 0; i < sizeof dflt / sizeof dflt[0]; i++)
            if (!strcmp(r->type, dflt[i].type)) r->length = dflt[i].len;
    }
    r->fields |= KELP_NR_LENGTH;
    if (!(r->fields & KELP_NR_COG)) {
        const uint32_t XY = KELP_NR_X | KELP_NR_Y;
        if (!prev_xy) r->cog = (r->fields & KELP_NR_HDG) ? r->hdg : 0, r->fields |= KELP_NR_COG;
        else if ((r->fields & XY) == XY) r->cog = kelp_helm_relang(prev_xy[0], prev_xy[1], r->x, r->y), r->fields |= KELP_NR_COG;
    }
    return KELP_OK;
}
