/* kelp poller: pAcommsPoller's core, the topside poll list (no allocation, no I/O). */
#ifndef KELP_POLLER_H
#define KELP_POLLER_H

#include <stdbool.h>
#include <stddef.h>
#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/mac.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Parse one poll slot: "src=2,dest=1,rate=0,type=data,slot_seconds=10" (keys case-insensitive;
 *  type data|ping|remus_lbl or SLOT_DATA|SLOT_PING|SLOT_REMUS_LBL; dest default -1, rate 0,
 *  type data, slot_seconds default_seconds).  src 1..31, dest -1..31, rate 0..5, slot_seconds > 0.
 *  @return 0 or KELP_ERR_PARSE / KELP_ERR_RANGE (d's message names the offending key). */
KELP_MUST_CHECK int kelp_poller_parse_slot(const char *spec, unsigned default_seconds, kelp_mac_slot *out,
                                           kelp_diag *d);

/** Goby's single-line TextFormat of a MACUpdate (ACOMMS_MAC_CYCLE_UPDATE), e.g.
 *  "dest: 1 update_type: REPLACE slot { src: 2 dest: 1 rate: 0 type: SLOT_DATA slot_seconds: 10 }".
 *  @return 0 or KELP_ERR_NOSPACE (never truncated silently). */
KELP_MUST_CHECK int kelp_poller_format_update(int dest, kelp_mac_update_type type, const kelp_mac_slot *slots,
                                              size_t n, char *buf, size_t cap, size_t *len);

/** One slot in the "src=2,dest=1,rate=0,type=data,slot_seconds=10" form (buf NUL-terminated). */
KELP_MUST_CHECK int kelp_poller_format_slot(const kelp_mac_slot *s, char *buf, size_t cap, size_t *len);

/** The poll list pAcommsPoller owns: the cycle in order, and whether it is paused. */
typedef struct kelp_poller_list {
    kelp_mac_slot slot[KELP_MAX_MSIM_POLL_SLOTS];
    size_t n;
    bool paused;
    unsigned default_seconds;          /**< slot_seconds of a slot that does not say */
} kelp_poller_list;

/** Append one slot spec. 0, or <0 with d (the bad key, or "list full"; d may be NULL). */
KELP_MUST_CHECK int kelp_poller_add(kelp_poller_list *l, const char *spec, kelp_diag *d);

/** Apply one POLLER_COMMAND: "add SLOT", "remove SLOT", "replace SLOT;SLOT;..." (all or
 *  nothing), "clear", "pause", "resume", "publish". @return 1 (the cycle is to be published
 *  again), or <0 with d (may be NULL); the list is unchanged on an error. */
KELP_MUST_CHECK int kelp_poller_command(kelp_poller_list *l, const char *cmd, kelp_diag *d);

/** Sum of the slots' lengths (s). */
unsigned kelp_poller_cycle_seconds(const kelp_poller_list *l);

#ifdef __cplusplus
}
#endif

#endif
