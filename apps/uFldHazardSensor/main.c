/* uFldHazardSensor: a simulated hazard sensor (detection on a ROC curve, classification on
 * request) for every vehicle over a field of hazard and benign objects, as MOOS-IvP 24.8's
 * build of the app behaves. The logic is kelp_hazardsensor in the core
 * (include/kelp/hazardsensor.h); this file reads the block and the hazard file and wires the
 * core to the bus. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/app.h>
#include <kelp/hazardsensor.h>
#include <kelp/util.h>

typedef struct uhz_app {
    kelp_app *app;
    kelp_hazardsensor *core;      /* about 200 KB: on the heap (freed at exit) */
    kelp_hazardsensor_cfg *cfg;
    kelp_field_sink sink;
    char file[512];            /* the AppCast's "Hazard File:" ("": none given) */
    char text[16384];
} uhz_app;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    uhz_app *a = ctx;
    int rc = is_string ? kelp_app_notify_string(a->app, var, sval) : kelp_app_notify_double(a->app, var, dval);
    if (rc < 0) kelp_app_run_warning(a->app, "cannot publish %s", var);
}

static void warn(void *ctx, const char *msg)
{
    kelp_app_run_warning(((uhz_app *)ctx)->app, "%s", msg);
}

static void event(void *ctx, const char *msg)
{
    kelp_app_event(((uhz_app *)ctx)->app, "%s", msg);
}

static void cfg_warning(void *ctx, const char *msg)
{
    kelp_app_config_warning(((uhz_app *)ctx)->app, "%s", msg);
}

/* A relative hazard file is looked for in the working directory, then beside the mission. */
static FILE *open_hazards(uhz_app *a, const char *name)
{
    FILE *f = fopen(name, "r");
    const char *m = kelp_app_mission_path(a->app);
    const char *slash = m ? strrchr(m, '/') : NULL;
    if (!f && name[0] != '/' && slash) {
        char path[1024];
        kelp_util_snprintf(path, sizeof path, "%.*s/%s", (int)(slash - m), m, name);
        f = fopen(path, "r");
    }
    return f;
}

/* As 24.8: a file that cannot be read (or is empty) shows as "Error reading: <file>" and is
 * an unhandled parameter; a poorly specified hazard in it is a configuration warning. */
static int read_hazard_file(uhz_app *a, const char *name)
{
    FILE *f = open_hazards(a, name);
    char line[1024];
    unsigned lines = 0;
    while (f && fgets(line, sizeof line, f)) {
        lines++;
        kelp_diag dg = { 0 };
        if (kelp_hazardsensor_hazard_line(a->cfg, line, &dg) < 0) {
            line[strcspn(line, "\r\n")] = 0;
            kelp_app_config_warning(a->app, "Poorly specified hazard: %s", line);
        }
    }
    if (f) fclose(f);
    kelp_util_snprintf(a->file, sizeof a->file, lines ? "%s" : "Error reading: %s", name);
    if (!lines) kelp_app_config_warning(a->app, "Unhandled config line: hazard_file = %s", name);
    return 1;
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    uhz_app *a = ctx;
    if (kelp_util_strieq(key, "HAZARD_FILE")) return read_hazard_file(a, val);
    /* 24.8's AppCasting settings: kelp's runner has its own */
    if (kelp_util_strieq(key, "TERM_REPORT_INTERVAL") || kelp_util_strieq(key, "MAX_APPCAST_EVENTS") ||
        kelp_util_strieq(key, "MAX_APPCAST_RUN_WARNINGS"))
        return 1;
    kelp_diag why = { 0 };
    int rc = kelp_hazardsensor_config(a->cfg, key, val, &why);
    if (rc < 0) { /* 24.8 warns and goes on */
        if (kelp_util_strieq(key, "HAZARD")) kelp_app_config_warning(a->app, "%s", kelp_diag_text(&why));
        else kelp_app_config_warning(a->app, "%s = %s: %s", key, val, kelp_diag_text(&why));
        return 1;
    }
    (void)d;
    return rc;
}

static int startup(kelp_app *app, void *st)
{
    uhz_app *a = st;
    a->app = app;
    a->sink = (kelp_field_sink){ a, publish, warn };
    a->cfg = malloc(sizeof *a->cfg);
    a->core = malloc(sizeof *a->core);
    if (!a->cfg || !a->core) return kelp_app_config_error(app, NULL, "out of memory");
    kelp_hazardsensor_cfg_default(a->cfg);
    int rc = kelp_app_param_foreach(app, param, a);
    if (rc < 0) return rc;
    /* SEED_RANDOM = true (24.8's default): srand(time(NULL)) */
    if (a->cfg->seed_random) a->cfg->seed = (uint32_t)time(NULL);
    if (a->cfg->nobjects == 0) kelp_app_config_warning(app, "No Hazard Field Laydown Provided.");
    if (a->cfg->nsettings == 0) kelp_app_config_warning(app, "Sensor was configured with NO sensor_config properties!");
    if (kelp_hazardsensor_init(a->core, a->cfg) < 0) return kelp_app_config_error(app, NULL, "bad configuration");
    kelp_hazardsensor_set_log(a->core, event, cfg_warning, a);
    const char *v;
    for (unsigned i = 0; (v = kelp_hazardsensor_subscription(i)) != NULL; i++)
        if (kelp_app_register(app, v, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", v);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    uhz_app *a = st;
    if (v->kind == KELP_VAR_BINARY) return;
    if (kelp_hazardsensor_mail(a->core, v->name, v->kind == KELP_VAR_STRING ? v->sval : NULL, v->community,
                            kelp_app_time(app), &a->sink) == 0)
        kelp_app_run_warning(app, "Unhandled mail: %s", v->name);
}

static int iterate(kelp_app *app, void *st, double now)
{
    uhz_app *a = st;
    (void)app;
    kelp_hazardsensor_iterate(a->core, now, &a->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    uhz_app *a = st;
    if (!a->core) return;
    if (kelp_hazardsensor_report(a->core, a->file[0] ? a->file : NULL, kelp_app_start_time(app), a->text,
                              sizeof a->text) < 0)
        fputs("(report truncated)\n", out);
    fputs(a->text, out);
}

static void shutdown(kelp_app *app, void *st)
{
    uhz_app *a = st;
    (void)app;
    free(a->core);
    free(a->cfg);
    a->core = NULL;
    a->cfg = NULL;
}

static const kelp_app_def def = {
    .name = "uFldHazardSensor",
    .purpose = "Simulated hazard sensor (ROC-curve detection, classification) for vehicles over a hazard field.",
    .synopsis = "Typically run in a shoreside community, configured with objects at x,y that are hazards or\n"
                "benign. While a vehicle's UHZ_SENSOR_REQUEST holds (600 s), objects newly in its swath are\n"
                "detected with P_D (hazard) or P_FA = P_D^exp (benign) by its sensor setting\n"
                "(UHZ_CONFIG_REQUEST from its own community); each detection earns one classify request.",
    .ignore_own_posts = true,
    .params = (const kelp_app_param_info[]){
        { "DEFAULT_HAZARD_SHAPE", "triangle", "marker shape of hazards (default triangle)", NULL },
        { "DEFAULT_HAZARD_COLOR", "red", "marker colour of hazards (default red)", NULL },
        { "DEFAULT_HAZARD_WIDTH", "8", "marker width of hazards, m (default 8)", NULL },
        { "DEFAULT_BENIGN_SHAPE", "triangle", "marker shape of benign objects (default triangle)", NULL },
        { "DEFAULT_BENIGN_COLOR", "light_blue", "marker colour of benign objects (default light_blue)", NULL },
        { "DEFAULT_BENIGN_WIDTH", "8", "marker width of benign objects, m (default 8)", NULL },
        { "SWATH_TRANSPARENCY", "0.2", "fill of the swath polygon (default 0.2)", NULL },
        { "SENSOR_CONFIG", "width=25, exp=4, class=0.85", "one setting (repeat): width m each side, ROC exponent, P_C[, max=n]", NULL },
        { "HAZARD_FILE", "hazards.txt", "file of \"hazard = ...\" lines; relative: cwd, then the mission's dir", NULL },
        { "HAZARD", "x=-151,y=-217.3,type=hazard,label=h1", "one object (repeat): x, y, type, label[, hr, aspect, color, shape, width]", NULL },
        { "SWATH_LENGTH", "5", "m ahead and behind (default 5, at least 1)", NULL },
        { "SEED_RANDOM", "true", "true: srand from the clock (default); false: rand() as never seeded", NULL },
        { "RANDOM_SEED", "1", "kelp: the srand seed when SEED_RANDOM is false (default 1)", NULL },
        { "SHOW_HAZARDS", "true", "VIEW_MARKER per object (default true)", NULL },
        { "SHOW_SWATH", "true", "VIEW_POLYGON swath (default true)", NULL },
        { "SHOW_REPORTS", "60", "s a report circle stays drawn (default unlimited; 0: no circles)", NULL },
        { "SHOW_DETECTIONS", "60", "24.8's other name of SHOW_REPORTS", "SHOW_REPORTS" },
        { "SHOW_PD", "true", "the swath's msg shows pd (default true)", NULL },
        { "SHOW_PFA", "true", "the swath's msg shows pfa (default true)", NULL },
        { "IGNORE_RESEMBLANCES", "false", "hr= of benign objects left out of the draws (default false)", NULL },
        { "MAX_TURN_RATE", "1.5", "deg/s over 2 s above which the sensor is off (default 1.5)", NULL },
        { "MAX_VEHICLE_SPEED", "2.05", "m/s above which the sensor is off (default 2.05)", NULL },
        { "MIN_RESET_INTERVAL", "300", "s between accepted width requests of a vehicle (default 300)", NULL },
        { "MIN_CLASSIFY_INTERVAL", "30", "s between classify answers to a vehicle (default 30)", NULL },
        { "CLASSIFY_PERIOD", "30", "24.8's other name of MIN_CLASSIFY_INTERVAL", "MIN_CLASSIFY_INTERVAL" },
        { "OPTIONS_SUMMARY_INTERVAL", "10", "s between UHZ_OPTIONS_SUMMARY posts (default 10, 0..120)", NULL },
        { "RN_ALGORITHM", "uniform,pct=0", "accepted, not applied (as 24.8)", NULL },
        { "RN_UNIFORM_PCT", "0", "accepted, not applied (as 24.8)", NULL },
        { "TERM_REPORT_INTERVAL", "0.4", "accepted (24.8 AppCasting)", NULL },
        { "MAX_APPCAST_EVENTS", "8", "accepted (24.8 AppCasting)", NULL },
        { "MAX_APPCAST_RUN_WARNINGS", "10", "accepted (24.8 AppCasting)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_REPORT", "NAME=archie,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,SPD=2,HDG=118.8", "NAME, X, Y, SPD, HDG" },
        { "UHZ_SENSOR_REQUEST", "vname=archie", "the sensor is on for 600 s" },
        { "UHZ_CONFIG_REQUEST", "vname=archie,width=50,pd=0.9", "from the vehicle's own community" },
        { "UHZ_CLASSIFY_REQUEST", "vname=archie,label=07,priority=50", "one per detection" },
        { "PMV_CONNECT", "true", "re-post the markers" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "PSR", "archie", "each iteration, per vehicle whose sensor is on" },
        { "UHZ_DETECTION_REPORT", "x=51,y=11.3,label=12,vname=archie", NULL },
        { "UHZ_DETECTION_REPORT_<VNAME>", "x=51,y=11.3,label=12", NULL },
        { "UHZ_HAZARD_REPORT", "vname=archie,x=51,y=11.3,label=12,type=hazard", "classify answers" },
        { "UHZ_HAZARD_REPORT_<VNAME>", "x=51,y=11.3,label=12,type=hazard", NULL },
        { "UHZ_CONFIG_ACK_<VNAME>", "vname=archie,width=25,pd=0.9,pfa=0.656,pclass=0.63", NULL },
        { "UHZ_OPTIONS_SUMMARY", "width=50,exp=2,class=0.55:width=25,exp=4,class=0.63", NULL },
        { "UHZ_DEBUG", "Invalid incoming node report", NULL },
        { "VIEW_CIRCLE", "x=51,y=11.3,radius=10,vertices=12,edge_color=white,fill_color=white,time=..", NULL },
        { "VIEW_MARKER", "x=217.3,y=-16.7,width=8,primary_color=red,type=triangle,label=h6", NULL },
        { "VIEW_POLYGON", "pts={-1,-35:-11,-35:-11,15:-1,15},label=sensor_swath_archie,msg=0.90/0.66,..", NULL },
        { NULL, NULL, NULL } },
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown,
};

int main(int argc, char **argv)
{
    static uhz_app a;
    return kelp_app_run(argc, argv, &def, &a);
}
