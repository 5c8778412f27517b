/* kelp acomms: the glue of the Goby 1.1 acoustic stack (what pAcommsHandler is made of).
 *
 *  1. DCCL glue (edge, libkelp.a): message files, crypto, algorithms, src_var/trigger_var
 *     sourcing, encode and decode-and-publish, behind an opaque handle with plain types only.
 *  2. Protobuf TextFormat (core): the ACOMMS_* variable strings (ModemDataTransmission,
 *     ModemDataAck, ModemDataExpire, QueueSize, ModemRangingReply, ModemRangingRequest,
 *     MACUpdate) printed and parsed as Goby's serialize_for_moos / parse_for_moos do.
 *  3. The node (core): one vehicle's queue manager + TDMA MAC + modem driver wired together
 *     (Goby's pAcommsHandler signal connections), time as an argument, every event reported
 *     through one callback.
 *  4. Configuration (edge): the pAcommsHandler ProcessConfig block (the keys of Goby 1.1's pAcommsHandler).
 *  4b. The handler (core): pAcommsHandler itself (mail, DCCL encode/decode, queue and driver
 *     publications, link state, status) over the node, publications out through a sink.
 *  5. LCM structures (edge): the kelp.acomms_*_t copies of the handler's records.
 *
 * A translation unit that needs part 1 only may define KELP_ACOMMS_DCCL_ONLY before
 * including this header.
 */
#ifndef KELP_ACOMMS_H
#define KELP_ACOMMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <kelp/config.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ================================================================== 1. DCCL glue (edge) */

/** message_file manipulators (bit set). */
#define KELP_ACOMMS_MANIP_NO_ENCODE 0x01u
#define KELP_ACOMMS_MANIP_NO_DECODE 0x02u
#define KELP_ACOMMS_MANIP_NO_QUEUE 0x04u
#define KELP_ACOMMS_MANIP_LOOPBACK 0x08u
#define KELP_ACOMMS_MANIP_ON_DEMAND 0x10u
#define KELP_ACOMMS_MANIP_TCP_SHARE_IN 0x20u

/** Bit for a manipulator name ("NO_ENCODE", ...); NO_MANIP gives 0; -1 if unknown. */
long kelp_acomms_manip_from_name(const char *name, size_t len);

typedef struct kelp_acomms_dccl kelp_acomms_dccl;

typedef struct kelp_acomms_dccl_cfg {
    unsigned modem_id;
    const char *passphrase;       /**< NULL = "" (Goby encrypts with SHA-256("") then) */
    bool plaintext;               /**< true: no crypto at all (NOT Goby-compatible; tests only) */
    const char *lookup_path;      /**< modem_id lookup file, NULL/"" = none */
    bool have_origin;
    double lat_origin, lon_origin;
    const char *const *files;     /**< XML message files */
    const unsigned *manips;       /**< manipulator bits per file (may be NULL) */
    size_t nfiles;
} kelp_acomms_dccl_cfg;

/** What the handler needs to know about one message. Strings live as long as the handle. */
typedef struct kelp_acomms_dccl_info {
    const char *name;
    unsigned id;
    unsigned size;
    int trigger;                  /**< 0 none, 1 publish, 2 time */
    const char *trigger_var;      /**< may be NULL */
    const char *mandatory;        /**< trigger_var mandatory_content, may be NULL */
    double trigger_time;
    const char *in_var, *out_var; /**< IN_/OUT_<NAME>_HEX_<size>B unless set in the XML */
    unsigned manip;               /**< KELP_ACOMMS_MANIP_* of its file */
    bool ack;                     /**< <queuing> (libqueue defaults when absent) */
    double blackout_time;
    uint32_t max_queue;
    bool newest_first;
    double value_base;
    double ttl;
} kelp_acomms_dccl_info;

/** Load the message files (every file once, manipulators of repeated paths merged), set up
 *  algorithms (lat/lon origin, lookup file) and crypto.  NULL on failure, d says why (the
 *  XML loader's "file:line: reason", line in d->line). d may be NULL. */
kelp_acomms_dccl *kelp_acomms_dccl_open(const kelp_acomms_dccl_cfg *cfg, kelp_diag *d);
void kelp_acomms_dccl_close(kelp_acomms_dccl *d);

size_t kelp_acomms_dccl_count(const kelp_acomms_dccl *d);
KELP_MUST_CHECK int kelp_acomms_dccl_info_get(const kelp_acomms_dccl *d, size_t i, kelp_acomms_dccl_info *out);
/** Index of a message by DCCL id / by name, or -1. */
long kelp_acomms_dccl_find_id(const kelp_acomms_dccl *d, unsigned id);
long kelp_acomms_dccl_find_name(const kelp_acomms_dccl *d, const char *name);

/** The bus variables the messages read (src_vars and trigger_vars), each once. */
size_t kelp_acomms_dccl_nvars(const kelp_acomms_dccl *d);
const char *kelp_acomms_dccl_var_name(const kelp_acomms_dccl *d, size_t i);
/** Remember the newest value of a bus variable (ignored unless a message reads it). */
void kelp_acomms_dccl_set_var(kelp_acomms_dccl *d, const char *name, bool is_double, double dval, const char *sval);
/** Messages (indices) a write of this variable triggers (publish trigger, mandatory content,
 *  not NO_ENCODE).  Call after kelp_acomms_dccl_set_var().  @return the count (<= cap). */
size_t kelp_acomms_dccl_triggered(const kelp_acomms_dccl *d, const char *name, size_t *idx, size_t cap);
/** Start the time-trigger clocks (trigger_time periods count from `now`). */
void kelp_acomms_dccl_start(kelp_acomms_dccl *d, kelp_time now);
/** Time-triggered messages due at `now` (each firing counted once). */
size_t kelp_acomms_dccl_due(kelp_acomms_dccl *d, kelp_time now, size_t *idx, size_t cap);

/** Encode message i from the remembered variables at `now` (UNIX seconds).
 *  @return 0, or <0 with diag set (may be NULL). */
KELP_MUST_CHECK int kelp_acomms_dccl_encode_vars(kelp_acomms_dccl *d, size_t i, kelp_time now, uint8_t *out, size_t cap,
                                                 size_t *len, kelp_diag *diag);
/** Encode message i from one "field=value,field=value" string that every field reads
 *  (header fields by their <name>, e.g. Destination=3). */
KELP_MUST_CHECK int kelp_acomms_dccl_encode_string(kelp_acomms_dccl *d, size_t i, const char *kv, kelp_time now,
                                                   uint8_t *out, size_t cap, size_t *len, kelp_diag *diag);

typedef void (*kelp_acomms_pub_fn)(const char *var, bool is_double, double dval, const char *sval, void *user);
/** Decode one (unstitched, flags cleared) DCCL message and run its <publish> blocks, calling
 *  fn for each publication.  NO_DECODE messages give KELP_ERR_STATE.
 *  @return 0, or <0 with diag (unknown id, bad bytes; diag may be NULL). */
KELP_MUST_CHECK int kelp_acomms_dccl_decode(kelp_acomms_dccl *d, const uint8_t *in, size_t n, kelp_time now,
                                            kelp_acomms_pub_fn fn, void *user, kelp_diag *diag);
/** "Name: field=value,field=value" of a message (every header and layout field). */
KELP_MUST_CHECK int kelp_acomms_dccl_describe(kelp_acomms_dccl *d, const uint8_t *in, size_t n, kelp_time now, char *buf,
                                              size_t cap);

#ifndef KELP_ACOMMS_DCCL_ONLY

#include <kelp/bus.h>
#include <kelp/mac.h>
#include <kelp/mmdriver.h>
#include <kelp/queue.h>

/* ================================================================== 2. TextFormat (core) */

/** boost ptime text of a UNIX time: "2011-Jan-22 12:08:06.887950" ("2002-Jan-01 14:23:11"
 *  when the microseconds are 0); t is rounded to the nearest microsecond.
 *  @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_acomms_time_text(kelp_time t, char *buf, size_t cap);

/** ModemDataTransmission:
 *  `base { src: 1 dest: 2 time: "..." } ack_requested: true data: "\002..." frame: 0
 *   queue_key { type: QUEUE_CCL id: 2 }` (queue_key only when key.type != 0).
 *  @return 0 or KELP_ERR_NOSPACE (output cut, NUL-terminated). */
KELP_MUST_CHECK int kelp_acomms_print_data(const kelp_acomms_msg *m, char *buf, size_t cap, size_t *len);
/** A ModemDataTransmission with only base (src, dest, time when has_time) and data set, as
 *  pREMUSCodec fills it: `base { src: 2 dest: 0 } data: "\016..."`. Same returns. */
KELP_MUST_CHECK int kelp_acomms_print_data_bare(const kelp_acomms_msg *m, char *buf, size_t cap, size_t *len);
/** ModemDataAck: `base { src: S dest: D time: ".." } frame: F orig_msg { ... }`. */
KELP_MUST_CHECK int kelp_acomms_print_ack(int src, int dest, uint32_t frame, kelp_time time, const kelp_acomms_msg *orig,
                                          char *buf, size_t cap, size_t *len);
/** ModemDataExpire: `orig_msg { ... }`. */
KELP_MUST_CHECK int kelp_acomms_print_expire(const kelp_acomms_msg *orig, char *buf, size_t cap, size_t *len);
/** QueueSize: `key { type: QUEUE_DCCL id: 1 } size: 3`. */
KELP_MUST_CHECK int kelp_acomms_print_qsize(kelp_queue_key key, uint32_t size, char *buf, size_t cap, size_t *len);
/** ModemRangingReply: `base { src: S dest: D time: ".." } one_way_travel_time: 0.0101 ...
 *  type: MODEM_TWO_WAY_PING` (NaN travel times print as "nan"). */
KELP_MUST_CHECK int kelp_acomms_print_range(int src, int dest, kelp_time time, kelp_ranging_type type, const double *tt,
                                            unsigned n_tt, char *buf, size_t cap, size_t *len);

/** ModemRangingRequest (ACOMMS_RANGE_COMMAND). */
typedef struct kelp_acomms_range_req {
    int src, dest;
    kelp_ranging_type type;       /**< default MODEM_TWO_WAY_PING */
    unsigned max_range;           /**< default 1000 m */
    unsigned enable_beacons;      /**< default 15 */
} kelp_acomms_range_req;

/** MACUpdate (ACOMMS_MAC_CYCLE_UPDATE). */
typedef struct kelp_acomms_mac_update {
    int dest;
    bool has_dest;
    kelp_mac_update_type type;    /**< default REPLACE */
    kelp_mac_slot slot[KELP_MAX_MAC_SLOTS];
    size_t nslots;
} kelp_acomms_mac_update;

/** Parse a ModemDataTransmission (CCL out var, IN_ hex var).  Unknown fields, bad values and
 *  data longer than KELP_MAX_ACOMMS_FRAME are errors.  @return 0 or KELP_ERR_PARSE /
 *  KELP_ERR_NOSPACE with d's reason (d may be NULL). */
KELP_MUST_CHECK int kelp_acomms_parse_data(const char *text, size_t len, kelp_acomms_msg *out, kelp_diag *d);
KELP_MUST_CHECK int kelp_acomms_parse_range_req(const char *text, size_t len, kelp_acomms_range_req *out, kelp_diag *d);
/** dest is required; slot fields default as Slot does (dest -1, rate 0, SLOT_DATA). */
KELP_MUST_CHECK int kelp_acomms_parse_mac_update(const char *text, size_t len, kelp_acomms_mac_update *out,
                                                 kelp_diag *d);

/* ================================================================== 3. the node (core) */

typedef enum kelp_acomms_driver_type {
    KELP_ACOMMS_DRIVER_NONE = 0,             /**< no modem */
    KELP_ACOMMS_DRIVER_WHOI_MICROMODEM = 1
} kelp_acomms_driver_type;

typedef enum kelp_acomms_ev_kind {
    KELP_ACOMMS_EV_QUEUE = 1,   /**< q: received piece, CCL frame, ack, expiry, queue size */
    KELP_ACOMMS_EV_DRIVER,      /**< mm: NMEA in/out, range, cycle, errors, retries, dead */
    KELP_ACOMMS_EV_SLOT,        /**< slot: a MAC slot of ours started */
    KELP_ACOMMS_EV_FRAME_OUT,   /**< req + frame: the queue answered a data request */
    KELP_ACOMMS_EV_LOOPBACK     /**< frame: DRIVER_NONE's ideal channel delivered/acked a frame */
} kelp_acomms_ev_kind;

typedef struct kelp_acomms_event {
    kelp_acomms_ev_kind kind;
    kelp_time time;
    const kelp_queue_event *q;
    const kelp_mmdriver_event *mm;
    const kelp_mac_action *slot;
    const kelp_queue_request *req;
    const kelp_acomms_msg *frame;
} kelp_acomms_event;

typedef struct kelp_acomms_node_ops {
    /** Bytes for the modem link (WHOI driver). */
    void (*write)(const char *bytes, size_t len, void *user);
    void (*event)(const kelp_acomms_event *ev, void *user);
    /** ON_DEMAND queues: fill a message for `key` now (may be NULL). */
    kelp_queue_on_demand_fn on_demand;
} kelp_acomms_node_ops;

typedef struct kelp_acomms_node_cfg {
    int modem_id;                 /**< 1..31 */
    kelp_acomms_driver_type driver;
    kelp_mmdriver_cfg mm;               /**< WHOI driver configuration (modem_id is forced) */
    kelp_mac_cfg mac;             /**< modem_id is forced */
    /** DRIVER_NONE only: an ideal in-process channel.  At our MAC data slots the frames the
     *  queue hands out are delivered back to our receive path (which keeps the broadcast pieces),
     *  and every frame that asked for an ack is acknowledged as if its destination answered. */
    bool loopback_channel;
} kelp_acomms_node_cfg;

typedef struct kelp_acomms_node_counters {
    uint32_t slots, transmissions, ranging, frames_out, blank_frames, frames_in, acks, loopback_delivered,
        loopback_acked, driver_restarts, slots_skipped;
} kelp_acomms_node_counters;

typedef struct kelp_acomms_node {
    /* private */
    int modem_id;
    kelp_acomms_driver_type driver;
    bool loopback;
    bool started;
    bool link_up;                 /**< WHOI: false while the link is down (no cycles, no driver ticks) */
    kelp_queue_mgr q;
    kelp_mac mac;
    kelp_mmdriver mm;
    kelp_acomms_node_ops ops;
    void *user;
    kelp_time now;                /**< time of the call in progress (for callbacks) */
    kelp_acomms_msg scratch;      /**< driver callbacks: the frame asked for / received */
    union {
        kelp_acomms_msg frames[KELP_MAX_MM_FRAMES]; /**< DRIVER_NONE transmission: the packet's frames */
        kelp_mac_slot slots[KELP_MAX_MAC_SLOTS];     /**< kelp_acomms_node_start: the cycle kept */
    } work;                       /**< scratch of one call (never held across an event callback
                                       that could start another transmission or a start) */
    kelp_acomms_node_counters count;
    kelp_diag diag;               /**< why the last failed call failed (each failure replaces it) */
} kelp_acomms_node;

void kelp_acomms_node_cfg_default(kelp_acomms_node_cfg *cfg);

/** Set up over caller storage for queues and queued messages.  KELP_ERR_ARG for a modem id
 *  outside 1..31 (0 is broadcast) or a bad driver configuration. */
KELP_MUST_CHECK int kelp_acomms_node_init(kelp_acomms_node *n, const kelp_acomms_node_cfg *cfg, kelp_queue *queues,
                                          size_t cap_queues, kelp_queue_entry *pool, size_t cap_pool,
                                          const kelp_acomms_node_ops *ops, void *user);
/** Add a queue (before or after start). */
KELP_MUST_CHECK int kelp_acomms_node_add_queue(kelp_acomms_node *n, const kelp_queue_cfg *cfg, kelp_time now);
/** The queue configuration of a DCCL message: its <queuing> block and its file's manipulators
 *  (on_demand, no_queue). Loopback stays off: the handler decodes its own sends itself. */
void kelp_acomms_queue_cfg_from_info(const kelp_acomms_dccl_info *info, kelp_queue_cfg *q);
/** Start the MAC and (WHOI) the driver's start-up sequence. */
KELP_MUST_CHECK int kelp_acomms_node_start(kelp_acomms_node *n, kelp_time now);
/** The link came back: run the driver's start-up sequence again (queued messages are kept). */
KELP_MUST_CHECK int kelp_acomms_node_restart_driver(kelp_acomms_node *n, kelp_time now);
/** WHOI: tell the node whether the modem link is up.  While it is down (or the driver is dead)
 *  MAC slots are reported but start no cycle -- so no queued message is handed to a modem that
 *  cannot send it -- and the driver is not ticked.  Default: up. */
void kelp_acomms_node_set_link_up(kelp_acomms_node *n, bool up);
/** Periodic work: queue expiry, MAC slots, driver timers.  @return 0, or KELP_ERR_TIMEOUT when
 *  the modem has stopped answering (reconnect, then kelp_acomms_node_restart_driver). */
KELP_MUST_CHECK int kelp_acomms_node_tick(kelp_acomms_node *n, kelp_time now);
/** Bytes read from the modem link. */
KELP_MUST_CHECK int kelp_acomms_node_feed(kelp_acomms_node *n, const uint8_t *bytes, size_t len, kelp_time now);
/** Queue a message (see kelp_queue_push). */
KELP_MUST_CHECK int kelp_acomms_node_push(kelp_acomms_node *n, const kelp_acomms_msg *msg, kelp_time now);
/** Start a transmission as a MAC data slot would (src, dest -1 = ask the queue, rate 0..5). */
KELP_MUST_CHECK int kelp_acomms_node_transmit(kelp_acomms_node *n, int src, int dest, unsigned rate, kelp_time now);
/** Ranging (ACOMMS_RANGE_COMMAND or a MAC ping slot).  KELP_ERR_STATE without a driver. */
KELP_MUST_CHECK int kelp_acomms_node_range(kelp_acomms_node *n, const kelp_acomms_range_req *r, kelp_time now);
/** ACOMMS_MAC_CYCLE_UPDATE (see kelp_mac_update). */
KELP_MUST_CHECK int kelp_acomms_node_mac_update(kelp_acomms_node *n, const kelp_acomms_mac_update *u, kelp_time now);

/* Direct access for replay tools (what the modem would cause): */
/** A data request as the modem would make it; the FRAME_OUT event is emitted too. */
KELP_MUST_CHECK int kelp_acomms_node_data_request(kelp_acomms_node *n, const kelp_queue_request *req, kelp_time now,
                                                  kelp_acomms_msg *out);
/** A modem ack of `frame` from src (dest must be us).  @return messages acknowledged, or
 *  KELP_ERR_ARG (n NULL). */
KELP_MUST_CHECK int kelp_acomms_node_ack(kelp_acomms_node *n, int src, int dest, uint32_t frame, kelp_time now);
/** A frame received from the modem. @return pieces reported, or KELP_ERR_ARG (NULL n or frame). */
KELP_MUST_CHECK int kelp_acomms_node_receive(kelp_acomms_node *n, const kelp_acomms_msg *frame, kelp_time now);
/** Modem `src` was heard (MAC auto-discovery). */
void kelp_acomms_node_heard(kelp_acomms_node *n, int src, kelp_time now);

kelp_queue_mgr *kelp_acomms_node_queue(kelp_acomms_node *n);
kelp_mac *kelp_acomms_node_mac(kelp_acomms_node *n);
kelp_mmdriver *kelp_acomms_node_driver(kelp_acomms_node *n);
const kelp_acomms_node_counters *kelp_acomms_node_get_counters(const kelp_acomms_node *n);

/* ================================================================== 4. configuration (edge) */

#ifndef KELP_MISSION_H
struct kelp_mission;
struct kelp_mission_node;
#endif

typedef enum kelp_acomms_connection {
    KELP_ACOMMS_CONN_SERIAL = 0,
    KELP_ACOMMS_CONN_TCP_AS_CLIENT = 1,
    KELP_ACOMMS_CONN_TCP_AS_SERVER = 2,
    KELP_ACOMMS_CONN_DUAL_UDP_BROADCAST = 3 /**< accepted, unimplemented (as Goby 1.1) */
} kelp_acomms_connection;

typedef struct kelp_acomms_initializer {
    bool is_double;               /**< INI_DOUBLE, else INI_STRING */
    char moos_var[KELP_MAX_NAME];
    char global_cfg_var[KELP_MAX_NAME];
    bool has_dval, has_sval;
    double dval;
    char sval[KELP_ACOMMS_MAX_TEXT];
    int line;
} kelp_acomms_initializer;

typedef struct kelp_acomms_msgfile {
    char path[KELP_ACOMMS_MAX_PATH];
    unsigned manip;               /**< KELP_ACOMMS_MANIP_* */
} kelp_acomms_msgfile;

typedef struct kelp_acomms_ccl_queue {
    kelp_queue_cfg cfg;           /**< cfg.name points at name below */
    char name[KELP_MAX_NAME];
    char in_var[KELP_MAX_NAME];   /**< published on receipt */
    char out_var[KELP_MAX_NAME];  /**< subscribed: messages to queue */
} kelp_acomms_ccl_queue;

typedef enum kelp_acomms_verbosity {
    KELP_ACOMMS_VERBOSITY_QUIET = 0,
    KELP_ACOMMS_VERBOSITY_WARN,
    KELP_ACOMMS_VERBOSITY_VERBOSE,
    KELP_ACOMMS_VERBOSITY_DEBUG,
    KELP_ACOMMS_VERBOSITY_GUI
} kelp_acomms_verbosity;

/** The pAcommsHandler configuration block, every field Goby 1.1's pAcommsHandler reads. */
typedef struct kelp_acomms_config {
    /* common { } (global fallbacks: log, log_path, Community, LatOrigin, LongOrigin) */
    bool log;
    char log_path[KELP_ACOMMS_MAX_PATH];
    char community[KELP_MAX_NAME];
    bool has_lat_origin, has_lon_origin;
    double lat_origin, lon_origin;
    double app_tick, comm_tick;
    kelp_acomms_verbosity verbosity;
    kelp_acomms_initializer init[KELP_ACOMMS_MAX_INIT];
    size_t n_init;
    /* top level */
    int modem_id;
    kelp_acomms_driver_type driver_type;
    /* driver_cfg { } */
    kelp_acomms_connection connection;
    char line_delimiter[8];
    char serial_port[KELP_ACOMMS_MAX_PATH];
    unsigned serial_baud;
    char tcp_server[KELP_ACOMMS_MAX_PATH];
    unsigned tcp_port;
    bool reset_nvram;
    char nvram[KELP_MAX_MM_NVRAM][KELP_MAX_MM_NVRAM_LEN];
    size_t n_nvram;
    int hydroid_gateway_id;
    /* mac_cfg { } */
    kelp_mac_type mac_type;
    unsigned mac_rate, mac_slot_seconds, mac_expire_cycles;
    kelp_mac_slot slots[KELP_MAX_MAC_SLOTS];
    size_t nslots;
    /* queue_cfg { } and dccl_cfg { } (message files merged, de-duplicated by path) */
    kelp_acomms_ccl_queue ccl[KELP_ACOMMS_MAX_CCL];
    size_t nccl;
    kelp_acomms_msgfile files[KELP_ACOMMS_MAX_FILES];
    size_t nfiles;
    bool has_passphrase;
    char crypto_passphrase[KELP_ACOMMS_MAX_TEXT];
    char modem_id_lookup_path[KELP_ACOMMS_MAX_PATH];
    bool tcp_share_enable;
    unsigned tcp_share_port;
    char tcp_share_to_ip[4][KELP_MAX_NAME];
    size_t n_tcp_share;
} kelp_acomms_config;

/** kelp_acomms_dccl_open over a pAcommsHandler block: its message files and manipulators, modem
 *  id, passphrase, lookup file and LatOrigin/LongOrigin. `plaintext` as in kelp_acomms_dccl_cfg. */
kelp_acomms_dccl *kelp_acomms_dccl_open_config(const kelp_acomms_config *cfg, bool plaintext, kelp_diag *d);

void kelp_acomms_config_default(kelp_acomms_config *cfg);

/** Read the pAcommsHandler block (node index `block` of m; globals of m fill the fallbacks).
 *  Relative message-file and lookup paths are taken relative to `base_dir` (the mission's
 *  directory; NULL = as written).  Unknown fields, bad enums and out-of-range numbers are
 *  errors: "line N: key: reason" in d (and N in d->line; d may be NULL).  Values the Goby 1.1 User
 *  Manual defines as warnings (e.g. tcp sharing is experimental) go to warn (may be NULL).
 *  @return 0 or KELP_ERR_PARSE / KELP_ERR_ARG. */
KELP_MUST_CHECK int kelp_acomms_config_read(const struct kelp_mission *m, int block, const char *base_dir,
                                            kelp_acomms_config *cfg, kelp_diag *d, char *warn, size_t warncap);

/** A field of the block the pAcommsHandler reader does not know, offered to another tool
 *  reading a block of the same family (kelp-commander's load, show_variable, ...).
 *  @return 1 taken, 0 unknown ("unknown field"), <0 bad value (d says why). */
typedef int (*kelp_acomms_config_extra_fn)(void *ctx, const struct kelp_mission_node *n, kelp_diag *d);
/** kelp_acomms_config_read with extra top-level fields handed to `extra` (may be NULL). */
KELP_MUST_CHECK int kelp_acomms_config_read_extra(const struct kelp_mission *m, int block, const char *base_dir,
                                                  kelp_acomms_config *cfg, kelp_diag *d, char *warn, size_t warncap,
                                                  kelp_acomms_config_extra_fn extra, void *extra_ctx);

/** Node configuration from a block (driver, MAC, modem id); nvram strings point into cfg. */
void kelp_acomms_config_node(const kelp_acomms_config *cfg, kelp_acomms_node_cfg *out);

/* ================================================================== 4b. the handler (core) */

/* pAcommsHandler's logic as a core state machine: bus mail and `now` in; the ACOMMS_* strings,
 * the DCCL <publish> variables, the modem link bytes and the structured (LCM) copies out
 * through a kelp_acomms_sink.  It allocates nothing and reads no clock: the caller passes the
 * queue pool, the DCCL codec (as a kelp_acomms_codec: the edge fills one from a
 * kelp_acomms_dccl handle, a test passes a fake, firmware its own tables) and the time. */

/** The DCCL codec as the handler uses it (see the kelp_acomms_dccl_* functions of part 1 for
 *  the meaning of each call).  Every member is required when the codec is given at all. */
typedef struct kelp_acomms_codec {
    void *ctx;
    size_t (*count)(void *ctx);
    int (*info)(void *ctx, size_t i, kelp_acomms_dccl_info *out);
    long (*find_id)(void *ctx, unsigned id);
    size_t (*nvars)(void *ctx);
    const char *(*var_name)(void *ctx, size_t i);
    void (*set_var)(void *ctx, const char *name, bool is_double, double dval, const char *sval);
    size_t (*triggered)(void *ctx, const char *name, size_t *idx, size_t cap);
    void (*start)(void *ctx, kelp_time now);
    size_t (*due)(void *ctx, kelp_time now, size_t *idx, size_t cap);
    int (*encode)(void *ctx, size_t i, kelp_time now, uint8_t *out, size_t cap, size_t *len, kelp_diag *d);
    int (*decode)(void *ctx, const uint8_t *in, size_t n, kelp_time now, kelp_acomms_pub_fn fn, void *user,
                  kelp_diag *d);
    int (*describe)(void *ctx, const uint8_t *in, size_t n, kelp_time now, char *buf, size_t cap);
} kelp_acomms_codec;

/** Counters for kelp.acomms_status_t. */
typedef struct kelp_acomms_status {
    double time;
    int modem_id;
    const char *driver, *link, *mac;
    bool link_up, clock_ok;
    kelp_time next_slot;      /**< next MAC slot start, -1 when idle */
    uint32_t lines_in, lines_out, bad_lines, retries, modem_errors, reconnects, frames_out, frames_in, acks, expired,
        encoded, decoded;
    size_t nqueues;
    const char *const *queue_name;
    const int32_t *queue_size;
} kelp_acomms_status;

typedef enum kelp_acomms_rec_kind {
    KELP_ACOMMS_REC_DATA = 1, /**< msg, name, decoded */
    KELP_ACOMMS_REC_ACK,      /**< src, dest, frame, msg (the acknowledged message), name */
    KELP_ACOMMS_REC_EXPIRE,   /**< msg, name */
    KELP_ACOMMS_REC_QSIZE,    /**< key, name, size */
    KELP_ACOMMS_REC_RANGE,    /**< src, dest, type, tt, n_tt */
    KELP_ACOMMS_REC_STATUS    /**< status */
} kelp_acomms_rec_kind;

/** A structured copy of a publication (the LCM kelp.acomms_*_t structures).  Pointers are
 *  valid during the callback only. */
typedef struct kelp_acomms_record {
    kelp_acomms_rec_kind kind;
    const char *channel;          /**< ACOMMS_INCOMING_DATA_LCM, ACOMMS_ACK_LCM, ... */
    double time;
    const kelp_acomms_msg *msg;
    const char *name;             /**< DCCL message / CCL queue name, may be NULL */
    const char *decoded;          /**< "Name: field=value,..." , may be NULL */
    int src, dest;
    uint32_t frame;
    kelp_queue_key key;
    uint32_t size;
    kelp_ranging_type type;
    const double *tt;
    unsigned n_tt;
    const kelp_acomms_status *status;
} kelp_acomms_record;

/** Where the handler's output goes.  publish is required, every other member may be NULL. */
typedef struct kelp_acomms_sink {
    void *ctx;
    /** A bus variable.  @return <0 if it could not be published (the handler warns where
     *  pAcommsHandler does). */
    int (*publish)(void *ctx, const char *var, bool is_string, const char *sval, double dval);
    /** A run warning / an event for the app's status report. */
    void (*warn)(void *ctx, const char *msg);
    void (*event)(void *ctx, const char *msg);
    /** Bytes for the modem link (WHOI driver). */
    void (*write)(void *ctx, const char *bytes, size_t len);
    /** The modem stopped answering: close the link (the caller reopens it and then calls
     *  kelp_acomms_handler_link_up). */
    void (*close_link)(void *ctx);
    /** Structured copies; NULL = none wanted (and no DCCL message is described for them). */
    void (*record)(void *ctx, const kelp_acomms_record *rec);
    /** Every node event, after the handler has handled it (for tools that print them). */
    void (*node_event)(void *ctx, const kelp_acomms_event *ev);
} kelp_acomms_sink;

/** One queue of the handler, with the bus variables of its messages. */
typedef struct kelp_acomms_qname {
    kelp_queue_key key;
    const char *name;
    const char *in_var;           /**< DCCL: IN_ hex var; CCL: in_pubsub_var */
    const char *out_var;          /**< DCCL: OUT_ hex var; CCL: out_pubsub_var */
    long dccl_index;              /**< codec index, -1 for CCL */
} kelp_acomms_qname;

typedef struct kelp_acomms_handler_counters {
    unsigned long encoded, encode_errors, decoded, decode_errors, pushed, push_errors, in_data, out_data, acks, expires,
        ranges, nmea_in, nmea_out, bad_lines, retries, give_ups, modem_errors, reconnects, deaths, ccl_in, ccl_out,
        bad_mail;
} kelp_acomms_handler_counters;

#define KELP_ACOMMS_NMEA_KEEP 6       /**< sentences kept each way for the report */
#define KELP_ACOMMS_NMEA_KEEP_LEN 96  /**< bytes kept of each */

typedef struct kelp_acomms_handler {
    /* read-only for the caller (the app's report) */
    const kelp_acomms_config *cfg;
    kelp_acomms_node node;
    kelp_acomms_qname names[KELP_ACOMMS_MAX_QUEUES];
    size_t nnames;
    kelp_acomms_handler_counters count;
    bool started, link_up;
    kelp_time now;                   /**< time of the last mail or tick */
    const char *link_desc;        /**< set by the caller: how the modem link is described ("" none) */
    char last_in[KELP_ACOMMS_NMEA_KEEP][KELP_ACOMMS_NMEA_KEEP_LEN];
    char last_out[KELP_ACOMMS_NMEA_KEEP][KELP_ACOMMS_NMEA_KEEP_LEN];
    unsigned n_in, n_out;
    /** Why the last call failed: after a failed init/start the code and the node's reason (and
     *  for a refused queue err_queue, err_id and err_ccl below); while running, the reason of the
     *  last refused mail or failed encode/decode (then rewritten by each mail and tick). */
    kelp_diag diag;
    const char *err_queue;
    unsigned err_id;
    bool err_ccl;
    /* private */
    kelp_acomms_codec codec;
    bool has_codec;
    kelp_acomms_sink sink;
    kelp_queue queues[KELP_ACOMMS_MAX_QUEUES];
    bool driver_dead, started_on_link, seen_link;
    double next_status;
    char text[KELP_ACOMMS_MAX_PRINT];
    char decoded_text[1024];
    char line[512];
    union {
        kelp_acomms_msg msg;                 /**< a message being sent or decoded (mail, tick) */
        kelp_acomms_mac_update mac_update;   /**< ACOMMS_MAC_CYCLE_UPDATE being applied */
    } work; /**< scratch of one mail or tick (the sink must not call back into the handler) */
} kelp_acomms_handler;

/** A DCCL message encoded into m->data (len bytes) made ready for its queue: src, dest (from
 *  the DCCL header), time, queue key (QUEUE_DCCL, id).  @return 0, KELP_ERR_TRUNCATED (shorter
 *  than the header) or KELP_ERR_ARG. */
KELP_MUST_CHECK int kelp_acomms_msg_from_dccl(kelp_acomms_msg *m, size_t len, int src, unsigned id, kelp_time time);

/** "MAC_NONE", "MAC_FIXED_DECENTRALIZED", ... ("?" if unknown). */
const char *kelp_acomms_mac_name(kelp_mac_type t);

/** Set up the node (nc, over the caller's pool), add a queue for every DCCL message of the
 *  codec (NULL = none) and every CCL queue of cfg (until KELP_ACOMMS_MAX_QUEUES), then publish
 *  MODEM_ID and VEHICLE_ID.  cfg, the codec's strings and the pool must outlive the handler.
 *  @return 0, or <0 with h->diag (and err_queue/err_id when a queue was refused). */
KELP_MUST_CHECK int kelp_acomms_handler_init(kelp_acomms_handler *h, const kelp_acomms_config *cfg,
                                             const kelp_acomms_node_cfg *nc, const kelp_acomms_codec *codec,
                                             kelp_queue_entry *pool, size_t cap_pool, const kelp_acomms_sink *sink,
                                             kelp_time now);
/** The bus variables to subscribe to, i = 0, 1, ... until NULL: the codec's source and trigger
 *  variables, the DCCL IN_ and CCL out variables, ACOMMS_RANGE_COMMAND, ACOMMS_MAC_CYCLE_UPDATE
 *  and ACOMMS_POLLER_UPDATE. */
const char *kelp_acomms_handler_subscription(kelp_acomms_handler *h, size_t i);
/** Remember a value for the DCCL sources without triggering anything (initializers). */
void kelp_acomms_handler_set_var(kelp_acomms_handler *h, const char *name, bool is_double, double dval,
                                 const char *sval);
/** Start: DCCL time triggers and the node (WHOI: its start-up sequence goes out when link_up). */
KELP_MUST_CHECK int kelp_acomms_handler_start(kelp_acomms_handler *h, bool link_up, kelp_time now);
/** Mail.  own: our own publication coming back (an IN_ variable is then not decoded again). */
void kelp_acomms_handler_mail(kelp_acomms_handler *h, const kelp_var *v, bool own, kelp_time now);
/** Periodic work: node tick, driver death (close_link), time-triggered DCCL, status once a second. */
void kelp_acomms_handler_tick(kelp_acomms_handler *h, kelp_time now);
/** Bytes from the modem link (events use the time of the last mail or tick). */
void kelp_acomms_handler_feed(kelp_acomms_handler *h, const uint8_t *bytes, size_t len, kelp_time now);
/** The modem link came up (first time, or again after a loss) at `now`: restart the driver if
 *  needed (not the first time when start() was told the link was up). */
void kelp_acomms_handler_link_up(kelp_acomms_handler *h, kelp_time now);
/** The modem link was lost (why: the link's reason). */
void kelp_acomms_handler_link_lost(kelp_acomms_handler *h, const char *why);
/** The handler's queue of a key, or NULL. */
const kelp_acomms_qname *kelp_acomms_handler_queue(const kelp_acomms_handler *h, kelp_queue_key key);

/* ================================================================== 5. LCM structures (edge) */

/** The lcm-gen'd kelp.acomms_*_t structures of the handler's records, encoded for the
 *  <VARIABLE>_LCM channels (lcm-spy decodes them with `make spy-jar`) and handed to a send
 *  callback (pAcommsHandler: its own LCM socket). */
typedef struct kelp_acomms_lcm kelp_acomms_lcm;
/** Send one encoded LCM message on channel.  @return 0 on success. */
typedef int (*kelp_acomms_lcm_send_fn)(void *ctx, const char *channel, const void *data, size_t len);

/** NULL if out of memory or send is NULL. */
kelp_acomms_lcm *kelp_acomms_lcm_new(kelp_acomms_lcm_send_fn send, void *ctx);
void kelp_acomms_lcm_close(kelp_acomms_lcm *l);
/** name: DCCL message / CCL queue name (may be NULL); decoded: "Name: f=v,..." (may be NULL). */
KELP_MUST_CHECK int kelp_acomms_lcm_data(kelp_acomms_lcm *l, const char *channel, double time, const kelp_acomms_msg *m,
                                         const char *name, const char *decoded);
KELP_MUST_CHECK int kelp_acomms_lcm_ack(kelp_acomms_lcm *l, const char *channel, double time, int src, int dest,
                                        uint32_t frame, const kelp_acomms_msg *orig, const char *name);
KELP_MUST_CHECK int kelp_acomms_lcm_expire(kelp_acomms_lcm *l, const char *channel, double time,
                                           const kelp_acomms_msg *orig, const char *name);
KELP_MUST_CHECK int kelp_acomms_lcm_qsize(kelp_acomms_lcm *l, const char *channel, double time, kelp_queue_key key,
                                          const char *name, uint32_t size);
KELP_MUST_CHECK int kelp_acomms_lcm_range(kelp_acomms_lcm *l, const char *channel, double time, int src, int dest,
                                          kelp_ranging_type type, const double *tt, unsigned n_tt);
KELP_MUST_CHECK int kelp_acomms_lcm_status(kelp_acomms_lcm *l, const char *channel, const kelp_acomms_status *s);
/** Publish a handler record (the matching kelp_acomms_lcm_* call). */
KELP_MUST_CHECK int kelp_acomms_lcm_record(kelp_acomms_lcm *l, const kelp_acomms_record *rec);

/** The handler's view of a DCCL glue handle (part 1): out->ctx = d, the calls forward to it. */
void kelp_acomms_dccl_codec(kelp_acomms_dccl *d, kelp_acomms_codec *out);

#endif /* KELP_ACOMMS_DCCL_ONLY */
#ifdef __cplusplus
}
#endif

#endif
