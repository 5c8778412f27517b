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
       KELP_NREP_NAV };

typedef struct kelp_field_nrep_cfg {
    char name[KELP_NODEREPORT_MAX_FIELD];  /**< NAME= (VESSEL_NAME; default the community) */
    char type[KELP_NODEREPORT_MAX_FIELD];  /**< TYPE= (PLATFORM_TYPE / VESSEL_TYPE; default UUV) */
    char group[KELP_NODEREPORT_MAX_FIELD]; /**< GROUP= ("" none) */
    char out_var[KELP_MAX_NAME];           /**< NODE_REPORT_OUTPUT (default NODE_REPORT_LOCAL) */
    char mode_var[KELP_MAX_NAME];          /**< MODE_VAR: MODE= from this variable ("" none) */
    char prefix[24];                       /**< PREFIX of the navigation variables (default NAV) */
    double length;                         /**< PLATFORM_LENGTH (with have_length) */
    bool have_length;
    kelp_geo geo;                          /**< LatOrigin/LongOrigin (with have_geo) */
    bool have_geo;
} kelp_field_nrep_cfg;

typedef struct kelp_field_nrep {
    kelp_field_nrep_cfg cfg;
    char nav_var[KELP_NREP_NAV][KELP_MAX_NAME]; /**< NAV_X, NAV_Y, NAV_LAT, NAV_LONG, NAV_SPEED, ... */
    double nav[KELP_NREP_NAV];
    bool have[KELP_NREP_NAV];
    char helm_state[KELP_NODEREPORT_MAX_FIELD], helm_modes[KELP_NODEREPORT_MAX_FIELD];
    char mode[KELP_NODEREPORT_MAX_FIELD], allstop[KELP_NODEREPORT_MAX_FIELD];
    char helm_active[KELP_NODEREPORT_MAX_FIELD];
    bool fresh;                            /**< navigation mail since the last report */
    unsigned long posted, nav_mail, bad_mail;
    char last[KELP_NODEREPORT_MAX_LEN];    /**< the last report posted */
} kelp_field_nrep;

/** Defaults: name = community, type UUV, output NODE_REPORT_LOCAL, prefix NAV. */
void kelp_field_nrep_cfg_default(kelp_field_nrep_cfg *cfg, const char *community);
/** Start with cfg. KELP_ERR_ARG when a text field holds ',' or '=' or the name is empty. */
KELP_MUST_CHECK int kelp_field_nrep_init(kelp_field_nrep *r, const kelp_field_nrep_cfg *cfg);
/** The variables to subscribe to, one per call (i from 0) until NULL. */
const char *kelp_field_nrep_subscription(const kelp_field_nrep *r, unsigned i);
/** One mail. Returns 1 when it was used, 0 when not for this tool, <0 (and a warning) when
 *  bad (a navigation value that is not a finite number). */
int kelp_field_nrep_mail(kelp_field_nrep *r, const char *var, bool is_string, const char *sval, double dval,
                         const kelp_field_sink *out);
/** Iterate at `now`: publishes one report when navigation mail arrived since the last one.
 *  Returns 1 when a report was published, 0 when none was due, <0 on a formatting error. */
int kelp_field_nrep_iterate(kelp_field_nrep *r, double now, const kelp_field_sink *out);

#ifdef __cplusplus
}
#endif

#endif
