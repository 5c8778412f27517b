/* kelp LCM transport: kelp_bus over kelp's own udpm sockets (LCM wire format, no liblcm). */
#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/edge/udpm.h>
#include <kelp/lcmbus.h>

/* the bus's registrations plus its two sync channels */
#define KELP_LCMBUS_MAX_PATTERNS (KELP_MAX_SUBS + 2)
/* messages handled per kelp_lcmbus_handle call, so a flood cannot starve the app's loop */
#define KELP_LCMBUS_MAX_BATCH 4096

struct kelp_lcmbus {
    kelp_udpm_sock *sock;
    char (*pat)[KELP_MAX_NAME];
    size_t npat;
    kelp_bus bus;
    kelp_bus_storage st;
};

int kelp_lcmbus_url(const char *mission_url, char *buf, size_t cap)
{
    const char *u = getenv("KELP_LCM_URL");
    if (!u || !*u) u = mission_url;
    if (!u || !*u) u = KELP_LCM_DEFAULT_URL;
    int n;
    if (strncmp(u, "udpm://", 7) == 0 && !strstr(u, "recv_buf_size"))
        n = snprintf(buf, cap, "%s%crecv_buf_size=%d", u, strchr(u, '?') ? '&' : '?', KELP_LCM_RECV_BUF);
    else
        n = snprintf(buf, cap, "%s", u);
    return (n < 0 || (size_t)n >= cap) ? KELP_ERR_NOSPACE : KELP_OK;
}

int kelp_lcmbus_mission_url(const kelp_mission *m, char *buf, size_t cap, int *line)
{
    char murl[400] = "", port[16] = "", url[512];
    static const char *const keys[2] = { "LCM_URL", "ServerPort" };
    char *vals[2] = { murl, port };
    size_t caps[2] = { sizeof murl, sizeof port };
    *line = 0;
    for (int k = 0; k < 2; k++) {
        int i = kelp_mission_next(m, -1, -1, keys[k]);
        if (i < 0) continue;
        if (kelp_mission_copy(&m->nodes[i], vals[k], caps[k]) < 0) {
            *line = m->nodes[i].line;
            return KELP_ERR_RANGE;
        }
    }
    int rc = kelp_udpm_community_url(murl, port, url, sizeof url);
    if (rc < 0) {
        int i = kelp_mission_next(m, -1, -1, murl[0] ? "LCM_URL" : "ServerPort");
        *line = i >= 0 ? m->nodes[i].line : 0;
        return rc;
    }
    return kelp_lcmbus_url(url[0] ? url : NULL, buf, cap);
}

/* Only channels some registration (or the sync protocol) asked for reach the bus. */
static bool subscribed(const kelp_lcmbus *lb, const char *channel)
{
    for (size_t i = 0; i < lb->npat; i++)
        if (kelp_bus_match(lb->pat[i], channel)) return true;
    return false;
}

static int tr_subscribe(void *ctx, const char *pattern)
{
    kelp_lcmbus *lb = ctx;
    for (size_t i = 0; i < lb->npat; i++)
        if (strcmp(lb->pat[i], pattern) == 0) return KELP_OK;
    if (lb->npat >= KELP_LCMBUS_MAX_PATTERNS) return KELP_ERR_NOSPACE;
    return kelp_bus_name_set(lb->pat[lb->npat++], pattern);
}

static int tr_publish(void *ctx, const char *channel, const uint8_t *data, size_t len)
{
    kelp_lcmbus *lb = ctx;
    return kelp_udpm_sock_publish(lb->sock, channel, data, len);
}

kelp_lcmbus *kelp_lcmbus_open(const char *url, const char *app, const char *community, kelp_bus_handler handler,
                              void *user, kelp_diag *d)
{
    kelp_lcmbus *lb = calloc(1, sizeof *lb);
    if (!lb) {
        (void)kelp_fail(d, KELP_ERR_NOSPACE, "out of memory");
        return NULL;
    }
    kelp_diag why = {0};
    lb->sock = kelp_udpm_sock_open(url, &why);
    if (!lb->sock) {
        (void)kelp_failf(d, KELP_ERR_IO, "cannot open LCM URL '%s': %s", url, kelp_diag_text(&why));
        free(lb);
        return NULL;
    }
    lb->pat = calloc(KELP_LCMBUS_MAX_PATTERNS, sizeof *lb->pat);
    lb->st.nsubs = KELP_MAX_SUBS;
    lb->st.ncache = KELP_MAX_CACHE;
    lb->st.scratch_cap = kelp_bus_scratch_size();
    lb->st.subs = calloc(lb->st.nsubs, sizeof *lb->st.subs);
    lb->st.cache = calloc(lb->st.ncache, sizeof *lb->st.cache);
    lb->st.scratch = malloc(lb->st.scratch_cap);
    lb->st.rx = malloc(sizeof *lb->st.rx);
    if (!lb->pat || !lb->st.subs || !lb->st.cache || !lb->st.scratch || !lb->st.rx) {
        (void)kelp_fail(d, KELP_ERR_NOSPACE, "out of memory");
        kelp_lcmbus_close(lb);
        return NULL;
    }
    /* a reply channel unique to this client */
    char reply[KELP_MAX_NAME];
    unsigned long nonce = 0;
    FILE *r = fopen("/dev/urandom", "rb");
    if (r) {
        if (fread(&nonce, sizeof nonce, 1, r) != 1) nonce = 0;
        fclose(r);
    }
    if (kelp_bus_reply_channel(app, (uint32_t)nonce, reply) < 0) {
        (void)kelp_fail(d, KELP_ERR_ARG, "bad app name");
        kelp_lcmbus_close(lb);
        return NULL;
    }
    kelp_bus_transport tr = { tr_publish, tr_subscribe, lb };
    int rc = kelp_bus_init(&lb->bus, app, community, reply, &tr, &lb->st, handler, user);
    if (rc < 0) {
        (void)kelp_failf(d, KELP_ERR_IO, "bus init: %s", kelp_err_str(rc));
        kelp_lcmbus_close(lb);
        return NULL;
    }
    kelp_bus_limits lim;
    kelp_bus_limits_default(&lim);
    lim.time_margin = KELP_BUS_TIME_MARGIN; /* real clocks here: reject far-future stamps */
    if (kelp_bus_set_limits(&lb->bus, &lim) < 0) { /* constant limits: cannot fail */ }
    return lb;
}

void kelp_lcmbus_close(kelp_lcmbus *lb)
{
    if (!lb) return;
    kelp_udpm_sock_close(lb->sock);
    free(lb->pat);
    free(lb->st.subs);
    free(lb->st.cache);
    free(lb->st.scratch);
    free(lb->st.rx);
    free(lb);
}

kelp_bus *kelp_lcmbus_bus(kelp_lcmbus *lb)
{
    return &lb->bus;
}

void kelp_lcmbus_ignore_own(kelp_lcmbus *lb, bool on)
{
    kelp_udpm_sock_ignore_own(lb->sock, on);
}

int kelp_lcmbus_fd(kelp_lcmbus *lb)
{
    return kelp_udpm_sock_fd(lb->sock);
}

int kelp_lcmbus_handle(kelp_lcmbus *lb, int timeout_ms, double now)
{
    int handled = 0;
    kelp_udpm_msg m;
    if (kelp_udpm_sock_next(lb->sock, &m) == 0) {
        struct pollfd pfd = { kelp_udpm_sock_fd(lb->sock), POLLIN, 0 };
        int pr = poll(&pfd, 1, timeout_ms);
        if (pr < 0) return errno == EINTR ? 0 : KELP_ERR_IO;
        if (pr == 0 || kelp_udpm_sock_next(lb->sock, &m) == 0) return 0;
    }
    do {
        handled++;
        if (subscribed(lb, m.channel)) KELP_IGNORE(kelp_bus_receive(&lb->bus, m.channel, m.data, m.len, now));
    } while (handled < KELP_LCMBUS_MAX_BATCH && kelp_udpm_sock_next(lb->sock, &m) == 1);
    return handled;
}

void kelp_lcmbus_get_stats(kelp_lcmbus *lb, kelp_udpm_sock_stats *out)
{
    kelp_udpm_sock_get_stats(lb->sock, out);
}

void kelp_lcmbus_cork(kelp_lcmbus *lb, bool on)
{
    if (lb) kelp_udpm_sock_cork(lb->sock, on);
}

int kelp_lcmbus_publish_raw(kelp_lcmbus *lb, const char *channel, const void *data, size_t len)
{
    return tr_publish(lb, channel, data, len);
}
