/* kelp-moos2sql's core (src/field/moos2sql.c): classification, configuration, fleet, KML. */
#include <check.h>
#include <math.h>
#include <string.h>
#include <kelp/moos2sql.h>

static int classify(const kelp_moos2sql_cfg *c, const char *var, const char *val, kelp_moos2sql_record *r, kelp_diag *why)
{
    return kelp_moos2sql_classify(c, var, "shoreside", 1000.5, true, val, strlen(val), 0, r, why);
}

START_TEST(m2s_status_from_node_report)
{
    kelp_moos2sql_cfg c;
    kelp_moos2sql_cfg_default(&c);
    kelp_moos2sql_record r;
    kelp_diag why = { 0 };
    ck_assert_int_eq(classify(&c, "NODE_REPORT", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,LAT=43.824981,"
                                                 "LON=-70.329755,SPD=2.00,HDG=118.85,DEPTH=4.63,LENGTH=3.8,MODE=LOITERING",
                              &r, &why),
                     1);
    ck_assert_int_eq(r.kind, KELP_M2S_STATUS);
    ck_assert_str_eq(r.name, "alpha");
    ck_assert_str_eq(r.community, "shoreside");
    ck_assert_str_eq(r.nr.mode, "LOITERING");
    ck_assert_double_eq_tol(r.nr.lat, 43.824981, 1e-9);
    ck_assert_double_eq(r.time, 1000.5);
    ck_assert_uint_eq(r.value_len, strlen(r.value));
    ck_assert_int_eq(classify(&c, "NODE_REPORT_LOCAL", "NAME=bravo,X=1,Y=2", &r, &why), 1);
    ck_assert_str_eq(r.name, "bravo");
    /* no position: rejected with a reason; a number: rejected; not ours: 0 */
    ck_assert_int_lt(classify(&c, "NODE_REPORT", "NAME=alpha,SPD=2", &r, &why), 0);
    ck_assert_int_ne(why.code, 0);
    ck_assert_int_lt(kelp_moos2sql_classify(&c, "NODE_REPORT", "s", 1, false, NULL, 0, 3, &r, &why), 0);
    ck_assert_int_eq(classify(&c, "NAV_X", "3", &r, &why), 0);
    /* the text must end at its length (as a kelp_var's does) */
    ck_assert_int_lt(kelp_moos2sql_classify(&c, "NODE_REPORT", "s", 1, true, "NAME=a,X=1,Y=2", 6, 0, &r, &why), 0);
}
END_TEST

START_TEST(m2s_contact_counts)
{
    kelp_moos2sql_cfg c;
    kelp_moos2sql_cfg_default(&c);
    kelp_moos2sql_record r;
    ck_assert_int_eq(classify(&c, "CONTACTS_LIST", "delta,gus,charlie,henry", &r, NULL), 1);
    ck_assert_int_eq(r.kind, KELP_M2S_CONTACT);
    ck_assert_str_eq(r.name, "shoreside"); /* the ownship: the community that posted it */
    ck_assert_int_eq(r.count, 4);
    ck_assert_int_eq(classify(&c, "CONTACTS_RECAP", "vname=ben,range=82.72,age=0.83 # vname=cal,range=73.42,age=0.66", &r, NULL), 1);
    ck_assert_int_eq(r.count, 2);
    ck_assert_int_eq(classify(&c, "CONTACTS_ALERTED", "(delta,avd)(charlie,avd)", &r, NULL), 1);
    ck_assert_int_eq(r.count, 2);
    ck_assert_int_eq(classify(&c, "CONTACTS_RETIRED", "", &r, NULL), 1);
    ck_assert_int_eq(r.count, 0);
    ck_assert_int_eq(kelp_moos2sql_classify(&c, "CONTACTS_COUNT", "alpha", 5, false, NULL, 0, 3, &r, NULL), 1);
    ck_assert(r.is_number);
    ck_assert_int_eq(r.count, 3);
    ck_assert_int_eq(classify(&c, "CONTACT_RANGES", "48.32,56.3,112.08", &r, NULL), 1);
    ck_assert_int_eq(r.count, 3);
}
END_TEST

START_TEST(m2s_track_from_status_message)
{
    kelp_moos2sql_cfg c;
    kelp_moos2sql_cfg_default(&c);
    kelp_moos2sql_record r;
    kelp_diag why = { 0 };
    ck_assert_int_eq(classify(&c, "STATUS_REPORT", "dest=1,name=bravo,nav_x=15.0,nav_y=10.0,heading=0,speed=0.5,behavior=", &r, &why), 1);
    ck_assert_int_eq(r.kind, KELP_M2S_TRACK);
    ck_assert_str_eq(r.name, "bravo");
    ck_assert_uint_eq(r.nr.fields, KELP_NR_X | KELP_NR_Y | KELP_NR_HDG | KELP_NR_SPD);
    ck_assert_double_eq(r.nr.x, 15);
    ck_assert_double_eq(r.nr.spd, 0.5);
    /* the SIMPLE_STATUS example: Node names the vehicle; no name at all is "" */
    ck_assert_int_eq(classify(&c, "STATUS_REPORT_IN", "Timestamp=1,Node=2,MessageType=LAMSS_STATUS,nav_x=123,nav_y=321,"
                                                      "Speed=1.2,Heading=45.00,Depth=111.0", &r, &why), 1);
    ck_assert_str_eq(r.name, "2");
    ck_assert_double_eq(r.nr.depth, 111);
    ck_assert_int_eq(classify(&c, "STATUS_SUMMARY", "nav_x=1.5,nav_y=2,health=good", &r, &why), 1);
    ck_assert_str_eq(r.name, "");
    ck_assert_int_lt(classify(&c, "STATUS_SUMMARY", "garbage", &r, &why), 0);
}
END_TEST

START_TEST(m2s_config)
{
    kelp_moos2sql_cfg c;
    kelp_moos2sql_cfg_default(&c);
    kelp_diag why = { 0 };
    ck_assert_str_eq(c.database, "moos2sql.db");
    ck_assert_int_eq(kelp_moos2sql_config(&c, "track_var", " MY_STATUS , NODE_REPORT_LOCAL", &why), 1);
    ck_assert_int_eq(kelp_moos2sql_kind_of(&c, "MY_STATUS"), KELP_M2S_TRACK);
    ck_assert_int_eq(kelp_moos2sql_kind_of(&c, "NODE_REPORT_LOCAL"), KELP_M2S_TRACK); /* moved: the last word wins */
    ck_assert_int_eq(kelp_moos2sql_kind_of(&c, "NODE_REPORT"), KELP_M2S_STATUS);
    ck_assert_int_eq(kelp_moos2sql_config(&c, "COMMIT_PERIOD", "0.6", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_moos2sql_config(&c, "COMMIT_PERIOD", "0.5", &why), 1);
    ck_assert_int_eq(kelp_moos2sql_config(&c, "KML_PERIOD", "0", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_moos2sql_config(&c, "DATABASE", "", &why), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_moos2sql_config(&c, "KML_FILE", "", &why), 1);
    ck_assert_str_eq(c.kml, "");
    ck_assert_int_eq(kelp_moos2sql_config(&c, "FOO", "1", &why), 0);
    ck_assert_uint_ge(kelp_moos2sql_nmigrations, 2);
    ck_assert_ptr_nonnull(strstr(kelp_moos2sql_migrations[0], "CREATE INDEX status_name_time ON status (name, time)"));
}
END_TEST

START_TEST(m2s_fleet_kml)
{
    kelp_moos2sql_cfg c;
    kelp_moos2sql_cfg_default(&c);
    static kelp_moos2sql_fleet f;
    kelp_moos2sql_fleet_init(&f);
    kelp_moos2sql_record r;
    /* x/y only without a datum: no position */
    ck_assert_int_eq(classify(&c, "NODE_REPORT", "NAME=zed,X=10,Y=0,TIME=1795715787.32", &r, NULL), 1);
    ck_assert_int_eq(kelp_moos2sql_fleet_update(&f, &c, &r), 0);
    ck_assert_int_eq(kelp_geo_init(&c.datum, 43.8253, -70.3304), 0);
    c.have_datum = true;
    ck_assert_int_eq(kelp_moos2sql_fleet_update(&f, &c, &r), 1);
    ck_assert_int_eq(classify(&c, "NODE_REPORT", "NAME=a<b>&,LAT=43.5,LON=-70.25,HDG=90,MODE=X&Y,TIME=0", &r, NULL), 1);
    ck_assert_int_eq(kelp_moos2sql_fleet_update(&f, &c, &r), 1);
    ck_assert_int_eq(classify(&c, "NODE_REPORT", "NAME=zed,X=0,Y=0,TIME=1795715790", &r, NULL), 1);
    ck_assert_int_eq(kelp_moos2sql_fleet_update(&f, &c, &r), 1);
    ck_assert_uint_eq(f.n, 2);
    ck_assert(f.changed);
    static char buf[8192];
    int n = kelp_moos2sql_kml(&f, "fleet & co", buf, sizeof buf);
    ck_assert_int_gt(n, 0);
    ck_assert_uint_eq((size_t)n, strlen(buf));
    ck_assert(!f.changed);
    ck_assert_ptr_nonnull(strstr(buf, "<name>fleet &amp; co</name>"));
    ck_assert_ptr_nonnull(strstr(buf, "<name>a&lt;b&gt;&amp;</name>"));
    ck_assert_ptr_nonnull(strstr(buf, "mode X&amp;Y;"));
    ck_assert_ptr_nonnull(strstr(buf, "<heading>90.00</heading>"));
    ck_assert_ptr_nonnull(strstr(buf, "<Point><coordinates>-70.2500000,43.5000000,0</coordinates></Point>"));
    ck_assert_ptr_nonnull(strstr(buf, "<when>1970-01-01T00:00:00Z</when>"));
    ck_assert_ptr_nonnull(strstr(buf, "<when>2026-11-26T17:56:30Z</when>")); /* zed's latest */
    ck_assert_ptr_nonnull(strstr(buf, "<Point><coordinates>-70.3304000,43.8253000,0</coordinates>"));
    /* name order: "a<b>..." before "zed" */
    ck_assert(strstr(buf, "a&lt;b") < strstr(buf, "<name>zed"));
    ck_assert_int_eq(kelp_moos2sql_kml(&f, NULL, buf, 200), KELP_ERR_NOSPACE);
    n = kelp_moos2sql_kml_link(NULL, "dir/f&.kml", 5, buf, sizeof buf);
    ck_assert_int_gt(n, 0);
    ck_assert_ptr_nonnull(strstr(buf, "<href>dir/f&amp;.kml</href>"));
    ck_assert_ptr_nonnull(strstr(buf, "<refreshInterval>5</refreshInterval>"));
    ck_assert_ptr_nonnull(strstr(buf, "<refreshMode>onInterval</refreshMode>"));
}
END_TEST

START_TEST(m2s_escape_drops_controls)
{
    char buf[16];
    size_t len = 0;
    ck_assert_int_eq(kelp_moos2sql_xml_escape(buf, sizeof buf, &len, "a\001b\tc", 5), 0);
    ck_assert_str_eq(buf, "ab\tc");
    len = 0;
    ck_assert_int_eq(kelp_moos2sql_xml_escape(buf, sizeof buf, &len, "'\"", 2), 0);
    ck_assert_str_eq(buf, "&apos;&quot;");
    len = 0;
    ck_assert_int_eq(kelp_moos2sql_xml_escape(buf, 5, &len, "&&", 2), KELP_ERR_NOSPACE);
}
END_TEST

Suite *kelp_moos2sql_suite(void)
{
    Suite *s = suite_create("moos2sql");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, m2s_status_from_node_report);
    tcase_add_test(tc, m2s_contact_counts);
    tcase_add_test(tc, m2s_track_from_status_message);
    tcase_add_test(tc, m2s_config);
    tcase_add_test(tc, m2s_fleet_kml);
    tcase_add_test(tc, m2s_escape_drops_controls);
    suite_add_tcase(s, tc);
    return s;
}
