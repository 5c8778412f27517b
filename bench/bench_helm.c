/* Helm per-iteration cost for bench/helm.sh:
 *   bench_helm NBHV ITERS     NBHV = 3 or 10 behaviours, all active every iteration
 * One iteration = kelp_helm_iterate: every behaviour's checks and onRunState (function
 * builds), the IvP solve and the postings. The vehicle moves between iterations. Prints the
 * median wall time per iteration (ns) and the last decision. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/helm.h>
#include <kelp/mission.h>

static const char *B3 =
    "Behavior = BHV_SimpleWaypoint\n{\n name = transit\n pwt = 100\n speed = 2.0\n radius = 8\n ptx = 60\n pty = -40\n}\n"
    "Behavior = BHV_Waypoint\n{\n name = survey\n pwt = 80\n speed = 1.5\n points = 0,-100:100,-100:100,0\n repeat = forever\n}\n"
    "Behavior = BHV_Loiter\n{\n name = loiter\n pwt = 50\n speed = 1.0\n polygon = format=radial, x=50, y=-50, radius=30, pts=8\n}\n";

static const char *B10_EXTRA =
    "Behavior = BHV_SimpleWaypoint\n{\n name = home\n pwt = 30\n speed = 2.0\n ptx = -100\n pty = 100\n ipf_type = reflector\n}\n"
    "Behavior = BHV_Waypoint\n{\n name = survey2\n pwt = 40\n speed = 2.5\n points = -50,-50:-50,50:50,50\n lead = 8\n}\n"
    "Behavior = BHV_Waypoint\n{\n name = survey3\n pwt = 20\n speed = 1.0\n points = format=radial, x=0, y=0, radius=80, pts=12\n}\n"
    "Behavior = BHV_Loiter\n{\n name = loiter2\n pwt = 25\n speed = 2.0\n clockwise = false\n polygon = 10,10:40,10:40,40:10,40\n}\n"
    "Behavior = BHV_ConstantSpeed\n{\n name = cspeed\n pwt = 10\n speed = 1.8\n}\n"
    "Behavior = BHV_ConstantHeading\n{\n name = chead\n pwt = 10\n heading = 45\n}\n"
    "Behavior = BHV_SimpleWaypoint\n{\n name = transit2\n pwt = 60\n speed = 3.0\n ptx = -80\n pty = 30\n}\n";

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

static void sink(const kelp_helm_post *p, void *user)
{
    (void)p;
    (*(unsigned long *)user)++;
}

int main(int argc, char **argv)
{
    if (argc != 3)
        return 2;
    int nb = atoi(argv[1]);
    long n = atol(argv[2]);
    if ((nb != 3 && nb != 10) || n < 1)
        return 2;
    static kelp_helm h;
    static kelp_ivp_piece pool[16384], tmp[4096];
    static double dwork[4096];
    static kelp_ivp_pq_entry pq[8192];
    static unsigned char solve[4 << 20];
    static kelp_mission_node nodes[256];
    static char text[8192];
    unsigned long posts = 0;
    kelp_helm_config cfg;
    kelp_helm_config_default(&cfg);
    cfg.start_engaged = true; /* driving from the start (the default parks, as 24.8) */
    kelp_diag e;
    kelp_diag_clear(&e);
    if (kelp_ivp_domain_parse(&cfg.domain, "course:0:359:360,speed:0:4:21", &e))
        return 1;
    cfg.sink = sink;
    cfg.user = &posts;
    kelp_helm_mem mem = {pool, 16384, tmp, 4096, dwork, 4096, pq, 8192, solve, sizeof solve};
    if (kelp_helm_init(&h, &cfg, &mem))
        return 1;
    snprintf(text, sizeof text, "%s%s", B3, nb == 10 ? B10_EXTRA : "");
    kelp_mission m;
    if (kelp_mission_parse(&m, text, strlen(text), nodes, 256) || kelp_helm_load_bhv(&h, &m) || kelp_helm_configured(&h)) {
        fprintf(stderr, "config: %s\n", kelp_diag_text(&h.diag));
        return 1;
    }
    kelp_helm_start(&h, 0);
    double *t = calloc((size_t)n, sizeof *t);
    for (long i = 0; i < n; i++) {
        double a = (double)i * 0.01;
        kelp_helm_mail_double(&h, "NAV_X", 20 * cos(a));
        kelp_helm_mail_double(&h, "NAV_Y", -20 + 20 * sin(a));
        kelp_helm_mail_double(&h, "NAV_HEADING", 90.0); /* BHV_Loiter needs a heading (24.8: an error without) */
        double t0 = now_ns();
        if (kelp_helm_iterate(&h, 0.25 * (double)(i + 1)))
            return 1;
        t[i] = now_ns() - t0;
        if (h.rep.ofnum != (unsigned)nb) {
            fprintf(stderr, "only %u of %d behaviours active (%s)\n", h.rep.ofnum, nb, h.rep.allstop);
            return 1;
        }
    }
    qsort(t, (size_t)n, sizeof *t, cmp);
    size_t pieces = 0;
    for (unsigned i = 0; i < h.nbhv; i++)
        pieces += h.fn[i].n;
    printf("median_ns %.0f pieces %zu decision %.0f/%.1f\n", t[n / 2], pieces, h.rep.decision[0], h.rep.decision[1]);
    free(t);
    return 0;
}
