/* kelp acomms: pAcommsHandler's logic as a core state machine (see include/kelp/acomms.h, 4b).
 *
 * DCCL (encode on trigger/time, decode and publish on receipt) through the caller's codec,
 * priority queues + TDMA MAC + driver through the node, and every Goby 1.1 pAcommsHandler
 * publication (ACOMMS_* TextFormat strings, IN_/OUT_ hex variables, <publish> variables)
 * through the sink.  The structured copies (records) are made only when the sink wants them,
 * so an outgoing DCCL message is described (decoded once more) only for them. */
#include <math.h>
#include <stdarg.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/util.h>

#define MAX_RAW_PUBLISH 35000 /* Goby publishes raw NMEA only below this length */
#define MAX_IDX 16

const char *kelp_acomms_mac_name(kelp_mac_type t)
{
    static const char *const MACN[] = { "?", "MAC_NONE", "MAC_FIXED_DECENTRALIZED", "MAC_AUTO_DECENTRALIZED",
                                        "MAC_POLLED" };
    return MACN[(unsigned)t <= 4 ? (unsigned)t : 0];
}

const kelp_acomms_qname *kelp_acomms_handler_queue(const kelp_acomms_handler *h, kelp_queue_key key)
{
    for (size_t i = 0; i < h->nnames; i++)
        if (h->names[i].key.type == key.type && h->names[i].key.id == key.id) return &h->names[i];
    return NULL;
}

static const char *qname_of(const kelp_acomms_handler *h, kelp_queue_key key)
{
    const kelp_acomms_qname *n = kelp_acomms_handler_queue(h, key);
    return n ? n->name : NULL;
}

int kelp_acomms_msg_from_dccl(kelp_acomms_msg *m, size_t len, int src, unsigned id, kelp_time time)
{
    kelp_queue_header hd;
    if (!m || len > sizeof m->data) return KELP_ERR_ARG;
    int rc = kelp_queue_header_read(m->data, len, &hd);
    if (rc) return rc;
    m->len = len;
    m->src = src;
    m->dest = (int)hd.dest;
    m->has_time = true;
    m->time = time;
    m->key.type = KELP_QUEUE_DCCL;
    m->key.id = id;
    return KELP_OK;
}

/* ------------------------------------------------------------------ sink helpers */

static void say(kelp_acomms_handler *h, bool warning, const char *fmt, ...) KELP_PRINTF(3, 4);
static void say(kelp_acomms_handler *h, bool warning, const char *fmt, ...)
{
    void (*fn)(void *, const char *) = warning ? h->sink.warn : h->sink.event;
    if (!fn) return;
    va_list ap;
    va_start(ap, fmt);
    (void)kelp_util_vsnprintf(h->line, sizeof h->line, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized) */
    va_end(ap);
    fn(h->sink.ctx, h->line);
}

#define WARN(h, ...) say((h), true, __VA_ARGS__)

/* h->diag emptied for the next call that reports into it */
static kelp_diag *fresh(kelp_acomms_handler *h)
{
    kelp_diag_clear(&h->diag);
    return &h->diag;
}

/* the reason the node gave for its last failure, or dflt when none */
static const char *node_reason(const kelp_acomms_handler *h, const char *dflt)
{
    return h->node.diag.code ? kelp_diag_text(&h->node.diag) : dflt;
}

/* the reason h->diag holds, or dflt when the failed call gave none */
static const char *reason(const kelp_acomms_handler *h, const char *dflt)
{
    return h->diag.code ? kelp_diag_text(&h->diag) : dflt;
}
#define EVENT(h, ...) say((h), false, __VA_ARGS__)

/* h->text on var; a failure is a warning */
static void pub_text(kelp_acomms_handler *h, const char *var)
{
    if (h->sink.publish(h->sink.ctx, var, true, h->text, 0) < 0) WARN(h, "cannot publish %s", var);
}

static void pub_record(kelp_acomms_handler *h, const kelp_acomms_record *r)
{
    if (h->sink.record) h->sink.record(h->sink.ctx, r);
}

static void record_data(kelp_acomms_handler *h, const char *channel, const kelp_acomms_msg *m, const char *name,
                        const char *decoded)
{
    kelp_acomms_record r;
    memset(&r, 0, sizeof r);
    r.kind = KELP_ACOMMS_REC_DATA;
    r.channel = channel;
    r.time = h->now;
    r.msg = m;
    r.name = name;
    r.decoded = decoded;
    pub_record(h, &r);
}

/* a DCCL <publish> variable */
static void on_publication(const char *var, bool is_double, double dval, const char *sval, void *user)
{
    kelp_acomms_handler *h = user;
    if (h->sink.publish(h->sink.ctx, var, !is_double, is_double ? NULL : sval, is_double ? dval : 0) < 0)
        WARN(h, "cannot publish %s", var);
}

/* "Name: field=value,..." of a DCCL message into decoded_text, when a record will carry it */
static const char *describe(kelp_acomms_handler *h, const kelp_acomms_msg *m)
{
    h->decoded_text[0] = '\0';
    if (!h->sink.record || !h->has_codec) return h->decoded_text;
    if (h->codec.describe(h->codec.ctx, m->data, m->len, h->now, h->decoded_text, sizeof h->decoded_text) != KELP_OK) {
        /* the text says why ("(cannot decode ...)"); decode reports the error */
    }
    return h->decoded_text;
}

static void keep_line(char (*ring)[KELP_ACOMMS_NMEA_KEEP_LEN], unsigned *n, const char *raw)
{
    (void)kelp_util_snprintf(ring[*n % KELP_ACOMMS_NMEA_KEEP], KELP_ACOMMS_NMEA_KEEP_LEN, "%s", raw);
    (*n)++;
}

/* ------------------------------------------------------------------ incoming */

/* a DCCL message for us: ACOMMS_INCOMING_DATA, its IN_ hex var, decode + <publish> */
static void incoming_dccl(kelp_acomms_handler *h, const kelp_acomms_msg *m)
{
    const kelp_acomms_qname *nm = kelp_acomms_handler_queue(h, m->key);
    h->count.in_data++;
    const char *decoded = describe(h, m);
    if (kelp_acomms_print_data(m, h->text, sizeof h->text, NULL) == KELP_OK) {
        pub_text(h, "ACOMMS_INCOMING_DATA");
        if (nm && nm->in_var) pub_text(h, nm->in_var);
    }
    record_data(h, "ACOMMS_INCOMING_DATA_LCM", m, nm ? nm->name : NULL, decoded);
    if (!h->has_codec) return;
    int rc = h->codec.decode(h->codec.ctx, m->data, m->len, h->now, on_publication, h, fresh(h));
    if (rc == KELP_ERR_STATE) return; /* NO_DECODE */
    if (rc) {
        h->count.decode_errors++;
        WARN(h, "cannot decode a received DCCL message: %s", reason(h, kelp_err_str(rc)));
        return;
    }
    h->count.decoded++;
}

static void incoming_ccl(kelp_acomms_handler *h, const kelp_acomms_msg *m)
{
    const kelp_acomms_qname *nm = kelp_acomms_handler_queue(h, m->key);
    h->count.in_data++;
    h->count.ccl_in++;
    if (kelp_acomms_print_data(m, h->text, sizeof h->text, NULL) == KELP_OK) {
        pub_text(h, "ACOMMS_INCOMING_DATA");
        if (nm && nm->in_var && nm->in_var[0]) pub_text(h, nm->in_var);
    }
    record_data(h, "ACOMMS_INCOMING_DATA_LCM", m, nm ? nm->name : NULL, NULL);
}

static void on_queue_event(kelp_acomms_handler *h, const kelp_queue_event *q)
{
    const char *name = qname_of(h, q->key);
    kelp_acomms_record r;
    memset(&r, 0, sizeof r);
    r.time = h->now;
    r.name = name;
    switch (q->kind) {
    case KELP_QUEUE_EV_RECEIVE: incoming_dccl(h, q->msg); break;
    case KELP_QUEUE_EV_RECEIVE_CCL: incoming_ccl(h, q->msg); break;
    case KELP_QUEUE_EV_ACK:
        h->count.acks++;
        /* the acknowledging modem is the message's destination; the ack is addressed to us */
        if (kelp_acomms_print_ack(q->msg->dest, h->cfg->modem_id, q->frame, h->now, q->msg, h->text,
                                  sizeof h->text, NULL) == KELP_OK)
            pub_text(h, "ACOMMS_ACK");
        r.kind = KELP_ACOMMS_REC_ACK;
        r.channel = "ACOMMS_ACK_LCM";
        r.src = q->msg->dest;
        r.dest = h->cfg->modem_id;
        r.frame = q->frame;
        r.msg = q->msg;
        pub_record(h, &r);
        EVENT(h, "ack from %d for %s (frame %u)", q->msg->dest, name ? name : "?", (unsigned)q->frame);
        break;
    case KELP_QUEUE_EV_EXPIRE:
        h->count.expires++;
        if (kelp_acomms_print_expire(q->msg, h->text, sizeof h->text, NULL) == KELP_OK) pub_text(h, "ACOMMS_EXPIRE");
        r.kind = KELP_ACOMMS_REC_EXPIRE;
        r.channel = "ACOMMS_EXPIRE_LCM";
        r.msg = q->msg;
        pub_record(h, &r);
        EVENT(h, "expired: a %s message for %d", name ? name : "?", q->msg->dest);
        break;
    case KELP_QUEUE_EV_QSIZE:
        if (kelp_acomms_print_qsize(q->key, q->size, h->text, sizeof h->text, NULL) == KELP_OK)
            pub_text(h, "ACOMMS_QSIZE");
        r.kind = KELP_ACOMMS_REC_QSIZE;
        r.channel = "ACOMMS_QSIZE_LCM";
        r.key = q->key;
        r.size = q->size;
        pub_record(h, &r);
        break;
    default: break;
    }
}

static void on_driver_event(kelp_acomms_handler *h, const kelp_mmdriver_event *e)
{
    switch (e->kind) {
    case KELP_MMDRIVER_EV_NMEA_IN:
    case KELP_MMDRIVER_EV_NMEA_OUT: {
        bool in = e->kind == KELP_MMDRIVER_EV_NMEA_IN;
        if (in) h->count.nmea_in++;
        else h->count.nmea_out++;
        if (e->raw && e->raw_len < MAX_RAW_PUBLISH) {
            (void)h->sink.publish(h->sink.ctx, in ? "ACOMMS_NMEA_IN" : "ACOMMS_NMEA_OUT", true, e->raw, 0);
            if (in) keep_line(h->last_in, &h->n_in, e->raw);
            else keep_line(h->last_out, &h->n_out, e->raw);
        }
        break;
    }
    case KELP_MMDRIVER_EV_RANGE: {
        h->count.ranges++;
        if (kelp_acomms_print_range(e->src, e->dest, e->time, e->ranging, e->tt, e->n_tt, h->text, sizeof h->text,
                                    NULL) == KELP_OK)
            pub_text(h, "ACOMMS_RANGE_RESPONSE");
        kelp_acomms_record r;
        memset(&r, 0, sizeof r);
        r.kind = KELP_ACOMMS_REC_RANGE;
        r.channel = "ACOMMS_RANGE_RESPONSE_LCM";
        r.time = h->now;
        r.src = e->src;
        r.dest = e->dest;
        r.type = e->ranging;
        r.tt = e->tt;
        r.n_tt = e->n_tt;
        pub_record(h, &r);
        break;
    }
    case KELP_MMDRIVER_EV_MODEM_ERROR:
        h->count.modem_errors++;
        WARN(h, "modem error: %s", e->raw ? e->raw : "$CAERR");
        break;
    case KELP_MMDRIVER_EV_BAD_LINE:
        h->count.bad_lines++;
        WARN(h, "bad line from the modem ignored (%s)", kelp_err_str(e->err));
        break;
    case KELP_MMDRIVER_EV_RETRY:
        h->count.retries++;
        EVENT(h, "no answer from the modem: resending %.60s", e->raw ? e->raw : "");
        break;
    case KELP_MMDRIVER_EV_GIVE_UP:
        h->count.give_ups++;
        WARN(h, "modem did not answer %.40s after 3 tries: command queue cleared", e->raw ? e->raw : "");
        break;
    case KELP_MMDRIVER_EV_DEAD:
        h->count.deaths++;
        WARN(h, "modem not responding: reconnecting the link");
        EVENT(h, "modem not responding: reconnecting the link");
        break;
    case KELP_MMDRIVER_EV_CLOCK: EVENT(h, "modem clock %s", e->clock_ok ? "set" : "needs setting"); break;
    default: break;
    }
}

static void node_event(const kelp_acomms_event *ev, void *user)
{
    kelp_acomms_handler *h = user;
    switch (ev->kind) {
    case KELP_ACOMMS_EV_QUEUE: on_queue_event(h, ev->q); break;
    case KELP_ACOMMS_EV_DRIVER: on_driver_event(h, ev->mm); break;
    case KELP_ACOMMS_EV_SLOT:
        if (h->cfg->verbosity >= KELP_ACOMMS_VERBOSITY_DEBUG)
            EVENT(h, "MAC slot %u: %s %d -> %d rate %u", ev->slot->slot_index,
                  ev->slot->kind == KELP_MAC_ACT_TRANSMIT ? "transmit" : "ranging", ev->slot->src, ev->slot->dest,
                  ev->slot->rate);
        break;
    default: break;
    }
    if (h->sink.node_event) h->sink.node_event(h->sink.ctx, ev);
}

static void node_write(const char *bytes, size_t len, void *user)
{
    kelp_acomms_handler *h = user;
    if (h->sink.write) h->sink.write(h->sink.ctx, bytes, len);
}

/* ------------------------------------------------------------------ outgoing DCCL */

static int build_msg(kelp_acomms_handler *h, size_t idx, kelp_acomms_msg *m)
{
    kelp_acomms_dccl_info info;
    if (h->codec.info(h->codec.ctx, idx, &info) != KELP_OK) return KELP_ERR_ARG;
    memset(m, 0, sizeof *m);
    size_t len = 0;
    int rc = h->codec.encode(h->codec.ctx, idx, h->now, m->data, sizeof m->data, &len, fresh(h));
    if (rc) return rc;
    if (kelp_acomms_msg_from_dccl(m, len, h->cfg->modem_id, info.id, h->now) != KELP_OK)
        return kelp_fail(&h->diag, KELP_ERR_TRUNCATED, "encoded message shorter than its header");
    return KELP_OK;
}

static void outgoing_dccl(kelp_acomms_handler *h, size_t idx)
{
    kelp_acomms_dccl_info info;
    kelp_acomms_msg *m = &h->work.msg;
    if (h->codec.info(h->codec.ctx, idx, &info) != KELP_OK) return;
    if (info.manip & KELP_ACOMMS_MANIP_ON_DEMAND) return; /* encoded at the data request */
    int rc = build_msg(h, idx, m);
    if (rc == KELP_ERR_PARTIAL) return; /* <repeat>: still collecting */
    if (rc) {
        h->count.encode_errors++;
        WARN(h, "cannot encode %s: %s", info.name, reason(h, kelp_err_str(rc)));
        return;
    }
    h->count.encoded++;
    h->count.out_data++;
    const char *decoded = describe(h, m);
    if (kelp_acomms_print_data(m, h->text, sizeof h->text, NULL) == KELP_OK) {
        pub_text(h, "ACOMMS_OUTGOING_DATA");
        if (info.out_var) pub_text(h, info.out_var);
    }
    record_data(h, "ACOMMS_OUTGOING_DATA_LCM", m, info.name, decoded);
    rc = kelp_acomms_node_push(&h->node, m, h->now);
    if (rc) {
        h->count.push_errors++;
        WARN(h, "cannot queue %s: %s", info.name, kelp_err_str(rc));
    } else {
        h->count.pushed++;
    }
    /* LOOPBACK: "decode this message internally immediately following encode" (a message to
     * ourselves was already looped back by the queue) */
    if ((info.manip & KELP_ACOMMS_MANIP_LOOPBACK) && m->dest != h->cfg->modem_id) {
        rc = h->codec.decode(h->codec.ctx, m->data, m->len, h->now, on_publication, h, fresh(h));
        if (rc == KELP_OK) h->count.decoded++;
        else if (rc != KELP_ERR_STATE) WARN(h, "LOOPBACK decode of %s failed: %s", info.name, reason(h, "?"));
    }
}

static void outgoing_all(kelp_acomms_handler *h, const size_t *idx, size_t n)
{
    for (size_t k = 0; k < n; k++) outgoing_dccl(h, idx[k]);
}

static void on_demand(kelp_queue_key key, const kelp_queue_request *req, kelp_acomms_msg *out, void *user)
{
    kelp_acomms_handler *h = user;
    (void)req;
    out->len = 0;
    if (!h->has_codec) return;
    long idx = h->codec.find_id(h->codec.ctx, key.id);
    if (idx < 0) return;
    int rc = build_msg(h, (size_t)idx, out);
    if (rc) {
        out->len = 0;
        if (rc != KELP_ERR_PARTIAL) WARN(h, "ON_DEMAND encode failed: %s", reason(h, "?"));
        return;
    }
    h->count.encoded++;
}

/* ------------------------------------------------------------------ set-up */

static int add_queues(kelp_acomms_handler *h, kelp_time now)
{
    size_t nm = h->has_codec ? h->codec.count(h->codec.ctx) : 0;
    for (size_t i = 0; i < nm && h->nnames < KELP_ACOMMS_MAX_QUEUES; i++) {
        kelp_acomms_dccl_info info;
        if (h->codec.info(h->codec.ctx, i, &info) != KELP_OK) continue;
        kelp_queue_cfg q;
        /* loopback stays off: LOOPBACK is done here, right after the encode (whatever the dest) */
        kelp_acomms_queue_cfg_from_info(&info, &q);
        kelp_acomms_qname *n = &h->names[h->nnames];
        n->key = q.key;
        n->name = info.name;
        n->in_var = info.in_var;
        n->out_var = info.out_var;
        n->dccl_index = (long)i;
        h->nnames++; /* named before it is added: adding it reports its size */
        int rc = kelp_acomms_node_add_queue(&h->node, &q, now);
        if (rc) {
            h->nnames--;
            (void)kelp_fail(&h->diag, rc, node_reason(h, NULL));
            h->err_queue = info.name;
            h->err_id = info.id;
            return rc;
        }
    }
    for (size_t i = 0; i < h->cfg->nccl && h->nnames < KELP_ACOMMS_MAX_QUEUES; i++) {
        const kelp_acomms_ccl_queue *cq = &h->cfg->ccl[i];
        kelp_queue_cfg q = cq->cfg;
        q.name = cq->name;
        kelp_acomms_qname *n = &h->names[h->nnames];
        n->key = q.key;
        n->name = cq->name;
        n->in_var = cq->in_var;
        n->out_var = cq->out_var;
        n->dccl_index = -1;
        h->nnames++;
        int rc = kelp_acomms_node_add_queue(&h->node, &q, now);
        if (rc) {
            h->nnames--;
            (void)kelp_fail(&h->diag, rc, node_reason(h, NULL));
            h->err_queue = cq->name;
            h->err_id = q.key.id;
            h->err_ccl = true;
            return rc;
        }
    }
    return KELP_OK;
}

int kelp_acomms_handler_init(kelp_acomms_handler *h, const kelp_acomms_config *cfg, const kelp_acomms_node_cfg *nc,
                             const kelp_acomms_codec *codec, kelp_queue_entry *pool, size_t cap_pool,
                             const kelp_acomms_sink *sink, kelp_time now)
{
    if (!h || !cfg || !nc || !sink || !sink->publish) return KELP_ERR_ARG;
    memset(h, 0, sizeof *h);
    h->cfg = cfg;
    h->sink = *sink;
    h->link_desc = "";
    if (codec) {
        h->codec = *codec;
        h->has_codec = true;
    }
    h->now = now;
    kelp_acomms_node_ops ops = { node_write, node_event, on_demand };
    int rc = kelp_acomms_node_init(&h->node, nc, h->queues, KELP_ACOMMS_MAX_QUEUES, pool, cap_pool, &ops, h);
    if (rc) {
        (void)kelp_fail(&h->diag, rc, node_reason(h, NULL));
        return rc;
    }
    rc = add_queues(h, now);
    if (rc) return rc;
    (void)h->sink.publish(h->sink.ctx, "MODEM_ID", false, NULL, cfg->modem_id);
    (void)h->sink.publish(h->sink.ctx, "VEHICLE_ID", false, NULL, cfg->modem_id);
    return KELP_OK;
}

const char *kelp_acomms_handler_subscription(kelp_acomms_handler *h, size_t i)
{
    static const char *const COMMANDS[] = { "ACOMMS_RANGE_COMMAND", "ACOMMS_MAC_CYCLE_UPDATE", "ACOMMS_POLLER_UPDATE" };
    size_t nv = h->has_codec ? h->codec.nvars(h->codec.ctx) : 0;
    if (i < nv) return h->codec.var_name(h->codec.ctx, i);
    i -= nv;
    /* the IN_ variables of DCCL queues, the out variables of CCL queues, in queue order */
    for (size_t k = 0; k < h->nnames; k++) {
        const kelp_acomms_qname *n = &h->names[k];
        const char *var = n->dccl_index >= 0 ? n->in_var : (n->out_var && n->out_var[0] ? n->out_var : NULL);
        if (!var) continue;
        if (i == 0) return var;
        i--;
    }
    return i < 3 ? COMMANDS[i] : NULL;
}

void kelp_acomms_handler_set_var(kelp_acomms_handler *h, const char *name, bool is_double, double dval,
                                 const char *sval)
{
    if (h->has_codec) h->codec.set_var(h->codec.ctx, name, is_double, dval, sval);
}

int kelp_acomms_handler_start(kelp_acomms_handler *h, bool link_up, kelp_time now)
{
    h->now = now;
    if (h->cfg->driver_type == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
        h->link_up = link_up;
        h->started_on_link = link_up;
        kelp_acomms_node_set_link_up(&h->node, link_up);
    }
    if (h->has_codec) h->codec.start(h->codec.ctx, now);
    int rc = kelp_acomms_node_start(&h->node, now);
    if (rc) {
        (void)kelp_fail(&h->diag, rc, node_reason(h, NULL));
        return rc;
    }
    h->started = true;
    EVENT(h, "modem_id %d, %s, %zu DCCL messages, %zu CCL queues", h->cfg->modem_id,
          h->cfg->driver_type == KELP_ACOMMS_DRIVER_NONE ? "DRIVER_NONE (in-process channel)" : "DRIVER_WHOI_MICROMODEM",
          h->has_codec ? h->codec.count(h->codec.ctx) : 0, h->cfg->nccl);
    return KELP_OK;
}

/* ------------------------------------------------------------------ mail */

/* after a parse into fresh(h) (or none when the mail is not a string) */
static bool bad_mail(kelp_acomms_handler *h, const char *what)
{
    h->count.bad_mail++;
    WARN(h, "bad %s: %s", what, reason(h, "not a string"));
    return false;
}

static void mail_ccl(kelp_acomms_handler *h, const kelp_acomms_qname *n, const kelp_var *v, kelp_time now)
{
    /* CCL: a ModemDataTransmission to queue */
    kelp_acomms_msg *m = &h->work.msg;
    (void)fresh(h);
    if (v->kind != KELP_VAR_STRING || kelp_acomms_parse_data(v->sval, v->slen, m, &h->diag) != KELP_OK) {
        (void)bad_mail(h, v->name);
        return;
    }
    m->key = n->key;
    if (!m->has_time) {
        m->has_time = true;
        m->time = now;
    }
    h->count.ccl_out++;
    h->count.out_data++;
    if (kelp_acomms_print_data(m, h->text, sizeof h->text, NULL) == KELP_OK) pub_text(h, "ACOMMS_OUTGOING_DATA");
    record_data(h, "ACOMMS_OUTGOING_DATA_LCM", m, n->name, NULL);
    int rc = kelp_acomms_node_push(&h->node, m, now);
    if (rc) {
        h->count.push_errors++;
        WARN(h, "cannot queue %s: %s", v->name, node_reason(h, kelp_err_str(rc)));
    } else {
        h->count.pushed++;
    }
}

static void mail_in_var(kelp_acomms_handler *h, const kelp_var *v)
{
    /* a DCCL message from another process: decode it */
    kelp_acomms_msg *m = &h->work.msg;
    (void)fresh(h);
    if (v->kind != KELP_VAR_STRING || kelp_acomms_parse_data(v->sval, v->slen, m, &h->diag) != KELP_OK) {
        (void)bad_mail(h, v->name);
        return;
    }
    int rc = h->codec.decode(h->codec.ctx, m->data, m->len, h->now, on_publication, h, fresh(h));
    if (rc && rc != KELP_ERR_STATE) WARN(h, "cannot decode %s: %s", v->name, reason(h, "?"));
    else if (!rc) h->count.decoded++;
}

static void mail_command(kelp_acomms_handler *h, const kelp_var *v, kelp_time now)
{
    bool is_str = v->kind == KELP_VAR_STRING;
    (void)fresh(h);
    if (strcmp(v->name, "ACOMMS_RANGE_COMMAND") == 0) {
        kelp_acomms_range_req r;
        if (!is_str || kelp_acomms_parse_range_req(v->sval, v->slen, &r, &h->diag) != KELP_OK) {
            (void)bad_mail(h, "ACOMMS_RANGE_COMMAND");
            return;
        }
        if (r.src == 0) r.src = h->cfg->modem_id;
        if (kelp_acomms_node_range(&h->node, &r, now) != KELP_OK)
            WARN(h, "ranging refused: %s", node_reason(h, "?"));
        return;
    }
    kelp_acomms_mac_update *u = &h->work.mac_update;
    if (!is_str || kelp_acomms_parse_mac_update(v->sval, v->slen, u, &h->diag) != KELP_OK) {
        (void)bad_mail(h, v->name);
        return;
    }
    int rc = kelp_acomms_node_mac_update(&h->node, u, now);
    if (rc == KELP_ERR_NOTFOUND) return; /* for another modem */
    if (rc) WARN(h, "MAC update refused: %s", node_reason(h, kelp_err_str(rc)));
    else EVENT(h, "MAC cycle updated: %zu slot(s), cycle %u s", u->nslots, kelp_mac_cycle_length(&h->node.mac));
}

void kelp_acomms_handler_mail(kelp_acomms_handler *h, const kelp_var *v, bool own, kelp_time now)
{
    h->now = now;
    if (strcmp(v->name, "ACOMMS_RANGE_COMMAND") == 0 || strcmp(v->name, "ACOMMS_MAC_CYCLE_UPDATE") == 0 ||
        strcmp(v->name, "ACOMMS_POLLER_UPDATE") == 0) {
        mail_command(h, v, now);
        return;
    }
    /* our own publications come back through the bus: they are not mail for us */
    for (size_t i = 0; i < h->nnames; i++) {
        const kelp_acomms_qname *n = &h->names[i];
        if (n->dccl_index >= 0 && n->in_var && strcmp(v->name, n->in_var) == 0 && !own) {
            mail_in_var(h, v);
            return;
        }
        if (n->dccl_index < 0 && n->out_var && n->out_var[0] && strcmp(v->name, n->out_var) == 0) {
            mail_ccl(h, n, v, now);
            return;
        }
    }
    if (!h->has_codec) return;
    bool is_str = v->kind == KELP_VAR_STRING, is_dbl = v->kind == KELP_VAR_DOUBLE;
    if (!is_str && !is_dbl) return;
    h->codec.set_var(h->codec.ctx, v->name, is_dbl, v->dval, is_str ? v->sval : NULL);
    size_t idx[MAX_IDX];
    outgoing_all(h, idx, h->codec.triggered(h->codec.ctx, v->name, idx, MAX_IDX));
}

/* ------------------------------------------------------------------ link, tick */

void kelp_acomms_handler_link_up(kelp_acomms_handler *h, kelp_time now)
{
    h->now = now;
    bool first = !h->seen_link;
    h->seen_link = true;
    h->link_up = true;
    h->driver_dead = false;
    kelp_acomms_node_set_link_up(&h->node, true);
    if (!first) h->count.reconnects++;
    EVENT(h, "modem link %s: %s", first ? "up" : "re-established", h->link_desc ? h->link_desc : "");
    /* the start-up sequence already went out if the link was open at start */
    if (!(first && h->started_on_link) && kelp_acomms_node_restart_driver(&h->node, now) != KELP_OK)
        WARN(h, "driver restart failed: %s", node_reason(h, "?"));
}

void kelp_acomms_handler_link_lost(kelp_acomms_handler *h, const char *why)
{
    h->link_up = false;
    kelp_acomms_node_set_link_up(&h->node, false);
    WARN(h, "modem link lost: %s", why ? why : "");
    EVENT(h, "modem link lost: %s", why ? why : "");
}

void kelp_acomms_handler_feed(kelp_acomms_handler *h, const uint8_t *bytes, size_t len, kelp_time now)
{
    if (kelp_acomms_node_feed(&h->node, bytes, len, now) != KELP_OK) WARN(h, "driver refused input");
}

static void publish_status(kelp_acomms_handler *h)
{
    if (!h->sink.record) return;
    kelp_acomms_status s;
    memset(&s, 0, sizeof s);
    const char *qn[KELP_ACOMMS_MAX_QUEUES];
    int32_t qs[KELP_ACOMMS_MAX_QUEUES];
    s.time = h->now;
    s.modem_id = h->cfg->modem_id;
    s.driver = h->cfg->driver_type == KELP_ACOMMS_DRIVER_NONE ? "DRIVER_NONE" : "DRIVER_WHOI_MICROMODEM";
    s.link = h->link_desc ? h->link_desc : "";
    s.link_up = h->link_up;
    kelp_mmdriver *mm = kelp_acomms_node_driver(&h->node);
    s.clock_ok = mm ? kelp_mmdriver_clock_ok(mm) : false;
    s.mac = kelp_acomms_mac_name(h->cfg->mac_type);
    s.next_slot = kelp_mac_next_slot_time(&h->node.mac);
    if (mm) {
        s.lines_in = mm->count.lines_in;
        s.lines_out = mm->count.lines_out;
        s.bad_lines = mm->count.bad_lines;
        s.retries = mm->count.retries;
        s.modem_errors = mm->count.modem_errors;
    }
    const kelp_acomms_node_counters *nc = kelp_acomms_node_get_counters(&h->node);
    s.reconnects = (uint32_t)h->count.reconnects;
    s.frames_out = nc->frames_out;
    s.frames_in = nc->frames_in;
    s.acks = (uint32_t)h->count.acks;
    s.expired = (uint32_t)h->count.expires;
    s.encoded = (uint32_t)h->count.encoded;
    s.decoded = (uint32_t)h->count.decoded;
    for (size_t i = 0; i < h->nnames; i++) {
        qn[i] = h->names[i].name;
        long sz = kelp_queue_size(&h->node.q, h->names[i].key);
        qs[i] = (int32_t)(sz < 0 ? 0 : sz);
    }
    s.nqueues = h->nnames;
    s.queue_name = qn;
    s.queue_size = qs;
    kelp_acomms_record r;
    memset(&r, 0, sizeof r);
    r.kind = KELP_ACOMMS_REC_STATUS;
    r.channel = "ACOMMS_STATUS_LCM";
    r.time = h->now;
    r.status = &s;
    pub_record(h, &r);
}

void kelp_acomms_handler_tick(kelp_acomms_handler *h, kelp_time now)
{
    h->now = now;
    int rc = kelp_acomms_node_tick(&h->node, now);
    if (rc == KELP_ERR_TIMEOUT && !h->driver_dead) {
        /* the modem stopped answering: re-open the link and start the driver again */
        h->driver_dead = true;
        if (h->cfg->driver_type == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
            if (h->sink.close_link) h->sink.close_link(h->sink.ctx);
            h->link_up = false;
            kelp_acomms_node_set_link_up(&h->node, false);
        }
    }
    if (h->has_codec) {
        size_t idx[MAX_IDX];
        outgoing_all(h, idx, h->codec.due(h->codec.ctx, now, idx, MAX_IDX));
    }
    if (now >= h->next_status) {
        publish_status(h);
        h->next_status = now + 1.0;
    }
}
