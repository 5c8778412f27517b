/* kelp helm: behaviour run conditions ("DEPLOY = true", "(K <= 4)", and/or/not).
 * One recursive-descent pass both checks the syntax and, given a buffer, evaluates. */
#include <string.h>
#include "helm_int.h"

enum tok_kind { T_END, T_LP, T_RP, T_OP, T_AND, T_OR, T_NOT, T_STR, T_WORD, T_VAR, T_BAD };
enum rel_op { OP_EQ, OP_NE, OP_LT, OP_LE, OP_GT, OP_GE };

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
    unsigned depth; /* nesting of ( and not: at most KELP_HELM_COND_MAX_DEPTH */
    bool err;
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
        t.op = OP_EQ;
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
        if (kelp_strieq_n(t.s, t.n, "and"))
            t.k = T_AND;
        else if (kelp_strieq_n(t.s, t.n, "or"))
            t.k = T_OR;
        else if (kelp_strieq_n(t.s, t.n, "not"))
            t.k = T_NOT;
        i = j;
    } else {
        t.k = T_BAD;
        i++;
    }
    p->cur = t;
    p->pos = i;
}

typedef struct val {
    bool known;
    bool is_num;
    double num;
    const char *s;
    size_t n;
    bool literal;
    char buf[64];
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
    char name[KELP_MAX_NAME];
    if (!hx_copy(name, sizeof name, t->s, t->n))
        return;
    int i = kelp_helm_ib_find(p->ib, name);
    if (i < 0 || p->ib->var[i].time < 0)
        return;
    const kelp_helm_ibvar *x = &p->ib->var[i];
    v->known = true;
    if (x->is_str) {
        v->s = x->sval;
        v->n = strlen(x->sval);
        v->is_num = hx_number(v->s, v->n, &v->num);
    } else {
        v->is_num = true;
        v->num = x->dval;
        hx_fmt_double(v->buf, sizeof v->buf, x->dval);
        v->s = v->buf;
        v->n = strlen(v->buf);
    }
}

static bool is_bool_lit(const val *v)
{
    return v->literal && (kelp_strieq_n(v->s, v->n, "true") || kelp_strieq_n(v->s, v->n, "false"));
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

static bool compare(const val *a, enum rel_op op, const val *b)
{
    if (!a->known || !b->known)
        return false;
    int c;
    if (a->is_num && b->is_num) {
        c = a->num < b->num ? -1 : (a->num > b->num ? 1 : 0);
    } else if (a->is_num != b->is_num && op != OP_EQ && op != OP_NE) {
        return false; /* ordering a number against a non-number */
    } else {
        c = cmp_str(a, b, is_bool_lit(a) || is_bool_lit(b));
    }
    switch (op) {
    case OP_EQ: return c == 0;
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

static bool expr(cparse *p);

KELP_NOINLINE static bool relation(cparse *p)
{
    tok a = p->cur;
    if (!operand(a.k)) {
        p->err = true;
        return false;
    }
    next(p);
    if (p->cur.k != T_OP) {
        p->err = true;
        return false;
    }
    enum rel_op op = p->cur.op;
    next(p);
    tok b = p->cur;
    if (!operand(b.k)) {
        p->err = true;
        return false;
    }
    next(p);
    /* which side names a variable */
    bool av = a.k == T_VAR, bv = b.k == T_VAR;
    double dummy;
    bool aw = a.k == T_WORD && !hx_number(a.s, a.n, &dummy);
    bool bw = b.k == T_WORD && !hx_number(b.s, b.n, &dummy);
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

static bool factor(cparse *p)
{
    if (p->cur.k == T_NOT || p->cur.k == T_LP) {
        if (p->depth >= KELP_HELM_COND_MAX_DEPTH) { /* deeper would only grow the stack */
            p->err = true;
            return false;
        }
        p->depth++;
        bool v;
        if (p->cur.k == T_NOT) {
            next(p);
            v = !factor(p);
        } else {
            next(p);
            v = expr(p);
            if (p->cur.k != T_RP)
                p->err = true;
            else
                next(p);
        }
        p->depth--;
        return p->err ? false : v;
    }
    return relation(p);
}

static bool term(cparse *p)
{
    bool v = factor(p);
    while (!p->err && p->cur.k == T_AND) {
        next(p);
        bool w = factor(p);
        v = v && w;
    }
    return v;
}

static bool expr(cparse *p)
{
    bool v = term(p);
    while (!p->err && p->cur.k == T_OR) {
        next(p);
        bool w = term(p);
        v = v || w;
    }
    return v;
}

static int run(const char *cond, const kelp_helm_ib *ib, void (*on_var)(const char *, size_t, void *), void *user)
{
    if (!cond)
        return KELP_ERR_ARG;
    cparse p = {cond, 0, {T_END, cond, 0, OP_EQ}, ib, on_var, user, 0, false};
    next(&p);
    if (p.cur.k == T_END)
        return KELP_ERR_PARSE;
    bool v = expr(&p);
    if (p.err || p.cur.k != T_END)
        return KELP_ERR_PARSE;
    return v ? 1 : 0;
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
