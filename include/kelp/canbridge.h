/* kelp canbridge: kelp-canbridge's core (core: no allocation, no I/O, time passed in):
 * routes between a community and a CAN bus each way with renaming, the dictionary, the
 * sender and the receiver (kelp/can.h), and the kernel filters the routes need. */
#ifndef KELP_CANBRIDGE_H
#define KELP_CANBRIDGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/bus.h>
#include <kelp/err.h>
#include <kelp/can.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ kelp-canbridge's core */

#define KELP_CANBRIDGE_MAX_ROUTES 64u

/** What kelp-canbridge (and a test or firmware gateway) does between a community and a
 *  CAN bus: the routes each way with renaming, the dictionary, sender and receiver. */
typedef struct kelp_canbridge {
    kelp_can_dict dict;
    kelp_can_tx tx;
    kelp_can_rx rx;
    char to_src[KELP_CANBRIDGE_MAX_ROUTES][KELP_MAX_NAME];   /**< community names (globs) */
    char to_alias[KELP_CANBRIDGE_MAX_ROUTES][KELP_MAX_NAME]; /**< names on CAN ("" = same) */
    size_t nto;
    char from_src[KELP_CANBRIDGE_MAX_ROUTES][KELP_MAX_NAME]; /**< names on CAN (globs) */
    char from_alias[KELP_CANBRIDGE_MAX_ROUTES][KELP_MAX_NAME];
    size_t nfrom;
    bool send_time;          /**< put the variable's time in each message (default: receiver stamps) */
    bool send_source;        /**< put the variable's source in each message (default: "can<node>") */
    unsigned long to_msgs, to_frames, to_err, from_msgs, not_routed;
} kelp_canbridge;

KELP_MUST_CHECK int kelp_canbridge_init(kelp_canbridge *b, unsigned node, bool fd, double timeout);
/** Add a renaming list (kelp_bridge_parse_rename syntax): to_can = community -> CAN. */
KELP_MUST_CHECK int kelp_canbridge_add(kelp_canbridge *b, bool to_can, const char *line, kelp_diag *d);
/** Kernel filters for what FROM_CAN wants (ids of dictionary names; the named id when a
 *  route is a glob or not in the dictionary). */
size_t kelp_canbridge_filters(const kelp_canbridge *b, kelp_can_filter *out, size_t cap);
/** A bus write: when a TO_CAN route takes it (and it did not arrive through a bridge), send
 *  it under its CAN name. @return frames emitted, 0 not routed, < 0 error. */
KELP_MUST_CHECK int kelp_canbridge_from_bus(kelp_canbridge *b, const kelp_var *v, kelp_can_emit_fn emit, void *user);
/** A frame from CAN: 1 when *out holds a variable to publish (renamed, flagged BRIDGED),
 *  0 nothing yet / not routed, < 0 refused (counted in b->rx.st). */
KELP_MUST_CHECK int kelp_canbridge_from_can(kelp_canbridge *b, const kelp_can_frame *f, kelp_time now, kelp_var *out);

#ifdef __cplusplus
}
#endif

#endif
