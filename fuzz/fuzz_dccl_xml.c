/* Fuzz the DCCL XML loader; whatever loads is encoded (empty values) and decoded. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/edge/dccl.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kelp_dccl_alg_entry store[40];
    static kelp_dccl_modem_entry modems[4];
    static kelp_dccl_val vals[4096], out[4096];
    static kelp_dccl_pub pubs[64];
    kelp_dccl_algs algs;
    kelp_dccl_builtin bi;
    kelp_dccl_loaded ld;
    kelp_dccl_codec cx;
    size_t i, j, n, np;
    uint8_t buf[KELP_DCCL_MAX_SIZE];
    kelp_dccl_algs_init(&algs, store, 40);
    kelp_dccl_builtin_init(&bi, modems, 4);
    if (kelp_dccl_algs_add_builtin(&algs, &bi)) abort();
    kelp_dccl_loaded_init(&ld);
    if (kelp_dccl_load_buffer(&ld, "fuzz.xml", (const char *)data, size, (size & 1) ? &algs : NULL, NULL) == 0) {
        kelp_dccl_codec_init(&cx, 1, NULL, &algs);
        for (i = 0; i < ld.set.n; i++) {
            const kelp_dccl_msgdef *d = ld.set.msgs[i];
            if (d->n_slots > 4096) continue;
            for (j = 0; j < d->n_slots; j++) kelp_dccl_val_set_str(&vals[j], "1");
            if (kelp_dccl_encode(&cx, d, vals, d->n_slots, 1.7e9, buf, sizeof buf, &n) == 0 &&
                kelp_dccl_decode(&cx, d, buf, n, 1.7e9, out, d->n_slots) == 0)
                (void)kelp_dccl_publish_all(&cx, d, out, d->n_slots, pubs, 64, &np);
        }
    }
    kelp_dccl_loaded_free(&ld);
    return 0;
}
