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
    if (kelp_strieq_n(key, strlen(key), "APP_LOGGING")) {
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
    .synopsis = "The uFldMessageHandler tool handles incoming messages from other nodes. A message is a\n"
                "string holding its source and destination and a MOOS variable and value; the app\n"
                "posts that variable-value pair to the local community when the message is addressed\n"
                "to it (dest_node naming the community, dest_node=all, or a dest_group).",
    .params = (const kelp_app_param_info[]){
        { "VERBOSE", "true", "the full report (per source, last messages); false: totals only", NULL },
        { "STRICT_ADDRESSING", "false", "true: only messages whose dest_node names this community", NULL },
        { "AUX_INFO", "node", "node or node+app: the sender, as the posting's MOOS source-aux", NULL },
        { "APPCAST_TRUNC_MSG", "75", "characters of a listed valid message (0: whole)", NULL },
        { "MSG_FLAG", "RETURN=true", "posted after each message posted; $[CTR] $[GOOD_CTR] $[BAD_CTR] expand (repeatable)", NULL },
        { "BAD_MSG_FLAG", "TOTAL_BAD=$[BAD_CTR]", "posted after each message rejected for its address (repeatable); $[BAD_CTR]: rejected", NULL },
        { "APP_LOGGING", "false", "accepted (record the bus with kelp-record)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_MESSAGE", "src_node=alpha,dest_node=bravo,var_name=FOO,string_val=BAR",
          "also dest_group=, src_var= for var_name, double_val=, string_val=\"a,b\"" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "<var_name>", "BAR", "the message's variable: a string, or a double for double_val" },
        { "UMH_SUMMARY_MSGS", "total=23,valid=18,rejected=3", "after an iteration with mail, and every 100 iterations" },
        { "<MSG_FLAG>", "RETURN=true", NULL },
        { "<BAD_MSG_FLAG>", "TOTAL_BAD=5", NULL },
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
