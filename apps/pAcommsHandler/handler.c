/* pAcommsHandler: the Goby 1.1 acoustic communications handler over kelp.
 *
 * DCCL (encode on trigger/time, decode and publish on receipt) + priority queues + TDMA MAC +
 * WHOI Micro-Modem driver on a serial port (libserialport, termios fallback for ptys) or TCP.
 * DRIVER_NONE runs an ideal in-process channel (see kelp_acomms_node_cfg.loopback_channel). */
#include <libgen.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/app.h>
#include <kelp/lcmbus.h>
#include <kelp/link.h>

#include "handler.h"

#define NMEA_KEEP 6
#define MAX_RAW_PUBLISH 35000 /* Goby publishes raw NMEA only below this length */

typedef struct hq_name {
    kelp_queue_key key;
    const char *name;
    const char *in_var;   /* DCCL: IN_ hex var; CCL: in_pubsub_var */
    const char *out_var;  /* DCCL: OUT_ hex var; CCL: out_pubsub_var */
    long dccl_index;      /* -1 for CCL */
} hq_name;

struct handler {
    kelp_acomms_config cfg;
    kelp_acomms_dccl *dccl;
    kelp_acomms_node node;
    kelp_queue queues[KELP_ACOMMS_MAX_QUEUES];
    kelp_queue_entry *pool;
    hq_name names[KELP_ACOMMS_MAX_QUEUES];
    size_t nnames;
    kelp_link *link;
    kelp_acomms_lcm *lcm;
    kelp_app *app;
    double now;
    bool started;
    bool link_up;
    bool driver_dead;
    bool started_on_link; /* the driver's first start-up went out on an open link */
    bool seen_link;
    double next_status;
    /* counters */
    unsigned long encoded, encode_errors, decoded, decode_errors, pushed, push_errors, in_data, out_data, acks,
        expires, ranges, nmea_in, nmea_out, bad_lines, retries, give_ups, modem_errors, reconnects, deaths, ccl_in,
        ccl_out, bad_mail, write_errors;
    char last_in[NMEA_KEEP][96];
    char last_out[NMEA_KEEP][96];
    unsigned n_in, n_out;
    char text[KELP_ACOMMS_MAX_PRINT];
    char decoded_text[1024];
};

static int64_t us_of(double t)
{
    return (int64_t)llround(t * 1e6);
}

static const hq_name *name_of(const handler *h, kelp_queue_key key)
{
    for (size_t i = 0; i < h->nnames; i++)
        if (h->names[i].key.type == key.type && h->names[i].key.id == key.id) return &h->names[i];
    return NULL;
}

static void keep_line(char (*ring)[96], unsigned *n, const char *raw)
{
    snprintf(ring[*n % NMEA_KEEP], sizeof ring[0], "%s", raw);
    (*n)++;
}

/* ------------------------------------------------------------------ publishing */

static void pub_text(handler *h, const char *var)
{
    if (kelp_app_notify_string(h->app, var, h->text) < 0) kelp_app_run_warning(h->app, "cannot publish %s", var);
}

static void lcm_check(handler *h, int rc, const char *what)
{
    if (rc) kelp_app_run_warning(h->app, "LCM publish of %s failed", what);
}

static void on_publication(const char *var, bool is_double, double dval, const char *sval, void *user)
{
    handler *h = user;
    int rc = is_double ? kelp_app_notify_double(h->app, var, dval) : kelp_app_notify_string(h->app, var, sval);
    if (rc < 0) kelp_app_run_warning(h->app, "cannot publish %s", var);
}

/* a DCCL message for us: ACOMMS_INCOMING_DATA, its IN_ hex var, decode + <publish> */
static void incoming_dccl(handler *h, const kelp_acomms_msg *m)
{
    const hq_name *nm = name_of(h, m->key);
    h->in_data++;
    h->decoded_text[0] = '\0';
    if (h->dccl && kelp_acomms_dccl_describe(h->dccl, m->data, m->len, h->now, h->decoded_text,
                                             sizeof h->decoded_text) != KELP_OK) {
        /* the text says why; decode below reports the error */
    }
    if (kelp_acomms_print_data(m, h->text, sizeof h->text, NULL) == KELP_OK) {
        pub_text(h, "ACOMMS_INCOMING_DATA");
        if (nm && nm->in_var) pub_text(h, nm->in_var);
    }
    if (h->lcm)
        lcm_check(h, kelp_acomms_lcm_data(h->lcm, "ACOMMS_INCOMING_DATA_LCM", h->now, m, nm ? nm->name : NULL,
                                          h->decoded_text),
                  "ACOMMS_INCOMING_DATA_LCM");
    if (!h->dccl) return;
    const char *why = NULL;
    int rc = kelp_acomms_dccl_decode(h->dccl, m->data, m->len, h->now, on_publication, h, &why);
    if (rc == KELP_ERR_STATE) return; /* NO_DECODE */
    if (rc) {
        h->decode_errors++;
        kelp_app_run_warning(h->app, "cannot decode a received DCCL message: %s", why ? why : kelp_strerror(rc));
        return;
    }
    h->decoded++;
}

static void incoming_ccl(handler *h, const kelp_acomms_msg *m)
{
    const hq_name *nm = name_of(h, m->key);
    h->in_data++;
    h->ccl_in++;
    if (kelp_acomms_print_data(m, h->text, sizeof h->text, NULL) == KELP_OK) {
        pub_text(h, "ACOMMS_INCOMING_DATA");
        if (nm && nm->in_var && nm->in_var[0]) pub_text(h, nm->in_var);
    }
    if (h->lcm)
        lcm_check(h, kelp_acomms_lcm_data(h->lcm, "ACOMMS_INCOMING_DATA_LCM", h->now, m, nm ? nm->name : NULL, NULL),
                  "ACOMMS_INCOMING_DATA_LCM");
}

static void on_queue_event(handler *h, const kelp_queue_event *q)
{
    const hq_name *nm = name_of(h, q->key);
    switch (q->kind) {
    case KELP_QUEUE_EV_RECEIVE: incoming_dccl(h, q->msg); break;
    case KELP_QUEUE_EV_RECEIVE_CCL: incoming_ccl(h, q->msg); break;
    case KELP_QUEUE_EV_ACK:
        h->acks++;
        /* the acknowledging modem is the message's destination; the ack is addressed to us */
        if (kelp_acomms_print_ack(q->msg->dest, h->cfg.modem_id, q->frame, us_of(h->now), q->msg, h->text,
                                  sizeof h->text, NULL) == KELP_OK)
            pub_text(h, "ACOMMS_ACK");
        if (h->lcm)
            lcm_check(h, kelp_acomms_lcm_ack(h->lcm, "ACOMMS_ACK_LCM", h->now, q->msg->dest, h->cfg.modem_id, q->frame,
                                             q->msg, nm ? nm->name : NULL),
                      "ACOMMS_ACK_LCM");
        kelp_app_event(h->app, "ack from %d for %s (frame %u)", q->msg->dest, nm ? nm->name : "?", (unsigned)q->frame);
        break;
    case KELP_QUEUE_EV_EXPIRE:
        h->expires++;
        if (kelp_acomms_print_expire(q->msg, h->text, sizeof h->text, NULL) == KELP_OK) pub_text(h, "ACOMMS_EXPIRE");
        if (h->lcm)
            lcm_check(h, kelp_acomms_lcm_expire(h->lcm, "ACOMMS_EXPIRE_LCM", h->now, q->msg, nm ? nm->name : NULL),
                      "ACOMMS_EXPIRE_LCM");
        kelp_app_event(h->app, "expired: a %s message for %d", nm ? nm->name : "?", q->msg->dest);
        break;
    case KELP_QUEUE_EV_QSIZE:
        if (kelp_acomms_print_qsize(q->key, q->size, h->text, sizeof h->text, NULL) == KELP_OK)
            pub_text(h, "ACOMMS_QSIZE");
        if (h->lcm)
            lcm_check(h, kelp_acomms_lcm_qsize(h->lcm, "ACOMMS_QSIZE_LCM", h->now, q->key, nm ? nm->name : NULL, q->size),
                      "ACOMMS_QSIZE_LCM");
        break;
    default: break;
    }
}

static void on_driver_event(handler *h, const kelp_mmdriver_event *e)
{
    switch (e->kind) {
    case KELP_MMDRIVER_EV_NMEA_IN:
        h->nmea_in++;
        if (e->raw && e->raw_len < MAX_RAW_PUBLISH) {
            (void)kelp_app_notify_string(h->app, "ACOMMS_NMEA_IN", e->raw);
            keep_line(h->last_in, &h->n_in, e->raw);
        }
        break;
    case KELP_MMDRIVER_EV_NMEA_OUT:
        h->nmea_out++;
        if (e->raw && e->raw_len < MAX_RAW_PUBLISH) {
            (void)kelp_app_notify_string(h->app, "ACOMMS_NMEA_OUT", e->raw);
            keep_line(h->last_out, &h->n_out, e->raw);
        }
        break;
    case KELP_MMDRIVER_EV_RANGE:
        h->ranges++;
        if (kelp_acomms_print_range(e->src, e->dest, e->time_us, e->ranging, e->tt, e->n_tt, h->text, sizeof h->text,
                                    NULL) == KELP_OK)
            pub_text(h, "ACOMMS_RANGE_RESPONSE");
        if (h->lcm)
            lcm_check(h, kelp_acomms_lcm_range(h->lcm, "ACOMMS_RANGE_RESPONSE_LCM", h->now, e->src, e->dest, e->ranging,
                                               e->tt, e->n_tt),
                      "ACOMMS_RANGE_RESPONSE_LCM");
        break;
    case KELP_MMDRIVER_EV_MODEM_ERROR:
        h->modem_errors++;
        kelp_app_run_warning(h->app, "modem error: %s", e->raw ? e->raw : "$CAERR");
        break;
    case KELP_MMDRIVER_EV_BAD_LINE:
        h->bad_lines++;
        kelp_app_run_warning(h->app, "bad line from the modem ignored (%s)", kelp_strerror(e->err));
        break;
    case KELP_MMDRIVER_EV_RETRY:
        h->retries++;
        kelp_app_event(h->app, "no answer from the modem: resending %.60s", e->raw ? e->raw : "");
        break;
    case KELP_MMDRIVER_EV_GIVE_UP:
        h->give_ups++;
        kelp_app_run_warning(h->app, "modem did not answer %.40s after 3 tries: command queue cleared",
                             e->raw ? e->raw : "");
        break;
    case KELP_MMDRIVER_EV_DEAD:
        h->deaths++;
        kelp_app_run_warning(h->app, "modem not responding: reconnecting the link");
        kelp_app_event(h->app, "modem not responding: reconnecting the link");
        break;
    case KELP_MMDRIVER_EV_CLOCK:
        kelp_app_event(h->app, "modem clock %s", e->clock_ok ? "set" : "needs setting");
        break;
    default: break;
    }
}

static void node_event(const kelp_acomms_event *ev, void *user)
{
    handler *h = user;
    switch (ev->kind) {
    case KELP_ACOMMS_EV_QUEUE: on_queue_event(h, ev->q); break;
    case KELP_ACOMMS_EV_DRIVER: on_driver_event(h, ev->mm); break;
    case KELP_ACOMMS_EV_SLOT:
        if (h->cfg.verbosity >= KELP_ACOMMS_VERBOSITY_DEBUG)
            kelp_app_event(h->app, "MAC slot %u: %s %d -> %d rate %u", ev->slot->slot_index,
                           ev->slot->kind == KELP_MAC_ACT_TRANSMIT ? "transmit" : "ranging", ev->slot->src,
                           ev->slot->dest, ev->slot->rate);
        break;
    default: break;
    }
}

static void node_write(const char *bytes, size_t len, void *user)
{
    handler *h = user;
    if (!h->link) return;
    int rc = kelp_link_write(h->link, bytes, len);
    if (rc) {
        h->write_errors++;
        kelp_app_run_warning(h->app, "modem link write failed: %s", kelp_link_error(h->link));
    }
}

/* ------------------------------------------------------------------ outgoing DCCL */

static int build_msg(handler *h, size_t idx, kelp_acomms_msg *m, double now, const char **why)
{
    kelp_acomms_dccl_info info;
    if (kelp_acomms_dccl_info_get(h->dccl, idx, &info) != KELP_OK) return KELP_ERR_ARG;
    memset(m, 0, sizeof *m);
    size_t len = 0;
    int rc = kelp_acomms_dccl_encode_vars(h->dccl, idx, now, m->data, sizeof m->data, &len, why);
    if (rc) return rc;
    kelp_queue_header hd;
    if (kelp_queue_header_read(m->data, len, &hd) != KELP_OK) {
        *why = "encoded message shorter than its header";
        return KELP_ERR_TRUNCATED;
    }
    m->len = len;
    m->src = h->cfg.modem_id;
    m->dest = (int)hd.dest;
    m->has_time = true;
    m->time_us = us_of(now);
    m->key.type = KELP_QUEUE_DCCL;
    m->key.id = info.id;
    return KELP_OK;
}

static void outgoing_dccl(handler *h, size_t idx)
{
    kelp_acomms_dccl_info info;
    kelp_acomms_msg m;
    const char *why = NULL;
    if (kelp_acomms_dccl_info_get(h->dccl, idx, &info) != KELP_OK) return;
    if (info.manip & KELP_ACOMMS_MANIP_ON_DEMAND) return; /* encoded at the data request */
    int rc = build_msg(h, idx, &m, h->now, &why);
    if (rc == KELP_ERR_PARTIAL) return; /* <repeat>: still collecting */
    if (rc) {
        h->encode_errors++;
        kelp_app_run_warning(h->app, "cannot encode %s: %s", info.name, why ? why : kelp_strerror(rc));
        return;
    }
    h->encoded++;
    h->out_data++;
    h->decoded_text[0] = '\0';
    if (kelp_acomms_dccl_describe(h->dccl, m.data, m.len, h->now, h->decoded_text, sizeof h->decoded_text) != KELP_OK) {
        /* shown as "(cannot decode ...)" */
    }
    if (kelp_acomms_print_data(&m, h->text, sizeof h->text, NULL) == KELP_OK) {
        pub_text(h, "ACOMMS_OUTGOING_DATA");
        if (info.out_var) pub_text(h, info.out_var);
    }
    if (h->lcm)
        lcm_check(h, kelp_acomms_lcm_data(h->lcm, "ACOMMS_OUTGOING_DATA_LCM", h->now, &m, info.name, h->decoded_text),
                  "ACOMMS_OUTGOING_DATA_LCM");
    rc = kelp_acomms_node_push(&h->node, &m, us_of(h->now));
    if (rc) {
        h->push_errors++;
        kelp_app_run_warning(h->app, "cannot queue %s: %s", info.name, kelp_strerror(rc));
    } else {
        h->pushed++;
    }
    /* LOOPBACK: "decode this message internally immediately following encode" (a message to
     * ourselves was already looped back by the queue) */
    if ((info.manip & KELP_ACOMMS_MANIP_LOOPBACK) && m.dest != h->cfg.modem_id) {
        const char *w2 = NULL;
        rc = kelp_acomms_dccl_decode(h->dccl, m.data, m.len, h->now, on_publication, h, &w2);
        if (rc == KELP_OK) h->decoded++;
        else if (rc != KELP_ERR_STATE) kelp_app_run_warning(h->app, "LOOPBACK decode of %s failed: %s", info.name, w2 ? w2 : "?");
    }
}

static void on_demand(kelp_queue_key key, const kelp_queue_request *req, kelp_acomms_msg *out, void *user)
{
    handler *h = user;
    (void)req;
    const char *why = NULL;
    out->len = 0;
    if (!h->dccl) return;
    long idx = kelp_acomms_dccl_find_id(h->dccl, key.id);
    if (idx < 0) return;
    int rc = build_msg(h, (size_t)idx, out, h->now, &why);
    if (rc) {
        out->len = 0;
        if (rc != KELP_ERR_PARTIAL) kelp_app_run_warning(h->app, "ON_DEMAND encode failed: %s", why ? why : "?");
        return;
    }
    h->encoded++;
}

/* ------------------------------------------------------------------ link */

static void on_link_readable(kelp_app *app, void *state, int fd)
{
    handler *h = state;
    (void)fd;
    (void)app;
    uint8_t buf[4096];
    for (int guard = 0; guard < 64; guard++) {
        size_t n = 0;
        int rc = kelp_link_read(h->link, buf, sizeof buf, &n);
        if (rc) {
            kelp_app_run_warning(h->app, "modem link lost: %s", kelp_link_error(h->link));
            kelp_app_event(h->app, "modem link lost: %s", kelp_link_error(h->link));
            h->link_up = false;
            kelp_acomms_node_set_link_up(&h->node, false);
            return;
        }
        if (n == 0) return;
        if (kelp_acomms_node_feed(&h->node, buf, n, us_of(kelp_app_time(h->app))) != KELP_OK)
            kelp_app_run_warning(h->app, "driver refused input");
    }
}

static int open_link(handler *h)
{
    kelp_acomms_config *c = &h->cfg;
    kelp_link_cfg lc;
    switch (c->connection) {
    case KELP_ACOMMS_CONN_TCP_AS_CLIENT:
        kelp_link_cfg_default(&lc, KELP_LINK_TCP_CLIENT);
        lc.host = c->tcp_server;
        lc.port = c->tcp_port;
        break;
    case KELP_ACOMMS_CONN_TCP_AS_SERVER:
        kelp_link_cfg_default(&lc, KELP_LINK_TCP_SERVER);
        lc.port = c->tcp_port;
        break;
    default:
        kelp_link_cfg_default(&lc, KELP_LINK_SERIAL);
        lc.device = c->serial_port;
        lc.baud = c->serial_baud;
        break;
    }
    char err[256];
    h->link = kelp_link_create(&lc, err, sizeof err);
    if (!h->link) return kelp_app_config_error(h->app, NULL, "modem link: %s", err);
    if (kelp_app_watch_fd(h->app, kelp_link_fd(h->link), on_link_readable) != KELP_OK)
        return kelp_app_config_error(h->app, NULL, "cannot watch the modem link");
    if (!kelp_link_connected(h->link) && !kelp_link_listening(h->link))
        kelp_app_run_warning(h->app, "modem link not up yet (%s): retrying", kelp_link_error(h->link));
    return KELP_OK;
}

/* ------------------------------------------------------------------ start-up */

static int add_queues(handler *h, int64_t now_us)
{
    size_t nm = kelp_acomms_dccl_count(h->dccl);
    for (size_t i = 0; i < nm; i++) {
        kelp_acomms_dccl_info info;
        if (kelp_acomms_dccl_info_get(h->dccl, i, &info) != KELP_OK) continue;
        kelp_queue_cfg q;
        /* loopback stays off: LOOPBACK is done here, right after the encode (whatever the dest) */
        kelp_acomms_queue_cfg_from_info(&info, &q);
        int rc = kelp_acomms_node_add_queue(&h->node, &q, now_us);
        if (rc)
            return kelp_app_config_error(h->app, NULL, "cannot add the queue of DCCL message %s (id %u): %s", info.name,
                                         info.id, h->node.errmsg ? h->node.errmsg : kelp_strerror(rc));
        hq_name *n = &h->names[h->nnames++];
        n->key = q.key;
        n->name = info.name;
        n->in_var = info.in_var;
        n->out_var = info.out_var;
        n->dccl_index = (long)i;
    }
    for (size_t i = 0; i < h->cfg.nccl; i++) {
        kelp_acomms_ccl_queue *cq = &h->cfg.ccl[i];
        cq->cfg.name = cq->name;
        int rc = kelp_acomms_node_add_queue(&h->node, &cq->cfg, now_us);
        if (rc)
            return kelp_app_config_error(h->app, NULL, "cannot add CCL queue %s: %s", cq->name,
                                         h->node.errmsg ? h->node.errmsg : kelp_strerror(rc));
        hq_name *n = &h->names[h->nnames++];
        n->key = cq->cfg.key;
        n->name = cq->name;
        n->in_var = cq->in_var;
        n->out_var = cq->out_var;
        n->dccl_index = -1;
    }
    return KELP_OK;
}

static void publish_initializers(handler *h)
{
    for (size_t i = 0; i < h->cfg.n_init; i++) {
        const kelp_acomms_initializer *in = &h->cfg.init[i];
        char sval[KELP_ACOMMS_MAX_TEXT];
        double d = in->dval;
        bool have = in->is_double ? in->has_dval : in->has_sval;
        snprintf(sval, sizeof sval, "%s", in->sval);
        if (in->global_cfg_var[0]) {
            if (in->is_double) {
                have = kelp_app_global_double(h->app, in->global_cfg_var, &d) > 0;
            } else {
                have = kelp_app_global_str(h->app, in->global_cfg_var, sval, sizeof sval) > 0;
            }
            if (!have) {
                kelp_app_config_warning(h->app, "line %d: initializer: no global %s (or not a %s)", in->line,
                                        in->global_cfg_var, in->is_double ? "number" : "string");
                continue;
            }
        }
        if (!have) {
            kelp_app_config_warning(h->app, "line %d: initializer for %s without %s", in->line, in->moos_var,
                                    in->is_double ? "dval" : "sval");
            continue;
        }
        if (in->is_double) (void)kelp_app_notify_double(h->app, in->moos_var, d);
        else (void)kelp_app_notify_string(h->app, in->moos_var, sval);
        /* feed the DCCL sources directly too (our own write may arrive after the first trigger) */
        if (h->dccl) kelp_acomms_dccl_set_var(h->dccl, in->moos_var, in->is_double, d, sval);
    }
}

static int startup(kelp_app *app, void *state)
{
    handler *h = state;
    h->app = app;
    char err[512], warn[2048];
    char dirbuf[512];
    snprintf(dirbuf, sizeof dirbuf, "%s", kelp_app_mission_path(app));
    const char *base = dirname(dirbuf);
    const kelp_mission *m = kelp_app_mission(app);
    int block = kelp_app_block(app);
    if (kelp_acomms_config_read(m, block, base, &h->cfg, err, sizeof err, warn, sizeof warn) != KELP_OK)
        return kelp_app_config_error(app, NULL, "%s", err);
    /* every protobuf field of the block was understood (unknown ones are errors above) */
    for (int i = kelp_mission_next(m, block, -1, NULL); i >= 0; i = kelp_mission_next(m, block, i, NULL))
        if (m->nodes[i].kind == KELP_MN_FIELD || m->nodes[i].kind == KELP_MN_MSG) kelp_app_param_used(app, &m->nodes[i]);
    for (char *w = warn, *nl; w && *w; w = nl ? nl + 1 : NULL) {
        nl = strchr(w, '\n');
        if (nl) *nl = '\0';
        kelp_app_config_warning(app, "%s", w);
    }
    h->now = kelp_app_time(app);
    int64_t now_us = us_of(h->now);

    /* DCCL */
    const char *files[KELP_ACOMMS_MAX_FILES];
    unsigned manips[KELP_ACOMMS_MAX_FILES];
    for (size_t i = 0; i < h->cfg.nfiles; i++) {
        files[i] = h->cfg.files[i].path;
        manips[i] = h->cfg.files[i].manip;
    }
    kelp_acomms_dccl_cfg dc;
    memset(&dc, 0, sizeof dc);
    dc.modem_id = (unsigned)h->cfg.modem_id;
    dc.passphrase = h->cfg.has_passphrase ? h->cfg.crypto_passphrase : NULL;
    dc.lookup_path = h->cfg.modem_id_lookup_path;
    dc.have_origin = h->cfg.has_lat_origin && h->cfg.has_lon_origin;
    dc.lat_origin = h->cfg.lat_origin;
    dc.lon_origin = h->cfg.lon_origin;
    dc.files = files;
    dc.manips = manips;
    dc.nfiles = h->cfg.nfiles;
    h->dccl = kelp_acomms_dccl_open(&dc, err, sizeof err);
    if (!h->dccl) return kelp_app_config_error(app, NULL, "DCCL: %s", err);
    if (kelp_acomms_dccl_count(h->dccl) + h->cfg.nccl > KELP_ACOMMS_MAX_QUEUES)
        return kelp_app_config_error(app, NULL, "too many queues (max %d)", KELP_ACOMMS_MAX_QUEUES);

    /* node */
    kelp_acomms_node_cfg nc;
    kelp_acomms_config_node(&h->cfg, &nc);
    h->pool = calloc(KELP_ACOMMS_MAX_POOL, sizeof *h->pool);
    if (!h->pool) return kelp_app_config_error(app, NULL, "out of memory");
    kelp_acomms_node_ops ops = { node_write, node_event, on_demand };
    int rc = kelp_acomms_node_init(&h->node, &nc, h->queues, KELP_ACOMMS_MAX_QUEUES, h->pool, KELP_ACOMMS_MAX_POOL, &ops,
                                   h);
    if (rc) return kelp_app_config_error(app, NULL, "%s", h->node.errmsg ? h->node.errmsg : kelp_strerror(rc));
    if (add_queues(h, now_us) != KELP_OK) return -1;

    /* LCM structures on their own channels */
    char url[512];
    int uline;
    if (kelp_lcm_mission_url(kelp_app_mission(app), url, sizeof url, &uline) == KELP_OK) {
        h->lcm = kelp_acomms_lcm_open(url, err, sizeof err);
        if (!h->lcm) kelp_app_config_warning(app, "no LCM structures: %s", err);
    }

    /* identity, initializers */
    (void)kelp_app_notify_double(app, "MODEM_ID", h->cfg.modem_id);
    (void)kelp_app_notify_double(app, "VEHICLE_ID", h->cfg.modem_id);
    publish_initializers(h);

    /* subscriptions */
    size_t nv = kelp_acomms_dccl_nvars(h->dccl);
    for (size_t i = 0; i < nv; i++) (void)kelp_app_register(app, kelp_acomms_dccl_var_name(h->dccl, i), 0);
    for (size_t i = 0; i < h->nnames; i++) {
        const hq_name *n = &h->names[i];
        if (n->dccl_index >= 0 && n->in_var) (void)kelp_app_register(app, n->in_var, 0);
        if (n->dccl_index < 0 && n->out_var && n->out_var[0]) (void)kelp_app_register(app, n->out_var, 0);
    }
    (void)kelp_app_register(app, "ACOMMS_RANGE_COMMAND", 0);
    (void)kelp_app_register(app, "ACOMMS_MAC_CYCLE_UPDATE", 0);
    (void)kelp_app_register(app, "ACOMMS_POLLER_UPDATE", 0);

    /* start */
    if (h->cfg.driver_type == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
        if (open_link(h) != KELP_OK) return -1;
        h->link_up = kelp_link_connected(h->link);
        h->started_on_link = h->link_up;
        kelp_acomms_node_set_link_up(&h->node, h->link_up);
    }
    kelp_acomms_dccl_start(h->dccl, h->now);
    rc = kelp_acomms_node_start(&h->node, now_us);
    if (rc) return kelp_app_config_error(app, NULL, "%s", h->node.errmsg ? h->node.errmsg : kelp_strerror(rc));
    h->started = true;
    kelp_app_event(app, "modem_id %d, %s, %zu DCCL messages, %zu CCL queues", h->cfg.modem_id,
                   h->cfg.driver_type == KELP_ACOMMS_DRIVER_NONE ? "DRIVER_NONE (in-process channel)"
                                                                : "DRIVER_WHOI_MICROMODEM",
                   kelp_acomms_dccl_count(h->dccl), h->cfg.nccl);
    return 0;
}

/* ------------------------------------------------------------------ mail */

static void on_mail(kelp_app *app, void *state, const kelp_var *v)
{
    handler *h = state;
    h->now = kelp_app_time(app);
    int64_t now_us = us_of(h->now);
    bool is_str = v->kind == KELP_VAR_STRING;
    bool is_dbl = v->kind == KELP_VAR_DOUBLE;
    const char *why = NULL;
    if (strcmp(v->name, "ACOMMS_RANGE_COMMAND") == 0) {
        kelp_acomms_range_req r;
        if (!is_str || kelp_acomms_parse_range_req(v->sval, v->slen, &r, &why) != KELP_OK) {
            h->bad_mail++;
            kelp_app_run_warning(app, "bad ACOMMS_RANGE_COMMAND: %s", why ? why : "not a string");
            return;
        }
        if (r.src == 0) r.src = h->cfg.modem_id;
        if (kelp_acomms_node_range(&h->node, &r, now_us) != KELP_OK)
            kelp_app_run_warning(app, "ranging refused: %s", h->node.errmsg ? h->node.errmsg : "?");
        return;
    }
    if (strcmp(v->name, "ACOMMS_MAC_CYCLE_UPDATE") == 0 || strcmp(v->name, "ACOMMS_POLLER_UPDATE") == 0) {
        kelp_acomms_mac_update u;
        if (!is_str || kelp_acomms_parse_mac_update(v->sval, v->slen, &u, &why) != KELP_OK) {
            h->bad_mail++;
            kelp_app_run_warning(app, "bad %s: %s", v->name, why ? why : "not a string");
            return;
        }
        int rc = kelp_acomms_node_mac_update(&h->node, &u, now_us);
        if (rc == KELP_ERR_NOTFOUND) return; /* for another modem */
        if (rc) kelp_app_run_warning(app, "MAC update refused: %s", h->node.errmsg ? h->node.errmsg : kelp_strerror(rc));
        else kelp_app_event(app, "MAC cycle updated: %zu slot(s), cycle %u s", u.nslots, kelp_mac_cycle_length(&h->node.mac));
        return;
    }
    /* our own publications come back through LCM: they are not mail for us */
    bool own = strcmp(v->source, kelp_app_name(app)) == 0;
    for (size_t i = 0; i < h->nnames; i++) {
        const hq_name *n = &h->names[i];
        if (n->dccl_index >= 0 && n->in_var && strcmp(v->name, n->in_var) == 0 && !own) {
            /* a DCCL message from another process: decode it */
            kelp_acomms_msg m;
            if (!is_str || kelp_acomms_parse_data(v->sval, v->slen, &m, &why) != KELP_OK) {
                h->bad_mail++;
                kelp_app_run_warning(app, "bad %s: %s", v->name, why ? why : "not a string");
                return;
            }
            const char *w2 = NULL;
            int rc = kelp_acomms_dccl_decode(h->dccl, m.data, m.len, h->now, on_publication, h, &w2);
            if (rc && rc != KELP_ERR_STATE) kelp_app_run_warning(app, "cannot decode %s: %s", v->name, w2 ? w2 : "?");
            else if (!rc) h->decoded++;
            return;
        }
        if (n->dccl_index < 0 && n->out_var && n->out_var[0] && strcmp(v->name, n->out_var) == 0) {
            /* CCL: a ModemDataTransmission to queue */
            kelp_acomms_msg m;
            if (!is_str || kelp_acomms_parse_data(v->sval, v->slen, &m, &why) != KELP_OK) {
                h->bad_mail++;
                kelp_app_run_warning(app, "bad %s: %s", v->name, why ? why : "not a string");
                return;
            }
            m.key = n->key;
            if (!m.has_time) {
                m.has_time = true;
                m.time_us = now_us;
            }
            h->ccl_out++;
            h->out_data++;
            if (kelp_acomms_print_data(&m, h->text, sizeof h->text, NULL) == KELP_OK) pub_text(h, "ACOMMS_OUTGOING_DATA");
            if (h->lcm)
                lcm_check(h, kelp_acomms_lcm_data(h->lcm, "ACOMMS_OUTGOING_DATA_LCM", h->now, &m, n->name, NULL),
                          "ACOMMS_OUTGOING_DATA_LCM");
            int rc = kelp_acomms_node_push(&h->node, &m, now_us);
            if (rc) {
                h->push_errors++;
                kelp_app_run_warning(app, "cannot queue %s: %s", v->name,
                                     h->node.errmsg ? h->node.errmsg : kelp_strerror(rc));
            } else {
                h->pushed++;
            }
            return;
        }
    }
    if (!h->dccl) return;
    if (!is_str && !is_dbl) return;
    kelp_acomms_dccl_set_var(h->dccl, v->name, is_dbl, v->dval, is_str ? v->sval : NULL);
    size_t idx[16];
    size_t n = kelp_acomms_dccl_triggered(h->dccl, v->name, idx, 16);
    for (size_t k = 0; k < n; k++) outgoing_dccl(h, idx[k]);
}

/* ------------------------------------------------------------------ iterate */

static void publish_status(handler *h)
{
    if (!h->lcm) return;
    kelp_acomms_status s;
    memset(&s, 0, sizeof s);
    const char *qn[KELP_ACOMMS_MAX_QUEUES];
    int32_t qs[KELP_ACOMMS_MAX_QUEUES];
    s.time = h->now;
    s.modem_id = h->cfg.modem_id;
    s.driver = h->cfg.driver_type == KELP_ACOMMS_DRIVER_NONE ? "DRIVER_NONE" : "DRIVER_WHOI_MICROMODEM";
    s.link = h->link ? kelp_link_describe(h->link) : "";
    s.link_up = h->link ? h->link_up : false;
    kelp_mmdriver *mm = kelp_acomms_node_driver(&h->node);
    s.clock_ok = mm ? kelp_mmdriver_clock_ok(mm) : false;
    static const char *const MACN[] = { "?", "MAC_NONE", "MAC_FIXED_DECENTRALIZED", "MAC_AUTO_DECENTRALIZED",
                                        "MAC_POLLED" };
    s.mac = MACN[h->cfg.mac_type <= 4 ? h->cfg.mac_type : 0];
    s.next_slot_us = kelp_mac_next_slot_time(&h->node.mac);
    if (mm) {
        s.lines_in = mm->count.lines_in;
        s.lines_out = mm->count.lines_out;
        s.bad_lines = mm->count.bad_lines;
        s.retries = mm->count.retries;
        s.modem_errors = mm->count.modem_errors;
    }
    const kelp_acomms_node_counters *nc = kelp_acomms_node_get_counters(&h->node);
    s.reconnects = (uint32_t)h->reconnects;
    s.frames_out = nc->frames_out;
    s.frames_in = nc->frames_in;
    s.acks = (uint32_t)h->acks;
    s.expired = (uint32_t)h->expires;
    s.encoded = (uint32_t)h->encoded;
    s.decoded = (uint32_t)h->decoded;
    for (size_t i = 0; i < h->nnames; i++) {
        qn[i] = h->names[i].name;
        long sz = kelp_queue_size(&h->node.q, h->names[i].key);
        qs[i] = (int32_t)(sz < 0 ? 0 : sz);
    }
    s.nqueues = h->nnames;
    s.queue_name = qn;
    s.queue_size = qs;
    lcm_check(h, kelp_acomms_lcm_status(h->lcm, "ACOMMS_STATUS_LCM", &s), "ACOMMS_STATUS_LCM");
}

static int iterate(kelp_app *app, void *state, double now)
{
    handler *h = state;
    h->now = now;
    int64_t now_us = us_of(now);
    if (h->link) {
        if (kelp_link_service(h->link, now) == 1) {
            bool first = !h->seen_link;
            h->seen_link = true;
            h->link_up = true;
            h->driver_dead = false;
            kelp_acomms_node_set_link_up(&h->node, true);
            if (!first) h->reconnects++;
            kelp_app_event(app, "modem link %s: %s", first ? "up" : "re-established", kelp_link_describe(h->link));
            /* the start-up sequence already went out if the link was open at start */
            if (!(first && h->started_on_link) && kelp_acomms_node_restart_driver(&h->node, now_us) != KELP_OK)
                kelp_app_run_warning(app, "driver restart failed: %s", h->node.errmsg ? h->node.errmsg : "?");
        } else if (h->link_up && !kelp_link_connected(h->link)) {
            h->link_up = false;
            kelp_acomms_node_set_link_up(&h->node, false);
            kelp_app_run_warning(app, "modem link lost: %s", kelp_link_error(h->link));
            kelp_app_event(app, "modem link lost: %s", kelp_link_error(h->link));
        }
    }
    int rc = kelp_acomms_node_tick(&h->node, now_us);
    if (rc == KELP_ERR_TIMEOUT && !h->driver_dead) {
        /* the modem stopped answering: re-open the link and start the driver again */
        h->driver_dead = true;
        if (h->link) {
            kelp_link_close(h->link);
            h->link_up = false;
            kelp_acomms_node_set_link_up(&h->node, false);
        }
    }
    size_t idx[16];
    size_t n = kelp_acomms_dccl_due(h->dccl, now, idx, 16);
    for (size_t k = 0; k < n; k++) outgoing_dccl(h, idx[k]);
    if (now >= h->next_status) {
        publish_status(h);
        h->next_status = now + 1.0;
    }
    return 0;
}

/* ------------------------------------------------------------------ report */

static void report(kelp_app *app, void *state, FILE *out)
{
    handler *h = state;
    (void)app;
    if (!h->started) return;
    kelp_mmdriver *mm = kelp_acomms_node_driver(&h->node);
    fprintf(out, "modem_id %d   driver %s\n", h->cfg.modem_id,
            h->cfg.driver_type == KELP_ACOMMS_DRIVER_NONE ? "DRIVER_NONE (in-process channel)" : "DRIVER_WHOI_MICROMODEM");
    if (h->link) {
        fprintf(out, "link: %s  [%s]%s%s\n", kelp_link_describe(h->link),
                h->link_up ? "up" : (kelp_link_listening(h->link) ? "listening" : "DOWN"),
                kelp_link_error(h->link)[0] ? "  last error: " : "", kelp_link_error(h->link));
        const kelp_link_counters *lc = kelp_link_get_counters(h->link);
        fprintf(out, "      bytes in %llu out %llu, opens %u, failed opens %u, disconnects %u, reconnects %lu\n",
                (unsigned long long)lc->bytes_in, (unsigned long long)lc->bytes_out, lc->opens, lc->open_failures,
                lc->disconnects, h->reconnects);
    }
    if (mm)
        fprintf(out,
                "modem: clock %s, %zu command(s) pending, lines in %u out %u, bad %u, retries %u, give-ups %u, "
                "$CAERR %u, dead %lu\n",
                kelp_mmdriver_clock_ok(mm) ? "ok" : "not set", kelp_mmdriver_pending(mm), mm->count.lines_in, mm->count.lines_out,
                mm->count.bad_lines, mm->count.retries, mm->count.give_ups, mm->count.modem_errors, h->deaths);
    int64_t next = kelp_mac_next_slot_time(&h->node.mac);
    static const char *const MACN[] = { "?", "MAC_NONE", "MAC_FIXED_DECENTRALIZED", "MAC_AUTO_DECENTRALIZED",
                                        "MAC_POLLED" };
    fprintf(out, "MAC: %s, %zu slot(s), cycle %u s", MACN[h->cfg.mac_type <= 4 ? h->cfg.mac_type : 0], h->node.mac.n,
            kelp_mac_cycle_length(&h->node.mac));
    if (next >= 0) fprintf(out, ", next slot in %.1f s", (double)(next - us_of(h->now)) / 1e6);
    fprintf(out, ", %u slot(s) fired, %u skipped (link down)\n", h->node.count.slots, h->node.count.slots_skipped);
    fprintf(out, "%-24s %-6s %5s %9s\n", "queue", "key", "size", "priority");
    for (size_t i = 0; i < h->nnames; i++) {
        const hq_name *n = &h->names[i];
        double p = 0;
        if (kelp_queue_priority(&h->node.q, n->key, us_of(h->now), &p) != KELP_OK) p = NAN;
        fprintf(out, "%-24.24s %s%-4u %5ld %9.3f\n", n->name ? n->name : "?", n->key.type == KELP_QUEUE_CCL ? "C" : "D",
                (unsigned)n->key.id, kelp_queue_size(&h->node.q, n->key), p);
    }
    fprintf(out,
            "DCCL: %lu encoded (%lu errors), %lu decoded (%lu errors); queued %lu (%lu refused); CCL out %lu in %lu\n",
            h->encoded, h->encode_errors, h->decoded, h->decode_errors, h->pushed, h->push_errors, h->ccl_out, h->ccl_in);
    fprintf(out, "frames out %u (blank %u), frames in %u, acks %lu, expired %lu, ranges %lu, bad mail %lu\n",
            h->node.count.frames_out, h->node.count.blank_frames, h->node.count.frames_in, h->acks, h->expires, h->ranges,
            h->bad_mail);
    if (h->cfg.verbosity >= KELP_ACOMMS_VERBOSITY_VERBOSE && mm) {
        unsigned k0 = h->n_out > NMEA_KEEP ? h->n_out - NMEA_KEEP : 0;
        for (unsigned k = k0; k < h->n_out; k++) fprintf(out, "  > %s\n", h->last_out[k % NMEA_KEEP]);
        k0 = h->n_in > NMEA_KEEP ? h->n_in - NMEA_KEEP : 0;
        for (unsigned k = k0; k < h->n_in; k++) fprintf(out, "  < %s\n", h->last_in[k % NMEA_KEEP]);
    }
}

static void shutdown_handler(kelp_app *app, void *state)
{
    handler *h = state;
    (void)app;
    kelp_link_destroy(h->link);
    h->link = NULL;
    kelp_acomms_lcm_close(h->lcm);
    h->lcm = NULL;
    /* the DCCL handle and the pool are kept for the final report; freed in handler_free */
}

handler *handler_new(void)
{
    return calloc(1, sizeof(handler));
}

void handler_free(handler *h)
{
    if (!h) return;
    kelp_link_destroy(h->link);
    kelp_acomms_lcm_close(h->lcm);
    kelp_acomms_dccl_close(h->dccl);
    free(h->pool);
    free(h);
}

const kelp_app_def pacomms_def = {
    .name = "pAcommsHandler",
    .purpose = "Goby 1.1 acoustic communications: DCCL codec, priority queues, TDMA MAC, WHOI Micro-Modem driver.",
    .textformat = true,
    .params = (const kelp_app_param_info[]){
        { "modem_id", "1", "required: this modem, 1..31 (0 is broadcast)", NULL },
        { "common", "{ log: true log_path: \"./\" verbosity: VERBOSITY_VERBOSE }", "optional: Goby's common block", NULL },
        { "driver_type", "DRIVER_NONE", "or DRIVER_WHOI_MICROMODEM", NULL },
        { "driver_cfg", "{ connection_type: CONNECTION_SERIAL serial_port: \"/dev/ttyS0\" serial_baud: 19200 }",
          "the modem link", NULL },
        { "mac_cfg", "{ type: MAC_NONE }", "or MAC_FIXED_DECENTRALIZED, MAC_AUTO_DECENTRALIZED, MAC_POLLED", NULL },
        { "queue_cfg", "{ message_file { path: \"simple_status.xml\" manipulator: NO_MANIP } }", "DCCL and CCL queues", NULL },
        { "dccl_cfg", "{ message_file { path: \"example1.xml\" manipulator: LOOPBACK } }", "DCCL messages", NULL },
        { "modem_id_lookup_path", "\"modemidlookup.txt\"", "optional: \"id,name,type\" lines", NULL },
        { "tcp_share_enable", "false", "experimental in Goby: not implemented", NULL },
        { "tcp_share_port", "11000", "experimental in Goby: not implemented", NULL },
        { "tcp_share_to_ip", "\"192.168.1.20\"", "repeatable (up to 4); experimental in Goby: not implemented", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "<src_var>", "23.5", "every DCCL <src_var>/<moos_var> and <trigger_var> of the message files" },
        { "OUT_<NAME>_HEX_<size>B", "src: 1 dest: 2 data: \"...\"", "ModemDataTransmission to encode and queue"
          " (or <outgoing_hex_moos_var>)" },
        { "<queue.out_pubsub_var>", "data: \"\\002\\002\\003\\004\"", "CCL: ModemDataTransmission to queue" },
        { "ACOMMS_RANGE_COMMAND", "src: 1 dest: 2 type: MODEM_TWO_WAY_PING", "ModemRangingRequest" },
        { "ACOMMS_MAC_CYCLE_UPDATE", "dest: 1 update_type: REPLACE slot { src: 2 dest: 1 }", "MACUpdate" },
        { "ACOMMS_POLLER_UPDATE", "(as ACOMMS_MAC_CYCLE_UPDATE)", NULL },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "<publish_var>", "23.5", "DCCL publishes on receipt" },
        { "ACOMMS_INCOMING_DATA", "src: 2 dest: 1 data: \"...\"", "ModemDataTransmission (TextFormat)" },
        { "ACOMMS_OUTGOING_DATA", "src: 1 dest: 2 data: \"...\"", "ModemDataTransmission" },
        { "OUT_<NAME>_HEX_<size>B", "src: 1 dest: 2 data: \"...\"", "on encode" },
        { "IN_<NAME>_HEX_<size>B", "src: 2 dest: 1 data: \"...\"", "on receipt" },
        { "<queue.in_pubsub_var>", "data: \"\\002\\002\\003\\004\"", "CCL, on receipt" },
        { "ACOMMS_ACK", "src: 2 dest: 1 frame: 0", "ModemDataAck" },
        { "ACOMMS_EXPIRE", "src: 1 dest: 2", "ModemDataExpire" },
        { "ACOMMS_QSIZE", "key { type: QUEUE_DCCL id: 14 } size: 3", "QueueSize" },
        { "ACOMMS_RANGE_RESPONSE", "src: 1 dest: 2 one_way_travel_time: 0.35", "ModemRangingReply" },
        { "ACOMMS_NMEA_IN", "$CARXD,2,1,0,1,0102*2C", "every sentence from the modem" },
        { "ACOMMS_NMEA_OUT", "$CCCYC,0,1,2,0,0,1*5B", "every sentence to the modem" },
        { "MODEM_ID", "1", "at start-up; also the common.initializer variables" },
        { "VEHICLE_ID", "1", "at start-up" },
        { "ACOMMS_STATUS_LCM", "(kelp.acomms_status_t)", "LCM structures on their own channels, once a second;"
          " also ACOMMS_{INCOMING,OUTGOING}_DATA_LCM, ACOMMS_{ACK,EXPIRE,QSIZE,RANGE_RESPONSE}_LCM" },
        { NULL, NULL, NULL } },
    .notes = PACOMMS_EXAMPLE,
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown_handler,
};
