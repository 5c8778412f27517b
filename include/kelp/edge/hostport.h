/* kelp host port (edge): the device side of a serial line, for programs that play a device
 * (the simulated Micro-Modem): a pseudo-terminal whose slave a host opens (through a stable
 * symbolic link), or a TCP server that serves one host at a time (a new connection replaces
 * the old one). Bytes from the host arrive through a callback; writes nobody reads are
 * dropped and counted, as on a wire. */
#ifndef KELP_EDGE_HOSTPORT_H
#define KELP_EDGE_HOSTPORT_H

#include <stddef.h>
#include <stdint.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kelp_hostport {
    int master, slave;          /* pty */
    int lfd, cfd, ep;           /* tcp: listening socket, client, epoll set */
    unsigned port;
    char pty_name[256], link[256];
    unsigned long bytes_in, bytes_out, dropped_out, connects;
} kelp_hostport;

/** kelp_hostport_poll result bits */
#define KELP_HOSTPORT_CONNECTED 1u
#define KELP_HOSTPORT_DISCONNECTED 2u

/** A pseudo-terminal in raw mode (19200 baud set for hosts that check); link, when not NULL
 *  or empty, becomes a symbolic link to the slave (an existing non-link file is not
 *  replaced). 0, or <0 with the reason in d. */
KELP_MUST_CHECK int kelp_hostport_open_pty(kelp_hostport *h, const char *link, kelp_diag *d);
/** A TCP server on port (0: any free port, see h->port). 0, or <0 with the reason in d. */
KELP_MUST_CHECK int kelp_hostport_open_tcp(kelp_hostport *h, unsigned port, kelp_diag *d);
/** The descriptor to wait on for input. */
int kelp_hostport_fd(const kelp_hostport *h);
/** Read everything available, passing the bytes to on_bytes; accept or drop TCP clients.
 *  Returns KELP_HOSTPORT_* bits for what happened to the connection. Never blocks. */
unsigned kelp_hostport_poll(kelp_hostport *h, void (*on_bytes)(void *ctx, const uint8_t *b, size_t n), void *ctx);
/** Write to the host; what cannot be written (no host, host not reading) is dropped.
 *  @return bytes dropped (0 when all went out). */
size_t kelp_hostport_write(kelp_hostport *h, const void *b, size_t n);
/** Close everything (and remove the symbolic link). */
void kelp_hostport_close(kelp_hostport *h);

#ifdef __cplusplus
}
#endif

#endif
