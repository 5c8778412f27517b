/* kelp acomms: the kelp.acomms_*_t LCM structures (edge).  They are encoded here with the
 * lcm-gen'd encoders and handed to a send callback: pAcommsHandler sends them through its own
 * LCM socket (kelp_app_publish_raw), so no second LCM handle is opened. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/acomms.h>

#include "kelp_acomms_ack_t.h"
#include "kelp_acomms_data_t.h"
#include "kelp_acomms_expire_t.h"
#include "kelp_acomms_qsize_t.h"
#include "kelp_acomms_range_t.h"
#include "kelp_acomms_status_t.h"

struct kelp_acomms_lcm {
    kelp_acomms_lcm_send_fn send;
    void *ctx;
    uint8_t *buf;
    size_t cap;
    char time_text[48];
    char hex[2 * KELP_MAX_ACOMMS_FRAME + 1];
};

kelp_acomms_lcm *kelp_acomms_lcm_new(kelp_acomms_lcm_send_fn send, void *ctx)
{
    if (!send) return NULL;
    kelp_acomms_lcm *l = calloc(1, sizeof *l);
    if (!l) return NULL;
    l->send = send;
    l->ctx = ctx;
    return l;
}

void kelp_acomms_lcm_close(kelp_acomms_lcm *l)
{
    if (!l) return;
    free(l->buf);
    free(l);
}

/* room for n encoded bytes in l->buf */
static int reserve(kelp_acomms_lcm *l, int n)
{
    if (n < 0) return KELP_ERR_ARG;
    if ((size_t)n <= l->cap) return KELP_OK;
    uint8_t *b = realloc(l->buf, (size_t)n);
    if (!b) return KELP_ERR_NOSPACE;
    l->buf = b;
    l->cap = (size_t)n;
    return KELP_OK;
}

/* n encoded bytes (or an encoder's error) in l->buf: send them */
static int send_encoded(kelp_acomms_lcm *l, const char *channel, int n)
{
    if (n < 0) return KELP_ERR_IO;
    return l->send(l->ctx, channel, l->buf, (size_t)n) == 0 ? KELP_OK : KELP_ERR_IO;
}

/* encode a structure of lcm type T into l->buf and send it on channel */
#define SEND(l, T, channel, p)                                                                                    \
    (reserve((l), T##_encoded_size(p)) != KELP_OK ? KELP_ERR_NOSPACE                                           \
                                                   : send_encoded((l), (channel), T##_encode((l)->buf, 0, (int)(l)->cap, (p))))

/* fill a data_t; strings point into l (valid until the next fill) */
static void fill_data(kelp_acomms_lcm *l, kelp_acomms_data_t *d, double time, const kelp_acomms_msg *m, const char *name,
                      const char *decoded, char *time_text, char *hex)
{
    static const char H[] = "0123456789abcdef";
    memset(d, 0, sizeof *d);
    (void)l;
    d->time = time;
    d->src = m->src;
    d->dest = m->dest;
    time_text[0] = '\0';
    if (m->has_time && kelp_acomms_time_text(m->time, time_text, 48) != KELP_OK) time_text[0] = '\0';
    d->msg_time = time_text;
    d->ack_requested = m->ack_requested;
    d->frame = (int32_t)m->frame;
    d->queue_type = (int8_t)m->key.type;
    d->queue_id = (int32_t)m->key.id;
    d->queue_name = (char *)(name ? name : "");
    d->nbytes = (int32_t)m->len;
    d->data = (uint8_t *)m->data;
    for (size_t i = 0; i < m->len; i++) {
        hex[2 * i] = H[m->data[i] >> 4];
        hex[2 * i + 1] = H[m->data[i] & 15];
    }
    hex[2 * m->len] = '\0';
    d->hex = hex;
    d->decoded = (char *)(decoded ? decoded : "");
}

int kelp_acomms_lcm_data(kelp_acomms_lcm *l, const char *channel, double time, const kelp_acomms_msg *m,
                         const char *name, const char *decoded)
{
    if (!l || !channel || !m) return KELP_ERR_ARG;
    kelp_acomms_data_t d;
    fill_data(l, &d, time, m, name, decoded, l->time_text, l->hex);
    return SEND(l, kelp_acomms_data_t, channel, &d);
}

int kelp_acomms_lcm_ack(kelp_acomms_lcm *l, const char *channel, double time, int src, int dest, uint32_t frame,
                        const kelp_acomms_msg *orig, const char *name)
{
    if (!l || !channel || !orig) return KELP_ERR_ARG;
    kelp_acomms_ack_t a;
    memset(&a, 0, sizeof a);
    a.time = time;
    a.src = src;
    a.dest = dest;
    a.frame = (int32_t)frame;
    fill_data(l, &a.orig_msg, time, orig, name, NULL, l->time_text, l->hex);
    return SEND(l, kelp_acomms_ack_t, channel, &a);
}

int kelp_acomms_lcm_expire(kelp_acomms_lcm *l, const char *channel, double time, const kelp_acomms_msg *orig,
                           const char *name)
{
    if (!l || !channel || !orig) return KELP_ERR_ARG;
    kelp_acomms_expire_t e;
    memset(&e, 0, sizeof e);
    e.time = time;
    fill_data(l, &e.orig_msg, time, orig, name, NULL, l->time_text, l->hex);
    return SEND(l, kelp_acomms_expire_t, channel, &e);
}

int kelp_acomms_lcm_qsize(kelp_acomms_lcm *l, const char *channel, double time, kelp_queue_key key, const char *name,
                          uint32_t size)
{
    if (!l || !channel) return KELP_ERR_ARG;
    kelp_acomms_qsize_t q;
    memset(&q, 0, sizeof q);
    q.time = time;
    q.queue_type = (int8_t)key.type;
    q.queue_id = (int32_t)key.id;
    q.queue_name = (char *)(name ? name : "");
    q.size = (int32_t)size;
    return SEND(l, kelp_acomms_qsize_t, channel, &q);
}

int kelp_acomms_lcm_range(kelp_acomms_lcm *l, const char *channel, double time, int src, int dest, kelp_ranging_type type,
                          const double *tt, unsigned n_tt)
{
    if (!l || !channel || (n_tt && !tt)) return KELP_ERR_ARG;
    kelp_acomms_range_t r;
    double copy[8];
    memset(&r, 0, sizeof r);
    r.time = time;
    r.src = src;
    r.dest = dest;
    r.type = (char *)(type == KELP_RANGING_REMUS_LBL              ? "REMUS_LBL_RANGING"
                      : type == KELP_RANGING_ONE_WAY_SYNCHRONOUS ? "MODEM_ONE_WAY_SYNCHRONOUS"
                                                                 : "MODEM_TWO_WAY_PING");
    if (n_tt > 8) n_tt = 8;
    for (unsigned i = 0; i < n_tt; i++) copy[i] = tt[i];
    r.ntt = (int32_t)n_tt;
    r.one_way_travel_time = copy;
    return SEND(l, kelp_acomms_range_t, channel, &r);
}

int kelp_acomms_lcm_status(kelp_acomms_lcm *l, const char *channel, const kelp_acomms_status *s)
{
    if (!l || !channel || !s) return KELP_ERR_ARG;
    kelp_acomms_status_t t;
    memset(&t, 0, sizeof t);
    t.time = s->time;
    t.modem_id = s->modem_id;
    t.driver = (char *)(s->driver ? s->driver : "");
    t.link = (char *)(s->link ? s->link : "");
    t.link_up = s->link_up;
    t.clock_ok = s->clock_ok;
    t.mac = (char *)(s->mac ? s->mac : "");
    t.next_slot_us = s->next_slot < 0 ? -1 : (int64_t)llround(s->next_slot * 1e6); /* wire: UNIX us */
    t.lines_in = (int32_t)s->lines_in;
    t.lines_out = (int32_t)s->lines_out;
    t.bad_lines = (int32_t)s->bad_lines;
    t.retries = (int32_t)s->retries;
    t.modem_errors = (int32_t)s->modem_errors;
    t.reconnects = (int32_t)s->reconnects;
    t.frames_out = (int32_t)s->frames_out;
    t.frames_in = (int32_t)s->frames_in;
    t.acks = (int32_t)s->acks;
    t.expired = (int32_t)s->expired;
    t.messages_encoded = (int32_t)s->encoded;
    t.messages_decoded = (int32_t)s->decoded;
    t.nqueues = (int32_t)s->nqueues;
    t.queue_name = (char **)s->queue_name;
    t.queue_size = (int32_t *)s->queue_size;
    return SEND(l, kelp_acomms_status_t, channel, &t);
}

int kelp_acomms_lcm_record(kelp_acomms_lcm *l, const kelp_acomms_record *r)
{
    if (!l || !r) return KELP_ERR_ARG;
    switch (r->kind) {
    case KELP_ACOMMS_REC_DATA: return kelp_acomms_lcm_data(l, r->channel, r->time, r->msg, r->name, r->decoded);
    case KELP_ACOMMS_REC_ACK:
        return kelp_acomms_lcm_ack(l, r->channel, r->time, r->src, r->dest, r->frame, r->msg, r->name);
    case KELP_ACOMMS_REC_EXPIRE: return kelp_acomms_lcm_expire(l, r->channel, r->time, r->msg, r->name);
    case KELP_ACOMMS_REC_QSIZE: return kelp_acomms_lcm_qsize(l, r->channel, r->time, r->key, r->name, r->size);
    case KELP_ACOMMS_REC_RANGE:
        return kelp_acomms_lcm_range(l, r->channel, r->time, r->src, r->dest, r->type, r->tt, r->n_tt);
    case KELP_ACOMMS_REC_STATUS: return kelp_acomms_lcm_status(l, r->channel, r->status);
    default: return KELP_ERR_ARG;
    }
}
