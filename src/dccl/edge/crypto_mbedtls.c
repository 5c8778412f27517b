/* kelp DCCL: Goby 1.1 encryption with mbedTLS 2.28 (DCCLCodec::process_cfg,
 * encrypt, decrypt): key = SHA-256(passphrase), AES-256-CTR, initial counter
 * block = SHA-256(header bytes)[0..15], 128-bit big-endian increment. */
#include <string.h>

#include <mbedtls/aes.h>
#include <mbedtls/sha256.h>

#include <kelp/edge/dccl.h>

KELP_STATIC_ASSERT(sizeof(mbedtls_aes_context) <= KELP_DCCL_AES_CTX_SIZE, "KELP_DCCL_AES_CTX_SIZE too small");

static mbedtls_aes_context *aes_of(kelp_dccl_mbedtls *c)
{
    return (mbedtls_aes_context *)(void *)c->aes.bytes;
}

static int iv_fn(void *user, const uint8_t *head, size_t n, uint8_t iv[16])
{
    unsigned char digest[32];
    (void)user;
    if (mbedtls_sha256_ret(head, n, digest, 0) != 0) return KELP_ERR_CRYPTO;
    memcpy(iv, digest, 16);
    return KELP_OK;
}

static int ctr_fn(void *user, const uint8_t iv[16], uint8_t *buf, size_t n)
{
    kelp_dccl_mbedtls *c = user;
    unsigned char counter[16], stream[16];
    size_t off = 0;
    memcpy(counter, iv, 16);
    if (mbedtls_aes_crypt_ctr(aes_of(c), n, &off, counter, stream, buf, buf) != 0) return KELP_ERR_CRYPTO;
    return KELP_OK;
}

int kelp_dccl_mbedtls_init(kelp_dccl_mbedtls *c, const char *passphrase)
{
    const char *pw = passphrase ? passphrase : "";
    memset(c, 0, sizeof *c);
    mbedtls_aes_init(aes_of(c));
    if (mbedtls_sha256_ret((const unsigned char *)pw, strlen(pw), c->key, 0) != 0) return KELP_ERR_CRYPTO;
    if (mbedtls_aes_setkey_enc(aes_of(c), c->key, 256) != 0) return KELP_ERR_CRYPTO;
    c->ops.iv = iv_fn;
    c->ops.ctr = ctr_fn;
    c->ops.user = c;
    return KELP_OK;
}

void kelp_dccl_mbedtls_free(kelp_dccl_mbedtls *c)
{
    mbedtls_aes_free(aes_of(c));
    memset(c->key, 0, sizeof c->key);
}
