/* acomms glue (core): the ACOMMS_* TextFormat strings and the node (queue + MAC + driver). */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kelp/acomms.h>

#define S 1.0                               /* one second of kelp_time */
static const kelp_time T0 = 1704196800.0;   /* 2024-01-02 12:00:00 UTC, a multiple of 10 s */

/* ------------------------------------------------------------------ TextFormat */

START_TEST(test_print_data_seed_example)
{
    /* seed 002 section 2.3.15 example 1: data 2 2 3 4 (octal in the uTimerScript line) */
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    m.src = 1;
    m.dest = 2;
    m.ack_requested = true;
    m.len = 4;
    m.data[0] = 2, m.data[1] = 2, m.data[2] = 3, m.data[3] = 4;
    m.key.type = KELP_QUEUE_CCL;
    m.key.id = 2;
    char buf[512];
    size_t len = 0;
    ck_assert_int_eq(kelp_acomms_print_data(&m, buf, sizeof buf, &len), 0);
    ck_assert_str_eq(buf, "base { src: 1 dest: 2 } ack_requested: true data: \"\\002\\002\\003\\004\" frame: 0 "
                          "queue_key { type: QUEUE_CCL id: 2 }");
    ck_assert_uint_eq(len, strlen(buf));
    /* too small: error, still NUL-terminated */
    ck_assert_int_eq(kelp_acomms_print_data(&m, buf, 20, &len), KELP_ERR_NOSPACE);
    ck_assert_uint_eq(strlen(buf), 19);
}
END_TEST

START_TEST(test_escapes_and_round_trip)
{
    kelp_acomms_msg m, back;
    memset(&m, 0, sizeof m);
    const uint8_t d[] = { 'a', '"', '\\', '\n', '\r', '\t', '\'', 0x7f, 0xff, 0 };
    memcpy(m.data, d, sizeof d);
    m.len = sizeof d;
    char buf[KELP_ACOMMS_MAX_PRINT];
    ck_assert_int_eq(kelp_acomms_print_data(&m, buf, sizeof buf, NULL), 0);
    ck_assert_ptr_nonnull(strstr(buf, "data: \"a\\\"\\\\\\n\\r\\t\\'\\177\\377\\000\""));
    /* every byte value survives print -> parse */
    for (int i = 0; i < 256; i++) m.data[i] = (uint8_t)i;
    m.len = 256;
    m.src = 7;
    m.dest = 0;
    m.frame = 3;
    m.key.type = KELP_QUEUE_DCCL;
    m.key.id = 20;
    m.has_time = true;
    m.time = 1295698086.887950;
    ck_assert_int_eq(kelp_acomms_print_data(&m, buf, sizeof buf, NULL), 0);
    kelp_diag why = {0};
    ck_assert_int_eq(kelp_acomms_parse_data(buf, strlen(buf), &back, &why), 0);
    ck_assert_uint_eq(back.len, 256);
    ck_assert_int_eq(memcmp(back.data, m.data, 256), 0);
    ck_assert_int_eq(back.src, 7);
    ck_assert_int_eq(back.frame, 3);
    ck_assert_int_eq(back.key.type, KELP_QUEUE_DCCL);
    ck_assert_int_eq(back.key.id, 20);
}
END_TEST

START_TEST(test_parse_data_forms)
{
    kelp_acomms_msg m;
    kelp_diag why = {0};
    const char *seed = "data: \"\\002\\002\\003\\004\"";
    ck_assert_int_eq(kelp_acomms_parse_data(seed, strlen(seed), &m, &why), 0);
    ck_assert_uint_eq(m.len, 4);
    ck_assert_int_eq(m.data[0], 2);
    ck_assert_int_eq(m.data[3], 4);
    ck_assert(!m.has_ack);
    /* protobuf variants: '<>' sub-messages, ':' before '{', separators, comments, hex escapes,
     * adjacent literals, single quotes */
    const char *t = "base: < src: 3, dest: 4; time: \"x\" > # c\n ack_requested: false data: '\\x41' \"B\"";
    ck_assert_int_eq(kelp_acomms_parse_data(t, strlen(t), &m, &why), 0);
    ck_assert_int_eq(m.src, 3);
    ck_assert_int_eq(m.dest, 4);
    ck_assert(m.has_ack && !m.ack_requested);
    ck_assert_uint_eq(m.len, 2);
    ck_assert_int_eq(m.data[0], 'A');
    ck_assert_int_eq(m.data[1], 'B');
    /* the input ends inside a literal: protobuf's TextFormat parser reports it but keeps the
     * field (to the end, escapes applied), and Goby's parse_for_moos uses the message: the
     * seed's uTimerScript value of example 1 (section 2.3.15), val="data: "\002\002\003\004\"",
     * posted without its outer quotes, is the bytes 02 02 03 04 22 */
    const char *ts = "data: \"\\002\\002\\003\\004\\\"";
    ck_assert_int_eq(kelp_acomms_parse_data(ts, strlen(ts), &m, &why), 0);
    ck_assert_uint_eq(m.len, 5);
    ck_assert_int_eq(m.data[0], 2);
    ck_assert_int_eq(m.data[3], 4);
    ck_assert_int_eq(m.data[4], '"');
    const char *open = "data: \"abc";
    ck_assert_int_eq(kelp_acomms_parse_data(open, strlen(open), &m, &why), 0);
    ck_assert_uint_eq(m.len, 3);
    ck_assert_int_eq(m.data[2], 'c');
    /* errors, each with a reason */
    static const char *const bad[] = { "data: \"abc\n\" frame: 1", "bogus: 1", "base { src: x }", "frame: -1",
                                       "queue_key { type: QUEUE_FOO id: 1 }", "base { src: 1", "}", "data 1",
                                       "data: \"\\q\"", "ack_requested: maybe" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        kelp_diag_clear(&why);
        int rc = kelp_acomms_parse_data(bad[i], strlen(bad[i]), &m, &why);
        ck_assert_msg(rc < 0, "accepted: %s", bad[i]);
        ck_assert_int_eq(why.code, rc);
#ifndef KELP_NO_ERRMSG
        ck_assert_str_ne(why.msg, "");
#endif
    }
    char big[1400] = "data: \"";
    for (int i = 0; i < 300; i++) strcat(big, "\\001");
    strcat(big, "\"");
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_acomms_parse_data(big, strlen(big), &m, &why), KELP_ERR_NOSPACE);
    ck_diag(&why, KELP_ERR_NOSPACE, "data longer than a modem frame");
}
END_TEST

START_TEST(test_parse_mac_update_seed)
{
    /* seed 002 section 2.3.6: the C++ MACUpdate example, serialized (acomms.md 2.4 [DERIVED]) */
    const char *t = "dest: 1 update_type: ADD slot { src: 1 dest: 3 rate: 0 type: SLOT_DATA slot_seconds: 15 }";
    kelp_acomms_mac_update u;
    kelp_diag why = {0};
    ck_assert_int_eq(kelp_acomms_parse_mac_update(t, strlen(t), &u, &why), 0);
    ck_assert_int_eq(u.dest, 1);
    ck_assert_int_eq(u.type, KELP_MAC_UPDATE_ADD);
    ck_assert_uint_eq(u.nslots, 1);
    ck_assert_int_eq(u.slot[0].src, 1);
    ck_assert_int_eq(u.slot[0].dest, 3);
    ck_assert_uint_eq(u.slot[0].rate, 0);
    ck_assert_int_eq(u.slot[0].type, KELP_SLOT_DATA);
    ck_assert_uint_eq(u.slot[0].slot_seconds, 15);
    /* defaults: REPLACE, slot dest -1 */
    const char *t2 = "dest: 2 slot { src: 2 } slot { src: 1 type: SLOT_PING slot_seconds: 5 }";
    ck_assert_int_eq(kelp_acomms_parse_mac_update(t2, strlen(t2), &u, &why), 0);
    ck_assert_int_eq(u.type, KELP_MAC_UPDATE_REPLACE);
    ck_assert_uint_eq(u.nslots, 2);
    ck_assert_int_eq(u.slot[0].dest, -1);
    ck_assert_int_eq(u.slot[1].type, KELP_SLOT_PING);
    static const char *const bad[] = { "update_type: ADD", "dest: 1 slot { dest: 2 }", "dest: 1 update_type: MERGE",
                                       "dest: 1 slot { src: 1 rate: 9 }", "dest: 1 slot { src: 1 colour: 2 }" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        ck_assert_msg(kelp_acomms_parse_mac_update(bad[i], strlen(bad[i]), &u, &why) < 0, "accepted: %s", bad[i]);
}
END_TEST

START_TEST(test_parse_range_req)
{
    kelp_acomms_range_req r;
    kelp_diag why = {0};
    const char *t = "base { src: 1 dest: 2 }";
    ck_assert_int_eq(kelp_acomms_parse_range_req(t, strlen(t), &r, &why), 0);
    ck_assert_int_eq(r.type, KELP_RANGING_TWO_WAY_PING); /* defaults of ModemRangingRequest */
    ck_assert_uint_eq(r.max_range, 1000);
    ck_assert_uint_eq(r.enable_beacons, 15);
    const char *t2 = "base { src: 3 } type: REMUS_LBL_RANGING max_range: 2000 enable_beacons: 5";
    ck_assert_int_eq(kelp_acomms_parse_range_req(t2, strlen(t2), &r, &why), 0);
    ck_assert_int_eq(r.type, KELP_RANGING_REMUS_LBL);
    ck_assert_uint_eq(r.max_range, 2000);
    ck_assert_uint_eq(r.enable_beacons, 5);
    ck_assert_int_eq(kelp_acomms_parse_range_req("type: SONAR", 11, &r, &why), KELP_ERR_PARSE);
    ck_diag(&why, KELP_ERR_PARSE, "type must be MODEM_TWO_WAY_PING, MODEM_ONE_WAY_SYNCHRONOUS or REMUS_LBL_RANGING");
}
END_TEST

START_TEST(test_time_and_other_prints)
{
    char buf[256];
    ck_assert_int_eq(kelp_acomms_time_text(1295698086.887950, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "2011-Jan-22 12:08:06.887950"); /* acomms.md 2.4: Slot.last_heard_time form */
    ck_assert_int_eq(kelp_acomms_time_text(1009894991.0, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "2002-Jan-01 14:23:11");
    kelp_queue_key k = { KELP_QUEUE_DCCL, 20 };
    ck_assert_int_eq(kelp_acomms_print_qsize(k, 3, buf, sizeof buf, NULL), 0);
    ck_assert_str_eq(buf, "key { type: QUEUE_DCCL id: 20 } size: 3");
    /* $CAMPR,2,1,0.0101 (real_nmea_examples #7): reply src 2 dest 1 */
    double tt = 0.0101;
    ck_assert_int_eq(kelp_acomms_print_range(2, 1, 1009894991.0, KELP_RANGING_TWO_WAY_PING, &tt, 1, buf, sizeof buf, NULL), 0);
    ck_assert_str_eq(buf, "base { src: 2 dest: 1 time: \"2002-Jan-01 14:23:11\" } one_way_travel_time: 0.0101 "
                          "type: MODEM_TWO_WAY_PING");
    double nan4[2] = { 0.1, (double)NAN };
    ck_assert_int_eq(kelp_acomms_print_range(1, 0, 0, KELP_RANGING_REMUS_LBL, nan4, 2, buf, sizeof buf, NULL), 0);
    ck_assert_ptr_nonnull(strstr(buf, "one_way_travel_time: 0.1 one_way_travel_time: nan type: REMUS_LBL_RANGING"));
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    m.src = 1;
    m.dest = 2;
    m.len = 1;
    m.data[0] = 14;
    ck_assert_int_eq(kelp_acomms_print_ack(2, 1, 0, 1009894991.0, &m, buf, sizeof buf, NULL), 0);
    ck_assert_str_eq(buf, "base { src: 2 dest: 1 time: \"2002-Jan-01 14:23:11\" } frame: 0 orig_msg { base { src: 1 "
                          "dest: 2 } ack_requested: false data: \"\\016\" frame: 0 }");
    ck_assert_int_eq(kelp_acomms_print_expire(&m, buf, sizeof buf, NULL), 0);
    ck_assert_str_eq(buf, "orig_msg { base { src: 1 dest: 2 } ack_requested: false data: \"\\016\" frame: 0 }");
}
END_TEST

/* ------------------------------------------------------------------ node */

#define MAXW 64
static char wl[MAXW][KELP_MAX_NMEA_LINE + 8];
static int nw;
static int n_ack, n_recv, n_expire, n_slot, n_frame_out;
static uint32_t last_qsize;
static kelp_acomms_msg last_recv;

static void wr(const char *b, size_t n, void *u)
{
    (void)u;
    ck_assert_int_lt(nw, MAXW);
    memcpy(wl[nw], b, n);
    wl[nw][n] = '\0';
    nw++;
}

static void evt(const kelp_acomms_event *e, void *u)
{
    (void)u;
    if (e->kind == KELP_ACOMMS_EV_SLOT) n_slot++;
    if (e->kind == KELP_ACOMMS_EV_FRAME_OUT && e->frame->len) n_frame_out++;
    if (e->kind != KELP_ACOMMS_EV_QUEUE) return;
    switch (e->q->kind) {
    case KELP_QUEUE_EV_ACK: n_ack++; break;
    case KELP_QUEUE_EV_EXPIRE: n_expire++; break;
    case KELP_QUEUE_EV_QSIZE: last_qsize = e->q->size; break;
    case KELP_QUEUE_EV_RECEIVE:
    case KELP_QUEUE_EV_RECEIVE_CCL:
        n_recv++;
        last_recv = *e->q->msg;
        break;
    default: break;
    }
}

static void reset_capture(void)
{
    nw = n_ack = n_recv = n_expire = n_slot = n_frame_out = 0;
    last_qsize = 999;
}

/* "$BODY*HH\r\n" */
static void line(const char *body, char *out)
{
    sprintf(out, "$%s*%02X\r\n", body, kelp_nmea_checksum(body, strlen(body)));
}

static void feed(kelp_acomms_node *n, const char *body, kelp_time t)
{
    char l[KELP_MAX_NMEA_LINE + 8];
    line(body, l);
    ck_assert_int_eq(kelp_acomms_node_feed(n, (const uint8_t *)l, strlen(l), t), 0);
}

static kelp_queue qs[8];
static kelp_queue_entry pool[32];

static void whoi_node(kelp_acomms_node *n, kelp_time t)
{
    kelp_acomms_node_cfg c;
    kelp_acomms_node_cfg_default(&c);
    c.modem_id = 1;
    c.driver = KELP_ACOMMS_DRIVER_WHOI_MICROMODEM;
    static kelp_mac_slot slot;
    kelp_mac_slot_default(&slot, 1);
    slot.dest = 2;
    slot.slot_seconds = 10;
    c.mac.type = KELP_MAC_FIXED_DECENTRALIZED;
    c.mac.slots = &slot;
    c.mac.nslots = 1;
    kelp_acomms_node_ops ops = { wr, evt, NULL };
    ck_assert_int_eq(kelp_acomms_node_init(n, &c, qs, 8, pool, 32, &ops, NULL), 0);
    kelp_queue_cfg q;
    kelp_queue_cfg_default(&q, KELP_QUEUE_CCL, 2); /* seed example 1: CCL queue 2, ack true */
    ck_assert_int_eq(kelp_acomms_node_add_queue(n, &q, t), 0);
    ck_assert_int_eq(kelp_acomms_node_start(n, t), 0);
}

static void startup_answers(kelp_acomms_node *n, kelp_time t)
{
    char expect[64], clk[64];
    int sec = (int)((t - T0) / S); /* T0 is 12:00:00 */
    sprintf(clk, "CCCLK,2024,1,2,12,%d,%d", sec / 60, sec % 60);
    line(clk, expect);
    ck_assert_int_ge(nw, 1);
    ck_assert_str_eq(wl[nw - 1], expect); /* the driver's first line: the clock */
    clk[1] = 'A';
    feed(n, clk, t + S / 10);
    ck_assert_int_eq(kelp_acomms_node_tick(n, t + 11 * S / 10), 0); /* after the 1 s hold: reads */
    ck_assert_int_eq(kelp_acomms_node_tick(n, t + 115 * S / 100), 0); /* ... then writes */
    line("CCCFG,SRC,1", expect);
    ck_assert_str_eq(wl[nw - 1], expect);
    feed(n, "CACFG,SRC,1", t + 12 * S / 10);
    ck_assert_int_eq(kelp_acomms_node_tick(n, t + 125 * S / 100), 0);
    line("CCCFQ,ALL", expect);
    ck_assert_str_eq(wl[nw - 1], expect);
    feed(n, "CACFG,SRC,1", t + 13 * S / 10);
    ck_assert_int_eq(kelp_acomms_node_tick(n, t + 135 * S / 100), 0);
    ck_assert_uint_eq(kelp_mmdriver_pending(kelp_acomms_node_driver(n)), 0);
}

START_TEST(test_node_whoi_cycle)
{
    static kelp_acomms_node n;
    reset_capture();
    whoi_node(&n, T0);
    startup_answers(&n, T0);
    /* seed example 1: 02 02 03 04 queued for modem 2 */
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    m.dest = 2;
    m.len = 4;
    m.data[0] = 2, m.data[1] = 2, m.data[2] = 3, m.data[3] = 4;
    m.key.type = KELP_QUEUE_CCL;
    m.key.id = 2;
    m.has_time = true;
    m.time = T0 + 2 * S;
    ck_assert_int_eq(kelp_acomms_node_push(&n, &m, T0 + 2 * S), 0);
    ck_assert_uint_eq(last_qsize, 1);
    int before = nw;
    ck_assert_int_eq(kelp_acomms_node_tick(&n, T0 + 9 * S), 0);
    ck_assert_int_eq(nw, before); /* the slot starts at +10 s (aligned to UTC midnight) */
    ck_assert_int_eq(kelp_acomms_node_tick(&n, T0 + 10 * S), 0);
    ck_assert_int_eq(n_slot, 1);
    char expect[128];
    line("CCCYC,0,1,2,0,1,1", expect); /* acomms.md 9.17: $CCCYC,0,1,2,0,ACK,1 */
    ck_assert_str_eq(wl[nw - 1], expect);
    feed(&n, "CACYC,0,1,2,0,1,1", T0 + 10 * S + S / 2);
    feed(&n, "CADRQ,120011,1,2,1,32,1", T0 + 11 * S);
    line("CCTXD,1,2,1,02020304", expect);
    ck_assert_str_eq(wl[nw - 1], expect);
    ck_assert_uint_eq(last_qsize, 1); /* ack requested: kept until the ack */
    feed(&n, "CATXD,1,2,1,4", T0 + 11 * S + S / 10);
    feed(&n, "CAACK,2,1,1,1", T0 + 14 * S);
    ck_assert_int_eq(n_ack, 1);
    ck_assert_uint_eq(last_qsize, 0);
    /* a received CCL frame for queue 2 */
    feed(&n, "CARXD,2,1,0,1,02050607080910", T0 + 15 * S);
    ck_assert_int_eq(n_recv, 1);
    ck_assert_int_eq(last_recv.src, 2);
    ck_assert_uint_eq(last_recv.len, 7);
}
END_TEST

START_TEST(test_node_link_down_keeps_messages)
{
    static kelp_acomms_node n;
    reset_capture();
    whoi_node(&n, T0);
    startup_answers(&n, T0);
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    m.dest = 2;
    m.len = 2;
    m.data[0] = 2, m.data[1] = 9;
    m.key.type = KELP_QUEUE_CCL;
    m.key.id = 2;
    m.ack_requested = false;
    m.has_ack = true; /* without an ack the message would be popped when given to a modem */
    ck_assert_int_eq(kelp_acomms_node_push(&n, &m, T0 + 2 * S), 0);
    kelp_acomms_node_set_link_up(&n, false);
    int before = nw;
    ck_assert_int_eq(kelp_acomms_node_tick(&n, T0 + 10 * S), 0);
    ck_assert_int_eq(n_slot, 1);
    ck_assert_int_eq(nw, before);      /* nothing written */
    ck_assert_int_eq(n_frame_out, 0);  /* nothing taken from the queue */
    ck_assert_int_eq(kelp_queue_size(kelp_acomms_node_queue(&n), m.key), 1);
    ck_assert_uint_eq(n.count.slots_skipped, 1);
    kelp_acomms_node_set_link_up(&n, true);
    ck_assert_int_eq(kelp_acomms_node_restart_driver(&n, T0 + 15 * S), 0);
    startup_answers(&n, T0 + 15 * S); /* the start-up sequence again */
}
END_TEST

START_TEST(test_node_driver_dead)
{
    static kelp_acomms_node n;
    reset_capture();
    whoi_node(&n, T0);
    /* the modem never answers: $CCCLK re-sent every 3 s; after 3 the queue is given up; 5
     * failures without any sentence -> the node reports TIMEOUT */
    int rc = 0;
    kelp_time t = T0;
    for (int i = 0; i < 40 && rc == 0; i++) {
        t += S;
        rc = kelp_acomms_node_tick(&n, t);
    }
    ck_assert_int_eq(rc, KELP_ERR_TIMEOUT);
    ck_assert_int_le(t - T0, 20 * S);
    ck_assert_int_eq(kelp_acomms_node_restart_driver(&n, t), 0);
    ck_assert_int_eq(kelp_acomms_node_tick(&n, t + S / 10), 0);
}
END_TEST

START_TEST(test_node_none_loopback)
{
    static kelp_acomms_node n;
    reset_capture();
    kelp_acomms_node_cfg c;
    kelp_acomms_node_cfg_default(&c);
    c.modem_id = 1;
    c.loopback_channel = true;
    static kelp_mac_slot slot;
    kelp_mac_slot_default(&slot, 1);
    slot.slot_seconds = 5;
    c.mac.type = KELP_MAC_FIXED_DECENTRALIZED;
    c.mac.slots = &slot;
    c.mac.nslots = 1;
    kelp_acomms_node_ops ops = { NULL, evt, NULL };
    ck_assert_int_eq(kelp_acomms_node_init(&n, &c, qs, 8, pool, 32, &ops, NULL), 0);
    kelp_queue_cfg q;
    kelp_queue_cfg_default(&q, KELP_QUEUE_DCCL, 20);
    ck_assert_int_eq(kelp_acomms_node_add_queue(&n, &q, T0), 0);
    kelp_queue_cfg_default(&q, KELP_QUEUE_DCCL, 1);
    ck_assert_int_eq(kelp_acomms_node_add_queue(&n, &q, T0), 0);
    ck_assert_int_eq(kelp_acomms_node_start(&n, T0), 0);
    /* the spec's SIMPLE_STATUS frame (broadcast, acomms.md 3.8) and a GoToCommand header to 3 */
    static const uint8_t ss[] = { 0x20, 0x0a, 0x2a, 0x30, 0x04, 0x00, 0x06, 0x1c, 0x71, 0x87, 0xe2, 0x21, 0x11, 0x95, 0x04, 0x57 };
    static const uint8_t go[] = { 0x20, 0x00, 0xaa, 0x30, 0x02, 0x30, 0x02, 0xc0, 0x09, 0x3c };
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    memcpy(m.data, ss, sizeof ss);
    m.len = sizeof ss;
    m.key.type = KELP_QUEUE_DCCL;
    m.key.id = 20;
    ck_assert_int_eq(kelp_acomms_node_push(&n, &m, T0 + S), 0);
    memcpy(m.data, go, sizeof go);
    m.len = sizeof go;
    m.dest = 3;
    m.key.id = 1;
    ck_assert_int_eq(kelp_acomms_node_push(&n, &m, T0 + S), 0);
    ck_assert_int_eq(kelp_acomms_node_tick(&n, T0 + 5 * S), 0);
    ck_assert_int_eq(n_slot, 1);
    /* one frame: the tie goes to queue id 1 (to 3), the broadcast is stitched after it */
    ck_assert_int_eq(n_frame_out, 1);
    ck_assert_uint_eq(n.count.loopback_acked, 1);
    ck_assert_int_eq(kelp_acomms_node_tick(&n, T0 + 10 * S), 0);
    ck_assert_int_eq(n_recv, 1); /* the broadcast came back to us once */
    ck_assert_int_eq(n_ack, 1);  /* the message to 3 was acknowledged once */
    ck_assert_int_eq(last_recv.len, (int)sizeof ss);
    ck_assert_int_eq(memcmp(last_recv.data, ss, sizeof ss), 0);
    ck_assert_int_eq(kelp_acomms_node_range(&n, &(kelp_acomms_range_req){ 1, 2, KELP_RANGING_TWO_WAY_PING, 1000, 15 }, T0),
                     KELP_ERR_STATE);
}
END_TEST

START_TEST(test_node_bad_config)
{
    static kelp_acomms_node n;
    kelp_acomms_node_cfg c;
    kelp_acomms_node_cfg_default(&c);
    c.modem_id = 0; /* broadcast */
    ck_assert_int_eq(kelp_acomms_node_init(&n, &c, qs, 8, pool, 32, NULL, NULL), KELP_ERR_ARG);
    ck_diag(&n.diag, KELP_ERR_ARG, "acomms: modem_id must be 1..31 (0 is broadcast)");
    c.modem_id = 32;
    ck_assert_int_eq(kelp_acomms_node_init(&n, &c, qs, 8, pool, 32, NULL, NULL), KELP_ERR_ARG);
    c.modem_id = 1;
    c.driver = (kelp_acomms_driver_type)7;
    ck_assert_int_eq(kelp_acomms_node_init(&n, &c, qs, 8, pool, 32, NULL, NULL), KELP_ERR_ARG);
}
END_TEST

Suite *kelp_acomms_glue_suite(void)
{
    Suite *s = suite_create("acomms_glue");
    TCase *t = tcase_create("textformat");
    tcase_add_test(t, test_print_data_seed_example);
    tcase_add_test(t, test_escapes_and_round_trip);
    tcase_add_test(t, test_parse_data_forms);
    tcase_add_test(t, test_parse_mac_update_seed);
    tcase_add_test(t, test_parse_range_req);
    tcase_add_test(t, test_time_and_other_prints);
    suite_add_tcase(s, t);
    t = tcase_create("node");
    tcase_add_test(t, test_node_whoi_cycle);
    tcase_add_test(t, test_node_link_down_keeps_messages);
    tcase_add_test(t, test_node_driver_dead);
    tcase_add_test(t, test_node_none_loopback);
    tcase_add_test(t, test_node_bad_config);
    suite_add_tcase(s, t);
    return s;
}
