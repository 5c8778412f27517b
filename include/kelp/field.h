/* kelp field: the logic of the uField tools and of pNodeReporter, as core state machines.
 *
 * Every tool here follows one pattern: its configuration is a plain struct (filled by the app
 * from its ProcessConfig block), mail and `now` come in as arguments, and publications go out
 * through a kelp_field_sink (a context pointer and callbacks). The core allocates nothing,
 * reads no clock and does no I/O, so a tool runs the same in an app on the bus, in a unit
 * test with a recording sink, and in vehicle firmware.
 */
#ifndef KELP_FIELD_H
#define KELP_FIELD_H

#include <stdbool.h>
#include <stddef.h>
#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/geo.h>
#include <kelp/nodereport.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Where a tool's publications go. publish is required; warn (a run warning for the app's
 *  status report) may be NULL. */
typedef struct kelp_field_sink {
    void *ctx;
    void (*publish)(void *ctx, const char *var, bool is_string, const char *sval, double dval);
    void (*warn)(void *ctx, const char *msg);
} kelp_field_sink;

/* ------------------------------------------------------------------ pNodeReporter */

/** Navigation inputs, in the order of kelp_field_nrep.nav_var. */
enum { KELP_NREP_X, KELP_NREP_Y, KELP_NREP_LAT, KELP_NREP_LON, KELP_NREP_SPD, KELP_NREP_HDG, KELP_NREP_DEP,
       KELP_NREP_YAW, KELP_NREP_COG, KELP_NREP_NAV };

/** One navigation solution: the main one (PREFIX) or the alternate (ALT_NAV_PREFIX). */
typedef struct kelp_nrep_nav {
    char var[KELP_NREP_NAV][KELP_MAX_NAME]; /**< <prefix>_X, _Y, _LAT, _LONG, _SPEED, _HEADING, ... */
    double v[KELP_NREP_NAV];
    bool have[KELP_NREP_NAV];
    unsigned long xy_seq, ll_seq;           /**< order of the last X/Y and LAT/LON mail (use-latest) */
    bool mail;                              /**< mail since the last iteration */
    double last;                            /**< time of the last iteration with mail (-1 never) */
} kelp_nrep_nav;

#define KELP_NREP_MAX_PLAT 8   /**< plat_report_input entries */
#define KELP_NREP_MAX_RIDERS 8 /**< rider entries */

/** cross_fill_policy: how X/Y and LAT/LON fill each other (with a datum). */
typedef enum kelp_nrep_fill {
    KELP_NREP_FILL_LITERAL = 0, /**< report what arrived */
    KELP_NREP_FILL_EMPTY,       /**< fill one pair only if it never arrived */
    KELP_NREP_FILL_LATEST,      /**< the pair updated last fills the other */
    KELP_NREP_FILL_GLOBAL,      /**< X/Y always from LAT/LON */
    KELP_NREP_FILL_LOCAL        /**< LAT/LON always from X/Y */
} kelp_nrep_fill;

/** plat_report_input: a variable carried in the platform report, at most every gap s. */
typedef struct kelp_nrep_plat {
    char var[KELP_MAX_NAME], alias[KELP_MAX_NAME];
    double gap;
} kelp_nrep_plat;

/** rider: a variable carried in every node report (policy always) or only after it changed
 *  (policy updated), as rfld=<value>, numbers with prec decimals. */
typedef struct kelp_nrep_rider {
    char var[KELP_MAX_NAME], field[KELP_MAX_NAME];
    bool updated_only;
    int prec;
} kelp_nrep_rider;

typedef struct kelp_field_nrep_cfg {
    char name[KELP_NODEREPORT_MAX_FIELD];  /**< NAME= (VESSEL_NAME; default the community) */
    char type[KELP_NODEREPORT_MAX_FIELD];  /**< TYPE= (PLATFORM_TYPE / VESSEL_TYPE; default UUV) */
    char group[KELP_NODEREPORT_MAX_FIELD]; /**< GROUP= (PLATFORM_GROUP / GROUP; "" none) */
    char color[KELP_NODEREPORT_MAX_FIELD]; /**< COLOR= (PLATFORM_COLOR; "" none) */
    char aspect[256];                      /**< PLATFORM_ASPECT pairs "K=V,K=V" added to every report */
    char out_var[KELP_MAX_NAME];           /**< NODE_REPORT_OUTPUT (default NODE_REPORT_LOCAL) */
    char json_var[KELP_MAX_NAME];          /**< JSON_REPORT: also post the report as JSON here ("" none) */
    bool json_only;                        /**< JSON_REPORT = true: out_var carries JSON */
    char plat_var[KELP_MAX_NAME];          /**< PLAT_REPORT_OUTPUT (default PLATFORM_REPORT_LOCAL) */
    char mode_var[KELP_MAX_NAME];          /**< MODE_VAR: MODE= from this variable ("" none) */
    char prefix[24];                       /**< PREFIX of the navigation variables (default NAV) */
    char alt_prefix[24];                   /**< ALT_NAV_PREFIX: a second solution reported too ("" none) */
    char alt_name[KELP_NODEREPORT_MAX_FIELD];  /**< ALT_NAV_NAME: "_GT" appends to NAME (default "_GT") */
    char alt_group[KELP_NODEREPORT_MAX_FIELD]; /**< ALT_NAV_GROUP ("" the main group) */
    bool report_cog;                       /**< REPORT_COG: COG= from <PREFIX>_HEADING_OVER_GROUND */
    double length;                         /**< PLATFORM_LENGTH (with have_length) */
    bool have_length;
    double beam;                           /**< PLATFORM_BEAM (kept for viewers; not in the report) */
    kelp_geo geo;                          /**< LatOrigin/LongOrigin (with have_geo) */
    bool have_geo;
    double nohelm_threshold;               /**< s without helm mail before MODE=NOHELM-... (5) */
    double blackout_interval, blackout_variance; /**< s between reports, +- variance */
    double nav_grace_period;               /**< s after start to report without navigation (-1 never) */
    bool paused;                           /**< PAUSED: no reports */
    bool allow_color_change;               /**< NODE_COLOR_CHANGE may change COLOR */
    bool coord_global;                     /**< COORD_POLICY_GLOBAL: no X/Y in reports */
    bool dep_key;                          /**< DEPTH_KEY = DEP: depth written as DEP= (default DEPTH=) */
    double hdg_error;                      /**< HDG_ERROR: degrees added to the reported heading */
    kelp_nrep_fill fill;                   /**< CROSS_FILL_POLICY (needs the datum) */
    bool extrap;                           /**< EXTRAP_ENABLED: skip reports a receiver can extrapolate */
    double extrap_pos, extrap_hdg, extrap_gap; /**< m, degrees, s (0.25, 1, 5) */
    kelp_nrep_plat plat[KELP_NREP_MAX_PLAT];
    unsigned nplat;
    kelp_nrep_rider rider[KELP_NREP_MAX_RIDERS];
    unsigned nriders;
    uint64_t seed;                         /**< blackout variance draws */
} kelp_field_nrep_cfg;

typedef struct kelp_field_nrep {
    kelp_field_nrep_cfg cfg;
    kelp_nrep_nav nav[2];                  /**< [0] the main solution, [1] the alternate */
    char helm_state[KELP_NODEREPORT_MAX_FIELD], helm_modes[KELP_NODEREPORT_MAX_FIELD];
    char mode[KELP_NODEREPORT_MAX_FIELD], allstop[KELP_NODEREPORT_MAX_FIELD];
    char color[KELP_NODEREPORT_MAX_FIELD];
    bool helm_mail;                        /**< helm mail since the last iteration */
    double helm_last, start, last_post, blackout;
    struct { double x, y, hdg, spd, time; } posted_at; /**< the last report, for extrapolation */
    char plat_val[KELP_NREP_MAX_PLAT][KELP_NODEREPORT_MAX_FIELD];
    double plat_recv[KELP_NREP_MAX_PLAT], plat_sent[KELP_NREP_MAX_PLAT];
    bool plat_new[KELP_NREP_MAX_PLAT];
    char rider_val[KELP_NREP_MAX_RIDERS][KELP_NODEREPORT_MAX_FIELD];
    bool rider_have[KELP_NREP_MAX_RIDERS], rider_new[KELP_NREP_MAX_RIDERS];
    uint64_t rng;
    unsigned long posted, alt_posted, nav_mail, bad_mail, extrap_skipped;
    char last[KELP_NODEREPORT_MAX_LEN];    /**< the last report posted */
} kelp_field_nrep;

/** Defaults: name = community, type UUV, output NODE_REPORT_LOCAL, prefix NAV, nohelm 5 s,
 *  extrapolation thresholds 0.25 m / 1 degree / 5 s, platform report PLATFORM_REPORT_LOCAL. */
void kelp_field_nrep_cfg_default(kelp_field_nrep_cfg *cfg, const char *community);
/** Add a plat_report_input ("VAR, gap=1, alias=A") or a rider ("var=V, policy=always|updated,
 *  rfld=F, prec=3"). @return 0, or <0 with *why. */
KELP_MUST_CHECK int kelp_field_nrep_add_plat(kelp_field_nrep_cfg *cfg, const char *spec, const char **why);
KELP_MUST_CHECK int kelp_field_nrep_add_rider(kelp_field_nrep_cfg *cfg, const char *spec, const char **why);
/** CROSS_FILL_POLICY value: literal, fill-empty, use-latest, global, local ('_' for '-' too). */
KELP_MUST_CHECK int kelp_field_nrep_parse_fill(const char *s, kelp_nrep_fill *out);
/** Start with cfg at `now`. KELP_ERR_ARG when a text field holds ',' or '=' or the name is empty. */
KELP_MUST_CHECK int kelp_field_nrep_init(kelp_field_nrep *r, const kelp_field_nrep_cfg *cfg, double now);
/** The variables to subscribe to, one per call (i from 0) until NULL. */
const char *kelp_field_nrep_subscription(const kelp_field_nrep *r, unsigned i);
/** One mail. Returns 1 when it was used, 0 when not for this tool, <0 (and a warning) when
 *  bad (a navigation value that is not a finite number). */
int kelp_field_nrep_mail(kelp_field_nrep *r, const char *var, bool is_string, const char *sval, double dval,
                         const kelp_field_sink *out);
/** Iterate at `now` (pNodeReporter's rule): a report when the navigation is valid (a
 *  position, speed and heading; or the grace period is over) and the blackout interval has
 *  passed, unless a receiver could extrapolate it. The first goes to <OUT>_FIRST too; each is
 *  followed by PNR_POST_GAP; with ALT_NAV_PREFIX, a report of the alternate solution (its own
 *  name and group) follows while that solution had mail in the last 5 s. MODE is NOHELM-EVER / NOHELM-<s> without helm mail for
 *  nohelm_threshold s, else the helm state, or the helm's modes in DRIVE.
 *  Returns 1 when a report was published, 0 when none was due, <0 on a formatting error. */
int kelp_field_nrep_iterate(kelp_field_nrep *r, double now, const kelp_field_sink *out);

/* ------------------------------------------------------------------ pHostInfo */

#define KELP_HOSTINFO_MAX_ADDRS 16

/** One address found on this host: its source label (LINUX_ETHERNET, LINUX_WIFI, or the
 *  interface name upper-cased) and the dotted quad. */
typedef struct kelp_hostinfo_addr {
    char source[32];
    char ip[16];
    char ifname[16];
} kelp_hostinfo_addr;

typedef struct kelp_field_hostinfo_cfg {
    char community[KELP_MAX_NAME];
    double port_db;                /**< ServerPort (0: unknown) */
    double warp;                   /**< MOOSTimeWarp */
    char default_ip[64];           /**< DEFAULT_HOSTIP: when nothing is found (default "localhost") */
    char force_ip[64];             /**< DEFAULT_HOSTIP_FORCE: always this ("" none) */
    char prefer_if[16];            /**< PREFER_INTERFACE: its address wins ("" none) */
} kelp_field_hostinfo_cfg;

typedef struct kelp_field_hostinfo {
    kelp_field_hostinfo_cfg cfg;
    kelp_hostinfo_addr addr[KELP_HOSTINFO_MAX_ADDRS];
    unsigned naddr;
    double port_udp;               /**< from PMB_UDP_LISTEN (0: unknown) */
    char iroutes[256];             /**< from PSHARE_INPUT_SUMMARY ("" unknown) */
    bool redetect;                 /**< HOST_INFO_REQUEST arrived: the edge should look again */
    bool post_due;
    unsigned long posts, requests;
    char best[64];                 /**< the last PHI_HOST_IP */
} kelp_field_hostinfo;

void kelp_field_hostinfo_cfg_default(kelp_field_hostinfo_cfg *c);
void kelp_field_hostinfo_init(kelp_field_hostinfo *h, const kelp_field_hostinfo_cfg *cfg);
/** The interfaces' addresses as the edge found them (name, dotted quad), in any order: the
 *  loopback (127.*) and malformed quads are dropped; ethernet-like names (eth*, en*) are
 *  LINUX_ETHERNET, wireless ones (wlan*, wl*) LINUX_WIFI, others their name upper-cased;
 *  the list is ordered ethernet, wifi, others (stable), an address once. A post is due. */
void kelp_field_hostinfo_set(kelp_field_hostinfo *h, const char *const *ifnames, const char *const *ips, unsigned n);
/** HOST_INFO_REQUEST (any value: look again, post again), PMB_UDP_LISTEN (port),
 *  PSHARE_INPUT_SUMMARY. @return 1 used, 0 not ours, <0 bad value. */
int kelp_field_hostinfo_mail(kelp_field_hostinfo *h, const char *var, bool is_string, const char *sval, double dval);
/** When a post is due: PHI_HOST_IP, PHI_HOST_IP_ALL, PHI_HOST_IP_VERBOSE, PHI_HOST_PORT_DB
 *  and PHI_HOST_PORT (the seed's name), PHI_HOST_PORT_UDP when known, and PHI_HOST_INFO
 *  "community=..,hostip=..,port_db=..[,port_udp=..],timewarp=..[,pshare_iroutes=..]".
 *  @return 1 posted, 0 nothing due. */
int kelp_field_hostinfo_iterate(kelp_field_hostinfo *h, const kelp_field_sink *out);

/* ------------------------------------------------------------------ uFldNodeBroker / uFldShoreBroker */

#define KELP_BROKER_MAX_TRY 16      /**< TRY_SHORE_HOST entries, valid and invalid (node) */
#define KELP_BROKER_MAX_BRIDGES 32  /**< BRIDGE entries (node); BRIDGE + expanded QBRIDGE (shore) */
#define KELP_BROKER_MAX_NODES 64    /**< vehicles one shore broker tracks */
#define KELP_BROKER_MAX_VNODES 16   /**< try_vnode routes (shore) */
#define KELP_BROKER_LINE 128        /**< an invalid TRY_SHORE_HOST line kept for the report */
#define KELP_BROKER_MSG 512         /**< one PMB_REGISTER / ping / ack value */
#define KELP_BROKER_STALE 10.0      /**< s without a ping before a vehicle is stale (shore) */

/** A host record (ufield.md 1.3): PHI_HOST_INFO, NODE_BROKER_PING or NODE_BROKER_ACK. Keys
 *  are read case-insensitively with the synonyms host/hostip/host_ip/ip, port/port_db,
 *  time_warp/timewarp; without port_udp, the port of the first host:port of a 24.8
 *  pshare_iroutes ("10.0.0.5:9200&multicast_8") is taken. Zero / "" means absent. */
typedef struct kelp_broker_host {
    char community[KELP_MAX_NAME];
    char host[KELP_MAX_NAME];
    unsigned port_db, port_udp;
    double warp;                       /**< time_warp (have_warp) */
    bool have_warp;
    double time;                       /**< time= (have_time) */
    bool have_time;
    char keyword[KELP_MAX_NAME];
    char status[KELP_MAX_NAME];        /**< an ack's status= ("" none) */
} kelp_broker_host;

/** Parse a host record. @return 0; KELP_ERR_PARSE (not key=value pairs, a bad number or
 *  port) or KELP_ERR_RANGE (a value too long) with *why. Completeness is separate. */
KELP_MUST_CHECK int kelp_broker_host_parse(const char *s, kelp_broker_host *h, const char **why);
/** Complete: community, host and port_udp (seed 2.2). */
bool kelp_broker_host_complete(const kelp_broker_host *h);

/** A bridge to request: local src (macros $V $v $N on the shore) and the remote alias. */
typedef struct kelp_broker_bridge {
    char src[KELP_MAX_NAME], alias[KELP_MAX_NAME];
} kelp_broker_bridge;

/** A candidate shoreside: its bridge's UDP address and community ("" unknown). */
typedef struct kelp_broker_try {
    char host[KELP_MAX_NAME], community[KELP_MAX_NAME];
    unsigned port;
} kelp_broker_try;

/** Parse one TRY_SHORE_HOST: "host_ip=H, port_udp=P[, community=C]" (hostip too) or 24.8's
 *  "pshare_route=H:P". A multicast_N route is KELP_ERR_UNSUPPORTED (kelp-bridge is unicast);
 *  anything else missing or malformed KELP_ERR_PARSE; *why says which. */
KELP_MUST_CHECK int kelp_broker_try_parse(const char *s, kelp_broker_try *t, const char **why);
/** Parse one BRIDGE: "src=V[, alias=A]" (alias defaults to src). */
KELP_MUST_CHECK int kelp_broker_bridge_parse(const char *s, kelp_broker_bridge *b, const char **why);

typedef struct kelp_field_nbroker_cfg {
    char keyword[KELP_MAX_NAME];              /**< KEYWORD ("" none) */
    kelp_broker_try tryh[KELP_BROKER_MAX_TRY];/**< valid TRY_SHORE_HOSTs, config order */
    unsigned ntry;
    char bad_try[KELP_BROKER_MAX_TRY][KELP_BROKER_LINE]; /**< invalid lines, as written */
    const char *bad_why[KELP_BROKER_MAX_TRY];  /**< why each is invalid (static text) */
    bool bad_multicast[KELP_BROKER_MAX_TRY];   /**< a 24.8 multicast route: valid there, not here */
    unsigned nbad_try;
    kelp_broker_bridge bridge[KELP_BROKER_MAX_BRIDGES]; /**< BRIDGE, config order */
    unsigned nbridges;
    double warp;                               /**< MOOSTimeWarp (1) */
    double retry;                              /**< RETRY_INTERVAL: s without an ack before the ping
                                                    registrations are posted again (10) */
    bool auto_realmcast, auto_appcast, auto_pshare_vars; /**< 24.8 AUTO_BRIDGE_* (false) */
} kelp_field_nbroker_cfg;

typedef struct kelp_field_nbroker {
    kelp_field_nbroker_cfg cfg;
    kelp_broker_host node;                     /**< the last complete PHI_HOST_INFO */
    bool have_node;
    kelp_broker_host shore;                    /**< the shore of the last valid ack */
    bool have_shore;
    bool bridged;                              /**< BRIDGEs registered to `shore` */
    bool routes_posted;                        /**< ping registrations posted at least once */
    double routes_at, last_ack;                /**< times (-1 never) */
    unsigned long iterations, ok_phi, bad_phi, phi_changes, registers, pings, ok_ack, bad_ack;
    char last_register[KELP_BROKER_MSG];
} kelp_field_nbroker;

/** Defaults: no keyword, no try hosts, no bridges, warp 1, retry 10 s, auto bridges off. */
void kelp_field_nbroker_cfg_default(kelp_field_nbroker_cfg *cfg);
/** One block parameter: KEYWORD, TRY_SHORE_HOST (an invalid one is kept for the report and
 *  is still taken), BRIDGE, RETRY_INTERVAL, AUTO_BRIDGE_REALMCAST, AUTO_BRIDGE_APPCAST,
 *  AUTO_BRIDGE_PSHARE_VARS. @return 1 taken, 0 not its key, <0 with *why. */
KELP_MUST_CHECK int kelp_field_nbroker_config(kelp_field_nbroker_cfg *cfg, const char *key, const char *val,
                                              const char **why);
/** Start: the AUTO_BRIDGE_* bridges are appended to the BRIDGE list. */
void kelp_field_nbroker_init(kelp_field_nbroker *b, const kelp_field_nbroker_cfg *cfg);
/** PHI_HOST_INFO, NODE_BROKER_ACK, TRY_SHORE_HOST, then NULL. */
const char *kelp_field_nbroker_subscription(unsigned i);
/** One mail at `now`. PHI_HOST_INFO (complete: stored, a change counted; else BAD);
 *  NODE_BROKER_ACK (invalid when incomplete, of another time warp, with a keyword other than
 *  ours when both are set, or a status other than ok; valid: the shore is stored and, for a
 *  new shore or after RETRY_INTERVAL of silence, every BRIDGE is registered to it);
 *  TRY_SHORE_HOST (24.8: a try host added at run time). @return 1 used, 0 not ours, <0 bad. */
int kelp_field_nbroker_mail(kelp_field_nbroker *b, const char *var, bool is_string, const char *sval, double now,
                            const kelp_field_sink *out);
/** Iterate: once the host info is complete, the ping registrations (one PMB_REGISTER per
 *  valid try host; again every RETRY_INTERVAL while no ack is heard), then one
 *  NODE_BROKER_PING. @return the number of posts. */
int kelp_field_nbroker_iterate(kelp_field_nbroker *b, double now, const kelp_field_sink *out);
/** The terminal report (seed Listing 3) into buf. @return 0, or KELP_ERR_NOSPACE (truncated). */
KELP_MUST_CHECK int kelp_field_nbroker_report(const kelp_field_nbroker *b, char *buf, size_t cap);

typedef struct kelp_field_sbroker_cfg {
    char keyword[KELP_MAX_NAME];                        /**< KEYWORD ("" none) */
    kelp_broker_bridge bridge[KELP_BROKER_MAX_BRIDGES]; /**< BRIDGE and QBRIDGE, config order */
    unsigned nbridges;
    kelp_broker_try vnode[KELP_BROKER_MAX_VNODES];      /**< 24.8 try_vnode routes */
    unsigned nvnodes;
    double warp;                                        /**< MOOSTimeWarp (1) */
    bool warn_stale;                                    /**< WARNING_ON_STALE (false) */
    bool auto_realmcast, auto_appcast, auto_mhash;      /**< 24.8 AUTO_BRIDGE_* (false) */
} kelp_field_sbroker_cfg;

/** One vehicle as the shore knows it. */
typedef struct kelp_broker_node {
    kelp_broker_host rec;                 /**< its last ping */
    char status[KELP_MAX_NAME];           /**< ok, timewarp (<shore>!=<node>), keyword, invalid */
    double last_ping, skew;
    unsigned index;                       /**< $N: 1-based order of first acceptance (0 never) */
    bool bridged;                         /**< bridges registered to bridged_host:bridged_port */
    char bridged_host[KELP_MAX_NAME];
    unsigned bridged_port;
    bool stale;
    unsigned long pings, acks;
} kelp_broker_node;

typedef struct kelp_field_sbroker {
    kelp_field_sbroker_cfg cfg;
    kelp_broker_host shore;               /**< the last PHI_HOST_INFO */
    bool have_shore;                      /**< complete */
    kelp_broker_node node[KELP_BROKER_MAX_NODES];
    unsigned nnodes, naccepted;
    double vnode_reg_at, vnode_post_at, count_at; /**< -1 never */
    unsigned count_posted;
    unsigned long iterations, phi, pings, bad_pings, early_pings, full, acks, registers;
    char last_register[KELP_BROKER_MSG];
} kelp_field_sbroker;

/** Defaults: no keyword, no bridges, warp 1, no stale warnings, auto bridges off. */
void kelp_field_sbroker_cfg_default(kelp_field_sbroker_cfg *cfg);
/** One block parameter: BRIDGE ("src=V[, alias=A]"), QBRIDGE ("X[, Y ...]": X_ALL->X and
 *  X_$V->X each), KEYWORD, TRY_VNODE ("[route=]ip[:port]", port 9200), WARNING_ON_STALE,
 *  AUTO_BRIDGE_REALMCAST (QBRIDGE REALMCAST_REQ), AUTO_BRIDGE_APPCAST (QBRIDGE APPCAST_REQ),
 *  AUTO_BRIDGE_MHASH (BRIDGE src=MISSION_HASH). A bridge already listed is not added twice.
 *  @return 1 taken, 0 not its key, <0 with *why. */
KELP_MUST_CHECK int kelp_field_sbroker_config(kelp_field_sbroker_cfg *cfg, const char *key, const char *val,
                                              const char **why);
void kelp_field_sbroker_init(kelp_field_sbroker *s, const kelp_field_sbroker_cfg *cfg);
/** PHI_HOST_INFO, NODE_BROKER_PING, then NULL. */
const char *kelp_field_sbroker_subscription(unsigned i);
/** One mail at `now`. NODE_BROKER_PING (seed 3.4): counted; ignored until our own host info
 *  is complete; the vehicle (by community, case-insensitive) is recorded with its status and
 *  skew; accepted: on first acceptance it gets the next $N, and whenever its bridges are not
 *  registered to its current host:port_udp (first time, or it moved) the ack bridge
 *  (NODE_BROKER_ACK_<V> -> NODE_BROKER_ACK) and every BRIDGE are registered; then the ack
 *  NODE_BROKER_ACK_<V> and NODE_BROKER_VACK are posted. @return 1 used, 0 not ours, <0 bad. */
int kelp_field_sbroker_mail(kelp_field_sbroker *s, const char *var, bool is_string, const char *sval, double now,
                            const kelp_field_sink *out);
/** Iterate: stale warnings, UFSB_NODE_COUNT (on change, else every 30 s), try_vnode
 *  registrations (every 30 s) and TRY_SHORE_HOST (every 10 s). @return the number of posts. */
int kelp_field_sbroker_iterate(kelp_field_sbroker *s, double now, const kelp_field_sink *out);
/** The terminal report (seed Listing 6) at `now` into buf. @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_field_sbroker_report(const kelp_field_sbroker *s, double now, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
