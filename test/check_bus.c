/* Unit tests: the bus core (wire layout, validation, registration, sync, loopback). */
#include <check.h>
#include <string.h>
#include <stdlib.h>
#include <stdio.h>
#include <kelp/bus.h>
#include <kelp/udpm.h>
#include <kelp/loopback.h>

/* ------------------------------------------------------------------ a test client */
typedef struct tclient {
    kelp_bus bus;
    kelp_bus_sub subs[16];
    kelp_var cache[600]; /* more than KELP_BUS_CACHE_HASH / 2: the linear walk is tested too */
    kelp_var rx;
    uint8_t scratch[16384];
    kelp_loopback_port port;
    int ndeliv;
    kelp_var last;
    char log[2048];
} tclient;

static void on_var(const kelp_var *v, void *user)
{
    tclient *c = user;
    c->ndeliv++;
    c->last = *v;
    char line[KELP_MAX_SVAL + 256];
    if (v->kind == KELP_VAR_DOUBLE)
        snprintf(line, sizeof line, "%s=%g%s;", v->name, v->dval, (v->flags & KELP_VAR_FLAG_SYNC) ? "(s)" : "");
    else
        snprintf(line, sizeof line, "%s='%s'%s;", v->name, v->sval, (v->flags & KELP_VAR_FLAG_SYNC) ? "(s)" : "");
    size_t have = strlen(c->log), add = strlen(line);
    if (have + add < sizeof c->log) memcpy(c->log + have, line, add + 1);
}

static tclient *tc_new(kelp_loopback *net, const char *app, size_t ncache)
{
    tclient *c = calloc(1, sizeof *c);
    kelp_bus_transport tr;
    kelp_loopback_transport(net, &c->port, &tr);
    kelp_bus_storage st = { c->subs, 16, c->cache, ncache, c->scratch, sizeof c->scratch, &c->rx };
    char reply[KELP_MAX_NAME];
    snprintf(reply, sizeof reply, "KELP_SYNC_%s", app);
    ck_assert_int_eq(kelp_bus_init(&c->bus, app, "xrelay", reply, &tr, &st, on_var, c), 0);
    ck_assert_int_eq(kelp_loopback_attach(net, &c->bus), 0);
    return c;
}

static void mkvar(kelp_var *v, const char *name, kelp_var_kind kind, double d, const char *s)
{
    memset(v, 0, sizeof *v);
    strcpy(v->name, name);
    strcpy(v->source, "pXRelay_APPLES");
    strcpy(v->community, "xrelay");
    v->time = 1234.5;
    v->kind = kind;
    v->dval = d;
    if (s) {
        v->slen = strlen(s);
        memcpy(v->sval, s, v->slen + 1);
    }
}

/* ------------------------------------------------------------------ wire */
START_TEST(var_roundtrip_all_kinds)
{
    static kelp_var a, b;
    uint8_t buf[8192];
    size_t n;
    mkvar(&a, "APPLES", KELP_VAR_DOUBLE, 151.0, NULL);
    ck_assert_int_eq(kelp_var_encode(&a, buf, sizeof buf, &n), 0);
    ck_assert_uint_eq(n, kelp_var_encoded_size(&a));
    ck_assert_int_eq(kelp_var_decode(buf, n, &b), 0);
    ck_assert_str_eq(b.name, "APPLES");
    ck_assert_str_eq(b.source, "pXRelay_APPLES");
    ck_assert_str_eq(b.community, "xrelay");
    ck_assert(b.kind == KELP_VAR_DOUBLE);
    ck_assert(b.dval == 151.0 && b.time == 1234.5);

    mkvar(&a, "NODE_REPORT", KELP_VAR_STRING, 0, "NAME=alpha,X=1,Y=-2");
    ck_assert_int_eq(kelp_var_encode(&a, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_var_decode(buf, n, &b), 0);
    ck_assert_str_eq(b.sval, "NAME=alpha,X=1,Y=-2");
    ck_assert_uint_eq(b.slen, 19);

    mkvar(&a, "BLOB", KELP_VAR_BINARY, 0, NULL);
    const uint8_t bin[5] = { 0, 1, 0xff, 0, 7 };
    memcpy(a.sval, bin, 5);
    a.slen = 5;
    a.flags = KELP_VAR_FLAG_BRIDGED;
    ck_assert_int_eq(kelp_var_encode(&a, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_var_decode(buf, n, &b), 0);
    ck_assert(b.kind == KELP_VAR_BINARY);
    ck_assert_uint_eq(b.slen, 5);
    ck_assert_mem_eq(b.sval, bin, 5);
    ck_assert_uint_eq(b.flags, KELP_VAR_FLAG_BRIDGED);
}
END_TEST

START_TEST(var_encode_nospace_and_bad_args)
{
    static kelp_var a;
    uint8_t buf[64];
    size_t n;
    mkvar(&a, "A_LONG_ENOUGH_NAME", KELP_VAR_STRING, 0, "0123456789012345678901234567890123456789");
    ck_assert_int_eq(kelp_var_encode(&a, buf, sizeof buf, &n), KELP_ERR_NOSPACE);
    a.kind = (kelp_var_kind)9;
    ck_assert_int_eq(kelp_var_encode(&a, buf, sizeof buf, &n), KELP_ERR_ARG);
}
END_TEST

/* Every strict prefix of a valid datagram is rejected, never read past. */
START_TEST(var_decode_every_truncation)
{
    static kelp_var a, b;
    uint8_t buf[512];
    size_t n;
    mkvar(&a, "DEPLOY", KELP_VAR_STRING, 0, "true");
    ck_assert_int_eq(kelp_var_encode(&a, buf, sizeof buf, &n), 0);
    for (size_t k = 0; k < n; k++) {
        uint8_t *cut = malloc(k ? k : 1);
        memcpy(cut, buf, k);
        ck_assert_int_lt(kelp_var_decode(cut, k, &b), 0);
        free(cut);
    }
    /* a trailing byte other than zero is rejected; zero bytes are a publisher's padding
     * (segmented sends) up to KELP_UDPM_PAD_MAX, and one more is rejected */
    buf[n] = 1;
    ck_assert_int_eq(kelp_var_decode(buf, n + 1, &b), KELP_ERR_PARSE);
    memset(buf + n, 0, KELP_UDPM_PAD_MAX + 1);
    ck_assert_int_eq(kelp_var_decode(buf, n + 1, &b), 0);
    ck_assert_str_eq(b.sval, "true");
    ck_assert_int_eq(kelp_var_decode(buf, n + KELP_UDPM_PAD_MAX, &b), 0);
    ck_assert_int_eq(kelp_var_decode(buf, n + KELP_UDPM_PAD_MAX + 1, &b), KELP_ERR_PARSE);
    buf[n + 10] = 2; /* a non-zero byte inside the padding */
    ck_assert_int_eq(kelp_var_decode(buf, n + 20, &b), KELP_ERR_PARSE);
}
END_TEST

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24); p[1] = (uint8_t)(v >> 16); p[2] = (uint8_t)(v >> 8); p[3] = (uint8_t)v;
}

/* The datagrams that crash LCM 1.3.1's generated decoder. */
START_TEST(var_decode_hostile_lengths)
{
    static kelp_var a, b;
    uint8_t buf[512];
    size_t n;
    mkvar(&a, "X", KELP_VAR_DOUBLE, 1, NULL);
    ck_assert_int_eq(kelp_var_encode(&a, buf, sizeof buf, &n), 0);
    /* name length field sits at offset 16 */
    uint8_t t[512];
    memcpy(t, buf, n); put32(t + 16, 0x80000000u);           /* negative */
    ck_assert_int_eq(kelp_var_decode(t, n, &b), KELP_ERR_PARSE);
    memcpy(t, buf, n); put32(t + 16, 0x7ffffff0u);           /* huge */
    ck_assert_int_eq(kelp_var_decode(t, n, &b), KELP_ERR_TRUNCATED);
    memcpy(t, buf, n); put32(t + 16, 0);                     /* zero (no NUL) */
    ck_assert_int_eq(kelp_var_decode(t, n, &b), KELP_ERR_PARSE);
    memcpy(t, buf, n); t[16 + 4 + 1] = 'Z';                  /* missing NUL */
    ck_assert_int_eq(kelp_var_decode(t, n, &b), KELP_ERR_PARSE);
    memcpy(t, buf, n); t[0] ^= 1;                            /* wrong fingerprint */
    ck_assert_int_eq(kelp_var_decode(t, n, &b), KELP_ERR_DEFMISMATCH);
    /* kind byte: 8+8 + (4+2)*1 name "X" + source + source_aux + community */
    size_t koff = 16 + (4 + 2) + (4 + strlen(a.source) + 1) + (4 + strlen(a.source_aux) + 1) +
                  (4 + strlen(a.community) + 1);
    memcpy(t, buf, n); t[koff] = 7;
    ck_assert_int_eq(kelp_var_decode(t, n, &b), KELP_ERR_PARSE);
    /* nbytes negative */
    size_t nboff = koff + 1 + 8 + 5;
    memcpy(t, buf, n); put32(t + nboff, 0xffffffffu);
    ck_assert_int_eq(kelp_var_decode(t, n, &b), KELP_ERR_PARSE);
}
END_TEST

START_TEST(var_decode_rejects_name_longer_than_limit)
{
    uint8_t buf[512];
    size_t n = 0;
    memset(buf, 0, sizeof buf);
    uint64_t fp = KELP_VAR_FINGERPRINT;
    for (int i = 0; i < 8; i++) buf[n++] = (uint8_t)(fp >> (56 - 8 * i));
    n += 8;
    put32(buf + n, KELP_MAX_NAME + 1);
    n += 4;
    memset(buf + n, 'A', KELP_MAX_NAME);
    n += KELP_MAX_NAME + 1;
    static kelp_var b;
    ck_assert_int_eq(kelp_var_decode(buf, n + 60, &b), KELP_ERR_RANGE);
}
END_TEST

START_TEST(sync_req_roundtrip_and_reject)
{
    kelp_sync_req q, r;
    memset(&q, 0, sizeof q);
    strcpy(q.requester, "uXMS");
    strcpy(q.community, "xrelay");
    strcpy(q.reply_channel, "KELP_SYNC_uXMS_1");
    q.npatterns = 2;
    strcpy(q.patterns[0], "APPLES");
    strcpy(q.patterns[1], "*_HZ");
    uint8_t buf[1024];
    size_t n;
    ck_assert_int_eq(kelp_bus_sync_req_encode(&q, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_bus_sync_req_decode(buf, n, &r), 0);
    ck_assert_str_eq(r.patterns[1], "*_HZ");
    ck_assert_uint_eq(r.npatterns, 2);
    for (size_t k = 0; k < n; k++) ck_assert_int_lt(kelp_bus_sync_req_decode(buf, k, &r), 0);
}
END_TEST

static const struct { const char *pat, *name; bool m; } globs[] = {
    { "APPLES", "APPLES", true }, { "APPLES", "APPLE", false }, { "APPLES", "APPLESS", false },
    { "*", "ANY", true }, { "*", "", true }, { "*_HZ", "APPLES_ITER_HZ", true },
    { "*_HZ", "APPLES_ITER_HZ_X", false }, { "NAV_?", "NAV_X", true }, { "NAV_?", "NAV_XY", false },
    { "A*B*C", "AxxBxxC", true }, { "A*B*C", "AxxCxxB", false }, { "**", "x", true },
    { "?", "", false }, { "VIEW_*", "VIEW_POINT", true }, { "a*a*a*a*b", "aaaaaaaaaaaaaaaaaaaaaaaa", false },
};

START_TEST(glob_table)
{
    ck_assert_msg(kelp_bus_match(globs[_i].pat, globs[_i].name) == globs[_i].m, "%s ~ %s", globs[_i].pat,
                  globs[_i].name);
}
END_TEST

/* ------------------------------------------------------------------ pub/sub */
START_TEST(publish_subscribe_exact_and_wildcard)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    tclient *a = tc_new(&net, "pA", 32), *b = tc_new(&net, "pB", 32);
    ck_assert_int_eq(kelp_bus_register(&b->bus, "APPLES", 0, 10.0), 0);
    ck_assert_int_eq(kelp_bus_register(&b->bus, "*_HZ", 0, 10.0), 0);
    ck_assert_int_eq(kelp_bus_notify_double(&a->bus, "APPLES", 1, 11.0), 0);
    ck_assert_int_eq(kelp_bus_notify_double(&a->bus, "APPLES_ITER_HZ", 24.9, 11.0), 0);
    ck_assert_int_eq(kelp_bus_notify_string(&a->bus, "PEARS", "no", 11.0), 0);
    ck_assert_str_eq(b->log, "APPLES=1;APPLES_ITER_HZ=24.9;");
    ck_assert_str_eq(b->last.source, "pA");
    ck_assert_str_eq(b->last.community, "xrelay");
    ck_assert(b->last.time == 11.0);
    ck_assert_int_eq(a->ndeliv, 0);
    free(a); free(b);
}
END_TEST

/* MOOS source-aux travels with the write (uFldMessageHandler puts the sending node there) */
START_TEST(source_aux_roundtrip)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    tclient *a = tc_new(&net, "pA", 32), *b = tc_new(&net, "pB", 32);
    ck_assert_int_eq(kelp_bus_register(&b->bus, "FOO", 0, 10.0), 0);
    ck_assert_int_eq(kelp_bus_notify_aux(&a->bus, "FOO", true, "hello", 0, "alpha", 11.0), 0);
    ck_assert_str_eq(b->log, "FOO='hello';");
    ck_assert_str_eq(b->last.source, "pA");
    ck_assert_str_eq(b->last.source_aux, "alpha");
    ck_assert_int_eq(kelp_bus_notify_string(&a->bus, "FOO", "plain", 12.0), 0);
    ck_assert_str_eq(b->last.source_aux, "");
    char longaux[KELP_MAX_NAME + 1];
    memset(longaux, 'x', KELP_MAX_NAME);
    longaux[KELP_MAX_NAME] = 0;
    ck_assert_int_eq(kelp_bus_notify_aux(&a->bus, "FOO", true, "x", 0, longaux, 13.0), KELP_ERR_RANGE);
    free(a); free(b);
}
END_TEST

/* The MOOSDB's type rule: a variable's type is fixed by its first write; a double posted to a
 * variable holding strings (or the reverse) reaches nobody, and each side counts it. */
START_TEST(type_clash_dropped_as_moosdb)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    tclient *a = tc_new(&net, "pA", 32), *b = tc_new(&net, "pB", 32), *c = tc_new(&net, "pC", 32);
    ck_assert_int_eq(kelp_bus_register(&b->bus, "NODE_MESSAGE", 0, 10.0), 0);
    ck_assert_int_eq(kelp_bus_notify_string(&a->bus, "NODE_MESSAGE", "src_node=a", 11.0), 0);
    /* the writer knows the type: it does not send the double */
    ck_assert_int_eq(kelp_bus_notify_double(&a->bus, "NODE_MESSAGE", 3.0, 12.0), 0);
    ck_assert_uint_eq(kelp_bus_get_stats(&a->bus)->type_refused, 1);
    /* another writer that never saw it sends; the receiver that holds a string drops it */
    ck_assert_int_eq(kelp_bus_notify_double(&c->bus, "NODE_MESSAGE", 4.0, 13.0), 0);
    ck_assert_uint_eq(kelp_bus_get_stats(&b->bus)->type_refused, 1);
    ck_assert_int_eq(kelp_bus_notify_string(&a->bus, "NODE_MESSAGE", "src_node=b", 14.0), 0);
    ck_assert_str_eq(b->log, "NODE_MESSAGE='src_node=a';NODE_MESSAGE='src_node=b';");
    /* a new variable takes the type of its first write, whatever it is */
    ck_assert_int_eq(kelp_bus_register(&b->bus, "SPEED", 0, 15.0), 0);
    ck_assert_int_eq(kelp_bus_notify_double(&a->bus, "SPEED", 2.5, 16.0), 0);
    ck_assert_int_eq(kelp_bus_notify_string(&c->bus, "SPEED", "fast", 17.0), 0);
    ck_assert_str_eq(b->log, "NODE_MESSAGE='src_node=a';NODE_MESSAGE='src_node=b';SPEED=2.5;");
    free(a); free(b); free(c);
}
END_TEST

START_TEST(late_registrant_gets_current_value_once)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    tclient *a = tc_new(&net, "pA", 32), *c = tc_new(&net, "retainer", 32);
    ck_assert_int_eq(kelp_bus_retain_all(&c->bus, 0), 0);
    ck_assert_int_eq(kelp_bus_notify_string(&a->bus, "DEPLOY", "true", 5.0), 0);
    ck_assert_int_eq(kelp_bus_notify_double(&a->bus, "SPEED", 1.0, 5.0), 0);
    ck_assert_int_eq(kelp_bus_notify_double(&a->bus, "SPEED", 2.0, 6.0), 0);
    /* a and the retainer both hold DEPLOY and SPEED: the newcomer gets each once, the newest */
    tclient *late = tc_new(&net, "pLate", 32);
    ck_assert_int_eq(kelp_bus_register(&late->bus, "DEPLOY", 0, 7.0), 0);
    ck_assert_int_eq(kelp_bus_register(&late->bus, "SPEED", 0, 7.0), 0);
    ck_assert_str_eq(late->log, "DEPLOY='true'(s);SPEED=2(s);");
    ck_assert_uint_eq(kelp_bus_get_stats(&late->bus)->sync_delivered, 2);
    ck_assert_uint_eq(kelp_bus_get_stats(&late->bus)->sync_stale, 2);
    /* a poker that has left: only the retainer answers */
    tclient *poker = tc_new(&net, "kelp-poke", 32);
    ck_assert_int_eq(kelp_bus_notify_double(&poker->bus, "APPLES", 1, 8.0), 0);
    net.nclients--; /* poker exits */
    tclient *late2 = tc_new(&net, "pLate2", 32);
    ck_assert_int_eq(kelp_bus_register(&late2->bus, "APP*", 0, 9.0), 0);
    ck_assert_str_eq(late2->log, "APPLES=1(s);");
    ck_assert_str_eq(late2->last.source, "kelp-poke");
    free(a); free(c); free(late); free(poker); free(late2);
}
END_TEST

START_TEST(register_interval_limits_rate)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    tclient *a = tc_new(&net, "pA", 32), *b = tc_new(&net, "pB", 32);
    ck_assert_int_eq(kelp_bus_register(&b->bus, "NAV_X", 1.0, 0), 0);
    for (int i = 0; i < 10; i++) ck_assert_int_eq(kelp_bus_notify_double(&a->bus, "NAV_X", i, 100.0 + 0.25 * i), 0);
    /* times 100, 100.25 ... 102.25: delivered at 100, 101, 102 */
    ck_assert_str_eq(b->log, "NAV_X=0;NAV_X=4;NAV_X=8;");
    ck_assert_uint_eq(kelp_bus_get_stats(&b->bus)->rate_limited, 7);
    free(a); free(b);
}
END_TEST

/* Handlers may publish: two relays perpetuate a handshake (pXRelay) without recursion. */
typedef struct relay { tclient *c; const char *out; int count; } relay;
static relay relays[2];
static void relay_handler(const kelp_var *v, void *user)
{
    relay *r = &relays[(size_t)user];
    (void)v;
    if (r->count >= 50) return;
    r->count++;
    ck_assert_int_eq(kelp_bus_notify_double(&r->c->bus, r->out, r->count, 1.0), 0);
}

START_TEST(handlers_may_publish)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    tclient *a = tc_new(&net, "pXRelay_APPLES", 32), *p = tc_new(&net, "pXRelay_PEARs", 32);
    relays[0] = (relay){ a, "APPLES", 0 };
    relays[1] = (relay){ p, "PEARS", 0 };
    a->bus.handler = relay_handler; a->bus.user = (void *)0;
    p->bus.handler = relay_handler; p->bus.user = (void *)1;
    ck_assert_int_eq(kelp_bus_register(&a->bus, "PEARS", 0, 0), 0);
    ck_assert_int_eq(kelp_bus_register(&p->bus, "APPLES", 0, 0), 0);
    ck_assert_int_eq(kelp_bus_notify_double(&a->bus, "APPLES", 0, 1.0), 0);
    ck_assert_int_eq(relays[0].count, 50);
    ck_assert_int_eq(relays[1].count, 50);
    ck_assert_uint_eq(net.dropped, 0);
    free(a); free(p);
}
END_TEST

START_TEST(bad_datagram_counted_and_client_goes_on)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    tclient *b = tc_new(&net, "pB", 32);
    ck_assert_int_eq(kelp_bus_register(&b->bus, "APPLES", 0, 0), 0);
    const uint8_t junk[] = { 1, 2, 3 };
    ck_assert_int_lt(kelp_bus_receive(&b->bus, "APPLES", junk, sizeof junk, 0), 0);
    ck_assert_int_lt(kelp_bus_receive(&b->bus, KELP_BUS_SYNC_CHANNEL, junk, sizeof junk, 0), 0);
    /* a valid var on the wrong channel */
    static kelp_var v;
    mkvar(&v, "PEARS", KELP_VAR_DOUBLE, 1, NULL);
    uint8_t buf[512];
    size_t n;
    ck_assert_int_eq(kelp_var_encode(&v, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_bus_receive(&b->bus, "APPLES", buf, n, 0), KELP_ERR_PARSE);
    ck_assert_uint_eq(kelp_bus_get_stats(&b->bus)->bad, 3);
    mkvar(&v, "APPLES", KELP_VAR_DOUBLE, 3, NULL);
    ck_assert_int_eq(kelp_var_encode(&v, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_bus_receive(&b->bus, "APPLES", buf, n, 0), 0);
    ck_assert_str_eq(b->log, "APPLES=3;");
    free(b);
}
END_TEST

/* Another LCM type on a channel reached only through a wildcard is foreign, not bad; on a
 * channel registered by exact name it is bad. */
START_TEST(foreign_type_through_wildcard_is_not_bad)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    tclient *b = tc_new(&net, "pB", 32);
    ck_assert_int_eq(kelp_bus_register(&b->bus, "*", 0, 0), 0);
    ck_assert_int_eq(kelp_bus_register(&b->bus, "EXACT", 0, 0), 0);
    uint8_t other[24] = { 0x12, 0x34, 0x56, 0x78, 0x9a, 0xbc, 0xde, 0xf0 };
    ck_assert_int_eq(kelp_bus_receive(&b->bus, "ACOMMS_ACK_LCM", other, sizeof other, 0), 0);
    ck_assert_uint_eq(kelp_bus_get_stats(&b->bus)->foreign, 1);
    ck_assert_uint_eq(kelp_bus_get_stats(&b->bus)->bad, 0);
    ck_assert_int_eq(kelp_bus_receive(&b->bus, "EXACT", other, sizeof other, 0), KELP_ERR_DEFMISMATCH);
    ck_assert_uint_eq(kelp_bus_get_stats(&b->bus)->bad, 1);
    free(b);
}
END_TEST

START_TEST(cache_full_still_publishes)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    tclient *a = tc_new(&net, "pA", 1), *b = tc_new(&net, "pB", 32);
    ck_assert_int_eq(kelp_bus_register(&b->bus, "*", 0, 0), 0);
    ck_assert_int_eq(kelp_bus_notify_double(&a->bus, "V1", 1, 1), 0);
    ck_assert_int_eq(kelp_bus_notify_double(&a->bus, "V2", 2, 1), 0);
    ck_assert_str_eq(b->log, "V1=1;V2=2;");
    ck_assert_uint_eq(kelp_bus_get_stats(&a->bus)->cache_full, 1);
    ck_assert_ptr_nonnull(kelp_bus_cached(&a->bus, "V1"));
    ck_assert_ptr_null(kelp_bus_cached(&a->bus, "V2"));
    free(a); free(b);
}
END_TEST

/* the retained values are found by name through the index (KELP_BUS_CACHE_HASH) and, for a
 * caller cache larger than half the index, by the linear walk: the same answers either way */
static void many_names(size_t ncache, size_t nnames)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    tclient *a = tc_new(&net, "pA", ncache);
    char name[KELP_MAX_NAME];
    for (int round = 0; round < 2; round++)
        for (size_t i = 0; i < nnames; i++) {
            snprintf(name, sizeof name, "NODE_REPORT_V%zu", i);
            ck_assert_int_eq(kelp_bus_notify_double(&a->bus, name, (double)(i + 1000 * round), 1 + round), 0);
        }
    for (size_t i = 0; i < nnames; i++) {
        snprintf(name, sizeof name, "NODE_REPORT_V%zu", i);
        const kelp_var *v = kelp_bus_cached(&a->bus, name);
        if (i < ncache) {
            ck_assert_ptr_nonnull(v);
            ck_assert_str_eq(v->name, name);
            ck_assert_double_eq(v->dval, (double)(i + 1000));
        } else {
            ck_assert_ptr_null(v);
        }
    }
    ck_assert_ptr_null(kelp_bus_cached(&a->bus, "NODE_REPORT_V"));
    ck_assert_uint_eq(kelp_bus_get_stats(&a->bus)->cache_full, nnames > ncache ? 2 * (nnames - ncache) : 0);
    free(a);
}

START_TEST(cache_many_names_indexed_and_linear)
{
    size_t cap = sizeof ((tclient *)0)->cache / sizeof ((tclient *)0)->cache[0];
    many_names(cap < 200 ? cap : 200, 150);
    many_names(cap, cap + 40);
}
END_TEST

START_TEST(init_rejects_small_scratch)
{
    static kelp_loopback net;
    kelp_loopback_init(&net);
    static kelp_bus bus;
    static kelp_var rx;
    uint8_t small[16];
    kelp_loopback_port port;
    kelp_bus_transport tr;
    kelp_loopback_transport(&net, &port, &tr);
    kelp_bus_storage st = { NULL, 0, NULL, 0, small, sizeof small, &rx };
    ck_assert_int_eq(kelp_bus_init(&bus, "a", "c", "r", &tr, &st, NULL, NULL), KELP_ERR_NOSPACE);
}
END_TEST

Suite *kelp_bus_suite(void)
{
    Suite *s = suite_create("bus");
    TCase *w = tcase_create("wire");
    tcase_add_test(w, var_roundtrip_all_kinds);
    tcase_add_test(w, var_encode_nospace_and_bad_args);
    tcase_add_test(w, var_decode_every_truncation);
    tcase_add_test(w, var_decode_hostile_lengths);
    tcase_add_test(w, var_decode_rejects_name_longer_than_limit);
    tcase_add_test(w, sync_req_roundtrip_and_reject);
    tcase_add_loop_test(w, glob_table, 0, (int)(sizeof globs / sizeof globs[0]));
    suite_add_tcase(s, w);
    TCase *c = tcase_create("client");
    tcase_add_test(c, publish_subscribe_exact_and_wildcard);
    tcase_add_test(c, source_aux_roundtrip);
    tcase_add_test(c, type_clash_dropped_as_moosdb);
    tcase_add_test(c, late_registrant_gets_current_value_once);
    tcase_add_test(c, register_interval_limits_rate);
    tcase_add_test(c, handlers_may_publish);
    tcase_add_test(c, bad_datagram_counted_and_client_goes_on);
    tcase_add_test(c, cache_full_still_publishes);
    tcase_add_test(c, cache_many_names_indexed_and_linear);
    tcase_add_test(c, foreign_type_through_wildcard_is_not_bad);
    tcase_add_test(c, init_rejects_small_scratch);
    suite_add_tcase(s, c);
    return s;
}
