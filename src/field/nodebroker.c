/* uFldNodeBroker's logic: host info in, pings and bridge requests for the local kelp-bridge
 * out (see include/kelp/field.h). Two models: MOOS-IvP 24.8's (PSHARE_CMD to kelp-bridge
 * running as pShare, NODE_BROKER_PING_<n>, 24.8's host records and report) and the seed's
 * (chapter 2, ufield.md section 2: PMB_REGISTER to kelp-bridge as pMOOSBridge). */
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
    /* 24.8 (NodeBroker::OnStartUp): the automatic bridges are on unless turned off */
    cfg->auto_realmcast = cfg->auto_appcast = cfg->auto_pshare_vars = true;
}

void kelp_field_nbroker_cfg_seed(kelp_field_nbroker_cfg *cfg)
{
    kelp_field_nbroker_cfg_default(cfg);
    cfg->pmb = true;
    cfg->auto_realmcast = cfg->auto_appcast = cfg->auto_pshare_vars = false;
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

/* a try host, once: 1 added, 0 listed already (seed) or invalid (kept for the report), -1 the
 * same pshare_route again (24.8) */
static int add_try(kelp_field_nbroker_cfg *cfg, const char *val)
{
    kelp_field_broker_try t;
    kelp_diag *d = &cfg->ws_diag;
    kelp_diag_clear(d);
    int rc = cfg->pmb ? kelp_field_broker_try_parse(val, &t, d) : kelp_field_broker_try_parse_pshare(val, &t, d);
    if (rc < 0) {
        keep_bad(cfg, val, kelp_diag_text(d), rc == KELP_ERR_UNSUPPORTED);
        return 0;
    }
    for (unsigned i = 0; i < cfg->ntry; i++) {
        if (!cfg->pmb && strcmp(cfg->tryh[i].route, t.route) == 0) return -1; /* 24.8: the same route */
        if (cfg->pmb && strcmp(cfg->tryh[i].host, t.host) == 0 && cfg->tryh[i].port == t.port) return 0;
    }
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
    if (kelp_util_strieq_n(key, kl, "KEYWORD")) {
        if (strlen(val) >= sizeof cfg->keyword || strpbrk(val, " ,=")) {
            return kelp_fail(d, KELP_ERR_PARSE, "one word without ',' or '=', up to 63 characters");
        }
        memcpy(cfg->keyword, val, strlen(val) + 1);
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "TRY_SHORE_HOST")) {
        /* an invalid one is listed in the report (seed 2.2); 24.8 warns of a duplicate */
        if (add_try(cfg, val) < 0) return kelp_fail(d, KELP_ERR_EXISTS, "Duplicate try_shore_host");
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "BRIDGE")) {
        kelp_field_broker_bridge b;
        if (kelp_field_broker_bridge_parse(val, &b, d) < 0) return KELP_ERR_PARSE;
        return broker_add_bridge(cfg->bridge, &cfg->nbridges, b.src, b.alias, d);
    }
    if (kelp_util_strieq_n(key, kl, "RETRY_INTERVAL")) {
        double dv;
        if (kelp_util_parse_double(val, strlen(val), &dv) < 0 || !(dv > 0 && dv < 1e6)) {
            return kelp_fail(d, KELP_ERR_PARSE, "seconds > 0");
        }
        cfg->retry = dv;
        return 1;
    }
    bool *flag = kelp_util_strieq_n(key, kl, "AUTO_BRIDGE_REALMCAST") ? &cfg->auto_realmcast
                 : kelp_util_strieq_n(key, kl, "AUTO_BRIDGE_APPCAST") ? &cfg->auto_appcast
                 : kelp_util_strieq_n(key, kl, "AUTO_BRIDGE_PSHARE_VARS") ? &cfg->auto_pshare_vars
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
    b->ping_at = b->ok_ack_at = -1e300; /* 24.8 starts them at 0: long ago */
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

static int ping_route(kelp_field_nbroker *b, const kelp_field_broker_try *t, const kelp_field_sink *out)
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
        const kelp_field_broker_bridge *br = &b->cfg.bridge[i];
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
    kelp_field_broker_host *hp = &b->ws_host;
#define h (*hp)
    kelp_diag *d = &b->cfg.ws_diag;
    kelp_diag_clear(d);
    int rc = kelp_field_broker_host_parse(sval, &h, d);
    if (rc == 0 && !kelp_field_broker_host_complete(&h)) rc = kelp_fail(d, KELP_ERR_PARSE, "no community, host or port_udp");
    if (rc == 0 && h.have_warp && h.warp != b->cfg.warp) rc = kelp_fail(d, KELP_ERR_STATE, "another time warp");
    if (rc == 0 && h.keyword[0] && b->cfg.keyword[0] && strcmp(h.keyword, b->cfg.keyword) != 0)
        rc = kelp_fail(d, KELP_ERR_DENIED, "another keyword");
    if (rc == 0 && h.status[0] && strcmp(h.status, "ok") != 0) rc = kelp_fail(d, KELP_ERR_DENIED, "refused by the shore");
    if (rc < 0) {
        b->bad_ack++;
        char msg[128];
        kelp_util_snprintf(msg, sizeof msg, "bad NODE_BROKER_ACK: %s", kelp_diag_text(d));
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
#undef h
}

KELP_NOINLINE static int seed_mail(kelp_field_nbroker *b, const char *var, bool is_string, const char *sval, kelp_time now,
                     const kelp_field_sink *out)
{
    if (strcmp(var, "PHI_HOST_INFO") == 0) {
        kelp_field_broker_host *h = &b->ws_host;
        if (!is_string || kelp_field_broker_host_parse(sval, h, NULL) < 0 || !kelp_field_broker_host_complete(h)) {
            b->bad_phi++;
            return KELP_ERR_PARSE;
        }
        b->ok_phi++;
        if (b->have_node && !broker_same_host(&b->node, h)) b->phi_changes++;
        b->node = *h;
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

KELP_NOINLINE static int seed_iterate(kelp_field_nbroker *b, kelp_time now, const kelp_field_sink *out)
{
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

static void host_block(char *buf, size_t cap, size_t *n, bool *full, const char *title, const kelp_field_broker_host *h,
                       bool have)
{
    char db[12] = "", udp[12] = "", warp[24] = "";
    size_t wn = 0;
    if (have && h->port_db) kelp_util_snprintf(db, sizeof db, "%u", h->port_db);
    if (have && h->port_udp) kelp_util_snprintf(udp, sizeof udp, "%u", h->port_udp);
    if (have && h->have_warp && field_put_fixed(warp, sizeof warp, &wn, h->warp, 6, true) < 0) warp[0] = 0;
    broker_put(buf, cap, n, full,
        "%s: %s\n    HostIP: %s\n    Port (DB): %s\n    Port (UDP): %s\n    Time Warp: %s\n", title,
        have ? h->community : "", have ? h->host : "", db, udp, warp);
}

static int seed_report(const kelp_field_nbroker *b, char *buf, size_t cap)
{
    size_t n = 0;
    bool full = false;
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

/* ------------------------------------------------------------------ 24.8 */

/* 24.8 (NodeBroker::postPShareCommand): NODE_MESSAGE_LOCAL only with its NODE_MESSAGE bridge
 * (the "unmediated" policy), MEDIATED_MESSAGE_LOCAL only with its MEDIATED_MESSAGE one */
static bool policy_allows(const kelp_field_nbroker *b, const char *src)
{
    const char *alias = strcmp(src, "NODE_MESSAGE_LOCAL") == 0       ? "NODE_MESSAGE"
                        : strcmp(src, "MEDIATED_MESSAGE_LOCAL") == 0 ? "MEDIATED_MESSAGE"
                                                                     : NULL;
    if (!alias) return true;
    for (unsigned i = 0; i < b->cfg.nbridges; i++)
        if (strcmp(b->cfg.bridge[i].src, src) == 0 && strcmp(b->cfg.bridge[i].alias, alias) == 0) return true;
    return false;
}

static int cmd(kelp_field_nbroker *b, const char *src, const char *dest, const char *route, const kelp_field_sink *out)
{
    if (!policy_allows(b, src)) return 0;
    if (broker_pshare_cmd(out, src, dest, route, b->last_register, sizeof b->last_register) < 0) return 0;
    b->pshare_cmds++;
    return 1;
}

/* PSHARE_CMD NODE_BROKER_PING_<i> -> NODE_BROKER_PING for route i (from..to) */
static int ping_bridges(kelp_field_nbroker *b, unsigned from, unsigned to, const kelp_field_sink *out)
{
    int posts = 0;
    for (unsigned i = from; i < to; i++) {
        char src[32];
        kelp_util_snprintf(src, sizeof src, "NODE_BROKER_PING_%u", i);
        posts += cmd(b, src, "NODE_BROKER_PING", b->cfg.tryh[i].route, out);
    }
    return posts;
}

/* a run warning a b2 c, built in the workspace (b2 must not live there) */
KELP_NOINLINE static void warn24(kelp_field_nbroker *b, const kelp_field_sink *out, const char *a, const char *b2,
                                 const char *c)
{
    if (!out->warn) return;
    size_t n = 0;
    b->ws[0] = 0;
    if (field_put_str(b->ws, sizeof b->ws, &n, a) == 0 && field_put_str(b->ws, sizeof b->ws, &n, b2) == 0)
        KELP_IGNORE(field_put_str(b->ws, sizeof b->ws, &n, c));
    out->warn(out->ctx, b->ws);
}

static int ack24(kelp_field_nbroker *b, const char *sval, kelp_time now, const kelp_field_sink *out)
{
    kelp_field_broker_host *h = &b->ws_host; /* the ack's record */
    long ix = -1;
    bool ok = kelp_field_broker_host_parse(sval, h, NULL) == 0 && kelp_field_broker_host_valid(h);
    if (ok && (!h->key[0] || kelp_util_parse_long(h->key, strlen(h->key), &ix) < 0 || ix < 0 || (unsigned long)ix >= b->cfg.ntry))
        ok = false;
    if (!ok) {
        b->bad_ack++;
        warn24(b, out, "NODE_BROKER_ACK recvd from ", h->host, " w/ null or bad key, for now.");
        return KELP_ERR_PARSE;
    }
    b->shore = *h;
    kelp_field_broker_shore *sh = &b->sh[ix];
    memcpy(sh->community, h->community, sizeof sh->community);
    memcpy(sh->ip, h->host, sizeof sh->ip);
    memcpy(sh->warp, h->warp_s, sizeof sh->warp);
    sh->acks++;
    b->have_shore = true;
    char *aliases = b->ws; /* 24.8: every bridge's alias, for uFldDelve */
    size_t n = 0;
    aliases[0] = 0;
    for (unsigned i = 0; i < b->cfg.nbridges; i++)
        field_putf(aliases, sizeof b->ws, &n, "%s%s", i ? "," : "", b->cfg.bridge[i].alias);
    out->publish(out->ctx, "NODE_PSHARE_VARS", true, aliases, 0);
    b->ok_ack++;
    b->ok_ack_at = now;
    /* the user's bridges to every route that acked and has none yet */
    for (unsigned k = 0; k < b->cfg.ntry; k++) {
        if (b->sh[k].bridged || !b->sh[k].acks) continue;
        b->sh[k].bridged = true;
        b->bridged = true;
        for (unsigned i = 0; i < b->cfg.nbridges; i++)
            (void)cmd(b, b->cfg.bridge[i].src, b->cfg.bridge[i].alias, b->cfg.tryh[k].route, out);
    }
    return 1;
}

KELP_NOINLINE static int mail24(kelp_field_nbroker *b, const char *var, bool is_string, const char *sval, kelp_time now,
                  const kelp_field_sink *out)
{
    if (strcmp(var, "PHI_HOST_INFO") == 0) {
        kelp_field_broker_host *h = &b->ws_host;
        if (!is_string || !sval || kelp_field_broker_host_parse(sval, h, NULL) < 0 || !kelp_field_broker_host_valid(h)) {
            b->bad_phi++;
            warn24(b, out, "Invalid PHI_HOST_INFO recd: ", sval && is_string ? sval : "", "");
            return KELP_ERR_PARSE;
        }
        b->ok_phi++;
        const kelp_field_broker_host *o = &b->node;
        if (strcmp(o->community, h->community) != 0 || strcmp(o->warp_s, h->warp_s) != 0 || strcmp(o->host, h->host) != 0 ||
            o->port_db != h->port_db || o->have_port_db != h->have_port_db || o->port_udp != h->port_udp ||
            o->have_port_udp != h->have_port_udp || strcmp(o->iroutes, h->iroutes) != 0)
            b->phi_changes++;
        b->node = *h;
        b->have_node = true;
        return 1;
    }
    if (strcmp(var, "NODE_BROKER_ACK") == 0) {
        return ack24(b, is_string && sval ? sval : "", now, out);
    }
    if (strcmp(var, "TRY_SHORE_HOST") == 0) {
        unsigned nbad = b->cfg.nbad_try;
        int rc = add_try(&b->cfg, is_string && sval ? sval : "");
        if (rc == 0 && b->cfg.nbad_try > nbad) {
            b->cfg.nbad_try = nbad; /* 24.8 warns at run time; the report lists configured ones */
            warn24(b, out, "Invalid incoming TRY_SHORE_HOST:", is_string && sval ? sval : "", "");
            return KELP_ERR_PARSE;
        }
        /* a new route or one listed already: the latest route's ping bridge (as 24.8) */
        if (b->cfg.ntry) (void)ping_bridges(b, b->cfg.ntry - 1, b->cfg.ntry, out);
        return 1;
    }
    return 0;
}

KELP_NOINLINE static int iterate24(kelp_field_nbroker *b, kelp_time now, const kelp_field_sink *out)
{
    int posts = 0;
    bool acked = false;
    for (unsigned i = 0; i < b->cfg.ntry; i++) acked = acked || b->sh[i].acks > 0;
    if (!acked) posts += ping_bridges(b, 0, b->cfg.ntry, out);
    /* the ping: once our own record has pshare_iroutes and timewarp */
    if (!b->have_node || !b->node.iroutes[0] || !b->node.warp_s[0]) return posts;
    char tstamp[32];
    size_t tn = 0;
    if (field_put_fixed(tstamp, sizeof tstamp, &tn, now, 2, false) < 0) return posts;
    for (unsigned i = 0; i < b->cfg.ntry; i++) {
        /* one clock for every route (24.8): after route 0 pings the others wait */
        double thresh = now - b->ok_ack_at > KELP_BROKER_PING_FAST ? KELP_BROKER_PING_FAST : KELP_BROKER_PING_SLOW;
        if (!(now - b->ping_at > thresh)) continue;
        char key[16], var[40];
        kelp_util_snprintf(key, sizeof key, "%u", i);
        kelp_util_snprintf(var, sizeof var, "NODE_BROKER_PING_%u", i);
        if (kelp_field_broker_host_spec(&b->node, tstamp, key, b->ws, sizeof b->ws) < 0) continue;
        out->publish(out->ctx, var, true, b->ws, 0);
        b->sh[i].pings++;
        b->pings++;
        b->ping_at = now;
        posts++;
    }
    return posts;
}

static const char *shore_cell(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap)
{
    static const char *const head[2][6] = { { "Community", "", "Pings", "Pings", "IP", "Time" },
                                            { "Name", "Route", "Sent", "Acked", "Address", "Warp" } };
    const kelp_field_nbroker *b = ctx;
    if (row < 2) return head[row][col];
    const kelp_field_broker_shore *sh = &b->sh[row - 2];
    switch (col) {
    case 0: return sh->community;
    case 1: return b->cfg.tryh[row - 2].route;
    case 2: kelp_util_snprintf(tmp, cap, "%lu", sh->pings); return tmp;
    case 3: kelp_util_snprintf(tmp, cap, "%lu", sh->acks); return tmp;
    case 4: return sh->ip;
    default: return sh->warp;
    }
}

static int report24(const kelp_field_nbroker *b, char *buf, size_t cap)
{
    size_t n = 0;
    bool full = false;
    const kelp_field_broker_host *h = &b->node;
    static const char rule[] = "===========================================================\n";
    broker_put(buf, cap, &n, &full,
               "\n  Total OK  PHI_HOST_INFO    received: %lu\n"
               "  Total BAD PHI_HOST_INFO    received: %lu\n"
               "  Total HOST_INFO changes    received: %lu\n"
               "  Total          PSHARE_CMD    posted: %lu\n"
               "  Total BAD NODE_BROKER_ACK  received: %lu\n\n",
               b->ok_phi, b->bad_phi, b->phi_changes, b->pshare_cmds, b->bad_ack);
    char port_db[12] = "";
    if (h->have_port_db) kelp_util_snprintf(port_db, sizeof port_db, "%u", h->port_db);
    broker_put(buf, cap, &n, &full,
               "%s             Vehicle Node Information:\n%s\n"
               "     Community: %s\n        HostIP: %s\n   Port MOOSDB: %s\n     Time Warp: %s\n   TryHost IPs: ",
               rule, rule, h->community, h->host, port_db, h->warp_s);
    bool first = true;
    for (unsigned i = 0; i < b->cfg.ntry; i++) { /* the real addresses among the routes */
        const kelp_field_broker_try *t = &b->cfg.tryh[i];
        if (!t->host[0] || kelp_util_strieq(t->host, "localhost") || !field_ip_ok(t->host, strlen(t->host))) continue;
        broker_put(buf, cap, &n, &full, "%s%s", first ? "" : ",", t->host);
        first = false;
    }
    broker_put(buf, cap, &n, &full, "\n");
    broker_block(buf, cap, &n, &full, "      IRoutes: ", h->iroutes, 1, '&');
    broker_put(buf, cap, &n, &full, "\n%s            Shoreside Node(s) Information:\n%s\n", rule, rule);
    broker_table(buf, cap, &n, &full, 6, 2 + b->cfg.ntry, 2, shore_cell, b);
    bool s1 = b->ok_phi > 0, s2 = b->cfg.ntry > 0, s3 = b->pings > 0, s4 = b->ok_ack > 0, s5 = false;
    for (unsigned k = 0; k < b->cfg.ntry; k++) s5 = s5 || b->sh[k].bridged;
#define YN(x) ((x) ? "(Y)" : "(N)")
    broker_put(buf, cap, &n, &full,
               "\n\nPhase Completion Summary:\n------------------------------------\n"
               " Phase 1: %s Valid Host information retrieved (iroutes).\n"
               " Phase 2: %s Valid TryHosts (%u) configured.\n"
               " Phase 3: %s NODE_BROKER_PINGS are being sent to TryHosts.\n"
               " Phase 4: %s A Valid NODE_BROKER_ACK has been received.\n"
               " Phase 5: %s pShare requested to share user vars with shoreside.\n",
               YN(s1), YN(s2), b->cfg.ntry, YN(s3), YN(s4), YN(s5));
#undef YN
    if (!s1) broker_put(buf, cap, &n, &full, "*Hint: Phase 1 problem. Check status/output of pHostInfo.              \n");
    else if (!s2) broker_put(buf, cap, &n, &full, "*Hint: Phase 2 problem. Check your .moos file configuration.           \n");
    else if (!s3) broker_put(buf, cap, &n, &full, "*Hint: Phase 3 problem. Check if our node's iroutes, timewarp are set. \n");
    else if (!s4)
        broker_put(buf, cap, &n, &full,
                   "*Hint: Phase 4 problem. Check that shoreside is running and            \n"
                   "      that shoreside has received this node's NODE_BROKER_PING.        \n"
                   "      If the shoreside HAS NOT received the ping, check that the       \n"
                   "      pShare input route matches one of the TryHosts in uFldNodeBroker.\n"
                   "      If the shoreside HAS received a ping, check that we have received\n"
                   "      a NODE_BROKER_ACK in the local MOOSDB.\n");
    else if (!s5)
        broker_put(buf, cap, &n, &full,
                   "*Hint: Phase 5 problem. Check that the user has indeed configured \n"
                   "      in the .moos config block for this app.\n");
    else broker_put(buf, cap, &n, &full, "All Phases complete. Things should be working as configured. \n");
    return full ? KELP_ERR_NOSPACE : KELP_OK;
}

/* the time step rule (docs/ARCHITECTURE.md): a `now` that is no time is refused; after a step
 * back every stored time moves back by the step, so each wait (ping interval, retry, the host
 * info request) keeps what remained of it instead of stalling for the step */
static bool clock_ok(kelp_field_nbroker *b, kelp_time now)
{
    if (!kelp_util_time_ok(now)) return false;
    double back = kelp_util_clock_back(&b->clock, now);
    if (back > 0) {
        double *t[] = { &b->host_req_at, &b->routes_at, &b->last_ack, &b->ping_at, &b->ok_ack_at };
        for (size_t i = 0; i < sizeof t / sizeof t[0]; i++)
            if (*t[i] > -KELP_TIME_LIMIT && *t[i] != -1) *t[i] -= back; /* not "never" (-1, -1e300) */
    }
    return true;
}

int kelp_field_nbroker_mail(kelp_field_nbroker *b, const char *var, bool is_string, const char *sval, kelp_time now,
                            const kelp_field_sink *out)
{
    if (!clock_ok(b, now)) return KELP_ERR_ARG;
    return b->cfg.pmb ? seed_mail(b, var, is_string, sval, now, out) : mail24(b, var, is_string, sval, now, out);
}

int kelp_field_nbroker_iterate(kelp_field_nbroker *b, kelp_time now, const kelp_field_sink *out)
{
    if (!clock_ok(b, now)) return 0;
    b->iterations++;
    return b->cfg.pmb ? seed_iterate(b, now, out) : iterate24(b, now, out);
}

int kelp_field_nbroker_report(const kelp_field_nbroker *b, char *buf, size_t cap)
{
    if (!buf || cap == 0) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    return b->cfg.pmb ? seed_report(b, buf, cap) : report24(b, buf, cap);
}
