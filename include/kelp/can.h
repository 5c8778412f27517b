/* kelp over CAN: bus variables carried in classic CAN (8-byte) and CAN FD (64-byte) frames.
 *
 * The wire format (docs/CAN.md has the full table, written for a firmware engineer):
 *
 * 29-bit extended CAN id
 *   28..26  priority (0 wins arbitration; kelp sends KELP_CAN_PRIO_DEFAULT unless told)
 *   25..21  protocol tag, always KELP_CAN_TAG (0x15): kernel and hardware filters select kelp
 *   20..14  source node id, 1..127 (0 is reserved)
 *   13..9   transfer id, 0..31, the sender's message counter (wraps)
 *    8..0   variable id from the dictionary, 0..510; 511 (KELP_CAN_VAR_NAMED) = the
 *           variable's name travels in the message body
 *
 * Data bytes: byte 0 is a protocol control byte (PCI), high two bits the frame type
 *   00 single frame       low 6 bits: body length L (1..7 classic, 1..63 FD); body in 1..L
 *   01 first frame        low 6 bits 0; bytes 1-2 body length (big-endian, > one single frame);
 *                         bytes 3-4 CRC-16/CCITT-FALSE of the body; bytes 5.. the first chunk
 *                         (3 bytes classic, 59 FD). The frame is full: 8 or 64 bytes.
 *   10 consecutive frame  low 6 bits: index 1..63; bytes 1.. chunk (7 classic, 63 FD) at body
 *                         offset first_chunk + (index-1)*chunk. Full except the last.
 *   11 reserved (junk)
 * All frames of one message have the same CAN id and the same format (classic or FD).
 * Consecutive frames may arrive in any order (each one's index says where it goes).
 *
 * Body: a header byte, then the fields it announces, numbers big-endian:
 *   bits 2..0 value kind: 0 f64, 1 f32, 2 i32, 3 string, 4 binary
 *   bit 3 time present (f64 seconds), bit 4 name present, bit 5 source present, bits 7..6 zero
 *   [time f64] [name: u8 length + bytes] [source: u8 length + bytes] value
 *   value: f64 8 bytes, f32 4 bytes, i32 4 bytes (two's complement); string/binary: the rest
 * The name is present exactly when the variable id is KELP_CAN_VAR_NAMED.
 *
 * Everything here is allocation-free with no I/O and no clock: times are arguments. The same
 * code runs in Cortex-M firmware (firmware/can_node.c). The SocketCAN edge is kelp/edge/can.h.
 */
#ifndef KELP_CAN_H
#define KELP_CAN_H
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/bus.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_CAN_TAG 0x15u              /**< protocol tag, CAN id bits 25..21 */
#define KELP_CAN_PRIO_DEFAULT 4u
#define KELP_CAN_VAR_NAMED 511u         /**< variable id: name in the body */
#define KELP_CAN_MAX_NODE 127u
#define KELP_CAN_EFF_MASK 0x1FFFFFFFu

#define KELP_CAN_ID(prio, node, tid, var)                                                            \
    ((((uint32_t)(prio) & 7u) << 26) | (KELP_CAN_TAG << 21) | (((uint32_t)(node) & 0x7Fu) << 14) | \
     (((uint32_t)(tid) & 0x1Fu) << 9) | ((uint32_t)(var) & 0x1FFu))
#define KELP_CAN_ID_PRIO(id) (((id) >> 26) & 7u)
#define KELP_CAN_ID_TAG(id) (((id) >> 21) & 0x1Fu)
#define KELP_CAN_ID_NODE(id) (((id) >> 14) & 0x7Fu)
#define KELP_CAN_ID_TID(id) (((id) >> 9) & 0x1Fu)
#define KELP_CAN_ID_VAR(id) ((id) & 0x1FFu)

#define KELP_CAN_PCI_SINGLE 0x00u
#define KELP_CAN_PCI_FIRST 0x40u
#define KELP_CAN_PCI_CONSEC 0x80u
#define KELP_CAN_MAX_SEGS 63u           /**< consecutive frames in one message */
#define KELP_CAN_CLASSIC_FIRST 3u       /**< body bytes in a classic first frame */
#define KELP_CAN_CLASSIC_CHUNK 7u
#define KELP_CAN_FD_FIRST 59u
#define KELP_CAN_FD_CHUNK 63u

#define KELP_CAN_KIND_F64 0u
#define KELP_CAN_KIND_F32 1u
#define KELP_CAN_KIND_I32 2u
#define KELP_CAN_KIND_STRING 3u
#define KELP_CAN_KIND_BINARY 4u
#define KELP_CAN_HDR_TIME 0x08u
#define KELP_CAN_HDR_NAME 0x10u
#define KELP_CAN_HDR_SOURCE 0x20u

/** Largest message body; the classic limit (3 + 63 * 7) so every message fits both formats.
 *  A firmware build may define it smaller. */
#ifndef KELP_CAN_MAX_BODY
#define KELP_CAN_MAX_BODY 444u
#endif
/** Messages being reassembled at once (a firmware build may define it smaller). */
#ifndef KELP_CAN_SLOTS
#define KELP_CAN_SLOTS 8u
#endif
/** Entries in a variable-name dictionary. */
#ifndef KELP_CAN_DICT_MAX
#define KELP_CAN_DICT_MAX 64u
#endif
/** Name bytes kept for a dictionary entry and a decoded name or source, with NUL. */
#define KELP_CAN_NAME 64u
/** Kernel-filter entries kelp_can_filters() produces at most. */
#define KELP_CAN_MAX_FILTERS 64u
#define KELP_CAN_TIMEOUT_DEFAULT 1.0    /**< seconds a partial message may wait */

KELP_STATIC_ASSERT(KELP_CAN_MAX_BODY <= KELP_CAN_CLASSIC_FIRST + KELP_CAN_MAX_SEGS * KELP_CAN_CLASSIC_CHUNK,
                   "a body must fit a classic transfer");

/** One frame as it is on the bus. id is the 29-bit extended id (no flag bits). */
typedef struct kelp_can_frame {
    uint32_t id;
    uint8_t len;     /**< data bytes, 0..8 classic; FD: 0..8, 12, 16, 20, 24, 32, 48, 64 */
    bool fd;         /**< CAN FD format */
    uint8_t data[64];
} kelp_can_frame;

/** A variable-name dictionary: the same on both ends of the bus. */
typedef struct kelp_can_dict_entry {
    uint16_t id;
    char name[KELP_CAN_NAME];
} kelp_can_dict_entry;
typedef struct kelp_can_dict {
    kelp_can_dict_entry e[KELP_CAN_DICT_MAX];
    size_t n;
} kelp_can_dict;

void kelp_can_dict_init(kelp_can_dict *d);
/** Add id <-> name. KELP_ERR_RANGE (id > 510 or name too long), KELP_ERR_EXISTS (id or name
 *  already there), KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_can_dict_add(kelp_can_dict *d, unsigned id, const char *name);
/** Add the pairs of "1=NAV_X, 2=NAV_Y" (kv list). KELP_ERR_PARSE (reason in d) on a bad pair. */
KELP_MUST_CHECK int kelp_can_dict_parse(kelp_can_dict *dict, const char *spec, kelp_diag *d);
/** The id of a name, or -1. */
int kelp_can_dict_id(const kelp_can_dict *d, const char *name);
/** The name of an id, or NULL. */
const char *kelp_can_dict_name(const kelp_can_dict *d, unsigned id);

/** A message as the framing sees it. Decoded pointers point into the receiver and stay
 *  valid until its next call. */
typedef struct kelp_can_msg {
    uint8_t node;            /**< source node (decoded; the sender's own on encode) */
    uint16_t var;            /**< variable id (KELP_CAN_VAR_NAMED when named) */
    const char *name;        /**< NUL-terminated variable name (dictionary's when var is an id) */
    const char *source;      /**< NUL-terminated source, or NULL when absent */
    bool has_time;
    double time;
    unsigned kind;           /**< KELP_CAN_KIND_*; on encode F64 means "choose f32/i32 when exact" */
    double dval;             /**< numeric kinds */
    const uint8_t *sval;     /**< string/binary bytes (a decoded string is NUL-terminated) */
    size_t slen;
} kelp_can_msg;

/** Sender state. */
typedef struct kelp_can_tx {
    uint8_t node;            /**< 1..127 */
    uint8_t prio;            /**< 0..7 */
    uint8_t tid;             /**< next transfer id */
    bool fd;                 /**< send CAN FD frames */
    bool exact_f64;          /**< never shrink a double to f32/i32 */
    uint8_t body[KELP_CAN_MAX_BODY];
} kelp_can_tx;

KELP_MUST_CHECK int kelp_can_tx_init(kelp_can_tx *tx, unsigned node, bool fd);

/** Called once per frame, in order; a return < 0 stops the send (and is returned). */
typedef int (*kelp_can_emit_fn)(void *user, const kelp_can_frame *f);

/** Encode m (name looked up in d; when absent it travels named) and emit its frames.
 *  m->source and m->has_time are sent when set. @return number of frames, or
 *  KELP_ERR_RANGE (too big for KELP_CAN_MAX_BODY / name over 255), KELP_ERR_ARG. */
KELP_MUST_CHECK int kelp_can_send(kelp_can_tx *tx, const kelp_can_dict *d, const kelp_can_msg *m,
                                  kelp_can_emit_fn emit, void *user);

/** Receiver counters. Every frame handed in is counted in exactly one of frames_ok /
 *  bad_frame / foreign / duplicate / slot_full. */
typedef struct kelp_can_stats {
    unsigned long frames;        /**< handed in */
    unsigned long frames_ok;     /**< used */
    unsigned long messages;      /**< complete messages delivered */
    unsigned long foreign;       /**< not kelp (standard id or another tag): ignored */
    unsigned long bad_frame;     /**< kelp tag but malformed (PCI, length, index, mixed format) */
    unsigned long out_of_order;  /**< consecutive frames that arrived before an earlier one */
    unsigned long duplicate;     /**< a segment already held */
    unsigned long timed_out;     /**< partial messages dropped after the timeout */
    unsigned long aborted;       /**< partial messages replaced by a new first frame */
    unsigned long slot_full;     /**< frames of a new message with every slot busy */
    unsigned long bad_crc;       /**< reassembled bodies whose CRC did not match */
    unsigned long bad_body;      /**< bodies that did not parse */
    unsigned long unknown_var;   /**< variable ids not in the dictionary */
} kelp_can_stats;

typedef struct kelp_can_slot {
    bool used, have_first, fd;
    uint32_t key;                /**< CAN id without priority */
    uint16_t total, crc;
    uint8_t nseg;                /**< consecutive frames expected (known after the first) */
    uint8_t highest;             /**< highest index seen */
    uint64_t got;                /**< bit i: index i held (bit 0: first frame) */
    double started;
    uint8_t buf[KELP_CAN_MAX_BODY];
} kelp_can_slot;

typedef struct kelp_can_rx {
    kelp_can_slot slots[KELP_CAN_SLOTS];
    double timeout;
    kelp_can_stats st;
    uint8_t body[KELP_CAN_MAX_BODY]; /**< a completed body (single frames are copied here) */
    char name[KELP_CAN_NAME];
    char source[KELP_CAN_NAME];
    uint8_t value[KELP_CAN_MAX_BODY + 1];
} kelp_can_rx;

void kelp_can_rx_init(kelp_can_rx *rx, double timeout);
/** Drop partial messages older than the timeout (counted timed_out).  The time step rule
 *  (docs/ARCHITECTURE.md): a partial message started after `now` (the clock stepped back) waits
 *  one timeout from now; a NaN or infinite `now` drops nothing. */
void kelp_can_rx_expire(kelp_can_rx *rx, kelp_time now);
/** Feed one frame. @return 1 when *out holds a complete message, 0 when the frame was used
 *  (or ignored as foreign), < 0 when it was refused (counted; never fatal), KELP_ERR_ARG
 *  (not counted, nothing changed) for a NaN, infinite or absurd `now`. */
KELP_MUST_CHECK int kelp_can_rx_frame(kelp_can_rx *rx, const kelp_can_dict *d, const kelp_can_frame *f, kelp_time now,
                      kelp_can_msg *out);

/** Fill a kelp_var from a decoded message: name as given (or `as` when non-empty), source
 *  (the message's, else "can<node>"), time (the message's, else now). */
KELP_MUST_CHECK int kelp_can_msg_to_var(const kelp_can_msg *m, const char *as, kelp_time now, kelp_var *v);
/** A kelp_var as a message to send (pointers into v). */
void kelp_can_msg_from_var(const kelp_var *v, const char *as, kelp_can_msg *m);

/** An acceptance filter as CAN_RAW_FILTER takes it: match when (id & mask) == (want & mask)
 *  (both with bit 31 standing for the extended-frame flag, as in SocketCAN). */
typedef struct kelp_can_filter {
    uint32_t id, mask;
} kelp_can_filter;
#define KELP_CAN_FILTER_EFF 0x80000000u

/** Filters accepting kelp frames carrying the given variable ids (KELP_CAN_VAR_NAMED for
 *  named ones); n == 0 accepts every kelp frame. Never more than KELP_CAN_MAX_FILTERS:
 *  past that it falls back to one filter for all of kelp. @return number written. */
size_t kelp_can_filters(const uint16_t *vars, size_t n, kelp_can_filter *out, size_t cap);
/** Whether a frame id (29 bits, extended) passes a filter list (n == 0: passes). */
bool kelp_can_filter_pass(const kelp_can_filter *f, size_t n, uint32_t id, bool eff);

/** CAN FD data length for a payload of len bytes (the next valid DLC size); 0 if > 64. */
uint8_t kelp_can_fd_len(size_t len);
/** CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor). */
uint16_t kelp_can_crc16(const uint8_t *p, size_t n);

#ifdef __cplusplus
}
#endif
#endif
