/* kelp: WHOI Micro-Modem simulator core -- the MODEM side of the Micro-Modem NMEA protocol and
 * a simulated acoustic channel (core; no allocation, no I/O, no clock).
 *
 * One kelp_modemsim is one simulated modem.  The host (pAcommsHandler with DRIVER_WHOI_MICROMODEM,
 * or anything that speaks $CC... sentences) talks to it through bytes; the modems hear each other
 * through packets that the edge carries over the bus (kelp-modemsim: ACOMMS_SIM_CHANNEL).
 *
 *   host bytes in   kelp_modemsim_feed(m, bytes, n, now)        ("$CCCYC,0,1,2,0,1,1*hh\r\n")
 *   host bytes out  ops.write(bytes, n, user)               ("$CACYC,...*hh\r\n")
 *   packets out     ops.transmit(&pkt, user)                (publish on the channel)
 *   packets in      kelp_modemsim_hear(m, &pkt, now)            (every packet on the channel)
 *   timers          kelp_modemsim_tick(m, now)                  (often: every 10-50 ms)
 *   time            every call takes now = kelp_time of the shared simulation clock (used to the
 *                   whole microsecond)
 *
 * Host protocol (sentence forms of the WHOI Micro-Modem):
 *   $CCCLK,Y,M,D,h,m,s      -> $CACLK,YYYY,MM,DD,hh,mm,ss (the modem clock is set)
 *   $CCCFG,NAME,VALUE       -> $CACFG,NAME,VALUE          (ALL,0 resets every NVRAM value)
 *   $CCCFQ,NAME | ALL       -> $CACFG,NAME,VALUE for the one / for every parameter
 *   $CCCYC,CMD,A1,A2,R,K,N  -> $CACYC,CMD,A1,A2,R,K,N echo; a cycle-init packet goes out; if A1 is
 *                              this modem: $CADRQ,hhmmss,A1,A2,K,bytes,F for F = 1.. until all N
 *                              frames are given (or an empty $CCTXD / the DRQ timeout), then the
 *                              data packet goes out after the cycle init: $CATXP,n / $CATXF,n.
 *   $CCTXD,SRC,DEST,ACK,HEX -> $CATXD,SRC,DEST,ACK,NBYTES
 *   $CCMPC,SRC,DEST         -> $CAMPC,SRC,DEST; at DEST $CAMPA,SRC,DEST; back at SRC
 *                              $CAMPR,DEST,SRC,owtt (one-way travel time, s, 4 decimals)
 *   $CCMUC,SRC,DEST,HHHH    -> $CAMUC echo; at DEST $CAMUA,SRC,DEST,hhhh (13-bit mini-packet)
 *   $CCPDT,G,C,SF,STO,TO,A,B,C,D -> $SNPDT echo, then $SNTTA,ta,tb,tc,td,hhmmss.ss (REMUS LBL)
 *   anything malformed      -> $CAERR,hhmmss,NMEA,<n>,<text>
 * Heard on the channel:     $CACYC (cycle init; a poll of this modem starts its DRQs), $CARXD per
 *                           frame received, $CAACK,SRC,DEST,F,1 for acknowledged frames.
 * Unsolicited:              $CAREV,hhmmss,INIT,<rev> at boot, $CAREV,hhmmss,AUV,<rev> heartbeat.
 *
 * Channel model:
 *  - travel time = 3-D distance between the transmitter (position carried in the packet) and
 *    this modem (kelp_modemsim_set_position) / sound speed (default 1500 m/s);
 *  - rate-dependent packets: frames x bytes = {1x32, 3x32, 3x64, 2x256, 2x256, 8x256} for
 *    rates 0..5, lasting frames*bytes*8 / {80, 250, 500, 1200, 1300, 5300} bit/s;
 *  - a packet is received when it arrives whole, no other arrival overlaps it (collision),
 *    this modem did not transmit during it (half duplex), it is within max_range, and the
 *    caller-seeded RNG does not drop it (loss_probability per cycle init, per data frame, per
 *    ack, per ping).
 */
#ifndef KELP_MODEMSIM_H
#define KELP_MODEMSIM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/rng.h>

#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/mac.h>
#include <kelp/nmea.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_MODEMSIM_SOUND_SPEED 1500.0       /**< m/s, default */
#define KELP_MODEMSIM_MAX_ID 127               /**< highest acoustic address */

/* ------------------------------------------------------------------ channel arithmetic */

/** Frames per packet and bytes per frame for rates 0..5 (the Micro-Modem packet types). */
extern const unsigned kelp_modemsim_rate_frames[6];
extern const unsigned kelp_modemsim_rate_bytes[6];
/** Nominal bit rates (bit/s) for rates 0..5: FH-FSK 80, PSK 250, 500, 1200, 1300, 5300. */
extern const unsigned kelp_modemsim_rate_bps[6];

/** Seconds on the water of a data packet of `frames` full frames at `rate` (0 for a bad rate). */
double kelp_modemsim_packet_seconds(unsigned rate, unsigned frames);

/** Travel time (s) between two points (x, y, depth in metres) at sound speed c (m/s). */
double kelp_modemsim_travel_time(double x1, double y1, double z1, double x2, double y2, double z2, double c);

/** Minimal slot length (s) for one polled data slot at `rate` with all its frames: the Eq. 2.1
 *  overhead tau_ci + r_max/c, then the data packet and its travel, then an acknowledgement:
 *  ci + packet + mini + 2 turnaround + 3 r_max/c. */
double kelp_modemsim_min_slot_seconds(unsigned rate, double max_range, double ci_seconds, double mini_seconds,
                                  double turnaround_seconds, double sound_speed);

/* ------------------------------------------------------------------ packets on the channel */

typedef enum kelp_modemsim_pkt_kind {
    KELP_MODEMSIM_PKT_CYCLE_INIT = 1, /**< $CCCYC: adr1 adr2 rate ack nframes cmd */
    KELP_MODEMSIM_PKT_DATA = 2,       /**< frames (each with its own src/dest/ack) */
    KELP_MODEMSIM_PKT_ACK = 3,        /**< ack_mask of frames of the data packet from `dest` */
    KELP_MODEMSIM_PKT_PING = 4,       /**< two-way ping src -> dest */
    KELP_MODEMSIM_PKT_PING_REPLY = 5, /**< reply dest <- src; turnaround as measured by the replier */
    KELP_MODEMSIM_PKT_MINI = 6        /**< $CCMUC 13-bit mini-packet */
} kelp_modemsim_pkt_kind;

typedef struct kelp_modemsim_frame {
    uint8_t src, dest;
    bool ack;
    uint16_t len;
    uint8_t data[KELP_MAX_ACOMMS_FRAME];
} kelp_modemsim_frame;

typedef struct kelp_modemsim_pkt {
    kelp_modemsim_pkt_kind kind;
    uint32_t instance;       /**< transmitting simulator instance (a modem ignores its own) */
    uint32_t seq;            /**< per-instance transmission counter */
    uint8_t src;             /**< acoustic address (SRC) of the transmitter */
    uint8_t dest;
    uint8_t cmd, adr1, adr2; /**< cycle init */
    uint8_t rate;
    uint8_t ack;             /**< cycle init: ACK flag */
    uint8_t nframes;         /**< cycle init: frames announced; data: frames carried */
    uint32_t ack_mask;       /**< ack: bit f = frame f+1 acknowledged */
    uint16_t mini;           /**< mini-packet payload (13 bits) */
    kelp_time start;         /**< transmission start (shared clock; whole microseconds) */
    kelp_time duration;      /**< seconds (whole microseconds) */
    kelp_time turnaround;    /**< ping reply: seconds between the ping's end and the reply's start */
    double x, y, depth;      /**< transmitter position at start */
    kelp_modemsim_frame frame[KELP_MAX_MM_FRAMES];
} kelp_modemsim_pkt;

/** Bytes of the largest encoded packet. */
#define KELP_MODEMSIM_PKT_MAX_ENCODED (80 + KELP_MAX_MM_FRAMES * (5 + KELP_MAX_ACOMMS_FRAME))

/** Encode for the bus ("KMS1", little-endian, only the frames carried).
 *  @return 0 or KELP_ERR_NOSPACE / KELP_ERR_ARG (bad kind, too many frames, frame too long). */
KELP_MUST_CHECK int kelp_modemsim_pkt_encode(const kelp_modemsim_pkt *p, uint8_t *buf, size_t cap, size_t *len);
/** Decode and validate (every length and enum checked; safe on arbitrary bytes).
 *  @return 0, KELP_ERR_PARSE (magic, kind, rate, ids, counts), KELP_ERR_TRUNCATED, KELP_ERR_RANGE
 *  (also a start outside 1843..2096, which a kelp_time would not hold to the microsecond). */
KELP_MUST_CHECK int kelp_modemsim_pkt_decode(const uint8_t *buf, size_t len, kelp_modemsim_pkt *p);

/* ------------------------------------------------------------------ one simulated modem */

typedef struct kelp_modemsim_cfg {
    int modem_id;              /**< initial NVRAM SRC, 1..127 (the host may change it: $CCCFG,SRC) */
    uint32_t instance;         /**< unique per simulator process (0 is allowed) */
    double x, y, depth;        /**< initial position (m) */
    double sound_speed;        /**< m/s, default 1500 */
    double loss_probability;   /**< 0..1, default 0 */
    uint64_t seed;             /**< RNG seed, default 1 */
    double max_range;          /**< m; 0 = unlimited (default) */
    double ci_seconds;         /**< cycle-init packet, default 1.0 (tau_ci) */
    double mini_seconds;       /**< ack / ping / reply / mini-packet, default 0.5 */
    double turnaround_seconds; /**< before an ack, a ping reply or a polled data packet, default 0.25 */
    double drq_timeout_seconds;/**< wait for $CCTXD after a $CADRQ, default 2.0 */
    double ping_timeout_seconds; /**< forget an unanswered ping, default 10 */
    double rev_interval_seconds; /**< $CAREV,..,AUV heartbeat; 0 = none; default 60 */
    bool clock_set_at_boot;    /**< true: the modem clock starts at `now`; false (default): at
                                *   2000-01-01 00:00:00 + time since boot, until $CCCLK */
    const char *revision;      /**< firmware text for $CAREV, default "0.93.0.52" (copied) */
    unsigned n_lbl;            /**< REMUS LBL transponders (A..D) */
    double lbl_x[4], lbl_y[4], lbl_depth[4];
    double lbl_turnaround_seconds; /**< default 0.05 */
} kelp_modemsim_cfg;

typedef enum kelp_modemsim_event_kind {
    KELP_MODEMSIM_EV_TX = 1,     /**< a transmission started: pkt */
    KELP_MODEMSIM_EV_RX,         /**< a packet (or data frame) was received: pkt, frame (1-based, 0 = all) */
    KELP_MODEMSIM_EV_LOST,       /**< a packet / frame was lost: pkt, reason */
    KELP_MODEMSIM_EV_HOST_IN,    /**< a host line was accepted: text */
    KELP_MODEMSIM_EV_HOST_OUT,   /**< a sentence was written to the host: text (without CRLF) */
    KELP_MODEMSIM_EV_HOST_ERROR, /**< a host line was rejected ($CAERR sent): text, err */
    KELP_MODEMSIM_EV_INFO        /**< a notable state change: text */
} kelp_modemsim_event_kind;

typedef enum kelp_modemsim_loss {
    KELP_MODEMSIM_LOSS_NONE = 0,
    KELP_MODEMSIM_LOSS_RANDOM,      /**< the RNG dropped it */
    KELP_MODEMSIM_LOSS_COLLISION,   /**< another arrival overlapped it */
    KELP_MODEMSIM_LOSS_HALF_DUPLEX, /**< this modem was transmitting */
    KELP_MODEMSIM_LOSS_STALE        /**< it had already ended when it was heard */
} kelp_modemsim_loss;

typedef struct kelp_modemsim_event {
    kelp_modemsim_event_kind kind;
    kelp_time time;
    const kelp_modemsim_pkt *pkt;   /**< valid during the callback */
    unsigned frame;             /**< 1-based frame of a data packet, 0 = the whole packet */
    kelp_modemsim_loss loss;
    double range_m, travel_s;
    const char *text;           /**< NUL-terminated, valid during the callback ("" if none) */
    int err;
} kelp_modemsim_event;

/** ACOMMS_SIM_EVENT text of a transmission, reception or loss, e.g.
 *  "modem=1,event=rx,kind=data,src=2,dest=1,frame=1,range=750.0,travel=0.5000".
 *  @return 1 when written, 0 for the other event kinds, KELP_ERR_NOSPACE. */
struct kelp_modemsim;
KELP_MUST_CHECK int kelp_modemsim_event_format(const struct kelp_modemsim *m, const kelp_modemsim_event *e, char *buf, size_t cap);

typedef struct kelp_modemsim_ops {
    void (*write)(const char *bytes, size_t len, void *user);
    void (*transmit)(const kelp_modemsim_pkt *p, void *user);
    void (*event)(const kelp_modemsim_event *ev, void *user);  /**< optional */
} kelp_modemsim_ops;

typedef struct kelp_modemsim_counters {
    uint32_t host_lines, host_errors, host_out;
    uint32_t tx[7], rx[7];      /**< by kelp_modemsim_pkt_kind */
    uint32_t frames_tx, frames_rx, acks_out;
    uint32_t lost_random, lost_collision, lost_half_duplex, lost_stale, out_of_range, overflow;
} kelp_modemsim_counters;

typedef struct kelp_modemsim_nv {
    char name[4];
    long value, deflt;
} kelp_modemsim_nv;

typedef struct kelp_modemsim_arrival {
    bool used, decided;
    kelp_modemsim_loss loss;        /**< decided before its end (half duplex, collision) */
    int64_t start_us, end_us;
    double range_m, travel_s;
    kelp_modemsim_pkt pkt;
} kelp_modemsim_arrival;

typedef struct kelp_modemsim_txslot {
    int64_t due_us;
    kelp_modemsim_pkt pkt;
} kelp_modemsim_txslot;

typedef struct kelp_modemsim_txlog {
    int64_t start_us, end_us;
    kelp_modemsim_pkt_kind kind;
    unsigned bytes;
    bool txf_pending;           /**< $CATXF not yet written */
} kelp_modemsim_txlog;

typedef struct kelp_modemsim {
    /* configuration */
    kelp_modemsim_cfg cfg;
    char revision[24];
    kelp_modemsim_ops ops;
    void *user;
    /* state (private). Its times (*_us, and those of the arrival / txslot / txlog records) are
     * the simulator's internal clock in whole UNIX microseconds: arrival overlaps, turnarounds
     * and the modem clock are integer arithmetic, converted from / to kelp_time at the calls. */
    double x, y, depth;
    int64_t clock_offset_us;    /**< modem clock = now + offset */
    int64_t last_host_us, last_rev_us;
    kelp_rng rng;
    uint32_t seq;
    kelp_nmea_reader rd;
    kelp_nmea_sentence s;
    kelp_modemsim_nv nv[KELP_MAX_MSIM_NVRAM];
    size_t n_nv;
    /* data cycle being assembled (this modem is ADR1) */
    struct {
        bool active, drq_pending;
        uint8_t cmd, adr1, adr2, rate, ack, nframes;
        unsigned next;              /**< frames gathered */
        int64_t drq_deadline_us;
        int64_t not_before_us;      /**< the data packet starts after the cycle init */
    } cyc;
    kelp_modemsim_frame txbuf[KELP_MAX_MM_FRAMES]; /**< $CCTXD given without a $CADRQ */
    unsigned n_txbuf;
    kelp_modemsim_frame gathered[KELP_MAX_MM_FRAMES];
    /* ping in flight */
    bool ping_active;
    uint8_t ping_dest;
    int64_t ping_start_us, ping_duration_us;
    /* LBL interrogation in flight */
    bool lbl_active;
    int64_t lbl_start_us, lbl_timeout_us;
    bool lbl_enable[4];
    kelp_modemsim_txslot txq[KELP_MAX_MSIM_TXQ];
    size_t n_txq;
    int64_t busy_until_us;
    kelp_modemsim_txlog txlog[KELP_MAX_MSIM_TXLOG];
    size_t txlog_next;
    kelp_modemsim_arrival arr[KELP_MAX_MSIM_ARRIVALS];
    kelp_modemsim_counters count;
    kelp_modemsim_pkt scratch;      /**< packet being built */
    /* scratch of one call (large for a firmware stack); callbacks must not feed or tick this
     * modem again while they run (as for m->s and the line reader) */
    kelp_modemsim_txslot txwork;    /**< the transmission being started (out of txq) */
    char line[KELP_MAX_NMEA_LINE + 1]; /**< the host line being handled, NUL-terminated */
    char rxd[KELP_MAX_NMEA_LINE + 4];  /**< a $CARXD being written */
    kelp_modemsim_frame txd;        /**< the frame of a $CCTXD being handled */
    kelp_diag diag;                 /**< first error (transmit queue full, packets in flight...) */
} kelp_modemsim;

void kelp_modemsim_cfg_default(kelp_modemsim_cfg *cfg);

/** Configure (copies cfg).  KELP_ERR_ARG for a modem id outside 1..127, a negative or non-finite
 *  duration, loss outside [0,1], a sound speed <= 0, more than 4 LBL transponders. */
KELP_MUST_CHECK int kelp_modemsim_init(kelp_modemsim *m, const kelp_modemsim_cfg *cfg, const kelp_modemsim_ops *ops, void *user,
                                   kelp_time now);

/** Power-on message: $CAREV,hhmmss,INIT,<revision>. */
void kelp_modemsim_boot(kelp_modemsim *m, kelp_time now);

/** Bytes from the host (lines end with CR, LF or both).  @return 0 or KELP_ERR_ARG. */
KELP_MUST_CHECK int kelp_modemsim_feed(kelp_modemsim *m, const uint8_t *bytes, size_t n, kelp_time now);

/** A packet heard on the channel (own packets are ignored).  @return 0, or KELP_ERR_NOSPACE when
 *  too many packets are in flight (counted in overflow; the packet is not received). */
KELP_MUST_CHECK int kelp_modemsim_hear(kelp_modemsim *m, const kelp_modemsim_pkt *p, kelp_time now);

/** Timers: scheduled transmissions, arrivals that ended, DRQ / ping / LBL timeouts, heartbeat. */
void kelp_modemsim_tick(kelp_modemsim *m, kelp_time now);

/** Earliest time at which kelp_modemsim_tick has something to do (HUGE_VAL if nothing). */
kelp_time kelp_modemsim_next_due(const kelp_modemsim *m);

void kelp_modemsim_set_position(kelp_modemsim *m, double x, double y, double depth);
/** The acoustic address now in use (NVRAM SRC). */
int kelp_modemsim_src(const kelp_modemsim *m);
/** The NVRAM value of a parameter (3 letters). @return 0 or KELP_ERR_NOTFOUND. */
KELP_MUST_CHECK int kelp_modemsim_nvram(const kelp_modemsim *m, const char *name, long *value);
/** The modem clock (kelp_time) at `now`. */
kelp_time kelp_modemsim_clock(const kelp_modemsim *m, kelp_time now);
const kelp_modemsim_counters *kelp_modemsim_get_counters(const kelp_modemsim *m);

#ifdef __cplusplus
}
#endif

#endif
