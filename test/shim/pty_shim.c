/* LD_PRELOAD shim that lets libserialport 0.1.1 open pseudo-terminals (TEST USE ONLY).
 * (NOTES-PLATFORM.md section 5.)  libserialport looks a port up in sysfs
 * (/sys/class/tty/pts/N does not exist) and reads the modem lines with TIOCMGET (ENOTTY on a
 * pty).  This shim answers both:
 *  - __lxstat / readlink of /sys/class/tty/pts/ * behave as /sys/class/tty/tty0, a symlink into
 *    ../../devices/virtual/tty/...
 *  - ioctl TIOCMGET/TIOCMSET/TIOCMBIS/TIOCMBIC that fail with ENOTTY use a fake line word.
 * Build: cc -shared -fPIC -o pty_shim.so pty_shim.c -ldl ; run: LD_PRELOAD=./pty_shim.so prog */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdarg.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

static int fake_lines = TIOCM_DTR | TIOCM_RTS | TIOCM_CTS | TIOCM_DSR | TIOCM_CD;
static const char PTS[] = "/sys/class/tty/pts/";

static const char *fix(const char *path)
{
    return (path && strncmp(path, PTS, sizeof PTS - 1) == 0) ? "/sys/class/tty/tty0" : path;
}

int ioctl(int fd, unsigned long req, ...);
int ioctl(int fd, unsigned long req, ...)
{
    static int (*real)(int, unsigned long, ...);
    va_list ap;
    va_start(ap, req);
    void *arg = va_arg(ap, void *);
    va_end(ap);
    if (!real) real = (int (*)(int, unsigned long, ...))dlsym(RTLD_NEXT, "ioctl");
    int rc = real(fd, req, arg);
    if (rc < 0 && errno == ENOTTY && arg) {
        int *v = arg;
        switch (req) {
        case TIOCMGET: *v = fake_lines; return 0;
        case TIOCMSET: fake_lines = *v; return 0;
        case TIOCMBIS: fake_lines |= *v; return 0;
        case TIOCMBIC: fake_lines &= ~*v; return 0;
        default: break;
        }
    }
    return rc;
}

int __lxstat(int ver, const char *path, struct stat *st);
int __lxstat(int ver, const char *path, struct stat *st)
{
    static int (*real)(int, const char *, struct stat *);
    if (!real) real = (int (*)(int, const char *, struct stat *))dlsym(RTLD_NEXT, "__lxstat");
    return real(ver, fix(path), st);
}

ssize_t readlink(const char *path, char *buf, size_t n);
ssize_t readlink(const char *path, char *buf, size_t n)
{
    static ssize_t (*real)(const char *, char *, size_t);
    if (!real) real = (ssize_t(*)(const char *, char *, size_t))dlsym(RTLD_NEXT, "readlink");
    if (strncmp(path, PTS, sizeof PTS - 1) == 0) {
        static const char target[] = "../../devices/virtual/tty/pts";
        size_t k = sizeof target - 1 < n ? sizeof target - 1 : n;
        memcpy(buf, target, k);
        return (ssize_t)k;
    }
    return real(path, buf, n);
}
