/* pNodeReporter: publish NODE_REPORT_LOCAL, the vehicle's position and status in the format
 * of the uField seed (include/kelp/nodereport.h), from the navigation solution and the helm's
 * state. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/geo.h>
#include <kelp/kv.h>
#include <kelp/nodereport.h>

enum { N_X, N_Y, N_LAT, N_LON, N_SPD, N_HDG, N_DEP, N_NAV };
static const char *const nav_suffix[N_NAV] = {"_X", "_Y", "_LAT", "_LONG", "_SPEED", "_HEADING", "_DEPTH"};

typedef struct nrep {
    char name[KELP_NODEREPORT_MAX_FIELD], type[KELP_NODEREPORT_MAX_FIELD], group[KELP_NODEREPORT_MAX_FIELD];
    char out_var[KELP_MAX_NAME], mode_var[KELP_MAX_NAME];
    char nav_var[N_NAV][KELP_MAX_NAME];
    double nav[N_NAV];
    bool have[N_NAV];
    double length;
    bool have_length;
    kelp_geo geo;
    bool have_geo;
    char helm_state[KELP_NODEREPORT_MAX_FIELD], helm_modes[KELP_NODEREPORT_MAX_FIELD], mode[KELP_NODEREPORT_MAX_FIELD];
    char allstop[KELP_NODEREPORT_MAX_FIELD], helm_active[KELP_NODEREPORT_MAX_FIELD];
    bool fresh;
    unsigned long posted, nav_mail, bad_mail;
    char last[KELP_NODEREPORT_MAX_LEN];
} nrep;

/* a text parameter copied into a report field: no ',' or '=' allowed */
static int text_param(kelp_app *app, const char *key, char *dst, size_t cap)
{
    const kelp_mission_node *n = kelp_app_param(app, key);
    if (!n) return 0;
    if (n->vlen == 0 || kelp_mission_copy(n, dst, cap) < 0 || strpbrk(dst, ",="))
        return kelp_app_config_error(app, n, "%s must be 1..%zu characters without ',' or '='", key, cap - 1);
    return 1;
}

static void copy_field(char *dst, const char *src)
{
    /* helm strings go into a report field: drop separators, bound the length */
    size_t j = 0;
    for (size_t i = 0; src[i] && j + 1 < KELP_NODEREPORT_MAX_FIELD; i++)
        if (src[i] != ',' && src[i] != '=') dst[j++] = src[i];
    dst[j] = 0;
}

static int startup(kelp_app *app, void *st)
{
    nrep *r = st;
    int rc;
    snprintf(r->name, sizeof r->name, "%s", kelp_app_community(app));
    snprintf(r->type, sizeof r->type, "UUV");
    snprintf(r->out_var, sizeof r->out_var, "NODE_REPORT_LOCAL");
    if ((rc = text_param(app, "VESSEL_NAME", r->name, sizeof r->name)) < 0) return rc;
    if ((rc = text_param(app, "PLATFORM_TYPE", r->type, sizeof r->type)) < 0) return rc;
    if (rc == 0 && (rc = text_param(app, "VESSEL_TYPE", r->type, sizeof r->type)) < 0) return rc;
    if ((rc = text_param(app, "GROUP", r->group, sizeof r->group)) < 0) return rc;
    if ((rc = text_param(app, "NODE_REPORT_OUTPUT", r->out_var, sizeof r->out_var)) < 0) return rc;
    if ((rc = text_param(app, "MODE_VAR", r->mode_var, sizeof r->mode_var)) < 0) return rc;
    if (strpbrk(r->name, ",=") || !r->name[0])
        return kelp_app_config_error(app, NULL, "vehicle name '%s' (the Community) is not usable in a report", r->name);
    const char *lk[] = {"PLATFORM_LENGTH", "VESSEL_LENGTH"};
    for (int i = 0; i < 2 && !r->have_length; i++) {
        const kelp_mission_node *n = kelp_app_param(app, lk[i]);
        if (!n) continue;
        if (kelp_mission_double(n, &r->length) < 0 || !(r->length >= 0) || !isfinite(r->length))
            return kelp_app_config_error(app, n, "%s must be a number >= 0", lk[i]);
        r->have_length = true;
    }
    char prefix[24] = "NAV";
    const kelp_mission_node *n = kelp_app_param(app, "PREFIX");
    if (n && (n->vlen == 0 || kelp_mission_copy(n, prefix, sizeof prefix) < 0))
        return kelp_app_config_error(app, n, "PREFIX must be 1..23 characters");
    for (int i = 0; i < N_NAV; i++) {
        snprintf(r->nav_var[i], sizeof r->nav_var[i], "%s%s", prefix, nav_suffix[i]);
        if (kelp_app_register(app, r->nav_var[i], 0) < 0) return kelp_app_config_error(app, NULL, "cannot register");
    }
    double lat0, lon0;
    if (kelp_app_global_double(app, "LatOrigin", &lat0) == 1 && kelp_app_global_double(app, "LongOrigin", &lon0) == 1 &&
        kelp_geo_init(&r->geo, lat0, lon0) == 0)
        r->have_geo = true;
    const char *helm[] = {"IVPHELM_STATE", "IVPHELM_SUMMARY", "IVPHELM_ALLSTOP"};
    for (int i = 0; i < 3; i++)
        if (kelp_app_register(app, helm[i], 0) < 0) return kelp_app_config_error(app, NULL, "cannot register");
    if (r->mode_var[0] && kelp_app_register(app, r->mode_var, 0) < 0)
        return kelp_app_config_error(app, NULL, "cannot register");
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    nrep *r = st;
    for (int i = 0; i < N_NAV; i++)
        if (strcmp(v->name, r->nav_var[i]) == 0) {
            double d = v->dval;
            if (v->kind != KELP_VAR_DOUBLE && (v->kind != KELP_VAR_STRING || kelp_parse_double(v->sval, v->slen, &d) < 0))
                d = NAN;
            if (!isfinite(d)) {
                r->bad_mail++;
                kelp_app_run_warning(app, "%s is not a finite number; ignored", v->name);
                return;
            }
            r->nav[i] = d;
            r->have[i] = true;
            r->fresh = true;
            r->nav_mail++;
            return;
        }
    if (v->kind != KELP_VAR_STRING) return;
    if (strcmp(v->name, "IVPHELM_STATE") == 0) {
        copy_field(r->helm_state, v->sval);
    } else if (strcmp(v->name, "IVPHELM_ALLSTOP") == 0) {
        copy_field(r->allstop, v->sval);
    } else if (strcmp(v->name, "IVPHELM_SUMMARY") == 0) {
        /* MOOS-IvP helm modes ("modes=MODE@ACTIVE:LOITERING") when present, else the active
         * behaviours of kelp's helm ("active_bhvs=survey") */
        char modes[KELP_NODEREPORT_MAX_FIELD * 2];
        if (kelp_kv_get(v->sval, ',', "modes", modes, sizeof modes) == 1) {
            copy_field(r->helm_modes, modes);
        } else if (kelp_kv_get(v->sval, ',', "active_bhvs", modes, sizeof modes) == 1) {
            if (!strcmp(modes, "none")) r->helm_active[0] = 0;
            else copy_field(r->helm_active, modes);
        }
    } else if (r->mode_var[0] && strcmp(v->name, r->mode_var) == 0) {
        copy_field(r->mode, v->sval);
    }
}

static int iterate(kelp_app *app, void *st, double now)
{
    nrep *r = st;
    bool xy = r->have[N_X] && r->have[N_Y], ll = r->have[N_LAT] && r->have[N_LON];
    if (!r->fresh || (!xy && !ll)) return 0;
    kelp_nodereport n;
    kelp_nodereport_init(&n);
    memcpy(n.name, r->name, sizeof n.name);
    memcpy(n.type, r->type, sizeof n.type);
    n.fields = KELP_NR_NAME | KELP_NR_TYPE | KELP_NR_TIME;
    n.time = now;
    if (xy) n.x = r->nav[N_X], n.y = r->nav[N_Y], n.fields |= KELP_NR_X | KELP_NR_Y;
    if (ll) n.lat = r->nav[N_LAT], n.lon = r->nav[N_LON], n.fields |= KELP_NR_LAT | KELP_NR_LON;
    if (r->have_geo && kelp_nodereport_complete(&n, &r->geo) < 0) kelp_app_run_warning(app, "datum conversion failed");
    n.spd = r->nav[N_SPD];
    n.hdg = r->nav[N_HDG];
    n.depth = r->nav[N_DEP];
    n.fields |= KELP_NR_SPD | KELP_NR_HDG | KELP_NR_DEPTH;
    if (r->have_length) n.length = r->length, n.fields |= KELP_NR_LENGTH;
    /* MODE: MODE_VAR if configured, else the helm summary's modes, else the helm state with its
     * active behaviours ("DRIVE@survey") */
    char hm[KELP_NODEREPORT_MAX_FIELD * 2 + 2];
    snprintf(hm, sizeof hm, "%s%s%s", r->helm_state, r->helm_state[0] && r->helm_active[0] ? "@" : "", r->helm_active);
    const char *mode = r->mode[0] ? r->mode : r->helm_modes[0] ? r->helm_modes : hm;
    if (mode[0]) {
        size_t ml = strlen(mode);
        if (ml >= sizeof n.mode) ml = sizeof n.mode - 1; /* bounded: a long behaviour list is cut */
        memcpy(n.mode, mode, ml);
        n.mode[ml] = 0;
        n.fields |= KELP_NR_MODE;
    }
    if (r->allstop[0]) memcpy(n.allstop, r->allstop, sizeof n.allstop), n.fields |= KELP_NR_ALLSTOP;
    if (r->group[0]) memcpy(n.group, r->group, sizeof n.group), n.fields |= KELP_NR_GROUP;
    size_t len;
    int rc = kelp_nodereport_format(&n, r->last, sizeof r->last, &len);
    if (rc < 0) {
        kelp_app_run_warning(app, "cannot format the report (%s)", kelp_strerror(rc));
        return 0;
    }
    if (kelp_app_notify_string(app, r->out_var, r->last) < 0) kelp_app_run_warning(app, "publish failed");
    else r->posted++;
    r->fresh = false;
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    nrep *r = st;
    (void)app;
    fprintf(out, "Vehicle %s (%s)%s%s; nav mail %lu (bad %lu); %s posted %lu times\n", r->name, r->type,
            r->group[0] ? " group " : "", r->group, r->nav_mail, r->bad_mail, r->out_var, r->posted);
    fprintf(out, "Last: %s\n", r->last[0] ? r->last : "(none yet: waiting for NAV_X/NAV_Y or NAV_LAT/NAV_LONG)");
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
