/* Fuzz: the uField brokers' text parsers and mail handlers -- PHI_HOST_INFO, NODE_BROKER_PING
 * and NODE_BROKER_ACK host records, TRY_SHORE_HOST and BRIDGE / QBRIDGE / TRY_VNODE lines,
 * the mail handlers of both brokers on such text, and their terminal reports. The first
 * byte picks the target; the rest is the text (NUL-terminated copy of exact size). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/field.h>

static void check_publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx, (void)dval;
    if (!var || (is_string && !sval)) abort();
    if (is_string && strlen(sval) >= KELP_BROKER_MSG) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    size_t n = size - 1;
    char *t = malloc(n + 1);
    memcpy(t, data + 1, n);
    t[n] = 0;
    kelp_diag why = { 0 };
    kelp_field_sink sink = { NULL, check_publish, NULL };
    static char rep[16384];
    switch (data[0] % 5) {
    case 0: {
        kelp_field_broker_host h;
        if (kelp_field_broker_host_parse(t, &h, &why) == 0) {
            if (kelp_field_broker_host_complete(&h) && (!h.community[0] || !h.host[0] || !h.port_udp)) abort();
            if (h.port_udp > 65535 || h.port_db > 65535) abort();
        } else if (why.code == KELP_OK)
            abort(); /* a refusal says why */
        break;
    }
    case 1: {
        kelp_field_broker_try tr;
        kelp_field_broker_bridge b;
        if (kelp_field_broker_try_parse(t, &tr, &why) == 0 && (!tr.host[0] || tr.port == 0 || tr.port > 65535)) abort();
        if (kelp_field_broker_bridge_parse(t, &b, &why) == 0 && (!b.src[0] || !b.alias[0])) abort();
        break;
    }
    case 2: {
        /* node: a config line (key chosen by the second byte), then the text as each mail */
        static kelp_field_nbroker nb;
        kelp_field_nbroker_cfg c;
        kelp_field_nbroker_cfg_default(&c);
        static const char *const keys[] = { "TRY_SHORE_HOST", "BRIDGE", "KEYWORD", "AUTO_BRIDGE_REALMCAST" };
        (void)kelp_field_nbroker_config(&c, keys[(n ? (uint8_t)t[0] : 0) % 4], t, &why);
        if (c.ntry > KELP_BROKER_MAX_TRY || c.nbad_try > KELP_BROKER_MAX_TRY || c.nbridges > KELP_BROKER_MAX_BRIDGES)
            abort();
        kelp_field_nbroker_init(&nb, &c);
        (void)kelp_field_nbroker_mail(&nb, "PHI_HOST_INFO", true,
                                      "community=a,hostip=10.0.0.1,port_db=9000,port_udp=9200,timewarp=1", 0, &sink);
        (void)kelp_field_nbroker_mail(&nb, "TRY_SHORE_HOST", true, t, 0, &sink);
        (void)kelp_field_nbroker_iterate(&nb, 1, &sink);
        (void)kelp_field_nbroker_mail(&nb, "NODE_BROKER_ACK", true, t, 1, &sink);
        (void)kelp_field_nbroker_mail(&nb, "PHI_HOST_INFO", true, t, 2, &sink);
        (void)kelp_field_nbroker_iterate(&nb, 20, &sink);
        (void)kelp_field_nbroker_report(&nb, rep, sizeof rep);
        break;
    }
    case 3: {
        /* shore: a config line, then the text as a ping (twice: the second is a repeat) */
        static kelp_field_sbroker sb;
        kelp_field_sbroker_cfg c;
        kelp_field_sbroker_cfg_default(&c);
        static const char *const keys[] = { "BRIDGE", "QBRIDGE", "TRY_VNODE", "KEYWORD" };
        (void)kelp_field_sbroker_config(&c, keys[(n ? (uint8_t)t[0] : 0) % 4], t, &why);
        if (c.nbridges > KELP_BROKER_MAX_BRIDGES || c.nvnodes > KELP_BROKER_MAX_VNODES) abort();
        kelp_field_sbroker_init(&sb, &c);
        (void)kelp_field_sbroker_mail(&sb, "PHI_HOST_INFO", true,
                                      "community=s,hostip=10.0.0.2,port_db=9000,port_udp=9200,timewarp=1", 0, &sink);
        (void)kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true, t, 1, &sink);
        (void)kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true, t, 2, &sink);
        if (sb.nnodes > KELP_BROKER_MAX_NODES || sb.naccepted > sb.nnodes) abort();
        (void)kelp_field_sbroker_iterate(&sb, 3, &sink);
        (void)kelp_field_sbroker_report(&sb, 4, rep, sizeof rep);
        break;
    }
    default: {
        /* a shore configured with bridges full of macros, pinged by the text's community */
        static kelp_field_sbroker sb;
        kelp_field_sbroker_cfg c;
        kelp_field_sbroker_cfg_default(&c);
        if (kelp_field_sbroker_config(&c, "BRIDGE", "src=A_$V_$v_$N_$$V, alias=A", &why) != 1) abort();
        kelp_field_sbroker_init(&sb, &c);
        (void)kelp_field_sbroker_mail(&sb, "PHI_HOST_INFO", true, t, 0, &sink);
        (void)kelp_field_sbroker_mail(&sb, "PHI_HOST_INFO", true,
                                      "community=s,hostip=10.0.0.2,port_db=9000,port_udp=9200,timewarp=1", 0, &sink);
        char ping[600];
        size_t l = n < 200 ? n : 200;
        memcpy(ping, "community=", 10);
        memcpy(ping + 10, t, l);
        static const char tail[] = ",host=1.2.3.4,port_udp=9200,time_warp=1";
        memcpy(ping + 10 + l, tail, sizeof tail);
        (void)kelp_field_sbroker_mail(&sb, "NODE_BROKER_PING", true, ping, 1, &sink);
        break;
    }
    }
    free(t);
    return 0;
}
