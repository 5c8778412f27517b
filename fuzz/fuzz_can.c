/* Fuzz kelp's CAN reassembler (kelp/can.h) and the text it is configured with.
 * Input: [mode byte] then bytes.
 *   mode % 3 == 0: a stream of frames, each [id: 4 bytes BE][len | 0x80 FD][dt: 1 byte, ms]
 *                  + len data bytes, fed to one receiver. Every frame must be counted in exactly
 *                  one of frames_ok / bad_frame / foreign / duplicate / slot_full, and a message
 *                  delivered must be well formed.
 *   mode % 3 == 1: the bytes are a value (string) sent under a name cut from them, classic or FD
 *                  (mode bit 2), its frames shuffled by the input: it must come back exactly.
 *   mode % 3 == 2: the bytes are a dictionary spec and a renaming list (parsers must not crash). */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/bridge.h>
#include <kelp/can.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static kelp_can_rx rx;
static kelp_can_tx tx;
static kelp_can_dict dict;

static void check_msg(const kelp_can_msg *m)
{
    if (!m->name || strlen(m->name) == 0 || strlen(m->name) >= KELP_CAN_NAME) abort();
    if (m->source && (strlen(m->source) == 0 || strlen(m->source) >= KELP_CAN_NAME)) abort();
    if (m->kind == KELP_CAN_KIND_STRING || m->kind == KELP_CAN_KIND_BINARY) {
        if (m->slen >= KELP_CAN_MAX_BODY || (m->slen && !m->sval)) abort();
    } else if (m->kind != KELP_CAN_KIND_F64) {
        abort();
    }
}

static void stream(const uint8_t *d, size_t n)
{
    double now = 0;
    size_t i = 0;
    while (i + 6 <= n) {
        kelp_can_frame f;
        memset(&f, 0, sizeof f);
        f.id = (uint32_t)d[i] << 24 | (uint32_t)d[i + 1] << 16 | (uint32_t)d[i + 2] << 8 | d[i + 3];
        f.fd = (d[i + 4] & 0x80u) != 0;
        f.len = d[i + 4] & 0x7Fu;
        now += d[i + 5] / 1000.0;
        i += 6;
        size_t take = f.len > 64 ? 64 : f.len;
        if (take > n - i) take = n - i;
        memcpy(f.data, d + i, take);
        i += take;
        kelp_can_msg m;
        if (kelp_can_rx_frame(&rx, &dict, &f, now, &m) == 1) check_msg(&m);
        const kelp_can_stats *s = &rx.st;
        if (s->frames != s->frames_ok + s->bad_frame + s->foreign + s->duplicate + s->slot_full) abort();
    }
}

typedef struct rec {
    kelp_can_frame f[64];
    int n;
} rec;

static int rec_emit(void *user, const kelp_can_frame *f)
{
    rec *r = user;
    if (r->n >= 64) abort(); /* a message never takes more than 64 frames */
    r->f[r->n++] = *f;
    return 0;
}

static void roundtrip(const uint8_t *d, size_t n, bool fd)
{
    static rec r;
    char name[KELP_CAN_NAME];
    size_t nl = n ? 1 + d[0] % 20 : 1;
    for (size_t i = 0; i < nl; i++) name[i] = (char)('A' + (i < n ? d[i] : 0) % 26);
    name[nl] = 0;
    if (kelp_can_tx_init(&tx, 1 + (n ? d[n - 1] : 0) % 127, fd) < 0) abort();
    kelp_can_msg m;
    memset(&m, 0, sizeof m);
    m.name = name;
    m.kind = KELP_CAN_KIND_BINARY;
    m.sval = d;
    m.slen = n;
    r.n = 0;
    int rc = kelp_can_send(&tx, &dict, &m, rec_emit, &r);
    if (rc == KELP_ERR_RANGE) return; /* too large for one message */
    if (rc < 1 || rc != r.n) abort();
    /* shuffle by the data (Fisher-Yates) */
    for (int i = r.n - 1; i > 0; i--) {
        int j = (int)(d[(size_t)i % n] % (unsigned)(i + 1));
        kelp_can_frame t = r.f[i];
        r.f[i] = r.f[j];
        r.f[j] = t;
    }
    kelp_can_rx_init(&rx, 1.0);
    int got = 0;
    for (int i = 0; i < r.n; i++) {
        kelp_can_msg out;
        rc = kelp_can_rx_frame(&rx, &dict, &r.f[i], 0, &out);
        if (rc < 0) abort();
        if (rc == 1) {
            got++;
            if (strcmp(out.name, name) != 0 || out.slen != n || (n && memcmp(out.sval, d, n) != 0)) abort();
        }
    }
    if (got != 1) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    uint8_t mode = data[0];
    data++;
    size--;
    kelp_can_dict_init(&dict);
    if (kelp_can_dict_add(&dict, 3, "THRUST_CMD") < 0 || kelp_can_dict_add(&dict, 7, "DEPTH") < 0) abort();
    switch (mode % 3) {
    case 0:
        kelp_can_rx_init(&rx, 0.05);
        stream(data, size);
        break;
    case 1:
        roundtrip(data, size, (mode & 4) != 0);
        break;
    default: {
        char text[512];
        size_t n = size < sizeof text - 1 ? size : sizeof text - 1;
        memcpy(text, data, n);
        text[n] = 0;
        kelp_diag why;
        kelp_diag_clear(&why);
        (void)kelp_can_dict_parse(&dict, text, &why);
        kelp_bridge_route r[16];
        size_t nr = 0;
        if (kelp_bridge_parse_rename(text, r, 16, &nr, &why) == 0 && (nr == 0 || nr > 16)) abort();
        break;
    }
    }
    return 0;
}
