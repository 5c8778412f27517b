/* acomms glue benchmark: TextFormat print+parse of a full 256-byte ModemDataTransmission, and a
 * node (DRIVER_NONE, ideal channel) running TDMA slots with a busy queue. */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <kelp/acomms.h>

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
}

static unsigned long delivered;
static void ev(const kelp_acomms_event *e, void *u)
{
    (void)u;
    if (e->kind == KELP_ACOMMS_EV_QUEUE && (e->q->kind == KELP_QUEUE_EV_ACK || e->q->kind == KELP_QUEUE_EV_RECEIVE))
        delivered++;
}

int main(void)
{
    static char buf[KELP_ACOMMS_MAX_PRINT];
    kelp_acomms_msg m, back;
    memset(&m, 0, sizeof m);
    for (int i = 0; i < 256; i++) m.data[i] = (uint8_t)(i * 7);
    m.len = 256;
    m.src = 1;
    m.dest = 2;
    m.has_time = true;
    m.time = 1295698086.887950;
    m.key.type = KELP_QUEUE_DCCL;
    m.key.id = 20;
    const int N = 20000;
    double t0 = now_s();
    size_t len = 0;
    for (int i = 0; i < N; i++) {
        if (kelp_acomms_print_data(&m, buf, sizeof buf, &len) != KELP_OK) return 1;
        if (kelp_acomms_parse_data(buf, len, &back, NULL) != KELP_OK) return 1;
    }
    double dt = now_s() - t0;
    printf("textformat: print+parse of a 256-byte ModemDataTransmission (%zu chars): %.2f us per round trip\n", len,
           dt / N * 1e6);

    static kelp_acomms_node n;
    static kelp_queue qs[4];
    static kelp_queue_entry pool[512];
    kelp_acomms_node_cfg c;
    kelp_acomms_node_cfg_default(&c);
    c.modem_id = 1;
    c.loopback_channel = true;
    kelp_mac_slot s;
    kelp_mac_slot_default(&s, 1);
    s.dest = 2;
    s.rate = 5; /* 8 frames of 256 bytes per slot */
    s.slot_seconds = 1;
    c.mac.type = KELP_MAC_FIXED_DECENTRALIZED;
    c.mac.slots = &s;
    c.mac.nslots = 1;
    kelp_acomms_node_ops ops = { NULL, ev, NULL };
    if (kelp_acomms_node_init(&n, &c, qs, 4, pool, 512, &ops, NULL) != KELP_OK) return 1;
    const kelp_time T = 1704196800.0;
    kelp_queue_cfg q;
    kelp_queue_cfg_default(&q, KELP_QUEUE_DCCL, 20);
    if (kelp_acomms_node_add_queue(&n, &q, T) || kelp_acomms_node_start(&n, T)) return 1;
    uint8_t hdr[6] = { 0x20, 0x0a, 0x2a, 0x30, 0x08, 0x00 }; /* id 20 to modem 2 */
    memset(&m, 0, sizeof m);
    memcpy(m.data, hdr, 6);
    memset(m.data + 6, 0x5a, 26);
    m.len = 32;
    m.dest = 2;
    m.key = q.key;
    unsigned long pushed = 0;
    const int SECONDS = 2000;
    t0 = now_s();
    for (int sec = 1; sec <= SECONDS; sec++) {
        for (int k = 0; k < 60; k++, pushed++) {
            m.has_time = true;
            m.time = T + sec;
            if (kelp_acomms_node_push(&n, &m, m.time) != KELP_OK) return 1;
        }
        for (int tick = 1; tick <= 10; tick++)
            if (kelp_acomms_node_tick(&n, T + sec + tick * 0.1) != KELP_OK) return 1;
    }
    dt = now_s() - t0;
    printf("node: %d simulated s at AppTick 10, %lu messages pushed, %lu acknowledged through %u frames (rate 5 "
           "slots, stitched): %.3f s wall, %.2f us per tick, %.2f us per message\n",
           SECONDS, pushed, delivered, n.count.frames_out, dt, dt / (SECONDS * 10) * 1e6, dt / (double)delivered * 1e6);
    return delivered > 0 ? 0 : 1;
}
