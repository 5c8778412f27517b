/* kelp helm: BHV_Loiter, a polygon loiter: the vehicle visits the polygon's vertices in turn
 * (clockwise, counter-clockwise or in the given order), in "acquiring" mode while it is
 * outside the polygon by more than acquire_dist and in "loitering" mode otherwise. Posts
 * LOITER_INDEX, LOITER_ACQUIRE (1/0), LOITER_REPORT (each + post_suffix) and VIEW_POLYGON
 * drawn with its visual_hints. center_activate re-centres the polygon on the vehicle each
 * time the behaviour becomes active. */
#include <math.h>
#include <string.h>
#include "helm_int.h"

static void loiter_init(kelp_bhv *b)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    (void)hx_copy(b->name, sizeof b->name, "loiter", 6);
    bhv_use_subdomain(b, "course,speed");
    s->speed = 0;
    s->capture_radius = 3;
    s->slip_radius = 15;
    s->acquire_dist = 10;
    s->clockwise = 1;
    s->min_dist = INFINITY;
    bhv_hints_default(&s->hints);
    hx_ignore(kelp_helm_bhv_add_info_vars(b, "NAV_X, NAV_Y")); /* a constructor cannot fail: a full list only skips the registration */
}

static double signed_area(const kelp_bhv_pt *p, unsigned n)
{
    double a = 0;
    for (unsigned i = 0; i < n; i++) {
        const kelp_bhv_pt *q = &p[(i + 1) % n];
        a += p[i].x * q->y - q->x * p[i].y;
    }
    return a / 2; /* > 0: counter-clockwise (x east, y north) */
}

static void order(kelp_bhv_loiter *s)
{
    memcpy(s->pts, s->given, sizeof s->pts);
    s->npts = s->ngiven;
    double a = signed_area(s->given, s->ngiven);
    bool reverse = (s->clockwise == 1 && a > 0) || (s->clockwise == 0 && a < 0);
    if (reverse)
        for (unsigned i = 0; i < s->npts; i++)
            s->pts[i] = s->given[s->ngiven - 1 - i];
    s->started = false;
}

static int loiter_set_param(kelp_bhv *b, const char *p, const char *v)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    double d;
    bool num = hx_number(v, strlen(v), &d);
    if (!strcmp(p, "polygon") || !strcmp(p, "points")) {
        kelp_bhv_pt *pts = b->helm->ws_bhv.pts;  /* parsed aside: a bad polygon changes nothing */
        unsigned n;
        if (kelp_helm_parse_points(v, pts, KELP_HELM_MAX_PTS, &n) != 0 || n < 3)
            return KELP_ERR_PARSE;
        memcpy(s->given, pts, sizeof s->given);
        s->ngiven = n;
        order(s);
        return 0;
    }
    if (!strcmp(p, "clockwise")) {
        if (hx_ieq(v, "true"))
            s->clockwise = 1;
        else if (hx_ieq(v, "false"))
            s->clockwise = 0;
        else if (hx_ieq(v, "best"))
            s->clockwise = -1;
        else
            return KELP_ERR_PARSE;
        if (s->ngiven)
            order(s);
        return 0;
    }
    if (!strcmp(p, "speed"))
        return num && d >= 0 ? (s->speed = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "capture_radius") || !strcmp(p, "radius"))
        return num && d >= 0 ? (s->capture_radius = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "slip_radius") || !strcmp(p, "nm_radius"))
        return num && d >= 0 ? (s->slip_radius = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "acquire_dist"))
        return num && d >= 0 ? (s->acquire_dist = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "visual_hints"))
        return bhv_set_hints(&s->hints, v);
    if (!strcmp(p, "post_suffix"))
        return bhv_set_suffix(s->suffix, sizeof s->suffix, v);
    if (!strcmp(p, "spiral_factor"))
        return num ? (s->spiral_factor = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "center_activate")) {
        if (!hx_ieq(v, "true") && !hx_ieq(v, "false"))
            return KELP_ERR_PARSE;
        s->center_activate = hx_ieq(v, "true");
        return 0;
    }
    return KELP_ERR_NOTFOUND;
}

static int loiter_params_done(kelp_bhv *b)
{
    if (b->u.loiter.npts < 3)
        return kelp_helm_bhv_fail(b, "no polygon given");
    return 0;
}

static bool inside(const kelp_bhv_pt *p, unsigned n, double x, double y)
{
    bool in = false;
    for (unsigned i = 0, j = n - 1; i < n; j = i++)
        if ((p[i].y > y) != (p[j].y > y) && x < (p[j].x - p[i].x) * (y - p[i].y) / (p[j].y - p[i].y) + p[i].x)
            in = !in;
    return in;
}

static double seg_dist(kelp_bhv_pt a, kelp_bhv_pt b, double x, double y)
{
    double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy, t = 0;
    if (l2 > 0)
        t = fmax(0, fmin(1, ((x - a.x) * dx + (y - a.y) * dy) / l2));
    return hypot(a.x + t * dx - x, a.y + t * dy - y);
}

static void post_polygon(kelp_bhv *b, bool active)
{
    const kelp_bhv_loiter *s = &b->u.loiter;
    /* composed in the helm's behaviour workspace */
    char *buf = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num;
    char *x = nb[0], *y = nb[1], *vs = nb[2], *es = nb[3];
    const size_t cap = sizeof b->helm->ws_bhv.post;
    size_t n = hx_cat(buf, cap, "pts={", HX_END);
    for (unsigned i = 0; i < s->ngiven; i++) {
        hx_fmt_double(x, sizeof nb[0], s->given[i].x);
        hx_fmt_double(y, sizeof nb[0], s->given[i].y);
        n += hx_cat(buf + n, cap - n, i ? ":" : "", x, ",", y, HX_END);
    }
    hx_fmt_double(vs, sizeof nb[0], s->hints.vertex_size);
    hx_fmt_double(es, sizeof nb[0], s->hints.edge_size);
    hx_cat(buf + n, cap - n, "},label=", b->name, ",active=", active ? "true" : "false", ",edge_color=",
           s->hints.edge_color, ",vertex_color=", s->hints.vertex_color, ",label_color=", s->hints.label_color,
           ",vertex_size=", vs, ",edge_size=", es, HX_END);
    kelp_helm_bhv_post_string(b, "VIEW_POLYGON", buf, NULL);
}

static void loiter_idle(kelp_bhv *b)
{
    b->u.loiter.started = false;
    if (b->u.loiter.npts)
        post_polygon(b, false);
}

/* onRunState up to the objective: the vertex to steer for, reports and the course to it (*crs);
 * false when no objective is made this time. Out of line: its locals are not on the stack under
 * the IvP build that follows. */
KELP_NOINLINE static bool loiter_advance(kelp_bhv *b, double *crs)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    double x, y;
    bool ok1 = kelp_helm_bhv_buf_double(b, "NAV_X", &x);
    bool ok2 = kelp_helm_bhv_buf_double(b, "NAV_Y", &y);
    if (!ok1 || !ok2) {
        kelp_helm_bhv_post_warning(b, "No ownship X/Y info in info_buffer.");
        return false;
    }
    if (s->npts < 3)
        return false;
    if (!s->started && s->center_activate && s->ngiven > 0) {
        /* the polygon moves so that its centre is where the vehicle is now */
        double cx = 0, cy = 0;
        for (unsigned i = 0; i < s->ngiven; i++)
            cx += s->given[i].x / s->ngiven, cy += s->given[i].y / s->ngiven;
        for (unsigned i = 0; i < s->ngiven; i++)
            s->given[i].x += x - cx, s->given[i].y += y - cy;
        order(s);
    }
    if (s->npts < 3)
        return false;
    if (!s->started) {
        /* start at the nearest vertex */
        double best = INFINITY;
        for (unsigned i = 0; i < s->npts; i++) {
            double d = hypot(s->pts[i].x - x, s->pts[i].y - y);
            if (d < best) {
                best = d;
                s->index = i;
            }
        }
        s->started = true;
        s->min_dist = INFINITY;
    }
    double pd = INFINITY;
    for (unsigned i = 0; i < s->npts; i++)
        pd = fmin(pd, seg_dist(s->pts[i], s->pts[(i + 1) % s->npts], x, y));
    s->acquiring = !inside(s->pts, s->npts, x, y) && pd > s->acquire_dist;
    kelp_bhv_pt cur = s->pts[s->index];
    double dist = hypot(cur.x - x, cur.y - y);
    bool hit = dist <= s->capture_radius || (s->slip_radius > 0 && dist <= s->slip_radius && dist > s->min_dist);
    s->min_dist = fmin(s->min_dist, dist);
    if (hit) {
        s->index = (s->index + 1) % s->npts;
        s->laps_pts++;
        s->min_dist = INFINITY;
        cur = s->pts[s->index];
    }
    /* the report and the variable names are composed in the helm's behaviour workspace (each
     * posting is copied by the helm, so a name's buffer is free again for the next) */
    char *rep = b->helm->ws_bhv.post2, *vn = b->helm->ws_bhv.var, *ix = b->helm->ws_bhv.num[0],
         *vr = b->helm->ws_bhv.num[1];
    const size_t ncap = sizeof b->helm->ws_bhv.num[0], vcap = sizeof b->helm->ws_bhv.var;
    hx_fmt_ulong(ix, ncap, s->index);
    hx_fmt_ulong(vr, ncap, s->laps_pts);
    hx_cat(rep, sizeof b->helm->ws_bhv.post2, "mode=", s->acquiring ? "acquiring" : "loitering", ",index=", ix,
           ",vertices_reached=", vr, HX_END);
    hx_cat(vn, vcap, "LOITER_INDEX", s->suffix, HX_END);
    kelp_helm_bhv_post_double(b, vn, (double)s->index, NULL);
    hx_cat(vn, vcap, "LOITER_ACQUIRE", s->suffix, HX_END);
    kelp_helm_bhv_post_double(b, vn, s->acquiring ? 1.0 : 0.0, NULL);
    hx_cat(vn, vcap, "LOITER_REPORT", s->suffix, HX_END);
    kelp_helm_bhv_post_string(b, vn, rep, NULL);
    post_polygon(b, true); /* (uses post and num[0..3]: the report is posted by now) */
    *crs = kelp_helm_relang(x, y, cur.x, cur.y);
    return true;
}

static int loiter_run(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    double crs;
    if (!loiter_advance(b, &crs))
        return 0;
    if (bhv_course_speed_zaic(b, w, crs, b->u.loiter.speed, 0.5, 1.0, 0.8, out) < 0) {
        kelp_helm_bhv_post_warning(b, "Problem Creating the IvP Function");
        return 0;
    }
    return 1;
}

/* BHV_SETTINGS after configuration and each applied update (MOOS-IvP's postConfigStatus) */
static void loiter_post_config(kelp_bhv *b)
{
    const kelp_bhv_loiter *s = &b->u.loiter;
    double x0 = s->given[0].x, x1 = x0, y0 = s->given[0].y, y1 = y0;
    for (unsigned i = 1; i < s->ngiven; i++) {
        x0 = fmin(x0, s->given[i].x), x1 = fmax(x1, s->given[i].x);
        y0 = fmin(y0, s->given[i].y), y1 = fmax(y1, s->given[i].y);
    }
    /* composed in the helm's behaviour workspace */
    char *buf = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num;
    char *cx = nb[0], *cy = nb[1], *sp = nb[2], *x = nb[3], *y = nb[4];
    const size_t cap = sizeof b->helm->ws_bhv.post;
    hx_fmt_fixed(cx, sizeof nb[0], (x0 + x1) / 2, 2);
    hx_fmt_fixed(cy, sizeof nb[0], (y0 + y1) / 2, 2);
    hx_fmt_fixed(sp, sizeof nb[0], s->speed, 1);
    size_t n = hx_cat(buf, cap, "type=BHV_Loiter,name=", b->name, ",x=", cx, ",y=", cy, ",clockwise=",
                      s->clockwise == 1 ? "true" : "false", ",dynamic_clockwise=", s->clockwise < 0 ? "true" : "false",
                      ",center_activate=", s->center_activate ? "true" : "false", ",desired_speed=", sp,
                      ",polygon=\"pts={", HX_END);
    for (unsigned i = 0; i < s->ngiven; i++) {
        hx_fmt_x(x, sizeof nb[0], s->given[i].x, 2);
        hx_fmt_x(y, sizeof nb[0], s->given[i].y, 2);
        n += hx_cat(buf + n, cap - n, i ? ":" : "", x, ",", y, HX_END);
    }
    hx_cat(buf + n, cap - n, "}\"", HX_END);
    kelp_helm_bhv_post_string(b, "BHV_SETTINGS", buf, "repeatable");
}

const kelp_bhv_ops kelp_bhv_loiter_ops = {
    .type = "BHV_Loiter",
    .init = loiter_init,
    .set_param = loiter_set_param,
    .params_done = loiter_params_done,
    .on_idle = loiter_idle,
    .on_run = loiter_run,
    .post_config = loiter_post_config,
};
