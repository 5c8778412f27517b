/* kelp-viewer's model: vehicles, trails, staleness, artifacts, pMarineViewer's buttons and
 * actions, and the JSON snapshots / change lists the page consumes. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/viewer.h>

static kelp_viewer *V;
static char J[1 << 20];

static void setup(void)
{
    V = malloc(sizeof *V);
    ck_assert_ptr_nonnull(V);
    kelp_viewer_init(V);
    ck_assert_int_eq(kelp_viewer_set_datum(V, 43.8253, -70.3304), 0);
}

static void teardown(void)
{
    free(V);
}

static int mail(const char *var, const char *s, double now)
{
    return kelp_viewer_mail(V, var, s, strlen(s), now);
}

static void snap(double now)
{
    size_t n = 0;
    ck_assert_int_eq(kelp_viewer_json_snapshot(V, now, 1, J, sizeof J, &n), 0);
    ck_assert_uint_eq(n, strlen(J));
}

static void changes(uint32_t since, double now)
{
    ck_assert_int_eq(kelp_viewer_json_changes(V, since, now, 1, J, sizeof J, NULL), 0);
}

START_TEST(test_report_xy_and_latlon)
{
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=alpha,TYPE=kayak,X=10,Y=-20,HDG=90,SPD=1.5,MODE=SURVEYING", 100), 1);
    /* LAT/LON only: X/Y from the datum */
    ck_assert_int_eq(mail("NODE_REPORT_LOCAL", "NAME=bravo,TYPE=UUV,LAT=43.8262,LON=-70.3304,HDG=0", 100), 1);
    ck_assert_int_eq(V->veh[0].rep.x, 10);
    /* UTM as 24.8 (PROJ: the datum's meridian runs 0.9 deg off grid north in zone 19) */
    ck_assert(fabs(V->veh[1].rep.y - 99.9591) < 0.001 && fabs(V->veh[1].rep.x - 1.6075) < 0.001);
    snap(100.5);
    ck_assert_ptr_nonnull(strstr(J, "\"name\":\"alpha\",\"type\":\"kayak\",\"x\":10,\"y\":-20,\"hdg\":90"));
    ck_assert_ptr_nonnull(strstr(J, "\"mode\":\"SURVEYING\""));
    ck_assert_ptr_nonnull(strstr(J, "\"name\":\"bravo\",\"type\":\"UUV\""));
    ck_assert_ptr_nonnull(strstr(J, "\"full\":1"));
    ck_assert_ptr_nonnull(strstr(J, "\"lat0\":43.8253"));
    /* bad mail is counted, not stored */
    ck_assert_int_lt(mail("NODE_REPORT", "X=1,Y=2", 101), 0);
    ck_assert_int_lt(mail("NODE_REPORT", "garbage", 101), 0);
    ck_assert_uint_eq(V->stats.reports_bad, 2);
    ck_assert_int_eq(mail("DEPLOY", "true", 101), 0);
    ck_assert_int_eq(mail("NODE_REPORT_BRAVO", "NAME=zulu,X=1,Y=2", 101), 0); /* a relayed copy */
}
END_TEST

START_TEST(test_no_datum_latlon_refused)
{
    kelp_viewer_init(V);
    ck_assert_int_lt(mail("NODE_REPORT", "NAME=a,LAT=43.8,LON=-70.3", 1), 0);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=a,X=1,Y=2", 1), 1);
    snap(1);
    ck_assert_ptr_nonnull(strstr(J, "\"datum\":0"));
}
END_TEST

START_TEST(test_trail_ring_and_changes)
{
    ck_assert_int_eq(kelp_viewer_config(V, "trails_length", "3", NULL), 1);
    for (int i = 0; i < 5; i++) {
        char r[96];
        snprintf(r, sizeof r, "NAME=a,X=%d,Y=0", i);
        ck_assert_int_eq(mail("NODE_REPORT", r, 10 + i), 1);
    }
    snap(15);
    ck_assert_ptr_nonnull(strstr(J, "\"trail\":[[2,0],[3,0],[4,0]]"));
    uint32_t s = kelp_viewer_seq(V);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=a,X=5,Y=0", 16), 1);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=a,X=6,Y=1", 16.2), 1);
    changes(s, 16.3);
    /* one record for the vehicle (coalesced), the two new trail points only */
    ck_assert_ptr_nonnull(strstr(J, "\"full\":0"));
    ck_assert_ptr_nonnull(strstr(J, "\"x\":6,\"y\":1"));
    ck_assert_ptr_nonnull(strstr(J, "\"trail\":[[5,0],[6,1]]"));
    ck_assert_ptr_null(strstr(J, "\"x\":5,"));
    /* nothing new: empty lists */
    changes(kelp_viewer_seq(V), 17);
    ck_assert_ptr_nonnull(strstr(J, "\"veh\":[],\"art\":[]"));
    /* an unknown future seq or 0 gets a snapshot */
    changes(0, 17);
    ck_assert_ptr_nonnull(strstr(J, "\"full\":1"));
}
END_TEST

START_TEST(test_stale_and_remove)
{
    ck_assert_int_eq(kelp_viewer_config(V, "stale_report_thresh", "1", NULL), 1);
    ck_assert(V->stale_report_thresh == KELP_VIEWER_STALE_MIN); /* clipped to 2 s */
    ck_assert_int_eq(kelp_viewer_config(V, "stale_remove_thresh", "10", NULL), 1);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=a,X=1,Y=1", 100), 1);
    ck_assert_int_eq(kelp_viewer_tick(V, 101.5), 0);
    uint32_t s = kelp_viewer_seq(V);
    ck_assert_int_eq(kelp_viewer_tick(V, 102.5), 1);
    ck_assert_int_eq(kelp_viewer_tick(V, 103), 0);
    changes(s, 103);
    ck_assert_ptr_nonnull(strstr(J, "\"stale\":1"));
    /* a report makes it fresh again */
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=a,X=1,Y=2", 104), 1);
    snap(104);
    ck_assert_ptr_nonnull(strstr(J, "\"stale\":0"));
    s = kelp_viewer_seq(V);
    ck_assert_int_eq(kelp_viewer_tick(V, 115), 1);
    changes(s, 115);
    ck_assert_ptr_nonnull(strstr(J, "{\"name\":\"a\",\"gone\":1}"));
    snap(115);
    ck_assert_ptr_nonnull(strstr(J, "\"veh\":[]"));
    /* back again: a new trail */
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=a,X=7,Y=7", 116), 1);
    snap(116);
    ck_assert_ptr_nonnull(strstr(J, "\"trail\":[[7,7]]"));
}
END_TEST

START_TEST(test_default_stale_60s_removed_180s)
{
    ck_assert(V->stale_report_thresh == 60.0 && V->stale_remove_thresh == 180.0);
    ck_assert_uint_eq(V->trails_length, KELP_VIEWER_TRAIL_DEFAULT);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=a,X=1,Y=1", 0), 1);
    ck_assert_int_eq(kelp_viewer_tick(V, 59.9), 0);
    ck_assert_int_eq(kelp_viewer_tick(V, 60.1), 1);
    ck_assert(V->veh[0].stale && !V->veh[0].gone);
    ck_assert_int_eq(kelp_viewer_tick(V, 179.9), 0);
    ck_assert_int_eq(kelp_viewer_tick(V, 180.1), 1);
    ck_assert(V->veh[0].gone);
    /* 0: never removed */
    ck_assert_int_eq(kelp_viewer_config(V, "stale_remove_thresh", "0", NULL), 1);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=b,X=1,Y=1", 200), 1);
    ck_assert_int_eq(kelp_viewer_tick(V, 1e6), 1);
    ck_assert(V->veh[1].stale && !V->veh[1].gone);
}
END_TEST

START_TEST(test_artifacts_keyed_and_erased)
{
    ck_assert_int_eq(mail("VIEW_POLYGON", "pts={0,0:10,0:10,10},label=ops,edge_color=dodger_blue,fill=0.2", 1), 1);
    ck_assert_int_eq(mail("VIEW_POLYGON", "pts={0,0:20,0:20,20},label=ops,edge_color=light_green", 2), 1);
    ck_assert_int_eq(mail("VIEW_CIRCLE", "x=5,y=5,radius=12,label=ops,fill_color=red", 2), 1); /* other kind, same label */
    ck_assert_int_eq(mail("VIEW_MARKER", "x=0,y=-200,label=03,color=orange,type=circle,width=4", 2), 1);
    snap(3);
    ck_assert_ptr_nonnull(strstr(J, "{\"kind\":\"polygon\",\"label\":\"ops\",\"t\":2,\"pts\":[[0,0],[20,0],[20,20]]"));
    ck_assert_ptr_nonnull(strstr(J, "\"edge_color\":\"light_green\""));
    ck_assert_ptr_null(strstr(J, "dodger_blue"));
    ck_assert_ptr_nonnull(strstr(J, "\"kind\":\"circle\",\"label\":\"ops\""));
    ck_assert_ptr_nonnull(strstr(J, "\"radius\":12"));
    ck_assert_ptr_nonnull(strstr(J, "\"kind\":\"marker\",\"label\":\"03\""));
    ck_assert_ptr_nonnull(strstr(J, "\"fill_color\":\"orange\""));
    uint32_t s = kelp_viewer_seq(V);
    ck_assert_int_eq(mail("VIEW_POLYGON", "label=ops,active=false", 4), 1);
    ck_assert_int_eq(mail("VIEW_POLYGON", "label=never_seen,active=false", 4), 0);
    changes(s, 4);
    ck_assert_ptr_nonnull(strstr(J, "\"art\":[{\"kind\":\"polygon\",\"label\":\"ops\",\"gone\":1}]"));
    snap(5);
    ck_assert_ptr_null(strstr(J, "\"kind\":\"polygon\""));
    ck_assert_int_lt(mail("VIEW_CIRCLE", "x=1", 5), 0);
    ck_assert_uint_eq(V->stats.views_bad, 1);
}
END_TEST

START_TEST(test_pulses_expire)
{
    ck_assert_int_eq(mail("VIEW_RANGE_PULSE", "x=1,y=2,radius=40,duration=15,label=04", 100), 1);
    ck_assert_int_eq(mail("VIEW_COMMS_PULSE", "sx=0,sy=0,tx=50,ty=0,beam_width=7,duration=10,label=A2B", 100), 1);
    snap(101);
    ck_assert_ptr_nonnull(strstr(J, "\"kind\":\"range_pulse\",\"label\":\"04\",\"t\":100,\"x\":1,\"y\":2,\"radius\":40,\"duration\":15"));
    ck_assert_ptr_nonnull(strstr(J, "\"tx\":50"));
    ck_assert_int_eq(kelp_viewer_tick(V, 109), 0);
    ck_assert_int_eq(kelp_viewer_tick(V, 111), 1); /* the comms pulse */
    snap(111);
    ck_assert_ptr_null(strstr(J, "comms_pulse"));
    ck_assert_ptr_nonnull(strstr(J, "range_pulse"));
    ck_assert_int_eq(kelp_viewer_tick(V, 116), 1);
    snap(116);
    ck_assert_ptr_nonnull(strstr(J, "\"art\":[]"));
}
END_TEST

START_TEST(test_artifact_table_full_evicts_pulse_first)
{
    char s[128];
    ck_assert_int_eq(mail("VIEW_POINT", "x=1,y=1,label=keep", 1), 1);
    for (int i = 0; i < KELP_VIEWER_MAX_ARTIFACTS + 10; i++) {
        snprintf(s, sizeof s, "x=1,y=2,radius=4,duration=100,label=p%d", i);
        ck_assert_int_eq(mail("VIEW_RANGE_PULSE", s, 2), 1);
    }
    ck_assert_uint_eq(V->stats.evicted, 11);
    snap(3);
    ck_assert_ptr_nonnull(strstr(J, "\"label\":\"keep\""));
    ck_assert_ptr_null(strstr(J, "\"label\":\"p0\""));
    ck_assert_ptr_nonnull(strstr(J, "\"label\":\"p265\""));
    /* an eviction cannot be told as a change: older pages get a snapshot */
    changes(5, 3);
    ck_assert_ptr_nonnull(strstr(J, "\"full\":1"));
    /* a page that has that snapshot gets changes again */
    changes(kelp_viewer_seq(V), 3);
    ck_assert_ptr_nonnull(strstr(J, "\"full\":0"));
}
END_TEST

START_TEST(test_buttons)
{
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_viewer_config(V, "button_one", "DEPLOY # DEPLOY_ALL=true # MOOS_MANUAL_OVERRIDE_ALL=false", &why), 1);
    ck_assert_int_eq(kelp_viewer_config(V, "BUTTON_2", "RETURN # RETURN_ALL = true # SPEED=1.5 # NAME=\"3\"", &why), 1);
    ck_assert_int_eq(kelp_viewer_config(V, "button_twenty", "A=b # X # color=light_green", &why), 1); /* label anywhere */
    ck_assert_uint_eq(V->ncmds, 3);
    const kelp_viewer_cmd *c = kelp_viewer_cmd_get(V, 0);
    ck_assert_str_eq(c->label, "DEPLOY");
    ck_assert_uint_eq(c->slot, 1);
    ck_assert_uint_eq(c->npokes, 2);
    ck_assert_str_eq(c->pokes[0].var, "DEPLOY_ALL");
    ck_assert(c->pokes[0].is_string);
    ck_assert_str_eq(c->pokes[0].sval, "true");
    ck_assert_str_eq(c->pokes[1].var, "MOOS_MANUAL_OVERRIDE_ALL");
    ck_assert_str_eq(c->pokes[1].sval, "false");
    c = kelp_viewer_cmd_get(V, 1);
    ck_assert_uint_eq(c->slot, 2);
    ck_assert_str_eq(c->pokes[0].var, "RETURN_ALL");
    ck_assert(!c->pokes[1].is_string && c->pokes[1].dval == 1.5);
    ck_assert(c->pokes[2].is_string);
    ck_assert_str_eq(c->pokes[2].sval, "3"); /* quoted: a string */
    c = kelp_viewer_cmd_get(V, 2);
    ck_assert_uint_eq(c->slot, 20);
    ck_assert_str_eq(c->label, "X");
    ck_assert_str_eq(c->color, "light_green");
    ck_assert_uint_eq(c->npokes, 1);
    /* another line for the same button adds its pokes and relabels it (pMarineViewer) */
    ck_assert_int_eq(kelp_viewer_config(V, "button_one", "GO # DEPLOY=true", &why), 1);
    ck_assert_uint_eq(V->ncmds, 3);
    c = kelp_viewer_cmd_get(V, 0);
    ck_assert_str_eq(c->label, "GO");
    ck_assert_uint_eq(c->npokes, 3);
    ck_assert_str_eq(c->pokes[2].var, "DEPLOY");
    ck_assert_ptr_null(kelp_viewer_cmd_get(V, 3));
    const kelp_viewer_poke *pk[16];
    ck_assert_uint_eq(kelp_viewer_press(V, 0, pk, 16), 3);
    ck_assert_ptr_eq(pk[2], &c->pokes[2]);
    ck_assert_uint_eq(kelp_viewer_press(V, 3, pk, 16), 0);
    /* refused */
    ck_assert_int_lt(kelp_viewer_config(V, "button_three", "A=1 # B=2", &why), 0); /* no label */
    ck_assert_int_ne(why.code, 0);
    ck_assert_int_lt(kelp_viewer_config(V, "button_three", "L # =2", &why), 0);
    ck_assert_int_lt(kelp_viewer_config(V, "button_three", "L # A B=2", &why), 0);
    ck_assert_int_eq(kelp_viewer_config(V, "button_three", "ONLYLABEL", &why), 1); /* a label alone: posts nothing */
    ck_assert_uint_eq(kelp_viewer_press(V, 3, pk, 16), 0);
    ck_assert_int_eq(kelp_viewer_config(V, "button_21", "L # A=2", &why), 0); /* not a key */
    ck_assert_int_eq(kelp_viewer_config(V, "tiff_file", "x.tif", &why), 0);
    snap(0);
    ck_assert_ptr_nonnull(strstr(J, "{\"i\":0,\"kind\":\"button\",\"slot\":1,\"sep\":0,\"label\":\"GO\",\"pokes\":"
                                    "[\"DEPLOY_ALL=true\",\"MOOS_MANUAL_OVERRIDE_ALL=false\",\"DEPLOY=true\"]}"));
    ck_assert_ptr_nonnull(strstr(J, "\"pokes\":[\"RETURN_ALL=true\",\"SPEED=1.5\",\"NAME=3\"]"));
    ck_assert_ptr_nonnull(strstr(J, "\"label\":\"X\",\"color\":\"light_green\""));
}
END_TEST

START_TEST(test_actions)
{
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_viewer_config(V, "action", "menu_key=deploy # DEPLOY = true # RETURN = false", &why), 1);
    ck_assert_int_eq(kelp_viewer_config(V, "action+", "menu_key=return # RETURN=true", &why), 1);
    ck_assert_int_eq(kelp_viewer_config(V, "action", "STATION_KEEP=true # LOITER=false", &why), 1);
    ck_assert_int_eq(kelp_viewer_config(V, "action", "SPEED=2 # menu_key=deploy", &why), 1);
    ck_assert_uint_eq(V->ncmds, 6); /* one entry per pair */
    const kelp_viewer_cmd *c = kelp_viewer_cmd_get(V, 0);
    ck_assert_int_eq(c->kind, KELP_VIEWER_ACTION);
    ck_assert_str_eq(c->label, "DEPLOY=true");
    ck_assert_str_eq(c->key, "deploy");
    ck_assert_str_eq(kelp_viewer_cmd_get(V, 1)->label, "RETURN=false");
    ck_assert(!c->separator);
    ck_assert(kelp_viewer_cmd_get(V, 2)->separator);
    ck_assert_str_eq(kelp_viewer_cmd_get(V, 3)->label, "STATION_KEEP=true");
    ck_assert_str_eq(kelp_viewer_cmd_get(V, 3)->key, "");
    ck_assert_str_eq(kelp_viewer_cmd_get(V, 5)->label, "SPEED=2");
    /* choosing an entry with a key posts every pair with that key, from every line */
    const kelp_viewer_poke *pk[16];
    ck_assert_uint_eq(kelp_viewer_press(V, 1, pk, 16), 3);
    ck_assert_str_eq(pk[0]->var, "DEPLOY");
    ck_assert_str_eq(pk[1]->var, "RETURN");
    ck_assert_str_eq(pk[2]->var, "SPEED");
    ck_assert(!pk[2]->is_string && pk[2]->dval == 2);
    ck_assert_uint_eq(kelp_viewer_press(V, 2, pk, 16), 1);
    ck_assert_str_eq(pk[0]->var, "RETURN");
    /* without a key, only its own pair */
    ck_assert_uint_eq(kelp_viewer_press(V, 4, pk, 16), 1);
    ck_assert_str_eq(pk[0]->var, "LOITER");
    ck_assert_uint_eq(kelp_viewer_press(V, 1, pk, 2), 2); /* bounded by the caller's room */
    ck_assert_int_lt(kelp_viewer_config(V, "action", "menu_key=x", &why), 0);
    ck_assert_int_lt(kelp_viewer_config(V, "action", "nonsense", &why), 0);
    ck_assert_uint_eq(V->ncmds, 6);
    snap(0);
    ck_assert_ptr_nonnull(strstr(J, "{\"i\":2,\"kind\":\"action\",\"slot\":0,\"sep\":1,\"label\":\"RETURN=true\",\"key\":\"return\",\"pokes\":[\"RETURN=true\"]}"));
    /* the table is bounded */
    int rc = 1;
    for (int i = 0; i < KELP_VIEWER_MAX_CMDS + 2 && rc > 0; i++) rc = kelp_viewer_config(V, "action", "A=1", &why);
    ck_assert_int_eq(rc, KELP_ERR_NOSPACE);
    ck_assert_uint_eq(V->ncmds, KELP_VIEWER_MAX_CMDS);
}
END_TEST

START_TEST(test_poke_parse)
{
    kelp_viewer_poke p;
    ck_assert_int_eq(kelp_viewer_poke_parse(" DEPTH = 400 ", 13, &p), 0);
    ck_assert(!p.is_string && p.dval == 400);
    ck_assert_int_eq(kelp_viewer_poke_parse("POLY=pts={1,2:3,4}", 18, &p), 0);
    ck_assert(p.is_string);
    ck_assert_str_eq(p.sval, "pts={1,2:3,4}");
    ck_assert_int_eq(kelp_viewer_poke_parse("E=", 2, &p), 0);
    ck_assert(p.is_string && p.sval[0] == 0);
    ck_assert_int_lt(kelp_viewer_poke_parse("novalue", 7, &p), 0);
}
END_TEST

START_TEST(test_json_escaping_and_room)
{
    ck_assert_int_eq(mail("VIEW_POINT", "x=1,y=2,label=a\\b\001c", 1), 1);
    snap(1);
    ck_assert_ptr_nonnull(strstr(J, "\"label\":\"a\\\\b\\u0001c\""));
    char small[64];
    size_t n = 99;
    ck_assert_int_eq(kelp_viewer_json_snapshot(V, 1, 1, small, sizeof small, &n), KELP_ERR_NOSPACE);
    ck_assert_uint_lt(strlen(small), sizeof small);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=v1,X=1,Y=2,SPD=1,DEPTH=3,MODE=A", 1), 1);
    ck_assert_int_eq(kelp_viewer_json_vehicle(V, "v1", J, sizeof J, &n), 0);
    ck_assert_ptr_nonnull(strstr(J, "\"dep\":3"));
    ck_assert_ptr_nonnull(strstr(J, "\"trail\":[]"));
    ck_assert_int_eq(kelp_viewer_json_vehicle(V, "nobody", J, sizeof J, &n), KELP_ERR_NOTFOUND);
}
END_TEST

START_TEST(test_image_and_clear)
{
    ck_assert_int_eq(kelp_viewer_set_image(V, "/image", 43.83, 43.82, -70.32, -70.34), 0);
    ck_assert_int_eq(kelp_viewer_set_image(V, "/image", 43.81, 43.82, -70.32, -70.34), KELP_ERR_ARG);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=a,X=1,Y=1", 1), 1);
    snap(1);
    ck_assert_ptr_nonnull(strstr(J, "\"image\":{\"url\":\"/image\",\"n\":43.83,\"s\":43.82,\"e\":-70.32,\"w\":-70.34}"));
    uint32_t s = kelp_viewer_seq(V);
    kelp_viewer_clear(V);
    changes(s, 2);
    ck_assert_ptr_nonnull(strstr(J, "\"full\":1"));
    ck_assert_ptr_nonnull(strstr(J, "\"veh\":[]"));
    changes(kelp_viewer_seq(V), 2);
    ck_assert_ptr_nonnull(strstr(J, "\"full\":0"));
}
END_TEST

START_TEST(test_many_vehicles)
{
    char r[96];
    for (int i = 0; i < KELP_VIEWER_MAX_VEHICLES; i++) {
        snprintf(r, sizeof r, "NAME=v%d,X=%d,Y=0", i, i);
        ck_assert_int_eq(mail("NODE_REPORT", r, 1), 1);
    }
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=extra,X=0,Y=0", 1), KELP_ERR_NOSPACE);
    ck_assert_uint_eq(V->stats.vehicles_full, 1);
    /* a removed vehicle's slot is reused */
    ck_assert_int_eq(kelp_viewer_config(V, "stale_remove_thresh", "5", NULL), 1);
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=v0,X=0,Y=0", 1), 1);
    for (int i = 1; i < KELP_VIEWER_MAX_VEHICLES; i++) {
        snprintf(r, sizeof r, "NAME=v%d,X=%d,Y=0", i, i);
        ck_assert_int_eq(mail("NODE_REPORT", r, 8), 1);
    }
    ck_assert_int_eq(kelp_viewer_tick(V, 8.5), 1); /* v0 removed */
    uint32_t s = kelp_viewer_seq(V) - 1;
    ck_assert_int_eq(mail("NODE_REPORT", "NAME=extra,X=0,Y=0", 9), 1);
    changes(s, 9);
    ck_assert_ptr_nonnull(strstr(J, "\"full\":1")); /* the tombstone was overwritten */
}
END_TEST

START_TEST(test_appcasts)
{
    const char *c1 = "proc=pHelmIvP!@#iter=12!@#node=alpha!@#messages=line 1!@line 2!@#run_warning_total=0";
    ck_assert_int_eq(mail("APPCAST", c1, 10), 1);
    ck_assert_int_eq(mail("APPCAST", "proc=pNodeReporter!@#node=alpha!@#iter=3", 10), 1);
    uint32_t s = kelp_viewer_seq(V);
    ck_assert_int_eq(mail("APPCAST", "proc=pHelmIvP!@#iter=13!@#node=alpha", 11), 1); /* replaces */
    ck_assert_int_lt(mail("APPCAST", "iter=1!@#node=alpha", 11), 0);               /* no proc */
    ck_assert_uint_eq(V->stats.casts_bad, 1);
    changes(s, 12);
    ck_assert_ptr_nonnull(strstr(J, "\"cast\":[{\"node\":\"alpha\",\"proc\":\"pHelmIvP\",\"t\":11,\"text\":\"proc=pHelmIvP!@#iter=13!@#node=alpha\"}]"));
    snap(12);
    ck_assert_ptr_nonnull(strstr(J, "\"proc\":\"pNodeReporter\""));
    /* a full table: the oldest goes */
    char c[128];
    for (int i = 0; i < KELP_VIEWER_MAX_CASTS; i++) {
        snprintf(c, sizeof c, "proc=p%d!@#node=n", i);
        ck_assert_int_eq(mail("APPCAST", c, 20), 1);
    }
    snap(21);
    ck_assert_ptr_null(strstr(J, "\"proc\":\"pHelmIvP\""));
    ck_assert_ptr_nonnull(strstr(J, "\"proc\":\"p63\""));
}
END_TEST

Suite *kelp_viewer_suite(void);
Suite *kelp_viewer_suite(void)
{
    Suite *s = suite_create("viewer");
    TCase *tc = tcase_create("core");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, test_report_xy_and_latlon);
    tcase_add_test(tc, test_no_datum_latlon_refused);
    tcase_add_test(tc, test_trail_ring_and_changes);
    tcase_add_test(tc, test_stale_and_remove);
    tcase_add_test(tc, test_default_stale_60s_removed_180s);
    tcase_add_test(tc, test_artifacts_keyed_and_erased);
    tcase_add_test(tc, test_pulses_expire);
    tcase_add_test(tc, test_artifact_table_full_evicts_pulse_first);
    tcase_add_test(tc, test_buttons);
    tcase_add_test(tc, test_actions);
    tcase_add_test(tc, test_poke_parse);
    tcase_add_test(tc, test_json_escaping_and_room);
    tcase_add_test(tc, test_image_and_clear);
    tcase_add_test(tc, test_many_vehicles);
    tcase_add_test(tc, test_appcasts);
    suite_add_tcase(s, tc);
    return s;
}
