/* kelp UDP multicast datagrams, wire-compatible with LCM's udpm transport (core).
 *
 * LCM puts a message (channel + payload) on the wire in one of two forms, all integers
 * big-endian:
 *   short     u32 magic "LC02", u32 seqno, channel, NUL, payload          (8-byte header)
 *   fragment  u32 magic "LC03", u32 seqno, u32 msg_size, u32 fragment_offset,
 *             u16 fragment_no, u16 fragments_in_msg                       (20-byte header)
 *             fragment 0: channel, NUL, then payload bytes; others: payload bytes only.
 * msg_size counts payload bytes only and fragment_offset is an offset into the payload.
 * A sender uses the short form while header + channel + NUL + payload fit one datagram
 * (65507 bytes, the IPv4 UDP maximum) and fragments of at most 65487 bytes otherwise.
 * Channel names are at most 63 bytes.
 *
 * This module parses datagrams and reassembles fragmented messages without allocating:
 * the caller supplies the reassembly slots and their byte storage (one message of at most
 * slot_cap bytes per slot). Every header field is checked before it is used; a datagram
 * that fails a check is counted and dropped, never trusted. Fragments may arrive in any
 * order; a duplicate is counted and ignored; a slot that has not completed within the
 * timeout is freed and counted. No clock reads: `now` (seconds) comes in as an argument.
 *
 * Not thread-safe: one thread owns a kelp_udpm_rx.
 */
#ifndef KELP_UDPM_H
#define KELP_UDPM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_UDPM_MAGIC_SHORT 0x4c433032u /**< "LC02" */
#define KELP_UDPM_MAGIC_FRAG 0x4c433033u  /**< "LC03" */
#define KELP_UDPM_SHORT_HDR 8u            /**< bytes in a short-message header */
#define KELP_UDPM_FRAG_HDR 20u            /**< bytes in a fragment header */
#define KELP_UDPM_MAX_DATAGRAM 65507u     /**< largest IPv4 UDP payload: LCM's datagram limit */
#define KELP_UDPM_MAX_CHANNEL 63u         /**< bytes in a channel name, without the NUL */
#define KELP_UDPM_MAX_MESSAGE (1u << 28)  /**< largest payload LCM sends (256 MiB) */

/** A complete message. channel and data point into the datagram just fed or into a
 *  reassembly slot: valid until the next call on the same kelp_udpm_rx. */
typedef struct kelp_udpm_msg {
    const char *channel;
    const uint8_t *data;
    size_t len;
    uint32_t seqno;
    uint64_t sender;
    bool fragmented;
} kelp_udpm_msg;

/** One reassembly slot. The caller provides an array; kelp_udpm_init wires the storage. */
typedef struct kelp_udpm_slot {
    /* private */
    bool used;
    bool have_channel;
    uint64_t sender;
    uint32_t seqno;
    uint32_t size;                    /* msg_size of the message being assembled */
    uint32_t bytes;                   /* payload bytes received so far */
    uint16_t nfrags, nrecv;
    double first;                     /* time the first fragment arrived */
    char channel[KELP_UDPM_MAX_CHANNEL + 1];
    uint8_t seen[(KELP_UDPM_MAX_FRAGS + 7) / 8];
    uint8_t *data;
} kelp_udpm_slot;

typedef struct kelp_udpm_stats {
    uint64_t datagrams;      /**< datagrams fed */
    uint64_t short_msgs;     /**< complete short messages */
    uint64_t frag_msgs;      /**< complete reassembled messages */
    uint64_t fragments;      /**< fragments accepted into a slot */
    uint64_t bad;            /**< datagrams rejected (sum of the reasons below) */
    uint64_t bad_magic;      /**< neither LC02 nor LC03 */
    uint64_t bad_header;     /**< shorter than its header */
    uint64_t bad_channel;    /**< channel missing its NUL, empty or over 63 bytes */
    uint64_t bad_fragment;   /**< fragment number/count/offset/size inconsistent */
    uint64_t too_big;        /**< message larger than a slot */
    uint64_t duplicates;     /**< a fragment already received (ignored) */
    uint64_t timeouts;       /**< slots freed incomplete after the timeout */
    uint64_t evicted;        /**< incomplete slots reused because every slot was busy */
    int last_err;            /**< status of the last rejected datagram */
} kelp_udpm_stats;

typedef struct kelp_udpm_rx {
    /* private */
    kelp_udpm_slot *slots;
    size_t nslots;
    size_t slot_cap;
    double timeout;
    kelp_udpm_stats stats;
} kelp_udpm_rx;

/** @param slots nslots slots; @param mem nslots * slot_cap bytes (slot i uses
 *  mem + i*slot_cap); @param timeout seconds an incomplete message may wait.
 *  nslots may be 0 (short messages only: every fragment is counted too_big).
 *  @return 0 or KELP_ERR_ARG. */
KELP_MUST_CHECK int kelp_udpm_init(kelp_udpm_rx *r, kelp_udpm_slot *slots, size_t nslots, uint8_t *mem,
                                   size_t slot_cap, double timeout);

/** Feed one datagram received from `sender` (any stable id of the source address).
 *  @return 1 with *out filled when a message is complete, 0 when the datagram was a
 *  fragment of a message still incomplete (or a duplicate), or a negative kelp_err when it
 *  was rejected (counted in stats): KELP_ERR_TRUNCATED (short header), KELP_ERR_PARSE
 *  (magic, channel), KELP_ERR_RANGE (fragment fields, size over slot_cap). Safe on
 *  arbitrary bytes. */
KELP_MUST_CHECK int kelp_udpm_feed(kelp_udpm_rx *r, const uint8_t *dg, size_t len, uint64_t sender, kelp_time now,
                   kelp_udpm_msg *out);

/** Free slots idle for longer than the timeout. @return how many were freed. */
size_t kelp_udpm_expire(kelp_udpm_rx *r, kelp_time now);

const kelp_udpm_stats *kelp_udpm_get_stats(const kelp_udpm_rx *r);

/* ------------------------------------------------------------------ sending */

/** How a message of `len` payload bytes on a channel of `chanlen` bytes goes on the wire
 *  with datagrams of at most max_datagram bytes (KELP_UDPM_MAX_DATAGRAM for LCM).
 *  @param[out] nfrags 0 for the short form, else the fragment count.
 *  @return 0, KELP_ERR_RANGE (channel over 63 bytes, payload over KELP_UDPM_MAX_MESSAGE or
 *  over 65535 fragments), KELP_ERR_ARG (max_datagram too small for the channel). */
KELP_MUST_CHECK int kelp_udpm_plan(size_t chanlen, size_t len, size_t max_datagram, uint16_t *nfrags);

/** Header of a short message (8 bytes). */
void kelp_udpm_put_short_header(uint8_t out[KELP_UDPM_SHORT_HDR], uint32_t seqno);
/** Header of a fragment (20 bytes). */
void kelp_udpm_put_frag_header(uint8_t out[KELP_UDPM_FRAG_HDR], uint32_t seqno, uint32_t msg_size,
                               uint32_t offset, uint16_t frag_no, uint16_t nfrags);

/** Write datagram k of a message (k = 0 for the short form) as LCM lays it out.
 *  Offsets follow kelp_udpm_plan with the same max_datagram.
 *  @return 0, KELP_ERR_NOSPACE (cap), KELP_ERR_RANGE/KELP_ERR_ARG as kelp_udpm_plan or k
 *  out of range. */
KELP_MUST_CHECK int kelp_udpm_datagram(const char *channel, const uint8_t *data, size_t len, uint32_t seqno,
                                       size_t max_datagram, uint16_t k, uint8_t *buf, size_t cap, size_t *out_len);

/* ------------------------------------------------------------------ URLs */

/** A parsed udpm URL: udpm://A.B.C.D:PORT?ttl=N&recv_buf_size=BYTES&queue_size=BYTES&send_buf_size=BYTES
 *  (the LCM form; queue_size and send_buf_size are kelp's: bytes of the receive queue, and
 *  the SO_SNDBUF a publisher of many thousand messages a second asks for). */
typedef struct kelp_udpm_url {
    uint32_t group;          /**< IPv4 multicast group, host order */
    uint16_t port;
    int ttl;                 /**< 0..255; LCM's default is 0 */
    long recv_buf_size;      /**< SO_RCVBUF request, 0 = not given */
    long queue_size;         /**< receive queue bytes, 0 = not given */
    long send_buf_size;      /**< SO_SNDBUF request, 0 = not given (the kernel's default) */
    int gso;                 /**< kelp's gso=0|1: segmented sends of a corked batch (1 unless gso=0) */
} kelp_udpm_url;

/** Most zero bytes a publisher may append to a short message's payload (kelp's segmented
 *  sends pad the datagrams of one send to one size; LCM decoders read their fields and stop,
 *  kelp's decoders accept at most this many trailing zero bytes). */
#define KELP_UDPM_PAD_MAX 64u

/** Whether buf[off, len) is nothing or a publisher's padding: at most KELP_UDPM_PAD_MAX zero
 *  bytes (what a message's decoder may leave after its last field). */
static inline bool kelp_udpm_padding_only(const uint8_t *buf, size_t off, size_t len)
{
    if (off > len || len - off > KELP_UDPM_PAD_MAX) return false;
    for (size_t i = off; i < len; i++)
        if (buf[i]) return false;
    return true;
}

#define KELP_UDPM_DEFAULT_PORT 7667u

/** Parse a udpm URL. The group must be a multicast address (224.0.0.0/4); a missing port
 *  is LCM's 7667; the options are ttl, recv_buf_size, queue_size, send_buf_size, gso and LCM's obsolete
 *  transmit_only (ignored). @return 0, KELP_ERR_UNSUPPORTED (not udpm://), KELP_ERR_PARSE
 *  (address, port, option, unknown key), KELP_ERR_RANGE (a value out of range). */
KELP_MUST_CHECK int kelp_udpm_url_parse(const char *url, kelp_udpm_url *out);

#define KELP_UDPM_DEFAULT_GROUP "239.255.76.67"

/** The URL of a community from its mission: lcm_url when given (non-empty), else
 *  udpm://239.255.76.67:<server_port>?ttl=0 when server_port is given -- one port per
 *  community, the number MOOS users already give each community as its ServerPort -- else
 *  NULL is written as "" and 0 returned so the caller uses its default.
 *  @return 0, KELP_ERR_RANGE (server_port not an integer in 1..65535 or lcm_url not a
 *  valid udpm URL), KELP_ERR_NOSPACE. */
KELP_MUST_CHECK int kelp_udpm_community_url(const char *lcm_url, const char *server_port, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
