/* Fuzz: APPCAST parse -> format -> parse must agree; render and APPCAST_REQ never fail badly. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/appcast.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kelp_appcast a, b;
    static char buf[3 * KELP_APPCAST_MSG + 16 * 3 * KELP_APPCAST_ITEM], buf2[sizeof buf];
    char *s = malloc(size ? size : 1);
    memcpy(s, data, size);
    kelp_diag why;
    kelp_diag_clear(&why);
    if (kelp_appcast_parse(s, size, &a, &why) == KELP_OK) {
        size_t n, n2;
        if (kelp_appcast_format(&a, buf, sizeof buf, &n) == KELP_OK) {
            if (strlen(buf) != n) abort();
            if (kelp_appcast_parse(buf, n, &b, &why) != KELP_OK) abort();
            if (kelp_appcast_format(&b, buf2, sizeof buf2, &n2) != KELP_OK) abort();
            if (strcmp(a.proc, b.proc) != 0 || a.iter != b.iter || a.ncfg != b.ncfg || a.nrun != b.nrun) abort();
        }
        if (kelp_appcast_render(&a, buf, sizeof buf, &n) == KELP_OK && strlen(buf) != n) abort();
    } else if (why.code == KELP_OK) { /* a refusal always says why */
        abort();
    }
    kelp_appcast_req r;
    if (kelp_appcast_req_parse(s, size, &r) == KELP_OK && (r.duration < 0 || r.duration > 30 || !r.key[0])) abort();
    free(s);
    return 0;
}
