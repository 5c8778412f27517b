/* uFldNodeComms core cost for bench/nodecomms.sh:
 *   bench_nodecomms N [SECONDS]
 * N vehicles on a square grid 60 m apart, each reporting at 4 Hz (its position jitters by
 * up to 1 m), COMMS_RANGE 100, CRITICAL_RANGE 30, report pulses on, fed straight into the
 * core (kelp_field_ncomms_mail + one iterate per 0.25 s) for SECONDS of simulated time (10).
 * Prints the CPU time per simulated second as a percentage of one core, the relays made
 * against the relays owed (pairs within range, counted by brute force here), and the
 * size of the core's state. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/field.h>

static unsigned long posts, pulses;

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx, (void)is_string, (void)sval, (void)dval;
    if (var[0] == 'V') pulses++;
    else posts++;
}

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    if (argc < 2) return 2;
    int n = atoi(argv[1]);
    double secs = argc > 2 ? atof(argv[2]) : 10;
    if (n < 2 || n > KELP_NCOMMS_MAX_NODES || !(secs > 0)) return 2;
    kelp_field_ncomms *c = malloc(sizeof *c);
    double *x = malloc(sizeof(double) * (size_t)n * 2), *y = x + n;
    if (!c || !x) return 1;
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    cfg.comms_range = 100;
    cfg.critical_range = 30;
    cfg.view_node_rpt_pulses = true;
    if (kelp_field_ncomms_init(c, &cfg) < 0) return 1;
    kelp_field_sink sink = { NULL, pub, NULL };
    int side = (int)ceil(sqrt((double)n));
    uint64_t rng = 88172645463325252ull;
    int steps = (int)(secs * 4 + 0.5);
    long owed = 0;
    char buf[256];
    double cpu = 0;
    for (int k = 0; k < steps; k++) {
        double now = 1e9 + k * 0.25;
        for (int i = 0; i < n; i++) {
            rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
            x[i] = (i % side) * 60.0 + (double)(rng % 2001) / 1000.0 - 1.0;
            y[i] = (i / side) * 60.0 + (double)((rng >> 20) % 2001) / 1000.0 - 1.0;
        }
        /* owed: every ordered pair within range at this step (all reports are fresh) */
        for (int a = 0; a < n; a++)
            for (int b = 0; b < n; b++)
                if (a != b && hypot(x[a] - x[b], y[a] - y[b]) < 100) owed++;
        double t0 = cpu_s();
        for (int i = 0; i < n; i++) {
            snprintf(buf, sizeof buf, "NAME=v%d,TYPE=UUV,TIME=%.2f,X=%.2f,Y=%.2f,SPD=1.50,HDG=90.00,DEP=0.00,LENGTH=4",
                     i, now, x[i], y[i]);
            if (kelp_field_ncomms_mail(c, "NODE_REPORT", true, buf, 0, "bench", now, &sink) != 1) return 1;
        }
        KELP_IGNORE(kelp_field_ncomms_iterate(c, now, &sink));
        cpu += cpu_s() - t0;
    }
    printf("N %d  cpu_pct %.2f  relayed %lu  owed %ld  pulses %lu  scanned %lu  struct_bytes %zu\n", n,
           100.0 * cpu / secs, c->rpts_sent, owed, pulses, c->scanned, sizeof *c);
    int ok = (long)c->rpts_sent == owed && (long)posts == owed;
    free(x);
    free(c);
    return ok ? 0 : 3;
}
