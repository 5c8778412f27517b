/* MOOS .alog lines (include/kelp/alog.h). */
#include <math.h>
#include <string.h>
#include <kelp/alog.h>
#include <kelp/util.h>

#define ALOG_TIME_WIDTH 15
#define ALOG_VAR_WIDTH 20
#define ALOG_SRC_WIDTH 15
#define ALOG_DOUBLE_WIDTH 12

static bool ws(char c) { return c == ' ' || c == '\t'; }

/* next white-space separated word of s[*i..len) */
static bool word(const char *s, size_t len, size_t *i, const char **w, size_t *wl)
{
    while (*i < len && ws(s[*i])) (*i)++;
    size_t b = *i;
    while (*i < len && !ws(s[*i])) (*i)++;
    *w = s + b;
    *wl = *i - b;
    return *wl > 0;
}

int kelp_alog_parse_line(const char *line, size_t len, kelp_alog_line *out)
{
    while (len && (line[len - 1] == '\r' || line[len - 1] == '\n')) len--;
    size_t i = 0;
    while (i < len && ws(line[i])) i++;
    if (i == len || line[i] == '%') return 0;
    const char *t;
    size_t tl;
    (void)word(line, len, &i, &t, &tl);
    if (kelp_util_parse_finite(t, tl, &out->time) < 0) return KELP_ERR_PARSE;
    if (!word(line, len, &i, &out->var, &out->var_len) || !word(line, len, &i, &out->src, &out->src_len))
        return KELP_ERR_PARSE;
    while (i < len && ws(line[i])) i++;
    out->val = line + i;
    out->val_len = len - i;
    if (out->val_len && out->val[out->val_len - 1] == ' ') out->val_len--;
    return 1;
}

/* "%%" then optional white space then the word */
static bool banner_key(const char *line, size_t len, const char *key, size_t *after)
{
    size_t i = 0;
    while (i < len && line[i] == '%') i++;
    if (i == 0) return false;
    while (i < len && ws(line[i])) i++;
    size_t kl = strlen(key);
    if (len - i < kl || !kelp_util_strieq_n(line + i, kl, key)) return false;
    *after = i + kl;
    return true;
}

int kelp_alog_parse_logstart(const char *line, size_t len, double *t)
{
    size_t a;
    while (len && (line[len - 1] == '\r' || line[len - 1] == '\n' || ws(line[len - 1]))) len--;
    if (!banner_key(line, len, "LOGSTART", &a)) return 0;
    return kelp_util_parse_finite(line + a, len - a, t) < 0 ? KELP_ERR_PARSE : 1;
}

bool kelp_alog_is_marking(const char *line, size_t len)
{
    size_t a;
    return banner_key(line, len, "DATATYPE MARKING ON", &a);
}

int kelp_alog_value(const char *val, size_t len, bool marking, double *d, const char **s, size_t *slen)
{
    if (marking && len >= 2 && (val[0] == 'D' || val[0] == 'S') && val[1] == ':') {
        if (val[0] == 'D') return kelp_util_parse_finite(val + 2, len - 2, d) < 0 ? KELP_ERR_PARSE : 1;
        *s = val + 2;
        *slen = len - 2;
        return 0;
    }
    if (len && kelp_util_parse_finite(val, len, d) == 0) return 1;
    *s = val;
    *slen = len;
    return 0;
}

typedef struct out {
    char *b;
    size_t cap, n;
    bool full;
} out;

static void put(out *o, const char *s, size_t l)
{
    if (o->n + l + 1 > o->cap) {
        o->full = true;
        return;
    }
    memcpy(o->b + o->n, s, l);
    o->n += l;
    o->b[o->n] = 0;
}

static void pad(out *o, size_t from, size_t width)
{
    while (o->n - from < width && !o->full) put(o, " ", 1);
}

static void num(out *o, double v, int dp)
{
    char t[64];
    int k = dp < 0 ? -1 : kelp_util_fmt_fixed(t, sizeof t, v, (unsigned)dp, false);
    if (k < 0) k = kelp_util_snprintf(t, sizeof t, "%.17g", v); /* exact, or too large for fixed decimals */
    if (k < 0 || (size_t)k >= sizeof t) o->full = true;
    else put(o, t, (size_t)k);
}

int kelp_alog_format_line(char *buf, size_t cap, double time, const char *var, const char *src, bool is_string,
                          const char *sval, double dval, int dp, bool marking)
{
    if (!isfinite(time) || !var || !*var || !src || !*src || strpbrk(var, " \t\r\n") || strpbrk(src, " \t\r\n") ||
        (is_string && (!sval || strpbrk(sval, "\r\n"))) || dp > 9)
        return KELP_ERR_ARG;
    if (!cap) return KELP_ERR_NOSPACE;
    out o = { buf, cap, 0, false };
    buf[0] = 0;
    num(&o, time, dp < 0 ? -1 : KELP_ALOG_DEFAULT_DP);
    pad(&o, 0, ALOG_TIME_WIDTH);
    put(&o, " ", 1);
    size_t at = o.n;
    put(&o, var, strlen(var));
    pad(&o, at, ALOG_VAR_WIDTH);
    put(&o, " ", 1);
    at = o.n;
    put(&o, src, strlen(src));
    pad(&o, at, ALOG_SRC_WIDTH);
    put(&o, " ", 1);
    if (marking) put(&o, is_string ? "S:" : "D:", 2);
    if (is_string) {
        put(&o, sval, strlen(sval));
    } else {
        at = o.n;
        num(&o, dval, dp);
        pad(&o, at, ALOG_DOUBLE_WIDTH);
    }
    put(&o, " \n", 2);
    if (o.full) return KELP_ERR_NOSPACE;
    return (int)o.n;
}
