/* kelp acomms node: queue manager + TDMA MAC + Micro-Modem driver, wired as Goby 1.1's
 * pAcommsHandler connects its signals:
 *   MAC signal_initiate_transmission -> driver handle_initiate_transmission
 *   MAC signal_initiate_ranging      -> driver handle_initiate_ranging
 *   driver signal_data_request       -> queue handle_modem_data_request
 *   driver signal_receive            -> queue handle_modem_receive
 *   driver signal_ack                -> queue handle_modem_ack
 *   driver signal_all_incoming       -> MAC handle_modem_all_incoming (discovery)
 * Everything else goes out through ops.event.  Core: no allocation, no clock, no I/O. */
#include <string.h>

#include <kelp/acomms.h>

void kelp_acomms_queue_cfg_from_info(const kelp_acomms_dccl_info *info, kelp_queue_cfg *q)
{
    kelp_queue_cfg_default(q, KELP_QUEUE_DCCL, info->id);
    q->name = info->name;
    q->ack = info->ack;
    q->blackout_time = info->blackout_time > 0 ? (uint32_t)info->blackout_time : 0;
    q->max_queue = info->max_queue;
    q->newest_first = info->newest_first;
    q->value_base = info->value_base;
    q->ttl = info->ttl > 0 ? (uint32_t)info->ttl : 0;
    q->on_demand = (info->manip & KELP_ACOMMS_MANIP_ON_DEMAND) != 0;
    q->loopback = false;
    q->no_queue = (info->manip & KELP_ACOMMS_MANIP_NO_QUEUE) != 0;
}

/* the reason a lower layer recorded, or NULL */
static const char *inner_text(const kelp_diag *d)
{
    return d->code ? kelp_diag_text(d) : NULL;
}

/* record a failure of this call in n->diag (replacing an older one: the node outlives its
 * calls): the inner module's reason when it gave one, else the node's own; returns rc */
static int node_fail(kelp_acomms_node *n, int rc, const char *inner, const char *own)
{
#ifdef KELP_NO_ERRMSG
    (void)inner, (void)own;
#endif
    kelp_diag_clear(&n->diag);
    (void)kelp_fail(&n->diag, rc, inner ? inner : own);
    return rc;
}

static void emit(kelp_acomms_node *n, const kelp_acomms_event *ev)
{
    if (n->ops.event) n->ops.event(ev, n->user);
}

static void ev_init(kelp_acomms_event *ev, kelp_acomms_ev_kind kind, kelp_time now)
{
    memset(ev, 0, sizeof *ev);
    ev->kind = kind;
    ev->time = now;
}

/* ------------------------------------------------------------------ callbacks */

static void on_queue(const kelp_queue_event *qe, void *user)
{
    kelp_acomms_node *n = user;
    kelp_acomms_event ev;
    ev_init(&ev, KELP_ACOMMS_EV_QUEUE, n->now);
    ev.q = qe;
    emit(n, &ev);
}

static void on_demand(kelp_queue_key key, const kelp_queue_request *req, kelp_acomms_msg *out, void *user)
{
    kelp_acomms_node *n = user;
    if (n->ops.on_demand) n->ops.on_demand(key, req, out, n->user);
}

static void mm_write(const char *bytes, size_t len, void *user)
{
    kelp_acomms_node *n = user;
    if (n->ops.write) n->ops.write(bytes, len, n->user);
}

/* the queue answers one data request; FRAME_OUT reports it */
static int request_frame(kelp_acomms_node *n, const kelp_queue_request *req, kelp_acomms_msg *out)
{
    int rc = kelp_queue_data_request(&n->q, req, n->now, out);
    if (rc) {
        (void)node_fail(n, rc, inner_text(&n->q.diag), "acomms: data request failed");
        out->len = 0;
        return rc;
    }
    if (out->len) n->count.frames_out++;
    else n->count.blank_frames++;
    kelp_acomms_event ev;
    ev_init(&ev, KELP_ACOMMS_EV_FRAME_OUT, n->now);
    ev.req = req;
    ev.frame = out;
    emit(n, &ev);
    return KELP_OK;
}

static void mm_data_request(const kelp_mmdriver_data_request *r, kelp_mmdriver_frame *f, void *user)
{
    kelp_acomms_node *n = user;
    kelp_queue_request req;
    req.dest = r->dest;
    req.frame = r->frame;
    req.max_bytes = r->max_bytes;
    kelp_acomms_msg *m = &n->scratch;
    memset(m, 0, sizeof *m);
    f->len = 0;
    if (request_frame(n, &req, m) != KELP_OK || m->len == 0) return;
    f->src = m->src;
    f->dest = m->dest;
    f->ack_requested = m->ack_requested;
    f->len = m->len <= sizeof f->data ? m->len : sizeof f->data;
    memcpy(f->data, m->data, f->len);
}

static void mm_event(const kelp_mmdriver_event *me, void *user)
{
    kelp_acomms_node *n = user;
    kelp_acomms_event ev;
    ev_init(&ev, KELP_ACOMMS_EV_DRIVER, n->now);
    ev.mm = me;
    emit(n, &ev);
    switch (me->kind) {
    case KELP_MMDRIVER_EV_NMEA_IN:
        if (me->has_src) kelp_mac_heard(&n->mac, me->src, n->now);
        break;
    case KELP_MMDRIVER_EV_RECEIVE: {
        kelp_acomms_msg *m = &n->scratch;
        memset(m, 0, sizeof *m);
        m->src = me->src;
        m->dest = me->dest;
        m->ack_requested = me->ack_requested;
        m->has_ack = true;
        m->frame = me->frame;
        m->has_time = true;
        m->time = n->now;
        m->len = me->data_len <= sizeof m->data ? me->data_len : sizeof m->data;
        memcpy(m->data, me->data, m->len);
        n->count.frames_in++;
        (void)kelp_queue_receive(&n->q, m);
        break;
    }
    case KELP_MMDRIVER_EV_ACK:
        n->count.acks++;
        (void)kelp_queue_ack(&n->q, me->src, me->dest, me->frame);
        break;
    default:
        break;
    }
}

/* ------------------------------------------------------------------ public */

void kelp_acomms_node_cfg_default(kelp_acomms_node_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->modem_id = 1;
    cfg->driver = KELP_ACOMMS_DRIVER_NONE;
    cfg->mm.modem_id = 1;
    kelp_mac_cfg_default(&cfg->mac);
}

int kelp_acomms_node_init(kelp_acomms_node *n, const kelp_acomms_node_cfg *cfg, kelp_queue *queues, size_t cap_queues,
                          kelp_queue_entry *pool, size_t cap_pool, const kelp_acomms_node_ops *ops, void *user)
{
    if (!n || !cfg) return KELP_ERR_ARG;
    memset(n, 0, sizeof *n);
    if (cfg->modem_id < 1 || cfg->modem_id > 31) {
        return node_fail(n, KELP_ERR_ARG, NULL, "acomms: modem_id must be 1..31 (0 is broadcast)");
    }
    if (cfg->driver != KELP_ACOMMS_DRIVER_NONE && cfg->driver != KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
        return node_fail(n, KELP_ERR_ARG, NULL, "acomms: unknown driver type");
    }
    n->modem_id = cfg->modem_id;
    n->driver = cfg->driver;
    n->loopback = cfg->driver == KELP_ACOMMS_DRIVER_NONE && cfg->loopback_channel;
    n->link_up = true;
    if (ops) n->ops = *ops;
    n->user = user;
    int rc = kelp_queue_init(&n->q, cfg->modem_id, queues, cap_queues, pool, cap_pool, on_queue, on_demand, n);
    if (rc) {
        return node_fail(n, rc, inner_text(&n->q.diag), "acomms: queue storage");
    }
    if (n->driver == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
        kelp_mmdriver_cfg mc = cfg->mm;
        mc.modem_id = cfg->modem_id;
        kelp_mmdriver_ops mo = { mm_write, mm_event, mm_data_request };
        rc = kelp_mmdriver_init(&n->mm, &mc, &mo, n);
        if (rc) {
            return node_fail(n, rc, NULL, "acomms: bad Micro-Modem driver configuration");
        }
    }
    /* the MAC starts in kelp_acomms_node_start; keep its configuration by initialising now
     * with the same values (the slot array is copied) */
    kelp_mac_cfg mac = cfg->mac;
    mac.modem_id = cfg->modem_id;
    rc = kelp_mac_init(&n->mac, &mac, 0);
    if (rc) {
        return node_fail(n, rc, inner_text(&n->mac.diag), "acomms: bad MAC configuration");
    }
    return KELP_OK;
}

int kelp_acomms_node_add_queue(kelp_acomms_node *n, const kelp_queue_cfg *cfg, kelp_time now)
{
    if (!n || !cfg) return KELP_ERR_ARG;
    n->now = now;
    int rc = kelp_queue_add(&n->q, cfg, now);
    if (rc) (void)node_fail(n, rc, inner_text(&n->q.diag), "acomms: cannot add queue");
    return rc;
}

int kelp_acomms_node_start(kelp_acomms_node *n, kelp_time now)
{
    if (!n) return KELP_ERR_ARG;
    n->now = now;
    /* re-align the cycle to the start time (kelp_mac_init at 0 aligned it to 1970) */
    kelp_mac_slot *slots = n->work.slots;
    kelp_mac_cfg mc;
    kelp_mac_cfg_default(&mc);
    mc.type = n->mac.type;
    mc.modem_id = n->modem_id;
    mc.rate = n->mac.rate;
    mc.slot_seconds = n->mac.slot_seconds;
    mc.expire_cycles = n->mac.expire_cycles;
    if (mc.type == KELP_MAC_FIXED_DECENTRALIZED || mc.type == KELP_MAC_POLLED) {
        size_t ns = 0;
        for (size_t i = 0; i < n->mac.n && i < KELP_MAX_MAC_SLOTS; i++) slots[ns++] = n->mac.slot[i];
        mc.slots = slots;
        mc.nslots = ns;
    }
    int rc = kelp_mac_init(&n->mac, &mc, now);
    if (rc) {
        return node_fail(n, rc, inner_text(&n->mac.diag), "acomms: MAC start failed");
    }
    if (n->driver == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
        rc = kelp_mmdriver_start(&n->mm, now);
        if (rc) {
            return node_fail(n, rc, inner_text(&n->mm.diag), "acomms: driver start failed");
        }
    }
    n->started = true;
    return KELP_OK;
}

int kelp_acomms_node_restart_driver(kelp_acomms_node *n, kelp_time now)
{
    if (!n) return KELP_ERR_ARG;
    if (n->driver != KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) return KELP_OK;
    n->now = now;
    n->count.driver_restarts++;
    int rc = kelp_mmdriver_start(&n->mm, now);
    if (rc) (void)node_fail(n, rc, inner_text(&n->mm.diag), "acomms: driver restart failed");
    return rc;
}

/* DRIVER_NONE: a transmission handled inside the node (as the driver would request frames) */
static int transmit_internal(kelp_acomms_node *n, int src, int dest, unsigned rate, kelp_time now)
{
    if (src != n->modem_id) return KELP_OK; /* third-party cycles need a modem */
    unsigned nframes = kelp_mmdriver_packet_frames[rate];
    kelp_acomms_msg *frames = n->work.frames;
    unsigned got = 0;
    for (unsigned i = 0; i < nframes && i < KELP_MAX_MM_FRAMES; i++) {
        kelp_queue_request req;
        req.dest = dest;
        req.frame = i;
        req.max_bytes = kelp_mmdriver_packet_size[rate];
        kelp_acomms_msg *m = &frames[got];
        memset(m, 0, sizeof *m);
        int rc = request_frame(n, &req, m);
        if (rc) return rc;
        if (m->len == 0) break; /* as the Micro-Modem driver: stop at the first empty frame */
        got++;
    }
    if (!n->loopback) return KELP_OK;
    for (unsigned i = 0; i < got; i++) {
        kelp_acomms_msg *m = &frames[i];
        kelp_acomms_event ev;
        ev_init(&ev, KELP_ACOMMS_EV_LOOPBACK, now);
        ev.frame = m;
        emit(n, &ev);
        /* everyone hears a frame: the queue keeps the pieces for us (broadcast pieces, also
         * those stitched into a frame addressed to another modem) */
        /* received as sent, stamped with the time (the frame is not used again after) */
        m->has_time = true;
        m->time = now;
        if (kelp_queue_receive(&n->q, m) > 0) n->count.loopback_delivered++;
        if (m->ack_requested && m->dest != KELP_ACOMMS_BROADCAST) {
            n->count.loopback_acked++;
            (void)kelp_queue_ack(&n->q, m->dest, n->modem_id, m->frame);
        }
    }
    return KELP_OK;
}

int kelp_acomms_node_transmit(kelp_acomms_node *n, int src, int dest, unsigned rate, kelp_time now)
{
    if (!n) return KELP_ERR_ARG;
    if (rate > 5) {
        return node_fail(n, KELP_ERR_RANGE, NULL, "acomms: rate must be 0..5");
    }
    n->now = now;
    n->count.transmissions++;
    if (n->driver == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
        int rc = kelp_mmdriver_initiate_transmission(&n->mm, src, dest, rate, now);
        if (rc) return node_fail(n, rc, inner_text(&n->mm.diag), "acomms: cannot initiate transmission");
    }
    return transmit_internal(n, src, dest, rate, now);
}

int kelp_acomms_node_range(kelp_acomms_node *n, const kelp_acomms_range_req *r, kelp_time now)
{
    if (!n || !r) return KELP_ERR_ARG;
    n->now = now;
    if (n->driver != KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
        return node_fail(n, KELP_ERR_STATE, NULL, "acomms: ranging needs a modem driver");
    }
    n->count.ranging++;
    int rc = kelp_mmdriver_initiate_ranging(&n->mm, r->src, r->dest, r->type, r->max_range, r->enable_beacons, now);
    if (rc) (void)node_fail(n, rc, inner_text(&n->mm.diag), "acomms: cannot start ranging");
    return rc;
}

int kelp_acomms_node_mac_update(kelp_acomms_node *n, const kelp_acomms_mac_update *u, kelp_time now)
{
    if (!n || !u) return KELP_ERR_ARG;
    n->now = now;
    int rc = kelp_mac_update(&n->mac, u->dest, u->type, u->slot, u->nslots, now);
    if (rc && rc != KELP_ERR_NOTFOUND) (void)node_fail(n, rc, inner_text(&n->mac.diag), "acomms: MAC update refused");
    return rc;
}

void kelp_acomms_node_set_link_up(kelp_acomms_node *n, bool up)
{
    if (n) n->link_up = up;
}

/* can the driver start a cycle now? */
static bool driver_usable(const kelp_acomms_node *n)
{
    if (n->driver != KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) return true;
    return n->link_up && n->mm.started && !n->mm.dead;
}

int kelp_acomms_node_tick(kelp_acomms_node *n, kelp_time now)
{
    if (!n) return KELP_ERR_ARG;
    if (!n->started) return KELP_ERR_STATE;
    n->now = now;
    kelp_queue_do_work(&n->q, now);
    /* every slot that has come (one per call of kelp_mac_tick) */
    for (int guard = 0; guard < 4 * KELP_MAX_MAC_SLOTS; guard++) {
        kelp_mac_action act;
        int rc = kelp_mac_tick(&n->mac, now, &act);
        if (rc == KELP_ERR_EMPTY) break;
        if (rc) break;
        if (act.kind == KELP_MAC_ACT_NONE) continue;
        n->count.slots++;
        kelp_acomms_event ev;
        ev_init(&ev, KELP_ACOMMS_EV_SLOT, now);
        ev.slot = &act;
        emit(n, &ev);
        if (!driver_usable(n)) {
            n->count.slots_skipped++;
            continue;
        }
        if (act.kind == KELP_MAC_ACT_TRANSMIT) {
            if (kelp_acomms_node_transmit(n, act.src, act.dest, act.rate, now) != KELP_OK) {
                /* reported through n->diag; the cycle goes on */
            }
        } else if (act.kind == KELP_MAC_ACT_RANGING && n->driver == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
            kelp_acomms_range_req r;
            r.src = act.src;
            r.dest = act.dest;
            r.type = act.ranging;
            r.max_range = 1000;
            r.enable_beacons = 15;
            if (kelp_acomms_node_range(n, &r, now) != KELP_OK) {
                /* reported through n->diag */
            }
        }
    }
    if (n->driver == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM && n->link_up) {
        int rc = kelp_mmdriver_tick(&n->mm, now);
        if (rc) {
            return node_fail(n, rc, inner_text(&n->mm.diag), "acomms: modem not responding");
        }
    }
    return KELP_OK;
}

int kelp_acomms_node_feed(kelp_acomms_node *n, const uint8_t *bytes, size_t len, kelp_time now)
{
    if (!n) return KELP_ERR_ARG;
    if (n->driver != KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) return KELP_OK;
    n->now = now;
    return kelp_mmdriver_feed(&n->mm, bytes, len, now);
}

int kelp_acomms_node_push(kelp_acomms_node *n, const kelp_acomms_msg *msg, kelp_time now)
{
    if (!n || !msg) return KELP_ERR_ARG;
    n->now = now;
    int rc = kelp_queue_push(&n->q, msg, now);
    if (rc) (void)node_fail(n, rc, inner_text(&n->q.diag), "acomms: push refused");
    return rc;
}

int kelp_acomms_node_data_request(kelp_acomms_node *n, const kelp_queue_request *req, kelp_time now,
                                  kelp_acomms_msg *out)
{
    if (!n || !req || !out) return KELP_ERR_ARG;
    n->now = now;
    memset(out, 0, sizeof *out);
    return request_frame(n, req, out);
}

int kelp_acomms_node_ack(kelp_acomms_node *n, int src, int dest, uint32_t frame, kelp_time now)
{
    if (!n) return KELP_ERR_ARG;
    n->now = now;
    n->count.acks++;
    return kelp_queue_ack(&n->q, src, dest, frame);
}

int kelp_acomms_node_receive(kelp_acomms_node *n, const kelp_acomms_msg *frame, kelp_time now)
{
    if (!n || !frame) return KELP_ERR_ARG;
    n->now = now;
    n->count.frames_in++;
    kelp_mac_heard(&n->mac, frame->src, now);
    return kelp_queue_receive(&n->q, frame);
}

void kelp_acomms_node_heard(kelp_acomms_node *n, int src, kelp_time now)
{
    if (!n) return;
    n->now = now;
    kelp_mac_heard(&n->mac, src, now);
}

kelp_queue_mgr *kelp_acomms_node_queue(kelp_acomms_node *n)
{
    return n ? &n->q : NULL;
}

kelp_mac *kelp_acomms_node_mac(kelp_acomms_node *n)
{
    return n ? &n->mac : NULL;
}

kelp_mmdriver *kelp_acomms_node_driver(kelp_acomms_node *n)
{
    return n && n->driver == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM ? &n->mm : NULL;
}

const kelp_acomms_node_counters *kelp_acomms_node_get_counters(const kelp_acomms_node *n)
{
    return n ? &n->count : NULL;
}
