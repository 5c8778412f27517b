/* Fuzz: the node report parser (and formatter: parse -> format -> parse -> format must be
 * stable) and the VIEW_* artifact parser for every kind. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/nodereport.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* exact-length copy: the parsers must not read past len */
    char *s = malloc(size ? size : 1);
    memcpy(s, data, size);
    kelp_nodereport r, r2;
    kelp_diag why = { 0 };
    int rc = kelp_nodereport_parse(s, size, &r, &why);
    if (rc < 0 && why.code == KELP_OK) abort(); /* every rejection has a reason */
    if (rc == 0) {
        if (!(r.fields & KELP_NR_NAME)) abort();
        char a[KELP_NODEREPORT_MAX_LEN * 2], b[KELP_NODEREPORT_MAX_LEN * 2];
        size_t na, nb;
        if (kelp_nodereport_format(&r, a, sizeof a, &na) == 0) {
            if (strlen(a) != na) abort();
            if (kelp_nodereport_parse(a, na, &r2, &why) != 0) abort();
            if (r2.fields != r.fields) abort();
            if (kelp_nodereport_format(&r2, b, sizeof b, &nb) != 0 || strcmp(a, b) != 0) abort();
        }
        kelp_geo g;
        if (kelp_geo_init(&g, 43.8253, -70.3304) == 0) (void)kelp_nodereport_complete(&r, &g);
    }
    static kelp_view v;
    for (int k = 0; k < KELP_VIEW_NKINDS; k++) {
        kelp_diag_clear(&why);
        rc = kelp_nodereport_view_parse((kelp_view_kind)k, s, size, &v, &why);
        if (rc < 0 && why.code == KELP_OK) abort();
        if (rc == 0 && v.npts > KELP_VIEW_MAX_PTS) abort();
    }
    free(s);
    return 0;
}
