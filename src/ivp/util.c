/* kelp IvP: string and number helpers. Own number parser: strtod in newlib allocates, and the
 * core must link into firmware without the heap. */
#include <string.h>
#include <math.h>
#include <kelp/util.h>
#include "ivp_int.h"

void ivp_strncat(char *dst, size_t cap, const char *src, size_t n)
{
    if (!dst || cap == 0)
        return;
    size_t len = strlen(dst);
    while (n > 0 && *src && len + 1 < cap) {
        dst[len++] = *src++;
        n--;
    }
    dst[len] = '\0';
}

void ivp_strcat(char *dst, size_t cap, const char *src)
{
    ivp_strncat(dst, cap, src, (size_t)-1);
}

void ivp_warn(char *warn, const char *text)
{
    if (warn[0])
        ivp_strcat(warn, KELP_IVP_MAX_WARN, " # ");
    ivp_strcat(warn, KELP_IVP_MAX_WARN, text);
}

int ivp_fail_(kelp_diag *d, int code, const char *what, const char *tok, size_t toklen)
{
    if (!d || d->code != KELP_OK)
        return code;
    (void)kelp_diag_set(d, code, what);
#ifndef KELP_NO_ERRMSG
    if (what && tok) {
        ivp_strcat(d->msg, sizeof d->msg, " '");
        ivp_strncat(d->msg, sizeof d->msg, tok, toklen > 60 ? 60 : toklen);
        ivp_strcat(d->msg, sizeof d->msg, "'");
    }
#else
    (void)tok;
    (void)toklen;
#endif
    return code;
}

const char *ivp_skip_ws(const char *s)
{
    while (*s == ' ' || *s == '\t' || *s == '\r')
        s++;
    return s;
}

void ivp_trim(const char **s, size_t *n)
{
    while (*n > 0 && (**s == ' ' || **s == '\t' || **s == '\r' || **s == '\n')) {
        (*s)++;
        (*n)--;
    }
    while (*n > 0 && ((*s)[*n - 1] == ' ' || (*s)[*n - 1] == '\t' || (*s)[*n - 1] == '\r' || (*s)[*n - 1] == '\n'))
        (*n)--;
}

int ivp_word_eq(const char *s, size_t n, const char *word)
{
    return kelp_util_strieq_n(s, n, word);
}

/* A finite number filling the whole span (no white space): the util parser */
int ivp_parse_double(const char *s, size_t n, double *out)
{
    if (n == 0 || s[0] == ' ' || s[0] == '\t' || s[n - 1] == ' ' || s[n - 1] == '\t')
        return KELP_ERR_PARSE;
    return kelp_util_parse_finite(s, n, out);
}

int ivp_parse_long(const char *s, size_t n, long *out)
{
    size_t i = 0;
    int neg = 0;
    long v = 0;
    if (n == 0)
        return KELP_ERR_PARSE;
    if (s[i] == '+' || s[i] == '-') {
        neg = s[i] == '-';
        i++;
    }
    if (i >= n)
        return KELP_ERR_PARSE;
    for (; i < n; i++) {
        if (s[i] < '0' || s[i] > '9')
            return KELP_ERR_PARSE;
        if (v > 100000000L)
            return KELP_ERR_RANGE;
        v = v * 10 + (s[i] - '0');
    }
    *out = neg ? -v : v;
    return 0;
}
