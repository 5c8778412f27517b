/* kelp helm: BHV_Waypoint, the multi-point waypoint behaviour MOOS-IvP users expect:
 * points (or polygon; newpt adds one, xpoints replaces them keeping the index), order, repeat,
 * capture_radius, slip_radius, capture_line, lead, lead_damper, lead_to_start, lead_condition,
 * speed, speed_alt/use_alt_speed, crs_spd_zaic_ratio (patience), ipf_type (zaic),
 * end_spd, greedy_tour, efficiency_measure, visual_hints, wptflag / wptflag_on_start / cycleflag, reset_on_idle,
 * eager_prev_index_flag, the names of its reports (wpt_status_var, wpt_index_var,
 * cycle_index_var, post_suffix, wpt_dist_to_prev/next); posts WPT_STAT, WPT_INDEX,
 * CYCLE_INDEX, WPT_ODO, WPT_EFF_* (efficiency_measure = all), VIEW_POINT, VIEW_SEGLIST and
 * its flags with MOOS-IvP 24.8's macros ($(NX), $(PX), $(NI), $(CYCLES), $[SPEED], ...).
 *
 * Steering follows MOOS-IvP's BHV_Waypoint: with a lead distance, the vehicle steers at a point
 * `lead` metres (times the damper factor near the trackline) beyond its perpendicular
 * projection on the current leg. The leg starts at the previous waypoint; on the very first
 * leg there is none, so the vehicle heads straight at the first point unless lead_to_start
 * asks for a leg from where it started. The course x speed function is the SimpleWaypoint
 * ZAIC one. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/kv.h>
#include "helm_int.h"
#include <kelp/util.h>

static void wpt_reset(kelp_bhv_wpt *s)
{
    s->index = 0;
    s->cycles = s->cycles_posted = 0;
    s->captured = s->slipped = 0;
    s->repeats_done = 0;
    s->prev_index = -1;
    s->have_prev = false;
    s->have_mark = false;
    s->min_dist = INFINITY;
}

#define SETSTR(dst, src) ((void)hx_copy((dst), sizeof(dst), (src), strlen(src)))

static void wpt_init(kelp_bhv *b)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    (void)hx_copy(b->name, sizeof b->name, "waypoint", 8);
    bhv_use_subdomain(b, "course,speed");
    s->speed = 0;
    s->capture_radius = 3;
    s->slip_radius = 15;
    s->lead = -1;
    s->lead_damper = -1;
    s->slow_dist = s->stop_dist = -1;
    s->speed_alt = -1;
    s->course_pct = 50;
    s->repeat = 0;
    SETSTR(s->var_report, "WPT_STAT");
    SETSTR(s->var_index, "WPT_INDEX");
    SETSTR(s->var_cyindex, "CYCLE_INDEX");
    bhv_hints_default(&s->hints);
    s->odo_virgin = true;
    s->odo_disq = true;
    wpt_reset(s);
    hx_ignore(kelp_helm_bhv_add_info_vars(b, "NAV_X, NAV_Y, NAV_SPEED")); /* a constructor cannot fail: a full list only skips the registration */
}

static int add_flag(kelp_bhv_flag *arr, unsigned *n, unsigned cap, const char *v)
{
    if (*n >= cap || !hx_pair(v, &arr[*n].p))
        return KELP_ERR_PARSE;
    arr[*n].kind = KELP_FLAG_RUN;
    (*n)++;
    return 0;
}

static int parse_bool(const char *v, bool *out)
{
    return bhv_parse_true_false(v, out) ? 0 : KELP_ERR_PARSE;
}

/* a report variable name: no white space, not empty; "silent" (any case) turns it off */
static int set_var(char *dst, size_t cap, const char *v, bool empty_ok)
{
    size_t n = strlen(v);
    if ((!n && !empty_ok) || n >= cap)
        return KELP_ERR_PARSE;
    for (size_t i = 0; i < n; i++)
        if (hx_is_space(v[i]))
            return KELP_ERR_PARSE;
    if (hx_ieq(v, "silent"))
        v = empty_ok ? "" : "silent";
    (void)hx_copy(dst, cap, v, strlen(v));
    return 0;
}

/* lead_condition: a run condition with ',' read as '=' (24.8 writes "VAR,val" too); reached
 * through bhv_general_param, so its check runs on no deeper a stack than a condition's */
int helm_wpt_lead_condition(kelp_bhv *b, const char *v)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    size_t n = strlen(v);
    if (s->nlead_cond >= sizeof s->lead_cond / sizeof s->lead_cond[0] || n >= sizeof s->lead_cond[0])
        return KELP_ERR_NOSPACE;
    char *c = s->lead_cond[s->nlead_cond];
    for (size_t i = 0; i <= n; i++)
        c[i] = v[i] == ',' ? '=' : v[i];
    if (kelp_helm_cond_check(c, bhv_cond_var, b) != 0)
        return KELP_ERR_PARSE;
    s->nlead_cond++;
    return 0;
}

/* end_spd = slow_dist=D1, stop_dist=D2 (24.8's setEndSpeed): both needed, D1 > 0, 0 <= D2 <= D1 */
KELP_NOINLINE static int set_end_speed(kelp_bhv_wpt *s, const char *v)
{
    double slow = -1, stop = -1, d;
    size_t pos = 0, kl, vl;
    const char *k, *val;
    int rc;
    while ((rc = kelp_kv_next(v, ',', &pos, &k, &kl, &val, &vl)) == 1) {
        if (!hx_number(val, vl, &d))
            return KELP_ERR_PARSE;
        if (kl == 9 && !strncmp(k, "slow_dist", 9) && d > 0)
            slow = d;
        else if (kl == 9 && !strncmp(k, "stop_dist", 9) && d >= 0)
            stop = d;
        else
            return KELP_ERR_PARSE;
    }
    if (rc < 0 || slow < 0 || stop < 0 || stop > slow)
        return KELP_ERR_PARSE;
    s->slow_dist = slow;
    s->stop_dist = stop;
    return 0;
}

/* newpt: one more point at the end; xpoints: new points of the same count, the index kept */
KELP_NOINLINE static int wpt_more_points(kelp_bhv *b, const char *p, const char *v)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    kelp_bhv_pt *pts = b->helm->ws_bhv.pts;
    unsigned n;
    if (kelp_helm_parse_points(v, pts, KELP_HELM_MAX_PTS, &n) != 0)
        return KELP_ERR_PARSE;
    if (!strcmp(p, "newpt")) {
        if (n != 1 || s->npts >= KELP_HELM_MAX_PTS)
            return KELP_ERR_PARSE;
        s->pts[s->npts++] = pts[0];
        return 0;
    }
    if (n != s->npts)
        return KELP_ERR_PARSE;
    memcpy(s->pts, pts, sizeof s->pts);
    return 0;
}

static int wpt_set_param(kelp_bhv *b, const char *p, const char *v)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    double d;
    bool num = hx_number(v, strlen(v), &d);
    if (!strcmp(p, "points") || !strcmp(p, "polygon") || !strcmp(p, "point")) {
        /* 24.8: "empty" leaves the list empty on purpose (no warning); "start" takes the
         * vehicle's position once NAV_X/NAV_Y are known (onEveryState) */
        if (hx_ieq(v, "empty") || hx_ieq(v, "start")) {
            s->init = hx_ieq(v, "empty") ? 1 : 2;
            return 0;
        }
        kelp_bhv_pt *pts = b->helm->ws_bhv.pts;  /* parsed aside: a bad list changes nothing */
        unsigned n;
        if (kelp_helm_parse_points(v, pts, KELP_HELM_MAX_PTS, &n) != 0)
            return KELP_ERR_PARSE;
        memcpy(s->pts, pts, sizeof s->pts);
        s->npts = n;
        wpt_reset(s);
        return 0;
    }
    if (!strcmp(p, "newpt") || !strcmp(p, "xpoints"))
        return wpt_more_points(b, p, v);
    /* a change of speed starts the efficiency measure's leg afresh (24.8's odo_leg_disq) */
    if (!strcmp(p, "speed") || !strcmp(p, "speed_alt")) {
        double *dst = p[5] ? &s->speed_alt : &s->speed;
        if (!num || d < 0)
            return KELP_ERR_PARSE;
        s->odo_disq |= d != *dst;
        *dst = d;
        return 0;
    }
    if (!strcmp(p, "use_alt_speed")) {
        bool was = s->use_alt_speed;
        int rc = parse_bool(v, &s->use_alt_speed);
        s->odo_disq |= was != s->use_alt_speed;
        return rc;
    }
    if (!strcmp(p, "wptflag_on_start"))
        return parse_bool(v, &s->wpt_flag_on_start);
    if (!strcmp(p, "reset_on_idle"))
        return parse_bool(v, &s->reset_on_idle);
    if (!strcmp(p, "eager_prev_index_flag"))
        return parse_bool(v, &s->eager_prev);
    if (!strcmp(p, "end_spd"))
        return set_end_speed(s, v);
    if (!strcmp(p, "greedy_tour") || !strcmp(p, "shortest_tour"))
        return parse_bool(v, &s->greedy_pending);
    if (!strcmp(p, "ipf_type") || !strcmp(p, "ipf-type")) /* zaic: the objective built here */
        return hx_ieq(v, "zaic") ? 0 : KELP_ERR_UNSUPPORTED;
    if (!strcmp(p, "capture_radius") || !strcmp(p, "radius"))
        return num && d > 0 ? (s->capture_radius = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "slip_radius") || !strcmp(p, "nm_radius"))
        return num && d >= 0 ? (s->slip_radius = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "capture_line")) {
        if (hx_ieq(v, "absolute")) {
            s->capture_line = true;
            s->capture_radius = s->slip_radius = 0;
            return 0;
        }
        return parse_bool(v, &s->capture_line);
    }
    if (!strcmp(p, "lead")) /* zero or less: off (-1, as 24.8 keeps it) */
        return num ? (s->lead = d > 0 ? d : -1, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "lead_damper"))
        return num && d > 0 ? (s->lead_damper = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "lead_to_start"))
        return parse_bool(v, &s->lead_to_start);
    if (!strcmp(p, "crs_spd_zaic_ratio") || !strcmp(p, "patience"))
        return num && d >= 1 && d <= 99 ? (s->course_pct = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "efficiency_measure")) {
        if (hx_ieq(v, "all") || hx_ieq(v, "off")) {
            s->efficiency = hx_ieq(v, "all");
            return 0;
        }
        return KELP_ERR_PARSE;
    }
    if (!strcmp(p, "visual_hints"))
        return bhv_set_hints(&s->hints, v);
    if (!strcmp(p, "wpt_status") || !strcmp(p, "wpt_status_var"))
        return set_var(s->var_report, sizeof s->var_report, v, false);
    if (!strcmp(p, "wpt_index") || !strcmp(p, "wpt_index_var"))
        return set_var(s->var_index, sizeof s->var_index, v, false);
    if (!strcmp(p, "cycle_index_var"))
        return set_var(s->var_cyindex, sizeof s->var_cyindex, v, false);
    if (!strcmp(p, "wpt_dist_to_prev"))
        return set_var(s->var_dist_prev, sizeof s->var_dist_prev, v, true);
    if (!strcmp(p, "wpt_dist_to_next"))
        return set_var(s->var_dist_next, sizeof s->var_dist_next, v, true);
    if (!strcmp(p, "post_suffix")) {
        /* stored with its leading '_' (added when missing) */
        if (set_var(s->suffix + 1, sizeof s->suffix - 1, v[0] == '_' ? v + 1 : v, true))
            return KELP_ERR_PARSE;
        if (s->suffix[1])
            s->suffix[0] = '_';
        else
            s->suffix[0] = '\0';
        return 0;
    }
    if (!strcmp(p, "currix")) {
        if (!num || d < 0 || d != floor(d))
            return KELP_ERR_PARSE;
        s->index = s->npts && (unsigned)d < s->npts ? (unsigned)d : 0;
        return 0;
    }
    if (!strcmp(p, "repeat")) {
        if (hx_ieq(v, "forever")) {
            s->repeat = -1;
            return 0;
        }
        if (!num || d < 0 || d != floor(d) || d > 1e9)
            return KELP_ERR_PARSE;
        s->repeat = (long)d;
        return 0;
    }
    if (!strcmp(p, "order")) {
        if (hx_ieq(v, "normal"))
            s->reverse = false;
        else if (hx_ieq(v, "reverse") || hx_ieq(v, "reversed"))
            s->reverse = true;
        else if (hx_ieq(v, "toggle"))
            s->reverse = !s->reverse;
        else
            return KELP_ERR_PARSE;
        wpt_reset(s);
        return 0;
    }
    if (!strcmp(p, "wptflag"))
        return add_flag(s->wptflag, &s->nwptflag, 4, v);
    if (!strcmp(p, "cycleflag"))
        return add_flag(s->cycleflag, &s->ncycleflag, 4, v);
    return KELP_ERR_NOTFOUND;
}

static int wpt_params_done(kelp_bhv *b)
{
    (void)b; /* no points is a warning (wpt_post_config), as 24.8's */
    return 0;
}

/* points = start: the vehicle's position, once known, becomes the one point (24.8's
 * onEveryState, x and y to 3 decimals) */
static void wpt_start_point(kelp_bhv *b)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    double x, y;
    if (s->npts || s->init != 2 || !kelp_helm_bhv_buf_double(b, "NAV_X", &x) || !kelp_helm_bhv_buf_double(b, "NAV_Y", &y))
        return;
    s->pts[0].x = round(x * 1000) / 1000;
    s->pts[0].y = round(y * 1000) / 1000;
    s->npts = 1;
    wpt_reset(s);
}

static kelp_bhv_pt point(const kelp_bhv_wpt *s, unsigned i)
{
    return s->pts[s->reverse ? s->npts - 1 - i : i];
}

/* the seglist as 24.8 draws it (XYSegList's spec): active, its vertices to 3 decimals, the
 * label "<us>_<name>" and the hints; erased (run -> idle), to 1 decimal with active=false and
 * the label only; an edge_color "off"/"inactive" draws the erasing stub */
KELP_NOINLINE static void post_seglist(kelp_bhv *b, bool active)
{
    const kelp_bhv_wpt *s = &b->u.wpt;
    /* composed in the helm's behaviour workspace */
    char *buf = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num;
    char *x = nb[0], *y = nb[1], *vs = nb[2], *es = nb[3];
    const size_t cap = sizeof b->helm->ws_bhv.post, ncap = sizeof nb[0];
    const char *us = b->us[0] ? b->us : "vehicle";
    if (active && (hx_ieq(s->hints.edge_color, "off") || hx_ieq(s->hints.edge_color, "inactive"))) {
        hx_cat(buf, cap, "pts={0,0:9,0:0,9},active=false,label=", us, "_", b->name, HX_END);
        kelp_helm_bhv_post_string(b, "VIEW_SEGLIST", buf, NULL);
        return;
    }
    size_t n = hx_cat(buf, cap, "pts={", HX_END);
    for (unsigned i = 0; i < s->npts; i++) {
        kelp_bhv_pt p = point(s, i);
        hx_fmt_x(x, ncap, p.x, active ? 3 : 1);
        hx_fmt_x(y, ncap, p.y, active ? 3 : 1);
        n += hx_cat(buf + n, cap - n, i ? ":" : "", x, ",", y, HX_END);
    }
    n += hx_cat(buf + n, cap - n, active ? "},label=" : "},active=false,label=", us, "_", b->name, HX_END);
    if (active) {
        hx_fmt_x(vs, ncap, s->hints.vertex_size, 1);
        hx_fmt_x(es, ncap, s->hints.edge_size, 1);
        hx_cat(buf + n, cap - n, ",label_color=", s->hints.label_color, ",edge_color=", s->hints.edge_color,
               ",vertex_color=", s->hints.vertex_color, ",vertex_size=", vs, ",edge_size=", es, HX_END);
    }
    kelp_helm_bhv_post_string(b, "VIEW_SEGLIST", buf, NULL);
}

/* the next-point marker (key "wpt") and the track point (key "trk", drawn when it is more
 * than 5 m from the next point) as 24.8 draws them (XYPoint's spec, coordinates to 2
 * decimals); erased as "x=0,y=0,active=false,label=..". pt NULL: erase. */
KELP_NOINLINE static void post_marker(kelp_bhv *b, bool track, const kelp_bhv_pt *pt)
{
    const kelp_bhv_wpt *s = &b->u.wpt;
    /* composed in the helm's behaviour workspace (the text's bound as before: two names and 256) */
    char *spec = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num;
    char *x = nb[0], *y = nb[1], *vs = nb[2];
    const size_t cap = KELP_MAX_NAME * 2 + 256, ncap = sizeof nb[0];
    KELP_STATIC_ASSERT(KELP_MAX_NAME * 2 + 256 <= sizeof b->helm->ws_bhv.post, "VIEW_POINT text fits ws_bhv.post");
    const char *us = b->us[0] ? b->us : "vehicle", *what = track ? "'s trackpt" : "'s nextpt";
    if (!pt) {
        hx_cat(spec, cap, "x=0,y=0,active=false,label=", us, what, HX_END);
    } else {
        hx_fmt_x(x, ncap, pt->x, 2);
        hx_fmt_x(y, ncap, pt->y, 2);
        if (track)
            hx_cat(spec, cap, "x=", x, ",y=", y, ",label=", us, what, ",label_color=", s->hints.nextpt_color,
                   ",vertex_color=", s->hints.nextpt_color, ",vertex_size=4", HX_END);
        else {
            hx_fmt_x(vs, ncap, s->hints.nextpt_vertex_size, 1);
            hx_cat(spec, cap, "x=", x, ",y=", y, ",active=true,label=", us, what, ",label_color=",
                   s->hints.nextpt_lcolor, ",vertex_color=", s->hints.nextpt_color, ",vertex_size=", vs, HX_END);
        }
    }
    kelp_helm_bhv_post_string(b, "VIEW_POINT", spec, track ? "trk" : "wpt");
}

/* a report under its configured name plus post_suffix; "silent" posts nothing */
static bool report_name(const kelp_bhv_wpt *s, const char *var, char *out, size_t cap)
{
    if (!var[0] || hx_ieq(var, "silent"))
        return false;
    hx_cat(out, cap, var, s->suffix, HX_END);
    return true;
}

static void wpt_idle(kelp_bhv *b)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    wpt_start_point(b);
    s->restart = true;
    /* on the way from running to idle (24.8's onRunToIdleState): the drawings erased, with
     * reset_on_idle back to the first point, the efficiency leg dropped, and the distances to
     * the previous and next points posted as -1 */
    if (b->state == KELP_BHV_RUNNING || b->state == KELP_BHV_ACTIVE) {
        if (s->npts) {
            post_marker(b, true, NULL);
            post_marker(b, false, NULL);
            post_seglist(b, false);
        }
        if (s->reset_on_idle) {
            s->index = 0;
            s->repeats_done = 0;
            s->prev_index = -1;
        }
        s->odo_set = false;
        s->odo_disq = true;
        if (s->var_dist_prev[0])
            kelp_helm_bhv_post_double(b, s->var_dist_prev, -1, NULL);
        if (s->var_dist_next[0])
            kelp_helm_bhv_post_double(b, s->var_dist_next, -1, NULL);
    }
}

/* on completion 24.8 erases the route (its onRunToIdleState's erasables; the next-point marker's
 * erasure went out with the completion) */
static void wpt_complete(kelp_bhv *b)
{
    if (b->u.wpt.npts)
        post_seglist(b, false);
}

/* BHV_Waypoint posts the cycle count when it changes from the last it posted (0 at first),
 * also on the iteration the last pass completes */
KELP_NOINLINE static void post_cycle_index(kelp_bhv *b)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    char *var = b->helm->ws_bhv.var;
    if (s->cycles != s->cycles_posted && report_name(s, s->var_cyindex, var, sizeof b->helm->ws_bhv.var)) {
        kelp_helm_bhv_post_double(b, var, (double)s->cycles, NULL);
        s->cycles_posted = s->cycles;
    }
}

KELP_NOINLINE static void post_stat(kelp_bhv *b, double dist)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    /* composed in the helm's behaviour workspace (the text's bound as before: two names and 160) */
    char *buf = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num, *var = b->helm->ws_bhv.var;
    char *ix = nb[0], *hc = nb[1], *ht = nb[2], *cy = nb[3], *ds = nb[4], *et = nb[5];
    const size_t cap = KELP_MAX_NAME * 2 + 160, ncap = sizeof nb[0], vcap = sizeof b->helm->ws_bhv.var;
    KELP_STATIC_ASSERT(KELP_MAX_NAME * 2 + 160 <= sizeof b->helm->ws_bhv.post, "WPT_STAT text fits ws_bhv.post");
    /* eta as 24.8 writes it: the distance over the vehicle's own speed (NAV_SPEED, 0 when none
     * came), printed as printf prints the quotient: "inf" stopped, "-nan" stopped on the point */
    double osv = 0;
    if (!kelp_helm_bhv_buf_double(b, "NAV_SPEED", &osv) || !isfinite(osv))
        osv = 0;
    hx_fmt_ulong(ix, ncap, s->index);
    hx_fmt_ulong(hc, ncap, s->captured);
    hx_fmt_ulong(ht, ncap, s->captured + s->slipped);
    hx_fmt_ulong(cy, ncap, s->cycles);
    hx_fmt_fixed(ds, ncap, dist, 0);
    if (osv != 0)
        hx_fmt_fixed(et, ncap, dist / osv, 0);
    else
        hx_copy(et, ncap, dist > 0 ? "inf" : "-nan", dist > 0 ? 3 : 4);
    hx_cat(buf, cap, "vname=", b->us[0] ? b->us : "vehicle", ",behavior-name=", b->name, ",index=", ix, ",hits=", hc,
           "/", ht, ",cycles=", cy, ",dist=", ds, ",eta=", et, HX_END);
    if (report_name(s, s->var_report, var, vcap))
        kelp_helm_bhv_post_string(b, var, buf, NULL);
    if (report_name(s, s->var_index, var, vcap))
        kelp_helm_bhv_post_double(b, var, (double)s->index, NULL);
    post_cycle_index(b);
}

/* on the iteration a pass ends, 24.8 posts "behavior-name=<name>,completed" (or ",cycled")
 * to the status variable */
KELP_NOINLINE static void post_feedback(kelp_bhv *b, const char *what)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    char *buf = b->helm->ws_bhv.post, *var = b->helm->ws_bhv.var;
    hx_cat(buf, sizeof b->helm->ws_bhv.post, "behavior-name=", b->name, ",", what, HX_END);
    if (report_name(s, s->var_report, var, sizeof b->helm->ws_bhv.var))
        kelp_helm_bhv_post_string(b, var, buf, NULL);
}

/* wptflags (through the duplicate filter) and cycleflags (repeatable), macros expanded */
static void post_pairs(kelp_bhv *b, const kelp_bhv_flag *f, unsigned n, bool repeatable)
{
    const char *key = repeatable ? "repeatable" : NULL;
    for (unsigned i = 0; i < n; i++) {
        if (f[i].p.is_str)
            helm_post_flag_string(b, f[i].p.var, f[i].p.sval, key);
        else
            kelp_helm_bhv_post_double(b, f[i].p.var, f[i].p.dval, key);
    }
}

/* odometry and, with efficiency_measure = all, the leg's efficiency (straight-line distance
 * over distance travelled) when a leg ends */
static void odo_update(kelp_bhv_wpt *s)
{
    if (!s->odo_virgin)
        s->odo_leg += hypot(s->osx - s->odo_px, s->osy - s->odo_py);
    s->odo_virgin = false;
    s->odo_px = s->osx;
    s->odo_py = s->osy;
}

/* A leg's end for efficiency_measure = all (24.8's markOdoLeg): the first mark after a start,
 * an idle spell or a change of speed only marks; later ones post the leg's and the run's
 * straight-line and travelled distances and times (straight-line time at cruise speed) and
 * their ratios. Out of line, as track_point: its locals are not on the stack under the IvP
 * build. */
KELP_NOINLINE static void odo_mark_leg(kelp_bhv *b)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    if (!s->efficiency)
        return;
    double now = kelp_helm_bhv_buf_now(b);
    if (!s->odo_set || s->odo_disq) {
        s->odo_setx = s->osx;
        s->odo_sety = s->osy;
        s->odo_settime = now;
        s->odo_set = true;
        s->odo_leg = 0;
        s->odo_disq = false;
        return;
    }
    double lin = hypot(s->osx - s->odo_setx, s->osy - s->odo_sety), tlin = 0;
    s->eff_linear += lin;
    if (s->speed > 0) {
        tlin = lin / s->speed;
        s->eff_tlinear += tlin;
    }
    double odo = s->odo_leg, todo = now - s->odo_settime;
    s->eff_odo += odo;
    s->eff_todo += todo;
    double e_leg = odo > 0 ? lin / odo : 0, t_leg = todo > 0 ? tlin / todo : 0;
    double e_all = s->eff_odo > 0 ? s->eff_linear / s->eff_odo : 0;
    double t_all = s->eff_todo > 0 ? s->eff_tlinear / s->eff_todo : 0;
    char *buf = b->helm->ws_bhv.post, *var = b->helm->ws_bhv.var; /* the helm's behaviour workspace */
    const size_t cap = sizeof b->helm->ws_bhv.post, vcap = sizeof b->helm->ws_bhv.var;
    const char *us = b->us[0] ? b->us : "vehicle";
    for (int all = 0; all < 2; all++) {
        char (*nb)[32] = b->helm->ws_bhv.num;
        hx_fmt_x(nb[0], 32, all ? s->eff_linear : lin, 1);
        hx_fmt_x(nb[1], 32, all ? s->eff_odo : odo, 1);
        hx_fmt_x(nb[2], 32, all ? e_all : e_leg, 3);
        hx_fmt_x(nb[3], 32, all ? s->eff_tlinear : tlin, 1);
        hx_fmt_x(nb[4], 32, all ? s->eff_todo : todo, 1);
        hx_fmt_x(nb[5], 32, all ? t_all : t_leg, 3);
        hx_cat(buf, cap, "vname=", us, ", bhv_name=", b->name, ", linear_dist=", nb[0], ", odo_dist=", nb[1],
               ", efficiency_dist=", nb[2], ", linear_time=", nb[3], ", odo_time=", nb[4], ", efficiency_time=", nb[5],
               HX_END);
        hx_cat(var, vcap, all ? "WPT_EFF_SUMM_ALL" : "WPT_EFF_SUMM_LEG", s->suffix, HX_END);
        kelp_helm_bhv_post_string(b, var, buf, NULL);
    }
    static const char *const names[4] = { "WPT_EFF_DIST_ALL", "WPT_EFF_TIME_ALL", "WPT_EFF_DIST_LEG", "WPT_EFF_TIME_LEG" };
    for (int i = 0; i < 4; i++) {
        hx_cat(var, vcap, names[i], s->suffix, HX_END);
        kelp_helm_bhv_post_double(b, var, i == 0 ? e_all : i == 1 ? t_all : i == 2 ? e_leg : t_leg, NULL);
    }
    s->odo_setx = s->osx;
    s->odo_sety = s->osy;
    s->odo_settime = now;
    s->odo_leg = 0;
}

/* the start of the current leg for lead steering, or false on the first leg (unless
 * lead_to_start) */
static bool leg_anchor(kelp_bhv_wpt *s, kelp_bhv_pt *a)
{
    if (s->index > 0) {
        *a = point(s, s->index - 1);
        return true;
    }
    if (s->cycles > 0) {
        *a = point(s, s->npts - 1);
        return true;
    }
    if (!s->lead_to_start)
        return false;
    if (!s->have_mark) {
        s->mark.x = s->osx;
        s->mark.y = s->osy;
        s->have_mark = true;
    }
    *a = s->mark;
    return true;
}

/* the point to steer at: the waypoint, or with a lead distance a point on the leg ahead of the
 * vehicle's perpendicular projection on it */
KELP_NOINLINE static kelp_bhv_pt track_point(kelp_bhv_wpt *s, kelp_bhv_pt cur)
{
    kelp_bhv_pt a;
    if (!(s->lead > 0) || !leg_anchor(s, &a))
        return cur;
    double lx = cur.x - a.x, ly = cur.y - a.y, l2 = lx * lx + ly * ly;
    if (!(l2 > 0))
        return cur;
    double t = ((s->osx - a.x) * lx + (s->osy - a.y) * ly) / l2;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double px = a.x + t * lx, py = a.y + t * ly;
    double factor = 1.0;
    if (s->lead_damper > 0) {
        double off = hypot(px - s->osx, py - s->osy);
        if (off < s->lead_damper)
            factor += 2 * (1 - off / s->lead_damper);
    }
    double len = sqrt(l2), d = hypot(cur.x - px, cur.y - py);
    if (d > s->lead * factor)
        d = s->lead * factor;
    kelp_bhv_pt tp = { px + d * lx / len, py + d * ly / len };
    return tp;
}

/* greedy_tour (24.8's greedyPath, applied once ownship's position is known): from the vehicle,
 * each next point the nearest of those not yet taken (the first of equals); the list then
 * starts over as a new one */
KELP_NOINLINE static void wpt_greedy(kelp_bhv_wpt *s)
{
    double x = s->osx, y = s->osy;
    for (unsigned k = 0; k < s->npts; k++) { /* visiting positions k.. still free */
        unsigned best = k;
        double bd = -1;
        for (unsigned j = k; j < s->npts; j++) {
            kelp_bhv_pt p = point(s, j);
            double d = hypot(p.x - x, p.y - y);
            if (bd < 0 || d < bd) {
                bd = d;
                best = j;
            }
        }
        /* swap visiting positions k and best in the stored order */
        unsigned a = s->reverse ? s->npts - 1 - k : k, c = s->reverse ? s->npts - 1 - best : best;
        kelp_bhv_pt t = s->pts[a];
        s->pts[a] = s->pts[c];
        s->pts[c] = t;
        x = point(s, k).x;
        y = point(s, k).y;
    }
    wpt_reset(s);
}

/* 24.8's WaypointEngine::setNextWaypoint: a capture strictly inside capture_radius; a slip
 * when moving away after coming within slip_radius (only if it exceeds capture_radius);
 * independently, crossing the line through the point square to the leg from the previous
 * point (counted as neither). Out of line: its locals are not on wpt_advance's frame. */
KELP_NOINLINE static bool wpt_arrived(kelp_bhv_wpt *s, kelp_bhv_pt cur, double dist)
{
    if (dist < s->min_dist)
        s->min_dist = dist;
    if (dist < s->capture_radius) {
        s->captured++;
        return true;
    }
    bool hit = false;
    if (s->slip_radius > s->capture_radius && dist > s->min_dist && s->min_dist <= s->slip_radius) {
        s->slipped++;
        hit = true;
    }
    if (s->capture_line) {
        /* past the line through the waypoint square to the leg from the previous point */
        double lx = cur.x - s->prev.x, ly = cur.y - s->prev.y;
        hit |= (lx != 0 || ly != 0) && (s->osx - cur.x) * lx + (s->osy - cur.y) * ly >= 0;
    }
    return hit;
}

#define WPT_EV_DONE 1u  /* wpt_advance: the list completed */
#define WPT_EV_FLAGS 2u /* wpt_advance: the wptflags are due */
#define WPT_EV_CYCLED 4u /* wpt_advance: a pass ended (cycleflags) */

/* onRunState up to the objective: captures, reports and the course to steer (*crs); false when
 * no objective is made this time. Out of line: its locals are not on the stack under the IvP
 * build that follows. */
KELP_NOINLINE static bool wpt_advance(kelp_bhv *b, unsigned *ev)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    /* 24.8: no points (points = start before the position is known included): nothing, quietly;
     * then ownship's X/Y and heading must be known (IvPBehavior::updatePlatformInfo): a
     * BHV_ERROR otherwise, which halts the helm */
    wpt_start_point(b);
    if (s->npts == 0)
        return false;
    if (!bhv_platform_info(b, &s->osx, &s->osy, &s->osh))
        return false;
    if (s->greedy_pending) {
        s->greedy_pending = false;
        wpt_greedy(s);
    }
    if (!s->have_prev || s->restart || b->state == KELP_BHV_IDLE || b->state == KELP_BHV_NONE) {
        /* the capture line of the first leg is measured from where the vehicle is when the
         * behaviour first runs; odometry picks up from here; an efficiency leg interrupted by
         * an idle spell is not measured (24.8's onIdleToRunState) */
        if (!s->have_prev) {
            s->prev.x = s->osx;
            s->prev.y = s->osy;
            s->have_prev = true;
        }
        s->odo_virgin = true;
        s->odo_disq = true;
        s->restart = false;
        s->min_dist = INFINITY;
    }
    odo_update(s);
    const unsigned this_i = s->index;
    kelp_bhv_pt cur = point(s, this_i);
    double dist = hypot(cur.x - s->osx, cur.y - s->osy);
    bool hit = wpt_arrived(s, cur, dist);
    bool completed = false, cycled = false;
    if (hit) {
        odo_mark_leg(b);
        s->index++;
        if (s->index >= s->npts) {
            s->cycles++;
            s->index = 0;
            s->repeats_done++;
            cycled = true;
            completed = !(s->repeat < 0 || s->repeats_done <= (unsigned long)s->repeat);
        }
    }
    char *var = b->helm->ws_bhv.var; /* the helm's behaviour workspace */
    hx_cat(var, sizeof b->helm->ws_bhv.var, "WPT_ODO", s->suffix, HX_END);
    kelp_helm_bhv_post_double(b, var, s->odo_leg, NULL);
    if (cycled) {
        post_feedback(b, completed ? "completed" : "cycled");
        *ev |= WPT_EV_CYCLED; /* the cycleflags: posted by the caller, off this frame */
    }
    if (completed) {
        *ev |= WPT_EV_DONE; /* the caller completes the behaviour (its endflags), off this frame */
        if (b->perpetual) { /* ready for the next traversal (24.8's resetForNewTraversal) */
            s->repeats_done = 0;
            s->min_dist = INFINITY;
        }
    } else {
        s->nextpt = point(s, s->index);
        cur = s->nextpt;
        dist = hypot(cur.x - s->osx, cur.y - s->osy);
        if (hit) /* an advance: the closest approach to the new point starts here; a new cycle starts afresh */
            s->min_dist = cycled ? INFINITY : dist;
    }
    /* the wptflags: when the point steered for changed, a point was reached or the list
     * completed, and with wptflag_on_start on the first run; $(PX),$(PY) then name the point
     * just left, which starts the next leg */
    if (hit || completed || cur.x != point(s, this_i).x || cur.y != point(s, this_i).y ||
        (s->wpt_flag_on_start && !s->wpt_flag_published)) {
        s->prev = point(s, this_i);
        if (s->eager_prev)
            s->prev_index = (int)this_i;
        *ev |= WPT_EV_FLAGS; /* posted by the caller, off this frame */
        s->wpt_flag_published = true;
    }
    if (completed) {
        post_cycle_index(b);
        post_marker(b, false, NULL); /* no next point: 24.8 erases the marker */
        return false;
    }
    return true;
}

/* the distance still to go in this pass: to the point steered for, then along the rest of the
 * list (24.8's distToEndCycle); with the passes still owed (distToEndFinal), each a full list
 * plus the leg back to its first point; -1 for endless repeats */
static double dist_to_go(const kelp_bhv_wpt *s, bool all)
{
    if (all && s->repeat < 0)
        return -1;
    kelp_bhv_pt c = point(s, s->index);
    double d = hypot(c.x - s->osx, c.y - s->osy), list = 0;
    for (unsigned i = 0; i + 1 < s->npts; i++) {
        kelp_bhv_pt p = point(s, i), q = point(s, i + 1);
        double l = hypot(q.x - p.x, q.y - p.y);
        list += l;
        if (i >= s->index)
            d += l;
    }
    unsigned long owed = all && (unsigned long)s->repeat > s->repeats_done ? (unsigned long)s->repeat - s->repeats_done : 0;
    if (owed && s->npts) {
        kelp_bhv_pt f = point(s, 0), l = point(s, s->npts - 1);
        d += (double)owed * (list + hypot(f.x - l.x, f.y - l.y));
    }
    return d;
}

bool helm_wpt_macro(const kelp_bhv *b, const char *m, size_t ml, char *val, size_t cap)
{
    const kelp_bhv_wpt *s = &b->u.wpt;
    /* a constant table: the macro, how it is written (0 text, 1 integer, 2 three decimals) */
    static const struct { const char *m; unsigned char what, how; } mac[] = {
        {"POINTS", 0, 0},    {"IPF_TYPE", 1, 0},  {"ORDER", 2, 0},      {"SPEED", 3, 2},   {"SPEED_ALT", 4, 2},
        {"USE_SPEED_ALT", 5, 1}, {"WPT_FLAG_ON_START", 6, 1}, {"LEAD_TO_START", 7, 1}, {"LEAD_DAMPER", 8, 2},
        {"NI", 9, 1},        {"IX", 9, 1},        {"NX", 10, 2},        {"NY", 11, 2},     {"PI", 12, 1},
        {"PX", 13, 2},       {"X", 13, 2},        {"PY", 14, 2},        {"Y", 14, 2},      {"CYCLES", 15, 1},
        {"CYCREM", 16, 1},   {"WPTS_HIT", 17, 1}, {"WPTS_REM", 18, 1},  {"WPTS", 19, 1},   {"CYC_DIST_TOGO", 20, 2},
        {"ALL_DIST_TOGO", 21, 2}, {"OSX", 22, 2}, {"OSY", 23, 2},       {"OSH", 24, 2},    {"OSV", 25, 2}};
    for (size_t i = 0; i < sizeof mac / sizeof mac[0]; i++) {
        if (strlen(mac[i].m) != ml || strncmp(m, mac[i].m, ml) != 0)
            continue;
        double d = 0;
        switch (mac[i].what) {
        case 0: { /* pts={x,y:...}, each number written in place (no buffers on the stack) */
            size_t n = hx_cat(val, cap, "pts={", HX_END);
            for (unsigned k = 0; k < s->npts && n + 2 < cap; k++) {
                kelp_bhv_pt p = point(s, k);
                n += hx_cat(val + n, cap - n, k ? ":" : "", HX_END);
                hx_fmt_x(val + n, cap - n, p.x, 2);
                n += strlen(val + n);
                n += hx_cat(val + n, cap - n, ",", HX_END);
                hx_fmt_x(val + n, cap - n, p.y, 2);
                n += strlen(val + n);
            }
            hx_cat(val + n, cap - n, "}", HX_END);
            return true;
        }
        case 1: return hx_copy(val, cap, "zaic", 4);
        case 2: return s->reverse ? hx_copy(val, cap, "reverse", 7) : hx_copy(val, cap, "normal", 6);
        case 3: d = s->speed; break;
        case 4: d = s->speed_alt; break;
        case 5: d = s->use_alt_speed; break;
        case 6: d = s->wpt_flag_on_start; break;
        case 7: d = s->lead_to_start; break;
        case 8: d = s->lead_damper; break;
        case 9: d = s->index; break;
        case 10: d = s->nextpt.x; break;
        case 11: d = s->nextpt.y; break;
        case 12: d = s->prev_index; break;
        case 13: d = s->have_prev ? s->prev.x : 0; break;
        case 14: d = s->have_prev ? s->prev.y : 0; break;
        case 15: d = (double)s->cycles; break;
        case 16: d = s->repeat > 0 && (unsigned long)s->repeat > s->repeats_done ? (double)((unsigned long)s->repeat - s->repeats_done) : 0; break;
        case 17: d = (double)(s->captured + s->slipped); break;
        case 18: d = (double)(s->npts - s->index); break;
        case 19: d = s->npts; break;
        case 20: d = dist_to_go(s, false); break;
        case 21: d = dist_to_go(s, true); break;
        case 22: d = s->osx; break;
        case 23: d = s->osy; break;
        case 24: d = s->osh; break;
        default: /* NAV_SPEED, 0 when none came (24.8's m_osv) */
            if (!kelp_helm_bhv_buf_double(b, "NAV_SPEED", &d) || !isfinite(d))
                d = 0;
            break;
        }
        if (mac[i].how == 1) { /* an integer ($(PI) is -1 before any point) */
            if (cap < 2)
                return false;
            if (d < 0)
                val[0] = '-';
            hx_fmt_ulong(val + (d < 0), cap - (d < 0), (unsigned long)fabs(d));
        } else {
            hx_fmt_x(val, cap, d, 3);
        }
        return true;
    }
    return false;
}

/* MOOS-IvP 24.8's BHV_Waypoint objective (buildOF, ipf_type zaic): speed, a ZAIC peak at the
 * cruise speed (peak width half of it, base width 1.6, summit delta 20, utilities 0..100);
 * course, a wrapping ZAIC of two components summed: the bearing to the track point (peak width
 * 0, base width 180, 0..100) and ownship's heading (peak width 30, base width 180, summit
 * delta 5, 0..20), which damps a change of course; coupled course_pct : 100 - course_pct. */
KELP_NOINLINE static int wpt_function(kelp_bhv *b, const kelp_helm_work *w, double crs, double osh, double speed,
                                      double course_pct, kelp_ivp_func *out)
{
    size_t ns;
    int rc = bhv_cs_speed_points(b, w, &ns);
    if (rc < 0)
        return rc;
    kelp_ivp_zaic_peak *z = &b->helm->ws_bhv.zaic;
    kelp_ivp_func *spd = &b->helm->ws_bhv.cs[0], *cf = &b->helm->ws_bhv.cs[1];
    rc = kelp_ivp_zaic_peak_init(z, &b->dom, "speed");
    if (rc >= 0) rc = kelp_ivp_zaic_peak_set_params(z, speed, speed / 2, 1.6, 20, 0, 100, 0);
    if (rc >= 0) rc = kelp_ivp_zaic_peak_extract(z, true, w->dwork, w->dwork_cap, w->tmp, ns, spd);
    if (rc < 0) return rc;
    rc = kelp_ivp_zaic_peak_init(z, &b->dom, "course");
    z->wrap = true;
    if (rc >= 0) rc = kelp_ivp_zaic_peak_set_params(z, crs, 0, 180, 50, 0, 100, 0);
    if (rc >= 0) rc = kelp_ivp_zaic_peak_add_component(z);
    if (rc >= 0) rc = kelp_ivp_zaic_peak_set_params(z, osh, 30, 180, 5, 0, 20, 1);
    if (rc >= 0) rc = kelp_ivp_zaic_peak_extract(z, false, w->dwork, w->dwork_cap, w->tmp + ns, w->tmp_cap - ns, cf);
    if (rc < 0) return rc;
    return kelp_ivp_couple(cf, course_pct, spd, 100 - course_pct, true, 0, 100, w->out, w->out_cap, out);
}

/* the reports of a running iteration (status, route, markers, distances) and the course to
 * steer, toward the track point (with lead) or the point itself. Called from wpt_run, not
 * under wpt_advance's frame. */
KELP_NOINLINE static double wpt_report(kelp_bhv *b, bool lead_ok)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    kelp_bhv_pt cur = point(s, s->index);
    double dist = hypot(cur.x - s->osx, cur.y - s->osy);
    kelp_bhv_pt tp = lead_ok ? track_point(s, cur) : cur;
    post_stat(b, dist);
    post_seglist(b, true);
    post_marker(b, false, &cur);
    post_marker(b, true, hypot(cur.x - tp.x, cur.y - tp.y) > 5 ? &tp : NULL);
    if (s->var_dist_prev[0])
        kelp_helm_bhv_post_double(b, s->var_dist_prev, hypot(s->prev.x - s->osx, s->prev.y - s->osy), NULL);
    if (s->var_dist_next[0])
        kelp_helm_bhv_post_double(b, s->var_dist_next, dist, NULL);
    return kelp_helm_relang(s->osx, s->osy, tp.x, tp.y);
}

/* lead_condition: all must hold for lead steering (24.8's checkLeadConditions, each run);
 * evaluated here, not under wpt_advance's frame */
KELP_NOINLINE static bool wpt_lead_ok(const kelp_bhv *b)
{
    const kelp_bhv_wpt *s = &b->u.wpt;
    for (unsigned i = 0; i < s->nlead_cond; i++)
        if (kelp_helm_cond_eval(s->lead_cond[i], &b->helm->ib) != 1)
            return false;
    return true;
}

static int wpt_run(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    const kelp_bhv_wpt *s = &b->u.wpt;
    unsigned ev = 0;
    bool lead_ok = wpt_lead_ok(b);
    bool go = wpt_advance(b, &ev);
    /* what 24.8 posts inside its setNextWaypoint and onRunState, made here (same iteration):
     * the wptflags with the state they name; then the previous index as $(PI) reads it next
     * time (unless eager_prev_index_flag set it as the flags went); the completion's endflags */
    if (ev & WPT_EV_CYCLED)
        post_pairs(b, s->cycleflag, s->ncycleflag, true);
    if (ev & WPT_EV_FLAGS)
        post_pairs(b, s->wptflag, s->nwptflag, false);
    if (go && !s->eager_prev)
        b->u.wpt.prev_index = (int)s->index;
    if (ev & WPT_EV_DONE)
        kelp_helm_bhv_set_complete(b);
    if (!go)
        return 0;
    double crs = wpt_report(b, lead_ok);
    double speed = s->use_alt_speed && s->speed_alt >= 0 ? s->speed_alt : s->speed;
    if (s->slow_dist > 0) { /* end_spd: over the distance still to go to the list's end (24.8's buildOF) */
        double togo = dist_to_go(s, true); /* -1 with endless repeats: stopped, as 24.8 */
        if (togo <= s->stop_dist)
            speed = 0;
        else if (togo < s->slow_dist)
            speed *= s->slow_dist > s->stop_dist ? (togo - s->stop_dist) / (s->slow_dist - s->stop_dist) : 0;
    }
    if (wpt_function(b, w, crs, s->osh, speed, s->course_pct, out) < 0) {
        kelp_helm_bhv_post_warning(b, "Problem Creating the IvP Function");
        return 0;
    }
    return 1;
}

/* after configuration and each applied update (MOOS-IvP 24.8's onSetParamComplete): the
 * single-point warning, the no-points warning's retraction (a behaviour here always has
 * points), then BHV_SETTINGS as 24.8's postConfigStatus writes it (post_suffix twice, with
 * its '_'; lead -1 when off; crs_spd_zaic_ratio as the course percentage) */
static void wpt_post_config(kelp_bhv *b)
{
    const kelp_bhv_wpt *s = &b->u.wpt;
    if (s->npts == 1 && s->repeat > 0)
        kelp_helm_bhv_post_warning(b, "cycles/repeats not supported with single waypt");
    if (s->npts)
        kelp_helm_bhv_post_retract(b, "No waypts given. Set val to empty if intentional");
    else if (!s->init)
        kelp_helm_bhv_post_warning(b, "No waypts given. Set val to empty if intentional");
    /* the text and its numbers are composed in the helm's behaviour workspace */
    char *buf = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num;
    char *sp = nb[0], *sa = nb[1], *ld = nb[2], *dm = nb[3], *cr = nb[4], *sr = nb[5], *rt = nb[6], *ix = nb[7],
         *rp = nb[8], *x = nb[9], *y = nb[10];
    const size_t cap = sizeof b->helm->ws_bhv.post, ncap = sizeof nb[0];
    size_t n = hx_cat(buf, cap, "type=BHV_Waypoint,name=", b->name, ",points=", HX_END);
    for (unsigned i = 0; i < s->npts; i++) {
        hx_fmt_x(x, ncap, s->pts[i].x, 2);
        hx_fmt_x(y, ncap, s->pts[i].y, 2);
        n += hx_cat(buf + n, cap - n, i ? ":" : "pts={", x, ",", y, i + 1 == s->npts ? "}" : "", HX_END);
    }
    struct { char *dst; double v; unsigned dec; } num[] = {
        {sp, s->speed, 1},       {sa, s->speed_alt, 1},      {ld, s->lead, 1},
        {dm, s->lead_damper, 1}, {cr, s->capture_radius, 1}, {sr, s->slip_radius, 1},
        {rt, s->course_pct, 2}};
    for (size_t i = 0; i < sizeof num / sizeof num[0]; i++)
        hx_fmt_x(num[i].dst, 32, num[i].v, num[i].dec);
    hx_fmt_ulong(ix, ncap, s->index);
    hx_fmt_ulong(rp, ncap, s->repeat < 0 ? 0 : (unsigned long)s->repeat);
    n += hx_cat(buf + n, cap - n, ",speed=", sp, ",speed_alt=", sa, ",currix=", ix,
                ",greedy_tour=", s->greedy_pending ? "true" : "false", ",use_alt_speed=", s->use_alt_speed ? "true" : "false", ",wpt_status=", s->var_report,
                ",wpt_dist_to_prev=", s->var_dist_prev, ",wpt_dist_to_next=", s->var_dist_next, ",wpt_index=",
                s->var_index, ",cycle_index_var=", s->var_cyindex, ",post_suffix=", s->suffix, ",post_suffix=", s->suffix,
                ",ipf_type=zaic,lead=", ld, ",lead_damper=", dm, ",lead_to_start=", s->lead_to_start ? "true" : "false",
                ",order=", s->reverse ? "reverse" : "normal", ",repeats=", s->repeat < 0 ? "forever" : rp,
                ",efficiency_measure=", s->efficiency ? "all" : "off", ",capture_radius=", cr, ",slip_radius=", sr,
                HX_END);
    if (s->capture_line)
        n += hx_cat(buf + n, cap - n, ",capture_line=",
                    s->capture_radius == 0 && s->slip_radius == 0 ? "absolute" : "true", HX_END);
    hx_cat(buf + n, cap - n, ",crs_spd_zaic_ratio=", rt, HX_END);
    kelp_helm_bhv_post_string(b, "BHV_SETTINGS", buf, "repeatable");
}

const kelp_bhv_ops kelp_bhv_waypoint_ops = {
    .type = "BHV_Waypoint",
    .init = wpt_init,
    .set_param = wpt_set_param,
    .params_done = wpt_params_done,
    .on_idle = wpt_idle,
    .on_complete = wpt_complete,
    .on_run = wpt_run,
    .post_config = wpt_post_config,
};
