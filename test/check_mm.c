/* Micro-Modem driver core: recorded conversations replayed against the state machine, comparing
 * the lines it writes (goby-wire.md 10; acomms.md 5 and 9 items 11-17; real sentences from
 * shared/data/real_nmea_examples.md). */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kelp/mmdriver.h>

#define S 1000000LL
static const int64_t T = 1704196800LL * S; /* 2024-01-02 12:00:00 UTC */
/* the test clock counts whole microseconds; the driver takes kelp_time seconds */
#define SEC(us) ((kelp_time)(us) / 1e6)

/* ------------------------------------------------------------------ capture */

#define MAXL 64
static char out[MAXL][KELP_MAX_NMEA_LINE + 16];
static int nout, rd;           /* lines written, lines already checked */
static kelp_mmdriver_event ev[MAXL];
static uint8_t evdata[MAXL][KELP_MAX_ACOMMS_FRAME];
static int nev;
static kelp_mmdriver_frame next_frames[KELP_MAX_MM_FRAMES];
static int n_next;
static int n_requests;
static kelp_mmdriver_data_request last_req;

static void w(const char *b, size_t n, void *u)
{
    (void)u;
    ck_assert_int_lt(nout, MAXL);
    ck_assert_uint_lt(n, sizeof out[0]);
    memcpy(out[nout], b, n);
    out[nout][n] = '\0';
    nout++;
}

static void on_ev(const kelp_mmdriver_event *e, void *u)
{
    (void)u;
    if (nev >= MAXL) return;
    ev[nev] = *e;
    if (e->data && e->data_len) {
        memcpy(evdata[nev], e->data, e->data_len);
        ev[nev].data = evdata[nev];
    }
    ev[nev].raw = "";
    nev++;
}

static void dr(const kelp_mmdriver_data_request *req, kelp_mmdriver_frame *f, void *u)
{
    (void)u;
    n_requests++;
    last_req = *req;
    if ((int)req->frame < n_next) *f = next_frames[req->frame];
}

static const kelp_mmdriver_ops OPS = { w, on_ev, dr };

static void cs(const char *body, char *dst)
{
    unsigned x = 0;
    for (const char *p = body + 1; *p; p++) x ^= (unsigned char)*p;
    sprintf(dst, "%s*%02X", body, x);
}

/* expect the next written line to be `body` + "*hh" + CRLF (prefix allowed) */
static void expect(const char *prefix, const char *body)
{
    char want[2 * KELP_MAX_NMEA_LINE + 64], line[KELP_MAX_NMEA_LINE + 16];
    cs(body, line);
    snprintf(want, sizeof want, "%s%s\r\n", prefix, line);
    ck_assert_msg(rd < nout, "expected %s, nothing written", body);
    ck_assert_str_eq(out[rd], want);
    rd++;
}

static void expect_raw(const char *exact)
{
    ck_assert_msg(rd < nout, "expected %s, nothing written", exact);
    ck_assert_str_eq(out[rd], exact);
    rd++;
}

static void expect_none(void)
{
    ck_assert_msg(rd == nout, "unexpected line: %s", rd < nout ? out[rd] : "");
}

static void feed(kelp_mmdriver *mm, const char *body_without_cs, int64_t t)
{
    char line[KELP_MAX_NMEA_LINE + 8];
    cs(body_without_cs, line);
    strcat(line, "\r\n");
    ck_assert_int_eq(kelp_mmdriver_feed(mm, (const uint8_t *)line, strlen(line), SEC(t)), KELP_OK);
}

static void feed_pfx(kelp_mmdriver *mm, const char *pfx, const char *body_without_cs, int64_t t)
{
    char line[KELP_MAX_NMEA_LINE + 8], all[KELP_MAX_NMEA_LINE + 16];
    cs(body_without_cs, line);
    snprintf(all, sizeof all, "%s%s\r\n", pfx, line);
    ck_assert_int_eq(kelp_mmdriver_feed(mm, (const uint8_t *)all, strlen(all), SEC(t)), KELP_OK);
}

static void feed_raw(kelp_mmdriver *mm, const char *exact, int64_t t)
{
    ck_assert_int_eq(kelp_mmdriver_feed(mm, (const uint8_t *)exact, strlen(exact), SEC(t)), KELP_OK);
}

static void tick(kelp_mmdriver *mm, int64_t t)
{
    ck_assert_int_eq(kelp_mmdriver_tick(mm, SEC(t)), KELP_OK);
}

static int find_ev(kelp_mmdriver_event_kind k, int from)
{
    for (int i = from; i < nev; i++)
        if (ev[i].kind == k) return i;
    return -1;
}

static int count_evk(kelp_mmdriver_event_kind k)
{
    int n = 0;
    for (int i = 0; i < nev; i++) n += ev[i].kind == k;
    return n;
}

static void reset_capture(void)
{
    nout = rd = nev = n_next = n_requests = 0;
}

static void make(kelp_mmdriver *mm, int id, bool reset, const char *nvram, int hydroid)
{
    reset_capture();
    kelp_mmdriver_cfg c;
    memset(&c, 0, sizeof c);
    c.modem_id = id;
    c.reset_nvram = reset;
    if (nvram) { c.nvram_cfg[0] = nvram; c.n_nvram = 1; }
    c.hydroid_gateway_id = hydroid;
    ck_assert_int_eq(kelp_mmdriver_init(mm, &c, &OPS, NULL), KELP_OK);
}

/* the start-up conversation of modem 1 with nvram "cst,1" */
static void boot(kelp_mmdriver *mm)
{
    make(mm, 1, false, "cst,1", 0);
    ck_assert_int_eq(kelp_mmdriver_start(mm, SEC(T)), KELP_OK);
    expect("", "$CCCLK,2024,1,2,12,0,0");
    expect_none();
    feed(mm, "$CACLK,2024,1,2,12,0,0", T + 300000);   /* arrives during the 1 s pause */
    ck_assert(!kelp_mmdriver_clock_ok(mm));
    tick(mm, T + 500000);
    expect_none();
    tick(mm, T + 1000000);                             /* pause over: the reply is processed */
    ck_assert(kelp_mmdriver_clock_ok(mm));
    expect_none();                                     /* the next command goes at the next tick */
    tick(mm, T + 1100000);
    expect("", "$CCCFG,SRC,1");
    tick(mm, T + 1200000);
    expect_none();                                     /* one command outstanding */
    feed_raw(mm, "$CACFG,SRC,1*33\r\n", T + 1300000);  /* real reply */
    tick(mm, T + 1400000);
    expect("", "$CCCFG,CST,1");                        /* nvram_cfg upper-cased */
    feed(mm, "$CACFG,CST,1", T + 1500000);
    tick(mm, T + 1600000);
    expect("", "$CCCFQ,ALL");
    feed(mm, "$CACFG,AGC,0", T + 1700000);             /* the first $CACFG completes $CCCFQ */
    feed(mm, "$CACFG,AGN,250", T + 1700000);
    tick(mm, T + 1800000);
    expect_none();
    ck_assert_uint_eq(kelp_mmdriver_pending(mm), 0);
}

START_TEST(startup_sequence)
{
    kelp_mmdriver mm;
    boot(&mm);
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_NMEA_OUT), 4);
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_NMEA_IN), 5);
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_CLOCK), 1);
    /* reset_nvram: $CCCFG,ALL,0 before SRC */
    kelp_mmdriver m2;
    make(&m2, 3, true, NULL, 0);
    ck_assert_int_eq(kelp_mmdriver_start(&m2, SEC(T + 59 * S)), KELP_OK);
    expect("", "$CCCLK,2024,1,2,12,0,59");
    feed(&m2, "$CACLK,2024,1,2,12,0,59", T + 60 * S);
    tick(&m2, T + 61 * S);
    expect("", "$CCCFG,ALL,0");
    feed(&m2, "$CACFG,ALL,0", T + 61 * S);
    tick(&m2, T + 62 * S);
    expect("", "$CCCFG,SRC,3");
    /* modem_id 0 (broadcast) is refused */
    kelp_mmdriver_cfg c;
    memset(&c, 0, sizeof c);
    ck_assert_int_eq(kelp_mmdriver_init(&m2, &c, &OPS, NULL), KELP_ERR_ARG);
}
END_TEST

START_TEST(data_cycle_local)
{
    kelp_mmdriver mm;
    boot(&mm);
    reset_capture();
    /* the queue has one frame for node 2 with ack */
    memset(next_frames, 0, sizeof next_frames);
    next_frames[0].src = 1;
    next_frames[0].dest = 2;
    next_frames[0].ack_requested = true;
    static const uint8_t hello[11] = { 0x20, 0x00, 0xaa, 0x30, 0x02, 0x00, 'h', 'e', 'l', 'l', 'o' };
    memcpy(next_frames[0].data, hello, 11);
    next_frames[0].len = 11;
    n_next = 1;
    ck_assert_int_eq(kelp_mmdriver_initiate_transmission(&mm, 1, -1, 0, SEC(T + 10 * S)), KELP_OK);
    ck_assert_int_eq(n_requests, 1);                 /* rate 0: one frame asked for */
    ck_assert_uint_eq(last_req.max_bytes, 32);
    ck_assert_int_eq(last_req.dest, -1);
    expect("", "$CCCYC,0,1,2,0,1,1");                 /* ADR2 and ACK from the cached frame */
    feed(&mm, "$CACYC,0,1,2,0,1,1", T + 10 * S + 200000);  /* our echo: no second data request */
    ck_assert_int_eq(n_requests, 1);
    feed(&mm, "$CADRQ,120010,1,2,1,32,1", T + 11 * S);
    expect("", "$CCTXD,1,2,1,2000aa30020068656c6c6f");    /* lower-case hex, written at once */
    feed(&mm, "$CATXD,1,2,1,2000aa30020068656c6c6f", T + 11 * S + 100000);
    feed(&mm, "$CAACK,2,1,1,1", T + 14 * S);
    int a = find_ev(KELP_MMDRIVER_EV_ACK, 0);
    ck_assert_int_ge(a, 0);
    ck_assert_int_eq(ev[a].src, 2);
    ck_assert_int_eq(ev[a].dest, 1);
    ck_assert_uint_eq(ev[a].frame, 0);
    /* an ack for a frame not sent with ack this cycle is not reported */
    feed(&mm, "$CAACK,2,1,2,1", T + 14 * S);
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_ACK), 1);
    tick(&mm, T + 15 * S);
    expect_none();

    /* no data: no cycle at all */
    n_next = 0;
    ck_assert_int_eq(kelp_mmdriver_initiate_transmission(&mm, 1, 2, 2, SEC(T + 20 * S)), KELP_OK);
    ck_assert_uint_eq(last_req.max_bytes, 64);
    expect_none();
    /* rate out of range */
    ck_assert_int_eq(kelp_mmdriver_initiate_transmission(&mm, 1, 2, 6, SEC(T + 20 * S)), KELP_ERR_RANGE);
    ck_diag(&mm.diag, KELP_ERR_RANGE, "mmdriver: rate out of range (0..5)");
}
END_TEST

START_TEST(caller_frames_fewer_than_requested)
{
    kelp_mmdriver mm;
    boot(&mm);
    reset_capture();
    /* rate 2 carries 3 frames of 64 bytes; the caller gives one (no data request is made) */
    kelp_mmdriver_frame f;
    memset(&f, 0, sizeof f);
    f.dest = 3;
    f.ack_requested = false;
    f.len = 2;
    f.data[0] = 0xab, f.data[1] = 0xcd;
    ck_assert_int_eq(kelp_mmdriver_transmit_frames(&mm, 2, &f, 1, SEC(T + 10 * S)), KELP_OK);
    ck_assert_int_eq(n_requests, 0);
    expect("", "$CCCYC,0,1,3,2,0,3");               /* the rate's frame count, not the caller's */
    feed(&mm, "$CACYC,0,1,3,2,0,3", T + 10 * S + 200000);
    ck_assert_int_eq(n_requests, 0);
    feed(&mm, "$CADRQ,120010,1,3,0,64,1", T + 11 * S);
    expect("", "$CCTXD,1,3,0,abcd");
    feed(&mm, "$CATXD,1,3,0,abcd", T + 11 * S + 100000);
    feed(&mm, "$CADRQ,120011,1,3,0,64,2", T + 12 * S);
    expect("", "$CCTXD,1,3,0,");                      /* the remaining frames go empty */
    feed(&mm, "$CATXD,1,3,0,", T + 12 * S + 100000);
    feed(&mm, "$CADRQ,120012,1,3,0,64,3", T + 13 * S);
    expect("", "$CCTXD,1,3,0,");
    /* nothing given: nothing sent; more than the rate carries: refused */
    ck_assert_int_eq(kelp_mmdriver_transmit_frames(&mm, 2, &f, 0, SEC(T + 20 * S)), KELP_OK);
    kelp_mmdriver_frame many[4];
    memset(many, 0, sizeof many);
    ck_assert_int_eq(kelp_mmdriver_transmit_frames(&mm, 2, many, 4, SEC(T + 20 * S)), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_mmdriver_transmit_frames(&mm, 7, &f, 1, SEC(T + 20 * S)), KELP_ERR_RANGE);
}
END_TEST

START_TEST(clock_written_late_in_a_second)
{
    /* $CCCLK at hh:mm:ss.95 and the echo held through the 1 s pause: read the moment the
     * pause ends (ss+1.95, within the 2 s skew), not at the caller's next tick (ss+2.05) */
    kelp_mmdriver mm;
    make(&mm, 1, false, NULL, 0);
    ck_assert_int_eq(kelp_mmdriver_start(&mm, SEC(T + 950000)), KELP_OK);
    expect("", "$CCCLK,2024,1,2,12,0,0");
    feed(&mm, "$CACLK,2024,1,2,12,0,0", T + 1300000);
    tick(&mm, T + 1850000);
    ck_assert(!kelp_mmdriver_clock_ok(&mm));
    tick(&mm, T + 2050000);
    ck_assert(kelp_mmdriver_clock_ok(&mm));
    for (int k = 1; k <= 20; k++) tick(&mm, T + 2050000 + k * 100000);
    for (int i = 0; i < nout; i++) ck_assert_msg(strstr(out[i] + 1, "CCCLK") == NULL || i == 0, "second $CCCLK: %s", out[i]);
}
END_TEST

START_TEST(data_request_without_cache_real_vector)
{
    kelp_mmdriver mm;
    boot(&mm);
    reset_capture();
    /* a $CADRQ with nothing cached: Goby answers with an empty data field (real sentence #12) */
    feed(&mm, "$CADRQ,120010,2,1,1,32,1", T + 10 * S);
    expect_raw("$CCTXD,2,1,1,*7A\r\n");
}
END_TEST

START_TEST(remote_cycle_and_third_party_cycle)
{
    kelp_mmdriver mm;
    boot(&mm);
    reset_capture();
    memset(next_frames, 0, sizeof next_frames);
    for (int i = 0; i < 2; i++) {
        next_frames[i].src = 1;
        next_frames[i].dest = 3;
        next_frames[i].len = 2;
        next_frames[i].data[0] = 0x0e;
        next_frames[i].data[1] = (uint8_t)(0xa0 + i);
    }
    n_next = 2;
    /* the master (modem 3) polls us: $CACYC with ADR1 == 1 we did not start -> fetch data now */
    feed(&mm, "$CACYC,0,1,3,1,1,3", T + 5 * S);
    ck_assert_int_eq(n_requests, 3);                  /* frames 0, 1 and the empty frame 2 */
    int c = find_ev(KELP_MMDRIVER_EV_CYCLE, 0);
    ck_assert_int_ge(c, 0);
    ck_assert_int_eq(ev[c].src, 1);
    ck_assert_int_eq(ev[c].dest, 3);
    ck_assert_uint_eq(ev[c].rate, 1);
    ck_assert_uint_eq(ev[c].frame, 3);
    feed(&mm, "$CADRQ,120005,1,3,0,32,2", T + 6 * S);
    expect("", "$CCTXD,1,3,0,0ea1");                  /* frame 2 = cached frame 1 */
    feed(&mm, "$CATXD,1,3,0,0ea1", T + 6 * S);
    feed(&mm, "$CADRQ,120005,1,3,0,32,3", T + 7 * S);
    expect("", "$CCTXD,1,3,0,");                      /* nothing for frame 3 */
    feed(&mm, "$CATXD,1,3,0,", T + 7 * S);
    /* we are the master: a slot src 2 -> dest 1 is a third-party cycle, ACK field 1 */
    reset_capture();
    ck_assert_int_eq(kelp_mmdriver_initiate_transmission(&mm, 2, 1, 0, SEC(T + 8 * S)), KELP_OK);
    ck_assert_int_eq(n_requests, 0);
    expect("", "$CCCYC,0,2,1,0,1,1");
}
END_TEST

START_TEST(receive_ranging_and_toa)
{
    kelp_mmdriver mm;
    boot(&mm);
    reset_capture();
    feed(&mm, "$CARXD,2,1,1,1,2000aa30020068656c6c6f", T + 5 * S);
    int r = find_ev(KELP_MMDRIVER_EV_RECEIVE, 0);
    ck_assert_int_ge(r, 0);
    ck_assert_int_eq(ev[r].src, 2);
    ck_assert_int_eq(ev[r].dest, 1);
    ck_assert(ev[r].ack_requested);
    ck_assert_uint_eq(ev[r].frame, 0);
    ck_assert_uint_eq(ev[r].data_len, 11);
    ck_assert_mem_eq(ev[r].data, "\x20\x00\xaa\x30\x02\x00hello", 11);
    int in = find_ev(KELP_MMDRIVER_EV_NMEA_IN, r);
    ck_assert_int_ge(in, 0);
    ck_assert(ev[in].has_src);
    ck_assert_int_eq(ev[in].src, 2);                  /* for MAC discovery */

    /* two-way ping, real request/reply pair #5/#7 */
    ck_assert_int_eq(kelp_mmdriver_initiate_ranging(&mm, 1, 2, KELP_RANGING_TWO_WAY_PING, 1000, 15, SEC(T + 6 * S)), KELP_OK);
    expect("", "$CCMPC,1,2");
    feed_raw(&mm, "$CAMPR,2,1,0.0101*7C\r\n", T + 7 * S);
    r = find_ev(KELP_MMDRIVER_EV_RANGE, 0);
    ck_assert_int_ge(r, 0);
    ck_assert_int_eq(ev[r].ranging, KELP_RANGING_TWO_WAY_PING);
    ck_assert_int_eq(ev[r].src, 1);                   /* swapped back to match the request */
    ck_assert_int_eq(ev[r].dest, 2);
    ck_assert_uint_eq(ev[r].n_tt, 1);
    ck_assert_double_eq_tol(ev[r].tt[0], 0.0101, 1e-12);
    feed(&mm, "$CAMPC,1,2", T + 7 * S);               /* echo completes $CCMPC */

    /* REMUS LBL: timeout int(1000*2/1500*1000 + 50) = 1383 ms, channel 1 % 4 + 1 = 2 */
    ck_assert_int_eq(kelp_mmdriver_initiate_ranging(&mm, 1, 0, KELP_RANGING_REMUS_LBL, 1000, 15, SEC(T + 8 * S)), KELP_OK);
    tick(&mm, T + 8 * S);
    expect("", "$CCPDT,1,2,0,0,1383,1,1,1,1");
    feed(&mm, "$CAPDT,1,2,0,0,1383,1,1,1,1", T + 8 * S);
    nev = 0;
    feed(&mm, "$SNTTA,0.1,,0.3,0.4,120101.00", T + 9 * S);
    ck_assert_int_eq(ev[0].kind, KELP_MMDRIVER_EV_RANGE);
    ck_assert_int_eq(ev[0].ranging, KELP_RANGING_REMUS_LBL);
    ck_assert_int_eq(ev[0].src, 1);
    ck_assert_uint_eq(ev[0].n_tt, 4);
    ck_assert_double_eq_tol(ev[0].tt[0], 0.1, 1e-12);
    ck_assert(isnan(ev[0].tt[1]));
    ck_assert_double_eq_tol(ev[0].tt[3], 0.4, 1e-12);
    ck_assert_int_eq(kelp_mmdriver_initiate_ranging(&mm, 1, 2, KELP_RANGING_ONE_WAY_SYNCHRONOUS, 0, 0, SEC(T)), KELP_ERR_UNSUPPORTED);

    /* one-way synchronous: $CATOA (mode 3) then the next $CARXD gives 7 candidate times */
    nev = 0;
    feed(&mm, "$CATOA,120102.2500,3", T + 10 * S);
    ck_assert_int_eq(find_ev(KELP_MMDRIVER_EV_RANGE, 0), -1);
    feed(&mm, "$CARXD,3,1,0,1,0102", T + 10 * S);
    r = find_ev(KELP_MMDRIVER_EV_RANGE, 0);
    ck_assert_int_ge(r, 0);
    ck_assert_int_eq(ev[r].ranging, KELP_RANGING_ONE_WAY_SYNCHRONOUS);
    ck_assert_int_eq(ev[r].src, 3);
    ck_assert_int_eq(ev[r].dest, 1);
    ck_assert_uint_eq(ev[r].n_tt, 7);
    ck_assert_double_eq_tol(ev[r].tt[0], 0.25, 1e-9);
    ck_assert_double_eq_tol(ev[r].tt[6], 6.25, 1e-9);
    /* a TOA of mode 1 is ignored; $CARXP drops a pending one */
    nev = 0;
    feed(&mm, "$CATOA,120102.2500,1", T + 11 * S);
    feed(&mm, "$CARXD,3,1,0,1,0102", T + 11 * S);
    feed(&mm, "$CATOA,120103.5,3", T + 12 * S);
    feed(&mm, "$CARXP,1", T + 12 * S);
    feed(&mm, "$CARXD,3,1,0,1,0102", T + 12 * S);
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_RANGE), 0);
}
END_TEST

START_TEST(timeouts_retries_and_death)
{
    kelp_mmdriver mm;
    make(&mm, 1, false, NULL, 0);
    ck_assert_int_eq(kelp_mmdriver_start(&mm, SEC(T)), KELP_OK);
    expect("", "$CCCLK,2024,1,2,12,0,0");
    tick(&mm, T + 2 * S);
    expect_none();
    tick(&mm, T + 3 * S);                     /* 3 s without a reply: written again */
    expect("", "$CCCLK,2024,1,2,12,0,0");
    tick(&mm, T + 6 * S);
    expect("", "$CCCLK,2024,1,2,12,0,0");
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_RETRY), 2);
    tick(&mm, T + 9 * S);                     /* third timeout: the whole command queue is dropped */
    expect_none();
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_GIVE_UP), 1);
    ck_assert_uint_eq(kelp_mmdriver_pending(&mm), 0);
    /* clock still unset, queue empty: $CCCLK again.  Goby leaves "waiting" set when it gives up,
     * so this first write already counts as the 4th consecutive failure (quirk reproduced) */
    tick(&mm, T + 9 * S + 100000);
    expect("", "$CCCLK,2024,1,2,12,0,9");
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_RETRY), 3);
    tick(&mm, T + 11 * S);
    expect_none();
    ck_assert_int_eq(kelp_mmdriver_tick(&mm, SEC(T + 12 * S + 100000)), KELP_ERR_TIMEOUT); /* 5th: dead */
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_DEAD), 1);
    expect_none();
    ck_assert_int_eq(kelp_mmdriver_tick(&mm, SEC(T + 16 * S)), KELP_ERR_TIMEOUT);
    /* the edge reconnects and restarts */
    ck_assert_int_eq(kelp_mmdriver_start(&mm, SEC(T + 20 * S)), KELP_OK);
    expect("", "$CCCLK,2024,1,2,12,0,20");
    /* any sentence from the modem resets the consecutive-failure count */
    tick(&mm, T + 23 * S);
    expect("", "$CCCLK,2024,1,2,12,0,20");
    feed(&mm, "$CAREV,120023,AUV,0.93.0.09", T + 23 * S + 500000);
    ck_assert_uint_eq(mm.global_fail, 0);
}
END_TEST

START_TEST(caerr_nmea_resends_at_once)
{
    kelp_mmdriver mm;
    make(&mm, 1, false, NULL, 0);
    ck_assert_int_eq(kelp_mmdriver_start(&mm, SEC(T)), KELP_OK);
    expect("", "$CCCLK,2024,1,2,12,0,0");
    feed(&mm, "$CAERR,120000,NMEA,1,bad sentence", T + 1 * S + 100000);
    expect("", "$CCCLK,2024,1,2,12,0,0");
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_MODEM_ERROR), 1);
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_RETRY), 1);
    /* another module's error is only reported */
    feed(&mm, "$CAERR,120001,CYCLE,3,timeout", T + 1 * S + 200000);
    expect_none();
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_MODEM_ERROR), 2);
}
END_TEST

START_TEST(clock_checks_rev_and_reboot_pause)
{
    kelp_mmdriver mm;
    boot(&mm);
    reset_capture();
    /* real heartbeat: 18:18:07 is later than 12:00 -> the clock stays good */
    feed_raw(&mm, "$CAREV,181807,AUV,2.0.27087*12", T + 10 * S);
    feed_raw(&mm, "\r\n", T + 10 * S);
    ck_assert(kelp_mmdriver_clock_ok(&mm));
    /* the same heartbeat at 18:18:10 is 3 s behind: clock unset, $CCCLK sent again */
    int64_t t2 = T + (6 * 3600 + 18 * 60 + 10) * S;
    feed_raw(&mm, "$CAREV,181807,AUV,2.0.27087*12\r\n", t2);
    ck_assert(!kelp_mmdriver_clock_ok(&mm));
    tick(&mm, t2 + 100000);
    expect("", "$CCCLK,2024,1,2,18,18,10");
    feed(&mm, "$CACLK,2024,1,2,18,18,9", t2 + 1 * S + 200000);   /* 2.2 s behind: not set */
    ck_assert(!kelp_mmdriver_clock_ok(&mm));
    tick(&mm, t2 + 1 * S + 300000);                               /* so it is sent again */
    expect("", "$CCCLK,2024,1,2,18,18,11");
    feed(&mm, "$CACLK,2024,1,2,18,18,11", t2 + 2 * S + 400000);  /* 1.4 s behind: accepted */
    ck_assert(kelp_mmdriver_clock_ok(&mm));
    /* reboot: 2 s pause; lines arriving meanwhile are processed afterwards */
    nev = 0;
    int64_t t3 = t2 + 10 * S;
    feed_raw(&mm, "$CAREV,000052,INIT,0.93.0.09\r\n$CARXD,2,1,0,1,00ff\r\n", t3);
    ck_assert(!kelp_mmdriver_clock_ok(&mm));
    ck_assert_double_eq(kelp_mmdriver_busy_until(&mm), SEC(t3 + 2 * S));
    ck_assert_int_eq(find_ev(KELP_MMDRIVER_EV_RECEIVE, 0), -1);
    tick(&mm, t3 + 1 * S);
    ck_assert_int_eq(find_ev(KELP_MMDRIVER_EV_RECEIVE, 0), -1);
    expect_none();
    tick(&mm, t3 + 2 * S);                    /* pause over: queue empty + clock unset -> $CCCLK */
    expect("", "$CCCLK,2024,1,2,18,18,22");
    tick(&mm, t3 + 3 * S);                    /* after its own pause the held $CARXD is processed */
    ck_assert_int_ge(find_ev(KELP_MMDRIVER_EV_RECEIVE, 0), 0);
}
END_TEST

START_TEST(hydroid_gateway_prefix)
{
    kelp_mmdriver mm;
    make(&mm, 1, true, NULL, 1);
    ck_assert_int_eq(kelp_mmdriver_start(&mm, SEC(T)), KELP_OK);
    expect("#M1", "$CCCLK,2024,1,2,12,0,0");
    feed_pfx(&mm, "!M1", "$CACLK,2024,1,2,12,0,0", T + 1 * S);
    tick(&mm, T + 1 * S + 100000);
    ck_assert(kelp_mmdriver_clock_ok(&mm));
    tick(&mm, T + 1 * S + 200000);
    expect("#M1", "$CCCFG,SRC,1");               /* no $CCCFG,ALL,0 through a Hydroid buoy */
    feed_pfx(&mm, "!M1", "$CACFG,SRC,1", T + 2 * S);
    tick(&mm, T + 2 * S + 100000);
    expect("#M1", "$CCCFQ,ALL");
    feed_pfx(&mm, "!M1", "$CACFG,AGC,0", T + 3 * S);
    tick(&mm, T + 30 * S);
    expect_none();
    tick(&mm, T + 30 * S + 1);                   /* GPS query every 30 s */
    expect_raw("#G1\r\n");
    tick(&mm, T + 45 * S);
    expect_none();
}
END_TEST

START_TEST(garbage_is_reported_and_survived)
{
    kelp_mmdriver mm;
    boot(&mm);
    reset_capture();
    static const char junk[] = "\x01\x02\xff garbage\r$CARXD,2,1,1,1,zz*00\r$CARXD,2,1,1,1,0g*";
    ck_assert_int_eq(kelp_mmdriver_feed(&mm, (const uint8_t *)junk, sizeof junk - 1, SEC(T + 5 * S)), KELP_OK);
    feed(&mm, "$CARXD,2,1,1,1,zz", T + 5 * S);        /* good checksum, bad hex */
    feed(&mm, "$CARXD,2,1,x,1,00", T + 5 * S);        /* bad ack field */
    feed(&mm, "$CACYC,0,1", T + 5 * S);               /* missing fields */
    feed(&mm, "$CACLK,2024,13,2,12,0,0", T + 5 * S);  /* no $CCCLK pending: ignored */
    /* junk, bad checksum, (unterminated junk + bad hex line = one bad line), bad ack, missing fields */
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_BAD_LINE), 5);
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_RECEIVE), 0);
    /* a line far too long is dropped, the next one still works */
    char big[KELP_MAX_NMEA_LINE + 100];
    memset(big, 'A', sizeof big);
    big[0] = '$';
    big[sizeof big - 1] = '\r';
    ck_assert_int_eq(kelp_mmdriver_feed(&mm, (const uint8_t *)big, sizeof big, SEC(T + 6 * S)), KELP_OK);
    feed(&mm, "$CARXD,2,1,1,1,00ff", T + 6 * S);
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_RECEIVE), 1);
    ck_assert_int_eq(count_evk(KELP_MMDRIVER_EV_BAD_LINE), 6);
    /* the driver refuses calls before start */
    kelp_mmdriver m2;
    make(&m2, 2, false, NULL, 0);
    ck_assert_int_eq(kelp_mmdriver_feed(&m2, (const uint8_t *)"x", 1, SEC(T)), KELP_ERR_STATE);
    ck_assert_int_eq(kelp_mmdriver_tick(&m2, SEC(T)), KELP_ERR_STATE);
}
END_TEST

START_TEST(civil_time)
{
    int y, mo, d, h, mi, s;
    kelp_mmdriver_civil(SEC(T), &y, &mo, &d, &h, &mi, &s);
    ck_assert_int_eq(y, 2024); ck_assert_int_eq(mo, 1); ck_assert_int_eq(d, 2);
    ck_assert_int_eq(h, 12); ck_assert_int_eq(mi, 0); ck_assert_int_eq(s, 0);
    kelp_mmdriver_civil(SEC(951782400LL * S), &y, &mo, &d, &h, &mi, &s);   /* 2000-02-29 */
    ck_assert_int_eq(y, 2000); ck_assert_int_eq(mo, 2); ck_assert_int_eq(d, 29);
    kelp_mmdriver_civil(SEC(-1), &y, &mo, &d, &h, &mi, &s);               /* 1969-12-31 23:59:59 */
    ck_assert_int_eq(y, 1969); ck_assert_int_eq(mo, 12); ck_assert_int_eq(d, 31);
    ck_assert_int_eq(h, 23); ck_assert_int_eq(mi, 59); ck_assert_int_eq(s, 59);
}
END_TEST

Suite *kelp_mmdriver_suite(void)
{
    Suite *s = suite_create("mm");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, startup_sequence);
    tcase_add_test(tc, data_cycle_local);
    tcase_add_test(tc, caller_frames_fewer_than_requested);
    tcase_add_test(tc, clock_written_late_in_a_second);
    tcase_add_test(tc, data_request_without_cache_real_vector);
    tcase_add_test(tc, remote_cycle_and_third_party_cycle);
    tcase_add_test(tc, receive_ranging_and_toa);
    tcase_add_test(tc, timeouts_retries_and_death);
    tcase_add_test(tc, caerr_nmea_resends_at_once);
    tcase_add_test(tc, clock_checks_rev_and_reboot_pause);
    tcase_add_test(tc, hydroid_gateway_prefix);
    tcase_add_test(tc, garbage_is_reported_and_survived);
    tcase_add_test(tc, civil_time);
    suite_add_tcase(s, tc);
    return s;
}
