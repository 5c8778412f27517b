/* kelp var: one MOOS variable write (kelp_var: name, kind, value, source, source-aux,
 * community, time) and its LCM kelp.var_t wire format. kelp/bus.h includes this header. */
#ifndef KELP_VAR_H
#define KELP_VAR_H

#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum kelp_var_kind {
    KELP_VAR_DOUBLE = 0,
    KELP_VAR_STRING = 1,
    KELP_VAR_BINARY = 2
} kelp_var_kind;

#define KELP_VAR_FLAG_SYNC 0x01u    /**< replay of a retained value for a late registrant */
#define KELP_VAR_FLAG_BRIDGED 0x02u /**< arrived from another community through a bridge */

/** LCM fingerprint of kelp.var_t (lcmtypes/), as lcm-gen computes it;
 *  a unit test checks it against the generated code, so a change to a .lcm file is caught. */
#define KELP_VAR_FINGERPRINT UINT64_C(0x0ba5b50d8930056a)

/** One variable write. Strings are NUL-terminated in sval; slen excludes the NUL. */
typedef struct kelp_var {
    double time;                     /**< MOOS time (s since 1970, times MOOSTimeWarp) */
    char name[KELP_MAX_NAME];
    char source[KELP_MAX_NAME];
    char source_aux[KELP_MAX_NAME];  /**< MOOS source-aux ("" when the writer set none) */
    char community[KELP_MAX_NAME];
    kelp_var_kind kind;
    uint8_t flags;
    double dval;
    size_t slen;
    char sval[KELP_MAX_SVAL + 1];    /**< string, or binary bytes for KELP_VAR_BINARY */
} kelp_var;

/* ------------------------------------------------------------------ wire format */

/** Bytes needed to encode v as an LCM kelp.var_t datagram (with fingerprint). */
size_t kelp_var_encoded_size(const kelp_var *v);

/** Encode v in LCM's kelp.var_t layout. @param[out] len bytes written.
 *  @return 0, KELP_ERR_NOSPACE if cap is too small, KELP_ERR_ARG on a bad var. */
KELP_MUST_CHECK int kelp_var_encode(const kelp_var *v, uint8_t *buf, size_t cap, size_t *len);

/** Decode and validate one datagram. Every length is checked against the datagram before
 *  use; strings must be NUL-terminated where the layout says; names and values that do not
 *  fit kelp_var are rejected, never truncated. Safe on arbitrary bytes.
 *  @return 0, KELP_ERR_DEFMISMATCH (fingerprint), KELP_ERR_TRUNCATED, KELP_ERR_RANGE
 *  (a length beyond kelp's limits), KELP_ERR_PARSE (missing NUL, bad kind). */
KELP_MUST_CHECK int kelp_var_decode(const uint8_t *buf, size_t len, kelp_var *out);

#ifdef __cplusplus
}
#endif

#endif
