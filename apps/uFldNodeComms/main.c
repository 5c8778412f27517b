/* uFldNodeComms: the shoreside relay of node reports and node messages between vehicles, by
 * range, stealth, earange, groups, staleness, message rate and length, as MOOS-IvP 24.8 runs
 * it. The logic is kelp_field_ncomms in the core; this file reads the block and wires the core
 * to the bus. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/field.h>

typedef struct ncomms {
    kelp_app *app;
    kelp_field_ncomms *core;   /* about 2.8 MB: on the heap (freed at exit) */
    kelp_field_ncomms_cfg cfg;
    kelp_field_sink sink;
    char *text;                /* the terminal summary */
    size_t text_cap;
} ncomms;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    ncomms *a = ctx;
    int rc = is_string ? kelp_app_notify_string(a->app, var, sval) : kelp_app_notify_double(a->app, var, dval);
    if (rc < 0) kelp_app_run_warning(a->app, "cannot publish %s", var);
}

static void warn(void *ctx, const char *msg)
{
    kelp_app_run_warning(((ncomms *)ctx)->app, "%s", msg);
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    ncomms *a = ctx;
    int rc = kelp_field_ncomms_config(&a->cfg, key, val, d);
    if (rc != 0) return rc;
    if (kelp_util_strieq_n(key, strlen(key), "APP_LOGGING")) {
        kelp_app_event(a->app, "APP_LOGGING accepted (record the bus with kelp-record)");
        return 1;
    }
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    ncomms *a = st;
    a->app = app;
    a->sink = (kelp_field_sink){ a, publish, warn };
    kelp_field_ncomms_cfg_default(&a->cfg);
    a->cfg.warp = kelp_app_warp(app);
    /* drop_percentage draws: a different sequence each run, as MOOS-IvP's (seeded from time) */
    a->cfg.seed = (uint64_t)(kelp_app_time(app) * 1000.0) ^ 0xA0761D6478BD642Full;
    int rc = kelp_app_param_foreach(app, param, a);
    if (rc < 0) return rc;
    double lat0, lon0; /* the datum: LAT,LON of reports with X,Y only, and the reverse */
    if (kelp_app_global_double(app, "LatOrigin", &lat0) == 1 && kelp_app_global_double(app, "LongOrigin", &lon0) == 1) {
        a->cfg.have_geo = kelp_geo_init(&a->cfg.geo, lat0, lon0) == 0;
        if (!a->cfg.have_geo) kelp_app_config_warning(app, "Geodesy failed to initialize");
    } else {
        kelp_app_config_warning(app, "Lat or Lon Origin not set in *.moos file.");
    }
    a->core = malloc(sizeof *a->core);
    a->text_cap = 64 * 1024 + (size_t)KELP_NCOMMS_MAX_NODES * 160;
    a->text = malloc(a->text_cap);
    if (!a->core || !a->text) return kelp_app_config_error(app, NULL, "out of memory");
    if (kelp_field_ncomms_init(a->core, &a->cfg) < 0)
        return kelp_app_config_error(app, NULL, "more STEALTH/EARANGE vehicles than %d", KELP_NCOMMS_MAX_NODES);
    const char *v;
    for (unsigned i = 0; (v = kelp_field_ncomms_subscription(i)) != NULL; i++)
        if (kelp_app_register(app, v, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", v);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    ncomms *a = st;
    if (v->kind == KELP_VAR_BINARY) return;
    int rc = kelp_field_ncomms_mail(a->core, v->name, v->kind == KELP_VAR_STRING, v->sval, v->dval, v->source,
                                    kelp_app_time(app), &a->sink);
    if (rc == 1 && (strstr(v->name, "_MESSAGE") != NULL)) kelp_app_event(app, "Msg rec'd: %s", v->sval); /* as 24.8 */
}

static int iterate(kelp_app *app, void *st, double now)
{
    ncomms *a = st;
    (void)app;
    (void)kelp_field_ncomms_iterate(a->core, now, &a->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    ncomms *a = st;
    if (!a->core || !a->cfg.verbose) return; /* VERBOSE = false: no summary */
    if (kelp_field_ncomms_report(a->core, kelp_app_time(app), a->text, a->text_cap) < 0)
        fputs("(summary truncated)\n", out);
    fputs(a->text, out);
}

static const kelp_app_def def = {
    .name = "uFldNodeComms",
    .purpose = "Relay node reports and node messages between vehicles by range, stealth, earange, groups and rate.",
    .ignore_own_posts = true, /* it reads NODE_REPORT/NODE_MESSAGE and posts NODE_REPORT_<V>, VIEW_COMMS_PULSE... */
    .params = (const kelp_app_param_info[]){
        { "COMMS_RANGE", "100", "m (default 100) within which reports and messages pass; nolimit or < 0: no limit", NULL },
        { "CRITICAL_RANGE", "30", "m (default 30) within which reports always pass (not messages)", NULL },
        { "STALE_TIME", "5", "s (default 5) after its last report a vehicle gets no reports; 20 x: forgotten; < 0 never", NULL },
        { "MAX_MSG_LENGTH", "1000", "characters of string_val (default 1000); 0 unlimited", NULL },
        { "MIN_MSG_INTERVAL", "30", "s (default 30) between the messages of one source, delivered or not", NULL },
        { "MIN_RPT_INTERVAL", "-1", "s between reports of one vehicle to another (default -1: off)", NULL },
        { "VERBOSE", "true", "print the summary (default true)", NULL },
        { "DEBUG", "false", "extra output (default false)", NULL },
        { "GROUPS", "false", "reports only within a GROUP, unless within the critical range (default false)", NULL },
        { "MSG_GROUPS", "false", "messages only within a GROUP (default false)", NULL },
        { "STEALTH", "vname=alpha, stealth=0.8", "a vehicle's reach factor in [0.1,1]; repeat per vehicle", NULL },
        { "EARANGE", "vname=alpha, earange=4.5", "a vehicle's hearing factor in [1,10]; repeat per vehicle", NULL },
        { "SHARED_NODE_REPORTS", "false", "NODE_REPORT_UNC locally: true (every 0.1 s real time), false, or s", NULL },
        { "PULSE_DURATION", "10", "s (default 10) of VIEW_COMMS_PULSE; <= 0 no pulses", NULL },
        { "VIEW_NODE_RPT_PULSES", "true", "pulses for node reports too (default true)", NULL },
        { "DROP_PERCENTAGE", "10", "percent [0,100] of relays dropped at random (default 0)", NULL },
        { "MSG_COLOR", "white", "message pulse colour (default white; off: none)", NULL },
        { "MSG_REPEAT_COLOR", "light_green", "pulse colour of a message id seen before (default light_green)", NULL },
        { "APP_LOGGING", "true", "accepted (record the bus with kelp-record)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_REPORT", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,LAT=43.824981,LON=-70.329755,"
                         "SPD=2.0,HDG=118.8,YAW=118.8,DEPTH=4.6,LENGTH=3.8,MODE=MODE@ACTIVE:LOITERING",
          "NAME, TIME and X,Y or LAT,LON required; DEP or DEPTH" },
        { "NODE_REPORT_LOCAL", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,DEP=4.6", NULL },
        { "NODE_MESSAGE", "src_node=henry,dest_node=ike,var_name=FOO,string_val=bar", "dest_node a:b list, all; dest_group" },
        { "MEDIATED_MESSAGE", "src_node=henry,dest_node=ike,var_name=FOO,string_val=bar,ack=true,ack_id=henry_3", NULL },
        { "ACK_MESSAGE", "src=ike,dest=henry,id=henry_3", NULL },
        { "UNC_STEALTH", "vname=alpha,stealth=0.4", NULL },
        { "UNC_EARANGE", "vname=alpha,earange=0.5", NULL },
        { "UNC_COMMS_RANGE", "250", NULL },
        { "UNC_DROP_PCT", "10", NULL },
        { "UNC_VIEW_NODE_RPT_PULSES", "false", NULL },
        { "UNC_SHARED_NODE_REPORTS", "true", NULL },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "NODE_REPORT_<VNAME>", "NAME=alpha,X=51.71,Y=-35.5,SPD=2,HDG=118.8,COG=118.8,DEP=4.6,LAT=43.824981,"
                                 "LON=-70.329755,TYPE=auv,TIME=1252348077.59,LENGTH=3.8",
          "re-written: COG, LAT/LON from the datum, type uuv -> auv, unknown -> ship" },
        { "NODE_MESSAGE_<VNAME>", "src_node=henry,dest_node=ike,src_app=pHelmIvP,var_name=FOO,string_val=bar",
          "re-written, src_app added" },
        { "MEDIATED_MESSAGE_<VNAME>", "ack_id=henry_3,ack=true,src_node=henry,dest_node=ike,var_name=FOO,string_val=bar",
          "a message with ack=true" },
        { "ACK_MESSAGE_<dest>", "id=henry_3, src=ike, dest=henry", "dest as written" },
        { "NODE_REPORT_UNC", "NAME=alpha,X=51.71,Y=-35.5,...", "with SHARED_NODE_REPORTS" },
        { "RTE", "0.25", "with SHARED_NODE_REPORTS: real seconds since a vehicle's last NODE_REPORT_UNC" },
        { "VIEW_COMMS_PULSE", "sx=4,sy=2,tx=44,ty=55,beam_width=6.64,fill=0.35,ptype=nrep,label=one2two,"
                              "fill_color=orange,time=1252348077.5,duration=10,edge_size=0",
          "messages: ptype=msg, fill=0.6, label <src>2<dest><colour>" },
        { NULL, NULL, NULL } },
    .synopsis = "A shoreside tool for managing communications between vehicles. It knows every\n"
                "vehicle's position from the node reports it receives, and passes reports and\n"
                "messages on to the vehicles that may hear them: limited by range, by how often\n"
                "messages are sent and how long they are, and by group.",
    .notes = "Globals used: MOOSTimeWarp (SHARED_NODE_REPORTS counts real time), LatOrigin and LongOrigin\n"
             "(LAT,LON of the relayed reports; a configuration warning without them).\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static ncomms a;
    return kelp_app_run(argc, argv, &def, &a);
}
