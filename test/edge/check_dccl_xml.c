/* Edge tests for DCCL: the expat loader, mbedTLS crypto, publish strings, the
 * seed's XML examples and load-time errors. */
#include <check.h>
#include "check_diag.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/edge/dccl.h>

#define DAY0 1699920000.0
#define NOON (DAY0 + 43200.0)

static const char EXAMPLE1[] =
    "<?xml version=\"1.0\" encoding=\"ASCII\" standalone=\"yes\"?>\n"
    "<message_set>\n"
    "  <message>\n"
    "    <name>GoToCommand</name>\n"
    "    <id>1</id>\n"
    "    <trigger>publish</trigger>\n"
    "    <trigger_var mandatory_content=\"CommandType=GoTo\">\n"
    "      OUTGOING_COMMAND\n"
    "    </trigger_var>\n"
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
    "    <on_receipt>\n"
    "      <publish><publish_var>INCOMING_COMMAND</publish_var><all /></publish>\n"
    "      <publish><publish_var>SPECIAL_INSTRUCTIONS</publish_var>\n"
    "        <format>special_instructions=%1%,lights_on=%2%</format>\n"
    "        <message_var>new_instructions</message_var><message_var>lights_on</message_var></publish>\n"
    "      <publish><publish_var>TWO</publish_var>\n"
    "        <message_var>new_instructions</message_var><message_var>lights_on</message_var></publish>\n"
    "    </on_receipt>\n"
    "  </message>\n"
    "  <message>\n"
    "    <name>VehicleStatus</name><id>2</id><trigger>time</trigger><trigger_time>30</trigger_time><size>32</size>\n"
    "    <layout>\n"
    "      <float><name>nav_x</name><src_var>NAV_X</src_var><max>1000</max><min>0</min><precision>1</precision></float>\n"
    "      <float><name>nav_y</name><src_var>NAV_Y</src_var><max>1000</max><min>0</min><precision>1</precision></float>\n"
    "      <enum><name>health</name><src_var>VEHICLE_HEALTH</src_var><value>good</value><value>low_battery</value><value>abort</value></enum>\n"
    "    </layout>\n"
    "    <on_receipt><publish><publish_var>STATUS_SUMMARY</publish_var><all /></publish></on_receipt>\n"
    "  </message>\n"
    "</message_set>\n";

static const char SIMPLE_STATUS[] =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<message_set><message>\n"
    "  <name>SIMPLE_STATUS</name><trigger>time</trigger><trigger_time>5</trigger_time><size>32</size>\n"
    "  <header><id>20</id><time><name>Timestamp</name></time>\n"
    "    <src_id algorithm=\"to_lower,name2modem_id\"><name>Node</name><moos_var>VEHICLE_NAME</moos_var></src_id></header>\n"
    "  <layout>\n"
    "    <static><name>MessageType</name><value>LAMSS_STATUS</value></static>\n"
    "    <float><name>nav_x</name><moos_var>NAV_X</moos_var><max>100000</max><min>-100000</min><precision>0</precision></float>\n"
    "    <float><name>nav_y</name><moos_var>NAV_Y</moos_var><max>100000</max><min>-100000</min><precision>0</precision></float>\n"
    "    <float><name>Speed</name><moos_var>NAV_SPEED</moos_var><max>20</max><min>-2</min><precision>1</precision></float>\n"
    "    <float algorithm=\"angle_0_360\"><name>Heading</name><moos_var>NAV_HEADING</moos_var><max>360</max><min>0</min><precision>2</precision></float>\n"
    "    <float><name>Depth</name><moos_var>NAV_DEPTH</moos_var><max>6400</max><min>0</min><precision>1</precision></float>\n"
    "  </layout>\n"
    "  <on_receipt>\n"
    "    <publish><moos_var>STATUS_REPORT_IN</moos_var><all /></publish>\n"
    "    <publish><moos_var>NODE_REPORT</moos_var>\n"
    "      <format>NAME=%1%,TYPE=%2%,UTC_TIME=%3$.01f,X=%4%,Y=%5%,LAT=%6$1f,LON=%7$1f,SPD=%8%,HDG=%9%,DEPTH=%10%</format>\n"
    "      <message_var algorithm=\"modem_id2name\">Node</message_var><message_var algorithm=\"modem_id2type\">Node</message_var>\n"
    "      <message_var>Timestamp</message_var><message_var>nav_x</message_var><message_var>nav_y</message_var>\n"
    "      <message_var algorithm=\"utm_y2lat:nav_x\">nav_y</message_var><message_var algorithm=\"utm_x2lon:nav_y\">nav_x</message_var>\n"
    "      <message_var>Speed</message_var><message_var>Heading</message_var><message_var>Depth</message_var></publish>\n"
    "    <publish><moos_var>DEPTH_ONLY</moos_var><message_var>Depth</message_var></publish>\n"
    "  </on_receipt>\n"
    "  <queuing><ack>false</ack><blackout_time>10</blackout_time><ttl>300</ttl><value_base>1.5</value_base></queuing>\n"
    "</message></message_set>\n";

static const char SMALL_TEST[] =
    "<message_set><message><name>small_test</name><trigger>publish</trigger>\n"
    "<trigger_moos_var>SMALL_TEST_OUT</trigger_moos_var><size>256</size>\n"
    "<header><id>51</id><dest_id><name>destination</name></dest_id></header>\n"
    "<layout><static><name>static</name><value>static_val</value></static>\n"
    "<int><name>int</name><max>100</max><min>-100</min><array_length>3</array_length><max_delta>2</max_delta></int>\n"
    "<float><name>float</name><max>100</max><min>-1000</min><max_delta>2</max_delta><precision>3</precision></float>\n"
    "<string><name>string</name><max_length>5</max_length></string>\n"
    "<enum><name>enum</name><value>enum1</value><value>enum2</value><value>enum3</value></enum>\n"
    "<bool><name>bool</name></bool></layout>\n"
    "<on_receipt><publish><moos_var>SMALL_TEST_IN</moos_var><all /></publish>\n"
    "<publish><moos_var>BOOL_TEST</moos_var><message_var>bool</message_var></publish>\n"
    "<publish><moos_var type=\"double\">BOOL_TEST_FORCE_DBL</moos_var><message_var>bool</message_var></publish>\n"
    "<publish><moos_var type=\"string\">FLOAT_TEST_FORCE_STR</moos_var><message_var>float</message_var></publish>\n"
    "</on_receipt><queuing><ack>false</ack><ttl>300</ttl><value_base>10</value_base></queuing></message></message_set>\n";

static const char REPEAT_TEST[] =
    "<message_set><message><name>TEST</name><size>128</size><id>4</id><repeat/>\n"
    "<layout><static><name>Stat</name><value>hi</value></static>\n"
    "<float algorithm=\"sum:I\"><name>SUM</name><max>200</max><min>-100</min><precision>2</precision></float>\n"
    "<int algorithm=\"+1\"><name>I</name><max>100</max><min>-50</min><max_delta>10</max_delta></int>\n"
    "</layout></message></message_set>\n";

static kelp_dccl_alg_entry alg_store[48];
static kelp_dccl_modem_entry modem_store[16];
static kelp_dccl_algs algs;
static kelp_dccl_builtin bi;

static void setup_algs(void)
{
    static const char lookup[] = "1,mm1,topside\n2,mm2,auv\n";
    kelp_dccl_algs_init(&algs, alg_store, 48);
    kelp_dccl_builtin_init(&bi, modem_store, 16);
    ck_assert_int_eq(kelp_dccl_algs_add_builtin(&algs, &bi), 0);
    ck_assert_int_eq(kelp_dccl_builtin_parse_modems(&bi, lookup, sizeof lookup - 1), 0);
    kelp_dccl_builtin_set_origin(&bi, 42.35, -70.95);
}

static void hex(const uint8_t *b, size_t n, char *out)
{
    static const char H[] = "0123456789abcdef";
    size_t i;
    for (i = 0; i < n; i++) {
        out[2 * i] = H[b[i] >> 4];
        out[2 * i + 1] = H[b[i] & 15];
    }
    out[2 * n] = '\0';
}

static void setv(const kelp_dccl_msgdef *d, kelp_dccl_val *v, const char *name, unsigned k, const char *s)
{
    int fi = kelp_dccl_field_find(d, name);
    ck_assert_msg(fi >= 0, "no field %s", name);
    kelp_dccl_val_set_str(&v[d->fields[fi].slot + k], s);
}

static void clear_all(kelp_dccl_val *v, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) kelp_dccl_val_clear(&v[i]);
}

static const kelp_dccl_pub *find_pub(const kelp_dccl_pub *p, size_t n, const char *var)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (strcmp(p[i].var, var) == 0) return &p[i];
    return NULL;
}

START_TEST(example1_loads_encrypts_publishes)
{
    kelp_dccl_loaded ld;
    kelp_dccl_mbedtls mb;
    kelp_dccl_codec cx;
    kelp_dccl_val v[32], out[32];
    kelp_dccl_pub pubs[8];
    const kelp_dccl_msgdef *d;
    const kelp_dccl_pub *p;
    uint8_t buf[64];
    kelp_diag err = {0};
    char h[128];
    size_t n, np;
    setup_algs();
    kelp_dccl_loaded_init(&ld);
    ck_assert_msg(kelp_dccl_load_buffer(&ld, "example1.xml", EXAMPLE1, sizeof EXAMPLE1 - 1, &algs, &err) == 0,
                  "%s", kelp_diag_text(&err));
    ck_assert_uint_eq(ld.set.n, 2);
    d = kelp_dccl_set_find_name(&ld.set, "GoToCommand");
    ck_assert_ptr_nonnull(d);
    ck_assert_uint_eq(d->body_bits, 119);
    ck_assert_uint_eq(kelp_dccl_max_len(d), 21);
    ck_assert_str_eq(d->trigger_var, "OUTGOING_COMMAND"); /* whitespace trimmed */
    ck_assert_str_eq(d->trigger_mandatory, "CommandType=GoTo");
    ck_assert_str_eq(d->in_var, "IN_GOTOCOMMAND_HEX_32B");
    ck_assert_str_eq(d->fields[12].src_var, "SPECIAL_INSTRUCTIONS");
    ck_assert(d->queuing.ack && d->queuing.newest_first && d->queuing.ttl == 1800 && !d->queuing.present);
    ck_assert_str_eq(d->publishes[0].format, "Destination=%1%,type=%2%,goto_x=%3%,goto_y=%4%,lights_on=%5%,"
                                             "new_instructions=%6%,goto_speed=%7%");
    ck_assert_str_eq(d->publishes[2].format, "new_instructions=%1%,lights_on=%2%");
    ck_assert_uint_eq(kelp_dccl_set_find_id(&ld.set, 2)->body_bits, 30);

    ck_assert_int_eq(kelp_dccl_mbedtls_init(&mb, NULL), 0);
    kelp_dccl_codec_init(&cx, 1, &mb.ops, &algs);
    clear_all(v, 32);
    setv(d, v, "Destination", 0, "3");
    setv(d, v, "goto_x", 0, "351");
    setv(d, v, "goto_y", 0, "294");
    setv(d, v, "lights_on", 0, "true");
    setv(d, v, "new_instructions", 0, "make_toast");
    setv(d, v, "goto_speed", 0, "2.3");
    ck_assert_int_eq(kelp_dccl_encode(&cx, d, v, 32, NOON, buf, sizeof buf, &n), 0);
    hex(buf, n, h);
    /* AES-256-CTR, key SHA-256(""), IV SHA-256(header)[0..15]; checked with openssl enc -aes-256-ctr */
    ck_assert_str_eq(h, "2000aa3002301900cf87ea6b7ee47f21b7777603c7");
    ck_assert_int_eq(kelp_dccl_decode(&cx, d, buf, n, NOON + 10, out, 32), 0);
    ck_assert_int_eq(kelp_dccl_publish_all(&cx, d, out, 32, pubs, 8, &np), 0);
    ck_assert_uint_eq(np, 3);
    p = find_pub(pubs, np, "INCOMING_COMMAND");
    ck_assert_ptr_nonnull(p);
    ck_assert(!p->is_double);
    ck_assert_str_eq(p->s, "Destination=3,type=goto,goto_x=351,goto_y=294,lights_on=true,new_instructions=make_toast,"
                           "goto_speed=2.29");
    p = find_pub(pubs, np, "SPECIAL_INSTRUCTIONS");
    ck_assert_str_eq(p->s, "special_instructions=make_toast,lights_on=true");
    p = find_pub(pubs, np, "TWO");
    ck_assert_str_eq(p->s, "new_instructions=make_toast,lights_on=true");
    kelp_dccl_mbedtls_free(&mb);
    kelp_dccl_loaded_free(&ld);
}
END_TEST

START_TEST(simple_status_vector_and_node_report)
{
    kelp_dccl_loaded ld;
    kelp_dccl_mbedtls mb, wrong;
    kelp_dccl_codec cx, cxw;
    kelp_dccl_val v[32], out[32];
    kelp_dccl_pub pubs[8];
    const kelp_dccl_msgdef *d;
    const kelp_dccl_pub *p;
    kelp_dccl_var vars[] = {{"VEHICLE_NAME", false, 0, "MM2"}, {"NAV_X", true, 123, NULL},
                            {"NAV_Y", true, 321, NULL},        {"NAV_SPEED", true, 1.2, NULL},
                            {"NAV_HEADING", true, 45, NULL},   {"NAV_DEPTH", true, 111, NULL}};
    uint8_t buf[64];
    kelp_diag err = {0};
    char h[128];
    size_t n, np;
    setup_algs();
    kelp_dccl_loaded_init(&ld);
    ck_assert_msg(kelp_dccl_load_buffer(&ld, "simple_status.xml", SIMPLE_STATUS, sizeof SIMPLE_STATUS - 1, &algs,
                                        &err) == 0, "%s", kelp_diag_text(&err));
    d = ld.set.msgs[0];
    ck_assert_uint_eq(d->id, 20);
    ck_assert_uint_eq(d->body_bits, 76);
    ck_assert(d->queuing.present && !d->queuing.ack && d->queuing.blackout_time == 10 && d->queuing.ttl == 300 &&
              d->queuing.value_base == 1.5);
    kelp_dccl_codec_init(&cx, 2, NULL, &algs);
    clear_all(v, 32);
    ck_assert_int_eq(kelp_dccl_source(d, vars, 6, 0, v, 32), 0);
    ck_assert_int_eq(kelp_dccl_encode(&cx, d, v, 32, NOON, buf, sizeof buf, &n), 0);
    hex(buf, n, h);
    ck_assert_str_eq(h, "200a2a300400061c7187e22111950457"); /* acomms.md 3.8 */
    ck_assert_int_eq(kelp_dccl_decode(&cx, d, buf, n, NOON, out, 32), 0);
    ck_assert_int_eq(kelp_dccl_publish_all(&cx, d, out, 32, pubs, 8, &np), 0);
    p = find_pub(pubs, np, "STATUS_REPORT_IN");
    ck_assert_str_eq(p->s, "Timestamp=1699963200,Node=2,MessageType=LAMSS_STATUS,nav_x=123,nav_y=321,Speed=1.2,"
                           "Heading=45.00,Depth=111.0");
    p = find_pub(pubs, np, "NODE_REPORT");
    ck_assert_msg(strncmp(p->s, "NAME=mm2,TYPE=auv,UTC_TIME=1699963200,X=123,Y=321,LAT=42.35", 59) == 0, "%s", p->s);
    p = find_pub(pubs, np, "DEPTH_ONLY");
    ck_assert(p->is_double && p->d == 111.0);

    /* crypto_passphrase: header in clear, body differs, receiver recovers; wrong key: garbage, no error */
    ck_assert_int_eq(kelp_dccl_mbedtls_init(&mb, "twinkletoes%24"), 0);
    ck_assert_int_eq(kelp_dccl_mbedtls_init(&wrong, "other"), 0);
    kelp_dccl_codec_init(&cx, 2, &mb.ops, &algs);
    kelp_dccl_codec_init(&cxw, 2, &wrong.ops, &algs);
    ck_assert_int_eq(kelp_dccl_encode(&cx, d, v, 32, NOON, buf, sizeof buf, &n), 0);
    hex(buf, 6, h);
    ck_assert_str_eq(h, "200a2a300400");
    hex(buf + 6, n - 6, h);
    ck_assert_str_ne(h, "061c7187e22111950457");
    ck_assert_int_eq(kelp_dccl_decode(&cx, d, buf, n, NOON, out, 32), 0);
    ck_assert_int_eq(kelp_dccl_publish_all(&cx, d, out, 32, pubs, 8, &np), 0);
    p = find_pub(pubs, np, "DEPTH_ONLY");
    ck_assert(p->is_double && p->d == 111.0);
    ck_assert_int_eq(kelp_dccl_decode(&cxw, d, buf, n, NOON, out, 32), 0);
    ck_assert_int_eq(kelp_dccl_publish_all(&cxw, d, out, 32, pubs, 8, &np), 0);
    p = find_pub(pubs, np, "DEPTH_ONLY");
    ck_assert(!(p->is_double && p->d == 111.0));
    kelp_dccl_mbedtls_free(&mb);
    kelp_dccl_mbedtls_free(&wrong);
    kelp_dccl_loaded_free(&ld);
}
END_TEST

START_TEST(arrays_all_and_typed_publish)
{
    kelp_dccl_loaded ld;
    kelp_dccl_codec cx;
    kelp_dccl_val v[32], out[32];
    kelp_dccl_pub pubs[8];
    const kelp_dccl_msgdef *d;
    const kelp_dccl_pub *p;
    uint8_t buf[300];
    kelp_diag err = {0};
    size_t n, np;
    kelp_dccl_var trig = {"SMALL_TEST_OUT", false, 0, "destination=4,int={1,2,3},float=5.5,string=hello,enum=enum2,bool=false"};
    kelp_dccl_loaded_init(&ld);
    ck_assert_msg(kelp_dccl_load_buffer(&ld, "small.xml", SMALL_TEST, sizeof SMALL_TEST - 1, NULL, &err) == 0,
                  "%s", kelp_diag_text(&err));
    d = ld.set.msgs[0];
    ck_assert_str_eq(d->publishes[0].format, "destination=%1%,static=%2%,int={%3%,%4%,%5%},float=%6%,string=%7%,"
                                             "enum=%8%,bool=%9%");
    kelp_dccl_codec_init(&cx, 1, NULL, NULL);
    clear_all(v, 32);
    ck_assert_int_eq(kelp_dccl_source(d, &trig, 1, 0, v, 32), 0);
    ck_assert_int_eq(kelp_dccl_encode(&cx, d, v, 32, NOON, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_dccl_decode(&cx, d, buf, n, NOON, out, 32), 0);
    ck_assert_int_eq(kelp_dccl_publish_all(&cx, d, out, 32, pubs, 8, &np), 0);
    ck_assert_uint_eq(np, 4);
    p = find_pub(pubs, np, "SMALL_TEST_IN");
    ck_assert_str_eq(p->s, "destination=4,static=static_val,int={1,2,3},float=5.500,string=hello,enum=enum2,bool=false");
    p = find_pub(pubs, np, "BOOL_TEST");
    ck_assert(!p->is_double);
    ck_assert_str_eq(p->s, "false");
    p = find_pub(pubs, np, "BOOL_TEST_FORCE_DBL");
    ck_assert(p->is_double && p->d == 0);
    p = find_pub(pubs, np, "FLOAT_TEST_FORCE_STR");
    ck_assert(!p->is_double);
    ck_assert_str_eq(p->s, "5.500");
    kelp_dccl_loaded_free(&ld);
}
END_TEST

static const char WIDE_INTS[] =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<message_set><message><name>WIDE</name><id>40</id><size>64</size>\n"
    "  <layout>\n"
    "    <int><name>u32</name><max>4000000000</max><min>0</min></int>\n"
    "    <int><name>s34</name><max>5000000000</max><min>-5000000000</min></int>\n"
    "    <int><name>quirk</name><max>2147483646</max><min>0</min></int>\n"
    "    <int><name>quirk29</name><max>536870910</max><min>0</min></int>\n"
    "    <int><name>big</name><max>1e15</max><min>-1e15</min></int>\n"
    "    <int><name>huge</name><max>9e18</max><min>0</min></int>\n"
    "    <int><name>dl</name><max>4e9</max><min>-4e9</min><array_length>3</array_length><max_delta>3e9</max_delta></int>\n"
    "  </layout>\n"
    "  <queuing><blackout_time>0.5</blackout_time><max_queue>4000000000</max_queue></queuing>\n"
    "</message></message_set>\n";

static int64_t wide_field(const kelp_dccl_msgdef *d, const kelp_dccl_val *out, const char *name, unsigned el)
{
    int fi = kelp_dccl_field_find(d, name);
    ck_assert_int_ge(fi, 0);
    int64_t l = 0;
    ck_assert_msg(kelp_dccl_val_to_long(&out[d->fields[fi].slot + el], &l), "%s not a number", name);
    return l;
}

/* a <repeat> message, the count given (3) or computed by <repeat/> (8*(10-6) bits / 9 bits a copy = 3) */
#define REPEAT_PUB(size, repeat)                                                                                      \
    "<message_set><message><name>REP</name><size>" size "</size><id>5</id>" repeat "\n"                             \
    "<header><src_id><name>src</name></src_id></header>\n"                                                            \
    "<layout><int><name>a</name><max>100</max><min>0</min></int><bool><name>b</name></bool></layout>\n"                \
    "<on_receipt><publish><publish_var>REP_IN</publish_var><all/></publish>\n"                                        \
    "<publish><publish_var>REP_AB</publish_var><message_var>a</message_var><message_var>b</message_var></publish>\n"  \
    "<publish><publish_var>REP_FMT</publish_var><format>a is %1% from %2%</format>"                                   \
    "<message_var>a</message_var><message_var>src</message_var></publish></on_receipt>\n"                             \
    "</message></message_set>\n"
static unsigned wide_field_bits(const kelp_dccl_msgdef *d, const char *name)
{
    int fi = kelp_dccl_field_find(d, name);
    ck_assert_int_ge(fi, 0);
    return d->fields[fi].bits;
}

static const char *const REPEAT_PUBS[] = {REPEAT_PUB("32", "<repeat>3</repeat>"), REPEAT_PUB("10", "<repeat/>")};

START_TEST(repeat_publishes_once_per_index)
{
    kelp_dccl_loaded ld;
    kelp_dccl_codec cx;
    kelp_dccl_val v[32], out[32];
    kelp_dccl_pub pubs[16];
    uint8_t buf[64];
    kelp_diag err = {0};
    size_t n, np;
    kelp_dccl_loaded_init(&ld);
    ck_assert_msg(kelp_dccl_load_buffer(&ld, "rep.xml", REPEAT_PUBS[_i], strlen(REPEAT_PUBS[_i]), NULL, &err) == 0,
                  "%s", kelp_diag_text(&err));
    const kelp_dccl_msgdef *d = ld.set.msgs[0];
    ck_assert_uint_eq(d->repeat, 3);
    /* a generated format has one placeholder per field, not per array element */
    ck_assert_str_eq(d->publishes[0].format, "src=%1%,a=%2%,b=%3%");
    ck_assert_str_eq(d->publishes[1].format, "a=%1%,b=%2%");
    kelp_dccl_codec_init(&cx, 7, NULL, NULL);
    clear_all(v, 32);
    int fa = kelp_dccl_field_find(d, "a"), fb = kelp_dccl_field_find(d, "b");
    for (unsigned k = 0; k < 3; k++) {
        kelp_dccl_val_set_long(&v[d->fields[fa].slot + k], 10 * (k + 1));
        kelp_dccl_val_set_bool(&v[d->fields[fb].slot + k], k != 1);
    }
    ck_assert_int_eq(kelp_dccl_encode(&cx, d, v, 32, NOON, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_dccl_decode(&cx, d, buf, n, NOON, out, 32), 0);
    ck_assert_int_eq(kelp_dccl_publish_all(&cx, d, out, 32, pubs, 16, &np), 0);
    ck_assert_uint_eq(np, 9); /* 3 publishes x 3 repeats */
    static const char *const want[] = {
        "src=7,a=10,b=true", "src=7,a=20,b=false", "src=7,a=30,b=true",
        "a=10,b=true",       "a=20,b=false",       "a=30,b=true",
        "a is 10 from 7",    "a is 20 from 7",     "a is 30 from 7",
    };
    for (size_t i = 0; i < np; i++) ck_assert_str_eq(pubs[i].s, want[i]);
    kelp_dccl_loaded_free(&ld);
}
END_TEST

START_TEST(int_bounds_in_the_billions)
{
    kelp_dccl_loaded ld;
    kelp_dccl_codec cx;
    kelp_dccl_val v[32], out[32];
    uint8_t buf[128];
    kelp_diag err = {0};
    size_t n;
    kelp_dccl_loaded_init(&ld);
    ck_assert_msg(kelp_dccl_load_buffer(&ld, "wide.xml", WIDE_INTS, sizeof WIDE_INTS - 1, NULL, &err) == 0,
                  "%s", kelp_diag_text(&err));
    const kelp_dccl_msgdef *d = ld.set.msgs[0];
    /* widths by Goby's double expression, its quirks included */
    static const struct { const char *name; unsigned bits; } W[] = {
        {"u32", 32}, {"s34", 34}, {"quirk", 32}, {"quirk29", 30}, {"big", 51}, {"huge", 63},
    };
    for (size_t i = 0; i < sizeof W / sizeof W[0]; i++)
        ck_assert_msg(d->fields[kelp_dccl_field_find(d, W[i].name)].bits == W[i].bits, "%s: %u bits, expected %u",
                      W[i].name, d->fields[kelp_dccl_field_find(d, W[i].name)].bits, W[i].bits);
    const kelp_dccl_field *dl = &d->fields[kelp_dccl_field_find(d, "dl")];
    ck_assert_uint_eq(dl->bits, 33);       /* 8e9 + 2 */
    ck_assert_uint_eq(dl->delta_bits, 33); /* 2 * 3e9 + 2 */
    ck_assert(d->queuing.blackout_time == 0.5 && d->queuing.max_queue == 4000000000u);
    kelp_dccl_codec_init(&cx, 1, NULL, NULL);
    static const int64_t vals[][3] = {
        /* u32, s34, big */
        {0, -5000000000LL, -1000000000000000LL},
        {4000000000LL, 5000000000LL, 1000000000000000LL},
        {2999999999LL, -1234567890123LL / 1000, 9007199254740LL},
    };
    for (size_t k = 0; k < 3; k++) {
        clear_all(v, 32);
        kelp_dccl_val_set_long(&v[d->fields[kelp_dccl_field_find(d, "u32")].slot], vals[k][0]);
        kelp_dccl_val_set_long(&v[d->fields[kelp_dccl_field_find(d, "s34")].slot], vals[k][1]);
        kelp_dccl_val_set_long(&v[d->fields[kelp_dccl_field_find(d, "big")].slot], vals[k][2]);
        kelp_dccl_val_set_long(&v[d->fields[kelp_dccl_field_find(d, "huge")].slot], 4503599627370496LL); /* 2^52 */
        kelp_dccl_val_set_long(&v[dl->slot], 3500000000LL);
        kelp_dccl_val_set_long(&v[dl->slot + 1], 1000000000LL);
        kelp_dccl_val_set_long(&v[dl->slot + 2], -3900000000LL); /* more than max_delta from the key: null */
        ck_assert_int_eq(kelp_dccl_encode(&cx, d, v, 32, NOON, buf, sizeof buf, &n), 0);
        ck_assert_int_eq(kelp_dccl_decode(&cx, d, buf, n, NOON, out, 32), 0);
        ck_assert_int_eq(wide_field(d, out, "u32", 0), vals[k][0]);
        ck_assert_int_eq(wide_field(d, out, "s34", 0), vals[k][1]);
        ck_assert_int_eq(wide_field(d, out, "big", 0), vals[k][2]);
        ck_assert_int_eq(wide_field(d, out, "huge", 0), 4503599627370496LL);
        ck_assert_int_eq(wide_field(d, out, "dl", 0), 3500000000LL);
        ck_assert_int_eq(wide_field(d, out, "dl", 1), 1000000000LL);
        ck_assert(out[dl->slot + 2].kind == KELP_DCCL_V_EMPTY);
    }
    /* beyond the bounds: "not given" (0 on the wire), as Goby */
    clear_all(v, 32);
    kelp_dccl_val_set_long(&v[d->fields[kelp_dccl_field_find(d, "u32")].slot], 4000000001LL);
    ck_assert_int_eq(kelp_dccl_encode(&cx, d, v, 32, NOON, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_dccl_decode(&cx, d, buf, n, NOON, out, 32), 0);
    ck_assert(out[d->fields[kelp_dccl_field_find(d, "u32")].slot].kind == KELP_DCCL_V_EMPTY);
    kelp_dccl_loaded_free(&ld);
    /* what Goby refuses: a bound that is not a number */
    static const char NAN_MAX[] = "<message_set><message><name>A</name><size>32</size><layout>"
                                  "<int><name>i</name><max>lots</max><min>0</min></int></layout></message></message_set>";
    kelp_dccl_loaded_init(&ld);
    ck_assert_int_lt(kelp_dccl_load_buffer(&ld, "n.xml", NAN_MAX, sizeof NAN_MAX - 1, NULL, &err), 0);
    ck_diag_has(&err, "<max> must be a number");
    kelp_dccl_loaded_free(&ld);
}
END_TEST

/* test/data/dccl/wide.xml: every field type with bounds in the billions, encrypted
 * round trip and publications; its <repeat/> message publishes once per index */
#ifndef KELP_TEST_ROOT
#define KELP_TEST_ROOT "."
#endif
typedef struct wide_in {
    const char *name;
    unsigned k;
    const char *s;
} wide_in;

static void set_wide(const kelp_dccl_msgdef *d, kelp_dccl_val *v, const wide_in *in, size_t n)
{
    clear_all(v, 64);
    for (size_t i = 0; i < n; i++) setv(d, v, in[i].name, in[i].k, in[i].s);
}

START_TEST(wide_message_set_file)
{
    kelp_dccl_loaded ld;
    kelp_dccl_mbedtls mb;
    kelp_dccl_codec cx;
    kelp_dccl_val v[64], out[64];
    kelp_dccl_pub pubs[16];
    uint8_t buf[KELP_DCCL_MAX_SIZE];
    kelp_diag err = {0};
    size_t n, np;
    kelp_dccl_loaded_init(&ld);
    ck_assert_msg(kelp_dccl_load_file(&ld, KELP_TEST_ROOT "/test/data/dccl/wide.xml", NULL, &err) == 0, "%s", kelp_diag_text(&err));
    const kelp_dccl_msgdef *d = kelp_dccl_set_find_name(&ld.set, "WIDE_ALL");
    const kelp_dccl_msgdef *r = kelp_dccl_set_find_name(&ld.set, "WIDE_REP");
    ck_assert(d && r);
    ck_assert_uint_eq(d->body_bits, 468);
    ck_assert_uint_eq(wide_field_bits(d, "s64"), 64);
    ck_assert_uint_eq(wide_field_bits(d, "pos"), 41);
    ck_assert(d->trigger_time == 0.5 && d->queuing.blackout_time == 0.25 && d->queuing.max_queue == 4000000000u);
    ck_assert_uint_eq(r->repeat, 5); /* 8 * 26 bits / (34 + 2) */
    ck_assert_int_eq(kelp_dccl_mbedtls_init(&mb, NULL), 0);
    kelp_dccl_codec_init(&cx, 1, &mb.ops, NULL);
    static const wide_in IN[] = {
        {"to", 0, "4"}, {"u32", 0, "4000000000"}, {"s34", 0, "-5000000000"}, {"q32", 0, "2147483646"},
        {"stamp", 0, "999999999999999"}, {"s64", 0, "-9200000000000000000"}, {"pos", 0, "-123456789.125"},
        {"ok", 0, "true"}, {"note", 0, "hello_kelp"}, {"mode", 0, "survey"}, {"raw", 0, "deadbeef"},
        {"track", 0, "-3999999999"}, {"track", 1, "-999999999"}, {"track", 2, "1"}, /* beyond max_delta: null */
    };
    set_wide(d, v, IN, sizeof IN / sizeof IN[0]);
    ck_assert_int_eq(kelp_dccl_encode(&cx, d, v, 64, NOON, buf, sizeof buf, &n), 0);
    ck_assert_uint_eq(n, 65);
    ck_assert_int_eq(kelp_dccl_decode(&cx, d, buf, n, NOON, out, 64), 0);
    ck_assert_int_eq(kelp_dccl_publish_all(&cx, d, out, 64, pubs, 16, &np), 0);
    ck_assert_uint_eq(np, 2);
    ck_assert_str_eq(pubs[0].s, "when=1699963200,from=1,to=4,kind=wide,u32=4000000000,s34=-5000000000,q32=2147483646,"
                                "stamp=999999999999999,s64=-9200000000000000000,pos=-123456789.125,ok=true,"
                                "note=hello_kelp,mode=survey,raw=deadbeef,track={-3999999999,-999999999,}");
    ck_assert_str_eq(pubs[1].s, "-5000000000 at 999999999999999");
    /* <repeat/>: 5 copies, one publication per index and publish */
    kelp_dccl_codec_init(&cx, 2, &mb.ops, NULL);
    static const wide_in REP[] = {
        {"big", 0, "-5000000000"}, {"big", 1, "4000000000"}, {"big", 4, "7"}, {"ok", 0, "true"}, {"ok", 4, "false"},
    };
    set_wide(r, v, REP, sizeof REP / sizeof REP[0]);
    ck_assert_int_eq(kelp_dccl_encode(&cx, r, v, 64, NOON, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_dccl_decode(&cx, r, buf, n, NOON, out, 64), 0);
    ck_assert_int_eq(kelp_dccl_publish_all(&cx, r, out, 64, pubs, 16, &np), 0);
    ck_assert_uint_eq(np, 15);
    ck_assert_str_eq(pubs[0].s, "from=2,big=-5000000000,ok=true");
    ck_assert_str_eq(pubs[2].s, "from=2,big=,ok=");
    ck_assert_str_eq(pubs[4].s, "from=2,big=7,ok=false");
    ck_assert_str_eq(pubs[6].s, "big=4000000000,ok=");
    ck_assert_str_eq(pubs[10].s, "-5000000000 from 2");
    ck_assert_str_eq(pubs[14].s, "7 from 2");
    kelp_dccl_mbedtls_free(&mb);
    kelp_dccl_loaded_free(&ld);
}
END_TEST

START_TEST(repeat_auto_count)
{
    kelp_dccl_loaded ld;
    kelp_diag err = {0};
    const kelp_dccl_msgdef *d;
    kelp_dccl_loaded_init(&ld);
    /* the Goby test algorithms are not registered: with no registry, unknown names load */
    ck_assert_msg(kelp_dccl_load_buffer(&ld, "test.xml", REPEAT_TEST, sizeof REPEAT_TEST - 1, NULL, &err) == 0,
                  "%s", kelp_diag_text(&err));
    d = ld.set.msgs[0];
    /* one copy: SUM 15 bits + I 8 bits = 23; 8*(128-6) = 976 -> 42 copies */
    ck_assert_uint_eq(d->repeat, 42);
    ck_assert_uint_eq(d->fields[9].array_length, 42);
    ck_assert_uint_eq(d->body_bits, 42u * 15u + 8u + 41u * 5u);
    kelp_dccl_loaded_free(&ld);
    /* with a registry, an unknown algorithm is an error */
    setup_algs();
    kelp_dccl_loaded_init(&ld);
    ck_assert_int_eq(kelp_dccl_load_buffer(&ld, "test.xml", REPEAT_TEST, sizeof REPEAT_TEST - 1, &algs, &err),
                     KELP_ERR_NOTFOUND);
    ck_assert_int_eq(err.code, KELP_ERR_NOTFOUND);
    ck_assert_int_eq(err.line, 3);
#ifndef KELP_NO_ERRMSG
    ck_assert_msg(strstr(err.msg, "test.xml:3: unknown algorithm \"sum\"") != NULL, "%s", err.msg);
#endif
    kelp_dccl_loaded_free(&ld);
}
END_TEST

/* ------------------------------------------------------------------ load-time errors */
static const struct {
    const char *xml;
    int rc;
    const char *msg;
} BAD[] = {
    {"<message_set><message><name>A</name><size>6</size><layout><bool><name>b</name></bool></layout></message></message_set>",
     KELP_ERR_RANGE, "bad.xml:1: <size> 6 must be larger than the 6-byte header"},
    {"<message_set><message><name>A</name><size>8</size>\n<layout><string><name>s</name><max_length>3</max_length></string></layout>\n</message></message_set>",
     KELP_ERR_RANGE, "bad.xml:1: DCCL: the message [A]: the message will not fit"},
    {"<message_set><message><name>A</name><size>32</size><layout><bool><name>b</name></bool></layout>\n"
     "<on_receipt><publish><publish_var>X</publish_var>\n<message_var>nope</message_var></publish></on_receipt></message></message_set>",
     KELP_ERR_NOTFOUND, "bad.xml:3: no such name \"nope\" found in <layout> or <header>"},
    {"<message_set><message><name>A</name><size>32</size><layout>\n<float algorithm=\"add:zz\"><name>f</name><max>1</max><min>0</min><precision>1</precision></float></layout></message></message_set>",
     KELP_ERR_NOTFOUND, "bad.xml:2: no such name \"zz\""},
    {"<message_set><message><name>A</name><size>32</size><layout><bool><name>b</name></bool></layout>\n<queuing><tll>1000</tll></queuing></message></message_set>",
     KELP_ERR_PARSE, "bad.xml:2: unexpected <tll> in <queuing>"},
    {"<message_set><message><name>A</name><size>32</size><repeat>2</repeat><layout>\n<bool><name>b</name><array_length>2</array_length></bool></layout></message></message_set>",
     KELP_ERR_RANGE, "<repeat> is not allowed on messages with arrays"},
    {"<message_set><message><size>32</size><layout><bool><name>b</name></bool></layout></message></message_set>",
     KELP_ERR_PARSE, "bad.xml:1: <message> needs a <name>"},
    {"<message_set><message><name>A</name><size>32</size><layout>\n<int><name>i</name><max>10</max></int></layout></message></message_set>",
     KELP_ERR_PARSE, "bad.xml:2: <int> i needs <max> and <min>"},
    {"<message_set><message><name>A</name><size>3x</size><layout><bool><name>b</name></bool></layout></message></message_set>",
     KELP_ERR_PARSE, "<size> must be an integer"},
    {"<message_set><message><name>A</name><id>1</id><size>32</size><layout><bool><name>b</name></bool></layout></message>\n"
     "<message><name>B</name><id>1</id><size>32</size><layout><bool><name>b</name></bool></layout></message></message_set>",
     KELP_ERR_EXISTS, "bad.xml:2: message B: id 1 already used by message A"},
    {"<message_set><message><name>A</name><size>32</size><layout><bool><name>b</name></bool></layout></message>",
     KELP_ERR_PARSE, "XML error"},
    {"<message_set><message><name>A</name><size>32</size><layout><bool foo=\"1\"><name>b</name></bool></layout></message></message_set>",
     KELP_ERR_PARSE, "attribute \"foo\" is not allowed on <bool>"},
    {"<message_set><message><name>A</name><size>32</size><trigger>publish</trigger><layout><bool><name>b</name></bool></layout></message></message_set>",
     KELP_ERR_PARSE, "needs a <trigger_var>"},
    {"<message_set><message><name>A</name><size>32</size><layout><hex><name>h</name></hex></layout></message></message_set>",
     KELP_ERR_PARSE, "<hex> h needs a <num_bytes>"},
};

START_TEST(load_errors_have_file_line_reason)
{
    kelp_dccl_loaded ld;
    kelp_diag err = {0};
    int rc;
    setup_algs();
    kelp_dccl_loaded_init(&ld);
    rc = kelp_dccl_load_buffer(&ld, "bad.xml", BAD[_i].xml, strlen(BAD[_i].xml), &algs, &err);
    ck_assert_msg(rc == BAD[_i].rc, "case %d: rc %d (%s)", _i, rc, kelp_diag_text(&err));
    ck_assert_int_eq(err.code, rc);
    if (strncmp(BAD[_i].msg, "bad.xml:", 8) == 0) /* the line of the message is the diag's line */
        ck_assert_msg(err.line == (int)strtol(BAD[_i].msg + 8, NULL, 10), "case %d: line %d", _i, err.line);
#ifndef KELP_NO_ERRMSG
    ck_assert_msg(strstr(err.msg, BAD[_i].msg) != NULL, "case %d: \"%s\" lacks \"%s\"", _i, err.msg, BAD[_i].msg);
#endif
    ck_assert_uint_eq(ld.set.n, 0);
    kelp_dccl_loaded_free(&ld);
}
END_TEST

START_TEST(missing_file_is_io_error)
{
    kelp_dccl_loaded ld;
    kelp_diag err = {0};
    kelp_dccl_loaded_init(&ld);
    ck_assert_int_eq(kelp_dccl_load_file(&ld, "/nonexistent/x.xml", NULL, &err), KELP_ERR_IO);
    ck_assert_int_eq(err.code, KELP_ERR_IO);
    ck_diag_has(&err, "/nonexistent/x.xml:0: cannot open");
    kelp_dccl_loaded_free(&ld);
}
END_TEST

Suite *kelp_dccl_xml_suite(void)
{
    Suite *s = suite_create("dccl_xml");
    TCase *tc = tcase_create("edge");
    tcase_add_test(tc, example1_loads_encrypts_publishes);
    tcase_add_test(tc, simple_status_vector_and_node_report);
    tcase_add_test(tc, arrays_all_and_typed_publish);
    tcase_add_test(tc, repeat_auto_count);
    tcase_add_test(tc, int_bounds_in_the_billions);
    tcase_add_test(tc, wide_message_set_file);
    tcase_add_loop_test(tc, repeat_publishes_once_per_index, 0, 2);
    tcase_add_loop_test(tc, load_errors_have_file_line_reason, 0, (int)(sizeof BAD / sizeof BAD[0]));
    tcase_add_test(tc, missing_file_is_io_error);
    suite_add_tcase(s, tc);
    return s;
}
