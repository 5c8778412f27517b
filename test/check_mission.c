/* Unit tests: mission-file parser and strict number parsing. */
#include <check.h>
#include "check_diag.h"
#include <string.h>
#include <math.h>
#include <kelp/mission.h>

static kelp_mission_node nodes[256];

static int parse(kelp_mission *m, const char *t)
{
    return kelp_mission_parse(m, t, strlen(t), nodes, 256);
}

static const char *val(const kelp_mission *m, int idx)
{
    static char buf[512];
    ck_assert_int_ge(idx, 0);
    ck_assert_int_eq(kelp_mission_copy(&m->nodes[idx], buf, sizeof buf), 0);
    return buf;
}

static const char xrelay[] =
    "ServerHost = localhost\n"
    "ServerPort = 9000\n"
    "Community  = xrelay\n"
    "\n"
    "//-----\n"
    "// Antler configuration block\n"
    "ProcessConfig = ANTLER\n"
    "{\n"
    "  MSBetweenLaunches = 200\n"
    "\n"
    "  Run = MOOSDB @ NewConsole = true\n"
    "  Run = pXRelay @ NewConsole = true ~ pXRelay_PEARs\n"
    "  Run = pXRelay @ NewConsole = true ~ pXRelay_APPLES\n"
    "  Run = uXMS @ NewConsole = true\n"
    "}\n"
    "ProcessConfig = pXRelay_APPLES\n"
    "{\n"
    "    AppTick      = 25\n"
    "    OUTGOING_VAR = APPLES // trailing comment\n"
    "    INCOMING_VAR = PEARS\n"
    "}\n";

START_TEST(xrelay_listing)
{
    kelp_mission m;
    ck_assert_int_eq(parse(&m, xrelay), 0);
    int g = kelp_mission_next(&m, -1, -1, "community");
    ck_assert_str_eq(val(&m, g), "xrelay");
    ck_assert_int_eq(m.nodes[g].line, 3);
    int ant = kelp_mission_block(&m, "processconfig", "antler");
    ck_assert_int_ge(ant, 0);
    int r = kelp_mission_next(&m, ant, -1, "RUN");
    ck_assert_str_eq(val(&m, r), "MOOSDB @ NewConsole = true");
    r = kelp_mission_next(&m, ant, r, "run");
    ck_assert_str_eq(val(&m, r), "pXRelay @ NewConsole = true ~ pXRelay_PEARs");
    ck_assert_int_eq(m.nodes[r].line, 12);
    int nrun = 0;
    for (int i = kelp_mission_next(&m, ant, -1, "run"); i >= 0; i = kelp_mission_next(&m, ant, i, "run")) nrun++;
    ck_assert_int_eq(nrun, 4);
    int ap = kelp_mission_block(&m, "ProcessConfig", "pXRelay_APPLES");
    int o = kelp_mission_next(&m, ap, -1, "outgoing_var");
    ck_assert_str_eq(val(&m, o), "APPLES");
    double tick;
    ck_assert_int_eq(kelp_mission_double(&m.nodes[kelp_mission_next(&m, ap, -1, "apptick")], &tick), 0);
    ck_assert(tick == 25.0);
    /* a global is not found inside a block */
    ck_assert_int_eq(kelp_mission_next(&m, ap, -1, "community"), -1);
}
END_TEST

START_TEST(values_keep_spaces_commas_equals_and_urls)
{
    kelp_mission m;
    ck_assert_int_eq(parse(&m, "LCM_URL = udpm://239.255.76.67:7667?ttl=0\n"
                               "X = a=1, b = 2 ,c\n"
                               "  // whole-line comment\n"
                               "Y=   spaced value   \n"),
                     0);
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, -1, -1, "lcm_url")), "udpm://239.255.76.67:7667?ttl=0");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, -1, -1, "x")), "a=1, b = 2 ,c");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, -1, -1, "y")), "spaced value");
    ck_assert_int_eq((int)m.nnodes, 3);
}
END_TEST

static const char goby[] =
    "ProcessConfig = pAcommsHandler\n"
    "{\n"
    "  common { # Configuration common to all Goby MOOS applications\n"
    "    log: true # comment\n"
    "    community: \"AUV23\"\n"
    "    initializer {\n"
    "      type: INI_DOUBLE\n"
    "      moos_var: \"SOME_MOOS_VAR\"\n"
    "      dval: 3.454\n"
    "    }\n"
    "  }\n"
    "  modem_id: 1\n"
    "  driver_cfg\n"
    "  {\n"
    "      serial_port: \"/tmp/ttyLOOPA2\"\n"
    "      [MicroModemConfig.reset_nvram]: false\n"
    "  }\n"
    "  queue_cfg { queue { key { type: QUEUE_CCL id: 2 } name: \"TEST\" } }\n"
    "  AppTick = 4\n"
    "}\n";

START_TEST(goby_protobuf_blocks)
{
    kelp_mission m;
    ck_assert_int_eq(parse(&m, goby), 0);
    int b = kelp_mission_block(&m, "ProcessConfig", "pAcommsHandler");
    int common = kelp_mission_next(&m, b, -1, "common");
    ck_assert_int_ge(common, 0);
    ck_assert(m.nodes[common].kind == KELP_MN_MSG);
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, common, -1, "community")), "AUV23");
    ck_assert(m.nodes[kelp_mission_next(&m, common, -1, "community")].quoted);
    int ini = kelp_mission_next(&m, common, -1, "initializer");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, ini, -1, "dval")), "3.454");
    ck_assert_int_eq(m.nodes[kelp_mission_next(&m, ini, -1, "dval")].line, 9);
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, b, -1, "modem_id")), "1");
    int drv = kelp_mission_next(&m, b, -1, "driver_cfg");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, drv, -1, "[MicroModemConfig.reset_nvram]")), "false");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, drv, -1, "serial_port")), "/tmp/ttyLOOPA2");
    int qc = kelp_mission_next(&m, b, -1, "queue_cfg");
    int q = kelp_mission_next(&m, qc, -1, "queue");
    int key = kelp_mission_next(&m, q, -1, "key");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, key, -1, "id")), "2");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, key, -1, "type")), "QUEUE_CCL");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, q, -1, "name")), "TEST");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, b, -1, "apptick")), "4");
    ck_assert_int_eq(kelp_mission_next(&m, b, -1, "id"), -1);
}
END_TEST

START_TEST(behavior_file_syntax)
{
    kelp_mission m;
    ck_assert_int_eq(parse(&m, "initialize DEPLOY = false\n"
                               "Behavior = BHV_SimpleWaypoint\n"
                               "{\n"
                               "  name = waypt_to_point\n"
                               "  speed = 2.0 // meters per second\n"
                               "  condition = RETURN = false\n"
                               "  UPDATES = RETURN_UPDATES\n"
                               "}\n"),
                     0);
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, -1, -1, "initialize DEPLOY")), "false");
    int b = kelp_mission_block(&m, "behavior", "BHV_SimpleWaypoint");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, b, -1, "condition")), "RETURN = false");
    ck_assert_str_eq(val(&m, kelp_mission_next(&m, b, -1, "speed")), "2.0");
}
END_TEST

static const struct { const char *text; int line; const char *why; } bad[] = {
    { "A = 1\n{\n", 1, "block not closed: missing '}'" },
    { "ProcessConfig = x\n{\n  a = 1\n", 1, "block not closed: missing '}'" },
    { "A = 1\n}\n", 2, "'}' without an open block" },
    { "just words\n", 1, "expected 'Name = Value'" },
    { "x: 3\n", 1, "protobuf-style 'key: value' outside a ProcessConfig block" },
    { "P = a\n{\n  s: \"abc\n}\n", 3, "unterminated string" },
    { "P = a\n{\n  s 3\n}\n", 3, "expected ':' or '{' after field name" },
    { "P = a\n{\n  m {\n    x: 1\n", 3, "block not closed: missing '}'" },
    { " = 5\n", 1, "missing parameter name before '='" },
    { "P = a\n{\n  [Ext.name: 1\n}\n", 3, "unterminated [extension] name" },
};

START_TEST(bad_text_gives_line_and_reason)
{
    kelp_mission m;
    ck_assert_int_eq(parse(&m, bad[_i].text), KELP_ERR_PARSE);
    ck_assert_int_eq(m.diag.code, KELP_ERR_PARSE);
    ck_assert_int_eq(m.diag.line, bad[_i].line);
    ck_diag_msg(&m.diag, bad[_i].why);
}
END_TEST

START_TEST(measure_then_nospace)
{
    kelp_mission m;
    ck_assert_int_eq(kelp_mission_parse(&m, goby, strlen(goby), NULL, 0), 0);
    size_t need = m.nnodes;
    ck_assert_uint_eq(need, 19); /* block + 18 statements */
    ck_assert_int_eq(kelp_mission_parse(&m, goby, strlen(goby), nodes, need - 1), KELP_ERR_NOSPACE);
    ck_assert_int_eq(kelp_mission_parse(&m, goby, strlen(goby), nodes, need), 0);
}
END_TEST

static const struct { const char *s; double v; int rc; } nums[] = {
    { "0", 0, 0 }, { "25", 25, 0 }, { "-70.330400", -70.3304, 0 }, { "43.825300", 43.8253, 0 },
    { "1e3", 1000, 0 }, { " 2.5 ", 2.5, 0 }, { "+.5", 0.5, 0 }, { "5.", 5, 0 }, { "1.5e-3", 0.0015, 0 },
    { "0.1", 0.1, 0 }, { "123456789012345678", 123456789012345678.0, 0 }, { "", 0, KELP_ERR_PARSE },
    { "abc", 0, KELP_ERR_PARSE }, { "1.2.3", 0, KELP_ERR_PARSE }, { "1e", 0, KELP_ERR_PARSE },
    { "12x", 0, KELP_ERR_PARSE }, { ".", 0, KELP_ERR_PARSE }, { "-", 0, KELP_ERR_PARSE },
};

START_TEST(strict_numbers)
{
    double v = -1;
    int rc = kelp_util_parse_double(nums[_i].s, strlen(nums[_i].s), &v);
    ck_assert_msg(rc == nums[_i].rc, "'%s' rc %d", nums[_i].s, rc);
    if (rc == 0) ck_assert_msg(v == nums[_i].v, "'%s' -> %.17g", nums[_i].s, v);
}
END_TEST

START_TEST(strict_long)
{
    long v;
    ck_assert_int_eq(kelp_util_parse_long("9000", 4, &v), 0);
    ck_assert_int_eq(v, 9000);
    ck_assert_int_eq(kelp_util_parse_long("-3", 2, &v), 0);
    ck_assert_int_eq(v, -3);
    ck_assert_int_eq(kelp_util_parse_long("3.5", 3, &v), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_util_parse_long("99999999999999999999999", 23, &v), KELP_ERR_RANGE);
}
END_TEST

Suite *kelp_mission_suite(void)
{
    Suite *s = suite_create("mission");
    TCase *tc = tcase_create("parse");
    tcase_add_test(tc, xrelay_listing);
    tcase_add_test(tc, values_keep_spaces_commas_equals_and_urls);
    tcase_add_test(tc, goby_protobuf_blocks);
    tcase_add_test(tc, behavior_file_syntax);
    tcase_add_loop_test(tc, bad_text_gives_line_and_reason, 0, (int)(sizeof bad / sizeof bad[0]));
    tcase_add_test(tc, measure_then_nospace);
    tcase_add_loop_test(tc, strict_numbers, 0, (int)(sizeof nums / sizeof nums[0]));
    tcase_add_test(tc, strict_long);
    suite_add_tcase(s, tc);
    return s;
}
