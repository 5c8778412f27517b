/* kelp modemsim: one simulated WHOI Micro-Modem (the modem side of the NMEA protocol). */
#include <kelp/mmdriver.h>
#include <kelp/modemsim.h>
#include <kelp/util.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#define US_PER_S 1000000LL
#define US_PER_DAY (86400LL * US_PER_S)
#define EPOCH_2000_US (946684800LL * US_PER_S)
#define STALE_US (2 * US_PER_S)       /* an arrival that ended this long before it was heard */
#define KEEP_DECIDED_US (15 * US_PER_S) /* decided arrivals kept for collision checks */
#define LATE_START_US (200000LL)       /* a transmission never starts further in the past */
#define MINI_BYTES 2u                  /* $CATXP/$CATXF byte count of a mini-packet */

/* Host-error numbers of $CAERR,hhmmss,NMEA,<n>,<text> (the simulator's own choice) */
enum { ERR_SYNTAX = 1, ERR_CHECKSUM = 2, ERR_TALKER = 3, ERR_UNKNOWN = 4, ERR_FIELD = 5, ERR_STATE = 6 };

/* NVRAM parameters the simulated modem knows, with the simulator's defaults (SRC = modem_id). */
static const struct {
    const char *name;
    long value;
} NV_DEFAULTS[] = {
    { "AGC", 1 }, { "AGN", 250 }, { "ASD", 0 }, { "BBD", 0 }, { "BND", 3 }, { "BR1", 3 }, { "BR2", 3 },
    { "CPR", 1 }, { "CRL", 50 }, { "CST", 0 }, { "CTO", 10 }, { "DBG", 0 }, { "DGM", 0 }, { "DOP", 1 },
    { "DQF", 1 }, { "DTH", 108 }, { "DTO", 2 }, { "DTP", 90 }, { "ECD", 50 }, { "EFF", 100 }, { "EX1", 0 },
    { "FMD", 0 }, { "FML", 200 }, { "GPS", 0 }, { "IRE", 0 }, { "MCM", 1 }, { "MFD", 1 }, { "MOD", 0 },
    { "MPR", 1 }, { "MSE", 0 }, { "MVM", 1 }, { "NDT", 150 }, { "NPT", 50 }, { "NRL", 25 }, { "NRV", 150 },
    { "PCM", 0 }, { "POW", -100 }, { "PRL", 50 }, { "PTH", 180 }, { "PTO", 6 }, { "REV", 1 }, { "SGP", 0 },
    { "SHF", 0 }, { "SNR", 0 }, { "SRC", 0 }, { "TAT", 50 }, { "TOA", 0 }, { "TXD", 600 }, { "TXP", 15 },
    { "XST", 1 },
};
#define N_NV_DEFAULTS (sizeof NV_DEFAULTS / sizeof NV_DEFAULTS[0])
_Static_assert(N_NV_DEFAULTS <= KELP_MAX_MSIM_NVRAM, "KELP_MAX_MSIM_NVRAM too small for the NVRAM table");

static const char HEXL[] = "0123456789abcdef";

/* ------------------------------------------------------------------ small helpers */

static unsigned days_in_month(long y, long mo)
{
    static const unsigned dm[12] = { 31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31 };
    if (mo == 2 && ((y % 4 == 0 && y % 100 != 0) || y % 400 == 0)) return 29;
    return dm[mo - 1];
}

/* The simulator's clock counts whole microseconds (arrival overlaps, turnarounds and the
 * modem clock are exact): a kelp_time is converted here, once per call, and back for events. */
static int64_t us_of(double s)
{
    double u = s * 1e6;
    return (int64_t)(u >= 0 ? u + 0.5 : u - 0.5);
}

static kelp_time time_of(int64_t us)
{
    return (kelp_time)us / 1e6;
}

/* unsigned v as exactly `width` digits (zero padded) at b; returns chars written */
static size_t put_digits(char *b, unsigned long v, unsigned width)
{
    for (unsigned i = 0; i < width; i++) {
        b[width - 1 - i] = (char)('0' + v % 10);
        v /= 10;
    }
    b[width] = '\0';
    return width;
}

/* HHMMSS of a modem clock time */
static void hhmmss(int64_t clock_us, char out[7])
{
    int64_t tod = (clock_us - kelp_util_floor_div(clock_us, US_PER_DAY) * US_PER_DAY) / US_PER_S;
    (void)put_digits(out, (unsigned long)(tod / 3600), 2);
    (void)put_digits(out + 2, (unsigned long)(tod / 60 % 60), 2);
    (void)put_digits(out + 4, (unsigned long)(tod % 60), 2);
}

/* "%.<dec>f" for a non-negative double without printf (newlib-friendly) */
static void fixed(double v, unsigned dec, char *out, size_t cap)
{
    if (!(v >= 0) || v > 1e9) v = 0;
    double scale = 1;
    for (unsigned i = 0; i < dec; i++) scale *= 10;
    unsigned long long t = (unsigned long long)(v * scale + 0.5);
    unsigned long long ip = t / (unsigned long long)scale, fp = t % (unsigned long long)scale;
    char tmp[40];
    size_t n = 0;
    char rev[24];
    size_t r = 0;
    do {
        rev[r++] = (char)('0' + ip % 10);
        ip /= 10;
    } while (ip && r < sizeof rev);
    while (r) tmp[n++] = rev[--r];
    if (dec) {
        tmp[n++] = '.';
        n += put_digits(tmp + n, (unsigned long)fp, dec);
    }
    tmp[n] = '\0';
    if (n + 1 > cap) n = cap - 1;
    memcpy(out, tmp, n);
    out[n] = '\0';
}

static void emit(kelp_modemsim *m, kelp_modemsim_event_kind kind, const kelp_modemsim_pkt *p, unsigned frame, kelp_modemsim_loss loss,
                 const char *text, int err, int64_t now_us)
{
    if (!m->ops.event) return;
    kelp_modemsim_event ev;
    memset(&ev, 0, sizeof ev);
    ev.kind = kind;
    ev.time = time_of(now_us);
    ev.pkt = p;
    ev.frame = frame;
    ev.loss = loss;
    ev.text = text ? text : "";
    ev.err = err;
    m->ops.event(&ev, m->user);
}

static int src_id(const kelp_modemsim *m)
{
    for (size_t i = 0; i < m->n_nv; i++)
        if (!strcmp(m->nv[i].name, "SRC")) return (int)m->nv[i].value;
    return m->cfg.modem_id;
}

int kelp_modemsim_src(const kelp_modemsim *m)
{
    return src_id(m);
}

static int64_t clock_us(const kelp_modemsim *m, int64_t now_us)
{
    return now_us + m->clock_offset_us;
}

kelp_time kelp_modemsim_clock(const kelp_modemsim *m, kelp_time now)
{
    return time_of(clock_us(m, us_of(now)));
}

/* ------------------------------------------------------------------ writing to the host */

static void send_sentence(kelp_modemsim *m, kelp_nmea_writer *w, int64_t now_us)
{
    size_t len;
    if (kelp_nmea_writer_finish(w, &len) != KELP_OK || len + 3 > w->cap) {
        (void)kelp_fail(&m->diag, KELP_ERR_NOSPACE, "modemsim: sentence too long");
        return;
    }
    emit(m, KELP_MODEMSIM_EV_HOST_OUT, NULL, 0, KELP_MODEMSIM_LOSS_NONE, w->buf, 0, now_us);
    w->buf[len] = '\r';
    w->buf[len + 1] = '\n';
    w->buf[len + 2] = '\0';
    m->count.host_out++;
    if (m->ops.write) m->ops.write(w->buf, len + 2, m->user);
}

static void host_error(kelp_modemsim *m, int num, const char *text, const char *line, int err, int64_t now_us)
{
    char buf[96];
    char t[7];
    kelp_nmea_writer w;
    m->count.host_errors++;
    emit(m, KELP_MODEMSIM_EV_HOST_ERROR, NULL, 0, KELP_MODEMSIM_LOSS_NONE, line, err, now_us);
    hhmmss(clock_us(m, now_us), t);
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CAERR");
    kelp_nmea_writer_str(&w, t);
    kelp_nmea_writer_str(&w, "NMEA");
    kelp_nmea_writer_long(&w, num);
    kelp_nmea_writer_str(&w, text);
    send_sentence(m, &w, now_us);
}

static void write_rev(kelp_modemsim *m, const char *ident, int64_t now_us)
{
    char buf[80];
    char t[7];
    kelp_nmea_writer w;
    hhmmss(clock_us(m, now_us), t);
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CAREV");
    kelp_nmea_writer_str(&w, t);
    kelp_nmea_writer_str(&w, ident);
    kelp_nmea_writer_str(&w, m->revision);
    send_sentence(m, &w, now_us);
    m->last_rev_us = now_us;
}

static void write_hex(kelp_nmea_writer *w, const uint8_t *d, size_t n)
{
    if (n > KELP_MAX_ACOMMS_FRAME) n = KELP_MAX_ACOMMS_FRAME;
    kelp_nmea_writer_hex(w, d, n);
}

/* ------------------------------------------------------------------ configuration */

void kelp_modemsim_cfg_default(kelp_modemsim_cfg *c)
{
    memset(c, 0, sizeof *c);
    c->modem_id = 1;
    c->sound_speed = KELP_MODEMSIM_SOUND_SPEED;
    c->seed = 1;
    c->ci_seconds = 1.0;
    c->mini_seconds = 0.5;
    c->turnaround_seconds = 0.25;
    c->drq_timeout_seconds = 2.0;
    c->ping_timeout_seconds = 10.0;
    c->rev_interval_seconds = 60.0;
    c->revision = "0.93.0.52";
    c->lbl_turnaround_seconds = 0.05;
}

static bool dur_ok(double d)
{
    return isfinite(d) && d >= 0 && d < 3600;
}

static void nv_reset(kelp_modemsim *m)
{
    m->n_nv = N_NV_DEFAULTS;
    for (size_t i = 0; i < N_NV_DEFAULTS; i++) {
        memcpy(m->nv[i].name, NV_DEFAULTS[i].name, 4);
        m->nv[i].deflt = !strcmp(NV_DEFAULTS[i].name, "SRC") ? m->cfg.modem_id : NV_DEFAULTS[i].value;
        m->nv[i].value = m->nv[i].deflt;
    }
}

/* index of an NVRAM parameter (3 letters, any case), or SIZE_MAX */
static size_t nv_index(const kelp_modemsim *m, const char *name)
{
    if (!name || strlen(name) != 3) return SIZE_MAX;
    for (size_t i = 0; i < m->n_nv; i++) {
        bool eq = true;
        for (int k = 0; k < 3; k++) {
            char c = name[k];
            if (c >= 'a' && c <= 'z') c = (char)(c - 32);
            if (c != m->nv[i].name[k]) eq = false;
        }
        if (eq) return i;
    }
    return SIZE_MAX;
}

static kelp_modemsim_nv *nv_find(kelp_modemsim *m, const char *name)
{
    size_t i = nv_index(m, name);
    return i == SIZE_MAX ? NULL : &m->nv[i];
}

int kelp_modemsim_nvram(const kelp_modemsim *m, const char *name, long *value)
{
    size_t i = nv_index(m, name);
    if (i == SIZE_MAX) return KELP_ERR_NOTFOUND;
    if (value) *value = m->nv[i].value;
    return KELP_OK;
}

int kelp_modemsim_init(kelp_modemsim *m, const kelp_modemsim_cfg *cfg, const kelp_modemsim_ops *ops, void *user, kelp_time now)
{
    const int64_t now_us = us_of(now);
    if (!m || !cfg) return KELP_ERR_ARG;
    memset(m, 0, sizeof *m);
    if (cfg->modem_id < 1 || cfg->modem_id > KELP_MODEMSIM_MAX_ID) return KELP_ERR_ARG;
    if (!(cfg->sound_speed > 0) || !isfinite(cfg->sound_speed)) return KELP_ERR_ARG;
    if (!(cfg->loss_probability >= 0 && cfg->loss_probability <= 1)) return KELP_ERR_ARG;
    if (!dur_ok(cfg->ci_seconds) || !dur_ok(cfg->mini_seconds) || !dur_ok(cfg->turnaround_seconds) ||
        !dur_ok(cfg->drq_timeout_seconds) || !dur_ok(cfg->ping_timeout_seconds) ||
        !(isfinite(cfg->rev_interval_seconds) && cfg->rev_interval_seconds >= 0) ||
        !dur_ok(cfg->lbl_turnaround_seconds))
        return KELP_ERR_ARG;
    if (!(cfg->max_range >= 0) || !isfinite(cfg->max_range)) return KELP_ERR_ARG;
    if (!isfinite(cfg->x) || !isfinite(cfg->y) || !isfinite(cfg->depth)) return KELP_ERR_ARG;
    if (cfg->n_lbl > 4) return KELP_ERR_ARG;
    m->cfg = *cfg;
    const char *rev = cfg->revision ? cfg->revision : "0.93.0.52";
    size_t rl = strlen(rev);
    if (rl == 0 || rl >= sizeof m->revision) return KELP_ERR_ARG;
    for (size_t i = 0; i < rl; i++)
        if (rev[i] == ',' || rev[i] == '*' || rev[i] == '$' || rev[i] < 32 || rev[i] > 126) return KELP_ERR_ARG;
    memcpy(m->revision, rev, rl + 1);
    m->cfg.revision = m->revision;
    if (ops) m->ops = *ops;
    m->user = user;
    m->x = cfg->x;
    m->y = cfg->y;
    m->depth = cfg->depth;
    m->clock_offset_us = cfg->clock_set_at_boot ? 0 : EPOCH_2000_US - now_us;
    m->last_host_us = INT64_MIN;
    m->last_rev_us = now_us;
    kelp_rng_seed(&m->rng, cfg->seed);
    kelp_nmea_reader_init(&m->rd, '\r');
    nv_reset(m);
    m->busy_until_us = INT64_MIN;
    return KELP_OK;
}

void kelp_modemsim_boot(kelp_modemsim *m, kelp_time now)
{
    const int64_t now_us = us_of(now);
    write_rev(m, "INIT", now_us);
}

void kelp_modemsim_set_position(kelp_modemsim *m, double x, double y, double depth)
{
    if (!isfinite(x) || !isfinite(y) || !isfinite(depth)) return;
    m->x = x;
    m->y = y;
    m->depth = depth;
}

const kelp_modemsim_counters *kelp_modemsim_get_counters(const kelp_modemsim *m)
{
    return &m->count;
}

/* ------------------------------------------------------------------ transmissions */

static void new_pkt(kelp_modemsim *m, kelp_modemsim_pkt_kind kind)
{
    memset(&m->scratch, 0, sizeof m->scratch);
    m->scratch.kind = kind;
    m->scratch.src = (uint8_t)src_id(m);
}

/* queue m->scratch for transmission at due_us; ref_us = reference for a ping reply's turnaround */
static void schedule(kelp_modemsim *m, int64_t due_us, int64_t ref_us)
{
    if (m->n_txq >= KELP_MAX_MSIM_TXQ) {
        (void)kelp_fail(&m->diag, KELP_ERR_NOSPACE, "modemsim: transmit queue full");
        m->count.overflow++;
        emit(m, KELP_MODEMSIM_EV_INFO, &m->scratch, 0, KELP_MODEMSIM_LOSS_NONE, "transmit queue full: dropped", KELP_ERR_NOSPACE,
             due_us);
        return;
    }
    kelp_modemsim_txslot *t = &m->txq[m->n_txq++];
    t->due_us = due_us;
    t->pkt = m->scratch;
    t->pkt.turnaround = time_of(ref_us); /* replaced by the real turnaround when it starts */
}

static int64_t pkt_duration(const kelp_modemsim *m, const kelp_modemsim_pkt *p)
{
    switch (p->kind) {
    case KELP_MODEMSIM_PKT_CYCLE_INIT: return us_of(m->cfg.ci_seconds);
    case KELP_MODEMSIM_PKT_DATA: return us_of(kelp_modemsim_packet_seconds(p->rate, p->nframes));
    default: return us_of(m->cfg.mini_seconds);
    }
}

static unsigned pkt_bytes(const kelp_modemsim_pkt *p)
{
    if (p->kind != KELP_MODEMSIM_PKT_DATA) return MINI_BYTES;
    unsigned b = 0;
    for (unsigned i = 0; i < p->nframes; i++) b += p->frame[i].len;
    return b;
}

static void write_txpf(kelp_modemsim *m, const char *head, unsigned bytes, int64_t now_us)
{
    char buf[40];
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, head);
    kelp_nmea_writer_long(&w, (long)bytes);
    send_sentence(m, &w, now_us);
}

static void start_tx(kelp_modemsim *m, kelp_modemsim_txslot *t, int64_t now_us)
{
    kelp_modemsim_pkt *p = &t->pkt;
    int64_t start = t->due_us > m->busy_until_us ? t->due_us : m->busy_until_us;
    if (start < now_us - LATE_START_US) start = now_us - LATE_START_US;
    const int64_t duration = pkt_duration(m, p);
    p->start = time_of(start);
    p->duration = time_of(duration);
    if (p->kind == KELP_MODEMSIM_PKT_PING_REPLY) {
        int64_t ta = start - us_of(p->turnaround);
        p->turnaround = time_of(ta > 0 ? ta : 0);
    } else {
        p->turnaround = 0;
    }
    p->instance = m->cfg.instance;
    p->seq = ++m->seq;
    p->x = m->x;
    p->y = m->y;
    p->depth = m->depth;
    m->busy_until_us = start + duration;
    kelp_modemsim_txlog *l = &m->txlog[m->txlog_next];
    m->txlog_next = (m->txlog_next + 1) % KELP_MAX_MSIM_TXLOG;
    l->start_us = start;
    l->end_us = start + duration;
    l->kind = p->kind;
    l->bytes = pkt_bytes(p);
    l->txf_pending = true;
    if (p->kind == KELP_MODEMSIM_PKT_PING) {
        m->ping_active = true;
        m->ping_dest = p->dest;
        m->ping_start_us = start;
        m->ping_duration_us = duration;
    }
    m->count.tx[p->kind]++;
    if (p->kind == KELP_MODEMSIM_PKT_DATA) m->count.frames_tx += p->nframes;
    write_txpf(m, "$CATXP", l->bytes, now_us);
    emit(m, KELP_MODEMSIM_EV_TX, p, 0, KELP_MODEMSIM_LOSS_NONE, NULL, 0, now_us);
    if (m->ops.transmit) m->ops.transmit(p, m->user);
}

/* start every queued transmission whose time has come, one after the other (half duplex) */
static void run_txq(kelp_modemsim *m, int64_t now_us)
{
    for (;;) {
        size_t best = SIZE_MAX;
        for (size_t i = 0; i < m->n_txq; i++)
            if (best == SIZE_MAX || m->txq[i].due_us < m->txq[best].due_us) best = i;
        if (best == SIZE_MAX) return;
        kelp_modemsim_txslot *t = &m->txq[best];
        int64_t start = t->due_us > m->busy_until_us ? t->due_us : m->busy_until_us;
        if (start > now_us) return;
        kelp_modemsim_txslot *tmp = &m->txwork;
        *tmp = *t;
        memmove(&m->txq[best], &m->txq[best + 1], (m->n_txq - best - 1) * sizeof m->txq[0]);
        m->n_txq--;
        start_tx(m, tmp, now_us);
    }
}

/* ------------------------------------------------------------------ data cycles */

static void finish_cycle(kelp_modemsim *m, int64_t now_us)
{
    m->cyc.active = false;
    m->cyc.drq_pending = false;
    if (m->cyc.next == 0) {
        emit(m, KELP_MODEMSIM_EV_INFO, NULL, 0, KELP_MODEMSIM_LOSS_NONE, "cycle without data: nothing sent", 0, now_us);
        return;
    }
    new_pkt(m, KELP_MODEMSIM_PKT_DATA);
    m->scratch.rate = m->cyc.rate;
    m->scratch.ack = m->cyc.ack;
    m->scratch.adr1 = m->cyc.adr1;
    m->scratch.adr2 = m->cyc.adr2;
    m->scratch.dest = m->gathered[0].dest;
    m->scratch.nframes = (uint8_t)m->cyc.next;
    for (unsigned i = 0; i < m->cyc.next; i++) m->scratch.frame[i] = m->gathered[i];
    int64_t due = m->cyc.not_before_us > now_us ? m->cyc.not_before_us : now_us;
    schedule(m, due, 0);
}

static void gather_next(kelp_modemsim *m, int64_t now_us)
{
    while (m->cyc.next < m->cyc.nframes && m->n_txbuf > 0) {
        kelp_modemsim_frame *f = &m->txbuf[0];
        if (f->len <= kelp_modemsim_rate_bytes[m->cyc.rate]) m->gathered[m->cyc.next++] = *f;
        memmove(&m->txbuf[0], &m->txbuf[1], (m->n_txbuf - 1) * sizeof m->txbuf[0]);
        m->n_txbuf--;
    }
    if (m->cyc.next >= m->cyc.nframes) {
        finish_cycle(m, now_us);
        return;
    }
    char buf[80];
    char t[7];
    kelp_nmea_writer w;
    hhmmss(clock_us(m, now_us), t);
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CADRQ");
    kelp_nmea_writer_str(&w, t);
    kelp_nmea_writer_long(&w, m->cyc.adr1);
    kelp_nmea_writer_long(&w, m->cyc.adr2);
    kelp_nmea_writer_long(&w, m->cyc.ack);
    kelp_nmea_writer_long(&w, (long)kelp_modemsim_rate_bytes[m->cyc.rate]);
    kelp_nmea_writer_long(&w, (long)m->cyc.next + 1);
    send_sentence(m, &w, now_us);
    m->cyc.drq_pending = true;
    m->cyc.drq_deadline_us = now_us + us_of(m->cfg.drq_timeout_seconds);
}

static void start_gathering(kelp_modemsim *m, uint8_t cmd, uint8_t adr1, uint8_t adr2, uint8_t rate, uint8_t ack,
                            uint8_t nframes, int64_t not_before_us, int64_t now_us)
{
    if (m->cyc.active)
        emit(m, KELP_MODEMSIM_EV_INFO, NULL, 0, KELP_MODEMSIM_LOSS_NONE, "new cycle replaces the one being assembled", 0,
             now_us);
    m->cyc.active = true;
    m->cyc.drq_pending = false;
    m->cyc.cmd = cmd;
    m->cyc.adr1 = adr1;
    m->cyc.adr2 = adr2;
    m->cyc.rate = rate;
    m->cyc.ack = ack;
    m->cyc.nframes = nframes;
    m->cyc.next = 0;
    m->cyc.not_before_us = not_before_us;
    gather_next(m, now_us);
}

/* ------------------------------------------------------------------ host commands */

static bool field_range(const kelp_nmea_sentence *s, unsigned i, long lo, long hi, long *v)
{
    return kelp_nmea_field_long(s, i, v) == KELP_OK && *v >= lo && *v <= hi;
}

static void cmd_clk(kelp_modemsim *m, const kelp_nmea_sentence *s, const char *line, int64_t now_us)
{
    long v[6];
    static const long lo[6] = { 1970, 1, 1, 0, 0, 0 }, hi[6] = { 9999, 12, 31, 23, 59, 59 };
    for (unsigned i = 0; i < 6; i++) {
        if (!field_range(s, i + 1, lo[i], hi[i], &v[i])) {
            host_error(m, ERR_FIELD, "BAD_CLK_FIELD", line, KELP_ERR_PARSE, now_us);
            return;
        }
    }
    if (s->nfields != 7 || v[2] > (long)days_in_month(v[0], v[1])) {
        host_error(m, ERR_FIELD, "BAD_CLK_FIELD", line, KELP_ERR_PARSE, now_us);
        return;
    }
    int64_t t = (kelp_util_days_from_civil(v[0], (unsigned)v[1], (unsigned)v[2]) * 86400 + v[3] * 3600 + v[4] * 60 + v[5]) *
                US_PER_S;
    m->clock_offset_us = t - now_us;
    emit(m, KELP_MODEMSIM_EV_INFO, NULL, 0, KELP_MODEMSIM_LOSS_NONE, "clock set", 0, now_us);
    int y, mo, d, h, mi, sec;
    kelp_mmdriver_civil(time_of(clock_us(m, now_us)), &y, &mo, &d, &h, &mi, &sec);
    char buf[64];
    char f[8];
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CACLK");
    kelp_nmea_writer_long(&w, y);
    (void)put_digits(f, (unsigned long)mo, 2);
    kelp_nmea_writer_str(&w, f);
    (void)put_digits(f, (unsigned long)d, 2);
    kelp_nmea_writer_str(&w, f);
    (void)put_digits(f, (unsigned long)h, 2);
    kelp_nmea_writer_str(&w, f);
    (void)put_digits(f, (unsigned long)mi, 2);
    kelp_nmea_writer_str(&w, f);
    (void)put_digits(f, (unsigned long)sec, 2);
    kelp_nmea_writer_str(&w, f);
    send_sentence(m, &w, now_us);
}

static void write_cfg(kelp_modemsim *m, const char *name, long value, int64_t now_us)
{
    char buf[48];
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CACFG");
    kelp_nmea_writer_str(&w, name);
    kelp_nmea_writer_long(&w, value);
    send_sentence(m, &w, now_us);
}

static void cmd_cfg(kelp_modemsim *m, const kelp_nmea_sentence *s, const char *line, int64_t now_us)
{
    const char *name = kelp_nmea_field(s, 1);
    long v;
    if (s->nfields != 3 || kelp_nmea_field_long(s, 2, &v) != KELP_OK) {
        host_error(m, ERR_FIELD, "BAD_CFG_FIELD", line, KELP_ERR_PARSE, now_us);
        return;
    }
    if (!strcmp(name, "ALL") || !strcmp(name, "all")) {
        int before = src_id(m);
        nv_reset(m);
        if (src_id(m) != before)
            emit(m, KELP_MODEMSIM_EV_INFO, NULL, 0, KELP_MODEMSIM_LOSS_NONE, "NVRAM reset: SRC back to default", 0, now_us);
        write_cfg(m, "ALL", 0, now_us);
        return;
    }
    kelp_modemsim_nv *n = nv_find(m, name);
    if (!n) {
        host_error(m, ERR_FIELD, "UNKNOWN_CFG_PARAM", line, KELP_ERR_NOTFOUND, now_us);
        return;
    }
    if (!strcmp(n->name, "SRC") && (v < 1 || v > KELP_MODEMSIM_MAX_ID)) {
        host_error(m, ERR_FIELD, "BAD_CFG_VALUE", line, KELP_ERR_RANGE, now_us);
        return;
    }
    if (!strcmp(n->name, "SRC") && v != n->value)
        emit(m, KELP_MODEMSIM_EV_INFO, NULL, 0, KELP_MODEMSIM_LOSS_NONE, "SRC changed by the host", 0, now_us);
    n->value = v;
    write_cfg(m, n->name, v, now_us);
}

static void cmd_cfq(kelp_modemsim *m, const kelp_nmea_sentence *s, const char *line, int64_t now_us)
{
    const char *name = kelp_nmea_field(s, 1);
    if (s->nfields != 2) {
        host_error(m, ERR_FIELD, "BAD_CFQ_FIELD", line, KELP_ERR_PARSE, now_us);
        return;
    }
    if (!strcmp(name, "ALL") || !strcmp(name, "all")) {
        for (size_t i = 0; i < m->n_nv; i++) write_cfg(m, m->nv[i].name, m->nv[i].value, now_us);
        return;
    }
    kelp_modemsim_nv *n = nv_find(m, name);
    if (!n) {
        host_error(m, ERR_FIELD, "UNKNOWN_CFG_PARAM", line, KELP_ERR_NOTFOUND, now_us);
        return;
    }
    write_cfg(m, n->name, n->value, now_us);
}

static void write_cyc(kelp_modemsim *m, const char *head, long cmd, long a1, long a2, long rate, long ack, long nf,
                      int64_t now_us)
{
    char buf[64];
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, head);
    kelp_nmea_writer_long(&w, cmd);
    kelp_nmea_writer_long(&w, a1);
    kelp_nmea_writer_long(&w, a2);
    kelp_nmea_writer_long(&w, rate);
    kelp_nmea_writer_long(&w, ack);
    kelp_nmea_writer_long(&w, nf);
    send_sentence(m, &w, now_us);
}

static void cmd_cyc(kelp_modemsim *m, const kelp_nmea_sentence *s, const char *line, int64_t now_us)
{
    long cmd, a1, a2, rate, ack, nf;
    if (s->nfields != 7 || !field_range(s, 1, 0, 255, &cmd) || !field_range(s, 2, 0, KELP_MODEMSIM_MAX_ID, &a1) ||
        !field_range(s, 3, 0, KELP_MODEMSIM_MAX_ID, &a2) || !field_range(s, 4, 0, 5, &rate) ||
        !field_range(s, 5, 0, 1, &ack) || !field_range(s, 6, 1, (long)kelp_modemsim_rate_frames[rate > 5 || rate < 0 ? 0 : rate], &nf)) {
        host_error(m, ERR_FIELD, "BAD_CYC_FIELD", line, KELP_ERR_PARSE, now_us);
        return;
    }
    write_cyc(m, "$CACYC", cmd, a1, a2, rate, ack, nf, now_us);
    new_pkt(m, KELP_MODEMSIM_PKT_CYCLE_INIT);
    m->scratch.cmd = (uint8_t)cmd;
    m->scratch.adr1 = (uint8_t)a1;
    m->scratch.adr2 = (uint8_t)a2;
    m->scratch.dest = (uint8_t)a2;
    m->scratch.rate = (uint8_t)rate;
    m->scratch.ack = (uint8_t)ack;
    m->scratch.nframes = (uint8_t)nf;
    int64_t ci_start = m->busy_until_us > now_us ? m->busy_until_us : now_us;
    schedule(m, now_us, 0);
    run_txq(m, now_us);
    if (a1 == src_id(m))
        start_gathering(m, (uint8_t)cmd, (uint8_t)a1, (uint8_t)a2, (uint8_t)rate, (uint8_t)ack, (uint8_t)nf,
                        ci_start + us_of(m->cfg.ci_seconds), now_us);
}

static void cmd_txd(kelp_modemsim *m, const kelp_nmea_sentence *s, const char *line, int64_t now_us)
{
    long src, dest, ack;
    if (s->nfields < 4 || s->nfields > 5 || !field_range(s, 1, 0, KELP_MODEMSIM_MAX_ID, &src) ||
        !field_range(s, 2, 0, KELP_MODEMSIM_MAX_ID, &dest) || !field_range(s, 3, 0, 1, &ack)) {
        host_error(m, ERR_FIELD, "BAD_TXD_FIELD", line, KELP_ERR_PARSE, now_us);
        return;
    }
    kelp_modemsim_frame *f = &m->txd;
    memset(f, 0, sizeof *f);
    size_t n = 0;
    size_t cap = m->cyc.active ? kelp_modemsim_rate_bytes[m->cyc.rate] : KELP_MAX_ACOMMS_FRAME;
    int rc = kelp_util_hex_decode(kelp_nmea_field(s, 4), strlen(kelp_nmea_field(s, 4)), f->data, cap, &n);
    if (rc) {
        host_error(m, ERR_FIELD, rc == KELP_ERR_RANGE ? "TXD_TOO_LONG" : "BAD_TXD_HEX", line, rc, now_us);
        return;
    }
    f->src = (uint8_t)src;
    f->dest = (uint8_t)dest;
    f->ack = ack == 1;
    f->len = (uint16_t)n;
    char buf[64];
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CATXD");
    kelp_nmea_writer_long(&w, src);
    kelp_nmea_writer_long(&w, dest);
    kelp_nmea_writer_long(&w, ack);
    kelp_nmea_writer_long(&w, (long)n);
    send_sentence(m, &w, now_us);
    if (m->cyc.active && m->cyc.drq_pending) {
        m->cyc.drq_pending = false;
        if (n == 0) {
            finish_cycle(m, now_us);
        } else {
            m->gathered[m->cyc.next++] = *f;
            gather_next(m, now_us);
        }
    } else if (n > 0) {
        if (m->n_txbuf < KELP_MAX_MM_FRAMES) m->txbuf[m->n_txbuf++] = *f;
        else emit(m, KELP_MODEMSIM_EV_INFO, NULL, 0, KELP_MODEMSIM_LOSS_NONE, "transmit buffer full: frame dropped", 0, now_us);
    }
}

static void cmd_mpc(kelp_modemsim *m, const kelp_nmea_sentence *s, const char *line, int64_t now_us)
{
    long src, dest;
    if (s->nfields != 3 || !field_range(s, 1, 0, KELP_MODEMSIM_MAX_ID, &src) ||
        !field_range(s, 2, 0, KELP_MODEMSIM_MAX_ID, &dest)) {
        host_error(m, ERR_FIELD, "BAD_MPC_FIELD", line, KELP_ERR_PARSE, now_us);
        return;
    }
    char buf[48];
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CAMPC");
    kelp_nmea_writer_long(&w, src);
    kelp_nmea_writer_long(&w, dest);
    send_sentence(m, &w, now_us);
    new_pkt(m, KELP_MODEMSIM_PKT_PING);
    m->scratch.dest = (uint8_t)dest;
    schedule(m, now_us, 0);
    run_txq(m, now_us);
}

static void cmd_muc(kelp_modemsim *m, const kelp_nmea_sentence *s, const char *line, int64_t now_us)
{
    long src, dest;
    const char *h = kelp_nmea_field(s, 3);
    size_t hl = strlen(h);
    long v = 0;
    bool ok = s->nfields == 4 && field_range(s, 1, 0, KELP_MODEMSIM_MAX_ID, &src) &&
              field_range(s, 2, 0, KELP_MODEMSIM_MAX_ID, &dest) && hl >= 1 && hl <= 4;
    for (size_t i = 0; ok && i < hl; i++) {
        int d = kelp_util_hex_digit(h[i]);
        if (d < 0) ok = false;
        else v = v * 16 + d;
    }
    if (!ok || v > 0x1fff) {
        host_error(m, ERR_FIELD, "BAD_MUC_FIELD", line, KELP_ERR_PARSE, now_us);
        return;
    }
    char buf[48];
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CAMUC");
    kelp_nmea_writer_long(&w, src);
    kelp_nmea_writer_long(&w, dest);
    kelp_nmea_writer_str(&w, h);
    send_sentence(m, &w, now_us);
    new_pkt(m, KELP_MODEMSIM_PKT_MINI);
    m->scratch.dest = (uint8_t)dest;
    m->scratch.mini = (uint16_t)v;
    schedule(m, now_us, 0);
    run_txq(m, now_us);
}

static void cmd_pdt(kelp_modemsim *m, const kelp_nmea_sentence *s, const char *line, int64_t now_us)
{
    long v[9];
    static const long hi[9] = { 255, 4, 1, 100000, 100000, 1, 1, 1, 1 };
    bool ok = s->nfields == 10;
    for (unsigned i = 0; ok && i < 9; i++) ok = field_range(s, i + 1, i == 1 ? 1 : 0, hi[i], &v[i]);
    if (!ok) {
        host_error(m, ERR_FIELD, "BAD_PDT_FIELD", line, KELP_ERR_PARSE, now_us);
        return;
    }
    char buf[80];
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$SNPDT");
    for (unsigned i = 0; i < 9; i++) kelp_nmea_writer_long(&w, v[i]);
    send_sentence(m, &w, now_us);
    m->lbl_active = true;
    m->lbl_start_us = now_us;
    m->lbl_timeout_us = v[4] * 1000;
    for (unsigned i = 0; i < 4; i++) m->lbl_enable[i] = v[5 + i] == 1;
}

static void handle_line(kelp_modemsim *m, const char *line, size_t len, int64_t now_us)
{
    kelp_nmea_sentence *s = &m->s;
    int rc = kelp_nmea_parse(line, len, s);
    char *copy = m->line;
    size_t cl = len < KELP_MAX_NMEA_LINE ? len : KELP_MAX_NMEA_LINE;
    memcpy(copy, line, cl);
    copy[cl] = '\0';
    if (rc == KELP_ERR_CHECKSUM) {
        host_error(m, ERR_CHECKSUM, "BAD_CHECKSUM", copy, rc, now_us);
        return;
    }
    if (rc) {
        host_error(m, ERR_SYNTAX, "BAD_NMEA_SENTENCE", copy, rc, now_us);
        return;
    }
    if (strcmp(s->talker, "CC") != 0) {
        host_error(m, ERR_TALKER, "NOT_A_HOST_COMMAND", copy, KELP_ERR_PARSE, now_us);
        return;
    }
    m->count.host_lines++;
    m->last_host_us = now_us;
    emit(m, KELP_MODEMSIM_EV_HOST_IN, NULL, 0, KELP_MODEMSIM_LOSS_NONE, copy, 0, now_us);
    const char *id = s->id;
    if (!strcmp(id, "CLK")) cmd_clk(m, s, copy, now_us);
    else if (!strcmp(id, "CFG")) cmd_cfg(m, s, copy, now_us);
    else if (!strcmp(id, "CFQ")) cmd_cfq(m, s, copy, now_us);
    else if (!strcmp(id, "CYC")) cmd_cyc(m, s, copy, now_us);
    else if (!strcmp(id, "TXD")) cmd_txd(m, s, copy, now_us);
    else if (!strcmp(id, "MPC")) cmd_mpc(m, s, copy, now_us);
    else if (!strcmp(id, "MUC")) cmd_muc(m, s, copy, now_us);
    else if (!strcmp(id, "PDT")) cmd_pdt(m, s, copy, now_us);
    else host_error(m, ERR_UNKNOWN, "UNSUPPORTED_COMMAND", copy, KELP_ERR_UNSUPPORTED, now_us);
}

int kelp_modemsim_feed(kelp_modemsim *m, const uint8_t *bytes, size_t n, kelp_time now)
{
    const int64_t now_us = us_of(now);
    if (!m || (n && !bytes)) return KELP_ERR_ARG;
    for (size_t i = 0; i < n; i++) {
        uint8_t b = bytes[i] == '\n' ? (uint8_t)'\r' : bytes[i];
        const char *line;
        size_t len;
        int rc = kelp_nmea_reader_feed(&m->rd, b, &line, &len);
        if (rc == KELP_ERR_PARTIAL) continue;
        if (rc != KELP_OK) {
            host_error(m, ERR_SYNTAX, "LINE_TOO_LONG", "", rc, now_us);
            continue;
        }
        handle_line(m, line, len, now_us);
    }
    return KELP_OK;
}

/* ------------------------------------------------------------------ the channel: hearing */

int kelp_modemsim_hear(kelp_modemsim *m, const kelp_modemsim_pkt *p, kelp_time now)
{
    const int64_t now_us = us_of(now);
    if (!m || !p) return KELP_ERR_ARG;
    if (p->instance == m->cfg.instance) return KELP_OK; /* our own transmission */
    double range = sqrt((p->x - m->x) * (p->x - m->x) + (p->y - m->y) * (p->y - m->y) +
                        (p->depth - m->depth) * (p->depth - m->depth));
    if (m->cfg.max_range > 0 && range > m->cfg.max_range) {
        m->count.out_of_range++;
        return KELP_OK;
    }
    double tt = range / m->cfg.sound_speed;
    int64_t start = us_of(p->start) + us_of(tt);
    int64_t end = start + us_of(p->duration);
    if (end < now_us - STALE_US) {
        m->count.lost_stale++;
        emit(m, KELP_MODEMSIM_EV_LOST, p, 0, KELP_MODEMSIM_LOSS_STALE, "heard too late", 0, now_us);
        return KELP_OK;
    }
    size_t slot = SIZE_MAX, oldest = SIZE_MAX;
    for (size_t i = 0; i < KELP_MAX_MSIM_ARRIVALS; i++) {
        if (!m->arr[i].used) {
            slot = i;
            break;
        }
        if (m->arr[i].decided && (oldest == SIZE_MAX || m->arr[i].end_us < m->arr[oldest].end_us)) oldest = i;
    }
    if (slot == SIZE_MAX) slot = oldest;
    if (slot == SIZE_MAX) {
        m->count.overflow++;
        (void)kelp_fail(&m->diag, KELP_ERR_NOSPACE, "modemsim: too many packets in flight");
        emit(m, KELP_MODEMSIM_EV_LOST, p, 0, KELP_MODEMSIM_LOSS_NONE, "too many packets in flight", KELP_ERR_NOSPACE, now_us);
        return KELP_ERR_NOSPACE;
    }
    kelp_modemsim_arrival *a = &m->arr[slot];
    a->used = true;
    a->decided = false;
    a->loss = KELP_MODEMSIM_LOSS_NONE;
    a->start_us = start;
    a->end_us = end;
    a->range_m = range;
    a->travel_s = tt;
    a->pkt = *p;
    return KELP_OK;
}

static void emit_arrival(kelp_modemsim *m, kelp_modemsim_event_kind kind, const kelp_modemsim_arrival *a, unsigned frame,
                         kelp_modemsim_loss loss, int64_t now_us)
{
    if (!m->ops.event) return;
    kelp_modemsim_event ev;
    memset(&ev, 0, sizeof ev);
    ev.kind = kind;
    ev.time = time_of(now_us);
    ev.pkt = &a->pkt;
    ev.frame = frame;
    ev.loss = loss;
    ev.range_m = a->range_m;
    ev.travel_s = a->travel_s;
    ev.text = "";
    m->ops.event(&ev, m->user);
}

static void count_loss(kelp_modemsim *m, kelp_modemsim_loss l)
{
    if (l == KELP_MODEMSIM_LOSS_RANDOM) m->count.lost_random++;
    else if (l == KELP_MODEMSIM_LOSS_COLLISION) m->count.lost_collision++;
    else if (l == KELP_MODEMSIM_LOSS_HALF_DUPLEX) m->count.lost_half_duplex++;
}

static bool dropped(kelp_modemsim *m)
{
    if (!(m->cfg.loss_probability > 0)) return false;
    return kelp_rng_uniform(&m->rng) < m->cfg.loss_probability;
}

/* the physical outcome of an arrival, before the random loss */
static kelp_modemsim_loss physical(const kelp_modemsim *m, const kelp_modemsim_arrival *a)
{
    for (size_t i = 0; i < KELP_MAX_MSIM_TXLOG; i++) {
        const kelp_modemsim_txlog *l = &m->txlog[i];
        if (l->end_us > l->start_us && l->start_us < a->end_us && l->end_us > a->start_us)
            return KELP_MODEMSIM_LOSS_HALF_DUPLEX;
    }
    for (size_t i = 0; i < KELP_MAX_MSIM_ARRIVALS; i++) {
        const kelp_modemsim_arrival *b = &m->arr[i];
        if (!b->used || b == a) continue;
        /* one transmitter sends its packets one after another: two of them never collide
         * with each other, even when the sender's motion makes the second arrive a few
         * milliseconds "early" (it would otherwise look like an overlap) */
        if (b->pkt.instance == a->pkt.instance) continue;
        if (b->start_us < a->end_us && b->end_us > a->start_us) return KELP_MODEMSIM_LOSS_COLLISION;
    }
    return KELP_MODEMSIM_LOSS_NONE;
}

static void receive_ci(kelp_modemsim *m, const kelp_modemsim_arrival *a, int64_t now_us)
{
    const kelp_modemsim_pkt *p = &a->pkt;
    write_cyc(m, "$CACYC", p->cmd, p->adr1, p->adr2, p->rate, p->ack, p->nframes, now_us);
    int me = src_id(m);
    if (p->adr1 == me && p->src != me) /* we are polled: gather our data and send it */
        start_gathering(m, p->cmd, p->adr1, p->adr2, p->rate, p->ack, p->nframes,
                        now_us + us_of(m->cfg.turnaround_seconds), now_us);
}

static void receive_data(kelp_modemsim *m, kelp_modemsim_arrival *a, int64_t now_us)
{
    const kelp_modemsim_pkt *p = &a->pkt;
    int me = src_id(m);
    uint32_t mask = 0;
    for (unsigned i = 0; i < p->nframes; i++) {
        const kelp_modemsim_frame *f = &p->frame[i];
        if (dropped(m)) {
            m->count.lost_random++;
            emit_arrival(m, KELP_MODEMSIM_EV_LOST, a, i + 1, KELP_MODEMSIM_LOSS_RANDOM, now_us);
            continue;
        }
        kelp_nmea_writer w;
        kelp_nmea_writer_init(&w, m->rxd, sizeof m->rxd, "$CARXD");
        kelp_nmea_writer_long(&w, f->src);
        kelp_nmea_writer_long(&w, f->dest);
        kelp_nmea_writer_long(&w, f->ack ? 1 : 0);
        kelp_nmea_writer_long(&w, (long)i + 1);
        write_hex(&w, f->data, f->len);
        send_sentence(m, &w, now_us);
        m->count.frames_rx++;
        emit_arrival(m, KELP_MODEMSIM_EV_RX, a, i + 1, KELP_MODEMSIM_LOSS_NONE, now_us);
        if (f->ack && f->dest == me && f->dest != 0) mask |= 1u << i;
    }
    if (mask) {
        new_pkt(m, KELP_MODEMSIM_PKT_ACK);
        m->scratch.dest = p->src;
        m->scratch.rate = p->rate;
        m->scratch.ack_mask = mask;
        schedule(m, now_us + us_of(m->cfg.turnaround_seconds), 0);
    }
}

static void decide(kelp_modemsim *m, kelp_modemsim_arrival *a, int64_t now_us)
{
    a->decided = true;
    const kelp_modemsim_pkt *p = &a->pkt;
    int me = src_id(m);
    kelp_modemsim_loss l = physical(m, a);
    if (l != KELP_MODEMSIM_LOSS_NONE) {
        a->loss = l;
        count_loss(m, l);
        emit_arrival(m, KELP_MODEMSIM_EV_LOST, a, 0, l, now_us);
        return;
    }
    switch (p->kind) {
    case KELP_MODEMSIM_PKT_CYCLE_INIT:
        if (dropped(m)) break;
        m->count.rx[p->kind]++;
        emit_arrival(m, KELP_MODEMSIM_EV_RX, a, 0, KELP_MODEMSIM_LOSS_NONE, now_us);
        receive_ci(m, a, now_us);
        return;
    case KELP_MODEMSIM_PKT_DATA:
        m->count.rx[p->kind]++;
        receive_data(m, a, now_us);
        return;
    case KELP_MODEMSIM_PKT_ACK:
        if (p->dest != me) return;
        if (dropped(m)) break;
        m->count.rx[p->kind]++;
        emit_arrival(m, KELP_MODEMSIM_EV_RX, a, 0, KELP_MODEMSIM_LOSS_NONE, now_us);
        for (unsigned f = 0; f < 32; f++) {
            if (!(p->ack_mask & (1u << f))) continue;
            char buf[64];
            kelp_nmea_writer w;
            kelp_nmea_writer_init(&w, buf, sizeof buf, "$CAACK");
            kelp_nmea_writer_long(&w, p->src);
            kelp_nmea_writer_long(&w, me);
            kelp_nmea_writer_long(&w, (long)f + 1);
            kelp_nmea_writer_long(&w, 1);
            send_sentence(m, &w, now_us);
            m->count.acks_out++;
        }
        return;
    case KELP_MODEMSIM_PKT_PING:
        if (p->dest != me) return;
        if (dropped(m)) break;
        m->count.rx[p->kind]++;
        emit_arrival(m, KELP_MODEMSIM_EV_RX, a, 0, KELP_MODEMSIM_LOSS_NONE, now_us);
        {
            char buf[48];
            kelp_nmea_writer w;
            kelp_nmea_writer_init(&w, buf, sizeof buf, "$CAMPA");
            kelp_nmea_writer_long(&w, p->src);
            kelp_nmea_writer_long(&w, me);
            send_sentence(m, &w, now_us);
        }
        new_pkt(m, KELP_MODEMSIM_PKT_PING_REPLY);
        m->scratch.dest = p->src;
        schedule(m, a->end_us + us_of(m->cfg.turnaround_seconds), a->end_us);
        return;
    case KELP_MODEMSIM_PKT_PING_REPLY:
        if (p->dest != me || !m->ping_active || p->src != m->ping_dest) return;
        if (dropped(m)) break;
        m->count.rx[p->kind]++;
        m->ping_active = false;
        emit_arrival(m, KELP_MODEMSIM_EV_RX, a, 0, KELP_MODEMSIM_LOSS_NONE, now_us);
        {
            double owtt =
                (double)(a->start_us - m->ping_start_us - m->ping_duration_us - us_of(p->turnaround)) / 2.0 / 1e6;
            char tt[24];
            fixed(owtt, 4, tt, sizeof tt);
            char buf[64];
            kelp_nmea_writer w;
            kelp_nmea_writer_init(&w, buf, sizeof buf, "$CAMPR");
            kelp_nmea_writer_long(&w, p->src);
            kelp_nmea_writer_long(&w, me);
            kelp_nmea_writer_str(&w, tt);
            send_sentence(m, &w, now_us);
        }
        return;
    case KELP_MODEMSIM_PKT_MINI:
        if (p->dest != me && p->dest != 0) return;
        if (dropped(m)) break;
        m->count.rx[p->kind]++;
        emit_arrival(m, KELP_MODEMSIM_EV_RX, a, 0, KELP_MODEMSIM_LOSS_NONE, now_us);
        {
            char hx[5] = { HEXL[(p->mini >> 12) & 15], HEXL[(p->mini >> 8) & 15], HEXL[(p->mini >> 4) & 15],
                           HEXL[p->mini & 15], '\0' };
            char buf[48];
            kelp_nmea_writer w;
            kelp_nmea_writer_init(&w, buf, sizeof buf, "$CAMUA");
            kelp_nmea_writer_long(&w, p->src);
            kelp_nmea_writer_long(&w, p->dest);
            kelp_nmea_writer_str(&w, hx);
            send_sentence(m, &w, now_us);
        }
        return;
    default:
        return;
    }
    /* random loss of a packet addressed to us (or of a cycle init) */
    a->loss = KELP_MODEMSIM_LOSS_RANDOM;
    count_loss(m, KELP_MODEMSIM_LOSS_RANDOM);
    emit_arrival(m, KELP_MODEMSIM_EV_LOST, a, 0, KELP_MODEMSIM_LOSS_RANDOM, now_us);
}

/* ------------------------------------------------------------------ timers */

static void lbl_reply(kelp_modemsim *m, int64_t now_us)
{
    m->lbl_active = false;
    char buf[96];
    kelp_nmea_writer w;
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$SNTTA");
    for (unsigned i = 0; i < 4; i++) {
        char tt[24] = "";
        if (i < m->cfg.n_lbl && m->lbl_enable[i]) {
            double ow = kelp_modemsim_travel_time(m->x, m->y, m->depth, m->cfg.lbl_x[i], m->cfg.lbl_y[i],
                                              m->cfg.lbl_depth[i], m->cfg.sound_speed);
            double two_way = 2 * ow + m->cfg.lbl_turnaround_seconds;
            if (two_way * 1e6 <= (double)m->lbl_timeout_us) fixed(ow, 4, tt, sizeof tt);
        }
        kelp_nmea_writer_str(&w, tt);
    }
    /* hhmmss.ss of the modem clock */
    int64_t c = clock_us(m, now_us);
    char t[16];
    hhmmss(c, t);
    int64_t cs = (c - kelp_util_floor_div(c, US_PER_S) * US_PER_S) / 10000;
    t[6] = '.';
    (void)put_digits(t + 7, (unsigned long)cs, 2);
    kelp_nmea_writer_str(&w, t);
    send_sentence(m, &w, now_us);
}

void kelp_modemsim_tick(kelp_modemsim *m, kelp_time now)
{
    const int64_t now_us = us_of(now);
    if (!m) return;
    run_txq(m, now_us);
    for (size_t i = 0; i < KELP_MAX_MSIM_TXLOG; i++) {
        kelp_modemsim_txlog *l = &m->txlog[i];
        if (l->txf_pending && l->end_us <= now_us) {
            l->txf_pending = false;
            write_txpf(m, "$CATXF", l->bytes, now_us);
        }
    }
    for (;;) {
        kelp_modemsim_arrival *next = NULL;
        for (size_t i = 0; i < KELP_MAX_MSIM_ARRIVALS; i++) {
            kelp_modemsim_arrival *a = &m->arr[i];
            if (a->used && !a->decided && a->end_us <= now_us && (!next || a->end_us < next->end_us)) next = a;
        }
        if (!next) break;
        decide(m, next, now_us);
    }
    for (size_t i = 0; i < KELP_MAX_MSIM_ARRIVALS; i++) {
        kelp_modemsim_arrival *a = &m->arr[i];
        if (a->used && a->decided && a->end_us + KEEP_DECIDED_US < now_us) a->used = false;
    }
    if (m->cyc.active && m->cyc.drq_pending && now_us >= m->cyc.drq_deadline_us) {
        emit(m, KELP_MODEMSIM_EV_INFO, NULL, 0, KELP_MODEMSIM_LOSS_NONE, "no $CCTXD before the DRQ timeout", 0, now_us);
        finish_cycle(m, now_us);
    }
    if (m->ping_active && now_us >= m->ping_start_us + us_of(m->cfg.ping_timeout_seconds)) {
        m->ping_active = false;
        emit(m, KELP_MODEMSIM_EV_INFO, NULL, 0, KELP_MODEMSIM_LOSS_NONE, "ping not answered", 0, now_us);
    }
    if (m->lbl_active && now_us >= m->lbl_start_us + m->lbl_timeout_us) lbl_reply(m, now_us);
    if (m->cfg.rev_interval_seconds > 0 && m->last_host_us != INT64_MIN) {
        int64_t iv = us_of(m->cfg.rev_interval_seconds);
        if (now_us - m->last_rev_us >= iv && now_us - m->last_host_us <= 3 * iv) write_rev(m, "AUV", now_us);
    }
    run_txq(m, now_us); /* acks and replies decided above */
}

kelp_time kelp_modemsim_next_due(const kelp_modemsim *m)
{
    int64_t t = INT64_MAX;
    for (size_t i = 0; i < m->n_txq; i++) {
        int64_t s = m->txq[i].due_us > m->busy_until_us ? m->txq[i].due_us : m->busy_until_us;
        if (s < t) t = s;
    }
    for (size_t i = 0; i < KELP_MAX_MSIM_TXLOG; i++)
        if (m->txlog[i].txf_pending && m->txlog[i].end_us < t) t = m->txlog[i].end_us;
    for (size_t i = 0; i < KELP_MAX_MSIM_ARRIVALS; i++)
        if (m->arr[i].used && !m->arr[i].decided && m->arr[i].end_us < t) t = m->arr[i].end_us;
    if (m->cyc.active && m->cyc.drq_pending && m->cyc.drq_deadline_us < t) t = m->cyc.drq_deadline_us;
    if (m->ping_active) {
        int64_t pt = m->ping_start_us + us_of(m->cfg.ping_timeout_seconds);
        if (pt < t) t = pt;
    }
    if (m->lbl_active && m->lbl_start_us + m->lbl_timeout_us < t) t = m->lbl_start_us + m->lbl_timeout_us;
    if (m->cfg.rev_interval_seconds > 0 && m->last_host_us != INT64_MIN) {
        int64_t r = m->last_rev_us + us_of(m->cfg.rev_interval_seconds);
        if (r < t) t = r;
    }
    return t == INT64_MAX ? HUGE_VAL : time_of(t);
}

/* ------------------------------------------------------------------ event text */

static const char *pkt_kind_name(kelp_modemsim_pkt_kind k)
{
    switch (k) {
    case KELP_MODEMSIM_PKT_CYCLE_INIT: return "cycle_init";
    case KELP_MODEMSIM_PKT_DATA: return "data";
    case KELP_MODEMSIM_PKT_ACK: return "ack";
    case KELP_MODEMSIM_PKT_PING: return "ping";
    case KELP_MODEMSIM_PKT_PING_REPLY: return "ping_reply";
    case KELP_MODEMSIM_PKT_MINI: return "mini";
    default: return "?";
    }
}

static const char *pkt_loss_name(kelp_modemsim_loss l)
{
    switch (l) {
    case KELP_MODEMSIM_LOSS_RANDOM: return "random";
    case KELP_MODEMSIM_LOSS_COLLISION: return "collision";
    case KELP_MODEMSIM_LOSS_HALF_DUPLEX: return "half_duplex";
    case KELP_MODEMSIM_LOSS_STALE: return "stale";
    default: return "overflow";
    }
}

int kelp_modemsim_event_format(const kelp_modemsim *m, const kelp_modemsim_event *e, char *buf, size_t cap)
{
    const kelp_modemsim_pkt *p = e->pkt;
    int n;
    switch (e->kind) {
    case KELP_MODEMSIM_EV_TX:
        if (!p) return 0;
        n = kelp_util_snprintf(buf, cap, "modem=%d,event=tx,kind=%s,src=%d,dest=%d,frames=%d,rate=%d", kelp_modemsim_src(m),
                     pkt_kind_name(p->kind), p->src, p->dest, p->kind == KELP_MODEMSIM_PKT_DATA ? p->nframes : 0, p->rate);
        break;
    case KELP_MODEMSIM_EV_RX:
        if (!p) return 0;
        n = kelp_util_snprintf(buf, cap, "modem=%d,event=rx,kind=%s,src=%d,dest=%d,frame=%u,range=%.1f,travel=%.4f",
                     kelp_modemsim_src(m), pkt_kind_name(p->kind), p->src, p->dest, e->frame, e->range_m, e->travel_s);
        break;
    case KELP_MODEMSIM_EV_LOST:
        n = kelp_util_snprintf(buf, cap, "modem=%d,event=lost,kind=%s,src=%d,dest=%d,frame=%u,reason=%s", kelp_modemsim_src(m),
                     p ? pkt_kind_name(p->kind) : "?", p ? p->src : 0, p ? p->dest : 0, e->frame,
                     pkt_loss_name(e->loss));
        break;
    default:
        return 0;
    }
    return n > 0 && (size_t)n < cap ? 1 : KELP_ERR_NOSPACE;
}
