/* The uFldNodeComms app benchmark's feeder (bench/nodecomms_app.sh):
 *   bench_ncomms_feed N SECONDS
 * N vehicles on a square grid 60 m apart post NODE_REPORT on the bus at 4 Hz each (the
 * reports of one quarter second spread over it), for SECONDS; the feeder also listens to
 * NODE_REPORT_* and counts the relays uFldNodeComms makes. A relay is counted against the
 * round its report was sent in (the report's TIME field), and the relays owed for a round
 * are the pairs within the comms range (100 m) counted by brute force; the first round is
 * left out (uFldNodeComms does not know the receivers yet) and so is the last (its relays
 * may still be on the way when the feeder stops listening, 1.5 s later).
 * Prints: "feed N <n> rounds <r> relayed <k> owed <o> sent <s>". */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/bus.h>
#include <kelp/lcmbus.h>
#include <kelp/util.h>

typedef struct feed {
    double t0;         /* time of round 0 */
    int rounds;
    unsigned long relayed, other;
    unsigned long per_round[4096];
} feed;

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void on_var(const kelp_var *v, void *user)
{
    feed *f = user;
    if (strncmp(v->name, "NODE_REPORT_", 12) != 0 || v->kind != KELP_VAR_STRING) return;
    const char *t = strstr(v->sval, "TIME=");
    if (!t) { f->other++; return; }
    const char *e = strchr(t, ',');
    double tv = 0;
    if (kelp_util_parse_double(t + 5, e ? (size_t)(e - t - 5) : strlen(t + 5), &tv) != 0) { f->other++; return; }
    int round = (int)lround((tv - f->t0) / 0.25);
    if (round >= 0 && round < 4096) f->per_round[round]++;
    if (round >= 1 && round < f->rounds - 1) f->relayed++;
    else f->other++;
}

int main(int argc, char **argv)
{
    if (argc < 3) { fprintf(stderr, "usage: bench_ncomms_feed N SECONDS\n"); return 2; }
    long n = 0;
    double secs = 0;
    if (kelp_util_parse_long(argv[1], strlen(argv[1]), &n) != 0 || kelp_util_parse_double(argv[2], strlen(argv[2]), &secs) != 0 ||
        n < 2 || n > 5000 || !(secs > 0))
        return 2;
    char url[512];
    kelp_diag err = {0};
    if (kelp_lcmbus_url(NULL, url, sizeof url) < 0) return 1;
    static feed f;
    kelp_lcmbus *lb = kelp_lcmbus_open(url, "bench_ncomms_feed", "shoreside", on_var, &f, &err);
    if (!lb) { fprintf(stderr, "%s\n", kelp_diag_text(&err)); return 1; }
    kelp_bus *bus = kelp_lcmbus_bus(lb);
    if (kelp_bus_register(bus, "NODE_REPORT_*", 0, 0) < 0) return 1;
    int side = (int)ceil(sqrt((double)n));
    int nv = (int)n;
    f.rounds = (int)(secs * 4 + 0.5);
    /* owed per round: ordered pairs closer than 100 m (the grid does not move) */
    unsigned long pairs = 0;
    for (int i = 0; i < nv; i++)
        for (int j = 0; j < nv; j++) {
            if (i == j) continue;
            int gx = i % side - j % side, gy = i / side - j / side; /* grid cells apart */
            double dx = 60.0 * gx, dy = 60.0 * gy;
            if (hypot(dx, dy) < 100) pairs++;
        }
    f.t0 = floor(wall()) + 1;
    unsigned long sent = 0;
    char rpt[256];
    for (int k = 0; k < f.rounds; k++) {
        double round_t = f.t0 + k * 0.25;
        for (int i = 0; i < nv; i++) {
            double due = round_t + 0.25 * i / n;
            /* wait in the bus's poll (whole milliseconds): a report is sent at most 1 ms
             * late rather than the feeder spinning a core between reports and taking it
             * from the app it measures */
            for (double now; (now = wall()) < due - 0.0005;)
                KELP_IGNORE(kelp_lcmbus_handle(lb, 1, now));
            int gx = i % side, gy = i / side;
            snprintf(rpt, sizeof rpt, "NAME=v%d,TYPE=UUV,TIME=%.3f,X=%.1f,Y=%.1f,SPD=1,HDG=90,DEP=0,LENGTH=4", i, round_t,
                     60.0 * gx, 60.0 * gy);
            if (kelp_bus_notify_string(bus, "NODE_REPORT", rpt, round_t) == 0) sent++;
        }
    }
    for (double until = wall() + 1.5; wall() < until;) KELP_IGNORE(kelp_lcmbus_handle(lb, 20, wall()));
    unsigned long owed = pairs * (unsigned long)(f.rounds > 2 ? f.rounds - 2 : 0);
    if (getenv("FEED_ROUNDS"))
        for (int k = 0; k < f.rounds && k < 4096; k++) fprintf(stderr, "round %d: %lu of %lu\n", k, f.per_round[k], pairs);
    printf("feed N %ld rounds %d relayed %lu owed %lu sent %lu\n", n, f.rounds, f.relayed, owed, sent);
    /* where relays were lost on this side: the feeder's socket (kernel drops show in
     * /proc/net/udp), its receive queue, or never sent */
    kelp_udpm_sock_stats st;
    kelp_lcmbus_get_stats(lb, &st);
    fprintf(stderr, "feeder socket: %llu datagrams read (%llu coalesced runs split), %llu messages queued, %llu queue drops,"
                    " %llu sent, %llu send errors, receive buffer %d B\n", (unsigned long long)st.rx.datagrams,
            (unsigned long long)st.gro_runs, (unsigned long long)st.queued,
            (unsigned long long)st.queue_dropped, (unsigned long long)st.sent, (unsigned long long)st.send_errors, st.recv_buf);
    kelp_lcmbus_close(lb);
    return 0;
}
