/* Unit tests: LCM-compatible UDP multicast datagrams (parse, reassemble, frame). */
#include <check.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/udpm.h>

#define NSLOT 4
#define CAP 4096
#define SMALL_DG 100 /* small datagrams so a few hundred bytes make many fragments */

typedef struct rxfix {
    kelp_udpm_rx rx;
    kelp_udpm_slot slots[NSLOT];
    uint8_t mem[NSLOT * CAP];
} rxfix;

static rxfix *fix_new(void)
{
    rxfix *f = calloc(1, sizeof *f);
    ck_assert_int_eq(kelp_udpm_init(&f->rx, f->slots, NSLOT, f->mem, CAP, 2.0), 0);
    return f;
}

static void fill(uint8_t *p, size_t n, unsigned seed)
{
    for (size_t i = 0; i < n; i++) p[i] = (uint8_t)(i * 31u + seed);
}

/* Every datagram of a message, in order; returns the count. */
static int frames(const char *ch, const uint8_t *data, size_t len, uint32_t seq, size_t maxdg, uint8_t dg[][SMALL_DG],
                  size_t *lens, int max)
{
    uint16_t n = 0;
    ck_assert_int_eq(kelp_udpm_plan(strlen(ch), len, maxdg, &n), 0);
    int count = n ? n : 1;
    ck_assert_int_le(count, max);
    for (int k = 0; k < count; k++)
        ck_assert_int_eq(kelp_udpm_datagram(ch, data, len, seq, maxdg, (uint16_t)k, dg[k], SMALL_DG, &lens[k]), 0);
    return count;
}

START_TEST(short_message_roundtrip)
{
    rxfix *f = fix_new();
    uint8_t dg[200];
    size_t n = 0;
    const uint8_t pay[] = { 1, 2, 3, 0, 5 };
    ck_assert_int_eq(kelp_udpm_datagram("NAV_X", pay, sizeof pay, 77, KELP_UDPM_MAX_DATAGRAM, 0, dg, sizeof dg, &n), 0);
    ck_assert_uint_eq(n, 8 + 6 + 5);
    /* the LCM layout: "LC02", seqno, channel NUL, payload */
    ck_assert(memcmp(dg, "LC02", 4) == 0);
    ck_assert_int_eq(dg[7], 77);
    ck_assert_str_eq((const char *)dg + 8, "NAV_X");
    kelp_udpm_msg m;
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg, n, 1, 0.0, &m), 1);
    ck_assert_str_eq(m.channel, "NAV_X");
    ck_assert_uint_eq(m.len, 5);
    ck_assert(memcmp(m.data, pay, 5) == 0);
    ck_assert_uint_eq(m.seqno, 77);
    ck_assert(!m.fragmented);
    ck_assert_uint_eq(kelp_udpm_get_stats(&f->rx)->short_msgs, 1);
    free(f);
}
END_TEST

START_TEST(plan_matches_lcm_limits)
{
    uint16_t n = 9;
    /* 8 + channel + NUL + payload <= 65507 stays short */
    ck_assert_int_eq(kelp_udpm_plan(5, 65507 - 8 - 6, KELP_UDPM_MAX_DATAGRAM, &n), 0);
    ck_assert_uint_eq(n, 0);
    ck_assert_int_eq(kelp_udpm_plan(5, 65507 - 8 - 6 + 1, KELP_UDPM_MAX_DATAGRAM, &n), 0);
    ck_assert_uint_eq(n, 2);
    /* 60 KB is one short datagram; 100 KB two fragments of at most 65487 payload bytes */
    ck_assert_int_eq(kelp_udpm_plan(5, 60000, KELP_UDPM_MAX_DATAGRAM, &n), 0);
    ck_assert_uint_eq(n, 0);
    ck_assert_int_eq(kelp_udpm_plan(5, 100000, KELP_UDPM_MAX_DATAGRAM, &n), 0);
    ck_assert_uint_eq(n, 2);
    ck_assert_int_eq(kelp_udpm_plan(64, 10, KELP_UDPM_MAX_DATAGRAM, &n), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_plan(0, 10, KELP_UDPM_MAX_DATAGRAM, &n), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_plan(3, (size_t)KELP_UDPM_MAX_MESSAGE + 1, KELP_UDPM_MAX_DATAGRAM, &n), KELP_ERR_RANGE);
}
END_TEST

START_TEST(fragments_in_order)
{
    rxfix *f = fix_new();
    uint8_t pay[1000], dg[32][SMALL_DG];
    size_t lens[32];
    fill(pay, sizeof pay, 3);
    int n = frames("BIG", pay, sizeof pay, 9, SMALL_DG, dg, lens, 32);
    ck_assert_int_gt(n, 10);
    /* fragment 0: LC03, seqno, size, offset 0, no 0, count, then channel */
    ck_assert(memcmp(dg[0], "LC03", 4) == 0);
    ck_assert_int_eq(dg[0][10] << 8 | dg[0][11], 1000);
    ck_assert_int_eq(dg[0][19], n);
    ck_assert_str_eq((const char *)dg[0] + 20, "BIG");
    kelp_udpm_msg m;
    for (int k = 0; k < n - 1; k++) ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[k], lens[k], 5, 0.1, &m), 0);
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[n - 1], lens[n - 1], 5, 0.1, &m), 1);
    ck_assert_str_eq(m.channel, "BIG");
    ck_assert_uint_eq(m.len, 1000);
    ck_assert(memcmp(m.data, pay, 1000) == 0);
    ck_assert(m.fragmented);
    ck_assert_uint_eq(kelp_udpm_get_stats(&f->rx)->frag_msgs, 1);
    free(f);
}
END_TEST

/* reversed, and fragment 0 last: liblcm 1.3.1 loses these */
START_TEST(fragments_any_order)
{
    rxfix *f = fix_new();
    uint8_t pay[700], dg[32][SMALL_DG];
    size_t lens[32];
    fill(pay, sizeof pay, 11);
    int n = frames("OOO", pay, sizeof pay, 1, SMALL_DG, dg, lens, 32);
    kelp_udpm_msg m;
    int order = _i;
    int got = 0;
    for (int j = 0; j < n; j++) {
        int k = order == 0 ? n - 1 - j : (j * 7) % n; /* 7 is prime to n below */
        int rc = kelp_udpm_feed(&f->rx, dg[k], lens[k], 5, 0.0, &m);
        ck_assert_int_eq(rc, j == n - 1 ? 1 : 0);
        got += rc;
    }
    ck_assert_int_eq(got, 1);
    ck_assert_uint_eq(m.len, 700);
    ck_assert(memcmp(m.data, pay, 700) == 0);
    ck_assert_str_eq(m.channel, "OOO");
    free(f);
}
END_TEST

START_TEST(interleaved_senders_and_messages)
{
    rxfix *f = fix_new();
    uint8_t a[300], b[400], da[8][SMALL_DG], db[8][SMALL_DG];
    size_t la[8], lb[8];
    fill(a, sizeof a, 1);
    fill(b, sizeof b, 2);
    int na = frames("A", a, sizeof a, 4, SMALL_DG, da, la, 8);
    int nb = frames("B", b, sizeof b, 4, SMALL_DG, db, lb, 8); /* same seqno, other sender */
    kelp_udpm_msg m;
    int done = 0;
    for (int k = 0; k < 8; k++) {
        if (k < na && kelp_udpm_feed(&f->rx, da[k], la[k], 100, 0, &m) == 1) {
            ck_assert_str_eq(m.channel, "A");
            ck_assert(memcmp(m.data, a, sizeof a) == 0);
            done++;
        }
        if (k < nb && kelp_udpm_feed(&f->rx, db[k], lb[k], 200, 0, &m) == 1) {
            ck_assert_str_eq(m.channel, "B");
            ck_assert(memcmp(m.data, b, sizeof b) == 0);
            done++;
        }
    }
    ck_assert_int_eq(done, 2);
    free(f);
}
END_TEST

START_TEST(duplicates_ignored_and_counted)
{
    rxfix *f = fix_new();
    uint8_t pay[250], dg[8][SMALL_DG];
    size_t lens[8];
    fill(pay, sizeof pay, 5);
    int n = frames("DUP", pay, sizeof pay, 2, SMALL_DG, dg, lens, 8);
    kelp_udpm_msg m;
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[0], lens[0], 1, 0, &m), 0);
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[0], lens[0], 1, 0, &m), 0);
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[0], lens[0], 1, 0, &m), 0);
    for (int k = 1; k < n; k++)
        ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[k], lens[k], 1, 0, &m), k == n - 1 ? 1 : 0);
    ck_assert(memcmp(m.data, pay, sizeof pay) == 0);
    ck_assert_uint_eq(kelp_udpm_get_stats(&f->rx)->duplicates, 2);
    /* a late duplicate of a finished message starts a slot that times out, nothing else */
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[1], lens[1], 1, 0, &m), 0);
    ck_assert_uint_eq(kelp_udpm_expire(&f->rx, 10.0), 1);
    free(f);
}
END_TEST

START_TEST(incomplete_slot_times_out)
{
    rxfix *f = fix_new();
    uint8_t pay[300], dg[8][SMALL_DG];
    size_t lens[8];
    fill(pay, sizeof pay, 9);
    int n = frames("TO", pay, sizeof pay, 3, SMALL_DG, dg, lens, 8);
    kelp_udpm_msg m;
    for (int k = 0; k < n - 1; k++) ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[k], lens[k], 1, 100.0, &m), 0);
    ck_assert_uint_eq(kelp_udpm_expire(&f->rx, 101.9), 0);
    ck_assert_uint_eq(kelp_udpm_expire(&f->rx, 102.1), 1);
    ck_assert_uint_eq(kelp_udpm_get_stats(&f->rx)->timeouts, 1);
    /* the last fragment alone no longer completes anything */
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[n - 1], lens[n - 1], 1, 102.2, &m), 0);
    /* expiry also runs inside feed */
    uint8_t s[64];
    size_t sl;
    ck_assert_int_eq(kelp_udpm_datagram("X", pay, 3, 1, KELP_UDPM_MAX_DATAGRAM, 0, s, sizeof s, &sl), 0);
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, s, sl, 1, 200.0, &m), 1);
    ck_assert_uint_eq(kelp_udpm_get_stats(&f->rx)->timeouts, 2);
    free(f);
}
END_TEST

START_TEST(busy_slots_evict_oldest)
{
    rxfix *f = fix_new();
    uint8_t pay[300], dg[8][SMALL_DG];
    size_t lens[8];
    fill(pay, sizeof pay, 4);
    kelp_udpm_msg m;
    /* NSLOT + 1 senders each start a message: the oldest is evicted */
    for (int s = 0; s <= NSLOT; s++) {
        (void)frames("E", pay, sizeof pay, 1, SMALL_DG, dg, lens, 8);
        ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[0], lens[0], (uint64_t)s, (double)s * 0.1, &m), 0);
    }
    ck_assert_uint_eq(kelp_udpm_get_stats(&f->rx)->evicted, 1);
    /* the newest completes */
    int n = frames("E", pay, sizeof pay, 1, SMALL_DG, dg, lens, 8);
    for (int k = 1; k < n; k++)
        ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[k], lens[k], NSLOT, 0.5, &m), k == n - 1 ? 1 : 0);
    free(f);
}
END_TEST

/* one sender starting many messages cannot push out another sender's message */
START_TEST(one_sender_cannot_take_every_slot)
{
    rxfix *f = fix_new();
    uint8_t pay[300], dg[8][SMALL_DG], fl[8][SMALL_DG];
    size_t lens[8], fll[8];
    fill(pay, sizeof pay, 8);
    kelp_udpm_msg m;
    int n = frames("GOOD", pay, sizeof pay, 1, SMALL_DG, dg, lens, 8);
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[0], lens[0], 42, 0, &m), 0);
    for (uint32_t seq = 0; seq < 50; seq++) {
        (void)frames("FLOOD", pay, sizeof pay, seq, SMALL_DG, fl, fll, 8);
        ck_assert_int_eq(kelp_udpm_feed(&f->rx, fl[0], fll[0], 666, 0.01 * seq, &m), 0);
    }
    for (int k = 1; k < n; k++)
        ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[k], lens[k], 42, 0.6, &m), k == n - 1 ? 1 : 0);
    ck_assert_str_eq(m.channel, "GOOD");
    ck_assert_uint_ge(kelp_udpm_get_stats(&f->rx)->evicted, 48);
    free(f);
}
END_TEST

/* ---- malformed datagrams: each is rejected with the right counter, nothing else happens */
typedef struct bad_case {
    const char *what;
    uint8_t dg[40];
    size_t len;
    int err;
    size_t counter; /* offsetof in kelp_udpm_stats */
} bad_case;

#define FRAG(seq, size, off, no, n)                                                                             \
    'L', 'C', '0', '3', 0, 0, 0, (seq), (uint8_t)((size) >> 24), (uint8_t)((size) >> 16), (uint8_t)((size) >> 8), \
        (uint8_t)(size), (uint8_t)((off) >> 24), (uint8_t)((off) >> 16), (uint8_t)((off) >> 8), (uint8_t)(off), \
        (uint8_t)((no) >> 8), (uint8_t)(no), (uint8_t)((n) >> 8), (uint8_t)(n)

static const bad_case bad_cases[] = {
    { "empty", { 0 }, 0, KELP_ERR_TRUNCATED, offsetof(kelp_udpm_stats, bad_header) },
    { "3 bytes", { 'L', 'C', '0' }, 3, KELP_ERR_TRUNCATED, offsetof(kelp_udpm_stats, bad_header) },
    { "bad magic", { 'L', 'C', '0', '1', 0, 0, 0, 1, 'X', 0 }, 10, KELP_ERR_PARSE, offsetof(kelp_udpm_stats, bad_magic) },
    { "short header cut", { 'L', 'C', '0', '2', 0, 0 }, 6, KELP_ERR_TRUNCATED, offsetof(kelp_udpm_stats, bad_header) },
    { "short no NUL", { 'L', 'C', '0', '2', 0, 0, 0, 1, 'A', 'B' }, 10, KELP_ERR_PARSE, offsetof(kelp_udpm_stats, bad_channel) },
    { "short empty channel", { 'L', 'C', '0', '2', 0, 0, 0, 1, 0, 7 }, 10, KELP_ERR_PARSE, offsetof(kelp_udpm_stats, bad_channel) },
    /* crafted 1 of the issue: a fragment header shorter than 20 bytes (liblcm wraps its size) */
    { "fragment header of 12 bytes", { 'L', 'C', '0', '3', 0, 0, 0, 1, 0, 0, 0x10, 0 }, 12, KELP_ERR_TRUNCATED,
      offsetof(kelp_udpm_stats, bad_header) },
    { "fragment header of 19 bytes", { FRAG(1, 100, 0, 0, 2) }, 19, KELP_ERR_TRUNCATED, offsetof(kelp_udpm_stats, bad_header) },
    /* crafted 2: offset near 2^32 so offset + size wraps past a 32-bit check */
    { "fragment offset near 2^32", { FRAG(1, 1000, 0xfffffff0u, 1, 2), 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20 },
      40, KELP_ERR_RANGE, offsetof(kelp_udpm_stats, bad_fragment) },
    { "fragment past size", { FRAG(1, 30, 25, 1, 2), 1, 2, 3, 4, 5, 6 }, 26, KELP_ERR_RANGE, offsetof(kelp_udpm_stats, bad_fragment) },
    { "fragment count 0", { FRAG(1, 30, 0, 0, 0), 'A', 0 }, 22, KELP_ERR_RANGE, offsetof(kelp_udpm_stats, bad_fragment) },
    { "fragment no >= count", { FRAG(1, 30, 0, 3, 3), 'A', 0 }, 22, KELP_ERR_RANGE, offsetof(kelp_udpm_stats, bad_fragment) },
    { "too many fragments", { FRAG(1, 30, 0, 0, 0xffff), 'A', 0 }, 22, KELP_ERR_RANGE, offsetof(kelp_udpm_stats, bad_fragment) },
    { "message over slot size", { FRAG(1, 0x7fffffffu, 0, 0, 2), 'A', 0 }, 22, KELP_ERR_RANGE, offsetof(kelp_udpm_stats, too_big) },
    { "fragment 0 without NUL", { FRAG(1, 30, 0, 0, 2), 'A', 'B' }, 22, KELP_ERR_PARSE, offsetof(kelp_udpm_stats, bad_channel) },
    { "fragment 0 nonzero offset", { FRAG(1, 30, 4, 0, 2), 'A', 0, 1 }, 23, KELP_ERR_RANGE, offsetof(kelp_udpm_stats, bad_fragment) },
    { "single fragment that does not cover", { FRAG(1, 30, 0, 0, 1), 'A', 0, 1, 2 }, 24, KELP_ERR_RANGE,
      offsetof(kelp_udpm_stats, bad_fragment) },
};
#define N_BAD ((int)(sizeof bad_cases / sizeof bad_cases[0]))

START_TEST(malformed_is_rejected)
{
    const bad_case *c = &bad_cases[_i];
    rxfix *f = fix_new();
    /* an exact-size heap copy so a sanitizer sees any over-read */
    uint8_t *dg = malloc(c->len ? c->len : 1);
    memcpy(dg, c->dg, c->len);
    kelp_udpm_msg m;
    int rc = kelp_udpm_feed(&f->rx, dg, c->len, 1, 0, &m);
    ck_assert_msg(rc == c->err, "%s: rc %d want %d", c->what, rc, c->err);
    const kelp_udpm_stats *st = kelp_udpm_get_stats(&f->rx);
    ck_assert_msg(*(const uint64_t *)((const char *)st + c->counter) == 1, "%s: counter", c->what);
    ck_assert_uint_eq(st->bad, 1);
    ck_assert_uint_eq(st->short_msgs + st->frag_msgs, 0);
    free(dg);
    free(f);
}
END_TEST

/* a conflicting fragment cannot change a message in progress */
START_TEST(conflicting_shape_rejected)
{
    rxfix *f = fix_new();
    uint8_t pay[300], dg[8][SMALL_DG];
    size_t lens[8];
    fill(pay, sizeof pay, 6);
    int n = frames("C", pay, sizeof pay, 8, SMALL_DG, dg, lens, 8);
    kelp_udpm_msg m;
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[0], lens[0], 1, 0, &m), 0);
    uint8_t bad[SMALL_DG];
    memcpy(bad, dg[1], lens[1]);
    bad[11] ^= 1; /* msg_size differs */
    ck_assert_int_eq(kelp_udpm_feed(&f->rx, bad, lens[1], 1, 0, &m), KELP_ERR_RANGE);
    for (int k = 1; k < n; k++)
        ck_assert_int_eq(kelp_udpm_feed(&f->rx, dg[k], lens[k], 1, 0, &m), k == n - 1 ? 1 : 0);
    ck_assert(memcmp(m.data, pay, sizeof pay) == 0);
    free(f);
}
END_TEST

/* random bytes never crash, never complete a message with out-of-range data */
START_TEST(random_datagrams_survive)
{
    rxfix *f = fix_new();
    uint8_t dg[300];
    unsigned seed = 12345;
    kelp_udpm_msg m;
    for (int i = 0; i < 20000; i++) {
        size_t len = (size_t)(seed % sizeof dg);
        for (size_t k = 0; k < len; k++) {
            seed = seed * 1103515245u + 12345u;
            dg[k] = (uint8_t)(seed >> 16);
        }
        if (len >= 4 && (i & 1)) memcpy(dg, (i & 2) ? "LC03" : "LC02", 4);
        if (kelp_udpm_feed(&f->rx, dg, len, seed & 3, i * 0.001, &m) == 1) {
            ck_assert_uint_le(m.len, CAP > len ? CAP : len);
            ck_assert_uint_le(strlen(m.channel), KELP_UDPM_MAX_CHANNEL);
        }
    }
    ck_assert_uint_gt(kelp_udpm_get_stats(&f->rx)->bad, 1000);
    free(f);
}
END_TEST

START_TEST(init_and_args)
{
    kelp_udpm_rx rx;
    kelp_udpm_slot s[1];
    uint8_t mem[16];
    ck_assert_int_eq(kelp_udpm_init(&rx, s, 1, NULL, 16, 1.0), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_udpm_init(&rx, s, 1, mem, 16, 0.0), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_udpm_init(&rx, NULL, 0, NULL, 0, 1.0), 0);
    /* no slots: fragments are too big by definition, short messages still work */
    uint8_t dg[64];
    size_t n;
    ck_assert_int_eq(kelp_udpm_datagram("A", mem, 4, 1, 40, 0, dg, sizeof dg, &n), 0);
    kelp_udpm_msg m;
    ck_assert_int_eq(kelp_udpm_feed(&rx, dg, n, 0, 0, &m), 1);
    uint8_t big[200];
    memset(big, 1, sizeof big);
    ck_assert_int_eq(kelp_udpm_datagram("A", big, sizeof big, 1, 40, 0, dg, sizeof dg, &n), 0);
    ck_assert_int_eq(kelp_udpm_feed(&rx, dg, n, 0, 0, &m), KELP_ERR_RANGE);
    ck_assert_uint_eq(rx.stats.too_big, 1);
    ck_assert_int_eq(kelp_udpm_datagram("A", big, sizeof big, 1, 40, 60, dg, sizeof dg, &n), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_datagram("A", big, sizeof big, 1, 40, 0, dg, 10, &n), KELP_ERR_NOSPACE);
}
END_TEST

START_TEST(url_parse)
{
    kelp_udpm_url u;
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304", &u), 0);
    ck_assert_uint_eq(u.group, 0xefff4c43u);
    ck_assert_uint_eq(u.port, 7667);
    ck_assert_int_eq(u.ttl, 0);
    ck_assert_int_eq(u.recv_buf_size, 4194304);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.3", &u), 0);
    ck_assert_uint_eq(u.port, KELP_UDPM_DEFAULT_PORT);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.3:9000?ttl=1&queue_size=1000&transmit_only=true", &u), 0);
    ck_assert_int_eq(u.ttl, 1);
    ck_assert_int_eq(u.queue_size, 1000);
    ck_assert_int_eq(u.send_buf_size, 0);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.3:9000?ttl=0&send_buf_size=4194304", &u), 0);
    ck_assert_int_eq(u.send_buf_size, 4194304);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.3:9000?send_buf_size=-1", &u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_url_parse("memq://", &u), KELP_ERR_UNSUPPORTED);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://10.0.0.1:7667", &u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2:7667", &u), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.3.4:7667", &u), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.300:7667", &u), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.3:70000", &u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.3:x", &u), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.3:1?ttl=256", &u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.3:1?ttl=abc", &u), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_udpm_url_parse("udpm://239.1.2.3:1?colour=red", &u), KELP_ERR_PARSE);
}
END_TEST

Suite *kelp_udpm_suite(void)
{
    Suite *s = suite_create("udpm");
    TCase *tc = tcase_create("udpm");
    tcase_add_test(tc, short_message_roundtrip);
    tcase_add_test(tc, plan_matches_lcm_limits);
    tcase_add_test(tc, fragments_in_order);
    tcase_add_loop_test(tc, fragments_any_order, 0, 2);
    tcase_add_test(tc, interleaved_senders_and_messages);
    tcase_add_test(tc, duplicates_ignored_and_counted);
    tcase_add_test(tc, incomplete_slot_times_out);
    tcase_add_test(tc, busy_slots_evict_oldest);
    tcase_add_test(tc, one_sender_cannot_take_every_slot);
    tcase_add_loop_test(tc, malformed_is_rejected, 0, N_BAD);
    tcase_add_test(tc, conflicting_shape_rejected);
    tcase_add_test(tc, random_datagrams_survive);
    tcase_add_test(tc, init_and_args);
    tcase_add_test(tc, url_parse);
    suite_add_tcase(s, tc);
    return s;
}
