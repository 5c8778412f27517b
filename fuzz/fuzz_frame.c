/* Fuzz received modem frames (unstitching, CCL/DCCL routing) and the stitch/unstitch round trip.
 * Input: [mode byte] then bytes.  Mode bit 0 clear: the bytes are one received frame.
 * Mode bit 0 set: the bytes are cut into up to 4 DCCL messages that are queued, stitched into one
 * frame by the queue, and unstitched by a second manager: every piece must equal a pushed message
 * (flags cleared), byte for byte. */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/queue.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static kelp_acomms_msg pushed[4];
static int npushed;
static int bad;

static void rx_check(const kelp_queue_event *ev, void *u)
{
    (void)u;
    if (ev->kind != KELP_QUEUE_EV_RECEIVE) return;
    bool found = false;
    for (int i = 0; i < npushed; i++) {
        kelp_acomms_msg m = pushed[i];
        m.data[5] &= (uint8_t)~0x0C;
        if (m.len == ev->msg->len && memcmp(m.data, ev->msg->data, m.len) == 0) found = true;
    }
    if (!found) bad++;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kelp_queue qa[8], qb[8];
    static kelp_queue_entry pa[16], pb[16];
    kelp_queue_mgr a, b;
    if (size < 1) return 0;
    const kelp_time t = 1704196800.0;
    if (kelp_queue_init(&a, 1, qa, 8, pa, 16, NULL, NULL, NULL) != KELP_OK) abort();
    if (kelp_queue_init(&b, 2, qb, 8, pb, 16, rx_check, NULL, NULL) != KELP_OK) abort();
    for (unsigned id = 1; id <= 4; id++) {
        kelp_queue_cfg c;
        kelp_queue_cfg_default(&c, KELP_QUEUE_DCCL, id);
        c.ack = (id & 1) != 0;
        if (kelp_queue_add(&a, &c, t) || kelp_queue_add(&b, &c, t)) abort();
    }
    kelp_queue_cfg c;
    kelp_queue_cfg_default(&c, KELP_QUEUE_CCL, 14);
    if (kelp_queue_add(&b, &c, t)) abort();
    npushed = 0;
    bad = 0;
    if (!(data[0] & 1)) {
        kelp_acomms_msg f;
        memset(&f, 0, sizeof f);
        f.src = 3;
        f.dest = data[0] >> 1 & 3;
        f.len = size - 1 > KELP_MAX_ACOMMS_FRAME ? KELP_MAX_ACOMMS_FRAME : size - 1;
        memcpy(f.data, data + 1, f.len);
        (void)kelp_queue_receive(&b, &f);
        return 0;
    }
    /* build up to 4 messages for ids 1..4 addressed to 2 or broadcast */
    size_t p = 1;
    for (unsigned id = 1; id <= 4 && p < size; id++) {
        size_t body = data[p++] % 60;
        if (p + body > size) body = size - p;
        kelp_acomms_msg m;
        memset(&m, 0, sizeof m);
        kelp_queue_header h = { KELP_DCCL_CCL_ID, id, 100, 1, (id & 2) ? 0u : 2u, false, false, 0 };
        kelp_queue_header_write(&h, m.data);
        memcpy(m.data + 6, data + p, body);
        p += body;
        m.len = 6 + body;
        m.dest = (int)h.dest;
        m.key.type = KELP_QUEUE_DCCL;
        m.key.id = id;
        if (kelp_queue_push(&a, &m, t) != KELP_OK) abort();
        pushed[npushed++] = m;
    }
    kelp_queue_request r = { -1, 0, (data[0] & 2) ? 256u : 64u };
    kelp_acomms_msg out;
    if (kelp_queue_data_request(&a, &r, t + 1, &out) != KELP_OK) abort();
    if (out.len > r.max_bytes) abort();
    out.dest = 2;
    int n = kelp_queue_receive(&b, &out);
    if (out.len && n < 1) abort();
    if (bad) abort();
    return 0;
}
