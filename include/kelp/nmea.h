/* kelp: NMEA 0183 sentences (core; no allocation, no I/O).
 *
 * Reading: a byte-fed line reader (kelp_nmea_reader_feed) returns KELP_ERR_PARTIAL until the
 * line delimiter arrives, then hands out the trimmed line; kelp_nmea_parse() verifies the
 * checksum (when the line carries "*hh") BEFORE the line is split into fields.  This is the
 * acceptance rule of Goby 1.1's NMEASentence(VALIDATE): a '$', an optional trailing "*hh",
 * a first field of exactly 6 characters ("$" + talker + sentence id).
 *
 * Writing: kelp_nmea_writer builds "$CCCYC,0,1,2,0,0,1*hh" into caller storage; the checksum
 * is the XOR of the characters between '$' and '*', two upper-case hex digits.
 */
#ifndef KELP_NMEA_H
#define KELP_NMEA_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <kelp/config.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

/** One parsed sentence.  Fields are NUL-terminated copies inside buf (field 0 = "$CARXD"). */
typedef struct kelp_nmea_sentence {
    char buf[KELP_MAX_NMEA_LINE + 1];     /**< fields, each NUL-terminated */
    uint16_t off[KELP_MAX_NMEA_FIELDS];   /**< offset of field i in buf */
    unsigned nfields;                     /**< number of fields (>= 1) */
    bool had_checksum;                    /**< the line carried "*hh" (and it matched) */
    char talker[3];                       /**< "CA", "CC", "SN", ... */
    char id[4];                           /**< "RXD", "CYC", ... */
} kelp_nmea_sentence;

/** XOR of the bytes of s[0..n) (pass the text between '$' and '*'). */
uint8_t kelp_nmea_checksum(const char *s, size_t n);

/** Parse one complete line (leading/trailing whitespace is ignored).
 *  @return 0; KELP_ERR_EMPTY (blank line); KELP_ERR_PARSE (no '$', bad talker length, bad
 *  checksum digits, too many fields); KELP_ERR_CHECKSUM (mismatch); KELP_ERR_NOSPACE (too long). */
KELP_MUST_CHECK int kelp_nmea_parse(const char *line, size_t len, kelp_nmea_sentence *out);

/** Field i as a C string, or "" when i >= nfields. */
const char *kelp_nmea_field(const kelp_nmea_sentence *s, unsigned i);

/** Field i as a decimal integer (optional sign, digits only, no spaces).
 *  @return 0, KELP_ERR_NOTFOUND (no such field), KELP_ERR_PARSE (not an integer), KELP_ERR_RANGE. */
KELP_MUST_CHECK int kelp_nmea_field_long(const kelp_nmea_sentence *s, unsigned i, long *out);

/** Field i as a decimal number ("0.0101", "-1.2", "12"; no exponent).  0 or as above. */
KELP_MUST_CHECK int kelp_nmea_field_double(const kelp_nmea_sentence *s, unsigned i, double *out);

/** Re-render a parsed sentence as Goby's NMEASentence::message() does: fields joined by ','
 *  plus "*HH".  @return 0 or KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_nmea_render(const kelp_nmea_sentence *s, char *buf, size_t cap, size_t *len);

/* ------------------------------------------------------------------ byte-fed line reader */

/** Reader counters (monotonic). */
typedef struct kelp_nmea_counters {
    uint32_t bytes;       /**< bytes fed */
    uint32_t lines;       /**< non-blank lines completed */
    uint32_t ok;          /**< sentences accepted by kelp_nmea_reader_feed_sentence */
    uint32_t checksum;    /**< checksum mismatches */
    uint32_t parse;       /**< other malformed lines */
    uint32_t overflow;    /**< lines longer than KELP_MAX_NMEA_LINE (discarded) */
} kelp_nmea_counters;

typedef struct kelp_nmea_reader {
    char line[KELP_MAX_NMEA_LINE + 1];
    size_t len;
    bool overflow;        /**< current line too long: discarding until the delimiter */
    char delim;           /**< line delimiter; Goby's Micro-Modem driver reads with '\r' */
    kelp_nmea_counters count;
} kelp_nmea_reader;

/** Initialise; delim 0 selects '\r'. */
void kelp_nmea_reader_init(kelp_nmea_reader *r, char delim);

/** Feed one byte.  When a non-blank line completes: 0 and *line, *len point at the trimmed line
 *  (valid until the next feed).  KELP_ERR_PARTIAL while the line is incomplete (and for blank
 *  lines); KELP_ERR_NOSPACE once when an over-long line ends (it is discarded). */
KELP_MUST_CHECK int kelp_nmea_reader_feed(kelp_nmea_reader *r, uint8_t byte, const char **line, size_t *len);

/** Feed one byte and parse a completed line into out (counters updated).  0 when out holds a
 *  valid sentence; KELP_ERR_PARTIAL until then; a parse error code for a bad complete line. */
KELP_MUST_CHECK int kelp_nmea_reader_feed_sentence(kelp_nmea_reader *r, uint8_t byte, kelp_nmea_sentence *out);

/* ------------------------------------------------------------------ writer */

typedef struct kelp_nmea_writer {
    char *buf;
    size_t cap;
    size_t len;
    int err;              /**< first error (KELP_ERR_NOSPACE), 0 if none */
} kelp_nmea_writer;

/** Start a sentence with the given first field, e.g. "$CCCYC".  buf must hold the result and
 *  its NUL. */
void kelp_nmea_writer_init(kelp_nmea_writer *w, char *buf, size_t cap, const char *head);
void kelp_nmea_writer_str(kelp_nmea_writer *w, const char *field);
void kelp_nmea_writer_long(kelp_nmea_writer *w, long v);
/** A field of the bytes in lower-case hex (two digits a byte), as $CCTXD carries a frame. */
void kelp_nmea_writer_hex(kelp_nmea_writer *w, const uint8_t *data, size_t n);
/** Append "*HH" and NUL-terminate.  @return 0 or the first error; *len = sentence length. */
KELP_MUST_CHECK int kelp_nmea_writer_finish(kelp_nmea_writer *w, size_t *len);

#ifdef __cplusplus
}
#endif

#endif
