/* kelp AppCast: the APPCAST string, its terminal form and APPCAST_REQ (see kelp/appcast.h). */
#include <string.h>
#include <kelp/appcast.h>
#include <kelp/kv.h>
#include <kelp/util.h>

#define OSEP "!@#"
#define ISEP "!@"

typedef struct out {
    char *buf;
    size_t cap, n;
    bool full;
} out;

static void put(out *o, const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (o->n + 1 < o->cap) o->buf[o->n] = s[i];
        else o->full = true;
        o->n++;
    }
    if (o->cap) o->buf[o->n < o->cap ? o->n : o->cap - 1] = '\0';
}

static void puts_(out *o, const char *s)
{
    put(o, s, strlen(s));
}

/* field text: a separator inside it would split the cast, so "!@" goes out as "!_"; and text
 * that starts with '#' right after an inner "!@" would read as the outer "!@#": a space goes
 * first (list items are trimmed when read) */
static void put_text(out *o, const char *s, size_t n)
{
    if (n && s[0] == '#' && o->n >= 2 && o->n < o->cap && o->buf[o->n - 1] == '@' &&
        o->buf[o->n - 2] == '!')
        put(o, " ", 1);
    for (size_t i = 0; i < n; i++) {
        if (s[i] == '!' && i + 1 < n && s[i + 1] == '@') {
            put(o, "!_", 2);
            i++;
        } else {
            put(o, &s[i], 1);
        }
    }
}

static void put_ul(out *o, unsigned long v)
{
    char t[24];
    int n = kelp_util_snprintf(t, sizeof t, "%lu", v);
    put(o, t, (size_t)n);
}

static int finish(out *o, size_t *len)
{
    if (len) *len = o->n;
    return o->full ? KELP_ERR_NOSPACE : KELP_OK;
}

int kelp_appcast_format(const kelp_appcast *ac, char *buf, size_t cap, size_t *len)
{
    out o = {buf, cap, 0, false};
    if (cap) buf[0] = '\0';
    puts_(&o, "proc=");
    put_text(&o, ac->proc, strlen(ac->proc));
    puts_(&o, OSEP "iter=");
    put_ul(&o, ac->iter);
    puts_(&o, OSEP);
    if (ac->node[0]) {
        puts_(&o, "node=");
        put_text(&o, ac->node, strlen(ac->node));
        puts_(&o, OSEP);
    }
    puts_(&o, "iter=");
    put_ul(&o, ac->iter);
    puts_(&o, OSEP "messages=");
    for (const char *p = ac->messages; *p;) {
        const char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        put_text(&o, p, n);
        puts_(&o, ISEP);
        p += n + (nl ? 1 : 0);
    }
    puts_(&o, OSEP);
    if (ac->ncfg) {
        puts_(&o, "config_warnings=");
        for (unsigned i = 0; i < ac->ncfg; i++) {
            if (i) puts_(&o, ISEP);
            put_text(&o, ac->cfg[i], strlen(ac->cfg[i]));
        }
    }
    puts_(&o, OSEP "events_total=");
    put_ul(&o, ac->nevents);
    puts_(&o, OSEP);
    if (ac->nevents) {
        puts_(&o, "events=");
        for (unsigned i = 0; i < ac->nevents; i++) {
            if (i) puts_(&o, ISEP);
            put_text(&o, ac->events[i], strlen(ac->events[i]));
        }
    }
    puts_(&o, OSEP "run_warning_total=");
    put_ul(&o, ac->run_total);
    puts_(&o, OSEP);
    if (ac->nrun) {
        /* in text order, as a sorted map gives them */
        bool done[KELP_APPCAST_ITEMS] = {false};
        puts_(&o, "run_warnings=");
        for (unsigned k = 0; k < ac->nrun && k < KELP_APPCAST_ITEMS; k++) {
            int best = -1;
            for (unsigned i = 0; i < ac->nrun && i < KELP_APPCAST_ITEMS; i++)
                if (!done[i] && (best < 0 || strcmp(ac->run[i], ac->run[best]) < 0)) best = (int)i;
            if (best < 0) break;
            done[best] = true;
            if (k) puts_(&o, ISEP);
            put_ul(&o, ac->run_count[best]);
            puts_(&o, ":");
            put_text(&o, ac->run[best], strlen(ac->run[best]));
        }
    }
    return finish(&o, len);
}

/* ---- parsing ---- */

static const char *find(const char *s, size_t len, const char *sep)
{
    size_t k = strlen(sep);
    for (size_t i = 0; i + k <= len; i++)
        if (memcmp(s + i, sep, k) == 0) return s + i;
    return NULL;
}

static void trim(const char **s, size_t *n)
{
    while (*n && (**s == ' ' || **s == '\t')) (*s)++, (*n)--;
    while (*n && ((*s)[*n - 1] == ' ' || (*s)[*n - 1] == '\t')) (*n)--;
}

/* a field's text as kelp_appcast_format would write it: up to a NUL, "!@" as "!_" */
static void copy(char *dst, size_t cap, const char *s, size_t n)
{
    size_t o = 0;
    for (size_t i = 0; i < n && s[i] && o + 1 < cap; i++) {
        dst[o++] = s[i];
        if (s[i] == '!' && i + 1 < n && s[i + 1] == '@' && o + 1 < cap) {
            dst[o++] = '_';
            i++;
        }
    }
    while (o && (dst[o - 1] == ' ' || dst[o - 1] == '\t')) o--; /* a NUL cut the text short of its trim */
    dst[o] = '\0';
}

static unsigned long to_ul(const char *s, size_t n)
{
    long v = 0;
    return kelp_util_parse_long(s, n, &v) == KELP_OK && v > 0 ? (unsigned long)v : 0;
}

/* the items of a "!@"-separated list, each into list[*count] (trimmed) */
static void split_list(const char *v, size_t vl, char (*list)[KELP_APPCAST_ITEM], unsigned *count,
                       unsigned long *counts)
{
    while (vl) {
        const char *e = find(v, vl, ISEP);
        size_t n = e ? (size_t)(e - v) : vl;
        const char *item = v;
        size_t il = n;
        trim(&item, &il);
        if (il && *count < KELP_APPCAST_ITEMS) {
            if (counts) {
                /* "count:text" */
                const char *c = memchr(item, ':', il);
                size_t cl = c ? (size_t)(c - item) : 0;
                counts[*count] = c ? to_ul(item, cl) : 1;
                if (c) item += cl + 1, il -= cl + 1;
                trim(&item, &il);
            }
            copy(list[*count], KELP_APPCAST_ITEM, item, il);
            if (list[*count][0]) (*count)++; /* a NUL may have emptied it */
        }
        if (!e) break;
        v = e + 2;
        vl -= n + 2;
    }
}

/* the next "key=value" part of an APPCAST string (both trimmed; *has_eq false for a part
 * without '='), advancing *s / *len past it and its separator; false at the end */
static bool next_part(const char **s, size_t *len, const char **k, size_t *kl, const char **v, size_t *vl,
                      bool *has_eq)
{
    if (*len == 0) return false;
    const char *e = find(*s, *len, OSEP);
    size_t n = e ? (size_t)(e - *s) : *len;
    const char *eq = memchr(*s, '=', n);
    *k = *s, *v = eq ? eq + 1 : NULL;
    *kl = eq ? (size_t)(eq - *s) : n, *vl = eq ? n - *kl - 1 : 0;
    *has_eq = eq != NULL;
    trim(k, kl);
    if (eq) trim(v, vl);
    *len = e ? *len - n - 3 : 0;
    *s = e ? e + 3 : *s + n;
    return true;
}

int kelp_appcast_field(const char *s, size_t len, const char *key, char *dst, size_t cap)
{
    const char *k, *v;
    size_t kl, vl;
    bool eq;
    while (next_part(&s, &len, &k, &kl, &v, &vl, &eq))
        if (eq && kl == strlen(key) && kelp_util_strieq_n(k, kl, key)) {
            if (cap) copy(dst, cap, v, vl);
            return 1;
        }
    return 0;
}

int kelp_appcast_parse(const char *s, size_t len, kelp_appcast *out_, kelp_diag *d)
{
    memset(out_, 0, sizeof *out_);
    bool have_proc = false;
    const char *k, *v;
    size_t kl, vl;
    bool eq;
    while (next_part(&s, &len, &k, &kl, &v, &vl, &eq)) {
        if (kl && !eq) return kelp_fail(d, KELP_ERR_PARSE, "a part without '='");
        if (kl == 0) {
            /* empty part */
        } else if (kelp_util_strieq_n(k, kl, "proc")) {
            copy(out_->proc, sizeof out_->proc, v, vl);
            have_proc = out_->proc[0] != '\0';
        } else if (kelp_util_strieq_n(k, kl, "node")) {
            copy(out_->node, sizeof out_->node, v, vl);
        } else if (kelp_util_strieq_n(k, kl, "iter")) {
            out_->iter = to_ul(v, vl);
        } else if (kelp_util_strieq_n(k, kl, "messages")) {
            size_t o = 0;
            while (vl) {
                const char *ie = find(v, vl, ISEP);
                size_t il = ie ? (size_t)(ie - v) : vl;
                for (size_t i = 0; i < il && v[i] && o + 2 < sizeof out_->messages; i++) {
                    out_->messages[o++] = v[i];
                    if (v[i] == '!' && i + 1 < il && v[i + 1] == '@' && o + 2 < sizeof out_->messages) {
                        out_->messages[o++] = '_';
                        i++;
                    }
                }
                if (o + 2 < sizeof out_->messages) out_->messages[o++] = '\n';
                if (!ie) break;
                v = ie + 2;
                vl -= il + 2;
            }
            out_->messages[o] = '\0';
        } else if (kelp_util_strieq_n(k, kl, "config_warnings")) {
            split_list(v, vl, out_->cfg, &out_->ncfg, NULL);
        } else if (kelp_util_strieq_n(k, kl, "events")) {
            split_list(v, vl, out_->events, &out_->nevents, NULL);
        } else if (kelp_util_strieq_n(k, kl, "run_warnings")) {
            split_list(v, vl, out_->run, &out_->nrun, out_->run_count);
        } else if (kelp_util_strieq_n(k, kl, "run_warning_total")) {
            out_->run_total = to_ul(v, vl);
        }
    }
    if (!have_proc) return kelp_fail(d, KELP_ERR_PARSE, "no proc=");
    return KELP_OK;
}

/* ---- the terminal form ---- */

int kelp_appcast_render(const kelp_appcast *ac, char *buf, size_t cap, size_t *len)
{
    out o = {buf, cap, 0, false};
    if (cap) buf[0] = '\0';
    static const char rule[] = "==============================================================\n";
    char t[KELP_APPCAST_NAME * 2 + 64], w[48];
    int tn = kelp_util_snprintf(t, sizeof t, "%s %s", ac->proc, ac->node);
    int wn = kelp_util_snprintf(w, sizeof w, "%u/%lu(%lu)", ac->ncfg, ac->run_total, ac->iter);
    puts_(&o, rule);
    puts_(&o, t);
    for (int pad = 62 - tn - wn; pad > 0; pad--) put(&o, " ", 1);
    puts_(&o, w);
    puts_(&o, "\n");
    puts_(&o, rule);
    char line[KELP_APPCAST_ITEM + 48];
    if (ac->ncfg) {
        kelp_util_snprintf(line, sizeof line, "Configuration Warnings: %u\n", ac->ncfg);
        puts_(&o, line);
        for (unsigned i = 0; i < ac->ncfg; i++) {
            kelp_util_snprintf(line, sizeof line, " [%u of %u]: %s\n", i + 1, ac->ncfg, ac->cfg[i]);
            puts_(&o, line);
        }
        puts_(&o, "\n");
    }
    if (ac->run_total) {
        kelp_util_snprintf(line, sizeof line, "Runtime Warnings: %lu\n", ac->run_total);
        puts_(&o, line);
        for (unsigned i = 0; i < ac->nrun; i++) {
            kelp_util_snprintf(line, sizeof line, " [%lu]: %s\n", ac->run_count[i], ac->run[i]);
            puts_(&o, line);
        }
        puts_(&o, "\n");
    }
    puts_(&o, ac->messages);
    puts_(&o, "\n");
    if (ac->nevents) {
        static const char erule[] = "===================================================================\n";
        puts_(&o, erule);
        kelp_util_snprintf(line, sizeof line, "Most Recent Events (%u):\n", ac->nevents);
        puts_(&o, line);
        puts_(&o, erule);
        for (unsigned i = ac->nevents; i-- > 0;) {
            puts_(&o, ac->events[i]);
            puts_(&o, "\n");
        }
    }
    return finish(&o, len);
}

/* ---- APPCAST_REQ ---- */

int kelp_appcast_req_parse(const char *s, size_t len, kelp_appcast_req *r)
{
    memset(r, 0, sizeof *r);
    memcpy(r->thresh, "any", 4);
    size_t pos = 0;
    const char *k, *v;
    size_t kl, vl;
    int rc;
    if (len >= 512) return KELP_ERR_RANGE;
    const char *nul = memchr(s, '\0', len);
    if (nul) len = (size_t)(nul - s); /* a C string's end, wherever the length says */
    while ((rc = kelp_kv_next_n(s, len, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        if (kelp_util_strieq_n(k, kl, "node")) copy(r->node, sizeof r->node, v, vl);
        else if (kelp_util_strieq_n(k, kl, "app")) copy(r->app, sizeof r->app, v, vl);
        else if (kelp_util_strieq_n(k, kl, "key")) copy(r->key, sizeof r->key, v, vl);
        else if (kelp_util_strieq_n(k, kl, "thresh")) copy(r->thresh, sizeof r->thresh, v, vl);
        else if (kelp_util_strieq_n(k, kl, "duration")) {
            double d = 0;
            if (kelp_util_parse_finite(v, vl, &d) != KELP_OK) d = 0; /* as atof: junk is 0 */
            r->duration = d < 0 ? 0 : d > 30 ? 30 : d;
        }
    }
    if (rc < 0) return rc;
    return r->key[0] ? KELP_OK : KELP_ERR_PARSE;
}

bool kelp_appcast_req_matches(const kelp_appcast_req *r, const char *node, const char *app)
{
    bool n = !r->node[0] || strcmp(r->node, "all") == 0 || strcmp(r->node, node) == 0;
    bool a = !r->app[0] || strcmp(r->app, "all") == 0 || strcmp(r->app, app) == 0;
    return n && a;
}
