/* The pContactMgrV20 app benchmark's feeder (bench/contactmgr_app.sh):
 *   bench_cmgr_feed N SECONDS
 * Ownship NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED at 4 Hz and N contacts scattered over a
 * 1400 m disk, each posting a NODE_REPORT once per second (spread over the second), on the
 * community "abe" for SECONDS. It listens to CONTACTS_LIST and counts the names in the last
 * one (the list is cut at the bus limit of 4 KB, so at most a few hundred names).
 * Prints: "feed N <n> sent <s> listed <k>". */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/bus.h>
#include <kelp/lcmbus.h>
#include <kelp/util.h>

#define PI 3.14159265358979323846

static unsigned long listed;

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void on_var(const kelp_var *v, void *user)
{
    (void)user;
    if (strcmp(v->name, "CONTACTS_LIST") != 0 || v->kind != KELP_VAR_STRING) return;
    listed = v->sval[0] ? 1 : 0;
    for (const char *p = v->sval; *p; p++) listed += *p == ',';
}

int main(int argc, char **argv)
{
    if (argc < 3) { fprintf(stderr, "usage: bench_cmgr_feed N SECONDS\n"); return 2; }
    long n = 0;
    double secs = 0;
    if (kelp_util_parse_long(argv[1], strlen(argv[1]), &n) != 0 || kelp_util_parse_double(argv[2], strlen(argv[2]), &secs) != 0 ||
        n < 1 || n > 5000 || !(secs > 0))
        return 2;
    char url[512];
    kelp_diag err = {0};
    if (kelp_lcmbus_url(NULL, url, sizeof url) < 0) return 1;
    kelp_lcmbus *lb = kelp_lcmbus_open(url, "bench_cmgr_feed", "abe", on_var, NULL, &err);
    if (!lb) { fprintf(stderr, "%s\n", kelp_diag_text(&err)); return 1; }
    kelp_bus *bus = kelp_lcmbus_bus(lb);
    if (kelp_bus_register(bus, "CONTACTS_LIST", 0, 0) < 0) return 1;
    double *pos = malloc(sizeof(double) * (size_t)n * 3);
    if (!pos) return 1;
    uint64_t rng = 88172645463325252ull;
    for (long i = 0; i < n; i++) {
        rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
        double r = 1400 * sqrt((double)(rng % 1000000) / 1e6), a = (double)((rng >> 20) % 3600) / 10.0 * PI / 180;
        pos[3 * i] = r * sin(a), pos[3 * i + 1] = r * cos(a), pos[3 * i + 2] = (double)((rng >> 40) % 360);
    }
    double t0 = floor(wall()) + 1;
    unsigned long sent = 0;
    char rpt[256];
    int quarters = (int)(secs * 4 + 0.5);
    long per_q = (n + 3) / 4;
    for (int q = 0; q < quarters; q++) {
        double qt = t0 + q * 0.25;
        for (double now; (now = wall()) < qt;) (void)kelp_lcmbus_handle(lb, (int)((qt - now) * 1000) > 0 ? 1 : 0, now);
        if (kelp_bus_notify_double(bus, "NAV_X", 0.5 * (qt - t0), qt) < 0) return 1;
        if (kelp_bus_notify_double(bus, "NAV_Y", 0, qt) < 0) return 1;
        if (kelp_bus_notify_double(bus, "NAV_HEADING", 90, qt) < 0) return 1;
        if (kelp_bus_notify_double(bus, "NAV_SPEED", 0.5, qt) < 0) return 1;
        for (long i = (q % 4) * per_q; i < n && i < (q % 4 + 1) * per_q; i++) {
            double due = qt + 0.25 * (double)(i % per_q) / (double)per_q, t = due - t0, h = pos[3 * i + 2];
            for (double now; (now = wall()) < due;)
                (void)kelp_lcmbus_handle(lb, (int)((due - now) * 1000) > 0 ? 1 : 0, now);
            snprintf(rpt, sizeof rpt, "NAME=vessel_%04ld,TYPE=ship,TIME=%.2f,X=%.2f,Y=%.2f,SPD=2.00,HDG=%.2f,DEP=0,LENGTH=20",
                     i, due, pos[3 * i] + 2 * t * sin(h * PI / 180), pos[3 * i + 1] + 2 * t * cos(h * PI / 180), h);
            if (kelp_bus_notify_string(bus, "NODE_REPORT", rpt, due) == 0) sent++;
        }
    }
    for (double until = wall() + 1.0; wall() < until;) (void)kelp_lcmbus_handle(lb, 20, wall());
    printf("feed N %ld sent %lu listed %lu\n", n, sent, listed);
    free(pos);
    kelp_lcmbus_close(lb);
    return 0;
}
