/* kelp-bridge: forward variables between communities over UDP, as pShare (MOOS-IvP 24.8; any
 * name but pMOOSBridge: input/output blocks, <NAME>_CMD at run time, PSHARE_*_SUMMARY every
 * second; multicast_N routes on multicast_address:multicast_base_port+N; an output's frequency,
 * duration and max_shares as 24.8 applies them) or as the seed's pMOOSBridge (UDPListen,
 * UDPSHARE, PMB_REGISTER, PMB_UDP_LISTEN). Both: KEY (HMAC-SHA256) and ALLOW (the names
 * received datagrams may publish here). A bridged variable is never forwarded again, a route
 * is added once, a replayed datagram is refused (kelp/bridge.h); the datagrams are kelp's. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <mbedtls/md.h>
#include <kelp/app.h>
#include <kelp/bridge.h>
#include <kelp/edge/udp.h>

#define MAX_ROUTES 256
#define MAX_INPUTS 8
#define MAX_PEERS 64
#define DGRAM_MAX 65536 /* any UDP datagram whole; larger than KELP_BRIDGE_DGRAM_MAX */

typedef struct bridge {
    bool pshare;                 /* the pShare role (else pMOOSBridge) */
    char cmd_var[KELP_MAX_NAME]; /* PMB_REGISTER or <NAME>_CMD */
    int sock, in_fd[MAX_INPUTS];
    uint8_t key[256];
    size_t keylen;
    kelp_bridge_route rt[MAX_ROUTES], in[MAX_INPUTS];
    struct sockaddr_in addr[MAX_ROUTES];
    unsigned long sent[MAX_ROUTES];
    kelp_bridge_share share[MAX_ROUTES]; /* pShare's per-route limits' state */
    char mc_group[64];                   /* multicast_address */
    unsigned mc_base;                    /* multicast_base_port */
    size_t nroutes, ninputs;
    char allow[2048]; /* comma-separated ALLOW entries; "" allows every name */
    kelp_bridge_tx btx;
    kelp_bridge_rx brx;
    kelp_bridge_peer peers[MAX_PEERS];
    unsigned long rx, rx_auth_fail, rx_bad, rx_replay, rx_denied, rx_oversize, tx, tx_err, tx_oversize, reg_ok,
        reg_bad;
    double summary_at;
    kelp_var *rxv;
    char summary[KELP_MAX_SVAL];
    uint8_t buf[DGRAM_MAX];
} bridge;

static int hmac_sha256(const uint8_t *key, size_t keylen, const uint8_t *data, size_t len, uint8_t out[32], void *user)
{
    (void)user;
    return mbedtls_md_hmac(mbedtls_md_info_from_type(MBEDTLS_MD_SHA256), key, keylen, data, len, out) ? KELP_ERR_CRYPTO : 0;
}

/* route i shares v when its limits allow (pShare's rule); counts the share */
static void send_route(kelp_app *app, bridge *b, size_t i, const kelp_var *v, double now)
{
    if (!b->addr[i].sin_family || !kelp_bridge_share_active(&b->rt[i], &b->share[i], now)) return;
    size_t len = 0;
    int rc = kelp_bridge_frame(&b->btx, v, b->rt[i].alias, b->key, b->keylen, hmac_sha256, NULL, b->buf,
                               KELP_BRIDGE_DGRAM_MAX, &len);
    if (rc == KELP_ERR_NOSPACE) b->tx_oversize++, kelp_app_run_warning(app, "%s is too large for one datagram", v->name);
    else if (rc < 0) b->tx_err++;
    else if (kelp_udp_send(b->sock, &b->addr[i], b->buf, len) < 0)
        b->tx_err++, kelp_app_run_warning(app, "send to %s:%u failed: %s", b->rt[i].host, b->rt[i].port, strerror(errno));
    else b->tx++, b->sent[i]++, b->share[i].done++, b->share[i].last_sent = now;
}

/* 24.8: stating a route again resets its limits and its clock (kelp_bridge_share_restate) */
static void restate_route(kelp_app *app, bridge *b, const kelp_bridge_route *r)
{
    long i = kelp_bridge_table_find(b->rt, b->nroutes, r);
    if (i < 0 || !kelp_bridge_share_restate(&b->rt[i], &b->share[i], r, kelp_app_time(app))) return;
    const kelp_var *v = kelp_bus_cached(kelp_app_bus(app), r->src);
    if (v) send_route(app, b, (size_t)i, v, kelp_app_time(app));
}

static int add_route(kelp_app *app, bridge *b, const kelp_bridge_route *r)
{
    size_t at = b->nroutes;
    int rc = kelp_bridge_table_add(b->rt, &b->nroutes, MAX_ROUTES, r);
    if (rc <= 0) {
        if (rc < 0) kelp_app_run_warning(app, "too many routes (max %d)", MAX_ROUTES);
        else restate_route(app, b, r);
        return rc; /* 0: already bridged, no duplicates */
    }
    memset(&b->addr[at], 0, sizeof b->addr[at]), b->sent[at] = 0;
    b->share[at] = (kelp_bridge_share){ .created = kelp_app_time(app) };
    if (r->multicast) {
        if (kelp_udp_resolve(b->mc_group, (uint16_t)(b->mc_base + r->port), &b->addr[at]) < 0)
            kelp_app_run_warning(app, "bad multicast_address %s: %s not sent", b->mc_group, r->src);
    } else if (kelp_udp_resolve(r->host, r->port, &b->addr[at]) < 0) /* kept, never sent (as pShare) */
        kelp_app_run_warning(app, "cannot resolve host %s: %s not sent there", r->host, r->src);
    bool first = true; /* register once per distinct source */
    for (size_t i = 0; i < at; i++) first = first && strcmp(b->rt[i].src, r->src) != 0;
    if (first && kelp_app_register(app, r->src, 0) < 0) kelp_app_run_warning(app, "cannot register %s", r->src);
    kelp_app_event(app, "bridge %s -> %s:%u as %s", r->src, r->multicast ? "multicast" : r->host, r->port,
                   r->alias[0] ? r->alias : r->src);
    return 1;
}

static void on_udp(kelp_app *app, void *st, int fd)
{
    bridge *b = st;
    size_t n = 0;
    int got;
    while ((got = kelp_udp_recv(fd, b->buf, sizeof b->buf, &n)) > 0) {
        b->rx++;
        if (n > sizeof b->buf || n > KELP_BRIDGE_DGRAM_MAX) {
            b->rx_oversize++, kelp_app_run_warning(app, "oversize datagram (%zu bytes): dropped", n);
            continue;
        }
        int rc = kelp_bridge_unframe(&b->brx, b->buf, n, b->key, b->keylen, hmac_sha256, NULL, b->rxv);
        if (rc == KELP_ERR_AUTH) b->rx_auth_fail++, kelp_app_run_warning(app, "datagram failed authentication: dropped");
        else if (rc == KELP_ERR_REPLAY)
            b->rx_replay++, kelp_app_run_warning(app, "replayed or stale datagram from %s: dropped", b->rxv->community);
        else if (rc == KELP_ERR_RANGE)
            b->rx_oversize++, kelp_app_run_warning(app, "oversize value (%zu-byte datagram, values up to %d bytes): dropped",
                                                   n, KELP_MAX_SVAL);
        else if (rc < 0) b->rx_bad++, kelp_app_run_warning(app, "malformed bridge datagram: %s", kelp_err_str(rc));
        else if (!kelp_bridge_allowed(b->allow, b->rxv->name)) {
            b->rx_denied++;
            kelp_app_run_warning(app, "%s from %s is not on the ALLOW list: dropped", b->rxv->name, b->rxv->community);
        } else if (kelp_bus_forward(kelp_app_bus(app), b->rxv) < 0)
            kelp_app_run_warning(app, "republish failed");
    }
    if (got < 0) kelp_app_run_warning(app, "UDP receive failed: %s", strerror(errno));
}

/* a listening route (an input); 1 added, 0 there already, <0 failed (reason in d) */
static int add_input(kelp_app *app, bridge *b, const kelp_bridge_route *r, kelp_diag *d)
{
    size_t at = b->ninputs;
    int rc = kelp_bridge_table_add(b->in, &b->ninputs, MAX_INPUTS, r);
    if (rc <= 0) return rc < 0 ? kelp_fail(d, rc, "too many inputs") : 0;
    b->in_fd[at] = r->multicast ? kelp_udp_open_group(b->mc_group, (uint16_t)(b->mc_base + r->port), 4 << 20, d)
                                : kelp_udp_open(r->port, 4 << 20, d);
    if (b->in_fd[at] < 0 || kelp_app_watch_fd(app, b->in_fd[at], on_udp) < 0) {
        b->ninputs--;
        return kelp_fail(d, KELP_ERR_IO, "cannot listen");
    }
    if (b->sock < 0 && !r->multicast) b->sock = b->in_fd[at]; /* send from the first listening port */
    return 1;
}

/* a PMB_REGISTER or a PSHARE_CMD / output / input line: <0 when it is not usable */
static int directive(kelp_app *app, bridge *b, const char *s, int kind, kelp_diag *d)
{
    kelp_bridge_route rs[16];
    size_t nr = 0;
    int rc = kind == 0   ? (nr = 1, kelp_bridge_parse_register(s, rs, d))
             : kind == 1 ? kelp_bridge_pshare_output(s, rs, 16, &nr, d)
                         : kelp_bridge_pshare_input(s, rs, 16, &nr, NULL, 0, d);
    for (size_t i = 0; i < nr && rc == 0; i++)
        if ((kind == 2 ? add_input(app, b, &rs[i], d) : add_route(app, b, &rs[i])) < 0) rc = KELP_ERR_IO;
    return rc;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    bridge *b = st;
    if (strcmp(v->name, b->cmd_var) == 0) {
        kelp_diag why;
        kelp_diag_clear(&why);
        int kind = !b->pshare ? 0 : v->kind == KELP_VAR_STRING ? kelp_bridge_pshare_cmd(v->sval) : -1;
        if (v->kind != KELP_VAR_STRING || kind < 0 ||
            (kind == 0 && b->pshare && kelp_fail(&why, KELP_ERR_PARSE, "cmd= is neither output nor input")) ||
            directive(app, b, v->sval, kind, &why) < 0)
            b->reg_bad++, kelp_app_run_warning(app, "bad %s (%s)", b->cmd_var, why.code ? kelp_diag_text(&why) : "not a string");
        else b->reg_ok++;
    }
    /* forward what belongs to this community and did not come through a bridge */
    if (v->flags & KELP_VAR_FLAG_BRIDGED) return;
    if (strcmp(v->community, kelp_app_community(app)) != 0) return;
    for (size_t i = 0; i < b->nroutes; i++)
        if (kelp_bus_match(b->rt[i].src, v->name)) send_route(app, b, i, v, kelp_app_time(app));
}

/* every line of `name` in the block through directive() (kind 0: UDPSHARE, 1 output, 2 input) */
static int lines(kelp_app *app, bridge *b, const char *name, int kind)
{
    for (const kelp_mission_node *n = kelp_app_param_next(app, name, NULL); n; n = kelp_app_param_next(app, name, n)) {
        char line[1024];
        kelp_bridge_route rs[16];
        size_t nr = 0;
        kelp_diag why;
        kelp_diag_clear(&why);
        if (kelp_mission_copy(n, line, sizeof line) < 0) return kelp_app_config_error(app, n, "%s too long", name);
        int rc = kind ? directive(app, b, line, kind, &why) : kelp_bridge_parse_share(line, rs, 16, &nr, &why);
        if (kind == 2 && rc == 0) /* a white_list joins the ALLOW list */
            KELP_IGNORE(kelp_bridge_pshare_input(line, rs, 16, &nr, b->allow + strlen(b->allow),
                                                 sizeof b->allow - strlen(b->allow), NULL));
        for (size_t i = 0; i < nr && kind == 0 && rc == 0; i++) rc = add_route(app, b, &rs[i]) < 0 ? KELP_ERR_IO : 0;
        if (rc < 0) return kelp_app_config_error(app, n, "bad %s: %s", name, why.code ? kelp_diag_text(&why) : "cannot add route");
    }
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    bridge *b = st;
    kelp_bus_set_bridge(kelp_app_bus(app), true); /* sees every community's writes */
    b->rxv = malloc(sizeof *b->rxv);
    b->sock = -1;
    b->summary_at = kelp_app_time(app);
    b->pshare = !kelp_util_strieq(kelp_app_name(app), "pMOOSBridge");
    if (b->pshare) {
        size_t i = 0; /* 24.8: <APPNAME>_CMD, upper case */
        for (const char *p = kelp_app_name(app); *p && i + 5 < sizeof b->cmd_var; p++)
            b->cmd_var[i++] = (char)(*p >= 'a' && *p <= 'z' ? *p - 'a' + 'A' : *p);
        memcpy(b->cmd_var + i, "_CMD", 5);
    } else memcpy(b->cmd_var, "PMB_REGISTER", sizeof "PMB_REGISTER");
    double port = 0;
    const kelp_mission_node *pn = kelp_app_param(app, "UDPListen");
    if (pn && (kelp_mission_double(pn, &port) < 0 || port < 1 || port > 65535 || port != (int)port))
        return kelp_app_config_error(app, pn, "UDPListen must be a port number 1-65535");
    char key[256];
    int kr = kelp_app_param_str(app, "KEY", key, sizeof key);
    if (kr < 0 || (kr > 0 && memcpy(b->key, key, b->keylen = strlen(key)) == NULL))
        return kelp_app_config_error(app, kelp_app_param(app, "KEY"), "KEY too long (max 255)");
    for (const kelp_mission_node *n = kelp_app_param_next(app, "ALLOW", NULL); n; n = kelp_app_param_next(app, "ALLOW", n)) {
        size_t used = strlen(b->allow);
        char one[1024];
        if (kelp_mission_copy(n, one, sizeof one) < 0 || used + strlen(one) + 2 > sizeof b->allow)
            return kelp_app_config_error(app, n, "ALLOW lists too long (max %zu characters)", sizeof b->allow - 1);
        snprintf(b->allow + used, sizeof b->allow - used, "%s%s", used ? "," : "", one);
    }
    struct timespec ts; /* this run's identity for the receivers' replay windows: its start in microseconds */
    clock_gettime(CLOCK_REALTIME, &ts);
    kelp_bridge_tx_init(&b->btx, (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u);
    kelp_bridge_rx_init(&b->brx, b->peers, MAX_PEERS);
    kelp_diag err = {0};
    if (port) {
        kelp_bridge_route r = { .port = (uint16_t)port };
        memcpy(r.host, "localhost", sizeof "localhost");
        if (add_input(app, b, &r, &err) < 0) return kelp_app_config_error(app, pn, "%s", kelp_diag_text(&err));
        if (!b->pshare) KELP_IGNORE(kelp_app_notify_double(app, "PMB_UDP_LISTEN", port));
    }
    /* pShare's multicast channels: multicast_N is multicast_address : multicast_base_port + N */
    memcpy(b->mc_group, KELP_PSHARE_MCAST_ADDR, sizeof KELP_PSHARE_MCAST_ADDR);
    b->mc_base = KELP_PSHARE_MCAST_PORT;
    const kelp_mission_node *mn = kelp_app_param(app, "multicast_address");
    struct sockaddr_in probe;
    if (mn && (kelp_mission_copy(mn, b->mc_group, sizeof b->mc_group) < 0 || kelp_udp_resolve(b->mc_group, 1, &probe) < 0 ||
               !IN_MULTICAST(ntohl(probe.sin_addr.s_addr))))
        return kelp_app_config_error(app, mn, "multicast_address must be an IPv4 multicast address (224.0.0.0/4)");
    double base = KELP_PSHARE_MCAST_PORT;
    mn = kelp_app_param(app, "multicast_base_port");
    if (mn && (kelp_mission_double(mn, &base) < 0 || base < 1 || base > 65535 - 255 || base != (int)base))
        return kelp_app_config_error(app, mn, "multicast_base_port must be a port number 1-65280");
    b->mc_base = (unsigned)base;
    (void)kelp_app_param(app, "verbose");
    if (lines(app, b, "input", 2) < 0) return -1;
    if (b->sock < 0 && (b->sock = kelp_udp_open(0, 0, &err)) < 0) return kelp_app_config_error(app, NULL, "%s", kelp_diag_text(&err));
    if (kelp_udp_multicast_tx(b->sock, 1) < 0) kelp_app_run_warning(app, "multicast sending not set up: %s", strerror(errno));
    if (lines(app, b, "output", 1) < 0) return -1;
    if (lines(app, b, "UDPSHARE", 0) < 0 || lines(app, b, "SHARE", 0) < 0) return -1;
    return kelp_app_register(app, b->cmd_var, 0);
}

static int iterate(kelp_app *app, void *st, double now)
{
    bridge *b = st;
    if (!b->pshare || now - b->summary_at < 1.0) return 0; /* pShare's summaries, every second */
    b->summary_at = now;
    KELP_IGNORE(kelp_bridge_pshare_summary(b->rt, b->nroutes, false, b->summary, sizeof b->summary));
    KELP_IGNORE(kelp_app_notify_string(app, "PSHARE_OUTPUT_SUMMARY", b->summary));
    KELP_IGNORE(kelp_bridge_pshare_summary(b->in, b->ninputs, true, b->summary, sizeof b->summary));
    KELP_IGNORE(kelp_app_notify_string(app, "PSHARE_INPUT_SUMMARY", b->summary));
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    bridge *b = st;
    KELP_IGNORE(kelp_bridge_pshare_summary(b->in, b->ninputs, true, b->summary, sizeof b->summary));
    (void)app;
    fprintf(out, "listening %s  key %s  allow %s  routes %zu  %s ok %lu bad %lu\n", b->summary[0] ? b->summary : "(none)",
            b->keylen ? "yes" : "no", b->allow[0] ? b->allow : "(all)", b->nroutes, b->cmd_var, b->reg_ok, b->reg_bad);
    fprintf(out, "sent %lu (errors %lu, oversize %lu)  received %lu  auth failures %lu  replays %lu  not allowed %lu  "
                 "oversize %lu  malformed %lu  peers %zu (forgotten %lu)\n",
            b->tx, b->tx_err, b->tx_oversize, b->rx, b->rx_auth_fail, b->rx_replay, b->rx_denied, b->rx_oversize,
            b->rx_bad, b->brx.n, b->brx.evicted);
    for (size_t i = 0; i < b->nroutes; i++)
        fprintf(out, "  %-20s -> %-10s %s:%u as %-20s sent %lu\n", b->rt[i].src, b->rt[i].community,
                b->rt[i].multicast ? "multicast" : b->rt[i].host, b->rt[i].port,
                b->rt[i].alias[0] ? b->rt[i].alias : b->rt[i].src, b->sent[i]);
}

static const kelp_app_def def = {
    .name = "kelp-bridge",
    .moos_name = "pMOOSBridge",
    .purpose = "Forward variables between communities over UDP (the pShare and pMOOSBridge roles), with renaming "
               "and optional HMAC authentication.",
    .params = (const kelp_app_param_info[]){
        { "input", "route = localhost:9067 & multicast_9", "pShare, repeatable: where to listen (, white_list = A & B*)", NULL },
        { "output", "src_name = P, dest_name = H, route = 178.4.5.6:9001",
          "pShare, repeatable (or P->H:178.4.5.6:9001@F); also frequency = F (shares/s at most), duration = D (s), max_shares = M",
          NULL },
        { "multicast_base_port", "24460", "pShare: multicast_N is this port + N (default 24460)", NULL },
        { "multicast_address", "224.1.1.11", "pShare: the multicast group of multicast_N routes (default 224.1.1.11)", NULL },
        { "verbose", "false", "pShare: accepted (kelp's run warnings and APPCAST say what verbose prints)", NULL },
        { "UDPListen", "9200", "pMOOSBridge: UDP port other bridges send to (default: none, send only)", NULL },
        { "UDPSHARE", "[NODE_REPORT_LOCAL] -> shoreside @ 192.168.1.10:9200 [NODE_REPORT]",
          "pMOOSBridge, repeatable: [vars] -> community @ host:port [aliases]", NULL },
        { "SHARE", "[APPLES] -> shoreside @ 192.168.1.10:9200", "repeatable: same as UDPSHARE", NULL },
        { "KEY", "change-me", "optional shared secret (HMAC), up to 255 characters", NULL },
        { "ALLOW", "NODE_REPORT, NODE_MESSAGE, DEPLOY_*",
          "repeatable: the only names (globs) received datagrams may publish into this community (default: all)",
          NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "PSHARE_CMD", "cmd=output,src_name=P,dest_name=H,route=multicast_9", "pShare (<NAME>_CMD): an output or input at run time" },
        { "PMB_REGISTER", "src_var=NAV_X,dest_community=shoreside,dest_host=192.168.1.10,dest_port=9200,dest_alias=VEHICLE_X",
          "pMOOSBridge: a route added at run time" },
        { "<shared variable>", "any value", "every source variable of the routes" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "PSHARE_OUTPUT_SUMMARY", "X->Y:165.45.3.61:9000 & Z:165.45.3.61:2000,K->K:192.168.66.12:3000", "pShare, every second" },
        { "PSHARE_INPUT_SUMMARY", "localhost:9001,224.1.1.11:24478:multicast_18", "pShare, every second" },
        { "PMB_UDP_LISTEN", "9200", "pMOOSBridge, at start-up" },
        { "<alias>", "any value", "on the receiving side, every bridged variable under its alias" },
        { NULL, NULL, NULL } },
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static bridge b;
    return kelp_app_run(argc, argv, &def, &b);
}
