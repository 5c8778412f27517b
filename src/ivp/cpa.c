/* kelp CPA: closest point of approach on straight legs (see include/kelp/cpa.h). */
#include <math.h>
#include <string.h>
#include <kelp/cpa.h>

static const double DEG = 0.017453292519943295;

/* Closest approach of d(t) = d0 + w t over [0, tol] (tol <= 0: [0, inf)). */
static double closest(double dx, double dy, double wx, double wy, double tol, double *tcpa)
{
    double ww = wx * wx + wy * wy, t = 0.0;
    if (ww > 0.0) {
        t = -(dx * wx + dy * wy) / ww;
        if (t < 0.0) t = 0.0;
        if (tol > 0.0 && t > tol) t = tol;
    }
    if (tcpa) *tcpa = t;
    return hypot(dx + wx * t, dy + wy * t);
}

double kelp_cpa_range(double cnx, double cny, double cnh, double cnv, double osx, double osy, double osh,
                      double osv, double tol, double *tcpa)
{
    /* the contact relative to ownship: d(t) = d0 + w t */
    double wx = cnv * sin(cnh * DEG) - osv * sin(osh * DEG);
    double wy = cnv * cos(cnh * DEG) - osv * cos(osh * DEG);
    return closest(cnx - osx, cny - osy, wx, wy, tol, tcpa);
}

static double norm360(double a)
{
    a = fmod(a, 360.0);
    if (a < 0) a += 360.0;
    if (a >= 360.0) a = 0.0;
    return a;
}

/* sine and cosine of a heading in degrees, exact at the quadrant headings */
static void sincosd(double hdg, double *s, double *c)
{
    double h = norm360(hdg);
    if (h == 0) *s = 0, *c = 1;
    else if (h == 90) *s = 1, *c = 0;
    else if (h == 180) *s = 0, *c = -1;
    else if (h == 270) *s = -1, *c = 0;
    else *s = sin(h * DEG), *c = cos(h * DEG);
}

/* velocity of a vessel under the header's conventions (heading mod 360, speed >= 0) */
static void velocity(double hdg, double spd, double *vx, double *vy)
{
    double s, c, v = spd > 0 ? spd : 0;
    sincosd(hdg, &s, &c);
    *vx = v * s;
    *vy = v * c;
}

/* rounding noise: a component this small relative to its vector's length counts as 0 */
#define CPA_REL_EPS 1e-9

/* true bearing of vector (dx, dy) in [0,360); 0 for the null vector */
static double bearing(double dx, double dy)
{
    if (dx == 0 && dy == 0) return 0;
    return norm360(atan2(dx, dy) / DEG);
}

static bool vessel_ok(const kelp_cpa_vessel *v)
{
    return v && isfinite(v->x) && isfinite(v->y) && isfinite(v->hdg) && isfinite(v->spd);
}

/* How mover a (relative position r = a - b, relative velocity w = va - vb) meets the
 * reference vessel b of heading hb: crossings of b's heading line, passings of its beam. */
typedef struct encounter {
    bool bow, stern, port, star;
    double bow_d, stern_d, port_d, star_d;
} encounter;

static void meet(double rx, double ry, double wx, double wy, double hb, encounter *e)
{
    memset(e, 0, sizeof *e);
    if (rx == 0 && ry == 0) return;
    double fx, fy;
    sincosd(hb, &fx, &fy);
    double sx = fy, sy = -fx; /* forward and starboard units */
    double ws = wx * sx + wy * sy, wf = wx * fx + wy * fy;
    double weps = CPA_REL_EPS * hypot(wx, wy), reps = CPA_REL_EPS * hypot(rx, ry);
    double ww = wx * wx + wy * wy;
    if (ww > 0) { /* a collision course (head-on included) crosses the bow at 0, passes neither */
        double tc = -(rx * wx + ry * wy) / ww;
        if (tc >= 0 && hypot(rx + wx * tc, ry + wy * tc) <= reps) {
            e->bow = true;
            return;
        }
    }
    if (fabs(ws) > weps) {
        double t = -(rx * sx + ry * sy) / ws;
        if (t >= 0) {
            double a = (rx + wx * t) * fx + (ry + wy * t) * fy;
            if (fabs(a) <= reps) a = 0;
            if (a >= 0) e->bow = true, e->bow_d = a;
            else e->stern = true, e->stern_d = -a;
        }
    }
    if (fabs(wf) > weps) {
        double t = -(rx * fx + ry * fy) / wf;
        if (t >= 0) {
            double b = (rx + wx * t) * sx + (ry + wy * t) * sy;
            if (fabs(b) <= reps) b = 0;
            if (b > 0) e->star = true, e->star_d = b;
            else if (b < 0) e->port = true, e->port_d = -b;
        }
    }
}

/* side of the vessel at relative position (rx, ry) from a vessel of heading h */
static void sides(double rx, double ry, double h, bool *fore, bool *aft, bool *port, bool *star)
{
    if (rx == 0 && ry == 0) {
        *fore = *aft = *port = *star = false;
        return;
    }
    double sh, ch, eps = CPA_REL_EPS * hypot(rx, ry);
    sincosd(h, &sh, &ch);
    double along = rx * sh + ry * ch, across = rx * ch - ry * sh;
    if (fabs(along) <= eps) along = 0;
    if (fabs(across) <= eps) across = 0;
    *fore = along >= 0;
    *aft = along <= 0;
    *star = across >= 0;
    *port = across <= 0;
}

int kelp_cpa_eval(const kelp_cpa_vessel *cn, const kelp_cpa_vessel *os, double tol, kelp_cpa_result *out)
{
    if (!out) return KELP_ERR_ARG;
    memset(out, 0, sizeof *out);
    if (!vessel_ok(cn) || !vessel_ok(os) || isnan(tol)) return KELP_ERR_ARG;
    double cvx, cvy, ovx, ovy;
    velocity(cn->hdg, cn->spd, &cvx, &cvy);
    velocity(os->hdg, os->spd, &ovx, &ovy);
    double dx = cn->x - os->x, dy = cn->y - os->y; /* contact relative to ownship */
    double wx = cvx - ovx, wy = cvy - ovy;
    out->cpa = closest(dx, dy, wx, wy, tol, &out->tcpa);
    out->range = hypot(dx, dy);
    if (out->range > 0) {
        double rr = dx * dx + dy * dy;
        out->roc = -(dx * wx + dy * wy) / out->range;
        out->bearing_rate = (dy * wx - dx * wy) / rr / DEG;
        out->abs_bearing = bearing(dx, dy);
        out->rel_bearing = norm360(out->abs_bearing - os->hdg);
        out->cn_rel_bearing = norm360(bearing(-dx, -dy) - cn->hdg);
    }
    out->roc += 0.0; /* -0 + 0 is +0: no "-0" printed */
    out->bearing_rate += 0.0;
    sides(dx, dy, os->hdg, &out->cn_fore_of_os, &out->cn_aft_of_os, &out->cn_port_of_os, &out->cn_star_of_os);
    sides(-dx, -dy, cn->hdg, &out->os_fore_of_cn, &out->os_aft_of_cn, &out->os_port_of_cn, &out->os_star_of_cn);
    encounter e;
    meet(-dx, -dy, -wx, -wy, cn->hdg, &e); /* ownship about the contact */
    out->os_crosses_cn_bow = e.bow, out->os_crosses_cn_bow_dist = e.bow_d;
    out->os_crosses_cn_stern = e.stern, out->os_crosses_cn_stern_dist = e.stern_d;
    out->os_passes_cn_port = e.port, out->os_passes_cn_port_dist = e.port_d;
    out->os_passes_cn_star = e.star, out->os_passes_cn_star_dist = e.star_d;
    meet(dx, dy, wx, wy, os->hdg, &e); /* the contact about ownship */
    out->cn_crosses_os_bow = e.bow, out->cn_crosses_os_bow_dist = e.bow_d;
    out->cn_crosses_os_stern = e.stern, out->cn_crosses_os_stern_dist = e.stern_d;
    out->cn_passes_os_port = e.port, out->cn_passes_os_port_dist = e.port_d;
    out->cn_passes_os_star = e.star, out->cn_passes_os_star_dist = e.star_d;
    return KELP_OK;
}

int kelp_cpa_fast_init(kelp_cpa_fast *f, const kelp_cpa_vessel *cn, double osx, double osy, double tol)
{
    if (!f || !vessel_ok(cn) || !isfinite(osx) || !isfinite(osy) || isnan(tol)) return KELP_ERR_ARG;
    f->dx = cn->x - osx;
    f->dy = cn->y - osy;
    velocity(cn->hdg, cn->spd, &f->cvx, &f->cvy);
    f->tol = tol;
    return KELP_OK;
}

double kelp_cpa_fast_eval(const kelp_cpa_fast *f, double osh, double osv, double *tcpa)
{
    double ovx, ovy;
    velocity(osh, osv, &ovx, &ovy);
    return closest(f->dx, f->dy, f->cvx - ovx, f->cvy - ovy, f->tol, tcpa);
}

void kelp_cpa_unit(double hdg, double *ux, double *uy)
{
    sincosd(hdg, ux, uy);
}

double kelp_cpa_fast_eval_unit(const kelp_cpa_fast *f, double ux, double uy, double osv, double *tcpa)
{
    double v = osv > 0 ? osv : 0; /* as velocity() */
    double dx = f->dx, dy = f->dy, wx = f->cvx - v * ux, wy = f->cvy - v * uy;
    /* closest(), with the length as sqrt of the sum of squares (within an ulp of hypot, a
     * tenth of its cost; no overflow at any distance a helm sees) */
    double ww = wx * wx + wy * wy, t = 0.0;
    if (ww > 0.0) {
        t = -(dx * wx + dy * wy) / ww;
        if (t < 0.0) t = 0.0;
        if (f->tol > 0.0 && t > f->tol) t = f->tol;
    }
    if (tcpa) *tcpa = t;
    double ex = dx + wx * t, ey = dy + wy * t;
    return sqrt(ex * ex + ey * ey);
}
