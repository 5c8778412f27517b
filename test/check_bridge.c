/* Unit tests: kelp-bridge's core -- route lines, datagram framing, the replay window per
 * sending community, the allow-list and oversize values. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/bridge.h>

/* a keyed toy MAC: enough to tell a changed byte or key (the real app uses HMAC-SHA256) */
static int toy_hmac(const uint8_t *key, size_t keylen, const uint8_t *data, size_t len, uint8_t out[32], void *user)
{
    (void)user;
    uint64_t h = 1469598103934665603u;
    for (size_t i = 0; i < keylen; i++) h = (h ^ key[i]) * 1099511628211u;
    for (size_t i = 0; i < len; i++) h = (h ^ data[i]) * 1099511628211u;
    for (int i = 0; i < 32; i++) {
        h = (h ^ (uint64_t)i) * 1099511628211u;
        out[i] = (uint8_t)(h >> 32);
    }
    return 0;
}

static const uint8_t KEY[] = "sea-secret";
#define KL (sizeof KEY - 1)

static kelp_var mkvar(const char *name, const char *community, const char *val)
{
    kelp_var v;
    memset(&v, 0, sizeof v);
    snprintf(v.name, sizeof v.name, "%s", name);
    snprintf(v.source, sizeof v.source, "test");
    snprintf(v.community, sizeof v.community, "%s", community);
    v.time = 1700000000.0;
    v.kind = KELP_VAR_STRING;
    v.slen = strlen(val);
    memcpy(v.sval, val, v.slen + 1);
    return v;
}

typedef struct dg {
    uint8_t b[8192];
    size_t n;
} dg;

static dg frame(kelp_bridge_tx *tx, const char *name, const char *community)
{
    dg d;
    kelp_var v = mkvar(name, community, "go");
    ck_assert_int_eq(kelp_bridge_frame(tx, &v, NULL, KEY, KL, toy_hmac, NULL, d.b, sizeof d.b, &d.n), 0);
    return d;
}

static int rx(kelp_bridge_rx *r, const dg *d)
{
    static kelp_var out;
    return kelp_bridge_unframe(r, d->b, d->n, KEY, KL, toy_hmac, NULL, &out);
}

START_TEST(t_frame_roundtrip_alias_and_flag)
{
    kelp_bridge_tx tx;
    kelp_bridge_tx_init(&tx, 42);
    kelp_var v = mkvar("NAV_X", "alpha", "12.5"), out;
    uint8_t b[4096];
    size_t n = 0;
    ck_assert_int_eq(kelp_bridge_frame(&tx, &v, "NAV_X_ALPHA", KEY, KL, toy_hmac, NULL, b, sizeof b, &n), 0);
    ck_assert_uint_eq(tx.seq, 1);
    ck_assert_mem_eq(b, "KBR2", 4);
    ck_assert_int_eq(kelp_bridge_unframe(NULL, b, n, KEY, KL, toy_hmac, NULL, &out), 0);
    ck_assert_str_eq(out.name, "NAV_X_ALPHA");
    ck_assert_str_eq(out.community, "alpha");
    ck_assert_str_eq(out.sval, "12.5");
    ck_assert(out.flags & KELP_VAR_FLAG_BRIDGED);
    /* wrong key, missing MAC, and a changed sequence number all fail authentication */
    ck_assert_int_eq(kelp_bridge_unframe(NULL, b, n, (const uint8_t *)"other", 5, toy_hmac, NULL, &out), KELP_ERR_AUTH);
    ck_assert_int_eq(kelp_bridge_unframe(NULL, b, n - KELP_BRIDGE_HMAC_LEN, KEY, KL, toy_hmac, NULL, &out),
                     KELP_ERR_AUTH);
    b[20] ^= 1;
    ck_assert_int_eq(kelp_bridge_unframe(NULL, b, n, KEY, KL, toy_hmac, NULL, &out), KELP_ERR_AUTH);
    /* short header, unknown flag bits, old magic */
    ck_assert_int_eq(kelp_bridge_unframe(NULL, b, 12, NULL, 0, NULL, NULL, &out), KELP_ERR_TRUNCATED);
    b[20] ^= 1;
    b[4] |= 0x80;
    ck_assert_int_eq(kelp_bridge_unframe(NULL, b, n, NULL, 0, NULL, NULL, &out), KELP_ERR_PARSE);
    memcpy(b, "KBR1", 4);
    ck_assert_int_eq(kelp_bridge_unframe(NULL, b, n, NULL, 0, NULL, NULL, &out), KELP_ERR_PARSE);
}
END_TEST

START_TEST(t_replay_refused)
{
    kelp_bridge_peer peers[4];
    kelp_bridge_rx r;
    kelp_bridge_rx_init(&r, peers, 4);
    kelp_bridge_tx tx;
    kelp_bridge_tx_init(&tx, 1000);
    dg a = frame(&tx, "X", "alpha");
    ck_assert_int_eq(rx(&r, &a), 0);
    for (int i = 0; i < 1000; i++) ck_assert_int_eq(rx(&r, &a), KELP_ERR_REPLAY);
    ck_assert_uint_eq(r.replayed, 1000);
    dg b = frame(&tx, "X", "alpha");
    ck_assert_int_eq(rx(&r, &b), 0);
    ck_assert_int_eq(rx(&r, &b), KELP_ERR_REPLAY);
}
END_TEST

START_TEST(t_window_out_of_order)
{
    kelp_bridge_peer peers[4];
    kelp_bridge_rx r;
    kelp_bridge_rx_init(&r, peers, 4);
    kelp_bridge_tx tx;
    kelp_bridge_tx_init(&tx, 7);
    static dg d[100];
    for (int i = 0; i < 100; i++) d[i] = frame(&tx, "X", "alpha");
    /* 1..10 in reverse after 10: all accepted once */
    ck_assert_int_eq(rx(&r, &d[9]), 0);
    for (int i = 8; i >= 0; i--) ck_assert_int_eq(rx(&r, &d[i]), 0);
    for (int i = 0; i < 10; i++) ck_assert_int_eq(rx(&r, &d[i]), KELP_ERR_REPLAY);
    /* jump to seq 80: seq 17..79 are inside the window (high-63..high), 16 and below are not */
    ck_assert_int_eq(rx(&r, &d[79]), 0);
    ck_assert_int_eq(rx(&r, &d[16]), 0);   /* seq 17 = 80 - 63: last seq in the window */
    ck_assert_int_eq(rx(&r, &d[15]), KELP_ERR_REPLAY); /* seq 16: below the window */
    ck_assert_int_eq(rx(&r, &d[50]), 0);
    ck_assert_int_eq(rx(&r, &d[50]), KELP_ERR_REPLAY);
    /* a jump of more than the window forgets everything below */
    ck_assert_int_eq(rx(&r, &d[99]), 0);
    ck_assert_int_eq(rx(&r, &d[79]), KELP_ERR_REPLAY);
    ck_assert_int_eq(rx(&r, &d[30]), KELP_ERR_REPLAY); /* seq 31 < 100 - 63 */
    ck_assert_int_eq(rx(&r, &d[40]), 0);              /* seq 41: in the window, never seen */
}
END_TEST

START_TEST(t_epochs_and_peers)
{
    kelp_bridge_peer peers[2];
    kelp_bridge_rx r;
    kelp_bridge_rx_init(&r, peers, 2);
    kelp_bridge_tx old, now, shore;
    kelp_bridge_tx_init(&old, 100);
    kelp_bridge_tx_init(&now, 200);
    kelp_bridge_tx_init(&shore, 50);
    dg o1 = frame(&old, "X", "alpha"), o2 = frame(&old, "X", "alpha");
    ck_assert_int_eq(rx(&r, &o1), 0);
    /* the peer restarted: a newer epoch starts a fresh window at seq 1 */
    dg n1 = frame(&now, "X", "alpha");
    ck_assert_int_eq(rx(&r, &n1), 0);
    /* the old run's datagrams are stale now, even one never seen */
    ck_assert_int_eq(rx(&r, &o2), KELP_ERR_REPLAY);
    /* another community has its own window: seq 1 of its own epoch is fine */
    dg s1 = frame(&shore, "Y", "shoreside");
    ck_assert_int_eq(rx(&r, &s1), 0);
    ck_assert_uint_eq(r.n, 2);
    /* a third community evicts the least recently used (alpha was used before shoreside) */
    kelp_bridge_tx t3;
    kelp_bridge_tx_init(&t3, 9);
    dg c1 = frame(&t3, "Z", "charlie");
    ck_assert_int_eq(rx(&r, &c1), 0);
    ck_assert_uint_eq(r.evicted, 1);
    ck_assert_int_eq(rx(&r, &s1), KELP_ERR_REPLAY); /* shoreside kept */
    /* a datagram that fails authentication does not move the window */
    dg n2 = frame(&now, "X", "alpha"), n3 = frame(&now, "X", "alpha");
    n3.b[n3.n - 1] ^= 1;
    ck_assert_int_eq(rx(&r, &n3), KELP_ERR_AUTH);
    ck_assert_int_eq(rx(&r, &n2), 0);
}
END_TEST

START_TEST(t_seq_zero_refused)
{
    kelp_bridge_peer peers[1];
    kelp_bridge_rx r;
    kelp_bridge_rx_init(&r, peers, 1);
    kelp_bridge_tx tx;
    kelp_bridge_tx_init(&tx, 5);
    tx.seq = UINT64_MAX; /* the next frame carries seq 0 after wrapping */
    dg d = frame(&tx, "X", "alpha");
    ck_assert_int_eq(rx(&r, &d), KELP_ERR_REPLAY);
}
END_TEST

START_TEST(t_allow_list)
{
    ck_assert(kelp_bridge_allowed("", "ANYTHING"));
    ck_assert(kelp_bridge_allowed(NULL, "ANYTHING"));
    const char *allow = "NODE_REPORT, NODE_MESSAGE_* ,DEPLOY";
    ck_assert(kelp_bridge_allowed(allow, "NODE_REPORT"));
    ck_assert(kelp_bridge_allowed(allow, "NODE_MESSAGE_ALPHA"));
    ck_assert(kelp_bridge_allowed(allow, "DEPLOY"));
    ck_assert(!kelp_bridge_allowed(allow, "DEPLOY_ALL"));
    ck_assert(!kelp_bridge_allowed(allow, "NODE_REPORT_LOCAL"));
    ck_assert(!kelp_bridge_allowed(allow, "MOOS_MANUAL_OVERRIDE"));
    ck_assert(!kelp_bridge_allowed(" , ", "X"));
}
END_TEST

START_TEST(t_oversize_value)
{
    /* a value longer than KELP_MAX_SVAL: hand-built LCM bytes inside a valid frame */
    static uint8_t b[KELP_MAX_SVAL + 512];
    kelp_bridge_tx tx;
    kelp_bridge_tx_init(&tx, 3);
    kelp_var v = mkvar("BIG", "alpha", "x");
    size_t n = 0;
    ck_assert_int_eq(kelp_bridge_frame(&tx, &v, NULL, NULL, 0, NULL, NULL, b, sizeof b, &n), 0);
    /* the sval string sits before nbytes(4) and flags(1): length field at n-5-4-2 */
    size_t lenpos = n - 1 - 4 - 2 - 4;
    ck_assert_int_eq(b[lenpos + 3], 2); /* "x\0" */
    size_t big = KELP_MAX_SVAL + 2;
    memmove(b + lenpos + 4 + big, b + lenpos + 4 + 2, 5);
    memset(b + lenpos + 4, 'x', big - 1);
    b[lenpos + 4 + big - 1] = 0;
    b[lenpos] = (uint8_t)(big >> 24), b[lenpos + 1] = (uint8_t)(big >> 16), b[lenpos + 2] = (uint8_t)(big >> 8),
    b[lenpos + 3] = (uint8_t)big;
    kelp_var out;
    ck_assert_int_eq(kelp_bridge_unframe(NULL, b, lenpos + 4 + big + 5, NULL, 0, NULL, NULL, &out), KELP_ERR_RANGE);
    /* a frame that does not fit the caller's buffer is NOSPACE, not a short datagram */
    uint8_t small[40];
    ck_assert_int_eq(kelp_bridge_frame(&tx, &v, NULL, NULL, 0, NULL, NULL, small, sizeof small, &n), KELP_ERR_NOSPACE);
}
END_TEST


/* pShare's configuration and command model (MOOS-IvP 24.8 Share.cpp, ShareHelp.cpp, readme.md) */
/* 24.8's Route::IsActive: frequency, duration, max_shares, and duration = 0 restated */
START_TEST(t_pshare_limits)
{
    kelp_bridge_route r[4];
    size_t n = 0;
    kelp_diag why = {0};
    ck_assert_int_eq(kelp_bridge_pshare_output("src_name=A, route=h:9000, frequency=4, duration=10, max_shares=3", r, 4, &n, &why), 0);
    ck_assert(r[0].limited && r[0].frequency == 4 && r[0].duration == 10 && r[0].max_shares == 3);
    kelp_bridge_share s = { .created = 100 };
    ck_assert(kelp_bridge_share_active(&r[0], &s, 100));
    s.done = 1, s.last_sent = 100;
    ck_assert(!kelp_bridge_share_active(&r[0], &s, 100.2));  /* sooner than 1/4 s */
    ck_assert(kelp_bridge_share_active(&r[0], &s, 100.25));
    ck_assert(kelp_bridge_share_active(&r[0], &s, 99));      /* a clock step back never stalls it */
    s.done = 3, s.last_sent = 101;
    ck_assert(!kelp_bridge_share_active(&r[0], &s, 102));    /* max_shares */
    s.done = 1;
    ck_assert(!kelp_bridge_share_active(&r[0], &s, 110.5));  /* past its duration */
    ck_assert(!kelp_bridge_share_active(&r[0], &s, NAN));
    /* defaults: every notification, for ever; shorthand @F (not a number: 0, every one) */
    ck_assert_int_eq(kelp_bridge_pshare_output("X->Y:h:9000@0.5 & h2:9001@fast & multicast_3", r, 4, &n, &why), 0);
    ck_assert_uint_eq(n, 3);
    ck_assert(r[0].frequency == 0.5 && r[1].frequency == 0 && r[2].frequency == 0);
    ck_assert(r[0].duration < 0 && r[0].max_shares < 0);
    s = (kelp_bridge_share){ .created = 0, .done = 1000000, .last_sent = 5 };
    ck_assert(kelp_bridge_share_active(&r[1], &s, 1e9));
    /* a new route with duration = 0 never shares (24.8); restated, it is max_shares 1 */
    ck_assert_int_eq(kelp_bridge_pshare_output("src_name=A, route=h:9000, duration=0", r, 4, &n, &why), 0);
    s = (kelp_bridge_share){ .created = 100 };
    ck_assert(!kelp_bridge_share_active(&r[0], &s, 100.5));
    r[0].max_shares = 1, r[0].duration = INFINITY;
    ck_assert(kelp_bridge_share_active(&r[0], &s, 100.5));
    s.done = 1;
    ck_assert(!kelp_bridge_share_active(&r[0], &s, 100.6));
    /* UDPSHARE routes (pMOOSBridge) have no limits */
    ck_assert_int_eq(kelp_bridge_parse_share("[X] -> c @ h:9000", r, 4, &n, &why), 0);
    ck_assert(!r[0].limited);
    s = (kelp_bridge_share){ .created = 0, .done = 5, .last_sent = 1 };
    ck_assert(kelp_bridge_share_active(&r[0], &s, 1));
}
END_TEST

START_TEST(t_pshare_output_forms)
{
    kelp_bridge_route r[8];
    size_t n = 0;
    kelp_diag why = { 0 };
    /* long form: dest_name defaults to src_name; an '&' list of routes; duration etc. accepted */
    ck_assert_int_eq(kelp_bridge_pshare_output("src_name = P,dest_name = H,route=multicast_9 & robots.ox.ac.uk:10200 & "
                                               "178.4.5.6:9001, max_shares = 2", r, 8, &n, &why), 0);
    ck_assert_uint_eq(n, 3);
    ck_assert(r[0].multicast && r[0].port == 9);
    ck_assert_str_eq(r[1].host, "robots.ox.ac.uk");
    ck_assert_uint_eq(r[2].port, 9001);
    ck_assert_str_eq(r[2].src, "P");
    ck_assert_str_eq(r[2].alias, "H");
    ck_assert_int_eq(kelp_bridge_pshare_output("src_name = Z, route = oceanai.mit.edu:9020", r, 8, &n, &why), 0);
    ck_assert_str_eq(r[0].alias, "Z");
    /* the PSHARE_CMD the brokers post */
    const char *cmd = "cmd=output,src_name=NODE_BROKER_PING_0,dest_name=NODE_BROKER_PING,route=10.0.0.1:9300";
    ck_assert_int_eq(kelp_bridge_pshare_cmd(cmd), 1);
    ck_assert_int_eq(kelp_bridge_pshare_output(cmd, r, 8, &n, &why), 0);
    ck_assert_str_eq(r[0].src, "NODE_BROKER_PING_0");
    ck_assert_str_eq(r[0].alias, "NODE_BROKER_PING");
    ck_assert_str_eq(r[0].host, "10.0.0.1");
    ck_assert_int_eq(kelp_bridge_pshare_cmd("cmd=Input,route=localhost:9200"), 2);
    ck_assert_int_eq(kelp_bridge_pshare_cmd("cmd=delete,src_name=X"), 0);
    /* shorthand: X->[Y:]host:port[@freq] & [Y:]multicast_N */
    ck_assert_int_eq(kelp_bridge_pshare_output("VAR1->VAR3:multicast_8 & multicast_2 & oranges:oceanai.mit.edu:10007@4.0",
                                               r, 8, &n, &why), 0);
    ck_assert_uint_eq(n, 3);
    ck_assert_str_eq(r[0].alias, "VAR3");
    ck_assert_str_eq(r[1].alias, "VAR1");
    ck_assert_str_eq(r[2].alias, "oranges");
    ck_assert_uint_eq(r[2].port, 10007);
    /* refused: no src_name, no route, a bad port */
    ck_assert_int_lt(kelp_bridge_pshare_output("dest_name=A,route=1.2.3.4:9000", r, 8, &n, &why), 0);
    ck_assert_int_lt(kelp_bridge_pshare_output("src_name=A,dest_name=B", r, 8, &n, &why), 0);
    ck_assert_int_lt(kelp_bridge_pshare_output("src_name=A,route=1.2.3.4:99999", r, 8, &n, &why), 0);
}
END_TEST

START_TEST(t_pshare_inputs_and_summaries)
{
    kelp_bridge_route in[8], out[8];
    size_t n = 0, m = 0, k = 0;
    char white[64];
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_bridge_pshare_input("route = localhost:9300 & multicast_9, white_list = NODE_* & DEPLOY",
                                              in, 8, &n, white, sizeof white, &why), 0);
    ck_assert_uint_eq(n, 2);
    ck_assert_str_eq(in[0].host, "localhost");
    ck_assert_uint_eq(in[0].port, 9300);
    ck_assert(in[1].multicast && in[1].port == 9);
    ck_assert_str_eq(white, "NODE_*,DEPLOY");
    ck_assert_int_lt(kelp_bridge_pshare_input("localhost:9300", in, 8, &k, NULL, 0, &why), 0); /* route= required */
    char buf[512];
    ck_assert_int_eq(kelp_bridge_pshare_summary(in, n, true, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "224.1.1.11:24469:multicast_9,localhost:9300");
    /* the output summary: sources in name order, each source's routes joined with " & " */
    kelp_bridge_route t[8];
    size_t nt = 0;
    ck_assert_int_eq(kelp_bridge_pshare_output("src_name=Y,dest_name=YY,route=10.0.0.2:9201", out, 8, &m, &why), 0);
    ck_assert_int_eq(kelp_bridge_table_add(t, &nt, 8, &out[0]), 1);
    ck_assert_int_eq(kelp_bridge_pshare_output("X->10.0.0.3:9202 & Z:multicast_8", out, 8, &m, &why), 0);
    for (size_t i = 0; i < m; i++) ck_assert_int_eq(kelp_bridge_table_add(t, &nt, 8, &out[i]), 1);
    ck_assert_int_eq(kelp_bridge_pshare_output("src_name=Y,dest_name=Q,route=10.0.0.4:9203", out, 8, &m, &why), 0);
    ck_assert_int_eq(kelp_bridge_table_add(t, &nt, 8, &out[0]), 1);
    ck_assert_int_eq(kelp_bridge_table_add(t, &nt, 8, &out[0]), 0); /* the same route once */
    ck_assert_int_eq(kelp_bridge_pshare_summary(t, nt, false, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "X->X:10.0.0.3:9202 & Z:224.1.1.11:24468:multicast_8, Y->YY:10.0.0.2:9201 & Q:10.0.0.4:9203");
}
END_TEST

Suite *kelp_bridge_suite(void)
{
    Suite *s = suite_create("bridge");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, t_frame_roundtrip_alias_and_flag);
    tcase_add_test(tc, t_replay_refused);
    tcase_add_test(tc, t_window_out_of_order);
    tcase_add_test(tc, t_epochs_and_peers);
    tcase_add_test(tc, t_seq_zero_refused);
    tcase_add_test(tc, t_allow_list);
    tcase_add_test(tc, t_oversize_value);
    tcase_add_test(tc, t_pshare_output_forms);
    tcase_add_test(tc, t_pshare_limits);
    tcase_add_test(tc, t_pshare_inputs_and_summaries);
    suite_add_tcase(s, tc);
    return s;
}
