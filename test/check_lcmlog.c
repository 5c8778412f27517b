/* Unit tests: LCM log events -- parse, partial events, damage and resynchronisation. */
#include <check.h>
#include <string.h>
#include <kelp/lcmlog.h>

static size_t put_event(uint8_t *out, uint64_t n, const char *ch, const char *data)
{
    size_t cl = strlen(ch), dl = strlen(data);
    kelp_lcmlog_header(n, 1700000000123456LL, cl, dl, out);
    memcpy(out + KELP_LCMLOG_HDR_LEN, ch, cl);
    memcpy(out + KELP_LCMLOG_HDR_LEN + cl, data, dl);
    return KELP_LCMLOG_HDR_LEN + cl + dl;
}

START_TEST(t_parse_one)
{
    uint8_t b[256];
    size_t n = put_event(b, 7, "NAV_X", "hello");
    kelp_lcmlog_event ev;
    size_t used = 0;
    ck_assert_int_eq(kelp_lcmlog_parse(b, n, 1024, &ev, &used), KELP_OK);
    ck_assert_uint_eq(used, n);
    ck_assert_uint_eq(ev.eventnum, 7);
    ck_assert_int_eq(ev.timestamp, 1700000000123456LL);
    ck_assert_uint_eq(ev.channel_len, 5);
    ck_assert_mem_eq(ev.channel, "NAV_X", 5);
    ck_assert_uint_eq(ev.data_len, 5);
    ck_assert_mem_eq(ev.data, "hello", 5);
    /* bytes as lcm-logger writes them: sync word first, big-endian */
    ck_assert_uint_eq(b[0], 0xED);
    ck_assert_uint_eq(b[3], 0x01);
    ck_assert_uint_eq(b[11], 7);
}
END_TEST

START_TEST(t_partial_and_empty_channel)
{
    uint8_t b[256];
    size_t n = put_event(b, 1, "", "x");
    kelp_lcmlog_event ev;
    size_t used = 0;
    for (size_t k = 0; k < n; k++) {
        ck_assert_int_eq(kelp_lcmlog_parse(b, k, 1024, &ev, &used), KELP_ERR_PARTIAL);
        ck_assert_uint_eq(used, k < KELP_LCMLOG_HDR_LEN ? KELP_LCMLOG_HDR_LEN : n);
    }
    ck_assert_int_eq(kelp_lcmlog_parse(b, n, 1024, &ev, &used), KELP_OK);
    ck_assert_uint_eq(ev.channel_len, 0); /* an empty channel is an event like any other */
}
END_TEST

START_TEST(t_damage)
{
    uint8_t b[256];
    size_t n = put_event(b, 1, "A", "data");
    kelp_lcmlog_event ev;
    size_t used = 0;
    b[2] ^= 0xff; /* sync word */
    ck_assert_int_eq(kelp_lcmlog_parse(b, n, 1024, &ev, &used), KELP_ERR_PARSE);
    b[2] ^= 0xff;
    ck_assert_int_eq(kelp_lcmlog_parse(b, n, 3, &ev, &used), KELP_ERR_PARSE); /* data over max */
    b[20] = 0xff;                                                              /* channel length 4 G */
    ck_assert_int_eq(kelp_lcmlog_parse(b, n, 1024, &ev, &used), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_lcmlog_parse(NULL, n, 1024, &ev, &used), KELP_ERR_ARG);
}
END_TEST

START_TEST(t_resync)
{
    uint8_t b[512];
    memcpy(b, "junk-bytes", 10);
    size_t n1 = put_event(b + 10, 1, "A", "1");
    ck_assert_uint_eq(kelp_lcmlog_resync(b, 10 + n1, 1), 10);
    /* none: the last three bytes are kept (a sync word may straddle the buffer's end) */
    ck_assert_uint_eq(kelp_lcmlog_resync(b, 10, 0), 7);
    ck_assert_uint_eq(kelp_lcmlog_resync(b, 10 + n1, 11), 10 + n1 - 3);
    /* a whole walk: junk, event, junk, event */
    size_t n = 10 + n1;
    memcpy(b + n, "\xed\xa1zz", 4);
    n += 4;
    n += put_event(b + n, 2, "B", "22");
    size_t pos = 0, events = 0, damage = 0;
    while (pos < n) {
        kelp_lcmlog_event ev;
        size_t used;
        int rc = kelp_lcmlog_parse(b + pos, n - pos, 1024, &ev, &used);
        if (rc == KELP_OK) {
            events++;
            pos += used;
        } else if (rc == KELP_ERR_PARSE) {
            damage++;
            pos = kelp_lcmlog_resync(b, n, pos + 1);
        } else {
            break;
        }
    }
    ck_assert_uint_eq(events, 2);
    ck_assert_uint_eq(damage, 2);
    ck_assert_uint_eq(pos, n);
}
END_TEST

Suite *kelp_lcmlog_suite(void)
{
    Suite *s = suite_create("lcmlog");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, t_parse_one);
    tcase_add_test(tc, t_partial_and_empty_channel);
    tcase_add_test(tc, t_damage);
    tcase_add_test(tc, t_resync);
    suite_add_tcase(s, tc);
    return s;
}
