/* kelp-modemsim: its ProcessConfig block (iModemSim's names accepted too). */
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <kelp/kv.h>
#include "msim.h"

/* ------------------------------------------------------------------ configuration */

static int param_d(kelp_app *app, const char *key, double *v, double lo, double hi)
{
    int rc = kelp_app_param_double(app, key, v);
    if (rc < 0) return kelp_app_config_error(app, kelp_app_param(app, key), "%s must be a number", key);
    if (rc > 0 && !(*v >= lo && *v <= hi))
        return kelp_app_config_error(app, kelp_app_param(app, key), "%s must be in [%g, %g]", key, lo, hi);
    return 0;
}

static int parse_xyz(const char *s, double *x, double *y, double *z)
{
    char b[64];
    double *dst[3] = { x, y, z };
    static const char *const keys[3] = { "x", "y", "depth" };
    for (int i = 0; i < 3; i++) {
        int rc = kelp_kv_get(s, ',', keys[i], b, sizeof b);
        if (rc < 0) return -1;
        if (rc == 0) {
            if (i == 2 && kelp_kv_get(s, ',', "z", b, sizeof b) == 1) {
                /* z is accepted for depth */
            } else if (i == 2) {
                *dst[i] = 0;
                continue;
            } else {
                return -1;
            }
        }
        if (kelp_util_parse_double(b, strlen(b), dst[i]) < 0 || !isfinite(*dst[i])) return -1;
    }
    return 0;
}

uint32_t msim_instance(void)
{
    uint32_t v = 0;
    int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
        if (read(fd, &v, sizeof v) != (ssize_t)sizeof v) v = 0;
        close(fd);
    }
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return v ^ (uint32_t)getpid() ^ (uint32_t)ts.tv_nsec;
}

int msim_config(kelp_app *app, msim_app *s, kelp_modemsim_cfg *c)
{
    /* modem_id: the initial NVRAM SRC; iModemSim's blocks have none, and the host sets SRC at
     * start-up anyway ($CCCFG,SRC,<its modem_id>), so 1 until then */
    double d = 1;
    int have_id = kelp_app_param_double(app, "modem_id", &d);
    if (have_id < 0 || d != floor(d) || d < 1 || d > KELP_MODEMSIM_MAX_ID)
        return kelp_app_config_error(app, kelp_app_param(app, "modem_id"), "modem_id must be in 1..%d",
                                     KELP_MODEMSIM_MAX_ID);
    c->modem_id = s->modem_id = (int)d;
    /* host side: a pseudo-terminal (pty_link, or iModemSim's Port) or a TCP server port */
    if (kelp_app_param_str(app, "pty_link", s->pty_link, sizeof s->pty_link) <= 0)
        KELP_IGNORE(kelp_app_param_str(app, "Port", s->pty_link, sizeof s->pty_link));
    (void)kelp_app_param(app, "Speed"); /* iModemSim's baud: a pty has none */
    if (kelp_app_param(app, "tcp_port")) {
        if (param_d(app, "tcp_port", &d, 1, 65535) < 0) return -1;
        s->tcp_port = (unsigned)d;
    }
    if (s->tcp_port && s->pty_link[0])
        return kelp_app_config_error(app, kelp_app_param(app, "tcp_port"), "give either pty_link or tcp_port");
    /* position: x/y/depth (or iModemSim's ConstantPosX/Y/Depth), NODE_REPORT or NAV_* variables */
    const char *px[3][2] = { { "x", "ConstantPosX" }, { "y", "ConstantPosY" }, { "depth", "ConstantDepth" } };
    double *pv[3] = { &c->x, &c->y, &c->depth };
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < 2; k++) {
            if (!kelp_app_param(app, px[i][k])) continue;
            if (param_d(app, px[i][k], pv[i], -1e9, 1e9) < 0) return -1;
        }
    }
    char buf[256];
    if (kelp_app_param_str(app, "position", buf, sizeof buf) > 0 && parse_xyz(buf, &c->x, &c->y, &c->depth) < 0)
        return kelp_app_config_error(app, kelp_app_param(app, "position"), "position must be x=..,y=..[,depth=..]");
    (void)kelp_app_param(app, "InputLocType");
    KELP_IGNORE(kelp_app_param_str(app, "node_report_var", s->node_report_var, sizeof s->node_report_var));
    if (kelp_app_param_bool(app, "nav_vars", &s->nav_vars) < 0) return -1;
    s->nav_x = c->x;
    s->nav_y = c->y;
    s->nav_depth = c->depth;
    /* channel model */
    if (param_d(app, "sound_speed", &c->sound_speed, 1, 10000) < 0 ||
        param_d(app, "loss_probability", &c->loss_probability, 0, 1) < 0 ||
        param_d(app, "loss", &c->loss_probability, 0, 1) < 0 || param_d(app, "max_range", &c->max_range, 0, 1e7) < 0 ||
        param_d(app, "ci_seconds", &c->ci_seconds, 0, 60) < 0 || param_d(app, "mini_seconds", &c->mini_seconds, 0, 60) < 0 ||
        param_d(app, "turnaround_seconds", &c->turnaround_seconds, 0, 60) < 0 ||
        param_d(app, "drq_timeout", &c->drq_timeout_seconds, 0, 60) < 0 ||
        param_d(app, "ping_timeout", &c->ping_timeout_seconds, 0, 600) < 0 ||
        param_d(app, "rev_interval", &c->rev_interval_seconds, 0, 86400) < 0)
        return -1;
    d = 1;
    if (param_d(app, "seed", &d, 0, 1.8e19) < 0) return -1;
    c->seed = (uint64_t)d;
    if (kelp_app_param_bool(app, "clock_set_at_boot", &c->clock_set_at_boot) < 0) return -1;
    static char rev[24];
    if (kelp_app_param_str(app, "revision", rev, sizeof rev) > 0) c->revision = rev;
    for (const kelp_mission_node *n = kelp_app_param_next(app, "lbl_beacon", NULL); n;
         n = kelp_app_param_next(app, "lbl_beacon", n)) {
        if (c->n_lbl >= 4) return kelp_app_config_error(app, n, "at most 4 lbl_beacon lines (A..D)");
        if (kelp_mission_copy(n, buf, sizeof buf) < 0 ||
            parse_xyz(buf, &c->lbl_x[c->n_lbl], &c->lbl_y[c->n_lbl], &c->lbl_depth[c->n_lbl]) < 0)
            return kelp_app_config_error(app, n, "lbl_beacon must be x=..,y=..[,depth=..]");
        c->n_lbl++;
    }
    snprintf(s->channel_var, sizeof s->channel_var, "%s", DEFAULT_CHANNEL);
    KELP_IGNORE(kelp_app_param_str(app, "channel_var", s->channel_var, sizeof s->channel_var));
    KELP_IGNORE(kelp_app_param_str(app, "channel_url", s->channel_url, sizeof s->channel_url));
    /* iModemSim's channel: UDP broadcasts to BroadcastAddr:IPPort; here an LCM channel on that
     * port, kept on this host when BroadcastAddr is a loopback address */
    char bcast[64] = "127.0.0.1";
    KELP_IGNORE(kelp_app_param_str(app, "BroadcastAddr", bcast, sizeof bcast));
    if (kelp_app_param(app, "IPPort")) {
        if (param_d(app, "IPPort", &d, 1, 65535) < 0) return -1;
        if (!s->channel_url[0])
            snprintf(s->channel_url, sizeof s->channel_url, "udpm://239.255.76.67:%u?ttl=%d", (unsigned)d,
                     strncmp(bcast, "127.", 4) == 0 ? 0 : 1);
    }
    s->publish_events = true;
    if (kelp_app_param_bool(app, "publish_events", &s->publish_events) < 0) return -1;
    return 0;
}
