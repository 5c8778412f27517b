/* kelp links (edge): the byte pipe between a modem driver and the modem.
 *
 *   serial      libserialport (19200 8N1 by default, no flow control).  libserialport 0.1.1
 *               refuses pseudo-terminals (sysfs lookup, TIOCMGET on a pty gives ENOTTY), so when
 *               it fails on a device that is a tty the link opens it with plain termios instead
 *               (raw, 8N1, the same baud).  Symbolic links (socat's link=/tmp/ttyA) are resolved
 *               again at every (re)open, so a re-created pty is found under the same name.
 *   tcp client  connects to host:port (IPv4 address or name), non-blocking connect.
 *   tcp server  listens on port; one modem connection at a time (a new one replaces the old).
 *
 * Every link has one file descriptor that stays the same for its whole life (an epoll set
 * holding whatever the link currently has open: device, socket, listening socket), so an event
 * loop watches kelp_link_fd() once (kelp_app_watch_fd) and never has to re-register after a
 * reconnect.  When the device disappears (EOF, EIO, POLLHUP, write error) the link closes it
 * and kelp_link_service() re-opens it every reconnect_s seconds until it is back.
 *
 * Not thread-safe; one thread owns a link.  Reads and writes never block for long (writes poll
 * for at most write_timeout_ms when the device is full, then fail).
 */
#ifndef KELP_LINK_H
#define KELP_LINK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <kelp/config.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum kelp_link_type {
    KELP_LINK_SERIAL = 0,
    KELP_LINK_TCP_CLIENT = 1,
    KELP_LINK_TCP_SERVER = 2
} kelp_link_type;

/** Serial back end choice (KELP_LINK_SERIAL). */
typedef enum kelp_link_serial_backend {
    KELP_LINK_BACKEND_AUTO = 0,         /**< libserialport, termios if that fails on a tty */
    KELP_LINK_BACKEND_LIBSERIALPORT = 1,/**< libserialport only */
    KELP_LINK_BACKEND_TERMIOS = 2       /**< termios only */
} kelp_link_serial_backend;

typedef struct kelp_link_cfg {
    kelp_link_type type;
    const char *device;        /**< serial: device path (copied) */
    unsigned baud;             /**< serial: default 19200 */
    kelp_link_serial_backend backend;
    const char *host;          /**< tcp client: server address or name (copied) */
    unsigned port;             /**< tcp client: port to connect to; tcp server: port to listen on */
    double reconnect_s;        /**< seconds between re-open attempts, default 1 */
    int write_timeout_ms;      /**< longest wait for a full device on write, default 500 */
} kelp_link_cfg;

typedef struct kelp_link_counters {
    uint64_t bytes_in, bytes_out;
    uint32_t opens;            /**< successful (re)connections */
    uint32_t open_failures;    /**< failed attempts */
    uint32_t disconnects;      /**< device lost / peer closed */
    uint32_t write_errors;
} kelp_link_counters;

typedef struct kelp_link kelp_link;

/** The small interface a driver loop uses, so any link type (or a test fake) fits. */
typedef struct kelp_link_ops {
    int (*open)(kelp_link *l);                                        /**< 0 or <0 */
    int (*read)(kelp_link *l, uint8_t *buf, size_t cap, size_t *n);   /**< 0 (n may be 0) or KELP_ERR_IO */
    int (*write)(kelp_link *l, const uint8_t *buf, size_t n);         /**< 0 or KELP_ERR_IO */
    void (*close)(kelp_link *l);
    int (*fd)(const kelp_link *l);
} kelp_link_ops;

void kelp_link_cfg_default(kelp_link_cfg *cfg, kelp_link_type type);

/** Create a link and try to open it once.  A device that is not there yet is NOT an error:
 *  the link retries in kelp_link_service().  @return NULL only for a bad configuration
 *  (d: KELP_ERR_ARG, KELP_ERR_UNSUPPORTED for a baud rate) or when the process is out of
 *  resources (KELP_ERR_NOSPACE, KELP_ERR_IO); d may be NULL. */
kelp_link *kelp_link_create(const kelp_link_cfg *cfg, kelp_diag *d);
void kelp_link_destroy(kelp_link *l);

/** The link's operations (the same for every link of a type). */
const kelp_link_ops *kelp_link_get_ops(const kelp_link *l);

/** Open now (a no-op when already connected; a tcp server starts listening).
 *  @return 0 when connected (or listening), else <0 with kelp_link_error() set. */
KELP_MUST_CHECK int kelp_link_open(kelp_link *l);
/** Read what is available without blocking; *n = 0 when nothing is.  A tcp server accepts a
 *  waiting connection here.  @return 0, or KELP_ERR_IO when the device was lost (the link is
 *  then closed and will be re-opened by kelp_link_service). */
KELP_MUST_CHECK int kelp_link_read(kelp_link *l, uint8_t *buf, size_t cap, size_t *n);
/** Write all n bytes.  @return 0; KELP_ERR_STATE when not connected; KELP_ERR_IO on failure
 *  (the device is then closed). */
KELP_MUST_CHECK int kelp_link_write(kelp_link *l, const void *buf, size_t n);
/** Close the device (the link stays usable: service() or open() re-opens it). */
void kelp_link_close(kelp_link *l);
/** The stable pollable descriptor (readable when the device has data, a connection waits or
 *  the device hung up). */
int kelp_link_fd(const kelp_link *l);

/** Re-open when down and the retry interval has passed.  `now` is any monotonic seconds.
 *  @return 1 when the link has just (re)connected, 0 otherwise. */
int kelp_link_service(kelp_link *l, kelp_time now);

bool kelp_link_connected(const kelp_link *l);
/** A tcp server that is listening without a client (connected() is false then). */
bool kelp_link_listening(const kelp_link *l);
/** Last error text ("" if none). */
const char *kelp_link_error(const kelp_link *l);
/** "serial /dev/pts/3 19200 8N1 (termios)", "tcp client 127.0.0.1:50010", ... */
const char *kelp_link_describe(const kelp_link *l);
const kelp_link_counters *kelp_link_get_counters(const kelp_link *l);
/** Serial: which back end opened the device ("libserialport", "termios") or "" . */
const char *kelp_link_backend(const kelp_link *l);
/** tcp server: the port actually bound (useful with port 0). */
unsigned kelp_link_bound_port(const kelp_link *l);

#ifdef __cplusplus
}
#endif

#endif
