/* kelp mission files: the MOOS .moos syntax (and .bhv behaviour files, which share it).
 *
 *   // comment (at line start or after white space; "udpm://..." is not a comment)
 *   Key = value with spaces, commas = and all        <- global parameter
 *   ProcessConfig = pHelmIvP                         <- block header (any "Kind = Name")
 *   {
 *      AppTick = 4                                   <- MOOS parameter
 *      common { log: true  verbosity: VERBOSITY_WARN }  <- Goby (protobuf text) syntax
 *      driver_cfg
 *      {
 *         [MicroModemConfig.reset_nvram]: false      # comment
 *         serial_port: "/dev/ttyUSB0"
 *      }
 *   }
 *
 * The parser works in place over caller text and stores nodes in caller storage (a NULL
 * node array measures). Keys compare case-insensitively, as MOOS does. Values are trimmed;
 * a quoted protobuf string has its quotes removed (kelp_mission_copy unescapes it).
 * Allocation-free; the file loader is at the edge (kelp_mission_load, src/bus/edge/).
 */
#ifndef KELP_MISSION_H
#define KELP_MISSION_H

#include <stddef.h>
#include <stdbool.h>
#include <kelp/err.h>
#include <kelp/util.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum kelp_mission_kind {
    KELP_MN_PARAM = 0,   /**< Key = Value (global when parent < 0) */
    KELP_MN_BLOCK = 1,   /**< Kind = Name { ... }; key = Kind, val = Name */
    KELP_MN_FIELD = 2,   /**< protobuf text: key: value */
    KELP_MN_MSG = 3      /**< protobuf text: key { ... } */
} kelp_mission_kind;

typedef struct kelp_mission_node {
    kelp_mission_kind kind;
    const char *key;
    size_t klen;
    const char *val;
    size_t vlen;
    bool quoted;         /**< value was a "quoted string" (escapes not yet resolved) */
    int line;            /**< 1-based line of the key */
    int parent;          /**< index of enclosing BLOCK or MSG, -1 at top level */
} kelp_mission_node;

typedef struct kelp_mission {
    const char *text;
    size_t len;
    kelp_mission_node *nodes;
    size_t nnodes;
    size_t cap;
    kelp_diag diag; /**< why a parse failed: line and reason (first error wins) */
} kelp_mission;

/** Parse text. @param nodes storage for cap nodes, or NULL to count (m->nnodes).
 *  @return 0; KELP_ERR_PARSE with the line and reason in m->diag; KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_mission_parse(kelp_mission *m, const char *text, size_t len,
                                       kelp_mission_node *nodes, size_t cap);

/** Case-insensitive comparison of a node's key (or value) with a C string. */
bool kelp_mission_key_is(const kelp_mission_node *n, const char *key);
bool kelp_mission_val_is(const kelp_mission_node *n, const char *val);

/** Index of the first BLOCK whose kind is `kind` (e.g. "ProcessConfig") and name is `name`
 *  (both case-insensitive), or -1. */
int kelp_mission_block(const kelp_mission *m, const char *kind, const char *name);

/** Next direct child of `parent` (-1 = top level) after index `after` (-1 = from the start)
 *  whose key matches `key` (case-insensitive; NULL = any). Returns its index or -1. */
int kelp_mission_next(const kelp_mission *m, int parent, int after, const char *key);

/** Copy a node's value into buf as a C string (unescaping quoted strings).
 *  @return 0 or KELP_ERR_NOSPACE (never truncates silently). */
KELP_MUST_CHECK int kelp_mission_copy(const kelp_mission_node *n, char *buf, size_t cap);

/** Value conversions. @return 0, or KELP_ERR_PARSE when the value is not of that type. */
KELP_MUST_CHECK int kelp_mission_double(const kelp_mission_node *n, double *out);
KELP_MUST_CHECK int kelp_mission_bool(const kelp_mission_node *n, bool *out);

/* Number parsing and case-insensitive compares: include/kelp/util.h (included above). */

/* Loading a mission from a file is edge code: include/kelp/edge/mission.h. */

#ifdef __cplusplus
}
#endif

#endif
