/* Text helpers for node reports and VIEW_* strings: pair walking and number printing. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdint.h>
#include <string.h>
#include <kelp/err.h>
#include <kelp/mission.h>
#include <kelp/util.h>
#include "field_int.h"

static bool is_ws(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

static void trim(const char **p, size_t *n)
{
    while (*n && is_ws(**p)) (*p)++, (*n)--;
    while (*n && is_ws((*p)[*n - 1])) (*n)--;
}

int field_next_item(const char *s, size_t len, size_t *pos, char sep, const char **item, size_t *ilen)
{
    for (;;) {
        if (*pos >= len) return 0;
        size_t i = *pos;
        int depth = 0;
        bool quote = false;
        for (; i < len; i++) {
            char c = s[i];
            if (c == '\0') break;
            if (quote) {
                if (c == '"') quote = false;
                continue;
            }
            if (c == '"') quote = true;
            else if (c == '{') depth++;
            else if (c == '}') {
                if (--depth < 0) return KELP_ERR_PARSE;
            } else if (c == sep && depth == 0)
                break;
        }
        if (quote || depth != 0) return KELP_ERR_PARSE;
        const char *p = s + *pos;
        size_t n = i - *pos;
        *pos = (i < len && s[i] == sep) ? i + 1 : len;
        if (i < len && s[i] == '\0') *pos = len;
        trim(&p, &n);
        if (n == 0) continue;
        *item = p;
        *ilen = n;
        return 1;
    }
}

/* first '=' of v outside braces and quotes, or vl */
static size_t find_eq(const char *v, size_t vl)
{
    int depth = 0;
    bool quote = false;
    for (size_t i = 0; i < vl; i++) {
        char c = v[i];
        if (quote) {
            if (c == '"') quote = false;
        } else if (c == '"')
            quote = true;
        else if (c == '{')
            depth++;
        else if (c == '}')
            depth--;
        else if (c == '=' && depth == 0)
            return i;
    }
    return vl;
}

int field_for_pairs(const char *s, size_t len, char sep, field_pair_fn fn, void *ctx, kelp_diag *d)
{
    size_t pos = 0;
    const char *it;
    size_t il;
    int rc;
    while ((rc = field_next_item(s, len, &pos, sep, &it, &il)) == 1) {
        for (;;) {
            size_t eq = find_eq(it, il);
            if (eq >= il) {
                return kelp_fail(d, KELP_ERR_PARSE, "item without '='");
            }
            const char *k = it, *v = it + eq + 1;
            size_t kl = eq, vl = il - eq - 1;
            trim(&k, &kl);
            trim(&v, &vl);
            if (kl == 0) {
                return kelp_fail(d, KELP_ERR_PARSE, "empty key");
            }
            /* "type=waypoint source=transit": the value holds another pair after a space */
            size_t eq2 = find_eq(v, vl);
            size_t rest = vl;
            if (eq2 < vl) {
                size_t sp = eq2;
                while (sp > 0 && !is_ws(v[sp - 1])) sp--;
                if (sp > 0) rest = sp - 1;
            }
            size_t cur = rest;
            const char *cv = v;
            trim(&cv, &cur);
            if (cur >= 2 && cv[0] == '"' && cv[cur - 1] == '"') cv++, cur -= 2;
            rc = fn(ctx, k, kl, cv, cur);
            if (rc < 0) return rc;
            if (rest >= vl) break;
            it = v + rest + 1;
            il = vl - rest - 1;
            trim(&it, &il);
            if (il == 0) break;
        }
    }
    return rc < 0 ? kelp_fail(d, KELP_ERR_PARSE, "unbalanced brace or quote") : KELP_OK;
}

int field_copy_text(char *dst, size_t cap, const char *v, size_t vl)
{
    if (vl + 1 > cap) return KELP_ERR_RANGE;
    memcpy(dst, v, vl);
    dst[vl] = 0;
    return KELP_OK;
}

#define SIM_MAX_ABS_NUMBER 1e12

int sim_number(const char *v, size_t vl, double *out)
{
    double d;
    if (kelp_util_parse_double(v, vl, &d) < 0 || !isfinite(d)) return KELP_ERR_PARSE;
    /* no position, speed, heading or time of a vehicle is this large; beyond it a value
     * would not survive format -> parse exactly */
    if (d > SIM_MAX_ABS_NUMBER || d < -SIM_MAX_ABS_NUMBER) return KELP_ERR_PARSE;
    *out = d;
    return KELP_OK;
}

int field_put_str(char *buf, size_t cap, size_t *n, const char *s)
{
    size_t l = strlen(s);
    if (*n + l + 1 > cap) return KELP_ERR_NOSPACE;
    memcpy(buf + *n, s, l + 1);
    *n += l;
    return KELP_OK;
}

int field_put_fixed(char *buf, size_t cap, size_t *n, double v, int dec, bool strip)
{
    if (!isfinite(v)) return KELP_ERR_ARG;
    int len = kelp_util_fmt_fixed(buf + *n, cap > *n ? cap - *n : 0, v, dec < 0 ? 0u : (unsigned)dec, strip);
    if (len < 0) return len;
    if (*n + (size_t)len + 1 > cap) {
        if (cap > *n) buf[*n] = '\0';
        return KELP_ERR_NOSPACE;
    }
    *n += (size_t)len;
    return KELP_OK;
}

void field_putf(char *buf, size_t cap, size_t *n, const char *fmt, ...)
{
    if (!cap || *n + 1 >= cap) return;
    va_list ap;
    va_start(ap, fmt);
    int k = kelp_util_vsnprintf(buf + *n, cap - *n, fmt, ap);
    va_end(ap);
    if (k < 0) return;
    *n += (size_t)k;
    if (*n >= cap) *n = cap - 1;
}
