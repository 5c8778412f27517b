/* kelp helm: BHV_Loiter as MOOS-IvP 24.8 runs it. The polygon (convex, snapped to 0.1 m, put in
 * clockwise or counter-clockwise order) is visited vertex by vertex with the waypoint engine's
 * rules (a capture within capture_radius; a "nonmono" hit when the distance grows again after
 * coming within slip_radius). While the vehicle is more than acquire_dist outside the polygon it
 * is in acquire mode and the vertex is chosen again each iteration: from outside, the viewable
 * vertex whose next edge turns most in the loiter's direction; from inside, the vertex that
 * makes the smallest turn onto the next edge, the one ahead of the vehicle favoured by
 * spiral_factor. The function is a course peak at the vertex (base width 180, wrapping) coupled
 * with a narrow speed peak, the course weighted by patience.
 *
 * Posts, with post_suffix: LOITER_REPORT, LOITER_INDEX, LOITER_MODE, LOITER_ACQUIRE,
 * LOITER_DIST_TO_POLY, LOITER_ETA_TO_POLY (each run iteration and each idle one); without it:
 * LOITER_DIST_TO_VERT, LOITER_BNG_TOTAL / _DELTA (slingshot), LOITER_COMPLETE, VIEW_POLYGON and
 * VIEW_POINT; BHV_SETTINGS at start, after an update and on each idle to running transition. */
#include <limits.h>
#include <math.h>
#include <string.h>
#include <kelp/kv.h>
#include "helm_int.h"

#define SNAP_M 0.1          /* the polygon's vertices are snapped to 0.1 m */
#define MOD_RAD_MIN 5.0     /* mod_poly_rad never shrinks the polygon's radius below 5 m */
#define SPEED_BASE 0.3      /* the speed peak's base width (peak width and summit delta 0) */
#define SPIRAL_DEFAULT (-2.0) /* the loiter engine's spiral factor before spiral_factor is set */
#define INT_POST_ABOVE 10.0 /* a distance or ETA above this is posted rounded to an integer */
#define ZSPD_LOW 0.1        /* ipf_type = zaic_spd: the low speed (m/s) and its utility, */
#define ZSPD_LOW_UTIL 85.0
#define ZSPD_ABOVE 0.4      /* ... the high speed above the desired one and its utility */
#define ZSPD_ABOVE_UTIL 20.0

enum { MODE_IDLE, MODE_STABLE, MODE_ACQ_EXT, MODE_REC_EXT, MODE_ACQ_INT, MODE_REC_INT };
static const char *const mode_name[] = {"idle", "stable", "acquiring_external", "recovering_external",
                                        "acquiring_internal", "recovering_internal"};

static void loiter_init(kelp_bhv *b)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    (void)hx_copy(b->name, sizeof b->name, "loiter", 6);
    bhv_use_subdomain(b, "course,speed");
    s->speed = 0;
    s->speed_alt = -1;
    s->capture_radius = 3;
    s->slip_radius = 15;
    s->acquire_dist = 10;
    s->patience = 50;
    s->slingshot = -1;
    s->spiral_factor = SPIRAL_DEFAULT;
    s->clockwise = true;
    s->acquire = true;
    s->mode = MODE_IDLE;
    s->cpa = -1;
    s->bng_last = -1;
    bhv_hints_default(&s->hints);
    s->hints.vertex_size = 1; /* the loiter's own defaults: vertices and edges 1, no label colour */
    s->hints.edge_size = 1;
    s->hints.label_color[0] = '\0';
    hx_ignore(kelp_helm_bhv_add_info_vars(b, "NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED")); /* a constructor cannot fail: a full list only skips the registration */
}

/* ---------------------------------------------------------------- polygon geometry */

static double angle360(double a)
{
    while (a >= 360.0)
        a -= 360.0;
    while (a < 0.0)
        a += 360.0;
    return a;
}

/* the signed turn from leg p1->p2 to leg p2->p3, in (-180, 180]; 0 when a leg has no length */
static double turn_angle(double x1, double y1, double x2, double y2, double x3, double y3)
{
    if ((x1 == x2 && y1 == y2) || (x2 == x3 && y2 == y3))
        return 0;
    double a1 = kelp_helm_relang(x1, y1, x2, y2), a2 = kelp_helm_relang(x2, y2, x3, y3);
    if (a1 > 180)
        a1 -= 360;
    if (a2 > 180)
        a2 -= 360;
    double r = a2 - a1;
    if (r > 180)
        r -= 360;
    if (r <= -180)
        r += 360;
    return r;
}

/* which side of the line through a and b the point p is on: 0 below, 1 above, 2 on it (a
 * vertical line: 0 right of it, 1 left; a and b equal: on it) */
static int line_side(kelp_bhv_pt a, kelp_bhv_pt b, double px, double py)
{
    if (a.x == b.x) {
        if (a.y == b.y || px == a.x)
            return 2;
        return px > a.x ? 0 : 1;
    }
    double m = (b.y - a.y) / (b.x - a.x), c = b.y - m * b.x, ly = m * px + c;
    return ly > py ? 0 : (ly < py ? 1 : 2);
}

/* each edge's side (the side all the other vertices lie on, -1 when they do not) into side;
 * true when convex: three or more vertices and every edge with its other vertices on one side
 * (vertices on the edge's line do not count) */
static bool poly_sides(const kelp_bhv_pt *pts, unsigned n, signed char *side)
{
    bool convex = n >= 3;
    for (unsigned i = 0; i < n; i++) {
        kelp_bhv_pt a = pts[i], b = pts[(i + 1) % n];
        int sd = -1;
        bool fresh = true;
        for (unsigned j = 0; j < n && n > 2; j++) {
            if (j == i || j == (i + 1) % n)
                continue;
            int k = line_side(a, b, pts[j].x, pts[j].y);
            if (k == 2)
                continue;
            if (fresh)
                sd = k, fresh = false;
            else if (k != sd)
                sd = -1;
        }
        side[i] = (signed char)sd;
        convex = convex && sd != -1;
    }
    return convex;
}

static void sides(kelp_bhv_loiter *s)
{
    s->convex = poly_sides(s->pts, s->npts, s->side);
}

/* inside or on the polygon (never, when it is not convex) */
static bool poly_contains(const kelp_bhv_loiter *s, double x, double y)
{
    if (!s->convex)
        return false;
    for (unsigned i = 0; i < s->npts; i++) {
        if (x == s->pts[i].x && y == s->pts[i].y)
            return true;
        int k = line_side(s->pts[i], s->pts[(i + 1) % s->npts], x, y);
        if (k != 2 && k != s->side[i])
            return false;
    }
    return true;
}

static double seg_dist(kelp_bhv_pt a, kelp_bhv_pt b, double x, double y)
{
    double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy, t = 0;
    if (l2 > 0)
        t = fmax(0, fmin(1, ((x - a.x) * dx + (y - a.y) * dy) / l2));
    return hypot(a.x + t * dx - x, a.y + t * dy - y);
}

static double poly_dist(const kelp_bhv_loiter *s, double x, double y)
{
    double d = INFINITY;
    for (unsigned i = 0; i < s->npts; i++)
        d = fmin(d, seg_dist(s->pts[i], s->pts[(i + 1) % s->npts], x, y));
    return d;
}

/* the polygon's centre: the middle of its bounding box */
static kelp_bhv_pt poly_center(const kelp_bhv_loiter *s)
{
    if (s->npts == 0)
        return (kelp_bhv_pt){0, 0};
    double x0 = s->pts[0].x, x1 = x0, y0 = s->pts[0].y, y1 = y0;
    for (unsigned i = 1; i < s->npts; i++) {
        x0 = fmin(x0, s->pts[i].x), x1 = fmax(x1, s->pts[i].x);
        y0 = fmin(y0, s->pts[i].y), y1 = fmax(y1, s->pts[i].y);
    }
    return (kelp_bhv_pt){(x0 + x1) / 2, (y0 + y1) / 2};
}

/* clockwise order: the bearing from the centre grows from vertex to vertex more often than not */
static bool poly_is_clockwise(const kelp_bhv_loiter *s)
{
    if (s->npts < 3)
        return false;
    kelp_bhv_pt c = poly_center(s);
    unsigned inc = 0, dec = 0;
    for (unsigned i = 0; i < s->npts; i++) {
        const kelp_bhv_pt *p = &s->pts[i], *q = &s->pts[(i + 1) % s->npts];
        if (kelp_helm_relang(c.x, c.y, q->x, q->y) > kelp_helm_relang(c.x, c.y, p->x, p->y))
            inc++;
        else
            dec++;
    }
    return inc > dec;
}

static void poly_reverse(kelp_bhv_loiter *s)
{
    for (unsigned i = 0, j = s->npts ? s->npts - 1 : 0; i < j; i++, j--) {
        kelp_bhv_pt t = s->pts[i];
        s->pts[i] = s->pts[j];
        s->pts[j] = t;
    }
    sides(s);
}

/* the loiter engine's setClockwise: the order is reversed when it is not the one asked for */
static void set_clockwise(kelp_bhv_loiter *s, bool cw)
{
    s->clockwise = cw;
    if (poly_is_clockwise(s) != cw)
        poly_reverse(s);
}

/* the waypoint engine takes the polygon: from its first vertex, no closest approach yet */
static void restart_list(kelp_bhv_loiter *s)
{
    s->index = 0;
    s->cpa = -1;
}

static void set_index(kelp_bhv_loiter *s, int ix)
{
    if (ix < 0 || (unsigned)ix >= s->npts)
        return;
    s->index = (unsigned)ix;
    s->cpa = -1;
}

static void move_center(kelp_bhv_loiter *s, double x, double y)
{
    kelp_bhv_pt c = poly_center(s);
    for (unsigned i = 0; i < s->npts; i++)
        s->pts[i].x += x - c.x, s->pts[i].y += y - c.y;
    sides(s);
}

/* do segments a-b and c-d meet (touching counts; a shared end point always does)? */
static double orient(kelp_bhv_pt a, kelp_bhv_pt b, kelp_bhv_pt c)
{
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

static bool on_box(kelp_bhv_pt a, kelp_bhv_pt b, kelp_bhv_pt p)
{
    return p.x >= fmin(a.x, b.x) && p.x <= fmax(a.x, b.x) && p.y >= fmin(a.y, b.y) && p.y <= fmax(a.y, b.y);
}

static bool segs_meet(kelp_bhv_pt a, kelp_bhv_pt b, kelp_bhv_pt c, kelp_bhv_pt d)
{
    if ((a.x == c.x && a.y == c.y) || (a.x == d.x && a.y == d.y) || (b.x == c.x && b.y == c.y) ||
        (b.x == d.x && b.y == d.y))
        return true;
    double d1 = orient(c, d, a), d2 = orient(c, d, b), d3 = orient(a, b, c), d4 = orient(a, b, d);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
        return true;
    return (d1 == 0 && on_box(c, d, a)) || (d2 == 0 && on_box(c, d, b)) || (d3 == 0 && on_box(a, b, c)) ||
           (d4 == 0 && on_box(a, b, d));
}

/* vertex i seen from outside: the line of sight crosses no edge but the two at the vertex */
static bool vertex_viewable(const kelp_bhv_loiter *s, unsigned i, double x, double y)
{
    kelp_bhv_pt o = {x, y}, v = s->pts[i];
    if (x == v.x && y == v.y)
        return true;
    if (poly_contains(s, x, y))
        return false;
    unsigned count = 0;
    for (unsigned k = 0; k < s->npts && count <= 2; k++)
        if (segs_meet(o, v, s->pts[k], s->pts[(k + 1) % s->npts]))
            count++;
    return count <= 2;
}

/* from outside: of the viewable vertices, the one whose next edge turns most to the right
 * (clockwise) or to the left (counter-clockwise) seen from the vehicle; the first on a tie */
static unsigned acquire_out(const kelp_bhv_loiter *s, double x, double y, bool cw)
{
    if (!s->convex || poly_contains(s, x, y))
        return 0;
    unsigned best = 0;
    bool fresh = true;
    double best_ang = 0;
    for (unsigned i = 0; i < s->npts; i++) {
        if (!vertex_viewable(s, i, x, y))
            continue;
        const kelp_bhv_pt *p = &s->pts[i], *q = &s->pts[(i + 1) % s->npts];
        double a = turn_angle(x, y, p->x, p->y, q->x, q->y);
        if (fresh || (cw ? a > best_ang : a < best_ang)) {
            fresh = false;
            best = i;
            best_ang = a;
        }
    }
    return best;
}

/* from inside: the vertex with the smallest turn onto its next edge; the vertex nearest the
 * heading (by the plain difference of bearings) gets spiral_factor added to its turn */
static unsigned acquire_in(const kelp_bhv_loiter *s, double hdg, double x, double y)
{
    hdg = angle360(hdg);
    double smallest = 360;
    unsigned ahead = 0;
    for (unsigned i = 0; i < s->npts; i++) {
        double d = fabs(hdg - kelp_helm_relang(x, y, s->pts[i].x, s->pts[i].y));
        if (d < smallest) {
            smallest = d;
            ahead = i;
        }
    }
    unsigned low = 0;
    double low_ang = 0;
    for (unsigned i = 0; i < s->npts; i++) {
        const kelp_bhv_pt *p = &s->pts[i], *q = &s->pts[(i + 1) % s->npts];
        double a = fabs(turn_angle(x, y, p->x, p->y, q->x, q->y)) + (i == ahead ? s->spiral_factor : 0);
        if (i == 0 || a < low_ang) {
            low = i;
            low_ang = a;
        }
    }
    return low;
}

/* the loiter engine's acquireVertex: -1 when the polygon is not convex */
static int acquire_vertex(const kelp_bhv_loiter *s, double hdg, double x, double y)
{
    if (!s->convex)
        return -1;
    if (poly_contains(s, x, y))
        return (int)acquire_in(s, hdg, x, y);
    return (int)acquire_out(s, x, y, s->clockwise);
}

/* clockwise = best: the direction whose entry vertex needs the smaller turn from the heading
 * (outside the polygon only); the polygon is re-ordered and the waypoint engine restarts */
static void reset_clockwise_best(kelp_bhv_loiter *s)
{
    if (s->convex && !poly_contains(s, s->osx, s->osy)) {
        unsigned vc = acquire_out(s, s->osx, s->osy, true), vcc = acquire_out(s, s->osx, s->osy, false);
        double hc = kelp_helm_relang(s->osx, s->osy, s->pts[vc].x, s->pts[vc].y);
        double hcc = kelp_helm_relang(s->osx, s->osy, s->pts[vcc].x, s->pts[vcc].y);
        double dc = angle360(s->osh - hc), dcc = angle360(s->osh - hcc);
        dc = fabs(dc > 180 ? dc - 360 : dc);
        dcc = fabs(dcc > 180 ? dcc - 360 : dcc);
        set_clockwise(s, dc < dcc);
    }
    restart_list(s);
}

/* the waypoint engine's next waypoint (perpetual, repeating without end): true when a vertex
 * was reached (advanced or cycled) */
static bool next_waypoint(kelp_bhv_loiter *s, double x, double y)
{
    if (s->npts == 0)
        return false;
    kelp_bhv_pt p = s->pts[s->index];
    double dist = hypot(x - p.x, y - p.y);
    if (s->cpa < 0 || dist < s->cpa)
        s->cpa = dist;
    if (dist < s->capture_radius)
        s->capture_hits++;
    else if (s->slip_radius > s->capture_radius && dist > s->cpa && s->cpa <= s->slip_radius)
        s->nonmono_hits++;
    else
        return false;
    if (++s->index >= s->npts) {
        s->index = 0;
        s->cpa = -1;
    } else {
        p = s->pts[s->index];
        s->cpa = hypot(x - p.x, y - p.y);
    }
    return true;
}

/* ---------------------------------------------------------------- parameters */

/* MOOS-IvP's setBooleanOnString: true/on/yes, false/off/no, toggle (any case) */
static bool parse_bool(const char *v, bool *out)
{
    if (hx_ieq(v, "toggle"))
        *out = !*out;
    else if (hx_ieq(v, "true") || hx_ieq(v, "on") || hx_ieq(v, "yes"))
        *out = true;
    else if (hx_ieq(v, "false") || hx_ieq(v, "off") || hx_ieq(v, "no"))
        *out = false;
    else
        return false;
    return true;
}

/* the polygon spec's label: "label=" among its comma-separated items, or the sixth item of the
 * short radial form */
static void spec_label(kelp_bhv_loiter *s, const char *v)
{
    size_t pos = 0, kl, vl;
    const char *k, *val;
    int rc;
    s->spec_label[0] = '\0';
    if (!strncmp(v, "radial:", 7) && v[7] != ':') {
        const char *c = v;
        for (unsigned i = 0; i < 5 && c; i++)
            c = strchr(c + 1, ',');
        if (c) {
            size_t n = strlen(c + 1);
            const char *t = c + 1;
            hx_trim(&t, &n);
            (void)hx_copy(s->spec_label, sizeof s->spec_label, t, n);
        }
        return;
    }
    while ((rc = kelp_kv_next(v, ',', &pos, &k, &kl, &val, &vl)) != 0)
        if (rc > 0 && kelp_util_strieq_n(k, kl, "label")) {
            (void)hx_copy(s->spec_label, sizeof s->spec_label, val, vl);
            return;
        }
}

/* a parsed polygon (n vertices in the helm's ws_bhv.pts) taken: convex or refused (nothing
 * changes); snapped to 0.1 m unless the snap would make it concave; ordered; the waypoint
 * engine restarts on it */
KELP_NOINLINE static int take_polygon(kelp_bhv *b, const char *v, unsigned n)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    const kelp_bhv_pt *pts = b->helm->ws_bhv.pts;
    if (!poly_sides(pts, n, s->side)) { /* (the sides are scratch until the polygon is taken) */
        (void)poly_sides(s->pts, s->npts, s->side);
        return kelp_helm_bhv_fail(b, "polygon: not a convex polygon of three or more vertices");
    }
    for (unsigned i = 0; i < n; i++) {
        s->pts[i].x = bhv_snap_step(pts[i].x, SNAP_M);
        s->pts[i].y = bhv_snap_step(pts[i].y, SNAP_M);
    }
    if (!poly_sides(s->pts, n, s->side))
        memcpy(s->pts, pts, n * sizeof *pts);
    s->npts = n;
    sides(s);
    spec_label(s, v);
    set_clockwise(s, s->clockwise);
    restart_list(s);
    s->acquire = true;
    return 0;
}

/* polygon: parsed aside (in the helm's workspace: a refused polygon changes nothing). Out of
 * line and small: the parse is the deepest call under a parameter. */
KELP_NOINLINE static int set_polygon(kelp_bhv *b, const char *v)
{
    unsigned n;
    if (kelp_helm_parse_points(v, b->helm->ws_bhv.pts, KELP_HELM_MAX_PTS, &n) != 0)
        return kelp_helm_bhv_fail(b, "polygon: not a polygon");
    return take_polygon(b, v, n);
}

/* mod_poly_rad: the polygon grows (or shrinks) by d, each vertex moved along its bearing from
 * the vertices' mean, to a largest radius of at least 5 m; the vertex steered for is kept */
KELP_NOINLINE static void mod_poly_rad(kelp_bhv_loiter *s, double d)
{
    kelp_bhv_pt c = poly_center(s);
    double cur = 0, mx = 0, my = 0;
    for (unsigned i = 0; i < s->npts; i++) {
        cur = fmax(cur, hypot(c.x - s->pts[i].x, c.y - s->pts[i].y));
        mx += s->pts[i].x / s->npts, my += s->pts[i].y / s->npts;
    }
    double amt = fmax(cur + d, MOD_RAD_MIN) - cur;
    for (unsigned i = 0; i < s->npts; i++)
        bhv_project(kelp_helm_relang(mx, my, s->pts[i].x, s->pts[i].y), amt, &s->pts[i].x, &s->pts[i].y);
    sides(s);
    unsigned ix = s->index;
    restart_list(s);
    set_index(s, (int)ix);
    s->acquire = true;
    s->mode = MODE_IDLE;
}

/* visual_hints: the shared hints plus the polygon's label and lcolor (label_color) */
KELP_NOINLINE static int set_hints(kelp_bhv_loiter *s, const char *v)
{
    int rc = bhv_set_hints(&s->hints, v);
    size_t pos = 0, kl, vl;
    const char *k, *val;
    while (rc == 0 && kelp_kv_next(v, ',', &pos, &k, &kl, &val, &vl) == 1) {
        if (kelp_util_strieq_n(k, kl, "label"))
            (void)hx_copy(s->poly_label, sizeof s->poly_label, val, vl);
        else if (kelp_util_strieq_n(k, kl, "lcolor"))
            (void)hx_copy(s->hints.label_color, sizeof s->hints.label_color, val, vl);
    }
    return rc;
}

/* post_suffix: "_" and the value upper-cased; an empty value or one with blanks is refused */
KELP_NOINLINE static int set_suffix(kelp_bhv_loiter *s, const char *v)
{
    size_t n = strlen(v);
    if (n == 0 || n + 2 > sizeof s->suffix || strpbrk(v, " \t"))
        return KELP_ERR_PARSE;
    s->suffix[0] = '_';
    for (size_t i = 0; i <= n; i++)
        s->suffix[i + 1] = (char)(v[i] >= 'a' && v[i] <= 'z' ? v[i] - 'a' + 'A' : v[i]);
    return 0;
}

static void update_center(kelp_bhv_loiter *s);

/* center_assign (applied at once), xcenter_assign / ycenter_assign (added to the pending
 * assignment, applied at the next run iteration) */
KELP_NOINLINE static int set_center(kelp_bhv_loiter *s, const char *p, const char *v)
{
    size_t n = strlen(s->center_assign);
    if (!strcmp(p, "center_assign")) {
        if (!hx_copy(s->center_assign, sizeof s->center_assign, v, strlen(v)))
            return KELP_ERR_RANGE;
        s->center_pending = true;
        update_center(s);
        return 0;
    }
    if (n + strlen(v) + 4 > sizeof s->center_assign)
        return KELP_ERR_RANGE;
    hx_cat(s->center_assign + n, sizeof s->center_assign - n, p[0] == 'x' ? ",x=" : ",y=", v, HX_END);
    s->center_pending = true;
    return 0;
}

/* the parameters other than polygon. Out of line: its locals are not under the polygon parse. */
KELP_NOINLINE static int set_other(kelp_bhv *b, const char *p, const char *v)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    double d;
    bool num = hx_number(v, strlen(v), &d);
    if (!strcmp(p, "center_assign") || !strcmp(p, "xcenter_assign") || !strcmp(p, "ycenter_assign"))
        return set_center(s, p, v);
    if (!strcmp(p, "mod_poly_rad")) {
        if (!num)
            return KELP_ERR_PARSE;
        mod_poly_rad(s, d);
        return 0;
    }
    if (!strcmp(p, "use_alt_speed"))
        return parse_bool(v, &s->use_alt_speed) ? 0 : KELP_ERR_PARSE;
    if (!strcmp(p, "center_activate"))
        return bhv_parse_true_false(v, &s->center_activate) ? 0 : KELP_ERR_PARSE;
    if (!strcmp(p, "clockwise")) {
        if (hx_ieq(v, "best")) {
            s->dynamic_clockwise = true;
            return 0;
        }
        bool cw = s->clockwise;
        if (!parse_bool(v, &cw))
            return KELP_ERR_PARSE;
        s->dynamic_clockwise = false;
        set_clockwise(s, cw);
        restart_list(s);
        return 0;
    }
    if (!strcmp(p, "speed") && num && d >= 0) {
        int is = kelp_ivp_domain_index(&b->dom, "speed");
        s->speed = is >= 0 && d > b->dom.var[is].high ? b->dom.var[is].high : d;
        return 0;
    }
    if (!strcmp(p, "slingshot"))
        return num && d >= 0 ? (s->slingshot = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "ipf-type") || !strcmp(p, "ipf_type")) {
        if (hx_ieq(v, "zaic") || hx_ieq(v, "zaic_spd"))
            s->zaic_spd = hx_ieq(v, "zaic_spd");
        return 0; /* any other value is taken and changes nothing */
    }
    if (!strcmp(p, "speed_alt") && num)
        return s->speed_alt = d, 0;
    if (!strcmp(p, "radius") || !strcmp(p, "capture_radius"))
        return num && d >= 0 ? (s->capture_radius = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "acquire_dist") || !strcmp(p, "acquire_distance"))
        return num && d >= 0 ? (s->acquire_dist = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "patience"))
        return num && d >= 1 && d <= 99 ? (s->patience = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "nm_radius") || !strcmp(p, "slip_radius"))
        return num && d >= 0 ? (s->slip_radius = d, 0) : KELP_ERR_PARSE;
    if (!strcmp(p, "post_suffix"))
        return set_suffix(s, v);
    if (!strcmp(p, "visual_hints"))
        return set_hints(s, v);
    if (!strcmp(p, "spiral_factor")) {
        /* the loiter engine maps 0..100 onto -75..-1 (a value that is no number reads as 0) */
        s->spiral_factor = -75.0 + ((num ? d : 0) / 100.0) * 74.0;
        return 0;
    }
    return KELP_ERR_NOTFOUND;
}

static int loiter_set_param(kelp_bhv *b, const char *p, const char *v)
{
    return !strcmp(p, "polygon") ? set_polygon(b, v) : set_other(b, p, v);
}

static int loiter_params_done(kelp_bhv *b)
{
    if (b->u.loiter.npts < 3)
        return kelp_helm_bhv_fail(b, "no polygon given");
    return 0;
}

/* ---------------------------------------------------------------- state updates */

/* updateInfoIn: ownship and the distance to the polygon (negative inside) and the ETA to it.
 * false (with a warning or an error, as 24.8 posts them) when something vital is missing. */
static bool update_info(kelp_bhv *b)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    if (s->npts == 0) {
        kelp_helm_bhv_post_warning(b, "Empty/NULL Loiter Specification.");
        return false;
    }
    double x, y, h;
    bool okx = kelp_helm_bhv_buf_double(b, "NAV_X", &x), oky = kelp_helm_bhv_buf_double(b, "NAV_Y", &y);
    if (!okx || !oky) {
        kelp_helm_bhv_post_error(b, "No ownship X/Y info in info_buffer.");
        return false;
    }
    s->osx = x, s->osy = y;
    if (!kelp_helm_bhv_buf_double(b, "NAV_HEADING", &h)) {
        kelp_helm_bhv_post_error(b, "No ownship heading info in info_buffer.");
        return false;
    }
    s->osh = angle360(h);
    if (!kelp_helm_bhv_buf_double(b, "NAV_SPEED", &s->osv))
        s->osv = 0;
    s->dist_to_poly = poly_dist(s, x, y);
    if (poly_contains(s, x, y))
        s->dist_to_poly = -s->dist_to_poly;
    s->eta_to_poly = 0;
    if (s->dist_to_poly > 0 && s->osh > 0.001) /* (24.8 tests the heading here, not the speed) */
        s->eta_to_poly = s->dist_to_poly / s->osv;
    return true;
}

static void update_mode(kelp_bhv_loiter *s)
{
    if (s->dist_to_poly > s->acquire_dist)
        s->mode = (s->mode == MODE_STABLE || s->mode == MODE_REC_EXT) ? MODE_REC_EXT : MODE_ACQ_EXT;
    else if (s->dist_to_poly < -s->acquire_dist)
        s->mode = (s->mode == MODE_STABLE || s->mode == MODE_REC_INT) ? MODE_REC_INT : MODE_ACQ_INT;
    else
        s->mode = MODE_STABLE;
}

/* a pending centre: "present_position" (where the vehicle was last seen), "x=..", "y=.." or
 * both ("x=..,y=.."), or "x,y"; a malformed one is dropped */
static void update_center(kelp_bhv_loiter *s)
{
    if (!s->center_pending)
        return;
    char *a = s->center_assign;
    for (char *c = a; *c; c++)
        *c = hx_lower(*c);
    if (!strcmp(a, "present_position")) {
        move_center(s, s->osx, s->osy);
    } else if (strchr(a, '=')) {
        kelp_bhv_pt c = poly_center(s);
        bool moved = false;
        for (const char *p = a; p;) {
            const char *e = strchr(p, ','), *end = e ? e : p + strlen(p);
            const char *eq = memchr(p, '=', (size_t)(end - p));
            if (eq && !memchr(eq + 1, '=', (size_t)(end - eq - 1))) {
                const char *k = p;
                size_t kn = (size_t)(eq - p);
                hx_trim(&k, &kn);
                bool isx = kn == 1 && *k == 'x', isy = kn == 1 && *k == 'y';
                double v;
                if ((isx || isy) && hx_number(eq + 1, (size_t)(end - eq - 1), &v)) {
                    *(isx ? &c.x : &c.y) = v;
                    moved = true;
                }
            }
            p = e ? e + 1 : NULL;
        }
        if (moved)
            move_center(s, c.x, c.y);
    } else {
        const char *comma = strchr(a, ',');
        double x, y;
        if (comma && !strchr(comma + 1, ',') && hx_number(a, (size_t)(comma - a), &x) &&
            hx_number(comma + 1, strlen(comma + 1), &y))
            move_center(s, x, y);
    }
    a[0] = '\0';
    s->center_pending = false;
}

/* ---------------------------------------------------------------- postings */

/* the variable base + post_suffix, composed in the helm's behaviour workspace */
static const char *var_sfx(const kelp_bhv *b, const char *base)
{
    hx_cat(b->helm->ws_bhv.var, sizeof b->helm->ws_bhv.var, base, b->u.loiter.suffix, HX_END);
    return b->helm->ws_bhv.var;
}

/* postIntMessage's value: v + 0.5 truncated toward zero; a value no int holds (an ETA at
 * speed 0 is infinite) comes out as the x86-64 conversion gives it, INT_MIN */
static double int_value(double v)
{
    double r = v + 0.5;
    if (!(r > (double)INT_MIN - 1.0 && r < (double)INT_MAX + 1.0))
        return (double)INT_MIN;
    return (double)(int)r;
}

/* postStatusReports */
KELP_NOINLINE static void post_status(kelp_bhv *b)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    char *rep = b->helm->ws_bhv.post2, (*nb)[32] = b->helm->ws_bhv.num;
    hx_fmt_ulong(nb[0], sizeof nb[0], s->index);
    hx_fmt_ulong(nb[1], sizeof nb[0], s->capture_hits);
    hx_fmt_ulong(nb[2], sizeof nb[0], s->nonmono_hits);
    hx_cat(rep, sizeof b->helm->ws_bhv.post2, "index=", nb[0], ",capture_hits=", nb[1], ",nonmono_hits=", nb[2],
           ",acquire_mode=", s->acquire ? "true" : "false", HX_END);
    kelp_helm_bhv_post_string(b, var_sfx(b, "LOITER_REPORT"), rep, NULL);
    kelp_helm_bhv_post_double(b, var_sfx(b, "LOITER_INDEX"), (double)s->index, NULL);
    kelp_helm_bhv_post_string(b, var_sfx(b, "LOITER_MODE"), mode_name[s->mode], NULL);
    kelp_helm_bhv_post_double(b, var_sfx(b, "LOITER_ACQUIRE"), s->acquire ? 1 : 0, NULL);
    double d = s->dist_to_poly, e = s->eta_to_poly;
    kelp_helm_bhv_post_double(b, var_sfx(b, "LOITER_DIST_TO_POLY"), d > INT_POST_ABOVE ? int_value(d) : d, NULL);
    kelp_helm_bhv_post_double(b, var_sfx(b, "LOITER_ETA_TO_POLY"),
                              (e > INT_POST_ABOVE || e == 0) ? int_value(e) : e, NULL);
}

/* the drawings' label: visual_hints label, else <vehicle>_<behaviour name, lower case> */
static const char *poly_tag(const kelp_bhv *b, char *buf, size_t cap)
{
    if (b->u.loiter.poly_label[0])
        return b->u.loiter.poly_label;
    size_t n = hx_cat(buf, cap, b->us, "_", b->name, HX_END);
    for (size_t i = n - strlen(b->name); i < n; i++)
        buf[i] = hx_lower(buf[i]);
    return buf;
}

/* "pts={x,y:...}" with at most one decimal (the polygon's spec); returns the length */
static size_t pts_spec(const kelp_bhv_loiter *s, char *buf, size_t cap, char *x, char *y, size_t ncap)
{
    if (s->npts == 0) {
        buf[0] = '\0';
        return 0;
    }
    size_t n = hx_cat(buf, cap, "pts={", HX_END);
    for (unsigned i = 0; i < s->npts; i++) {
        hx_fmt_x(x, ncap, s->pts[i].x, 1);
        hx_fmt_x(y, ncap, s->pts[i].y, 1);
        n += hx_cat(buf + n, cap - n, i ? ":" : "", x, ",", y, HX_END);
    }
    return n + hx_cat(buf + n, cap - n, "}", HX_END);
}

/* VIEW_POLYGON: drawn with its hints (active), or the erasing spec */
KELP_NOINLINE static void post_polygon(kelp_bhv *b, bool active)
{
    const kelp_bhv_loiter *s = &b->u.loiter;
    char *buf = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num, *tag = b->helm->ws_bhv.post2;
    const size_t cap = sizeof b->helm->ws_bhv.post, ncap = sizeof nb[0];
    size_t n = pts_spec(s, buf, cap, nb[0], nb[1], ncap);
    const char *label = poly_tag(b, tag, sizeof b->helm->ws_bhv.post2);
    if (!active) {
        hx_cat(buf + n, cap - n, n ? "," : "", "active=false,label=", label, HX_END);
    } else {
        n += hx_cat(buf + n, cap - n, n ? "," : "", "label=", label, HX_END);
        if (s->hints.label_color[0])
            n += hx_cat(buf + n, cap - n, ",label_color=", s->hints.label_color, HX_END);
        hx_fmt_x(nb[2], ncap, s->hints.vertex_size, 1);
        hx_fmt_x(nb[3], ncap, s->hints.edge_size, 1);
        hx_cat(buf + n, cap - n, ",edge_color=", s->hints.edge_color, ",vertex_color=", s->hints.vertex_color,
               ",vertex_size=", nb[2], ",edge_size=", nb[3], HX_END);
    }
    kelp_helm_bhv_post_string(b, "VIEW_POLYGON", buf, NULL);
}

/* VIEW_POINT: the vertex steered for (active) or the erasing spec */
KELP_NOINLINE static void post_point(kelp_bhv *b, bool active)
{
    const kelp_bhv_loiter *s = &b->u.loiter;
    char *buf = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num;
    const size_t cap = sizeof b->helm->ws_bhv.post, ncap = sizeof nb[0];
    hx_fmt_x(nb[0], ncap, s->ptx, 2);
    hx_fmt_x(nb[1], ncap, s->pty, 2);
    size_t n = hx_cat(buf, cap, "x=", nb[0], ",y=", nb[1], active ? "" : ",active=false", ",label=", b->us,
                      "_waypoint", HX_END);
    if (active) {
        hx_fmt_x(nb[2], ncap, s->hints.nextpt_vertex_size, 1);
        hx_cat(buf + n, cap - n, ",label_color=", s->hints.nextpt_lcolor, ",vertex_color=", s->hints.nextpt_color,
               ",vertex_size=", nb[2], HX_END);
    }
    kelp_helm_bhv_post_string(b, "VIEW_POINT", buf, NULL);
}

/* BHV_SETTINGS (postConfigStatus): after configuration, each applied update and each idle to
 * running transition */
static void loiter_post_config(kelp_bhv *b)
{
    const kelp_bhv_loiter *s = &b->u.loiter;
    char *buf = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num;
    const size_t cap = sizeof b->helm->ws_bhv.post, ncap = sizeof nb[0];
    kelp_bhv_pt c = poly_center(s);
    hx_fmt_fixed(nb[0], ncap, c.x, 2);
    hx_fmt_fixed(nb[1], ncap, c.y, 2);
    hx_fmt_fixed(nb[2], ncap, s->speed, 1);
    size_t n = hx_cat(buf, cap, "type=BHV_Loiter,name=", b->name, ",x=", nb[0], ",y=", nb[1], ",clockwise=",
                      s->clockwise ? "true" : "false", ",dynamic_clockwise=", s->dynamic_clockwise ? "true" : "false",
                      ",center_activate=", s->center_activate ? "true" : "false", ",desired_speed=", nb[2],
                      ",polygon=\"", HX_END);
    n += pts_spec(s, buf + n, cap - n, nb[3], nb[4], ncap);
    hx_cat(buf + n, cap - n, s->spec_label[0] ? ",label=" : "", s->spec_label, "\"", HX_END);
    kelp_helm_bhv_post_string(b, "BHV_SETTINGS", buf, "repeatable");
}

/* ---------------------------------------------------------------- states */

static void loiter_idle(kelp_bhv *b)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    post_point(b, false);
    post_polygon(b, false);
    s->mode = MODE_IDLE;
    post_status(b);
    s->bng_last = -1;
    s->bng_total = 0;
    if (s->center_activate) {
        (void)hx_copy(s->center_assign, sizeof s->center_assign, "present_position", 16);
        s->center_pending = true;
    }
}

/* onIdleToRunState: BHV_SETTINGS, the entry vertex from where the vehicle is, and with
 * clockwise = best the direction (which restarts the list at its first vertex) */
KELP_NOINLINE static void idle_to_run(kelp_bhv *b)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    loiter_post_config(b);
    (void)update_info(b);
    set_index(s, acquire_vertex(s, s->osh, s->osx, s->osy));
    if (s->dynamic_clockwise)
        reset_clockwise_best(s);
}

/* onCompleteState: the slingshot done, the duration run out, ... */
static void loiter_complete(kelp_bhv *b)
{
    post_point(b, false);
    post_polygon(b, false);
    kelp_helm_bhv_post_string(b, "LOITER_COMPLETE", "true", NULL);
    b->u.loiter.bng_last = -1;
    b->u.loiter.bng_total = 0;
}

/* the slingshot's bearing count while loitering: true when it passed the limit */
KELP_NOINLINE static bool slingshot(kelp_bhv *b)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    if (s->acquire || s->slingshot <= -1)
        return false;
    kelp_bhv_pt c = poly_center(s);
    double bng = kelp_helm_relang(s->osx, s->osy, c.x, c.y);
    if (s->bng_last != -1) {
        double delta = fabs(angle360(bng) - angle360(s->bng_last));
        if (delta >= 180)
            delta = 360 - delta;
        s->bng_total += delta;
        kelp_helm_bhv_post_double(b, "LOITER_BNG_TOTAL", s->bng_total, NULL);
        kelp_helm_bhv_post_double(b, "LOITER_BNG_DELTA", delta, NULL);
    }
    s->bng_last = bng;
    return s->bng_total > s->slingshot;
}

static double clamp(double v, double lo, double hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

/* the domain point nearest v (a half rounds up), within 0..top */
static int dom_index(double v, double lo, double delta, int top)
{
    int i = (int)((v - lo) / delta + 0.5);
    return i < 0 ? 0 : (i > top ? top : i);
}

/* ipf_type = zaic_spd: 24.8's loiter sets ZAIC_SPD to utility 100 at the speed, 85 at 0.1 m/s,
 * 20 at the speed + 0.4 and 0 at both ends of the domain (a point at an end takes the end's 0),
 * straight lines between the points (each snapped to the nearest domain point): into w->tmp */
KELP_NOINLINE static int zaic_spd(kelp_bhv *b, const kelp_helm_work *w, double speed, kelp_ivp_func *spd)
{
    if (kelp_ivp_domain_sub(&b->dom, "speed", &spd->dom) < 0)
        return KELP_ERR_NOTFOUND;
    const kelp_ivp_var *v = &spd->dom.var[0];
    double lo = v->low, hi = v->high, dl = v->delta > 0 ? v->delta : 1;
    int top = (int)v->points - 1;
    double med = clamp(speed, lo, hi), low = fmin(clamp(ZSPD_LOW, lo, hi), med);
    double hgh = fmax(clamp(speed + ZSPD_ABOVE, lo, hi), med);
    /* the domain points of the low, desired and high speeds, in that order */
    int i_lo = dom_index(low, lo, dl, top), i_med = dom_index(med, lo, dl, top), i_hi = dom_index(hgh, lo, dl, top);
    if (i_lo > i_med)
        i_lo = i_med;
    if (i_hi < i_med)
        i_hi = i_med;
    int32_t d[5];
    double r[5];
    unsigned k = 0;
    if (i_med != 0)
        d[k] = 0, r[k++] = 0;
    if (i_lo != 0 && i_lo != i_med)
        d[k] = i_lo, r[k++] = low == lo ? 0 : ZSPD_LOW_UTIL;
    d[k] = i_med, r[k++] = 100;
    if (i_hi != i_med)
        d[k] = i_hi, r[k++] = hgh == hi ? 0 : ZSPD_ABOVE_UTIL;
    if (top != i_hi)
        d[k] = top, r[k++] = 0;
    spd->pcs = w->tmp;
    spd->cap = w->tmp_cap;
    spd->n = 0;
    spd->pwt = 100;
    for (unsigned i = 0; i + 1 < k || (k == 1 && i == 0); i++) {
        int32_t a = k == 1 ? d[0] : (i == 0 ? d[0] : d[i] + 1), e = k == 1 ? d[0] : d[i + 1];
        double slope = k == 1 ? 0 : (r[i + 1] - r[i]) / (double)(d[i + 1] - d[i]);
        int rc = kelp_ivp_func_add(spd, &a, &e, &slope, r[i] - slope * d[i]);
        if (rc < 0)
            return rc;
    }
    return 0;
}

/* onRunState up to the function: idle -> running, ownship, mode, centre, acquisition, the
 * slingshot (*done) and the next waypoint; false when vital information is missing. Out of
 * line: the geometry's locals are not on the stack under the IvP build that follows. */
KELP_NOINLINE static bool loiter_advance(kelp_bhv *b, bool *done)
{
    kelp_bhv_loiter *s = &b->u.loiter;
    if (b->state == KELP_BHV_IDLE) /* the state of the last iteration: this is idle -> running */
        idle_to_run(b);
    if (!update_info(b)) {
        post_point(b, false);
        return false;
    }
    update_mode(s);
    update_center(s);
    s->acquire = s->dist_to_poly > s->acquire_dist;
    if (s->acquire)
        set_index(s, acquire_vertex(s, s->osh, s->osx, s->osy));
    *done = slingshot(b);
    if (next_waypoint(s, s->osx, s->osy))
        s->acquire = false;
    s->ptx = s->pts[s->index].x;
    s->pty = s->pts[s->index].y;
    kelp_helm_bhv_post_double(b, "LOITER_DIST_TO_VERT", hypot(s->osx - s->ptx, s->osy - s->pty), NULL);
    return true;
}

static int loiter_run(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    const kelp_bhv_loiter *s = &b->u.loiter;
    bool done = false;
    if (!loiter_advance(b, &done))
        return 0;
    /* buildIPF: the course peak coupled with the speed function, the course's share patience */
    double speed = (s->speed_alt >= 0 && s->use_alt_speed) ? s->speed_alt : s->speed;
    double crs = kelp_helm_relang(s->osx, s->osy, s->ptx, s->pty);
    kelp_ivp_func *spd = &b->helm->ws_bhv.cs[0];
    int rc;
    if (!s->zaic_spd)
        rc = bhv_course_speed_zaic_ratio(b, w, crs, speed, 0, SPEED_BASE, 0, s->patience, out);
    else if ((rc = zaic_spd(b, w, speed, spd)) >= 0)
        rc = bhv_course_couple(b, w, crs, spd, spd->n, s->patience, out);
    post_polygon(b, true);
    post_point(b, true);
    post_status(b);
    if (done)
        kelp_helm_bhv_set_complete(b); /* (on_complete then posts LOITER_COMPLETE) */
    if (rc < 0) {
        kelp_helm_bhv_post_warning(b, "Problem Creating the IvP Function");
        return 0;
    }
    return 1;
}

const kelp_bhv_ops kelp_bhv_loiter_ops = {
    .type = "BHV_Loiter",
    .init = loiter_init,
    .set_param = loiter_set_param,
    .params_done = loiter_params_done,
    .on_idle = loiter_idle,
    .on_run = loiter_run,
    .post_config = loiter_post_config,
    .on_complete = loiter_complete,
};
