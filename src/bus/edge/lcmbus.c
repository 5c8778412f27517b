/* kelp LCM transport: kelp_bus over liblcm (udpm multicast). */
#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <lcm/lcm.h>
#include <kelp/lcmbus.h>

struct kelp_lcmbus {
    lcm_t *lcm;
    kelp_bus bus;
    kelp_bus_storage st;
    double now;
    int handled;
};

int kelp_lcm_url(const char *mission_url, char *buf, size_t cap)
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

static void on_lcm(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    kelp_lcmbus *lb = user;
    lb->handled++;
    (void)kelp_bus_receive(&lb->bus, channel, rbuf->data, rbuf->data_size, lb->now);
}

/* glob -> anchored POSIX regex (LCM anchors it with ^...$) */
static int glob_to_regex(const char *g, char *out, size_t cap)
{
    size_t o = 0;
    for (; *g; g++) {
        const char *add;
        char one[3] = { 0 };
        if (*g == '*') add = ".*";
        else if (*g == '?') add = ".";
        else if (strchr(".^$|()[]{}+\\", *g)) { one[0] = '\\'; one[1] = *g; add = one; }
        else { one[0] = *g; add = one; }
        size_t n = strlen(add);
        if (o + n + 1 > cap) return KELP_ERR_NOSPACE;
        memcpy(out + o, add, n);
        o += n;
    }
    out[o] = 0;
    return KELP_OK;
}

static int tr_subscribe(void *ctx, const char *pattern)
{
    kelp_lcmbus *lb = ctx;
    char re[4 * KELP_MAX_NAME];
    int rc = glob_to_regex(pattern, re, sizeof re);
    if (rc < 0) return rc;
    lcm_subscription_t *s = lcm_subscribe(lb->lcm, re, on_lcm, lb);
    if (!s) return KELP_ERR_IO;
    lcm_subscription_set_queue_capacity(s, 0); /* unbounded: never drop a burst */
    return KELP_OK;
}

static int tr_publish(void *ctx, const char *channel, const uint8_t *data, size_t len)
{
    kelp_lcmbus *lb = ctx;
    if (len > 0x7fffffff) return KELP_ERR_ARG;
    return lcm_publish(lb->lcm, channel, data, (unsigned int)len) == 0 ? KELP_OK : KELP_ERR_IO;
}

kelp_lcmbus *kelp_lcmbus_open(const char *url, const char *app, const char *community, kelp_bus_handler handler,
                              void *user, char *err, size_t errcap)
{
    kelp_lcmbus *lb = calloc(1, sizeof *lb);
    if (!lb) {
        snprintf(err, errcap, "out of memory");
        return NULL;
    }
    lb->lcm = lcm_create(url);
    if (!lb->lcm) {
        snprintf(err, errcap, "cannot open LCM URL '%s' (is there a multicast route? see README)", url);
        free(lb);
        return NULL;
    }
    lb->st.nsubs = KELP_MAX_SUBS;
    lb->st.ncache = KELP_MAX_CACHE;
    lb->st.scratch_cap = kelp_bus_scratch_size();
    lb->st.subs = calloc(lb->st.nsubs, sizeof *lb->st.subs);
    lb->st.cache = calloc(lb->st.ncache, sizeof *lb->st.cache);
    lb->st.scratch = malloc(lb->st.scratch_cap);
    lb->st.rx = malloc(sizeof *lb->st.rx);
    if (!lb->st.subs || !lb->st.cache || !lb->st.scratch || !lb->st.rx) {
        snprintf(err, errcap, "out of memory");
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
    snprintf(reply, sizeof reply, "KELP_SYNC_%.24s_%08lx", app, nonce & 0xfffffffful);
    kelp_bus_transport tr = { tr_publish, tr_subscribe, lb };
    int rc = kelp_bus_init(&lb->bus, app, community, reply, &tr, &lb->st, handler, user);
    if (rc < 0) {
        snprintf(err, errcap, "bus init: %s", kelp_strerror(rc));
        kelp_lcmbus_close(lb);
        return NULL;
    }
    return lb;
}

void kelp_lcmbus_close(kelp_lcmbus *lb)
{
    if (!lb) return;
    if (lb->lcm) lcm_destroy(lb->lcm);
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

int kelp_lcmbus_fd(kelp_lcmbus *lb)
{
    return lcm_get_fileno(lb->lcm);
}

int kelp_lcmbus_handle(kelp_lcmbus *lb, int timeout_ms, double now)
{
    lb->now = now;
    lb->handled = 0;
    struct pollfd pfd = { lcm_get_fileno(lb->lcm), POLLIN, 0 };
    int first = 1;
    for (;;) {
        int pr = poll(&pfd, 1, first ? timeout_ms : 0);
        first = 0;
        if (pr < 0) {
            if (errno == EINTR) return lb->handled;
            return KELP_ERR_IO;
        }
        if (pr == 0 || !(pfd.revents & POLLIN)) break;
        if (lcm_handle(lb->lcm) != 0) return KELP_ERR_IO;
    }
    return lb->handled;
}

int kelp_lcmbus_publish_raw(kelp_lcmbus *lb, const char *channel, const void *data, size_t len)
{
    return tr_publish(lb, channel, data, len);
}
