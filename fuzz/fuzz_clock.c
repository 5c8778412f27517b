/* Fuzz the time step rule (docs/ARCHITECTURE.md) in the acomms trio: arbitrary `now` sequences
 * (steps both ways, repeats, NaN, infinities, absurd magnitudes) fed to a TDMA MAC, a priority
 * queue and a Micro-Modem driver.  Invariants: a tick instant starts at most one slot, a slot
 * starts only within its own time, a queue's priority is never negative at the `now` it last saw.
 * Input: records of 3 bytes (op, then a little-endian int16 d):
 *   op % 4 == 0: now += d * 0.01 s; 1: now += d * 60 s (steps of up to 22 days either way);
 *   op % 4 == 2: a refused time (NaN, +inf, -inf or 1e300 by d % 4), the clock unchanged;
 *   op % 4 == 3: now = T0 + d s.  Then op / 4 % 4 picks the call: 0 tick everything, 1 push
 *   and data request, 2 driver bytes ($CAREV / $CACLK answers), 3 a MAC update. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/mac.h>
#include <kelp/mmdriver.h>
#include <kelp/queue.h>
#include <kelp/util.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const kelp_time T0 = 1704196800.0; /* 2024-01-02 12:00:00 UTC */
static kelp_mac mac;
static kelp_queue qs[2];
static kelp_queue_entry pool[8];
static kelp_queue_mgr qm;
static kelp_mmdriver mm;

static void w(const char *b, size_t n, void *u)
{
    (void)u;
    volatile size_t sum = 0;
    for (size_t i = 0; i < n; i++) sum += (unsigned char)b[i];
    (void)sum;
}

static const kelp_mmdriver_ops OPS = { w, NULL, NULL };

static void tick_mac(kelp_time now)
{
    kelp_mac_action a;
    int started = 0;
    while (kelp_mac_tick(&mac, now, &a) == KELP_OK) {
        if (++started > 1) abort(); /* a burst of slots at one instant */
        /* the MAC compares whole microseconds (as Goby), so this does too */
        unsigned len = mac.slot[a.slot_index < mac.n ? a.slot_index : 0].slot_seconds;
        long long now_us = llround(now * 1e6), start_us = llround(a.slot_start * 1e6);
        if (now_us < start_us || now_us >= start_us + (long long)(len ? len : 1) * 1000000LL) abort(); /* outside its slot */
    }
}

static void check_priority(kelp_time now)
{
    kelp_queue_key key = { KELP_QUEUE_DCCL, 10 };
    double p;
    if (kelp_queue_priority(&qm, key, now, &p) == KELP_OK && !(p >= 0.0)) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    kelp_mac_slot sl[3];
    for (int i = 0; i < 3; i++) {
        kelp_mac_slot_default(&sl[i], i == 1 ? 2 : 1);
        sl[i].slot_seconds = (unsigned)(i + 1) * 5;
    }
    kelp_mac_cfg mc;
    kelp_mac_cfg_default(&mc);
    mc.type = KELP_MAC_FIXED_DECENTRALIZED;
    mc.modem_id = 1;
    mc.slots = sl;
    mc.nslots = 3;
    if (kelp_mac_init(&mac, &mc, T0) != KELP_OK) abort();
    if (kelp_queue_init(&qm, 1, qs, 2, pool, 8, NULL, NULL, NULL) != KELP_OK) abort();
    kelp_queue_cfg qc;
    kelp_queue_cfg_default(&qc, KELP_QUEUE_DCCL, 10);
    qc.blackout_time = 10;
    qc.ttl = 100;
    qc.max_queue = 4;
    if (kelp_queue_add(&qm, &qc, T0) != KELP_OK) abort();
    kelp_mmdriver_cfg dc;
    memset(&dc, 0, sizeof dc);
    dc.modem_id = 1;
    dc.reset_nvram = true;
    if (kelp_mmdriver_init(&mm, &dc, &OPS, NULL) != KELP_OK) abort();
    if (kelp_mmdriver_start(&mm, T0) != KELP_OK) abort();

    kelp_time now = T0;
    for (size_t i = 0; i + 3 <= size; i += 3) {
        uint8_t op = data[i];
        int16_t d = (int16_t)(uint16_t)(data[i + 1] | (data[i + 2] << 8));
        kelp_time t;
        switch (op % 4) {
        case 0: t = now += d * 0.01; break;
        case 1: t = now += d * 60.0; break;
        case 2: {
            static const double BAD[4] = { NAN, INFINITY, -INFINITY, 1e300 };
            t = BAD[(unsigned)d % 4u];
            break;
        }
        default: t = now = T0 + d; break;
        }
        bool ok = kelp_util_time_ok(t);
        kelp_acomms_msg m, out;
        switch (op / 4 % 4) {
        case 0: {
            tick_mac(t);
            kelp_queue_do_work(&qm, t);
            if (ok) check_priority(t);
            int rc = kelp_mmdriver_tick(&mm, t);
            if (!ok && rc != KELP_ERR_ARG) abort();
            break;
        }
        case 1: {
            memset(&m, 0, sizeof m);
            kelp_queue_header h = { KELP_DCCL_CCL_ID, 10, 43200, 1, 0, false, false, 0 };
            kelp_queue_header_write(&h, m.data);
            m.data[6] = op;
            m.len = 7;
            m.key.type = KELP_QUEUE_DCCL;
            m.key.id = 10;
            m.has_time = ok;
            m.time = ok ? t : 0;
            (void)kelp_queue_push(&qm, &m, t);
            kelp_queue_request req = { -1, 0, 32 };
            int rc = kelp_queue_data_request(&qm, &req, t, &out);
            if (!ok && rc != KELP_ERR_ARG) abort();
            if (ok) check_priority(t);
            break;
        }
        case 2: {
            static const char *const LINES[2] = { "$CAREV,000000,AUV,1.0*02\r\n", "$CACLK,2024,1,2,12,0,0*42\r\n" };
            const char *l = LINES[op / 16 % 2];
            (void)kelp_mmdriver_feed(&mm, (const uint8_t *)l, strlen(l), t);
            (void)kelp_mmdriver_initiate_transmission(&mm, 1, 2, (unsigned)(op / 32 % 6), t);
            break;
        }
        default: {
            kelp_mac_update_type ty = (op / 16 % 2) ? KELP_MAC_UPDATE_ADD : KELP_MAC_UPDATE_REMOVE;
            kelp_mac_slot s = sl[(unsigned)d % 3u];
            int rc = kelp_mac_update(&mac, 1, ty, &s, 1, t);
            if (!ok && rc != KELP_ERR_ARG) abort();
            break;
        }
        }
    }
    return 0;
}
