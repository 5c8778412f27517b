/* kelp: Goby 1.1 priority queue (libqueue), re-implemented from the behaviour described in
 * goby-wire.md section 8 (queue.cpp / queue_manager.cpp).  Core: no allocation, no I/O. */
#include <kelp/queue.h>
#include <kelp/util.h>

#include <math.h>
#include <stddef.h>
#include <string.h>

#define US_PER_S 1000000LL
#define ON_DEMAND_SKEW_US (1 * US_PER_S)

/* Times are compared in whole microseconds (as Goby's boost::posix_time): converted here. */
static int64_t q_us(kelp_time t)
{
    return (int64_t)llround(t * 1e6);
}

static int key_cmp(kelp_queue_key a, kelp_queue_key b)
{
    /* map order: id first, then DCCL (1) before CCL (2) */
    if (a.id != b.id) return a.id < b.id ? -1 : 1;
    if (a.type != b.type) return a.type < b.type ? -1 : 1;
    return 0;
}

static kelp_queue *find_q(const kelp_queue_mgr *m, kelp_queue_key key)
{
    for (size_t i = 0; i < m->nq; i++)
        if (key_cmp(m->q[i].cfg.key, key) == 0) return &m->q[i];
    return NULL;
}

static void emit(kelp_queue_mgr *m, kelp_queue_event_kind kind, kelp_queue_key key, const kelp_acomms_msg *msg,
                 uint32_t size, uint32_t frame)
{
    if (!m->event) return;
    kelp_queue_event ev;
    ev.kind = kind;
    ev.key = key;
    ev.msg = msg;
    ev.size = size;
    ev.frame = frame;
    m->event(&ev, m->user);
}

static void qsize(kelp_queue_mgr *m, const kelp_queue *q)
{
    emit(m, KELP_QUEUE_EV_QSIZE, q->cfg.key, NULL, q->size, 0);
}

void kelp_queue_cfg_default(kelp_queue_cfg *cfg, uint8_t type, uint32_t id)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->key.type = type;
    cfg->key.id = id;
    cfg->ack = true;
    cfg->blackout_time = 0;
    cfg->max_queue = 0;
    cfg->newest_first = true;
    cfg->value_base = 1.0;
    cfg->ttl = 1800;
}

int kelp_queue_init(kelp_queue_mgr *m, int modem_id, kelp_queue *queues, size_t cap_queues, kelp_queue_entry *pool,
                    size_t cap_pool, kelp_queue_event_fn event, kelp_queue_on_demand_fn on_demand, void *user)
{
    if (!m || (!queues && cap_queues) || (!pool && cap_pool)) return KELP_ERR_ARG;
    if (cap_queues > UINT16_MAX || cap_pool > (size_t)INT32_MAX) return KELP_ERR_RANGE;
    memset(m, 0, sizeof *m);
    m->modem_id = modem_id;
    m->q = queues;
    m->cap_q = cap_queues;
    m->pool = pool;
    m->cap_pool = cap_pool;
    for (size_t i = 0; i < cap_pool; i++) pool[i].used = false;
    m->event = event;
    m->on_demand = on_demand;
    m->user = user;
    m->packet_ack = false;
    m->packet_dest = KELP_ACOMMS_BROADCAST;
    return KELP_OK;
}

/* The time step rule (docs/ARCHITECTURE.md): after the clock steps back, every stored time moves
 * back as far, so a blackout or a ttl keeps what remained of it instead of lasting the step too
 * (a send time an hour ahead would black a queue out for an hour).  A step forward is elapsed
 * time: blackouts end, old messages expire, one frame per request as always. */
static void clock_step(kelp_queue_mgr *m, kelp_time now)
{
    double back = kelp_util_clock_back(&m->clock, now);
    if (back <= 0.0) return;
    m->count.clock_steps++;
    for (size_t k = 0; k < m->nq; k++) {
        kelp_queue *q = &m->q[k];
        q->last_send -= back;
        for (int32_t i = q->head; i >= 0; i = m->pool[i].next)
            if (m->pool[i].msg.has_time) m->pool[i].msg.time -= back;
    }
}

int kelp_queue_add(kelp_queue_mgr *m, const kelp_queue_cfg *cfg, kelp_time now)
{
    if (!m || !cfg || !kelp_util_time_ok(now)) return KELP_ERR_ARG;
    clock_step(m, now);
    if (cfg->key.type != KELP_QUEUE_DCCL && cfg->key.type != KELP_QUEUE_CCL) return KELP_ERR_ARG;
    if (find_q(m, cfg->key)) return kelp_fail(&m->diag, KELP_ERR_EXISTS, "queue: duplicate key");
    if (cfg->key.type == KELP_QUEUE_DCCL &&
        (cfg->key.id < KELP_QUEUE_DCCL_MIN_ID || cfg->key.id > KELP_QUEUE_DCCL_MAX_ID)) {
        return kelp_fail(&m->diag, KELP_ERR_RANGE, "queue: DCCL id out of bounds (1..512)");
    }
    if (cfg->key.type == KELP_QUEUE_CCL && cfg->key.id > 255) return KELP_ERR_RANGE;
    if (m->nq >= m->cap_q) return kelp_fail(&m->diag, KELP_ERR_NOSPACE, "queue: no room for another queue");
    /* sorted insert; wait records hold queue indices, so move them along */
    size_t pos = 0;
    while (pos < m->nq && key_cmp(m->q[pos].cfg.key, cfg->key) < 0) pos++;
    memmove(&m->q[pos + 1], &m->q[pos], (m->nq - pos) * sizeof m->q[0]);
    for (size_t i = 0; i < m->nwait; i++)
        if (m->wait[i].q >= pos) m->wait[i].q++;
    kelp_queue *q = &m->q[pos];
    memset(q, 0, sizeof *q);
    q->cfg = *cfg;
    q->last_send = now;
    q->head = q->tail = -1;
    m->nq++;
    qsize(m, q);
    return KELP_OK;
}

/* ------------------------------------------------------------------ list helpers */

static void unlink_entry(kelp_queue_mgr *m, kelp_queue *q, int32_t i)
{
    kelp_queue_entry *e = &m->pool[i];
    if (e->prev >= 0) m->pool[e->prev].next = e->next;
    else q->head = e->next;
    if (e->next >= 0) m->pool[e->next].prev = e->prev;
    else q->tail = e->prev;
    if (e->ack_frame >= 0 && q->n_waiting) q->n_waiting--;
    e->used = false;
    q->size--;
}

/* Queue::next_message_it: newest (back) or oldest (front), skipping messages awaiting an ack */
static int32_t next_message(const kelp_queue_mgr *m, const kelp_queue *q)
{
    int32_t i = q->cfg.newest_first ? q->tail : q->head;
    while (i >= 0 && m->pool[i].ack_frame >= 0) i = q->cfg.newest_first ? m->pool[i].prev : m->pool[i].next;
    return i;
}

static int queue_push(kelp_queue_mgr *m, kelp_queue *q, const kelp_acomms_msg *msg)
{
    if (msg->len == 0) return kelp_fail(&m->diag, KELP_ERR_ARG, "queue: empty message");
    if (msg->len > KELP_MAX_ACOMMS_FRAME) return KELP_ERR_NOSPACE;
    if (q->cfg.key.type == KELP_QUEUE_CCL && msg->data[0] != (uint8_t)q->cfg.key.id) {
        return kelp_fail(&m->diag, KELP_ERR_ARG, "queue: CCL message without the queue's CCL id byte");
    }
    if (q->cfg.key.type == KELP_QUEUE_DCCL && msg->len < KELP_DCCL_HEADER_BYTES) {
        return kelp_fail(&m->diag, KELP_ERR_ARG, "queue: DCCL message shorter than its header");
    }
    int32_t slot = -1;
    for (size_t i = 0; i < m->cap_pool; i++)
        if (!m->pool[i].used) { slot = (int32_t)i; break; }
    if (slot < 0) return kelp_fail(&m->diag, KELP_ERR_NOSPACE, "queue: message pool full");
    kelp_queue_entry *e = &m->pool[slot];
    e->msg = *msg;
    e->msg.key = q->cfg.key;
    if (!msg->has_ack) {
        e->msg.ack_requested = q->cfg.ack;
        e->msg.has_ack = true;
    }
    e->msg.src = m->modem_id;
    e->used = true;
    e->ack_frame = -1;
    e->ack_seq = 0;
    e->next = -1;
    e->prev = q->tail;
    if (q->tail >= 0) m->pool[q->tail].next = slot;
    else q->head = slot;
    q->tail = slot;
    q->size++;
    if (q->cfg.max_queue && q->size > q->cfg.max_queue) {
        /* newest_first drops the oldest, FIFO drops the newest (the one just pushed) */
        int32_t drop = q->cfg.newest_first ? q->head : q->tail;
        unlink_entry(m, q, drop);
        m->count.dropped_overflow++;
    }
    return KELP_OK;
}

int kelp_queue_push(kelp_queue_mgr *m, const kelp_acomms_msg *msg, kelp_time now)
{
    (void)now;
    if (!m || !msg) return KELP_ERR_ARG;
    if (msg->dest == m->modem_id) {
        /* addressed to us: loop back, never queued */
        (void)kelp_queue_receive(m, msg);
        return KELP_OK;
    }
    kelp_queue *q = find_q(m, msg->key);
    if (!q) return kelp_fail(&m->diag, KELP_ERR_NOTFOUND, "queue: no queue for key");
    int rc = KELP_OK;
    bool dccl = q->cfg.key.type == KELP_QUEUE_DCCL;
    if (!(dccl && q->cfg.no_queue)) {
        rc = queue_push(m, q, msg);
        if (rc == KELP_OK) m->count.pushed++;
        else m->count.rejected++;
        qsize(m, q);
    }
    if (dccl && q->cfg.loopback) (void)kelp_queue_receive(m, msg);
    return rc;
}

/* ------------------------------------------------------------------ contest */

static double priority_of(const kelp_queue *q, kelp_time now)
{
    double dt = (double)(q_us(now) - q_us(q->last_send)) / 1e6;
    return dt / (double)q->cfg.ttl * q->cfg.value_base;
}

int kelp_queue_priority(const kelp_queue_mgr *m, kelp_queue_key key, kelp_time now, double *prio)
{
    if (!m || !prio || !kelp_util_time_ok(now)) return KELP_ERR_ARG;
    const kelp_queue *q = find_q(m, key);
    if (!q) return KELP_ERR_NOTFOUND;
    *prio = priority_of(q, now);
    return KELP_OK;
}

/* Queue::priority_values: may this queue compete for the frame built so far? */
static bool priority_values(const kelp_queue_mgr *m, const kelp_queue *q, const kelp_queue_request *req,
                            const kelp_acomms_msg *sofar, kelp_time now, double *prio)
{
    *prio = priority_of(q, now);
    if (q->size <= q->n_waiting) return false;
    int32_t ni = next_message(m, q);
    if (ni < 0) return false;
    const kelp_acomms_msg *next = &m->pool[ni].msg;
    if (q_us(q->last_send) + (int64_t)q->cfg.blackout_time * US_PER_S > q_us(now)) return false; /* blackout */
    if (next->len > (size_t)req->max_bytes - sofar->len) return false;                       /* too big */
    if (sofar->dest != KELP_ACOMMS_QUERY_DEST && next->dest != KELP_ACOMMS_BROADCAST && sofar->dest != next->dest)
        return false;                                                                           /* wrong dest */
    if (sofar->has_ack && !sofar->ack_requested && next->ack_requested && sofar->dest != KELP_ACOMMS_BROADCAST)
        return false;                                                                           /* wrong ack */
    return true;
}

static kelp_queue *find_next_sender(kelp_queue_mgr *m, const kelp_queue_request *req, const kelp_acomms_msg *sofar,
                                    bool first_user_frame, kelp_time now)
{
    kelp_queue *win = NULL;
    double win_p = 0.0;
    kelp_time win_last = 0;
    for (size_t i = 0; i < m->nq; i++) {
        kelp_queue *q = &m->q[i];
        if (q->cfg.key.type == KELP_QUEUE_DCCL && q->cfg.on_demand && m->on_demand) {
            bool stale = q->size == 0;
            if (!stale && m->pool[q->tail].msg.has_time)
                stale = q_us(m->pool[q->tail].msg.time) + ON_DEMAND_SKEW_US < q_us(now);
            if (stale) {
                kelp_acomms_msg *fresh = &m->fresh;
                memset(fresh, 0, sizeof *fresh);
                fresh->key = q->cfg.key;
                m->on_demand(q->cfg.key, req, fresh, m->user);
                fresh->key = q->cfg.key;
                if (kelp_queue_push(m, fresh, now) != KELP_OK) (void)kelp_fail(&m->diag, KELP_ERR_STATE, "queue: ON_DEMAND message rejected"); /* recorded; the contest goes on */
                q = &m->q[i];
            }
        }
        double p;
        if (!priority_values(m, q, req, sofar, now, &p)) continue;
        if ((!win || p > win_p || (p == win_p && q_us(q->last_send) < q_us(win_last))) &&
            !(q->cfg.key.type == KELP_QUEUE_CCL && !first_user_frame)) {
            win = q;
            win_p = p;
            win_last = q->last_send;
        }
    }
    return win;
}

/* Queue::give_data: hand out the next message (broadcast never requests an ack) */
static int32_t give_data(kelp_queue_mgr *m, kelp_queue *q, uint32_t frame, kelp_time now)
{
    int32_t i = next_message(m, q);
    kelp_queue_entry *e = &m->pool[i];
    bool ack = e->msg.ack_requested;
    if (e->msg.dest == KELP_ACOMMS_BROADCAST && ack) ack = false;
    e->msg.ack_requested = ack;
    if (ack) {
        e->ack_frame = (int32_t)frame;
        e->ack_seq = ++m->ack_seq;
        q->n_waiting++;
    }
    q->last_send = now;
    return i;
}

/* Queue::pop_message: pops the back (newest_first) or front only if that one has no ack */
static bool pop_message(kelp_queue_mgr *m, kelp_queue *q)
{
    int32_t i = q->cfg.newest_first ? q->tail : q->head;
    if (i < 0 || m->pool[i].msg.ack_requested) return false;
    unlink_entry(m, q, i);
    return true;
}

static void clear_packet(kelp_queue_mgr *m)
{
    for (size_t w = 0; w < m->nwait; w++) {
        kelp_queue *q = &m->q[m->wait[w].q];
        for (int32_t i = q->head; i >= 0; i = m->pool[i].next) m->pool[i].ack_frame = -1;
        q->n_waiting = 0;
    }
    m->nwait = 0;
    m->packet_ack = false;
    m->packet_dest = KELP_ACOMMS_BROADCAST;
}

static int stitch(kelp_queue_mgr *m, const kelp_queue_request *req, kelp_acomms_msg *out, kelp_queue *win,
                  kelp_time now)
{
    for (;;) {
        int32_t gi = give_data(m, win, req->frame, now);
        kelp_acomms_msg *next = &m->next;
        *next = m->pool[gi].msg;
        if (next->ack_requested) {
            if (m->nwait < KELP_MAX_QUEUE_ACK_WAIT) {
                m->wait[m->nwait].frame = req->frame;
                m->wait[m->nwait].q = (uint16_t)(win - m->q);
                m->nwait++;
            } else {
                /* recorded; the message is sent without waiting for its ack */
                (void)kelp_fail(&m->diag, KELP_ERR_NOSPACE, "queue: too many messages waiting for acks (KELP_MAX_QUEUE_ACK_WAIT)");
            }
        } else {
            (void)pop_message(m, win);
            qsize(m, win); /* Goby notifies after pop_message whatever it returned */
        }
        if (!m->packet_ack) m->packet_ack = next->ack_requested;
        if (req->frame == 0) {
            if (out->dest == KELP_ACOMMS_QUERY_DEST) out->dest = next->dest;
            if (m->packet_dest == KELP_ACOMMS_BROADCAST) m->packet_dest = out->dest;
        } else {
            out->dest = m->packet_dest;
        }
        if (win->cfg.key.type != KELP_QUEUE_DCCL) {
            /* CCL: the frame is the message itself */
            uint32_t frame = out->frame;
            *out = *next;
            out->frame = frame;
            return KELP_OK;
        }
        /* DCCL piece: header bytes 1..5, body length byte, body (the CCL id byte is added once) */
        size_t start = out->len;
        if (start + next->len > KELP_MAX_ACOMMS_FRAME) return KELP_ERR_NOSPACE;
        memcpy(out->data + start, next->data + 1, KELP_DCCL_HEADER_BYTES - 1);
        out->data[start + 5] = (uint8_t)(next->len - KELP_DCCL_HEADER_BYTES);
        memcpy(out->data + start + 6, next->data + KELP_DCCL_HEADER_BYTES, next->len - KELP_DCCL_HEADER_BYTES);
        out->len = start + next->len;

        kelp_queue *more = NULL;
        if ((size_t)req->max_bytes - out->len > KELP_DCCL_HEADER_BYTES)
            more = find_next_sender(m, req, out, false, now);
        /* replace_header: multimessage unless last, broadcast if this piece's dest is 0 */
        uint8_t *b5 = &out->data[start + 4];
        *b5 = (uint8_t)(*b5 & ~(KELP_DCCL_MULTIMESSAGE_MASK | KELP_DCCL_BROADCAST_MASK));
        if (more) *b5 |= KELP_DCCL_MULTIMESSAGE_MASK;
        if (next->dest == KELP_ACOMMS_BROADCAST) *b5 |= KELP_DCCL_BROADCAST_MASK;
        if (more) { win = more; continue; }
        /* last piece: prepend 0x20, drop this piece's length byte */
        size_t szpos = start + 5;
        memmove(out->data + szpos, out->data + szpos + 1, out->len - szpos - 1);
        memmove(out->data + 1, out->data, out->len - 1);
        out->data[0] = KELP_DCCL_CCL_ID;
        out->ack_requested = m->packet_ack;
        out->has_ack = true;
        return KELP_OK;
    }
}

int kelp_queue_data_request(kelp_queue_mgr *m, const kelp_queue_request *req_in, kelp_time now, kelp_acomms_msg *out)
{
    if (!m || !req_in || !out || !kelp_util_time_ok(now)) return KELP_ERR_ARG;
    clock_step(m, now);
    kelp_queue_request req = *req_in;
    if (req.max_bytes == 0 || req.max_bytes > KELP_MAX_ACOMMS_FRAME) req.max_bytes = KELP_MAX_ACOMMS_FRAME;
    memset(out, 0, sizeof *out);
    out->src = m->modem_id;
    out->frame = req.frame;
    if (req.frame == 0) {
        clear_packet(m);
        out->dest = req.dest;
    } else {
        if (m->packet_ack) {
            out->ack_requested = true;
            out->has_ack = true;
        }
        out->dest = m->packet_dest;
    }
    kelp_queue *win = find_next_sender(m, &req, out, true, now);
    if (!win) {
        out->ack_requested = m->packet_ack;
        out->has_ack = true;
        out->dest = m->packet_dest;
        return KELP_OK;
    }
    return stitch(m, &req, out, win, now);
}

int kelp_queue_ack(kelp_queue_mgr *m, int src, int dest, uint32_t frame)
{
    (void)src;
    if (!m || dest != m->modem_id) return 0;
    int n = 0;
    size_t w = 0;
    while (w < m->nwait) {
        if (m->wait[w].frame != frame) { w++; continue; }
        kelp_queue *q = &m->q[m->wait[w].q];
        /* Queue::pop_message_ack: the earliest message of this queue waiting for `frame` */
        int32_t best = -1;
        for (int32_t i = q->head; i >= 0; i = m->pool[i].next)
            if (m->pool[i].ack_frame == (int32_t)frame && (best < 0 || m->pool[i].ack_seq < m->pool[best].ack_seq))
                best = i;
        if (best >= 0) {
            kelp_acomms_msg orig = m->pool[best].msg;
            unlink_entry(m, q, best);
            qsize(m, q);
            m->count.acked++;
            emit(m, KELP_QUEUE_EV_ACK, q->cfg.key, &orig, q->size, frame);
            n++;
        }
        memmove(&m->wait[w], &m->wait[w + 1], (m->nwait - w - 1) * sizeof m->wait[0]);
        m->nwait--;
    }
    return n;
}

void kelp_queue_do_work(kelp_queue_mgr *m, kelp_time now)
{
    if (!m || !kelp_util_time_ok(now)) return;
    clock_step(m, now);
    for (size_t k = 0; k < m->nq; k++) {
        kelp_queue *q = &m->q[k];
        while (q->head >= 0) {
            kelp_queue_entry *e = &m->pool[q->head];
            if (!e->msg.has_time || !(q_us(e->msg.time) + (int64_t)q->cfg.ttl * US_PER_S < q_us(now))) break;
            kelp_acomms_msg orig = e->msg;
            unlink_entry(m, q, q->head);
            m->count.expired++;
            emit(m, KELP_QUEUE_EV_EXPIRE, q->cfg.key, &orig, q->size, 0);
        }
    }
}

int kelp_queue_flush(kelp_queue_mgr *m, kelp_queue_key key)
{
    if (!m) return KELP_ERR_ARG;
    kelp_queue *q = find_q(m, key);
    if (!q) return KELP_ERR_NOTFOUND;
    while (q->head >= 0) unlink_entry(m, q, q->head);
    q->n_waiting = 0;
    qsize(m, q);
    return KELP_OK;
}

long kelp_queue_size(const kelp_queue_mgr *m, kelp_queue_key key)
{
    const kelp_queue *q = m ? find_q(m, key) : NULL;
    return q ? (long)q->size : -1;
}

/* ------------------------------------------------------------------ receive */

static int unstitch_into(const uint8_t *d, size_t n, kelp_unstitch_fn fn, void *user, uint8_t *piece);

struct rx_ctx {
    kelp_queue_mgr *m;
    const kelp_acomms_msg *frame;
    int n;
};

static void publish_piece(const uint8_t *piece, size_t len, unsigned id, bool broadcast, void *user)
{
    struct rx_ctx *c = user;
    kelp_queue_mgr *m = c->m;
    int dest = broadcast ? KELP_ACOMMS_BROADCAST : c->frame->dest;
    if (dest != KELP_ACOMMS_BROADCAST && dest != m->modem_id) { m->count.rx_not_for_us++; return; }
    kelp_queue_key key = { KELP_QUEUE_DCCL, id };
    if (!find_q(m, key)) { m->count.rx_no_queue++; return; }
    kelp_acomms_msg *msg = &m->rx; /* the piece is already in msg->data (unstitch_into) */
    memcpy(msg, c->frame, offsetof(kelp_acomms_msg, data));
    msg->dest = dest;
    msg->key = key;
    if (piece != msg->data) memcpy(msg->data, piece, len);
    msg->len = len;
    m->count.rx_pieces++;
    c->n++;
    emit(m, KELP_QUEUE_EV_RECEIVE, key, msg, 0, msg->frame);
}

int kelp_queue_receive(kelp_queue_mgr *m, const kelp_acomms_msg *frame)
{
    if (!m || !frame) return 0;
    m->count.rx_frames++;
    if (frame->len == 0) { m->count.rx_malformed++; return 0; }
    size_t n = frame->len > KELP_MAX_ACOMMS_FRAME ? KELP_MAX_ACOMMS_FRAME : frame->len;
    if (frame->data[0] == KELP_DCCL_CCL_ID) {
        /* the 6-byte header rule applies to DCCL only; a CCL frame may be shorter */
        if (n < KELP_DCCL_HEADER_BYTES) { m->count.rx_malformed++; return 0; }
        struct rx_ctx c = { m, frame, 0 };
        if (unstitch_into(frame->data, n, publish_piece, &c, m->rx.data) < 0) m->count.rx_malformed++;
        return c.n;
    }
    kelp_queue_key key = { KELP_QUEUE_CCL, frame->data[0] };
    if (!find_q(m, key)) { m->count.rx_no_queue++; return 0; }
    kelp_acomms_msg *msg = &m->rx;
    if (msg != frame) *msg = *frame;
    msg->key = key;
    msg->len = n;
    m->count.rx_pieces++;
    emit(m, KELP_QUEUE_EV_RECEIVE_CCL, key, msg, 0, msg->frame);
    return 1;
}

/* ------------------------------------------------------------------ DCCL header */

static uint64_t be48(const uint8_t *d)
{
    uint64_t v = 0;
    for (int i = 0; i < 6; i++) v = (v << 8) | d[i];
    return v;
}

static unsigned field48(uint64_t v, unsigned off, unsigned width)
{
    return (unsigned)((v >> (48 - off - width)) & ((1u << width) - 1u));
}

int kelp_queue_header_read(const uint8_t *d, size_t n, kelp_queue_header *h)
{
    if (!d || !h) return KELP_ERR_ARG;
    if (n < KELP_DCCL_HEADER_BYTES) return KELP_ERR_TRUNCATED;
    uint64_t v = be48(d);
    h->ccl_id = field48(v, 0, 8);
    h->id = field48(v, 8, 9);
    h->time_of_day = field48(v, 17, 17);
    h->src = field48(v, 34, 5);
    h->dest = field48(v, 39, 5);
    h->multimessage = field48(v, 44, 1) != 0;
    h->broadcast = field48(v, 45, 1) != 0;
    h->unused = field48(v, 46, 2);
    return KELP_OK;
}

void kelp_queue_header_write(const kelp_queue_header *h, uint8_t out[KELP_DCCL_HEADER_BYTES])
{
    uint64_t v = h->ccl_id & 0xffu;
    v = (v << 9) | (h->id & 0x1ffu);
    v = (v << 17) | (h->time_of_day & 0x1ffffu);
    v = (v << 5) | (h->src & 0x1fu);
    v = (v << 5) | (h->dest & 0x1fu);
    v = (v << 1) | (h->multimessage ? 1u : 0u);
    v = (v << 1) | (h->broadcast ? 1u : 0u);
    v = (v << 2) | (h->unused & 3u);
    for (int i = 5; i >= 0; i--) { out[i] = (uint8_t)(v & 0xff); v >>= 8; }
}

/* piece: KELP_MAX_ACOMMS_FRAME + 1 bytes of caller storage */
static int unstitch_into(const uint8_t *d, size_t n, kelp_unstitch_fn fn, void *user, uint8_t *piece)
{
    if (!d || n < KELP_DCCL_HEADER_BYTES || d[0] != KELP_DCCL_CCL_ID) return KELP_ERR_PARSE;
    if (n > KELP_MAX_ACOMMS_FRAME) n = KELP_MAX_ACOMMS_FRAME;
    size_t p = 1; /* start of the current header (without its 0x20) */
    int count = 0;
    for (;;) {
        if (n - p < KELP_DCCL_HEADER_BYTES - 1) return count ? KELP_ERR_TRUNCATED : KELP_ERR_PARSE;
        uint8_t b5 = d[p + 4];
        bool mm = (b5 & KELP_DCCL_MULTIMESSAGE_MASK) != 0;
        bool bc = (b5 & KELP_DCCL_BROADCAST_MASK) != 0;
        unsigned id = ((unsigned)d[p] << 1) | (d[p + 1] >> 7);
        size_t body, next;
        piece[0] = KELP_DCCL_CCL_ID;
        memcpy(piece + 1, d + p, 5);
        if (mm) {
            if (p + 5 >= n) return KELP_ERR_TRUNCATED;  /* no body-length byte */
            size_t sz = d[p + 5];
            size_t avail = n - (p + 6);
            body = sz < avail ? sz : avail;               /* Goby's substr clamps */
            memcpy(piece + 6, d + p + 6, body);
            next = p + 6 + body;
        } else {
            body = n - (p + 5);
            memcpy(piece + 6, d + p + 5, body);
            next = n;
        }
        piece[5] = (uint8_t)(piece[5] & ~(KELP_DCCL_MULTIMESSAGE_MASK | KELP_DCCL_BROADCAST_MASK));
        if (fn) fn(piece, KELP_DCCL_HEADER_BYTES + body, id, bc, user);
        count++;
        if (!mm) return count;
        p = next;
    }
}

int kelp_queue_unstitch(const uint8_t *d, size_t n, kelp_unstitch_fn fn, void *user)
{
    uint8_t piece[KELP_MAX_ACOMMS_FRAME + 1];
    return unstitch_into(d, n, fn, user, piece);
}
