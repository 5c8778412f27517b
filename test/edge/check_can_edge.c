/* The CAN port (kelp/edge/can.h) over the AF_UNIX SOCK_SEQPACKET stand-in: frames both ways,
 * user-space filters, skipped error/remote/odd-size frames, a whole message through the
 * framing with reordering on the wire, the interface going down and coming back (same fd
 * number), and real SocketCAN failing cleanly where the kernel has no CAN. */
#include <check.h>
#include "check_diag.h"
#include <errno.h>
#include <string.h>
#include <unistd.h>
#include <sys/socket.h>
#include <linux/can.h>
#include <kelp/edge/can.h>

typedef struct standin {
    int peer; /* the "bus" end the test reads and writes */
    int up;
    int opens;
} standin;

static int si_open(void *ctx, const char *ifname, const kelp_can_filter *f, size_t nf, bool fd_frames, kelp_diag *d)
{
    standin *s = ctx;
    (void)ifname; (void)f; (void)nf; (void)fd_frames; (void)d;
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, sv) < 0) return KELP_ERR_IO;
    s->peer = sv[1];
    s->opens++;
    return sv[0];
}

static int si_is_up(void *ctx, const char *ifname)
{
    (void)ifname;
    return ((standin *)ctx)->up;
}

static standin SI;
static kelp_can_ops OPS;
static kelp_can_port P;

static void setup(void)
{
    memset(&SI, 0, sizeof SI);
    SI.up = 1;
    OPS = (kelp_can_ops){ si_open, si_is_up, false, &SI };
}

static void teardown(void)
{
    kelp_can_port_close(&P);
    if (SI.peer > 0) close(SI.peer);
}

static void peer_send(uint32_t canid, const void *data, uint8_t len, bool fd)
{
    struct canfd_frame c;
    memset(&c, 0, sizeof c);
    c.can_id = canid;
    c.len = len;
    memcpy(c.data, data, len);
    ck_assert_int_eq(write(SI.peer, &c, fd ? CANFD_MTU : CAN_MTU), fd ? CANFD_MTU : CAN_MTU);
}

START_TEST(t_frames_filters_and_skips)
{
    const uint16_t vars[] = { 7 };
    kelp_can_filter f[4];
    size_t nf = kelp_can_filters(vars, 1, f, 4);
    ck_assert_int_eq(kelp_can_port_open(&P, &OPS, "vcan0", f, nf, true), 0);
    const uint8_t d[8] = { 0x05, 0x02, 0, 0, 0, 42, 0, 0 };
    peer_send(KELP_CAN_ID(4, 2, 0, 8) | CAN_EFF_FLAG, d, 6, false);                 /* filtered out */
    peer_send(KELP_CAN_ID(4, 2, 0, 7) | CAN_EFF_FLAG | CAN_RTR_FLAG, d, 0, false);  /* remote request */
    peer_send(CAN_ERR_FLAG | 0x40u, d, 8, false);                          /* error frame */
    ck_assert_int_eq(write(SI.peer, d, 5), 5);                                      /* not a frame */
    peer_send(KELP_CAN_ID(4, 2, 0, 7) | CAN_EFF_FLAG, d, 6, false);
    uint8_t big[64] = { 0x05, 0x02, 0, 0, 0, 43 };
    peer_send(KELP_CAN_ID(4, 2, 1, 7) | CAN_EFF_FLAG, big, 64, true);
    kelp_can_frame fr;
    ck_assert_int_eq(kelp_can_port_read(&P, &fr), 1);
    ck_assert_uint_eq(fr.id, KELP_CAN_ID(4, 2, 0, 7));
    ck_assert(!fr.fd);
    ck_assert_uint_eq(fr.len, 6);
    ck_assert_uint_eq(fr.data[5], 42);
    ck_assert_int_eq(kelp_can_port_read(&P, &fr), 1);
    ck_assert(fr.fd);
    ck_assert_uint_eq(fr.len, 64);
    ck_assert_uint_eq(fr.data[5], 43);
    ck_assert_int_eq(kelp_can_port_read(&P, &fr), 0);
    ck_assert_uint_eq(P.rx_filtered, 1);
    ck_assert_uint_eq(P.rx_other, 3);
    ck_assert_uint_eq(P.rx, 2);
    /* writes: classic and FD sizes, extended flag set */
    kelp_can_frame w;
    memset(&w, 0, sizeof w);
    w.id = KELP_CAN_ID(3, 1, 2, 9);
    w.len = 8;
    w.data[7] = 0x77;
    ck_assert_int_eq(kelp_can_port_write(&P, &w), 0);
    w.fd = true;
    w.len = 12;
    ck_assert_int_eq(kelp_can_port_write(&P, &w), 0);
    struct canfd_frame c;
    ck_assert_int_eq(read(SI.peer, &c, sizeof c), CAN_MTU);
    ck_assert_uint_eq(c.can_id, KELP_CAN_ID(3, 1, 2, 9) | CAN_EFF_FLAG);
    ck_assert_uint_eq(c.data[7], 0x77);
    ck_assert_int_eq(read(SI.peer, &c, sizeof c), CANFD_MTU);
    ck_assert_uint_eq(c.len, 12);
    w.len = 65;
    ck_assert_int_eq(kelp_can_port_write(&P, &w), KELP_ERR_ARG);
}
END_TEST

typedef struct sink {
    kelp_can_port *p;
} sink;

static int port_emit(void *user, const kelp_can_frame *f)
{
    return kelp_can_port_write(((sink *)user)->p, f);
}

START_TEST(t_message_through_port_reordered)
{
    ck_assert_int_eq(kelp_can_port_open(&P, &OPS, "vcan0", NULL, 0, false), 0);
    kelp_can_dict d;
    kelp_can_dict_init(&d);
    static kelp_can_tx tx;
    static kelp_can_rx rx;
    ck_assert_int_eq(kelp_can_tx_init(&tx, 9, false), 0);
    kelp_can_rx_init(&rx, 1.0);
    const char *text = "status=ok,leak=false,volts=15.9,amps=2.25,temp=21.5";
    kelp_can_msg m;
    memset(&m, 0, sizeof m);
    m.name = "POWER_STATUS";
    m.kind = KELP_CAN_KIND_STRING;
    m.sval = (const uint8_t *)text;
    m.slen = strlen(text);
    sink s = { &P };
    int nf = kelp_can_send(&tx, &d, &m, port_emit, &s);
    ck_assert_int_gt(nf, 5);
    ck_assert_uint_eq(P.tx, (unsigned long)nf);
    /* the peer swaps frames 2 and 3 and puts everything back */
    struct canfd_frame c[16];
    for (int i = 0; i < nf; i++) ck_assert_int_eq(read(SI.peer, &c[i], sizeof c[i]), CAN_MTU);
    struct canfd_frame t = c[2];
    c[2] = c[3];
    c[3] = t;
    for (int i = 0; i < nf; i++) ck_assert_int_eq(write(SI.peer, &c[i], CAN_MTU), CAN_MTU);
    kelp_can_frame fr;
    kelp_can_msg out;
    int got = 0;
    while (kelp_can_port_read(&P, &fr) == 1)
        if (kelp_can_rx_frame(&rx, &d, &fr, 0, &out) == 1) got++;
    ck_assert_int_eq(got, 1);
    ck_assert_str_eq(out.name, "POWER_STATUS");
    ck_assert_str_eq((const char *)out.sval, text);
    ck_assert_uint_eq(out.node, 9);
    ck_assert_uint_eq(rx.st.out_of_order, 1);
}
END_TEST

START_TEST(t_down_and_reopen)
{
    ck_assert_int_eq(kelp_can_port_open(&P, &OPS, "vcan0", NULL, 0, false), 0);
    int fdnum = P.fd;
    close(SI.peer); /* the stand-in's "interface went away" */
    SI.peer = -1;
    SI.up = 0;
    kelp_can_frame fr;
    ck_assert_int_eq(kelp_can_port_read(&P, &fr), KELP_ERR_IO);
    ck_assert(P.down);
    ck_assert_uint_eq(P.went_down, 1);
    ck_assert_int_eq(P.diag.code, KELP_ERR_IO);
    ck_diag_has(&P.diag, "went down");
    ck_assert_int_eq(P.fd, fdnum);
    ck_assert_int_eq(kelp_can_port_read(&P, &fr), 0); /* quiet while down */
    memset(&fr, 0, sizeof fr);
    fr.id = KELP_CAN_ID(4, 1, 0, 1);
    fr.len = 2;
    ck_assert_int_eq(kelp_can_port_write(&P, &fr), KELP_ERR_STATE);
    ck_assert_int_eq(kelp_can_port_maintain(&P), 0); /* not up yet */
    ck_assert_int_eq(SI.opens, 1);
    SI.up = 1;
    ck_assert_int_eq(kelp_can_port_maintain(&P), 1);
    ck_assert(!P.down);
    ck_assert_uint_eq(P.reopened, 1);
    ck_assert_int_eq(P.fd, fdnum); /* an app watching the number keeps working */
    ck_assert_int_eq(kelp_can_port_write(&P, &fr), 0);
    struct canfd_frame c;
    ck_assert_int_eq(read(SI.peer, &c, sizeof c), CAN_MTU);
    ck_assert_uint_eq(c.can_id & CAN_EFF_MASK, fr.id);
    /* a write to a vanished peer also takes the port down */
    close(SI.peer);
    SI.peer = -1;
    ck_assert_int_eq(kelp_can_port_write(&P, &fr), KELP_ERR_IO);
    ck_assert(P.down);
    ck_assert_uint_eq(P.went_down, 2);
}
END_TEST

START_TEST(t_socketcan_fails_cleanly_without_can)
{
    const uint16_t vars[] = { 3 };
    kelp_can_filter f[2];
    size_t nf = kelp_can_filters(vars, 1, f, 2);
    int rc = kelp_can_port_open(&P, &kelp_can_socketcan_ops, "kelpnosuch0", f, nf, true);
    ck_assert_int_eq(rc, KELP_ERR_IO);
    ck_assert(P.down); /* left down on a quiet placeholder, to be opened when the interface is up */
    ck_assert_int_ge(P.fd, 0);
    kelp_can_frame fr;
    ck_assert_int_eq(kelp_can_port_read(&P, &fr), 0);
    ck_assert_int_eq(kelp_can_port_maintain(&P), 0); /* no such interface: nothing tried */
    /* no CAN in the kernel, or no such interface: either way the reason is given */
    ck_assert_int_eq(P.diag.code, KELP_ERR_IO);
#ifndef KELP_NO_ERRMSG
    ck_assert(strstr(kelp_diag_text(&P.diag), "CAN_RAW") || strstr(kelp_diag_text(&P.diag), "no such interface"));
#endif
    ck_assert_int_eq(kelp_can_socketcan_ops.is_up(NULL, "kelpnosuch0"), 0);
    ck_assert_int_eq(kelp_can_socketcan_ops.is_up(NULL, "lo"), 1);
}
END_TEST

Suite *kelp_can_edge_suite(void)
{
    Suite *s = suite_create("can_edge");
    TCase *tc = tcase_create("standin");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, t_frames_filters_and_skips);
    tcase_add_test(tc, t_message_through_port_reordered);
    tcase_add_test(tc, t_down_and_reopen);
    tcase_add_test(tc, t_socketcan_fails_cleanly_without_can);
    suite_add_tcase(s, tc);
    return s;
}
