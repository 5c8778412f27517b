/* kelp LCM log reader (src/bus/edge/lcmlog_file.c): a whole file, whatever it holds. */
#include <check.h>
#include "check_diag.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <kelp/edge/lcmlog.h>

static void put(FILE *f, uint64_t n, const char *ch, size_t dl, char fill)
{
    uint8_t h[KELP_LCMLOG_HDR_LEN];
    kelp_lcmlog_header(n, 5, strlen(ch), dl, h);
    fwrite(h, 1, sizeof h, f);
    fwrite(ch, 1, strlen(ch), f);
    for (size_t i = 0; i < dl; i++) fputc(fill, f);
}

START_TEST(reads_past_empty_channel_and_damage)
{
    char path[] = "/tmp/kelp-lcmlog-XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    FILE *f = fdopen(fd, "wb");
    put(f, 1, "A", 10, 'a');
    put(f, 2, "", 3, 'e');               /* empty channel: an ordinary event */
    fputs("\xed\xa1 damaged bytes", f);   /* damage between events */
    put(f, 3, "BIG", 200000, 'b');        /* larger than the reader's first buffer */
    put(f, 4, "C", 1, 'c');
    uint8_t h[KELP_LCMLOG_HDR_LEN];      /* cut last event */
    kelp_lcmlog_header(5, 5, 1, 100, h);
    fwrite(h, 1, sizeof h, f);
    fclose(f);
    kelp_diag err = {0};
    kelp_lcmlog_reader *r = kelp_lcmlog_open(path, 0, &err);
    ck_assert_ptr_nonnull(r);
    kelp_lcmlog_event ev;
    const char *ch;
    const char *want[] = { "A", "", "BIG", "C" };
    size_t lens[] = { 10, 3, 200000, 1 };
    for (int i = 0; i < 4; i++) {
        ck_assert_int_eq(kelp_lcmlog_next(r, &ev, &ch), 1);
        ck_assert_str_eq(ch, want[i]);
        ck_assert_uint_eq(ev.data_len, lens[i]);
        ck_assert_uint_eq(ev.eventnum, (uint64_t)i + 1);
    }
    ck_assert_uint_eq(ev.data[0], 'c');
    ck_assert_int_eq(kelp_lcmlog_next(r, &ev, &ch), 0);
    kelp_lcmlog_stats st = kelp_lcmlog_get_stats(r);
    ck_assert_uint_eq(st.events, 4);
    ck_assert_uint_eq(st.damaged, 1);
    ck_assert(st.truncated);
    ck_assert_uint_eq(st.skipped_bytes, 16 + KELP_LCMLOG_HDR_LEN);
    kelp_lcmlog_close(r);
    unlink(path);
    kelp_diag_clear(&err);
    ck_assert_ptr_null(kelp_lcmlog_open("/nonexistent/x.lcmlog", 0, &err));
    ck_assert_int_eq(err.code, KELP_ERR_IO);
    ck_diag_has(&err, "cannot open");
}
END_TEST

Suite *kelp_lcmlog_file_suite(void)
{
    Suite *s = suite_create("lcmlog_file");
    TCase *tc = tcase_create("edge");
    tcase_add_test(tc, reads_past_empty_channel_and_damage);
    suite_add_tcase(s, tc);
    return s;
}
