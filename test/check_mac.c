/* TDMA MAC: cycle arithmetic of every type, UTC-midnight alignment, AUTO discovery/blank/expiry,
 * run-time updates (acomms.md 9 items 56-62, goby-wire.md 9). */
#include <check.h>
#include "check_diag.h"
#include <string.h>

#include <kelp/mac.h>

#define S 1.0                                   /* one second of kelp_time */
static const kelp_time DAY0 = 1704153600.0;    /* 2024-01-02 00:00:00 UTC */
#define AT(h, m, s) (DAY0 + (kelp_time)((h) * 3600 + (m) * 60 + (s)))
#define US 1e-6                                 /* one microsecond */

static kelp_mac_slot slot(int src, int dest, unsigned secs)
{
    kelp_mac_slot s;
    kelp_mac_slot_default(&s, src);
    s.dest = dest;
    s.slot_seconds = secs;
    return s;
}

static void init_fixed(kelp_mac *mac, kelp_mac_type type, int id, const kelp_mac_slot *sl, size_t n, kelp_time now)
{
    kelp_mac_cfg c;
    kelp_mac_cfg_default(&c);
    c.type = type;
    c.modem_id = id;
    c.slots = sl;
    c.nslots = n;
    ck_assert_int_eq(kelp_mac_init(mac, &c, now), KELP_OK);
}

START_TEST(alignment_to_utc_midnight)
{
    unsigned long k;
    /* cycle 20 s at 00:00:07 -> first cycle at 00:00:20 (k = 1) */
    ck_assert_double_eq(kelp_mac_aligned_start(AT(0, 0, 7), 20, &k), AT(0, 0, 20));
    ck_assert_uint_eq(k, 1);
    /* fractional seconds are dropped: 00:00:19.9 -> still 00:00:20 */
    ck_assert_double_eq(kelp_mac_aligned_start(AT(0, 0, 19) + 900000 * US, 20, &k), AT(0, 0, 20));
    /* exactly on a boundary -> the next one */
    ck_assert_double_eq(kelp_mac_aligned_start(AT(0, 0, 20), 20, &k), AT(0, 0, 40));
    ck_assert_uint_eq(k, 2);
    /* 7 s cycles do not divide the day: at 23:59:58, k = 86398/7 + 1 = 12343 -> 86401 s = 00:00:01 tomorrow */
    ck_assert_double_eq(kelp_mac_aligned_start(AT(23, 59, 58), 7, &k), AT(24, 0, 1));
    ck_assert_uint_eq(k, 12343);
    /* just after midnight the count restarts from 0 */
    ck_assert_double_eq(kelp_mac_aligned_start(AT(24, 0, 0) + 1 * US, 7, &k), AT(24, 0, 7));
    ck_assert_uint_eq(k, 1);
    ck_assert_double_eq(kelp_mac_aligned_start(AT(0, 0, 1), 0, &k), -1);
}
END_TEST

START_TEST(fixed_example1_single_slot)
{
    kelp_mac_slot sl = slot(1, 2, 10);
    kelp_mac m1, m2;
    init_fixed(&m1, KELP_MAC_FIXED_DECENTRALIZED, 1, &sl, 1, AT(12, 0, 3));
    init_fixed(&m2, KELP_MAC_FIXED_DECENTRALIZED, 2, &sl, 1, AT(12, 0, 3));
    ck_assert_uint_eq(kelp_mac_cycle_length(&m1), 10);
    ck_assert_double_eq(kelp_mac_next_slot_time(&m1), AT(12, 0, 10));
    kelp_mac_action a;
    ck_assert_int_eq(kelp_mac_tick(&m1, AT(12, 0, 10) - 1 * US, &a), KELP_ERR_EMPTY);
    for (int i = 0; i < 5; i++) {
        kelp_time t = AT(12, 0, 10) + i * 10 * S;
        ck_assert_int_eq(kelp_mac_tick(&m1, t, &a), KELP_OK);
        ck_assert_int_eq(a.kind, KELP_MAC_ACT_TRANSMIT);
        ck_assert_int_eq(a.src, 1);
        ck_assert_int_eq(a.dest, 2);
        ck_assert_uint_eq(a.rate, 0);
        ck_assert_double_eq(a.slot_start, t);
        ck_assert_int_eq(kelp_mac_tick(&m2, t, &a), KELP_OK);   /* the slot passes at node 2 ... */
        ck_assert_int_eq(a.kind, KELP_MAC_ACT_NONE);               /* ... without an action */
    }
}
END_TEST

START_TEST(fixed_example2_two_slots)
{
    kelp_mac_slot sl[2] = { slot(1, 2, 10), slot(2, 1, 10) };
    kelp_mac m1, m2;
    init_fixed(&m1, KELP_MAC_FIXED_DECENTRALIZED, 1, sl, 2, AT(12, 0, 5));
    init_fixed(&m2, KELP_MAC_FIXED_DECENTRALIZED, 2, sl, 2, AT(12, 0, 5));
    ck_assert_uint_eq(kelp_mac_cycle_length(&m1), 20);
    ck_assert_double_eq(kelp_mac_next_slot_time(&m1), AT(12, 0, 20));
    /* second by second until 12:01:10: node 1 at :20 :40 :00, node 2 at :30 :50 :10 */
    int n1 = 0, n2 = 0;
    for (kelp_time t = AT(12, 0, 5); t <= AT(12, 1, 10); t += S) {
        kelp_mac_action a;
        if (kelp_mac_tick(&m1, t, &a) == KELP_OK && a.kind == KELP_MAC_ACT_TRANSMIT) {
            ck_assert_int_eq((long)(t - DAY0) % 20, 0);
            ck_assert_int_eq(a.dest, 2);
            n1++;
        }
        if (kelp_mac_tick(&m2, t, &a) == KELP_OK && a.kind == KELP_MAC_ACT_TRANSMIT) {
            ck_assert_int_eq((long)(t - DAY0) % 20, 10);
            ck_assert_int_eq(a.src, 2);
            ck_assert_int_eq(a.dest, 1);
            n2++;
        }
    }
    ck_assert_int_eq(n1, 3);
    ck_assert_int_eq(n2, 3);
}
END_TEST

START_TEST(polled_master_initiates_every_slot)
{
    kelp_mac_slot sl[3] = { slot(1, 2, 10), slot(2, 1, 15), slot(0, -1, 5) };
    sl[1].rate = 2;
    kelp_mac m;
    init_fixed(&m, KELP_MAC_POLLED, 1, sl, 3, AT(12, 0, 0));
    ck_assert_uint_eq(kelp_mac_cycle_length(&m), 30);
    ck_assert_double_eq(kelp_mac_next_slot_time(&m), AT(12, 0, 30));
    kelp_mac_action a;
    ck_assert_int_eq(kelp_mac_tick(&m, AT(12, 0, 30), &a), KELP_OK);
    ck_assert_int_eq(a.kind, KELP_MAC_ACT_TRANSMIT);
    ck_assert_int_eq(a.src, 1);
    ck_assert_int_eq(kelp_mac_tick(&m, AT(12, 0, 40), &a), KELP_OK);
    ck_assert_int_eq(a.kind, KELP_MAC_ACT_TRANSMIT);      /* third-party slot: we poll node 2 */
    ck_assert_int_eq(a.src, 2);
    ck_assert_int_eq(a.dest, 1);
    ck_assert_uint_eq(a.rate, 2);
    ck_assert_int_eq(kelp_mac_tick(&m, AT(12, 0, 55), &a), KELP_OK);
    ck_assert_int_eq(a.kind, KELP_MAC_ACT_NONE);          /* src 0: quiet */
    ck_assert_double_eq(kelp_mac_next_slot_time(&m), AT(12, 1, 0));
}
END_TEST

START_TEST(ping_and_lbl_slots_and_late_ticks)
{
    kelp_mac_slot sl[2] = { slot(1, 3, 10), slot(1, 0, 10) };
    sl[0].type = KELP_SLOT_PING;
    sl[1].type = KELP_SLOT_REMUS_LBL;
    kelp_mac m;
    init_fixed(&m, KELP_MAC_FIXED_DECENTRALIZED, 1, sl, 2, AT(1, 0, 0));
    kelp_mac_action a;
    ck_assert_int_eq(kelp_mac_tick(&m, AT(1, 0, 20), &a), KELP_OK);
    ck_assert_int_eq(a.kind, KELP_MAC_ACT_RANGING);
    ck_assert_int_eq(a.ranging, KELP_RANGING_TWO_WAY_PING);
    ck_assert_int_eq(a.dest, 3);
    ck_assert_double_eq(a.slot_start, AT(1, 0, 20));
    /* late within its slot (9.5 s of 10): the slot still starts */
    ck_assert_int_eq(kelp_mac_tick(&m, AT(1, 0, 39) + 0.5 * S, &a), KELP_OK);
    ck_assert_int_eq(a.ranging, KELP_RANGING_REMUS_LBL);
    ck_assert_double_eq(a.slot_start, AT(1, 0, 30));
    /* 45 s late (the clock stepped): the missed slots are not replayed; the cycle re-aligns to
     * the next 20 s boundary after 01:01:25 and its first slot starts there */
    kelp_time late = AT(1, 0, 40) + 45 * S;
    ck_assert_int_eq(kelp_mac_tick(&m, late, &a), KELP_ERR_EMPTY);
    ck_assert_int_eq(a.kind, KELP_MAC_ACT_NONE);
    ck_assert_uint_eq(m.clock_steps, 1);
    ck_assert_double_eq(kelp_mac_next_slot_time(&m), AT(1, 1, 40));
    ck_assert_int_eq(kelp_mac_tick(&m, late, &a), KELP_ERR_EMPTY);
    ck_assert_int_eq(kelp_mac_tick(&m, AT(1, 1, 40), &a), KELP_OK);
    ck_assert_int_eq(a.ranging, KELP_RANGING_TWO_WAY_PING);
    ck_assert_double_eq(a.slot_start, AT(1, 1, 40));
    ck_assert_double_eq(kelp_mac_next_slot_time(&m), AT(1, 1, 50));
}
END_TEST

START_TEST(mac_update_add_remove_replace)
{
    kelp_mac_slot sl[2] = { slot(1, 2, 10), slot(2, 1, 10) };
    kelp_mac m1, m2;
    init_fixed(&m1, KELP_MAC_FIXED_DECENTRALIZED, 1, sl, 2, AT(12, 0, 5));
    init_fixed(&m2, KELP_MAC_FIXED_DECENTRALIZED, 2, sl, 2, AT(12, 0, 5));
    /* the manual's example: dest 1, ADD, slot {src 1 dest 3 rate 0 slot_seconds 15 SLOT_DATA} */
    kelp_mac_slot add = slot(1, 3, 15);
    ck_assert_int_eq(kelp_mac_update(&m1, 1, KELP_MAC_UPDATE_ADD, &add, 1, AT(12, 0, 33)), KELP_OK);
    ck_assert_int_eq(kelp_mac_update(&m2, 1, KELP_MAC_UPDATE_ADD, &add, 1, AT(12, 0, 33)), KELP_ERR_NOTFOUND);
    ck_assert_uint_eq(m1.n, 3);
    ck_assert_int_eq(m1.slot[2].dest, 3);                        /* appended at the end */
    ck_assert_uint_eq(kelp_mac_cycle_length(&m1), 35);
    ck_assert_uint_eq(m2.n, 2);
    /* re-aligned: 43233 / 35 = 1235 -> 1236 * 35 = 43260 = 12:01:00 */
    ck_assert_double_eq(kelp_mac_next_slot_time(&m1), AT(12, 1, 0));
    kelp_mac_action a;
    ck_assert_int_eq(kelp_mac_tick(&m1, AT(12, 1, 0), &a), KELP_OK);
    ck_assert_int_eq(a.dest, 2);
    ck_assert_int_eq(kelp_mac_tick(&m1, AT(12, 1, 10), &a), KELP_OK);
    ck_assert_int_eq(a.kind, KELP_MAC_ACT_NONE);
    ck_assert_int_eq(kelp_mac_tick(&m1, AT(12, 1, 20), &a), KELP_OK);
    ck_assert_int_eq(a.dest, 3);
    ck_assert_double_eq(kelp_mac_next_slot_time(&m1), AT(12, 1, 35));
    /* REMOVE matches on (src, dest, rate, type, slot_seconds) */
    kelp_mac_slot rm = slot(1, 3, 16);
    ck_assert_int_eq(kelp_mac_update(&m1, 1, KELP_MAC_UPDATE_REMOVE, &rm, 1, AT(12, 2, 0)), KELP_ERR_NOTFOUND);
    rm.slot_seconds = 15;
    ck_assert_int_eq(kelp_mac_update(&m1, 1, KELP_MAC_UPDATE_REMOVE, &rm, 1, AT(12, 2, 0)), KELP_OK);
    ck_assert_uint_eq(kelp_mac_cycle_length(&m1), 20);
    /* REPLACE: the new cycle only */
    kelp_mac_slot rep = slot(1, 4, 30);
    ck_assert_int_eq(kelp_mac_update(&m1, 1, KELP_MAC_UPDATE_REPLACE, &rep, 1, AT(12, 2, 1)), KELP_OK);
    ck_assert_uint_eq(m1.n, 1);
    ck_assert_double_eq(kelp_mac_next_slot_time(&m1), AT(12, 2, 30));
    /* removing the last slot stops the MAC instead of dividing by zero */
    ck_assert_int_eq(kelp_mac_remove_slot(&m1, &rep, AT(12, 2, 2)), KELP_OK);
    ck_assert_double_eq(kelp_mac_next_slot_time(&m1), -1);
    ck_assert_int_eq(kelp_mac_tick(&m1, AT(13, 0, 0), &a), KELP_ERR_EMPTY);
}
END_TEST

static kelp_mac_action tick_at(kelp_mac *m, kelp_time t)
{
    kelp_mac_action a;
    ck_assert_double_eq(kelp_mac_next_slot_time(m), t);
    ck_assert_int_eq(kelp_mac_tick(m, t, &a), KELP_OK);
    return a;
}

START_TEST(auto_decentralized_blank_discovery_expiry)
{
    kelp_mac_cfg c;
    kelp_mac_cfg_default(&c);
    c.type = KELP_MAC_AUTO_DECENTRALIZED;
    c.modem_id = 3;
    c.expire_cycles = 2;
    kelp_mac m;
    ck_assert_int_eq(kelp_mac_init(&m, &c, AT(12, 0, 0)), KELP_OK);
    /* initial state at modem 3: {blank, 3}, 30 s cycle with the default 15 s slots */
    ck_assert_uint_eq(m.n, 2);
    ck_assert_uint_eq(kelp_mac_cycle_length(&m), 30);
    ck_assert_uint_eq(m.cycles_since_day_start, 1441);   /* 43200 / 30 + 1 */
    /* k % 5 = 1 != 3 % 5: blank_pos = 30 - 0 - 1 = 29 -> 29 mod 2 = 1: blank last */
    ck_assert_int_eq(m.slot[0].src, 3);
    ck_assert_int_eq(m.slot[1].src, 0);
    kelp_mac_action a = tick_at(&m, AT(12, 0, 30));
    ck_assert_int_eq(a.kind, KELP_MAC_ACT_TRANSMIT);
    ck_assert_int_eq(a.src, 3);
    ck_assert_int_eq(a.dest, -1);
    ck_assert_int_eq(tick_at(&m, AT(12, 0, 45)).kind, KELP_MAC_ACT_NONE);       /* blank */
    ck_assert_int_eq(tick_at(&m, AT(12, 1, 0)).kind, KELP_MAC_ACT_TRANSMIT);    /* k 1442 */
    ck_assert_int_eq(tick_at(&m, AT(12, 1, 15)).kind, KELP_MAC_ACT_NONE);
    /* k 1443: 1443 % 5 == 3 == sum % 5 -> blank_pos 28 -> position 0: blank first */
    ck_assert_int_eq(tick_at(&m, AT(12, 1, 30)).kind, KELP_MAC_ACT_NONE);
    ck_assert_int_eq(tick_at(&m, AT(12, 1, 45)).kind, KELP_MAC_ACT_TRANSMIT);
    ck_assert_int_eq(tick_at(&m, AT(12, 2, 0)).kind, KELP_MAC_ACT_TRANSMIT);    /* k 1444: own first again */
    /* discovery of id 1 at 12:02:20: {0,1,3}, 45 s, k = 43340/45 + 1 = 964, start 43380 = 12:03:00;
     * sum 4, 964 % 5 == 4 -> blank_pos = 45 - 1 - 1 = 43 -> 43 mod 3 = 1: [1, blank, 3] */
    kelp_mac_heard(&m, 1, AT(12, 2, 20));
    ck_assert_uint_eq(m.n, 3);
    ck_assert_uint_eq(kelp_mac_cycle_length(&m), 45);
    ck_assert_uint_eq(m.cycles_since_day_start, 964);
    ck_assert_int_eq(m.slot[0].src, 1);
    ck_assert_int_eq(m.slot[1].src, 0);
    ck_assert_int_eq(m.slot[2].src, 3);
    ck_assert_int_eq(tick_at(&m, AT(12, 3, 0)).kind, KELP_MAC_ACT_NONE);        /* node 1's slot */
    ck_assert_int_eq(tick_at(&m, AT(12, 3, 15)).kind, KELP_MAC_ACT_NONE);       /* blank */
    ck_assert_int_eq(tick_at(&m, AT(12, 3, 30)).kind, KELP_MAC_ACT_TRANSMIT);   /* own */
    /* k 965: 965 % 5 = 0 != 4 -> 44 mod 3 = 2: [1, 3, blank] */
    ck_assert_int_eq(m.slot[2].src, 0);
    ck_assert_int_eq(tick_at(&m, AT(12, 3, 45)).kind, KELP_MAC_ACT_NONE);
    /* 12:04:00: own slot; afterwards id 1 (last heard 12:02:20 < 12:04:00 - 45*2 s) expires: the
     * cycle is re-aligned (30 s -> 12:04:30) and Goby still adds one slot length: 12:04:45 */
    ck_assert_int_eq(tick_at(&m, AT(12, 4, 0)).kind, KELP_MAC_ACT_TRANSMIT);
    ck_assert_uint_eq(m.n, 2);
    ck_assert_double_eq(kelp_mac_next_slot_time(&m), AT(12, 4, 45));
    /* hearing a known id only refreshes it; MAC updates do not apply to AUTO */
    kelp_mac_heard(&m, 3, AT(12, 4, 1));
    ck_assert_uint_eq(m.n, 2);
    kelp_mac_slot s = slot(3, 1, 10);
    ck_assert_int_eq(kelp_mac_update(&m, 3, KELP_MAC_UPDATE_ADD, &s, 1, AT(12, 4, 1)), KELP_ERR_STATE);
}
END_TEST

START_TEST(auto_keeps_heard_ids_alive)
{
    kelp_mac_cfg c;
    kelp_mac_cfg_default(&c);
    c.type = KELP_MAC_AUTO_DECENTRALIZED;
    c.modem_id = 2;
    kelp_mac m;
    ck_assert_int_eq(kelp_mac_init(&m, &c, AT(6, 0, 0)), KELP_OK);
    kelp_mac_heard(&m, 5, AT(6, 0, 1));
    kelp_mac_heard(&m, 4, AT(6, 0, 2));
    ck_assert_uint_eq(m.n, 4);
    /* default expire_cycles 30: heard every cycle, nobody expires over 30 minutes */
    for (kelp_time t = AT(6, 0, 3); t < AT(6, 30, 0); t += S) {
        kelp_mac_action a;
        if ((long long)t % 60 == 0) { kelp_mac_heard(&m, 5, t); kelp_mac_heard(&m, 4, t); }
        if (kelp_mac_tick(&m, t, &a) == KELP_OK) ck_assert_int_ne(a.kind, KELP_MAC_ACT_RANGING);
    }
    ck_assert_uint_eq(m.n, 4);
    /* node 4 falls silent: gone after 60 s * 30 cycles */
    kelp_time t = AT(6, 30, 0);
    for (; t < AT(7, 2, 0); t += S) {
        kelp_mac_action a;
        if ((long long)t % 60 == 0) kelp_mac_heard(&m, 5, t);
        if (kelp_mac_tick(&m, t, &a) == KELP_OK) ck_assert_int_ne(a.kind, KELP_MAC_ACT_RANGING);
    }
    ck_assert_uint_eq(m.n, 3);
    ck_assert_int_eq(m.slot[0].src == 4 || m.slot[1].src == 4 || m.slot[2].src == 4, 0);
}
END_TEST

START_TEST(bad_configuration)
{
    kelp_mac_cfg c;
    kelp_mac_cfg_default(&c);
    kelp_mac m;
    ck_assert_int_eq(c.slot_seconds, 15);
    ck_assert_int_eq(c.expire_cycles, 30);
    c.type = KELP_MAC_AUTO_DECENTRALIZED;
    c.modem_id = 1;
    c.slot_seconds = 0;
    ck_assert_int_eq(kelp_mac_init(&m, &c, AT(0, 0, 0)), KELP_ERR_ARG);
    ck_diag(&m.diag, KELP_ERR_ARG, "mac: slot_seconds must be > 0");
    kelp_mac_cfg_default(&c);
    ck_assert_int_eq(kelp_mac_init(&m, &c, AT(0, 0, 0)), KELP_OK);  /* MAC_NONE: never fires */
    kelp_mac_action a;
    ck_assert_int_eq(kelp_mac_tick(&m, AT(1, 0, 0), &a), KELP_ERR_EMPTY);
    kelp_mac_slot sl[KELP_MAX_MAC_SLOTS + 1];
    for (int i = 0; i <= KELP_MAX_MAC_SLOTS; i++) sl[i] = slot(1, 2, 1);
    c.type = KELP_MAC_FIXED_DECENTRALIZED;
    c.slots = sl;
    c.nslots = KELP_MAX_MAC_SLOTS + 1;
    ck_assert_int_eq(kelp_mac_init(&m, &c, AT(0, 0, 0)), KELP_ERR_NOSPACE);
    ck_diag(&m.diag, KELP_ERR_NOSPACE, "mac: too many slots (KELP_MAX_MAC_SLOTS)");
}
END_TEST

Suite *kelp_mac_suite(void)
{
    Suite *s = suite_create("mac");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, alignment_to_utc_midnight);
    tcase_add_test(tc, fixed_example1_single_slot);
    tcase_add_test(tc, fixed_example2_two_slots);
    tcase_add_test(tc, polled_master_initiates_every_slot);
    tcase_add_test(tc, ping_and_lbl_slots_and_late_ticks);
    tcase_add_test(tc, mac_update_add_remove_replace);
    tcase_add_test(tc, auto_decentralized_blank_discovery_expiry);
    tcase_add_test(tc, auto_keeps_heard_ids_alive);
    tcase_add_test(tc, bad_configuration);
    suite_add_tcase(s, tc);
    return s;
}
