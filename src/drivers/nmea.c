/* kelp: NMEA 0183 line reader, parser and writer (core). */
#include <kelp/util.h>
#include <kelp/nmea.h>

#include <limits.h>
#include <string.h>

static const char HEXU[] = "0123456789ABCDEF";

static bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}


uint8_t kelp_nmea_checksum(const char *s, size_t n)
{
    uint8_t cs = 0;
    for (size_t i = 0; i < n; i++) cs ^= (uint8_t)s[i];
    return cs;
}

int kelp_nmea_parse(const char *line, size_t len, kelp_nmea_sentence *out)
{
    if (!line || !out) return KELP_ERR_ARG;
    /* trim, as boost::trim in Goby's driver and NMEASentence */
    while (len > 0 && is_space(line[0])) { line++; len--; }
    while (len > 0 && is_space(line[len - 1])) len--;
    out->nfields = 0;
    out->had_checksum = false;
    out->talker[0] = out->id[0] = '\0';
    if (len == 0) return KELP_ERR_EMPTY;
    if (line[0] != '$') return KELP_ERR_PARSE;
    if (len > KELP_MAX_NMEA_LINE) return KELP_ERR_NOSPACE;
    /* checksum first: "*hh" must be the last three characters */
    if (len > 3 && line[len - 3] == '*') {
        int h = kelp_util_hex_digit(line[len - 2]), l = kelp_util_hex_digit(line[len - 1]);
        if (h < 0 || l < 0) return KELP_ERR_PARSE;
        if (kelp_nmea_checksum(line + 1, len - 4) != (uint8_t)(h * 16 + l)) return KELP_ERR_CHECKSUM;
        out->had_checksum = true;
        len -= 3;
    }
    /* then split at ',' */
    unsigned nf = 0;
    out->off[nf++] = 0;
    for (size_t i = 0; i < len; i++) {
        char c = line[i];
        if (c == ',') {
            if (nf >= KELP_MAX_NMEA_FIELDS) { out->nfields = 0; return KELP_ERR_PARSE; }
            out->buf[i] = '\0';
            out->off[nf++] = (uint16_t)(i + 1);
        } else {
            out->buf[i] = c;
        }
    }
    out->buf[len] = '\0';
    /* field 0 must be "$" + 2-letter talker + 3-letter sentence id */
    size_t f0 = strlen(out->buf);
    if (f0 != 6) return KELP_ERR_PARSE;
    out->nfields = nf;
    memcpy(out->talker, out->buf + 1, 2);
    out->talker[2] = '\0';
    memcpy(out->id, out->buf + 3, 3);
    out->id[3] = '\0';
    return KELP_OK;
}

const char *kelp_nmea_field(const kelp_nmea_sentence *s, unsigned i)
{
    if (!s || i >= s->nfields) return "";
    return s->buf + s->off[i];
}

int kelp_nmea_field_long(const kelp_nmea_sentence *s, unsigned i, long *out)
{
    if (!s || !out) return KELP_ERR_ARG;
    if (i >= s->nfields) return KELP_ERR_NOTFOUND;
    const char *p = s->buf + s->off[i];
    bool neg = false;
    if (*p == '-' || *p == '+') { neg = (*p == '-'); p++; }
    if (*p == '\0') return KELP_ERR_PARSE;
    long v = 0;
    for (; *p; p++) {
        if (*p < '0' || *p > '9') return KELP_ERR_PARSE;
        int d = *p - '0';
        if (v > (LONG_MAX - d) / 10) return KELP_ERR_RANGE;
        v = v * 10 + d;
    }
    *out = neg ? -v : v;
    return KELP_OK;
}

int kelp_nmea_field_double(const kelp_nmea_sentence *s, unsigned i, double *out)
{
    if (!s || !out) return KELP_ERR_ARG;
    if (i >= s->nfields) return KELP_ERR_NOTFOUND;
    const char *p = s->buf + s->off[i];
    bool neg = false, digits = false;
    if (*p == '-' || *p == '+') { neg = (*p == '-'); p++; }
    double v = 0.0;
    for (; *p >= '0' && *p <= '9'; p++) { v = v * 10.0 + (*p - '0'); digits = true; }
    if (*p == '.') {
        double scale = 1.0;
        for (p++; *p >= '0' && *p <= '9'; p++) {
            scale /= 10.0;
            v += (*p - '0') * scale;
            digits = true;
        }
    }
    if (*p != '\0' || !digits) return KELP_ERR_PARSE;
    *out = neg ? -v : v;
    return KELP_OK;
}

static void put(char *buf, size_t cap, size_t *len, bool *full, char c)
{
    if (*len + 1 < cap) buf[(*len)++] = c;
    else *full = true;
}

int kelp_nmea_render(const kelp_nmea_sentence *s, char *buf, size_t cap, size_t *len)
{
    if (!s || !buf || !len || cap == 0) return KELP_ERR_ARG;
    size_t n = 0;
    bool full = false;
    for (unsigned i = 0; i < s->nfields; i++) {
        if (i) put(buf, cap, &n, &full, ',');
        for (const char *p = s->buf + s->off[i]; *p; p++) put(buf, cap, &n, &full, *p);
    }
    uint8_t cs = n > 1 ? kelp_nmea_checksum(buf + 1, n - 1) : 0;
    put(buf, cap, &n, &full, '*');
    put(buf, cap, &n, &full, HEXU[cs >> 4]);
    put(buf, cap, &n, &full, HEXU[cs & 15]);
    buf[n] = '\0';
    *len = n;
    return full ? KELP_ERR_NOSPACE : KELP_OK;
}

/* ------------------------------------------------------------------ reader */

void kelp_nmea_reader_init(kelp_nmea_reader *r, char delim)
{
    memset(r, 0, sizeof *r);
    r->delim = delim ? delim : '\r';
}

int kelp_nmea_reader_feed(kelp_nmea_reader *r, uint8_t byte, const char **line, size_t *len)
{
    r->count.bytes++;
    if ((char)byte != r->delim) {
        if (r->overflow) return KELP_ERR_PARTIAL;
        /* skip leading whitespace (the '\n' of "\r\n" when reading with '\r') */
        if (r->len == 0 && is_space((char)byte)) return KELP_ERR_PARTIAL;
        if (r->len >= KELP_MAX_NMEA_LINE) {
            r->overflow = true;
            r->len = 0;
            return KELP_ERR_PARTIAL;
        }
        r->line[r->len++] = (char)byte;
        return KELP_ERR_PARTIAL;
    }
    if (r->overflow) {
        r->overflow = false;
        r->count.overflow++;
        return KELP_ERR_NOSPACE;
    }
    size_t n = r->len;
    r->len = 0;
    while (n > 0 && is_space(r->line[n - 1])) n--;
    if (n == 0) return KELP_ERR_PARTIAL;
    r->line[n] = '\0';
    r->count.lines++;
    *line = r->line;
    *len = n;
    return KELP_OK;
}

int kelp_nmea_reader_feed_sentence(kelp_nmea_reader *r, uint8_t byte, kelp_nmea_sentence *out)
{
    const char *line;
    size_t len;
    int rc = kelp_nmea_reader_feed(r, byte, &line, &len);
    if (rc == KELP_ERR_PARTIAL) return rc;
    if (rc != KELP_OK) return rc; /* overflow already counted */
    rc = kelp_nmea_parse(line, len, out);
    if (rc == KELP_OK) r->count.ok++;
    else if (rc == KELP_ERR_CHECKSUM) r->count.checksum++;
    else r->count.parse++;
    return rc;
}

/* ------------------------------------------------------------------ writer */

static void wput(kelp_nmea_writer *w, char c)
{
    if (w->err) return;
    if (w->len + 1 >= w->cap) { w->err = KELP_ERR_NOSPACE; return; }
    w->buf[w->len++] = c;
}

void kelp_nmea_writer_init(kelp_nmea_writer *w, char *buf, size_t cap, const char *head)
{
    w->buf = buf;
    w->cap = cap;
    w->len = 0;
    w->err = (buf && cap) ? 0 : KELP_ERR_ARG;
    for (const char *p = head; p && *p; p++) wput(w, *p);
}

void kelp_nmea_writer_str(kelp_nmea_writer *w, const char *field)
{
    wput(w, ',');
    for (const char *p = field; p && *p; p++) wput(w, *p);
}

void kelp_nmea_writer_hex(kelp_nmea_writer *w, const uint8_t *data, size_t n)
{
    static const char HEXL[] = "0123456789abcdef";
    wput(w, ',');
    for (size_t i = 0; i < n; i++) {
        wput(w, HEXL[data[i] >> 4]);
        wput(w, HEXL[data[i] & 15]);
    }
}

void kelp_nmea_writer_long(kelp_nmea_writer *w, long v)
{
    char tmp[24];
    size_t n = 0;
    unsigned long u = v < 0 ? 0UL - (unsigned long)v : (unsigned long)v;
    do { tmp[n++] = (char)('0' + u % 10); u /= 10; } while (u && n < sizeof tmp);
    wput(w, ',');
    if (v < 0) wput(w, '-');
    while (n) wput(w, tmp[--n]);
}

int kelp_nmea_writer_finish(kelp_nmea_writer *w, size_t *len)
{
    uint8_t cs = w->len > 1 ? kelp_nmea_checksum(w->buf + 1, w->len - 1) : 0;
    wput(w, '*');
    wput(w, HEXU[cs >> 4]);
    wput(w, HEXU[cs & 15]);
    if (w->buf && w->cap) w->buf[w->len < w->cap ? w->len : w->cap - 1] = '\0';
    if (len) *len = w->len;
    return w->err;
}
