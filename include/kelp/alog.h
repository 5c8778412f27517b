/* kelp MOOS .alog text (core): one line of pLogger's asynchronous log, parsed and written
 * without allocation, so kelp's LCM logs convert to what MOOS users' alog tools read.
 *
 * A file starts with a banner of lines beginning with '%':
 *   %%%%...%%%%
 *   %% LOG FILE:       <name>
 *   %% FILE OPENED ON  <ctime(3) date>
 *   %% LOGSTART        <MOOS time of the logger's start, %.16g, right-aligned in 20>
 *   %%%%...%%%%
 * then one line per posting, columns left-aligned and separated by white space:
 *   <time since LOGSTART, 5 decimals, width 15> <VARIABLE, width 20> <SOURCE, width 15> <VALUE>
 * A double value is written with a fixed number of decimals (5 by default) in a field of 12,
 * a string as it is; pLogger ends every line with one space after the value. With
 * "%% DATATYPE MARKING ON" in the banner, values start with "D:" or "S:".
 * The source may carry ":aux" and "@community" (pLogger's LogAuxSrc and
 * MarkExternalCommunityMessages). */
#ifndef KELP_ALOG_H
#define KELP_ALOG_H
#include <stdbool.h>
#include <stddef.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_ALOG_BANNER "%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%"
#define KELP_ALOG_DEFAULT_DP 5

/** One data line's fields, pointing into the line (not NUL-terminated). */
typedef struct kelp_alog_line {
    double time;                 /**< seconds since LOGSTART */
    const char *var, *src, *val;
    size_t var_len, src_len, val_len;
} kelp_alog_line;

/** Split a line (without its newline). @return 1 a data line, 0 a banner/comment/blank line,
 *  KELP_ERR_PARSE when the time is not a number or a column is missing. The value keeps
 *  inner white space; one trailing space (pLogger's) and a '\r' are dropped. */
KELP_MUST_CHECK int kelp_alog_parse_line(const char *line, size_t len, kelp_alog_line *out);

/** A banner line "%% LOGSTART <t>": @return 1 with *t, 0 not that line, KELP_ERR_PARSE bad number. */
KELP_MUST_CHECK int kelp_alog_parse_logstart(const char *line, size_t len, double *t);
/** True for the banner line "%% DATATYPE MARKING ON". */
bool kelp_alog_is_marking(const char *line, size_t len);

/** The kind of a value: with marking, "D:" is a double and "S:" a string (the prefix is
 *  removed); without, a value that is a finite number is a double.
 *  @return 1 double (*d), 0 string (*s, *slen), KELP_ERR_PARSE ("D:" and no number). */
KELP_MUST_CHECK int kelp_alog_value(const char *val, size_t len, bool marking, double *d, const char **s, size_t *slen);

/** Write one data line and its newline as pLogger does. dp < 0 writes doubles (and the time)
 *  with 17 significant digits, so they read back exactly; marking adds "D:"/"S:".
 *  @return the length written (without NUL), KELP_ERR_NOSPACE, KELP_ERR_ARG (a string
 *  holding a newline, a non-finite time, an empty name). */
KELP_MUST_CHECK int kelp_alog_format_line(char *buf, size_t cap, double time, const char *var, const char *src,
                                          bool is_string, const char *sval, double dval, int dp, bool marking);

#ifdef __cplusplus
}
#endif

#endif
