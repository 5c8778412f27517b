/* The time step rule (docs/ARCHITECTURE.md, "When the clock steps"): every time-driven core
 * state machine driven through a clock step of +1 s, +1 h, +1 day, -1 s, -1 h, and a NaN or
 * infinite `now` (refused, then the clock goes on).  Each case checks the rule against the
 * machine's own period: outputs per period bounded after the step, work resumes within one
 * period, nothing negative in what it reports.  Loop index = the step (STEP[]), so a failure
 * names the step. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kelp/bus.h>
#include <kelp/can.h>
#include <kelp/contactmgr.h>
#include <kelp/field.h>
#include <kelp/mac.h>
#include <kelp/mmdriver.h>
#include <kelp/pathcheck.h>
#include <kelp/pid.h>
#include <kelp/queue.h>
#include <kelp/sim.h>
#include <kelp/timerscript.h>
#include <kelp/util.h>
#include <kelp/viewer.h>

static const double STEP[] = { 1.0, 3600.0, 86400.0, -1.0, -3600.0, NAN, INFINITY };
#define NSTEP ((int)(sizeof STEP / sizeof STEP[0]))
static const kelp_time T0 = 1704196800.0; /* 2024-01-02 12:00:00 UTC */

/* the clock offset a step leaves behind (a refused `now` leaves none) */
static double offset_of(double step)
{
    return isfinite(step) ? step : 0.0;
}

/* ------------------------------------------------------------------ TDMA MAC */

#define MAC_DT 0.5       /* the caller's tick */
#define MAC_BEFORE 100.0 /* seconds of normal running before the step */
#define MAC_AFTER 200.0  /* and after */

typedef struct mac_run {
    int first_after;   /* seconds from the step to the first action after it (-1: none) */
    int max_per_tick;  /* slot starts in one tick instant */
    int late;          /* actions fired outside their own slot's time */
    int actions_after;
} mac_run;

static void mac_ticks(kelp_mac *m, kelp_time now, kelp_time step_at, bool after, mac_run *r)
{
    kelp_mac_action a;
    int n = 0;
    while (n < 100 && kelp_mac_tick(m, now, &a) == KELP_OK) {
        n++;
        if (a.kind == KELP_MAC_ACT_NONE || !after) continue;
        unsigned len = m->type == KELP_MAC_AUTO_DECENTRALIZED ? m->slot_seconds : m->slot[a.slot_index].slot_seconds;
        if (now < a.slot_start || now >= a.slot_start + len) r->late++;
        if (r->first_after < 0) r->first_after = (int)ceil(now - step_at);
        r->actions_after++;
    }
    if (n > r->max_per_tick) r->max_per_tick = n;
}

/* run a MAC through the step; AUTO hears modems 2 and 3 every 10 s of its clock */
static void mac_drive(kelp_mac *m, double step, mac_run *r)
{
    memset(r, 0, sizeof *r);
    r->first_after = -1;
    kelp_time step_at = T0 + MAC_BEFORE;
    for (double t = T0; t < step_at; t += MAC_DT) {
        if (fmod(t - T0, 10.0) == 0.0) {
            kelp_mac_heard(m, 2, t);
            kelp_mac_heard(m, 3, t);
        }
        mac_ticks(m, t, step_at, false, r);
    }
    kelp_mac_action a;
    if (!isfinite(step)) {
        ck_assert_int_eq(kelp_mac_tick(m, step, &a), KELP_ERR_ARG);
        kelp_mac_heard(m, 4, step); /* ignored */
        kelp_mac_slot s;
        kelp_mac_slot_default(&s, 1);
        ck_assert_int_eq(kelp_mac_add_slot(m, &s, step), KELP_ERR_ARG);
    }
    kelp_time from = step_at + offset_of(step);
    for (double k = 0; k < MAC_AFTER; k += MAC_DT) {
        kelp_time t = from + k;
        if (fmod(k, 10.0) == 0.0) {
            kelp_mac_heard(m, 2, t);
            kelp_mac_heard(m, 3, t);
        }
        mac_ticks(m, t, from, true, r);
    }
}

static void mac_check(const kelp_mac *m, const mac_run *r, double step)
{
    unsigned longest = 0;
    for (size_t i = 0; i < m->n; i++)
        if (m->slot[i].slot_seconds > longest) longest = m->slot[i].slot_seconds;
    unsigned cycle = kelp_mac_cycle_length(m);
    ck_assert_msg(r->max_per_tick <= 1, "step %g: %d slots started in one tick", step, r->max_per_tick);
    ck_assert_msg(r->late == 0, "step %g: %d actions outside their slot", step, r->late);
    ck_assert_msg(r->first_after >= 0 && r->first_after <= (int)(cycle + longest) + 1,
                  "step %g: first action %d s after the step (cycle %u s)", step, r->first_after, cycle);
    /* at most one action per slot time of our own */
    ck_assert_int_le(r->actions_after, (int)(MAC_AFTER / 10.0) + 1);
}

START_TEST(mac_fixed_step)
{
    double step = STEP[_i];
    kelp_mac_slot sl[3];
    kelp_mac_slot_default(&sl[0], 1);
    kelp_mac_slot_default(&sl[1], 2);
    kelp_mac_slot_default(&sl[2], 1);
    for (int i = 0; i < 3; i++) sl[i].slot_seconds = 10;
    sl[2].dest = 3;
    kelp_mac_cfg cfg;
    kelp_mac_cfg_default(&cfg);
    cfg.type = KELP_MAC_FIXED_DECENTRALIZED;
    cfg.modem_id = 1;
    cfg.slots = sl;
    cfg.nslots = 3;
    static kelp_mac m;
    ck_assert_int_eq(kelp_mac_init(&m, &cfg, T0), KELP_OK);
    mac_run r;
    mac_drive(&m, step, &r);
    mac_check(&m, &r, step);
}
END_TEST

START_TEST(mac_auto_step)
{
    double step = STEP[_i];
    kelp_mac_cfg cfg;
    kelp_mac_cfg_default(&cfg);
    cfg.type = KELP_MAC_AUTO_DECENTRALIZED;
    cfg.modem_id = 1;
    cfg.slot_seconds = 10;
    static kelp_mac m;
    ck_assert_int_eq(kelp_mac_init(&m, &cfg, T0), KELP_OK);
    mac_run r;
    mac_drive(&m, step, &r);
    mac_check(&m, &r, step);
    ck_assert_uint_eq(m.n, 4); /* blank, 1, 2, 3: nobody expired for good */
}
END_TEST

/* ------------------------------------------------------------------ priority queue */

static kelp_queue tq[2];
static kelp_queue_entry tpool[8];
static kelp_queue_mgr TQ;

static kelp_acomms_msg tmsg(uint8_t x, kelp_time t)
{
    kelp_acomms_msg m;
    memset(&m, 0, sizeof m);
    kelp_queue_header h = { KELP_DCCL_CCL_ID, 10, 43200, 1, 0, false, false, 0 };
    kelp_queue_header_write(&h, m.data);
    m.data[6] = x;
    m.len = 7;
    m.dest = 0;
    m.key.type = KELP_QUEUE_DCCL;
    m.key.id = 10;
    m.has_time = true;
    m.time = t;
    return m;
}

/* blackout 10 s, ttl 100 s: m1 sent just before the step, m2 must leave the queue (sent, or
 * expired by a step beyond its ttl) within the blackout of the step; a priority is never negative */
START_TEST(queue_step)
{
    double step = STEP[_i];
    ck_assert_int_eq(kelp_queue_init(&TQ, 1, tq, 2, tpool, 8, NULL, NULL, NULL), KELP_OK);
    kelp_queue_cfg c;
    kelp_queue_cfg_default(&c, KELP_QUEUE_DCCL, 10);
    c.ack = false;
    c.blackout_time = 10;
    c.ttl = 100;
    c.newest_first = false;
    ck_assert_int_eq(kelp_queue_add(&TQ, &c, T0), KELP_OK);
    kelp_acomms_msg m1 = tmsg(1, T0 + 20), m2 = tmsg(2, T0 + 20), out;
    ck_assert_int_eq(kelp_queue_push(&TQ, &m1, T0 + 20), KELP_OK);
    ck_assert_int_eq(kelp_queue_push(&TQ, &m2, T0 + 20), KELP_OK);
    kelp_queue_request req = { -1, 0, 32 };
    kelp_queue_do_work(&TQ, T0 + 20);
    ck_assert_int_eq(kelp_queue_data_request(&TQ, &req, T0 + 20, &out), KELP_OK);
    ck_assert_uint_eq(out.len, 7);
    kelp_queue_key key = { KELP_QUEUE_DCCL, 10 };
    kelp_time step_at = T0 + 21;
    if (!isfinite(step)) {
        kelp_queue_do_work(&TQ, step);
        ck_assert_int_eq(kelp_queue_data_request(&TQ, &req, step, &out), KELP_ERR_ARG);
        double p;
        ck_assert_int_eq(kelp_queue_priority(&TQ, key, step, &p), KELP_ERR_ARG);
    }
    kelp_time from = step_at + offset_of(step);
    int left = -1, frames = 0;
    for (int k = 0; k <= 60; k++) {
        kelp_time t = from + k;
        kelp_queue_do_work(&TQ, t);
        double p;
        ck_assert_int_eq(kelp_queue_priority(&TQ, key, t, &p), KELP_OK);
        ck_assert_msg(p >= 0.0, "step %g: priority %g at +%d s", step, p, k);
        ck_assert_int_eq(kelp_queue_data_request(&TQ, &req, t, &out), KELP_OK);
        if (out.len) frames++;
        if (left < 0 && kelp_queue_size(&TQ, key) == 0) left = k;
    }
    ck_assert_msg(left >= 0 && left <= 10, "step %g: m2 still queued %d s after the step", step, left);
    ck_assert_int_le(frames, 1); /* one message left: at most one frame */
}
END_TEST

/* ------------------------------------------------------------------ Micro-Modem driver */

/* a modem that answers every command by echoing it ($CCxxx -> $CAxxx) at the next tick */
static char mm_pend[16][KELP_MAX_NMEA_LINE + 8];
static int mm_npend, mm_lines;

static void mm_w(const char *b, size_t n, void *u)
{
    (void)u;
    mm_lines++;
    if (mm_npend < 16 && n < sizeof mm_pend[0] && n > 3 && b[0] == '$') {
        memcpy(mm_pend[mm_npend], b, n);
        mm_pend[mm_npend][n] = '\0';
        mm_npend++;
    }
}

static void mm_answer(kelp_mmdriver *mm, kelp_time now)
{
    int n = mm_npend;
    mm_npend = 0;
    for (int i = 0; i < n; i++) {
        char body[KELP_MAX_NMEA_LINE + 8], line[KELP_MAX_NMEA_LINE + 16];
        const char *star = strchr(mm_pend[i], '*');
        size_t len = star ? (size_t)(star - mm_pend[i]) : strlen(mm_pend[i]);
        memcpy(body, mm_pend[i], len);
        body[len] = '\0';
        body[2] = 'A'; /* $CC -> $CA */
        unsigned x = 0;
        for (const char *p = body + 1; *p; p++) x ^= (unsigned char)*p;
        snprintf(line, sizeof line, "%s*%02X\r\n", body, x);
        ck_assert_int_eq(kelp_mmdriver_feed(mm, (const uint8_t *)line, strlen(line), now), KELP_OK);
    }
}

/* the step comes 0.5 s after start (the $CCCLK is out, its one-second pause running, no answer
 * yet): the start-up commands must all be answered and the clock set within MODEM_WAIT and the
 * pause after the step, with no more than one re-send each and the modem never declared dead */
START_TEST(mmdriver_step)
{
    double step = STEP[_i];
    static kelp_mmdriver mm;
    kelp_mmdriver_cfg cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.modem_id = 1;
    cfg.reset_nvram = true;
    cfg.nvram_cfg[0] = "DTO,2";
    cfg.n_nvram = 1;
    static const kelp_mmdriver_ops ops = { mm_w, NULL, NULL };
    mm_npend = mm_lines = 0;
    ck_assert_int_eq(kelp_mmdriver_init(&mm, &cfg, &ops, NULL), KELP_OK);
    ck_assert_int_eq(kelp_mmdriver_start(&mm, T0), KELP_OK);
    mm_npend = 0; /* the modem missed the $CCCLK */
    kelp_time step_at = T0 + 0.5;
    if (!isfinite(step)) {
        ck_assert_int_eq(kelp_mmdriver_tick(&mm, step), KELP_ERR_ARG);
        ck_assert_int_eq(kelp_mmdriver_feed(&mm, (const uint8_t *)"x", 1, step), KELP_ERR_ARG);
        ck_assert_int_eq(kelp_mmdriver_initiate_transmission(&mm, 1, 2, 0, step), KELP_ERR_ARG);
    }
    kelp_time from = step_at + offset_of(step);
    int lines_before = mm_lines, done = -1;
    for (int k = 0; k <= 600; k++) {
        kelp_time t = from + k * 0.1;
        ck_assert_int_eq(kelp_mmdriver_tick(&mm, t), KELP_OK);
        mm_answer(&mm, t);
        if (done < 0 && mm.clock_set && mm.out_n == 0) done = k;
    }
    ck_assert_msg(done >= 0 && done <= (KELP_MMDRIVER_MODEM_WAIT + 2) * 10,
                  "step %g: start-up not done %.1f s after the step", step, done / 10.0);
    ck_assert_uint_le(mm.count.retries, 1);
    ck_assert_uint_eq(mm.count.deaths, 0);
    /* CLK (again), CFG ALL, CFG SRC, CFG DTO, CFQ, plus one re-send and one more CLK */
    ck_assert_int_le(mm_lines - lines_before, 8);
}
END_TEST

/* ------------------------------------------------------------------ pMarinePID and uSimMarine */

typedef struct pubs {
    double rudder;  /* the last DESIRED_RUDDER */
    int n_rudder;
    bool bad;       /* a non-finite value published */
} pubs;

static void pid_sink(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    pubs *p = ctx;
    (void)sval;
    if (!is_string && !isfinite(dval)) p->bad = true;
    if (!strcmp(var, "DESIRED_RUDDER")) p->rudder = dval, p->n_rudder++;
}

static void pid_feed(kelp_pid_marine *m, kelp_time t)
{
    ck_assert_int_eq(kelp_pid_marine_mail(m, "NAV_HEADING", false, NULL, 350, t), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(m, "NAV_SPEED", false, NULL, 1, t), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(m, "DESIRED_HEADING", false, NULL, 10, t), 1);
    ck_assert_int_eq(kelp_pid_marine_mail(m, "DESIRED_SPEED", false, NULL, 2, t), 1);
}

/* a 20 degree heading error held: the yaw loop's integral grows by ki * e * dt each 0.1 s run;
 * a step must not be a dt (an hour of integral, a NaN rudder), nor stop the rudder for an hour */
START_TEST(pid_step)
{
    double step = STEP[_i];
    kelp_pid_marine_cfg c;
    kelp_pid_marine_cfg_default(&c);
    c.active_start = true;
    c.yaw[0] = 0.5;  /* kp */
    c.yaw[2] = 0.01; /* ki */
    c.yaw[3] = 50;   /* integral limit */
    c.speed_factor = 20;
    c.max_rudder = 100;
    static kelp_pid_marine m;
    ck_assert_int_eq(kelp_pid_marine_init(&m, &c, T0), 0);
    pubs p = { 0, 0, false };
    kelp_time t = T0;
    for (int k = 0; k < 100; k++, t += 0.1) {
        pid_feed(&m, t);
        kelp_pid_marine_iterate(&m, t, pid_sink, &p);
    }
    double before = p.rudder;
    if (!isfinite(step)) kelp_pid_marine_iterate(&m, step, pid_sink, &p);
    kelp_time from = t + offset_of(step);
    int n0 = p.n_rudder, first = -1;
    double jump = 0;
    for (int k = 0; k < 50; k++) {
        kelp_time tk = from + k * 0.1;
        pid_feed(&m, tk);
        int n = p.n_rudder;
        kelp_pid_marine_iterate(&m, tk, pid_sink, &p);
        if (p.n_rudder > n && first < 0) {
            first = k;
            jump = fabs(p.rudder - before);
        }
    }
    ck_assert_msg(!p.bad, "step %g: a non-finite value published", step);
    ck_assert_msg(first >= 0 && first <= 10, "step %g: no rudder for %d runs after the step", step, first);
    ck_assert_msg(jump < 1.0, "step %g: the rudder jumped by %g at the step", step, jump);
    ck_assert_int_ge(p.n_rudder - n0, 40);
}
END_TEST

typedef struct simpos {
    double x, y;
} simpos;

static void usim_sink(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    simpos *p = ctx;
    (void)is_string, (void)sval;
    if (!strcmp(var, "NAV_X")) p->x = dval;
    if (!strcmp(var, "NAV_Y")) p->y = dval;
}

/* at 2 m/s, 10 Hz: a step is not dead-reckoned (an hour or a day of travel in one iteration), and
 * after a step back the vehicle moves on at once */
START_TEST(usim_step)
{
    double step = STEP[_i];
    static kelp_usim u;
    kelp_usim_defaults(&u, NULL, NULL);
    ck_assert_int_eq(kelp_usim_config(&u, "START_SPEED", "2", NULL), 1);
    ck_assert_int_eq(kelp_usim_config(&u, "START_HEADING", "90", NULL), 1);
    ck_assert_int_eq(kelp_usim_start(&u, NULL, T0), KELP_OK);
    simpos p = { 0, 0 };
    kelp_time t = T0;
    for (int k = 0; k < 50; k++, t += 0.1) {
        (void)kelp_usim_mail(&u, "DESIRED_THRUST", false, NULL, 40, t);
        (void)kelp_usim_iterate(&u, t, usim_sink, &p);
    }
    ck_assert(p.x > 1.0); /* it moves */
    if (!isfinite(step)) ck_assert_int_eq(kelp_usim_iterate(&u, step, usim_sink, &p), KELP_ERR_ARG);
    kelp_time from = t + offset_of(step);
    simpos prev = p;
    double most = 0;
    int moved = -1;
    for (int k = 0; k < 50; k++) {
        kelp_time tk = from + k * 0.1;
        (void)kelp_usim_mail(&u, "DESIRED_THRUST", false, NULL, 40, tk);
        (void)kelp_usim_iterate(&u, tk, usim_sink, &p);
        double d = hypot(p.x - prev.x, p.y - prev.y);
        if (d > most) most = d;
        if (d > 0 && moved < 0 && k > 0) moved = k;
        prev = p;
    }
    ck_assert_msg(isfinite(p.x) && isfinite(p.y), "step %g: position not finite", step);
    ck_assert_msg(most < 5.0 + fmax(0.0, offset_of(step) <= 1.0 ? 2.0 * offset_of(step) : 0.0),
                  "step %g: %g m in one iteration", step, most);
    ck_assert_msg(moved >= 0 && moved <= 2, "step %g: standing still %d iterations after the step", step, moved);
}
END_TEST

/* ------------------------------------------------------------------ uField tools: a counting sink */

typedef struct count_sink {
    const char *var; /* the variable counted */
    int n;           /* its postings */
    double last;     /* its last double value */
    bool negative;   /* a value of `neg_var` below zero */
    const char *neg_var;
} count_sink;

static void count_pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    count_sink *c = ctx;
    (void)sval;
    if (c->var && !strcmp(var, c->var)) c->n++, c->last = dval;
    if (c->neg_var && !is_string && !strcmp(var, c->neg_var) && dval < 0) c->negative = true;
}

/* ------------------------------------------------------------------ uTimerScript */

/* events at 10, 20, ..., 100 s of script time; the step comes at 35 s: each event is posted once,
 * never two in one iteration, and the next one within 10 s of the step */
START_TEST(timerscript_step)
{
    double step = STEP[_i];
    static kelp_timerscript_cfg c;
    static kelp_timerscript ts;
    kelp_timerscript_cfg_default(&c, "uTimerScript", "alpha");
    for (int k = 1; k <= 10; k++) {
        char ev[64];
        snprintf(ev, sizeof ev, "var=EV, val=%d, time=%d", k, 10 * k);
        ck_assert_int_eq(kelp_timerscript_cfg_add_event(&c, ev, NULL), KELP_OK);
    }
    ck_assert_int_eq(kelp_timerscript_init(&ts, &c, 1), KELP_OK);
    count_sink cs = { "EV", 0, 0, false, NULL };
    kelp_field_sink out = { &cs, count_pub, NULL };
    kelp_time t = T0;
    for (; t < T0 + 35; t += 0.5) ck_assert_int_le(kelp_timerscript_iterate(&ts, t, &out), 1);
    ck_assert_int_eq(cs.n, 3);
    if (!isfinite(step)) ck_assert_int_eq(kelp_timerscript_iterate(&ts, step, &out), KELP_ERR_ARG);
    kelp_time from = t + offset_of(step);
    int most = 0, next = -1;
    for (int k = 0; k < 200; k++) {
        int n = kelp_timerscript_iterate(&ts, from + k * 0.5, &out);
        if (n > most) most = n;
        if (n > 0 && next < 0) next = k;
    }
    ck_assert_msg(most <= 1, "step %g: %d events in one iteration", step, most);
    ck_assert_msg(next >= 0 && next <= 21, "step %g: next event %d iterations after the step", step, next);
    ck_assert_int_eq(cs.n, 10);
}
END_TEST

/* ------------------------------------------------------------------ uFldNodeComms */

static kelp_field_ncomms nc; /* 3 MB */
static char nc_rep[16384];

static void nc_second(kelp_time t, const kelp_field_sink *out)
{
    char b[256];
    for (int v = 0; v < 2; v++) {
        snprintf(b, sizeof b, "NAME=%s,TYPE=UUV,TIME=%.2f,X=%d,Y=0,SPD=1,HDG=90,DEPTH=0", v ? "bravo" : "alpha", t,
                 v * 50);
        ck_assert_int_eq(kelp_field_ncomms_mail(&nc, "NODE_REPORT", true, b, 0, "t", t, out), 1);
    }
    ck_assert_int_eq(kelp_field_ncomms_mail(&nc, "NODE_MESSAGE", true, "src_node=alpha,dest_node=bravo,var_name=M,string_val=hi",
                                            0, "t", t, out), 1);
    (void)kelp_field_ncomms_iterate(&nc, t, out);
}

/* reports every second, a message every second held to MIN_MSG_INTERVAL 30 s: after the step a
 * message goes within the interval, at most one per interval, and no age in the report is < 0 */
START_TEST(nodecomms_step)
{
    double step = STEP[_i];
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    ck_assert_int_eq(kelp_field_ncomms_init(&nc, &cfg), 0);
    count_sink cs = { "NODE_MESSAGE_BRAVO", 0, 0, false, NULL };
    kelp_field_sink out = { &cs, count_pub, NULL };
    kelp_time t = T0;
    for (; t < T0 + 100; t += 1) nc_second(t, &out);
    ck_assert_int_eq(cs.n, 4); /* 0, 30, 60, 90 */
    if (!isfinite(step)) {
        ck_assert_uint_eq(kelp_field_ncomms_iterate(&nc, step, &out), 0);
        ck_assert_int_eq(kelp_field_ncomms_mail(&nc, "NODE_REPORT", true, "NAME=x", 0, "t", step, &out), KELP_ERR_ARG);
    }
    kelp_time from = t + offset_of(step);
    int first = -1, n0 = cs.n;
    for (int k = 0; k < 100; k++) {
        int n = cs.n;
        nc_second(from + k, &out);
        if (cs.n > n && first < 0) first = k;
    }
    ck_assert_msg(first >= 0 && first <= 30, "step %g: first message %d s after the step", step, first);
    ck_assert_msg(cs.n - n0 <= 4, "step %g: %d messages in 100 s", step, cs.n - n0);
    ck_assert_int_eq(kelp_field_ncomms_report(&nc, from + 100, nc_rep, sizeof nc_rep), KELP_OK);
    ck_assert_msg(strstr(nc_rep, "(-") == NULL, "step %g: a negative age in the report:\n%s", step, nc_rep);
}
END_TEST

/* ------------------------------------------------------------------ uFldMessageHandler */

static kelp_field_umh umh;
static char umh_rep[8192];

/* a message to bravo every second, iterations every 0.25 s (AppTick 4) */
static void umh_second(kelp_time t, const kelp_field_sink *out, int *most)
{
    ck_assert_int_eq(kelp_field_umh_mail(&umh, "NODE_MESSAGE", true,
                                         "src_node=alpha,dest_node=bravo,var_name=FOO,string_val=x", t, out), 1);
    for (int q = 0; q < 4; q++) {
        int n = kelp_field_umh_iterate(&umh, t + 0.25 * q, out);
        if (most && n > *most) *most = n;
    }
}

/* every message is posted when it comes, summaries at most one per iteration, and the report's
 * ages ("Time since last Msg", the table's Elapsed) are never negative */
START_TEST(msghandler_step)
{
    double step = STEP[_i];
    kelp_field_umh_cfg cfg;
    kelp_field_umh_cfg_default(&cfg, "bravo");
    kelp_field_umh_init(&umh, &cfg);
    count_sink cs = { "FOO", 0, 0, false, NULL };
    kelp_field_sink out = { &cs, count_pub, NULL };
    kelp_time t = T0;
    for (; t < T0 + 100; t += 1) umh_second(t, &out, NULL);
    ck_assert_int_eq(cs.n, 100);
    if (!isfinite(step)) {
        ck_assert_int_eq(kelp_field_umh_mail(&umh, "NODE_MESSAGE", true,
                                             "src_node=alpha,dest_node=bravo,var_name=FOO,string_val=x", step, &out),
                         KELP_ERR_ARG);
        ck_assert_int_eq(kelp_field_umh_iterate(&umh, step, &out), 0);
    }
    kelp_time from = t + offset_of(step);
    /* the report right after the step, before any new message: no negative age */
    ck_assert_uint_gt(kelp_field_umh_report(&umh, from, umh_rep, sizeof umh_rep), 0);
    ck_assert_msg(strstr(umh_rep, "Msg: -") == NULL && strstr(umh_rep, "200    -") == NULL && strstr(umh_rep, "100    -") == NULL,
                  "step %g: a negative age in the report:\n%s", step, umh_rep);
    int most = 0;
    for (int k = 0; k < 100; k++) umh_second(from + k, &out, &most);
    ck_assert_int_eq(cs.n, 200);
    ck_assert_int_le(most, 1);
    ck_assert_uint_gt(kelp_field_umh_report(&umh, from + 100, umh_rep, sizeof umh_rep), 0);
    ck_assert_msg(strstr(umh_rep, "Time since last Msg: 1.0\n") != NULL && strstr(umh_rep, "alpha   200    1.0 ") != NULL,
                  "step %g: the ages in the report:\n%s", step, umh_rep);
}
END_TEST

/* ------------------------------------------------------------------ uFldNodeBroker's pings */

static kelp_field_nbroker nb;

/* 24.8's model: with no ack, a NODE_BROKER_PING_0 every 5 s (KELP_BROKER_PING_FAST) */
START_TEST(nodebroker_step)
{
    double step = STEP[_i];
    kelp_field_nbroker_cfg cfg;
    kelp_diag why = {0};
    kelp_field_nbroker_cfg_default(&cfg);
    ck_assert_int_eq(kelp_field_nbroker_config(&cfg, "TRY_SHORE_HOST", "pshare_route=198.51.100.1:9300", &why), 1);
    kelp_field_nbroker_init(&nb, &cfg);
    count_sink cs = { "NODE_BROKER_PING_0", 0, 0, false, NULL };
    kelp_field_sink out = { &cs, count_pub, NULL };
    const char *phi = "community=alpha,hostip=198.51.100.2,port_db=9000,port_udp=9301,"
                      "pshare_iroutes=198.51.100.2:9301,timewarp=1";
    kelp_time t = T0;
    ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "PHI_HOST_INFO", true, phi, t, &out), 1);
    for (; t < T0 + 100; t += 0.25) (void)kelp_field_nbroker_iterate(&nb, t, &out);
    ck_assert_int_ge(cs.n, 18);
    if (!isfinite(step)) {
        ck_assert_int_eq(kelp_field_nbroker_mail(&nb, "PHI_HOST_INFO", true, phi, step, &out), KELP_ERR_ARG);
        ck_assert_int_eq(kelp_field_nbroker_iterate(&nb, step, &out), 0);
    }
    kelp_time from = t + offset_of(step);
    int n0 = cs.n, first = -1, most = 0;
    for (int k = 0; k < 400; k++) {
        int n = cs.n;
        (void)kelp_field_nbroker_iterate(&nb, from + 0.25 * k, &out);
        if (cs.n - n > most) most = cs.n - n;
        if (cs.n > n && first < 0) first = k;
    }
    ck_assert_msg(first >= 0 && first * 0.25 <= 5.25, "step %g: first ping %.2f s after the step", step, first * 0.25);
    ck_assert_msg(most <= 1 && cs.n - n0 <= 21, "step %g: %d pings in 100 s (%d in one iteration)", step, cs.n - n0, most);
}
END_TEST

/* ------------------------------------------------------------------ uFldShoreBroker's passes */

static kelp_field_sbroker sbk;

/* 24.8's model: a vehicle pings every 5 s; the shore's bridge-request passes (PSHARE_CMD) come
 * at a gap growing by 3 s a pass; after a step the next pass is at most one gap away */
START_TEST(shorebroker_step)
{
    double step = STEP[_i];
    kelp_field_sbroker_cfg cfg;
    kelp_diag why = {0};
    kelp_field_sbroker_cfg_default(&cfg);
    ck_assert_int_eq(kelp_field_sbroker_config(&cfg, "QBRIDGE", "DEPLOY", &why), 1);
    kelp_field_sbroker_init(&sbk, &cfg);
    count_sink cs = { "PSHARE_CMD", 0, 0, false, NULL };
    kelp_field_sink out = { &cs, count_pub, NULL };
    const char *phi = "community=shoreside,hostip=10.0.0.1,port_db=9000,port_udp=9300,pshare_iroutes=10.0.0.1:9300,"
                      "hostip_alts=,timewarp=1";
    const char *ping = "community=alpha,hostip=10.0.0.2,port_db=9001,port_udp=9201,pshare_iroutes=10.0.0.2:9201,"
                       "timewarp=1,time=0,key=0";
    kelp_time t = T0;
    ck_assert_int_eq(kelp_field_sbroker_mail(&sbk, "PHI_HOST_INFO", true, phi, t, &out), 1);
    for (int k = 0; k < 200; k++, t += 0.5) {
        if (k % 10 == 0) ck_assert_int_ge(kelp_field_sbroker_mail(&sbk, "NODE_BROKER_PING", true, ping, t, &out), 0);
        (void)kelp_field_sbroker_iterate(&sbk, t, &out);
    }
    ck_assert_int_gt(cs.n, 0);
    double gap = sbk.cmd_interval;
    if (!isfinite(step)) {
        ck_assert_int_eq(kelp_field_sbroker_mail(&sbk, "NODE_BROKER_PING", true, ping, step, &out), KELP_ERR_ARG);
        ck_assert_int_eq(kelp_field_sbroker_iterate(&sbk, step, &out), 0);
    }
    kelp_time from = t + offset_of(step);
    int first = -1;
    for (int k = 0; k < 400; k++) {
        int n = cs.n;
        if (k % 10 == 0) ck_assert_int_ge(kelp_field_sbroker_mail(&sbk, "NODE_BROKER_PING", true, ping, from + 0.5 * k, &out), 0);
        (void)kelp_field_sbroker_iterate(&sbk, from + 0.5 * k, &out);
        if (cs.n > n && first < 0) first = k;
    }
    ck_assert_msg(first >= 0 && first * 0.5 <= gap + 0.5, "step %g: first pass %.1f s after the step (gap %.0f s)", step,
                  first * 0.5, gap);
}
END_TEST

/* ------------------------------------------------------------------ the bus: retained values, sync, limits */

static struct {
    kelp_bus bus;
    kelp_bus_sub subs[4];
    kelp_var cache[8];
    kelp_var rx;
    uint8_t scratch[16384];
    kelp_loopback_port port;
    kelp_loopback net;
    int got[2];
} TB;

static void tb_on(const kelp_var *v, void *u)
{
    (void)u;
    TB.got[v->name[0] == 'Y']++;
}

static void tb_write(const char *name, kelp_time stamp, kelp_time now)
{
    static kelp_var v;
    memset(&v, 0, sizeof v);
    snprintf(v.name, sizeof v.name, "%s", name);
    snprintf(v.source, sizeof v.source, "pWriter");
    snprintf(v.community, sizeof v.community, "c");
    v.time = stamp;
    v.kind = KELP_VAR_DOUBLE;
    uint8_t buf[512];
    size_t n;
    ck_assert_int_eq(kelp_var_encode(&v, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_bus_receive(&TB.bus, name, buf, n, now), 0);
}

/* A peer writes X on its own (steady) clock while ours steps: the future-time check must not
 * refuse the peer for the length of a backward step.  Y is written on a clock that steps with
 * ours: the subscription's 0.5 s rate limit must not hold it back for the length of the step. */
START_TEST(bus_step)
{
    double step = STEP[_i];
    memset(&TB, 0, sizeof TB);
    kelp_loopback_init(&TB.net);
    kelp_bus_transport tr;
    kelp_loopback_transport(&TB.net, &TB.port, &tr);
    kelp_bus_storage st = { TB.subs, 4, TB.cache, 8, TB.scratch, sizeof TB.scratch, &TB.rx };
    ck_assert_int_eq(kelp_bus_init(&TB.bus, "pA", "c", "KELP_SYNC_pA", &tr, &st, tb_on, NULL), 0);
    kelp_bus_limits lim;
    kelp_bus_limits_default(&lim);
    lim.time_margin = KELP_BUS_TIME_MARGIN;
    ck_assert_int_eq(kelp_bus_set_limits(&TB.bus, &lim), 0);
    ck_assert_int_eq(kelp_bus_register(&TB.bus, "X", 0, T0), 0);
    ck_assert_int_eq(kelp_bus_register(&TB.bus, "Y", 0.5, T0), 0);
    for (int k = 0; k < 20; k++) {
        tb_write("X", T0 + k, T0 + k);
        tb_write("Y", T0 + k, T0 + k);
    }
    ck_assert_int_eq(TB.got[0], 20);
    ck_assert_int_eq(TB.got[1], 20);
    double off = offset_of(step);
    for (int k = 20; k < 40; k++) {
        tb_write("X", T0 + k, T0 + k + off);
        tb_write("Y", T0 + k + off, T0 + k + off);
    }
    ck_assert_msg(TB.got[0] == 40, "step %g: %d of 20 X after the step", step, TB.got[0] - 20);
    ck_assert_msg(TB.got[1] >= 39, "step %g: %d of 20 Y after the step", step, TB.got[1] - 20);
}
END_TEST

/* ------------------------------------------------------------------ CAN reassembly */

#define CAN_MAXF 64
static struct {
    kelp_can_frame f[CAN_MAXF];
    int n;
} CF;

static int can_emit(void *user, const kelp_can_frame *f)
{
    (void)user;
    if (CF.n >= CAN_MAXF) return KELP_ERR_NOSPACE;
    CF.f[CF.n++] = *f;
    return 0;
}

/* every reassembly slot holds a partial message when the clock steps (timeout 1 s): a new
 * message must get through within a timeout of the step, not after it */
START_TEST(can_step)
{
    double step = STEP[_i];
    static kelp_can_dict d;
    static kelp_can_rx rx;
    static kelp_can_tx tx;
    kelp_can_dict_init(&d);
    ck_assert_int_eq(kelp_can_dict_add(&d, 12, "STATUS_TEXT"), 0);
    kelp_can_rx_init(&rx, 1.0);
    ck_assert_int_eq(kelp_can_tx_init(&tx, 5, false), 0);
    kelp_can_msg m, out;
    memset(&m, 0, sizeof m);
    m.name = "STATUS_TEXT";
    m.kind = KELP_CAN_KIND_STRING;
    m.sval = (const uint8_t *)"a status line long enough for several classic frames";
    m.slen = strlen((const char *)m.sval);
    for (unsigned k = 0; k < KELP_CAN_SLOTS; k++) { /* the first frame of each: a slot each */
        CF.n = 0;
        ck_assert_int_gt(kelp_can_send(&tx, &d, &m, can_emit, NULL), 1);
        ck_assert_int_eq(kelp_can_rx_frame(&rx, &d, &CF.f[0], T0 + 0.5, &out), 0);
    }
    if (!isfinite(step)) {
        kelp_can_rx_expire(&rx, step);
        ck_assert_uint_eq(rx.st.timed_out, 0);
        ck_assert_int_eq(kelp_can_rx_frame(&rx, &d, &CF.f[1], step, &out), KELP_ERR_ARG);
    }
    kelp_time from = T0 + 0.6 + offset_of(step);
    int got = -1;
    for (int k = 0; k < 30 && got < 0; k++) { /* a new message every 0.1 s */
        CF.n = 0;
        ck_assert_int_gt(kelp_can_send(&tx, &d, &m, can_emit, NULL), 1);
        for (int i = 0; i < CF.n; i++)
            if (kelp_can_rx_frame(&rx, &d, &CF.f[i], from + 0.1 * k, &out) == 1) got = k;
    }
    ck_assert_msg(got >= 0 && got <= 11, "step %g: no message through %d x 0.1 s after the step", step, got);
}
END_TEST

/* ------------------------------------------------------------------ kelp-viewer staleness */

/* a vehicle reports every second until the step and never again: it must turn stale within the
 * threshold (60 s) of the step (and not be dropped before: removal is later) */
START_TEST(viewer_step)
{
    double step = STEP[_i];
    static kelp_viewer v;
    kelp_viewer_init(&v);
    const char *r = "NAME=alpha,TYPE=kayak,X=10,Y=-20,HDG=90,SPD=1.5";
    kelp_time t = T0;
    for (; t < T0 + 10; t += 1) {
        ck_assert_int_eq(kelp_viewer_mail(&v, "NODE_REPORT", r, strlen(r), t), 1);
        (void)kelp_viewer_tick(&v, t);
    }
    if (!isfinite(step)) {
        ck_assert_int_eq(kelp_viewer_mail(&v, "NODE_REPORT", r, strlen(r), step), KELP_ERR_ARG);
        ck_assert_int_eq(kelp_viewer_tick(&v, step), 0);
    }
    kelp_time from = t + offset_of(step);
    int stale = -1;
    for (int k = 0; k <= 120 && stale < 0; k++) {
        (void)kelp_viewer_tick(&v, from + k);
        if (v.veh[0].stale || v.veh[0].gone) stale = k;
    }
    ck_assert_msg(stale >= 0 && stale <= (int)KELP_VIEWER_STALE_DEFAULT + 1, "step %g: stale %d s after the step", step,
                  stale);
}
END_TEST

/* ------------------------------------------------------------------ uFldPathCheck */

/* a vehicle at 1 m/s reports every second on its own clock, which steps with ours: reports must
 * be taken again within a second of the step, and the speed over the history must stay ~1 m/s
 * (not an average over the step) once the history has refilled */
START_TEST(pathcheck_step)
{
    double step = STEP[_i];
    static kelp_pathcheck p;
    kelp_pathcheck_cfg cfg;
    kelp_pathcheck_cfg_default(&cfg);
    ck_assert_int_eq(kelp_pathcheck_init(&p, &cfg), 0);
    kelp_field_sink out = { NULL, count_pub, NULL };
    count_sink cs = { NULL, 0, 0, false, NULL };
    out.ctx = &cs;
    char r[160];
    double x = 0;
    kelp_time t = T0;
    for (; t < T0 + 20; t += 1, x += 1) {
        snprintf(r, sizeof r, "NAME=alpha,TYPE=kayak,TIME=%.2f,X=%.1f,Y=0,SPD=1,HDG=90", t, x);
        ck_assert_int_eq(kelp_pathcheck_mail(&p, "NODE_REPORT", true, r, t, &out), 1);
    }
    if (!isfinite(step)) ck_assert_int_eq(kelp_pathcheck_mail(&p, "NODE_REPORT", true, r, step, &out), KELP_ERR_ARG);
    kelp_time from = t + offset_of(step);
    unsigned long before = p.node[0].reports;
    for (int k = 0; k < 15; k++, x += 1) {
        snprintf(r, sizeof r, "NAME=alpha,TYPE=kayak,TIME=%.2f,X=%.1f,Y=0,SPD=1,HDG=90", from + k, x);
        ck_assert_int_eq(kelp_pathcheck_mail(&p, "NODE_REPORT", true, r, from + k, &out), 1);
        (void)kelp_pathcheck_iterate(&p, from + k, &out);
    }
    ck_assert_msg(p.node[0].reports - before >= 14, "step %g: %lu of 15 reports taken", step,
                  p.node[0].reports - before);
    double v = kelp_pathcheck_speed(&p.node[0]);
    ck_assert_msg(fabs(v - 1.0) < 0.01, "step %g: speed %g after the step", step, v);
}
END_TEST

/* ------------------------------------------------------------------ pNodeReporter */

/* a report every 5 s (blackout), nav mail every second: after the step the reports resume
 * within the blackout, at most one per blackout, and PNR_POST_GAP is never negative */
START_TEST(nodereporter_step)
{
    double step = STEP[_i];
    static kelp_field_nrep nr;
    kelp_field_nrep_cfg cfg;
    kelp_field_nrep_cfg_default(&cfg, "alpha");
    cfg.blackout_interval = 5;
    ck_assert_int_eq(kelp_field_nrep_init(&nr, &cfg, T0), 0);
    count_sink cs = { "NODE_REPORT_LOCAL", 0, 0, false, "PNR_POST_GAP" };
    kelp_field_sink out = { &cs, count_pub, NULL };
    static const char *const navs[4] = { "NAV_X", "NAV_Y", "NAV_SPEED", "NAV_HEADING" };
    kelp_time t = T0;
    for (; t < T0 + 30; t += 1) {
        for (int i = 0; i < 4; i++) ck_assert_int_eq(kelp_field_nrep_mail(&nr, navs[i], false, NULL, 1, &out), 1);
        (void)kelp_field_nrep_iterate(&nr, t, &out);
    }
    ck_assert_int_ge(cs.n, 4);
    if (!isfinite(step)) ck_assert_int_eq(kelp_field_nrep_iterate(&nr, step, &out), 0);
    kelp_time from = t + offset_of(step);
    int n0 = cs.n, first = -1;
    for (int k = 0; k < 30; k++) {
        int n = cs.n;
        for (int i = 0; i < 4; i++) ck_assert_int_eq(kelp_field_nrep_mail(&nr, navs[i], false, NULL, 1, &out), 1);
        (void)kelp_field_nrep_iterate(&nr, from + k, &out);
        if (cs.n > n && first < 0) first = k;
    }
    ck_assert_msg(first >= 0 && first <= 6, "step %g: first report %d s after the step", step, first);
    ck_assert_msg(cs.n - n0 <= 6, "step %g: %d reports in 30 s", step, cs.n - n0);
    ck_assert_msg(!cs.negative, "step %g: a negative PNR_POST_GAP", step);
}
END_TEST

/* ------------------------------------------------------------------ pContactMgrV20 */

/* CONTACTS_RECAP every second (recap_interval 1), a contact reporting every second with its own
 * TIME: after the step the recap resumes within a second, at most one per iteration; a refused
 * `now` changes nothing */
START_TEST(contactmgr_step)
{
    double step = STEP[_i];
    static kelp_contactmgr c;
    kelp_contactmgr_init(&c, "abe");
    count_sink cs = { "CONTACTS_RECAP", 0, 0, false, NULL };
    kelp_field_sink out = { &cs, count_pub, NULL };
    kelp_contactmgr_config_done(&c, false, 0, false, 0, &out);
    char r[160];
    kelp_time t = T0;
    for (int i = 0; i < 4; i++) ck_assert_int_eq(kelp_contactmgr_mail(&c, (const char *[]){ "NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED" }[i], false, NULL, 0, t, NULL, &out), 1);
    for (; t < T0 + 20; t += 1) {
        snprintf(r, sizeof r, "NAME=ben,TYPE=kayak,TIME=%.2f,X=100,Y=0,SPD=0,HDG=90", t);
        (void)kelp_contactmgr_mail(&c, "NODE_REPORT", true, r, 0, t, NULL, &out);
        kelp_contactmgr_iterate(&c, t, &out);
    }
    ck_assert_int_ge(cs.n, 18);
    if (!isfinite(step)) {
        unsigned long it = c.iterations;
        ck_assert_int_eq(kelp_contactmgr_mail(&c, "NODE_REPORT", true, r, 0, step, NULL, &out), KELP_ERR_ARG);
        kelp_contactmgr_iterate(&c, step, &out);
        ck_assert_uint_eq(c.iterations, it);
    }
    kelp_time from = t + offset_of(step);
    int n0 = cs.n, first = -1;
    for (int k = 0; k < 15; k++) {
        int n = cs.n;
        snprintf(r, sizeof r, "NAME=ben,TYPE=kayak,TIME=%.2f,X=100,Y=0,SPD=0,HDG=90", from + k);
        (void)kelp_contactmgr_mail(&c, "NODE_REPORT", true, r, 0, from + k, NULL, &out);
        kelp_contactmgr_iterate(&c, from + k, &out);
        ck_assert_int_le(cs.n - n, 1);
        if (cs.n > n && first < 0) first = k;
    }
    ck_assert_msg(first >= 0 && first <= 1, "step %g: first recap %d s after the step", step, first);
    ck_assert_msg(cs.n - n0 >= 13, "step %g: %d recaps in 15 s", step, cs.n - n0);
}
END_TEST

Suite *kelp_timefaults_suite(void)
{
    Suite *s = suite_create("timefaults");
    TCase *tc = tcase_create("acomms");
    tcase_add_loop_test(tc, mac_fixed_step, 0, NSTEP);
    tcase_add_loop_test(tc, mac_auto_step, 0, NSTEP);
    tcase_add_loop_test(tc, queue_step, 0, NSTEP);
    tcase_add_loop_test(tc, mmdriver_step, 0, NSTEP);
    suite_add_tcase(s, tc);
    tc = tcase_create("sim");
    tcase_add_loop_test(tc, pid_step, 0, NSTEP);
    tcase_add_loop_test(tc, usim_step, 0, NSTEP);
    suite_add_tcase(s, tc);
    tc = tcase_create("bus");
    tcase_add_loop_test(tc, bus_step, 0, NSTEP);
    tcase_add_loop_test(tc, can_step, 0, NSTEP);
    suite_add_tcase(s, tc);
    tc = tcase_create("field");
    tcase_add_loop_test(tc, timerscript_step, 0, NSTEP);
    tcase_add_loop_test(tc, nodecomms_step, 0, NSTEP);
    tcase_add_loop_test(tc, msghandler_step, 0, NSTEP);
    tcase_add_loop_test(tc, nodebroker_step, 0, NSTEP);
    tcase_add_loop_test(tc, shorebroker_step, 0, NSTEP);
    tcase_add_loop_test(tc, viewer_step, 0, NSTEP);
    tcase_add_loop_test(tc, pathcheck_step, 0, NSTEP);
    tcase_add_loop_test(tc, nodereporter_step, 0, NSTEP);
    tcase_add_loop_test(tc, contactmgr_step, 0, NSTEP);
    suite_add_tcase(s, tc);
    return s;
}
