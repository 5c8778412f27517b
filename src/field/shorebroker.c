/* uFldShoreBroker's logic: vehicles' pings in, acks and bridge requests for the shore's
 * kelp-bridge out (see include/kelp/field.h). Two models: MOOS-IvP 24.8's (PSHARE_CMD to
 * kelp-bridge running as pShare, 24.8's acks, cadence and report) and the seed's (chapter 3,
 * ufield.md section 3: PMB_REGISTER to kelp-bridge as pMOOSBridge). */
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>
#include <kelp/mission.h>
#include "field_int.h"
#include <kelp/util.h>

#define SB_VNODE_PORT 9200        /* try_vnode port when none is given (24.8) */
#define SB_VNODE_REG_EVERY 30.0   /* s between try_vnode PMB_REGISTERs (24.8) */
#define SB_VNODE_POST_EVERY 10.0  /* s between TRY_SHORE_HOST posts (24.8) */
#define SB_COUNT_EVERY 30.0       /* s between unchanged UFSB_NODE_COUNT posts (24.8) */
#define SB_CMD_INTERVAL 5.0       /* s to the next bridge-request pass after a new vehicle (24.8) */
#define SB_CMD_GROWTH 3.0         /* s the gap grows by after each pass (24.8) */

void kelp_field_sbroker_cfg_default(kelp_field_sbroker_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->warp = 1;
    /* 24.8 (ShoreBroker::OnStartUp): the automatic bridges are on unless turned off */
    cfg->auto_realmcast = cfg->auto_appcast = cfg->auto_mhash = true;
}

void kelp_field_sbroker_cfg_seed(kelp_field_sbroker_cfg *cfg)
{
    kelp_field_sbroker_cfg_default(cfg);
    cfg->pmb = true;
    cfg->auto_realmcast = cfg->auto_appcast = cfg->auto_mhash = false;
}

static int qbridge(kelp_field_sbroker_cfg *cfg, const char *val, kelp_diag *d)
{
    size_t pos = 0, il, len = strlen(val);
    const char *it;
    int rc, any = 0;
    while ((rc = field_next_item(val, len, &pos, ',', &it, &il)) == 1) {
        char name[KELP_MAX_NAME - 4], all[KELP_MAX_NAME], each[KELP_MAX_NAME];
        /* room for the "_ALL" / "_$V" suffix */
        if (il + 1 > sizeof name || memchr(it, '=', il) || memchr(it, ' ', il)) {
            return kelp_fail(d, KELP_ERR_PARSE, "QBRIDGE takes variable names (X: X_ALL->X and X_$V->X)");
        }
        memcpy(name, it, il);
        name[il] = 0;
        bool known = false;
        for (unsigned i = 0; i < cfg->nqbridge && !known; i++) known = strcmp(cfg->qbridge[i], name) == 0;
        if (!known && cfg->nqbridge < KELP_BROKER_MAX_BRIDGES / 2) memcpy(cfg->qbridge[cfg->nqbridge++], name, il + 1);
        kelp_util_snprintf(all, sizeof all, "%s_ALL", name);
        kelp_util_snprintf(each, sizeof each, "%s_$V", name);
        if (broker_add_bridge(cfg->bridge, &cfg->nbridges, all, name, d) < 0 ||
            broker_add_bridge(cfg->bridge, &cfg->nbridges, each, name, d) < 0)
            return KELP_ERR_NOSPACE;
        any = 1;
    }
    if (rc < 0 || !any) {
        return kelp_fail(d, KELP_ERR_PARSE, "QBRIDGE takes variable names (X: X_ALL->X and X_$V->X)");
    }
    return 1;
}

/* a BRIDGE line's bridge: listed (once) and marked as named by a BRIDGE line */
static int raw_bridge(kelp_field_sbroker_cfg *cfg, const char *src, const char *alias, kelp_diag *d)
{
    int rc = broker_add_bridge(cfg->bridge, &cfg->nbridges, src, alias, d);
    if (rc < 0) return rc;
    for (unsigned i = 0; i < cfg->nbridges; i++)
        if (strcmp(cfg->bridge[i].src, src) == 0 && strcmp(cfg->bridge[i].alias, alias) == 0) cfg->raw[i] = true;
    return rc;
}

static int vnode(kelp_field_sbroker_cfg *cfg, const char *val, kelp_diag *d)
{
    const char *v = val;
    if (kelp_util_strieq_n(v, strlen(v) < 6 ? strlen(v) : 6, "route=")) v += 6;
    while (*v == ' ') v++;
    kelp_field_broker_try t;
    memset(&t, 0, sizeof t);
    const char *colon = strrchr(v, ':');
    size_t hl = colon ? (size_t)(colon - v) : strlen(v);
    t.port = SB_VNODE_PORT;
    if ((colon && broker_port(colon + 1, strlen(colon + 1), &t.port) < 0) || hl == 0 || hl >= sizeof t.host ||
        memchr(v, ',', hl) || memchr(v, ' ', hl) || memchr(v, '=', hl)) {
        return kelp_fail(d, KELP_ERR_PARSE, "[route=]host[:port]");
    }
    memcpy(t.host, v, hl);
    for (unsigned i = 0; i < cfg->nvnodes; i++)
        if (strcmp(cfg->vnode[i].host, t.host) == 0 && cfg->vnode[i].port == t.port) {
            return kelp_fail(d, KELP_ERR_EXISTS, "duplicate try_vnode");
        }
    if (cfg->nvnodes >= KELP_BROKER_MAX_VNODES) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many try_vnode routes (KELP_BROKER_MAX_VNODES)");
    }
    cfg->vnode[cfg->nvnodes++] = t;
    return 1;
}

int kelp_field_sbroker_config(kelp_field_sbroker_cfg *cfg, const char *key, const char *val, kelp_diag *d)
{
    size_t kl = strlen(key);
    if (kelp_util_strieq_n(key, kl, "BRIDGE")) {
        kelp_field_broker_bridge b;
        if (kelp_field_broker_bridge_parse(val, &b, d) < 0) return KELP_ERR_PARSE;
        return raw_bridge(cfg, b.src, b.alias, d);
    }
    if (kelp_util_strieq_n(key, kl, "QBRIDGE")) return qbridge(cfg, val, d);
    if (kelp_util_strieq_n(key, kl, "KEYWORD")) {
        if (strlen(val) >= sizeof cfg->keyword || strpbrk(val, " ,=")) {
            return kelp_fail(d, KELP_ERR_PARSE, "one word without ',' or '=', up to 63 characters");
        }
        memcpy(cfg->keyword, val, strlen(val) + 1);
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "TRY_VNODE")) return vnode(cfg, val, d);
    bool *flag = kelp_util_strieq_n(key, kl, "WARNING_ON_STALE") ? &cfg->warn_stale
                 : kelp_util_strieq_n(key, kl, "AUTO_BRIDGE_REALMCAST") ? &cfg->auto_realmcast
                 : kelp_util_strieq_n(key, kl, "AUTO_BRIDGE_APPCAST") ? &cfg->auto_appcast
                 : kelp_util_strieq_n(key, kl, "AUTO_BRIDGE_MHASH") ? &cfg->auto_mhash
                                                                : NULL;
    if (flag) {
        if (!broker_bool(val, flag)) {
            return kelp_fail(d, KELP_ERR_PARSE, "true or false");
        }
        return 1;
    }
    return 0;
}

void kelp_field_sbroker_init(kelp_field_sbroker *s, const kelp_field_sbroker_cfg *cfg)
{
    memset(s, 0, sizeof *s);
    s->cfg = *cfg;
    s->vnode_reg_at = s->vnode_post_at = s->count_at = s->host_req_at = -1;
    s->cmd_at = -1e300; /* 24.8 starts at 0: long ago */
    s->cmd_interval = SB_CMD_INTERVAL;
    /* a full list keeps the user's bridges: an automatic one is dropped (no reason wanted) */
    if (s->cfg.auto_realmcast) (void)qbridge(&s->cfg, "REALMCAST_REQ", NULL);
    if (s->cfg.auto_appcast) (void)qbridge(&s->cfg, "APPCAST_REQ", NULL);
    if (s->cfg.auto_mhash) (void)raw_bridge(&s->cfg, "MISSION_HASH", "MISSION_HASH", NULL);
}

const char *kelp_field_sbroker_subscription(unsigned i)
{
    static const char *const subs[] = { "PHI_HOST_INFO", "NODE_BROKER_PING", "PSHARE_OUTPUT_SUMMARY" };
    return i < 3 ? subs[i] : NULL;
}

/* a run warning "<a><name><b>" */
static void warn(const kelp_field_sink *out, const char *a, const char *name, const char *b)
{
    if (!out->warn) return;
    char msg[160];
    size_t n = 0;
    if (field_put_str(msg, sizeof msg, &n, a) < 0 || field_put_str(msg, sizeof msg, &n, name) < 0 ||
        field_put_str(msg, sizeof msg, &n, b) < 0)
        return;
    out->warn(out->ctx, msg);
}

/* src with $V (upper case), $v (as received) and $N (index) expanded; KELP_ERR_NOSPACE when
 * the name does not fit */
static int expand(const char *src, const char *community, unsigned index, char *dst, size_t cap)
{
    size_t n = 0;
    for (const char *p = src; *p; p++) {
        char num[12];
        const char *put = NULL;
        char one[2] = { *p, 0 };
        bool upper = false;
        if (p[0] == '$' && (p[1] == 'V' || p[1] == 'v')) {
            put = community, upper = p[1] == 'V', p++;
        } else if (p[0] == '$' && p[1] == 'N') {
            kelp_util_snprintf(num, sizeof num, "%u", index);
            put = num, p++;
        } else
            put = one;
        for (; *put; put++) {
            if (n + 1 >= cap) return KELP_ERR_NOSPACE;
            char c = *put;
            dst[n++] = (char)(upper && c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
        }
    }
    dst[n] = 0;
    return KELP_OK;
}

static int reg(kelp_field_sbroker *s, const kelp_field_broker_node *nd, const char *src, const char *alias,
               const kelp_field_sink *out)
{
    char var[KELP_MAX_NAME];
    if (expand(src, nd->rec.community, nd->index, var, sizeof var) < 0) {
        warn(out, "bridge source too long for ", nd->rec.community, ": not registered");
        return 0;
    }
    if (broker_register(out, var, nd->rec.community, nd->rec.host, nd->rec.port_udp, alias, s->last_register,
                        sizeof s->last_register) < 0)
        return 0;
    s->registers++;
    return 1;
}

/* ---- UFSB_BRIDGE_VARS: a sorted set of names, each candidate made on demand ---- */

#define SB_ACK_SRC "NODE_BROKER_ACK_$V"
#define SB_PER_NODE (KELP_BROKER_MAX_BRIDGES + 1) /* the bridges, then the ack bridge */
#define SB_MAX_CANDS (SB_PER_NODE * (KELP_BROKER_MAX_NODES + 1))

/* candidate v: a BRIDGE line's src (v < MAX_BRIDGES), NODE_BROKER_ACK_$V (MAX_BRIDGES), or
 * bridge b expanded for node j (SB_PER_NODE * (j + 1) + b); "" when it does not fit */
static void cand(const kelp_field_sbroker *s, unsigned v, char *buf, size_t cap)
{
    buf[0] = 0;
    if (v < KELP_BROKER_MAX_BRIDGES) { /* as written, macros and all */
        size_t l = strlen(s->cfg.bridge[v].src);
        if (l < cap) memcpy(buf, s->cfg.bridge[v].src, l + 1);
        return;
    }
    if (v == KELP_BROKER_MAX_BRIDGES) {
        memcpy(buf, SB_ACK_SRC, sizeof SB_ACK_SRC);
        return;
    }
    const kelp_field_broker_node *nd = &s->node[v / SB_PER_NODE - 1];
    unsigned b = v % SB_PER_NODE;
    unsigned index = s->cfg.pmb ? nd->index : v / SB_PER_NODE; /* 24.8: $N is the position in the list */
    if (expand(b < s->cfg.nbridges ? s->cfg.bridge[b].src : SB_ACK_SRC, nd->rec.community, index, buf, cap) < 0)
        buf[0] = 0;
}

static void post_bridge_vars(kelp_field_sbroker *s, const kelp_field_sink *out)
{
    KELP_STATIC_ASSERT(sizeof s->ws_idx / sizeof s->ws_idx[0] >= SB_MAX_CANDS, "ws_idx too small");
    uint16_t *idx = s->ws_idx;
    unsigned n = 0;
    for (unsigned i = 0; i < s->cfg.nbridges; i++)
        if (s->cfg.raw[i]) idx[n++] = (uint16_t)i;
    idx[n++] = KELP_BROKER_MAX_BRIDGES;
    for (unsigned j = 0; j < s->nnodes; j++) {
        unsigned inset = s->cfg.pmb ? (s->node[j].bridged ? s->cfg.nbridges + 1 : 0) : s->node[j].nset;
        for (unsigned b = 0; b < inset; b++)
            idx[n++] = (uint16_t)(SB_PER_NODE * (j + 1) + (b < s->cfg.nbridges ? b : KELP_BROKER_MAX_BRIDGES));
    }
    char a[KELP_MAX_NAME], c[KELP_MAX_NAME];
    for (unsigned gap = n / 2; gap > 0; gap /= 2) /* shell sort, by name (strcmp: std::set's order) */
        for (unsigned i = gap; i < n; i++) {
            uint16_t t = idx[i];
            cand(s, t, a, sizeof a);
            unsigned j = i;
            for (; j >= gap; j -= gap) {
                cand(s, idx[j - gap], c, sizeof c);
                if (strcmp(c, a) <= 0) break;
                idx[j] = idx[j - gap];
            }
            idx[j] = t;
        }
    char *list = s->ws;
    size_t len = 0;
    c[0] = 0;
    list[0] = 0;
    for (unsigned i = 0; i < n; i++) {
        cand(s, idx[i], a, sizeof a);
        if (!a[0] || strcmp(a, c) == 0) continue;
        size_t l = strlen(a);
        if (len + (len ? 1 : 0) + l + 1 > sizeof s->ws) break; /* the longest string a variable holds */
        if (len) list[len++] = ',';
        memcpy(list + len, a, l + 1);
        len += l;
        memcpy(c, a, l + 1);
    }
    out->publish(out->ctx, "UFSB_BRIDGE_VARS", true, list, 0);
}

static kelp_field_broker_node *find(kelp_field_sbroker *s, const char *community, const kelp_field_sink *out)
{
    for (unsigned i = 0; i < s->nnodes; i++)
        if (kelp_util_strieq_n(s->node[i].rec.community, strlen(s->node[i].rec.community), community)) return &s->node[i];
    if (s->nnodes >= KELP_BROKER_MAX_NODES) {
        s->full++;
        warn(out, "too many vehicles (KELP_BROKER_MAX_NODES): ", community, " ignored");
        return NULL;
    }
    kelp_field_broker_node *nd = &s->node[s->nnodes++];
    memset(nd, 0, sizeof *nd);
    return nd;
}

static int ping_mail(kelp_field_sbroker *s, const char *sval, kelp_time now, const kelp_field_sink *out)
{
    kelp_field_broker_host *h = &s->ws_host; /* (a workspace) */
    s->pings++;
    if (kelp_field_broker_host_parse(sval, h, NULL) < 0 || !h->community[0] || strpbrk(h->community, " ")) {
        s->bad_pings++;
        return KELP_ERR_PARSE;
    }
    if (!s->have_shore) {
        s->early_pings++; /* nothing to ack with until our own host info is complete */
        return 1;
    }
    kelp_field_broker_node *nd = find(s, h->community, out);
    if (!nd) return KELP_ERR_NOSPACE;
    nd->pings++;
    nd->last_ping = now;
    nd->stale = false;
    nd->skew = h->have_time ? now - h->time : 0;
    if (!kelp_field_broker_host_complete(h)) {
        if (!nd->rec.community[0]) memcpy(nd->rec.community, h->community, sizeof h->community);
        kelp_util_snprintf(nd->status, sizeof nd->status, "invalid");
        s->bad_pings++;
        return KELP_ERR_PARSE;
    }
    nd->rec = *h;
    if (!h->have_warp || h->warp != s->cfg.warp) {
        char w[2][24];
        size_t n0 = 0, n1 = 0;
        if (field_put_fixed(w[0], sizeof w[0], &n0, s->cfg.warp, 6, true) < 0) kelp_util_snprintf(w[0], sizeof w[0], "?");
        if (!h->have_warp || field_put_fixed(w[1], sizeof w[1], &n1, h->warp, 6, true) < 0) kelp_util_snprintf(w[1], sizeof w[1], "?");
        kelp_util_snprintf(nd->status, sizeof nd->status, "timewarp (%s!=%s)", w[0], w[1]);
        return 1;
    }
    if (s->cfg.keyword[0] && strcmp(s->cfg.keyword, h->keyword) != 0) {
        kelp_util_snprintf(nd->status, sizeof nd->status, "keyword");
        return 1;
    }
    kelp_util_snprintf(nd->status, sizeof nd->status, "ok");
    if (!nd->index) nd->index = ++s->naccepted;
    bool moved = nd->bridged && (strcmp(nd->bridged_host, h->host) != 0 || nd->bridged_port != h->port_udp);
    if (!nd->bridged || moved) {
        (void)reg(s, nd, SB_ACK_SRC, "NODE_BROKER_ACK", out);
        for (unsigned i = 0; i < s->cfg.nbridges; i++) (void)reg(s, nd, s->cfg.bridge[i].src, s->cfg.bridge[i].alias, out);
        memcpy(nd->bridged_host, h->host, sizeof h->host);
        nd->bridged_port = h->port_udp;
        if (!nd->bridged) {
            nd->bridged = true;
            post_bridge_vars(s, out); /* new names: this vehicle's (a move adds none) */
        }
    }
    char var[KELP_MAX_NAME], *ack = s->ws; /* (the workspace: not in use here) */
    if (expand("NODE_BROKER_ACK_$V", h->community, nd->index, var, sizeof var) < 0 ||
        broker_host_format(&s->shore, s->cfg.keyword, s->cfg.warp, now, "ok", ack, sizeof s->ws) < 0)
        return KELP_ERR_RANGE;
    out->publish(out->ctx, var, true, ack, 0);
    out->publish(out->ctx, "NODE_BROKER_VACK", true, h->community, 0);
    nd->acks++;
    s->acks++;
    return 1;
}

/* the shoreside's own PHI_HOST_INFO (out of line: its host record is not on the ping path) */
KELP_NOINLINE static int host_info(kelp_field_sbroker *s, bool is_string, const char *sval)
{
    kelp_field_broker_host *h = &s->ws_host;
    s->phi++;
    if (!is_string || kelp_field_broker_host_parse(sval, h, NULL) < 0 || !kelp_field_broker_host_complete(h))
        return KELP_ERR_PARSE;
    s->shore = *h;
    s->have_shore = true;
    return 1;
}

KELP_NOINLINE static int seed_mail(kelp_field_sbroker *s, const char *var, bool is_string, const char *sval, kelp_time now,
                     const kelp_field_sink *out)
{
    if (strcmp(var, "PHI_HOST_INFO") == 0) return host_info(s, is_string, sval);
    if (strcmp(var, "NODE_BROKER_PING") == 0) {
        if (!is_string || !sval) {
            s->pings++, s->bad_pings++;
            return KELP_ERR_PARSE;
        }
        return ping_mail(s, sval, now, out);
    }
    return 0;
}

/* UFSB_QBRIDGE_VARS: the QBRIDGE names, sorted (24.8 posts them at start-up) */
KELP_NOINLINE static int qvars(kelp_field_sbroker *s, const kelp_field_sink *out)
{
    if (!s->qvars_posted) { /* the QBRIDGE names, sorted (24.8 posts them at start-up) */
        char *list = s->ws;
        size_t len = 0;
        const char *prev = "";
        list[0] = 0;
        for (;;) {
            const char *next = NULL;
            for (unsigned i = 0; i < s->cfg.nqbridge; i++)
                if (strcmp(s->cfg.qbridge[i], prev) > 0 && (!next || strcmp(s->cfg.qbridge[i], next) < 0))
                    next = s->cfg.qbridge[i];
            if (!next) break;
            if ((len && field_put_str(list, sizeof s->ws, &len, ",") < 0) || field_put_str(list, sizeof s->ws, &len, next) < 0) break;
            prev = next;
        }
        out->publish(out->ctx, "UFSB_QBRIDGE_VARS", true, list, 0);
        s->qvars_posted = true;
        return 1;
    }
    return 0;
}

/* stale warnings (no ping for 10 s) and UFSB_NODE_COUNT (on a change, else every 30 s) */
KELP_NOINLINE static int stale_and_count(kelp_field_sbroker *s, kelp_time now, const kelp_field_sink *out)
{
    for (unsigned i = 0; i < s->nnodes; i++) {
        kelp_field_broker_node *nd = &s->node[i];
        bool stale = now - nd->last_ping > KELP_BROKER_STALE;
        if (stale && !nd->stale && s->cfg.warn_stale) warn(out, "Node ", nd->rec.community, " is stale.");
        nd->stale = stale;
    }
    if (s->nnodes == s->count_posted && s->count_at >= 0 && now - s->count_at <= SB_COUNT_EVERY) return 0;
    out->publish(out->ctx, "UFSB_NODE_COUNT", false, NULL, s->nnodes);
    s->count_posted = s->nnodes;
    s->count_at = now;
    return 1;
}

KELP_NOINLINE static int seed_iterate(kelp_field_sbroker *s, kelp_time now, const kelp_field_sink *out)
{
    int posts = qvars(s, out);
    if (!s->have_shore && (s->host_req_at < 0 || now - s->host_req_at >= KELP_BROKER_HOST_REQ_PERIOD)) {
        out->publish(out->ctx, "HOST_INFO_REQUEST", true, "true", 0); /* pHostInfo may have posted before we listened */
        s->host_req_at = now;
        posts++;
    }
    posts += stale_and_count(s, now, out);
    if (s->cfg.nvnodes && (s->vnode_reg_at < 0 || now - s->vnode_reg_at > SB_VNODE_REG_EVERY)) {
        for (unsigned i = 0; i < s->cfg.nvnodes; i++)
            if (broker_register(out, "TRY_SHORE_HOST", NULL, s->cfg.vnode[i].host, s->cfg.vnode[i].port,
                                "TRY_SHORE_HOST", s->last_register, sizeof s->last_register) > 0)
                s->registers++, posts++;
        s->vnode_reg_at = now;
    }
    if (s->cfg.nvnodes && s->have_shore && (s->vnode_post_at < 0 || now - s->vnode_post_at > SB_VNODE_POST_EVERY)) {
        char v[KELP_BROKER_MSG];
        kelp_util_snprintf(v, sizeof v, "pshare_route=%s:%u", s->shore.host, s->shore.port_udp);
        out->publish(out->ctx, "TRY_SHORE_HOST", true, v, 0);
        s->vnode_post_at = now;
        posts++;
    }
    return posts;
}

static int seed_report(const kelp_field_sbroker *s, kelp_time now, char *buf, size_t cap)
{
    size_t n = 0, wn = 0;
    bool full = false;
    char warp[24];
    if (field_put_fixed(warp, sizeof warp, &wn, s->cfg.warp, 6, true) < 0) kelp_util_snprintf(warp, sizeof warp, "?");
    broker_put(buf, cap, &n, &full,
               "ShoreBroker Status ----- (%lu)\n"
               "MOOS Time Warp:          %s\n"
               "Total PHI_HOST_INFO    received: %lu\n"
               "Total NODE_BROKER_PING received: %lu\n"
               "Total NODE_BROKER_ACK    posted: %lu\n"
               "Total PMB_REGISTER      posted: %lu\n\n"
               "%-13s %-12s %-10s %-8s %s\n-----\n",
               s->iterations, warp, s->phi, s->pings, s->acks, s->registers, "Node", "IPAddress", "Status", "Elapsed",
               "Skew");
    for (unsigned i = 0; i < s->nnodes; i++) {
        const kelp_field_broker_node *nd = &s->node[i];
        broker_put(buf, cap, &n, &full, "%-13s %-12s %-10s %-8.1f %.4f\n", nd->rec.community, nd->rec.host, nd->status,
                   now - nd->last_ping, nd->skew);
    }
    if (!s->have_shore) broker_put(buf, cap, &n, &full, "(waiting for a complete PHI_HOST_INFO: %lu pings ignored)\n",
                                   s->early_pings);
    return full ? KELP_ERR_NOSPACE : KELP_OK;
}

/* ------------------------------------------------------------------ 24.8 */

/* "localhost" in s replaced by ip, into dst */
static void localhost_to(char *dst, size_t cap, const char *s, const char *ip)
{
    size_t n = 0;
    dst[0] = 0;
    for (const char *p = s; *p;) {
        if (strncmp(p, "localhost", 9) == 0) {
            field_putf(dst, cap, &n, "%s", ip);
            p += 9;
        } else
            field_putf(dst, cap, &n, "%c", *p++);
    }
}

static int ping24(kelp_field_sbroker *s, const char *sval, kelp_time now, const kelp_field_sink *out)
{
    kelp_field_broker_host *h = &s->ws_host;
    s->pings++;
    if (kelp_field_broker_host_parse(sval, h, NULL) < 0 || !kelp_field_broker_host_valid(h)) {
        s->bad_pings++;
        if (out->warn) out->warn(out->ctx, "Invalid Incoming NODE_BROKER_PING");
        return KELP_ERR_PARSE;
    }
    /* the answer: ok, a time warp other than ours (as strings: 24.8 compares its own warp
     * with 5 decimals, trailing zeros dropped), or another keyword */
    char status[KELP_MAX_NAME], ours[24];
    size_t wn = 0;
    if (field_put_fixed(ours, sizeof ours, &wn, s->cfg.warp, 5, true) < 0) kelp_util_snprintf(ours, sizeof ours, "?");
    kelp_util_snprintf(status, sizeof status, "ok");
    if (strcmp(ours, h->warp_s) != 0) {
        kelp_util_snprintf(status, sizeof status, "timewarp (%s!=%s)", ours, h->warp_s);
        if (out->warn) out->warn(out->ctx, status);
    }
    if (s->cfg.keyword[0] && strcmp(s->cfg.keyword, h->keyword) != 0) kelp_util_snprintf(status, sizeof status, "keyword_mismatch");
    double skew = now - (h->have_time ? h->time : 0);
    for (unsigned j = 0; j < s->nnodes; j++) {
        kelp_field_broker_node *nd = &s->node[j];
        if (strcmp(nd->rec.community, h->community) != 0) continue;
        nd->last_ping = now; /* a known vehicle: its first record stays (24.8) */
        nd->skew += skew;
        nd->pings++;
        memcpy(nd->status, status, sizeof nd->status);
        return 1;
    }
    if (s->nnodes >= KELP_BROKER_MAX_NODES) {
        s->full++;
        warn(out, "too many vehicles (KELP_BROKER_MAX_NODES): ", h->community, " ignored");
        return KELP_ERR_NOSPACE;
    }
    kelp_field_broker_node *nd = &s->node[s->nnodes++];
    memset(nd, 0, sizeof *nd);
    nd->rec = *h;
    if (strcmp(h->host, s->shore.host) != 0) localhost_to(nd->rec.iroutes, sizeof nd->rec.iroutes, h->iroutes, h->host);
    memcpy(nd->status, status, sizeof nd->status);
    nd->skew = skew;
    nd->last_ping = now;
    nd->pings = 1;
    nd->index = s->nnodes;
    s->ack_bridge = true;          /* NODE_BROKER_ACK_$V -> NODE_BROKER_ACK, from now on */
    s->cmd_interval = SB_CMD_INTERVAL;
    return 1;
}

/* PSHARE_OUTPUT_SUMMARY lists src -> "dest" (24.8's handleMailShareSummary) */
static bool shared_already(const kelp_field_sbroker *s, const char *src, const char *dest)
{
    size_t pos = 0, len = strlen(s->summary), il, dl = strlen(dest), sl = strlen(src);
    const char *it;
    while (field_next_item(s->summary, len, &pos, ',', &it, &il) == 1) {
        const char *arrow = NULL;
        for (size_t i = 0; i + 1 < il && !arrow; i++)
            if (it[i] == '-' && it[i + 1] == '>') arrow = it + i;
        if (!arrow || (size_t)(arrow - it) != sl || strncmp(it, src, sl) != 0) continue;
        const char *d = arrow + 2, *end = it + il;
        while (d < end) {
            const char *e = d;
            while (e < end && *e != '&') e++;
            const char *a = d, *b = e;
            while (a < b && *a == ' ') a++;
            while (b > a && b[-1] == ' ') b--;
            if ((size_t)(b - a) == dl && strncmp(a, dest, dl) == 0) return true;
            d = e + 1;
        }
    }
    return false;
}

/* is name in UFSB_BRIDGE_VARS's set already? */
static bool in_set(const kelp_field_sbroker *s, const char *name)
{
    char c[KELP_MAX_NAME];
    for (unsigned i = 0; i < s->cfg.nbridges; i++)
        if (s->cfg.raw[i] && strcmp(s->cfg.bridge[i].src, name) == 0) return true;
    if (s->ack_bridge && strcmp(SB_ACK_SRC, name) == 0) return true;
    for (unsigned j = 0; j < s->nnodes; j++)
        for (unsigned b = 0; b < s->node[j].nset; b++) {
            cand(s, SB_PER_NODE * (j + 1) + (b < s->cfg.nbridges ? b : KELP_BROKER_MAX_BRIDGES), c, sizeof c);
            if (strcmp(c, name) == 0) return true;
        }
    return false;
}

/* bridge k (the ack bridge when k == nbridges) requested for vehicle j */
static void request(kelp_field_sbroker *s, unsigned j, unsigned k, const kelp_field_sink *out)
{
    kelp_field_broker_node *nd = &s->node[j];
    const char *src = k < s->cfg.nbridges ? s->cfg.bridge[k].src : SB_ACK_SRC;
    const char *alias = k < s->cfg.nbridges ? s->cfg.bridge[k].alias : "NODE_BROKER_ACK";
    char var[KELP_MAX_NAME];
    if (expand(src, nd->rec.community, j + 1, var, sizeof var) < 0) {
        warn(out, "bridge source too long for ", nd->rec.community, ": not requested");
        return;
    }
    char *t = s->ws;
    size_t n = 0;
    field_putf(t, sizeof s->ws, &n, "%lu", s->tests++);
    out->publish(out->ctx, "PSHARE_TEST", true, t, 0);
    n = 0;
    field_putf(t, sizeof s->ws, &n, "%s:%s", alias, nd->rec.iroutes);
    bool needed = !shared_already(s, var, t);
    n = 0;
    field_putf(t, sizeof s->ws, &n, "%s->%s:%s", var, alias, nd->rec.iroutes);
    out->publish(out->ctx, "PSHARE_TEST", true, t, 0);
    out->publish(out->ctx, "PSHARE_TEST", true, needed ? "needed=true" : "needed=false", 0);
    if (needed) (void)broker_pshare_cmd(out, var, alias, nd->rec.iroutes, s->last_register, sizeof s->last_register);
    s->pshare_cmds++;
    if (k >= nd->nset) {
        bool fresh = !in_set(s, var);
        nd->nset = k + 1;
        if (fresh) post_bridge_vars(s, out);
    }
}

KELP_NOINLINE static int iterate24(kelp_field_sbroker *s, kelp_time now, const kelp_field_sink *out)
{
    int posts = qvars(s, out);
    /* every bridge for every vehicle, 5 s after a new vehicle, the gap growing by 3 s a pass */
    if (now - s->cmd_at >= s->cmd_interval) {
        s->cmd_at = now;
        s->cmd_interval += SB_CMD_GROWTH;
        for (unsigned j = 0; j < s->nnodes; j++)
            for (unsigned k = 0; k < s->cfg.nbridges + (s->ack_bridge ? 1u : 0u); k++) request(s, j, k, out);
    }
    /* the acks: every vehicle heard in the last 10 s, every iteration */
    if (s->have_shore) {
        char *ack = s->ws;
        for (unsigned j = 0; j < s->nnodes; j++) {
            kelp_field_broker_node *nd = &s->node[j];
            if (!(now - nd->last_ping < KELP_BROKER_ACK_WINDOW)) continue;
            char var[KELP_MAX_NAME];
            size_t n = 0;
            if (expand("NODE_BROKER_ACK_$V", nd->rec.community, 0, var, sizeof var) < 0 ||
                kelp_field_broker_host_spec(&s->shore, NULL, NULL, ack, sizeof s->ws) < 0)
                continue;
            n = strlen(ack);
            field_putf(ack, sizeof s->ws, &n, ",status=%s", nd->status);
            if (nd->rec.key[0]) field_putf(ack, sizeof s->ws, &n, ",key=%s", nd->rec.key);
            field_putf(ack, sizeof s->ws, &n, ",id=%lu", s->acks);
            out->publish(out->ctx, var, true, ack, 0);
            out->publish(out->ctx, "NODE_BROKER_VACK", true, nd->rec.community, 0);
            nd->acks++;
            posts += 2;
        }
        s->acks++;
    }
    posts += stale_and_count(s, now, out);
    if (s->vnode_reg_at < 0 || now - s->vnode_reg_at > SB_VNODE_REG_EVERY) {
        s->vnode_reg_at = now;
        for (unsigned i = 0; i < s->cfg.nvnodes; i++) {
            char route[KELP_BROKER_ROUTE];
            kelp_util_snprintf(route, sizeof route, "%s:%u", s->cfg.vnode[i].host, s->cfg.vnode[i].port);
            if (broker_pshare_cmd(out, "TRY_SHORE_HOST", "TRY_SHORE_HOST", route, s->last_register,
                                  sizeof s->last_register) > 0)
                s->pshare_cmds++, posts++;
        }
    }
    if (s->vnode_post_at < 0 || now - s->vnode_post_at > SB_VNODE_POST_EVERY) {
        s->vnode_post_at = now;
        for (unsigned i = 0; i < s->cfg.nvnodes && s->shore.host[0] && s->shore.have_port_udp; i++) {
            char v[KELP_BROKER_ROUTE + 16];
            kelp_util_snprintf(v, sizeof v, "pshare_route=%s:%u", s->shore.host, s->shore.port_udp);
            out->publish(out->ctx, "TRY_SHORE_HOST", true, v, 0);
            posts++;
        }
    }
    return posts;
}

KELP_NOINLINE static int mail24(kelp_field_sbroker *s, const char *var, bool is_string, const char *sval, kelp_time now,
                  const kelp_field_sink *out)
{
    if (strcmp(var, "NODE_BROKER_PING") == 0) return ping24(s, is_string && sval ? sval : "", now, out);
    if (strcmp(var, "PHI_HOST_INFO") == 0) {
        s->phi++;
        if (!is_string || !sval || kelp_field_broker_host_parse(sval, &s->shore, NULL) < 0 || !kelp_field_broker_host_valid(&s->shore)) {
            memset(&s->shore, 0, sizeof s->shore); /* 24.8 keeps an empty record */
            s->have_shore = false;
            return KELP_ERR_PARSE;
        }
        s->have_shore = true;
        return 1;
    }
    if (strcmp(var, "PSHARE_OUTPUT_SUMMARY") == 0) {
        if (!is_string || !sval) return KELP_ERR_PARSE;
        size_t l = strlen(sval);
        if (l >= sizeof s->summary) l = sizeof s->summary - 1;
        memcpy(s->summary, sval, l);
        s->summary[l] = 0;
        return 1;
    }
    return 0;
}

typedef struct rep_ctx {
    const kelp_field_sbroker *s;
    kelp_time now;
} rep_ctx;

/* 24.8's vehicle table; a vehicle's further input routes are joined in its row (24.8 gives
 * each its own row) */
static const char *node_cell(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap)
{
    static const char *const head[2][6] = { { "Node", "IP", "", "Elap", "pShare", "" },
                                            { "Name", "Address", "Status", "Time", "Input Route(s)", "Skew" } };
    const rep_ctx *c = ctx;
    if (row < 2) return head[row][col];
    const kelp_field_broker_node *nd = &c->s->node[row - 2];
    switch (col) {
    case 0: return nd->rec.community;
    case 1: return nd->rec.host;
    case 2: return nd->status;
    case 3: kelp_util_snprintf(tmp, cap, "%.1f", c->now - nd->last_ping); return tmp;
    case 4: return nd->rec.iroutes;
    default: kelp_util_snprintf(tmp, cap, "%.4f", nd->pings ? nd->skew / (double)nd->pings : 0.0); return tmp;
    }
}

static int report24(const kelp_field_sbroker *s, kelp_time now, char *buf, size_t cap)
{
    size_t n = 0;
    bool full = false;
    static const char rule[] = "===========================================================\n";
    const kelp_field_broker_host *h = &s->shore;
    char port_db[12] = "";
    if (h->have_port_db) kelp_util_snprintf(port_db, sizeof port_db, "%u", h->port_db);
    broker_put(buf, cap, &n, &full,
               "\n Total PHI_HOST_INFO    received: %lu\n Total NODE_BROKER_PING received: %lu\n"
               " Total NODE_BROKER_ACK    posted: %lu\n Total PSHARE_CMD         posted: %lu\n\n"
               "%s            Shoreside Node(s) Information:\n%s\n"
               "     Community: %s\n        HostIP: %s\n   Port MOOSDB: %s\n     Time Warp: %s\n",
               s->phi, s->pings, s->acks, s->pshare_cmds, rule, rule, h->community, h->host, port_db, h->warp_s);
    broker_block(buf, cap, &n, &full, "       IRoutes: ", h->iroutes, 1, '&');
    broker_put(buf, cap, &n, &full, "\n%s             Vehicle Node Information:\n%s\n", rule, rule);
    rep_ctx c = { s, now };
    broker_table(buf, cap, &n, &full, 6, 2 + s->nnodes, 2, node_cell, &c);
    return full ? KELP_ERR_NOSPACE : KELP_OK;
}

/* the time step rule (docs/ARCHITECTURE.md): a `now` that is no time is refused; after a step
 * back every stored time of this clock moves back by the step (the bridge-request pass, the
 * counts, the vehicles' last pings: none stalls or goes stale for the step) */
static bool clock_ok(kelp_field_sbroker *s, kelp_time now)
{
    if (!kelp_util_time_ok(now)) return false;
    double back = kelp_util_clock_back(&s->clock, now);
    if (back > 0) {
        double *t[] = { &s->host_req_at, &s->vnode_reg_at, &s->vnode_post_at, &s->count_at, &s->cmd_at };
        for (size_t i = 0; i < sizeof t / sizeof t[0]; i++)
            if (*t[i] > -KELP_TIME_LIMIT && *t[i] != -1) *t[i] -= back; /* not "never" (-1, -1e300) */
        for (unsigned i = 0; i < s->nnodes; i++) s->node[i].last_ping -= back;
    }
    return true;
}

int kelp_field_sbroker_mail(kelp_field_sbroker *s, const char *var, bool is_string, const char *sval, kelp_time now,
                            const kelp_field_sink *out)
{
    if (!clock_ok(s, now)) return KELP_ERR_ARG;
    return s->cfg.pmb ? seed_mail(s, var, is_string, sval, now, out) : mail24(s, var, is_string, sval, now, out);
}

int kelp_field_sbroker_iterate(kelp_field_sbroker *s, kelp_time now, const kelp_field_sink *out)
{
    if (!clock_ok(s, now)) return 0;
    s->iterations++;
    return s->cfg.pmb ? seed_iterate(s, now, out) : iterate24(s, now, out);
}

int kelp_field_sbroker_report(const kelp_field_sbroker *s, kelp_time now, char *buf, size_t cap)
{
    if (!buf || cap == 0) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    return s->cfg.pmb ? seed_report(s, now, buf, cap) : report24(s, now, buf, cap);
}
