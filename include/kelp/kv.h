/* kelp key=value lists: the MOOS "a=1,b=2" string convention. Allocation-free. */
#ifndef KELP_KV_H
#define KELP_KV_H
#include <stddef.h>
#include <stdbool.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Find `key` (case-insensitive, trimmed) in a list of pairs separated by `sep` (usually
 *  ',') and copy its trimmed value into out. Later duplicates do not override the first.
 *  @return 1 found, 0 absent, KELP_ERR_NOSPACE if the value does not fit. */
KELP_MUST_CHECK int kelp_kv_get(const char *s, char sep, const char *key, char *out, size_t cap);

/** Iterate pairs: *pos starts at 0. Writes pointers/lengths into the string (trimmed).
 *  @return 1 while a pair is produced, 0 at the end, KELP_ERR_PARSE on a pair without '='. */
KELP_MUST_CHECK int kelp_kv_next(const char *s, char sep, size_t *pos, const char **key, size_t *klen, const char **val,
                                 size_t *vlen);
/** kelp_kv_next over the first n bytes of s (a text that need not end in NUL). */
KELP_MUST_CHECK int kelp_kv_next_n(const char *s, size_t n, char sep, size_t *pos, const char **key, size_t *klen,
                                   const char **val, size_t *vlen);
#ifdef __cplusplus
}
#endif

#endif
