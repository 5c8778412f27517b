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
#include <kelp/rng.h>
#include <kelp/util.h>

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
    bool dep_key;                          /**< depth written as DEP= (default; DEPTH_KEY = DEPTH: DEPTH=) */
    bool seed_format;                      /**< the 2012 uField layout (fixed decimals) instead of 24.8's */
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
    kelp_rng rng;
    unsigned long posted, alt_posted, nav_mail, bad_mail, extrap_skipped;
    char last[KELP_NODEREPORT_MAX_LEN];    /**< the last report posted */
    struct {                               /* workspace of one call (keeps the stack under 1 KB) */
        kelp_nodereport main, alt;         /**< the report being posted; the alternate solution's */
        char extra[KELP_NODEREPORT_MAX_LEN / 2], text[KELP_NODEREPORT_MAX_LEN];
        char json[KELP_NODEREPORT_MAX_LEN + 128];
    } ws;
} kelp_field_nrep;

/** Defaults: name = community, type UUV, output NODE_REPORT_LOCAL, prefix NAV, nohelm 5 s,
 *  extrapolation thresholds 0.25 m / 1 degree / 5 s, platform report PLATFORM_REPORT_LOCAL. */
void kelp_field_nrep_cfg_default(kelp_field_nrep_cfg *cfg, const char *community);
/** Add a plat_report_input ("VAR, gap=1, alias=A") or a rider ("var=V, policy=always|updated,
 *  rfld=F, prec=3"). @return@return 0, or <0 (reason in d). */
KELP_MUST_CHECK int kelp_field_nrep_add_plat(kelp_field_nrep_cfg *cfg, const char *spec, kelp_diag *d);
KELP_MUST_CHECK int kelp_field_nrep_add_rider(kelp_field_nrep_cfg *cfg, const char *spec, kelp_diag *d);
/** CROSS_FILL_POLICY value: literal, fill-empty, use-latest, global, local ('_' for '-' too). */
KELP_MUST_CHECK int kelp_field_nrep_parse_fill(const char *s, kelp_nrep_fill *out);
/** Start with cfg at `now`. KELP_ERR_ARG when a text field holds ',' or '=' or the name is empty. */
KELP_MUST_CHECK int kelp_field_nrep_init(kelp_field_nrep *r, const kelp_field_nrep_cfg *cfg, kelp_time now);
/** The variables to subscribe to, one per call (i from 0) until NULL. */
const char *kelp_field_nrep_subscription(const kelp_field_nrep *r, unsigned i);
/** One mail. Returns 1 when it was used, 0 when not for this tool, <0 (and a warning) when
 *  bad (a navigation value that is not a finite number). */
KELP_MUST_CHECK int kelp_field_nrep_mail(kelp_field_nrep *r, const char *var, bool is_string, const char *sval, double dval,
                                         const kelp_field_sink *out);
/** Iterate at `now` (pNodeReporter's rule): a report when the navigation is valid (a
 *  position, speed and heading; or the grace period is over) and the blackout interval has
 *  passed, unless a receiver could extrapolate it. The first goes to <OUT>_FIRST too; each is
 *  followed by PNR_POST_GAP; with ALT_NAV_PREFIX, a report of the alternate solution (its own
 *  name and group) follows while that solution had mail in the last 5 s. MODE is NOHELM-EVER / NOHELM-<s> without helm mail for
 *  nohelm_threshold s, else the helm state, or the helm's modes in DRIVE.
 *  Returns 1 when a report was published, 0 when none was due, <0 on a formatting error. */
KELP_MUST_CHECK int kelp_field_nrep_iterate(kelp_field_nrep *r, kelp_time now, const kelp_field_sink *out);

/* ------------------------------------------------------------------ pHostInfo */

#define KELP_BROKER_IROUTES 192     /**< a pshare_iroutes / hostip_alts value */

/** A host record (pHostInfo's, as the brokers exchange it): PHI_HOST_INFO, NODE_BROKER_PING or NODE_BROKER_ACK. Keys
 *  are read case-insensitively with the synonyms host/hostip/host_ip/ip, port/port_db,
 *  time_warp/timewarp; without port_udp, the port of the first host:port of a 24.8
 *  pshare_iroutes ("10.0.0.5:9200&multicast_8") is taken. Zero / "" means absent. */
typedef struct kelp_field_broker_host {
    char community[KELP_MAX_NAME];
    char host[KELP_MAX_NAME];
    unsigned port_db, port_udp;
    double warp;                       /**< time_warp (have_warp) */
    bool have_warp;
    double time;                       /**< time= (have_time) */
    bool have_time;
    char keyword[KELP_MAX_NAME];
    char status[KELP_MAX_NAME];        /**< an ack's status= ("" none) */
    /* 24.8's HostRecord fields, kept as written */
    char iroutes[KELP_BROKER_IROUTES]; /**< pshare_iroutes ("" none) */
    char alts[KELP_BROKER_IROUTES];    /**< hostip_alts ("" none) */
    char warp_s[24];                   /**< timewarp as written ("" none) */
    char key[24];                      /**< key= (a ping's try-host index) */
    bool have_port_db;
    bool have_port_udp;                /**< 24.8's record has port_udp: given, or the port of a
                                            single-route pshare_iroutes ("10.0.0.5:9200") */
} kelp_field_broker_host;

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
    char force_ip[64];             /**< DEFAULT_HOSTIP_FORCE: always this, and the only address
                                        posted (USER_HARD_CONFIGURED=ip) ("" none) */
    char prefer_if[16];            /**< PREFER_INTERFACE: its address wins, the name in any case;
                                        "wifi": the wireless interface's ("" none) */
} kelp_field_hostinfo_cfg;

typedef struct kelp_field_hostinfo {
    kelp_field_hostinfo_cfg cfg;
    kelp_hostinfo_addr addr[KELP_HOSTINFO_MAX_ADDRS];
    unsigned naddr;
    double port_udp;               /**< from PMB_UDP_LISTEN (0: unknown) */
    char iroutes[256];             /**< from PSHARE_INPUT_SUMMARY ("" unknown) */
    bool redetect;                 /**< HOST_INFO_REQUEST arrived: the edge should look again */
    bool post_due;                 /**< post at the next iteration (the first, after HOST_INFO_REQUEST) */
    unsigned long posts, requests, iterations;
    char best[64];                 /**< the last PHI_HOST_IP */
    /* workspace of one call (keeps the stack under 1 KB) */
    char ws_all[KELP_HOSTINFO_MAX_ADDRS * 17 + 1], ws_verbose[KELP_HOSTINFO_MAX_ADDRS * 50 + 1], ws_info[1024];
    char ws_spec[1024];
    kelp_field_broker_host ws_rec;
} kelp_field_hostinfo;

void kelp_field_hostinfo_cfg_default(kelp_field_hostinfo_cfg *c);
void kelp_field_hostinfo_init(kelp_field_hostinfo *h, const kelp_field_hostinfo_cfg *cfg);
/** The interfaces' addresses as the edge found them (name, dotted quad), in any order: the
 *  loopback (127.*) and malformed quads are dropped; ethernet-like names (eth*, en*) are
 *  LINUX_ETHERNET, wireless ones (wlan*, wl*) LINUX_WIFI, others their name upper-cased;
 *  the list is ordered ethernet, wifi, others (stable), an address once. A post is due. */
void kelp_field_hostinfo_set(kelp_field_hostinfo *h, const char *const *ifnames, const char *const *ips, unsigned n);
/** HOST_INFO_REQUEST (any value: look again, post again), PMB_UDP_LISTEN (port),
 *  PSHARE_INPUT_SUMMARY ("localhost:9200:udp,1.2.3.4:2000:multicast_23" is kept as 24.8 keeps
 *  it: "localhost:9200&multicast_23"). @return 1 used, 0 not ours, <0 bad value. */
KELP_MUST_CHECK int kelp_field_hostinfo_mail(kelp_field_hostinfo *h, const char *var, bool is_string, const char *sval, double dval);
/** One iteration; a post at the first, after HOST_INFO_REQUEST and every tenth (24.8):
 *  PHI_HOST_IP ("localhost", or DEFAULT_HOSTIP, when nothing was found), PHI_HOST_IP_ALL and
 *  PHI_HOST_IP_VERBOSE (both "" when nothing was found), PHI_HOST_PORT_DB, PHI_HOST_PORT_UDP
 *  when PMB_UDP_LISTEN told it (the uField Toolbox manual's pMOOSBridge; the ports as strings), and
 *  PHI_HOST_INFO as 24.8's host record: community, hostip, port_db, port_udp (PMB_UDP_LISTEN's,
 *  or a single pshare route's), pshare_iroutes, hostip_alts (PHI_HOST_IP_ALL without hostip),
 *  timewarp (one decimal, trailing zeros dropped), "localhost" anywhere read as this host's
 *  address. @return 1 posted, 0 nothing due. */
int kelp_field_hostinfo_iterate(kelp_field_hostinfo *h, const kelp_field_sink *out);
/** 24.8's report (the PHI_HOST_* lines) into buf. @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_field_hostinfo_report(const kelp_field_hostinfo *h, char *buf, size_t cap);

/* ------------------------------------------------------------------ uFldNodeComms */
/* The shoreside relay of node reports and node messages between vehicles, as MOOS-IvP 24.8's
 * uFldNodeComms does it (the uField Toolbox manual (MOOS-IvP 12.2) chapter 5 plus min_rpt_interval, msg_groups,
 * drop_percentage, shared_node_reports, MEDIATED_MESSAGE / ACK_MESSAGE, UNC_COMMS_RANGE...):
 *
 * - a report goes through 24.8's contact ledger (kelp_nodereport_ledger: type, length, COG;
 *   LAT/LON from X/Y with the datum, or the reverse) and is relayed re-serialised as 24.8's
 *   node record (kelp_nodereport_format_record), to NODE_REPORT_<NAME in upper case>;
 * - vehicles are named as they report (case kept: "abe" and "ABE" are two vehicles), visited
 *   in name order (byte order), as 24.8's maps are;
 * - a report reaches D from S when both have SPD and HDG and their range is <= CRITICAL_RANGE;
 *   else when D's last report came less than STALE_TIME ago, the range is <= COMMS_RANGE *
 *   stealth(S) * earange(D) (COMMS_RANGE < 0: any; 0: none), the groups match (GROUPS), the
 *   random drop spares it and MIN_RPT_INTERVAL has passed since the last S -> D relay;
 * - a message is re-serialised (src_app= added from the poster, 24.8's field order and number
 *   format); each source's messages go out in arrival order, each only MIN_MSG_INTERVAL after
 *   the source's previous one, delivered or not ("Too Recent" otherwise); dest_node (a colon
 *   list, or all / ALL) and dest_group match names and groups exactly; a destination gets it
 *   when its report is valid and fresh by its TIME ("Missing Info"), and in range ("Range Too
 *   Far"); random drops are not counted;
 * - ACK_MESSAGE "src=..,dest=..,id=.." goes to ACK_MESSAGE_<dest as written> as
 *   "id=.., src=.., dest=..";
 * - a vehicle not heard from for 20 x STALE_TIME is forgotten ("Stale Vehicles").
 *
 * Relaying one node report costs work proportional to the sender's neighbours: vehicles sit
 * in a uniform grid (cells of max(COMMS_RANGE, CRITICAL_RANGE) metres, hashed into
 * KELP_NCOMMS_GRID_BUCKETS lists), and a sender scans the cells within its largest effective
 * range, max(CRITICAL_RANGE, COMMS_RANGE * stealth * largest earange), then visits those
 * receivers in name order. With no range limit (COMMS_RANGE < 0), or a window wider than the
 * fleet, it visits the fleet in name order.
 *
 * Size: sizeof(kelp_field_ncomms) is 3,077,656 bytes (x86-64) with the defaults below: 2048
 * vehicles with a 640-byte report each, 65536 pair stamps (1 MB), 64 pending messages of
 * 2 KB; place it statically or on the heap, not on a small stack. */

#ifndef KELP_NCOMMS_MAX_NODES
#define KELP_NCOMMS_MAX_NODES 2048       /**< vehicles known (reports, messages or stealth/earange) */
#endif
#ifndef KELP_NCOMMS_GRID_BUCKETS
#define KELP_NCOMMS_GRID_BUCKETS 4096    /**< grid cell lists (a power of two) */
#endif
#ifndef KELP_NCOMMS_NAME_SLOTS
#define KELP_NCOMMS_NAME_SLOTS 4096      /**< name hash slots (a power of two > 1.5 x nodes) */
#endif
#ifndef KELP_NCOMMS_MAX_MSGS
#define KELP_NCOMMS_MAX_MSGS 64          /**< node/ack messages pending between iterations */
#endif
#ifndef KELP_NCOMMS_MSG_LEN
#define KELP_NCOMMS_MSG_LEN 2048         /**< bytes of a stored message, with NUL */
#endif
#ifndef KELP_NCOMMS_PAIR_SLOTS
#define KELP_NCOMMS_PAIR_SLOTS 65536     /**< min_rpt_interval stamps per (source, receiver) */
#endif
#define KELP_NCOMMS_REPORT_LEN (KELP_NODEREPORT_MAX_LEN + 128) /**< a relayed report: the input and COG, LAT, LON... */
#define KELP_NCOMMS_MAX_FACTORS 32       /**< STEALTH / EARANGE lines of the block */
#define KELP_NCOMMS_RECENT_IDS 100       /**< message ids remembered for msg_repeat_color */
KELP_STATIC_ASSERT((KELP_NCOMMS_GRID_BUCKETS & (KELP_NCOMMS_GRID_BUCKETS - 1)) == 0, "grid buckets: a power of two");
KELP_STATIC_ASSERT((KELP_NCOMMS_NAME_SLOTS & (KELP_NCOMMS_NAME_SLOTS - 1)) == 0, "name slots: a power of two");
KELP_STATIC_ASSERT((KELP_NCOMMS_PAIR_SLOTS & (KELP_NCOMMS_PAIR_SLOTS - 1)) == 0, "pair slots: a power of two");
KELP_STATIC_ASSERT(KELP_NCOMMS_NAME_SLOTS >= KELP_NCOMMS_MAX_NODES + KELP_NCOMMS_MAX_NODES / 2, "name slots too few");
KELP_STATIC_ASSERT(KELP_NCOMMS_MAX_NODES < 32768, "node index must fit 15 bits (pair keys)");

/** Why a message was not delivered (the report's "Total Blocked Msgs" lines, 24.8's). */
typedef enum kelp_ncomms_block {
    KELP_NCOMMS_BLK_INVALID = 0,  /**< "Invalid" (24.8 refuses an invalid message at mail: never counted) */
    KELP_NCOMMS_BLK_NOINFO,       /**< "Missing Info": the destination's report is invalid or old by its TIME */
    KELP_NCOMMS_BLK_STALE,        /**< "Stale Receiver": an ack whose source or destination is old */
    KELP_NCOMMS_BLK_TOO_RECENT,   /**< "Too Recent": within MIN_MSG_INTERVAL of the source's last one */
    KELP_NCOMMS_BLK_TOO_LONG,     /**< "Msg Too Long": longer than MAX_MSG_LENGTH */
    KELP_NCOMMS_BLK_TOO_FAR,      /**< "Range Too Far": range > COMMS_RANGE * stealth(src) * earange(dest) */
    KELP_NCOMMS_BLK_N
} kelp_ncomms_block;

typedef struct kelp_ncomms_factor {
    char vname[KELP_NODEREPORT_MAX_FIELD];
    double stealth, earange;      /**< 0: not set by this line */
} kelp_ncomms_factor;

typedef struct kelp_field_ncomms_cfg {
    double comms_range;           /**< COMMS_RANGE m (100); < 0 no limit ("nolimit"), 0 nothing */
    double critical_range;        /**< CRITICAL_RANGE m (30): reports shared within it */
    double stale_time;            /**< STALE_TIME s (5); < 0 never stale; 20 x: forgotten */
    double min_msg_interval;      /**< MIN_MSG_INTERVAL s (30) between messages of one source */
    double min_rpt_interval;      /**< MIN_RPT_INTERVAL s (-1 off) between reports S -> D */
    unsigned long max_msg_length; /**< MAX_MSG_LENGTH characters (1000); 0 unlimited */
    bool verbose;                 /**< VERBOSE (true): the report */
    bool debug;                   /**< DEBUG (false) */
    bool groups;                  /**< GROUPS (false): reports only within a group */
    bool msg_groups;              /**< MSG_GROUPS (false): messages only within a group */
    bool view_node_rpt_pulses;    /**< VIEW_NODE_RPT_PULSES (true) */
    double pulse_duration;        /**< PULSE_DURATION s (10); <= 0 no pulses */
    double drop_pct;              /**< DROP_PERCENTAGE [0,100] (0) of relays dropped */
    double share_interval;        /**< SHARED_NODE_REPORTS: NODE_REPORT_UNC every s of real
                                       time (true 0.1, false -1 off: the default) */
    double warp;                  /**< MOOSTimeWarp (for share_interval) */
    kelp_geo geo;                 /**< LatOrigin/LongOrigin: LAT,LON from X,Y and the reverse */
    bool have_geo;                /**< false: the datum 0,0 (as 24.8 without LatOrigin/LongOrigin) */
    char msg_color[KELP_VIEW_MAX_FIELD];        /**< MSG_COLOR (white); off/invisible: none */
    char msg_repeat_color[KELP_VIEW_MAX_FIELD]; /**< MSG_REPEAT_COLOR (light_green) */
    kelp_ncomms_factor factor[KELP_NCOMMS_MAX_FACTORS]; /**< STEALTH / EARANGE lines */
    unsigned nfactor;
    uint64_t seed;                /**< drop_percentage draws */
    char ws_val[256];             /**< workspace: the value being read by kelp_field_ncomms_config */
} kelp_field_ncomms_cfg;

/** One vehicle (or a name a message or a STEALTH/EARANGE line gave). */
typedef struct kelp_ncomms_node {
    char name[KELP_NODEREPORT_MAX_FIELD];   /**< as it reports (NODE_REPORT_<upper case>) */
    char group[KELP_NODEREPORT_MAX_FIELD];  /**< as it reports ("" none) */
    char report[KELP_NCOMMS_REPORT_LEN];    /**< the last report, re-serialised (24.8's node record) */
    double rpt_time;                        /**< TIME of the last report */
    double stealth, earange;
    double msg_time, ack_time, share_time;  /**< last message / ack sent on, NODE_REPORT_UNC */
    bool has_msg_time, has_ack_time, has_share_time;
    bool valid;                             /**< the last report has SPD and HDG */
    unsigned long rpts_rcvd, rpts_sent, msgs_rcvd, msgs_sent, acks_rcvd, acks_sent;
    unsigned long mark;                     /**< message de-duplication stamp */
    bool updated;                           /**< a report since the last iteration */
} kelp_ncomms_node;

typedef struct kelp_ncomms_hot {
    double x, y, t_recv;
    int32_t cx, cy;                         /**< grid cell */
    int32_t next, prev;                     /**< bucket list (-1 end) */
    int32_t bucket;                         /**< -1: not in the ledger (no report, or forgotten) */
} kelp_ncomms_hot;

typedef struct kelp_ncomms_msg {
    char text[KELP_NCOMMS_MSG_LEN];         /**< re-serialised (NodeMessage / AckMessage spec) */
    uint16_t src;                           /**< its source's node */
    bool is_ack;
} kelp_ncomms_msg;

typedef struct kelp_ncomms_pair {
    uint32_t key;                           /**< (src+1) << 16 | (dst+1); 0 empty */
    double t;
} kelp_ncomms_pair;

typedef struct kelp_field_ncomms {
    kelp_field_ncomms_cfg cfg;
    double comms_range;                     /**< current (UNC_COMMS_RANGE) */
    double drop_pct;                        /**< current (UNC_DROP_PCT) */
    bool view_rpt_pulses;                   /**< current (UNC_VIEW_NODE_RPT_PULSES) */
    double share_interval;                  /**< current (UNC_SHARED_NODE_REPORTS) */
    /* private */
    kelp_ncomms_node node[KELP_NCOMMS_MAX_NODES];
    kelp_ncomms_hot hot[KELP_NCOMMS_MAX_NODES];
    uint16_t sorted[KELP_NCOMMS_MAX_NODES]; /**< every node, in name order */
    unsigned nnodes, nreporting;
    int16_t name_slot[KELP_NCOMMS_NAME_SLOTS];  /**< node index + 1, 0 empty */
    int32_t grid[KELP_NCOMMS_GRID_BUCKETS];     /**< first node of each bucket, -1 empty */
    double cell;                            /**< grid cell size m */
    double max_earange;                     /**< over all vehicles */
    uint16_t upd[KELP_NCOMMS_MAX_NODES];    /**< vehicles updated since the last iteration */
    unsigned nupd;
    kelp_ncomms_msg msg[KELP_NCOMMS_MAX_MSGS];
    unsigned nmsg;
    kelp_ncomms_pair pair[KELP_NCOMMS_PAIR_SLOTS];
    char recent_id[KELP_NCOMMS_RECENT_IDS][KELP_NODEREPORT_MAX_FIELD]; /**< newest first */
    unsigned nrecent;
    unsigned long mark;
    kelp_rng rng;
    kelp_time now;                          /**< time of the last iteration */
    kelp_time start;                        /**< time of the first mail or iteration */
    bool started;
    /* counters */
    unsigned long rpts_rcvd, rpts_sent, rpts_bad, rpts_full, stale_dropped;
    unsigned long msgs_rcvd, msgs_sent, acks_rcvd, acks_sent, msgs_queue_full, pair_full;
    unsigned long blocked[KELP_NCOMMS_BLK_N];
    unsigned long scanned;                  /**< candidate receivers examined (bench) */
    unsigned long pulses;
    uint16_t ws_idx[KELP_NCOMMS_MAX_NODES]; /**< workspace: receivers of one sender, messages by source */
    kelp_nodereport ws_rec;                 /**< workspace: the report being read */
    char ws_report[KELP_NCOMMS_REPORT_LEN]; /**< workspace: the report being re-serialised */
    kelp_diag diag;                         /**< workspace: why the last mail was refused */
    char ws_pulse[384];                     /**< workspace: a VIEW_COMMS_PULSE being built */
    char ws_line[256];                      /**< workspace: a warning or a report line */
} kelp_field_ncomms;

/** Defaults of 24.8 (comms 100, critical 30, stale 5, message interval 30, length 1000,
 *  verbose, report pulses on, duration 10, white / light_green, warp 1). */
void kelp_field_ncomms_cfg_default(kelp_field_ncomms_cfg *cfg);
/** One block parameter (key case-insensitive; a trailing ';' of the value is ignored):
 *  COMMS_RANGE (a number or nolimit), CRITICAL_RANGE, STALE_TIME, MIN_MSG_INTERVAL,
 *  MIN_RPT_INTERVAL, MAX_MSG_LENGTH, STEALTH, EARANGE ("vname=alpha, stealth=0.8"; repeat),
 *  GROUPS, MSG_GROUPS, VERBOSE, DEBUG, VIEW_NODE_RPT_PULSES, PULSE_DURATION,
 *  DROP_PERCENTAGE, SHARED_NODE_REPORTS (true, false or seconds), MSG_COLOR,
 *  MSG_REPEAT_COLOR. @return 1 taken, 0 not its key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_field_ncomms_config(kelp_field_ncomms_cfg *cfg, const char *key, const char *val,
                                             kelp_diag *d);
/** Start with cfg (copied). @return 0 or KELP_ERR_NOSPACE (more STEALTH/EARANGE vehicles
 *  than KELP_NCOMMS_MAX_NODES). */
KELP_MUST_CHECK int kelp_field_ncomms_init(kelp_field_ncomms *c, const kelp_field_ncomms_cfg *cfg);
/** The variables to subscribe to (24.8's), one per call (i from 0) until NULL. */
const char *kelp_field_ncomms_subscription(unsigned i);
/** One mail at `now` from the client `source` (the MOOS source: a message without src_app
 *  gets it; may be NULL): NODE_REPORT, NODE_REPORT_LOCAL, NODE_MESSAGE, MEDIATED_MESSAGE,
 *  ACK_MESSAGE (queued for the next iteration), UNC_STEALTH, UNC_EARANGE, UNC_COMMS_RANGE,
 *  UNC_DROP_PCT, UNC_VIEW_NODE_RPT_PULSES, UNC_SHARED_NODE_REPORTS. Returns 1 used, 0 not
 *  ours, <0 when the value is refused, with 24.8's run warning through out->warn ("Bad Mail:
 *  <VAR>", for a report with the reason: "Bad Mail: NODE_REPORT Missing timestamp."). */
KELP_MUST_CHECK int kelp_field_ncomms_mail(kelp_field_ncomms *c, const char *var, bool is_string, const char *sval, double dval,
                                           const char *source, kelp_time now, const kelp_field_sink *out);
/** Iterate at `now`: relay every report received since the last iteration (senders in name
 *  order; NODE_REPORT_UNC and RTE with SHARED_NODE_REPORTS), route the queued messages, then
 *  the acks (sources in name order), forget vehicles silent for 20 x STALE_TIME. @return the
 *  number of NODE_REPORT_* / NODE_MESSAGE_* / MEDIATED_MESSAGE_* / ACK_MESSAGE_* posts. */
unsigned long kelp_field_ncomms_iterate(kelp_field_ncomms *c, kelp_time now, const kelp_field_sink *out);
/** 24.8's report (Configuration, Node Report Summary, Node Message Summary) at `now` into buf
 *  (always terminated when cap > 0). @return 0 or KELP_ERR_NOSPACE (truncated). */
KELP_MUST_CHECK int kelp_field_ncomms_report(kelp_field_ncomms *c, kelp_time now, char *buf, size_t cap);
/** Index of a vehicle by its exact name, or -1. */
int kelp_field_ncomms_find(const kelp_field_ncomms *c, const char *name);

/* ------------------------------------------------------------------ NODE_MESSAGE */

/** A piece of the parsed string: p points into the text given to the parser (not
 *  NUL-terminated); n is 0 when absent or empty. */
typedef struct kelp_field_text {
    const char *p;
    size_t n;
} kelp_field_text;

/** One NODE_MESSAGE "src_node=alpha,dest_node=bravo,var_name=SPEED,double_val=2.5"
 *  (the uField Toolbox manual's), read as MOOS-IvP 24.8 reads it (string2NodeMessage): items cut at ','
 *  outside quotes and braces (parseStringQ: an unclosed quote or brace runs to the end), the
 *  key before the first '=' in any case, key and value blank-stripped, the last of a repeated
 *  key wins, unknown keys ignored. The 12.2 manual's spellings are read too: dest_name for dest_node,
 *  src_var for var_name (var_name wins when both are given), "dest_node;bravo". string_val
 *  loses its enclosing quotes once when string_val_quoted=true and once more if still quoted. */
typedef struct kelp_node_message {
    kelp_field_text src_node, src_app, src_bhv, dest_node, dest_group, var_name, string_val, color, ack_id;
    double double_val;
    bool has_string;             /**< a non-empty string_val is left: it is posted as a string */
    bool has_double;             /**< double_val= was given (double_val read as atof; 0 without) */
    bool string_quoted;          /**< string_val lost enclosing double quotes */
    bool string_val_quoted;      /**< string_val_quoted=true: the quotes were added to hide commas */
    bool ack;                    /**< ack=true */
} kelp_node_message;

/** Parse and validate s[0..len) as NodeMessage::valid() does: src_node, a destination
 *  (dest_node or dest_group) and a var_name are required, and not both a string_val (judged
 *  after string_val_quoted's stripping) and a double_val. Neither value is no error: 24.8 posts
 *  the double, 0. kelp refuses besides a var_name that is not a MOOS name (1..KELP_MAX_NAME-1
 *  printable characters, no space, ',', '=' or '"') or is NODE_MESSAGE (docs/CONFORMANCE.md).
 *  @param[out] m spans into s. @return 0, or KELP_ERR_PARSE (a short reason in d). */
KELP_MUST_CHECK int kelp_field_nodemsg_parse(const char *s, size_t len, kelp_node_message *m, kelp_diag *d);
/** Is `me` (case-insensitive) one of the colon-separated names of the message's dest_node? */
bool kelp_field_nodemsg_to(const kelp_node_message *m, const char *me);

/* ------------------------------------------------------------------ uFldMessageHandler */

#define KELP_UMH_MAX_FLAGS 8      /**< MSG_FLAG and BAD_MSG_FLAG entries, each */
#define KELP_UMH_FLAG_LEN 128     /**< bytes of a flag's value, with NUL */
#define KELP_UMH_MAX_SOURCES 32   /**< source nodes in the per-source table (least recent reused) */
#define KELP_UMH_LAST 5           /**< messages kept in each "last few" list */
#define KELP_UMH_WHY_LEN 48       /**< bytes of a kept reason (a copy of the diag's text) */
#define KELP_UMH_MSG_LEN 256      /**< bytes kept of a listed message, with NUL */
#define KELP_UMH_VAL_LEN 64       /**< bytes kept of a source's last value, with NUL */

/** A MSG_FLAG / BAD_MSG_FLAG "VAR=value": a number (MBUtils' isNumber) is posted as a double,
 *  anything else as a string after expanding $[CTR] / $(CTR) (messages received), $[GOOD_CTR]
 *  (well formed, rejected ones included) and $[BAD_CTR] (rejected), as MOOS-IvP 24.8 does. */
typedef struct kelp_umh_flag {
    char var[KELP_MAX_NAME];
    char sval[KELP_UMH_FLAG_LEN];
    double dval;
    bool is_string;
} kelp_umh_flag;

typedef struct kelp_field_umh_cfg {
    char community[KELP_MAX_NAME]; /**< this vehicle: dest_node must name it */
    bool verbose;                  /**< VERBOSE: the full terminal report (true) */
    bool strict;                   /**< STRICT_ADDRESSING: only dest_node naming us (false) */
    bool aux_app;                  /**< AUX_INFO = node+app: aux source "node+src_app" (node) */
    unsigned trunc;                /**< APPCAST_TRUNC_MSG: characters of a listed valid message (75; 0 all) */
    kelp_umh_flag msg_flag[KELP_UMH_MAX_FLAGS], bad_flag[KELP_UMH_MAX_FLAGS];
    unsigned nmsg_flag, nbad_flag;
} kelp_field_umh_cfg;

/** One sending node: messages posted, when the last arrived, its variable and value. */
typedef struct kelp_umh_source {
    char name[KELP_MAX_NAME];
    unsigned long total;
    double last;
    char var[KELP_MAX_NAME];
    char val[KELP_UMH_VAL_LEN];
} kelp_umh_source;

/** The last few messages of one kind, oldest first from `first`. */
typedef struct kelp_umh_list {
    char msg[KELP_UMH_LAST][KELP_UMH_MSG_LEN];
    char why[KELP_UMH_LAST][KELP_UMH_WHY_LEN]; /**< reason (invalid and rejected lists; "" none) */
    unsigned n, first;
} kelp_umh_list;

typedef struct kelp_field_umh {
    kelp_field_umh_cfg cfg;
    unsigned long total, valid, invalid, rejected, reports, summaries;
    double last_msg;                         /**< MOOS time of the last NODE_MESSAGE (-1 none) */
    kelp_umh_source src[KELP_UMH_MAX_SOURCES];
    unsigned nsrc;
    kelp_umh_list last_valid, last_invalid, last_rejected;
    char aux[2 * KELP_MAX_NAME];             /**< aux source of the last post (node or node+app) */
    bool posting;                            /**< set while the carried variable is published: the
                                                  sink posts it with `aux` as its MOOS source-aux */
    /* private */
    bool summary_due;
    unsigned long iter;                      /* iterations, for 24.8's summary on 1, 101, 201, ... */
    double last_summary;
    kelp_clock clock;                        /* the newest `now` seen (the time step rule) */
    char post[KELP_MAX_SVAL + 1];            /**< the string value being posted */
    kelp_diag diag;                          /**< workspace: why the last NODE_MESSAGE was invalid */
} kelp_field_umh;

/** Defaults: verbose, not strict, aux_info node, trunc 75. */
void kelp_field_umh_cfg_default(kelp_field_umh_cfg *c, const char *community);
/** One block parameter, read as MOOS-IvP 24.8's OnStartUp reads it: STRICT_ADDRESSING
 *  (true/false, yes/no, on/off, toggle), AUX_INFO (exactly node or node+app), APPCAST_TRUNC_MSG
 *  (a number read as atoi, below 0 is 0), MSG_FLAG and BAD_MSG_FLAG ("VAR=value" with 24.8's
 *  optional tags and [if] part, which its handler does not use; "clearall" empties the list);
 *  and kelp's VERBOSE.
 *  @return 1 taken, 0 not ours, <0 (reason in d). */
KELP_MUST_CHECK int kelp_field_umh_config(kelp_field_umh_cfg *c, const char *key, const char *val, kelp_diag *d);
void kelp_field_umh_init(kelp_field_umh *h, const kelp_field_umh_cfg *cfg);
/** NODE_MESSAGE (other variables: 0), as MOOS-IvP 24.8's handleMailNodeMessage: a valid one
 *  is counted valid and listed, and its source's row updated, before its address is looked
 *  at; dest_node must be this community exactly, "all" or "ALL", or absent (a dest_group
 *  message; refused when strict). Taken: the variable is posted (a string, or the double when
 *  no string is left) with `posting` set and the sender in `aux` (the app's sink posts it as
 *  the MOOS source-aux), then the MSG_FLAGs. Invalid: counted and listed with the reason, no
 *  flag. Rejected: counted and listed, then the BAD_MSG_FLAGs. A double is an invalid "".
 *  @return 1 posted, KELP_ERR_PARSE invalid, KELP_ERR_ARG rejected (addressing). */
KELP_MUST_CHECK int kelp_field_umh_mail(kelp_field_umh *h, const char *var, bool is_string, const char *sval, kelp_time now,
                                        const kelp_field_sink *out);
/** One iteration: UMH_SUMMARY_MSGS "total=..,valid=..,rejected=.." (MOOS-IvP 24.8: valid counts
 *  every well-formed message, rejected ones included; the invalid are total - valid) after an
 *  iteration that had NODE_MESSAGE mail and on iterations 1, 101, 201, ... as 24.8 posts it.
 *  @return 1 posted, 0 not due. */
int kelp_field_umh_iterate(kelp_field_umh *h, kelp_time now, const kelp_field_sink *out);
/** The report as MOOS-IvP 24.8's buildReport writes it (totals, the per-source table as
 *  ACTable draws it, the last five valid, invalid and rejected messages; kelp's VERBOSE =
 *  false: the totals only) into buf, NUL-terminated, truncated to fit. Counts a report.
 *  @return the length written. */
size_t kelp_field_umh_report(kelp_field_umh *h, kelp_time now, char *buf, size_t cap);

/* ------------------------------------------------------------------ uFldScope */

#define KELP_UFS_MAX_ELEMS 16     /**< SCOPE entries (columns) */
#define KELP_UFS_MAX_LAYOUTS 8    /**< LAYOUT entries */
#define KELP_UFS_MAX_ROWS 32      /**< vehicles shown (later ones are counted, not shown) */
#define KELP_UFS_FIELD_LEN 32     /**< bytes of a key, field, alias, colour or vehicle name, with NUL */
#define KELP_UFS_CELL_LEN 48      /**< bytes kept of a cell, with NUL (longer values are cut) */
#define KELP_UFS_LAYOUT_LEN 256   /**< bytes of a LAYOUT line, with NUL */

/** One SCOPE = var=<MOOSVAR>, key=<KEYNAME>, fld=<FIELD>, alias=<ALIAS> (and 24.8's color,
 *  xcolor, xthresh, kept for a terminal that shows colours). */
typedef struct kelp_ufs_elem {
    char var[KELP_MAX_NAME];
    char key[KELP_UFS_FIELD_LEN];   /**< as written; at init every element of a var takes its last line's ("": not shown) */
    char fld[KELP_UFS_FIELD_LEN];
    char alias[KELP_UFS_FIELD_LEN]; /**< the column header ("" = fld) */
    char color[KELP_UFS_FIELD_LEN], xcolor[KELP_UFS_FIELD_LEN];
    double xthresh;
} kelp_ufs_elem;

typedef struct kelp_field_ufs_cfg {
    kelp_ufs_elem elem[KELP_UFS_MAX_ELEMS];
    unsigned nelem;
    char layout[KELP_UFS_MAX_LAYOUTS][KELP_UFS_LAYOUT_LEN]; /**< in configuration order */
    unsigned nlayout;
} kelp_field_ufs_cfg;

typedef enum kelp_ufs_mode { KELP_UFS_STREAMING = 0, KELP_UFS_PAUSED, KELP_UFS_HELP } kelp_ufs_mode;

typedef struct kelp_ufs_row {
    char name[KELP_UFS_FIELD_LEN];
    char cell[KELP_UFS_MAX_ELEMS][KELP_UFS_CELL_LEN];
} kelp_ufs_row;

typedef struct kelp_field_ufs {
    kelp_field_ufs_cfg cfg;
    uint32_t layout_mask[KELP_UFS_MAX_LAYOUTS]; /**< [n-1]: the columns of layout (n); layout 1 is
                                                     the last LAYOUT line (as 24.8 does) */
    unsigned unmatched;                         /**< LAYOUT names matching no alias or field */
    char first_unmatched[KELP_UFS_FIELD_LEN];
    kelp_ufs_row row[KELP_UFS_MAX_ROWS];        /**< sorted by name, case-insensitive */
    unsigned nrow;
    unsigned long mail, bad_mail, dropped_rows, reports;
    kelp_ufs_mode mode;
    unsigned layout;                            /**< 0: all (A); n: layout (n) */
    unsigned last_layout;                       /**< the last user layout shown (1 when none yet) */
    bool update;                                /**< a key asked for one refresh */
} kelp_field_ufs;

/** One block parameter: SCOPE (repeatable) or LAYOUT (repeatable, resolved at init).
 *  @return 1 taken, 0 not ours, <0 (reason in d). */
KELP_MUST_CHECK int kelp_field_ufs_config(kelp_field_ufs_cfg *c, const char *key, const char *val, kelp_diag *d);
/** Resolve keys and layouts; start streaming the all-columns view (A). */
void kelp_field_ufs_init(kelp_field_ufs *s, const kelp_field_ufs_cfg *cfg);
/** The distinct SCOPE variables to subscribe to, one per call (i from 0) until NULL. */
const char *kelp_field_ufs_subscription(const kelp_field_ufs *s, unsigned i);
/** A report "k=v,k=v": for each element on this variable whose key is present (vname and
 *  name stand for each other), the vehicle's cell becomes the element's field (empty when the
 *  report lacks it). @return 1 used, 0 not for us, KELP_ERR_PARSE (a double, or malformed
 *  pairs: what could be read is used). */
KELP_MUST_CHECK int kelp_field_ufs_mail(kelp_field_ufs *s, const char *var, bool is_string, const char *sval);
/** A key press: l/L cycle A, 1..k, A; a/A toggle A and the last layout; p/P/space pause (and
 *  refresh once); r/R stream; h/H help (again: paused). @return 1 when the view changed or a
 *  refresh is asked for, 0 for other keys. */
int kelp_field_ufs_key(kelp_field_ufs *s, int c);
/** Is a render due this iteration (streaming, or a key asked for one)? */
bool kelp_field_ufs_due(const kelp_field_ufs *s);
/** Render the table (or the help) into buf, NUL-terminated, truncated to fit:
 *  "VName  <headers>  STREAMING(A)", "=====  ...  (<n>)", one row per vehicle, columns
 *  padded to their widest entry and two spaces apart. Counts a report; clears the request.
 *  @return the length written. */
size_t kelp_field_ufs_render(kelp_field_ufs *s, char *buf, size_t cap);
/** The AppCast report as 24.8's uFldScope builds it: "VName" and the current layout's
 *  headers, a dashed line, one row per vehicle (ACTable: columns two blanks apart).
 *  @return the length written (cut to fit). */
size_t kelp_field_ufs_table(const kelp_field_ufs *s, char *buf, size_t cap);

/* ------------------------------------------------------------------ uFldNodeBroker / uFldShoreBroker */

/** Without PHI_HOST_INFO, a broker posts HOST_INFO_REQUEST this often (s): pHostInfo posts
 *  once, perhaps before the broker listened. */
#define KELP_BROKER_HOST_REQ_PERIOD 2.0
#define KELP_BROKER_MAX_TRY 16      /**< TRY_SHORE_HOST entries, valid and invalid (node) */
#define KELP_BROKER_MAX_BRIDGES 32  /**< BRIDGE entries (node); BRIDGE + expanded QBRIDGE (shore) */
#define KELP_BROKER_MAX_NODES 64    /**< vehicles one shore broker tracks */
#define KELP_BROKER_MAX_VNODES 16   /**< try_vnode routes (shore) */
#define KELP_BROKER_LINE 128        /**< an invalid TRY_SHORE_HOST line kept for the report */
#define KELP_BROKER_WHY 64          /**< bytes of the reason kept with it */
#define KELP_BROKER_MSG 512         /**< one PMB_REGISTER / ping / ack value */
#define KELP_BROKER_STALE 10.0      /**< s without a ping before a vehicle is stale (shore) */
#define KELP_BROKER_ROUTE 64        /**< one pShare route: "host:port" or "multicast_N" */
#define KELP_BROKER_ACK_WINDOW 10.0 /**< 24.8: s after a vehicle's last ping during which the shore acks
                                         it every iteration (and after which it is stale) */
#define KELP_BROKER_PING_SLOW 20.0  /**< 24.8: s between pings while acks are heard */
#define KELP_BROKER_PING_FAST 5.0   /**< 24.8: s between pings when no ack came for 5 s */
#define KELP_BROKER_SUMMARY KELP_MAX_SVAL /**< the last PSHARE_OUTPUT_SUMMARY the shore keeps */

/** The two command models. 24.8 (the default): the brokers drive pShare (kelp-bridge running
 *  as pShare) with PSHARE_CMD "cmd=output,src_name=..,dest_name=..,route=..", ping on
 *  NODE_BROKER_PING_<n> and ack with 24.8's host records. uField Toolbox 12.2 (pmb = true, a
 *  mission with a pMOOSBridge block): PMB_REGISTER to kelp-bridge as pMOOSBridge, the 12.2
 *  manual's records. */


/** Parse a host record. @return 0; KELP_ERR_PARSE (not key=value pairs, a bad number or
 *  port) or KELP_ERR_RANGE (a value too long), the reason in d. Completeness is separate. */
KELP_MUST_CHECK int kelp_field_broker_host_parse(const char *s, kelp_field_broker_host *h, kelp_diag *d);
/** Complete: community, host and port_udp (what a node broker needs to reach the shore). */
bool kelp_field_broker_host_complete(const kelp_field_broker_host *h);
/** 24.8's HostRecord::valid(): a community, an IPv4 dotted quad or "localhost" as host, a port_db. */
bool kelp_field_broker_host_valid(const kelp_field_broker_host *h);
/** 24.8's HostRecord::getSpec() into buf: community, hostip, port_db, port_udp,
 *  pshare_iroutes, keyword, hostip_alts (the host's own address taken out), timewarp, then
 *  `time` and `key` when non-NULL. @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_field_broker_host_spec(const kelp_field_broker_host *h, const char *time, const char *key, char *buf,
                                          size_t cap);

/** A bridge to request: local src (macros $V $v $N on the shore) and the remote alias. */
typedef struct kelp_field_broker_bridge {
    char src[KELP_MAX_NAME], alias[KELP_MAX_NAME];
} kelp_field_broker_bridge;

/** A candidate shoreside: its bridge's UDP address and community ("" unknown). */
typedef struct kelp_field_broker_try {
    char host[KELP_MAX_NAME], community[KELP_MAX_NAME];
    unsigned port;
    char route[KELP_BROKER_ROUTE];     /**< 24.8: the pshare_route as written (host:port or multicast_N) */
} kelp_field_broker_try;

/** 24.8's TRY_SHORE_HOST: only "pshare_route=R", R a "host:port" (host a dotted quad,
 *  localhost or a name) or "multicast_N". @return 0 or KELP_ERR_PARSE (reason in d). */
KELP_MUST_CHECK int kelp_field_broker_try_parse_pshare(const char *s, kelp_field_broker_try *t, kelp_diag *d);

/** What a node broker knows of one try host (24.8's per-route columns). */
typedef struct kelp_field_broker_shore {
    char community[KELP_MAX_NAME], ip[KELP_MAX_NAME], warp[24];
    unsigned long pings, acks;
    bool bridged;                      /**< the user bridges were requested to this route */
} kelp_field_broker_shore;

/** Parse one TRY_SHORE_HOST: "host_ip=H, port_udp=P[, community=C]" (hostip too) or 24.8's
 *  "pshare_route=H:P". A multicast_N route is KELP_ERR_UNSUPPORTED (kelp-bridge is unicast);
 *  anything else missing or malformed KELP_ERR_PARSE; d says which. */
KELP_MUST_CHECK int kelp_field_broker_try_parse(const char *s, kelp_field_broker_try *t, kelp_diag *d);
/** Parse one BRIDGE: "src=V[, alias=A]" (alias defaults to src). */
KELP_MUST_CHECK int kelp_field_broker_bridge_parse(const char *s, kelp_field_broker_bridge *b, kelp_diag *d);

typedef struct kelp_field_nbroker_cfg {
    char keyword[KELP_MAX_NAME];              /**< KEYWORD ("" none) */
    kelp_field_broker_try tryh[KELP_BROKER_MAX_TRY];/**< valid TRY_SHORE_HOSTs, config order */
    unsigned ntry;
    char bad_try[KELP_BROKER_MAX_TRY][KELP_BROKER_LINE]; /**< invalid lines, as written */
    char bad_why[KELP_BROKER_MAX_TRY][KELP_BROKER_WHY]; /**< why each is invalid (the diag's text) */
    bool bad_multicast[KELP_BROKER_MAX_TRY];   /**< a 24.8 multicast route: valid there, not here */
    unsigned nbad_try;
    kelp_field_broker_bridge bridge[KELP_BROKER_MAX_BRIDGES]; /**< BRIDGE, config order */
    unsigned nbridges;
    double warp;                               /**< MOOSTimeWarp (1) */
    double retry;                              /**< RETRY_INTERVAL: s without an ack before the ping
                                                    registrations are posted again (10) */
    bool auto_realmcast, auto_appcast, auto_pshare_vars; /**< AUTO_BRIDGE_* (24.8: true; 12.2: false) */
    bool pmb;                                  /**< the 12.2 manual's model (PMB_REGISTER); false: 24.8's */
    kelp_diag ws_diag;                         /**< workspace: why a try host or an ack was refused */
} kelp_field_nbroker_cfg;

typedef struct kelp_field_nbroker {
    kelp_field_nbroker_cfg cfg;
    kelp_field_broker_host node;                     /**< the last complete PHI_HOST_INFO */
    bool have_node;
    double host_req_at;                        /**< last HOST_INFO_REQUEST (-1 never) */
    kelp_field_broker_host shore;                    /**< the shore of the last valid ack */
    bool have_shore;
    bool bridged;                              /**< BRIDGEs registered to `shore` */
    bool routes_posted;                        /**< ping registrations posted at least once */
    double routes_at, last_ack;                /**< times (-1 never) */
    unsigned long iterations, ok_phi, bad_phi, phi_changes, registers, pings, ok_ack, bad_ack;
    char last_register[KELP_BROKER_MSG];
    /* 24.8's model */
    kelp_field_broker_shore sh[KELP_BROKER_MAX_TRY]; /**< per valid try host, config order */
    double ping_at, ok_ack_at;                 /**< last ping, last valid ack (long ago at start) */
    kelp_clock clock;                          /**< the newest `now` seen (the time step rule) */
    unsigned long pshare_cmds;
    char ws[KELP_MAX_SVAL];                    /**< workspace of one call (keeps the stack under 1 KB) */
    kelp_field_broker_host ws_host;                  /**< workspace: a record being parsed */
} kelp_field_nbroker;

/** Defaults, 24.8's: no keyword, no try hosts, no bridges, warp 1, the AUTO_BRIDGE_* on. */
void kelp_field_nbroker_cfg_default(kelp_field_nbroker_cfg *cfg);
/** The uField Toolbox 12.2 model (a mission with a pMOOSBridge block): PMB_REGISTER, its ping and
 *  ack records and report, retry 10 s, auto bridges off. */
void kelp_field_nbroker_cfg_seed(kelp_field_nbroker_cfg *cfg);
/** One block parameter: KEYWORD, TRY_SHORE_HOST (an invalid one is kept for the report and
 *  is still taken), BRIDGE, RETRY_INTERVAL, AUTO_BRIDGE_REALMCAST, AUTO_BRIDGE_APPCAST,
 *  AUTO_BRIDGE_PSHARE_VARS. @return 1 taken, 0 not its key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_field_nbroker_config(kelp_field_nbroker_cfg *cfg, const char *key, const char *val,
                                              kelp_diag *d);
/** Start: the AUTO_BRIDGE_* bridges are appended to the BRIDGE list. */
void kelp_field_nbroker_init(kelp_field_nbroker *b, const kelp_field_nbroker_cfg *cfg);
/** PHI_HOST_INFO, NODE_BROKER_ACK, TRY_SHORE_HOST, then NULL. */
const char *kelp_field_nbroker_subscription(unsigned i);
/** One mail at `now`. PHI_HOST_INFO (complete: stored, a change counted; else BAD);
 *  NODE_BROKER_ACK (invalid when incomplete, of another time warp, with a keyword other than
 *  ours when both are set, or a status other than ok; valid: the shore is stored and, for a
 *  new shore or after RETRY_INTERVAL of silence, every BRIDGE is registered to it; then
 *  NODE_PSHARE_VARS, the bridges' aliases comma-joined, as 24.8 posts it);
 *  TRY_SHORE_HOST (24.8: a try host added at run time). @return 1 used, 0 not ours, <0 bad. */
KELP_MUST_CHECK int kelp_field_nbroker_mail(kelp_field_nbroker *b, const char *var, bool is_string, const char *sval, kelp_time now,
                                            const kelp_field_sink *out);
/** Iterate. 24.8: while no try host has acked, the ping bridges (PSHARE_CMD
 *  NODE_BROKER_PING_<i> -> NODE_BROKER_PING to route i); once PHI_HOST_INFO gave
 *  pshare_iroutes and timewarp, NODE_BROKER_PING_<i> = the host record with time= and key=i
 *  when the last ping is older than 5 s (20 s while an ack came in the last 5 s).
 *  uField Toolbox 12.2 (pmb): once the host info is complete, the ping registrations (one PMB_REGISTER per
 *  valid try host; again every RETRY_INTERVAL while no ack is heard), then one
 *  NODE_BROKER_PING. @return the number of posts. */
int kelp_field_nbroker_iterate(kelp_field_nbroker *b, kelp_time now, const kelp_field_sink *out);
/** The report into buf (24.8's layout; the 12.2 manual's Listing 3 with pmb). @return 0, or
 *  KELP_ERR_NOSPACE (truncated). */
KELP_MUST_CHECK int kelp_field_nbroker_report(const kelp_field_nbroker *b, char *buf, size_t cap);

typedef struct kelp_field_sbroker_cfg {
    char keyword[KELP_MAX_NAME];                        /**< KEYWORD ("" none) */
    kelp_field_broker_bridge bridge[KELP_BROKER_MAX_BRIDGES]; /**< BRIDGE and QBRIDGE, config order */
    unsigned nbridges;
    kelp_field_broker_try vnode[KELP_BROKER_MAX_VNODES];      /**< 24.8 try_vnode routes */
    unsigned nvnodes;
    double warp;                                        /**< MOOSTimeWarp (1) */
    bool warn_stale;                                    /**< WARNING_ON_STALE (false) */
    bool auto_realmcast, auto_appcast, auto_mhash;      /**< AUTO_BRIDGE_* (24.8: true; 12.2: false) */
    bool pmb;                                           /**< the 12.2 manual's model; false: 24.8's */
    bool raw[KELP_BROKER_MAX_BRIDGES];                  /**< named by a BRIDGE line (its src as written
                                                             is in UFSB_BRIDGE_VARS) */
    char qbridge[KELP_BROKER_MAX_BRIDGES / 2][KELP_MAX_NAME]; /**< QBRIDGE names (UFSB_QBRIDGE_VARS) */
    unsigned nqbridge;
} kelp_field_sbroker_cfg;

/** One vehicle as the shore knows it. */
typedef struct kelp_field_broker_node {
    kelp_field_broker_host rec;                 /**< its last ping */
    char status[KELP_MAX_NAME];           /**< ok, timewarp (<shore>!=<node>), keyword, invalid */
    double last_ping, skew;
    unsigned index;                       /**< $N: 1-based order of first acceptance (0 never) */
    bool bridged;                         /**< bridges registered to bridged_host:bridged_port */
    char bridged_host[KELP_MAX_NAME];
    unsigned bridged_port;
    bool stale;
    unsigned long pings, acks;
    unsigned nset;                        /**< 24.8: bridges requested so far (UFSB_BRIDGE_VARS) */
} kelp_field_broker_node;

typedef struct kelp_field_sbroker {
    kelp_field_sbroker_cfg cfg;
    kelp_field_broker_host shore;               /**< the last PHI_HOST_INFO */
    bool have_shore;                      /**< complete */
    double host_req_at;                   /**< last HOST_INFO_REQUEST (-1 never) */
    kelp_field_broker_node node[KELP_BROKER_MAX_NODES];
    unsigned nnodes, naccepted;
    double vnode_reg_at, vnode_post_at, count_at; /**< -1 never */
    unsigned count_posted;
    bool qvars_posted;                    /**< UFSB_QBRIDGE_VARS posted (once, at the first iteration) */
    unsigned long iterations, phi, pings, bad_pings, early_pings, full, acks, registers;
    char last_register[KELP_BROKER_MSG];
    /* 24.8's model */
    double cmd_at, cmd_interval;          /**< bridge requests: last pass, the gap to the next */
    kelp_clock clock;                     /**< the newest `now` seen (the time step rule) */
    bool ack_bridge;                      /**< NODE_BROKER_ACK_$V -> NODE_BROKER_ACK listed */
    unsigned long pshare_cmds, tests;     /**< PSHARE_CMD posted, PSHARE_TEST count */
    char summary[KELP_BROKER_SUMMARY];    /**< the last PSHARE_OUTPUT_SUMMARY */
    /* workspace of one call (keeps the stack under 1 KB): the bridge-name candidates, a list */
    uint16_t ws_idx[(KELP_BROKER_MAX_BRIDGES + 1) * (KELP_BROKER_MAX_NODES + 1)];
    char ws[KELP_MAX_SVAL];
    kelp_field_broker_host ws_host;      /**< workspace: the pinging node's host record */
} kelp_field_sbroker;

/** Defaults, 24.8's: no keyword, no bridges, warp 1, no stale warnings, the AUTO_BRIDGE_* on. */
void kelp_field_sbroker_cfg_default(kelp_field_sbroker_cfg *cfg);
/** The uField Toolbox 12.2 model (PMB_REGISTER, its records and report), auto bridges off. */
void kelp_field_sbroker_cfg_seed(kelp_field_sbroker_cfg *cfg);
/** One block parameter: BRIDGE ("src=V[, alias=A]"), QBRIDGE ("X[, Y ...]": X_ALL->X and
 *  X_$V->X each), KEYWORD, TRY_VNODE ("[route=]ip[:port]", port 9200), WARNING_ON_STALE,
 *  AUTO_BRIDGE_REALMCAST (QBRIDGE REALMCAST_REQ), AUTO_BRIDGE_APPCAST (QBRIDGE APPCAST_REQ),
 *  AUTO_BRIDGE_MHASH (BRIDGE src=MISSION_HASH). A bridge already listed is not added twice.
 *  @return 1 taken, 0 not its key, <0 (reason in d). */
KELP_MUST_CHECK int kelp_field_sbroker_config(kelp_field_sbroker_cfg *cfg, const char *key, const char *val,
                                              kelp_diag *d);
void kelp_field_sbroker_init(kelp_field_sbroker *s, const kelp_field_sbroker_cfg *cfg);
/** PHI_HOST_INFO, NODE_BROKER_PING, PSHARE_OUTPUT_SUMMARY (24.8), then NULL. */
const char *kelp_field_sbroker_subscription(unsigned i);
/** One mail at `now`. NODE_BROKER_PING: counted; ignored until our own host info
 *  is complete; the vehicle (by community, case-insensitive) is recorded with its status and
 *  skew; accepted: on first acceptance it gets the next $N, and whenever its bridges are not
 *  registered to its current host:port_udp (first time, or it moved) the ack bridge
 *  (NODE_BROKER_ACK_<V> -> NODE_BROKER_ACK) and every BRIDGE are registered (the first time,
 *  UFSB_BRIDGE_VARS follows: the sorted set of the BRIDGE lines' src as written,
 *  NODE_BROKER_ACK_$V and every source expanded for a vehicle, as MOOS-IvP 24.8 posts it);
 *  then the ack NODE_BROKER_ACK_<V> and NODE_BROKER_VACK are posted. @return 1 used, 0 not
 *  ours, <0 bad. */
KELP_MUST_CHECK int kelp_field_sbroker_mail(kelp_field_sbroker *s, const char *var, bool is_string, const char *sval, kelp_time now,
                                            const kelp_field_sink *out);
/** Iterate: UFSB_QBRIDGE_VARS (the QBRIDGE names, sorted; once), stale warnings,
 *  UFSB_NODE_COUNT (on change, else every 30 s), try_vnode registrations (every 30 s) and
 *  TRY_SHORE_HOST (every 10 s). @return the number of posts. */
int kelp_field_sbroker_iterate(kelp_field_sbroker *s, kelp_time now, const kelp_field_sink *out);
/** 24.8 (pmb false): a ping (a valid host record) makes a new vehicle known (its record and
 *  status kept, the ack bridge listed) or refreshes a known one (time, skew, status); acks
 *  (NODE_BROKER_ACK_<V> = our host record, status, key, id) go out every iteration while a
 *  vehicle's last ping is younger than 10 s; every bridge is requested for every vehicle
 *  (PSHARE_CMD unless PSHARE_OUTPUT_SUMMARY lists it; PSHARE_TEST; UFSB_BRIDGE_VARS on a new
 *  name) 5 s after a new vehicle, the gap growing by 3 s per pass.
 *  The report at `now` into buf (24.8's layout; the 12.2 manual's Listing 6 with pmb). @return 0 or
 *  KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_field_sbroker_report(const kelp_field_sbroker *s, kelp_time now, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
