/* kelp edge: the postings of a run, read from either kind of log -- an LCM log of the bus
 * (kelp.var_t events on channels named after their variable; sync requests, sync replies,
 * binary values and other types are skipped and counted) or a MOOS .alog (kelp/alog.h) --
 * one posting at a time, in file order. */
#ifndef KELP_EDGE_ALOG_H
#define KELP_EDGE_ALOG_H
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kelp_alog_postlog kelp_alog_postlog;

typedef struct kelp_post {
    double time;            /**< MOOS time of the posting (alog: LOGSTART + the time column) */
    int64_t log_us;         /**< LCM: the event's timestamp; alog: time in microseconds */
    const char *var, *src, *community; /**< NUL-terminated; community "" when unknown */
    bool is_string;
    const char *sval;       /**< NUL-terminated string value */
    double dval;
} kelp_post;

typedef struct kelp_alog_postlog_stats {
    size_t posts;           /**< postings returned */
    size_t skipped;         /**< LCM: sync traffic, binary values, undecodable or other types; alog: bad lines */
    size_t damaged;         /**< LCM: damaged stretches */
} kelp_alog_postlog_stats;

/** Open path; the kind is told from its first bytes (an LCM sync word, else text).
 *  default_community: the community of .alog postings whose source has no "@community"
 *  (a "%% COMMUNITY <name>" banner line overrides it). */
kelp_alog_postlog *kelp_alog_postlog_open(const char *path, const char *default_community, kelp_diag *d);
bool kelp_alog_postlog_is_alog(const kelp_alog_postlog *p);
/** The log's time origin: the .alog's LOGSTART, or an LCM log's first posting time (NAN before
 *  the first kelp_alog_postlog_next). */
double kelp_alog_postlog_start(const kelp_alog_postlog *p);
/** Next posting (valid until the next call). @return 1, 0 at the end, <0 on a read error. */
KELP_MUST_CHECK int kelp_alog_postlog_next(kelp_alog_postlog *p, kelp_post *out);
kelp_alog_postlog_stats kelp_alog_postlog_get_stats(const kelp_alog_postlog *p);
void kelp_alog_postlog_close(kelp_alog_postlog *p);

#ifdef __cplusplus
}
#endif

#endif
