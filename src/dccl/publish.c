/* kelp DCCL: <publish> on receipt (Goby message_publish.cpp) and the boost::format
 * subset its <format> strings use. Every argument is fed as a string, so numeric
 * conversions in a spec (%3$.01f) do not reformat it; %s/%S precision truncates,
 * %c keeps one character, width pads. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "dccl_int.h"

typedef struct fmt_item {
    int arg;        /* 0-based argument, -1 for a literal */
    bool left, zero, space;
    unsigned width;
    long trunc;     /* -1: none */
} fmt_item;

static bool isdig(char c)
{
    return c >= '0' && c <= '9';
}

/* Parse "[flags][width][.prec][lhL]type" starting at s[*i]; `bar` = inside %|...| (type optional). */
static bool parse_spec(const char *s, size_t *i, bool bar, fmt_item *it)
{
    size_t p = *i;
    bool have_prec = false;
    unsigned long prec = 0;
    for (;; p++) {
        char c = s[p];
        if (c == '-') it->left = true;
        else if (c == '0') it->zero = true;
        else if (c == ' ') it->space = true;
        else if (c == '+' || c == '#' || c == '\'') continue;
        else break;
    }
    while (isdig(s[p])) {
        if (it->width < 100000u) it->width = it->width * 10u + (unsigned)(s[p] - '0');
        p++;
    }
    if (s[p] == '.') {
        p++;
        have_prec = true;
        while (isdig(s[p])) {
            if (prec < 100000u) prec = prec * 10u + (unsigned long)(s[p] - '0');
            p++;
        }
    }
    while (s[p] == 'l' || s[p] == 'h' || s[p] == 'L') p++;
    switch (s[p]) {
    case 's':
    case 'S':
        if (have_prec) it->trunc = (long)prec;
        p++;
        break;
    case 'c':
    case 'C':
        it->trunc = 1;
        p++;
        break;
    case 'd': case 'i': case 'u': case 'o': case 'x': case 'X': case 'e': case 'E': case 'f': case 'F':
    case 'g': case 'G': case 'a': case 'A': case 'p': case 'T': case 't':
        p++;
        break;
    case '|':
        if (!bar) return false;
        break;
    default: return false;
    }
    if (bar) {
        if (s[p] != '|') return false;
        p++;
    }
    *i = p;
    return true;
}

static size_t emit(char *out, size_t cap, size_t n, const char *s, size_t k)
{
    size_t j;
    for (j = 0; j < k; j++, n++)
        if (n + 1 < cap) out[n] = s[j];
    return n;
}

static size_t emit_arg(char *out, size_t cap, size_t n, const fmt_item *it, const char *a)
{
    size_t len = strlen(a), pad = 0;
    char sp = ' ';
    bool space_prefix = false;
    if (it->trunc >= 0 && (size_t)it->trunc < len) len = (size_t)it->trunc;
    if (it->space && (len == 0 || (a[0] != '+' && a[0] != '-'))) space_prefix = true;
    if (it->width > len + space_prefix) pad = it->width - len - space_prefix;
    if (it->zero && !it->left) sp = '0';
    if (space_prefix) n = emit(out, cap, n, " ", 1);
    if (!it->left)
        for (; pad; pad--) n = emit(out, cap, n, &sp, 1);
    n = emit(out, cap, n, a, len);
    for (; pad; pad--) n = emit(out, cap, n, " ", 1);
    return n;
}

/* The string of argument i, fetched when the format reaches it (valid until the next call). */
typedef const char *(*fmt_arg_fn)(void *ctx, size_t i);

static int format_with(const char *fmt, fmt_arg_fn arg, void *ctx, size_t n_args, char *out, size_t cap, size_t *len)
{
    size_t n = 0, pass;
    int positional = -1; /* -1 unknown, 0 sequential, 1 positional */
    size_t max_arg = 0;
    /* pass 0 validates and counts arguments; pass 1 writes */
    for (pass = 0; pass < 2; pass++) {
        size_t i = 0, seq = 0;
        n = 0;
        while (fmt[i]) {
            fmt_item it = {-1, false, false, false, 0, -1};
            size_t lit = i;
            while (fmt[i] && fmt[i] != '%') i++;
            if (pass) n = emit(out, cap, n, fmt + lit, i - lit);
            if (!fmt[i]) break;
            i++; /* past % */
            if (fmt[i] == '%') {
                if (pass) n = emit(out, cap, n, "%", 1);
                i++;
                continue;
            }
            if (fmt[i] == '|') {
                size_t j = i + 1, num = 0;
                i++;
                while (isdig(fmt[j])) {
                    if (num < 100000u) num = num * 10u + (size_t)(fmt[j] - '0');
                    j++;
                }
                if (j > i && fmt[j] == '$') {
                    it.arg = (int)num - 1;
                    i = j + 1;
                    if (positional == 0) return KELP_ERR_PARSE;
                    positional = 1;
                } else {
                    if (positional == 1) return KELP_ERR_PARSE;
                    positional = 0;
                    it.arg = (int)seq++;
                }
                if (!parse_spec(fmt, &i, true, &it)) return KELP_ERR_PARSE;
            } else {
                size_t j = i, num = 0;
                while (isdig(fmt[j])) {
                    if (num < 100000u) num = num * 10u + (size_t)(fmt[j] - '0');
                    j++;
                }
                if (j > i && (fmt[j] == '%' || fmt[j] == '$')) {
                    if (positional == 0) return KELP_ERR_PARSE;
                    positional = 1;
                    it.arg = (int)num - 1;
                    i = j + 1;
                    if (fmt[j] == '$' && !parse_spec(fmt, &i, false, &it)) return KELP_ERR_PARSE;
                } else {
                    if (positional == 1) return KELP_ERR_PARSE;
                    positional = 0;
                    it.arg = (int)seq++;
                    if (!parse_spec(fmt, &i, false, &it)) return KELP_ERR_PARSE;
                }
            }
            if (it.arg < 0) return KELP_ERR_PARSE; /* %0% */
            if (!pass) {
                if ((size_t)it.arg + 1 > max_arg) max_arg = (size_t)it.arg + 1;
            } else {
                n = emit_arg(out, cap, n, &it, arg(ctx, (size_t)it.arg));
            }
        }
        /* boost::format: more arguments than the format uses -> too_many_args,
         * fewer -> too_few_args */
        if (!pass && n_args != max_arg) return KELP_ERR_RANGE;
    }
    if (cap) out[n < cap ? n : cap - 1] = '\0';
    if (len) *len = n;
    return n < cap ? KELP_OK : KELP_ERR_NOSPACE;
}

static const char *argv_arg(void *ctx, size_t i)
{
    return ((const char *const *)ctx)[i];
}

int kelp_dccl_format(const char *fmt, const char *const *args, size_t n_args, char *out, size_t cap, size_t *len)
{
    /* the cast drops only the const of the array itself, which argv_arg keeps */
    return format_with(fmt, argv_arg, (void *)(uintptr_t)args, n_args, out, cap, len);
}

/* ------------------------------------------------------------------ publish */
/* The arguments of one publication: every element of every <message_var> in order (one
 * element per publication for <repeat> messages). An argument with algorithms is run once,
 * in argument order, before formatting (algorithms may keep state), and its string kept
 * in the workspace; an argument without is a pure function of the values and is
 * formatted into the workspace when the format string reaches it. */
typedef struct pub_ctx {
    kelp_dccl_codec *cx;
    const kelp_dccl_msgdef *def;
    const kelp_dccl_val *vals;
    const kelp_dccl_publish *p;
    unsigned r;
} pub_ctx;

static const kelp_dccl_val *pub_ref(void *ctx, unsigned field, unsigned element)
{
    const pub_ctx *p = ctx;
    const kelp_dccl_field *f;
    if (field >= p->def->n_fields) return NULL;
    f = &p->def->fields[field];
    if (element >= f->array_length) element = 0;
    return &p->vals[f->slot + element];
}

/* Elements [*i0, *i1) of argument a's field for publication r. */
static const kelp_dccl_field *arg_field(const pub_ctx *pc, unsigned a, unsigned *i0, unsigned *i1)
{
    const kelp_dccl_field *f = &pc->def->fields[pc->p->args[a].field];
    *i0 = 0;
    *i1 = f->array_length;
    if (pc->def->repeat > 1) {
        /* one element per publication; single-entry fields (header) repeat */
        *i0 = f->array_length == 1 ? 0 : pc->r;
        *i1 = *i0 + 1;
    }
    return f;
}

static const char *pub_arg(void *ctx, size_t want)
{
    const pub_ctx *pc = ctx;
    kelp_dccl_work *w = &pc->cx->work;
    size_t na = 0;
    unsigned a, i0, i1;
    for (a = 0; a < pc->p->n_args; a++) {
        const kelp_dccl_field *f = arg_field(pc, a, &i0, &i1);
        if (want >= na + (i1 - i0)) {
            na += i1 - i0;
            continue;
        }
        if (pc->p->args[a].n_algs && pc->cx->algs) return w->pub.alg + w->pub.off[want];
        (void)kelp_dccl_val_to_str(&pc->vals[f->slot + i0 + (want - na)], w->pub.arg, sizeof w->pub.arg, NULL);
        return w->pub.arg;
    }
    return ""; /* never: the format checked the count */
}

/* Run the arguments with algorithms (in order) into the workspace; count all of them. */
static int pub_run_algs(pub_ctx *pc, size_t *n_args)
{
    kelp_dccl_codec *cx = pc->cx;
    kelp_dccl_work *w = &cx->work;
    size_t na = 0, used = 0;
    unsigned a, i0, i1, i;
    for (a = 0; a < pc->p->n_args; a++) {
        const kelp_dccl_pubarg *pa = &pc->p->args[a];
        const kelp_dccl_field *f = arg_field(pc, a, &i0, &i1);
        for (i = i0; i < i1; i++, na++) {
            size_t n, room;
            if (na >= KELP_DCCL_MAX_PUB_ARGS) return kelp_fail(&cx->diag, KELP_ERR_NOSPACE, "too many publish arguments");
            if (!pa->n_algs || !cx->algs) continue;
            w->pub.val = pc->vals[f->slot + i];
            dccl_apply_algs(cx->algs, pa->algs, pa->n_algs, &w->pub.val, i, pub_ref, pc);
            room = sizeof w->pub.alg - used;
            if (room > KELP_DCCL_MAX_STRLEN + 1) room = KELP_DCCL_MAX_STRLEN + 1;
            (void)kelp_dccl_val_to_str(&w->pub.val, w->pub.alg + used, room, &n);
            if (n > KELP_DCCL_MAX_STRLEN) n = KELP_DCCL_MAX_STRLEN; /* cut as a value's string is */
            if (n >= room) return kelp_fail(&cx->diag, KELP_ERR_NOSPACE, "publish algorithm results longer than KELP_DCCL_PUB_ALG_WORK");
            w->pub.off[na] = (uint16_t)used;
            used += n + 1u;
        }
    }
    *n_args = na;
    return KELP_OK;
}

size_t kelp_dccl_n_publications(const kelp_dccl_msgdef *def)
{
    return def ? (size_t)def->n_publishes * (def->repeat ? def->repeat : 1u) : 0;
}

int kelp_dccl_publish_all(kelp_dccl_codec *cx, const kelp_dccl_msgdef *def, const kelp_dccl_val *vals, size_t n_vals,
                          kelp_dccl_pub *out, size_t cap, size_t *n_out)
{
    pub_ctx pc;
    unsigned pi, r;
    size_t count = 0;
    kelp_diag_clear(&cx->diag);
    if (!def || !vals || !n_out || n_vals < def->n_slots) return kelp_fail(&cx->diag, KELP_ERR_ARG, "values array too short");
    pc.cx = cx;
    pc.def = def;
    pc.vals = vals;
    for (pi = 0; pi < def->n_publishes; pi++) {
        const kelp_dccl_publish *p = &def->publishes[pi];
        pc.p = p;
        for (r = 0; r < def->repeat; r++) {
            size_t na = 0, flen;
            kelp_dccl_pub *o;
            const char *fmt = p->format ? p->format : "";
            int rc;
            pc.r = r;
            rc = pub_run_algs(&pc, &na);
            if (rc) return rc;
            if (count >= cap) {
                /* no room: report what the format would have (bad format, too long) first */
                rc = format_with(fmt, pub_arg, &pc, na, NULL, 0, &flen);
                if (rc == KELP_ERR_NOSPACE && flen >= KELP_DCCL_MAX_PUBLEN)
                    return kelp_fail(&cx->diag, KELP_ERR_NOSPACE, "published value longer than KELP_DCCL_MAX_PUBLEN");
                if (rc && rc != KELP_ERR_NOSPACE)
                    return kelp_fail(&cx->diag, KELP_ERR_PARSE, "decode failed. check format string for this <publish />");
                return kelp_fail(&cx->diag, KELP_ERR_NOSPACE, "more publications than storage");
            }
            o = &out[count];
            rc = format_with(fmt, pub_arg, &pc, na, o->s, sizeof o->s, &flen);
            if (rc == KELP_ERR_NOSPACE) return kelp_fail(&cx->diag, KELP_ERR_NOSPACE, "published value longer than KELP_DCCL_MAX_PUBLEN");
            if (rc) return kelp_fail(&cx->diag, KELP_ERR_PARSE, "decode failed. check format string for this <publish />");
            count++;
            {
                size_t vn = strlen(p->var);
                if (vn >= sizeof o->var) vn = sizeof o->var - 1;
                memcpy(o->var, p->var, vn);
                o->var[vn] = '\0';
            }
            o->is_double = false;
            o->d = 0;
            switch (p->type) {
            case KELP_DCCL_PUB_STRING: break;
            case KELP_DCCL_PUB_DOUBLE:
            case KELP_DCCL_PUB_LONG:
            case KELP_DCCL_PUB_BOOL: {
                kelp_dccl_val *t = &cx->work.pub.val;
                double d = NAN;
                int64_t l = 0;
                bool b = false;
                kelp_dccl_val_set_strn(t, o->s, flen);
                if (p->type == KELP_DCCL_PUB_DOUBLE) {
                    if (!kelp_dccl_val_to_double(t, &d)) d = NAN;
                } else if (p->type == KELP_DCCL_PUB_LONG) {
                    if (!kelp_dccl_val_to_long(t, &l)) l = 0;
                    d = (double)l;
                } else {
                    if (!kelp_dccl_val_to_bool(t, &b)) b = false;
                    d = b ? 1 : 0;
                }
                o->is_double = true;
                o->d = d;
                break;
            }
            default: {
                double d;
                if (kelp_dccl_parse_double(o->s, flen, &d)) {
                    o->is_double = true;
                    o->d = d;
                }
                break;
            }
            }
        }
    }
    *n_out = count;
    return KELP_OK;
}
