/* uFldScope's state machine (src/field/scope.c): ufield.md 7.5 and the rules around it. */
#include <check.h>
#include "check_diag.h"
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>

static kelp_field_ufs s;
static char out[8192];

/* Listing 16 */
static const char *const listing16[][2] = {
    { "SCOPE", "var=NODE_REPORT,key=vname,fld=TIME,alias=Time" },
    { "SCOPE", "var=NODE_REPORT,key=vname,fld=MODE" },
    { "SCOPE", "var=SPEED_REPORT,key=vname,fld=avg_speed,alias=speed" },
    { "SCOPE", "var=ODOMETRY_REPORT,key=vname,fld=trip_dist" },
    { "SCOPE", "var=ODOMETRY_REPORT,key=vname,fld=total_dist" },
    { "LAYOUT", "trip_dist, total_dist" },
    { "LAYOUT", "MODE, speed, Time" },
};

static void setup(const char *const (*lines)[2], int n)
{
    kelp_field_ufs_cfg c;
    memset(&c, 0, sizeof c);
    kelp_diag why = { 0 };
    for (int i = 0; i < n; i++) ck_assert_int_eq(kelp_field_ufs_config(&c, lines[i][0], lines[i][1], &why), 1);
    kelp_field_ufs_init(&s, &c);
}

static void listing(void)
{
    setup(listing16, 7);
}

static const char *render(void)
{
    size_t n = kelp_field_ufs_render(&s, out, sizeof out);
    ck_assert_uint_eq(n, strlen(out));
    return out;
}

/* the first line of the render */
static const char *line(int k)
{
    static char l[1024];
    const char *p = render();
    for (int i = 0; i < k && p; i++) {
        p = strchr(p, '\n');
        if (p) p++;
    }
    ck_assert_ptr_nonnull(p);
    size_t n = strcspn(p, "\n");
    memcpy(l, p, n);
    l[n] = 0;
    return l;
}

/* 7.5.1: key NAME, field MODE */
START_TEST(ufs_node_report_mode)
{
    static const char *const cfg[][2] = { { "SCOPE", "var=NODE_REPORT,key=NAME,fld=MODE" } };
    setup(cfg, 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "NODE_REPORT", true,
                                         "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,SPD=2.00,MODE=LOITERING"),
                     1);
    ck_assert_str_eq(line(0), "VName  MODE       STREAMING(A)");
    ck_assert_str_eq(line(1), "=====  =========  (1)");
    ck_assert_str_eq(line(2), "alpha  LOITERING");
}
END_TEST

/* 7.5.2: alias is the header. Keys and fields match exactly, as 24.8's token parse (the
 * seed let vname and NAME stand for each other): a report without the key is the row "" */
START_TEST(ufs_alias_and_vname)
{
    static const char *const cfg[][2] = { { "SCOPE", "var = SPEED_REPORT, key = vname, fld = avg_speed, alias = speed" } };
    setup(cfg, 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "SPEED_REPORT", true, "vname=alpha,avg_speed=2.21"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "SPEED_REPORT", true, "NAME=bravo, AVG_SPEED = 1.5"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "SPEED_REPORT", true, " vname = charlie , avg_speed = 0.5 "), 1);
    ck_assert_str_eq(line(0), "VName    speed  STREAMING(A)");
    ck_assert_str_eq(line(2), "");             /* "" (bravo's report: no vname, no avg_speed) */
    ck_assert_str_eq(line(3), "alpha    2.21");
    ck_assert_str_eq(line(4), "charlie  0.5"); /* blanks around keys and values are trimmed */
}
END_TEST

/* the APPCAST carries 24.8's table (ACTable: VName and the headers, dashes, a row per vehicle) */
START_TEST(ufs_appcast_table)
{
    static const char *const cfg[][2] = { { "SCOPE", "var=NODE_REPORT,key=NAME,fld=MODE" },
                                          { "SCOPE", "var=SPEED_REPORT,key=vname,fld=avg_spd,alias=speed" } };
    setup(cfg, 2);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "NODE_REPORT", true, "NAME=bravo,MODE=PARK"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "SPEED_REPORT", true, "vname=alpha,avg_spd=2.21"), 1);
    char buf[512];
    ck_assert_uint_gt(kelp_field_ufs_table(&s, buf, sizeof buf), 0);
    ck_assert_str_eq(buf, "VName  MODE  speed\n"
                          "-----  ----  -----\n"
                          "alpha        2.21\n"
                          "bravo  PARK\n");
}
END_TEST

/* 7.5.3: a field no message carries stays empty; a message without the key is the row "" */
START_TEST(ufs_missing_field_and_key)
{
    static const char *const cfg[][2] = { { "SCOPE", "var=R,key=vname,fld=a" }, { "SCOPE", "var=R,key=vname,fld=battery" } };
    setup(cfg, 2);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, "vname=alpha,a=1"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, "who=bravo,a=2"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, ""), 0); /* an empty posting is not kept */
    ck_assert_uint_eq(s.nrow, 2);
    ck_assert_str_eq(s.row[0].name, "");
    ck_assert_str_eq(s.row[0].cell[0], "2");
    ck_assert_str_eq(s.row[1].cell[0], "1");
    ck_assert_str_eq(s.row[1].cell[1], "");
    ck_assert_str_eq(line(3), "alpha  1");
    /* a newer report without the field empties its cell (the latest report is what shows) */
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, "vname=alpha,b=3"), 1);
    ck_assert_str_eq(s.row[1].cell[0], "");
}
END_TEST

/* 7.5.4: Listing 16: three subscriptions, view (A) with five columns in SCOPE order */
START_TEST(ufs_listing16_view_all)
{
    listing();
    ck_assert_str_eq(kelp_field_ufs_subscription(&s, 0), "NODE_REPORT");
    ck_assert_str_eq(kelp_field_ufs_subscription(&s, 1), "SPEED_REPORT");
    ck_assert_str_eq(kelp_field_ufs_subscription(&s, 2), "ODOMETRY_REPORT");
    ck_assert_ptr_null(kelp_field_ufs_subscription(&s, 3));
    ck_assert_uint_eq(s.unmatched, 0);
    /* the listing keys NODE_REPORT by vname, which node reports carry as NAME: 24.8 shows
     * their fields in the row "" (the latest report) */
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "NODE_REPORT", true, "NAME=gilda,TIME=2651922526.73,MODE=MODE@ACTIVE:LOITERING"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "SPEED_REPORT", true, "vname=gilda,avg_speed=1.06"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "ODOMETRY_REPORT", true, "vname=gilda,trip_dist=517.1,total_dist=517.1"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "NODE_REPORT", true, "NAME=henry,TIME=2651922526.54,MODE=MODE@ACTIVE:LOITERING"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "NODE_REPORT", true, "vname=gilda,TIME=2651922527.5,MODE=PARK"), 1);
    ck_assert_str_eq(line(0), "VName  Time           MODE                   speed  trip_dist  total_dist  STREAMING(A)");
    ck_assert_str_eq(line(2), "       2651922526.54  MODE@ACTIVE:LOITERING");
    ck_assert_str_eq(line(3), "gilda  2651922527.5   PARK                   1.06   517.1      517.1");
}
END_TEST

/* 7.5.5: l cycles A -> (1) Time MODE speed -> (2) trip_dist total_dist -> A */
START_TEST(ufs_layout_cycle)
{
    listing();
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "ODOMETRY_REPORT", true, "vname=gilda,trip_dist=1081.9,total_dist=1081.9"), 1);
    ck_assert_int_eq(kelp_field_ufs_key(&s, 'L'), 1);
    ck_assert_str_eq(line(0), "VName  Time  MODE  speed  STREAMING(1)");
    ck_assert_int_eq(kelp_field_ufs_key(&s, 'l'), 1);
    ck_assert_str_eq(line(0), "VName  trip_dist  total_dist  STREAMING(2)");
    ck_assert_str_eq(line(2), "gilda  1081.9     1081.9");
    ck_assert_int_eq(kelp_field_ufs_key(&s, 'L'), 1);
    ck_assert_str_eq(line(0), "VName  Time  MODE  speed  trip_dist  total_dist  STREAMING(A)");
    /* the digit 1 does nothing (A30) */
    ck_assert_int_eq(kelp_field_ufs_key(&s, '1'), 0);
    ck_assert_uint_eq(s.layout, 0);
}
END_TEST

/* 7.5.6: a toggles (2) and A */
START_TEST(ufs_a_toggle)
{
    listing();
    ck_assert_int_eq(kelp_field_ufs_key(&s, 'a'), 1);
    ck_assert_uint_eq(s.layout, 1); /* no layout used yet: the first */
    (void)kelp_field_ufs_key(&s, 'a');
    (void)kelp_field_ufs_key(&s, 'l');
    (void)kelp_field_ufs_key(&s, 'l');
    ck_assert_uint_eq(s.layout, 2);
    (void)kelp_field_ufs_key(&s, 'a');
    ck_assert_str_eq(line(0), "VName  Time  MODE  speed  trip_dist  total_dist  STREAMING(A)");
    (void)kelp_field_ufs_key(&s, 'A');
    ck_assert_str_eq(line(0), "VName  trip_dist  total_dist  STREAMING(2)");
}
END_TEST

/* without layouts, l and a stay on A */
START_TEST(ufs_no_layouts)
{
    static const char *const cfg[][2] = { { "SCOPE", "var=R,key=vname,fld=a" } };
    setup(cfg, 1);
    (void)kelp_field_ufs_key(&s, 'l');
    ck_assert_uint_eq(s.layout, 0);
    (void)kelp_field_ufs_key(&s, 'a');
    ck_assert_uint_eq(s.layout, 0);
    ck_assert_str_eq(line(0), "VName  a  STREAMING(A)");
}
END_TEST

/* 7.5.7: p pauses (the counter stops), a further p refreshes once, r streams */
START_TEST(ufs_pause_resume)
{
    listing();
    ck_assert(kelp_field_ufs_due(&s));
    ck_assert_str_eq(line(1), "=====  ====  ====  =====  =========  ==========  (0)");
    ck_assert_int_eq(kelp_field_ufs_key(&s, 'p'), 1);
    ck_assert(kelp_field_ufs_due(&s)); /* one refresh for the key */
    ck_assert_str_eq(line(0), "VName  Time  MODE  speed  trip_dist  total_dist  PAUSED(A)");
    ck_assert(!kelp_field_ufs_due(&s));
    unsigned long n = s.reports;
    ck_assert_int_eq(kelp_field_ufs_key(&s, ' '), 1);
    ck_assert(kelp_field_ufs_due(&s));
    (void)render();
    ck_assert(!kelp_field_ufs_due(&s));
    ck_assert_uint_eq(s.reports, n + 1);
    ck_assert_int_eq(kelp_field_ufs_key(&s, 'R'), 1);
    ck_assert(kelp_field_ufs_due(&s));
    ck_assert_str_eq(line(0), "VName  Time  MODE  speed  trip_dist  total_dist  STREAMING(A)");
    ck_assert(kelp_field_ufs_due(&s));
    ck_assert_int_eq(kelp_field_ufs_key(&s, 'x'), 0);
}
END_TEST

/* h shows the help; h again pauses on the table */
START_TEST(ufs_help)
{
    listing();
    ck_assert_int_eq(kelp_field_ufs_key(&s, 'h'), 1);
    ck_assert_uint_eq(s.mode, KELP_UFS_HELP);
    ck_assert_ptr_nonnull(strstr(render(), "l / L    next layout"));
    ck_assert_ptr_null(strstr(out, "VName"));
    ck_assert(!kelp_field_ufs_due(&s)); /* help is not refreshed every iteration */
    (void)kelp_field_ufs_key(&s, 'H');
    ck_assert_uint_eq(s.mode, KELP_UFS_PAUSED);
    ck_assert_str_eq(line(0), "VName  Time  MODE  speed  trip_dist  total_dist  PAUSED(A)");
}
END_TEST

/* 7.5.8: rows in name order whatever the arrival order */
START_TEST(ufs_rows_sorted)
{
    static const char *const cfg[][2] = { { "SCOPE", "var=R,key=vname,fld=m" } };
    setup(cfg, 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, "vname=charlie,m=RETURNING"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, "vname=alpha,m=LOITERING"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, "vname=Bravo,m=PARK"), 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, "vname=ALPHA,m=SURVEY"), 1); /* another name */
    ck_assert_uint_eq(s.nrow, 4);
    ck_assert_str_eq(line(2), "ALPHA    SURVEY"); /* byte order, as 24.8's set of names */
    ck_assert_str_eq(line(3), "Bravo    PARK");
    ck_assert_str_eq(line(4), "alpha    LOITERING");
    ck_assert_str_eq(line(5), "charlie  RETURNING");
}
END_TEST

/* a variable's key is its last SCOPE line's, as 24.8's: the earlier line without one takes it,
 * and a variable whose last line has none is not shown */
START_TEST(ufs_default_key)
{
    static const char *const cfg[][2] = { { "SCOPE", "var=NODE_REPORT,fld=TIME,alias=Time" },
                                          { "SCOPE", "var=NODE_REPORT,key=vname,fld=MODE" },
                                          { "SCOPE", "var=OTHER,fld=x" },
                                          { "SCOPE", "var=THIRD,key=id,fld=y" },
                                          { "SCOPE", "var=THIRD,fld=z" } };
    setup(cfg, 5);
    ck_assert_str_eq(s.cfg.elem[0].key, "vname");
    ck_assert_str_eq(s.cfg.elem[2].key, "");
    ck_assert_str_eq(s.cfg.elem[3].key, "");
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "OTHER", true, "vname=a,x=5"), 0);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "THIRD", true, "id=a,y=5"), 0);
    ck_assert_uint_eq(s.nrow, 0);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "NODE_REPORT", true, "vname=a,TIME=3,MODE=M"), 1);
    ck_assert_str_eq(s.row[0].cell[0], "3");
    ck_assert_str_eq(s.row[0].cell[1], "M");
}
END_TEST

/* bad SCOPE and LAYOUT lines are refused with a reason; layout names matching nothing counted */
START_TEST(ufs_config_errors)
{
    kelp_field_ufs_cfg c;
    memset(&c, 0, sizeof c);
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_ufs_config(&c, "SCOPE", "var=A,key=vname", &why), KELP_ERR_PARSE);
    ck_diag_msg(&why, "var and fld are required");
    ck_assert_int_eq(kelp_field_ufs_config(&c, "SCOPE", "var=A,fld=x,colour=red", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_ufs_config(&c, "SCOPE", "var=A,fld", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_ufs_config(&c, "SCOPE", "var=A,fld=x,xthresh=-2", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_ufs_config(&c, "SCOPE", "var=A,fld=this_field_name_is_far_too_long_to_keep", &why),
                     KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_field_ufs_config(&c, "SCOPE", "var=A,fld=x,color=red,xcolor=blue,xthresh=3", &why), 1);
    ck_assert_str_eq(c.elem[0].xcolor, "blue");
    ck_assert_double_eq(c.elem[0].xthresh, 3);
    ck_assert_int_eq(kelp_field_ufs_config(&c, "VERBOSE", "true", &why), 0);
    ck_assert_int_eq(kelp_field_ufs_config(&c, "LAYOUT", "x, nosuch", &why), 1);
    for (int i = 1; i < KELP_UFS_MAX_ELEMS; i++) ck_assert_int_eq(kelp_field_ufs_config(&c, "SCOPE", "var=B,fld=y", &why), 1);
    ck_assert_int_eq(kelp_field_ufs_config(&c, "SCOPE", "var=B,fld=y", &why), KELP_ERR_NOSPACE);
    kelp_field_ufs_init(&s, &c);
    ck_assert_uint_eq(s.unmatched, 1);
    ck_assert_str_eq(s.first_unmatched, "nosuch");
    ck_assert_uint_eq(s.layout_mask[0], 1u);
}
END_TEST

/* numbers and malformed reports: counted, what can be read is used */
START_TEST(ufs_bad_mail)
{
    static const char *const cfg[][2] = { { "SCOPE", "var=R,key=vname,fld=m" } };
    setup(cfg, 1);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", false, NULL), KELP_ERR_PARSE);
    /* an item that is not one key=value pair ends 24.8's search: m is not found after it */
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, "vname=alpha,junk,m=7"), KELP_ERR_PARSE);
    ck_assert_uint_eq(s.bad_mail, 2);
    ck_assert_str_eq(s.row[0].cell[0], "");
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, "vname=alpha,m=7,junk"), 1);
    ck_assert_str_eq(s.row[0].cell[0], "7");
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, "vname=alpha,q=a=b,m=8"), KELP_ERR_PARSE);
    ck_assert_str_eq(s.row[0].cell[0], "");
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "NOT_SCOPED", true, "vname=alpha,m=1"), 0);
    ck_assert_uint_eq(s.mail, 4);
    /* a long value is cut to the cell */
    char big[200];
    snprintf(big, sizeof big, "vname=alpha,m=%0120d", 5);
    ck_assert_int_eq(kelp_field_ufs_mail(&s, "R", true, big), 1);
    ck_assert_uint_eq(strlen(s.row[0].cell[0]), KELP_UFS_CELL_LEN - 1);
}
END_TEST

/* more vehicles than rows: counted and said */
START_TEST(ufs_too_many_rows)
{
    static const char *const cfg[][2] = { { "SCOPE", "var=R,key=vname,fld=m" } };
    setup(cfg, 1);
    char m[64];
    for (int i = 0; i < KELP_UFS_MAX_ROWS + 2; i++) {
        snprintf(m, sizeof m, "vname=v%02d,m=%d", i, i);
        KELP_IGNORE(kelp_field_ufs_mail(&s, "R", true, m)); /* rows past the table are dropped: nrow is checked */
    }
    ck_assert_uint_eq(s.nrow, KELP_UFS_MAX_ROWS);
    ck_assert_uint_eq(s.dropped_rows, 2);
    ck_assert_ptr_nonnull(strstr(render(), "(2 reports of vehicles beyond 32 not shown)"));
    char small[16];
    size_t n = kelp_field_ufs_render(&s, small, sizeof small);
    ck_assert_uint_eq(n, strlen(small));
    ck_assert_uint_eq(n, sizeof small - 1);
}
END_TEST

Suite *kelp_field_scope_suite(void);
Suite *kelp_field_scope_suite(void)
{
    Suite *su = suite_create("field_scope");
    TCase *tc = tcase_create("ufs");
    tcase_add_test(tc, ufs_node_report_mode);
    tcase_add_test(tc, ufs_alias_and_vname);
    tcase_add_test(tc, ufs_appcast_table);
    tcase_add_test(tc, ufs_missing_field_and_key);
    tcase_add_test(tc, ufs_listing16_view_all);
    tcase_add_test(tc, ufs_layout_cycle);
    tcase_add_test(tc, ufs_a_toggle);
    tcase_add_test(tc, ufs_no_layouts);
    tcase_add_test(tc, ufs_pause_resume);
    tcase_add_test(tc, ufs_help);
    tcase_add_test(tc, ufs_rows_sorted);
    tcase_add_test(tc, ufs_default_key);
    tcase_add_test(tc, ufs_config_errors);
    tcase_add_test(tc, ufs_bad_mail);
    tcase_add_test(tc, ufs_too_many_rows);
    suite_add_tcase(su, tc);
    return su;
}
