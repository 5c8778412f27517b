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
/* Record "what 'token'" in err if it holds no error yet (first error wins); returns code. */
int ivp_fail(kelp_ivp_errbuf *err, int code, const char *what, const char *tok, size_t toklen);

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
