/* kelp-viewer's benchmark feeder (bench/viewer.sh):
 *   bench_viewer_feed N SECONDS
 * N vehicles each on its own 40 m circle (so every report moves it and grows its trail) post
 * NODE_REPORT on the bus at 4 Hz each, the reports of one quarter second spread over it, for
 * SECONDS. Prints "feed N <n> sent <s> late <l>" (late: rounds that started behind time). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <kelp/bus.h>
#include <kelp/lcmbus.h>
#include <kelp/util.h>

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void on_var(const kelp_var *v, void *user)
{
    (void)v;
    (void)user;
}

int main(int argc, char **argv)
{
    if (argc < 3) { fprintf(stderr, "usage: bench_viewer_feed N SECONDS\n"); return 2; }
    long n = 0;
    double secs = 0;
    if (kelp_util_parse_long(argv[1], strlen(argv[1]), &n) != 0 || kelp_util_parse_double(argv[2], strlen(argv[2]), &secs) != 0 ||
        n < 1 || n > 5000 || !(secs > 0))
        return 2;
    char url[512];
    kelp_diag err = {0};
    if (kelp_lcmbus_url(NULL, url, sizeof url) < 0) return 1;
    kelp_lcmbus *lb = kelp_lcmbus_open(url, "bench_viewer_feed", "shoreside", on_var, NULL, &err);
    if (!lb) { fprintf(stderr, "%s\n", kelp_diag_text(&err)); return 1; }
    kelp_bus *bus = kelp_lcmbus_bus(lb);
    int side = (int)ceil(sqrt((double)n)), rounds = (int)(secs * 4 + 0.5);
    double t0 = floor(wall()) + 1;
    unsigned long sent = 0, late = 0;
    char rpt[256];
    static const char *const types[] = {"UUV", "kayak", "ship", "glider"};
    for (int k = 0; k < rounds; k++) {
        double round_t = t0 + k * 0.25;
        if (wall() > round_t + 0.25) late++;
        for (long i = 0; i < n; i++) {
            double due = round_t + 0.25 * (double)i / (double)n;
            for (double now; (now = wall()) < due;)
                (void)kelp_lcmbus_handle(lb, (int)((due - now) * 1000) > 0 ? 1 : 0, now);
            double a = 0.05 * k + (double)i, cx = 200.0 * (double)(i % side), cy = 200.0 * (double)(i / side);
            snprintf(rpt, sizeof rpt, "NAME=v%ld,TYPE=%s,TIME=%.3f,X=%.2f,Y=%.2f,SPD=2,HDG=%.1f,DEP=0,LENGTH=4,MODE=SURVEY",
                     i, types[i % 4], round_t, cx + 40 * cos(a), cy + 40 * sin(a), fmod(360.0 - a * 57.29578, 360.0));
            if (kelp_bus_notify_string(bus, "NODE_REPORT", rpt, round_t) == 0) sent++;
        }
    }
    printf("feed N %ld sent %lu late %lu\n", n, sent, late);
    kelp_lcmbus_close(lb);
    return 0;
}
