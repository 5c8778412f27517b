/* Fuzz: LCM log event parsing and resynchronisation over arbitrary bytes, the way
 * kelp-logcheck walks a log; every event found must lie inside the input. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/lcmlog.h>
#include <kelp/bus.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *buf = malloc(size ? size : 1); /* exact size: ASan sees any over-read */
    memcpy(buf, data, size);
    size_t pos = 0, steps = 0;
    static kelp_var v;
    while (pos < size) {
        kelp_lcmlog_event ev;
        size_t used = 0;
        int rc = kelp_lcmlog_parse(buf + pos, size - pos, 1 << 20, &ev, &used);
        if (rc == KELP_OK) {
            if (used < KELP_LCMLOG_HDR_LEN || used > size - pos || ev.data + ev.data_len > buf + size) abort();
            (void)kelp_var_decode(ev.data, ev.data_len, &v);
            pos += used;
        } else if (rc == KELP_ERR_PARSE) {
            size_t next = kelp_lcmlog_resync(buf, size, pos + 1);
            if (next <= pos || next > size) abort();
            pos = next;
        } else {
            break; /* partial: the end of the input */
        }
        if (++steps > size + 1) abort(); /* always progresses */
    }
    free(buf);
    return 0;
}
