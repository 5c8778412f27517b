/* kelp util: the small text, number and time helpers every module shares (core: no
 * allocation, no locale, no I/O). Number parsing and key=value walking are declared in
 * include/kelp/mission.h and include/kelp/kv.h. */
#ifndef KELP_UTIL_H
#define KELP_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- integers and civil time (proleptic Gregorian, UTC) ---- */

/** a / b rounded toward negative infinity (b > 0). */
int64_t kelp_floor_div(int64_t a, int64_t b);
/** Days since 1970-01-01 of year-month-day (month 1..12, day 1..31). */
int64_t kelp_days_from_civil(int64_t year, unsigned month, unsigned day);
/** The date of a day number (days since 1970-01-01). */
void kelp_civil_from_days(int64_t days, int64_t *year, unsigned *month, unsigned *day);

/* ---- hexadecimal ---- */

/** The value of a hex digit (either case), or -1. */
int kelp_hex_digit(char c);
/** Decode exactly n hex characters (n even) into out. @return 0, KELP_ERR_PARSE (odd length
 *  or a non-hex character), KELP_ERR_NOSPACE (more than cap bytes). */
KELP_MUST_CHECK int kelp_hex_decode(const char *hex, size_t n, uint8_t *out, size_t cap, size_t *len);

#ifdef __cplusplus
}
#endif

#endif
