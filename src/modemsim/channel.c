/* kelp modemsim: acoustic channel arithmetic, the seeded RNG and the bus packet codec. */
#include <kelp/modemsim.h>

#include <math.h>
#include <string.h>

const unsigned kelp_modemsim_rate_frames[6] = { 1, 3, 3, 2, 2, 8 };
const unsigned kelp_modemsim_rate_bytes[6] = { 32, 32, 64, 256, 256, 256 };
const unsigned kelp_modemsim_rate_bps[6] = { 80, 250, 500, 1200, 1300, 5300 };

double kelp_modemsim_packet_seconds(unsigned rate, unsigned frames)
{
    if (rate > 5) return 0.0;
    return (double)frames * (double)kelp_modemsim_rate_bytes[rate] * 8.0 / (double)kelp_modemsim_rate_bps[rate];
}

double kelp_modemsim_travel_time(double x1, double y1, double z1, double x2, double y2, double z2, double c)
{
    double dx = x2 - x1, dy = y2 - y1, dz = z2 - z1;
    if (!(c > 0)) return 0.0;
    return sqrt(dx * dx + dy * dy + dz * dz) / c;
}

double kelp_modemsim_min_slot_seconds(unsigned rate, double max_range, double ci_seconds, double mini_seconds,
                                  double turnaround_seconds, double sound_speed)
{
    if (rate > 5 || !(sound_speed > 0)) return 0.0;
    double tt = max_range / sound_speed;
    return ci_seconds + kelp_modemsim_packet_seconds(rate, kelp_modemsim_rate_frames[rate]) + mini_seconds +
           2.0 * turnaround_seconds + 3.0 * tt;
}

/* ------------------------------------------------------------------ packet codec
 *
 * "KMS1" | kind u8 | src dest cmd adr1 adr2 rate ack nframes u8 | instance seq ack_mask u32 |
 * mini u16 | start duration turnaround i64 | x y depth f64 (IEEE bits) |
 * nframes x { src dest ack u8, len u16, data[len] }                      (little-endian)
 */

typedef struct wbuf {
    uint8_t *p;
    size_t cap, n;
    bool over;
} wbuf;

static void put(wbuf *w, uint64_t v, unsigned bytes)
{
    if (w->over || w->n + bytes > w->cap) {
        w->over = true;
        return;
    }
    for (unsigned i = 0; i < bytes; i++) w->p[w->n++] = (uint8_t)(v >> (8 * i));
}

static void put_f64(wbuf *w, double d)
{
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    put(w, u, 8);
}

static void put_bytes(wbuf *w, const uint8_t *b, size_t n)
{
    if (w->over || w->n + n > w->cap) {
        w->over = true;
        return;
    }
    if (n) memcpy(w->p + w->n, b, n);
    w->n += n;
}

static bool kind_ok(int k)
{
    return k >= KELP_MODEMSIM_PKT_CYCLE_INIT && k <= KELP_MODEMSIM_PKT_MINI;
}

/* The wire carries times as whole microseconds (int64). A start within +-4e15 us (1843..2096)
 * survives the kelp_time double exactly; the decoder refuses the rest. */
#define WIRE_START_MAX_US INT64_C(4000000000000000)
static int64_t wire_us(kelp_time t)
{
    return (int64_t)llround(t * 1e6);
}

static bool wire_time_ok(kelp_time t)
{
    return fabs(t) < 9.2e12; /* finite, and whole microseconds fit an int64 */
}

int kelp_modemsim_pkt_encode(const kelp_modemsim_pkt *p, uint8_t *buf, size_t cap, size_t *len)
{
    if (!p || !buf || !len) return KELP_ERR_ARG;
    if (!kind_ok((int)p->kind) || p->rate > 5) return KELP_ERR_ARG;
    if (!wire_time_ok(p->start) || !wire_time_ok(p->duration) || !wire_time_ok(p->turnaround)) return KELP_ERR_ARG;
    unsigned nf = p->kind == KELP_MODEMSIM_PKT_DATA ? p->nframes : 0;
    if (nf > KELP_MAX_MM_FRAMES) return KELP_ERR_ARG;
    wbuf w = { buf, cap, 0, false };
    put_bytes(&w, (const uint8_t *)"KMS1", 4);
    put(&w, (uint64_t)p->kind, 1);
    put(&w, p->src, 1);
    put(&w, p->dest, 1);
    put(&w, p->cmd, 1);
    put(&w, p->adr1, 1);
    put(&w, p->adr2, 1);
    put(&w, p->rate, 1);
    put(&w, p->ack, 1);
    put(&w, p->nframes, 1);
    put(&w, p->instance, 4);
    put(&w, p->seq, 4);
    put(&w, p->ack_mask, 4);
    put(&w, p->mini, 2);
    put(&w, (uint64_t)wire_us(p->start), 8);
    put(&w, (uint64_t)wire_us(p->duration), 8);
    put(&w, (uint64_t)wire_us(p->turnaround), 8);
    put_f64(&w, p->x);
    put_f64(&w, p->y);
    put_f64(&w, p->depth);
    for (unsigned i = 0; i < nf; i++) {
        const kelp_modemsim_frame *f = &p->frame[i];
        if (f->len > KELP_MAX_ACOMMS_FRAME) return KELP_ERR_ARG;
        put(&w, f->src, 1);
        put(&w, f->dest, 1);
        put(&w, f->ack ? 1 : 0, 1);
        put(&w, f->len, 2);
        put_bytes(&w, f->data, f->len);
    }
    if (w.over) return KELP_ERR_NOSPACE;
    *len = w.n;
    return KELP_OK;
}

typedef struct rbuf {
    const uint8_t *p;
    size_t len, n;
    bool short_;
} rbuf;

static uint64_t get(rbuf *r, unsigned bytes)
{
    if (r->short_ || r->len - r->n < bytes) {
        r->short_ = true;
        return 0;
    }
    uint64_t v = 0;
    for (unsigned i = 0; i < bytes; i++) v |= (uint64_t)r->p[r->n++] << (8 * i);
    return v;
}

static double get_f64(rbuf *r)
{
    uint64_t u = get(r, 8);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

int kelp_modemsim_pkt_decode(const uint8_t *buf, size_t len, kelp_modemsim_pkt *p)
{
    if (!buf || !p) return KELP_ERR_ARG;
    if (len < 4) return KELP_ERR_TRUNCATED;
    if (memcmp(buf, "KMS1", 4) != 0) return KELP_ERR_PARSE;
    rbuf r = { buf, len, 4, false };
    memset(p, 0, sizeof *p);
    uint64_t kind = get(&r, 1);
    p->src = (uint8_t)get(&r, 1);
    p->dest = (uint8_t)get(&r, 1);
    p->cmd = (uint8_t)get(&r, 1);
    p->adr1 = (uint8_t)get(&r, 1);
    p->adr2 = (uint8_t)get(&r, 1);
    p->rate = (uint8_t)get(&r, 1);
    p->ack = (uint8_t)get(&r, 1);
    p->nframes = (uint8_t)get(&r, 1);
    p->instance = (uint32_t)get(&r, 4);
    p->seq = (uint32_t)get(&r, 4);
    p->ack_mask = (uint32_t)get(&r, 4);
    p->mini = (uint16_t)get(&r, 2);
    const int64_t start_us = (int64_t)get(&r, 8), duration_us = (int64_t)get(&r, 8),
                  turnaround_us = (int64_t)get(&r, 8);
    p->x = get_f64(&r);
    p->y = get_f64(&r);
    p->depth = get_f64(&r);
    if (r.short_) return KELP_ERR_TRUNCATED;
    if (!kind_ok((int)kind)) return KELP_ERR_PARSE;
    p->kind = (kelp_modemsim_pkt_kind)kind;
    if (p->rate > 5 || p->ack > 1) return KELP_ERR_PARSE;
    if (p->src > KELP_MODEMSIM_MAX_ID || p->dest > KELP_MODEMSIM_MAX_ID || p->adr1 > KELP_MODEMSIM_MAX_ID ||
        p->adr2 > KELP_MODEMSIM_MAX_ID)
        return KELP_ERR_PARSE;
    if (p->nframes > kelp_modemsim_rate_frames[p->rate] || p->nframes > KELP_MAX_MM_FRAMES) return KELP_ERR_RANGE;
    if (p->kind == KELP_MODEMSIM_PKT_DATA && p->nframes == 0) return KELP_ERR_PARSE;
    if (p->mini > 0x1fff) return KELP_ERR_RANGE;
    if (duration_us < 0 || duration_us > INT64_C(3600000000) || turnaround_us < 0 || turnaround_us > INT64_C(3600000000))
        return KELP_ERR_RANGE;
    if (start_us < -WIRE_START_MAX_US || start_us > WIRE_START_MAX_US) return KELP_ERR_RANGE;
    p->start = (kelp_time)start_us / 1e6;
    p->duration = (kelp_time)duration_us / 1e6;
    p->turnaround = (kelp_time)turnaround_us / 1e6;
    if (!isfinite(p->x) || !isfinite(p->y) || !isfinite(p->depth)) return KELP_ERR_RANGE;
    if (fabs(p->x) > 1e9 || fabs(p->y) > 1e9 || fabs(p->depth) > 1e6) return KELP_ERR_RANGE;
    unsigned nf = p->kind == KELP_MODEMSIM_PKT_DATA ? p->nframes : 0;
    for (unsigned i = 0; i < nf; i++) {
        kelp_modemsim_frame *f = &p->frame[i];
        f->src = (uint8_t)get(&r, 1);
        f->dest = (uint8_t)get(&r, 1);
        uint64_t a = get(&r, 1);
        uint64_t fl = get(&r, 2);
        if (r.short_) return KELP_ERR_TRUNCATED;
        if (a > 1 || f->src > KELP_MODEMSIM_MAX_ID || f->dest > KELP_MODEMSIM_MAX_ID) return KELP_ERR_PARSE;
        if (fl > kelp_modemsim_rate_bytes[p->rate] || fl > KELP_MAX_ACOMMS_FRAME) return KELP_ERR_RANGE;
        f->ack = a == 1;
        f->len = (uint16_t)fl;
        if (r.len - r.n < fl) return KELP_ERR_TRUNCATED;
        if (fl) memcpy(f->data, r.p + r.n, fl);
        r.n += fl;
    }
    if (r.n != r.len) return KELP_ERR_PARSE; /* trailing bytes */
    return KELP_OK;
}
