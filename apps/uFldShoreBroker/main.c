/* uFldShoreBroker: on the shoreside, answer the vehicles' NODE_BROKER_PING and ask the
 * shore's kelp-bridge (the pMOOSBridge role) for the bridges to each vehicle. A ping with
 * our time warp (and our KEYWORD, when set) is accepted: the first time a vehicle is
 * accepted (and whenever it pings from another host or port) the ack bridge
 * NODE_BROKER_ACK_<V> -> NODE_BROKER_ACK and every BRIDGE / QBRIDGE are registered to it
 * (PMB_REGISTER, with $V, $v and $N expanded in src); every accepted ping is acked. A
 * restarted shore broker registers them again when the vehicle's next ping arrives
 * (kelp-bridge ignores a route it has already). The logic is the core kelp_field_sbroker
 * (include/kelp/field.h).
 *
 * The shore's kelp-bridge must let in what vehicles send: ALLOW = NODE_BROKER_PING and the
 * aliases of the vehicles' BRIDGE lines (NODE_REPORT, NODE_MESSAGE, VIEW_*, ...). */
#include <stdio.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/field.h>

typedef struct sbroker {
    kelp_app *app;
    kelp_field_sbroker_cfg cfg;
    kelp_field_sbroker core;
    kelp_field_sink sink;
    char report[16384];
} sbroker;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    sbroker *s = ctx;
    int rc = is_string ? kelp_app_notify_string(s->app, var, sval) : kelp_app_notify_double(s->app, var, dval);
    if (rc < 0) kelp_app_run_warning(s->app, "cannot publish %s", var);
    else if (strcmp(var, "PMB_REGISTER") == 0) kelp_app_event(s->app, "PMB_REGISTER %s", sval);
}

static void warn(void *ctx, const char *msg)
{
    kelp_app_run_warning(((sbroker *)ctx)->app, "%s", msg);
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    sbroker *s = ctx;
    int rc = kelp_field_sbroker_config(&s->cfg, key, val, d);
    if (rc != 0) return rc;
    static const char *const accepted[] = { "APP_LOGGING", "MAX_APPCAST_EVENTS" };
    for (size_t i = 0; i < sizeof accepted / sizeof accepted[0]; i++)
        if (kelp_strieq_n(key, strlen(key), accepted[i])) return 1;
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    sbroker *s = st;
    s->app = app;
    s->sink = (kelp_field_sink){ s, publish, warn };
    kelp_field_sbroker_cfg_default(&s->cfg);
    s->cfg.warp = kelp_app_warp(app);
    int rc = kelp_app_param_foreach(app, param, s);
    if (rc < 0) return rc;
    kelp_field_sbroker_init(&s->core, &s->cfg);
    for (unsigned i = 0; i < s->core.cfg.nbridges; i++)
        kelp_app_event(app, "bridge %s -> %s for each vehicle", s->core.cfg.bridge[i].src, s->core.cfg.bridge[i].alias);
    for (unsigned i = 0; kelp_field_sbroker_subscription(i); i++)
        if (kelp_app_register(app, kelp_field_sbroker_subscription(i), 0) < 0)
            return kelp_app_config_error(app, NULL, "cannot register %s", kelp_field_sbroker_subscription(i));
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    sbroker *s = st;
    if (v->kind == KELP_VAR_BINARY) return;
    int rc = kelp_field_sbroker_mail(&s->core, v->name, v->kind == KELP_VAR_STRING, v->sval, kelp_app_time(app),
                                     &s->sink);
    if (rc < 0)
        kelp_app_run_warning(app, "%s: %s; ignored", v->name,
                             strcmp(v->name, "PHI_HOST_INFO") == 0 ? "incomplete (community, hostip, port_udp)"
                                                                   : "malformed or incomplete (community, host, port_udp)");
}

static int iterate(kelp_app *app, void *st, double now)
{
    sbroker *s = st;
    (void)app;
    (void)kelp_field_sbroker_iterate(&s->core, now, &s->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    sbroker *s = st;
    if (kelp_field_sbroker_report(&s->core, kelp_app_time(app), s->report, sizeof s->report) < 0)
        fputs("(report truncated)\n", out);
    fputs(s->report, out);
    if (s->core.last_register[0]) fprintf(out, "\nLast PMB_REGISTER: %s\n", s->core.last_register);
}

static const kelp_app_def def = {
    .name = "uFldShoreBroker",
    .purpose = "Accept vehicles' NODE_BROKER_PING, ack them, and bridge BRIDGE/QBRIDGE variables to each.",
    .params = (const kelp_app_param_info[]){
        { "BRIDGE", "src=DEPLOY_$V, alias=DEPLOY",
          "repeatable: src=V[, alias=A] bridged to each vehicle; in src $V = NAME, $v = name, $N = 1,2,..", NULL },
        { "QBRIDGE", "DEPLOY, RETURN", "repeatable: X is BRIDGE src=X_ALL, alias=X plus src=X_$V, alias=X", NULL },
        { "KEYWORD", "lemon", "optional: pings must carry this keyword", NULL },
        { "TRY_VNODE", "192.168.4.24:9200", "24.8, repeatable: send TRY_SHORE_HOST to this vehicle bridge", NULL },
        { "WARNING_ON_STALE", "false", "24.8: a run warning when a vehicle stops pinging for 10 s", NULL },
        { "AUTO_BRIDGE_REALMCAST", "false", "24.8: also QBRIDGE REALMCAST_REQ", NULL },
        { "AUTO_BRIDGE_APPCAST", "false", "24.8: also QBRIDGE APPCAST_REQ", NULL },
        { "AUTO_BRIDGE_MHASH", "false", "24.8: also BRIDGE src=MISSION_HASH", NULL },
        { "APP_LOGGING", "false", "accepted (24.8)", NULL },
        { "MAX_APPCAST_EVENTS", "8", "accepted (24.8)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "PHI_HOST_INFO", "community=shoreside,hostip=10.0.0.8,port_db=9000,port_udp=9200,timewarp=1",
          "from pHostInfo: needed before any ping is acked" },
        { "NODE_BROKER_PING",
          "community=henry,host=192.168.1.22,port=9000,port_udp=9200,keyword=lemon,time_warp=10,time=1325178800.81",
          "from the vehicles (bridged)" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "PMB_REGISTER",
          "src_var=DEPLOY_ALL,dest_community=henry,dest_host=12.56.111.1,dest_port=9200,dest_alias=DEPLOY",
          "to the shore's kelp-bridge, per vehicle: the ack bridge, then each BRIDGE" },
        { "NODE_BROKER_ACK_<V>",
          "community=shoreside,host=10.0.0.8,port=9000,port_udp=9200,time_warp=1,time=1325178801.2,status=ok",
          "per accepted ping; bridged to the vehicle as NODE_BROKER_ACK" },
        { "NODE_BROKER_VACK", "henry", "24.8: the vehicle just acked" },
        { "UFSB_NODE_COUNT", "3", "24.8: vehicles known" },
        { "UFSB_QBRIDGE_VARS", "NODE_REPORT,RETURN", "24.8: the QBRIDGE names, sorted; at start" },
        { "UFSB_BRIDGE_VARS", "DEPLOY_$V,DEPLOY_HENRY,NODE_BROKER_ACK_$V,NODE_BROKER_ACK_HENRY,RETURN_ALL,RETURN_HENRY",
          "24.8: the bridged sources, sorted; when a vehicle is first bridged" },
        { "TRY_SHORE_HOST", "pshare_route=10.0.0.8:9200", "24.8: to each TRY_VNODE every 10 s" },
        { "HOST_INFO_REQUEST", "true", "every 2 s until PHI_HOST_INFO is complete" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: MOOSTimeWarp (a vehicle's must be equal).\n"
             "The shore's kelp-bridge needs UDPListen and ALLOW = NODE_BROKER_PING, <vehicle aliases>.\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static sbroker s;
    return kelp_app_run(argc, argv, &def, &s);
}
