/* kelp UDP multicast sockets: LCM's udpm wire format without liblcm (edge).
 *
 * The receive thread owns the socket and the reassembler; the owner thread only takes
 * complete messages from the queue. The queue is one byte ring of records, so a message
 * costs one copy in and none out (the record stays reserved until the next take).
 */
#include <errno.h>
#include <poll.h>
#include <linux/filter.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/udp.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <kelp/edge/udpm.h>

#define REC_HDR 12u           /* u32 record bytes (0 = wrap), u32 payload bytes, u32 channel bytes */
#define REC_ALIGN 8u
#define RECV_BATCH 64         /* datagrams drained before the queue lock is taken for stats */
#define IDLE_POLL_MS 250      /* wake at least this often to time out reassembly slots */
#define SEND_BATCH 64         /* datagrams a corked socket hands the kernel in one sendmmsg */
#define SEND_BATCH_BYTES (256u * 1024u)
#ifndef UDP_SEGMENT
#define UDP_SEGMENT 103       /* linux/udp.h, Linux 4.18 */
#endif
#define GSO_MAX_SEGS 64       /* the kernel's UDP_MAX_SEGMENTS */
#define GSO_MAX_SEG 1400u     /* a segment's datagram fits an Ethernet MTU (1500 - IP - UDP) */
#define GSO_MAX_BYTES 65000u  /* a segmented send is one UDP datagram to the kernel */
#define GSO_CTL CMSG_SPACE(sizeof(uint16_t))
#ifndef UDP_GRO
#define UDP_GRO 104           /* linux/udp.h, Linux 5.0 */
#endif
#define RX_BUF 65536u         /* a datagram, or a coalesced run of them (UDP GRO: at most 64 KiB) */

struct kelp_udpm_sock {
    int rfd, sfd, evfd, stopfd;
    pthread_t th;
    int th_started;
    struct sockaddr_in dest;
    /* queue, under qlock */
    pthread_mutex_t qlock;
    uint8_t *q;
    size_t qcap, head, tail, used, nrec, held;
    kelp_udpm_sock_stats st;
    /* receive thread only */
    kelp_udpm_rx rx;
    kelp_udpm_slot slots[KELP_UDPM_REASM_SLOTS];
    uint8_t *slotmem;
    uint8_t *dg;
    /* publish, under slock */
    pthread_mutex_t slock;
    uint32_t seqno;
    uint64_t sent, send_errors;
    /* corked (kelp_udpm_sock_cork): short messages wait here, whole datagrams, for one
     * sendmmsg at the flush; allocated at the first cork */
    bool corked;
    uint8_t *batch;
    size_t batch_used;
    unsigned nbatch;
    struct mmsghdr bmsg[SEND_BATCH];
    struct iovec biov[SEND_BATCH];
    uint64_t batches;
    /* segmented sends (UDP GSO): consecutive short datagrams within KELP_UDPM_PAD_MAX bytes
     * of each other go to the kernel as one send, padded with zeros to one size, and the
     * kernel cuts them apart; a kernel that refuses turns them off for the socket */
    bool gso_off;
    uint8_t *gbuf;                        /* the padded copies, allocated with batch */
    struct iovec giov[SEND_BATCH];
    unsigned gfirst[SEND_BATCH], gcount[SEND_BATCH];
    union { struct cmsghdr h; uint8_t b[GSO_CTL]; } gctl[SEND_BATCH]; /* aligned for cmsghdr */
    uint64_t gso_sends, gso_segments;
    /* ignore our own datagrams (kelp_udpm_sock_ignore_own): set by the owner, read by the
     * receive thread, which attaches the kernel filter on the first own datagram it sees */
    volatile int ignore_own;
    int own_filtered;
    uint32_t own_ip;   /* network order, with own_port: our send socket as seen by receivers */
    uint16_t own_port;
};

static double mono_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void put32(uint8_t *p, uint32_t v) { memcpy(p, &v, 4); } /* host order: never on the wire */
static uint32_t get32(const uint8_t *p)
{
    uint32_t v;
    memcpy(&v, p, 4);
    return v;
}

/* Queue one complete message; called with qlock held. */
static void enqueue(kelp_udpm_sock *s, const kelp_udpm_msg *m)
{
    size_t cl = strlen(m->channel) + 1;
    size_t rec = (REC_HDR + cl + m->len + REC_ALIGN - 1) & ~(size_t)(REC_ALIGN - 1);
    size_t waste = s->tail + rec > s->qcap ? s->qcap - s->tail : 0;
    if (rec > s->qcap || s->used + waste + rec > s->qcap) {
        s->st.queue_dropped++;
        return;
    }
    if (waste) {
        put32(s->q + s->tail, 0); /* wrap marker: the consumer skips to the start */
        s->used += waste;
        s->tail = 0;
    }
    uint8_t *p = s->q + s->tail;
    put32(p, (uint32_t)rec);
    put32(p + 4, (uint32_t)m->len);
    put32(p + 8, (uint32_t)cl);
    memcpy(p + REC_HDR, m->channel, cl);
    if (m->len) memcpy(p + REC_HDR + cl, m->data, m->len);
    s->tail += rec;
    if (s->tail == s->qcap) s->tail = 0;
    s->used += rec;
    if (s->nrec++ == 0) {
        uint64_t one = 1;
        if (write(s->evfd, &one, sizeof one) < 0) { /* counter saturated: already readable */ }
    }
    s->st.queued++;
}

/* a datagram sent by our own send socket (its address and port) */
static bool own_datagram(const kelp_udpm_sock *s, const struct sockaddr_in *from)
{
    struct sockaddr_in me = { 0 };
    socklen_t ml = sizeof me;
    return getsockname(s->sfd, (struct sockaddr *)&me, &ml) == 0 && me.sin_port == from->sin_port;
}

/* A socket filter that drops, in the kernel, the datagrams from our own address and send
 * port: an app that never reads its own posts then neither wakes nor copies for them. */
static void attach_own_filter(kelp_udpm_sock *s, const struct sockaddr_in *from)
{
    uint32_t ip = ntohl(from->sin_addr.s_addr), port = ntohs(from->sin_port);
    struct sock_filter code[] = {
        BPF_STMT(BPF_LD | BPF_W | BPF_ABS, (uint32_t)SKF_NET_OFF + 12), /* IPv4 source address */
        BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, ip, 0, 3),
        BPF_STMT(BPF_LD | BPF_H | BPF_ABS, 0),                          /* UDP source port */
        BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, port, 0, 1),
        BPF_STMT(BPF_RET | BPF_K, 0),                                   /* ours: drop */
        BPF_STMT(BPF_RET | BPF_K, 0xFFFFFFFFu),                         /* anyone else's */
    };
    struct sock_fprog prog = { (unsigned short)(sizeof code / sizeof code[0]), code };
    s->own_filtered = setsockopt(s->rfd, SOL_SOCKET, SO_ATTACH_FILTER, &prog, sizeof prog) == 0 ? 1 : -1;
}

void kelp_udpm_sock_ignore_own(kelp_udpm_sock *s, bool on)
{
    if (!s) return;
    s->ignore_own = on;
    if (!on && s->own_filtered == 1) {
        int dummy = 0;
        (void)setsockopt(s->rfd, SOL_SOCKET, SO_DETACH_FILTER, &dummy, sizeof dummy);
        s->own_filtered = 0;
    }
}

static void *recv_main(void *arg)
{
    kelp_udpm_sock *s = arg;
    sigset_t all;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, NULL); /* signals belong to the owner thread */
    for (;;) {
        struct pollfd p[2] = { { s->rfd, POLLIN, 0 }, { s->stopfd, POLLIN, 0 } };
        int pr = poll(p, 2, IDLE_POLL_MS);
        if (pr < 0 && errno != EINTR) break;
        if (p[1].revents) break;
        double now = mono_now();
        if (!(p[0].revents & POLLIN)) {
            (void)kelp_udpm_expire(&s->rx, now);
            pthread_mutex_lock(&s->qlock);
            s->st.rx = s->rx.stats;
            pthread_mutex_unlock(&s->qlock);
            continue;
        }
        for (int i = 0; i < RECV_BATCH; i++) {
            struct sockaddr_in from = { 0 };
            union { struct cmsghdr h; uint8_t b[CMSG_SPACE(sizeof(int))]; } ctl;
            struct iovec iov = { s->dg, RX_BUF };
            struct msghdr mh = { .msg_name = &from, .msg_namelen = sizeof from, .msg_iov = &iov, .msg_iovlen = 1,
                                 .msg_control = ctl.b, .msg_controllen = sizeof ctl.b };
            ssize_t n = recvmsg(s->rfd, &mh, MSG_DONTWAIT);
            if (n < 0) break;
            if (mh.msg_flags & MSG_TRUNC) n = RX_BUF; /* (over 64 KiB: cannot be LCM's; feed() counts it) */
            /* a coalesced run (UDP GRO: a sender's segmented send, or a NIC's coalescing) holds
             * datagrams of seg bytes each, the last one shorter */
            size_t seg = (size_t)n;
            for (struct cmsghdr *c = CMSG_FIRSTHDR(&mh); c; c = CMSG_NXTHDR(&mh, c))
                if (c->cmsg_level == SOL_UDP && c->cmsg_type == UDP_GRO) {
                    int g;
                    memcpy(&g, CMSG_DATA(c), sizeof g);
                    if (g > 0 && (size_t)g < seg) seg = (size_t)g;
                }
            if (seg < (size_t)n) {
                pthread_mutex_lock(&s->qlock);
                s->st.gro_runs++;
                pthread_mutex_unlock(&s->qlock);
            }
            uint64_t sender = (uint64_t)ntohl(from.sin_addr.s_addr) << 16 | ntohs(from.sin_port);
            if (s->ignore_own) {
                if (!s->own_port && own_datagram(s, &from)) {
                    s->own_ip = from.sin_addr.s_addr, s->own_port = from.sin_port;
                    attach_own_filter(s, &from);
                }
                /* (datagrams queued before the filter came are dropped here) */
                if (s->own_port && from.sin_port == s->own_port && from.sin_addr.s_addr == s->own_ip) continue;
            }
            for (size_t off = 0; off < (size_t)n; off += seg) {
                size_t len = (size_t)n - off < seg ? (size_t)n - off : seg;
                kelp_udpm_msg m;
                /* a datagram over the UDP maximum cannot come from LCM; feed() counts it */
                if (kelp_udpm_feed(&s->rx, s->dg + off, len, sender, now, &m) == 1) {
                    pthread_mutex_lock(&s->qlock);
                    enqueue(s, &m);
                    s->st.rx = s->rx.stats;
                    pthread_mutex_unlock(&s->qlock);
                }
            }
        }
        pthread_mutex_lock(&s->qlock);
        s->st.rx = s->rx.stats;
        pthread_mutex_unlock(&s->qlock);
    }
    return NULL;
}

int kelp_udpm_sock_next(kelp_udpm_sock *s, kelp_udpm_msg *out)
{
    pthread_mutex_lock(&s->qlock);
    if (s->held) {
        s->head += s->held;
        if (s->head == s->qcap) s->head = 0;
        s->used -= s->held;
        s->held = 0;
    }
    if (s->nrec == 0) {
        s->head = s->tail = s->used = 0; /* empty: start over, no wrap needed soon */
        uint64_t c;
        if (read(s->evfd, &c, sizeof c) < 0) { /* EAGAIN: already clear */ }
        pthread_mutex_unlock(&s->qlock);
        return 0;
    }
    uint32_t rec = get32(s->q + s->head);
    if (rec == 0) {
        s->used -= s->qcap - s->head;
        s->head = 0;
        rec = get32(s->q);
    }
    const uint8_t *p = s->q + s->head;
    s->held = rec;
    s->nrec--;
    pthread_mutex_unlock(&s->qlock);
    uint32_t cl = get32(p + 8);
    out->channel = (const char *)(p + REC_HDR);
    out->data = p + REC_HDR + cl;
    out->len = get32(p + 4);
    out->seqno = 0;
    out->sender = 0;
    out->fragmented = false;
    return 1;
}

/* Send datagrams [from, nbatch) one message each; called with slock held. A datagram the
 * kernel refuses is counted as a send error and the rest still go. */
static void send_plain(kelp_udpm_sock *s, unsigned from)
{
    for (unsigned i = from; i < s->nbatch; i++) {
        memset(&s->bmsg[i], 0, sizeof s->bmsg[i]);
        s->bmsg[i].msg_hdr.msg_iov = &s->biov[i];
        s->bmsg[i].msg_hdr.msg_iovlen = 1;
    }
    unsigned done = from;
    while (done < s->nbatch) {
        int n = sendmmsg(s->sfd, &s->bmsg[done], s->nbatch - done, 0);
        if (n < 0) {
            if (errno == EINTR) continue;
            s->send_errors++; /* this one; the kernel stops at the first that fails */
            done++;
            continue;
        }
        s->sent += (uint64_t)n;
        done += (unsigned)n;
    }
}

/* One send of datagrams [i, j): padded to the longest (all but the last), one segment each. */
static void gso_group(kelp_udpm_sock *s, unsigned g, unsigned i, unsigned j, size_t seg, size_t *goff)
{
    struct msghdr *h = &s->bmsg[g].msg_hdr;
    memset(&s->bmsg[g], 0, sizeof s->bmsg[g]);
    s->gfirst[g] = i;
    s->gcount[g] = j - i;
    if (j - i == 1) {
        h->msg_iov = &s->biov[i];
        h->msg_iovlen = 1;
        return;
    }
    uint8_t *base = s->gbuf + *goff, *p = base;
    for (unsigned k = i; k < j; k++) {
        size_t l = s->biov[k].iov_len, take = k + 1 < j ? seg : l;
        memcpy(p, s->biov[k].iov_base, l);
        if (take > l) memset(p + l, 0, take - l);
        p += take;
    }
    *goff += (size_t)(p - base);
    s->giov[g] = (struct iovec){ base, (size_t)(p - base) };
    h->msg_iov = &s->giov[g];
    h->msg_iovlen = 1;
    h->msg_control = s->gctl[g].b;
    h->msg_controllen = GSO_CTL;
    struct cmsghdr *c = CMSG_FIRSTHDR(h);
    c->cmsg_level = SOL_UDP;
    c->cmsg_type = UDP_SEGMENT;
    c->cmsg_len = CMSG_LEN(sizeof(uint16_t));
    uint16_t gs = (uint16_t)seg;
    memcpy(CMSG_DATA(c), &gs, sizeof gs);
}

/* The batch as segmented sends; called with slock held. @return the first datagram not
 * handed over: nbatch, or where a kernel without UDP segmentation refused (gso_off is then
 * set and the caller sends the rest one by one). */
static unsigned send_gso(kelp_udpm_sock *s)
{
    unsigned ng = 0;
    size_t goff = 0;
    for (unsigned i = 0; i < s->nbatch;) {
        size_t lo = s->biov[i].iov_len, hi = lo;
        unsigned j = i + 1;
        if (hi <= GSO_MAX_SEG)
            while (j < s->nbatch && j - i < GSO_MAX_SEGS) {
                size_t l = s->biov[j].iov_len, nlo = l < lo ? l : lo, nhi = l > hi ? l : hi;
                if (nhi > GSO_MAX_SEG || nhi - nlo > KELP_UDPM_PAD_MAX || nhi * (j - i + 1) > GSO_MAX_BYTES) break;
                lo = nlo;
                hi = nhi;
                j++;
            }
        gso_group(s, ng++, i, j, hi, &goff);
        i = j;
    }
    unsigned done = 0;
    while (done < ng) {
        int n = sendmmsg(s->sfd, &s->bmsg[done], ng - done, 0);
        if (n < 0) {
            if (errno == EINTR) continue;
            if (s->gcount[done] > 1 && (errno == EINVAL || errno == EIO || errno == EOPNOTSUPP || errno == ENOPROTOOPT ||
                                        errno == EMSGSIZE)) {
                s->gso_off = true;
                return s->gfirst[done];
            }
            s->send_errors += s->gcount[done]; /* the kernel stops at the first that fails */
            done++;
            continue;
        }
        for (unsigned k = done; k < done + (unsigned)n; k++) {
            s->sent += s->gcount[k];
            if (s->gcount[k] > 1) {
                s->gso_sends++;
                s->gso_segments += s->gcount[k];
            }
        }
        done += (unsigned)n;
    }
    return s->nbatch;
}

/* hand the batch to the kernel; called with slock held */
static void flush_locked(kelp_udpm_sock *s)
{
    unsigned from = 0;
    if (!s->gso_off && s->gbuf) from = send_gso(s);
    if (from < s->nbatch) send_plain(s, from);
    if (s->nbatch) s->batches++;
    s->nbatch = 0;
    s->batch_used = 0;
}

void kelp_udpm_sock_cork(kelp_udpm_sock *s, bool on)
{
    if (!s) return;
    pthread_mutex_lock(&s->slock);
    if (on && !s->batch) {
        s->batch = malloc(SEND_BATCH_BYTES); /* none: publish sends at once */
        if (s->batch && !s->gso_off) s->gbuf = malloc(SEND_BATCH_BYTES + (size_t)SEND_BATCH * KELP_UDPM_PAD_MAX);
    }
    if (!on && s->nbatch) flush_locked(s);
    s->corked = on;
    pthread_mutex_unlock(&s->slock);
}

void kelp_udpm_sock_flush(kelp_udpm_sock *s)
{
    if (!s) return;
    pthread_mutex_lock(&s->slock);
    if (s->nbatch) flush_locked(s);
    pthread_mutex_unlock(&s->slock);
}

int kelp_udpm_sock_publish(kelp_udpm_sock *s, const char *channel, const void *data, size_t len)
{
    if (!s || !channel || (!data && len)) return KELP_ERR_ARG;
    size_t cl = strlen(channel);
    uint16_t nfrags = 0;
    int rc = kelp_udpm_plan(cl, len, KELP_UDPM_MAX_DATAGRAM, &nfrags);
    if (rc < 0) return rc;
    uint8_t hdr[KELP_UDPM_FRAG_HDR];
    struct iovec iov[3];
    struct msghdr mh;
    memset(&mh, 0, sizeof mh);
    mh.msg_iov = iov;
    pthread_mutex_lock(&s->slock);
    uint32_t seq = s->seqno++;
    size_t dlen = KELP_UDPM_SHORT_HDR + cl + 1 + len;
    if (nfrags == 0 && s->corked && s->batch && dlen <= SEND_BATCH_BYTES) {
        if (s->nbatch == SEND_BATCH || s->batch_used + dlen > SEND_BATCH_BYTES) flush_locked(s);
        uint8_t *p = s->batch + s->batch_used;
        kelp_udpm_put_short_header(p, seq);
        memcpy(p + KELP_UDPM_SHORT_HDR, channel, cl + 1);
        if (len) memcpy(p + KELP_UDPM_SHORT_HDR + cl + 1, data, len);
        s->biov[s->nbatch] = (struct iovec){ p, dlen };
        s->nbatch++;
        s->batch_used += dlen;
        pthread_mutex_unlock(&s->slock);
        return KELP_OK;
    }
    if (s->nbatch) flush_locked(s); /* a fragmented message keeps its place in the order */
    if (nfrags == 0) {
        kelp_udpm_put_short_header(hdr, seq);
        struct iovec one[3] = { { hdr, KELP_UDPM_SHORT_HDR }, { (void *)channel, cl + 1 }, { (void *)data, len } };
        mh.msg_iov = one;
        mh.msg_iovlen = 3;
        ssize_t n = sendmsg(s->sfd, &mh, 0);
        rc = n == (ssize_t)(KELP_UDPM_SHORT_HDR + cl + 1 + len) ? KELP_OK : KELP_ERR_IO;
    } else {
        const size_t fp = KELP_UDPM_MAX_DATAGRAM - KELP_UDPM_FRAG_HDR;
        size_t off = 0;
        for (uint16_t k = 0; k < nfrags && rc == KELP_OK; k++) {
            size_t pre = k == 0 ? cl + 1 : 0;
            size_t chunk = fp - pre < len - off ? fp - pre : len - off;
            kelp_udpm_put_frag_header(hdr, seq, (uint32_t)len, (uint32_t)off, k, nfrags);
            int i = 0;
            iov[i++] = (struct iovec){ hdr, KELP_UDPM_FRAG_HDR };
            if (pre) iov[i++] = (struct iovec){ (void *)channel, pre };
            iov[i++] = (struct iovec){ (uint8_t *)data + off, chunk };
            mh.msg_iovlen = (size_t)i;
            ssize_t n = sendmsg(s->sfd, &mh, 0);
            if (n != (ssize_t)(KELP_UDPM_FRAG_HDR + pre + chunk)) rc = KELP_ERR_IO;
            off += chunk;
        }
    }
    if (rc == KELP_OK) s->sent++;
    else s->send_errors++;
    pthread_mutex_unlock(&s->slock);
    return rc;
}

int kelp_udpm_sock_fd(const kelp_udpm_sock *s)
{
    return s->evfd;
}

void kelp_udpm_sock_get_stats(kelp_udpm_sock *s, kelp_udpm_sock_stats *out)
{
    pthread_mutex_lock(&s->qlock);
    *out = s->st;
    pthread_mutex_unlock(&s->qlock);
    pthread_mutex_lock(&s->slock);
    out->sent = s->sent;
    out->send_batches = s->batches;
    {
        int sb = 0;
        socklen_t sl = sizeof sb;
        (void)getsockopt(s->sfd, SOL_SOCKET, SO_SNDBUF, &sb, &sl);
        out->send_buf = sb;
    }
    out->send_errors = s->send_errors;
    out->gso_sends = s->gso_sends;
    out->gso_segments = s->gso_segments;
    pthread_mutex_unlock(&s->slock);
}

static kelp_udpm_sock *fail(kelp_udpm_sock *s, kelp_diag *d, const char *what, int e)
{
    (void)kelp_failf(d, KELP_ERR_IO, "%s%s%s", what, e ? ": " : "", e ? strerror(e) : "");
    kelp_udpm_sock_close(s);
    return NULL;
}

static int open_tx(kelp_udpm_sock *s, const kelp_udpm_url *u, kelp_diag *d)
{
    s->sfd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (s->sfd < 0) return fail(s, d, "socket", errno) ? 0 : -1;
    s->gso_off = !u->gso;
    unsigned char ttl = (unsigned char)u->ttl, loop = 1;
    if (setsockopt(s->sfd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl) < 0 ||
        setsockopt(s->sfd, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) < 0)
        return fail(s, d, "multicast ttl/loop", errno) ? 0 : -1;
    if (u->send_buf_size > 0) {
        /* beyond net.core.wmem_max only with CAP_NET_ADMIN; otherwise what the kernel allows */
        int sb = (int)u->send_buf_size;
        if (setsockopt(s->sfd, SOL_SOCKET, SO_SNDBUFFORCE, &sb, sizeof sb) < 0)
            (void)setsockopt(s->sfd, SOL_SOCKET, SO_SNDBUF, &sb, sizeof sb);
    }
    if (connect(s->sfd, (struct sockaddr *)&s->dest, sizeof s->dest) < 0)
        return fail(s, d, "no route to the multicast group (see README)", errno) ? 0 : -1;
    /* sequence numbers start somewhere different per socket, as a restarted sender's
     * reassembly slots at receivers must not match its new messages */
    s->seqno = (uint32_t)getpid() << 16 ^ (uint32_t)(mono_now() * 1e6);

    return 0;
}

static kelp_udpm_sock *open_sock(const char *url, int listen, kelp_diag *d)
{
    kelp_udpm_url u;
    int rc = kelp_udpm_url_parse(url, &u);
    if (rc < 0) {
        (void)kelp_failf(d, KELP_ERR_IO, "bad URL '%s': %s (expected udpm://GROUP:PORT?ttl=N&recv_buf_size=B)", url,
                 kelp_err_str(rc));
        return NULL;
    }
    kelp_udpm_sock *s = calloc(1, sizeof *s);
    if (!s) return fail(s, d, "out of memory", 0);
    s->rfd = s->sfd = s->evfd = s->stopfd = -1;
    pthread_mutex_init(&s->qlock, NULL);
    pthread_mutex_init(&s->slock, NULL);
    s->qcap = (size_t)(u.queue_size ? u.queue_size : KELP_UDPM_DEFAULT_QUEUE);
    s->qcap = (s->qcap + REC_ALIGN - 1) & ~(size_t)(REC_ALIGN - 1);
    if (s->qcap < 2 * (KELP_UDPM_MAX_DATAGRAM + REC_HDR + REC_ALIGN)) s->qcap = 2 * (KELP_UDPM_MAX_DATAGRAM + REC_HDR + REC_ALIGN);
    s->dest.sin_family = AF_INET;
    s->dest.sin_addr.s_addr = htonl(u.group);
    s->dest.sin_port = htons(u.port);
    s->evfd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    s->stopfd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (s->evfd < 0 || s->stopfd < 0) return fail(s, d, "eventfd", errno);
    if (open_tx(s, &u, d) < 0) return NULL; /* open_tx closed s */
    if (!listen) return s; /* publish only: no socket, thread or queue for our own echo */
    s->q = malloc(s->qcap);
    s->slotmem = malloc((size_t)KELP_UDPM_REASM_SLOTS * KELP_UDPM_REASM_CAP);
    s->dg = malloc(RX_BUF);
    if (!s->q || !s->slotmem || !s->dg) return fail(s, d, "out of memory", 0);
    if (kelp_udpm_init(&s->rx, s->slots, KELP_UDPM_REASM_SLOTS, s->slotmem, KELP_UDPM_REASM_CAP,
                       KELP_UDPM_REASM_TIMEOUT) < 0)
        return fail(s, d, "reassembler init", 0);
    s->rfd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (s->rfd < 0) return fail(s, d, "socket", errno);
    int one = 1;
    if (setsockopt(s->rfd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) < 0)
        return fail(s, d, "SO_REUSEADDR", errno);
    int rb = (int)(u.recv_buf_size ? u.recv_buf_size : KELP_UDPM_DEFAULT_RECV_BUF);
    /* beyond net.core.rmem_max only with CAP_NET_ADMIN; otherwise what the kernel allows */
    if (setsockopt(s->rfd, SOL_SOCKET, SO_RCVBUFFORCE, &rb, sizeof rb) < 0)
        (void)setsockopt(s->rfd, SOL_SOCKET, SO_RCVBUF, &rb, sizeof rb);
    socklen_t rl = sizeof s->st.recv_buf;
    (void)getsockopt(s->rfd, SOL_SOCKET, SO_RCVBUF, &s->st.recv_buf, &rl);
    if (bind(s->rfd, (struct sockaddr *)&s->dest, sizeof s->dest) < 0)
        return fail(s, d, "bind to the multicast group", errno);
    /* take a segmented send whole (one read, one copy, split here) rather than have the
     * kernel cut it up for this socket; a kernel without UDP GRO delivers datagrams */
    if (u.gso) (void)setsockopt(s->rfd, IPPROTO_UDP, UDP_GRO, &one, sizeof one);
    struct ip_mreq mr;
    mr.imr_multiaddr = s->dest.sin_addr;
    mr.imr_interface.s_addr = htonl(INADDR_ANY);
    if (setsockopt(s->rfd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &mr, sizeof mr) < 0)
        return fail(s, d, "join the multicast group (is there a multicast route? see README)", errno);

    if (pthread_create(&s->th, NULL, recv_main, s) != 0) return fail(s, d, "receive thread", errno);
    s->th_started = 1;
    return s;
}

void kelp_udpm_sock_close(kelp_udpm_sock *s)
{
    if (!s) return;
    if (s->th_started) {
        uint64_t one = 1;
        if (write(s->stopfd, &one, sizeof one) < 0) { /* cannot fail on a fresh eventfd */ }
        pthread_join(s->th, NULL);
    }
    if (s->rfd >= 0) close(s->rfd);
    if (s->sfd >= 0) {
        kelp_udpm_sock_flush(s); /* what a corked owner left */
        close(s->sfd);
    }
    if (s->evfd >= 0) close(s->evfd);
    if (s->stopfd >= 0) close(s->stopfd);
    pthread_mutex_destroy(&s->qlock);
    pthread_mutex_destroy(&s->slock);
    free(s->q);
    free(s->slotmem);
    free(s->dg);
    free(s->batch);
    free(s->gbuf);
    free(s);
}

kelp_udpm_sock *kelp_udpm_sock_open(const char *url, kelp_diag *d)
{
    return open_sock(url, 1, d);
}

kelp_udpm_sock *kelp_udpm_sock_open_tx(const char *url, kelp_diag *d)
{
    return open_sock(url, 0, d);
}
