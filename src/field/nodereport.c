/* NODE_REPORT formatting and parsing (see include/kelp/nodereport.h). */
#include <math.h>
#include <stddef.h>
#include <string.h>
#include <kelp/nodereport.h>
#include <kelp/mission.h>
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

int kelp_nodereport_format(const kelp_nodereport *r, char *buf, size_t cap, size_t *len)
{
    size_t n = 0;
    if (buf && cap) buf[0] = 0;
    if (!r || !buf || !(r->fields & KELP_NR_NAME) || !r->name[0]) return KELP_ERR_ARG;
    const char *texts[] = {r->name, r->type, r->mode, r->allstop, r->group, r->color};
    const uint32_t tbits[] = {KELP_NR_NAME, KELP_NR_TYPE, KELP_NR_MODE, KELP_NR_ALLSTOP, KELP_NR_GROUP, KELP_NR_COLOR};
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++)
        if ((r->fields & tbits[i]) && (!memchr(texts[i], 0, KELP_NODEREPORT_MAX_FIELD) || !text_ok(texts[i])))
            return KELP_ERR_ARG;
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
    int rc = KELP_OK;
    const char *base = (const char *)r;
    for (size_t i = 0; i < sizeof f / sizeof f[0] && rc == KELP_OK; i++) {
        if (!(r->fields & f[i].bit)) continue;
        bool index = f[i].bit == KELP_NR_INDEX;
        if (index && !r->index) continue;
        const char *key = f[i].bit == KELP_NR_DEPTH && r->dep_key ? "DEP" : f[i].key;
        double num = 0;
        if (index) num = (double)r->index;
        else if (!f[i].text) memcpy(&num, base + f[i].off, sizeof num);
        if (n > 0) rc = field_put_str(buf, cap, &n, ",");
        if (rc == KELP_OK) rc = field_put_str(buf, cap, &n, key);
        if (rc == KELP_OK) rc = field_put_str(buf, cap, &n, "=");
        if (rc == KELP_OK) rc = f[i].text ? field_put_str(buf, cap, &n, base + f[i].off)
                                          : field_put_fixed(buf, cap, &n, num, f[i].dec, f[i].strip);
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
    static const struct {
        const char *key;
        uint32_t bit;
    } keys[] = {
        {"NAME", KELP_NR_NAME},   {"VNAME", KELP_NR_NAME},     {"TYPE", KELP_NR_TYPE},   {"TIME", KELP_NR_TIME},
        {"X", KELP_NR_X},         {"Y", KELP_NR_Y},            {"LAT", KELP_NR_LAT},     {"LON", KELP_NR_LON},
        {"LONG", KELP_NR_LON},    {"SPD", KELP_NR_SPD},        {"SPEED", KELP_NR_SPD},   {"HDG", KELP_NR_HDG},
        {"HEADING", KELP_NR_HDG}, {"DEPTH", KELP_NR_DEPTH},    {"DEP", KELP_NR_DEPTH},   {"LENGTH", KELP_NR_LENGTH},
        {"MODE", KELP_NR_MODE},   {"ALLSTOP", KELP_NR_ALLSTOP}, {"GROUP", KELP_NR_GROUP},
        {"YAW", KELP_NR_YAW},     {"INDEX", KELP_NR_INDEX},    {"COLOR", KELP_NR_COLOR},
    };
    uint32_t bit = 0;
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (kelp_strieq_n(k, kl, keys[i].key)) {
            bit = keys[i].bit;
            break;
        }
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
