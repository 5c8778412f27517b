/* pNodeReporter: publish NODE_REPORT_LOCAL, the vehicle's position and status in the format
 * of the uField seed, from the navigation solution and the helm's state. The logic is the core
 * state machine kelp_field_nrep (include/kelp/field.h); this file reads the ProcessConfig
 * block into its configuration and wires it to the bus. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/field.h>

typedef struct nrep {
    kelp_field_nrep core;
    kelp_app *app;
    kelp_field_sink sink;
} nrep;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    nrep *r = ctx;
    int rc = is_string ? kelp_app_notify_string(r->app, var, sval) : kelp_app_notify_double(r->app, var, dval);
    if (rc < 0) kelp_app_run_warning(r->app, "cannot publish %s", var);
}

static void warn(void *ctx, const char *msg)
{
    kelp_app_run_warning(((nrep *)ctx)->app, "%s", msg);
}

/* a text parameter copied into a report field: no ',' or '=' allowed */
static int text_param(kelp_app *app, const char *key, char *dst, size_t cap)
{
    const kelp_mission_node *n = kelp_app_param(app, key);
    if (!n) return 0;
    if (n->vlen == 0 || kelp_mission_copy(n, dst, cap) < 0 || strpbrk(dst, ",="))
        return kelp_app_config_error(app, n, "%s must be 1..%zu characters without ',' or '='", key, cap - 1);
    return 1;
}

static int startup(kelp_app *app, void *st)
{
    nrep *r = st;
    r->app = app;
    r->sink = (kelp_field_sink){ r, publish, warn };
    kelp_field_nrep_cfg c;
    kelp_field_nrep_cfg_default(&c, kelp_app_community(app));
    int rc;
    if ((rc = text_param(app, "VESSEL_NAME", c.name, sizeof c.name)) < 0) return rc;
    if ((rc = text_param(app, "PLATFORM_TYPE", c.type, sizeof c.type)) < 0) return rc;
    if (rc == 0 && (rc = text_param(app, "VESSEL_TYPE", c.type, sizeof c.type)) < 0) return rc;
    if ((rc = text_param(app, "GROUP", c.group, sizeof c.group)) < 0) return rc;
    if ((rc = text_param(app, "NODE_REPORT_OUTPUT", c.out_var, sizeof c.out_var)) < 0) return rc;
    if ((rc = text_param(app, "MODE_VAR", c.mode_var, sizeof c.mode_var)) < 0) return rc;
    const char *lk[] = {"PLATFORM_LENGTH", "VESSEL_LENGTH"};
    for (int i = 0; i < 2 && !c.have_length; i++) {
        const kelp_mission_node *n = kelp_app_param(app, lk[i]);
        if (!n) continue;
        if (kelp_mission_double(n, &c.length) < 0 || !(c.length >= 0) || !isfinite(c.length))
            return kelp_app_config_error(app, n, "%s must be a number >= 0", lk[i]);
        c.have_length = true;
    }
    const kelp_mission_node *n = kelp_app_param(app, "PREFIX");
    if (n && (n->vlen == 0 || kelp_mission_copy(n, c.prefix, sizeof c.prefix) < 0))
        return kelp_app_config_error(app, n, "PREFIX must be 1..%zu characters", sizeof c.prefix - 1);
    double lat0, lon0;
    if (kelp_app_global_double(app, "LatOrigin", &lat0) == 1 && kelp_app_global_double(app, "LongOrigin", &lon0) == 1 &&
        kelp_geo_init(&c.geo, lat0, lon0) == 0)
        c.have_geo = true;
    if (kelp_field_nrep_init(&r->core, &c) < 0)
        return kelp_app_config_error(app, NULL, "vehicle name '%s' (the Community) is not usable in a report", c.name);
    const char *var;
    for (unsigned i = 0; (var = kelp_field_nrep_subscription(&r->core, i)) != NULL; i++)
        if (kelp_app_register(app, var, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", var);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    nrep *r = st;
    (void)app;
    if (v->kind == KELP_VAR_BINARY) return;
    (void)kelp_field_nrep_mail(&r->core, v->name, v->kind == KELP_VAR_STRING, v->sval, v->dval, &r->sink);
}

static int iterate(kelp_app *app, void *st, double now)
{
    nrep *r = st;
    (void)app;
    (void)kelp_field_nrep_iterate(&r->core, now, &r->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    const kelp_field_nrep *c = &((nrep *)st)->core;
    (void)app;
    fprintf(out, "Vehicle %s (%s)%s%s; nav mail %lu (bad %lu); %s posted %lu times\n", c->cfg.name, c->cfg.type,
            c->cfg.group[0] ? " group " : "", c->cfg.group, c->nav_mail, c->bad_mail, c->cfg.out_var, c->posted);
    fprintf(out, "Last: %s\n", c->last[0] ? c->last : "(none yet: waiting for NAV_X/NAV_Y or NAV_LAT/NAV_LONG)");
}

static const kelp_app_def def = {
    .name = "pNodeReporter",
    .purpose = "Publish NODE_REPORT_LOCAL (NAME,TYPE,TIME,X,Y,LAT,LON,SPD,HDG,DEPTH,...) from NAV_* and the helm.",
    .params = (const kelp_app_param_info[]){
        { "PLATFORM_TYPE", "UUV", "TYPE= in the report", NULL },
        { "VESSEL_TYPE", "UUV", "older name of PLATFORM_TYPE (used when that is absent)", "PLATFORM_TYPE" },
        { "PLATFORM_LENGTH", "3.8", "meters, LENGTH= (optional; no default)", NULL },
        { "VESSEL_LENGTH", "3.8", "older name of PLATFORM_LENGTH", "PLATFORM_LENGTH" },
        { "VESSEL_NAME", "alpha", "NAME= (default: the Community)", NULL },
        { "GROUP", "red_team", "GROUP= (optional; no default)", NULL },
        { "PREFIX", "NAV", "navigation variables read: <PREFIX>_X, _Y, ...", NULL },
        { "MODE_VAR", "MY_MODE", "MODE= from this variable instead of the helm (optional)", NULL },
        { "NODE_REPORT_OUTPUT", "NODE_REPORT_LOCAL", "the variable the report is posted to", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NAV_X", "112.3", "meters east of the datum (NAV = PREFIX)" },
        { "NAV_Y", "-99.1", "meters north of the datum" },
        { "NAV_LAT", "43.824981", NULL },
        { "NAV_LONG", "-70.329755", NULL },
        { "NAV_SPEED", "2.0", "m/s" },
        { "NAV_HEADING", "118.8", "degrees" },
        { "NAV_DEPTH", "4.6", "meters" },
        { "IVPHELM_STATE", "DRIVE", NULL },
        { "IVPHELM_SUMMARY", "iter=12,modes=MODE@ACTIVE:LOITERING,active_bhvs=loiter", "MODE= from modes=, else active_bhvs=" },
        { "IVPHELM_ALLSTOP", "clear", NULL },
        { "<MODE_VAR>", "SURVEYING", "when MODE_VAR is set" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "NODE_REPORT_LOCAL", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,LAT=43.824981,"
          "LON=-70.329755,SPD=2.00,HDG=118.85,DEPTH=4.63,LENGTH=3.8,MODE=LOITERING",
          "once per iteration with new navigation data (the variable is NODE_REPORT_OUTPUT)" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: LatOrigin, LongOrigin (LAT/LON from X/Y, or X/Y from LAT/LON).\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static nrep r;
    return kelp_app_run(argc, argv, &def, &r);
}
