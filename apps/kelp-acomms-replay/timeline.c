/* kelp-acomms-replay: the output lines, the clock and the timeline's language.  The queues, MAC
 * and DCCL codec are the core pAcommsHandler's (kelp_acomms_handler); its node events come
 * here through the handler's sink (replay_on_event) and print as one line each. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <kelp/util.h>

#include "replay.h"

const char *replay_name_of(const replay *r, kelp_queue_key key)
{
    const kelp_acomms_qname *q = kelp_acomms_handler_queue(&r->h, key);
    if (q) return q->name;
    return key.type == KELP_QUEUE_CCL ? "CCL?" : "DCCL?";
}

void replay_stamp(replay *r)
{
    fprintf(r->out, "%10.3f ", (double)(r->now_us - r->start_us) / 1e6);
}

void replay_hex(FILE *f, const uint8_t *d, size_t n)
{
    for (size_t i = 0; i < n; i++) fprintf(f, "%02x", d[i]);
}

void replay_error(replay *r, const char *fmt, ...)
{
    va_list ap;
    r->errors++;
    replay_stamp(r);
    fprintf(r->out, "error line=%lu ", r->lineno);
    va_start(ap, fmt);
    vfprintf(r->out, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized): va_start above */
    va_end(ap);
    fputc('\n', r->out);
}

/* ------------------------------------------------------------------ node events */

void replay_on_event(void *ctx, const kelp_acomms_event *ev)
{
    replay *r = ctx;
    switch (ev->kind) {
    case KELP_ACOMMS_EV_SLOT:
        replay_stamp(r);
        fprintf(r->out, "slot index=%u %s src=%d dest=%d rate=%u type=%s\n", ev->slot->slot_index,
                ev->slot->kind == KELP_MAC_ACT_TRANSMIT ? "transmit" : "ranging", ev->slot->src, ev->slot->dest,
                ev->slot->rate,
                ev->slot->slot_type == KELP_SLOT_PING ? "SLOT_PING"
                : ev->slot->slot_type == KELP_SLOT_REMUS_LBL ? "SLOT_REMUS_LBL" : "SLOT_DATA");
        break;
    case KELP_ACOMMS_EV_FRAME_OUT:
        replay_stamp(r);
        if (ev->frame->len == 0) {
            fprintf(r->out, "frame frame=%u request_dest=%d max_bytes=%u blank dest=%d ack=%d\n", (unsigned)ev->req->frame,
                    ev->req->dest, (unsigned)ev->req->max_bytes, ev->frame->dest, ev->frame->ack_requested ? 1 : 0);
        } else {
            fprintf(r->out, "frame frame=%u request_dest=%d max_bytes=%u src=%d dest=%d ack=%d bytes=%zu hex=",
                    (unsigned)ev->req->frame, ev->req->dest, (unsigned)ev->req->max_bytes, ev->frame->src,
                    ev->frame->dest, ev->frame->ack_requested ? 1 : 0, ev->frame->len);
            replay_hex(r->out, ev->frame->data, ev->frame->len);
            fputc('\n', r->out);
        }
        break;
    case KELP_ACOMMS_EV_QUEUE: {
        const kelp_queue_event *q = ev->q;
        const char *nm = replay_name_of(r, q->key);
        replay_stamp(r);
        switch (q->kind) {
        case KELP_QUEUE_EV_QSIZE: fprintf(r->out, "qsize queue=%s size=%u\n", nm, (unsigned)q->size); break;
        case KELP_QUEUE_EV_ACK:
            fprintf(r->out, "ack queue=%s from=%d frame=%u hex=", nm, q->msg->dest, (unsigned)q->frame);
            replay_hex(r->out, q->msg->data, q->msg->len);
            fputc('\n', r->out);
            break;
        case KELP_QUEUE_EV_EXPIRE:
            fprintf(r->out, "expire queue=%s dest=%d hex=", nm, q->msg->dest);
            replay_hex(r->out, q->msg->data, q->msg->len);
            fputc('\n', r->out);
            break;
        case KELP_QUEUE_EV_RECEIVE: {
            char text[1024] = "";
            if (r->dccl && kelp_acomms_dccl_describe(r->dccl, q->msg->data, q->msg->len,
                                                     replay_sec(r->now_us), text, sizeof text) != KELP_OK) {
                /* text holds the reason */
            }
            fprintf(r->out, "receive queue=%s src=%d dest=%d hex=", nm, q->msg->src, q->msg->dest);
            replay_hex(r->out, q->msg->data, q->msg->len);
            fprintf(r->out, " decoded=\"%s\"\n", text);
            break;
        }
        case KELP_QUEUE_EV_RECEIVE_CCL:
            fprintf(r->out, "receive queue=%s src=%d dest=%d hex=", nm, q->msg->src, q->msg->dest);
            replay_hex(r->out, q->msg->data, q->msg->len);
            fputc('\n', r->out);
            break;
        default: fprintf(r->out, "queue-event %d\n", (int)q->kind); break;
        }
        break;
    }
    default: break;
    }
}

/* ------------------------------------------------------------------ time */

static void advance_to(replay *r, int64_t t_us)
{
    while (r->now_us < t_us) {
        int64_t next = (r->now_us / TICK_US + 1) * TICK_US;
        if (next > t_us) next = t_us;
        r->now_us = next;
        if (!r->auto_request) {
            /* report slots without requesting data: step the MAC ourselves */
            kelp_queue_do_work(&r->h.node.q, replay_sec(r->now_us));
            kelp_mac_action act;
            while (kelp_mac_tick(&r->h.node.mac, replay_sec(r->now_us), &act) == KELP_OK) {
                if (act.kind == KELP_MAC_ACT_NONE) continue;
                kelp_acomms_event ev;
                memset(&ev, 0, sizeof ev);
                ev.kind = KELP_ACOMMS_EV_SLOT;
                ev.time = replay_sec(r->now_us);
                ev.slot = &act;
                replay_on_event(r, &ev);
            }
        } else if (kelp_acomms_node_tick(&r->h.node, replay_sec(r->now_us)) != KELP_OK) {
            replay_error(r, "tick failed: %s", kelp_diag_text(&r->h.node.diag));
        }
        rmodem_tick(&r->modem, r->now_us);
    }
}

/* ------------------------------------------------------------------ parsing helpers */

bool replay_num(const char *s, double *out)
{
    return s && *s && kelp_util_parse_double(s, strlen(s), out) == KELP_OK;
}

bool replay_int(const char *s, long *out)
{
    return s && *s && kelp_util_parse_long(s, strlen(s), out) == KELP_OK;
}

/* "key=value" option among the remaining words */
const char *replay_opt(char **w, int n, const char *key)
{
    size_t k = strlen(key);
    for (int i = 0; i < n; i++)
        if (strncmp(w[i], key, k) == 0 && w[i][k] == '=') return w[i] + k + 1;
    return NULL;
}

bool replay_known_opts(replay *r, char **w, int n, const char *const *keys)
{
    for (int i = 0; i < n; i++) {
        const char *eq = strchr(w[i], '=');
        bool ok = false;
        for (int k = 0; eq && keys[k]; k++)
            if ((size_t)(eq - w[i]) == strlen(keys[k]) && strncmp(w[i], keys[k], strlen(keys[k])) == 0) ok = true;
        if (!ok) {
            replay_error(r, "unexpected argument \"%s\"", w[i]);
            return false;
        }
    }
    return true;
}

int replay_hex_bytes(const char *h, uint8_t *out, size_t cap, size_t *n)
{
    return kelp_util_hex_decode(h, strlen(h), out, cap, n);
}

/* ------------------------------------------------------------------ the timeline */

static int split(char *s, char **w, int cap)
{
    int n = 0;
    while (*s && n < cap) {
        while (*s == ' ' || *s == '\t') s++;
        if (!*s) break;
        w[n++] = s;
        while (*s && *s != ' ' && *s != '\t') s++;
        if (*s) *s++ = '\0';
    }
    return n;
}

void replay_run_line(replay *r, char *line)
{
    char *hash = strchr(line, '#');
    if (hash) *hash = '\0';
    size_t L = strlen(line);
    while (L && (line[L - 1] == '\n' || line[L - 1] == '\r' || line[L - 1] == ' ')) line[--L] = '\0';
    if (!L) return;
    if (strncmp(line, "mac_update ", 11) == 0) {
        kelp_acomms_mac_update u;
        kelp_diag why;
        kelp_diag_clear(&why);
        if (kelp_acomms_parse_mac_update(line + 11, strlen(line + 11), &u, &why) != KELP_OK)
            {
            replay_error(r, "bad MACUpdate: %s", kelp_diag_text(&why));
            return;
        }
        int rc = kelp_acomms_node_mac_update(&r->h.node, &u, replay_sec(r->now_us));
        replay_stamp(r);
        if (rc == KELP_ERR_NOTFOUND && u.dest != r->cfg.modem_id)
            fprintf(r->out, "mac_update ignored (dest %d is not us)\n", u.dest);
        else if (rc == KELP_ERR_NOTFOUND) fprintf(r->out, "mac_update remove: no such slot\n");
        else if (rc) fprintf(r->out, "mac_update refused (%s)\n", kelp_err_str(rc));
        else fprintf(r->out, "mac_update slots=%zu cycle=%u\n", r->h.node.mac.n, kelp_mac_cycle_length(&r->h.node.mac));
        return;
    }
    char *w[64];
    int n = split(line, w, 64);
    if (n == 0) return;
    double d;
    long v;
    if (!strcmp(w[0], "time")) {
        if (n != 2 || !replay_num(w[1], &d)) {
            replay_error(r, "time needs seconds since the start");
            return;
        }
        int64_t t = r->start_us + (int64_t)llround(d * 1e6);
        if (t < r->now_us) {
            replay_error(r, "time cannot go backwards");
            return;
        }
        advance_to(r, t);
    } else if (!strcmp(w[0], "advance")) {
        if (n != 2 || !replay_num(w[1], &d) || d < 0) {
            replay_error(r, "advance needs a number of seconds >= 0");
            return;
        }
        advance_to(r, r->now_us + (int64_t)llround(d * 1e6));
    } else if (!strcmp(w[0], "push")) {
        cmd_push(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "push_ccl")) {
        cmd_push_ccl(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "data_request")) {
        cmd_data_request(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "ack")) {
        cmd_ack(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "flush")) {
        cmd_flush(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "modem")) {
        cmd_modem(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "cycle")) {
        cmd_cycle(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "heard")) {
        if (n != 2 || !replay_int(w[1], &v) || v < 0 || v > 31) {
            replay_error(r, "heard needs a modem id");
            return;
        }
        kelp_acomms_node_heard(&r->h.node, (int)v, replay_sec(r->now_us));
        replay_stamp(r);
        fprintf(r->out, "heard id=%ld slots=%zu cycle=%u\n", v, r->h.node.mac.n, kelp_mac_cycle_length(&r->h.node.mac));
    } else if (!strcmp(w[0], "receive")) {
        cmd_receive(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "transmit")) {
        cmd_transmit(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "status")) {
        cmd_status(r);
    } else if (!strcmp(w[0], "auto_request")) {
        if (n != 2 || (strcmp(w[1], "on") != 0 && strcmp(w[1], "off") != 0)) {
            replay_error(r, "auto_request on|off");
            return;
        }
        r->auto_request = strcmp(w[1], "on") == 0;
    } else if (!strcmp(w[0], "echo")) {
        replay_stamp(r);
        fputs("echo", r->out);
        for (int i = 1; i < n; i++) fprintf(r->out, " %s", w[i]);
        fputc('\n', r->out);
    } else {
        replay_error(r, "unknown command \"%s\"", w[0]);
    }
}
