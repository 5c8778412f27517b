/* kelp-logcheck: decode every event of an LCM log with kelp's types.
 *
 *   kelp-logcheck [--print] LOGFILE
 *
 * Every event must decode with kelp's validating decoder and, for kelp.var_t and
 * kelp.sync_req_t, with the lcm-gen decoder too, to the same fields. Prints a line per
 * channel (events, kind) and exits 1 if any event does not decode. The log is read with
 * kelp's own reader: a damaged stretch is skipped to the next event and reported, and an
 * event with an empty channel does not end the log. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/edge/lcmlog.h>
#include <kelp/edge/cli.h>
#include <kelp/bus.h>
#include "kelp_var_t.h"
#include "kelp_sync_req_t.h"
#include <kelp/udpm.h>

/* the lcm-gen decoder read every byte but a publisher's padding (segmented sends) */
static bool decoded_all(int used, const void *data, int datalen)
{
    return used >= 0 && used <= datalen && kelp_udpm_padding_only(data, (size_t)used, (size_t)datalen);
}

typedef struct chan { char name[128]; long n, bad; char kind[16]; } chan;

int main(int argc, char **argv)
{
    const kelp_cli cli = {
        .name = "kelp-logcheck",
        .purpose = "Decode every event of an LCM log with kelp's types (and lcm-gen's for kelp.var_t and\n"
                   "kelp.sync_req_t, to the same fields); a line per channel; exit 1 if any event does not decode.",
        .synopsis = "[--print] LOGFILE",
        .opts = (const kelp_cli_opt[]){ { "print", no_argument, 'p', NULL, "print every event" },
                                        { NULL, 0, 0, NULL, NULL } },
    };
    int opt, status, print = 0;
    while ((opt = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        if (opt == KELP_CLI_EXIT) return status;
        if (opt == 'p') print = 1;
    }
    if (argc - optind != 1) {
        kelp_cli_usage(&cli, stderr);
        return kelp_cli_error(&cli, argc == optind ? "no log file given" : "one log file at a time");
    }
    const char *path = argv[optind];
    kelp_diag err = {0};
    kelp_lcmlog_reader *log = kelp_lcmlog_open(path, 0, &err);
    if (!log) {
        fprintf(stderr, "kelp-logcheck: %s\n", kelp_diag_text(&err));
        return 1;
    }
    static chan chans[1024];
    int nch = 0;
    long total = 0, bad = 0;
    kelp_var *v = malloc(sizeof *v);
    kelp_sync_req q;
    kelp_lcmlog_event ev;
    const char *channel;
    int rr;
    while ((rr = kelp_lcmlog_next(log, &ev, &channel)) > 0) {
        if (strcmp(channel, "LCM_SELF_TEST") == 0) continue; /* liblcm's own probe, not a kelp type */
        const uint8_t *data = ev.data;
        int datalen = (int)ev.data_len;
        total++;
        chan *c = NULL;
        for (int i = 0; i < nch; i++)
            if (strcmp(chans[i].name, channel) == 0) c = &chans[i];
        if (!c && nch < 1024) {
            c = &chans[nch++];
            snprintf(c->name, sizeof c->name, "%s", channel);
        }
        int ok = 0;
        if (strcmp(channel, KELP_BUS_SYNC_CHANNEL) == 0) {
            kelp_sync_req_t g;
            ok = kelp_bus_sync_req_decode(data, (size_t)datalen, &q) == 0 &&
                 decoded_all(kelp_sync_req_t_decode(data, 0, datalen, &g), data, datalen);
            if (ok) {
                ok = strcmp(g.reply_channel, q.reply_channel) == 0 && g.npatterns == q.npatterns;
                kelp_sync_req_t_decode_cleanup(&g);
            }
            if (c) snprintf(c->kind, sizeof c->kind, "sync_req_t");
        } else {
            kelp_var_t g;
            ok = kelp_var_decode(data, (size_t)datalen, v) == 0 &&
                 decoded_all(kelp_var_t_decode(data, 0, datalen, &g), data, datalen);
            if (ok) {
                ok = strcmp(g.name, v->name) == 0 && strcmp(g.source, v->source) == 0 &&
                     strcmp(g.community, v->community) == 0 && g.kind == (int8_t)v->kind &&
                     (v->kind != KELP_VAR_DOUBLE || g.dval == v->dval) &&
                     (v->kind != KELP_VAR_STRING || strcmp(g.sval, v->sval) == 0) &&
                     (v->kind != KELP_VAR_BINARY || ((size_t)g.nbytes == v->slen && memcmp(g.bval, v->sval, v->slen) == 0));
                kelp_var_t_decode_cleanup(&g);
            }
            if (c) snprintf(c->kind, sizeof c->kind, "var_t");
            /* --print lists bus writes; sync replies (retained values replayed to a late
             * registrant on its own channel) are not new writes */
            if (ok && print && strcmp(channel, v->name) == 0) {
                if (v->kind == KELP_VAR_DOUBLE) printf("%.3f %s %s %.17g\n", v->time, v->source, v->name, v->dval);
                else if (v->kind == KELP_VAR_STRING) printf("%.3f %s %s %s\n", v->time, v->source, v->name, v->sval);
            }
        }
        if (c) c->n++;
        if (!ok) {
            bad++;
            if (c) c->bad++;
        }
    }
    fflush(stdout); /* the listing first: a warning below must not land inside a buffered line */
    kelp_lcmlog_stats st = kelp_lcmlog_get_stats(log);
    kelp_lcmlog_close(log);
    free(v);
    if (rr < 0) fprintf(stderr, "kelp-logcheck: read error in %s\n", path);
    if (st.damaged || st.truncated)
        fprintf(stderr, "kelp-logcheck: %s: %zu damaged stretch(es), %zu bytes skipped%s\n", path, st.damaged,
                st.skipped_bytes, st.truncated ? ", the file ends inside an event" : "");
    if (!print) {
        for (int i = 0; i < nch; i++)
            printf("  %-32s %-11s %7ld events%s\n", chans[i].name[0] ? chans[i].name : "(empty channel)", chans[i].kind, chans[i].n,
                   chans[i].bad ? "  <- UNDECODABLE" : "");
        printf("kelp-logcheck: %ld events on %d channels, %ld undecodable\n", total, nch, bad);
    }
    return (bad || total == 0 || rr < 0 || st.damaged) ? 1 : 0; /* a cut last event is a logger stopped mid-write */
}
