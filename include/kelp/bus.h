/* kelp bus: MOOS publish/subscribe semantics over a pluggable transport.
 *
 * A variable write (a MOOS "notification") is a kelp_var: name, kind (double, string or
 * binary), value, source app, source community and time. Clients register by exact name or
 * by wildcard pattern ('*' any run, '?' one character). There is no broker: each client
 * retains the latest value of every variable it wrote or received, and answers a late
 * registrant's sync request with the values it retains, so a registrant gets the current
 * value of a variable on registration as the MOOSDB gives it.
 *
 * The core here is transport-agnostic and allocation-free: the caller passes storage, a
 * transport ops struct (the LCM transport lives at the edge, src/bus/edge/; the in-process
 * loopback transport is in the core) and feeds received datagrams to kelp_bus_receive().
 * Nothing here reads a clock: times are arguments.
 *
 * Not thread-safe; one thread owns a kelp_bus. Handlers may publish (re-entrancy through
 * the loopback transport is bounded by KELP_BUS_MAX_DEPTH).
 */
#ifndef KELP_BUS_H
#define KELP_BUS_H

#include <stddef.h>
#include <stdint.h>
#include <stdbool.h>
#include <kelp/config.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum kelp_var_kind {
    KELP_VAR_DOUBLE = 0,
    KELP_VAR_STRING = 1,
    KELP_VAR_BINARY = 2
} kelp_var_kind;

#define KELP_VAR_FLAG_SYNC 0x01u    /**< replay of a retained value for a late registrant */
#define KELP_VAR_FLAG_BRIDGED 0x02u /**< arrived from another community through a bridge */

/** LCM fingerprints of kelp.var_t and kelp.sync_req_t (lcmtypes/), as lcm-gen computes them;
 *  a unit test checks them against the generated code, so a change to a .lcm file is caught. */
#define KELP_VAR_FINGERPRINT UINT64_C(0x0ba5b50d8930056a)
#define KELP_SYNC_REQ_FINGERPRINT UINT64_C(0xbd478c3a05578b77)

/** Channel on which sync requests travel. */
#define KELP_BUS_SYNC_CHANNEL "KELP_SYNC_REQ"
/** Reply channels start with this prefix (clients pick a unique rest, see kelp_bus_init). */
#define KELP_BUS_SYNC_REPLY_PREFIX "KELP_SYNC_"
/** Bytes of the app name a reply channel carries. */
#define KELP_BUS_REPLY_APP_LEN 24

/** One variable write. Strings are NUL-terminated in sval; slen excludes the NUL. */
typedef struct kelp_var {
    double time;                     /**< MOOS time (s since 1970, times MOOSTimeWarp) */
    char name[KELP_MAX_NAME];
    char source[KELP_MAX_NAME];
    char source_aux[KELP_MAX_NAME];  /**< MOOS source-aux ("" when the writer set none) */
    char community[KELP_MAX_NAME];
    kelp_var_kind kind;
    uint8_t flags;
    double dval;
    size_t slen;
    char sval[KELP_MAX_SVAL + 1];    /**< string, or binary bytes for KELP_VAR_BINARY */
} kelp_var;

/* ------------------------------------------------------------------ wire format */

/** Bytes needed to encode v as an LCM kelp.var_t datagram (with fingerprint). */
size_t kelp_var_encoded_size(const kelp_var *v);

/** Encode v in LCM's kelp.var_t layout. @param[out] len bytes written.
 *  @return 0, KELP_ERR_NOSPACE if cap is too small, KELP_ERR_ARG on a bad var. */
KELP_MUST_CHECK int kelp_var_encode(const kelp_var *v, uint8_t *buf, size_t cap, size_t *len);

/** Decode and validate one datagram. Every length is checked against the datagram before
 *  use; strings must be NUL-terminated where the layout says; names and values that do not
 *  fit kelp_var are rejected, never truncated. Safe on arbitrary bytes.
 *  @return 0, KELP_ERR_DEFMISMATCH (fingerprint), KELP_ERR_TRUNCATED, KELP_ERR_RANGE
 *  (a length beyond kelp's limits), KELP_ERR_PARSE (missing NUL, bad kind). */
KELP_MUST_CHECK int kelp_var_decode(const uint8_t *buf, size_t len, kelp_var *out);

/** A decoded sync request. */
typedef struct kelp_sync_req {
    double time;
    char requester[KELP_MAX_NAME];
    char community[KELP_MAX_NAME];
    char reply_channel[KELP_MAX_NAME];
    uint16_t npatterns;
    char patterns[KELP_MAX_SYNC_PATTERNS][KELP_MAX_NAME];
} kelp_sync_req;

KELP_MUST_CHECK int kelp_bus_sync_req_encode(const kelp_sync_req *r, uint8_t *buf, size_t cap, size_t *len);
KELP_MUST_CHECK int kelp_bus_sync_req_decode(const uint8_t *buf, size_t len, kelp_sync_req *out);

/** Glob match: '*' matches any run (also empty), '?' one character; anything else literal. */
bool kelp_bus_match(const char *pattern, const char *name);

/** Copy s into a name field; KELP_ERR_RANGE when it does not fit (never truncates). */
KELP_MUST_CHECK int kelp_bus_name_set(char dst[KELP_MAX_NAME], const char *s);

/* ------------------------------------------------------------------ the client */

/** Transport: moves encoded datagrams. All callbacks return 0 or a negative kelp_err. */
typedef struct kelp_bus_transport {
    /** Send one datagram on a channel. */
    int (*publish)(void *ctx, const char *channel, const uint8_t *data, size_t len);
    /** Start receiving channels matching a glob pattern (exact names contain no wildcard). */
    int (*subscribe)(void *ctx, const char *pattern);
    void *ctx;
} kelp_bus_transport;

typedef void (*kelp_bus_handler)(const kelp_var *v, void *user);

typedef struct kelp_bus_sub {
    char pattern[KELP_MAX_NAME];
    bool wildcard;
    double min_interval;             /**< MOOS Register interval: 0 = every write */
    double last_delivered;           /**< per-subscription rate limiting (min_interval) */
} kelp_bus_sub;

typedef struct kelp_bus_stats {
    uint64_t published;
    uint64_t received;               /**< datagrams handed to kelp_bus_receive */
    uint64_t delivered;              /**< handler calls */
    uint64_t bad;                    /**< datagrams rejected by validation */
    uint64_t foreign;                /**< other LCM types reached only through a wildcard */
    uint64_t sync_sent;              /**< retained values sent to late registrants */
    uint64_t sync_delivered;         /**< retained values delivered to us on registration */
    uint64_t sync_stale;             /**< sync replies dropped as not newer than what we had */
    uint64_t rate_limited;           /**< writes withheld by a Register interval */
    uint64_t cache_full;             /**< variables we could not retain (cache full) */
    uint64_t foreign_community;      /**< writes and sync requests of another community, dropped */
    uint64_t time_rejected;          /**< writes stamped non-finite or too far in the future */
    uint64_t sync_limited;           /**< retained values not sent: requester over its budget */
    uint64_t sync_bad_reply;         /**< sync requests naming a reply channel not the requester's */
    uint64_t type_refused;           /**< writes dropped as the MOOSDB does: a double to a variable
                                          holding strings or the reverse (sent or received) */
    int last_bad_err;                /**< status of the last rejected datagram */
} kelp_bus_stats;

/** Caller-provided storage for one client. */
typedef struct kelp_bus_storage {
    kelp_bus_sub *subs;              /**< capacity nsubs */
    size_t nsubs;
    kelp_var *cache;                 /**< retained latest values; capacity ncache */
    size_t ncache;
    uint8_t *scratch;                /**< encode buffer, at least kelp_bus_scratch_size() */
    size_t scratch_cap;
    kelp_var *rx;                    /**< one decode slot */
} kelp_bus_storage;

/** Scratch bytes needed to encode the largest var or sync request. */
size_t kelp_bus_scratch_size(void);

/** Limits on what a client trusts and sends (kelp_bus_set_limits). */
typedef struct kelp_bus_limits {
    double time_margin;   /**< reject writes stamped more than this after `now` (s); 0 = no check
                               (non-finite times are always rejected) */
    double sync_burst;    /**< retained values one requester may draw at once */
    double sync_rate;     /**< ... refilled at this many per second of `now` */
    double sync_burst_all;/**< the same for all requesters together (spoofed names) */
    double sync_rate_all;
} kelp_bus_limits;

#define KELP_BUS_TIME_MARGIN 30.0    /**< default future margin the LCM transport sets (s) */
#define KELP_BUS_SYNC_BURST 1024.0   /**< default per-requester budget: two full caches */
#define KELP_BUS_SYNC_RATE 128.0     /**< values per second */
#define KELP_BUS_SYNC_BURST_ALL 4096.0
#define KELP_BUS_SYNC_RATE_ALL 512.0

typedef struct kelp_bus_sync_peer {
    char reply[KELP_MAX_NAME];
    double tokens, last;
} kelp_bus_sync_peer;

typedef struct kelp_bus {
    /* private */
    char app[KELP_MAX_NAME];
    char community[KELP_MAX_NAME];
    char reply_channel[KELP_MAX_NAME];
    kelp_bus_transport tr;
    kelp_bus_handler handler;
    void *user;
    kelp_bus_storage st;
    size_t nsubs_used;
    size_t ncache_used;
#if KELP_BUS_CACHE_HASH > 0
    uint16_t cache_hash[KELP_BUS_CACHE_HASH]; /* 0 empty, else cache index + 1 (names never leave) */
#endif
    int depth;
    kelp_bus_stats stats;
    kelp_bus_limits lim;
    bool bridge;
    kelp_bus_sync_peer peers[KELP_BUS_SYNC_PEERS];
    double all_tokens, all_last;
    kelp_time newest;      /* the newest `now` of kelp_bus_receive (0 none): the time step rule */
    kelp_sync_req sync_rx; /* scratch: the sync request being answered */
} kelp_bus;

/** @param app this client's MOOS name (source of its writes); @param reply_channel a channel
 *  name unique to this client, starting with KELP_BUS_SYNC_REPLY_PREFIX (sync replies arrive
 *  there), e.g. "KELP_SYNC_<app>_<nonce>".
 *  The handler receives every delivered var (live and sync). */
KELP_MUST_CHECK int kelp_bus_init(kelp_bus *b, const char *app, const char *community,
                                  const char *reply_channel, const kelp_bus_transport *tr,
                                  const kelp_bus_storage *st, kelp_bus_handler handler, void *user);

/** Defaults: no future check (time_margin 0), sync budgets KELP_BUS_SYNC_*. */
void kelp_bus_limits_default(kelp_bus_limits *l);
/** Replace the limits (kelp_bus_init sets the defaults). @return 0 or KELP_ERR_ARG
 *  (negative or non-finite values). */
KELP_MUST_CHECK int kelp_bus_set_limits(kelp_bus *b, const kelp_bus_limits *l);
/** A bridge receives every community's writes; any other client drops writes and sync
 *  requests of another community (counted in foreign_community) unless they carry
 *  KELP_VAR_FLAG_BRIDGED (a bridge of this community republished them). */
void kelp_bus_set_bridge(kelp_bus *b, bool bridge);

/** The reply channel of a client: "KELP_SYNC_<app, first 24 bytes>_<nonce, 8 hex>". Sync
 *  replies only go to a channel of this form built from the requester's own name.
 *  @return 0 or KELP_ERR_ARG. */
KELP_MUST_CHECK int kelp_bus_reply_channel(const char *app, uint32_t nonce, char out[KELP_MAX_NAME]);

/** Publish (MOOS Notify). The var is stamped with this client's app and community and time
 *  `now`, retained in the cache and sent. */
KELP_MUST_CHECK int kelp_bus_notify_double(kelp_bus *b, const char *name, double value, kelp_time now);
KELP_MUST_CHECK int kelp_bus_notify_string(kelp_bus *b, const char *name, const char *value, kelp_time now);
KELP_MUST_CHECK int kelp_bus_notify_binary(kelp_bus *b, const char *name, const void *data, size_t len,
                                           kelp_time now);
/** Publish a double or a string with a MOOS source-aux (e.g. the node a message came from);
 *  aux may be NULL or "". */
KELP_MUST_CHECK int kelp_bus_notify_aux(kelp_bus *b, const char *name, bool is_string, const char *sval,
                                        double dval, const char *aux, kelp_time now);
/* The MOOSDB's type rule: a write of another type than the one this client retains for the
 * name (the first write it saw) is refused -- not sent by notify, not delivered by receive --
 * and counted in stats.type_refused; notify still returns 0, as MOOS's Notify does. */
/** Publish a fully formed var as is (source/community/time kept): bridges and replays. */
KELP_MUST_CHECK int kelp_bus_forward(kelp_bus *b, const kelp_var *v);

/** Register (MOOS Register) by exact name or wildcard pattern; sends a sync request so the
 *  current value(s) arrive. Registering the same pattern twice updates its interval. */
KELP_MUST_CHECK int kelp_bus_register(kelp_bus *b, const char *pattern, double min_interval, kelp_time now);

/** Feed one received datagram (from the transport) with its channel.
 *  @return 0 when handled (delivered or not of interest), or the validation error (counted
 *  in stats.bad; the client goes on). */
KELP_MUST_CHECK int kelp_bus_receive(kelp_bus *b, const char *channel, const uint8_t *data, size_t len, kelp_time now);

/** Latest retained value of a variable, or NULL. */
const kelp_var *kelp_bus_cached(const kelp_bus *b, const char *name);

/** Retain every variable seen on the bus (for a launcher-side retainer). */
KELP_MUST_CHECK int kelp_bus_retain_all(kelp_bus *b, kelp_time now);

const kelp_bus_stats *kelp_bus_get_stats(const kelp_bus *b);

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
