/* uFldNodeBroker: on a vehicle, find the shoreside and ask the local kelp-bridge for the
 * bridges to it. The logic is the core kelp_field_nbroker (include/kelp/field.h), in one of
 * two models chosen by the mission:
 *  - MOOS-IvP 24.8's (a mission without a pMOOSBridge block, kelp-bridge running as pShare):
 *    PSHARE_CMD to pShare, NODE_BROKER_PING_<n> to each pshare_route, the user's BRIDGEs once
 *    a NODE_BROKER_ACK (from another community) names that route's key;
 *  - the seed's (a mission with a pMOOSBridge block): PMB_REGISTER, NODE_BROKER_PING every
 *    iteration, the registrations again every RETRY_INTERVAL while no ack is heard. */
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
    else if (strcmp(var, "PMB_REGISTER") == 0 || strcmp(var, "PSHARE_CMD") == 0)
        kelp_app_event(b->app, "%s %s", var, sval);
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
        if (kelp_util_strieq_n(key, strlen(key), accepted[i])) return 1;
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    nbroker *b = st;
    b->app = app;
    b->sink = (kelp_field_sink){ b, publish, warn };
    /* the seed's model when the mission runs pMOOSBridge, MOOS-IvP 24.8's otherwise */
    if (kelp_mission_block(kelp_app_mission(app), "ProcessConfig", "pMOOSBridge") >= 0) kelp_field_nbroker_cfg_seed(&b->cfg);
    else kelp_field_nbroker_cfg_default(&b->cfg);
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
    /* 24.8: our own community's PHI_HOST_INFO, another community's NODE_BROKER_ACK */
    bool local = strcmp(v->community, kelp_app_community(app)) == 0;
    if (!b->cfg.pmb && ((!strcmp(v->name, "PHI_HOST_INFO") && !local) || (!strcmp(v->name, "NODE_BROKER_ACK") && local)))
        return;
    int rc = kelp_field_nbroker_mail(&b->core, v->name, v->kind == KELP_VAR_STRING, v->sval, kelp_app_time(app),
                                     &b->sink);
    if (rc < 0 && b->cfg.pmb && strcmp(v->name, "NODE_BROKER_ACK") != 0) /* the core explains bad acks itself */
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
    if (b->report[0] && b->report[strlen(b->report) - 1] != '\n') fputc('\n', out); /* 24.8's table ends without one */
    if (b->core.last_register[0] && b->cfg.pmb) fprintf(out, "\nLast PMB_REGISTER: %s\n", b->core.last_register);
}

static const kelp_app_def def = {
    .name = "uFldNodeBroker",
    .pid_var = "UFLDNODEBROKER_PID",
    .purpose = "Find the shoreside from TRY_SHORE_HOST, ping it, and have pShare bridge the BRIDGE variables to it "
               "once it acks.",
    .params = (const kelp_app_param_info[]){
        { "AUTO_BRIDGE_REALMCAST", "true  (default)", "also bridge REALMCAST, WATCHCAST, REALMCAST_CHANNELS", NULL },
        { "AUTO_BRIDGE_APPCAST", "true  (default)", "also bridge APPCAST", NULL },
        { "AUTO_BRIDGE_PSHARE_VARS", "true  (default)", "also bridge NODE_PSHARE_VARS", NULL },
        { "TRY_SHORE_HOST", "pshare_route=192.168.0.122:9301",
          "repeatable: a shoreside pShare input route (host:port or multicast_N); the seed's "
          "host_ip=H, port_udp=P[, community=C] with pMOOSBridge", NULL },
        { "BRIDGE", "src=NODE_REPORT_LOCAL, alias=NODE_REPORT",
          "repeatable: src=V[, alias=A] bridged to the shore once it acks (alias defaults to src)", NULL },
        { "KEYWORD", "lemon", "optional: sent in every ping; the shore may require it", NULL },
        { "RETRY_INTERVAL", "10", "seed (pMOOSBridge) missions: s without an ack before the registrations are posted again", NULL },
        { "APP_LOGGING", "true  // {true or file} By default disabled", "accepted", NULL },
        { "MAX_APPCAST_EVENTS", "8", "accepted", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "PHI_HOST_INFO", "community=alpha,hostip=123.1.1.0,port_db=9000,port_udp=9200,timewarp=8",
          "from pHostInfo (our own community only)" },
        { "NODE_BROKER_ACK", "community=shoreside,hostip=192.168.1.99,port_db=9000,port_udp=9200,timewarp=8,status=ok,key=0,id=3",
          "from the shore (its NODE_BROKER_ACK_<V>, bridged): key= names the try host" },
        { "TRY_SHORE_HOST", "pshare_route=192.168.4.100:9200", "a try host added at run time" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "PSHARE_CMD", "cmd=output,src_name=NODE_REPORT_LOCAL,dest_name=NODE_REPORT,route=18.11.4.23:9200",
          "to pShare: NODE_BROKER_PING_<n> to each try host (every iteration until an ack), then each BRIDGE" },
        { "NODE_BROKER_PING_<n>",
          "community=henry,hostip=12.16.1.22,port_db=9000,port_udp=9200,pshare_iroutes=12.16.1.22:9200,timewarp=8,"
          "time=1325178800.81,key=0",
          "every 5 s, every 20 s while acks come" },
        { "NODE_PSHARE_VARS", "VIEW_POLYGON,VIEW_POINT,VIEW_SEGLIST,NODE_REPORT", "the bridges' aliases, after each valid ack (for uFldDelve)" },
        { "PMB_REGISTER", "src_var=NODE_REPORT_LOCAL,dest_community=shoreside,dest_host=10.0.0.8,dest_port=9200,dest_alias=NODE_REPORT",
          "seed (pMOOSBridge) missions, with NODE_BROKER_PING and HOST_INFO_REQUEST" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: MOOSTimeWarp (must equal the shore's).\n"
             "The model follows the mission: with a pMOOSBridge block the seed's (PMB_REGISTER), else MOOS-IvP 24.8's "
             "(PSHARE_CMD to kelp-bridge running as pShare).\n",
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
