/* uFldMessageHandler: unwrap the NODE_MESSAGEs other vehicles send this one and post the
 * variable each carries (ufield.md 6). The logic is the core kelp_field_umh
 * (include/kelp/field.h); this file reads the block and wires the core to the bus.
 *
 * As MOOS-IvP 24.8 does, the carried variable is posted with the sending node (node+app with
 * aux_info = node+app) as its MOOS source-aux. */
#include <stdio.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/field.h>

typedef struct umh {
    kelp_app *app;
    kelp_field_umh_cfg cfg;
    kelp_field_umh core;
    kelp_field_sink sink;
} umh;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    umh *u = ctx;
    int rc = kelp_app_notify_aux(u->app, var, is_string, sval, dval, u->core.posting ? u->core.aux : NULL);
    if (rc < 0) kelp_app_run_warning(u->app, "cannot publish %s", var);
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    umh *u = ctx;
    int rc = kelp_field_umh_config(&u->cfg, key, val, d);
    if (rc != 0) return rc;
    if (kelp_util_strieq_n(key, strlen(key), "APP_LOGGING")) {
        kelp_app_event(u->app, "APP_LOGGING accepted (record the bus with kelp-record)");
        return 1;
    }
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    umh *u = st;
    u->app = app;
    u->sink = (kelp_field_sink){ u, publish, NULL };
    kelp_field_umh_cfg_default(&u->cfg, kelp_app_community(app));
    int rc = kelp_app_param_foreach(app, param, u);
    if (rc < 0) return rc;
    kelp_field_umh_init(&u->core, &u->cfg);
    if (kelp_app_register(app, "NODE_MESSAGE", 0) < 0) return kelp_app_config_error(app, NULL, "cannot register NODE_MESSAGE");
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    umh *u = st;
    /* an invalid or rejected message is counted and listed in the report (24.8 warns of neither) */
    KELP_IGNORE(kelp_field_umh_mail(&u->core, v->name, v->kind == KELP_VAR_STRING, v->sval, kelp_app_time(app), &u->sink));
}

static int iterate(kelp_app *app, void *st, double now)
{
    umh *u = st;
    (void)app;
    (void)kelp_field_umh_iterate(&u->core, now, &u->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    umh *u = st;
    static char buf[8192];
    size_t n = kelp_field_umh_report(&u->core, kelp_app_time(app), buf, sizeof buf);
    fwrite(buf, 1, n, out);
}

static const kelp_app_def def = {
    .name = "uFldMessageHandler",
    .purpose = "Post the variable-value pair carried by each NODE_MESSAGE addressed to this vehicle.",
    .synopsis = "The uFldMessageHandler tool handles the messages other nodes send this one. A message is\n"
                "a string naming its source and destination and carrying a MOOS variable and its\n"
                "value; the app posts that variable-value pair to the local MOOSDB, with the sending\n"
                "node as the posting's source-aux, when the message is addressed to it (dest_node\n"
                "naming the community exactly, all or ALL, or only a dest_group).",
    /* as MOOS-IvP 24.8's --example writes its block: names, order and sample values */
    .params = (const kelp_app_param_info[]){
        { "strict_addressing", "false", "default; true: only messages whose dest_node names this community", NULL },
        { "appcast_trunc_msg", "75", "default: characters of a listed valid message in the report (0: whole)", NULL },
        { "msg_flag", "RETURN=true", "posted after each message posted; $[CTR] $[GOOD_CTR] $[BAD_CTR] expand (repeatable)", NULL },
        { "bad_msg_flag", "TOTAL_BAD=$[BAD_CTR]", "posted after each message rejected for its address (repeatable)", NULL },
        { "aux_info", "node+app", "node or node+app (default node): the sender, as the posting's MOOS source-aux", NULL },
        { "app_logging", "true", "accepted (record the bus with kelp-record)", NULL },
        { "verbose", "true", "kelp: the full report (per source, last messages); false: totals only", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_MESSAGE", "src_node=alpha,dest_node=bravo,var_name=FOO,string_val=BAR",
          "or dest_group=, double_val=, string_val=\"a,b\" (kelp also reads the seed's src_var= for var_name)" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "UMH_SUMMARY_MSGS", "total=23,valid=18,rejected=5", "after an iteration with mail, and every 100 iterations" },
        { "<var_name>", "BAR", "(a) node message content: a string, or a double when there is no string" },
        { "<MSG_FLAG>", "RETURN=true", "(b) msg_flag content" },
        { "<BAD_MSG_FLAG>", "TOTAL_BAD=5", "(c) bad_msg_flag content" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: Community (this vehicle's name, matched against dest_node).\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static umh u;
    return kelp_app_run(argc, argv, &def, &u);
}
