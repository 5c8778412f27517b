/* kelp acomms: Google protobuf TextFormat for the ACOMMS_* variables (core, no allocation).
 *
 * Printing follows protobuf's single-line TextFormat printer (what Goby's serialize_for_moos
 * uses): "name: value" separated by single spaces, sub-messages "name { ... }", fields in
 * field-number order, only the fields that are set, enums by name, strings and bytes in double
 * quotes with CEscape (\n \r \t \" \' \\ and every other non-printable byte as three octal
 * digits).  Doubles print with the shortest of %.15g / %.17g that reads back exactly
 * (protobuf's SimpleDtoa).
 *
 * Parsing accepts what protobuf's TextFormat parser accepts for these messages: ':' optional
 * before a sub-message, '{ }' or '< >', optional ',' or ';' separators, '#' comments, adjacent
 * string literals concatenated, single or double quotes, C escapes (octal, \x hex). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/mission.h>
#include <kelp/util.h>

/* ------------------------------------------------------------------ writer */

typedef struct tw {
    char *buf;
    size_t cap, len;
    int err;
} tw;

static void tw_init(tw *w, char *buf, size_t cap)
{
    w->buf = buf;
    w->cap = cap;
    w->len = 0;
    w->err = 0;
    if (cap) buf[0] = '\0';
}

static void tw_putc(tw *w, char c)
{
    if (w->len + 1 < w->cap) {
        w->buf[w->len++] = c;
        w->buf[w->len] = '\0';
    } else {
        w->err = KELP_ERR_NOSPACE;
    }
}

static void tw_puts(tw *w, const char *s)
{
    while (*s) tw_putc(w, *s++);
}

/* a separating space unless at the start or right after "{ " */
static void tw_sep(tw *w)
{
    if (w->len && w->buf[w->len - 1] != ' ') tw_putc(w, ' ');
}

static void tw_field(tw *w, const char *name)
{
    tw_sep(w);
    tw_puts(w, name);
    tw_puts(w, ": ");
}

static void tw_long(tw *w, long v)
{
    char tmp[24];
    kelp_util_snprintf(tmp, sizeof tmp, "%ld", v);
    tw_puts(w, tmp);
}

static void tw_double(tw *w, double v)
{
    char tmp[40];
    if (isnan(v)) {
        tw_puts(w, "nan");
        return;
    }
    if (isinf(v)) {
        tw_puts(w, v < 0 ? "-inf" : "inf");
        return;
    }
    kelp_util_snprintf(tmp, sizeof tmp, "%.15g", v);
    double back = 0;
    if (kelp_util_parse_double(tmp, strlen(tmp), &back) != KELP_OK || back != v) kelp_util_snprintf(tmp, sizeof tmp, "%.17g", v);
    tw_puts(w, tmp);
}

static void tw_bytes(tw *w, const uint8_t *d, size_t n)
{
    tw_putc(w, '"');
    for (size_t i = 0; i < n; i++) {
        uint8_t c = d[i];
        switch (c) {
        case '\n': tw_puts(w, "\\n"); break;
        case '\r': tw_puts(w, "\\r"); break;
        case '\t': tw_puts(w, "\\t"); break;
        case '"': tw_puts(w, "\\\""); break;
        case '\'': tw_puts(w, "\\'"); break;
        case '\\': tw_puts(w, "\\\\"); break;
        default:
            if (c < 0x20 || c >= 0x7f) {
                tw_putc(w, '\\');
                tw_putc(w, (char)('0' + ((c >> 6) & 7)));
                tw_putc(w, (char)('0' + ((c >> 3) & 7)));
                tw_putc(w, (char)('0' + (c & 7)));
            } else {
                tw_putc(w, (char)c);
            }
        }
    }
    tw_putc(w, '"');
}

static void tw_open(tw *w, const char *name)
{
    tw_sep(w);
    tw_puts(w, name);
    tw_puts(w, " { ");
}

static void tw_close(tw *w)
{
    tw_sep(w);
    tw_putc(w, '}');
}

static int tw_finish(tw *w, size_t *len)
{
    if (len) *len = w->len;
    return w->err;
}

/* ------------------------------------------------------------------ time */

static const char MONTHS[12][4] = { "Jan", "Feb", "Mar", "Apr", "May", "Jun",
                                    "Jul", "Aug", "Sep", "Oct", "Nov", "Dec" };

int kelp_acomms_time_text(kelp_time t, char *buf, size_t cap)
{
    int y, mo, d, h, mi, s;
    const int64_t unix_us = (int64_t)llround(t * 1e6); /* boost ptime: whole microseconds */
    kelp_mmdriver_civil(t, &y, &mo, &d, &h, &mi, &s);
    int64_t frac = unix_us % 1000000;
    if (frac < 0) frac += 1000000;
    int n;
    if (frac)
        n = kelp_util_snprintf(buf, cap, "%04d-%s-%02d %02d:%02d:%02d.%06ld", y, MONTHS[(mo - 1) % 12], d, h, mi, s, (long)frac);
    else
        n = kelp_util_snprintf(buf, cap, "%04d-%s-%02d %02d:%02d:%02d", y, MONTHS[(mo - 1) % 12], d, h, mi, s);
    return (n < 0 || (size_t)n >= cap) ? KELP_ERR_NOSPACE : KELP_OK;
}

static void tw_base(tw *w, int src, int dest, bool has_time, kelp_time time)
{
    tw_open(w, "base");
    tw_field(w, "src");
    tw_long(w, src);
    tw_field(w, "dest");
    tw_long(w, dest);
    if (has_time) {
        char t[48];
        if (kelp_acomms_time_text(time, t, sizeof t) == KELP_OK) {
            tw_field(w, "time");
            tw_bytes(w, (const uint8_t *)t, strlen(t));
        }
    }
    tw_close(w);
}

static const char *queue_type_name(uint8_t t)
{
    return t == KELP_QUEUE_CCL ? "QUEUE_CCL" : "QUEUE_DCCL";
}

static void tw_key(tw *w, const char *name, kelp_queue_key key)
{
    tw_open(w, name);
    tw_field(w, "type");
    tw_puts(w, queue_type_name(key.type));
    tw_field(w, "id");
    tw_long(w, (long)key.id);
    tw_close(w);
}

static void tw_data(tw *w, const kelp_acomms_msg *m)
{
    tw_base(w, m->src, m->dest, m->has_time, m->time);
    tw_field(w, "ack_requested");
    tw_puts(w, m->ack_requested ? "true" : "false");
    tw_field(w, "data");
    tw_bytes(w, m->data, m->len);
    tw_field(w, "frame");
    tw_long(w, (long)m->frame);
    if (m->key.type) tw_key(w, "queue_key", m->key);
}

int kelp_acomms_print_data(const kelp_acomms_msg *m, char *buf, size_t cap, size_t *len)
{
    tw w;
    if (!m || !buf || !cap) return KELP_ERR_ARG;
    tw_init(&w, buf, cap);
    tw_data(&w, m);
    return tw_finish(&w, len);
}

int kelp_acomms_print_data_bare(const kelp_acomms_msg *m, char *buf, size_t cap, size_t *len)
{
    tw w;
    if (!m || !buf || !cap) return KELP_ERR_ARG;
    tw_init(&w, buf, cap);
    tw_base(&w, m->src, m->dest, m->has_time, m->time);
    tw_field(&w, "data");
    tw_bytes(&w, m->data, m->len);
    return tw_finish(&w, len);
}

int kelp_acomms_print_ack(int src, int dest, uint32_t frame, kelp_time time, const kelp_acomms_msg *orig, char *buf,
                          size_t cap, size_t *len)
{
    tw w;
    if (!orig || !buf || !cap) return KELP_ERR_ARG;
    tw_init(&w, buf, cap);
    tw_base(&w, src, dest, true, time);
    tw_field(&w, "frame");
    tw_long(&w, (long)frame);
    tw_open(&w, "orig_msg");
    tw_data(&w, orig);
    tw_close(&w);
    return tw_finish(&w, len);
}

int kelp_acomms_print_expire(const kelp_acomms_msg *orig, char *buf, size_t cap, size_t *len)
{
    tw w;
    if (!orig || !buf || !cap) return KELP_ERR_ARG;
    tw_init(&w, buf, cap);
    tw_open(&w, "orig_msg");
    tw_data(&w, orig);
    tw_close(&w);
    return tw_finish(&w, len);
}

int kelp_acomms_print_qsize(kelp_queue_key key, uint32_t size, char *buf, size_t cap, size_t *len)
{
    tw w;
    if (!buf || !cap) return KELP_ERR_ARG;
    tw_init(&w, buf, cap);
    tw_key(&w, "key", key);
    tw_field(&w, "size");
    tw_long(&w, (long)size);
    return tw_finish(&w, len);
}

static const char *ranging_name(kelp_ranging_type t)
{
    switch (t) {
    case KELP_RANGING_ONE_WAY_SYNCHRONOUS: return "MODEM_ONE_WAY_SYNCHRONOUS";
    case KELP_RANGING_REMUS_LBL: return "REMUS_LBL_RANGING";
    case KELP_RANGING_TWO_WAY_PING:
    default: return "MODEM_TWO_WAY_PING";
    }
}

int kelp_acomms_print_range(int src, int dest, kelp_time time, kelp_ranging_type type, const double *tt, unsigned n_tt,
                            char *buf, size_t cap, size_t *len)
{
    tw w;
    if (!buf || !cap || (n_tt && !tt)) return KELP_ERR_ARG;
    tw_init(&w, buf, cap);
    tw_base(&w, src, dest, true, time);
    for (unsigned i = 0; i < n_tt; i++) {
        tw_field(&w, "one_way_travel_time");
        tw_double(&w, tt[i]);
    }
    tw_field(&w, "type");
    tw_puts(&w, ranging_name(type));
    return tw_finish(&w, len);
}

/* ------------------------------------------------------------------ tokenizer */

typedef enum tk_kind { TK_END = 0, TK_IDENT, TK_NUMBER, TK_STRING, TK_COLON, TK_OPEN, TK_CLOSE, TK_SEP, TK_BAD } tk_kind;

typedef struct tk {
    tk_kind kind;
    const char *s;
    size_t n;
    char close; /* '}' or '>' for TK_OPEN; for TK_STRING its quote, or 0 if the input ended inside it */
} tk;

typedef struct lexer {
    const char *p, *end;
} lexer;

static bool is_ident_start(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}

static bool is_ident(char c)
{
    return is_ident_start(c) || (c >= '0' && c <= '9');
}

static tk lex(lexer *lx)
{
    tk t = { TK_END, NULL, 0, 0 };
    for (;;) {
        while (lx->p < lx->end && (*lx->p == ' ' || *lx->p == '\t' || *lx->p == '\n' || *lx->p == '\r')) lx->p++;
        if (lx->p < lx->end && *lx->p == '#') {
            while (lx->p < lx->end && *lx->p != '\n') lx->p++;
            continue;
        }
        break;
    }
    if (lx->p >= lx->end) return t;
    const char *s = lx->p;
    char c = *s;
    t.s = s;
    if (c == ':') {
        t.kind = TK_COLON;
        lx->p++;
    } else if (c == '{' || c == '<') {
        t.kind = TK_OPEN;
        t.close = c == '{' ? '}' : '>';
        lx->p++;
    } else if (c == '}' || c == '>') {
        t.kind = TK_CLOSE;
        t.close = c;
        lx->p++;
    } else if (c == ',' || c == ';') {
        t.kind = TK_SEP;
        lx->p++;
    } else if (c == '"' || c == '\'') {
        /* one literal (adjacent literals are joined by the caller) */
        const char *q = s + 1;
        while (q < lx->end && *q != c) {
            if (*q == '\\' && q + 1 < lx->end) q++;
            if (*q == '\n') break;
            q++;
        }
        if (q >= lx->end) {
            /* the input ends inside the literal: protobuf's tokenizer reports the error but
             * keeps the literal (to the end) and its TextFormat parser still sets the field,
             * which Goby's parse_for_moos uses (e.g. the seed's uTimerScript value
             * data: "\002\002\003\004\" of example 1 gives 02 02 03 04 22) */
            t.kind = TK_STRING;
            t.close = 0;
            lx->p = lx->end;
            t.n = (size_t)(lx->p - s);
            return t;
        }
        if (*q != c) {
            t.kind = TK_BAD;
            lx->p = lx->end;
            return t;
        }
        t.kind = TK_STRING;
        t.close = c;
        lx->p = q + 1;
    } else if (is_ident_start(c)) {
        const char *q = s;
        while (q < lx->end && is_ident(*q)) q++;
        t.kind = TK_IDENT;
        lx->p = q;
    } else if ((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.') {
        const char *q = s + 1;
        while (q < lx->end && (is_ident(*q) || *q == '.' || ((*q == '-' || *q == '+') && (q[-1] == 'e' || q[-1] == 'E'))))
            q++;
        t.kind = TK_NUMBER;
        lx->p = q;
    } else {
        t.kind = TK_BAD;
        lx->p++;
    }
    t.n = (size_t)(lx->p - s);
    return t;
}

static int hexval(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

/* unescape one quoted literal (with its quotes; without the closing one if !closed) and append
 * to out; KELP_ERR_NOSPACE if full. out NULL: only check and count (the value is not used). */
static int unescape(const char *s, size_t n, bool closed, uint8_t *out, size_t cap, size_t *len)
{
    size_t i = 1, o = *len;
    if (closed) n--; /* closing quote */
    while (i < n) {
        uint8_t c = (uint8_t)s[i++];
        if (c == '\\' && i < n) {
            char e = s[i++];
            switch (e) {
            case 'n': c = '\n'; break;
            case 'r': c = '\r'; break;
            case 't': c = '\t'; break;
            case 'a': c = '\a'; break;
            case 'b': c = '\b'; break;
            case 'f': c = '\f'; break;
            case 'v': c = '\v'; break;
            case '?': c = '?'; break;
            case '\\': c = '\\'; break;
            case '\'': c = '\''; break;
            case '"': c = '"'; break;
            case 'x':
            case 'X': {
                int v = 0, k = 0;
                while (k < 2 && i < n && hexval(s[i]) >= 0) v = v * 16 + hexval(s[i++]), k++;
                if (!k) return KELP_ERR_PARSE;
                c = (uint8_t)v;
                break;
            }
            default:
                if (e >= '0' && e <= '7') {
                    int v = e - '0', k = 1;
                    while (k < 3 && i < n && s[i] >= '0' && s[i] <= '7') v = v * 8 + (s[i++] - '0'), k++;
                    if (v > 255) return KELP_ERR_PARSE;
                    c = (uint8_t)v;
                } else {
                    return KELP_ERR_PARSE;
                }
            }
        }
        if (o >= cap) return KELP_ERR_NOSPACE;
        if (out) out[o] = c;
        o++;
    }
    *len = o;
    return KELP_OK;
}

/* ------------------------------------------------------------------ generic walker */

#define TF_MAX_DEPTH 4

typedef struct tf_val {
    tk_kind kind;       /* TK_IDENT, TK_NUMBER or TK_STRING */
    const char *s;      /* first token */
    size_t n;
    uint8_t *bytes;     /* unescaped string (TK_STRING) */
    size_t blen;
} tf_val;

typedef struct tf_walk {
    /* callbacks return 0 or a negative code recorded in d (kelp_fail) */
    int (*field)(void *ctx, const char *const *path, unsigned depth, const char *name, size_t nlen, const tf_val *v);
    int (*open)(void *ctx, const char *const *path, unsigned depth, const char *name, size_t nlen);
    int (*close)(void *ctx, unsigned depth);
    void *ctx;
    kelp_diag *d;           /* the caller's record (may be NULL) */
    const char *too_long;   /* reason of a string longer than the string buffer */
} tf_walk;

static bool tok_is(const char *s, size_t n, const char *z)
{
    return strlen(z) == n && memcmp(s, z, n) == 0;
}

static int walk(tf_walk *wk, const char *text, size_t len, uint8_t *sbuf, size_t scap)
{
    lexer lx = { text, text + len };
    char names[TF_MAX_DEPTH][40];
    const char *path[TF_MAX_DEPTH];
    char closers[TF_MAX_DEPTH];
    unsigned depth = 0;
    for (unsigned i = 0; i < TF_MAX_DEPTH; i++) path[i] = names[i];
    tk t = lex(&lx);
    for (;;) {
        if (t.kind == TK_END) {
            if (depth) {
                return kelp_fail(wk->d, KELP_ERR_PARSE, "unterminated sub-message");
            }
            return KELP_OK;
        }
        if (t.kind == TK_CLOSE) {
            if (!depth || closers[depth - 1] != t.close) {
                return kelp_fail(wk->d, KELP_ERR_PARSE, "unbalanced '}'");
            }
            depth--;
            int rc = wk->close ? wk->close(wk->ctx, depth) : 0;
            if (rc) return rc;
            t = lex(&lx);
            if (t.kind == TK_SEP) t = lex(&lx);
            continue;
        }
        if (t.kind != TK_IDENT) {
            return kelp_fail(wk->d, KELP_ERR_PARSE, t.kind == TK_BAD ? "unexpected character or unterminated string" : "expected a field name");
        }
        tk name = t;
        t = lex(&lx);
        bool colon = false;
        if (t.kind == TK_COLON) {
            colon = true;
            t = lex(&lx);
        }
        if (t.kind == TK_OPEN) {
            if (depth >= TF_MAX_DEPTH) {
                return kelp_fail(wk->d, KELP_ERR_PARSE, "sub-messages nested too deeply");
            }
            size_t nn = name.n < sizeof names[0] - 1 ? name.n : sizeof names[0] - 1;
            memcpy(names[depth], name.s, nn);
            names[depth][nn] = '\0';
            closers[depth] = t.close;
            int rc = wk->open ? wk->open(wk->ctx, path, depth, name.s, name.n) : 0;
            if (rc) return rc;
            depth++;
            t = lex(&lx);
            continue;
        }
        if (!colon) {
            return kelp_fail(wk->d, KELP_ERR_PARSE, "expected ':' after a field name");
        }
        tf_val v = { t.kind, t.s, t.n, NULL, 0 };
        if (t.kind == TK_STRING) {
            v.bytes = sbuf;
            v.blen = 0;
            while (t.kind == TK_STRING) {
                int rc = unescape(t.s, t.n, t.close != 0, sbuf, scap, &v.blen);
                if (rc) {
                    return kelp_fail(wk->d, rc, rc == KELP_ERR_NOSPACE ? wk->too_long : "bad escape in string");
                }
                t = lex(&lx);
            }
        } else if (t.kind == TK_NUMBER || t.kind == TK_IDENT) {
            t = lex(&lx);
        } else {
            return kelp_fail(wk->d, KELP_ERR_PARSE, "expected a value");
        }
        int rc = wk->field(wk->ctx, path, depth, name.s, name.n, &v);
        if (rc) return rc;
        if (t.kind == TK_SEP) t = lex(&lx);
    }
}

static int val_long(const tf_val *v, long long lo, long long hi, long long *out)
{
    if (v->kind != TK_NUMBER) return KELP_ERR_PARSE;
    long long x;
    const char *s = v->s;
    size_t n = v->n;
    if (n && s[0] == '+') s++, n--;
    if (kelp_util_parse_llong(s, n, &x) != KELP_OK) return KELP_ERR_PARSE;
    if (x < lo || x > hi) return KELP_ERR_RANGE;
    *out = x;
    return KELP_OK;
}

static int val_bool(const tf_val *v, bool *out)
{
    if ((v->kind == TK_IDENT && (tok_is(v->s, v->n, "true") || tok_is(v->s, v->n, "True") || tok_is(v->s, v->n, "t"))) ||
        (v->kind == TK_NUMBER && tok_is(v->s, v->n, "1"))) {
        *out = true;
        return KELP_OK;
    }
    if ((v->kind == TK_IDENT && (tok_is(v->s, v->n, "false") || tok_is(v->s, v->n, "False") || tok_is(v->s, v->n, "f"))) ||
        (v->kind == TK_NUMBER && tok_is(v->s, v->n, "0"))) {
        *out = false;
        return KELP_OK;
    }
    return KELP_ERR_PARSE;
}

/* ------------------------------------------------------------------ ModemMsgBase (shared) */

/* base { src dest time time_source rate raw description }: src/dest kept, others checked */
static int base_field(const char *name, size_t nlen, const tf_val *v, int *src, int *dest, kelp_diag *d)
{
    long long x;
    if (tok_is(name, nlen, "src") || tok_is(name, nlen, "dest")) {
        if (val_long(v, -2147483647LL - 1, 2147483647LL, &x) != KELP_OK) {
            return kelp_fail(d, KELP_ERR_PARSE, "base.src/dest must be an integer");
        }
        if (name[0] == 's') *src = (int)x;
        else *dest = (int)x;
        return KELP_OK;
    }
    if (tok_is(name, nlen, "time") || tok_is(name, nlen, "raw") || tok_is(name, nlen, "description")) {
        if (v->kind != TK_STRING) {
            return kelp_fail(d, KELP_ERR_PARSE, "base.time/raw/description must be a string");
        }
        return KELP_OK;
    }
    if (tok_is(name, nlen, "time_source")) {
        if (v->kind == TK_IDENT && (tok_is(v->s, v->n, "MODEM_TIME") || tok_is(v->s, v->n, "GOBY_TIME"))) return KELP_OK;
        if (val_long(v, 1, 2, &x) == KELP_OK) return KELP_OK;
        return kelp_fail(d, KELP_ERR_PARSE, "base.time_source must be MODEM_TIME or GOBY_TIME");
    }
    if (tok_is(name, nlen, "rate")) {
        if (val_long(v, 0, 4294967295LL, &x) != KELP_OK) {
            return kelp_fail(d, KELP_ERR_PARSE, "base.rate must be an unsigned integer");
        }
        return KELP_OK;
    }
    return kelp_fail(d, KELP_ERR_PARSE, "unknown field in base");
}

/* ------------------------------------------------------------------ ModemDataTransmission */

typedef struct data_ctx {
    kelp_acomms_msg *m;
    kelp_diag *d;
    bool in_base, in_key;
    bool has_key_type;
} data_ctx;

static int data_open(void *c, const char *const *path, unsigned depth, const char *name, size_t nlen)
{
    (void)path;
    data_ctx *x = c;
    if (depth == 0 && tok_is(name, nlen, "base")) {
        x->in_base = true;
        return KELP_OK;
    }
    if (depth == 0 && tok_is(name, nlen, "queue_key")) {
        x->in_key = true;
        return KELP_OK;
    }
    return kelp_fail(x->d, KELP_ERR_PARSE, "unknown sub-message in ModemDataTransmission");
}

static int data_close(void *c, unsigned depth)
{
    data_ctx *x = c;
    if (depth == 0) x->in_base = x->in_key = false;
    return KELP_OK;
}

static int data_field(void *c, const char *const *path, unsigned depth, const char *name, size_t nlen, const tf_val *v)
{
    (void)path;
    data_ctx *x = c;
    kelp_acomms_msg *m = x->m;
    long long l;
    if (depth == 1 && x->in_base) return base_field(name, nlen, v, &m->src, &m->dest, x->d);
    if (depth == 1 && x->in_key) {
        if (tok_is(name, nlen, "type")) {
            if (v->kind == TK_IDENT && tok_is(v->s, v->n, "QUEUE_DCCL")) m->key.type = KELP_QUEUE_DCCL;
            else if (v->kind == TK_IDENT && tok_is(v->s, v->n, "QUEUE_CCL")) m->key.type = KELP_QUEUE_CCL;
            else if (val_long(v, 1, 2, &l) == KELP_OK) m->key.type = (uint8_t)l;
            else {
                return kelp_fail(x->d, KELP_ERR_PARSE, "queue_key.type must be QUEUE_DCCL or QUEUE_CCL");
            }
            x->has_key_type = true;
            return KELP_OK;
        }
        if (tok_is(name, nlen, "id")) {
            if (val_long(v, 0, 4294967295LL, &l) != KELP_OK) {
                return kelp_fail(x->d, KELP_ERR_PARSE, "queue_key.id must be an unsigned integer");
            }
            m->key.id = (uint32_t)l;
            if (!x->has_key_type) m->key.type = KELP_QUEUE_DCCL;
            return KELP_OK;
        }
        return kelp_fail(x->d, KELP_ERR_PARSE, "unknown field in queue_key");
    }
    if (depth != 0) {
        return kelp_fail(x->d, KELP_ERR_PARSE, "unexpected nesting");
    }
    if (tok_is(name, nlen, "ack_requested")) {
        if (val_bool(v, &m->ack_requested) != KELP_OK) {
            return kelp_fail(x->d, KELP_ERR_PARSE, "ack_requested must be true or false");
        }
        m->has_ack = true;
        return KELP_OK;
    }
    if (tok_is(name, nlen, "data")) {
        if (v->kind != TK_STRING) {
            return kelp_fail(x->d, KELP_ERR_PARSE, "data must be a quoted string");
        }
        memcpy(m->data, v->bytes, v->blen);
        m->len = v->blen;
        return KELP_OK;
    }
    if (tok_is(name, nlen, "frame")) {
        if (val_long(v, 0, 4294967295LL, &l) != KELP_OK) {
            return kelp_fail(x->d, KELP_ERR_PARSE, "frame must be an unsigned integer");
        }
        m->frame = (uint32_t)l;
        return KELP_OK;
    }
    return kelp_fail(x->d, KELP_ERR_PARSE, "unknown field in ModemDataTransmission");
}

int kelp_acomms_parse_data(const char *text, size_t len, kelp_acomms_msg *out, kelp_diag *d)
{
    if (!text || !out) return kelp_fail(d, KELP_ERR_ARG, "no text or no message");
    memset(out, 0, sizeof *out);
    data_ctx x = { out, d, false, false, false };
    tf_walk wk = { data_field, data_open, data_close, &x, d, "data longer than a modem frame" };
    int rc = walk(&wk, text, len, out->data, sizeof out->data);
    return rc ? kelp_fail(d, rc, "malformed ModemDataTransmission") : KELP_OK;
}

/* ------------------------------------------------------------------ ModemRangingRequest */

typedef struct range_ctx {
    kelp_acomms_range_req *r;
    kelp_diag *d;
    bool in_base;
} range_ctx;

static int range_open(void *c, const char *const *path, unsigned depth, const char *name, size_t nlen)
{
    (void)path;
    range_ctx *x = c;
    if (depth == 0 && tok_is(name, nlen, "base")) {
        x->in_base = true;
        return KELP_OK;
    }
    return kelp_fail(x->d, KELP_ERR_PARSE, "unknown sub-message in ModemRangingRequest");
}

static int range_close(void *c, unsigned depth)
{
    range_ctx *x = c;
    if (depth == 0) x->in_base = false;
    return KELP_OK;
}

static int range_field(void *c, const char *const *path, unsigned depth, const char *name, size_t nlen, const tf_val *v)
{
    (void)path;
    range_ctx *x = c;
    long long l;
    if (depth == 1 && x->in_base) return base_field(name, nlen, v, &x->r->src, &x->r->dest, x->d);
    if (depth != 0) {
        return kelp_fail(x->d, KELP_ERR_PARSE, "unexpected nesting");
    }
    if (tok_is(name, nlen, "type")) {
        if (v->kind == TK_IDENT && tok_is(v->s, v->n, "MODEM_TWO_WAY_PING")) x->r->type = KELP_RANGING_TWO_WAY_PING;
        else if (v->kind == TK_IDENT && tok_is(v->s, v->n, "MODEM_ONE_WAY_SYNCHRONOUS"))
            x->r->type = KELP_RANGING_ONE_WAY_SYNCHRONOUS;
        else if (v->kind == TK_IDENT && tok_is(v->s, v->n, "REMUS_LBL_RANGING")) x->r->type = KELP_RANGING_REMUS_LBL;
        else if (val_long(v, 1, 3, &l) == KELP_OK) x->r->type = (kelp_ranging_type)l;
        else {
            return kelp_fail(x->d, KELP_ERR_PARSE, "type must be MODEM_TWO_WAY_PING, MODEM_ONE_WAY_SYNCHRONOUS or REMUS_LBL_RANGING");
        }
        return KELP_OK;
    }
    if (tok_is(name, nlen, "max_range") || tok_is(name, nlen, "enable_beacons")) {
        if (val_long(v, 0, 4294967295LL, &l) != KELP_OK) {
            return kelp_fail(x->d, KELP_ERR_PARSE, "max_range/enable_beacons must be unsigned integers");
        }
        if (name[0] == 'm') x->r->max_range = (unsigned)l;
        else x->r->enable_beacons = (unsigned)l;
        return KELP_OK;
    }
    return kelp_fail(x->d, KELP_ERR_PARSE, "unknown field in ModemRangingRequest");
}

int kelp_acomms_parse_range_req(const char *text, size_t len, kelp_acomms_range_req *out, kelp_diag *d)
{
    if (!text || !out) return kelp_fail(d, KELP_ERR_ARG, "no text or no request");
    memset(out, 0, sizeof *out);
    out->type = KELP_RANGING_TWO_WAY_PING;
    out->max_range = 1000;
    out->enable_beacons = 15;
    range_ctx x = { out, d, false };
    tf_walk wk = { range_field, range_open, range_close, &x, d, "string too long" };
    /* no string field's value is kept: strings are checked and counted, not stored */
    int rc = walk(&wk, text, len, NULL, KELP_MAX_NMEA_LINE);
    return rc ? kelp_fail(d, rc, "malformed ModemRangingRequest") : KELP_OK;
}

/* ------------------------------------------------------------------ MACUpdate */

typedef struct mac_ctx {
    kelp_acomms_mac_update *u;
    kelp_diag *d;
    bool in_slot;
    bool slot_has_src;
} mac_ctx;

static int mac_open(void *c, const char *const *path, unsigned depth, const char *name, size_t nlen)
{
    (void)path;
    mac_ctx *x = c;
    if (depth == 0 && tok_is(name, nlen, "slot")) {
        if (x->u->nslots >= KELP_MAX_MAC_SLOTS) {
            return kelp_fail(x->d, KELP_ERR_NOSPACE, "too many slots");
        }
        kelp_mac_slot_default(&x->u->slot[x->u->nslots], 0);
        x->in_slot = true;
        x->slot_has_src = false;
        return KELP_OK;
    }
    return kelp_fail(x->d, KELP_ERR_PARSE, "unknown sub-message in MACUpdate");
}

static int mac_close(void *c, unsigned depth)
{
    mac_ctx *x = c;
    if (depth == 0 && x->in_slot) {
        if (!x->slot_has_src) {
            return kelp_fail(x->d, KELP_ERR_PARSE, "slot without src (required)");
        }
        x->u->nslots++;
        x->in_slot = false;
    }
    return KELP_OK;
}

static int mac_field(void *c, const char *const *path, unsigned depth, const char *name, size_t nlen, const tf_val *v)
{
    (void)path;
    mac_ctx *x = c;
    long long l;
    if (depth == 1 && x->in_slot) {
        kelp_mac_slot *s = &x->u->slot[x->u->nslots];
        if (tok_is(name, nlen, "src") || tok_is(name, nlen, "dest")) {
            if (val_long(v, -1, 31, &l) != KELP_OK) {
                return kelp_fail(x->d, KELP_ERR_PARSE, "slot src/dest must be -1..31");
            }
            if (name[0] == 's') {
                s->src = (int)l;
                x->slot_has_src = true;
            } else {
                s->dest = (int)l;
            }
            return KELP_OK;
        }
        if (tok_is(name, nlen, "rate")) {
            if (val_long(v, 0, 5, &l) != KELP_OK) {
                return kelp_fail(x->d, KELP_ERR_PARSE, "slot rate must be 0..5");
            }
            s->rate = (unsigned)l;
            return KELP_OK;
        }
        if (tok_is(name, nlen, "slot_seconds")) {
            if (val_long(v, 0, 86400, &l) != KELP_OK) {
                return kelp_fail(x->d, KELP_ERR_PARSE, "slot_seconds must be 0..86400");
            }
            s->slot_seconds = (unsigned)l;
            return KELP_OK;
        }
        if (tok_is(name, nlen, "type")) {
            if (v->kind == TK_IDENT && tok_is(v->s, v->n, "SLOT_DATA")) s->type = KELP_SLOT_DATA;
            else if (v->kind == TK_IDENT && tok_is(v->s, v->n, "SLOT_PING")) s->type = KELP_SLOT_PING;
            else if (v->kind == TK_IDENT && tok_is(v->s, v->n, "SLOT_REMUS_LBL")) s->type = KELP_SLOT_REMUS_LBL;
            else if (val_long(v, 1, 3, &l) == KELP_OK) s->type = (kelp_slot_type)l;
            else {
                return kelp_fail(x->d, KELP_ERR_PARSE, "slot type must be SLOT_DATA, SLOT_PING or SLOT_REMUS_LBL");
            }
            return KELP_OK;
        }
        if (tok_is(name, nlen, "last_heard_time")) {
            if (v->kind != TK_STRING) {
                return kelp_fail(x->d, KELP_ERR_PARSE, "last_heard_time must be a string");
            }
            return KELP_OK;
        }
        return kelp_fail(x->d, KELP_ERR_PARSE, "unknown field in slot");
    }
    if (depth != 0) {
        return kelp_fail(x->d, KELP_ERR_PARSE, "unexpected nesting");
    }
    if (tok_is(name, nlen, "dest")) {
        if (val_long(v, -2147483647LL - 1, 2147483647LL, &l) != KELP_OK) {
            return kelp_fail(x->d, KELP_ERR_PARSE, "dest must be an integer");
        }
        x->u->dest = (int)l;
        x->u->has_dest = true;
        return KELP_OK;
    }
    if (tok_is(name, nlen, "update_type")) {
        if (v->kind == TK_IDENT && tok_is(v->s, v->n, "ADD")) x->u->type = KELP_MAC_UPDATE_ADD;
        else if (v->kind == TK_IDENT && tok_is(v->s, v->n, "REMOVE")) x->u->type = KELP_MAC_UPDATE_REMOVE;
        else if (v->kind == TK_IDENT && tok_is(v->s, v->n, "REPLACE")) x->u->type = KELP_MAC_UPDATE_REPLACE;
        else if (val_long(v, 1, 3, &l) == KELP_OK) x->u->type = (kelp_mac_update_type)l;
        else {
            return kelp_fail(x->d, KELP_ERR_PARSE, "update_type must be ADD, REMOVE or REPLACE");
        }
        return KELP_OK;
    }
    return kelp_fail(x->d, KELP_ERR_PARSE, "unknown field in MACUpdate");
}

int kelp_acomms_parse_mac_update(const char *text, size_t len, kelp_acomms_mac_update *out, kelp_diag *d)
{
    if (!text || !out) return kelp_fail(d, KELP_ERR_ARG, "no text or no update");
    memset(out, 0, sizeof *out);
    out->type = KELP_MAC_UPDATE_REPLACE;
    mac_ctx x = { out, d, false, false };
    tf_walk wk = { mac_field, mac_open, mac_close, &x, d, "string too long" };
    int rc = walk(&wk, text, len, NULL, 128); /* strings checked and counted, not stored */
    if (rc) return kelp_fail(d, rc, "malformed MACUpdate");
    if (!out->has_dest) return kelp_fail(d, KELP_ERR_PARSE, "MACUpdate without dest (required)");
    return KELP_OK;
}
