/* kelp: WHOI Micro-Modem driver core -- the protocol state machine of Goby 1.1's MMDriver
 * with no file descriptor, no clock, no allocation.
 *
 *   bytes in   kelp_mmdriver_feed(mm, bytes, n, now)      (serial/TCP reader at the edge)
 *   lines out  ops.write(bytes, n, user)             ("#M1" Hydroid prefix + "$CC...*hh\r\n")
 *   events     ops.event(&ev, user)                  (received frames, acks, ranges, raw NMEA ...)
 *   data       ops.data_request(&req, &frame, user)  (the queue fills a frame; len 0 = none)
 *   time       every call takes now (kelp_time; the timers count whole microseconds of it)
 *
 * Call kelp_mmdriver_tick(mm, now) often (Goby's do_work runs at app_tick, 10 Hz by default), then
 * feed what the link read: the same order as do_work (send, then read).
 *
 * Behaviour reproduced from Goby 1.1 (see the issue note for the list):
 *  - start-up: $CCCLK,Y,M,D,h,m,s (UTC, unpadded), a 1 s pause, [$CCCFG,ALL,0 if reset_nvram and
 *    not a Hydroid gateway], $CCCFG,SRC,<id>, each nvram_cfg upper-cased, $CCCFQ,ALL.
 *  - one outstanding command: the next queued $CC... is written only after a modem sentence with
 *    the same 3-letter id (the first $CACFG also completes $CCCFQ); no reply for 3 s -> written
 *    again; the third timeout clears the whole command queue; 5 timeouts without any sentence
 *    received in between -> KELP_MMDRIVER_EV_DEAD and kelp_mmdriver_tick() returns KELP_ERR_TIMEOUT until
 *    kelp_mmdriver_start() is called again (the edge reconnects).  $CAERR,...,NMEA,... counts as one
 *    timeout of the pending command and re-sends it at once.
 *  - Goby's sleep(1) after $CCCLK and sleep(2) after $CAREV,...,INIT are a "hold": bytes fed
 *    during the hold are kept and processed, and nothing is written, until `now` passes it.
 */
#ifndef KELP_MMDRIVER_H
#define KELP_MMDRIVER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/mac.h>
#include <kelp/nmea.h>
#include <kelp/util.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_MMDRIVER_MODEM_WAIT 3              /**< MODEM_WAIT: resend after 3 s (seconds) */
#define KELP_MMDRIVER_RETRIES 3                 /**< RETRIES: clear the command queue */
#define KELP_MMDRIVER_MAX_FAILS_BEFORE_DEAD 5
#define KELP_MMDRIVER_ALLOWED_SKEW 2            /**< seconds */
#define KELP_MMDRIVER_HYDROID_GPS_INTERVAL 30   /**< seconds */

/** Frames per packet and bytes per frame for rates 0..5 (PACKET_FRAME_COUNT, PACKET_SIZE). */
extern const unsigned kelp_mmdriver_packet_frames[6];
extern const unsigned kelp_mmdriver_packet_size[6];

typedef struct kelp_mmdriver_frame {
    int src, dest;
    bool ack_requested;
    size_t len;
    uint8_t data[KELP_MAX_ACOMMS_FRAME];
} kelp_mmdriver_frame;

typedef struct kelp_mmdriver_data_request {
    int src, dest;          /**< dest -1: ask the queue */
    uint32_t frame;         /**< Goby frame (0-based) */
    uint32_t max_bytes;
} kelp_mmdriver_data_request;

typedef enum kelp_mmdriver_event_kind {
    KELP_MMDRIVER_EV_NMEA_OUT = 1, /**< a sentence was written (raw, without prefix and CRLF) */
    KELP_MMDRIVER_EV_NMEA_IN,      /**< a sentence was processed (raw re-rendered with "*HH"; src if it has one) */
    KELP_MMDRIVER_EV_RECEIVE,      /**< $CARXD: src, dest, ack_requested, frame (0-based), data */
    KELP_MMDRIVER_EV_ACK,          /**< $CAACK for a frame sent with ack this cycle: src, dest, frame */
    KELP_MMDRIVER_EV_RANGE,        /**< $CAMPR / $SNTTA / $CATOA: src, dest, ranging, tt[n_tt] */
    KELP_MMDRIVER_EV_CYCLE,        /**< $CACYC: src = ADR1, dest = ADR2, rate, frame = number of frames */
    KELP_MMDRIVER_EV_MODEM_ERROR,  /**< $CAERR: raw */
    KELP_MMDRIVER_EV_BAD_LINE,     /**< a line was rejected: err, raw = the line */
    KELP_MMDRIVER_EV_RETRY,        /**< the pending command is written again: raw */
    KELP_MMDRIVER_EV_GIVE_UP,      /**< no answer after the retries: the command queue was cleared */
    KELP_MMDRIVER_EV_DEAD,         /**< the modem does not answer: reconnect and kelp_mmdriver_start() */
    KELP_MMDRIVER_EV_CLOCK         /**< clock state changed: clock_ok */
} kelp_mmdriver_event_kind;

typedef struct kelp_mmdriver_event {
    kelp_mmdriver_event_kind kind;
    kelp_time time;
    const char *raw;        /**< NUL-terminated, valid during the callback */
    size_t raw_len;
    bool has_src;
    int src, dest;
    bool ack_requested;
    uint32_t frame;
    unsigned rate;
    const uint8_t *data;
    size_t data_len;
    kelp_ranging_type ranging;
    unsigned n_tt;
    double tt[7];           /**< one-way travel times (s); NaN where the modem gave none */
    int err;
    bool clock_ok;
} kelp_mmdriver_event;

typedef struct kelp_mmdriver_ops {
    void (*write)(const char *bytes, size_t len, void *user);
    void (*event)(const kelp_mmdriver_event *ev, void *user);
    void (*data_request)(const kelp_mmdriver_data_request *req, kelp_mmdriver_frame *out, void *user);
} kelp_mmdriver_ops;

typedef struct kelp_mmdriver_cfg {
    int modem_id;                       /**< SRC, 1..31 */
    bool reset_nvram;                   /**< $CCCFG,ALL,0 at start-up (not with a Hydroid gateway) */
    const char *nvram_cfg[KELP_MAX_MM_NVRAM]; /**< e.g. "cst,1" (copied, upper-cased when sent) */
    size_t n_nvram;
    int hydroid_gateway_id;             /**< 0 = none; else "#M<id>" out, 3 chars stripped in */
    char line_delimiter;                /**< read delimiter; 0 = '\r' (Goby's MM default) */
} kelp_mmdriver_cfg;

typedef struct kelp_mmdriver_cmd {
    char line[KELP_MAX_NMEA_LINE + 1];
    size_t len;
    char id[4];
} kelp_mmdriver_cmd;

typedef struct kelp_mmdriver_counters {
    uint32_t lines_in, lines_out, bad_lines, retries, give_ups, modem_errors, backlog_dropped, deaths;
    uint32_t clock_steps;  /**< backward clock steps absorbed (the time step rule) */
} kelp_mmdriver_counters;

typedef struct kelp_mmdriver {
    int modem_id;
    bool reset_nvram;
    char nvram[KELP_MAX_MM_NVRAM][KELP_MAX_MM_NVRAM_LEN];
    size_t n_nvram;
    int hydroid_id;
    char prefix[12];
    kelp_mmdriver_ops ops;
    void *user;
    kelp_nmea_reader rd;
    kelp_nmea_sentence s;               /**< scratch for the sentence being processed */
    char raw[KELP_MAX_NMEA_LINE + 4];   /**< scratch: the sentence re-rendered (event raw text) */
    uint8_t rxdata[KELP_MAX_ACOMMS_FRAME]; /**< scratch: a $CARXD frame's bytes */
    char wbuf[12 + KELP_MAX_NMEA_LINE + 3]; /**< scratch: prefix + command + CRLF being written */
    kelp_mmdriver_cmd outq[KELP_MAX_MM_OUTQ]; /**< commands waiting (ring) */
    size_t out_head, out_n;
    bool waiting;                       /**< the front command was written, no reply yet */
    kelp_time last_write;
    unsigned global_fail, present_fail;
    bool clock_set, started, dead, local_cccyc;
    kelp_time hold_until;                /**< paused (sleep) until then; 0 = not */
    uint8_t backlog[KELP_MAX_MM_BACKLOG];
    size_t backlog_len;
    kelp_time last_gps;
    kelp_mmdriver_frame cache[KELP_MAX_MM_FRAMES];
    unsigned ncache;
    uint32_t ack_mask;                  /**< frames sent with ack=1 in the current cycle */
    bool toa_pending;
    double toa_frac;
    kelp_mmdriver_counters count;
    kelp_diag diag;                     /**< first error */
    kelp_clock clock;                   /**< newest `now` seen (the time step rule) */
} kelp_mmdriver;

/** Configure (copies cfg).  KELP_ERR_ARG for modem_id outside 1..31 (0 is broadcast) or a bad
 *  nvram entry, KELP_ERR_NOSPACE for too many / too long nvram entries. */
KELP_MUST_CHECK int kelp_mmdriver_init(kelp_mmdriver *mm, const kelp_mmdriver_cfg *cfg, const kelp_mmdriver_ops *ops, void *user);

/** (Re)start: forget queued commands and partial input, then the start-up sequence. */
KELP_MUST_CHECK int kelp_mmdriver_start(kelp_mmdriver *mm, kelp_time now);

/** Periodic work (do_work without the read): clock re-set, resend on timeout, Hydroid GPS
 *  query, lines held during a pause.  KELP_ERR_TIMEOUT once the modem is declared dead. */
KELP_MUST_CHECK int kelp_mmdriver_tick(kelp_mmdriver *mm, kelp_time now);

/** Bytes read from the modem.  Bad lines are reported (KELP_MMDRIVER_EV_BAD_LINE) and skipped.
 *  @return 0, or KELP_ERR_STATE before kelp_mmdriver_start(). */
KELP_MUST_CHECK int kelp_mmdriver_feed(kelp_mmdriver *mm, const uint8_t *bytes, size_t n, kelp_time now);

/** MAC slot (signal_initiate_transmission): src == own id requests the frames now and sends
 *  $CCCYC only if there are data; another src starts a third-party cycle (ACK field 1). */
KELP_MUST_CHECK int kelp_mmdriver_initiate_transmission(kelp_mmdriver *mm, int src, int dest, unsigned rate, kelp_time now);

/** A cycle of our own with frames the caller supplies (no data request is made): $CCCYC
 *  with ADR2/ACK from frames[0] and the rate's frame count; each $CADRQ is answered from
 *  frames (cut to the rate's size), and one beyond n with an empty $CCTXD. n == 0 sends
 *  nothing; n larger than the rate carries is KELP_ERR_RANGE. */
KELP_MUST_CHECK int kelp_mmdriver_transmit_frames(kelp_mmdriver *mm, unsigned rate, const kelp_mmdriver_frame *frames, size_t n,
                                            kelp_time now);

/** Ranging: TWO_WAY_PING -> $CCMPC,src,dest; REMUS_LBL -> $CCPDT (max_range m, beacon bits);
 *  ONE_WAY_SYNCHRONOUS cannot be requested (KELP_ERR_UNSUPPORTED). */
KELP_MUST_CHECK int kelp_mmdriver_initiate_ranging(kelp_mmdriver *mm, int src, int dest, kelp_ranging_type type,
                                             unsigned max_range, unsigned enable_beacons, kelp_time now);

/** The driver is pausing until this time (Goby's sleep); 0 if not. */
kelp_time kelp_mmdriver_busy_until(const kelp_mmdriver *mm);
bool kelp_mmdriver_clock_ok(const kelp_mmdriver *mm);
/** Commands queued (the first may be awaiting its reply). */
size_t kelp_mmdriver_pending(const kelp_mmdriver *mm);

/** UTC civil date of a UNIX time, rounded to the microsecond (helper, exposed for tests and
 *  the simulator). */
void kelp_mmdriver_civil(kelp_time t, int *year, int *month, int *day, int *hour, int *minute, int *second);

#ifdef __cplusplus
}
#endif

#endif
