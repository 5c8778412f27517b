/* kelp-acomms-replay: what the Goby 1.1 queue and MAC do with a scripted timeline.
 * Deterministic: the only clock is the timeline's. See usage() for the language. */
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/edge/cli.h>
#include <kelp/edge/mission.h>

#include "replay.h"

#define TICK_US 100000LL /* Goby's do_work at AppTick 10 */
#define MAX_LINE 4096

typedef struct replay {
    kelp_acomms_config cfg;
    kelp_acomms_dccl *dccl;
    kelp_acomms_node node;
    kelp_queue queues[KELP_ACOMMS_MAX_QUEUES];
    kelp_queue_entry *pool;
    const char *qname[KELP_ACOMMS_MAX_QUEUES];
    kelp_queue_key qkey[KELP_ACOMMS_MAX_QUEUES];
    size_t nq;
    int64_t start_us, now_us;
    bool auto_request;
    FILE *out;
    unsigned long lineno;
    unsigned long errors;
    rmodem modem;           /* the Micro-Modem driver, after "modem start" */
} replay;

static const char *name_of(const replay *r, kelp_queue_key key)
{
    for (size_t i = 0; i < r->nq; i++)
        if (r->qkey[i].type == key.type && r->qkey[i].id == key.id) return r->qname[i];
    return key.type == KELP_QUEUE_CCL ? "CCL?" : "DCCL?";
}

static void stamp(replay *r)
{
    fprintf(r->out, "%10.3f ", (double)(r->now_us - r->start_us) / 1e6);
}

static void hex(FILE *f, const uint8_t *d, size_t n)
{
    for (size_t i = 0; i < n; i++) fprintf(f, "%02x", d[i]);
}

static void error(replay *r, const char *fmt, ...) KELP_PRINTF(2, 3);
static void error(replay *r, const char *fmt, ...)
{
    va_list ap;
    r->errors++;
    stamp(r);
    fprintf(r->out, "error line=%lu ", r->lineno);
    va_start(ap, fmt);
    vfprintf(r->out, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized): va_start above */
    va_end(ap);
    fputc('\n', r->out);
}

/* ------------------------------------------------------------------ node events */

static void on_event(const kelp_acomms_event *ev, void *user)
{
    replay *r = user;
    switch (ev->kind) {
    case KELP_ACOMMS_EV_SLOT:
        stamp(r);
        fprintf(r->out, "slot index=%u %s src=%d dest=%d rate=%u type=%s\n", ev->slot->slot_index,
                ev->slot->kind == KELP_MAC_ACT_TRANSMIT ? "transmit" : "ranging", ev->slot->src, ev->slot->dest,
                ev->slot->rate,
                ev->slot->slot_type == KELP_SLOT_PING ? "SLOT_PING"
                : ev->slot->slot_type == KELP_SLOT_REMUS_LBL ? "SLOT_REMUS_LBL" : "SLOT_DATA");
        break;
    case KELP_ACOMMS_EV_FRAME_OUT:
        stamp(r);
        if (ev->frame->len == 0) {
            fprintf(r->out, "frame frame=%u request_dest=%d max_bytes=%u blank dest=%d ack=%d\n", (unsigned)ev->req->frame,
                    ev->req->dest, (unsigned)ev->req->max_bytes, ev->frame->dest, ev->frame->ack_requested ? 1 : 0);
        } else {
            fprintf(r->out, "frame frame=%u request_dest=%d max_bytes=%u src=%d dest=%d ack=%d bytes=%zu hex=",
                    (unsigned)ev->req->frame, ev->req->dest, (unsigned)ev->req->max_bytes, ev->frame->src,
                    ev->frame->dest, ev->frame->ack_requested ? 1 : 0, ev->frame->len);
            hex(r->out, ev->frame->data, ev->frame->len);
            fputc('\n', r->out);
        }
        break;
    case KELP_ACOMMS_EV_QUEUE: {
        const kelp_queue_event *q = ev->q;
        const char *nm = name_of(r, q->key);
        stamp(r);
        switch (q->kind) {
        case KELP_QUEUE_EV_QSIZE: fprintf(r->out, "qsize queue=%s size=%u\n", nm, (unsigned)q->size); break;
        case KELP_QUEUE_EV_ACK:
            fprintf(r->out, "ack queue=%s from=%d frame=%u hex=", nm, q->msg->dest, (unsigned)q->frame);
            hex(r->out, q->msg->data, q->msg->len);
            fputc('\n', r->out);
            break;
        case KELP_QUEUE_EV_EXPIRE:
            fprintf(r->out, "expire queue=%s dest=%d hex=", nm, q->msg->dest);
            hex(r->out, q->msg->data, q->msg->len);
            fputc('\n', r->out);
            break;
        case KELP_QUEUE_EV_RECEIVE: {
            char text[1024] = "";
            if (r->dccl && kelp_acomms_dccl_describe(r->dccl, q->msg->data, q->msg->len,
                                                     (double)r->now_us / 1e6, text, sizeof text) != KELP_OK) {
                /* text holds the reason */
            }
            fprintf(r->out, "receive queue=%s src=%d dest=%d hex=", nm, q->msg->src, q->msg->dest);
            hex(r->out, q->msg->data, q->msg->len);
            fprintf(r->out, " decoded=\"%s\"\n", text);
            break;
        }
        case KELP_QUEUE_EV_RECEIVE_CCL:
            fprintf(r->out, "receive queue=%s src=%d dest=%d hex=", nm, q->msg->src, q->msg->dest);
            hex(r->out, q->msg->data, q->msg->len);
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
            kelp_queue_do_work(&r->node.q, r->now_us);
            kelp_mac_action act;
            while (kelp_mac_tick(&r->node.mac, r->now_us, &act) == KELP_OK) {
                if (act.kind == KELP_MAC_ACT_NONE) continue;
                kelp_acomms_event ev;
                memset(&ev, 0, sizeof ev);
                ev.kind = KELP_ACOMMS_EV_SLOT;
                ev.time_us = r->now_us;
                ev.slot = &act;
                on_event(&ev, r);
            }
        } else if (kelp_acomms_node_tick(&r->node, r->now_us) != KELP_OK) {
            error(r, "tick failed: %s", r->node.errmsg);
        }
        rmodem_tick(&r->modem, r->now_us);
    }
}

/* ------------------------------------------------------------------ parsing helpers */

static bool parse_num(const char *s, double *out)
{
    return s && *s && kelp_parse_double(s, strlen(s), out) == KELP_OK;
}

static bool parse_int(const char *s, long *out)
{
    return s && *s && kelp_parse_long(s, strlen(s), out) == KELP_OK;
}

/* "key=value" option among the remaining words */
static const char *opt(char **w, int n, const char *key)
{
    size_t k = strlen(key);
    for (int i = 0; i < n; i++)
        if (strncmp(w[i], key, k) == 0 && w[i][k] == '=') return w[i] + k + 1;
    return NULL;
}

static bool known_opts(replay *r, char **w, int n, const char *const *keys)
{
    for (int i = 0; i < n; i++) {
        const char *eq = strchr(w[i], '=');
        bool ok = false;
        for (int k = 0; eq && keys[k]; k++)
            if ((size_t)(eq - w[i]) == strlen(keys[k]) && strncmp(w[i], keys[k], strlen(keys[k])) == 0) ok = true;
        if (!ok) {
            error(r, "unexpected argument \"%s\"", w[i]);
            return false;
        }
    }
    return true;
}

static int hex_to_bytes(const char *h, uint8_t *out, size_t cap, size_t *n)
{
    size_t len = strlen(h);
    if (len % 2 || len / 2 > cap) return KELP_ERR_PARSE;
    for (size_t i = 0; i < len / 2; i++) {
        int v = 0;
        for (int k = 0; k < 2; k++) {
            char c = h[2 * i + (size_t)k];
            int d = isdigit((unsigned char)c) ? c - '0' : (c >= 'a' && c <= 'f') ? c - 'a' + 10 : (c >= 'A' && c <= 'F') ? c - 'A' + 10 : -1;
            if (d < 0) return KELP_ERR_PARSE;
            v = v * 16 + d;
        }
        out[i] = (uint8_t)v;
    }
    *n = len / 2;
    return KELP_OK;
}

/* ------------------------------------------------------------------ commands */

static void cmd_push(replay *r, char **w, int n)
{
    if (n < 1) {
        error(r, "push needs a message name");
        return;
    }
    long idx = kelp_acomms_dccl_find_name(r->dccl, w[0]);
    if (idx < 0) {
        error(r, "no DCCL message \"%s\"", w[0]);
        return;
    }
    /* fields may be given as separate words or one comma list */
    char kv[MAX_LINE] = "";
    for (int i = 1; i < n; i++) {
        size_t o = strlen(kv);
        snprintf(kv + o, sizeof kv - o, "%s%s", o ? "," : "", w[i]);
    }
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    size_t len = 0;
    const char *why = NULL;
    if (kelp_acomms_dccl_encode_string(r->dccl, (size_t)idx, kv, (double)r->now_us / 1e6, m.data, sizeof m.data, &len,
                                       &why) != KELP_OK) {
        error(r, "cannot encode: %s", why);
        return;
    }
    kelp_queue_header hd;
    if (kelp_queue_header_read(m.data, len, &hd) != KELP_OK) {
        error(r, "encoded message too short");
        return;
    }
    kelp_acomms_dccl_info info;
    if (kelp_acomms_dccl_info_get(r->dccl, (size_t)idx, &info) != KELP_OK) return;
    m.len = len;
    m.src = r->cfg.modem_id;
    m.dest = (int)hd.dest;
    m.has_time = true;
    m.time_us = r->now_us;
    m.key.type = KELP_QUEUE_DCCL;
    m.key.id = info.id;
    stamp(r);
    fprintf(r->out, "push queue=%s id=%u dest=%d bytes=%zu hex=", info.name, info.id, m.dest, len);
    hex(r->out, m.data, len);
    fputc('\n', r->out);
    if (kelp_acomms_node_push(&r->node, &m, r->now_us) != KELP_OK) error(r, "push refused: %s", r->node.errmsg);
}

static void cmd_push_ccl(replay *r, char **w, int n)
{
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    if (n < 1 || hex_to_bytes(w[0], m.data, sizeof m.data, &m.len) != KELP_OK || m.len == 0) {
        error(r, "push_ccl needs HEX bytes (the first byte is the CCL id)");
        return;
    }
    static const char *const keys[] = { "dest", "ack", NULL };
    if (!known_opts(r, w + 1, n - 1, keys)) return;
    long v;
    const char *d = opt(w + 1, n - 1, "dest"), *a = opt(w + 1, n - 1, "ack");
    m.dest = d && parse_int(d, &v) ? (int)v : 0;
    if (a && parse_int(a, &v)) {
        m.ack_requested = v != 0;
        m.has_ack = true;
    }
    m.src = r->cfg.modem_id;
    m.has_time = true;
    m.time_us = r->now_us;
    m.key.type = KELP_QUEUE_CCL;
    m.key.id = m.data[0];
    stamp(r);
    fprintf(r->out, "push queue=%s id=%u dest=%d bytes=%zu hex=%s\n", name_of(r, m.key), (unsigned)m.key.id, m.dest, m.len,
            w[0]);
    if (kelp_acomms_node_push(&r->node, &m, r->now_us) != KELP_OK) error(r, "push refused: %s", r->node.errmsg);
}

static void cmd_data_request(replay *r, char **w, int n)
{
    static const char *const keys[] = { "dest", "frame", "bytes", "rate", NULL };
    if (!known_opts(r, w, n, keys)) return;
    long v;
    kelp_queue_request req;
    req.dest = -1;
    req.frame = 0;
    req.max_bytes = 32;
    const char *s;
    if ((s = opt(w, n, "rate"))) {
        if (!parse_int(s, &v) || v < 0 || v > 5) {
            error(r, "rate must be 0..5");
            return;
        }
        req.max_bytes = kelp_mmdriver_packet_size[v];
    }
    if ((s = opt(w, n, "dest"))) {
        if (!parse_int(s, &v) || v < -1 || v > 31) {
            error(r, "dest must be -1..31");
            return;
        }
        req.dest = (int)v;
    }
    if ((s = opt(w, n, "frame"))) {
        if (!parse_int(s, &v) || v < 0 || v > 31) {
            error(r, "frame must be 0..31");
            return;
        }
        req.frame = (uint32_t)v;
    }
    if ((s = opt(w, n, "bytes"))) {
        if (!parse_int(s, &v) || v < 1 || v > KELP_MAX_ACOMMS_FRAME) {
            error(r, "bytes must be 1..256");
            return;
        }
        req.max_bytes = (uint32_t)v;
    }
    kelp_acomms_msg out;
    if (kelp_acomms_node_data_request(&r->node, &req, r->now_us, &out) != KELP_OK)
        error(r, "data request failed: %s", r->node.errmsg);
}

static void cmd_ack(replay *r, char **w, int n)
{
    long frame, src = -1;
    if (n < 1 || !parse_int(w[0], &frame) || frame < 0) {
            error(r, "ack needs a frame number");
            return;
        }
    static const char *const keys[] = { "src", "dest", NULL };
    if (!known_opts(r, w + 1, n - 1, keys)) return;
    long dest = r->cfg.modem_id;
    const char *s = opt(w + 1, n - 1, "src"), *d = opt(w + 1, n - 1, "dest");
    if ((s && !parse_int(s, &src)) || (d && !parse_int(d, &dest))) {
        error(r, "bad src or dest");
        return;
    }
    int k = kelp_acomms_node_ack(&r->node, (int)src, (int)dest, (uint32_t)frame, r->now_us);
    if (k == 0) {
        stamp(r);
        if (dest != r->cfg.modem_id) fprintf(r->out, "ack-ignored frame=%ld (addressed to %ld, not us)\n", frame, dest);
        else fprintf(r->out, "ack-ignored frame=%ld (no message waits for it)\n", frame);
    }
}

static void cmd_flush(replay *r, char **w, int n)
{
    for (size_t i = 0; i < r->nq && n == 1; i++) {
        if (strcmp(r->qname[i], w[0]) != 0) continue;
        stamp(r);
        fprintf(r->out, "flush queue=%s\n", r->qname[i]);
        if (kelp_queue_flush(&r->node.q, r->qkey[i]) != KELP_OK) error(r, "flush failed");
        return;
    }
    error(r, "flush needs the name of a queue");
}

static void cmd_receive(replay *r, char **w, int n)
{
    long src, dest;
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    if (n < 3 || !parse_int(w[0], &src) || !parse_int(w[1], &dest) ||
        hex_to_bytes(w[2], m.data, sizeof m.data, &m.len) != KELP_OK)
        {
            error(r, "receive needs SRC DEST HEX");
            return;
        }
    m.src = (int)src;
    m.dest = (int)dest;
    m.has_time = true;
    m.time_us = r->now_us;
    int k = kelp_acomms_node_receive(&r->node, &m, r->now_us);
    if (k == 0) {
        stamp(r);
        fprintf(r->out, "receive-ignored src=%ld dest=%ld (not for us, no queue, or malformed)\n", src, dest);
    }
}

static void cmd_transmit(replay *r, char **w, int n)
{
    static const char *const keys[] = { "dest", "rate", NULL };
    if (!known_opts(r, w, n, keys)) return;
    long dest = -1, rate = 0;
    const char *s;
    if ((s = opt(w, n, "dest")) && (!parse_int(s, &dest) || dest < -1 || dest > 31))
        {
            error(r, "dest must be -1..31");
            return;
        }
    if ((s = opt(w, n, "rate")) && (!parse_int(s, &rate) || rate < 0 || rate > 5))
        {
            error(r, "rate must be 0..5");
            return;
        }
    stamp(r);
    fprintf(r->out, "transmit src=%d dest=%ld rate=%ld\n", r->cfg.modem_id, dest, rate);
    if (kelp_acomms_node_transmit(&r->node, r->cfg.modem_id, (int)dest, (unsigned)rate, r->now_us) != KELP_OK)
        error(r, "transmit failed: %s", r->node.errmsg);
}

/* modem start | modem $CA... : the driver, and a sentence from the modem */
static void cmd_modem(replay *r, char **w, int n)
{
    if (n == 1 && !strcmp(w[0], "start")) {
        if (rmodem_start(&r->modem, r->cfg.modem_id, r->out, r->start_us, r->now_us) != KELP_OK)
            error(r, "the modem driver cannot start");
    } else if (n == 1 && w[0][0] == '$') {
        if (!r->modem.on) error(r, "modem: say \"modem start\" first");
        else if (rmodem_feed(&r->modem, w[0], r->now_us) != KELP_OK) error(r, "modem: sentence not taken");
    } else {
        error(r, "modem start | modem $CA...");
    }
}

/* cycle rate=R dest=D [ack=0|1] HEX|- ... : a cycle of ours with these frames */
static void cmd_cycle(replay *r, char **w, int n)
{
    static kelp_mmdriver_frame fr[KELP_MAX_MM_FRAMES];
    long rate = -1, dest = -1, ack = 0;
    size_t nf = 0;
    for (int i = 0; i < n; i++) {
        const char *eq = strchr(w[i], '=');
        bool ok = true;
        if (!eq) {
            ok = nf < KELP_MAX_MM_FRAMES;
            if (ok) {
                memset(&fr[nf], 0, sizeof fr[nf]);
                ok = !strcmp(w[i], "-") || hex_to_bytes(w[i], fr[nf].data, sizeof fr[nf].data, &fr[nf].len) == KELP_OK;
                nf++;
            }
        } else if (!strncmp(w[i], "rate=", 5)) ok = parse_int(eq + 1, &rate) && rate >= 0 && rate <= 5;
        else if (!strncmp(w[i], "dest=", 5)) ok = parse_int(eq + 1, &dest) && dest >= 0 && dest <= 31;
        else if (!strncmp(w[i], "ack=", 4)) ok = parse_int(eq + 1, &ack) && (ack == 0 || ack == 1);
        else ok = false;
        if (!ok) {
            error(r, "cycle: bad argument \"%s\"", w[i]);
            return;
        }
    }
    if (rate < 0 || dest < 0) {
        error(r, "cycle needs rate=R and dest=D");
        return;
    }
    for (size_t i = 0; i < nf; i++) fr[i].src = r->cfg.modem_id, fr[i].dest = (int)dest, fr[i].ack_requested = ack == 1;
    stamp(r);
    fprintf(r->out, "cycle rate=%ld dest=%ld ack=%ld frames=%zu\n", rate, dest, ack, nf);
    int rc = rmodem_cycle(&r->modem, (unsigned)rate, fr, nf, r->now_us);
    if (rc == KELP_ERR_STATE) error(r, "cycle: say \"modem start\" first");
    else if (rc != KELP_OK) error(r, "cycle: rate %ld carries %u frames", rate, kelp_mmdriver_packet_frames[rate]);
}

static void cmd_status(replay *r)
{
    for (size_t i = 0; i < r->nq; i++) {
        double p = 0;
        if (kelp_queue_priority(&r->node.q, r->qkey[i], r->now_us, &p) != KELP_OK) p = NAN;
        stamp(r);
        fprintf(r->out, "status queue=%s size=%ld priority=%.6g\n", r->qname[i], kelp_queue_size(&r->node.q, r->qkey[i]),
                p);
    }
    int64_t next = kelp_mac_next_slot_time(&r->node.mac);
    stamp(r);
    fprintf(r->out, "status mac slots=%zu cycle=%u next_slot=%.3f\n", r->node.mac.n, kelp_mac_cycle_length(&r->node.mac),
            next < 0 ? -1.0 : (double)(next - r->start_us) / 1e6);
}

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

static void run_line(replay *r, char *line)
{
    char *hash = strchr(line, '#');
    if (hash) *hash = '\0';
    size_t L = strlen(line);
    while (L && (line[L - 1] == '\n' || line[L - 1] == '\r' || line[L - 1] == ' ')) line[--L] = '\0';
    if (!L) return;
    if (strncmp(line, "mac_update ", 11) == 0) {
        kelp_acomms_mac_update u;
        const char *why = NULL;
        if (kelp_acomms_parse_mac_update(line + 11, strlen(line + 11), &u, &why) != KELP_OK)
            {
            error(r, "bad MACUpdate: %s", why);
            return;
        }
        int rc = kelp_acomms_node_mac_update(&r->node, &u, r->now_us);
        stamp(r);
        if (rc == KELP_ERR_NOTFOUND && u.dest != r->cfg.modem_id)
            fprintf(r->out, "mac_update ignored (dest %d is not us)\n", u.dest);
        else if (rc == KELP_ERR_NOTFOUND) fprintf(r->out, "mac_update remove: no such slot\n");
        else if (rc) fprintf(r->out, "mac_update refused (%s)\n", kelp_strerror(rc));
        else fprintf(r->out, "mac_update slots=%zu cycle=%u\n", r->node.mac.n, kelp_mac_cycle_length(&r->node.mac));
        return;
    }
    char *w[64];
    int n = split(line, w, 64);
    if (n == 0) return;
    double d;
    long v;
    if (!strcmp(w[0], "time")) {
        if (n != 2 || !parse_num(w[1], &d)) {
            error(r, "time needs seconds since the start");
            return;
        }
        int64_t t = r->start_us + (int64_t)llround(d * 1e6);
        if (t < r->now_us) {
            error(r, "time cannot go backwards");
            return;
        }
        advance_to(r, t);
    } else if (!strcmp(w[0], "advance")) {
        if (n != 2 || !parse_num(w[1], &d) || d < 0) {
            error(r, "advance needs a number of seconds >= 0");
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
        if (n != 2 || !parse_int(w[1], &v) || v < 0 || v > 31) {
            error(r, "heard needs a modem id");
            return;
        }
        kelp_acomms_node_heard(&r->node, (int)v, r->now_us);
        stamp(r);
        fprintf(r->out, "heard id=%ld slots=%zu cycle=%u\n", v, r->node.mac.n, kelp_mac_cycle_length(&r->node.mac));
    } else if (!strcmp(w[0], "receive")) {
        cmd_receive(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "transmit")) {
        cmd_transmit(r, w + 1, n - 1);
    } else if (!strcmp(w[0], "status")) {
        cmd_status(r);
    } else if (!strcmp(w[0], "auto_request")) {
        if (n != 2 || (strcmp(w[1], "on") != 0 && strcmp(w[1], "off") != 0)) {
            error(r, "auto_request on|off");
            return;
        }
        r->auto_request = strcmp(w[1], "on") == 0;
    } else if (!strcmp(w[0], "echo")) {
        stamp(r);
        fputs("echo", r->out);
        for (int i = 1; i < n; i++) fprintf(r->out, " %s", w[i]);
        fputc('\n', r->out);
    } else {
        error(r, "unknown command \"%s\"", w[0]);
    }
}

/* ------------------------------------------------------------------ main */

/* --help after the options: what it does, the timeline language, the output */
static const char replay_more[] =
        "Replays a timeline against the Goby 1.1 priority queue and TDMA MAC (kelp's core, no modem,\n"
        "no clock: time comes only from the timeline) and prints what they do.  The queue and MAC\n"
        "configuration is the pAcommsHandler block of FILE.moos (modem_id, mac_cfg, queue_cfg with its\n"
        "message files and CCL queues, dccl_cfg); --xml adds DCCL message files (their <queuing>).\n"
        "Without --moos: modem id 1 (or --modem-id), MAC_NONE.  DCCL is encrypted as Goby 1.1 does\n"
        "(key SHA-256 of the passphrase, also of the empty one); --plain switches crypto off.\n"
        "The timeline starts at --start (default 1262304000 = 2010-01-01 00:00:00 UTC); TIMELINE is a\n"
        "file, or standard input when absent or \"-\".\n"
        "\n"
        "Input: one command per line; '#' starts a comment.\n"
        "  time T                       go to T seconds after the start (never backwards)\n"
        "  advance S                    let S seconds pass\n"
        "     (time passes in 0.1 s steps, as pAcommsHandler's AppTick 10: queue expiry, MAC slots;\n"
        "      at a slot of ours the frames are requested as the Micro-Modem driver does: frame 0..n-1\n"
        "      of the slot's rate, stopping at the first blank)\n"
        "  push MSG field=value ...     encode DCCL message MSG now and queue it (header fields by their\n"
        "                               <name>, e.g. Destination=3; arrays as name={1,2,3})\n"
        "  push_ccl HEX [dest=D] [ack=0|1]   queue CCL bytes (queue = the first byte)\n"
        "  data_request [dest=D] [frame=F] [bytes=N | rate=R]   one modem data request (frame 0 starts\n"
        "                               a packet; dest -1 = ask the queue; default 32 bytes)\n"
        "  transmit [dest=D] [rate=R]   what a data slot of ours does, now\n"
        "  ack FRAME [src=S] [dest=D]   the modem reports an ack of FRAME (Goby frame, from 0) sent to D\n"
        "                               (default us; an ack addressed to another modem is ignored)\n"
        "  flush QUEUE                  empty a queue (the queue manager's flush_queue)\n"
        "  receive SRC DEST HEX         a frame arrives from the modem (unstitched, filtered, decoded)\n"
        "  modem start                  start the Micro-Modem driver (its sentences print as nmea-out)\n"
        "  modem $CA...                 a sentence from the modem to the driver\n"
        "  cycle rate=R dest=D [ack=0|1] HEX|- ...   a cycle of ours with these frames: $CCCYC, then\n"
        "                               each $CADRQ answered from them, the rest empty (- = empty)\n"
        "  heard ID                     modem ID was heard (MAC_AUTO_DECENTRALIZED discovery)\n"
        "  mac_update TEXT              ACOMMS_MAC_CYCLE_UPDATE, e.g.\n"
        "                               mac_update dest: 1 update_type: ADD slot { src: 1 dest: 3 slot_seconds: 15 }\n"
        "  auto_request on|off          off: MAC slots are only reported (no data requests)\n"
        "  status                       print every queue's size and priority, and the MAC\n"
        "  echo TEXT                    copy TEXT to the output\n"
        "\n"
        "Output: one event per line, \"SECONDS EVENT key=value ...\" (SECONDS since the start, 3 decimals):\n"
        "  slot index=I transmit|ranging src= dest= rate= type=   a MAC slot of ours began\n"
        "  transmit src= dest= rate=                             an explicit transmit command\n"
        "  frame frame= request_dest= max_bytes= src= dest= ack= bytes= hex=   the queue answered a\n"
        "        data request (hex = the modem frame, stitched DCCL messages included)\n"
        "  frame ... blank dest= ack=                            nothing eligible: a blank frame\n"
        "  push queue= id= dest= bytes= hex=                     a message was offered to its queue\n"
        "  qsize queue= size=                                    a queue's size after a push or pop\n"
        "  ack queue= from= frame= hex=                          a message was acknowledged and removed\n"
        "  expire queue= dest= hex=                              a message outlived its ttl\n"
        "  receive queue= src= dest= hex= decoded=\"...\"          a received piece for us\n"
        "  flush queue=                                          a queue was emptied (then qsize)\n"
        "  nmea-out $CC...                                       the driver wrote a sentence\n"
        "  cycle rate= dest= ack= frames=                        a cycle of caller frames was handed over\n"
        "  modem-ack / modem-receive / modem-request / modem-bad-line / modem-retry   from the driver\n"
        "  ack-ignored / receive-ignored / mac_update / heard / status / echo   as named\n"
        "  error line=N reason                                   a bad command (the replay goes on;\n"
        "                                                        the exit status is 1)\n";

enum { O_MOOS = 256, O_BLOCK, O_XML, O_MODEM_ID, O_START, O_PASS, O_PLAIN };

static const kelp_cli cli = {
    .name = "kelp-acomms-replay",
    .purpose = "Replay a timeline against the Goby 1.1 priority queue and TDMA MAC and print what they do.",
    .synopsis = "[--moos=FILE.moos [--block=NAME]] [--xml=FILE]... [--modem-id=N]\n"
                " [--start=UNIXTIME] [--passphrase=PW | --plain] [TIMELINE]",
    .opts = (const kelp_cli_opt[]){
        { "moos", required_argument, O_MOOS, "FILE.moos", "queue and MAC configuration from this mission" },
        { "block", required_argument, O_BLOCK, "NAME", "... its ProcessConfig = NAME (default pAcommsHandler)" },
        { "xml", required_argument, O_XML, "FILE", "a DCCL message file (repeatable)" },
        { "modem-id", required_argument, O_MODEM_ID, "N", "our modem id, 1..31 (default 1)" },
        { "start", required_argument, O_START, "UNIXTIME", "time of the timeline's start (default 1262304000)" },
        { "passphrase", required_argument, O_PASS, "PW", "DCCL encryption passphrase" },
        { "plain", no_argument, O_PLAIN, NULL, "no DCCL encryption" },
        { NULL, 0, 0, NULL, NULL } },
    .more = replay_more,
};

static int load_config(replay *r, const char *moos, const char *block_name, char *err, size_t cap)
{
    kelp_mission_file mf;
    if (kelp_mission_load(&mf, moos) != KELP_OK) {
        snprintf(err, cap, "%s", mf.error);
        return KELP_ERR_PARSE;
    }
    int block = kelp_mission_block(&mf.m, "ProcessConfig", block_name);
    char dir[512];
    snprintf(dir, sizeof dir, "%s", moos);
    char *slash = strrchr(dir, '/');
    if (slash) *slash = '\0';
    else snprintf(dir, sizeof dir, ".");
    char e2[512];
    int rc = kelp_acomms_config_read(&mf.m, block, dir, &r->cfg, e2, sizeof e2, NULL, 0);
    if (rc) snprintf(err, cap, "%s: %s", moos, block < 0 ? "no ProcessConfig = pAcommsHandler block" : e2);
    kelp_mission_free(&mf);
    return rc;
}

int replay_main(int argc, char **argv)
{
    static replay R;
    replay *r = &R;
    memset(r, 0, sizeof *r);
    const char *moos = NULL, *block = "pAcommsHandler", *timeline = NULL, *pass = NULL;
    const char *xml[KELP_ACOMMS_MAX_FILES];
    size_t nxml = 0;
    long modem_id = -1;
    double start = 1262304000.0;
    bool plain = false;
    int o, status;
    while ((o = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        switch (o) {
        case KELP_CLI_EXIT: return status;
        case O_MOOS: moos = optarg; break;
        case O_BLOCK: block = optarg; break;
        case O_XML:
            if (nxml >= KELP_ACOMMS_MAX_FILES) return kelp_cli_error(&cli, "too many --xml files");
            xml[nxml++] = optarg;
            break;
        case O_MODEM_ID:
            if (!parse_int(optarg, &modem_id) || modem_id < 1 || modem_id > 31)
                return kelp_cli_error(&cli, "--modem-id must be 1..31");
            break;
        case O_START:
            if (!parse_num(optarg, &start) || start < 0) return kelp_cli_error(&cli, "bad --start '%s'", optarg);
            break;
        case O_PASS: pass = optarg; break;
        case O_PLAIN: plain = true; break;
        }
    }
    if (optind < argc) timeline = argv[optind++];
    if (optind < argc) return kelp_cli_error(&cli, "unexpected argument '%s'", argv[optind]);
    char err[1024];
    kelp_acomms_config_default(&r->cfg);
    r->cfg.modem_id = 1;
    if (moos && load_config(r, moos, block, err, sizeof err) != KELP_OK) {
        fprintf(stderr, "kelp-acomms-replay: %s\n", err);
        return 2;
    }
    if (modem_id > 0) r->cfg.modem_id = (int)modem_id;
    for (size_t i = 0; i < nxml; i++) {
        if (r->cfg.nfiles >= KELP_ACOMMS_MAX_FILES) break;
        snprintf(r->cfg.files[r->cfg.nfiles].path, sizeof r->cfg.files[0].path, "%s", xml[i]);
        r->cfg.files[r->cfg.nfiles++].manip = 0;
    }
    if (pass) {
        snprintf(r->cfg.crypto_passphrase, sizeof r->cfg.crypto_passphrase, "%s", pass);
        r->cfg.has_passphrase = true;
    }
    const char *files[KELP_ACOMMS_MAX_FILES];
    unsigned manips[KELP_ACOMMS_MAX_FILES];
    for (size_t i = 0; i < r->cfg.nfiles; i++) {
        files[i] = r->cfg.files[i].path;
        manips[i] = r->cfg.files[i].manip;
    }
    kelp_acomms_dccl_cfg dc;
    memset(&dc, 0, sizeof dc);
    dc.modem_id = (unsigned)r->cfg.modem_id;
    dc.passphrase = r->cfg.has_passphrase ? r->cfg.crypto_passphrase : NULL;
    dc.plaintext = plain;
    dc.lookup_path = r->cfg.modem_id_lookup_path;
    dc.have_origin = r->cfg.has_lat_origin && r->cfg.has_lon_origin;
    dc.lat_origin = r->cfg.lat_origin;
    dc.lon_origin = r->cfg.lon_origin;
    dc.files = files;
    dc.manips = manips;
    dc.nfiles = r->cfg.nfiles;
    r->dccl = kelp_acomms_dccl_open(&dc, err, sizeof err);
    if (!r->dccl) {
        fprintf(stderr, "kelp-acomms-replay: %s\n", err);
        return 2;
    }
    r->pool = calloc(KELP_ACOMMS_MAX_POOL, sizeof *r->pool);
    if (!r->pool) return 2;
    kelp_acomms_node_cfg nc;
    kelp_acomms_config_node(&r->cfg, &nc);
    nc.driver = KELP_ACOMMS_DRIVER_NONE;
    nc.loopback_channel = false;
    kelp_acomms_node_ops ops = { NULL, on_event, NULL };
    r->out = stdout;
    r->auto_request = true;
    r->start_us = r->now_us = (int64_t)llround(start * 1e6);
    int rc = kelp_acomms_node_init(&r->node, &nc, r->queues, KELP_ACOMMS_MAX_QUEUES, r->pool, KELP_ACOMMS_MAX_POOL, &ops, r);
    if (rc) {
        fprintf(stderr, "kelp-acomms-replay: %s\n", r->node.errmsg ? r->node.errmsg : kelp_strerror(rc));
        return 2;
    }
    size_t nm = kelp_acomms_dccl_count(r->dccl);
    for (size_t i = 0; i < nm && r->nq < KELP_ACOMMS_MAX_QUEUES; i++) {
        kelp_acomms_dccl_info info;
        if (kelp_acomms_dccl_info_get(r->dccl, i, &info) != KELP_OK) continue;
        kelp_queue_cfg q;
        kelp_acomms_queue_cfg_from_info(&info, &q);
        r->qname[r->nq] = info.name;
        r->qkey[r->nq++] = q.key;
        if (kelp_acomms_node_add_queue(&r->node, &q, r->now_us) != KELP_OK) {
            fprintf(stderr, "kelp-acomms-replay: queue %s: %s\n", info.name, r->node.errmsg);
            return 2;
        }
    }
    for (size_t i = 0; i < r->cfg.nccl && r->nq < KELP_ACOMMS_MAX_QUEUES; i++) {
        r->cfg.ccl[i].cfg.name = r->cfg.ccl[i].name;
        r->qname[r->nq] = r->cfg.ccl[i].name;
        r->qkey[r->nq++] = r->cfg.ccl[i].cfg.key;
        if (kelp_acomms_node_add_queue(&r->node, &r->cfg.ccl[i].cfg, r->now_us) != KELP_OK) {
            fprintf(stderr, "kelp-acomms-replay: queue %s: %s\n", r->cfg.ccl[i].name, r->node.errmsg);
            return 2;
        }
    }
    if (kelp_acomms_node_start(&r->node, r->now_us) != KELP_OK) {
        fprintf(stderr, "kelp-acomms-replay: %s\n", r->node.errmsg);
        return 2;
    }
    FILE *in = stdin;
    if (timeline && strcmp(timeline, "-") != 0) {
        in = fopen(timeline, "r");
        if (!in) {
            fprintf(stderr, "kelp-acomms-replay: cannot open %s\n", timeline);
            return 2;
        }
    }
    stamp(r);
    fprintf(r->out, "start modem_id=%d queues=%zu mac_slots=%zu cycle=%u unix=%.0f\n", r->cfg.modem_id, r->nq,
            r->node.mac.n, kelp_mac_cycle_length(&r->node.mac), start);
    char line[MAX_LINE];
    while (fgets(line, sizeof line, in)) {
        r->lineno++;
        if (!strchr(line, '\n') && !feof(in)) {
            error(r, "line too long");
            int c;
            while ((c = fgetc(in)) != EOF && c != '\n') {
            }
            continue;
        }
        run_line(r, line);
    }
    if (in != stdin) fclose(in);
    kelp_acomms_dccl_close(r->dccl);
    free(r->pool);
    return r->errors ? 1 : 0;
}
