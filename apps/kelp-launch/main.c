/* kelp-launch (the pAntler role): start every app of a mission, stop them all together.
 *
 *   kelp-launch [--run-seconds S] [--log-dir DIR] [--report] MISSION.moos
 *
 * Reads ProcessConfig = ANTLER: "Run = prog [@ LaunchConfig] [~ MOOSName]" lines and
 * MSBetweenLaunches. Each app is started as "prog MISSION.moos MOOSName" with its output in
 * DIR/<MOOSName>.log. MOOS program names map to kelp's: MOOSDB is not needed (kelp has no
 * broker: the launcher itself retains the latest value of every variable for late
 * registrants), uXMS -> kelp-scope, uPokeDB -> kelp-poke, pMOOSBridge -> kelp-bridge,
 * iMarineSim -> uSimMarine, pMarineViewer -> kelp-plot.
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
#include <kelp/lcmbus.h>
#include <kelp/mission.h>

#define MAX_APPS 64
#define MAX_VARS 512
#define STOP_GRACE_S 3.0

typedef struct child {
    char prog[128], alias[KELP_MAX_NAME], path[PATH_MAX];
    pid_t pid;
    int status, exited, stopped_by_us;
    double started, ended;
} child;

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

static const char *map_prog(const char *p)
{
    if (strcmp(p, "uXMS") == 0) return "kelp-scope";
    if (strcmp(p, "uPokeDB") == 0) return "kelp-poke";
    if (strcmp(p, "pMOOSBridge") == 0) return "kelp-bridge";
    if (strcmp(p, "pAntler") == 0) return "kelp-launch";
    if (strcmp(p, "iMarineSim") == 0) return "uSimMarine";
    if (strcmp(p, "pMarineViewer") == 0) return "kelp-plot";
    return p;
}

static void trim(char *s)
{
    char *a = s;
    while (*a == ' ' || *a == '\t') a++;
    memmove(s, a, strlen(a) + 1);
    size_t n = strlen(s);
    while (n && (s[n - 1] == ' ' || s[n - 1] == '\t')) s[--n] = 0;
}

static int varcmp(const void *a, const void *b)
{
    return strcmp(((const varstat *)a)->name, ((const varstat *)b)->name);
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
            if (kelp_parse_double(optarg, strlen(optarg), &run_seconds) < 0)
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
    int ant = kelp_mission_block(m, "ProcessConfig", "ANTLER");
    if (ant < 0) {
        fprintf(stderr, "%s: no ProcessConfig = ANTLER block\n", mission);
        return 1;
    }
    double ms_between = 0;
    int ix = kelp_mission_next(m, ant, -1, "MSBetweenLaunches");
    if (ix >= 0 && (kelp_mission_double(&m->nodes[ix], &ms_between) < 0 || ms_between < 0)) {
        fprintf(stderr, "%s:%d: MSBetweenLaunches must be a non-negative number\n", mission, m->nodes[ix].line);
        return 1;
    }
    /* where our sibling programs live */
    char selfdir[PATH_MAX] = ".";
    ssize_t sl = readlink("/proc/self/exe", selfdir, sizeof selfdir - 1);
    if (sl > 0) {
        selfdir[sl] = 0;
        char *d = dirname(selfdir);
        memmove(selfdir, d, strlen(d) + 1);
    }
    static child kids[MAX_APPS];
    int nkids = 0;
    for (int i = kelp_mission_next(m, ant, -1, "Run"); i >= 0; i = kelp_mission_next(m, ant, i, "Run")) {
        char line[1024];
        if (kelp_mission_copy(&m->nodes[i], line, sizeof line) < 0) {
            fprintf(stderr, "%s:%d: Run line too long\n", mission, m->nodes[i].line);
            return 1;
        }
        char *alias = strchr(line, '~');
        if (alias) *alias++ = 0;
        char *cfg = strchr(line, '@');
        if (cfg) *cfg++ = 0;
        trim(line);
        if (!line[0] || strchr(line, ' ')) {
            fprintf(stderr, "%s:%d: Run = prog [@ config] [~ name]: bad program '%s'\n", mission, m->nodes[i].line, line);
            return 1;
        }
        if (alias) trim(alias);
        if (strcmp(line, "MOOSDB") == 0) {
            printf("kelp-launch: %s: MOOSDB is not needed (no broker in kelp); skipped\n", mission);
            continue;
        }
        if (nkids >= MAX_APPS) {
            fprintf(stderr, "%s: more than %d Run lines\n", mission, MAX_APPS);
            return 1;
        }
        if (strlen(line) >= sizeof kids[0].prog || (alias && strlen(alias) >= sizeof kids[0].alias)) {
            fprintf(stderr, "%s:%d: program or name too long\n", mission, m->nodes[i].line);
            return 1;
        }
        child *c = &kids[nkids++];
        snprintf(c->prog, sizeof c->prog, "%.127s", line);
        snprintf(c->alias, sizeof c->alias, "%.63s", alias && *alias ? alias : line);
        const char *real = map_prog(line);
        int pl = snprintf(c->path, sizeof c->path, "%.3000s/%.1000s", selfdir, real);
        if (pl < 0 || access(c->path, X_OK) != 0) snprintf(c->path, sizeof c->path, "%.1000s", real); /* PATH */
    }
    if (nkids == 0) {
        fprintf(stderr, "%s: no Run lines in ProcessConfig = ANTLER\n", mission);
        return 1;
    }
    char community[KELP_MAX_NAME] = "kelp", url[512];
    ix = kelp_mission_next(m, -1, -1, "Community");
    if (ix >= 0 && kelp_mission_copy(&m->nodes[ix], community, sizeof community) < 0) {
        fprintf(stderr, "%s:%d: Community too long\n", mission, m->nodes[ix].line);
        return 1;
    }
    if (kelp_lcm_mission_url(m, url, sizeof url, &ix) < 0) {
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
    if (eps && kelp_parse_double(eps, strlen(eps), &ep) < 0) ep = 0;
    double warp = 1;
    ix = kelp_mission_next(m, -1, -1, "MOOSTimeWarp");
    if (ix >= 0 && kelp_mission_double(&m->nodes[ix], &warp) < 0) warp = 1;

    /* the retainer: answers late registrants, counts writes for the report */
    static retain rt;
    char err[600];
    kelp_lcmbus *lb = kelp_lcmbus_open(url, "kelp-launch", community, on_var, &rt, err, sizeof err);
    if (!lb) {
        fprintf(stderr, "kelp-launch: %s\n", err);
        return 1;
    }
    if (kelp_bus_retain_all(kelp_lcmbus_bus(lb), 0) < 0) return 1;

    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    double t_start = wall();
#define MOOSNOW() (ep + (wall() - ep) * warp)
    for (int k = 0; k < nkids && !g_stop; k++) {
        child *c = &kids[k];
        char logpath[PATH_MAX + KELP_MAX_NAME + 8];
        snprintf(logpath, sizeof logpath, "%s/%s.log", ldir, c->alias);
        pid_t pid = fork();
        if (pid < 0) {
            fprintf(stderr, "kelp-launch: fork: %s\n", strerror(errno));
            g_stop = 1;
            break;
        }
        if (pid == 0) {
            int fd = open(logpath, O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd >= 0) {
                dup2(fd, 1);
                dup2(fd, 2);
                close(fd);
            }
            signal(SIGINT, SIG_DFL);
            signal(SIGTERM, SIG_DFL);
            execlp(c->path, c->path, mission, c->alias, (char *)NULL);
            fprintf(stderr, "kelp-launch: cannot run %s: %s\n", c->path, strerror(errno));
            _exit(127);
        }
        c->pid = pid;
        c->started = wall();
        printf("kelp-launch: started %-16s as %-18s pid %d  log %s\n", c->prog, c->alias, (int)pid, logpath);
        fflush(stdout);
        double until = wall() + ms_between / 1000.0;
        do {
            (void)kelp_lcmbus_handle(lb, 20, MOOSNOW());
        } while (wall() < until && !g_stop);
    }
    int running = nkids;
    double stop_at = 0;
    while (running > 0) {
        (void)kelp_lcmbus_handle(lb, 50, MOOSNOW());
        if (!stop_at && (g_stop || (run_seconds > 0 && wall() - t_start >= run_seconds))) {
            stop_at = wall();
            for (int k = 0; k < nkids; k++)
                if (kids[k].pid > 0 && !kids[k].exited) {
                    kids[k].stopped_by_us = 1;
                    kill(kids[k].pid, SIGTERM);
                }
        }
        if (stop_at && wall() - stop_at > STOP_GRACE_S) {
            for (int k = 0; k < nkids; k++)
                if (kids[k].pid > 0 && !kids[k].exited) kill(kids[k].pid, SIGKILL);
        }
        int st;
        pid_t p;
        while ((p = waitpid(-1, &st, WNOHANG)) > 0) {
            for (int k = 0; k < nkids; k++)
                if (kids[k].pid == p) {
                    kids[k].exited = 1;
                    kids[k].status = st;
                    kids[k].ended = wall();
                    running--;
                    if (!kids[k].stopped_by_us) {
                        printf("kelp-launch: %s exited on its own (%s %d)\n", kids[k].alias,
                               WIFEXITED(st) ? "status" : "signal", WIFEXITED(st) ? WEXITSTATUS(st) : WTERMSIG(st));
                        fflush(stdout);
                    }
                }
        }
    }
    int rc = 0;
    printf("kelp-launch: all %d apps stopped after %.1f s\n", nkids, wall() - t_start);
    for (int k = 0; k < nkids; k++) {
        child *c = &kids[k];
        int st = c->status;
        int clean = (WIFEXITED(st) && WEXITSTATUS(st) == 0) ||
                    (c->stopped_by_us && WIFSIGNALED(st) && WTERMSIG(st) == SIGTERM);
        if (!clean) rc = 1;
        printf("  %-20s %-14s %s %d%s\n", c->alias, c->prog, WIFEXITED(st) ? "exit" : "signal",
               WIFEXITED(st) ? WEXITSTATUS(st) : WTERMSIG(st), clean ? "" : "  <- not clean");
    }
    if (want_report) {
        kelp_bus *bus = kelp_lcmbus_bus(lb);
        qsort(rt.vars, (size_t)rt.nvars, sizeof rt.vars[0], varcmp);
        printf("Variables written in community %s (%d):\n", community, rt.nvars);
        printf("  %-24s %8s  %-18s %s\n", "VarName", "writes", "last source", "last value");
        for (int i = 0; i < rt.nvars; i++) {
            const kelp_var *v = kelp_bus_cached(bus, rt.vars[i].name);
            char val[96] = "?";
            if (v && v->kind == KELP_VAR_DOUBLE) snprintf(val, sizeof val, "%.5g", v->dval);
            else if (v && v->kind == KELP_VAR_STRING) snprintf(val, sizeof val, "\"%.80s\"", v->sval);
            else if (v) snprintf(val, sizeof val, "<%zu bytes>", v->slen);
            printf("  %-24s %8lu  %-18s %s\n", rt.vars[i].name, rt.vars[i].writes, v ? v->source : "?", val);
        }
        const kelp_bus_stats *bs = kelp_bus_get_stats(bus);
        printf("Retained values sent to late registrants: %llu; malformed datagrams: %llu\n",
               (unsigned long long)bs->sync_sent, (unsigned long long)bs->bad);
    }
    kelp_lcmbus_close(lb);
    kelp_mission_free(&mf);
    return rc;
}
