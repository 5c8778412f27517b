/* kelp commander: the model behind kelp-commander (the iCommander role of Goby 1.1: the
 * Goby 1.1 User Manual, section 2.4). Core: no allocation, no I/O, no clock.
 *
 * The console edits "open messages": one per DCCL message definition, each a row per field the
 * operator can see (renamed header fields such as <dest_id><name>Destination</name>, then the
 * layout in XML order; statics are shown but cannot be changed). Values are kept as the text
 * typed, checked against the field's definition (type, min/max, precision, enum values,
 * max_length, hex bytes) and may hold the specials of the editing menu:
 *   "_time"         replaced at send by the UNIX time (whole seconds),
 *   "y(lat)N:M"     M metres north of LatOrigin, paired with "x(lon)N:M" (M metres east):
 *                   replaced at send by the latitude / longitude of that local point.
 * Send turns a message into the publications pAcommsHandler reads for it: for every source
 * variable (<src_var>/<moos_var>, default the <trigger_var>) one string "key=value,..." of the
 * fields it feeds (key: <src_key> or the field name; a value holding ',' is wrapped in {}),
 * the trigger variable last, carrying the trigger's mandatory content when the fields do not.
 */
#ifndef KELP_COMMANDER_H
#define KELP_COMMANDER_H

#include <stdbool.h>
#include <stddef.h>

#include <kelp/config.h>
#include <kelp/dccl.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_CMDR_MAX_OPEN 32    /**< open messages */
#define KELP_CMDR_MAX_ROWS 64    /**< rows (fields) of one message */
#define KELP_CMDR_VAL 256        /**< bytes of one value's text */
#define KELP_CMDR_PUBLEN 2048    /**< bytes of one publication */
#define KELP_CMDR_MAX_PUBS 8     /**< publications of one send */

typedef struct kelp_commander_msg {
    const kelp_dccl_msgdef *def;
    unsigned n_rows;
    unsigned short field[KELP_CMDR_MAX_ROWS]; /**< index into def->fields per row */
    char val[KELP_CMDR_MAX_ROWS][KELP_CMDR_VAL];
    bool edited;
} kelp_commander_msg;

typedef struct kelp_commander {
    const kelp_dccl_set *set;
    kelp_dccl_builtin *geo;   /**< LatOrigin/LongOrigin and the modem-id table (may be NULL) */
    bool force_xy_only;       /**< accept only the x/y specials in latitude/longitude fields */
    kelp_commander_msg open[KELP_CMDR_MAX_OPEN];
    unsigned n_open;
    int active;               /**< open message edited last, or -1 */
    char line[KELP_CMDR_VAL + 2 * KELP_DCCL_MAX_NAME]; /**< scratch: the line kelp_commander_load reads */
} kelp_commander;

/** One publication of a send. */
typedef struct kelp_commander_pub {
    char var[KELP_DCCL_MAX_NAME];
    char val[KELP_CMDR_PUBLEN];
} kelp_commander_pub;

void kelp_commander_init(kelp_commander *c, const kelp_dccl_set *set, kelp_dccl_builtin *geo);
/** Open (or find the open) message named `name`; returns its index or KELP_ERR_NOTFOUND /
 *  KELP_ERR_NOSPACE. A new message starts with statics filled and every other value empty. */
KELP_MUST_CHECK int kelp_commander_open(kelp_commander *c, const char *name);
/** Row of the field named `name` (case-sensitive), or -1. */
int kelp_commander_row(const kelp_commander_msg *m, const char *name);
const kelp_dccl_field *kelp_commander_row_field(const kelp_commander_msg *m, unsigned row);
/** Type word shown on a row: "static", "int", "float", "bool", "string", "enum", "hex". */
const char *kelp_commander_type_name(const kelp_dccl_field *f);
/** One line telling what the field accepts ("(static) you cannot change the value of this
 *  field", "(int) range: 0 to 10000", ...). */
void kelp_commander_describe(const kelp_dccl_field *f, char *out, size_t cap);
/** Check a value for a field. "" (not given) and the specials are accepted where they apply.
 *  @return 0, or KELP_ERR_RANGE / KELP_ERR_PARSE with d's message (d may be NULL). */
KELP_MUST_CHECK int kelp_commander_check(const kelp_commander *c, const kelp_dccl_field *f, const char *val, kelp_diag *d);
/** Check and store; the message becomes the active one. */
KELP_MUST_CHECK int kelp_commander_set(kelp_commander *c, unsigned msg, unsigned row, const char *val, kelp_diag *d);
/** Clear every value (statics stay). */
void kelp_commander_clear(kelp_commander *c, unsigned msg);
/** The next free pair number of the x/y special in a message (1, 2, ...). */
unsigned kelp_commander_next_xy(const kelp_commander_msg *m);
/** Build the publications of a send at UNIX time `now`. KELP_ERR_NOSPACE when they do not
 *  fit (no message in d); KELP_ERR_PARSE (with d's message) for an x/y special without its
 *  pair or without LatOrigin. */
KELP_MUST_CHECK int kelp_commander_send(const kelp_commander *c, unsigned msg, kelp_time now, kelp_commander_pub *out, size_t cap,
                                   size_t *n, kelp_diag *d);

/* ---- save files: plain text, "message = NAME" opens a message, then "field = value" lines;
 *      '#' starts a comment line ---- */
/** Write every open message. @return KELP_ERR_NOSPACE when it does not fit. */
KELP_MUST_CHECK int kelp_commander_save(const kelp_commander *c, char *out, size_t cap, size_t *len);
/** Read a save file (NUL-terminated text) into open messages. Stops at the first bad line.
 *  @return 0, or KELP_ERR_PARSE / KELP_ERR_NOTFOUND / KELP_ERR_RANGE / KELP_ERR_NOSPACE with
 *  the bad line (1-based) in d->line and the reason in d's message. */
KELP_MUST_CHECK int kelp_commander_load(kelp_commander *c, const char *text, kelp_diag *d);

/* ---- acks and expiries (ACOMMS_ACK / ACOMMS_EXPIRE of pAcommsHandler) ---- */
/** The on-screen note for an ACOMMS_ACK (ack = true) or ACOMMS_EXPIRE text:
 *  "Message acknowledged from queue: NAME\n for destination: N\n at time: 2011-Mar-03 22:38:12".
 *  The queue is named from the DCCL id in the data; `now` (UNIX) is used when the text has no
 *  time. @return 0 or KELP_ERR_PARSE. */
KELP_MUST_CHECK int kelp_commander_ack_note(const kelp_commander *c, bool ack, const char *text, kelp_time now, char *out,
                                       size_t cap);

#ifdef __cplusplus
}
#endif
#endif
