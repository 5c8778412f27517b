/* acomms edge: the pAcommsHandler configuration block (seed 002 2.3.5 / 2.3.15) and the DCCL glue
 * (trigger, sourcing, encode with the spec's vectors, decode and publish). */
#include <check.h>
#include "check_diag.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/edge/mission.h>

#ifndef KELP_TEST_ROOT
#define KELP_TEST_ROOT "."
#endif

/* reads the block; err gets kelp_diag_text, *line (when not NULL) the diag's line */
static int read_cfg_line(const char *text, kelp_acomms_config *c, char *err, size_t cap, int *line)
{
    kelp_diag d = {0};
    static kelp_mission_file mf;
    kelp_mission_free(&mf);
    memset(&mf, 0, sizeof mf);
    ck_assert_int_eq(kelp_mission_load_text(&mf, "t.moos", text, strlen(text)), 0);
    int b = kelp_mission_block(&mf.m, "ProcessConfig", "pAcommsHandler");
    char warn[512];
    int rc = kelp_acomms_config_read(&mf.m, b, NULL, c, &d, warn, sizeof warn);
    ck_assert_int_eq(d.code, rc);
    snprintf(err, cap, "%s", kelp_diag_text(&d));
    if (line) *line = d.line;
    return rc;
}

static int read_cfg(const char *text, kelp_acomms_config *c, char *err, size_t cap)
{
    return read_cfg_line(text, c, err, cap, NULL);
}

/* seed 002 section 2.3.15, example 2, node mm1 (verbatim apart from the path) */
static const char MM1[] =
    "ServerHost = localhost\nServerPort = 9101\nCommunity = mm1\nLatOrigin = 42.35\nLongOrigin = -70.95\n"
    "modem_id_lookup_path = modemidlookup.txt\n"
    "ProcessConfig = pAcommsHandler\n{\n  AppTick = 10\n  CommsTick = 10\n"
    "  common { verbosity: VERBOSITY_GUI\n"
    "    initializer { type: INI_DOUBLE global_cfg_var: \"LatOrigin\" moos_var: \"LAT_ORIGIN\" }\n"
    "    initializer { type: INI_DOUBLE global_cfg_var: \"LongOrigin\" moos_var: \"LONG_ORIGIN\" }\n"
    "    initializer { type: INI_STRING moos_var: \"VEHICLE_TYPE\" sval: \"topside\" }\n"
    "    initializer { type: INI_STRING moos_var: \"VEHICLE_NAME\" sval: \"mm1\" }\n"
    "    initializer { type: INI_DOUBLE moos_var: \"NAV_X\" dval: 100 }\n"
    "    initializer { type: INI_DOUBLE moos_var: \"NAV_Y\" dval: 300 }\n"
    "    initializer { type: INI_DOUBLE moos_var: \"NAV_HEADING\" dval: 150 }\n"
    "    initializer { type: INI_DOUBLE moos_var: \"NAV_SPEED\" dval: 0 }\n"
    "    initializer { type: INI_DOUBLE moos_var: \"NAV_DEPTH\" dval: 0 } }\n"
    "  modem_id: 1\n  driver_type: DRIVER_WHOI_MICROMODEM\n"
    "  driver_cfg { serial_port: \"/tmp/ttyLOOPA2\"  [MicroModemConfig.reset_nvram]: false }\n"
    "  mac_cfg { type: MAC_FIXED_DECENTRALIZED\n"
    "    slot { src: 1 dest: 2 rate: 0 type: SLOT_DATA slot_seconds: 10 }  # downlink\n"
    "    slot { src: 2 dest: 1 rate: 0 type: SLOT_DATA slot_seconds: 10 }  # uplink\n  }\n"
    "  queue_cfg { queue { key { type: QUEUE_CCL id: 14 }\n"
    "    in_pubsub_var: \"IN_REMUS_STATUS\" out_pubsub_var: \"OUT_REMUS_STATUS\" name: \"Remus_State\" } }\n"
    "  dccl_cfg { message_file { path: \"../../xml/simple_status.xml\" } }\n}\n";

START_TEST(test_config_seed_example_mm1)
{
    kelp_acomms_config c;
    char err[256];
    ck_assert_int_eq(read_cfg(MM1, &c, err, sizeof err), 0);
    ck_assert_int_eq(c.modem_id, 1);
    ck_assert_int_eq(c.driver_type, KELP_ACOMMS_DRIVER_WHOI_MICROMODEM);
    ck_assert_int_eq(c.connection, KELP_ACOMMS_CONN_SERIAL);
    ck_assert_str_eq(c.serial_port, "/tmp/ttyLOOPA2");
    ck_assert_uint_eq(c.serial_baud, 19200);
    ck_assert(!c.reset_nvram);
    ck_assert_int_eq(c.verbosity, KELP_ACOMMS_VERBOSITY_GUI);
    ck_assert_uint_eq(c.n_init, 9);
    ck_assert_str_eq(c.init[0].global_cfg_var, "LatOrigin");
    ck_assert_str_eq(c.init[0].moos_var, "LAT_ORIGIN");
    ck_assert(c.init[0].is_double);
    ck_assert(!c.init[2].is_double);
    ck_assert_str_eq(c.init[2].sval, "topside");
    ck_assert(c.init[4].has_dval);
    ck_assert(c.init[4].dval == 100);
    ck_assert_int_eq(c.mac_type, KELP_MAC_FIXED_DECENTRALIZED);
    ck_assert_uint_eq(c.nslots, 2);
    ck_assert_int_eq(c.slots[1].src, 2);
    ck_assert_int_eq(c.slots[1].dest, 1);
    ck_assert_uint_eq(c.slots[1].slot_seconds, 10);
    ck_assert_uint_eq(c.nccl, 1);
    ck_assert_int_eq(c.ccl[0].cfg.key.type, KELP_QUEUE_CCL);
    ck_assert_uint_eq(c.ccl[0].cfg.key.id, 14);
    ck_assert_str_eq(c.ccl[0].name, "Remus_State");
    ck_assert_str_eq(c.ccl[0].in_var, "IN_REMUS_STATUS");
    ck_assert_str_eq(c.ccl[0].out_var, "OUT_REMUS_STATUS");
    ck_assert(c.ccl[0].cfg.ack); /* listing default (acomms.md 10.2) */
    ck_assert(c.ccl[0].cfg.newest_first);
    ck_assert_uint_eq(c.nfiles, 1); /* dccl_cfg files are also queue files (9.9) */
    ck_assert_str_eq(c.files[0].path, "../../xml/simple_status.xml");
    ck_assert_str_eq(c.community, "mm1");                  /* global Community= */
    ck_assert(c.has_lat_origin && c.lat_origin == 42.35);  /* global LatOrigin= */
    ck_assert(c.has_lon_origin && c.lon_origin == -70.95);
    ck_assert_str_eq(c.modem_id_lookup_path, "modemidlookup.txt");
    kelp_acomms_node_cfg nc;
    kelp_acomms_config_node(&c, &nc);
    ck_assert_int_eq(nc.mm.modem_id, 1); /* modem_id set for every module (9.4) */
    ck_assert_int_eq(nc.mac.modem_id, 1);
    ck_assert_uint_eq(nc.mac.nslots, 2);
    ck_assert(!nc.loopback_channel);
}
END_TEST

START_TEST(test_config_defaults)
{
    kelp_acomms_config c;
    char err[256];
    ck_assert_int_eq(read_cfg("ProcessConfig = pAcommsHandler\n{\n modem_id: 2\n mac_cfg { type: MAC_AUTO_DECENTRALIZED }\n"
                              " queue_cfg { queue { key { type: QUEUE_CCL id: 2 } name: \"TEST\" } }\n}\n",
                              &c, err, sizeof err),
                     0);
    /* acomms.md 9.1, 9.5, 9.7, 9.8 */
    ck_assert(c.log);
    ck_assert_str_eq(c.log_path, "./");
    ck_assert(c.app_tick == 10 && c.comm_tick == 10);
    ck_assert_int_eq(c.verbosity, KELP_ACOMMS_VERBOSITY_VERBOSE);
    ck_assert_int_eq(c.driver_type, KELP_ACOMMS_DRIVER_NONE);
    ck_assert_uint_eq(c.mac_rate, 0);
    ck_assert_uint_eq(c.mac_slot_seconds, 15);
    ck_assert_uint_eq(c.mac_expire_cycles, 30);
    ck_assert_uint_eq(c.ccl[0].cfg.blackout_time, 0);
    ck_assert_uint_eq(c.ccl[0].cfg.max_queue, 0);
    ck_assert(c.ccl[0].cfg.newest_first && c.ccl[0].cfg.ack);
    ck_assert(!c.tcp_share_enable);
    ck_assert_uint_eq(c.tcp_share_port, 11000);
    ck_assert_str_eq(c.line_delimiter, "\r\n");
    /* 9.6: slot { src: 1 } only */
    ck_assert_int_eq(read_cfg("ProcessConfig = pAcommsHandler\n{\n modem_id: 1\n mac_cfg { type: MAC_POLLED slot { src: 1 } }\n}\n",
                              &c, err, sizeof err),
                     0);
    ck_assert_int_eq(c.slots[0].dest, -1);
    ck_assert_uint_eq(c.slots[0].rate, 0);
    ck_assert_int_eq(c.slots[0].type, KELP_SLOT_DATA);
    /* TCP and manipulators, files merged by path */
    ck_assert_int_eq(read_cfg("ProcessConfig = pAcommsHandler\n{\n modem_id: 3\n driver_type: DRIVER_WHOI_MICROMODEM\n"
                              " driver_cfg { connection_type: CONNECTION_TCP_AS_CLIENT tcp_server: \"127.0.0.1\" tcp_port: 50010\n"
                              "   [MicroModemConfig.nvram_cfg]: \"cst,1\" [MicroModemConfig.hydroid_gateway_id]: 2 }\n"
                              " queue_cfg { message_file { path: \"a.xml\" manipulator: ON_DEMAND } }\n"
                              " dccl_cfg { message_file { path: \"a.xml\" manipulator: NO_ENCODE manipulator: LOOPBACK }\n"
                              "   crypto_passphrase: \"twinkletoes%24\" }\n}\n",
                              &c, err, sizeof err),
                     0);
    ck_assert_int_eq(c.connection, KELP_ACOMMS_CONN_TCP_AS_CLIENT);
    ck_assert_uint_eq(c.tcp_port, 50010);
    ck_assert_uint_eq(c.n_nvram, 1);
    ck_assert_str_eq(c.nvram[0], "cst,1");
    ck_assert_int_eq(c.hydroid_gateway_id, 2);
    ck_assert_uint_eq(c.nfiles, 1);
    ck_assert_uint_eq(c.files[0].manip,
                      KELP_ACOMMS_MANIP_ON_DEMAND | KELP_ACOMMS_MANIP_NO_ENCODE | KELP_ACOMMS_MANIP_LOOPBACK);
    ck_assert(c.has_passphrase);
    ck_assert_str_eq(c.crypto_passphrase, "twinkletoes%24");
}
END_TEST

START_TEST(test_config_errors)
{
    static const struct {
        const char *body;
        const char *why;
    } bad[] = {
        { " modem_id: 0\n", "reserved for broadcast" },              /* 9.10 */
        { " driver_type: DRIVER_NONE\n", "modem_id (required)" },
        { " modem_id: 1\n colour: blue\n", "line 4: colour: unknown field" },
        { " modem_id: 1\n driver_type: DRIVER_FOO\n", "unknown value \"DRIVER_FOO\"" },
        { " modem_id: 1\n driver_type: DRIVER_WHOI_MICROMODEM\n", "needs driver_cfg { serial_port" },
        { " modem_id: 1\n mac_cfg { slot { dest: 2 } }\n", "slot without src" },
        { " modem_id: 1\n mac_cfg { slot { src: 1 rate: 6 } }\n", "out of range 0..5" },
        { " modem_id: 40\n", "out of range" },
        { " modem_id: 1\n queue_cfg { queue { key { type: QUEUE_CCL id: 2 } } }\n", "without name" },
        { " modem_id: 1\n queue_cfg { queue { key { id: 2 } name: \"x\" } }\n", "CCL queues" },
        { " modem_id: 1\n common { initializer { moos_var: \"X\" } }\n", "without type" },
        { " modem_id: 1\n dccl_cfg { message_file { manipulator: NO_ENCODE } }\n", "without path" },
        { " modem_id: 1\n queue_cfg { message_file { path: \"a\" manipulator: SHRED } }\n", "unknown manipulator" },
        { " modem_id: 1\n driver_cfg { [MicroModemConfig.nvram_cfg]: \"SRC\" }\n", "KEY,VALUE" },
        { " modem_id: 1\n common { log: maybe }\n", "true or false" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char text[512], err[256] = "";
        kelp_acomms_config c;
        snprintf(text, sizeof text, "ProcessConfig = pAcommsHandler\n{\n%s}\n", bad[i].body);
        ck_assert_msg(read_cfg(text, &c, err, sizeof err) < 0, "accepted: %s", bad[i].body);
#ifndef KELP_NO_ERRMSG
        ck_assert_msg(strstr(err, bad[i].why) != NULL, "error \"%s\" lacks \"%s\"", err, bad[i].why);
#endif
    }
    {
        /* code and line of a bad field, in both builds */
        char err[256];
        int line = 0;
        kelp_acomms_config c;
        ck_assert_int_eq(read_cfg_line("ProcessConfig = pAcommsHandler\n{\n modem_id: 1\n colour: blue\n}\n", &c, err,
                                       sizeof err, &line),
                         KELP_ERR_PARSE);
        ck_assert_int_eq(line, 4);
    }
}
END_TEST

/* ------------------------------------------------------------------ DCCL glue */

#define NOON 1262347200.0 /* 2010-01-01 12:00:00 UTC: header time 43200 as the spec's vectors */

static kelp_acomms_dccl *open_example1(bool plain, const char *pass)
{
    static const char *files[1];
    files[0] = KELP_TEST_ROOT "/missions/acomms/example1.xml";
    kelp_acomms_dccl_cfg c;
    memset(&c, 0, sizeof c);
    c.modem_id = 1;
    c.plaintext = plain;
    c.passphrase = pass;
    c.files = files;
    c.nfiles = 1;
    kelp_diag err = {0};
    kelp_acomms_dccl *d = kelp_acomms_dccl_open(&c, &err);
    ck_assert_msg(d != NULL, "%s", kelp_diag_text(&err));
    return d;
}

static void hex(const uint8_t *b, size_t n, char *out)
{
    for (size_t i = 0; i < n; i++) sprintf(out + 2 * i, "%02x", b[i]);
}

static char pubs[8][1100];
static int npubs;
static void on_pub(const char *var, bool is_double, double d, const char *s, void *u)
{
    (void)u;
    if (npubs >= 8) return;
    if (is_double) snprintf(pubs[npubs++], sizeof pubs[0], "%s %g", var, d);
    else snprintf(pubs[npubs++], sizeof pubs[0], "%s %s", var, s);
}

START_TEST(test_glue_goto_vectors)
{
    kelp_acomms_dccl *d = open_example1(true, NULL);
    ck_assert_uint_eq(kelp_acomms_dccl_count(d), 2);
    long gi = kelp_acomms_dccl_find_name(d, "GoToCommand");
    ck_assert_int_ge(gi, 0);
    kelp_acomms_dccl_info info;
    ck_assert_int_eq(kelp_acomms_dccl_info_get(d, (size_t)gi, &info), 0);
    ck_assert_uint_eq(info.id, 1);
    ck_assert_str_eq(info.trigger_var, "OUTGOING_COMMAND");
    ck_assert_str_eq(info.mandatory, "CommandType=GoTo");
    ck_assert_str_eq(info.out_var, "OUT_GOTOCOMMAND_HEX_32B");
    size_t idx[4];
    /* 9.20: CommandType=Loiter triggers nothing */
    kelp_acomms_dccl_set_var(d, "OUTGOING_COMMAND", false, 0, "Destination=3,CommandType=Loiter,goto_x=1");
    ck_assert_uint_eq(kelp_acomms_dccl_triggered(d, "OUTGOING_COMMAND", idx, 4), 0);
    kelp_acomms_dccl_set_var(d, "OUTGOING_COMMAND", false, 0,
                             "Destination=3,CommandType=GoTo,goto_x=351,goto_y=294,lights_on=true,"
                             "special_instructions=make_toast,goto_speed=2.3");
    ck_assert_uint_eq(kelp_acomms_dccl_triggered(d, "OUTGOING_COMMAND", idx, 4), 1);
    ck_assert_uint_eq(idx[0], (size_t)gi);
    uint8_t out[64];
    size_t len = 0;
    char h[160];
    kelp_diag why = {0};
    /* acomms.md 3.8 vector (SPECIAL_INSTRUCTIONS unset), with goby-wire 12.2's truncation:
     * goto_speed 2.3 -> code 230 (e6), not 231 (e7) */
    ck_assert_int_eq(kelp_acomms_dccl_encode_vars(d, (size_t)gi, NOON, out, sizeof out, &len, &why), 0);
    hex(out, len, h);
    ck_assert_str_eq(h, "2000aa30023002c0093c00000000000000000000e6");
    kelp_acomms_dccl_set_var(d, "SPECIAL_INSTRUCTIONS", false, 0, "make_toast");
    ck_assert_int_eq(kelp_acomms_dccl_encode_vars(d, (size_t)gi, NOON, out, sizeof out, &len, &why), 0);
    hex(out, len, h);
    ck_assert_str_eq(h, "2000aa30023002c0093cdac2d6cabee8dec2e6e8e6");
    /* receipt: <all/> and <format> (acomms.md 3.7 [DERIVED], 9.37) */
    npubs = 0;
    ck_assert_int_eq(kelp_acomms_dccl_decode(d, out, len, NOON + 5, on_pub, NULL, &why), 0);
    ck_assert_int_eq(npubs, 2);
    ck_assert_str_eq(pubs[0], "INCOMING_COMMAND Destination=3,type=goto,goto_x=351,goto_y=294,lights_on=true,"
                              "new_instructions=make_toast,goto_speed=2.29");
    ck_assert_str_eq(pubs[1], "SPECIAL_INSTRUCTIONS special_instructions=make_toast,lights_on=true");
    /* VehicleStatus from doubles (time trigger 30 s) */
    long vi = kelp_acomms_dccl_find_name(d, "VehicleStatus");
    kelp_acomms_dccl_set_var(d, "NAV_X", true, 100, NULL);
    kelp_acomms_dccl_set_var(d, "NAV_Y", true, 300, NULL);
    kelp_acomms_dccl_set_var(d, "VEHICLE_HEALTH", false, 0, "low_battery");
    kelp_acomms_dccl_start(d, NOON);
    ck_assert_uint_eq(kelp_acomms_dccl_due(d, NOON + 29.9, idx, 4), 0);
    ck_assert_uint_eq(kelp_acomms_dccl_due(d, NOON + 30.1, idx, 4), 1);
    ck_assert_uint_eq(idx[0], (size_t)vi);
    ck_assert_uint_eq(kelp_acomms_dccl_due(d, NOON + 30.2, idx, 4), 0);
    ck_assert_int_eq(kelp_acomms_dccl_encode_vars(d, (size_t)vi, NOON, out, sizeof out, &len, &why), 0);
    hex(out, len, h);
    ck_assert_str_eq(h + 12, "03e92ee6"); /* acomms.md 3.8 body */
    /* the replay tool's form: one string for every field */
    ck_assert_int_eq(kelp_acomms_dccl_encode_string(d, (size_t)vi, "nav_x=100,nav_y=300,health=low_battery", NOON, out,
                                                    sizeof out, &len, &why),
                     0);
    hex(out, len, h);
    ck_assert_str_eq(h + 12, "03e92ee6");
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_acomms_dccl_encode_string(d, (size_t)vi, "colour=3", NOON, out, sizeof out, &len, &why),
                     KELP_ERR_NOTFOUND);
    ck_diag(&why, KELP_ERR_NOTFOUND, "no such field in the message");
    char desc[256];
    ck_assert_int_eq(kelp_acomms_dccl_describe(d, out, len, NOON, desc, sizeof desc), 0);
    ck_assert_ptr_nonnull(strstr(desc, "VehicleStatus:"));
    ck_assert_ptr_nonnull(strstr(desc, "health=low_battery"));
    /* a frame for an unknown id is an error, not a crash */
    const uint8_t unknown[] = { 0x20, 0xff, 0x80, 0, 0, 0, 1 };
    kelp_diag_clear(&why);
    ck_assert_int_lt(kelp_acomms_dccl_decode(d, unknown, sizeof unknown, NOON, on_pub, NULL, &why), 0);
    ck_assert_int_lt(why.code, 0);
    kelp_acomms_dccl_close(d);
}
END_TEST

START_TEST(test_glue_crypto)
{
    /* acomms.md 9.30: same header, different body, receiver recovers; another passphrase: no */
    kelp_acomms_dccl *a = open_example1(false, "twinkletoes%24");
    kelp_acomms_dccl *b = open_example1(false, "other");
    long gi = kelp_acomms_dccl_find_name(a, "GoToCommand");
    kelp_acomms_dccl_set_var(a, "OUTGOING_COMMAND", false, 0,
                             "Destination=3,CommandType=GoTo,goto_x=351,goto_y=294,lights_on=true,goto_speed=2.3");
    uint8_t out[64];
    size_t len;
    char h[160];
    kelp_diag why = {0};
    ck_assert_int_eq(kelp_acomms_dccl_encode_vars(a, (size_t)gi, NOON, out, sizeof out, &len, &why), 0);
    hex(out, len, h);
    ck_assert_int_eq(strncmp(h, "2000aa300230", 12), 0);
    ck_assert_str_ne(h + 12, "02c0093c00000000000000000000e6");
    npubs = 0;
    ck_assert_int_eq(kelp_acomms_dccl_decode(a, out, len, NOON, on_pub, NULL, &why), 0);
    ck_assert_ptr_nonnull(strstr(pubs[0], "goto_x=351,goto_y=294"));
    npubs = 0;
    if (kelp_acomms_dccl_decode(b, out, len, NOON, on_pub, NULL, &why) == 0 && npubs)
        ck_assert_ptr_null(strstr(pubs[0], "goto_x=351,goto_y=294"));
    kelp_acomms_dccl_close(a);
    kelp_acomms_dccl_close(b);
}
END_TEST

START_TEST(test_glue_open_errors)
{
    const char *files[2] = { "/nonexistent.xml", NULL };
    kelp_acomms_dccl_cfg c;
    memset(&c, 0, sizeof c);
    c.modem_id = 1;
    c.files = files;
    c.nfiles = 1;
    kelp_diag err = {0};
    ck_assert_ptr_null(kelp_acomms_dccl_open(&c, &err));
    ck_assert_int_eq(err.code, KELP_ERR_IO);
    ck_diag_has(&err, "nonexistent");
    /* the same file twice is loaded once (dccl_cfg + queue_cfg), manipulators merged */
    files[0] = files[1] = KELP_TEST_ROOT "/missions/acomms/example1.xml";
    unsigned man[2] = { KELP_ACOMMS_MANIP_NO_ENCODE, KELP_ACOMMS_MANIP_LOOPBACK };
    c.manips = man;
    c.nfiles = 2;
    kelp_acomms_dccl *d = kelp_acomms_dccl_open(&c, NULL);
    ck_assert_ptr_nonnull(d);
    ck_assert_uint_eq(kelp_acomms_dccl_count(d), 2);
    kelp_acomms_dccl_info info;
    ck_assert_int_eq(kelp_acomms_dccl_info_get(d, 0, &info), 0);
    ck_assert_uint_eq(info.manip, KELP_ACOMMS_MANIP_NO_ENCODE | KELP_ACOMMS_MANIP_LOOPBACK);
    size_t idx[2];
    kelp_acomms_dccl_set_var(d, "OUTGOING_COMMAND", false, 0, "CommandType=GoTo");
    ck_assert_uint_eq(kelp_acomms_dccl_triggered(d, "OUTGOING_COMMAND", idx, 2), 0); /* NO_ENCODE */
    kelp_acomms_dccl_close(d);
}
END_TEST

Suite *kelp_acomms_edge_suite(void)
{
    Suite *s = suite_create("acomms_edge");
    TCase *t = tcase_create("config");
    tcase_add_test(t, test_config_seed_example_mm1);
    tcase_add_test(t, test_config_defaults);
    tcase_add_test(t, test_config_errors);
    suite_add_tcase(s, t);
    t = tcase_create("dccl_glue");
    tcase_add_test(t, test_glue_goto_vectors);
    tcase_add_test(t, test_glue_crypto);
    tcase_add_test(t, test_glue_open_errors);
    suite_add_tcase(s, t);
    return s;
}
