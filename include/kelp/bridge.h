/* kelp bridge (the pMOOSBridge role): forwarding variables between communities by UDP.
 *
 * Routes come from static lines in the pMOOSBridge style,
 *   UDPSHARE = [VAR1,VAR2] -> community @ host:port [ALIAS1,ALIAS2]
 * and from run-time requests on PMB_REGISTER (uField seed):
 *   src_var=DEPLOY_ALL,dest_community=henry,dest_host=10.0.0.5,dest_port=9200,dest_alias=DEPLOY
 *
 * Datagram: "KBR1" | u8 flags | kelp.var_t bytes | [32-byte HMAC-SHA256 over all before it]
 * The HMAC is computed by a caller-supplied function (mbedTLS at the edge). With a key
 * configured, a datagram without a valid HMAC is dropped. The core parses and frames; it
 * does no I/O.
 */
#ifndef KELP_BRIDGE_H
#define KELP_BRIDGE_H
#include <stdint.h>
#include <stddef.h>
#include <kelp/bus.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_BRIDGE_MAGIC "KBR1"
#define KELP_BRIDGE_HMAC_LEN 32
#define KELP_BRIDGE_F_AUTH 0x01u

typedef struct kelp_bridge_route {
    char src[KELP_MAX_NAME];          /**< local variable (or glob) */
    char alias[KELP_MAX_NAME];        /**< name at the destination ("" = same) */
    char community[KELP_MAX_NAME];    /**< destination community (informational) */
    char host[KELP_MAX_NAME];
    uint16_t port;
} kelp_bridge_route;

/** Parse one UDPSHARE/SHARE value into up to cap routes. @return 0 and *n, or
 *  KELP_ERR_PARSE with *why set. */
KELP_MUST_CHECK int kelp_bridge_parse_share(const char *line, kelp_bridge_route *routes, size_t cap, size_t *n,
                                            const char **why);
/** Parse a PMB_REGISTER request. */
KELP_MUST_CHECK int kelp_bridge_parse_register(const char *s, kelp_bridge_route *r, const char **why);

/** HMAC-SHA256(key, data) -> out[32]; returns 0 or <0. */
typedef int (*kelp_hmac_fn)(const uint8_t *key, size_t keylen, const uint8_t *data, size_t len, uint8_t out[32],
                            void *user);

/** Frame a var (renamed to `as` when non-empty; flagged BRIDGED) into buf. */
KELP_MUST_CHECK int kelp_bridge_frame(const kelp_var *v, const char *as, const uint8_t *key, size_t keylen,
                                      kelp_hmac_fn hmac, void *user, uint8_t *buf, size_t cap, size_t *len);
/** Check and decode a datagram. With keylen > 0 the HMAC must be present and valid
 *  (KELP_ERR_AUTH otherwise). */
KELP_MUST_CHECK int kelp_bridge_unframe(const uint8_t *buf, size_t len, const uint8_t *key, size_t keylen,
                                        kelp_hmac_fn hmac, void *user, kelp_var *out);
#ifdef __cplusplus
}
#endif

#endif
