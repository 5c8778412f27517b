/* kelp AppCast: an app's status as MOOS-IvP's AppCasting carries it (core: no allocation).
 *
 * An app posts APPCAST when a client asks with APPCAST_REQ (node=, app=, duration= up to 30 s,
 * key= naming the client, thresh=any|run_warning), and in its first iterations. The APPCAST
 * string is "param=value" pairs separated by "!@#", lists inside a value by "!@":
 *
 *   proc=pHostInfo!@#iter=12!@#node=alpha!@#iter=12!@#messages=line 1!@line 2!@!@#
 *   config_warnings=w1!@w2!@#events_total=1!@#events=[3.20]: started!@#
 *   run_warning_total=4!@#run_warnings=3:no route!@1:bad mail
 *
 * (iter appears twice, as MOOS-IvP writes it; run warnings are "count:text" in text order).
 */
#ifndef KELP_APPCAST_H
#define KELP_APPCAST_H

#include <stdbool.h>
#include <stddef.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_APPCAST_NAME 64
#define KELP_APPCAST_ITEMS 16     /* config warnings, events, run warnings: each */
#define KELP_APPCAST_ITEM 200
#define KELP_APPCAST_MSG 4096     /* the report body */

typedef struct kelp_appcast {
    char proc[KELP_APPCAST_NAME];
    char node[KELP_APPCAST_NAME];
    unsigned long iter;
    char messages[KELP_APPCAST_MSG];          /**< lines, '\n'-separated */
    unsigned ncfg, nevents, nrun;
    char cfg[KELP_APPCAST_ITEMS][KELP_APPCAST_ITEM];
    char events[KELP_APPCAST_ITEMS][KELP_APPCAST_ITEM];
    char run[KELP_APPCAST_ITEMS][KELP_APPCAST_ITEM];
    unsigned long run_count[KELP_APPCAST_ITEMS];
    unsigned long run_total;
} kelp_appcast;

/** The APPCAST string. Writes at most cap-1 characters and a NUL; KELP_ERR_NOSPACE when it
 *  does not fit (the text is then cut). The separators never occur inside a field: a "!@"
 *  in the text is written as "!_". */
KELP_MUST_CHECK int kelp_appcast_format(const kelp_appcast *ac, char *buf, size_t cap, size_t *len);
/** Parse an APPCAST string (unknown parameters ignored, as MOOS-IvP does). KELP_ERR_PARSE
 *  (reason in d) when proc= is missing or a pair has no '='. Lists past KELP_APPCAST_ITEMS and
 *  text past the field sizes are cut. */
KELP_MUST_CHECK int kelp_appcast_parse(const char *s, size_t len, kelp_appcast *out, kelp_diag *d);
/** One field of an APPCAST string (key case-insensitive, e.g. "proc", "node") into out, read
 *  as kelp_appcast_parse reads it, without parsing the rest. @return 1 found, 0 not there. */
int kelp_appcast_field(const char *s, size_t len, const char *key, char *out, size_t cap);
/** The terminal form (uMAC's view of one app): header with proc, node, warnings and
 *  iteration, then configuration warnings, run warnings, the report and recent events. */
KELP_MUST_CHECK int kelp_appcast_render(const kelp_appcast *ac, char *buf, size_t cap, size_t *len);

/** An APPCAST_REQ: node, app (either may be "all"), duration (s, clamped to [0, 30]), key
 *  (the client; required), thresh ("any" by default, or "run_warning"). */
typedef struct kelp_appcast_req {
    char node[KELP_APPCAST_NAME], app[KELP_APPCAST_NAME], key[KELP_APPCAST_NAME], thresh[16];
    double duration;
} kelp_appcast_req;

KELP_MUST_CHECK int kelp_appcast_req_parse(const char *s, size_t len, kelp_appcast_req *out);
/** Does the request address this node and app ("all" matches any)? */
bool kelp_appcast_req_matches(const kelp_appcast_req *r, const char *node, const char *app);

#ifdef __cplusplus
}
#endif

#endif
