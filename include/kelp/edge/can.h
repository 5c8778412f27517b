/* kelp edge: a CAN port over SocketCAN CAN_RAW (or a test stand-in), for kelp/can.h frames.
 *
 * Socket creation, binding and filters sit behind kelp_can_ops, so unit tests run the same
 * read/write/reopen code over an AF_UNIX SOCK_SEQPACKET socketpair (one write of a 16-byte
 * struct can_frame or 72-byte struct canfd_frame is one read, as on CAN_RAW). With real
 * SocketCAN the filters are the kernel's (CAN_RAW_FILTER); ops without kernel filters get
 * them applied in user space here.
 *
 * The port's file descriptor keeps its number for the port's life: when the interface goes
 * down (a read or write fails with ENETDOWN/ENODEV, or the stand-in's peer hangs up) a quiet
 * placeholder takes the number, and kelp_can_port_maintain() later puts a fresh socket there
 * (dup2) once the interface is up again. An app can watch that fd once.
 */
#ifndef KELP_EDGE_CAN_H
#define KELP_EDGE_CAN_H
#include <stdbool.h>
#include <stddef.h>
#include <kelp/can.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kelp_can_ops {
    /** A non-blocking socket for ifname with filters (nf == 0: everything) and, when
     *  fd_frames, CAN FD frames enabled. @return fd, or < 0 with the reason in d. */
    int (*open)(void *ctx, const char *ifname, const kelp_can_filter *f, size_t nf, bool fd_frames, kelp_diag *d);
    /** 1 when ifname exists and is up (worth reopening), 0 otherwise. */
    int (*is_up)(void *ctx, const char *ifname);
    bool kernel_filters; /**< open() installed the filters; otherwise the port applies them */
    void *ctx;
} kelp_can_ops;

/** Real SocketCAN: CAN_RAW bound to the interface, CAN_RAW_FILTER, CAN_RAW_FD_FRAMES. */
extern const kelp_can_ops kelp_can_socketcan_ops;

typedef struct kelp_can_port {
    kelp_can_ops ops;
    char ifname[32];
    kelp_can_filter filters[KELP_CAN_MAX_FILTERS];
    size_t nf;
    bool fd_frames;
    int fd;
    bool down;
    unsigned long rx, tx, rx_filtered, rx_other, tx_full, tx_err, went_down, reopened;
    kelp_diag diag; /**< the latest failure (replaced by each new one) */
} kelp_can_port;

/** Open the port. @return 0, or KELP_ERR_IO with p->diag set: the port is then left down on
 *  a placeholder fd (p->down), and kelp_can_port_maintain() opens it once the interface is
 *  up (an interface that appears later, a USB adapter plugged in). */
KELP_MUST_CHECK int kelp_can_port_open(kelp_can_port *p, const kelp_can_ops *ops, const char *ifname,
                                       const kelp_can_filter *f, size_t nf, bool fd_frames);
/** Read one frame without blocking. Error and remote-request frames and frames the
 *  filters refuse are skipped (counted). @return 1 with a frame, 0 none waiting,
 *  KELP_ERR_IO when the interface went down (p->down set). */
KELP_MUST_CHECK int kelp_can_port_read(kelp_can_port *p, kelp_can_frame *f);
/** Write one frame (29-bit id). @return 0, KELP_ERR_NOSPACE (queue full: dropped),
 *  KELP_ERR_STATE (down), KELP_ERR_IO (went down now, or another error). */
KELP_MUST_CHECK int kelp_can_port_write(kelp_can_port *p, const kelp_can_frame *f);
/** When down and the interface is up again, reopen. @return 1 reopened, 0 nothing to do,
 *  KELP_ERR_IO when the reopen failed (p->diag). */
KELP_MUST_CHECK int kelp_can_port_maintain(kelp_can_port *p);
void kelp_can_port_close(kelp_can_port *p);

#ifdef __cplusplus
}
#endif
#endif
