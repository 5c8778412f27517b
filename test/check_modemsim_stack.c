/* The simulated modems under the real host stack: main's Micro-Modem driver core (kelp_mmdriver), the
 * Goby priority queue (kelp_queue) and the TDMA MAC (kelp_mac) on each of two nodes, each node
 * talking NMEA to its own kelp_modemsim over a simulated serial line (byte FIFOs), the two modems
 * sharing one simulated channel.  The seed's example DCCL messages (GoToCommand, VehicleStatus:
 * the [DERIVED] frames of acomms.md 3.8) are exchanged under a FIXED TDMA cycle with acks. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/mac.h>
#include <kelp/mmdriver.h>
#include <kelp/modemsim.h>
#include <kelp/queue.h>

#define S 1000000LL
static const int64_t T0 = 1297857600LL * S; /* 2011-02-16 12:00:00 UTC */

#define NN 2
#define FIFO 65536
#define MAXMSG 64

typedef struct fifo {
    uint8_t b[FIFO];
    size_t n;
} fifo;

typedef struct node {
    int id;
    kelp_mmdriver mm;
    kelp_modemsim sim;
    kelp_mac mac;
    kelp_queue_mgr qm;
    kelp_queue queues[4];
    kelp_queue_entry pool[64];
    fifo to_modem, to_host;
    int acked[MAXMSG], expired[MAXMSG], received[MAXMSG]; /* by message tag */
    int ranges;
    double last_tt;
    int clock_events;
    bool dead;
} node;

static node nodes[NN];
static int64_t now; /* the simulation clock, whole microseconds */
#define SEC(us) ((kelp_time)(us) / 1e6)
static uint8_t air[KELP_MODEMSIM_PKT_MAX_ENCODED];

static void fifo_put(fifo *f, const void *b, size_t n)
{
    ck_assert_uint_le(f->n + n, FIFO);
    memcpy(f->b + f->n, b, n);
    f->n += n;
}

/* the message tag is the low byte of the DCCL header's time field (header byte 4) */
static int tag_of(const uint8_t *d, size_t n)
{
    kelp_queue_header h;
    if (kelp_queue_header_read(d, n, &h) != KELP_OK) return -1;
    return (int)(h.time_of_day % MAXMSG);
}

/* ---- modem side */
static void sim_write(const char *b, size_t n, void *u)
{
    fifo_put(&((node *)u)->to_host, b, n);
}

static void sim_tx(const kelp_modemsim_pkt *p, void *u)
{
    (void)u;
    size_t len;
    static kelp_modemsim_pkt q;
    ck_assert_int_eq(kelp_modemsim_pkt_encode(p, air, sizeof air, &len), KELP_OK);
    ck_assert_int_eq(kelp_modemsim_pkt_decode(air, len, &q), KELP_OK);
    for (int i = 0; i < NN; i++) ck_assert_int_eq(kelp_modemsim_hear(&nodes[i].sim, &q, SEC(now)), KELP_OK);
}

static const kelp_modemsim_ops SIM_OPS = { sim_write, sim_tx, NULL };

/* ---- host side */
static void mm_write(const char *b, size_t n, void *u)
{
    fifo_put(&((node *)u)->to_modem, b, n);
}

static void mm_event(const kelp_mmdriver_event *e, void *u)
{
    node *nd = u;
    if (getenv("TRACE") && (e->kind == KELP_MMDRIVER_EV_NMEA_IN || e->kind == KELP_MMDRIVER_EV_NMEA_OUT || e->kind == KELP_MMDRIVER_EV_RETRY))
        printf("%.3f node%d %s %s\n", (double)(now - T0) / 1e6, nd->id, e->kind == KELP_MMDRIVER_EV_NMEA_IN ? "IN " : e->kind == KELP_MMDRIVER_EV_RETRY ? "RETRY" : "OUT", e->raw);
    if (e->kind == KELP_MMDRIVER_EV_NMEA_IN && e->has_src) kelp_mac_heard(&nd->mac, e->src, SEC(now));
    if (e->kind == KELP_MMDRIVER_EV_RECEIVE) {
        static kelp_acomms_msg f;
        memset(&f, 0, sizeof f);
        f.src = e->src;
        f.dest = e->dest;
        f.ack_requested = e->ack_requested;
        f.frame = e->frame;
        f.len = e->data_len;
        memcpy(f.data, e->data, e->data_len);
        (void)kelp_queue_receive(&nd->qm, &f);
    } else if (e->kind == KELP_MMDRIVER_EV_ACK) {
        (void)kelp_queue_ack(&nd->qm, e->src, e->dest, e->frame);
    } else if (e->kind == KELP_MMDRIVER_EV_RANGE) {
        nd->ranges++;
        nd->last_tt = e->tt[0];
    } else if (e->kind == KELP_MMDRIVER_EV_CLOCK) {
        nd->clock_events++;
    } else if (e->kind == KELP_MMDRIVER_EV_DEAD) {
        nd->dead = true;
    }
}

static void mm_data_request(const kelp_mmdriver_data_request *req, kelp_mmdriver_frame *out, void *u)
{
    node *nd = u;
    kelp_queue_request r = { req->dest, req->frame, req->max_bytes };
    static kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    ck_assert_int_eq(kelp_queue_data_request(&nd->qm, &r, SEC(now), &m), KELP_OK);
    out->src = nd->id;
    out->dest = m.dest;
    out->ack_requested = m.ack_requested;
    out->len = m.len;
    memcpy(out->data, m.data, m.len);
}

static const kelp_mmdriver_ops MM_OPS = { mm_write, mm_event, mm_data_request };

static void q_event(const kelp_queue_event *e, void *u)
{
    node *nd = u;
    int tag = e->msg ? tag_of(e->msg->data, e->msg->len) : -1;
    if (tag < 0) return;
    if (e->kind == KELP_QUEUE_EV_RECEIVE) nd->received[tag]++;
    else if (e->kind == KELP_QUEUE_EV_ACK) nd->acked[tag]++;
    else if (e->kind == KELP_QUEUE_EV_EXPIRE) nd->expired[tag]++;
}

/* GoToCommand (id 1) from modem 1 and VehicleStatus (id 2): header + [DERIVED] body bytes */
static const uint8_t GOTO_BODY[] = { 0x02, 0xc0, 0x09, 0x3c, 0xda, 0xc2, 0xd6, 0xca,
                                     0xbe, 0xe8, 0xde, 0xc2, 0xe6, 0xe8, 0xe7 };
static const uint8_t STATUS_BODY[] = { 0x03, 0xe9, 0x2e, 0xe6 };

static void push(node *nd, unsigned dccl_id, int dest, int tag)
{
    static kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    kelp_queue_header h;
    memset(&h, 0, sizeof h);
    h.ccl_id = 0x20;
    h.id = dccl_id;
    h.time_of_day = (unsigned)(43200 + tag); /* 43200 % 64 == 0: tag = time % 64 */
    h.src = (unsigned)nd->id;
    h.dest = (unsigned)dest;
    kelp_queue_header_write(&h, m.data);
    const uint8_t *body = dccl_id == 1 ? GOTO_BODY : STATUS_BODY;
    size_t bl = dccl_id == 1 ? sizeof GOTO_BODY : sizeof STATUS_BODY;
    memcpy(m.data + 6, body, bl);
    m.len = 6 + bl;
    m.dest = dest;
    m.key.type = KELP_QUEUE_DCCL;
    m.key.id = dccl_id;
    m.has_time = true;
    m.time = SEC(now);
    ck_assert_int_eq(kelp_queue_push(&nd->qm, &m, SEC(now)), KELP_OK);
}

static void setup(double loss, uint32_t ttl_status, double separation)
{
    memset(nodes, 0, sizeof nodes);
    now = T0 - 30 * S;
    kelp_mac_slot slots[2];
    kelp_mac_slot_default(&slots[0], 1);
    slots[0].dest = 2;
    slots[0].slot_seconds = 10;
    kelp_mac_slot_default(&slots[1], 2);
    slots[1].dest = 1;
    slots[1].slot_seconds = 10;
    for (int i = 0; i < NN; i++) {
        node *nd = &nodes[i];
        nd->id = i + 1;
        kelp_modemsim_cfg sc;
        kelp_modemsim_cfg_default(&sc);
        sc.modem_id = nd->id;
        sc.instance = (uint32_t)(7 + i);
        sc.x = i * separation;
        sc.depth = 10;
        sc.loss_probability = loss;
        sc.seed = (uint64_t)(1234 + i);
        ck_assert_int_eq(kelp_modemsim_init(&nd->sim, &sc, &SIM_OPS, nd, SEC(now)), KELP_OK);
        kelp_modemsim_boot(&nd->sim, SEC(now - 60 * S)); /* powered on a minute before the host opens the line */
        nd->to_host.n = 0;                       /* ... so the host never reads the $CAREV,INIT */
        kelp_mmdriver_cfg mc;
        memset(&mc, 0, sizeof mc);
        mc.modem_id = nd->id;
        ck_assert_int_eq(kelp_mmdriver_init(&nd->mm, &mc, &MM_OPS, nd), KELP_OK);
        ck_assert_int_eq(kelp_mmdriver_start(&nd->mm, SEC(now)), KELP_OK);
        ck_assert_int_eq(kelp_queue_init(&nd->qm, nd->id, nd->queues, 4, nd->pool, 64, q_event, NULL, nd), KELP_OK);
        kelp_queue_cfg qc;
        kelp_queue_cfg_default(&qc, KELP_QUEUE_DCCL, 1); /* GoToCommand: ack, newest first, ttl 1800 */
        ck_assert_int_eq(kelp_queue_add(&nd->qm, &qc, SEC(now)), KELP_OK);
        kelp_queue_cfg_default(&qc, KELP_QUEUE_DCCL, 2); /* VehicleStatus */
        qc.newest_first = false;
        qc.ttl = ttl_status;
        ck_assert_int_eq(kelp_queue_add(&nd->qm, &qc, SEC(now)), KELP_OK);
        kelp_mac_cfg cfg;
        kelp_mac_cfg_default(&cfg);
        cfg.type = KELP_MAC_FIXED_DECENTRALIZED;
        cfg.modem_id = nd->id;
        cfg.slots = slots;
        cfg.nslots = 2;
        ck_assert_int_eq(kelp_mac_init(&nd->mac, &cfg, SEC(now)), KELP_OK);
    }
}

static int n_cycles_started;

static void step(void)
{
    now += 10000;
    for (int i = 0; i < NN; i++) {
        node *nd = &nodes[i];
        if (kelp_mmdriver_tick(&nd->mm, SEC(now)) != KELP_OK) nd->dead = true;
        /* the serial line, both ways */
        if (nd->to_modem.n) {
            size_t n = nd->to_modem.n;
            static uint8_t tmp[FIFO];
            memcpy(tmp, nd->to_modem.b, n);
            nd->to_modem.n = 0;
            ck_assert_int_eq(kelp_modemsim_feed(&nd->sim, tmp, n, SEC(now)), KELP_OK);
        }
        kelp_modemsim_tick(&nd->sim, SEC(now));
        if (nd->to_host.n) {
            size_t n = nd->to_host.n;
            static uint8_t tmp2[FIFO];
            memcpy(tmp2, nd->to_host.b, n);
            nd->to_host.n = 0;
            ck_assert_int_eq(kelp_mmdriver_feed(&nd->mm, tmp2, n, SEC(now)), KELP_OK);
        }
        kelp_mac_action act;
        while (kelp_mac_tick(&nd->mac, SEC(now), &act) == KELP_OK) {
            if (act.kind == KELP_MAC_ACT_TRANSMIT) {
                n_cycles_started++;
                ck_assert_int_eq(kelp_mmdriver_initiate_transmission(&nd->mm, act.src, act.dest, act.rate, SEC(now)), KELP_OK);
            }
        }
        kelp_queue_do_work(&nd->qm, SEC(now));
    }
}

static void run_until(int64_t t)
{
    while (now < t) step();
}

START_TEST(driver_startup_against_the_simulator)
{
    setup(0, 1800, 1000);
    run_until(T0 - 20 * S);
    for (int i = 0; i < NN; i++) {
        ck_assert(kelp_mmdriver_clock_ok(&nodes[i].mm));
        ck_assert_uint_eq(kelp_mmdriver_pending(&nodes[i].mm), 0);
        ck_assert_uint_eq(nodes[i].mm.count.retries, 0);
        ck_assert_uint_eq(nodes[i].mm.count.bad_lines, 0);
        ck_assert_int_eq(kelp_modemsim_src(&nodes[i].sim), i + 1);
        /* the modem clock now follows the host's UTC (set from $CCCLK, within a second) */
        int64_t skew = llround(kelp_modemsim_clock(&nodes[i].sim, SEC(now)) * 1e6) - now;
        ck_assert(skew <= 0 && skew > -1100000);
        ck_assert_uint_eq(kelp_modemsim_get_counters(&nodes[i].sim)->host_errors, 0);
    }
    /* ranging through the driver: 1000 m apart -> 0.6667 s one way */
    ck_assert_int_eq(kelp_mmdriver_initiate_ranging(&nodes[0].mm, 1, 2, KELP_RANGING_TWO_WAY_PING, 0, 0, SEC(now)), KELP_OK);
    run_until(now + 5 * S);
    ck_assert_int_eq(nodes[0].ranges, 1);
    ck_assert_double_eq_tol(nodes[0].last_tt, 1000.0 / 1500.0, 0.0001);
    ck_assert(!nodes[0].dead && !nodes[1].dead);
}
END_TEST

START_TEST(tdma_exchange_with_acks_every_message_once)
{
    setup(0, 1800, 1000);
    run_until(T0 - 20 * S);
    for (int k = 0; k < 3; k++) {
        push(&nodes[0], 1, 2, k);      /* GoToCommand 1 -> 2, tags 0..2 */
        push(&nodes[1], 2, 1, 10 + k); /* VehicleStatus 2 -> 1, tags 10..12 */
    }
    run_until(T0 + 120 * S);
    for (int k = 0; k < 3; k++) {
        ck_assert_int_eq(nodes[1].received[k], 1);
        ck_assert_int_eq(nodes[0].acked[k], 1);
        ck_assert_int_eq(nodes[0].received[10 + k], 1);
        ck_assert_int_eq(nodes[1].acked[10 + k], 1);
    }
    /* nothing else arrived, nothing expired, queues empty, nobody complained */
    int total = 0;
    for (int t = 0; t < MAXMSG; t++) total += nodes[0].received[t] + nodes[1].received[t];
    ck_assert_int_eq(total, 6);
    for (int i = 0; i < NN; i++) {
        kelp_queue_key k1 = { KELP_QUEUE_DCCL, 1 }, k2 = { KELP_QUEUE_DCCL, 2 };
        ck_assert_int_eq(kelp_queue_size(&nodes[i].qm, k1), 0);
        ck_assert_int_eq(kelp_queue_size(&nodes[i].qm, k2), 0);
        ck_assert_uint_eq(nodes[i].mm.count.retries, 0);
        ck_assert_uint_eq(kelp_modemsim_get_counters(&nodes[i].sim)->host_errors, 0);
        ck_assert_uint_eq(kelp_modemsim_get_counters(&nodes[i].sim)->lost_collision, 0);
        ck_assert_uint_eq(kelp_modemsim_get_counters(&nodes[i].sim)->lost_half_duplex, 0);
    }
    /* VehicleStatus (10 B) messages are stitched: node 2 needed fewer slots than messages */
    ck_assert_uint_le(kelp_modemsim_get_counters(&nodes[1].sim)->tx[KELP_MODEMSIM_PKT_DATA], 2);
    ck_assert_uint_eq(kelp_modemsim_get_counters(&nodes[0].sim)->tx[KELP_MODEMSIM_PKT_DATA], 3);
}
END_TEST

START_TEST(lossy_channel_resends_and_expires_nothing_else_lost)
{
    /* 30 % loss at both modems; VehicleStatus lives 30 s, GoToCommand 1800 s */
    setup(0.3, 30, 1000);
    run_until(T0 - 20 * S);
    for (int k = 0; k < 4; k++) push(&nodes[0], 1, 2, k);
    for (int k = 0; k < 12; k++) push(&nodes[1], 2, 1, 10 + k);
    run_until(T0 + 600 * S);
    int expired = 0;
    for (int k = 0; k < 4; k++) {
        /* GoToCommand: acknowledged in the end, so received at least once */
        ck_assert_int_eq(nodes[0].acked[k], 1);
        ck_assert_int_ge(nodes[1].received[k], 1);
        ck_assert_int_eq(nodes[0].expired[k], 0);
    }
    for (int t = 10; t < 22; t++) {
        /* VehicleStatus: acknowledged (then received) or expired, never both, never neither */
        ck_assert_int_eq(nodes[1].acked[t] + nodes[1].expired[t], 1);
        if (nodes[1].acked[t]) ck_assert_int_ge(nodes[0].received[t], 1);
        expired += nodes[1].expired[t];
    }
    /* more GoToCommand frames than messages (21 B: one per frame): unacknowledged ones went again */
    ck_assert_uint_gt(kelp_modemsim_get_counters(&nodes[0].sim)->frames_tx, 4);
    ck_assert_uint_gt(kelp_modemsim_get_counters(&nodes[0].sim)->lost_random +
                          kelp_modemsim_get_counters(&nodes[1].sim)->lost_random,
                      0);
    ck_assert_int_gt(expired, 0); /* 50 s of ttl under 30 % loss: some VehicleStatus expire */
    for (int i = 0; i < NN; i++) ck_assert(!nodes[i].dead);
}
END_TEST

Suite *kelp_modemsim_stack_suite(void)
{
    Suite *s = suite_create("modemsim_stack");
    TCase *tc = tcase_create("stack");
    tcase_set_timeout(tc, 30);
    tcase_add_test(tc, driver_startup_against_the_simulator);
    tcase_add_test(tc, tdma_exchange_with_acks_every_message_once);
    tcase_add_test(tc, lossy_channel_resends_and_expires_nothing_else_lost);
    suite_add_tcase(s, tc);
    return s;
}
