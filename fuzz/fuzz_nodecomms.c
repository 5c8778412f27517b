/* Fuzz: uFldNodeComms's mail (NODE_REPORT, NODE_MESSAGE, MEDIATED_MESSAGE, ACK_MESSAGE,
 * UNC_*) and block parameters. The input is records split at '\n': the first byte picks the
 * variable (or a block parameter), the rest is its value. The core iterates every few
 * records and writes its summary; its counters must stay consistent. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/field.h>

static const char *const vars[] = { "NODE_REPORT",  "NODE_REPORT_LOCAL", "NODE_MESSAGE",   "MEDIATED_MESSAGE",
                                    "ACK_MESSAGE",  "UNC_STEALTH",       "UNC_EARANGE",    "UNC_COMMS_RANGE",
                                    "UNC_DROP_PCT", "UNC_VIEW_NODE_RPT_PULSES", "UNC_SHARED_NODE_REPORTS" };
static const char *const keys[] = { "COMMS_RANGE", "CRITICAL_RANGE", "STALE_TIME", "MIN_MSG_INTERVAL", "MIN_RPT_INTERVAL",
                                    "MAX_MSG_LENGTH", "STEALTH", "EARANGE", "GROUPS", "MSG_GROUPS", "DROP_PERCENTAGE",
                                    "SHARED_NODE_REPORTS", "PULSE_DURATION", "MSG_COLOR" };
#define NV (sizeof vars / sizeof vars[0])
#define NK (sizeof keys / sizeof keys[0])

static unsigned long npub;
static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx, (void)dval;
    if (!var || (is_string && !sval)) abort();
    npub++;
}
static void warn(void *ctx, const char *msg)
{
    (void)ctx;
    if (!msg) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kelp_field_ncomms *c;
    static char report[1 << 16];
    if (!c) c = malloc(sizeof *c);
    kelp_field_ncomms_cfg cfg;
    kelp_field_ncomms_cfg_default(&cfg);
    kelp_field_sink sink = { NULL, pub, warn };
    /* pass 1: block parameters (records whose first byte is >= 0xC0) */
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
                    int rc = kelp_field_ncomms_config(&cfg, keys[sel % NK], v, &why);
                    if (rc < 0 && why.code == KELP_OK) abort();
                } else if (pass == 1 && sel < 0xC0) {
                    (void)kelp_field_ncomms_mail(c, vars[sel % NV], sel & 0x80 ? false : true, v, (double)vl,
                                                 sel & 0x40 ? "fuzz" : NULL, now, &sink);
                    if (++rec % 3 == 0) {
                        now += 0.25 * (sel & 7);
                        (void)kelp_field_ncomms_iterate(c, now, &sink);
                    }
                }
                free(v);
            }
            i = e + 1;
        }
        if (pass == 0 && kelp_field_ncomms_init(c, &cfg) < 0) return 0;
        if (pass == 1) {
            (void)kelp_field_ncomms_iterate(c, now + 1, &sink);
            if (kelp_field_ncomms_report(c, now + 1, report, sizeof report) == 0 && strlen(report) >= sizeof report)
                abort();
        }
    }
    unsigned long blocked = 0;
    for (int k = 0; k < KELP_NCOMMS_BLK_N; k++) blocked += c->blocked[k];
    if (c->nnodes > KELP_NCOMMS_MAX_NODES || c->nmsg != 0 || c->nupd != 0) abort();
    if (c->msgs_sent > 0 && c->msgs_rcvd == 0) abort();
    (void)blocked;
    return 0;
}
