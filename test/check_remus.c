/* REMUS CCL codec (pREMUSCodec core): hand-computed vectors for every field encoding, the State
 * layout, round trips and rejections. Expected codes are worked out from the WHOI helper
 * formulas documented in include/kelp/remus.h (e.g. lat code = round-half-away(deg*8388607/180)). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/nodereport.h>

#include <kelp/remus.h>

#define ULP_LL (180.0 / 8388607.0) /* one lat/lon code in degrees */

/* ------------------------------------------------------------------ lat/lon */

START_TEST(test_latlon_vectors)
{
    /* 0 -> 0 (the -0.5 branch truncates to 0) */
    ck_assert_int_eq(kelp_remus_latlon_encode(0.0), 0);
    ck_assert_int_eq(kelp_remus_latlon_encode(-0.0), 0);
    /* +-90: 4194303.5 +- 0.5 -> +-4194304 (0x400000 / 0xC00000) */
    ck_assert_int_eq(kelp_remus_latlon_encode(90.0), 4194304);
    ck_assert_int_eq(kelp_remus_latlon_encode(-90.0), -4194304);
    /* +-180: +-8388607 (0x7FFFFF / 0x800001), the extremes of the code */
    ck_assert_int_eq(kelp_remus_latlon_encode(180.0), 8388607);
    ck_assert_int_eq(kelp_remus_latlon_encode(-180.0), -8388607);
    /* 42.35 * 8388607/180 = 1973652.81 -> 1973653; -70.95 -> -3306509.26 -> -3306509 */
    ck_assert_int_eq(kelp_remus_latlon_encode(42.35), 1973653);
    ck_assert_int_eq(kelp_remus_latlon_encode(-70.95), -3306509);
    /* rounding edge: 1e-5 deg = 0.466 code -> 0; 1.1e-5 = 0.513 -> 1; same on the south/west side */
    ck_assert_int_eq(kelp_remus_latlon_encode(1e-5), 0);
    ck_assert_int_eq(kelp_remus_latlon_encode(1.1e-5), 1);
    ck_assert_int_eq(kelp_remus_latlon_encode(-1e-5), 0);
    ck_assert_int_eq(kelp_remus_latlon_encode(-1.1e-5), -1);
    /* just below a half code: (n + 0.5 - 1e-6) codes rounds down, (n + 0.5 + 1e-6) up */
    ck_assert_int_eq(kelp_remus_latlon_encode((1000.5 - 1e-6) * ULP_LL), 1000);
    ck_assert_int_eq(kelp_remus_latlon_encode((1000.5 + 1e-6) * ULP_LL), 1001);
    ck_assert_int_eq(kelp_remus_latlon_encode(-(1000.5 - 1e-6) * ULP_LL), -1000);
    ck_assert_int_eq(kelp_remus_latlon_encode(-(1000.5 + 1e-6) * ULP_LL), -1001);
    /* 181 deg: 8435210.87 -> 8435210 wraps in 24 bits to -8342006: 2^24 codes are 360.00004 deg,
     * so it decodes 2.37 codes west of -179 */
    ck_assert_int_eq(kelp_remus_latlon_encode(181.0), -8342006);
    ck_assert(fabs(kelp_remus_latlon_decode(-8342006) - (-179.0 - 2.37 * ULP_LL)) < 0.01 * ULP_LL);
    ck_assert_int_eq(kelp_remus_latlon_encode(NAN), 0);
    ck_assert_int_eq(kelp_remus_latlon_encode(INFINITY), 0);
    ck_assert_int_eq(kelp_remus_latlon_encode(-1e308), 0); /* overflows to -inf when scaled */
    /* 1e9 deg: trunc(46603372222222.2 + 0.5) mod 2^24, as a 24-bit signed code */
    ck_assert_int_eq(kelp_remus_latlon_encode(1e9), (int32_t)((46603372222222LL & 0xFFFFFF) >= 0x800000
                                                                ? (46603372222222LL & 0xFFFFFF) - 0x1000000
                                                                : (46603372222222LL & 0xFFFFFF)));
}
END_TEST

START_TEST(test_latlon_decode)
{
    ck_assert(kelp_remus_latlon_decode(0) == 0.0);
    ck_assert(fabs(kelp_remus_latlon_decode(8388607) - 180.0) < 1e-12);
    ck_assert(fabs(kelp_remus_latlon_decode(-8388607) + 180.0) < 1e-12);
    ck_assert(fabs(kelp_remus_latlon_decode(4194304) - 4194304.0 * 180.0 / 8388607.0) < 1e-12);
    ck_assert(fabs(kelp_remus_latlon_decode(-4194304) + 4194304.0 * 180.0 / 8388607.0) < 1e-12);
    /* within half a code of the input */
    ck_assert(fabs(kelp_remus_latlon_decode(1973653) - 42.35) <= ULP_LL / 2);
    ck_assert(fabs(kelp_remus_latlon_decode(-3306509) - -70.95) <= ULP_LL / 2);
    /* only the low 24 bits count: 0x00800000 as an unsigned pattern is -8388608 */
    ck_assert(fabs(kelp_remus_latlon_decode(0x800000) + 8388608.0 * ULP_LL) < 1e-9);
    /* Goby 1.x: the same for positive codes, two codes high for negative ones */
    ck_assert(kelp_remus_latlon_decode_goby1(1973653) == kelp_remus_latlon_decode(1973653));
    ck_assert(fabs(kelp_remus_latlon_decode_goby1(-3306509) - kelp_remus_latlon_decode(-3306507)) <
              1e-9);
    ck_assert(kelp_remus_latlon_decode_goby1(-3306509) > kelp_remus_latlon_decode(-3306509));
}
END_TEST

/* ------------------------------------------------------------------ heading */

START_TEST(test_heading)
{
    ck_assert_uint_eq(kelp_remus_heading_encode(0), 0);
    /* 45 * 255/360 = 31.875 (+0.5 -> 32) */
    ck_assert_uint_eq(kelp_remus_heading_encode(45), 32);
    /* code 1 starts at 0.70588 deg */
    ck_assert_uint_eq(kelp_remus_heading_encode(0.705), 0);
    ck_assert_uint_eq(kelp_remus_heading_encode(0.706), 1);
    /* 359.9 -> 254.93 + 0.5 -> 255; 360 wraps to 0; -90 is 270 -> 191.25 + .5 -> 191 */
    ck_assert_uint_eq(kelp_remus_heading_encode(359.9), 255);
    ck_assert_uint_eq(kelp_remus_heading_encode(360), 0);
    ck_assert_uint_eq(kelp_remus_heading_encode(-90), 191);
    ck_assert_uint_eq(kelp_remus_heading_encode(-1e-20), 0);
    ck_assert_uint_eq(kelp_remus_heading_encode(NAN), 0);
    ck_assert(fabs(kelp_remus_heading_decode(32) - 45.176470588235) < 1e-9);
    ck_assert(kelp_remus_heading_decode(255) == 360.0);
    ck_assert(kelp_remus_heading_decode(0) == 0.0);
}
END_TEST

/* ------------------------------------------------------------------ depth */

START_TEST(test_depth)
{
    ck_assert_uint_eq(kelp_remus_depth_encode(-1), 0);
    ck_assert_uint_eq(kelp_remus_depth_encode(0), 0);          /* 0.05/0.1 = 0.5 -> 0 */
    ck_assert_uint_eq(kelp_remus_depth_encode(0.04), 0);       /* 0.9 */
    ck_assert_uint_eq(kelp_remus_depth_encode(0.06), 1);       /* 1.1 */
    ck_assert_uint_eq(kelp_remus_depth_encode(12.3), 123);     /* 123.5 -> 123 */
    ck_assert_uint_eq(kelp_remus_depth_encode(99.99), 1000);   /* 1000.4 */
    ck_assert_uint_eq(kelp_remus_depth_encode(100), 1000);     /* (0+0.1)/0.2 + 1000 = 1000.5 */
    ck_assert_uint_eq(kelp_remus_depth_encode(111), 1055);     /* 11.1/0.2 = 55.5 */
    ck_assert_uint_eq(kelp_remus_depth_encode(150), 1250);
    ck_assert_uint_eq(kelp_remus_depth_encode(200), 1500);
    ck_assert_uint_eq(kelp_remus_depth_encode(200.3), 1501);   /* 0.55/0.5 = 1.1 */
    ck_assert_uint_eq(kelp_remus_depth_encode(999.9), 3100);
    ck_assert_uint_eq(kelp_remus_depth_encode(1000), 3100);    /* 0.5 + 3100 */
    ck_assert_uint_eq(kelp_remus_depth_encode(1000.6), 3101);
    ck_assert_uint_eq(kelp_remus_depth_encode(5999.4), 8099);
    ck_assert_uint_eq(kelp_remus_depth_encode(6000), 8100);
    ck_assert_uint_eq(kelp_remus_depth_encode(1e9), 8100);
    ck_assert_uint_eq(kelp_remus_depth_encode(NAN), 8100);

    ck_assert(kelp_remus_depth_decode(0) == 0.0);
    ck_assert(kelp_remus_depth_decode(123) == (double)12.3f); /* float, as Goby returns */
    ck_assert(kelp_remus_depth_decode(1000) == 100.0);
    ck_assert(kelp_remus_depth_decode(1055) == 111.0);
    ck_assert(kelp_remus_depth_decode(1500) == 200.0);
    ck_assert(kelp_remus_depth_decode(1501) == 200.5);
    ck_assert(kelp_remus_depth_decode(3100) == 1000.0);
    ck_assert(kelp_remus_depth_decode(8100) == 6000.0);
    ck_assert(kelp_remus_depth_decode(8101) == 6000.0);
    ck_assert(kelp_remus_depth_decode(8191) == 6000.0);
    /* the mission-mode bits above bit 12 are ignored */
    ck_assert(kelp_remus_depth_decode((uint16_t)(0xC000 | 1055)) == 111.0);
}
END_TEST

/* ------------------------------------------------------------------ velocity, speed, watts, fix age */

START_TEST(test_velocity_speed_watts_fixage)
{
    ck_assert_int_eq(kelp_remus_velocity_encode(1.2), 30);    /* 1.2f*25 = 30.0000012 */
    ck_assert_int_eq(kelp_remus_velocity_encode(1.19), 29);   /* 29.75 truncates */
    ck_assert_int_eq(kelp_remus_velocity_encode(-1.19), -29); /* toward zero */
    ck_assert_int_eq(kelp_remus_velocity_encode(0), 0);
    ck_assert_int_eq(kelp_remus_velocity_encode(6), 127);     /* 150 clamps */
    ck_assert_int_eq(kelp_remus_velocity_encode(-6), -128);
    ck_assert_int_eq(kelp_remus_velocity_encode(NAN), 0);
    ck_assert(kelp_remus_velocity_decode(30) == (double)1.2f);
    ck_assert(kelp_remus_velocity_decode(-128) == (double)-5.12f);
    ck_assert(kelp_remus_velocity_decode(127) == (double)5.08f);

    ck_assert_int_eq(kelp_remus_speed_encode(1.0), 30);
    ck_assert_int_eq(kelp_remus_speed_encode(1.05), 31);      /* 31.5 */
    ck_assert_int_eq(kelp_remus_speed_encode(5), 127);
    ck_assert_int_eq(kelp_remus_speed_encode(-5), -127);
    ck_assert(kelp_remus_speed_decode(30) == 1.0);
    ck_assert(kelp_remus_speed_decode(-127) == (double)(float)(-127 / 30.0));

    ck_assert_uint_eq(kelp_remus_watts_encode(100), 25);
    ck_assert_uint_eq(kelp_remus_watts_encode(3), 0);         /* 0.75 */
    ck_assert_uint_eq(kelp_remus_watts_encode(7.99), 1);
    ck_assert_uint_eq(kelp_remus_watts_encode(1020), 255);
    ck_assert_uint_eq(kelp_remus_watts_encode(1100), 255);
    ck_assert_uint_eq(kelp_remus_watts_encode(-5), 0);
    ck_assert_uint_eq(kelp_remus_watts_encode(NAN), 0);
    ck_assert(kelp_remus_watts_decode(25) == 100.0);
    ck_assert(kelp_remus_watts_decode(255) == 1020.0);

    ck_assert_uint_eq(kelp_remus_fix_age_encode(0), 0);
    ck_assert_uint_eq(kelp_remus_fix_age_encode(7), 1);
    ck_assert_uint_eq(kelp_remus_fix_age_encode(8), 2);
    ck_assert_uint_eq(kelp_remus_fix_age_encode(1019), 254);
    ck_assert_uint_eq(kelp_remus_fix_age_encode(2000), 255);
    ck_assert_uint_eq(kelp_remus_fix_age_encode(-3), 0);
    ck_assert_uint_eq(kelp_remus_fix_age_decode(2), 8);
}
END_TEST

/* ------------------------------------------------------------------ gfi / pitch / oil */

START_TEST(test_gfi_pitch_oil)
{
    /* gfi 100 -> 31 (bits 0-4), oil 100 -> 31 (bits 5-9), pitch 0 */
    ck_assert_uint_eq(kelp_remus_gfi_pitch_oil_encode(100, 0, 100), 0x03FF);
    /* 50 % -> 15.5 -> 15 each; pitch 10 * 63/180 = 3.5 (+0.5) -> 4 -> 0x1000 */
    ck_assert_uint_eq(kelp_remus_gfi_pitch_oil_encode(50, 10, 50), 0x11EF);
    /* pitch -10 -> -4 -> 6-bit 0x3C << 10 = 0xF000 */
    ck_assert_uint_eq(kelp_remus_gfi_pitch_oil_encode(50, -10, 50), 0xF1EF);
    /* clamps: gfi/oil to 0..100, pitch to +-90; +90 saturates at +31, -90 is -32 */
    ck_assert_uint_eq(kelp_remus_gfi_pitch_oil_encode(-5, 90, 150), 0x7C00 | (31u << 5));
    ck_assert_uint_eq(kelp_remus_gfi_pitch_oil_encode(0, 100, 0), 0x7C00);
    ck_assert_uint_eq(kelp_remus_gfi_pitch_oil_encode(0, -90, 0), 0x8000);
    /* pitch rounding edge: 1.428 deg = 0.4998 code -> +0.5 -> 0; 1.43 -> 1 */
    ck_assert_uint_eq(kelp_remus_gfi_pitch_oil_encode(0, 1.428, 0), 0);
    ck_assert_uint_eq(kelp_remus_gfi_pitch_oil_encode(0, 1.43, 0), 0x0400);
    ck_assert_uint_eq(kelp_remus_gfi_pitch_oil_encode(0, -1.43, 0), 0xFC00);
    ck_assert_uint_eq(kelp_remus_gfi_pitch_oil_encode(NAN, NAN, NAN), 0);

    double g, p, o;
    kelp_remus_gfi_pitch_oil_decode(0x11EF, &g, &p, &o);
    ck_assert(g == 48.0); /* 48.39 truncated to whole percent */
    ck_assert(o == (double)(float)(15 * 100.0 / 31.0));
    ck_assert(p == (double)(float)(4 * 180.0 / 63.0));
    kelp_remus_gfi_pitch_oil_decode(0x8000, &g, &p, &o);
    ck_assert(g == 0.0 && o == 0.0);
    ck_assert(p == (double)(float)(-32 * 180.0 / 63.0));
    kelp_remus_gfi_pitch_oil_decode(0xFC00, &g, &p, &o);
    ck_assert(p == (double)(float)(-180.0 / 63.0));
    kelp_remus_gfi_pitch_oil_decode(0x03FF, &g, &p, &o);
    ck_assert(g == 100.0 && o == 100.0 && p == 0.0);
}
END_TEST

/* ------------------------------------------------------------------ time / date */

START_TEST(test_time_date)
{
    /* 2024-01-02 12:00:00 UTC: hour 12 << 10 | day 2 << 15 | month 1 << 20 */
    ck_assert_uint_eq(kelp_remus_time_date_encode(1704196800), 0x113000);
    /* 2011-03-03 22:38:13: 13 s -> 3, 38 << 4, 22 << 10, 3 << 15, 3 << 20 */
    ck_assert_uint_eq(kelp_remus_time_date_encode(1299191893), 0x31DA63);
    /* 2023-12-31 23:59:59: 14 | 59 << 4 | 23 << 10 | 31 << 15 | 12 << 20 */
    ck_assert_uint_eq(kelp_remus_time_date_encode(1704067199), 0xCFDFBE);
    /* 1969-12-31 23:59:59 (negative UNIX time) */
    ck_assert_uint_eq(kelp_remus_time_date_encode(-1), 0xCFDFBE);

    kelp_remus_time t;
    kelp_remus_time_date_decode(0x31DA63, &t);
    ck_assert_uint_eq(t.month, 3);
    ck_assert_uint_eq(t.day, 3);
    ck_assert_uint_eq(t.hour, 22);
    ck_assert_uint_eq(t.minute, 38);
    ck_assert_uint_eq(t.second, 12);

    int64_t u = 0;
    ck_assert_int_eq(kelp_remus_time_date_to_unix(0x31DA63, 2011, &u), 0);
    ck_assert_int_eq(u, 1299191892); /* seconds floored to a multiple of 4 */
    ck_assert_int_eq(kelp_remus_time_date_to_unix(0x113000, 2024, &u), 0);
    ck_assert_int_eq(u, 1704196800);
    /* month 0, month 13, day 0, Feb 30, hour 24, minute 60, second 60 are refused */
    ck_assert_int_eq(kelp_remus_time_date_to_unix(0x013000, 2024, &u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_remus_time_date_to_unix((13u << 20) | (1u << 15), 2024, &u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_remus_time_date_to_unix(1u << 20, 2024, &u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_remus_time_date_to_unix((2u << 20) | (30u << 15), 2024, &u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_remus_time_date_to_unix((1u << 20) | (1u << 15) | (24u << 10), 2024, &u),
                     KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_remus_time_date_to_unix((1u << 20) | (1u << 15) | (60u << 4), 2024, &u),
                     KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_remus_time_date_to_unix((1u << 20) | (1u << 15) | 15u, 2024, &u), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_remus_time_date_to_unix((1u << 20) | (1u << 15) | 14u, 2024, &u), 0);
    ck_assert_int_eq(u, 1704067200 + 56);
    /* Feb 29 exists in 2024, not in 2023 */
    ck_assert_int_eq(kelp_remus_time_date_to_unix((2u << 20) | (29u << 15), 2024, &u), 0);
    ck_assert_int_eq(kelp_remus_time_date_to_unix((2u << 20) | (29u << 15), 2023, &u), KELP_ERR_RANGE);
}
END_TEST

/* ------------------------------------------------------------------ State message */

static const uint8_t STATE_VEC[32] = {
    0x0E,             /* id 14 */
    0x95, 0x1D, 0x1E, /* lat 1973653 (42.35) */
    0xF3, 0x8B, 0xCD, /* lon -3306509 (-70.95) */
    0x02,             /* fix age 2 (8 s) */
    0x63, 0xDA, 0x31, /* 2011-03-03 22:38:12 */
    0x20,             /* heading 32 */
    0x1F, 0xC4,       /* mode 6 (NORMAL) << 13 | depth 1055 = 0xC41F */
    0x04, 0x03, 0x02, 0x01, /* faults 0x01020304 */
    0xA5,             /* faults_2 */
    0x07,             /* mission leg */
    0xE2,             /* est_velocity -30 */
    0x09,             /* objective index */
    0x19,             /* watts 25 (100 W) */
    0x00, 0x00, 0x40, /* lat goal 4194304 */
    0x01, 0x00, 0x80, /* lon goal -8388607 */
    0x55,             /* battery 85 % */
    0xEF, 0x11,       /* gfi/pitch/oil 0x11EF */
};

static kelp_remus_state state_vec_struct(void)
{
    kelp_remus_state s;
    memset(&s, 0, sizeof s);
    s.lat = 1973653;
    s.lon = -3306509;
    s.fix_age = 2;
    s.time_date = 0x31DA63;
    s.heading = 32;
    s.mission_mode = KELP_REMUS_MODE_NORMAL;
    s.depth = 1055;
    s.faults = 0x01020304u;
    s.faults_2 = 0xA5;
    s.mission_leg = 7;
    s.est_velocity = -30;
    s.objective_index = 9;
    s.watts = 25;
    s.lat_goal = 4194304;
    s.lon_goal = -8388607;
    s.battery_percent = 85;
    s.gfi_pitch_oil = 0x11EF;
    return s;
}

START_TEST(test_state_encode_vector)
{
    kelp_remus_state s = state_vec_struct();
    uint8_t buf[40];
    size_t len = 0;
    memset(buf, 0xAA, sizeof buf);
    ck_assert_int_eq(kelp_remus_state_encode(&s, buf, sizeof buf, &len), 0);
    ck_assert_uint_eq(len, 32);
    for (int i = 0; i < 32; i++) ck_assert_msg(buf[i] == STATE_VEC[i], "byte %d: %02x", i, buf[i]);
    ck_assert_uint_eq(buf[32], 0xAA); /* nothing past the frame */
}
END_TEST

START_TEST(test_state_decode_vector)
{
    kelp_remus_state s, want = state_vec_struct();
    memset(&s, 0x5A, sizeof s);
    ck_assert_int_eq(kelp_remus_state_decode(STATE_VEC, sizeof STATE_VEC, &s), 0);
    ck_assert_int_eq(s.lat, want.lat);
    ck_assert_int_eq(s.lon, want.lon);
    ck_assert_uint_eq(s.fix_age, want.fix_age);
    ck_assert_uint_eq(s.time_date, want.time_date);
    ck_assert_uint_eq(s.heading, want.heading);
    ck_assert_uint_eq(s.mission_mode, want.mission_mode);
    ck_assert_uint_eq(s.depth, want.depth);
    ck_assert_uint_eq(s.faults, want.faults);
    ck_assert_uint_eq(s.faults_2, want.faults_2);
    ck_assert_uint_eq(s.mission_leg, want.mission_leg);
    ck_assert_int_eq(s.est_velocity, want.est_velocity);
    ck_assert_uint_eq(s.objective_index, want.objective_index);
    ck_assert_uint_eq(s.watts, want.watts);
    ck_assert_int_eq(s.lat_goal, want.lat_goal);
    ck_assert_int_eq(s.lon_goal, want.lon_goal);
    ck_assert_uint_eq(s.battery_percent, want.battery_percent);
    ck_assert_uint_eq(s.gfi_pitch_oil, want.gfi_pitch_oil);
    /* and the physical values of the vector */
    ck_assert(fabs(kelp_remus_latlon_decode(s.lat) - 42.35) <= ULP_LL / 2);
    ck_assert(fabs(kelp_remus_latlon_decode(s.lon) + 70.95) <= ULP_LL / 2);
    ck_assert(kelp_remus_depth_decode(s.depth) == 111.0);
    ck_assert(kelp_remus_velocity_decode(s.est_velocity) == (double)-1.2f);
}
END_TEST

START_TEST(test_state_round_trip_all_bytes)
{
    /* every byte pattern after the id decodes and re-encodes to itself */
    uint8_t in[32], out[32];
    for (int v = 0; v < 256; v++) {
        in[0] = 14;
        for (int i = 1; i < 32; i++) in[i] = (uint8_t)(v * 31 + i * 17);
        kelp_remus_state s;
        size_t len = 0;
        ck_assert_int_eq(kelp_remus_state_decode(in, 32, &s), 0);
        ck_assert_int_eq(kelp_remus_state_encode(&s, out, sizeof out, &len), 0);
        ck_assert_int_eq(memcmp(in, out, 32), 0);
    }
}
END_TEST

START_TEST(test_state_from_nav)
{
    /* the ccl_and_dccl mm2 values: heading 45, speed 1.2, depth 111 (+ a position and a time) */
    kelp_remus_state s;
    memset(&s, 0x77, sizeof s);
    kelp_remus_state_from_nav(&s, 42.35, -70.95, 1299191893, 45, 111, 1.2);
    uint8_t buf[32];
    size_t len;
    ck_assert_int_eq(kelp_remus_state_encode(&s, buf, sizeof buf, &len), 0);
    static const uint8_t want[32] = {0x0E, 0x95, 0x1D, 0x1E, 0xF3, 0x8B, 0xCD, 0x00, 0x63, 0xDA, 0x31,
                                     0x20, 0x1F, 0x04, 0,    0,    0,    0,    0,    0,    0x1E, 0,
                                     0,    0,    0,    0,    0,    0,    0,    0,    0,    0};
    for (int i = 0; i < 32; i++) ck_assert_msg(buf[i] == want[i], "byte %d: %02x", i, buf[i]);
}
END_TEST

START_TEST(test_state_rejections)
{
    kelp_remus_state s;
    uint8_t frame[33];
    memcpy(frame, STATE_VEC, 32);
    frame[32] = 0;
    ck_assert_int_eq(kelp_remus_state_decode(frame, 31, &s), KELP_ERR_TRUNCATED);
    ck_assert_int_eq(kelp_remus_state_decode(frame, 0, &s), KELP_ERR_TRUNCATED);
    ck_assert_int_eq(kelp_remus_state_decode(frame, 33, &s), KELP_ERR_RANGE);
    ck_assert_int_eq(kelp_remus_state_decode(NULL, 32, &s), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_remus_state_decode(frame, 32, NULL), KELP_ERR_ARG);
    frame[0] = KELP_REMUS_ID_RANGER;
    ck_assert_int_eq(kelp_remus_state_decode(frame, 32, &s), KELP_ERR_PARSE);
    frame[0] = 0x20; /* a DCCL frame */
    ck_assert_int_eq(kelp_remus_state_decode(frame, 32, &s), KELP_ERR_PARSE);

    uint8_t out[32];
    size_t len = 99;
    kelp_remus_state ok = state_vec_struct(), bad;
    ck_assert_int_eq(kelp_remus_state_encode(&ok, out, 31, &len), KELP_ERR_NOSPACE);
    ck_assert_uint_eq(len, 99);
    ck_assert_int_eq(kelp_remus_state_encode(NULL, out, 32, &len), KELP_ERR_ARG);
    ck_assert_int_eq(kelp_remus_state_encode(&ok, NULL, 32, &len), KELP_ERR_ARG);
    bad = ok, bad.lat = 0x800000;
    ck_assert_int_eq(kelp_remus_state_encode(&bad, out, 32, &len), KELP_ERR_RANGE);
    bad = ok, bad.lon_goal = -0x800001;
    ck_assert_int_eq(kelp_remus_state_encode(&bad, out, 32, &len), KELP_ERR_RANGE);
    bad = ok, bad.lat_goal = -0x800000; /* the most negative code fits */
    ck_assert_int_eq(kelp_remus_state_encode(&bad, out, 32, &len), 0);
    bad = ok, bad.depth = 0x2000;
    ck_assert_int_eq(kelp_remus_state_encode(&bad, out, 32, &len), KELP_ERR_RANGE);
    bad = ok, bad.mission_mode = 8;
    ck_assert_int_eq(kelp_remus_state_encode(&bad, out, 32, &len), KELP_ERR_RANGE);
    bad = ok, bad.time_date = 0x1000000;
    ck_assert_int_eq(kelp_remus_state_encode(&bad, out, 32, &len), KELP_ERR_RANGE);
}
END_TEST

/* ------------------------------------------------------------------ identification, Ranger */

START_TEST(test_identify)
{
    uint8_t f[32] = {0};
    ck_assert_int_eq(kelp_remus_identify(f, 0), KELP_REMUS_UNKNOWN);
    ck_assert_int_eq(kelp_remus_identify(NULL, 32), KELP_REMUS_UNKNOWN);
    f[0] = 14;
    ck_assert_int_eq(kelp_remus_identify(f, 32), KELP_REMUS_STATE);
    f[0] = 16;
    ck_assert_int_eq(kelp_remus_identify(f, 32), KELP_REMUS_RANGER);
    f[0] = 7;
    ck_assert_int_eq(kelp_remus_identify(f, 1), KELP_REMUS_REDIRECT);
    f[0] = 8;
    ck_assert_int_eq(kelp_remus_identify(f, 32), KELP_REMUS_POSITION);
    f[0] = 31;
    ck_assert_int_eq(kelp_remus_identify(f, 32), KELP_REMUS_OASIS);
    f[0] = 0x20;
    ck_assert_int_eq(kelp_remus_identify(f, 32), KELP_REMUS_UNKNOWN);
    f[0] = 15;
    ck_assert_int_eq(kelp_remus_identify(f, 32), KELP_REMUS_UNKNOWN);
}
END_TEST

START_TEST(test_ranger)
{
    uint8_t f[32] = {0};
    f[0] = 16;
    /* 42 deg 21.0000 min N: digits 0 4 | 2, sign nibble 0 | 2 1 | 0 0 | 0 0 */
    f[1] = 0x04, f[2] = 0x20, f[3] = 0x21;
    /* 070 deg 57.0000 min W: sign nibble D */
    f[6] = 0x07, f[7] = 0x0D, f[8] = 0x57;
    f[18] = 0x12;             /* speed 12 * 0.1 */
    f[19] = 0x04, f[20] = 0x50; /* heading 0450 * 0.1 */
    f[28] = 0x01, f[23] = 0x11; /* depth 0111 */
    kelp_remus_ranger r;
    ck_assert_int_eq(kelp_remus_ranger_decode(f, 32, &r), 0);
    ck_assert(fabs(r.lat - 42.35) < 1e-12);
    ck_assert(fabs(r.lon + 70.95) < 1e-12);
    ck_assert(fabs(r.speed - 1.2) < 1e-12);
    ck_assert(fabs(r.heading - 45.0) < 1e-12);
    ck_assert(r.depth == 111.0);
    /* sign nibble C is negative too; minutes to 1e-4 */
    f[2] = 0x2C, f[4] = 0x12, f[5] = 0x34; /* 42 deg 21.1234 min S */
    ck_assert_int_eq(kelp_remus_ranger_decode(f, 32, &r), 0);
    ck_assert(fabs(r.lat + (42.0 + 21.1234 / 60.0)) < 1e-12);
    ck_assert_int_eq(kelp_remus_ranger_decode(f, 31, &r), KELP_ERR_TRUNCATED);
    ck_assert_int_eq(kelp_remus_ranger_decode(f, 33, &r), KELP_ERR_RANGE);
    f[0] = 14;
    ck_assert_int_eq(kelp_remus_ranger_decode(f, 32, &r), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_remus_ranger_decode(f, 32, NULL), KELP_ERR_ARG);
}
END_TEST

/* ------------------------------------------------------------------ the pREMUSCodec tool */

typedef struct rec {
    int n;
    char var[64][64];
    char sval[64][1024];
    double dval[64];
    bool is_string[64];
    int warns;
} rec;

static void rec_pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    if (r->n >= 64) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    snprintf(r->sval[r->n], sizeof r->sval[0], "%s", is_string && sval ? sval : "");
    r->dval[r->n] = dval;
    r->is_string[r->n] = is_string;
    r->n++;
}

static void rec_warn(void *ctx, const char *msg)
{
    (void)msg;
    ((rec *)ctx)->warns++;
}

static int find(const rec *r, const char *var)
{
    for (int i = 0; i < r->n; i++)
        if (strcmp(r->var[i], var) == 0) return i;
    return -1;
}

static kelp_dccl_modem_entry modems[8];
static kelp_dccl_builtin geo;

static void tool_setup(kelp_remus_codec *t, bool create)
{
    kelp_dccl_builtin_init(&geo, modems, 8);
    static const char lk[] = "1,mm1,topside\n2,mm2,auv\n";
    ck_assert_int_eq(kelp_dccl_builtin_parse_modems(&geo, lk, sizeof lk - 1), 0);
    kelp_dccl_builtin_set_origin(&geo, 42.35, -70.95);
    kelp_remus_codec_cfg c;
    kelp_remus_codec_cfg_default(&c);
    ck_assert_str_eq(c.in_var[KELP_REMUS_STATE_VAR], "IN_REMUS_STATUS_HEX_30B");
    ck_assert_str_eq(c.out_var[KELP_REMUS_STATE_VAR], "OUT_REMUS_STATUS_HEX_30B");
    ck_assert_str_eq(c.in_var[KELP_REMUS_ALERT2_VAR], "IN_REMUS_ALERT2_HEX_30B");
    ck_assert_str_eq(c.out_var[KELP_REMUS_REDIRECT_VAR], "OUT_REMUS_REDIRECT_HEX_30B");
    ck_assert(!c.create_status);
    snprintf(c.in_var[KELP_REMUS_STATE_VAR], KELP_MAX_NAME, "IN_REMUS_STATUS");
    snprintf(c.out_var[KELP_REMUS_STATE_VAR], KELP_MAX_NAME, "OUT_REMUS_STATUS");
    c.create_status = create;
    c.geo = &geo;
    ck_assert_int_eq(kelp_remus_codec_init(t, &c), 0);
}

START_TEST(test_tool_create_status)
{
    kelp_remus_codec t;
    tool_setup(&t, true);
    rec r = {0};
    kelp_field_sink sink = {&r, rec_pub, rec_warn};
    const double now = 1299191893.5; /* 2011-03-03 22:38:13.5 */
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "MODEM_ID", false, NULL, 2, now, &sink), 1);
    const char *nav[] = {"NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"};
    const double val[] = {0, 0, 45, 1.2};
    for (int i = 0; i < 4; i++) ck_assert_int_eq(kelp_remus_codec_mail(&t, nav[i], false, NULL, val[i], now, &sink), 1);
    /* no State before every NAV_* has arrived */
    ck_assert_int_eq(kelp_remus_codec_iterate(&t, now, &sink), 0);
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "nav_depth", false, NULL, 111, now, &sink), 1);
    ck_assert_int_eq(kelp_remus_codec_iterate(&t, now, &sink), 1);
    ck_assert_int_eq(r.n, 1);
    ck_assert_str_eq(r.var[0], "OUT_REMUS_STATUS");
    /* at the datum: lat 42.35 (95 1D 1E), lon -70.95 (F3 8B CD); time 22:38:12 (63 DA 31);
     * heading 32 (040), depth 1055 (037 004), velocity 30 (036) */
    ck_assert_str_eq(r.sval[0], "base { src: 2 dest: 0 } data: "
                                "\"\\016\\225\\035\\036\\363\\213\\315\\000c\\3321 \\037\\004\\000\\000\\000\\000\\000"
                                "\\000\\036\\000\\000\\000\\000\\000\\000\\000\\000\\000\\000\\000\"");
    /* every status_interval (10 s) */
    ck_assert_int_eq(kelp_remus_codec_iterate(&t, now + 9.9, &sink), 0);
    ck_assert_int_eq(kelp_remus_codec_iterate(&t, now + 10, &sink), 1);
    ck_assert_int_eq(r.n, 2);
}
END_TEST

START_TEST(test_tool_no_create_status)
{
    kelp_remus_codec t;
    tool_setup(&t, false);
    rec r = {0};
    kelp_field_sink sink = {&r, rec_pub, rec_warn};
    const char *nav[] = {"NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED", "NAV_DEPTH"};
    for (int i = 0; i < 5; i++) ck_assert_int_eq(kelp_remus_codec_mail(&t, nav[i], false, NULL, 1, 0, &sink), 1);
    ck_assert_int_eq(kelp_remus_codec_iterate(&t, 100, &sink), 0);
    ck_assert_int_eq(r.n, 0);
}
END_TEST

START_TEST(test_tool_incoming_state)
{
    kelp_remus_codec t;
    tool_setup(&t, false);
    rec r = {0};
    kelp_field_sink sink = {&r, rec_pub, rec_warn};
    /* the State of test_tool_create_status, from modem 2 (mm2, auv) */
    const char *in = "base { src: 2 dest: 0 } data: \"\\016\\225\\035\\036\\363\\213\\315\\000c\\3321 \\037\\004"
                     "\\000\\000\\000\\000\\000\\000\\036\"";
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "IN_REMUS_STATUS", true, in, 0, 1000, &sink), 1);
    int i = find(&r, "NODE_REPORT");
    ck_assert_int_ge(i, 0);
    kelp_nodereport nr;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_nodereport_parse(r.sval[i], strlen(r.sval[i]), &nr, &why), 0);
    ck_assert_str_eq(nr.name, "mm2");
    ck_assert_str_eq(nr.type, "auv");
    ck_assert_str_eq(nr.mode, "NOMOOS");
    ck_assert(fabs(nr.lat - 42.35) < 1e-4);
    ck_assert(fabs(nr.lon + 70.95) < 1e-4);
    ck_assert(fabs(nr.x) < 2 && fabs(nr.y) < 2); /* at the datum, within a code */
    ck_assert(fabs(nr.spd - 1.2) < 0.01);
    ck_assert(fabs(nr.hdg - 45.18) < 0.01);
    ck_assert(fabs(nr.depth - 111) < 0.01);
    ck_assert_int_ge(find(&r, "STATUS_REPORT_IN"), 0);
    ck_assert(strncmp(r.sval[find(&r, "STATUS_REPORT_IN")], "MessageType=CCL_STATUS,Node=2,Timestamp=1000,", 45) == 0);
    i = find(&r, "MM2_NAV_DEPTH");
    ck_assert_int_ge(i, 0);
    ck_assert(r.dval[i] == 111.0);
    /* unknown sender: the id as the name */
    r.n = 0;
    const char *in7 = "base { src: 7 dest: 0 } data: \"\\016\"";
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "IN_REMUS_STATUS", true, in7, 0, 1000, &sink), 1);
    i = find(&r, "NODE_REPORT");
    ck_assert_int_ge(i, 0);
    ck_assert(strncmp(r.sval[i], "NAME=7,TYPE=unknown_type,", 25) == 0);
    ck_assert_int_ge(find(&r, "7_NAV_X"), 0);
    /* a Ranger on the State variable, and garbage, are refused with a warning */
    r.n = 0;
    ck_assert_int_lt(kelp_remus_codec_mail(&t, "IN_REMUS_STATUS", true, "data: \"\\020\"", 0, 1000, &sink), 0);
    ck_assert_int_lt(kelp_remus_codec_mail(&t, "IN_REMUS_STATUS", true, "nonsense {", 0, 1000, &sink), 0);
    ck_assert_int_eq(r.n, 0);
    ck_assert_int_eq(r.warns, 2);
}
END_TEST

START_TEST(test_tool_init_and_subscriptions)
{
    kelp_remus_codec t;
    tool_setup(&t, false);
    ck_assert_str_eq(kelp_remus_codec_subscription(&t, 0), "IN_REMUS_STATUS");
    ck_assert_str_eq(kelp_remus_codec_subscription(&t, 5), "OUT_REMUS_STATUS");
    ck_assert_str_eq(kelp_remus_codec_subscription(&t, 10), "MODEM_ID");
    ck_assert_str_eq(kelp_remus_codec_subscription(&t, 15), "NAV_DEPTH");
    ck_assert_str_eq(kelp_remus_codec_subscription(&t, 16), "OUTGOING_COMMAND");
    ck_assert_ptr_null(kelp_remus_codec_subscription(&t, 17));
    kelp_remus_codec_cfg c;
    kelp_remus_codec_cfg_default(&c);
    ck_assert_int_eq(kelp_remus_codec_init(&t, &c), KELP_ERR_ARG); /* no geo */
    c.geo = &geo;
    c.status_interval = 0;
    ck_assert_int_eq(kelp_remus_codec_init(&t, &c), KELP_ERR_ARG);
    c.status_interval = 10;
    c.in_var[2][0] = '\0';
    ck_assert_int_eq(kelp_remus_codec_init(&t, &c), KELP_ERR_ARG);
}
END_TEST

START_TEST(test_tool_redirect_alerts)
{
    kelp_remus_codec t;
    tool_setup(&t, false);
    rec r = {0};
    kelp_field_sink sink = {&r, rec_pub, rec_warn};
    kelp_acomms_msg m;
    char text[1024], want[1536];
    double la = kelp_remus_latlon_decode(1973653), lo = kelp_remus_latlon_decode(-3306509);

    /* Redirect from modem 3 */
    memset(&m, 0, sizeof m);
    m.src = 3;
    m.len = 32;
    uint8_t *f = m.data;
    f[0] = 7;
    f[2] = 0x95, f[3] = 0x1D, f[4] = 0x1E;  /* lat 42.35 */
    f[5] = 0xF3, f[6] = 0x8B, f[7] = 0xCD;  /* lon -70.95 */
    f[8] = 0xA5;                            /* speed/depth flags */
    f[9] = 0x1F, f[10] = 0x04;              /* transit depth 1055 -> 111 m */
    f[11] = 30;                             /* transit speed 1 m/s */
    f[12] = 3;
    f[13] = 123, f[14] = 0;                 /* survey depth 12.3 m */
    f[15] = 0xE2;                           /* survey speed -30 -> -1 m/s */
    f[16] = 4, f[17] = 5;
    f[18] = 0x00, f[19] = 0x01;             /* row length 256 */
    f[20] = 20, f[21] = 30, f[22] = 64;     /* spacings, row heading 64 -> 90.35 deg */
    f[23] = 0x95, f[24] = 0x1D, f[25] = 0x1E;
    f[26] = 0xF3, f[27] = 0x8B, f[28] = 0xCD;
    ck_assert_int_eq(kelp_acomms_print_data_bare(&m, text, sizeof text, NULL), 0);
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "IN_REMUS_REDIRECT_HEX_30B", true, text, 0, 1000, &sink), 1);
    ck_assert_int_eq(r.n, 1);
    ck_assert_str_eq(r.var[0], "CCL_REDIRECT_IN");
    snprintf(want, sizeof want,
             "MessageType=CCL_REDIRECT,DestinationPlatformId=3,Timestamp=1000,Latitude=%.17g,Longitude=%.17g,"
             "SpeedDepthFlags=A5,TransitSpeed=1,TransitDepth=111,TransitCommand=3,SurveySpeed=-1,"
             "SurveyDepth=12.300000190734863,SurveyCommand=4,NumberOfRows=5,RowLength=256,RowSpacing0=20,"
             "RowSpacing1=30,RowHeading=90.352941176470594,StartLatitude=%.17g,StartLongitude=%.17g",
             la, lo, la, lo);
    ck_assert_str_eq(r.sval[0], want);
    ck_assert_str_eq("42.350003999472143", (snprintf(want, sizeof want, "%.17g", la), want));
    /* a State on the Redirect variable is refused */
    f[0] = 14;
    ck_assert_int_eq(kelp_acomms_print_data_bare(&m, text, sizeof text, NULL), 0);
    ck_assert_int_lt(kelp_remus_codec_mail(&t, "IN_REMUS_REDIRECT_HEX_30B", true, text, 0, 1000, &sink), 0);
    ck_assert_int_eq(r.n, 1);

    /* Alert2 from modem 2 (any first byte) */
    memset(&m, 0, sizeof m);
    m.src = 2;
    m.len = 32;
    f[0] = 31;
    f[1] = 0x10, f[2] = 0x32, f[3] = 0x54, f[4] = 0x76; /* OASIS time 0x76543210 */
    f[5] = 0x95, f[6] = 0x1D, f[7] = 0x1E;
    f[8] = 0xF3, f[9] = 0x8B, f[10] = 0xCD;
    f[11] = 0x34, f[12] = 0x12, f[13] = 0x85, f[14] = 90, f[15] = 32, f[16] = 1, f[17] = 2; /* contact 1 */
    f[18] = 0x01, f[19] = 0x00, f[20] = 0x05, f[21] = 200, f[22] = 0, f[23] = 255, f[24] = 128; /* contact 2 */
    ck_assert_int_eq(kelp_acomms_print_data_bare(&m, text, sizeof text, NULL), 0);
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "IN_REMUS_ALERT2_HEX_30B", true, text, 0, 1000, &sink), 1);
    ck_assert_str_eq(r.var[1], "CCL_ALERT2_IN");
    snprintf(want, sizeof want,
             "MessageType=CCL_ALERT2,Node=2,Timestamp=1985229328,Latitude=%.17g,Longitude=%.17g,"
             "Contact1Id=4660,Contact1Age=133,Contact1Bearing=90,Contact1HeadingType=Absolute,"
             "Contact1Heading=45.176470588235297,Contact1Signature1=1,Contact1Signature2=2,"
             "Contact2Id=1,Contact2Age=5,Contact2Bearing=200,Contact2HeadingType=Vehicle,Contact2Heading=0,"
             "Contact2Signature1=255,Contact2Signature2=128,"
             "Contact3Id=0,Contact3Age=0,Contact3Bearing=0,Contact3HeadingType=Vehicle,Contact3Heading=0,"
             "Contact3Signature1=0,Contact3Signature2=0",
             la, lo);
    ck_assert_str_eq(r.sval[1], want);

    /* Alert: heading at byte 11, contacts of 6 bytes from byte 12 */
    f[11] = 32;
    f[12] = 0x34, f[13] = 0x12, f[14] = 7, f[15] = 90, f[16] = 1, f[17] = 2;
    f[18] = 0, f[19] = 0, f[20] = 0, f[21] = 0, f[22] = 0, f[23] = 0, f[24] = 0;
    f[29] = 9;
    ck_assert_int_eq(kelp_acomms_print_data_bare(&m, text, sizeof text, NULL), 0);
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "IN_REMUS_ALERT_HEX_30B", true, text, 0, 1000, &sink), 1);
    ck_assert_str_eq(r.var[2], "CCL_ALERT_IN");
    snprintf(want, sizeof want,
             "MessageType=CCL_ALERT,Node=2,Timestamp=1985229328,Latitude=%.17g,Longitude=%.17g,"
             "Heading=45.176470588235297,"
             "Contact1Id=4660,Contact1Age=7,Contact1Bearing=90,Contact1Signature1=1,Contact1Signature2=2,"
             "Contact2Id=0,Contact2Age=0,Contact2Bearing=0,Contact2Signature1=0,Contact2Signature2=0,"
             "Contact3Id=0,Contact3Age=0,Contact3Bearing=0,Contact3Signature1=0,Contact3Signature2=9",
             la, lo);
    ck_assert_str_eq(r.sval[2], want);
}
END_TEST

START_TEST(test_tool_outgoing_redirect)
{
    kelp_remus_codec t;
    tool_setup(&t, false);
    rec r = {0};
    kelp_field_sink sink = {&r, rec_pub, rec_warn};
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "MODEM_ID", true, "2", 0, 1000, &sink), 1);
    /* not a CCL_REDIRECT: ignored */
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "OUTGOING_COMMAND", true, "MessageType=GOTO,x=1", 0, 1000, &sink), 0);
    ck_assert_int_eq(r.n, 0);
    const char *cmd = "MessageType=CCL_REDIRECT,DestinationPlatformId=3,Timestamp=1,Latitude=42.35,Longitude=-70.95,"
                      "SpeedDepthFlags=A5,TransitSpeed=1,TransitDepth=111,TransitCommand=3,SurveySpeed=-1,"
                      "SurveyDepth=12.3,SurveyCommand=4,NumberOfRows=5,RowLength=256,RowSpacing0=20,"
                      "RowSpacing1=30,RowHeading=90.35,StartLatitude=42.35,StartLongitude=-70.95";
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "OUTGOING_COMMAND", true, cmd, 0, 1000, &sink), 1);
    ck_assert_int_eq(r.n, 1);
    ck_assert_str_eq(r.var[0], "OUT_REMUS_REDIRECT_HEX_30B");
    /* 07 00 | 95 1D 1E | F3 8B CD | A5 | 1F 04 (1055) | 1E (30) | 03 | 7B 00 (123) | E2 (-30) | 04 | 05 |
     * 00 01 (256) | 14 | 1E | 40 (heading 64) | 95 1D 1E | F3 8B CD | 00 00 00 */
    ck_assert_str_eq(r.sval[0], "base { src: 2 dest: 3 } data: \"\\007\\000\\225\\035\\036\\363\\213\\315\\245\\037\\004"
                                "\\036\\003{\\000\\342\\004\\005\\000\\001\\024\\036@\\225\\035\\036\\363\\213\\315"
                                "\\000\\000\\000\"");
    /* the same frame through the incoming side */
    ck_assert_int_eq(kelp_remus_codec_mail(&t, "IN_REMUS_REDIRECT_HEX_30B", true, r.sval[0], 0, 1000, &sink), 1);
    ck_assert_str_eq(r.var[1], "CCL_REDIRECT_IN");
    ck_assert(strstr(r.sval[1], ",SpeedDepthFlags=A5,TransitSpeed=1,TransitDepth=111,TransitCommand=3,SurveySpeed=-1,"
                                "SurveyDepth=12.300000190734863,SurveyCommand=4,NumberOfRows=5,RowLength=256,"
                                "RowSpacing0=20,RowSpacing1=30,RowHeading=90.352941176470594,") != NULL);
    /* the encoder alone: clamps */
    kelp_remus_redirect rd;
    memset(&rd, 0, sizeof rd);
    rd.row_length = 70000, rd.row_spacing_0 = 300, rd.row_spacing_1 = -4;
    uint8_t f[32];
    size_t len = 0;
    ck_assert_int_eq(kelp_remus_redirect_encode(&rd, f, sizeof f, &len), 0);
    ck_assert_uint_eq(len, 32);
    ck_assert_uint_eq(f[0], 7);
    ck_assert_uint_eq(f[18], 0xFF);
    ck_assert_uint_eq(f[19], 0xFF);
    ck_assert_uint_eq(f[20], 255);
    ck_assert_uint_eq(f[21], 0);
    ck_assert_int_eq(kelp_remus_redirect_encode(&rd, f, 31, &len), KELP_ERR_NOSPACE);
    ck_assert_int_eq(kelp_remus_redirect_encode(NULL, f, 32, &len), KELP_ERR_ARG);
}
END_TEST

Suite *kelp_remus_suite(void)
{
    Suite *s = suite_create("remus");
    TCase *t = tcase_create("fields");
    tcase_add_test(t, test_latlon_vectors);
    tcase_add_test(t, test_latlon_decode);
    tcase_add_test(t, test_heading);
    tcase_add_test(t, test_depth);
    tcase_add_test(t, test_velocity_speed_watts_fixage);
    tcase_add_test(t, test_gfi_pitch_oil);
    tcase_add_test(t, test_time_date);
    suite_add_tcase(s, t);
    t = tcase_create("messages");
    tcase_add_test(t, test_state_encode_vector);
    tcase_add_test(t, test_state_decode_vector);
    tcase_add_test(t, test_state_round_trip_all_bytes);
    tcase_add_test(t, test_state_from_nav);
    tcase_add_test(t, test_state_rejections);
    tcase_add_test(t, test_identify);
    tcase_add_test(t, test_ranger);
    suite_add_tcase(s, t);
    t = tcase_create("tool");
    tcase_add_test(t, test_tool_create_status);
    tcase_add_test(t, test_tool_no_create_status);
    tcase_add_test(t, test_tool_incoming_state);
    tcase_add_test(t, test_tool_init_and_subscriptions);
    tcase_add_test(t, test_tool_redirect_alerts);
    tcase_add_test(t, test_tool_outgoing_redirect);
    suite_add_tcase(s, t);
    return s;
}
