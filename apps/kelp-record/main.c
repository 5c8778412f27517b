/* kelp-record: record every channel of an LCM URL to an LCM log file, losing nothing.
 *
 *   kelp-record [--lcm-url=URL] [-f] [-q] FILE     (lcm-logger's options: -f overwrite, -q quiet)
 *
 * Why not lcm-logger: Debian's 1.3.1 lcm-logger keeps LCM's default subscription queue
 * (30 messages) and the default socket buffer, so it drops part of any burst, and a test
 * that reads its log then fails at random on a loaded machine. kelp-record receives through
 * kelp's own udpm socket (a receive thread, a bounded queue, a 4 MiB receive buffer;
 * liblcm only writes the log) and writes events in order.
 * The log is the standard LCM event log: lcm-logplayer, lcm-spy and kelp-logcheck read it. */
#include <poll.h>
#include <regex.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <lcm/eventlog.h>
#include <kelp/edge/cli.h>
#include <kelp/lcmbus.h>

static volatile sig_atomic_t g_stop;
static void on_signal(int s) { (void)s; g_stop = 1; }

typedef struct rec {
    lcm_eventlog_t *log;
    long n, errors;
} rec;

static void on_msg(rec *r, const kelp_udpm_msg *m)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    lcm_eventlog_event_t e;
    memset(&e, 0, sizeof e);
    e.timestamp = (int64_t)tv.tv_sec * 1000000 + tv.tv_usec;
    e.channellen = (int32_t)strlen(m->channel);
    e.datalen = (int32_t)m->len;
    e.channel = (char *)m->channel;
    e.data = (void *)m->data;
    if (lcm_eventlog_write_event(r->log, &e) != 0) r->errors++;
    else r->n++;
}

int main(int argc, char **argv)
{
    const char *url_in = NULL, *file = NULL, *chan = ".*";
    int quiet = 0;
    const kelp_cli cli = {
        .name = "kelp-record",
        .purpose = "Record every channel to an LCM event log with no loss (unbounded queue, 4 MiB socket\n"
                   "buffer); stops on SIGINT/SIGTERM.",
        .synopsis = "[--lcm-url=URL] [-c CHANNEL_REGEX] [-f] [-q] FILE",
        .opts = (const kelp_cli_opt[]){
            { "lcm-url", required_argument, 'u', "URL", "the bus (default: $KELP_LCM_URL or kelp's default)" },
            { "channel", required_argument, 'c', "REGEX", "record only channels matching REGEX (default .*)" },
            { "force", no_argument, 'f', NULL, "overwrite FILE (always done; accepted as lcm-logger's)" },
            { "quiet", no_argument, 'q', NULL, "print nothing but errors" },
            { NULL, 0, 0, NULL, NULL } },
    };
    int c, status;
    while ((c = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        switch (c) {
        case KELP_CLI_EXIT: return status;
        case 'u': url_in = optarg; break;
        case 'c': chan = optarg; break;
        case 'q': quiet = 1; break;
        default: break; /* -f */
        }
    }
    if (optind < argc) file = argv[optind++];
    if (optind < argc) return kelp_cli_error(&cli, "unexpected argument '%s'", argv[optind]);
    if (!file) return kelp_cli_error(&cli, "FILE is required");
    char url[600];
    if (url_in && *url_in) {
        /* an explicit URL wins over $KELP_LCM_URL; add the receive buffer as kelp_lcmbus_url does */
        if (strncmp(url_in, "udpm://", 7) == 0 && !strstr(url_in, "recv_buf_size"))
            snprintf(url, sizeof url, "%s%crecv_buf_size=%d", url_in, strchr(url_in, '?') ? '&' : '?', KELP_LCM_RECV_BUF);
        else
            snprintf(url, sizeof url, "%s", url_in);
    } else if (kelp_lcmbus_url(NULL, url, sizeof url) < 0) {
        return 1;
    }
    static rec r;
    r.log = lcm_eventlog_create(file, "w");
    if (!r.log) {
        fprintf(stderr, "kelp-record: cannot write %s\n", file);
        return 1;
    }
    kelp_diag err = {0};
    char re[600];
    regex_t rx;
    snprintf(re, sizeof re, "^(%s)$", chan); /* LCM anchors subscription regexes */
    if (regcomp(&rx, re, REG_EXTENDED | REG_NOSUB) != 0) {
        fprintf(stderr, "kelp-record: bad channel regex '%s'\n", chan);
        lcm_eventlog_destroy(r.log);
        return 2;
    }
    kelp_udpm_sock *sock = kelp_udpm_sock_open(url, &err);
    if (!sock) {
        fprintf(stderr, "kelp-record: cannot open LCM URL %s: %s\n", url, kelp_diag_text(&err));
        lcm_eventlog_destroy(r.log);
        regfree(&rx);
        return 1;
    }
    kelp_cli_on_stop(on_signal);
    kelp_udpm_msg m;
    for (int last = 0; !last;) {
        last = g_stop; /* one more pass after the signal drains what is already queued */
        struct pollfd p = { kelp_udpm_sock_fd(sock), POLLIN, 0 };
        if (!last) (void)poll(&p, 1, 100);
        while (kelp_udpm_sock_next(sock, &m) == 1)
            if (regexec(&rx, m.channel, 0, NULL, 0) == 0) on_msg(&r, &m);
    }
    kelp_udpm_sock_close(sock);
    regfree(&rx);
    lcm_eventlog_destroy(r.log);
    if (!quiet) printf("kelp-record: %ld events written to %s (%ld write errors)\n", r.n, file, r.errors);
    return r.errors ? 1 : 0;
}
