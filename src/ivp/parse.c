/* kelp IvP: text forms shared by kelp-ivp, the tests and the fuzz target:
 * SPEC strings, solve FILE lines, and the seed's shape / point / region strings (ch. 9.1). */
#include <string.h>
#include <math.h>
#include "ivp_int.h"

/* ------------------------------------------------------------------ SPEC */

typedef struct {
    const char *s;
    size_t n;
} span;

static int parse_num(span t, double *v, kelp_diag *diag, const char *what)
{
    if (ivp_parse_double(t.s, t.n, v))
        return ivp_fail(diag, KELP_ERR_PARSE, what, t.s, t.n);
    return 0;
}

/* One "kind(args)" component at *p; advances *p past ')'. */
static int parse_component(const char **pp, kelp_ivp_spec *sp, unsigned ci, kelp_diag *diag)
{
    const char *p = ivp_skip_ws(*pp);
    const char *k0 = p;
    while ((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z'))
        p++;
    size_t kn = (size_t)(p - k0);
    int kind;
    if (ivp_word_eq(k0, kn, "peak"))
        kind = KELP_IVP_SPEC_PEAK;
    else if (ivp_word_eq(k0, kn, "leq"))
        kind = KELP_IVP_SPEC_LEQ;
    else if (ivp_word_eq(k0, kn, "heq"))
        kind = KELP_IVP_SPEC_HEQ;
    else {
        size_t tl = kn ? kn : strcspn(k0, "(+ ");
        return ivp_fail(diag, KELP_ERR_PARSE, "spec: unknown function kind (want peak, leq or heq):", k0, tl ? tl : strlen(k0));
    }
    if (ci == 0)
        sp->kind = kind;
    else if (kind != KELP_IVP_SPEC_PEAK || sp->kind != KELP_IVP_SPEC_PEAK)
        return ivp_fail(diag, KELP_ERR_PARSE, "spec: only peak components can be joined with '+', at", k0, kn);
    p = ivp_skip_ws(p);
    if (*p != '(')
        return ivp_fail(diag, KELP_ERR_PARSE, "spec: expected '(' after", k0, kn);
    p++;
    const char *close = strchr(p, ')');
    if (!close)
        return ivp_fail(diag, KELP_ERR_PARSE, "spec: missing ')' in", k0, strlen(k0));
    kelp_ivp_zaic_comp *c = &sp->comp[ci];
    memset(c, 0, sizeof *c);
    c->maxutil = 100;
    if (ci > 0)
        c->summitdelta = 50; /* seed 004 7.1.6: addComponent default */
    unsigned seen = 0;
    const char *q = p;
    while (q < close) {
        const char *e = q;
        while (e < close && *e != ',')
            e++;
        span t = {q, (size_t)(e - q)};
        ivp_trim(&t.s, &t.n);
        if (t.n == 0)
            return ivp_fail(diag, KELP_ERR_PARSE, "spec: empty argument in", k0, (size_t)(close - k0) + 1);
        const char *eq = memchr(t.s, '=', t.n);
        if (!eq) {
            unsigned bit;
            bool *flag;
            if (kind != KELP_IVP_SPEC_PEAK)
                return ivp_fail(diag, KELP_ERR_PARSE, "spec: leq/heq take no flags:", t.s, t.n);
            if (ivp_word_eq(t.s, t.n, "wrap")) {
                bit = 1u << 8;
                flag = &sp->wrap;
            } else if (ivp_word_eq(t.s, t.n, "insist")) {
                bit = 1u << 9;
                flag = &sp->insist;
            } else if (ivp_word_eq(t.s, t.n, "sum")) {
                bit = 1u << 10;
                flag = &sp->sum;
            } else {
                return ivp_fail(diag, KELP_ERR_PARSE, "spec: unknown flag (want wrap, insist or sum):", t.s, t.n);
            }
            if (seen & bit)
                return ivp_fail(diag, KELP_ERR_PARSE, "spec: repeated flag", t.s, t.n);
            seen |= bit;
            *flag = true;
        } else {
            span key = {t.s, (size_t)(eq - t.s)}, val = {eq + 1, t.n - (size_t)(eq - t.s) - 1};
            ivp_trim(&key.s, &key.n);
            ivp_trim(&val.s, &val.n);
            static const char *const keys[6] = {"summit", "peakwidth", "basewidth", "summitdelta", "minutil", "maxutil"};
            unsigned kix = 6;
            for (unsigned i = 0; i < 6; i++)
                if (ivp_word_eq(key.s, key.n, keys[i]))
                    kix = i;
            if (kix == 6 || (kind != KELP_IVP_SPEC_PEAK && kix == 1))
                return ivp_fail(diag, KELP_ERR_PARSE, "spec: unknown parameter", key.s, key.n);
            if (seen & (1u << kix))
                return ivp_fail(diag, KELP_ERR_PARSE, "spec: repeated parameter", key.s, key.n);
            seen |= 1u << kix;
            double v;
            int rc = parse_num(val, &v, diag, "spec: bad number");
            if (rc)
                return rc;
            double *dst[6] = {&c->summit, &c->peakwidth, &c->basewidth, &c->summitdelta, &c->minutil, &c->maxutil};
            *dst[kix] = v;
        }
        if (e < close && e + 1 >= close)
            return ivp_fail(diag, KELP_ERR_PARSE, "spec: empty argument in", k0, (size_t)(close - k0) + 1);
        q = e < close ? e + 1 : e;
    }
    *pp = close + 1;
    return 0;
}

int kelp_ivp_spec_parse(kelp_ivp_spec *sp, const char *s, kelp_diag *diag)
{
    memset(sp, 0, sizeof *sp);
    if (!s)
        return ivp_fail(diag, KELP_ERR_ARG, "spec: no text", NULL, 0);
    const char *p = s;
    for (unsigned ci = 0;; ci++) {
        if (ci >= KELP_IVP_MAX_COMPONENTS)
            return ivp_fail(diag, KELP_ERR_NOSPACE, "spec: too many components at", p, strlen(p));
        int rc = parse_component(&p, sp, ci, diag);
        if (rc)
            return rc;
        sp->ncomp = ci + 1;
        p = ivp_skip_ws(p);
        if (*p == '+') {
            p++;
            continue;
        }
        if (*p == '\0' || *p == '\n')
            break;
        return ivp_fail(diag, KELP_ERR_PARSE, "spec: unexpected text", p, strcspn(p, " \t\n"));
    }
    return 0;
}

size_t kelp_ivp_spec_max_pieces(const kelp_ivp_spec *sp, const kelp_ivp_domain *dom, const char *var)
{
    int ix = kelp_ivp_domain_index(dom, var);
    if (ix < 0)
        return 0;
    if (sp->kind == KELP_IVP_SPEC_PEAK)
        return dom->var[ix].points;
    return KELP_IVP_ZAIC_HLEQ_MAX_PIECES;
}

int kelp_ivp_spec_build(const kelp_ivp_spec *sp, const kelp_ivp_domain *dom, const char *var, double *work,
                        size_t work_len, kelp_ivp_spec_ws *ws, kelp_ivp_piece *store, size_t cap, kelp_ivp_func *out,
                        kelp_diag *diag)
{
    int rc;
    if (kelp_ivp_domain_index(dom, var) < 0)
        return ivp_fail(diag, KELP_ERR_NOTFOUND, "spec: variable not in domain:", var, strlen(var));
    if (sp->kind == KELP_IVP_SPEC_PEAK) {
        if (!ws)
            return ivp_fail(diag, KELP_ERR_ARG, "spec: no workspace", NULL, 0);
        kelp_ivp_zaic_peak *z = &ws->peak;
        rc = kelp_ivp_zaic_peak_init(z, dom, var);
        if (rc)
            return ivp_fail(diag, rc, "spec: cannot build ZAIC_PEAK on", var, strlen(var));
        for (unsigned i = 0; i < sp->ncomp; i++) {
            const kelp_ivp_zaic_comp *c = &sp->comp[i];
            if (i > 0) /* a full component table is fatal: z->ok is false, checked below */
                KELP_IGNORE(kelp_ivp_zaic_peak_add_component(z));
            ivp_ignore(kelp_ivp_zaic_peak_set_params(z, c->summit, c->peakwidth, c->basewidth, c->summitdelta, c->minutil,
                                                c->maxutil, i));
        }
        z->wrap = sp->wrap;
        z->insist = sp->insist;
        if (!z->ok)
            return ivp_fail(diag, KELP_ERR_RANGE, "spec: bad peak parameters:", z->warn, strlen(z->warn));
        rc = kelp_ivp_zaic_peak_extract(z, !sp->sum, work, work_len, store, cap, out);
        if (rc)
            return ivp_fail(diag, rc, "spec: peak extraction failed (storage)", NULL, 0);
        return 0;
    }
    if (!ws)
        return ivp_fail(diag, KELP_ERR_ARG, "spec: no workspace", NULL, 0);
    kelp_ivp_zaic_hleq *z = &ws->hleq;
    rc = kelp_ivp_zaic_hleq_init(z, sp->kind == KELP_IVP_SPEC_LEQ ? KELP_IVP_ZAIC_LEQ : KELP_IVP_ZAIC_HEQ, dom, var);
    if (rc)
        return ivp_fail(diag, rc, "spec: cannot build ZAIC_LEQ/HEQ on", var, strlen(var));
    const kelp_ivp_zaic_comp *c = &sp->comp[0];
    ivp_ignore(kelp_ivp_zaic_hleq_set_summit(z, c->summit));
    ivp_ignore(kelp_ivp_zaic_hleq_set_basewidth(z, c->basewidth));
    ivp_ignore(kelp_ivp_zaic_hleq_set_minmaxutil(z, c->minutil, c->maxutil));
    ivp_ignore(kelp_ivp_zaic_hleq_set_summitdelta(z, c->summitdelta));
    if (!z->ok)
        return ivp_fail(diag, KELP_ERR_RANGE, "spec: bad leq/heq parameters:", z->warn, strlen(z->warn));
    rc = kelp_ivp_zaic_hleq_extract(z, store, cap, out);
    if (rc)
        return ivp_fail(diag, rc, "spec: leq/heq extraction failed (storage)", NULL, 0);
    return 0;
}

/* ------------------------------------------------------------------ FILE lines */

/* Next token: whitespace separated, but blanks inside (...) belong to the token. */
static span next_tok(const char **pp)
{
    const char *p = ivp_skip_ws(*pp);
    const char *st = p;
    int depth = 0;
    while (*p && *p != '\n' && (depth > 0 || (*p != ' ' && *p != '\t' && *p != '\r'))) {
        if (*p == '(')
            depth++;
        else if (*p == ')' && depth > 0)
            depth--;
        p++;
    }
    *pp = p;
    span t = {st, (size_t)(p - st)};
    return t;
}

static int tok_copy(span t, char *buf, size_t cap)
{
    if (t.n + 1 > cap)
        return KELP_ERR_NOSPACE;
    memcpy(buf, t.s, t.n);
    buf[t.n] = '\0';
    return 0;
}

int kelp_ivp_file_domain(const char *line, kelp_ivp_domain *dom, kelp_diag *diag)
{
    const char *p = line;
    span t = next_tok(&p);
    if (!ivp_word_eq(t.s, t.n, "domain"))
        return ivp_fail(diag, KELP_ERR_PARSE, "file: first line must be 'domain DOMAIN', got", t.s, t.n);
    p = ivp_skip_ws(p);
    size_t n = strcspn(p, "\n");
    span r = {p, n};
    ivp_trim(&r.s, &r.n);
    if (r.n == 0)
        return ivp_fail(diag, KELP_ERR_PARSE, "file: 'domain' needs name:low:high:points", NULL, 0);
    if (r.n >= 512)
        return ivp_fail(diag, KELP_ERR_PARSE, "file: domain text too long", r.s, r.n);
    return kelp_ivp_domain_parse_n(dom, r.s, r.n, diag);
}

static int spec_tok(span t, kelp_ivp_spec *sp, char *buf, size_t cap, kelp_diag *diag)
{
    if (t.n == 0)
        return ivp_fail(diag, KELP_ERR_PARSE, "file: missing SPEC", NULL, 0);
    if (tok_copy(t, buf, cap))
        return ivp_fail(diag, KELP_ERR_PARSE, "file: SPEC too long", t.s, t.n);
    return kelp_ivp_spec_parse(sp, buf, diag);
}

static int weight_tok(span t, double *w, kelp_diag *diag, const char *what)
{
    if (t.n == 0)
        return ivp_fail(diag, KELP_ERR_PARSE, what, "(missing)", 9);
    if (ivp_parse_double(t.s, t.n, w))
        return ivp_fail(diag, KELP_ERR_PARSE, what, t.s, t.n);
    return 0;
}

int kelp_ivp_file_line(const char *line, const kelp_ivp_domain *dom, kelp_ivp_fileline *fl, kelp_diag *diag)
{
    memset(fl, 0, sizeof *fl);
    const char *p = line;
    span t = next_tok(&p);
    if (!ivp_word_eq(t.s, t.n, "pwt"))
        return ivp_fail(diag, KELP_ERR_PARSE, "file: function line must start with 'pwt', got", t.s, t.n);
    int rc = weight_tok(next_tok(&p), &fl->pwt, diag, "file: bad pwt");
    if (rc)
        return rc;
    span kind = next_tok(&p);
    if (kind.n == 0)
        return ivp_fail(diag, KELP_ERR_PARSE, "file: missing function after pwt", NULL, 0);
    if (ivp_word_eq(kind.s, kind.n, "couple")) {
        fl->kind = KELP_IVP_LINE_COUPLE;
        if ((rc = weight_tok(next_tok(&p), &fl->wc, diag, "file: bad couple weight WC")))
            return rc;
        if ((rc = weight_tok(next_tok(&p), &fl->ws, diag, "file: bad couple weight WS")))
            return rc;
        if (!(fl->wc > 0) || !(fl->ws > 0))
            return ivp_fail(diag, KELP_ERR_RANGE, "file: couple weights must be > 0", NULL, 0);
        if ((rc = spec_tok(next_tok(&p), &fl->a, fl->ws_spec, sizeof fl->ws_spec, diag)) || (rc = spec_tok(next_tok(&p), &fl->b, fl->ws_spec, sizeof fl->ws_spec, diag)))
            return rc;
        int vc, vs;
        if (kelp_ivp_couple_vars(dom, &vc, &vs))
            return ivp_fail(diag, KELP_ERR_RANGE, "file: couple needs a domain of at least two variables", NULL, 0);
    } else if (ivp_word_eq(kind.s, kind.n, "raw")) {
        fl->kind = KELP_IVP_LINE_RAW;
        span vars = next_tok(&p);
        if (vars.n == 0)
            return ivp_fail(diag, KELP_ERR_PARSE, "file: raw needs VARS", NULL, 0);
        const char *q = vars.s, *end = vars.s + vars.n;
        while (q <= end) {
            const char *c = q;
            while (c < end && *c != ',')
                c++;
            char nm[KELP_IVP_MAX_VARNAME];
            span v = {q, (size_t)(c - q)};
            int ix = -1;
            if (v.n > 0 && tok_copy(v, nm, sizeof nm) == 0)
                ix = kelp_ivp_domain_index(dom, nm);
            if (ix < 0)
                return ivp_fail(diag, KELP_ERR_NOTFOUND, "file: raw variable not in domain:", v.s, v.n);
            for (unsigned i = 0; i < fl->nvars; i++)
                if (fl->vars[i] == ix)
                    return ivp_fail(diag, KELP_ERR_PARSE, "file: raw variable repeated:", v.s, v.n);
            if (fl->nvars >= KELP_IVP_MAX_DIM)
                return ivp_fail(diag, KELP_ERR_NOSPACE, "file: too many raw variables", vars.s, vars.n);
            fl->vars[fl->nvars++] = ix;
            q = c + 1;
        }
        span nt = next_tok(&p);
        long np;
        if (nt.n == 0 || ivp_parse_long(nt.s, nt.n, &np) || np < 1)
            return ivp_fail(diag, KELP_ERR_PARSE, "file: raw needs a piece count N >= 1, got", nt.s, nt.n ? nt.n : 0);
        fl->npieces = (unsigned long)np;
    } else {
        fl->kind = KELP_IVP_LINE_SPEC;
        if (tok_copy(kind, fl->var, sizeof fl->var) || kelp_ivp_domain_index(dom, fl->var) < 0)
            return ivp_fail(diag, KELP_ERR_NOTFOUND, "file: expected couple, raw or a domain variable, got", kind.s, kind.n);
        if ((rc = spec_tok(next_tok(&p), &fl->a, fl->ws_spec, sizeof fl->ws_spec, diag)))
            return rc;
    }
    span extra = next_tok(&p);
    if (extra.n)
        return ivp_fail(diag, KELP_ERR_PARSE, "file: unexpected text", extra.s, extra.n);
    return 0;
}

int kelp_ivp_file_piece(const char *line, unsigned nvars, kelp_ivp_func *f, kelp_diag *diag)
{
    int32_t lo[KELP_IVP_MAX_DIM], hi[KELP_IVP_MAX_DIM];
    double sl[KELP_IVP_MAX_DIM], cst = 0;
    const char *p = line;
    if (nvars != f->dom.dim || nvars == 0)
        return ivp_fail(diag, KELP_ERR_ARG, "file: raw piece variable count mismatch", NULL, 0);
    for (unsigned d = 0; d < nvars; d++) {
        for (int e = 0; e < 2; e++) {
            span t = next_tok(&p);
            long v;
            if (t.n == 0)
                return ivp_fail(diag, KELP_ERR_PARSE, "file: raw piece line too short:", line, strcspn(line, "\n"));
            if (ivp_parse_long(t.s, t.n, &v))
                return ivp_fail(diag, KELP_ERR_PARSE, "file: bad piece bound", t.s, t.n);
            if (v < 0 || v >= (long)f->dom.var[d].points)
                return ivp_fail(diag, KELP_ERR_RANGE, "file: piece bound outside the domain:", t.s, t.n);
            if (e == 0)
                lo[d] = (int32_t)v;
            else
                hi[d] = (int32_t)v;
        }
        if (hi[d] < lo[d])
            return ivp_fail(diag, KELP_ERR_RANGE, "file: piece bound hi < lo in", line, strcspn(line, "\n"));
    }
    for (unsigned d = 0; d <= nvars; d++) {
        span t = next_tok(&p);
        double v;
        if (t.n == 0)
            return ivp_fail(diag, KELP_ERR_PARSE, "file: raw piece line too short:", line, strcspn(line, "\n"));
        if (ivp_parse_double(t.s, t.n, &v))
            return ivp_fail(diag, KELP_ERR_PARSE, "file: bad piece coefficient", t.s, t.n);
        if (d < nvars)
            sl[d] = v;
        else
            cst = v;
    }
    span extra = next_tok(&p);
    if (extra.n)
        return ivp_fail(diag, KELP_ERR_PARSE, "file: unexpected text after piece", extra.s, extra.n);
    int rc = kelp_ivp_func_add(f, lo, hi, sl, cst);
    if (rc == KELP_ERR_NOSPACE)
        return ivp_fail(diag, rc, "file: more piece lines than N", NULL, 0);
    if (rc)
        return ivp_fail(diag, rc, "file: bad piece", line, strcspn(line, "\n"));
    return 0;
}

int kelp_ivp_couple_vars(const kelp_ivp_domain *dom, int *vc, int *vs)
{
    if (dom->dim < 2)
        return KELP_ERR_RANGE;
    int c = kelp_ivp_domain_index(dom, "course"), s = kelp_ivp_domain_index(dom, "speed");
    if (c >= 0 && s >= 0) {
        *vc = c;
        *vs = s;
    } else {
        *vc = 0;
        *vs = 1;
    }
    return 0;
}

/* ------------------------------------------------------------------ shapes, points, regions */

/* Split "kind @ a:b,c:d" and call fn for each "var:rest". Every domain variable exactly once. */
typedef int (*item_fn)(const kelp_ivp_domain *d, unsigned v, bool native, span rest, void *ctx, kelp_diag *diag);

static int walk(const kelp_ivp_domain *d, const char *s, item_fn fn, void *ctx, kelp_diag *diag)
{
    if (!s)
        return ivp_fail(diag, KELP_ERR_ARG, "no text", NULL, 0);
    const char *at = strchr(s, '@');
    if (!at)
        return ivp_fail(diag, KELP_ERR_PARSE, "expected 'discrete @ ...' or 'native @ ...', got", s, strlen(s));
    span k = {s, (size_t)(at - s)};
    ivp_trim(&k.s, &k.n);
    bool native;
    if (ivp_word_eq(k.s, k.n, "discrete"))
        native = false;
    else if (ivp_word_eq(k.s, k.n, "native"))
        native = true;
    else
        return ivp_fail(diag, KELP_ERR_PARSE, "unknown kind (want discrete or native):", k.s, k.n);
    unsigned seen = 0;
    const char *p = at + 1;
    for (;;) {
        const char *c = strchr(p, ',');
        span it = {p, c ? (size_t)(c - p) : strlen(p)};
        ivp_trim(&it.s, &it.n);
        const char *colon = memchr(it.s, ':', it.n);
        if (!colon)
            return ivp_fail(diag, KELP_ERR_PARSE, "expected var:value, got", it.s, it.n);
        span nm = {it.s, (size_t)(colon - it.s)};
        ivp_trim(&nm.s, &nm.n);
        char name[KELP_IVP_MAX_VARNAME];
        int ix = -1;
        if (nm.n > 0 && tok_copy(nm, name, sizeof name) == 0)
            ix = kelp_ivp_domain_index(d, name);
        if (ix < 0)
            return ivp_fail(diag, KELP_ERR_NOTFOUND, "unknown variable", nm.s, nm.n);
        if (seen & (1u << ix))
            return ivp_fail(diag, KELP_ERR_PARSE, "variable given twice:", nm.s, nm.n);
        seen |= 1u << ix;
        span rest = {colon + 1, it.n - (size_t)(colon + 1 - it.s)};
        ivp_trim(&rest.s, &rest.n);
        int rc = fn(d, (unsigned)ix, native, rest, ctx, diag);
        if (rc)
            return rc;
        if (!c)
            break;
        p = c + 1;
    }
    for (unsigned v = 0; v < d->dim; v++)
        if (!(seen & (1u << v)))
            return ivp_fail(diag, KELP_ERR_PARSE, "missing variable", d->var[v].name, strlen(d->var[v].name));
    return 0;
}

static int shape_item(const kelp_ivp_domain *d, unsigned v, bool native, span r, void *ctx, kelp_diag *diag)
{
    uint32_t *edge = ctx;
    double x;
    if (ivp_parse_double(r.s, r.n, &x))
        return ivp_fail(diag, KELP_ERR_PARSE, "bad length", r.s, r.n);
    double pts;
    if (native)
        pts = d->var[v].delta > 0 ? floor(x / d->var[v].delta + 0.5) : 1.0; /* .5 rounds up (seed 9.1.2) */
    else {
        if (x != floor(x))
            return ivp_fail(diag, KELP_ERR_PARSE, "discrete length must be an integer:", r.s, r.n);
        pts = x;
    }
    if (pts < 1)
        return ivp_fail(diag, KELP_ERR_RANGE, "piece edge must be at least one point:", r.s, r.n);
    if (pts > d->var[v].points)
        pts = d->var[v].points;
    edge[v] = (uint32_t)pts;
    return 0;
}

int kelp_ivp_parse_shape(const kelp_ivp_domain *d, const char *s, uint32_t *edge, kelp_diag *diag)
{
    return walk(d, s, shape_item, edge, diag);
}

static int point_item(const kelp_ivp_domain *d, unsigned v, bool native, span r, void *ctx, kelp_diag *diag)
{
    uint32_t *ix = ctx;
    double x;
    if (ivp_parse_double(r.s, r.n, &x))
        return ivp_fail(diag, KELP_ERR_PARSE, "bad value", r.s, r.n);
    if (native) {
        ix[v] = kelp_ivp_domain_snap(d, v, x, KELP_IVP_SNAP_NEAREST);
    } else {
        if (x != floor(x) || x < 0 || x >= d->var[v].points)
            return ivp_fail(diag, KELP_ERR_RANGE, "index outside the domain:", r.s, r.n);
        ix[v] = (uint32_t)x;
    }
    return 0;
}

int kelp_ivp_parse_point(const kelp_ivp_domain *d, const char *s, uint32_t *ix, kelp_diag *diag)
{
    return walk(d, s, point_item, ix, diag);
}

typedef struct {
    int32_t *lo, *hi;
} region_ctx;

static int region_item(const kelp_ivp_domain *d, unsigned v, bool native, span r, void *ctx, kelp_diag *diag)
{
    region_ctx *rc = ctx;
    const char *colon = memchr(r.s, ':', r.n);
    if (!colon)
        return ivp_fail(diag, KELP_ERR_PARSE, "region needs var:low:high, got", r.s, r.n);
    span a = {r.s, (size_t)(colon - r.s)}, b = {colon + 1, r.n - (size_t)(colon + 1 - r.s)};
    ivp_trim(&a.s, &a.n);
    ivp_trim(&b.s, &b.n);
    double x, y;
    if (ivp_parse_double(a.s, a.n, &x))
        return ivp_fail(diag, KELP_ERR_PARSE, "bad region low", a.s, a.n);
    if (ivp_parse_double(b.s, b.n, &y))
        return ivp_fail(diag, KELP_ERR_PARSE, "bad region high", b.s, b.n);
    const kelp_ivp_var *var = &d->var[v];
    double top = (double)var->points - 1;
    int32_t lo, hi;
    if (native) {
        if (x > var->high || y < var->low || x > y)
            return ivp_fail(diag, KELP_ERR_RANGE, "region holds no domain point:", r.s, r.n);
        lo = (int32_t)kelp_ivp_domain_snap(d, v, x, KELP_IVP_SNAP_CEIL);  /* first point >= low */
        hi = (int32_t)kelp_ivp_domain_snap(d, v, y, KELP_IVP_SNAP_FLOOR); /* last point <= high */
    } else {
        if (x != floor(x) || y != floor(y))
            return ivp_fail(diag, KELP_ERR_PARSE, "discrete region bounds must be integers:", r.s, r.n);
        lo = x < 0 ? 0 : (x > top ? (int32_t)top + 1 : (int32_t)x);
        hi = y > top ? (int32_t)top : (y < 0 ? -1 : (int32_t)y);
    }
    if (lo > hi)
        return ivp_fail(diag, KELP_ERR_RANGE, "region holds no domain point:", r.s, r.n);
    rc->lo[v] = lo;
    rc->hi[v] = hi;
    return 0;
}

int kelp_ivp_parse_region(const kelp_ivp_domain *d, const char *s, int32_t *lo, int32_t *hi, kelp_diag *diag)
{
    region_ctx c = {lo, hi};
    return walk(d, s, region_item, &c, diag);
}
