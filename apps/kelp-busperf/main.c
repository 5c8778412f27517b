/* kelp-busperf: bus throughput / latency / robustness probe, for tests and `make bench`.
 *
 *   kelp-busperf pub N [SIZE]          publish N string vars of SIZE bytes on BURST (kelp bus)
 *   kelp-busperf sub N [TIMEOUT_S]     count BURST messages until N or timeout; prints "received R/N"
 *   kelp-busperf raw-pub N [SIZE]      the same through raw liblcm (pre-encoded bytes)
 *   kelp-busperf raw-sub N [TIMEOUT_S]
 *   kelp-busperf ping N | pong         kelp round trips (PING -> PONG); prints p50/p90/p99 in us
 *   kelp-busperf raw-ping N | raw-pong raw liblcm round trips
 *   kelp-busperf junk CHANNEL N        publish N malformed datagrams on CHANNEL
 * The URL is $KELP_LCM_URL or the default (recv_buf_size added for udpm). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <lcm/lcm.h>
#include <kelp/edge/cli.h>
#include <kelp/lcmbus.h>
#include <kelp/mission.h>

/* a command-line number; exits with a message when it is not one */
static double num(const char *s)
{
    double d;
    if (kelp_util_parse_double(s, strlen(s), &d) < 0) {
        fprintf(stderr, "kelp-busperf: '%s' is not a number\n", s);
        exit(2);
    }
    return d;
}

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

typedef struct ctr {
    long n, want;
    double first, last;
    double *rtt;
    long nrtt;
    double sent_at;
    kelp_bus *bus;
    lcm_t *lcm;
    int pong_mode;
} ctr;

static void on_kelp(const kelp_var *v, void *user)
{
    ctr *c = user;
    double t = wall();
    if (strcmp(v->name, "BURST") == 0) {
        if (c->n == 0) c->first = t;
        c->n++;
        c->last = t;
    } else if (strcmp(v->name, "PING") == 0 && c->pong_mode) {
        if (kelp_bus_notify_double(c->bus, "PONG", v->dval, 0) < 0) fprintf(stderr, "pong failed\n");
    } else if (strcmp(v->name, "PONG") == 0 && !c->pong_mode) {
        if (c->nrtt < c->want) c->rtt[c->nrtt++] = (t - c->sent_at) * 1e6;
        c->n++;
    }
}

static void on_raw(const lcm_recv_buf_t *rb, const char *chan, void *user)
{
    ctr *c = user;
    double t = wall();
    if (strcmp(chan, "BURST") == 0) {
        if (c->n == 0) c->first = t;
        c->n++;
        c->last = t;
    } else if (strcmp(chan, "PING") == 0 && c->pong_mode) {
        lcm_publish(c->lcm, "PONG", rb->data, rb->data_size);
    } else if (strcmp(chan, "PONG") == 0 && !c->pong_mode) {
        if (c->nrtt < c->want) c->rtt[c->nrtt++] = (t - c->sent_at) * 1e6;
        c->n++;
    }
}

static int dcmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static void pct(ctr *c, const char *what)
{
    qsort(c->rtt, (size_t)c->nrtt, sizeof(double), dcmp);
    if (c->nrtt == 0) {
        printf("%s: no round trips\n", what);
        return;
    }
    printf("%s: %ld round trips  p50 %.1f us  p90 %.1f us  p99 %.1f us  max %.1f us\n", what, c->nrtt,
           c->rtt[c->nrtt / 2], c->rtt[c->nrtt * 9 / 10], c->rtt[c->nrtt * 99 / 100], c->rtt[c->nrtt - 1]);
}

int main(int argc, char **argv)
{
    static const kelp_cli cli = {
        .name = "kelp-busperf",
        .purpose = "Bus throughput, latency and robustness probe, for tests and `make bench`.",
        .synopsis = "pub N [SIZE]          publish N string vars of SIZE bytes on BURST (kelp bus)\n"
                    "sub N [TIMEOUT_S]     count BURST messages until N or timeout; prints \"received R/N\"\n"
                    "raw-pub N [SIZE]      the same through raw liblcm (pre-encoded bytes)\n"
                    "raw-sub N [TIMEOUT_S]\n"
                    "ping N | pong         kelp round trips (PING -> PONG); prints p50/p90/p99 in us\n"
                    "raw-ping N | raw-pong raw liblcm round trips\n"
                    "junk CHANNEL N        publish N malformed datagrams on CHANNEL",
        .more = "The URL is $KELP_LCM_URL or kelp's default (recv_buf_size added for udpm).\n",
        .in_order = true,
    };
    int opt, status;
    while ((opt = kelp_cli_next(&cli, argc, argv, &status)) != -1)
        if (opt == KELP_CLI_EXIT) return status;
    argc -= optind - 1; /* from here argv[1] is the mode */
    argv += optind - 1;
    if (argc < 2) {
        kelp_cli_usage(&cli, stderr);
        return kelp_cli_error(&cli, "no mode given");
    }
    const char *mode = argv[1];
    long n = (argc > 2 && strcmp(mode, "junk") != 0) ? (long)num(argv[2]) : 10000;
    char url[512];
    if (kelp_lcmbus_url(NULL, url, sizeof url) < 0) return 1;
    static ctr c;
    c.want = n;
    int raw = strncmp(mode, "raw-", 4) == 0;
    const char *m = raw ? mode + 4 : mode;
    kelp_lcmbus *lb = NULL;
    lcm_t *lcm = NULL;
    if (raw) {
        lcm = lcm_create(url);
        if (!lcm) { fprintf(stderr, "lcm_create failed\n"); return 1; }
        c.lcm = lcm;
    } else {
        kelp_diag err = {0};
        lb = kelp_lcmbus_open(url, "kelp-busperf", "bench", on_kelp, &c, &err);
        if (!lb) { fprintf(stderr, "%s\n", kelp_diag_text(&err)); return 1; }
        c.bus = kelp_lcmbus_bus(lb);
    }
    if (strcmp(m, "pub") == 0) {
        size_t size = argc > 3 ? (size_t)(long)num(argv[3]) : 32;
        if (size > KELP_MAX_SVAL) size = KELP_MAX_SVAL;
        char *payload = malloc(size + 1);
        memset(payload, 'x', size);
        payload[size] = 0;
        /* raw: a pre-encoded kelp var, so both carry identical bytes */
        uint8_t buf[8192];
        size_t len = 0;
        kelp_var *v = calloc(1, sizeof *v);
        strcpy(v->name, "BURST");
        strcpy(v->source, "kelp-busperf");
        strcpy(v->community, "bench");
        v->kind = KELP_VAR_STRING;
        memcpy(v->sval, payload, size + 1);
        v->slen = size;
        if (kelp_var_encode(v, buf, sizeof buf, &len) < 0) {
            free(payload);
            free(v);
            return 1;
        }
        int perr = 0;
        double t0 = wall();
        for (long i = 0; i < n; i++) {
            if (raw) {
                if (lcm_publish(lcm, "BURST", buf, (unsigned)len) != 0) perr = 1;
            } else if (kelp_bus_notify_string(c.bus, "BURST", payload, 0.0) < 0) {
                perr = 1;
            }
            if (perr) break;
        }
        if (perr) {
            fprintf(stderr, "publish failed\n");
            free(payload);
            free(v);
            return 1;
        }
        double dt = wall() - t0;
        printf("%s published %ld messages (%zu-byte datagrams) in %.3f s: %.0f msg/s\n", raw ? "raw liblcm" : "kelp bus",
               n, len, dt, n / dt);
        free(payload);
        free(v);
    } else if (strcmp(m, "sub") == 0) {
        double timeout = argc > 3 ? num(argv[3]) : 10;
        if (raw) {
            lcm_subscription_t *s = lcm_subscribe(lcm, "BURST", on_raw, &c);
            lcm_subscription_set_queue_capacity(s, 0);
        } else if (kelp_bus_register(c.bus, "BURST", 0, 0) < 0) {
            return 1;
        }
        printf("ready\n");
        fflush(stdout);
        double until = wall() + timeout;
        while (c.n < n && wall() < until) {
            if (raw) lcm_handle_timeout(lcm, 50);
            else KELP_IGNORE(kelp_lcmbus_handle(lb, 50, 0));
        }
        double dt = c.last - c.first;
        printf("%s received %ld/%ld", raw ? "raw liblcm" : "kelp bus", c.n, n);
        if (c.n > 1 && dt > 0) printf(" at %.0f msg/s", (c.n - 1) / dt);
        if (!raw) printf(" (bad datagrams %llu)", (unsigned long long)kelp_bus_get_stats(c.bus)->bad);
        printf("\n");
        return c.n == n ? 0 : 1;
    } else if (strcmp(m, "pong") == 0) {
        c.pong_mode = 1;
        if (raw) lcm_subscription_set_queue_capacity(lcm_subscribe(lcm, "PING", on_raw, &c), 0);
        else if (kelp_bus_register(c.bus, "PING", 0, 0) < 0) return 1;
        printf("ready\n");
        fflush(stdout);
        double until = wall() + (argc > 2 ? num(argv[2]) : 30);
        while (wall() < until) {
            if (raw) lcm_handle_timeout(lcm, 50);
            else KELP_IGNORE(kelp_lcmbus_handle(lb, 50, 0));
        }
    } else if (strcmp(m, "ping") == 0) {
        c.rtt = calloc((size_t)n, sizeof(double));
        if (raw) lcm_subscription_set_queue_capacity(lcm_subscribe(lcm, "PONG", on_raw, &c), 0);
        else if (kelp_bus_register(c.bus, "PONG", 0, 0) < 0) return 1;
        uint8_t buf[256];
        size_t len = 0;
        static kelp_var pv;
        kelp_var *v = &pv;
        strcpy(v->name, "PING");
        strcpy(v->source, "kelp-busperf");
        strcpy(v->community, "bench");
        if (kelp_var_encode(v, buf, sizeof buf, &len) < 0) return 1;
        for (long i = 0; i < n; i++) {
            long before = c.n;
            c.sent_at = wall();
            if (raw) lcm_publish(lcm, "PING", buf, (unsigned)len);
            else if (kelp_bus_notify_double(c.bus, "PING", (double)i, 0) < 0) return 1;
            double until = wall() + 1.0;
            while (c.n == before && wall() < until) {
                if (raw) lcm_handle_timeout(lcm, 100);
                else KELP_IGNORE(kelp_lcmbus_handle(lb, 100, 0));
            }
        }
        pct(&c, raw ? "raw liblcm" : "kelp bus");
    } else if (strcmp(m, "junk") == 0 && argc > 3) {
        const char *chan = argv[2];
        long k = (long)num(argv[3]);
        lcm_t *l = lcm ? lcm : lcm_create(url);
        uint8_t junk[64];
        for (long i = 0; i < k; i++) {
            for (size_t j = 0; j < sizeof junk; j++) junk[j] = (uint8_t)(rand() & 0xff);
            /* half of them with a valid fingerprint and a hostile string length */
            if (i % 2) {
                uint64_t fp = KELP_VAR_FINGERPRINT;
                for (int b = 0; b < 8; b++) junk[b] = (uint8_t)(fp >> (56 - 8 * b));
                junk[16] = 0x80; junk[17] = 0; junk[18] = 0; junk[19] = 0;
            }
            lcm_publish(l, chan, junk, sizeof junk);
        }
        printf("published %ld malformed datagrams on %s\n", k, chan);
        if (l != lcm) lcm_destroy(l);
    } else {
        if (lb) kelp_lcmbus_close(lb);
        if (lcm) lcm_destroy(lcm);
        return kelp_cli_error(&cli, "unknown mode '%s'", mode);
    }
    if (lb) kelp_lcmbus_close(lb);
    if (lcm) lcm_destroy(lcm);
    return 0;
}
