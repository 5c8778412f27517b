/* kelp DCCL, edge layer (libkelp.a): the expat XML loader, the mbedTLS crypto
 * glue, the modem-id lookup file, the C table generator and the kelp-dccl CLI.
 * These allocate at start-up and do I/O; the codec itself is in <kelp/dccl.h>. */
#ifndef KELP_DCCL_EDGE_H
#define KELP_DCCL_EDGE_H

#include <stdio.h>


#include <kelp/dccl.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ XML loader */
/** Message definitions loaded from XML files; owns every definition it holds. */
typedef struct kelp_dccl_loaded {
    kelp_dccl_set set; /**< every message loaded so far, in load order */
    /* private */
    const kelp_dccl_msgdef **msgs;
    size_t cap;
    void *arena;
} kelp_dccl_loaded;

void kelp_dccl_loaded_init(kelp_dccl_loaded *ld);
void kelp_dccl_loaded_free(kelp_dccl_loaded *ld);

/** Load one XML message file (the Goby 1.1 schema, validated as Goby's schema does)
 *  and add its messages. Every load-time check Goby makes is applied: <size> > 6,
 *  the body fits, <repeat> without arrays, references to unknown fields in
 *  algorithms and <message_var>, unknown algorithm names when `algs` holds at least
 *  one algorithm; plus duplicate ids/names in the set.
 * @param d   receives "file:line: reason" and the line on failure (may be NULL)
 * @return 0, KELP_ERR_IO (cannot read), KELP_ERR_PARSE (XML or schema), KELP_ERR_RANGE
 *         (a message does not fit), KELP_ERR_NOTFOUND (unknown reference), KELP_ERR_EXISTS.
 *         On failure nothing of this file is added. */
KELP_MUST_CHECK int kelp_dccl_load_file(kelp_dccl_loaded *ld, const char *path, const kelp_dccl_algs *algs,
                                        kelp_diag *d);
/** Same from memory; `name` is used in error messages. */
KELP_MUST_CHECK int kelp_dccl_load_buffer(kelp_dccl_loaded *ld, const char *name, const char *xml, size_t len,
                                          const kelp_dccl_algs *algs, kelp_diag *d);

/* ------------------------------------------------------------------ mbedTLS crypto */
/** Goby 1.1 crypto: key = SHA-256(passphrase) (also for the empty passphrase),
 *  AES-256-CTR, IV = SHA-256(header)[0..15]. `ops` is what kelp_dccl_codec wants. */
#define KELP_DCCL_AES_CTX_SIZE 512   /**< room for mbedTLS's AES context (288 bytes in 2.28) */
typedef struct kelp_dccl_mbedtls {
    kelp_dccl_crypto ops;
    /* private: the AES context lives here, opaque so that no mbedTLS header is needed */
    union {
        unsigned char bytes[KELP_DCCL_AES_CTX_SIZE];
        long double align_ld;
        void *align_p;
        unsigned long long align_ll;
    } aes;
    unsigned char key[32];
} kelp_dccl_mbedtls;

/** @param passphrase NULL is the empty passphrase (Goby's default). */
KELP_MUST_CHECK int kelp_dccl_mbedtls_init(kelp_dccl_mbedtls *c, const char *passphrase);
void kelp_dccl_mbedtls_free(kelp_dccl_mbedtls *c);

/* ------------------------------------------------------------------ modem-id lookup file */
/** Read a modem_id_lookup_path file into ctx (see kelp_dccl_builtin_parse_modems); d says why not. */
KELP_MUST_CHECK int kelp_dccl_builtin_load_modems(kelp_dccl_builtin *ctx, const char *path, kelp_diag *d);

/* ------------------------------------------------------------------ generator */
/** Write C source and header holding `set` as const tables.
 * @param prefix  C identifier prefix (e.g. "goby_chat"); the set is <prefix>_set
 * @param header_name  how the source #includes the header */
KELP_MUST_CHECK int kelp_dccl_gen_write(const kelp_dccl_set *set, const char *prefix, const char *header_name,
                                        const char *source_name, FILE *c_out, FILE *h_out);

#ifdef __cplusplus
}
#endif
#endif
