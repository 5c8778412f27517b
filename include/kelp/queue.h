/* kelp: Goby 1.1 libqueue -- the priority queue of the acoustic stack (core; no allocation).
 *
 * One queue per DCCL message id (configured from the XML <queuing> block) and per CCL queue
 * (first byte of the CCL message).  On every modem data request the queues hold a contest:
 *   P = (now - last_send_time) / ttl * value_base           (seconds, double; ttl 0 -> inf/NaN)
 * highest P wins; a tie goes to the older last_send_time, then to the first queue in key order
 * (id, then DCCL before CCL).  Several DCCL messages are stitched into one modem frame exactly as
 * Goby 1.1 does (byte-compatible), and received frames are unstitched back into pieces.
 *
 * Storage: the caller passes an array of kelp_queue (one per queue) and a pool of
 * kelp_queue_entry (one per message held over all queues).  Time is an argument (kelp_time),
 * compared in whole microseconds as Goby does.  Everything the queue reports (received
 * pieces, acks, expiries, queue sizes) goes through one event callback with `void *user` last.
 *
 * DCCL messages are byte strings whose first 6 bytes are the DCCL header:
 *   ccl id 8 (0x20) | id 9 | time 17 | src 5 | dest 5 | multimessage 1 | broadcast 1 | unused 2
 * The queue never decodes bodies; it only touches the two flag bits of header byte 5.
 */
#ifndef KELP_QUEUE_H
#define KELP_QUEUE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/util.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_QUEUE_DCCL 1             /**< QueueType QUEUE_DCCL */
#define KELP_QUEUE_CCL 2              /**< QueueType QUEUE_CCL */
#define KELP_ACOMMS_BROADCAST 0       /**< modem id 0 = broadcast */
#define KELP_ACOMMS_QUERY_DEST (-1)   /**< slot/request dest -1 = "ask the queue" */
#ifndef KELP_DCCL_CCL_ID
#define KELP_DCCL_CCL_ID 32u          /**< first byte of every DCCL message (also in dccl.h) */
#endif
#define KELP_DCCL_HEADER_BYTES 6
#define KELP_DCCL_MULTIMESSAGE_MASK 0x08 /**< bit 44 = header byte 5, 0x08 */
#define KELP_DCCL_BROADCAST_MASK 0x04    /**< bit 45 = header byte 5, 0x04 */
#define KELP_QUEUE_DCCL_MIN_ID 1      /**< Goby 1.1 accepts DCCL queue ids 1..512 */
#define KELP_QUEUE_DCCL_MAX_ID 512

typedef struct kelp_queue_key {
    uint8_t type;   /**< KELP_QUEUE_DCCL or KELP_QUEUE_CCL */
    uint32_t id;    /**< DCCL id, or the CCL id byte */
} kelp_queue_key;

/** Queue configuration (QueueConfig / XML <queuing>). */
typedef struct kelp_queue_cfg {
    kelp_queue_key key;
    const char *name;       /**< not copied: must outlive the manager (may be NULL) */
    bool ack;               /**< default true */
    uint32_t blackout_time; /**< seconds, default 0 */
    uint32_t max_queue;     /**< default 0 = unlimited */
    bool newest_first;      /**< default true (FILO) */
    double value_base;      /**< default 1 */
    uint32_t ttl;           /**< seconds, default 1800 */
    bool on_demand;         /**< ON_DEMAND manipulator (DCCL): encode at the contest */
    bool loopback;          /**< LOOPBACK manipulator (DCCL): queue and loop back */
    bool no_queue;          /**< NO_QUEUE manipulator (DCCL): never queued */
} kelp_queue_cfg;

/** A modem data transmission (ModemDataTransmission): one queued message, one modem frame or
 *  one received piece. */
typedef struct kelp_acomms_msg {
    int src;
    int dest;
    bool ack_requested;
    bool has_ack;           /**< ack_requested was set (else the queue's `ack` applies) */
    bool has_time;
    kelp_time time;         /**< base.time (kelp_time seconds); used for expiry */
    uint32_t frame;         /**< Goby frame number (WHOI frame - 1) */
    kelp_queue_key key;     /**< queue of the message (push) / of the piece (receive) */
    size_t len;
    uint8_t data[KELP_MAX_ACOMMS_FRAME];
} kelp_acomms_msg;

/** One stored message (pool element; treat as opaque). */
typedef struct kelp_queue_entry {
    kelp_acomms_msg msg;
    int32_t prev, next;     /**< links inside its queue, -1 = none */
    int32_t ack_frame;      /**< frame this message waits an ack for, -1 = not waiting */
    uint32_t ack_seq;       /**< order among messages waiting for the same frame */
    bool used;
} kelp_queue_entry;

/** One queue (treat as opaque; read with the accessors). */
typedef struct kelp_queue {
    kelp_queue_cfg cfg;
    kelp_time last_send;    /**< starts at creation; set when the queue gives a message */
    int32_t head, tail;     /**< oldest, newest; -1 when empty */
    uint32_t size;
    uint32_t n_waiting;     /**< messages of this queue waiting for an ack */
} kelp_queue;

typedef enum kelp_queue_event_kind {
    KELP_QUEUE_EV_RECEIVE = 1,  /**< a DCCL piece for us (signal_receive): msg, key */
    KELP_QUEUE_EV_RECEIVE_CCL,  /**< a CCL frame for a configured CCL queue: msg, key */
    KELP_QUEUE_EV_ACK,          /**< a message was acknowledged: msg = original, key, frame */
    KELP_QUEUE_EV_EXPIRE,       /**< a message expired (ttl): msg = original, key */
    KELP_QUEUE_EV_QSIZE         /**< a queue's size (maybe) changed: key, size */
} kelp_queue_event_kind;

typedef struct kelp_queue_event {
    kelp_queue_event_kind kind;
    kelp_queue_key key;
    const kelp_acomms_msg *msg; /**< valid during the callback only */
    uint32_t size;
    uint32_t frame;
} kelp_queue_event;

typedef void (*kelp_queue_event_fn)(const kelp_queue_event *ev, void *user);

/** A data request from the driver (ModemDataRequest). */
typedef struct kelp_queue_request {
    int dest;               /**< destination of the packet, -1 = ask the queue */
    uint32_t frame;         /**< 0 starts a new packet */
    uint32_t max_bytes;     /**< frame size (32/64/256); 0 = KELP_MAX_ACOMMS_FRAME */
} kelp_queue_request;

/** ON_DEMAND hook: fill *out (data, dest, time...) for queue `key`; the manager pushes it. */
typedef void (*kelp_queue_on_demand_fn)(kelp_queue_key key, const kelp_queue_request *req,
                                        kelp_acomms_msg *out, void *user);

typedef struct kelp_queue_wait {
    uint32_t frame;
    uint16_t q;
} kelp_queue_wait;

typedef struct kelp_queue_counters {
    uint32_t rx_frames;     /**< frames handed to kelp_queue_receive */
    uint32_t rx_pieces;     /**< pieces delivered (RECEIVE + RECEIVE_CCL) */
    uint32_t rx_not_for_us; /**< pieces with another destination */
    uint32_t rx_no_queue;   /**< pieces / CCL frames without a configured queue */
    uint32_t rx_malformed;  /**< frames too short, or stitched frames cut short */
    uint32_t pushed, rejected, expired, acked, dropped_overflow;
    uint32_t clock_steps;   /**< backward clock steps absorbed (stored times moved back) */
} kelp_queue_counters;

typedef struct kelp_queue_mgr {
    int modem_id;
    kelp_queue *q;          /**< caller array, kept sorted by key */
    size_t nq, cap_q;
    kelp_queue_entry *pool; /**< caller array */
    size_t cap_pool;
    kelp_queue_wait wait[KELP_MAX_QUEUE_ACK_WAIT]; /**< QueueManager::waiting_for_ack_, in order */
    size_t nwait;
    uint32_t ack_seq;
    bool packet_ack;
    int packet_dest;
    kelp_queue_event_fn event;
    kelp_queue_on_demand_fn on_demand;
    void *user;
    kelp_queue_counters count;
    kelp_diag diag;         /**< first error (code KELP_OK if none) */
    kelp_clock clock;       /**< newest `now` of do_work / data_request (the time step rule) */
    /* scratch (not on the stack, which is small on firmware); all three can be in use at once:
     * a data request stitches `next` while an ON_DEMAND queue fills `fresh`, whose loopback
     * push receives it through `rx` */
    kelp_acomms_msg next;   /**< stitch: the message being packed into the frame */
    kelp_acomms_msg fresh;  /**< ON_DEMAND: the message asked of the application */
    kelp_acomms_msg rx;     /**< receive: the piece being handed to the application */
} kelp_queue_mgr;

/** Defaults of QueueConfig: ack true, blackout 0, max_queue 0, newest_first true,
 *  value_base 1, ttl 1800, no manipulators. */
void kelp_queue_cfg_default(kelp_queue_cfg *cfg, uint8_t type, uint32_t id);

/** Initialise a manager over caller storage.  event/on_demand may be NULL. */
KELP_MUST_CHECK int kelp_queue_init(kelp_queue_mgr *m, int modem_id, kelp_queue *queues, size_t cap_queues,
                                    kelp_queue_entry *pool, size_t cap_pool, kelp_queue_event_fn event,
                                    kelp_queue_on_demand_fn on_demand, void *user);

/** Add a queue (last_send_time = now).  Emits QSIZE 0.  KELP_ERR_EXISTS for a duplicate key,
 *  KELP_ERR_RANGE for a DCCL id outside 1..512, KELP_ERR_NOSPACE when the array is full. */
KELP_MUST_CHECK int kelp_queue_add(kelp_queue_mgr *m, const kelp_queue_cfg *cfg, kelp_time now);

/** Push a message (msg->key names the queue).  dest == own id: looped back to the receive path,
 *  not queued.  src is set to the own id; ack_requested defaults to the queue's `ack`.
 *  A QSIZE event follows every push attempt on an existing queue (as Goby), even a rejected one.
 *  @return 0; KELP_ERR_NOTFOUND (no queue); KELP_ERR_ARG (empty data, CCL data whose first byte
 *  is not the queue id, DCCL data shorter than the 6-byte header); KELP_ERR_NOSPACE (pool full). */
KELP_MUST_CHECK int kelp_queue_push(kelp_queue_mgr *m, const kelp_acomms_msg *msg, kelp_time now);

/** Answer a modem data request (handle_modem_data_request): fills *out with src, dest,
 *  ack_requested and the (possibly stitched) frame; out->len 0 = nothing to send (a blank). */
KELP_MUST_CHECK int kelp_queue_data_request(kelp_queue_mgr *m, const kelp_queue_request *req, kelp_time now,
                                           kelp_acomms_msg *out);

/** Handle a modem ack (handle_modem_ack): ignored unless dest == own id and a message waits for
 *  `frame` in the current packet.  @return number of messages acknowledged (>= 0). */
int kelp_queue_ack(kelp_queue_mgr *m, int src, int dest, uint32_t frame);

/** Handle a received frame (handle_modem_receive): DCCL (first byte 0x20) is unstitched and
 *  each piece for us (dest 0 via the broadcast flag, or own id) with a queue is reported;
 *  a CCL frame goes to its CCL queue.  @return number of pieces reported (>= 0). */
int kelp_queue_receive(kelp_queue_mgr *m, const kelp_acomms_msg *frame);

/** Expire old messages (do_work): per queue, from the oldest, while time + ttl < now.
 *  The time step rule (docs/ARCHITECTURE.md), here and in kelp_queue_data_request: a `now`
 *  behind the newest one seen is a backward clock step, and every stored time (send times,
 *  message times) moves back as far, so blackouts and ttls keep what remained of them; a step
 *  forward is elapsed time.  A NaN, infinite or absurd `now` is ignored here and refused
 *  (KELP_ERR_ARG) by the calls that return a status. */
void kelp_queue_do_work(kelp_queue_mgr *m, kelp_time now);

/** Empty a queue (emits QSIZE).  KELP_ERR_NOTFOUND if no such queue. */
KELP_MUST_CHECK int kelp_queue_flush(kelp_queue_mgr *m, kelp_queue_key key);

/** Current size of a queue, or -1 if no such queue. */
long kelp_queue_size(const kelp_queue_mgr *m, kelp_queue_key key);

/** Priority of a queue at `now` (the contest formula), NAN-free only for ttl > 0. */
KELP_MUST_CHECK int kelp_queue_priority(const kelp_queue_mgr *m, kelp_queue_key key, kelp_time now, double *prio);

/* ------------------------------------------------------------------ DCCL header helpers */

typedef struct kelp_queue_header {
    unsigned ccl_id;        /**< 8 bits, 0x20 for DCCL */
    unsigned id;            /**< 9 bits */
    unsigned time_of_day;   /**< 17 bits: seconds since UTC midnight */
    unsigned src, dest;     /**< 5 bits each */
    bool multimessage, broadcast;
    unsigned unused;        /**< 2 bits */
} kelp_queue_header;

/** Read the 6-byte header.  KELP_ERR_TRUNCATED if n < 6. */
KELP_MUST_CHECK int kelp_queue_header_read(const uint8_t *d, size_t n, kelp_queue_header *h);
/** Write a header (values are taken modulo their widths). */
void kelp_queue_header_write(const kelp_queue_header *h, uint8_t out[KELP_DCCL_HEADER_BYTES]);

/** Callback for each unstitched piece: the piece (header flags cleared) and the broadcast flag. */
typedef void (*kelp_unstitch_fn)(const uint8_t *piece, size_t len, unsigned dccl_id, bool broadcast, void *user);

/** Split a received DCCL frame (first byte 0x20) into its user-frames as Goby 1.1 does.
 *  @return number of pieces, or KELP_ERR_PARSE (not DCCL / < 6 bytes) or KELP_ERR_TRUNCATED
 *  (a multimessage piece without its size byte or without a following header; the pieces before
 *  it were still reported). */
KELP_MUST_CHECK int kelp_queue_unstitch(const uint8_t *d, size_t n, kelp_unstitch_fn fn, void *user);

#ifdef __cplusplus
}
#endif

#endif
