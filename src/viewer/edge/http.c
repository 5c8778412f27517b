/* kelp-viewer's web server over libmicrohttpd (see include/kelp/edge/viewer.h).
 *
 * Hand-off: the model thread formats JSON into frames (a ring, each frame a heap copy with its
 * "data: ...\n\n" framing) under h->mu and broadcasts h->cv; every event-stream connection
 * runs on its own microhttpd thread and copies the frames it has not sent yet. A new
 * connection asks the model thread for a snapshot (h->want_snap, a byte on the wake pipe)
 * and waits for it on h->cv. */
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include <kelp/edge/viewer.h>
#include <kelp/util.h>

#define RING 64                /* frames kept for slow connections */
#define REQS 64                /* page requests waiting for the model thread */
#define JSON_CAP (8u << 20)    /* bytes of one JSON text (a snapshot of 512 vehicles with full trails is ~3 MB) */
#define PING_S 1               /* an idle stream gets a comment this often (finds closed pages) */
#define SNAP_WAIT_S 5          /* a connection gives up waiting for a snapshot after this */

typedef struct frame {
    unsigned long id;
    char *text;                /* "event: ..\ndata: ..\n\n" */
    size_t len;
} frame;

struct kelp_viewer_http {
    struct MHD_Daemon *d;
    kelp_viewer_http_cfg cfg;
    char docroot[512], image[512], token[128];
    int wake[2];
    double push_period, last_push;
    uint32_t pushed_seq;
    char *json;                /* the model thread's scratch */
    pthread_mutex_t mu;
    pthread_cond_t cv;
    /* under mu */
    frame ring[RING];
    unsigned long next_id;     /* id the next frame gets */
    char *snap;                /* the last snapshot message */
    size_t snap_len;
    unsigned long snap_after;  /* frames with id > this follow it */
    unsigned long snap_gen;
    bool want_snap, stopping;
    kelp_viewer_req reqs[REQS];
    unsigned nreq;
    unsigned clients;
    size_t last_snap_bytes, last_frame_bytes;
    unsigned long frames;
};

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void wake(kelp_viewer_http *h)
{
    char b = 1;
    ssize_t n = write(h->wake[1], &b, 1); /* non-blocking: a full pipe already wakes */
    (void)n;
}

static void drain(kelp_viewer_http *h)
{
    char b[64];
    while (read(h->wake[0], b, sizeof b) > 0) {
    }
}

/* "event: E\ndata: JSON\n\n" on the heap */
static char *sse(const char *event, const char *json, size_t jlen, size_t *len)
{
    size_t el = event ? strlen(event) + 8 : 0, sz = el + jlen + 9;
    char *t = malloc(sz);
    if (!t) return NULL;
    int h = snprintf(t, sz, "%s%s%sdata: ", event ? "event: " : "", event ? event : "", event ? "\n" : "");
    if (h < 0) {
        free(t);
        return NULL;
    }
    size_t k = (size_t)h;
    memcpy(t + k, json, jlen);
    k += jlen;
    memcpy(t + k, "\n\n", 3);
    *len = k + 2;
    return t;
}

static void ring_add(kelp_viewer_http *h, char *text, size_t len)
{
    frame *f = &h->ring[h->next_id % RING];
    free(f->text);
    f->id = h->next_id++;
    f->text = text;
    f->len = len;
    h->frames++;
    h->last_frame_bytes = len;
    pthread_cond_broadcast(&h->cv);
}

int kelp_viewer_http_push_event(kelp_viewer_http *h, const char *event, const char *json)
{
    size_t len;
    char *t = sse(event, json, strlen(json), &len);
    if (!t) return KELP_ERR_NOSPACE;
    pthread_mutex_lock(&h->mu);
    ring_add(h, t, len);
    pthread_mutex_unlock(&h->mu);
    return 0;
}

int kelp_viewer_http_pump(kelp_viewer_http *h, const kelp_viewer *v, double now, double rate, bool force)
{
    double t = mono();
    pthread_mutex_lock(&h->mu);
    bool want = h->want_snap;
    pthread_mutex_unlock(&h->mu);
    drain(h);
    int pushed = 0;
    bool due = force || want || t - h->last_push >= h->push_period;
    if (due && (kelp_viewer_seq(v) != h->pushed_seq || t - h->last_push >= 1.0 || force)) {
        /* the changes (or, once a second, the time alone) */
        size_t n = 0;
        if (kelp_viewer_json_changes(v, h->pushed_seq, now, rate, h->json, JSON_CAP, &n) < 0) return KELP_ERR_NOSPACE;
        size_t len;
        char *text = sse(NULL, h->json, n, &len);
        if (!text) return KELP_ERR_NOSPACE;
        pthread_mutex_lock(&h->mu);
        ring_add(h, text, len);
        pthread_mutex_unlock(&h->mu);
        h->pushed_seq = kelp_viewer_seq(v);
        h->last_push = t;
        pushed = 1;
    }
    if (want) {
        size_t n = 0;
        if (kelp_viewer_json_snapshot(v, now, rate, h->json, JSON_CAP, &n) < 0) return KELP_ERR_NOSPACE;
        size_t len;
        char *text = sse(NULL, h->json, n, &len);
        if (!text) return KELP_ERR_NOSPACE;
        pthread_mutex_lock(&h->mu);
        free(h->snap);
        h->snap = text;
        h->snap_len = len;
        h->snap_after = h->next_id - 1; /* every change up to now is in it (pushed just above) */
        h->snap_gen++;
        h->want_snap = false;
        h->last_snap_bytes = len;
        pthread_cond_broadcast(&h->cv);
        pthread_mutex_unlock(&h->mu);
    }
    return pushed;
}

int kelp_viewer_http_next(kelp_viewer_http *h, kelp_viewer_req *out)
{
    int got = 0;
    pthread_mutex_lock(&h->mu);
    if (h->nreq) {
        *out = h->reqs[0];
        memmove(h->reqs, h->reqs + 1, (h->nreq - 1) * sizeof h->reqs[0]);
        h->nreq--;
        got = 1;
    }
    pthread_mutex_unlock(&h->mu);
    return got;
}

unsigned kelp_viewer_http_port(const kelp_viewer_http *h)
{
    const union MHD_DaemonInfo *i = MHD_get_daemon_info(h->d, MHD_DAEMON_INFO_BIND_PORT);
    return i ? i->port : h->cfg.port;
}

int kelp_viewer_http_fd(const kelp_viewer_http *h)
{
    return h->wake[0];
}

unsigned kelp_viewer_http_clients(const kelp_viewer_http *h)
{
    kelp_viewer_http *m = (kelp_viewer_http *)h;
    pthread_mutex_lock(&m->mu);
    unsigned n = m->clients;
    pthread_mutex_unlock(&m->mu);
    return n;
}

void kelp_viewer_http_sizes(const kelp_viewer_http *h, size_t *snapshot, size_t *frame_bytes, unsigned long *frames)
{
    kelp_viewer_http *m = (kelp_viewer_http *)h;
    pthread_mutex_lock(&m->mu);
    *snapshot = m->last_snap_bytes;
    *frame_bytes = m->last_frame_bytes;
    *frames = m->frames;
    pthread_mutex_unlock(&m->mu);
}

/* ------------------------------------------------------------------ the event stream */

typedef struct stream {
    kelp_viewer_http *h;
    char *buf;                 /* what is being sent */
    size_t len, off;
    unsigned long next;        /* next frame id to send */
    bool have_snap;
} stream;

static ssize_t stream_read(void *cls, uint64_t pos, char *out, size_t max)
{
    stream *s = cls;
    kelp_viewer_http *h = s->h;
    (void)pos;
    if (s->off < s->len) {
        size_t n = s->len - s->off < max ? s->len - s->off : max;
        memcpy(out, s->buf + s->off, n);
        s->off += n;
        return (ssize_t)n;
    }
    free(s->buf);
    s->buf = NULL;
    s->len = s->off = 0;
    pthread_mutex_lock(&h->mu);
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    if (!s->have_snap || (h->next_id > RING && s->next < h->next_id - RING)) {
        /* first message, or fallen behind the ring: a snapshot */
        unsigned long gen = h->snap_gen;
        h->want_snap = true;
        wake(h);
        until.tv_sec += SNAP_WAIT_S;
        while (h->snap_gen == gen && !h->stopping)
            if (pthread_cond_timedwait(&h->cv, &h->mu, &until) == ETIMEDOUT) break;
        if (h->stopping || h->snap_gen == gen || !h->snap) {
            pthread_mutex_unlock(&h->mu);
            return MHD_CONTENT_READER_END_WITH_ERROR;
        }
        s->buf = malloc(h->snap_len);
        if (s->buf) memcpy(s->buf, h->snap, h->snap_len);
        s->len = s->buf ? h->snap_len : 0;
        s->next = h->snap_after + 1;
        s->have_snap = true;
    } else {
        until.tv_sec += PING_S;
        while (s->next >= h->next_id && !h->stopping)
            if (pthread_cond_timedwait(&h->cv, &h->mu, &until) == ETIMEDOUT) break;
        if (h->stopping) {
            pthread_mutex_unlock(&h->mu);
            return MHD_CONTENT_READER_END_OF_STREAM;
        }
        if (s->next < h->next_id && s->next + RING >= h->next_id) {
            frame *f = &h->ring[s->next % RING];
            s->buf = malloc(f->len);
            if (s->buf) memcpy(s->buf, f->text, f->len);
            s->len = s->buf ? f->len : 0;
            s->next++;
        } else if (s->next >= h->next_id) {
            s->buf = strdup(": ping\n\n");
            s->len = s->buf ? strlen(s->buf) : 0;
        }
    }
    pthread_mutex_unlock(&h->mu);
    if (!s->buf) return MHD_CONTENT_READER_END_WITH_ERROR;
    return stream_read(cls, pos, out, max);
}

static void stream_free(void *cls)
{
    stream *s = cls;
    pthread_mutex_lock(&s->h->mu);
    s->h->clients--;
    pthread_mutex_unlock(&s->h->mu);
    free(s->buf);
    free(s);
}

/* ------------------------------------------------------------------ requests */

static enum MHD_Result reply_text(struct MHD_Connection *c, unsigned code, const char *text)
{
    struct MHD_Response *r = MHD_create_response_from_buffer(strlen(text), (void *)text, MHD_RESPMEM_MUST_COPY);
    if (!r) return MHD_NO;
    MHD_add_response_header(r, "Content-Type", "text/plain; charset=utf-8");
    MHD_add_response_header(r, "Cache-Control", "no-store");
    enum MHD_Result rc = MHD_queue_response(c, code, r);
    MHD_destroy_response(r);
    return rc;
}

static const char *mime_of(const char *path)
{
    const char *dot = strrchr(path, '.');
    if (!dot) return "application/octet-stream";
    if (!strcmp(dot, ".html")) return "text/html; charset=utf-8";
    if (!strcmp(dot, ".js")) return "text/javascript; charset=utf-8";
    if (!strcmp(dot, ".css")) return "text/css; charset=utf-8";
    if (!strcmp(dot, ".png")) return "image/png";
    if (!strcmp(dot, ".jpg") || !strcmp(dot, ".jpeg")) return "image/jpeg";
    if (!strcmp(dot, ".tif") || !strcmp(dot, ".tiff")) return "image/tiff";
    return "application/octet-stream";
}

static enum MHD_Result reply_file(struct MHD_Connection *c, const char *path, const char *cookie)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) < 0 || !S_ISREG(st.st_mode)) {
        if (fd >= 0) close(fd);
        return reply_text(c, MHD_HTTP_NOT_FOUND, "not found\n");
    }
    struct MHD_Response *r = MHD_create_response_from_fd((uint64_t)st.st_size, fd);
    if (!r) {
        close(fd);
        return MHD_NO;
    }
    MHD_add_response_header(r, "Content-Type", mime_of(path));
    MHD_add_response_header(r, "Cache-Control", "no-cache");
    if (cookie) MHD_add_response_header(r, "Set-Cookie", cookie);
    enum MHD_Result rc = MHD_queue_response(c, MHD_HTTP_OK, r);
    MHD_destroy_response(r);
    return rc;
}

/* constant-time comparison of a presented token */
static bool token_eq(const char *a, const char *b)
{
    size_t na = strlen(a), nb = strlen(b);
    unsigned char d = (unsigned char)(na != nb);
    for (size_t i = 0; i < na && i < nb; i++) d |= (unsigned char)(a[i] ^ b[i]);
    return d == 0;
}

static bool authorised(kelp_viewer_http *h, struct MHD_Connection *c, bool *from_query)
{
    *from_query = false;
    if (!h->token[0]) return true;
    const char *q = MHD_lookup_connection_value(c, MHD_GET_ARGUMENT_KIND, "token");
    if (q && token_eq(q, h->token)) return (*from_query = true);
    const char *hd = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "X-Kelp-Token");
    if (hd && token_eq(hd, h->token)) return true;
    const char *ck = MHD_lookup_connection_value(c, MHD_COOKIE_KIND, "kelp_token");
    return ck && token_eq(ck, h->token);
}

static void queue_req(kelp_viewer_http *h, kelp_viewer_req_kind kind, unsigned idx, double value)
{
    pthread_mutex_lock(&h->mu);
    if (h->nreq < REQS) h->reqs[h->nreq++] = (kelp_viewer_req){kind, idx, value};
    pthread_mutex_unlock(&h->mu);
    wake(h);
}

static enum MHD_Result handle_post(kelp_viewer_http *h, struct MHD_Connection *c, const char *url)
{
    const char *mark = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "X-Kelp");
    if (!mark || strcmp(mark, "1") != 0) return reply_text(c, MHD_HTTP_FORBIDDEN, "missing X-Kelp header\n");
    if (!strcmp(url, "/cmd")) {
        const char *i = MHD_lookup_connection_value(c, MHD_GET_ARGUMENT_KIND, "i");
        long k;
        if (!i || kelp_util_parse_long(i, strlen(i), &k) < 0 || k < 0 || k >= KELP_VIEWER_MAX_CMDS)
            return reply_text(c, MHD_HTTP_BAD_REQUEST, "bad command index\n");
        queue_req(h, KELP_VIEWER_REQ_CMD, (unsigned)k, 0);
        return reply_text(c, MHD_HTTP_OK, "ok\n");
    }
    if (!strcmp(url, "/replay")) {
        const char *op = MHD_lookup_connection_value(c, MHD_GET_ARGUMENT_KIND, "op");
        const char *vs = MHD_lookup_connection_value(c, MHD_GET_ARGUMENT_KIND, "v");
        double val = 0;
        if (vs && kelp_util_parse_finite(vs, strlen(vs), &val) < 0) return reply_text(c, MHD_HTTP_BAD_REQUEST, "bad v\n");
        kelp_viewer_req_kind kind;
        if (op && !strcmp(op, "play")) kind = KELP_VIEWER_REQ_PLAY;
        else if (op && !strcmp(op, "pause")) kind = KELP_VIEWER_REQ_PAUSE;
        else if (op && !strcmp(op, "seek") && vs) kind = KELP_VIEWER_REQ_SEEK;
        else if (op && !strcmp(op, "speed") && vs) kind = KELP_VIEWER_REQ_SPEED;
        else return reply_text(c, MHD_HTTP_BAD_REQUEST, "bad op\n");
        queue_req(h, kind, 0, val);
        return reply_text(c, MHD_HTTP_OK, "ok\n");
    }
    return reply_text(c, MHD_HTTP_NOT_FOUND, "not found\n");
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *c, const char *url, const char *method,
                                  const char *version, const char *upload, size_t *upload_size, void **con_cls)
{
    kelp_viewer_http *h = cls;
    (void)version;
    (void)upload;
    if (*con_cls == NULL) { /* first call: headers only */
        *con_cls = h;
        return MHD_YES;
    }
    if (*upload_size) { /* no bodies are read */
        *upload_size = 0;
        return MHD_YES;
    }
    bool from_query;
    if (!authorised(h, c, &from_query)) return reply_text(c, MHD_HTTP_FORBIDDEN, "token required\n");
    char cookie[200];
    cookie[0] = '\0';
    if (from_query) snprintf(cookie, sizeof cookie, "kelp_token=%s; Path=/; HttpOnly; SameSite=Strict", h->token);
    if (!strcmp(method, "POST")) return handle_post(h, c, url);
    if (strcmp(method, "GET") != 0 && strcmp(method, "HEAD") != 0) return reply_text(c, MHD_HTTP_METHOD_NOT_ALLOWED, "GET or POST\n");
    if (!strcmp(url, "/events")) {
        stream *s = calloc(1, sizeof *s);
        if (!s) return MHD_NO;
        s->h = h;
        struct MHD_Response *r = MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, 64 * 1024, stream_read, s, stream_free);
        if (!r) {
            free(s);
            return MHD_NO;
        }
        pthread_mutex_lock(&h->mu);
        h->clients++;
        pthread_mutex_unlock(&h->mu);
        MHD_add_response_header(r, "Content-Type", "text/event-stream");
        MHD_add_response_header(r, "Cache-Control", "no-store");
        enum MHD_Result rc = MHD_queue_response(c, MHD_HTTP_OK, r);
        MHD_destroy_response(r);
        return rc;
    }
    if (!strcmp(url, "/image")) {
        if (!h->image[0]) return reply_text(c, MHD_HTTP_NOT_FOUND, "no image\n");
        return reply_file(c, h->image, cookie[0] ? cookie : NULL);
    }
    /* static files: a fixed list, so no path ever leaves the document root */
    static const char *const files[] = {"/index.html", "/viewer.js", "/viewer.css"};
    const char *name = !strcmp(url, "/") ? "/index.html" : NULL;
    for (size_t i = 0; !name && i < sizeof files / sizeof files[0]; i++)
        if (!strcmp(url, files[i])) name = files[i];
    if (!name) return reply_text(c, MHD_HTTP_NOT_FOUND, "not found\n");
    char path[600];
    snprintf(path, sizeof path, "%s%s", h->docroot, name);
    return reply_file(c, path, cookie[0] ? cookie : NULL);
}

/* ------------------------------------------------------------------ start / stop */

kelp_viewer_http *kelp_viewer_http_start(const kelp_viewer_http_cfg *cfg, kelp_diag *d)
{
    const char *bind = cfg->bind && cfg->bind[0] ? cfg->bind : "127.0.0.1";
    struct sockaddr_in sa;
    memset(&sa, 0, sizeof sa);
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)cfg->port);
    if (inet_pton(AF_INET, bind, &sa.sin_addr) != 1) {
        (void)kelp_failf(d, KELP_ERR_IO, "--bind %s: not an IPv4 address", bind);
        return NULL;
    }
    bool local = ntohl(sa.sin_addr.s_addr) == 0x7f000001u; /* 127.0.0.1 alone goes without a token */
    if (!local && !(cfg->token && cfg->token[0])) {
        (void)kelp_failf(d, KELP_ERR_IO, "binding %s (not 127.0.0.1) needs a token (--token or token =)", bind);
        return NULL;
    }
    if (cfg->port > 65535) {
        (void)kelp_failf(d, KELP_ERR_IO, "port %u out of range", cfg->port);
        return NULL;
    }
    kelp_viewer_http *h = calloc(1, sizeof *h);
    if (!h) {
        (void)kelp_fail(d, KELP_ERR_IO, "out of memory");
        return NULL;
    }
    h->cfg = *cfg;
    snprintf(h->docroot, sizeof h->docroot, "%s", cfg->docroot ? cfg->docroot : ".");
    snprintf(h->image, sizeof h->image, "%s", cfg->image_path ? cfg->image_path : "");
    if (cfg->token && strlen(cfg->token) >= sizeof h->token) {
        (void)kelp_failf(d, KELP_ERR_IO, "token longer than %zu characters", sizeof h->token - 1);
        free(h);
        return NULL;
    }
    snprintf(h->token, sizeof h->token, "%s", cfg->token ? cfg->token : "");
    for (const char *p = h->token; *p; p++)
        if (*p <= ' ' || *p == ';' || *p == ',' || *p == '"' || *p == '\\' || (unsigned char)*p >= 0x7f) {
            (void)kelp_failf(d, KELP_ERR_IO, "token: printable characters without ; , \" \\ or spaces");
            free(h);
            return NULL;
        }
    h->push_period = cfg->push_period > 0 ? cfg->push_period : 0.2;
    h->json = malloc(JSON_CAP);
    if (!h->json || pipe2(h->wake, O_NONBLOCK | O_CLOEXEC) < 0) {
        (void)kelp_fail(d, KELP_ERR_IO, "out of memory or descriptors");
        free(h->json);
        free(h);
        return NULL;
    }
    pthread_mutex_init(&h->mu, NULL);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_cond_init(&h->cv, &ca); /* CLOCK_REALTIME: the timed waits use it */
    pthread_condattr_destroy(&ca);
    h->next_id = 1;
    h->d = MHD_start_daemon(MHD_USE_THREAD_PER_CONNECTION | MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_ERROR_LOG,
                            0, NULL, NULL, on_request, h, MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&sa,
                            MHD_OPTION_CONNECTION_LIMIT, (unsigned)64, MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)0,
                            MHD_OPTION_END);
    if (!h->d) {
        (void)kelp_failf(d, KELP_ERR_IO, "cannot serve on %s:%u (%s)", bind, cfg->port, strerror(errno));
        close(h->wake[0]);
        close(h->wake[1]);
        free(h->json);
        free(h);
        return NULL;
    }
    return h;
}

void kelp_viewer_http_stop(kelp_viewer_http *h)
{
    if (!h) return;
    pthread_mutex_lock(&h->mu);
    h->stopping = true;
    pthread_cond_broadcast(&h->cv);
    pthread_mutex_unlock(&h->mu);
    MHD_stop_daemon(h->d);
    for (unsigned i = 0; i < RING; i++) free(h->ring[i].text);
    free(h->snap);
    free(h->json);
    close(h->wake[0]);
    close(h->wake[1]);
    pthread_cond_destroy(&h->cv);
    pthread_mutex_destroy(&h->mu);
    free(h);
}
