/* kelp over CAN: dictionary, body coding, segmentation and reassembly (core; see kelp/can.h). */
#include <math.h>
#include <string.h>
#include <kelp/can.h>
#include <kelp/kv.h>
#include <kelp/util.h>

/* ------------------------------------------------------------------ dictionary */

void kelp_can_dict_init(kelp_can_dict *d)
{
    d->n = 0;
}

int kelp_can_dict_add(kelp_can_dict *d, unsigned id, const char *name)
{
    size_t len = strlen(name);
    if (id >= KELP_CAN_VAR_NAMED || len == 0 || len >= KELP_CAN_NAME) return KELP_ERR_RANGE;
    if (kelp_can_dict_id(d, name) >= 0 || kelp_can_dict_name(d, id)) return KELP_ERR_EXISTS;
    if (d->n >= KELP_CAN_DICT_MAX) return KELP_ERR_NOSPACE;
    d->e[d->n].id = (uint16_t)id;
    memcpy(d->e[d->n].name, name, len + 1);
    d->n++;
    return KELP_OK;
}

int kelp_can_dict_parse(kelp_can_dict *dict, const char *spec, kelp_diag *d)
{
    size_t pos = 0, klen, vlen;
    const char *k, *v;
    int rc;
    while ((rc = kelp_kv_next(spec, ',', &pos, &k, &klen, &v, &vlen)) == 1) {
        long id;
        char name[KELP_CAN_NAME];
        if (kelp_util_parse_long(k, klen, &id) < 0 || id < 0 || id >= (long)KELP_CAN_VAR_NAMED) return kelp_fail(d, KELP_ERR_PARSE, "variable id must be 0-510");
        if (vlen == 0 || vlen >= sizeof name) return kelp_fail(d, KELP_ERR_PARSE, "name empty or longer than 63");
        memcpy(name, v, vlen);
        name[vlen] = 0;
        rc = kelp_can_dict_add(dict, (unsigned)id, name);
        if (rc < 0) return kelp_fail(d, KELP_ERR_PARSE, rc == KELP_ERR_EXISTS ? "id or name given twice" : "dictionary full");
    }
    return rc < 0 ? kelp_fail(d, KELP_ERR_PARSE, "expected id=NAME pairs") : KELP_OK;
}

int kelp_can_dict_id(const kelp_can_dict *d, const char *name)
{
    for (size_t i = 0; d && i < d->n; i++)
        if (strcmp(d->e[i].name, name) == 0) return d->e[i].id;
    return -1;
}

const char *kelp_can_dict_name(const kelp_can_dict *d, unsigned id)
{
    for (size_t i = 0; d && i < d->n; i++)
        if (d->e[i].id == id) return d->e[i].name;
    return NULL;
}

/* ------------------------------------------------------------------ helpers */

uint16_t kelp_can_crc16(const uint8_t *p, size_t n)
{
    /* a nibble at a time: a 32-byte table, small enough for firmware */
    static const uint16_t t[16] = { 0x0000, 0x1021, 0x2042, 0x3063, 0x4084, 0x50A5, 0x60C6, 0x70E7,
                                    0x8108, 0x9129, 0xA14A, 0xB16B, 0xC18C, 0xD1AD, 0xE1CE, 0xF1EF };
    uint16_t c = 0xFFFFu;
    for (size_t i = 0; i < n; i++) {
        c = (uint16_t)((unsigned)(c << 4) ^ t[(c >> 12) ^ (p[i] >> 4)]);
        c = (uint16_t)((unsigned)(c << 4) ^ t[(c >> 12) ^ (p[i] & 0x0Fu)]);
    }
    return c;
}

uint8_t kelp_can_fd_len(size_t len)
{
    static const uint8_t sizes[] = { 8, 12, 16, 20, 24, 32, 48, 64 };
    if (len <= 8) return (uint8_t)len;
    for (size_t i = 1; i < sizeof sizes; i++)
        if (len <= sizes[i]) return sizes[i];
    return 0;
}

static void put_f64(uint8_t *p, double d)
{
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    kelp_util_be_put64(p, u);
}

static double get_f64(const uint8_t *p)
{
    uint64_t u = kelp_util_be_get64(p);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

/* ------------------------------------------------------------------ sending */

int kelp_can_tx_init(kelp_can_tx *tx, unsigned node, bool fd)
{
    if (node < 1 || node > KELP_CAN_MAX_NODE) return KELP_ERR_RANGE;
    memset(tx, 0, sizeof *tx);
    tx->node = (uint8_t)node;
    tx->prio = KELP_CAN_PRIO_DEFAULT;
    tx->fd = fd;
    return KELP_OK;
}

/* The numeric kind that carries d exactly in the fewest bytes. */
static unsigned numeric_kind(double d)
{
    if (d >= -2147483648.0 && d <= 2147483647.0 && d == floor(d) && !(d == 0 && signbit(d))) return KELP_CAN_KIND_I32;
    if (isnan(d) || (double)(float)d == d) return isnan(d) ? KELP_CAN_KIND_F64 : KELP_CAN_KIND_F32;
    return KELP_CAN_KIND_F64;
}

static int put_str(uint8_t *b, size_t *n, const char *s)
{
    size_t len = strlen(s);
    if (len >= KELP_CAN_NAME || *n + 1 + len > KELP_CAN_MAX_BODY) return KELP_ERR_RANGE;
    b[(*n)++] = (uint8_t)len;
    for (size_t i = 0; i < len; i++) b[(*n)++] = (uint8_t)s[i]; /* length-prefixed, no NUL */
    return KELP_OK;
}

/* Encode the body of m into tx->body. */
static int encode_body(kelp_can_tx *tx, const kelp_can_msg *m, bool named, size_t *len)
{
    uint8_t *b = tx->body;
    unsigned kind = m->kind;
    if (kind > KELP_CAN_KIND_BINARY) return KELP_ERR_ARG;
    if (kind == KELP_CAN_KIND_F64 && !tx->exact_f64) kind = numeric_kind(m->dval);
    size_t n = 1;
    b[0] = (uint8_t)(kind | (m->has_time ? KELP_CAN_HDR_TIME : 0u) | (named ? KELP_CAN_HDR_NAME : 0u) |
                     (m->source ? KELP_CAN_HDR_SOURCE : 0u));
    if (m->has_time) {
        put_f64(b + n, m->time);
        n += 8;
    }
    if (named && put_str(b, &n, m->name) < 0) return KELP_ERR_RANGE;
    if (m->source && put_str(b, &n, m->source) < 0) return KELP_ERR_RANGE;
    switch (kind) {
    case KELP_CAN_KIND_F64:
        if (n + 8 > KELP_CAN_MAX_BODY) return KELP_ERR_RANGE;
        put_f64(b + n, m->dval);
        n += 8;
        break;
    case KELP_CAN_KIND_F32: {
        float f = (float)m->dval;
        uint32_t u;
        memcpy(&u, &f, sizeof u);
        if (n + 4 > KELP_CAN_MAX_BODY) return KELP_ERR_RANGE;
        kelp_util_be_put32(b + n, u);
        n += 4;
        break;
    }
    case KELP_CAN_KIND_I32:
        if (n + 4 > KELP_CAN_MAX_BODY || !(m->dval >= -2147483648.0 && m->dval <= 2147483647.0)) return KELP_ERR_RANGE;
        kelp_util_be_put32(b + n, (uint32_t)(int32_t)m->dval);
        n += 4;
        break;
    default:
        if (m->slen > KELP_CAN_MAX_BODY - n || (m->slen && !m->sval)) return KELP_ERR_RANGE;
        if (m->slen) memcpy(b + n, m->sval, m->slen);
        n += m->slen;
        break;
    }
    *len = n;
    return KELP_OK;
}

int kelp_can_send(kelp_can_tx *tx, const kelp_can_dict *d, const kelp_can_msg *m, kelp_can_emit_fn emit, void *user)
{
    if (!tx || !m || !m->name || !emit) return KELP_ERR_ARG;
    int id = kelp_can_dict_id(d, m->name);
    bool named = id < 0;
    size_t len = 0;
    int rc = encode_body(tx, m, named, &len);
    if (rc < 0) return rc;
    uint32_t canid = KELP_CAN_ID(tx->prio, tx->node, tx->tid, named ? KELP_CAN_VAR_NAMED : (unsigned)id);
    tx->tid = (uint8_t)((tx->tid + 1u) & 0x1Fu);
    kelp_can_frame f;
    memset(&f, 0, sizeof f);
    f.id = canid;
    f.fd = tx->fd;
    size_t full = tx->fd ? 64u : 8u;
    if (len <= full - 1) { /* single frame */
        f.data[0] = (uint8_t)(KELP_CAN_PCI_SINGLE | len);
        memcpy(f.data + 1, tx->body, len);
        f.len = tx->fd ? kelp_can_fd_len(len + 1) : (uint8_t)(len + 1);
        rc = emit(user, &f);
        return rc < 0 ? rc : 1;
    }
    size_t first = tx->fd ? KELP_CAN_FD_FIRST : KELP_CAN_CLASSIC_FIRST;
    size_t chunk = tx->fd ? KELP_CAN_FD_CHUNK : KELP_CAN_CLASSIC_CHUNK;
    uint16_t crc = kelp_can_crc16(tx->body, len);
    f.data[0] = KELP_CAN_PCI_FIRST;
    f.data[1] = (uint8_t)(len >> 8);
    f.data[2] = (uint8_t)len;
    f.data[3] = (uint8_t)(crc >> 8);
    f.data[4] = (uint8_t)crc;
    memcpy(f.data + 5, tx->body, first);
    f.len = (uint8_t)full;
    rc = emit(user, &f);
    if (rc < 0) return rc;
    int frames = 1;
    for (size_t off = first, idx = 1; off < len; off += chunk, idx++) {
        size_t c = len - off < chunk ? len - off : chunk;
        memset(f.data, 0, sizeof f.data);
        f.data[0] = (uint8_t)(KELP_CAN_PCI_CONSEC | idx);
        memcpy(f.data + 1, tx->body + off, c);
        f.len = tx->fd ? kelp_can_fd_len(c + 1) : (uint8_t)(c + 1);
        rc = emit(user, &f);
        if (rc < 0) return rc;
        frames++;
    }
    return frames;
}

/* ------------------------------------------------------------------ receiving */

void kelp_can_rx_init(kelp_can_rx *rx, double timeout)
{
    memset(rx, 0, sizeof *rx);
    rx->timeout = timeout > 0 ? timeout : KELP_CAN_TIMEOUT_DEFAULT;
}

void kelp_can_rx_expire(kelp_can_rx *rx, kelp_time now)
{
    if (!kelp_util_time_ok(now)) return; /* the time step rule: a NaN would expire every transfer */
    for (size_t i = 0; i < KELP_CAN_SLOTS; i++) {
        kelp_can_slot *s = &rx->slots[i];
        /* a transfer started "later" than now: the clock stepped back; its timeout counts
         * from now, so a full table frees within one timeout and not after the step */
        if (s->used && s->started > now) s->started = now;
        if (s->used && !(now - s->started <= rx->timeout)) {
            s->used = false;
            rx->st.timed_out++;
        }
    }
}

static int get_str(const uint8_t *b, size_t len, size_t *n, char out[KELP_CAN_NAME])
{
    if (*n >= len) return KELP_ERR_TRUNCATED;
    size_t l = b[(*n)++];
    if (l == 0 || l >= KELP_CAN_NAME || l > len - *n || memchr(b + *n, 0, l)) return KELP_ERR_PARSE;
    memcpy(out, b + *n, l);
    out[l] = 0;
    *n += l;
    return KELP_OK;
}

/* Parse a complete body (id from the CAN id) into out. */
static int decode_body(kelp_can_rx *rx, const kelp_can_dict *d, uint32_t id, const uint8_t *b, size_t len,
                       kelp_can_msg *out)
{
    unsigned var = KELP_CAN_ID_VAR(id);
    if (len < 1 || (b[0] & 0xC0u) || (b[0] & 7u) > KELP_CAN_KIND_BINARY) return KELP_ERR_PARSE;
    unsigned kind = b[0] & 7u;
    bool named = (b[0] & KELP_CAN_HDR_NAME) != 0;
    if (named != (var == KELP_CAN_VAR_NAMED)) return KELP_ERR_PARSE;
    memset(out, 0, sizeof *out);
    out->node = (uint8_t)KELP_CAN_ID_NODE(id);
    out->var = (uint16_t)var;
    out->kind = kind;
    size_t n = 1;
    if (b[0] & KELP_CAN_HDR_TIME) {
        if (len - n < 8) return KELP_ERR_TRUNCATED;
        out->has_time = true;
        out->time = get_f64(b + n);
        n += 8;
    }
    if (named) {
        if (get_str(b, len, &n, rx->name) < 0) return KELP_ERR_PARSE;
        out->name = rx->name;
    }
    if (b[0] & KELP_CAN_HDR_SOURCE) {
        if (get_str(b, len, &n, rx->source) < 0) return KELP_ERR_PARSE;
        out->source = rx->source;
    }
    size_t rest = len - n;
    switch (kind) {
    case KELP_CAN_KIND_F64:
        if (rest != 8) return KELP_ERR_PARSE;
        out->dval = get_f64(b + n);
        break;
    case KELP_CAN_KIND_F32: {
        if (rest != 4) return KELP_ERR_PARSE;
        uint32_t u = kelp_util_be_get32(b + n);
        float f;
        memcpy(&f, &u, sizeof f);
        out->dval = f;
        out->kind = KELP_CAN_KIND_F64;
        break;
    }
    case KELP_CAN_KIND_I32:
        if (rest != 4) return KELP_ERR_PARSE;
        out->dval = (double)(int32_t)kelp_util_be_get32(b + n);
        out->kind = KELP_CAN_KIND_F64;
        break;
    default:
        memcpy(rx->value, b + n, rest);
        rx->value[rest] = 0;
        out->sval = rx->value;
        out->slen = rest;
        break;
    }
    if (!named) {
        out->name = kelp_can_dict_name(d, var);
        if (!out->name) {
            rx->st.unknown_var++;
            return KELP_ERR_NOTFOUND;
        }
    }
    return KELP_OK;
}

static int deliver(kelp_can_rx *rx, const kelp_can_dict *d, uint32_t id, const uint8_t *b, size_t len,
                   kelp_can_msg *out)
{
    if (b != rx->body) memcpy(rx->body, b, len);
    int rc = decode_body(rx, d, id, rx->body, len, out);
    if (rc == KELP_ERR_NOTFOUND) return rc;
    if (rc < 0) {
        rx->st.bad_body++;
        return rc;
    }
    rx->st.messages++;
    return 1;
}

static int bad(kelp_can_rx *rx)
{
    rx->st.bad_frame++;
    return KELP_ERR_PARSE;
}

static kelp_can_slot *find_slot(kelp_can_rx *rx, uint32_t key)
{
    for (size_t i = 0; i < KELP_CAN_SLOTS; i++)
        if (rx->slots[i].used && rx->slots[i].key == key) return &rx->slots[i];
    return NULL;
}

static kelp_can_slot *new_slot(kelp_can_rx *rx, uint32_t key, bool fd, kelp_time now)
{
    for (size_t i = 0; i < KELP_CAN_SLOTS; i++) {
        kelp_can_slot *s = &rx->slots[i];
        if (s->used) continue;
        s->used = true;
        s->have_first = false;
        s->fd = fd;
        s->key = key;
        s->total = 0;
        s->crc = 0;
        s->nseg = 0;
        s->highest = 0;
        s->got = 0;
        s->started = now;
        return s;
    }
    return NULL;
}

/* Whether every segment of s is in. */
static bool complete(const kelp_can_slot *s)
{
    if (!s->have_first) return false;
    uint64_t want = s->nseg >= 63 ? ~(uint64_t)0 : (((uint64_t)1 << (s->nseg + 1)) - 1u);
    return (s->got & want) == want;
}

int kelp_can_rx_frame(kelp_can_rx *rx, const kelp_can_dict *d, const kelp_can_frame *f, kelp_time now, kelp_can_msg *out)
{
    if (!kelp_util_time_ok(now)) return KELP_ERR_ARG;
    rx->st.frames++;
    kelp_can_rx_expire(rx, now);
    if (f->id > KELP_CAN_EFF_MASK || KELP_CAN_ID_TAG(f->id) != KELP_CAN_TAG) {
        rx->st.foreign++;
        return 0;
    }
    size_t full = f->fd ? 64u : 8u;
    if (f->len < 1 || f->len > full || (f->fd && kelp_can_fd_len(f->len) != f->len)) return bad(rx);
    if (KELP_CAN_ID_NODE(f->id) == 0) return bad(rx);
    uint8_t pci = f->data[0];
    uint32_t key = f->id & 0x03FFFFFFu; /* without priority */
    size_t first = f->fd ? KELP_CAN_FD_FIRST : KELP_CAN_CLASSIC_FIRST;
    size_t chunk = f->fd ? KELP_CAN_FD_CHUNK : KELP_CAN_CLASSIC_CHUNK;
    switch (pci & 0xC0u) {
    case KELP_CAN_PCI_SINGLE: {
        size_t len = pci & 0x3Fu;
        if (len == 0 || len > (size_t)f->len - 1u) return bad(rx);
        rx->st.frames_ok++;
        return deliver(rx, d, f->id, f->data + 1, len, out);
    }
    case KELP_CAN_PCI_FIRST: {
        size_t total = (size_t)f->data[1] << 8 | f->data[2];
        size_t nseg = total > first ? (total - first + chunk - 1) / chunk : 0;
        if ((pci & 0x3Fu) || f->len != full || total <= full - 1 || total > KELP_CAN_MAX_BODY || nseg > KELP_CAN_MAX_SEGS)
            return bad(rx);
        kelp_can_slot *s = find_slot(rx, key);
        if (s && (s->have_first || s->fd != f->fd || s->highest > nseg)) {
            /* a new message under the same id: the old one will never finish */
            s->used = false;
            rx->st.aborted++;
            s = NULL;
        }
        if (!s) s = new_slot(rx, key, f->fd, now);
        if (!s) {
            rx->st.slot_full++;
            return KELP_ERR_NOSPACE;
        }
        s->have_first = true;
        s->total = (uint16_t)total;
        s->crc = (uint16_t)(f->data[3] << 8 | f->data[4]);
        s->nseg = (uint8_t)nseg;
        s->got |= 1u;
        memcpy(s->buf, f->data + 5, first);
        if (s->highest > 0) rx->st.out_of_order++; /* consecutive frames came first */
        rx->st.frames_ok++;
        break;
    }
    case KELP_CAN_PCI_CONSEC: {
        unsigned idx = pci & 0x3Fu;
        if (idx == 0) return bad(rx);
        kelp_can_slot *s = find_slot(rx, key);
        if (s && s->fd != f->fd) return bad(rx);
        if (s && s->have_first && idx > s->nseg) return bad(rx);
        size_t off = first + (idx - 1u) * chunk;
        size_t c = (size_t)f->len - 1u;
        if (c > chunk) return bad(rx);
        if (s && s->have_first) {
            size_t want = s->total - off < chunk ? s->total - off : chunk;
            if (c < want) return bad(rx);
            c = want;
        } else if (off + c > KELP_CAN_MAX_BODY) {
            c = off < KELP_CAN_MAX_BODY ? KELP_CAN_MAX_BODY - off : 0;
            if (c == 0) return bad(rx);
        }
        if (s && (s->got >> idx) & 1u) {
            rx->st.duplicate++;
            return KELP_ERR_REPLAY;
        }
        if (!s) s = new_slot(rx, key, f->fd, now);
        if (!s) {
            rx->st.slot_full++;
            return KELP_ERR_NOSPACE;
        }
        if (idx < s->highest) rx->st.out_of_order++; /* a later segment came first */
        memcpy(s->buf + off, f->data + 1, c);
        s->got |= (uint64_t)1 << idx;
        if (idx > s->highest) s->highest = (uint8_t)idx;
        rx->st.frames_ok++;
        break;
    }
    default:
        return bad(rx);
    }
    kelp_can_slot *s = find_slot(rx, key);
    if (!s || !complete(s)) return 0;
    s->used = false;
    if (kelp_can_crc16(s->buf, s->total) != s->crc) {
        rx->st.bad_crc++;
        return KELP_ERR_CHECKSUM;
    }
    return deliver(rx, d, f->id, s->buf, s->total, out);
}

/* ------------------------------------------------------------------ bus variables */

int kelp_can_msg_to_var(const kelp_can_msg *m, const char *as, kelp_time now, kelp_var *v)
{
    memset(v, 0, offsetof(kelp_var, sval));
    v->sval[0] = 0;
    if (kelp_bus_name_set(v->name, (as && *as) ? as : m->name) < 0) return KELP_ERR_RANGE;
    if (m->source) {
        if (kelp_bus_name_set(v->source, m->source) < 0) return KELP_ERR_RANGE;
    } else {
        (void)kelp_util_snprintf(v->source, sizeof v->source, "can%u", (unsigned)m->node);
    }
    v->time = m->has_time ? m->time : now;
    if (m->kind == KELP_CAN_KIND_STRING || m->kind == KELP_CAN_KIND_BINARY) {
        if (m->slen > KELP_MAX_SVAL) return KELP_ERR_RANGE;
        v->kind = m->kind == KELP_CAN_KIND_STRING ? KELP_VAR_STRING : KELP_VAR_BINARY;
        if (m->slen) memcpy(v->sval, m->sval, m->slen);
        v->sval[m->slen] = 0;
        v->slen = m->slen;
    } else {
        v->kind = KELP_VAR_DOUBLE;
        v->dval = m->dval;
    }
    return KELP_OK;
}

void kelp_can_msg_from_var(const kelp_var *v, const char *as, kelp_can_msg *m)
{
    memset(m, 0, sizeof *m);
    m->name = (as && *as) ? as : v->name;
    m->source = v->source[0] ? v->source : NULL;
    m->has_time = true;
    m->time = v->time;
    m->kind = v->kind == KELP_VAR_DOUBLE ? KELP_CAN_KIND_F64
              : v->kind == KELP_VAR_STRING ? KELP_CAN_KIND_STRING
                                           : KELP_CAN_KIND_BINARY;
    m->dval = v->dval;
    m->sval = (const uint8_t *)v->sval;
    m->slen = v->kind == KELP_VAR_DOUBLE ? 0 : v->slen;
}

/* ------------------------------------------------------------------ filters */

size_t kelp_can_filters(const uint16_t *vars, size_t n, kelp_can_filter *out, size_t cap)
{
    const uint32_t tagmask = KELP_CAN_FILTER_EFF | (0x1Fu << 21);
    const uint32_t tagid = KELP_CAN_FILTER_EFF | (KELP_CAN_TAG << 21);
    if (cap == 0) return 0;
    if (n == 0 || n > cap || n > KELP_CAN_MAX_FILTERS) {
        out[0].id = tagid;
        out[0].mask = tagmask;
        return 1;
    }
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        bool dup = false;
        for (size_t j = 0; j < k; j++) dup = dup || (out[j].id & 0x1FFu) == (vars[i] & 0x1FFu);
        if (dup) continue;
        out[k].id = tagid | (vars[i] & 0x1FFu);
        out[k].mask = tagmask | 0x1FFu;
        k++;
    }
    return k;
}

bool kelp_can_filter_pass(const kelp_can_filter *f, size_t n, uint32_t id, bool eff)
{
    if (n == 0) return true;
    uint32_t full = (id & KELP_CAN_EFF_MASK) | (eff ? KELP_CAN_FILTER_EFF : 0u);
    for (size_t i = 0; i < n; i++)
        if ((full & f[i].mask) == (f[i].id & f[i].mask)) return true;
    return false;
}
