/* uFldNodeBroker: on a vehicle, find the shoreside and ask the local kelp-bridge (the
 * pMOOSBridge role) for the bridges to it. From pHostInfo's PHI_HOST_INFO it learns its own
 * community, IP and bridge port; it asks the bridge to carry NODE_BROKER_PING to every
 * TRY_SHORE_HOST (PMB_REGISTER) and pings on every iteration; the shore's uFldShoreBroker
 * answers NODE_BROKER_ACK, and the vehicle's BRIDGE variables are then registered to that
 * shore. Pings never stop, so a restarted shore finds the vehicle again; while no ack is
 * heard the ping registrations are posted again every RETRY_INTERVAL (kelp-bridge ignores
 * a route it has already). The logic is the core kelp_field_nbroker (include/kelp/field.h).
 *
 * The vehicle's kelp-bridge must let in what the shore sends: ALLOW = NODE_BROKER_ACK,
 * TRY_SHORE_HOST and the aliases of the shore's BRIDGE/QBRIDGE lines (DEPLOY, RETURN, ...). */
#include <stdio.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/field.h>

typedef struct nbroker {
    kelp_app *app;
    kelp_field_nbroker_cfg cfg;
    kelp_field_nbroker core;
    kelp_field_sink sink;
    char report[8192];
} nbroker;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    nbroker *b = ctx;
    int rc = is_string ? kelp_app_notify_string(b->app, var, sval) : kelp_app_notify_double(b->app, var, dval);
    if (rc < 0) kelp_app_run_warning(b->app, "cannot publish %s", var);
    else if (strcmp(var, "PMB_REGISTER") == 0) kelp_app_event(b->app, "PMB_REGISTER %s", sval);
}

static void warn(void *ctx, const char *msg)
{
    kelp_app_run_warning(((nbroker *)ctx)->app, "%s", msg);
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    nbroker *b = ctx;
    int rc = kelp_field_nbroker_config(&b->cfg, key, val, d);
    if (rc != 0) return rc;
    static const char *const accepted[] = { "APP_LOGGING", "MAX_APPCAST_EVENTS" };
    for (size_t i = 0; i < sizeof accepted / sizeof accepted[0]; i++)
        if (kelp_strieq_n(key, strlen(key), accepted[i])) return 1;
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    nbroker *b = st;
    b->app = app;
    b->sink = (kelp_field_sink){ b, publish, warn };
    kelp_field_nbroker_cfg_default(&b->cfg);
    b->cfg.warp = kelp_app_warp(app);
    int rc = kelp_app_param_foreach(app, param, b);
    if (rc < 0) return rc;
    for (unsigned i = 0; i < b->cfg.nbad_try; i++) {
        if (b->cfg.bad_multicast[i])
            kelp_app_event(app, "TRY_SHORE_HOST = %s: not used (%s)", b->cfg.bad_try[i], b->cfg.bad_why[i]);
        else
            kelp_app_config_warning(app, "TRY_SHORE_HOST = %s: invalid (%s)", b->cfg.bad_try[i],
                                    b->cfg.bad_why[i][0] ? b->cfg.bad_why[i] : "malformed");
    }
    if (b->cfg.ntry == 0) kelp_app_event(app, "no valid TRY_SHORE_HOST yet: waiting for one by mail");
    kelp_field_nbroker_init(&b->core, &b->cfg);
    for (unsigned i = 0; kelp_field_nbroker_subscription(i); i++)
        if (kelp_app_register(app, kelp_field_nbroker_subscription(i), 0) < 0)
            return kelp_app_config_error(app, NULL, "cannot register %s", kelp_field_nbroker_subscription(i));
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    nbroker *b = st;
    if (v->kind == KELP_VAR_BINARY) return;
    int rc = kelp_field_nbroker_mail(&b->core, v->name, v->kind == KELP_VAR_STRING, v->sval, kelp_app_time(app),
                                     &b->sink);
    if (rc < 0 && strcmp(v->name, "NODE_BROKER_ACK") != 0) /* the core explains bad acks itself */
        kelp_app_run_warning(app, "%s: %s; ignored", v->name,
                             strcmp(v->name, "PHI_HOST_INFO") == 0 ? "incomplete (community, hostip, port_udp)"
                                                                   : "not a usable value");
}

static int iterate(kelp_app *app, void *st, double now)
{
    nbroker *b = st;
    (void)app;
    (void)kelp_field_nbroker_iterate(&b->core, now, &b->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    nbroker *b = st;
    (void)app;
    if (kelp_field_nbroker_report(&b->core, b->report, sizeof b->report) < 0) fputs("(report truncated)\n", out);
    fputs(b->report, out);
    if (b->core.last_register[0]) fprintf(out, "\nLast PMB_REGISTER: %s\n", b->core.last_register);
}

static const kelp_app_def def = {
    .name = "uFldNodeBroker",
    .purpose = "Find the shoreside from TRY_SHORE_HOST, ping it, and bridge BRIDGE variables to it once it acks.",
    .params = (const kelp_app_param_info[]){
        { "KEYWORD", "lemon", "optional: sent in every ping; the shore may require it", NULL },
        { "TRY_SHORE_HOST", "host_ip=localhost, port_udp=9200, community=topside",
          "repeatable: a shore bridge to ping (also 24.8's pshare_route=host:port)", NULL },
        { "BRIDGE", "src=NODE_REPORT_LOCAL, alias=NODE_REPORT",
          "repeatable: src=V[, alias=A] bridged to the shore once it acks (alias defaults to src)", NULL },
        { "RETRY_INTERVAL", "10", "s without an ack before the ping registrations are posted again", NULL },
        { "AUTO_BRIDGE_REALMCAST", "false", "24.8: also bridge REALMCAST, WATCHCAST, REALMCAST_CHANNELS", NULL },
        { "AUTO_BRIDGE_APPCAST", "false", "24.8: also bridge APPCAST", NULL },
        { "AUTO_BRIDGE_PSHARE_VARS", "false", "24.8: also bridge NODE_PSHARE_VARS", NULL },
        { "APP_LOGGING", "false", "accepted (24.8)", NULL },
        { "MAX_APPCAST_EVENTS", "8", "accepted (24.8)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "PHI_HOST_INFO", "community=james,hostip=10.0.0.8,port_db=9204,port_udp=9304,timewarp=1",
          "from pHostInfo: complete with community, hostip and port_udp" },
        { "NODE_BROKER_ACK", "community=shoreside,host=10.0.0.8,port=9000,port_udp=9200,time_warp=1,time=0,status=ok",
          "from the shore (its NODE_BROKER_ACK_<V>, bridged)" },
        { "TRY_SHORE_HOST", "pshare_route=192.168.4.100:9200", "24.8: a try host added at run time" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "PMB_REGISTER",
          "src_var=NODE_REPORT_LOCAL,dest_community=shoreside,dest_host=10.0.0.8,dest_port=9200,dest_alias=NODE_REPORT",
          "to the local kelp-bridge: NODE_BROKER_PING to each try host, then each BRIDGE to the shore" },
        { "NODE_BROKER_PING",
          "community=henry,host=192.168.1.22,port=9000,port_udp=9200,keyword=lemon,time_warp=10,time=1325178800.81",
          "every iteration once PHI_HOST_INFO is complete" },
        { "NODE_PSHARE_VARS", "VIEW_POLYGON,VIEW_POINT,VIEW_SEGLIST,NODE_REPORT", "the bridges' aliases, after each valid ack" },
        { "HOST_INFO_REQUEST", "true", "every 2 s until PHI_HOST_INFO is complete" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: MOOSTimeWarp (must equal the shore's).\n"
             "The vehicle's kelp-bridge needs UDPListen and ALLOW = NODE_BROKER_ACK, TRY_SHORE_HOST, <shore aliases>.\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static nbroker b;
    return kelp_app_run(argc, argv, &def, &b);
}
