/* kelp helm: geometry and IvP-function helpers shared by the behaviours. */
#include <math.h>
#include <string.h>
#include <kelp/kv.h>
#include <kelp/mission.h>
#include "helm_int.h"

#define DEG_PER_RAD 57.29577951308232
#define PI_DEG 3.14159265358979323846 /* pi, for degrees / 180 * pi as MOOS-IvP converts */

double kelp_helm_relang(double xa, double ya, double xb, double yb)
{
    if (xa == xb && ya == yb)
        return 0;
    double a = atan2(xb - xa, yb - ya) * DEG_PER_RAD;
    if (a < 0)
        a += 360.0;
    if (a >= 360.0)
        a -= 360.0;
    return a;
}

/* The value under key in "k=v,..." (the first pair with that key, trimmed), read in place:
 * no copy on the stack, which the polygon parse under AvoidCollision's run needs for the
 * firmware's 1 KB. A malformed item is skipped, as kelp_kv_get does. */
static bool kv_find(const char *s, const char *key, const char **v, size_t *vl)
{
    size_t pos = 0, kl;
    const char *k;
    int rc;
    while ((rc = kelp_kv_next(s, ',', &pos, &k, &kl, v, vl)) != 0)
        if (rc > 0 && kelp_util_strieq_n(k, kl, key))
            return true;
    return false;
}

/* The number under key; a value of 64 bytes or more is refused (as when it was copied into 64). */
static bool kv_num(const char *s, const char *key, double *out, bool *present)
{
    const char *v;
    size_t vl;
    *present = false;
    if (!kv_find(s, key, &v, &vl))
        return true;
    if (vl >= 64)
        return false;
    *present = true;
    return hx_number(v, vl, out);
}

double bhv_snap_step(double v, double step)
{
    double q = v / step;
    return (double)(long)(q < 0 ? q - 0.5 : q + 0.5) * step;
}

void bhv_project(double deg, double dist, double *x, double *y)
{
    if (deg == 90)
        *x += dist;
    else if (deg == 180)
        *y -= dist;
    else if (deg == 270)
        *x -= dist;
    else if (deg == 0)
        *y += dist;
    else {
        double a = deg / 180.0 * PI_DEG;
        *x += sin(a) * dist;
        *y += cos(a) * dist;
    }
}

/* The radial polygon of v = {x, y, radius, pts, snap} as MOOS-IvP 24.8 lays it out
 * (XYFormatUtilsPoly's radial forms): pts vertices on the circle, the first half a step
 * clockwise of north (22.5 degrees for 8), the bearings summed step by step; on an axis
 * (0, 90, 180, 270) the vertex lies exactly on it. Snapped to a grid of snap when snap > 0.
 * Out of line: its locals are not on the stack while parse_radial reads the numbers. */
KELP_NOINLINE static int radial_make(const double *v, kelp_bhv_pt *pts, size_t cap, unsigned *n)
{
    double x = v[0], y = v[1], r = v[2], np = v[3], snap = v[4];
    if (r <= 0 || np < 3 || np != floor(np) || snap < 0)
        return KELP_ERR_PARSE;
    if (np > (double)cap)
        return KELP_ERR_NOSPACE;
    double step = 360.0 / np;
    unsigned k = 0;
    for (double deg = step / 2; deg < 360 && k < cap; deg += step) {
        double vx = x, vy = y;
        bhv_project(deg, r, &vx, &vy);
        if (snap > 0) {
            vx = bhv_snap_step(vx, snap);
            vy = bhv_snap_step(vy, snap);
        }
        pts[k].x = vx;
        pts[k].y = vy;
        k++;
    }
    *n = k;
    return 0;
}

static int parse_radial(const char *s, kelp_bhv_pt *pts, size_t cap, unsigned *n)
{
    /* read one after another into an array (no five live doubles across the calls) */
    static const char *const key[5] = {"x", "y", "radius", "pts", "snap"};
    double v[5] = {0, 0, 0, 0, 0}; /* snap 0 when absent */
    bool missing = false;
    for (unsigned i = 0; i < 5; i++) {
        bool present;
        if (!kv_num(s, key[i], &v[i], &present))
            return KELP_ERR_PARSE;
        missing = missing || (i < 4 && !present);
    }
    return missing ? KELP_ERR_PARSE : radial_make(v, pts, cap, n);
}

/* The short radial form "px, py, radius, pts[, snap[, label]]" (after "radial:"). Out of line:
 * its numbers are not on the stack under the other forms' parses. */
KELP_NOINLINE static int parse_short_radial(const char *s, kelp_bhv_pt *pts, size_t cap, unsigned *n)
{
    double v[5] = {0, 0, 0, 0, 0};
    unsigned k = 0;
    const char *p = s;
    for (;;) {
        const char *c = strchr(p, ',');
        size_t len = c ? (size_t)(c - p) : strlen(p);
        if (k < 5 && !hx_number(p, len, &v[k]))
            return KELP_ERR_PARSE;
        k++;
        if (!c)
            break;
        p = c + 1;
    }
    if (k < 4 || k > 6)
        return KELP_ERR_PARSE;
    return radial_make(v, pts, cap, n);
}

/* "x1,y1:x2,y2:..." with one level of braces or parentheses around it and "(x,y)" items
 * allowed. Out of line: its locals are not on the stack under the radial parse. */
KELP_NOINLINE static int parse_list(const char *b, kelp_bhv_pt *pts, size_t cap, unsigned *n)
{
    /* strip one level of braces or parentheses */
    size_t bl = strlen(b);
    const char *t = b;
    hx_trim(&t, &bl);
    if (bl >= 2 && ((t[0] == '{' && t[bl - 1] == '}') || (t[0] == '(' && t[bl - 1] == ')'))) {
        t++;
        bl -= 2;
    }
    unsigned k = 0;
    const char *p = t, *end = t + bl;
    while (p < end) {
        const char *c = memchr(p, ':', (size_t)(end - p));
        const char *e = c ? c : end;
        const char *comma = memchr(p, ',', (size_t)(e - p));
        if (!comma)
            return KELP_ERR_PARSE;
        double x, y;
        const char *q = p;
        size_t qn = (size_t)(comma - p);
        /* tolerate "(x,y)" items */
        hx_trim(&q, &qn);
        if (qn && *q == '(') {
            q++;
            qn--;
        }
        const char *r = comma + 1;
        size_t rn = (size_t)(e - r);
        hx_trim(&r, &rn);
        if (rn && r[rn - 1] == ')')
            rn--;
        if (memchr(r, ',', rn))
            return KELP_ERR_PARSE;
        if (!hx_number(q, qn, &x) || !hx_number(r, rn, &y))
            return KELP_ERR_PARSE;
        if (k >= cap)
            return KELP_ERR_NOSPACE;
        pts[k].x = x;
        pts[k].y = y;
        k++;
        if (c && c + 1 >= end)
            return KELP_ERR_PARSE; /* trailing ':' */
        p = c ? c + 1 : end;
    }
    if (k == 0)
        return KELP_ERR_PARSE;
    *n = k;
    return 0;
}

int kelp_helm_parse_points(const char *str, kelp_bhv_pt *pts, size_t cap, unsigned *n)
{
    const char *s = str;
    size_t len = strlen(s);
    hx_trim(&s, &len);
    /* read in place (no copy): every reader below trims or stops at its own delimiters */
    if (len == 0 || len >= KELP_HELM_MAX_SVAL)
        return KELP_ERR_PARSE;
    const char *b = s;
    if (!strncmp(b, "radial::", 8))
        return parse_radial(b + 8, pts, cap, n);
    if (!strncmp(b, "radial:", 7))
        return parse_short_radial(b + 7, pts, cap, n);
    /* (the values were read into 32 and 8 bytes: a longer one did not count, and still does not) */
    const char *v;
    size_t vl;
    if (kv_find(b, "format", &v, &vl) && vl < 32) {
        if (!kelp_util_strieq_n(v, vl, "radial"))
            return KELP_ERR_UNSUPPORTED;
        return parse_radial(b, pts, cap, n);
    }
    if (kv_find(b, "radius", &v, &vl))
        return KELP_ERR_UNSUPPORTED; /* 24.8 reads a radial polygon only with format=radial */
    if ((b[0] == 'p' || b[0] == 'P') && kelp_util_strieq_n(b, 3, "pts")) {
        const char *eq = strchr(b, '=');
        if (!eq)
            return KELP_ERR_PARSE;
        b = eq + 1;
    } else if (strchr(b, '=')) {
        double x, y;
        bool px, py;
        if (!kv_num(b, "x", &x, &px) || !kv_num(b, "y", &y, &py) || !px || !py)
            return KELP_ERR_PARSE;
        if (cap < 1)
            return KELP_ERR_NOSPACE;
        pts[0].x = x;
        pts[0].y = y;
        *n = 1;
        return 0;
    }
    return parse_list(b, pts, cap, n);
}

int bhv_zaic1(kelp_bhv *b, const kelp_helm_work *w, const char *var, double summit, double pw, double bw, double sd,
              bool wrap, kelp_ivp_func *out)
{
    kelp_ivp_zaic_peak *z = &b->helm->ws_bhv.zaic;
    hx_ignore(kelp_ivp_zaic_peak_init(z, &b->dom, var));
    hx_ignore(kelp_ivp_zaic_peak_set_summit(z, summit, 0));
    hx_ignore(kelp_ivp_zaic_peak_set_peakwidth(z, pw, 0));
    hx_ignore(kelp_ivp_zaic_peak_set_basewidth(z, bw, 0));
    hx_ignore(kelp_ivp_zaic_peak_set_summitdelta(z, sd, 0));
    z->wrap = wrap;
    if (!z->ok) {
        char *msg = b->helm->ws_bhv.zaic_msg;
        hx_cat(msg, sizeof b->helm->ws_bhv.zaic_msg, var, " ZAIC problems ", z->warn, HX_END);
        if (msg[0] >= 'a' && msg[0] <= 'z')
            msg[0] = (char)(msg[0] - 'a' + 'A');
        kelp_helm_bhv_post_warning(b, msg);
        return KELP_ERR_STATE;
    }
    return kelp_ivp_zaic_peak_extract(z, true, w->dwork, w->dwork_cap, w->out, w->out_cap, out);
}

int bhv_course_speed_zaic(kelp_bhv *b, const kelp_helm_work *w, double course, double speed, double spw, double sbw,
                          double ssd, kelp_ivp_func *out)
{
    return bhv_course_speed_zaic_ratio(b, w, course, speed, spw, sbw, ssd, 50, out);
}

int bhv_cs_speed_points(const kelp_bhv *b, const kelp_helm_work *w, size_t *ns)
{
    int is = kelp_ivp_domain_index(&b->dom, "speed");
    if (is < 0 || kelp_ivp_domain_index(&b->dom, "course") < 0)
        return KELP_ERR_NOTFOUND;
    *ns = b->dom.var[is].points;
    return w->tmp_cap <= *ns ? KELP_ERR_NOSPACE : 0;
}

int bhv_course_speed_zaic_ratio(kelp_bhv *b, const kelp_helm_work *w, double course, double speed, double spw,
                                double sbw, double ssd, double course_pct, kelp_ivp_func *out)
{
    size_t ns;
    int rc = bhv_cs_speed_points(b, w, &ns);
    if (rc < 0)
        return rc;
    kelp_ivp_func *spd = &b->helm->ws_bhv.cs[0];
    kelp_helm_work wz = *w; /* the speed ZAIC's pieces first in tmp (the course's after them) */
    wz.out = w->tmp;
    wz.out_cap = ns;
    rc = bhv_zaic1(b, &wz, "speed", speed, spw, sbw, ssd, false, spd);
    if (rc < 0)
        return rc;
    return bhv_course_couple(b, w, course, spd, ns, course_pct, out);
}

int bhv_course_couple(kelp_bhv *b, const kelp_helm_work *w, double course, const kelp_ivp_func *spd, size_t used,
                      double course_pct, kelp_ivp_func *out)
{
    if (used >= w->tmp_cap)
        return KELP_ERR_NOSPACE;
    kelp_ivp_func *crs = &b->helm->ws_bhv.cs[1];
    kelp_helm_work wz = *w; /* the course ZAIC's pieces after the speed function's in tmp */
    wz.out = w->tmp + used;
    wz.out_cap = w->tmp_cap - used;
    int rc = bhv_zaic1(b, &wz, "course", course, 0, 180.0, 0, true, crs);
    if (rc < 0)
        return rc;
    return kelp_ivp_couple(crs, course_pct, spd, 100 - course_pct, true, 0, 100, w->out, w->out_cap, out);
}

bool bhv_platform_info(kelp_bhv *b, double *osx, double *osy, double *osh)
{
    bool ok1 = kelp_helm_bhv_buf_double(b, "NAV_X", osx);
    bool ok2 = kelp_helm_bhv_buf_double(b, "NAV_Y", osy);
    if (!ok1 || !ok2) {
        kelp_helm_bhv_post_error(b, "No ownship X/Y info in info_buffer.");
        return false;
    }
    double h;
    if (!kelp_helm_bhv_buf_double(b, "NAV_HEADING", &h)) {
        kelp_helm_bhv_post_error(b, "No ownship heading info in info_buffer.");
        return false;
    }
    *osh = fmod(h, 360.0);
    if (*osh < 0) *osh += 360.0;
    return true;
}
