/* kelp: WHOI Micro-Modem driver core (Goby 1.1 MMDriver behaviour). */
#include <kelp/mmdriver.h>
#include <kelp/util.h>

#include <math.h>
#include <string.h>

#define US_PER_S 1000000LL
#define US_PER_DAY (86400LL * US_PER_S)
#define ROUGH_SPEED_OF_SOUND 1500
#define REMUS_LBL_TURN_AROUND_MS 50
#define TOA_MAX_RANGE 10000
#define HYDROID_PREFIX_LEN 3

const unsigned kelp_mmdriver_packet_frames[6] = { 1, 3, 3, 2, 2, 8 };
const unsigned kelp_mmdriver_packet_size[6] = { 32, 32, 64, 256, 256, 256 };


/* ------------------------------------------------------------------ time helpers */

/* The driver's timers count whole microseconds (Goby's boost clocks; the one-second $CCCLK
 * hold must end exactly): every kelp_time is converted here, once per call. */
static int64_t mm_us(kelp_time t)
{
    return (int64_t)llround(t * 1e6);
}

static kelp_time mm_time(int64_t us)
{
    return (kelp_time)us / 1e6;
}

void kelp_mmdriver_civil(kelp_time t, int *year, int *month, int *day, int *hour, int *minute, int *second)
{
    const int64_t unix_us = mm_us(t);
    int64_t days = kelp_util_floor_div(unix_us, US_PER_DAY);
    int64_t tod = (unix_us - days * US_PER_DAY) / US_PER_S;
    int64_t y;
    unsigned m, d;
    kelp_util_civil_from_days(days, &y, &m, &d);
    if (year) *year = (int)y;
    if (month) *month = (int)m;
    if (day) *day = (int)d;
    if (hour) *hour = (int)(tod / 3600);
    if (minute) *minute = (int)(tod / 60 % 60);
    if (second) *second = (int)(tod % 60);
}

/* nmea_time2ptime: "HHMMSS[.ffff]" on today's UTC date; false = not_a_date_time */
static bool nmea_time(const char *t, int64_t now_us, int64_t *out)
{
    size_t n = strlen(t);
    if (n < 6) return false;
    int v[3];
    for (int i = 0; i < 3; i++) {
        if (t[2 * i] < '0' || t[2 * i] > '9' || t[2 * i + 1] < '0' || t[2 * i + 1] > '9') return false;
        v[i] = (t[2 * i] - '0') * 10 + (t[2 * i + 1] - '0');
    }
    int64_t micro = 0;
    if (n > 7) {
        const char *fs = t + 7;
        size_t nf = strlen(fs);
        if (nf > 9) return false; /* lexical_cast<int> overflow */
        int64_t f = 0;
        for (size_t i = 0; i < nf; i++) {
            if (fs[i] < '0' || fs[i] > '9') return false;
            f = f * 10 + (fs[i] - '0');
        }
        micro = (int64_t)((double)f * pow(10.0, 6.0 - (double)nf));
    }
    int64_t midnight = kelp_util_floor_div(now_us, US_PER_DAY) * US_PER_DAY;
    *out = midnight + ((int64_t)v[0] * 3600 + v[1] * 60 + v[2]) * US_PER_S + micro;
    return true;
}

/* ------------------------------------------------------------------ events and writing */


static void ev_init(kelp_mmdriver_event *ev, kelp_mmdriver_event_kind kind, int64_t now_us)
{
    memset(ev, 0, sizeof *ev);
    ev->kind = kind;
    ev->time = mm_time(now_us);
    ev->raw = "";
}

static void emit(kelp_mmdriver *mm, const kelp_mmdriver_event *ev)
{
    if (mm->ops.event) mm->ops.event(ev, mm->user);
}

static void emit_simple(kelp_mmdriver *mm, kelp_mmdriver_event_kind kind, const char *raw, size_t len, int err, int64_t now_us)
{
    kelp_mmdriver_event ev;
    ev_init(&ev, kind, now_us);
    ev.raw = raw ? raw : "";
    ev.raw_len = raw ? len : 0;
    ev.err = err;
    ev.clock_ok = mm->clock_set;
    emit(mm, &ev);
}

static void set_clock_state(kelp_mmdriver *mm, bool ok, int64_t now_us)
{
    if (mm->clock_set == ok) return;
    mm->clock_set = ok;
    emit_simple(mm, KELP_MMDRIVER_EV_CLOCK, NULL, 0, 0, now_us);
}

static void mm_write(kelp_mmdriver *mm, const kelp_mmdriver_cmd *c, int64_t now_us)
{
    /* mm->wbuf is filled after the event, right before the write: an event handler that
     * writes again does not clobber it */
    char *buf = mm->wbuf;
    size_t pl = strlen(mm->prefix);
    mm->count.lines_out++;
    emit_simple(mm, KELP_MMDRIVER_EV_NMEA_OUT, c->line, c->len, 0, now_us);
    memcpy(buf, mm->prefix, pl);
    memcpy(buf + pl, c->line, c->len);
    buf[pl + c->len] = '\r';
    buf[pl + c->len + 1] = '\n';
    buf[pl + c->len + 2] = '\0';
    if (mm->ops.write) mm->ops.write(buf, pl + c->len + 2, mm->user);
}

static kelp_mmdriver_cmd *front(kelp_mmdriver *mm)
{
    return mm->out_n ? &mm->outq[mm->out_head] : NULL;
}

static void pop_out(kelp_mmdriver *mm)
{
    mm->waiting = false;
    if (mm->out_n) {
        mm->out_head = (mm->out_head + 1) % KELP_MAX_MM_OUTQ;
        mm->out_n--;
    }
    mm->present_fail = 0;
}

static void clear_out(kelp_mmdriver *mm)
{
    mm->out_head = 0;
    mm->out_n = 0;
}

static bool holding(const kelp_mmdriver *mm, int64_t now_us)
{
    return now_us < mm_us(mm->hold_until);
}

/* count one failure of the pending command; false when the command queue was given up or the
 * modem declared dead (nothing to write) */
static bool count_failure(kelp_mmdriver *mm, int64_t now_us)
{
    mm->global_fail++;
    mm->present_fail++;
    mm->count.retries++;
    if (mm->global_fail == KELP_MMDRIVER_MAX_FAILS_BEFORE_DEAD) {
        mm->dead = true;
        mm->count.deaths++;
        (void)kelp_fail(&mm->diag, KELP_ERR_TIMEOUT, "mmdriver: modem appears to not be responding");
        emit_simple(mm, KELP_MMDRIVER_EV_DEAD, NULL, 0, KELP_ERR_TIMEOUT, now_us);
        return false;
    }
    if (mm->present_fail == KELP_MMDRIVER_RETRIES) {
        mm->count.give_ups++;
        kelp_mmdriver_cmd *f = front(mm);
        emit_simple(mm, KELP_MMDRIVER_EV_GIVE_UP, f ? f->line : NULL, f ? f->len : 0, KELP_ERR_TIMEOUT, now_us);
        clear_out(mm);
        return false;
    }
    kelp_mmdriver_cmd *f = front(mm);
    emit_simple(mm, KELP_MMDRIVER_EV_RETRY, f ? f->line : NULL, f ? f->len : 0, 0, now_us);
    return true;
}

static void try_send(kelp_mmdriver *mm, int64_t now_us)
{
    if (mm->dead || !mm->out_n || holding(mm, now_us)) return;
    bool resend = mm->waiting && mm_us(mm->last_write) <= now_us - KELP_MMDRIVER_MODEM_WAIT * US_PER_S;
    if (mm->waiting && !resend) return;
    if (resend && !count_failure(mm, now_us)) return;
    mm_write(mm, front(mm), now_us);
    mm->waiting = true;
    mm->last_write = mm_time(now_us);
}

static int append(kelp_mmdriver *mm, kelp_nmea_writer *w, int64_t now_us)
{
    size_t len;
    int rc = kelp_nmea_writer_finish(w, &len);
    if (rc) return kelp_fail(&mm->diag, rc, "mmdriver: sentence too long");
    if (mm->out_n >= KELP_MAX_MM_OUTQ) return kelp_fail(&mm->diag, KELP_ERR_NOSPACE, "mmdriver: command queue full");
    kelp_mmdriver_cmd *c = &mm->outq[(mm->out_head + mm->out_n) % KELP_MAX_MM_OUTQ];
    memcpy(c->line, w->buf, len + 1);
    c->len = len;
    memcpy(c->id, c->line + 3, 3);
    c->id[3] = '\0';
    mm->out_n++;
    try_send(mm, now_us);
    return KELP_OK;
}

static int set_clock(kelp_mmdriver *mm, int64_t now_us)
{
    char buf[64];
    kelp_nmea_writer w;
    int y, mo, d, h, mi, s;
    kelp_mmdriver_civil(mm_time(now_us), &y, &mo, &d, &h, &mi, &s);
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CCCLK");
    kelp_nmea_writer_long(&w, y);
    kelp_nmea_writer_long(&w, mo);
    kelp_nmea_writer_long(&w, d);
    kelp_nmea_writer_long(&w, h);
    kelp_nmea_writer_long(&w, mi);
    kelp_nmea_writer_long(&w, s);
    int rc = append(mm, &w, now_us);
    mm->hold_until = mm_time(now_us + US_PER_S); /* sleep(1): let the clock be set */
    return rc;
}

static int write_single_cfg(kelp_mmdriver *mm, const char *s, int64_t now_us)
{
    char buf[KELP_MAX_MM_NVRAM_LEN + 16];
    char up[KELP_MAX_MM_NVRAM_LEN];
    size_t i = 0;
    for (; s[i] && i + 1 < sizeof up; i++) up[i] = (s[i] >= 'a' && s[i] <= 'z') ? (char)(s[i] - 32) : s[i];
    up[i] = '\0';
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CCCFG");
    kelp_nmea_writer_str(&w, up);
    return append(mm, &w, now_us);
}

/* ------------------------------------------------------------------ configuration */

int kelp_mmdriver_init(kelp_mmdriver *mm, const kelp_mmdriver_cfg *cfg, const kelp_mmdriver_ops *ops, void *user)
{
    if (!mm || !cfg) return KELP_ERR_ARG;
    memset(mm, 0, sizeof *mm);
    if (cfg->modem_id < 1 || cfg->modem_id > 31) return KELP_ERR_ARG;
    if (cfg->n_nvram > KELP_MAX_MM_NVRAM) return KELP_ERR_NOSPACE;
    if (cfg->hydroid_gateway_id < 0 || cfg->hydroid_gateway_id > 99) return KELP_ERR_ARG;
    mm->modem_id = cfg->modem_id;
    mm->reset_nvram = cfg->reset_nvram;
    for (size_t i = 0; i < cfg->n_nvram; i++) {
        const char *s = cfg->nvram_cfg[i];
        if (!s || !*s) return KELP_ERR_ARG;
        size_t n = strlen(s);
        if (n >= KELP_MAX_MM_NVRAM_LEN) return KELP_ERR_NOSPACE;
        for (size_t k = 0; k < n; k++)
            if (s[k] == '*' || s[k] == '$' || s[k] == '\r' || s[k] == '\n') return KELP_ERR_ARG;
        memcpy(mm->nvram[i], s, n + 1);
    }
    mm->n_nvram = cfg->n_nvram;
    mm->hydroid_id = cfg->hydroid_gateway_id;
    if (mm->hydroid_id) {
        kelp_nmea_writer w; /* reuse the integer formatter: "#M" + id */
        char tmp[12];
        kelp_nmea_writer_init(&w, tmp, sizeof tmp, "");
        kelp_nmea_writer_long(&w, mm->hydroid_id);
        mm->prefix[0] = '#';
        mm->prefix[1] = 'M';
        memcpy(mm->prefix + 2, tmp + 1, w.len - 1);
        mm->prefix[2 + w.len - 1] = '\0';
    }
    if (ops) mm->ops = *ops;
    mm->user = user;
    kelp_nmea_reader_init(&mm->rd, cfg->line_delimiter);
    return KELP_OK;
}

/* The time step rule (docs/ARCHITECTURE.md): every entry point that takes `now` comes through
 * here.  A backward step moves the driver's stored times back as far, so the pause after $CCCLK,
 * the wait for a reply and the GPS interval keep what remained of them; and the modem's clock,
 * set from ours, is now ahead by the step: beyond the allowed skew it is set again (one $CCCLK
 * when the command queue is idle).  A forward step is elapsed time: at most one re-send, and
 * the modem's next $CAREV shows its clock behind (as Goby checks). */
static int mm_enter(kelp_mmdriver *mm, kelp_time now, int64_t *now_us)
{
    if (!mm || !kelp_util_time_ok(now)) return KELP_ERR_ARG;
    *now_us = mm_us(now);
    double back = kelp_util_clock_back(&mm->clock, now);
    if (back > 0.0) {
        mm->count.clock_steps++;
        if (mm->hold_until > 0) mm->hold_until -= back;
        mm->last_write -= back;
        mm->last_gps -= back;
        if (back > KELP_MMDRIVER_ALLOWED_SKEW) mm->clock_set = false;
    }
    return KELP_OK;
}

int kelp_mmdriver_start(kelp_mmdriver *mm, kelp_time now)
{
    int64_t now_us;
    if (mm_enter(mm, now, &now_us) != KELP_OK || mm->modem_id < 1) return KELP_ERR_ARG;
    clear_out(mm);
    mm->waiting = false;
    mm->global_fail = mm->present_fail = 0;
    mm->clock_set = false;
    mm->dead = false;
    mm->local_cccyc = false;
    mm->hold_until = 0;
    mm->backlog_len = 0;
    mm->ncache = 0;
    mm->ack_mask = 0;
    mm->toa_pending = false;
    mm->last_write = mm_time(now_us);
    mm->last_gps = mm_time(now_us);
    kelp_nmea_reader_init(&mm->rd, mm->rd.delim);
    mm->started = true;
    int rc = set_clock(mm, now_us);
    if (!rc && !mm->hydroid_id && mm->reset_nvram) rc = write_single_cfg(mm, "ALL,0", now_us);
    if (!rc) {
        char src[16];
        kelp_nmea_writer w;
        kelp_nmea_writer_init(&w, src, sizeof src, "SRC");
        kelp_nmea_writer_long(&w, mm->modem_id);
        src[w.len] = '\0';
        rc = write_single_cfg(mm, src, now_us);
    }
    for (size_t i = 0; !rc && i < mm->n_nvram; i++) rc = write_single_cfg(mm, mm->nvram[i], now_us);
    if (!rc) {
        char buf[32];
        kelp_nmea_writer w;
        kelp_nmea_writer_init(&w, buf, sizeof buf, "$CCCFQ,ALL");
        rc = append(mm, &w, now_us);
    }
    return rc;
}

kelp_time kelp_mmdriver_busy_until(const kelp_mmdriver *mm)
{
    return mm->hold_until;
}

bool kelp_mmdriver_clock_ok(const kelp_mmdriver *mm)
{
    return mm->clock_set;
}

size_t kelp_mmdriver_pending(const kelp_mmdriver *mm)
{
    return mm->out_n;
}

/* ------------------------------------------------------------------ outgoing cycles */

static int cache_outgoing(kelp_mmdriver *mm, int src, int dest, unsigned rate, unsigned nframes, int64_t now_us)
{
    (void)now_us;
    if (src != mm->modem_id) return KELP_OK;
    if (rate > 5) return kelp_fail(&mm->diag, KELP_ERR_RANGE, "mmdriver: rate out of range (0..5)");
    mm->ncache = 0; /* flush frames never asked for by a $CADRQ */
    mm->ack_mask = 0;
    if (nframes > KELP_MAX_MM_FRAMES) nframes = KELP_MAX_MM_FRAMES;
    for (unsigned i = 0; i < nframes; i++) {
        kelp_mmdriver_data_request req;
        req.src = src;
        req.dest = dest;
        req.frame = i;
        req.max_bytes = kelp_mmdriver_packet_size[rate];
        kelp_mmdriver_frame *f = &mm->cache[mm->ncache];
        memset(f, 0, sizeof *f);
        if (mm->ops.data_request) mm->ops.data_request(&req, f, mm->user);
        if (f->len == 0) break; /* no more data */
        if (f->len > req.max_bytes) f->len = req.max_bytes;
        mm->ncache++;
    }
    return KELP_OK;
}

/* $CCCYC for a cycle whose frames are cached (local) or that another modem sends */
static int write_cycle(kelp_mmdriver *mm, int src, int dest, unsigned rate, int64_t now_us)
{
    bool local = (src == mm->modem_id);
    char buf[96];
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CCCYC");
    kelp_nmea_writer_long(&w, 0);                                     /* CMD (deprecated) */
    kelp_nmea_writer_long(&w, src);                                   /* ADR1 */
    kelp_nmea_writer_long(&w, local ? mm->cache[0].dest : dest);      /* ADR2 */
    kelp_nmea_writer_long(&w, (long)rate);                            /* packet type */
    kelp_nmea_writer_long(&w, local ? (mm->cache[0].ack_requested ? 1 : 0) : 1); /* ACK */
    kelp_nmea_writer_long(&w, (long)kelp_mmdriver_packet_frames[rate]);
    return append(mm, &w, now_us);
}

int kelp_mmdriver_initiate_transmission(kelp_mmdriver *mm, int src, int dest, unsigned rate, kelp_time now)
{
    int64_t now_us;
    if (mm_enter(mm, now, &now_us) != KELP_OK) return KELP_ERR_ARG;
    if (!mm->started) return KELP_ERR_STATE;
    if (rate > 5) return kelp_fail(&mm->diag, KELP_ERR_RANGE, "mmdriver: rate out of range (0..5)");
    mm->local_cccyc = true; /* we initiated: don't fetch data again on the $CACYC echo */
    int rc = cache_outgoing(mm, src, dest, rate, kelp_mmdriver_packet_frames[rate], now_us);
    if (rc) return rc;
    if (src == mm->modem_id && mm->ncache == 0) return KELP_OK; /* no data: no cycle */
    return write_cycle(mm, src, dest, rate, now_us);
}

int kelp_mmdriver_transmit_frames(kelp_mmdriver *mm, unsigned rate, const kelp_mmdriver_frame *frames, size_t n, kelp_time now)
{
    int64_t now_us;
    if ((n && !frames) || mm_enter(mm, now, &now_us) != KELP_OK) return KELP_ERR_ARG;
    if (!mm->started) return KELP_ERR_STATE;
    if (rate > 5) return kelp_fail(&mm->diag, KELP_ERR_RANGE, "mmdriver: rate out of range (0..5)");
    if (n == 0) return KELP_OK; /* no data: no cycle, as a local slot with an empty queue */
    if (n > kelp_mmdriver_packet_frames[rate]) {
        return kelp_fail(&mm->diag, KELP_ERR_RANGE, "mmdriver: more frames than the rate carries");
    }
    mm->local_cccyc = true;
    mm->ncache = 0;
    mm->ack_mask = 0;
    for (size_t i = 0; i < n; i++) {
        kelp_mmdriver_frame *f = &mm->cache[mm->ncache++];
        *f = frames[i];
        f->src = mm->modem_id;
        if (f->len > kelp_mmdriver_packet_size[rate]) f->len = kelp_mmdriver_packet_size[rate];
    }
    return write_cycle(mm, mm->modem_id, frames[0].dest, rate, now_us);
}

int kelp_mmdriver_initiate_ranging(kelp_mmdriver *mm, int src, int dest, kelp_ranging_type type, unsigned max_range,
                             unsigned enable_beacons, kelp_time now)
{
    int64_t now_us;
    if (mm_enter(mm, now, &now_us) != KELP_OK) return KELP_ERR_ARG;
    if (!mm->started) return KELP_ERR_STATE;
    char buf[96];
    kelp_nmea_writer w;
    switch (type) {
    case KELP_RANGING_TWO_WAY_PING:
        kelp_nmea_writer_init(&w, buf, sizeof buf, "$CCMPC");
        kelp_nmea_writer_long(&w, src);
        kelp_nmea_writer_long(&w, dest);
        return append(mm, &w, now_us);
    case KELP_RANGING_REMUS_LBL:
        kelp_nmea_writer_init(&w, buf, sizeof buf, "$CCPDT");
        kelp_nmea_writer_long(&w, 1);                              /* group */
        kelp_nmea_writer_long(&w, (long)((unsigned)src % 4 + 1));  /* channel 1..4 */
        kelp_nmea_writer_long(&w, 0);
        kelp_nmea_writer_long(&w, 0);
        kelp_nmea_writer_long(&w, (long)((max_range * 2.0 / ROUGH_SPEED_OF_SOUND) * 1000 + REMUS_LBL_TURN_AROUND_MS));
        for (unsigned b = 0; b < 4; b++) kelp_nmea_writer_long(&w, (long)((enable_beacons >> b) & 1u));
        return append(mm, &w, now_us);
    case KELP_RANGING_ONE_WAY_SYNCHRONOUS:
    default:
        return kelp_fail(&mm->diag, KELP_ERR_UNSUPPORTED, "mmdriver: ONE_WAY_SYNCHRONOUS cannot be requested (enable NVRAM TOA,1)");
    }
}

/* ------------------------------------------------------------------ incoming sentences */

static int field_u(const kelp_nmea_sentence *s, unsigned i, long *v)
{
    return kelp_nmea_field_long(s, i, v);
}

static void flush_toa(kelp_mmdriver *mm, int src, int64_t now_us)
{
    if (!mm->toa_pending) return;
    kelp_mmdriver_event ev;
    ev_init(&ev, KELP_MMDRIVER_EV_RANGE, now_us);
    ev.ranging = KELP_RANGING_ONE_WAY_SYNCHRONOUS;
    ev.has_src = true;
    ev.src = src;
    ev.dest = mm->modem_id;
    /* i = 0 .. MAX_RANGE / speed of sound (10000 / 1500 = 6): 7 candidates */
    _Static_assert(TOA_MAX_RANGE / ROUGH_SPEED_OF_SOUND + 1 <= 7, "tt[] holds 7 travel times");
    for (int i = 0; i <= TOA_MAX_RANGE / ROUGH_SPEED_OF_SOUND; i++) ev.tt[ev.n_tt++] = mm->toa_frac + i;
    mm->toa_pending = false;
    emit(mm, &ev);
}

static int drq(kelp_mmdriver *mm, const kelp_nmea_sentence *s, int64_t now_us)
{
    if (s->nfields < 5) return KELP_ERR_PARSE;
    long f = 0;
    bool cached = field_u(s, 6, &f) == KELP_OK && f >= 1 && (unsigned long)(f - 1) < mm->ncache;
    kelp_nmea_writer w;
    /* built in mm->wbuf: append() copies it into the command queue before anything writes */
    kelp_nmea_writer_init(&w, mm->wbuf, KELP_MAX_NMEA_LINE + 1, "$CCTXD");
    if (cached) {
        const kelp_mmdriver_frame *fr = &mm->cache[f - 1];
        kelp_nmea_writer_long(&w, fr->src);
        kelp_nmea_writer_long(&w, fr->dest);
        kelp_nmea_writer_long(&w, fr->ack_requested ? 1 : 0);
        kelp_nmea_writer_hex(&w, fr->data, fr->len);
        if (fr->ack_requested && f - 1 < 32) mm->ack_mask |= 1u << (f - 1);
    } else {
        /* nothing cached: a blank to stop further requests, echoing SRC, DEST, ACK */
        kelp_nmea_writer_str(&w, kelp_nmea_field(s, 2));
        kelp_nmea_writer_str(&w, kelp_nmea_field(s, 3));
        kelp_nmea_writer_str(&w, kelp_nmea_field(s, 4));
        kelp_nmea_writer_str(&w, "");
    }
    return append(mm, &w, now_us);
}

static int clk(kelp_mmdriver *mm, const kelp_nmea_sentence *s, int64_t now_us)
{
    kelp_mmdriver_cmd *f = front(mm);
    if (!f || strcmp(f->id, "CLK") != 0) return KELP_OK;
    long v[6];
    for (unsigned i = 0; i < 6; i++)
        if (field_u(s, i + 1, &v[i]) != KELP_OK) return KELP_ERR_PARSE;
    if (v[1] < 1 || v[1] > 12 || v[2] < 1 || v[2] > 31 || v[0] < 1400 || v[0] > 9999) return KELP_ERR_RANGE;
    int64_t reported = (kelp_util_days_from_civil(v[0], (unsigned)v[1], (unsigned)v[2]) * 86400 + v[3] * 3600 + v[4] * 60 + v[5]) *
                       US_PER_S;
    if (reported >= now_us - KELP_MMDRIVER_ALLOWED_SKEW * US_PER_S) set_clock_state(mm, true, now_us);
    return KELP_OK;
}

static void rev(kelp_mmdriver *mm, const kelp_nmea_sentence *s, int64_t now_us)
{
    const char *what = kelp_nmea_field(s, 2);
    if (strcmp(what, "INIT") == 0) {
        mm->hold_until = mm_time(now_us + 2 * US_PER_S); /* sleep(WAIT_AFTER_REBOOT) */
        set_clock_state(mm, false, now_us);
    } else if (strcmp(what, "AUV") == 0) {
        int64_t reported;
        if (nmea_time(kelp_nmea_field(s, 1), now_us, &reported) && reported < now_us - KELP_MMDRIVER_ALLOWED_SKEW * US_PER_S)
            set_clock_state(mm, false, now_us);
    }
}

static void err_sentence(kelp_mmdriver *mm, const kelp_nmea_sentence *s, const char *raw, size_t rawlen, int64_t now_us)
{
    mm->count.modem_errors++;
    emit_simple(mm, KELP_MMDRIVER_EV_MODEM_ERROR, raw, rawlen, 0, now_us);
    /* the modem did not understand the pending command: one failure, re-send it now */
    if (strcmp(kelp_nmea_field(s, 2), "NMEA") == 0 && mm->out_n && mm->waiting) {
        if (count_failure(mm, now_us)) {
            mm_write(mm, front(mm), now_us);
            mm->waiting = true;
            mm->last_write = mm_time(now_us);
        }
    }
}

static void process_sentence(kelp_mmdriver *mm, const char *line, size_t len, int64_t now_us)
{
    kelp_nmea_sentence *s = &mm->s;
    int rc = kelp_nmea_parse(line, len, s);
    if (rc) {
        mm->count.bad_lines++;
        emit_simple(mm, KELP_MMDRIVER_EV_BAD_LINE, line, len, rc, now_us);
        return;
    }
    char *raw = mm->raw;
    size_t rawlen = 0;
    if (kelp_nmea_render(s, raw, sizeof mm->raw, &rawlen) != KELP_OK) {
        mm->count.bad_lines++;
        emit_simple(mm, KELP_MMDRIVER_EV_BAD_LINE, line, len, KELP_ERR_NOSPACE, now_us);
        return;
    }
    mm->global_fail = 0; /* the modem is alive */
    /* sub: the event a sentence gives (cycle, receive, ...), then the NMEA_IN event, whose
     * source is kept in ev_src until then */
    kelp_mmdriver_event sub;
    bool ev_has_src = false;
    int ev_src = 0;
    const char *id = s->id;
    long a = 0, b = 0, c = 0, d = 0;
    rc = KELP_OK;
    if (!strcmp(id, "REV")) {
        rev(mm, s, now_us);
    } else if (!strcmp(id, "ERR")) {
        err_sentence(mm, s, raw, rawlen, now_us);
    } else if (!strcmp(id, "DRQ")) {
        rc = drq(mm, s, now_us);
    } else if (!strcmp(id, "CFG")) {
        kelp_mmdriver_cmd *f = front(mm);
        if (f && !strcmp(f->id, "CFQ")) pop_out(mm); /* the first $CACFG also completes $CCCFQ */
    } else if (!strcmp(id, "CLK")) {
        rc = clk(mm, s, now_us);
    } else if (!strcmp(id, "CYC")) {
        /* $CACYC,CMD,ADR1,ADR2,RATE,ACK,NPKT */
        if (field_u(s, 2, &a) != KELP_OK || field_u(s, 3, &b) != KELP_OK || field_u(s, 4, &c) != KELP_OK ||
            field_u(s, 6, &d) != KELP_OK) {
            rc = KELP_ERR_PARSE;
        } else if (c < 0 || c > 5 || d < 0) {
            rc = KELP_ERR_RANGE;
        } else {
            kelp_mmdriver_event *cy = &sub;
            ev_init(cy, KELP_MMDRIVER_EV_CYCLE, now_us);
            cy->has_src = true;
            cy->src = (int)a;
            cy->dest = (int)b;
            cy->rate = (unsigned)c;
            cy->frame = (uint32_t)d;
            emit(mm, cy);
            ev_has_src = true;
            ev_src = (int)a;
            if (!mm->local_cccyc) rc = cache_outgoing(mm, (int)a, (int)b, (unsigned)c, (unsigned)d, now_us);
            else mm->local_cccyc = false;
        }
    } else if (!strcmp(id, "RXD")) {
        /* $CARXD,SRC,DEST,ACK,FRAME,HEX */
        kelp_mmdriver_event *rx = &sub;
        ev_init(rx, KELP_MMDRIVER_EV_RECEIVE, now_us);
        uint8_t *data = mm->rxdata;
        size_t dl = 0;
        const char *ackf = kelp_nmea_field(s, 3);
        if (field_u(s, 1, &a) != KELP_OK || field_u(s, 2, &b) != KELP_OK || field_u(s, 4, &d) != KELP_OK ||
            (strcmp(ackf, "0") != 0 && strcmp(ackf, "1") != 0) || s->nfields < 6) {
            rc = KELP_ERR_PARSE;
        } else if ((rc = kelp_util_hex_decode(kelp_nmea_field(s, 5), strlen(kelp_nmea_field(s, 5)), data, sizeof mm->rxdata, &dl)) == KELP_OK) {
            rx->has_src = true;
            rx->src = (int)a;
            rx->dest = (int)b;
            rx->ack_requested = ackf[0] == '1';
            rx->frame = (uint32_t)(d - 1); /* WHOI counts from 1 */
            rx->data = data;
            rx->data_len = dl;
            rx->raw = raw;
            rx->raw_len = rawlen;
            emit(mm, rx);
            ev_has_src = true;
            ev_src = (int)a;
            flush_toa(mm, (int)a, now_us);
        }
    } else if (!strcmp(id, "ACK")) {
        /* $CAACK,SRC,DEST,FRAME,ACK */
        if (field_u(s, 1, &a) != KELP_OK || field_u(s, 2, &b) != KELP_OK || field_u(s, 3, &c) != KELP_OK) {
            rc = KELP_ERR_PARSE;
        } else {
            uint32_t fr = (uint32_t)(c - 1);
            if (fr < 32 && (mm->ack_mask & (1u << fr))) {
                kelp_mmdriver_event *ak = &sub;
                ev_init(ak, KELP_MMDRIVER_EV_ACK, now_us);
                ak->has_src = true;
                ak->src = (int)a;
                ak->dest = (int)b;
                ak->frame = fr;
                ak->raw = raw;
                ak->raw_len = rawlen;
                emit(mm, ak);
            }
            ev_has_src = true;
            ev_src = (int)a;
            flush_toa(mm, (int)a, now_us);
        }
    } else if (!strcmp(id, "MPR")) {
        /* $CAMPR,SRC,DEST,TRAVELTIME: reply src/dest swapped back to match the request */
        mm->toa_pending = false;
        if (field_u(s, 1, &a) != KELP_OK || field_u(s, 2, &b) != KELP_OK) {
            rc = KELP_ERR_PARSE;
        } else {
            kelp_mmdriver_event *rg = &sub;
            ev_init(rg, KELP_MMDRIVER_EV_RANGE, now_us);
            rg->ranging = KELP_RANGING_TWO_WAY_PING;
            rg->has_src = true;
            rg->src = (int)b;
            rg->dest = (int)a;
            if (s->nfields > 3) {
                double t;
                rg->tt[rg->n_tt++] = kelp_nmea_field_double(s, 3, &t) == KELP_OK ? t : (double)NAN;
            }
            rg->raw = raw;
            rg->raw_len = rawlen;
            emit(mm, rg);
            ev_has_src = true;
            ev_src = (int)b;
        }
    } else if (!strcmp(id, "TTA")) {
        /* $SNTTA,T1,T2,T3,T4,HHMMSS.SS */
        mm->toa_pending = false;
        kelp_mmdriver_event *rg = &sub;
        ev_init(rg, KELP_MMDRIVER_EV_RANGE, now_us);
        rg->ranging = KELP_RANGING_REMUS_LBL;
        rg->has_src = true;
        rg->src = mm->modem_id;
        for (unsigned i = 1; i <= 4; i++) {
            double t;
            rg->tt[rg->n_tt++] = kelp_nmea_field_double(s, i, &t) == KELP_OK ? t : (double)NAN;
        }
        rg->raw = raw;
        rg->raw_len = rawlen;
        emit(mm, rg);
        ev_has_src = true;
        ev_src = mm->modem_id;
    } else if (!strcmp(id, "TOA")) {
        /* $CATOA,HHMMSS.ssss,MODE: only mode 3 (PPS and $CCCLK good) is used */
        mm->toa_pending = false;
        int64_t t;
        if (field_u(s, 2, &a) == KELP_OK && a == 3 && nmea_time(kelp_nmea_field(s, 1), now_us, &t)) {
            int64_t us = t - kelp_util_floor_div(t, US_PER_S) * US_PER_S;
            mm->toa_frac = (double)us / 1e6;
            mm->toa_pending = true;
        }
    } else if (!strcmp(id, "RXP")) {
        mm->toa_pending = false; /* a pending TOA that was never flushed */
    }
    if (rc) {
        /* Goby throws out of the handler: the line is logged and dropped */
        mm->count.bad_lines++;
        emit_simple(mm, KELP_MMDRIVER_EV_BAD_LINE, raw, rawlen, rc, now_us);
        return;
    }
    mm->count.lines_in++;
    ev_init(&sub, KELP_MMDRIVER_EV_NMEA_IN, now_us);
    sub.has_src = ev_has_src;
    sub.src = ev_src;
    sub.raw = raw;
    sub.raw_len = rawlen;
    emit(mm, &sub);
    kelp_mmdriver_cmd *f = front(mm);
    if (f && !strcmp(f->id, id)) pop_out(mm); /* the modem answered the pending command */
}

static void process_line(kelp_mmdriver *mm, const char *line, size_t len, int64_t now_us)
{
    if (mm->hydroid_id) {
        size_t k = len < HYDROID_PREFIX_LEN ? len : HYDROID_PREFIX_LEN;
        line += k;
        len -= k;
    }
    process_sentence(mm, line, len, now_us);
}

static void feed_byte(kelp_mmdriver *mm, uint8_t byte, int64_t now_us)
{
    const char *line;
    size_t len;
    int rc = kelp_nmea_reader_feed(&mm->rd, byte, &line, &len);
    if (rc == KELP_ERR_PARTIAL) return;
    if (rc != KELP_OK) {
        mm->count.bad_lines++;
        emit_simple(mm, KELP_MMDRIVER_EV_BAD_LINE, NULL, 0, rc, now_us);
        return;
    }
    process_line(mm, line, len, now_us);
}

/* Bytes held during a pause are read the moment the pause ends (as a driver that sleeps and
 * then reads in the same step), so a reply's freshness is judged at that moment, whenever
 * the caller's next feed or tick comes. */
static void drain_backlog(kelp_mmdriver *mm, int64_t now_us)
{
    if (mm->hold_until > 0 && mm_us(mm->hold_until) <= now_us) now_us = mm_us(mm->hold_until);
    size_t i = 0;
    while (i < mm->backlog_len && !holding(mm, now_us)) feed_byte(mm, mm->backlog[i++], now_us);
    memmove(mm->backlog, mm->backlog + i, mm->backlog_len - i);
    mm->backlog_len -= i;
}

int kelp_mmdriver_feed(kelp_mmdriver *mm, const uint8_t *bytes, size_t n, kelp_time now)
{
    int64_t now_us;
    if ((n && !bytes) || mm_enter(mm, now, &now_us) != KELP_OK) return KELP_ERR_ARG;
    if (!mm->started) return KELP_ERR_STATE;
    if (!holding(mm, now_us) && mm->backlog_len) drain_backlog(mm, now_us);
    for (size_t i = 0; i < n; i++) {
        if (holding(mm, now_us) || mm->backlog_len) {
            if (mm->backlog_len < sizeof mm->backlog) mm->backlog[mm->backlog_len++] = bytes[i];
            else mm->count.backlog_dropped++;
        } else {
            feed_byte(mm, bytes[i], now_us);
        }
    }
    return KELP_OK;
}

int kelp_mmdriver_tick(kelp_mmdriver *mm, kelp_time now)
{
    int64_t now_us;
    if (mm_enter(mm, now, &now_us) != KELP_OK) return KELP_ERR_ARG;
    if (!mm->started) return KELP_ERR_STATE;
    if (mm->dead) return KELP_ERR_TIMEOUT;
    if (holding(mm, now_us)) return KELP_OK;
    /* don't set the clock while commands are queued: the time would be stale when sent */
    if (!mm->clock_set && mm->out_n == 0) {
        int rc = set_clock(mm, now_us);
        if (rc) return rc;
        return KELP_OK; /* sleeping */
    }
    try_send(mm, now_us);
    if (mm->dead) return KELP_ERR_TIMEOUT;
    if (mm->backlog_len) drain_backlog(mm, now_us);
    if (mm->hydroid_id && mm_us(mm->last_gps) + KELP_MMDRIVER_HYDROID_GPS_INTERVAL * US_PER_S < now_us) {
        char q[16];
        kelp_nmea_writer w;
        kelp_nmea_writer_init(&w, q, sizeof q, "");
        kelp_nmea_writer_long(&w, mm->hydroid_id);
        char out[20];
        out[0] = '#';
        out[1] = 'G';
        memcpy(out + 2, q + 1, w.len - 1);
        size_t n = 2 + w.len - 1;
        out[n++] = '\r';
        out[n++] = '\n';
        out[n] = '\0';
        if (mm->ops.write) mm->ops.write(out, n, mm->user);
        mm->last_gps = mm_time(now_us);
    }
    return mm->dead ? KELP_ERR_TIMEOUT : KELP_OK;
}
