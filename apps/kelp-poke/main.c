/* kelp-poke (the uPokeDB role): write one or more variables to a community and show each
 * before and after the poke.
 *
 *   kelp-poke MISSION.moos VAR=value [VAR=value ...]
 *
 * A value that parses as a number is posted as a double, anything else as a string;
 * VAR:=value forces a string (so "VAR:=12" posts the string "12"). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/edge/cli.h>
#include <kelp/lcmbus.h>
#include <kelp/edge/mission.h>

#define MAX_POKES 64
#define SYNC_WAIT_S 0.6   /* wall seconds to collect current values before poking */
#define ECHO_WAIT_S 2.0   /* wall seconds to see our own writes come back */

typedef struct poke {
    char name[KELP_MAX_NAME];
    char value[KELP_MAX_SVAL + 1];
    int is_string;
    double d;
} poke;

typedef struct seen {
    int n;
    poke *pokes;
    kelp_var before[MAX_POKES], after[MAX_POKES];
    int have_before[MAX_POKES], have_after[MAX_POKES];
    int phase; /* 0 = before, 1 = after */
    char app[KELP_MAX_NAME];
} seen;

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void on_var(const kelp_var *v, void *user)
{
    seen *s = user;
    for (int i = 0; i < s->n; i++) {
        if (strcmp(v->name, s->pokes[i].name) != 0) continue;
        if (s->phase == 0) {
            s->before[i] = *v;
            s->have_before[i] = 1;
        } else if (strcmp(v->source, s->app) == 0) {
            s->after[i] = *v;
            s->have_after[i] = 1;
        }
    }
}

static void show(const kelp_var *v, int have, const char *name, double t0)
{
    if (!have) {
        printf("  %-16s\n", name);
        return;
    }
    char val[64];
    if (v->kind == KELP_VAR_DOUBLE) snprintf(val, sizeof val, "%.5f", v->dval);
    printf("  %-16s %-14s %-10.2f %s%s%s\n", v->name, v->source, v->time - t0,
           v->kind == KELP_VAR_STRING ? "\"" : "", v->kind == KELP_VAR_DOUBLE ? val : v->sval,
           v->kind == KELP_VAR_STRING ? "\"" : "");
}

int main(int argc, char **argv)
{
    static const kelp_cli cli = {
        .name = "kelp-poke",
        .purpose = "Write variables to the mission's community (the uPokeDB role) and show each before and\n"
                   "after. Numbers post as doubles, other values as strings; VAR:=value forces a string.",
        .synopsis = "MISSION.moos VAR=value [VAR=value ...]",
        .in_order = true,
    };
    int c, status;
    while ((c = kelp_cli_next(&cli, argc, argv, &status)) != -1)
        if (c == KELP_CLI_EXIT) return status;
    argc -= optind - 1; /* from here argv[1] is the mission, argv[2..] the pokes */
    argv += optind - 1;
    if (argc < 3) {
        kelp_cli_usage(&cli, stderr);
        return kelp_cli_error(&cli, argc < 2 ? "no mission file" : "nothing to poke");
    }
    static kelp_mission_file mf;
    if (kelp_mission_load(&mf, argv[1]) < 0) {
        fprintf(stderr, "%s\n", mf.error);
        return 1;
    }
    static poke pokes[MAX_POKES];
    int n = 0;
    for (int i = 2; i < argc; i++) {
        if (n >= MAX_POKES) {
            fprintf(stderr, "kelp-poke: at most %d pokes\n", MAX_POKES);
            return 2;
        }
        const char *a = argv[i];
        const char *eq = strchr(a, '=');
        if (!eq || eq == a) {
            fprintf(stderr, "kelp-poke: '%s' is not VAR=value\n", a);
            return 2;
        }
        poke *p = &pokes[n];
        size_t nl = (size_t)(eq - a);
        if (eq[-1] == ':') {
            p->is_string = 1;
            nl--;
        }
        if (nl == 0 || nl >= sizeof p->name || strlen(eq + 1) >= sizeof p->value) {
            fprintf(stderr, "kelp-poke: '%s': name or value too long\n", a);
            return 2;
        }
        memcpy(p->name, a, nl);
        p->name[nl] = 0;
        memcpy(p->value, eq + 1, strlen(eq + 1) + 1);
        if (!p->is_string && kelp_util_parse_double(p->value, strlen(p->value), &p->d) < 0) p->is_string = 1;
        n++;
    }
    char community[KELP_MAX_NAME] = "kelp", url[512];
    int gi = kelp_mission_next(&mf.m, -1, -1, "Community");
    if (gi >= 0 && kelp_mission_copy(&mf.m.nodes[gi], community, sizeof community) < 0) return 1;
    double warp = 1;
    gi = kelp_mission_next(&mf.m, -1, -1, "MOOSTimeWarp");
    if (gi >= 0 && kelp_mission_double(&mf.m.nodes[gi], &warp) < 0) warp = 1;
    const char *ep = getenv("KELP_WARP_EPOCH");
    double epoch = 0;
    if (ep && kelp_util_parse_double(ep, strlen(ep), &epoch) < 0) epoch = 0;
    if (kelp_lcmbus_mission_url(&mf.m, url, sizeof url, &gi) < 0) {
        fprintf(stderr, "%s:%d: bad LCM_URL or ServerPort\n", argv[1], gi);
        return 1;
    }
    static seen s;
    s.n = n;
    s.pokes = pokes;
    snprintf(s.app, sizeof s.app, "kelp-poke");
    kelp_diag err = {0};
    kelp_lcmbus *lb = kelp_lcmbus_open(url, "kelp-poke", community, on_var, &s, &err);
    if (!lb) {
        fprintf(stderr, "kelp-poke: %s\n", kelp_diag_text(&err));
        return 1;
    }
    kelp_bus *bus = kelp_lcmbus_bus(lb);
#define MOOSNOW() (epoch + (wall() - epoch) * warp)
    double t0 = MOOSNOW();
    for (int i = 0; i < n; i++) {
        if (kelp_bus_register(bus, pokes[i].name, 0, MOOSNOW()) < 0) {
            fprintf(stderr, "kelp-poke: cannot register %s\n", pokes[i].name);
            return 1;
        }
    }
    double until = wall() + SYNC_WAIT_S;
    while (wall() < until) KELP_IGNORE(kelp_lcmbus_handle(lb, 50, MOOSNOW()));
    printf("PRIOR to Poking the community %s\n", community);
    printf("  %-16s %-14s %-10s %s\n  %-16s %-14s %-10s %s\n", "VarName", "(S)ource", "(T)ime", "VarValue", "-------",
           "-------", "------", "--------");
    for (int i = 0; i < n; i++) show(&s.before[i], s.have_before[i], pokes[i].name, t0);
    s.phase = 1;
    int rc = 0;
    for (int i = 0; i < n; i++) {
        int r = pokes[i].is_string ? kelp_bus_notify_string(bus, pokes[i].name, pokes[i].value, MOOSNOW())
                                   : kelp_bus_notify_double(bus, pokes[i].name, pokes[i].d, MOOSNOW());
        if (r < 0) {
            fprintf(stderr, "kelp-poke: publish %s failed: %s\n", pokes[i].name, kelp_err_str(r));
            rc = 1;
        }
    }
    until = wall() + ECHO_WAIT_S;
    for (;;) {
        int all = 1;
        for (int i = 0; i < n; i++) all &= s.have_after[i];
        if (all || wall() > until) break;
        KELP_IGNORE(kelp_lcmbus_handle(lb, 50, MOOSNOW()));
    }
    printf("\nAFTER Poking the community %s\n", community);
    printf("  %-16s %-14s %-10s %s\n  %-16s %-14s %-10s %s\n", "VarName", "(S)ource", "(T)ime", "VarValue", "-------",
           "-------", "------", "--------");
    for (int i = 0; i < n; i++) {
        show(&s.after[i], s.have_after[i], pokes[i].name, t0);
        if (!s.have_after[i]) {
            fprintf(stderr, "kelp-poke: %s was not seen on the bus after the poke\n", pokes[i].name);
            rc = 1;
        }
    }
    kelp_lcmbus_close(lb);
    kelp_mission_free(&mf);
    return rc;
}
