/* kelp commander (the iCommander model): rows, checks, specials, send as pAcommsHandler reads
 * it (through kelp_dccl_source and the codec), save files, ack/expiry notes. */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kelp/commander.h>
#include <kelp/edge/dccl.h>
#include <kelp/acomms.h>
#include <kelp/edge/launch.h>
#include <kelp/edge/mission.h>
#include <kelp/mission.h>

static const char XML[] =
    "<?xml version=\"1.0\" encoding=\"ASCII\" standalone=\"yes\"?>\n"
    "<message_set>\n"
    "  <message>\n"
    "    <name>GoToCommand</name><id>1</id><trigger>publish</trigger>\n"
    "    <trigger_var mandatory_content=\"CommandType=GoTo\">OUTGOING_COMMAND</trigger_var>\n"
    "    <size>32</size>\n"
    "    <header><dest_id><name>Destination</name></dest_id></header>\n"
    "    <layout>\n"
    "      <static><name>type</name><value>goto</value></static>\n"
    "      <int><name>goto_x</name><max>10000</max><min>0</min></int>\n"
    "      <int><name>goto_y</name><max>10000</max><min>0</min></int>\n"
    "      <bool><name>lights_on</name></bool>\n"
    "      <string><moos_var>SPECIAL_INSTRUCTIONS</moos_var><name>new_instructions</name><max_length>10</max_length></string>\n"
    "      <float><name>goto_speed</name><max>3</max><min>0</min><precision>2</precision></float>\n"
    "    </layout>\n"
    "  </message>\n"
    "  <message>\n"
    "    <name>Where</name><id>3</id><trigger>publish</trigger><trigger_var>WHERE</trigger_var><size>32</size>\n"
    "    <header><time><name>When</name></time></header>\n"
    "    <layout>\n"
    "      <float><name>Latitude</name><max>90</max><min>-90</min><precision>6</precision></float>\n"
    "      <float><name>Longitude</name><max>180</max><min>-180</min><precision>6</precision></float>\n"
    "      <enum><name>mode</name><value>park</value><value>go</value></enum>\n"
    "      <int><name>legs</name><max>9</max><min>0</min><array_length>3</array_length></int>\n"
    "    </layout>\n"
    "  </message>\n"
    "</message_set>\n";

static kelp_dccl_loaded ld;
static kelp_dccl_builtin geo;
static kelp_dccl_modem_entry modems[4];
static kelp_commander c;

static void setup(void)
{
    kelp_dccl_loaded_init(&ld);
    ck_assert_int_eq(kelp_dccl_load_buffer(&ld, "t.xml", XML, sizeof XML - 1, NULL, NULL), 0);
    kelp_dccl_builtin_init(&geo, modems, 4);
    kelp_dccl_builtin_set_origin(&geo, 42.35, -70.95);
    kelp_commander_init(&c, &ld.set, &geo);
}

static void teardown(void)
{
    kelp_dccl_loaded_free(&ld);
}

START_TEST(cmdr_rows_and_checks)
{
    kelp_diag why = {0};
    int m = kelp_commander_open(&c, "GoToCommand");
    ck_assert_int_eq(m, 0);
    ck_assert_int_eq(kelp_commander_open(&c, "GoToCommand"), 0);
    ck_assert_int_eq(kelp_commander_open(&c, "Nope"), KELP_ERR_NOTFOUND);
    const kelp_commander_msg *g = &c.open[0];
    ck_assert_uint_eq(g->n_rows, 7); /* Destination (renamed header) + 6 layout fields */
    ck_assert_str_eq(kelp_commander_row_field(g, 0)->name, "Destination");
    ck_assert_str_eq(kelp_commander_row_field(g, 1)->name, "type");
    ck_assert_str_eq(kelp_commander_type_name(kelp_commander_row_field(g, 1)), "static");
    ck_assert_str_eq(g->val[1], "goto");
    ck_assert_str_eq(kelp_commander_type_name(kelp_commander_row_field(g, 2)), "int");
    char d[128];
    kelp_commander_describe(kelp_commander_row_field(g, 1), d, sizeof d);
    ck_assert_str_eq(d, "(static) you cannot change the value of this field");
    kelp_commander_describe(kelp_commander_row_field(g, 2), d, sizeof d);
    ck_assert_str_eq(d, "(int) range: 0 to 10000");
    kelp_commander_describe(kelp_commander_row_field(g, 6), d, sizeof d);
    ck_assert_str_eq(d, "(float) range: 0.00 to 3.00, 2 decimal places");
    ck_assert_int_eq(kelp_commander_set(&c, 0, 1, "stop", &why), KELP_ERR_RANGE);
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 2, "10001", &why), KELP_ERR_RANGE);
    ck_diag(&why, KELP_ERR_RANGE, "out of range");
    ck_assert_int_eq(kelp_commander_set(&c, 0, 2, "-1", &why), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 2, "1.5", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 2, "abc", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(c.active, -1);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 2, "10000", &why), 0);
    ck_assert_int_eq(c.active, 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 0, "32", &why), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 0, "31", &why), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 4, "maybe", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 4, "true", &why), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 5, "12345678901", &why), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 5, "1234567890", &why), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 6, "3.01", &why), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 6, "_time", &why), 0);
    int w = kelp_commander_open(&c, "Where");
    ck_assert_int_eq(w, 1);
    ck_assert_str_eq(kelp_commander_row_field(&c.open[1], 0)->name, "When");
    ck_assert_int_eq(kelp_commander_set(&c, 1, 3, "fly", &why), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_commander_set(&c, 1, 3, "go", &why), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 1, 4, "1,2,3,4", &why), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_commander_set(&c, 1, 4, "1,10", &why), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_commander_set(&c, 1, 4, "1,2,3", &why), 0);
    c.force_xy_only = true;
    ck_assert_int_eq(kelp_commander_set(&c, 1, 1, "42.5", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_commander_set(&c, 1, 1, "y(lat)1:100", &why), 0);
    kelp_commander_clear(&c, 0);
    ck_assert_str_eq(c.open[0].val[1], "goto");
    ck_assert_str_eq(c.open[0].val[2], "");
}
END_TEST

/* what pAcommsHandler makes of the publications: source, encode, decode */
static void through_handler(const kelp_commander_pub *p, size_t n, const kelp_dccl_msgdef *def, kelp_dccl_val *out)
{
    kelp_dccl_var vars[KELP_CMDR_MAX_PUBS];
    static kelp_dccl_val in[64];
    uint8_t buf[64];
    size_t len;
    kelp_dccl_codec cx;
    for (size_t i = 0; i < n; i++) vars[i] = (kelp_dccl_var){p[i].var, false, 0, p[i].val};
    ck_assert(kelp_dccl_is_trigger(def, &vars[n - 1]));
    for (unsigned i = 0; i < def->n_slots; i++) kelp_dccl_val_clear(&in[i]);
    ck_assert_int_eq(kelp_dccl_source(def, vars, n, 0, in, 64), 0);
    kelp_dccl_codec_init(&cx, 1, NULL, NULL);
    ck_assert_int_eq(kelp_dccl_encode(&cx, def, in, 64, 1700000000.0, buf, sizeof buf, &len), 0);
    ck_assert_int_eq(kelp_dccl_decode(&cx, def, buf, len, 1700000000.0, out, 64), 0);
}

START_TEST(cmdr_send_is_what_the_handler_reads)
{
    kelp_diag why = {0};
    kelp_commander_pub p[KELP_CMDR_MAX_PUBS];
    size_t n;
    static kelp_dccl_val out[64];
    char s[64];
    ck_assert_int_eq(kelp_commander_open(&c, "GoToCommand"), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 0, "2", &why), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 2, "101", &why), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 3, "294", &why), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 4, "true", &why), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 5, "make_toast", &why), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 6, "2.3", &why), 0);
    ck_assert_int_eq(kelp_commander_send(&c, 0, 1700000000.0, p, KELP_CMDR_MAX_PUBS, &n, &why), 0);
    ck_assert_uint_eq(n, 2);
    ck_assert_str_eq(p[0].var, "SPECIAL_INSTRUCTIONS");
    ck_assert_str_eq(p[0].val, "new_instructions=make_toast");
    ck_assert_str_eq(p[1].var, "OUTGOING_COMMAND");
    ck_assert_str_eq(p[1].val, "CommandType=GoTo,Destination=2,goto_x=101,goto_y=294,lights_on=true,goto_speed=2.3");
    const kelp_dccl_msgdef *def = c.open[0].def;
    through_handler(p, n, def, out);
    ck_assert(kelp_dccl_val_to_str(&out[def->fields[kelp_dccl_field_find(def, "goto_x")].slot], s, sizeof s, NULL));
    ck_assert_str_eq(s, "101");
    ck_assert(kelp_dccl_val_to_str(&out[def->fields[kelp_dccl_field_find(def, "new_instructions")].slot], s, sizeof s, NULL));
    ck_assert_str_eq(s, "make_toast");
    ck_assert(kelp_dccl_val_to_str(&out[def->fields[KELP_DCCL_H_DEST].slot], s, sizeof s, NULL));
    ck_assert_str_eq(s, "2");

    /* specials: _time, the x/y pair, arrays in {} */
    ck_assert_int_eq(kelp_commander_open(&c, "Where"), 1);
    ck_assert_int_eq(kelp_commander_set(&c, 1, 0, "_time", &why), 0);
    ck_assert_uint_eq(kelp_commander_next_xy(&c.open[1]), 1);
    ck_assert_int_eq(kelp_commander_set(&c, 1, 1, "y(lat)1:1000", &why), 0);
    ck_assert_int_eq(kelp_commander_send(&c, 1, 1700000000.0, p, KELP_CMDR_MAX_PUBS, &n, &why), KELP_ERR_PARSE);
    ck_assert_uint_eq(kelp_commander_next_xy(&c.open[1]), 1);
    ck_assert_int_eq(kelp_commander_set(&c, 1, 2, "x(lon)1:0", &why), 0);
    ck_assert_uint_eq(kelp_commander_next_xy(&c.open[1]), 2);
    ck_assert_int_eq(kelp_commander_set(&c, 1, 4, "1,2,3", &why), 0);
    ck_assert_int_eq(kelp_commander_send(&c, 1, 1700000123.7, p, KELP_CMDR_MAX_PUBS, &n, &why), 0);
    ck_assert_uint_eq(n, 1);
    double lat, lon;
    kelp_dccl_geo_local2latlon(&geo, 0, 1000, &lat, &lon);
    ck_assert(fabs(lat - 42.359) < 0.001 && fabs(lon + 70.95) < 0.001);
    char want[256];
    char la[32], lo[32];
    (void)snprintf(la, sizeof la, "%.7f", lat);
    (void)snprintf(lo, sizeof lo, "%.7f", lon);
    while (la[strlen(la) - 1] == '0') la[strlen(la) - 1] = 0;
    while (lo[strlen(lo) - 1] == '0') lo[strlen(lo) - 1] = 0;
    (void)snprintf(want, sizeof want, "When=1700000123,Latitude=%s,Longitude=%s,legs={1,2,3}", la, lo);
    ck_assert_str_eq(p[0].val, want);
    through_handler(p, n, c.open[1].def, out);
    def = c.open[1].def;
    ck_assert(kelp_dccl_val_to_str(&out[def->fields[kelp_dccl_field_find(def, "legs")].slot + 2], s, sizeof s, NULL));
    ck_assert_str_eq(s, "3");
}
END_TEST

START_TEST(cmdr_save_load)
{
    kelp_diag why = {0};
    char buf[2048];
    size_t len;
    ck_assert_int_eq(kelp_commander_open(&c, "GoToCommand"), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 2, "101", &why), 0);
    ck_assert_int_eq(kelp_commander_set(&c, 0, 5, "a b", &why), 0);
    ck_assert_int_eq(kelp_commander_save(&c, buf, sizeof buf, &len), 0);
    ck_assert_str_eq(buf, "# kelp-commander saved messages\nmessage = GoToCommand\ngoto_x = 101\nnew_instructions = a b\n");
    ck_assert_int_eq(kelp_commander_save(&c, buf, 40, &len), KELP_ERR_NOSPACE);
    kelp_commander d;
    kelp_commander_init(&d, &ld.set, &geo);
    ck_assert_int_eq(kelp_commander_load(&d, "# x\n\nmessage = Where\n mode = go \r\nmessage=GoToCommand\ngoto_x=7", &why), 0);
    ck_assert_uint_eq(d.n_open, 2);
    ck_assert_str_eq(d.open[0].val[3], "go");
    ck_assert_str_eq(d.open[1].val[2], "7");
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_commander_load(&d, "message = Where\nmode = fly\n", &why), KELP_ERR_RANGE);
    ck_assert_int_eq(why.code, KELP_ERR_RANGE);
    ck_assert_int_eq(why.line, 2);
    ck_diag_msg(&why, "not one of the enum values");
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_commander_load(&d, "message = Where\n\nmessage = Nope\n", &why), KELP_ERR_NOTFOUND);
    ck_assert_int_eq(why.code, KELP_ERR_NOTFOUND);
    ck_assert_int_eq(why.line, 3);
    ck_assert_int_eq(kelp_commander_load(&d, "goto_x = 1\n", NULL), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_commander_load(&d, "message = Where\nbogus\n", NULL), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_commander_load(&d, "message = Nope\n", NULL), KELP_ERR_NOTFOUND);
    ck_assert_int_eq(kelp_commander_load(&d, "message = Where\nnofield = 1\n", NULL), KELP_ERR_NOTFOUND);
}
END_TEST

START_TEST(cmdr_ack_note)
{
    char out[256];
    /* 2011-Mar-03 22:38:12 UTC = 1299191892 */
    const char *ack = "base { src: 2 dest: 1 time: \"2011-Mar-03 22:38:12.000000\" } frame: 0 orig_msg { base "
                      "{ src: 1 dest: 5 time: \"2011-Mar-03 22:38:00.000000\" } data: \"\\040\\000\\200\\000\\000\\020\" }";
    ck_assert_int_eq(kelp_commander_ack_note(&c, true, ack, 1299191892.4, out, sizeof out), 0);
    ck_assert_str_eq(out, "Message acknowledged from queue: GoToCommand\n for destination: 5\n at time: 2011-Mar-03 22:38:12");
    ck_assert_int_eq(kelp_commander_ack_note(&c, false, "orig_msg { base { src: 1 dest: 5 } data: \"\\040\\000\\200\\000\\000\\020\" }",
                                        1299191892.0, out, sizeof out), 0);
    ck_assert_str_eq(out, "Message expired from queue: GoToCommand\n for destination: 5\n at time: 2011-Mar-03 22:38:12");
    ck_assert_int_eq(kelp_commander_ack_note(&c, true, "frame: 0", 0, out, sizeof out), KELP_ERR_PARSE);
}
END_TEST

static int extra(void *ctx, const kelp_mission_node *n, kelp_diag *d)
{
    int *seen = ctx;
    if (!kelp_mission_key_is(n, "load")) return 0;
    if (n->vlen == 0) return kelp_fail(d, KELP_ERR_PARSE, "empty");
    (*seen)++;
    return 1;
}

/* the iCommander block: pAcommsHandler's reader with load (and the others) handed over, and
 * dccl_cfg's modem_id as the only one */
START_TEST(cmdr_block)
{
    static kelp_mission_file mf;
    static kelp_acomms_config cfg;
    char warn[256];
    kelp_diag err = {0};
    int seen = 0;
    const char *text = "ProcessConfig = iCommander\n{\n  dccl_cfg { modem_id: 3 }\n  load: \"a.txt\"\n  load: \"b.txt\"\n}\n";
    memset(&mf, 0, sizeof mf);
    ck_assert_int_eq(kelp_mission_load_text(&mf, "t.moos", text, strlen(text)), 0);
    int b = kelp_mission_block(&mf.m, "ProcessConfig", "iCommander");
    ck_assert_int_eq(kelp_acomms_config_read_extra(&mf.m, b, NULL, &cfg, &err, warn, sizeof warn, extra, &seen), 0);
    ck_assert_int_eq(seen, 2);
    ck_assert_int_eq(cfg.modem_id, 3);
    /* without the hook: unknown field, and no top-level modem_id */
    ck_assert_int_eq(kelp_acomms_config_read(&mf.m, b, NULL, &cfg, &err, warn, sizeof warn), KELP_ERR_PARSE);
    ck_assert_int_eq(err.code, KELP_ERR_PARSE);
    ck_assert_int_eq(err.line, 4);
    ck_diag_has(&err, "unknown field");
    kelp_mission_free(&mf);
}
END_TEST

START_TEST(cmdr_launch_name)
{
    ck_assert_str_eq(kelp_launch_map_prog("iCommander"), "kelp-commander");
    ck_assert_str_eq(kelp_launch_map_prog("pMOOSBridge"), "kelp-bridge");
}
END_TEST

Suite *kelp_commander_suite(void);
Suite *kelp_commander_suite(void)
{
    Suite *s = suite_create("commander");
    TCase *tc = tcase_create("core");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, cmdr_rows_and_checks);
    tcase_add_test(tc, cmdr_send_is_what_the_handler_reads);
    tcase_add_test(tc, cmdr_save_load);
    tcase_add_test(tc, cmdr_ack_note);
    tcase_add_test(tc, cmdr_launch_name);
    tcase_add_test(tc, cmdr_block);
    suite_add_tcase(s, tc);
    return s;
}
