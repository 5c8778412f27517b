/* Core tests for the DCCL codec: definitions built by hand (no XML), plaintext
 * vectors from ../shared/spec/acomms.md 3.8 and goby-wire.md 5. */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <string.h>

#include <kelp/dccl.h>

/* ------------------------------------------------------------------ helpers */
static void hex(const uint8_t *b, size_t n, char *out)
{
    static const char H[] = "0123456789abcdef";
    size_t i;
    for (i = 0; i < n; i++) {
        out[2 * i] = H[b[i] >> 4];
        out[2 * i + 1] = H[b[i] & 15];
    }
    out[2 * n] = '\0';
}

#define DAY0 1699920000.0 /* 2023-11-14 00:00:00 UTC */
#define NOON (DAY0 + 43200.0)

/* example1 GoToCommand (seed 002, 2.3.8) */
static const char *const NO_ENUM[] = {NULL};
static kelp_dccl_field goto_fields[14];
static kelp_dccl_msgdef goto_def;

static void build_goto(void)
{
    memset(goto_fields, 0, sizeof goto_fields);
    memset(&goto_def, 0, sizeof goto_def);
    goto_fields[KELP_DCCL_H_DEST].name = "Destination";
    goto_fields[8] = (kelp_dccl_field){.name = "type", .type = KELP_DCCL_T_STATIC, .array_length = 1, .static_value = "goto"};
    goto_fields[9] = (kelp_dccl_field){.name = "goto_x", .type = KELP_DCCL_T_INT, .array_length = 1, .min = 0, .max = 10000};
    goto_fields[10] = (kelp_dccl_field){.name = "goto_y", .type = KELP_DCCL_T_INT, .array_length = 1, .min = 0, .max = 10000};
    goto_fields[11] = (kelp_dccl_field){.name = "lights_on", .type = KELP_DCCL_T_BOOL, .array_length = 1};
    goto_fields[12] = (kelp_dccl_field){.name = "new_instructions", .type = KELP_DCCL_T_STRING, .array_length = 1, .max_length = 10};
    goto_fields[13] = (kelp_dccl_field){.name = "goto_speed", .type = KELP_DCCL_T_FLOAT, .array_length = 1, .min = 0, .max = 3, .precision = 2};
    goto_def.name = "GoToCommand";
    goto_def.id = 1;
    goto_def.size = 32;
    goto_def.n_fields = 14;
    (void)NO_ENUM;
    ck_assert_int_eq(kelp_dccl_def_finalize(&goto_def, goto_fields, NULL), 0);
}

static void set(const kelp_dccl_msgdef *d, kelp_dccl_val *v, const char *name, const char *s)
{
    int fi = kelp_dccl_field_find(d, name);
    ck_assert_int_ge(fi, 0);
    kelp_dccl_val_set_str(&v[d->fields[fi].slot], s);
}

static void clear_all(kelp_dccl_val *v, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) kelp_dccl_val_clear(&v[i]);
}

static void str_of(const kelp_dccl_msgdef *d, const kelp_dccl_val *v, const char *name, unsigned k, char *out)
{
    int fi = kelp_dccl_field_find(d, name);
    ck_assert_int_ge(fi, 0);
    (void)kelp_dccl_val_to_str(&v[d->fields[fi].slot + k], out, 300, NULL);
}

/* ------------------------------------------------------------------ widths, rounding, conversions */
START_TEST(width_expression)
{
    ck_assert_uint_eq(kelp_dccl_width(1000, 0), 10);      /* seed: "10 bits long" */
    ck_assert_uint_eq(kelp_dccl_width(1023, 0), 11);      /* code 0 reserved */
    ck_assert_uint_eq(kelp_dccl_width(10000, 0), 14);
    ck_assert_uint_eq(kelp_dccl_width(3, 2), 9);          /* goto_speed */
    ck_assert_uint_eq(kelp_dccl_width(200000, 0), 18);    /* SIMPLE_STATUS nav_x */
    ck_assert_uint_eq(kelp_dccl_width(536870910, 0), 30); /* 2^29: one bit too many, as Goby */
    ck_assert_uint_eq(kelp_dccl_width(2147483646, 0), 32);
    ck_assert_uint_eq(kelp_dccl_width(536870909, 0), 29);
}
END_TEST

START_TEST(unbiased_round_half_even)
{
    ck_assert(kelp_dccl_unbiased_round(2.5, 0) == 2);
    ck_assert(kelp_dccl_unbiased_round(3.5, 0) == 4);
    ck_assert(kelp_dccl_unbiased_round(5.5, 0) == 6);
    ck_assert(kelp_dccl_unbiased_round(4.5, 0) == 4);
    ck_assert(kelp_dccl_unbiased_round(4.123, 2) == 4.12);
    ck_assert(kelp_dccl_unbiased_round(-2.5, 0) == -2);
    ck_assert(kelp_dccl_unbiased_round(2.3, 2) == 2.3);
    ck_assert(kelp_dccl_unbiased_round(1234, -2) == 1200);
}
END_TEST

START_TEST(parse_double_like_lexical_cast)
{
    double d;
    ck_assert(kelp_dccl_parse_double("1e1", 3, &d) && d == 10);
    ck_assert(kelp_dccl_parse_double("+5", 2, &d) && d == 5);
    ck_assert(kelp_dccl_parse_double("5.", 2, &d) && d == 5);
    ck_assert(kelp_dccl_parse_double(".5", 2, &d) && d == 0.5);
    ck_assert(kelp_dccl_parse_double("-inf", 4, &d) && isinf(d) && d < 0);
    ck_assert(kelp_dccl_parse_double("NaN", 3, &d) && isnan(d));
    ck_assert(!kelp_dccl_parse_double(" 1", 2, &d));
    ck_assert(!kelp_dccl_parse_double("1 ", 2, &d));
    ck_assert(!kelp_dccl_parse_double("", 0, &d));
    ck_assert(!kelp_dccl_parse_double(".", 1, &d));
    ck_assert(!kelp_dccl_parse_double("1e", 2, &d));
    ck_assert(!kelp_dccl_parse_double("0x10", 4, &d));
    ck_assert(!kelp_dccl_parse_double("1e400", 5, &d));
    ck_assert(!kelp_dccl_parse_double("blah=3.56", 9, &d));
}
END_TEST

START_TEST(value_string_forms)
{
    kelp_dccl_val v;
    char s[64];
    kelp_dccl_val_clear(&v);
    ck_assert(!kelp_dccl_val_to_str(&v, s, sizeof s, NULL));
    ck_assert_str_eq(s, "");
    kelp_dccl_val_set_double(&v, 2.3, 2);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "2.30");
    kelp_dccl_val_set_double(&v, 0.1, 15);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "0.100000000000000");
    kelp_dccl_val_set_double(&v, 1.5, 15);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "1.5");
    kelp_dccl_val_set_double(&v, 1e20, 15);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "1e+20");
    /* a negative precision: the C++ stream's default, 6, as Goby 1.1 prints it (fixed while
     * log10(|d|) + precision <= 15) */
    kelp_dccl_val_set_double(&v, 1230, -1);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "1230.000000");
    kelp_dccl_val_set_double(&v, 0, -2);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "0.000000");
    kelp_dccl_val_set_double(&v, 1e20, -1);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "1e+20");
    kelp_dccl_val_set_long(&v, -5);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "-5");
    kelp_dccl_val_set_bool(&v, true);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "true");
}
END_TEST

START_TEST(value_conversions)
{
    kelp_dccl_val v;
    bool b;
    int64_t l;
    double d;
    kelp_dccl_val_set_str(&v, "TRUE");
    ck_assert(kelp_dccl_val_to_bool(&v, &b) && b);
    ck_assert(kelp_dccl_val_to_double(&v, &d) && d == 1);
    kelp_dccl_val_set_str(&v, "2");
    ck_assert(!kelp_dccl_val_to_bool(&v, &b));
    kelp_dccl_val_set_double(&v, 0.5, 15);
    ck_assert(kelp_dccl_val_to_bool(&v, &b) && !b);
    kelp_dccl_val_set_double(&v, 2.0, 15);
    ck_assert(!kelp_dccl_val_to_bool(&v, &b));
    kelp_dccl_val_set_long(&v, 2);
    ck_assert(!kelp_dccl_val_to_bool(&v, &b));
    kelp_dccl_val_set_str(&v, "2.5");
    ck_assert(kelp_dccl_val_to_long(&v, &l) && l == 3); /* sci_round: half away from zero */
    kelp_dccl_val_set_str(&v, "abc");
    ck_assert(!kelp_dccl_val_to_double(&v, &d));
}
END_TEST

/* ------------------------------------------------------------------ encode / decode */
START_TEST(goto_command_plain_vector)
{
    kelp_dccl_val v[32], out[32];
    kelp_dccl_codec cx;
    uint8_t buf[64];
    char h[200], s[300];
    size_t n;
    build_goto();
    kelp_dccl_codec_init(&cx, 1, NULL, NULL);
    clear_all(v, 32);
    set(&goto_def, v, "Destination", "3");
    set(&goto_def, v, "goto_x", "351");
    set(&goto_def, v, "goto_y", "294");
    set(&goto_def, v, "lights_on", "true");
    set(&goto_def, v, "new_instructions", "make_toast");
    set(&goto_def, v, "goto_speed", "2.3");
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, buf, sizeof buf, &n), 0);
    hex(buf, n, h);
    /* acomms.md 3.8 gives ...e8e7 with round(); Goby truncates: 2.3*100 -> 229 + 1 = 230 -> ...e8e6 */
    ck_assert_str_eq(h, "2000aa30023002c0093cdac2d6cabee8dec2e6e8e6");
    ck_assert_int_eq(kelp_dccl_decode(&cx, &goto_def, buf, n, NOON + 5, out, 32), 0);
    str_of(&goto_def, out, "goto_speed", 0, s);
    ck_assert_str_eq(s, "2.29"); /* the seed command's 2.3 decodes as 2.29 */
    str_of(&goto_def, out, "goto_x", 0, s);
    ck_assert_str_eq(s, "351");
    str_of(&goto_def, out, "new_instructions", 0, s);
    ck_assert_str_eq(s, "make_toast");
    str_of(&goto_def, out, "type", 0, s);
    ck_assert_str_eq(s, "goto");
    str_of(&goto_def, out, "Destination", 0, s);
    ck_assert_str_eq(s, "3");
    str_of(&goto_def, out, "_time", 0, s);
    ck_assert_str_eq(s, "1699963200");
    /* SPECIAL_INSTRUCTIONS unset */
    kelp_dccl_val_clear(&v[goto_def.fields[12].slot]);
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, buf, sizeof buf, &n), 0);
    hex(buf, n, h);
    ck_assert_str_eq(h, "2000aa30023002c0093c00000000000000000000e6");
    /* measure only */
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, NULL, 0, &n), 0);
    ck_assert_uint_eq(n, 21);
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, buf, 20, &n), KELP_ERR_NOSPACE);
}
END_TEST

START_TEST(null_codes_and_ranges)
{
    kelp_dccl_val v[32], out[32];
    kelp_dccl_codec cx;
    uint8_t buf[64];
    char s[300];
    size_t n;
    build_goto();
    kelp_dccl_codec_init(&cx, 1, NULL, NULL);
    clear_all(v, 32);
    set(&goto_def, v, "goto_x", "10001");  /* out of range -> 0 */
    set(&goto_def, v, "goto_y", "pig");    /* not convertible -> 0 */
    set(&goto_def, v, "lights_on", "2");   /* not a bool -> 0 */
    set(&goto_def, v, "goto_speed", "3.01");
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, buf, sizeof buf, &n), 0);
    ck_assert_uint_eq(n, 6); /* every body byte zero: stripped */
    ck_assert_int_eq(kelp_dccl_decode(&cx, &goto_def, buf, n, NOON, out, 32), 0);
    str_of(&goto_def, out, "goto_x", 0, s);
    ck_assert_str_eq(s, "");
    ck_assert_int_eq(out[goto_def.fields[11].slot].kind, KELP_DCCL_V_EMPTY);
    /* header wraps modulo 2^width; -1 -> 31 */
    set(&goto_def, v, "_src_id", "37");
    set(&goto_def, v, "Destination", "-1");
    set(&goto_def, v, "goto_x", "1");
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_dccl_decode(&cx, &goto_def, buf, n, NOON, out, 32), 0);
    str_of(&goto_def, out, "_src_id", 0, s);
    ck_assert_str_eq(s, "5");
    str_of(&goto_def, out, "Destination", 0, s);
    ck_assert_str_eq(s, "31");
}
END_TEST

START_TEST(trailing_zero_header_quirk)
{
    /* an all-null body with dest 0: the decoder strips into the header */
    kelp_dccl_val v[32], out[32];
    kelp_dccl_codec cx;
    uint8_t buf[64];
    char h[100], s[300];
    size_t n;
    build_goto();
    kelp_dccl_codec_init(&cx, 1, NULL, NULL);
    clear_all(v, 32);
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, buf, sizeof buf, &n), 0);
    hex(buf, n, h);
    ck_assert_str_eq(h, "2000aa300200");
    ck_assert_int_eq(kelp_dccl_decode(&cx, &goto_def, buf, n, NOON, out, 32), 0);
    str_of(&goto_def, out, "_ccl_id", 0, s);
    ck_assert_str_eq(s, "0");
    str_of(&goto_def, out, "_id", 0, s);
    ck_assert_str_eq(s, "64");
}
END_TEST

START_TEST(string_high_byte_sign_extension)
{
    kelp_dccl_field f[9];
    kelp_dccl_msgdef d;
    kelp_dccl_val v[16];
    kelp_dccl_codec cx;
    uint8_t buf[64];
    char h[100];
    size_t n;
    memset(f, 0, sizeof f);
    memset(&d, 0, sizeof d);
    f[8] = (kelp_dccl_field){.name = "s", .type = KELP_DCCL_T_STRING, .array_length = 1, .max_length = 8};
    d.name = "S";
    d.id = 3;
    d.size = 32;
    d.n_fields = 9;
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, NULL), 0);
    kelp_dccl_codec_init(&cx, 0, NULL, NULL);
    clear_all(v, 16);
    kelp_dccl_val_set_str(&v[f[8].slot], "ab\xe9xyz");
    ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 16, NOON, buf, sizeof buf, &n), 0);
    hex(buf + 6, n - 6, h);
    ck_assert_str_eq(h, "ffffe978797a"); /* ff ff e9 78 79 7a 00 00, trailing zeros stripped */
}
END_TEST

static const char *const HEALTH[] = {"good", "low_battery", "abort"};

START_TEST(arrays_delta_hex_enum)
{
    kelp_dccl_field f[12];
    kelp_dccl_msgdef d;
    kelp_dccl_val v[32], out[32];
    kelp_dccl_codec cx;
    uint8_t buf[64];
    char s[300];
    size_t n;
    memset(f, 0, sizeof f);
    memset(&d, 0, sizeof d);
    f[8] = (kelp_dccl_field){.name = "i", .type = KELP_DCCL_T_INT, .array_length = 3, .min = -100, .max = 100,
                             .has_delta = true, .max_delta = 2};
    f[9] = (kelp_dccl_field){.name = "f", .type = KELP_DCCL_T_FLOAT, .array_length = 2, .min = -1000, .max = 100,
                             .precision = 3, .has_delta = true, .max_delta = -2};
    f[10] = (kelp_dccl_field){.name = "h", .type = KELP_DCCL_T_HEX, .array_length = 1, .num_bytes = 2};
    f[11] = (kelp_dccl_field){.name = "e", .type = KELP_DCCL_T_ENUM, .array_length = 1, .enum_values = HEALTH, .n_enum = 3};
    d.name = "A";
    d.id = 9;
    d.size = 64;
    d.n_fields = 12;
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, NULL), 0);
    ck_assert_uint_eq(f[8].bits, 8);
    ck_assert_uint_eq(f[8].delta_bits, 3);
    ck_assert_uint_eq(f[8].total_bits, 14);
    ck_assert(f[9].max_delta == 2);
    ck_assert_uint_eq(f[9].delta_bits, 12); /* ceil(log(4002)/log 2) */
    ck_assert_uint_eq(f[11].bits, 2);
    ck_assert_uint_eq(d.n_slots, 8 + 3 + 2 + 1 + 1);
    kelp_dccl_codec_init(&cx, 2, NULL, NULL);
    clear_all(v, 32);
    kelp_dccl_val_set_str(&v[f[8].slot + 0], "10");
    kelp_dccl_val_set_str(&v[f[8].slot + 1], "11");
    kelp_dccl_val_set_str(&v[f[8].slot + 2], "13"); /* delta 3 > max_delta 2 -> null */
    kelp_dccl_val_set_double(&v[f[9].slot + 0], -500.5, 15);
    kelp_dccl_val_set_double(&v[f[9].slot + 1], -499.0, 15);
    kelp_dccl_val_set_str(&v[f[10].slot], "BEeF");
    kelp_dccl_val_set_str(&v[f[11].slot], "abort");
    ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 32, NOON, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_dccl_decode(&cx, &d, buf, n, NOON, out, 32), 0);
    (void)kelp_dccl_val_to_str(&out[f[8].slot + 0], s, sizeof s, NULL);
    ck_assert_str_eq(s, "10");
    (void)kelp_dccl_val_to_str(&out[f[8].slot + 1], s, sizeof s, NULL);
    ck_assert_str_eq(s, "11");
    ck_assert_int_eq(out[f[8].slot + 2].kind, KELP_DCCL_V_EMPTY);
    (void)kelp_dccl_val_to_str(&out[f[9].slot + 0], s, sizeof s, NULL);
    ck_assert_str_eq(s, "-500.500");
    (void)kelp_dccl_val_to_str(&out[f[9].slot + 1], s, sizeof s, NULL);
    ck_assert_str_eq(s, "-499.000");
    (void)kelp_dccl_val_to_str(&out[f[10].slot], s, sizeof s, NULL);
    ck_assert_str_eq(s, "beef");
    (void)kelp_dccl_val_to_str(&out[f[11].slot], s, sizeof s, NULL);
    ck_assert_str_eq(s, "abort");
    /* hex errors */
    kelp_dccl_val_set_str(&v[f[10].slot], "bee");
    ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 32, NOON, buf, sizeof buf, &n), KELP_ERR_PARSE);
    ck_diag(&cx.diag, KELP_ERR_PARSE, "hex value too short");
    kelp_dccl_val_set_str(&v[f[10].slot], "beef0");
    ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 32, NOON, buf, sizeof buf, &n), KELP_ERR_PARSE);
    kelp_dccl_val_clear(&v[f[10].slot]);
    ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 32, NOON, buf, sizeof buf, &n), KELP_ERR_PARSE);
}
END_TEST

START_TEST(enum_out_of_range_is_an_error)
{
    kelp_dccl_field f[9];
    kelp_dccl_msgdef d;
    kelp_dccl_val out[16];
    kelp_dccl_codec cx;
    const uint8_t msg[] = {0x20, 0x04, 0x80, 0x00, 0x00, 0x00, 0x03}; /* id 9, enum code 3 of 2 values */
    memset(f, 0, sizeof f);
    memset(&d, 0, sizeof d);
    f[8] = (kelp_dccl_field){.name = "e", .type = KELP_DCCL_T_ENUM, .array_length = 1, .enum_values = HEALTH, .n_enum = 2};
    d.name = "E";
    d.id = 9;
    d.size = 8;
    d.n_fields = 9;
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, NULL), 0);
    kelp_dccl_codec_init(&cx, 0, NULL, NULL);
    ck_assert_int_eq(kelp_dccl_decode(&cx, &d, msg, sizeof msg, NOON, out, 16), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_dccl_decode(&cx, &d, msg, 0, NOON, out, 16), KELP_ERR_TRUNCATED);
}
END_TEST

START_TEST(chat_and_vehicle_status_vectors)
{
    kelp_dccl_field f[11];
    kelp_dccl_msgdef d;
    kelp_dccl_val v[16];
    kelp_dccl_codec cx;
    uint8_t buf[64];
    char h[100];
    size_t n;
    memset(f, 0, sizeof f);
    memset(&d, 0, sizeof d);
    f[8] = (kelp_dccl_field){.name = "message", .type = KELP_DCCL_T_STRING, .array_length = 1, .max_length = 26};
    d.name = "Chat";
    d.id = 1;
    d.size = 32;
    d.n_fields = 9;
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, NULL), 0);
    kelp_dccl_codec_init(&cx, 1, NULL, NULL);
    clear_all(v, 16);
    kelp_dccl_val_set_str(&v[f[8].slot], "hello");
    ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 16, NOON, buf, sizeof buf, &n), 0);
    hex(buf, n, h);
    ck_assert_str_eq(h, "2000aa30020068656c6c6f");
    kelp_dccl_val_set_str(&v[f[8].slot], "abcdefghijklmnopqrstuvwxyz0123"); /* 30 chars: 26 sent */
    ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 16, NOON, buf, sizeof buf, &n), 0);
    ck_assert_uint_eq(n, 32);
    ck_assert_int_eq(buf[31], 'z');

    memset(f, 0, sizeof f);
    memset(&d, 0, sizeof d);
    f[8] = (kelp_dccl_field){.name = "nav_x", .type = KELP_DCCL_T_FLOAT, .array_length = 1, .max = 1000, .precision = 1};
    f[9] = (kelp_dccl_field){.name = "nav_y", .type = KELP_DCCL_T_FLOAT, .array_length = 1, .max = 1000, .precision = 1};
    f[10] = (kelp_dccl_field){.name = "health", .type = KELP_DCCL_T_ENUM, .array_length = 1, .enum_values = HEALTH, .n_enum = 3};
    d.name = "VehicleStatus";
    d.id = 2;
    d.size = 32;
    d.n_fields = 11;
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, NULL), 0);
    ck_assert_uint_eq(d.body_bits, 30);
    clear_all(v, 16);
    kelp_dccl_val_set_double(&v[f[8].slot], 100, 15);
    kelp_dccl_val_set_double(&v[f[9].slot], 300, 15);
    kelp_dccl_val_set_str(&v[f[10].slot], "low_battery");
    ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 16, NOON, buf, sizeof buf, &n), 0);
    hex(buf + 6, n - 6, h);
    ck_assert_str_eq(h, "03e92ee6");
}
END_TEST

START_TEST(header_time_and_flags)
{
    kelp_dccl_header h;
    uint8_t head[6] = {0x20, 0x0a, 0x2a, 0x30, 0x04, 0x00};
    ck_assert(kelp_dccl_time_infer(43200, DAY0 + 43300) == DAY0 + 43200);
    ck_assert(kelp_dccl_time_infer(86000, DAY0 + 100) == DAY0 - 86400 + 86000);     /* across midnight */
    ck_assert(kelp_dccl_time_infer(100, DAY0 + 50000) == DAY0 - 86400 + 100);       /* > 12 h old: wrong day */
    ck_assert_int_eq(kelp_dccl_head_read(head, 6, NOON, &h), 0);
    ck_assert_uint_eq(h.id, 20);
    ck_assert_uint_eq(h.src, 2);
    ck_assert_uint_eq(h.dest, 0);
    ck_assert_uint_eq(h.time_of_day, 43200);
    kelp_dccl_head_set_flags(head, false, true);
    ck_assert_uint_eq(head[5], 0x04); /* "200a2a300404" with the broadcast flag */
    kelp_dccl_head_set_flags(head, true, false);
    ck_assert_uint_eq(head[5], 0x08);
    ck_assert_int_eq(kelp_dccl_head_read(head, 5, NOON, &h), KELP_ERR_TRUNCATED);
}
END_TEST

/* ------------------------------------------------------------------ format, sourcing, algorithms */
START_TEST(format_like_boost)
{
    char out[128];
    size_t n;
    const char *a[] = {"make_toast", "true", "1699963200"};
    ck_assert_int_eq(kelp_dccl_format("special_instructions=%1%,lights_on=%2%", a, 2, out, sizeof out, &n), 0);
    ck_assert_str_eq(out, "special_instructions=make_toast,lights_on=true");
    ck_assert_int_eq(kelp_dccl_format("T=%3$.01f|%1$.3s|%2$6s|%2$-6s|%%", a, 3, out, sizeof out, &n), 0);
    ck_assert_str_eq(out, "T=1699963200|mak|  true|true  |%");
    ck_assert_int_eq(kelp_dccl_format("%s-%c", a, 2, out, sizeof out, &n), 0);
    ck_assert_str_eq(out, "make_toast-t");
    ck_assert_int_eq(kelp_dccl_format("%1%", a, 2, out, sizeof out, &n), KELP_ERR_RANGE); /* too many args */
    ck_assert_int_eq(kelp_dccl_format("%1% %3%", a, 2, out, sizeof out, &n), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_dccl_format("%1% %s", a, 2, out, sizeof out, &n), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_dccl_format("constant", a, 0, out, sizeof out, &n), 0);
    ck_assert_str_eq(out, "constant");
}
END_TEST

START_TEST(val_from_string_cases)
{
    const char *v;
    size_t n;
    ck_assert(kelp_dccl_val_from_string("foo=1,bar={2,3,4,5},pig=3", "bar", &v, &n));
    ck_assert_int_eq(strncmp(v, "2,3,4,5", n), 0);
    ck_assert_uint_eq(n, 7);
    ck_assert(kelp_dccl_val_from_string("foo=1,bar={2,3,4,5},pig=3", "pig", &v, &n) && n == 1 && v[0] == '3');
    ck_assert(!kelp_dccl_val_from_string("foo=bar,x=1", "o", &v, &n)); /* "o=" inside foo= does not count */
    ck_assert(kelp_dccl_val_from_string("my_float=3.56", "my_float", &v, &n) && n == 4);
    ck_assert(!kelp_dccl_val_from_string("blah=3.56", "my_float", &v, &n));
}
END_TEST

START_TEST(sourcing_float_cases)
{
    /* seed 2.3.9: <float><name>my_float</name><moos_var>SOME_FLOAT_VARIABLE</moos_var> */
    kelp_dccl_field f[9];
    kelp_dccl_msgdef d;
    kelp_dccl_val v[16];
    kelp_dccl_codec cx;
    kelp_dccl_var var = {"SOME_FLOAT_VARIABLE", true, 3.56, NULL};
    uint8_t buf[64], expect[64];
    size_t n, en;
    const char *strs[] = {"my_float=3.56", "3.56"};
    unsigned i;
    memset(f, 0, sizeof f);
    memset(&d, 0, sizeof d);
    f[8] = (kelp_dccl_field){.name = "my_float", .type = KELP_DCCL_T_FLOAT, .array_length = 1, .max = 10,
                             .precision = 2, .src_var = "SOME_FLOAT_VARIABLE"};
    d.name = "F";
    d.id = 5;
    d.size = 16;
    d.n_fields = 9;
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, NULL), 0);
    kelp_dccl_codec_init(&cx, 1, NULL, NULL);
    clear_all(v, 16);
    ck_assert_int_eq(kelp_dccl_source(&d, &var, 1, 0, v, 16), 0);
    ck_assert_int_eq(v[f[8].slot].kind, KELP_DCCL_V_DOUBLE);
    ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 16, NOON, expect, sizeof expect, &en), 0);
    ck_assert_uint_eq(en, 8);
    for (i = 0; i < 2; i++) {
        kelp_dccl_var sv = {"SOME_FLOAT_VARIABLE", false, 0, strs[i]};
        clear_all(v, 16);
        ck_assert_int_eq(kelp_dccl_source(&d, &sv, 1, 0, v, 16), 0);
        ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 16, NOON, buf, sizeof buf, &n), 0);
        ck_assert_uint_eq(n, en);
        ck_assert_int_eq(memcmp(buf, expect, n), 0);
    }
    {
        kelp_dccl_var sv = {"SOME_FLOAT_VARIABLE", false, 0, "blah=3.56"};
        clear_all(v, 16);
        ck_assert_int_eq(kelp_dccl_source(&d, &sv, 1, 0, v, 16), 0);
        ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 16, NOON, buf, sizeof buf, &n), 0);
        ck_assert_uint_eq(n, 6); /* not a number: null code, body stripped */
    }
}
END_TEST

START_TEST(trigger_and_timer)
{
    kelp_dccl_timer t;
    kelp_dccl_var goto_cmd = {"OUTGOING_COMMAND", false, 0,
                              "Destination=3,CommandType=GoTo,goto_x=351,goto_y=294,lights_on=true,"
                              "special_instructions=make_toast,goto_speed=2.3"};
    kelp_dccl_var loiter = {"OUTGOING_COMMAND", false, 0, "Destination=3,CommandType=Loiter"};
    kelp_dccl_val v[32];
    char s[300];
    build_goto();
    goto_def.trigger = KELP_DCCL_TRIG_PUBLISH;
    goto_def.trigger_var = "OUTGOING_COMMAND";
    goto_def.trigger_mandatory = "CommandType=GoTo";
    ck_assert(kelp_dccl_is_trigger(&goto_def, &goto_cmd));
    ck_assert(!kelp_dccl_is_trigger(&goto_def, &loiter));
    clear_all(v, 32);
    ck_assert_int_eq(kelp_dccl_source(&goto_def, &goto_cmd, 1, 0, v, 32), 0);
    str_of(&goto_def, v, "Destination", 0, s);
    ck_assert_str_eq(s, "3");
    str_of(&goto_def, v, "goto_x", 0, s);
    ck_assert_str_eq(s, "351");
    /* default-named header fields read no variable: _id and _time are not taken from the
     * whole trigger string (that would make _id 0) */
    str_of(&goto_def, v, "_id", 0, s);
    ck_assert_str_eq(s, "");
    str_of(&goto_def, v, "_time", 0, s);
    ck_assert_str_eq(s, "");
    goto_def.trigger = KELP_DCCL_TRIG_TIME;
    goto_def.trigger_time = 30;
    kelp_dccl_timer_init(&t, 1000);
    ck_assert(!kelp_dccl_timer_due(&t, &goto_def, 1030));
    ck_assert(kelp_dccl_timer_due(&t, &goto_def, 1030.5));
    ck_assert(!kelp_dccl_timer_due(&t, &goto_def, 1059));
    ck_assert(kelp_dccl_timer_due(&t, &goto_def, 1061));
}
END_TEST

static void run_alg(const kelp_dccl_algs *algs, const char *name, kelp_dccl_val *v, const kelp_dccl_val *r0,
                    const kelp_dccl_val *r1)
{
    const kelp_dccl_alg_entry *a = kelp_dccl_algs_find(algs, name);
    const kelp_dccl_val *refs[2] = {r0, r1};
    ck_assert_ptr_nonnull(a);
    a->fn(v, refs, r1 ? 2 : (r0 ? 1 : 0), a->user);
}

static double alg_d(const kelp_dccl_algs *algs, const char *name, double in)
{
    kelp_dccl_val v;
    double d;
    kelp_dccl_val_set_double(&v, in, 15);
    run_alg(algs, name, &v, NULL, NULL);
    ck_assert(kelp_dccl_val_to_double(&v, &d));
    return d;
}

static const char *alg_s(const kelp_dccl_algs *algs, const char *name, const char *in, char *out)
{
    kelp_dccl_val v;
    kelp_dccl_val_set_str(&v, in);
    run_alg(algs, name, &v, NULL, NULL);
    (void)kelp_dccl_val_to_str(&v, out, 64, NULL);
    return out;
}

START_TEST(builtin_algorithms)
{
    kelp_dccl_alg_entry store[40];
    kelp_dccl_modem_entry modems[8];
    kelp_dccl_algs algs;
    kelp_dccl_builtin bi;
    kelp_dccl_val v, a, b;
    char s[64];
    const char lookup[] = "// modem id, vehicle name (should be community name), vehicle type\n"
                          "0, broadcast, broadcast\n1, endeavor, ship\n3, unicorn, auv\n4, macrura, auv\n";
    double lat, lon, north, east;
    kelp_dccl_algs_init(&algs, store, 40);
    kelp_dccl_builtin_init(&bi, modems, 8);
    ck_assert_int_eq(kelp_dccl_algs_add_builtin(&algs, &bi), 0);
    ck_assert_int_eq(kelp_dccl_builtin_parse_modems(&bi, lookup, sizeof lookup - 1), 0);
    ck_assert_uint_eq(bi.n_modems, 4);
    ck_assert(alg_d(&algs, "angle_0_360", -90) == 270);
    ck_assert(alg_d(&algs, "angle_0_360", 360) == 0);
    ck_assert(alg_d(&algs, "angle_0_360", 45) == 45);
    ck_assert(alg_d(&algs, "angle_-180_180", 180) == -180);
    ck_assert(alg_d(&algs, "angle_-180_180", 190) == -170);
    ck_assert(alg_d(&algs, "angle_-180_180", -180) == -180);
    ck_assert(fabs(alg_d(&algs, "power_to_dB", 100) - 20) < 1e-12);
    ck_assert(fabs(alg_d(&algs, "dB_to_power", 20) - 100) < 1e-9);
    ck_assert(alg_d(&algs, "abs", -3.5) == 3.5);
    ck_assert_str_eq(alg_s(&algs, "to_upper", "goto", s), "GOTO");
    ck_assert_str_eq(alg_s(&algs, "to_lower", "MM2", s), "mm2");
    ck_assert_str_eq(alg_s(&algs, "modem_id2name", "3", s), "unicorn");
    ck_assert_str_eq(alg_s(&algs, "modem_id2type", "1", s), "ship");
    ck_assert_str_eq(alg_s(&algs, "modem_id2name", "10", s), "10");
    ck_assert_str_eq(alg_s(&algs, "modem_id2type", "10", s), "unknown_type");
    ck_assert_str_eq(alg_s(&algs, "modem_id2name", "mm", s), "mm"); /* not numeric: unchanged */
    ck_assert_str_eq(alg_s(&algs, "name2modem_id", "Macrura", s), "4");
    ck_assert_str_eq(alg_s(&algs, "name2modem_id", "4", s), "4");
    ck_assert_str_eq(alg_s(&algs, "name2modem_id", "nobody", s), "-2147483648"); /* int(NaN) on x86-64 */
    ck_assert_str_eq(alg_s(&algs, "lat2hemisphere_initial", "-1", s), "S");
    ck_assert_str_eq(alg_s(&algs, "lon2hemisphere_initial", "10", s), "E");
    ck_assert_str_eq(alg_s(&algs, "lat2nmea_lat", "42.5", s), "4230.0000");
    ck_assert_str_eq(alg_s(&algs, "lon2nmea_lon", "7.25", s), "00715.0000");
    ck_assert_str_eq(alg_s(&algs, "unix_time2nmea_time", "1699963200.5", s), "120000.500000");
    /* add / subtract keep the value's precision */
    kelp_dccl_val_set_double(&v, 5, 2);
    kelp_dccl_val_set_double(&a, 3, 15);
    run_alg(&algs, "add", &v, &a, NULL);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "8.00");
    kelp_dccl_val_set_double(&v, 5, 2);
    run_alg(&algs, "subtract", &v, &a, NULL);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "2.00");
    /* Mackenzie, stored with precision 3, under both names */
    kelp_dccl_val_set_double(&v, 25, 15);
    kelp_dccl_val_set_double(&a, 35, 15);
    kelp_dccl_val_set_double(&b, 1000, 15);
    run_alg(&algs, "alg_TSD_to_soundspeed", &v, &a, &b);
    (void)kelp_dccl_val_to_str(&v, s, sizeof s, NULL);
    ck_assert_str_eq(s, "1550.744");
    kelp_dccl_val_set_double(&v, 25, 15);
    run_alg(&algs, "TSD_to_soundspeed", &v, &a, &b);
    ck_assert_int_eq(v.precision, 3);
    /* geodesy around LatOrigin 42.35 / LongOrigin -70.95 */
    kelp_dccl_builtin_set_origin(&bi, 42.35, -70.95);
    kelp_dccl_geo_latlon2local(&bi, 42.35, -70.95, &north, &east);
    ck_assert(fabs(north) < 1e-6 && fabs(east) < 1e-6);
    kelp_dccl_geo_local2latlon(&bi, 0, 0, &lat, &lon);
    ck_assert(fabs(lat - 42.35) < 1e-4 && fabs(lon + 70.95) < 1e-4);
    kelp_dccl_geo_latlon2local(&bi, 42.36, -70.94, &north, &east);
    ck_assert(north > 1085 && north < 1095); /* UTM zone 19 northing step (grid convergence) */
    ck_assert(east > 845 && east < 853);
    kelp_dccl_geo_local2latlon(&bi, east, north, &lat, &lon);
    ck_assert(fabs(lat - 42.36) < 2e-5 && fabs(lon + 70.94) < 2e-5);
}
END_TEST

static void twice(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    double d;
    (void)r; (void)nr; (void)u;
    if (kelp_dccl_val_to_double(v, &d)) kelp_dccl_val_set_double(v, 2 * d, v->precision);
}

START_TEST(user_algorithm_on_encode)
{
    kelp_dccl_alg_entry store[2];
    kelp_dccl_algs algs;
    kelp_dccl_algcall call = {"*2", 0, {0}};
    kelp_dccl_val v[32], out[32];
    kelp_dccl_codec cx;
    uint8_t buf[64];
    char s[300];
    size_t n;
    build_goto();
    goto_fields[9].algs = &call;
    goto_fields[9].n_algs = 1;
    kelp_dccl_algs_init(&algs, store, 2);
    ck_assert_int_eq(kelp_dccl_algs_add(&algs, "*2", twice, NULL), 0);
    ck_assert_int_eq(kelp_dccl_algs_add(&algs, "a", twice, NULL), 0);
    ck_assert_int_eq(kelp_dccl_algs_add(&algs, "b", twice, NULL), KELP_ERR_NOSPACE);
    kelp_dccl_codec_init(&cx, 1, NULL, &algs);
    clear_all(v, 32);
    set(&goto_def, v, "goto_x", "100.4"); /* pre-encode rounding to 100, then *2 */
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_dccl_decode(&cx, &goto_def, buf, n, NOON, out, 32), 0);
    str_of(&goto_def, out, "goto_x", 0, s);
    ck_assert_str_eq(s, "200");
}
END_TEST

START_TEST(finalize_rejects)
{
    kelp_dccl_field f[9];
    kelp_dccl_msgdef d;
    kelp_diag why = {0};
    memset(f, 0, sizeof f);
    memset(&d, 0, sizeof d);
    f[8] = (kelp_dccl_field){.name = "s", .type = KELP_DCCL_T_STRING, .array_length = 1, .max_length = 27};
    d.name = "X";
    d.size = 32;
    d.n_fields = 9;
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, &why), KELP_ERR_RANGE);
    ck_assert_int_eq(why.code, KELP_ERR_RANGE);
    ck_diag_has(&why, "will not fit");
    kelp_diag_clear(&why);
    f[8].max_length = 26;
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, &why), 0);
    d.size = 6;
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, &why), KELP_ERR_RANGE);
    d.size = 32;
    d.repeat = 2;
    f[8].array_length = 3;
    kelp_diag_clear(&why);
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, &why), KELP_ERR_RANGE);
    ck_diag_has(&why, "<repeat>");
}
END_TEST

/* ------------------------------------------------------------------ integers as wide as Goby's (to 64 bits) */
/* a message of the 8 header fields and one layout field */
static kelp_dccl_field one_fields[9];
static kelp_dccl_msgdef one_def;

static void build_one(kelp_dccl_field f)
{
    memset(one_fields, 0, sizeof one_fields);
    memset(&one_def, 0, sizeof one_def);
    one_fields[8] = f;
    one_def.name = "ONE";
    one_def.id = 9;
    one_def.size = 64;
    one_def.n_fields = 9;
    ck_assert_int_eq(kelp_dccl_def_finalize(&one_def, one_fields, NULL), 0);
}

/* plaintext encode then decode of `one` layout value; returns the decoded slot */
static const kelp_dccl_val *round_trip(const kelp_dccl_val *in, uint8_t *buf, size_t *n)
{
    static kelp_dccl_val v[16], out[16];
    kelp_dccl_codec cx;
    kelp_dccl_codec_init(&cx, 1, NULL, NULL);
    clear_all(v, 16);
    v[one_fields[8].slot] = *in;
    ck_assert_int_eq(kelp_dccl_encode(&cx, &one_def, v, 16, NOON, buf, 64, n), 0);
    ck_assert_int_eq(kelp_dccl_decode(&cx, &one_def, buf, *n, NOON, out, 16), 0);
    return &out[one_fields[8].slot];
}

START_TEST(width_quirks_past_32_bits)
{
    /* the double expression's extra bit where (max-min)+2 is exactly 2^31, 2^39, 2^47, 2^51 */
    static const struct { double range; unsigned bits; } W[] = {
        {2147483645.0, 31},     {2147483646.0, 32}, /* 2^31 */
        {4294967294.0, 32},     {4000000000.0, 32},     {8000000000.0, 33},    {10000000000.0, 34},
        {549755813885.0, 39},   {549755813886.0, 40},   /* 2^39 */
        {140737488355325.0, 47}, {140737488355326.0, 48}, /* 2^47 */
        {2e15, 51},             {2251799813685246.0, 52}, /* 2^51 */
        {562949953421311.0, 49}, /* 2^49 + 1: one bit too few */
        {9007199254740990.0, 53}, {9007199254740992.0, 53}, /* 2^53 + 2 rounds down too: one too few */
        {9.2e18, 63},           {1.8e19, 64},           {1.8446744073709550e19, 64},
    };
    for (size_t i = 0; i < sizeof W / sizeof W[0]; i++)
        ck_assert_msg(kelp_dccl_width(W[i].range, 0) == W[i].bits, "range %.17g: %u bits, expected %u", W[i].range,
                      kelp_dccl_width(W[i].range, 0), W[i].bits);
    /* float: the scaled range counts */
    ck_assert_uint_eq(kelp_dccl_width(2e9, 3), 41);
    ck_assert_uint_eq(kelp_dccl_width(2147483.646, 3), 32); /* 2^31 again, through pow10 */
}
END_TEST

/* min, max, mid and the neighbours of the bounds round-trip exactly; beyond them: null */
static const struct { double min, max; unsigned bits; } WIDE[] = {
    {0, 4000000000.0, 32},
    {-5e9, 5e9, 34},
    {-4000000000.0, 0, 32},
    {0, 2147483646.0, 32},        /* the 2^31 quirk: one spare bit */
    {-274877906943.0, 274877906943.0, 40}, /* 2^39 */
    {1e12, 1e15, 50},             /* a minimum far from zero */
    {-4503599627370000.0, 4503599627370000.0, 53}, /* about +-2^52 */
    {-9007199254740000.0, 0, 53}, /* about -2^53 .. 0 */
    {-4.6e18, 4.6e18, 63},
    {-9.2e18, 9.2e18, 64},        /* beyond 2^53 only min, max and mid are exact doubles apart */
};

START_TEST(wide_int_round_trips)
{
    uint8_t buf[64];
    size_t n;
    double mn = WIDE[_i].min, mx = WIDE[_i].max;
    build_one((kelp_dccl_field){.name = "i", .type = KELP_DCCL_T_INT, .array_length = 1, .min = mn, .max = mx});
    ck_assert_uint_eq(one_fields[8].bits, WIDE[_i].bits);
    double vals[] = {mn, mx, mn + (mx - mn) / 2, mn + 1, mx - 1, floor(mn + (mx - mn) / 3)};
    size_t nv = mx - mn <= 9007199254740992.0 ? sizeof vals / sizeof vals[0] : 3;
    for (size_t k = 0; k < nv; k++) {
        kelp_dccl_val in;
        const kelp_dccl_val *o;
        int64_t l = 0;
        kelp_dccl_val_set_long(&in, (int64_t)vals[k]);
        o = round_trip(&in, buf, &n);
        ck_assert_msg(kelp_dccl_val_to_long(o, &l) && l == (int64_t)vals[k], "[%.17g, %.17g]: %.17g decoded as %lld", mn,
                      mx, vals[k], (long long)l);
    }
    /* beyond the bounds: "not given", code 0, the body strips to nothing */
    {
        kelp_dccl_val in;
        kelp_dccl_val_set_double(&in, mx + fmax(1.0, mx * 1e-15), 15);
        ck_assert_int_eq(round_trip(&in, buf, &n)->kind, KELP_DCCL_V_EMPTY);
        ck_assert_uint_eq(n, 6);
        kelp_dccl_val_set_double(&in, mn - fmax(1.0, fabs(mn) * 1e-15), 15);
        ck_assert_int_eq(round_trip(&in, buf, &n)->kind, KELP_DCCL_V_EMPTY);
        ck_assert_uint_eq(n, 6);
    }
}
END_TEST

START_TEST(wide_int_wire_and_rounding)
{
    uint8_t buf[64];
    char h[200], s[300];
    size_t n;
    kelp_dccl_val in;
    build_one((kelp_dccl_field){.name = "i", .type = KELP_DCCL_T_INT, .array_length = 1, .min = -5e9, .max = 5e9});
    /* 34 bits right-aligned in 5 bytes: 6 padding bits then (v - min) + 1 */
    kelp_dccl_val_set_long(&in, 5000000000LL);
    (void)round_trip(&in, buf, &n);
    hex(buf + 6, n - 6, h);
    ck_assert_str_eq(h, "02540be401"); /* 10000000001 */
    kelp_dccl_val_set_long(&in, -5000000000LL);
    (void)round_trip(&in, buf, &n);
    hex(buf + 6, n - 6, h);
    ck_assert_str_eq(h, "0000000001");
    /* pre-encode rounds half to even on the floor, as Goby: x.5 goes to the even neighbour */
    kelp_dccl_val_set_str(&in, "4000000000.5");
    ck_assert_int_eq(kelp_dccl_val_to_str(round_trip(&in, buf, &n), s, sizeof s, NULL), true);
    ck_assert_str_eq(s, "4000000000");
    kelp_dccl_val_set_str(&in, "-3999999998.5");
    (void)kelp_dccl_val_to_str(round_trip(&in, buf, &n), s, sizeof s, NULL);
    ck_assert_str_eq(s, "-3999999998");
    kelp_dccl_val_set_str(&in, "3e9");
    (void)kelp_dccl_val_to_str(round_trip(&in, buf, &n), s, sizeof s, NULL);
    ck_assert_str_eq(s, "3000000000");
    /* 2^49 + 1 quirk: the field is one bit short, so its largest code (2^49) wraps to 0 = null */
    build_one((kelp_dccl_field){.name = "i", .type = KELP_DCCL_T_INT, .array_length = 1, .min = 0, .max = 562949953421311.0});
    ck_assert_uint_eq(one_fields[8].bits, 49);
    kelp_dccl_val_set_long(&in, 562949953421311LL);
    ck_assert_int_eq(round_trip(&in, buf, &n)->kind, KELP_DCCL_V_EMPTY);
    kelp_dccl_val_set_long(&in, 562949953421310LL);
    ck_assert_int_eq(kelp_dccl_val_to_str(round_trip(&in, buf, &n), s, sizeof s, NULL), true);
    ck_assert_str_eq(s, "562949953421310");
}
END_TEST

START_TEST(wide_float_and_delta)
{
    uint8_t buf[64];
    char s[300];
    size_t n;
    kelp_dccl_val in;
    /* float, precision 3, 41 bits: binary fractions survive the truncating scale */
    build_one((kelp_dccl_field){.name = "f", .type = KELP_DCCL_T_FLOAT, .array_length = 1, .min = -1e9, .max = 1e9,
                                .precision = 3});
    ck_assert_uint_eq(one_fields[8].bits, 41);
    static const char *const F[][2] = {
        {"-1000000000", "-1000000000.000"}, {"1000000000", "1000000000.000"}, {"123456789.125", "123456789.125"},
        {"-999999999.5", "-999999999.500"}, {"0.0625", "0.062"}, /* half to even */
    };
    for (size_t k = 0; k < sizeof F / sizeof F[0]; k++) {
        kelp_dccl_val_set_str(&in, F[k][0]);
        (void)kelp_dccl_val_to_str(round_trip(&in, buf, &n), s, sizeof s, NULL);
        ck_assert_msg(strcmp(s, F[k][1]) == 0, "%s decoded as %s, expected %s", F[k][0], s, F[k][1]);
    }
    /* a delta array of wide ints: key 33 bits, elements 2*max_delta+2 -> 33 bits */
    build_one((kelp_dccl_field){.name = "d", .type = KELP_DCCL_T_INT, .array_length = 3, .min = -4e9, .max = 4e9,
                                .has_delta = true, .max_delta = -3e9});
    ck_assert_uint_eq(one_fields[8].bits, 33);
    ck_assert_uint_eq(one_fields[8].delta_bits, 33);
    ck_assert_uint_eq(one_fields[8].total_bits, 99);
    {
        kelp_dccl_val v[16], out[16];
        kelp_dccl_codec cx;
        unsigned sl = one_fields[8].slot;
        int64_t l;
        kelp_dccl_codec_init(&cx, 1, NULL, NULL);
        clear_all(v, 16);
        kelp_dccl_val_set_long(&v[sl], -3999999999LL);
        kelp_dccl_val_set_long(&v[sl + 1], -999999999LL); /* key + 3e9 exactly */
        kelp_dccl_val_set_long(&v[sl + 2], -999999998LL); /* one beyond max_delta: null */
        ck_assert_int_eq(kelp_dccl_encode(&cx, &one_def, v, 16, NOON, buf, 64, &n), 0);
        ck_assert_int_eq(kelp_dccl_decode(&cx, &one_def, buf, n, NOON, out, 16), 0);
        ck_assert(kelp_dccl_val_to_long(&out[sl], &l) && l == -3999999999LL);
        ck_assert(kelp_dccl_val_to_long(&out[sl + 1], &l) && l == -999999999LL);
        ck_assert_int_eq(out[sl + 2].kind, KELP_DCCL_V_EMPTY);
    }
}
END_TEST

/* A <repeat> message publishes once per index: each publication takes the element at
 * that index, a single-valued (header) field repeats in every one. */
/* A stateful algorithm: appends how many times it has run ("#1", "#2", ...). */
static void counter(kelp_dccl_val *v, const kelp_dccl_val *const *r, size_t nr, void *u)
{
    unsigned *calls = u;
    char t[32];
    (void)r; (void)nr;
    ++*calls;
    t[0] = '#';
    t[1] = (char)('0' + (int)(*calls % 10u));
    t[2] = '\0';
    kelp_dccl_val_set_str(v, t);
}

/* The codec's workspace replaced the stack buffers: the message is built in the caller's
 * buffer (only cap bytes of it), arguments with algorithms run once each and in order however
 * often the format uses them, and the argument limits fail cleanly. */
START_TEST(workspace_in_caller_buffers)
{
    kelp_dccl_alg_entry store[1];
    kelp_dccl_algs algs;
    unsigned calls = 0;
    static const kelp_dccl_algcall cnt = {"count", 0, {0}};
    kelp_dccl_val v[32], out[32];
    kelp_dccl_codec cx;
    kelp_dccl_pub p[4];
    uint8_t full[64], tight[21];
    size_t n, n2, np, i;
    build_goto();
    kelp_dccl_codec_init(&cx, 1, NULL, NULL);
    clear_all(v, 32);
    set(&goto_def, v, "goto_x", "351");
    set(&goto_def, v, "goto_y", "294"); /* goto_speed (last) unset: trailing zero bytes */
    memset(full, 0xaa, sizeof full);
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, full, sizeof full, &n), 0);
    ck_assert_uint_lt(n, kelp_dccl_max_len(&goto_def));
    /* exactly the stripped length is enough, though the unstripped message is longer */
    memset(tight, 0x55, sizeof tight);
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, tight, n, &n2), 0);
    ck_assert_uint_eq(n2, n);
    ck_assert_int_eq(memcmp(tight, full, n), 0);
    ck_assert_uint_eq(tight[n], 0x55); /* nothing past cap */
    ck_assert_int_eq(kelp_dccl_encode(&cx, &goto_def, v, 32, NOON, tight, n - 1, &n2), KELP_ERR_NOSPACE);
    ck_assert_uint_eq(n2, n);
    ck_assert_int_eq(kelp_dccl_decode(&cx, &goto_def, full, n, NOON, out, 32), 0);

    /* publish: %2% (algorithm) used twice, %3% (algorithm) once, %1% plain */
    kelp_dccl_algs_init(&algs, store, 1);
    ck_assert_int_eq(kelp_dccl_algs_add(&algs, "count", counter, &calls), 0);
    kelp_dccl_codec_init(&cx, 1, NULL, &algs);
    {
        const kelp_dccl_pubarg args[] = {{9, NULL, 0}, {10, &cnt, 1}, {9, &cnt, 1}};
        const kelp_dccl_publish pub = {.var = "P", .format = "%2%,%1%,%2%,%3%,%2%", .args = args, .n_args = 3};
        goto_def.publishes = &pub;
        goto_def.n_publishes = 1;
        ck_assert_int_eq(kelp_dccl_publish_all(&cx, &goto_def, out, 32, p, 4, &np), 0);
        ck_assert_uint_eq(np, 1);
        ck_assert_str_eq(p[0].s, "#1,351,#1,#2,#1");
        ck_assert_uint_eq(calls, 2);
        ck_assert(!p[0].is_double);
        /* no room for the publication: the algorithms still ran (as before), NOSPACE */
        ck_assert_int_eq(kelp_dccl_publish_all(&cx, &goto_def, out, 32, p, 0, &np), KELP_ERR_NOSPACE);
        ck_assert_uint_eq(calls, 4);
    }
    {
        /* no room and a bad format: the format error wins, as it did */
        const kelp_dccl_pubarg args[] = {{9, NULL, 0}};
        const kelp_dccl_publish pub = {.var = "P", .format = "%1%,%2%", .args = args, .n_args = 1};
        goto_def.publishes = &pub;
        ck_assert_int_eq(kelp_dccl_publish_all(&cx, &goto_def, out, 32, p, 0, &np), KELP_ERR_PARSE);
        ck_assert_int_eq(kelp_dccl_publish_all(&cx, &goto_def, out, 32, p, 4, &np), KELP_ERR_PARSE);
    }
    {
        /* more arguments than KELP_DCCL_MAX_PUB_ARGS */
        static kelp_dccl_pubarg many[KELP_DCCL_MAX_PUB_ARGS + 1];
        const kelp_dccl_publish pub = {.var = "P", .format = "%1%", .args = many, .n_args = KELP_DCCL_MAX_PUB_ARGS + 1};
        for (i = 0; i < KELP_DCCL_MAX_PUB_ARGS + 1; i++) many[i] = (kelp_dccl_pubarg){9, NULL, 0};
        goto_def.publishes = &pub;
        ck_assert_int_eq(kelp_dccl_publish_all(&cx, &goto_def, out, 32, p, 4, &np), KELP_ERR_NOSPACE);
        ck_diag(&cx.diag, KELP_ERR_NOSPACE, "too many publish arguments");
    }
    goto_def.publishes = NULL;
    goto_def.n_publishes = 0;
}
END_TEST

START_TEST(repeat_publish_per_index)
{
    static kelp_dccl_field f[10];
    static kelp_dccl_msgdef d;
    static const kelp_dccl_pubarg args[] = {{KELP_DCCL_H_SRC, NULL, 0}, {8, NULL, 0}, {9, NULL, 0}};
    static const kelp_dccl_publish pubs[] = {
        {.var = "GEN", .format = "src=%1%,big=%2%,ok=%3%", .args = args, .n_args = 3},
        {.var = "FMT", .format = "%2% (%3%) from %1%", .args = args, .n_args = 3},
    };
    kelp_dccl_val v[64], out[64];
    kelp_dccl_pub p[16];
    kelp_dccl_codec cx;
    uint8_t buf[64];
    size_t n, np;
    memset(f, 0, sizeof f);
    f[KELP_DCCL_H_SRC].name = "src";
    f[8] = (kelp_dccl_field){.name = "big", .type = KELP_DCCL_T_INT, .array_length = 1, .min = -5e9, .max = 4e9};
    f[9] = (kelp_dccl_field){.name = "ok", .type = KELP_DCCL_T_BOOL, .array_length = 1};
    d = (kelp_dccl_msgdef){.name = "REP", .id = 6, .size = 32, .repeat = 3, .n_fields = 10, .publishes = pubs, .n_publishes = 2};
    ck_assert_int_eq(kelp_dccl_def_finalize(&d, f, NULL), 0);
    ck_assert_uint_eq(f[8].array_length, 3);
    kelp_dccl_codec_init(&cx, 4, NULL, NULL);
    clear_all(v, 64);
    kelp_dccl_val_set_long(&v[f[8].slot], -5000000000LL);
    kelp_dccl_val_set_long(&v[f[8].slot + 1], 4000000000LL);
    kelp_dccl_val_set_long(&v[f[8].slot + 2], 17);
    kelp_dccl_val_set_bool(&v[f[9].slot], true);
    kelp_dccl_val_set_bool(&v[f[9].slot + 2], false);
    ck_assert_int_eq(kelp_dccl_encode(&cx, &d, v, 64, NOON, buf, sizeof buf, &n), 0);
    ck_assert_int_eq(kelp_dccl_decode(&cx, &d, buf, n, NOON, out, 64), 0);
    ck_assert_int_eq(kelp_dccl_publish_all(&cx, &d, out, 64, p, 16, &np), 0);
    ck_assert_uint_eq(np, 6);
    ck_assert_uint_eq(kelp_dccl_n_publications(&d), 6);
    static const char *const want[] = {
        "src=4,big=-5000000000,ok=true", "src=4,big=4000000000,ok=", "src=4,big=17,ok=false",
        "-5000000000 (true) from 4",     "4000000000 () from 4",     "17 (false) from 4",
    };
    for (size_t i = 0; i < np; i++) ck_assert_str_eq(p[i].s, want[i]);
    /* a format with one placeholder per element is the wrong shape for a <repeat> message */
    static const kelp_dccl_publish bad = {.var = "BAD", .format = "%1%,%2%,%3%,%4%,%5%,%6%,%7%", .args = args, .n_args = 3};
    d.publishes = &bad;
    d.n_publishes = 1;
    ck_assert_int_eq(kelp_dccl_publish_all(&cx, &d, out, 64, p, 16, &np), KELP_ERR_PARSE);
}
END_TEST

Suite *kelp_dccl_suite(void)
{
    Suite *s = suite_create("dccl");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, width_expression);
    tcase_add_test(tc, unbiased_round_half_even);
    tcase_add_test(tc, parse_double_like_lexical_cast);
    tcase_add_test(tc, value_string_forms);
    tcase_add_test(tc, value_conversions);
    tcase_add_test(tc, goto_command_plain_vector);
    tcase_add_test(tc, null_codes_and_ranges);
    tcase_add_test(tc, trailing_zero_header_quirk);
    tcase_add_test(tc, string_high_byte_sign_extension);
    tcase_add_test(tc, arrays_delta_hex_enum);
    tcase_add_test(tc, enum_out_of_range_is_an_error);
    tcase_add_test(tc, chat_and_vehicle_status_vectors);
    tcase_add_test(tc, header_time_and_flags);
    tcase_add_test(tc, format_like_boost);
    tcase_add_test(tc, val_from_string_cases);
    tcase_add_test(tc, sourcing_float_cases);
    tcase_add_test(tc, trigger_and_timer);
    tcase_add_test(tc, builtin_algorithms);
    tcase_add_test(tc, user_algorithm_on_encode);
    tcase_add_test(tc, finalize_rejects);
    tcase_add_test(tc, width_quirks_past_32_bits);
    tcase_add_loop_test(tc, wide_int_round_trips, 0, (int)(sizeof WIDE / sizeof WIDE[0]));
    tcase_add_test(tc, wide_int_wire_and_rounding);
    tcase_add_test(tc, wide_float_and_delta);
    tcase_add_test(tc, repeat_publish_per_index);
    tcase_add_test(tc, workspace_in_caller_buffers);
    suite_add_tcase(s, tc);
    return s;
}
