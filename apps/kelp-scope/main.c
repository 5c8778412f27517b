/* kelp-scope (the uXMS role): a live table of bus variables with source, time and community,
 * one variable's history, and uXMS's key commands. The logic is the core kelp_xms
 * (include/kelp/xms.h); this file reads the command line and the block, feeds it mail and
 * keys, and draws its frames (ncurses on a terminal, plain lines otherwise: kelp/edge/term.h).
 *
 *   kelp-scope mission.moos [VAR ...] [--all] [--history=VAR] [--mode=events|paused|streaming]
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <kelp/app.h>
#include <kelp/edge/term.h>
#include <kelp/util.h>
#include <kelp/xms.h>

#define FRAME_CAP 65536

typedef struct scope {
    kelp_xms core;
    kelp_term term;
    const char *history; /* --history, added after the command line's variables */
    unsigned nsources_registered;
    char frame[FRAME_CAP];
    char cast[FRAME_CAP]; /* the report's copy */
} scope;

enum { OPT_ALL = 300, OPT_ALLL, OPT_HISTORY, OPT_MODE, OPT_SHOW, OPT_FILTER, OPT_SRC, OPT_TRUNC, OPT_TERMINT, OPT_COLOR };

static const kelp_cli_opt opts[] = {
    { "all", no_argument, 'a', NULL, "show every variable on the bus (but *_STATUS, APPCAST)" },
    { "alll", no_argument, OPT_ALLL, NULL, "show every variable on the bus, *_STATUS and APPCAST too" },
    { "novirgins", no_argument, 'g', NULL, "hide variables never written" },
    { "clean", no_argument, 'c', NULL, "ignore the mission block's VAR and DISPLAY_ALL" },
    { "history", required_argument, OPT_HISTORY, "VAR", "the history variable (key z shows its history)" },
    { "mode", required_argument, OPT_MODE, "MODE", "refresh mode: events, paused or streaming" },
    { "show", required_argument, OPT_SHOW, "COLS", "columns to show: source,time,community" },
    { "filter", required_argument, OPT_FILTER, "PREFIX", "show only variables starting with PREFIX (and all of them)" },
    { "src", required_argument, OPT_SRC, "PROC", "also show what process PROC publishes" },
    { "trunc", required_argument, OPT_TRUNC, "N", "cut string values at N characters (10..1000)" },
    { "termint", required_argument, OPT_TERMINT, "SECS", "seconds between frames when streaming (0..10)" },
    { "colormap", required_argument, OPT_COLOR, "PAIRS", "accepted for uXMS compatibility (no colours)" },
    { "paused", no_argument, 'p', NULL, "start paused (as --mode=paused)" },
    { "source", no_argument, 's', NULL, "show the source column (as --show=source)" },
    { "truncate", no_argument, 't', NULL, "cut string values at 25 characters" },
    { NULL, 0, 0, NULL, NULL },
};

static int on_arg(void *st, int val, const char *arg, kelp_diag *dg)
{
    scope *s = st;
    kelp_xms *x = &s->core;
    double d;
    switch (val) {
    case 0:
        if (kelp_xms_add_var(x, arg, false) <= 0) return kelp_fail(dg, KELP_ERR_ARG, "not a variable name");
        return 0;
    case 'a': x->disp_all = true; return 0;
    case OPT_ALLL: x->disp_all = x->disp_all_really = true; return 0;
    case 'g': x->disp_virgins = false; return 0;
    case 'c': x->ignore_file_vars = true; return 0;
    case 'p': x->refresh = KELP_XMS_PAUSED; return 0;
    case 's': x->disp_source = true; return 0;
    case 't': kelp_xms_set_trunc(x, 25); return 0;
    case OPT_SHOW: kelp_xms_set_columns(x, arg); return 0;
    case OPT_FILTER: kelp_xms_set_filter(x, arg); return 0;
    case OPT_COLOR: return 0;
    case OPT_HISTORY:
        if (!arg[0] || strchr(arg, ' ') || strstr(arg, "uXMS")) return kelp_fail(dg, KELP_ERR_ARG, "--history: not a variable name");
        s->history = arg;
        return 0;
    case OPT_MODE:
        if (kelp_xms_set_refresh(x, arg) < 0) return kelp_fail(dg, KELP_ERR_ARG, "--mode: events, paused or streaming");
        return 0;
    case OPT_SRC:
        if (kelp_xms_add_sources(x, arg) < 0) return kelp_fail(dg, KELP_ERR_ARG, "--src: a process name");
        return 0;
    case OPT_TRUNC:
    case OPT_TERMINT:
        if (kelp_util_parse_finite(arg, strlen(arg), &d) < 0 || d < 0) return kelp_fail(dg, KELP_ERR_ARG, "expected a number >= 0");
        if (val == OPT_TRUNC) kelp_xms_set_trunc(x, d > 1000 ? 1000 : (unsigned)d);
        else x->term_interval = d > 10 ? 10 : d;
        return 0;
    default: return kelp_fail(dg, KELP_ERR_ARG, "unknown option");
    }
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    return kelp_xms_config(&((scope *)ctx)->core, key, val, d);
}

static void subscribe(kelp_app *app, scope *s)
{
    const char *v;
    while ((v = kelp_xms_next_subscription(&s->core)) != NULL)
        if (kelp_app_register(app, v, 0) < 0) kelp_app_run_warning(app, "cannot register %s", v);
}

static void draw(kelp_app *app, scope *s)
{
    double now = kelp_app_time(app) - kelp_app_start_time(app);
    size_t n = kelp_app_cast_banner(app, s->frame, sizeof s->frame); /* as AppCasting prints it */
    (void)kelp_xms_render(&s->core, now, s->frame + n, sizeof s->frame - n);
    kelp_term_draw(&s->term, s->frame, "keys: s/t/c columns  v virgins  z history  h help  SPC pause  r stream  e events");
}

static void on_key(kelp_app *app, void *st, int fd)
{
    scope *s = st;
    int keys[64];
    int n = kelp_term_keys(&s->term, fd, keys, 64);
    for (int i = 0; i < n; i++) {
        if (keys[i] == 'q' && s->core.entry_mode == KELP_XMS_KEYS) kelp_app_quit(app);
        else if (keys[i] == KELP_TERM_RESIZE || kelp_xms_key(&s->core, keys[i]) > 0) draw(app, s);
    }
    subscribe(app, s); /* 'A' subscribes to everything */
    for (; s->nsources_registered < s->core.nsources; s->nsources_registered++) /* '+' added sources */
        if (kelp_app_register(app, s->core.sources[s->nsources_registered], 0) < 0)
            kelp_app_run_warning(app, "cannot register %s", s->core.sources[s->nsources_registered]);
}

static int startup(kelp_app *app, void *st)
{
    scope *s = st;
    if (s->history) (void)kelp_xms_add_var(&s->core, s->history, true); /* history mode if alone */
    int rc = kelp_app_param_foreach(app, param, s);
    if (rc < 0) return rc;
    const char *extra = getenv("KELP_SCOPE_VARS");
    if (extra && kelp_xms_add_vars(&s->core, extra) < 0) kelp_app_config_warning(app, "KELP_SCOPE_VARS: a name refused");
    for (; s->nsources_registered < s->core.nsources; s->nsources_registered++)
        if (kelp_app_register(app, s->core.sources[s->nsources_registered], 0) < 0)
            kelp_app_config_warning(app, "cannot register %s", s->core.sources[s->nsources_registered]);
    subscribe(app, s);
    (void)kelp_term_start(&s->term);
    if (kelp_app_watch_fd(app, STDIN_FILENO, on_key) < 0) kelp_app_run_warning(app, "keys cannot be read");
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    scope *s = st;
    if (v->kind == KELP_VAR_BINARY) return;
    (void)kelp_xms_mail(&s->core, v->name, v->kind == KELP_VAR_STRING, v->sval, v->dval, v->source, v->community,
                        v->time - kelp_app_start_time(app));
}

static int iterate(kelp_app *app, void *st, double now)
{
    scope *s = st;
    subscribe(app, s); /* variables a SOURCE publishes, or display-all */
    if (kelp_xms_due(&s->core, now - kelp_app_start_time(app))) draw(app, s);
    return 0;
}

/* the status report and AppCast body: the current frame, as uXMS casts its table */
static void report(kelp_app *app, void *st, FILE *out)
{
    scope *s = st;
    (void)kelp_xms_format(&s->core, kelp_app_time(app) - kelp_app_start_time(app), s->cast, sizeof s->cast);
    fputs(s->cast, out);
    if (s->core.dropped) fprintf(out, "(%lu variables not shown: table full)\n", s->core.dropped);
}

static void shutdown_(kelp_app *app, void *st)
{
    (void)app;
    kelp_term_stop(&((scope *)st)->term);
}

static const kelp_app_def def = {
    .name = "kelp-scope",
    .moos_name = "uXMS",
    .purpose = "Terminal scope of bus variables: value, source, time, community and history (the uXMS role).",
    .synopsis = "Shows bus variables named on the command line, in the block (VAR), published by a\n"
                "SOURCE, or all of them (--all, DISPLAY_ALL), refreshed in place on a terminal. Keys as\n"
                "uXMS: s/t/c source, time, community columns; v virgins; z history of HISTORY_VAR;\n"
                "j its name; p processes; - hide a process's variables, + add it as a source (type\n"
                "its ID, Enter); h help; d scoping; SPC/u refresh and pause; r streaming; e events;\n"
                "/ filter (Enter ends), ? clear it; A all variables, a back; < > history length;\n"
                "{ } ` value truncation; w wrap; q quits.",
    .opts = opts,
    .args = "[VAR ...]",
    .on_arg = on_arg,
    .params = (const kelp_app_param_info[]){
        { "VAR", "NAV_X, NAV_Y", "repeatable: variables to show, comma-separated", NULL },
        { "HISTORY_VAR", "NAV_X", "the variable whose history key z shows", NULL },
        { "SOURCE", "pHelmIvP", "show what these processes publish (their <PROC>_STATUS Publishing)", NULL },
        { "REFRESH_MODE", "events", "events, paused or streaming", NULL },
        { "CONTENT_MODE", "scoping", "scoping, history, procs or help", NULL },
        { "PAUSED", "false", "deprecated: REFRESH_MODE = paused", "REFRESH_MODE" },
        { "DISPLAY_SOURCE", "false", "show the source column", NULL },
        { "DISPLAY_AUX_SOURCE", "false", "as DISPLAY_SOURCE (kelp has no auxiliary source)", NULL },
        { "DISPLAY_TIME", "false", "show the time column", NULL },
        { "DISPLAY_COMMUNITY", "false", "show the community column", NULL },
        { "DISPLAY_VIRGINS", "true", "show variables never written", NULL },
        { "DISPLAY_HISTORY_VAR", "true", "show the variable's name in history mode", NULL },
        { "DISPLAY_ALL", "false", "show every variable on the bus", NULL },
        { "DISPLAY_ALLL", "false", "show every variable, *_STATUS and APPCAST too", NULL },
        { "TRUNC_DATA", "false", "cut long string values (at 20 characters, more for hidden columns)", NULL },
        { "WRAP_DATA", "false", "wrap long values", NULL },
        { "WRAP_DATA_LEN", "45", "wrap width, 10..120", NULL },
        { "TERM_REPORT_INTERVAL", "0.5", "seconds between frames at most (0..10)", NULL },
        { "COLOR_MAP", "NAV_X,red", "accepted (kelp draws no colours)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "<VAR>", "any value", "every variable shown" },
        { "<SOURCE>_STATUS", "Publishing=\"A,B\"", "what a SOURCE publishes" },
        { NULL, NULL, NULL } },
    .notes = "Environment: KELP_SCOPE_VARS, more variables to show (as VAR).\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown_,
};

int main(int argc, char **argv)
{
    static scope s;
    kelp_xms_init(&s.core);
    return kelp_app_run(argc, argv, &def, &s);
}
