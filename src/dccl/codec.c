/* kelp DCCL: encode and decode (Goby 1.1 DCCLCodec / DCCLMessage / DCCLMessageVar*).
 *
 * Bit layout: Goby appends each field with `bits <<= n; bits |= value` and writes
 * the bitset most significant byte first, so the body is right-aligned in
 * ceil(body_bits/8) bytes: the pad bits are the top bits of the first body byte.
 * We write fields MSB-first starting at bit offset pad, which gives the same bytes
 * without a big-integer shift. Array elements 1..n-1 come first, element 0 (the
 * "key") last.
 */
#include <math.h>
#include <string.h>
#include <kelp/util.h>

#include "dccl_int.h"

void kelp_dccl_codec_init(kelp_dccl_codec *cx, unsigned modem_id, const kelp_dccl_crypto *crypto,
                          const kelp_dccl_algs *algs)
{
    cx->modem_id = modem_id;
    cx->crypto = crypto;
    cx->algs = algs;
    kelp_diag_clear(&cx->diag);
}

/* ------------------------------------------------------------------ bits */
static const uint8_t LOWMASK[9] = {0x00, 0x01, 0x03, 0x07, 0x0f, 0x1f, 0x3f, 0x7f, 0xff};

/* The encoder writes into the caller's buffer: bytes at or past cap are dropped, but
 * `end` still records one past the last byte that received a set bit, which is all the
 * length (trailing zero bytes stripped) needs. */
typedef struct bitbuf {
    uint8_t *buf;
    size_t cap;
    size_t end;
} bitbuf;

static void or_byte(bitbuf *b, size_t i, uint8_t v)
{
    if (!v) return;
    if (i < b->cap) b->buf[i] |= v;
    if (i + 1u > b->end) b->end = i + 1u;
}

static void put_bits(bitbuf *buf, uint32_t *pos, uint64_t v, unsigned n)
{
    /* MSB-first; n <= 64 */
    uint32_t p = *pos;
    if (n > 64) n = 64;
    while (n) {
        unsigned room = 8u - (p & 7u);
        unsigned take = n < room ? n : room;
        unsigned shift;
        if (take > 8u) take = 8u; /* never: room <= 8 */
        shift = n - take;
        uint8_t chunk = (uint8_t)((v >> shift) & LOWMASK[take]);
        or_byte(buf, p >> 3, (uint8_t)(chunk << (room - take)));
        p += take;
        n -= take;
    }
    *pos = p;
}

static uint64_t get_bits(const uint8_t *buf, uint32_t pos, unsigned n)
{
    uint64_t v = 0;
    if (n > 64) n = 64;
    while (n) {
        unsigned room = 8u - (pos & 7u);
        unsigned take = n < room ? n : room;
        uint8_t b = buf[pos >> 3];
        if (take > 8u) take = 8u; /* never: room <= 8 */
        v = (take >= 8 ? v << 8 : v << take) | (uint64_t)((b >> (room - take)) & LOWMASK[take]);
        pos += take;
        n -= take;
    }
    return v;
}

/* A field wider than 64 bits: zero high part then the 64-bit value (Goby builds
 * the bitset from an unsigned long). */
static void put_wide(bitbuf *buf, uint32_t *pos, uint64_t v, unsigned n)
{
    if (n > 64) {
        *pos += n - 64; /* zeros: the buffer starts zeroed */
        n = 64;
    }
    put_bits(buf, pos, v, n);
}

static bool get_wide(const uint8_t *buf, uint32_t pos, unsigned n, uint64_t *v)
{
    if (n > 64) {
        unsigned k;
        for (k = 0; k < n - 64; k += 32) {
            unsigned t = (n - 64 - k) < 32 ? (n - 64 - k) : 32;
            if (get_bits(buf, pos + k, t)) return false; /* to_ulong() overflow */
        }
        pos += n - 64;
        n = 64;
    }
    *v = get_bits(buf, pos, n);
    return true;
}

/* ------------------------------------------------------------------ encode helpers */
static const kelp_dccl_val EMPTY_VAL = {KELP_DCCL_V_EMPTY, KELP_DCCL_MAX_DBL_PRECISION, 0, 0, false, false, 0, {0}};

static void val_copy(kelp_dccl_val *dst, const kelp_dccl_val *src)
{
    dst->kind = src->kind;
    dst->precision = src->precision;
    dst->d = src->d;
    dst->l = src->l;
    dst->b = src->b;
    dst->cut = src->cut;
    dst->len = src->len;
    memcpy(dst->s, src->s, (size_t)src->len + 1u);
}

static bool is_numeric_type(kelp_dccl_type t)
{
    return t == KELP_DCCL_T_INT || t == KELP_DCCL_T_FLOAT || t >= KELP_DCCL_T_HEAD_CCL_ID;
}

/* Goby's pre-encode: a value that converts to double becomes the double
 * unbiased_round(v, precision) (int/float fields; every header field with p 0). */
static void pre_encode(const kelp_dccl_field *f, const kelp_dccl_val *src, kelp_dccl_val *dst)
{
    double d;
    if (dst != src) val_copy(dst, src);
    if (is_numeric_type(f->type) && src->kind != KELP_DCCL_V_EMPTY && kelp_dccl_val_to_double(src, &d))
        kelp_dccl_val_set_double(dst, kelp_dccl_unbiased_round(d, f->precision), f->precision);
}

typedef struct enc_ctx {
    kelp_dccl_codec *cx;
    const kelp_dccl_msgdef *def;
    const kelp_dccl_val *in;
    kelp_time now;
    unsigned cur;          /* field being encoded */
    unsigned nref;         /* temps (cx->work.enc.ref) handed out for the current algorithm call */
} enc_ctx;

static void head_default(const kelp_dccl_codec *cx, const kelp_dccl_msgdef *def, unsigned h, const kelp_dccl_val *given,
                         kelp_time now, kelp_dccl_val *out);

/* A layout field's value as the caller gave it (header fields: see enc_ref). */
static const kelp_dccl_val *field_raw(const enc_ctx *e, unsigned field, unsigned element)
{
    const kelp_dccl_field *f = &e->def->fields[field];
    if (element >= f->array_length) element = 0;
    return &e->in[f->slot + element];
}

/* A referenced field encoded before (or being encoded) is seen after its
 * pre-encode rounding; a later one exactly as the caller gave it (a header field
 * with its default filled in). */
static const kelp_dccl_val *enc_ref(void *ctx, unsigned field, unsigned element)
{
    enc_ctx *e = ctx;
    kelp_dccl_val *t;
    if (field >= e->def->n_fields) return &EMPTY_VAL;
    if (field > e->cur && field >= KELP_DCCL_N_HEAD) return field_raw(e, field, element);
    t = &e->cx->work.enc.ref[e->nref++ % KELP_DCCL_MAX_ALG_REFS];
    if (field < KELP_DCCL_N_HEAD)
        head_default(e->cx, e->def, field, &e->in[e->def->fields[field].slot], e->now, t);
    else
        val_copy(t, field_raw(e, field, element));
    if (field <= e->cur) pre_encode(&e->def->fields[field], t, t);
    return t;
}

void dccl_apply_algs(const kelp_dccl_algs *algs, const kelp_dccl_algcall *calls, unsigned n_calls, kelp_dccl_val *v,
                     unsigned element, dccl_ref_fn ref, void *ref_ctx)
{
    unsigned i, r;
    for (i = 0; i < n_calls; i++) {
        const kelp_dccl_alg_entry *a;
        const kelp_dccl_val *refs[KELP_DCCL_MAX_ALG_REFS];
        if (v->kind == KELP_DCCL_V_EMPTY) return;
        if (!algs) return;
        a = kelp_dccl_algs_find(algs, calls[i].name);
        if (!a) continue; /* unknown algorithms are no-ops at run time */
        for (r = 0; r < calls[i].n_refs && r < KELP_DCCL_MAX_ALG_REFS; r++) {
            refs[r] = ref(ref_ctx, (unsigned)calls[i].refs[r], element);
            if (!refs[r]) refs[r] = &EMPTY_VAL;
        }
        a->fn(v, refs, r, a->user);
        if (ref == enc_ref) ((enc_ctx *)ref_ctx)->nref = 0;
    }
}

/* Value of one element after pre-encode and algorithms. Returns a pointer to
 * either the caller's value (nothing to change) or `work`. */
static const kelp_dccl_val *element_value(enc_ctx *e, unsigned fi, unsigned k, kelp_dccl_val *work)
{
    const kelp_dccl_field *f = &e->def->fields[fi];
    const kelp_dccl_val *src = field_raw(e, fi, k);
    if (f->n_algs == 0) return src;
    pre_encode(f, src, work);
    e->nref = 0;
    dccl_apply_algs(e->cx->algs, f->algs, f->n_algs, work, k, enc_ref, e);
    return work;
}

/* int/float code for a value that is already the post-algorithm value. The
 * pre-encode rounding is applied here for values that skipped element_value's
 * copy (no algorithms). */
static uint64_t float_code(const kelp_dccl_field *f, const kelp_dccl_val *v, bool rounded, bool delta, double key,
                           bool key_ok)
{
    double r, scale;
    if (v->kind == KELP_DCCL_V_EMPTY || !kelp_dccl_val_to_double(v, &r)) return 0;
    if (!rounded) r = kelp_dccl_unbiased_round(r, f->precision);
    if (isnan(r) || r < f->min || r > f->max) return 0;
    scale = dccl_pow10(f->precision);
    if (delta) {
        if (!key_ok) return 0;
        r = r + f->max_delta - key;
        if (r > 2 * f->max_delta || r < 0) return 0;
        r = r * scale;
    } else {
        r = (r - f->min) * scale;
    }
    if (!(r < 18446744073709551615.0)) return 0;
    return (uint64_t)r + 1u;
}

static uint64_t bool_code(const kelp_dccl_val *v)
{
    bool b;
    if (v->kind == KELP_DCCL_V_EMPTY || !kelp_dccl_val_to_bool(v, &b)) return 0;
    return b ? 2u : 1u;
}

static uint64_t enum_code(const kelp_dccl_field *f, const kelp_dccl_val *v, char buf[KELP_DCCL_MAX_STRLEN + 1])
{
    const char *s;
    size_t n;
    unsigned i;
    if (v->kind == KELP_DCCL_V_EMPTY) return 0;
    if (v->kind == KELP_DCCL_V_STRING) {
        s = v->s;
        n = v->len;
    } else {
        (void)kelp_dccl_val_to_str(v, buf, KELP_DCCL_MAX_STRLEN + 1, &n);
        if (n > KELP_DCCL_MAX_STRLEN) return 0;
        s = buf;
    }
    for (i = 0; i < f->n_enum; i++)
        if (strlen(f->enum_values[i]) == n && memcmp(f->enum_values[i], s, n) == 0) return i + 1u;
    return 0;
}

static int put_string(enc_ctx *e, const kelp_dccl_field *f, const kelp_dccl_val *v, bitbuf *buf, uint32_t *pos)
{
    char *sbuf = e->cx->work.enc.str;
    const char *s = "";
    size_t n = 0, i, m = f->type == KELP_DCCL_T_HEX ? f->num_bytes : f->max_length, high = 0;
    bool hex = f->type == KELP_DCCL_T_HEX;
    if (v->kind == KELP_DCCL_V_STRING) {
        s = v->s;
        n = v->len;
    } else if (v->kind != KELP_DCCL_V_EMPTY) {
        (void)kelp_dccl_val_to_str(v, sbuf, KELP_DCCL_MAX_STRLEN + 1, &n);
        if (n > KELP_DCCL_MAX_STRLEN) n = KELP_DCCL_MAX_STRLEN;
        s = sbuf;
    }
    if (hex) {
        if (n < 2 * m || (n == 2 * m && v->cut)) return kelp_fail(&e->cx->diag, KELP_ERR_PARSE, "hex value too short");
        if (n > 2 * m || v->cut) return kelp_fail(&e->cx->diag, KELP_ERR_PARSE, "hex value too long");
        for (i = 0; i < 2 * m; i++)
            if (kelp_util_hex_digit(s[i]) < 0) return kelp_fail(&e->cx->diag, KELP_ERR_PARSE, "hex value has a non-hex character");
    } else {
        /* Goby ORs each char sign-extended into the field: a byte >= 0x80 sets
         * every higher bit of the field, i.e. all earlier bytes become 0xff. */
        for (i = 0; i < m && i < n; i++)
            if ((uint8_t)s[i] & 0x80u) high = i;
    }
    {
        uint32_t p = *pos;
        unsigned sh = p & 7u;
        size_t b = p >> 3;
        for (i = 0; i < m; i++) {
            uint8_t byte;
            if (hex) byte = (uint8_t)(kelp_util_hex_digit(s[2 * i]) << 4 | kelp_util_hex_digit(s[2 * i + 1]));
            else if (i < high) byte = 0xff;
            else byte = i < n ? (uint8_t)s[i] : 0;
            or_byte(buf, b + i, (uint8_t)(byte >> sh));
            if (sh) or_byte(buf, b + i + 1, (uint8_t)(byte << (8u - sh)));
        }
        *pos = p + 8u * (uint32_t)m;
    }
    return KELP_OK;
}

/* Encode one element of a layout field at *pos. */
static int put_element(enc_ctx *e, unsigned fi, const kelp_dccl_val *v, bool rounded, bool delta, double key,
                       bool key_ok, bitbuf *buf, uint32_t *pos)
{
    const kelp_dccl_field *f = &e->def->fields[fi];
    switch (f->type) {
    case KELP_DCCL_T_INT:
    case KELP_DCCL_T_FLOAT:
        put_wide(buf, pos, float_code(f, v, rounded, delta, key, key_ok), delta ? f->delta_bits : f->bits);
        return KELP_OK;
    case KELP_DCCL_T_BOOL: put_bits(buf, pos, bool_code(v), 2); return KELP_OK;
    case KELP_DCCL_T_ENUM: put_bits(buf, pos, enum_code(f, v, e->cx->work.enc.str), f->bits); return KELP_OK;
    case KELP_DCCL_T_STRING:
    case KELP_DCCL_T_HEX: return put_string(e, f, v, buf, pos);
    default: return KELP_OK; /* static: no bits */
    }
}

static int encode_field(enc_ctx *e, unsigned fi, bitbuf *buf, uint32_t *pos)
{
    const kelp_dccl_field *f = &e->def->fields[fi];
    const kelp_dccl_val *kv;
    double key = 0;
    bool key_ok = false, rounded = f->n_algs > 0;
    unsigned k;
    uint32_t key_pos;
    if (f->type == KELP_DCCL_T_STATIC) return KELP_OK;
    e->cur = fi;
    kv = element_value(e, fi, 0, &e->cx->work.enc.key);
    if (f->has_delta) {
        key_ok = kv->kind != KELP_DCCL_V_EMPTY && kelp_dccl_val_to_double(kv, &key);
        if (key_ok && !rounded) key = kelp_dccl_unbiased_round(key, f->precision);
        if (key_ok && isnan(key)) key_ok = false;
    }
    key_pos = *pos + (uint32_t)(f->array_length - 1u) * f->delta_bits;
    for (k = 1; k < f->array_length; k++) {
        const kelp_dccl_val *v = element_value(e, fi, k, &e->cx->work.enc.elem);
        int rc = put_element(e, fi, v, rounded, f->has_delta, key, key_ok, buf, pos);
        if (rc) return rc;
    }
    *pos = key_pos;
    return put_element(e, fi, kv, rounded, false, 0, false, buf, pos);
}

/* header value after defaults (set_head_defaults) */
static void head_default(const kelp_dccl_codec *cx, const kelp_dccl_msgdef *def, unsigned h, const kelp_dccl_val *given,
                         kelp_time now, kelp_dccl_val *out)
{
    double d;
    bool empty = given->kind == KELP_DCCL_V_EMPTY;
    switch (h) {
    case KELP_DCCL_H_CCL_ID: kelp_dccl_val_set_long(out, KELP_DCCL_CCL_ID); return;
    case KELP_DCCL_H_ID:
        if (empty) { kelp_dccl_val_set_long(out, def->id); return; }
        break;
    case KELP_DCCL_H_TIME:
        if (empty || !kelp_dccl_val_to_double(given, &d)) {
            kelp_dccl_val_set_double(out, now, KELP_DCCL_MAX_DBL_PRECISION);
            return;
        }
        break;
    case KELP_DCCL_H_SRC:
        if (empty) { kelp_dccl_val_set_long(out, cx->modem_id); return; }
        break;
    case KELP_DCCL_H_DEST:
    case KELP_DCCL_H_UNUSED:
        if (empty) { kelp_dccl_val_set_long(out, 0); return; }
        break;
    default:
        if (empty) { kelp_dccl_val_set_bool(out, false); return; }
        break;
    }
    val_copy(out, given);
}

static double floor_mod(double a, double m)
{
    double r = fmod(a, m);
    if (r < 0) r += m;
    return r;
}

static uint64_t head_code(unsigned h, const kelp_dccl_val *v)
{
    int64_t l = 0;
    bool b = false;
    double d;
    switch (h) {
    case KELP_DCCL_H_TIME:
        /* unix_double2ptime(v).time_of_day(), in whole seconds */
        if (!kelp_dccl_val_to_double(v, &d) || isnan(d) || isinf(d)) return 0;
        d = floor_mod(floor(d + 0.5), 86400.0);
        return (uint64_t)d & 0x1ffffu;
    case KELP_DCCL_H_MULTIMESSAGE:
    case KELP_DCCL_H_BROADCAST:
        if (!kelp_dccl_val_to_bool(v, &b)) b = false;
        return b ? 1u : 0u;
    default:
        if (!kelp_dccl_val_to_long(v, &l)) l = 0;
        return (uint64_t)l;
    }
}

int kelp_dccl_encode(kelp_dccl_codec *cx, const kelp_dccl_msgdef *def, const kelp_dccl_val *in, size_t n_in, kelp_time now,
                     uint8_t *out, size_t cap, size_t *len)
{
    enc_ctx e;
    bitbuf msg;
    uint32_t pos = 0, nbody, pad;
    size_t blen, total;
    unsigned h, fi;
    kelp_diag_clear(&cx->diag);
    if (!def || !in || !len || n_in < def->n_slots) return kelp_fail(&cx->diag, KELP_ERR_ARG, "values array too short");
    nbody = (def->body_bits + 7u) / 8u;
    if (KELP_DCCL_HEAD_BYTES + nbody > KELP_DCCL_MAX_SIZE)
        return kelp_fail(&cx->diag, KELP_ERR_RANGE, "message larger than KELP_DCCL_MAX_SIZE");
    e.cx = cx;
    e.def = def;
    e.in = in;
    e.now = now;
    e.nref = 0;
    /* the message is built in out: bytes past cap (or all, measuring) are counted, not kept */
    msg.buf = out;
    msg.cap = out ? cap : 0;
    if (msg.cap > KELP_DCCL_HEAD_BYTES + nbody) msg.cap = KELP_DCCL_HEAD_BYTES + nbody;
    msg.end = 0;
    if (msg.cap) memset(out, 0, msg.cap);
    /* header: defaults, pre-encode (precision 0), header algorithms on a copy, wrap to width */
    for (h = 0; h < KELP_DCCL_N_HEAD; h++) {
        const kelp_dccl_field *f = &def->fields[h];
        kelp_dccl_val *w = &cx->work.enc.elem;
        uint64_t code;
        e.cur = h;
        head_default(cx, def, h, &in[f->slot], now, w);
        if (f->n_algs || h == KELP_DCCL_H_TIME) {
            pre_encode(f, w, w);
            e.nref = 0;
            dccl_apply_algs(cx->algs, f->algs, f->n_algs, w, 0, enc_ref, &e);
        } else {
            double d;
            /* pre-encode rounding then long(): same as unbiased_round + sci_round */
            bool flag = h == KELP_DCCL_H_MULTIMESSAGE || h == KELP_DCCL_H_BROADCAST;
            kelp_dccl_kind exact = flag ? KELP_DCCL_V_BOOL : KELP_DCCL_V_LONG; /* nothing to round */
            if (w->kind != exact && kelp_dccl_val_to_double(w, &d))
                kelp_dccl_val_set_double(w, kelp_dccl_unbiased_round(d, 0), 0);
        }
        code = head_code(h, w);
        put_bits(&msg, &pos, code & ((1u << f->bits) - 1u), f->bits);
    }
    /* body, right-aligned */
    pad = 8u * nbody - def->body_bits;
    pos = 8u * KELP_DCCL_HEAD_BYTES + pad;
    for (fi = KELP_DCCL_N_HEAD; fi < def->n_fields; fi++) {
        uint32_t start = pos;
        int rc = encode_field(&e, fi, &msg, &pos);
        if (rc) return rc;
        pos = start + def->fields[fi].total_bits;
    }
    /* strip trailing zero bytes of the body */
    blen = msg.end > KELP_DCCL_HEAD_BYTES ? msg.end - KELP_DCCL_HEAD_BYTES : 0;
    total = KELP_DCCL_HEAD_BYTES + blen;
    *len = total;
    if (!out) return KELP_OK;
    if (cap < total) return kelp_fail(&cx->diag, KELP_ERR_NOSPACE, "output buffer too small");
    if (cx->crypto && blen) {
        uint8_t iv[16];
        if (cx->crypto->iv(cx->crypto->user, out, KELP_DCCL_HEAD_BYTES, iv) ||
            cx->crypto->ctr(cx->crypto->user, iv, out + KELP_DCCL_HEAD_BYTES, blen))
            return kelp_fail(&cx->diag, KELP_ERR_CRYPTO, "encryption failed");
    }
    return KELP_OK;
}

/* ------------------------------------------------------------------ header */
double kelp_dccl_time_infer(unsigned tod, kelp_time now)
{
    double day = floor(now / 86400.0) * 86400.0;
    double tod_now = floor(now - day);
    if (fabs(tod_now - (double)tod) > 43200.0) day -= 86400.0;
    return day + (double)tod;
}

static uint64_t head48(const uint8_t *in, size_t n)
{
    uint64_t hv = 0;
    size_t i;
    for (i = 0; i < n && i < KELP_DCCL_HEAD_BYTES; i++) hv = (hv << 8) | in[i];
    return hv;
}

int kelp_dccl_peek_id(const uint8_t *in, size_t n, unsigned *id)
{
    if (!in || n == 0 || !id) return KELP_ERR_TRUNCATED;
    *id = (unsigned)((head48(in, n) >> 31) & 0x1ffu);
    return KELP_OK;
}

static void head_split(uint64_t hv, kelp_time now, kelp_dccl_header *h)
{
    h->unused = (unsigned)(hv & 3u);
    h->broadcast = (hv >> 2) & 1u;
    h->multimessage = (hv >> 3) & 1u;
    h->dest = (unsigned)((hv >> 4) & 31u);
    h->src = (unsigned)((hv >> 9) & 31u);
    h->time_of_day = (unsigned)((hv >> 14) & 0x1ffffu);
    h->id = (unsigned)((hv >> 31) & 0x1ffu);
    h->ccl_id = (unsigned)((hv >> 40) & 0xffu);
    h->time = kelp_dccl_time_infer(h->time_of_day, now);
}

int kelp_dccl_head_read(const uint8_t *in, size_t n, kelp_time now, kelp_dccl_header *h)
{
    if (!in || !h || n < KELP_DCCL_HEAD_BYTES) return KELP_ERR_TRUNCATED;
    head_split(head48(in, n), now, h);
    return KELP_OK;
}

void kelp_dccl_head_set_flags(uint8_t head[KELP_DCCL_HEAD_BYTES], bool multimessage, bool broadcast)
{
    head[5] = (uint8_t)((head[5] & ~0x0cu) | (multimessage ? 0x08u : 0u) | (broadcast ? 0x04u : 0u));
}

/* ------------------------------------------------------------------ decode */
static int decode_element(kelp_dccl_codec *cx, const kelp_dccl_field *f, const uint8_t *buf, uint32_t pos, bool delta,
                          const kelp_dccl_val *key, kelp_dccl_val *out)
{
    unsigned n = delta ? f->delta_bits : f->bits;
    uint64_t t;
    switch (f->type) {
    case KELP_DCCL_T_INT:
    case KELP_DCCL_T_FLOAT: {
        double d;
        if (!get_wide(buf, pos, n, &t)) return kelp_fail(&cx->diag, KELP_ERR_RANGE, "field value overflows 64 bits");
        if (t == 0) { kelp_dccl_val_clear(out); return KELP_OK; }
        d = (double)(t - 1u) / dccl_pow10(f->precision);
        if (delta) {
            double kd;
            if (key->kind == KELP_DCCL_V_EMPTY || !kelp_dccl_val_to_double(key, &kd)) kd = NAN;
            d = d - f->max_delta + kd;
        } else {
            d = d + f->min;
        }
        if (f->type == KELP_DCCL_T_FLOAT) {
            kelp_dccl_val_set_double(out, d, f->precision);
        } else if (isnan(d) || !(d > -9223372036854775808.0 && d < 9223372036854775808.0)) {
            kelp_dccl_val_clear(out); /* long(NaN): undefined in Goby */
        } else {
            kelp_dccl_val_set_long(out, (int64_t)d);
        }
        return KELP_OK;
    }
    case KELP_DCCL_T_BOOL:
        t = get_bits(buf, pos, 2);
        if (t == 0) kelp_dccl_val_clear(out);
        else kelp_dccl_val_set_bool(out, t != 1u);
        return KELP_OK;
    case KELP_DCCL_T_ENUM:
        t = get_bits(buf, pos, n);
        if (t == 0) { kelp_dccl_val_clear(out); return KELP_OK; }
        if (t - 1u >= f->n_enum) return kelp_fail(&cx->diag, KELP_ERR_RANGE, "enum value out of range");
        kelp_dccl_val_set_str(out, f->enum_values[t - 1u]);
        return KELP_OK;
    case KELP_DCCL_T_STRING: {
        unsigned i;
        kelp_dccl_val_clear(out);
        out->kind = KELP_DCCL_V_STRING;
        for (i = 0; i < f->max_length; i++) {
            char c = (char)get_bits(buf, pos + 8u * i, 8);
            if (c == '\0') break;
            out->s[i] = c;
        }
        out->s[i] = '\0';
        out->len = (uint16_t)i;
        if (i == 0) kelp_dccl_val_clear(out);
        return KELP_OK;
    }
    case KELP_DCCL_T_HEX: {
        static const char HEX[] = "0123456789abcdef";
        unsigned i;
        kelp_dccl_val_clear(out);
        out->kind = KELP_DCCL_V_STRING;
        for (i = 0; i < f->num_bytes; i++) {
            unsigned b = (unsigned)get_bits(buf, pos + 8u * i, 8);
            out->s[2 * i] = HEX[b >> 4];
            out->s[2 * i + 1] = HEX[b & 15u];
        }
        out->s[2u * f->num_bytes] = '\0';
        out->len = (uint16_t)(2u * f->num_bytes);
        return KELP_OK;
    }
    default:
        kelp_dccl_val_set_str(out, f->static_value ? f->static_value : "");
        return KELP_OK;
    }
}

int kelp_dccl_decode(kelp_dccl_codec *cx, const kelp_dccl_msgdef *def, const uint8_t *in, size_t n, kelp_time now,
                     kelp_dccl_val *out, size_t n_out)
{
    uint8_t *body = cx->work.dec.body;
    kelp_dccl_header h;
    size_t m, nhead, nbody, blen;
    uint32_t pos;
    unsigned fi;
    kelp_diag_clear(&cx->diag);
    if (!def || !out || n_out < def->n_slots) return kelp_fail(&cx->diag, KELP_ERR_ARG, "values array too short");
    if (!in || n == 0) return kelp_fail(&cx->diag, KELP_ERR_TRUNCATED, "empty message");
    nbody = (def->body_bits + 7u) / 8u;
    if (nbody > sizeof cx->work.dec.body) return kelp_fail(&cx->diag, KELP_ERR_RANGE, "message larger than KELP_DCCL_MAX_SIZE");
    /* Goby strips every trailing zero byte of the received message (header included) */
    m = n;
    while (m > 0 && in[m - 1] == 0) m--;
    nhead = m < KELP_DCCL_HEAD_BYTES ? m : KELP_DCCL_HEAD_BYTES;
    blen = m > KELP_DCCL_HEAD_BYTES ? m - KELP_DCCL_HEAD_BYTES : 0;
    if (blen > nbody) blen = nbody; /* the decrypted body is cut to ceil(body_bits/8) */
    memset(body, 0, nbody);
    if (blen) {
        memcpy(body, in + KELP_DCCL_HEAD_BYTES, blen);
        if (cx->crypto) {
            uint8_t iv[16];
            if (cx->crypto->iv(cx->crypto->user, in, nhead, iv) || cx->crypto->ctr(cx->crypto->user, iv, body, blen))
                return kelp_fail(&cx->diag, KELP_ERR_CRYPTO, "decryption failed");
        }
    }
    /* header: 48-bit integer from the (maybe short) header bytes, right-aligned */
    head_split(nhead ? head48(in, nhead) : 0, now, &h);
    kelp_dccl_val_set_long(&out[def->fields[KELP_DCCL_H_CCL_ID].slot], h.ccl_id);
    kelp_dccl_val_set_long(&out[def->fields[KELP_DCCL_H_ID].slot], h.id);
    kelp_dccl_val_set_double(&out[def->fields[KELP_DCCL_H_TIME].slot], h.time, KELP_DCCL_MAX_DBL_PRECISION);
    kelp_dccl_val_set_long(&out[def->fields[KELP_DCCL_H_SRC].slot], h.src);
    kelp_dccl_val_set_long(&out[def->fields[KELP_DCCL_H_DEST].slot], h.dest);
    kelp_dccl_val_set_bool(&out[def->fields[KELP_DCCL_H_MULTIMESSAGE].slot], h.multimessage);
    kelp_dccl_val_set_bool(&out[def->fields[KELP_DCCL_H_BROADCAST].slot], h.broadcast);
    kelp_dccl_val_set_long(&out[def->fields[KELP_DCCL_H_UNUSED].slot], h.unused);
    pos = (uint32_t)(8u * nbody - def->body_bits);
    for (fi = KELP_DCCL_N_HEAD; fi < def->n_fields; fi++) {
        const kelp_dccl_field *f = &def->fields[fi];
        kelp_dccl_val *vals = &out[f->slot];
        uint32_t key_pos = pos + (uint32_t)(f->array_length - 1u) * f->delta_bits;
        unsigned k;
        int rc = decode_element(cx, f, body, key_pos, false, NULL, &vals[0]);
        if (rc) return rc;
        for (k = 1; k < f->array_length; k++) {
            rc = decode_element(cx, f, body, pos + (uint32_t)(k - 1u) * f->delta_bits, f->has_delta, &vals[0], &vals[k]);
            if (rc) return rc;
        }
        pos += f->total_bits;
    }
    return KELP_OK;
}
