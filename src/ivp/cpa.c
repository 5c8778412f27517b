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

/* ---- sides, crossings and passings as MOOS-IvP 24.8 decides them ----
 * 24.8 (lib_geometry/CPAEngine.cpp) decides these from exact comparisons of bearings and of
 * signs, so a degenerate encounter (a vessel on the other's bow-stern line or beam, still
 * vessels, parallel tracks) is answered by how its arithmetic rounds. The quantities below are
 * computed the same way so that every tie falls the same side: bearings from an arctangent of
 * the absolute offsets (exact on the axes), angles wrapped by adding or removing whole turns,
 * degrees to radians with a 12-digit pi, the mover's heading taken in whole degrees (24.8
 * tabulates the mover's cosines per degree), the range from the expanded sum of squares. */

static const double PI_12 = 3.14159265359;          /* 24.8's pi for degrees to radians */
static const double PI_FULL = 3.14159265358979323846; /* and for radians to degrees */

/* [0,360) by whole turns (fmod is exact; a tiny negative angle gives 360, as 24.8's does) */
static double turn360(double a)
{
    a = fmod(a, 360.0);
    if (a < 0) a += 360.0;
    return a;
}

static double turn180(double a)
{
    a = turn360(a);
    return a > 180 ? a - 360.0 : a;
}

/* cosine of the angle between directions a and b (degrees, within a turn of each other),
 * exactly 0 when they are square */
static double cos_apart(double a, double b)
{
    double d = a - b;
    if (d > 180) d -= 360;
    else if (d < -180) d += 360;
    d = fabs(d);
    return d == 90 ? 0 : cos(d / 180.0 * PI_12);
}

/* bearing of (xb, yb) from (xa, ya): exact on the axes, else from the arctangent of the
 * absolute offsets measured from east (90) or west (270) */
static double bearing_from(double xa, double ya, double xb, double yb)
{
    if (xa == xb && ya == yb) return 0;
    if (ya == yb) return xa < xb ? 90.0 : 270.0;
    if (xa == xb) return ya < yb ? 0.0 : 180.0;
    double deg = atan(fabs(yb - ya) / fabs(xb - xa)) / PI_FULL * 180;
    double b;
    if (xb > xa) b = yb > ya ? -deg + 90 : deg + 90;
    else b = yb > ya ? deg + 270 : -deg + 270;
    return turn360(b);
}

/* A mover (a) about a reference vessel (b): what does not depend on the mover's velocity. */
typedef struct encounter {
    double range, gam, eps;   /* range; its parts square to and along b's heading line */
    double hb, vb;            /* b's heading [0,360) and speed (>= 0) */
    double tangent;           /* direction square to the line of sight (bearing of b + 90) */
    double vb_tangent;        /* b's speed along it */
    double per_metre;         /* degrees of bearing per metre of tangential travel */
    double theta_gam;         /* the direction from a's side of b's heading line towards it */
    bool on, bowline, sternline, beam, fore, aft, port, star;
} encounter;

static void encounter_init(encounter *e, const kelp_cpa_vessel *b, double ax, double ay)
{
    e->hb = turn360(b->hdg);
    e->vb = b->spd > 0 ? b->spd : 0;
    double from_b = bearing_from(b->x, b->y, ax, ay);
    double rel = turn360(from_b - e->hb); /* a's bearing relative to b's heading */
    e->tangent = turn360(bearing_from(ax, ay, b->x, b->y) + 90);
    double d = fabs(turn180(e->hb - e->tangent));
    e->vb_tangent = d != 90 ? cos(d / 180.0 * PI_12) * e->vb : 0;
    double k0 = ay * ay;
    k0 += ax * ax;
    k0 += (-2.0) * ay * b->y;
    k0 += (-2.0) * ax * b->x;
    k0 += b->y * b->y;
    k0 += b->x * b->x;
    e->range = sqrt(k0);
    e->per_metre = 360 / (2 * e->range * PI_12);
    e->on = ax == b->x && ay == b->y;
    e->bowline = from_b == turn360(e->hb);
    e->sternline = !e->bowline && from_b == turn360(e->hb - 180);
    e->fore = !e->on && !(rel > 90 && rel < 270);
    e->aft = !e->on && rel >= 90 && rel <= 270;
    e->port = !e->on && (rel == 0 || (rel >= 180 && rel < 360));
    e->star = !e->on && rel >= 0 && rel <= 180;
    e->beam = e->on || (e->fore && e->aft);
    e->theta_gam = e->port ? turn360(e->hb + 90) : turn360(e->hb - 90);
    double r = rel > 180 ? rel - 360 : rel;
    r = fabs(r);
    if (r == 0 || r == 180) {
        e->gam = 0;
        e->eps = e->range;
    } else {
        e->gam = e->range * cos((90 - r) / 180.0 * PI_12);
        e->eps = sqrt(e->range * e->range - e->gam * e->gam);
    }
}

/* a distance as reported: the distance, 0 when it does not happen */
static double reported(double x) { return x > 0 ? x : 0; }

/* How the mover, heading h at speed v, meets b. */
static void encounter_meet(const encounter *e, double h, double v, bool *bow, double *bow_d, bool *stern,
                           double *stern_d, bool *port, double *port_d, bool *star, double *star_d)
{
    v = v > 0 ? v : 0;
    double hd = floor(turn360(h));
    if (hd >= 360) hd = 0;
    double g = cos_apart(hd, e->theta_gam) * v;    /* speed towards b's heading line */
    double c = cos_apart(hd, e->hb) * v;           /* speed along b's heading */
    double rate = (cos_apart(hd, e->tangent) * -v + e->vb_tangent) * e->per_metre; /* bearing rate */

    /* crossing b's heading line: the side it crosses from the sign of the bearing rate */
    *bow = e->sternline || (v > 0 && g > 0 && (e->port ? rate >= 0 : rate <= 0));
    *stern = e->sternline || (v > 0 && g > 0 && (e->port ? rate <= 0 : rate >= 0));
    /* where: from the time to reach the line at the speed towards it */
    double xb = -1, xs = -1;
    if (e->bowline) xb = e->range;
    else if (!e->sternline && !e->on && g > 0) {
        double t = e->gam / g, b_ahead = t * e->vb, a_ahead = t * c;
        xb = a_ahead - b_ahead;
        xb = e->fore ? xb + e->eps : xb - e->eps;
    }
    if (e->sternline) xs = e->range;
    else if (!e->bowline && !e->on && g > 0) {
        double t = e->gam / g, b_ahead = t * e->vb, a_ahead = t * c;
        xs = b_ahead;
        xs = e->fore ? xs - e->eps : xs + e->eps;
        xs -= a_ahead;
    }
    *bow_d = reported(xb);
    *stern_d = reported(xs);

    /* passing b's beam: the closing speed along b's heading line */
    double closing = e->aft ? c - e->vb : e->vb - c;
    bool passes = e->beam || closing > 0;
    bool pp = false;
    if (!e->on && passes) pp = e->fore && e->aft ? e->port : e->aft ? rate > 0 : rate < 0;
    *port = pp;
    *star = !e->on && passes && !pp;
    double xp = -1, xt = -1;
    if (e->on) {
    } else if (e->beam) {
        if (e->port) xp = e->range;
        else if (e->star) xt = e->range;
    } else if (closing > 0) {
        double across = e->eps / closing * g; /* travel towards b's line until abeam */
        if (e->port && across <= e->gam) xp = e->gam - across;
        if (e->star && across > e->gam) xp = across - e->gam;
        if (e->star && across <= e->gam) xt = e->gam - across;
        if (e->port && across > e->gam) xt = across - e->gam;
    }
    *port_d = reported(xp);
    *star_d = reported(xt);
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
    encounter e;
    encounter_init(&e, cn, os->x, os->y); /* ownship about the contact */
    out->os_fore_of_cn = e.fore, out->os_aft_of_cn = e.aft, out->os_port_of_cn = e.port, out->os_star_of_cn = e.star;
    encounter_meet(&e, os->hdg, os->spd, &out->os_crosses_cn_bow, &out->os_crosses_cn_bow_dist,
                   &out->os_crosses_cn_stern, &out->os_crosses_cn_stern_dist, &out->os_passes_cn_port,
                   &out->os_passes_cn_port_dist, &out->os_passes_cn_star, &out->os_passes_cn_star_dist);
    encounter_init(&e, os, cn->x, cn->y); /* the contact about ownship */
    out->cn_fore_of_os = e.fore, out->cn_aft_of_os = e.aft, out->cn_port_of_os = e.port, out->cn_star_of_os = e.star;
    encounter_meet(&e, cn->hdg, cn->spd, &out->cn_crosses_os_bow, &out->cn_crosses_os_bow_dist,
                   &out->cn_crosses_os_stern, &out->cn_crosses_os_stern_dist, &out->cn_passes_os_port,
                   &out->cn_passes_os_port_dist, &out->cn_passes_os_star, &out->cn_passes_os_star_dist);
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
