/* Helm iteration cost with spawned avoidance behaviours, for bench/helm_spawn.sh:
 *   bench_helm_spawn NSPAWN ITERS    NSPAWN avoidance instances (1..KELP_HELM_MAX_SPAWNED)
 * A BHV_AvoidCollision template spawns one instance per contact from CONTACT_INFO alerts (as
 * the contact manager posts them); a BHV_Waypoint runs beside them. Contacts sit on a ring 60
 * to 160 m around the area ownship circles in, report at 1 Hz (the helm runs at 4 Hz), and
 * all instances are active every iteration. Prints the median wall time per iteration (ns),
 * the median build (all behaviours' functions) and solve times (us) the helm measured, the
 * pieces and the last decision. bench/helm_spawn.sh compiles the helm with room for 50
 * spawned instances (-DKELP_HELM_MAX_SPAWNED). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/helm.h>
#include <kelp/mission.h>

static const char *BHV =
    "Behavior = BHV_Waypoint\n{\n name = survey\n pwt = 100\n speed = 1.5\n points = 0,-100:100,-100:100,0\n"
    " repeat = forever\n}\n"
    "Behavior = BHV_AvoidCollision\n{\n name = avd_\n pwt = 200\n updates = CONTACT_INFO\n templating = spawn\n"
    " contact = to-be-set\n on_no_contact_ok = true\n extrapolate = true\n decay = 30,60\n pwt_outer_dist = 200\n"
    " pwt_inner_dist = 50\n completed_dist = 250\n min_util_cpa_dist = 10\n max_util_cpa_dist = 40\n}\n";

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static double cpu(void *user)
{
    (void)user;
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void sink(const kelp_helm_post *p, void *user)
{
    (void)p;
    (*(unsigned long *)user)++;
}

#define POOL 65536

int main(int argc, char **argv)
{
    if (argc != 3)
        return 2;
    int ns = atoi(argv[1]);
    long n = atol(argv[2]);
    if (ns < 1 || ns > KELP_HELM_MAX_SPAWNED || n < 1)
        return 2;
    static kelp_helm h;
    static kelp_ivp_piece pool[POOL], tmp[4096];
    static double dwork[4096];
    static kelp_ivp_pq_entry pq[POOL];
    static unsigned char solve[8 << 20];
    static kelp_mission_node nodes[256];
    static char text[4096];
    unsigned long posts = 0;
    kelp_helm_config cfg;
    kelp_helm_config_default(&cfg);
    cfg.start_engaged = true; /* driving from the start (the default parks, as 24.8) */
    kelp_diag e;
    kelp_diag_clear(&e);
    if (kelp_ivp_domain_parse(&cfg.domain, "course:0:359:360,speed:0:4:21", &e))
        return 1;
    snprintf(cfg.us, sizeof cfg.us, "alder");
    cfg.sink = sink;
    cfg.user = &posts;
    cfg.cpu_clock = cpu;
    kelp_helm_mem mem = {pool, POOL, tmp, 4096, dwork, 4096, pq, POOL, solve, sizeof solve};
    if (kelp_helm_init(&h, &cfg, &mem))
        return 1;
    snprintf(text, sizeof text, "%s", BHV);
    kelp_mission m;
    if (kelp_mission_parse(&m, text, strlen(text), nodes, 256) || kelp_helm_load_bhv(&h, &m) || kelp_helm_configured(&h)) {
        fprintf(stderr, "config: %s\n", kelp_diag_text(&h.diag));
        return 1;
    }
    kelp_helm_start(&h, 0);
    double *t = calloc((size_t)n, sizeof *t), *tc = calloc((size_t)n, sizeof *tc), *ts = calloc((size_t)n, sizeof *ts);
    for (long i = 0; i < n; i++) {
        double now = 0.25 * (double)(i + 1), a = (double)i * 0.01;
        kelp_helm_mail_double(&h, "NAV_X", 20 * cos(a));
        kelp_helm_mail_double(&h, "NAV_Y", -20 + 20 * sin(a));
        kelp_helm_mail_double(&h, "NAV_HEADING", fmod(90 + a * 57.29577951308232, 360));
        kelp_helm_mail_double(&h, "NAV_SPEED", 1.5);
        if (i % 4 == 0) /* 1 Hz contact reports */
            for (int c = 0; c < ns; c++) {
                double r = 60 + 100.0 * c / (ns > 1 ? ns - 1 : 1), b = 6.283185307179586 * c / ns;
                char rep[192];
                snprintf(rep, sizeof rep, "NAME=c%02d,TYPE=kayak,TIME=%.2f,X=%.1f,Y=%.1f,SPD=1.5,HDG=%.0f", c, now,
                         r * sin(b), -20 + r * cos(b), fmod(180 + b * 57.29577951308232, 360));
                kelp_helm_mail_string(&h, "NODE_REPORT", rep);
                if (i == 0) {
                    snprintf(rep, sizeof rep, "name=c%02d # contact=c%02d", c, c);
                    kelp_helm_mail_string(&h, "CONTACT_INFO", rep);
                }
            }
        double t0 = now_ns();
        if (kelp_helm_iterate(&h, now))
            return 1;
        t[i] = now_ns() - t0;
        tc[i] = h.rep.create_time * 1e9;
        ts[i] = h.rep.solve_time * 1e9;
        if (h.rep.ofnum != (unsigned)ns + 1) {
            fprintf(stderr, "only %u of %d functions (%s)\n", h.rep.ofnum, ns + 1, h.rep.allstop);
            return 1;
        }
    }
    qsort(t, (size_t)n, sizeof *t, cmp);
    qsort(tc, (size_t)n, sizeof *tc, cmp);
    qsort(ts, (size_t)n, sizeof *ts, cmp);
    size_t pieces = 0;
    for (unsigned i = 0; i < h.nbhv; i++)
        pieces += h.fn[i].n;
    printf("median_ns %.0f build_us %.0f solve_us %.0f pieces %zu decision %.0f/%.1f\n", t[n / 2], tc[n / 2] / 1000,
           ts[n / 2] / 1000, pieces, h.rep.decision[0], h.rep.decision[1]);
    free(t);
    free(tc);
    free(ts);
    return 0;
}
