/* Helm framework unit tests: the information buffer, run conditions, every general behaviour
 * parameter of seed 004 section 4.2 (condition transitions, flags, endflag, updates, duration
 * and its status/reset/idle-decay, perpetual, nostarve, post_mapping, priority), the call
 * order, the duplicate filter, all-stop and .bhv loading. The ht_* harness is shared with
 * check_bhv.c. */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/helm.h>
#include <kelp/mission.h>
#include "check_ht.h"

/* ---------------------------------------------------------------- harness */

#define HT_MAXPOST 4096

static kelp_helm g_h;
static kelp_ivp_piece g_pool[16384], g_tmp[4096];
static double g_dwork[4096];
static kelp_ivp_pq_entry g_pq[8192];
static unsigned char g_solve[4 << 20];
static ht_post g_posts[HT_MAXPOST];
static unsigned g_nposts;
static unsigned long g_iter;
static kelp_mission_node g_nodes[512];

static void ht_sink(const kelp_helm_post *p, void *user)
{
    (void)user;
    if (g_nposts >= HT_MAXPOST)
        return;
    ht_post *q = &g_posts[g_nposts++];
    snprintf(q->var, sizeof q->var, "%s", p->var);
    q->is_str = p->is_str;
    snprintf(q->sval, sizeof q->sval, "%s", p->is_str ? p->sval : "");
    q->dval = p->dval;
    q->iter = g_iter;
}


kelp_helm *ht_helm(void)
{
    return &g_h;
}

static void (*g_tweak)(kelp_helm_config *cfg); /* one test's configuration changes */

kelp_helm *ht_setup(const char *domain, const kelp_bhv_ops *const *types)
{
    kelp_helm_config cfg;
    kelp_helm_config_default(&cfg);
    cfg.start_engaged = true; /* most tests drive; helm_starts_parked checks the default */
    if (g_tweak) g_tweak(&cfg), g_tweak = NULL;
    kelp_diag e = {0};
    ck_assert_int_eq(kelp_ivp_domain_parse(&cfg.domain, domain, &e), 0);
    snprintf(cfg.us, sizeof cfg.us, "alder");
    cfg.sink = ht_sink;
    cfg.types = types;
    kelp_helm_mem mem = {g_pool, 16384, g_tmp, 4096, g_dwork, 4096, g_pq, 8192, g_solve, sizeof g_solve};
    ck_assert_int_eq(kelp_helm_init(&g_h, &cfg, &mem), 0);
    g_nposts = 0;
    g_iter = 0;
    return &g_h;
}

int ht_load_rc(const char *bhv)
{
    static char text[16384];
    snprintf(text, sizeof text, "%s", bhv);
    kelp_mission m;
    int rc = kelp_mission_parse(&m, text, strlen(text), g_nodes, 512);
    if (rc < 0)
        return rc;
    rc = kelp_helm_load_bhv(&g_h, &m);
    if (rc < 0)
        return rc;
    return kelp_helm_configured(&g_h);
}

void ht_load(const char *bhv)
{
    int rc = ht_load_rc(bhv);
    ck_assert_msg(rc == 0, "load failed: line %d: %s", g_h.diag.line, kelp_diag_text(&g_h.diag));
    kelp_helm_start(&g_h, 1000.0);
}

/* One iteration at buffer time t (MOOS time 1000 + t); the post log keeps only this one. */
void ht_iter(double t)
{
    g_nposts = 0;
    g_iter++;
    ck_assert_int_eq(kelp_helm_iterate(&g_h, 1000.0 + t), 0);
}

const ht_post *ht_last(const char *var)
{
    for (unsigned i = g_nposts; i-- > 0;)
        if (!strcmp(g_posts[i].var, var))
            return &g_posts[i];
    return NULL;
}

unsigned ht_count(const char *var)
{
    unsigned n = 0;
    for (unsigned i = 0; i < g_nposts; i++)
        n += !strcmp(g_posts[i].var, var);
    return n;
}

bool ht_has_str(const char *var, const char *val)
{
    for (unsigned i = 0; i < g_nposts; i++)
        if (!strcmp(g_posts[i].var, var) && g_posts[i].is_str && !strcmp(g_posts[i].sval, val))
            return true;
    return false;
}

/* a string post of var this iteration containing sub */
bool ht_has_sub(const char *var, const char *sub)
{
    for (unsigned i = 0; i < g_nposts; i++)
        if (!strcmp(g_posts[i].var, var) && g_posts[i].is_str && strstr(g_posts[i].sval, sub))
            return true;
    return false;
}

double ht_num(const char *var)
{
    const ht_post *p = ht_last(var);
    ck_assert_msg(p != NULL, "%s not posted", var);
    ck_assert_msg(!p->is_str, "%s is a string", var);
    return p->dval;
}

static kelp_bhv *bhv(const char *name)
{
    kelp_bhv *b = kelp_helm_find(&g_h, name);
    ck_assert_msg(b != NULL, "no behaviour %s", name);
    return b;
}

static void nav(double x, double y)
{
    kelp_helm_mail_double(&g_h, "NAV_X", x);
    kelp_helm_mail_double(&g_h, "NAV_Y", y);
    kelp_helm_mail_double(&g_h, "NAV_HEADING", 0); /* 24.8's waypoint needs a heading */
}

#define DOM2 "course:0:359:360,speed:0:4:21"

/* A test behaviour type ("BHV_Probe"): produces a constant-speed function when PROBE_FN is
 * "yes", calls postEMessage when PROBE_ERR = 1, setComplete when PROBE_DONE = 1, records the
 * per-iteration vector of PROBE_VEC, post_int of PROBE_INT, and accepts parameter "level". */
typedef struct probe_state {
    double level;
    unsigned nvec;
    double vec[8];
    double seen_now, seen_time;
} probe_state;

static void probe_init(kelp_bhv *b)
{
    kelp_ivp_domain d;
    if (kelp_ivp_domain_sub(&b->helm->cfg.domain, "speed", &d) == 0)
        b->dom = d;
    ck_assert_int_eq(kelp_helm_bhv_add_info_vars(b, "PROBE_FN, PROBE_ERR, PROBE_DONE, PROBE_VEC, PROBE_INT"), 0);
}

static int probe_set(kelp_bhv *b, const char *p, const char *v)
{
    probe_state *s = (probe_state *)(void *)b->u.raw;
    double d;
    if (!strcmp(p, "level")) {
        if (kelp_util_parse_double(v, strlen(v), &d) || d < 0)
            return KELP_ERR_PARSE;
        s->level = d;
        return 0;
    }
    return KELP_ERR_NOTFOUND;
}

static int probe_run(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    probe_state *s = (probe_state *)(void *)b->u.raw;
    char buf[32];
    double d;
    s->nvec = 0;
    while (s->nvec < 8 && kelp_helm_bhv_buf_delta(b, "PROBE_VEC", s->nvec, &s->vec[s->nvec], NULL))
        s->nvec++;
    s->seen_now = kelp_helm_bhv_buf_now(b);
    s->seen_time = kelp_helm_bhv_buf_time(b, "PROBE_VEC");
    if (kelp_helm_bhv_buf_double(b, "PROBE_INT", &d))
        kelp_helm_bhv_post_int(b, "PROBE_INT_OUT", d, NULL);
    if (kelp_helm_bhv_buf_double(b, "PROBE_ERR", &d) && d == 1)
        kelp_helm_bhv_post_error(b, "probe error");
    if (kelp_helm_bhv_buf_double(b, "PROBE_DONE", &d) && d == 1)
        kelp_helm_bhv_set_complete(b);
    kelp_helm_bhv_post_double(b, "PROBE_LEVEL", s->level, NULL);
    if (!kelp_helm_bhv_buf_string(b, "PROBE_FN", buf, sizeof buf) || strcmp(buf, "yes"))
        return 0;
    kelp_ivp_zaic_peak z;
    ck_assert_int_eq(kelp_ivp_zaic_peak_init(&z, &b->dom, "speed"), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_set_params(&z, 1.0, 0, 1, 0, 0, 100, 0), 0);
    ck_assert_int_eq(kelp_ivp_zaic_peak_extract(&z, true, w->dwork, w->dwork_cap, w->out, w->out_cap, out), 0);
    return 1;
}

static const kelp_bhv_ops probe_ops = {"BHV_Probe", probe_init, probe_set, NULL, NULL, probe_run, NULL, NULL, NULL};
static const kelp_bhv_ops *const probe_types[] = {&probe_ops, &kelp_bhv_simple_waypoint_ops, NULL};

static probe_state *probe(const char *name)
{
    return (probe_state *)(void *)bhv(name)->u.raw;
}

/* ---------------------------------------------------------------- information buffer */

START_TEST(ib_values_times_vectors)
{
    static kelp_helm_ib ib;
    kelp_helm_ib_init(&ib);
    double d = 0;
    char s[32];
    ck_assert(!kelp_helm_ib_double(&ib, "X", &d));
    ck_assert(kelp_helm_ib_time(&ib, "UNKNOWN") == -1.0);
    ck_assert_int_eq(kelp_helm_ib_set_double(&ib, "X", 1, 5.0, true), 0);
    ck_assert_int_eq(kelp_helm_ib_set_double(&ib, "X", 2, 5.0, true), 0);
    ck_assert_int_eq(kelp_helm_ib_set_string(&ib, "S", "3.5", 6.0, true), 0);
    ck_assert_int_eq(kelp_helm_ib_set_double(&ib, "X", 3, 7.0, true), 0);
    ck_assert(kelp_helm_ib_double(&ib, "X", &d) && d == 3);
    ck_assert(kelp_helm_ib_time(&ib, "X") == 7.0);
    ck_assert(kelp_helm_ib_double(&ib, "S", &d) && d == 3.5); /* numeric string as double */
    ck_assert(kelp_helm_ib_string(&ib, "X", s, sizeof s) && !strcmp(s, "3"));
    ck_assert_uint_eq(kelp_helm_ib_ndeltas(&ib, "X"), 3);
    double v[3];
    for (unsigned k = 0; k < 3; k++)
        ck_assert(kelp_helm_ib_delta(&ib, "X", k, &v[k], NULL));
    ck_assert(v[0] == 1 && v[1] == 2 && v[2] == 3); /* oldest first */
    ck_assert(!kelp_helm_ib_delta(&ib, "X", 3, NULL, NULL));
    const char *sv = NULL;
    ck_assert(kelp_helm_ib_delta(&ib, "S", 0, NULL, &sv) && !strcmp(sv, "3.5"));
    kelp_helm_ib_clear_deltas(&ib);
    ck_assert_uint_eq(kelp_helm_ib_ndeltas(&ib, "X"), 0);
    ck_assert(kelp_helm_ib_double(&ib, "X", &d) && d == 3); /* latest value survives */
    char big[KELP_HELM_MAX_SVAL + 8];
    memset(big, 'a', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    ck_assert_int_eq(kelp_helm_ib_set_string(&ib, "BIG", big, 1, true), KELP_ERR_RANGE);
    ck_assert_uint_eq(ib.dropped, 1);
}
END_TEST

START_TEST(ib_same_snapshot_and_mail_time)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p1\n}\nBehavior = BHV_Probe\n{\n name = p2\n}\n");
    ht_iter(0);
    kelp_helm_mail_double(&g_h, "PROBE_VEC", 1);
    kelp_helm_mail_double(&g_h, "PROBE_VEC", 2);
    kelp_helm_mail_double(&g_h, "PROBE_VEC", 3);
    ht_iter(2.5);
    /* both behaviours saw the same values, oldest first, time == buffer time (seed 4.5.4) */
    for (int i = 0; i < 2; i++) {
        probe_state *s = probe(i ? "p2" : "p1");
        ck_assert_uint_eq(s->nvec, 3);
        ck_assert(s->vec[0] == 1 && s->vec[1] == 2 && s->vec[2] == 3);
        ck_assert(s->seen_now == 2.5);
        ck_assert(s->seen_time == s->seen_now);
    }
    ht_iter(3.0); /* no new mail: empty vector, old time */
    ck_assert_uint_eq(probe("p1")->nvec, 0);
    ck_assert(probe("p1")->seen_time == 2.5);
}
END_TEST

/* ---------------------------------------------------------------- conditions */

typedef struct cond_case {
    const char *cond;
    int expect;
} cond_case;

static const cond_case g_conds[] = {
    {"DEPLOY = true", 1},
    {"DEPLOY == true", 1},
    {"DEPLOY = TRUE", 1},          /* true/false literals ignore case */
    {"DEPLOY != true", 0},
    {"RETURN = false", 1},
    {"MODE = survey", 0},          /* other strings are case-sensitive */
    {"MODE = Survey", 1},
    {"MODE = \"Survey\"", 1},
    {"(K <= 4)", 1},
    {"(K < 4)", 0},
    {"(K >= 4)", 1},
    {"K > 3.5", 1},
    {"(4 >= K)", 1},               /* the word is the variable */
    {"(5 < K)", 0},
    {"KS = 4", 1},                 /* numeric string compares numerically */
    {"KS < 10", 1},
    {"UNKNOWN = true", 0},         /* unknown variable: false */
    {"UNKNOWN != true", 0},
    {"DEPLOY = true and K <= 4", 1},
    {"DEPLOY = true && K > 4", 0},
    {"DEPLOY = false or K = 4", 1},
    {"DEPLOY = false || K = 5", 0},
    {"not (K = 5)", 1},
    {"!(K = 4)", 0},
    {"(DEPLOY = true) and ((K < 2) or (MODE = Survey))", 1},
    {"$(K) = $(KS)", 1},
    {"$(K) < $(J)", 1},
    {"MODE < Tango", 1},           /* lexical ordering of strings */
    {"MODE > 3", 0},               /* ordering a string against a number */
    /* precedence and nesting (the parser keeps an explicit stack, not recursion) */
    {"K = 5 or K = 4 and J = 9", 1},       /* and binds tighter than or */
    {"(K = 5 or K = 4) and J = 8", 0},
    {"not K = 5 and not not J = 9", 1},    /* not binds to one factor */
    {"not (K = 4 and J = 9) or MODE = Survey", 1},
    {"not (K = 4 and (J = 9 or (MODE = x)))", 0},
    {"((K = 4)) and ((J = 9) or (K = 1))", 1},
    {"K = 4 and (J = 1 or (MODE = Survey and not (DEPLOY = false)))", 1},
    {"K = 4 or J = 9 or MODE = x and DEPLOY = false", 1},
    {"K = 4 and ()", -1},
    {"(K = 4))", -1},
    {"((K = 4)", -1},
    {"K = 4 (J = 9)", -1},
    {"not", -1},
    {"K = 4 or not", -1},
    {"DEPLOY", -1},
    {"DEPLOY =", -1},
    {"= true", -1},
    {"(K <= 4", -1},
    {"K <= 4)", -1},
    {"DEPLOY = true and", -1},
    {"MODE = \"Survey", -1},
    {"K <> 4", -1},
    {"", -1},
    /* "==": 24.8's field match on ':' components (hierarchical modes) */
    {"HMODE == SURVEYING", 1},
    {"HMODE == ACTIVE:SURVEYING", 1},
    {"HMODE == \"ACTIVE: SURVEYING\"", 0},  /* one side must first be a substring of the other */
    {"HMODE == ACTIVE:SURVEYING:NORTH", 1},
    {"HMODE = SURVEYING", 0},              /* "=": the whole value */
    {"HMODE == SURVEY", 0},                /* a substring is not a component */
    {"HMODE == ACTIVE:NORTH", 0},          /* components in a row */
    {"$(HMODE) == SURVEYING", 1},
    {"SURVEYING == $(HMODE)", 1},          /* either side may be the shorter */
    {"MODE == Survey", 1},
    {"K == 4", 1},                         /* numbers: equality */
    {"H5 == A:B:C", 1},                    /* a run of three (24.8 misses it: docs/CONFORMANCE.md) */
    {"H5 == A:C", 0},
    {"H5 == A:B", 1},
};

START_TEST(condition_grammar)
{
    static kelp_helm_ib ib;
    kelp_helm_ib_init(&ib);
    ck_assert_int_eq(kelp_helm_ib_set_string(&ib, "DEPLOY", "true", 0, false), 0);
    ck_assert_int_eq(kelp_helm_ib_set_string(&ib, "RETURN", "false", 0, false), 0);
    ck_assert_int_eq(kelp_helm_ib_set_string(&ib, "MODE", "Survey", 0, false), 0);
    ck_assert_int_eq(kelp_helm_ib_set_double(&ib, "K", 4, 0, false), 0);
    ck_assert_int_eq(kelp_helm_ib_set_double(&ib, "J", 9, 0, false), 0);
    ck_assert_int_eq(kelp_helm_ib_set_string(&ib, "KS", "4", 0, false), 0);
    ck_assert_int_eq(kelp_helm_ib_set_string(&ib, "HMODE", "ACTIVE:SURVEYING:NORTH", 0, false), 0);
    ck_assert_int_eq(kelp_helm_ib_set_string(&ib, "H5", "X:A:B:C:D", 0, false), 0);
    const cond_case *c = &g_conds[_i];
    int rc = kelp_helm_cond_eval(c->cond, &ib);
    if (c->expect < 0) {
        ck_assert_msg(rc == KELP_ERR_PARSE, "'%s' should not parse (got %d)", c->cond, rc);
        ck_assert_int_eq(kelp_helm_cond_check(c->cond, NULL, NULL), KELP_ERR_PARSE);
    } else {
        ck_assert_msg(rc == c->expect, "'%s' gave %d, expected %d", c->cond, rc, c->expect);
        ck_assert_int_eq(kelp_helm_cond_check(c->cond, NULL, NULL), 0);
    }
}
END_TEST

static void collect(const char *v, size_t n, void *user)
{
    char *out = user;
    strncat(out, v, n);
    strcat(out, ";");
}

/* nesting is bounded (KELP_HELM_COND_MAX_DEPTH): the recursive parser's stack stays bounded */
START_TEST(condition_nesting_bounded)
{
    char c[512];
    for (unsigned depth = 1; depth <= KELP_HELM_COND_MAX_DEPTH + 4; depth++) {
        size_t n = 0;
        for (unsigned i = 0; i < depth; i++) c[n++] = '(';
        n += (size_t)snprintf(c + n, sizeof c - n, "A = 1");
        for (unsigned i = 0; i < depth; i++) c[n++] = ')';
        c[n] = 0;
        int want = depth <= KELP_HELM_COND_MAX_DEPTH ? 0 : KELP_ERR_PARSE;
        ck_assert_msg(kelp_helm_cond_check(c, NULL, NULL) == want, "depth %u", depth);
    }
    ck_assert_int_eq(kelp_helm_cond_check("not not (not (A = 1))", NULL, NULL), 0);
}
END_TEST

START_TEST(condition_variables_registered)
{
    char vars[128] = "";
    ck_assert_int_eq(kelp_helm_cond_check("(A = 1) and (4 > B) or $(C) = x", collect, vars), 0);
    ck_assert_str_eq(vars, "A;B;C;");
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_SimpleWaypoint\n{\n condition = (K <= 4) and MODE = go\n updates = UPD\n"
            " nostarve = NAV_HEADING, 3\n duration = 5\n duration_reset = RST=true\n}\n");
    char all[512] = "";
    for (const char *v; (v = kelp_helm_next_new_var(&g_h)) != NULL;) {
        strcat(all, v);
        strcat(all, ";");
    }
    ck_assert_ptr_nonnull(strstr(all, "NAV_X;NAV_Y;"));
    ck_assert_ptr_nonnull(strstr(all, "K;MODE;"));
    ck_assert_ptr_nonnull(strstr(all, "UPD;"));
    ck_assert_ptr_nonnull(strstr(all, "NAV_HEADING;"));
    ck_assert_ptr_nonnull(strstr(all, "RST;"));
    ck_assert_ptr_nonnull(strstr(all, "MOOS_MANUAL_OVERIDE;"));
    ck_assert_ptr_null(kelp_helm_next_new_var(&g_h)); /* each name once */
}
END_TEST

/* ---------------------------------------------------------------- parameters */

typedef struct param_case {
    const char *param, *value;
    int ok;
} param_case;

static const param_case g_params[] = {
    {"name", "transit", 1}, {"NAME", "x", 1}, {"descriptor", "d", 1}, {"name", "", 0},
    {"pwt", "50", 1}, {"priority", "0", 1}, {"PRIWT", "7.5", 1}, {"pwt", "-1", 0}, {"pwt", "abc", 0},
    {"condition", "A = 1", 1}, {"condition", "A =", 0},
    {"runflag", "RUNNING = true", 1}, {"idleflag", "WAITING=true", 1}, {"activeflag", "A=1", 1},
    {"inactiveflag", "B = x y", 1}, {"endflag", "RETURN = true", 1}, {"endflag", "RETURN", 0},
    {"endflag", "= true", 0}, {"endflag", "TWO WORDS = true", 0},
    {"updates", "WPT_UPDATES", 1}, {"updates", "TWO WORDS", 0},
    {"duration", "10", 1}, {"duration", "0", 0}, {"duration", "-5", 0}, {"duration", "abc", 0},
    {"duration", "no-time-limit", 1}, {"duration", "-1", 1},
    {"duration_status", "DS", 1}, {"duration_reset", "BRAVO_TIMER_RESET=true", 1}, {"duration_reset", "X", 0},
    {"duration_idle_decay", "false", 1}, {"duration_idle_decay", "FALSE", 1}, {"duration_idle_decay", "no", 0},
    {"perpetual", "true", 1}, {"perpetual", "TRUE", 1}, {"perpetual", "False", 1}, {"perpetual", "yes", 0},
    {"post_mapping", "WPT_STAT, WAYPT_STATUS", 1}, {"post_mapping", "WPT_STAT", 0}, {"post_mapping", ", X", 0},
    {"nostarve", "NAV_X, NAV_Y, 5.0", 1}, {"no_starve", "NAV_X, 3", 1}, {"nostarve", "NAV_X", 0},
    {"nostarve", "NAV_X, 0", 0}, {"nostarve", "NAV_X, abc", 0}, {"nostarve", ", 5", 0},
    {"_pwt", "20", 1}, {"no_such_param", "1", 0},
    {"ptx", "60", 1}, {"PTY", "-40", 1}, {"speed", "2", 1}, {"speed", "0", 0}, {"speed", "-1", 0},
    {"speed", "abc", 0}, {"radius", "0", 0}, {"radius", "8", 1}, {"ipf_type", "foo", 0},
    {"IPF_TYPE", "ZAIC", 1}, {"ipf_type", "Reflector", 1}, {"ptx", "sixty", 0},
};

START_TEST(general_parameters)
{
    ht_setup(DOM2, NULL);
    kelp_bhv *b;
    ck_assert_int_eq(kelp_helm_add(&g_h, "BHV_SimpleWaypoint", &b), 0);
    const param_case *c = &g_params[_i];
    b->fail = NULL;
    int rc = kelp_helm_bhv_set_param(b, c->param, c->value);
    ck_assert_msg((rc == 0) == (c->ok == 1), "%s = %s: rc %d", c->param, c->value, rc);
    if (!c->ok)
        ck_assert_ptr_nonnull(b->fail);
}
END_TEST

START_TEST(parameter_values_stored)
{
    ht_setup(DOM2, NULL);
    kelp_bhv *b;
    ck_assert_int_eq(kelp_helm_add(&g_h, "bhv_simplewaypoint", &b), 0); /* type case-insensitive */
    ck_assert_str_eq(b->name, "simple_waypoint");  /* Listing 9 default name */
    ck_assert(b->pwt == 100);                       /* default priority */
    ck_assert(b->duration < 0 && b->duration_idle_decay && !b->perpetual);
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "priority", "35"), 0);
    ck_assert(b->pwt == 35);
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "perpetual", "TRUE"), 0);
    ck_assert(b->perpetual);
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "endflag", "RETURN = true"), 0);
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "endflag", "COUNT = 3"), 0);
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "endflag", "MSG = \"42\""), 0);
    ck_assert_uint_eq(b->nflag, 3);
    ck_assert_str_eq(b->flag[0].p.var, "RETURN");
    ck_assert(b->flag[0].p.is_str && !strcmp(b->flag[0].p.sval, "true"));
    ck_assert(!b->flag[1].p.is_str && b->flag[1].p.dval == 3);  /* numbers post as doubles */
    ck_assert(b->flag[2].p.is_str && !strcmp(b->flag[2].p.sval, "42"));
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "nostarve", "NAV_X, NAV_Y, 5.0"), 0);
    ck_assert_uint_eq(b->nstarve, 2);
    ck_assert_str_eq(b->starve[1], "NAV_Y");
    ck_assert(b->starve_time == 5.0);
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "duration_reset", "BRAVO_TIMER_RESET = true"), 0);
    ck_assert_str_eq(b->duration_reset_var, "BRAVO_TIMER_RESET");
    ck_assert_str_eq(b->duration_reset_val, "true");
    ck_assert_int_eq(kelp_helm_bhv_set_param(b, "PTY", "-40"), 0);
    ck_assert(b->u.swpt.nextpt.y == -40);
}
END_TEST

/* ---------------------------------------------------------------- .bhv loading */

static const char *ALDER =
    "//----- FILE: alder.bhv -----\n\n"
    "initialize  DEPLOY = false\n"
    "initialize  RETURN = false\n\n"
    "//-----\n"
    "Behavior = BHV_SimpleWaypoint\n{\n"
    "    name      = transit_to_point\n    pwt       = 100\n"
    "    condition = RETURN = false\n    condition = DEPLOY = true\n    endflag   = RETURN = true\n\n"
    "    speed = 2.0 // meters per second\n    radius = 8.0\n    ptx = 60\n    pty = -40\n    ipf_type = zaic\n}\n\n"
    "//-----\n"
    "Behavior = BHV_SimpleWaypoint\n{\n"
    "    name      = waypt_return\n    pwt       = 100\n"
    "    condition = RETURN = true\n    condition = DEPLOY = true\n\n"
    "    speed = 2.0\n    radius = 8.0\n    ptx = 0\n    pty = 0\n    ipf_type = reflector\n}\n";

START_TEST(load_alder_and_initialize)
{
    ht_setup(DOM2, NULL);
    ht_load(ALDER);
    ck_assert_uint_eq(g_h.nbhv, 2);
    ck_assert_str_eq(g_h.bhv[0].name, "transit_to_point");
    ck_assert(g_h.bhv[0].u.swpt.nextpt.x == 60 && g_h.bhv[0].u.swpt.nextpt.y == -40);
    ck_assert(g_h.bhv[0].u.swpt.desired_speed == 2.0 && g_h.bhv[0].u.swpt.arrival_radius == 8.0);
    ck_assert(!g_h.bhv[0].u.swpt.reflector && g_h.bhv[1].u.swpt.reflector);
    ck_assert_uint_eq(g_h.bhv[0].ncond, 2);
    /* kelp_helm_start posted the initialize values (as strings) */
    ck_assert(ht_has_str("DEPLOY", "false") && ht_has_str("RETURN", "false"));
    ck_assert_uint_eq(ht_count("DEPLOY"), 1);
}
END_TEST

START_TEST(load_initialize_forms)
{
    ht_setup(DOM2, NULL);
    ht_load("initialize A = 5, B = hello, C = \"7\"\ninitialize_ D = later\ninitialize_ E = x\n");
    ck_assert(ht_num("A") == 5);
    ck_assert(ht_has_str("B", "hello") && ht_has_str("C", "7"));
    ck_assert_uint_eq(ht_count("D"), 0); /* deferred */
    kelp_helm_mail_string(&g_h, "E", "already");
    ht_iter(0);
    ck_assert(ht_has_str("D", "later"));   /* still unknown: posted at the first iteration */
    ck_assert_uint_eq(ht_count("E"), 0);   /* known by then: not posted */
}
END_TEST

typedef struct bad_file {
    const char *text;
    int line;
    const char *msg;
} bad_file;

static const bad_file g_bad[] = {
    {"Behavior = BHV_Nope\n{\n name = x\n}\n", 1, "unknown behaviour type BHV_Nope"},
    {"Behavior = BHV_SimpleWaypoint\n{\n name = x\n speed = 0\n}\n", 4, "bad parameter speed"},
    {"Behavior = BHV_SimpleWaypoint\n{\n bogus = 1\n}\n", 3, "bad parameter bogus"},
    {"Behavior = BHV_SimpleWaypoint\n{\n condition = (A = \n}\n", 3, "malformed condition"},
    {"initialize = 5\n", 1, "bad initialize"},
    {"initialize TWO WORDS = 5\n", 1, "bad initialize"},
    {"set MODE = ACTIVE\n", 1, "unexpected line"},
    {"Behavior = BHV_Waypoint\n{\n speed = 2\n points = 1,2:zz\n}\n", 4, "bad parameter points"},
};

START_TEST(load_errors_name_the_line)
{
    ht_setup(DOM2, NULL);
    int rc = ht_load_rc(g_bad[_i].text);
    ck_assert_int_lt(rc, 0);
    ck_assert_int_eq(g_h.diag.code, rc);
    ck_assert_int_eq(g_h.diag.line, g_bad[_i].line);
#ifndef KELP_NO_ERRMSG
    ck_assert_msg(strstr(g_h.diag.msg, g_bad[_i].msg) != NULL, "error '%s' lacks '%s'", g_h.diag.msg, g_bad[_i].msg);
#endif
}
END_TEST

START_TEST(null_domain_refused_at_launch)
{
    ht_setup("course:0:359:360", NULL); /* no speed: subDomain("course,speed") is null */
    int rc = ht_load_rc("Behavior = BHV_SimpleWaypoint\n{\n name = s\n}\n");
    ck_assert_int_lt(rc, 0);
    ck_assert_int_eq(g_h.diag.code, KELP_ERR_STATE);
    ck_diag_has(&g_h.diag, "null IvP domain");
}
END_TEST

/* ---------------------------------------------------------------- run states and flags */

static const char *FLAGS =
    "Behavior = BHV_Probe\n{\n name = p\n condition = GO = true\n"
    " runflag = RUNF = 1\n idleflag = IDLEF = 1\n activeflag = ACTF = 1\n inactiveflag = INACTF = 1\n"
    " endflag = ENDF = 1\n}\n";

START_TEST(condition_transitions_and_flags)
{
    ht_setup(DOM2, probe_types);
    ht_load(FLAGS);
    /* no GO: idle; first iteration posts idle and inactive flags */
    ht_iter(0);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_IDLE);
    ck_assert(ht_count("IDLEF") == 1 && ht_count("INACTF") == 1 && ht_count("RUNF") == 0);
    ht_iter(1); /* still idle: flags only on transitions */
    ck_assert(ht_count("IDLEF") == 0 && ht_count("INACTF") == 0);
    /* condition true: running (no function: not active) */
    kelp_helm_mail_string(&g_h, "GO", "true");
    ht_iter(2);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ck_assert(ht_count("RUNF") == 1 && ht_count("ACTF") == 0);
    ck_assert_str_eq(g_h.rep.allstop, "NothingToDo");
    /* the zeros came once, on iteration 1 (postAllStop posts a reason only when it changes) */
    ck_assert_uint_eq(ht_count("DESIRED_SPEED"), 0);
    ck_assert_uint_eq(ht_count("IVPHELM_ALLSTOP"), 0);
    /* function produced: active */
    kelp_helm_mail_string(&g_h, "PROBE_FN", "yes");
    ht_iter(3);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_ACTIVE);
    ck_assert(ht_count("ACTF") == 1 && ht_count("RUNF") == 0);
    ck_assert(g_h.rep.decided[1] && g_h.rep.decision[1] == 1.0);
    ck_assert(!g_h.rep.decided[0]);
    ck_assert_str_eq(g_h.rep.allstop, "MissingDecVars:course"); /* course undecided */
    ck_assert(ht_num("DESIRED_SPEED") == 0);                      /* so all-stop zeros */
    ck_assert(ht_has_str("BHV_ERROR", "MissingDecVars:course"));
    /* the function, serialised as 24.8's BHV_IPF: context "<iteration>:<behaviour>", in one
     * packet "P,<behaviour>^<iteration>,1,1," (HelmIvP's IvPFunctionToVector) */
    ck_assert_uint_eq(ht_count("BHV_IPF"), 1);
    char ctx[32], pk[32];
    snprintf(ctx, sizeof ctx, ",%lu:p,", g_h.dec_iter);
    snprintf(pk, sizeof pk, "P,p^%lu,1,1,H,", g_h.dec_iter);
    ck_assert_msg(!strncmp(ht_last("BHV_IPF")->sval, pk, strlen(pk)) && strstr(ht_last("BHV_IPF")->sval, ctx),
                  "%s", ht_last("BHV_IPF")->sval);
    ck_assert_uint_eq(g_h.ipf_posted, 1);
    /* no function again: inactive flag */
    kelp_helm_mail_string(&g_h, "PROBE_FN", "no");
    ht_iter(4);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ck_assert(ht_count("INACTF") == 1 && ht_count("IDLEF") == 0);
    ck_assert_uint_eq(ht_count("BHV_IPF"), 0);
    /* condition false: idle again */
    kelp_helm_mail_string(&g_h, "GO", "false");
    ht_iter(5);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_IDLE);
    ck_assert(ht_count("IDLEF") == 1 && ht_count("INACTF") == 1);
    ck_assert_uint_eq(ht_count("ENDF"), 0);
}
END_TEST

START_TEST(endflag_and_completed_forever)
{
    ht_setup(DOM2, probe_types);
    ht_load(FLAGS);
    kelp_helm_mail_string(&g_h, "GO", "true");
    kelp_helm_mail_double(&g_h, "PROBE_DONE", 1);
    ht_iter(0);
    /* setComplete in iteration n: end flags (and inactive flags) posted, still running in n */
    ck_assert_uint_eq(ht_count("ENDF"), 1);
    ck_assert_uint_eq(ht_count("INACTF"), 1);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ht_iter(1);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_COMPLETED);
    ck_assert_uint_eq(ht_count("ENDF"), 0);
    ck_assert_uint_eq(ht_count("PROBE_LEVEL"), 0); /* never runs again */
    kelp_helm_mail_string(&g_h, "GO", "false");
    ht_iter(2);
    kelp_helm_mail_string(&g_h, "GO", "true");
    ht_iter(3);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_COMPLETED);
    ck_assert(ht_count("IDLEF") == 0 && ht_count("RUNF") == 0);
    ck_assert_uint_eq(g_h.rep.ncompleted, 1);
}
END_TEST

START_TEST(endflag_reaches_buffer_next_iteration)
{
    /* Alder: transit's endflag RETURN=true makes waypt_return runnable at the next iteration
     * even without the bus echoing it (postings are written to the buffer). */
    ht_setup(DOM2, NULL);
    ht_load(ALDER);
    nav(0, 0);
    kelp_helm_mail_string(&g_h, "DEPLOY", "true");
    ht_iter(0);
    ck_assert_int_eq(bhv("transit_to_point")->state, KELP_BHV_ACTIVE);
    ck_assert_int_eq(bhv("waypt_return")->state, KELP_BHV_IDLE);
    nav(55, -36); /* 6.4 m from (60,-40) */
    ht_iter(1);
    ck_assert(ht_has_str("RETURN", "true"));
    ck_assert_int_eq(bhv("transit_to_point")->state, KELP_BHV_RUNNING);
    ck_assert_int_eq(bhv("waypt_return")->state, KELP_BHV_IDLE); /* same snapshot this iteration */
    ht_iter(2);
    ck_assert_int_eq(bhv("transit_to_point")->state, KELP_BHV_COMPLETED);
    ck_assert_int_eq(bhv("waypt_return")->state, KELP_BHV_ACTIVE);
    ck_assert(ht_has_str("IVPHELM_BHV_ACTIVE", "waypt_return"));
}
END_TEST

/* ---------------------------------------------------------------- updates */

START_TEST(updates_valid_same_iteration)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_SimpleWaypoint\n{\n name = WAYPT_RETURN\n speed = 2.0\n radius = 8.0\n ptx = 0\n pty = 0\n"
            " UPDATES = RETURN_UPDATES\n condition = DEPLOY = true\n}\n");
    nav(0, -100);
    kelp_helm_mail_string(&g_h, "DEPLOY", "true");
    ht_iter(0);
    ck_assert(ht_num("DESIRED_SPEED") == 2.0);
    ck_assert(ht_num("DESIRED_HEADING") == 0);
    kelp_helm_mail_string(&g_h, "RETURN_UPDATES", "ptx = 100 # pty=-100 # speed = 1.5");
    ht_iter(1); /* applied by checkUpdates before onRunState, in effect this iteration */
    ck_assert_msg(fabs(ht_num("DESIRED_SPEED") - 1.5) < 0.11, "speed %g", ht_num("DESIRED_SPEED")); /* 1.5 is off the 0.2 grid */
    ck_assert(ht_num("DESIRED_HEADING") == 90);
    ck_assert(bhv("WAYPT_RETURN")->u.swpt.desired_speed == 1.5);
    /* 24.8 counts it in the behaviour's updates=1/1 and posts no per-behaviour variable */
    ck_assert_uint_eq(bhv("WAYPT_RETURN")->good_updates, 1);
    ck_assert_uint_eq(ht_count("UH_WAYPT_RETURN"), 0);
    ck_assert_uint_eq(ht_count("BHV_WARNING"), 0);
}
END_TEST

START_TEST(updates_bad_pairs_ignored_with_warning)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_SimpleWaypoint\n{\n name = WAYPT_RETURN\n speed = 2.0\n ptx = 0\n pty = 0\n"
            " updates = RETURN_UPDATES\n}\n");
    nav(0, -100);
    kelp_helm_mail_string(&g_h, "RETURN_UPDATES", "ptx = 50 # speed = abc");
    ht_iter(0);
    ck_assert(ht_has_str("BHV_WARNING", "Faulty update for behavior: WAYPT_RETURN. Bad parameter(s): speed."));
    kelp_bhv *b = bhv("WAYPT_RETURN");
    ck_assert(b->u.swpt.desired_speed == 2.0); /* bad pair ignored */
    ck_assert(b->u.swpt.nextpt.x == 50);       /* good pair of the same update applied */
    ck_assert_uint_eq(b->good_updates, 0);
    ck_assert_uint_eq(b->bad_updates, 1);
    ck_assert_uint_eq(ht_count("UH_WAYPT_RETURN"), 0);
    kelp_helm_mail_string(&g_h, "RETURN_UPDATES", "bogus = 1 # nonsense # speed = 3");
    ht_iter(1);
    ck_assert(ht_has_str("BHV_WARNING", "Faulty update for behavior: WAYPT_RETURN. Bad parameter(s): bogus,nonsense."));
    ck_assert(b->u.swpt.desired_speed == 3.0);
    /* a good update repeated verbatim is applied once */
    kelp_helm_mail_string(&g_h, "RETURN_UPDATES", "speed = 1");
    ht_iter(2);
    kelp_helm_mail_string(&g_h, "RETURN_UPDATES", "speed = 1");
    ht_iter(3);
    ck_assert_uint_eq(b->good_updates, 1);
    ck_assert_uint_eq(b->bad_updates, 2);
    /* general parameters update too (priority, condition) */
    kelp_helm_mail_string(&g_h, "RETURN_UPDATES", "priority = 40 # condition = GO = yes");
    ht_iter(4);
    ck_assert(b->pwt == 40 && b->ncond == 1);
    ck_assert_int_eq(b->state, KELP_BHV_IDLE);
}
END_TEST

/* IVPHELM_UPDATE_RESULT: one line per update read, MOOS-IvP's result words */
START_TEST(update_results_posted)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = survey\n speed = 2\n points = 0,0:100,0\n updates = WPT_UPDATE\n}\n");
    nav(0, -100);
    ht_iter(1); /* the start-up settings go out with the first engaged iteration (24.8) */
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 1);
    kelp_helm_mail_string(&g_h, "WPT_UPDATE", "speed = 1.5");
    ht_iter(2);
    ck_assert(ht_has_str("IVPHELM_UPDATE_RESULT", "bhv=survey,var=WPT_UPDATE,time=2.00,result=success,val=speed = 1.5"));
    ck_assert(ht_has_sub("BHV_STATUS", "name=survey,pwt=100.00000,pcs=") &&
              ht_has_sub("BHV_STATUS", ",state=active,updates=1/1"));
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 1); /* re-posted after an applied update */
    kelp_helm_mail_string(&g_h, "WPT_UPDATE", "speed = 1.5");
    ht_iter(3);
    ck_assert(ht_has_str("IVPHELM_UPDATE_RESULT", "bhv=survey,var=WPT_UPDATE,time=3.00,result=duplicate,val=speed = 1.5"));
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 0);
    ck_assert_uint_eq(ht_count("BHV_STATUS"), 0); /* unchanged: not posted again */
    kelp_helm_mail_string(&g_h, "WPT_UPDATE", "name=other # speed = 3");
    ht_iter(4);
    ck_assert(ht_has_str("IVPHELM_UPDATE_RESULT", "bhv=survey,var=WPT_UPDATE,time=4.00,result=name_mismatch,val=name=other # speed = 3"));
    ck_assert(bhv("survey")->u.wpt.speed == 1.5);
    kelp_helm_mail_string(&g_h, "WPT_UPDATE", "name=survey # speed = 3");
    ht_iter(5);
    ck_assert(ht_has_str("IVPHELM_UPDATE_RESULT", "bhv=survey,var=WPT_UPDATE,time=5.00,result=success,val=name=survey # speed = 3"));
    ck_assert(bhv("survey")->u.wpt.speed == 3);
    kelp_helm_mail_string(&g_h, "WPT_UPDATE", "speed = fast");
    ht_iter(6);
    ck_assert(ht_has_str("IVPHELM_UPDATE_RESULT", "bhv=survey,var=WPT_UPDATE,time=6.00,result=param_error,val=speed = fast"));
    ck_assert(ht_has_str("BHV_CONFIG_WARNING", "Faulty update for behavior: survey. Bad parameter(s): speed."));
    ck_assert(ht_has_sub("BHV_STATUS", "name=survey,pwt=100.00000,pcs=") &&
              ht_has_sub("BHV_STATUS", ",state=active,updates=2/3"));
    /* a repeated update carrying "toggle", "engage" or "mod" is applied again */
    kelp_helm_mail_string(&g_h, "WPT_UPDATE", "order = toggle");
    ht_iter(7);
    ck_assert(bhv("survey")->u.wpt.reverse);
    kelp_helm_mail_string(&g_h, "WPT_UPDATE", "order = toggle");
    ht_iter(8);
    ck_assert(ht_has_str("IVPHELM_UPDATE_RESULT", "bhv=survey,var=WPT_UPDATE,time=8.00,result=success,val=order = toggle"));
    ck_assert(!bhv("survey")->u.wpt.reverse);
}
END_TEST

/* 24.8's onSetParamComplete of a waypoint behaviour: the no-points warning's retraction, posted
 * as a BHV_WARNING (its text) once per behaviour, counted as no warning; a single point with
 * repeats warns */
static bool g_retract_seen;
static void retract_sink(const kelp_helm_post *p, void *user)
{
    if (p->retract) g_retract_seen = true;
    ht_sink(p, user);
}

START_TEST(bhv_wpt_retract_warning)
{
    ht_setup(DOM2, NULL);
    g_h.cfg.sink = retract_sink;
    g_retract_seen = false;
    ht_load("Behavior = BHV_Waypoint\n{\n name = survey\n speed = 2\n points = 0,0:100,0\n updates = WPT_UPDATE\n}\n"
            "Behavior = BHV_Waypoint\n{\n name = home\n speed = 2\n points = 0,-20\n repeat = 2\n}\n");
    nav(0, 0);
    ht_iter(0); /* with the first engaged iteration (24.8) */
    ck_assert(ht_has_str("BHV_WARNING", "survey: No waypts given. Set val to empty if intentional"));
    ck_assert(ht_has_str("BHV_WARNING", "home: No waypts given. Set val to empty if intentional"));
    ck_assert(ht_has_str("BHV_WARNING", "home: cycles/repeats not supported with single waypt"));
    ck_assert_uint_eq(ht_count("BHV_WARNING"), 3);
    ck_assert(g_retract_seen);
    ck_assert_uint_eq(g_h.rep.warnings, 1); /* the repeats warning only */
    /* the order of 24.8: the warnings, then the settings */
    unsigned iw = 0, is = 0;
    for (unsigned i = 0; i < g_nposts; i++) {
        if (!strcmp(g_posts[i].var, "BHV_WARNING") && strstr(g_posts[i].sval, "survey:")) iw = i + 1;
        if (!strcmp(g_posts[i].var, "BHV_SETTINGS") && strstr(g_posts[i].sval, "name=survey")) is = i + 1;
    }
    ck_assert(iw > 0 && is > iw);
    nav(0, -100);
    ht_iter(1);
    ck_assert_uint_eq(ht_count("BHV_WARNING"), 0);
    /* an applied update runs onSetParamComplete again: the settings change, the retraction
     * (same text, same key) is not posted again */
    kelp_helm_mail_string(&g_h, "WPT_UPDATE", "speed = 1.5");
    ht_iter(2);
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 1);
    ck_assert_uint_eq(ht_count("BHV_WARNING"), 0);
    ck_assert_uint_eq(g_h.rep.warnings, 1);
}
END_TEST

/* BHV_SETTINGS (waypoint, loiter) at start; BHV_STATUS per behaviour with "n/a" without updates */
START_TEST(bhv_settings_and_status)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = survey\n speed = 2.5\n points = 0,0:100,-20.25\n lead = 8\n"
            " capture_radius = 5\n slip_radius = 12\n repeat = forever\n}\n"
            "Behavior = BHV_Loiter\n{\n name = loiter\n speed = 1.5\n condition = GO = true\n"
            " polygon = 0,0:40,0:40,-30:0,-30\n clockwise = false\n}\n");
    nav(0, -100);
    kelp_helm_mail_double(&g_h, "NAV_HEADING", 0); /* the loiter needs a heading (24.8: an error without) */
    ht_iter(1);
    /* the start-up settings go out with the first engaged iteration (24.8) */
    const ht_post *p = ht_last("BHV_SETTINGS");
    ck_assert(p != NULL);
    ck_assert_uint_eq(ht_count("BHV_SETTINGS"), 2);
    ck_assert(ht_has_str("BHV_SETTINGS", "type=BHV_Waypoint,name=survey,points=pts={0,0:100,-20.25},speed=2.5,speed_alt=-1,"
                         "currix=0,greedy_tour=false,use_alt_speed=false,wpt_status=WPT_STAT,wpt_dist_to_prev=,"
                         "wpt_dist_to_next=,wpt_index=WPT_INDEX,cycle_index_var=CYCLE_INDEX,post_suffix=,post_suffix=,"
                         "ipf_type=zaic,lead=8,lead_damper=-1,lead_to_start=false,order=normal,repeats=forever,"
                         "efficiency_measure=off,capture_radius=5,slip_radius=12,crs_spd_zaic_ratio=50"));
    ck_assert(ht_has_str("BHV_SETTINGS", "type=BHV_Loiter,name=loiter,x=20.00,y=-15.00,clockwise=false,"
                         "dynamic_clockwise=false,center_activate=false,desired_speed=1.5,polygon=\"pts={0,-30:40,-30:40,0:0,0}\""));
    /* 24.8's: an active behaviour's weight and pieces, an idle one's failed condition (twice:
     * asked before and after the run) */
    char st[96];
    snprintf(st, sizeof st, "name=survey,pwt=100.00000,pcs=%zu,state=active,updates=n/a", g_h.fn[0].n);
    ck_assert_msg(ht_has_str("BHV_STATUS", st), "%s", st);
    ck_assert(ht_has_str("BHV_STATUS", "name=loiter,pc=GO = true,pc=GO = true,state=idle,updates=n/a"));
    ht_iter(2);
    ck_assert_uint_eq(ht_count("BHV_STATUS"), 0);
    kelp_helm_mail_string(&g_h, "GO", "true");
    ht_iter(3);
    snprintf(st, sizeof st, "name=loiter,pwt=100.00000,pcs=%zu,state=active,updates=n/a", g_h.fn[1].n);
    ck_assert_msg(ht_has_str("BHV_STATUS", st), "%s", st);
}
END_TEST

/* IVPHELM_SUMMARY: active_goal, ivpdomain and halt_msg as MOOS-IvP's HelmReport writes them */
START_TEST(summary_goal_domain_halt)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = survey\n speed = 2\n points = 0,0:100,0\n condition = GO = true\n}\n"
            "Behavior = BHV_ConstantSpeed\n{\n name = cs\n speed = 1\n condition = HALT = true\n nostarve = NAV_Q,1\n}\n");
    nav(0, -100);
    ht_iter(1);
    const ht_post *s = ht_last("IVPHELM_SUMMARY");
    ck_assert(s != NULL);
    ck_assert_msg(strstr(s->sval, ",active_goal=false") != NULL, "%s", s->sval);
    ck_assert_msg(strstr(s->sval, ",ivpdomain=\"course,0,359,360:speed,0,4,21\"") != NULL, "%s", s->sval);
    ck_assert(strstr(s->sval, ",halt_msg=none") != NULL);
    kelp_helm_mail_string(&g_h, "GO", "true");
    ht_iter(2);
    s = ht_last("IVPHELM_SUMMARY");
    ck_assert_msg(strstr(s->sval, ",active_goal=true") != NULL, "%s", s->sval);
    kelp_helm_mail_string(&g_h, "HALT", "true"); /* NAV_Q never arrives: a VarStarve error halts the helm */
    ht_iter(3);
    s = ht_last("IVPHELM_SUMMARY");
    ck_assert_msg(strstr(s->sval, ",halt_msg=BHV_ERROR: cs: VarStarve: NAV_Q older than 1 s") != NULL, "%s", s->sval);
}
END_TEST

/* runxflag every running iteration, configflag and spawnx_flag once; underscored aliases */
START_TEST(flags_runx_config_spawnx)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = survey\n speed = 2\n points = 0,0:100,0\n"
            " runx_flag = RUNX = $[CTR]\n config_flag = CONFIGURED = true\n spawnx_flag = SPAWNX = 1\n"
            " run_flag = RUNNING = yes\n templating = disallowed\n build_info = uniform_piece=discrete@course:3\n}\n");
    nav(0, -100);
    ht_iter(1);
    ck_assert_uint_eq(ht_count("RUNX"), 1);
    ck_assert_uint_eq(ht_count("CONFIGURED"), 1);
    ck_assert_uint_eq(ht_count("SPAWNX"), 1);
    ck_assert_uint_eq(ht_count("RUNNING"), 1);
    ht_iter(2);
    ck_assert_uint_eq(ht_count("RUNX"), 1); /* repeatable: every iteration */
    ck_assert_uint_eq(ht_count("CONFIGURED"), 0);
    ck_assert_uint_eq(ht_count("SPAWNX"), 0);
    ck_assert_uint_eq(ht_count("RUNNING"), 0);
    ht_setup(DOM2, NULL);
    ck_assert_int_lt(ht_load_rc("Behavior = BHV_Waypoint\n{\n name = s\n points = 0,0\n templating = sometimes\n}\n"), 0);
}
END_TEST

/* ---------------------------------------------------------------- duration */

START_TEST(duration_expiry)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n duration = 10\n endflag = DONE = yes\n condition = GO = 1\n}\n");
    ht_iter(0); /* idle: the clock has not started (starts when conditions first hold) */
    ht_iter(5);
    kelp_helm_mail_double(&g_h, "GO", 1);
    ht_iter(6); /* clock starts at 6 */
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ht_iter(15.9);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ck_assert_uint_eq(ht_count("DONE"), 0);
    ht_iter(16.0);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_COMPLETED);
    ck_assert(ht_has_str("DONE", "yes"));
    ck_assert_uint_eq(ht_count("PROBE_LEVEL"), 0);
    ht_iter(17);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_COMPLETED);
    ck_assert_uint_eq(ht_count("DONE"), 0);
}
END_TEST

/* The time step rule (docs/ARCHITECTURE.md): a clock step is not helm time. Before it, +1 h
 * completed every behaviour with a duration at once; -1 h stalled them for an hour (elapsed
 * time negative) and reported a duration status above the duration itself. */
START_TEST(duration_across_clock_steps)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n duration = 100\n duration_status = DS\n"
            " condition = GO = 1\n}\n");
    kelp_helm_mail_double(&g_h, "GO", 1);
    for (int t = 0; t <= 5; t++) ht_iter(t); /* the clock started at 0: 5 s used */
    unsigned long it = g_h.iteration;
    /* NaN, an infinity, an absurd time: refused, nothing changes */
    ck_assert_int_eq(kelp_helm_iterate(&g_h, NAN), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_helm_iterate(&g_h, INFINITY), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_helm_iterate(&g_h, 1e300), KELP_ERR_ARG);
    ck_assert_uint_eq(g_h.iteration, it);
    /* +1 h: still running, 95 s left, one iteration's postings */
    ht_iter(3605);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ck_assert_uint_eq(g_h.clock_steps, 1);
    ht_iter(3606); /* one second of helm time since the step */
    ck_assert_uint_eq(ht_count("DS"), 1);
    ck_assert_double_eq_tol(ht_num("DS"), 94, 1e-9);
    for (int t = 3607; t < 3695; t++) ht_iter(t);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    /* -1 h (10 s used since the step): no stall, no status above the duration */
    ht_iter(95); /* helm time carries on at 5 + 89 = 94 s */
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ck_assert_uint_eq(g_h.clock_steps, 2);
    ht_iter(96);
    ck_assert_double_eq_tol(ht_num("DS"), 5, 1e-9); /* helm time 95 */
    for (int t = 97; t <= 100; t++) ht_iter(t); /* helm time 99 */
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ht_iter(101);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_COMPLETED); /* 100 s of helm time */
    /* +1 s is time, not a step */
    ck_assert_uint_eq(g_h.clock_steps, 2);
}
END_TEST

START_TEST(duration_keeps_ticking_while_idle)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n duration = 10\n condition = GO = 1\n}\n");
    kelp_helm_mail_double(&g_h, "GO", 1);
    ht_iter(0);
    kelp_helm_mail_double(&g_h, "GO", 0);
    ht_iter(2);
    ht_iter(11); /* idle: expiry is noticed only when the conditions hold again */
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_IDLE);
    kelp_helm_mail_double(&g_h, "GO", 1);
    ht_iter(12);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_COMPLETED);
}
END_TEST

START_TEST(duration_idle_decay_false_pauses)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n duration = 10\n duration_idle_decay = false\n condition = GO = 1\n}\n");
    kelp_helm_mail_double(&g_h, "GO", 1);
    for (int t = 0; t <= 4; t++)
        ht_iter(t);
    kelp_helm_mail_double(&g_h, "GO", 0);
    for (int t = 5; t <= 14; t++)
        ht_iter(t); /* 10 s idle, paused (4->5 ran, 5..14 idle) */
    kelp_helm_mail_double(&g_h, "GO", 1);
    ht_iter(15);
    ht_iter(19);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING); /* 19 - 10 s idle = 9 */
    ht_iter(19.5);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ht_iter(20.0);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_COMPLETED); /* 20 - 10 s paused = 10 */
}
END_TEST

START_TEST(duration_status_rounding)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n duration = 20\n duration_status = DS\n condition = GO = 1\n}\n");
    ht_iter(0);
    ck_assert_uint_eq(ht_count("DS"), 0); /* only while running */
    kelp_helm_mail_double(&g_h, "GO", 1);
    ht_iter(1); /* clock starts: 20 left */
    ck_assert(ht_num("DS") == 20);
    ht_iter(5.6); /* 15.4 left -> 15 */
    ck_assert(ht_num("DS") == 15);
    ht_iter(11.544); /* 9.456 left -> 9.46 */
    ck_assert(fabs(ht_num("DS") - 9.46) < 1e-9);
    kelp_helm_mail_double(&g_h, "GO", 0);
    ht_iter(12);
    ck_assert_uint_eq(ht_count("DS"), 0);
}
END_TEST

START_TEST(duration_reset_variable)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n duration = 10\n duration_status = DS\n"
            " duration_reset = BRAVO_TIMER_RESET=true\n}\n");
    ht_iter(0);
    ht_iter(8);
    kelp_helm_mail_string(&g_h, "BRAVO_TIMER_RESET", "true");
    ht_iter(8.5); /* reset: full duration again, started at 8.5 */
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ck_assert(ht_num("DS") == 10);
    ht_iter(12); /* no new write: the old sighting does not reset again */
    ck_assert(fabs(ht_num("DS") - 6.5) < 1e-9);
    kelp_helm_mail_string(&g_h, "BRAVO_TIMER_RESET", "true"); /* written again, same value: resets */
    ht_iter(13);
    ck_assert(ht_num("DS") == 10);
    ht_iter(22.9);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
    ht_iter(23);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_COMPLETED);
}
END_TEST

/* ---------------------------------------------------------------- perpetual */

START_TEST(perpetual_duration_restarts)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n duration = 5\n perpetual = true\n endflag = TICK = 1\n}\n");
    ht_iter(0);
    ht_iter(4.9);
    ck_assert_uint_eq(ht_count("TICK"), 0);
    ht_iter(5);
    ck_assert_uint_eq(ht_count("TICK"), 1);  /* end flags at timeout */
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING); /* not completed */
    ht_iter(6);  /* clock restarted when it next ran */
    ht_iter(10.9);
    ck_assert_uint_eq(ht_count("TICK"), 0);
    ht_iter(11);
    ck_assert_uint_eq(ht_count("TICK"), 1);  /* end flags are repeatable: posted again */
    ck_assert(!bhv("p")->completed);
}
END_TEST

START_TEST(perpetual_set_complete)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n perpetual = TRUE\n endflag = ENDF = 1\n}\n");
    kelp_helm_mail_double(&g_h, "PROBE_DONE", 1);
    ht_iter(0);
    ck_assert_uint_eq(ht_count("ENDF"), 1);
    ht_iter(1);
    ck_assert_uint_eq(ht_count("ENDF"), 1);
    ck_assert_int_eq(bhv("p")->state, KELP_BHV_RUNNING);
}
END_TEST

/* ---------------------------------------------------------------- nostarve, errors, all-stop */

START_TEST(nostarve_all_stop_and_recovery)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_SimpleWaypoint\n{\n name = w\n speed = 2\n ptx = 0\n pty = 100\n nostarve = NAV_X, NAV_Y, 5.0\n}\n");
    ht_iter(0); /* never written: starved */
    ck_assert(g_h.rep.halted);
    ck_assert_str_eq(g_h.rep.allstop, "BehaviorError");
    ck_assert(ht_has_str("BHV_ERROR", "w: VarStarve: NAV_X older than 5 s"));
    ck_assert(ht_num("DESIRED_SPEED") == 0);
    nav(0, 0);
    ht_iter(1);
    ck_assert(!g_h.rep.halted);
    ck_assert(ht_num("DESIRED_SPEED") == 2);
    ht_iter(6.0); /* 5.0 s old: still fresh */
    ck_assert(!g_h.rep.halted);
    ht_iter(6.1);
    ck_assert(g_h.rep.halted);
    ck_assert(ht_num("DESIRED_SPEED") == 0 && ht_num("DESIRED_HEADING") == 0);
    ck_assert(ht_has_str("IVPHELM_ALLSTOP", "BehaviorError"));
    nav(0, 1);
    ht_iter(7);
    ck_assert(!g_h.rep.halted);
    ck_assert(ht_num("DESIRED_SPEED") == 2);
    ck_assert(ht_has_str("IVPHELM_ALLSTOP", "clear"));
}
END_TEST

START_TEST(post_emessage_all_stop)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n}\nBehavior = BHV_SimpleWaypoint\n{\n name = w\n speed = 2\n pty = 50\n}\n");
    nav(0, 0);
    ht_iter(0);
    ck_assert_str_eq(g_h.rep.allstop, "clear");
    kelp_helm_mail_double(&g_h, "PROBE_ERR", 1);
    ht_iter(1);
    ck_assert(ht_has_str("BHV_ERROR", "p: probe error"));
    ck_assert_str_eq(g_h.rep.allstop, "BehaviorError");
    ck_assert(ht_num("DESIRED_SPEED") == 0);
    ht_iter(2); /* repeatable: posted again while the condition lasts */
    ck_assert_uint_eq(ht_count("BHV_ERROR"), 1);
    kelp_helm_mail_double(&g_h, "PROBE_ERR", 0);
    ht_iter(3);
    ck_assert_str_eq(g_h.rep.allstop, "clear");
}
END_TEST

START_TEST(manual_override_parks)
{
    ht_setup(DOM2, NULL);
    ht_load(ALDER);
    nav(0, 0);
    kelp_helm_mail_string(&g_h, "DEPLOY", "true");
    ht_iter(0);
    ck_assert(ht_has_str("IVPHELM_STATE", "DRIVE"));
    ck_assert(ht_num("DESIRED_SPEED") == 2);
    kelp_helm_mail_string(&g_h, "MOOS_MANUAL_OVERIDE", "true");
    ht_iter(1);
    ck_assert(ht_has_str("IVPHELM_STATE", "PARK"));
    ck_assert_str_eq(g_h.rep.allstop, "ManualOverride");
    ck_assert(ht_num("DESIRED_SPEED") == 0);
    kelp_helm_mail_string(&g_h, "MOOS_MANUAL_OVERRIDE", "FALSE");
    ht_iter(2);
    ck_assert(ht_num("DESIRED_SPEED") == 2);
}
END_TEST

static void tweak_default_start(kelp_helm_config *cfg)
{
    kelp_helm_config def;
    kelp_helm_config_default(&def);
    cfg->start_engaged = def.start_engaged;
}

/* HelmIvP (24.8): parked until MOOS_MANUAL_OVERRIDE = false unless start_engaged; while parked
 * IVPHELM_STATE = PARK every iteration; postAllStop posts IVPHELM_ALLSTOP (and the decision
 * variables' zeros) only when the reason changes: ManualOverride once; the first iteration with
 * nothing to do posts the reason without zeros, the next posts it again with the zeros, then
 * nothing until the reason changes */
/* comms_policy (IvPBehavior::setParam): open, lean or dire, anything else refused */
START_TEST(general_comms_policy)
{
    ht_setup(DOM2, NULL);
    ck_assert_int_eq(ht_load_rc("Behavior = BHV_ConstantSpeed\n{\n name = a\n speed = 1\n comms_policy = lean\n}\n"), 0);
    ht_setup(DOM2, NULL);
    ck_assert_int_lt(ht_load_rc("Behavior = BHV_ConstantSpeed\n{\n name = a\n speed = 1\n comms_policy = loose\n}\n"), 0);
}
END_TEST

/* IVPHELM_REGISTER as 24.8's registerNewVariables (HelmIvP.cpp, BehaviorSet::getInfoVars /
 * getNewInfoVars, IvPBehavior::getInfoVars): at the first engaged iteration each behaviour's
 * information variables -- its conditions', its duration_reset variable, the ones it adds itself
 * (BHV_Waypoint: NAV_X, NAV_Y, NAV_SPEED), its updates variable -- then the mode declarations',
 * each once, in that order (the order of 24.8's s1_alpha recording); none while parked, none
 * again after */
START_TEST(register_info_vars_as_248)
{
    g_tweak = tweak_default_start;
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = survey\n condition = RETURN = false\n condition = DEPLOY = true\n"
            " updates = WPT_UPDATE\n speed = 2\n points = 0,50:50,50\n}\n"
            "Behavior = BHV_Waypoint\n{\n name = ret\n condition = RETURN = true\n condition = DEPLOY = true\n"
            " updates = RETURN_UPDATE\n speed = 2\n points = 0,0\n}\n"
            "Behavior = BHV_ConstantSpeed\n{\n name = cs\n condition = SPD = true\n speed = 0.5\n duration = 10\n"
            " duration_reset = CONST_SPD_RESET = true\n updates = SPEED_UPDATE\n perpetual = true\n}\n");
    nav(0, 0);
    kelp_helm_mail_string(&g_h, "DEPLOY", "true");
    ht_iter(0);
    ck_assert(ht_has_str("IVPHELM_STATE", "PARK"));
    ck_assert_uint_eq(ht_count("IVPHELM_REGISTER"), 0);
    kelp_helm_mail_string(&g_h, "MOOS_MANUAL_OVERRIDE", "false");
    ht_iter(1);
    static const char *const want[] = {"RETURN", "DEPLOY", "NAV_X", "NAV_Y", "NAV_SPEED", "WPT_UPDATE",
                                       "RETURN_UPDATE", "SPD", "CONST_SPD_RESET", "SPEED_UPDATE"};
    unsigned k = 0;
    for (unsigned i = 0; i < g_nposts; i++)
        if (!strcmp(g_posts[i].var, "IVPHELM_REGISTER")) {
            ck_assert_msg(k < sizeof want / sizeof want[0], "extra %s", g_posts[i].sval);
            ck_assert_str_eq(g_posts[i].sval, want[k]);
            k++;
        }
    ck_assert_uint_eq(k, sizeof want / sizeof want[0]);
    ht_iter(2);
    ck_assert_uint_eq(ht_count("IVPHELM_REGISTER"), 0);
}
END_TEST

/* $[DUR_RUN_TIME] / $[DUR_IDLE_TIME] (IvPBehavior::expandMacros, updateStateDurations): the time
 * the behaviour has spent running / idle, each iteration's time since the previous one counted,
 * at the iteration's end, to the state it is in then; 3 decimals trimmed; 24.8's s1_alpha posts SUMMARY=speed=3,time=232.009 at its survey's end */
START_TEST(macro_dur_run_time)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_Waypoint\n{\n name = s\n condition = GO = true\n speed = 2\n points = 0,1000\n"
            " runflag = RUNT = $[DUR_RUN_TIME]\n activeflag = ACT = t=$[DUR_RUN_TIME],i=$[DUR_IDLE_TIME]\n"
            " inactiveflag = OFF = i=$[DUR_IDLE_TIME]\n perpetual = true\n}\n");
    nav(0, 0);
    kelp_helm_mail_string(&g_h, "GO", "false");
    ht_iter(0);
    ht_iter(1.5); /* idle 1.5 s */
    kelp_helm_mail_string(&g_h, "GO", "true");
    ht_iter(2.0); /* running: the 0.5 s since 1.5 counts as running once this iteration ends */
    ck_assert_msg(ht_has_str("ACT", "t=0,i=1.5"), "%s", ht_last("ACT") ? ht_last("ACT")->sval : "none");
    ht_iter(2.25);
    ht_iter(4.75);
    kelp_helm_mail_string(&g_h, "GO", "false");
    ht_iter(5.0); /* idle: 0.25 s more idle at this iteration's end; running 4.75 - 1.5 */
    ck_assert_msg(ht_has_str("OFF", "i=1.5"), "%s", ht_last("OFF") ? ht_last("OFF")->sval : "none");
    kelp_helm_mail_string(&g_h, "GO", "true");
    ht_iter(6.125);
    ck_assert_msg(ht_has_str("ACT", "t=3.25,i=1.75"), "%s", ht_last("ACT") ? ht_last("ACT")->sval : "none");
}
END_TEST

START_TEST(helm_starts_parked)
{
    g_tweak = tweak_default_start;
    ht_setup(DOM2, NULL);
    ht_load(ALDER);
    nav(0, 0);
    kelp_helm_mail_string(&g_h, "DEPLOY", "true");
    ht_iter(0);
    ck_assert(ht_has_str("IVPHELM_STATE", "PARK"));
    ck_assert(ht_has_str("IVPHELM_ALLSTOP", "ManualOverride"));
    ck_assert(ht_num("DESIRED_SPEED") == 0 && ht_num("DESIRED_HEADING") == 0);
    ht_iter(1);
    ck_assert(ht_has_str("IVPHELM_STATE", "PARK"));
    ck_assert_uint_eq(ht_count("IVPHELM_ALLSTOP") + ht_count("MOOS_DEBUG") + ht_count("DESIRED_SPEED"), 0);
    ck_assert_uint_eq(ht_count("IVPHELM_STATEVARS"), 0); /* posted by drive iterations */
    ck_assert_uint_eq(ht_count("IVPHELM_LIFE_EVENT"), 0); /* the first decision posts them */
    kelp_helm_mail_string(&g_h, "MOOS_MANUAL_OVERRIDE", "false");
    ht_iter(2);
    ck_assert(ht_has_str("IVPHELM_STATE", "DRIVE"));
    /* helm time since the first iteration, 24.8's layout, the iteration appended */
    ck_assert(ht_has_sub("IVPHELM_LIFE_EVENT", "iter=0,time=2.00, bname="));
    /* the iteration is the helm's decision count (24.8: HelmEngine's), 1 at the first decision */
    ck_assert(ht_has_sub("IVPHELM_LIFE_EVENT", ", event=spawn, seed=helm_startup,iter=1"));
    ck_assert(ht_has_str("IVPHELM_ALLSTOP", "clear"));
    ck_assert(ht_num("DESIRED_SPEED") == 2);
    /* the conditions' and the end flag's variables, each once, in order */
    ck_assert_str_eq(ht_last("IVPHELM_STATEVARS")->sval, "DEPLOY,RETURN");
    ck_assert_uint_eq(ht_count("IVPHELM_UPDATEVARS"), 0); /* no behaviour has updates */
    ht_iter(3); /* the reason unchanged: not posted; the decision is */
    ck_assert_uint_eq(ht_count("IVPHELM_ALLSTOP"), 0);
    ck_assert_uint_eq(ht_count("IVPHELM_STATEVARS"), 0); /* again only when the set grows */
    ck_assert(ht_num("DESIRED_SPEED") == 2);
    /* DEPLOY off: nothing to do; no zeros on the first such iteration, zeros on the second */
    kelp_helm_mail_string(&g_h, "DEPLOY", "false");
    ht_iter(4);
    ck_assert(ht_has_str("IVPHELM_ALLSTOP", "NothingToDo"));
    ck_assert_uint_eq(ht_count("DESIRED_SPEED"), 0);
    ck_assert_uint_eq(ht_count("DESIRED_HEADING"), 0);
    ht_iter(5);
    ck_assert(ht_has_str("IVPHELM_ALLSTOP", "NothingToDo"));
    ck_assert(ht_num("DESIRED_SPEED") == 0);
    ht_iter(6);
    ck_assert_uint_eq(ht_count("IVPHELM_ALLSTOP") + ht_count("DESIRED_SPEED") + ht_count("DESIRED_HEADING"), 0);
}
END_TEST

/* pHelmIvP 24.8's other postings: IVPHELM_LEDGER_SUMMARY (ContactLedger::getSummary) once the
 * navigation is known, MOOS_DEBUG with each all-stop reason (postAllStop's MOOSDebugWrite),
 * TURN_RATE (PlatModelGenerator::getTurnRate: the mean heading change per iteration over 5 s),
 * IVPHELM_COMPLETED_PENDING on change */
START_TEST(helm_v248_postings)
{
    ht_setup(DOM2, NULL);
    ht_load("Behavior = BHV_SimpleWaypoint\n{\n name = w\n speed = 2\n radius = 3\n ptx = 0\n pty = 50\n}\n");
    ck_assert(ht_has_str("IVPHELM_MODESET", "")); /* at start, empty without modes */
    static const double hdg[4] = { 0, 10, 30, 30 };
    for (int i = 0; i < 4; i++) {
        nav(0, i < 3 ? 0 : 49);
        kelp_helm_mail_double(&g_h, "NAV_HEADING", hdg[i]);
        kelp_helm_mail_double(&g_h, "NAV_SPEED", 2);
        if (i == 1) {
            ck_assert_int_eq(kelp_helm_ledger_report(&g_h, "NAME=ben,X=10,Y=0,SPD=1,HDG=0"), 0);
            ck_assert_int_eq(kelp_helm_ledger_report(&g_h, "NAME=al,X=20,Y=0,SPD=1,HDG=0"), 0);
            ck_assert_int_eq(kelp_helm_ledger_report(&g_h, "NAME=ben,X=11,Y=0,SPD=1,HDG=0"), 0);
        }
        ht_iter(i);
        if (i == 0 || i == 3) /* each reason once, when it changes */
            ck_assert(ht_has_str("MOOS_DEBUG", i == 0 ? "pHelmIvP AllStop: clear" : "pHelmIvP AllStop: NothingToDo"));
        else
            ck_assert_uint_eq(ht_count("MOOS_DEBUG"), 0);
        if (i == 0) {
            ck_assert(ht_has_str("IVPHELM_LEDGER_SUMMARY", "now:0, reps:0, who:"));
            ck_assert(ht_has_str("IVPHELM_COMPLETED_PENDING", "false"));
            ck_assert(ht_num("TURN_RATE") == 0);
        }
    }
    /* 0 -> 10 -> 30 -> 30: (10 + 20 + 0) / 3 per iteration */
    ck_assert_double_eq_tol(ht_num("TURN_RATE"), 10, 1e-9);
    ck_assert(ht_has_str("IVPHELM_LEDGER_SUMMARY", "now:2, reps:3, who:al,ben"));
    ck_assert(ht_has_str("IVPHELM_COMPLETED_PENDING", "true")); /* arrived at (0,50) */
    ht_iter(4);
    ck_assert(ht_has_str("IVPHELM_COMPLETED_PENDING", "false"));
    ht_iter(5);
    ck_assert_uint_eq(ht_count("IVPHELM_COMPLETED_PENDING"), 0);
    /* headings older than 5 s leave the average */
    kelp_helm_mail_double(&g_h, "NAV_HEADING", 40);
    ht_iter(20);
    ck_assert(ht_num("TURN_RATE") == 0);
}
END_TEST

static void tweak_park(kelp_helm_config *cfg)
{
    cfg->allow_park = false;
    snprintf(cfg->other_override, sizeof cfg->other_override, "AUTONOMY_OVERRIDE");
}

static void tweak_allstop(kelp_helm_config *cfg)
{
    cfg->park_on_allstop = true;
}

START_TEST(park_policies_and_other_override)
{
    /* allow_park = false: an override cannot park an engaged helm */
    g_tweak = tweak_park;
    ht_setup(DOM2, NULL);
    ht_load(ALDER);
    nav(0, 0);
    kelp_helm_mail_string(&g_h, "DEPLOY", "true");
    ht_iter(0);
    kelp_helm_mail_string(&g_h, "MOOS_MANUAL_OVERRIDE", "true");
    kelp_helm_mail_string(&g_h, "AUTONOMY_OVERRIDE", "true");
    ht_iter(1);
    ck_assert_str_eq(g_h.rep.allstop, "clear");
    ck_assert(ht_num("DESIRED_SPEED") == 2);
    /* other_override_var engages like MOOS_MANUAL_OVERRIDE */
    g_tweak = tweak_park;
    ht_setup(DOM2, NULL);
    ht_load(ALDER);
    g_h.engaged = false;
    nav(0, 0);
    kelp_helm_mail_string(&g_h, "DEPLOY", "true");
    ht_iter(0);
    ck_assert_str_eq(g_h.rep.allstop, "ManualOverride");
    kelp_helm_mail_string(&g_h, "AUTONOMY_OVERRIDE", "false");
    ht_iter(1);
    ck_assert(ht_num("DESIRED_SPEED") == 2);
    /* park_on_allstop: nothing to do parks the helm, and it stays parked */
    g_tweak = tweak_allstop;
    ht_setup(DOM2, NULL);
    ht_load(ALDER);
    nav(0, 0);
    ht_iter(0); /* DEPLOY never set: NothingToDo */
    ck_assert_str_eq(g_h.rep.allstop, "NothingToDo");
    ck_assert(!g_h.engaged);
    kelp_helm_mail_string(&g_h, "DEPLOY", "true");
    ht_iter(1);
    ck_assert_str_eq(g_h.rep.allstop, "ManualOverride");
    kelp_helm_mail_string(&g_h, "MOOS_MANUAL_OVERRIDE", "false");
    ht_iter(2);
    ck_assert(ht_num("DESIRED_SPEED") == 2);
}
END_TEST

START_TEST(domain_lines)
{
    kelp_helm_config cfg;
    kelp_helm_config_default(&cfg);
    kelp_diag why = {0};
    ck_assert_int_eq(kelp_helm_config_add_domain(&cfg, "course:0:359:360", &why), 0);
    ck_assert_int_eq(kelp_helm_config_add_domain(&cfg, " speed : 0 : 2 : 21 ", &why), 0);
    ck_assert_int_eq(kelp_helm_config_add_domain(&cfg, "depth:0:1000:1001:optional", &why), 0);
    ck_assert_uint_eq(cfg.domain.dim, 3);
    ck_assert_str_eq(cfg.domain.var[1].name, "speed");
    ck_assert(cfg.optional[2] && !cfg.optional[1]);
    ck_assert_int_eq(why.code, KELP_OK);
    ck_assert_int_eq(kelp_helm_config_add_domain(&cfg, "x:0:1", &why), KELP_ERR_PARSE);
    ck_diag(&why, KELP_ERR_PARSE, "expected name:low:high:points[:optional]");
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_helm_config_add_domain(&cfg, "course:0:1:2", &why), KELP_ERR_EXISTS);
    ck_assert_str_eq(kelp_diag_text(&why), kelp_err_str(KELP_ERR_EXISTS));
    kelp_diag_clear(&why);
    ck_assert_int_lt(kelp_helm_config_add_domain(&cfg, "x:0:1:0", &why), 0);
    ck_assert_int_lt(kelp_helm_config_add_domain(&cfg, "x:0:1:2:maybe", &why), 0);
    ck_assert_int_lt(kelp_helm_config_add_domain(&cfg, "x:a:1:2", &why), 0);
    ck_assert_int_eq(why.code, KELP_ERR_PARSE); /* first error wins: x:0:1:0's */
    ck_diag_msg(&why, "bad low, high or points (1..100000)");
}
END_TEST

START_TEST(optional_domain_variable)
{
    ht_setup(DOM2 ",depth:0:100:101", NULL);
    ht_load(ALDER);
    nav(0, 0);
    kelp_helm_mail_string(&g_h, "DEPLOY", "true");
    ht_iter(0);
    ck_assert_str_eq(g_h.rep.allstop, "MissingDecVars:depth");
    ck_assert_uint_eq(ht_count("DESIRED_SPEED"), 0); /* the first such iteration posts no zeros */
    g_h.cfg.optional[2] = true;
    ht_iter(1);
    ck_assert_str_eq(g_h.rep.allstop, "clear");
    ck_assert(ht_num("DESIRED_SPEED") == 2);
    ck_assert_uint_eq(ht_count("DESIRED_DEPTH"), 0);
}
END_TEST

/* ---------------------------------------------------------------- postings */

START_TEST(post_mapping_not_transitive)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n runflag = FOO = 1\n runflag = BAR = 2\n runflag = HUSH = 3\n"
            " post_mapping = FOO, BAR\n post_mapping = BAR, CAR\n post_mapping = HUSH, silent\n"
            " post_mapping = PROBE_LEVEL, LEVEL\n level = 4\n}\n");
    ht_iter(0);
    ck_assert_uint_eq(ht_count("FOO"), 0);
    ck_assert(ht_num("BAR") == 1);  /* FOO -> BAR, not CAR */
    ck_assert(ht_num("CAR") == 2);  /* BAR -> CAR */
    ck_assert_uint_eq(ht_count("HUSH"), 0);
    ck_assert_uint_eq(ht_count("silent"), 0);
    ck_assert(ht_num("LEVEL") == 4);
}
END_TEST

START_TEST(duplicate_filter_and_post_int)
{
    ht_setup(DOM2, probe_types);
    ht_load("Behavior = BHV_Probe\n{\n name = p\n level = 1\n}\n");
    kelp_helm_mail_double(&g_h, "PROBE_INT", 2.6);
    ht_iter(0);
    ck_assert(ht_num("PROBE_LEVEL") == 1);
    ck_assert(ht_num("PROBE_INT_OUT") == 3); /* postIntMessage rounds */
    kelp_helm_mail_double(&g_h, "PROBE_INT", 3.2);
    ht_iter(1);
    ck_assert_uint_eq(ht_count("PROBE_LEVEL"), 0);  /* unchanged: filtered */
    ck_assert_uint_eq(ht_count("PROBE_INT_OUT"), 0); /* 3.2 -> 3 again: filtered */
    kelp_helm_mail_string(&g_h, "PROBE_UPD", "x");
    ck_assert_int_eq(kelp_helm_bhv_set_param(bhv("p"), "level", "2"), 0);
    ht_iter(2);
    ck_assert(ht_num("PROBE_LEVEL") == 2);
}
END_TEST

START_TEST(summary_and_lists)
{
    ht_setup(DOM2, NULL);
    ht_load(ALDER);
    nav(0, 0);
    kelp_helm_mail_string(&g_h, "DEPLOY", "true");
    ht_iter(0);
    const ht_post *p = ht_last("IVPHELM_SUMMARY");
    ck_assert_ptr_nonnull(p);
    ck_assert_msg(strstr(p->sval, "iter=1,") == p->sval, "%s", p->sval);
    /* 24.8's HelmReport layout, whole the first time */
    ck_assert_ptr_nonnull(strstr(p->sval, ",ofnum=1,"));
    ck_assert_msg(strstr(p->sval, ",var=course:124,var=speed:2,halted=false,active_goal=true,modes=none,"
                                  "running_bhvs=none,active_bhvs=transit_to_point$") != NULL, "%s", p->sval);
    ck_assert_ptr_nonnull(strstr(p->sval, "$100.00000$"));
    ck_assert_ptr_nonnull(strstr(p->sval, ",disabled_bhvs=none,idle_bhvs=waypt_return$"));
    ck_assert_ptr_nonnull(strstr(p->sval, ",completed_bhvs=none,ivpdomain=\"course,0,359,360:speed,0,4,21\",halt_msg=none"));
    ck_assert(ht_has_str("IVPHELM_BHV_IDLE", "waypt_return"));
    ck_assert(ht_num("IVPHELM_ITER") == 1 && ht_num("IVPHELM_IPF_CNT") == 1);
    ck_assert(ht_num("IVPHELM_TOTAL_PCS_FORMED") > 0 && ht_num("IVPHELM_TOTAL_PCS_CACHED") == 0);
    ht_iter(1);
    ck_assert_uint_eq(ht_count("IVPHELM_BHV_IDLE"), 0); /* lists only on change */
    p = ht_last("IVPHELM_SUMMARY"); /* then iter and utc_time, and only the fields that changed */
    ck_assert_ptr_nonnull(p);
    ck_assert_msg(strstr(p->sval, "iter=2,utc_time=") == p->sval && !strstr(p->sval, "idle_bhvs") &&
                  !strstr(p->sval, "ivpdomain") && !strstr(p->sval, "halted"), "%s", p->sval);
    kelp_helm_mail_string(&g_h, "IVPHELM_REJOURNAL", "true");
    ht_iter(2);
    ck_assert_ptr_nonnull(strstr(ht_last("IVPHELM_SUMMARY")->sval, ",ivpdomain=")); /* whole again */
}
END_TEST

Suite *kelp_helm_suite(void);
Suite *kelp_helm_suite(void)
{
    Suite *s = suite_create("helm");
    TCase *tc = tcase_create("framework");
    tcase_add_test(tc, ib_values_times_vectors);
    tcase_add_test(tc, ib_same_snapshot_and_mail_time);
    tcase_add_loop_test(tc, condition_grammar, 0, (int)(sizeof g_conds / sizeof g_conds[0]));
    tcase_add_test(tc, condition_variables_registered);
    tcase_add_test(tc, condition_nesting_bounded);
    tcase_add_loop_test(tc, general_parameters, 0, (int)(sizeof g_params / sizeof g_params[0]));
    tcase_add_test(tc, parameter_values_stored);
    tcase_add_test(tc, load_alder_and_initialize);
    tcase_add_test(tc, load_initialize_forms);
    tcase_add_loop_test(tc, load_errors_name_the_line, 0, (int)(sizeof g_bad / sizeof g_bad[0]));
    tcase_add_test(tc, null_domain_refused_at_launch);
    tcase_add_test(tc, condition_transitions_and_flags);
    tcase_add_test(tc, endflag_and_completed_forever);
    tcase_add_test(tc, endflag_reaches_buffer_next_iteration);
    tcase_add_test(tc, updates_valid_same_iteration);
    tcase_add_test(tc, updates_bad_pairs_ignored_with_warning);
    tcase_add_test(tc, update_results_posted);
    tcase_add_test(tc, bhv_settings_and_status);
    tcase_add_test(tc, bhv_wpt_retract_warning);
    tcase_add_test(tc, summary_goal_domain_halt);
    tcase_add_test(tc, flags_runx_config_spawnx);
    tcase_add_test(tc, duration_expiry);
    tcase_add_test(tc, duration_across_clock_steps);
    tcase_add_test(tc, duration_keeps_ticking_while_idle);
    tcase_add_test(tc, duration_idle_decay_false_pauses);
    tcase_add_test(tc, duration_status_rounding);
    tcase_add_test(tc, duration_reset_variable);
    tcase_add_test(tc, perpetual_duration_restarts);
    tcase_add_test(tc, perpetual_set_complete);
    tcase_add_test(tc, nostarve_all_stop_and_recovery);
    tcase_add_test(tc, post_emessage_all_stop);
    tcase_add_test(tc, manual_override_parks);
    tcase_add_test(tc, helm_starts_parked);
    tcase_add_test(tc, register_info_vars_as_248);
    tcase_add_test(tc, general_comms_policy);
    tcase_add_test(tc, macro_dur_run_time);
    tcase_add_test(tc, helm_v248_postings);
    tcase_add_test(tc, park_policies_and_other_override);
    tcase_add_test(tc, domain_lines);
    tcase_add_test(tc, optional_domain_variable);
    tcase_add_test(tc, post_mapping_not_transitive);
    tcase_add_test(tc, duplicate_filter_and_post_int);
    tcase_add_test(tc, summary_and_lists);
    suite_add_tcase(s, tc);
    return s;
}
