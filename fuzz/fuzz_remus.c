/* Fuzz: the REMUS CCL codec. Any 32-byte State frame decodes and re-encodes to the same bytes
 * (the State struct holds wire codes, so there is no canonical rewrite); every other length or id
 * is refused with a status. The field helpers are driven with doubles taken from the input: their
 * codes stay in range and their decoded values re-encode to the same code (except gfi/oil, which
 * Goby's decoder truncates, velocity, which its encoder truncates, and depth codes past 8100).
 * The input as text on each of pREMUSCodec's incoming variables exercises the tool. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/remus.h>
#include <stdbool.h>

static void sink_pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx;
    (void)dval;
    if (!var || !var[0] || (is_string && !sval)) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* exact-length copy: the decoders must not read past len */
    uint8_t *in = malloc(size ? size : 1);
    memcpy(in, data, size);
    kelp_remus_state s;
    int rc = kelp_remus_state_decode(in, size, &s);
    if (size == KELP_REMUS_FRAME_LEN && in[0] == KELP_REMUS_ID_STATE) {
        if (rc != 0) abort();
        uint8_t out[KELP_REMUS_FRAME_LEN];
        size_t len = 0;
        if (kelp_remus_state_encode(&s, out, sizeof out, &len) != 0 || len != sizeof out) abort();
        if (memcmp(in, out, sizeof out) != 0) abort();
        /* decoded values are finite and re-encode to their codes */
        double lat = kelp_remus_latlon_decode(s.lat);
        if (!(fabs(lat) <= 180.0 + 1e-3)) abort();
        if (kelp_remus_latlon_encode(lat) != s.lat) abort();
        if (kelp_remus_heading_encode(kelp_remus_heading_decode(s.heading)) != s.heading &&
            s.heading != 255) /* 255 decodes as 360, which is heading 0 again */
            abort();
        if (s.depth <= 8100 && kelp_remus_depth_encode(kelp_remus_depth_decode(s.depth)) != s.depth)
            abort();
        /* velocity truncates (Goby 1.x): code/25 as float may come back one code toward zero */
        int dv = kelp_remus_velocity_encode(kelp_remus_velocity_decode(s.est_velocity)) - s.est_velocity;
        if (dv > 1 || dv < -1) abort();
        kelp_remus_time t;
        kelp_remus_time_date_decode(s.time_date, &t);
        int64_t u;
        if (kelp_remus_time_date_to_unix(s.time_date, 2024, &u) == 0 &&
            kelp_remus_time_date_encode(u) != s.time_date)
            abort();
        double g, p, o;
        kelp_remus_gfi_pitch_oil_decode(s.gfi_pitch_oil, &g, &p, &o);
        if (!(g >= 0 && g <= 100 && o >= 0 && o <= 100 && fabs(p) <= 92)) abort();
        if ((kelp_remus_gfi_pitch_oil_encode(0, p, 0) >> 10) != (s.gfi_pitch_oil >> 10) &&
            (s.gfi_pitch_oil >> 10) != 32) /* -32 is -91.4 deg, clamped to -90 -> -32 too */
            abort();
    } else if (rc == 0) {
        abort();
    }
    kelp_remus_ranger r;
    rc = kelp_remus_ranger_decode(in, size, &r);
    if ((rc == 0) != (size == KELP_REMUS_FRAME_LEN && in[0] == KELP_REMUS_ID_RANGER)) abort();
    (void)kelp_remus_identify(in, size);
    /* helpers on arbitrary doubles: no UB, codes in range */
    if (size >= 8) {
        double d;
        memcpy(&d, in + size - 8, sizeof d);
        int32_t c = kelp_remus_latlon_encode(d);
        if (c < -0x800000 || c > 0x7FFFFF) abort();
        if (kelp_remus_depth_encode(d) > 8100) abort();
        (void)kelp_remus_heading_encode(d);
        (void)kelp_remus_velocity_encode(d);
        (void)kelp_remus_speed_encode(d);
        (void)kelp_remus_watts_encode(d);
        (void)kelp_remus_fix_age_encode(d);
        (void)kelp_remus_gfi_pitch_oil_encode(d, d, d);
        kelp_remus_redirect rd = {d, d, 1, d, d, 2, d, d, 3, 4, d, d, d, d, d, d};
        uint8_t rf[KELP_REMUS_FRAME_LEN];
        size_t rl;
        if (kelp_remus_redirect_encode(&rd, rf, sizeof rf, &rl) != 0 || rl != sizeof rf || rf[0] != 7) abort();
        if (isfinite(d) && fabs(d) < 1e15) (void)kelp_remus_time_date_encode((int64_t)d);
    }
    /* the pREMUSCodec tool: the input as the text of each incoming variable */
    static kelp_dccl_modem_entry modems[4];
    static kelp_dccl_builtin geo;
    static kelp_remus_codec tool;
    static bool ready;
    if (!ready) {
        kelp_dccl_builtin_init(&geo, modems, 4);
        static const char lk[] = "1,mm1,topside\n2,mm2,auv\n";
        if (kelp_dccl_builtin_parse_modems(&geo, lk, sizeof lk - 1) != 0) abort();
        kelp_dccl_builtin_set_origin(&geo, 42.35, -70.95);
        kelp_remus_codec_cfg c;
        kelp_remus_codec_cfg_default(&c);
        c.create_status = true;
        c.geo = &geo;
        if (kelp_remus_codec_init(&tool, &c) != 0) abort();
        ready = true;
    }
    char *text = malloc(size + 1);
    memcpy(text, data, size);
    text[size] = '\0';
    kelp_field_sink sink = {NULL, sink_pub, NULL};
    for (int k = 0; k < KELP_REMUS_NVARS; k++)
        (void)kelp_remus_codec_mail(&tool, tool.cfg.in_var[k], true, text, 0, 1000, &sink);
    (void)kelp_remus_codec_mail(&tool, "OUTGOING_COMMAND", true, text, 0, 1000, &sink);
    (void)kelp_remus_codec_mail(&tool, "MODEM_ID", true, text, 0, 1000, &sink);
    free(text);
    free(in);
    return 0;
}
