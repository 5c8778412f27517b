/* acomms core throughput: queue contest + stitching, unstitching, NMEA parsing, driver line handling. */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <kelp/mmdriver.h>
#include <kelp/nmea.h>
#include <kelp/queue.h>

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec / 1e9;
}

static kelp_queue qs[16];
static kelp_queue_entry pool[512];
static void nop_w(const char *b, size_t n, void *u) { (void)b; (void)n; (void)u; }

int main(void)
{
    const kelp_time T = 1704196800.0;
    kelp_queue_mgr m;
    if (kelp_queue_init(&m, 1, qs, 16, pool, 512, NULL, NULL, NULL)) return 1;
    for (unsigned id = 1; id <= 16; id++) {
        kelp_queue_cfg c;
        kelp_queue_cfg_default(&c, KELP_QUEUE_DCCL, id);
        c.ack = false;
        c.value_base = id;
        if (kelp_queue_add(&m, &c, T)) return 1;
    }
    kelp_acomms_msg msg, out;
    memset(&msg, 0, sizeof msg);
    msg.len = 32;
    msg.data[0] = 0x20;
    msg.dest = 2;
    msg.key.type = KELP_QUEUE_DCCL;
    int N = 200000;
    double t0 = now_s();
    long frames = 0, bytes = 0;
    for (int i = 0; i < N; i++) {
        for (unsigned id = 1; id <= 8; id++) {
            msg.key.id = id;
            msg.data[1] = (uint8_t)(id >> 1);
            msg.data[2] = (uint8_t)(id << 7);
            if (kelp_queue_push(&m, &msg, T)) return 1;
        }
        kelp_queue_request r = { -1, 0, 256 };
        if (kelp_queue_data_request(&m, &r, T + i * 0.001, &out)) return 1;
        frames++;
        bytes += (long)out.len;
        for (unsigned id = 1; id <= 16; id++) {
            kelp_queue_key k = { KELP_QUEUE_DCCL, id };
            if (kelp_queue_flush(&m, k)) return 1;
        }
    }
    double t1 = now_s();
    printf("queue: push 8 + 16-queue contest + stitch 256-byte frame: %.2f us/frame (%ld B avg)\n",
           (t1 - t0) / N * 1e6, bytes / frames);
    t0 = now_s();
    int pieces = 0;
    for (int i = 0; i < N * 5; i++) pieces += kelp_queue_unstitch(out.data, out.len, NULL, NULL);
    t1 = now_s();
    printf("unstitch 256-byte frame (%d pieces): %.3f us/frame\n", pieces / (N * 5), (t1 - t0) / (N * 5) * 1e6);

    const char *line = "$CACST,1,153026.0000,0,4105,30,0318,0193,10,00,00,01,01,2,004,004,3,3,3,1,154,09,08,10,-6,000,0.0,4125000,5000*5B";
    kelp_nmea_sentence s;
    size_t ll = strlen(line);
    t0 = now_s();
    for (int i = 0; i < N * 5; i++)
        if (kelp_nmea_parse(line, ll, &s)) return 1;
    t1 = now_s();
    printf("nmea: parse+verify %zu-char $CACST: %.3f us/line (%.1f MB/s)\n", ll, (t1 - t0) / (N * 5) * 1e6,
           ll * (double)N * 5 / (t1 - t0) / 1e6);

    static kelp_mmdriver mm;
    kelp_mmdriver_cfg c;
    memset(&c, 0, sizeof c);
    c.modem_id = 1;
    kelp_mmdriver_ops ops = { nop_w, NULL, NULL };
    if (kelp_mmdriver_init(&mm, &c, &ops, NULL) || kelp_mmdriver_start(&mm, T)) return 1;
    char rx[600];
    strcpy(rx, "$CARXD,2,1,0,1,");
    for (int i = 0; i < 256; i++) strcat(rx, "a5");
    kelp_nmea_writer wr;
    char full[640];
    size_t fl;
    kelp_nmea_writer_init(&wr, full, sizeof full, rx);
    if (kelp_nmea_writer_finish(&wr, &fl)) return 1;
    full[fl++] = '\r';
    full[fl++] = '\n';
    int M = 50000;
    t0 = now_s();
    for (int i = 0; i < M; i++)
        if (kelp_mmdriver_feed(&mm, (const uint8_t *)full, fl, T + 2)) return 1;
    t1 = now_s();
    printf("mmdriver: feed a 256-byte $CARXD (%zu bytes): %.2f us/line (%.1f MB/s; a 19200-baud link is 0.002 MB/s)\n",
           fl, (t1 - t0) / M * 1e6, fl * (double)M / (t1 - t0) / 1e6);
    printf("sizes: kelp_mmdriver %zu B, kelp_mac %zu B, kelp_queue_entry %zu B, kelp_queue_mgr %zu B\n", sizeof(kelp_mmdriver),
           sizeof(kelp_mac), sizeof(kelp_queue_entry), sizeof(kelp_queue_mgr));
    return 0;
}
