/* Postings from an .alog or an LCM log (src/bus/edge/alog_file.c). */
#include <check.h>
#include <stdlib.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <kelp/bus.h>
#include <kelp/edge/alog.h>
#include <kelp/lcmlog.h>

static void temp(char *path, const char *text, size_t len)
{
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    FILE *f = fdopen(fd, "wb");
    ck_assert_uint_eq(fwrite(text, 1, len, f), len);
    fclose(f);
}

START_TEST(alog_postings_with_banner_marks_and_communities)
{
    static char text[8192];
    size_t n = (size_t)snprintf(text, sizeof text,
                                "%%%%%%%%\n%%%% LOGSTART        1000.5\n%%%% DATATYPE MARKING ON\n%%%% COMMUNITY       alpha\n"
                                "%%%%%%%%\n"
                                "0.50000   NAV_X   uSimMarine   D:-99.37100   \n"
                                "1.25000   NOTE    kelp-poke@bravo   S:12 \n"
                                "not a line\n"
                                "2.00000   LONG    src   S:");
    memset(text + n, 'x', 5000); /* longer than a value may be: skipped */
    n += 5000;
    n += (size_t)snprintf(text + n, sizeof text - n, " \n3.00000   LAST    src   S:two  words \n");
    char path[] = "/tmp/kelp-alog-XXXXXX";
    temp(path, text, n);
    kelp_diag err = {0};
    kelp_alog_postlog *p = kelp_alog_postlog_open(path, "dflt", &err);
    ck_assert_ptr_nonnull(p);
    ck_assert(kelp_alog_postlog_is_alog(p));
    kelp_post e;
    ck_assert_int_eq(kelp_alog_postlog_next(p, &e), 1);
    ck_assert_double_eq(kelp_alog_postlog_start(p), 1000.5);
    ck_assert_str_eq(e.var, "NAV_X");
    ck_assert_str_eq(e.community, "alpha");
    ck_assert(!e.is_string && e.dval == -99.371 && e.time == 1001.0);
    ck_assert_int_eq(kelp_alog_postlog_next(p, &e), 1);
    ck_assert_str_eq(e.src, "kelp-poke");
    ck_assert_str_eq(e.community, "bravo");
    ck_assert(e.is_string);
    ck_assert_str_eq(e.sval, "12");
    ck_assert_int_eq(kelp_alog_postlog_next(p, &e), 1);
    ck_assert_str_eq(e.var, "LAST");
    ck_assert_str_eq(e.sval, "two  words");
    ck_assert_int_eq(kelp_alog_postlog_next(p, &e), 0);
    kelp_alog_postlog_stats st = kelp_alog_postlog_get_stats(p);
    ck_assert_uint_eq(st.posts, 3);
    ck_assert_uint_eq(st.skipped, 2); /* the bad line and the long one */
    kelp_alog_postlog_close(p);
    unlink(path);
}
END_TEST

START_TEST(lcm_postings_skip_sync_and_binary)
{
    static uint8_t file[16384];
    size_t n = 0;
    static kelp_var v;
    const struct { const char *chan, *name; kelp_var_kind kind; } ev[] = {
        { "X", "X", KELP_VAR_DOUBLE }, { "REPLY_CH", "Y", KELP_VAR_STRING }, /* a sync reply: not a write */
        { "B", "B", KELP_VAR_BINARY },  { "S", "S", KELP_VAR_STRING } };
    for (int i = 0; i < 4; i++) {
        memset(&v, 0, sizeof v);
        v.time = 50 + i;
        snprintf(v.name, sizeof v.name, "%s", ev[i].name);
        snprintf(v.source, sizeof v.source, "app");
        snprintf(v.community, sizeof v.community, "alpha");
        v.kind = ev[i].kind;
        v.dval = 2.5;
        v.slen = 3;
        memcpy(v.sval, "abc", 4);
        uint8_t buf[512];
        size_t len;
        ck_assert_int_eq(kelp_var_encode(&v, buf, sizeof buf, &len), 0);
        size_t cl = strlen(ev[i].chan);
        kelp_lcmlog_header((uint64_t)i, (int64_t)(50 + i) * 1000000, cl, len, file + n);
        n += KELP_LCMLOG_HDR_LEN;
        memcpy(file + n, ev[i].chan, cl), n += cl;
        memcpy(file + n, buf, len), n += len;
    }
    char path[] = "/tmp/kelp-alog-lcm-XXXXXX";
    temp(path, (const char *)file, n);
    kelp_diag err = {0};
    kelp_alog_postlog *p = kelp_alog_postlog_open(path, NULL, &err);
    ck_assert_ptr_nonnull(p);
    ck_assert(!kelp_alog_postlog_is_alog(p));
    ck_assert(isnan(kelp_alog_postlog_start(p)));
    kelp_post e;
    ck_assert_int_eq(kelp_alog_postlog_next(p, &e), 1);
    ck_assert_str_eq(e.var, "X");
    ck_assert(!e.is_string && e.dval == 2.5 && e.time == 50 && e.log_us == 50000000);
    ck_assert_double_eq(kelp_alog_postlog_start(p), 50);
    ck_assert_int_eq(kelp_alog_postlog_next(p, &e), 1);
    ck_assert_str_eq(e.var, "S");
    ck_assert_str_eq(e.sval, "abc");
    ck_assert_str_eq(e.community, "alpha");
    ck_assert_int_eq(kelp_alog_postlog_next(p, &e), 0);
    ck_assert_uint_eq(kelp_alog_postlog_get_stats(p).skipped, 2);
    kelp_alog_postlog_close(p);
    unlink(path);
}
END_TEST

Suite *kelp_alog_file_suite(void)
{
    Suite *s = suite_create("alog_file");
    TCase *tc = tcase_create("edge");
    tcase_add_test(tc, alog_postings_with_banner_marks_and_communities);
    tcase_add_test(tc, lcm_postings_skip_sync_and_binary);
    suite_add_tcase(s, tc);
    return s;
}
