/* uFldNodeBroker's logic (seed chapter 2, ufield.md section 2): host info in, pings and
 * PMB_REGISTER requests for the local kelp-bridge out (see include/kelp/field.h). */
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>
#include <kelp/mission.h>
#include "field_int.h"
#include <kelp/util.h>

#define NB_DEFAULT_RETRY 10.0         /* s: ping registrations re-posted while no ack is heard */
#define NB_DEFAULT_SHORE "shoreside"  /* dest_community of a try host without one (A25) */

void kelp_field_nbroker_cfg_default(kelp_field_nbroker_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->warp = 1;
    cfg->retry = NB_DEFAULT_RETRY;
}

static void keep_bad(kelp_field_nbroker_cfg *cfg, const char *line, const char *why, bool multicast)
{
    if (cfg->nbad_try >= KELP_BROKER_MAX_TRY) return;
    unsigned i = cfg->nbad_try++;
    size_t n = strlen(line);
    if (n >= KELP_BROKER_LINE) n = KELP_BROKER_LINE - 1;
    memcpy(cfg->bad_try[i], line, n);
    cfg->bad_try[i][n] = 0;
    n = strlen(why);
    if (n >= KELP_BROKER_WHY) n = KELP_BROKER_WHY - 1;
    memcpy(cfg->bad_why[i], why, n);
    cfg->bad_why[i][n] = 0;
    cfg->bad_multicast[i] = multicast;
}

/* a try host, once: 1 added, 0 listed already or invalid (kept for the report) */
static int add_try(kelp_field_nbroker_cfg *cfg, const char *val)
{
    kelp_broker_try t;
    kelp_diag *d = &cfg->ws_diag;
    kelp_diag_clear(d);
    int rc = kelp_broker_try_parse(val, &t, d);
    if (rc < 0) {
        keep_bad(cfg, val, kelp_diag_text(d), rc == KELP_ERR_UNSUPPORTED);
        return 0;
    }
    for (unsigned i = 0; i < cfg->ntry; i++)
        if (strcmp(cfg->tryh[i].host, t.host) == 0 && cfg->tryh[i].port == t.port) return 0;
    if (cfg->ntry >= KELP_BROKER_MAX_TRY) {
        (void)kelp_fail(d, KELP_ERR_NOSPACE, "too many try hosts (KELP_BROKER_MAX_TRY)");
        keep_bad(cfg, val, kelp_diag_text(d), false);
        return 0;
    }
    cfg->tryh[cfg->ntry++] = t;
    return 1;
}

int kelp_field_nbroker_config(kelp_field_nbroker_cfg *cfg, const char *key, const char *val, kelp_diag *d)
{
    size_t kl = strlen(key);
    if (kelp_strieq_n(key, kl, "KEYWORD")) {
        if (strlen(val) >= sizeof cfg->keyword || strpbrk(val, " ,=")) {
            return kelp_fail(d, KELP_ERR_PARSE, "one word without ',' or '=', up to 63 characters");
        }
        memcpy(cfg->keyword, val, strlen(val) + 1);
        return 1;
    }
    if (kelp_strieq_n(key, kl, "TRY_SHORE_HOST")) {
        (void)add_try(cfg, val); /* an invalid one is listed in the report (seed 2.2) */
        return 1;
    }
    if (kelp_strieq_n(key, kl, "BRIDGE")) {
        kelp_broker_bridge b;
        if (kelp_broker_bridge_parse(val, &b, d) < 0) return KELP_ERR_PARSE;
        return broker_add_bridge(cfg->bridge, &cfg->nbridges, b.src, b.alias, d);
    }
    if (kelp_strieq_n(key, kl, "RETRY_INTERVAL")) {
        double dv;
        if (kelp_parse_double(val, strlen(val), &dv) < 0 || !(dv > 0 && dv < 1e6)) {
            return kelp_fail(d, KELP_ERR_PARSE, "seconds > 0");
        }
        cfg->retry = dv;
        return 1;
    }
    bool *flag = kelp_strieq_n(key, kl, "AUTO_BRIDGE_REALMCAST") ? &cfg->auto_realmcast
                 : kelp_strieq_n(key, kl, "AUTO_BRIDGE_APPCAST") ? &cfg->auto_appcast
                 : kelp_strieq_n(key, kl, "AUTO_BRIDGE_PSHARE_VARS") ? &cfg->auto_pshare_vars
                                                                    : NULL;
    if (flag) {
        if (!broker_bool(val, flag)) {
            return kelp_fail(d, KELP_ERR_PARSE, "true or false");
        }
        return 1;
    }
    return 0;
}

void kelp_field_nbroker_init(kelp_field_nbroker *b, const kelp_field_nbroker_cfg *cfg)
{
    memset(b, 0, sizeof *b);
    b->cfg = *cfg;
    b->routes_at = b->last_ack = b->host_req_at = -1;
    /* 24.8's automatic bridges, after the user's (a full list keeps the user's) */
    static const char *const realm[] = { "REALMCAST", "WATCHCAST", "REALMCAST_CHANNELS" };
    /* a full list keeps the user's bridges: the automatic one is dropped (no reason wanted) */
    for (int i = 0; i < 3 && b->cfg.auto_realmcast; i++)
        (void)broker_add_bridge(b->cfg.bridge, &b->cfg.nbridges, realm[i], realm[i], NULL);
    if (b->cfg.auto_appcast) (void)broker_add_bridge(b->cfg.bridge, &b->cfg.nbridges, "APPCAST", "APPCAST", NULL);
    if (b->cfg.auto_pshare_vars)
        (void)broker_add_bridge(b->cfg.bridge, &b->cfg.nbridges, "NODE_PSHARE_VARS", "NODE_PSHARE_VARS", NULL);
}

const char *kelp_field_nbroker_subscription(unsigned i)
{
    static const char *const subs[] = { "PHI_HOST_INFO", "NODE_BROKER_ACK", "TRY_SHORE_HOST" };
    return i < 3 ? subs[i] : NULL;
}

static int ping_route(kelp_field_nbroker *b, const kelp_broker_try *t, const kelp_field_sink *out)
{
    int rc = broker_register(out, "NODE_BROKER_PING", t->community[0] ? t->community : NB_DEFAULT_SHORE, t->host,
                             t->port, "NODE_BROKER_PING", b->last_register, sizeof b->last_register);
    if (rc > 0) b->registers++;
    return rc;
}

static int user_bridges(kelp_field_nbroker *b, const kelp_field_sink *out)
{
    int posts = 0;
    for (unsigned i = 0; i < b->cfg.nbridges; i++) {
        const kelp_broker_bridge *br = &b->cfg.bridge[i];
        if (broker_register(out, br->src, b->shore.community, b->shore.host, b->shore.port_udp, br->alias,
                            b->last_register, sizeof b->last_register) > 0)
            b->registers++, posts++;
    }
    b->bridged = true;
    return posts;
}

static void warn(const kelp_field_sink *out, const char *msg)
{
    if (out->warn) out->warn(out->ctx, msg);
}

static int ack_mail(kelp_field_nbroker *b, const char *sval, kelp_time now, const kelp_field_sink *out)
{
    kelp_broker_host h;
    kelp_diag *d = &b->cfg.ws_diag;
    kelp_diag_clear(d);
    int rc = kelp_broker_host_parse(sval, &h, d);
    if (rc == 0 && !kelp_broker_host_complete(&h)) rc = kelp_fail(d, KELP_ERR_PARSE, "no community, host or port_udp");
    if (rc == 0 && h.have_warp && h.warp != b->cfg.warp) rc = kelp_fail(d, KELP_ERR_STATE, "another time warp");
    if (rc == 0 && h.keyword[0] && b->cfg.keyword[0] && strcmp(h.keyword, b->cfg.keyword) != 0)
        rc = kelp_fail(d, KELP_ERR_DENIED, "another keyword");
    if (rc == 0 && h.status[0] && strcmp(h.status, "ok") != 0) rc = kelp_fail(d, KELP_ERR_DENIED, "refused by the shore");
    if (rc < 0) {
        b->bad_ack++;
        char msg[128];
        kelp_snprintf(msg, sizeof msg, "bad NODE_BROKER_ACK: %s", kelp_diag_text(d));
        warn(out, msg);
        return rc;
    }
    b->ok_ack++;
    bool silence = b->last_ack >= 0 && now - b->last_ack > b->cfg.retry;
    bool same = b->have_shore && strcmp(b->shore.community, h.community) == 0 && strcmp(b->shore.host, h.host) == 0 &&
                b->shore.port_udp == h.port_udp;
    b->shore = h;
    b->have_shore = true;
    b->last_ack = now;
    /* a new shore, or the same one after a silence (it or our bridge may have restarted):
     * register the user's bridges; kelp-bridge ignores a route it has already */
    if (!same || silence || !b->bridged) (void)user_bridges(b, out);
    /* 24.8 (for uFldDelve): the bridges' aliases, after every valid ack */
    char *aliases = b->ws;
    size_t n = 0;
    aliases[0] = 0;
    for (unsigned i = 0; i < b->cfg.nbridges; i++)
        field_putf(aliases, sizeof b->ws, &n, "%s%s", i ? "," : "", b->cfg.bridge[i].alias);
    out->publish(out->ctx, "NODE_PSHARE_VARS", true, aliases, 0);
    return 1;
}

int kelp_field_nbroker_mail(kelp_field_nbroker *b, const char *var, bool is_string, const char *sval, kelp_time now,
                            const kelp_field_sink *out)
{
    if (strcmp(var, "PHI_HOST_INFO") == 0) {
        kelp_broker_host h;
        if (!is_string || kelp_broker_host_parse(sval, &h, NULL) < 0 || !kelp_broker_host_complete(&h)) {
            b->bad_phi++;
            return KELP_ERR_PARSE;
        }
        b->ok_phi++;
        if (b->have_node && !broker_same_host(&b->node, &h)) b->phi_changes++;
        b->node = h;
        b->have_node = true;
        return 1;
    }
    if (strcmp(var, "NODE_BROKER_ACK") == 0) {
        if (!is_string || !sval) {
            b->bad_ack++;
            return KELP_ERR_PARSE;
        }
        return ack_mail(b, sval, now, out);
    }
    if (strcmp(var, "TRY_SHORE_HOST") == 0) {
        if (!is_string || !sval) return KELP_ERR_PARSE;
        unsigned nbad = b->cfg.nbad_try;
        if (add_try(&b->cfg, sval) > 0) {
            if (b->routes_posted) (void)ping_route(b, &b->cfg.tryh[b->cfg.ntry - 1], out);
            return 1;
        }
        return b->cfg.nbad_try > nbad ? KELP_ERR_PARSE : 1;
    }
    return 0;
}

int kelp_field_nbroker_iterate(kelp_field_nbroker *b, kelp_time now, const kelp_field_sink *out)
{
    b->iterations++;
    if (!b->have_node) { /* nothing to say about ourselves yet: ask pHostInfo */
        if (b->host_req_at < 0 || now - b->host_req_at >= KELP_BROKER_HOST_REQ_PERIOD) {
            out->publish(out->ctx, "HOST_INFO_REQUEST", true, "true", 0);
            b->host_req_at = now;
            return 1;
        }
        return 0;
    }
    int posts = 0;
    bool heard = b->last_ack >= 0 && now - b->last_ack <= b->cfg.retry;
    if (!b->routes_posted || (!heard && now - b->routes_at >= b->cfg.retry)) {
        for (unsigned i = 0; i < b->cfg.ntry; i++)
            if (ping_route(b, &b->cfg.tryh[i], out) > 0) posts++;
        b->routes_posted = true;
        b->routes_at = now;
    }
    char ping[KELP_BROKER_MSG];
    if (broker_host_format(&b->node, b->cfg.keyword, b->cfg.warp, now, NULL, ping, sizeof ping) < 0) return posts;
    out->publish(out->ctx, "NODE_BROKER_PING", true, ping, 0);
    b->pings++;
    return posts + 1;
}

static void host_block(char *buf, size_t cap, size_t *n, bool *full, const char *title, const kelp_broker_host *h,
                       bool have)
{
    char db[12] = "", udp[12] = "", warp[24] = "";
    size_t wn = 0;
    if (have && h->port_db) kelp_snprintf(db, sizeof db, "%u", h->port_db);
    if (have && h->port_udp) kelp_snprintf(udp, sizeof udp, "%u", h->port_udp);
    if (have && h->have_warp && field_put_fixed(warp, sizeof warp, &wn, h->warp, 6, true) < 0) warp[0] = 0;
    broker_put(buf, cap, n, full,
        "%s: %s\n    HostIP: %s\n    Port (DB): %s\n    Port (UDP): %s\n    Time Warp: %s\n", title,
        have ? h->community : "", have ? h->host : "", db, udp, warp);
}

int kelp_field_nbroker_report(const kelp_field_nbroker *b, char *buf, size_t cap)
{
    size_t n = 0;
    bool full = false;
    if (!buf || cap == 0) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    broker_put(buf, cap, &n, &full,
        "NodeBroker Status ----- (%lu)\n"
        "Total OK PHI_HOST_INFO    received: %lu\n"
        "Total BAD PHI_HOST_INFO   received: %lu\n"
        "Total HOST_INFO changes  received: %lu\n"
        "Total PMB_REGISTER        posted: %lu\n"
        "Total NODE_BROKER_PING   posted: %lu\n"
        "Total OK NODE_BROKER_ACK received: %lu\n"
        "Total BAD NODE_BROKER_ACK received: %lu\n\n"
        "Configuration Info:\n  Total Valid TryHosts:   %u\n",
        b->iterations, b->ok_phi, b->bad_phi, b->phi_changes, b->registers, b->pings, b->ok_ack, b->bad_ack,
        b->cfg.ntry);
    for (unsigned i = 0; i < b->cfg.ntry; i++)
        broker_put(buf, cap, &n, &full, "  [%u]: hostip=%s,port_udp=%u\n", i + 1, b->cfg.tryh[i].host, b->cfg.tryh[i].port);
    broker_put(buf, cap, &n, &full, "  Total InValid TryHosts: %u\n", b->cfg.nbad_try);
    for (unsigned i = 0; i < b->cfg.nbad_try; i++) broker_put(buf, cap, &n, &full, "  %s\n", b->cfg.bad_try[i]);
    broker_put(buf, cap, &n, &full, "\n");
    host_block(buf, cap, &n, &full, "Node Information", &b->node, b->have_node);
    broker_put(buf, cap, &n, &full, "\n");
    host_block(buf, cap, &n, &full, "Shoreside Information", &b->shore, b->have_shore);
    return full ? KELP_ERR_NOSPACE : KELP_OK;
}
