/* uFldScope's logic (ufield.md 7): key=value reports in, a table of vehicles by scoped field
 * out, switched between layouts and paused from the keyboard (see include/kelp/field.h). */
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>
#include <kelp/kv.h>
#include <kelp/mission.h>
#include "field_int.h"

#define UFS_SEP "  "       /* between columns */
#define UFS_NAME_HDR "VName"

static bool copy_fit(char *dst, size_t cap, const char *src, size_t n)
{
    if (n >= cap) return false;
    memcpy(dst, src, n);
    dst[n] = 0;
    return true;
}

/* ------------------------------------------------------------------ configuration */

static int add_scope(kelp_field_ufs_cfg *c, const char *val, kelp_diag *d)
{
    if (c->nelem >= KELP_UFS_MAX_ELEMS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many SCOPE entries (at most 16)");
    }
    kelp_ufs_elem e;
    memset(&e, 0, sizeof e);
    size_t pos = 0;
    const char *k, *v;
    size_t kl, vl;
    int rc;
    while ((rc = kelp_kv_next(val, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        char *dst = NULL;
        size_t cap = KELP_UFS_FIELD_LEN;
        if (kelp_util_strieq_n(k, kl, "var")) dst = e.var, cap = sizeof e.var;
        else if (kelp_util_strieq_n(k, kl, "key")) dst = e.key;
        else if (kelp_util_strieq_n(k, kl, "fld") || kelp_util_strieq_n(k, kl, "field")) dst = e.fld;
        else if (kelp_util_strieq_n(k, kl, "alias")) dst = e.alias;
        else if (kelp_util_strieq_n(k, kl, "color")) dst = e.color;
        else if (kelp_util_strieq_n(k, kl, "xcolor")) dst = e.xcolor;
        else if (kelp_util_strieq_n(k, kl, "xthresh")) {
            if (kelp_util_parse_double(v, vl, &e.xthresh) < 0 || !(e.xthresh >= 0)) {
                return kelp_fail(d, KELP_ERR_PARSE, "xthresh must be a number >= 0");
            }
            continue;
        } else {
            return kelp_fail(d, KELP_ERR_PARSE, "unknown field (var, key, fld, alias, color, xcolor, xthresh)");
        }
        if (!copy_fit(dst, cap, v, vl) || memchr(v, ' ', vl)) {
            return kelp_fail(d, KELP_ERR_RANGE, "a field is too long or holds a space");
        }
    }
    if (rc < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "expected var=<VAR>, key=<KEY>, fld=<FIELD>, alias=<ALIAS>");
    }
    if (!e.var[0] || !e.fld[0]) {
        return kelp_fail(d, KELP_ERR_PARSE, "var and fld are required");
    }
    c->elem[c->nelem++] = e;
    return 1;
}

int kelp_field_ufs_config(kelp_field_ufs_cfg *c, const char *key, const char *val, kelp_diag *d)
{
    size_t kl = strlen(key);
    if (kelp_util_strieq_n(key, kl, "SCOPE")) return add_scope(c, val, d);
    if (!kelp_util_strieq_n(key, kl, "LAYOUT")) return 0;
    if (c->nlayout >= KELP_UFS_MAX_LAYOUTS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many LAYOUT entries (at most 8)");
    }
    if (!copy_fit(c->layout[c->nlayout], KELP_UFS_LAYOUT_LEN, val, strlen(val))) {
        return kelp_fail(d, KELP_ERR_RANGE, "LAYOUT too long");
    }
    c->nlayout++;
    return 1;
}

static const char *header(const kelp_ufs_elem *e)
{
    return e->alias[0] ? e->alias : e->fld;
}

void kelp_field_ufs_init(kelp_field_ufs *s, const kelp_field_ufs_cfg *cfg)
{
    memset(s, 0, sizeof *s);
    s->cfg = *cfg;
    s->last_layout = 1;
    /* a variable's key is the key of its last SCOPE line, as 24.8's (a line without one
     * leaves the variable keyless: its reports are then not shown) */
    for (unsigned i = 0; i < s->cfg.nelem; i++) {
        kelp_ufs_elem *e = &s->cfg.elem[i];
        for (unsigned j = i + 1; j < s->cfg.nelem; j++)
            if (!strcmp(s->cfg.elem[j].var, e->var)) memcpy(e->key, s->cfg.elem[j].key, sizeof e->key);
    }
    /* layout (n) is LAYOUT line nlayout-n+1: the last line is (1) */
    for (unsigned l = 0; l < s->cfg.nlayout; l++) {
        const char *text = s->cfg.layout[s->cfg.nlayout - 1 - l];
        size_t pos = 0, len = strlen(text), il;
        const char *it;
        while (field_next_item(text, len, &pos, ',', &it, &il) == 1) {
            bool hit = false;
            for (unsigned i = 0; i < s->cfg.nelem; i++)
                if (kelp_util_strieq_n(it, il, header(&s->cfg.elem[i]))) s->layout_mask[l] |= 1u << i, hit = true;
            for (unsigned i = 0; i < s->cfg.nelem && !hit; i++)
                if (kelp_util_strieq_n(it, il, s->cfg.elem[i].fld)) s->layout_mask[l] |= 1u << i, hit = true;
            if (!hit && s->unmatched++ == 0)
                (void)copy_fit(s->first_unmatched, sizeof s->first_unmatched, it,
                               il < KELP_UFS_FIELD_LEN ? il : KELP_UFS_FIELD_LEN - 1);
        }
    }
}

const char *kelp_field_ufs_subscription(const kelp_field_ufs *s, unsigned i)
{
    for (unsigned e = 0; e < s->cfg.nelem; e++) {
        bool first = true;
        for (unsigned j = 0; j < e && first; j++) first = strcmp(s->cfg.elem[j].var, s->cfg.elem[e].var) != 0;
        if (first && i-- == 0) return s->cfg.elem[e].var;
    }
    return NULL;
}

/* ------------------------------------------------------------------ mail */

/* the value of `key` in a report as 24.8's token parse finds it: the first pair whose key
 * is exactly `key` (case and all); an item before it that is not one key=value pair ends
 * the search with nothing (and is counted in *bad) */
static bool lookup(const char *s, const char *key, const char **v, size_t *vl, unsigned *bad)
{
    size_t pos = 0, kl, n = strlen(key);
    const char *k;
    int rc;
    while ((rc = kelp_kv_next(s, ',', &pos, &k, &kl, v, vl)) != 0) {
        if (rc < 0 || memchr(*v, '=', *vl)) {
            (*bad)++;
            return false;
        }
        if (kl == n && !memcmp(k, key, n)) return true;
    }
    return false;
}

/* the row of vehicle name[0..n), made in name order when new; NULL when full or bad */
static kelp_ufs_row *row_for(kelp_field_ufs *s, const char *name, size_t n)
{
    char nm[KELP_UFS_FIELD_LEN];
    if (!copy_fit(nm, sizeof nm, name, n)) return NULL;
    unsigned at = 0;
    for (; at < s->nrow; at++) {
        int c = strcmp(s->row[at].name, nm); /* 24.8's set of names: byte order, "" first */
        if (c == 0) return &s->row[at];
        if (c > 0) break;
    }
    if (s->nrow >= KELP_UFS_MAX_ROWS) {
        s->dropped_rows++;
        return NULL;
    }
    memmove(&s->row[at + 1], &s->row[at], (s->nrow - at) * sizeof s->row[0]);
    s->nrow++;
    memset(&s->row[at], 0, sizeof s->row[at]);
    memcpy(s->row[at].name, nm, sizeof nm);
    return &s->row[at];
}

int kelp_field_ufs_mail(kelp_field_ufs *s, const char *var, bool is_string, const char *sval)
{
    bool ours = false;
    for (unsigned e = 0; e < s->cfg.nelem && !ours; e++) ours = !strcmp(s->cfg.elem[e].var, var);
    if (!ours) return 0;
    s->mail++;
    if (!is_string || !sval) {
        s->bad_mail++;
        return KELP_ERR_PARSE;
    }
    if (!*sval) return 0; /* 24.8 keeps no empty posting */
    unsigned bad = 0;
    bool used = false;
    for (unsigned e = 0; e < s->cfg.nelem; e++) {
        const kelp_ufs_elem *el = &s->cfg.elem[e];
        if (strcmp(el->var, var) != 0 || !el->key[0]) continue; /* keyless: not shown */
        const char *nv = "", *fv;
        size_t nl = 0, fl;
        if (!lookup(sval, el->key, &nv, &nl, &bad)) nv = "", nl = 0; /* the row named "" */
        kelp_ufs_row *r = row_for(s, nv, nl);
        if (!r) continue;
        char *cell = r->cell[e];
        if (!lookup(sval, el->fld, &fv, &fl, &bad)) fl = 0;
        if (fl >= KELP_UFS_CELL_LEN) fl = KELP_UFS_CELL_LEN - 1;
        memcpy(cell, fv, fl);
        cell[fl] = 0;
        used = true;
    }
    if (bad) s->bad_mail++;
    return bad ? KELP_ERR_PARSE : used ? 1 : 0;
}

/* ------------------------------------------------------------------ keys */

int kelp_field_ufs_key(kelp_field_ufs *s, int c)
{
    unsigned k = s->cfg.nlayout;
    switch (c) {
    case 'l':
    case 'L':
        s->layout = s->layout >= k ? 0 : s->layout + 1;
        if (s->layout) s->last_layout = s->layout;
        break;
    case 'a':
    case 'A':
        s->layout = (s->layout || !k) ? 0 : s->last_layout;
        break;
    case 'p':
    case 'P':
    case ' ':
        s->mode = KELP_UFS_PAUSED;
        break;
    case 'r':
    case 'R':
        s->mode = KELP_UFS_STREAMING;
        break;
    case 'h':
    case 'H':
        s->mode = s->mode == KELP_UFS_HELP ? KELP_UFS_PAUSED : KELP_UFS_HELP;
        break;
    default:
        return 0;
    }
    s->update = true;
    return 1;
}

bool kelp_field_ufs_due(const kelp_field_ufs *s)
{
    return s->update || s->mode == KELP_UFS_STREAMING;
}

/* ------------------------------------------------------------------ render */

typedef struct outbuf {
    char *b;
    size_t cap, n;
} outbuf;

#define put(o, ...) field_putf((o)->b, (o)->cap, &(o)->n, __VA_ARGS__)

static void help(outbuf *o)
{
    put(o, "Key        Action                                   HELP\n");
    put(o, "---------  ---------------------------------------\n");
    put(o, "  SPACE    refresh once now, then stay paused\n");
    put(o, "  p / P    pause the refresh (again: refresh once)\n");
    put(o, "  r / R    resume refreshing every iteration\n");
    put(o, "  a / A    all columns <-> the last layout\n");
    put(o, "  l / L    next layout: A, 1, 2, ..., A\n");
    put(o, "  h / H    this help (again: back to the table)\n");
}

size_t kelp_field_ufs_render(kelp_field_ufs *s, char *buf, size_t cap)
{
    if (!buf || !cap) return 0;
    outbuf o = { buf, cap, 0 };
    buf[0] = 0;
    s->update = false;
    if (s->mode == KELP_UFS_HELP) {
        help(&o);
        return o.n;
    }
    uint32_t mask = s->layout ? s->layout_mask[s->layout - 1] : 0xffffffffu;
    unsigned ne = s->cfg.nelem < KELP_UFS_MAX_ELEMS ? s->cfg.nelem : KELP_UFS_MAX_ELEMS;
    unsigned nr = s->nrow < KELP_UFS_MAX_ROWS ? s->nrow : KELP_UFS_MAX_ROWS;
    int w[KELP_UFS_MAX_ELEMS + 1] = { 0 };
    w[0] = (int)strlen(UFS_NAME_HDR);
    // cppcheck-suppress knownConditionTrueFalse ; nelem/nrow are set by the mail, not 0
    for (unsigned r = 0; r < nr; r++)
        if ((int)strlen(s->row[r].name) > w[0]) w[0] = (int)strlen(s->row[r].name);
    // cppcheck-suppress knownConditionTrueFalse ; nelem/nrow are set by the mail, not 0
    for (unsigned e = 0; e < ne; e++) {
        w[e + 1] = (int)strlen(header(&s->cfg.elem[e]));
        for (unsigned r = 0; r < nr; r++)
            if ((int)strlen(s->row[r].cell[e]) > w[e + 1]) w[e + 1] = (int)strlen(s->row[r].cell[e]);
    }
    static const char rule[] = "================================================";
    const char *state = s->mode == KELP_UFS_PAUSED ? "PAUSED" : "STREAMING";
    put(&o, "%-*s" UFS_SEP, w[0], UFS_NAME_HDR);
    // cppcheck-suppress knownConditionTrueFalse ; nelem/nrow are set by the mail, not 0
    for (unsigned e = 0; e < ne; e++)
        if (mask & (1u << e)) put(&o, "%-*s" UFS_SEP, w[e + 1], header(&s->cfg.elem[e]));
    if (s->layout) put(&o, "%s(%u)\n", state, s->layout);
    else put(&o, "%s(A)\n", state);
    put(&o, "%.*s" UFS_SEP, w[0], rule);
    // cppcheck-suppress knownConditionTrueFalse ; nelem/nrow are set by the mail, not 0
    for (unsigned e = 0; e < ne; e++)
        if (mask & (1u << e)) put(&o, "%.*s" UFS_SEP, w[e + 1], rule);
    put(&o, "(%lu)\n", s->reports);
    // cppcheck-suppress knownConditionTrueFalse ; nelem/nrow are set by the mail, not 0
    for (unsigned r = 0; r < nr; r++) {
        size_t start = o.n;
        put(&o, "%-*s" UFS_SEP, w[0], s->row[r].name);
        // cppcheck-suppress knownConditionTrueFalse ; nelem/nrow are set by the mail, not 0
        for (unsigned e = 0; e < ne; e++)
            if (mask & (1u << e)) put(&o, "%-*s" UFS_SEP, w[e + 1], s->row[r].cell[e]);
        while (o.n > start && buf[o.n - 1] == ' ') buf[--o.n] = 0; /* no trailing blanks */
        put(&o, "\n");
    }
    if (s->dropped_rows) put(&o, "(%lu reports of vehicles beyond %d not shown)\n", s->dropped_rows, KELP_UFS_MAX_ROWS);
    s->reports++;
    return o.n;
}

/* the e-th element shown in the current layout, or -1 */
static int shown_elem(const kelp_field_ufs *s, unsigned k)
{
    uint32_t mask = s->layout ? s->layout_mask[s->layout - 1] : 0xffffffffu;
    unsigned ne = s->cfg.nelem < KELP_UFS_MAX_ELEMS ? s->cfg.nelem : KELP_UFS_MAX_ELEMS;
    // cppcheck-suppress knownConditionTrueFalse ; nelem comes from the configuration
    for (unsigned e = 0; e < ne; e++)
        if ((mask & (1u << e)) && k-- == 0) return (int)e;
    return -1;
}

static const char *table_cell(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap)
{
    const kelp_field_ufs *s = ctx;
    (void)tmp, (void)cap;
    int e = col ? shown_elem(s, col - 1) : -1;
    if (row == 0) return col == 0 ? UFS_NAME_HDR : e >= 0 ? header(&s->cfg.elem[e]) : "";
    const kelp_ufs_row *r = &s->row[row - 1];
    return col == 0 ? r->name : e >= 0 ? r->cell[e] : "";
}

size_t kelp_field_ufs_table(const kelp_field_ufs *s, char *buf, size_t cap)
{
    if (!buf || !cap) return 0;
    size_t n = 0;
    bool full = false;
    buf[0] = 0;
    unsigned cols = 1;
    while (shown_elem(s, cols - 1) >= 0) cols++;
    unsigned nr = s->nrow < KELP_UFS_MAX_ROWS ? s->nrow : KELP_UFS_MAX_ROWS;
    /* 24.8's buildReport: ACTable(columns, 2), the header row, dashes, a row per vehicle */
    field_actable(buf, cap, &n, &full, cols, nr + 1, 1, 2, 0, table_cell, s);
    broker_put(buf, cap, &n, &full, "\n");
    return n;
}
