/* kelp helm: behaviour run conditions ("DEPLOY = true", "(K <= 4)", and/or/not).
 * One pass both checks the syntax and, given a buffer, evaluates. */
#include <math.h>
#include <string.h>
#include "helm_int.h"

enum tok_kind { T_END, T_LP, T_RP, T_OP, T_AND, T_OR, T_NOT, T_STR, T_WORD, T_VAR, T_BAD };
enum rel_op { OP_EQ, OP_NE, OP_LT, OP_LE, OP_GT, OP_GE, OP_FEQ };

typedef struct tok {
    enum tok_kind k;
    const char *s;   /* text (for STR without quotes, for VAR the name inside $( )) */
    size_t n;
    enum rel_op op;
} tok;

typedef struct cparse {
    const char *s;
    size_t pos;
    tok cur;
    const kelp_helm_ib *ib;  /* NULL: syntax check only */
    void (*on_var)(const char *var, size_t len, void *user);
    void *user;
} cparse;

static bool word_char(char c)
{
    return c && !hx_is_space(c) && !strchr("()=!<>\"&|", c);
}

static void next(cparse *p)
{
    const char *s = p->s;
    size_t i = p->pos;
    while (s[i] && hx_is_space(s[i]))
        i++;
    tok t = {T_END, s + i, 0, OP_EQ};
    char c = s[i];
    if (!c) {
        p->cur = t;
        p->pos = i;
        return;
    }
    if (c == '(') {
        t.k = T_LP;
        i++;
    } else if (c == ')') {
        t.k = T_RP;
        i++;
    } else if (c == '=') {
        t.k = T_OP;
        t.op = s[i + 1] == '=' ? OP_FEQ : OP_EQ;
        i += (s[i + 1] == '=') ? 2 : 1;
    } else if (c == '!' && s[i + 1] == '=') {
        t.k = T_OP;
        t.op = OP_NE;
        i += 2;
    } else if (c == '!') {
        t.k = T_NOT;
        i++;
    } else if (c == '<' || c == '>') {
        t.k = T_OP;
        bool eq = s[i + 1] == '=';
        t.op = c == '<' ? (eq ? OP_LE : OP_LT) : (eq ? OP_GE : OP_GT);
        i += eq ? 2 : 1;
    } else if (c == '&' && s[i + 1] == '&') {
        t.k = T_AND;
        i += 2;
    } else if (c == '|' && s[i + 1] == '|') {
        t.k = T_OR;
        i += 2;
    } else if (c == '"') {
        const char *e = strchr(s + i + 1, '"');
        if (!e) {
            t.k = T_BAD;
            i = strlen(s);
        } else {
            t.k = T_STR;
            t.s = s + i + 1;
            t.n = (size_t)(e - (s + i + 1));
            i = (size_t)(e - s) + 1;
        }
    } else if (c == '$' && s[i + 1] == '(') {
        const char *e = strchr(s + i + 2, ')');
        if (!e) {
            t.k = T_BAD;
            i = strlen(s);
        } else {
            t.k = T_VAR;
            t.s = s + i + 2;
            t.n = (size_t)(e - (s + i + 2));
            hx_trim(&t.s, &t.n);
            if (!hx_varname(t.s, t.n))
                t.k = T_BAD;
            i = (size_t)(e - s) + 1;
        }
    } else if (word_char(c)) {
        size_t j = i;
        while (word_char(s[j]))
            j++;
        t.k = T_WORD;
        t.n = j - i;
        if (kelp_util_strieq_n(t.s, t.n, "and"))
            t.k = T_AND;
        else if (kelp_util_strieq_n(t.s, t.n, "or"))
            t.k = T_OR;
        else if (kelp_util_strieq_n(t.s, t.n, "not"))
            t.k = T_NOT;
        i = j;
    } else {
        t.k = T_BAD;
        i++;
    }
    p->cur = t;
    p->pos = i;
}

/* An operand's value. A double read from the buffer keeps no text (s == NULL): its string
 * form is made only when a comparison needs one (cmp_fmt), so a relation's frame stays small. */
typedef struct val {
    bool known;
    bool is_num;
    bool literal;
    double num;
    const char *s;
    size_t n;
} val;

static void lit_value(const tok *t, val *v)
{
    memset(v, 0, sizeof *v);
    v->known = true;
    v->literal = true;
    v->s = t->s;
    v->n = t->n;
    if (t->k == T_WORD)
        v->is_num = hx_number(t->s, t->n, &v->num);
}

static void var_value(cparse *p, const tok *t, val *v)
{
    memset(v, 0, sizeof *v);
    if (p->on_var)
        p->on_var(t->s, t->n, p->user);
    if (!p->ib)
        return;
    if (t->n >= KELP_MAX_NAME)
        return;
    const kelp_helm_ibvar *x = NULL; /* kelp_helm_ib_find on the token itself (no copy of the name) */
    for (unsigned i = 0; i < p->ib->nvar && !x; i++)
        if (!strncmp(p->ib->var[i].name, t->s, t->n) && p->ib->var[i].name[t->n] == '\0')
            x = &p->ib->var[i];
    if (!x || x->time < 0)
        return;
    v->known = true;
    if (x->is_str) {
        v->s = x->sval;
        v->n = strlen(x->sval);
        /* hx_number's reading, straight into v (one frame less on this deep path) */
        v->is_num = kelp_util_parse_double(v->s, v->n, &v->num) == KELP_OK && isfinite(v->num);
        if (!v->is_num)
            v->num = 0;
    } else {
        v->is_num = true;
        v->num = x->dval;
    }
}

static bool is_bool_lit(const val *v)
{
    return v->literal && (kelp_util_strieq_n(v->s, v->n, "true") || kelp_util_strieq_n(v->s, v->n, "false"));
}

static int cmp_str(const val *a, const val *b, bool ci)
{
    size_t n = a->n < b->n ? a->n : b->n;
    for (size_t i = 0; i < n; i++) {
        char x = ci ? hx_lower(a->s[i]) : a->s[i], y = ci ? hx_lower(b->s[i]) : b->s[i];
        if (x != y)
            return (unsigned char)x < (unsigned char)y ? -1 : 1;
    }
    return a->n == b->n ? 0 : (a->n < b->n ? -1 : 1);
}

/* cmp_str where one side is a buffer double (only one can be: two numbers compare as numbers):
 * its text is the %g-like form the buffer gives (hx_fmt_double). */
KELP_NOINLINE static int cmp_fmt(const val *a, const val *b, bool ci)
{
    char buf[32]; /* hx_fmt_double: at most 20 characters */
    val t = a->s ? *b : *a;
    hx_fmt_double(buf, sizeof buf, t.num);
    t.s = buf;
    t.n = strlen(buf);
    return a->s ? cmp_str(a, &t, ci) : cmp_str(&t, b, ci);
}

static bool has_sub(const char *s, size_t n, const char *t, size_t m)
{
    if (m > n) return false;
    for (size_t i = 0; i + m <= n; i++)
        if (!memcmp(s + i, t, m)) return true;
    return false;
}

/* the k-th ':' component of s (blank ends stripped); false past the last */
static bool component(const char *s, size_t n, unsigned k, const char **c, size_t *cn)
{
    size_t i = 0;
    for (unsigned j = 0; j < k; j++) {
        while (i < n && s[i] != ':') i++;
        if (i >= n) return false;
        i++;
    }
    size_t e = i;
    while (e < n && s[e] != ':') e++;
    while (i < e && hx_is_space(s[i])) i++;
    while (e > i && hx_is_space(s[e - 1])) e--;
    *c = s + i, *cn = e - i;
    return true;
}

static unsigned components(const char *s, size_t n)
{
    unsigned c = 1;
    for (size_t i = 0; i < n; i++) c += s[i] == ':';
    return c;
}

static bool comp_eq(const char *a, size_t an, unsigned i, const char *b, size_t bn, unsigned j)
{
    const char *x, *y;
    size_t xn, yn;
    return component(a, an, i, &x, &xn) && component(b, bn, j, &y, &yn) && xn == yn && !memcmp(x, y, xn);
}

/* "==" between two strings, as MOOS-IvP's logic conditions (LogicUtils' field match): true when
 * one side is a run of consecutive ':'-separated components of the other, blank ends stripped
 * ("TRANSIT" == "ACTIVE:TRANSIT", "ACTIVE:TRANSIT" == "ACTIVE:TRANSIT:EAST"). 24.8 steps along
 * the longer side by 1, then 2, ... and so misses runs of three or more components, even equal
 * strings (docs/CONFORMANCE.md): kelp walks the run. */
KELP_NOINLINE static bool field_match(const char *a, size_t an, const char *b, size_t bn)
{
    if (!has_sub(a, an, b, bn) && !has_sub(b, bn, a, an)) return false;
    unsigned na = components(a, an), nb = components(b, bn);
    const char *sh = b, *lo = a;
    size_t shn = bn, lon = an;
    unsigned ns = nb, nl = na;
    if (na < nb) sh = a, shn = an, ns = na, lo = b, lon = bn, nl = nb;
    for (unsigned j = 0; j + ns <= nl; j++) {
        unsigned i = 0;
        while (i < ns && comp_eq(sh, shn, i, lo, lon, j + i)) i++;
        if (i == ns) return true;
    }
    return false;
}

static bool compare(const val *a, enum rel_op op, const val *b)
{
    if (!a->known || !b->known)
        return false;
    int c;
    if (a->is_num && b->is_num) {
        c = a->num < b->num ? -1 : (a->num > b->num ? 1 : 0);
    } else if (op == OP_FEQ && a->s && b->s) { /* (two numbers compared above) */
        return field_match(a->s, a->n, b->s, b->n);
    } else if (a->is_num != b->is_num && op != OP_EQ && op != OP_NE && op != OP_FEQ) {
        return false; /* ordering a number against a non-number */
    } else {
        bool ci = is_bool_lit(a) || is_bool_lit(b);
        c = a->s && b->s ? cmp_str(a, b, ci) : cmp_fmt(a, b, ci);
    }
    switch (op) {
    case OP_EQ:
    case OP_FEQ: return c == 0;
    case OP_NE: return c != 0;
    case OP_LT: return c < 0;
    case OP_LE: return c <= 0;
    case OP_GT: return c > 0;
    case OP_GE: return c >= 0;
    }
    return false;
}

static bool operand(enum tok_kind k)
{
    return k == T_STR || k == T_WORD || k == T_VAR;
}

/* relation := operand op operand. *ok = false on a syntax error. */
/* a word that reads as a number (out of line: its double is not in relation's frame) */
KELP_NOINLINE static bool is_number(const tok *t)
{
    double d;
    return hx_number(t->s, t->n, &d);
}

KELP_NOINLINE static bool relation(cparse *p, bool *ok)
{
    tok a = p->cur;
    if (!operand(a.k))
        return *ok = false;
    next(p);
    if (p->cur.k != T_OP)
        return *ok = false;
    enum rel_op op = p->cur.op;
    next(p);
    tok b = p->cur;
    if (!operand(b.k))
        return *ok = false;
    next(p);
    /* which side names a variable */
    bool av = a.k == T_VAR, bv = b.k == T_VAR;
    bool aw = a.k == T_WORD && !is_number(&a);
    bool bw = b.k == T_WORD && !is_number(&b);
    if (!av && !bv) {
        if (aw)
            av = true;
        else if (bw)
            bv = true;
    }
    val x, y;
    if (av)
        var_value(p, &a, &x);
    else
        lit_value(&a, &x);
    if (bv)
        var_value(p, &b, &y);
    else
        lit_value(&b, &y);
    return compare(&x, op, &y);
}

/* The grammar (expr := term {or term}, term := factor {and factor}, factor := not factor |
 * ( expr ) | relation) without recursion: one byte per open "not" or "(" on an explicit stack
 * of KELP_HELM_COND_MAX_DEPTH, so the stack use does not grow with the nesting. Every factor is
 * evaluated (no short cut: each relation reports its variables), left to right. */
enum { F_PAREN = 1, F_OR = 2, F_AND = 4 }; /* stack entry: "(" (else "not"), the saved level */

static int run(const char *cond, const kelp_helm_ib *ib, void (*on_var)(const char *, size_t, void *), void *user)
{
    if (!cond)
        return KELP_ERR_ARG;
    cparse p = {cond, 0, {T_END, cond, 0, OP_EQ}, ib, on_var, user};
    uint8_t st[KELP_HELM_COND_MAX_DEPTH];
    unsigned depth = 0;
    bool or_v = false, and_v = true; /* this level: or of the terms done, and of this term's factors */
    next(&p);
    if (p.cur.k == T_END)
        return KELP_ERR_PARSE;
    for (;;) {
        /* a factor: open "not"s and "("s, then a relation */
        if (p.cur.k == T_NOT || p.cur.k == T_LP) {
            if (depth >= KELP_HELM_COND_MAX_DEPTH) /* deeper would only grow the stack */
                return KELP_ERR_PARSE;
            if (p.cur.k == T_NOT) {
                st[depth++] = 0;
            } else {
                st[depth++] = (uint8_t)(F_PAREN | (or_v ? F_OR : 0) | (and_v ? F_AND : 0));
                or_v = false;
                and_v = true;
            }
            next(&p);
            continue;
        }
        bool ok = true;
        bool f = relation(&p, &ok);
        if (!ok)
            return KELP_ERR_PARSE;
        for (;;) {
            /* the factor is done: apply the "not"s waiting for it */
            while (depth > 0 && !(st[depth - 1] & F_PAREN)) {
                f = !f;
                depth--;
            }
            and_v = and_v && f;
            if (p.cur.k != T_RP || depth == 0)
                break;
            /* ")" closes the level: its value is a factor of the level around it */
            f = or_v || and_v;
            depth--;
            or_v = (st[depth] & F_OR) != 0;
            and_v = (st[depth] & F_AND) != 0;
            next(&p);
        }
        if (p.cur.k == T_AND) {
            next(&p);
        } else if (p.cur.k == T_OR) {
            or_v = or_v || and_v;
            and_v = true;
            next(&p);
        } else if (p.cur.k == T_END && depth == 0) {
            return or_v || and_v ? 1 : 0;
        } else {
            return KELP_ERR_PARSE; /* an unclosed "(", a stray ")" or a missing and/or */
        }
    }
}

int kelp_helm_cond_check(const char *cond, void (*on_var)(const char *var, size_t len, void *user), void *user)
{
    int rc = run(cond, NULL, on_var, user);
    return rc < 0 ? rc : 0;
}

int kelp_helm_cond_eval(const char *cond, const kelp_helm_ib *ib)
{
    return run(cond, ib, NULL, NULL);
}
