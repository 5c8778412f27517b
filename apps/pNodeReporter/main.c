/* pNodeReporter: publish NODE_REPORT_LOCAL, the vehicle's position and status in the format
 * of the uField seed, from the navigation solution and the helm's state. The logic is the core
 * state machine kelp_field_nrep (include/kelp/field.h); this file reads the ProcessConfig
 * block into its configuration and wires it to the bus. */
#include <math.h>
#include <stddef.h>
#include <unistd.h>
#include <stdio.h>
#include <string.h>
#include <kelp/edge/app.h>
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

static int num_param(kelp_app *app, const char *key, double *out, double lo)
{
    const kelp_mission_node *n = kelp_app_param(app, key);
    if (!n) return 0;
    if (kelp_mission_double(n, out) < 0 || !isfinite(*out) || *out < lo)
        return kelp_app_config_error(app, n, "%s must be a number >= %g", key, lo);
    return 1;
}

static int bool_param(kelp_app *app, const char *key, bool *out)
{
    const kelp_mission_node *n = kelp_app_param(app, key);
    if (n && kelp_mission_bool(n, out) < 0) return kelp_app_config_error(app, n, "%s must be true or false", key);
    return n ? 1 : 0;
}

/* the text parameters; of two names for one field the one written later in the block wins */
static int text_params(kelp_app *app, kelp_field_nrep_cfg *c)
{
    static const struct { const char *key; size_t off, cap; } t[] = {
        { "VESSEL_NAME", offsetof(kelp_field_nrep_cfg, name), KELP_NODEREPORT_MAX_FIELD },
        { "VESSEL_TYPE", offsetof(kelp_field_nrep_cfg, type), KELP_NODEREPORT_MAX_FIELD },
        { "PLATFORM_TYPE", offsetof(kelp_field_nrep_cfg, type), KELP_NODEREPORT_MAX_FIELD },
        { "GROUP", offsetof(kelp_field_nrep_cfg, group), KELP_NODEREPORT_MAX_FIELD },
        { "PLATFORM_GROUP", offsetof(kelp_field_nrep_cfg, group), KELP_NODEREPORT_MAX_FIELD },
        { "PLATFORM_COLOR", offsetof(kelp_field_nrep_cfg, color), KELP_NODEREPORT_MAX_FIELD },
        { "NODE_REPORT_VAR", offsetof(kelp_field_nrep_cfg, out_var), KELP_MAX_NAME },
        { "NODE_REPORT_SUMMARY", offsetof(kelp_field_nrep_cfg, out_var), KELP_MAX_NAME },
        { "NODE_REPORT_OUTPUT", offsetof(kelp_field_nrep_cfg, out_var), KELP_MAX_NAME },
        { "PLAT_REPORT_OUTPUT", offsetof(kelp_field_nrep_cfg, plat_var), KELP_MAX_NAME },
        { "MODE_VAR", offsetof(kelp_field_nrep_cfg, mode_var), KELP_MAX_NAME },
        { "ALT_NAV_PREFIX", offsetof(kelp_field_nrep_cfg, alt_prefix), 24 },
        { "ALT_NAV_NAME", offsetof(kelp_field_nrep_cfg, alt_name), KELP_NODEREPORT_MAX_FIELD },
        { "ALT_NAV_GROUP", offsetof(kelp_field_nrep_cfg, alt_group), KELP_NODEREPORT_MAX_FIELD },
    };
    int line[sizeof t / sizeof t[0]] = { 0 };
    for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
        const kelp_mission_node *n = kelp_app_param(app, t[i].key);
        line[i] = n ? n->line : 0;
        bool later = true;
        for (size_t k = 0; k < i; k++)
            if (t[k].off == t[i].off && line[k] > line[i]) later = false;
        int rc = later ? text_param(app, t[i].key, (char *)c + t[i].off, t[i].cap) : 0;
        if (rc < 0) return rc;
    }
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    nrep *r = st;
    r->app = app;
    r->sink = (kelp_field_sink){ r, publish, warn };
    kelp_field_nrep_cfg c;
    kelp_field_nrep_cfg_default(&c, kelp_app_community(app));
    int rc = text_params(app, &c);
    if (rc < 0) return rc;
    const char *lk[] = { "PLATFORM_LENGTH", "VESSEL_LENGTH" };
    for (int i = 0; i < 2 && !c.have_length; i++)
        if ((rc = num_param(app, lk[i], &c.length, 0)) < 0) return rc;
        else c.have_length = rc > 0;
    const struct { const char *key; double *v; double lo; } nums[] = {
        { "PLATFORM_BEAM", &c.beam, 0 },           { "NOHELM_THRESHOLD", &c.nohelm_threshold, 1e-3 },
        { "BLACKOUT_INTERVAL", &c.blackout_interval, 0 }, { "BLACKOUT_VARIANCE", &c.blackout_variance, 0 },
        { "NAV_GRACE_PERIOD", &c.nav_grace_period, -1 },  { "HDG_ERROR", &c.hdg_error, -360 },
        { "EXTRAP_POS_THRESH", &c.extrap_pos, 0 },  { "EXTRAP_HDG_THRESH", &c.extrap_hdg, 0 },
        { "EXTRAP_MAX_GAP", &c.extrap_gap, 0 },
    };
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++)
        if ((rc = num_param(app, nums[i].key, nums[i].v, nums[i].lo)) < 0) return rc;
    const struct { const char *key; bool *v; } bools[] = {
        { "ALLOW_COLOR_CHANGE", &c.allow_color_change }, { "PAUSED", &c.paused },
        { "COORD_POLICY_GLOBAL", &c.coord_global },      { "EXTRAP_ENABLED", &c.extrap },
        { "REPORT_COG", &c.report_cog },
        { "APP_LOGGING", &(bool){ false } }, /* logging is the logger's job on an LCM bus */
    };
    for (size_t i = 0; i < sizeof bools / sizeof bools[0]; i++)
        if ((rc = bool_param(app, bools[i].key, bools[i].v)) < 0) return rc;
    const kelp_mission_node *n;
    char buf[256];
    kelp_diag dg = { 0 };
    if ((n = kelp_app_param(app, "JSON_REPORT")) && kelp_mission_bool(n, &c.json_only) < 0) {
        /* not true/false: the name of a variable to post the JSON form to as well */
        if (kelp_mission_copy(n, c.json_var, sizeof c.json_var) < 0 || strpbrk(c.json_var, " ,="))
            return kelp_app_config_error(app, n, "JSON_REPORT must be true, false or a variable name");
    }
    if ((n = kelp_app_param(app, "DEPTH_KEY"))) {
        if (kelp_mission_copy(n, buf, sizeof buf) < 0 || (strcmp(buf, "DEP") != 0 && strcmp(buf, "DEPTH") != 0))
            return kelp_app_config_error(app, n, "DEPTH_KEY must be DEP (MOOS-IvP 24.8's report) or DEPTH (the seed's)");
        c.dep_key = strcmp(buf, "DEP") == 0;
        c.seed_format = !c.dep_key; /* DEPTH= comes with the seed's whole layout */
    }
    const char *fk[] = { "CROSS_FILL_POLICY", "CROSSFILL_POLICY" };
    for (int i = 0; i < 2; i++)
        if ((n = kelp_app_param(app, fk[i])) &&
            (kelp_mission_copy(n, buf, sizeof buf) < 0 || kelp_field_nrep_parse_fill(buf, &c.fill) < 0))
            return kelp_app_config_error(app, n, "%s must be literal, fill-empty, use-latest, global or local", fk[i]);
    for (n = kelp_app_param_next(app, "PLATFORM_ASPECT", NULL); n; n = kelp_app_param_next(app, "PLATFORM_ASPECT", n)) {
        size_t used = strlen(c.aspect);
        if (kelp_mission_copy(n, buf, sizeof buf) < 0 || !strchr(buf, '=') || strchr(buf, ',') ||
            used + strlen(buf) + 2 > sizeof c.aspect)
            return kelp_app_config_error(app, n, "PLATFORM_ASPECT must be one KEY=VALUE (all of them within %zu characters)",
                                         sizeof c.aspect - 1);
        if (used) c.aspect[used++] = ',';
        memcpy(c.aspect + used, buf, strlen(buf) + 1); /* fits: checked above */
    }
    const char *pk[] = { "PLAT_REPORT_INPUT", "PLAT_REPORT_VAR", "PLATFORM_VARIABLE", "RIDER" };
    for (int k = 0; k < 4; k++)
        for (n = kelp_app_param_next(app, pk[k], NULL); n; n = kelp_app_param_next(app, pk[k], n))
            if (kelp_mission_copy(n, buf, sizeof buf) < 0 ||
                (k < 3 ? kelp_field_nrep_add_plat(&c, buf, &dg) : kelp_field_nrep_add_rider(&c, buf, &dg)) < 0)
                return kelp_app_config_error(app, n, "bad %s: %s", pk[k], dg.code ? kelp_diag_text(&dg) : "too long");
    if ((n = kelp_app_param(app, "PREFIX")) && (n->vlen == 0 || kelp_mission_copy(n, c.prefix, sizeof c.prefix) < 0))
        return kelp_app_config_error(app, n, "PREFIX must be 1..%zu characters", sizeof c.prefix - 1);
    double lat0, lon0;
    if (kelp_app_global_double(app, "LatOrigin", &lat0) == 1 && kelp_app_global_double(app, "LongOrigin", &lon0) == 1 &&
        kelp_geo_init(&c.geo, lat0, lon0) == 0)
        c.have_geo = true;
    c.seed = (uint64_t)getpid() ^ (uint64_t)(kelp_app_time(app) * 1e6);
    if (kelp_field_nrep_init(&r->core, &c, kelp_app_time(app)) < 0)
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
    /* refused mail is warned through the sink and counted by the core */
    KELP_IGNORE(kelp_field_nrep_mail(&r->core, v->name, v->kind == KELP_VAR_STRING, v->sval, v->dval, &r->sink));
}

static int iterate(kelp_app *app, void *st, double now)
{
    nrep *r = st;
    if (kelp_field_nrep_iterate(&r->core, now, &r->sink) < 0)
        kelp_app_run_warning(app, "NODE_REPORT not posted: it does not fit a report");
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
    .pid_var = "PNODEREPORTER_PID",
    .purpose = "Publish NODE_REPORT_LOCAL (NAME,X,Y,SPD,HDG,DEP,LAT,LON,TYPE,...,TIME) from NAV_* and the helm.",
    .params = (const kelp_app_param_info[]){
        { "PLATFORM_TYPE", "UUV", "TYPE= in the report", NULL },
        { "VESSEL_TYPE", "UUV", "older name of PLATFORM_TYPE", "PLATFORM_TYPE" },
        { "PLATFORM_LENGTH", "3.8", "meters, LENGTH= (optional; no default)", NULL },
        { "VESSEL_LENGTH", "3.8", "older name of PLATFORM_LENGTH", "PLATFORM_LENGTH" },
        { "PLATFORM_BEAM", "1.2", "meters (kept for viewers; not in the report)", NULL },
        { "VESSEL_NAME", "alpha", "NAME= (default: the Community)", NULL },
        { "PLATFORM_GROUP", "red_team", "GROUP= (optional; no default)", NULL },
        { "GROUP", "red_team", "same as PLATFORM_GROUP", "PLATFORM_GROUP" },
        { "PLATFORM_COLOR", "yellow", "COLOR= (optional)", NULL },
        { "ALLOW_COLOR_CHANGE", "false", "NODE_COLOR_CHANGE may change COLOR", NULL },
        { "PLATFORM_ASPECT", "ID=439", "repeatable: a KEY=VALUE added to every report", NULL },
        { "PREFIX", "NAV", "navigation variables read: <PREFIX>_X, _Y, ...", NULL },
        { "MODE_VAR", "MY_MODE", "MODE= from this variable instead of the helm (optional)", NULL },
        { "NODE_REPORT_OUTPUT", "NODE_REPORT_LOCAL", "the variable the report is posted to", NULL },
        { "NODE_REPORT_SUMMARY", "NODE_REPORT_LOCAL", "older name of NODE_REPORT_OUTPUT", "NODE_REPORT_OUTPUT" },
        { "NODE_REPORT_VAR", "NODE_REPORT_LOCAL", "older name of NODE_REPORT_OUTPUT", "NODE_REPORT_OUTPUT" },
        { "DEPTH_KEY", "DEP", "DEP: MOOS-IvP 24.8's report; DEPTH: the seed's (DEPTH=, fixed decimals, its order)", NULL },
        { "NOHELM_THRESHOLD", "5", "seconds without helm mail before MODE=NOHELM-<s>", NULL },
        { "BLACKOUT_INTERVAL", "0", "seconds between reports (0: every iteration)", NULL },
        { "BLACKOUT_VARIANCE", "0", "seconds, the interval varies by +- this", NULL },
        { "NAV_GRACE_PERIOD", "-1", "seconds after start to report without navigation (-1: never)", NULL },
        { "CROSS_FILL_POLICY", "literal", "literal, fill-empty, use-latest, global or local (needs the datum)", NULL },
        { "CROSSFILL_POLICY", "literal", "same as CROSS_FILL_POLICY", "CROSS_FILL_POLICY" },
        { "COORD_POLICY_GLOBAL", "false", "true: no X/Y in reports (LAT/LON only)", NULL },
        { "HDG_ERROR", "0", "degrees added to the reported heading (testing)", NULL },
        { "EXTRAP_ENABLED", "false", "skip reports a receiver can extrapolate from the last one", NULL },
        { "EXTRAP_POS_THRESH", "0.25", "meters", NULL },
        { "EXTRAP_HDG_THRESH", "1", "degrees", NULL },
        { "EXTRAP_MAX_GAP", "5", "seconds: report at least this often", NULL },
        { "PLAT_REPORT_INPUT", "COMPASS_HEADING, gap=1", "repeatable: VAR, gap=S, alias=A into the platform report", NULL },
        { "PLAT_REPORT_VAR", "GPS_SAT, gap=5", "older name of PLAT_REPORT_INPUT", "PLAT_REPORT_INPUT" },
        { "PLATFORM_VARIABLE", "WIFI_QUALITY", "older name of PLAT_REPORT_INPUT", "PLAT_REPORT_INPUT" },
        { "PLAT_REPORT_OUTPUT", "PLATFORM_REPORT_LOCAL", "the variable the platform report is posted to", NULL },
        { "RIDER", "var=DB_UPTIME, policy=always, rfld=upt, prec=3", "repeatable: a variable carried in the report", NULL },
        { "JSON_REPORT", "false", "true: the report as JSON; a NAME: JSON in NAME as well", NULL },
        { "PAUSED", "false", "true: no reports", NULL },
        { "ALT_NAV_PREFIX", "NAV_GT", "a second navigation solution, reported too (e.g. ground truth)", NULL },
        { "ALT_NAV_NAME", "_GT", "its NAME= (\"_GT\": appended to the vehicle's name)", NULL },
        { "ALT_NAV_GROUP", "blue", "its GROUP= (default: the vehicle's)", NULL },
        { "REPORT_COG", "false", "true: COG= from <PREFIX>_HEADING_OVER_GROUND", NULL },
        { "APP_LOGGING", "false", "accepted (record the bus with lcm-logger instead)", NULL },
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
        { "IVPHELM_SUMMARY", "iter=12,utc_time=17514261063.25,modes=MODE@ACTIVE:LOITERING", "MODE= from modes= (kept until the next modes=)" },
        { "IVPHELM_ALLSTOP", "clear", NULL },
        { "NAV_YAW", "118.8", "when it arrives, YAW= (the heading in radians, as MOOS-IvP writes it)" },
        { "NODE_COLOR_CHANGE", "yellow", "COLOR= when ALLOW_COLOR_CHANGE" },
        { "NAV_HEADING_OVER_GROUND", "120.1", "COG= when REPORT_COG" },
        { "<ALT_NAV_PREFIX>_X, ...", "112.3", "the alternate solution's NAV_* when ALT_NAV_PREFIX is set" },
        { "<PLAT_REPORT_INPUT / RIDER vars>", "any", NULL },
        { "<MODE_VAR>", "SURVEYING", "when MODE_VAR is set" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "NODE_REPORT_LOCAL", "NAME=alpha,X=51.71,Y=-35.5,SPD=2,HDG=118.85,DEP=4.63,LAT=43.82498058,"
          "LON=-70.3297551,TYPE=UUV,MODE=LOITERING,ALLSTOP=clear,TIME=1252348077.59,LENGTH=3.8",
          "every iteration once the navigation is valid (NODE_REPORT_OUTPUT; BLACKOUT_INTERVAL apart)" },
        { "NODE_REPORT_LOCAL_FIRST", "(the first report)", "once, a copy of the first report" },
        { "PNR_POST_GAP", "0.25", "seconds since the previous report" },
        { "PLATFORM_REPORT_LOCAL", "platform=alpha,utc_time=1252348077.59,COMPASS_HEADING=118", "PLAT_REPORT_OUTPUT" },
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
