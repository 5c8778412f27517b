/* pREMUSCodec: the REMUS CCL codec of Goby 1.1 (seed 002 section 2.5). The logic is the core
 * state machine kelp_remus_codec (include/kelp/remus.h); this file reads the Goby TextFormat
 * block (create_status, mdat_*_var / mdat_*_out, modem_id_lookup_path, status_interval) and the
 * globals (LatOrigin, LongOrigin, modem_id_lookup_path as the fallback), loads the modem-id
 * lookup file and wires the tool to the bus. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kelp/edge/app.h>
#include <kelp/edge/dccl.h>
#include <kelp/remus.h>

typedef struct premus {
    kelp_remus_codec core;
    kelp_dccl_builtin geo;
    kelp_dccl_modem_entry modems[64];
    kelp_app *app;
    kelp_field_sink sink;
    char lookup[512];
} premus;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    premus *p = ctx;
    int rc = is_string ? kelp_app_notify_string(p->app, var, sval) : kelp_app_notify_double(p->app, var, dval);
    if (rc < 0) kelp_app_run_warning(p->app, "cannot publish %s", var);
}

static void warn(void *ctx, const char *msg)
{
    kelp_app_run_warning(((premus *)ctx)->app, "%s", msg);
}

static const char *const VAR_KEY[KELP_REMUS_NVARS] = {"state", "ranger", "redirect", "alert", "alert2"};

static int startup(kelp_app *app, void *st)
{
    premus *p = st;
    p->app = app;
    p->sink = (kelp_field_sink){p, publish, warn};
    kelp_remus_codec_cfg c;
    kelp_remus_codec_cfg_default(&c);
    (void)kelp_app_param(app, "common"); /* Goby's common { } block: nothing here needs it */
    int rc = kelp_app_param_bool(app, "create_status", &c.create_status);
    if (rc < 0) return kelp_app_config_error(app, kelp_app_param(app, "create_status"), "create_status must be true or false");
    double d;
    if ((rc = kelp_app_param_double(app, "status_interval", &d)) < 0 || (rc > 0 && !(d > 0 && isfinite(d))))
        return kelp_app_config_error(app, kelp_app_param(app, "status_interval"), "status_interval must be > 0 (s)");
    if (rc > 0) c.status_interval = d;
    for (int k = 0; k < KELP_REMUS_NVARS; k++) {
        char key[32];
        (void)snprintf(key, sizeof key, "mdat_%s_var", VAR_KEY[k]);
        if ((rc = kelp_app_param_str(app, key, c.in_var[k], sizeof c.in_var[k])) < 0 || (rc > 0 && !c.in_var[k][0]))
            return kelp_app_config_error(app, kelp_app_param(app, key), "%s must be a variable name", key);
        (void)snprintf(key, sizeof key, "mdat_%s_out", VAR_KEY[k]);
        if ((rc = kelp_app_param_str(app, key, c.out_var[k], sizeof c.out_var[k])) < 0 || (rc > 0 && !c.out_var[k][0]))
            return kelp_app_config_error(app, kelp_app_param(app, key), "%s must be a variable name", key);
    }
    kelp_dccl_builtin_init(&p->geo, p->modems, sizeof p->modems / sizeof p->modems[0]);
    double lat0 = 0, lon0 = 0;
    bool have_lat = kelp_app_global_double(app, "LatOrigin", &lat0) == 1;
    bool have_lon = kelp_app_global_double(app, "LongOrigin", &lon0) == 1;
    if (!have_lat || !have_lon)
        kelp_app_config_warning(app, "LatOrigin/LongOrigin missing: positions are taken relative to 0,0");
    kelp_dccl_builtin_set_origin(&p->geo, lat0, lon0);
    if ((rc = kelp_app_param_str(app, "modem_id_lookup_path", p->lookup, sizeof p->lookup)) == 0)
        rc = kelp_app_global_str(app, "modem_id_lookup_path", p->lookup, sizeof p->lookup);
    if (rc < 0) return kelp_app_config_error(app, kelp_app_param(app, "modem_id_lookup_path"), "modem_id_lookup_path too long");
    if (p->lookup[0]) {
        char path[1024];
        const char *mp = kelp_app_mission_path(app);
        const char *slash = mp ? strrchr(mp, '/') : NULL;
        if (p->lookup[0] != '/' && slash)
            (void)snprintf(path, sizeof path, "%.*s/%s", (int)(slash - mp), mp, p->lookup);
        else
            (void)snprintf(path, sizeof path, "%s", p->lookup);
        kelp_diag why;
        kelp_diag_clear(&why);
        if (kelp_dccl_builtin_load_modems(&p->geo, path, &why) < 0)
            return kelp_app_config_error(app, kelp_app_param(app, "modem_id_lookup_path"), "%s", kelp_diag_text(&why));
    } else {
        kelp_app_config_warning(app, "no modem_id_lookup_path: senders are named by their modem id");
    }
    c.geo = &p->geo;
    if (kelp_remus_codec_init(&p->core, &c) < 0) return kelp_app_config_error(app, NULL, "bad configuration");
    const char *var;
    for (unsigned i = 0; (var = kelp_remus_codec_subscription(&p->core, i)) != NULL; i++)
        if (kelp_app_register(app, var, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", var);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    premus *p = st;
    if (v->kind == KELP_VAR_BINARY) return;
    /* refused mail is warned through the sink and counted by the core */
    KELP_IGNORE(kelp_remus_codec_mail(&p->core, v->name, v->kind == KELP_VAR_STRING, v->sval, v->dval, kelp_app_time(app),
                                      &p->sink));
}

static int iterate(kelp_app *app, void *st, double now)
{
    (void)app;
    (void)kelp_remus_codec_iterate(&((premus *)st)->core, now, &((premus *)st)->sink);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    const premus *p = st;
    const kelp_remus_codec *c = &p->core;
    (void)app;
    fprintf(out, "create_status %s (every %g s); modem id %d; %zu lookup entries\n", c->cfg.create_status ? "on" : "off",
            c->cfg.status_interval, c->my_id, p->geo.n_modems);
    fprintf(out, "States sent %lu; received: State %lu, Ranger %lu, Redirect %lu, Alert %lu, Alert2 %lu; refused %lu\n",
            c->sent, c->received[0], c->received[1], c->received[2], c->received[3], c->received[4], c->refused);
}

static const kelp_app_def def = {
    .name = "pREMUSCodec",
    .purpose = "REMUS CCL codec: State from NAV_* (create_status); NODE_REPORT from State/Ranger; Redirect/Alert texts.",
    .textformat = true,
    .params = (const kelp_app_param_info[]){
        {"common", "{ verbosity: VERBOSITY_VERBOSE }", "optional: Goby's common block (accepted)", NULL},
        {"create_status", "false", "Will generate REMUS State message if true", NULL},
        {"status_interval", "10", "kelp: seconds between State messages (Goby: 10, fixed)", NULL},
        {"mdat_state_var", "\"IN_REMUS_STATUS_HEX_30B\"", "incoming REMUS State (ModemDataTransmission)", NULL},
        {"mdat_state_out", "\"OUT_REMUS_STATUS_HEX_30B\"", "outgoing REMUS State", NULL},
        {"mdat_ranger_var", "\"IN_REMUS_RANGER_HEX_30B\"", "incoming REMUS Ranger", NULL},
        {"mdat_ranger_out", "\"OUT_REMUS_RANGER_HEX_30B\"", "outgoing REMUS Ranger", NULL},
        {"mdat_redirect_var", "\"IN_REMUS_REDIRECT_HEX_30B\"", "incoming REMUS Redirect", NULL},
        {"mdat_redirect_out", "\"OUT_REMUS_REDIRECT_HEX_30B\"", "outgoing REMUS Redirect", NULL},
        {"mdat_alert_var", "\"IN_REMUS_ALERT_HEX_30B\"", "incoming REMUS Alert", NULL},
        {"mdat_alert_out", "\"OUT_REMUS_ALERT_HEX_30B\"", "outgoing REMUS Alert", NULL},
        {"mdat_alert2_var", "\"IN_REMUS_ALERT2_HEX_30B\"", "incoming REMUS Alert2", NULL},
        {"mdat_alert2_out", "\"OUT_REMUS_ALERT2_HEX_30B\"", "outgoing REMUS Alert2", NULL},
        {"modem_id_lookup_path", "\"modemidlookup.txt\"", "\"id,name,type\" lines (default: the global)", NULL},
        {NULL, NULL, NULL, NULL}},
    .subscribes = (const kelp_app_var_info[]){
        {"IN_REMUS_STATUS_HEX_30B", "base { src: 2 dest: 0 } data: \"\\016...\"", "mdat_state_var (and the other _var)"},
        {"MODEM_ID", "2", "src of the States made here"},
        {"NAV_X", "123", "meters east of LatOrigin/LongOrigin"},
        {"NAV_Y", "321", NULL},
        {"NAV_HEADING", "45", "degrees"},
        {"NAV_SPEED", "1.2", "m/s"},
        {"NAV_DEPTH", "111", "meters"},
        {"OUTGOING_COMMAND", "MessageType=CCL_REDIRECT,DestinationPlatformId=3,Latitude=42.35,...",
         "a CCL_REDIRECT becomes a Redirect on mdat_redirect_out"},
        {NULL, NULL, NULL}},
    .publishes = (const kelp_app_var_info[]){
        {"OUT_REMUS_STATUS_HEX_30B", "base { src: 2 dest: 0 } data: \"\\016...\"",
         "mdat_state_out: a State every status_interval when create_status"},
        {"OUT_REMUS_REDIRECT_HEX_30B", "base { src: 2 dest: 3 } data: \"\\007...\"",
         "mdat_redirect_out: for each CCL_REDIRECT on OUTGOING_COMMAND"},
        {"NODE_REPORT", "NAME=mm2,TYPE=auv,TIME=...,X=123,Y=321,...,MODE=NOMOOS,ALLSTOP=NotUsingIvP",
         "for each State or Ranger received"},
        {"STATUS_REPORT_IN", "MessageType=CCL_STATUS,Node=2,Timestamp=...,Latitude=...", "with it"},
        {"<NAME>_NAV_X", "123", "and _NAV_UTC, _Y, _LAT, _LONG, _SPEED, _DEPTH, _HEADING of the sender"},
        {"CCL_REDIRECT_IN", "MessageType=CCL_REDIRECT,DestinationPlatformId=3,...", "for each Redirect received"},
        {"CCL_ALERT_IN", "MessageType=CCL_ALERT,Node=2,...", "for each Alert received"},
        {"CCL_ALERT2_IN", "MessageType=CCL_ALERT2,Node=2,...", "for each Alert2 received"},
        {NULL, NULL, NULL}},
    .notes = "Globals used: LatOrigin, LongOrigin, modem_id_lookup_path (when not in the block).\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static premus p;
    return kelp_app_run(argc, argv, &def, &p);
}
