/* kelp-acomms-replay: what the Goby 1.1 queue and MAC do with a scripted timeline.
 * Deterministic: the only clock is the timeline's. See replay_more for the language.  The
 * queues, MAC and DCCL codec are set up as pAcommsHandler sets them up, by the core handler
 * (kelp_acomms_handler); the timeline's commands (commands.c, timeline.c) drive its node. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/edge/cli.h>
#include <kelp/edge/mission.h>

#include "replay.h"

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
    kelp_diag e2;
    kelp_diag_clear(&e2);
    int rc = kelp_acomms_config_read(&mf.m, block, dir, &r->cfg, &e2, NULL, 0);
    if (rc) snprintf(err, cap, "%s: %s", moos, block < 0 ? "no ProcessConfig = pAcommsHandler block" : kelp_diag_text(&e2));
    kelp_mission_free(&mf);
    return rc;
}

/* the replay prints node events; the bus publications of the handler go nowhere */
static int no_publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx, (void)var, (void)is_string, (void)sval, (void)dval;
    return 0;
}

static int open_dccl(replay *r, bool plain, char *err, size_t cap)
{
    kelp_diag d;
    kelp_diag_clear(&d);
    r->dccl = kelp_acomms_dccl_open_config(&r->cfg, plain, &d);
    if (!r->dccl) {
        snprintf(err, cap, "%s", kelp_diag_text(&d));
        return KELP_ERR_PARSE;
    }
    kelp_acomms_dccl_codec(r->dccl, &r->codec);
    return KELP_OK;
}

/* the handler over the configuration: no driver, no in-process channel, node events printed */
static int start_handler(replay *r)
{
    r->pool = calloc(KELP_ACOMMS_MAX_POOL, sizeof *r->pool);
    if (!r->pool) return KELP_ERR_NOSPACE;
    kelp_acomms_node_cfg nc;
    kelp_acomms_config_node(&r->cfg, &nc);
    nc.driver = KELP_ACOMMS_DRIVER_NONE;
    nc.loopback_channel = false;
    const kelp_acomms_sink sink = { r, no_publish, NULL, NULL, NULL, NULL, NULL, replay_on_event };
    double now = replay_sec(r->now_us);
    int rc = kelp_acomms_handler_init(&r->h, &r->cfg, &nc, &r->codec, r->pool, KELP_ACOMMS_MAX_POOL, &sink, now);
    if (rc && r->h.err_queue) {
        fprintf(stderr, "kelp-acomms-replay: queue %s: %s\n", r->h.err_queue, kelp_diag_text(&r->h.diag));
        return rc;
    }
    if (!rc) rc = kelp_acomms_handler_start(&r->h, false, now);
    if (rc) fprintf(stderr, "kelp-acomms-replay: %s\n", kelp_diag_text(&r->h.diag));
    return rc;
}

static void run(replay *r, FILE *in, double start)
{
    replay_stamp(r);
    fprintf(r->out, "start modem_id=%d queues=%zu mac_slots=%zu cycle=%u unix=%.0f\n", r->cfg.modem_id, r->h.nnames,
            r->h.node.mac.n, kelp_mac_cycle_length(&r->h.node.mac), start);
    char line[MAX_LINE];
    while (fgets(line, sizeof line, in)) {
        r->lineno++;
        if (!strchr(line, '\n') && !feof(in)) {
            replay_error(r, "line too long");
            int c;
            while ((c = fgetc(in)) != EOF && c != '\n') {
            }
            continue;
        }
        replay_run_line(r, line);
    }
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
            if (!replay_int(optarg, &modem_id) || modem_id < 1 || modem_id > 31)
                return kelp_cli_error(&cli, "--modem-id must be 1..31");
            break;
        case O_START:
            if (!replay_num(optarg, &start) || start < 0) return kelp_cli_error(&cli, "bad --start '%s'", optarg);
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
    if (open_dccl(r, plain, err, sizeof err) != KELP_OK) {
        fprintf(stderr, "kelp-acomms-replay: %s\n", err);
        return 2;
    }
    r->out = stdout;
    r->auto_request = true;
    r->start_us = r->now_us = (int64_t)llround(start * 1e6);
    if (start_handler(r) != KELP_OK) return 2;
    FILE *in = stdin;
    if (timeline && strcmp(timeline, "-") != 0) {
        in = fopen(timeline, "r");
        if (!in) {
            fprintf(stderr, "kelp-acomms-replay: cannot open %s\n", timeline);
            return 2;
        }
    }
    run(r, in, start);
    if (in != stdin) fclose(in);
    kelp_acomms_dccl_close(r->dccl);
    free(r->pool);
    return r->errors ? 1 : 0;
}
