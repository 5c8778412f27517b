/* Micro-Modem simulator core: host protocol (real sentences of shared/data/real_nmea_examples.md),
 * channel arithmetic (acomms.md 1.5 rate table, Eq. 2.1), travel time, loss, half duplex,
 * collisions, ranging, polling and the bus packet codec. */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kelp/poller.h>
#include <kelp/modemsim.h>

#define S 1000000LL
static const int64_t T0 = 1297857600LL * S; /* 2011-02-16 12:00:00 UTC */
/* the test clock counts whole microseconds; the simulator takes kelp_time seconds */
#define SEC(us) ((kelp_time)(us) / 1e6)

/* ------------------------------------------------------------------ a little world of modems */

#define NM 4
#define MAXL 512
typedef struct hostline {
    int64_t t;
    char s[KELP_MAX_NMEA_LINE + 8];
} hostline;

static kelp_modemsim mod[NM];
static int nmod;
static hostline lines[NM][MAXL];
static int nlines[NM];
static int64_t now;
static int n_lost[NM][8];
static int n_tx;
static uint8_t air[KELP_MODEMSIM_PKT_MAX_ENCODED];

static void w_cb(const char *b, size_t n, void *u)
{
    int k = (int)(intptr_t)u;
    ck_assert_int_lt(nlines[k], MAXL);
    ck_assert_uint_ge(n, 2);
    ck_assert_msg(b[n - 2] == '\r' && b[n - 1] == '\n', "line not CRLF terminated");
    hostline *l = &lines[k][nlines[k]++];
    l->t = now;
    ck_assert_uint_lt(n, sizeof l->s);
    memcpy(l->s, b, n - 2);
    l->s[n - 2] = '\0';
}

static void tx_cb(const kelp_modemsim_pkt *p, void *u)
{
    (void)u;
    size_t len;
    n_tx++;
    ck_assert_int_eq(kelp_modemsim_pkt_encode(p, air, sizeof air, &len), KELP_OK);
    static kelp_modemsim_pkt q;
    ck_assert_int_eq(kelp_modemsim_pkt_decode(air, len, &q), KELP_OK);
    for (int i = 0; i < nmod; i++) ck_assert_int_eq(kelp_modemsim_hear(&mod[i], &q, SEC(now)), KELP_OK);
}

static void ev_cb(const kelp_modemsim_event *e, void *u)
{
    int k = (int)(intptr_t)u;
    if (e->kind == KELP_MODEMSIM_EV_LOST && e->loss < 8) n_lost[k][e->loss]++;
}

static const kelp_modemsim_ops OPS = { w_cb, tx_cb, ev_cb };

static void world(int n)
{
    memset(lines, 0, sizeof lines);
    memset(nlines, 0, sizeof nlines);
    memset(n_lost, 0, sizeof n_lost);
    n_tx = 0;
    nmod = n;
    now = T0;
}

static kelp_modemsim_cfg cfg_for(int id, double x, double y)
{
    kelp_modemsim_cfg c;
    kelp_modemsim_cfg_default(&c);
    c.modem_id = id;
    c.instance = (uint32_t)(100 + id);
    c.x = x;
    c.y = y;
    c.clock_set_at_boot = true;
    return c;
}

static void add(int k, const kelp_modemsim_cfg *c)
{
    ck_assert_int_eq(kelp_modemsim_init(&mod[k], c, &OPS, (void *)(intptr_t)k, SEC(now)), KELP_OK);
}

static void run_until(int64_t t)
{
    while (now < t) {
        now += 5000;
        for (int i = 0; i < nmod; i++) kelp_modemsim_tick(&mod[i], SEC(now));
    }
}

static void host(int k, const char *s)
{
    ck_assert_int_eq(kelp_modemsim_feed(&mod[k], (const uint8_t *)s, strlen(s), SEC(now)), KELP_OK);
    ck_assert_int_eq(kelp_modemsim_feed(&mod[k], (const uint8_t *)"\r\n", 2, SEC(now)), KELP_OK);
}

/* body + "*HH" */
static const char *cs(const char *body)
{
    static char b[4][KELP_MAX_NMEA_LINE + 8];
    static int i;
    i = (i + 1) % 4;
    unsigned x = 0;
    for (const char *p = body + 1; *p; p++) x ^= (unsigned char)*p;
    snprintf(b[i], sizeof b[i], "%s*%02X", body, x);
    return b[i];
}

/* index of the first line of modem k at or after `from` that starts with prefix, or -1 */
static int find(int k, const char *prefix, int from)
{
    for (int i = from; i < nlines[k]; i++)
        if (!strncmp(lines[k][i].s, prefix, strlen(prefix))) return i;
    return -1;
}

static int count(int k, const char *prefix)
{
    int n = 0;
    for (int i = 0; i < nlines[k]; i++)
        if (!strncmp(lines[k][i].s, prefix, strlen(prefix))) n++;
    return n;
}

static double t_of(int k, int i)
{
    return (double)(lines[k][i].t - T0) / 1e6;
}

/* ------------------------------------------------------------------ channel arithmetic */

START_TEST(rate_table_and_durations)
{
    /* acomms.md 1.5: "0 is a single 32 byte packet (FSK), 2 is three frames of 64 bytes (PSK),
     * 3 is two frames of 256 bytes (PSK), and 5 is eight frames of 256 bytes (PSK)" */
    ck_assert_uint_eq(kelp_modemsim_rate_frames[0], 1);
    ck_assert_uint_eq(kelp_modemsim_rate_bytes[0], 32);
    ck_assert_uint_eq(kelp_modemsim_rate_frames[2], 3);
    ck_assert_uint_eq(kelp_modemsim_rate_bytes[2], 64);
    ck_assert_uint_eq(kelp_modemsim_rate_frames[3], 2);
    ck_assert_uint_eq(kelp_modemsim_rate_bytes[3], 256);
    ck_assert_uint_eq(kelp_modemsim_rate_frames[5], 8);
    ck_assert_uint_eq(kelp_modemsim_rate_bytes[5], 256);
    ck_assert_uint_eq(kelp_modemsim_rate_frames[1], 3);
    ck_assert_uint_eq(kelp_modemsim_rate_bytes[4], 256);
    /* 32 B at 80 bit/s = 3.2 s; 8 x 256 B at 5300 bit/s = 3.0913 s */
    ck_assert_double_eq_tol(kelp_modemsim_packet_seconds(0, 1), 3.2, 1e-12);
    ck_assert_double_eq_tol(kelp_modemsim_packet_seconds(5, 8), 16384.0 / 5300.0, 1e-12);
    ck_assert_double_eq_tol(kelp_modemsim_packet_seconds(2, 3), 3.072, 1e-12);
    ck_assert_double_eq(kelp_modemsim_packet_seconds(6, 1), 0.0);
    /* travel time: 1500 m at 1500 m/s is 1 s; a 300-400 (500 m) offset with 0 depth is 1/3 s */
    ck_assert_double_eq_tol(kelp_modemsim_travel_time(0, 0, 0, 1500, 0, 0, 1500), 1.0, 1e-12);
    ck_assert_double_eq_tol(kelp_modemsim_travel_time(10, 20, 5, 310, 420, 5, 1500), 1.0 / 3.0, 1e-12);
    ck_assert_double_eq_tol(kelp_modemsim_travel_time(0, 0, 0, 0, 0, 1480, 1480), 1.0, 1e-12);
    /* Eq. 2.1 (acomms.md 9 item 60): tau_ci 1 s + 3000 m / 1500 m/s = 3 s of overhead per slot */
    ck_assert_double_eq_tol(kelp_modemsim_min_slot_seconds(0, 3000, 1.0, 0, 0, 1500) - kelp_modemsim_packet_seconds(0, 1) -
                                2 * 3000 / 1500.0,
                            3.0, 1e-12);
    ck_assert_double_eq_tol(kelp_modemsim_min_slot_seconds(0, 3000, 1.0, 0.5, 0.25, 1500), 11.2, 1e-12);
}
END_TEST

START_TEST(rng_is_splitmix64_and_seeded)
{
    kelp_rng r, q;
    kelp_rng_seed(&r, 0);
    /* splitmix64's first output for state 0 */
    ck_assert_uint_eq(kelp_rng_next(&r), UINT64_C(0xE220A8397B1DCDAF));
    ck_assert_uint_eq(kelp_rng_next(&r), UINT64_C(0x6E789E6AA1B965F4));
    kelp_rng_seed(&r, 42);
    kelp_rng_seed(&q, 42);
    double sum = 0;
    for (int i = 0; i < 20000; i++) {
        double u = kelp_rng_uniform(&r);
        ck_assert(u >= 0 && u < 1);
        ck_assert(u == kelp_rng_uniform(&q));
        sum += u;
    }
    ck_assert_double_eq_tol(sum / 20000, 0.5, 0.01);
}
END_TEST

/* ------------------------------------------------------------------ packet codec */

START_TEST(packet_codec_round_trip_and_rejects)
{
    static kelp_modemsim_pkt p, q;
    memset(&p, 0, sizeof p);
    p.kind = KELP_MODEMSIM_PKT_DATA;
    p.instance = 0xdeadbeef;
    p.seq = 7;
    p.src = 3;
    p.dest = 1;
    p.rate = 2;
    p.nframes = 2;
    p.start = SEC(T0);
    p.duration = SEC(3072000);
    p.x = -12.5;
    p.y = 1e6;
    p.depth = 30;
    p.frame[0].src = 3;
    p.frame[0].dest = 1;
    p.frame[0].ack = true;
    p.frame[0].len = 64;
    for (int i = 0; i < 64; i++) p.frame[0].data[i] = (uint8_t)(i * 7);
    p.frame[1].src = 3;
    p.frame[1].dest = 0;
    p.frame[1].len = 3;
    memcpy(p.frame[1].data, "\x20\x01\x02", 3);
    uint8_t buf[KELP_MODEMSIM_PKT_MAX_ENCODED];
    size_t len;
    ck_assert_int_eq(kelp_modemsim_pkt_encode(&p, buf, sizeof buf, &len), KELP_OK);
    ck_assert_uint_eq(len, 4 + 9 + 14 + 24 + 24 + (5 + 64) + (5 + 3));
    ck_assert_int_eq(kelp_modemsim_pkt_decode(buf, len, &q), KELP_OK);
    ck_assert_int_eq(q.kind, KELP_MODEMSIM_PKT_DATA);
    ck_assert_uint_eq(q.instance, 0xdeadbeef);
    ck_assert_uint_eq(q.seq, 7);
    ck_assert_double_eq(q.start, SEC(T0));
    ck_assert_double_eq(q.x, -12.5);
    ck_assert_double_eq(q.y, 1e6);
    ck_assert_uint_eq(q.frame[0].len, 64);
    ck_assert(q.frame[0].ack);
    ck_assert_mem_eq(q.frame[0].data, p.frame[0].data, 64);
    ck_assert_mem_eq(q.frame[1].data, "\x20\x01\x02", 3);
    /* every truncation is caught */
    for (size_t n = 0; n < len; n++) ck_assert_int_ne(kelp_modemsim_pkt_decode(buf, n, &q), KELP_OK);
    /* trailing garbage, bad magic, bad kind, frame longer than the rate allows */
    uint8_t big[KELP_MODEMSIM_PKT_MAX_ENCODED + 1];
    memcpy(big, buf, len);
    big[len] = 0;
    ck_assert_int_eq(kelp_modemsim_pkt_decode(big, len + 1, &q), KELP_ERR_PARSE);
    memcpy(big, buf, len);
    big[0] = 'X';
    ck_assert_int_eq(kelp_modemsim_pkt_decode(big, len, &q), KELP_ERR_PARSE);
    memcpy(big, buf, len);
    big[4] = 9;
    ck_assert_int_eq(kelp_modemsim_pkt_decode(big, len, &q), KELP_ERR_PARSE);
    p.rate = 0; /* 64-byte frame in a rate-0 (32-byte) packet */
    p.nframes = 1;
    ck_assert_int_eq(kelp_modemsim_pkt_encode(&p, buf, sizeof buf, &len), KELP_OK);
    ck_assert_int_eq(kelp_modemsim_pkt_decode(buf, len, &q), KELP_ERR_RANGE);
    /* encoder refuses what cannot be sent */
    p.nframes = KELP_MAX_MM_FRAMES + 1;
    ck_assert_int_eq(kelp_modemsim_pkt_encode(&p, buf, sizeof buf, &len), KELP_ERR_ARG);
    p.nframes = 1;
    ck_assert_int_eq(kelp_modemsim_pkt_encode(&p, buf, 20, &len), KELP_ERR_NOSPACE);
}
END_TEST

/* ------------------------------------------------------------------ host protocol */

START_TEST(clock_cfg_and_queries)
{
    world(1);
    kelp_modemsim_cfg c = cfg_for(1, 0, 0);
    c.clock_set_at_boot = false;
    add(0, &c);
    /* before $CCCLK the clock counts from 2000-01-01 */
    ck_assert_double_eq(kelp_modemsim_clock(&mod[0], SEC(now)), 946684800.0);
    host(0, "$CCCLK,2011,2,16,12,0,0");
    ck_assert_str_eq(lines[0][0].s, cs("$CACLK,2011,02,16,12,00,00"));
    ck_assert_double_eq(kelp_modemsim_clock(&mod[0], SEC(now)), SEC(T0));
    /* real example 3: the reply to $CCCFQ,SRC after $CCCFG,SRC,1 is $CACFG,SRC,1*33 */
    host(0, "$CCCFG,SRC,1");
    ck_assert_str_eq(lines[0][1].s, cs("$CACFG,SRC,1"));
    host(0, "$CCCFQ,SRC");
    ck_assert_str_eq(lines[0][2].s, "$CACFG,SRC,1*33");
    /* the host changes SRC (Goby sends $CCCFG,SRC,<modem_id>) and sets an nvram value */
    host(0, cs("$CCCFG,SRC,3"));
    ck_assert_str_eq(lines[0][3].s, cs("$CACFG,SRC,3"));
    ck_assert_int_eq(kelp_modemsim_src(&mod[0]), 3);
    host(0, "$CCCFG,CST,1");
    long v;
    ck_assert_int_eq(kelp_modemsim_nvram(&mod[0], "cst", &v), KELP_OK);
    ck_assert_int_eq(v, 1);
    /* ALL: every parameter once, each a $CACFG */
    int before = nlines[0];
    host(0, "$CCCFQ,ALL");
    int n = nlines[0] - before;
    ck_assert_int_ge(n, 40);
    for (int i = before; i < nlines[0]; i++) ck_assert(!strncmp(lines[0][i].s, "$CACFG,", 7));
    ck_assert_int_ge(find(0, "$CACFG,SRC,3*", before), 0);
    ck_assert_int_ge(find(0, "$CACFG,CST,1*", before), 0);
    /* $CCCFG,ALL,0 resets: SRC back to the configured modem id */
    host(0, "$CCCFG,ALL,0");
    ck_assert_str_eq(lines[0][nlines[0] - 1].s, cs("$CACFG,ALL,0"));
    ck_assert_int_eq(kelp_modemsim_src(&mod[0]), 1);
    ck_assert_int_eq(kelp_modemsim_nvram(&mod[0], "CST", &v), KELP_OK);
    ck_assert_int_eq(v, 0);
    ck_assert_int_eq(kelp_modemsim_nvram(&mod[0], "XYZ", &v), KELP_ERR_NOTFOUND);
}
END_TEST

START_TEST(revision_at_boot_and_heartbeat)
{
    world(1);
    kelp_modemsim_cfg c = cfg_for(1, 0, 0);
    c.clock_set_at_boot = false;
    c.revision = "0.93.0.09";
    c.rev_interval_seconds = 52;
    add(0, &c);
    kelp_modemsim_boot(&mod[0], SEC(now));
    ck_assert_str_eq(lines[0][0].s, cs("$CAREV,000000,INIT,0.93.0.09"));
    /* no host yet: no heartbeat */
    run_until(T0 + 60 * S);
    ck_assert_int_eq(nlines[0], 1);
    /* a host talks; 52 s of modem time after power-on gives real example 4 exactly */
    world(1);
    add(0, &c);
    host(0, "$CCCFQ,SRC");
    run_until(T0 + 52 * S);
    ck_assert_int_eq(count(0, "$CAREV"), 1);
    ck_assert_str_eq(lines[0][nlines[0] - 1].s, "$CAREV,000052,AUV,0.93.0.09*07");
}
END_TEST

START_TEST(bad_host_input_gets_caerr)
{
    world(1);
    kelp_modemsim_cfg c = cfg_for(1, 0, 0);
    add(0, &c);
    host(0, "$CCCFG,SRC,1*00"); /* wrong checksum */
    ck_assert_int_ge(find(0, "$CAERR,120000,NMEA,2,BAD_CHECKSUM*", 0), 0);
    host(0, "$CCXYZ,1,2");
    ck_assert_int_ge(find(0, "$CAERR,120000,NMEA,4,UNSUPPORTED_COMMAND*", 0), 0);
    host(0, "garbage \x01\xff");
    ck_assert_int_ge(find(0, "$CAERR,120000,NMEA,1,", 0), 0);
    host(0, "$GPGGA,1,2");
    ck_assert_int_ge(find(0, "$CAERR,120000,NMEA,3,", 0), 0);
    host(0, "$CCCYC,0,1,2,9,0,1"); /* rate 9 */
    host(0, "$CCCYC,0,1,2,0,0,2"); /* two frames at rate 0 */
    host(0, "$CCTXD,1,2,1,abc");   /* odd hex */
    host(0, "$CCCLK,2011,2,30,12,0,0");
    ck_assert_int_eq(count(0, "$CAERR,120000,NMEA,5,"), 4);
    ck_assert_int_eq(n_tx, 0);
    /* a line longer than the reader holds, then a good one */
    char big[KELP_MAX_NMEA_LINE + 100];
    memset(big, 'A', sizeof big - 1);
    big[0] = '$';
    big[sizeof big - 1] = '\0';
    host(0, big);
    host(0, "$CCCFQ,SRC");
    ck_assert_str_eq(lines[0][nlines[0] - 1].s, "$CACFG,SRC,1*33");
    ck_assert_uint_eq(kelp_modemsim_get_counters(&mod[0])->host_errors, 9);
}
END_TEST

/* ------------------------------------------------------------------ ranging and mini-packets */

START_TEST(two_way_ping_real_sentences)
{
    /* real examples 5-7: $CCMPC,1,2 -> $CAMPA,1,2*5D at node 2, $CAMPR,2,1,0.0101*7C at node 1:
     * one-way travel time 0.0101 s = 15.15 m at 1500 m/s */
    world(2);
    kelp_modemsim_cfg a = cfg_for(1, 0, 0), b = cfg_for(2, 15.15, 0);
    add(0, &a);
    add(1, &b);
    host(0, "$CCMPC,1,2");
    ck_assert_str_eq(lines[0][0].s, cs("$CAMPC,1,2"));
    run_until(T0 + 3 * S);
    int i = find(1, "$CAMPA", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_str_eq(lines[1][i].s, "$CAMPA,1,2*5D");
    /* heard when the 0.5 s ping has arrived: 0.5 + 0.0101 s */
    ck_assert_double_eq_tol(t_of(1, i), 0.5101, 0.006);
    i = find(0, "$CAMPR", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_str_eq(lines[0][i].s, "$CAMPR,2,1,0.0101*7C");
    ck_assert_int_eq(count(0, "$CATXF,2*"), 1);
    ck_assert_int_eq(count(1, "$CATXF,2*"), 1);
}
END_TEST

START_TEST(ping_range_is_distance_over_sound_speed)
{
    world(3);
    kelp_modemsim_cfg a = cfg_for(1, 0, 0), b = cfg_for(2, 3000, 4000), c = cfg_for(3, -100, 0);
    a.depth = 10;
    b.depth = 10;
    add(0, &a);
    add(1, &b);
    add(2, &c);
    host(0, "$CCMPC,1,2");
    run_until(T0 + 10 * S);
    int i = find(0, "$CAMPR", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_str_eq(lines[0][i].s, cs("$CAMPR,2,1,3.3333")); /* 5000 m */
    /* modem 3 heard the ping (not for it): no $CAMPA there */
    ck_assert_int_eq(find(2, "$CAMPA", 0), -1);
    /* out of range: no answer */
    world(2);
    b.max_range = 4000;
    add(0, &a);
    add(1, &b);
    host(0, "$CCMPC,1,2");
    run_until(T0 + 12 * S);
    ck_assert_int_eq(find(0, "$CAMPR", 0), -1);
    ck_assert_uint_eq(kelp_modemsim_get_counters(&mod[1])->out_of_range, 1);
}
END_TEST

START_TEST(mini_packet_real_sentence)
{
    /* real examples 8-9: $CCMUC,1,2,1FAB -> $CAMUA,1,2,1fab*20 at node 2 */
    world(2);
    kelp_modemsim_cfg a = cfg_for(1, 0, 0), b = cfg_for(2, 300, 0);
    add(0, &a);
    add(1, &b);
    host(0, "$CCMUC,1,2,1FAB");
    ck_assert_str_eq(lines[0][0].s, cs("$CAMUC,1,2,1FAB"));
    run_until(T0 + 2 * S);
    int i = find(1, "$CAMUA", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_str_eq(lines[1][i].s, "$CAMUA,1,2,1fab*20");
    host(0, "$CCMUC,1,2,2000"); /* more than 13 bits */
    ck_assert_int_ge(find(0, "$CAERR", 0), 0);
}
END_TEST

START_TEST(remus_lbl_travel_times)
{
    world(1);
    kelp_modemsim_cfg c = cfg_for(1, 0, 0);
    c.n_lbl = 3;
    c.lbl_x[0] = 1000;
    c.lbl_y[1] = 2000;
    c.lbl_x[2] = 3100;
    add(0, &c);
    /* Goby: $CCPDT,1,src%4+1,0,0,int(max_range*2/1500*1000+50),b1..b4; max_range 3000 -> 4050 ms;
     * beacon C (3100 m, two-way 4.18 s) is enabled but its reply comes after the timeout */
    host(0, "$CCPDT,1,2,0,0,4050,1,1,1,0");
    ck_assert_str_eq(lines[0][0].s, cs("$SNPDT,1,2,0,0,4050,1,1,1,0"));
    run_until(T0 + 4 * S);
    ck_assert_int_eq(find(0, "$SNTTA", 0), -1);
    run_until(T0 + 4060000);
    int i = find(0, "$SNTTA", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_str_eq(lines[0][i].s, cs("$SNTTA,0.6667,1.3333,,,120004.05"));
}
END_TEST

/* ------------------------------------------------------------------ data cycles */

START_TEST(local_cycle_with_ack_timeline)
{
    /* modem 1 sends one rate-0 frame with ack to modem 2, 1500 m away (1 s of travel) */
    world(2);
    kelp_modemsim_cfg a = cfg_for(1, 0, 0), b = cfg_for(2, 1500, 0);
    add(0, &a);
    add(1, &b);
    host(0, "$CCCYC,0,1,2,0,1,1");
    ck_assert_str_eq(lines[0][0].s, cs("$CACYC,0,1,2,0,1,1"));
    ck_assert_str_eq(lines[0][1].s, cs("$CATXP,2")); /* the cycle init goes out */
    ck_assert_str_eq(lines[0][2].s, cs("$CADRQ,120000,1,2,1,32,1"));
    host(0, "$CCTXD,1,2,1,200aa2a30040461c7187e22111950457");
    ck_assert_str_eq(lines[0][3].s, cs("$CATXD,1,2,1,16"));
    run_until(T0 + 10 * S);
    /* receiver: cycle init heard at 1 s (0..1 s on the water, +1 s travel) = 2 s; the 3.2 s data
     * packet starts after the cycle init (1 s) and arrives 2.0 .. 5.2 s */
    int i = find(1, "$CACYC", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_str_eq(lines[1][i].s, cs("$CACYC,0,1,2,0,1,1"));
    ck_assert_double_eq_tol(t_of(1, i), 2.0, 0.006);
    i = find(1, "$CARXD", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_str_eq(lines[1][i].s, cs("$CARXD,1,2,1,1,200aa2a30040461c7187e22111950457"));
    ck_assert_double_eq_tol(t_of(1, i), 5.2, 0.006);
    /* the ack: 0.25 s turnaround, 0.5 s mini-packet, 1 s back: $CAACK,2,1,1,1 at 6.95 s */
    i = find(0, "$CAACK", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_str_eq(lines[0][i].s, cs("$CAACK,2,1,1,1"));
    ck_assert_double_eq_tol(t_of(0, i), 6.95, 0.006);
    /* transmit reports at the sender: cycle init (mini) and data (16 bytes), each TXP then TXF */
    ck_assert_int_eq(count(0, "$CATXP,16*"), 1);
    ck_assert_int_ge(find(0, "$CATXF,16*", 0), 0);
    ck_assert_double_eq_tol(t_of(0, find(0, "$CATXF,16*", 0)), 4.2, 0.006);
    ck_assert_int_eq(count(1, "$CATXF,2*"), 1); /* the ack */
    ck_assert_uint_eq(kelp_modemsim_get_counters(&mod[0])->tx[KELP_MODEMSIM_PKT_DATA], 1);
    ck_assert_uint_eq(kelp_modemsim_get_counters(&mod[1])->frames_rx, 1);
}
END_TEST

START_TEST(multi_frame_rates_and_early_stop)
{
    /* rate 2: three 64-byte frames requested one DRQ at a time */
    world(2);
    kelp_modemsim_cfg a = cfg_for(1, 0, 0), b = cfg_for(2, 150, 0);
    add(0, &a);
    add(1, &b);
    host(0, "$CCCYC,0,1,2,2,0,3");
    char hex[129];
    for (int f = 1; f <= 3; f++) {
        char want[64];
        snprintf(want, sizeof want, "$CADRQ,120000,1,2,0,64,%d", f);
        ck_assert_str_eq(lines[0][nlines[0] - 1].s, cs(want));
        for (int i = 0; i < 128; i++) hex[i] = "0123456789abcdef"[(i + f) % 16];
        hex[128] = '\0';
        char txd[200];
        snprintf(txd, sizeof txd, "$CCTXD,1,2,0,%s", hex);
        host(0, txd);
    }
    ck_assert_int_eq(count(0, "$CADRQ"), 3);
    run_until(T0 + 6 * S);
    ck_assert_int_eq(count(1, "$CARXD,1,2,0,"), 3);
    ck_assert_int_ge(find(1, "$CARXD,1,2,0,3,", 0), 0);
    ck_assert_int_eq(count(1, "$CAACK"), 0); /* no ack asked */
    ck_assert_int_eq(count(0, "$CAACK"), 0);
    /* an empty $CCTXD (Goby's blank) ends the requests: rate 5 with one frame */
    world(2);
    add(0, &a);
    add(1, &b);
    host(0, "$CCCYC,0,1,2,5,1,8");
    host(0, "$CCTXD,1,2,1,0102");
    ck_assert_str_eq(lines[0][nlines[0] - 1].s, cs("$CADRQ,120000,1,2,1,256,2"));
    host(0, "$CCTXD,1,2,1,");
    ck_assert_str_eq(lines[0][nlines[0] - 1].s, cs("$CATXD,1,2,1,0"));
    run_until(T0 + 6 * S);
    ck_assert_int_eq(count(0, "$CADRQ"), 2);
    ck_assert_int_eq(count(1, "$CARXD"), 1);
    ck_assert_int_ge(find(0, "$CAACK,2,1,1,1", 0), 0);
    /* rate 5 with all eight frames lasts 8*256*8/5300 s */
    world(2);
    add(0, &a);
    add(1, &b);
    host(0, "$CCCYC,0,1,0,5,0,8");
    for (int f = 0; f < 8; f++) host(0, "$CCTXD,1,0,0,aa55");
    run_until(T0 + 8 * S);
    ck_assert_int_eq(count(1, "$CARXD,1,0,0,"), 8);
    int i = find(1, "$CARXD,1,0,0,8,aa55", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_double_eq_tol(t_of(1, i), 1.0 + 16384.0 / 5300.0 + 0.1, 0.006);
}
END_TEST

START_TEST(drq_timeout_and_no_data)
{
    world(2);
    kelp_modemsim_cfg a = cfg_for(1, 0, 0), b = cfg_for(2, 150, 0);
    add(0, &a);
    add(1, &b);
    host(0, "$CCCYC,0,1,2,0,1,1");
    run_until(T0 + 8 * S);
    /* only the cycle init went out; the receiver saw a cycle but no data */
    ck_assert_int_eq(n_tx, 1);
    ck_assert_int_ge(find(1, "$CACYC,0,1,2,0,1,1", 0), 0);
    ck_assert_int_eq(find(1, "$CARXD", 0), -1);
    /* $CCTXD given ahead of the cycle is used without a DRQ */
    world(2);
    add(0, &a);
    add(1, &b);
    host(0, "$CCTXD,1,2,0,c0ffee");
    host(0, "$CCCYC,0,1,2,0,0,1");
    ck_assert_int_eq(count(0, "$CADRQ"), 0);
    run_until(T0 + 6 * S);
    ck_assert_int_ge(find(1, "$CARXD,1,2,0,1,c0ffee", 0), 0);
}
END_TEST

START_TEST(polled_cycle)
{
    /* topside 1 polls vehicle 2 to send to 1 (MAC_POLLED third-party cycle, ACK 1) */
    world(2);
    kelp_modemsim_cfg a = cfg_for(1, 0, 0), b = cfg_for(2, 750, 0);
    add(0, &a);
    add(1, &b);
    host(0, "$CCCYC,0,2,1,0,1,1");
    ck_assert_str_eq(lines[0][0].s, cs("$CACYC,0,2,1,0,1,1"));
    ck_assert_int_eq(find(0, "$CADRQ", 0), -1); /* not ours to send */
    run_until(T0 + 1600000);
    /* at 2: cycle init heard at 1.5 s, then the DRQ */
    int i = find(1, "$CACYC,0,2,1,0,1,1", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_double_eq_tol(t_of(1, i), 1.5, 0.006);
    ck_assert_str_eq(lines[1][i + 1].s, cs("$CADRQ,120001,2,1,1,32,1"));
    host(1, "$CCTXD,2,1,1,2a2b");
    run_until(T0 + 10 * S);
    /* data starts 0.25 s after the poll was heard (1.75 s), 3.2 s long, 0.5 s of travel */
    i = find(0, "$CARXD", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_str_eq(lines[0][i].s, cs("$CARXD,2,1,1,1,2a2b"));
    ck_assert_double_eq_tol(t_of(0, i), 1.75 + 3.2 + 0.5, 0.006);
    i = find(1, "$CAACK", 0);
    ck_assert_int_ge(i, 0);
    ck_assert_str_eq(lines[1][i].s, cs("$CAACK,1,2,1,1"));
}
END_TEST

START_TEST(loss_is_seeded_and_total_loss_loses_all)
{
    kelp_modemsim_cfg a = cfg_for(1, 0, 0), b = cfg_for(2, 150, 0);
    b.loss_probability = 1.0;
    world(2);
    add(0, &a);
    add(1, &b);
    host(0, "$CCCYC,0,1,2,0,1,1");
    host(0, "$CCTXD,1,2,1,01");
    run_until(T0 + 8 * S);
    ck_assert_int_eq(find(1, "$CACYC", 0), -1);
    ck_assert_int_eq(find(1, "$CARXD", 0), -1);
    ck_assert_int_eq(find(0, "$CAACK", 0), -1);
    ck_assert_int_eq(n_lost[1][KELP_MODEMSIM_LOSS_RANDOM], 2); /* cycle init and the frame */
    /* p = 0.5: the same seed loses the same frames, a different seed others */
    int got[3];
    uint64_t seeds[3] = { 7, 7, 8 };
    char pattern[3][64];
    for (int r = 0; r < 3; r++) {
        world(2);
        b.loss_probability = 0.5;
        b.seed = seeds[r];
        add(0, &a);
        add(1, &b);
        host(0, "$CCCYC,0,1,2,5,0,8");
        for (int f = 0; f < 8; f++) host(0, "$CCTXD,1,2,0,01");
        run_until(T0 + 5 * S);
        for (int k = 0; k < 5; k++) {
            host(0, "$CCCYC,0,1,2,5,0,8");
            for (int f = 0; f < 8; f++) host(0, "$CCTXD,1,2,0,01");
            run_until(now + 5 * S);
        }
        got[r] = count(1, "$CARXD");
        memset(pattern[r], 0, sizeof pattern[r]);
        int n = 0;
        for (int i = 0; i < nlines[1] && n < 63; i++)
            if (!strncmp(lines[1][i].s, "$CARXD", 6)) pattern[r][n++] = lines[1][i].s[13];
    }
    ck_assert_int_eq(got[0], got[1]);
    ck_assert_str_eq(pattern[0], pattern[1]);
    ck_assert_int_gt(got[0], 10); /* 48 frames at p = 0.5 */
    ck_assert_int_lt(got[0], 38);
    ck_assert(got[2] != got[0] || strcmp(pattern[2], pattern[0]) != 0);
}
END_TEST

START_TEST(half_duplex_and_collisions)
{
    /* 2 is pinging 3 while the data of 1 reaches it: the data is lost at 2 (half duplex) */
    world(3);
    kelp_modemsim_cfg a = cfg_for(1, 0, 0), b = cfg_for(2, 1500, 0), c = cfg_for(3, 1500, 1500);
    add(0, &a);
    add(1, &b);
    add(2, &c);
    host(0, "$CCCYC,0,1,2,0,0,1");
    host(0, "$CCTXD,1,2,0,01");
    run_until(T0 + 3 * S); /* data on the water 1.0 .. 4.2 s, at 2 from 2.0 .. 5.2 s */
    host(1, "$CCMPC,2,3");
    run_until(T0 + 10 * S);
    ck_assert_int_eq(find(1, "$CARXD", 0), -1);
    ck_assert_int_eq(n_lost[1][KELP_MODEMSIM_LOSS_HALF_DUPLEX], 1);
    /* 1 and 3 both send data to 2 at once: both lost there (collision) */
    world(3);
    add(0, &a);
    add(1, &b);
    add(2, &c);
    host(0, "$CCCYC,0,1,2,0,0,1");
    host(0, "$CCTXD,1,2,0,01");
    host(2, "$CCCYC,0,3,2,0,0,1");
    host(2, "$CCTXD,3,2,0,03");
    run_until(T0 + 10 * S);
    ck_assert_int_eq(find(1, "$CARXD", 0), -1);
    ck_assert_int_eq(find(1, "$CACYC", 0), -1);
    ck_assert_int_eq(n_lost[1][KELP_MODEMSIM_LOSS_COLLISION], 4); /* two cycle inits, two data packets */
    /* the same two transmissions 6 s apart (no overlap): both received */
    world(3);
    add(0, &a);
    add(1, &b);
    add(2, &c);
    host(0, "$CCCYC,0,1,2,0,0,1");
    host(0, "$CCTXD,1,2,0,01");
    run_until(T0 + 6 * S);
    host(2, "$CCCYC,0,3,2,0,0,1");
    host(2, "$CCTXD,3,2,0,03");
    run_until(T0 + 14 * S);
    ck_assert_int_ge(find(1, "$CARXD,1,2,0,1,01", 0), 0);
    ck_assert_int_ge(find(1, "$CARXD,3,2,0,1,03", 0), 0);
    ck_assert_int_eq(n_lost[1][KELP_MODEMSIM_LOSS_COLLISION], 0);
}
END_TEST

START_TEST(stale_and_overflow_are_counted)
{
    world(2);
    kelp_modemsim_cfg a = cfg_for(1, 0, 0);
    add(0, &a);
    static kelp_modemsim_pkt p;
    memset(&p, 0, sizeof p);
    p.kind = KELP_MODEMSIM_PKT_MINI;
    p.instance = 999;
    p.src = 5;
    p.dest = 1;
    p.start = SEC(now - 10 * S);
    p.duration = SEC(500000);
    ck_assert_int_eq(kelp_modemsim_hear(&mod[0], &p, SEC(now)), KELP_OK);
    ck_assert_uint_eq(kelp_modemsim_get_counters(&mod[0])->lost_stale, 1);
    /* own packets are ignored */
    p.instance = a.instance;
    p.start = SEC(now);
    ck_assert_int_eq(kelp_modemsim_hear(&mod[0], &p, SEC(now)), KELP_OK);
    p.instance = 999;
    int rc = KELP_OK;
    for (int i = 0; i < KELP_MAX_MSIM_ARRIVALS + 1; i++) {
        p.seq = (uint32_t)i;
        p.start = SEC(now + i * 10 * S);
        rc = kelp_modemsim_hear(&mod[0], &p, SEC(now));
    }
    ck_assert_int_eq(rc, KELP_ERR_NOSPACE);
    ck_diag(&mod[0].diag, KELP_ERR_NOSPACE, "modemsim: too many packets in flight");
    ck_assert_uint_eq(kelp_modemsim_get_counters(&mod[0])->overflow, 1);
}
END_TEST

START_TEST(init_rejects_bad_configuration)
{
    kelp_modemsim m;
    kelp_modemsim_cfg c;
    kelp_modemsim_cfg_default(&c);
    c.modem_id = 0;
    ck_assert_int_eq(kelp_modemsim_init(&m, &c, &OPS, NULL, SEC(T0)), KELP_ERR_ARG);
    kelp_modemsim_cfg_default(&c);
    c.loss_probability = 1.5;
    ck_assert_int_eq(kelp_modemsim_init(&m, &c, &OPS, NULL, SEC(T0)), KELP_ERR_ARG);
    kelp_modemsim_cfg_default(&c);
    c.sound_speed = 0;
    ck_assert_int_eq(kelp_modemsim_init(&m, &c, &OPS, NULL, SEC(T0)), KELP_ERR_ARG);
    kelp_modemsim_cfg_default(&c);
    c.ci_seconds = -1;
    ck_assert_int_eq(kelp_modemsim_init(&m, &c, &OPS, NULL, SEC(T0)), KELP_ERR_ARG);
    kelp_modemsim_cfg_default(&c);
    c.revision = "a,b";
    ck_assert_int_eq(kelp_modemsim_init(&m, &c, &OPS, NULL, SEC(T0)), KELP_ERR_ARG);
    kelp_modemsim_cfg_default(&c);
    c.x = NAN;
    ck_assert_int_eq(kelp_modemsim_init(&m, &c, &OPS, NULL, SEC(T0)), KELP_ERR_ARG);
    kelp_modemsim_cfg_default(&c);
    ck_assert_int_eq(kelp_modemsim_init(&m, &c, &OPS, NULL, SEC(T0)), KELP_OK);
    ck_assert(isinf(kelp_modemsim_next_due(&m)));
}
END_TEST

/* ------------------------------------------------------------------ pAcommsPoller core */

START_TEST(poller_slots_and_update_text)
{
    kelp_mac_slot s[3];
    kelp_diag bad = {0};
    ck_assert_int_eq(kelp_poller_parse_slot("src=1,dest=3,rate=0,type=SLOT_DATA,slot_seconds=15", 10, &s[0], &bad),
                     KELP_OK);
    ck_assert_int_eq(s[0].src, 1);
    ck_assert_int_eq(s[0].dest, 3);
    ck_assert_int_eq(s[0].type, KELP_SLOT_DATA);
    ck_assert_uint_eq(s[0].slot_seconds, 15);
    /* defaults: dest -1 (ask the queue), rate 0, data, the default seconds */
    ck_assert_int_eq(kelp_poller_parse_slot("src=2", 10, &s[1], &bad), KELP_OK);
    ck_assert_int_eq(s[1].dest, -1);
    ck_assert_uint_eq(s[1].rate, 0);
    ck_assert_uint_eq(s[1].slot_seconds, 10);
    ck_assert_int_eq(kelp_poller_parse_slot(" SRC = 3 , Type = ping , Slot_Seconds = 5 ", 10, &s[2], &bad), KELP_OK);
    ck_assert_int_eq(s[2].type, KELP_SLOT_PING);
    /* acomms.md 2.4 [DERIVED]: the document's C++ MACUpdate example serialized */
    char buf[512];
    size_t len;
    ck_assert_int_eq(kelp_poller_format_update(1, KELP_MAC_UPDATE_ADD, s, 1, buf, sizeof buf, &len), KELP_OK);
    ck_assert_str_eq(buf, "dest: 1 update_type: ADD slot { src: 1 dest: 3 rate: 0 type: SLOT_DATA slot_seconds: 15 }");
    ck_assert_uint_eq(len, strlen(buf));
    ck_assert_int_eq(kelp_poller_format_update(1, KELP_MAC_UPDATE_REPLACE, s, 3, buf, sizeof buf, &len), KELP_OK);
    ck_assert_str_eq(buf, "dest: 1 update_type: REPLACE"
                          " slot { src: 1 dest: 3 rate: 0 type: SLOT_DATA slot_seconds: 15 }"
                          " slot { src: 2 dest: -1 rate: 0 type: SLOT_DATA slot_seconds: 10 }"
                          " slot { src: 3 dest: -1 rate: 0 type: SLOT_PING slot_seconds: 5 }");
    ck_assert_int_eq(kelp_poller_format_update(1, KELP_MAC_UPDATE_REPLACE, s, 3, buf, 40, &len), KELP_ERR_NOSPACE);
    ck_assert_int_eq(kelp_poller_format_slot(&s[2], buf, sizeof buf, &len), KELP_OK);
    ck_assert_str_eq(buf, "src=3,dest=-1,rate=0,type=ping,slot_seconds=5");
    /* errors name the key */
    kelp_diag_clear(&bad);
    ck_assert_int_eq(kelp_poller_parse_slot("dest=1", 10, &s[0], &bad), KELP_ERR_PARSE);
    ck_diag(&bad, KELP_ERR_PARSE, "src");
    kelp_diag_clear(&bad);
    ck_assert_int_eq(kelp_poller_parse_slot("src=1,rate=6", 10, &s[0], &bad), KELP_ERR_RANGE);
    ck_diag(&bad, KELP_ERR_RANGE, "rate");
    ck_assert_int_eq(kelp_poller_parse_slot("src=32", 10, &s[0], &bad), KELP_ERR_RANGE);
    kelp_diag_clear(&bad);
    ck_assert_int_eq(kelp_poller_parse_slot("src=1,type=bogus", 10, &s[0], &bad), KELP_ERR_PARSE);
    ck_diag(&bad, KELP_ERR_PARSE, "type");
    ck_assert_int_eq(kelp_poller_parse_slot("src=1,colour=red", 10, &s[0], &bad), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_poller_parse_slot("src=1,slot_seconds=0", 10, &s[0], &bad), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_poller_parse_slot("src=1x", 10, &s[0], &bad), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_poller_parse_slot("src", 10, &s[0], &bad), KELP_ERR_PARSE);
}
END_TEST

Suite *kelp_modemsim_suite(void)
{
    Suite *s = suite_create("modemsim");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, rate_table_and_durations);
    tcase_add_test(tc, rng_is_splitmix64_and_seeded);
    tcase_add_test(tc, packet_codec_round_trip_and_rejects);
    tcase_add_test(tc, clock_cfg_and_queries);
    tcase_add_test(tc, revision_at_boot_and_heartbeat);
    tcase_add_test(tc, bad_host_input_gets_caerr);
    tcase_add_test(tc, two_way_ping_real_sentences);
    tcase_add_test(tc, ping_range_is_distance_over_sound_speed);
    tcase_add_test(tc, mini_packet_real_sentence);
    tcase_add_test(tc, remus_lbl_travel_times);
    tcase_add_test(tc, local_cycle_with_ack_timeline);
    tcase_add_test(tc, multi_frame_rates_and_early_stop);
    tcase_add_test(tc, drq_timeout_and_no_data);
    tcase_add_test(tc, polled_cycle);
    tcase_add_test(tc, loss_is_seeded_and_total_loss_loses_all);
    tcase_add_test(tc, half_duplex_and_collisions);
    tcase_add_test(tc, stale_and_overflow_are_counted);
    tcase_add_test(tc, init_rejects_bad_configuration);
    tcase_add_test(tc, poller_slots_and_update_text);
    suite_add_tcase(s, tc);
    return s;
}
