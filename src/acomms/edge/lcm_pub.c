/* kelp acomms: publishing the kelp.acomms_*_t LCM structures (edge). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcm/lcm.h>

#include <kelp/acomms.h>

#include "kelp_acomms_ack_t.h"
#include "kelp_acomms_data_t.h"
#include "kelp_acomms_expire_t.h"
#include "kelp_acomms_qsize_t.h"
#include "kelp_acomms_range_t.h"
#include "kelp_acomms_status_t.h"

struct kelp_acomms_lcm {
    lcm_t *lcm;
    char time_text[48];
    char hex[2 * KELP_MAX_ACOMMS_FRAME + 1];
};

kelp_acomms_lcm *kelp_acomms_lcm_open(const char *url, char *err, size_t errcap)
{
    kelp_acomms_lcm *l = calloc(1, sizeof *l);
    if (!l) {
        if (err) snprintf(err, errcap, "out of memory");
        return NULL;
    }
    l->lcm = lcm_create(url);
    if (!l->lcm) {
        if (err) snprintf(err, errcap, "cannot open LCM URL '%s'", url ? url : "(default)");
        free(l);
        return NULL;
    }
    return l;
}

void kelp_acomms_lcm_close(kelp_acomms_lcm *l)
{
    if (!l) return;
    if (l->lcm) lcm_destroy(l->lcm);
    free(l);
}

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
    if (m->has_time && kelp_acomms_time_text(m->time_us, time_text, 48) != KELP_OK) time_text[0] = '\0';
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
    return kelp_acomms_data_t_publish(l->lcm, channel, &d) == 0 ? KELP_OK : KELP_ERR_IO;
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
    return kelp_acomms_ack_t_publish(l->lcm, channel, &a) == 0 ? KELP_OK : KELP_ERR_IO;
}

int kelp_acomms_lcm_expire(kelp_acomms_lcm *l, const char *channel, double time, const kelp_acomms_msg *orig,
                           const char *name)
{
    if (!l || !channel || !orig) return KELP_ERR_ARG;
    kelp_acomms_expire_t e;
    memset(&e, 0, sizeof e);
    e.time = time;
    fill_data(l, &e.orig_msg, time, orig, name, NULL, l->time_text, l->hex);
    return kelp_acomms_expire_t_publish(l->lcm, channel, &e) == 0 ? KELP_OK : KELP_ERR_IO;
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
    return kelp_acomms_qsize_t_publish(l->lcm, channel, &q) == 0 ? KELP_OK : KELP_ERR_IO;
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
    return kelp_acomms_range_t_publish(l->lcm, channel, &r) == 0 ? KELP_OK : KELP_ERR_IO;
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
    t.next_slot_us = s->next_slot_us;
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
    return kelp_acomms_status_t_publish(l->lcm, channel, &t) == 0 ? KELP_OK : KELP_ERR_IO;
}
