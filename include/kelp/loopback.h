/* kelp loopback: the in-process transport of kelp/bus.h (core, allocation-free): every
 * client attached to one kelp_loopback receives what any of them publishes. Unit tests,
 * benchmarks and firmware use it where a program uses the LCM transport. */
#ifndef KELP_LOOPBACK_H
#define KELP_LOOPBACK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/bus.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ loopback transport */

/** An in-process "network": every client attached receives every datagram published by any
 *  client attached (including itself, as LCM multicast loops back). Publishing queues the
 *  datagram in a FIFO; delivery runs when the outermost publish returns (or on
 *  kelp_loopback_pump), so handlers that publish never recurse. Allocation-free. */
typedef struct kelp_loopback {
    /* private */
    kelp_bus *clients[KELP_MAX_LOOPBACK_CLIENTS];
    size_t nclients;
    kelp_time now;
    uint8_t fifo[KELP_LOOPBACK_FIFO];   /* records: u16 chan len, chan, u32 len, data */
    size_t head, tail;
    bool pumping;
    uint64_t dropped;                     /* datagrams dropped: FIFO full */
} kelp_loopback;

typedef struct kelp_loopback_port {
    kelp_loopback *net;
} kelp_loopback_port;

void kelp_loopback_init(kelp_loopback *net);
/** Set the time handed to receivers' kelp_bus_receive (the "now" of delivery). */
void kelp_loopback_set_time(kelp_loopback *net, kelp_time now);
/** Fill a transport for a client; attach the client after kelp_bus_init. */
void kelp_loopback_transport(kelp_loopback *net, kelp_loopback_port *port, kelp_bus_transport *tr);
KELP_MUST_CHECK int kelp_loopback_attach(kelp_loopback *net, kelp_bus *b);
/** Deliver everything queued. */
void kelp_loopback_pump(kelp_loopback *net);

#ifdef __cplusplus
}
#endif

#endif
