/* Fuzz: pAcommsHandler's glue between bus strings and DCCL messages -- a
 * "field=value,..." string encoded as message i, a bus variable written then its message
 * encoded from the variables, and raw bytes decoded into publications. Whatever encodes
 * must decode again. The message set is the project's own example
 * (the XML files in missions/acomms, found from the working directory or $KELP_ROOT), read once. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/acomms.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static kelp_acomms_dccl *open_set(void)
{
    static const char *roots[] = { NULL, "..", ".", "../.." };
    static char paths[2][512];
    roots[0] = getenv("KELP_ROOT");
    for (size_t r = 0; r < sizeof roots / sizeof *roots; r++) {
        if (!roots[r]) continue;
        snprintf(paths[0], sizeof paths[0], "%s/missions/acomms/example1.xml", roots[r]);
        snprintf(paths[1], sizeof paths[1], "%s/missions/acomms/simple_status.xml", roots[r]);
        FILE *f = fopen(paths[0], "r");
        if (!f) continue;
        fclose(f);
        static const char *files[2];
        files[0] = paths[0], files[1] = paths[1];
        kelp_acomms_dccl_cfg c;
        memset(&c, 0, sizeof c);
        c.modem_id = 1;
        c.files = files;
        c.nfiles = 2;
        kelp_diag err;
        kelp_diag_clear(&err);
        kelp_acomms_dccl *d = kelp_acomms_dccl_open(&c, &err);
        if (!d) {
            fprintf(stderr, "fuzz_dccl_glue: %s\n", kelp_diag_text(&err));
            abort();
        }
        return d;
    }
    fprintf(stderr, "fuzz_dccl_glue: missions/acomms/example1.xml not found (set KELP_ROOT)\n");
    abort();
}

static void pub(const char *var, bool is_double, double dval, const char *sval, void *user)
{
    (void)is_double, (void)dval;
    size_t *n = user;
    if (!var || !sval) abort();
    (*n)++;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kelp_acomms_dccl *d;
    if (!d) d = open_set();
    if (size < 2) return 0;
    size_t count = kelp_acomms_dccl_count(d);
    size_t i = data[1] % count;
    char *t = malloc(size - 1);
    memcpy(t, data + 2, size - 2);
    t[size - 2] = 0;
    uint8_t out[1024];
    size_t len = 0, npub = 0;
    int rc = -1;
    switch (data[0] % 3) {
    case 0:
        rc = kelp_acomms_dccl_encode_string(d, i, t, 1700000000.0, out, sizeof out, &len, NULL);
        break;
    case 1: {
        size_t nv = kelp_acomms_dccl_nvars(d);
        if (nv) {
            const char *name = kelp_acomms_dccl_var_name(d, (size_t)data[1] % nv);
            bool num = (data[0] & 8) != 0;
            kelp_acomms_dccl_set_var(d, name, num, num ? strtod(t, NULL) : 0, t);
        }
        rc = kelp_acomms_dccl_encode_vars(d, i, 1700000000.0, out, sizeof out, &len, NULL);
        break;
    }
    default:
        (void)kelp_acomms_dccl_decode(d, (const uint8_t *)t, size - 2, 1700000000.0, pub, &npub, NULL);
        break;
    }
    if (rc == 0) {
        if (len == 0 || len > sizeof out) abort();
        /* what kelp encodes, kelp decodes */
        if (kelp_acomms_dccl_decode(d, out, len, 1700000000.0, pub, &npub, NULL) != 0 &&
            kelp_acomms_dccl_describe(d, out, len, 1700000000.0, (char *)out, sizeof out) != 0)
            abort();
    }
    free(t);
    return 0;
}
