/* kelp IvP: domains, piecewise-linear IvP functions, the IvPBuild tools (ZAIC_PEAK, ZAIC_LEQ,
 * ZAIC_HEQ, Reflector, Coupler) and the branch-and-bound IvP solver.
 *
 * Follows MOOS-IvP's IvP model (Benjamin et al., MIT-CSAIL-TR-2009-037, chapters 6-9).
 *
 * Everything here is allocation-free: the caller owns every struct and passes piece and work
 * storage, sized with the *_max_pieces / *_work_size queries. Too little storage gives
 * KELP_ERR_NOSPACE, never a truncated function. Nothing keeps global state; every call is
 * re-entrant on distinct objects. Builders (ZAIC, Reflector) follow the IvPBuild guide's error model (MIT-CSAIL-TR-2009-037):
 * a fatal configuration error sets ok=false for good and extraction then fails with
 * KELP_ERR_STATE; warnings accumulate in warn[] (fatal or not, joined with " # ").
 * The text parsers and the solver say why they failed through a kelp_diag (err.h; NULL
 * allowed, first error wins): the message names the bad token, "what 'token'".
 *
 * Representation (as in MOOS-IvP's PDMap/IvPBox): a piece is a box of inclusive domain INDEX
 * bounds, one [lo,hi] per variable of the function's domain, with the linear interior
 *     value(ix) = cst + sum_d slope[d] * ix[d]          (ix[d] = index, not native value)
 * Pieces are kept in a stored order, which the solver uses to break ties.
 */
#ifndef KELP_IVP_H
#define KELP_IVP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ domain */

/** One decision variable: low..high with `points` evenly spaced points (both ends included). */
typedef struct kelp_ivp_var {
    char name[KELP_IVP_MAX_VARNAME];
    double low, high;
    double delta;       /**< (high-low)/(points-1); 0 when points == 1 */
    uint32_t points;
} kelp_ivp_var;

/** An ordered set of variables (IvPDomain). dim == 0 is the null domain. */
typedef struct kelp_ivp_domain {
    unsigned dim;
    kelp_ivp_var var[KELP_IVP_MAX_DIM];
} kelp_ivp_domain;

/** How a native value snaps to an index (IvPDomain::getDiscreteVal): below low -> 0, above
 * high -> points-1; in between FLOOR truncates, CEIL rounds up, NEAREST rounds to the nearest
 * point with an exact half going DOWN (as MOOS-IvP does). */
typedef enum kelp_ivp_snap { KELP_IVP_SNAP_FLOOR = 0, KELP_IVP_SNAP_CEIL = 1, KELP_IVP_SNAP_NEAREST = 2 } kelp_ivp_snap;

void kelp_ivp_domain_init(kelp_ivp_domain *d);
/** Append a variable. KELP_ERR_EXISTS duplicate name, KELP_ERR_RANGE low>high, points<1,
 * points==1 with high!=low, or a non-finite bound; KELP_ERR_NOSPACE when dim is full;
 * KELP_ERR_ARG for an empty or too long name. */
KELP_MUST_CHECK int kelp_ivp_domain_add(kelp_ivp_domain *d, const char *name, double low, double high, uint32_t points);
/** Index of the named variable, or -1. */
int kelp_ivp_domain_index(const kelp_ivp_domain *d, const char *name);
/** Native value of index ix of variable v: low + ix*delta. */
double kelp_ivp_domain_value(const kelp_ivp_domain *d, unsigned v, uint32_t ix);
/** Index for a native value (see kelp_ivp_snap). */
uint32_t kelp_ivp_domain_snap(const kelp_ivp_domain *d, unsigned v, double val, kelp_ivp_snap mode);
/** Product of the points of all variables (581760 for course:0:359:360,speed:0:3:16,depth:0:500:101). */
double kelp_ivp_domain_total(const kelp_ivp_domain *d);
/** subDomain(): the named variables (comma separated, in the order named). Any unknown name
 * gives the null domain (out->dim == 0) and KELP_ERR_NOTFOUND. */
KELP_MUST_CHECK int kelp_ivp_domain_sub(const kelp_ivp_domain *d, const char *names, kelp_ivp_domain *out);
/** True when every variable of sub is in d with exactly equal low/high/points (proper sub-domain). */
bool kelp_ivp_domain_is_sub(const kelp_ivp_domain *sub, const kelp_ivp_domain *d);
/** Parse "name:low:high:points[,name:low:high:points]..." (blanks around tokens allowed). */
KELP_MUST_CHECK int kelp_ivp_domain_parse(kelp_ivp_domain *d, const char *s, kelp_diag *diag);
/** The same over the first len bytes of s (no NUL needed). */
KELP_MUST_CHECK int kelp_ivp_domain_parse_n(kelp_ivp_domain *d, const char *s, size_t len, kelp_diag *diag);

/* ------------------------------------------------------------------ functions */

typedef struct kelp_ivp_piece {
    int32_t lo[KELP_IVP_MAX_DIM];     /**< inclusive index bounds per function variable */
    int32_t hi[KELP_IVP_MAX_DIM];
    double slope[KELP_IVP_MAX_DIM];   /**< per index step */
    double cst;                       /**< value at index 0 of every variable */
} kelp_ivp_piece;

/** An IvP function: pieces over its own domain, plus a priority weight. */
typedef struct kelp_ivp_func {
    kelp_ivp_domain dom;
    kelp_ivp_piece *pcs;   /**< caller storage */
    size_t n, cap;
    double pwt;            /**< priority weight, default 100 */
} kelp_ivp_func;

/** Start an empty function over dom using caller storage for cap pieces. */
KELP_MUST_CHECK int kelp_ivp_func_init(kelp_ivp_func *f, const kelp_ivp_domain *dom, kelp_ivp_piece *store, size_t cap);
/** Append a piece (bounds per function variable, inclusive; checked against the domain). */
KELP_MUST_CHECK int kelp_ivp_func_add(kelp_ivp_func *f, const int32_t *lo, const int32_t *hi, const double *slope, double cst);
/** Value of a piece at its max corner, per dimension the high end when slope >= 0. */
double kelp_ivp_piece_max(const kelp_ivp_piece *p, unsigned dim);
double kelp_ivp_piece_min(const kelp_ivp_piece *p, unsigned dim);
/** Evaluate at index point ix[dim]: the first piece (stored order) containing it.
 * KELP_ERR_NOTFOUND when no piece covers it, KELP_ERR_RANGE when ix is outside the domain. */
KELP_MUST_CHECK int kelp_ivp_func_eval(const kelp_ivp_func *f, const uint32_t *ix, double *out);
/** Minimum and maximum over all pieces (PDMap::getMinWT/getMaxWT). KELP_ERR_EMPTY for no pieces. */
KELP_MUST_CHECK int kelp_ivp_func_range(const kelp_ivp_func *f, double *min, double *max);
/** Map [min,max] onto [base, base+range] (no-op for a flat function), exactly as PDMap::normalize:
 * cst += base-min, then every coefficient *= range/(max-min). */
KELP_MUST_CHECK int kelp_ivp_func_normalize(kelp_ivp_func *f, double base, double range);
/** The function as the IPF string of MOOS-IvP's BHV_IPF (its FunctionEncoder's layout, see
 *  src/ivp/ipf.c): context "<iteration>:<behaviour>", gel the grid element box's upper index per
 *  dimension (NULL: each variable's last index). @return the length, KELP_ERR_NOSPACE when it
 *  does not fit in cap (buf then holds a truncated prefix), KELP_ERR_ARG. */
KELP_MUST_CHECK int kelp_ivp_func_to_ipf(const kelp_ivp_func *f, const char *context, const int32_t *gel, char *buf,
                                         size_t cap);
/** Multiply every coefficient by w (PDMap::applyWeight). */
void kelp_ivp_func_scale(kelp_ivp_func *f, double w);
/** Align to a larger domain in place: variables are re-ordered to big's order and a variable the
 * function lacks spans its full range with slope 0. KELP_ERR_NOTFOUND if a function variable is
 * missing from big, KELP_ERR_RANGE if its extents differ. */
KELP_MUST_CHECK int kelp_ivp_func_align(kelp_ivp_func *f, const kelp_ivp_domain *big);
/** Check that the pieces tile the domain: every point covered exactly once (each piece inside
 *  the domain, no two sharing a point, volumes adding up to the domain's). Cost: O(pieces^2). */
bool kelp_ivp_func_tiles(const kelp_ivp_func *f);

/* ------------------------------------------------------------------ ZAIC_PEAK / LEQ / HEQ */

typedef struct kelp_ivp_zaic_comp {
    double summit, peakwidth, basewidth, summitdelta, minutil, maxutil;
} kelp_ivp_zaic_comp;

typedef struct kelp_ivp_zaic_peak {
    kelp_ivp_domain dom;     /**< one-variable sub-domain */
    kelp_ivp_zaic_comp comp[KELP_IVP_MAX_COMPONENTS];
    unsigned ncomp;
    bool wrap;               /**< valuewrap, default false */
    bool insist;             /**< summitinsist, default true */
    bool ok;                 /**< false after a fatal configuration error (irreversible) */
    char warn[KELP_IVP_MAX_WARN];
} kelp_ivp_zaic_peak;

/** ZAIC_PEAK(domain, var). Component 0: summit=0, widths 0, summitdelta 0, min/max 0/100.
 * A missing variable is fatal (ok=false, returns KELP_ERR_NOTFOUND). */
KELP_MUST_CHECK int kelp_ivp_zaic_peak_init(kelp_ivp_zaic_peak *z, const kelp_ivp_domain *dom, const char *var);
/** addComponent(): returns the new index (1 on the first call) or KELP_ERR_NOSPACE (fatal).
 * New component: summit=0, peakwidth=0, basewidth=0, summitdelta=50, minutil=0, maxutil=100. */
KELP_MUST_CHECK int kelp_ivp_zaic_peak_add_component(kelp_ivp_zaic_peak *z);
/* Setters return 0 or a negative code; a bad index is fatal (KELP_ERR_RANGE). A summit outside the
 * domain is kept as given (so summitinsist can act) with a warning. Negative widths are clipped to 0
 * with a warning. summitdelta < 0 and min >= max are fatal; summitdelta > max-min is clipped. */
KELP_MUST_CHECK int kelp_ivp_zaic_peak_set_summit(kelp_ivp_zaic_peak *z, double v, unsigned idx);
KELP_MUST_CHECK int kelp_ivp_zaic_peak_set_peakwidth(kelp_ivp_zaic_peak *z, double v, unsigned idx);
KELP_MUST_CHECK int kelp_ivp_zaic_peak_set_basewidth(kelp_ivp_zaic_peak *z, double v, unsigned idx);
KELP_MUST_CHECK int kelp_ivp_zaic_peak_set_summitdelta(kelp_ivp_zaic_peak *z, double v, unsigned idx);
KELP_MUST_CHECK int kelp_ivp_zaic_peak_set_minmaxutil(kelp_ivp_zaic_peak *z, double min, double max, unsigned idx);
/** setParams(): summit, widths, then min/max, then summitdelta (clipped to the new range). */
KELP_MUST_CHECK int kelp_ivp_zaic_peak_set_params(kelp_ivp_zaic_peak *z, double summit, double pwidth, double bwidth,
                                  double sdelta, double minutil, double maxutil, unsigned idx);
/** Raw (unpieced) value of index ix: components combined by max (use_max) or sum. No insist. */
double kelp_ivp_zaic_peak_value(const kelp_ivp_zaic_peak *z, uint32_t ix, bool use_max);
/** Upper bound on the pieces extraction makes (the number of domain points). */
size_t kelp_ivp_zaic_peak_max_pieces(const kelp_ivp_zaic_peak *z);
/** Doubles of work storage extraction needs (the number of domain points). */
size_t kelp_ivp_zaic_peak_work_len(const kelp_ivp_zaic_peak *z);
/** extractIvPFunction(use_max): evaluate every point, apply summitinsist per component, then cut
 * the values into linear runs (MOOS-IvP's rule: tolerance 0.001, and a break where the slope
 * changes sign). KELP_ERR_STATE after a fatal error; KELP_ERR_NOSPACE for small storage. */
KELP_MUST_CHECK int kelp_ivp_zaic_peak_extract(const kelp_ivp_zaic_peak *z, bool use_max, double *work, size_t work_len,
                                               kelp_ivp_piece *store, size_t cap, kelp_ivp_func *out);

typedef enum kelp_ivp_zaic_kind { KELP_IVP_ZAIC_LEQ = 0, KELP_IVP_ZAIC_HEQ = 1 } kelp_ivp_zaic_kind;

/** ZAIC_LEQ (max utility for x <= summit) and ZAIC_HEQ (for x >= summit). */
typedef struct kelp_ivp_zaic_hleq {
    kelp_ivp_domain dom;
    kelp_ivp_zaic_kind kind;
    double summit, basewidth, minutil, maxutil;
    double summitdelta;      /**< optional spike of maxutil+summitdelta at the summit point (newer MOOS-IvP); default 0 */
    bool ok;
    char warn[KELP_IVP_MAX_WARN];
} kelp_ivp_zaic_hleq;

#define KELP_IVP_ZAIC_HLEQ_MAX_PIECES 4

KELP_MUST_CHECK int kelp_ivp_zaic_hleq_init(kelp_ivp_zaic_hleq *z, kelp_ivp_zaic_kind kind, const kelp_ivp_domain *dom, const char *var);
/** Always succeeds; a summit outside the domain is clipped to it with a warning. */
KELP_MUST_CHECK int kelp_ivp_zaic_hleq_set_summit(kelp_ivp_zaic_hleq *z, double v);
/** basewidth < 0 is fatal. */
KELP_MUST_CHECK int kelp_ivp_zaic_hleq_set_basewidth(kelp_ivp_zaic_hleq *z, double v);
/** min >= max is fatal. */
KELP_MUST_CHECK int kelp_ivp_zaic_hleq_set_minmaxutil(kelp_ivp_zaic_hleq *z, double min, double max);
/** summitdelta < 0 is clipped to 0 with a warning. */
KELP_MUST_CHECK int kelp_ivp_zaic_hleq_set_summitdelta(kelp_ivp_zaic_hleq *z, double v);
/** 2 pieces when basewidth rounds to 0 index steps, else 3 (fewer at the domain edges), +1 with summitdelta. */
KELP_MUST_CHECK int kelp_ivp_zaic_hleq_extract(const kelp_ivp_zaic_hleq *z, kelp_ivp_piece *store, size_t cap, kelp_ivp_func *out);

/* ------------------------------------------------------------------ Coupler */

/** OF_Coupler::couple(a, b, wa, wb): a and b over disjoint variables. Each input is mapped to
 * [0,wa] / [0,wb] (flat inputs are left as they are), the pieces are crossed (a's pieces outer,
 * b's inner; n_a*n_b pieces over a's variables then b's), and the result is normalised to
 * [nmin,nmax] when normalize is true (MOOS-IvP default [0,100]). Inputs are not modified.
 * KELP_ERR_ARG for a weight <= 0 or shared variables, KELP_ERR_NOSPACE for cap < n_a*n_b. */
KELP_MUST_CHECK int kelp_ivp_couple(const kelp_ivp_func *a, double wa, const kelp_ivp_func *b, double wb, bool normalize,
                                    double nmin, double nmax, kelp_ivp_piece *store, size_t cap, kelp_ivp_func *out);

/* ------------------------------------------------------------------ piece shapes, points, regions */

/** Parse an IvPBuild guide ch. 9 string "discrete @ x:5,y:5" / "native @ x:5,y:25" as a piece SHAPE (edge
 * lengths in points per variable; native lengths are divided by delta and rounded, .5 up).
 * Every domain variable must be given exactly once. Result: edge[d] >= 1 points. */
KELP_MUST_CHECK int kelp_ivp_parse_shape(const kelp_ivp_domain *d, const char *s, uint32_t *edge, kelp_diag *diag);
/** Parse a POINT ("discrete @ x:22,y:12" index, "native @ x:22,y:10" nearest point). */
KELP_MUST_CHECK int kelp_ivp_parse_point(const kelp_ivp_domain *d, const char *s, uint32_t *ix, kelp_diag *diag);
/** Parse a REGION ("native @ x:10:24,y:-25:20", native bounds are strict: lo -> first point >= lo,
 * hi -> last point <= hi; extents beyond the domain are clipped). KELP_ERR_RANGE for an empty region. */
KELP_MUST_CHECK int kelp_ivp_parse_region(const kelp_ivp_domain *d, const char *s, int32_t *lo, int32_t *hi, kelp_diag *diag);

/* ------------------------------------------------------------------ Reflector */

/** The underlying function (AOF): native values in domain variable order. */
typedef double (*kelp_ivp_aof_fn)(const double *pt, void *user);
/** Optional companion of an AOF: its values along one line of the domain, out[i] = the AOF at
 *  pt with variable d set to x[i] (i < n; pt's other coordinates fixed). It must give exactly
 *  the AOF's values; it lets an AOF do once per line what it would otherwise redo per point. */
typedef void (*kelp_ivp_aof_line_fn)(const double *pt, unsigned d, const double *x, unsigned n, double *out, void *user);

/** Tiles of one row a line sampler is asked for at a time (the Reflector's own scratch). */
#define KELP_IVP_LINE_CHUNK 8

typedef struct kelp_ivp_reflector {
    kelp_ivp_domain dom;
    kelp_ivp_aof_fn aof;
    void *aof_user;
    kelp_ivp_aof_line_fn aof_line;   /**< NULL unless kelp_ivp_reflector_set_line */
    int uniform_amount;              /**< <1: not given */
    bool have_uniform_piece;
    uint32_t uniform_piece[KELP_IVP_MAX_DIM];
    bool strict_range;               /**< default true */
    unsigned nrefine;
    bool refine_pending;             /**< a refine_region waits for its refine_piece */
    int32_t refine_lo[KELP_IVP_MAX_REFINE][KELP_IVP_MAX_DIM];
    int32_t refine_hi[KELP_IVP_MAX_REFINE][KELP_IVP_MAX_DIM];
    uint32_t refine_piece[KELP_IVP_MAX_REFINE][KELP_IVP_MAX_DIM];
    int smart_amount, smart_percent; /**< <0: not given */
    double smart_thresh;             /**< default 0 (no early stop unless scores fall below it) */
    bool have_smart_thresh;
    bool auto_peak;
    int auto_peak_max_pcs;           /**< <=0: no limit */
    bool ok;
    char warn[KELP_IVP_MAX_WARN];
    kelp_diag ws_diag;               /**< workspace of kelp_ivp_reflector_set_param (a parse's reason) */
    double ws_line[8 * KELP_IVP_LINE_CHUNK]; /**< workspace of create's line sampling */
} kelp_ivp_reflector;

/** Priority-queue entry used in the Reflector's work storage. */
typedef struct kelp_ivp_pq_entry { double key; uint32_t piece; } kelp_ivp_pq_entry;

KELP_MUST_CHECK int kelp_ivp_reflector_init(kelp_ivp_reflector *r, const kelp_ivp_domain *dom, kelp_ivp_aof_fn aof, void *user);
/** Give the AOF's line sampler (after init). create then samples the uniform pieces of a 2-D
 *  domain a row at a time through it (the same points, the same values, the same pieces);
 *  refinement and scored builds still use the AOF point by point. */
void kelp_ivp_reflector_set_line(kelp_ivp_reflector *r, kelp_ivp_aof_line_fn line);
/** setParam(name, value) with the IvPBuild guide's names: uniform_amount, uniform_piece, strict_range,
 * refine_region, refine_piece, refine_point (accepted and validated; it does not change the build),
 * smart_amount, smart_percent, smart_thresh, auto_peak, auto_peak_max_pcs. Names and values are
 * case-insensitive and trimmed. A bad name or value is fatal (ok=false) and returns
 * KELP_ERR_NOTFOUND / KELP_ERR_PARSE / KELP_ERR_RANGE / KELP_ERR_STATE (pairing). */
KELP_MUST_CHECK int kelp_ivp_reflector_set_param(kelp_ivp_reflector *r, const char *name, const char *value);
KELP_MUST_CHECK int kelp_ivp_reflector_set_paramf(kelp_ivp_reflector *r, const char *name, double value);
/** The uniform piece the piece-count heuristic (Listing 26, integer ratio) picks for `amount`. */
void kelp_ivp_uniform_piece(const kelp_ivp_domain *d, int amount, uint32_t *edge);
/** Upper bound on the pieces create() makes with these arguments (see create); when auto-peak
 * has no limit, the bound is the number of domain points. */
size_t kelp_ivp_reflector_max_pieces(const kelp_ivp_reflector *r, int uniform_amount, int smart_amount);
/** Work entries (kelp_ivp_pq_entry) create() needs for a given piece capacity: cap. */
size_t kelp_ivp_reflector_work_len(size_t cap);
/** create(uniform_amount, smart_amount, smart_thresh): arguments >= 1 (>= 0 for smart_amount,
 * smart_thresh used when smart_amount >= 0) override setParam values; pass -1 to use them.
 * Runs the reflector-script: uniform, directed refinement, smart refinement, auto-peak.
 * The result is NOT normalised. Returns the piece count (>0) or a negative code. */
KELP_MUST_CHECK int kelp_ivp_reflector_create(kelp_ivp_reflector *r, int uniform_amount, int smart_amount, double smart_thresh,
                                              kelp_ivp_piece *store, size_t cap, kelp_ivp_pq_entry *work, size_t work_len,
                                              kelp_ivp_func *out);

/* ------------------------------------------------------------------ solver */

typedef struct kelp_ivp_problem {
    kelp_ivp_domain dom;
    const kelp_ivp_func *f[KELP_IVP_MAX_FUNCS];
    unsigned nf;
    kelp_diag diag;                  /**< why problem_add / solve failed (cleared by problem_init) */
} kelp_ivp_problem;

typedef struct kelp_ivp_result {
    uint32_t ix[KELP_IVP_MAX_DIM];   /**< decision index per problem variable */
    double val[KELP_IVP_MAX_DIM];    /**< native decision value */
    double value;                    /**< objective: sum of weighted (normalised) function values */
    unsigned long leaves;            /**< leaf nodes visited (diagnostic) */
} kelp_ivp_result;

void kelp_ivp_problem_init(kelp_ivp_problem *p, const kelp_ivp_domain *dom);
/** Add a function in helm order. Functions with pwt <= 0 are ignored (returns 0). Every function
 * variable must be a problem variable with equal extents (else KELP_ERR_NOTFOUND/RANGE). The
 * function is referenced, not copied, and must outlive the solve; it is never modified. */
KELP_MUST_CHECK int kelp_ivp_problem_add(kelp_ivp_problem *p, const kelp_ivp_func *f);
#ifndef KELP_IVP_SOLVE_GRID_MAX
#define KELP_IVP_SOLVE_GRID_MAX 65536 /**< domain points up to which the solver can use its grid path */
#endif
KELP_STATIC_ASSERT(KELP_IVP_MAX_FUNCS < 65535, "the grid path counts functions in 16 bits");

/** Bytes of work storage kelp_ivp_solve needs (the branch-and-bound search alone). */
size_t kelp_ivp_solve_work_size(const kelp_ivp_problem *p);
/** Bytes with which kelp_ivp_solve takes its grid path: a domain of at most
 * KELP_IVP_SOLVE_GRID_MAX points is evaluated point by point first (about 20 bytes per point
 * plus 4 per piece), and the search then follows only the boxes that hold an optimal point.
 * Same answer as the search alone, at a cost near one evaluation of every function at every
 * point. Larger domains: equal to kelp_ivp_solve_work_size. */
size_t kelp_ivp_solve_grid_work_size(const kelp_ivp_problem *p);
/** Maximise sum_i pwt_i * f_i (f_i normalised to [0,100] first when its range exceeds 100) by
 * branch and bound, choosing exactly what MOOS-IvP's IvPProblem chooses: the first optimum in
 * depth-first order (first function's pieces in stored order, then the next function's
 * intersecting pieces in stored order, ...), replaced only by a strictly better leaf; inside the
 * winning box, per variable, the high end when the summed slope is >= 0 else the low end.
 * KELP_ERR_EMPTY with no (positive-weight) functions, KELP_ERR_INFEASIBLE when no point is covered
 * by every function, KELP_ERR_NOSPACE when work is too small. */
KELP_MUST_CHECK int kelp_ivp_solve(kelp_ivp_problem *p, void *work, size_t work_size, kelp_ivp_result *res);

/* ------------------------------------------------------------------ text forms (kelp-ivp) */

/** A parsed SPEC: peak(...)[+peak(...)...], leq(...) or heq(...). */
typedef struct kelp_ivp_spec {
    enum { KELP_IVP_SPEC_PEAK, KELP_IVP_SPEC_LEQ, KELP_IVP_SPEC_HEQ } kind;
    unsigned ncomp;
    kelp_ivp_zaic_comp comp[KELP_IVP_MAX_COMPONENTS];
    bool wrap, insist, sum;
} kelp_ivp_spec;

/** Parse a SPEC string (see kelp-ivp). Unknown keys, repeated keys, bad numbers, flags on a later
 * component and trailing text are errors naming the token. Omitted keys take the builder
 * defaults (summitdelta 50 on added peak components, as the IvPBuild guide's addComponent). The flags
 * insist/wrap/sum default to off in the text form. */
KELP_MUST_CHECK int kelp_ivp_spec_parse(kelp_ivp_spec *sp, const char *s, kelp_diag *diag);
size_t kelp_ivp_spec_max_pieces(const kelp_ivp_spec *sp, const kelp_ivp_domain *dom, const char *var);
/** The builder a spec needs, as the caller's workspace (a ZAIC_PEAK is some 900 bytes, a
 *  ZAIC_LEQ/HEQ some 550: kept off the stack). */
typedef union kelp_ivp_spec_ws {
    kelp_ivp_zaic_peak peak;
    kelp_ivp_zaic_hleq hleq;
} kelp_ivp_spec_ws;
/** Build the spec's function over variable var of dom. work: kelp_ivp_spec_work_len doubles;
 *  ws: the builder's workspace. */
KELP_MUST_CHECK int kelp_ivp_spec_build(const kelp_ivp_spec *sp, const kelp_ivp_domain *dom, const char *var, double *work,
                                        size_t work_len, kelp_ivp_spec_ws *ws, kelp_ivp_piece *store, size_t cap,
                                        kelp_ivp_func *out, kelp_diag *diag);

/** One function line of a solve FILE. */
typedef struct kelp_ivp_fileline {
    enum { KELP_IVP_LINE_COUPLE, KELP_IVP_LINE_SPEC, KELP_IVP_LINE_RAW } kind;
    double pwt;
    double wc, ws;                    /**< couple weights */
    kelp_ivp_spec a, b;               /**< couple: a = course spec, b = speed spec; spec: a */
    char var[KELP_IVP_MAX_VARNAME];   /**< spec: the variable */
    unsigned nvars;                   /**< raw: variables spanned, in order */
    int vars[KELP_IVP_MAX_DIM];       /**< raw: problem variable index of each */
    unsigned long npieces;            /**< raw: piece lines that follow */
    char ws_spec[512];                /**< workspace: a SPEC token's text while it is parsed */
} kelp_ivp_fileline;

/** Parse "domain DOMAIN" (the first non-blank, non-# line of a FILE). */
KELP_MUST_CHECK int kelp_ivp_file_domain(const char *line, kelp_ivp_domain *dom, kelp_diag *diag);
/** Parse one function line "pwt W couple WC WS CRS SPD" | "pwt W VAR SPEC" | "pwt W raw VARS N". */
KELP_MUST_CHECK int kelp_ivp_file_line(const char *line, const kelp_ivp_domain *dom, kelp_ivp_fileline *fl,
                                       kelp_diag *diag);
/** Parse one raw piece line "lo hi [lo hi ...] slope [slope ...] constant" for nvars variables
 * and append it (translated to the function's variables, which are fl->vars) to f. */
KELP_MUST_CHECK int kelp_ivp_file_piece(const char *line, unsigned nvars, kelp_ivp_func *f, kelp_diag *diag);
/** The two variables a couple line applies to: "course" and "speed" when the domain has both,
 * else variables 0 and 1. KELP_ERR_RANGE when the domain has fewer than two variables. */
KELP_MUST_CHECK int kelp_ivp_couple_vars(const kelp_ivp_domain *dom, int *vc, int *vs);

#ifdef __cplusplus
}
#endif

#endif
