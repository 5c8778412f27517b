/* Fuzz the NMEA reader/parser and the Micro-Modem driver state machine with arbitrary modem bytes.
 * Input: raw bytes as read from the serial line; the first byte picks options (Hydroid prefix,
 * time steps) so both paths get exercised. */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <kelp/mmdriver.h>
#include <kelp/nmea.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void w(const char *b, size_t n, void *u) { (void)b; (void)n; (void)u; }
static void ev(const kelp_mmdriver_event *e, void *u)
{
    (void)u;
    /* touch what the event points at so ASan sees bad pointers */
    volatile size_t sum = 0;
    for (size_t i = 0; i < e->raw_len; i++) sum += (unsigned char)e->raw[i];
    for (size_t i = 0; i < e->data_len; i++) sum += e->data[i];
    (void)sum;
}
static void dr(const kelp_mmdriver_data_request *req, kelp_mmdriver_frame *f, void *u)
{
    (void)u;
    if (req->frame < 2) {
        f->src = req->src;
        f->dest = 2;
        f->ack_requested = true;
        f->len = req->max_bytes;
        memset(f->data, 0x20, f->len);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0) return 0;
    static kelp_mmdriver mm;
    static kelp_nmea_reader rd;
    static kelp_nmea_sentence s;
    kelp_mmdriver_cfg c;
    memset(&c, 0, sizeof c);
    c.modem_id = 1;
    c.hydroid_gateway_id = (data[0] & 1) ? 1 : 0;
    c.reset_nvram = (data[0] & 2) != 0;
    c.nvram_cfg[0] = "cst,1";
    c.n_nvram = 1;
    kelp_mmdriver_ops ops = { w, ev, dr };
    if (kelp_mmdriver_init(&mm, &c, &ops, NULL) != KELP_OK) return 0;
    int64_t t = 1704196800LL * 1000000LL; /* whole microseconds; the driver takes seconds */
    if (kelp_mmdriver_start(&mm, (kelp_time)t / 1e6) != KELP_OK) return 0;
    kelp_nmea_reader_init(&rd, (data[0] & 4) ? '\n' : 0);
    int64_t step = (int64_t)(data[0] >> 3) * 250000;
    size_t chunk = 1 + (data[0] & 7) * 9;
    for (size_t i = 1; i < size; i += chunk) {
        size_t n = size - i < chunk ? size - i : chunk;
        for (size_t k = 0; k < n; k++) (void)kelp_nmea_reader_feed_sentence(&rd, data[i + k], &s);
        (void)kelp_mmdriver_feed(&mm, data + i, n, (kelp_time)t / 1e6);
        t += step;
        if (kelp_mmdriver_tick(&mm, (kelp_time)t / 1e6) == KELP_ERR_TIMEOUT) (void)kelp_mmdriver_start(&mm, (kelp_time)t / 1e6);
        if ((data[i] & 0x3f) == 0x3f) (void)kelp_mmdriver_initiate_transmission(&mm, 1, -1, data[i] >> 6, (kelp_time)t / 1e6);
    }
    return 0;
}
