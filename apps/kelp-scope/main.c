/* kelp-scope (the uXMS role): a terminal table of variables with source, time and
 * community. Configuration (ProcessConfig = uXMS, or the alias it runs under):
 *   VAR = NAME[,NAME...]   (repeatable; wildcards * and ? allowed)
 *   PAUSED, DISPLAY_SOURCE, DISPLAY_TIME, DISPLAY_COMMUNITY = true/false
 *   DISPLAY_ALL = true     (scope every variable)
 * Extra variable names may follow the mission file on the command line as VAR=NAME. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/app.h>

#define MAX_ROWS 256

typedef struct row {
    char name[KELP_MAX_NAME];
    int seen;
    kelp_var v;
    unsigned long writes;
} row;

typedef struct scope {
    row rows[MAX_ROWS];
    int nrows;
    char patterns[64][KELP_MAX_NAME];
    int npat;
    bool paused, src, tim, com, all;
    unsigned long updates;
} scope;

static row *find_row(scope *s, const char *name, bool create)
{
    for (int i = 0; i < s->nrows; i++)
        if (strcmp(s->rows[i].name, name) == 0) return &s->rows[i];
    if (!create || s->nrows >= MAX_ROWS) return NULL;
    row *r = &s->rows[s->nrows++];
    memset(r, 0, sizeof *r);
    snprintf(r->name, sizeof r->name, "%s", name);
    return r;
}

static int add_vars(kelp_app *app, scope *s, const char *list)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", list);
    for (char *save = NULL, *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        while (*t == ' ') t++;
        char *e = t + strlen(t);
        while (e > t && e[-1] == ' ') *--e = 0;
        if (!*t) continue;
        if (strchr(t, '*') || strchr(t, '?')) {
            if (s->npat < 64) snprintf(s->patterns[s->npat++], KELP_MAX_NAME, "%s", t);
        } else {
            find_row(s, t, true);
        }
        if (kelp_app_register(app, t, 0) < 0) kelp_app_config_warning(app, "cannot register %s", t);
    }
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    scope *s = st;
    s->src = s->tim = s->com = true;
    (void)kelp_app_param_bool(app, "PAUSED", &s->paused);
    (void)kelp_app_param_bool(app, "DISPLAY_SOURCE", &s->src);
    (void)kelp_app_param_bool(app, "DISPLAY_TIME", &s->tim);
    (void)kelp_app_param_bool(app, "DISPLAY_COMMUNITY", &s->com);
    (void)kelp_app_param_bool(app, "DISPLAY_ALL", &s->all);
    char buf[1024];
    for (const kelp_mission_node *n = kelp_app_param_next(app, "VAR", NULL); n; n = kelp_app_param_next(app, "VAR", n)) {
        if (kelp_mission_copy(n, buf, sizeof buf) == 0) add_vars(app, s, buf);
    }
    const char *extra = getenv("KELP_SCOPE_VARS");
    if (extra) add_vars(app, s, extra);
    if (s->all) add_vars(app, s, "*");
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    scope *s = st;
    (void)app;
    row *r = find_row(s, v->name, false);
    if (!r) {
        for (int i = 0; i < s->npat && !r; i++)
            if (kelp_bus_match(s->patterns[i], v->name)) r = find_row(s, v->name, true);
    }
    if (!r) return;
    r->seen = 1;
    r->writes++;
    memcpy(&r->v, v, offsetof(kelp_var, sval));
    memcpy(r->v.sval, v->sval, v->slen + 1);
}

static int iterate(kelp_app *app, void *st, double now)
{
    (void)app;
    (void)now;
    scope *s = st;
    if (!s->paused) s->updates++;
    return 0;
}

static void fmt_value(const kelp_var *v, char *buf, size_t cap)
{
    if (v->kind == KELP_VAR_DOUBLE) {
        if (v->dval == (double)(long long)v->dval && v->dval < 1e15 && v->dval > -1e15)
            snprintf(buf, cap, "%lld", (long long)v->dval);
        else
            snprintf(buf, cap, "%.5f", v->dval);
    } else if (v->kind == KELP_VAR_STRING) {
        snprintf(buf, cap, "\"%s\"", v->sval);
    } else {
        snprintf(buf, cap, "<binary %zu bytes>", v->slen);
    }
}

static void report(kelp_app *app, void *st, FILE *out)
{
    scope *s = st;
    double t0 = kelp_app_start_time(app);
    fprintf(out, "  %-22s", "VarName");
    if (s->src) fprintf(out, " %-16s", "(S)ource");
    if (s->tim) fprintf(out, " %-9s", "(T)ime");
    if (s->com) fprintf(out, " %-12s", "(C)ommunity");
    fprintf(out, " VarValue\n");
    fprintf(out, "  %-22s", "-------");
    if (s->src) fprintf(out, " %-16s", "-------");
    if (s->tim) fprintf(out, " %-9s", "-------");
    if (s->com) fprintf(out, " %-12s", "-------");
    fprintf(out, " -------- (%lu)\n", s->updates);
    for (int i = 0; i < s->nrows; i++) {
        const row *r = &s->rows[i];
        char val[KELP_MAX_SVAL + 32];
        char tbuf[32];
        if (r->seen) {
            fmt_value(&r->v, val, sizeof val);
            snprintf(tbuf, sizeof tbuf, "%.2f", r->v.time - t0);
        }
        fprintf(out, "  %-22s", r->name);
        if (s->src) fprintf(out, " %-16s", r->seen ? r->v.source : "n/a");
        if (s->tim) fprintf(out, " %-9s", r->seen ? tbuf : "n/a");
        if (s->com) fprintf(out, " %-12s", r->seen ? r->v.community : "n/a");
        fprintf(out, " %s\n", r->seen ? val : "n/a");
    }
}

static const kelp_app_def def = {
    .name = "kelp-scope",
    .moos_name = "uXMS",
    .purpose = "Terminal scope of bus variables: value, source, time and community (the uXMS role).",
    .params = (const kelp_app_param_info[]){
        { "VAR", "APPLES", "repeatable: a variable (or pattern, *_HZ) to show", NULL },
        { "PAUSED", "false", "start paused", NULL },
        { "DISPLAY_SOURCE", "true", "show the source column", NULL },
        { "DISPLAY_TIME", "true", "show the time column", NULL },
        { "DISPLAY_COMMUNITY", "true", "show the community column", NULL },
        { "DISPLAY_ALL", "false", "show every variable on the bus", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "<VAR>", "any value", "every VAR named or matched" },
        { NULL, NULL, NULL } },
    .notes = "Environment: KELP_SCOPE_VARS, more variables to show (as VAR).\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static scope s;
    return kelp_app_run(argc, argv, &def, &s);
}
