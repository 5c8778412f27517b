/* kelp-acomms-replay: the Micro-Modem driver core on the timeline (no serial line). What the
 * driver writes is printed as "nmea-out"; modem sentences come from "modem $CA..." lines; a
 * "cycle" hands the driver the frames of a cycle of our own (kelp_mmdriver_transmit_frames). */
#include <stdio.h>
#include <string.h>

#include "replay.h"

static void stamp(const rmodem *m, int64_t t)
{
    fprintf(m->out, "%10.3f ", (double)(t - m->start_us) / 1e6);
}

static void on_write(const char *bytes, size_t len, void *user)
{
    (void)bytes, (void)len, (void)user; /* shown by the NMEA_OUT event, without the CRLF */
}

static void on_event(const kelp_mmdriver_event *ev, void *user)
{
    rmodem *m = user;
    switch (ev->kind) {
    case KELP_MMDRIVER_EV_NMEA_OUT:
        stamp(m, replay_us(ev->time));
        fprintf(m->out, "nmea-out %s\n", ev->raw);
        break;
    case KELP_MMDRIVER_EV_ACK:
        stamp(m, replay_us(ev->time));
        fprintf(m->out, "modem-ack src=%d dest=%d frame=%u\n", ev->src, ev->dest, (unsigned)ev->frame);
        break;
    case KELP_MMDRIVER_EV_RECEIVE:
        stamp(m, replay_us(ev->time));
        fprintf(m->out, "modem-receive src=%d dest=%d frame=%u hex=", ev->src, ev->dest, (unsigned)ev->frame);
        for (size_t i = 0; i < ev->data_len; i++) fprintf(m->out, "%02x", ev->data[i]);
        fputc('\n', m->out);
        break;
    case KELP_MMDRIVER_EV_BAD_LINE:
        stamp(m, replay_us(ev->time));
        fprintf(m->out, "modem-bad-line %s\n", ev->raw ? ev->raw : "");
        break;
    case KELP_MMDRIVER_EV_RETRY:
    case KELP_MMDRIVER_EV_GIVE_UP:
    case KELP_MMDRIVER_EV_DEAD:
        stamp(m, replay_us(ev->time));
        fprintf(m->out, "modem-%s\n", ev->kind == KELP_MMDRIVER_EV_RETRY ? "retry" : ev->kind == KELP_MMDRIVER_EV_DEAD ? "dead" : "give-up");
        break;
    default:
        break;
    }
}

/* a cycle the modem started asks us for data: kelp-acomms-replay answers blank (use
 * data_request to see what the queue would give) */
static void on_request(const kelp_mmdriver_data_request *req, kelp_mmdriver_frame *out, void *user)
{
    rmodem *m = user;
    out->len = 0;
    fprintf(m->out, "%10s modem-request dest=%d frame=%u max_bytes=%u (answered blank)\n", "", req->dest,
            (unsigned)req->frame, (unsigned)req->max_bytes);
}

int rmodem_start(rmodem *m, int modem_id, FILE *out, int64_t start_us, int64_t now_us)
{
    static const kelp_mmdriver_ops ops = { on_write, on_event, on_request };
    kelp_mmdriver_cfg cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.modem_id = modem_id;
    m->out = out;
    m->start_us = start_us;
    int rc = kelp_mmdriver_init(&m->mm, &cfg, &ops, m);
    if (rc == KELP_OK) rc = kelp_mmdriver_start(&m->mm, replay_sec(now_us));
    m->on = rc == KELP_OK;
    return rc;
}

void rmodem_tick(rmodem *m, int64_t now_us)
{
    if (m->on && kelp_mmdriver_tick(&m->mm, replay_sec(now_us)) == KELP_ERR_TIMEOUT) {
        fprintf(m->out, "%10.3f modem-dead (say \"modem start\" to start again)\n", (double)(now_us - m->start_us) / 1e6);
        m->on = false;
    }
}

int rmodem_feed(rmodem *m, const char *line, int64_t now_us)
{
    if (!m->on) return KELP_ERR_STATE;
    char buf[KELP_MAX_NMEA_LINE + 2];
    int n = snprintf(buf, sizeof buf, "%s\r", line);
    if (n < 0 || (size_t)n >= sizeof buf) return KELP_ERR_RANGE;
    return kelp_mmdriver_feed(&m->mm, (const uint8_t *)buf, (size_t)n, replay_sec(now_us));
}

int rmodem_cycle(rmodem *m, unsigned rate, const kelp_mmdriver_frame *frames, size_t n, int64_t now_us)
{
    if (!m->on) return KELP_ERR_STATE;
    return kelp_mmdriver_transmit_frames(&m->mm, rate, frames, n, replay_sec(now_us));
}
