/* kelp CPA: the closest point of approach of two vessels on straight legs (core: pure
 * arithmetic, no allocation). Positions in local metres, headings in degrees true (0 north,
 * clockwise), speeds in m/s; both vessels hold course and speed from the moment given. */
#ifndef KELP_CPA_H
#define KELP_CPA_H

#ifdef __cplusplus
extern "C" {
#endif

/** The CPA range between contact (cnx, cny, cnh, cnv) and ownship (osx, osy, osh, osv)
 *  within tol seconds from now (tol <= 0: no time limit). If the two are opening, or do not
 *  move relative to each other, the CPA is the present range at time 0. *tcpa (if not NULL)
 *  receives the time of the CPA, in [0, tol]. */
double kelp_cpa_range(double cnx, double cny, double cnh, double cnv, double osx, double osy, double osh,
                      double osv, double tol, double *tcpa);

#ifdef __cplusplus
}
#endif

#endif
