/* kelp mission files: an in-place, allocation-free parser of MOOS .moos/.bhv text with the
 * protobuf-text blocks Goby apps use inside a ProcessConfig.
 *
 * Two modes. MOOS mode is line oriented: "Key = Value" (the first '=' splits, the value
 * runs to the end of the line) and "Kind = Name" followed by '{' opens a block. Inside a
 * block, a statement whose first significant character among '=', ':', '{' is not '='
 * switches to protobuf-text mode, which is token oriented and may span lines until the
 * braces it opened are closed.
 */
#include <string.h>
#include <kelp/mission.h>

#define MAX_DEPTH 16

typedef struct ps {
    kelp_mission *m;
    const char *s;
    size_t len, pos;
    int line;
    int stack[MAX_DEPTH]; /* node index of each open BLOCK / MSG */
    int depth;
    bool stack_pb[MAX_DEPTH];
    bool stack_set[MAX_DEPTH]; /* a .bhv "set VAR = VAL" block */
    int stack_line[MAX_DEPTH]; /* line of each open block's header */
} ps;

static bool sp(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

#define fail(p, line, why) fail_at((p), (line), kelp_fail(&(p)->m->diag, KELP_ERR_PARSE, why))

static int fail_at(ps *p, int line, int rc)
{
    (void)kelp_diag_where(&p->m->diag, line, 0);
    return rc;
}

static int add(ps *p, kelp_mission_kind kind, const char *k, size_t kl, const char *v, size_t vl, bool quoted,
               int line)
{
    kelp_mission *m = p->m;
    if (m->nodes) {
        if (m->nnodes >= m->cap) return KELP_ERR_NOSPACE;
        kelp_mission_node *n = &m->nodes[m->nnodes];
        n->kind = kind;
        n->key = k;
        n->klen = kl;
        n->val = v;
        n->vlen = vl;
        n->quoted = quoted;
        n->line = line;
        n->parent = p->depth ? p->stack[p->depth - 1] : -1;
    }
    return (int)m->nnodes++;
}

static void trim(const char **a, size_t *n)
{
    while (*n && sp(**a)) { (*a)++; (*n)--; }
    while (*n && sp((*a)[*n - 1])) (*n)--;
}

/* End of the current line's content, without a "//" comment (only at line start or after
 * white space, so that "udpm://host" survives). */
static size_t line_end(const ps *p, size_t from, size_t *next)
{
    size_t e = from;
    while (e < p->len && p->s[e] != '\n') e++;
    *next = e < p->len ? e + 1 : e;
    for (size_t i = from; i + 1 < e; i++) {
        if (p->s[i] == '/' && p->s[i + 1] == '/' && (i == from || sp(p->s[i - 1]))) return i;
    }
    return e;
}

/* ------------------------------------------------------------------ protobuf text mode */
static void pb_skip(ps *p)
{
    for (;;) {
        while (p->pos < p->len && (sp(p->s[p->pos]) || p->s[p->pos] == '\n')) {
            if (p->s[p->pos] == '\n') p->line++;
            p->pos++;
        }
        if (p->pos < p->len && p->s[p->pos] == '#') {
            while (p->pos < p->len && p->s[p->pos] != '\n') p->pos++;
            continue;
        }
        if (p->pos + 1 < p->len && p->s[p->pos] == '/' && p->s[p->pos + 1] == '/') {
            while (p->pos < p->len && p->s[p->pos] != '\n') p->pos++;
            continue;
        }
        return;
    }
}

static bool ident_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '.' ||
           c == '-' || c == '+';
}

/* One protobuf statement at p->pos: key ':' value | key '{' ... | key ':' '{' ... | '}' */
static int pb_statement(ps *p)
{
    int rc;
    const char *k = p->s + p->pos;
    size_t kl = 0;
    int kline = p->line;
    if (p->s[p->pos] == '[') {
        while (p->pos + kl < p->len && p->s[p->pos + kl] != ']' && p->s[p->pos + kl] != '\n') kl++;
        if (p->pos + kl >= p->len || p->s[p->pos + kl] != ']') return fail(p, kline, "unterminated [extension] name");
        kl++;
    } else {
        while (p->pos + kl < p->len && ident_char(p->s[p->pos + kl])) kl++;
    }
    if (kl == 0) return fail(p, kline, "expected a field name");
    p->pos += kl;
    pb_skip(p);
    bool colon = false;
    if (p->pos < p->len && p->s[p->pos] == ':') {
        colon = true;
        p->pos++;
        pb_skip(p);
    }
    if (p->pos < p->len && p->s[p->pos] == '{') {
        p->pos++;
        if (p->depth >= MAX_DEPTH) return fail(p, kline, "blocks nested too deeply");
        if ((rc = add(p, KELP_MN_MSG, k, kl, k, 0, false, kline)) < 0) return rc;
        p->stack_pb[p->depth] = true;
        p->stack_set[p->depth] = false;
        p->stack_line[p->depth] = kline;
        p->stack[p->depth++] = rc;
        return KELP_OK;
    }
    if (!colon) return fail(p, kline, "expected ':' or '{' after field name");
    if (p->pos >= p->len) return fail(p, kline, "missing value");
    const char *v = p->s + p->pos;
    size_t vl = 0;
    bool quoted = false;
    if (*v == '"' || *v == '\'') {
        char q = *v;
        size_t i = 1;
        while (p->pos + i < p->len && p->s[p->pos + i] != q && p->s[p->pos + i] != '\n') {
            if (p->s[p->pos + i] == '\\' && p->pos + i + 1 < p->len) i++;
            i++;
        }
        if (p->pos + i >= p->len || p->s[p->pos + i] != q) return fail(p, kline, "unterminated string");
        v++;
        vl = i - 1;
        quoted = true;
        p->pos += i + 1;
    } else {
        while (p->pos + vl < p->len && !sp(v[vl]) && v[vl] != '\n' && v[vl] != '#' && v[vl] != '}' && v[vl] != '{' &&
               v[vl] != ';' && v[vl] != ',')
            vl++;
        if (vl == 0) return fail(p, kline, "missing value");
        p->pos += vl;
    }
    if (p->pos < p->len && (p->s[p->pos] == ';' || p->s[p->pos] == ',')) p->pos++;
    rc = add(p, KELP_MN_FIELD, k, kl, v, vl, quoted, kline);
    return rc < 0 ? rc : KELP_OK;
}

/* Run protobuf mode until the pb depth returns to `base`. */
static int pb_run(ps *p, int base)
{
    int rc;
    for (;;) {
        pb_skip(p);
        if (p->pos >= p->len) return fail(p, p->stack_line[p->depth - 1], "block not closed: missing '}'");
        if (p->s[p->pos] == '}') {
            p->pos++;
            p->depth--;
            if (p->depth <= base) return KELP_OK;
            continue;
        }
        if ((rc = pb_statement(p)) < 0) return rc;
        if (p->depth <= base) return KELP_OK;
    }
}

/* ------------------------------------------------------------------ MOOS mode */
int kelp_mission_parse(kelp_mission *m, const char *text, size_t len, kelp_mission_node *nodes, size_t cap)
{
    if (!m || (!text && len)) return KELP_ERR_ARG;
    memset(m, 0, sizeof *m);
    m->text = text;
    m->len = len;
    m->nodes = nodes;
    m->cap = nodes ? cap : 0;
    ps p;
    memset(&p, 0, sizeof p);
    p.m = m;
    p.s = text;
    p.len = len;
    p.line = 1;
    int pending_block = -1; /* a "Kind = Name" line waiting for its '{' */
    int pending_line = 0;
    bool pending_set = false;
    int rc;
    while (p.pos < p.len) {
        size_t next;
        size_t end = line_end(&p, p.pos, &next);
        const char *a = p.s + p.pos;
        size_t n = end - p.pos;
        trim(&a, &n);
        int line = p.line;
        if (n == 0) {
            p.pos = next;
            p.line++;
            continue;
        }
        if (memchr(a, 0, n)) return fail(&p, line, "NUL byte in text");
        if (a[0] == '{') {
            if (pending_block < 0) return fail(&p, line, "'{' without a block header (Kind = Name) before it");
            if (p.depth >= MAX_DEPTH) return fail(&p, line, "blocks nested too deeply");
            p.stack_pb[p.depth] = false;
            p.stack_set[p.depth] = pending_set;
            p.stack_line[p.depth] = pending_line;
            p.stack[p.depth++] = pending_block;
            pending_block = -1;
            p.pos = (size_t)(a - p.s) + 1;
            /* anything after '{' on the same line is handled as a new line's content */
            continue;
        }
        if (pending_block >= 0) return fail(&p, pending_line, "block header not followed by '{'");
        if (a[0] == '}') {
            if (p.depth == 0) return fail(&p, line, "'}' without an open block");
            /* a .bhv mode declaration "set MODE = VAL { ... } ELSEVAL": the word after '}' is
             * kept as the block's last child, key "}else" */
            const char *w = a + 1;
            size_t wl = n - 1;
            trim(&w, &wl);
            if (wl && w[0] != '}' && w[0] != '#' && !(wl > 1 && w[0] == '/' && w[1] == '/') &&
                p.stack_set[p.depth - 1]) {
                size_t k = 0;
                while (k < wl && !sp(w[k]) && w[k] != '#') k++;
                if ((rc = add(&p, KELP_MN_PARAM, "}else", 5, w, k, false, line)) < 0) return rc;
                p.depth--;
                p.pos = (size_t)(w + k - p.s);
                continue;
            }
            p.depth--;
            p.pos = (size_t)(a - p.s) + 1;
            continue;
        }
        /* which of '=', ':', '{' comes first decides the syntax */
        size_t i = 0;
        while (i < n && a[i] != '=' && a[i] != ':' && a[i] != '{') i++;
        if (i < n && a[i] == '=' && a[0] != '[') {
            const char *k = a, *v = a + i + 1;
            size_t kl = i, vl = n - i - 1;
            trim(&k, &kl);
            trim(&v, &vl);
            if (kl == 0) return fail(&p, line, "missing parameter name before '='");
            /* "Kind = Name {" on one line, or "Kind = Name" with '{' on the next */
            bool brace_here = vl > 0 && v[vl - 1] == '{';
            if (brace_here) {
                vl--;
                trim(&v, &vl);
            }
            size_t nn;
            size_t la = next;
            /* look ahead for a line starting with '{' */
            bool is_block = brace_here;
            if (!is_block) {
                while (la < p.len) {
                    size_t e2 = line_end(&p, la, &nn);
                    const char *b = p.s + la;
                    size_t bl = e2 - la;
                    trim(&b, &bl);
                    if (bl == 0) { la = nn; continue; }
                    is_block = b[0] == '{';
                    break;
                }
            }
            if (is_block) {
                if (vl == 0) return fail(&p, line, "block header without a name");
                if ((rc = add(&p, KELP_MN_BLOCK, k, kl, v, vl, false, line)) < 0) return rc;
                bool is_set = kl > 4 && kelp_util_strieq_n(k, 3, "set") && sp(k[3]);
                if (brace_here) {
                    if (p.depth >= MAX_DEPTH) return fail(&p, line, "blocks nested too deeply");
                    p.stack_pb[p.depth] = false;
                    p.stack_set[p.depth] = is_set;
                    p.stack_line[p.depth] = line;
                    p.stack[p.depth++] = rc;
                } else {
                    pending_block = rc;
                    pending_line = line;
                    pending_set = is_set;
                }
            } else {
                if ((rc = add(&p, KELP_MN_PARAM, k, kl, v, vl, false, line)) < 0) return rc;
            }
            p.pos = next;
            p.line++;
            continue;
        }
        if (p.depth == 0) {
            if (i < n && (a[i] == ':' || a[i] == '{'))
                return fail(&p, line, "protobuf-style 'key: value' outside a ProcessConfig block");
            return fail(&p, line, "expected 'Name = Value'");
        }
        /* protobuf text statement(s), possibly spanning lines */
        p.pos = (size_t)(a - p.s);
        int base = p.depth;
        if ((rc = pb_statement(&p)) < 0) return rc;
        if (p.depth > base && (rc = pb_run(&p, base)) < 0) return rc;
        /* rest of this line: allow further statements "a: 1 b: 2" */
        for (;;) {
            while (p.pos < p.len && sp(p.s[p.pos])) p.pos++;
            if (p.pos >= p.len || p.s[p.pos] == '\n' || p.s[p.pos] == '#' || p.s[p.pos] == '}') break;
            if (p.pos + 1 < p.len && p.s[p.pos] == '/' && p.s[p.pos + 1] == '/') break;
            if ((rc = pb_statement(&p)) < 0) return rc;
            if (p.depth > base && (rc = pb_run(&p, base)) < 0) return rc;
        }
        if (p.pos < p.len && p.s[p.pos] == '#') {
            while (p.pos < p.len && p.s[p.pos] != '\n') p.pos++;
        }
        if (p.pos < p.len && p.s[p.pos] == '/') {
            while (p.pos < p.len && p.s[p.pos] != '\n') p.pos++;
        }
        if (p.pos < p.len && p.s[p.pos] == '\n') {
            p.pos++;
            p.line++;
        }
    }
    if (pending_block >= 0) return fail(&p, pending_line, "block header not followed by '{'");
    if (p.depth > 0) {
        return fail(&p, p.stack_line[p.depth - 1], "block not closed: missing '}'");
    }
    if (!nodes) return KELP_OK;
    return KELP_OK;
}

bool kelp_mission_key_is(const kelp_mission_node *n, const char *key)
{
    return kelp_util_strieq_n(n->key, n->klen, key);
}

bool kelp_mission_val_is(const kelp_mission_node *n, const char *val)
{
    return kelp_util_strieq_n(n->val, n->vlen, val);
}

int kelp_mission_block(const kelp_mission *m, const char *kind, const char *name)
{
    for (size_t i = 0; i < m->nnodes && m->nodes; i++) {
        const kelp_mission_node *n = &m->nodes[i];
        if (n->kind == KELP_MN_BLOCK && kelp_mission_key_is(n, kind) && kelp_mission_val_is(n, name)) return (int)i;
    }
    return -1;
}

int kelp_mission_next(const kelp_mission *m, int parent, int after, const char *key)
{
    if (!m->nodes) return -1;
    for (size_t i = after < 0 ? 0 : (size_t)after + 1; i < m->nnodes; i++) {
        const kelp_mission_node *n = &m->nodes[i];
        if (n->parent != parent) continue;
        if (!key || kelp_mission_key_is(n, key)) return (int)i;
    }
    return -1;
}

int kelp_mission_copy(const kelp_mission_node *n, char *buf, size_t cap)
{
    size_t o = 0;
    for (size_t i = 0; i < n->vlen; i++) {
        char c = n->val[i];
        if (n->quoted && c == '\\' && i + 1 < n->vlen) {
            c = n->val[++i];
            if (c == 'n') c = '\n';
            else if (c == 't') c = '\t';
        }
        if (o + 1 >= cap) return KELP_ERR_NOSPACE;
        buf[o++] = c;
    }
    if (cap == 0) return KELP_ERR_NOSPACE;
    buf[o] = 0;
    return KELP_OK;
}

int kelp_mission_double(const kelp_mission_node *n, double *out)
{
    return kelp_util_parse_double(n->val, n->vlen, out);
}

int kelp_mission_bool(const kelp_mission_node *n, bool *out)
{
    if (kelp_mission_val_is(n, "true") || kelp_mission_val_is(n, "1") || kelp_mission_val_is(n, "yes")) {
        *out = true;
        return KELP_OK;
    }
    if (kelp_mission_val_is(n, "false") || kelp_mission_val_is(n, "0") || kelp_mission_val_is(n, "no")) {
        *out = false;
        return KELP_OK;
    }
    return KELP_ERR_PARSE;
}
