/* kelp bridge (the pMOOSBridge role): forwarding variables between communities by UDP.
 *
 * Routes come from static lines in the pMOOSBridge style,
 *   UDPSHARE = [VAR1,VAR2] -> community @ host:port [ALIAS1,ALIAS2]
 * and from run-time requests on PMB_REGISTER (the uField Toolbox manual (MOOS-IvP 12.2)):
 *   src_var=DEPLOY_ALL,dest_community=henry,dest_host=10.0.0.5,dest_port=9200,dest_alias=DEPLOY
 *
 * Datagram (big-endian):
 *   "KBR2" | u8 flags | u64 epoch | u64 seq | kelp.var_t bytes | [32-byte HMAC-SHA256]
 * The HMAC covers everything before it, so epoch and seq are authenticated. epoch names
 * one run of the sending bridge (its start time in microseconds, chosen at the edge);
 * seq counts that run's datagrams from 1. The receiver keeps, per sending community, the
 * newest epoch and a 64-datagram window below the highest seq: a datagram from an older
 * epoch, below the window, or already seen in it is a replay and is refused. A newer
 * epoch (the peer restarted) starts a fresh window.
 * The HMAC is computed by a caller-supplied function (mbedTLS at the edge). With a key
 * configured, a datagram without a valid HMAC is dropped. The core parses and frames; it
 * does no I/O.
 */
#ifndef KELP_BRIDGE_H
#define KELP_BRIDGE_H
#include <stdint.h>
#include <stddef.h>
#include <stdbool.h>
#include <kelp/bus.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_BRIDGE_MAGIC "KBR2"
#define KELP_BRIDGE_HDR_LEN 21u      /**< magic, flags, epoch, seq */
#define KELP_BRIDGE_HMAC_LEN 32u
#define KELP_BRIDGE_F_AUTH 0x01u
#define KELP_BRIDGE_WINDOW 64u       /**< out-of-order datagrams accepted below the highest seq */
#define KELP_BRIDGE_DGRAM_MAX 65507u /**< largest UDP/IPv4 payload */

/** Sender state: one per bridge run. */
typedef struct kelp_bridge_tx {
    uint64_t epoch; /**< this run's identity (start time in microseconds, from the edge) */
    uint64_t seq;   /**< last sequence number sent */
} kelp_bridge_tx;

/** What the receiver remembers of one sending community. */
typedef struct kelp_bridge_peer {
    char community[KELP_MAX_NAME];
    uint64_t epoch, high, window; /**< window bit i: seq high-i already seen */
    uint64_t used;                /**< receive counter at last use (least recently used is evicted) */
} kelp_bridge_peer;

/** Receiver state over caller-owned peer slots. */
typedef struct kelp_bridge_rx {
    kelp_bridge_peer *peers;
    size_t cap, n;
    uint64_t tick;
    unsigned long replayed; /**< refused: seen, below the window, or an older epoch */
    unsigned long evicted;  /**< peers forgotten to make room */
} kelp_bridge_rx;

void kelp_bridge_tx_init(kelp_bridge_tx *tx, uint64_t epoch);
void kelp_bridge_rx_init(kelp_bridge_rx *rx, kelp_bridge_peer *peers, size_t cap);

typedef struct kelp_bridge_route {
    char src[KELP_MAX_NAME];          /**< local variable (or glob) */
    char alias[KELP_MAX_NAME];        /**< name at the destination ("" = same) */
    char community[KELP_MAX_NAME];    /**< destination community (informational) */
    char host[KELP_MAX_NAME];
    uint16_t port;
    bool multicast;                   /**< pShare's multicast_<port> (port holds the channel; host "") */
    bool limited;                     /**< pShare output: duration and max_shares below apply */
    double frequency;                 /**< pShare: shares per second at most (0: every notification) */
    double duration;                  /**< pShare: seconds the share lasts from its creation (<0: for ever) */
    int max_shares;                   /**< pShare: shares at most (<0: no limit) */
} kelp_bridge_route;

/** A share's run-time state (pShare's route bookkeeping). */
typedef struct kelp_bridge_share {
    double created;      /**< MOOS time the route was (re)stated */
    double last_sent;    /**< MOOS time of the last share (0: none yet) */
    long done;           /**< shares made */
} kelp_bridge_share;

/** pShare's rule for whether a route shares a notification at now: not once its duration has
 *  passed (duration 0 on a restated route: the latest value once), not past max_shares, not
 *  sooner than 1/frequency after the last share. A clock step back never stops a route. */
bool kelp_bridge_share_active(const kelp_bridge_route *r, const kelp_bridge_share *s, double now);

/** Parse one UDPSHARE/SHARE value into up to cap routes. @return 0 and *n, or
 *  KELP_ERR_PARSE, the reason in d. */
KELP_MUST_CHECK int kelp_bridge_parse_share(const char *line, kelp_bridge_route *routes, size_t cap, size_t *n,
                                            kelp_diag *d);
/** Parse a PMB_REGISTER request. */
KELP_MUST_CHECK int kelp_bridge_parse_register(const char *s, kelp_bridge_route *r, kelp_diag *d);

/* ---- pShare's model (MOOS-IvP 24.8's pShare: kelp-bridge running as pShare) ----
 * A route is "host:port" (an optional ":udp" after it) or "multicast_N". Outputs:
 *   output = src_name=X, dest_name=Y, route=10.0.0.5:9200 & multicast_8   (long form)
 *   output = X->Y:10.0.0.5:9200 & 10.0.0.6:9300 & Z:multicast_8            (shorthand)
 * and at run time PSHARE_CMD (<APP>_CMD) = "cmd=output,src_name=..,dest_name=..,route=..".
 * Inputs: input = route=localhost:9200 & multicast_9 [, white_list=A & B*]. Keys are read
 * case-insensitively. An output's frequency (or "@F" after a shorthand route), duration and
 * max_shares fill the routes' limits (kelp_bridge_share_active). */
#define KELP_PSHARE_MCAST_ADDR "224.1.1.11" /**< pShare's multicast group (multicast_address) */
#define KELP_PSHARE_MCAST_PORT 24460u       /**< multicast_N is this port + N (multicast_base_port) */

/** One output directive (long form when it names a route, shorthand otherwise) into up to
 *  cap routes (src, alias = dest_name or src, host/port or multicast). @return 0 and *n, or
 *  KELP_ERR_PARSE / KELP_ERR_NOSPACE, the reason in d. */
KELP_MUST_CHECK int kelp_bridge_pshare_output(const char *line, kelp_bridge_route *routes, size_t cap, size_t *n,
                                              kelp_diag *d);
/** One input directive ("route=R & R[, white_list=M & M]") into up to cap listen routes
 *  (host, port or multicast); white_list (when given) is written comma-separated into white
 *  (a kelp_bridge_allowed list). @return 0 and *n, or KELP_ERR_PARSE, the reason in d. */
KELP_MUST_CHECK int kelp_bridge_pshare_input(const char *line, kelp_bridge_route *routes, size_t cap, size_t *n,
                                             char *white, size_t wcap, kelp_diag *d);
/** A PSHARE_CMD's cmd=: 1 output, 2 input, 0 neither (24.8 refuses it). */
int kelp_bridge_pshare_cmd(const char *s);
/** PSHARE_OUTPUT_SUMMARY (input false): "SRC->dest:host:port & dest:host:port, SRC2->..",
 *  sources in name order, a multicast route as "dest:<addr>:<port>:multicast_N"; or
 *  PSHARE_INPUT_SUMMARY (input true): "host:port,<addr>:<port>:multicast_N" in address order.
 *  @return 0 or KELP_ERR_NOSPACE (cut). */
KELP_MUST_CHECK int kelp_bridge_pshare_summary(const kelp_bridge_route *r, size_t n, bool input, char *buf, size_t cap);
/** The index of the route with r's src, alias and destination in tab, or -1. */
long kelp_bridge_table_find(const kelp_bridge_route *tab, size_t n, const kelp_bridge_route *r);
/** A route stated again (24.8): q takes r's limits and s starts over at now. @return true when
 *  r has duration = 0: q then shares the latest value once (max_shares 1, no end). */
bool kelp_bridge_share_restate(kelp_bridge_route *q, kelp_bridge_share *s, const kelp_bridge_route *r, double now);
/** Add r to a route table unless the same src, alias and destination is there.
 *  @return 1 added, 0 there already, KELP_ERR_NOSPACE full. */
KELP_MUST_CHECK int kelp_bridge_table_add(kelp_bridge_route *tab, size_t *n, size_t cap, const kelp_bridge_route *r);

/** HMAC-SHA256(key, data) -> out[32]; returns 0 or <0. */
typedef int (*kelp_hmac_fn)(const uint8_t *key, size_t keylen, const uint8_t *data, size_t len, uint8_t out[32],
                            void *user);

/** Frame a var (renamed to `as` when non-empty; flagged BRIDGED) into buf, with the
 *  next sequence number of tx. KELP_ERR_NOSPACE when it does not fit cap. */
KELP_MUST_CHECK int kelp_bridge_frame(kelp_bridge_tx *tx, const kelp_var *v, const char *as, const uint8_t *key, size_t keylen,
                                      kelp_hmac_fn hmac, void *user, uint8_t *buf, size_t cap, size_t *len);
/** Check and decode a datagram. With keylen > 0 the HMAC must be present and valid
 *  (KELP_ERR_AUTH otherwise). With rx, a replayed or stale datagram is KELP_ERR_REPLAY
 *  (the window is only updated by datagrams that decode and authenticate). A value
 *  longer than this build's KELP_MAX_SVAL is KELP_ERR_RANGE (oversize). */
KELP_MUST_CHECK int kelp_bridge_unframe(kelp_bridge_rx *rx, const uint8_t *buf, size_t len, const uint8_t *key, size_t keylen,
                                        kelp_hmac_fn hmac, void *user, kelp_var *out);
/** Allow-list: comma-separated names or globs ("NODE_*"), the names a bridge will
 *  publish into its community. An empty list allows everything. */
bool kelp_bridge_allowed(const char *allow, const char *name);

/** A renaming list (kelp-canbridge's TO_CAN / FROM_CAN): "VAR", "VAR -> ALIAS",
 *  "[V1,V2]" or "[V1,V2] -> [A1,A2]". Fills src and alias of up to cap routes (the other
 *  fields zero). A glob (* or ?) may not be renamed. KELP_ERR_PARSE, the reason in d. */
KELP_MUST_CHECK int kelp_bridge_parse_rename(const char *line, kelp_bridge_route *routes, size_t cap, size_t *n,
                                             kelp_diag *d);

#ifdef __cplusplus
}
#endif

#endif
