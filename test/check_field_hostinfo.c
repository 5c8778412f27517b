/* pHostInfo's state machine (src/field/hostinfo.c): ufield.md 4.6 and the rules around it. */
#include <check.h>
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>

typedef struct rec {
    int n;
    char var[16][32];
    char val[16][512];
    bool str[16];
} rec;

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    if (r->n >= 16) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    if (is_string) snprintf(r->val[r->n], sizeof r->val[0], "%s", sval);
    else snprintf(r->val[r->n], sizeof r->val[0], "%g", dval);
    r->str[r->n] = is_string;
    r->n++;
}

static const char *get(const rec *r, const char *var)
{
    for (int i = r->n; i-- > 0;)
        if (!strcmp(r->var[i], var)) return r->val[i];
    return NULL;
}

START_TEST(hostinfo_addresses_and_info)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, NULL };
    kelp_field_hostinfo_cfg c;
    kelp_field_hostinfo_cfg_default(&c);
    snprintf(c.community, sizeof c.community, "alpha");
    c.port_db = 9000;
    c.warp = 8;
    kelp_field_hostinfo h;
    kelp_field_hostinfo_init(&h, &c);
    /* nothing found: localhost */
    kelp_field_hostinfo_set(&h, NULL, NULL, 0);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_IP"), "localhost");
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 0); /* posted once */
    /* ethernet before wireless, loopback and bad quads dropped, an address listed once */
    const char *names[] = { "lo", "wlan0", "eth0", "docker0", "eth1", "en5", "wlp2s0" };
    const char *ips[] = { "127.0.0.1", "169.224.126.40", "118.10.24.23", "172.17.0.1", "118.10.24.23", "300.1.1.1",
                          "10.0.0.9" };
    kelp_field_hostinfo_set(&h, names, ips, 7);
    r.n = 0;
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_IP"), "118.10.24.23");
    ck_assert_str_eq(get(&r, "PHI_HOST_IP_ALL"), "118.10.24.23,169.224.126.40,10.0.0.9,172.17.0.1");
    ck_assert_str_eq(get(&r, "PHI_HOST_IP_VERBOSE"), "LINUX_ETHERNET=118.10.24.23,LINUX_ETHERNET=118.10.24.23,"
                                                     "LINUX_WIFI=169.224.126.40,LINUX_WIFI=10.0.0.9,DOCKER0=172.17.0.1");
    ck_assert_str_eq(get(&r, "PHI_HOST_PORT_DB"), "9000");
    ck_assert_ptr_null(get(&r, "PHI_HOST_PORT")); /* 24.8 posts PHI_HOST_PORT_DB only */
    ck_assert_ptr_null(get(&r, "PHI_HOST_PORT_UDP"));
    ck_assert_str_eq(get(&r, "PHI_HOST_INFO"), "community=alpha,hostip=118.10.24.23,port_db=9000,"
                                               "hostip_alts=169.224.126.40,10.0.0.9,172.17.0.1,timewarp=8");
    /* the seed's bridge port arrives: in PHI_HOST_INFO from the next post, the tenth iteration */
    ck_assert_int_eq(kelp_field_hostinfo_mail(&h, "PMB_UDP_LISTEN", false, NULL, 9200), 1);
    ck_assert_int_lt(kelp_field_hostinfo_mail(&h, "PMB_UDP_LISTEN", true, "port", 0), 0);
    r.n = 0;
    for (int i = 4; i < 10; i++) ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 0);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_PORT_UDP"), "9200");
    ck_assert_str_eq(get(&r, "PHI_HOST_INFO"), "community=alpha,hostip=118.10.24.23,port_db=9000,port_udp=9200,"
                                               "hostip_alts=169.224.126.40,10.0.0.9,172.17.0.1,timewarp=8");
    /* HOST_INFO_REQUEST: the edge looks again, everything is posted again */
    ck_assert_int_eq(kelp_field_hostinfo_mail(&h, "HOST_INFO_REQUEST", true, "true", 0), 1);
    ck_assert(h.redetect);
    ck_assert_int_eq(kelp_field_hostinfo_mail(&h, "NAV_X", false, NULL, 1), 0);
    /* a single wireless address (4.6 case 2); a preferred interface; a forced address */
    const char *n1[] = { "wlan0" }, *i1[] = { "192.168.0.1" };
    kelp_field_hostinfo_set(&h, n1, i1, 1);
    r.n = 0;
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_IP"), "192.168.0.1");
    snprintf(h.cfg.prefer_if, sizeof h.cfg.prefer_if, "wlan0");
    kelp_field_hostinfo_set(&h, names, ips, 7);
    r.n = 0;
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_IP"), "169.224.126.40");
    snprintf(h.cfg.force_ip, sizeof h.cfg.force_ip, "192.168.0.55");
    kelp_field_hostinfo_set(&h, names, ips, 7);
    r.n = 0;
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_IP"), "192.168.0.55");
}
END_TEST

/* ufield.md 4.4 and A17: nothing found -> PHI_HOST_IP=localhost with an empty _ALL and
 * _VERBOSE (the default address is not a detected one) */
START_TEST(hostinfo_nothing_found)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, NULL };
    kelp_field_hostinfo_cfg c;
    kelp_field_hostinfo_cfg_default(&c);
    kelp_field_hostinfo h;
    kelp_field_hostinfo_init(&h, &c);
    const char *n1[] = { "lo" }, *i1[] = { "127.0.0.1" };
    kelp_field_hostinfo_set(&h, n1, i1, 1);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_IP"), "localhost");
    ck_assert_str_eq(get(&r, "PHI_HOST_IP_ALL"), "");
    ck_assert_str_eq(get(&r, "PHI_HOST_IP_VERBOSE"), "");
}
END_TEST

/* DEFAULT_HOSTIP_FORCE (MOOS-IvP 24.8 HostInfo.cpp postIPInfo): the forced address is the only
 * one posted, its source USER_HARD_CONFIGURED */
START_TEST(hostinfo_forced)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, NULL };
    kelp_field_hostinfo_cfg c;
    kelp_field_hostinfo_cfg_default(&c);
    snprintf(c.force_ip, sizeof c.force_ip, "192.168.0.55");
    kelp_field_hostinfo h;
    kelp_field_hostinfo_init(&h, &c);
    const char *n2[] = { "eth0", "wlan0" }, *i2[] = { "10.0.0.5", "10.0.0.6" };
    kelp_field_hostinfo_set(&h, n2, i2, 2);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_IP"), "192.168.0.55");
    ck_assert_str_eq(get(&r, "PHI_HOST_IP_ALL"), "192.168.0.55");
    ck_assert_str_eq(get(&r, "PHI_HOST_IP_VERBOSE"), "USER_HARD_CONFIGURED=192.168.0.55");
}
END_TEST

/* PREFER_INTERFACE (MOOS-IvP 24.8 HostInfo.cpp handleConfigPreferInterface, postIPInfo): the
 * name is read case-insensitively, and "wifi" names the wireless interface */
START_TEST(hostinfo_prefer_wifi)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, NULL };
    kelp_field_hostinfo_cfg c;
    kelp_field_hostinfo_cfg_default(&c);
    snprintf(c.prefer_if, sizeof c.prefer_if, "wifi");
    kelp_field_hostinfo h;
    kelp_field_hostinfo_init(&h, &c);
    const char *n2[] = { "eth0", "wlp2s0" }, *i2[] = { "10.0.0.5", "10.0.0.6" };
    kelp_field_hostinfo_set(&h, n2, i2, 2);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_IP"), "10.0.0.6");
    snprintf(h.cfg.prefer_if, sizeof h.cfg.prefer_if, "ETH0");
    const char *n3[] = { "wlan0", "eth0" }, *i3[] = { "10.0.0.6", "10.0.0.5" };
    kelp_field_hostinfo_set(&h, n3, i3, 2);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_IP"), "10.0.0.5");
    snprintf(h.cfg.prefer_if, sizeof h.cfg.prefer_if, "WLAN0");
    kelp_field_hostinfo_set(&h, n3, i3, 2);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_IP"), "10.0.0.6");
}
END_TEST

/* MOOS-IvP 24.8 pHostInfo posts the ports as strings (HostInfo.cpp: m_host_port_db) */
START_TEST(hostinfo_ports_are_strings)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, NULL };
    kelp_field_hostinfo_cfg c;
    kelp_field_hostinfo_cfg_default(&c);
    c.port_db = 9000;
    kelp_field_hostinfo h;
    kelp_field_hostinfo_init(&h, &c);
    ck_assert_int_eq(kelp_field_hostinfo_mail(&h, "PMB_UDP_LISTEN", false, NULL, 9200), 1);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    const char *vars[] = { "PHI_HOST_PORT_DB", "PHI_HOST_PORT_DB", "PHI_HOST_PORT_UDP" };
    for (int k = 0; k < 3; k++) {
        int i = r.n;
        while (i-- > 0 && strcmp(r.var[i], vars[k]) != 0) {}
        ck_assert_int_ge(i, 0);
        ck_assert_msg(r.str[i], "%s is not a string", vars[k]);
        ck_assert_str_eq(r.val[i], k == 2 ? "9200" : "9000");
    }
}
END_TEST

/* PSHARE_INPUT_SUMMARY (MOOS-IvP 24.8 pHostInfo handleMailPShareInput): each "host:port[:udp]"
 * input route is carried as host:port, a "host:port:multicast_N" one as multicast_N, anything
 * else is dropped; the routes are joined with '&' and "localhost" reads as the host's address
 * (postIPInfo). Several routes: no port_udp (24.8); the seed's brokers take the first
 * unicast route's port. */
START_TEST(hostinfo_pshare_iroutes)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, NULL };
    kelp_field_hostinfo_cfg c;
    kelp_field_hostinfo_cfg_default(&c);
    snprintf(c.community, sizeof c.community, "alpha");
    c.port_db = 9000;
    kelp_field_hostinfo h;
    kelp_field_hostinfo_init(&h, &c);
    const char *n1[] = { "eth0" }, *i1[] = { "10.0.0.5" };
    kelp_field_hostinfo_set(&h, n1, i1, 1);
    ck_assert_int_eq(kelp_field_hostinfo_mail(&h, "PSHARE_INPUT_SUMMARY", true,
                                              "localhost:9200:udp,1.2.3.4:2000:multicast_23,bogus,5.6.7.8:9300", 0),
                     1);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_INFO"),
                     "community=alpha,hostip=10.0.0.5,port_db=9000,"
                     "pshare_iroutes=10.0.0.5:9200&multicast_23&5.6.7.8:9300,hostip_alts=,timewarp=1");
    kelp_field_broker_host bh;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_broker_host_parse(get(&r, "PHI_HOST_INFO"), &bh, &why), 0);
    ck_assert_uint_eq(bh.port_udp, 9200);
}
END_TEST

/* MOOS-IvP 24.8 (HostInfo.cpp Iterate/postIPInfo, HostRecord::getSpec): PHI_HOST_INFO at the
 * first iteration, every tenth and after HOST_INFO_REQUEST (not when pShare's summary
 * changes); the record in getSpec's order with port_udp from a single route, pshare_iroutes,
 * hostip_alts (the other addresses), timewarp; the report's PHI_HOST_* lines */
START_TEST(hostinfo_24_record_and_cadence)
{
    rec r = { 0 };
    kelp_field_sink sink = { &r, pub, NULL };
    kelp_field_hostinfo_cfg c;
    kelp_field_hostinfo_cfg_default(&c);
    snprintf(c.community, sizeof c.community, "alpha");
    c.port_db = 9001;
    c.warp = 2;
    kelp_field_hostinfo h;
    kelp_field_hostinfo_init(&h, &c);
    const char *n1[] = { "eth0" }, *i1[] = { "10.0.0.5" };
    kelp_field_hostinfo_set(&h, n1, i1, 1);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    ck_assert_str_eq(get(&r, "PHI_HOST_INFO"), "community=alpha,hostip=10.0.0.5,port_db=9001,hostip_alts=,timewarp=2");
    ck_assert_int_eq(kelp_field_hostinfo_mail(&h, "PSHARE_INPUT_SUMMARY", true, "localhost:9201", 0), 1);
    int posts = 0;
    for (int i = 2; i <= 25; i++) {
        int rc = kelp_field_hostinfo_iterate(&h, &sink);
        ck_assert_int_eq(rc, i % 10 == 0);
        posts += rc;
    }
    ck_assert_int_eq(posts, 2);
    ck_assert_str_eq(get(&r, "PHI_HOST_INFO"), "community=alpha,hostip=10.0.0.5,port_db=9001,port_udp=9201,"
                                               "pshare_iroutes=10.0.0.5:9201,hostip_alts=,timewarp=2");
    ck_assert_int_eq(kelp_field_hostinfo_mail(&h, "HOST_INFO_REQUEST", true, "true", 0), 1);
    ck_assert_int_eq(kelp_field_hostinfo_iterate(&h, &sink), 1);
    static char rep[4096];
    ck_assert_int_eq(kelp_field_hostinfo_report(&h, rep, sizeof rep), 0);
    ck_assert_ptr_nonnull(strstr(rep, "\n  PHI_HOST_IP:          10.0.0.5\n  PHI_HOST_IP_ALL:      10.0.0.5\n\n"));
    ck_assert_ptr_nonnull(strstr(rep, "  PHI_HOST_PORT:        9001\n  PHI_PSHARES_IROUTES:  localhost:9201\n"));
    /* ACBlock(42): items joined while a line stays within 42 characters */
    ck_assert_ptr_nonnull(strstr(rep, "  PHI_HOST_INFO:        community=alpha,hostip=10.0.0.5,\n"
                                      "                        port_db=9001,port_udp=9201,\n"
                                      "                        pshare_iroutes=10.0.0.5:9201,hostip_alts=,\n"
                                      "                        timewarp=2\n"));
}
END_TEST

Suite *kelp_field_hostinfo_suite(void)
{
    Suite *s = suite_create("field_hostinfo");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, hostinfo_addresses_and_info);
    tcase_add_test(tc, hostinfo_nothing_found);
    tcase_add_test(tc, hostinfo_pshare_iroutes);
    tcase_add_test(tc, hostinfo_ports_are_strings);
    tcase_add_test(tc, hostinfo_forced);
    tcase_add_test(tc, hostinfo_prefer_wifi);
    tcase_add_test(tc, hostinfo_24_record_and_cadence);
    suite_add_tcase(s, tc);
    return s;
}
