/* uFldBeaconRangeSensor: range-only sensing to fixed beacons, solicited (BRS_RANGE_REQUEST)
 * or on each beacon's own schedule, with optional noise (uField seed chapter 10, with
 * MOOS-IvP 24.8's names). The logic is kelp_beaconrange in the core (kelp/beaconrange.h); this
 * file reads the block and wires the core to the bus. */
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <kelp/edge/app.h>
#include <kelp/beaconrange.h>
#include <kelp/util.h>

typedef struct brs_app {
    kelp_app *app;
    kelp_beaconrange core;
    kelp_beaconrange_cfg cfg;
    kelp_field_sink sink;
    char rn_line[192]; /* the last RN_ALGORITHM line, for 24.8's warning in glibc mode */
    char text[8192];
} brs_app;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    brs_app *a = ctx;
    int rc = is_string ? kelp_app_notify_string(a->app, var, sval) : kelp_app_notify_double(a->app, var, dval);
    if (rc < 0) kelp_app_run_warning(a->app, "cannot publish %s", var);
}

static void warn(void *ctx, const char *msg) { kelp_app_run_warning(((brs_app *)ctx)->app, "%s", msg); }

static void log_line(void *ctx, const char *line)
{
    brs_app *a = ctx;
    if (a->cfg.com.verbose) printf("%s\n", line);
    kelp_app_event(a->app, "%s", line); /* 24.8's reportEvent */
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    brs_app *a = ctx;
    if (kelp_util_strieq(key, "RN_ALGORITHM")) (void)kelp_util_snprintf(a->rn_line, sizeof a->rn_line, "%s=%s", key, val);
    int rc = kelp_beaconrange_config(&a->cfg, key, val, d);
    if (rc == 2) {
        kelp_app_config_warning(a->app, "%s = %s: %s", key, val, KELP_BRS_WARN_QUERY_RANGE);
        return 1;
    }
    if (rc != 0) return rc;
    if (kelp_util_strieq(key, "APP_LOGGING")) return 1; /* 24.8: record the bus with kelp-record instead */
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    brs_app *a = st;
    a->app = app;
    a->sink = (kelp_field_sink){ a, publish, warn };
    kelp_beaconrange_cfg_default(&a->cfg);
    /* RAND_MODE first (the block's, else $KELP_RAND_MODE): in glibc mode the noise lines are read
     * as 24.8 reads them; a bad block value is said by foreach, a bad environment one here */
    char mode[16];
    const char *m = kelp_app_param_str(app, "RAND_MODE", mode, sizeof mode) == 1 ? mode : getenv("KELP_RAND_MODE");
    kelp_diag dm = { 0 };
    if (m && kelp_rangesense_common_config(&a->cfg.com, "RAND_MODE", m, &dm) < 0 && m != mode)
        return kelp_app_config_error(app, NULL, "KELP_RAND_MODE=%s: %s", m, kelp_diag_text(&dm));
    int rc = kelp_app_param_foreach(app, param, a);
    if (rc < 0) return rc;
    if (kelp_rangesense_common_as_248(&a->cfg.com)) /* RAND_MODE = glibc: 24.8 has no gaussian */
        kelp_app_config_warning(app, "Unhandled config line: %s", a->rn_line);
    double lat0, lon0;
    if (kelp_app_global_double(app, "LatOrigin", &lat0) == 1 && kelp_app_global_double(app, "LongOrigin", &lon0) == 1)
        a->cfg.com.have_geo = kelp_geo_init(&a->cfg.com.geo, lat0, lon0) == 0;
    a->cfg.com.log = log_line;
    a->cfg.com.log_ctx = a;
    kelp_diag dg = { 0 };
    if (kelp_beaconrange_init(&a->core, &a->cfg, kelp_app_time(app), &dg) < 0)
        return kelp_app_config_error(app, NULL, "BEACON: %s", dg.code ? kelp_diag_text(&dg) : "bad");
    const char *v;
    for (unsigned i = 0; (v = kelp_beaconrange_subscription(i)) != NULL; i++)
        if (kelp_app_register(app, v, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", v);
    printf("Simulated Range Sensor starting...\n");
    if (kelp_beaconrange_summary(&a->core, a->text, sizeof a->text) < 0) fputs("(summary truncated)\n", stdout);
    fputs(a->text, stdout);
    printf("Simulated Range Sensor started.\n");
    fflush(stdout);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    brs_app *a = st;
    if (v->kind == KELP_VAR_BINARY) return;
    /* refused mail is warned through the sink and counted by the core */
    KELP_IGNORE(kelp_beaconrange_mail(&a->core, v->name, v->kind == KELP_VAR_STRING, v->sval, kelp_app_time(app), &a->sink));
}

static int iterate(kelp_app *app, void *st, double now)
{
    brs_app *a = st;
    (void)app;
    (void)kelp_beaconrange_iterate(&a->core, now, &a->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    brs_app *a = st;
    (void)app;
    if (kelp_beaconrange_report(&a->core, a->text, sizeof a->text) < 0) fputs("(report truncated)\n", out);
    fputs(a->text, out);
}

static const kelp_app_def def = {
    .name = "uFldBeaconRangeSensor",
    .purpose = "Simulate range-only sensing from vehicles to fixed beacons, on request or on a schedule.",
    .ignore_own_posts = true,
    .params = (const kelp_app_param_info[]){
        { "BEACON", "x=200, y=435, label=01, report_range=45", "x, y (required), label, freq, shape, width, color, "
          "report_range (push_dist), pull_dist; repeat; a label given again replaces that beacon", NULL },
        { "DEFAULT_BEACON_FREQ", "never", "unsolicited period: never (default), <secs> or <a>:<b> (uniform)", NULL },
        { "DEFAULT_BEACON_REPORT_RANGE", "50", "m (default 50, 24.8's) a beacon's reply carries; nolimit", NULL },
        { "DEFAULT_BEACON_PUSH_DIST", "50", "24.8 name of DEFAULT_BEACON_REPORT_RANGE", "DEFAULT_BEACON_REPORT_RANGE" },
        { "DEFAULT_BEACON_PULL_DIST", "50", "m added to a vehicle's reach (default 50, 24.8's)", NULL },
        { "DEFAULT_BEACON_WIDTH", "4", "m (default 4) when rendered", NULL },
        { "DEFAULT_BEACON_COLOR", "orange", "default orange", NULL },
        { "DEFAULT BEACON_COLOR", "orange", "24.8's --example spelling", "DEFAULT_BEACON_COLOR" },
        { "DEFAULT_BEACON_SHAPE", "circle", "circle (default), square, diamond, triangle, ...", NULL },
        { "REACH_DISTANCE", "default = 100", "[<vname>|default =] m or nolimit a vehicle's request carries (100)", NULL },
        { "NODE_PUSH_DIST", "default = 100", "24.8 name of REACH_DISTANCE", "REACH_DISTANCE" },
        { "NODE_PULL_DIST", "default = 100", "[<vname>|default =] m added to the beacons' report range (100)", NULL },
        { "PING_WAIT", "default = 30", "[<vname>|default =] s between honoured requests (30)", NULL },
        { "PING_PAYMENTS", "upon_response", "upon_response (default, 24.8's), upon_accept (alias upon_receipt), upon_request", NULL },
        { "REPORT_VARS", "short", "short (BRS_RANGE_REPORT), long (BRS_RANGE_REPORT_<V>) or both", NULL },
        { "GROUND_TRUTH", "true", "with noise, also post BRS_RANGE_REPORT_GT, the noiseless range (default true)", NULL },
        { "RN_ALGORITHM", "uniform,pct=0", "noise: uniform,pct=<[0,1]> or gaussian,sigma=<m> (default none)", NULL },
        { "RN_UNIFORM_PCT", "0", "the fraction of RN_ALGORITHM = uniform (alone: no noise, as 24.8)", "RN_ALGORITHM" },
        { "RN_GAUSSIAN_SIGMA", "0", "the sigma of RN_ALGORITHM = gaussian (kelp's)", "RN_ALGORITHM" },
        { "REPORT_XY", "false", "x=,y= of the beacon in each report (default false)", NULL },
        { "BEACON_ORDER", "reverse", "reverse (24.8's: its mission reader hands the block over backwards; default) or config", NULL },
        { "RAND_MODE", "kelp", "kelp (seeded by SEED_RANDOM) or glibc (rand() unseeded, as MOOS-IvP; also $KELP_RAND_MODE when the block has none)", NULL },
        { "SEED_RANDOM", "1", "seed of the kelp generator (default 1)", NULL },
        { "VERBOSE", "false", "print events (default false; --verbose also)", NULL },
        { "APP_LOGGING", "true", "accepted (record the bus with kelp-record)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_REPORT", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,SPD=2.0,HDG=118.8", NULL },
        { "NODE_REPORT_LOCAL", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50", NULL },
        { "BRS_RANGE_REQUEST", "name=archie", NULL },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "BRS_RANGE_REPORT", "vname=indigo,range=166.7446,id=03,time=23371445385.6", "REPORT_VARS short/both" },
        { "BRS_RANGE_REPORT_<VNAME>", "range=166.7446,id=03,time=23371445385.6", "REPORT_VARS long/both" },
        { "BRS_RANGE_REPORT_GT", "vname=indigo,range=166.7446,id=03,time=23371445385.6", "GROUND_TRUTH" },
        { "BRS_RANGE_REPORT_GT_<VNAME>", "range=166.7446,id=03,time=23371445385.6", "GROUND_TRUTH, long/both" },
        { "VIEW_MARKER", "x=0,y=-200,width=5,primary_color=red,type=triangle", "once per beacon" },
        { "VIEW_RANGE_PULSE", "x=23.76,y=0,radius=40,fill=0.9,label=indigo_range_req,edge_color=white,fill_color=white,"
                              "time=1795285739.73,duration=6,edge_size=1", "request <v>_range_req white; a beacon's <label> pink" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: LatOrigin and LongOrigin (optional: X,Y for reports with only LAT,LON).\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .unhandled_prefix = "Unhandled config line: ", /* 24.8's warning for an unhandled line */
};

int main(int argc, char **argv)
{
    static brs_app a;
    return kelp_app_run(argc, argv, &def, &a);
}
