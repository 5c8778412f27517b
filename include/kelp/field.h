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

#ifdef __cplusplus
}
#endif

#endif
