/* kelp DCCL: the Goby 1.1 (DCCL v1) message codec, byte-compatible on the wire.
 *
 * Core API: allocation-free, no I/O, no clock. A compiled message definition
 * (kelp_dccl_msgdef, produced by the XML loader in <kelp/edge/dccl.h> or as
 * const tables by kelp-dccl-gen) drives encode, decode, publish and value sourcing.
 *
 * Wire format (Goby 1.1's DCCL):
 *   wire = header[6] || AES-256-CTR(body)
 * header: ccl id 32 (8 bits), DCCL id (9), seconds of UTC day (17), src (5),
 * dest (5), multimessage flag (1), broadcast flag (1), unused (2), MSB first.
 *
 * Values: every header and layout field owns `array_length` consecutive value
 * slots starting at kelp_dccl_field.slot in a caller-owned array of
 * kelp_dccl_val of length kelp_dccl_msgdef.n_slots. An EMPTY slot is "not
 * given" (null code 0 on the wire). Header fields occupy fields[0..7].
 *
 * Thread-safety: all functions are re-entrant; a kelp_dccl_codec must not be
 * shared between threads while a call runs (it holds the diag of the last call and, through the
 * algorithm context, the MOOS geodesy state).
 */
#ifndef KELP_DCCL_H
#define KELP_DCCL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <kelp/config.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ constants */
#define KELP_DCCL_HEAD_BYTES 6u        /**< header length on the wire */
#ifndef KELP_DCCL_CCL_ID
#define KELP_DCCL_CCL_ID 32u          /**< first byte of every DCCL message (also in queue.h) */
#endif
#define KELP_DCCL_N_HEAD 8u            /**< header fields (fields[0..7]) */
#define KELP_DCCL_MAX_DBL_PRECISION 15 /**< Goby MAX_DBL_PRECISION */

/** Header field indices (position in kelp_dccl_msgdef.fields and wire order). */
enum kelp_dccl_head {
    KELP_DCCL_H_CCL_ID = 0,
    KELP_DCCL_H_ID = 1,
    KELP_DCCL_H_TIME = 2,
    KELP_DCCL_H_SRC = 3,
    KELP_DCCL_H_DEST = 4,
    KELP_DCCL_H_MULTIMESSAGE = 5,
    KELP_DCCL_H_BROADCAST = 6,
    KELP_DCCL_H_UNUSED = 7
};

/** Field types. Header fields have their own types. */
typedef enum kelp_dccl_type {
    KELP_DCCL_T_STATIC = 0,
    KELP_DCCL_T_INT,
    KELP_DCCL_T_FLOAT,
    KELP_DCCL_T_BOOL,
    KELP_DCCL_T_STRING,
    KELP_DCCL_T_ENUM,
    KELP_DCCL_T_HEX,
    KELP_DCCL_T_HEAD_CCL_ID,
    KELP_DCCL_T_HEAD_ID,
    KELP_DCCL_T_HEAD_TIME,
    KELP_DCCL_T_HEAD_SRC,
    KELP_DCCL_T_HEAD_DEST,
    KELP_DCCL_T_HEAD_FLAG,
    KELP_DCCL_T_HEAD_UNUSED
} kelp_dccl_type;

/* ------------------------------------------------------------------ values */
/** Kind of a value, as Goby's DCCLMessageVal types. */
typedef enum kelp_dccl_kind {
    KELP_DCCL_V_EMPTY = 0,
    KELP_DCCL_V_STRING,
    KELP_DCCL_V_DOUBLE,
    KELP_DCCL_V_LONG,
    KELP_DCCL_V_BOOL
} kelp_dccl_kind;

/** One value. Strings longer than KELP_DCCL_MAX_STRLEN are cut and flagged. */
typedef struct kelp_dccl_val {
    kelp_dccl_kind kind;
    int precision;    /**< display precision of a double (decimals) */
    double d;         /**< KELP_DCCL_V_DOUBLE */
    int64_t l;        /**< KELP_DCCL_V_LONG */
    bool b;           /**< KELP_DCCL_V_BOOL */
    bool cut;         /**< a string was longer than the buffer */
    uint16_t len;     /**< string length */
    char s[KELP_DCCL_MAX_STRLEN + 1]; /**< KELP_DCCL_V_STRING, NUL-terminated */
} kelp_dccl_val;

void kelp_dccl_val_clear(kelp_dccl_val *v);
void kelp_dccl_val_set_str(kelp_dccl_val *v, const char *s);
void kelp_dccl_val_set_strn(kelp_dccl_val *v, const char *s, size_t n);
/** A double with display precision (Goby's default for caller doubles is 15). */
void kelp_dccl_val_set_double(kelp_dccl_val *v, double d, int precision);
void kelp_dccl_val_set_long(kelp_dccl_val *v, int64_t l);
void kelp_dccl_val_set_bool(kelp_dccl_val *v, bool b);
/** Goby conversions (DCCLMessageVal::get). Return false when not convertible. */
bool kelp_dccl_val_to_double(const kelp_dccl_val *v, double *out);
bool kelp_dccl_val_to_long(const kelp_dccl_val *v, int64_t *out);
bool kelp_dccl_val_to_bool(const kelp_dccl_val *v, bool *out);
/** The string form (Goby's display form of doubles). EMPTY gives "" and false.
 *  Output is cut to cap-1 bytes; *len (optional) gets the full length. */
bool kelp_dccl_val_to_str(const kelp_dccl_val *v, char *out, size_t cap, size_t *len);
/** boost::lexical_cast<double> of a whole string (no spaces, "1e1" ok, inf/nan). */
bool kelp_dccl_parse_double(const char *s, size_t n, double *out);
/** Goby's util unbiased_round(v, p): round half even on the floor of v*10^p. */
double kelp_dccl_unbiased_round(double v, int p);

/* ------------------------------------------------------------------ definitions */
/** One algorithm call "name:ref1:ref2" already resolved to field indices. */
typedef struct kelp_dccl_algcall {
    const char *name;
    uint8_t n_refs;
    int16_t refs[KELP_DCCL_MAX_ALG_REFS]; /**< indices into msgdef.fields */
} kelp_dccl_algcall;

/** A header or layout field. Widths are precomputed (kelp_dccl_def_finalize). */
typedef struct kelp_dccl_field {
    const char *name;
    kelp_dccl_type type;
    uint16_t array_length;    /**< >= 1 */
    uint16_t slot;            /**< first value slot */
    uint16_t bits;            /**< width of one element (element 0 for delta arrays) */
    uint16_t delta_bits;      /**< width of elements 1..n-1 when has_delta */
    uint32_t total_bits;
    bool has_delta;
    double min, max, max_delta;
    int precision;            /**< int: 0; header: 0 */
    uint16_t max_length;      /**< string: bytes */
    uint16_t num_bytes;       /**< hex: bytes */
    const char *static_value; /**< static */
    const char *const *enum_values;
    uint16_t n_enum;
    const kelp_dccl_algcall *algs; /**< applied on encode, in order */
    uint8_t n_algs;
    const char *src_var;      /**< value source (pAcommsHandler); NULL = trigger var */
    const char *src_key;      /**< key searched in name=value strings; NULL = name */
} kelp_dccl_field;

typedef enum kelp_dccl_pubtype {
    KELP_DCCL_PUB_AUTO = 0, /**< double if the whole text is a number, else string */
    KELP_DCCL_PUB_STRING,
    KELP_DCCL_PUB_DOUBLE,
    KELP_DCCL_PUB_LONG,
    KELP_DCCL_PUB_BOOL
} kelp_dccl_pubtype;

/** One <message_var> argument of a <publish>. */
typedef struct kelp_dccl_pubarg {
    uint16_t field; /**< index into msgdef.fields */
    const kelp_dccl_algcall *algs;
    uint8_t n_algs;
} kelp_dccl_pubarg;

/** One <publish> block. `format` is always set (defaults are filled at load). */
typedef struct kelp_dccl_publish {
    const char *var;
    kelp_dccl_pubtype type;
    const char *format;
    const kelp_dccl_pubarg *args;
    uint16_t n_args;
} kelp_dccl_publish;

/** <queuing> configuration (libqueue defaults when absent). */
typedef struct kelp_dccl_queuing {
    bool present;        /**< the message had a <queuing> block */
    bool ack;            /**< default true */
    double blackout_time;/**< s, default 0 */
    uint32_t max_queue;  /**< 0 = unlimited */
    bool newest_first;   /**< default true */
    double value_base;   /**< default 1 */
    double ttl;          /**< s, default 1800 */
} kelp_dccl_queuing;

typedef enum kelp_dccl_trigger { KELP_DCCL_TRIG_NONE = 0, KELP_DCCL_TRIG_PUBLISH, KELP_DCCL_TRIG_TIME } kelp_dccl_trigger;

/** A compiled message definition. */
typedef struct kelp_dccl_msgdef {
    const char *name;
    uint16_t id;
    uint16_t size;          /**< maximum bytes on the wire including the header */
    uint16_t repeat;        /**< <repeat> count (1 = none) */
    const kelp_dccl_field *fields; /**< [0..7] header, then layout in order */
    uint16_t n_fields;
    uint16_t n_slots;       /**< value slots needed for encode/decode */
    uint32_t body_bits;
    uint32_t hash;          /**< fingerprint of the wire-relevant definition */
    kelp_dccl_trigger trigger;
    const char *trigger_var;
    const char *trigger_mandatory;
    double trigger_time;
    const char *in_var;     /**< IN_<NAME>_HEX_<size>B unless set */
    const char *out_var;
    const kelp_dccl_publish *publishes;
    uint16_t n_publishes;
    kelp_dccl_queuing queuing;
} kelp_dccl_msgdef;

/** A set of message definitions (one or more XML files). */
typedef struct kelp_dccl_set {
    const kelp_dccl_msgdef *const *msgs;
    size_t n;
} kelp_dccl_set;

/** Goby's width expression ceil(log(range*10^p + 2)/log(2)) (one bit off at 2^29 etc., on purpose). */
unsigned kelp_dccl_width(double range, int precision);
/** Compute slots, widths, body_bits and hash of a definition being built (loader, tests).
 *  Fails with KELP_ERR_RANGE (d says why) if Goby would reject it at load. d may be NULL. */
KELP_MUST_CHECK int kelp_dccl_def_finalize(kelp_dccl_msgdef *def, kelp_dccl_field *fields, kelp_diag *d);
/** Field index by name (header renames and default names, then layout), or -1. */
int kelp_dccl_field_find(const kelp_dccl_msgdef *def, const char *name);
const kelp_dccl_msgdef *kelp_dccl_set_find_id(const kelp_dccl_set *set, unsigned id);
const kelp_dccl_msgdef *kelp_dccl_set_find_name(const kelp_dccl_set *set, const char *name);
/** Largest encoded length: 6 + ceil(body_bits/8). */
size_t kelp_dccl_max_len(const kelp_dccl_msgdef *def);
/** Default name of a header field ("_ccl_id", "_id", "_time", ...). */
const char *kelp_dccl_head_default_name(unsigned h);

/* ------------------------------------------------------------------ algorithms */
/** An algorithm: modifies *v in place; refs are the referenced values (never NULL,
 *  possibly EMPTY). Called only for non-empty *v. */
typedef void (*kelp_dccl_alg_fn)(kelp_dccl_val *v, const kelp_dccl_val *const *refs, size_t n_refs, void *user);

typedef struct kelp_dccl_alg_entry {
    const char *name;
    kelp_dccl_alg_fn fn;
    void *user;
} kelp_dccl_alg_entry;

/** Registry of algorithms in caller storage. */
typedef struct kelp_dccl_algs {
    kelp_dccl_alg_entry *entries;
    size_t n, cap;
} kelp_dccl_algs;

/** One modem-id lookup entry (modem_id_lookup_path file). */
typedef struct kelp_dccl_modem_entry {
    int id;
    char name[KELP_DCCL_MAX_MODEM_NAME];
    char type[KELP_DCCL_MAX_MODEM_NAME];
} kelp_dccl_modem_entry;

/** Context of the built-in algorithms: modem-id table, LatOrigin/LongOrigin. */
typedef struct kelp_dccl_builtin {
    kelp_dccl_modem_entry *modems; /**< caller storage, sorted by id */
    size_t n_modems, cap_modems;
    bool have_origin;
    double lat_origin, lon_origin;
    /* private: MOOS CMOOSGeodesy state */
    double origin_north, origin_east, north, east;
    bool step_after_init;
} kelp_dccl_builtin;

void kelp_dccl_algs_init(kelp_dccl_algs *algs, kelp_dccl_alg_entry *storage, size_t cap);
/** Register (or replace) an algorithm. KELP_ERR_NOSPACE when full. */
KELP_MUST_CHECK int kelp_dccl_algs_add(kelp_dccl_algs *algs, const char *name, kelp_dccl_alg_fn fn, void *user);
const kelp_dccl_alg_entry *kelp_dccl_algs_find(const kelp_dccl_algs *algs, const char *name);
/** Register every algorithm pAcommsHandler 1.1 registers, plus `alg_TSD_to_soundspeed`. */
KELP_MUST_CHECK int kelp_dccl_algs_add_builtin(kelp_dccl_algs *algs, kelp_dccl_builtin *ctx);
void kelp_dccl_builtin_init(kelp_dccl_builtin *ctx, kelp_dccl_modem_entry *storage, size_t cap);
/** Set LatOrigin/LongOrigin (enables lat2utm_y, lon2utm_x, utm_x2lon, utm_y2lat). */
void kelp_dccl_builtin_set_origin(kelp_dccl_builtin *ctx, double lat, double lon);
/** Parse modem-id lookup text ("id,name,type" lines, '#' and '//' comments, spaces stripped). */
KELP_MUST_CHECK int kelp_dccl_builtin_parse_modems(kelp_dccl_builtin *ctx, const char *text, size_t len);
/** MOOS CMOOSGeodesy (WGS-84 Gantz/USGS UTM) used by the UTM algorithms. */
void kelp_dccl_geo_latlon2local(kelp_dccl_builtin *ctx, double lat, double lon, double *north, double *east);
void kelp_dccl_geo_local2latlon(kelp_dccl_builtin *ctx, double x, double y, double *lat, double *lon);
/** Mackenzie (1981) sound speed, T degC, S, D metres. */
double kelp_dccl_mackenzie(double t, double s, double d);

/* ------------------------------------------------------------------ crypto */
/** Crypto operations the core needs; the edge provides mbedTLS, firmware its own.
 *  iv(): first 16 bytes of SHA-256(header bytes). ctr(): AES-256-CTR with the
 *  key SHA-256(passphrase), counter block = iv, 128-bit big-endian increment, in place. */
typedef struct kelp_dccl_crypto {
    int (*iv)(void *user, const uint8_t *head, size_t n, uint8_t iv[16]);
    int (*ctr)(void *user, const uint8_t iv[16], uint8_t *buf, size_t n);
    void *user;
} kelp_dccl_crypto;

/* ------------------------------------------------------------------ codec */
/** Workspace of a codec (private): the large temporaries of encode, decode and publish live
 *  here, not on the stack (firmware stacks are small). One call uses it at a time; nothing
 *  in it outlives a call. Sized by KELP_DCCL_MAX_STRLEN, _MAX_ALG_REFS, _MAX_SIZE,
 *  _MAX_PUB_ARGS and _PUB_ALG_WORK. */
typedef union kelp_dccl_work {
    struct {
        kelp_dccl_val ref[KELP_DCCL_MAX_ALG_REFS]; /**< referenced values handed to an algorithm */
        kelp_dccl_val key, elem;                   /**< element 0 (array key) and element k; header */
        char str[KELP_DCCL_MAX_STRLEN + 1];        /**< string form of a non-string value */
    } enc;
    struct {
        uint8_t body[KELP_DCCL_MAX_SIZE];          /**< the (decrypted) body */
    } dec;
    struct {
        kelp_dccl_val val;                         /**< argument being run through algorithms; typed value */
        char arg[KELP_DCCL_MAX_STRLEN + 1];        /**< string of an argument without algorithms */
        uint16_t off[KELP_DCCL_MAX_PUB_ARGS];      /**< offset in alg of an argument with algorithms */
        char alg[KELP_DCCL_PUB_ALG_WORK];          /**< strings of the arguments with algorithms */
    } pub;
} kelp_dccl_work;

/** Codec context: modem id, crypto (NULL = plaintext, i.e. NOT Goby-compatible
 *  on the wire), algorithm registry (NULL = algorithms are no-ops), and the workspace of
 *  the calls (a few KB: place a codec statically or in the caller's state on firmware). */
typedef struct kelp_dccl_codec {
    unsigned modem_id;
    const kelp_dccl_crypto *crypto;
    const kelp_dccl_algs *algs;
    kelp_diag diag;      /**< first error of the last call (code KELP_OK when none) */
    kelp_dccl_work work; /**< private */
} kelp_dccl_codec;

void kelp_dccl_codec_init(kelp_dccl_codec *cx, unsigned modem_id, const kelp_dccl_crypto *crypto,
                          const kelp_dccl_algs *algs);

/** Encode one message.
 * @param in   n_in >= def->n_slots values (header defaults apply to EMPTY header slots;
 *             the caller's values are not modified)
 * @param now  UNIX seconds used when _time is not given
 * @param out  NULL to measure only; else cap >= kelp_dccl_max_len(def) is always enough.
 *             The message is built in out itself (bytes past cap are only measured); on an
 *             error return out[0..cap) holds no meaningful bytes.
 * @return 0, KELP_ERR_NOSPACE, KELP_ERR_PARSE (hex field of the wrong length),
 *         KELP_ERR_CRYPTO. cx->diag says why (kelp_diag_text). */
KELP_MUST_CHECK int kelp_dccl_encode(kelp_dccl_codec *cx, const kelp_dccl_msgdef *def, const kelp_dccl_val *in,
                                     size_t n_in, kelp_time now, uint8_t *out, size_t cap, size_t *len);

/** Decode one message (trailing zero bytes stripped first, as Goby does).
 * @param out n_out >= def->n_slots; every slot is written (EMPTY = null)
 * @param now decoder clock for the 12-hour day inference of _time
 * @return 0, KELP_ERR_TRUNCATED (empty input), KELP_ERR_RANGE (enum index out of range),
 *         KELP_ERR_CRYPTO. Never reads outside in[0..n). */
KELP_MUST_CHECK int kelp_dccl_decode(kelp_dccl_codec *cx, const kelp_dccl_msgdef *def, const uint8_t *in, size_t n,
                                     kelp_time now, kelp_dccl_val *out, size_t n_out);

/** DCCL id from the first (up to 6) bytes, as Goby reads it before decoding. */
KELP_MUST_CHECK int kelp_dccl_peek_id(const uint8_t *in, size_t n, unsigned *id);

/** Header fields of raw wire bytes (no stripping, no defaults). */
typedef struct kelp_dccl_header {
    unsigned ccl_id, id, src, dest, unused;
    unsigned time_of_day; /**< seconds since UTC midnight (0..131071 on the wire) */
    double time;          /**< UNIX time after the 12-hour day inference */
    bool multimessage, broadcast;
} kelp_dccl_header;

KELP_MUST_CHECK int kelp_dccl_head_read(const uint8_t *in, size_t n, kelp_time now, kelp_dccl_header *h);
/** Set or clear the two flag bits that libqueue uses (byte 5, bits 3 and 2). */
void kelp_dccl_head_set_flags(uint8_t head[KELP_DCCL_HEAD_BYTES], bool multimessage, bool broadcast);
/** Goby's time inference: midnight (UTC) of now's day, or the day before when
 *  |tod_now - tod| > 43200, plus tod. */
double kelp_dccl_time_infer(unsigned tod, kelp_time now);

/* ------------------------------------------------------------------ publish (on receipt) */
/** One publication: variable and a double or a string. */
typedef struct kelp_dccl_pub {
    char var[KELP_DCCL_MAX_NAME];
    bool is_double;
    double d;
    char s[KELP_DCCL_MAX_PUBLEN];
} kelp_dccl_pub;

/** Fill every <publish> of def (times repeat) from decoded values.
 * @param vals as written by kelp_dccl_decode (not modified)
 * Each value is formatted straight into out[i].s. The argument strings of arguments that run
 * algorithms are kept in the codec's workspace (KELP_DCCL_PUB_ALG_WORK bytes a publication);
 * the others are formatted when the format string reaches them.
 * @return 0, KELP_ERR_NOSPACE (more publications than cap, more than KELP_DCCL_MAX_PUB_ARGS
 *         arguments, or algorithm results longer than KELP_DCCL_PUB_ALG_WORK),
 *         KELP_ERR_PARSE (bad format). */
KELP_MUST_CHECK int kelp_dccl_publish_all(kelp_dccl_codec *cx, const kelp_dccl_msgdef *def, const kelp_dccl_val *vals,
                                          size_t n_vals, kelp_dccl_pub *out, size_t cap, size_t *n_out);

/** How many publications kelp_dccl_publish_all writes for def: every <publish> once per
 * repeat index (a <repeat/> message can need thousands). Size `out` with it. */
size_t kelp_dccl_n_publications(const kelp_dccl_msgdef *def);

/** boost::format subset used by <format>: %N%, %N$spec, %spec, %|spec|, %%. Every argument is a string. */
KELP_MUST_CHECK int kelp_dccl_format(const char *fmt, const char *const *args, size_t n_args, char *out, size_t cap,
                                     size_t *len);

/* ------------------------------------------------------------------ value sourcing (encode side) */
/** A bus variable value. */
typedef struct kelp_dccl_var {
    const char *name;
    bool is_double;
    double d;
    const char *s;
} kelp_dccl_var;

/** tes_util::val_from_string: value of "key=" in "a=1,key={2,3},b=4" ("2,3"), as (ptr,len). */
bool kelp_dccl_val_from_string(const char *str, const char *key, const char **val, size_t *len);

/** True if v is this message's trigger variable and contains the mandatory content. */
bool kelp_dccl_is_trigger(const kelp_dccl_msgdef *def, const kelp_dccl_var *v);

/** Build values from variables as pAcommsHandler does: each field reads its src_var
 * (default the trigger var); a string is searched for key=value, else used whole;
 * array fields split on ','. `element` selects the element written for <repeat>
 * messages (0 otherwise). Slots of fields without a value are left unchanged. */
KELP_MUST_CHECK int kelp_dccl_source(const kelp_dccl_msgdef *def, const kelp_dccl_var *vars, size_t n_vars,
                                     unsigned element, kelp_dccl_val *out, size_t n_out);

/** Time trigger: fires when now > start + k*trigger_time (k = 1, 2, ...). */
typedef struct kelp_dccl_timer {
    double start;
    unsigned k;
} kelp_dccl_timer;
void kelp_dccl_timer_init(kelp_dccl_timer *t, double start);
bool kelp_dccl_timer_due(kelp_dccl_timer *t, const kelp_dccl_msgdef *def, kelp_time now);

#ifdef __cplusplus
}
#endif
#endif
