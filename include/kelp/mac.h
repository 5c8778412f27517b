/* kelp: Goby 1.1 libamac -- slotted TDMA medium access control (core; no allocation, no clock).
 *
 * Time is an argument (kelp_time: UNIX UTC seconds).  Slot starts are whole seconds; the
 * manager compares times in whole microseconds (as Goby) after rounding `now`.  The manager
 * keeps the next slot start; the caller calls kelp_mac_tick(mac, now, &act) regularly (and
 * again while it returns an action: each call starts at most one slot, so a caller late within
 * a slot still starts it).  The time step rule (docs/ARCHITECTURE.md): a slot whose whole time
 * has passed was missed (the clock stepped forward, or nobody ticked), and a next slot more than
 * a cycle and the longest slot ahead means the clock stepped back: either way the tick re-aligns
 * the cycle to the next boundary after `now` (counted in clock_steps) and starts nothing, so
 * missed slots are never replayed as a burst.  A NaN, infinite or absurd `now` is refused
 * (KELP_ERR_ARG) by every call that takes one (kelp_mac_heard ignores it).
 *
 * Cycle alignment (as Goby): cycle length D = sum of slot_seconds; a (re)started cycle begins at
 *   UTC midnight + (floor(tod / D) + 1) * D        (tod = whole seconds since UTC midnight)
 * whenever a slot is added, removed, discovered or expired.
 *
 *  - MAC_FIXED_DECENTRALIZED: slots in configuration order; an action only for slots whose
 *    src == own id.
 *  - MAC_POLLED: an action for every slot whose src != 0 (we initiate third-party cycles).
 *  - MAC_AUTO_DECENTRALIZED: slots = blank (src 0) + own id + every id heard, sorted by src, each
 *    cfg.slot_seconds long; an action only in the own slot.  After each cycle the blank is moved to
 *    position (D_seconds - ((k % 5) == (sum_of_srcs % 5)) - 1) of a circular list that counts its
 *    end as a position -- D in seconds, not slots: Goby 1.1's bug, reproduced for interoperability.
 *    Ids not heard for D * expire_cycles seconds are removed after the next slot.
 */
#ifndef KELP_MAC_H
#define KELP_MAC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <kelp/config.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum kelp_mac_type {
    KELP_MAC_NONE = 1,
    KELP_MAC_FIXED_DECENTRALIZED = 2,
    KELP_MAC_AUTO_DECENTRALIZED = 3,
    KELP_MAC_POLLED = 4
} kelp_mac_type;

typedef enum kelp_slot_type {
    KELP_SLOT_DATA = 1,
    KELP_SLOT_PING = 2,
    KELP_SLOT_REMUS_LBL = 3
} kelp_slot_type;

/** RangingType of the Goby protobuf messages. */
typedef enum kelp_ranging_type {
    KELP_RANGING_TWO_WAY_PING = 1,
    KELP_RANGING_ONE_WAY_SYNCHRONOUS = 2,
    KELP_RANGING_REMUS_LBL = 3
} kelp_ranging_type;

typedef struct kelp_mac_slot {
    int src;                 /**< initiating modem id (0 = blank in AUTO) */
    int dest;                /**< default -1: ask the queue */
    unsigned rate;           /**< 0..5 */
    kelp_slot_type type;     /**< default SLOT_DATA */
    unsigned slot_seconds;   /**< duration */
    kelp_time last_heard;     /**< AUTO: last time this id was heard */
    bool never_expires;      /**< AUTO: own id and the blank */
} kelp_mac_slot;

typedef struct kelp_mac_cfg {
    kelp_mac_type type;      /**< default MAC_NONE */
    int modem_id;
    unsigned rate;           /**< AUTO only, default 0 */
    unsigned slot_seconds;   /**< AUTO only, default 15 */
    unsigned expire_cycles;  /**< AUTO only, default 30 */
    const kelp_mac_slot *slots; /**< FIXED / POLLED: the cycle, copied */
    size_t nslots;
} kelp_mac_cfg;

typedef enum kelp_mac_action_kind {
    KELP_MAC_ACT_NONE = 0,
    KELP_MAC_ACT_TRANSMIT,   /**< signal_initiate_transmission(src, dest, rate) */
    KELP_MAC_ACT_RANGING     /**< signal_initiate_ranging(src, dest, ranging_type) */
} kelp_mac_action_kind;

typedef struct kelp_mac_action {
    kelp_mac_action_kind kind;
    int src, dest;
    unsigned rate;
    kelp_ranging_type ranging;
    kelp_slot_type slot_type;
    kelp_time slot_start;     /**< scheduled start of the slot that fired */
    unsigned slot_index;     /**< its position in the cycle */
} kelp_mac_action;

typedef enum kelp_mac_update_type {
    KELP_MAC_UPDATE_ADD = 1,
    KELP_MAC_UPDATE_REMOVE = 2,
    KELP_MAC_UPDATE_REPLACE = 3  /**< default of MACUpdate */
} kelp_mac_update_type;

typedef struct kelp_mac {
    kelp_mac_type type;
    int modem_id;
    unsigned rate, slot_seconds, expire_cycles;
    kelp_mac_slot slot[KELP_MAX_MAC_SLOTS]; /**< the cycle in order (slot_order_) */
    size_t n;
    size_t current;          /**< slot that starts next */
    bool running;            /**< the slot timer is armed */
    kelp_time next_slot;     /**< start of the next slot (whole seconds) */
    unsigned long cycles_since_day_start; /**< k */
    uint32_t slots_fired;
    uint32_t clock_steps;    /**< re-alignments after a clock step (or a missed slot) */
    kelp_diag diag;          /**< first error (too many slots / ids, bad configuration) */
} kelp_mac;

void kelp_mac_cfg_default(kelp_mac_cfg *cfg);
void kelp_mac_slot_default(kelp_mac_slot *s, int src);

/** Start the MAC (MACManager::startup) at `now`.  KELP_ERR_ARG for a bad configuration
 *  (AUTO with slot_seconds 0, negative modem id), KELP_ERR_NOSPACE for too many slots. */
KELP_MUST_CHECK int kelp_mac_init(kelp_mac *mac, const kelp_mac_cfg *cfg, kelp_time now);

/** Start the next slot if its time has come.  act->kind is NONE when nothing is due or the slot
 *  is not ours to initiate.  @return 0, or KELP_ERR_EMPTY when no slot was due (act->kind NONE). */
KELP_MUST_CHECK int kelp_mac_tick(kelp_mac *mac, kelp_time now, kelp_mac_action *act);

/** Anything received from modem `src` (handle_modem_all_incoming; AUTO only: discovery). */
void kelp_mac_heard(kelp_mac *mac, int src, kelp_time now);

/** Run-time cycle change (ACOMMS_MAC_CYCLE_UPDATE, FIXED/POLLED).  KELP_ERR_NOTFOUND when
 *  dest != own id (ignored), KELP_ERR_STATE for NONE/AUTO. */
KELP_MUST_CHECK int kelp_mac_update(kelp_mac *mac, int dest, kelp_mac_update_type type,
                                    const kelp_mac_slot *slots, size_t n, kelp_time now);

KELP_MUST_CHECK int kelp_mac_add_slot(kelp_mac *mac, const kelp_mac_slot *s, kelp_time now);
/** Remove the first slot equal on (src, dest, rate, type, slot_seconds).  KELP_ERR_NOTFOUND. */
KELP_MUST_CHECK int kelp_mac_remove_slot(kelp_mac *mac, const kelp_mac_slot *s, kelp_time now);
void kelp_mac_clear(kelp_mac *mac);

/** Cycle length in seconds (sum of slot_seconds). */
unsigned kelp_mac_cycle_length(const kelp_mac *mac);
/** Start of the next slot, or -1 when the MAC is idle. */
kelp_time kelp_mac_next_slot_time(const kelp_mac *mac);
/** First cycle start at or after `now` for a cycle of `cycle_seconds` (Goby's next_cycle_time). */
kelp_time kelp_mac_aligned_start(kelp_time now, unsigned cycle_seconds, unsigned long *cycles_since_day_start);

#ifdef __cplusplus
}
#endif

#endif
