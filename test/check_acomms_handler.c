/* kelp acomms handler (pAcommsHandler's logic): mail in, queue, frames, publications out
 * through a recording sink.  The DCCL codec is a fake with one message, "Status" (id 5): a
 * 6-byte DCCL header and the 16-bit value of SPEED; decoding publishes SPEED_IN. */
#include <check.h>
#include <stdio.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/nmea.h>

#define T0 1262304000.0

/* ------------------------------------------------------------------ the fake codec */

typedef struct fake_codec {
    unsigned manip;
    double speed;
    int dest;
    unsigned encodes, decodes, describes;
} fake_codec;

static size_t f_count(void *ctx)
{
    (void)ctx;
    return 1;
}

static int f_info(void *ctx, size_t i, kelp_acomms_dccl_info *out)
{
    fake_codec *f = ctx;
    if (i != 0) return KELP_ERR_ARG;
    memset(out, 0, sizeof *out);
    out->name = "Status";
    out->id = 5;
    out->size = 8;
    out->trigger = 1;
    out->trigger_var = "STATUS_TRIGGER";
    out->in_var = "IN_STATUS_HEX_8B";
    out->out_var = "OUT_STATUS_HEX_8B";
    out->manip = f->manip;
    out->ack = false;
    out->newest_first = true;
    out->value_base = 1;
    out->ttl = 1800;
    return KELP_OK;
}

static long f_find_id(void *ctx, unsigned id)
{
    (void)ctx;
    return id == 5 ? 0 : -1;
}

static size_t f_nvars(void *ctx)
{
    (void)ctx;
    return 2;
}

static const char *f_var_name(void *ctx, size_t i)
{
    (void)ctx;
    return i == 0 ? "SPEED" : i == 1 ? "STATUS_TRIGGER" : NULL;
}

static void f_set_var(void *ctx, const char *name, bool is_double, double dval, const char *sval)
{
    fake_codec *f = ctx;
    (void)sval;
    if (strcmp(name, "SPEED") == 0 && is_double) f->speed = dval;
}

static size_t f_triggered(void *ctx, const char *name, size_t *idx, size_t cap)
{
    (void)ctx;
    if (strcmp(name, "STATUS_TRIGGER") != 0 || cap < 1) return 0;
    idx[0] = 0;
    return 1;
}

static void f_start(void *ctx, double now)
{
    (void)ctx;
    (void)now;
}

static size_t f_due(void *ctx, double now, size_t *idx, size_t cap)
{
    (void)ctx;
    (void)now;
    (void)idx;
    (void)cap;
    return 0;
}

static int f_encode(void *ctx, size_t i, double now, uint8_t *out, size_t cap, size_t *len, kelp_diag *d)
{
    fake_codec *f = ctx;
    (void)now;
    if (i != 0 || cap < 8) return kelp_fail(d, KELP_ERR_ARG, "no such message");
    kelp_queue_header hd = { KELP_DCCL_CCL_ID, 5, 0, 1, (unsigned)f->dest, false, false, 0 };
    kelp_queue_header_write(&hd, out);
    unsigned v = (unsigned)f->speed;
    out[6] = (uint8_t)(v >> 8);
    out[7] = (uint8_t)v;
    *len = 8;
    f->encodes++;
    return KELP_OK;
}

static int f_decode(void *ctx, const uint8_t *in, size_t n, double now, kelp_acomms_pub_fn fn, void *user,
                    kelp_diag *d)
{
    fake_codec *f = ctx;
    (void)now;
    kelp_queue_header hd;
    if (kelp_queue_header_read(in, n, &hd) != KELP_OK || hd.id != 5 || n != 8)
        return kelp_fail(d, KELP_ERR_PARSE, "not a Status message");
    f->decodes++;
    fn("SPEED_IN", true, (double)((unsigned)in[6] << 8 | in[7]), NULL, user);
    char text[32];
    snprintf(text, sizeof text, "src=%u", hd.src);
    fn("STATUS_FROM", false, 0, text, user);
    return KELP_OK;
}

static int f_describe(void *ctx, const uint8_t *in, size_t n, double now, char *buf, size_t cap)
{
    fake_codec *f = ctx;
    (void)now;
    f->describes++;
    snprintf(buf, cap, "Status: speed=%u", n == 8 ? (unsigned)in[6] << 8 | in[7] : 0u);
    return KELP_OK;
}

static fake_codec fc;
static const kelp_acomms_codec codec = { &fc,     f_count, f_info,      f_find_id, f_nvars, f_var_name, f_set_var,
                                         f_triggered, f_start, f_due, f_encode,  f_decode, f_describe };

/* ------------------------------------------------------------------ the recording sink */

#define MAXP 64
typedef struct pub {
    char var[64];
    bool is_string;
    char sval[KELP_ACOMMS_MAX_PRINT];
    double dval;
} pub;

static pub pubs[MAXP];
static int npub;
static char warns[16][512], events[16][512];
static int nwarn, nevent;
static kelp_acomms_rec_kind rec_kind[MAXP];
static char rec_channel[MAXP][48], rec_decoded[MAXP][64];
static int nrec, nwrite, nclose;

static int s_publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx;
    ck_assert_int_lt(npub, MAXP);
    pub *p = &pubs[npub++];
    snprintf(p->var, sizeof p->var, "%s", var);
    p->is_string = is_string;
    snprintf(p->sval, sizeof p->sval, "%s", is_string ? sval : "");
    p->dval = dval;
    return 0;
}

static void s_warn(void *ctx, const char *msg)
{
    (void)ctx;
    ck_assert_int_lt(nwarn, 16);
    snprintf(warns[nwarn++], sizeof warns[0], "%s", msg);
}

static void s_event(void *ctx, const char *msg)
{
    (void)ctx;
    ck_assert_int_lt(nevent, 16);
    snprintf(events[nevent++], sizeof events[0], "%s", msg);
}

static void s_write(void *ctx, const char *bytes, size_t len)
{
    (void)ctx;
    (void)bytes;
    (void)len;
    nwrite++;
}

static void s_close(void *ctx)
{
    (void)ctx;
    nclose++;
}

static void s_record(void *ctx, const kelp_acomms_record *r)
{
    (void)ctx;
    ck_assert_int_lt(nrec, MAXP);
    rec_kind[nrec] = r->kind;
    snprintf(rec_channel[nrec], sizeof rec_channel[0], "%s", r->channel);
    snprintf(rec_decoded[nrec], sizeof rec_decoded[0], "%s", r->decoded ? r->decoded : "");
    nrec++;
}

static const pub *find_pub(const char *var)
{
    for (int i = 0; i < npub; i++)
        if (strcmp(pubs[i].var, var) == 0) return &pubs[i];
    return NULL;
}

static int count_pub(const char *var)
{
    int n = 0;
    for (int i = 0; i < npub; i++) n += strcmp(pubs[i].var, var) == 0;
    return n;
}

static int find_rec(const char *channel)
{
    for (int i = 0; i < nrec; i++)
        if (strcmp(rec_channel[i], channel) == 0) return i;
    return -1;
}

static void clear(void)
{
    npub = nwarn = nevent = nrec = nwrite = nclose = 0;
}

/* ------------------------------------------------------------------ set-up */

static kelp_acomms_config cfg;
static kelp_acomms_handler h;
static kelp_queue_entry pool[32];

static void setup_cfg(kelp_acomms_driver_type driver)
{
    memset(&cfg, 0, sizeof cfg);
    cfg.modem_id = 1;
    cfg.driver_type = driver;
    cfg.mac_type = KELP_MAC_NONE;
    cfg.verbosity = KELP_ACOMMS_VERBOSITY_WARN;
    /* one CCL queue (id 3) fed from OUT_CCL, published on IN_CCL */
    kelp_queue_cfg_default(&cfg.ccl[0].cfg, KELP_QUEUE_CCL, 3);
    snprintf(cfg.ccl[0].name, sizeof cfg.ccl[0].name, "Remus");
    snprintf(cfg.ccl[0].in_var, sizeof cfg.ccl[0].in_var, "IN_CCL");
    snprintf(cfg.ccl[0].out_var, sizeof cfg.ccl[0].out_var, "OUT_CCL");
    cfg.nccl = 1;
}

static void start_handler(kelp_acomms_driver_type driver, unsigned manip, bool with_records)
{
    memset(&fc, 0, sizeof fc);
    fc.manip = manip;
    fc.dest = 2;
    setup_cfg(driver);
    kelp_acomms_node_cfg nc;
    kelp_acomms_node_cfg_default(&nc);
    nc.modem_id = 1;
    nc.driver = driver;
    nc.mm.modem_id = 1;
    kelp_acomms_sink sink = { NULL, s_publish, s_warn, s_event, s_write, s_close, with_records ? s_record : NULL, NULL };
    clear();
    ck_assert_int_eq(kelp_acomms_handler_init(&h, &cfg, &nc, &codec, pool, 32, &sink, T0), 0);
    ck_assert_int_eq(kelp_acomms_handler_start(&h, false, T0), 0);
}

static kelp_var mail_d(const char *name, double d)
{
    kelp_var v;
    memset(&v, 0, sizeof v);
    snprintf(v.name, sizeof v.name, "%s", name);
    v.kind = KELP_VAR_DOUBLE;
    v.dval = d;
    return v;
}

static kelp_var mail_s(const char *name, const char *s)
{
    kelp_var v;
    memset(&v, 0, sizeof v);
    snprintf(v.name, sizeof v.name, "%s", name);
    v.kind = KELP_VAR_STRING;
    v.slen = strlen(s);
    memcpy(v.sval, s, v.slen + 1);
    return v;
}

/* ------------------------------------------------------------------ tests */

START_TEST(test_handler_init_and_subscriptions)
{
    memset(&fc, 0, sizeof fc);
    setup_cfg(KELP_ACOMMS_DRIVER_NONE);
    kelp_acomms_node_cfg nc;
    kelp_acomms_node_cfg_default(&nc);
    nc.modem_id = 1;
    kelp_acomms_sink sink = { NULL, s_publish, NULL, s_event, NULL, NULL, NULL, NULL };
    clear();
    ck_assert_int_eq(kelp_acomms_handler_init(&h, &cfg, &nc, &codec, pool, 32, &sink, T0), 0);
    /* MODEM_ID and VEHICLE_ID at the end of init */
    /* each queue's size as it is added, then MODEM_ID and VEHICLE_ID */
    ck_assert_int_eq(npub, 4);
    ck_assert_str_eq(pubs[0].var, "ACOMMS_QSIZE");
    ck_assert_str_eq(pubs[0].sval, "key { type: QUEUE_DCCL id: 5 } size: 0");
    ck_assert_str_eq(pubs[1].sval, "key { type: QUEUE_CCL id: 3 } size: 0");
    ck_assert_str_eq(pubs[2].var, "MODEM_ID");
    ck_assert(!pubs[2].is_string && pubs[2].dval == 1);
    ck_assert_str_eq(pubs[3].var, "VEHICLE_ID");
    ck_assert_uint_eq(h.nnames, 2);
    static const char *const want[] = { "SPEED",   "STATUS_TRIGGER",          "IN_STATUS_HEX_8B",     "OUT_CCL",
                                        "ACOMMS_RANGE_COMMAND", "ACOMMS_MAC_CYCLE_UPDATE", "ACOMMS_POLLER_UPDATE" };
    size_t i = 0;
    for (const char *v; (v = kelp_acomms_handler_subscription(&h, i)) != NULL; i++) {
        ck_assert_uint_lt(i, 7);
        ck_assert_str_eq(v, want[i]);
    }
    ck_assert_uint_eq(i, 7);
    ck_assert_int_eq(kelp_acomms_handler_start(&h, false, T0), 0);
    ck_assert_int_eq(nevent, 1);
    ck_assert_str_eq(events[0], "modem_id 1, DRIVER_NONE (in-process channel), 1 DCCL messages, 1 CCL queues");
    ck_assert_str_eq(kelp_acomms_mac_name(KELP_MAC_POLLED), "MAC_POLLED");
    /* no publish callback: refused */
    sink.publish = NULL;
    ck_assert_int_eq(kelp_acomms_handler_init(&h, &cfg, &nc, &codec, pool, 32, &sink, T0), KELP_ERR_ARG);
}
END_TEST

/* mail -> encode -> ACOMMS_OUTGOING_DATA / OUT_ var / record -> queue -> a frame */
START_TEST(test_handler_trigger_encodes_and_queues)
{
    start_handler(KELP_ACOMMS_DRIVER_NONE, 0, true);
    clear();
    kelp_var v = mail_d("SPEED", 300);
    kelp_acomms_handler_mail(&h, &v, false, T0 + 1);
    ck_assert_int_eq(npub, 0); /* a source variable only */
    v = mail_s("STATUS_TRIGGER", "go");
    kelp_acomms_handler_mail(&h, &v, false, T0 + 2);
    ck_assert_uint_eq(fc.encodes, 1);
    ck_assert_uint_eq(h.count.encoded, 1);
    ck_assert_uint_eq(h.count.pushed, 1);
    const pub *p = find_pub("ACOMMS_OUTGOING_DATA");
    ck_assert_ptr_nonnull(p);
    ck_assert_ptr_nonnull(strstr(p->sval, "src: 1 dest: 2"));
    ck_assert_ptr_nonnull(strstr(p->sval, "queue_key { type: QUEUE_DCCL id: 5 }"));
    ck_assert_ptr_nonnull(find_pub("OUT_STATUS_HEX_8B"));
    ck_assert_str_eq(find_pub("OUT_STATUS_HEX_8B")->sval, p->sval);
    ck_assert_ptr_nonnull(strstr(find_pub("ACOMMS_QSIZE")->sval, "size: 1"));
    int r = find_rec("ACOMMS_OUTGOING_DATA_LCM");
    ck_assert_int_ge(r, 0);
    ck_assert_int_eq(rec_kind[r], KELP_ACOMMS_REC_DATA);
    ck_assert_str_eq(rec_decoded[r], "Status: speed=300");
    ck_assert_int_ge(find_rec("ACOMMS_QSIZE_LCM"), 0);
    /* the modem asks for data: the queue hands out the message */
    kelp_queue_request req = { -1, 0, 32 };
    kelp_acomms_msg out;
    ck_assert_int_eq(kelp_acomms_node_data_request(&h.node, &req, T0 + 3, &out), 0);
    ck_assert_uint_eq(out.len, 8);
    ck_assert_int_eq(out.dest, 2);
    ck_assert_int_eq(out.data[6] << 8 | out.data[7], 300);
    ck_assert_int_eq(kelp_queue_size(&h.node.q, (kelp_queue_key){ KELP_QUEUE_DCCL, 5 }), 0);
    /* a trigger of another variable does nothing; no warnings so far */
    v = mail_s("OTHER", "x");
    kelp_acomms_handler_mail(&h, &v, false, T0 + 4);
    ck_assert_uint_eq(fc.encodes, 1);
    ck_assert_int_eq(nwarn, 0);
}
END_TEST

/* a frame from the modem: ACOMMS_INCOMING_DATA, the IN_ var, decoded and published */
START_TEST(test_handler_incoming_frame_decoded)
{
    start_handler(KELP_ACOMMS_DRIVER_NONE, 0, true);
    clear();
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    kelp_queue_header hd = { KELP_DCCL_CCL_ID, 5, 0, 2, 1, false, false, 0 };
    kelp_queue_header_write(&hd, m.data);
    m.data[6] = 0x01;
    m.data[7] = 0x02;
    m.len = 8;
    m.src = 2;
    m.dest = 1;
    ck_assert_int_eq(kelp_acomms_node_receive(&h.node, &m, T0 + 5), 1);
    const pub *p = find_pub("ACOMMS_INCOMING_DATA");
    ck_assert_ptr_nonnull(p);
    ck_assert_ptr_nonnull(strstr(p->sval, "src: 2 dest: 1"));
    ck_assert_ptr_nonnull(find_pub("IN_STATUS_HEX_8B"));
    p = find_pub("SPEED_IN");
    ck_assert_ptr_nonnull(p);
    ck_assert(!p->is_string);
    ck_assert_double_eq(p->dval, 258);
    ck_assert_str_eq(find_pub("STATUS_FROM")->sval, "src=2");
    ck_assert_uint_eq(h.count.decoded, 1);
    ck_assert_uint_eq(h.count.in_data, 1);
    int r = find_rec("ACOMMS_INCOMING_DATA_LCM");
    ck_assert_int_ge(r, 0);
    ck_assert_str_eq(rec_decoded[r], "Status: speed=258");
    /* a piece the codec cannot decode: a warning, counted */
    clear();
    m.data[7] = 0;
    m.len = 7;
    ck_assert_int_eq(kelp_acomms_node_receive(&h.node, &m, T0 + 6), 1);
    ck_assert_ptr_nonnull(find_pub("ACOMMS_INCOMING_DATA"));
    ck_assert_ptr_null(find_pub("SPEED_IN"));
    ck_assert_uint_eq(h.count.decode_errors, 1);
    ck_assert_int_eq(nwarn, 1);
#ifndef KELP_NO_ERRMSG
    ck_assert_str_eq(warns[0], "cannot decode a received DCCL message: not a Status message");
#else
    ck_assert_str_eq(warns[0], "cannot decode a received DCCL message: parse error"); /* the code's text */
#endif
    ck_assert_int_eq(h.diag.code, KELP_ERR_PARSE);
}
END_TEST

/* IN_ hex var from another process is decoded; our own is not */
START_TEST(test_handler_in_var_mail)
{
    start_handler(KELP_ACOMMS_DRIVER_NONE, 0, false);
    clear();
    /* data bytes of a Status from 3: header then 0x00 0x07 (escaped as TextFormat octal) */
    uint8_t b[8];
    kelp_queue_header hd = { KELP_DCCL_CCL_ID, 5, 0, 3, 1, false, false, 0 };
    kelp_queue_header_write(&hd, b);
    b[6] = 0;
    b[7] = 7;
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    memcpy(m.data, b, 8);
    m.len = 8;
    m.src = 3;
    m.dest = 1;
    char text[512];
    ck_assert_int_eq(kelp_acomms_print_data(&m, text, sizeof text, NULL), 0);
    kelp_var v = mail_s("IN_STATUS_HEX_8B", text);
    kelp_acomms_handler_mail(&h, &v, true, T0 + 1);
    ck_assert_int_eq(npub, 0);
    kelp_acomms_handler_mail(&h, &v, false, T0 + 1);
    ck_assert_double_eq(find_pub("SPEED_IN")->dval, 7);
    ck_assert_str_eq(find_pub("STATUS_FROM")->sval, "src=3");
    ck_assert_uint_eq(h.count.decoded, 1);
    /* not a ModemDataTransmission: bad mail */
    v = mail_d("IN_STATUS_HEX_8B", 1);
    kelp_acomms_handler_mail(&h, &v, false, T0 + 2);
    ck_assert_uint_eq(h.count.bad_mail, 1);
    ck_assert_str_eq(warns[nwarn - 1], "bad IN_STATUS_HEX_8B: not a string");
    /* no records wanted: nothing was described */
    ck_assert_uint_eq(fc.describes, 0);
}
END_TEST

/* CCL mail is queued as it is; commands refused or bad are warnings */
START_TEST(test_handler_ccl_and_commands)
{
    start_handler(KELP_ACOMMS_DRIVER_NONE, 0, true);
    clear();
    kelp_var v = mail_s("OUT_CCL", "base { src: 1 dest: 4 } data: \"\\003\\001\\002\"");
    kelp_acomms_handler_mail(&h, &v, false, T0 + 1);
    ck_assert_uint_eq(h.count.ccl_out, 1);
    ck_assert_uint_eq(h.count.pushed, 1);
    const pub *p = find_pub("ACOMMS_OUTGOING_DATA");
    ck_assert_ptr_nonnull(p);
    ck_assert_ptr_nonnull(strstr(p->sval, "queue_key { type: QUEUE_CCL id: 3 }"));
    ck_assert_int_eq(count_pub("ACOMMS_OUTGOING_DATA"), 1);
    ck_assert_int_eq(kelp_queue_size(&h.node.q, (kelp_queue_key){ KELP_QUEUE_CCL, 3 }), 1);
    int r = find_rec("ACOMMS_OUTGOING_DATA_LCM");
    ck_assert_int_ge(r, 0);
    ck_assert_str_eq(rec_decoded[r], "");
    v = mail_s("OUT_CCL", "nonsense: 1");
    kelp_acomms_handler_mail(&h, &v, false, T0 + 2);
    ck_assert_uint_eq(h.count.bad_mail, 1);
    v = mail_d("ACOMMS_RANGE_COMMAND", 1);
    kelp_acomms_handler_mail(&h, &v, false, T0 + 3);
    ck_assert_uint_eq(h.count.bad_mail, 2);
    ck_assert_str_eq(warns[nwarn - 1], "bad ACOMMS_RANGE_COMMAND: not a string");
    v = mail_s("ACOMMS_RANGE_COMMAND", "base { src: 1 dest: 2 } type: MODEM_TWO_WAY_PING");
    kelp_acomms_handler_mail(&h, &v, false, T0 + 4);
    ck_assert_int_eq(h.node.diag.code, KELP_ERR_STATE);
#ifndef KELP_NO_ERRMSG
    ck_assert_str_eq(warns[nwarn - 1], "ranging refused: acomms: ranging needs a modem driver");
#endif
    /* MAC_NONE has no cycle to update */
    v = mail_s("ACOMMS_MAC_CYCLE_UPDATE", "dest: 1 update_type: REPLACE slot { src: 1 dest: 2 }");
    kelp_acomms_handler_mail(&h, &v, false, T0 + 5);
    ck_assert_int_lt(h.node.diag.code, 0);
#ifndef KELP_NO_ERRMSG
    ck_assert_str_eq(warns[nwarn - 1], "MAC update refused: acomms: MAC update refused");
#endif
    v = mail_s("ACOMMS_POLLER_UPDATE", "update_type: REPLACE");
    kelp_acomms_handler_mail(&h, &v, false, T0 + 5);
    ck_assert_uint_eq(h.count.bad_mail, 3);
}
END_TEST

/* LOOPBACK decodes right after the encode; status once a second when records are wanted */
START_TEST(test_handler_loopback_and_status)
{
    start_handler(KELP_ACOMMS_DRIVER_NONE, KELP_ACOMMS_MANIP_LOOPBACK, true);
    clear();
    kelp_var v = mail_d("SPEED", 12);
    kelp_acomms_handler_mail(&h, &v, false, T0 + 1);
    v = mail_s("STATUS_TRIGGER", "go");
    kelp_acomms_handler_mail(&h, &v, false, T0 + 1);
    ck_assert_double_eq(find_pub("SPEED_IN")->dval, 12);
    ck_assert_uint_eq(h.count.decoded, 1);
    clear();
    kelp_acomms_handler_tick(&h, T0 + 1.1);
    kelp_acomms_handler_tick(&h, T0 + 1.5);
    kelp_acomms_handler_tick(&h, T0 + 2.2);
    int n = 0;
    for (int i = 0; i < nrec; i++) n += rec_kind[i] == KELP_ACOMMS_REC_STATUS;
    ck_assert_int_eq(n, 2);
    ck_assert_int_eq(nclose, 0);
}
END_TEST

/* WHOI: the link's life (start-up sequence on the link, loss, re-established) */
START_TEST(test_handler_whoi_link)
{
    start_handler(KELP_ACOMMS_DRIVER_WHOI_MICROMODEM, 0, false);
    ck_assert(!h.link_up);
    int w0 = nwrite;
    clear();
    h.link_desc = "serial /dev/null";
    kelp_acomms_handler_link_up(&h, T0 + 1);
    ck_assert(h.link_up);
    ck_assert_str_eq(events[0], "modem link up: serial /dev/null");
    ck_assert_int_gt(nwrite, 0); /* the driver's start-up sequence went out */
    (void)w0;
    kelp_acomms_handler_link_lost(&h, "EOF");
    ck_assert(!h.link_up);
    ck_assert_str_eq(warns[0], "modem link lost: EOF");
    kelp_acomms_handler_link_up(&h, T0 + 2);
    ck_assert_uint_eq(h.count.reconnects, 1);
    ck_assert_str_eq(events[nevent - 1], "modem link re-established: serial /dev/null");
    /* bytes from the modem: an NMEA sentence is published on ACOMMS_NMEA_IN and kept */
    clear();
    static const char body[] = "CAREV,000000,INIT,0.93.0.30";
    char line[64];
    snprintf(line, sizeof line, "$%s*%02X\r\n", body, kelp_nmea_checksum(body, strlen(body)));
    kelp_acomms_handler_feed(&h, (const uint8_t *)line, strlen(line), T0 + 3);
    ck_assert_ptr_nonnull(find_pub("ACOMMS_NMEA_IN"));
    ck_assert_uint_eq(h.n_in, 1);
    ck_assert_uint_eq(h.count.nmea_in, 1);
}
END_TEST

/* WHOI: a modem that never answers -> retries, give-up, the driver dead: the link is closed
 * once (the caller reopens it), the link is down until link_up, which restarts the driver */
START_TEST(test_handler_whoi_driver_dead)
{
    start_handler(KELP_ACOMMS_DRIVER_WHOI_MICROMODEM, 0, false);
    clear();
    kelp_acomms_handler_link_up(&h, T0); /* the link was down at start: the start-up goes out now */
    ck_assert(h.link_up);
    ck_assert_int_gt(nwrite, 0);
    ck_assert_ptr_nonnull(find_pub("ACOMMS_NMEA_OUT"));
    double t = T0;
    for (int i = 0; i < 40 && nclose == 0; i++) {
        t += 1;
        kelp_acomms_handler_tick(&h, t);
    }
    ck_assert_int_eq(nclose, 1);
    ck_assert(!h.link_up);
    ck_assert_uint_ge(h.count.retries, 1);
    ck_assert_uint_eq(h.count.deaths, 1);
    bool said = false;
    for (int i = 0; i < nwarn; i++) said = said || strcmp(warns[i], "modem not responding: reconnecting the link") == 0;
    ck_assert(said);
    /* no second close while it stays dead */
    kelp_acomms_handler_tick(&h, t + 1);
    kelp_acomms_handler_tick(&h, t + 2);
    ck_assert_int_eq(nclose, 1);
    int w = nwrite;
    kelp_acomms_handler_link_up(&h, t + 3);
    ck_assert(h.link_up);
    ck_assert_uint_eq(h.count.reconnects, 1);
    ck_assert_int_gt(nwrite, w); /* the start-up sequence again */
}
END_TEST

Suite *kelp_acomms_handler_suite(void)
{
    Suite *s = suite_create("acomms_handler");
    TCase *t = tcase_create("handler");
    tcase_add_test(t, test_handler_init_and_subscriptions);
    tcase_add_test(t, test_handler_trigger_encodes_and_queues);
    tcase_add_test(t, test_handler_incoming_frame_decoded);
    tcase_add_test(t, test_handler_in_var_mail);
    tcase_add_test(t, test_handler_ccl_and_commands);
    tcase_add_test(t, test_handler_loopback_and_status);
    tcase_add_test(t, test_handler_whoi_link);
    tcase_add_test(t, test_handler_whoi_driver_dead);
    suite_add_tcase(s, t);
    return s;
}
