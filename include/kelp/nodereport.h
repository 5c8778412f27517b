/* kelp node reports and viewer artifacts: the strings a shoreside consumes.
 *
 * NODE_REPORT / NODE_REPORT_LOCAL (pNodeReporter role; the uField Toolbox manual's NODE_REPORT):
 *
 *   NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,LAT=43.824981,
 *   LON=-70.329755,SPD=2.00,HDG=118.85,DEPTH=4.63,LENGTH=3.8,MODE=LOITERING
 *
 * kelp_nodereport_format writes the fields present in that order and those decimals (TIME,
 * X, Y, SPD, HDG, DEPTH: 2 fixed; LAT, LON: 6 fixed; LENGTH: up to 2, trailing zeros
 * stripped), with COLOR after TIME and YAW (radians, up to 7 decimals) after HDG when set,
 * then ALLSTOP, GROUP, INDEX (when not 0) and any extra "K=V" pairs. kelp_nodereport_parse reads any order, keys
 * case-insensitively (synonyms: VNAME=NAME, LONG=LON, SPEED=SPD, HEADING=HDG, DEP=DEPTH,
 * UTC_TIME=TIME, LEN=LENGTH; COG is read too),
 * ignores unknown keys, keeps the first of a repeated key, and requires NAME plus a position
 * (X and Y, or LAT and LON).
 *
 * VIEW_* artifacts (behaviours, uField tools; pMarineViewer's inputs), parsed for drawing:
 *   VIEW_POINT        x=60,y=-40,label=alder's next waypoint,type=waypoint,source=transit,active=true
 *                     or the colon form "active,false:label,alder's next waypoint:type,waypoint:
 *                     source,waypt_return:0,0,0" (MIT-CSAIL-TR-2009-037 section 5.2.3)
 *   VIEW_CIRCLE       x=..,y=..,radius=10,label=..,edge_color=..,fill_color=..,fill=0.3,edge_size=1
 *   VIEW_POLYGON      pts={x1,y1:x2,y2:x3,y3},label=..,edge_color=..,fill_color=..,fill=..
 *   VIEW_SEGLIST      pts={x1,y1:x2,y2:...},label=..   (colon form "label,L:x1,y1:x2,y2" too)
 *   VIEW_MARKER       x=0,y=-200,label=03,color=orange,type=circle,width=4
 *   VIEW_COMMS_PULSE  sx=..,sy=..,tx=..,ty=..,beam_width=7,duration=10,fill=0.35,label=JAMES2IKE,
 *                     edge_color=..,fill_color=..,time=..,edge_size=1
 *   VIEW_RANGE_PULSE  x=..,y=..,radius=40,duration=15,fill=0.25,fill_color=green,label=04,
 *                     edge_color=green,time=..,edge_size=1   (these are also the defaults)
 * Pairs are split at commas outside braces; a value holding a further " key=value" (the uField Toolbox manual's
 * "type=waypoint source=transit") is split at that space. Unknown keys are ignored.
 *
 * Core: allocation-free, no I/O. Parsers are safe on arbitrary bytes (fuzzed).
 */
#ifndef KELP_NODEREPORT_H
#define KELP_NODEREPORT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/err.h>
#include <kelp/geo.h>

#ifdef __cplusplus
extern "C" {
#endif

/* presence bits of kelp_nodereport.fields */
#define KELP_NR_NAME 0x0001u
#define KELP_NR_TYPE 0x0002u
#define KELP_NR_TIME 0x0004u
#define KELP_NR_X 0x0008u
#define KELP_NR_Y 0x0010u
#define KELP_NR_LAT 0x0020u
#define KELP_NR_LON 0x0040u
#define KELP_NR_SPD 0x0080u
#define KELP_NR_HDG 0x0100u
#define KELP_NR_DEPTH 0x0200u
#define KELP_NR_LENGTH 0x0400u
#define KELP_NR_MODE 0x0800u
#define KELP_NR_ALLSTOP 0x1000u
#define KELP_NR_GROUP 0x2000u
#define KELP_NR_YAW 0x4000u
#define KELP_NR_INDEX 0x8000u
#define KELP_NR_COLOR 0x10000u
#define KELP_NR_COG 0x20000u

typedef struct kelp_nodereport {
    char name[KELP_NODEREPORT_MAX_FIELD];
    char type[KELP_NODEREPORT_MAX_FIELD];
    char mode[KELP_NODEREPORT_MAX_FIELD];
    char allstop[KELP_NODEREPORT_MAX_FIELD];
    char group[KELP_NODEREPORT_MAX_FIELD];
    char color[KELP_NODEREPORT_MAX_FIELD];
    double time, x, y, lat, lon, spd, hdg, depth, length;
    double yaw;                  /**< radians, counter-clockwise from east (written with 7 decimals) */
    double cog;                  /**< course over ground, degrees (COG; read, and written by the record format) */
    long index;                  /**< reports posted before this one (written when not 0) */
    uint32_t fields;             /**< KELP_NR_* bits of the fields present */
    bool dep_key;                /**< format: write depth as DEP= (MOOS-IvP today) instead of DEPTH= */
    bool moos248;                /**< format: MOOS-IvP 24.8's NodeRecord layout: NAME,X,Y,SPD,HDG,DEP,
                                      LAT,LON,TYPE,COLOR,GROUP,MODE,ALLSTOP,INDEX,YAW,TIME,LENGTH, numbers
                                      with trailing zeros trimmed (2 decimals; LAT/LON 8, YAW 7) */
    const char *extra;           /**< format: "K=V,K=V" appended as they are (may be NULL) */
} kelp_nodereport;

/** Empty report (no fields). */
void kelp_nodereport_init(kelp_nodereport *r);

/** Format the fields present. @param len may be NULL. @return 0; KELP_ERR_ARG without NAME,
 *  with a non-finite number, or a text field holding ',' or '='; KELP_ERR_NOSPACE if cap is
 *  too small; KELP_ERR_RANGE for a number too large to print. buf is always terminated when
 *  cap > 0. */
KELP_MUST_CHECK int kelp_nodereport_format(const kelp_nodereport *r, char *buf, size_t cap, size_t *len);

/** MOOS-IvP 24.8's node record (NodeRecord::getSpec), what uFldNodeComms relays: NAME, X, Y,
 *  SPD, HDG, COG, DEP, LAT, LON, TYPE, COLOR, GROUP, MODE, ALLSTOP, INDEX (when not 0), YAW,
 *  TIME, LENGTH, each when present, numbers with trailing zeros stripped (X, Y, SPD, HDG, COG,
 *  DEP, TIME, LENGTH: 2 decimals; LAT, LON: 8; YAW: 7, written as 24.8 writes it, from HDG),
 *  then the pairs of r->extra whose keys kelp_nodereport_parse does not read (24.8's
 *  "properties": ordered by key, the last of a repeated key). @return as kelp_nodereport_format. */
KELP_MUST_CHECK int kelp_nodereport_format_record(const kelp_nodereport *r, char *buf, size_t cap, size_t *len);

/** MOOS-IvP 24.8's contact ledger on a received report (ContactLedger::processNodeRecord):
 *  the type "uuv" becomes "auv" and one that is not a known vehicle type (kayak, auv, uuv,
 *  usv, glider, asv, ship, mokai, longship, buoy, heron, swimmer, cray, bcray, crayx, bcrayx,
 *  wamv, smr, smrx, skyw, skywalker, quad, quadcopter; any case) or absent becomes "ship"; an
 *  auv or glider must report its depth; a LENGTH absent or <= 0 takes the type's default
 *  (auv, kayak, heron 3; glider 2; cray, bcray, crayx, bcrayx 1.5; ship 12; longship 15; wamv,
 *  smr 6; else what it was) and is always written; COG, when not reported, is the bearing
 *  from prev_xy (the vehicle's last position, NULL when none) or else HDG.
 *  @return 0, or KELP_ERR_PARSE (reason in d) for an underwater type without depth. */
KELP_MUST_CHECK int kelp_nodereport_ledger(kelp_nodereport *r, const double *prev_xy, kelp_diag *d);

/** Parse a report. @param d (may be NULL) the reason on failure (first error wins).
 *  @return 0; KELP_ERR_PARSE (pair without '=', bad number, unbalanced quote/brace, no NAME,
 *  no position); KELP_ERR_RANGE (a text field longer than KELP_NODEREPORT_MAX_FIELD - 1). */
KELP_MUST_CHECK int kelp_nodereport_parse(const char *s, size_t len, kelp_nodereport *out, kelp_diag *d);

/** Fill X/Y from LAT/LON with the datum when X/Y are absent (and LAT/LON from X/Y when those
 *  are absent). @return 0, KELP_ERR_RANGE if the conversion fails. */
KELP_MUST_CHECK int kelp_nodereport_complete(kelp_nodereport *r, const kelp_geo *g);

/* ------------------------------------------------------------------ VIEW_* artifacts */

typedef enum kelp_view_kind {
    KELP_VIEW_POINT = 0,
    KELP_VIEW_CIRCLE,
    KELP_VIEW_POLYGON,
    KELP_VIEW_SEGLIST,
    KELP_VIEW_MARKER,
    KELP_VIEW_COMMS_PULSE,
    KELP_VIEW_RANGE_PULSE,
    KELP_VIEW_NKINDS
} kelp_view_kind;

/* presence bits of kelp_view.fields (numbers given explicitly; defaults are not marked) */
#define KELP_VF_X 0x0001u
#define KELP_VF_Y 0x0002u
#define KELP_VF_TX 0x0004u
#define KELP_VF_TY 0x0008u
#define KELP_VF_RADIUS 0x0010u
#define KELP_VF_DURATION 0x0020u
#define KELP_VF_TIME 0x0040u
#define KELP_VF_FILL 0x0080u
#define KELP_VF_WIDTH 0x0100u
#define KELP_VF_EDGE_SIZE 0x0200u
#define KELP_VF_VERTEX_SIZE 0x0400u

typedef struct kelp_view {
    kelp_view_kind kind;
    bool active;                 /**< false: an "erase" posting (active=false) */
    char label[KELP_VIEW_MAX_FIELD];
    char type[KELP_VIEW_MAX_FIELD];       /**< point type ("waypoint") or marker shape */
    char source[KELP_VIEW_MAX_FIELD];
    char msg[KELP_VIEW_MAX_FIELD];
    char edge_color[KELP_VIEW_MAX_FIELD];
    char fill_color[KELP_VIEW_MAX_FIELD]; /**< also a marker's "color" */
    char vertex_color[KELP_VIEW_MAX_FIELD];
    char label_color[KELP_VIEW_MAX_FIELD];
    double x, y;                 /**< point, centre, marker, pulse source (sx, sy) */
    double tx, ty;               /**< comms pulse target */
    double radius, duration, time, fill, width, edge_size, vertex_size;
    double beam_width;
    uint32_t fields;             /**< KELP_VF_* bits */
    size_t npts;
    double pts[KELP_VIEW_MAX_PTS][2];
} kelp_view;

/** The kind posted on a variable: VIEW_POINT, VIEW_CIRCLE, VIEW_POLYGON, VIEW_SEGLIST,
 *  VIEW_MARKER, VIEW_COMMS_PULSE (also the uField Toolbox manual's VIEW_COMM_PULSE spelling), VIEW_RANGE_PULSE
 *  (case-insensitive). @return 0 or KELP_ERR_NOTFOUND. */
KELP_MUST_CHECK int kelp_nodereport_view_kind_of(const char *var, kelp_view_kind *out);

/** The canonical variable name of a kind. */
const char *kelp_nodereport_view_var(kelp_view_kind kind);

/** Parse one posting. Required: POINT, CIRCLE, MARKER, RANGE_PULSE an x and y (CIRCLE also a
 *  radius > 0); COMMS_PULSE sx, sy, tx, ty; POLYGON and SEGLIST at least one vertex unless
 *  the posting is an erase (active=false).
 *  @return 0; KELP_ERR_PARSE (reason in d); KELP_ERR_RANGE (text too long); KELP_ERR_NOSPACE
 *  (more than KELP_VIEW_MAX_PTS vertices). */
KELP_MUST_CHECK int kelp_nodereport_view_parse(kelp_view_kind kind, const char *s, size_t len, kelp_view *out, kelp_diag *d);

#ifdef __cplusplus
}
#endif

#endif
