/* kelp launch (src/app/launch.c): the ANTLER block as a plan; children started and reaped. */
#include <check.h>
#include "check_diag.h"
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <kelp/edge/launch.h>

static kelp_mission_node g_nodes[128];

static int plan_of(const char *text, kelp_launch_plan *p, kelp_diag *err)
{
    static char buf[4096];
    snprintf(buf, sizeof buf, "%s", text);
    kelp_mission m;
    ck_assert_int_eq(kelp_mission_parse(&m, buf, strlen(buf), g_nodes, 128), 0);
    return kelp_launch_plan_read(p, &m, "t.moos", "/nonexistent", err);
}

START_TEST(launch_plan)
{
    static kelp_launch_plan p;
    kelp_diag err = {0};
    ck_assert_int_eq(plan_of("ProcessConfig = ANTLER\n{\n MSBetweenLaunches = 200\n Run = MOOSDB @ NewConsole = true\n"
                             " Run = pXRelay @ NewConsole = true ~ pXRelay_PEARS\n Run = uXMS\n}\n",
                             &p, &err),
                     0);
    ck_assert_int_eq(p.nkids, 2);
    ck_assert_int_eq(p.skipped_moosdb, 1);
    ck_assert(p.ms_between == 200);
    ck_assert_str_eq(p.kids[0].prog, "pXRelay");
    ck_assert_str_eq(p.kids[0].alias, "pXRelay_PEARS");
    ck_assert_str_eq(p.kids[1].alias, "uXMS");
    ck_assert_str_eq(p.kids[1].path, "kelp-scope"); /* MOOS name mapped; not in bindir: from PATH */
    ck_assert_str_eq(kelp_launch_map_prog("pMarineViewer"), "kelp-plot");
    ck_assert_str_eq(kelp_launch_map_prog("pHelmIvP"), "pHelmIvP");
    /* errors say where */
    ck_assert_int_lt(plan_of("ProcessConfig = X\n{\n a = 1\n}\n", &p, &err), 0);
    ck_diag_has(&err, "no ProcessConfig = ANTLER");
    kelp_diag_clear(&err);
    ck_assert_int_lt(plan_of("ProcessConfig = ANTLER\n{\n MSBetweenLaunches = nan\n Run = a\n}\n", &p, &err), 0);
    ck_diag_has(&err, "t.moos:3: MSBetweenLaunches");
    kelp_diag_clear(&err);
    ck_assert_int_lt(plan_of("ProcessConfig = ANTLER\n{\n Run = two words\n}\n", &p, &err), 0);
    ck_diag_has(&err, "t.moos:3:");
    kelp_diag_clear(&err);
    ck_assert_int_lt(plan_of("ProcessConfig = ANTLER\n{\n Run = MOOSDB\n}\n", &p, &err), 0);
    ck_diag_has(&err, "no Run lines");
    kelp_diag_clear(&err);
}
END_TEST

START_TEST(launch_start_reap)
{
    static kelp_launch_plan p;
    memset(&p, 0, sizeof p);
    p.nkids = 2;
    snprintf(p.kids[0].path, sizeof p.kids[0].path, "true");
    snprintf(p.kids[0].alias, sizeof p.kids[0].alias, "a");
    snprintf(p.kids[1].path, sizeof p.kids[1].path, "sleep"); /* "sleep t.moos b": fails fast */
    snprintf(p.kids[1].alias, sizeof p.kids[1].alias, "b");
    ck_assert_int_eq(kelp_launch_start(&p.kids[0], "t.moos", "/dev/null", 1), 0);
    ck_assert_int_eq(kelp_launch_start(&p.kids[1], "30", "/dev/null", 1), 0); /* sleep 30 b: bad operand, exits 1 */
    int running = 2;
    for (int i = 0; i < 200 && running > 0; i++) {
        running = kelp_launch_reap(&p, 2, NULL, NULL);
        usleep(10000);
    }
    ck_assert_int_eq(running, 0);
    ck_assert(kelp_launch_clean(&p.kids[0]));
    ck_assert(!kelp_launch_clean(&p.kids[1]));
}
END_TEST

Suite *kelp_launch_suite(void)
{
    Suite *s = suite_create("launch");
    TCase *tc = tcase_create("edge");
    tcase_add_test(tc, launch_plan);
    tcase_add_test(tc, launch_start_reap);
    suite_add_tcase(s, tc);
    return s;
}
