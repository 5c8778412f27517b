/* uFldContactRangeSensor: a simulated active sonar; a vehicle's ping (CRS_RANGE_REQUEST) is
 * answered with the range to each other vehicle within reach + reply, with optional noise
 * (uField seed chapter 11, with MOOS-IvP 24.8's names). The logic is kelp_contactrange in the
 * core (kelp/contactrange.h); this file reads the block and wires the core to the bus. */
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <kelp/edge/app.h>
#include <kelp/contactrange.h>
#include <kelp/util.h>

typedef struct crs_app {
    kelp_app *app;
    kelp_contactrange core;
    kelp_contactrange_cfg cfg;
    kelp_field_sink sink;
    char rn_line[192]; /* the last RN_ALGORITHM line, for 24.8's warning in glibc mode */
    char text[8192];
} crs_app;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    crs_app *a = ctx;
    int rc = is_string ? kelp_app_notify_string(a->app, var, sval) : kelp_app_notify_double(a->app, var, dval);
    if (rc < 0) kelp_app_run_warning(a->app, "cannot publish %s", var);
    if (a->cfg.com.verbose) printf("DBPost: %s %s\n", var, is_string ? sval : "");
}

static void warn(void *ctx, const char *msg) { kelp_app_run_warning(((crs_app *)ctx)->app, "%s", msg); }

static void log_line(void *ctx, const char *line)
{
    crs_app *a = ctx;
    if (a->cfg.com.verbose) printf("%s\n", line);
    kelp_app_event(a->app, "%s", line); /* 24.8's reportEvent */
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    crs_app *a = ctx;
    if (kelp_util_strieq(key, "RN_ALGORITHM")) (void)kelp_util_snprintf(a->rn_line, sizeof a->rn_line, "%s=%s", key, val);
    int rc = kelp_contactrange_config(&a->cfg, key, val, d);
    if (rc != 0) return rc;
    if (kelp_util_strieq(key, "APP_LOGGING")) return 1; /* 24.8: record the bus with kelp-record instead */
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    crs_app *a = st;
    a->app = app;
    a->sink = (kelp_field_sink){ a, publish, warn };
    kelp_contactrange_cfg_default(&a->cfg);
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
        kelp_app_config_warning(app, "Unhandled config: %s", a->rn_line);
    double lat0, lon0;
    if (kelp_app_global_double(app, "LatOrigin", &lat0) == 1 && kelp_app_global_double(app, "LongOrigin", &lon0) == 1)
        a->cfg.com.have_geo = kelp_geo_init(&a->cfg.com.geo, lat0, lon0) == 0;
    a->cfg.com.log = log_line;
    a->cfg.com.log_ctx = a;
    kelp_contactrange_init(&a->core, &a->cfg, kelp_app_time(app));
    const char *v;
    for (unsigned i = 0; (v = kelp_contactrange_subscription(i)) != NULL; i++)
        if (kelp_app_register(app, v, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", v);
    printf("Simulated Active Sonar starting...\n-----\n");
    if (kelp_contactrange_summary(&a->core, a->text, sizeof a->text) < 0) fputs("(summary truncated)\n", stdout);
    fputs(a->text, stdout);
    printf("-----\nSimulated Active Sonar started.\n");
    fflush(stdout);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    crs_app *a = st;
    if (v->kind == KELP_VAR_BINARY) return;
    /* refused mail is warned through the sink and counted by the core */
    KELP_IGNORE(kelp_contactrange_mail(&a->core, v->name, v->kind == KELP_VAR_STRING, v->sval, kelp_app_time(app),
                                       &a->sink));
}

static void report(kelp_app *app, void *st, FILE *out)
{
    crs_app *a = st;
    (void)app;
    if (kelp_contactrange_report(&a->core, a->text, sizeof a->text) < 0) fputs("(report truncated)\n", out);
    fputs(a->text, out);
}

static const kelp_app_def def = {
    .name = "uFldContactRangeSensor",
    .purpose = "Simulate an active sonar: answer a vehicle's ping with the ranges to the vehicles it reaches.",
    .ignore_own_posts = true,
    .params = (const kelp_app_param_info[]){
        { "REACH_DISTANCE", "default = 100", "[<vname>|default =] m or nolimit the pinger's ping reaches (100)", NULL },
        { "PUSH_DIST", "default = 100", "24.8 name of REACH_DISTANCE", "REACH_DISTANCE" },
        { "PUSH_DISTANCE", "default = 100", "24.8 name of REACH_DISTANCE", "REACH_DISTANCE" },
        { "REPLY_DISTANCE", "default = 100", "[<vname>|default =] m or nolimit a target's echo carries (100)", NULL },
        { "PULL_DIST", "default = 100", "24.8 name of REPLY_DISTANCE", "REPLY_DISTANCE" },
        { "PULL_DISTANCE", "default = 100", "24.8 name of REPLY_DISTANCE", "REPLY_DISTANCE" },
        { "PING_WAIT", "default = 30", "[<vname>|default =] s between honoured pings (30)", NULL },
        { "REPORT_VARS", "short", "short (CRS_RANGE_REPORT), long (CRS_RANGE_REPORT_<V>) or both", NULL },
        { "GROUND_TRUTH", "true", "with noise, also post CRS_RANGE_REPORT_GT, the noiseless range (default true)", NULL },
        { "PING_COLOR", "white", "colour of the ping pulse (default white)", NULL },
        { "REPLY_COLOR", "chartreuse", "colour of the reply pulse (default chartreuse)", NULL },
        { "ECHO_COLOR", "chartreuse", "24.8 name of REPLY_COLOR", "REPLY_COLOR" },
        { "DISPLAY_PULSES", "true", "post VIEW_RANGE_PULSE (default true)", NULL },
        { "RN_ALGORITHM", "uniform,pct=0", "noise: uniform,pct=<[0,1]> or gaussian,sigma=<m> (default none)", NULL },
        { "RN_UNIFORM_PCT", "0", "the fraction of RN_ALGORITHM = uniform (alone: no noise, as 24.8)", "RN_ALGORITHM" },
        { "RN_GAUSSIAN_SIGMA", "0", "the sigma of RN_ALGORITHM = gaussian (kelp's; alone: no noise, as 24.8)", "RN_ALGORITHM" },
        { "ALLOW_ECHO_TYPES", "uuv", "only targets of these node report TYPEs answer (default all)", NULL },
        { "SENSOR_ARC", "360", "relative bearings heard: 360 (default) or <a>:<b>[,<a>:<b>]", NULL },
        { "ECHO_FALLOFF", "true", "24.8's chance of an echo beyond reach + reply (default true; kelp's switch)", NULL },
        { "RAND_MODE", "kelp", "kelp (seeded by SEED_RANDOM) or glibc (rand() unseeded, as MOOS-IvP; also $KELP_RAND_MODE when the block has none)", NULL },
        { "SEED_RANDOM", "1", "seed of the kelp generator (default 1)", NULL },
        { "VERBOSE", "false", "print events (default false; --verbose also)", NULL },
        { "APP_LOGGING", "true", "accepted (record the bus with kelp-record)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_REPORT", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,SPD=2.0,HDG=118.8", NULL },
        { "NODE_REPORT_LOCAL", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50", NULL },
        { "CRS_RANGE_REQUEST", "name=archie", NULL },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "CRS_RANGE_REPORT", "vname=archie,range=176.6565,target=jackal,time=23588509131.764", "REPORT_VARS short/both" },
        { "CRS_RANGE_REPORT_<VNAME>", "range=176.6565,target=jackal,time=23588509131.764", "the requester; long/both" },
        { "CRS_RANGE_REPORT_GT", "vname=archie,range=174.1391,target=jackal,time=23588509131.764", "GROUND_TRUTH" },
        { "CRS_RANGE_REPORT_GT_<VNAME>", "range=174.1391,target=jackal,time=23588509131.764", "GROUND_TRUTH, long" },
        { "VIEW_RANGE_PULSE", "x=-59.5,y=-40,radius=50,fill=0.9,label=archie_ping,edge_color=white,fill_color=white,"
                              "time=1795284917.5,duration=6,edge_size=1", "<v>_ping, and <t>_echo at each target" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: LatOrigin and LongOrigin (optional: X,Y for reports with only LAT,LON).\n",
    .startup = startup,
    .on_mail = on_mail,
    .report = report,
    .unhandled_prefix = "Unhandled config: ", /* 24.8's warning for an unhandled line */
};

int main(int argc, char **argv)
{
    static crs_app a;
    return kelp_app_run(argc, argv, &def, &a);
}
