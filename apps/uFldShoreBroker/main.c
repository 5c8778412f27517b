/* uFldShoreBroker: on the shoreside, answer the vehicles' NODE_BROKER_PING and ask the
 * shore's kelp-bridge for the bridges to each vehicle ($V, $v and $N expanded in src). The
 * logic is the core kelp_field_sbroker (include/kelp/field.h), in one of two models chosen
 * by the mission:
 *  - MOOS-IvP 24.8's (no pMOOSBridge block, kelp-bridge running as pShare): PSHARE_CMD to
 *    each vehicle's pshare_iroutes, acks every iteration while a vehicle's ping is fresh;
 *  - the seed's (a pMOOSBridge block): PMB_REGISTER, an ack per accepted ping. */
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
    else if (strcmp(var, "PSHARE_CMD") == 0) kelp_app_event(s->app, "PSHARE_CMD:%s", sval);
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
        if (kelp_util_strieq_n(key, strlen(key), accepted[i])) return 1;
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    sbroker *s = st;
    s->app = app;
    s->sink = (kelp_field_sink){ s, publish, warn };
    /* the seed's model when the mission runs pMOOSBridge, MOOS-IvP 24.8's otherwise */
    if (kelp_mission_block(kelp_app_mission(app), "ProcessConfig", "pMOOSBridge") >= 0) kelp_field_sbroker_cfg_seed(&s->cfg);
    else kelp_field_sbroker_cfg_default(&s->cfg);
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
    /* 24.8: another community's NODE_BROKER_PING, our own community's PHI_HOST_INFO */
    bool local = strcmp(v->community, kelp_app_community(app)) == 0;
    if (!s->cfg.pmb && ((!strcmp(v->name, "PHI_HOST_INFO") && !local) || (!strcmp(v->name, "NODE_BROKER_PING") && local)))
        return;
    if (!s->cfg.pmb && !strcmp(v->name, "PSHARE_OUTPUT_SUMMARY")) {
        KELP_IGNORE(kelp_field_sbroker_mail(&s->core, v->name, v->kind == KELP_VAR_STRING, v->sval, kelp_app_time(app), &s->sink));
        return;
    }
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
    if (s->report[0] && s->report[strlen(s->report) - 1] != '\n') fputc('\n', out); /* 24.8's table ends without one */
    if (s->core.last_register[0] && s->cfg.pmb) fprintf(out, "\nLast PMB_REGISTER: %s\n", s->core.last_register);
}

static const kelp_app_def def = {
    .name = "uFldShoreBroker",
    .purpose = "Take the vehicles' NODE_BROKER_PING, ack them, and have pShare bridge BRIDGE/QBRIDGE variables to each.",
    .params = (const kelp_app_param_info[]){
        { "WARNING_ON_STALE", "false (default)", "a run warning when a vehicle stops pinging for 10 s", NULL },
        { "AUTO_BRIDGE_REALMCAST", "true  (default)", "also QBRIDGE REALMCAST_REQ", NULL },
        { "AUTO_BRIDGE_APPCAST", "true  (default)", "also QBRIDGE APPCAST_REQ", NULL },
        { "AUTO_BRIDGE_MHASH", "true  (default)", "also BRIDGE src=MISSION_HASH", NULL },
        { "BRIDGE", "src=DEPLOY_$V,  alias=DEPLOY",
          "repeatable: src=V[, alias=A] bridged to each vehicle; in src $V = NAME, $v = name, $N = 1,2,..", NULL },
        { "TRY_VNODE", "192.168.4.24:9200", "repeatable: send TRY_SHORE_HOST to this vehicle pShare ([route=]ip[:port])", NULL },
        { "QBRIDGE", "NODE_REPORT, STATION_KEEP", "repeatable: X is BRIDGE src=X_ALL, alias=X plus src=X_$V, alias=X", NULL },
        { "KEYWORD", "lemon", "optional: pings must carry this keyword", NULL },
        { "APP_LOGGING", "true  // {true or file} By default disabled", "accepted", NULL },
        { "MAX_APPCAST_EVENTS", "8", "accepted", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "PHI_HOST_INFO", "community=shoreside,hostip=10.0.0.8,port_db=9000,port_udp=9200,pshare_iroutes=10.0.0.8:9200,timewarp=8",
          "from pHostInfo (our own community): needed before any ack" },
        { "NODE_BROKER_PING",
          "community=henry,hostip=12.16.1.22,port_db=9000,port_udp=9200,pshare_iroutes=12.16.1.22:9200,timewarp=8,"
          "time=1325178800.81,key=0",
          "from the vehicles (bridged)" },
        { "PSHARE_OUTPUT_SUMMARY", "DEPLOY_ALL->DEPLOY:12.16.1.22:9200", "from pShare: bridges it has already" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "PSHARE_CMD", "cmd=output,src_name=DEPLOY_ALL,dest_name=DEPLOY,route=18.11.4.23:9200",
          "to pShare, per vehicle: each bridge, then NODE_BROKER_ACK_$V -> NODE_BROKER_ACK" },
        { "NODE_BROKER_ACK_<V>",
          "community=shoreside,hostip=192.168.1.199,port_db=9000,pshare_iroutes=192.168.1.199:9300,timewarp=8,status=ok,key=0,id=123",
          "every iteration while the vehicle's last ping is younger than 10 s" },
        { "NODE_BROKER_VACK", "alpha", "with each ack" },
        { "UFSB_NODE_COUNT", "5", "vehicles known" },
        { "UFSB_QBRIDGE_VARS", "NODE_REPORT,RETURN", "the QBRIDGE names, sorted; at start" },
        { "UFSB_BRIDGE_VARS", "DEPLOY_$V,DEPLOY_HENRY,NODE_BROKER_ACK_$V,NODE_BROKER_ACK_HENRY,RETURN_ALL",
          "the bridged sources, sorted; when one is new" },
        { "PSHARE_TEST", "DEPLOY_ALL->DEPLOY:12.16.1.22:9200", "per bridge request: a count, the bridge, needed=true|false" },
        { "TRY_SHORE_HOST", "pshare_route=192.168.4.100:9200", "to each TRY_VNODE every 10 s" },
        { "PMB_REGISTER", "src_var=DEPLOY_ALL,dest_community=henry,dest_host=12.56.111.1,dest_port=9200,dest_alias=DEPLOY",
          "seed (pMOOSBridge) missions, with HOST_INFO_REQUEST" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: MOOSTimeWarp (a vehicle's must be equal).\n"
             "The model follows the mission: with a pMOOSBridge block the seed's (PMB_REGISTER), else MOOS-IvP 24.8's "
             "(PSHARE_CMD to kelp-bridge running as pShare).\n",
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
