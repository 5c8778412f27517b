/* uFldMessageHandler's logic (ufield.md 6, 1.2): NODE_MESSAGE in, the carried variable out,
 * with tallies, the last few messages and the Listing 14 report (see include/kelp/field.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>
#include <kelp/mission.h>
#include "field_int.h"
#include <kelp/util.h>

#define UMH_DEFAULT_TRUNC 75

/* ------------------------------------------------------------------ NODE_MESSAGE */

static bool key_is(const char *k, size_t kl, const char *a, const char *b)
{
    return kelp_strieq_n(k, kl, a) || (b && kelp_strieq_n(k, kl, b));
}

static void set_text(kelp_field_text *t, const char *v, size_t vl)
{
    if (t->p) return; /* the first of a repeated key wins */
    t->p = v;
    t->n = vl;
}

/* double_val as MOOS-IvP reads it (atof): the longest leading number, 0 when there is none */
static double leading_number(const char *v, size_t vl)
{
    while (vl && (*v == ' ' || *v == '\t')) v++, vl--;
    if (vl > 64) vl = 64;
    for (size_t n = vl; n > 0; n--) {
        double d;
        if (kelp_parse_double(v, n, &d) == 0 && isfinite(d)) return d;
    }
    return 0.0;
}

/* a MOOS variable name we are willing to post */
static bool name_ok(const char *v, size_t vl)
{
    if (vl == 0 || vl >= KELP_MAX_NAME) return false;
    for (size_t i = 0; i < vl; i++) {
        unsigned char c = (unsigned char)v[i];
        if (c <= ' ' || c >= 0x7f || c == ',' || c == '=' || c == '"') return false;
    }
    return true;
}

static void take_pair(kelp_node_message *m, kelp_field_text *var_alt, kelp_field_text *dval, const char *k, size_t kl,
                     const char *v, size_t vl)
{
    if (key_is(k, kl, "src_node", NULL)) set_text(&m->src_node, v, vl);
    else if (key_is(k, kl, "src_app", NULL)) set_text(&m->src_app, v, vl);
    else if (key_is(k, kl, "src_bhv", NULL)) set_text(&m->src_bhv, v, vl);
    else if (key_is(k, kl, "dest_node", "dest_name")) set_text(&m->dest_node, v, vl);
    else if (key_is(k, kl, "dest_group", NULL)) set_text(&m->dest_group, v, vl);
    else if (key_is(k, kl, "var_name", NULL)) set_text(&m->var_name, v, vl);
    else if (key_is(k, kl, "src_var", NULL)) set_text(var_alt, v, vl);
    else if (key_is(k, kl, "color", NULL)) set_text(&m->color, v, vl);
    else if (key_is(k, kl, "ack_id", "msg_id")) set_text(&m->ack_id, v, vl);
    else if (key_is(k, kl, "ack", NULL)) m->ack = kelp_strieq_n(v, vl, "true");
    else if (key_is(k, kl, "string_val_quoted", NULL)) m->string_val_quoted = kelp_strieq_n(v, vl, "true");
    else if (key_is(k, kl, "string_val", NULL)) {
        if (!m->has_string) {
            m->string_quoted = vl >= 2 && v[0] == '"' && v[vl - 1] == '"';
            if (m->string_quoted) v++, vl -= 2;
            m->string_val.p = v;
            m->string_val.n = vl;
        }
        m->has_string = true;
    } else if (key_is(k, kl, "double_val", NULL)) {
        if (!m->has_double) dval->p = v, dval->n = vl;
        m->has_double = true;
    }
    /* string_val_quoted and unknown keys: nothing to keep */
}

int kelp_field_nodemsg_parse(const char *s, size_t len, kelp_node_message *m, kelp_diag *d)
{
    memset(m, 0, sizeof *m);
    if (!s) {
        return kelp_fail(d, KELP_ERR_PARSE, "no text");
    }
    kelp_field_text var_alt = { NULL, 0 }, dval = { NULL, 0 };
    size_t pos = 0;
    const char *it;
    size_t il;
    int rc;
    while ((rc = field_next_item(s, len, &pos, ',', &it, &il)) == 1) {
        const char *eq = memchr(it, '=', il);
        if (!eq) eq = memchr(it, ';', il); /* "dest_node;bravo" */
        if (!eq) continue;                 /* a stray word: ignored, as MOOS does */
        const char *k = it, *v = eq + 1;
        size_t kl = (size_t)(eq - it), vl = il - kl - 1;
        while (kl && (k[kl - 1] == ' ' || k[kl - 1] == '\t')) kl--;
        while (vl && (*v == ' ' || *v == '\t')) v++, vl--;
        take_pair(m, &var_alt, &dval, k, kl, v, vl);
    }
    if (rc < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "unbalanced quote or brace");
    }
    if (!m->var_name.n) m->var_name = var_alt;
    if (!m->src_node.n) return kelp_fail(d, KELP_ERR_PARSE, "no src_node");
    if (!m->dest_node.n && !m->dest_group.n) return kelp_fail(d, KELP_ERR_PARSE, "no dest_node or dest_group");
    if (!m->var_name.n) return kelp_fail(d, KELP_ERR_PARSE, "no var_name");
    if (!name_ok(m->var_name.p, m->var_name.n)) return kelp_fail(d, KELP_ERR_PARSE, "var_name is not a variable name");
    if (kelp_strieq_n(m->var_name.p, m->var_name.n, "NODE_MESSAGE")) return kelp_fail(d, KELP_ERR_PARSE, "var_name NODE_MESSAGE would loop");
    /* MOOS-IvP 24.8 (NodeMessage): an empty string_val is no string value; a message with a
     * string and a double is invalid; a double_val is read as atof reads it */
    if (m->has_string && m->string_val.n == 0 && !m->string_quoted) m->has_string = false;
    if (m->has_string && m->has_double) return kelp_fail(d, KELP_ERR_PARSE, "both string_val and double_val");
    if (m->has_double) m->double_val = leading_number(dval.p, dval.n);
    return KELP_OK;
}

bool kelp_field_nodemsg_to(const kelp_node_message *m, const char *me)
{
    size_t pos = 0;
    const char *it;
    size_t il;
    while (field_next_item(m->dest_node.p, m->dest_node.n, &pos, ':', &it, &il) == 1)
        if (kelp_strieq_n(it, il, me)) return true;
    return false;
}

/* ------------------------------------------------------------------ configuration */

static void copy_text(char *dst, size_t cap, const char *src, size_t n)
{
    if (n >= cap) n = cap - 1;
    if (n) memcpy(dst, src, n);
    dst[n] = 0;
}

void kelp_field_umh_cfg_default(kelp_field_umh_cfg *c, const char *community)
{
    memset(c, 0, sizeof *c);
    copy_text(c->community, sizeof c->community, community ? community : "", community ? strlen(community) : 0);
    c->verbose = true;
    c->trunc = UMH_DEFAULT_TRUNC;
}

static int parse_bool(const char *val, bool *out, kelp_diag *d)
{
    if (kelp_parse_bool(val, strlen(val), out) != KELP_OK) {
        return kelp_fail(d, KELP_ERR_PARSE, "expected true or false");
    }
    return 1;
}

/* "VAR=value": a number is a double, anything else (quotes removed) a string */
static int parse_flag(kelp_umh_flag *f, unsigned *n, const char *val, kelp_diag *d)
{
    if (*n >= KELP_UMH_MAX_FLAGS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many flags (at most 8 of each kind)");
    }
    const char *eq = strchr(val, '=');
    size_t vl = strlen(val);
    if (!eq) {
        return kelp_fail(d, KELP_ERR_PARSE, "expected VAR=value");
    }
    const char *k = val, *v = eq + 1;
    size_t kl = (size_t)(eq - val), l = vl - kl - 1;
    while (kl && (k[kl - 1] == ' ' || k[kl - 1] == '\t')) kl--;
    while (kl && (*k == ' ' || *k == '\t')) k++, kl--;
    while (l && (*v == ' ' || *v == '\t')) v++, l--;
    while (l && (v[l - 1] == ' ' || v[l - 1] == '\t')) l--;
    if (!name_ok(k, kl)) {
        return kelp_fail(d, KELP_ERR_PARSE, "the flag's variable is not a variable name");
    }
    kelp_umh_flag *t = &f[*n];
    memset(t, 0, sizeof *t);
    copy_text(t->var, sizeof t->var, k, kl);
    bool quoted = l >= 2 && v[0] == '"' && v[l - 1] == '"';
    if (!quoted && kelp_parse_double(v, l, &t->dval) == 0 && isfinite(t->dval)) {
        t->is_string = false;
    } else {
        if (quoted) v++, l -= 2;
        if (l >= sizeof t->sval) {
            return kelp_fail(d, KELP_ERR_RANGE, "the flag's value is too long");
        }
        copy_text(t->sval, sizeof t->sval, v, l);
        t->is_string = true;
    }
    (*n)++;
    return 1;
}

int kelp_field_umh_config(kelp_field_umh_cfg *c, const char *key, const char *val, kelp_diag *d)
{
    size_t kl = strlen(key), vl = strlen(val);
    if (kelp_strieq_n(key, kl, "VERBOSE")) return parse_bool(val, &c->verbose, d);
    if (kelp_strieq_n(key, kl, "STRICT_ADDRESSING")) return parse_bool(val, &c->strict, d);
    if (kelp_strieq_n(key, kl, "AUX_INFO")) {
        if (kelp_strieq_n(val, vl, "node")) c->aux_app = false;
        else if (kelp_strieq_n(val, vl, "node+app")) c->aux_app = true;
        else {
            return kelp_fail(d, KELP_ERR_PARSE, "expected node or node+app");
        }
        return 1;
    }
    if (kelp_strieq_n(key, kl, "APPCAST_TRUNC_MSG")) {
        long n;
        if (kelp_parse_long(val, vl, &n) < 0 || n < 0 || n >= KELP_UMH_MSG_LEN) {
            return kelp_fail(d, KELP_ERR_RANGE, "expected a whole number of characters in [0, 255]");
        }
        c->trunc = (unsigned)n;
        return 1;
    }
    if (kelp_strieq_n(key, kl, "MSG_FLAG")) return parse_flag(c->msg_flag, &c->nmsg_flag, val, d);
    if (kelp_strieq_n(key, kl, "BAD_MSG_FLAG")) return parse_flag(c->bad_flag, &c->nbad_flag, val, d);
    return 0;
}

void kelp_field_umh_init(kelp_field_umh *h, const kelp_field_umh_cfg *cfg)
{
    memset(h, 0, sizeof *h);
    h->cfg = *cfg;
    h->last_msg = -1;
    h->summary_due = true;
}

/* ------------------------------------------------------------------ mail */

static void list_add(kelp_umh_list *l, const char *msg, const char *why)
{
    unsigned slot;
    if (l->n < KELP_UMH_LAST) slot = (l->first + l->n++) % KELP_UMH_LAST;
    else {
        slot = l->first;
        l->first = (l->first + 1) % KELP_UMH_LAST;
    }
    copy_text(l->msg[slot], sizeof l->msg[slot], msg, strlen(msg));
    if (!why) why = "";
    copy_text(l->why[slot], sizeof l->why[slot], why, strlen(why));
}

/* $[CTR], $[GOOD_CTR], $[BAD_CTR] expanded into out */
static void expand(const kelp_field_umh *h, const char *in, char *out, size_t cap)
{
    static const char *const names[] = { "$[CTR]", "$[GOOD_CTR]", "$[BAD_CTR]" };
    unsigned long vals[] = { h->total, h->valid, h->rejected }; /* 24.8: BAD_CTR counts the rejected */
    size_t n = 0;
    out[0] = 0;
    while (*in && n + 1 < cap) {
        bool hit = false;
        for (int i = 0; i < 3 && !hit; i++) {
            size_t ml = strlen(names[i]);
            if (strncmp(in, names[i], ml) != 0) continue;
            char num[24];
            int k = kelp_snprintf(num, sizeof num, "%lu", vals[i]);
            if (k > 0 && n + (size_t)k < cap) {
                memcpy(out + n, num, (size_t)k);
                n += (size_t)k;
            }
            in += ml;
            hit = true;
        }
        if (!hit) out[n++] = *in++;
    }
    out[n] = 0;
}

static void post_flags(const kelp_field_umh *h, const kelp_umh_flag *f, unsigned n, const kelp_field_sink *out)
{
    for (unsigned i = 0; i < n; i++) {
        if (!f[i].is_string) {
            out->publish(out->ctx, f[i].var, false, NULL, f[i].dval);
            continue;
        }
        char buf[KELP_UMH_FLAG_LEN + 64];
        expand(h, f[i].sval, buf, sizeof buf);
        out->publish(out->ctx, f[i].var, true, buf, 0);
    }
}

static kelp_umh_source *source(kelp_field_umh *h, const kelp_field_text *name)
{
    unsigned oldest = 0;
    for (unsigned i = 0; i < h->nsrc; i++) {
        if (kelp_strieq_n(name->p, name->n, h->src[i].name)) return &h->src[i];
        if (h->src[i].last < h->src[oldest].last) oldest = i;
    }
    unsigned i = h->nsrc < KELP_UMH_MAX_SOURCES ? h->nsrc++ : oldest;
    kelp_umh_source *s = &h->src[i];
    memset(s, 0, sizeof *s);
    copy_text(s->name, sizeof s->name, name->p, name->n);
    return s;
}

static int bad(kelp_field_umh *h, kelp_umh_list *l, unsigned long *ctr, const char *msg, const char *why,
               const kelp_field_sink *out)
{
    (*ctr)++;
    list_add(l, msg, why);
    h->summary_due = true;
    if (l == &h->last_invalid) return KELP_ERR_PARSE;
    post_flags(h, h->cfg.bad_flag, h->cfg.nbad_flag, out); /* 24.8: after a rejected message only */
    return KELP_ERR_ARG;
}

int kelp_field_umh_mail(kelp_field_umh *h, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out)
{
    if (strcmp(var, "NODE_MESSAGE") != 0) return 0;
    h->total++;
    h->last_msg = now;
    if (!is_string || !sval) return bad(h, &h->last_invalid, &h->invalid, "(a number)", "not a string", out);
    kelp_node_message m;
    kelp_diag_clear(&h->diag);
    if (kelp_field_nodemsg_parse(sval, strlen(sval), &m, &h->diag) < 0)
        return bad(h, &h->last_invalid, &h->invalid, sval, kelp_diag_text(&h->diag), out);
    /* well formed: counted valid (24.8 counts it before the address check) and listed */
    h->valid++;
    h->summary_due = true;
    char var_name[KELP_MAX_NAME];
    copy_text(var_name, sizeof var_name, m.var_name.p, m.var_name.n);
    kelp_umh_source *s = source(h, &m.src_node);
    s->total++;
    s->last = now;
    memcpy(s->var, var_name, sizeof s->var);
    if (m.has_string) copy_text(s->val, sizeof s->val, m.string_val.p, m.string_val.n);
    else {
        size_t n = 0;
        if (field_put_fixed(s->val, sizeof s->val, &n, m.double_val, 6, true) < 0) copy_text(s->val, sizeof s->val, "?", 1);
    }
    list_add(&h->last_valid, sval, NULL);
    /* addressing as MOOS-IvP 24.8: dest_node must be this community exactly (case and all; a
     * colon list is no name), "all" or "ALL"; no dest_node (a group message) is taken, unless
     * addressing is strict */
    bool all = m.dest_node.n == 3 && (memcmp(m.dest_node.p, "all", 3) == 0 || memcmp(m.dest_node.p, "ALL", 3) == 0);
    bool mine = m.dest_node.n == strlen(h->cfg.community) && memcmp(m.dest_node.p, h->cfg.community, m.dest_node.n) == 0;
    if (m.dest_node.n && !all && !mine) return bad(h, &h->last_rejected, &h->rejected, sval, "dest_node is not this node", out);
    if (h->cfg.strict && !mine)
        return bad(h, &h->last_rejected, &h->rejected, sval,
                   m.dest_node.n ? "dest_node all (strict addressing)" : "group address (strict addressing)", out);
    size_t an = m.src_node.n < KELP_MAX_NAME ? m.src_node.n : KELP_MAX_NAME - 1;
    copy_text(h->aux, sizeof h->aux, m.src_node.p, an);
    if (h->cfg.aux_app && m.src_app.n) {
        h->aux[an] = '+';
        copy_text(h->aux + an + 1, sizeof h->aux - an - 1, m.src_app.p, m.src_app.n);
    }
    h->posting = true;
    if (m.has_string) {
        copy_text(h->post, sizeof h->post, m.string_val.p, m.string_val.n);
        out->publish(out->ctx, var_name, true, h->post, 0);
    } else {
        out->publish(out->ctx, var_name, false, NULL, m.double_val);
    }
    h->posting = false;
    post_flags(h, h->cfg.msg_flag, h->cfg.nmsg_flag, out);
    return 1;
}

int kelp_field_umh_iterate(kelp_field_umh *h, kelp_time now, const kelp_field_sink *out)
{
    /* MOOS-IvP 24.8: after an iteration with NODE_MESSAGE mail, and on iterations 1, 101, 201, ... */
    h->iter++;
    if (!h->summary_due && h->iter % 100 != 1) return 0;
    char buf[128];
    /* seed 6.1.2: total, valid and rejected; written as 24.8 writes it */
    kelp_snprintf(buf, sizeof buf, "total=%lu,valid=%lu,rejected=%lu", h->total, h->valid, h->rejected);
    out->publish(out->ctx, "UMH_SUMMARY_MSGS", true, buf, 0);
    h->summary_due = false;
    h->last_summary = now;
    h->summaries++;
    return 1;
}

/* ------------------------------------------------------------------ report */

typedef struct outbuf {
    char *b;
    size_t cap, n;
} outbuf;

#define put(o, ...) field_putf((o)->b, (o)->cap, &(o)->n, __VA_ARGS__)

/* one "last few" list as 24.8 writes it: the valid ones cut at APPCAST_TRUNC_MSG with "...",
 * the invalid and rejected ones at 70 characters */
static void put_list(outbuf *o, const char *title, const kelp_umh_list *l, unsigned trunc, bool dots)
{
    put(o, "%s\n", title);
    if (!l->n) put(o, "  NONE  \n");
    for (unsigned i = 0; i < l->n; i++) {
        unsigned k = (l->first + i) % KELP_UMH_LAST;
        size_t len = strlen(l->msg[k]);
        bool cut = trunc && len > trunc;
        put(o, "  %.*s%s\n", (int)(cut ? trunc : len), l->msg[k], cut && dots ? "..." : "");
    }
}

#define UMH_RULE "======================================\n"

size_t kelp_field_umh_report(kelp_field_umh *h, kelp_time now, char *buf, size_t cap)
{
    if (!buf || !cap) return 0;
    outbuf o = { buf, cap, 0 };
    buf[0] = 0;
    h->reports++;
    /* MOOS-IvP 24.8's report (MessageHandler::buildReport): every message received under "Total
     * Received Valid", the invalid as total - valid */
    put(&o, "Overall Totals Summary\n" UMH_RULE);
    put(&o, "   Total Received Valid: %lu\n", h->total);
    put(&o, "                Invalid: %lu\n", h->total - h->valid);
    put(&o, "               Rejected: %lu\n", h->rejected);
    if (h->last_msg < 0) put(&o, "    Time since last Msg: N/A\n");
    else put(&o, "    Time since last Msg: %.1f\n", now - h->last_msg);
    if (!h->cfg.verbose) return o.n;
    put(&o, "\nPer Source Node Summary\n" UMH_RULE);
    /* a table as MOOS-IvP's ACTable draws it: columns as wide as their widest cell, two blanks
     * apart, a dashed line under the header; sources in name order */
    char tot[24], ela[24]; /* one cell at a time: the table is measured, then written */
    int w[5] = { 6, 5, 7, 8, 5 };
    for (unsigned i = 0; i < h->nsrc; i++) {
        const int c[5] = { (int)strlen(h->src[i].name), kelp_snprintf(tot, sizeof tot, "%lu", h->src[i].total),
                           kelp_snprintf(ela, sizeof ela, "%.1f", now - h->src[i].last), (int)strlen(h->src[i].var),
                           (int)strlen(h->src[i].val) };
        for (int j = 0; j < 5; j++)
            if (c[j] > w[j]) w[j] = c[j];
    }
    static const char dashes[] = "----------------------------------------------------------------";
    put(&o, "%-*s  %-*s  %-*s  %-*s  %s\n", w[0], "Source", w[1], "Total", w[2], "Elapsed", w[3], "Variable", "Value");
    put(&o, "%.*s  %.*s  %.*s  %.*s  %.*s", w[0], dashes, w[1], dashes, w[2], dashes, w[3], dashes, w[4], dashes);
    bool done[KELP_UMH_MAX_SOURCES] = { false };
    for (unsigned r = 0; r < h->nsrc; r++) {
        int best = -1;
        for (unsigned i = 0; i < h->nsrc; i++)
            if (!done[i] && (best < 0 || strcmp(h->src[i].name, h->src[best].name) < 0)) best = (int)i;
        if (best < 0) break;
        done[best] = true;
        const kelp_umh_source *s = &h->src[best];
        kelp_snprintf(tot, sizeof tot, "%lu", s->total);
        kelp_snprintf(ela, sizeof ela, "%.1f", now - s->last);
        put(&o, "\n%-*s  %-*s  %-*s  %-*s  %s", w[0], s->name, w[1], tot, w[2], ela, w[3], s->var, s->val);
    }
    put(&o, "\n\nLast Few Messages: (oldest to newest) \n" UMH_RULE);
    put_list(&o, "Valid Mgs: ", &h->last_valid, h->cfg.trunc, true);
    put_list(&o, "Invalid Mgs: ", &h->last_invalid, 70, false);
    put_list(&o, "Rejected Mgs: ", &h->last_rejected, 70, false);
    return o.n;
}
