/* uFldNodeBroker's and uFldShoreBroker's state machines (src/field/nodebroker.c,
 * shorebroker.c, broker.c): ufield.md 2.6 and 3.6, the handshake between them, restarts. */
#include <check.h>
#include "check_diag.h"
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>

#define REC_MAX 512

typedef struct rec {
    int n, warns;
    char var[REC_MAX][64];
    char val[REC_MAX][KELP_BROKER_MSG];
} rec;

static rec R; /* one recorder per test; the tests run one after another */

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    if (r->n >= REC_MAX) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    if (is_string) snprintf(r->val[r->n], sizeof r->val[0], "%s", sval);
    else snprintf(r->val[r->n], sizeof r->val[0], "%g", dval);
    r->n++;
}

static void warned(void *ctx, const char *msg)
{
    (void)msg;
    ((rec *)ctx)->warns++;
}

static kelp_field_sink sink(void)
{
    memset(&R, 0, sizeof R);
    return (kelp_field_sink){ &R, pub, warned };
}

static int count(const char *var)
{
    int c = 0;
    for (int i = 0; i < R.n; i++) c += strcmp(R.var[i], var) == 0;
    return c;
}

/* the k-th (0-based) value posted to var, or NULL */
static const char *nth(const char *var, int k)
{
    for (int i = 0; i < R.n; i++)
        if (strcmp(R.var[i], var) == 0 && k-- == 0) return R.val[i];
    return NULL;
}

static const char *last(const char *var)
{
    for (int i = R.n; i-- > 0;)
        if (strcmp(R.var[i], var) == 0) return R.val[i];
    return NULL;
}

static void cfg_node(kelp_field_nbroker_cfg *c, const char *const *lines)
{
    kelp_field_nbroker_cfg_seed(c);
    for (; *lines; lines += 2) {
        kelp_diag why = { 0 };
        ck_assert_int_eq(kelp_field_nbroker_config(c, lines[0], lines[1], &why), 1);
    }
}

#define JAMES_PHI "community=james,hostip=10.0.0.8,port_db=9204,port_udp=9304,timewarp=1"
#define SHORE_ACK "community=shoreside,host=10.0.0.8,port=9000,port_udp=9200,time_warp=1"

/* ---------------------------------------------------------------- parsers */

START_TEST(host_record_synonyms)
{
    kelp_field_broker_host h;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_broker_host_parse(JAMES_PHI, &h, &why), 0);
    ck_assert_str_eq(h.community, "james");
    ck_assert_str_eq(h.host, "10.0.0.8");
    ck_assert_uint_eq(h.port_db, 9204);
    ck_assert_uint_eq(h.port_udp, 9304);
    ck_assert(h.have_warp && h.warp == 1);
    ck_assert(kelp_field_broker_host_complete(&h));
    /* the seed's ping, broken over two lines with spaces */
    ck_assert_int_eq(kelp_field_broker_host_parse("community=henry,host=192.168.1.22,port=9000,port_udp=9200,  \n"
                                            "keyword=lemon,time_warp=10,time=1325178800.81",
                                            &h, &why),
                     0);
    ck_assert_str_eq(h.keyword, "lemon");
    ck_assert(h.warp == 10 && h.have_time && h.time > 1325178800.80 && h.time < 1325178800.82);
    ck_assert_uint_eq(h.port_db, 9000);
    /* 24.8: host_ip / port_db / pshare_iroutes */
    ck_assert_int_eq(kelp_field_broker_host_parse("community=abe,host_ip=192.168.7.6,port_db=9000,"
                                            "pshare_iroutes=multicast_8&192.168.7.6:9201,time_warp=5,key=1",
                                            &h, &why),
                     0);
    ck_assert_uint_eq(h.port_udp, 9201);
    ck_assert_str_eq(h.host, "192.168.7.6");
    /* incomplete and malformed */
    ck_assert_int_eq(kelp_field_broker_host_parse("community=james,hostip=10.0.0.8,port_db=9204", &h, &why), 0);
    ck_assert(!kelp_field_broker_host_complete(&h));
    ck_assert_int_eq(kelp_field_broker_host_parse("community=james,port_udp=99999", &h, &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_broker_host_parse("community=james,time_warp=0", &h, &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_broker_host_parse("community", &h, &why), KELP_ERR_PARSE);
}
END_TEST

START_TEST(try_and_bridge_lines)
{
    kelp_field_broker_try t;
    kelp_field_broker_bridge b;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_broker_try_parse("host_ip=localhost, port_udp=9200, community=topside", &t, &why), 0);
    ck_assert_str_eq(t.host, "localhost");
    ck_assert_str_eq(t.community, "topside");
    ck_assert_uint_eq(t.port, 9200);
    ck_assert_int_eq(kelp_field_broker_try_parse("hostip=128.30.24.232, port_udp=9200", &t, &why), 0);
    ck_assert_str_eq(t.community, "");
    ck_assert_int_eq(kelp_field_broker_try_parse("pshare_route=192.168.0.122:9301", &t, &why), 0);
    ck_assert_str_eq(t.host, "192.168.0.122");
    ck_assert_uint_eq(t.port, 9301);
    ck_assert_int_eq(kelp_field_broker_try_parse("pshare_route=multicast_8", &t, &why), KELP_ERR_UNSUPPORTED);
    ck_assert_int_eq(kelp_field_broker_try_parse("pshare_route=localhost", &t, &why), KELP_ERR_PARSE);
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_field_broker_try_parse("port_udp=9200", &t, &why), KELP_ERR_PARSE);
    ck_diag(&why, KELP_ERR_PARSE, "no host_ip");
    ck_assert_int_eq(why.line, 0); /* one value: no line of its own */
    /* first error wins: a second failure keeps the first reason */
    ck_assert_int_eq(kelp_field_broker_try_parse("host_ip=localhost", &t, &why), KELP_ERR_PARSE);
    ck_diag_msg(&why, "no host_ip");
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_field_broker_try_parse("pshare_route=multicast_8", &t, &why), KELP_ERR_UNSUPPORTED);
    ck_diag(&why, KELP_ERR_UNSUPPORTED, "a multicast route (kelp-bridge sends unicast UDP only)");
    ck_assert_int_eq(kelp_field_broker_try_parse("port_udp=9200", &t, NULL), KELP_ERR_PARSE); /* NULL: no record */
    ck_assert_int_eq(kelp_field_broker_try_parse("host_ip=localhost", &t, &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_broker_try_parse("host_ip=localhost, port_udp=x", &t, &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_broker_bridge_parse("src=VIEW_POINT", &b, &why), 0);
    ck_assert_str_eq(b.alias, "VIEW_POINT");
    ck_assert_int_eq(kelp_field_broker_bridge_parse("src=NODE_REPORT_LOCAL, alias=NODE_REPORT", &b, &why), 0);
    ck_assert_str_eq(b.src, "NODE_REPORT_LOCAL");
    ck_assert_str_eq(b.alias, "NODE_REPORT");
    ck_assert_int_eq(kelp_field_broker_bridge_parse("alias=NODE_REPORT", &b, &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_broker_bridge_parse("src=A, dest=B", &b, &why), KELP_ERR_PARSE);
}
END_TEST

/* ---------------------------------------------------------------- uFldNodeBroker (2.6) */

static const char *const try1[] = { "TRY_SHORE_HOST", "host_ip=localhost, port_udp=9200, community=topside", NULL };

START_TEST(nb_valid_try_host_listed) /* 2.6.1 */
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    cfg_node(&c, try1);
    ck_assert_uint_eq(c.ntry, 1);
    kelp_field_nbroker_init(&b, &c);
    char rep[4096];
    ck_assert_int_eq(kelp_field_nbroker_report(&b, rep, sizeof rep), 0);
    ck_assert_ptr_nonnull(strstr(rep, "  Total Valid TryHosts:   1\n  [1]: hostip=localhost,port_udp=9200\n"
                                      "  Total InValid TryHosts: 0\n"));
}
END_TEST

START_TEST(nb_invalid_try_host) /* 2.6.2 */
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    const char *const lines[] = { "TRY_SHORE_HOST", "port_udp=9200", NULL };
    cfg_node(&c, lines);
    ck_assert_uint_eq(c.ntry, 0);
    ck_assert_uint_eq(c.nbad_try, 1);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 1, &s), 1);
    ck_assert_int_eq(kelp_field_nbroker_iterate(&b, 1, &s), 1); /* a ping, no registration */
    ck_assert_int_eq(count("PMB_REGISTER"), 0);
    char rep[4096];
    ck_assert_int_eq(kelp_field_nbroker_report(&b, rep, sizeof rep), 0);
    ck_assert_ptr_nonnull(strstr(rep, "  Total InValid TryHosts: 1\n  port_udp=9200\n"));
}
END_TEST

START_TEST(nb_silent_without_host_info) /* 2.6.3 */
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    cfg_node(&c, try1);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    /* no ping and no registration; only kelp's HOST_INFO_REQUEST every 2 s (pHostInfo posts
     * once, and kelp's bus keeps no value for a late subscriber) */
    for (int i = 0; i < 50; i++) ck_assert_int_eq(kelp_field_nbroker_iterate(&b, i, &s), i % 2 == 0);
    ck_assert_int_eq(R.n, 25);
    ck_assert_int_eq(count("HOST_INFO_REQUEST"), 25);
}
END_TEST

START_TEST(nb_ping_registration_and_format) /* 2.6.4 */
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    const char *const lines[] = { "TRY_SHORE_HOST", "host_ip=localhost, port_udp=9200, community=topside",
                                  "TRY_SHORE_HOST", "pshare_route=198.51.100.1:9300", NULL };
    cfg_node(&c, lines);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 1000, &s), 1);
    ck_assert_int_eq(kelp_field_nbroker_iterate(&b, 1000.25, &s), 3);
    ck_assert_int_eq(count("PMB_REGISTER"), 2);
    ck_assert_str_eq(nth("PMB_REGISTER", 0), "src_var=NODE_BROKER_PING,dest_community=topside,dest_host=localhost,"
                                             "dest_port=9200,dest_alias=NODE_BROKER_PING");
    /* no community given: the shore is called shoreside (A25) */
    ck_assert_str_eq(nth("PMB_REGISTER", 1), "src_var=NODE_BROKER_PING,dest_community=shoreside,dest_host=198.51.100.1,"
                                             "dest_port=9300,dest_alias=NODE_BROKER_PING");
    ck_assert_str_eq(last("NODE_BROKER_PING"), "community=james,host=10.0.0.8,port=9204,port_udp=9304,time_warp=1,time=1000.25");
    /* later iterations: a ping each, no more registrations while acks come */
    for (int i = 1; i <= 5; i++) {
        ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, 1000 + i, &s), 1);
        ck_assert_int_eq(kelp_field_nbroker_iterate(&b, 1000.25 + i, &s), 1);
    }
    ck_assert_int_eq(count("PMB_REGISTER"), 2);
    ck_assert_int_eq(count("NODE_BROKER_PING"), 6);
    ck_assert_str_eq(last("NODE_BROKER_PING"), "community=james,host=10.0.0.8,port=9204,port_udp=9304,time_warp=1,time=1005.25");
}
END_TEST

START_TEST(nb_keyword_in_ping) /* 2.6.5 */
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    const char *const lines[] = { "KEYWORD", "lemon", "TRY_SHORE_HOST", "host_ip=localhost, port_udp=9200", NULL };
    cfg_node(&c, lines);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 5, &s), 1);
    for (int i = 0; i < 3; i++) (void)kelp_field_nbroker_iterate(&b, 5 + i, &s);
    ck_assert_int_eq(count("NODE_BROKER_PING"), 3);
    for (int i = 0; i < 3; i++) ck_assert_ptr_nonnull(strstr(nth("NODE_BROKER_PING", i), ",keyword=lemon,time_warp=1,"));
}
END_TEST

START_TEST(nb_bad_host_info) /* 2.6.6 */
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    cfg_node(&c, try1);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    ck_assert_int_lt(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, "community=james,hostip=10.0.0.8,port_db=9204", 1, &s), 0);
    ck_assert_int_lt(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", false, NULL, 1, &s), 0);
    ck_assert_uint_eq(b.bad_phi, 2);
    ck_assert_uint_eq(b.ok_phi, 0);
    ck_assert_int_eq(kelp_field_nbroker_iterate(&b, 2, &s), 1); /* HOST_INFO_REQUEST only */
    ck_assert_int_eq(count("HOST_INFO_REQUEST"), 1);
    ck_assert_int_eq(count("NODE_BROKER_PING"), 0);
}
END_TEST

START_TEST(nb_host_info_changes) /* 2.6.7 */
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    cfg_node(&c, try1);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 1, &s), 1);
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 2, &s), 1);
    ck_assert_uint_eq(b.phi_changes, 0);
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true,
                                             "community=james,hostip=10.0.0.9,port_db=9204,port_udp=9304,timewarp=1", 3, &s),
                     1);
    ck_assert_uint_eq(b.phi_changes, 1);
    ck_assert_uint_eq(b.ok_phi, 3);
    ck_assert_str_eq(b.node.host, "10.0.0.9");
}
END_TEST

static const char *const listing2[] = { "KEYWORD", "lemon",
                                        "TRY_SHORE_HOST", "host_ip=localhost, port_udp=9200, community=topside",
                                        "BRIDGE", "src=VIEW_POLYGON",
                                        "BRIDGE", "src=VIEW_POINT",
                                        "BRIDGE", "src=VIEW_SEGLIST",
                                        "BRIDGE", "src=NODE_REPORT_LOCAL, alias=NODE_REPORT",
                                        NULL };

START_TEST(nb_bridges_after_ack) /* 2.6.8 and 2.6.9 */
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    cfg_node(&c, listing2);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 1, &s), 1);
    (void)kelp_field_nbroker_iterate(&b, 1, &s);
    ck_assert_int_eq(count("PMB_REGISTER"), 1);
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, 1.5, &s), 1);
    ck_assert_int_eq(count("PMB_REGISTER"), 5);
    ck_assert_str_eq(nth("PMB_REGISTER", 1), "src_var=VIEW_POLYGON,dest_community=shoreside,dest_host=10.0.0.8,"
                                             "dest_port=9200,dest_alias=VIEW_POLYGON");
    ck_assert_str_eq(nth("PMB_REGISTER", 2), "src_var=VIEW_POINT,dest_community=shoreside,dest_host=10.0.0.8,"
                                             "dest_port=9200,dest_alias=VIEW_POINT");
    ck_assert_str_eq(nth("PMB_REGISTER", 3), "src_var=VIEW_SEGLIST,dest_community=shoreside,dest_host=10.0.0.8,"
                                             "dest_port=9200,dest_alias=VIEW_SEGLIST");
    ck_assert_str_eq(last("PMB_REGISTER"), "src_var=NODE_REPORT_LOCAL,dest_community=shoreside,dest_host=10.0.0.8,"
                                           "dest_port=9200,dest_alias=NODE_REPORT");
    /* 25 more acks from the same shore (no silence): nothing more registered */
    for (int i = 0; i < 25; i++) {
        (void)kelp_field_nbroker_iterate(&b, 2 + i * 0.25, &s);
        ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, 2.1 + i * 0.25, &s), 1);
    }
    ck_assert_int_eq(count("PMB_REGISTER"), 5);
    ck_assert_uint_eq(b.registers, 5);
    ck_assert_uint_eq(b.ok_ack, 26);
    ck_assert_uint_eq(b.pings, 26);
}
END_TEST

/* MOOS-IvP 24.8 NodeBroker.cpp (handleMailAck): every valid ack is followed by
 * NODE_PSHARE_VARS, the bridges' aliases in configuration order, comma-joined; a bad ack posts
 * none */
START_TEST(nb_pshare_vars)
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    cfg_node(&c, listing2);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 1, &s), 1);
    (void)kelp_field_nbroker_iterate(&b, 1, &s);
    ck_assert_int_lt(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK ",keyword=apple", 1.2, &s), 0);
    ck_assert_int_eq(count("NODE_PSHARE_VARS"), 0);
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, 1.5, &s), 1);
    ck_assert_int_eq(count("NODE_PSHARE_VARS"), 1);
    ck_assert_str_eq(last("NODE_PSHARE_VARS"), "VIEW_POLYGON,VIEW_POINT,VIEW_SEGLIST,NODE_REPORT");
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, 1.75, &s), 1);
    ck_assert_int_eq(count("NODE_PSHARE_VARS"), 2);
}
END_TEST

START_TEST(nb_bad_ack_warp) /* 2.6.10 */
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    cfg_node(&c, listing2);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 1, &s), 1);
    (void)kelp_field_nbroker_iterate(&b, 1, &s);
    ck_assert_int_lt(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true,
                                             "community=shoreside,host=10.0.0.8,port=9000,port_udp=9200,time_warp=10", 2, &s),
                     0);
    ck_assert_uint_eq(b.bad_ack, 1);
    ck_assert_uint_eq(b.ok_ack, 0);
    ck_assert_int_eq(count("PMB_REGISTER"), 1);
    ck_assert(!b.have_shore);
    ck_assert_int_eq(R.warns, 1);
    char rep[4096];
    ck_assert_int_eq(kelp_field_nbroker_report(&b, rep, sizeof rep), 0);
    ck_assert_ptr_nonnull(strstr(rep, "Shoreside Information: \n    HostIP: \n    Port (DB): \n"));
}
END_TEST

START_TEST(nb_ack_keyword_and_status)
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    cfg_node(&c, listing2); /* KEYWORD = lemon */
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 1, &s), 1);
    ck_assert_int_lt(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK ",keyword=apple", 2, &s), 0);
    ck_assert_int_lt(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK ",status=keyword_mismatch", 2, &s), 0);
    ck_assert_int_lt(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, "community=shoreside,host=10.0.0.8", 2, &s), 0);
    ck_assert_int_lt(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, "garbage", 2, &s), 0);
    ck_assert_uint_eq(b.bad_ack, 4);
    ck_assert_int_eq(count("PMB_REGISTER"), 0);
    /* a matching keyword, or none on the shore side, is fine */
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK ",keyword=lemon,status=ok", 3, &s), 1);
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, 3.5, &s), 1);
    ck_assert_uint_eq(b.ok_ack, 2);
    ck_assert_int_eq(count("PMB_REGISTER"), 4);
}
END_TEST

START_TEST(nb_retries_until_ack)
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    cfg_node(&c, listing2); /* RETRY_INTERVAL 10 (default) */
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    const char *ping_reg = "src_var=NODE_BROKER_PING,dest_community=topside,dest_host=localhost,dest_port=9200,"
                           "dest_alias=NODE_BROKER_PING";
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 0, &s), 1);
    for (double t = 0; t < 25; t += 0.25) (void)kelp_field_nbroker_iterate(&b, t, &s);
    /* nobody answers: registered at 0, again at 10 and 20 */
    ck_assert_int_eq(count("PMB_REGISTER"), 3);
    for (int i = 0; i < 3; i++) ck_assert_str_eq(nth("PMB_REGISTER", i), ping_reg);
    ck_assert_uint_eq(b.pings, 100);
    /* the shore answers: bridges; pings go on, registrations stop */
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, 25, &s), 1);
    ck_assert_int_eq(count("PMB_REGISTER"), 7);
    for (double t = 25; t < 35; t += 0.25) {
        (void)kelp_field_nbroker_iterate(&b, t, &s);
        ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, t + 0.1, &s), 1);
    }
    ck_assert_int_eq(count("PMB_REGISTER"), 7);
    /* the shore goes away (restart): after RETRY_INTERVAL of silence the ping route is
     * registered again, and when it answers again the bridges are registered again */
    for (double t = 35; t < 50; t += 0.25) (void)kelp_field_nbroker_iterate(&b, t, &s);
    ck_assert_int_eq(count("PMB_REGISTER"), 8);
    ck_assert_str_eq(last("PMB_REGISTER"), ping_reg);
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, 50, &s), 1);
    ck_assert_int_eq(count("PMB_REGISTER"), 12);
    for (int i = 0; i < 4; i++) ck_assert_str_eq(nth("PMB_REGISTER", 8 + i), nth("PMB_REGISTER", 3 + i));
}
END_TEST

START_TEST(nb_new_shore_and_try_host_mail)
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    const char *const lines[] = { "BRIDGE", "src=NODE_REPORT_LOCAL, alias=NODE_REPORT", NULL };
    cfg_node(&c, lines);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 0, &s), 1);
    (void)kelp_field_nbroker_iterate(&b, 0, &s);
    ck_assert_int_eq(count("PMB_REGISTER"), 0); /* no try host yet */
    /* 24.8: the shore's try_vnode sends one */
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "TRY_SHORE_HOST", true, "pshare_route=198.51.100.1:9300", 1, &s), 1);
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "TRY_SHORE_HOST", true, "pshare_route=198.51.100.1:9300", 2, &s), 1);
    ck_assert_int_lt(kelp_field_nbroker_mail(&b, "TRY_SHORE_HOST", true, "pshare_route=nowhere", 2, &s), 0);
    ck_assert_int_eq(count("PMB_REGISTER"), 1);
    ck_assert_str_eq(last("PMB_REGISTER"), "src_var=NODE_BROKER_PING,dest_community=shoreside,dest_host=198.51.100.1,"
                                           "dest_port=9300,dest_alias=NODE_BROKER_PING");
    /* two shores: each gets the bridges once */
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, 3, &s), 1);
    ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true,
                                             "community=topside,host=10.0.0.9,port_udp=9300,time_warp=1", 3.1, &s),
                     1);
    ck_assert_int_eq(count("PMB_REGISTER"), 3);
    ck_assert_str_eq(last("PMB_REGISTER"), "src_var=NODE_REPORT_LOCAL,dest_community=topside,dest_host=10.0.0.9,"
                                           "dest_port=9300,dest_alias=NODE_REPORT");
}
END_TEST

START_TEST(nb_report_listing3)
{
    static kelp_field_nbroker b;
    kelp_field_nbroker_cfg c;
    const char *const lines[] = { "TRY_SHORE_HOST", "host_ip=localhost, port_udp=9200, community=topside",
                                  "BRIDGE", "src=VIEW_POLYGON", "BRIDGE", "src=VIEW_POINT", "BRIDGE", "src=VIEW_SEGLIST",
                                  "BRIDGE", "src=NODE_REPORT_LOCAL, alias=NODE_REPORT", NULL };
    cfg_node(&c, lines);
    kelp_field_nbroker_init(&b, &c);
    kelp_field_sink s = sink();
    (void)kelp_field_nbroker_iterate(&b, 0, &s);
    for (int i = 0; i < 4; i++) ck_assert_int_eq(kelp_field_nbroker_mail(&b, "PHI_HOST_INFO", true, JAMES_PHI, 0, &s), 1);
    for (int i = 1; i < 32; i++) {
        (void)kelp_field_nbroker_iterate(&b, i * 0.25, &s);
        if (i > 5)
            ck_assert_int_eq(kelp_field_nbroker_mail(&b, "NODE_BROKER_ACK", true, SHORE_ACK, i * 0.25 + 0.1, &s), 1);
    }
    char rep[4096];
    ck_assert_int_eq(kelp_field_nbroker_report(&b, rep, sizeof rep), 0);
    ck_assert_str_eq(rep, "NodeBroker Status ----- (32)\n"
                          "Total OK PHI_HOST_INFO    received: 4\n"
                          "Total BAD PHI_HOST_INFO   received: 0\n"
                          "Total HOST_INFO changes  received: 0\n"
                          "Total PMB_REGISTER        posted: 5\n"
                          "Total NODE_BROKER_PING   posted: 31\n"
                          "Total OK NODE_BROKER_ACK received: 26\n"
                          "Total BAD NODE_BROKER_ACK received: 0\n"
                          "\n"
                          "Configuration Info:\n"
                          "  Total Valid TryHosts:   1\n"
                          "  [1]: hostip=localhost,port_udp=9200\n"
                          "  Total InValid TryHosts: 0\n"
                          "\n"
                          "Node Information: james\n"
                          "    HostIP: 10.0.0.8\n"
                          "    Port (DB): 9204\n"
                          "    Port (UDP): 9304\n"
                          "    Time Warp: 1\n"
                          "\n"
                          "Shoreside Information: shoreside\n"
                          "    HostIP: 10.0.0.8\n"
                          "    Port (DB): 9000\n"
                          "    Port (UDP): 9200\n"
                          "    Time Warp: 1\n");
    char small[64];
    ck_assert_int_eq(kelp_field_nbroker_report(&b, small, sizeof small), KELP_ERR_NOSPACE);
    ck_assert_uint_eq(strlen(small), sizeof small - 1);
}
END_TEST

START_TEST(nb_auto_bridges_and_bools)
{
    kelp_field_nbroker_cfg c;
    kelp_field_nbroker_cfg_seed(&c);
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_nbroker_config(&c, "auto_bridge_realmcast", "true  (default)", &why), 1);
    ck_assert_int_eq(kelp_field_nbroker_config(&c, "AUTO_BRIDGE_APPCAST", "false", &why), 1);
    ck_assert_int_lt(kelp_field_nbroker_config(&c, "AUTO_BRIDGE_APPCAST", "maybe", &why), 0);
    ck_assert_int_lt(kelp_field_nbroker_config(&c, "BRIDGE", "alias=X", &why), 0);
    ck_assert_int_lt(kelp_field_nbroker_config(&c, "KEYWORD", "two words", &why), 0);
    ck_assert_int_eq(kelp_field_nbroker_config(&c, "TEMP_FILE_DIR", "./", &why), 0);
    static kelp_field_nbroker b;
    kelp_field_nbroker_init(&b, &c);
    ck_assert_uint_eq(b.cfg.nbridges, 3);
    ck_assert_str_eq(b.cfg.bridge[0].src, "REALMCAST");
    ck_assert_str_eq(b.cfg.bridge[2].src, "REALMCAST_CHANNELS");
}
END_TEST

/* ---------------------------------------------------------------- uFldShoreBroker (3.6) */

#define SHORE_PHI "community=shoreside,hostip=10.0.0.8,port_db=9000,port_udp=9200,timewarp=1"

static void shore(kelp_field_sbroker *sb, double warp, const char *const *lines, const kelp_field_sink *s)
{
    kelp_field_sbroker_cfg c;
    kelp_field_sbroker_cfg_seed(&c);
    c.warp = warp;
    for (; lines && *lines; lines += 2) {
        kelp_diag why = { 0 };
        ck_assert_int_eq(kelp_field_sbroker_config(&c, lines[0], lines[1], &why), 1);
    }
    kelp_field_sbroker_init(sb, &c);
    char phi[128];
    snprintf(phi, sizeof phi, "community=shoreside,hostip=10.0.0.8,port_db=9000,port_udp=9200,timewarp=%g", warp);
    ck_assert_int_eq(kelp_field_sbroker_mail(sb, "PHI_HOST_INFO", true, phi, 0, s), 1);
}

static int ping(kelp_field_sbroker *sb, const char *name, const char *ip, const char *extra, double warp, double now,
                const kelp_field_sink *s)
{
    char p[256];
    snprintf(p, sizeof p, "community=%s,host=%s,port=9000,port_udp=9200%s,time_warp=%g,time=%.2f", name, ip, extra,
             warp, now - 0.5);
    return kelp_field_sbroker_mail(sb, "NODE_BROKER_PING", true, p, now, s);
}

/* the PMB_REGISTER posts whose src_var starts with prefix, in order, joined by '\n' */
static const char *regs(const char *prefix, char *buf, size_t cap)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; i < R.n; i++) {
        if (strcmp(R.var[i], "PMB_REGISTER") != 0) continue;
        if (strncmp(R.val[i] + 8, prefix, strlen(prefix)) != 0) continue;
        n += (size_t)snprintf(buf + n, cap - n, "%s\n", R.val[i]);
    }
    return buf;
}

START_TEST(sb_qbridge_list) /* 3.6.1 */
{
    kelp_field_sbroker_cfg c;
    kelp_field_sbroker_cfg_seed(&c);
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_sbroker_config(&c, "QBRIDGE", "DEPLOY, RETURN", &why), 1);
    ck_assert_uint_eq(c.nbridges, 4);
    const char *want[4][2] = { { "DEPLOY_ALL", "DEPLOY" }, { "DEPLOY_$V", "DEPLOY" }, { "RETURN_ALL", "RETURN" },
                               { "RETURN_$V", "RETURN" } };
    for (int i = 0; i < 4; i++) {
        ck_assert_str_eq(c.bridge[i].src, want[i][0]);
        ck_assert_str_eq(c.bridge[i].alias, want[i][1]);
    }
    /* the same bridge again is not listed twice; a name with '=' is refused */
    ck_assert_int_eq(kelp_field_sbroker_config(&c, "BRIDGE", "src=DEPLOY_ALL, alias=DEPLOY", &why), 1);
    ck_assert_uint_eq(c.nbridges, 4);
    ck_assert_int_lt(kelp_field_sbroker_config(&c, "QBRIDGE", "src=FOO", &why), 0);
    ck_assert_int_lt(kelp_field_sbroker_config(&c, "QBRIDGE", "", &why), 0);
}
END_TEST

START_TEST(sb_bridge_each_vehicle) /* 3.6.2 */
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    const char *const lines[] = { "BRIDGE", "src=DEPLOY_ALL, alias=DEPLOY", NULL };
    shore(&sb, 1, lines, &s);
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 10, &s), 1);
    ck_assert_int_eq(ping(&sb, "james", "2.56.111.3", "", 1, 10, &s), 1);
    ck_assert_int_eq(ping(&sb, "ike", "2.56.111.4", "", 1, 10, &s), 1);
    char buf[2048];
    ck_assert_str_eq(regs("DEPLOY", buf, sizeof buf),
                     "src_var=DEPLOY_ALL,dest_community=henry,dest_host=2.56.111.1,dest_port=9200,dest_alias=DEPLOY\n"
                     "src_var=DEPLOY_ALL,dest_community=james,dest_host=2.56.111.3,dest_port=9200,dest_alias=DEPLOY\n"
                     "src_var=DEPLOY_ALL,dest_community=ike,dest_host=2.56.111.4,dest_port=9200,dest_alias=DEPLOY\n");
}
END_TEST

START_TEST(sb_macros) /* 3.6.3, 3.6.5, 3.6.6 */
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    const char *const lines[] = { "BRIDGE", "src=DEPLOY_$V, alias=DEPLOY", "BRIDGE", "src=X, alias=DEPLOY_$V",
                                  "BRIDGE", "src=GO_$v, alias=GO", NULL };
    shore(&sb, 1, lines, &s);
    ck_assert_int_eq(ping(&sb, "gilda", "2.56.111.9", "", 1, 10, &s), 1);
    char buf[2048];
    ck_assert_str_eq(regs("DEPLOY", buf, sizeof buf),
                     "src_var=DEPLOY_GILDA,dest_community=gilda,dest_host=2.56.111.9,dest_port=9200,dest_alias=DEPLOY\n");
    ck_assert_str_eq(regs("X,", buf, sizeof buf),
                     "src_var=X,dest_community=gilda,dest_host=2.56.111.9,dest_port=9200,dest_alias=DEPLOY_$V\n");
    ck_assert_str_eq(regs("GO", buf, sizeof buf),
                     "src_var=GO_gilda,dest_community=gilda,dest_host=2.56.111.9,dest_port=9200,dest_alias=GO\n");
}
END_TEST

START_TEST(sb_macro_n) /* 3.6.4 */
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    const char *const lines[] = { "BRIDGE", "src=LOITER_$N, alias=LOITER", NULL };
    shore(&sb, 1, lines, &s);
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 10, &s), 1);
    ck_assert_int_eq(ping(&sb, "james", "2.56.111.3", "", 1, 11, &s), 1);
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 12, &s), 1);
    ck_assert_int_eq(ping(&sb, "ike", "2.56.111.4", "", 1, 13, &s), 1);
    char buf[2048];
    ck_assert_str_eq(regs("LOITER", buf, sizeof buf),
                     "src_var=LOITER_1,dest_community=henry,dest_host=2.56.111.1,dest_port=9200,dest_alias=LOITER\n"
                     "src_var=LOITER_2,dest_community=james,dest_host=2.56.111.3,dest_port=9200,dest_alias=LOITER\n"
                     "src_var=LOITER_3,dest_community=ike,dest_host=2.56.111.4,dest_port=9200,dest_alias=LOITER\n");
}
END_TEST

/* MOOS-IvP 24.8 ShoreBroker.cpp (postQBridgeSet, postBridgeSet): UFSB_QBRIDGE_VARS, the
 * QBRIDGE names sorted, once at start; UFSB_BRIDGE_VARS, the sorted set of bridged sources (the
 * BRIDGE lines' src as written, NODE_BROKER_ACK_$V, and every name expanded for a vehicle),
 * whenever it grows */
START_TEST(sb_bridge_var_sets)
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    const char *const lines[] = { "QBRIDGE", "RETURN",   "BRIDGE", "src=DEPLOY_$V, alias=DEPLOY",
                                  "QBRIDGE", "NODE_REPORT, STATION_KEEP", "BRIDGE", "src=UP_LOITER_$N, alias=UP_LOITER",
                                  NULL };
    shore(&sb, 1, lines, &s);
    (void)kelp_field_sbroker_iterate(&sb, 1, &s);
    ck_assert_int_eq(count("UFSB_QBRIDGE_VARS"), 1);
    ck_assert_str_eq(last("UFSB_QBRIDGE_VARS"), "NODE_REPORT,RETURN,STATION_KEEP");
    (void)kelp_field_sbroker_iterate(&sb, 2, &s);
    ck_assert_int_eq(count("UFSB_QBRIDGE_VARS"), 1);
    ck_assert_int_eq(count("UFSB_BRIDGE_VARS"), 0);
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 10, &s), 1);
    ck_assert_str_eq(last("UFSB_BRIDGE_VARS"),
                     "DEPLOY_$V,DEPLOY_HENRY,NODE_BROKER_ACK_$V,NODE_BROKER_ACK_HENRY,NODE_REPORT_ALL,"
                     "NODE_REPORT_HENRY,RETURN_ALL,RETURN_HENRY,STATION_KEEP_ALL,STATION_KEEP_HENRY,UP_LOITER_$N,"
                     "UP_LOITER_1");
    int n = count("UFSB_BRIDGE_VARS");
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 11, &s), 1);
    ck_assert_int_eq(count("UFSB_BRIDGE_VARS"), n);
    ck_assert_int_eq(ping(&sb, "abe", "2.56.111.2", "", 1, 12, &s), 1);
    ck_assert_int_eq(count("UFSB_BRIDGE_VARS"), n + 1);
    ck_assert_str_eq(last("UFSB_BRIDGE_VARS"),
                     "DEPLOY_$V,DEPLOY_ABE,DEPLOY_HENRY,NODE_BROKER_ACK_$V,NODE_BROKER_ACK_ABE,NODE_BROKER_ACK_HENRY,"
                     "NODE_REPORT_ABE,NODE_REPORT_ALL,NODE_REPORT_HENRY,RETURN_ABE,RETURN_ALL,RETURN_HENRY,"
                     "STATION_KEEP_ABE,STATION_KEEP_ALL,STATION_KEEP_HENRY,UP_LOITER_$N,UP_LOITER_1,UP_LOITER_2");
}
END_TEST

START_TEST(sb_repeat_pings_once) /* 3.6.7 */
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    const char *const lines[] = { "QBRIDGE", "DEPLOY", NULL };
    shore(&sb, 1, lines, &s);
    for (int i = 0; i < 6; i++) ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 10 + i, &s), 1);
    ck_assert_int_eq(count("PMB_REGISTER"), 3);
    ck_assert_str_eq(nth("PMB_REGISTER", 0), "src_var=NODE_BROKER_ACK_HENRY,dest_community=henry,dest_host=2.56.111.1,"
                                             "dest_port=9200,dest_alias=NODE_BROKER_ACK");
    ck_assert_str_eq(nth("PMB_REGISTER", 2), "src_var=DEPLOY_HENRY,dest_community=henry,dest_host=2.56.111.1,"
                                             "dest_port=9200,dest_alias=DEPLOY");
    ck_assert_int_eq(count("NODE_BROKER_ACK_HENRY"), 6);
    ck_assert_int_eq(count("NODE_BROKER_VACK"), 6);
    ck_assert_str_eq(last("NODE_BROKER_ACK_HENRY"),
                     "community=shoreside,host=10.0.0.8,port=9000,port_udp=9200,time_warp=1,time=15,status=ok");
    ck_assert_uint_eq(sb.acks, 6);
    ck_assert_uint_eq(sb.pings, 6);
}
END_TEST

START_TEST(sb_timewarp_rejected) /* 3.6.8 */
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    const char *const lines[] = { "BRIDGE", "src=LOITER_$N, alias=LOITER", NULL };
    shore(&sb, 10, lines, &s);
    ck_assert_int_eq(ping(&sb, "gilda", "18.3.224.246", "", 1, 10, &s), 1);
    ck_assert_str_eq(sb.node[0].status, "timewarp (10!=1)");
    ck_assert_int_eq(R.n, 0); /* no ack, no registration */
    ck_assert_int_eq(ping(&sb, "henry", "18.12.14.26", "", 10, 11, &s), 1);
    char buf[1024];
    ck_assert_str_eq(regs("LOITER", buf, sizeof buf),
                     "src_var=LOITER_1,dest_community=henry,dest_host=18.12.14.26,dest_port=9200,dest_alias=LOITER\n");
    ck_assert_uint_eq(sb.node[0].index, 0);
}
END_TEST

START_TEST(sb_keyword) /* 3.6.9, 3.6.10 */
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    const char *const lines[] = { "KEYWORD", "lemon", NULL };
    shore(&sb, 1, lines, &s);
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 10, &s), 1);
    ck_assert_str_eq(sb.node[0].status, "keyword");
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", ",keyword=apple", 1, 11, &s), 1);
    ck_assert_str_eq(sb.node[0].status, "keyword");
    ck_assert_int_eq(R.n, 0);
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", ",keyword=lemon", 1, 12, &s), 1);
    ck_assert_str_eq(sb.node[0].status, "ok");
    ck_assert_int_eq(count("NODE_BROKER_ACK_HENRY"), 1);
    ck_assert_ptr_nonnull(strstr(last("NODE_BROKER_ACK_HENRY"), ",keyword=lemon,"));
    /* no shore keyword: a vehicle's keyword is fine */
    static kelp_field_sbroker sb2;
    s = sink();
    shore(&sb2, 1, NULL, &s);
    ck_assert_int_eq(ping(&sb2, "henry", "2.56.111.1", ",keyword=lemon", 1, 12, &s), 1);
    ck_assert_str_eq(sb2.node[0].status, "ok");
    ck_assert_int_eq(count("NODE_BROKER_ACK_HENRY"), 1);
}
END_TEST

START_TEST(sb_skew_and_report) /* 3.6.11, Listing 6 */
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    shore(&sb, 10, NULL, &s);
    /* in time order (a time before the newest seen is a clock step back: docs/ARCHITECTURE.md) */
    ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true,
                                             "community=gilda,host=18.3.224.246,port=9000,port_udp=9200,time_warp=1,time=990",
                                             994.7, &s),
                     1);
    ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true,
                                             "community=henry,host=18.12.14.26,port=9000,port_udp=9200,time_warp=10,time=1000.0",
                                             1000.6673, &s),
                     1);
    (void)kelp_field_sbroker_iterate(&sb, 1001.6673, &s);
    char rep[4096];
    ck_assert_int_eq(kelp_field_sbroker_report(&sb, 1001.6673, rep, sizeof rep), 0);
    ck_assert_ptr_nonnull(strstr(rep, "ShoreBroker Status ----- (1)\nMOOS Time Warp:          10\n"
                                      "Total PHI_HOST_INFO    received: 1\nTotal NODE_BROKER_PING received: 2\n"
                                      "Total NODE_BROKER_ACK    posted: 1\nTotal PMB_REGISTER      posted: 1\n"));
    ck_assert_ptr_nonnull(strstr(rep, "henry         18.12.14.26  ok         1.0      0.6673\n"));
    ck_assert_ptr_nonnull(strstr(rep, "gilda         18.3.224.246 timewarp (10!=1) 7.0      4.7000\n"));
}
END_TEST

START_TEST(sb_waits_for_own_host_info)
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    kelp_field_sbroker_cfg c;
    kelp_field_sbroker_cfg_seed(&c);
    kelp_field_sbroker_init(&sb, &c);
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 10, &s), 1);
    ck_assert_int_lt(kelp_field_sbroker_mail(&sb, "PHI_HOST_INFO", true, "community=shoreside,hostip=10.0.0.8", 10, &s), 0);
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 10, &s), 1);
    ck_assert_uint_eq(sb.early_pings, 2);
    ck_assert_uint_eq(sb.nnodes, 0);
    ck_assert_int_eq(count("PMB_REGISTER") + count("NODE_BROKER_ACK_HENRY"), 0);
    ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "PHI_HOST_INFO", true, SHORE_PHI, 11, &s), 1);
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 12, &s), 1);
    ck_assert_int_eq(count("NODE_BROKER_ACK_HENRY"), 1);
    /* a malformed or incomplete ping is counted, never acked */
    ck_assert_int_lt(kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true, "community=x,host=1.2.3.4", 13, &s), 0);
    ck_assert_int_lt(kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true, "host=1.2.3.4,port_udp=9", 13, &s), 0);
    ck_assert_int_lt(kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", false, NULL, 13, &s), 0);
    ck_assert_uint_eq(sb.bad_pings, 3);
    ck_assert_int_eq(count("NODE_BROKER_ACK_X"), 0);
    ck_assert_str_eq(sb.node[1].status, "invalid");
}
END_TEST

/* a shore restart: a fresh broker seeing the same vehicles registers exactly the same
 * bridges, once each; a vehicle that moves gets them again at its new address */
START_TEST(sb_restart_idempotent)
{
    static kelp_field_sbroker a, b;
    const char *const lines[] = { "QBRIDGE", "DEPLOY, RETURN", "BRIDGE", "src=LOITER_$N, alias=LOITER", NULL };
    kelp_field_sink s = sink();
    shore(&a, 1, lines, &s);
    for (int i = 0; i < 5; i++) {
        ck_assert_int_eq(ping(&a, "alpha", "198.51.100.2", "", 1, 10 + i, &s), 1);
        ck_assert_int_eq(ping(&a, "bravo", "198.51.100.3", "", 1, 10 + i, &s), 1);
    }
    static char first[8192], second[8192];
    (void)regs("", first, sizeof first);
    ck_assert_int_eq(count("PMB_REGISTER"), 12); /* (ack + 5 bridges) x 2 */
    s = sink();
    shore(&b, 1, lines, &s);
    for (int i = 0; i < 7; i++) {
        ck_assert_int_eq(ping(&b, "alpha", "198.51.100.2", "", 1, 100 + i, &s), 1);
        ck_assert_int_eq(ping(&b, "bravo", "198.51.100.3", "", 1, 100 + i, &s), 1);
    }
    (void)regs("", second, sizeof second);
    ck_assert_str_eq(first, second);
    for (int i = 0; i < R.n; i++)
        for (int j = i + 1; j < R.n; j++)
            if (!strcmp(R.var[i], "PMB_REGISTER") && !strcmp(R.var[j], "PMB_REGISTER"))
                ck_assert_str_ne(R.val[i], R.val[j]);
    /* alpha comes back from another address: registered again there, same $N */
    ck_assert_int_eq(ping(&b, "alpha", "198.51.100.9", "", 1, 120, &s), 1);
    ck_assert_int_eq(count("PMB_REGISTER"), 18);
    ck_assert_str_eq(last("PMB_REGISTER"), "src_var=LOITER_1,dest_community=alpha,dest_host=198.51.100.9,"
                                           "dest_port=9200,dest_alias=LOITER");
}
END_TEST

START_TEST(sb_many_vehicles)
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    const char *const lines[] = { "BRIDGE", "src=LOITER_$N, alias=LOITER", NULL };
    shore(&sb, 1, lines, &s);
    for (int i = 0; i < KELP_BROKER_MAX_NODES; i++) {
        char name[16], ip[32];
        snprintf(name, sizeof name, "v%02d", i);
        snprintf(ip, sizeof ip, "10.1.0.%d", i + 1);
        ck_assert_int_eq(ping(&sb, name, ip, "", 1, 10, &s), 1);
    }
    ck_assert_uint_eq(sb.nnodes, KELP_BROKER_MAX_NODES);
    ck_assert_uint_eq(sb.naccepted, KELP_BROKER_MAX_NODES);
    ck_assert_uint_eq(sb.node[63].index, 64);
    ck_assert_str_eq(last("PMB_REGISTER"), "src_var=LOITER_64,dest_community=v63,dest_host=10.1.0.64,dest_port=9200,"
                                           "dest_alias=LOITER");
    ck_assert_str_eq(nth("NODE_BROKER_VACK", 17), "v17");
    ck_assert_int_lt(ping(&sb, "one_too_many", "10.1.1.1", "", 1, 10, &s), 0);
    ck_assert_uint_eq(sb.full, 1);
    ck_assert_int_eq(R.warns, 1);
    /* names compare case-insensitively: V05 is v05 */
    ck_assert_int_eq(ping(&sb, "V05", "10.1.0.6", "", 1, 11, &s), 1);
    ck_assert_uint_eq(sb.nnodes, KELP_BROKER_MAX_NODES);
    ck_assert_str_eq(last("NODE_BROKER_VACK"), "V05");
    /* UFSB_NODE_COUNT on change (and UFSB_QBRIDGE_VARS at the first iteration) */
    ck_assert_int_eq(kelp_field_sbroker_iterate(&sb, 12, &s), 2);
    ck_assert_str_eq(last("UFSB_NODE_COUNT"), "64");
    ck_assert_int_eq(kelp_field_sbroker_iterate(&sb, 13, &s), 0);
}
END_TEST

START_TEST(sb_try_vnode_and_stale)
{
    static kelp_field_sbroker sb;
    kelp_field_sink s = sink();
    const char *const lines[] = { "TRY_VNODE", "192.168.4.24:9201", "TRY_VNODE", "route=192.168.4.25",
                                  "WARNING_ON_STALE", "true", NULL };
    shore(&sb, 1, lines, &s);
    kelp_diag why = { 0 };
    ck_assert_int_lt(kelp_field_sbroker_config(&sb.cfg, "TRY_VNODE", "192.168.4.24:9201", &why), 0);
    ck_assert_int_eq(ping(&sb, "henry", "2.56.111.1", "", 1, 10, &s), 1);
    R.n = 0;
    ck_assert_int_eq(kelp_field_sbroker_iterate(&sb, 10, &s), 5); /* with UFSB_QBRIDGE_VARS */
    ck_assert_str_eq(nth("PMB_REGISTER", 0), "src_var=TRY_SHORE_HOST,dest_host=192.168.4.24,dest_port=9201,"
                                             "dest_alias=TRY_SHORE_HOST");
    ck_assert_str_eq(nth("PMB_REGISTER", 1), "src_var=TRY_SHORE_HOST,dest_host=192.168.4.25,dest_port=9200,"
                                             "dest_alias=TRY_SHORE_HOST");
    ck_assert_str_eq(last("TRY_SHORE_HOST"), "pshare_route=10.0.0.8:9200");
    ck_assert_int_eq(kelp_field_sbroker_iterate(&sb, 15, &s), 0);
    ck_assert_int_eq(R.warns, 0);
    ck_assert_int_eq(kelp_field_sbroker_iterate(&sb, 20.5, &s), 1); /* TRY_SHORE_HOST again; henry stale */
    ck_assert_int_eq(R.warns, 1);
    ck_assert_int_eq(kelp_field_sbroker_iterate(&sb, 21, &s), 0);
    ck_assert_int_eq(R.warns, 1);
}
END_TEST

/* the whole handshake, node and shore cores joined by a fake pair of bridges */
START_TEST(handshake_node_and_shore)
{
    static kelp_field_nbroker nb;
    static kelp_field_sbroker sb;
    kelp_field_nbroker_cfg c;
    cfg_node(&c, listing2);
    c.warp = 4;
    kelp_field_nbroker_init(&nb, &c);
    kelp_field_sink s = sink();
    const char *const lines[] = { "KEYWORD", "lemon", "QBRIDGE", "DEPLOY", NULL };
    shore(&sb, 4, lines, &s);
    ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "PHI_HOST_INFO", true,
                                             "community=james,hostip=10.0.0.7,port_db=9204,port_udp=9304,timewarp=4", 0, &s),
                     1);
    for (double t = 0; t < 3; t += 0.25) {
        R.n = 0;
        (void)kelp_field_nbroker_iterate(&nb, t, &s);
        ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true, last("NODE_BROKER_PING"), t + 0.05, &s),
                         1);
        ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "NODE_BROKER_ACK", true, last("NODE_BROKER_ACK_JAMES"), t + 0.1, &s),
                         1);
    }
    ck_assert_uint_eq(nb.ok_ack, 12);
    ck_assert_uint_eq(nb.bad_ack, 0);
    ck_assert_uint_eq(nb.registers, 5);
    ck_assert_str_eq(nb.shore.host, "10.0.0.8");
    ck_assert_uint_eq(sb.registers, 3);
    ck_assert_str_eq(sb.last_register, "src_var=DEPLOY_JAMES,dest_community=james,dest_host=10.0.0.7,dest_port=9304,"
                                       "dest_alias=DEPLOY");
    ck_assert_str_eq(nb.last_register, "src_var=NODE_REPORT_LOCAL,dest_community=shoreside,dest_host=10.0.0.8,"
                                       "dest_port=9200,dest_alias=NODE_REPORT");
}
END_TEST


/* ================================================================ MOOS-IvP 24.8's model
 * (NodeBroker.cpp, ShoreBroker.cpp, HostRecord.cpp of 24.8; the default configuration) */

#define ALPHA_PHI "community=alpha,hostip=10.0.0.2,port_db=9001,port_udp=9201,pshare_iroutes=10.0.0.2:9201,hostip_alts=,timewarp=2"
#define SHORE24_PHI "community=shoreside,hostip=10.0.0.1,port_db=9000,port_udp=9300,pshare_iroutes=10.0.0.1:9300,hostip_alts=,timewarp=2"

static void node24(kelp_field_nbroker *nb, const char *const *lines)
{
    kelp_field_nbroker_cfg c;
    kelp_field_nbroker_cfg_default(&c);
    c.warp = 2;
    for (; *lines; lines += 2) {
        kelp_diag why = { 0 };
        ck_assert_int_eq(kelp_field_nbroker_config(&c, lines[0], lines[1], &why), 1);
    }
    kelp_field_nbroker_init(nb, &c);
}

static void shore24(kelp_field_sbroker *sb, const char *const *lines)
{
    kelp_field_sbroker_cfg c;
    kelp_field_sbroker_cfg_default(&c);
    c.warp = 2;
    for (; lines && *lines; lines += 2) {
        kelp_diag why = { 0 };
        ck_assert_int_eq(kelp_field_sbroker_config(&c, lines[0], lines[1], &why), 1);
    }
    kelp_field_sbroker_init(sb, &c);
}

START_TEST(hr24_spec_order)
{
    /* HostRecord::getSpec: community, hostip, port_db, port_udp, pshare_iroutes, keyword,
     * hostip_alts (own address out), timewarp, time, key */
    kelp_field_broker_host h;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_broker_host_parse("timewarp=2,hostip_alts=10.0.0.2,10.9.9.9,community=alpha,"
                                            "pshare_iroutes=10.0.0.2:9201,port_db=9001,hostip=10.0.0.2,keyword=lemon",
                                            &h, &why),
                     0);
    ck_assert(kelp_field_broker_host_valid(&h));
    ck_assert(h.have_port_udp && h.port_udp == 9201); /* a single route gives port_udp */
    char buf[512];
    ck_assert_int_eq(kelp_field_broker_host_spec(&h, "100.00", "0", buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "community=alpha,hostip=10.0.0.2,port_db=9001,port_udp=9201,pshare_iroutes=10.0.0.2:9201,"
                          "keyword=lemon,hostip_alts=,timewarp=2,time=100.00,key=0");
    /* two routes: no port_udp; no port_db: not valid */
    ck_assert_int_eq(kelp_field_broker_host_parse("community=a,hostip=localhost,pshare_iroutes=10.0.0.2:9201&multicast_8", &h, &why), 0);
    ck_assert(!h.have_port_udp);
    ck_assert(!kelp_field_broker_host_valid(&h));
    ck_assert_int_eq(kelp_field_broker_host_parse("community=a,hostip=host.example,port_db=9000", &h, &why), 0);
    ck_assert(!kelp_field_broker_host_valid(&h)); /* hostip must be a dotted quad or localhost */
}
END_TEST

START_TEST(nb24_try_hosts)
{
    kelp_field_nbroker_cfg c;
    kelp_field_nbroker_cfg_default(&c);
    kelp_diag why = { 0 };
    ck_assert(c.auto_realmcast && c.auto_appcast && c.auto_pshare_vars && !c.pmb);
    ck_assert_int_eq(kelp_field_nbroker_config(&c, "try_shore_host", "pshare_route=localhost:9200", &why), 1);
    ck_assert_int_eq(kelp_field_nbroker_config(&c, "try_shore_host", "pshare_route=multicast_8", &why), 1);
    ck_assert_int_eq(kelp_field_nbroker_config(&c, "try_shore_host", "host_ip=10.0.0.1, port_udp=9300", &why), 1);
    ck_assert_uint_eq(c.ntry, 2);     /* 24.8 takes pshare_route= only */
    ck_assert_uint_eq(c.nbad_try, 1);
    ck_assert_int_eq(kelp_field_nbroker_config(&c, "try_shore_host", "pshare_route=localhost:9200", &why), KELP_ERR_EXISTS);
    ck_assert_str_eq(c.tryh[1].route, "multicast_8");
    static kelp_field_nbroker nb;
    kelp_field_nbroker_init(&nb, &c);
    /* the automatic bridges after the user's */
    ck_assert_uint_eq(nb.cfg.nbridges, 5);
    ck_assert_str_eq(nb.cfg.bridge[0].src, "REALMCAST");
    ck_assert_str_eq(nb.cfg.bridge[1].src, "WATCHCAST");
    ck_assert_str_eq(nb.cfg.bridge[2].src, "REALMCAST_CHANNELS");
    ck_assert_str_eq(nb.cfg.bridge[3].src, "APPCAST");
    ck_assert_str_eq(nb.cfg.bridge[4].src, "NODE_PSHARE_VARS");
}
END_TEST

START_TEST(nb24_ping_bridge_until_ack)
{
    static kelp_field_nbroker nb;
    const char *const lines[] = { "TRY_SHORE_HOST", "pshare_route=10.0.0.1:9300", "BRIDGE",
                                  "src=NODE_REPORT_LOCAL, alias=NODE_REPORT", "AUTO_BRIDGE_REALMCAST", "false",
                                  "AUTO_BRIDGE_APPCAST", "false", "AUTO_BRIDGE_PSHARE_VARS", "false", NULL };
    node24(&nb, lines);
    kelp_field_sink s = sink();
    /* no host info yet: the ping bridge, every iteration; no ping, no HOST_INFO_REQUEST */
    for (int i = 0; i < 3; i++) (void)kelp_field_nbroker_iterate(&nb, 100 + i, &s);
    ck_assert_int_eq(count("PSHARE_CMD"), 3);
    ck_assert_str_eq(nth("PSHARE_CMD", 0), "cmd=output,src_name=NODE_BROKER_PING_0,dest_name=NODE_BROKER_PING,route=10.0.0.1:9300");
    ck_assert_int_eq(count("NODE_BROKER_PING_0") + count("NODE_BROKER_PING") + count("HOST_INFO_REQUEST"), 0);
    /* PHI_HOST_INFO without pshare_iroutes: still no ping */
    ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "PHI_HOST_INFO", true, "community=alpha,hostip=10.0.0.2,port_db=9001,timewarp=2", 103, &s), 1);
    (void)kelp_field_nbroker_iterate(&nb, 103, &s);
    ck_assert_int_eq(count("NODE_BROKER_PING_0"), 0);
    ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "PHI_HOST_INFO", true, ALPHA_PHI, 104, &s), 1);
    ck_assert_uint_eq(nb.phi_changes, 2);
    (void)kelp_field_nbroker_iterate(&nb, 104, &s);
    ck_assert_str_eq(last("NODE_BROKER_PING_0"), "community=alpha,hostip=10.0.0.2,port_db=9001,port_udp=9201,"
                                                 "pshare_iroutes=10.0.0.2:9201,timewarp=2,time=104.00,key=0");
    ck_assert_int_eq(count("PSHARE_CMD"), 5);
    /* the shore's ack (key 0): the user's bridge to that route, NODE_PSHARE_VARS; the ping
     * bridge is not posted again */
    ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "NODE_BROKER_ACK", true,
                                             "community=shoreside,hostip=10.0.0.1,port_db=9000,port_udp=9300,"
                                             "pshare_iroutes=10.0.0.1:9300,timewarp=2,status=ok,key=0,id=7", 104.5, &s), 1);
    ck_assert_str_eq(last("PSHARE_CMD"), "cmd=output,src_name=NODE_REPORT_LOCAL,dest_name=NODE_REPORT,route=10.0.0.1:9300");
    ck_assert_str_eq(last("NODE_PSHARE_VARS"), "NODE_REPORT");
    int cmds = count("PSHARE_CMD");
    (void)kelp_field_nbroker_iterate(&nb, 105, &s);
    ck_assert_int_eq(count("PSHARE_CMD"), cmds);
    ck_assert_str_eq(nb.sh[0].community, "shoreside");
    ck_assert_uint_eq(nb.sh[0].acks, 1);
    /* a bad key, no key: a bad ack */
    ck_assert_int_lt(kelp_field_nbroker_mail(&nb, "NODE_BROKER_ACK", true,
                                             "community=shoreside,hostip=10.0.0.1,port_db=9000,status=ok,key=4", 106, &s), 0);
    ck_assert_int_lt(kelp_field_nbroker_mail(&nb, "NODE_BROKER_ACK", true, "community=shoreside,hostip=10.0.0.1,port_db=9000", 106, &s), 0);
    ck_assert_uint_eq(nb.bad_ack, 2);
}
END_TEST

START_TEST(nb24_ping_cadence)
{
    /* pings every 5 s without acks; while acks come (the shore acks for 10 s after a ping)
     * every 20 s, so with a live shore one ping per 15 s */
    static kelp_field_nbroker nb;
    const char *const lines[] = { "TRY_SHORE_HOST", "pshare_route=10.0.0.1:9300", "TRY_SHORE_HOST",
                                  "pshare_route=10.0.0.9:9300", NULL };
    node24(&nb, lines);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "PHI_HOST_INFO", true, ALPHA_PHI, 0, &s), 1);
    double pings[16];
    int np = 0;
    double last_ping = -100;
    for (double t = 0; t < 40; t += 0.25) {
        int before = count("NODE_BROKER_PING_0");
        (void)kelp_field_nbroker_iterate(&nb, t, &s);
        if (count("NODE_BROKER_PING_0") > before && np < 16) pings[np++] = t, last_ping = t;
        if (t - last_ping < 10) /* the shore acks each iteration while the ping is fresh */
            ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "NODE_BROKER_ACK", true,
                                                     "community=shoreside,hostip=10.0.0.1,port_db=9000,timewarp=2,"
                                                     "status=ok,key=0", t, &s), 1);
    }
    ck_assert_int_eq(count("NODE_BROKER_PING_1"), 0); /* one clock for all routes (24.8) */
    ck_assert_int_eq(np, 3);
    ck_assert(pings[0] == 0);
    ck_assert(pings[1] > 14.9 && pings[1] < 15.3);
    ck_assert(pings[2] > 29.9 && pings[2] < 30.6);
    /* no acks: every 5 s */
    np = count("NODE_BROKER_PING_0");
    for (double t = 40; t < 60; t += 0.25) (void)kelp_field_nbroker_iterate(&nb, t, &s);
    ck_assert_int_ge(count("NODE_BROKER_PING_0") - np, 3);
    ck_assert_int_le(count("NODE_BROKER_PING_0") - np, 4);
}
END_TEST

START_TEST(nb24_report)
{
    static kelp_field_nbroker nb;
    const char *const lines[] = { "TRY_SHORE_HOST", "pshare_route=10.0.0.1:9300", NULL };
    node24(&nb, lines);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "PHI_HOST_INFO", true, ALPHA_PHI, 0, &s), 1);
    (void)kelp_field_nbroker_iterate(&nb, 1, &s);
    static char rep[8192];
    ck_assert_int_eq(kelp_field_nbroker_report(&nb, rep, sizeof rep), 0);
    ck_assert_ptr_nonnull(strstr(rep, "  Total OK  PHI_HOST_INFO    received: 1\n"));
    ck_assert_ptr_nonnull(strstr(rep, "  Total          PSHARE_CMD    posted: 1\n"));
    ck_assert_ptr_nonnull(strstr(rep, "     Community: alpha\n        HostIP: 10.0.0.2\n   Port MOOSDB: 9001\n     Time Warp: 2\n   TryHost IPs: 10.0.0.1\n      IRoutes: 10.0.0.2:9201\n"));
    ck_assert_ptr_nonnull(strstr(rep, "Community                 Pings  Pings  IP       Time\n"
                                      "Name       Route          Sent   Acked  Address  Warp\n"
                                      "---------  -------------  -----  -----  -------  ----\n"
                                      "           10.0.0.1:9300  1      0\n\nPhase Completion Summary:"));
    ck_assert_ptr_nonnull(strstr(rep, " Phase 3: (Y) NODE_BROKER_PINGS are being sent to TryHosts.\n Phase 4: (N)"));
    ck_assert_ptr_nonnull(strstr(rep, "*Hint: Phase 4 problem."));
}
END_TEST

START_TEST(sb24_acks_every_iteration_while_fresh)
{
    static kelp_field_sbroker sb;
    const char *const lines[] = { "QBRIDGE", "DEPLOY", NULL };
    shore24(&sb, lines);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "PHI_HOST_INFO", true, SHORE24_PHI, 0, &s), 1);
    ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true,
                                             "community=alpha,hostip=10.0.0.2,port_db=9001,port_udp=9201,"
                                             "pshare_iroutes=10.0.0.2:9201,timewarp=2,time=0.50,key=0", 1, &s), 1);
    for (double t = 1; t < 14; t += 0.5) (void)kelp_field_sbroker_iterate(&sb, t, &s);
    /* t = 1 .. 10.5 (younger than last ping + 10 s): 20 acks, ids counting iterations */
    ck_assert_int_eq(count("NODE_BROKER_ACK_ALPHA"), 20);
    ck_assert_int_eq(count("NODE_BROKER_VACK"), 20);
    ck_assert_str_eq(nth("NODE_BROKER_ACK_ALPHA", 0), "community=shoreside,hostip=10.0.0.1,port_db=9000,port_udp=9300,"
                                                      "pshare_iroutes=10.0.0.1:9300,timewarp=2,status=ok,key=0,id=0");
    ck_assert_ptr_nonnull(strstr(nth("NODE_BROKER_ACK_ALPHA", 3), ",id=3"));
    ck_assert_uint_eq(sb.acks, 26); /* one per iteration with our own record */
    ck_assert_str_eq(last("NODE_BROKER_VACK"), "alpha");
    ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true,
                                             "community=bravo,hostip=10.0.0.3,port_db=9002,pshare_iroutes=10.0.0.3:9202,"
                                             "timewarp=4,time=14.00,key=0", 14, &s), 1);
    ck_assert_str_eq(sb.node[1].status, "timewarp (2!=4)");
}
END_TEST

START_TEST(sb24_bridge_requests)
{
    static kelp_field_sbroker sb;
    const char *const lines[] = { "QBRIDGE", "DEPLOY", "BRIDGE", "src=RETURN_$V, alias=RETURN", NULL };
    shore24(&sb, lines);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "PHI_HOST_INFO", true, SHORE24_PHI, 0, &s), 1);
    (void)kelp_field_sbroker_iterate(&sb, 0, &s); /* a pass with no vehicle: the gap grows to 8 */
    ck_assert_str_eq(last("UFSB_QBRIDGE_VARS"), "APPCAST_REQ,DEPLOY,REALMCAST_REQ");
    ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "PSHARE_OUTPUT_SUMMARY", true,
                                             "DEPLOY_ALL->DEPLOY:10.0.0.2:9201, X->Y:1.2.3.4:5", 0.5, &s), 1);
    ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true,
                                             "community=alpha,hostip=10.0.0.2,port_db=9001,port_udp=9201,"
                                             "pshare_iroutes=10.0.0.2:9201,timewarp=2,time=0.50,key=0", 1, &s), 1);
    for (double t = 1; t < 4.9; t += 0.5) (void)kelp_field_sbroker_iterate(&sb, t, &s);
    ck_assert_int_eq(count("PSHARE_CMD"), 0); /* the next pass 5 s after the last one */
    (void)kelp_field_sbroker_iterate(&sb, 5, &s);
    /* config order, the automatic ones, then the ack bridge; DEPLOY_ALL is shared already */
    static const char *const want[] = {
        "cmd=output,src_name=DEPLOY_ALPHA,dest_name=DEPLOY,route=10.0.0.2:9201",
        "cmd=output,src_name=RETURN_ALPHA,dest_name=RETURN,route=10.0.0.2:9201",
        "cmd=output,src_name=REALMCAST_REQ_ALL,dest_name=REALMCAST_REQ,route=10.0.0.2:9201",
        "cmd=output,src_name=REALMCAST_REQ_ALPHA,dest_name=REALMCAST_REQ,route=10.0.0.2:9201",
        "cmd=output,src_name=APPCAST_REQ_ALL,dest_name=APPCAST_REQ,route=10.0.0.2:9201",
        "cmd=output,src_name=APPCAST_REQ_ALPHA,dest_name=APPCAST_REQ,route=10.0.0.2:9201",
        "cmd=output,src_name=MISSION_HASH,dest_name=MISSION_HASH,route=10.0.0.2:9201",
        "cmd=output,src_name=NODE_BROKER_ACK_ALPHA,dest_name=NODE_BROKER_ACK,route=10.0.0.2:9201" };
    ck_assert_int_eq(count("PSHARE_CMD"), 8);
    for (int i = 0; i < 8; i++) ck_assert_str_eq(nth("PSHARE_CMD", i), want[i]);
    ck_assert_int_eq(count("PSHARE_TEST"), 27);
    ck_assert_str_eq(nth("PSHARE_TEST", 1), "DEPLOY_ALL->DEPLOY:10.0.0.2:9201");
    ck_assert_str_eq(nth("PSHARE_TEST", 2), "needed=false");
    ck_assert_str_eq(last("UFSB_BRIDGE_VARS"),
                     "APPCAST_REQ_ALL,APPCAST_REQ_ALPHA,DEPLOY_ALL,DEPLOY_ALPHA,MISSION_HASH,NODE_BROKER_ACK_$V,"
                     "NODE_BROKER_ACK_ALPHA,REALMCAST_REQ_ALL,REALMCAST_REQ_ALPHA,RETURN_$V,RETURN_ALPHA");
    /* again 8 s later, then 11 s */
    int n = count("PSHARE_CMD");
    for (double t = 5.5; t < 12.9; t += 0.5) (void)kelp_field_sbroker_iterate(&sb, t, &s);
    ck_assert_int_eq(count("PSHARE_CMD"), n);
    (void)kelp_field_sbroker_iterate(&sb, 13, &s);
    ck_assert_int_eq(count("PSHARE_CMD"), n + 8);
    ck_assert_uint_eq(sb.pshare_cmds, 18);
    static char rep[8192];
    ck_assert_int_eq(kelp_field_sbroker_report(&sb, 13, rep, sizeof rep), 0);
    ck_assert_ptr_nonnull(strstr(rep, " Total PSHARE_CMD         posted: 18\n"));
    ck_assert_ptr_nonnull(strstr(rep, "Node   IP                Elap  pShare\n"
                                      "Name   Address   Status  Time  Input Route(s)  Skew\n"
                                      "-----  --------  ------  ----  --------------  ------\n"
                                      "alpha  10.0.0.2  ok      12.0  10.0.0.2:9201   0.5000"));
}
END_TEST

START_TEST(handshake24)
{
    static kelp_field_nbroker nb;
    static kelp_field_sbroker sb;
    const char *const nl[] = { "TRY_SHORE_HOST", "pshare_route=10.0.0.1:9300", "BRIDGE", "src=NODE_REPORT_LOCAL, alias=NODE_REPORT", NULL };
    node24(&nb, nl);
    shore24(&sb, NULL);
    kelp_field_sink s = sink();
    ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "PHI_HOST_INFO", true, ALPHA_PHI, 0, &s), 1);
    ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "PHI_HOST_INFO", true, SHORE24_PHI, 0, &s), 1);
    for (double t = 0; t < 3; t += 0.5) {
        R.n = 0;
        (void)kelp_field_nbroker_iterate(&nb, t, &s);
        if (last("NODE_BROKER_PING_0"))
            ck_assert_int_eq(kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true, last("NODE_BROKER_PING_0"), t, &s), 1);
        (void)kelp_field_sbroker_iterate(&sb, t, &s);
        if (last("NODE_BROKER_ACK_ALPHA"))
            ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "NODE_BROKER_ACK", true, last("NODE_BROKER_ACK_ALPHA"), t, &s), 1);
    }
    ck_assert_uint_eq(nb.pings, 1);
    ck_assert_uint_eq(nb.ok_ack, 6);
    ck_assert(nb.sh[0].bridged);
    ck_assert_str_eq(sb.node[0].rec.iroutes, "10.0.0.2:9201");
    ck_assert_str_eq(sb.node[0].status, "ok");
}
END_TEST

Suite *kelp_field_brokers_suite(void)
{
    Suite *s = suite_create("field_brokers");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, host_record_synonyms);
    tcase_add_test(tc, try_and_bridge_lines);
    tcase_add_test(tc, nb_valid_try_host_listed);
    tcase_add_test(tc, nb_invalid_try_host);
    tcase_add_test(tc, nb_silent_without_host_info);
    tcase_add_test(tc, nb_ping_registration_and_format);
    tcase_add_test(tc, nb_keyword_in_ping);
    tcase_add_test(tc, nb_bad_host_info);
    tcase_add_test(tc, nb_host_info_changes);
    tcase_add_test(tc, nb_bridges_after_ack);
    tcase_add_test(tc, nb_pshare_vars);
    tcase_add_test(tc, nb_bad_ack_warp);
    tcase_add_test(tc, nb_ack_keyword_and_status);
    tcase_add_test(tc, nb_retries_until_ack);
    tcase_add_test(tc, nb_new_shore_and_try_host_mail);
    tcase_add_test(tc, nb_report_listing3);
    tcase_add_test(tc, nb_auto_bridges_and_bools);
    tcase_add_test(tc, sb_qbridge_list);
    tcase_add_test(tc, sb_bridge_each_vehicle);
    tcase_add_test(tc, sb_macros);
    tcase_add_test(tc, sb_macro_n);
    tcase_add_test(tc, sb_bridge_var_sets);
    tcase_add_test(tc, sb_repeat_pings_once);
    tcase_add_test(tc, sb_timewarp_rejected);
    tcase_add_test(tc, sb_keyword);
    tcase_add_test(tc, sb_skew_and_report);
    tcase_add_test(tc, sb_waits_for_own_host_info);
    tcase_add_test(tc, sb_restart_idempotent);
    tcase_add_test(tc, sb_many_vehicles);
    tcase_add_test(tc, sb_try_vnode_and_stale);
    tcase_add_test(tc, handshake_node_and_shore);
    tcase_add_test(tc, hr24_spec_order);
    tcase_add_test(tc, nb24_try_hosts);
    tcase_add_test(tc, nb24_ping_bridge_until_ack);
    tcase_add_test(tc, nb24_ping_cadence);
    tcase_add_test(tc, nb24_report);
    tcase_add_test(tc, sb24_acks_every_iteration_while_fresh);
    tcase_add_test(tc, sb24_bridge_requests);
    tcase_add_test(tc, handshake24);
    suite_add_tcase(s, tc);
    return s;
}
