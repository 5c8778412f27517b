/* kelp-scope's state machine (src/xms/xms.c): uXMS's table layout, keys, history and
 * display-all, as MOOS-IvP's uXMS (ivp/src/uXMS/XMS.cpp, lib_apputil/ACTable.cpp) has them. */
#include <check.h>
#include <string.h>
#include <kelp/xms.h>

static kelp_xms x;
static char out[16384];

static const char *render(void)
{
    size_t n = kelp_xms_render(&x, 100.0, out, sizeof out);
    ck_assert_uint_eq(n, strlen(out));
    return out;
}

static void start(void)
{
    kelp_xms_init(&x);
}

/* uXMS's defaults: no source/time/community columns, virgins shown as n/a, sorted by name */
START_TEST(xms_virgin_table)
{
    ck_assert_int_eq(kelp_xms_add_vars(&x, "NAV_Y, NAV_X"), 0);
    ck_assert_str_eq(render(), "VarName  (S)  (T)  (C)  VarValue (SCOPING:EVENTS)\n"
                               "-------  ---  ---  ---  -------------------------\n"
                               "NAV_X                   n/a\n"
                               "NAV_Y                   n/a\n");
}
END_TEST

/* doubles as %.6f compacted, strings quoted; 's' 't' 'c' show the columns; the time is %.2f */
START_TEST(xms_values_and_columns)
{
    ck_assert_int_eq(kelp_xms_add_vars(&x, "NAV_X,MODE"), 0);
    ck_assert_int_eq(kelp_xms_mail(&x, "NAV_X", false, "", 12.5, "uSimMarine", "alder", 3.456), 1);
    ck_assert_int_eq(kelp_xms_mail(&x, "MODE", true, "DEPLOY", 0, "pHelmIvP", "alder", 10), 1);
    ck_assert_int_eq(kelp_xms_key(&x, 's'), 1);
    ck_assert_int_eq(kelp_xms_key(&x, 't'), 1);
    ck_assert_int_eq(kelp_xms_key(&x, 'C'), 1);
    ck_assert_str_eq(render(), "VarName  (S)ource    (T)ime  (C)ommunity  VarValue (SCOPING:EVENTS)\n"
                               "-------  ----------  ------  -----------  -------------------------\n"
                               "MODE     pHelmIvP    10.00   alder        \"DEPLOY\"\n"
                               "NAV_X    uSimMarine  3.46    alder        12.5\n");
    ck_assert_int_eq(kelp_xms_key(&x, 's'), 1);
    ck_assert_ptr_nonnull(strstr(render(), "MODE          10.00   alder        \"DEPLOY\"\n"));
}
END_TEST

/* a source longer than 16 is cut in the middle to 16 (7 + ".." + 7); a virgin row's source is " n/a" */
START_TEST(xms_source_truncated)
{
    ck_assert_int_eq(kelp_xms_add_vars(&x, "A,B"), 0);
    x.disp_source = true;
    (void)kelp_xms_mail(&x, "A", false, "", 1e-7, "pContactMgrV20_alder", "c", 1);
    const char *r = render();
    ck_assert_ptr_nonnull(strstr(r, "A        pContac..0_alder            0\n"));
    ck_assert_ptr_nonnull(strstr(r, "B         n/a                        n/a\n"));
}
END_TEST

/* space pauses, r streams, e back to events; a frame is due on a change in events mode only */
START_TEST(xms_refresh_modes)
{
    ck_assert_int_eq(kelp_xms_add_var(&x, "A", false), 1);
    ck_assert(kelp_xms_due(&x, 0));
    (void)render();
    ck_assert(!kelp_xms_due(&x, 100.5));
    (void)kelp_xms_mail(&x, "A", false, "", 1, "p", "c", 1);
    ck_assert(!kelp_xms_due(&x, 100.3)); /* at most one frame per term interval (0.5 s) */
    ck_assert(kelp_xms_due(&x, 100.5));
    (void)render();
    ck_assert_int_eq(kelp_xms_mail(&x, "A", false, "", 1, "p", "c", 1), 0); /* unchanged */
    ck_assert(!kelp_xms_due(&x, 100.5));
    ck_assert_int_eq(kelp_xms_key(&x, ' '), 1);
    ck_assert_ptr_nonnull(strstr(render(), "VarValue (SCOPING:PAUSED)"));
    (void)kelp_xms_mail(&x, "A", false, "", 2, "p", "c", 2);
    ck_assert(!kelp_xms_due(&x, 200));
    ck_assert_int_eq(kelp_xms_key(&x, 'u'), 1);
    ck_assert_ptr_nonnull(strstr(render(), "A                       2\n"));
    ck_assert_int_eq(kelp_xms_key(&x, 'r'), 0);
    ck_assert(kelp_xms_due(&x, 100.5));
    ck_assert(!kelp_xms_due(&x, 100.1));
    ck_assert_ptr_nonnull(strstr(render(), "(SCOPING:STREAMING)"));
    ck_assert_int_eq(kelp_xms_key(&x, 'E'), 1);
    ck_assert_ptr_nonnull(strstr(render(), "(SCOPING:EVENTS)"));
}
END_TEST

/* the history variable: oldest first, repeats counted, (J)VarName column, z toggles */
START_TEST(xms_history)
{
    ck_assert_int_eq(kelp_xms_add_var(&x, "DEPTH", true), 1);
    ck_assert_int_eq(x.content, KELP_XMS_HISTORY); /* nothing else scoped */
    (void)kelp_xms_mail(&x, "DEPTH", false, "", 5, "uSim", "c", 1);
    (void)kelp_xms_mail(&x, "DEPTH", false, "", 5, "uSim", "c", 2);
    (void)kelp_xms_mail(&x, "DEPTH", true, "deep", 0, "uSim", "c", 3.5);
    x.disp_time = true;
    ck_assert_str_eq(render(), "(J)VarName  (S)  (T)ime  VarValue (HISTORY:EVENTS)\n"
                               "----------  ---  ------  -------------------------\n"
                               "DEPTH            2.00    (2) 5\n"
                               "DEPTH            3.50    (1) \"deep\"\n");
    ck_assert_int_eq(kelp_xms_key(&x, 'j'), 1);
    ck_assert_ptr_nonnull(strstr(render(), "(J)  (S)  (T)ime  VarValue"));
    ck_assert_int_eq(kelp_xms_key(&x, 'z'), 1);
    ck_assert_int_eq(x.content, KELP_XMS_SCOPING);
    ck_assert_int_eq(kelp_xms_key(&x, 'z'), 1);
    ck_assert_int_eq(x.content, KELP_XMS_HISTORY);
    x.history_len = 5;
    for (int i = 0; i < 20; i++) (void)kelp_xms_mail(&x, "DEPTH", false, "", i, "uSim", "c", i);
    const char *r = render();
    ck_assert_ptr_nonnull(strstr(r, "(1) 15\n"));
    ck_assert_ptr_null(strstr(r, "(1) 14\n"));
    ck_assert_int_eq(kelp_xms_key(&x, '<'), 1);
    ck_assert_uint_eq(x.history_len, 5);
}
END_TEST

/* display-all: anything but *_STATUS, APPCAST, DB_*SUMMARY joins; 'a' goes back to the start list */
START_TEST(xms_display_all)
{
    ck_assert_int_eq(kelp_xms_add_var(&x, "NAV_X", false), 1);
    ck_assert_ptr_eq(kelp_xms_next_subscription(&x), x.var[0].name);
    ck_assert_ptr_null(kelp_xms_next_subscription(&x));
    ck_assert_int_eq(kelp_xms_key(&x, 'A'), 1);
    ck_assert_str_eq(kelp_xms_next_subscription(&x), "*");
    ck_assert_int_eq(kelp_xms_mail(&x, "DEPLOY", true, "true", 0, "poke", "c", 1), 1);
    (void)kelp_xms_mail(&x, "PHELMIVP_STATUS", true, "x=1", 0, "pHelmIvP", "c", 1);
    (void)kelp_xms_mail(&x, "APPCAST", true, "x", 0, "pHelmIvP", "c", 1);
    ck_assert_uint_eq(x.nvar, 2);
    const char *r = render();
    ck_assert_ptr_nonnull(strstr(r, "DEPLOY                  \"true\"\n"));
    ck_assert_ptr_nonnull(strstr(r, "\n  -- displaying all variables --\n"));
    ck_assert_int_eq(kelp_xms_key(&x, 'a'), 1);
    ck_assert_uint_eq(x.nvar, 1);
    ck_assert_str_eq(x.var[0].name, "NAV_X");
    ck_assert_int_eq(kelp_xms_key(&x, 'a'), 0);
}
END_TEST

/* '/' then a prefix and Enter filters by name (any case); '?' clears; 'v' hides virgins */
START_TEST(xms_filter_and_virgins)
{
    ck_assert_int_eq(kelp_xms_add_vars(&x, "NAV_X,NAV_Y,DEPLOY"), 0);
    (void)kelp_xms_mail(&x, "NAV_X", false, "", 1, "p", "c", 1);
    ck_assert_int_eq(kelp_xms_key(&x, '/'), 1); /* the filter line shows what is typed */
    ck_assert_ptr_nonnull(strstr(render(), "  -- filter: _ -- \n"));
    const char *keys = "nav\n";
    int drawn = 0;
    for (const char *k = keys; *k; k++) drawn = kelp_xms_key(&x, *k);
    ck_assert_int_eq(drawn, 1);
    const char *r = render();
    ck_assert_ptr_null(strstr(r, "DEPLOY"));
    ck_assert_ptr_nonnull(strstr(r, "NAV_Y"));
    ck_assert_ptr_nonnull(strstr(r, "  -- filter: nav -- \n"));
    ck_assert_int_eq(x.refresh, KELP_XMS_PAUSED);
    ck_assert_int_eq(kelp_xms_key(&x, 'v'), 1);
    r = render();
    ck_assert_ptr_null(strstr(r, "NAV_Y"));
    ck_assert_ptr_nonnull(strstr(r, "NAV_X"));
    ck_assert_int_eq(kelp_xms_key(&x, '?'), 1);
    ck_assert_ptr_null(strstr(render(), "filter"));
}
END_TEST

/* TRUNC_DATA: 20 characters, plus 8/5/10 for each hidden column, then "..." inside the quotes */
START_TEST(xms_trunc)
{
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_xms_config(&x, "TRUNC_DATA", "true", &why), 1);
    ck_assert_int_eq(kelp_xms_add_var(&x, "S", false), 1);
    x.disp_source = x.disp_time = x.disp_community = true;
    (void)kelp_xms_mail(&x, "S", true, "abcdefghijklmnopqrstuvwxyz", 0, "p", "c", 1);
    ck_assert_ptr_nonnull(strstr(render(), "\"abcdefghijklmnopqrst...\"\n"));
    ck_assert_int_eq(kelp_xms_key(&x, '`'), 1);
    ck_assert_ptr_nonnull(strstr(render(), "\"abcdefghijklmnopqrstuvwxyz\"\n"));
}
END_TEST

/* the mission block: VAR lists, REFRESH_MODE, CONTENT_MODE, PAUSED, bad values refused */
START_TEST(xms_config)
{
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_xms_config(&x, "VAR", "B, A", &why), 1);
    ck_assert_int_eq(kelp_xms_config(&x, "var", "C", &why), 1);
    ck_assert_uint_eq(x.nvar, 3);
    ck_assert_str_eq(x.var[0].name, "A");
    ck_assert_int_eq(kelp_xms_config(&x, "REFRESH_MODE", "streaming", &why), 1);
    ck_assert_int_eq(x.refresh, KELP_XMS_STREAMING);
    ck_assert_int_eq(kelp_xms_config(&x, "REFRESH_MODE", "fast", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_xms_config(&x, "PAUSED", "true", &why), 1);
    ck_assert_int_eq(x.refresh, KELP_XMS_PAUSED);
    ck_assert_int_eq(kelp_xms_config(&x, "DISPLAY_SOURCE", "maybe", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_xms_config(&x, "DISPLAY_ALL", "true", &why), 1);
    ck_assert(x.disp_all);
    ck_assert_int_eq(kelp_xms_config(&x, "CONTENT_MODE", "help", &why), 1);
    ck_assert_ptr_nonnull(strstr(render(), "(HELP)"));
    ck_assert_int_eq(kelp_xms_config(&x, "NO_SUCH", "1", &why), 0);
    ck_assert_int_eq(kelp_xms_add_var(&x, "uXMS_12", false), 0); /* pAntler's name argument */
    ck_assert_int_eq(kelp_xms_add_var(&x, "A B", false), 0);
}
END_TEST

/* SOURCE: the Publishing list of <SRC>_STATUS joins the scope list */
START_TEST(xms_source_publishing)
{
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_xms_config(&x, "SOURCE", "pHelmIvP", &why), 1);
    ck_assert_str_eq(x.sources[0], "PHELMIVP_STATUS");
    (void)kelp_xms_mail(&x, "PHELMIVP_STATUS", true,
                        "AppErrorFlag=false,Uptime=1,Publishing=\"DESIRED_HEADING,IVPHELM_STATE,PHELMIVP_STATUS\","
                        "Subscribing=\"NAV_X\"",
                        0, "pHelmIvP", "c", 1);
    ck_assert_uint_eq(x.nvar, 2);
    ck_assert_str_eq(x.var[0].name, "DESIRED_HEADING");
    ck_assert_str_eq(x.var[1].name, "IVPHELM_STATE");
}
END_TEST

/* 'p': the processes seen, IDs 0 MOOSDB, 1 pHelmIvP, then a, b in order; '-' then IDs and
 * Enter hides their variables, '-' '?' Enter shows them again; '+' adds a source */
START_TEST(xms_procs_and_masks)
{
    ck_assert_int_eq(kelp_xms_add_vars(&x, "A,B,C,D"), 0);
    (void)kelp_xms_mail(&x, "A", false, "", 1, "uSimMarine", "c", 10);
    (void)kelp_xms_mail(&x, "B", false, "", 2, "pHelmIvP", "c", 20);
    (void)kelp_xms_mail(&x, "C", false, "", 3, "kelp-poke", "c", 30);
    (void)kelp_xms_mail(&x, "D", false, "", 4, "MOOSDB_alder", "c", 40);
    ck_assert_int_eq(kelp_xms_key(&x, 'p'), 1);
    ck_assert_str_eq(render(), "                                                            (PROCESSES:EVENTS)\n"
                               "uProcessWatch(0): not running\n"
                               "ID  Process Name  Mail   Client\n"
                               "--  ------------  -----  ------\n"
                               "0   MOOSDB_alder  60.00  -\n"
                               "1   pHelmIvP      80.00  -\n"
                               "a   uSimMarine    90.00  -\n"
                               "b   kelp-poke     70.00  -\n");
    const char *keys = "-ab\n";
    for (const char *k = keys; *k; k++) ck_assert_int_eq(kelp_xms_key(&x, *k), 1);
    ck_assert_int_eq(x.content, KELP_XMS_SCOPING);
    ck_assert_int_eq(x.refresh, KELP_XMS_PAUSED);
    const char *r = render();
    ck_assert_ptr_null(strstr(r, "\nA "));
    ck_assert_ptr_null(strstr(r, "\nC "));
    ck_assert_ptr_nonnull(strstr(r, "\nB "));
    ck_assert_int_eq(kelp_xms_key(&x, 'p'), 1);
    ck_assert_ptr_nonnull(strstr(render(), "\n-a  uSimMarine"));
    keys = "-?\n";
    for (const char *k = keys; *k; k++) (void)kelp_xms_key(&x, *k);
    ck_assert_ptr_nonnull(strstr(render(), "\nA "));
    keys = "+1\n";
    for (const char *k = keys; *k; k++) (void)kelp_xms_key(&x, *k);
    ck_assert_uint_eq(x.nsources, 1);
    ck_assert_str_eq(x.sources[0], "PHELMIVP_STATUS");
}
END_TEST

Suite *kelp_xms_suite(void);
Suite *kelp_xms_suite(void)
{
    Suite *s = suite_create("xms");
    TCase *t = tcase_create("uxms");
    tcase_add_checked_fixture(t, start, NULL);
    tcase_add_test(t, xms_virgin_table);
    tcase_add_test(t, xms_values_and_columns);
    tcase_add_test(t, xms_source_truncated);
    tcase_add_test(t, xms_refresh_modes);
    tcase_add_test(t, xms_history);
    tcase_add_test(t, xms_display_all);
    tcase_add_test(t, xms_filter_and_virgins);
    tcase_add_test(t, xms_trunc);
    tcase_add_test(t, xms_config);
    tcase_add_test(t, xms_source_publishing);
    tcase_add_test(t, xms_procs_and_masks);
    suite_add_tcase(s, t);
    return s;
}
