/* kelp-bridge (the pMOOSBridge role): forward variables between communities over UDP.
 *
 * ProcessConfig = pMOOSBridge (or the name it runs under):
 *   UDPListen = 9200                                        UDP port this bridge listens on
 *   UDPSHARE  = [VAR1,VAR2] -> community @ host:port [A1,A2]   (repeatable; SHARE is a synonym)
 *   KEY       = shared-secret                               authenticate datagrams (HMAC-SHA256)
 *   ALLOW     = NODE_REPORT, NODE_MESSAGE_*                 (repeatable) the only names this bridge
 *               publishes into its community, whatever a far side's PMB_REGISTER asked for
 * Run time: PMB_REGISTER = "src_var=V,dest_community=C,dest_host=H,dest_port=P,dest_alias=A".
 * Publishes PMB_UDP_LISTEN (the port) at start-up. Variables that arrived through a bridge
 * are never forwarded again (no loops); a route is added once (no duplicates); a replayed
 * datagram is refused (sequence window per sending community, see kelp/bridge.h). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <mbedtls/md.h>
#include <kelp/app.h>
#include <kelp/bridge.h>
#include <kelp/edge/udp.h>

#define MAX_ROUTES 256
#define MAX_PEERS 64
#define DGRAM_MAX 65536 /* any UDP datagram whole; larger than KELP_BRIDGE_DGRAM_MAX */

typedef struct route {
    kelp_bridge_route r;
    struct sockaddr_in addr;
    unsigned long sent;
} route;

typedef struct bridge {
    int sock;
    uint16_t port;
    uint8_t key[256];
    size_t keylen;
    route routes[MAX_ROUTES];
    int nroutes;
    char allow[2048]; /* comma-separated ALLOW entries; "" allows every name */
    kelp_bridge_tx btx;
    kelp_bridge_rx brx;
    kelp_bridge_peer peers[MAX_PEERS];
    unsigned long rx, rx_auth_fail, rx_bad, rx_replay, rx_denied, rx_oversize, tx, tx_err, tx_oversize, reg_ok,
        reg_bad;
    kelp_var *rxv;
    uint8_t buf[DGRAM_MAX];
} bridge;

static int hmac_sha256(const uint8_t *key, size_t keylen, const uint8_t *data, size_t len, uint8_t out[32], void *user)
{
    (void)user;
    const mbedtls_md_info_t *md = mbedtls_md_info_from_type(MBEDTLS_MD_SHA256);
    return mbedtls_md_hmac(md, key, keylen, data, len, out) == 0 ? 0 : KELP_ERR_CRYPTO;
}

static int add_route(kelp_app *app, bridge *b, const kelp_bridge_route *r)
{
    for (int i = 0; i < b->nroutes; i++) {
        const kelp_bridge_route *o = &b->routes[i].r;
        if (strcmp(o->src, r->src) == 0 && strcmp(o->alias, r->alias) == 0 && strcmp(o->host, r->host) == 0 &&
            o->port == r->port)
            return 0; /* already bridged: no duplicates */
    }
    if (b->nroutes >= MAX_ROUTES) {
        kelp_app_run_warning(app, "too many routes (max %d)", MAX_ROUTES);
        return KELP_ERR_NOSPACE;
    }
    route *rt = &b->routes[b->nroutes];
    memset(rt, 0, sizeof *rt);
    rt->r = *r;
    if (kelp_udp_resolve(r->host, r->port, &rt->addr) < 0) {
        kelp_app_run_warning(app, "cannot resolve host %s", r->host);
        return KELP_ERR_NOTFOUND;
    }
    b->nroutes++;
    /* register once per distinct source */
    int first = 1;
    for (int i = 0; i < b->nroutes - 1; i++)
        if (strcmp(b->routes[i].r.src, r->src) == 0) first = 0;
    if (first && kelp_app_register(app, r->src, 0) < 0) kelp_app_run_warning(app, "cannot register %s", r->src);
    kelp_app_event(app, "bridge %s -> %s@%s:%u as %s", r->src, r->community, r->host, r->port,
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
            b->rx_oversize++;
            kelp_app_run_warning(app, "oversize datagram (%zu bytes): dropped", n);
            continue;
        }
        int rc = kelp_bridge_unframe(&b->brx, b->buf, n, b->key, b->keylen, hmac_sha256, NULL, b->rxv);
        if (rc == KELP_ERR_AUTH) {
            b->rx_auth_fail++;
            kelp_app_run_warning(app, "datagram failed authentication: dropped");
            continue;
        }
        if (rc == KELP_ERR_REPLAY) {
            b->rx_replay++;
            kelp_app_run_warning(app, "replayed or stale datagram from %s: dropped", b->rxv->community);
            continue;
        }
        if (rc == KELP_ERR_RANGE) {
            b->rx_oversize++;
            kelp_app_run_warning(app, "oversize value (%zu-byte datagram, values up to %d bytes): dropped", n,
                                 KELP_MAX_SVAL);
            continue;
        }
        if (rc < 0) {
            b->rx_bad++;
            kelp_app_run_warning(app, "malformed bridge datagram: %s", kelp_strerror(rc));
            continue;
        }
        if (!kelp_bridge_allowed(b->allow, b->rxv->name)) {
            b->rx_denied++;
            kelp_app_run_warning(app, "%s from %s is not on the ALLOW list: dropped", b->rxv->name, b->rxv->community);
            continue;
        }
        if (kelp_bus_forward(kelp_app_bus(app), b->rxv) < 0) kelp_app_run_warning(app, "republish failed");
    }
    if (got < 0) kelp_app_run_warning(app, "UDP receive failed: %s", strerror(errno));
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    bridge *b = st;
    if (strcmp(v->name, "PMB_REGISTER") == 0) {
        kelp_bridge_route r;
        kelp_diag why;
        kelp_diag_clear(&why);
        if (v->kind != KELP_VAR_STRING || kelp_bridge_parse_register(v->sval, &r, &why) < 0) {
            b->reg_bad++;
            kelp_app_run_warning(app, "bad PMB_REGISTER (%s)", why.code ? kelp_diag_text(&why) : "not a string");
            return;
        }
        b->reg_ok++;
        (void)add_route(app, b, &r);
    }
    /* forward what belongs to this community and did not come through a bridge */
    if (v->flags & KELP_VAR_FLAG_BRIDGED) return;
    if (strcmp(v->community, kelp_app_community(app)) != 0) return;
    for (int i = 0; i < b->nroutes; i++) {
        route *rt = &b->routes[i];
        if (!kelp_bus_match(rt->r.src, v->name)) continue;
        size_t len = 0;
        int rc = kelp_bridge_frame(&b->btx, v, rt->r.alias, b->key, b->keylen, hmac_sha256, NULL, b->buf,
                                   KELP_BRIDGE_DGRAM_MAX, &len);
        if (rc == KELP_ERR_NOSPACE) {
            b->tx_oversize++;
            kelp_app_run_warning(app, "%s is too large for one datagram: not sent", v->name);
            continue;
        }
        if (rc < 0) {
            b->tx_err++;
            continue;
        }
        if (kelp_udp_send(b->sock, &rt->addr, b->buf, len) < 0) {
            b->tx_err++;
            kelp_app_run_warning(app, "send to %s:%u failed: %s", rt->r.host, rt->r.port, strerror(errno));
        } else {
            b->tx++;
            rt->sent++;
        }
    }
}

static int startup(kelp_app *app, void *st)
{
    bridge *b = st;
    kelp_bus_set_bridge(kelp_app_bus(app), true); /* sees every community's writes */
    b->rxv = malloc(sizeof *b->rxv);
    double port = 0;
    const kelp_mission_node *pn = kelp_app_param(app, "UDPListen");
    if (pn && (kelp_mission_double(pn, &port) < 0 || port < 1 || port > 65535 || port != (int)port))
        return kelp_app_config_error(app, pn, "UDPListen must be a port number 1-65535");
    b->port = (uint16_t)port;
    char key[256];
    int kr = kelp_app_param_str(app, "KEY", key, sizeof key);
    if (kr < 0) return kelp_app_config_error(app, kelp_app_param(app, "KEY"), "KEY too long (max 255)");
    if (kr > 0) {
        b->keylen = strlen(key);
        memcpy(b->key, key, b->keylen);
    }
    for (const kelp_mission_node *n = kelp_app_param_next(app, "ALLOW", NULL); n;
         n = kelp_app_param_next(app, "ALLOW", n)) {
        size_t used = strlen(b->allow);
        char one[1024];
        if (kelp_mission_copy(n, one, sizeof one) < 0 || used + strlen(one) + 2 > sizeof b->allow)
            return kelp_app_config_error(app, n, "ALLOW lists too long (max %zu characters)", sizeof b->allow - 1);
        snprintf(b->allow + used, sizeof b->allow - used, "%s%s", used ? "," : "", one);
    }
    /* this run's identity for the receivers' replay windows: start time in microseconds */
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    kelp_bridge_tx_init(&b->btx, (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u);
    kelp_bridge_rx_init(&b->brx, b->peers, MAX_PEERS);
    kelp_diag err = {0};
    b->sock = kelp_udp_open(b->port, 4 << 20, &err);
    if (b->sock < 0) return kelp_app_config_error(app, pn, "%s", kelp_diag_text(&err));
    if (b->port) {
        if (kelp_app_watch_fd(app, b->sock, on_udp) < 0) return KELP_ERR_NOSPACE;
        KELP_IGNORE(kelp_app_notify_double(app, "PMB_UDP_LISTEN", b->port));
    }
    const char *names[] = { "UDPSHARE", "SHARE" };
    for (int k = 0; k < 2; k++) {
        for (const kelp_mission_node *n = kelp_app_param_next(app, names[k], NULL); n;
             n = kelp_app_param_next(app, names[k], n)) {
            char line[1024];
            kelp_bridge_route rs[16];
            size_t nr = 0;
            kelp_diag why;
            kelp_diag_clear(&why);
            if (kelp_mission_copy(n, line, sizeof line) < 0) (void)kelp_fail(&why, KELP_ERR_NOSPACE, "too long");
            int rc = why.code ? why.code : kelp_bridge_parse_share(line, rs, 16, &nr, &why);
            if (rc < 0) return kelp_app_config_error(app, n, "bad %s: %s", names[k], rc == KELP_ERR_NOSPACE && !why.code ? "too many variables" : kelp_diag_text(&why));
            for (size_t i = 0; i < nr; i++)
                if (add_route(app, b, &rs[i]) < 0) return kelp_app_config_error(app, n, "cannot add route");
        }
    }
    return kelp_app_register(app, "PMB_REGISTER", 0);
}

static int iterate(kelp_app *app, void *st, double now)
{
    (void)app; (void)st; (void)now;
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    bridge *b = st;
    (void)app;
    fprintf(out, "UDP port %u  key %s  allow %s  routes %d  PMB_REGISTER ok %lu bad %lu\n", b->port,
            b->keylen ? "yes" : "no", b->allow[0] ? b->allow : "(all)", b->nroutes, b->reg_ok, b->reg_bad);
    fprintf(out, "sent %lu (errors %lu, oversize %lu)  received %lu  auth failures %lu  replays %lu  not allowed %lu  "
                 "oversize %lu  malformed %lu  peers %zu (forgotten %lu)\n",
            b->tx, b->tx_err, b->tx_oversize, b->rx, b->rx_auth_fail, b->rx_replay, b->rx_denied, b->rx_oversize,
            b->rx_bad, b->brx.n, b->brx.evicted);
    for (int i = 0; i < b->nroutes; i++)
        fprintf(out, "  %-20s -> %-10s %s:%u as %-20s sent %lu\n", b->routes[i].r.src, b->routes[i].r.community,
                b->routes[i].r.host, b->routes[i].r.port, b->routes[i].r.alias[0] ? b->routes[i].r.alias : b->routes[i].r.src,
                b->routes[i].sent);
}

static const kelp_app_def def = {
    .name = "kelp-bridge",
    .moos_name = "pMOOSBridge",
    .purpose = "Forward variables between communities over UDP, with renaming and optional HMAC authentication.",
    .params = (const kelp_app_param_info[]){
        { "UDPListen", "9200", "UDP port other bridges send to (default: none, send only)", NULL },
        { "UDPSHARE", "[NODE_REPORT_LOCAL] -> shoreside @ 192.168.1.10:9200 [NODE_REPORT]",
          "repeatable: [vars] -> community @ host:port [aliases]", NULL },
        { "SHARE", "[APPLES] -> shoreside @ 192.168.1.10:9200", "repeatable: same as UDPSHARE", NULL },
        { "KEY", "change-me", "optional shared secret (HMAC), up to 255 characters", NULL },
        { "ALLOW", "NODE_REPORT, NODE_MESSAGE, DEPLOY_*",
          "repeatable: the only names (globs) received datagrams may publish into this community (default: all)",
          NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "PMB_REGISTER", "[NAV_X] -> shoreside @ 192.168.1.10:9200 [VEHICLE_X]", "a UDPSHARE line added at run time" },
        { "<shared variable>", "any value", "every source variable of UDPSHARE" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "PMB_UDP_LISTEN", "9200", NULL },
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
