/* kelp helm: BHV_AvoidCollision, a contact behaviour built the IvP way. Parameters, defaults
 * and the utility/priority model are MOOS-IvP's (BHV_AvoidCollision, IvPContactBehavior,
 * AOF_AvoidCollision); the code is kelp's. The objective over (course, speed) is the CPA
 * range within time_on_leg from the CPA engine (include/kelp/cpa.h) through the Reflector:
 * utility 0 below min_util_cpa_dist, 100 above max_util_cpa_dist, linear from 25 to 100
 * between (MOOS-IvP's metric). The function is normalised to [0,100] and weighted by
 * pwt x relevance, relevance 0 beyond pwt_outer_dist rising to 1 at pwt_inner_dist (linear,
 * quadratic or quasi = power 1.5), and past 1 inside pwt_inner_dist as MOOS-IvP's (it does not
 * cap). The behaviour completes when the contact is at or beyond
 * 1.1 x completed_dist (MOOS-IvP's margin, so a contact manager re-alert is not missed) or
 * fails an exit_on_filter_* check. Contact state comes from the helm's NODE_REPORT ledger. */
#include <math.h>
#include <string.h>
#include "helm_int.h"

#define AVD_PIECE "discrete @ course:3,speed:3"   /* MOOS-IvP's uniform_piece for this behaviour */

static void avd_init(kelp_bhv *b)
{
    kelp_bhv_avoid *a = &b->u.avoid;
    (void)hx_copy(b->name, sizeof b->name, "avoid_collision", 15);
    bhv_use_subdomain(b, "course,speed");
    a->completed_dist = 500;
    a->pwt_outer_dist = 200;
    a->pwt_inner_dist = 50;
    a->min_util_cpa_dist = 10;
    a->max_util_cpa_dist = 75;
    a->pwt_grade = 2;
    a->roc_max_dampen = -2;
    a->roc_max_heighten = 2;
    a->time_on_leg = 120;
    a->extrapolate = true;
    a->decay_start = 15;
    a->decay_end = 30;
    a->on_no_contact_ok = true;
    a->strict_ignore = -1;
    hx_ignore(kelp_helm_bhv_add_info_vars(b, "NAV_X, NAV_Y, NAV_SPEED, NAV_HEADING, NODE_REPORT")); /* a constructor cannot fail: a full list only skips the registration */
}

static int set_bool(const char *v, bool *out)
{
    bool t;
    if (kelp_util_parse_bool(v, strlen(v), &t) != 0)
        return KELP_ERR_PARSE;
    *out = t;
    return 0;
}

static int nonneg(const char *v, double *out)
{
    double d;
    if (!hx_number(v, strlen(v), &d) || d < 0)
        return KELP_ERR_PARSE;
    *out = d;
    return 0;
}

/* the low or high member of a pair kept ordered (the other follows when crossed) */
static int pair_low(const char *v, double *lo, double *hi)
{
    if (nonneg(v, lo) < 0) return KELP_ERR_PARSE;
    if (*hi < *lo) *hi = *lo;
    return 0;
}

static int pair_high(const char *v, double *lo, double *hi)
{
    if (nonneg(v, hi) < 0) return KELP_ERR_PARSE;
    if (*lo > *hi) *lo = *hi;
    return 0;
}

/* ExFilterSet's list entry: "a", "a,b" or "{a,b}", lower-cased, kept sorted and unique. An
 * entry already in the opposite list (other) is refused, the rest are taken (MOOS-IvP's rule). */
static int add_name(char list[][KELP_MAX_NAME], unsigned *n, const char other[][KELP_MAX_NAME], unsigned nother,
                    const char *v)
{
    const char *s = v;
    size_t sn = strlen(v);
    hx_trim(&s, &sn);
    if (sn >= 2 && s[0] == '{' && s[sn - 1] == '}') s++, sn -= 2;
    bool ok = sn > 0;
    while (sn > 0) {
        const char *e = memchr(s, ',', sn);
        size_t in = e ? (size_t)(e - s) : sn;
        const char *it = s;
        size_t il = in;
        hx_trim(&it, &il);
        s += e ? in + 1 : in;
        sn -= e ? in + 1 : in;
        if (il == 0) continue;
        char low[KELP_MAX_NAME];
        if (il >= sizeof low) return KELP_ERR_PARSE;
        for (size_t i = 0; i < il; i++) low[i] = hx_lower(it[i]);
        low[il] = '\0';
        bool skip = false;
        for (unsigned i = 0; i < nother && !skip; i++) skip = strcmp(other[i], low) == 0;
        if (skip) {
            ok = false;
            continue;
        }
        unsigned pos = 0;
        while (pos < *n && strcmp(list[pos], low) < 0) pos++;
        if (pos < *n && strcmp(list[pos], low) == 0) continue; /* repeated updates are harmless */
        if (*n >= KELP_BHV_AVD_MAX_FILTER) return KELP_ERR_PARSE;
        memmove(list[pos + 1], list[pos], (size_t)(*n - pos) * KELP_MAX_NAME);
        memcpy(list[pos], low, il + 1);
        (*n)++;
    }
    return ok ? 0 : KELP_ERR_PARSE;
}

/* pts: room for KELP_HELM_MAX_PTS points to check the polygon with (the helm's workspace) */
static int add_region(char list[][KELP_HELM_MAX_FLAG_VAL], unsigned *n, const char *v, kelp_bhv_pt *pts)
{
    unsigned np;
    if (*n >= KELP_BHV_AVD_MAX_REGION || kelp_helm_parse_points(v, pts, KELP_HELM_MAX_PTS, &np) < 0 || np < 3 ||
        !hx_copy(list[*n], KELP_HELM_MAX_FLAG_VAL, v, strlen(v)))
        return KELP_ERR_PARSE;
    (*n)++;
    return 0;
}

/* bearing_lines = white:0, green:0.65, yellow:0.8, red:1.0 [, info:range|relevance], as
 * IvPContactBehavior: colours lower-cased and added to those already given; the first bad
 * component stops further colours (info still read); the parameter itself never fails */
static int set_lines(kelp_bhv_avoid *a, const char *v)
{
    a->bearing_line_show = false;
    bool valid = true;
    for (const char *item = v;;) {
        const char *e = strchr(item, ',');
        size_t in = e ? (size_t)(e - item) : strlen(item);
        const char *c = memchr(item, ':', in);
        const char *l = item, *r = c ? c + 1 : item + in;
        size_t ln = c ? (size_t)(c - item) : in, rn = c ? in - ln - 1 : 0;
        hx_trim(&l, &ln);
        hx_trim(&r, &rn);
        double d;
        if (ln == 4 && kelp_util_strieq_n(l, ln, "info") && rn == 5 && !strncmp(r, "range", 5))
            a->bearing_info_range = true;
        else if (ln == 4 && kelp_util_strieq_n(l, ln, "info") && rn == 9 && !strncmp(r, "relevance", 9))
            a->bearing_info_range = false;
        else if (valid && ln > 0 && hx_number(r, rn, &d) && a->nlines < KELP_BHV_AVD_MAX_LINES &&
                 hx_copy(a->line_color[a->nlines], sizeof a->line_color[0], l, ln)) {
            for (char *q = a->line_color[a->nlines]; *q; q++) *q = hx_lower(*q);
            a->line_thresh[a->nlines++] = d;
            a->bearing_line_show = true;
        } else
            valid = false;
        if (!e) return 0;
        item = e + 1;
    }
}

/* IvPContactBehavior::addContactFlag's tags: "<R", ">R", "@<R", "@>R" (R >= 0) or an event tag */
static bool cnflag_tag_ok(const char *v)
{
    while (*v == ' ' || *v == '\t') v++;
    size_t tl = strcspn(v, " \t");
    if (tl == 0 || v[tl] == '\0') return false;
    size_t skip = v[0] == '@' && (v[1] == '<' || v[1] == '>') ? 2 : (v[0] == '<' || v[0] == '>') ? 1 : 0;
    double r;
    if (skip) return hx_number(v + skip, tl - skip, &r) && r >= 0;
    static const char *const ev[] = {"@cpa", "@os_passed_cn", "@cn_passed_os", "@os_crossed_cn", "@cn_crossed_os"};
    for (size_t i = 0; i < sizeof ev / sizeof ev[0]; i++)
        if (!strncmp(v, ev[i], strlen(ev[i]))) return true;
    return false;
}

static int avd_set_param(kelp_bhv *b, const char *p, const char *v)
{
    kelp_bhv_avoid *a = &b->u.avoid;
    size_t vn = strlen(v);
    double d;
    /* IvPContactBehavior's parameters */
    if (!strcmp(p, "contact")) { /* kept upper-case, as MOOS-IvP (RANGE_AVD_<CONTACT>); looked up by name */
        if (vn == 0 || !hx_copy(a->contact, sizeof a->contact, v, vn)) return KELP_ERR_PARSE;
        for (char *c = a->contact; *c; c++)
            if (*c >= 'a' && *c <= 'z') *c = (char)(*c - 'a' + 'A');
        return 0;
    }
    if (!strcmp(p, "extrapolate")) return set_bool(v, &a->extrapolate);
    if (!strcmp(p, "post_per_contact_info")) return set_bool(v, &a->post_per_contact_info);
    if (!strcmp(p, "match_name")) return add_name(a->match_name, &a->nmatch_name, a->ignore_name, a->nignore_name, v);
    if (!strcmp(p, "ignore_name")) return add_name(a->ignore_name, &a->nignore_name, a->match_name, a->nmatch_name, v);
    if (!strcmp(p, "match_group"))
        return add_name(a->match_group, &a->nmatch_group, a->ignore_group, a->nignore_group, v);
    if (!strcmp(p, "ignore_group"))
        return add_name(a->ignore_group, &a->nignore_group, a->match_group, a->nmatch_group, v);
    if (!strcmp(p, "match_type") || !strcmp(p, "contact_type_required"))
        return add_name(a->match_type, &a->nmatch_type, a->ignore_type, a->nignore_type, v);
    if (!strcmp(p, "ignore_type")) return add_name(a->ignore_type, &a->nignore_type, a->match_type, a->nmatch_type, v);
    if (!strcmp(p, "match_region")) return add_region(a->match_region, &a->nmatch_region, v, b->helm->ws_bhv.pts);
    if (!strcmp(p, "ignore_region")) return add_region(a->ignore_region, &a->nignore_region, v, b->helm->ws_bhv.pts);
    if (!strcmp(p, "strict_ignore")) {
        bool t;
        if (set_bool(v, &t) < 0) return KELP_ERR_PARSE;
        a->strict_ignore = t;
        return 0;
    }
    if (!strcmp(p, "exit_on_filter_vtype")) return set_bool(v, &a->exit_on_filter_vtype);
    if (!strcmp(p, "exit_on_filter_group")) return set_bool(v, &a->exit_on_filter_group);
    if (!strcmp(p, "exit_on_filter_region")) return set_bool(v, &a->exit_on_filter_region);
    if (!strcmp(p, "cnflag")) {
        if (!cnflag_tag_ok(v) || a->ncnflag >= KELP_BHV_AVD_MAX_CNFLAGS ||
            !hx_copy(a->cnflag[a->ncnflag], sizeof a->cnflag[0], v, vn))
            return KELP_ERR_PARSE;
        a->ncnflag++;
        return 0;
    }
    if (!strcmp(p, "decay")) {
        const char *c = strchr(v, ',');
        double s, e;
        if (!c || !hx_number(v, (size_t)(c - v), &s) || !hx_number(c + 1, strlen(c + 1), &e) || s < 0 || s > e)
            return KELP_ERR_PARSE;
        a->decay_start = s, a->decay_end = e;
        return 0;
    }
    if (!strcmp(p, "decay_end")) {
        if (!hx_number(v, vn, &d)) return KELP_ERR_PARSE;
        a->decay_end = d;
        return 0;
    }
    if (!strcmp(p, "on_no_contact_ok")) return set_bool(v, &a->on_no_contact_ok);
    if (!strcmp(p, "time_on_leg")) return nonneg(v, &a->time_on_leg);
    if (!strcmp(p, "bearing_line_label_show")) return set_bool(v, &a->bearing_line_label_show);
    if (!strcmp(p, "bearing_line_show")) return set_bool(v, &a->bearing_line_show);
    if (!strcmp(p, "bearing_lines") || !strcmp(p, "bearing_line_config")) return set_lines(a, v);
    if (!strcmp(p, "use_plat_model")) return set_bool(v, &a->use_plat_model);
    /* BHV_AvoidCollision's own */
    if (!strcmp(p, "pwt_inner_dist")) return pair_low(v, &a->pwt_inner_dist, &a->pwt_outer_dist);
    if (!strcmp(p, "pwt_outer_dist")) return pair_high(v, &a->pwt_inner_dist, &a->pwt_outer_dist);
    if (!strcmp(p, "min_util_cpa_dist")) return pair_low(v, &a->min_util_cpa_dist, &a->max_util_cpa_dist);
    if (!strcmp(p, "max_util_cpa_dist")) return pair_high(v, &a->min_util_cpa_dist, &a->max_util_cpa_dist);
    if (!strcmp(p, "completed_dist")) return nonneg(v, &a->completed_dist);
    if (!strcmp(p, "collision_depth")) {
        if (!hx_number(v, vn, &d) || d <= 0) return KELP_ERR_PARSE;
        a->collision_depth = d; /* accepted; kelp builds the course x speed function only */
        return 0;
    }
    if (!strcmp(p, "pwt_grade")) {
        static const char *const g[3] = {"linear", "quadratic", "quasi"};
        for (int i = 0; i < 3; i++)
            if (hx_ieq(v, g[i])) {
                a->pwt_grade = i;
                return 0;
            }
        return KELP_ERR_PARSE;
    }
    if (!strcmp(p, "roc_max_heighten")) {
        if (nonneg(v, &a->roc_max_heighten) < 0) return KELP_ERR_PARSE;
        if (a->roc_max_dampen > a->roc_max_heighten) a->roc_max_dampen = a->roc_max_heighten;
        return 0;
    }
    if (!strcmp(p, "roc_max_dampen")) return nonneg(v, &a->roc_max_dampen);
    if (!strcmp(p, "no_alert_request")) return set_bool(v, &a->no_alert_request);
    if (!strcmp(p, "verbose")) return set_bool(v, &a->verbose);
    if (!strcmp(p, "use_refinery")) return set_bool(v, &a->use_refinery);
    if (!strcmp(p, "check_plateaus")) return set_bool(v, &a->check_plateaus);
    if (!strcmp(p, "check_validity")) return set_bool(v, &a->check_validity);
    if (!strcmp(p, "pcheck_thresh")) return nonneg(v, &a->pcheck_thresh);
    if (!strcmp(p, "can_disable")) return set_bool(v, &a->can_disable);
    return KELP_ERR_NOTFOUND;
}

/* MOOS-IvP's filter summary (ExFilterSet::getSummary): "key=value" entries joined by ", ",
 * ignore before match for groups, names, types, then regions; strict_ignore only when there
 * is an ignore_type or ignore_group */
static size_t filter_summary(const kelp_bhv_avoid *a, char *buf, size_t cap)
{
    size_t n = 0;
    const struct { const char *key; const char (*list)[KELP_MAX_NAME]; unsigned cnt; } kinds[6] = {
        {"ignore_group", a->ignore_group, a->nignore_group}, {"match_group", a->match_group, a->nmatch_group},
        {"ignore_name", a->ignore_name, a->nignore_name},    {"match_name", a->match_name, a->nmatch_name},
        {"ignore_type", a->ignore_type, a->nignore_type},    {"match_type", a->match_type, a->nmatch_type}};
    buf[0] = '\0';
    for (int k = 0; k < 6; k++)
        for (unsigned i = 0; i < kinds[k].cnt; i++)
            n += hx_cat(buf + n, cap - n, n ? ", " : "", kinds[k].key, "=", kinds[k].list[i], HX_END);
    for (unsigned i = 0; i < a->nignore_region; i++)
        n += hx_cat(buf + n, cap - n, n ? ", " : "", "ignore_region=", a->ignore_region[i], HX_END);
    for (unsigned i = 0; i < a->nmatch_region; i++)
        n += hx_cat(buf + n, cap - n, n ? ", " : "", "match_region=", a->match_region[i], HX_END);
    if (a->nignore_type || a->nignore_group)
        n += hx_cat(buf + n, cap - n, n ? ", " : "", "strict_ignore=", a->strict_ignore != 0 ? "true" : "false",
                    HX_END);
    return n;
}

/* onHelmStart: a spawn template with an UPDATES variable asks the contact manager for alerts */
static void avd_helm_start(kelp_bhv *b)
{
    const kelp_bhv_avoid *a = &b->u.avoid;
    if (a->no_alert_request || !b->updates[0] || !hx_ieq(b->templating, "spawn"))
        return;
    /* composed in the helm's behaviour workspace */
    char *req = b->helm->ws_bhv.post, *filt = b->helm->ws_bhv.post2, *ar = b->helm->ws_bhv.num[0],
         *cr = b->helm->ws_bhv.num[1];
    hx_fmt_x(ar, sizeof b->helm->ws_bhv.num[0], a->pwt_outer_dist, 1);
    hx_fmt_x(cr, sizeof b->helm->ws_bhv.num[1], a->completed_dist, 1);
    (void)filter_summary(a, filt, sizeof b->helm->ws_bhv.post2);
    /* MOOS-IvP's exact string, separators included (augmentSpec joins the summary with ",") */
    hx_cat(req, sizeof b->helm->ws_bhv.post, "id=", b->name, ", on_flag=", b->updates, "=name=$[VNAME] # contact=$[VNAME]",
           ",alert_range=", ar, ", cpa_range=", cr, filt[0] ? "," : "", filt, HX_END);
    kelp_helm_bhv_post_string(b, "BCM_ALERT_REQUEST", req, NULL);
}

double kelp_helm_bhv_avoid_relevance(double range, double inner, double outer, int grade)
{
    if (range >= outer) return 0;
    if (outer <= inner) return 1; /* degenerate rings (MOOS-IvP would divide by zero) */
    /* no cap inside the inner ring: MOOS-IvP's getRelevance overwrites its cap and grades on */
    double p = (outer - range) / (outer - inner);
    if (grade == 1) return p * p;
    if (grade == 2) return pow(p, 1.5);
    return p;
}

/* MOOS-IvP's metric: CPA range to utility */
static inline double cpa_utility(const kelp_bhv_avoid_aof *f, double cpa)
{
    if (cpa < f->min_util) return 0;
    if (cpa > f->max_util) return 100;
    if (f->max_util <= f->min_util) return 100;
    return 25.0 + 75.0 * (cpa - f->min_util) / (f->max_util - f->min_util);
}

double kelp_helm_bhv_avoid_aof_eval(const double *pt, void *user)
{
    const kelp_bhv_avoid_aof *f = user;
    return cpa_utility(f, kelp_cpa_fast_eval(&f->cpa, pt[f->icrs], pt[f->ispd], NULL));
}

/* the utility of squared CPA range q (q > far: beyond max_util surely, 100) */
static inline double avd_util_q(const kelp_bhv_avoid_aof *f, double q, double far)
{
    return q > far ? 100.0 : cpa_utility(f, sqrt(q));
}

#if defined(__GNUC__) && (defined(__SSE2__) || defined(__aarch64__))
#define AVD_VECTORS 1
typedef double avd_v2 __attribute__((vector_size(16)));
typedef long long avd_m2 __attribute__((vector_size(16)));
/* lane by lane: m ? a : b (m from a vector comparison: all ones or all zeros) */
static inline avd_v2 avd_sel(avd_m2 m, avd_v2 a, avd_v2 b)
{
    return (avd_v2)(((avd_m2)a & m) | ((avd_m2)b & ~m));
}
#endif

/* The same AOF along a line of speeds at one course (the Reflector's line sampler): the
 * course's unit vector once, then per speed kelp_cpa_fast_eval_unit's closest approach, the
 * same arithmetic in the same order (so the same bits), its square root taken only where the
 * utility is not already decided by the squared range (beyond max_util: 100). Other lines
 * (course varying) go point by point. */
static void avd_line(const double *pt, unsigned d, const double *x, unsigned n, double *out, void *user)
{
    const kelp_bhv_avoid_aof *f = user;
    if ((int)d != f->ispd || f->icrs > 1 || f->ispd > 1) {
        double q[2] = {pt[0], pt[1]};
        for (unsigned i = 0; i < n; i++) {
            q[d] = x[i];
            out[i] = kelp_helm_bhv_avoid_aof_eval(q, user);
        }
        return;
    }
    double c = pt[f->icrs], ux, uy, xi = f->unit_delta > 0 ? (c - f->unit_low) / f->unit_delta : 0;
    uint32_t k = xi > 0 && xi < (double)f->unit_n ? (uint32_t)(xi + 0.5) : 0;
    if (k < f->unit_n && (double)k * f->unit_delta + f->unit_low == c) /* the course's kept unit vector */
        ux = f->unit[2 * k], uy = f->unit[2 * k + 1];
    else
        kelp_cpa_unit(c, &ux, &uy);
    const double dx = f->cpa.dx, dy = f->cpa.dy, cvx = f->cpa.cvx, cvy = f->cpa.cvy;
    const double tmax = f->cpa.tol > 0.0 ? f->cpa.tol : INFINITY; /* t > tmax: t > tol with tol > 0 */
    /* q > far: sqrt(q) > max_util surely (the margin is far above sqrt's rounding) */
    const double far = f->min_util <= f->max_util && f->max_util >= 0 ? f->max_util * f->max_util * (1 + 1e-9) : INFINITY;
    unsigned i = 0;
#ifdef AVD_VECTORS
    /* two speeds at a time in GCC's vector extension where the target has vectors of two
     * doubles (each lane the scalar loop's operations, so the same bits); others one by one */
    const avd_v2 DX = {dx, dx}, DY = {dy, dy}, CX = {cvx, cvx}, CY = {cvy, cvy}, UX = {ux, ux}, UY = {uy, uy};
    const avd_v2 ZERO = {0.0, 0.0}, TMAX = {tmax, tmax};
    for (; i + 2 <= n; i += 2) {
        avd_v2 xv;
        memcpy(&xv, x + i, sizeof xv);
        avd_v2 v = avd_sel(xv > ZERO, xv, ZERO);
        avd_v2 wx = CX - v * UX, wy = CY - v * UY;
        avd_v2 ww = wx * wx + wy * wy;
        avd_v2 t = avd_sel(ww > ZERO, -(DX * wx + DY * wy) / ww, ZERO);
        t = avd_sel(t < ZERO, ZERO, t);
        t = avd_sel(t > TMAX, TMAX, t);
        avd_v2 ex = DX + wx * t, ey = DY + wy * t, q = ex * ex + ey * ey;
        memcpy(out + i, &q, sizeof q);
    }
#endif
    for (; i < n; i++) {
        double v = x[i] > 0 ? x[i] : 0;
        double wx = cvx - v * ux, wy = cvy - v * uy;
        double ww = wx * wx + wy * wy, t = 0.0;
        if (ww > 0.0) {
            t = -(dx * wx + dy * wy) / ww;
            if (t < 0.0) t = 0.0;
            if (t > tmax) t = tmax;
        }
        double ex = dx + wx * t, ey = dy + wy * t;
        out[i] = ex * ex + ey * ey;
    }
    for (i = 0; i < n; i++) /* squared ranges to utilities */
        out[i] = avd_util_q(f, out[i], far);
}

/* distance a contact travelled dt seconds after its report, speed decaying from d1 to d2 */
static double extrap_dist(double v, double dt, double d1, double d2)
{
    if (dt <= 0) return 0;
    if (dt <= d1) return v * dt;
    if (d2 <= d1) return v * d1;
    if (dt <= d2) return v * d1 + (v + v * (1 - (dt - d1) / (d2 - d1))) / 2 * (dt - d1);
    return v * d1 + v / 2 * (d2 - d1);
}

/* range and its rate from the CPA of contact and ownship now (out of line: its locals are not
 * on the stack while update_info reads the buffer or posts) */
KELP_NOINLINE static bool range_update(kelp_bhv *b)
{
    kelp_bhv_avoid *a = &b->u.avoid;
    kelp_cpa_vessel cn = {a->cn.x, a->cn.y, a->cn.hdg, a->cn.spd}, os = {a->osx, a->osy, a->osh, a->osv};
    kelp_cpa_result r;
    if (kelp_cpa_eval(&cn, &os, a->time_on_leg, &r) != KELP_OK) {
        kelp_helm_bhv_post_warning(b, "non-finite contact or ownship state");
        return false;
    }
    a->prev_range = a->have_range ? a->range : r.range;
    a->have_range = true;
    a->range = r.range;
    a->roc = r.roc;
    return true;
}

/* updatePlatformInfo: ownship from NAV_*, the contact from the ledger. false: none this time */
static bool update_info(kelp_bhv *b)
{
    kelp_bhv_avoid *a = &b->u.avoid;
    bool ok = kelp_helm_bhv_buf_double(b, "NAV_X", &a->osx);
    ok = kelp_helm_bhv_buf_double(b, "NAV_Y", &a->osy) && ok;
    ok = kelp_helm_bhv_buf_double(b, "NAV_HEADING", &a->osh) && ok;
    ok = kelp_helm_bhv_buf_double(b, "NAV_SPEED", &a->osv) && ok;
    if (!ok) {
        kelp_helm_bhv_post_warning(b, "No ownship NAV_X/NAV_Y/NAV_HEADING/NAV_SPEED info in info_buffer.");
        return false;
    }
    if (!a->contact[0]) {
        if (!a->on_no_contact_ok) kelp_helm_bhv_post_error(b, "contact IDX not set.");
        return false;
    }
    const kelp_helm_contact *c = kelp_helm_contact_get(b->helm, a->contact);
    if (!c) { /* MOOS-IvP: an error, or nothing at all with on_no_contact_ok */
        char *msg = b->helm->ws_bhv.post; /* the helm's behaviour workspace; the bound as before */
        hx_cat(msg, KELP_MAX_NAME + 48, a->contact, " x/y/heading/speed info not found", HX_END);
        if (!a->on_no_contact_ok) kelp_helm_bhv_post_error(b, msg);
        return false;
    }
    a->cn = *c;
    if (a->extrapolate && c->utc >= 0) {
        kelp_time now = b->helm->t0 + kelp_helm_bhv_buf_now(b);
        double d = extrap_dist(c->spd > 0 ? c->spd : 0, now - c->utc, a->decay_start, a->decay_end);
        double h = c->hdg * 0.017453292519943295;
        a->cn.x += d * sin(h);
        a->cn.y += d * cos(h);
    }
    return range_update(b);
}


static bool in_list(const char list[][KELP_MAX_NAME], unsigned n, const char *v)
{
    for (unsigned i = 0; i < n; i++)
        if (hx_ieq(list[i], v)) return true;
    return false;
}

static bool kind_ok(const char mt[][KELP_MAX_NAME], unsigned nm, const char ig[][KELP_MAX_NAME], unsigned ni,
                    const char *v, bool strict)
{
    if (nm && (!v[0] || !in_list(mt, nm, v))) return false;
    if (ni && ((strict && !v[0]) || in_list(ig, ni, v))) return false;
    return true;
}

/* p: room for KELP_HELM_MAX_PTS points (the helm's workspace). The contact's position is read
 * after the parse (no doubles held across it: the stack under the parse stays small) */
static bool in_polygon(const char *spec, const kelp_helm_contact *c, kelp_bhv_pt *p)
{
    unsigned n;
    if (kelp_helm_parse_points(spec, p, KELP_HELM_MAX_PTS, &n) < 0 || n < 3) return false;
    double x = c->x, y = c->y;
    bool in = false;
    for (unsigned i = 0, j = n - 1; i < n; j = i++)
        if ((p[i].y > y) != (p[j].y > y) && x < (p[j].x - p[i].x) * (y - p[i].y) / (p[j].y - p[i].y) + p[i].x)
            in = !in;
    return in;
}

/* filterCheckHolds: only the exit_on_filter_* checks end the behaviour */
static bool filter_holds(const kelp_bhv_avoid *a, kelp_bhv_pt *pts)
{
    bool strict = a->strict_ignore != 0; /* MOOS-IvP's filter sets default to strict */
    if (a->exit_on_filter_vtype &&
        !kind_ok(a->match_type, a->nmatch_type, a->ignore_type, a->nignore_type, a->cn.type, strict))
        return false;
    if (a->exit_on_filter_group &&
        !kind_ok(a->match_group, a->nmatch_group, a->ignore_group, a->nignore_group, a->cn.group, strict))
        return false;
    if (a->exit_on_filter_region) {
        bool any = a->nmatch_region == 0;
        for (unsigned i = 0; i < a->nmatch_region; i++) any = any || in_polygon(a->match_region[i], &a->cn, pts);
        for (unsigned i = 0; i < a->nignore_region; i++)
            if (in_polygon(a->ignore_region[i], &a->cn, pts)) any = false;
        if (!any) return false;
    }
    return true;
}

static void post_range(kelp_bhv *b)
{
    const kelp_bhv_avoid *a = &b->u.avoid;
    if (!a->post_per_contact_info) return;
    char var[KELP_MAX_NAME + 16];
    hx_cat(var, sizeof var, "CLSG_SPD_AVD_", a->contact, HX_END);
    kelp_helm_bhv_post_double(b, var, floor(a->roc * 10 + 0.5) / 10, NULL);
    hx_cat(var, sizeof var, "RANGE_AVD_", a->contact, HX_END);
    if (a->range <= 10) kelp_helm_bhv_post_double(b, var, a->range, NULL);
    else kelp_helm_bhv_post_int(b, var, a->range, NULL);
}

/* IvPContactBehavior::postViewableBearingLine: XYSegList's spec, points to 1 decimal, label
 * <us>_<name>, label colour white (shown) or pink, the first colour whose threshold the index
 * does not exceed (none: MOOS-IvP's "blank", not a colour, so no edge_color), time, duration
 * 100; inactive: XYSegList's get_spec_inactive */
static void post_bearing_line(kelp_bhv *b, bool active)
{
    const kelp_bhv_avoid *a = &b->u.avoid;
    if (!a->bearing_line_show) return;
    /* composed in the helm's behaviour workspace */
    char *spec = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num;
    const size_t cap = sizeof b->helm->ws_bhv.post;
    if (!active) {
        hx_cat(spec, cap, "pts={0,0:9,0:0,9},active=false,label=", b->us, "_", b->name, HX_END);
        kelp_helm_bhv_post_string(b, "VIEW_SEGLIST", spec, NULL);
        return;
    }
    double index = a->bearing_info_range ? a->range : a->relevance;
    const char *color = NULL;
    for (unsigned i = 0; i < a->nlines && !color; i++)
        if (index <= a->line_thresh[i]) color = a->line_color[i];
    char *x1 = nb[0], *y1 = nb[1], *x2 = nb[2], *y2 = nb[3], *t = nb[4];
    hx_fmt_x(x1, sizeof nb[0], a->osx, 1);
    hx_fmt_x(y1, sizeof nb[0], a->osy, 1);
    hx_fmt_x(x2, sizeof nb[0], a->cn.x, 1);
    hx_fmt_x(y2, sizeof nb[0], a->cn.y, 1);
    hx_fmt_x(t, sizeof nb[0], b->helm->t0 + kelp_helm_bhv_buf_now(b), 2);
    hx_cat(spec, cap, "pts={", x1, ",", y1, ":", x2, ",", y2, "},label=", b->us, "_", b->name,
           ",label_color=", a->bearing_line_label_show ? "white" : "pink", color ? ",edge_color=" : "",
           color ? color : "", ",time=", t, ",duration=100", HX_END);
    kelp_helm_bhv_post_string(b, "VIEW_SEGLIST", spec, NULL);
}

bool helm_avoid_macro(const kelp_bhv *b, const char *m, size_t ml, char *val, size_t cap)
{
    const kelp_bhv_avoid *a = &b->u.avoid;
    /* a constant table (not built on the stack): the macro, then its string or number */
    static const struct { const char *m; unsigned char what, dec; } mac[] = {
        {"CONTACT", 0, 0}, {"CN_NAME", 0, 0}, {"CN_VTYPE", 1, 0}, {"CN_GROUP", 2, 0}, {"CN_RANGE", 3, 1},
        {"RANGE", 3, 1},   {"CNX", 4, 3},     {"CNY", 5, 3},      {"CNH", 6, 3},      {"CNV", 7, 3},
        {"OSX", 8, 3},     {"OSY", 9, 3},     {"OSH", 10, 3},     {"OSV", 11, 3}};
    for (size_t i = 0; i < sizeof mac / sizeof mac[0]; i++) {
        if (strlen(mac[i].m) != ml || strncmp(m, mac[i].m, ml) != 0) continue;
        if (mac[i].what < 3) {
            const char *s = mac[i].what == 0 ? a->contact : mac[i].what == 1 ? a->cn.type : a->cn.group;
            return hx_copy(val, cap, s, strlen(s));
        }
        /* (picked by a switch, not from an array of the nine built on the stack) */
        double d;
        switch (mac[i].what) {
        case 3: d = a->range; break;
        case 4: d = a->cn.x; break;
        case 5: d = a->cn.y; break;
        case 6: d = a->cn.hdg; break;
        case 7: d = a->cn.spd; break;
        case 8: d = a->osx; break;
        case 9: d = a->osy; break;
        case 10: d = a->osh; break;
        default: d = a->osv; break;
        }
        hx_fmt_x(val, cap, d, mac[i].dec);
        return true;
    }
    return false;
}

/* cnflag "<R VAR=val" / ">R VAR=val": posted while the contact is within / beyond R;
 * "@<R" / "@>R": posted once when the range crosses R inward / outward since the last update.
 * Event tags (@cpa, @os_passed_cn, ...) are accepted and not posted. */
KELP_NOINLINE static void contact_flags(kelp_bhv *b)
{
    const kelp_bhv_avoid *a = &b->u.avoid;
    for (unsigned i = 0; i < a->ncnflag; i++) {
        const char *f = a->cnflag[i];
        while (*f == ' ' || *f == '\t') f++;
        bool once = f[0] == '@';
        const char *t = once ? f + 1 : f;
        if (t[0] != '<' && t[0] != '>') continue;
        const char *sp = strpbrk(t, " \t");
        double r;
        kelp_helm_pair *p = &b->helm->ws_bhv.pair; /* the helm's workspace, not the stack */
        if (!sp || !hx_number(t + 1, (size_t)(sp - t - 1), &r) || !hx_pair(sp + 1, p)) continue;
        bool post;
        if (once && t[0] == '<') post = a->range <= r && a->prev_range > r;
        else if (once) post = a->range >= r && a->prev_range < r;
        else post = t[0] == '<' ? a->range <= r : a->range >= r;
        if (!post) continue;
        if (!p->is_str) {
            kelp_helm_bhv_post_double(b, p->var, p->dval, "repeatable");
            continue;
        }
        helm_post_flag_string(b, p->var, p->sval, "repeatable");
    }
}

static void avd_idle(kelp_bhv *b)
{
    kelp_bhv_avoid *a = &b->u.avoid;
    if (!update_info(b)) return;
    post_range(b);
    if (!filter_holds(a, b->helm->ws_bhv.pts) || a->range >= a->completed_dist * 1.1) kelp_helm_bhv_set_complete(b);
}

/* the objective the Reflector samples, in the helm's workspace (out of line: its locals are
 * not on the stack while the Reflector runs) */
KELP_NOINLINE static int aof_setup(kelp_bhv *b, kelp_bhv_avoid_aof *f)
{
    const kelp_bhv_avoid *a = &b->u.avoid;
    f->icrs = kelp_ivp_domain_index(&b->dom, "course");
    f->ispd = kelp_ivp_domain_index(&b->dom, "speed");
    if (f->icrs < 0 || f->ispd < 0) return KELP_ERR_NOTFOUND;
    const kelp_ivp_var *cv = &b->dom.var[f->icrs];
    if (cv->points <= KELP_BHV_AVD_UNITS && (f->unit_n != cv->points || f->unit_low != cv->low || f->unit_delta != cv->delta)) {
        for (uint32_t i = 0; i < cv->points; i++)
            kelp_cpa_unit(kelp_ivp_domain_value(&b->dom, (unsigned)f->icrs, i), &f->unit[2 * i], &f->unit[2 * i + 1]);
        f->unit_n = cv->points, f->unit_low = cv->low, f->unit_delta = cv->delta;
    }
    f->min_util = a->range <= a->min_util_cpa_dist ? a->range / 2 : a->min_util_cpa_dist;
    f->max_util = a->max_util_cpa_dist;
    kelp_cpa_vessel cn = {a->cn.x, a->cn.y, a->cn.hdg, a->cn.spd};
    if (kelp_cpa_fast_init(&f->cpa, &cn, a->osx, a->osy, a->time_on_leg) != KELP_OK) return KELP_ERR_ARG;
    return 0;
}

/* (out of line: its locals are not on the stack while avd_run tests the regions) */
KELP_NOINLINE static int build(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    kelp_bhv_avoid_aof *f = &b->helm->ws_bhv.avd_aof; /* the helm's workspace, not the stack */
    int rc = aof_setup(b, f);
    if (rc < 0) return rc;
    kelp_ivp_aof_fn aof = kelp_helm_bhv_avoid_aof_eval;
    void *user = f;
    size_t cap = w->out_cap < w->pq_cap ? w->out_cap : w->pq_cap;
    kelp_ivp_reflector *r = &b->helm->ws_bhv.refl;   /* the helm's workspace, not the stack */
    /* a failed init leaves r->ok false: kelp_ivp_reflector_create then fails with KELP_ERR_STATE */
    hx_ignore(kelp_ivp_reflector_init(r, &b->dom, aof, user));
    int amount = -1;
    if (kelp_ivp_reflector_set_param(r, "uniform_piece", AVD_PIECE) != 0 ||
        kelp_ivp_reflector_max_pieces(r, -1, -1) > cap) { /* a small pool: as many pieces as fit */
        hx_ignore(kelp_ivp_reflector_init(r, &b->dom, aof, user));
        amount = (int)(cap > 2 ? cap / 2 : 1);
    }
    kelp_ivp_reflector_set_line(r, avd_line);
    rc = kelp_ivp_reflector_create(r, amount, -1, 0, w->out, cap, w->pq, kelp_ivp_reflector_work_len(cap), out);
    if (rc < 0) return rc;
    if (r->have_uniform_piece) { /* BHV_IPF's grid element box: the uniform piece */
        b->ipf_gel_set = true;
        for (unsigned d = 0; d < r->dom.dim && d < KELP_IVP_MAX_DIM; d++)
            b->ipf_gel[d] = (int32_t)r->uniform_piece[d] - 1;
    }
    return kelp_ivp_func_normalize(out, 0, 100);
}

static int avd_run(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    kelp_bhv_avoid *a = &b->u.avoid;
    if (!update_info(b)) return 0;
    post_range(b);
    contact_flags(b);
    if (!filter_holds(a, b->helm->ws_bhv.pts) || a->range >= a->completed_dist * 1.1) {
        post_bearing_line(b, false);
        kelp_helm_bhv_set_complete(b);
        return 0;
    }
    a->relevance = kelp_helm_bhv_avoid_relevance(a->range, a->pwt_inner_dist, a->pwt_outer_dist, a->pwt_grade);
    if (a->relevance <= 0) {
        post_bearing_line(b, false);
        return 0;
    }
    if (build(b, w, out) < 0) {
        kelp_helm_bhv_post_warning(b, "Unable to build the AvoidCollision objective function.");
        return 0;
    }
    b->pwt_factor = a->relevance;
    post_bearing_line(b, true);
    return 1;
}

const kelp_bhv_ops kelp_bhv_avoid_collision_ops = {
    .type = "BHV_AvoidCollision",
    .init = avd_init,
    .set_param = avd_set_param,
    .on_idle = avd_idle,
    .on_run = avd_run,
    .on_helm_start = avd_helm_start,
};
