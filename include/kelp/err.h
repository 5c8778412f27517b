/* kelp: status codes shared by every module.
 *
 * Every status-returning function returns 0 (KELP_OK) or one negative kelp_err.
 * kelp_err_str() turns a code into constant text; it never allocates.
 */
#ifndef KELP_ERR_H
#define KELP_ERR_H

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__) || defined(__clang__)
#define KELP_MUST_CHECK __attribute__((warn_unused_result))
#define KELP_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define KELP_MUST_CHECK
#define KELP_PRINTF(f, a)
#endif

/** Discard a status on purpose, where failing changes nothing for the caller (GCC's
 *  warn_unused_result is not silenced by a plain (void) cast; this is). */
#define KELP_IGNORE(expr) ((void)!(expr))

typedef enum kelp_err {
    KELP_OK = 0,
    KELP_ERR_ARG = -1,          /**< invalid argument */
    KELP_ERR_NOSPACE = -2,      /**< caller storage too small */
    KELP_ERR_PARSE = -3,        /**< malformed input text */
    KELP_ERR_RANGE = -4,        /**< value out of range */
    KELP_ERR_NOTFOUND = -5,     /**< no such name / entry */
    KELP_ERR_PARTIAL = -6,      /**< more input needed */
    KELP_ERR_CHECKSUM = -7,     /**< checksum / MAC mismatch */
    KELP_ERR_DEFMISMATCH = -8,  /**< definition fingerprint mismatch */
    KELP_ERR_IO = -9,           /**< I/O failure (edge only) */
    KELP_ERR_TIMEOUT = -10,     /**< timed out */
    KELP_ERR_STATE = -11,       /**< call not valid in this state */
    KELP_ERR_UNSUPPORTED = -12, /**< feature not supported */
    KELP_ERR_TRUNCATED = -13,   /**< input ended early */
    KELP_ERR_EXISTS = -14,      /**< already present */
    KELP_ERR_CRYPTO = -15,      /**< crypto backend failure */
    KELP_ERR_AUTH = -16,        /**< authentication failed */
    KELP_ERR_EMPTY = -17,       /**< nothing to return */
    KELP_ERR_INFEASIBLE = -18,  /**< problem has no solution */
    KELP_ERR_REPLAY = -19,      /**< replayed, duplicated or stale message */
    KELP_ERR_DENIED = -20       /**< refused by configuration (not on an allow-list) */
} kelp_err;

/** Constant text for a status code; unknown codes give "unknown error". */
const char *kelp_err_str(int code);

#ifdef __cplusplus
}
#endif

/* the diagnostics record (kelp_diag, kelp_fail): the other half of the error path */
#include <kelp/diag.h>

#endif
