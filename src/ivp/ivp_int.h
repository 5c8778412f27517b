/* kelp IvP: private helpers shared by the src/ivp sources (never installed). */
#ifndef KELP_IVP_INT_H
#define KELP_IVP_INT_H

#include <stddef.h>
#include <stdint.h>
#include <kelp/ivp.h>

/* Bounded string append into dst[cap] (always NUL terminated). */
void ivp_strcat(char *dst, size_t cap, const char *src);
/* Append src limited to n bytes. */
void ivp_strncat(char *dst, size_t cap, const char *src, size_t n);
/* Append a warning to a builder's warn[] joined with " # ". */
void ivp_warn(char *warn, const char *text);
/* Record code with the message "what 'token'" (token cut to 60 bytes; no quotes when tok is
 * NULL) in d unless it holds a failure already (first error wins); returns code. With
 * KELP_NO_ERRMSG the texts are not linked in (the macro drops `what`). */
int ivp_fail_(kelp_diag *d, int code, const char *what, const char *tok, size_t toklen);
#ifdef KELP_NO_ERRMSG
#define ivp_fail(d, code, what, tok, toklen) ((void)(what), ivp_fail_((d), (code), (const char *)0, (tok), (toklen)))
#else
#define ivp_fail(d, code, what, tok, toklen) ivp_fail_((d), (code), (what), (tok), (toklen))
#endif

/* Drop a status on purpose: a ZAIC / Reflector setter's fatal error stays in the builder's ok
 * flag and warn[], which the caller reads after the setters. */
static inline void ivp_ignore(int rc)
{
    (void)rc;
}

/* Parse a decimal number occupying exactly s[0..n). Finite values only. 0 or KELP_ERR_PARSE. */
int ivp_parse_double(const char *s, size_t n, double *out);
/* Parse a non-negative or negative decimal integer occupying exactly s[0..n). */
int ivp_parse_long(const char *s, size_t n, long *out);
/* Skip blanks (space, tab, CR). */
const char *ivp_skip_ws(const char *s);
/* Trim blanks from both ends of [*s, *s+*n). */
void ivp_trim(const char **s, size_t *n);
/* Case-insensitive compare of [s,n) against a NUL terminated lower-case word. */
int ivp_word_eq(const char *s, size_t n, const char *word);

#endif
