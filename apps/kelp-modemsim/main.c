/* kelp-modemsim: a simulated WHOI Micro-Modem (the iModemSim role) -- the modem side of the
 * Micro-Modem NMEA protocol on a pseudo-terminal or a TCP port, with the acoustic channel
 * shared by every kelp-modemsim over the bus.  The protocol and the channel model are the core
 * module kelp_msim (include/kelp/modemsim.h); this file is the I/O around it. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pty.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/stat.h>

#include <kelp/app.h>
#include <kelp/kv.h>
#include <kelp/lcmbus.h>
#include <kelp/modemsim.h>

#define DEFAULT_CHANNEL "ACOMMS_SIM_CHANNEL"

typedef struct msim_app {
    kelp_app *app;
    kelp_msim m;
    int modem_id;
    /* host side */
    int master, slave;             /* pty */
    char pty_name[256], pty_link[256];
    int ep, lfd, cfd;              /* tcp: epoll set, listening socket, client */
    unsigned tcp_port;
    unsigned long bytes_in, bytes_out, dropped_out, host_connects;
    /* channel */
    char channel_var[KELP_MAX_NAME];
    char channel_url[400];
    kelp_lcmbus *chan;             /* separate channel bus, or NULL = the community bus */
    unsigned long pkts_out, pkts_in, pkts_bad, pkts_sync_ignored;
    /* position source */
    char node_report_var[KELP_MAX_NAME];
    bool nav_vars;
    double nav_x, nav_y, nav_depth;
    bool publish_events;
    double last_status;
    uint8_t enc[KELP_MSIM_PKT_MAX_ENCODED];
    kelp_msim_pkt rxpkt;
} msim_app;

static int64_t us_of(double t)
{
    return (int64_t)llround(t * 1e6);
}

/* ------------------------------------------------------------------ host I/O */

static void host_write(const char *b, size_t n, void *u)
{
    msim_app *s = u;
    int fd = s->master >= 0 ? s->master : s->cfd;
    if (fd < 0) {
        s->dropped_out += n;
        return;
    }
    size_t off = 0;
    while (off < n) {
        ssize_t w = write(fd, b + off, n - off);
        if (w > 0) {
            off += (size_t)w;
            continue;
        }
        if (w < 0 && errno == EINTR) continue;
        /* nobody reading (pty buffer full) or the client went away: the line is lost, as on a wire */
        s->dropped_out += n - off;
        if (s->dropped_out == n - off)
            kelp_app_run_warning(s->app, "host not reading: output dropped (%s)", strerror(errno));
        return;
    }
    s->bytes_out += n;
}

static void feed_host(msim_app *s, const uint8_t *b, size_t n)
{
    s->bytes_in += n;
    int64_t now = us_of(kelp_app_time(s->app));
    if (kelp_msim_feed(&s->m, b, n, now) < 0) kelp_app_run_warning(s->app, "modem feed failed");
    kelp_msim_tick(&s->m, now);
}

static void on_pty(kelp_app *app, void *st, int fd)
{
    msim_app *s = st;
    (void)app;
    uint8_t buf[4096];
    for (;;) {
        ssize_t n = read(fd, buf, sizeof buf);
        if (n > 0) {
            feed_host(s, buf, (size_t)n);
            continue;
        }
        return; /* EAGAIN (drained) or EIO (no slave open; we keep one, so not expected) */
    }
}

static void close_client(msim_app *s)
{
    if (s->cfd < 0) return;
    epoll_ctl(s->ep, EPOLL_CTL_DEL, s->cfd, NULL);
    close(s->cfd);
    s->cfd = -1;
}

static void on_tcp(kelp_app *app, void *st, int fd)
{
    msim_app *s = st;
    (void)fd;
    struct epoll_event ev[4];
    int n = epoll_wait(s->ep, ev, 4, 0);
    for (int i = 0; i < n; i++) {
        if (ev[i].data.fd == s->lfd) {
            int c = accept(s->lfd, NULL, NULL);
            if (c < 0) continue;
            close_client(s); /* one host at a time: a new connection replaces the old one */
            fcntl(c, F_SETFL, fcntl(c, F_GETFL) | O_NONBLOCK);
            int one = 1;
            setsockopt(c, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            struct epoll_event e = { .events = EPOLLIN, .data.fd = c };
            epoll_ctl(s->ep, EPOLL_CTL_ADD, c, &e);
            s->cfd = c;
            s->host_connects++;
            kelp_app_event(app, "host connected on TCP port %u", s->tcp_port);
        } else if (ev[i].data.fd == s->cfd) {
            uint8_t buf[4096];
            for (;;) {
                ssize_t r = read(s->cfd, buf, sizeof buf);
                if (r > 0) {
                    feed_host(s, buf, (size_t)r);
                    continue;
                }
                if (r == 0 || (errno != EAGAIN && errno != EINTR)) {
                    kelp_app_event(app, "host disconnected");
                    close_client(s);
                }
                break;
            }
        }
    }
}

static int open_pty(msim_app *s)
{
    if (openpty(&s->master, &s->slave, s->pty_name, NULL, NULL) < 0) {
        kelp_app_run_warning(s->app, "openpty: %s", strerror(errno));
        return -1;
    }
    /* raw: no echo, no CR/LF translation (the host reads lines ending in CR) */
    struct termios t;
    if (tcgetattr(s->slave, &t) == 0) {
        cfmakeraw(&t);
        cfsetispeed(&t, B19200);
        cfsetospeed(&t, B19200);
        tcsetattr(s->slave, TCSANOW, &t);
    }
    fcntl(s->master, F_SETFL, fcntl(s->master, F_GETFL) | O_NONBLOCK);
    fcntl(s->master, F_SETFD, FD_CLOEXEC);
    fcntl(s->slave, F_SETFD, FD_CLOEXEC);
    /* we keep our slave fd open, so the master never sees a hang-up when the host closes and
     * re-opens the port */
    if (s->pty_link[0]) {
        struct stat st;
        if (lstat(s->pty_link, &st) == 0) {
            if (!S_ISLNK(st.st_mode)) {
                kelp_app_run_warning(s->app, "%s exists and is not a symbolic link: not replaced", s->pty_link);
                return -1;
            }
            unlink(s->pty_link);
        }
        if (symlink(s->pty_name, s->pty_link) < 0) {
            kelp_app_run_warning(s->app, "symlink %s -> %s: %s", s->pty_link, s->pty_name, strerror(errno));
            return -1;
        }
    }
    return 0;
}

static int open_tcp(msim_app *s)
{
    s->lfd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (s->lfd < 0) return -1;
    int one = 1;
    setsockopt(s->lfd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    a.sin_port = htons((uint16_t)s->tcp_port);
    if (bind(s->lfd, (struct sockaddr *)&a, sizeof a) < 0 || listen(s->lfd, 2) < 0) {
        kelp_app_run_warning(s->app, "TCP port %u: %s", s->tcp_port, strerror(errno));
        return -1;
    }
    s->ep = epoll_create1(EPOLL_CLOEXEC);
    if (s->ep < 0) return -1;
    struct epoll_event e = { .events = EPOLLIN, .data.fd = s->lfd };
    epoll_ctl(s->ep, EPOLL_CTL_ADD, s->lfd, &e);
    return 0;
}

/* ------------------------------------------------------------------ the channel */

static void channel_tx(const kelp_msim_pkt *p, void *u)
{
    msim_app *s = u;
    size_t len;
    if (kelp_msim_pkt_encode(p, s->enc, sizeof s->enc, &len) != KELP_OK) {
        kelp_app_run_warning(s->app, "cannot encode a channel packet");
        return;
    }
    int rc = s->chan ? kelp_bus_notify_binary(kelp_lcmbus_bus(s->chan), s->channel_var, s->enc, len,
                                              kelp_app_time(s->app))
                     : kelp_app_notify_binary(s->app, s->channel_var, s->enc, len);
    if (rc < 0) kelp_app_run_warning(s->app, "channel publish failed");
    else s->pkts_out++;
}

static void channel_rx(msim_app *s, const kelp_var *v)
{
    if (v->flags & KELP_VAR_FLAG_SYNC) { /* a retained old transmission, not one on the water now */
        s->pkts_sync_ignored++;
        return;
    }
    if (v->kind != KELP_VAR_BINARY ||
        kelp_msim_pkt_decode((const uint8_t *)v->sval, v->slen, &s->rxpkt) != KELP_OK) {
        s->pkts_bad++;
        kelp_app_run_warning(s->app, "malformed %s from %s: ignored", s->channel_var, v->source);
        return;
    }
    int64_t now = us_of(kelp_app_time(s->app));
    if (s->rxpkt.instance != s->m.cfg.instance) s->pkts_in++;
    if (kelp_msim_hear(&s->m, &s->rxpkt, now) < 0) kelp_app_run_warning(s->app, "too many packets in flight");
    kelp_msim_tick(&s->m, now);
}

static void on_chan_var(const kelp_var *v, void *user)
{
    msim_app *s = user;
    if (strcmp(v->name, s->channel_var) == 0) channel_rx(s, v);
}

static void on_chan_fd(kelp_app *app, void *st, int fd)
{
    msim_app *s = st;
    (void)fd;
    if (kelp_lcmbus_handle(s->chan, 0, kelp_app_time(app)) < 0) kelp_app_run_warning(app, "channel receive error");
}

/* ------------------------------------------------------------------ events */

static const char *kind_name(kelp_msim_pkt_kind k)
{
    switch (k) {
    case KELP_MSIM_PKT_CYCLE_INIT: return "cycle_init";
    case KELP_MSIM_PKT_DATA: return "data";
    case KELP_MSIM_PKT_ACK: return "ack";
    case KELP_MSIM_PKT_PING: return "ping";
    case KELP_MSIM_PKT_PING_REPLY: return "ping_reply";
    case KELP_MSIM_PKT_MINI: return "mini";
    default: return "?";
    }
}

static const char *loss_name(kelp_msim_loss l)
{
    switch (l) {
    case KELP_MSIM_LOSS_RANDOM: return "random";
    case KELP_MSIM_LOSS_COLLISION: return "collision";
    case KELP_MSIM_LOSS_HALF_DUPLEX: return "half_duplex";
    case KELP_MSIM_LOSS_STALE: return "stale";
    default: return "overflow";
    }
}

static void on_event(const kelp_msim_event *e, void *u)
{
    msim_app *s = u;
    char text[256];
    const kelp_msim_pkt *p = e->pkt;
    switch (e->kind) {
    case KELP_MSIM_EV_TX:
        snprintf(text, sizeof text, "modem=%d,event=tx,kind=%s,src=%d,dest=%d,frames=%d,rate=%d", kelp_msim_src(&s->m),
                 kind_name(p->kind), p->src, p->dest, p->kind == KELP_MSIM_PKT_DATA ? p->nframes : 0, p->rate);
        break;
    case KELP_MSIM_EV_RX:
        snprintf(text, sizeof text, "modem=%d,event=rx,kind=%s,src=%d,dest=%d,frame=%u,range=%.1f,travel=%.4f",
                 kelp_msim_src(&s->m), kind_name(p->kind), p->src, p->dest, e->frame, e->range_m, e->travel_s);
        break;
    case KELP_MSIM_EV_LOST:
        snprintf(text, sizeof text, "modem=%d,event=lost,kind=%s,src=%d,dest=%d,frame=%u,reason=%s",
                 kelp_msim_src(&s->m), p ? kind_name(p->kind) : "?", p ? p->src : 0, p ? p->dest : 0, e->frame,
                 loss_name(e->loss));
        break;
    case KELP_MSIM_EV_HOST_ERROR:
        kelp_app_run_warning(s->app, "bad host line ($CAERR sent): %.120s", e->text);
        return;
    case KELP_MSIM_EV_INFO:
        kelp_app_event(s->app, "%s", e->text);
        return;
    default:
        return; /* host lines: see --verbose of the host's ACOMMS_NMEA_IN/OUT */
    }
    kelp_app_event(s->app, "%s", text);
    if (s->publish_events) (void)kelp_app_notify_string(s->app, "ACOMMS_SIM_EVENT", text);
}

/* ------------------------------------------------------------------ configuration */

static int param_d(kelp_app *app, const char *key, double *v, double lo, double hi)
{
    int rc = kelp_app_param_double(app, key, v);
    if (rc < 0) return kelp_app_config_error(app, kelp_app_param(app, key), "%s must be a number", key);
    if (rc > 0 && !(*v >= lo && *v <= hi))
        return kelp_app_config_error(app, kelp_app_param(app, key), "%s must be in [%g, %g]", key, lo, hi);
    return 0;
}

static int parse_xyz(const char *s, double *x, double *y, double *z)
{
    char b[64];
    double *dst[3] = { x, y, z };
    static const char *const keys[3] = { "x", "y", "depth" };
    for (int i = 0; i < 3; i++) {
        int rc = kelp_kv_get(s, ',', keys[i], b, sizeof b);
        if (rc < 0) return -1;
        if (rc == 0) {
            if (i == 2 && kelp_kv_get(s, ',', "z", b, sizeof b) == 1) {
                /* z is accepted for depth */
            } else if (i == 2) {
                *dst[i] = 0;
                continue;
            } else {
                return -1;
            }
        }
        if (kelp_parse_double(b, strlen(b), dst[i]) < 0 || !isfinite(*dst[i])) return -1;
    }
    return 0;
}

static uint32_t make_instance(void)
{
    uint32_t v = 0;
    int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
        if (read(fd, &v, sizeof v) != (ssize_t)sizeof v) v = 0;
        close(fd);
    }
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return v ^ (uint32_t)getpid() ^ (uint32_t)ts.tv_nsec;
}

static int startup(kelp_app *app, void *st)
{
    msim_app *s = st;
    s->app = app;
    s->master = s->slave = s->ep = s->lfd = s->cfd = -1;
    kelp_msim_cfg c;
    kelp_msim_cfg_default(&c);
    double d = 0;
    int rc;
    if (kelp_app_param_double(app, "modem_id", &d) <= 0 || d != floor(d) || d < 1 || d > KELP_MSIM_MAX_ID)
        return kelp_app_config_error(app, kelp_app_param(app, "modem_id"), "modem_id (1..%d) is required",
                                     KELP_MSIM_MAX_ID);
    c.modem_id = s->modem_id = (int)d;
    /* host side: a pseudo-terminal (pty_link, or iModemSim's Port) or a TCP server port */
    if (kelp_app_param_str(app, "pty_link", s->pty_link, sizeof s->pty_link) <= 0)
        (void)kelp_app_param_str(app, "Port", s->pty_link, sizeof s->pty_link);
    (void)kelp_app_param(app, "Speed"); /* iModemSim's baud: a pty has none */
    if (kelp_app_param(app, "tcp_port")) {
        if (param_d(app, "tcp_port", &d, 1, 65535) < 0) return -1;
        s->tcp_port = (unsigned)d;
    }
    if (s->tcp_port && s->pty_link[0])
        return kelp_app_config_error(app, kelp_app_param(app, "tcp_port"), "give either pty_link or tcp_port");
    /* position: x/y/depth (or iModemSim's ConstantPosX/Y/Depth), NODE_REPORT or NAV_* variables */
    const char *px[3][2] = { { "x", "ConstantPosX" }, { "y", "ConstantPosY" }, { "depth", "ConstantDepth" } };
    double *pv[3] = { &c.x, &c.y, &c.depth };
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < 2; k++) {
            if (!kelp_app_param(app, px[i][k])) continue;
            if (param_d(app, px[i][k], pv[i], -1e9, 1e9) < 0) return -1;
        }
    }
    char buf[256];
    if (kelp_app_param_str(app, "position", buf, sizeof buf) > 0 && parse_xyz(buf, &c.x, &c.y, &c.depth) < 0)
        return kelp_app_config_error(app, kelp_app_param(app, "position"), "position must be x=..,y=..[,depth=..]");
    (void)kelp_app_param(app, "InputLocType");
    (void)kelp_app_param_str(app, "node_report_var", s->node_report_var, sizeof s->node_report_var);
    if (kelp_app_param_bool(app, "nav_vars", &s->nav_vars) < 0) return -1;
    s->nav_x = c.x;
    s->nav_y = c.y;
    s->nav_depth = c.depth;
    /* channel model */
    if (param_d(app, "sound_speed", &c.sound_speed, 1, 10000) < 0 ||
        param_d(app, "loss_probability", &c.loss_probability, 0, 1) < 0 ||
        param_d(app, "loss", &c.loss_probability, 0, 1) < 0 || param_d(app, "max_range", &c.max_range, 0, 1e7) < 0 ||
        param_d(app, "ci_seconds", &c.ci_seconds, 0, 60) < 0 || param_d(app, "mini_seconds", &c.mini_seconds, 0, 60) < 0 ||
        param_d(app, "turnaround_seconds", &c.turnaround_seconds, 0, 60) < 0 ||
        param_d(app, "drq_timeout", &c.drq_timeout_seconds, 0, 60) < 0 ||
        param_d(app, "ping_timeout", &c.ping_timeout_seconds, 0, 600) < 0 ||
        param_d(app, "rev_interval", &c.rev_interval_seconds, 0, 86400) < 0)
        return -1;
    d = 1;
    if (param_d(app, "seed", &d, 0, 1.8e19) < 0) return -1;
    c.seed = (uint64_t)d;
    if (kelp_app_param_bool(app, "clock_set_at_boot", &c.clock_set_at_boot) < 0) return -1;
    static char rev[24];
    if (kelp_app_param_str(app, "revision", rev, sizeof rev) > 0) c.revision = rev;
    for (const kelp_mission_node *n = kelp_app_param_next(app, "lbl_beacon", NULL); n;
         n = kelp_app_param_next(app, "lbl_beacon", n)) {
        if (c.n_lbl >= 4) return kelp_app_config_error(app, n, "at most 4 lbl_beacon lines (A..D)");
        if (kelp_mission_copy(n, buf, sizeof buf) < 0 ||
            parse_xyz(buf, &c.lbl_x[c.n_lbl], &c.lbl_y[c.n_lbl], &c.lbl_depth[c.n_lbl]) < 0)
            return kelp_app_config_error(app, n, "lbl_beacon must be x=..,y=..[,depth=..]");
        c.n_lbl++;
    }
    snprintf(s->channel_var, sizeof s->channel_var, "%s", DEFAULT_CHANNEL);
    (void)kelp_app_param_str(app, "channel_var", s->channel_var, sizeof s->channel_var);
    (void)kelp_app_param_str(app, "channel_url", s->channel_url, sizeof s->channel_url);
    s->publish_events = true;
    if (kelp_app_param_bool(app, "publish_events", &s->publish_events) < 0) return -1;
    c.instance = make_instance();
    kelp_msim_ops ops = { host_write, channel_tx, on_event };
    int64_t now = us_of(kelp_app_time(app));
    if ((rc = kelp_msim_init(&s->m, &c, &ops, s, now)) < 0)
        return kelp_app_config_error(app, NULL, "bad modem configuration: %s", kelp_strerror(rc));
    /* the host link */
    if (s->tcp_port) {
        if (open_tcp(s) < 0) return kelp_app_config_error(app, NULL, "cannot listen on TCP port %u", s->tcp_port);
        if (kelp_app_watch_fd(app, s->ep, on_tcp) < 0) return -1;
        printf("%s: modem %d listening on TCP port %u\n", kelp_app_name(app), s->modem_id, s->tcp_port);
    } else {
        if (open_pty(s) < 0) return kelp_app_config_error(app, NULL, "cannot create the pseudo-terminal");
        if (kelp_app_watch_fd(app, s->master, on_pty) < 0) return -1;
        printf("%s: modem %d on %s%s%s\n", kelp_app_name(app), s->modem_id, s->pty_name, s->pty_link[0] ? " link " : "",
               s->pty_link);
    }
    fflush(stdout);
    /* the channel: the community bus, or a bus of its own shared by several communities */
    if (s->channel_url[0]) {
        char url[512], err[600];
        /* not kelp_lcm_url (it prefers $KELP_LCM_URL): the channel URL is explicit */
        if (strncmp(s->channel_url, "udpm://", 7) == 0 && !strstr(s->channel_url, "recv_buf_size"))
            snprintf(url, sizeof url, "%s%crecv_buf_size=%d", s->channel_url, strchr(s->channel_url, '?') ? '&' : '?',
                     KELP_LCM_RECV_BUF);
        else
            snprintf(url, sizeof url, "%s", s->channel_url);
        s->chan = kelp_lcmbus_open(url, kelp_app_name(app), "acomms_channel", on_chan_var, s, err, sizeof err);
        if (!s->chan) return kelp_app_config_error(app, kelp_app_param(app, "channel_url"), "channel: %s", err);
        if (kelp_bus_register(kelp_lcmbus_bus(s->chan), s->channel_var, 0, kelp_app_time(app)) < 0) return -1;
        if (kelp_app_watch_fd(app, kelp_lcmbus_fd(s->chan), on_chan_fd) < 0) return -1;
    } else if (kelp_app_register(app, s->channel_var, 0) < 0) {
        return -1;
    }
    if (s->node_report_var[0] && kelp_app_register(app, s->node_report_var, 0) < 0) return -1;
    if (s->nav_vars && (kelp_app_register(app, "NAV_X", 0) < 0 || kelp_app_register(app, "NAV_Y", 0) < 0 ||
                        kelp_app_register(app, "NAV_DEPTH", 0) < 0))
        return -1;
    kelp_msim_boot(&s->m, now);
    kelp_app_event(app, "modem %d at x=%.1f y=%.1f depth=%.1f, loss %.2f, channel %s%s%s", s->modem_id, c.x, c.y,
                   c.depth, c.loss_probability, s->channel_var, s->channel_url[0] ? " on " : "", s->channel_url);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    msim_app *s = st;
    (void)app;
    if (!s->chan && strcmp(v->name, s->channel_var) == 0) {
        channel_rx(s, v);
    } else if (s->node_report_var[0] && strcmp(v->name, s->node_report_var) == 0 && v->kind == KELP_VAR_STRING) {
        char b[64];
        double x, y, dep = s->nav_depth;
        if (kelp_kv_get(v->sval, ',', "X", b, sizeof b) == 1 && kelp_parse_double(b, strlen(b), &x) == 0 &&
            kelp_kv_get(v->sval, ',', "Y", b, sizeof b) == 1 && kelp_parse_double(b, strlen(b), &y) == 0) {
            if (kelp_kv_get(v->sval, ',', "DEP", b, sizeof b) == 1 && kelp_parse_double(b, strlen(b), &dep) < 0)
                dep = s->nav_depth;
            s->nav_x = x;
            s->nav_y = y;
            s->nav_depth = dep;
            kelp_msim_set_position(&s->m, x, y, dep);
        } else {
            kelp_app_run_warning(app, "%s without X= and Y=: position unchanged", v->name);
        }
    } else if (s->nav_vars && v->kind == KELP_VAR_DOUBLE) {
        if (!strcmp(v->name, "NAV_X")) s->nav_x = v->dval;
        else if (!strcmp(v->name, "NAV_Y")) s->nav_y = v->dval;
        else if (!strcmp(v->name, "NAV_DEPTH")) s->nav_depth = v->dval;
        kelp_msim_set_position(&s->m, s->nav_x, s->nav_y, s->nav_depth);
    }
}

static int iterate(kelp_app *app, void *st, double now)
{
    msim_app *s = st;
    kelp_msim_tick(&s->m, us_of(now));
    if (now - s->last_status >= 2.0) {
        const kelp_msim_counters *c = kelp_msim_get_counters(&s->m);
        (void)kelp_app_notify_stringf(app, "MODEMSIM_STATUS",
                                      "modem=%d,port=%s,host_lines=%u,host_errors=%u,tx_data=%u,rx_frames=%u,"
                                      "acks=%u,lost_random=%u,lost_collision=%u,lost_half_duplex=%u",
                                      kelp_msim_src(&s->m), s->tcp_port ? "tcp" : s->pty_name, c->host_lines,
                                      c->host_errors, c->tx[KELP_MSIM_PKT_DATA], c->frames_rx, c->acks_out,
                                      c->lost_random, c->lost_collision, c->lost_half_duplex);
        s->last_status = now;
    }
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    msim_app *s = st;
    (void)app;
    const kelp_msim_counters *c = kelp_msim_get_counters(&s->m);
    if (s->tcp_port)
        fprintf(out, "modem %d (SRC %d) on TCP port %u, host %s\n", s->modem_id, kelp_msim_src(&s->m), s->tcp_port,
                s->cfd >= 0 ? "connected" : "not connected");
    else
        fprintf(out, "modem %d (SRC %d) on %s%s%s\n", s->modem_id, kelp_msim_src(&s->m), s->pty_name,
                s->pty_link[0] ? " <- " : "", s->pty_link);
    fprintf(out, "position x=%.1f y=%.1f depth=%.1f\n", s->m.x, s->m.y, s->m.depth);
    fprintf(out, "host: %u lines in, %u out, %u errors; bytes in %lu out %lu dropped %lu\n", c->host_lines,
            c->host_out, c->host_errors, s->bytes_in, s->bytes_out, s->dropped_out);
    fprintf(out, "sent: cycle_init %u data %u (%u frames) ack %u ping %u reply %u mini %u\n", c->tx[1], c->tx[2],
            c->frames_tx, c->tx[3], c->tx[4], c->tx[5], c->tx[6]);
    fprintf(out, "heard: cycle_init %u data %u (%u frames) ack %u ping %u reply %u mini %u; acks to host %u\n",
            c->rx[1], c->rx[2], c->frames_rx, c->rx[3], c->rx[4], c->rx[5], c->rx[6], c->acks_out);
    fprintf(out, "lost: random %u collision %u half_duplex %u stale %u; out of range %u; overflow %u\n",
            c->lost_random, c->lost_collision, c->lost_half_duplex, c->lost_stale, c->out_of_range, c->overflow);
    fprintf(out, "channel %s: %lu packets out, %lu in, %lu malformed, %lu retained replays ignored\n", s->channel_var,
            s->pkts_out, s->pkts_in, s->pkts_bad, s->pkts_sync_ignored);
}

static void shutdown_app(kelp_app *app, void *st)
{
    msim_app *s = st;
    (void)app;
    if (s->pty_link[0]) {
        char target[256];
        ssize_t n = readlink(s->pty_link, target, sizeof target - 1);
        if (n > 0) {
            target[n] = '\0';
            if (strcmp(target, s->pty_name) == 0) unlink(s->pty_link);
        }
    }
    close_client(s);
    if (s->lfd >= 0) close(s->lfd);
    if (s->ep >= 0) close(s->ep);
    if (s->master >= 0) close(s->master);
    if (s->slave >= 0) close(s->slave);
    if (s->chan) kelp_lcmbus_close(s->chan);
}

static const kelp_app_def def = {
    .name = "kelp-modemsim",
    .purpose = "Simulated WHOI Micro-Modem (iModemSim): the modem side of the Micro-Modem NMEA protocol on a "
               "pseudo-terminal or TCP port; modems share a simulated acoustic channel over the bus.",
    .params = (const kelp_app_param_info[]){
        { "modem_id", "1", "required: initial NVRAM SRC, 1..31 (the host sets it with $CCCFG,SRC)", NULL },
        { "pty_link", "/tmp/ttyMM1", "symlink to the pseudo-terminal the host opens", NULL },
        { "Port", "/tmp/ttyMM1", "iModemSim's name for pty_link", "pty_link" },
        { "Speed", "19200", "iModemSim's baud: accepted, ignored (a pty has none)", NULL },
        { "tcp_port", "50010", "serve the host on this TCP port instead of a pty", "pty_link" },
        { "position", "x=0,y=0,depth=0", "fixed position, m", NULL },
        { "x", "0", "m (also ConstantPosX)", NULL },
        { "y", "0", "m (also ConstantPosY)", NULL },
        { "depth", "0", "m (also ConstantDepth)", NULL },
        { "ConstantPosX", "0", "iModemSim's x", NULL },
        { "ConstantPosY", "0", "iModemSim's y", NULL },
        { "ConstantDepth", "0", "iModemSim's depth", NULL },
        { "InputLocType", "Constant", "iModemSim's: accepted, ignored", NULL },
        { "node_report_var", "NODE_REPORT_LOCAL", "follow the vehicle: X=, Y=, DEP= of this variable (optional)", NULL },
        { "nav_vars", "false", "true: follow NAV_X, NAV_Y, NAV_DEPTH", NULL },
        { "sound_speed", "1500", "m/s", NULL },
        { "loss", "0", "probability of losing a packet or data frame, 0..1 (seeded)", NULL },
        { "loss_probability", "0", "same as loss", NULL },
        { "seed", "1", "random seed of the channel", NULL },
        { "max_range", "0", "m, 0 = unlimited", NULL },
        { "ci_seconds", "1.0", "cycle-init packet length, s", NULL },
        { "mini_seconds", "0.5", "ack, ping and mini-packet length, s", NULL },
        { "turnaround_seconds", "0.25", "s", NULL },
        { "drq_timeout", "2", "s to wait for $CCTXD after $CADRQ", NULL },
        { "ping_timeout", "10", "s to wait for a ping reply", NULL },
        { "rev_interval", "60", "$CAREV heartbeat period while a host talks, s (0 = off)", NULL },
        { "clock_set_at_boot", "false", "true: the modem clock starts set", NULL },
        { "revision", "0.93.0.52", "firmware revision in $CAREV", NULL },
        { "lbl_beacon", "x=1000,y=0,depth=50", "repeatable (up to 4): REMUS LBL transponders A..D for $CCPDT", NULL },
        { "channel_var", "ACOMMS_SIM_CHANNEL", "where transmissions travel", NULL },
        { "channel_url", "udpm://239.255.76.67:7690?ttl=0", "a channel bus shared by communities (optional)", NULL },
        { "publish_events", "true", "ACOMMS_SIM_EVENT per transmission, reception and loss", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "ACOMMS_SIM_CHANNEL", "(binary channel packet)", "<channel_var>; or on channel_url" },
        { "NODE_REPORT_LOCAL", "NAME=alpha,X=10,Y=-20,DEP=5", "<node_report_var>, when set" },
        { "NAV_X", "10", "with nav_vars = true" },
        { "NAV_Y", "-20", "with nav_vars = true" },
        { "NAV_DEPTH", "5", "with nav_vars = true" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "ACOMMS_SIM_CHANNEL", "(binary channel packet)", "<channel_var>: each transmission" },
        { "ACOMMS_SIM_EVENT", "event=tx,src=1,dest=2,rate=0,time=12.5", "with publish_events = true" },
        { "MODEMSIM_STATUS", "modem=1,port=/dev/pts/3,host_lines=12,host_errors=0,tx_data=3,rx_frames=2,acks=1,"
          "lost_random=0,lost_collision=0,lost_half_duplex=0", "every 2 s" },
        { NULL, NULL, NULL } },
    .notes = "Host link: a pseudo-terminal (pty_link) or TCP (tcp_port) speaking WHOI Micro-Modem NMEA:\n"
             "  in  $CCCLK $CCCFG $CCCFQ $CCCYC $CCTXD $CCMPC $CCMUC $CCPDT\n"
             "  out $CACLK $CACFG $CACYC $CADRQ $CATXD $CATXP $CATXF $CARXD $CAACK $CAMPC $CAMPA $CAMPR\n"
             "      $CAMUC $CAMUA $SNPDT $SNTTA $CAREV $CAERR\n"
             "Run it as iModemSim with: Run = kelp-modemsim ~ iModemSim\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown_app,
};

int main(int argc, char **argv)
{
    static msim_app s;
    return kelp_app_run(argc, argv, &def, &s);
}
