/* kelp-viewer (the pMarineViewer role): a web page of the shoreside bus, served live.
 *
 *   kelp-viewer [--port N] [--bind ADDR --token T] mission.moos [NAME]     live, on the bus
 *   kelp-viewer --log run.lcm [--port N] [--speed S] [mission.moos]        replay a recorded mission
 *
 * The model is the core kelp_viewer (include/kelp/viewer.h); the web server and the replay are
 * libkelp_viewer (include/kelp/edge/viewer.h); this file wires them to the app runner. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/edge/viewer.h>
#include <kelp/util.h>

typedef struct viewer {
    kelp_viewer model;
    kelp_viewer_http *http;
    kelp_viewer_http_cfg hc;
    const char *opt_bind, *opt_token, *opt_docroot;
    long opt_port;
    char port_s[16], token[128], bind[64], image[512], docroot[512];
    unsigned long pressed, refused;
    double next_castreq;
} viewer;

#define CASTREQ_PERIOD 2.0 /* s (MOOS time) between AppCast requests; each asks for 5 s of casts */

enum { OPT_PORT = 300, OPT_BIND, OPT_TOKEN, OPT_DOCROOT, OPT_LOG, OPT_SPEED, OPT_PAUSED };

static const kelp_cli_opt opts[] = {
    { "port", required_argument, OPT_PORT, "N", "HTTP port (default 8080, or the block's port; 0: any free)" },
    { "bind", required_argument, OPT_BIND, "ADDR", "IPv4 address to serve on (default 127.0.0.1; others need a token)" },
    { "token", required_argument, OPT_TOKEN, "T", "access token every request must carry (?token=T)" },
    { "docroot", required_argument, OPT_DOCROOT, "DIR", "the page's files (default: share/viewer next to the program)" },
    { "log", required_argument, OPT_LOG, "RUN.lcm", "replay this log (kelp-record's LCM log or an .alog) instead" },
    { "speed", required_argument, OPT_SPEED, "S", "replay: initial speed, 1..20" },
    { "paused", no_argument, OPT_PAUSED, NULL, "replay: start paused" },
    { NULL, 0, 0, NULL, NULL },
};

static int on_arg(void *st, int val, const char *arg, kelp_diag *d)
{
    viewer *s = st;
    switch (val) {
    case OPT_PORT:
        if (kelp_util_parse_long(arg, strlen(arg), &s->opt_port) < 0 || s->opt_port < 0 || s->opt_port > 65535)
            return kelp_fail(d, KELP_ERR_ARG, "--port: 0..65535");
        return 0;
    case OPT_BIND: s->opt_bind = arg; return 0;
    case OPT_TOKEN: s->opt_token = arg; return 0;
    case OPT_DOCROOT: s->opt_docroot = arg; return 0;
    default: return kelp_fail(d, KELP_ERR_ARG, "only with --log");
    }
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    viewer *s = ctx;
    int rc = kelp_viewer_config(&s->model, key, val, d);
    if (rc != 0) return rc;
    struct { const char *key; char *dst; size_t cap; } own[] = {
        {"port", s->port_s, sizeof s->port_s}, {"token", s->token, sizeof s->token},
        {"bind", s->bind, sizeof s->bind}, {"tiff_file", s->image, sizeof s->image}};
    for (size_t i = 0; i < sizeof own / sizeof own[0]; i++) {
        if (!kelp_util_strieq(key, own[i].key)) continue;
        if (strlen(val) >= own[i].cap) return kelp_fail(d, KELP_ERR_ARG, "too long");
        memcpy(own[i].dst, val, strlen(val) + 1);
        return 1;
    }
    return 0;
}

/* press command i: its pokes go on the bus */
static void press(kelp_app *app, viewer *s, unsigned i)
{
    const kelp_viewer_cmd *c = kelp_viewer_cmd_get(&s->model, i);
    if (!c) {
        s->refused++;
        kelp_app_run_warning(app, "the page pressed command %u, which is not configured", i);
        return;
    }
    s->pressed++;
    const kelp_viewer_poke *pk[KELP_VIEWER_MAX_CMDS * KELP_VIEWER_MAX_POKES];
    unsigned n = kelp_viewer_press(&s->model, i, pk, sizeof pk / sizeof pk[0]);
    for (unsigned k = 0; k < n; k++) {
        if (pk[k]->is_string) KELP_IGNORE(kelp_app_notify_string(app, pk[k]->var, pk[k]->sval));
        else KELP_IGNORE(kelp_app_notify_double(app, pk[k]->var, pk[k]->dval));
    }
    kelp_app_event(app, "%s \"%s\" pressed in the page (%u pokes)", c->kind == KELP_VIEWER_BUTTON ? "button" : "action",
                   c->label, n);
}

static void serve(kelp_app *app, viewer *s, bool force)
{
    kelp_viewer_req rq;
    while (kelp_viewer_http_next(s->http, &rq) == 1)
        if (rq.kind == KELP_VIEWER_REQ_CMD) press(app, s, rq.idx);
    if (kelp_viewer_http_pump(s->http, &s->model, kelp_app_time(app), kelp_app_warp(app), force) < 0)
        kelp_app_run_warning(app, "the page's JSON does not fit its buffer");
}

static void on_wake(kelp_app *app, void *st, int fd)
{
    (void)fd;
    serve(app, st, false);
}

static int startup(kelp_app *app, void *st)
{
    viewer *s = st;
    double lat, lon;
    if (kelp_app_global_double(app, "LatOrigin", &lat) == 1 && kelp_app_global_double(app, "LongOrigin", &lon) == 1 &&
        kelp_viewer_set_datum(&s->model, lat, lon) < 0)
        kelp_app_config_warning(app, "LatOrigin/LongOrigin out of range");
    int rc = kelp_app_param_foreach(app, param, s);
    if (rc < 0) return rc;
    kelp_diag err = {0};
    s->hc.port = 8080;
    if (s->port_s[0]) {
        long p;
        if (kelp_util_parse_long(s->port_s, strlen(s->port_s), &p) < 0 || p < 0 || p > 65535)
            return kelp_app_config_error(app, kelp_app_param(app, "port"), "port: 0..65535");
        s->hc.port = (unsigned)p;
    }
    if (s->opt_port >= 0) s->hc.port = (unsigned)s->opt_port;
    s->hc.bind = s->opt_bind ? s->opt_bind : s->bind[0] ? s->bind : NULL;
    s->hc.token = s->opt_token ? s->opt_token : s->token;
    if (!s->opt_docroot && kelp_viewer_docroot(s->docroot, sizeof s->docroot) < 0)
        return kelp_app_config_error(app, NULL, "the page's files (share/viewer) not found: use --docroot");
    s->hc.docroot = s->opt_docroot ? s->opt_docroot : s->docroot;
    if (s->image[0]) {
        /* pMarineViewer's tiff_file with its .info; a .png/.jpg of the same name is preferred (browsers show those) */
        char shown[512], info[512];
        double n, so, e, w;
        if (kelp_viewer_image_files(s->image, kelp_app_mission_path(app), shown, sizeof shown, info, sizeof info) < 0)
            kelp_app_config_warning(app, "tiff_file %s: no such image", s->image);
        else if (kelp_viewer_read_info(info, &n, &so, &e, &w, &err) < 0)
            kelp_app_config_warning(app, "tiff_file: %s", kelp_diag_text(&err));
        else if (kelp_viewer_set_image(&s->model, "/image", n, so, e, w) < 0)
            kelp_app_config_warning(app, "%s: an empty or inverted box", info);
        else
            snprintf(s->image, sizeof s->image, "%s", shown);
    }
    s->hc.image_path = s->model.image_url[0] ? s->image : NULL;
    kelp_diag_clear(&err);
    s->http = kelp_viewer_http_start(&s->hc, &err);
    if (!s->http) return kelp_app_config_error(app, NULL, "%s", kelp_diag_text(&err));
    static const char *const vars[] = {"NODE_REPORT", "NODE_REPORT_LOCAL", "VIEW_POINT", "VIEW_CIRCLE", "VIEW_POLYGON",
                                       "VIEW_SEGLIST", "VIEW_MARKER", "VIEW_COMMS_PULSE", "VIEW_COMM_PULSE",
                                       "VIEW_RANGE_PULSE", "APPCAST"};
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
        if (kelp_app_register(app, vars[i], 0) < 0) kelp_app_config_warning(app, "cannot register %s", vars[i]);
    if (kelp_app_watch_fd(app, kelp_viewer_http_fd(s->http), on_wake) < 0)
        return kelp_app_config_error(app, NULL, "cannot watch the server's descriptor");
    const char *host = s->hc.bind ? s->hc.bind : "127.0.0.1";
    printf("kelp-viewer: http://%s:%u/%s%s\n", host, kelp_viewer_http_port(s->http), s->hc.token[0] ? "?token=" : "",
           s->hc.token);
    fflush(stdout);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    viewer *s = st;
    if (v->kind != KELP_VAR_STRING) return;
    (void)kelp_viewer_mail(&s->model, v->name, v->sval, strlen(v->sval), kelp_app_time(app));
}

static int iterate(kelp_app *app, void *st, double now)
{
    viewer *s = st;
    (void)kelp_viewer_tick(&s->model, now);
    if (now >= s->next_castreq) {
        /* AppCasting: every app of this community (and, through uFldShoreBroker's QBRIDGE of
         * APPCAST_REQ, every vehicle's) casts for the page's AppCast pane */
        static const char req[] = "node=all,app=all,duration=5,key=kelp-viewer,thresh=any";
        KELP_IGNORE(kelp_app_notify_string(app, "APPCAST_REQ", req));
        KELP_IGNORE(kelp_app_notify_string(app, "APPCAST_REQ_ALL", req));
        s->next_castreq = now + CASTREQ_PERIOD;
    }
    serve(app, s, false);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    viewer *s = st;
    size_t snap, frame;
    unsigned long frames;
    if (!s->http) return; /* stopped */
    kelp_viewer_http_sizes(s->http, &snap, &frame, &frames);
    const kelp_viewer_stats *x = &s->model.stats;
    unsigned nv = 0;
    for (unsigned i = 0; i < s->model.nveh; i++) nv += s->model.veh[i].used && !s->model.veh[i].gone;
    fprintf(out, "page: http://%s:%u/  (%u streams)\n", s->hc.bind ? s->hc.bind : "127.0.0.1",
            kelp_viewer_http_port(s->http), kelp_viewer_http_clients(s->http));
    fprintf(out, "vehicles %u  reports %lu (refused %lu)  artifacts %lu (refused %lu, evicted %lu)  appcasts %lu\n", nv,
            x->reports, x->reports_bad, x->views, x->views_bad, x->evicted, x->casts);
    fprintf(out, "frames %lu (last %zu B, snapshot %zu B)  commands %u, pressed %lu, refused %lu\n", frames, frame,
            snap, s->model.ncmds, s->pressed, s->refused);
    (void)app;
}

static void shutdown_(kelp_app *app, void *st)
{
    viewer *s = st;
    (void)app;
    kelp_viewer_http_stop(s->http);
    s->http = NULL;
}

#define BTN(w, n) { "BUTTON_" w, "LABEL # VAR=value", "a button: its label, pokes and color= separated by #", NULL }, \
                  { "BUTTON_" n, "LABEL # VAR=value", "the same as BUTTON_" w, "BUTTON_" w }

static const kelp_app_def def = {
    .name = "kelp-viewer",
    .pid_var = "PMARINEVIEWER_PID", /* the pMarineViewer role: 24.8 posts it at start-up */
    .purpose = "The pMarineViewer role in a browser: vehicles, trails and VIEW_* artifacts live, with action buttons.",
    .synopsis = "Serves a web page (HTTP and Server-Sent Events, on 127.0.0.1 unless --bind with a token) showing\n"
                "every vehicle of NODE_REPORT/NODE_REPORT_LOCAL (icon by type and heading, name, trail, stale\n"
                "ones greyed), every VIEW_* artifact, the datum with a metre grid and a lat/lon readout, an\n"
                "optional background image (tiff_file + .info), the selected vehicle's report, and\n"
                "pMarineViewer's button_* and action lines, which poke the bus. --log RUN.lcm replays a recorded\n"
                "mission in the same page (time slider, play/pause, speed) without the bus.",
    .opts = opts,
    .on_arg = on_arg,
    .params = (const kelp_app_param_info[]){
        { "PORT", "8080", "HTTP port (--port wins); 0: any free port", NULL },
        { "BIND", "127.0.0.1", "IPv4 address to serve on (--bind wins); not loopback needs TOKEN", NULL },
        { "TOKEN", "", "optional: every request must carry ?token=TOKEN (or the cookie it sets)", NULL },
        { "TIFF_FILE", "", "optional background image, e.g. MIT_SP.tif with MIT_SP.info (MIT_SP.png/.jpg served first)", NULL },
        { "STALE_REPORT_THRESH", "60", "seconds without a report before a vehicle is drawn stale (at least 2)", NULL },
        { "STALE_REMOVE_THRESH", "180", "seconds without a report before a vehicle is removed; 0 never", NULL },
        { "TRAILS_LENGTH", "100", "trail points per vehicle (1..256)", NULL },
        { "ACTION", "menu_key=deploy # DEPLOY=true # RETURN=false", "repeatable: Action menu entries, one per pair; a menu_key posts all its pairs", NULL },
        { "ACTION+", "RETURN=true", "as ACTION, with separators after its entries", NULL },
        BTN("ONE", "1"), BTN("TWO", "2"), BTN("THREE", "3"), BTN("FOUR", "4"), BTN("FIVE", "5"),
        BTN("SIX", "6"), BTN("SEVEN", "7"), BTN("EIGHT", "8"), BTN("NINE", "9"), BTN("TEN", "10"),
        BTN("ELEVEN", "11"), BTN("TWELVE", "12"), BTN("THIRTEEN", "13"), BTN("FOURTEEN", "14"), BTN("FIFTEEN", "15"),
        BTN("SIXTEEN", "16"), BTN("SEVENTEEN", "17"), BTN("EIGHTEEN", "18"), BTN("NINETEEN", "19"), BTN("TWENTY", "20"),
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_REPORT", "NAME=alpha,TYPE=UUV,X=51.7,Y=-35.5,HDG=118.8,SPD=2", "a vehicle (also NODE_REPORT_LOCAL)" },
        { "VIEW_POLYGON", "pts={0,0:10,0:10,10},label=ops", "artifacts: VIEW_POINT, _CIRCLE, _POLYGON, _SEGLIST, _MARKER, _COMMS_PULSE, _RANGE_PULSE" },
        { "APPCAST", "proc=pHelmIvP!@#node=alpha!@#iter=12", "apps' AppCasts, shown in the page's AppCast pane" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "<VAR>", "true", "the pokes of a button or action pressed in the page" },
        { "APPCAST_REQ", "node=all,app=all,duration=5,key=kelp-viewer,thresh=any", "every 2 s: casts for the AppCast pane" },
        { "APPCAST_REQ_ALL", "node=all,app=all,duration=5,key=kelp-viewer,thresh=any", "the same for every vehicle (uFldShoreBroker's QBRIDGE)" },
        { NULL, NULL, NULL } },
    .notes = "Globals used: LatOrigin, LongOrigin (the datum).\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown_,
};

int main(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--log") || !strncmp(argv[i], "--log=", 6)) return kelp_viewer_replay_main(argc, argv);
    static viewer s;
    kelp_viewer_init(&s.model);
    s.opt_port = -1;
    return kelp_app_run(argc, argv, &def, &s);
}
