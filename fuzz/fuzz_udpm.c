/* Fuzz: raw UDP multicast datagrams (LCM short and fragment forms) into the reassembler.
 * The input is a sequence of records: u8 sender, u16 length, bytes. Each datagram is an
 * exact-size heap copy so ASan sees any over-read; time advances 0.25 s per datagram so
 * timeouts run too. A complete message must lie within the slot or the datagram. Then the
 * whole input, framed by kelp_udpm_datagram in small fragments and fed in reverse order,
 * must come back byte for byte. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/udpm.h>

#define NSLOT 3
#define CAP 2048

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kelp_udpm_rx rx;
    static kelp_udpm_slot slots[NSLOT];
    static uint8_t mem[NSLOT * CAP];
    if (kelp_udpm_init(&rx, slots, NSLOT, mem, CAP, 1.0) != 0) abort();
    double now = 0;
    size_t i = 0;
    kelp_udpm_msg m;
    while (i + 3 <= size) {
        uint8_t sender = data[i];
        size_t len = (size_t)data[i + 1] << 8 | data[i + 2];
        i += 3;
        if (len > size - i) len = size - i;
        uint8_t *dg = malloc(len ? len : 1);
        memcpy(dg, data + i, len);
        i += len;
        if (kelp_udpm_feed(&rx, dg, len, sender, now, &m) == 1) {
            if (strlen(m.channel) == 0 || strlen(m.channel) > KELP_UDPM_MAX_CHANNEL) abort();
            if (m.fragmented ? m.len > CAP : (m.data < dg || m.data + m.len > dg + len)) abort();
        }
        free(dg);
        now += 0.25;
    }
    /* round trip: the input as a payload on channel "F", 64-byte datagrams, reversed */
    size_t plen = size < CAP ? size : CAP;
    uint16_t n = 0;
    if (kelp_udpm_plan(1, plen, 64, &n) != 0) abort();
    int count = n ? n : 1, done = 0;
    for (int k = count - 1; k >= 0; k--) {
        uint8_t dg[64];
        size_t len = 0;
        if (kelp_udpm_datagram("F", data, plen, 7, 64, (uint16_t)k, dg, sizeof dg, &len) != 0) abort();
        int rc = kelp_udpm_feed(&rx, dg, len, 999, now, &m);
        if (rc < 0) abort();
        if (rc == 1) {
            if (k != 0 || m.len != plen || strcmp(m.channel, "F") || (plen && memcmp(m.data, data, plen))) abort();
            done = 1;
        }
    }
    if (!done) abort();
    return 0;
}
