/* The pAntler role: an ANTLER block as a plan, child processes started and reaped. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <kelp/edge/launch.h>
#include <kelp/util.h>

const char *kelp_launch_map_prog(const char *p)
{
    static const char *const map[][2] = { { "uXMS", "kelp-scope" },        { "uPokeDB", "kelp-poke" },
                                          { "pMOOSBridge", "kelp-bridge" }, { "pShare", "kelp-bridge" },
                                          { "pAntler", "kelp-launch" },
                                          { "iMarineSim", "uSimMarine" },   { "pMarineViewer", "kelp-plot" },
                                          { "uSimMarineV22", "uSimMarine" }, { "pMarinePIDV22", "pMarinePID" },
                                          { "iCommander", "kelp-commander" },
                                          { "iModemSim", "kelp-modemsim" }, { "pGeneralCodec", "pAcommsHandler" } };
    for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
        if (strcmp(p, map[i][0]) == 0) return map[i][1];
    return p;
}

/* trim a C string in place */
static void trim(char *s)
{
    const char *a = s;
    size_t n = strlen(s);
    kelp_util_trim(&a, &n);
    memmove(s, a, n);
    s[n] = 0;
}

int kelp_launch_plan_read(kelp_launch_plan *p, const kelp_mission *m, const char *mission, const char *bindir,
                          kelp_diag *d)
{
    memset(p, 0, sizeof *p);
    int ant = kelp_mission_block(m, "ProcessConfig", "ANTLER");
    if (ant < 0) {
        (void)kelp_failf(d, KELP_ERR_PARSE, "%s: no ProcessConfig = ANTLER block", mission);
        return -1;
    }
    int ix = kelp_mission_next(m, ant, -1, "MSBetweenLaunches");
    if (ix >= 0 && (kelp_mission_double(&m->nodes[ix], &p->ms_between) < 0 || !(p->ms_between >= 0) ||
                    p->ms_between > 3.6e6)) {
        (void)kelp_failf(d, KELP_ERR_PARSE, "%s:%d: MSBetweenLaunches must be a number of milliseconds in [0, 3600000]", mission,
                 m->nodes[ix].line);
        return -1;
    }
    for (int i = kelp_mission_next(m, ant, -1, "Run"); i >= 0; i = kelp_mission_next(m, ant, i, "Run")) {
        int line_no = m->nodes[i].line;
        char line[1024];
        if (kelp_mission_copy(&m->nodes[i], line, sizeof line) < 0) {
            (void)kelp_failf(d, KELP_ERR_PARSE, "%s:%d: Run line too long", mission, line_no);
            return -1;
        }
        char *alias = strchr(line, '~');
        if (alias) *alias++ = 0;
        char *cfg = strchr(line, '@');
        if (cfg) *cfg = 0;
        trim(line);
        if (!line[0] || strchr(line, ' ')) {
            (void)kelp_failf(d, KELP_ERR_PARSE, "%s:%d: Run = prog [@ config] [~ name]: bad program '%.100s'", mission, line_no, line);
            return -1;
        }
        if (alias) trim(alias);
        if (strcmp(line, "MOOSDB") == 0) {
            p->skipped_moosdb++;
            continue;
        }
        if (p->nkids >= KELP_LAUNCH_MAX_APPS) {
            (void)kelp_failf(d, KELP_ERR_PARSE, "%s:%d: more than %d Run lines", mission, line_no, KELP_LAUNCH_MAX_APPS);
            return -1;
        }
        kelp_launch_child *c = &p->kids[p->nkids];
        if (strlen(line) >= sizeof c->prog || (alias && *alias ? strlen(alias) : strlen(line)) >= sizeof c->alias ||
            (alias && strpbrk(alias, " \t"))) {
            (void)kelp_failf(d, KELP_ERR_PARSE, "%s:%d: program or name too long, or a name with spaces", mission, line_no);
            return -1;
        }
        p->nkids++;
        /* lengths checked above */
        snprintf(c->prog, sizeof c->prog, "%.127s", line);
        snprintf(c->alias, sizeof c->alias, "%.63s", alias && *alias ? alias : line);
        const char *real = kelp_launch_map_prog(line);
        int pl = snprintf(c->path, sizeof c->path, "%s/%s", bindir ? bindir : ".", real);
        if (pl < 0 || (size_t)pl >= sizeof c->path || access(c->path, X_OK) != 0)
            snprintf(c->path, sizeof c->path, "%.127s", real); /* on PATH */
    }
    if (p->nkids == 0) {
        (void)kelp_failf(d, KELP_ERR_PARSE, "%s: no Run lines in ProcessConfig = ANTLER", mission);
        return -1;
    }
    return 0;
}

int kelp_launch_start(kelp_launch_child *c, const char *mission, const char *logpath, double now)
{
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        int fd = open(logpath, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
        }
        signal(SIGINT, SIG_DFL);
        signal(SIGTERM, SIG_DFL);
        execlp(c->path, c->path, mission, c->alias, (char *)NULL);
        fprintf(stderr, "kelp-launch: cannot run %s: %s\n", c->path, strerror(errno));
        _exit(127);
    }
    c->pid = pid;
    c->started = now;
    return 0;
}

void kelp_launch_signal_all(kelp_launch_plan *p, int sig)
{
    for (int k = 0; k < p->nkids; k++)
        if (p->kids[k].pid > 0 && !p->kids[k].exited) {
            p->kids[k].stopped_by_us = true;
            kill(p->kids[k].pid, sig);
        }
}

int kelp_launch_reap(kelp_launch_plan *p, double now, void (*on_exit)(const kelp_launch_child *c, void *ctx), void *ctx)
{
    int st;
    pid_t pid;
    while ((pid = waitpid(-1, &st, WNOHANG)) > 0)
        for (int k = 0; k < p->nkids; k++)
            if (p->kids[k].pid == pid) {
                p->kids[k].exited = true;
                p->kids[k].status = st;
                p->kids[k].ended = now;
                if (!p->kids[k].stopped_by_us && on_exit) on_exit(&p->kids[k], ctx);
            }
    int running = 0;
    for (int k = 0; k < p->nkids; k++)
        if (p->kids[k].pid > 0 && !p->kids[k].exited) running++;
    return running;
}

bool kelp_launch_clean(const kelp_launch_child *c)
{
    int st = c->status;
    return (WIFEXITED(st) && WEXITSTATUS(st) == 0) || (c->stopped_by_us && WIFSIGNALED(st) && WTERMSIG(st) == SIGTERM);
}
