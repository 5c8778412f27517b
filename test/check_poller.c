/* pAcommsPoller's poll list (src/modemsim/poller.c): POLLER_COMMAND applied to the cycle. */
#include <check.h>
#include "check_diag.h"
#include <string.h>
#include <kelp/poller.h>
#include <kelp/modemsim.h>

START_TEST(poller_commands)
{
    kelp_poller_list l;
    memset(&l, 0, sizeof l);
    l.default_seconds = 15;
    kelp_diag why = {0};
    ck_assert_int_eq(kelp_poller_add(&l, "src=2,dest=1", &why), 0);
    ck_assert_int_eq(kelp_poller_command(&l, "add src=3,dest=1,rate=1,slot_seconds=20", &why), 1);
    ck_assert_uint_eq(l.n, 2);
    ck_assert_uint_eq(kelp_poller_cycle_seconds(&l), 35);
    ck_assert_int_eq(kelp_poller_command(&l, "remove src=2,dest=1", &why), 1);
    ck_assert_uint_eq(l.n, 1);
    ck_assert_int_eq(l.slot[0].src, 3);
    ck_assert_int_eq(kelp_poller_command(&l, "remove src=9,dest=1", &why), KELP_ERR_NOTFOUND);
    ck_diag(&why, KELP_ERR_NOTFOUND, "no such slot");
    kelp_diag_clear(&why);
    /* replace is all or nothing */
    ck_assert_int_lt(kelp_poller_command(&l, "replace src=4,dest=1;src=99,dest=1", &why), 0);
    ck_assert_uint_eq(l.n, 1);
    ck_assert_int_eq(l.slot[0].src, 3);
    ck_assert_int_eq(kelp_poller_command(&l, "replace src=4,dest=1;src=5,dest=1;", &why), 1);
    ck_assert_uint_eq(l.n, 2);
    ck_assert_int_eq(l.slot[1].src, 5);
    ck_assert_int_eq(kelp_poller_command(&l, "  pause", &why), 1);
    ck_assert(l.paused);
    ck_assert_int_eq(kelp_poller_command(&l, "resume", &why), 1);
    ck_assert(!l.paused);
    ck_assert_int_eq(kelp_poller_command(&l, "publish", &why), 1);
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_poller_command(&l, "frobnicate", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(why.code, KELP_ERR_PARSE);
    ck_diag_has(&why, "unknown command");
    ck_assert_int_lt(kelp_poller_command(&l, "add", &why), 0);
    ck_assert_int_eq(kelp_poller_command(&l, "clear", &why), 1);
    ck_assert_uint_eq(l.n, 0);
    for (int i = 0; i < KELP_MAX_MSIM_POLL_SLOTS; i++) ck_assert_int_eq(kelp_poller_add(&l, "src=1", &why), 0);
    ck_assert_int_lt(kelp_poller_add(&l, "src=1", &why), 0);
}
END_TEST

Suite *kelp_poller_suite(void)
{
    Suite *s = suite_create("poller");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, poller_commands);
    suite_add_tcase(s, tc);
    return s;
}
