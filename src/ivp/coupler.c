/* kelp IvP: the Coupler (seed 004 section 6.2.3; MOOS-IvP OF_Coupler semantics). */
#include <string.h>
#include "ivp_int.h"

/* Piece p after PDMap::normalize(0, w) given the function's min/max, written into q's variables
 * at..at+dim-1 (bounds, and slopes + 0.0); returns its constant. Written straight into the output
 * piece, no piece copies on the stack (kelp_ivp_couple runs under the helm's 1 KB firmware bound). */
static double put_norm(const kelp_ivp_piece *p, unsigned dim, double lo, double hi, double w, kelp_ivp_piece *q,
                       unsigned at)
{
    double er = hi - lo, radj = er > 0 ? w / er : 1.0, cst = p->cst;
    if (er > 0)
        cst = (cst + (0.0 - lo)) * radj;
    for (unsigned d = 0; d < dim; d++) {
        q->lo[at + d] = p->lo[d];
        q->hi[at + d] = p->hi[d];
        q->slope[at + d] = (er > 0 ? p->slope[d] * radj : p->slope[d]) + 0.0;
    }
    return cst;
}

int kelp_ivp_couple(const kelp_ivp_func *a, double wa, const kelp_ivp_func *b, double wb, bool normalize,
                    double nmin, double nmax, kelp_ivp_piece *store, size_t cap, kelp_ivp_func *out)
{
    if (!a || !b || !out || !(wa > 0) || !(wb > 0) || a->n == 0 || b->n == 0)
        return KELP_ERR_ARG;
    if (normalize && !(nmin < nmax))
        return KELP_ERR_ARG;
    for (unsigned d = 0; d < b->dom.dim; d++)
        if (kelp_ivp_domain_index(&a->dom, b->dom.var[d].name) >= 0)
            return KELP_ERR_ARG; /* variable sets must be disjoint */
    if (a->dom.dim + b->dom.dim > KELP_IVP_MAX_DIM)
        return KELP_ERR_NOSPACE;
    if (a->n > cap / b->n)
        return KELP_ERR_NOSPACE;
    double alo, ahi, blo, bhi;
    int rc;
    if ((rc = kelp_ivp_func_range(a, &alo, &ahi)) || (rc = kelp_ivp_func_range(b, &blo, &bhi)))
        return rc;
    /* the joint domain (a's variables, then b's) is built in out itself, not in a copy on the stack */
    if ((rc = kelp_ivp_func_init(out, &a->dom, store, cap)))
        return rc;
    for (unsigned d = 0; d < b->dom.dim; d++) {
        const kelp_ivp_var *v = &b->dom.var[d];
        if ((rc = kelp_ivp_domain_add(&out->dom, v->name, v->low, v->high, v->points)))
            return rc;
    }
    unsigned da = a->dom.dim, db = b->dom.dim;
    for (size_t i = 0; i < a->n; i++) {
        for (size_t j = 0; j < b->n; j++) {
            kelp_ivp_piece *q = &out->pcs[out->n++];
            memset(q, 0, sizeof *q);
            double ca = put_norm(&a->pcs[i], da, alo, ahi, wa, q, 0);
            q->cst = ca + put_norm(&b->pcs[j], db, blo, bhi, wb, q, da);
        }
    }
    if (normalize)
        return kelp_ivp_func_normalize(out, nmin, nmax - nmin);
    return 0;
}
