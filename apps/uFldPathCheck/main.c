/* uFldPathCheck: each vehicle's odometry and speed, computed on the shoreside from its node
 * reports, as MOOS-IvP 24.8's uFldPathCheck. The logic is kelp_pathcheck in the core
 * (include/kelp/pathcheck.h); this file reads the block and wires the core to the bus. */
#include <stdio.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/pathcheck.h>
#include <kelp/util.h>

typedef struct upc_app {
    kelp_app *app;
    kelp_pathcheck core;
    kelp_pathcheck_cfg cfg;
    kelp_field_sink sink;
    char text[32768];
} upc_app;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    upc_app *a = ctx;
    int rc = is_string ? kelp_app_notify_string(a->app, var, sval) : kelp_app_notify_double(a->app, var, dval);
    if (rc < 0) kelp_app_run_warning(a->app, "cannot publish %s", var);
}

static void warn(void *ctx, const char *msg)
{
    kelp_app_run_warning(((upc_app *)ctx)->app, "%s", msg);
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    upc_app *a = ctx;
    int rc = kelp_pathcheck_config(&a->cfg, key, val, d);
    if (rc != 0) return rc;
    /* 24.8's AppCasting parameters are taken quietly; the runner warns of the rest as 24.8 */
    return kelp_util_strieq(key, "APP_LOGGING") || kelp_util_strieq(key, "MAX_APPCAST_EVENTS");
}

static int startup(kelp_app *app, void *st)
{
    upc_app *a = st;
    a->app = app;
    a->sink = (kelp_field_sink){ a, publish, warn };
    kelp_pathcheck_cfg_default(&a->cfg);
    int rc = kelp_app_param_foreach(app, param, a);
    if (rc < 0) return rc;
    if (kelp_pathcheck_init(&a->core, &a->cfg) < 0) return kelp_app_config_error(app, NULL, "bad HISTORY_LENGTH");
    const char *v;
    for (unsigned i = 0; (v = kelp_pathcheck_subscription(i)) != NULL; i++)
        if (kelp_app_register(app, v, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", v);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    upc_app *a = st;
    if (v->kind != KELP_VAR_STRING) return;
    (void)kelp_pathcheck_mail(&a->core, v->name, true, v->sval, kelp_app_time(app), &a->sink);
}

static int iterate(kelp_app *app, void *st, double now)
{
    upc_app *a = st;
    (void)app;
    (void)kelp_pathcheck_iterate(&a->core, now, &a->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    upc_app *a = st;
    if (kelp_pathcheck_report(&a->core, kelp_app_time(app), kelp_app_warp(app), a->text, sizeof a->text) < 0)
        fputs("(report truncated)\n", out);
    fputs(a->text, out);
}

static const kelp_app_def def = {
    .name = "uFldPathCheck",
    .purpose = "Speed and odometry of every vehicle, computed on the shoreside from its node reports.",
    .synopsis = "Typically run in a shoreside community. Takes node reports from remote vehicles and computes\n"
                "each one's present speed (the mean leg speed along its last HISTORY_LENGTH reports, posted\n"
                "every iteration) and the distance travelled (total and since the last trip reset).",
    .params = (const kelp_app_param_info[]){
        { "HISTORY_LENGTH", "10", "reports in the speed queue (default 10), 2..100", NULL },
        { "APP_LOGGING", "true", "accepted (record the bus with kelp-record)", NULL },
        { "MAX_APPCAST_EVENTS", "8", "accepted", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_REPORT", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,SPD=2.0,HDG=118.8", "NAME, X, Y, TIME" },
        { "NODE_REPORT_LOCAL", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50", NULL },
        { "UPC_TRIP_RESET", "alpha", "resets alpha's trip_dist" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "UPC_SPEED_REPORT", "vname=alpha,avg_spd=2.21", "every iteration, per vehicle with two reports" },
        { "UPC_ODOMETRY_REPORT", "vname=alpha,total_dist=4205.4,trip_dist=1105.2", "after each change" },
        { NULL, NULL, NULL } },
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .unhandled_prefix = "Unhandled config line: ", /* 24.8's reportUnhandledConfigWarning */
};

int main(int argc, char **argv)
{
    static upc_app a;
    return kelp_app_run(argc, argv, &def, &a);
}
