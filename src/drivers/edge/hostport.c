/* The device side of a serial line: a pseudo-terminal or a one-client TCP server. */
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <pty.h>
#include <stdio.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <kelp/edge/hostport.h>

static void reset(kelp_hostport *h)
{
    memset(h, 0, sizeof *h);
    h->master = h->slave = h->lfd = h->cfd = h->ep = -1;
}

int kelp_hostport_open_pty(kelp_hostport *h, const char *link, kelp_diag *d)
{
    reset(h);
    if (openpty(&h->master, &h->slave, h->pty_name, NULL, NULL) < 0) {
        (void)kelp_failf(d, KELP_ERR_IO, "openpty: %s", strerror(errno));
        return -1;
    }
    /* raw: no echo, no CR/LF translation (the host reads lines ending in CR) */
    struct termios t;
    if (tcgetattr(h->slave, &t) == 0) {
        cfmakeraw(&t);
        cfsetispeed(&t, B19200);
        cfsetospeed(&t, B19200);
        tcsetattr(h->slave, TCSANOW, &t);
    }
    fcntl(h->master, F_SETFL, fcntl(h->master, F_GETFL) | O_NONBLOCK);
    fcntl(h->master, F_SETFD, FD_CLOEXEC);
    fcntl(h->slave, F_SETFD, FD_CLOEXEC);
    /* we keep our slave fd open, so the master never sees a hang-up when the host closes and
     * re-opens the port */
    if (link && link[0]) {
        struct stat st;
        if (lstat(link, &st) == 0) {
            if (!S_ISLNK(st.st_mode)) {
                (void)kelp_failf(d, KELP_ERR_IO, "%s exists and is not a symbolic link: not replaced", link);
                kelp_hostport_close(h);
                return -1;
            }
            unlink(link);
        }
        if (symlink(h->pty_name, link) < 0) {
            (void)kelp_failf(d, KELP_ERR_IO, "symlink %s -> %s: %s", link, h->pty_name, strerror(errno));
            kelp_hostport_close(h);
            return -1;
        }
        snprintf(h->link, sizeof h->link, "%s", link);
    }
    return 0;
}

int kelp_hostport_open_tcp(kelp_hostport *h, unsigned port, kelp_diag *d)
{
    reset(h);
    h->lfd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (h->lfd < 0) {
        (void)kelp_failf(d, KELP_ERR_IO, "socket: %s", strerror(errno));
        return -1;
    }
    int one = 1;
    setsockopt(h->lfd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    a.sin_port = htons((uint16_t)port);
    socklen_t al = sizeof a;
    if (bind(h->lfd, (struct sockaddr *)&a, sizeof a) < 0 || listen(h->lfd, 2) < 0 ||
        getsockname(h->lfd, (struct sockaddr *)&a, &al) < 0) {
        (void)kelp_failf(d, KELP_ERR_IO, "TCP port %u: %s", port, strerror(errno));
        kelp_hostport_close(h);
        return -1;
    }
    h->port = ntohs(a.sin_port);
    h->ep = epoll_create1(EPOLL_CLOEXEC);
    struct epoll_event e = { .events = EPOLLIN, .data.fd = h->lfd };
    if (h->ep < 0 || epoll_ctl(h->ep, EPOLL_CTL_ADD, h->lfd, &e) < 0) {
        (void)kelp_failf(d, KELP_ERR_IO, "epoll: %s", strerror(errno));
        kelp_hostport_close(h);
        return -1;
    }
    return 0;
}

int kelp_hostport_fd(const kelp_hostport *h)
{
    return h->master >= 0 ? h->master : h->ep;
}

static void close_client(kelp_hostport *h)
{
    if (h->cfd < 0) return;
    epoll_ctl(h->ep, EPOLL_CTL_DEL, h->cfd, NULL);
    close(h->cfd);
    h->cfd = -1;
}

/* read fd until it would block; false when the peer closed or failed */
static int drain(kelp_hostport *h, int fd, void (*on_bytes)(void *, const uint8_t *, size_t), void *ctx)
{
    uint8_t buf[4096];
    for (;;) {
        ssize_t n = read(fd, buf, sizeof buf);
        if (n > 0) {
            h->bytes_in += (size_t)n;
            on_bytes(ctx, buf, (size_t)n);
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        return n < 0 && errno == EAGAIN;
    }
}

unsigned kelp_hostport_poll(kelp_hostport *h, void (*on_bytes)(void *ctx, const uint8_t *b, size_t n), void *ctx)
{
    unsigned what = 0;
    if (h->master >= 0) {
        (void)drain(h, h->master, on_bytes, ctx); /* EIO (no slave open) cannot happen: we keep one */
        return 0;
    }
    if (h->ep < 0) return 0;
    struct epoll_event ev[4];
    int n = epoll_wait(h->ep, ev, 4, 0);
    for (int i = 0; i < n; i++) {
        if (ev[i].data.fd == h->lfd) {
            int c = accept(h->lfd, NULL, NULL);
            if (c < 0) continue;
            if (h->cfd >= 0) what |= KELP_HOSTPORT_DISCONNECTED;
            close_client(h); /* one host at a time: a new connection replaces the old one */
            fcntl(c, F_SETFL, fcntl(c, F_GETFL) | O_NONBLOCK);
            fcntl(c, F_SETFD, FD_CLOEXEC);
            int one = 1;
            setsockopt(c, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            struct epoll_event e = { .events = EPOLLIN, .data.fd = c };
            epoll_ctl(h->ep, EPOLL_CTL_ADD, c, &e);
            h->cfd = c;
            h->connects++;
            what |= KELP_HOSTPORT_CONNECTED;
        } else if (ev[i].data.fd == h->cfd) {
            if (!drain(h, h->cfd, on_bytes, ctx)) {
                close_client(h);
                what |= KELP_HOSTPORT_DISCONNECTED;
            }
        }
    }
    return what;
}

size_t kelp_hostport_write(kelp_hostport *h, const void *b, size_t n)
{
    int fd = h->master >= 0 ? h->master : h->cfd;
    size_t off = 0;
    while (fd >= 0 && off < n) {
        ssize_t w = write(fd, (const char *)b + off, n - off);
        if (w > 0) {
            off += (size_t)w;
            continue;
        }
        if (w < 0 && errno == EINTR) continue;
        break; /* nobody reading (pty buffer full) or the client went away */
    }
    h->bytes_out += off;
    h->dropped_out += n - off;
    return n - off;
}

void kelp_hostport_close(kelp_hostport *h)
{
    close_client(h);
    int fds[] = { h->master, h->slave, h->lfd, h->ep };
    for (size_t i = 0; i < sizeof fds / sizeof fds[0]; i++)
        if (fds[i] >= 0) close(fds[i]);
    if (h->link[0]) {
        /* only our own link: another instance may have taken the name since */
        char target[256];
        ssize_t n = readlink(h->link, target, sizeof target - 1);
        if (n > 0) {
            target[n] = '\0';
            if (strcmp(target, h->pty_name) == 0) unlink(h->link);
        }
    }
    h->master = h->slave = h->lfd = h->ep = -1;
    h->link[0] = '\0';
}
