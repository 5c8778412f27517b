/* Node reports (uField seed format) and VIEW_* artifacts (seed 004 / seed 000 strings). */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/nodereport.h>

static const char *SEED_REPORT = "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,LAT=43.824981,"
                                 "LON=-70.329755,SPD=2.00,HDG=118.85,DEPTH=4.63,LENGTH=3.8,MODE=LOITERING";

START_TEST(test_parse_seed)
{
    kelp_nodereport r;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_nodereport_parse(SEED_REPORT, strlen(SEED_REPORT), &r, &why), KELP_OK);
    ck_assert_int_eq(why.code, 0);
    ck_assert_str_eq(r.name, "alpha");
    ck_assert_str_eq(r.type, "UUV");
    ck_assert_str_eq(r.mode, "LOITERING");
    ck_assert(r.time == 1252348077.59 && r.x == 51.71 && r.y == -35.50 && r.lat == 43.824981 && r.lon == -70.329755);
    ck_assert(r.spd == 2.0 && r.hdg == 118.85 && r.depth == 4.63 && r.length == 3.8);
    ck_assert_uint_eq(r.fields, KELP_NR_NAME | KELP_NR_TYPE | KELP_NR_TIME | KELP_NR_X | KELP_NR_Y | KELP_NR_LAT |
                                    KELP_NR_LON | KELP_NR_SPD | KELP_NR_HDG | KELP_NR_DEPTH | KELP_NR_LENGTH |
                                    KELP_NR_MODE);
}
END_TEST

START_TEST(test_format_seed)
{
    /* formatting the parsed seed report gives the seed's string back, byte for byte */
    kelp_nodereport r;
    ck_assert_int_eq(kelp_nodereport_parse(SEED_REPORT, strlen(SEED_REPORT), &r, NULL), KELP_OK);
    char buf[KELP_NODEREPORT_MAX_LEN];
    size_t n = 0;
    ck_assert_int_eq(kelp_nodereport_format(&r, buf, sizeof buf, &n), KELP_OK);
    ck_assert_str_eq(buf, SEED_REPORT);
    ck_assert_uint_eq(n, strlen(SEED_REPORT));
    /* too small: NOSPACE, and an empty string */
    char small[40];
    ck_assert_int_eq(kelp_nodereport_format(&r, small, sizeof small, &n), KELP_ERR_NOSPACE);
    ck_assert_str_eq(small, "");
}
END_TEST

START_TEST(test_format_numbers)
{
    kelp_nodereport r;
    kelp_nodereport_init(&r);
    memcpy(r.name, "bravo", 6);
    r.x = -0.004;
    r.y = 1234.565001;
    r.hdg = 359.996;
    r.length = 4.0;
    r.lat = -33.1234565;
    r.time = 1700000000.004999;
    memcpy(r.allstop, "clear", 6);
    memcpy(r.group, "red", 4);
    r.fields = KELP_NR_NAME | KELP_NR_X | KELP_NR_Y | KELP_NR_HDG | KELP_NR_LENGTH | KELP_NR_LAT | KELP_NR_TIME |
               KELP_NR_ALLSTOP | KELP_NR_GROUP;
    char buf[256];
    ck_assert_int_eq(kelp_nodereport_format(&r, buf, sizeof buf, NULL), KELP_OK);
    ck_assert_str_eq(buf, "NAME=bravo,TIME=1700000000.00,X=0.00,Y=1234.57,LAT=-33.123457,HDG=360.00,LENGTH=4,"
                          "ALLSTOP=clear,GROUP=red");
    /* bad input to the formatter */
    memcpy(r.mode, "A,B", 4);
    r.fields |= KELP_NR_MODE;
    ck_assert_int_eq(kelp_nodereport_format(&r, buf, sizeof buf, NULL), KELP_ERR_ARG);
    r.fields &= ~KELP_NR_MODE;
    r.x = NAN;
    ck_assert_int_eq(kelp_nodereport_format(&r, buf, sizeof buf, NULL), KELP_ERR_ARG);
    r.x = 1e30;
    ck_assert_int_eq(kelp_nodereport_format(&r, buf, sizeof buf, NULL), KELP_ERR_RANGE);
    r.x = 0;
    r.fields &= ~KELP_NR_NAME;
    ck_assert_int_eq(kelp_nodereport_format(&r, buf, sizeof buf, NULL), KELP_ERR_ARG);
}
END_TEST

START_TEST(test_parse_variants)
{
    kelp_nodereport r;
    /* any order, lower-case keys, synonyms, spaces, unknown keys, the quoted whole */
    const char *s = "\"x = 10, y=-2.5,name=charlie ,dep=3,long=-70.1,lat=43.2,Speed=1.5,heading=90,"
                    "ALLSTOP=clear,INDEX=7,YAW=1.2\"";
    ck_assert_int_eq(kelp_nodereport_parse(s, strlen(s), &r, NULL), KELP_OK);
    ck_assert_str_eq(r.name, "charlie");
    ck_assert(r.x == 10 && r.y == -2.5 && r.depth == 3 && r.lon == -70.1 && r.lat == 43.2 && r.spd == 1.5 &&
              r.hdg == 90);
    ck_assert_str_eq(r.allstop, "clear");
    /* repeated key: the first wins */
    s = "NAME=a,X=1,Y=2,X=5";
    ck_assert_int_eq(kelp_nodereport_parse(s, strlen(s), &r, NULL), KELP_OK);
    ck_assert(r.x == 1);
    /* LAT/LON only is a position; complete() fills X/Y from the datum */
    s = "NAME=alpha,LAT=43.824981,LON=-70.329755";
    ck_assert_int_eq(kelp_nodereport_parse(s, strlen(s), &r, NULL), KELP_OK);
    ck_assert(!(r.fields & KELP_NR_X));
    kelp_geo g;
    ck_assert_int_eq(kelp_geo_init(&g, 43.8253, -70.3304), KELP_OK);
    ck_assert_int_eq(kelp_nodereport_complete(&r, &g), KELP_OK);
    ck_assert(r.fields & KELP_NR_X && r.fields & KELP_NR_Y);
    /* UTM as 24.8 (PROJ; the seed's 2012 LAT/LON were the older local grid's) */
    ck_assert_double_eq_tol(r.x, 51.2949, 0.001);
    ck_assert_double_eq_tol(r.y, -36.2638, 0.001);
    /* and LAT/LON from X/Y */
    s = "NAME=alpha,X=51.71,Y=-35.50";
    ck_assert_int_eq(kelp_nodereport_parse(s, strlen(s), &r, NULL), KELP_OK);
    ck_assert_int_eq(kelp_nodereport_complete(&r, &g), KELP_OK);
    /* PROJ; MOOS's inverse stops within 1 m of the UTM point: 1.4 cm here */
    ck_assert_double_eq_tol(r.lat, 43.8249879354, 3e-7);
    ck_assert_double_eq_tol(r.lon, -70.3297499916, 3e-7);
    /* length-bounded: only the first len bytes count */
    s = "NAME=delta,X=1,Y=2,MODE=PARK";
    ck_assert_int_eq(kelp_nodereport_parse(s, strlen(s) - 10, &r, NULL), KELP_OK);
    ck_assert(!(r.fields & KELP_NR_MODE) && r.y == 2);
}
END_TEST

START_TEST(test_parse_errors)
{
    kelp_nodereport r;
    memset(&r, 0x5a, sizeof r);
    kelp_nodereport keep = r;
    kelp_diag why = { 0 };
    const struct {
        const char *s;
        int rc;
        const char *why;
    } bad[] = {
        {"", KELP_ERR_PARSE, "no NAME"},
        {"X=1,Y=2", KELP_ERR_PARSE, "no NAME"},
        {"NAME=,X=1,Y=2", KELP_ERR_PARSE, "no NAME"},
        {"NAME=a,X=1", KELP_ERR_PARSE, "no position (X,Y or LAT,LON)"},
        {"NAME=a,X=1,Y=two", KELP_ERR_PARSE, "bad number"},
        {"NAME=a,X=1,Y=nan", KELP_ERR_PARSE, "bad number"},
        {"NAME=a,X=1,Y=2,junk", KELP_ERR_PARSE, "item without '='"},
        {"NAME=a,=3,X=1,Y=2", KELP_ERR_PARSE, "empty key"},
        {"NAME=a{,X=1,Y=2", KELP_ERR_PARSE, "unbalanced brace or quote"},
        {"NAME=aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa,X=1,Y=2", KELP_ERR_RANGE,
         "text field too long"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        kelp_diag_clear(&why);
        ck_assert_int_eq(kelp_nodereport_parse(bad[i].s, strlen(bad[i].s), &r, &why), bad[i].rc);
        ck_assert_int_ne(why.code, 0);
        ck_diag_msg(&why, bad[i].why);
        ck_assert(memcmp(&r, &keep, sizeof r) == 0); /* output untouched on error */
    }
}
END_TEST

START_TEST(test_round_trip_fields)
{
    kelp_nodereport a, b;
    kelp_nodereport_init(&a);
    memcpy(a.name, "henry", 6);
    memcpy(a.type, "kayak", 6);
    memcpy(a.mode, "MODE@ACTIVE:LOITERING", 22);
    a.time = 12.25;
    a.x = -100.5;
    a.y = 7.75;
    a.spd = 1.25;
    a.hdg = 270.5;
    a.depth = 0;
    a.fields = KELP_NR_NAME | KELP_NR_TYPE | KELP_NR_MODE | KELP_NR_TIME | KELP_NR_X | KELP_NR_Y | KELP_NR_SPD |
               KELP_NR_HDG | KELP_NR_DEPTH;
    char buf[KELP_NODEREPORT_MAX_LEN];
    size_t n;
    ck_assert_int_eq(kelp_nodereport_format(&a, buf, sizeof buf, &n), KELP_OK);
    ck_assert_str_eq(buf, "NAME=henry,TYPE=kayak,TIME=12.25,X=-100.50,Y=7.75,SPD=1.25,HDG=270.50,DEPTH=0.00,"
                          "MODE=MODE@ACTIVE:LOITERING");
    ck_assert_int_eq(kelp_nodereport_parse(buf, n, &b, NULL), KELP_OK);
    ck_assert_uint_eq(a.fields, b.fields);
    ck_assert_str_eq(b.mode, a.mode);
    ck_assert(b.x == a.x && b.y == a.y && b.time == a.time && b.hdg == a.hdg);
}
END_TEST

/* ------------------------------------------------------------------ VIEW_* */

static kelp_view V;

static int vparse(kelp_view_kind k, const char *s, kelp_diag *why)
{
    return kelp_nodereport_view_parse(k, s, strlen(s), &V, why);
}

/* MOOS-IvP 24.8's node record (what uFldNodeComms relays): the readers take it (COG, DEP,
 * 8-decimal LAT/LON), and it writes back the same (a row of the recorded 24.8 run a3) */
START_TEST(test_record_248)
{
    const char *rec = "NAME=abe,X=0,Y=0,SPD=0,HDG=0,COG=0,DEP=0,LAT=42.358456,LON=-71.087589,TYPE=kayak,GROUP=g1,"
                      "TIME=1795284022.41,LENGTH=4";
    kelp_nodereport r;
    char buf[512];
    size_t n = 0;
    ck_assert_int_eq(kelp_nodereport_parse(rec, strlen(rec), &r, NULL), KELP_OK);
    ck_assert(r.fields & KELP_NR_COG);
    ck_assert(r.fields & KELP_NR_DEPTH);
    ck_assert_int_eq(kelp_nodereport_format_record(&r, buf, sizeof buf, &n), KELP_OK);
    ck_assert_str_eq(buf, rec);
    ck_assert_uint_eq(n, strlen(rec));
    const char *b = "NAME=ben,X=50.004,Y=-0.001,SPD=1,HDG=90,COG=89.999,DEPTH=2.5,LAT=42.35846706,LON=-71.08698225,TYPE=kayak,"
                    "TIME=1795284022.406,LENGTH=4,YAW=1";
    ck_assert_int_eq(kelp_nodereport_parse(b, strlen(b), &r, NULL), KELP_OK);
    ck_assert_double_eq_tol(r.depth, 2.5, 1e-12);
    ck_assert_int_eq(kelp_nodereport_format_record(&r, buf, sizeof buf, NULL), KELP_OK);
    ck_assert_str_eq(buf, "NAME=ben,X=50,Y=0,SPD=1,HDG=90,COG=90,DEP=2.5,LAT=42.35846706,LON=-71.08698225,TYPE=kayak,YAW=0,"
                          "TIME=1795284022.41,LENGTH=4");
    /* the ledger: no type -> ship, length 12, COG from HDG; uuv without depth refused */
    ck_assert_int_eq(kelp_nodereport_parse("NAME=c,X=1,Y=2,HDG=30,TIME=5", 28, &r, NULL), KELP_OK);
    ck_assert_int_eq(kelp_nodereport_ledger(&r, NULL, NULL), KELP_OK);
    ck_assert_int_eq(kelp_nodereport_format_record(&r, buf, sizeof buf, NULL), KELP_OK);
    ck_assert_str_eq(buf, "NAME=c,X=1,Y=2,HDG=30,COG=30,TYPE=ship,TIME=5,LENGTH=12");
    ck_assert_int_eq(kelp_nodereport_parse("NAME=c,X=1,Y=2,TYPE=glider,TIME=5", 33, &r, NULL), KELP_OK);
    ck_assert_int_eq(kelp_nodereport_ledger(&r, NULL, NULL), KELP_ERR_PARSE);
}
END_TEST

START_TEST(test_view_kinds)
{
    kelp_view_kind k;
    ck_assert_int_eq(kelp_nodereport_view_kind_of("VIEW_POINT", &k), KELP_OK);
    ck_assert_int_eq(k, KELP_VIEW_POINT);
    ck_assert_int_eq(kelp_nodereport_view_kind_of("view_seglist", &k), KELP_OK);
    ck_assert_int_eq(k, KELP_VIEW_SEGLIST);
    ck_assert_int_eq(kelp_nodereport_view_kind_of("VIEW_COMM_PULSE", &k), KELP_OK);
    ck_assert_int_eq(k, KELP_VIEW_COMMS_PULSE);
    ck_assert_int_eq(kelp_nodereport_view_kind_of("VIEW_COMMS_PULSE", &k), KELP_OK);
    ck_assert_int_eq(kelp_nodereport_view_kind_of("VIEW_RANGE_PULSE", &k), KELP_OK);
    ck_assert_int_eq(k, KELP_VIEW_RANGE_PULSE);
    ck_assert_int_eq(kelp_nodereport_view_kind_of("NODE_REPORT", &k), KELP_ERR_NOTFOUND);
    ck_assert_str_eq(kelp_nodereport_view_var(KELP_VIEW_MARKER), "VIEW_MARKER");
}
END_TEST

START_TEST(test_view_point_seed)
{
    /* seed 004 5.2.4 (note the missing comma before source) */
    ck_assert_int_eq(vparse(KELP_VIEW_POINT, "label=alder's next waypoint,type=waypoint source=transit,x=60,y=-40", NULL),
                     KELP_OK);
    ck_assert_str_eq(V.label, "alder's next waypoint");
    ck_assert_str_eq(V.type, "waypoint");
    ck_assert_str_eq(V.source, "transit");
    ck_assert(V.x == 60 && V.y == -40 && V.active);
    /* seed 004 5.2.3, the colon form of an erase */
    ck_assert_int_eq(
        vparse(KELP_VIEW_POINT, "active,false:label,alder's next waypoint:type,waypoint:source,waypt_return:0,0,0", NULL),
        KELP_OK);
    ck_assert(!V.active && V.x == 0 && V.y == 0);
    ck_assert_str_eq(V.label, "alder's next waypoint");
    ck_assert_str_eq(V.source, "waypt_return");
    ck_assert_int_eq(vparse(KELP_VIEW_POINT, "x=1,y=2,active=true,vertex_size=4,vertex_color=red", NULL), KELP_OK);
    ck_assert(V.active && V.vertex_size == 4);
    ck_assert_str_eq(V.vertex_color, "red");
}
END_TEST

START_TEST(test_view_shapes)
{
    kelp_diag why = { 0 };
    /* uField seed 1.8 (uFldHazardSensor) */
    ck_assert_int_eq(vparse(KELP_VIEW_CIRCLE,
                            "x=12,y=-30,radius=10,label=archie_h1,edge_color=yellow,fill_color=yellow,fill=0.3,"
                            "edge_size=1,duration=60",
                            NULL),
                     KELP_OK);
    ck_assert(V.x == 12 && V.y == -30 && V.radius == 10 && V.fill == 0.3 && V.duration == 60);
    ck_assert_str_eq(V.edge_color, "yellow");
    ck_assert_int_eq(vparse(KELP_VIEW_POLYGON,
                            "pts={10,20:30,20:30,-5:10,-5},label=archie_swath,edge_color=white,fill_color=white,fill=0.1",
                            NULL),
                     KELP_OK);
    ck_assert_uint_eq(V.npts, 4);
    ck_assert(V.pts[2][0] == 30 && V.pts[2][1] == -5 && V.fill == 0.1);
    ck_assert_str_eq(V.label, "archie_swath");
    ck_assert_int_eq(vparse(KELP_VIEW_SEGLIST, "pts={60,-40:60,-100,0:150,-100},label=alpha_wpts,edge_color=gray", NULL),
                     KELP_OK);
    ck_assert_uint_eq(V.npts, 3);
    ck_assert(V.pts[1][1] == -100);
    ck_assert_int_eq(vparse(KELP_VIEW_SEGLIST, "label,old_style:0,0:10,0:10,10", NULL), KELP_OK);
    ck_assert_uint_eq(V.npts, 3);
    ck_assert_str_eq(V.label, "old_style");
    /* uField seed 1.7 and the beacon log */
    ck_assert_int_eq(vparse(KELP_VIEW_MARKER, "x=400,y=-200,label=02,color=orange,type=circle,width=4", NULL), KELP_OK);
    ck_assert(V.x == 400 && V.y == -200 && V.width == 4);
    ck_assert_str_eq(V.fill_color, "orange");
    ck_assert_str_eq(V.type, "circle");
    /* uField seed 1.5 */
    ck_assert_int_eq(vparse(KELP_VIEW_COMMS_PULSE,
                            "sx=109.63,sy=-60.06,tx=30.96,ty=-60.22,beam_width=7,duration=10,fill=0.35,label=JAMES2IKE,"
                            "edge_color=green,fill_color=red,time=2652414456.59,edge_size=1",
                            NULL),
                     KELP_OK);
    ck_assert(V.x == 109.63 && V.y == -60.06 && V.tx == 30.96 && V.ty == -60.22 && V.beam_width == 7);
    ck_assert(V.time == 2652414456.59);
    ck_assert_str_eq(V.label, "JAMES2IKE");
    /* uField seed 1.6: defaults fill what is missing */
    ck_assert_int_eq(vparse(KELP_VIEW_RANGE_PULSE, "x=-40,y=-150,label=04", &why), KELP_OK);
    ck_assert(V.radius == 40 && V.duration == 15 && V.fill == 0.25 && V.edge_size == 1);
    ck_assert_str_eq(V.fill_color, "green");
    ck_assert_str_eq(V.edge_color, "green");
    ck_assert_int_eq(vparse(KELP_VIEW_RANGE_PULSE,
                            "x=0,y=-200,radius=50,duration=6,label=indigo_ping,edge_color=white,fill_color=white,"
                            "time=19473362999.76,edge_size=1",
                            NULL),
                     KELP_OK);
    ck_assert(V.radius == 50 && V.duration == 6);
    ck_assert_str_eq(V.fill_color, "white");
    /* an erase of a polygon needs no vertices */
    ck_assert_int_eq(vparse(KELP_VIEW_POLYGON, "label=archie_swath,active=false", NULL), KELP_OK);
    ck_assert(!V.active && V.npts == 0);
}
END_TEST

START_TEST(test_view_errors)
{
    kelp_diag why = { 0 };
    const struct {
        kelp_view_kind k;
        const char *s;
        int rc;
        const char *why;
    } bad[] = {
        {KELP_VIEW_POINT, "label=a", KELP_ERR_PARSE, "needs x and y"},
        {KELP_VIEW_POINT, "x=1,y=zz", KELP_ERR_PARSE, "bad number"},
        {KELP_VIEW_CIRCLE, "x=1,y=2", KELP_ERR_PARSE, "needs a radius > 0"},
        {KELP_VIEW_CIRCLE, "x=1,y=2,radius=-3", KELP_ERR_PARSE, "needs a radius > 0"},
        {KELP_VIEW_POLYGON, "label=a", KELP_ERR_PARSE, "needs at least one vertex"},
        {KELP_VIEW_POLYGON, "pts=1,2:3,4", KELP_ERR_PARSE, "pts must be {x,y:x,y:...}"},
        {KELP_VIEW_POLYGON, "pts={1,2:3}", KELP_ERR_PARSE, "bad vertex"},
        {KELP_VIEW_POLYGON, "pts={1,2:3,4,5,6}", KELP_ERR_PARSE, "bad vertex"},
        {KELP_VIEW_POLYGON, "pts={1,2:3,4", KELP_ERR_PARSE, "unbalanced brace or quote"},
        {KELP_VIEW_COMMS_PULSE, "sx=1,sy=2,tx=3", KELP_ERR_PARSE, "needs sx, sy, tx and ty"},
        {KELP_VIEW_POINT, "x=1,y=2,active=maybe", KELP_ERR_PARSE, "active must be true or false"},
        {KELP_VIEW_POINT, "label:x", KELP_ERR_PARSE, "segment without ','"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        kelp_diag_clear(&why);
        ck_assert_int_eq(vparse(bad[i].k, bad[i].s, &why), bad[i].rc);
        ck_assert_int_ne(why.code, 0);
        ck_diag_msg(&why, bad[i].why);
    }
    /* too many vertices */
    char big[4096];
    size_t n = 0;
    n += (size_t)snprintf(big + n, sizeof big - n, "pts={");
    for (int i = 0; i <= KELP_VIEW_MAX_PTS; i++) n += (size_t)snprintf(big + n, sizeof big - n, "%s%d,%d", i ? ":" : "", i, i);
    snprintf(big + n, sizeof big - n, "}");
    ck_assert_int_eq(vparse(KELP_VIEW_SEGLIST, big, &why), KELP_ERR_NOSPACE);
    /* a label too long */
    char lab[200];
    memset(lab, 'q', sizeof lab);
    memcpy(lab, "x=1,y=2,label=", 14);
    lab[sizeof lab - 1] = 0;
    ck_assert_int_eq(vparse(KELP_VIEW_POINT, lab, &why), KELP_ERR_RANGE);
}
END_TEST

Suite *kelp_nodereport_suite(void)
{
    Suite *s = suite_create("nodereport");
    TCase *tc = tcase_create("report");
    tcase_add_test(tc, test_parse_seed);
    tcase_add_test(tc, test_format_seed);
    tcase_add_test(tc, test_format_numbers);
    tcase_add_test(tc, test_parse_variants);
    tcase_add_test(tc, test_parse_errors);
    tcase_add_test(tc, test_round_trip_fields);
    tcase_add_test(tc, test_record_248);
    suite_add_tcase(s, tc);
    TCase *tv = tcase_create("view");
    tcase_add_test(tv, test_view_kinds);
    tcase_add_test(tv, test_view_point_seed);
    tcase_add_test(tv, test_view_shapes);
    tcase_add_test(tv, test_view_errors);
    suite_add_tcase(s, tv);
    return s;
}
