/* kelp helm: BHV_Waypoint, the multi-point waypoint behaviour MOOS-IvP users expect:
 * points (or polygon), order, repeat, capture_radius, slip_radius, lead (trackline
 * following), speed; posts WPT_STAT, WPT_INDEX, CYCLE_INDEX, VIEW_POINT, VIEW_SEGLIST, and
 * wptflag / cycleflag / endflag. The course x speed function is the SimpleWaypoint ZAIC one. */
#include <math.h>
#include <string.h>
#include "helm_int.h"

static void wpt_reset(kelp_bhv_wpt *s)
{
    s->index = 0;
    s->cycles = 0;
    s->captured = s->slipped = 0;
    s->have_prev = false;
    s->min_dist = INFINITY;
}

static void wpt_init(kelp_bhv *b)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    (void)hx_copy(b->name, sizeof b->name, "waypoint", 8);
    bhv_use_subdomain(b, "course,speed");
    s->speed = 0;
    s->capture_radius = 3;
    s->slip_radius = 15;
    s->lead = 0;
    s->repeat = 0;
    wpt_reset(s);
    (void)kelp_bhv_add_info_vars(b, "NAV_X, NAV_Y");
}

static int add_flag(kelp_bhv_flag *arr, unsigned *n, unsigned cap, const char *v)
{
    if (*n >= cap || !hx_pair(v, &arr[*n].p))
        return KELP_ERR_PARSE;
    arr[*n].kind = KELP_FLAG_RUN;
    (*n)++;
    return 0;
}

static int wpt_set_param(kelp_bhv *b, const char *p, const char *v)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    double d;
    bool num = hx_number(v, strlen(v), &d);
    if (!strcmp(p, "points") || !strcmp(p, "polygon") || !strcmp(p, "point")) {
        kelp_bhv_pt pts[KELP_HELM_MAX_PTS];
        unsigned n;
        if (kelp_helm_parse_points(v, pts, KELP_HELM_MAX_PTS, &n) != 0)
            return KELP_ERR_PARSE;
        memcpy(s->pts, pts, sizeof pts);
        s->npts = n;
        wpt_reset(s);
        return 0;
    }
    if (!strcmp(p, "speed"))
        return num && d >= 0 ? (s->speed = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "capture_radius") || !strcmp(p, "radius"))
        return num && d >= 0 ? (s->capture_radius = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "slip_radius") || !strcmp(p, "nm_radius"))
        return num && d >= 0 ? (s->slip_radius = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "lead"))
        return num && d >= 0 ? (s->lead = d, 0) : KELP_ERR_PARSE;
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
        else if (hx_ieq(v, "reverse"))
            s->reverse = true;
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
    if (b->u.wpt.npts == 0)
        return kelp_bhv_fail(b, "no points given");
    return 0;
}

static kelp_bhv_pt point(const kelp_bhv_wpt *s, unsigned i)
{
    return s->pts[s->reverse ? s->npts - 1 - i : i];
}

static void post_seglist(kelp_bhv *b, bool active)
{
    const kelp_bhv_wpt *s = &b->u.wpt;
    char buf[KELP_HELM_MAX_SVAL];
    size_t n = hx_cat(buf, sizeof buf, "pts={", HX_END);
    for (unsigned i = 0; i < s->npts; i++) {
        char x[32], y[32];
        kelp_bhv_pt p = point(s, i);
        hx_fmt_double(x, sizeof x, p.x);
        hx_fmt_double(y, sizeof y, p.y);
        n += hx_cat(buf + n, sizeof buf - n, i ? ":" : "", x, ",", y, HX_END);
    }
    hx_cat(buf + n, sizeof buf - n, "},label=", b->name, ",active=", active ? "true" : "false", HX_END);
    kelp_bhv_post_string(b, "VIEW_SEGLIST", buf, NULL);
}

static void post_point(kelp_bhv *b, kelp_bhv_pt p, bool active)
{
    char x[32], y[32], spec[KELP_MAX_NAME * 2 + 128];
    hx_fmt_double(x, sizeof x, p.x);
    hx_fmt_double(y, sizeof y, p.y);
    hx_cat(spec, sizeof spec, "label=", b->us[0] ? b->us : "vehicle", "'s next waypoint,type=waypoint,source=", b->name,
           ",x=", x, ",y=", y, ",active=", active ? "true" : "false", HX_END);
    kelp_bhv_post_string(b, "VIEW_POINT", spec, NULL);
}

static void wpt_idle(kelp_bhv *b)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    s->restart = true;
    if (s->npts) {
        post_seglist(b, false);
        post_point(b, point(s, s->index < s->npts ? s->index : 0), false);
    }
}

static void post_stat(kelp_bhv *b, double dist)
{
    const kelp_bhv_wpt *s = &b->u.wpt;
    char buf[KELP_MAX_NAME * 2 + 160];
    double eta = s->speed > 0 ? dist / s->speed : -1;
    char ix[24], hc[24], ht[24], cy[24], ds[32], et[32];
    hx_fmt_ulong(ix, sizeof ix, s->index);
    hx_fmt_ulong(hc, sizeof hc, s->captured);
    hx_fmt_ulong(ht, sizeof ht, s->captured + s->slipped);
    hx_fmt_ulong(cy, sizeof cy, s->cycles);
    hx_fmt_fixed(ds, sizeof ds, dist, 0);
    hx_fmt_fixed(et, sizeof et, eta, 0);
    hx_cat(buf, sizeof buf, "vname=", b->us[0] ? b->us : "vehicle", ",behavior-name=", b->name, ",index=", ix, ",hits=", hc,
           "/", ht, ",cycles=", cy, ",dist=", ds, ",eta=", et, HX_END);
    kelp_bhv_post_string(b, "WPT_STAT", buf, NULL);
    kelp_bhv_post_double(b, "WPT_INDEX", (double)s->index, NULL);
    kelp_bhv_post_double(b, "CYCLE_INDEX", (double)s->cycles, NULL);
}

static void post_pairs(kelp_bhv *b, const kelp_bhv_flag *f, unsigned n)
{
    for (unsigned i = 0; i < n; i++) {
        if (f[i].p.is_str)
            kelp_bhv_post_string(b, f[i].p.var, f[i].p.sval, "repeatable");
        else
            kelp_bhv_post_double(b, f[i].p.var, f[i].p.dval, "repeatable");
    }
}

static int wpt_run(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    kelp_bhv_wpt *s = &b->u.wpt;
    bool ok1 = kelp_bhv_buf_double(b, "NAV_X", &s->osx);
    bool ok2 = kelp_bhv_buf_double(b, "NAV_Y", &s->osy);
    if (!ok1 || !ok2) {
        kelp_bhv_post_warning(b, "No ownship X/Y info in info_buffer.");
        return 0;
    }
    if (s->npts == 0)
        return 0;
    if (!s->have_prev || s->restart || b->state == KELP_BHV_IDLE || b->state == KELP_BHV_NONE) {
        /* the first trackline starts where the vehicle is when the behaviour (re)starts */
        s->prev.x = s->osx;
        s->prev.y = s->osy;
        s->have_prev = true;
        s->restart = false;
        s->min_dist = INFINITY;
    }
    kelp_bhv_pt cur = point(s, s->index);
    double dist = hypot(cur.x - s->osx, cur.y - s->osy);
    bool captured = dist <= s->capture_radius;
    bool slipped = !captured && s->slip_radius > 0 && dist <= s->slip_radius && dist > s->min_dist;
    if (dist < s->min_dist)
        s->min_dist = dist;
    if (captured || slipped) {
        if (captured)
            s->captured++;
        else
            s->slipped++;
        post_pairs(b, s->wptflag, s->nwptflag);
        s->prev = cur;
        s->min_dist = INFINITY;
        s->index++;
        if (s->index >= s->npts) {
            s->cycles++;
            post_pairs(b, s->cycleflag, s->ncycleflag);
            if (s->repeat < 0 || s->cycles <= (unsigned long)s->repeat) {
                s->index = 0;
            } else {
                s->index = s->npts - 1;
                post_stat(b, 0);
                post_point(b, cur, false);
                post_seglist(b, false);
                kelp_bhv_set_complete(b);
                return 0;
            }
        }
        cur = point(s, s->index);
        dist = hypot(cur.x - s->osx, cur.y - s->osy);
    }
    /* track point: lead metres ahead of the projection on the current leg, capped at cur */
    kelp_bhv_pt tp = cur;
    if (s->lead > 0) {
        double lx = cur.x - s->prev.x, ly = cur.y - s->prev.y, l2 = lx * lx + ly * ly;
        if (l2 > 0) {
            double t = ((s->osx - s->prev.x) * lx + (s->osy - s->prev.y) * ly) / l2;
            double len = sqrt(l2);
            t += s->lead / len;
            if (t < 1) {
                if (t < 0)
                    t = 0;
                tp.x = s->prev.x + t * lx;
                tp.y = s->prev.y + t * ly;
            }
        }
    }
    post_stat(b, dist);
    post_point(b, cur, true);
    post_seglist(b, true);
    double crs = kelp_helm_relang(s->osx, s->osy, tp.x, tp.y);
    if (bhv_course_speed_zaic(b, w, crs, s->speed, 0.5, 1.0, 0.8, out) < 0) {
        kelp_bhv_post_warning(b, "Problem Creating the IvP Function");
        return 0;
    }
    return 1;
}

const kelp_bhv_ops kelp_bhv_waypoint_ops = {
    .type = "BHV_Waypoint",
    .init = wpt_init,
    .set_param = wpt_set_param,
    .params_done = wpt_params_done,
    .on_idle = wpt_idle,
    .on_run = wpt_run,
};
