/* kelp links: serial (libserialport, termios fallback for ptys), TCP client, TCP server.
 *
 * Why an epoll set as the public fd: the app runner registers a descriptor once and has no way
 * to unregister it; the device fd changes at every reconnect (and a tcp server has a listening
 * socket and a client socket).  An epoll fd is itself pollable and level-triggered, so it stays
 * readable exactly while one of its members is, and it never changes. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <netdb.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <unistd.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>

#include <libserialport.h>

#include <kelp/link.h>

#define LINK_ERR_CAP 256
#define LINK_DESC_CAP 600
#define LINK_CONNECT_TIMEOUT_MS 1000

struct kelp_link {
    kelp_link_cfg cfg;
    char device[PATH_MAX];
    char host[256];
    const kelp_link_ops *ops;
    int ep;                 /* the stable epoll descriptor */
    int fd;                 /* device / connected socket, -1 when down */
    int lfd;                /* tcp server: listening socket, -1 when not listening */
    struct sp_port *sp;     /* libserialport handle when that back end opened the device */
    bool just_connected;
    bool retry_armed;
    double next_retry;
    unsigned bound_port;
    char backend[16];
    char err[LINK_ERR_CAP];
    char desc[LINK_DESC_CAP];
    kelp_link_counters count;
};

static void set_err(kelp_link *l, const char *fmt, ...) KELP_PRINTF(2, 3);
static void set_err(kelp_link *l, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(l->err, sizeof l->err, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized): va_start above */
    va_end(ap);
}

static int ep_add(kelp_link *l, int fd)
{
    struct epoll_event ev;
    memset(&ev, 0, sizeof ev);
    ev.events = EPOLLIN;
    ev.data.fd = fd;
    if (epoll_ctl(l->ep, EPOLL_CTL_ADD, fd, &ev) < 0) {
        set_err(l, "epoll_ctl: %s", strerror(errno));
        return KELP_ERR_IO;
    }
    return KELP_OK;
}

static void ep_del(kelp_link *l, int fd)
{
    if (fd >= 0) (void)epoll_ctl(l->ep, EPOLL_CTL_DEL, fd, NULL);
}

static int set_nonblock(int fd)
{
    int fl = fcntl(fd, F_GETFL);
    if (fl < 0 || fcntl(fd, F_SETFL, fl | O_NONBLOCK) < 0) return KELP_ERR_IO;
    return KELP_OK;
}

/* drop the device (or client) descriptor; the listening socket stays */
static void drop_fd(kelp_link *l)
{
    if (l->fd < 0) return;
    ep_del(l, l->fd);
    if (l->sp) {
        (void)sp_close(l->sp);
        sp_free_port(l->sp);
        l->sp = NULL;
    } else {
        close(l->fd);
    }
    l->fd = -1;
}

static void lost(kelp_link *l, const char *why)
{
    set_err(l, "%s", why);
    l->count.disconnects++;
    l->just_connected = false; /* a connection nobody saw is not news any more */
    drop_fd(l);
}

/* ------------------------------------------------------------------ serial */

static speed_t speed_of(unsigned baud)
{
    switch (baud) {
    case 300: return B300;
    case 600: return B600;
    case 1200: return B1200;
    case 2400: return B2400;
    case 4800: return B4800;
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    default: return 0;
    }
}

static int open_libserialport(kelp_link *l, const char *path)
{
    struct sp_port *p = NULL;
    if (sp_get_port_by_name(path, &p) != SP_OK) {
        char *m = sp_last_error_message();
        set_err(l, "libserialport: %s: %s", path, m ? m : "cannot look up port");
        if (m) sp_free_error_message(m);
        return KELP_ERR_IO;
    }
    if (sp_open(p, SP_MODE_READ_WRITE) != SP_OK) {
        char *m = sp_last_error_message();
        set_err(l, "libserialport: cannot open %s: %s", path, m ? m : "?");
        if (m) sp_free_error_message(m);
        sp_free_port(p);
        return KELP_ERR_IO;
    }
    int fd = -1;
    if (sp_set_baudrate(p, (int)l->cfg.baud) != SP_OK || sp_set_bits(p, 8) != SP_OK ||
        sp_set_parity(p, SP_PARITY_NONE) != SP_OK || sp_set_stopbits(p, 1) != SP_OK ||
        sp_set_flowcontrol(p, SP_FLOWCONTROL_NONE) != SP_OK || sp_get_port_handle(p, &fd) != SP_OK || fd < 0 ||
        set_nonblock(fd) != KELP_OK) {
        char *m = sp_last_error_message();
        set_err(l, "libserialport: cannot configure %s: %s", path, m ? m : "?");
        if (m) sp_free_error_message(m);
        (void)sp_close(p);
        sp_free_port(p);
        return KELP_ERR_IO;
    }
    l->sp = p;
    l->fd = fd;
    snprintf(l->backend, sizeof l->backend, "libserialport");
    return KELP_OK;
}

static int open_termios(kelp_link *l, const char *path)
{
    int fd = open(path, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        set_err(l, "cannot open %s: %s", path, strerror(errno));
        return KELP_ERR_IO;
    }
    if (!isatty(fd)) {
        set_err(l, "%s is not a terminal", path);
        close(fd);
        return KELP_ERR_IO;
    }
    struct termios t;
    if (tcgetattr(fd, &t) < 0) {
        set_err(l, "tcgetattr %s: %s", path, strerror(errno));
        close(fd);
        return KELP_ERR_IO;
    }
    cfmakeraw(&t);
    t.c_cflag &= ~(tcflag_t)(CSIZE | PARENB | CSTOPB | CRTSCTS);
    t.c_cflag |= CS8 | CLOCAL | CREAD;
    t.c_iflag &= ~(tcflag_t)(IXON | IXOFF | IXANY);
    t.c_cc[VMIN] = 1; /* with O_NONBLOCK: EAGAIN when empty (VMIN 0 would read 0 = "EOF") */
    t.c_cc[VTIME] = 0;
    speed_t sp = speed_of(l->cfg.baud);
    if (cfsetispeed(&t, sp) < 0 || cfsetospeed(&t, sp) < 0 || tcsetattr(fd, TCSANOW, &t) < 0) {
        set_err(l, "cannot configure %s: %s", path, strerror(errno));
        close(fd);
        return KELP_ERR_IO;
    }
    l->fd = fd;
    snprintf(l->backend, sizeof l->backend, "termios");
    return KELP_OK;
}

static int serial_open(kelp_link *l)
{
    char real[PATH_MAX];
    if (l->fd >= 0) return KELP_OK;
    /* resolve a socat link= name again each time: a re-created pty has a new /dev/pts/N */
    if (!realpath(l->device, real)) {
        set_err(l, "%s: %s", l->device, strerror(errno));
        return KELP_ERR_IO;
    }
    int rc = KELP_ERR_IO;
    char first[LINK_ERR_CAP] = "";
    if (l->cfg.backend != KELP_LINK_BACKEND_TERMIOS) {
        rc = open_libserialport(l, real);
        if (rc) snprintf(first, sizeof first, "%s", l->err);
    }
    if (rc && l->cfg.backend != KELP_LINK_BACKEND_LIBSERIALPORT) {
        rc = open_termios(l, real);
        if (rc && first[0]) {
            char second[LINK_ERR_CAP];
            snprintf(second, sizeof second, "%s", l->err);
            set_err(l, "%.120s; %.120s", first, second);
        }
    }
    if (rc) return rc;
    rc = ep_add(l, l->fd);
    if (rc) {
        drop_fd(l);
        return rc;
    }
    snprintf(l->desc, sizeof l->desc, "serial %.250s (%.250s) %u 8N1 (%s)", l->device, real, l->cfg.baud, l->backend);
    return KELP_OK;
}

/* ------------------------------------------------------------------ tcp */

static int tcp_client_open(kelp_link *l)
{
    if (l->fd >= 0) return KELP_OK;
    struct addrinfo hints, *res = NULL;
    char port[16];
    memset(&hints, 0, sizeof hints);
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_STREAM;
    snprintf(port, sizeof port, "%u", l->cfg.port);
    int g = getaddrinfo(l->host, port, &hints, &res);
    if (g != 0 || !res) {
        set_err(l, "cannot resolve %s: %s", l->host, gai_strerror(g));
        return KELP_ERR_NOTFOUND;
    }
    int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) {
        freeaddrinfo(res);
        set_err(l, "socket: %s", strerror(errno));
        return KELP_ERR_IO;
    }
    int rc = connect(fd, res->ai_addr, res->ai_addrlen);
    freeaddrinfo(res);
    if (rc < 0 && errno == EINPROGRESS) {
        struct pollfd pf = { fd, POLLOUT, 0 };
        int tmo = l->cfg.write_timeout_ms > 0 ? l->cfg.write_timeout_ms * 2 : LINK_CONNECT_TIMEOUT_MS;
        if (tmo > LINK_CONNECT_TIMEOUT_MS) tmo = LINK_CONNECT_TIMEOUT_MS;
        int n = poll(&pf, 1, tmo);
        int soerr = 0;
        socklen_t sl = sizeof soerr;
        if (n <= 0) {
            soerr = n == 0 ? ETIMEDOUT : errno;
        } else if (getsockopt(fd, SOL_SOCKET, SO_ERROR, &soerr, &sl) < 0) {
            soerr = errno;
        }
        rc = soerr ? -1 : 0;
        errno = soerr;
    }
    if (rc < 0) {
        set_err(l, "cannot connect to %s:%u: %s", l->host, l->cfg.port, strerror(errno));
        close(fd);
        return KELP_ERR_IO;
    }
    /* nobody listening on a local ephemeral port can give a TCP "simultaneous open" with
     * ourselves (source port == destination port): that is not a modem */
    struct sockaddr_in me, peer;
    memset(&me, 0, sizeof me);
    memset(&peer, 0, sizeof peer);
    socklen_t ml = sizeof me, pl = sizeof peer;
    if (getsockname(fd, (struct sockaddr *)&me, &ml) == 0 && getpeername(fd, (struct sockaddr *)&peer, &pl) == 0 &&
        me.sin_port == peer.sin_port && me.sin_addr.s_addr == peer.sin_addr.s_addr) {
        set_err(l, "cannot connect to %s:%u: Connection refused (self-connection)", l->host, l->cfg.port);
        close(fd);
        return KELP_ERR_IO;
    }
    int one = 1;
    (void)setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    l->fd = fd;
    rc = ep_add(l, fd);
    if (rc) {
        drop_fd(l);
        return rc;
    }
    snprintf(l->desc, sizeof l->desc, "tcp client %s:%u", l->host, l->cfg.port);
    return KELP_OK;
}

static int tcp_server_open(kelp_link *l)
{
    if (l->lfd >= 0) return KELP_OK;
    int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) {
        set_err(l, "socket: %s", strerror(errno));
        return KELP_ERR_IO;
    }
    int one = 1;
    (void)setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    a.sin_port = htons((uint16_t)l->cfg.port);
    if (bind(fd, (struct sockaddr *)&a, sizeof a) < 0 || listen(fd, 4) < 0) {
        set_err(l, "cannot listen on port %u: %s", l->cfg.port, strerror(errno));
        close(fd);
        return KELP_ERR_IO;
    }
    socklen_t al = sizeof a;
    if (getsockname(fd, (struct sockaddr *)&a, &al) == 0) l->bound_port = ntohs(a.sin_port);
    l->lfd = fd;
    int rc = ep_add(l, fd);
    if (rc) {
        close(fd);
        l->lfd = -1;
        return rc;
    }
    snprintf(l->desc, sizeof l->desc, "tcp server port %u", l->bound_port);
    return KELP_OK;
}

/* accept a waiting connection; it replaces the current one */
static void tcp_server_accept(kelp_link *l)
{
    if (l->lfd < 0) return;
    for (;;) {
        int c = accept4(l->lfd, NULL, NULL, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (c < 0) return;
        if (l->fd >= 0) lost(l, "replaced by a new connection");
        int one = 1;
        (void)setsockopt(c, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        l->fd = c;
        if (ep_add(l, c) != KELP_OK) {
            close(c);
            l->fd = -1;
            return;
        }
        l->count.opens++;
        l->just_connected = true;
        l->err[0] = '\0';
    }
}

/* ------------------------------------------------------------------ common ops */

static int op_open(kelp_link *l)
{
    int rc;
    switch (l->cfg.type) {
    case KELP_LINK_SERIAL: rc = serial_open(l); break;
    case KELP_LINK_TCP_CLIENT: rc = tcp_client_open(l); break;
    case KELP_LINK_TCP_SERVER: rc = tcp_server_open(l); break;
    default: rc = KELP_ERR_ARG; break;
    }
    if (rc) {
        l->count.open_failures++;
        return rc;
    }
    if (l->cfg.type != KELP_LINK_TCP_SERVER) {
        l->count.opens++;
        l->just_connected = true;
        l->err[0] = '\0';
    }
    return KELP_OK;
}

static int op_read(kelp_link *l, uint8_t *buf, size_t cap, size_t *n)
{
    *n = 0;
    if (l->cfg.type == KELP_LINK_TCP_SERVER) tcp_server_accept(l);
    if (l->fd < 0) return l->cfg.type == KELP_LINK_TCP_SERVER ? KELP_OK : KELP_ERR_STATE;
    if (cap == 0) return KELP_OK;
    ssize_t r = read(l->fd, buf, cap);
    if (r > 0) {
        *n = (size_t)r;
        l->count.bytes_in += (uint64_t)r;
        return KELP_OK;
    }
    if (r == 0 && l->cfg.type != KELP_LINK_SERIAL) {
        lost(l, "connection closed by peer");
        return KELP_ERR_IO;
    }
    /* a tty read of 0 bytes is "nothing now" (VMIN 0), not end of file: look for a hang-up */
    if (r == 0 || errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) {
        /* nothing to read: but a hung-up device keeps the epoll set readable, so look */
        struct pollfd pf = { l->fd, POLLIN, 0 };
        if (poll(&pf, 1, 0) > 0 && (pf.revents & (POLLHUP | POLLERR | POLLNVAL))) {
            lost(l, "device hung up");
            return KELP_ERR_IO;
        }
        return KELP_OK;
    }
    char why[128];
    snprintf(why, sizeof why, "read: %s", strerror(errno));
    lost(l, why);
    return KELP_ERR_IO;
}

static int op_write(kelp_link *l, const uint8_t *buf, size_t n)
{
    if (l->fd < 0) {
        set_err(l, "write while not connected");
        return KELP_ERR_STATE;
    }
    size_t off = 0;
    while (off < n) {
        ssize_t w = write(l->fd, buf + off, n - off);
        if (w > 0) {
            off += (size_t)w;
            l->count.bytes_out += (uint64_t)w;
            continue;
        }
        if (w < 0 && errno == EINTR) continue;
        if (w < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            struct pollfd pf = { l->fd, POLLOUT, 0 };
            int p = poll(&pf, 1, l->cfg.write_timeout_ms);
            if (p > 0 && (pf.revents & POLLOUT)) continue;
            l->count.write_errors++;
            set_err(l, "write timed out (device not reading)");
            return KELP_ERR_TIMEOUT;
        }
        l->count.write_errors++;
        char why[128];
        snprintf(why, sizeof why, "write: %s", w < 0 ? strerror(errno) : "no progress");
        lost(l, why);
        return KELP_ERR_IO;
    }
    return KELP_OK;
}

static void op_close(kelp_link *l)
{
    drop_fd(l);
}

static int op_fd(const kelp_link *l)
{
    return l->ep;
}

static const kelp_link_ops LINK_OPS = { op_open, op_read, op_write, op_close, op_fd };

/* ------------------------------------------------------------------ public */

void kelp_link_cfg_default(kelp_link_cfg *cfg, kelp_link_type type)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->type = type;
    cfg->baud = 19200;
    cfg->backend = KELP_LINK_BACKEND_AUTO;
    cfg->reconnect_s = 1.0;
    cfg->write_timeout_ms = 500;
}

kelp_link *kelp_link_create(const kelp_link_cfg *cfg, kelp_diag *d)
{
    if (!cfg) {
        (void)kelp_fail(d, KELP_ERR_ARG, "no link configuration");
        return NULL;
    }
    if (cfg->type == KELP_LINK_SERIAL) {
        if (!cfg->device || !cfg->device[0]) {
            (void)kelp_fail(d, KELP_ERR_ARG, "serial link without a device path");
            return NULL;
        }
        if (strlen(cfg->device) >= PATH_MAX) {
            (void)kelp_fail(d, KELP_ERR_ARG, "serial device path too long");
            return NULL;
        }
        if (speed_of(cfg->baud ? cfg->baud : 19200) == 0) {
            (void)kelp_failf(d, KELP_ERR_UNSUPPORTED, "unsupported baud rate %u", cfg->baud);
            return NULL;
        }
    } else if (cfg->type == KELP_LINK_TCP_CLIENT) {
        if (!cfg->host || !cfg->host[0] || strlen(cfg->host) >= 256) {
            (void)kelp_fail(d, KELP_ERR_ARG, "tcp client link needs a server address");
            return NULL;
        }
        if (cfg->port == 0 || cfg->port > 65535) {
            (void)kelp_fail(d, KELP_ERR_ARG, "tcp client link needs a port 1..65535");
            return NULL;
        }
    } else if (cfg->type == KELP_LINK_TCP_SERVER) {
        if (cfg->port > 65535) {
            (void)kelp_fail(d, KELP_ERR_ARG, "tcp server port out of range");
            return NULL;
        }
    } else {
        (void)kelp_fail(d, KELP_ERR_ARG, "unknown link type");
        return NULL;
    }
    kelp_link *l = calloc(1, sizeof *l);
    if (!l) {
        (void)kelp_fail(d, KELP_ERR_NOSPACE, "out of memory");
        return NULL;
    }
    l->cfg = *cfg;
    if (!l->cfg.baud) l->cfg.baud = 19200;
    if (!(l->cfg.reconnect_s > 0)) l->cfg.reconnect_s = 1.0;
    if (l->cfg.write_timeout_ms <= 0) l->cfg.write_timeout_ms = 500;
    if (cfg->device) snprintf(l->device, sizeof l->device, "%s", cfg->device);
    if (cfg->host) snprintf(l->host, sizeof l->host, "%s", cfg->host);
    l->cfg.device = l->device;
    l->cfg.host = l->host;
    l->ops = &LINK_OPS;
    l->fd = -1;
    l->lfd = -1;
    l->ep = epoll_create1(EPOLL_CLOEXEC);
    if (l->ep < 0) {
        (void)kelp_failf(d, KELP_ERR_IO, "epoll_create1: %s", strerror(errno));
        free(l);
        return NULL;
    }
    switch (cfg->type) {
    case KELP_LINK_SERIAL: snprintf(l->desc, sizeof l->desc, "serial %.500s %u 8N1", l->device, l->cfg.baud); break;
    case KELP_LINK_TCP_CLIENT: snprintf(l->desc, sizeof l->desc, "tcp client %s:%u", l->host, l->cfg.port); break;
    default: snprintf(l->desc, sizeof l->desc, "tcp server port %u", l->cfg.port); break;
    }
    if (kelp_link_open(l) != KELP_OK) {
        /* not there yet is fine: kelp_link_service() retries */
    }
    return l;
}

void kelp_link_destroy(kelp_link *l)
{
    if (!l) return;
    drop_fd(l);
    if (l->lfd >= 0) close(l->lfd);
    if (l->ep >= 0) close(l->ep);
    free(l);
}

const kelp_link_ops *kelp_link_get_ops(const kelp_link *l)
{
    return l ? l->ops : NULL;
}

int kelp_link_open(kelp_link *l)
{
    if (!l) return KELP_ERR_ARG;
    return l->ops->open(l);
}

int kelp_link_read(kelp_link *l, uint8_t *buf, size_t cap, size_t *n)
{
    if (!l || !n || (cap && !buf)) return KELP_ERR_ARG;
    int rc = l->ops->read(l, buf, cap, n);
    return rc == KELP_ERR_STATE ? KELP_OK : rc;
}

int kelp_link_write(kelp_link *l, const void *buf, size_t n)
{
    if (!l || (n && !buf)) return KELP_ERR_ARG;
    return l->ops->write(l, buf, n);
}

void kelp_link_close(kelp_link *l)
{
    if (l) l->ops->close(l);
}

int kelp_link_fd(const kelp_link *l)
{
    return l ? l->ops->fd(l) : -1;
}

int kelp_link_service(kelp_link *l, double now)
{
    if (!l) return 0;
    bool down = l->cfg.type == KELP_LINK_TCP_SERVER ? l->lfd < 0 : l->fd < 0;
    if (down) {
        if (!l->retry_armed || now >= l->next_retry) {
            if (kelp_link_open(l) != KELP_OK) {
                l->retry_armed = true;
                l->next_retry = now + l->cfg.reconnect_s;
            } else {
                l->retry_armed = false;
            }
        }
    }
    if (l->cfg.type == KELP_LINK_TCP_SERVER) tcp_server_accept(l);
    if (l->just_connected) {
        l->just_connected = false;
        return 1;
    }
    return 0;
}

bool kelp_link_connected(const kelp_link *l)
{
    return l && l->fd >= 0;
}

bool kelp_link_listening(const kelp_link *l)
{
    return l && l->lfd >= 0 && l->fd < 0;
}

const char *kelp_link_error(const kelp_link *l)
{
    return l ? l->err : "";
}

const char *kelp_link_describe(const kelp_link *l)
{
    return l ? l->desc : "";
}

const kelp_link_counters *kelp_link_get_counters(const kelp_link *l)
{
    return l ? &l->count : NULL;
}

const char *kelp_link_backend(const kelp_link *l)
{
    return l ? l->backend : "";
}

unsigned kelp_link_bound_port(const kelp_link *l)
{
    return l ? l->bound_port : 0;
}
