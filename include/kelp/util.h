/* kelp util: the small text, number and time helpers every module shares (core: no
 * allocation, no locale, no I/O). key=value walking is in include/kelp/kv.h. */
#ifndef KELP_UTIL_H
#define KELP_UTIL_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- text ---- */

/** C-locale white space: ' ', '\t', '\r', '\n', '\f', '\v'. */
bool kelp_util_is_space(char c);
/** Narrow [*s, *s + *n) to drop leading and trailing white space (kelp_util_is_space). */
void kelp_util_trim(const char **s, size_t *n);

/* ---- numbers: one parser and one formatter for every module ---- */

/** Strict number parsing (the whole string, surrounding white space allowed, no trailing junk;
 *  "inf", "infinity", "nan" in any case). Correctly rounded for up to 19 significant digits
 *  and powers of ten to 22; no strtod (newlib's allocates), no locale. */
KELP_MUST_CHECK int kelp_util_parse_double(const char *s, size_t len, double *out);
/** The same, refusing inf, nan and overflow (KELP_ERR_PARSE). */
KELP_MUST_CHECK int kelp_util_parse_finite(const char *s, size_t len, double *out);
KELP_MUST_CHECK int kelp_util_parse_long(const char *s, size_t len, long *out);
/** true/yes/1 or false/no/0, any case, surrounding white space allowed. */
KELP_MUST_CHECK int kelp_util_parse_bool(const char *s, size_t len, bool *out);
/** The same for long long (64-bit on every target, so uint32 values fit on 32-bit ARM). */
KELP_MUST_CHECK int kelp_util_parse_llong(const char *s, size_t len, long long *out);

/** v with dec decimals (0..9), rounded as printf's %.*f rounds (on the double's exact value,
 *  so 0.35 gives 0.3 and 2.675 gives 2.67; an exact half goes to the even digit: 2.5 gives 2,
 *  0.125 gives 0.12), as MOOS-IvP's and Goby's sprintf/ostream formatting does; never "-0"; strip drops trailing
 *  zeros of the fraction (and a bare '.'). Non-finite values print as nan, inf, -inf. Writes
 *  at most cap-1 characters and a NUL; returns the length the whole text needs (as snprintf),
 *  or KELP_ERR_RANGE when |v| x 10^dec reaches 9e18 (nothing written). */
KELP_MUST_CHECK int kelp_util_fmt_fixed(char *buf, size_t cap, double v, unsigned dec, bool strip);

/** snprintf for the core: the C library's on a hosted system; on newlib (firmware) kelp's own
 *  (newlib's links malloc, and its nano variant prints no floating point). Flags - 0 + space #,
 *  width and precision (also *), lengths hh h l ll z j t, conversions d i u x X o c s p % f F e
 *  E g G. Same return as snprintf. */
int kelp_util_snprintf(char *buf, size_t cap, const char *fmt, ...) KELP_PRINTF(3, 4);
int kelp_util_vsnprintf(char *buf, size_t cap, const char *fmt, va_list ap) KELP_PRINTF(3, 0);
/** kelp's own formatter, on every target (kelp_util_vsnprintf on newlib; tested on the host). */
int kelp_util_vsnprintf_own(char *buf, size_t cap, const char *fmt, va_list ap) KELP_PRINTF(3, 0);

/* ---- text ---- */

/** Case-insensitive, length-bounded equality: s[0..len) == z. */
bool kelp_util_strieq_n(const char *s, size_t len, const char *z);
/** Case-insensitive equality of two NUL-terminated strings (ASCII). */
bool kelp_util_strieq(const char *a, const char *b);
/** s[0..n) as a JSON string literal, quotes included: '"' and '\\' escaped, control bytes,
 *  DEL and bytes >= 0x80 as \u00XX (bus strings are not promised to be UTF-8, so the output is
 *  plain ASCII; a NUL inside s is kept as \u0000). Writes at most cap-1 characters and a NUL;
 *  returns the length the whole literal needs (as snprintf). */
size_t kelp_util_json_quote(char *buf, size_t cap, const char *s, size_t n);

/* ---- integers and civil time (proleptic Gregorian, UTC) ---- */

/** a / b rounded toward negative infinity (b > 0). */
int64_t kelp_util_floor_div(int64_t a, int64_t b);
/** Days since 1970-01-01 of year-month-day (month 1..12, day 1..31). */
int64_t kelp_util_days_from_civil(int64_t year, unsigned month, unsigned day);
/** The date of a day number (days since 1970-01-01). */
void kelp_util_civil_from_days(int64_t days, int64_t *year, unsigned *month, unsigned *day);

/* ---- the time-step rule (docs/ARCHITECTURE.md, "When the clock steps") ---- */

/** |now| at or beyond this many seconds is not a time (year 5138): whole microseconds of any
 *  accepted time fit an int64 many times over. */
#define KELP_TIME_LIMIT 1e11
/** A `now` a core entry point accepts: finite and within KELP_TIME_LIMIT (NaN fails every
 *  comparison, so it is refused too). */
static inline bool kelp_util_time_ok(double t)
{
    return t > -KELP_TIME_LIMIT && t < KELP_TIME_LIMIT;
}

/** The newest `now` a state machine has seen, to tell a backward step (zeroed: none seen). */
typedef struct kelp_clock {
    double last;
    bool seen;
} kelp_clock;

/** Record `now` (a kelp_util_time_ok one).  @return how far the clock went back from the newest
 *  time seen (> 0: a backward step; the caller moves its stored times back by as much, so
 *  what remains of each wait is kept), else 0. */
double kelp_util_clock_back(kelp_clock *c, double now);

/** Record `now` (a kelp_util_time_ok one).  @return the clock step, signed: now minus the previous
 *  `now` when it is negative (a backward step) or beyond max_fwd (a forward step an integrator
 *  or controller must not take as elapsed time), else 0. */
double kelp_util_clock_step(kelp_clock *c, double now, double max_fwd);

/* ---- big-endian integers in byte buffers (wire headers) ---- */

void kelp_util_be_put32(uint8_t *p, uint32_t v);
void kelp_util_be_put64(uint8_t *p, uint64_t v);
uint32_t kelp_util_be_get32(const uint8_t *p);
uint64_t kelp_util_be_get64(const uint8_t *p);

/* ---- hashing ---- */

/** FNV-1a over n bytes (table lookups by name; not for anything adversarial). */
uint32_t kelp_util_hash(const char *s, size_t n);

/* ---- hexadecimal ---- */

/** The value of a hex digit (either case), or -1. */
int kelp_util_hex_digit(char c);
/** Decode exactly n hex characters (n even) into out. @return 0, KELP_ERR_PARSE (odd length
 *  or a non-hex character), KELP_ERR_NOSPACE (more than cap bytes). */
KELP_MUST_CHECK int kelp_util_hex_decode(const char *hex, size_t n, uint8_t *out, size_t cap, size_t *len);

#ifdef __cplusplus
}
#endif

#endif
