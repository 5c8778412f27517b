/* kelp-launch (the pAntler role): start every app of a mission, stop them all together.
 *
 *   kelp-launch [--run-seconds S] [--log-dir DIR] [--report] MISSION.moos
 *
 * Reads ProcessConfig = ANTLER: "Run = prog [@ LaunchConfig] [~ MOOSName]" lines and
 * MSBetweenLaunches. Each app is started as "prog MISSION.moos MOOSName" with its output in
 * DIR/<MOOSName>.log. MOOS program names map to kelp's: MOOSDB is not needed (kelp has no
 * broker: the launcher itself retains the latest value of every variable for late
 * registrants), uXMS -> kelp-scope, uPokeDB -> kelp-poke, pMOOSBridge -> kelp-bridge,
 * iMarineSim -> uSimMarine, pMarineViewer -> kelp-plot, iCommander -> kelp-commander,
 * iModemSim -> kelp-modemsim, pGeneralCodec -> pAcommsHandler (encode/decode only).
 * Waits for all apps to exit, or stops them (SIGTERM, then SIGKILL after 3 s) on SIGINT,
 * SIGTERM or when --run-seconds have passed. Exit status 0 when every app ended cleanly. */
#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <kelp/edge/cli.h>
#include <kelp/edge/launch.h>
#include <kelp/lcmbus.h>
#include <kelp/edge/mission.h>

#define MAX_VARS 512
#define STOP_GRACE_S 10.0 /* a loaded machine (CI) can take more than 3 s to end a fleet of apps */

typedef struct varstat {
    char name[KELP_MAX_NAME];
    unsigned long writes;
} varstat;

static volatile sig_atomic_t g_stop;
static void on_signal(int s) { (void)s; g_stop = 1; }

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

typedef struct retain {
    varstat vars[MAX_VARS];
    int nvars;
} retain;

static void on_var(const kelp_var *v, void *user)
{
    retain *r = user;
    for (int i = 0; i < r->nvars; i++)
        if (strcmp(r->vars[i].name, v->name) == 0) {
            r->vars[i].writes++;
            return;
        }
    if (r->nvars < MAX_VARS) {
        snprintf(r->vars[r->nvars].name, KELP_MAX_NAME, "%s", v->name);
        r->vars[r->nvars++].writes = 1;
    }
}

static int varcmp(const void *a, const void *b)
{
    return strcmp(((const varstat *)a)->name, ((const varstat *)b)->name);
}

typedef struct launcher {
    kelp_launch_plan *plan;
    kelp_lcmbus *lb;
    double ep, warp, t_start, run_seconds, stop_at;
} launcher;

static double moos_now(const launcher *L) { return L->ep + (wall() - L->ep) * L->warp; }

/* the stop request: a signal, or --run-seconds passed */
static bool stop_due(const launcher *L)
{
    return g_stop || (L->run_seconds > 0 && wall() - L->t_start >= L->run_seconds);
}

/* start the apps in order, serving the bus during MSBetweenLaunches; a stop request at any
 * moment ends the start-up (the apps not started yet are never started) */
static void start_all(launcher *L, const char *mission, const char *ldir)
{
    for (int k = 0; k < L->plan->nkids && !stop_due(L); k++) {
        kelp_launch_child *c = &L->plan->kids[k];
        char logpath[PATH_MAX + KELP_MAX_NAME + 8];
        snprintf(logpath, sizeof logpath, "%s/%s.log", ldir, c->alias);
        if (kelp_launch_start(c, mission, logpath, wall()) < 0) {
            fprintf(stderr, "kelp-launch: fork: %s\n", strerror(errno));
            g_stop = 1;
            break;
        }
        printf("kelp-launch: started %-16s as %-18s pid %d  log %s\n", c->prog, c->alias, (int)c->pid, logpath);
        fflush(stdout);
        double until = wall() + L->plan->ms_between / 1000.0;
        do {
            KELP_IGNORE(kelp_lcmbus_handle(L->lb, 20, moos_now(L)));
        } while (wall() < until && !stop_due(L));
    }
}

static void on_own_exit(const kelp_launch_child *c, void *ctx)
{
    (void)ctx;
    printf("kelp-launch: %s exited on its own (%s %d)\n", c->alias, WIFEXITED(c->status) ? "status" : "signal",
           WIFEXITED(c->status) ? WEXITSTATUS(c->status) : WTERMSIG(c->status));
    fflush(stdout);
}

/* serve the bus until every started app has ended; on a stop request SIGTERM, then SIGKILL
 * after STOP_GRACE_S */
static void supervise(launcher *L)
{
    while (kelp_launch_reap(L->plan, wall(), on_own_exit, NULL) > 0) {
        KELP_IGNORE(kelp_lcmbus_handle(L->lb, 50, moos_now(L)));
        if (!L->stop_at && stop_due(L)) {
            L->stop_at = wall();
            kelp_launch_signal_all(L->plan, SIGTERM);
        }
        if (L->stop_at && wall() - L->stop_at > STOP_GRACE_S) kelp_launch_signal_all(L->plan, SIGKILL);
    }
}

static int summary(const kelp_launch_plan *plan, double t_start)
{
    int rc = 0, started = 0;
    for (int k = 0; k < plan->nkids; k++) started += plan->kids[k].pid > 0;
    printf("kelp-launch: all %d apps stopped after %.1f s%s\n", started, wall() - t_start,
           started < plan->nkids ? " (start-up was interrupted)" : "");
    for (int k = 0; k < plan->nkids; k++) {
        const kelp_launch_child *c = &plan->kids[k];
        if (c->pid <= 0) continue;
        int st = c->status;
        bool clean = kelp_launch_clean(c);
        if (!clean) rc = 1;
        printf("  %-20s %-14s %s %d%s\n", c->alias, c->prog, WIFEXITED(st) ? "exit" : "signal",
               WIFEXITED(st) ? WEXITSTATUS(st) : WTERMSIG(st), clean ? "" : "  <- not clean");
    }
    return rc;
}

static void print_report(retain *rt, kelp_bus *bus, const char *community)
{
    qsort(rt->vars, (size_t)rt->nvars, sizeof rt->vars[0], varcmp);
    printf("Variables written in community %s (%d):\n", community, rt->nvars);
    printf("  %-24s %8s  %-18s %s\n", "VarName", "writes", "last source", "last value");
    for (int i = 0; i < rt->nvars; i++) {
        const kelp_var *v = kelp_bus_cached(bus, rt->vars[i].name);
        char val[96] = "?";
        if (v && v->kind == KELP_VAR_DOUBLE) snprintf(val, sizeof val, "%.5g", v->dval);
        else if (v && v->kind == KELP_VAR_STRING) snprintf(val, sizeof val, "\"%.80s\"", v->sval);
        else if (v) snprintf(val, sizeof val, "<%zu bytes>", v->slen);
        printf("  %-24s %8lu  %-18s %s\n", rt->vars[i].name, rt->vars[i].writes, v ? v->source : "?", val);
    }
    const kelp_bus_stats *bs = kelp_bus_get_stats(bus);
    printf("Retained values sent to late registrants: %llu; malformed datagrams: %llu\n",
           (unsigned long long)bs->sync_sent, (unsigned long long)bs->bad);
}

int main(int argc, char **argv)
{
    double run_seconds = 0;
    const char *mission = NULL, *logdir = NULL;
    int want_report = 0;
    const kelp_cli cli = {
        .name = "kelp-launch",
        .purpose = "Start every 'Run = prog @ config ~ name' of ProcessConfig = ANTLER (the pAntler role) and\n"
                   "stop them all on exit, on SIGINT/SIGTERM or after --run-seconds.",
        .synopsis = "[--run-seconds=S] [--log-dir=DIR] [--report] MISSION.moos",
        .opts = (const kelp_cli_opt[]){
            { "run-seconds", required_argument, 's', "S", "stop everything after S seconds (default: never)" },
            { "log-dir", required_argument, 'd', "DIR", "app output goes to DIR/<name>.log (default ./kelp-logs)" },
            { "report", no_argument, 'r', NULL,
              "at the end, print every variable written on the bus: writes, last value, source" },
            { NULL, 0, 0, NULL, NULL } },
    };
    int opt, status;
    while ((opt = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        switch (opt) {
        case KELP_CLI_EXIT: return status;
        case 's':
            if (kelp_util_parse_double(optarg, strlen(optarg), &run_seconds) < 0)
                return kelp_cli_error(&cli, "bad --run-seconds '%s'", optarg);
            break;
        case 'd': logdir = optarg; break;
        case 'r': want_report = 1; break;
        }
    }
    if (optind < argc) mission = argv[optind++];
    if (optind < argc) return kelp_cli_error(&cli, "one mission at a time ('%s')", argv[optind]);
    if (!mission) {
        kelp_cli_usage(&cli, stderr);
        return kelp_cli_error(&cli, "no mission file");
    }
    static kelp_mission_file mf;
    if (kelp_mission_load(&mf, mission) < 0) {
        fprintf(stderr, "%s\n", mf.error);
        return 1;
    }
    const kelp_mission *m = &mf.m;
    /* where our sibling programs live */
    char selfdir[PATH_MAX] = ".";
    kelp_diag err = {0};
    ssize_t sl = readlink("/proc/self/exe", selfdir, sizeof selfdir - 1);
    if (sl > 0) {
        selfdir[sl] = 0;
        char *d = dirname(selfdir);
        memmove(selfdir, d, strlen(d) + 1);
    }
    static kelp_launch_plan plan;
    if (kelp_launch_plan_read(&plan, m, mission, selfdir, &err) < 0) {
        fprintf(stderr, "%s\n", kelp_diag_text(&err));
        return 1;
    }
    if (plan.skipped_moosdb) printf("kelp-launch: %s: MOOSDB is not needed (no broker in kelp); skipped\n", mission);
    char community[KELP_MAX_NAME] = "kelp", url[512];
    int ix = kelp_mission_next(m, -1, -1, "Community");
    if (ix >= 0 && kelp_mission_copy(&m->nodes[ix], community, sizeof community) < 0) {
        fprintf(stderr, "%s:%d: Community too long\n", mission, m->nodes[ix].line);
        return 1;
    }
    if (kelp_lcmbus_mission_url(m, url, sizeof url, &ix) < 0) {
        fprintf(stderr, "%s:%d: bad LCM_URL or ServerPort\n", mission, ix);
        return 1;
    }
    char ldir[PATH_MAX];
    snprintf(ldir, sizeof ldir, "%s", logdir ? logdir : "kelp-logs");
    mkdir(ldir, 0755);
    /* MOOS time is wall time times MOOSTimeWarp for every process (as MOOS does), so apps,
     * pokes from outside and other communities agree without coordination. A caller may
     * set KELP_WARP_EPOCH to warp relative to a chosen instant instead; it is passed on. */
    double ep = 0;
    const char *eps = getenv("KELP_WARP_EPOCH");
    if (eps && kelp_util_parse_double(eps, strlen(eps), &ep) < 0) ep = 0;
    double warp = 1;
    ix = kelp_mission_next(m, -1, -1, "MOOSTimeWarp");
    if (ix >= 0 && kelp_mission_double(&m->nodes[ix], &warp) < 0) warp = 1;

    /* the retainer: answers late registrants, counts writes for the report */
    static retain rt;
    kelp_lcmbus *lb = kelp_lcmbus_open(url, "kelp-launch", community, on_var, &rt, &err);
    if (!lb) {
        fprintf(stderr, "kelp-launch: %s\n", kelp_diag_text(&err));
        return 1;
    }
    if (kelp_bus_retain_all(kelp_lcmbus_bus(lb), 0) < 0) return 1;

    kelp_cli_on_stop(on_signal);
    double t_start = wall();
    launcher L = { &plan, lb, ep, warp, t_start, run_seconds, 0 };
    start_all(&L, mission, ldir);
    supervise(&L);
    int rc = summary(&plan, t_start);
    if (want_report) print_report(&rt, kelp_lcmbus_bus(lb), community);
    kelp_lcmbus_close(lb);
    kelp_mission_free(&mf);
    return rc;
}
