/* Fuzz the Micro-Modem simulator: the bus packet decoder (with a re-encode round trip that must
 * reproduce the input exactly) and the modem's host side fed arbitrary bytes, with two modems on
 * one channel so that whatever the host makes them send is heard and decided too.
 * Input: byte 0 picks the mode (even: host bytes; odd: a channel packet, then host bytes from
 * the rest of the input are skipped). */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/modemsim.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static kelp_modemsim mods[2];
static int64_t now; /* whole microseconds; the simulator takes kelp_time seconds */
#define SEC(us) ((kelp_time)(us) / 1e6)
static uint8_t enc[KELP_MODEMSIM_PKT_MAX_ENCODED];

static void w(const char *b, size_t n, void *u)
{
    (void)u;
    volatile size_t sum = 0;
    for (size_t i = 0; i < n; i++) sum += (unsigned char)b[i];
    (void)sum;
    if (n < 2 || b[n - 2] != '\r' || b[n - 1] != '\n') abort(); /* every line ends in CRLF */
}

static void tx(const kelp_modemsim_pkt *p, void *u)
{
    (void)u;
    size_t len;
    kelp_modemsim_pkt q;
    /* what a modem transmits always encodes and decodes */
    if (kelp_modemsim_pkt_encode(p, enc, sizeof enc, &len) != KELP_OK) abort();
    if (kelp_modemsim_pkt_decode(enc, len, &q) != KELP_OK) abort();
    for (int i = 0; i < 2; i++) (void)kelp_modemsim_hear(&mods[i], &q, SEC(now));
}

static void ev(const kelp_modemsim_event *e, void *u)
{
    (void)u;
    volatile size_t sum = strlen(e->text);
    if (e->pkt) sum += e->pkt->nframes;
    (void)sum;
}

static const kelp_modemsim_ops OPS = { w, tx, ev };

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    now = 1297857600LL * 1000000LL;
    for (int i = 0; i < 2; i++) {
        kelp_modemsim_cfg c;
        kelp_modemsim_cfg_default(&c);
        c.modem_id = i + 1;
        c.instance = (uint32_t)i + 1;
        c.x = i * 300.0;
        c.loss_probability = (data[0] & 2) ? 0.5 : 0.0;
        c.n_lbl = 1;
        c.lbl_x[0] = 500;
        if (kelp_modemsim_init(&mods[i], &c, &OPS, NULL, SEC(now)) != KELP_OK) abort();
    }
    if (data[0] & 1) {
        kelp_modemsim_pkt p;
        if (kelp_modemsim_pkt_decode(data + 1, size - 1, &p) == KELP_OK) {
            size_t len;
            if (kelp_modemsim_pkt_encode(&p, enc, sizeof enc, &len) != KELP_OK) abort();
            if (len != size - 1 || memcmp(enc, data + 1, len) != 0) abort(); /* canonical encoding */
            p.start = SEC(now);
            (void)kelp_modemsim_hear(&mods[0], &p, SEC(now));
            for (int k = 0; k < 40; k++) {
                now += 250000;
                kelp_modemsim_tick(&mods[0], SEC(now));
            }
        }
        return 0;
    }
    /* host bytes in chunks, with time passing between them */
    size_t off = 1;
    while (off < size) {
        size_t n = size - off < 64 ? size - off : 64;
        if (kelp_modemsim_feed(&mods[0], data + off, n, SEC(now)) != KELP_OK) abort();
        off += n;
        for (int k = 0; k < 4; k++) {
            now += 100000;
            for (int i = 0; i < 2; i++) kelp_modemsim_tick(&mods[i], SEC(now));
        }
    }
    for (int k = 0; k < 100; k++) {
        now += 200000;
        for (int i = 0; i < 2; i++) kelp_modemsim_tick(&mods[i], SEC(now));
    }
    return 0;
}
