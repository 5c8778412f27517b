/* kelp edge: plain UDP sockets for point-to-point links between hosts (kelp-bridge).
 * Multicast for the bus itself is kelp/edge/udpm.h. */
#ifndef KELP_EDGE_UDP_H
#define KELP_EDGE_UDP_H
#include <stddef.h>
#include <stdint.h>
#include <netinet/in.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

/** A non-blocking UDP socket, bound to `port` on every interface when port > 0 (send-only
 *  otherwise), with a receive buffer of rcvbuf bytes when > 0. @return fd, or <0 with the reason in d. */
KELP_MUST_CHECK int kelp_udp_open(uint16_t port, int rcvbuf, kelp_diag *d);

/** A non-blocking UDP socket listening to multicast group:port (address reuse on, so several
 *  listeners on one host share the port), receive buffer rcvbuf when > 0.
 *  @return fd, or <0 with the reason in d. */
KELP_MUST_CHECK int kelp_udp_open_group(const char *group, uint16_t port, int rcvbuf, kelp_diag *d);

/** Multicast sending on fd: hop limit ttl (0 keeps it on this host) and loop-back on, so
 *  listeners on this host hear it. @return 0 or KELP_ERR_IO. */
KELP_MUST_CHECK int kelp_udp_multicast_tx(int fd, int ttl);

/** Resolve an IPv4 host name or dotted address. @return 0 or KELP_ERR_NOTFOUND. */
KELP_MUST_CHECK int kelp_udp_resolve(const char *host, uint16_t port, struct sockaddr_in *out);

/** Receive one datagram without blocking. *full is the datagram's real length, larger than
 *  cap when it was cut (then it must be treated as oversize).
 *  @return 1 with a datagram, 0 when none is waiting, <0 on error. */
KELP_MUST_CHECK int kelp_udp_recv(int fd, uint8_t *buf, size_t cap, size_t *full);

/** Send one datagram. @return 0 or KELP_ERR_IO (errno set). */
KELP_MUST_CHECK int kelp_udp_send(int fd, const struct sockaddr_in *to, const uint8_t *buf, size_t len);

#ifdef __cplusplus
}
#endif

#endif
