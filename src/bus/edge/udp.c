/* kelp edge: plain UDP sockets (see kelp/edge/udp.h). */
#include <errno.h>
#include <fcntl.h>
#include <netdb.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <arpa/inet.h>
#include <sys/socket.h>
#include <kelp/err.h>
#include <kelp/edge/udp.h>

int kelp_udp_open(uint16_t port, int rcvbuf, kelp_diag *d)
{
    int fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        (void)kelp_failf(d, KELP_ERR_IO, "socket: %s", strerror(errno));
        return KELP_ERR_IO;
    }
    if (port) {
        struct sockaddr_in a;
        memset(&a, 0, sizeof a);
        a.sin_family = AF_INET;
        a.sin_port = htons(port);
        a.sin_addr.s_addr = htonl(INADDR_ANY);
        if (bind(fd, (struct sockaddr *)&a, sizeof a) < 0) {
            (void)kelp_failf(d, KELP_ERR_IO, "cannot listen on UDP port %u: %s", port, strerror(errno));
            close(fd);
            return KELP_ERR_IO;
        }
    }
    if (rcvbuf > 0) (void)setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    return fd;
}

int kelp_udp_open_group(const char *group, uint16_t port, int rcvbuf, kelp_diag *d)
{
    struct ip_mreq mr;
    memset(&mr, 0, sizeof mr);
    if (!group || inet_pton(AF_INET, group, &mr.imr_multiaddr) != 1 || !IN_MULTICAST(ntohl(mr.imr_multiaddr.s_addr)))
        return kelp_failf(d, KELP_ERR_ARG, "%s is not an IPv4 multicast address", group ? group : "(null)");
    int fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) return kelp_failf(d, KELP_ERR_IO, "socket: %s", strerror(errno));
    int one = 1;
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    mr.imr_interface.s_addr = htonl(INADDR_ANY);
    if (setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) < 0 || bind(fd, (struct sockaddr *)&a, sizeof a) < 0 ||
        setsockopt(fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &mr, sizeof mr) < 0) {
        int e = errno;
        close(fd);
        return kelp_failf(d, KELP_ERR_IO, "cannot listen to %s:%u: %s", group, port, strerror(e));
    }
    if (rcvbuf > 0) (void)setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    return fd;
}

int kelp_udp_multicast_tx(int fd, int ttl)
{
    unsigned char t = (unsigned char)(ttl < 0 ? 0 : ttl > 255 ? 255 : ttl), loop = 1;
    if (setsockopt(fd, IPPROTO_IP, IP_MULTICAST_TTL, &t, sizeof t) < 0 ||
        setsockopt(fd, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) < 0)
        return KELP_ERR_IO;
    return KELP_OK;
}

int kelp_udp_resolve(const char *host, uint16_t port, struct sockaddr_in *out)
{
    struct addrinfo hints, *res = NULL;
    memset(&hints, 0, sizeof hints);
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_DGRAM;
    if (getaddrinfo(host, NULL, &hints, &res) != 0 || !res) return KELP_ERR_NOTFOUND;
    memcpy(out, res->ai_addr, sizeof *out);
    out->sin_port = htons(port);
    freeaddrinfo(res);
    return KELP_OK;
}

int kelp_udp_recv(int fd, uint8_t *buf, size_t cap, size_t *full)
{
    /* MSG_TRUNC: the return value is the datagram's real length even when it was cut */
    ssize_t n = recv(fd, buf, cap, MSG_DONTWAIT | MSG_TRUNC);
    if (n < 0) return (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) ? 0 : KELP_ERR_IO;
    *full = (size_t)n;
    return 1;
}

int kelp_udp_send(int fd, const struct sockaddr_in *to, const uint8_t *buf, size_t len)
{
    return sendto(fd, buf, len, 0, (const struct sockaddr *)to, sizeof *to) < 0 ? KELP_ERR_IO : KELP_OK;
}
