/* Fuzz the acomms glue: the ACOMMS_* TextFormat parsers (with a print/parse round trip), the
 * pAcommsHandler configuration reader, and a node with the WHOI driver fed arbitrary modem
 * bytes.  The first input byte picks the target. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/edge/mission.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void round_trip(const char *t, size_t n)
{
    static kelp_acomms_msg m, back;
    static char buf[KELP_ACOMMS_MAX_PRINT];
    if (kelp_acomms_parse_data(t, n, &m, NULL) != KELP_OK) return;
    if (kelp_acomms_print_data(&m, buf, sizeof buf, NULL) != KELP_OK) abort();
    if (kelp_acomms_parse_data(buf, strlen(buf), &back, NULL) != KELP_OK) abort();
    if (back.len != m.len || memcmp(back.data, m.data, m.len) != 0 || back.src != m.src || back.dest != m.dest)
        abort();
}

static void node_feed(const uint8_t *d, size_t n)
{
    static kelp_acomms_node node;
    static kelp_queue qs[4];
    static kelp_queue_entry pool[16];
    kelp_acomms_node_cfg c;
    kelp_acomms_node_cfg_default(&c);
    c.modem_id = 1;
    c.driver = KELP_ACOMMS_DRIVER_WHOI_MICROMODEM;
    if (kelp_acomms_node_init(&node, &c, qs, 4, pool, 16, NULL, NULL) != KELP_OK) abort();
    const kelp_time t0 = 1704196800.0;
    kelp_queue_cfg q;
    kelp_queue_cfg_default(&q, KELP_QUEUE_CCL, 2);
    if (kelp_acomms_node_add_queue(&node, &q, t0) != KELP_OK) abort();
    if (kelp_acomms_node_start(&node, t0) != KELP_OK) abort();
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    m.dest = 2;
    m.len = 4;
    m.data[0] = 2;
    m.key.type = KELP_QUEUE_CCL;
    m.key.id = 2;
    (void)kelp_acomms_node_push(&node, &m, t0);
    kelp_time t = t0;
    size_t off = 0;
    while (off < n) {
        size_t k = n - off < 37 ? n - off : 37;
        (void)kelp_acomms_node_feed(&node, d + off, k, t);
        t += 0.7;
        (void)kelp_acomms_node_tick(&node, t);
        (void)kelp_acomms_node_transmit(&node, 1, 2, (unsigned)(d[off] % 6), t);
        off += k;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    const char *t = (const char *)data + 1;
    size_t n = size - 1;
    switch (data[0] % 5) {
    case 0: round_trip(t, n); break;
    case 1: {
        static kelp_acomms_mac_update u;
        (void)kelp_acomms_parse_mac_update(t, n, &u, NULL);
        break;
    }
    case 2: {
        kelp_acomms_range_req r;
        (void)kelp_acomms_parse_range_req(t, n, &r, NULL);
        break;
    }
    case 3: {
        static kelp_mission_file mf;
        static kelp_acomms_config cfg;
        char warn[256];
        if (kelp_mission_load_text(&mf, "fuzz.moos", t, n) == KELP_OK) {
            int b = kelp_mission_block(&mf.m, "ProcessConfig", "pAcommsHandler");
            (void)kelp_acomms_config_read(&mf.m, b, NULL, &cfg, NULL, warn, sizeof warn);
        }
        kelp_mission_free(&mf);
        break;
    }
    default: node_feed((const uint8_t *)t, n); break;
    }
    return 0;
}
