/* pContactMgrV20 core cost for bench/contactmgr.sh:
 *   bench_contactmgr N [SECONDS]
 * N contacts scattered over a 1400 m disk around ownship, each on a straight leg at 2 m/s,
 * each reporting once per second (staggered over the four 0.25 s steps); ownship NAV_X, NAV_Y,
 * NAV_HEADING, NAV_SPEED at 4 Hz and one iteration per 0.25 s (AppTick 4), max_contacts N.
 * Configured as a helm would: one avoidance alert (80/100 m, CONTACT_INFO with macros), a
 * custom range report re-requested every second, CONTACT_RANGES and CONTACT_CLOSEST_RANGE on.
 * Fed straight into the core for SECONDS of simulated time (10). Prints the CPU time per
 * simulated second as a percentage of one core, the contacts held at the end, the alerts
 * posted against those owed (contacts that were within the alert range, brute force here),
 * and the state size. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/contactmgr.h>

#define PI 3.14159265358979323846

static unsigned long posts, alerts;

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx, (void)is_string, (void)sval, (void)dval;
    posts++;
    if (strcmp(var, "CONTACT_INFO") == 0) alerts++;
}

static void warn(void *ctx, const char *msg)
{
    (void)ctx;
    fprintf(stderr, "warning: %s\n", msg);
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
    if (n < 1 || n > KELP_CMGR_MAX_CONTACTS || !(secs > 0)) return 2;
    kelp_contactmgr *c = malloc(sizeof *c);
    double *x = malloc(sizeof(double) * (size_t)n * 3), *y = x + n, *h = y + n;
    char *seen = calloc((size_t)n, 1);
    if (!c || !x || !seen) return 1;
    kelp_field_sink sink = { NULL, pub, warn };
    kelp_contactmgr_init(c, "ownship");
    char mc[32];
    snprintf(mc, sizeof mc, "%d", n);
    if (kelp_contactmgr_config(c, "max_contacts", mc, &sink) != 1 ||
        kelp_contactmgr_config(c, "alert", "id=avd, alert_range=80, cpa_range=100, "
                                     "on_flag=CONTACT_INFO=name=avd_$[VNAME] # contact=$[VNAME]", &sink) != 1 ||
        kelp_contactmgr_config(c, "post_all_ranges", "true", &sink) != 1 ||
        kelp_contactmgr_config(c, "post_closest_range", "true", &sink) != 1)
        return 1;
    kelp_contactmgr_config_done(c, false, 0, false, 0, &sink);
    uint64_t rng = 88172645463325252ull;
    for (int i = 0; i < n; i++) {
        rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
        double r = 1400 * sqrt((double)(rng % 1000000) / 1e6), a = (double)((rng >> 20) % 3600) / 10.0;
        x[i] = r * sin(a * PI / 180), y[i] = r * cos(a * PI / 180);
        h[i] = (double)((rng >> 40) % 360);
    }
    int steps = (int)(secs * 4 + 0.5);
    char buf[256];
    double cpu = 0, t0 = 1e9;
    long owed = 0;
    for (int k = 0; k < steps; k++) {
        double now = t0 + k * 0.25, osx = 0.5 * now - 0.5 * t0, osy = 0;
        double c0 = cpu_s();
        (void)kelp_contactmgr_mail(c, "NAV_X", false, NULL, osx, now, "uSimMarine", &sink);
        (void)kelp_contactmgr_mail(c, "NAV_Y", false, NULL, osy, now, "uSimMarine", &sink);
        (void)kelp_contactmgr_mail(c, "NAV_HEADING", false, NULL, 90, now, "uSimMarine", &sink);
        (void)kelp_contactmgr_mail(c, "NAV_SPEED", false, NULL, 2, now, "uSimMarine", &sink);
        if (k % 4 == 0)
            (void)kelp_contactmgr_mail(c, "BCM_REPORT_REQUEST", true, "var=CONTACTS_200, range=200", 0, now, "pHelmIvP",
                                 &sink);
        for (int i = k % 4; i < n; i += 4) {
            double t = now - t0;
            double px = x[i] + 2 * t * sin(h[i] * PI / 180), py = y[i] + 2 * t * cos(h[i] * PI / 180);
            snprintf(buf, sizeof buf, "NAME=vessel_%04d,TYPE=ship,TIME=%.2f,X=%.2f,Y=%.2f,LAT=43.8,LON=-70.3,"
                     "SPD=2.00,HDG=%.2f,DEPTH=0.00,LENGTH=20,MODE=SURVEY", i, now, px, py, h[i]);
            if (kelp_contactmgr_mail(c, "NODE_REPORT", true, buf, 0, now, "uFldNodeBroker", &sink) != 1) return 1;
        }
        kelp_contactmgr_iterate(c, now, &sink);
        cpu += cpu_s() - c0;
        for (int i = k % 4; i < n; i += 4) { /* owed: within the alert range at least once (first time) */
            double t = now - t0;
            double px = x[i] + 2 * t * sin(h[i] * PI / 180), py = y[i] + 2 * t * cos(h[i] * PI / 180);
            if (!seen[i] && hypot(px - osx, py - osy) <= 80) seen[i] = 1, owed++;
        }
    }
    printf("N %d  cpu_pct %.3f  contacts %u  alerts %lu  owed_min %ld  posts %lu  struct_bytes %zu\n", n,
           100.0 * cpu / secs, c->ncontacts, alerts, owed, posts, sizeof *c);
    int ok = c->ncontacts == (unsigned)n && (long)alerts >= owed;
    free(seen);
    free(x);
    free(c);
    return ok ? 0 : 3;
}
