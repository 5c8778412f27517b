/* Fuzz: MOOS .alog lines (src/bus/alog.c) -- parse a line, its value and the banner lines;
 * a parsed line written back with kelp_alog_format_line parses to the same fields. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/alog.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *s = (const char *)data;
    double t = 0, d = 0;
    (void)kelp_alog_parse_logstart(s, size, &t);
    (void)kelp_alog_is_marking(s, size);
    kelp_alog_line l;
    if (kelp_alog_parse_line(s, size, &l) != 1) return 0;
    if (l.var + l.var_len > s + size || l.val + l.val_len > s + size || !l.var_len || !l.src_len) abort();
    const char *v = NULL;
    size_t vl = 0;
    int kind = kelp_alog_value(l.val, l.val_len, size & 1, &d, &v, &vl);
    char var[64], src[64], val[256], out[512];
    if (l.var_len >= sizeof var || l.src_len >= sizeof src || (kind == 0 && vl >= sizeof val) || kind < 0) return 0;
    memcpy(var, l.var, l.var_len), var[l.var_len] = 0;
    memcpy(src, l.src, l.src_len), src[l.src_len] = 0;
    if (kind == 0) memcpy(val, v, vl), val[vl] = 0;
    if (memchr(var, 0, l.var_len) || memchr(src, 0, l.src_len) || (kind == 0 && memchr(val, 0, vl))) return 0;
    int n = kelp_alog_format_line(out, sizeof out, l.time, var, src, kind == 0, val, d, -1, true);
    if (n < 0) return 0; /* a value with a line break */
    kelp_alog_line l2;
    if (kelp_alog_parse_line(out, (size_t)n - 1, &l2) != 1 || l2.time != l.time || l2.var_len != l.var_len ||
        memcmp(l2.var, var, l.var_len) != 0 || l2.src_len != l.src_len)
        abort();
    return 0;
}
