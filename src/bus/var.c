/* kelp bus: the kelp.var_t and kelp.sync_req_t wire layouts, by hand.
 *
 * LCM 1.3.1's generated decoder trusts string lengths from the wire (it mallocs the length
 * before checking it, and a negative length reaches memcpy), so one malformed datagram can
 * crash a subscriber. This decoder checks every length against the remaining bytes and
 * against kelp's limits before touching memory, and needs no heap. Layout (big-endian):
 *   u64 fingerprint | f64 time | str name | str source | str source_aux | str community | i8 kind |
 *   f64 dval | str sval | i32 nbytes | nbytes bytes | i8 flags
 * where str = i32 length-including-NUL, bytes, NUL.
 */
#include <string.h>
#include <kelp/bus.h>
#include <kelp/udpm.h>
#include "bus_int.h"

typedef struct wr {
    uint8_t *p;
    size_t cap, n;
    int err;
} wr;

static void put_u8(wr *w, uint8_t v)
{
    if (w->err) return;
    if (w->n + 1 > w->cap) { w->err = KELP_ERR_NOSPACE; return; }
    w->p[w->n++] = v;
}

static void put_u32(wr *w, uint32_t v)
{
    for (int i = 3; i >= 0; i--) put_u8(w, (uint8_t)(v >> (8 * i)));
}

static void put_u64(wr *w, uint64_t v)
{
    for (int i = 7; i >= 0; i--) put_u8(w, (uint8_t)(v >> (8 * i)));
}

static void put_f64(wr *w, double d)
{
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    put_u64(w, u);
}

static void put_bytes(wr *w, const void *b, size_t n)
{
    if (w->err) return;
    if (n > w->cap - w->n) { w->err = KELP_ERR_NOSPACE; return; }
    if (n) memcpy(w->p + w->n, b, n);
    w->n += n;
}

static void put_str(wr *w, const char *s, size_t len)
{
    put_u32(w, (uint32_t)(len + 1));
    put_bytes(w, s, len);
    put_u8(w, 0);
}

typedef struct rd {
    const uint8_t *p;
    size_t len, off;
    int err;
} rd;

static uint64_t get_uN(rd *r, int nbytes)
{
    uint64_t v = 0;
    if (r->err) return 0;
    if ((size_t)nbytes > r->len - r->off) { r->err = KELP_ERR_TRUNCATED; return 0; }
    for (int i = 0; i < nbytes; i++) v = (v << 8) | r->p[r->off++];
    return v;
}

static double get_f64(rd *r)
{
    uint64_t u = get_uN(r, 8);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

/* A string: the length includes the NUL; it must fit cap (with NUL), lie within the
 * datagram, end in NUL and hold no interior NUL. */
static size_t get_str(rd *r, char *dst, size_t cap)
{
    uint32_t n = (uint32_t)get_uN(r, 4);
    if (r->err) return 0;
    if (n == 0 || n > 0x7fffffffu) { r->err = KELP_ERR_PARSE; return 0; }
    if (n > r->len - r->off) { r->err = KELP_ERR_TRUNCATED; return 0; }
    if (n > cap) { r->err = KELP_ERR_RANGE; return 0; }
    const uint8_t *s = r->p + r->off;
    if (s[n - 1] != 0 || memchr(s, 0, n - 1) != NULL) { r->err = KELP_ERR_PARSE; return 0; }
    memcpy(dst, s, n);
    r->off += n;
    return n - 1;
}

static size_t str_len_bounded(const char *s, size_t cap)
{
    const char *z = memchr(s, 0, cap);
    return z ? (size_t)(z - s) : cap;
}

size_t kelp_var_encoded_size(const kelp_var *v)
{
    size_t n = 8 + 8;
    n += 4 + str_len_bounded(v->name, KELP_MAX_NAME) + 1;
    n += 4 + str_len_bounded(v->source, KELP_MAX_NAME) + 1;
    n += 4 + str_len_bounded(v->source_aux, KELP_MAX_NAME) + 1;
    n += 4 + str_len_bounded(v->community, KELP_MAX_NAME) + 1;
    n += 1 + 8;
    n += 4 + (v->kind == KELP_VAR_STRING ? v->slen : 0) + 1;
    n += 4 + (v->kind == KELP_VAR_BINARY ? v->slen : 0);
    n += 1;
    return n;
}

int kelp_var_encode_parts(double time, const char *name, const char *source, const char *source_aux,
                          const char *community, kelp_var_kind kind, double dval, const char *val, size_t vlen,
                          uint8_t flags, uint8_t *buf, size_t cap, size_t *len)
{
    if (!source_aux) source_aux = "";
    if (!name || !source || !community || !len || (!buf && cap) || (!val && vlen)) return KELP_ERR_ARG;
    if (kind != KELP_VAR_DOUBLE && kind != KELP_VAR_STRING && kind != KELP_VAR_BINARY) return KELP_ERR_ARG;
    if (vlen > KELP_MAX_SVAL) return KELP_ERR_ARG;
    if (str_len_bounded(name, KELP_MAX_NAME) == KELP_MAX_NAME ||
        str_len_bounded(source, KELP_MAX_NAME) == KELP_MAX_NAME ||
        str_len_bounded(source_aux, KELP_MAX_NAME) == KELP_MAX_NAME ||
        str_len_bounded(community, KELP_MAX_NAME) == KELP_MAX_NAME)
        return KELP_ERR_ARG;
    /* A string value may not hold a NUL: LCM strings cannot carry one. */
    if (kind == KELP_VAR_STRING && vlen && memchr(val, 0, vlen) != NULL) return KELP_ERR_ARG;
    wr w = { buf, cap, 0, 0 };
    put_u64(&w, KELP_VAR_FINGERPRINT);
    put_f64(&w, time);
    put_str(&w, name, strlen(name));
    put_str(&w, source, strlen(source));
    put_str(&w, source_aux, strlen(source_aux));
    put_str(&w, community, strlen(community));
    put_u8(&w, (uint8_t)kind);
    put_f64(&w, kind == KELP_VAR_DOUBLE ? dval : 0.0);
    if (kind == KELP_VAR_STRING) put_str(&w, val, vlen);
    else put_str(&w, "", 0);
    if (kind == KELP_VAR_BINARY) {
        put_u32(&w, (uint32_t)vlen);
        put_bytes(&w, val, vlen);
    } else {
        put_u32(&w, 0);
    }
    put_u8(&w, flags);
    if (w.err) return w.err;
    *len = w.n;
    return KELP_OK;
}

int kelp_var_encode(const kelp_var *v, uint8_t *buf, size_t cap, size_t *len)
{
    if (!v) return KELP_ERR_ARG;
    if (v->slen > KELP_MAX_SVAL) return KELP_ERR_ARG;
    return kelp_var_encode_parts(v->time, v->name, v->source, v->source_aux, v->community, v->kind, v->dval,
                                 v->kind == KELP_VAR_DOUBLE ? NULL : v->sval,
                                 v->kind == KELP_VAR_DOUBLE ? 0 : v->slen, v->flags, buf, cap, len);
}

int kelp_var_decode(const uint8_t *buf, size_t len, kelp_var *out)
{
    if (!out) return KELP_ERR_ARG;
    if (!buf) return len ? KELP_ERR_ARG : KELP_ERR_TRUNCATED;
    rd r = { buf, len, 0, 0 };
    uint64_t fp = get_uN(&r, 8);
    if (r.err) return r.err;
    if (fp != KELP_VAR_FINGERPRINT) return KELP_ERR_DEFMISMATCH;
    out->time = get_f64(&r);
    get_str(&r, out->name, sizeof out->name);
    get_str(&r, out->source, sizeof out->source);
    get_str(&r, out->source_aux, sizeof out->source_aux);
    get_str(&r, out->community, sizeof out->community);
    int8_t kind = (int8_t)get_uN(&r, 1);
    out->dval = get_f64(&r);
    size_t slen = get_str(&r, out->sval, sizeof out->sval);
    if (r.err) return r.err;
    if (kind < KELP_VAR_DOUBLE || kind > KELP_VAR_BINARY) return KELP_ERR_PARSE;
    out->kind = (kelp_var_kind)kind;
    uint32_t nb = (uint32_t)get_uN(&r, 4);
    if (r.err) return r.err;
    if (nb > 0x7fffffffu) return KELP_ERR_PARSE;     /* negative int32 on the wire */
    if (nb > len - r.off) return KELP_ERR_TRUNCATED;
    if (nb > KELP_MAX_SVAL) return KELP_ERR_RANGE;
    if (out->kind == KELP_VAR_BINARY) {
        if (slen != 0) return KELP_ERR_PARSE;
        memcpy(out->sval, buf + r.off, nb);
        out->sval[nb] = 0;
        out->slen = nb;
    } else {
        if (nb != 0) return KELP_ERR_PARSE;
        out->slen = out->kind == KELP_VAR_STRING ? slen : 0;
        if (out->kind == KELP_VAR_DOUBLE) out->sval[0] = 0;
    }
    r.off += nb;
    out->flags = (uint8_t)get_uN(&r, 1);
    if (r.err) return r.err;
    if (!kelp_udpm_padding_only(buf, r.off, len)) return KELP_ERR_PARSE; /* trailing bytes, not padding */
    if (out->name[0] == 0) return KELP_ERR_PARSE;
    return KELP_OK;
}

static void sync_req_head(wr *w, double time, const char *requester, const char *community, const char *reply_channel,
                          uint16_t npatterns)
{
    put_u64(w, KELP_SYNC_REQ_FINGERPRINT);
    put_f64(w, time);
    put_str(w, requester, str_len_bounded(requester, KELP_MAX_NAME - 1));
    put_str(w, community, str_len_bounded(community, KELP_MAX_NAME - 1));
    put_str(w, reply_channel, str_len_bounded(reply_channel, KELP_MAX_NAME - 1));
    put_u8(w, (uint8_t)(npatterns >> 8));
    put_u8(w, (uint8_t)npatterns);
}

int kelp_bus_sync_req_encode(const kelp_sync_req *q, uint8_t *buf, size_t cap, size_t *len)
{
    if (!q || !len || q->npatterns > KELP_MAX_SYNC_PATTERNS) return KELP_ERR_ARG;
    wr w = { buf, cap, 0, 0 };
    sync_req_head(&w, q->time, q->requester, q->community, q->reply_channel, q->npatterns);
    for (uint16_t i = 0; i < q->npatterns; i++)
        put_str(&w, q->patterns[i], str_len_bounded(q->patterns[i], KELP_MAX_NAME - 1));
    if (w.err) return w.err;
    *len = w.n;
    return KELP_OK;
}

int kelp_sync_req_encode_one(double time, const char *requester, const char *community, const char *reply_channel,
                             const char *pattern, uint8_t *buf, size_t cap, size_t *len)
{
    wr w = { buf, cap, 0, 0 };
    sync_req_head(&w, time, requester, community, reply_channel, 1);
    put_str(&w, pattern, str_len_bounded(pattern, KELP_MAX_NAME - 1));
    if (w.err) return w.err;
    *len = w.n;
    return KELP_OK;
}

int kelp_bus_sync_req_decode(const uint8_t *buf, size_t len, kelp_sync_req *out)
{
    if (!out) return KELP_ERR_ARG;
    if (!buf) return len ? KELP_ERR_ARG : KELP_ERR_TRUNCATED;
    rd r = { buf, len, 0, 0 };
    uint64_t fp = get_uN(&r, 8);
    if (r.err) return r.err;
    if (fp != KELP_SYNC_REQ_FINGERPRINT) return KELP_ERR_DEFMISMATCH;
    out->time = get_f64(&r);
    get_str(&r, out->requester, sizeof out->requester);
    get_str(&r, out->community, sizeof out->community);
    get_str(&r, out->reply_channel, sizeof out->reply_channel);
    int16_t n = (int16_t)get_uN(&r, 2);
    if (r.err) return r.err;
    if (n < 0) return KELP_ERR_PARSE;
    if (n > KELP_MAX_SYNC_PATTERNS) return KELP_ERR_RANGE;
    out->npatterns = (uint16_t)n;
    for (int i = 0; i < n; i++) get_str(&r, out->patterns[i], sizeof out->patterns[i]);
    if (r.err) return r.err;
    if (!kelp_udpm_padding_only(buf, r.off, len)) return KELP_ERR_PARSE;
    if (out->reply_channel[0] == 0) return KELP_ERR_PARSE;
    return KELP_OK;
}

int kelp_bus_name_set(char dst[KELP_MAX_NAME], const char *s)
{
    if (!s) return KELP_ERR_ARG;
    size_t n = strlen(s);
    if (n >= KELP_MAX_NAME) return KELP_ERR_RANGE;
    memcpy(dst, s, n + 1);
    return KELP_OK;
}

bool kelp_bus_match(const char *pat, const char *name)
{
    /* Iterative glob with single-star backtracking: O(len(pat) * len(name)) worst case. */
    const char *star = NULL, *resume = NULL;
    while (*name) {
        if (*pat == '*') {
            star = pat++;
            resume = name;
        } else if (*pat == '?' || *pat == *name) {
            pat++;
            name++;
        } else if (star) {
            pat = star + 1;
            name = ++resume;
        } else {
            return false;
        }
    }
    while (*pat == '*') pat++;
    return *pat == 0;
}
