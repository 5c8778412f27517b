/* kelp CPA: closest point of approach on straight legs (see include/kelp/cpa.h). */
#include <math.h>
#include <kelp/cpa.h>

static const double DEG = 0.017453292519943295;

double kelp_cpa_range(double cnx, double cny, double cnh, double cnv, double osx, double osy, double osh,
                      double osv, double tol, double *tcpa)
{
    /* the contact relative to ownship: d(t) = d0 + w t */
    double dx = cnx - osx, dy = cny - osy;
    double wx = cnv * sin(cnh * DEG) - osv * sin(osh * DEG);
    double wy = cnv * cos(cnh * DEG) - osv * cos(osh * DEG);
    double ww = wx * wx + wy * wy, t = 0.0;
    if (ww > 0.0) {
        t = -(dx * wx + dy * wy) / ww;
        if (t < 0.0) t = 0.0;
        if (tol > 0.0 && t > tol) t = tol;
    }
    if (tcpa) *tcpa = t;
    return hypot(dx + wx * t, dy + wy * t);
}
