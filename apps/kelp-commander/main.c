/* kelp-commander: the iCommander role of Goby 1.1 (seed 002 section 2.4, acomms.md 7.1): a
 * console that loads the DCCL XML files pAcommsHandler loads and sends command messages by
 * publishing the variables pAcommsHandler builds them from. The model is the core kelp_commander
 * (include/kelp/commander.h); console.c draws it with ncurses; this file reads the block,
 * wires the bus and runs the scripted mode:
 *
 *   kelp-commander MISSION.moos --send NAME field=value ... [--wait SECONDS]
 *
 * publishes the message and exits, or with --wait prints the ack (or expiry) and exits 0, or
 * exits 1 when none came within SECONDS. */
#include <fcntl.h>
#include <libgen.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <kelp/kv.h>
#include <kelp/mission.h>
#include <kelp/util.h>

#include "cmdr.h"

static int extra_field(void *ctx, const kelp_mission_node *n, kelp_diag *d)
{
    cmdr_app *s = ctx;
    if (kelp_mission_key_is(n, "load")) {
        if (s->n_load >= CMDR_MAX_LOAD) return kelp_fail(d, KELP_ERR_RANGE, "too many load (max 8)");
        if (kelp_mission_copy(n, s->load[s->n_load], sizeof s->load[0]) < 0) return kelp_fail(d, KELP_ERR_RANGE, "path too long");
        if (s->load[s->n_load][0]) s->n_load++;
        return 1;
    }
    if (kelp_mission_key_is(n, "show_variable")) {
        if (s->n_show >= CMDR_MAX_SHOW) return kelp_fail(d, KELP_ERR_RANGE, "too many show_variable (max 8)");
        if (kelp_mission_copy(n, s->show[s->n_show], sizeof s->show[0]) < 0) return kelp_fail(d, KELP_ERR_RANGE, "name too long");
        if (s->show[s->n_show][0]) s->n_show++;
        return 1;
    }
    if (kelp_mission_key_is(n, "force_xy_only")) {
        if (kelp_mission_bool(n, &s->core.force_xy_only) < 0) return kelp_fail(d, KELP_ERR_PARSE, "force_xy_only must be true or false");
        return 1;
    }
    return 0;
}

static int script_fields(cmdr_app *s)
{
    int m = kelp_commander_open(&s->core, s->send_name);
    if (m < 0) return kelp_app_config_error(s->app, NULL, "--send %s: no such message in the XML files", s->send_name);
    for (int i = 0; i < s->n_send_args; i++) {
        char buf[KELP_CMDR_VAL + KELP_DCCL_MAX_NAME];
        const char *k, *v;
        kelp_diag why;
        kelp_diag_clear(&why);
        size_t kl, vl, pos = 0;
        (void)snprintf(buf, sizeof buf, "%s", s->send_args[i]);
        if (kelp_kv_next(buf, '\n', &pos, &k, &kl, &v, &vl) != 1)
            return kelp_app_config_error(s->app, NULL, "--send: \"%s\" is not field=value", s->send_args[i]);
        ((char *)k)[kl] = 0;
        ((char *)v)[vl] = 0;
        int row = kelp_commander_row(&s->core.open[m], k);
        if (row < 0) return kelp_app_config_error(s->app, NULL, "--send: %s has no field %s", s->send_name, k);
        if (kelp_commander_set(&s->core, (unsigned)m, (unsigned)row, v, &why) < 0)
            return kelp_app_config_error(s->app, NULL, "--send: %s=%s: %s", k, v, kelp_diag_text(&why));
    }
    return KELP_OK;
}

static int startup(kelp_app *app, void *st)
{
    cmdr_app *s = st;
    char warn[2048];
    kelp_diag d;
    kelp_diag_clear(&d);
    s->app = app;
    (void)snprintf(s->base_dir, sizeof s->base_dir, "%s", kelp_app_mission_path(app));
    (void)snprintf(s->base_dir, sizeof s->base_dir, "%s", dirname(s->base_dir));
    const kelp_mission *m = kelp_app_mission(app);
    int block = kelp_app_block(app);
    if (kelp_acomms_config_read_extra(m, block, s->base_dir, &s->cfg, &d, warn, sizeof warn, extra_field, s) < 0)
        return kelp_app_config_error(app, NULL, "%s", kelp_diag_text(&d));
    for (int i = kelp_mission_next(m, block, -1, NULL); i >= 0; i = kelp_mission_next(m, block, i, NULL))
        if (m->nodes[i].kind == KELP_MN_FIELD || m->nodes[i].kind == KELP_MN_MSG) kelp_app_param_used(app, &m->nodes[i]);
    kelp_dccl_loaded_init(&s->ld);
    kelp_dccl_builtin_init(&s->geo, s->modems, sizeof s->modems / sizeof s->modems[0]);
    if (s->cfg.has_lat_origin && s->cfg.has_lon_origin) kelp_dccl_builtin_set_origin(&s->geo, s->cfg.lat_origin, s->cfg.lon_origin);
    if (s->cfg.modem_id_lookup_path[0] && kelp_dccl_builtin_load_modems(&s->geo, s->cfg.modem_id_lookup_path, &d) < 0)
        return kelp_app_config_error(app, NULL, "%s", kelp_diag_text(&d));
    for (size_t i = 0; i < s->cfg.nfiles; i++)
        if (kelp_dccl_load_file(&s->ld, s->cfg.files[i].path, NULL, &d) < 0)
            return kelp_app_config_error(app, NULL, "%s", kelp_diag_text(&d));
    if (!s->cfg.nfiles) kelp_app_config_warning(app, "no dccl_cfg message_file: import one from the main menu");
    bool xy = s->core.force_xy_only;
    kelp_commander_init(&s->core, &s->ld.set, &s->geo);
    s->core.force_xy_only = xy;
    for (unsigned i = 0; i < s->n_load; i++)
        if (cmdr_load_file(s, s->load[i], &d) < 0) return kelp_app_config_error(app, NULL, "load: %s", kelp_diag_text(&d));
    if (kelp_app_register(app, "ACOMMS_ACK", 0) < 0 || kelp_app_register(app, "ACOMMS_EXPIRE", 0) < 0)
        return kelp_app_config_error(app, NULL, "cannot register ACOMMS_ACK / ACOMMS_EXPIRE");
    for (unsigned i = 0; i < s->n_show; i++)
        if (kelp_app_register(app, s->show[i], 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", s->show[i]);
    /* our own output goes to the terminal; the runner's status report goes quiet */
    s->out_fd = dup(STDOUT_FILENO);
    s->out = s->out_fd >= 0 ? fdopen(s->out_fd, "w") : stderr;
    if (s->send_name) {
        if (script_fields(s) < 0) return -1;
    } else if (!isatty(STDOUT_FILENO) || !cmdr_console_start(s)) {
        kelp_app_config_warning(app, "no terminal: no console; acks and expiries are printed as lines");
    }
    if (!s->send_name && !s->console) return 0; /* headless: the runner's report stays on stdout */
    fflush(stdout);
    int null = open("/dev/null", O_WRONLY);
    if (null >= 0) {
        (void)dup2(null, STDOUT_FILENO);
        close(null);
    }
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    cmdr_app *s = st;
    bool ack = strcmp(v->name, "ACOMMS_ACK") == 0;
    if (v->kind == KELP_VAR_STRING && (ack || strcmp(v->name, "ACOMMS_EXPIRE") == 0)) {
        if (kelp_commander_ack_note(&s->core, ack, v->sval, kelp_app_time(app), s->note, sizeof s->note) < 0) return;
        if (s->console) cmdr_console_note(s);
        if (!s->console && !s->send_name) fprintf(s->out, "%s\n", s->note), fflush(s->out);
        if (s->send_name && s->sent && strstr(s->note, s->send_name)) {
            fprintf(s->out, "%s\n", s->note);
            s->exit_code = ack ? 0 : 1;
            kelp_app_quit(app);
        }
        return;
    }
    for (unsigned i = 0; i < s->n_show; i++)
        if (strcmp(v->name, s->show[i]) == 0) {
            if (v->kind == KELP_VAR_STRING)
                (void)snprintf(s->show_val[i], sizeof s->show_val[i], "%.*s", (int)sizeof s->show_val[i] - 1, v->sval);
            else
                (void)snprintf(s->show_val[i], sizeof s->show_val[i], "%g", v->dval);
            if (s->console) cmdr_console_note(s);
        }
}

static int iterate(kelp_app *app, void *st, double now)
{
    cmdr_app *s = st;
    if (!s->send_name) return 0;
    if (!s->sent) {
        static char text[KELP_CMDR_MAX_PUBS * (KELP_CMDR_PUBLEN + 80)];
        s->sent = true;
        s->sent_at = now;
        int rc = cmdr_send(s, 0, text, sizeof text);
        fputs(text, s->out);
        if (rc < 0) fputc('\n', s->out);
        fflush(s->out);
        s->exit_code = rc < 0 ? 1 : 0;
        if (rc < 0 || !(s->wait > 0)) kelp_app_quit(app);
        return 0;
    }
    if (now - s->sent_at > s->wait) {
        fprintf(s->out, "no acknowledgement of %s within %g s\n", s->send_name, s->wait);
        s->exit_code = 1;
        kelp_app_quit(app);
    }
    return 0;
}

static void shutdown_(kelp_app *app, void *st)
{
    cmdr_app *s = st;
    (void)app;
    if (s->console) cmdr_console_stop(s);
    if (s->out && s->out != stderr) fflush(s->out);
}

/* --send NAME and --wait S are parsed by the runner from this table (so --help lists them);
 * the field=value words after --send NAME are taken out of argv before it runs */
enum { OPT_SEND = 1000, OPT_WAIT };
static const kelp_cli_opt cmdr_opts[] = {
    { "send", required_argument, OPT_SEND, "NAME", "script: send message NAME with the field=value words that follow, then exit" },
    { "wait", required_argument, OPT_WAIT, "SECONDS", "with --send: wait for the ack (exit 0) or expiry/timeout (exit 1)" },
    { NULL, 0, 0, NULL, NULL },
};

static int cmdr_arg(void *state, int val, const char *arg, kelp_diag *d)
{
    cmdr_app *s = state;
    if (val == OPT_SEND) {
        s->send_name = arg;
        return 0;
    }
    if (val == OPT_WAIT) {
        if (kelp_util_parse_finite(arg, strlen(arg), &s->wait) < 0 || s->wait < 0)
            return kelp_fail(d, KELP_ERR_PARSE, "--wait wants seconds");
        return 0;
    }
    return kelp_fail(d, KELP_ERR_PARSE, "unexpected argument");
}

static const kelp_app_def def = {
    .name = "kelp-commander",
    .moos_name = "iCommander",
    .purpose = "iCommander: a console that sends DCCL command messages through pAcommsHandler.",
    .textformat = true,
    .params = (const kelp_app_param_info[]){
        {"common", "{ verbosity: VERBOSITY_VERBOSE }", "optional: Goby's common block (community, lat_origin, lon_origin)", NULL},
        {"dccl_cfg", "{ modem_id: 1 }",
         "modem_id and the message_file { path: \"x.xml\" } blocks pAcommsHandler loads (crypto_passphrase unused)", NULL},
        {"modem_id_lookup_path", "\"\"", "optional: \"id,name,type\" lines for the modem id special", NULL},
        {"load", "\"\"", "optional, repeatable: a save file to load at start", NULL},
        {"show_variable", "\"DEPLOY\"", "optional, repeatable: a variable shown on the console", NULL},
        {"force_xy_only", "false", "true: latitude/longitude fields take only the x/y special", NULL},
        {NULL, NULL, NULL, NULL}},
    .subscribes = (const kelp_app_var_info[]){
        {"ACOMMS_ACK", "base { src: 2 dest: 1 } frame: 0 orig_msg { ... }", "shown as \"Message acknowledged from queue\""},
        {"ACOMMS_EXPIRE", "orig_msg { base { src: 1 dest: 2 } data: \"...\" }", "shown as \"Message expired from queue\""},
        {"<show_variable>", "anything", "each show_variable"},
        {NULL, NULL, NULL}},
    .publishes = (const kelp_app_var_info[]){
        {"<trigger_var>", "CommandType=GoTo,Destination=2,goto_x=101", "on Send: the message's trigger variable"},
        {"<src_var>", "new_instructions=make_toast", "on Send: each other source variable of the message"},
        {NULL, NULL, NULL}},
    .notes = "Command line: MISSION.moos [--send NAME field=value ... [--wait SECONDS]]\n"
             "Globals used: Community, LatOrigin, LongOrigin, modem_id_lookup_path.\n",
    .opts = cmdr_opts,
    .on_arg = cmdr_arg,
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .shutdown = shutdown_,
};

int main(int argc, char **argv)
{
    static cmdr_app s;
    static char *args[256];
    int n = 0;
    for (int i = 0; i < argc && n < 254; i++) {
        args[n++] = argv[i];
        bool send = strcmp(argv[i], "--send") == 0 && i + 1 < argc;
        if (send) args[n++] = argv[++i];
        if (send || strncmp(argv[i], "--send=", 7) == 0) {
            s.send_args = &argv[i + 1];
            while (i + 1 < argc && strncmp(argv[i + 1], "--", 2) != 0) i++, s.n_send_args++;
        }
    }
    args[n] = NULL;
    int rc = kelp_app_run(n, args, &def, &s);
    kelp_dccl_loaded_free(&s.ld);
    return rc ? rc : s.exit_code;
}
