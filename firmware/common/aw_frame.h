/*
 * airwake framing: CRC-16, COBS frame encoder and the streaming frame decoder.
 *
 * On the wire a frame is 0x00, COBS(msg_id u8 | seq u8 | flags u8 | board_time_us u32 |
 * payload | crc u16), 0x00 — all little-endian. The CRC is CRC-16/CCITT-FALSE's body
 * (poly 0x1021, MSB first, no reflection, no xorout) started from the message's seed
 * (the 16-bit fold of its definition hash) over msg_id..payload. docs/protocol.md is the
 * specification. No heap; the decoder is one fixed-size struct.
 */
#ifndef AW_FRAME_H
#define AW_FRAME_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "aw_messages.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    uint8_t msg_id;
    uint8_t seq;   /* per (origin board, msg_id), wraps at 256 */
    uint8_t flags; /* bits 0-2 origin board id; bits 3-7 reserved (0) */
    uint32_t board_time_us;
} aw_header_t;

/* CRC-16/CCITT-FALSE body over data, continuing from crc (a seed for a new frame). */
uint16_t aw_crc16(uint16_t crc, const uint8_t *data, size_t len);

/* The CRC seed of a definition hash: (h >> 16) ^ (h & 0xFFFF). */
static inline uint16_t aw_crc_seed(uint32_t def_hash)
{
    return (uint16_t)((def_hash >> 16) ^ (def_hash & 0xFFFFu));
}

/* Longest wire form of a frame with `payload_len` payload bytes (both delimiters). */
static inline size_t aw_wire_max(size_t payload_len)
{
    const size_t raw = payload_len + AW_FRAME_OVERHEAD;
    return raw + (raw + 253u) / 254u + 2u;
}

/*
 * Encode one frame into out: returns its length, or AW_ERR_NO_SPACE when
 * cap < aw_wire_max(len) (use AW_WIRE_MAX_<MSG> or AW_MAX_WIRE_SIZE buffers),
 * AW_ERR_UNKNOWN_ID, or AW_ERR_SIZE when len is not the message's payload size.
 */
int aw_frame_encode(uint8_t *out, size_t cap, const aw_header_t *h, const uint8_t *payload,
                    size_t len);

/* Same with an explicit CRC seed and no id/size check (tests, foreign definitions). */
int aw_frame_encode_seeded(uint8_t *out, size_t cap, const aw_header_t *h,
                           const uint8_t *payload, size_t len, uint16_t crc_seed);

/* What happened to every non-empty segment between two 0x00 bytes: exactly one of the
 * first six counts it. bytes_dropped: encoded bytes of segments not delivered. */
typedef struct {
    uint32_t frames_ok;
    uint32_t crc_error;    /* corrupt: CRC fails (or wrong length) and no announced match */
    uint32_t unknown_id;   /* msg_id not in this schema */
    uint32_t def_mismatch; /* intact under the sender's announced definition hash */
    uint32_t oversize;     /* longer than AW_MAX_ENCODED_SIZE */
    uint32_t cobs_error;   /* not valid COBS, or shorter than header + CRC */
    uint32_t bytes_dropped;
} aw_counters_t;

typedef struct {
    aw_header_t header;
    const uint8_t *payload; /* valid until the next byte is fed */
    size_t payload_len;
} aw_frame_t;

typedef void (*aw_frame_handler_t)(void *ctx, const aw_frame_t *frame);

typedef struct {
    aw_counters_t counters;
    aw_frame_handler_t on_frame; /* for aw_decoder_feed; may be NULL */
    void *ctx;
    /* Definition hashes the peer announced (schema_entry), by aw_msg_index row. */
    uint32_t announced_hash[AW_MSG_COUNT];
    bool announced[AW_MSG_COUNT];
    uint32_t enc_len; /* encoded bytes of the current segment (saturating) */
    uint16_t len;     /* decoded bytes in buf */
    uint8_t code_left;
    uint8_t code;
    uint8_t buf[AW_MAX_ENCODED_SIZE];
} aw_decoder_t;

void aw_decoder_init(aw_decoder_t *d, aw_frame_handler_t on_frame, void *ctx);

/* Poll form: feed one byte; true when it completed a frame, then *frame is filled. */
bool aw_decoder_feed_byte(aw_decoder_t *d, uint8_t byte, aw_frame_t *frame);

/* Buffer form: feed len bytes, call on_frame for each frame; returns frames delivered. */
size_t aw_decoder_feed(aw_decoder_t *d, const uint8_t *data, size_t len);

/* Record the peer's definition hash for msg_id (decoded schema_entry frames do this). */
void aw_decoder_announce(aw_decoder_t *d, uint8_t msg_id, uint32_t def_hash);

#ifdef __cplusplus
}
#endif

#endif /* AW_FRAME_H */
