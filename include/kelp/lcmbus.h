/* kelp LCM transport (edge): one community = one LCM URL.
 *
 * Wraps a kelp_bus client around kelp's own udpm socket (kelp/edge/udpm.h: LCM's wire
 * format, no liblcm receive path). Datagrams and messages are validated by kelp's own
 * code, so a malformed datagram is counted, not fatal. The receive side is set up for
 * bursts: recv_buf_size=4 MiB is added to udpm URLs that do not set it, and a receive
 * thread drains the socket into a bounded queue (queue_size in the URL).
 */
#ifndef KELP_LCMBUS_H
#define KELP_LCMBUS_H

#include <kelp/config.h>
#include <kelp/bus.h>
#include <kelp/edge/udpm.h>
#include <kelp/mission.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_LCM_DEFAULT_URL "udpm://239.255.76.67:7667?ttl=0"
#define KELP_LCM_RECV_BUF 4194304

typedef struct kelp_lcmbus kelp_lcmbus;

/** Resolve the URL for a community: $KELP_LCM_URL, else mission_url (may be NULL), else
 *  the default. Writes into buf. */
KELP_MUST_CHECK int kelp_lcmbus_url(const char *mission_url, char *buf, size_t cap);

/** The URL of the community a mission describes: $KELP_LCM_URL, else the global LCM_URL,
 *  else udpm://239.255.76.67:<ServerPort>?ttl=0 when ServerPort is set (one port per
 *  community, see kelp_udpm_community_url), else the default; then as kelp_lcmbus_url.
 *  @param[out] line the offending mission line on error (0 if none).
 *  @return 0, KELP_ERR_RANGE (bad LCM_URL or ServerPort), KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_lcmbus_mission_url(const kelp_mission *m, char *buf, size_t cap, int *line);

/** Open a client. @param url LCM URL (see kelp_lcmbus_url); @return NULL on failure with a
 *  reason in d. */
kelp_lcmbus *kelp_lcmbus_open(const char *url, const char *app, const char *community, kelp_bus_handler handler,
                              void *user, kelp_diag *d);
void kelp_lcmbus_close(kelp_lcmbus *lb);
kelp_bus *kelp_lcmbus_bus(kelp_lcmbus *lb);
int kelp_lcmbus_fd(kelp_lcmbus *lb);
/** Do not receive this client's own publications (see kelp_udpm_sock_ignore_own): for a
 *  program that never registers for what it posts. */
void kelp_lcmbus_ignore_own(kelp_lcmbus *lb, bool on);
/** Handle every datagram already received (non-blocking), then wait up to timeout_ms for
 *  more. `now` is the MOOS time handed to the bus. @return datagrams handled, or <0. */
KELP_MUST_CHECK int kelp_lcmbus_handle(kelp_lcmbus *lb, int timeout_ms, kelp_time now);
/** Transport counters (bad datagrams, reassembly timeouts, queue drops...). */
void kelp_lcmbus_get_stats(kelp_lcmbus *lb, kelp_udpm_sock_stats *out);
/** Cork the bus's socket (kelp_udpm_sock_cork): postings wait for one batched send at uncork. */
void kelp_lcmbus_cork(kelp_lcmbus *lb, bool on);
/** Publish raw bytes on a channel (bridges, tools). */
KELP_MUST_CHECK int kelp_lcmbus_publish_raw(kelp_lcmbus *lb, const char *channel, const void *data, size_t len);

#ifdef __cplusplus
}
#endif

#endif
