/* Fuzz: kelp's validating decoders for bus datagrams (var, sync request, bridge frame)
 * and kelp_bus_receive on a loopback client. The first byte picks the channel kind. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/bus.h>
#include <kelp/bridge.h>

static int fake_hmac(const uint8_t *key, size_t keylen, const uint8_t *data, size_t len, uint8_t out[32], void *user)
{
    (void)user;
    memset(out, 0, 32);
    for (size_t i = 0; i < len; i++) out[i % 32] ^= (uint8_t)(data[i] + key[i % keylen]);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kelp_var v;
    static kelp_sync_req q;
    if (size < 1) return 0;
    uint8_t sel = data[0];
    const uint8_t *d = data + 1;
    size_t n = size - 1;
    /* exact-size heap copies so ASan sees any over-read */
    uint8_t *buf = malloc(n ? n : 1);
    memcpy(buf, d, n);
    if (kelp_var_decode(buf, n, &v) == 0) {
        /* a decoded var re-encodes and decodes to the same fields (the encoder writes the
         * unused value slots as zero, so bytes may differ from a foreign encoder's) */
        static kelp_var w;
        uint8_t out[16384];
        size_t len = 0;
        if (kelp_var_encode(&v, out, sizeof out, &len) != 0 || len > n) abort();
        if (kelp_var_decode(out, len, &w) != 0) abort();
        if (strcmp(w.name, v.name) || w.kind != v.kind || w.slen != v.slen || memcmp(w.sval, v.sval, v.slen) ||
            (v.kind == KELP_VAR_DOUBLE && memcmp(&w.dval, &v.dval, sizeof w.dval)))
            abort();
    }
    (void)kelp_bus_sync_req_decode(buf, n, &q);
    {
        /* bridge frames through a receiver whose peer table persists across inputs */
        static kelp_bridge_peer peers[3];
        static kelp_bridge_rx brx;
        static int binit;
        if (!binit) kelp_bridge_rx_init(&brx, peers, 3), binit = 1;
        (void)kelp_bridge_unframe(&brx, buf, n, (const uint8_t *)"k", sel & 1, fake_hmac, NULL, &v);
        if (brx.n > 3) abort();
        (void)kelp_bridge_allowed((sel & 2) ? "NAV_*, X" : "", v.name);
    }

    static kelp_loopback net;
    static kelp_bus bus;
    static kelp_bus_sub subs[4];
    static kelp_var cache[4];
    static kelp_var rx;
    static uint8_t scratch[20000];
    static kelp_loopback_port port;
    static int init;
    if (!init) {
        kelp_bus_transport tr;
        kelp_loopback_init(&net);
        kelp_loopback_transport(&net, &port, &tr);
        kelp_bus_storage st = { subs, 4, cache, 4, scratch, sizeof scratch, &rx };
        if (kelp_bus_init(&bus, "fuzz", "c", "KELP_SYNC_fuzz", &tr, &st, NULL, NULL) != 0) abort();
        if (kelp_bus_retain_all(&bus, 0) != 0) abort();
        if (kelp_loopback_attach(&net, &bus) != 0) abort();
        init = 1;
    }
    static const char *const chans[] = { "X", KELP_BUS_SYNC_CHANNEL, "KELP_SYNC_fuzz", "KELP_SYNC_other", "NAV_X" };
    (void)kelp_bus_receive(&bus, chans[sel % 5], buf, n, 1.0);
    free(buf);
    return 0;
}
