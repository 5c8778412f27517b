/* kelp IvP: the Coupler (seed 004 section 6.2.3; MOOS-IvP OF_Coupler semantics). */
#include <string.h>
#include "ivp_int.h"

/* Coefficients of piece p after PDMap::normalize(0, w) given the function's min/max. */
static void norm_piece(const kelp_ivp_piece *p, unsigned dim, double lo, double hi, double w, kelp_ivp_piece *q)
{
    *q = *p;
    double er = hi - lo;
    if (er <= 0)
        return;
    double badj = 0.0 - lo, radj = w / er;
    q->cst += badj;
    for (unsigned d = 0; d < dim; d++)
        q->slope[d] *= radj;
    q->cst *= radj;
}

int kelp_ivp_couple(const kelp_ivp_func *a, double wa, const kelp_ivp_func *b, double wb, bool normalize,
                    double nmin, double nmax, kelp_ivp_piece *store, size_t cap, kelp_ivp_func *out)
{
    if (!a || !b || !out || !(wa > 0) || !(wb > 0) || a->n == 0 || b->n == 0)
        return KELP_ERR_ARG;
    if (normalize && !(nmin < nmax))
        return KELP_ERR_ARG;
    kelp_ivp_domain u = a->dom;
    for (unsigned d = 0; d < b->dom.dim; d++) {
        if (kelp_ivp_domain_index(&a->dom, b->dom.var[d].name) >= 0)
            return KELP_ERR_ARG; /* variable sets must be disjoint */
        const kelp_ivp_var *v = &b->dom.var[d];
        int rc = kelp_ivp_domain_add(&u, v->name, v->low, v->high, v->points);
        if (rc)
            return rc;
    }
    if (a->n > cap / b->n)
        return KELP_ERR_NOSPACE;
    int rc = kelp_ivp_func_init(out, &u, store, cap);
    if (rc)
        return rc;
    double alo, ahi, blo, bhi;
    if ((rc = kelp_ivp_func_range(a, &alo, &ahi)) || (rc = kelp_ivp_func_range(b, &blo, &bhi)))
        return rc;
    unsigned da = a->dom.dim, db = b->dom.dim;
    for (size_t i = 0; i < a->n; i++) {
        kelp_ivp_piece pa;
        norm_piece(&a->pcs[i], da, alo, ahi, wa, &pa);
        for (size_t j = 0; j < b->n; j++) {
            kelp_ivp_piece pb;
            norm_piece(&b->pcs[j], db, blo, bhi, wb, &pb);
            kelp_ivp_piece *q = &out->pcs[out->n++];
            memset(q, 0, sizeof *q);
            for (unsigned d = 0; d < da; d++) {
                q->lo[d] = pa.lo[d];
                q->hi[d] = pa.hi[d];
                q->slope[d] = pa.slope[d] + 0.0;
            }
            for (unsigned d = 0; d < db; d++) {
                q->lo[da + d] = pb.lo[d];
                q->hi[da + d] = pb.hi[d];
                q->slope[da + d] = 0.0 + pb.slope[d];
            }
            q->cst = pa.cst + pb.cst;
        }
    }
    if (normalize)
        return kelp_ivp_func_normalize(out, nmin, nmax - nmin);
    return 0;
}
