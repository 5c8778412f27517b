/* pHostInfo: the host's IP addresses, the community's ports and time warp, posted for the
 * uField brokers (PHI_HOST_IP, PHI_HOST_IP_ALL, PHI_HOST_IP_VERBOSE, PHI_HOST_PORT_DB,
 * PHI_HOST_INFO). The logic is the core kelp_field_hostinfo; this file finds the addresses
 * with getifaddrs() (no temporary files, no shell commands) and wires the core to the bus. */
#include <ifaddrs.h>
#include <stdio.h>
#include <string.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <kelp/edge/app.h>
#include <kelp/field.h>

typedef struct hostinfo {
    kelp_app *app;
    kelp_field_hostinfo core;
    kelp_field_sink sink;
    char report[4096];
} hostinfo;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    hostinfo *h = ctx;
    int rc = is_string ? kelp_app_notify_string(h->app, var, sval) : kelp_app_notify_double(h->app, var, dval);
    if (rc < 0) kelp_app_run_warning(h->app, "cannot publish %s", var);
}

static void warn(void *ctx, const char *msg)
{
    kelp_app_run_warning(((hostinfo *)ctx)->app, "%s", msg);
}

/* the IPv4 addresses of the interfaces that are up */
static void detect(hostinfo *h)
{
    struct ifaddrs *ifa = NULL;
    static char names[KELP_HOSTINFO_MAX_ADDRS * 2][16], ips[KELP_HOSTINFO_MAX_ADDRS * 2][16];
    const char *np[KELP_HOSTINFO_MAX_ADDRS * 2], *ip[KELP_HOSTINFO_MAX_ADDRS * 2];
    unsigned n = 0;
    if (getifaddrs(&ifa) != 0) {
        kelp_app_run_warning(h->app, "getifaddrs failed: no addresses");
        kelp_field_hostinfo_set(&h->core, np, ip, 0);
        return;
    }
    for (struct ifaddrs *a = ifa; a && n < KELP_HOSTINFO_MAX_ADDRS * 2; a = a->ifa_next) {
        if (!a->ifa_addr || a->ifa_addr->sa_family != AF_INET || !a->ifa_name) continue;
        const struct sockaddr_in *sin = (const struct sockaddr_in *)(const void *)a->ifa_addr;
        if (!inet_ntop(AF_INET, &sin->sin_addr, ips[n], sizeof ips[n])) continue;
        snprintf(names[n], sizeof names[n], "%.15s", a->ifa_name);
        np[n] = names[n], ip[n] = ips[n];
        n++;
    }
    freeifaddrs(ifa);
    kelp_field_hostinfo_set(&h->core, np, ip, n);
    kelp_app_event(h->app, "%u address(es) found", h->core.naddr);
}

/* key, or its MOOS-IvP 24.8 spelling alt (default_host_ip, default_host_ip_force) */
static int text(kelp_app *app, const char *key, const char *alt, char *dst, size_t cap)
{
    /* both spellings are read (so neither is reported unknown); the later line wins */
    const kelp_mission_node *n = kelp_app_param(app, key);
    const kelp_mission_node *m = alt ? kelp_app_param(app, alt) : NULL;
    if (m && (!n || m->line > n->line)) n = m;
    if (n && (kelp_mission_copy(n, dst, cap) < 0 || strpbrk(dst, " ,=")))
        return kelp_app_config_error(app, n, "%s must be one word of at most %zu characters", key, cap - 1);
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    hostinfo *h = st;
    h->app = app;
    h->sink = (kelp_field_sink){ h, publish, warn };
    kelp_field_hostinfo_cfg c;
    kelp_field_hostinfo_cfg_default(&c);
    snprintf(c.community, sizeof c.community, "%s", kelp_app_community(app));
    c.warp = kelp_app_warp(app);
    if (kelp_app_global_double(app, "ServerPort", &c.port_db) < 0) return -1;
    if (text(app, "DEFAULT_HOSTIP", "DEFAULT_HOST_IP", c.default_ip, sizeof c.default_ip) < 0 ||
        text(app, "DEFAULT_HOSTIP_FORCE", "DEFAULT_HOST_IP_FORCE", c.force_ip, sizeof c.force_ip) < 0 ||
        text(app, "PREFER_INTERFACE", NULL, c.prefer_if, sizeof c.prefer_if) < 0)
        return -1;
    static const char *const accepted[] = { "TEMP_FILE_DIR", "APP_LOGGING" };
    for (int i = 0; i < 2; i++)
        if (kelp_app_param(app, accepted[i])) kelp_app_event(app, "%s accepted (kelp reads the interfaces directly)", accepted[i]);
    kelp_field_hostinfo_init(&h->core, &c);
    detect(h);
    static const char *const subs[] = { "HOST_INFO_REQUEST", "PMB_UDP_LISTEN", "PSHARE_INPUT_SUMMARY" };
    for (int i = 0; i < 3; i++)
        if (kelp_app_register(app, subs[i], 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", subs[i]);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    hostinfo *h = st;
    if (v->kind == KELP_VAR_BINARY) return;
    if (kelp_field_hostinfo_mail(&h->core, v->name, v->kind == KELP_VAR_STRING, v->sval, v->dval) < 0)
        kelp_app_run_warning(app, "%s: not a usable value; ignored", v->name);
}

static int iterate(kelp_app *app, void *st, double now)
{
    hostinfo *h = st;
    (void)app, (void)now;
    if (h->core.redetect) detect(h);
    (void)kelp_field_hostinfo_iterate(&h->core, &h->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    hostinfo *h = st;
    (void)app;
    if (kelp_field_hostinfo_report(&h->core, h->report, sizeof h->report) < 0) fputs("(report truncated)\n", out);
    fputs(h->report, out);
    if (h->report[0] && h->report[strlen(h->report) - 1] != '\n') fputc('\n', out);
}

static const kelp_app_def def = {
    .name = "pHostInfo",
    .purpose = "Post this host's IP addresses, ports and time warp for the uField brokers.",
    .params = (const kelp_app_param_info[]){
        { "DEFAULT_HOSTIP", "192.168.0.55", "PHI_HOST_IP when no address is found (default localhost)", NULL },
        { "DEFAULT_HOSTIP_FORCE", "192.168.0.55", "PHI_HOST_IP whatever is found", NULL },
        { "DEFAULT_HOST_IP", "192.168.0.55", "same as DEFAULT_HOSTIP (24.8 takes both)", NULL },
        { "DEFAULT_HOST_IP_FORCE", "192.168.0.55", "same as DEFAULT_HOSTIP_FORCE (24.8 takes both)", NULL },
        { "PREFER_INTERFACE", "wlan0", "this interface's address wins (any case; wifi: the wireless one)", NULL },
        { "TEMP_FILE_DIR", "./", "accepted (kelp reads the interfaces with getifaddrs, no files)", NULL },
        { "APP_LOGGING", "false", "accepted", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "HOST_INFO_REQUEST", "true", "any value: look again and post again" },
        { "PSHARE_INPUT_SUMMARY", "localhost:9000:udp,1.2.3.4:2000:multicast_23", "pshare_iroutes= in PHI_HOST_INFO" },
        { "PMB_UDP_LISTEN", "9200", "the seed's pMOOSBridge port: PHI_HOST_PORT_UDP, port_udp=" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "PHI_HOST_IP", "192.168.0.1", "the best guess: ethernet before wireless" },
        { "PHI_HOST_IP_ALL", "192.168.0.1,10.1.127.3", NULL },
        { "PHI_HOST_IP_VERBOSE", "LINUX_ETHERNET=192.168.0.1,LINUX_WIFI=10.1.127.3", NULL },
        { "PHI_HOST_PORT_DB", "9000", "the ServerPort global" },
        { "PHI_HOST_PORT_UDP", "9200", "seed (pMOOSBridge) missions: once PMB_UDP_LISTEN is known" },
        { "PHI_HOST_INFO", "community=alpha,hostip=123.1.1.0,port_db=9000,port_udp=9200,pshare_iroutes=123.1.1.0:9200,"
          "hostip_alts=10.1.127.3,timewarp=8",
          "at the first iteration, every tenth, and after HOST_INFO_REQUEST" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: ServerPort, MOOSTimeWarp, Community.\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static hostinfo h;
    return kelp_app_run(argc, argv, &def, &h);
}
