/* Private helpers shared by the node report and VIEW_* code (not installed). */
#ifndef KELP_FIELD_INT_H
#define KELP_FIELD_INT_H
#include <stdbool.h>
#include <stddef.h>
#include <kelp/err.h>

/** Called per key=value pair (trimmed, outer double quotes of the value removed).
 *  Return 0 to go on or <0 to stop with that status. */
typedef int (*field_pair_fn)(void *ctx, const char *k, size_t kl, const char *v, size_t vl);

/** Walk the pairs of s[0..len): items are split at `sep` outside braces and quotes, each at
 *  its first '='; a value that holds " key=value" is split at that space (the seed's
 *  "type=waypoint source=transit"). Empty items are skipped.
 *  @return 0, the callback's status, or KELP_ERR_PARSE (unbalanced brace/quote, item
 *  without '=', empty key) with the reason in d (a callback records its own). */
int field_for_pairs(const char *s, size_t len, char sep, field_pair_fn fn, void *ctx, kelp_diag *d);

/** Next item of s[0..len) split at `sep` outside braces/quotes: 1 with a trimmed item, 0 at
 *  the end, KELP_ERR_PARSE when a brace or quote is unbalanced. */
int field_next_item(const char *s, size_t len, size_t *pos, char sep, const char **item, size_t *ilen);

/** Copy a value into a text field; KELP_ERR_RANGE when it does not fit. */
int field_copy_text(char *dst, size_t cap, const char *v, size_t vl);

/** Append v with `dec` decimals (strip: drop trailing zeros and a bare '.').
 *  @return 0, KELP_ERR_NOSPACE, KELP_ERR_RANGE (|v| too large), KELP_ERR_ARG (not finite). */
int field_put_fixed(char *buf, size_t cap, size_t *n, double v, int dec, bool strip);
/** Append a C string. */
int field_put_str(char *buf, size_t cap, size_t *n, const char *s);

/** Append printf-style text; output that does not fit is cut (buf stays NUL-terminated). */
void field_putf(char *buf, size_t cap, size_t *n, const char *fmt, ...) KELP_PRINTF(4, 5);

/** Strict finite number. */
int sim_number(const char *v, size_t vl, double *out);


/* ---- the brokers (src/field/broker.c) ---- */
struct kelp_field_sink;
struct kelp_field_broker_bridge;
struct kelp_field_broker_host;
/** A port 1..65535. */
int broker_port(const char *v, size_t vl, unsigned *out);
/** true/false/yes/no, optionally followed by 24.8's "(default)"; false when neither. */
bool broker_bool(const char *v, bool *out);
/** Append src->alias unless listed already. @return 1, or <0 (reason in d). */
int broker_add_bridge(struct kelp_field_broker_bridge *list, unsigned *n, const char *src, const char *alias,
                      kelp_diag *d);
/** Post PMB_REGISTER "src_var=..,dest_community=..,dest_host=..,dest_port=..,dest_alias=.."
 *  (dest_community left out when NULL); a copy goes to last. @return 1 or <0. */
int broker_register(const struct kelp_field_sink *out, const char *src, const char *community, const char *host,
                    unsigned port, const char *alias, char *last, size_t cap);
/** "community=..,host=..[,port=..],port_udp=..[,keyword=..],time_warp=..,time=..[,status=..]" */
int broker_host_format(const struct kelp_field_broker_host *h, const char *keyword, double warp, double now,
                       const char *status, char *buf, size_t cap);
/** snprintf at buf + *n (a report); *full when it ran out of room. */
void broker_put(char *buf, size_t cap, size_t *n, bool *full, const char *fmt, ...) KELP_PRINTF(5, 6);
/** 24.8's isValidIPAddress: "localhost" (any case) or a dotted quad of numbers 0..255. */
bool field_ip_ok(const char *s, size_t n);
/** Post PSHARE_CMD "cmd=output,src_name=S,dest_name=D,route=R" (built in last). @return 1 or <0. */
int broker_pshare_cmd(const struct kelp_field_sink *out, const char *src, const char *dest, const char *route,
                      char *last, size_t cap);
/** 24.8's ACBlock(label, msg, maxlen, sep) appended to a report. */
void broker_block(char *buf, size_t cap, size_t *n, bool *full, const char *label, const char *msg, size_t maxlen,
                  char sep);
/** A table cell: the text of (row, col), made in tmp when it has to be. */
typedef const char *(*broker_cell_fn)(const void *ctx, unsigned row, unsigned col, char *tmp, size_t cap);
/** 24.8's ACTable (two blanks apart, dashes after header_rows rows) appended to a report. */
void broker_table(char *buf, size_t cap, size_t *n, bool *full, unsigned ncols, unsigned nrows, unsigned header_rows,
                  broker_cell_fn cell, const void *ctx);
/** The same table with `sep` blanks between columns and the columns whose bit is set in
 *  `right` right-justified (ACTable's setColumnJustify); at most FIELD_ACTABLE_MAX_COLS
 *  columns, cells of at most 63 bytes. */
#define FIELD_ACTABLE_MAX_COLS 17 /* uFldScope: VName and 16 scope columns */
void field_actable(char *buf, size_t cap, size_t *n, bool *full, unsigned ncols, unsigned nrows, unsigned header_rows,
                   unsigned sep, unsigned right, broker_cell_fn cell, const void *ctx);
/** Same community, host, ports and warp. */
bool broker_same_host(const struct kelp_field_broker_host *a, const struct kelp_field_broker_host *b);

#endif
