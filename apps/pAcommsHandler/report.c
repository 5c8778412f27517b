/* pAcommsHandler: the status report (the handler's state, read-only). */
#include <math.h>
#include <stdio.h>

#include "handler.h"

static int64_t us_of(double t)
{
    return (int64_t)llround(t * 1e6);
}

static void report_link(const handler *h, FILE *out)
{
    const kelp_acomms_handler *c = &h->core;
    fprintf(out, "link: %s  [%s]%s%s\n", kelp_link_describe(h->link),
            c->link_up ? "up" : (kelp_link_listening(h->link) ? "listening" : "DOWN"),
            kelp_link_error(h->link)[0] ? "  last error: " : "", kelp_link_error(h->link));
    const kelp_link_counters *lc = kelp_link_get_counters(h->link);
    fprintf(out, "      bytes in %llu out %llu, opens %u, failed opens %u, disconnects %u, reconnects %lu\n",
            (unsigned long long)lc->bytes_in, (unsigned long long)lc->bytes_out, lc->opens, lc->open_failures,
            lc->disconnects, c->count.reconnects);
}

void handler_report(kelp_app *app, void *state, FILE *out)
{
    handler *h = state;
    (void)app;
    kelp_acomms_handler *c = &h->core;
    if (!c->started) return;
    const kelp_acomms_handler_counters *k = &c->count;
    kelp_mmdriver *mm = kelp_acomms_node_driver(&c->node);
    fprintf(out, "modem_id %d   driver %s\n", h->cfg.modem_id,
            h->cfg.driver_type == KELP_ACOMMS_DRIVER_NONE ? "DRIVER_NONE (in-process channel)" : "DRIVER_WHOI_MICROMODEM");
    if (h->link) report_link(h, out);
    if (mm)
        fprintf(out,
                "modem: clock %s, %zu command(s) pending, lines in %u out %u, bad %u, retries %u, give-ups %u, "
                "$CAERR %u, dead %lu\n",
                kelp_mmdriver_clock_ok(mm) ? "ok" : "not set", kelp_mmdriver_pending(mm), mm->count.lines_in,
                mm->count.lines_out, mm->count.bad_lines, mm->count.retries, mm->count.give_ups, mm->count.modem_errors,
                k->deaths);
    kelp_time next = kelp_mac_next_slot_time(&c->node.mac);
    fprintf(out, "MAC: %s, %zu slot(s), cycle %u s", kelp_acomms_mac_name(h->cfg.mac_type), c->node.mac.n,
            kelp_mac_cycle_length(&c->node.mac));
    if (next >= 0) fprintf(out, ", next slot in %.1f s", (double)(us_of(next) - us_of(c->now)) / 1e6);
    fprintf(out, ", %u slot(s) fired, %u skipped (link down)\n", c->node.count.slots, c->node.count.slots_skipped);
    fprintf(out, "%-24s %-6s %5s %9s\n", "queue", "key", "size", "priority");
    for (size_t i = 0; i < c->nnames; i++) {
        const kelp_acomms_qname *n = &c->names[i];
        double p = 0;
        if (kelp_queue_priority(&c->node.q, n->key, c->now, &p) != KELP_OK) p = NAN;
        fprintf(out, "%-24.24s %s%-4u %5ld %9.3f\n", n->name ? n->name : "?", n->key.type == KELP_QUEUE_CCL ? "C" : "D",
                (unsigned)n->key.id, kelp_queue_size(&c->node.q, n->key), p);
    }
    fprintf(out,
            "DCCL: %lu encoded (%lu errors), %lu decoded (%lu errors); queued %lu (%lu refused); CCL out %lu in %lu\n",
            k->encoded, k->encode_errors, k->decoded, k->decode_errors, k->pushed, k->push_errors, k->ccl_out, k->ccl_in);
    fprintf(out, "frames out %u (blank %u), frames in %u, acks %lu, expired %lu, ranges %lu, bad mail %lu\n",
            c->node.count.frames_out, c->node.count.blank_frames, c->node.count.frames_in, k->acks, k->expires, k->ranges,
            k->bad_mail);
    if (h->cfg.verbosity >= KELP_ACOMMS_VERBOSITY_VERBOSE && mm) {
        unsigned k0 = c->n_out > KELP_ACOMMS_NMEA_KEEP ? c->n_out - KELP_ACOMMS_NMEA_KEEP : 0;
        for (unsigned i = k0; i < c->n_out; i++) fprintf(out, "  > %s\n", c->last_out[i % KELP_ACOMMS_NMEA_KEEP]);
        k0 = c->n_in > KELP_ACOMMS_NMEA_KEEP ? c->n_in - KELP_ACOMMS_NMEA_KEEP : 0;
        for (unsigned i = k0; i < c->n_in; i++) fprintf(out, "  < %s\n", c->last_in[i % KELP_ACOMMS_NMEA_KEEP]);
    }
}
