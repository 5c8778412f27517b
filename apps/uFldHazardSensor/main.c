/* uFldHazardSensor: a simulated hazard sensor (detection on a ROC curve, classification) for
 * every vehicle over a field of hazard and benign objects (uField seed chapter 9, with
 * MOOS-IvP 24.8's names). The logic is kelp_field_uhz in the core
 * (include/kelp/hazardsensor.h); this file reads the block and the hazard file and wires the
 * core to the bus. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/hazardsensor.h>
#include <kelp/util.h>

typedef struct uhz_app {
    kelp_app *app;
    kelp_field_uhz *core;      /* about 200 KB: on the heap (freed at exit) */
    kelp_field_uhz_cfg *cfg;
    kelp_field_sink sink;
    char file[512];
    char text[65536];
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

/* A relative hazard file is looked for in the working directory, then beside the mission. */
static FILE *open_hazards(uhz_app *a, const char *name)
{
    FILE *f = fopen(name, "r");
    const char *m = kelp_app_mission_path(a->app);
    const char *slash = m ? strrchr(m, '/') : NULL;
    if (!f && name[0] != '/' && slash) {
        char path[1024];
        kelp_snprintf(path, sizeof path, "%.*s/%s", (int)(slash - m), m, name);
        f = fopen(path, "r");
    }
    return f;
}

/* A file that cannot be read is a configuration warning (as in MOOS-IvP), not fatal. */
static int read_hazard_file(uhz_app *a, const char *name)
{
    FILE *f = open_hazards(a, name);
    if (!f) {
        kelp_app_config_warning(a->app, "HAZARD_FILE %s: cannot open it", name);
        kelp_snprintf(a->file, sizeof a->file, "error reading %s", name);
        return 1;
    }
    char line[1024];
    unsigned lineno = 0, added = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        kelp_diag dg = { 0 };
        int rc = kelp_field_uhz_hazard_line(a->cfg, line, &dg);
        if (rc < 0) kelp_app_config_warning(a->app, "%s:%u: %s", name, lineno, dg.code ? kelp_diag_text(&dg) : "bad line");
        else added += (unsigned)rc;
    }
    fclose(f);
    kelp_snprintf(a->file, sizeof a->file, "%s", name);
    kelp_app_event(a->app, "hazard file %s: %u objects", name, added);
    return 1;
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    uhz_app *a = ctx;
    if (kelp_strieq(key, "HAZARD_FILE")) return read_hazard_file(a, val);
    /* 24.8's AppCasting settings: kelp's status report has its own */
    if (kelp_strieq(key, "TERM_REPORT_INTERVAL") || kelp_strieq(key, "MAX_APPCAST_EVENTS") ||
        kelp_strieq(key, "MAX_APPCAST_RUN_WARNINGS"))
        return 1;
    return kelp_field_uhz_config(a->cfg, key, val, d);
}

static int startup(kelp_app *app, void *st)
{
    uhz_app *a = st;
    a->app = app;
    a->sink = (kelp_field_sink){ a, publish, warn };
    a->cfg = malloc(sizeof *a->cfg);
    a->core = malloc(sizeof *a->core);
    if (!a->cfg || !a->core) return kelp_app_config_error(app, NULL, "out of memory");
    kelp_field_uhz_cfg_default(a->cfg);
    int rc = kelp_app_param_foreach(app, param, a);
    if (rc < 0) return rc;
    /* SEED_RANDOM = true: a different run each time (as MOOS-IvP's srand(time)) */
    if (a->cfg->seed_random) a->cfg->seed ^= (uint64_t)(kelp_app_time(app) * 1e6);
    if (a->cfg->nobjects == 0) kelp_app_config_warning(app, "no hazard field (HAZARD_FILE or HAZARD lines)");
    if (a->cfg->nsettings == 0) kelp_app_config_warning(app, "no SENSOR_CONFIG settings");
    if (kelp_field_uhz_init(a->core, a->cfg) < 0) return kelp_app_config_error(app, NULL, "bad configuration");
    const char *v;
    for (unsigned i = 0; (v = kelp_field_uhz_subscription(i)) != NULL; i++)
        if (kelp_app_register(app, v, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", v);
    kelp_app_event(app, "%u objects (%u hazard, %u benign), %u sensor settings, seed %llu", a->cfg->nobjects,
                   a->cfg->nhazard, a->cfg->nbenign, a->cfg->nsettings, (unsigned long long)a->cfg->seed);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    uhz_app *a = st;
    if (v->kind == KELP_VAR_BINARY) return;
    (void)kelp_field_uhz_mail(a->core, v->name, v->kind == KELP_VAR_STRING ? v->sval : NULL, kelp_app_time(app),
                              &a->sink);
}

static int iterate(kelp_app *app, void *st, double now)
{
    uhz_app *a = st;
    (void)app;
    kelp_field_uhz_iterate(a->core, now, &a->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    uhz_app *a = st;
    if (!a->core) return;
    fprintf(out, "Hazard file: (%s) hazard %u, benign %u\n", a->file[0] ? a->file : "none", a->cfg->nhazard,
            a->cfg->nbenign);
    if (kelp_field_uhz_report(a->core, kelp_app_time(app), a->text, sizeof a->text) < 0)
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
                "benign. Each UHZ_SENSOR_REQUEST from a vehicle checks which objects newly entered its swath;\n"
                "each is detected with P_D (hazard) or P_FA = P_D^exp (benign) and classified correctly with\n"
                "P_C, by the vehicle's sensor setting (UHZ_CONFIG_REQUEST).",
    .ignore_own_posts = true,
    .params = (const kelp_app_param_info[]){
        { "DEFAULT_HAZARD_SHAPE", "triangle", "marker shape of hazards (default triangle)", NULL },
        { "DEFAULT_HAZARD_COLOR", "green", "marker colour of hazards (default green)", NULL },
        { "DEFAULT_HAZARD_WIDTH", "8", "marker width of hazards, m (default 8)", NULL },
        { "DEFAULT_BENIGN_SHAPE", "triangle", "marker shape of benign objects (default triangle)", NULL },
        { "DEFAULT_BENIGN_COLOR", "light_blue", "marker colour of benign objects (default light_blue)", NULL },
        { "DEFAULT_BENIGN_WIDTH", "8", "marker width of benign objects, m (default 8)", NULL },
        { "SWATH_TRANSPARENCY", "0.25", "fill of the swath polygon (default 0.25)", NULL },
        { "SENSOR_CONFIG", "width=25, exp=4, pclass=0.85", "one setting (repeat): width m, ROC exponent, P_C[, max=n]", NULL },
        { "HAZARD_FILE", "hazards.txt", "file of hazard lines (gen_hazards' output); relative: cwd, then the mission's dir", NULL },
        { "HAZARD", "x=-151,y=-217.3,type=hazard", "one object (repeat): x, y, type[, label, color, shape, width]", NULL },
        { "SWATH_LENGTH", "5", "m along the heading (default 5)", NULL },
        { "SEED_RANDOM", "false", "true: seed from the clock (default false: repeatable runs)", NULL },
        { "RANDOM_SEED", "1", "the generator's seed (default 1)", NULL },
        { "VERBOSE", "false", "the summary report (default false: a one-character trace)", NULL },
        { "SHOW_HAZARDS", "true", "VIEW_MARKER per object (default true)", NULL },
        { "SHOW_SWATH", "true", "VIEW_POLYGON swath (default true)", NULL },
        { "SHOW_REPORTS", "60", "s a report circle stays drawn (default unlimited; 0: no circles)", NULL },
        { "SHOW_DETECTIONS", "60", "24.8's name of SHOW_REPORTS", "SHOW_REPORTS" },
        { "SHOW_PD", "true", "the swath's msg shows pd (default true)", NULL },
        { "SHOW_PFA", "true", "the swath's msg shows pfa (default true)", NULL },
        { "MIN_RESET_INTERVAL", "300", "s between accepted config requests of a vehicle (default 300, as MOOS-IvP)", NULL },
        { "MIN_CLASSIFY_INTERVAL", "30", "s between classify answers to a vehicle (default 30)", NULL },
        { "OPTIONS_SUMMARY_INTERVAL", "10", "s between UHZ_OPTIONS_SUMMARY posts (default 10)", NULL },
        { "TERM_REPORT_INTERVAL", "0.4", "accepted (24.8 AppCasting)", NULL },
        { "MAX_APPCAST_EVENTS", "8", "accepted (24.8 AppCasting)", NULL },
        { "MAX_APPCAST_RUN_WARNINGS", "10", "accepted (24.8 AppCasting)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_REPORT", "NAME=archie,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,HDG=118.8", "NAME, X, Y, HDG" },
        { "NODE_REPORT_LOCAL", "NAME=archie,X=51.71,Y=-35.50,HDG=118.8", NULL },
        { "UHZ_SENSOR_REQUEST", "vname=archie", "the sensor is on" },
        { "UHZ_CONFIG_REQUEST", "vname=archie,width=50,pd=0.9", NULL },
        { "UHZ_SENSOR_CONFIG", "vname=archie,width=50,pd=0.9", "the same" },
        { "UHZ_CLASSIFY_REQUEST", "vname=archie,label=07,priority=50", "24.8: one per detection" },
        { "PMV_CONNECT", "true", "re-post the markers" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "UHZ_DETECTION_REPORT", "vname=archie,x=51,y=11.3,label=12", NULL },
        { "UHZ_DETECTION_REPORT_<VNAME>", "x=51,y=11.3,label=12", NULL },
        { "UHZ_HAZARD_REPORT", "vname=archie,x=51,y=11.3,hazard=true,label=12", "classify answers: type=hazard" },
        { "UHZ_HAZARD_REPORT_<VNAME>", "x=51,y=11.3,hazard=true,label=12", NULL },
        { "UHZ_CONFIG_ACK", "vname=archie,width=20,pd=0.9,pfa=0.53,pclass=0.91", NULL },
        { "UHZ_CONFIG_ACK_<VNAME>", "width=30,pd=0.9,pfa=0.28,pclass=0.93", NULL },
        { "UHZ_OPTIONS_SUMMARY", "width=10,exp=6,pclass=0.9:width=25,exp=4,pclass=0.85", NULL },
        { "VIEW_CIRCLE", "x=51,y=11.3,radius=10,label=archie_12,edge_color=yellow,fill_color=yellow,fill=0.3", NULL },
        { "VIEW_MARKER", "x=217.3,y=-16.7,label=6,color=green,type=triangle,width=8", NULL },
        { "VIEW_POLYGON", "pts={-156.7,-314.6:-160.2,-305.2:-113.3,-287.7:-109.8,-297.1},label=sensor_swath_archie", NULL },
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
