/* Fuzz the IvP text parsers shared with kelp-ivp: DOMAIN, SPEC (and building it), FILE lines,
 * raw piece lines and the seed's shape/point/region strings. Input: lines separated by '\n';
 * the first line is a domain, the rest are tried as every kind of text. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/ivp.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static kelp_ivp_piece store[4096];
static double work[4096];
static kelp_ivp_spec_ws zws;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 4096)
        return 0;
    char *buf = malloc(size + 1);
    if (!buf)
        return 0;
    memcpy(buf, data, size);
    buf[size] = '\0';
    kelp_ivp_domain dom;
    kelp_diag err = {0};
    char *save = buf;
    char *line = strsep(&save, "\n");
    if (kelp_ivp_file_domain(line, &dom, &err) != 0 && kelp_ivp_domain_parse(&dom, line, &err) != 0) {
        kelp_ivp_domain_init(&dom);
        (void)kelp_ivp_domain_add(&dom, "course", 0, 359, 360);
        (void)kelp_ivp_domain_add(&dom, "speed", 0, 5, 41);
    }
    while ((line = strsep(&save, "\n")) != NULL) {
        kelp_diag_clear(&err);
        kelp_ivp_spec sp;
        if (kelp_ivp_spec_parse(&sp, line, &err) == 0 && dom.dim > 0 && dom.var[0].points <= 4096) {
            kelp_ivp_func f;
            (void)kelp_ivp_spec_build(&sp, &dom, dom.var[0].name, work, 4096, &zws, store, 4096, &f, &err);
        }
        kelp_ivp_fileline fl;
        (void)kelp_ivp_file_line(line, &dom, &fl, &err);
        kelp_ivp_func f;
        if (kelp_ivp_func_init(&f, &dom, store, 8) == 0)
            (void)kelp_ivp_file_piece(line, dom.dim, &f, &err);
        uint32_t ix[KELP_IVP_MAX_DIM];
        int32_t lo[KELP_IVP_MAX_DIM], hi[KELP_IVP_MAX_DIM];
        (void)kelp_ivp_parse_shape(&dom, line, ix, &err);
        (void)kelp_ivp_parse_point(&dom, line, ix, &err);
        (void)kelp_ivp_parse_region(&dom, line, lo, hi, &err);
#ifndef KELP_NO_ERRMSG
        if (strlen(err.msg) >= sizeof err.msg)
            abort();
#endif
    }
    free(buf);
    return 0;
}
