/* pAcommsHandler: the core handler wired to the bus, the modem link and the LCM structures.
 * What the app does with mail, frames and time is kelp_acomms_handler's (src/acomms/handler.c);
 * here: the configuration, the DCCL message files, the link's file descriptor, the app runner. */
#include <libgen.h>
#include <stdlib.h>
#include <string.h>

#include "handler.h"

/* ------------------------------------------------------------------ the sink */

static int sink_publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    handler *h = ctx;
    return is_string ? kelp_app_notify_string(h->app, var, sval) : kelp_app_notify_double(h->app, var, dval);
}

static void sink_warn(void *ctx, const char *msg)
{
    kelp_app_run_warning(((handler *)ctx)->app, "%s", msg);
}

static void sink_event(void *ctx, const char *msg)
{
    kelp_app_event(((handler *)ctx)->app, "%s", msg);
}

static void sink_write(void *ctx, const char *bytes, size_t len)
{
    handler *h = ctx;
    if (!h->link) return;
    if (kelp_link_write(h->link, bytes, len) != KELP_OK) {
        h->write_errors++;
        kelp_app_run_warning(h->app, "modem link write failed: %s", kelp_link_error(h->link));
    }
}

static void sink_close_link(void *ctx)
{
    handler *h = ctx;
    if (h->link) kelp_link_close(h->link);
}

static void sink_record(void *ctx, const kelp_acomms_record *rec)
{
    handler *h = ctx;
    if (h->lcm && kelp_acomms_lcm_record(h->lcm, rec) != KELP_OK)
        kelp_app_run_warning(h->app, "LCM publish of %s failed", rec->channel);
}

static int send_lcm(void *ctx, const char *channel, const void *data, size_t len)
{
    return kelp_app_publish_raw(((handler *)ctx)->app, channel, data, len);
}

/* ------------------------------------------------------------------ link */

static void on_link_readable(kelp_app *app, void *state, int fd)
{
    handler *h = state;
    (void)fd;
    uint8_t buf[4096];
    for (int guard = 0; guard < 64; guard++) {
        size_t n = 0;
        if (kelp_link_read(h->link, buf, sizeof buf, &n) != KELP_OK) {
            kelp_acomms_handler_link_lost(&h->core, kelp_link_error(h->link));
            return;
        }
        if (n == 0) return;
        kelp_acomms_handler_feed(&h->core, buf, n, kelp_app_time(app));
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
    kelp_diag d;
    kelp_diag_clear(&d);
    h->link = kelp_link_create(&lc, &d);
    if (!h->link) return kelp_app_config_error(h->app, NULL, "modem link: %s", kelp_diag_text(&d));
    h->core.link_desc = kelp_link_describe(h->link);
    if (kelp_app_watch_fd(h->app, kelp_link_fd(h->link), on_link_readable) != KELP_OK)
        return kelp_app_config_error(h->app, NULL, "cannot watch the modem link");
    if (!kelp_link_connected(h->link) && !kelp_link_listening(h->link))
        kelp_app_run_warning(h->app, "modem link not up yet (%s): retrying", kelp_link_error(h->link));
    return KELP_OK;
}

/* ------------------------------------------------------------------ start-up */

static void publish_initializers(handler *h)
{
    for (size_t i = 0; i < h->cfg.n_init; i++) {
        const kelp_acomms_initializer *in = &h->cfg.init[i];
        char sval[KELP_ACOMMS_MAX_TEXT];
        double d = in->dval;
        bool have = in->is_double ? in->has_dval : in->has_sval;
        snprintf(sval, sizeof sval, "%s", in->sval);
        if (in->global_cfg_var[0]) {
            if (in->is_double) have = kelp_app_global_double(h->app, in->global_cfg_var, &d) > 0;
            else have = kelp_app_global_str(h->app, in->global_cfg_var, sval, sizeof sval) > 0;
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
        if (in->is_double) KELP_IGNORE(kelp_app_notify_double(h->app, in->moos_var, d));
        else KELP_IGNORE(kelp_app_notify_string(h->app, in->moos_var, sval));
        /* feed the DCCL sources directly too (our own write may arrive after the first trigger) */
        kelp_acomms_handler_set_var(&h->core, in->moos_var, in->is_double, d, sval);
    }
}

/* the pAcommsHandler block into h->cfg; its warnings as configuration warnings */
static int read_config(handler *h)
{
    kelp_app *app = h->app;
    char warn[2048], dirbuf[512];
    kelp_diag err;
    kelp_diag_clear(&err);
    snprintf(dirbuf, sizeof dirbuf, "%s", kelp_app_mission_path(app));
    const kelp_mission *m = kelp_app_mission(app);
    int block = kelp_app_block(app);
    if (kelp_acomms_config_read(m, block, dirname(dirbuf), &h->cfg, &err, warn, sizeof warn) != KELP_OK)
        return kelp_app_config_error(app, NULL, "%s", kelp_diag_text(&err));
    /* every protobuf field of the block was understood (unknown ones are errors above) */
    for (int i = kelp_mission_next(m, block, -1, NULL); i >= 0; i = kelp_mission_next(m, block, i, NULL))
        if (m->nodes[i].kind == KELP_MN_FIELD || m->nodes[i].kind == KELP_MN_MSG) kelp_app_param_used(app, &m->nodes[i]);
    for (char *w = warn, *nl; w && *w; w = nl ? nl + 1 : NULL) {
        nl = strchr(w, '\n');
        if (nl) *nl = '\0';
        kelp_app_config_warning(app, "%s", w);
    }
    /* pGeneralCodec is deprecated for "pAcommsHandler with no driver, no MAC and no queuing"
     * (seed 002 section 2.10): run under that name, the block is a DCCL codec only; its
     * messages are encoded to OUT_<NAME>_HEX_<size>B and decoded from IN_<NAME>_HEX_<size>B */
    if (strcmp(kelp_app_name(app), "pGeneralCodec") == 0) {
        h->codec_only = true;
        if (h->cfg.driver_type != KELP_ACOMMS_DRIVER_NONE || h->cfg.mac_type != KELP_MAC_NONE || h->cfg.nccl)
            kelp_app_config_warning(app, "pGeneralCodec: encode/decode only: the driver, MAC and CCL queues are ignored");
        h->cfg.driver_type = KELP_ACOMMS_DRIVER_NONE;
        h->cfg.mac_type = KELP_MAC_NONE;
        h->cfg.nslots = 0;
        h->cfg.nccl = 0;
        for (size_t i = 0; i < h->cfg.nfiles; i++) h->cfg.files[i].manip |= KELP_ACOMMS_MANIP_NO_QUEUE;
    }
    return KELP_OK;
}

static int open_dccl(handler *h)
{
    kelp_diag err;
    kelp_diag_clear(&err);
    h->dccl = kelp_acomms_dccl_open_config(&h->cfg, false, &err);
    if (!h->dccl) return kelp_app_config_error(h->app, NULL, "DCCL: %s", kelp_diag_text(&err));
    if (kelp_acomms_dccl_count(h->dccl) + h->cfg.nccl > KELP_ACOMMS_MAX_QUEUES)
        return kelp_app_config_error(h->app, NULL, "too many queues (max %d)", KELP_ACOMMS_MAX_QUEUES);
    kelp_acomms_dccl_codec(h->dccl, &h->codec);
    return KELP_OK;
}

static int init_core(handler *h, double now)
{
    kelp_acomms_node_cfg nc;
    kelp_acomms_config_node(&h->cfg, &nc);
    if (h->codec_only) nc.loopback_channel = false; /* nothing is queued or sent */
    h->pool = calloc(KELP_ACOMMS_MAX_POOL, sizeof *h->pool);
    if (!h->pool) return kelp_app_config_error(h->app, NULL, "out of memory");
    const kelp_acomms_sink sink = { h, sink_publish, sink_warn, sink_event, sink_write, sink_close_link, sink_record,
                                    NULL };
    int rc = kelp_acomms_handler_init(&h->core, &h->cfg, &nc, &h->codec, h->pool, KELP_ACOMMS_MAX_POOL, &sink, now);
    if (rc && h->core.err_queue && h->core.err_ccl)
        return kelp_app_config_error(h->app, NULL, "cannot add CCL queue %s: %s", h->core.err_queue,
                                     kelp_diag_text(&h->core.diag));
    if (rc && h->core.err_queue)
        return kelp_app_config_error(h->app, NULL, "cannot add the queue of DCCL message %s (id %u): %s",
                                     h->core.err_queue, h->core.err_id, kelp_diag_text(&h->core.diag));
    if (rc) return kelp_app_config_error(h->app, NULL, "%s", kelp_diag_text(&h->core.diag));
    return KELP_OK;
}

int handler_startup(kelp_app *app, void *state)
{
    handler *h = state;
    h->app = app;
    if (read_config(h) != KELP_OK || open_dccl(h) != KELP_OK) return -1;
    double now = kelp_app_time(app);
    if (init_core(h, now) != KELP_OK) return -1;
    /* the LCM structures go out on their own channels, through the app's LCM socket (from
     * here on: the queues' sizes at init are bus variables only) */
    h->lcm = kelp_acomms_lcm_new(send_lcm, h);
    if (!h->lcm) return kelp_app_config_error(app, NULL, "out of memory");
    publish_initializers(h);
    const char *var;
    for (size_t i = 0; (var = kelp_acomms_handler_subscription(&h->core, i)) != NULL; i++)
        KELP_IGNORE(kelp_app_register(app, var, 0));
    bool link_up = false;
    if (h->cfg.driver_type == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
        if (open_link(h) != KELP_OK) return -1;
        link_up = kelp_link_connected(h->link);
    }
    int rc = kelp_acomms_handler_start(&h->core, link_up, now);
    if (rc) return kelp_app_config_error(app, NULL, "%s", kelp_diag_text(&h->core.diag));
    return 0;
}

/* ------------------------------------------------------------------ mail, iterate */

void handler_mail(kelp_app *app, void *state, const kelp_var *v)
{
    handler *h = state;
    /* our own publications come back through LCM */
    kelp_acomms_handler_mail(&h->core, v, strcmp(v->source, kelp_app_name(app)) == 0, kelp_app_time(app));
}

int handler_iterate(kelp_app *app, void *state, double now)
{
    handler *h = state;
    (void)app;
    if (h->link) {
        if (kelp_link_service(h->link, now) == 1) kelp_acomms_handler_link_up(&h->core, now);
        else if (h->core.link_up && !kelp_link_connected(h->link))
            kelp_acomms_handler_link_lost(&h->core, kelp_link_error(h->link));
    }
    kelp_acomms_handler_tick(&h->core, now);
    return 0;
}

void handler_shutdown(kelp_app *app, void *state)
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
