/* kelp diag: where and why a parser, a configuration call or an opener failed (the
 * kelp_diag record, kelp_fail / kelp_failf). The codes are in kelp/err.h, which includes
 * this header, so either one gives the whole error path. */
#ifndef KELP_DIAG_H
#define KELP_DIAG_H

#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

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
