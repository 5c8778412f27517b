/* uFldScope: a live table of vehicles by scoped report field (ufield.md 7). The logic is the
 * core kelp_field_ufs (include/kelp/field.h); this file reads the block, feeds it mail and
 * key presses, and draws the table.
 *
 * On a terminal the table is redrawn in place with ncurses and keys act at once (the
 * runner's status report is held back until exit, where it is printed as usual). Otherwise
 * each table is printed as plain lines, and keys may still be written to stdin (a pipe or
 * FIFO), one character each. */
#include <stdio.h>
#include <unistd.h>
#include <kelp/edge/app.h>
#include <kelp/edge/term.h>
#include <kelp/field.h>

#define SCOPE_TEXT_CAP 16384 /* bytes of one rendered table */

typedef struct scope {
    kelp_app *app;
    kelp_field_ufs_cfg cfg;
    kelp_field_ufs core;
    kelp_term term;
    char text[SCOPE_TEXT_CAP];
} scope;

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    return kelp_field_ufs_config(&((scope *)ctx)->cfg, key, val, d);
}

static void draw(scope *s)
{
    (void)kelp_field_ufs_render(&s->core, s->text, sizeof s->text);
    kelp_term_draw(&s->term, s->text, "keys: l layouts  a all/last  p pause  r resume  h help  (Ctrl-C quits)");
}

static void on_key(kelp_app *app, void *st, int fd)
{
    scope *s = st;
    int keys[64];
    (void)app;
    int n = kelp_term_keys(&s->term, fd, keys, 64);
    for (int i = 0; i < n; i++)
        if (keys[i] == KELP_TERM_RESIZE || kelp_field_ufs_key(&s->core, keys[i]) > 0) draw(s);
}

static int startup(kelp_app *app, void *st)
{
    scope *s = st;
    s->app = app;
    int rc = kelp_app_param_foreach(app, param, s);
    if (rc < 0) return rc;
    kelp_field_ufs_init(&s->core, &s->cfg);
    if (s->core.unmatched)
        kelp_app_config_warning(app, "LAYOUT: %u name(s) match no SCOPE alias or field (first: %s)", s->core.unmatched,
                                s->core.first_unmatched);
    if (!s->cfg.nelem) kelp_app_config_warning(app, "no SCOPE entries: the table has no columns");
    const char *v;
    for (unsigned i = 0; (v = kelp_field_ufs_subscription(&s->core, i)) != NULL; i++)
        if (kelp_app_register(app, v, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", v);
    (void)kelp_term_start(&s->term);
    if (kelp_app_watch_fd(app, STDIN_FILENO, on_key) < 0) kelp_app_run_warning(app, "keys cannot be read");
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    scope *s = st;
    if (kelp_field_ufs_mail(&s->core, v->name, v->kind == KELP_VAR_STRING, v->sval) < 0)
        kelp_app_run_warning(app, "%s: not a key=value report (what could be read was used)", v->name);
}

static int iterate(kelp_app *app, void *st, double now)
{
    scope *s = st;
    (void)app, (void)now;
    if (kelp_field_ufs_due(&s->core)) draw(s);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    scope *s = st;
    (void)app;
    /* the APPCAST carries the table, as 24.8's (a MOOS user reads it with uMAC) */
    (void)kelp_field_ufs_table(&s->core, s->text, sizeof s->text);
    fputs(s->text, out);
}

static void shutdown_(kelp_app *app, void *st)
{
    (void)app;
    kelp_term_stop(&((scope *)st)->term);
}

static const kelp_app_def def = {
    .name = "uFldScope",
    .purpose = "A live table of vehicles by fields of their key=value reports (NODE_REPORT and others).",
    .synopsis = "Typically run in a shoreside community. Takes user-chosen fields of incoming\n"
                "comma-separated key=value reports and shows them in a table: one row per vehicle,\n"
                "one column per scoped field. Keys: l/L cycle layouts, a/A all columns or the last\n"
                "layout, p/P/space pause (again: refresh once), r/R resume, h/H help.",
    .params = (const kelp_app_param_info[]){
        { "SCOPE", "var=NODE_REPORT,key=vname,fld=MODE",
          "var=<VAR>,key=<name key>,fld=<field>[,alias=<header>] one column (repeatable; key default name/vname)", NULL },
        { "LAYOUT", "MODE, speed, Time", "a set of columns by alias (repeatable; the last LAYOUT is layout 1)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "<SCOPE var>", "NAME=alpha,MODE=LOITERING,TIME=2651922526.73", "each distinct var of the SCOPE entries" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){ { NULL, NULL, NULL } },
    .notes = "Output: the table on the terminal (ncurses), or as plain lines when stdout is not a terminal.\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown_,
};

int main(int argc, char **argv)
{
    static scope s;
    return kelp_app_run(argc, argv, &def, &s);
}
