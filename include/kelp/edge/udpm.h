/* kelp UDP multicast sockets (edge): LCM's udpm transport without liblcm.
 *
 * One kelp_udpm_sock joins a multicast group (udpm://group:port?ttl=N&recv_buf_size=B
 * &queue_size=Q, see kelp_udpm_url_parse) and publishes to it in LCM's short and fragment
 * forms with a per-socket sequence number, so liblcm programs (lcm-logger, lcm-spy,
 * lcm-logplayer) and kelp interoperate both ways.
 *
 * Receiving: a thread drains the socket as fast as datagrams arrive, validates and
 * reassembles them with the core (kelp_udpm_feed) and queues complete messages in a
 * bounded queue (queue_size bytes), so a burst waits in user space instead of overflowing
 * the kernel buffer. When the queue is full a message is dropped and counted. The owner
 * polls kelp_udpm_sock_fd() (readable while messages wait) and takes them with
 * kelp_udpm_sock_next().
 *
 * Thread safety: publish may be called from any thread; next/stats from one owner thread.
 */
#ifndef KELP_EDGE_UDPM_H
#define KELP_EDGE_UDPM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/udpm.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_UDPM_DEFAULT_RECV_BUF 4194304L   /**< SO_RCVBUF when the URL gives none (bytes) */
#define KELP_UDPM_DEFAULT_QUEUE 16777216L     /**< receive queue when the URL gives none (bytes) */
#define KELP_UDPM_REASM_SLOTS 8               /**< fragmented messages assembled at once */
#define KELP_UDPM_REASM_CAP 1048576           /**< largest reassembled message (bytes) */
#define KELP_UDPM_REASM_TIMEOUT 2.0           /**< seconds an incomplete message may wait */

typedef struct kelp_udpm_sock kelp_udpm_sock;

typedef struct kelp_udpm_sock_stats {
    kelp_udpm_stats rx;       /**< the reassembler's counters (datagrams, bad, timeouts...) */
    uint64_t queued;          /**< complete messages queued */
    uint64_t queue_dropped;   /**< complete messages dropped: queue full */
    uint64_t sent;            /**< messages published */
    uint64_t send_errors;     /**< messages whose sendmsg failed */
    int recv_buf;             /**< SO_RCVBUF the kernel granted (bytes) */
    uint64_t send_batches;    /**< sendmmsg batches of a corked socket */
    int send_buf;             /**< SO_SNDBUF the kernel granted (bytes) */
    uint64_t gso_sends;       /**< segmented sends (UDP GSO) of a corked socket */
    uint64_t gso_segments;    /**< messages that went in them */
    uint64_t gro_runs;        /**< coalesced runs received (UDP GRO), each split into its datagrams */
} kelp_udpm_sock_stats;

/** Open and join. @return NULL on failure, with the reason in d. */
kelp_udpm_sock *kelp_udpm_sock_open(const char *url, kelp_diag *d);
/** Open for publishing only: no receive socket, thread or queue (a publisher would
 *  otherwise receive and queue its own multicast echo). next() always returns 0. */
kelp_udpm_sock *kelp_udpm_sock_open_tx(const char *url, kelp_diag *d);
void kelp_udpm_sock_close(kelp_udpm_sock *s);
/** Do not receive what this socket itself sends (on: a kernel socket filter drops datagrams
 *  from our own address and send port, found from the first one that comes back). For
 *  programs that never read their own posts: they then neither wake nor copy for them. */
void kelp_udpm_sock_ignore_own(kelp_udpm_sock *s, bool on);
/** Readable while complete messages wait. */
int kelp_udpm_sock_fd(const kelp_udpm_sock *s);
/** Take the next message. Its channel and data stay valid until the next call.
 *  @return 1 with *out filled, 0 when none waits. */
KELP_MUST_CHECK int kelp_udpm_sock_next(kelp_udpm_sock *s, kelp_udpm_msg *out);
/** Publish one message (short form or fragments). @return 0, KELP_ERR_RANGE (channel or
 *  size), KELP_ERR_IO. */
KELP_MUST_CHECK int kelp_udpm_sock_publish(kelp_udpm_sock *s, const char *channel, const void *data, size_t len);
void kelp_udpm_sock_get_stats(kelp_udpm_sock *s, kelp_udpm_sock_stats *out);
/** Cork (on) or uncork (off, which sends what waits). While corked, short messages are
 *  copied into a batch that goes to the kernel in one sendmmsg when it fills, at
 *  kelp_udpm_sock_flush, at uncork or at close; fragmented messages flush it and go at once,
 *  so the order of publication is kept. An app corks around its iteration: thousands of
 *  postings then cost tens of system calls, not thousands. */
void kelp_udpm_sock_cork(kelp_udpm_sock *s, bool on);
/** Send what a corked socket holds (it stays corked). */
void kelp_udpm_sock_flush(kelp_udpm_sock *s);

#ifdef __cplusplus
}
#endif

#endif
