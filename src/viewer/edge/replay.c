/* kelp-viewer --log: a recorded mission replayed into the page (see include/kelp/edge/viewer.h).
 * The postings the viewer shows (NODE_REPORT, NODE_REPORT_LOCAL, VIEW_*, APPCAST) are read once into memory; the replay
 * clock runs at `speed` times the wall clock; a seek back clears the model and feeds it again
 * from the start (each posting with its own time), so the page sees the state at the new time. */
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <kelp/edge/alog.h>
#include <kelp/edge/cli.h>
#include <kelp/edge/mission.h>
#include <kelp/edge/viewer.h>
#include <kelp/util.h>

#define TICK_MS 20          /* the replay loop's step */
#define STATE_PERIOD 0.25   /* s between replay state messages */
#define SPEED_MAX 20.0

static volatile sig_atomic_t g_stop; /* SIGINT/SIGTERM (the replay's one global) */

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

typedef struct post {
    double t;
    char *var, *val;
} post;

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static bool wanted(const char *var)
{
    kelp_view_kind k;
    return !strcmp(var, "NODE_REPORT") || !strcmp(var, "NODE_REPORT_LOCAL") || !strcmp(var, "APPCAST") ||
           kelp_nodereport_view_kind_of(var, &k) == 0;
}

static void free_posts(post *posts, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        free(posts[i].var);
        free(posts[i].val);
    }
    free(posts);
}

static int load(const char *path, post **out, size_t *n, kelp_diag *d)
{
    kelp_alog_postlog *pl = kelp_alog_postlog_open(path, "shoreside", d);
    if (!pl) return -1;
    size_t cap = 0;
    kelp_post p;
    int rc;
    *out = NULL;
    *n = 0;
    while ((rc = kelp_alog_postlog_next(pl, &p)) == 1) {
        if (!p.is_string || !wanted(p.var)) continue;
        if (*n == cap) {
            cap = cap ? cap * 2 : 1024;
            post *g = realloc(*out, cap * sizeof **out);
            if (!g) break;
            *out = g;
        }
        post *q = &(*out)[*n];
        q->t = p.time;
        q->var = strdup(p.var);
        q->val = strdup(p.sval);
        if (!q->var || !q->val) { /* out of memory: replay what was read so far */
            free(q->var);
            free(q->val);
            break;
        }
        (*n)++;
    }
    kelp_alog_postlog_close(pl);
    if (rc < 0) {
        (void)kelp_failf(d, KELP_ERR_IO, "%s: read error", path);
        free_posts(*out, *n);
        *out = NULL;
        *n = 0;
        return -1;
    }
    return 0;
}

static void copy(char *dst, size_t cap, const char *src)
{
    size_t n = strlen(src);
    if (n >= cap) n = cap - 1;
    memcpy(dst, src, n);
    dst[n] = '\0';
}

/* the mission's datum and viewer block (NAME, else kelp-viewer, else pMarineViewer) */
static void mission_config(kelp_viewer *v, const char *path, const char *name, char *port, char *token, char *image,
                           size_t cap)
{
    kelp_mission_file mf;
    memset(&mf, 0, sizeof mf);
    if (kelp_mission_load(&mf, path) < 0) {
        fprintf(stderr, "%s\n", mf.error);
        return;
    }
    const kelp_mission *m = &mf.m;
    int a = kelp_mission_next(m, -1, -1, "LatOrigin"), b = kelp_mission_next(m, -1, -1, "LongOrigin");
    double lat, lon;
    if (a >= 0 && b >= 0 && kelp_mission_double(&m->nodes[a], &lat) == 0 &&
        kelp_mission_double(&m->nodes[b], &lon) == 0 && kelp_viewer_set_datum(v, lat, lon) < 0)
        fprintf(stderr, "kelp-viewer: %s: LatOrigin/LongOrigin out of range\n", path);
    int blk = kelp_mission_block(m, "ProcessConfig", name ? name : "kelp-viewer");
    if (blk < 0 && !name) blk = kelp_mission_block(m, "ProcessConfig", "pMarineViewer");
    for (int i = blk >= 0 ? kelp_mission_next(m, blk, -1, NULL) : -1; i >= 0; i = kelp_mission_next(m, blk, i, NULL)) {
        const kelp_mission_node *nd = &m->nodes[i];
        char key[64], val[1024];
        if (nd->klen >= sizeof key || kelp_mission_copy(nd, val, sizeof val) < 0) continue;
        memcpy(key, nd->key, nd->klen);
        key[nd->klen] = '\0';
        kelp_diag dg = { 0 };
        if (kelp_viewer_config(v, key, val, &dg) < 0)
            fprintf(stderr, "kelp-viewer: %s:%d: %s\n", path, nd->line, dg.code ? kelp_diag_text(&dg) : "refused");
        else if (kelp_util_strieq(key, "port")) copy(port, 16, val);
        else if (kelp_util_strieq(key, "token")) copy(token, 128, val);
        else if (kelp_util_strieq(key, "tiff_file")) copy(image, cap, val);
    }
    kelp_mission_free(&mf);
}

enum { O_LOG = 300, O_PORT, O_BIND, O_TOKEN, O_DOCROOT, O_SPEED, O_PAUSED };

static const kelp_cli cli = {
    .name = "kelp-viewer",
    .purpose = "Replay a recorded mission (kelp-record's LCM log or an .alog) in kelp-viewer's page.",
    .synopsis = "--log RUN.lcm [OPTIONS] [mission.moos [NAME]]",
    .opts = (const kelp_cli_opt[]){
        { "log", required_argument, O_LOG, "RUN.lcm", "the log to replay" },
        { "port", required_argument, O_PORT, "N", "HTTP port (default 8080; 0: any free)" },
        { "bind", required_argument, O_BIND, "ADDR", "IPv4 address (default 127.0.0.1; others need --token)" },
        { "token", required_argument, O_TOKEN, "T", "access token" },
        { "docroot", required_argument, O_DOCROOT, "DIR", "the page's files" },
        { "speed", required_argument, O_SPEED, "S", "initial speed, 1..20 (default 1)" },
        { "paused", no_argument, O_PAUSED, NULL, "start paused" },
        { NULL, 0, 0, NULL, NULL } },
    .more = "The mission (optional) gives the datum (LatOrigin/LongOrigin) and the pMarineViewer block.\n",
};

int kelp_viewer_replay_main(int argc, char **argv)
{
    const char *log = NULL, *bind = NULL, *tok = NULL, *docroot = NULL;
    long port = -1;
    double speed = 1;
    bool playing = true;
    int c, status;
    while ((c = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        switch (c) {
        case KELP_CLI_EXIT: return status;
        case O_LOG: log = optarg; break;
        case O_BIND: bind = optarg; break;
        case O_TOKEN: tok = optarg; break;
        case O_DOCROOT: docroot = optarg; break;
        case O_PAUSED: playing = false; break;
        case O_PORT:
            if (kelp_util_parse_long(optarg, strlen(optarg), &port) < 0 || port < 0 || port > 65535)
                return kelp_cli_error(&cli, "--port: 0..65535");
            break;
        case O_SPEED:
            if (kelp_util_parse_finite(optarg, strlen(optarg), &speed) < 0 || speed < 1 || speed > SPEED_MAX)
                return kelp_cli_error(&cli, "--speed: 1..20");
            break;
        default: return 2;
        }
    }
    if (!log) return kelp_cli_error(&cli, "--log RUN.lcm");
    kelp_viewer *v = malloc(sizeof *v);
    if (!v) return 1;
    kelp_viewer_init(v);
    char port_s[16] = "", token[128] = "", image[512] = "", droot[512], shown[512], info[512];
    kelp_diag err = {0};
    const char *mission = optind < argc ? argv[optind] : NULL;
    if (mission) mission_config(v, mission, optind + 1 < argc ? argv[optind + 1] : NULL, port_s, token, image, sizeof image);
    kelp_viewer_http_cfg hc = {bind, 8080, tok ? tok : token, docroot, NULL, 0};
    long p2;
    if (port_s[0] && kelp_util_parse_long(port_s, strlen(port_s), &p2) == 0 && p2 >= 0 && p2 <= 65535) hc.port = (unsigned)p2;
    if (port >= 0) hc.port = (unsigned)port;
    if (!docroot && kelp_viewer_docroot(droot, sizeof droot) < 0) {
        fprintf(stderr, "kelp-viewer: the page's files (share/viewer) not found: use --docroot\n");
        free(v);
        return 1;
    }
    if (!docroot) hc.docroot = droot;
    double n, s, e, w;
    if (image[0] && kelp_viewer_image_files(image, mission, shown, sizeof shown, info, sizeof info) == 0 &&
        kelp_viewer_read_info(info, &n, &s, &e, &w, &err) == 0 &&
        kelp_viewer_set_image(v, "/image", n, s, e, w) == 0)
        hc.image_path = shown;
    post *posts;
    size_t np;
    if (load(log, &posts, &np, &err) < 0) {
        fprintf(stderr, "kelp-viewer: %s\n", kelp_diag_text(&err));
        free(v);
        return 1;
    }
    if (np == 0) fprintf(stderr, "kelp-viewer: %s: no NODE_REPORT or VIEW_* postings\n", log);
    double t0 = np ? posts[0].t : 0, t1 = np ? posts[np - 1].t : 0;
    kelp_diag_clear(&err);
    kelp_viewer_http *h = kelp_viewer_http_start(&hc, &err);
    if (!h) {
        fprintf(stderr, "kelp-viewer: %s\n", kelp_diag_text(&err));
        free_posts(posts, np);
        free(v);
        return 1;
    }
    printf("kelp-viewer: replaying %s (%zu postings, %.1f s): http://%s:%u/%s%s\n", log, np, t1 - t0,
           bind ? bind : "127.0.0.1", kelp_viewer_http_port(h), hc.token && hc.token[0] ? "?token=" : "",
           hc.token ? hc.token : "");
    fflush(stdout);
    kelp_cli_on_stop(on_signal);

    double t = t0, wprev = wall(), next_state = 0;
    size_t next = 0;
    bool changed = true;
    while (!g_stop) {
        struct pollfd pfd = {kelp_viewer_http_fd(h), POLLIN, 0};
        (void)poll(&pfd, 1, TICK_MS);
        kelp_viewer_req rq;
        while (kelp_viewer_http_next(h, &rq) == 1) {
            changed = true;
            if (rq.kind == KELP_VIEWER_REQ_PLAY) {
                playing = true;
                if (t >= t1) t = t0; /* play at the end starts again */
            } else if (rq.kind == KELP_VIEWER_REQ_PAUSE) {
                playing = false;
            } else if (rq.kind == KELP_VIEWER_REQ_SPEED) {
                speed = rq.value < 1 ? 1 : rq.value > SPEED_MAX ? SPEED_MAX : rq.value;
            } else if (rq.kind == KELP_VIEWER_REQ_SEEK) {
                double target = t0 + rq.value;
                target = target < t0 ? t0 : target > t1 ? t1 : target;
                if (target < t) {
                    kelp_viewer_clear(v);
                    next = 0;
                }
                t = target;
            }
        }
        double wn = wall();
        if (playing) t += (wn - wprev) * speed;
        wprev = wn;
        if (t >= t1 && playing) {
            t = t1;
            playing = false;
            changed = true;
        }
        for (; next < np && posts[next].t <= t; next++)
            (void)kelp_viewer_mail(v, posts[next].var, posts[next].val, strlen(posts[next].val), posts[next].t);
        (void)kelp_viewer_tick(v, t);
        if (changed || wn >= next_state) {
            char js[256];
            snprintf(js, sizeof js, "{\"t0\":%.3f,\"t1\":%.3f,\"t\":%.3f,\"playing\":%d,\"speed\":%g}", t0, t1, t,
                     playing ? 1 : 0, speed);
            KELP_IGNORE(kelp_viewer_http_push_event(h, "replay", js));
            next_state = wn + STATE_PERIOD;
        }
        if (kelp_viewer_http_pump(h, v, t, playing ? speed : 0, changed) < 0)
            fprintf(stderr, "kelp-viewer: the page's JSON does not fit its buffer\n");
        changed = false;
    }
    kelp_viewer_http_stop(h);
    free_posts(posts, np);
    free(v);
    return 0;
}
