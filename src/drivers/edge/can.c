/* kelp edge: SocketCAN CAN_RAW port with reopen (see kelp/edge/can.h). */
#include <errno.h>
#include <fcntl.h>
#include <net/if.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <kelp/edge/can.h>

KELP_STATIC_ASSERT(KELP_CAN_FILTER_EFF == CAN_EFF_FLAG, "filter flag bit is SocketCAN's");

static int sc_open(void *ctx, const char *ifname, const kelp_can_filter *f, size_t nf, bool fd_frames, kelp_diag *d)
{
    (void)ctx;
    int s = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (s < 0) {
        (void)kelp_failf(d, KELP_ERR_IO, "CAN_RAW socket: %s", strerror(errno));
        return KELP_ERR_IO;
    }
    struct can_filter cf[KELP_CAN_MAX_FILTERS];
    for (size_t i = 0; i < nf && i < KELP_CAN_MAX_FILTERS; i++) {
        cf[i].can_id = f[i].id;
        cf[i].can_mask = f[i].mask;
    }
    int on = 1;
    const char *what = NULL;
    struct sockaddr_can a;
    memset(&a, 0, sizeof a);
    a.can_family = AF_CAN;
    a.can_ifindex = (int)if_nametoindex(ifname);
    if (nf && setsockopt(s, SOL_CAN_RAW, CAN_RAW_FILTER, cf, (socklen_t)(nf * sizeof cf[0])) < 0)
        what = "CAN_RAW_FILTER";
    else if (fd_frames && setsockopt(s, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) < 0)
        what = "CAN_RAW_FD_FRAMES";
    else if (a.can_ifindex == 0)
        what = "interface";
    else if (bind(s, (struct sockaddr *)&a, sizeof a) < 0)
        what = "bind";
    if (what) {
        (void)kelp_failf(d, KELP_ERR_IO, "%s %s: %s", ifname, what, a.can_ifindex == 0 ? "no such interface" : strerror(errno));
        close(s);
        return KELP_ERR_IO;
    }
    return s;
}

static int sc_is_up(void *ctx, const char *ifname)
{
    (void)ctx;
    int s = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (s < 0) return 0;
    struct ifreq r;
    memset(&r, 0, sizeof r);
    snprintf(r.ifr_name, sizeof r.ifr_name, "%s", ifname);
    int up = ioctl(s, SIOCGIFFLAGS, &r) == 0 && (r.ifr_flags & IFF_UP);
    close(s);
    return up;
}

const kelp_can_ops kelp_can_socketcan_ops = { sc_open, sc_is_up, true, NULL };

/* Put a never-readable socket on the port's fd number. */
static void go_down(kelp_can_port *p, int err)
{
    int q = socket(AF_UNIX, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (q >= 0) {
        (void)dup3(q, p->fd, O_CLOEXEC);
        close(q);
    }
    p->down = true;
    p->went_down++;
    kelp_diag_clear(&p->diag);
    (void)kelp_failf(&p->diag, KELP_ERR_IO, "%s went down: %s", p->ifname, err ? strerror(err) : "peer closed");
}

int kelp_can_port_open(kelp_can_port *p, const kelp_can_ops *ops, const char *ifname, const kelp_can_filter *f,
                       size_t nf, bool fd_frames)
{
    memset(p, 0, sizeof *p);
    p->fd = -1;
    p->ops = *ops;
    if (strlen(ifname) >= sizeof p->ifname || nf > KELP_CAN_MAX_FILTERS) {
        kelp_diag_clear(&p->diag);
    (void)kelp_failf(&p->diag, KELP_ERR_IO, "bad interface name or too many filters");
        return KELP_ERR_ARG;
    }
    memcpy(p->ifname, ifname, strlen(ifname) + 1);
    if (nf) memcpy(p->filters, f, nf * sizeof *f);
    p->nf = nf;
    p->fd_frames = fd_frames;
    int s = ops->open(ops->ctx, ifname, f, nf, fd_frames, &p->diag);
    if (s >= 0) {
        p->fd = s;
        return KELP_OK;
    }
    /* left down on a placeholder: kelp_can_port_maintain() opens it when the interface is up */
    p->fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    p->down = p->fd >= 0;
    return KELP_ERR_IO;
}

int kelp_can_port_read(kelp_can_port *p, kelp_can_frame *f)
{
    if (p->down || p->fd < 0) return 0;
    for (;;) {
        struct canfd_frame c;
        ssize_t n = read(p->fd, &c, sizeof c);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return 0;
        if (n <= 0) {
            go_down(p, n < 0 ? errno : 0);
            return KELP_ERR_IO;
        }
        bool fd = n == (ssize_t)CANFD_MTU;
        if ((n != (ssize_t)CAN_MTU && !fd) || (c.can_id & (CAN_ERR_FLAG | CAN_RTR_FLAG)) ||
            c.len > (fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN)) {
            p->rx_other++;
            continue;
        }
        bool eff = (c.can_id & CAN_EFF_FLAG) != 0;
        uint32_t id = c.can_id & (eff ? CAN_EFF_MASK : CAN_SFF_MASK);
        if (!p->ops.kernel_filters && !kelp_can_filter_pass(p->filters, p->nf, id, eff)) {
            p->rx_filtered++;
            continue;
        }
        memset(f, 0, sizeof *f);
        /* a standard frame's id never carries kelp's tag; keep it recognisable as foreign */
        f->id = eff ? id : id | 0x80000000u;
        f->fd = fd;
        f->len = c.len;
        memcpy(f->data, c.data, c.len);
        p->rx++;
        return 1;
    }
}

int kelp_can_port_write(kelp_can_port *p, const kelp_can_frame *f)
{
    if (p->down || p->fd < 0) return KELP_ERR_STATE;
    struct canfd_frame c;
    memset(&c, 0, sizeof c);
    if (f->len > (f->fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN)) return KELP_ERR_ARG;
    c.can_id = (f->id & CAN_EFF_MASK) | CAN_EFF_FLAG;
    c.len = f->len;
    memcpy(c.data, f->data, f->len);
    size_t sz = f->fd ? CANFD_MTU : CAN_MTU;
    ssize_t n;
    do n = write(p->fd, &c, sz);
    while (n < 0 && errno == EINTR);
    if (n == (ssize_t)sz) {
        p->tx++;
        return KELP_OK;
    }
    if (n < 0 && (errno == ENOBUFS || errno == EAGAIN || errno == EWOULDBLOCK)) {
        p->tx_full++;
        return KELP_ERR_NOSPACE;
    }
    p->tx_err++;
    if (n < 0 && (errno == ENETDOWN || errno == ENODEV || errno == ENXIO || errno == EPIPE || errno == ECONNRESET ||
                  errno == ENOTCONN)) {
        go_down(p, errno);
    }
    return KELP_ERR_IO;
}

int kelp_can_port_maintain(kelp_can_port *p)
{
    if (!p->down || p->fd < 0) return 0;
    if (!p->ops.is_up(p->ops.ctx, p->ifname)) return 0;
    int s = p->ops.open(p->ops.ctx, p->ifname, p->filters, p->nf, p->fd_frames, &p->diag);
    if (s < 0) return KELP_ERR_IO;
    if (dup3(s, p->fd, O_CLOEXEC) < 0) {
        kelp_diag_clear(&p->diag);
    (void)kelp_failf(&p->diag, KELP_ERR_IO, "dup2: %s", strerror(errno));
        close(s);
        return KELP_ERR_IO;
    }
    close(s);
    p->down = false;
    p->reopened++;
    return 1;
}

void kelp_can_port_close(kelp_can_port *p)
{
    if (p->fd >= 0) close(p->fd);
    p->fd = -1;
}
