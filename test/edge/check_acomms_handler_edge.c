/* kelp acomms handler with the real DCCL glue (example1.xml, plaintext) as its codec: a
 * trigger mail encodes the spec's GoToCommand vector, and the same bytes received from the
 * modem are decoded and their <publish> variables published. */
#include <check.h>
#include <stdio.h>
#include <string.h>

#include <kelp/acomms.h>

#ifndef KELP_TEST_ROOT
#define KELP_TEST_ROOT "."
#endif

#define NOON 1262347200.0 /* 2010-01-01 12:00:00 UTC: header time 43200 as the spec's vectors */

#define MAXP 32
static char pubs[MAXP][1200];
static int npub;

static int rec_publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx;
    ck_assert_int_lt(npub, MAXP);
    if (is_string) snprintf(pubs[npub++], sizeof pubs[0], "%s %s", var, sval);
    else snprintf(pubs[npub++], sizeof pubs[0], "%s %g", var, dval);
    return 0;
}

static const char *find(const char *var)
{
    size_t n = strlen(var);
    for (int i = 0; i < npub; i++)
        if (strncmp(pubs[i], var, n) == 0 && pubs[i][n] == ' ') return pubs[i] + n + 1;
    return NULL;
}

static kelp_acomms_handler h;
static kelp_acomms_config cfg;
static kelp_queue_entry pool[32];

static kelp_acomms_dccl *start(int modem_id)
{
    static const char *files[1];
    files[0] = KELP_TEST_ROOT "/missions/acomms/example1.xml";
    kelp_acomms_dccl_cfg c;
    memset(&c, 0, sizeof c);
    c.modem_id = (unsigned)modem_id;
    c.plaintext = true;
    c.files = files;
    c.nfiles = 1;
    kelp_diag err = {0};
    kelp_acomms_dccl *d = kelp_acomms_dccl_open(&c, &err);
    ck_assert_msg(d != NULL, "%s", kelp_diag_text(&err));
    kelp_acomms_codec codec;
    kelp_acomms_dccl_codec(d, &codec);
    kelp_acomms_config_default(&cfg);
    cfg.modem_id = modem_id;
    kelp_acomms_node_cfg nc;
    kelp_acomms_config_node(&cfg, &nc);
    kelp_acomms_sink sink = { NULL, rec_publish, NULL, NULL, NULL, NULL, NULL, NULL };
    npub = 0;
    ck_assert_int_eq(kelp_acomms_handler_init(&h, &cfg, &nc, &codec, pool, 32, &sink, NOON), 0);
    ck_assert_int_eq(kelp_acomms_handler_start(&h, false, NOON), 0);
    return d;
}

static kelp_var smail(const char *name, const char *s)
{
    kelp_var v;
    memset(&v, 0, sizeof v);
    snprintf(v.name, sizeof v.name, "%s", name);
    v.kind = KELP_VAR_STRING;
    v.slen = strlen(s);
    memcpy(v.sval, s, v.slen + 1);
    return v;
}

START_TEST(test_handler_dccl_out_and_in)
{
    /* modem 1 sends GoToCommand to 3 */
    kelp_acomms_dccl *d = start(1);
    kelp_var v = smail("SPECIAL_INSTRUCTIONS", "make_toast");
    kelp_acomms_handler_mail(&h, &v, false, NOON);
    v = smail("OUTGOING_COMMAND", "Destination=3,CommandType=GoTo,goto_x=351,goto_y=294,lights_on=true,"
                                  "special_instructions=make_toast,goto_speed=2.3");
    npub = 0;
    kelp_acomms_handler_mail(&h, &v, false, NOON);
    ck_assert_uint_eq(h.count.encoded, 1);
    ck_assert_ptr_nonnull(find("ACOMMS_OUTGOING_DATA"));
    ck_assert_ptr_nonnull(find("OUT_GOTOCOMMAND_HEX_32B"));
    kelp_queue_request req = { 3, 0, 32 };
    kelp_acomms_msg frame;
    ck_assert_int_eq(kelp_acomms_node_data_request(&h.node, &req, NOON, &frame), 0);
    /* acomms.md 3.8 vector */
    static const uint8_t want[] = { 0x20, 0x00, 0xaa, 0x30, 0x02, 0x30, 0x02, 0xc0, 0x09, 0x3c, 0xda,
                                    0xc2, 0xd6, 0xca, 0xbe, 0xe8, 0xde, 0xc2, 0xe6, 0xe8, 0xe6 };
    ck_assert_uint_eq(frame.len, sizeof want);
    ck_assert_int_eq(memcmp(frame.data, want, sizeof want), 0);
    kelp_acomms_dccl_close(d);

    /* modem 3 receives it: decoded, its <publish> blocks published */
    d = start(3);
    npub = 0;
    frame.src = 1;
    frame.dest = 3;
    ck_assert_int_eq(kelp_acomms_node_receive(&h.node, &frame, NOON + 5), 1);
    ck_assert_ptr_nonnull(find("ACOMMS_INCOMING_DATA"));
    ck_assert_ptr_nonnull(find("IN_GOTOCOMMAND_HEX_32B"));
    ck_assert_str_eq(find("INCOMING_COMMAND"), "Destination=3,type=goto,goto_x=351,goto_y=294,lights_on=true,"
                                               "new_instructions=make_toast,goto_speed=2.29");
    ck_assert_str_eq(find("SPECIAL_INSTRUCTIONS"), "special_instructions=make_toast,lights_on=true");
    ck_assert_uint_eq(h.count.decoded, 1);
    kelp_acomms_dccl_close(d);
}
END_TEST

Suite *kelp_acomms_handler_edge_suite(void)
{
    Suite *s = suite_create("acomms_handler_edge");
    TCase *t = tcase_create("handler");
    tcase_add_test(t, test_handler_dccl_out_and_in);
    suite_add_tcase(s, t);
    return s;
}
