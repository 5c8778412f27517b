/* kelp edge: LCM log files read through the core parser (see kelp/edge/lcmlog.h). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/edge/lcmlog.h>

struct kelp_lcmlog_reader {
    FILE *f;
    uint8_t *buf;
    size_t cap, start, end, max_data;
    bool eof;
    char chan[KELP_LCMLOG_MAX_CHANNEL + 1];
    kelp_lcmlog_stats st;
};

kelp_lcmlog_reader *kelp_lcmlog_open(const char *path, size_t max_data, kelp_diag *d)
{
    kelp_lcmlog_reader *r = calloc(1, sizeof *r);
    if (!r) {
        (void)kelp_fail(d, KELP_ERR_IO, "out of memory");
        return NULL;
    }
    r->max_data = max_data ? max_data : (size_t)64 << 20;
    r->cap = 1 << 16;
    r->buf = malloc(r->cap);
    r->f = fopen(path, "rb");
    if (!r->buf || !r->f) {
        (void)kelp_failf(d, KELP_ERR_IO, "cannot open %s: %s", path, r->buf ? strerror(errno) : "out of memory");
        kelp_lcmlog_close(r);
        return NULL;
    }
    return r;
}

/* Make room for `need` bytes from start and read what the file has. */
static int fill(kelp_lcmlog_reader *r, size_t need)
{
    if (r->start > 0) {
        memmove(r->buf, r->buf + r->start, r->end - r->start);
        r->end -= r->start;
        r->start = 0;
    }
    if (need > r->cap) {
        size_t nc = r->cap;
        while (nc < need) nc *= 2;
        uint8_t *nb = realloc(r->buf, nc);
        if (!nb) return -1;
        r->buf = nb;
        r->cap = nc;
    }
    size_t got = fread(r->buf + r->end, 1, r->cap - r->end, r->f);
    r->end += got;
    if (got == 0) {
        if (ferror(r->f)) return -1;
        r->eof = true;
    }
    return 0;
}

int kelp_lcmlog_next(kelp_lcmlog_reader *r, kelp_lcmlog_event *ev, const char **channel)
{
    for (;;) {
        size_t used = 0;
        int rc = kelp_lcmlog_parse(r->buf + r->start, r->end - r->start, r->max_data, ev, &used);
        if (rc == KELP_OK) {
            memcpy(r->chan, ev->channel, ev->channel_len);
            r->chan[ev->channel_len] = 0;
            *channel = r->chan;
            r->start += used;
            r->st.events++;
            return 1;
        }
        if (rc == KELP_ERR_PARTIAL) {
            if (r->eof) {
                if (r->end > r->start) {
                    r->st.truncated = true;
                    r->st.skipped_bytes += r->end - r->start;
                    r->start = r->end;
                }
                return 0;
            }
            if (fill(r, used) < 0) return KELP_ERR_IO;
            continue;
        }
        /* damaged: skip to the next sync word, reading on while none is in the buffer */
        r->st.damaged++;
        size_t from = r->start + 1;
        for (;;) {
            size_t at = kelp_lcmlog_resync(r->buf, r->end, from);
            r->st.skipped_bytes += at - r->start;
            r->start = at;
            if (r->end - r->start >= 4 || r->eof) break;
            if (fill(r, 4) < 0) return KELP_ERR_IO;
            from = r->start;
            if (r->eof && r->end - r->start < 4) break;
        }
        if (r->eof && r->end - r->start < 4) {
            r->st.skipped_bytes += r->end - r->start;
            r->start = r->end;
            return 0;
        }
    }
}

kelp_lcmlog_stats kelp_lcmlog_get_stats(const kelp_lcmlog_reader *r)
{
    return r->st;
}

void kelp_lcmlog_close(kelp_lcmlog_reader *r)
{
    if (!r) return;
    if (r->f) fclose(r->f);
    free(r->buf);
    free(r);
}
