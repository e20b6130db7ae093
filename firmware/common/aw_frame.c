/* airwake framing: CRC-16, COBS frame encoder, streaming decoder (see aw_frame.h). */
#include "aw_frame.h"

/* CRC-16/CCITT-FALSE table (poly 0x1021, MSB first); test_proto_framing checks it. */
static const uint16_t crc_table[256] = {
    0x0000, 0x1021, 0x2042, 0x3063, 0x4084, 0x50A5, 0x60C6, 0x70E7,
    0x8108, 0x9129, 0xA14A, 0xB16B, 0xC18C, 0xD1AD, 0xE1CE, 0xF1EF,
    0x1231, 0x0210, 0x3273, 0x2252, 0x52B5, 0x4294, 0x72F7, 0x62D6,
    0x9339, 0x8318, 0xB37B, 0xA35A, 0xD3BD, 0xC39C, 0xF3FF, 0xE3DE,
    0x2462, 0x3443, 0x0420, 0x1401, 0x64E6, 0x74C7, 0x44A4, 0x5485,
    0xA56A, 0xB54B, 0x8528, 0x9509, 0xE5EE, 0xF5CF, 0xC5AC, 0xD58D,
    0x3653, 0x2672, 0x1611, 0x0630, 0x76D7, 0x66F6, 0x5695, 0x46B4,
    0xB75B, 0xA77A, 0x9719, 0x8738, 0xF7DF, 0xE7FE, 0xD79D, 0xC7BC,
    0x48C4, 0x58E5, 0x6886, 0x78A7, 0x0840, 0x1861, 0x2802, 0x3823,
    0xC9CC, 0xD9ED, 0xE98E, 0xF9AF, 0x8948, 0x9969, 0xA90A, 0xB92B,
    0x5AF5, 0x4AD4, 0x7AB7, 0x6A96, 0x1A71, 0x0A50, 0x3A33, 0x2A12,
    0xDBFD, 0xCBDC, 0xFBBF, 0xEB9E, 0x9B79, 0x8B58, 0xBB3B, 0xAB1A,
    0x6CA6, 0x7C87, 0x4CE4, 0x5CC5, 0x2C22, 0x3C03, 0x0C60, 0x1C41,
    0xEDAE, 0xFD8F, 0xCDEC, 0xDDCD, 0xAD2A, 0xBD0B, 0x8D68, 0x9D49,
    0x7E97, 0x6EB6, 0x5ED5, 0x4EF4, 0x3E13, 0x2E32, 0x1E51, 0x0E70,
    0xFF9F, 0xEFBE, 0xDFDD, 0xCFFC, 0xBF1B, 0xAF3A, 0x9F59, 0x8F78,
    0x9188, 0x81A9, 0xB1CA, 0xA1EB, 0xD10C, 0xC12D, 0xF14E, 0xE16F,
    0x1080, 0x00A1, 0x30C2, 0x20E3, 0x5004, 0x4025, 0x7046, 0x6067,
    0x83B9, 0x9398, 0xA3FB, 0xB3DA, 0xC33D, 0xD31C, 0xE37F, 0xF35E,
    0x02B1, 0x1290, 0x22F3, 0x32D2, 0x4235, 0x5214, 0x6277, 0x7256,
    0xB5EA, 0xA5CB, 0x95A8, 0x8589, 0xF56E, 0xE54F, 0xD52C, 0xC50D,
    0x34E2, 0x24C3, 0x14A0, 0x0481, 0x7466, 0x6447, 0x5424, 0x4405,
    0xA7DB, 0xB7FA, 0x8799, 0x97B8, 0xE75F, 0xF77E, 0xC71D, 0xD73C,
    0x26D3, 0x36F2, 0x0691, 0x16B0, 0x6657, 0x7676, 0x4615, 0x5634,
    0xD94C, 0xC96D, 0xF90E, 0xE92F, 0x99C8, 0x89E9, 0xB98A, 0xA9AB,
    0x5844, 0x4865, 0x7806, 0x6827, 0x18C0, 0x08E1, 0x3882, 0x28A3,
    0xCB7D, 0xDB5C, 0xEB3F, 0xFB1E, 0x8BF9, 0x9BD8, 0xABBB, 0xBB9A,
    0x4A75, 0x5A54, 0x6A37, 0x7A16, 0x0AF1, 0x1AD0, 0x2AB3, 0x3A92,
    0xFD2E, 0xED0F, 0xDD6C, 0xCD4D, 0xBDAA, 0xAD8B, 0x9DE8, 0x8DC9,
    0x7C26, 0x6C07, 0x5C64, 0x4C45, 0x3CA2, 0x2C83, 0x1CE0, 0x0CC1,
    0xEF1F, 0xFF3E, 0xCF5D, 0xDF7C, 0xAF9B, 0xBFBA, 0x8FD9, 0x9FF8,
    0x6E17, 0x7E36, 0x4E55, 0x5E74, 0x2E93, 0x3EB2, 0x0ED1, 0x1EF0
};

uint16_t aw_crc16(uint16_t crc, const uint8_t *data, size_t len)
{
    for (size_t i = 0; i < len; ++i) {
        crc = (uint16_t)((crc << 8) ^ crc_table[(uint8_t)((crc >> 8) ^ data[i])]);
    }
    return crc;
}

/* ---- encoder ---- */

/* COBS writer over a buffer already checked to hold the worst case. */
typedef struct {
    uint8_t *out;
    size_t pos;      /* next free byte */
    size_t code_pos; /* where the current block's code byte goes */
    uint8_t code;    /* 1 + data bytes in the current block */
    bool last_full;  /* the previous block was a full 0xFF block */
    uint16_t crc;
} cobs_writer_t;

static void cw_start(cobs_writer_t *w, uint8_t *out, uint16_t seed)
{
    out[0] = 0x00; /* leading delimiter: a cut frame before this one cannot swallow it */
    w->out = out;
    w->code_pos = 1;
    w->pos = 2;
    w->code = 1;
    w->last_full = false;
    w->crc = seed;
}

static void cw_byte(cobs_writer_t *w, uint8_t b)
{
    w->last_full = false;
    if (b != 0) {
        w->out[w->pos++] = b;
        if (++w->code != 0xFF) {
            return;
        }
        w->last_full = true;
    }
    w->out[w->code_pos] = w->code;
    w->code_pos = w->pos++;
    w->code = 1;
}

static void cw_bytes_crc(cobs_writer_t *w, const uint8_t *data, size_t len)
{
    w->crc = aw_crc16(w->crc, data, len);
    for (size_t i = 0; i < len; ++i) {
        cw_byte(w, data[i]);
    }
}

static size_t cw_finish(cobs_writer_t *w)
{
    uint8_t crc[2];
    aw_put_u16(crc, w->crc);
    cw_byte(w, crc[0]);
    cw_byte(w, crc[1]);
    if (w->last_full) {
        w->pos = w->code_pos; /* no empty block after a full block that ends the frame */
    } else {
        w->out[w->code_pos] = w->code;
    }
    w->out[w->pos++] = 0x00;
    return w->pos;
}

int aw_frame_encode_seeded(uint8_t *out, size_t cap, const aw_header_t *h,
                           const uint8_t *payload, size_t len, uint16_t crc_seed)
{
    if (cap < aw_wire_max(len) || len > (size_t)INT32_MAX / 2) {
        return AW_ERR_NO_SPACE;
    }
    uint8_t head[AW_HEADER_SIZE];
    head[0] = h->msg_id;
    head[1] = h->seq;
    head[2] = h->flags;
    aw_put_u32(head + 3, h->board_time_us);
    cobs_writer_t w;
    cw_start(&w, out, crc_seed);
    cw_bytes_crc(&w, head, sizeof head);
    cw_bytes_crc(&w, payload, len);
    return (int)cw_finish(&w);
}

int aw_frame_encode(uint8_t *out, size_t cap, const aw_header_t *h, const uint8_t *payload,
                    size_t len)
{
    const aw_msg_info_t *info = aw_msg_info(h->msg_id);
    if (info == NULL) {
        return AW_ERR_UNKNOWN_ID;
    }
    if (len != info->payload_size) {
        return AW_ERR_SIZE;
    }
    return aw_frame_encode_seeded(out, cap, h, payload, len, info->crc_seed);
}

/* ---- decoder ---- */

void aw_decoder_init(aw_decoder_t *d, aw_frame_handler_t on_frame, void *ctx)
{
    *d = (aw_decoder_t){.on_frame = on_frame, .ctx = ctx};
}

void aw_decoder_announce(aw_decoder_t *d, uint8_t msg_id, uint32_t def_hash)
{
    const int row = aw_msg_index(msg_id);
    if (row >= 0) {
        d->announced_hash[row] = def_hash;
        d->announced[row] = true;
    }
}

static bool drop(aw_decoder_t *d, uint32_t *counter)
{
    ++*counter;
    d->counters.bytes_dropped += d->enc_len;
    return false;
}

/* Classify the completed segment in d (see docs/protocol.md, "Receiving"). */
static bool finish_segment(aw_decoder_t *d, aw_frame_t *frame)
{
    aw_counters_t *c = &d->counters;
    if (d->enc_len > AW_MAX_ENCODED_SIZE) {
        return drop(d, &c->oversize);
    }
    if (d->code_left != 0 || d->len < AW_FRAME_OVERHEAD) {
        return drop(d, &c->cobs_error);
    }
    const int row = aw_msg_index(d->buf[0]);
    if (row < 0) {
        return drop(d, &c->unknown_id);
    }
    const aw_msg_info_t *info = &aw_msg_table[row];
    const size_t body = (size_t)d->len - AW_CRC_SIZE;
    uint16_t crc_rx;
    aw_get_u16(&crc_rx, d->buf + body);
    if (d->len == info->payload_size + AW_FRAME_OVERHEAD &&
        aw_crc16(info->crc_seed, d->buf, body) == crc_rx) {
        ++c->frames_ok;
        frame->header.msg_id = d->buf[0];
        frame->header.seq = d->buf[1];
        frame->header.flags = d->buf[2];
        aw_get_u32(&frame->header.board_time_us, d->buf + 3);
        frame->payload = d->buf + AW_HEADER_SIZE;
        frame->payload_len = info->payload_size;
        if (frame->header.msg_id == AW_ID_SCHEMA_ENTRY) {
            uint32_t hash;
            aw_get_u32(&hash, frame->payload + 1);
            aw_decoder_announce(d, frame->payload[0], hash);
        }
        return true;
    }
    if (d->announced[row] && d->announced_hash[row] != info->def_hash &&
        aw_crc16(aw_crc_seed(d->announced_hash[row]), d->buf, body) == crc_rx) {
        return drop(d, &c->def_mismatch);
    }
    return drop(d, &c->crc_error);
}

bool aw_decoder_feed_byte(aw_decoder_t *d, uint8_t byte, aw_frame_t *frame)
{
    if (byte != 0) {
        if (d->enc_len == UINT32_MAX) {
            return false;
        }
        if (++d->enc_len > AW_MAX_ENCODED_SIZE) {
            return false; /* oversize: count bytes until the delimiter */
        }
        if (d->code_left != 0) {
            d->buf[d->len++] = byte;
            --d->code_left;
        } else {
            /* A code byte; the block before it implies a zero unless it was full. */
            if (d->enc_len > 1 && d->code != 0xFF) {
                d->buf[d->len++] = 0;
            }
            d->code = byte;
            d->code_left = (uint8_t)(byte - 1);
        }
        return false;
    }
    if (d->enc_len == 0) {
        return false; /* empty segment: back-to-back delimiters */
    }
    const bool ok = finish_segment(d, frame);
    d->enc_len = 0;
    d->len = 0;
    d->code_left = 0;
    d->code = 0;
    return ok;
}

/* Copy what is left of the current COBS block straight into buf, up to a zero (the
 * delimiter) or the end of the input: the per-byte state machine then only sees code
 * bytes and delimiters. Returns the bytes consumed. */
static size_t copy_block(aw_decoder_t *d, const uint8_t *src, size_t avail)
{
    size_t n = d->code_left < avail ? d->code_left : avail;
    if (d->enc_len + n > AW_MAX_ENCODED_SIZE) {
        return 0; /* oversize: leave it to the byte path's counting */
    }
    uint8_t *dst = d->buf + d->len;
    size_t k = 0;
    while (k < n && src[k] != 0) {
        dst[k] = src[k];
        ++k;
    }
    d->len = (uint16_t)(d->len + k);
    d->enc_len += (uint32_t)k;
    d->code_left = (uint8_t)(d->code_left - k);
    return k;
}

size_t aw_decoder_feed(aw_decoder_t *d, const uint8_t *data, size_t len)
{
    size_t delivered = 0;
    aw_frame_t frame;
    size_t i = 0;
    while (i < len) {
        if (d->code_left != 0) {
            i += copy_block(d, data + i, len - i);
            if (i == len) {
                break;
            }
        }
        if (aw_decoder_feed_byte(d, data[i++], &frame)) {
            ++delivered;
            if (d->on_frame != NULL) {
                d->on_frame(d->ctx, &frame);
            }
        }
    }
    return delivered;
}
