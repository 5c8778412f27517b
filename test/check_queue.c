/* Priority queue: the formula, every queue rule and tie-break, stitching (acomms.md 9 items 42-55,
 * goby-wire.md 8). */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <string.h>

#include <kelp/queue.h>

#define S 1.0                                 /* one second of kelp_time */
#define US 1e-6                               /* one microsecond */
static const kelp_time T0 = 1704196800.0;     /* 2024-01-02 12:00:00 UTC */

static kelp_queue qs[8];
static kelp_queue_entry pool[48];
static kelp_queue_mgr M;

#define MAXEV 128
static int nev;
static kelp_queue_event evs[MAXEV];
static kelp_acomms_msg evmsg[MAXEV];

static void on_event(const kelp_queue_event *ev, void *user)
{
    (void)user;
    if (nev >= MAXEV) return;
    evs[nev] = *ev;
    if (ev->msg) evmsg[nev] = *ev->msg;
    nev++;
}

static int count_ev(kelp_queue_event_kind k)
{
    int n = 0;
    for (int i = 0; i < nev; i++) n += evs[i].kind == k;
    return n;
}

static void setup_mgr(int modem_id)
{
    nev = 0;
    ck_assert_int_eq(kelp_queue_init(&M, modem_id, qs, 8, pool, 48, on_event, NULL, NULL), KELP_OK);
}

static void add_q(uint8_t type, uint32_t id, double vb, uint32_t ttl, bool ack, kelp_time now)
{
    kelp_queue_cfg c;
    kelp_queue_cfg_default(&c, type, id);
    c.value_base = vb;
    c.ttl = ttl;
    c.ack = ack;
    ck_assert_int_eq(kelp_queue_add(&M, &c, now), KELP_OK);
}

/* a DCCL message: real header (id, time of day 43200, src 1, dest) + body of `body` bytes filled with `fill+i` */
static kelp_acomms_msg dccl(unsigned id, int dest, size_t body, uint8_t fill)
{
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    kelp_queue_header h = { KELP_DCCL_CCL_ID, id, 43200, 1, (unsigned)dest, false, false, 0 };
    kelp_queue_header_write(&h, m.data);
    for (size_t i = 0; i < body; i++) m.data[6 + i] = (uint8_t)(fill + i);
    m.len = 6 + body;
    m.dest = dest;
    m.key.type = KELP_QUEUE_DCCL;
    m.key.id = id;
    m.has_time = true;
    m.time = T0;
    return m;
}

static void push(kelp_acomms_msg m, kelp_time now)
{
    ck_assert_int_eq(kelp_queue_push(&M, &m, now), KELP_OK);
}

static kelp_acomms_msg request(int dest, uint32_t frame, uint32_t max_bytes, kelp_time now)
{
    kelp_queue_request r = { dest, frame, max_bytes };
    kelp_acomms_msg out;
    ck_assert_int_eq(kelp_queue_data_request(&M, &r, now, &out), KELP_OK);
    return out;
}

static unsigned id_of(const kelp_acomms_msg *m)
{
    kelp_queue_header h;
    ck_assert_int_eq(kelp_queue_header_read(m->data, m->len, &h), KELP_OK);
    return h.id;
}

static kelp_queue_key K(unsigned id) { kelp_queue_key k = { KELP_QUEUE_DCCL, id }; return k; }

/* ------------------------------------------------------------------ formula and contest */

START_TEST(priority_formula_seed_values)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 1.5, 300, false, T0);
    add_q(KELP_QUEUE_DCCL, 2, 4.0, 1000, false, T0);
    double p;
    ck_assert_int_eq(kelp_queue_priority(&M, K(1), T0 + 60 * S, &p), KELP_OK);
    ck_assert_double_eq_tol(p, 0.3, 1e-12);          /* V 1.5, ttl 300, 60 s */
    ck_assert_int_eq(kelp_queue_priority(&M, K(2), T0 + 100 * S, &p), KELP_OK);
    ck_assert_double_eq_tol(p, 0.4, 1e-12);          /* V 4, ttl 1000, 100 s */
    ck_assert_int_eq(kelp_queue_priority(&M, K(9), T0, &p), KELP_ERR_NOTFOUND);
}
END_TEST

START_TEST(contest_highest_priority_wins)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 4.0, 1000, false, T0);  /* A: 0.4 at 100 s */
    add_q(KELP_QUEUE_DCCL, 2, 1.5, 300, false, T0);   /* B: 0.5 at 100 s */
    push(dccl(1, 2, 14, 0), T0);
    push(dccl(2, 2, 14, 0), T0);
    kelp_acomms_msg f = request(-1, 0, 32, T0 + 100 * S);
    ck_assert_uint_eq(f.len, 20);
    ck_assert_uint_eq(id_of(&f), 2);
    ck_assert_int_eq(f.dest, 2);
    ck_assert_int_eq(f.src, 1);
}
END_TEST

START_TEST(ttl_zero_is_infinite_priority_and_immediate_expiry)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 1.0, 0, false, T0);
    add_q(KELP_QUEUE_DCCL, 2, 1000.0, 10, false, T0);
    double p;
    ck_assert_int_eq(kelp_queue_priority(&M, K(1), T0 + 1 * S, &p), KELP_OK);
    ck_assert(isinf(p) && p > 0);
    ck_assert_int_eq(kelp_queue_priority(&M, K(1), T0, &p), KELP_OK);
    ck_assert(isnan(p)); /* 0/0 */
    push(dccl(1, 2, 4, 0), T0);
    push(dccl(2, 2, 4, 0), T0);
    kelp_acomms_msg f = request(-1, 0, 10, T0 + 1 * S);   /* only one fits in 10 bytes */
    ck_assert_uint_eq(id_of(&f), 1);                        /* inf beats 100 */
    /* ttl 0: expires at the next do_work */
    push(dccl(1, 2, 4, 0), T0);
    nev = 0;
    kelp_queue_do_work(&M, T0 + 1 * US);
    ck_assert_int_eq(count_ev(KELP_QUEUE_EV_EXPIRE), 1);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 0);
}
END_TEST

START_TEST(tie_goes_to_older_last_send_then_map_order)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 2.0, 100, false, T0);  /* Y */
    add_q(KELP_QUEUE_DCCL, 2, 1.0, 100, false, T0);  /* X */
    push(dccl(1, 2, 20, 0), T0);
    push(dccl(1, 2, 20, 0), T0);
    push(dccl(2, 2, 20, 0), T0);
    /* at T0+50: Y = 1.0, X = 0.5 -> Y sends (last_send Y = T0+50) */
    kelp_acomms_msg f = request(-1, 0, 32, T0 + 50 * S);
    ck_assert_uint_eq(id_of(&f), 1);
    /* at T0+100: Y = 50/100*2 = 1.0, X = 100/100*1 = 1.0 -> tie, X has the older last_send */
    f = request(-1, 0, 32, T0 + 100 * S);
    ck_assert_uint_eq(id_of(&f), 2);

    /* equal priority and equal last_send: first in key order (id, then DCCL before CCL) */
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 7, 1.0, 100, false, T0);
    add_q(KELP_QUEUE_CCL, 3, 1.0, 100, false, T0);
    add_q(KELP_QUEUE_DCCL, 3, 1.0, 100, false, T0);
    kelp_acomms_msg c;
    memset(&c, 0, sizeof c);
    c.key.type = KELP_QUEUE_CCL;
    c.key.id = 3;
    c.dest = 2;
    c.len = 20;
    c.data[0] = 3;
    push(c, T0);
    push(dccl(3, 2, 20, 0), T0);
    push(dccl(7, 2, 20, 0), T0);
    f = request(-1, 0, 32, T0 + 10 * S);
    ck_assert_uint_eq(f.data[0], 0x20);
    ck_assert_uint_eq(id_of(&f), 3);          /* (3, DCCL) */
    f = request(-1, 0, 32, T0 + 10 * S);
    ck_assert_uint_eq(f.data[0], 3);          /* (3, CCL) before (7, DCCL) */
    ck_assert_uint_eq(f.len, 20);
    f = request(-1, 0, 32, T0 + 10 * S);
    ck_assert_uint_eq(id_of(&f), 7);
}
END_TEST

/* ------------------------------------------------------------------ queue rules */

START_TEST(blackout_time)
{
    setup_mgr(1);
    kelp_queue_cfg c;
    kelp_queue_cfg_default(&c, KELP_QUEUE_DCCL, 5);
    c.blackout_time = 10;
    c.ack = false;
    ck_assert_int_eq(kelp_queue_add(&M, &c, T0), KELP_OK);
    for (int i = 0; i < 3; i++) push(dccl(5, 2, 10, (uint8_t)i), T0);
    /* created at T0: in blackout until T0+10 */
    ck_assert_uint_eq(request(-1, 0, 32, T0 + 9 * S).len, 0);
    ck_assert_uint_eq(request(-1, 0, 32, T0 + 10 * S).len, 16);   /* last_send + 10 > now is false */
    ck_assert_uint_eq(request(-1, 0, 32, T0 + 19999999 * US).len, 0);  /* within 10 s of the send */
    ck_assert_uint_eq(request(-1, 0, 32, T0 + 20 * S).len, 16);
}
END_TEST

START_TEST(max_queue_newest_first_drops_oldest_fifo_drops_newest)
{
    setup_mgr(1);
    kelp_queue_cfg c;
    kelp_queue_cfg_default(&c, KELP_QUEUE_DCCL, 1);
    c.max_queue = 1;
    c.ack = false;
    ck_assert_int_eq(kelp_queue_add(&M, &c, T0), KELP_OK);
    kelp_queue_cfg_default(&c, KELP_QUEUE_DCCL, 2);
    c.max_queue = 1;
    c.newest_first = false;
    c.ack = false;
    ck_assert_int_eq(kelp_queue_add(&M, &c, T0), KELP_OK);
    push(dccl(1, 2, 4, 0x10), T0);   /* m1 */
    push(dccl(1, 2, 4, 0x20), T0);   /* m2 */
    push(dccl(2, 2, 4, 0x10), T0);   /* m1 */
    push(dccl(2, 2, 4, 0x20), T0);   /* m2 */
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 1);
    ck_assert_int_eq(kelp_queue_size(&M, K(2)), 1);
    kelp_acomms_msg f = request(-1, 0, 10, T0 + S);
    ck_assert_uint_eq(id_of(&f), 1);
    ck_assert_uint_eq(f.data[6], 0x20);       /* newest_first kept m2 */
    f = request(-1, 0, 10, T0 + S);
    ck_assert_uint_eq(id_of(&f), 2);
    ck_assert_uint_eq(f.data[6], 0x10);       /* FIFO kept m1 */
    ck_assert_uint_eq(M.count.dropped_overflow, 2);
}
END_TEST

START_TEST(newest_first_order)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 1, 1800, false, T0);
    for (int i = 1; i <= 3; i++) push(dccl(1, 2, 4, (uint8_t)(i * 16)), T0);
    ck_assert_uint_eq(request(-1, 0, 10, T0 + S).data[6], 0x30);    /* m3 first */
    ck_assert_uint_eq(request(-1, 0, 10, T0 + 2 * S).data[6], 0x20);

    setup_mgr(1);
    kelp_queue_cfg c;
    kelp_queue_cfg_default(&c, KELP_QUEUE_DCCL, 1);
    c.newest_first = false;
    c.ack = false;
    ck_assert_int_eq(kelp_queue_add(&M, &c, T0), KELP_OK);
    for (int i = 1; i <= 3; i++) push(dccl(1, 2, 4, (uint8_t)(i * 16)), T0);
    ck_assert_uint_eq(request(-1, 0, 10, T0 + S).data[6], 0x10);    /* m1 first */
}
END_TEST

START_TEST(ack_keeps_message_until_acknowledged)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 1, 1800, true, T0);
    push(dccl(1, 2, 10, 0x40), T0);
    kelp_acomms_msg f = request(-1, 0, 32, T0 + S);
    ck_assert_uint_eq(f.len, 16);
    ck_assert(f.ack_requested);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 1);       /* not popped */
    /* frame 1 of the same packet: the message waits for its ack -> blank, conforming to the packet */
    kelp_acomms_msg g = request(-1, 1, 32, T0 + S);
    ck_assert_uint_eq(g.len, 0);
    ck_assert_int_eq(g.dest, 2);
    ck_assert(g.ack_requested);
    /* acks for another modem or another frame are ignored */
    ck_assert_int_eq(kelp_queue_ack(&M, 2, 3, 0), 0);
    ck_assert_int_eq(kelp_queue_ack(&M, 2, 1, 1), 0);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 1);
    /* a new packet (frame 0) forgets the pending ack: the message is sent again */
    f = request(-1, 0, 32, T0 + 2 * S);
    ck_assert_uint_eq(f.len, 16);
    ck_assert_uint_eq(f.data[6], 0x40);
    nev = 0;
    ck_assert_int_eq(kelp_queue_ack(&M, 2, 1, 0), 1);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 0);
    ck_assert_int_eq(count_ev(KELP_QUEUE_EV_ACK), 1);
    ck_assert_int_eq(count_ev(KELP_QUEUE_EV_QSIZE), 1);
    for (int i = 0; i < nev; i++)
        if (evs[i].kind == KELP_QUEUE_EV_ACK) {
            ck_assert_uint_eq(evmsg[i].len, 16);
            ck_assert_uint_eq(evmsg[i].data[6], 0x40);       /* the original message */
            ck_assert_uint_eq(evs[i].key.id, 1);
        }
    /* the same ack again does nothing */
    ck_assert_int_eq(kelp_queue_ack(&M, 2, 1, 0), 0);

    /* broadcast never requests an ack: popped on send even from an ack queue */
    push(dccl(1, 0, 10, 0x50), T0);
    f = request(-1, 0, 32, T0 + 3 * S);
    ck_assert(!f.ack_requested);
    ck_assert_int_eq(f.dest, 0);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 0);
}
END_TEST

START_TEST(no_ack_pops_on_send_and_qsize_events)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 1, 1800, false, T0);
    ck_assert_int_eq(count_ev(KELP_QUEUE_EV_QSIZE), 1);    /* add */
    push(dccl(1, 2, 4, 0), T0);
    push(dccl(1, 2, 4, 0), T0);
    ck_assert_int_eq(nev, 3);
    ck_assert_uint_eq(evs[2].size, 2);
    kelp_acomms_msg f = request(-1, 0, 10, T0 + S);
    ck_assert(!f.ack_requested);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 1);
    ck_assert_uint_eq(evs[nev - 1].kind, KELP_QUEUE_EV_QSIZE);
    ck_assert_uint_eq(evs[nev - 1].size, 1);
    /* a rejected (empty) push still reports the size, as Goby */
    kelp_acomms_msg e = dccl(1, 2, 0, 0);
    e.len = 0;
    int before = nev;
    ck_assert_int_eq(kelp_queue_push(&M, &e, T0), KELP_ERR_ARG);
    ck_assert_int_eq(M.diag.code, KELP_ERR_ARG); /* the first error is kept */
    ck_diag_msg(&M.diag, "queue: empty message");
    ck_assert_int_eq(nev, before + 1);
    ck_assert_uint_eq(evs[nev - 1].size, 1);
    /* no queue for the key */
    kelp_acomms_msg x = dccl(9, 2, 4, 0);
    ck_assert_int_eq(kelp_queue_push(&M, &x, T0), KELP_ERR_NOTFOUND);
}
END_TEST

START_TEST(expiry_after_ttl)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 1, 300, true, T0);
    kelp_acomms_msg a = dccl(1, 2, 4, 0xa0), b = dccl(1, 2, 4, 0xb0);
    b.time = T0 + 100 * S;
    push(a, T0);
    push(b, T0);
    nev = 0;
    kelp_queue_do_work(&M, T0 + 300 * S);      /* time + ttl < now is false */
    ck_assert_int_eq(nev, 0);
    kelp_queue_do_work(&M, T0 + 300 * S + 1 * US);
    ck_assert_int_eq(nev, 1);                   /* only the expiry, no queue-size event */
    ck_assert_int_eq(evs[0].kind, KELP_QUEUE_EV_EXPIRE);
    ck_assert_uint_eq(evmsg[0].data[6], 0xa0);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 1);
    kelp_queue_do_work(&M, T0 + 401 * S);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 0);
    ck_assert_uint_eq(M.count.expired, 2);
}
END_TEST

START_TEST(loopback_and_manipulators)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 1, 1800, false, T0);
    nev = 0;
    push(dccl(1, 1, 4, 0), T0);           /* to ourselves: looped back, not queued */
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 0);
    ck_assert_int_eq(nev, 1);
    ck_assert_int_eq(evs[0].kind, KELP_QUEUE_EV_RECEIVE);
    ck_assert_uint_eq(evs[0].key.id, 1);

    kelp_queue_cfg c;
    kelp_queue_cfg_default(&c, KELP_QUEUE_DCCL, 2);
    c.loopback = true;
    ck_assert_int_eq(kelp_queue_add(&M, &c, T0), KELP_OK);
    kelp_queue_cfg_default(&c, KELP_QUEUE_DCCL, 3);
    c.no_queue = true;
    ck_assert_int_eq(kelp_queue_add(&M, &c, T0), KELP_OK);
    nev = 0;
    push(dccl(2, 0, 4, 0), T0);           /* LOOPBACK: queued and received */
    ck_assert_int_eq(kelp_queue_size(&M, K(2)), 1);
    ck_assert_int_eq(count_ev(KELP_QUEUE_EV_RECEIVE), 1);
    push(dccl(3, 0, 4, 0), T0);           /* NO_QUEUE */
    ck_assert_int_eq(kelp_queue_size(&M, K(3)), 0);
}
END_TEST

START_TEST(ccl_queues)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_CCL, 14, 10, 100, false, T0);   /* high priority */
    add_q(KELP_QUEUE_DCCL, 1, 1, 1800, false, T0);
    kelp_acomms_msg c;
    memset(&c, 0, sizeof c);
    c.key.type = KELP_QUEUE_CCL;
    c.key.id = 14;
    c.dest = 2;
    c.len = 8;
    c.data[0] = 15;
    ck_assert_int_eq(kelp_queue_push(&M, &c, T0), KELP_ERR_ARG);   /* wrong CCL byte */
    c.data[0] = 14;
    c.data[1] = 0xee;
    push(c, T0);
    push(dccl(1, 2, 4, 0), T0);
    /* DCCL first: the CCL queue may not join a stitched frame */
    push(dccl(1, 2, 4, 1), T0);
    kelp_acomms_msg f = request(-1, 0, 64, T0 + S);
    ck_assert_uint_eq(f.data[0], 14);           /* CCL wins the first user-frame: frame = the message */
    ck_assert_uint_eq(f.len, 8);
    ck_assert_uint_eq(f.data[1], 0xee);
    f = request(-1, 0, 64, T0 + S);
    ck_assert_uint_eq(f.data[0], 0x20);
    ck_assert_uint_eq(f.len, 20);               /* two DCCL messages of 10 bytes stitched */
    /* receive: CCL frame with a configured queue */
    nev = 0;
    kelp_acomms_msg rx = c;
    rx.dest = 1;
    ck_assert_int_eq(kelp_queue_receive(&M, &rx), 1);
    ck_assert_int_eq(evs[0].kind, KELP_QUEUE_EV_RECEIVE_CCL);
    ck_assert_uint_eq(evs[0].key.id, 14);
    rx.data[0] = 99;
    ck_assert_int_eq(kelp_queue_receive(&M, &rx), 0);   /* not DCCL or known CCL */
}
END_TEST

/* ------------------------------------------------------------------ stitching */

START_TEST(stitch_two_broadcasts_goby_bytes)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 1, 1800, true, T0);
    add_q(KELP_QUEUE_DCCL, 2, 1, 1800, true, T0);
    push(dccl(1, 0, 10, 0x01), T0);
    push(dccl(2, 0, 10, 0x11), T0);
    kelp_acomms_msg f = request(-1, 0, 64, T0 + 10 * S);
    static const uint8_t want[32] = {
        0x20, 0x00, 0xAA, 0x30, 0x02, 0x0C, 0x0A, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10,
        0x01, 0x2A, 0x30, 0x02, 0x04, 0x11, 0x12, 0x13, 0x14, 0x15, 0x16, 0x17, 0x18, 0x19, 0x1A
    };
    ck_assert_uint_eq(f.len, 32);
    ck_assert_mem_eq(f.data, want, 32);
    ck_assert_int_eq(f.dest, 0);
    ck_assert(!f.ack_requested);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 0);
    ck_assert_int_eq(kelp_queue_size(&M, K(2)), 0);

    /* the receiver (modem 5) unstitches: two pieces, flags cleared, original headers */
    setup_mgr(5);
    add_q(KELP_QUEUE_DCCL, 1, 1, 1800, true, T0);
    add_q(KELP_QUEUE_DCCL, 2, 1, 1800, true, T0);
    nev = 0;
    f.dest = 0;
    f.src = 1;
    ck_assert_int_eq(kelp_queue_receive(&M, &f), 2);
    kelp_acomms_msg a = dccl(1, 0, 10, 0x01), b = dccl(2, 0, 10, 0x11);
    ck_assert_int_eq(evs[0].kind, KELP_QUEUE_EV_RECEIVE);
    ck_assert_uint_eq(evmsg[0].len, 16);
    ck_assert_mem_eq(evmsg[0].data, a.data, 16);
    ck_assert_int_eq(evmsg[0].dest, 0);
    ck_assert_uint_eq(evmsg[1].len, 16);
    ck_assert_mem_eq(evmsg[1].data, b.data, 16);
    ck_assert_uint_eq(evs[1].key.id, 2);
}
END_TEST

START_TEST(stitch_destination_discipline_and_room)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 3, 1800, true, T0);   /* unicast to 3, wins */
    add_q(KELP_QUEUE_DCCL, 2, 2, 1800, true, T0);   /* to 4: wrong destination */
    add_q(KELP_QUEUE_DCCL, 3, 1, 1800, true, T0);   /* broadcast: may follow */
    push(dccl(1, 3, 10, 0), T0);
    push(dccl(2, 4, 10, 0), T0);
    push(dccl(3, 0, 10, 0), T0);
    kelp_acomms_msg f = request(-1, 0, 64, T0 + S);
    ck_assert_int_eq(f.dest, 3);
    ck_assert(f.ack_requested);                     /* the unicast asked for an ack */
    ck_assert_uint_eq(f.len, 32);
    ck_assert_uint_eq(f.data[5] & 0x0C, 0x08);      /* first: multimessage, not broadcast */
    ck_assert_uint_eq(f.data[21] & 0x0C, 0x04);     /* second (id 3): last, broadcast */
    ck_assert_int_eq(kelp_queue_size(&M, K(2)), 1);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 1); /* waiting for its ack */
    ck_assert_int_eq(kelp_queue_size(&M, K(3)), 0);
    /* frame 1 of the packet keeps dest 3: the message for 4 still does not qualify */
    kelp_acomms_msg g = request(-1, 1, 64, T0 + S);
    ck_assert_uint_eq(g.len, 0);
    ck_assert_int_eq(g.dest, 3);
    /* a slot with a fixed destination: only messages to it or broadcasts */
    kelp_acomms_msg h = request(4, 0, 64, T0 + 2 * S);
    ck_assert_int_eq(h.dest, 4);
    ck_assert_uint_eq(h.len, 16);
    ck_assert_uint_eq(id_of(&h), 2);
    /* no more than 6 bytes left: no further contest (16 + 16 in 37 leaves 5) */
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 1, 1800, false, T0);
    for (int i = 0; i < 3; i++) push(dccl(1, 2, 10, 0), T0);
    kelp_acomms_msg k = request(-1, 0, 37, T0 + S);
    ck_assert_uint_eq(k.len, 32);
    ck_assert_int_eq(kelp_queue_size(&M, K(1)), 1);
}
END_TEST

START_TEST(rate5_packet_eight_contests)
{
    setup_mgr(1);
    add_q(KELP_QUEUE_DCCL, 1, 1, 1800, false, T0);
    add_q(KELP_QUEUE_DCCL, 2, 1, 1800, false, T0);
    for (int i = 0; i < 3; i++) push(dccl(1, 2, 194, 0), T0);
    for (int i = 0; i < 10; i++) push(dccl(2, 2, 194, 0), T0);
    /* frame 0: tie, key order -> 1; frame 1: queue 1 just sent (P 0) -> 2; from then on both
     * last sent `now`: equal P and equal last_send -> key order again until queue 1 is empty */
    static const unsigned want[8] = { 1, 2, 1, 1, 2, 2, 2, 2 };
    for (uint32_t fr = 0; fr < 8; fr++) {
        kelp_acomms_msg f = request(-1, fr, 256, T0 + 5 * S);
        ck_assert_uint_eq(f.len, 200);
        ck_assert_uint_eq(id_of(&f), want[fr]);
        ck_assert_int_eq(f.dest, 2);
    }
}
END_TEST

START_TEST(receive_destination_filter)
{
    setup_mgr(5);
    add_q(KELP_QUEUE_DCCL, 1, 1, 1800, false, T0);
    kelp_acomms_msg m = dccl(1, 10, 4, 0);
    m.dest = 10;
    ck_assert_int_eq(kelp_queue_receive(&M, &m), 0);
    ck_assert_uint_eq(M.count.rx_not_for_us, 1);
    m.dest = 5;
    ck_assert_int_eq(kelp_queue_receive(&M, &m), 1);
    m.dest = 0;
    ck_assert_int_eq(kelp_queue_receive(&M, &m), 1);
    kelp_acomms_msg u = dccl(7, 5, 4, 0);  /* no queue for id 7 */
    ck_assert_int_eq(kelp_queue_receive(&M, &u), 0);
    ck_assert_uint_eq(M.count.rx_no_queue, 1);
    u.len = 5;
    ck_assert_int_eq(kelp_queue_receive(&M, &u), 0);  /* shorter than a header */
}
END_TEST

START_TEST(dccl_header_fields)
{
    static const uint8_t ss[6] = { 0x20, 0x0a, 0x2a, 0x30, 0x04, 0x00 }; /* SIMPLE_STATUS vector */
    kelp_queue_header h;
    ck_assert_int_eq(kelp_queue_header_read(ss, 6, &h), KELP_OK);
    ck_assert_uint_eq(h.ccl_id, 0x20);
    ck_assert_uint_eq(h.id, 20);
    ck_assert_uint_eq(h.time_of_day, 43200);
    ck_assert_uint_eq(h.src, 2);
    ck_assert_uint_eq(h.dest, 0);
    ck_assert(!h.multimessage && !h.broadcast);
    uint8_t back[6];
    kelp_queue_header_write(&h, back);
    ck_assert_mem_eq(back, ss, 6);
    ck_assert_int_eq(kelp_queue_header_read(ss, 5, &h), KELP_ERR_TRUNCATED);
    h.multimessage = h.broadcast = true;
    h.dest = 31;
    kelp_queue_header_write(&h, back);
    ck_assert_uint_eq(back[4], 0x05);
    ck_assert_uint_eq(back[5], 0xFC);
}
END_TEST

static int npieces;
static void count_piece(const uint8_t *p, size_t n, unsigned id, bool bc, void *u)
{
    (void)p; (void)n; (void)id; (void)bc; (void)u;
    npieces++;
}

START_TEST(unstitch_malformed_frames)
{
    /* multimessage flag without the size byte */
    static const uint8_t a[6] = { 0x20, 0, 0xAA, 0x30, 0x02, 0x08 };
    npieces = 0;
    ck_assert_int_eq(kelp_queue_unstitch(a, 6, count_piece, NULL), KELP_ERR_TRUNCATED);
    ck_assert_int_eq(npieces, 0);
    /* size byte larger than the rest: clamped piece, then nothing left for the next header */
    static const uint8_t b[10] = { 0x20, 0, 0xAA, 0x30, 0x02, 0x08, 200, 1, 2, 3 };
    npieces = 0;
    ck_assert_int_eq(kelp_queue_unstitch(b, 10, count_piece, NULL), KELP_ERR_TRUNCATED);
    ck_assert_int_eq(npieces, 1);
    ck_assert_int_eq(kelp_queue_unstitch(b, 5, count_piece, NULL), KELP_ERR_PARSE);
    static const uint8_t c[7] = { 0x21, 0, 0xAA, 0x30, 0x02, 0x00, 1 };
    ck_assert_int_eq(kelp_queue_unstitch(c, 7, count_piece, NULL), KELP_ERR_PARSE);
}
END_TEST

Suite *kelp_queue_suite(void)
{
    Suite *s = suite_create("queue");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, priority_formula_seed_values);
    tcase_add_test(tc, contest_highest_priority_wins);
    tcase_add_test(tc, ttl_zero_is_infinite_priority_and_immediate_expiry);
    tcase_add_test(tc, tie_goes_to_older_last_send_then_map_order);
    tcase_add_test(tc, blackout_time);
    tcase_add_test(tc, max_queue_newest_first_drops_oldest_fifo_drops_newest);
    tcase_add_test(tc, newest_first_order);
    tcase_add_test(tc, ack_keeps_message_until_acknowledged);
    tcase_add_test(tc, no_ack_pops_on_send_and_qsize_events);
    tcase_add_test(tc, expiry_after_ttl);
    tcase_add_test(tc, loopback_and_manipulators);
    tcase_add_test(tc, ccl_queues);
    tcase_add_test(tc, stitch_two_broadcasts_goby_bytes);
    tcase_add_test(tc, stitch_destination_discipline_and_room);
    tcase_add_test(tc, rate5_packet_eight_contests);
    tcase_add_test(tc, receive_destination_filter);
    tcase_add_test(tc, dccl_header_fields);
    tcase_add_test(tc, unstitch_malformed_frames);
    suite_add_tcase(s, tc);
    return s;
}
