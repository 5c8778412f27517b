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
    return kelp_util_strieq_n(k, kl, a) || (b && kelp_util_strieq_n(k, kl, b));
}

static void set_text(kelp_field_text *t, const char *v, size_t vl)
{
    t->p = v; /* 24.8's setters: the last of a repeated key wins */
    t->n = vl;
}

static bool blank(char c)
{
    return c == ' ' || c == '\t';
}

/* MBUtils' stripBlankEnds: blanks and tabs off both ends */
static void strip_blanks(const char **p, size_t *n)
{
    while (*n && blank(**p)) (*p)++, (*n)--;
    while (*n && blank((*p)[*n - 1])) (*n)--;
}

/* MBUtils' isQuoted / stripQuotes: a text whose blank-stripped form starts and ends with '"'
 * loses those two characters (and the blanks outside them); any other text is kept whole */
static bool strip_quotes(const char **p, size_t *n)
{
    const char *q = *p;
    size_t k = *n;
    strip_blanks(&q, &k);
    if (k < 2 || q[0] != '"' || q[k - 1] != '"') return false;
    *p = q + 1;
    *n = k - 2;
    return true;
}

/* The next item of s[0..len) as MOOS-IvP's parseStringQ cuts a message at ',': a separator
 * inside double quotes or braces does not count; a brace is counted inside quotes too, a '}'
 * with none open is plain text, and an unclosed quote or brace runs to the end of the text
 * (an item, not an error: field_next_item refuses those). @return false at the end. */
static bool next_item_q(const char *s, size_t len, size_t *pos, const char **item, size_t *ilen)
{
    if (*pos >= len) return false;
    bool quote = false;
    unsigned depth = 0;
    size_t i = *pos;
    for (; i < len && (s[i] != ',' || quote || depth); i++) {
        if (s[i] == '"') quote = !quote;
        else if (s[i] == '{') depth++;
        else if (s[i] == '}' && depth) depth--;
    }
    *item = s + *pos;
    *ilen = i - *pos;
    *pos = i < len ? i + 1 : len;
    return true;
}

/* The span of v[0..vl) that C's atof reads (leading white space, a sign, digits with a point
 * and an exponent, inf, infinity or nan), converted by kelp's parser; 0 when there is none.
 * Not read: hexadecimal ("0x1A" is 0 here, 26 for atof) and nan(...) payloads. */
static double atof_n(const char *v, size_t vl)
{
    size_t i = 0;
    while (i < vl && (v[i] == ' ' || (v[i] >= '\t' && v[i] <= '\r'))) i++;
    size_t b = i;
    if (i < vl && (v[i] == '+' || v[i] == '-')) i++;
    const char *w = v + i;
    size_t wl = vl - i, end;
    if (wl >= 8 && kelp_util_strieq_n(w, 8, "infinity")) end = i + 8;
    else if (wl >= 3 && (kelp_util_strieq_n(w, 3, "inf") || kelp_util_strieq_n(w, 3, "nan"))) end = i + 3;
    else {
        size_t digits = 0;
        for (; i < vl && v[i] >= '0' && v[i] <= '9'; i++) digits++;
        if (i < vl && v[i] == '.')
            for (i++; i < vl && v[i] >= '0' && v[i] <= '9'; i++) digits++;
        if (!digits) return 0.0;
        end = i;
        if (i < vl && (v[i] == 'e' || v[i] == 'E')) {
            i++;
            if (i < vl && (v[i] == '+' || v[i] == '-')) i++;
            if (i < vl && v[i] >= '0' && v[i] <= '9') {
                while (i < vl && v[i] >= '0' && v[i] <= '9') i++;
                end = i;
            }
        }
    }
    double d;
    return kelp_util_parse_double(v + b, end - b, &d) == 0 ? d : 0.0;
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
    else if (key_is(k, kl, "string_val", NULL)) {
        set_text(&m->string_val, v, vl);
        m->has_string = true;
    } else if (key_is(k, kl, "color", NULL)) set_text(&m->color, v, vl);
    else if (key_is(k, kl, "ack_id", "msg_id")) set_text(&m->ack_id, v, vl);
    /* as 24.8: only "true" (any case) sets these, and nothing clears them again */
    else if (key_is(k, kl, "string_val_quoted", NULL) && kelp_util_strieq_n(v, vl, "true")) m->string_val_quoted = true;
    else if (key_is(k, kl, "ack", NULL) && kelp_util_strieq_n(v, vl, "true")) m->ack = true;
    else if (key_is(k, kl, "double_val", NULL)) {
        set_text(dval, v, vl);
        m->has_double = true;
    }
    /* unknown keys: nothing to keep */
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
    while (next_item_q(s, len, &pos, &it, &il)) {
        /* 24.8 (string2NodeMessage): the key is the blank-stripped text before the first '=',
         * any case, the value the blank-stripped rest; an item with no '=' is a key alone */
        const char *eq = memchr(it, '=', il);
        if (!eq) eq = memchr(it, ';', il); /* the seed's "dest_node;bravo" */
        if (!eq) continue;                 /* a key with no value: nothing 24.8 reads */
        const char *k = it, *v = eq + 1;
        size_t kl = (size_t)(eq - it), vl = il - kl - 1;
        strip_blanks(&k, &kl);
        strip_blanks(&v, &vl);
        take_pair(m, &var_alt, &dval, k, kl, v, vl);
    }
    if (!m->var_name.n) m->var_name = var_alt;
    /* the string value as 24.8 carries it: quotes removed once when string_val_quoted=true
     * says they were added (string2NodeMessage), then once more if it is still quoted
     * (MessageHandler); NodeMessage::valid() judges the text between the two */
    m->string_quoted = m->string_val_quoted && strip_quotes(&m->string_val.p, &m->string_val.n);
    bool string_set = m->string_val.n > 0;
    m->string_quoted |= strip_quotes(&m->string_val.p, &m->string_val.n);
    if (!m->src_node.n) return kelp_fail(d, KELP_ERR_PARSE, "no src_node");
    if (!m->dest_node.n && !m->dest_group.n) return kelp_fail(d, KELP_ERR_PARSE, "no dest_node or dest_group");
    if (!m->var_name.n) return kelp_fail(d, KELP_ERR_PARSE, "no var_name");
    if (string_set && m->has_double) return kelp_fail(d, KELP_ERR_PARSE, "both string_val and double_val");
    if (!name_ok(m->var_name.p, m->var_name.n)) return kelp_fail(d, KELP_ERR_PARSE, "var_name is not a variable name");
    if (kelp_util_strieq_n(m->var_name.p, m->var_name.n, "NODE_MESSAGE")) return kelp_fail(d, KELP_ERR_PARSE, "var_name NODE_MESSAGE would loop");
    /* 24.8 posts a string only when one is left after the quotes; otherwise the double
     * (0 when there is none), read as atof reads it */
    m->has_string = m->string_val.n > 0;
    if (!m->has_string) m->string_val.p = NULL;
    m->double_val = m->has_double ? atof_n(dval.p, dval.n) : 0.0;
    return KELP_OK;
}

bool kelp_field_nodemsg_to(const kelp_node_message *m, const char *me)
{
    size_t pos = 0;
    const char *it;
    size_t il;
    while (field_next_item(m->dest_node.p, m->dest_node.n, &pos, ':', &it, &il) == 1)
        if (kelp_util_strieq_n(it, il, me)) return true;
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

/* MBUtils' setBooleanOnString: true/false, yes/no, on/off (any case); toggle flips */
static int parse_bool(const char *val, bool *out, kelp_diag *d)
{
    size_t n = strlen(val);
    if (kelp_util_strieq_n(val, n, "on")) *out = true;
    else if (kelp_util_strieq_n(val, n, "off")) *out = false;
    else if (kelp_util_strieq_n(val, n, "toggle")) *out = !*out;
    else if (kelp_util_parse_bool(val, n, out) != KELP_OK) return kelp_fail(d, KELP_ERR_PARSE, "expected true or false");
    return 1;
}

/* MBUtils' isNumber: digits, at most one point, '-' only before them, a leading '+' */
static bool moos_number(const char *v, size_t n)
{
    strip_blanks(&v, &n);
    if (n > 1 && v[0] == '+') v++, n--;
    unsigned digits = 0, points = 0;
    for (size_t i = 0; i < n; i++) {
        if (v[i] >= '0' && v[i] <= '9') digits++;
        else if (v[i] == '.') {
            if (++points > 1) return false;
        } else if (v[i] != '-' || digits || points) return false;
    }
    return digits > 0;
}

/* past a word and the blanks after it (24.8's biteStringX at ' '); false when nothing follows */
static bool skip_word(const char **p, size_t *l)
{
    const char *sp = memchr(*p, ' ', *l);
    if (!sp) return false;
    *l -= (size_t)(sp + 1 - *p);
    *p = sp + 1;
    strip_blanks(p, l);
    return *l > 0;
}

/* "VAR=value" read as 24.8's addVarDataPairOnString: "clearall" empties the list; a post tag
 * (@.., <.., >..), a destination tag (#..) and a "[if] ..." condition are read and not used
 * (24.8's handler posts its flags unconditionally); the value is a double when MBUtils'
 * isNumber says so (read as atof), else a string without its enclosing quotes */
static int parse_flag(kelp_umh_flag *f, unsigned *n, const char *val, kelp_diag *d)
{
    if (strcmp(val, "clearall") == 0) {
        *n = 0;
        return 1;
    }
    const char *p = val;
    size_t l = strlen(val);
    strip_blanks(&p, &l);
    if (l && (*p == '@' || *p == '<' || *p == '>') && !skip_word(&p, &l)) {
        return kelp_fail(d, KELP_ERR_PARSE, "a post tag with no VAR=value after it");
    }
    if (l && *p == '#' && !skip_word(&p, &l)) {
        return kelp_fail(d, KELP_ERR_PARSE, "a destination tag with no VAR=value after it");
    }
    for (size_t i = l; i >= 4; i--) /* the last "[if]" ends the pair */
        if (memcmp(p + i - 4, "[if]", 4) == 0) {
            l = i - 4;
            break;
        }
    const char *eq = memchr(p, '=', l);
    const char *k = p, *v = eq ? eq + 1 : p + l;
    size_t kl = eq ? (size_t)(eq - p) : l, vl = eq ? l - kl - 1 : 0;
    strip_blanks(&k, &kl);
    strip_blanks(&v, &vl);
    if (!kl || !vl) {
        return kelp_fail(d, KELP_ERR_PARSE, "expected VAR=value");
    }
    if (!name_ok(k, kl)) {
        return kelp_fail(d, KELP_ERR_PARSE, "the flag's variable is not a variable name");
    }
    if (*n >= KELP_UMH_MAX_FLAGS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many flags (at most 8 of each kind)");
    }
    kelp_umh_flag *t = &f[*n];
    memset(t, 0, sizeof *t);
    copy_text(t->var, sizeof t->var, k, kl);
    if (moos_number(v, vl)) {
        t->dval = atof_n(v, vl);
        t->is_string = false;
    } else {
        strip_quotes(&v, &vl);
        if (vl >= sizeof t->sval) {
            return kelp_fail(d, KELP_ERR_RANGE, "the flag's value is too long");
        }
        copy_text(t->sval, sizeof t->sval, v, vl);
        t->is_string = true;
    }
    (*n)++;
    return 1;
}

int kelp_field_umh_config(kelp_field_umh_cfg *c, const char *key, const char *val, kelp_diag *d)
{
    size_t kl = strlen(key), vl = strlen(val);
    if (kelp_util_strieq_n(key, kl, "VERBOSE")) return parse_bool(val, &c->verbose, d);
    if (kelp_util_strieq_n(key, kl, "STRICT_ADDRESSING")) return parse_bool(val, &c->strict, d);
    if (kelp_util_strieq_n(key, kl, "AUX_INFO")) {
        /* as 24.8 compares them: exactly these two, in lower case */
        if (strcmp(val, "node") == 0) c->aux_app = false;
        else if (strcmp(val, "node+app") == 0) c->aux_app = true;
        else {
            return kelp_fail(d, KELP_ERR_PARSE, "expected node or node+app");
        }
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "APPCAST_TRUNC_MSG")) {
        /* 24.8: a number (MBUtils' isNumber) read as atoi; below 0 is 0 */
        if (!moos_number(val, vl)) {
            return kelp_fail(d, KELP_ERR_PARSE, "expected a number of characters (0: whole)");
        }
        double n = trunc(atof_n(val, vl));
        c->trunc = n <= 0 ? 0u : n >= 2147483647.0 ? 2147483647u : (unsigned)n;
        return 1;
    }
    if (kelp_util_strieq_n(key, kl, "MSG_FLAG")) return parse_flag(c->msg_flag, &c->nmsg_flag, val, d);
    if (kelp_util_strieq_n(key, kl, "BAD_MSG_FLAG")) return parse_flag(c->bad_flag, &c->nbad_flag, val, d);
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

/* $[CTR] / $(CTR) (messages received), $[GOOD_CTR] / $(GOOD_CTR) (well formed, rejected ones
 * included) and $[BAD_CTR] / $(BAD_CTR) (rejected) expanded into out, as 24.8's MacroUtils
 * macroExpand writes both forms */
static void expand(const kelp_field_umh *h, const char *in, char *out, size_t cap)
{
    static const char *const names[] = { "$[CTR]", "$(CTR)", "$[GOOD_CTR]", "$(GOOD_CTR)", "$[BAD_CTR]", "$(BAD_CTR)" };
    unsigned long vals[] = { h->total, h->total, h->valid, h->valid, h->rejected, h->rejected };
    size_t n = 0;
    out[0] = 0;
    while (*in && n + 1 < cap) {
        bool hit = false;
        for (int i = 0; i < 6 && !hit; i++) {
            size_t ml = strlen(names[i]);
            if (strncmp(in, names[i], ml) != 0) continue;
            char num[24];
            int k = kelp_util_snprintf(num, sizeof num, "%lu", vals[i]);
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

/* MBUtils' doubleToStringX(v, 6): "%.6f" without trailing zeros and point, never "-0" (past
 * kelp_util_fmt_fixed's range, as 24.8 does it: "%.6e" above 2^128, and its zeros stripped too) */
static void double_x(char *buf, size_t cap, double v)
{
    if (kelp_util_fmt_fixed(buf, cap, v, 6, true) >= 0) return;
    kelp_util_snprintf(buf, cap, v > 0x1p128 ? "%.6e" : "%.6f", v);
    size_t n = strlen(buf);
    if (!strchr(buf, '.')) return;
    while (n && buf[n - 1] == '0') n--;
    if (n && buf[n - 1] == '.') n--;
    buf[n] = 0;
}

static kelp_umh_source *source(kelp_field_umh *h, const kelp_field_text *name)
{
    size_t kept = name->n < KELP_MAX_NAME ? name->n : KELP_MAX_NAME - 1;
    unsigned oldest = 0;
    for (unsigned i = 0; i < h->nsrc; i++) {
        /* 24.8 keys its table by the name as written (alpha and Alpha are two sources) */
        if (strlen(h->src[i].name) == kept && memcmp(name->p, h->src[i].name, kept) == 0) return &h->src[i];
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

/* the time step rule (docs/ARCHITECTURE.md): a `now` that is no time is refused; after a step
 * back the stored times move back by the step, so no age in the report is negative */
static bool clock_ok(kelp_field_umh *h, kelp_time now)
{
    if (!kelp_util_time_ok(now)) return false;
    double back = kelp_util_clock_back(&h->clock, now);
    if (back > 0) {
        if (h->last_msg >= 0) h->last_msg -= back;
        h->last_summary -= back;
        for (unsigned i = 0; i < h->nsrc; i++) h->src[i].last -= back;
    }
    return true;
}

int kelp_field_umh_mail(kelp_field_umh *h, const char *var, bool is_string, const char *sval, kelp_time now,
                        const kelp_field_sink *out)
{
    if (strcmp(var, "NODE_MESSAGE") != 0) return 0;
    if (!clock_ok(h, now)) return KELP_ERR_ARG;
    h->total++;
    h->last_msg = now;
    /* a double: 24.8 reads its (empty) string, an invalid message listed as "" */
    if (!is_string || !sval) return bad(h, &h->last_invalid, &h->invalid, "", "not a string", out);
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
    else double_x(s->val, sizeof s->val, m.double_val);
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
    if (!clock_ok(h, now)) return 0;
    h->iter++;
    if (!h->summary_due && h->iter % 100 != 1) return 0;
    char buf[128];
    /* seed 6.1.2: total, valid and rejected; written as 24.8 writes it */
    kelp_util_snprintf(buf, sizeof buf, "total=%lu,valid=%lu,rejected=%lu", h->total, h->valid, h->rejected);
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

/* The per-source table as MOOS-IvP 24.8's ACTable (lib_apputil) builds it from the stream of
 * cells MessageHandler::buildReport writes: the header's five, five dashed ones, then name,
 * total, elapsed, variable and value of each source in name order. Each text is cut at every
 * '|' into cells (ACTable's operator<<, blanks stripped; "" is one empty cell, "_ignore_" none),
 * cells fill rows of five; a column is as wide as its widest cell ("{}", a dashed cell, counts
 * two), cells are padded on the right and two blanks apart, each row loses its trailing blanks,
 * rows are joined by newlines, and a last row left short is not drawn. Walked twice (measured,
 * then drawn) so nothing is held but the column widths. */
#define UMH_COLS 5

typedef struct table {
    outbuf *o;
    size_t w[UMH_COLS];
    unsigned long cell; /* cells so far */
    size_t row_start;   /* where the row being drawn starts in the output */
} table;

typedef void (*cell_fn)(table *t, const char *c, size_t n);

/* one text as ACTable's operator<< takes it */
static void cells(table *t, cell_fn fn, const char *s)
{
    if (strcmp(s, "_ignore_") == 0) return;
    if (!*s) {
        fn(t, s, 0);
        return;
    }
    while (*s) { /* MBUtils' parseString: a trailing '|' adds no cell */
        const char *e = strchr(s, '|');
        size_t n = e ? (size_t)(e - s) : strlen(s), cn = n;
        const char *c = s;
        strip_blanks(&c, &cn);
        fn(t, c, cn);
        s += n + (e ? 1 : 0);
    }
}

static void walk_table(const kelp_field_umh *h, kelp_time now, cell_fn fn, table *t)
{
    cells(t, fn, "Source | Total | Elapsed | Variable | Value");
    for (int i = 0; i < UMH_COLS; i++) fn(t, "{}", 2);
    const char *prev = NULL;
    for (unsigned r = 0; r < h->nsrc; r++) {
        const kelp_umh_source *s = NULL; /* the next name after prev (names are distinct) */
        for (unsigned i = 0; i < h->nsrc; i++)
            if ((!prev || strcmp(h->src[i].name, prev) > 0) && (!s || strcmp(h->src[i].name, s->name) < 0)) s = &h->src[i];
        if (!s) break;
        prev = s->name;
        char num[32];
        cells(t, fn, s->name);
        kelp_util_snprintf(num, sizeof num, "%lu", s->total);
        cells(t, fn, num);
        kelp_util_snprintf(num, sizeof num, "%.1f", now - s->last);
        cells(t, fn, num);
        cells(t, fn, s->var);
        cells(t, fn, s->val);
    }
}

static void measure(table *t, const char *c, size_t n)
{
    (void)c;
    size_t j = t->cell++ % UMH_COLS;
    if (n > t->w[j]) t->w[j] = n;
}

static void draw(table *t, const char *c, size_t n)
{
    outbuf *o = t->o;
    size_t j = t->cell++ % UMH_COLS;
    if (j == 0) {
        t->row_start = o->n; /* with its newline: a row left short goes whole */
        if (t->cell > 1) put(o, "\n");
    } else put(o, "  ");
    bool dashes = n == 2 && c[0] == '{' && c[1] == '}';
    if (!dashes) put(o, "%.*s", (int)n, c);
    for (size_t k = dashes ? 0 : n; k < t->w[j]; k++) put(o, dashes ? "-" : " ");
    if (j == UMH_COLS - 1) { /* MBUtils' removeWhiteEnd */
        while (o->n > t->row_start + (t->cell > UMH_COLS) && (o->b[o->n - 1] == ' ' || o->b[o->n - 1] == '\t')) o->n--;
        if (o->n < o->cap) o->b[o->n] = 0;
    }
}

#define UMH_RULE "======================================\n"

size_t kelp_field_umh_report(kelp_field_umh *h, kelp_time now, char *buf, size_t cap)
{
    if (!buf || !cap) return 0;
    if (!clock_ok(h, now)) now = h->clock.last; /* a `now` that is no time: the newest one seen */
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
    table t;
    memset(&t, 0, sizeof t);
    t.o = &o;
    walk_table(h, now, measure, &t);
    t.cell = 0;
    walk_table(h, now, draw, &t);
    if (t.cell % UMH_COLS) { /* ACTable drops a row it never filled */
        o.n = t.row_start;
        if (o.n < o.cap) o.b[o.n] = 0;
    }
    put(&o, "\n\nLast Few Messages: (oldest to newest) \n" UMH_RULE);
    put_list(&o, "Valid Mgs: ", &h->last_valid, h->cfg.trunc, true);
    put_list(&o, "Invalid Mgs: ", &h->last_invalid, 70, false);
    put_list(&o, "Rejected Mgs: ", &h->last_rejected, 70, false);
    return o.n;
}
