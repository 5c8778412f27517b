/* kelp LCM log events (core): the byte layout lcm-logger writes, parsed and validated
 * without allocation. A log is a run of events, each
 *   u32 sync 0xEDA1DA01 | u64 event number | i64 timestamp (us) | u32 channel length |
 *   u32 data length | channel bytes | data bytes        (all big-endian)
 * A reader that meets bytes that are not an event skips to the next sync word and counts
 * what it skipped, so one damaged event costs that event only. */
#ifndef KELP_LCMLOG_H
#define KELP_LCMLOG_H
#include <stddef.h>
#include <stdint.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_LCMLOG_SYNC 0xEDA1DA01u
#define KELP_LCMLOG_HDR_LEN 28u
#define KELP_LCMLOG_MAX_CHANNEL 1024u /**< longer channel lengths mean a damaged event */

typedef struct kelp_lcmlog_event {
    uint64_t eventnum;
    int64_t timestamp;      /**< microseconds, as the logger wrote it */
    const uint8_t *channel; /**< not NUL-terminated; may be empty */
    size_t channel_len;
    const uint8_t *data;
    size_t data_len;
} kelp_lcmlog_event;

/** Parse the event at buf[0..len). max_data bounds the data length (larger is damage).
 *  @return KELP_OK with *ev and *used (bytes of the event);
 *          KELP_ERR_PARTIAL with *used = bytes the whole event needs (or the header) when
 *          buf holds only part of it;
 *          KELP_ERR_PARSE when buf does not start with a plausible event (no sync word,
 *          channel too long, data longer than max_data): resynchronise with
 *          kelp_lcmlog_resync. */
KELP_MUST_CHECK int kelp_lcmlog_parse(const uint8_t *buf, size_t len, size_t max_data, kelp_lcmlog_event *ev,
                                      size_t *used);

/** Offset in buf[from..len) of the next sync word, or of the last 3 bytes (a sync word may
 *  straddle the end) when there is none. */
size_t kelp_lcmlog_resync(const uint8_t *buf, size_t len, size_t from);

/** Write an event header for channel_len/data_len into out[KELP_LCMLOG_HDR_LEN]. */
void kelp_lcmlog_header(uint64_t eventnum, int64_t timestamp, size_t channel_len, size_t data_len,
                        uint8_t out[KELP_LCMLOG_HDR_LEN]);

#ifdef __cplusplus
}
#endif

#endif
