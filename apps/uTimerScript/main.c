/* uTimerScript: a script of timed postings (fixed or random times and values), paused,
 * forwarded and reset from the bus, optionally gated by conditions. The logic is the core
 * kelp_timerscript (include/kelp/timerscript.h); this file wires it to the bus. Random draws are
 * seeded from the pid and the clock unless `seed` is given (a reproducible run). */
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <kelp/app.h>
#include <kelp/timerscript.h>
#include <kelp/util.h>

typedef struct uts {
    kelp_app *app;
    kelp_timerscript_cfg cfg;
    kelp_timerscript core;
    kelp_field_sink sink;
    double seed;
    bool seeded;
} uts;

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    uts *u = ctx;
    int rc = is_string ? kelp_app_notify_string(u->app, var, sval) : kelp_app_notify_double(u->app, var, dval);
    if (rc < 0) kelp_app_run_warning(u->app, "cannot publish %s", var);
}

static void warn(void *ctx, const char *msg) { kelp_app_run_warning(((uts *)ctx)->app, "%s", msg); }

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    uts *u = ctx;
    int rc = kelp_timerscript_cfg_set(&u->cfg, key, val, d);
    if (rc != 0) return rc;
    if (kelp_util_strieq(key, "seed")) {
        if (kelp_util_parse_finite(val, strlen(val), &u->seed) < 0 || u->seed < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "seed must be a whole number >= 0");
        }
        u->seeded = true;
        return 1;
    }
    static const char *const accepted[] = { "AppTick", "CommsTick", "app_logging", "MaxAppTick" };
    for (size_t i = 0; i < sizeof accepted / sizeof accepted[0]; i++)
        if (kelp_util_strieq(key, accepted[i])) return 1;
    if (kelp_util_strieq(key, "rand_pair") || kelp_util_strieq(key, "randpair")) {
        return kelp_fail(d, KELP_ERR_UNSUPPORTED, "rand_pair is not supported by kelp's uTimerScript (use two rand_var lines)");
    }
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    uts *u = st;
    u->app = app;
    u->sink = (kelp_field_sink){ u, publish, warn };
    kelp_timerscript_cfg_default(&u->cfg, kelp_app_name(app), kelp_app_community(app));
    int rc = kelp_app_param_foreach(app, param, u);
    if (rc < 0) return rc;
    if (u->cfg.nev == 0) kelp_app_config_warning(app, "no event: the script posts nothing");
    uint64_t seed = u->seeded ? (uint64_t)u->seed : ((uint64_t)getpid() << 32) ^ (uint64_t)(kelp_app_time(app) * 1e6);
    if (kelp_timerscript_init(&u->core, &u->cfg, seed) < 0) return kelp_app_config_error(app, NULL, "a condition does not parse");
    kelp_timerscript_set_db_start(&u->core, kelp_app_start_time(app)); /* until a DB_UPTIME mail says otherwise */
    const char *s;
    for (unsigned i = 0; (s = kelp_timerscript_subscription(&u->core, i)) != NULL; i++)
        if (kelp_app_register(app, s, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", s);
    kelp_app_event(app, "%u event(s), %u random variable(s), %u condition(s), seed %llu", u->cfg.nev, u->cfg.nrv,
                   u->cfg.ncond, (unsigned long long)seed);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    uts *u = st;
    if (v->kind == KELP_VAR_BINARY) return;
    if (kelp_timerscript_mail(&u->core, v->name, v->kind == KELP_VAR_STRING, v->sval, v->dval, kelp_app_time(app), &u->sink) < 0)
        kelp_app_run_warning(app, "%s: not a usable value; ignored", v->name);
}

static int iterate(kelp_app *app, void *st, double now)
{
    uts *u = st;
    (void)kelp_timerscript_iterate(&u->core, now, &u->sink);
    if (u->core.quit) {
        kelp_app_event(app, "quitting by design (a quit event)");
        kelp_app_quit(app);
    }
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    const uts *u = st;
    const kelp_timerscript *r = &u->core;
    (void)app;
    fprintf(out, "Script %s: %u element(s) (%u posted this pass), %lu reset(s)%s\n", r->cfg.script_name, r->cfg.nev,
            r->posted_local, r->resets, r->cfg.reset_max < 0 ? "" : " (limited)");
    fprintf(out, "  time warp %g  delay start %g  delay reset %g  elapsed %.2f\n", r->warp, r->delay_start, r->delay_reset,
            r->elapsed);
    fprintf(out, "  paused %s  conditions %s  blocked %s\n", r->paused ? "yes" : "no", r->conds_ok ? "ok" : "NOT MET",
            r->blocked_any ? "yes (block_on apps not seen)" : "no");
    for (unsigned i = 0; i < r->cfg.nrv; i++)
        fprintf(out, "  rand_var %-12s %-8s [%g, %g] = %s\n", r->cfg.rv[i].name,
                r->cfg.rv[i].type == KELP_TS_RV_GAUSSIAN ? "gaussian" : "uniform", r->cfg.rv[i].min, r->cfg.rv[i].max,
                r->rv_text[i]);
    if (!u->cfg.verbose) return;
    fprintf(out, "P/Tot  P/Loc  T/Total   T/Local  Variable/Var\n");
    unsigned n = r->nlog < KELP_TS_LOG ? r->nlog : KELP_TS_LOG;
    for (unsigned k = r->nlog - n; k < r->nlog; k++) {
        const kelp_timerscript_logline *l = &r->log[k % KELP_TS_LOG];
        fprintf(out, "%-5lu  %-5u  %-8.2f  %-7.2f  %s\n", l->total, l->local, l->db_time, l->script_time, l->text);
    }
}

static const kelp_app_def def = {
    .name = "uTimerScript",
    .purpose = "Post a script of timed events (fixed or random times and values); pause, forward and reset it from the bus.",
    .params = (const kelp_app_param_info[]){
        { "event", "var=SBR_RANGE_REQUEST, val=\"name=archie\", time=25:35", "repeatable: var, val, time (T or A:B), amt, quit", NULL },
        { "rand_var", "varname=ANG, min=0, max=359, key=at_reset", "repeatable: a $[ANG] macro (type=uniform|gaussian, mu, sigma, snap)", NULL },
        { "randvar", "varname=ANG, min=0, max=359, key=at_reset", "MOOS-IvP 24.8's spelling of rand_var", "rand_var" },
        { "condition", "WIND_GUSTS = true", "repeatable: every condition must hold for the script to run", NULL },
        { "paused", "false", "true: the script starts paused", NULL },
        { "delay_start", "0", "seconds (or A:B) added to each event time on the first pass", NULL },
        { "delay_reset", "0", "seconds (or A:B) added to each event time after a reset", NULL },
        { "reset_max", "nolimit", "resets allowed (nolimit, any, or a whole number)", NULL },
        { "reset_time", "none", "none, all-posted, or script seconds", NULL },
        { "time_warp", "1", "script speed (T or A:B, > 0)", NULL },
        { "time_zero", "script_start", "script_start or db_start", NULL },
        { "shuffle", "true", "draw the random event times again on each reset", NULL },
        { "script_atomic", "false", "true: a started pass completes even if the conditions fail", NULL },
        { "script_name", "unnamed", "name= in the status", NULL },
        { "upon_awake", "n/a", "n/a, reset or restart when the conditions hold again", NULL },
        { "verbose", "true", "list recent postings in the status report", NULL },
        { "block_on", "pGenerateInfo, pPostValues", "apps to wait for (DB_CLIENTS or their <APP>_STATUS)", NULL },
        { "forward_var", "UTS_FORWARD", "variable for fast-forward cues (seconds; 0: to the next event)", NULL },
        { "pause_var", "UTS_PAUSE", "variable for pause cues (true, false, toggle)", NULL },
        { "reset_var", "UTS_RESET", "variable for reset cues (reset or true)", NULL },
        { "status_var", "UTS_STATUS", "variable for the status (silent: none)", NULL },
        { "next_var", "UTS_NEXT", "variable for jump-to-next-event cues", NULL },
        { "seed", "1", "random seed (default: from the pid and the clock)", NULL },
        { "app_logging", "false", "accepted", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "UTS_NEXT", "next", "jump to the next event's time" },
        { "UTS_RESET", "reset", "start the script over (reset or true)" },
        { "UTS_FORWARD", "10", "skip seconds ahead (0: to the next event)" },
        { "UTS_PAUSE", "true", "true, false or toggle" },
        { "DB_UPTIME", "12.5", "origin of $[DBTIME] and of time_zero = db_start" },
        { "DB_CLIENTS", "pGenerateInfo,pPostValues", "block_on apps seen" },
        { "<condition variables>", "NAV_SPEED", "the variables the conditions name" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "<event variables>", "SBR_RANGE_REQUEST=name=archie", "the script's events" },
        { "UTS_STATUS",
          "name=RND_TEST, elapsed_time=2.00, posted=1, pending=4, paused=false, conditions_ok=true, time_warp=3, "
          "delay_start=0, delay_reset=0, shuffle=false, upon_awake=reset, resets=0/4",
          NULL },
        { NULL, NULL, NULL } },
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static uts u;
    return kelp_app_run(argc, argv, &def, &u);
}
