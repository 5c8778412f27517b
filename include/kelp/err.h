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

/* ---- diagnostics: the one error path of every parser and configuration call ----
 *
 * A status code says what failed; a kelp_diag says where and why. Functions that can explain
 * a failure take a `kelp_diag *d` (NULL allowed: nothing is recorded) and fill it first-error-
 * wins: the innermost failure is kept, and an outer layer that knows the input line adds it with
 * kelp_diag_where() without replacing the reason. kelp_diag_clear() starts a new attempt.
 *
 * Built with -DKELP_NO_ERRMSG the message text is compiled out (the struct shrinks to three
 * ints and no message string is linked into the image); the code, line and column remain, and
 * kelp_diag_text() answers kelp_err_str(code). A program and the kelp library it links must
 * agree on KELP_NO_ERRMSG, as on the other KELP_* build limits. */
#ifndef KELP_DIAG_MSG_MAX
#define KELP_DIAG_MSG_MAX 160 /**< message bytes, terminator included */
#endif

typedef struct kelp_diag {
    int code; /**< first failure's kelp_err; KELP_OK while nothing failed */
    int line; /**< 1-based line of the input that failed; 0 when not known or not line input */
    int col;  /**< 1-based column (byte) within that line; 0 when not known */
#ifndef KELP_NO_ERRMSG
    char msg[KELP_DIAG_MSG_MAX]; /**< why, in words; "" when only the code is known */
#endif
} kelp_diag;

/** Empty the record (code KELP_OK, no place, no message). d may be NULL. */
void kelp_diag_clear(kelp_diag *d);

/** Record a failure unless one is already recorded; returns code (so `return kelp_fail(...)`).
 *  msg may be NULL. With KELP_NO_ERRMSG use the macros below so the text is not linked in. */
int kelp_diag_set(kelp_diag *d, int code, const char *msg);

/** As kelp_diag_set with a kelp_util_snprintf format (truncated to KELP_DIAG_MSG_MAX - 1 bytes). */
int kelp_diag_setf(kelp_diag *d, int code, const char *fmt, ...) KELP_PRINTF(3, 4);

/** Add the place of a recorded failure: line and col are set only where still 0, so the
 *  innermost layer that knows them wins. Does nothing when no failure is recorded. Returns
 *  the recorded code (KELP_OK when none). */
int kelp_diag_where(kelp_diag *d, int line, int col);

/** The message, or kelp_err_str(code) when there is none (or when compiled out); "" for a
 *  cleared record. Never NULL; d may be NULL (gives ""). */
const char *kelp_diag_text(const kelp_diag *d);

/** Fail with a code and a constant reason: `return kelp_fail(d, KELP_ERR_PARSE, "no '='");`
 *  kelp_failf() takes a format. With KELP_NO_ERRMSG both record the code only. */
/* (the macros yield `code` itself, so a static analyser sees the value returned; without
 * messages the arguments still appear in a branch that is never taken and folds away, so a
 * variable used only in a message is not "unused", and no message text reaches the image) */
#ifdef KELP_NO_ERRMSG
#define kelp_fail(d, code, msg) ((void)(0 ? (msg) : (const char *)0), kelp_diag_set((d), (code), (const char *)0), (code))
#define kelp_failf(d, code, ...) \
    ((void)(0 ? kelp_diag_setf((d), (code), __VA_ARGS__) : 0), kelp_diag_set((d), (code), (const char *)0), (code))
#else
#define kelp_fail(d, code, msg) (kelp_diag_set((d), (code), (msg)), (code))
#define kelp_failf(d, code, ...) (kelp_diag_setf((d), (code), __VA_ARGS__), (code))
#endif

#ifdef __cplusplus
}
#endif

#endif
