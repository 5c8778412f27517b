/* kelp-acomms-replay: the timeline's commands (see the --help text in replay.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "replay.h"

void cmd_push(replay *r, char **w, int n)
{
    if (n < 1) {
        replay_error(r, "push needs a message name");
        return;
    }
    long idx = kelp_acomms_dccl_find_name(r->dccl, w[0]);
    if (idx < 0) {
        replay_error(r, "no DCCL message \"%s\"", w[0]);
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
    kelp_diag why;
    kelp_diag_clear(&why);
    if (kelp_acomms_dccl_encode_string(r->dccl, (size_t)idx, kv, replay_sec(r->now_us), m.data, sizeof m.data, &len,
                                       &why) != KELP_OK) {
        replay_error(r, "cannot encode: %s", kelp_diag_text(&why));
        return;
    }
    kelp_acomms_dccl_info info;
    if (kelp_acomms_dccl_info_get(r->dccl, (size_t)idx, &info) != KELP_OK) return;
    if (kelp_acomms_msg_from_dccl(&m, len, r->cfg.modem_id, info.id, replay_sec(r->now_us)) != KELP_OK) {
        replay_error(r, "encoded message too short");
        return;
    }
    replay_stamp(r);
    fprintf(r->out, "push queue=%s id=%u dest=%d bytes=%zu hex=", info.name, info.id, m.dest, len);
    replay_hex(r->out, m.data, len);
    fputc('\n', r->out);
    if (kelp_acomms_node_push(&r->h.node, &m, replay_sec(r->now_us)) != KELP_OK) replay_error(r, "push refused: %s", kelp_diag_text(&r->h.node.diag));
}

void cmd_push_ccl(replay *r, char **w, int n)
{
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    if (n < 1 || replay_hex_bytes(w[0], m.data, sizeof m.data, &m.len) != KELP_OK || m.len == 0) {
        replay_error(r, "push_ccl needs HEX bytes (the first byte is the CCL id)");
        return;
    }
    static const char *const keys[] = { "dest", "ack", NULL };
    if (!replay_known_opts(r, w + 1, n - 1, keys)) return;
    long v;
    const char *d = replay_opt(w + 1, n - 1, "dest"), *a = replay_opt(w + 1, n - 1, "ack");
    m.dest = d && replay_int(d, &v) ? (int)v : 0;
    if (a && replay_int(a, &v)) {
        m.ack_requested = v != 0;
        m.has_ack = true;
    }
    m.src = r->cfg.modem_id;
    m.has_time = true;
    m.time = replay_sec(r->now_us);
    m.key.type = KELP_QUEUE_CCL;
    m.key.id = m.data[0];
    replay_stamp(r);
    fprintf(r->out, "push queue=%s id=%u dest=%d bytes=%zu hex=%s\n", replay_name_of(r, m.key), (unsigned)m.key.id, m.dest, m.len,
            w[0]);
    if (kelp_acomms_node_push(&r->h.node, &m, replay_sec(r->now_us)) != KELP_OK) replay_error(r, "push refused: %s", kelp_diag_text(&r->h.node.diag));
}

void cmd_data_request(replay *r, char **w, int n)
{
    static const char *const keys[] = { "dest", "frame", "bytes", "rate", NULL };
    if (!replay_known_opts(r, w, n, keys)) return;
    long v;
    kelp_queue_request req;
    req.dest = -1;
    req.frame = 0;
    req.max_bytes = 32;
    const char *s;
    if ((s = replay_opt(w, n, "rate"))) {
        if (!replay_int(s, &v) || v < 0 || v > 5) {
            replay_error(r, "rate must be 0..5");
            return;
        }
        req.max_bytes = kelp_mmdriver_packet_size[v];
    }
    if ((s = replay_opt(w, n, "dest"))) {
        if (!replay_int(s, &v) || v < -1 || v > 31) {
            replay_error(r, "dest must be -1..31");
            return;
        }
        req.dest = (int)v;
    }
    if ((s = replay_opt(w, n, "frame"))) {
        if (!replay_int(s, &v) || v < 0 || v > 31) {
            replay_error(r, "frame must be 0..31");
            return;
        }
        req.frame = (uint32_t)v;
    }
    if ((s = replay_opt(w, n, "bytes"))) {
        if (!replay_int(s, &v) || v < 1 || v > KELP_MAX_ACOMMS_FRAME) {
            replay_error(r, "bytes must be 1..256");
            return;
        }
        req.max_bytes = (uint32_t)v;
    }
    kelp_acomms_msg out;
    if (kelp_acomms_node_data_request(&r->h.node, &req, replay_sec(r->now_us), &out) != KELP_OK)
        replay_error(r, "data request failed: %s", kelp_diag_text(&r->h.node.diag));
}

void cmd_ack(replay *r, char **w, int n)
{
    long frame, src = -1;
    if (n < 1 || !replay_int(w[0], &frame) || frame < 0) {
            replay_error(r, "ack needs a frame number");
            return;
        }
    static const char *const keys[] = { "src", "dest", NULL };
    if (!replay_known_opts(r, w + 1, n - 1, keys)) return;
    long dest = r->cfg.modem_id;
    const char *s = replay_opt(w + 1, n - 1, "src"), *d = replay_opt(w + 1, n - 1, "dest");
    if ((s && !replay_int(s, &src)) || (d && !replay_int(d, &dest))) {
        replay_error(r, "bad src or dest");
        return;
    }
    int k = kelp_acomms_node_ack(&r->h.node, (int)src, (int)dest, (uint32_t)frame, replay_sec(r->now_us));
    if (k == 0) {
        replay_stamp(r);
        if (dest != r->cfg.modem_id) fprintf(r->out, "ack-ignored frame=%ld (addressed to %ld, not us)\n", frame, dest);
        else fprintf(r->out, "ack-ignored frame=%ld (no message waits for it)\n", frame);
    }
}

void cmd_flush(replay *r, char **w, int n)
{
    for (size_t i = 0; i < r->h.nnames && n == 1; i++) {
        if (strcmp(r->h.names[i].name, w[0]) != 0) continue;
        replay_stamp(r);
        fprintf(r->out, "flush queue=%s\n", r->h.names[i].name);
        if (kelp_queue_flush(&r->h.node.q, r->h.names[i].key) != KELP_OK) replay_error(r, "flush failed");
        return;
    }
    replay_error(r, "flush needs the name of a queue");
}

void cmd_receive(replay *r, char **w, int n)
{
    long src, dest;
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    if (n < 3 || !replay_int(w[0], &src) || !replay_int(w[1], &dest) ||
        replay_hex_bytes(w[2], m.data, sizeof m.data, &m.len) != KELP_OK)
        {
            replay_error(r, "receive needs SRC DEST HEX");
            return;
        }
    m.src = (int)src;
    m.dest = (int)dest;
    m.has_time = true;
    m.time = replay_sec(r->now_us);
    int k = kelp_acomms_node_receive(&r->h.node, &m, replay_sec(r->now_us));
    if (k == 0) {
        replay_stamp(r);
        fprintf(r->out, "receive-ignored src=%ld dest=%ld (not for us, no queue, or malformed)\n", src, dest);
    }
}

void cmd_transmit(replay *r, char **w, int n)
{
    static const char *const keys[] = { "dest", "rate", NULL };
    if (!replay_known_opts(r, w, n, keys)) return;
    long dest = -1, rate = 0;
    const char *s;
    if ((s = replay_opt(w, n, "dest")) && (!replay_int(s, &dest) || dest < -1 || dest > 31))
        {
            replay_error(r, "dest must be -1..31");
            return;
        }
    if ((s = replay_opt(w, n, "rate")) && (!replay_int(s, &rate) || rate < 0 || rate > 5))
        {
            replay_error(r, "rate must be 0..5");
            return;
        }
    replay_stamp(r);
    fprintf(r->out, "transmit src=%d dest=%ld rate=%ld\n", r->cfg.modem_id, dest, rate);
    if (kelp_acomms_node_transmit(&r->h.node, r->cfg.modem_id, (int)dest, (unsigned)rate, replay_sec(r->now_us)) != KELP_OK)
        replay_error(r, "transmit failed: %s", kelp_diag_text(&r->h.node.diag));
}

/* modem start | modem $CA... : the driver, and a sentence from the modem */
void cmd_modem(replay *r, char **w, int n)
{
    if (n == 1 && !strcmp(w[0], "start")) {
        if (rmodem_start(&r->modem, r->cfg.modem_id, r->out, r->start_us, r->now_us) != KELP_OK)
            replay_error(r, "the modem driver cannot start");
    } else if (n == 1 && w[0][0] == '$') {
        if (!r->modem.on) replay_error(r, "modem: say \"modem start\" first");
        else if (rmodem_feed(&r->modem, w[0], r->now_us) != KELP_OK) replay_error(r, "modem: sentence not taken");
    } else {
        replay_error(r, "modem start | modem $CA...");
    }
}

/* cycle rate=R dest=D [ack=0|1] HEX|- ... : a cycle of ours with these frames */
void cmd_cycle(replay *r, char **w, int n)
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
                ok = !strcmp(w[i], "-") || replay_hex_bytes(w[i], fr[nf].data, sizeof fr[nf].data, &fr[nf].len) == KELP_OK;
                nf++;
            }
        } else if (!strncmp(w[i], "rate=", 5)) ok = replay_int(eq + 1, &rate) && rate >= 0 && rate <= 5;
        else if (!strncmp(w[i], "dest=", 5)) ok = replay_int(eq + 1, &dest) && dest >= 0 && dest <= 31;
        else if (!strncmp(w[i], "ack=", 4)) ok = replay_int(eq + 1, &ack) && (ack == 0 || ack == 1);
        else ok = false;
        if (!ok) {
            replay_error(r, "cycle: bad argument \"%s\"", w[i]);
            return;
        }
    }
    if (rate < 0 || dest < 0) {
        replay_error(r, "cycle needs rate=R and dest=D");
        return;
    }
    for (size_t i = 0; i < nf; i++) fr[i].src = r->cfg.modem_id, fr[i].dest = (int)dest, fr[i].ack_requested = ack == 1;
    replay_stamp(r);
    fprintf(r->out, "cycle rate=%ld dest=%ld ack=%ld frames=%zu\n", rate, dest, ack, nf);
    int rc = rmodem_cycle(&r->modem, (unsigned)rate, fr, nf, r->now_us);
    if (rc == KELP_ERR_STATE) replay_error(r, "cycle: say \"modem start\" first");
    else if (rc != KELP_OK) replay_error(r, "cycle: rate %ld carries %u frames", rate, kelp_mmdriver_packet_frames[rate]);
}

void cmd_status(replay *r)
{
    for (size_t i = 0; i < r->h.nnames; i++) {
        double p = 0;
        if (kelp_queue_priority(&r->h.node.q, r->h.names[i].key, replay_sec(r->now_us), &p) != KELP_OK) p = NAN;
        replay_stamp(r);
        fprintf(r->out, "status queue=%s size=%ld priority=%.6g\n", r->h.names[i].name, kelp_queue_size(&r->h.node.q, r->h.names[i].key),
                p);
    }
    kelp_time next = kelp_mac_next_slot_time(&r->h.node.mac);
    replay_stamp(r);
    fprintf(r->out, "status mac slots=%zu cycle=%u next_slot=%.3f\n", r->h.node.mac.n, kelp_mac_cycle_length(&r->h.node.mac),
            next < 0 ? -1.0 : (double)(replay_us(next) - r->start_us) / 1e6);
}
