/* kelp UDP multicast datagrams: LCM-compatible parsing, reassembly and framing (core).
 *
 * Why every check is here: liblcm 1.3.1 computes a fragment's size as datagram length
 * minus 20 before checking the length (a 12-byte "fragment" wraps to ~4 GiB), and checks
 * offset + size <= msg_size in 32 bits (an offset near 2^32 wraps past the check). Here
 * each field is checked against the datagram and the slot in 64-bit arithmetic before
 * any byte is copied.
 */
#include <string.h>
#include <kelp/kv.h>
#include <kelp/mission.h>
#include <kelp/udpm.h>

static uint32_t rd32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3];
}

static uint16_t rd16(const uint8_t *p)
{
    return (uint16_t)((unsigned)p[0] << 8 | (unsigned)p[1]);
}

static void wr32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

static void wr16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v >> 8);
    p[1] = (uint8_t)v;
}

int kelp_udpm_init(kelp_udpm_rx *r, kelp_udpm_slot *slots, size_t nslots, uint8_t *mem, size_t slot_cap,
                   double timeout)
{
    if (!r || (nslots && (!slots || !mem || !slot_cap)) || !(timeout > 0)) return KELP_ERR_ARG;
    if (slot_cap > UINT32_MAX) return KELP_ERR_ARG;
    memset(r, 0, sizeof *r);
    r->slots = slots;
    r->nslots = nslots;
    r->slot_cap = slot_cap;
    r->timeout = timeout;
    for (size_t i = 0; i < nslots; i++) {
        memset(&slots[i], 0, sizeof slots[i]);
        slots[i].data = mem + i * slot_cap;
    }
    return KELP_OK;
}

static int reject(kelp_udpm_rx *r, uint64_t *reason, int err)
{
    (*reason)++;
    r->stats.bad++;
    r->stats.last_err = err;
    return err;
}

/* A channel name: NUL-terminated inside [p, p+n), 1..63 bytes. @return its length or -1. */
static int channel_len(const uint8_t *p, size_t n)
{
    size_t lim = n < KELP_UDPM_MAX_CHANNEL + 1 ? n : KELP_UDPM_MAX_CHANNEL + 1;
    const uint8_t *z = memchr(p, 0, lim);
    if (!z || z == p) return -1;
    return (int)(z - p);
}

size_t kelp_udpm_expire(kelp_udpm_rx *r, kelp_time now)
{
    size_t n = 0;
    for (size_t i = 0; i < r->nslots; i++) {
        kelp_udpm_slot *s = &r->slots[i];
        /* measured from the first fragment, so a trickle of fragments cannot hold a slot */
        if (s->used && !(now - s->first <= r->timeout)) {
            s->used = false;
            r->stats.timeouts++;
            n++;
        }
    }
    return n;
}

static kelp_udpm_slot *slot_find(kelp_udpm_rx *r, uint64_t sender, uint32_t seqno)
{
    for (size_t i = 0; i < r->nslots; i++) {
        kelp_udpm_slot *s = &r->slots[i];
        if (s->used && s->sender == sender && s->seqno == seqno) return s;
    }
    return NULL;
}

/* A free slot, else the oldest busy one (counted as evicted). One sender may hold at most
 * half of the slots (at least one): a sender that wants more reuses its own oldest, so a
 * flood of fragment starts from one address cannot evict everyone else's messages. */
static kelp_udpm_slot *slot_take(kelp_udpm_rx *r, uint64_t sender)
{
    kelp_udpm_slot *free_slot = NULL, *old = NULL, *own = NULL;
    size_t mine = 0, cap = r->nslots / 2 ? r->nslots / 2 : 1;
    for (size_t i = 0; i < r->nslots; i++) {
        kelp_udpm_slot *s = &r->slots[i];
        if (!s->used) {
            if (!free_slot) free_slot = s;
            continue;
        }
        if (!old || s->first < old->first) old = s;
        if (s->sender == sender) {
            mine++;
            if (!own || s->first < own->first) own = s;
        }
    }
    if (mine >= cap) {
        r->stats.evicted++;
        return own;
    }
    if (free_slot) return free_slot;
    if (old) r->stats.evicted++;
    return old;
}

static int feed_fragment(kelp_udpm_rx *r, const uint8_t *dg, size_t len, uint64_t sender, kelp_time now,
                         kelp_udpm_msg *out)
{
    if (len < KELP_UDPM_FRAG_HDR) return reject(r, &r->stats.bad_header, KELP_ERR_TRUNCATED);
    uint32_t seqno = rd32(dg + 4), size = rd32(dg + 8), offset = rd32(dg + 12);
    uint16_t no = rd16(dg + 16), nfrags = rd16(dg + 18);
    if (nfrags == 0 || no >= nfrags || nfrags > KELP_UDPM_MAX_FRAGS)
        return reject(r, &r->stats.bad_fragment, KELP_ERR_RANGE);
    if (size > r->slot_cap || r->nslots == 0) return reject(r, &r->stats.too_big, KELP_ERR_RANGE);
    const uint8_t *p = dg + KELP_UDPM_FRAG_HDR;
    size_t plen = len - KELP_UDPM_FRAG_HDR;
    int cl = -1;
    if (no == 0) {
        cl = channel_len(p, plen);
        if (cl < 0) return reject(r, &r->stats.bad_channel, KELP_ERR_PARSE);
        if (offset != 0) return reject(r, &r->stats.bad_fragment, KELP_ERR_RANGE);
        p += (size_t)cl + 1;
        plen -= (size_t)cl + 1;
    }
    if ((uint64_t)offset + (uint64_t)plen > (uint64_t)size) return reject(r, &r->stats.bad_fragment, KELP_ERR_RANGE);

    kelp_udpm_slot *s = slot_find(r, sender, seqno);
    if (s && (s->size != size || s->nfrags != nfrags)) {
        /* the same message cannot change its shape: keep the first, drop this one */
        return reject(r, &r->stats.bad_fragment, KELP_ERR_RANGE);
    }
    if (!s) {
        s = slot_take(r, sender);
        memset(s->seen, 0, sizeof s->seen);
        s->used = true;
        s->have_channel = false;
        s->sender = sender;
        s->seqno = seqno;
        s->size = size;
        s->bytes = 0;
        s->nfrags = nfrags;
        s->nrecv = 0;
        s->first = now;
    }
    uint8_t bit = (uint8_t)(1u << (no & 7));
    if (s->seen[no >> 3] & bit) {
        r->stats.duplicates++;
        return 0;
    }
    s->seen[no >> 3] |= bit;
    s->nrecv++;
    s->bytes += (uint32_t)plen; /* <= nfrags * size: no overflow with both bounded */
    if (plen) memcpy(s->data + offset, p, plen);
    if (cl >= 0) {
        memcpy(s->channel, dg + KELP_UDPM_FRAG_HDR, (size_t)cl + 1);
        s->have_channel = true;
    }
    r->stats.fragments++;
    if (s->nrecv < s->nfrags) return 0;
    s->used = false;
    if (s->bytes != s->size || !s->have_channel) {
        /* every fragment came but they do not tile the message: overlap or gap */
        return reject(r, &r->stats.bad_fragment, KELP_ERR_RANGE);
    }
    r->stats.frag_msgs++;
    out->channel = s->channel;
    out->data = s->data;
    out->len = s->size;
    out->seqno = s->seqno;
    out->sender = sender;
    out->fragmented = true;
    return 1;
}

int kelp_udpm_feed(kelp_udpm_rx *r, const uint8_t *dg, size_t len, uint64_t sender, kelp_time now,
                   kelp_udpm_msg *out)
{
    if (!r || !out || (!dg && len)) return KELP_ERR_ARG;
    r->stats.datagrams++;
    (void)kelp_udpm_expire(r, now);
    if (len < 4) return reject(r, &r->stats.bad_header, KELP_ERR_TRUNCATED);
    uint32_t magic = rd32(dg);
    if (magic == KELP_UDPM_MAGIC_FRAG) return feed_fragment(r, dg, len, sender, now, out);
    if (magic != KELP_UDPM_MAGIC_SHORT) return reject(r, &r->stats.bad_magic, KELP_ERR_PARSE);
    if (len < KELP_UDPM_SHORT_HDR) return reject(r, &r->stats.bad_header, KELP_ERR_TRUNCATED);
    int cl = channel_len(dg + KELP_UDPM_SHORT_HDR, len - KELP_UDPM_SHORT_HDR);
    if (cl < 0) return reject(r, &r->stats.bad_channel, KELP_ERR_PARSE);
    size_t off = KELP_UDPM_SHORT_HDR + (size_t)cl + 1;
    r->stats.short_msgs++;
    out->channel = (const char *)(dg + KELP_UDPM_SHORT_HDR);
    out->data = dg + off;
    out->len = len - off;
    out->seqno = rd32(dg + 4);
    out->sender = sender;
    out->fragmented = false;
    return 1;
}

const kelp_udpm_stats *kelp_udpm_get_stats(const kelp_udpm_rx *r)
{
    return r ? &r->stats : NULL;
}

/* ------------------------------------------------------------------ sending */

int kelp_udpm_plan(size_t chanlen, size_t len, size_t max_datagram, uint16_t *nfrags)
{
    if (!nfrags) return KELP_ERR_ARG;
    if (chanlen == 0 || chanlen > KELP_UDPM_MAX_CHANNEL || len > KELP_UDPM_MAX_MESSAGE) return KELP_ERR_RANGE;
    if (max_datagram > KELP_UDPM_MAX_DATAGRAM || max_datagram < KELP_UDPM_FRAG_HDR + chanlen + 2)
        return KELP_ERR_ARG;
    size_t total = chanlen + 1 + len;
    if (KELP_UDPM_SHORT_HDR + total <= max_datagram) {
        *nfrags = 0;
        return KELP_OK;
    }
    size_t fp = max_datagram - KELP_UDPM_FRAG_HDR;
    size_t n = total / fp + (total % fp != 0);
    if (n > 65535) return KELP_ERR_RANGE;
    *nfrags = (uint16_t)n;
    return KELP_OK;
}

void kelp_udpm_put_short_header(uint8_t out[KELP_UDPM_SHORT_HDR], uint32_t seqno)
{
    wr32(out, KELP_UDPM_MAGIC_SHORT);
    wr32(out + 4, seqno);
}

void kelp_udpm_put_frag_header(uint8_t out[KELP_UDPM_FRAG_HDR], uint32_t seqno, uint32_t msg_size, uint32_t offset,
                               uint16_t frag_no, uint16_t nfrags)
{
    wr32(out, KELP_UDPM_MAGIC_FRAG);
    wr32(out + 4, seqno);
    wr32(out + 8, msg_size);
    wr32(out + 12, offset);
    wr16(out + 16, frag_no);
    wr16(out + 18, nfrags);
}

int kelp_udpm_datagram(const char *channel, const uint8_t *data, size_t len, uint32_t seqno, size_t max_datagram,
                       uint16_t k, uint8_t *buf, size_t cap, size_t *out_len)
{
    if (!channel || (!data && len) || !buf || !out_len) return KELP_ERR_ARG;
    size_t cl = strlen(channel);
    uint16_t n = 0;
    int rc = kelp_udpm_plan(cl, len, max_datagram, &n);
    if (rc < 0) return rc;
    if (n == 0) {
        if (k != 0) return KELP_ERR_RANGE;
        size_t need = KELP_UDPM_SHORT_HDR + cl + 1 + len;
        if (cap < need) return KELP_ERR_NOSPACE;
        kelp_udpm_put_short_header(buf, seqno);
        memcpy(buf + KELP_UDPM_SHORT_HDR, channel, cl + 1);
        if (len) memcpy(buf + KELP_UDPM_SHORT_HDR + cl + 1, data, len);
        *out_len = need;
        return KELP_OK;
    }
    if (k >= n || !data) return KELP_ERR_RANGE; /* fragments carry payload: data is set */
    size_t fp = max_datagram - KELP_UDPM_FRAG_HDR;
    size_t first = fp - (cl + 1); /* fragment 0 carries the channel, then this much payload */
    size_t off = k == 0 ? 0 : first + (size_t)(k - 1) * fp;
    size_t chunk = k == 0 ? first : (len - off < fp ? len - off : fp);
    size_t pre = k == 0 ? cl + 1 : 0;
    size_t need = KELP_UDPM_FRAG_HDR + pre + chunk;
    if (cap < need) return KELP_ERR_NOSPACE;
    kelp_udpm_put_frag_header(buf, seqno, (uint32_t)len, (uint32_t)off, k, n);
    if (pre) memcpy(buf + KELP_UDPM_FRAG_HDR, channel, pre);
    if (chunk) memcpy(buf + KELP_UDPM_FRAG_HDR + pre, data + off, chunk);
    *out_len = need;
    return KELP_OK;
}

/* ------------------------------------------------------------------ URLs */

static int parse_group(const char *s, size_t n, uint32_t *out)
{
    uint32_t g = 0;
    size_t a = 0;
    for (int part = 0; part < 4; part++) {
        size_t e = a;
        while (e < n && s[e] != '.') e++;
        if ((part < 3) != (e < n)) return KELP_ERR_PARSE;
        long v;
        if (e == a || e - a > 3 || kelp_util_parse_long(s + a, e - a, &v) < 0 || v < 0 || v > 255) return KELP_ERR_PARSE;
        g = g << 8 | (uint32_t)v;
        a = e + 1;
    }
    *out = g;
    return KELP_OK;
}

int kelp_udpm_url_parse(const char *url, kelp_udpm_url *out)
{
    static const char scheme[] = "udpm://";
    if (!url || !out) return KELP_ERR_ARG;
    if (strncmp(url, scheme, sizeof scheme - 1) != 0) return KELP_ERR_UNSUPPORTED;
    memset(out, 0, sizeof *out);
    out->port = KELP_UDPM_DEFAULT_PORT;
    out->gso = 1;
    const char *h = url + sizeof scheme - 1;
    const char *q = strchr(h, '?');
    size_t hl = q ? (size_t)(q - h) : strlen(h);
    const char *colon = memchr(h, ':', hl);
    size_t gl = colon ? (size_t)(colon - h) : hl;
    if (parse_group(h, gl, &out->group) < 0) return KELP_ERR_PARSE;
    if ((out->group >> 28) != 0xEu) return KELP_ERR_RANGE; /* not 224.0.0.0/4 */
    if (colon) {
        long p;
        if (kelp_util_parse_long(colon + 1, hl - gl - 1, &p) < 0) return KELP_ERR_PARSE;
        if (p < 1 || p > 65535) return KELP_ERR_RANGE;
        out->port = (uint16_t)p;
    }
    if (!q) return KELP_OK;
    size_t pos = 0, kl, vl;
    const char *k, *v;
    int rc;
    while ((rc = kelp_kv_next(q + 1, '&', &pos, &k, &kl, &v, &vl)) != 0) {
        if (rc < 0) return rc;
        long n;
        if (kelp_util_strieq_n(k, kl, "transmit_only")) continue;
        if (kelp_util_parse_long(v, vl, &n) < 0) return KELP_ERR_PARSE;
        if (kelp_util_strieq_n(k, kl, "ttl")) {
            if (n < 0 || n > 255) return KELP_ERR_RANGE;
            out->ttl = (int)n;
        } else if (kelp_util_strieq_n(k, kl, "recv_buf_size")) {
            if (n < 0 || n > (1L << 30)) return KELP_ERR_RANGE;
            out->recv_buf_size = n;
        } else if (kelp_util_strieq_n(k, kl, "queue_size")) {
            if (n < 0 || n > (1L << 30)) return KELP_ERR_RANGE;
            out->queue_size = n;
        } else if (kelp_util_strieq_n(k, kl, "send_buf_size")) {
            if (n < 0 || n > (1L << 30)) return KELP_ERR_RANGE;
            out->send_buf_size = n;
        } else if (kelp_util_strieq_n(k, kl, "gso")) {
            if (n != 0 && n != 1) return KELP_ERR_RANGE;
            out->gso = (int)n;
        } else {
            return KELP_ERR_PARSE;
        }
    }
    return KELP_OK;
}

int kelp_udpm_community_url(const char *lcm_url, const char *server_port, char *buf, size_t cap)
{
    static const char pre[] = "udpm://" KELP_UDPM_DEFAULT_GROUP ":", post[] = "?ttl=0";
    if (!buf || cap == 0) return KELP_ERR_ARG;
    buf[0] = 0;
    if (lcm_url && *lcm_url) {
        kelp_udpm_url u;
        if (kelp_udpm_url_parse(lcm_url, &u) < 0) return KELP_ERR_RANGE;
        size_t n = strlen(lcm_url);
        if (n + 1 > cap) return KELP_ERR_NOSPACE;
        memcpy(buf, lcm_url, n + 1);
        return KELP_OK;
    }
    if (!server_port || !*server_port) return KELP_OK;
    long port;
    size_t pl = strlen(server_port);
    if (kelp_util_parse_long(server_port, pl, &port) < 0 || port < 1 || port > 65535) return KELP_ERR_RANGE;
    if (sizeof pre - 1 + pl + sizeof post > cap) return KELP_ERR_NOSPACE;
    size_t o = sizeof pre - 1;
    memcpy(buf, pre, o);
    memcpy(buf + o, server_port, pl);
    o += pl;
    memcpy(buf + o, post, sizeof post - 1);
    buf[o + sizeof post - 1] = 0;
    return KELP_OK;
}
