/* Unit tests: what a bus client trusts -- communities, message times, sync replies. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/bus.h>
#include <kelp/udpm.h>

/* a client whose transport records what it publishes */
typedef struct tb {
    kelp_bus bus;
    kelp_bus_sub subs[8];
    kelp_var cache[64];
    kelp_var rx;
    uint8_t scratch[16384];
    int ndeliv;
    kelp_var last;
    int npub;
    char last_chan[KELP_MAX_NAME];
} tb;

static int rec_publish(void *ctx, const char *channel, const uint8_t *data, size_t len)
{
    (void)data;
    (void)len;
    tb *t = ctx;
    t->npub++;
    snprintf(t->last_chan, sizeof t->last_chan, "%s", channel);
    return 0;
}

static int rec_subscribe(void *ctx, const char *pattern)
{
    (void)ctx;
    (void)pattern;
    return 0;
}

static void on_var(const kelp_var *v, void *user)
{
    tb *t = user;
    t->ndeliv++;
    t->last = *v;
}

static tb *tb_new(const char *app, const char *community)
{
    tb *t = calloc(1, sizeof *t);
    kelp_bus_transport tr = { rec_publish, rec_subscribe, t };
    kelp_bus_storage st = { t->subs, 8, t->cache, 64, t->scratch, sizeof t->scratch, &t->rx };
    char reply[KELP_MAX_NAME];
    ck_assert_int_eq(kelp_bus_reply_channel(app, 0x1234abcdu, reply), 0);
    ck_assert_int_eq(kelp_bus_init(&t->bus, app, community, reply, &tr, &st, on_var, t), 0);
    return t;
}

/* feed a var as if it came off the wire */
static int feed_var(tb *t, const char *name, const char *community, double time, double value, uint8_t flags,
                    double now)
{
    kelp_var v;
    memset(&v, 0, sizeof v);
    strcpy(v.name, name);
    strcpy(v.source, "peer");
    strcpy(v.community, community);
    v.time = time;
    v.kind = KELP_VAR_DOUBLE;
    v.dval = value;
    v.flags = flags;
    uint8_t buf[1024];
    size_t n = 0;
    ck_assert_int_eq(kelp_var_encode(&v, buf, sizeof buf, &n), 0);
    return kelp_bus_receive(&t->bus, name, buf, n, now);
}

static int feed_sync(tb *t, const char *requester, const char *community, const char *reply, const char *pattern,
                     double now)
{
    kelp_sync_req q;
    memset(&q, 0, sizeof q);
    strcpy(q.requester, requester);
    strcpy(q.community, community);
    strcpy(q.reply_channel, reply);
    q.npatterns = 1;
    strcpy(q.patterns[0], pattern);
    uint8_t buf[4096];
    size_t n = 0;
    ck_assert_int_eq(kelp_bus_sync_req_encode(&q, buf, sizeof buf, &n), 0);
    return kelp_bus_receive(&t->bus, KELP_BUS_SYNC_CHANNEL, buf, n, now);
}

/* ------------------------------------------------------------------ communities */
START_TEST(other_community_is_dropped_and_counted)
{
    tb *t = tb_new("app", "alpha");
    ck_assert_int_eq(kelp_bus_register(&t->bus, "X", 0, 0), 0);
    ck_assert_int_eq(feed_var(t, "X", "beta", 1, 5, 0, 1), 0);
    ck_assert_int_eq(t->ndeliv, 0);
    ck_assert_ptr_null(kelp_bus_cached(&t->bus, "X"));
    ck_assert_uint_eq(kelp_bus_get_stats(&t->bus)->foreign_community, 1);
    ck_assert_int_eq(feed_var(t, "X", "alpha", 1, 6, 0, 1), 0);
    ck_assert_int_eq(t->ndeliv, 1);
    /* a bridge of this community republished it: accepted */
    ck_assert_int_eq(feed_var(t, "X", "beta", 2, 7, KELP_VAR_FLAG_BRIDGED, 2), 0);
    ck_assert_int_eq(t->ndeliv, 2);
    free(t);
}
END_TEST

START_TEST(bridge_hears_every_community)
{
    tb *t = tb_new("pMOOSBridge", "alpha");
    kelp_bus_set_bridge(&t->bus, true);
    ck_assert_int_eq(kelp_bus_register(&t->bus, "X", 0, 0), 0);
    ck_assert_int_eq(feed_var(t, "X", "beta", 1, 5, 0, 1), 0);
    ck_assert_int_eq(t->ndeliv, 1);
    ck_assert_uint_eq(kelp_bus_get_stats(&t->bus)->foreign_community, 0);
    free(t);
}
END_TEST

START_TEST(other_community_sync_request_is_ignored)
{
    tb *t = tb_new("app", "alpha");
    ck_assert_int_eq(kelp_bus_notify_double(&t->bus, "X", 1, 0), 0);
    int before = t->npub;
    ck_assert_int_eq(feed_sync(t, "late", "beta", "KELP_SYNC_late_00000001", "*", 1), 0);
    ck_assert_int_eq(t->npub, before);
    ck_assert_uint_eq(kelp_bus_get_stats(&t->bus)->foreign_community, 1);
    ck_assert_int_eq(feed_sync(t, "late", "alpha", "KELP_SYNC_late_00000001", "*", 1), 0);
    ck_assert_int_eq(t->npub, before + 1);
    free(t);
}
END_TEST

START_TEST(community_url_from_mission)
{
    char u[128];
    ck_assert_int_eq(kelp_udpm_community_url("udpm://239.1.1.1:7000?ttl=1", "9000", u, sizeof u), 0);
    ck_assert_str_eq(u, "udpm://239.1.1.1:7000?ttl=1"); /* LCM_URL wins */
    ck_assert_int_eq(kelp_udpm_community_url(NULL, "9001", u, sizeof u), 0);
    ck_assert_str_eq(u, "udpm://239.255.76.67:9001?ttl=0");
    ck_assert_int_eq(kelp_udpm_community_url("", "9002", u, sizeof u), 0);
    ck_assert_str_eq(u, "udpm://239.255.76.67:9002?ttl=0");
    ck_assert_int_eq(kelp_udpm_community_url(NULL, NULL, u, sizeof u), 0);
    ck_assert_str_eq(u, ""); /* the caller's default */
    ck_assert_int_eq(kelp_udpm_community_url(NULL, "0", u, sizeof u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_community_url(NULL, "65536", u, sizeof u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_community_url(NULL, "90x", u, sizeof u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_community_url("tcpq://x", NULL, u, sizeof u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_community_url(NULL, "9001", u, 10), KELP_ERR_NOSPACE);
}
END_TEST

/* ------------------------------------------------------------------ times */
START_TEST(poisoned_times_are_rejected)
{
    tb *t = tb_new("app", "c");
    kelp_bus_limits lim;
    kelp_bus_limits_default(&lim);
    lim.time_margin = 30;
    ck_assert_int_eq(kelp_bus_set_limits(&t->bus, &lim), 0);
    ck_assert_int_eq(kelp_bus_register(&t->bus, "X", 0, 0), 0);
    const double bad[] = { 1e308, INFINITY, -INFINITY, NAN, 1000 + 30.5 };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        ck_assert_int_eq(feed_var(t, "X", "c", bad[i], 666, 0, 1000), KELP_ERR_RANGE);
    ck_assert_int_eq(t->ndeliv, 0);
    ck_assert_ptr_null(kelp_bus_cached(&t->bus, "X"));
    ck_assert_uint_eq(kelp_bus_get_stats(&t->bus)->time_rejected, 5);
    /* a genuine later value is the one retained */
    ck_assert_int_eq(feed_var(t, "X", "c", 1000 + 29, 1, 0, 1000), 0);
    ck_assert_int_eq(t->ndeliv, 1);
    ck_assert(kelp_bus_cached(&t->bus, "X")->dval == 1);
    /* a poisoned sync reply is rejected the same way */
    kelp_var v;
    memset(&v, 0, sizeof v);
    strcpy(v.name, "X");
    strcpy(v.community, "c");
    v.time = 1e308;
    v.flags = KELP_VAR_FLAG_SYNC;
    uint8_t buf[512];
    size_t n;
    ck_assert_int_eq(kelp_var_encode(&v, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_bus_receive(&t->bus, t->bus.reply_channel, buf, n, 1000), KELP_ERR_RANGE);
    ck_assert(kelp_bus_cached(&t->bus, "X")->dval == 1);
    free(t);
}
END_TEST

START_TEST(without_margin_only_nonfinite_rejected)
{
    tb *t = tb_new("app", "c");
    ck_assert_int_eq(kelp_bus_register(&t->bus, "X", 0, 0), 0);
    ck_assert_int_eq(feed_var(t, "X", "c", 1e9, 1, 0, 0), 0);
    ck_assert_int_eq(feed_var(t, "X", "c", NAN, 1, 0, 0), KELP_ERR_RANGE);
    ck_assert_int_eq(t->ndeliv, 1);
    kelp_bus_limits lim;
    kelp_bus_limits_default(&lim);
    lim.time_margin = -1;
    ck_assert_int_eq(kelp_bus_set_limits(&t->bus, &lim), KELP_ERR_ARG);
    lim.time_margin = NAN;
    ck_assert_int_eq(kelp_bus_set_limits(&t->bus, &lim), KELP_ERR_ARG);
    free(t);
}
END_TEST

/* ------------------------------------------------------------------ sync replies */
START_TEST(reply_channel_format)
{
    char r[KELP_MAX_NAME];
    ck_assert_int_eq(kelp_bus_reply_channel("pHelmIvP", 0xdeadbeefu, r), 0);
    ck_assert_str_eq(r, "KELP_SYNC_pHelmIvP_deadbeef");
    ck_assert_int_eq(kelp_bus_reply_channel("a_name_much_longer_than_twenty_four", 1, r), 0);
    ck_assert_str_eq(r, "KELP_SYNC_a_name_much_longer_than__00000001");
    ck_assert_int_eq(kelp_bus_reply_channel("", 1, r), KELP_ERR_ARG);
}
END_TEST

/* replies go only to the requester's own reply channel */
static const char *const bad_replies[] = { "NAV_X", "KELP_SYNC_other_00000001", "KELP_SYNC_late_xyz",
                                           "KELP_SYNC_late_123456789", "KELP_SYNC_late_", "KELP_SYNC_lat",
                                           "KELP_SYNC_latecomer" };

START_TEST(reply_only_to_requesters_channel)
{
    tb *t = tb_new("app", "c");
    ck_assert_int_eq(kelp_bus_notify_double(&t->bus, "X", 1, 0), 0);
    int before = t->npub;
    ck_assert_int_eq(feed_sync(t, "late", "c", bad_replies[_i], "*", 1), 0);
    ck_assert_int_eq(t->npub, before);
    ck_assert_uint_eq(kelp_bus_get_stats(&t->bus)->sync_bad_reply, 1);
    ck_assert_int_eq(feed_sync(t, "late", "c", "KELP_SYNC_late_00c0ffee", "*", 1), 0);
    ck_assert_int_eq(t->npub, before + 1);
    ck_assert_str_eq(t->last_chan, "KELP_SYNC_late_00c0ffee");
    ck_assert_int_eq(feed_sync(t, "late", "c", "KELP_SYNC_late", "*", 1), 0);
    ck_assert_int_eq(t->npub, before + 2);
    free(t);
}
END_TEST

/* a client retaining V00..V49, with sync budgets per requester / overall */
static tb *tb_fifty(double burst, double rate, double burst_all, double rate_all)
{
    tb *t = tb_new("app", "c");
    kelp_bus_limits lim;
    kelp_bus_limits_default(&lim);
    lim.sync_burst = burst;
    lim.sync_rate = rate;
    lim.sync_burst_all = burst_all;
    lim.sync_rate_all = rate_all;
    ck_assert_int_eq(kelp_bus_set_limits(&t->bus, &lim), 0);
    char name[16];
    for (int i = 0; i < 50; i++) {
        snprintf(name, sizeof name, "V%02d", i);
        ck_assert_int_eq(kelp_bus_notify_double(&t->bus, name, i, 0), 0);
    }
    return t;
}

START_TEST(sync_replies_rate_limited_per_requester)
{
    tb *t = tb_fifty(100, 10, KELP_BUS_SYNC_BURST_ALL, KELP_BUS_SYNC_RATE_ALL);
    int base = t->npub;
    /* 10 requests for "*" at one instant: the requester gets its burst of 100, no more */
    for (int i = 0; i < 10; i++) ck_assert_int_eq(feed_sync(t, "greedy", "c", "KELP_SYNC_greedy_00000001", "*", 5), 0);
    ck_assert_int_eq(t->npub - base, 100);
    ck_assert_uint_eq(kelp_bus_get_stats(&t->bus)->sync_limited, 400);
    /* another requester still has its own budget */
    ck_assert_int_eq(feed_sync(t, "modest", "c", "KELP_SYNC_modest_00000002", "V07", 5), 0);
    ck_assert_int_eq(t->npub - base, 101);
    /* one second later the greedy one has 10 more */
    ck_assert_int_eq(feed_sync(t, "greedy", "c", "KELP_SYNC_greedy_00000001", "*", 6), 0);
    ck_assert_int_eq(t->npub - base, 111);
    free(t);
}
END_TEST

START_TEST(sync_replies_rate_limited_overall)
{
    tb *t = tb_fifty(100, KELP_BUS_SYNC_RATE, 150, 0);
    int base = t->npub;
    /* a different requester name each time (spoofed): the overall budget holds */
    for (int i = 0; i < 40; i++) {
        char req[16], reply[KELP_MAX_NAME];
        snprintf(req, sizeof req, "r%d", i);
        ck_assert_int_eq(kelp_bus_reply_channel(req, 1, reply), 0);
        ck_assert_int_eq(feed_sync(t, req, "c", reply, "*", 1), 0);
    }
    ck_assert_int_eq(t->npub - base, 150);
    free(t);
}
END_TEST

Suite *kelp_bus_trust_suite(void)
{
    Suite *s = suite_create("bus_trust");
    TCase *tc = tcase_create("bus_trust");
    tcase_add_test(tc, other_community_is_dropped_and_counted);
    tcase_add_test(tc, bridge_hears_every_community);
    tcase_add_test(tc, other_community_sync_request_is_ignored);
    tcase_add_test(tc, community_url_from_mission);
    tcase_add_test(tc, poisoned_times_are_rejected);
    tcase_add_test(tc, without_margin_only_nonfinite_rejected);
    tcase_add_test(tc, reply_channel_format);
    tcase_add_loop_test(tc, reply_only_to_requesters_channel, 0, (int)(sizeof bad_replies / sizeof bad_replies[0]));
    tcase_add_test(tc, sync_replies_rate_limited_per_requester);
    tcase_add_test(tc, sync_replies_rate_limited_overall);
    suite_add_tcase(s, tc);
    return s;
}
