/* NMEA reader / parser / writer: real WHOI Micro-Modem sentences (shared/data/real_nmea_examples.md). */
#include <check.h>
#include <string.h>

#include <kelp/nmea.h>

/* every real sentence with a checksum, as printed in the public sources */
static const char *REAL_CS[] = {
    "$CAREV,181807,AUV,2.0.27087*12",
    "$CAREV,181807,COPROC,0.20.0.56*45",
    "$CACFG,SRC,1*33",
    "$CAREV,000052,AUV,0.93.0.09*07",
    "$CAMPA,1,2*5D",
    "$CAMPR,2,1,0.0101*7C",
    "$CAMUA,1,2,1fab*20",
    "$CACST,1,153026.0000,0,4105,30,0318,0193,10,00,00,01,01,2,004,004,3,3,3,1,154,09,08,10,-6,000,0.0,4125000,5000*5B",
    "$CCTXD,2,1,1,*7A",
    "$CCTXD,2,1,1*56",
};

START_TEST(real_sentences_checksums_verify)
{
    kelp_nmea_sentence s;
    for (size_t i = 0; i < sizeof REAL_CS / sizeof REAL_CS[0]; i++) {
        int rc = kelp_nmea_parse(REAL_CS[i], strlen(REAL_CS[i]), &s);
        ck_assert_msg(rc == KELP_OK, "%s -> %d", REAL_CS[i], rc);
        ck_assert(s.had_checksum);
    }
}
END_TEST

START_TEST(fields_of_real_sentences)
{
    kelp_nmea_sentence s;
    ck_assert_int_eq(kelp_nmea_parse("$CAREV,181807,AUV,2.0.27087*12", 30, &s), KELP_OK);
    ck_assert_uint_eq(s.nfields, 4);
    ck_assert_str_eq(s.talker, "CA");
    ck_assert_str_eq(s.id, "REV");
    ck_assert_str_eq(kelp_nmea_field(&s, 0), "$CAREV");
    ck_assert_str_eq(kelp_nmea_field(&s, 1), "181807");
    ck_assert_str_eq(kelp_nmea_field(&s, 2), "AUV");
    ck_assert_str_eq(kelp_nmea_field(&s, 3), "2.0.27087");
    ck_assert_str_eq(kelp_nmea_field(&s, 4), "");

    const char *mpr = "$CAMPR,2,1,0.0101*7C";
    ck_assert_int_eq(kelp_nmea_parse(mpr, strlen(mpr), &s), KELP_OK);
    long v;
    double d;
    ck_assert_int_eq(kelp_nmea_field_long(&s, 1, &v), KELP_OK);
    ck_assert_int_eq(v, 2);
    ck_assert_int_eq(kelp_nmea_field_double(&s, 3, &d), KELP_OK);
    ck_assert_double_eq_tol(d, 0.0101, 1e-12);
    ck_assert_int_eq(kelp_nmea_field_long(&s, 3, &v), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_nmea_field_long(&s, 9, &v), KELP_ERR_NOTFOUND);

    /* empty last field is a field: $CCTXD,2,1,1, has 5 fields, $CCTXD,2,1,1 has 4 */
    ck_assert_int_eq(kelp_nmea_parse("$CCTXD,2,1,1,*7A", 16, &s), KELP_OK);
    ck_assert_uint_eq(s.nfields, 5);
    ck_assert_str_eq(kelp_nmea_field(&s, 4), "");
    ck_assert_int_eq(kelp_nmea_parse("$CCTXD,2,1,1*56", 15, &s), KELP_OK);
    ck_assert_uint_eq(s.nfields, 4);

    /* 29 fields of $CACST */
    ck_assert_int_eq(kelp_nmea_parse(REAL_CS[7], strlen(REAL_CS[7]), &s), KELP_OK);
    ck_assert_uint_eq(s.nfields, 29);
    ck_assert_str_eq(kelp_nmea_field(&s, 24), "-6");
    ck_assert_str_eq(kelp_nmea_field(&s, 28), "5000");
}
END_TEST

START_TEST(sentences_without_checksum_accepted)
{
    kelp_nmea_sentence s;
    const char *a = "$CCMPC,1,2";
    ck_assert_int_eq(kelp_nmea_parse(a, strlen(a), &s), KELP_OK);
    ck_assert(!s.had_checksum);
    ck_assert_uint_eq(s.nfields, 3);
    const char *b = "$CACST,0,223413.0000,0,1440,25,0175,0166,75,01,01,01,03,1,007,006,0,3,3,0,146,03,04,-100,-1,000,-1.2,45,10000,2000";
    ck_assert_int_eq(kelp_nmea_parse(b, strlen(b), &s), KELP_OK);
    ck_assert_uint_eq(s.nfields, 30); /* the Goby 2.0 proto comment's $CACST has one field more */
    ck_assert_str_eq(kelp_nmea_field(&s, 27), "45");
}
END_TEST

START_TEST(bad_checksum_and_malformed_rejected)
{
    kelp_nmea_sentence s;
    ck_assert_int_eq(kelp_nmea_parse("$CAREV,181807,AUV,2.0.27087*13", 30, &s), KELP_ERR_CHECKSUM);
    ck_assert_int_eq(kelp_nmea_parse("$CAREV,181808,AUV,2.0.27087*12", 30, &s), KELP_ERR_CHECKSUM);
    /* lower-case checksum digits are accepted */
    ck_assert_int_eq(kelp_nmea_parse("$CAMPA,1,2*5d", 13, &s), KELP_OK);
    ck_assert_int_eq(kelp_nmea_parse("CAMPA,1,2*5D", 12, &s), KELP_ERR_PARSE);   /* no $ */
    ck_assert_int_eq(kelp_nmea_parse("$CAMP,1,2", 9, &s), KELP_ERR_PARSE);       /* talker length */
    ck_assert_int_eq(kelp_nmea_parse("$CAMPA,1,2*ZZ", 13, &s), KELP_ERR_PARSE);  /* bad hex */
    ck_assert_int_eq(kelp_nmea_parse("   \r\n", 5, &s), KELP_ERR_EMPTY);
    /* whitespace around is trimmed */
    ck_assert_int_eq(kelp_nmea_parse("\n $CACFG,SRC,1*33 \r", 19, &s), KELP_OK);
    ck_assert_str_eq(kelp_nmea_field(&s, 2), "1");
    /* too many fields */
    char many[200] = "$CAXXX";
    for (int i = 0; i < KELP_MAX_NMEA_FIELDS + 2; i++) strcat(many, ",1");
    ck_assert_int_eq(kelp_nmea_parse(many, strlen(many), &s), KELP_ERR_PARSE);
}
END_TEST

START_TEST(writer_matches_goby_rendering)
{
    char buf[64];
    kelp_nmea_writer w;
    size_t len;
    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CCTXD");
    kelp_nmea_writer_long(&w, 2);
    kelp_nmea_writer_long(&w, 1);
    kelp_nmea_writer_long(&w, 1);
    kelp_nmea_writer_str(&w, "");
    ck_assert_int_eq(kelp_nmea_writer_finish(&w, &len), KELP_OK);
    ck_assert_str_eq(buf, "$CCTXD,2,1,1,*7A");
    ck_assert_uint_eq(len, 16);

    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CAREV");
    kelp_nmea_writer_str(&w, "181807");
    kelp_nmea_writer_str(&w, "AUV");
    kelp_nmea_writer_str(&w, "2.0.27087");
    ck_assert_int_eq(kelp_nmea_writer_finish(&w, &len), KELP_OK);
    ck_assert_str_eq(buf, "$CAREV,181807,AUV,2.0.27087*12");

    kelp_nmea_writer_init(&w, buf, sizeof buf, "$CCXXX");
    kelp_nmea_writer_long(&w, -17);
    ck_assert_int_eq(kelp_nmea_writer_finish(&w, &len), KELP_OK);
    ck_assert(strncmp(buf, "$CCXXX,-17*", 11) == 0);

    char small[8];
    kelp_nmea_writer_init(&w, small, sizeof small, "$CCCFG");
    kelp_nmea_writer_str(&w, "SRC,1");
    ck_assert_int_eq(kelp_nmea_writer_finish(&w, &len), KELP_ERR_NOSPACE);

    /* render re-creates the checksum for a sentence read without one */
    kelp_nmea_sentence s;
    ck_assert_int_eq(kelp_nmea_parse("$CCTXD,2,1,1,", 13, &s), KELP_OK);
    ck_assert_int_eq(kelp_nmea_render(&s, buf, sizeof buf, &len), KELP_OK);
    ck_assert_str_eq(buf, "$CCTXD,2,1,1,*7A");
}
END_TEST

START_TEST(reader_is_byte_fed)
{
    kelp_nmea_reader r;
    kelp_nmea_sentence s;
    kelp_nmea_reader_init(&r, 0);
    const char *in = "$CAREV,181807,AUV,2.0.27087*12\r\n$CACFG,SRC,1*33\r\n";
    int got = 0;
    for (size_t i = 0; in[i]; i++) {
        int rc = kelp_nmea_reader_feed_sentence(&r, (uint8_t)in[i], &s);
        if (in[i] != '\r') {
            ck_assert_int_eq(rc, KELP_ERR_PARTIAL);
        } else {
            ck_assert_int_eq(rc, KELP_OK);
            got++;
            if (got == 1) ck_assert_str_eq(s.id, "REV");
            if (got == 2) ck_assert_str_eq(kelp_nmea_field(&s, 1), "SRC");
        }
    }
    ck_assert_int_eq(got, 2);
    ck_assert_uint_eq(r.count.ok, 2);
    ck_assert_uint_eq(r.count.lines, 2);

    /* a corrupted line and a garbage line are counted, the next good one still parses */
    const char *bad = "$CACFG,SRC,2*33\rxx garbage\r$CAMPA,1,2*5D\r";
    int codes[3], k = 0;
    for (size_t i = 0; bad[i]; i++) {
        int rc = kelp_nmea_reader_feed_sentence(&r, (uint8_t)bad[i], &s);
        if (rc != KELP_ERR_PARTIAL) codes[k++] = rc;
    }
    ck_assert_int_eq(k, 3);
    ck_assert_int_eq(codes[0], KELP_ERR_CHECKSUM);
    ck_assert_int_eq(codes[1], KELP_ERR_PARSE);
    ck_assert_int_eq(codes[2], KELP_OK);
    ck_assert_uint_eq(r.count.checksum, 1);
    ck_assert_uint_eq(r.count.parse, 1);
    ck_assert_uint_eq(r.count.ok, 3);
}
END_TEST

START_TEST(reader_overflow_discards_line)
{
    kelp_nmea_reader r;
    kelp_nmea_sentence s;
    kelp_nmea_reader_init(&r, '\n');
    ck_assert_int_eq(r.delim, '\n');
    int rc = 0;
    ck_assert_int_eq(kelp_nmea_reader_feed_sentence(&r, '$', &s), KELP_ERR_PARTIAL);
    for (int i = 0; i < KELP_MAX_NMEA_LINE + 50; i++) {
        rc = kelp_nmea_reader_feed_sentence(&r, 'A', &s);
        ck_assert_int_eq(rc, KELP_ERR_PARTIAL);
    }
    ck_assert_int_eq(kelp_nmea_reader_feed_sentence(&r, '\n', &s), KELP_ERR_NOSPACE);
    ck_assert_uint_eq(r.count.overflow, 1);
    const char *ok = "$CAMPA,1,2*5D\n";
    for (size_t i = 0; ok[i]; i++) rc = kelp_nmea_reader_feed_sentence(&r, (uint8_t)ok[i], &s);
    ck_assert_int_eq(rc, KELP_OK);
    ck_assert_str_eq(s.id, "MPA");
}
END_TEST

Suite *kelp_nmea_suite(void)
{
    Suite *s = suite_create("nmea");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, real_sentences_checksums_verify);
    tcase_add_test(tc, fields_of_real_sentences);
    tcase_add_test(tc, sentences_without_checksum_accepted);
    tcase_add_test(tc, bad_checksum_and_malformed_rejected);
    tcase_add_test(tc, writer_matches_goby_rendering);
    tcase_add_test(tc, reader_is_byte_fed);
    tcase_add_test(tc, reader_overflow_discards_line);
    suite_add_tcase(s, tc);
    return s;
}
