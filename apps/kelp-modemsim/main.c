/* kelp-modemsim: a simulated WHOI Micro-Modem (iModemSim). The protocol and the channel are the
 * core kelp_modemsim (include/kelp/modemsim.h), the host port is kelp_hostport; this is wiring. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kelp/nodereport.h>
#include "msim.h"


/* ------------------------------------------------------------------ host I/O */
static void host_write(const char *b, size_t n, void *u)
{
    msim_app *s = u;
    size_t before = s->host.dropped_out;
    /* nobody reading (pty buffer full) or no client: the line is lost, as on a wire */
    if (kelp_hostport_write(&s->host, b, n) && before == 0 && (s->host.master >= 0 || s->host.cfd >= 0))
        kelp_app_run_warning(s->app, "host not reading: output dropped");
}

static void feed_host(void *ctx, const uint8_t *b, size_t n)
{
    msim_app *s = ctx;
    kelp_time now = kelp_app_time(s->app);
    if (kelp_modemsim_feed(&s->m, b, n, now) < 0) kelp_app_run_warning(s->app, "modem feed failed");
    kelp_modemsim_tick(&s->m, now);
}

static void on_host(kelp_app *app, void *st, int fd)
{
    msim_app *s = st;
    (void)fd;
    unsigned what = kelp_hostport_poll(&s->host, feed_host, s);
    if (what & KELP_HOSTPORT_DISCONNECTED) kelp_app_event(app, "host disconnected");
    if (what & KELP_HOSTPORT_CONNECTED) kelp_app_event(app, "host connected on TCP port %u", s->tcp_port);
}

/* ------------------------------------------------------------------ the channel */
static void channel_tx(const kelp_modemsim_pkt *p, void *u)
{
    msim_app *s = u;
    size_t len;
    if (kelp_modemsim_pkt_encode(p, s->enc, sizeof s->enc, &len) != KELP_OK) {
        kelp_app_run_warning(s->app, "cannot encode a channel packet");
        return;
    }
    int rc = s->chan ? kelp_bus_notify_binary(kelp_lcmbus_bus(s->chan), s->channel_var, s->enc, len,
                                              kelp_app_time(s->app))
                     : kelp_app_notify_binary(s->app, s->channel_var, s->enc, len);
    if (rc < 0) kelp_app_run_warning(s->app, "channel publish failed");
    else s->pkts_out++;
}

static void channel_rx(msim_app *s, const kelp_var *v)
{
    if (v->flags & KELP_VAR_FLAG_SYNC) { /* a retained old transmission, not one on the water now */
        s->pkts_sync_ignored++;
        return;
    }
    if (v->kind != KELP_VAR_BINARY ||
        kelp_modemsim_pkt_decode((const uint8_t *)v->sval, v->slen, &s->rxpkt) != KELP_OK) {
        s->pkts_bad++;
        kelp_app_run_warning(s->app, "malformed %s from %s: ignored", s->channel_var, v->source);
        return;
    }
    kelp_time now = kelp_app_time(s->app);
    if (s->rxpkt.instance != s->m.cfg.instance) s->pkts_in++;
    if (kelp_modemsim_hear(&s->m, &s->rxpkt, now) < 0) kelp_app_run_warning(s->app, "too many packets in flight");
    kelp_modemsim_tick(&s->m, now);
}

static void on_chan_var(const kelp_var *v, void *user)
{
    msim_app *s = user;
    if (strcmp(v->name, s->channel_var) == 0) channel_rx(s, v);
}

static void on_chan_fd(kelp_app *app, void *st, int fd)
{
    msim_app *s = st;
    (void)fd;
    if (kelp_lcmbus_handle(s->chan, 0, kelp_app_time(app)) < 0) kelp_app_run_warning(app, "channel receive error");
}

/* ------------------------------------------------------------------ events */
static void on_event(const kelp_modemsim_event *e, void *u)
{
    msim_app *s = u;
    char text[256];
    if (e->kind == KELP_MODEMSIM_EV_HOST_ERROR) {
        kelp_app_run_warning(s->app, "bad host line ($CAERR sent): %.120s", e->text);
    } else if (e->kind == KELP_MODEMSIM_EV_INFO) {
        kelp_app_event(s->app, "%s", e->text);
    } else if (kelp_modemsim_event_format(&s->m, e, text, sizeof text) > 0) { /* tx, rx, lost */
        kelp_app_event(s->app, "%s", text);
        if (s->publish_events) KELP_IGNORE(kelp_app_notify_string(s->app, "ACOMMS_SIM_EVENT", text));
    }
}

static int startup(kelp_app *app, void *st)
{
    msim_app *s = st;
    s->app = app;
    kelp_modemsim_cfg c;
    kelp_modemsim_cfg_default(&c);
    int rc;
    if (msim_config(app, s, &c) < 0) return -1;
    c.instance = msim_instance();
    kelp_modemsim_ops ops = { host_write, channel_tx, on_event };
    kelp_time now = kelp_app_time(app);
    if ((rc = kelp_modemsim_init(&s->m, &c, &ops, s, now)) < 0)
        return kelp_app_config_error(app, NULL, "bad modem configuration: %s", kelp_err_str(rc));
    /* the host link */
    kelp_diag err = {0};
    if (s->tcp_port) {
        if (kelp_hostport_open_tcp(&s->host, s->tcp_port, &err) < 0)
            return kelp_app_config_error(app, NULL, "cannot listen on TCP port %u: %s", s->tcp_port, kelp_diag_text(&err));
        printf("%s: modem %d listening on TCP port %u\n", kelp_app_name(app), s->modem_id, s->tcp_port);
    } else {
        if (kelp_hostport_open_pty(&s->host, s->pty_link, &err) < 0)
            return kelp_app_config_error(app, NULL, "cannot create the pseudo-terminal: %s", kelp_diag_text(&err));
        printf("%s: modem %d on %s%s%s\n", kelp_app_name(app), s->modem_id, s->host.pty_name, s->pty_link[0] ? " link " : "",
               s->pty_link);
    }
    if (kelp_app_watch_fd(app, kelp_hostport_fd(&s->host), on_host) < 0) return -1;
    fflush(stdout);
    /* the channel: the community bus, or a bus of its own shared by several communities */
    if (s->channel_url[0]) {
        char url[512];
        /* not kelp_lcmbus_url (it prefers $KELP_LCM_URL): the channel URL is explicit */
        if (strncmp(s->channel_url, "udpm://", 7) == 0 && !strstr(s->channel_url, "recv_buf_size"))
            snprintf(url, sizeof url, "%s%crecv_buf_size=%d", s->channel_url, strchr(s->channel_url, '?') ? '&' : '?',
                     KELP_LCM_RECV_BUF);
        else
            snprintf(url, sizeof url, "%s", s->channel_url);
        s->chan = kelp_lcmbus_open(url, kelp_app_name(app), "acomms_channel", on_chan_var, s, &err);
        if (!s->chan) return kelp_app_config_error(app, kelp_app_param(app, "channel_url"), "channel: %s", kelp_diag_text(&err));
        if (kelp_bus_register(kelp_lcmbus_bus(s->chan), s->channel_var, 0, kelp_app_time(app)) < 0) return -1;
        if (kelp_app_watch_fd(app, kelp_lcmbus_fd(s->chan), on_chan_fd) < 0) return -1;
    } else if (kelp_app_register(app, s->channel_var, 0) < 0) {
        return -1;
    }
    if (s->node_report_var[0] && kelp_app_register(app, s->node_report_var, 0) < 0) return -1;
    if (s->nav_vars && (kelp_app_register(app, "NAV_X", 0) < 0 || kelp_app_register(app, "NAV_Y", 0) < 0 ||
                        kelp_app_register(app, "NAV_DEPTH", 0) < 0))
        return -1;
    kelp_modemsim_boot(&s->m, now);
    kelp_app_event(app, "modem %d at x=%.1f y=%.1f depth=%.1f, loss %.2f, channel %s%s%s", s->modem_id, c.x, c.y,
                   c.depth, c.loss_probability, s->channel_var, s->channel_url[0] ? " on " : "", s->channel_url);
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    msim_app *s = st;
    (void)app;
    if (!s->chan && strcmp(v->name, s->channel_var) == 0) {
        channel_rx(s, v);
    } else if (s->node_report_var[0] && strcmp(v->name, s->node_report_var) == 0 && v->kind == KELP_VAR_STRING) {
        static kelp_nodereport nr;
        if (kelp_nodereport_parse(v->sval, v->slen, &nr, NULL) == 0 && (nr.fields & KELP_NR_X) &&
            (nr.fields & KELP_NR_Y)) {
            s->nav_x = nr.x;
            s->nav_y = nr.y;
            if (nr.fields & KELP_NR_DEPTH) s->nav_depth = nr.depth;
            kelp_modemsim_set_position(&s->m, s->nav_x, s->nav_y, s->nav_depth);
        } else {
            kelp_app_run_warning(app, "%s without X= and Y=: position unchanged", v->name);
        }
    } else if (s->nav_vars && v->kind == KELP_VAR_DOUBLE) {
        if (!strcmp(v->name, "NAV_X")) s->nav_x = v->dval;
        else if (!strcmp(v->name, "NAV_Y")) s->nav_y = v->dval;
        else if (!strcmp(v->name, "NAV_DEPTH")) s->nav_depth = v->dval;
        kelp_modemsim_set_position(&s->m, s->nav_x, s->nav_y, s->nav_depth);
    }
}

static int iterate(kelp_app *app, void *st, double now)
{
    msim_app *s = st;
    kelp_modemsim_tick(&s->m, now);
    if (now - s->last_status >= 2.0) {
        const kelp_modemsim_counters *c = kelp_modemsim_get_counters(&s->m);
        KELP_IGNORE(kelp_app_notify_stringf(app, "MODEMSIM_STATUS",
                                      "modem=%d,port=%s,host_lines=%u,host_errors=%u,tx_data=%u,rx_frames=%u,"
                                      "acks=%u,lost_random=%u,lost_collision=%u,lost_half_duplex=%u",
                                      kelp_modemsim_src(&s->m), s->tcp_port ? "tcp" : s->host.pty_name, c->host_lines,
                                      c->host_errors, c->tx[KELP_MODEMSIM_PKT_DATA], c->frames_rx, c->acks_out,
                                      c->lost_random, c->lost_collision, c->lost_half_duplex));
        s->last_status = now;
    }
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    msim_app *s = st;
    (void)app;
    const kelp_modemsim_counters *c = kelp_modemsim_get_counters(&s->m);
    if (s->tcp_port)
        fprintf(out, "modem %d (SRC %d) on TCP port %u, host %s\n", s->modem_id, kelp_modemsim_src(&s->m), s->tcp_port,
                s->host.cfd >= 0 ? "connected" : "not connected");
    else
        fprintf(out, "modem %d (SRC %d) on %s%s%s\n", s->modem_id, kelp_modemsim_src(&s->m), s->host.pty_name,
                s->pty_link[0] ? " <- " : "", s->pty_link);
    fprintf(out, "position x=%.1f y=%.1f depth=%.1f\n", s->m.x, s->m.y, s->m.depth);
    fprintf(out, "host: %u lines in, %u out, %u errors; bytes in %lu out %lu dropped %lu\n", c->host_lines,
            c->host_out, c->host_errors, s->host.bytes_in, s->host.bytes_out, s->host.dropped_out);
    fprintf(out, "sent: cycle_init %u data %u (%u frames) ack %u ping %u reply %u mini %u\n", c->tx[1], c->tx[2],
            c->frames_tx, c->tx[3], c->tx[4], c->tx[5], c->tx[6]);
    fprintf(out, "heard: cycle_init %u data %u (%u frames) ack %u ping %u reply %u mini %u; acks to host %u\n",
            c->rx[1], c->rx[2], c->frames_rx, c->rx[3], c->rx[4], c->rx[5], c->rx[6], c->acks_out);
    fprintf(out, "lost: random %u collision %u half_duplex %u stale %u; out of range %u; overflow %u\n",
            c->lost_random, c->lost_collision, c->lost_half_duplex, c->lost_stale, c->out_of_range, c->overflow);
    fprintf(out, "channel %s: %lu packets out, %lu in, %lu malformed, %lu retained replays ignored\n", s->channel_var,
            s->pkts_out, s->pkts_in, s->pkts_bad, s->pkts_sync_ignored);
}

static void shutdown_app(kelp_app *app, void *st)
{
    msim_app *s = st;
    (void)app;
    kelp_hostport_close(&s->host);
    if (s->chan) kelp_lcmbus_close(s->chan);
}

static const kelp_app_def def = {
    .name = "kelp-modemsim",
    .purpose = "Simulated WHOI Micro-Modem (iModemSim): the modem side of the Micro-Modem NMEA protocol on a "
               "pseudo-terminal or TCP port; modems share a simulated acoustic channel over the bus.",
    .params = (const kelp_app_param_info[]){
        { "modem_id", "1", "initial NVRAM SRC, 1..31 (the host sets it with $CCCFG,SRC); default 1", NULL },
        { "pty_link", "/tmp/ttyMM1", "symlink to the pseudo-terminal the host opens", NULL },
        { "Port", "/tmp/ttyMM1", "iModemSim's name for pty_link", "pty_link" },
        { "Speed", "19200", "iModemSim's baud: accepted, ignored (a pty has none)", NULL },
        { "tcp_port", "50010", "serve the host on this TCP port instead of a pty", "pty_link" },
        { "position", "x=0,y=0,depth=0", "fixed position, m", NULL },
        { "x", "0", "m (also ConstantPosX)", NULL },
        { "y", "0", "m (also ConstantPosY)", NULL },
        { "depth", "0", "m (also ConstantDepth)", NULL },
        { "ConstantPosX", "0", "iModemSim's x", NULL },
        { "ConstantPosY", "0", "iModemSim's y", NULL },
        { "ConstantDepth", "0", "iModemSim's depth", NULL },
        { "InputLocType", "Constant", "iModemSim's: accepted, ignored", NULL },
        { "node_report_var", "NODE_REPORT_LOCAL", "follow the vehicle: X=, Y=, DEP= of this variable (optional)", NULL },
        { "nav_vars", "false", "true: follow NAV_X, NAV_Y, NAV_DEPTH", NULL },
        { "sound_speed", "1500", "m/s", NULL },
        { "loss", "0", "probability of losing a packet or data frame, 0..1 (seeded)", NULL },
        { "loss_probability", "0", "same as loss", NULL },
        { "seed", "1", "random seed of the channel", NULL },
        { "max_range", "0", "m, 0 = unlimited", NULL },
        { "ci_seconds", "1.0", "cycle-init packet length, s", NULL },
        { "mini_seconds", "0.5", "ack, ping and mini-packet length, s", NULL },
        { "turnaround_seconds", "0.25", "s", NULL },
        { "drq_timeout", "2", "s to wait for $CCTXD after $CADRQ", NULL },
        { "ping_timeout", "10", "s to wait for a ping reply", NULL },
        { "rev_interval", "60", "$CAREV heartbeat period while a host talks, s (0 = off)", NULL },
        { "clock_set_at_boot", "false", "true: the modem clock starts set", NULL },
        { "revision", "0.93.0.52", "firmware revision in $CAREV", NULL },
        { "lbl_beacon", "x=1000,y=0,depth=50", "repeatable (up to 4): REMUS LBL transponders A..D for $CCPDT", NULL },
        { "channel_var", "ACOMMS_SIM_CHANNEL", "where transmissions travel", NULL },
        { "channel_url", "udpm://239.255.76.67:7690?ttl=0", "a channel bus shared by communities (optional)", NULL },
        { "IPPort", "49234", "iModemSim's channel port: channel_url udpm://239.255.76.67:<IPPort> (unless channel_url)",
          "channel_url" },
        { "BroadcastAddr", "127.0.0.1", "iModemSim's: a 127.x address keeps the IPPort channel on this host (ttl=0)",
          NULL },
        { "publish_events", "true", "ACOMMS_SIM_EVENT per transmission, reception and loss", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "ACOMMS_SIM_CHANNEL", "(binary channel packet)", "<channel_var>; or on channel_url" },
        { "NODE_REPORT_LOCAL", "NAME=alpha,X=10,Y=-20,DEP=5", "<node_report_var>, when set" },
        { "NAV_X", "10", "with nav_vars = true" },
        { "NAV_Y", "-20", "with nav_vars = true" },
        { "NAV_DEPTH", "5", "with nav_vars = true" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "ACOMMS_SIM_CHANNEL", "(binary channel packet)", "<channel_var>: each transmission" },
        { "ACOMMS_SIM_EVENT", "event=tx,src=1,dest=2,rate=0,time=12.5", "with publish_events = true" },
        { "MODEMSIM_STATUS", "modem=1,port=/dev/pts/3,host_lines=12,host_errors=0,tx_data=3,rx_frames=2,acks=1,"
          "lost_random=0,lost_collision=0,lost_half_duplex=0", "every 2 s" },
        { NULL, NULL, NULL } },
    .notes = "Host link: a pseudo-terminal (pty_link) or TCP (tcp_port) speaking WHOI Micro-Modem NMEA:\n"
             "  in  $CCCLK $CCCFG $CCCFQ $CCCYC $CCTXD $CCMPC $CCMUC $CCPDT\n"
             "  out $CACLK $CACFG $CACYC $CADRQ $CATXD $CATXP $CATXF $CARXD $CAACK $CAMPC $CAMPA $CAMPR\n"
             "      $CAMUC $CAMUA $SNPDT $SNTTA $CAREV $CAERR\n"
             "Run it as iModemSim with: Run = kelp-modemsim ~ iModemSim\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown_app,
};

int main(int argc, char **argv)
{
    static msim_app s;
    return kelp_app_run(argc, argv, &def, &s);
}
