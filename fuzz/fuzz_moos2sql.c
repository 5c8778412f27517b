/* Fuzz kelp-moos2sql's core (include/kelp/moos2sql.h): the classifier on arbitrary postings of
 * each kind (first byte picks the variable, the rest is the value), the fleet and its KML
 * (which must stay well-formed: no raw '<' or '&' from the input), the configuration reader. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/moos2sql.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const vars[] = { "NODE_REPORT", "NODE_REPORT_LOCAL", "CONTACTS_LIST", "CONTACTS_RECAP",
                                        "CONTACTS_ALERTED", "CONTACTS_COUNT", "STATUS_REPORT", "STATUS_SUMMARY" };
    static kelp_moos2sql_cfg cfg;
    static kelp_moos2sql_fleet fleet;
    static kelp_moos2sql_record r;
    static char kml[4096 + KELP_M2S_MAX_VEHICLES * 1536];
    if (size < 1) return 0;
    kelp_moos2sql_cfg_default(&cfg);
    (void)kelp_geo_init(&cfg.datum, 43.8253, -70.3304);
    cfg.have_datum = true;
    kelp_moos2sql_fleet_init(&fleet);
    const char *var = vars[data[0] % (sizeof vars / sizeof vars[0])];
    static char val[KELP_MAX_SVAL + 1]; /* the text as a kelp_var holds it: terminated at its length */
    size_t n = size - 1 < KELP_MAX_SVAL ? size - 1 : KELP_MAX_SVAL;
    memcpy(val, data + 1, n);
    val[n] = 0;
    kelp_diag why = { 0 };
    int rc = kelp_moos2sql_classify(&cfg, var, "shoreside", 100, (data[0] & 0x80) == 0, val, n, 3.5, &r, &why);
    if (rc < 0 && why.code == KELP_OK) abort();
    if (rc == 1) {
        (void)kelp_moos2sql_fleet_update(&fleet, &cfg, &r);
        int len = kelp_moos2sql_kml(&fleet, "fuzz <&>", kml, sizeof kml);
        if (len < 0 || (size_t)len != strlen(kml)) abort();
        /* every '&' starts an entity; '<' only opens our own tags (no "<" followed by a space or digit) */
        for (const char *p = kml; (p = strchr(p, '&')) != NULL; p++)
            if (strncmp(p, "&amp;", 5) && strncmp(p, "&lt;", 4) && strncmp(p, "&gt;", 4) && strncmp(p, "&quot;", 6) &&
                strncmp(p, "&apos;", 6))
                abort();
    }
    /* the configuration reader on the same bytes as a value */
    char text[512];
    size_t m = n < sizeof text - 1 ? n : sizeof text - 1;
    memcpy(text, val, m);
    text[m] = 0;
    static const char *const keys[] = { "STATUS_VAR", "CONTACT_VAR", "TRACK_VAR", "KML_PERIOD", "COMMIT_PERIOD", "DATABASE" };
    (void)kelp_moos2sql_config(&cfg, keys[data[0] % 6], text, &why);
    return 0;
}
