/* kelp links over real pseudo-terminals (openpty) and loopback TCP. */
#include <check.h>
#include "check_diag.h"
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <unistd.h>

#include <kelp/link.h>

static int make_pty(int *master, char *name, size_t cap)
{
    int m, s;
    char n[128];
    if (openpty(&m, &s, n, NULL, NULL) != 0) return -1;
    struct termios t;
    tcgetattr(s, &t);
    cfmakeraw(&t);
    tcsetattr(s, TCSANOW, &t);
    close(s); /* the link opens the slave by name */
    snprintf(name, cap, "%s", n);
    *master = m;
    return 0;
}

/* wait until the link's fd is readable, then read what is there */
static size_t link_recv(kelp_link *l, uint8_t *buf, size_t cap, int ms)
{
    size_t got = 0;
    for (int i = 0; i < ms / 10 && got == 0; i++) {
        struct pollfd pf = { kelp_link_fd(l), POLLIN, 0 };
        if (poll(&pf, 1, 10) <= 0) continue;
        size_t n = 0;
        ck_assert_int_eq(kelp_link_read(l, buf, cap, &n), 0);
        got += n;
    }
    return got;
}

static size_t fd_recv(int fd, uint8_t *buf, size_t cap, int ms)
{
    struct pollfd pf = { fd, POLLIN, 0 };
    if (poll(&pf, 1, ms) <= 0) return 0;
    ssize_t n = read(fd, buf, cap);
    return n > 0 ? (size_t)n : 0;
}

START_TEST(test_serial_pty_termios_both_ways)
{
    int m;
    char name[128];
    ck_assert_int_eq(make_pty(&m, name, sizeof name), 0);
    kelp_link_cfg c;
    kelp_link_cfg_default(&c, KELP_LINK_SERIAL);
    ck_assert_uint_eq(c.baud, 19200); /* the Micro-Modem default */
    c.device = name;
    kelp_diag err;
    kelp_diag_clear(&err);
    kelp_link *l = kelp_link_create(&c, &err);
    ck_assert_ptr_nonnull(l);
    ck_assert(kelp_link_connected(l));
    /* libserialport 0.1.1 refuses ptys: the link fell back to termios */
    ck_assert_str_eq(kelp_link_backend(l), "termios");
    ck_assert_int_eq(kelp_link_service(l, 0), 1); /* reports the first connection once */
    ck_assert_int_eq(kelp_link_service(l, 0.1), 0);
    const char *out = "$CCCFG,SRC,1*31\r\n";
    ck_assert_int_eq(kelp_link_write(l, out, strlen(out)), 0);
    uint8_t buf[256];
    size_t n = fd_recv(m, buf, sizeof buf, 1000);
    ck_assert_uint_eq(n, strlen(out));
    ck_assert_int_eq(memcmp(buf, out, n), 0);
    const char *in = "$CACFG,SRC,1*33\r";
    ck_assert_int_eq(write(m, in, strlen(in)), (ssize_t)strlen(in));
    n = link_recv(l, buf, sizeof buf, 1000);
    ck_assert_uint_eq(n, strlen(in));
    ck_assert_int_eq(memcmp(buf, in, n), 0);
    /* nothing more: a read returns 0 bytes, not an error */
    ck_assert_int_eq(kelp_link_read(l, buf, sizeof buf, &n), 0);
    ck_assert_uint_eq(n, 0);
    ck_assert(kelp_link_connected(l));
    const kelp_link_counters *k = kelp_link_get_counters(l);
    ck_assert_uint_eq(k->bytes_out, strlen(out));
    ck_assert_uint_eq(k->bytes_in, strlen(in));
    /* the device goes away: the read reports it and the link is down */
    close(m);
    ck_assert_int_eq(kelp_link_read(l, buf, sizeof buf, &n), KELP_ERR_IO);
    ck_assert(!kelp_link_connected(l));
    ck_assert_int_eq(kelp_link_write(l, "x", 1), KELP_ERR_STATE);
    kelp_link_destroy(l);
}
END_TEST

START_TEST(test_serial_backends_and_errors)
{
    int m;
    char name[128];
    ck_assert_int_eq(make_pty(&m, name, sizeof name), 0);
    kelp_link_cfg c;
    kelp_link_cfg_default(&c, KELP_LINK_SERIAL);
    c.device = name;
    c.backend = KELP_LINK_BACKEND_LIBSERIALPORT; /* as shipped it cannot open a pty */
    kelp_diag err;
    kelp_diag_clear(&err);
    kelp_link *l = kelp_link_create(&c, &err);
    ck_assert_ptr_nonnull(l);
    ck_assert(!kelp_link_connected(l));
    ck_assert_ptr_nonnull(strstr(kelp_link_error(l), "libserialport"));
    kelp_link_destroy(l);
    /* a missing device is not fatal: retried */
    c.backend = KELP_LINK_BACKEND_AUTO;
    c.device = "/nonexistent/ttyS9";
    l = kelp_link_create(&c, &err);
    ck_assert_ptr_nonnull(l);
    ck_assert(!kelp_link_connected(l));
    ck_assert_ptr_nonnull(strstr(kelp_link_error(l), "No such file"));
    ck_assert_int_eq(kelp_link_service(l, 10.0), 0);
    ck_assert_uint_ge(kelp_link_get_counters(l)->open_failures, 2);
    kelp_link_destroy(l);
    /* not a terminal */
    c.device = "/dev/null";
    c.backend = KELP_LINK_BACKEND_TERMIOS;
    l = kelp_link_create(&c, &err);
    ck_assert_ptr_nonnull(l);
    ck_assert(!kelp_link_connected(l));
    ck_assert_ptr_nonnull(strstr(kelp_link_error(l), "not a terminal"));
    kelp_link_destroy(l);
    /* bad configurations */
    c.device = "";
    ck_assert_ptr_null(kelp_link_create(&c, &err));
    c.device = name;
    c.baud = 12345;
    kelp_diag_clear(&err);
    ck_assert_ptr_null(kelp_link_create(&c, &err));
    ck_diag(&err, KELP_ERR_UNSUPPORTED, "unsupported baud rate 12345");
    close(m);
}
END_TEST

START_TEST(test_serial_reconnect_same_name)
{
    /* a stable name (as socat's link=) pointing at a pty that disappears and comes back */
    char dir[] = "/tmp/kelp-link-XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(dir));
    char ln[256];
    snprintf(ln, sizeof ln, "%s/ttyMODEM", dir);
    int m1;
    char n1[128];
    ck_assert_int_eq(make_pty(&m1, n1, sizeof n1), 0);
    ck_assert_int_eq(symlink(n1, ln), 0);
    kelp_link_cfg c;
    kelp_link_cfg_default(&c, KELP_LINK_SERIAL);
    c.device = ln;
    c.reconnect_s = 1.0;
    kelp_diag err;
    kelp_diag_clear(&err);
    kelp_link *l = kelp_link_create(&c, &err);
    ck_assert_ptr_nonnull(l);
    ck_assert(kelp_link_connected(l));
    int fd = kelp_link_fd(l);
    ck_assert_int_eq(kelp_link_service(l, 0), 1);
    close(m1); /* the device disappears */
    uint8_t buf[64];
    size_t n;
    ck_assert_int_eq(kelp_link_read(l, buf, sizeof buf, &n), KELP_ERR_IO);
    ck_assert_int_eq(kelp_link_service(l, 1.0), 0); /* still gone */
    int m2;
    char n2[128];
    ck_assert_int_eq(make_pty(&m2, n2, sizeof n2), 0);
    ck_assert_int_eq(unlink(ln), 0);
    ck_assert_int_eq(symlink(n2, ln), 0);
    ck_assert_int_eq(kelp_link_service(l, 1.5), 0); /* retry interval not over yet */
    ck_assert_int_eq(kelp_link_service(l, 2.1), 1); /* back */
    ck_assert(kelp_link_connected(l));
    ck_assert_int_eq(kelp_link_fd(l), fd); /* the event loop never re-registers */
    ck_assert_int_eq(kelp_link_write(l, "ok\r\n", 4), 0);
    ck_assert_uint_eq(fd_recv(m2, buf, sizeof buf, 1000), 4);
    ck_assert_uint_eq(kelp_link_get_counters(l)->opens, 2);
    ck_assert_uint_eq(kelp_link_get_counters(l)->disconnects, 1);
    kelp_link_destroy(l);
    close(m2);
    unlink(ln);
    rmdir(dir);
}
END_TEST

START_TEST(test_tcp_client_server)
{
    kelp_link_cfg sc;
    kelp_link_cfg_default(&sc, KELP_LINK_TCP_SERVER);
    sc.port = 0; /* any free port */
    kelp_diag err;
    kelp_diag_clear(&err);
    kelp_link *srv = kelp_link_create(&sc, &err);
    ck_assert_ptr_nonnull(srv);
    ck_assert(kelp_link_listening(srv));
    ck_assert(!kelp_link_connected(srv));
    unsigned port = kelp_link_bound_port(srv);
    ck_assert_uint_gt(port, 0);
    kelp_link_cfg cc;
    kelp_link_cfg_default(&cc, KELP_LINK_TCP_CLIENT);
    cc.host = "127.0.0.1";
    cc.port = port;
    kelp_link *cli = kelp_link_create(&cc, &err);
    ck_assert_ptr_nonnull(cli);
    ck_assert(kelp_link_connected(cli));
    /* the server accepts when its fd is readable */
    struct pollfd pf = { kelp_link_fd(srv), POLLIN, 0 };
    ck_assert_int_eq(poll(&pf, 1, 1000), 1);
    ck_assert_int_eq(kelp_link_service(srv, 0), 1);
    ck_assert(kelp_link_connected(srv));
    uint8_t buf[64];
    ck_assert_int_eq(kelp_link_write(cli, "$CAREV,000052,AUV,0.93.0.09*07\r", 31), 0);
    ck_assert_uint_eq(link_recv(srv, buf, sizeof buf, 1000), 31);
    ck_assert_int_eq(memcmp(buf, "$CAREV", 6), 0);
    ck_assert_int_eq(kelp_link_write(srv, "$CCCLK\r\n", 8), 0);
    ck_assert_uint_eq(link_recv(cli, buf, sizeof buf, 1000), 8);
    /* the client goes away: the server notices and listens again; a new client is served */
    kelp_link_destroy(cli);
    size_t n = 0;
    int rc = 0;
    for (int i = 0; i < 100 && rc == 0; i++) {
        pf.revents = 0;
        if (poll(&pf, 1, 10) > 0) rc = kelp_link_read(srv, buf, sizeof buf, &n);
    }
    ck_assert_int_eq(rc, KELP_ERR_IO);
    ck_assert(kelp_link_listening(srv));
    cli = kelp_link_create(&cc, &err);
    ck_assert(kelp_link_connected(cli));
    ck_assert_int_eq(poll(&pf, 1, 1000), 1);
    ck_assert_int_eq(kelp_link_service(srv, 1), 1);
    ck_assert_int_eq(kelp_link_write(srv, "x", 1), 0);
    ck_assert_uint_eq(link_recv(cli, buf, sizeof buf, 1000), 1);
    /* the server disappears: the client read fails, retries fail until it is back */
    kelp_link_destroy(srv);
    rc = 0;
    for (int i = 0; i < 100 && rc == 0; i++) {
        struct pollfd cf = { kelp_link_fd(cli), POLLIN, 0 };
        if (poll(&cf, 1, 10) > 0) rc = kelp_link_read(cli, buf, sizeof buf, &n);
    }
    ck_assert_int_eq(rc, KELP_ERR_IO);
    ck_assert(!kelp_link_connected(cli));
    ck_assert_int_eq(kelp_link_service(cli, 100), 0); /* refused */
    ck_assert_ptr_nonnull(strstr(kelp_link_error(cli), "refused"));
    kelp_link_destroy(cli);
    /* bad configurations */
    cc.port = 0;
    ck_assert_ptr_null(kelp_link_create(&cc, &err));
    cc.port = 1;
    cc.host = "";
    ck_assert_ptr_null(kelp_link_create(&cc, &err));
}
END_TEST

Suite *kelp_link_suite(void)
{
    Suite *s = suite_create("link");
    TCase *t = tcase_create("serial");
    tcase_add_test(t, test_serial_pty_termios_both_ways);
    tcase_add_test(t, test_serial_backends_and_errors);
    tcase_add_test(t, test_serial_reconnect_same_name);
    suite_add_tcase(s, t);
    t = tcase_create("tcp");
    tcase_add_test(t, test_tcp_client_server);
    suite_add_tcase(s, t);
    return s;
}
