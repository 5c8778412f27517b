/* Unit tests: kelp over CAN -- dictionary, body kinds, segmentation and reassembly in order,
 * out of order, with a dropped frame, with junk, slots, CRC, filters, and kelp-canbridge's
 * routes with renaming. */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/bridge.h>
#include <kelp/can.h>
#include <kelp/canbridge.h>

#define MAXF 80
typedef struct rec {
    kelp_can_frame f[MAXF];
    size_t n;
} rec;

static int rec_emit(void *user, const kelp_can_frame *f)
{
    rec *r = user;
    if (r->n >= MAXF) return KELP_ERR_NOSPACE;
    r->f[r->n++] = *f;
    return 0;
}

static kelp_can_dict D;
static kelp_can_rx RX;
static kelp_can_tx TX;
static rec R;

static void setup(void)
{
    kelp_diag why;
    kelp_diag_clear(&why);
    kelp_can_dict_init(&D);
    ck_assert_int_eq(kelp_can_dict_parse(&D, "3=THRUST_CMD, 7 = DEPTH, 12=STATUS_TEXT", &why), 0);
    kelp_can_rx_init(&RX, 1.0);
    ck_assert_int_eq(kelp_can_tx_init(&TX, 5, false), 0);
    memset(&R, 0, sizeof R);
}

static kelp_can_msg num(const char *name, double d)
{
    kelp_can_msg m;
    memset(&m, 0, sizeof m);
    m.name = name;
    m.kind = KELP_CAN_KIND_F64;
    m.dval = d;
    return m;
}

static kelp_can_msg str(const char *name, const char *s)
{
    kelp_can_msg m;
    memset(&m, 0, sizeof m);
    m.name = name;
    m.kind = KELP_CAN_KIND_STRING;
    m.sval = (const uint8_t *)s;
    m.slen = strlen(s);
    return m;
}

/* feed frames in the order given by idx (n entries); return deliveries, last message in *out */
static int feed(const size_t *idx, size_t n, double now, kelp_can_msg *out)
{
    int got = 0;
    for (size_t i = 0; i < n; i++) {
        kelp_can_msg m;
        if (kelp_can_rx_frame(&RX, &D, &R.f[idx ? idx[i] : i], now, &m) == 1) {
            *out = m;
            got++;
        }
    }
    return got;
}

START_TEST(t_crc_and_dlc)
{
    ck_assert_uint_eq(kelp_can_crc16((const uint8_t *)"123456789", 9), 0x29B1);
    ck_assert_uint_eq(kelp_can_fd_len(5), 5);
    ck_assert_uint_eq(kelp_can_fd_len(9), 12);
    ck_assert_uint_eq(kelp_can_fd_len(33), 48);
    ck_assert_uint_eq(kelp_can_fd_len(64), 64);
    ck_assert_uint_eq(kelp_can_fd_len(65), 0);
}
END_TEST

START_TEST(t_dict)
{
    kelp_diag why;
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_can_dict_id(&D, "DEPTH"), 7);
    ck_assert_str_eq(kelp_can_dict_name(&D, 12), "STATUS_TEXT");
    ck_assert_ptr_null(kelp_can_dict_name(&D, 4));
    ck_assert_int_eq(kelp_can_dict_add(&D, 3, "OTHER"), KELP_ERR_EXISTS);
    ck_assert_int_eq(kelp_can_dict_add(&D, 4, "DEPTH"), KELP_ERR_EXISTS);
    ck_assert_int_eq(kelp_can_dict_add(&D, 511, "X"), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_can_dict_parse(&D, "600=X", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(why.code, KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_can_dict_parse(&D, "X", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_can_dict_parse(&D, "a=B", &why), KELP_ERR_PARSE);
    ck_assert_uint_eq(D.n, 3);
}
END_TEST

/* the example of docs/CAN.md, byte for byte */
START_TEST(t_wire_exact_single)
{
    kelp_can_msg m = num("THRUST_CMD", 1500);
    ck_assert_int_eq(kelp_can_send(&TX, &D, &m, rec_emit, &R), 1);
    ck_assert_uint_eq(R.f[0].id, 0x12A14003u);
    ck_assert_uint_eq(KELP_CAN_ID_NODE(R.f[0].id), 5);
    ck_assert_uint_eq(KELP_CAN_ID_VAR(R.f[0].id), 3);
    ck_assert_uint_eq(R.f[0].len, 6);
    const uint8_t want[6] = { 0x05, 0x02, 0x00, 0x00, 0x05, 0xDC };
    ck_assert_mem_eq(R.f[0].data, want, 6);
    kelp_can_msg out;
    ck_assert_int_eq(feed(NULL, 1, 0, &out), 1);
    ck_assert_str_eq(out.name, "THRUST_CMD");
    ck_assert_double_eq(out.dval, 1500);
    ck_assert_uint_eq(out.node, 5);
    ck_assert_ptr_null(out.source);
    /* DEPTH 12.25 as f32, and docs/CAN.md's named string in classic and FD */
    R.n = 0;
    kelp_can_msg dm = num("DEPTH", 12.25);
    ck_assert_int_eq(kelp_can_send(&TX, &D, &dm, rec_emit, &R), 1);
    const uint8_t wd[6] = { 0x05, 0x01, 0x41, 0x44, 0x00, 0x00 };
    ck_assert_mem_eq(R.f[0].data, wd, 6);
    R.n = 0;
    kelp_can_msg sm = str("FW_STATUS", "thrust=42.5,commands=1");
    ck_assert_int_eq(kelp_can_send(&TX, &D, &sm, rec_emit, &R), 6);
    const uint8_t wf[8] = { 0x40, 0x00, 0x21, 0, 0, 0x13, 0x09, 'F' };
    ck_assert_mem_eq(R.f[0].data, wf, 3);
    ck_assert_mem_eq(R.f[0].data + 5, wf + 5, 3);
    ck_assert_uint_eq(R.f[5].data[0], 0x85);
    ck_assert_uint_eq(R.f[5].len, 3);
    R.n = 0;
    TX.fd = true;
    ck_assert_int_eq(kelp_can_send(&TX, &D, &sm, rec_emit, &R), 1);
    ck_assert_uint_eq(R.f[0].len, 48);
    ck_assert_mem_eq(R.f[0].data, "\x21\x13\x09" "F", 4);
    TX.fd = false;
    R.n = 1;
    /* the next message has the next transfer id */
    ck_assert_int_eq(kelp_can_send(&TX, &D, &m, rec_emit, &R), 1);
    ck_assert_uint_eq(KELP_CAN_ID_TID(R.f[1].id), 4);
}
END_TEST

START_TEST(t_numeric_kinds_exact)
{
    const double vals[] = { 12.5, 12.3, -7, 3e9, 4294967297.0, -0.0, 1e-300, INFINITY };
    const unsigned kinds[] = { KELP_CAN_KIND_F32, KELP_CAN_KIND_F64, KELP_CAN_KIND_I32, KELP_CAN_KIND_F32,
                               KELP_CAN_KIND_F64, KELP_CAN_KIND_F32, KELP_CAN_KIND_F64, KELP_CAN_KIND_F32 };
    for (size_t i = 0; i < sizeof vals / sizeof vals[0]; i++) {
        R.n = 0;
        kelp_can_msg m = num("DEPTH", vals[i]);
        ck_assert_int_ge(kelp_can_send(&TX, &D, &m, rec_emit, &R), 1);
        ck_assert_uint_eq(R.f[0].data[0] & 0xC0u, R.n == 1 ? KELP_CAN_PCI_SINGLE : KELP_CAN_PCI_FIRST);
        if (R.n == 1) ck_assert_uint_eq(R.f[0].data[1] & 7u, kinds[i]);
        else ck_assert_uint_eq(R.f[0].data[5] & 7u, kinds[i]);
        kelp_can_msg out;
        ck_assert_int_eq(feed(NULL, R.n, 0, &out), 1);
        ck_assert(out.dval == vals[i]);
        ck_assert_int_eq(!!signbit(out.dval), !!signbit(vals[i]));
    }
    /* NaN stays a NaN */
    R.n = 0;
    kelp_can_msg m = num("DEPTH", NAN);
    ck_assert_int_eq(kelp_can_send(&TX, &D, &m, rec_emit, &R), 2);
    kelp_can_msg out;
    ck_assert_int_eq(feed(NULL, R.n, 0, &out), 1);
    ck_assert(isnan(out.dval));
}
END_TEST

static const char *LONG_TEXT = "MODE=SURVEYING,LEG=12,BATT=87.5,FAULTS=none,NOTE=the quick brown fox jumps over the "
                               "lazy dog again and again until the frame count is well past a dozen";

static void roundtrip_named(bool fd)
{
    TX.fd = fd;
    kelp_can_msg m = str("VEHICLE_STATUS_LONG_NAME", LONG_TEXT);
    m.source = "pFirmware";
    m.has_time = true;
    m.time = 1700000000.25;
    int nf = kelp_can_send(&TX, &D, &m, rec_emit, &R);
    /* body: hdr 1 + time 8 + name 1+24 + source 1+9 + text */
    size_t body = 1 + 8 + 25 + 10 + strlen(LONG_TEXT);
    size_t first = fd ? KELP_CAN_FD_FIRST : KELP_CAN_CLASSIC_FIRST, chunk = fd ? KELP_CAN_FD_CHUNK : KELP_CAN_CLASSIC_CHUNK;
    ck_assert_int_eq(nf, 1 + (int)((body - first + chunk - 1) / chunk));
    for (int i = 0; i < nf; i++) {
        ck_assert_uint_eq(KELP_CAN_ID_VAR(R.f[i].id), KELP_CAN_VAR_NAMED);
        ck_assert_uint_eq(R.f[i].id, R.f[0].id);
        ck_assert(R.f[i].fd == fd);
        if (i < nf - 1) ck_assert_uint_eq(R.f[i].len, fd ? 64 : 8);
    }
    ck_assert_uint_eq(R.f[0].data[1] << 8 | R.f[0].data[2], body);
    kelp_can_msg out;
    ck_assert_int_eq(feed(NULL, R.n, 0, &out), 1);
    ck_assert_str_eq(out.name, "VEHICLE_STATUS_LONG_NAME");
    ck_assert_str_eq(out.source, "pFirmware");
    ck_assert(out.has_time);
    ck_assert_double_eq(out.time, 1700000000.25);
    ck_assert_uint_eq(out.kind, KELP_CAN_KIND_STRING);
    ck_assert_uint_eq(out.slen, strlen(LONG_TEXT));
    ck_assert_str_eq((const char *)out.sval, LONG_TEXT);
    ck_assert_uint_eq(RX.st.out_of_order, 0);
    ck_assert_uint_eq(RX.st.messages, 1);
}

START_TEST(t_roundtrip_classic)
{
    roundtrip_named(false);
}
END_TEST

START_TEST(t_roundtrip_fd)
{
    roundtrip_named(true);
}
END_TEST

START_TEST(t_out_of_order)
{
    kelp_can_msg m = str("STATUS_TEXT", LONG_TEXT);
    int nf = kelp_can_send(&TX, &D, &m, rec_emit, &R);
    ck_assert_int_gt(nf, 10);
    size_t idx[MAXF];
    for (int i = 0; i < nf; i++) idx[i] = (size_t)(nf - 1 - i); /* completely reversed: first frame last */
    kelp_can_msg out;
    ck_assert_int_eq(feed(idx, (size_t)nf, 0.5, &out), 1);
    ck_assert_str_eq((const char *)out.sval, LONG_TEXT);
    ck_assert_str_eq(out.name, "STATUS_TEXT");
    ck_assert_uint_eq(RX.st.out_of_order, (unsigned long)nf - 1u);
    /* a swap of two neighbours in the middle */
    R.n = 0;
    nf = kelp_can_send(&TX, &D, &m, rec_emit, &R);
    for (int i = 0; i < nf; i++) idx[i] = (size_t)i;
    idx[4] = 5;
    idx[5] = 4;
    ck_assert_int_eq(feed(idx, (size_t)nf, 0.6, &out), 1);
    ck_assert_str_eq((const char *)out.sval, LONG_TEXT);
    ck_assert_uint_eq(RX.st.messages, 2);
    ck_assert_uint_eq(RX.st.timed_out, 0);
}
END_TEST

START_TEST(t_dropped_frame_times_out)
{
    kelp_can_msg m = str("STATUS_TEXT", LONG_TEXT);
    int nf = kelp_can_send(&TX, &D, &m, rec_emit, &R);
    size_t idx[MAXF], k = 0;
    for (int i = 0; i < nf; i++)
        if (i != 3) idx[k++] = (size_t)i;
    kelp_can_msg out;
    ck_assert_int_eq(feed(idx, k, 10.0, &out), 0);
    ck_assert_uint_eq(RX.st.timed_out, 0);
    kelp_can_rx_expire(&RX, 10.9);
    ck_assert_uint_eq(RX.st.timed_out, 0);
    kelp_can_rx_expire(&RX, 11.1);
    ck_assert_uint_eq(RX.st.timed_out, 1);
    /* the late frame now opens a fresh slot that also times out; nothing is delivered */
    ck_assert_int_eq(kelp_can_rx_frame(&RX, &D, &R.f[3], 11.2, &out), 0);
    kelp_can_rx_expire(&RX, 13);
    ck_assert_uint_eq(RX.st.timed_out, 2);
    ck_assert_uint_eq(RX.st.messages, 0);
    /* and a dropped last frame, noticed by a frame arriving later (expiry inside rx_frame) */
    R.n = 0;
    nf = kelp_can_send(&TX, &D, &m, rec_emit, &R);
    ck_assert_int_eq(feed(NULL, (size_t)nf - 1, 20, &out), 0);
    R.n = 0;
    kelp_can_msg s = num("DEPTH", 2.5);
    ck_assert_int_eq(kelp_can_send(&TX, &D, &s, rec_emit, &R), 1);
    ck_assert_int_eq(feed(NULL, 1, 22, &out), 1);
    ck_assert_double_eq(out.dval, 2.5);
    ck_assert_uint_eq(RX.st.timed_out, 3);
}
END_TEST

START_TEST(t_junk_counted)
{
    kelp_can_frame j;
    kelp_can_msg out;
    memset(&j, 0, sizeof j);
    /* not kelp: a standard id and another tag */
    j.id = 0x123;
    j.len = 8;
    ck_assert_int_eq(kelp_can_rx_frame(&RX, &D, &j, 0, &out), 0);
    j.id = KELP_CAN_ID(4, 5, 0, 3) ^ (1u << 21);
    ck_assert_int_eq(kelp_can_rx_frame(&RX, &D, &j, 0, &out), 0);
    ck_assert_uint_eq(RX.st.foreign, 2);
    j.id = KELP_CAN_ID(4, 5, 0, 3);
    const struct {
        uint8_t len, b0, b1, b2;
        bool fd;
    } bad[] = {
        { 0, 0, 0, 0, false },                      /* empty */
        { 8, 0xC0, 0, 0, false },                   /* reserved PCI */
        { 8, 0x00, 0, 0, false },                   /* single of length 0 */
        { 4, 0x07, 0, 0, false },                   /* single longer than the frame */
        { 8, 0x40, 0, 5, false },                   /* first frame whose total fits a single */
        { 8, 0x40, 0x10, 0, false },                /* first frame of 4096 bytes */
        { 5, 0x40, 0, 100, false },                 /* first frame not full */
        { 8, 0x80, 0, 0, false },                   /* consecutive index 0 */
        { 9, 0x01, 0, 0, false },                   /* classic with 9 bytes */
        { 13, 0x01, 0, 0, true },                   /* FD length that is no DLC */
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        j.len = bad[i].len;
        j.fd = bad[i].fd;
        j.data[0] = bad[i].b0;
        j.data[1] = bad[i].b1;
        j.data[2] = bad[i].b2;
        ck_assert_int_lt(kelp_can_rx_frame(&RX, &D, &j, 0, &out), 0);
    }
    ck_assert_uint_eq(RX.st.bad_frame, sizeof bad / sizeof bad[0]);
    /* a single frame whose body does not parse: header with reserved bits */
    j.fd = false;
    j.len = 6;
    j.data[0] = 0x05;
    j.data[1] = 0xC2;
    ck_assert_int_lt(kelp_can_rx_frame(&RX, &D, &j, 0, &out), 0);
    j.data[1] = 0x02; /* i32 but 3 value bytes */
    j.data[0] = 0x04;
    ck_assert_int_lt(kelp_can_rx_frame(&RX, &D, &j, 0, &out), 0);
    j.data[1] = KELP_CAN_KIND_I32 | KELP_CAN_HDR_NAME; /* a name under a dictionary id */
    ck_assert_int_lt(kelp_can_rx_frame(&RX, &D, &j, 0, &out), 0);
    ck_assert_uint_eq(RX.st.bad_body, 3);
    /* an id not in the dictionary */
    j.id = KELP_CAN_ID(4, 5, 0, 99);
    j.len = 6;
    j.data[0] = 0x05;
    j.data[1] = KELP_CAN_KIND_I32;
    ck_assert_int_eq(kelp_can_rx_frame(&RX, &D, &j, 0, &out), KELP_ERR_NOTFOUND);
    ck_assert_uint_eq(RX.st.unknown_var, 1);
    /* the receiver still works */
    kelp_can_msg m = num("DEPTH", 4.25);
    ck_assert_int_eq(kelp_can_send(&TX, &D, &m, rec_emit, &R), 1);
    ck_assert_int_eq(feed(NULL, 1, 0, &out), 1);
    ck_assert_double_eq(out.dval, 4.25);
    ck_assert_uint_eq(RX.st.messages, 1);
}
END_TEST

START_TEST(t_crc_duplicate_abort_mixed)
{
    kelp_can_msg m = str("STATUS_TEXT", LONG_TEXT), out;
    int nf = kelp_can_send(&TX, &D, &m, rec_emit, &R);
    R.f[2].data[3] ^= 0x10; /* a bit flipped where CAN's own CRC would not see it */
    ck_assert_int_eq(feed(NULL, (size_t)nf, 0, &out), 0);
    ck_assert_uint_eq(RX.st.bad_crc, 1);
    /* duplicate consecutive frame */
    R.n = 0;
    nf = kelp_can_send(&TX, &D, &m, rec_emit, &R);
    ck_assert_int_eq(kelp_can_rx_frame(&RX, &D, &R.f[0], 0, &out), 0);
    ck_assert_int_eq(kelp_can_rx_frame(&RX, &D, &R.f[1], 0, &out), 0);
    ck_assert_int_eq(kelp_can_rx_frame(&RX, &D, &R.f[1], 0, &out), KELP_ERR_REPLAY);
    ck_assert_uint_eq(RX.st.duplicate, 1);
    /* a new first frame under the same id aborts the old message; the new one completes */
    ck_assert_int_eq(feed(NULL, (size_t)nf, 0, &out), 1);
    ck_assert_uint_eq(RX.st.aborted, 1);
    ck_assert_str_eq((const char *)out.sval, LONG_TEXT);
    /* a classic frame joining an FD message is refused */
    R.n = 0;
    TX.fd = true;
    nf = kelp_can_send(&TX, &D, &m, rec_emit, &R);
    ck_assert_int_ge(nf, 2);
    ck_assert_int_eq(kelp_can_rx_frame(&RX, &D, &R.f[0], 0, &out), 0);
    kelp_can_frame c = R.f[1];
    c.fd = false;
    c.len = 8;
    unsigned long bf = RX.st.bad_frame;
    ck_assert_int_lt(kelp_can_rx_frame(&RX, &D, &c, 0, &out), 0);
    ck_assert_uint_eq(RX.st.bad_frame, bf + 1);
}
END_TEST

START_TEST(t_slots_full)
{
    kelp_can_msg m = str("STATUS_TEXT", LONG_TEXT), out;
    kelp_can_frame firsts[KELP_CAN_SLOTS + 1];
    for (unsigned i = 0; i <= KELP_CAN_SLOTS; i++) {
        R.n = 0;
        ck_assert_int_eq(kelp_can_tx_init(&TX, 10 + i, false), 0);
        ck_assert_int_gt(kelp_can_send(&TX, &D, &m, rec_emit, &R), 1);
        firsts[i] = R.f[0];
    }
    for (unsigned i = 0; i < KELP_CAN_SLOTS; i++)
        ck_assert_int_eq(kelp_can_rx_frame(&RX, &D, &firsts[i], 0, &out), 0);
    ck_assert_int_eq(kelp_can_rx_frame(&RX, &D, &firsts[KELP_CAN_SLOTS], 0, &out), KELP_ERR_NOSPACE);
    ck_assert_uint_eq(RX.st.slot_full, 1);
    /* after the timeout the slots are free again and the last sender's message gets through */
    ck_assert_int_eq(feed(NULL, R.n, 5, &out), 1);
    ck_assert_uint_eq(RX.st.timed_out, KELP_CAN_SLOTS);
    ck_assert_uint_eq(out.node, 10 + KELP_CAN_SLOTS);
    ck_assert_uint_eq(RX.st.frames, RX.st.frames_ok + RX.st.slot_full);
}
END_TEST

START_TEST(t_too_big)
{
    static char big[KELP_CAN_MAX_BODY + 1];
    memset(big, 'x', sizeof big - 1);
    kelp_can_msg m = str("STATUS_TEXT", big);
    ck_assert_int_eq(kelp_can_send(&TX, &D, &m, rec_emit, &R), KELP_ERR_RANGE);
    ck_assert_uint_eq(R.n, 0);
    m.slen = KELP_CAN_MAX_BODY - 1; /* plus the header byte: the largest body */
    int nf = kelp_can_send(&TX, &D, &m, rec_emit, &R);
    ck_assert_int_eq(nf, 1 + (int)KELP_CAN_MAX_SEGS);
    kelp_can_msg out;
    ck_assert_int_eq(feed(NULL, R.n, 0, &out), 1);
    ck_assert_uint_eq(out.slen, KELP_CAN_MAX_BODY - 1);
}
END_TEST

START_TEST(t_filters)
{
    const uint16_t vars[] = { 3, 7, 3, KELP_CAN_VAR_NAMED };
    kelp_can_filter f[8];
    size_t n = kelp_can_filters(vars, 4, f, 8);
    ck_assert_uint_eq(n, 3);
    ck_assert(kelp_can_filter_pass(f, n, KELP_CAN_ID(1, 9, 3, 7), true));
    ck_assert(kelp_can_filter_pass(f, n, KELP_CAN_ID(7, 1, 0, KELP_CAN_VAR_NAMED), true));
    ck_assert(!kelp_can_filter_pass(f, n, KELP_CAN_ID(1, 9, 3, 8), true));
    ck_assert(!kelp_can_filter_pass(f, n, KELP_CAN_ID(1, 9, 3, 7) & 0x7FFu, false)); /* standard frame */
    ck_assert(!kelp_can_filter_pass(f, n, KELP_CAN_ID(1, 9, 3, 7) ^ (1u << 22), true)); /* other tag */
    n = kelp_can_filters(vars, 0, f, 8);
    ck_assert_uint_eq(n, 1);
    ck_assert(kelp_can_filter_pass(f, n, KELP_CAN_ID(1, 9, 3, 100), true));
    ck_assert(!kelp_can_filter_pass(f, n, 0x123, false));
}
END_TEST

START_TEST(t_parse_rename)
{
    kelp_bridge_route r[16];
    size_t n = 0;
    kelp_diag why;
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_bridge_parse_rename("[A, B] -> [X,Y]", r, 16, &n, &why), 0);
    ck_assert_uint_eq(n, 2);
    ck_assert_str_eq(r[1].src, "B");
    ck_assert_str_eq(r[1].alias, "Y");
    ck_assert_int_eq(kelp_bridge_parse_rename("DESIRED_THRUST -> THRUST_CMD", r, 16, &n, &why), 0);
    ck_assert_uint_eq(n, 1);
    ck_assert_str_eq(r[0].src, "DESIRED_THRUST");
    ck_assert_str_eq(r[0].alias, "THRUST_CMD");
    ck_assert_int_eq(kelp_bridge_parse_rename("NAV_*", r, 16, &n, &why), 0);
    ck_assert_str_eq(r[0].alias, "");
    ck_assert_int_eq(kelp_bridge_parse_rename("[A,B] -> [X]", r, 16, &n, &why), KELP_ERR_PARSE);
    ck_diag(&why, KELP_ERR_PARSE, "alias list length differs from variable list");
    ck_assert_int_eq(kelp_bridge_parse_rename("NAV_* -> X", r, 16, &n, &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_bridge_parse_rename("A - X", r, 16, &n, &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_bridge_parse_rename("A -> X junk", r, 16, &n, &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_bridge_parse_rename("", r, 16, &n, &why), KELP_ERR_PARSE);
    /* the line is checked before the routes are written: too few routes leaves them alone */
    memset(r, 0x5a, sizeof r);
    ck_assert_int_eq(kelp_bridge_parse_rename("[A, B, C] -> [X, Y, Z]", r, 2, &n, &why), KELP_ERR_NOSPACE);
    ck_assert_uint_eq((unsigned char)r[0].src[0], 0x5a);
    ck_assert_int_eq(kelp_bridge_parse_rename("[A, B, C] -> [X, Y, Z]", r, 3, &n, &why), 0);
    ck_assert_uint_eq(n, 3);
    ck_assert_str_eq(r[2].src, "C");
    ck_assert_str_eq(r[2].alias, "Z");
    ck_assert_uint_eq((unsigned char)r[3].src[0], 0x5a);
    /* a route table that fills up; names read straight into it */
    static kelp_canbridge cb;
    ck_assert_int_eq(kelp_canbridge_init(&cb, 3, false, 1.0), 0);
    char line[64 * 17];
    size_t at = 0;
    line[at++] = '[';
    for (int i = 0; i < 16; i++) at += (size_t)snprintf(line + at, sizeof line - at, "%sV%d", i ? "," : "", i);
    line[at++] = ']';
    line[at] = 0;
    size_t added = 0;
    while (added + 16 <= KELP_CANBRIDGE_MAX_ROUTES) {
        ck_assert_int_eq(kelp_canbridge_add(&cb, true, line, &why), 0);
        added += 16;
    }
    ck_assert_uint_eq(cb.nto, added);
    while (cb.nto < KELP_CANBRIDGE_MAX_ROUTES) ck_assert_int_eq(kelp_canbridge_add(&cb, true, "S", &why), 0);
    kelp_diag_clear(&why); /* (earlier refusals above are still recorded: first error wins) */
    ck_assert_int_eq(kelp_canbridge_add(&cb, true, "S", &why), KELP_ERR_NOSPACE);
    ck_diag(&why, KELP_ERR_NOSPACE, "too many routes");
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_canbridge_add(&cb, true, "[NAV_*, B] -> [X, Y]", &why), KELP_ERR_PARSE);
    ck_diag_msg(&why, "a glob cannot be renamed");
    ck_assert_int_eq(kelp_canbridge_init(&cb, 3, false, 1.0), 0);
    ck_assert_int_eq(kelp_canbridge_add(&cb, false, "[OK, B] -> [SHORT, LONGER_NAME]", &why), 0);
    ck_assert_uint_eq(cb.nfrom, 2);
    ck_assert_str_eq(cb.from_src[1], "B");
    ck_assert_str_eq(cb.from_alias[1], "LONGER_NAME");
    ck_assert_int_eq(kelp_canbridge_add(&cb, false, "PLAIN", &why), 0);
    ck_assert_str_eq(cb.from_alias[2], "");
}
END_TEST

static kelp_canbridge B1, B2;

START_TEST(t_canbridge_both_ways)
{
    kelp_diag why;
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_canbridge_init(&B1, 1, false, 1.0), 0); /* the autonomy computer */
    ck_assert_int_eq(kelp_canbridge_init(&B2, 2, false, 1.0), 0); /* a firmware-side peer */
    ck_assert_int_eq(kelp_can_dict_parse(&B1.dict, "3=THRUST_CMD,7=DEPTH", &why), 0);
    ck_assert_int_eq(kelp_can_dict_parse(&B2.dict, "3=THRUST_CMD,7=DEPTH", &why), 0);
    ck_assert_int_eq(kelp_canbridge_add(&B1, true, "DESIRED_THRUST -> THRUST_CMD", &why), 0);
    ck_assert_int_eq(kelp_canbridge_add(&B1, false, "[DEPTH, FW_*] -> [NAV_DEPTH_CAN]", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_canbridge_add(&B1, false, "DEPTH -> NAV_DEPTH_CAN", &why), 0);
    ck_assert_int_eq(kelp_canbridge_add(&B1, false, "FW_*", &why), 0);
    ck_assert_int_eq(kelp_canbridge_add(&B2, true, "[NAV_DEPTH, FW_NOTE] -> [DEPTH, FW_NOTE]", &why), 0);
    ck_assert_int_eq(kelp_canbridge_add(&B2, false, "THRUST_CMD", &why), 0);
    kelp_can_filter f[8];
    size_t nf = kelp_canbridge_filters(&B1, f, 8);
    ck_assert_uint_eq(nf, 2); /* DEPTH's id and the named id (for the glob) */
    ck_assert(kelp_can_filter_pass(f, nf, KELP_CAN_ID(4, 2, 0, 7), true));
    ck_assert(!kelp_can_filter_pass(f, nf, KELP_CAN_ID(4, 2, 0, 3), true));

    static kelp_var v, out;
    memset(&v, 0, sizeof v);
    strcpy(v.name, "DESIRED_THRUST");
    strcpy(v.source, "pHelmIvP");
    v.kind = KELP_VAR_DOUBLE;
    v.dval = 42.5;
    v.time = 100;
    ck_assert_int_eq(kelp_canbridge_from_bus(&B1, &v, rec_emit, &R), 1); /* value only: one frame */
    ck_assert_uint_eq(R.f[0].len, 6);
    B1.send_time = B1.send_source = true;
    R.n = 0;
    ck_assert_int_eq(kelp_canbridge_from_bus(&B1, &v, rec_emit, &R), 4); /* 22-byte body: 3 + 3 * 7 */
    ck_assert_uint_eq(KELP_CAN_ID_VAR(R.f[0].id), 3);
    int got = 0;
    for (size_t i = 0; i < R.n; i++) got += kelp_canbridge_from_can(&B2, &R.f[i], 100, &out) == 1;
    ck_assert_int_eq(got, 1);
    ck_assert_str_eq(out.name, "THRUST_CMD");
    ck_assert_str_eq(out.source, "pHelmIvP");
    ck_assert_double_eq(out.time, 100);
    ck_assert_double_eq(out.dval, 42.5);
    ck_assert(out.flags & KELP_VAR_FLAG_BRIDGED);
    /* what came through a bridge is not sent back */
    R.n = 0;
    ck_assert_int_eq(kelp_canbridge_from_bus(&B2, &out, rec_emit, &R), 0);
    /* the other way, renamed, and a glob route with a named variable */
    strcpy(v.name, "NAV_DEPTH");
    v.source[0] = 0;
    v.dval = 12.75;
    ck_assert_int_ge(kelp_canbridge_from_bus(&B2, &v, rec_emit, &R), 1);
    strcpy(v.name, "FW_NOTE");
    v.kind = KELP_VAR_STRING;
    strcpy(v.sval, "hello from firmware");
    v.slen = strlen(v.sval);
    ck_assert_int_ge(kelp_canbridge_from_bus(&B2, &v, rec_emit, &R), 1);
    strcpy(v.name, "UNROUTED");
    ck_assert_int_eq(kelp_canbridge_from_bus(&B2, &v, rec_emit, &R), 0);
    int n = 0;
    static kelp_var outs[2];
    for (size_t i = 0; i < R.n; i++)
        if (kelp_canbridge_from_can(&B1, &R.f[i], 100, &outs[n < 2 ? n : 1]) == 1) n++;
    ck_assert_int_eq(n, 2);
    ck_assert_str_eq(outs[0].name, "NAV_DEPTH_CAN");
    ck_assert_double_eq(outs[0].dval, 12.75);
    ck_assert_str_eq(outs[0].source, "can2");
    ck_assert_str_eq(outs[1].name, "FW_NOTE");
    ck_assert_str_eq(outs[1].sval, "hello from firmware");
    ck_assert_uint_eq(B1.from_msgs, 2);
    ck_assert_uint_eq(B2.to_msgs, 2);
}
END_TEST

Suite *kelp_can_suite(void)
{
    Suite *s = suite_create("can");
    TCase *tc = tcase_create("core");
    tcase_add_checked_fixture(tc, setup, NULL);
    tcase_add_test(tc, t_crc_and_dlc);
    tcase_add_test(tc, t_dict);
    tcase_add_test(tc, t_wire_exact_single);
    tcase_add_test(tc, t_numeric_kinds_exact);
    tcase_add_test(tc, t_roundtrip_classic);
    tcase_add_test(tc, t_roundtrip_fd);
    tcase_add_test(tc, t_out_of_order);
    tcase_add_test(tc, t_dropped_frame_times_out);
    tcase_add_test(tc, t_junk_counted);
    tcase_add_test(tc, t_crc_duplicate_abort_mixed);
    tcase_add_test(tc, t_slots_full);
    tcase_add_test(tc, t_too_big);
    tcase_add_test(tc, t_filters);
    tcase_add_test(tc, t_parse_rename);
    tcase_add_test(tc, t_canbridge_both_ways);
    suite_add_tcase(s, tc);
    return s;
}
