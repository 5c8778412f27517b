/* pHelmIvP: the IvP helm. Reads "Behaviors = file.bhv" and "Domain = name:low:high:points"
 * lines, publishes the behaviour files' initialize values, registers for every variable the
 * behaviours need, and each iteration runs the behaviours, solves with kelp's IvP solver and
 * posts DESIRED_HEADING / DESIRED_SPEED / DESIRED_DEPTH (zeros on all-stop) plus the helm
 * summary. The logic is in src/helm (core); this file wires it to the app runner. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <kelp/edge/app.h>
#include <kelp/helm.h>
#include <kelp/edge/mission.h>

#define MAX_BHV_FILES 8
#define MAX_HOLDS 16
#define POOL_PIECES 32768   /* pieces of all functions of one iteration */
#define TMP_PIECES 8192     /* scratch pieces (one-variable ZAIC builds) */
#define PQ_ENTRIES 8192     /* Reflector work */

typedef struct helm_app {
    kelp_app *app;
    kelp_helm *h;
    kelp_helm_mem mem;
    char files[MAX_BHV_FILES][512];
    unsigned nfiles;
    unsigned long posts, iterations;
    char last_summary[512];
    char hold[MAX_HOLDS][KELP_MAX_NAME];
    unsigned nhold, held;
    bool started;
} helm_app;

static void sink(const kelp_helm_post *p, void *user)
{
    helm_app *a = user;
    /* a behaviour's posting carries "<iteration>:<behaviour>" as its source aux (24.8's
     * Notify(var, value, aux): pLogger writes pHelmIvP:12:survey) */
    int rc = kelp_app_notify_aux(a->app, p->var, p->is_str, p->sval, p->dval, p->aux);
    if (rc < 0) kelp_app_run_warning(a->app, "publish of %s failed", p->var);
    else a->posts++;
    if (p->is_str && !strcmp(p->var, "IVPHELM_SUMMARY"))
        snprintf(a->last_summary, sizeof a->last_summary, "%s", p->sval);
    if (p->is_str && !p->retract && (!strcmp(p->var, "BHV_WARNING") || !strcmp(p->var, "BHV_ERROR")))
        kelp_app_run_warning(a->app, "%s: %s", p->var, p->sval);
}

static void resolve(kelp_app *app, const char *file, char *out, size_t cap)
{
    snprintf(out, cap, "%s", file);
    if (file[0] == '/' || access(file, R_OK) == 0) return;
    const char *mp = kelp_app_mission_path(app);
    const char *slash = mp ? strrchr(mp, '/') : NULL;
    if (slash) snprintf(out, cap, "%.*s/%s", (int)(slash - mp), mp, file);
}

/* the process's CPU time, for IVPHELM_CREATE_CPU / IVPHELM_LOOP_CPU */
static double cpu_seconds(void *user)
{
    (void)user;
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return 0;
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* register for the variables the behaviours came to need, each announced in IVPHELM_REGISTER */
static void register_new(kelp_app *app, helm_app *a, bool starting)
{
    for (const char *v; (v = kelp_helm_next_new_var(a->h)) != NULL;) {
        /* at start-up each is announced (24.8's registerVariables); at run time the helm itself
         * announces the behaviours' new information variables (registerNewVariables) */
        if (kelp_app_register(app, v, 0) == 0) {
            if (starting) KELP_IGNORE(kelp_app_notify_string(app, "IVPHELM_REGISTER", v));
        } else if (starting) kelp_app_config_warning(app, "cannot register for %s", v);
        else kelp_app_run_warning(app, "cannot register for %s", v);
    }
}

/* the block's `key` lines (at most cap, else a configuration error), to be read last first */
static int lines(kelp_app *app, const char *key, const kelp_mission_node **out, int cap)
{
    int n = 0;
    for (const kelp_mission_node *l = NULL; (l = kelp_app_param_next(app, key, l)) != NULL;) {
        if (n == cap) return kelp_app_config_error(app, l, "more than %d %s lines", cap, key);
        out[n++] = l;
    }
    return n;
}

static int startup(kelp_app *app, void *st)
{
    helm_app *a = st;
    a->app = app;
    kelp_helm_config cfg;
    kelp_helm_config_default(&cfg);
    snprintf(cfg.us, sizeof cfg.us, "%s", kelp_app_community(app));
    cfg.sink = sink;
    cfg.user = a;
    cfg.cpu_clock = cpu_seconds;
    kelp_diag dd = {0};
    char buf[256];
    /* MOOS's GetConfiguration hands a block's lines to the app last line first, and 24.8's
     * helm adds its domain variables in that order: "domain = course..." then "domain =
     * speed..." is the domain speed:course (IVPHELM_DOMAIN, the summary, DESIRED_SPEED posted
     * before DESIRED_HEADING) */
    const kelp_mission_node *dl[KELP_IVP_MAX_DIM];
    int ndl = lines(app, "Domain", dl, KELP_IVP_MAX_DIM);
    if (ndl < 0) return -1;
    while (ndl > 0) {
        const kelp_mission_node *n = dl[--ndl];
        if (kelp_mission_copy(n, buf, sizeof buf) != 0 || kelp_helm_config_add_domain(&cfg, buf, &dd) < 0)
            return kelp_app_config_error(app, n, "Domain '%.*s': %s", (int)n->vlen, n->val,
                                         dd.code != KELP_OK ? kelp_diag_text(&dd) : "too long");
    }
    if (cfg.domain.dim == 0)
        return kelp_app_config_error(app, NULL, "ProcessConfig = %s needs Domain = name:low:high:points lines",
                                     kelp_app_name(app));
    /* start_engaged (MOOS-IvP today) and start_in_drive (the seed's): the later line wins */
    const kelp_mission_node *se = kelp_app_param(app, "start_engaged"), *sd = kelp_app_param(app, "start_in_drive");
    const char *sk = se && (!sd || se->line > sd->line) ? "start_engaged" : "start_in_drive";
    if (kelp_app_param_bool(app, sk, &cfg.start_engaged) < 0 || kelp_app_param_bool(app, "allow_park", &cfg.allow_park) < 0 ||
        kelp_app_param_bool(app, "park_on_allstop", &cfg.park_on_allstop) < 0 ||
        kelp_app_param_str(app, "other_override_var", cfg.other_override, sizeof cfg.other_override) < 0)
        return -1;
    a->nhold = 0;
    if (kelp_app_param_str(app, "hold_on_apps", buf, sizeof buf) > 0)
        for (char *sv, *t = strtok_r(buf, ", \t", &sv); t && a->nhold < MAX_HOLDS; t = strtok_r(NULL, ", \t", &sv)) {
            snprintf(a->hold[a->nhold], sizeof a->hold[0], "%.*s_STATUS", KELP_MAX_NAME - 8, t);
            for (char *c = a->hold[a->nhold]; *c; c++) *c = (char)toupper((unsigned char)*c);
            if (kelp_app_register(app, a->hold[a->nhold++], 0) < 0) return -1;
        }
    static const char *const ignored[] = {"Verbose", "ok_skew", "IVP_BEHAVIOR_DIR", "IVP_BEHAVIOR_DIRS", "node_skew",
                                          "goals_mandatory", "bhv_dir_not_found_ok", "app_logging", NULL};
    for (int i = 0; ignored[i]; i++)
        for (const kelp_mission_node *n = NULL; (n = kelp_app_param_next(app, ignored[i], n)) != NULL;)
            kelp_app_event(app, "%s is accepted for MOOS compatibility and ignored", ignored[i]);

    a->h = calloc(1, sizeof *a->h);
    a->mem.pool_cap = POOL_PIECES;
    a->mem.tmp_cap = TMP_PIECES;
    a->mem.pq_cap = PQ_ENTRIES;
    a->mem.dwork_cap = TMP_PIECES;
    for (unsigned d = 0; d < cfg.domain.dim; d++)
        if (cfg.domain.var[d].points > a->mem.dwork_cap) {
            a->mem.dwork_cap = cfg.domain.var[d].points;
            a->mem.tmp_cap = cfg.domain.var[d].points * 2u;
        }
    a->mem.pool = calloc(a->mem.pool_cap, sizeof *a->mem.pool);
    a->mem.tmp = calloc(a->mem.tmp_cap, sizeof *a->mem.tmp);
    a->mem.dwork = calloc(a->mem.dwork_cap, sizeof *a->mem.dwork);
    a->mem.pq = calloc(a->mem.pq_cap, sizeof *a->mem.pq);
    a->mem.solve_work_size = (size_t)POOL_PIECES * 160u + (size_t)KELP_HELM_MAX_BHVS * 4096u + 65536u;
    a->mem.solve_work = calloc(1, a->mem.solve_work_size);
    if (!a->h || !a->mem.pool || !a->mem.tmp || !a->mem.dwork || !a->mem.pq || !a->mem.solve_work)
        return kelp_app_config_error(app, NULL, "out of memory");
    if (kelp_helm_init(a->h, &cfg, &a->mem) < 0)
        return kelp_app_config_error(app, NULL, "helm init failed");

    /* the Behaviors lines last first, as 24.8's helm reads its block (the Domain lines above) */
    const kelp_mission_node *bl[MAX_BHV_FILES];
    int nbl = lines(app, "Behaviors", bl, MAX_BHV_FILES);
    if (nbl < 0) return -1;
    while (nbl > 0) {
        const kelp_mission_node *n = bl[--nbl];
        char file[256];
        if (a->nfiles >= MAX_BHV_FILES || kelp_mission_copy(n, file, sizeof file) != 0)
            return kelp_app_config_error(app, n, "too many or too long Behaviors lines");
        resolve(app, file, a->files[a->nfiles], sizeof a->files[0]);
        kelp_mission_file mf;
        int rc = kelp_mission_load(&mf, a->files[a->nfiles]);
        if (rc < 0)
            return kelp_app_config_error(app, n, "behaviour file: %s", mf.error);
        rc = kelp_helm_load_bhv(a->h, &mf.m);
        if (rc < 0) {
            fprintf(stderr, "%s:%d: %s\n", a->files[a->nfiles], a->h->diag.line, kelp_diag_text(&a->h->diag));
            KELP_IGNORE(kelp_app_config_error(app, n, "%s:%d: %s", a->files[a->nfiles], a->h->diag.line, kelp_diag_text(&a->h->diag)));
            kelp_mission_free(&mf);
            return -1;
        }
        kelp_mission_free(&mf);
        a->nfiles++;
        /* HelmIvP::requestBehaviorLogging: ask the logger to keep a copy of each behaviour file */
        KELP_IGNORE(kelp_app_notify_stringf(app, "PLOGGER_CMD", "COPY_FILE_REQUEST = %s", file));
    }
    if (a->nfiles == 0)
        return kelp_app_config_error(app, NULL, "ProcessConfig = %s needs a Behaviors = file.bhv line", kelp_app_name(app));
    if (kelp_helm_configured(a->h) < 0) {
        const char *f = a->files[0];
        return kelp_app_config_error(app, NULL, "%s:%d: %s", f, a->h->diag.line, kelp_diag_text(&a->h->diag));
    }
    printf("The IvP Helm (pHelmIvP) is starting...\nNumber of behavior files: %u\n", a->nfiles);
    for (unsigned i = 0; i < a->h->nbhv; i++)
        printf("  Behavior %s (%s)\n", a->h->bhv[i].name, a->h->bhv[i].type);
    if (a->nhold == 0) kelp_helm_start(a->h, kelp_app_time(app)), a->started = true;
    register_new(app, a, true);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    helm_app *a = st;
    for (unsigned i = 0; i < a->nhold; i++) /* hold_on_apps: start once each has reported */
        if (!strcmp(v->name, a->hold[i])) a->held |= 1u << i;
    if (!a->started && a->held == (1u << a->nhold) - 1) {
        kelp_helm_start(a->h, kelp_app_time(app));
        a->started = true;
        kelp_app_event(app, "hold_on_apps: every app reported, the helm starts");
    }
    if (v->kind == KELP_VAR_DOUBLE)
        kelp_helm_mail_double(a->h, v->name, v->dval);
    else if (v->kind == KELP_VAR_STRING)
        kelp_helm_mail_string(a->h, v->name, v->sval);
}

static int iterate(kelp_app *app, void *st, double now)
{
    helm_app *a = st;
    if (!a->started) return 0; /* waiting for hold_on_apps */
    a->iterations++;
    if (kelp_helm_iterate(a->h, now) < 0)
        kelp_app_run_warning(app, "helm iteration failed");
    register_new(app, a, false);
    KELP_IGNORE(kelp_app_notify_double(app, "IVPHELM_CPU", kelp_app_cpu_load(app)));
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    helm_app *a = st;
    const kelp_helm *h = a->h;
    (void)app;
    if (!h) return;
    fprintf(out, "Helm: %s   iteration %lu   functions %u   allstop %s\n", h->engaged ? "DRIVE" : "PARK",
            h->rep.iteration, h->rep.ofnum, h->rep.allstop);
    for (unsigned d = 0; d < h->cfg.domain.dim; d++)
        if (h->rep.decided[d])
            fprintf(out, "  decision %s = %.2f\n", h->cfg.domain.var[d].name, h->rep.decision[d]);
    for (unsigned i = 0; i < h->nbhv; i++)
        fprintf(out, "  %-24s %-20s %s\n", h->bhv[i].name, h->bhv[i].type, kelp_helm_bhv_state_name(h->bhv[i].state));
    fprintf(out, "  posts %lu   BHV_WARNING %lu   BHV_ERROR %lu   buffer drops %lu   post drops %lu\n", a->posts,
            h->rep.warnings, h->rep.errors, h->ib.dropped, h->posts_dropped);
    fprintf(out, "  BHV_IPF %lu   too long for one value %lu\n", h->ipf_posted, h->ipf_oversize);
}

static void shutdown_app(kelp_app *app, void *st)
{
    helm_app *a = st;
    (void)app;
    free(a->mem.pool), free(a->mem.tmp), free(a->mem.dwork), free(a->mem.pq), free(a->mem.solve_work);
    free(a->h);
    a->h = NULL;
}

static const kelp_app_def def = {
    .name = "pHelmIvP", .pid_var = "PHELMIVP_PID",
    .purpose = "The IvP helm: runs the behaviours of a .bhv file and posts DESIRED_HEADING/SPEED/DEPTH.",
    .synopsis = "The IvP helm: runs the behaviours of the Behaviors files, solves their objective\n"
                "functions over the Domain at each iteration and posts the decision as DESIRED_<var>.\n"
                "It subscribes to whatever its behaviours name (conditions, UPDATES, NOSTARVE,\n"
                "duration_reset, initialize variables, NAV_X/NAV_Y ...).",
    .params = (const kelp_app_param_info[]){
        { "Behaviors", "alder.bhv", "required, repeatable: a behaviour file (relative to the mission)", NULL },
        { "Domain", "course:0:359:360", "required, repeatable: name:low:high:points[:optional]", NULL },
        { "Domain", "speed:0:4:21", NULL, NULL },
        { "start_in_drive", "false", "true: DRIVE from the start; false: PARK until MOOS_MANUAL_OVERRIDE=false", NULL },
        { "start_engaged", "false", "MOOS-IvP's newer name of start_in_drive (the later line wins)", NULL },
        { "allow_park", "true", "false: an override cannot park the helm once engaged", NULL },
        { "park_on_allstop", "false", "true: park on an all-stop", NULL },
        { "other_override_var", "AUTONOMY_OVERRIDE", "a variable read like MOOS_MANUAL_OVERRIDE", NULL },
        { "hold_on_apps", "pContactMgrV20", "start only once these apps have posted <APP>_STATUS", NULL },
        { "node_skew", "charlie,45", "accepted, ignored (kelp does not check skew)", NULL },
        { "goals_mandatory", "true", "accepted: without a function the helm is in all-stop anyway", NULL },
        { "bhv_dir_not_found_ok", "true", "accepted, ignored (behaviours are built in)", NULL },
        { "app_logging", "false", "accepted, ignored (record the bus with lcm-logger)", NULL },
        { "Verbose", "false", "accepted for MOOS, ignored", NULL },
        { "ok_skew", "any", "accepted for MOOS, ignored", NULL },
        { "IVP_BEHAVIOR_DIR", "/path", "accepted for MOOS, ignored", NULL },
        { "IVP_BEHAVIOR_DIRS", "/path", "accepted for MOOS, ignored", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "MOOS_MANUAL_OVERIDE", "false", "true: all stop (PARK); false: DRIVE" },
        { "MOOS_MANUAL_OVERRIDE", "false", "same, correctly spelt" },
        { "IVPHELM_REJOURNAL", "true", "the next IVPHELM_SUMMARY whole" },
        { "NAV_X", "112.3", "and every variable the behaviours use" },
        { "NAV_Y", "-99.1", NULL },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "DESIRED_HEADING", "118.8", "each decision variable of the Domain (DESIRED_<VAR>; zero on all-stop)" },
        { "DESIRED_SPEED", "2.0", NULL },
        { "IVPHELM_STATE", "DRIVE", "DRIVE or PARK" },
        { "IVPHELM_ALLSTOP", "clear", "every iteration: or NothingToDo, BehaviorError, ManualOverride, MissingDecVars:x" },
        { "IVPHELM_SUMMARY", "iter=12,utc_time=17514261063.25,var=speed:1.2,var=course:195,"
          "active_bhvs=loiter$17514261051.50$100.00000$9$0.00000$n/a$1$$", "each decision, as 24.8's HelmReport:"
          " iter and utc_time, then the fields that changed (all of them the first time and after IVPHELM_REJOURNAL)" },
        { "IVPHELM_ITER", "12", NULL },
        { "IVPHELM_IPF_CNT", "1", NULL },
        { "IVPHELM_TOTAL_PCS_FORMED", "1240", "every iteration; also IVPHELM_TOTAL_PCS_CACHED (0: kelp caches none)" },
        { "IVPHELM_BHV_ACTIVE", "loiter", "also IVPHELM_BHV_RUNNING and IVPHELM_BHV_IDLE" },
        { "IVPHELM_BHV_CNT", "3", "on change; also IVPHELM_BHV_CNT_EVER, IVPHELM_BHV_ACTIVE_CNT,"
          " IVPHELM_BHV_RUNNING_CNT, IVPHELM_BHV_IDLE_CNT, IVPHELM_BHV_DISABLED_CNT" },
        { "IVPHELM_CREATE_CPU", "0.0012", "CPU seconds building the objective functions; also IVPHELM_LOOP_CPU" },
        { "IVPHELM_DOMAIN", "course,0,359,360:speed,0,4,21", NULL },
        { "IVPHELM_MODESET", "MODE#---,ACTIVE#---,INACTIVE#ACTIVE,SURVEYING#ACTIVE,RETURNING",
          "at start, when the behaviour file declares modes" },
        { "IVPHELM_LIFE_EVENT", "iter=0,time=10.96, bname=loiter, btype=BHV_Loiter, event=spawn, seed=helm_startup,iter=1",
          "by the first decision; also event=spawn/abort/death of template instances; IVPHELM_COMPLETED_COUNT" },
        { "BCM_ALERT_REQUEST", "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],alert_range=200, "
          "cpa_range=500", "at start, from BHV_AvoidCollision templates (templating = spawn)" },
        { "IVPHELM_UPDATEVARS", "UP_LOITER", "the variables behaviour updates and mode declarations listen to" },
        { "IVPHELM_STATEVARS", "DEPLOY,RETURN", "the variables the conditions read" },
        { "BHV_WARNING", "loiter: no points", "also BHV_ERROR, BHV_CONFIG_WARNING (a faulty update); a waypoint"
          " behaviour posts its no-points retraction once (24.8)" },
        { "BHV_SETTINGS", "type=BHV_Waypoint,name=survey,points=pts={0,0:50,-20},speed=1.2,...", "after configuration"
          " and each applied update (waypoint, loiter)" },
        { "BHV_STATUS", "name=survey,state=active,updates=0/0", "per behaviour, when it changes" },
        { "IVPHELM_UPDATE_RESULT", "bhv=survey,var=WPT_UPDATE,time=12.25,result=success,val=speed=2",
          "each update read: success, param_error, duplicate or name_mismatch" },
        { "IVPHELM_REGISTER", "NAV_X", "each variable the helm registers for: at start, then the behaviours'"
          " information variables at the first decision and when a behaviour is spawned" },
        { "IVPHELM_CPU", "1.25", "the helm's CPU load (percent of one core)" },
        { "IVPHELM_LEDGER_SUMMARY", "now:2, reps:31, who:ben,cal", "every iteration once NAV_X/NAV_Y are known" },
        { "IVPHELM_COMPLETED_PENDING", "false", "on change: true in the iteration a behaviour completes" },
        { "IVPHELM_COMPLETED_COUNT", "1", "on change: behaviours completed in this iteration" },
        { "TURN_RATE", "1.5", "in DRIVE: mean heading change per iteration over the last 5 s (deg, starboard +)" },
        { "MOOS_DEBUG", "pHelmIvP AllStop: clear", "with each IVPHELM_ALLSTOP (MOOS's debug channel)" },
        { "PLOGGER_CMD", "COPY_FILE_REQUEST = alder.bhv", "at start, one per Behaviors file" },
        { "BHV_IPF", "H,14,12:waypt_survey,2,36,1,100,D,course;0;359;360:speed;0;4;21,G,359,20,F,0,9,...",
          "each iteration, per behaviour with a function: MOOS-IvP's IPF string (pMarineViewer's function"
          " view); one longer than a bus value is counted in the report, not posted" },
        { "WPT_ODO", "42.5", "BHV_Waypoint: metres travelled on the current leg (+ post_suffix)" },
        { "WPT_EFF_SUMM_LEG", "vname=abe, bhv_name=survey, linear_dist=42.1, odo_dist=43.8, efficiency_dist=0.961, ...",
          "BHV_Waypoint with efficiency_measure = all, at each point after the first: the leg's and (WPT_EFF_SUMM_ALL)"
          " the run's distances and times; WPT_EFF_DIST_LEG/_ALL, WPT_EFF_TIME_LEG/_ALL their ratios (+ post_suffix)" },
        { "VIEW_POINT", "x=10,y=20,label=alpha", "behaviour postings: VIEW_SEGLIST, VIEW_POLYGON, WPT_STAT,"
          " WPT_INDEX, CYCLE_INDEX (on change), LOITER_INDEX, LOITER_ACQUIRE, LOITER_REPORT, the variables"
          " wpt_index_var / cycle_index_var name, flags" },
        { "DIST_TO_STATION", "12.4", "BHV_StationKeep each run; also PSKEEP_MODE (HIBERNATING, SEEKING_STATION),"
          " its radii as VIEW_POLYGON" },
        { NULL, NULL, NULL } },
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown_app,
};

int main(int argc, char **argv)
{
    static helm_app a;
    return kelp_app_run(argc, argv, &def, &a);
}
