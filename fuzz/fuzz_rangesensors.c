/* Fuzz: the beacon and contact range sensors' mail (NODE_REPORT, BRS_/CRS_RANGE_REQUEST) and
 * block parameters (BEACON lines, per-vehicle values, noise, frequencies). The input is
 * records split at '\n': the first byte picks the variable or a parameter (>= 0xC0), the rest
 * is its value. Both cores iterate every few records; reports must stay consistent. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/beaconrange.h>
#include <kelp/contactrange.h>

static const char *const vars[] = { "NODE_REPORT", "NODE_REPORT_LOCAL", "BRS_RANGE_REQUEST", "CRS_RANGE_REQUEST" };
static const char *const keys[] = { "BEACON", "DEFAULT_BEACON_FREQ", "DEFAULT_BEACON_REPORT_RANGE", "REACH_DISTANCE",
                                    "REPLY_DISTANCE", "PING_WAIT", "PING_PAYMENTS", "REPORT_VARS", "RN_ALGORITHM",
                                    "RN_UNIFORM_PCT", "RN_GAUSSIAN_SIGMA", "GROUND_TRUTH", "SENSOR_ARC",
                                    "ALLOW_ECHO_TYPES", "RAND_MODE", "NODE_PULL_DIST", "ECHO_FALLOFF", "IGNORE_GROUP" };
#define NV (sizeof vars / sizeof vars[0])
#define NK (sizeof keys / sizeof keys[0])

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx, (void)dval;
    if (!var || (is_string && !sval)) abort();
    if (is_string && strstr(var, "_RANGE_REPORT") && (strstr(sval, "nan") || strstr(sval, "inf"))) abort();
}
static void warn(void *ctx, const char *msg)
{
    (void)ctx;
    if (!msg) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kelp_beaconrange *b;
    static kelp_contactrange *c;
    static char text[1 << 14];
    if (!b) b = malloc(sizeof *b);
    if (!c) c = malloc(sizeof *c);
    static kelp_beaconrange_cfg bc;
    static kelp_contactrange_cfg cc;
    kelp_beaconrange_cfg_default(&bc);
    kelp_contactrange_cfg_default(&cc);
    kelp_field_sink sink = { NULL, pub, warn };
    bool ok = true;
    for (int pass = 0; pass < 2; pass++) {
        size_t i = 0;
        unsigned rec = 0;
        double now = 1000;
        while (i < size) {
            size_t e = i;
            while (e < size && data[e] != '\n') e++;
            if (e > i) {
                uint8_t sel = data[i];
                size_t vl = e - i - 1;
                char *v = malloc(vl + 1);
                memcpy(v, data + i + 1, vl);
                v[vl] = 0;
                if (pass == 0 && sel >= 0xC0) {
                    kelp_diag why = { 0 };
                    int rc = kelp_beaconrange_config(&bc, keys[sel % NK], v, &why);
                    if (rc < 0 && why.code == KELP_OK) abort();
                    kelp_diag_clear(&why);
                    rc = kelp_contactrange_config(&cc, keys[sel % NK], v, &why);
                    if (rc < 0 && why.code == KELP_OK) abort();
                } else if (pass == 1 && sel < 0xC0) {
                    (void)kelp_beaconrange_mail(b, vars[sel % NV], (sel & 0x40) == 0, v, now, &sink);
                    (void)kelp_contactrange_mail(c, vars[sel % NV], (sel & 0x40) == 0, v, now, &sink);
                    if (++rec % 4 == 0) {
                        now += (sel & 0x3F) * 2.5;
                        (void)kelp_beaconrange_iterate(b, now, &sink);
                    }
                }
                free(v);
            }
            i = e + 1;
        }
        if (pass == 0) {
            kelp_diag why = { 0 };
            ok = kelp_beaconrange_init(b, &bc, 0, &why) == 0;
            if (!ok && why.code == KELP_OK) abort();
            if (!ok) kelp_beaconrange_cfg_default(&bc), ok = kelp_beaconrange_init(b, &bc, 0, &why) == 0;
            kelp_contactrange_init(c, &cc, 0);
        }
    }
    if (!ok) abort();
    if (b->accepted + b->denied > b->requests || c->accepted + c->denied > c->requests) abort();
    if (b->nbeacons > KELP_BRS_MAX_BEACONS || b->nnodes > KELP_RSENSE_MAX_NODES) abort();
    (void)kelp_beaconrange_summary(b, text, sizeof text);
    (void)kelp_contactrange_summary(c, text, sizeof text);
    (void)kelp_beaconrange_report(b, text, sizeof text); /* the AppCast tables: always terminated */
    if (strlen(text) >= sizeof text) abort();
    (void)kelp_contactrange_report(c, text, sizeof text);
    if (strlen(text) >= sizeof text) abort();
    return 0;
}
