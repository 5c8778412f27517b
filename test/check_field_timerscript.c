/* uTimerScript's state machine (src/field/timerscript.c): events, random times and values,
 * macros, conditions, pause / forward / reset, resets, delays, time warp and the status. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/timerscript.h>

#define REC_MAX 8192

typedef struct rec {
    int n;
    char var[REC_MAX][32];
    char val[REC_MAX][300];
    bool str[REC_MAX];
    double d[REC_MAX];
    int warns;
} rec;

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    if (r->n >= REC_MAX) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    r->str[r->n] = is_string;
    if (is_string) snprintf(r->val[r->n], sizeof r->val[0], "%s", sval);
    else snprintf(r->val[r->n], sizeof r->val[0], "%.10g", dval);
    r->d[r->n] = dval;
    r->n++;
}

static void wrn(void *ctx, const char *msg)
{
    (void)msg;
    ((rec *)ctx)->warns++;
}

/* postings of var, excluding the status */
static int count(const rec *r, const char *var)
{
    int k = 0;
    for (int i = 0; i < r->n; i++) k += strcmp(r->var[i], var) == 0;
    return k;
}

static const char *last(const rec *r, const char *var)
{
    for (int i = r->n; i-- > 0;)
        if (!strcmp(r->var[i], var)) return r->val[i];
    return NULL;
}

static int nth(const rec *r, const char *var, int k)
{
    for (int i = 0; i < r->n; i++)
        if (!strcmp(r->var[i], var) && k-- == 0) return i;
    return -1;
}

static kelp_timerscript ts; /* large: not on the stack */
static kelp_timerscript_cfg cfg;
static rec R;
static kelp_field_sink sink = { &R, pub, wrn };

static void setup_cfg(const char *const *lines)
{
    memset(&R, 0, sizeof R);
    kelp_timerscript_cfg_default(&cfg, "uTimerScript", "archie");
    for (int i = 0; lines[i]; i += 2) {
        kelp_diag why = { 0 };
        int rc = kelp_timerscript_cfg_set(&cfg, lines[i], lines[i + 1], &why);
        ck_assert_msg(rc == 1, "%s = %s: %d %s", lines[i], lines[i + 1], rc, kelp_diag_text(&why));
    }
    ck_assert_int_eq(kelp_timerscript_init(&ts, &cfg, 42), 0);
    kelp_timerscript_set_db_start(&ts, 1000);
}

/* iterate every 0.25 s from t0 to t1 */
static int run(double t0, double t1)
{
    int n = 0;
    for (double t = t0; t <= t1 + 1e-9; t += 0.25) n += kelp_timerscript_iterate(&ts, t, &sink);
    return n;
}

/* time of the first posting of var (iterating every 0.25 s from t0), or -1 */
static double first_post(const char *var, double t0, double t1)
{
    for (double t = t0; t <= t1 + 1e-9; t += 0.25) {
        int before = count(&R, var);
        (void)kelp_timerscript_iterate(&ts, t, &sink);
        if (count(&R, var) > before) return t;
    }
    return -1;
}

START_TEST(ts_fixed_times_and_types)
{
    setup_cfg((const char *const[]){ "event", "var=A, val=hello, time=2", "event", "var=B, val=3.5, time=4",
                                     "event", "var=C, val=\"7\", time=4", NULL });
    ck_assert(first_post("A", 1000, 1010) == 1002.0);
    ck_assert_int_eq(count(&R, "B"), 0);
    run(1002.25, 1004);
    ck_assert_int_eq(count(&R, "B"), 1);
    int b = nth(&R, "B", 0), c = nth(&R, "C", 0), a = nth(&R, "A", 0);
    ck_assert(!R.str[b] && R.d[b] == 3.5);
    ck_assert(R.str[c]);
    ck_assert_str_eq(R.val[c], "7"); /* quoted: a string */
    ck_assert(R.str[a]);
    ck_assert_str_eq(R.val[a], "hello");
    run(1004.25, 1030); /* no reset: nothing more */
    ck_assert_int_eq(count(&R, "A") + count(&R, "B") + count(&R, "C"), 3);
}
END_TEST

START_TEST(ts_random_window_and_shuffle)
{
    /* the seed's range request: once every 25..35 s, repeating */
    setup_cfg((const char *const[]){ "event", "var=SBR_RANGE_REQUEST, val=\"name=archie\", time=25:35", "reset_time",
                                     "all-posted", NULL });
    /* the drawn times differ from pass to pass (shuffle) and stay in the window */
    double lo = 1e9, hi = 0, prev = 1000;
    for (int i = 0; i < 40; i++) {
        double t = first_post("SBR_RANGE_REQUEST", prev + 0.25, prev + 100);
        ck_assert(t > 0);
        double gap = t - prev;
        if (i > 0) {
            if (gap < lo) lo = gap;
            if (gap > hi) hi = gap;
        }
        prev = t;
    }
    ck_assert_str_eq(last(&R, "SBR_RANGE_REQUEST"), "name=archie");
    ck_assert(R.str[nth(&R, "SBR_RANGE_REQUEST", 0)]);
    ck_assert_int_eq(count(&R, "SBR_RANGE_REQUEST"), 40);
    /* a reset takes effect at the next iteration (0.25 s later) */
    ck_assert_msg(lo >= 25 && hi <= 35.75 && hi - lo > 3, "gaps %g..%g", lo, hi);
}
END_TEST

START_TEST(ts_no_shuffle_keeps_times)
{
    setup_cfg((const char *const[]){ "event", "var=X, val=1, time=10:20", "reset_time", "all-posted", "shuffle", "false",
                                     NULL });
    double t1 = first_post("X", 1000, 1030);
    double t2 = first_post("X", t1 + 0.25, t1 + 40);
    double t3 = first_post("X", t2 + 0.25, t2 + 40);
    ck_assert(t1 > 1000 && t2 > t1 && t3 > t2);
    ck_assert_double_eq_tol(t3 - t2, t2 - t1, 1e-9); /* the same draw every pass */
    ck_assert_double_eq_tol(t3 - t2 - 0.25, t1 - 1000, 0.25 + 1e-9);
}
END_TEST

START_TEST(ts_rand_vars)
{
    setup_cfg((const char *const[]){ "rand_var", "varname=ANG, min=0, max=359, key=at_reset", "rand_var",
                                     "varname=P, min=10, max=20, key=at_post", "randvar",
                                     "varname=S, min=100, max=200, key=at_start, snap=10", "event",
                                     "var=V, val=a=$[ANG]|p=$(P)|s=$[S], time=1", "event", "var=W, val=$[ANG]/$[P]/$[S], time=2",
                                     "reset_time", "all-posted", NULL });
    run(1000, 1100);
    int n = count(&R, "W");
    ck_assert_int_ge(n, 20);
    double s0 = -1;
    int ang_same_in_pass = 0, p_differs = 0, ang_changes = 0;
    double prev_ang = -1;
    for (int k = 0; k < n; k++) {
        double ang, p, s, ang2, p2, s2;
        ck_assert_int_eq(sscanf(R.val[nth(&R, "V", k)], "a=%lf|p=%lf|s=%lf", &ang, &p, &s), 3);
        ck_assert_int_eq(sscanf(R.val[nth(&R, "W", k)], "%lf/%lf/%lf", &ang2, &p2, &s2), 3);
        ck_assert(ang >= 0 && ang <= 359 && p >= 10 && p <= 20 && s >= 100 && s <= 200);
        ck_assert_double_eq(s, (double)(long)(s / 10) * 10); /* snapped to 10 */
        if (s0 < 0) s0 = s;
        ck_assert_double_eq(s, s0);  /* at_start: drawn once */
        ck_assert_double_eq(s2, s0);
        ang_same_in_pass += ang == ang2; /* at_reset: one value per pass */
        p_differs += p != p2;           /* at_post: a value per posting */
        if (prev_ang >= 0 && ang != prev_ang) ang_changes++;
        prev_ang = ang;
    }
    ck_assert_int_eq(ang_same_in_pass, n);
    ck_assert_int_ge(p_differs, n - 3);
    ck_assert_int_ge(ang_changes, n - 3);
}
END_TEST

START_TEST(ts_gaussian_rand_var)
{
    setup_cfg((const char *const[]){ "rand_var", "varname=G, type=gaussian, mu=50, sigma=5, min=0, max=100, key=at_post",
                                     "event", "var=G, val=$[G], time=0", "reset_time", "all-posted", NULL });
    run(1000, 1000 + 1000);
    int n = count(&R, "G");
    ck_assert_int_gt(n, 1000);
    double sum = 0, sq = 0;
    for (int i = 0; i < R.n; i++)
        if (!strcmp(R.var[i], "G")) {
            ck_assert(!R.str[i]); /* a number: posted as a double */
            sum += R.d[i], sq += R.d[i] * R.d[i];
        }
    double mean = sum / n, sd = sqrt(sq / n - mean * mean);
    ck_assert_msg(fabs(mean - 50) < 1 && fabs(sd - 5) < 1, "mean %g sd %g", mean, sd);
}
END_TEST

START_TEST(ts_macros)
{
    setup_cfg((const char *const[]){ "event", "var=DB, val=$[DBTIME], time=1", "event", "var=UTC, val=$(UTCTIME), time=1",
                                     "event", "var=T, val=t=$[DBTIME];u=$[UTC], time=1", "event",
                                     "var=CNT, val=$[COUNT], time=2", "event", "var=TC, val=n=$[TCOUNT], time=2", "event",
                                     "var=ID, val=idx=$[IDX], time=3, amt=2", "event", "var=VN, val=$[VNAME]_$(VNAME), time=3",
                                     "event", "var=NX, val=x=$[NAV_X];y=$(NAV_Y), time=3", "event", "var=DIG, val=$(5), time=3",
                                     "event", "var=M, val={2+3}, time=3", "event", "var=M2, val=r={{1+2}*3}|{7/2}|{-4-1}, time=3",
                                     "event", "var=M3, val=\"{2*4}\", time=3", "event", "var=UNK, val=$[NOPE] {a+b}, time=3",
                                     NULL });
    bool navx = false;
    for (unsigned i = 0; kelp_timerscript_subscription(&ts, i); i++) navx = navx || !strcmp(kelp_timerscript_subscription(&ts, i), "NAV_X");
    ck_assert(navx); /* registered because a value uses it */
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "NAV_X", false, "", 12.345, 1000, &sink), 1);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "NAV_Y", false, "", -7, 1000, &sink), 1);
    run(1000, 1005);
    int db = nth(&R, "DB", 0), utc = nth(&R, "UTC", 0);
    ck_assert(!R.str[db] && R.d[db] == 1.0); /* a lone time macro posts a number */
    ck_assert(!R.str[utc] && R.d[utc] == 1001.0);
    ck_assert_str_eq(last(&R, "T"), "t=1.00;u=1001.00");
    ck_assert_str_eq(R.val[nth(&R, "CNT", 0)], "3"); /* 3 posted before it in this pass */
    ck_assert_str_eq(last(&R, "TC"), "n=4");
    ck_assert_str_eq(R.val[nth(&R, "ID", 0)], "idx=005");
    ck_assert_str_eq(R.val[nth(&R, "ID", 1)], "idx=006");
    ck_assert_str_eq(last(&R, "VN"), "archie_archie");
    ck_assert_str_eq(last(&R, "NX"), "x=12.35;y=-7.00");
    const char *dig = last(&R, "DIG");
    ck_assert(strlen(dig) >= 1 && strlen(dig) <= 5 && strspn(dig, "0123456789") == strlen(dig));
    int m = nth(&R, "M", 0);
    ck_assert(!R.str[m] && R.d[m] == 5);
    ck_assert_str_eq(last(&R, "M2"), "r=9|3.5|-5");
    ck_assert_str_eq(last(&R, "M3"), "8"); /* quoted: stays a string */
    ck_assert(R.str[nth(&R, "M3", 0)]);
    ck_assert_str_eq(last(&R, "UNK"), "$[NOPE] {a+b}");
    /* a lone time macro posts the time itself (MOOS-IvP Notify(var, db_uptime)), not its 2-decimal text */
    char buf[64];
    double d = 0;
    ck_assert_int_eq(kelp_timerscript_expand(&ts, "$[DBTIME]", 1001.123456, buf, sizeof buf, &d), 1);
    ck_assert_msg(fabs(d - 1.123456) < 1e-9, "DBTIME %.9f", d);
    ck_assert_int_eq(kelp_timerscript_expand(&ts, "$(UTC)", 1001.123456, buf, sizeof buf, &d), 1);
    ck_assert_msg(d == 1001.123456, "UTC %.9f", d);
    ck_assert_int_eq(kelp_timerscript_expand(&ts, "t=$[UTCTIME]", 1001.123456, buf, sizeof buf, &d), 0);
    ck_assert_str_eq(buf, "t=1001.12"); /* inside text: 2 decimals */
}
END_TEST

START_TEST(ts_condition)
{
    setup_cfg((const char *const[]){ "event", "var=REQ, val=go, time=5", "condition", "NAV_SPEED > 0", NULL });
    bool sub = false;
    for (unsigned i = 0; kelp_timerscript_subscription(&ts, i); i++) sub = sub || !strcmp(kelp_timerscript_subscription(&ts, i), "NAV_SPEED");
    ck_assert(sub);
    run(1000, 1020);
    ck_assert_int_eq(count(&R, "REQ"), 0);
    ck_assert(strstr(last(&R, "UTS_STATUS"), "conditions_ok=false"));
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "NAV_SPEED", false, "", 1.5, 1020, &sink), 1);
    /* time before the condition held does not count */
    ck_assert(first_post("REQ", 1020.25, 1040) == 1025.0);
    ck_assert(strstr(last(&R, "UTS_STATUS"), "conditions_ok=true"));
}
END_TEST

START_TEST(ts_pause_and_commands)
{
    setup_cfg((const char *const[]){ "event", "var=E1, val=1, time=10", "event", "var=E2, val=2, time=100", "event",
                                     "var=E3, val=3, time=200", "paused", "true", NULL });
    run(1000, 1020);
    ck_assert_int_eq(count(&R, "E1"), 0);
    ck_assert(strstr(last(&R, "UTS_STATUS"), "paused=true"));
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "UTS_PAUSE", true, "false", 0, 1020, &sink), 1);
    ck_assert(first_post("E1", 1020.25, 1040) == 1030.0);
    ck_assert(strstr(last(&R, "UTS_STATUS"), "paused=false"));
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "UTS_PAUSE", true, "toggle", 0, 1030, &sink), 1);
    run(1030.25, 1200);
    ck_assert_int_eq(count(&R, "E2"), 0);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "UTS_PAUSE", true, "TOGGLE", 0, 1200, &sink), 1);
    ck_assert_int_lt(kelp_timerscript_mail(&ts, "UTS_PAUSE", true, "maybe", 0, 1200, &sink), 0);
    /* forward 80 s: E2 (script 100) is due at script 20 after the forward */
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "UTS_FORWARD", false, "", 80, 1200, &sink), 1);
    double t2 = first_post("E2", 1200.25, 1300);
    ck_assert_msg(t2 >= 1209.75 && t2 <= 1210.25, "E2 at %g", t2);
    /* forward 0: straight to the next event */
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "UTS_FORWARD", false, "", 0, t2, &sink), 1);
    ck_assert(first_post("E3", t2 + 0.25, t2 + 1) == t2 + 0.25);
    /* reset: the script starts over */
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "UTS_RESET", true, "reset", 0, t2 + 1, &sink), 1);
    double t1b = first_post("E1", t2 + 1, t2 + 30);
    ck_assert_msg(t1b >= t2 + 11 && t1b <= t2 + 11.5, "E1 again at %g (reset at %g)", t1b, t2 + 1);
    ck_assert(strstr(last(&R, "UTS_STATUS"), "resets=1/any"));
    /* UTS_NEXT also jumps */
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "UTS_NEXT", true, "next", 0, t1b, &sink), 1);
    ck_assert(first_post("E2", t1b + 0.25, t1b + 1) == t1b + 0.25);
}
END_TEST

START_TEST(ts_reset_max_and_reset_time)
{
    setup_cfg((const char *const[]){ "event", "var=P, val=x, time=1", "reset_time", "all-posted", "reset_max", "3", NULL });
    run(1000, 1100);
    ck_assert_int_eq(count(&R, "P"), 4); /* the first pass and three resets */
    ck_assert(strstr(last(&R, "UTS_STATUS"), "resets=3/3"));
    setup_cfg((const char *const[]){ "event", "var=P, val=x, time=1", "event", "var=Q, val=y, time=30", "reset_time", "10",
                                     NULL });
    run(1000, 1100);
    ck_assert_int_eq(count(&R, "Q"), 0); /* beyond reset_time: never */
    ck_assert_int_ge(count(&R, "P"), 9);
    ck_assert_int_le(count(&R, "P"), 10);
}
END_TEST

START_TEST(ts_delays_and_warp)
{
    setup_cfg((const char *const[]){ "event", "var=P, val=x, time=4", "delay_start", "6", "delay_reset", "2",
                                     "reset_time", "all-posted", NULL });
    ck_assert(first_post("P", 1000, 1020) == 1010.0);
    double t = first_post("P", 1010.25, 1030);
    ck_assert_msg(t == 1016.25, "second pass at %g", t); /* reset at 1010.25 + 4 + 2 */
    ck_assert(strstr(last(&R, "UTS_STATUS"), "delay_start=6, delay_reset=2"));
    setup_cfg((const char *const[]){ "event", "var=P, val=x, time=40", "time_warp", "4", NULL });
    ck_assert(first_post("P", 1000, 1020) == 1010.0);
    ck_assert(strstr(last(&R, "UTS_STATUS"), "time_warp=4"));
    /* a random warp and delay are drawn in their range */
    setup_cfg((const char *const[]){ "event", "var=P, val=x, time=40", "time_warp", "2:3", "delay_start", "1:2", NULL });
    run(1000, 1000.5);
    ck_assert(ts.warp >= 2 && ts.warp <= 3 && ts.delay_start >= 1 && ts.delay_start <= 2);
}
END_TEST

START_TEST(ts_status_format)
{
    setup_cfg((const char *const[]){ "event", "var=A, val=1, time=1", "event", "var=B, val=1, time=100", "script_name",
                                     "RND_TEST", "upon_awake", "reset", "shuffle", "false", "reset_max", "4", NULL });
    run(1000, 1002); /* the last status came with the posting at 1001 */
    ck_assert_str_eq(last(&R, "UTS_STATUS"), "name=RND_TEST, elapsed_time=1.00, posted=1, pending=1, paused=false, "
                                              "conditions_ok=true, time_warp=1, delay_start=0, delay_reset=0, "
                                              "shuffle=false, upon_awake=reset, resets=0/4");
    int n = count(&R, "UTS_STATUS");
    /* a command by mail (here a pause) brings no status of its own: MOOS-IvP's Iterate starts by
     * clearing the need, so only a posting, a change of conditions, a reset made by the iteration
     * or 5 s without a status make one */
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "UTS_PAUSE", true, "true", 0, 1002.1, &sink), 1);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "UTS_FORWARD", false, "", 0.5, 1002.1, &sink), 1);
    run(1002.25, 1004); /* nothing else changed: no status within 5 s */
    ck_assert_int_eq(count(&R, "UTS_STATUS"), n);
    run(1004.25, 1008);
    ck_assert_int_eq(count(&R, "UTS_STATUS"), n + 1);
    ck_assert(strstr(last(&R, "UTS_STATUS"), "paused=true"));
    setup_cfg((const char *const[]){ "event", "var=A, val=1, time=1", "status_var", "silent", NULL });
    run(1000, 1010);
    ck_assert_int_eq(count(&R, "UTS_STATUS"), 0);
    setup_cfg((const char *const[]){ "event", "var=A, val=1, time=1", "status_var", "MY_STATUS", NULL });
    run(1000, 1001);
    ck_assert_int_gt(count(&R, "MY_STATUS"), 0);
}
END_TEST

START_TEST(ts_upon_awake)
{
    /* reset: conditions failing then holding again start the script over */
    setup_cfg((const char *const[]){ "event", "var=A, val=1, time=5", "event", "var=B, val=1, time=50", "condition",
                                     "GO = true", "upon_awake", "reset", NULL });
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "GO", true, "true", 0, 1000, &sink), 1);
    ck_assert(first_post("A", 1000, 1010) == 1005.0);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "GO", true, "false", 0, 1010, &sink), 1);
    run(1010, 1020);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "GO", true, "true", 0, 1020, &sink), 1);
    double t = first_post("A", 1020, 1040);
    ck_assert_msg(t >= 1025 && t <= 1025.5, "A again at %g", t);
    ck_assert(strstr(last(&R, "UTS_STATUS"), "resets=1/any"));
    /* n/a: it resumes where it was */
    setup_cfg((const char *const[]){ "event", "var=A, val=1, time=5", "event", "var=B, val=1, time=20", "condition",
                                     "GO = true", NULL });
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "GO", true, "true", 0, 1000, &sink), 1);
    run(1000, 1010);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "GO", true, "false", 0, 1010, &sink), 1);
    run(1010.25, 1100);
    ck_assert_int_eq(count(&R, "B"), 0);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "GO", true, "TRUE", 0, 1100, &sink), 1);
    t = first_post("B", 1100.25, 1200);
    ck_assert_msg(t >= 1110 && t <= 1110.5, "B at %g", t);
    ck_assert_int_eq(count(&R, "A"), 1);
}
END_TEST

START_TEST(ts_atomic)
{
    setup_cfg((const char *const[]){ "event", "var=A, val=1, time=5", "event", "var=B, val=1, time=10", "condition",
                                     "GO = true", "script_atomic", "true", NULL });
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "GO", true, "true", 0, 1000, &sink), 1);
    ck_assert(first_post("A", 1000, 1006) == 1005.0);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "GO", true, "false", 0, 1006, &sink), 1);
    ck_assert(first_post("B", 1006.25, 1020) == 1010.0); /* a started pass completes */
    /* not atomic: B waits */
    setup_cfg((const char *const[]){ "event", "var=A, val=1, time=5", "event", "var=B, val=1, time=10", "condition",
                                     "GO = true", NULL });
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "GO", true, "true", 0, 1000, &sink), 1);
    run(1000, 1006);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "GO", true, "false", 0, 1006, &sink), 1);
    run(1006.25, 1020);
    ck_assert_int_eq(count(&R, "B"), 0);
}
END_TEST

START_TEST(ts_block_on_and_quit)
{
    setup_cfg((const char *const[]){ "event", "var=A, val=1, time=1", "event", "quit, time=2", "block_on",
                                     "pGenerateInfo, pPostValues", NULL });
    run(1000, 1010);
    ck_assert_int_eq(count(&R, "A"), 0);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "DB_CLIENTS", true, "pGenerateInfo,uTimerScript", 0, 1010, &sink), 1);
    run(1010.25, 1020);
    ck_assert_int_eq(count(&R, "A"), 0);
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "PPOSTVALUES_STATUS", true, "iter=1", 0, 1020, &sink), 1);
    ck_assert(!ts.quit);
    ck_assert(first_post("A", 1020.25, 1030) == 1021.0); /* blocked time does not count */
    ck_assert(first_post("EXITED_NORMALLY", 1021.25, 1030) == 1022.0);
    ck_assert_str_eq(last(&R, "EXITED_NORMALLY"), "uTimerScript");
    ck_assert(ts.quit);
}
END_TEST

START_TEST(ts_time_zero_db_start_and_db_uptime)
{
    setup_cfg((const char *const[]){ "event", "var=A, val=$[DBTIME], time=10", "time_zero", "db_start", NULL });
    ck_assert_int_eq(kelp_timerscript_mail(&ts, "DB_UPTIME", false, "", 7, 1500, &sink), 1); /* the DB started at 1493 */
    ck_assert(first_post("A", 1500, 1600) == 1503.0);
    ck_assert_str_eq(last(&R, "A"), "10");
}
END_TEST

static const char *const bad_cfg[][2] = {
    { "event", "val=1, time=2" },                 /* no var */
    { "event", "var=A, time=2" },                 /* no val */
    { "event", "var=A, val=1, time=-2" },
    { "event", "var=A, val=1, time=9:3" },
    { "event", "var=A, val=1, time=x" },
    { "event", "var=A, val=1, amt=0" },
    { "event", "var=A B, val=1" },
    { "event", "var=A, val=1, color=red" },
    { "event", "var=A, val=\"1, time=2" },
    { "rand_var", "varname=X, min=0, max=1" },    /* no key */
    { "rand_var", "varname=X, min=0, max=1, key=sometimes" },
    { "rand_var", "min=0, max=1, key=at_post" },
    { "rand_var", "varname=X, min=2, max=1, key=at_post" },
    { "rand_var", "varname=X, max=1, key=at_post" },
    { "rand_var", "varname=X, min=0, max=1, key=at_post, type=poisson" },
    { "rand_var", "varname=X, min=0, max=1, key=at_post, type=gaussian" },
    { "rand_var", "varname=X, min=zero, max=1, key=at_post" },
    { "time_warp", "0" },
    { "time_warp", "3:2" },
    { "delay_start", "-1" },
    { "delay_reset", "a:b" },
    { "reset_max", "-1" },
    { "reset_time", "0" },
    { "reset_time", "sometimes" },
    { "upon_awake", "later" },
    { "time_zero", "noon" },
    { "paused", "perhaps" },
    { "condition", "(A = " },
    { "forward_var", "MY VAR" },
    { "block_on", "pA, pA" },
};

START_TEST(ts_bad_config)
{
    kelp_timerscript_cfg_default(&cfg, "uTimerScript", "archie");
    kelp_diag why = { 0 };
    ck_assert_msg(kelp_timerscript_cfg_set(&cfg, bad_cfg[_i][0], bad_cfg[_i][1], &why) < 0, "%s = %s accepted", bad_cfg[_i][0],
                  bad_cfg[_i][1]);
    ck_assert_int_ne(why.code, 0);
    ck_assert_int_eq(cfg.nev, 0);
    ck_assert_int_eq(cfg.nrv, 0);
}
END_TEST

START_TEST(ts_unknown_key_and_dup_randvar)
{
    kelp_timerscript_cfg_default(&cfg, "uTimerScript", "archie");
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_timerscript_cfg_set(&cfg, "colour", "red", &why), 0);
    ck_assert_int_eq(kelp_timerscript_cfg_set(&cfg, "rand_var", "varname=X, min=0, max=1, key=at_post", &why), 1);
    ck_assert_int_lt(kelp_timerscript_cfg_set(&cfg, "rand_var", "varname=X, min=0, max=1, key=at_post", &why), 0);
    ck_assert_int_eq(kelp_timerscript_cfg_set(&cfg, "reset_max", "unlimited", &why), 1);
    ck_assert_int_eq(cfg.reset_max, -1);
    ck_assert_int_eq(kelp_timerscript_cfg_set(&cfg, "RESET_TIME", "end", &why), 1);
    ck_assert(cfg.reset_time == 0);
    /* a value with commas inside quotes, and braces */
    ck_assert_int_eq(kelp_timerscript_cfg_set(&cfg, "event", "var=M, val=\"a=1,b=2\", time=3", &why), 1);
    ck_assert_str_eq(cfg.ev[0].val, "a=1,b=2");
    ck_assert(cfg.ev[0].quoted && cfg.ev[0].tmin == 3 && cfg.ev[0].tmax == 3);
}
END_TEST

START_TEST(ts_reproducible_from_seed)
{
    const char *const lines[] = { "event", "var=R, val=$[X], time=5:50", "rand_var", "varname=X, min=0, max=1000, key=at_post",
                                  "reset_time", "all-posted", NULL };
    setup_cfg(lines);
    run(1000, 1500);
    static rec first;
    first = R;
    setup_cfg(lines);
    run(1000, 1500);
    ck_assert_int_eq(first.n, R.n);
    for (int i = 0; i < R.n; i++) ck_assert_str_eq(first.val[i], R.val[i]);
    ck_assert_int_eq(kelp_timerscript_init(&ts, &cfg, 43), 0);
    kelp_timerscript_set_db_start(&ts, 1000);
    memset(&R, 0, sizeof R);
    run(1000, 1500);
    bool differs = R.n != first.n;
    for (int i = 0; i < R.n && i < first.n && !differs; i++) differs = strcmp(first.val[i], R.val[i]) != 0;
    ck_assert(differs);
}
END_TEST

Suite *kelp_field_timerscript_suite(void)
{
    Suite *s = suite_create("field_timerscript");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, ts_fixed_times_and_types);
    tcase_add_test(tc, ts_random_window_and_shuffle);
    tcase_add_test(tc, ts_no_shuffle_keeps_times);
    tcase_add_test(tc, ts_rand_vars);
    tcase_add_test(tc, ts_gaussian_rand_var);
    tcase_add_test(tc, ts_macros);
    tcase_add_test(tc, ts_condition);
    tcase_add_test(tc, ts_pause_and_commands);
    tcase_add_test(tc, ts_reset_max_and_reset_time);
    tcase_add_test(tc, ts_delays_and_warp);
    tcase_add_test(tc, ts_status_format);
    tcase_add_test(tc, ts_upon_awake);
    tcase_add_test(tc, ts_atomic);
    tcase_add_test(tc, ts_block_on_and_quit);
    tcase_add_test(tc, ts_time_zero_db_start_and_db_uptime);
    tcase_add_loop_test(tc, ts_bad_config, 0, (int)(sizeof bad_cfg / sizeof bad_cfg[0]));
    tcase_add_test(tc, ts_unknown_key_and_dup_randvar);
    tcase_add_test(tc, ts_reproducible_from_seed);
    suite_add_tcase(s, tc);
    return s;
}
