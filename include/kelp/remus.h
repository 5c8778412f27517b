/* kelp: REMUS CCL messages for pREMUSCodec (core, allocation-free, no clock).
 *
 * FACTS and where they came from (Goby 1.x public source, GobySoft/goby history; read for facts,
 * no code copied):
 *  - src/moos/pREMUSCodec/pREMUSCodec.h (Goby 1.x, 2011): the CCL frame ids REDIRECT 7,
 *    POSITION 8, STATE 14, RANGER 16, OASIS 31.
 *  - src/moos/pREMUSCodec/pREMUSCodec.cpp (Goby 1.x): the MODEM_MSG_DATA_STATE byte layout (below),
 *    the Ranger byte positions (BCD lat/lon 1-5 and 6-10, speed 18, heading 19-20, depth 28+23),
 *    what create_status fills in (lat, lon, time/date, heading, depth, est_velocity; the rest 0),
 *    and that multi-byte fields sit little-endian on the wire.
 *  - src/moos/pREMUSCodec/WhoiUtil.cpp (Goby 1.x, WHOI helpers): every field encoding below.
 *  - src/acomms/protobuf/ccl.proto (Goby 2.0, 2012): mission mode in the top 3 bits of the
 *    depth word (13-bit depth), the MissionMode names, and fix_age at 4 s per unit saturating
 *    at 255 (src/acomms/dccl/dccl_ccl_compatibility.h).
 *
 * State message (32 bytes, byte 0 = 14):
 *   0 id | 1-3 lat | 4-6 lon | 7 fix_age | 8-10 time_date | 11 heading | 12-13 mode:3|depth:13 |
 *   14-17 faults | 18 faults_2 | 19 mission_leg | 20 est_velocity | 21 objective_index |
 *   22 watts | 23-25 lat_goal | 26-28 lon_goal | 29 battery_percent | 30-31 gfi_pitch_oil
 *
 * Field encodings (codes are what is on the wire; the decode helpers give physical values):
 *  - lat/lon: signed 24-bit two's complement, code = round-half-away(deg * 8388607/180); the
 *    hemisphere is the sign. A code outside 24 bits wraps (as Goby's truncation does), so a
 *    longitude past 180 lands on the other side of the antimeridian.
 *  - heading: code = trunc(h * 255/360 + 0.5), h in degrees taken modulo 360 (kelp: Goby leaves
 *    h outside [0,360) undefined); value = code * 360/255 (about 1.41 degrees per unit).
 *  - depth (13 bits): 0-100 m at 0.1 m (codes 0-1000), 100-200 m at 0.2 m (1000-1500),
 *    200-1000 m at 0.5 m (1500-3100), 1000-6000 m at 1 m (3100-8100); each band rounds by adding
 *    half its step then truncating; negative -> 0; 6000 m and beyond (and NaN) -> 8100.
 *  - est_velocity: signed byte, code = trunc(v * 25) (0.04 m/s, Goby 1.x truncates), clamped to
 *    [-128,127] (kelp: Goby's overflow is undefined).
 *  - speed (Redirect, m/s mode): signed byte, code = trunc(v * 30) clamped to [-127,127].
 *  - watts: code = trunc(W / 4) clamped to [0,255]; value = code * 4.
 *  - gfi_pitch_oil (16 bits): gfi bits 0-4 = trunc(gfi% * 31/100), oil bits 5-9 =
 *    trunc(oil% * 31/100) (both clamped to 0..100 %), pitch bits 10-15 = signed
 *    round-half-away(pitch * 63/180) with pitch clamped to +-90. kelp saturates the pitch code at
 *    +31: Goby lets +90 round to +32, which wraps to -32 (-90) in 6 bits. Decode: gfi is truncated
 *    to whole percent (Goby), oil = code * 100/31, pitch = code * 180/63.
 *  - time_date (24 bits, UTC, no year): bits 0-3 seconds/4, 4-9 minute, 10-14 hour, 15-19 day of
 *    month, 20-23 month (1-12).
 *  - fix_age: seconds / 4, saturating at 255.
 * Values the decoders return are rounded to float where Goby's helpers return float (depth,
 * velocity, speed, watts, gfi/pitch/oil), so printed values agree digit for digit.
 */
#ifndef KELP_REMUS_H
#define KELP_REMUS_H

#include <stddef.h>
#include <stdint.h>

#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_REMUS_FRAME_LEN 32 /**< every REMUS CCL message is one 32-byte modem frame */

/** CCL frame ids (first byte). */
enum {
    KELP_REMUS_ID_REDIRECT = 7,
    KELP_REMUS_ID_POSITION = 8,
    KELP_REMUS_ID_STATE = 14,
    KELP_REMUS_ID_RANGER = 16,
    KELP_REMUS_ID_OASIS = 31 /**< OASIS array data: the Alert and Alert2 reports */
};

typedef enum kelp_remus_kind {
    KELP_REMUS_UNKNOWN = 0,
    KELP_REMUS_REDIRECT,
    KELP_REMUS_POSITION,
    KELP_REMUS_STATE,
    KELP_REMUS_RANGER,
    KELP_REMUS_OASIS /**< Alert / Alert2: same id; Goby tells them apart by MOOS variable */
} kelp_remus_kind;

/** Which message a frame holds, by its first byte; UNKNOWN for an empty frame or another id. */
kelp_remus_kind kelp_remus_identify(const uint8_t *frame, size_t len);

/** State mission modes (top 3 bits of the depth word). */
typedef enum kelp_remus_mission_mode {
    KELP_REMUS_MODE_COMPLETED = 0,
    KELP_REMUS_MODE_MANUAL = 1,
    KELP_REMUS_MODE_TEST = 2,
    KELP_REMUS_MODE_FAULT = 3,
    KELP_REMUS_MODE_REDIRECT = 5,
    KELP_REMUS_MODE_NORMAL = 6
} kelp_remus_mission_mode;

/** The State message as wire codes (exact: decode then encode gives the same bytes). */
typedef struct kelp_remus_state {
    int32_t lat, lon;          /**< LATLON_COMPRESSED codes, -8388608..8388607 */
    uint8_t fix_age;           /**< 4 s per unit */
    uint32_t time_date;        /**< 24-bit TIME_DATE */
    uint8_t heading;           /**< heading code */
    uint8_t mission_mode;      /**< 0..7 */
    uint16_t depth;            /**< 13-bit depth code */
    uint32_t faults;           /**< bytes 14-17, little-endian */
    uint8_t faults_2;
    uint8_t mission_leg;
    int8_t est_velocity;       /**< velocity code */
    uint8_t objective_index;
    uint8_t watts;             /**< watts code */
    int32_t lat_goal, lon_goal;
    uint8_t battery_percent;
    uint16_t gfi_pitch_oil;
} kelp_remus_state;

/** Pack a State. @return 0; KELP_ERR_ARG (NULL); KELP_ERR_RANGE (a code wider than its field:
 *  lat/lon outside 24 bits, time_date > 0xFFFFFF, mission_mode > 7, depth > 0x1FFF);
 *  KELP_ERR_NOSPACE (cap < 32). *len = 32 on success. */
KELP_MUST_CHECK int kelp_remus_state_encode(const kelp_remus_state *s, uint8_t *out, size_t cap,
                                            size_t *len);
/** Unpack a State. @return 0; KELP_ERR_ARG (NULL); KELP_ERR_TRUNCATED (len < 32);
 *  KELP_ERR_RANGE (len > 32); KELP_ERR_PARSE (first byte not 14). */
KELP_MUST_CHECK int kelp_remus_state_decode(const uint8_t *in, size_t len, kelp_remus_state *out);

/** What Goby's create_status fills in (every other field 0): position, time (UNIX seconds),
 *  heading (deg), depth (m), est_velocity (m/s). */
void kelp_remus_state_from_nav(kelp_remus_state *s, double lat, double lon, int64_t unix_s,
                               double heading, double depth, double speed);

/* ---- field helpers ---- */

int32_t kelp_remus_latlon_encode(double deg);
/** Correct two's complement decode (Goby >= 2012). */
double kelp_remus_latlon_decode(int32_t code);
/** Goby 1.x pREMUSCodec's decode: the 24 bits unsigned, minus 360 when past 180 (its sign
 *  extension never fires), which puts every negative value 2 codes (about 4.3e-5 deg) high. */
double kelp_remus_latlon_decode_goby1(int32_t code);

uint8_t kelp_remus_heading_encode(double deg);
double kelp_remus_heading_decode(uint8_t code);

uint16_t kelp_remus_depth_encode(double m);
/** Only the low 13 bits are read. Codes past 8100 give 6000. */
double kelp_remus_depth_decode(uint16_t code);

int8_t kelp_remus_velocity_encode(double mps);
double kelp_remus_velocity_decode(int8_t code);

int8_t kelp_remus_speed_encode(double mps);
double kelp_remus_speed_decode(int8_t code);

uint8_t kelp_remus_watts_encode(double watts);
double kelp_remus_watts_decode(uint8_t code);

uint8_t kelp_remus_fix_age_encode(double seconds);
unsigned kelp_remus_fix_age_decode(uint8_t code);

uint16_t kelp_remus_gfi_pitch_oil_encode(double gfi, double pitch, double oil);
void kelp_remus_gfi_pitch_oil_decode(uint16_t code, double *gfi, double *pitch, double *oil);

typedef struct kelp_remus_time {
    unsigned month, day, hour, minute, second; /**< as on the wire; second is a multiple of 4 */
} kelp_remus_time;

/** The TIME_DATE code of a UNIX time (UTC; seconds floored to a multiple of 4). */
uint32_t kelp_remus_time_date_encode(int64_t unix_s);
/** Split a TIME_DATE code (only the low 24 bits are read). */
void kelp_remus_time_date_decode(uint32_t code, kelp_remus_time *out);
/** UNIX seconds of a TIME_DATE in a given year. @return 0; KELP_ERR_RANGE (month 0 or > 12, day 0
 *  or past the month's end, hour > 23, minute > 59, seconds code 15 = 60 s). */
KELP_MUST_CHECK int kelp_remus_time_date_to_unix(uint32_t code, int64_t year, int64_t *unix_s);

/* ---- Redirect (id 7), encode as Goby 1.x's pREMUSCodec fills it from OUTGOING_COMMAND ----
 * 0 id | 1 (0) | 2-4 lat | 5-7 lon | 8 speed/depth flags | 9-10 transit depth | 11 transit speed
 * (m/s code) | 12 transit command | 13-14 survey depth | 15 survey speed | 16 survey command |
 * 17 rows | 18-19 row length (LE) | 20 spacing 0 | 21 spacing 1 | 22 row heading code |
 * 23-25 start lat | 26-28 start lon | 29-31 (0). */
typedef struct kelp_remus_redirect {
    double lat, lon;
    uint8_t speed_depth_flags;
    double transit_depth, transit_speed;
    uint8_t transit_command;
    double survey_depth, survey_speed;
    uint8_t survey_command;
    uint8_t rows;
    double row_length;              /**< clamped to 0..65535, truncated */
    double row_spacing_0, row_spacing_1; /**< clamped to 0..255, truncated */
    double row_heading;
    double start_lat, start_lon;
} kelp_remus_redirect;

/** @return 0; KELP_ERR_ARG; KELP_ERR_NOSPACE (cap < 32). */
KELP_MUST_CHECK int kelp_remus_redirect_encode(const kelp_remus_redirect *r, uint8_t *out, size_t cap, size_t *len);

/* ---- Ranger (id 16), decode only, as Goby 1.x does ---- */

typedef struct kelp_remus_ranger {
    double lat, lon;  /**< degrees (BCD degrees, hemisphere nibble C/D = negative, BCD minutes) */
    double speed;     /**< byte 18, BCD, 0.1 units */
    double heading;   /**< bytes 19-20, BCD, 0.1 deg */
    double depth;     /**< BCD digits of bytes 28 (high) and 23 (low) */
} kelp_remus_ranger;

/** @return 0; KELP_ERR_ARG; KELP_ERR_TRUNCATED (len < 32); KELP_ERR_RANGE (len > 32);
 *  KELP_ERR_PARSE (first byte not 16). */
KELP_MUST_CHECK int kelp_remus_ranger_decode(const uint8_t *in, size_t len, kelp_remus_ranger *out);

/* ---- pREMUSCodec's logic as a core state machine (mail and now in, publications out) ----
 *
 * From Goby 1.x src/moos/pREMUSCodec/pREMUSCodec.cpp (facts):
 *  - create_status: once NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED and NAV_DEPTH have all arrived, a
 *    State is made every status_interval seconds (Goby: 10 s, fixed; the first at once), the
 *    position through the MOOS UTM geodesy at LatOrigin/LongOrigin, the time the UTC time of
 *    now, and published on mdat_state_out as a ModemDataTransmission with only base.src (MODEM_ID),
 *    base.dest (0) and data set: `base { src: 2 dest: 0 } data: "\016..."`.
 *  - an incoming ModemDataTransmission on mdat_state_var / mdat_ranger_var (data zero-padded or
 *    cut to 32 bytes) becomes a NODE_REPORT of the sender (name and type from the modem-id
 *    lookup: the id itself / "unknown_type" when absent), X/Y from the geodesy, MODE=NOMOOS,
 *    ALLSTOP=NotUsingIvP, LENGTH=4; plus STATUS_REPORT_IN (MessageType=CCL_STATUS,...) and the
 *    <NAME>_NAV_{UTC,X,Y,LAT,LONG,SPEED,DEPTH,HEADING} contact variables.
 *  - OUTGOING_COMMAND holding MessageType=CCL_REDIRECT (keys DestinationPlatformId, Latitude,
 *    Longitude, SpeedDepthFlags (hex), TransitDepth, TransitSpeed, TransitCommand, SurveyDepth,
 *    SurveySpeed, SurveyCommand, NumberOfRows, RowLength, RowSpacing0, RowSpacing1, RowHeading,
 *    StartLatitude, StartLongitude) -> a Redirect on mdat_redirect_out, src MODEM_ID, dest the
 *    DestinationPlatformId (kelp: an absent key is 0; Goby keeps the previous message's value).
 *  - Redirect -> CCL_REDIRECT_IN, Alert -> CCL_ALERT_IN, Alert2 -> CCL_ALERT2_IN: key=value text
 *    in Goby's key order (byte positions in remuscodec.c), numbers as boost::lexical_cast writes
 *    them (%.17g).
 * kelp differences: NODE_REPORT is written in the uField format (include/kelp/nodereport.h) with
 * TIME = now; MODEM_ID is read as a number or text (Goby reads only the text form); a State,
 * Ranger or Redirect frame whose first byte is not its id is refused with a warning (Goby decodes
 * it anyway; Alert frames are taken whatever their id, which no source gives); bytes >= 0x80 are
 * read as bytes (Goby sign-extends them through char, corrupting depth, gfi/pitch/oil, battery and
 * the alert fields); lat/lon decode with the sign (Goby 1.x: kelp_remus_latlon_decode_goby1);
 * SpeedDepthFlags is the byte's two hex digits (Goby appends them to the previous message's). */

#include <stdbool.h>
#include <kelp/config.h>
#include <kelp/dccl.h>
#include <kelp/field.h>
#include <kelp/nodereport.h>
#include <kelp/queue.h>

enum { KELP_REMUS_STATE_VAR, KELP_REMUS_RANGER_VAR, KELP_REMUS_REDIRECT_VAR, KELP_REMUS_ALERT_VAR,
       KELP_REMUS_ALERT2_VAR, KELP_REMUS_NVARS };

typedef struct kelp_remus_codec_cfg {
    bool create_status;                      /**< default false */
    double status_interval;                  /**< seconds between States (default 10) */
    char in_var[KELP_REMUS_NVARS][KELP_MAX_NAME];  /**< mdat_*_var (IN_REMUS_*_HEX_30B) */
    char out_var[KELP_REMUS_NVARS][KELP_MAX_NAME]; /**< mdat_*_out (OUT_REMUS_*_HEX_30B) */
    kelp_dccl_builtin *geo;                  /**< modem-id table and LatOrigin/LongOrigin (caller's) */
} kelp_remus_codec_cfg;

/** Defaults of the Goby 1.1 User Manual, section 2.5; geo NULL. */
void kelp_remus_codec_cfg_default(kelp_remus_codec_cfg *c);

enum { KELP_REMUS_NAV_X, KELP_REMUS_NAV_Y, KELP_REMUS_NAV_HEADING, KELP_REMUS_NAV_SPEED, KELP_REMUS_NAV_DEPTH,
       KELP_REMUS_NNAV };

/** Scratch of one call (private): too large for a firmware stack. */
typedef union kelp_remus_codec_work {
    struct {
        kelp_acomms_msg msg;               /**< the frame being sent */
        kelp_remus_redirect redirect;      /**< OUTGOING_COMMAND's Redirect */
        char text[KELP_ACOMMS_MAX_PRINT];  /**< its ModemDataTransmission text */
    } out;
    struct {
        kelp_acomms_msg msg;               /**< the frame received */
        kelp_diag diag;                    /**< why it was refused */
        kelp_nodereport report;            /**< the contact's NODE_REPORT */
        char extra[256];                   /**< State: the STATUS_REPORT_IN fields after Depth */
        char up[KELP_DCCL_MAX_MODEM_NAME + 1]; /**< the contact's name upper-cased */
        char var[KELP_MAX_NAME];           /**< a <NAME>_NAV_* variable */
        char text[1536];                   /**< STATUS_REPORT_IN, then NODE_REPORT; CCL_*_IN */
    } in;
} kelp_remus_codec_work;

typedef struct kelp_remus_codec {
    kelp_remus_codec_cfg cfg;
    /* private */
    int my_id;
    double nav[KELP_REMUS_NNAV];
    bool have[KELP_REMUS_NNAV];
    double last_status; /**< -1: none yet */
    unsigned long sent, received[KELP_REMUS_NVARS], refused;
    kelp_remus_codec_work work;
    char warn[256]; /**< workspace: a warning being formatted for the sink (not on the stack) */
} kelp_remus_codec;

/** @return 0; KELP_ERR_ARG (NULL geo, an empty variable name, status_interval not > 0). */
KELP_MUST_CHECK int kelp_remus_codec_init(kelp_remus_codec *t, const kelp_remus_codec_cfg *cfg);
/** The variables to register for, i = 0, 1, ... until NULL. */
const char *kelp_remus_codec_subscription(const kelp_remus_codec *t, unsigned i);
/** One piece of mail. @return 1 if it was used, 0 if not ours, <0 if refused (warned). */
KELP_MUST_CHECK int kelp_remus_codec_mail(kelp_remus_codec *t, const char *var, bool is_string, const char *sval, double dval,
                                          kelp_time now, const kelp_field_sink *sink);
/** Make the State when due. @return 1 if one was published, 0 otherwise. */
int kelp_remus_codec_iterate(kelp_remus_codec *t, kelp_time now, const kelp_field_sink *sink);

#ifdef __cplusplus
}
#endif

#endif
