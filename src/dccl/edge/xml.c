/* kelp DCCL: the XML message file loader (expat), with the checks Goby 1.1 makes
 * (schema validation as message_schema.xsd, DCCLMessage::preprocess, Publish::initialize,
 * algorithm name and reference checks). Allocates at load time only. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <expat.h>

#include <kelp/edge/dccl.h>

/* ------------------------------------------------------------------ arena */
typedef struct arena_blk {
    struct arena_blk *next;
    size_t used, cap;
    max_align_t data[];
} arena_blk;

static void *arena_alloc(void **arena, size_t n)
{
    arena_blk *b = *arena;
    n = (n + sizeof(max_align_t) - 1) / sizeof(max_align_t) * sizeof(max_align_t);
    if (!b || b->cap - b->used < n) {
        size_t cap = n > 16384 ? n : 16384;
        arena_blk *nb = malloc(sizeof *nb + cap);
        if (!nb) return NULL;
        nb->next = b;
        nb->used = 0;
        nb->cap = cap;
        *arena = nb;
        b = nb;
    }
    {
        void *p = (char *)b->data + b->used;
        b->used += n;
        memset(p, 0, n);
        return p;
    }
}

static char *arena_strndup(void **arena, const char *s, size_t n)
{
    char *p = arena_alloc(arena, n + 1);
    if (p) {
        memcpy(p, s, n);
        p[n] = '\0';
    }
    return p;
}

void kelp_dccl_loaded_init(kelp_dccl_loaded *ld)
{
    memset(ld, 0, sizeof *ld);
}

void kelp_dccl_loaded_free(kelp_dccl_loaded *ld)
{
    arena_blk *b = ld->arena;
    while (b) {
        arena_blk *n = b->next;
        free(b);
        b = n;
    }
    free(ld->msgs);
    memset(ld, 0, sizeof *ld);
}

/* ------------------------------------------------------------------ parse state */
enum ctx_kind { C_ROOT, C_SET, C_MSG, C_HEADER, C_HEADVAR, C_LAYOUT, C_FIELD, C_RECEIPT, C_PUBLISH, C_QUEUING, C_LEAF };

#define MAX_DEPTH 16
#define MAX_ITEMS 4096

typedef struct pfield {
    kelp_dccl_field f;
    const char *alg_text; /* algorithm attribute */
    int alg_line;
    const char **enums;
    size_t n_enum, cap_enum;
    unsigned seen;        /* bit per child element (xs:all) */
    bool have_max, have_min, have_prec, have_len, have_bytes, have_value, have_name;
    int line;
} pfield;

typedef struct parg {
    const char *name;
    const char *alg_text;
    int line;
} parg;

typedef struct ppub {
    const char *var;
    kelp_dccl_pubtype type;
    const char *format;
    bool all, have_format;
    parg *args;
    size_t n_args, cap_args;
    int line;
} ppub;

typedef struct pmsg {
    kelp_dccl_msgdef def;
    pfield *fields; /* [0..7] header */
    size_t n_fields, cap_fields;
    ppub *pubs;
    size_t n_pubs, cap_pubs;
    unsigned seen_msg, seen_header, seen_queuing;
    bool repeat_auto, have_layout_child, have_publish;
    bool have_name, have_size, have_layout;
    int line;
} pmsg;

typedef struct parser {
    kelp_dccl_loaded *ld;
    const kelp_dccl_algs *algs;
    const char *file;
    XML_Parser xp;
    kelp_diag *d; /* the caller's record (may be NULL) */
    int rc;
    int depth;
    enum ctx_kind kind[MAX_DEPTH];
    char name[MAX_DEPTH][32];
    int line[MAX_DEPTH];
    char *text;
    size_t tlen, tcap;
    pmsg *msg;     /* current message */
    pfield *field; /* current layout/header field */
    ppub *pub;
    int headvar;   /* header field index of <time>/<src_id>/<dest_id> */
    bool saw_root;
} parser;

static void fail(parser *p, int rc, int line, const char *fmt, ...) KELP_PRINTF(4, 5);

static void fail(parser *p, int rc, int line, const char *fmt, ...)
{
    char why[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized): va_start above */
    va_end(ap);
    if (p->rc) return;
    p->rc = rc;
    if (p->xp) XML_StopParser(p->xp, XML_FALSE);
    (void)kelp_failf(p->d, rc, "%s:%d: %s", p->file, line, why);
    (void)kelp_diag_where(p->d, line, 0);
}

static int cur_line(parser *p)
{
    return p->xp ? (int)XML_GetCurrentLineNumber(p->xp) : 0;
}

static void *grow(parser *p, void *arr, size_t *cap, size_t n, size_t elem)
{
    /* arrays live in the arena: grow by copying */
    void *na;
    size_t nc;
    if (n < *cap) return arr;
    if (n >= MAX_ITEMS) {
        fail(p, KELP_ERR_RANGE, cur_line(p), "too many items (more than %d)", MAX_ITEMS);
        return NULL;
    }
    nc = *cap ? *cap * 2 : 8;
    na = arena_alloc(&p->ld->arena, nc * elem);
    if (!na) {
        fail(p, KELP_ERR_NOSPACE, cur_line(p), "out of memory");
        return NULL;
    }
    if (arr) memcpy(na, arr, n * elem);
    *cap = nc;
    return na;
}

static const char *dup(parser *p, const char *s, size_t n)
{
    const char *d = arena_strndup(&p->ld->arena, s, n);
    if (!d) fail(p, KELP_ERR_NOSPACE, cur_line(p), "out of memory");
    return d;
}

/* trimmed copy of the collected text */
static void trimmed(const parser *p, const char **s, size_t *n)
{
    const char *a = p->text ? p->text : "";
    size_t k = p->tlen;
    while (k && (*a == ' ' || *a == '\t' || *a == '\n' || *a == '\r')) { a++; k--; }
    while (k && (a[k - 1] == ' ' || a[k - 1] == '\t' || a[k - 1] == '\n' || a[k - 1] == '\r')) k--;
    *s = a;
    *n = k;
}

/* ------------------------------------------------------------------ value checks (schema types) */
static bool parse_integer(const char *s, size_t n, long *out)
{
    size_t i = 0;
    long v = 0;
    bool neg = false;
    if (n == 0) return false;
    if (s[0] == '+' || s[0] == '-') { neg = s[0] == '-'; i = 1; }
    if (i == n) return false;
    for (; i < n; i++) {
        if (s[i] < '0' || s[i] > '9') return false;
        if (v > (LONG_MAX - 9) / 10) return false; /* no overflow */
        v = v * 10 + (s[i] - '0');
    }
    *out = neg ? -v : v;
    return true;
}

static bool parse_xsd_double(const char *s, size_t n, double *out)
{
    if (n == 3 && memcmp(s, "INF", 3) == 0) { *out = HUGE_VAL; return true; }
    if (n == 4 && memcmp(s, "-INF", 4) == 0) { *out = -HUGE_VAL; return true; }
    if (n == 3 && memcmp(s, "NaN", 3) == 0) { *out = NAN; return true; }
    {
        size_t i = 0, d = 0;
        if (i < n && (s[i] == '+' || s[i] == '-')) i++;
        for (; i < n; i++) {
            char c = s[i];
            if ((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-') d++;
            else return false;
        }
        if (!d) return false;
    }
    return kelp_dccl_parse_double(s, n, out);
}

/* ------------------------------------------------------------------ element tables */
typedef struct child_rule {
    const char *name;
    enum ctx_kind kind; /* context the child opens */
    unsigned bit;       /* xs:all duplicate detection; 0 = may repeat */
} child_rule;

static const child_rule MSG_CHILDREN[] = {
    {"name", C_LEAF, 1u << 0},
    {"id", C_LEAF, 1u << 1},
    {"repeat", C_LEAF, 1u << 2},
    {"destination_var", C_LEAF, 1u << 3},
    {"destination_moos_var", C_LEAF, 1u << 4},
    {"size", C_LEAF, 1u << 5},
    {"outgoing_hex_moos_var", C_LEAF, 1u << 6},
    {"incoming_hex_moos_var", C_LEAF, 1u << 7},
    {"trigger", C_LEAF, 1u << 8},
    {"trigger_time", C_LEAF, 1u << 9},
    {"trigger_var", C_LEAF, 1u << 10},
    {"trigger_moos_var", C_LEAF, 1u << 11},
    {"header", C_HEADER, 1u << 12},
    {"layout", C_LAYOUT, 1u << 13},
    {"on_receipt", C_RECEIPT, 1u << 14},
    {"queuing", C_QUEUING, 1u << 15},
    {NULL, C_LEAF, 0}};
static const child_rule HEADER_CHILDREN[] = {
    {"id", C_LEAF, 1u << 0}, {"time", C_HEADVAR, 1u << 1}, {"src_id", C_HEADVAR, 1u << 2},
    {"dest_id", C_HEADVAR, 1u << 3}, {NULL, C_LEAF, 0}};
static const child_rule HEADVAR_CHILDREN[] = {
    {"name", C_LEAF, 1u << 0}, {"src_var", C_LEAF, 1u << 1}, {"moos_var", C_LEAF, 1u << 2}, {NULL, C_LEAF, 0}};
static const child_rule LAYOUT_CHILDREN[] = {
    {"static", C_FIELD, 0}, {"int", C_FIELD, 0}, {"bool", C_FIELD, 0}, {"float", C_FIELD, 0},
    {"string", C_FIELD, 0}, {"hex", C_FIELD, 0}, {"enum", C_FIELD, 0}, {NULL, C_LEAF, 0}};
static const child_rule RECEIPT_CHILDREN[] = {{"publish", C_PUBLISH, 0}, {NULL, C_LEAF, 0}};
static const child_rule PUBLISH_CHILDREN[] = {{"format", C_LEAF, 0},      {"publish_var", C_LEAF, 0},
                                              {"moos_var", C_LEAF, 0},    {"message_var", C_LEAF, 0},
                                              {"all", C_LEAF, 0},         {NULL, C_LEAF, 0}};
static const child_rule QUEUING_CHILDREN[] = {
    {"ack", C_LEAF, 1u << 0},        {"blackout_time", C_LEAF, 1u << 1}, {"max_queue", C_LEAF, 1u << 2},
    {"value_base", C_LEAF, 1u << 3}, {"ttl", C_LEAF, 1u << 4},           {"newest_first", C_LEAF, 1u << 5},
    {"priority_base", C_LEAF, 1u << 6}, {"priority_time_const", C_LEAF, 1u << 7}, {NULL, C_LEAF, 0}};

/* children of each layout field type (enum <value> may repeat) */
static const char *const FIELD_KIDS_STATIC[] = {"name", "value", NULL};
static const char *const FIELD_KIDS_INT[] = {"name", "src_var", "moos_var", "max", "min", "array_length", "max_delta", NULL};
static const char *const FIELD_KIDS_BOOL[] = {"name", "src_var", "moos_var", "array_length", NULL};
static const char *const FIELD_KIDS_FLOAT[] = {"name",      "src_var",      "moos_var",  "max", "min",
                                               "precision", "array_length", "max_delta", NULL};
static const char *const FIELD_KIDS_STRING[] = {"name", "src_var", "moos_var", "array_length", "max_length", NULL};
static const char *const FIELD_KIDS_HEX[] = {"name", "src_var", "moos_var", "array_length", "num_bytes", NULL};
static const char *const FIELD_KIDS_ENUM[] = {"name", "src_var", "moos_var", "array_length", "value", NULL};

static const char *const *field_kids(kelp_dccl_type t)
{
    switch (t) {
    case KELP_DCCL_T_STATIC: return FIELD_KIDS_STATIC;
    case KELP_DCCL_T_INT: return FIELD_KIDS_INT;
    case KELP_DCCL_T_BOOL: return FIELD_KIDS_BOOL;
    case KELP_DCCL_T_FLOAT: return FIELD_KIDS_FLOAT;
    case KELP_DCCL_T_STRING: return FIELD_KIDS_STRING;
    case KELP_DCCL_T_HEX: return FIELD_KIDS_HEX;
    default: return FIELD_KIDS_ENUM;
    }
}

static const char *type_tag(kelp_dccl_type t)
{
    static const char *const N[] = {"static", "int", "float", "bool", "string", "enum", "hex"};
    return t <= KELP_DCCL_T_HEX ? N[t] : "header";
}

/* ------------------------------------------------------------------ start */
static const char *attr(const XML_Char **atts, const char *name)
{
    int i;
    for (i = 0; atts[i]; i += 2)
        if (strcmp(atts[i], name) == 0) return atts[i + 1];
    return NULL;
}

static bool check_attrs(parser *p, const char *el, const XML_Char **atts, const char *a1, const char *a2)
{
    int i;
    for (i = 0; atts[i]; i += 2) {
        const char *a = atts[i];
        if ((a1 && strcmp(a, a1) == 0) || (a2 && strcmp(a, a2) == 0)) continue;
        if (strncmp(a, "xmlns", 5) == 0 || strncmp(a, "xsi:", 4) == 0) continue;
        fail(p, KELP_ERR_PARSE, cur_line(p), "attribute \"%s\" is not allowed on <%s>", a, el);
        return false;
    }
    return true;
}

static pfield *new_field(parser *p, kelp_dccl_type t, int line)
{
    pmsg *m = p->msg;
    pfield *f;
    pfield *nf = grow(p, m->fields, &m->cap_fields, m->n_fields, sizeof *m->fields);
    if (!nf) return NULL;
    m->fields = nf;
    f = &m->fields[m->n_fields++];
    memset(f, 0, sizeof *f);
    f->f.type = t;
    f->f.array_length = 1;
    f->line = line;
    return f;
}

static pmsg *new_msg(parser *p, int line)
{
    pmsg *m = arena_alloc(&p->ld->arena, sizeof *m);
    unsigned h;
    if (!m) {
        fail(p, KELP_ERR_NOSPACE, line, "out of memory");
        return NULL;
    }
    m->line = line;
    m->def.repeat = 1;
    m->def.queuing.ack = true;
    m->def.queuing.newest_first = true;
    m->def.queuing.value_base = 1;
    m->def.queuing.ttl = 1800;
    p->msg = m;
    for (h = 0; h < KELP_DCCL_N_HEAD; h++) {
        pfield *f = new_field(p, KELP_DCCL_T_HEAD_CCL_ID, line);
        if (!f) return NULL;
        f->f.name = kelp_dccl_head_default_name(h);
    }
    return m;
}

static void XMLCALL on_start(void *ud, const XML_Char *el, const XML_Char **atts)
{
    parser *p = ud;
    int line = cur_line(p);
    enum ctx_kind parent, kind = C_LEAF;
    const child_rule *rules = NULL;
    unsigned *seen = NULL;
    if (p->rc) return;
    if (p->depth >= MAX_DEPTH - 1) {
        fail(p, KELP_ERR_PARSE, line, "elements nested too deeply");
        return;
    }
    parent = p->depth ? p->kind[p->depth - 1] : C_ROOT;
    p->tlen = 0;
    if (parent != C_ROOT && parent != C_SET && (!p->msg || ((parent == C_FIELD || parent == C_HEADVAR) && !p->field) ||
                                                 (parent == C_PUBLISH && !p->pub))) {
        fail(p, KELP_ERR_PARSE, line, "internal: no current message");
        return;
    }
    switch (parent) {
    case C_ROOT:
        if (strcmp(el, "message_set") != 0) {
            fail(p, KELP_ERR_PARSE, line, "root element must be <message_set>, not <%s>", el);
            return;
        }
        kind = C_SET;
        p->saw_root = true;
        if (!check_attrs(p, el, atts, NULL, NULL)) return;
        break;
    case C_SET:
        if (strcmp(el, "message") != 0) {
            fail(p, KELP_ERR_PARSE, line, "unexpected <%s> in <message_set> (only <message>)", el);
            return;
        }
        kind = C_MSG;
        if (!check_attrs(p, el, atts, NULL, NULL)) return;
        if (!new_msg(p, line)) return;
        break;
    case C_MSG: rules = MSG_CHILDREN; seen = &p->msg->seen_msg; break;
    case C_HEADER: rules = HEADER_CHILDREN; seen = &p->msg->seen_header; break;
    case C_HEADVAR: rules = HEADVAR_CHILDREN; seen = &p->field->seen; break;
    case C_LAYOUT: rules = LAYOUT_CHILDREN; break;
    case C_RECEIPT: rules = RECEIPT_CHILDREN; break;
    case C_PUBLISH: rules = PUBLISH_CHILDREN; break;
    case C_QUEUING: rules = QUEUING_CHILDREN; seen = &p->msg->seen_queuing; break;
    case C_FIELD: {
        const char *const *k = field_kids(p->field->f.type);
        unsigned i;
        for (i = 0; k[i]; i++)
            if (strcmp(k[i], el) == 0) break;
        if (!k[i]) {
            fail(p, KELP_ERR_PARSE, line, "unexpected <%s> in <%s>", el, type_tag(p->field->f.type));
            return;
        }
        if (strcmp(el, "value") != 0 || p->field->f.type != KELP_DCCL_T_ENUM) {
            if (p->field->seen & (1u << i)) {
                fail(p, KELP_ERR_PARSE, line, "duplicate <%s> in <%s>", el, type_tag(p->field->f.type));
                return;
            }
            p->field->seen |= 1u << i;
        }
        kind = C_LEAF;
        if (strcmp(el, "src_var") == 0 || strcmp(el, "moos_var") == 0) {
            const char *key = attr(atts, "key");
            if (!check_attrs(p, el, atts, "key", NULL)) return;
            if (key) p->field->f.src_key = dup(p, key, strlen(key));
        } else if (!check_attrs(p, el, atts, NULL, NULL)) {
            return;
        }
        break;
    }
    case C_LEAF:
        fail(p, KELP_ERR_PARSE, line, "unexpected <%s> inside <%s>", el, p->name[p->depth - 1]);
        return;
    default: break;
    }
    if (rules) {
        unsigned i;
        for (i = 0; rules[i].name; i++)
            if (strcmp(rules[i].name, el) == 0) break;
        if (!rules[i].name) {
            fail(p, KELP_ERR_PARSE, line, "unexpected <%s> in <%s>", el, p->name[p->depth - 1]);
            return;
        }
        if (seen && rules[i].bit) {
            if (*seen & rules[i].bit) {
                fail(p, KELP_ERR_PARSE, line, "duplicate <%s> in <%s>", el, p->name[p->depth - 1]);
                return;
            }
            *seen |= rules[i].bit;
        }
        kind = rules[i].kind;
        /* element-specific attributes and actions */
        if (parent == C_MSG && (strcmp(el, "trigger_var") == 0 || strcmp(el, "trigger_moos_var") == 0)) {
            const char *mc = attr(atts, "mandatory_content");
            if (!check_attrs(p, el, atts, "mandatory_content", NULL)) return;
            if (mc) p->msg->def.trigger_mandatory = dup(p, mc, strlen(mc));
        } else if (parent == C_MSG && (strcmp(el, "destination_var") == 0 || strcmp(el, "destination_moos_var") == 0)) {
            const char *key = attr(atts, "key");
            if (!check_attrs(p, el, atts, "key", NULL)) return;
            if (key) p->msg->fields[KELP_DCCL_H_DEST].f.name = dup(p, key, strlen(key));
        } else if (parent == C_HEADVAR && (strcmp(el, "src_var") == 0 || strcmp(el, "moos_var") == 0)) {
            const char *key = attr(atts, "key");
            if (!check_attrs(p, el, atts, "key", NULL)) return;
            if (key) p->field->f.src_key = dup(p, key, strlen(key));
        } else if (kind == C_HEADVAR) {
            const char *alg = attr(atts, "algorithm");
            if (!check_attrs(p, el, atts, "algorithm", NULL)) return;
            p->headvar = strcmp(el, "time") == 0 ? KELP_DCCL_H_TIME
                                                 : (strcmp(el, "src_id") == 0 ? KELP_DCCL_H_SRC : KELP_DCCL_H_DEST);
            p->field = &p->msg->fields[p->headvar];
            p->field->seen = 0;
            p->field->line = line;
            if (alg) {
                p->field->alg_text = dup(p, alg, strlen(alg));
                p->field->alg_line = line;
            }
        } else if (kind == C_FIELD) {
            static const kelp_dccl_type T[] = {KELP_DCCL_T_STATIC, KELP_DCCL_T_INT,    KELP_DCCL_T_BOOL,
                                               KELP_DCCL_T_FLOAT,  KELP_DCCL_T_STRING, KELP_DCCL_T_HEX,
                                               KELP_DCCL_T_ENUM};
            const char *alg = attr(atts, "algorithm");
            if (!check_attrs(p, el, atts, "algorithm", NULL)) return;
            p->field = new_field(p, T[i], line);
            if (!p->field) return;
            p->msg->have_layout_child = true;
            if (alg) {
                p->field->alg_text = dup(p, alg, strlen(alg));
                p->field->alg_line = line;
            }
        } else if (kind == C_PUBLISH) {
            ppub *np;
            if (!check_attrs(p, el, atts, NULL, NULL)) return;
            np = grow(p, p->msg->pubs, &p->msg->cap_pubs, p->msg->n_pubs, sizeof *p->msg->pubs);
            if (!np) return;
            p->msg->pubs = np;
            p->pub = &p->msg->pubs[p->msg->n_pubs++];
            memset(p->pub, 0, sizeof *p->pub);
            p->pub->line = line;
            p->msg->have_publish = true;
        } else if (parent == C_PUBLISH && (strcmp(el, "publish_var") == 0 || strcmp(el, "moos_var") == 0)) {
            const char *t = attr(atts, "type");
            if (!check_attrs(p, el, atts, "type", NULL)) return;
            if (t) {
                if (strcmp(t, "double") == 0) p->pub->type = KELP_DCCL_PUB_DOUBLE;
                else if (strcmp(t, "string") == 0) p->pub->type = KELP_DCCL_PUB_STRING;
                else if (strcmp(t, "long") == 0) p->pub->type = KELP_DCCL_PUB_LONG;
                else if (strcmp(t, "bool") == 0) p->pub->type = KELP_DCCL_PUB_BOOL;
            }
        } else if (parent == C_PUBLISH && strcmp(el, "message_var") == 0) {
            const char *alg = attr(atts, "algorithm");
            parg *na;
            if (!check_attrs(p, el, atts, "algorithm", NULL)) return;
            na = grow(p, p->pub->args, &p->pub->cap_args, p->pub->n_args, sizeof *p->pub->args);
            if (!na) return;
            p->pub->args = na;
            memset(&na[p->pub->n_args], 0, sizeof *na);
            na[p->pub->n_args].line = line;
            if (alg) na[p->pub->n_args].alg_text = dup(p, alg, strlen(alg));
            p->pub->n_args++;
        } else if (parent == C_PUBLISH && strcmp(el, "all") == 0) {
            if (!check_attrs(p, el, atts, NULL, NULL)) return;
            p->pub->all = true;
        } else {
            if (!check_attrs(p, el, atts, NULL, NULL)) return;
        }
    }
    if (p->rc) return;
    p->kind[p->depth] = kind;
    snprintf(p->name[p->depth], sizeof p->name[0], "%s", el);
    p->line[p->depth] = line;
    p->depth++;
}

static void XMLCALL on_text(void *ud, const XML_Char *s, int len)
{
    parser *p = ud;
    if (p->rc || len <= 0) return;
    if (p->depth && p->kind[p->depth - 1] != C_LEAF) {
        int i;
        for (i = 0; i < len; i++) {
            if (s[i] != ' ' && s[i] != '\t' && s[i] != '\n' && s[i] != '\r') {
                fail(p, KELP_ERR_PARSE, cur_line(p), "unexpected text in <%s>", p->name[p->depth - 1]);
                return;
            }
        }
        return;
    }
    if (p->tlen + (size_t)len + 1 > p->tcap) {
        size_t nc = (p->tlen + (size_t)len + 1) * 2;
        char *nt;
        if (nc > 1u << 20) {
            fail(p, KELP_ERR_RANGE, cur_line(p), "element text too long");
            return;
        }
        nt = realloc(p->text, nc);
        if (!nt) {
            fail(p, KELP_ERR_NOSPACE, cur_line(p), "out of memory");
            return;
        }
        p->text = nt;
        p->tcap = nc;
    }
    memcpy(p->text + p->tlen, s, (size_t)len);
    p->tlen += (size_t)len;
}

/* ------------------------------------------------------------------ end */
static bool want_int(parser *p, const char *el, long *out, long lo, long hi)
{
    const char *s;
    size_t n;
    trimmed(p, &s, &n);
    if (!parse_integer(s, n, out)) {
        fail(p, KELP_ERR_PARSE, p->line[p->depth - 1], "<%s> must be an integer, not \"%.*s\"", el, (int)n, s);
        return false;
    }
    if (*out < lo || *out > hi) {
        fail(p, KELP_ERR_RANGE, p->line[p->depth - 1], "<%s> %ld out of range [%ld, %ld]", el, *out, lo, hi);
        return false;
    }
    return true;
}

static bool want_double(parser *p, const char *el, double *out)
{
    const char *s;
    size_t n;
    trimmed(p, &s, &n);
    if (!parse_xsd_double(s, n, out)) {
        fail(p, KELP_ERR_PARSE, p->line[p->depth - 1], "<%s> must be a number, not \"%.*s\"", el, (int)n, s);
        return false;
    }
    return true;
}

/* a number that is not inf or nan (Goby's arithmetic on it would be meaningless) */
static bool want_finite(parser *p, const char *el, double *out)
{
    if (!want_double(p, el, out)) return false;
    if (!isfinite(*out)) {
        fail(p, KELP_ERR_RANGE, p->line[p->depth - 1], "<%s> must be a finite number", el);
        return false;
    }
    return true;
}

static bool text_bool(parser *p)
{
    const char *s;
    size_t n;
    trimmed(p, &s, &n);
    return (n == 4 && (s[0] | 32) == 't' && (s[1] | 32) == 'r' && (s[2] | 32) == 'u' && (s[3] | 32) == 'e') ||
           (n == 1 && s[0] == '1');
}

static const char *text_dup(parser *p)
{
    const char *s;
    size_t n;
    trimmed(p, &s, &n);
    return dup(p, s, n);
}

static void end_field_leaf(parser *p, const char *el)
{
    pfield *f = p->field;
    long l;
    double d;
    if (strcmp(el, "name") == 0) {
        f->f.name = text_dup(p);
        f->have_name = true;
    } else if (strcmp(el, "src_var") == 0 || strcmp(el, "moos_var") == 0) {
        f->f.src_var = text_dup(p);
    } else if (strcmp(el, "value") == 0) {
        if (f->f.type == KELP_DCCL_T_STATIC) {
            f->f.static_value = text_dup(p);
            f->have_value = true;
        } else {
            const char **ne = grow(p, (void *)f->enums, &f->cap_enum, f->n_enum, sizeof *f->enums);
            if (!ne) return;
            f->enums = ne;
            f->enums[f->n_enum++] = text_dup(p);
        }
    } else if (strcmp(el, "max") == 0) {
        /* xs:integer for <int>, but Goby reads every bound as a double (4000000000, 1e12) */
        if (want_finite(p, el, &d)) f->f.max = d;
        f->have_max = true;
    } else if (strcmp(el, "min") == 0) {
        if (want_finite(p, el, &d)) f->f.min = d;
        f->have_min = true;
    } else if (strcmp(el, "precision") == 0) {
        if (want_int(p, el, &l, -30, 30)) f->f.precision = (int)l;
        f->have_prec = true;
    } else if (strcmp(el, "max_delta") == 0) {
        if (want_finite(p, el, &d)) f->f.max_delta = d;
        f->f.has_delta = true;
    } else if (strcmp(el, "array_length") == 0) {
        if (want_int(p, el, &l, 1, 4096)) f->f.array_length = (uint16_t)l;
    } else if (strcmp(el, "max_length") == 0) {
        if (want_int(p, el, &l, 0, KELP_DCCL_MAX_STRLEN)) f->f.max_length = (uint16_t)l;
        f->have_len = true;
    } else if (strcmp(el, "num_bytes") == 0) {
        if (want_int(p, el, &l, 0, KELP_DCCL_MAX_STRLEN / 2)) f->f.num_bytes = (uint16_t)l;
        f->have_bytes = true;
    }
}

static void end_field(parser *p)
{
    pfield *f = p->field;
    int line = p->line[p->depth - 1];
    const char *tag = type_tag(f->f.type);
    if (!f->have_name) { fail(p, KELP_ERR_PARSE, line, "<%s> needs a <name>", tag); return; }
    switch (f->f.type) {
    case KELP_DCCL_T_STATIC:
        if (!f->have_value) fail(p, KELP_ERR_PARSE, line, "<static> %s needs a <value>", f->f.name);
        break;
    case KELP_DCCL_T_INT:
        if (!f->have_max || !f->have_min) fail(p, KELP_ERR_PARSE, line, "<int> %s needs <max> and <min>", f->f.name);
        break;
    case KELP_DCCL_T_FLOAT:
        if (!f->have_max || !f->have_min || !f->have_prec)
            fail(p, KELP_ERR_PARSE, line, "<float> %s needs <max>, <min> and <precision>", f->f.name);
        break;
    case KELP_DCCL_T_STRING:
        if (!f->have_len) fail(p, KELP_ERR_PARSE, line, "<string> %s needs a <max_length>", f->f.name);
        break;
    case KELP_DCCL_T_HEX:
        if (!f->have_bytes) fail(p, KELP_ERR_PARSE, line, "<hex> %s needs a <num_bytes>", f->f.name);
        break;
    default: break;
    }
    f->f.enum_values = f->enums;
    f->f.n_enum = (uint16_t)f->n_enum;
    if (isnan(f->f.min) || isnan(f->f.max) || isinf(f->f.min) || isinf(f->f.max))
        fail(p, KELP_ERR_RANGE, line, "<%s> %s: <min>/<max> must be finite", tag, f->f.name);
}

/* split "a, b:r1 :r2" (blanks stripped) into calls and resolve the references */
static int field_index(const pmsg *m, const char *name)
{
    size_t i;
    for (i = KELP_DCCL_N_HEAD; i < m->n_fields; i++)
        if (strcmp(m->fields[i].f.name, name) == 0) return (int)i;
    for (i = 0; i < KELP_DCCL_N_HEAD; i++)
        if (strcmp(m->fields[i].f.name, name) == 0) return (int)i;
    return -1;
}

static bool parse_algs(parser *p, const pmsg *m, const char *text, int line, const kelp_dccl_algcall **out,
                       uint8_t *n_out)
{
    char buf[1024];
    size_t n = 0, i, ncalls = 0;
    kelp_dccl_algcall *calls;
    char *s, *save = NULL;
    for (i = 0; text[i] && n < sizeof buf - 1; i++)
        if (text[i] != ' ' && text[i] != '\t' && text[i] != '\n' && text[i] != '\r') buf[n++] = text[i];
    buf[n] = '\0';
    for (i = 0; i <= n; i++)
        if (buf[i] == ',' || buf[i] == '\0') ncalls++;
    if (ncalls > 255) {
        fail(p, KELP_ERR_RANGE, line, "too many algorithms");
        return false;
    }
    calls = arena_alloc(&p->ld->arena, ncalls * sizeof *calls);
    if (!calls) {
        fail(p, KELP_ERR_NOSPACE, line, "out of memory");
        return false;
    }
    ncalls = 0;
    /* explode on ',' keeps empty pieces; an empty algorithm name matches nothing */
    s = buf;
    for (;;) {
        char *comma = strchr(s, ',');
        char *piece = s, *colon;
        kelp_dccl_algcall *c = &calls[ncalls++];
        if (comma) *comma = '\0';
        colon = strchr(piece, ':');
        if (colon) *colon = '\0';
        c->name = dup(p, piece, strlen(piece));
        if (!c->name) return false;
        if (p->algs && p->algs->n > 0 && !kelp_dccl_algs_find(p->algs, c->name)) {
            fail(p, KELP_ERR_NOTFOUND, line, "unknown algorithm \"%s\"", c->name);
            return false;
        }
        while (colon) {
            char *ref = colon + 1;
            int fi;
            colon = strchr(ref, ':');
            if (colon) *colon = '\0';
            fi = field_index(m, ref);
            if (fi < 0) {
                fail(p, KELP_ERR_NOTFOUND, line, "no such name \"%s\" found in <layout> or <header> (algorithm %s)",
                     ref, c->name);
                return false;
            }
            if (c->n_refs >= KELP_DCCL_MAX_ALG_REFS) {
                fail(p, KELP_ERR_RANGE, line, "algorithm %s has more than %d references", c->name,
                     KELP_DCCL_MAX_ALG_REFS);
                return false;
            }
            c->refs[c->n_refs++] = (int16_t)fi;
        }
        if (!comma) break;
        s = comma + 1;
    }
    (void)save;
    *out = calls;
    *n_out = (uint8_t)ncalls;
    return true;
}

static bool str_append(char **buf, size_t *n, size_t *cap, const char *s)
{
    size_t k = strlen(s);
    if (*n + k + 1 > *cap) {
        size_t nc = (*n + k + 1) * 2;
        char *nb = realloc(*buf, nc);
        if (!nb) return false;
        *buf = nb;
        *cap = nc;
    }
    memcpy(*buf + *n, s, k + 1);
    *n += k;
    return true;
}

/* Publish::initialize: resolve names, expand <all/>, default format */
static bool finish_publish(parser *p, pmsg *m, ppub *pb, kelp_dccl_publish *out)
{
    size_t na = pb->n_args, i, k;
    kelp_dccl_pubarg *args;
    const char **algtext;
    if (!pb->var) {
        fail(p, KELP_ERR_PARSE, pb->line, "<publish> needs a <publish_var> (or <moos_var>)");
        return false;
    }
    if (pb->all) {
        for (i = 0; i < KELP_DCCL_N_HEAD; i++)
            if (m->fields[i].f.name[0] != '_') na++;
        na += m->n_fields - KELP_DCCL_N_HEAD;
    }
    args = arena_alloc(&p->ld->arena, (na ? na : 1) * sizeof *args);
    algtext = arena_alloc(&p->ld->arena, (na ? na : 1) * sizeof *algtext);
    if (!args || !algtext) {
        fail(p, KELP_ERR_NOSPACE, pb->line, "out of memory");
        return false;
    }
    k = 0;
    for (i = 0; i < pb->n_args; i++) {
        int fi = field_index(m, pb->args[i].name ? pb->args[i].name : "");
        if (fi < 0) {
            fail(p, KELP_ERR_NOTFOUND, pb->args[i].line, "no such name \"%s\" found in <layout> or <header>",
                 pb->args[i].name ? pb->args[i].name : "");
            return false;
        }
        args[k].field = (uint16_t)fi;
        algtext[k] = pb->args[i].alg_text;
        if (pb->args[i].alg_text &&
            !parse_algs(p, m, pb->args[i].alg_text, pb->args[i].line, &args[k].algs, &args[k].n_algs))
            return false;
        k++;
    }
    if (pb->all) {
        for (i = 0; i < KELP_DCCL_N_HEAD; i++)
            if (m->fields[i].f.name[0] != '_') args[k++].field = (uint16_t)i;
        for (i = KELP_DCCL_N_HEAD; i < m->n_fields; i++) args[k++].field = (uint16_t)i;
    }
    out->var = pb->var;
    out->type = pb->type;
    out->args = args;
    out->n_args = (uint16_t)k;
    if (pb->have_format) {
        out->format = pb->format;
    } else {
        char *buf = NULL;
        size_t n = 0, cap = 0, count = 0, j;
        bool ok = str_append(&buf, &n, &cap, "");
        for (j = 0; ok && j < k; j++) {
            const kelp_dccl_field *f = &m->fields[args[j].field].f;
            size_t reps = m->def.repeat > 1 ? 1 : f->array_length, e;
            char num[32];
            if (k > 1) {
                size_t same = 0, q;
                if (j) ok = ok && str_append(&buf, &n, &cap, ",");
                for (q = 0; q < k; q++)
                    if (args[q].field == args[j].field) same++;
                if (same > 1 && args[j].n_algs) {
                    /* "<alg1><alg2>(<name>)=" with the algorithm texts as written */
                    char piece[1024];
                    size_t pn = 0;
                    const char *t = algtext[j] ? algtext[j] : "";
                    for (q = 0; t[q] && pn < sizeof piece - 1; q++)
                        if (t[q] != ',' && t[q] != ' ' && t[q] != '\t' && t[q] != '\n' && t[q] != '\r') piece[pn++] = t[q];
                    piece[pn] = '\0';
                    ok = ok && str_append(&buf, &n, &cap, piece);
                    ok = ok && str_append(&buf, &n, &cap, "(");
                    ok = ok && str_append(&buf, &n, &cap, f->name);
                    ok = ok && str_append(&buf, &n, &cap, ")=");
                } else {
                    ok = ok && str_append(&buf, &n, &cap, f->name);
                    ok = ok && str_append(&buf, &n, &cap, "=");
                }
            }
            for (e = 0; ok && e < reps; e++) {
                ++count;
                if (k > 1 && reps > 1 && e == 0) ok = ok && str_append(&buf, &n, &cap, "{");
                if (e) ok = ok && str_append(&buf, &n, &cap, ",");
                snprintf(num, sizeof num, "%%%zu%%", count);
                ok = ok && str_append(&buf, &n, &cap, num);
                if (k > 1 && reps > 1 && e + 1 == reps) ok = ok && str_append(&buf, &n, &cap, "}");
            }
        }
        if (!ok) {
            free(buf);
            fail(p, KELP_ERR_NOSPACE, pb->line, "out of memory");
            return false;
        }
        out->format = dup(p, buf, n);
        free(buf);
        if (!out->format) return false;
    }
    return true;
}

static void upper_into(char *dst, const char *s, size_t cap)
{
    size_t i;
    for (i = 0; s[i] && i + 1 < cap; i++) dst[i] = (s[i] >= 'a' && s[i] <= 'z') ? (char)(s[i] - 32) : s[i];
    dst[i] = '\0';
}

static void end_message(parser *p)
{
    pmsg *m = p->msg;
    kelp_dccl_field *fields;
    kelp_dccl_publish *pubs;
    kelp_dccl_msgdef *def;
    kelp_diag why; /* the definition check's reason, put into this file's message */
    int line = p->line[p->depth - 1];
    size_t i;
    int rc;
    if (!m->have_name) { fail(p, KELP_ERR_PARSE, line, "<message> needs a <name>"); return; }
    if (!m->have_size) { fail(p, KELP_ERR_PARSE, line, "<message> %s needs a <size>", m->def.name); return; }
    if (!m->have_layout) { fail(p, KELP_ERR_PARSE, line, "<message> %s needs a <layout>", m->def.name); return; }
    if (m->def.trigger == KELP_DCCL_TRIG_PUBLISH && !m->def.trigger_var) {
        fail(p, KELP_ERR_PARSE, line, "message %s: <trigger>publish</trigger> needs a <trigger_var>", m->def.name);
        return;
    }
    if (m->def.trigger == KELP_DCCL_TRIG_TIME && !(m->def.trigger_time > 0)) {
        fail(p, KELP_ERR_PARSE, line, "message %s: <trigger>time</trigger> needs a positive <trigger_time>",
             m->def.name);
        return;
    }
    /* field names must be unique (Goby keys values by name) */
    for (i = 0; i < m->n_fields; i++) {
        size_t j;
        for (j = i + 1; j < m->n_fields; j++) {
            if (strcmp(m->fields[i].f.name, m->fields[j].f.name) == 0) {
                fail(p, KELP_ERR_EXISTS, m->fields[j].line, "message %s: duplicate field name \"%s\"", m->def.name,
                     m->fields[j].f.name);
                return;
            }
        }
    }
    if (m->repeat_auto || m->def.repeat > 1) {
        for (i = KELP_DCCL_N_HEAD; i < m->n_fields; i++) {
            if (m->fields[i].f.array_length != 1) {
                fail(p, KELP_ERR_RANGE, m->fields[i].line,
                     "message %s: <repeat> is not allowed on messages with arrays (<array_length> not 1)", m->def.name);
                return;
            }
        }
    }
    /* algorithms (header and layout) */
    for (i = 0; i < m->n_fields; i++) {
        pfield *f = &m->fields[i];
        if (f->alg_text && !parse_algs(p, m, f->alg_text, f->alg_line, &f->f.algs, &f->f.n_algs)) return;
    }
    fields = arena_alloc(&p->ld->arena, m->n_fields * sizeof *fields);
    def = arena_alloc(&p->ld->arena, sizeof *def);
    if (!fields || !def) { fail(p, KELP_ERR_NOSPACE, line, "out of memory"); return; }
    for (i = 0; i < m->n_fields; i++) fields[i] = m->fields[i].f;
    *def = m->def;
    def->n_fields = (uint16_t)m->n_fields;
    def->publishes = NULL;
    def->n_publishes = 0;
    if (m->repeat_auto) def->repeat = 1;
    kelp_diag_clear(&why);
    rc = kelp_dccl_def_finalize(def, fields, &why);
    if (rc == 0 && m->repeat_auto) {
        /* <repeat/>: the largest k with k copies fitting in 8*(size-6) bits */
        uint32_t one = def->body_bits;
        if (one == 0) {
            fail(p, KELP_ERR_RANGE, line, "message %s: <repeat/> on a message without encoded fields", def->name);
            return;
        }
        def->repeat = (uint16_t)(8u * (uint32_t)(def->size - KELP_DCCL_HEAD_BYTES) / one);
        if (def->repeat < 1) def->repeat = 1;
        rc = kelp_dccl_def_finalize(def, fields, &why);
    }
    if (rc) {
        fail(p, rc, line, "DCCL: the message [%s]: %s (body %u bits, size %u bytes)", def->name, kelp_diag_text(&why),
             (unsigned)def->body_bits, (unsigned)def->size);
        return;
    }
    /* publishes need the final array lengths and repeat count (default formats: one
     * placeholder per field in a <repeat> message, also for <repeat/>) */
    for (i = 0; i < m->n_fields; i++) m->fields[i].f = fields[i];
    m->def.repeat = def->repeat;
    pubs = arena_alloc(&p->ld->arena, (m->n_pubs ? m->n_pubs : 1) * sizeof *pubs);
    if (!pubs) { fail(p, KELP_ERR_NOSPACE, line, "out of memory"); return; }
    for (i = 0; i < m->n_pubs; i++)
        if (!finish_publish(p, m, &m->pubs[i], &pubs[i])) return;
    def->publishes = pubs;
    def->n_publishes = (uint16_t)m->n_pubs;
    rc = kelp_dccl_def_finalize(def, fields, &why); /* re-check publish references */
    if (rc) { fail(p, rc, line, "message %s: %s", def->name, kelp_diag_text(&why)); return; }
    {
        char up[256], buf[300];
        upper_into(up, def->name, sizeof up);
        if (!def->in_var) {
            snprintf(buf, sizeof buf, "IN_%s_HEX_%uB", up, (unsigned)def->size);
            def->in_var = dup(p, buf, strlen(buf));
        }
        if (!def->out_var) {
            snprintf(buf, sizeof buf, "OUT_%s_HEX_%uB", up, (unsigned)def->size);
            def->out_var = dup(p, buf, strlen(buf));
        }
    }
    /* unique id and name in the whole set */
    for (i = 0; i < p->ld->set.n; i++) {
        const kelp_dccl_msgdef *o = p->ld->set.msgs[i];
        if (o->id == def->id) {
            fail(p, KELP_ERR_EXISTS, line, "message %s: id %u already used by message %s", def->name,
                 (unsigned)def->id, o->name);
            return;
        }
        if (strcmp(o->name, def->name) == 0) {
            fail(p, KELP_ERR_EXISTS, line, "message name %s already loaded", def->name);
            return;
        }
    }
    if (p->ld->set.n >= p->ld->cap) {
        size_t nc = p->ld->cap ? p->ld->cap * 2 : 16;
        const kelp_dccl_msgdef **nm = realloc(p->ld->msgs, nc * sizeof(void *)); /* NOLINT(bugprone-sizeof-expression) */
        if (!nm) { fail(p, KELP_ERR_NOSPACE, line, "out of memory"); return; }
        p->ld->msgs = nm;
        p->ld->cap = nc;
    }
    p->ld->msgs[p->ld->set.n++] = def;
    p->ld->set.msgs = p->ld->msgs;
    p->msg = NULL;
}

static void XMLCALL on_end(void *ud, const XML_Char *el)
{
    parser *p = ud;
    enum ctx_kind kind, parent;
    int line;
    long l;
    double d;
    if (p->rc || p->depth == 0) return;
    kind = p->kind[p->depth - 1];
    parent = p->depth > 1 ? p->kind[p->depth - 2] : C_ROOT;
    line = p->line[p->depth - 1];
    if (kind == C_LEAF) {
        pmsg *m = p->msg;
        switch (parent) {
        case C_MSG:
            if (strcmp(el, "name") == 0) {
                m->def.name = text_dup(p);
                m->have_name = true;
            } else if (strcmp(el, "id") == 0) {
                if (want_int(p, el, &l, 0, 65535)) m->def.id = (uint16_t)l;
            } else if (strcmp(el, "repeat") == 0) {
                const char *s;
                size_t n;
                trimmed(p, &s, &n);
                if (n == 0) m->repeat_auto = true;
                else if (want_int(p, el, &l, 1, 4096)) m->def.repeat = (uint16_t)l;
            } else if (strcmp(el, "size") == 0) {
                if (want_int(p, el, &l, -100000000L, 100000000L)) {
                    if (l <= (long)KELP_DCCL_HEAD_BYTES)
                        fail(p, KELP_ERR_RANGE, line, "<size> %ld must be larger than the 6-byte header", l);
                    else if (l > KELP_DCCL_MAX_SIZE)
                        fail(p, KELP_ERR_RANGE, line, "<size> %ld exceeds KELP_DCCL_MAX_SIZE (%d)", l, KELP_DCCL_MAX_SIZE);
                    else
                        m->def.size = (uint16_t)l;
                }
                m->have_size = true;
            } else if (strcmp(el, "destination_var") == 0 || strcmp(el, "destination_moos_var") == 0) {
                m->fields[KELP_DCCL_H_DEST].f.src_var = text_dup(p);
            } else if (strcmp(el, "outgoing_hex_moos_var") == 0) {
                m->def.out_var = text_dup(p);
            } else if (strcmp(el, "incoming_hex_moos_var") == 0) {
                m->def.in_var = text_dup(p);
            } else if (strcmp(el, "trigger") == 0) {
                const char *s;
                size_t n;
                trimmed(p, &s, &n);
                if (n == 7 && memcmp(s, "publish", 7) == 0) m->def.trigger = KELP_DCCL_TRIG_PUBLISH;
                else if (n == 4 && memcmp(s, "time", 4) == 0) m->def.trigger = KELP_DCCL_TRIG_TIME;
                else fail(p, KELP_ERR_PARSE, line, "<trigger> must be \"publish\" or \"time\", not \"%.*s\"", (int)n, s);
            } else if (strcmp(el, "trigger_time") == 0) {
                if (want_finite(p, el, &d)) {
                    if (d < 0) fail(p, KELP_ERR_RANGE, line, "<trigger_time> must be >= 0");
                    else m->def.trigger_time = d;
                }
            } else if (strcmp(el, "trigger_var") == 0 || strcmp(el, "trigger_moos_var") == 0) {
                m->def.trigger_var = text_dup(p);
            }
            break;
        case C_HEADER:
            if (strcmp(el, "id") == 0 && want_int(p, el, &l, 0, 65535)) m->def.id = (uint16_t)l;
            break;
        case C_HEADVAR:
            if (strcmp(el, "name") == 0) {
                p->field->f.name = text_dup(p);
                p->field->have_name = true;
            } else {
                p->field->f.src_var = text_dup(p);
            }
            break;
        case C_FIELD: end_field_leaf(p, el); break;
        case C_PUBLISH:
            if (strcmp(el, "format") == 0) {
                p->pub->format = text_dup(p);
                p->pub->have_format = true;
            } else if (strcmp(el, "publish_var") == 0 || strcmp(el, "moos_var") == 0) {
                p->pub->var = text_dup(p);
            } else if (strcmp(el, "message_var") == 0) {
                p->pub->args[p->pub->n_args - 1].name = text_dup(p);
            }
            break;
        case C_QUEUING:
            if (strcmp(el, "ack") == 0) m->def.queuing.ack = text_bool(p);
            else if (strcmp(el, "newest_first") == 0) m->def.queuing.newest_first = text_bool(p);
            else if (strcmp(el, "blackout_time") == 0) {
                if (want_finite(p, el, &d)) {
                    if (d < 0) fail(p, KELP_ERR_RANGE, line, "<blackout_time> must be >= 0");
                    else m->def.queuing.blackout_time = d;
                }
            } else if (strcmp(el, "max_queue") == 0) {
                if (want_finite(p, el, &d)) {
                    if (d < 0 || d > 4294967295.0 || d != floor(d))
                        fail(p, KELP_ERR_RANGE, line, "<max_queue> must be a whole number 0..4294967295");
                    else
                        m->def.queuing.max_queue = (uint32_t)d;
                }
            } else if (strcmp(el, "value_base") == 0 || strcmp(el, "priority_base") == 0) {
                if (want_double(p, el, &d)) m->def.queuing.value_base = d;
            } else if (strcmp(el, "ttl") == 0 || strcmp(el, "priority_time_const") == 0) {
                if (want_double(p, el, &d)) m->def.queuing.ttl = d;
            }
            break;
        default: break;
        }
    } else if (kind == C_FIELD) {
        end_field(p);
    } else if (kind == C_HEADVAR) {
        if (!p->field->have_name) fail(p, KELP_ERR_PARSE, line, "<%s> needs a <name>", el);
    } else if (kind == C_LAYOUT) {
        p->msg->have_layout = true;
        if (!p->msg->have_layout_child) fail(p, KELP_ERR_PARSE, line, "<layout> needs at least one field");
    } else if (kind == C_RECEIPT) {
        if (!p->msg->have_publish) fail(p, KELP_ERR_PARSE, line, "<on_receipt> needs at least one <publish>");
    } else if (kind == C_QUEUING) {
        p->msg->def.queuing.present = true;
    } else if (kind == C_MSG) {
        end_message(p);
    }
    p->tlen = 0;
    p->depth--;
}

/* ------------------------------------------------------------------ entry points */
/* Goby's parser (Xerces) accepts encoding="ASCII" (the seed's example1 uses it);
 * expat knows only UTF-8/16, ISO-8859-1 and US-ASCII. Single-byte encodings
 * with ASCII in 0..127 are mapped; other bytes are taken as Latin-1. */
static int XMLCALL on_unknown_encoding(void *ud, const XML_Char *name, XML_Encoding *info)
{
    static const char *const OK[] = {"ASCII", "ascii", "ANSI_X3.4-1968", "ISO646-US", "CP1252", "WINDOWS-1252",
                                     "windows-1252", "LATIN1", "latin1", NULL};
    unsigned i;
    (void)ud;
    for (i = 0; OK[i]; i++) {
        if (strcmp(OK[i], name) == 0) {
            int c;
            for (c = 0; c < 256; c++) info->map[c] = c;
            info->data = NULL;
            info->convert = NULL;
            info->release = NULL;
            return XML_STATUS_OK;
        }
    }
    return XML_STATUS_ERROR;
}

static int load(kelp_dccl_loaded *ld, const char *name, const char *xml, size_t len, const kelp_dccl_algs *algs,
                kelp_diag *d)
{
    parser p;
    size_t before = ld->set.n;
    memset(&p, 0, sizeof p);
    p.ld = ld;
    p.algs = algs;
    p.file = name;
    p.d = d;
    p.xp = XML_ParserCreate(NULL);
    if (!p.xp) return kelp_failf(d, KELP_ERR_NOSPACE, "%s:0: out of memory", name);
    XML_SetUserData(p.xp, &p);
    XML_SetElementHandler(p.xp, on_start, on_end);
    XML_SetCharacterDataHandler(p.xp, on_text);
    XML_SetUnknownEncodingHandler(p.xp, on_unknown_encoding, NULL);
    if (len > (size_t)2147483647) len = 2147483647;
    if (XML_Parse(p.xp, xml, (int)len, XML_TRUE) == XML_STATUS_ERROR && !p.rc) {
        fail(&p, KELP_ERR_PARSE, (int)XML_GetCurrentLineNumber(p.xp), "XML error: %s",
             XML_ErrorString(XML_GetErrorCode(p.xp)));
    }
    if (!p.rc && !p.saw_root) fail(&p, KELP_ERR_PARSE, 1, "no <message_set>");
    XML_ParserFree(p.xp);
    p.xp = NULL;
    free(p.text);
    if (p.rc) {
        ld->set.n = before; /* nothing of a failed file is kept */
        return p.rc;
    }
    return KELP_OK;
}

int kelp_dccl_load_buffer(kelp_dccl_loaded *ld, const char *name, const char *xml, size_t len,
                          const kelp_dccl_algs *algs, kelp_diag *d)
{
    if (!ld || !xml) return kelp_fail(d, KELP_ERR_ARG, "no loader or no text");
    return load(ld, name ? name : "(buffer)", xml, len, algs, d);
}

int kelp_dccl_load_file(kelp_dccl_loaded *ld, const char *path, const kelp_dccl_algs *algs, kelp_diag *d)
{
    FILE *f;
    char *buf = NULL;
    size_t n = 0, cap = 0;
    int rc;
    if (!ld || !path) return kelp_fail(d, KELP_ERR_ARG, "no loader or no path");
    f = fopen(path, "rb");
    if (!f) return kelp_failf(d, KELP_ERR_IO, "%s:0: cannot open: %s", path, strerror(errno));
    for (;;) {
        size_t got;
        if (n + 4096 > cap) {
            char *nb;
            cap = (n + 4096) * 2;
            if (cap > (64u << 20)) {
                free(buf);
                fclose(f);
                return kelp_failf(d, KELP_ERR_RANGE, "%s:0: file too large", path);
            }
            nb = realloc(buf, cap);
            if (!nb) {
                free(buf);
                fclose(f);
                return kelp_failf(d, KELP_ERR_NOSPACE, "%s:0: out of memory", path);
            }
            buf = nb;
        }
        got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0) break;
    }
    if (ferror(f)) {
        free(buf);
        fclose(f);
        return kelp_failf(d, KELP_ERR_IO, "%s:0: read error", path);
    }
    fclose(f);
    rc = load(ld, path, buf ? buf : "", n, algs, d);
    free(buf);
    return rc;
}

int kelp_dccl_builtin_load_modems(kelp_dccl_builtin *ctx, const char *path, kelp_diag *d)
{
    FILE *f = fopen(path, "rb");
    char buf[65536];
    size_t n;
    int rc;
    if (!f) return kelp_failf(d, KELP_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    rc = kelp_dccl_builtin_parse_modems(ctx, buf, n);
    return rc ? kelp_failf(d, rc, "%s: too many entries", path) : KELP_OK;
}
