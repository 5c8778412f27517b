/* The helm's decisions with spawned BHV_AvoidCollision instances, pinned: the encounters of
 * bench/helm_spawn.sh (a waypoint survey around a ring of 1, 5 and 20 kayaks reporting at 1 Hz,
 * the helm at 4 Hz) must give the same course and speed at every iteration as the helm gave
 * before its IvP build and solve were made fast (issue 28). The pinned pairs were printed by
 * this file's scenario (PIN_PRINT) linked against the library of that time.
 *
 * Compiled with -DPIN_PRINT it is a program printing those pairs instead. */
#ifndef PIN_PRINT
#include <check.h>
#endif
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/cpa.h>
#include <kelp/helm.h>
#include <kelp/mission.h>

#define PIN_ITERS 41
#define PIN_EVERY 4

static const char *const PIN_BHV =
    "Behavior = BHV_Waypoint\n{\n name = survey\n pwt = 100\n speed = 1.5\n points = 0,-100:100,-100:100,0\n"
    " repeat = forever\n}\n"
    "Behavior = BHV_AvoidCollision\n{\n name = avd_\n pwt = 200\n updates = CONTACT_INFO\n templating = spawn\n"
    " contact = to-be-set\n on_no_contact_ok = true\n extrapolate = true\n decay = 30,60\n pwt_outer_dist = 200\n"
    " pwt_inner_dist = 50\n completed_dist = 250\n min_util_cpa_dist = 10\n max_util_cpa_dist = 40\n}\n";

#define PIN_POOL 32768
static kelp_helm p_h;
static kelp_ivp_piece p_pool[PIN_POOL], p_tmp[4096];
static double p_dwork[4096];
static kelp_ivp_pq_entry p_pq[PIN_POOL];
static unsigned char p_solve[6 << 20];
static kelp_mission_node p_nodes[256];
static char p_text[4096];

static void pin_sink(const kelp_helm_post *p, void *user)
{
    (void)p, (void)user;
}

/* Run the encounter with ns contacts; out[2 i], out[2 i + 1]: course and speed of iteration
 * i * PIN_EVERY. Returns the number of pairs, or -1. */
static int pin_run(int ns, double *out)
{
    kelp_helm_config cfg;
    kelp_helm_config_default(&cfg);
    cfg.start_engaged = true;
    kelp_diag e;
    kelp_diag_clear(&e);
    if (kelp_ivp_domain_parse(&cfg.domain, "course:0:359:360,speed:0:4:21", &e)) return -1;
    snprintf(cfg.us, sizeof cfg.us, "alder");
    cfg.sink = pin_sink;
    kelp_helm_mem mem = {p_pool, PIN_POOL, p_tmp, 4096, p_dwork, 4096, p_pq, PIN_POOL, p_solve, sizeof p_solve};
    if (kelp_helm_init(&p_h, &cfg, &mem)) return -1;
    snprintf(p_text, sizeof p_text, "%s", PIN_BHV);
    kelp_mission m;
    if (kelp_mission_parse(&m, p_text, strlen(p_text), p_nodes, 256) || kelp_helm_load_bhv(&p_h, &m) ||
        kelp_helm_configured(&p_h))
        return -1;
    kelp_helm_start(&p_h, 0);
    int np = 0;
    for (long i = 0; i < PIN_ITERS; i++) {
        double now = 0.25 * (double)(i + 1), a = (double)i * 0.01;
        kelp_helm_mail_double(&p_h, "NAV_X", 20 * cos(a));
        kelp_helm_mail_double(&p_h, "NAV_Y", -20 + 20 * sin(a));
        kelp_helm_mail_double(&p_h, "NAV_HEADING", fmod(90 + a * 57.29577951308232, 360));
        kelp_helm_mail_double(&p_h, "NAV_SPEED", 1.5);
        if (i % 4 == 0)
            for (int c = 0; c < ns; c++) {
                double r = 60 + 100.0 * c / (ns > 1 ? ns - 1 : 1), b = 6.283185307179586 * c / ns;
                char rep[192];
                snprintf(rep, sizeof rep, "NAME=c%02d,TYPE=kayak,TIME=%.2f,X=%.1f,Y=%.1f,SPD=1.5,HDG=%.0f", c, now,
                         r * sin(b), -20 + r * cos(b), fmod(180 + b * 57.29577951308232, 360));
                kelp_helm_mail_string(&p_h, "NODE_REPORT", rep);
                if (i == 0) {
                    snprintf(rep, sizeof rep, "name=c%02d # contact=c%02d", c, c);
                    kelp_helm_mail_string(&p_h, "CONTACT_INFO", rep);
                }
            }
        if (kelp_helm_iterate(&p_h, now) || p_h.rep.ofnum != (unsigned)ns + 1) return -1;
        if (i % PIN_EVERY == 0) {
            out[2 * np] = p_h.rep.decision[0];
            out[2 * np + 1] = p_h.rep.decision[1];
            np++;
        }
    }
    return np;
}

static const int PIN_NS[3] = {1, 5, 20};
#define PIN_PAIRS ((PIN_ITERS + PIN_EVERY - 1) / PIN_EVERY)

#ifdef PIN_PRINT
int main(void)
{
    for (int k = 0; k < 3; k++) {
        double d[2 * PIN_PAIRS];
        int np = pin_run(PIN_NS[k], d);
        printf("    {");
        for (int i = 0; i < np; i++) printf("%s%.17g, %.17g", i ? ", " : "", d[2 * i], d[2 * i + 1]);
        printf("},\n");
    }
    return 0;
}
#else
static const double PIN_WANT[3][2 * PIN_PAIRS] = {
#include "helm_avoid_pin.inc"
};

START_TEST(avoid_decisions_pinned)
{
    int k = _i;
    double d[2 * PIN_PAIRS];
    ck_assert_int_eq(pin_run(PIN_NS[k], d), PIN_PAIRS);
    for (int i = 0; i < PIN_PAIRS; i++) {
        ck_assert_msg(d[2 * i] == PIN_WANT[k][2 * i] && d[2 * i + 1] == PIN_WANT[k][2 * i + 1],
                      "%d contacts, iteration %d: %g/%g, pinned %g/%g", PIN_NS[k], i * PIN_EVERY, d[2 * i],
                      d[2 * i + 1], PIN_WANT[k][2 * i], PIN_WANT[k][2 * i + 1]);
    }
}
END_TEST

/* The objective as the helm sampled it point by point before the line sampler: the course's
 * unit vector, kelp_cpa_fast_eval_unit's CPA range, MOOS-IvP's utility of it. */
static double ref_aof(const double *pt, void *user)
{
    const kelp_bhv_avoid_aof *f = user;
    double ux, uy;
    kelp_cpa_unit(pt[f->icrs], &ux, &uy);
    double c = kelp_cpa_fast_eval_unit(&f->cpa, ux, uy, pt[f->ispd], NULL);
    if (c < f->min_util) return 0;
    if (c > f->max_util || f->max_util <= f->min_util) return 100;
    return 25.0 + 75.0 * (c - f->min_util) / (f->max_util - f->min_util);
}

/* The AvoidCollision function the helm built (through the Reflector's line sampler) is the
 * point-by-point Reflector's, bit for bit: the last instance's function of the 20-contact
 * encounter against a build of the same objective (the helm's workspace keeps it) through
 * ref_aof; kelp_helm_bhv_avoid_aof_eval (hypot in place of the square root) within 1e-9. */
START_TEST(avoid_function_as_point_build)
{
    static kelp_ivp_piece ref[4096];
    static kelp_ivp_pq_entry w[4096];
    double d[2 * PIN_PAIRS];
    ck_assert_int_eq(pin_run(20, d), PIN_PAIRS);
    unsigned i = p_h.nbhv - 1;
    ck_assert_str_eq(p_h.bhv[i].ops->type, "BHV_AvoidCollision");
    const kelp_ivp_func *got = &p_h.fn[i];
    kelp_ivp_reflector r;
    kelp_ivp_func f;
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &p_h.bhv[i].dom, ref_aof, &p_h.ws_bhv.avd_aof), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "uniform_piece", "discrete @ course:3,speed:3"), 0);
    ck_assert_int_eq(kelp_ivp_reflector_create(&r, -1, -1, 0, ref, 4096, w, 4096, &f), (int)got->n);
    ck_assert_int_eq(kelp_ivp_func_normalize(&f, 0, 100), 0);
    unsigned flat = 0;
    for (size_t j = 0; j < f.n; j++) {
        const kelp_ivp_piece *a = &ref[j], *b = &got->pcs[j];
        ck_assert(memcmp(a->lo, b->lo, sizeof a->lo) == 0 && memcmp(a->hi, b->hi, sizeof a->hi) == 0);
        ck_assert_msg(a->slope[0] == b->slope[0] && a->slope[1] == b->slope[1] && a->cst == b->cst,
                      "piece %zu: %.17g %.17g %.17g, point by point %.17g %.17g %.17g", j, b->slope[0], b->slope[1],
                      b->cst, a->slope[0], a->slope[1], a->cst);
        flat += a->slope[0] == 0 && a->slope[1] == 0;
    }
    ck_assert_uint_gt(flat, 0);            /* both kinds of piece met */
    ck_assert_uint_lt(flat, (unsigned)f.n);
    ck_assert_int_eq(kelp_ivp_reflector_init(&r, &p_h.bhv[i].dom, kelp_helm_bhv_avoid_aof_eval, &p_h.ws_bhv.avd_aof), 0);
    ck_assert_int_eq(kelp_ivp_reflector_set_param(&r, "uniform_piece", "discrete @ course:3,speed:3"), 0);
    ck_assert_int_eq(kelp_ivp_reflector_create(&r, -1, -1, 0, ref, 4096, w, 4096, &f), (int)got->n);
    ck_assert_int_eq(kelp_ivp_func_normalize(&f, 0, 100), 0);
    for (size_t j = 0; j < f.n; j++)
        ck_assert(fabs(ref[j].cst - got->pcs[j].cst) < 1e-9 && fabs(ref[j].slope[1] - got->pcs[j].slope[1]) < 1e-9);
}
END_TEST

Suite *kelp_helm_avoid_pin_suite(void)
{
    Suite *s = suite_create("helm_avoid_pin");
    TCase *tc = tcase_create("pinned");
    tcase_set_timeout(tc, 120);
    tcase_add_loop_test(tc, avoid_decisions_pinned, 0, 3);
    tcase_add_test(tc, avoid_function_as_point_build);
    suite_add_tcase(s, tc);
    return s;
}
#endif
