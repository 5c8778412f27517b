/* kelp edge: read an LCM log file event by event with kelp's validating parser
 * (kelp/lcmlog.h). Damaged stretches are skipped to the next sync word and counted; an
 * event with an empty channel is an ordinary event. */
#ifndef KELP_EDGE_LCMLOG_H
#define KELP_EDGE_LCMLOG_H
#include <stdbool.h>
#include <stddef.h>
#include <kelp/lcmlog.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kelp_lcmlog_reader kelp_lcmlog_reader;

typedef struct kelp_lcmlog_stats {
    size_t events;        /**< events returned */
    size_t damaged;       /**< damaged stretches skipped */
    size_t skipped_bytes; /**< bytes in them */
    bool truncated;       /**< the file ends inside an event */
} kelp_lcmlog_stats;

/** Open path; events with more than max_data bytes of data count as damage (0: 64 MiB). */
kelp_lcmlog_reader *kelp_lcmlog_open(const char *path, size_t max_data, kelp_diag *d);
/** Next event; *channel is a NUL-terminated copy of its channel, valid until the next call.
 *  @return 1 with an event, 0 at the end of the file, <0 on a read error. */
KELP_MUST_CHECK int kelp_lcmlog_next(kelp_lcmlog_reader *r, kelp_lcmlog_event *ev, const char **channel);
kelp_lcmlog_stats kelp_lcmlog_get_stats(const kelp_lcmlog_reader *r);
void kelp_lcmlog_close(kelp_lcmlog_reader *r);

#ifdef __cplusplus
}
#endif

#endif
