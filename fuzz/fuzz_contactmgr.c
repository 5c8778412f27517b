/* Fuzz: pContactMgrV20's mail (NODE_REPORT, NAV_*, BCM_ALERT_REQUEST, BCM_REPORT_REQUEST,
 * BCM_DISPLAY_RADII) and block parameters (alert lines, filters, regions, numbers). The input
 * is records split at '\n': the first byte picks the variable (or, >= 0xC0, a block
 * parameter), the rest is its value. The core iterates every few records with a moving clock
 * and writes its report; the contact order must stay sorted and within capacity. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/contactmgr.h>

static const char *const vars[] = { "NODE_REPORT", "NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED", "BCM_ALERT_REQUEST",
                                    "BCM_REPORT_REQUEST", "BCM_DISPLAY_RADII", "IVPHELM_STATE" };
static const char *const keys[] = { "alert", "ignore_name", "match_name", "ignore_type", "match_type", "ignore_group",
                                    "match_group", "ignore_region", "match_region", "strict_ignore", "contact_max_age",
                                    "max_retired_history", "max_contacts", "display_radii", "decay", "recap_interval",
                                    "reject_range", "contact_local_coords", "post_all_ranges", "post_closest_range",
                                    "post_closest_relbng", "alert_verbose", "range_report_timeout", "display_radii_id" };
#define NV (sizeof vars / sizeof vars[0])
#define NK (sizeof keys / sizeof keys[0])

/* the sink checks what the core hands out: a name, and text within the bus limit */
static void on_post(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    unsigned long *n = ctx;
    (void)dval;
    if (!var || !var[0] || (is_string && (!sval || strlen(sval) > KELP_MAX_SVAL))) abort();
    ++*n;
}

static void on_warn(void *ctx, const char *msg)
{
    if (!ctx || !msg) abort();
}

static kelp_contactmgr *core;
static char text[1 << 16];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    unsigned long posts = 0;
    if (!core && !(core = malloc(sizeof *core))) return 0;
    kelp_contactmgr *c = core;
    kelp_contactmgr_init(c, "abe");
    kelp_field_sink sink = { &posts, on_post, on_warn };
    for (int pass = 0; pass < 2; pass++) {
        const uint8_t *p = data, *end = data + size;
        unsigned rec = 0;
        double now = 1000;
        for (const uint8_t *next; p < end; p = next) {
            const uint8_t *nl = memchr(p, '\n', (size_t)(end - p));
            size_t len = nl ? (size_t)(nl - p) : (size_t)(end - p);
            next = p + len + 1;
            if (len == 0) continue;
            uint8_t sel = p[0];
            bool param = sel >= 0xC0;
            if (param != (pass == 0)) continue;
            char *v = malloc(len); /* exact size: an overread trips ASan */
            if (!v) return 0;
            memcpy(v, p + 1, len - 1);
            v[len - 1] = 0;
            if (param) {
                if (kelp_contactmgr_config(c, keys[sel % NK], v, &sink) < 0) abort();
            } else {
                const char *var = vars[sel % NV];
                bool num = var[0] == 'N' && var[1] == 'A';
                (void)kelp_contactmgr_mail(c, var, !num, v, num ? (double)(int8_t)v[0] * 7.5 : 0, now, "fuzz", &sink);
                if (++rec % 3 == 0) {
                    now += (double)(sel % 40);
                    kelp_contactmgr_iterate(c, now, &sink);
                    (void)kelp_contactmgr_report_text(c, now, text, sizeof text);
                }
            }
            free(v);
        }
        if (pass == 0) kelp_contactmgr_config_done(c, true, 43.8253, true, -70.3304, &sink);
    }
    kelp_contactmgr_iterate(c, 5000, &sink);
    if (c->ncontacts > KELP_CMGR_MAX_CONTACTS || c->ncontacts + c->nspare != KELP_CMGR_MAX_CONTACTS) abort();
    for (unsigned k = 1; k < c->ncontacts; k++)
        if (strcmp(c->contact[c->order[k - 1]].name, c->contact[c->order[k]].name) >= 0) abort();
    return 0;
}
