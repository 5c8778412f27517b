/* Example vehicle-firmware node on a kelp CAN bus (firmware/can_node.c): it publishes a
 * sensor value (DEPTH, dictionary id 7) at 10 Hz and subscribes to a command (THRUST_CMD,
 * id 3), answering each command with a status string (FW_STATUS, sent by name, several
 * frames). Only kelp/can.h is used: no heap, no I/O; the board code moves frames. */
#ifndef KELP_FW_CAN_NODE_H
#define KELP_FW_CAN_NODE_H
#include <kelp/can.h>

#define FW_VAR_THRUST_CMD 3u
#define FW_VAR_DEPTH 7u
#define FW_PUBLISH_PERIOD 0.1

typedef struct fw_node {
    kelp_can_dict dict;
    kelp_can_tx tx;
    kelp_can_rx rx;
    double thrust;            /**< last command applied */
    unsigned long commands;   /**< commands received */
    bool status_due;          /**< a FW_STATUS answer is waiting */
    double next_publish;
} fw_node;

KELP_MUST_CHECK int fw_node_init(fw_node *n, unsigned node, bool fd);
/** A frame from the bus (already filtered or not: foreign frames are ignored). */
void fw_node_frame(fw_node *n, const kelp_can_frame *f, double now);
/** Periodic work: publish DEPTH when due and FW_STATUS after a command.
 *  @return frames emitted or < 0. */
int fw_node_tick(fw_node *n, double now, double depth, kelp_can_emit_fn emit, void *user);

#endif
