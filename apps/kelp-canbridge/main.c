/* kelp-canbridge: join a community and a SocketCAN interface, forward named variables each way.
 *
 * ProcessConfig = kelp-canbridge
 *   CAN_INTERFACE = can0                         SocketCAN interface (vcan0 for tests)
 *   NODE_ID       = 1                            this bridge's CAN node id, 1-127
 *   CAN_FD        = false                        send CAN FD (64-byte) frames
 *   DICTIONARY    = 3=THRUST_CMD, 7=DEPTH        (repeatable) variable ids, the same on every node
 *   TO_CAN        = DESIRED_THRUST -> THRUST_CMD (repeatable) community -> CAN, optional renaming
 *   FROM_CAN      = [DEPTH] -> [NAV_DEPTH_FW]    (repeatable) CAN -> community, optional renaming
 *   REASSEMBLY_TIMEOUT = 1.0                     seconds a partial message may wait
 *   SEND_TIME = false, SEND_SOURCE = false       carry the variable's time / source on CAN
 * The socket is CAN_RAW with kernel filters for the FROM_CAN variables; it is reopened when
 * the interface goes down and comes back. Wire format: docs/CAN.md. */
#include <stdio.h>
#include <string.h>
#include <kelp/edge/app.h>
#include <kelp/can.h>
#include <kelp/edge/can.h>
#include <kelp/canbridge.h>

typedef struct canbr {
    kelp_canbridge b;
    kelp_can_port port;
    kelp_var out;
    double last_status;
    unsigned long published, pub_err, send_err;
    char status[512];
} canbr;

static int emit(void *user, const kelp_can_frame *f)
{
    return kelp_can_port_write(user, f);
}

static void on_can(kelp_app *app, void *st, int fd)
{
    canbr *c = st;
    (void)fd;
    kelp_can_frame f;
    int rc;
    while ((rc = kelp_can_port_read(&c->port, &f)) == 1) {
        double now = kelp_app_time(app);
        int got = kelp_canbridge_from_can(&c->b, &f, now, &c->out);
        if (got != 1) continue;
        memcpy(c->out.community, kelp_app_community(app), strlen(kelp_app_community(app)) + 1);
        if (kelp_bus_forward(kelp_app_bus(app), &c->out) < 0) {
            c->pub_err++;
            kelp_app_run_warning(app, "cannot publish %s", c->out.name);
        } else {
            c->published++;
        }
    }
    if (rc < 0) kelp_app_run_warning(app, "%s (will reopen when it is up)", kelp_diag_text(&c->port.diag));
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    canbr *c = st;
    if (strcmp(v->community, kelp_app_community(app)) != 0) return;
    int rc = kelp_canbridge_from_bus(&c->b, v, emit, &c->port);
    if (rc < 0) {
        c->send_err++;
        if (rc == KELP_ERR_RANGE) kelp_app_run_warning(app, "%s is too large for CAN: not sent", v->name);
        else if (rc == KELP_ERR_IO) kelp_app_run_warning(app, "%s", kelp_diag_text(&c->port.diag));
    }
}

static int add_lists(kelp_app *app, canbr *c, const char *key, bool to_can)
{
    for (const kelp_mission_node *n = kelp_app_param_next(app, key, NULL); n; n = kelp_app_param_next(app, key, n)) {
        char line[1024];
        kelp_diag why;
        kelp_diag_clear(&why);
        if (kelp_mission_copy(n, line, sizeof line) < 0) (void)kelp_fail(&why, KELP_ERR_NOSPACE, "too long");
        if (why.code || kelp_canbridge_add(&c->b, to_can, line, &why) < 0)
            return kelp_app_config_error(app, n, "bad %s: %s", key, kelp_diag_text(&why));
    }
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    canbr *c = st;
    double node = 1, timeout = KELP_CAN_TIMEOUT_DEFAULT;
    bool fd = false, stime = false, ssrc = false;
    char ifname[32] = "can0";
    const kelp_mission_node *pn = kelp_app_param(app, "NODE_ID");
    if (pn && (kelp_mission_double(pn, &node) < 0 || node < 1 || node > KELP_CAN_MAX_NODE || node != (int)node))
        return kelp_app_config_error(app, pn, "NODE_ID must be 1-127");
    const kelp_mission_node *tn = kelp_app_param(app, "REASSEMBLY_TIMEOUT");
    if (tn && (kelp_mission_double(tn, &timeout) < 0 || !(timeout > 0 && timeout <= 60)))
        return kelp_app_config_error(app, tn, "REASSEMBLY_TIMEOUT must be a number of seconds, 0-60");
    if (kelp_app_param_bool(app, "CAN_FD", &fd) < 0 || kelp_app_param_bool(app, "SEND_TIME", &stime) < 0 ||
        kelp_app_param_bool(app, "SEND_SOURCE", &ssrc) < 0)
        return kelp_app_config_error(app, NULL, "CAN_FD, SEND_TIME and SEND_SOURCE are true or false");
    if (kelp_app_param_str(app, "CAN_INTERFACE", ifname, sizeof ifname) < 0)
        return kelp_app_config_error(app, kelp_app_param(app, "CAN_INTERFACE"), "interface name too long");
    if (kelp_canbridge_init(&c->b, (unsigned)node, fd, timeout) < 0) return KELP_ERR_ARG;
    c->b.send_time = stime;
    c->b.send_source = ssrc;
    for (const kelp_mission_node *n = kelp_app_param_next(app, "DICTIONARY", NULL); n;
         n = kelp_app_param_next(app, "DICTIONARY", n)) {
        char line[1024];
        kelp_diag why;
        kelp_diag_clear(&why);
        if (kelp_mission_copy(n, line, sizeof line) < 0) (void)kelp_fail(&why, KELP_ERR_NOSPACE, "too long");
        if (why.code || kelp_can_dict_parse(&c->b.dict, line, &why) < 0)
            return kelp_app_config_error(app, n, "bad DICTIONARY: %s", kelp_diag_text(&why));
    }
    if (add_lists(app, c, "TO_CAN", true) < 0 || add_lists(app, c, "FROM_CAN", false) < 0) return KELP_ERR_PARSE;
    kelp_can_filter f[KELP_CAN_MAX_FILTERS];
    size_t nf = kelp_canbridge_filters(&c->b, f, KELP_CAN_MAX_FILTERS);
    if (kelp_can_port_open(&c->port, &kelp_can_socketcan_ops, ifname, f, nf, fd) < 0) {
        if (c->port.fd < 0) return kelp_app_config_error(app, NULL, "%s", kelp_diag_text(&c->port.diag));
        kelp_app_run_warning(app, "%s: will open it when %s is up", kelp_diag_text(&c->port.diag), ifname);
    }
    if (kelp_app_watch_fd(app, c->port.fd, on_can) < 0) return KELP_ERR_NOSPACE;
    for (size_t i = 0; i < c->b.nto; i++) {
        bool seen = false;
        for (size_t j = 0; j < i; j++) seen = seen || strcmp(c->b.to_src[i], c->b.to_src[j]) == 0;
        if (!seen && kelp_app_register(app, c->b.to_src[i], 0) < 0)
            kelp_app_run_warning(app, "cannot register %s", c->b.to_src[i]);
    }
    kelp_app_event(app, "CAN %s node %u %s: %zu to CAN, %zu from CAN, %zu dictionary entries, %zu kernel filters",
                   ifname, (unsigned)node, fd ? "FD" : "classic", c->b.nto, c->b.nfrom, c->b.dict.n, nf);
    return 0;
}

static int iterate(kelp_app *app, void *st, double now)
{
    canbr *c = st;
    int rc = kelp_can_port_maintain(&c->port);
    if (rc == 1) kelp_app_event(app, "%s is up: opened", c->port.ifname);
    if (rc < 0) kelp_app_run_warning(app, "%s", kelp_diag_text(&c->port.diag));
    kelp_can_rx_expire(&c->b.rx, now);
    if (now - c->last_status >= 1.0) {
        const kelp_can_stats *s = &c->b.rx.st;
        char buf[sizeof c->status];
        (void)snprintf(buf, sizeof buf,
                       "up=%s,tx_msgs=%lu,tx_frames=%lu,rx_frames=%lu,rx_msgs=%lu,published=%lu,bad_frame=%lu,"
                       "out_of_order=%lu,timed_out=%lu,slot_full=%lu,bad_crc=%lu,bad_body=%lu,unknown_var=%lu,"
                       "duplicate=%lu,reopened=%lu",
                       c->port.down ? "false" : "true", c->b.to_msgs, c->b.to_frames, s->frames, s->messages,
                       c->published, s->bad_frame, s->out_of_order, s->timed_out, s->slot_full, s->bad_crc,
                       s->bad_body, s->unknown_var, s->duplicate, c->port.reopened);
        if (strcmp(buf, c->status) != 0) {
            memcpy(c->status, buf, sizeof buf);
            KELP_IGNORE(kelp_app_notify_string(app, "CANBRIDGE_STATUS", buf));
        }
        c->last_status = now;
    }
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    canbr *c = st;
    (void)app;
    fprintf(out, "CAN %s %s  node %u  %s\n", c->port.ifname, c->port.down ? "DOWN" : "up", c->b.tx.node,
            c->b.tx.fd ? "FD" : "classic");
    fprintf(out, "%s\n", c->status);
    fprintf(out, "port: rx %lu tx %lu queue full %lu errors %lu skipped %lu  went down %lu reopened %lu  "
                 "publish errors %lu send errors %lu\n",
            c->port.rx, c->port.tx, c->port.tx_full, c->port.tx_err, c->port.rx_other, c->port.went_down,
            c->port.reopened, c->pub_err, c->send_err);
    for (size_t i = 0; i < c->b.nto; i++)
        fprintf(out, "  to CAN   %-24s as %s\n", c->b.to_src[i], c->b.to_alias[i][0] ? c->b.to_alias[i] : c->b.to_src[i]);
    for (size_t i = 0; i < c->b.nfrom; i++)
        fprintf(out, "  from CAN %-24s as %s\n", c->b.from_src[i],
                c->b.from_alias[i][0] ? c->b.from_alias[i] : c->b.from_src[i]);
}

static void shutdown_cb(kelp_app *app, void *st)
{
    (void)app;
    kelp_can_port_close(&((canbr *)st)->port);
}

static const kelp_app_def def = {
    .name = "kelp-canbridge",
    .purpose = "Forward variables between a community and a SocketCAN bus (classic or FD), with renaming.",
    .params = (const kelp_app_param_info[]){
        { "CAN_INTERFACE", "can0", "SocketCAN interface (default can0)", NULL },
        { "NODE_ID", "1", "this bridge's node id on CAN, 1-127 (default 1)", NULL },
        { "CAN_FD", "false", "send CAN FD frames (64 bytes) rather than classic (8)", NULL },
        { "DICTIONARY", "3=THRUST_CMD, 7=DEPTH", "repeatable: id=NAME pairs, ids 0-510, the same on every node", NULL },
        { "TO_CAN", "DESIRED_THRUST -> THRUST_CMD", "repeatable: VAR, VAR -> ALIAS or [V1,V2] -> [A1,A2]", NULL },
        { "FROM_CAN", "[DEPTH] -> [NAV_DEPTH_FW]", "repeatable: names on CAN (globs allowed) -> community names", NULL },
        { "REASSEMBLY_TIMEOUT", "1.0", "seconds a partly received message may wait (default 1)", NULL },
        { "SEND_TIME", "false", "carry each variable's time on CAN (8 bytes more)", NULL },
        { "SEND_SOURCE", "false", "carry each variable's source on CAN", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "<TO_CAN variable>", "any value", "every source variable of TO_CAN" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "<FROM_CAN alias>", "any value", "every variable received from CAN, under its alias" },
        { "CANBRIDGE_STATUS", "up=true,tx_msgs=4,rx_msgs=9,bad_frame=0,timed_out=1,...", "counters, when they change" },
        { NULL, NULL, NULL } },
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown_cb,
};

int main(int argc, char **argv)
{
    static canbr c;
    return kelp_app_run(argc, argv, &def, &c);
}
