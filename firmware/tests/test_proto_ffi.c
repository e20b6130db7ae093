/* Entry points for the Python cross-language tests (ctypes over build/native/libawproto.so).
 * The generated aw_encode_msg / aw_unpack_msg / aw_msg_info are exported as they are;
 * these add a struct-size lookup and a whole-stream decode. */
#include <string.h>

#include "aw_frame.h"

/* sizeof(aw_<name>_t) for msg_id, 0 when unknown (ctypes checks its layout against it). */
size_t awffi_struct_size(uint8_t msg_id)
{
    const aw_msg_info_t *info = aw_msg_info(msg_id);
    return info == NULL ? 0 : info->struct_size;
}

/*
 * Decode a whole byte stream with a fresh decoder. Each delivered frame is written to
 * out as msg_id u8 | seq u8 | flags u8 | board_time_us u32 LE | payload_len u16 LE |
 * payload. counters receives aw_counters_t in declaration order (7 x u32). Returns the
 * number of frames, or -1 when out is too small.
 */
long awffi_decode(const uint8_t *data, size_t len, uint8_t *out, size_t cap,
                  uint32_t counters[7])
{
    aw_decoder_t d;
    aw_decoder_init(&d, NULL, NULL);
    size_t pos = 0;
    long frames = 0;
    for (size_t i = 0; i < len; ++i) {
        aw_frame_t f;
        if (!aw_decoder_feed_byte(&d, data[i], &f)) {
            continue;
        }
        if (pos + 9 + f.payload_len > cap) {
            return -1;
        }
        out[pos] = f.header.msg_id;
        out[pos + 1] = f.header.seq;
        out[pos + 2] = f.header.flags;
        aw_put_u32(out + pos + 3, f.header.board_time_us);
        aw_put_u16(out + pos + 7, (uint16_t)f.payload_len);
        memcpy(out + pos + 9, f.payload, f.payload_len);
        pos += 9 + f.payload_len;
        ++frames;
    }
    const aw_counters_t *c = &d.counters;
    const uint32_t values[7] = {c->frames_ok, c->crc_error, c->unknown_id, c->def_mismatch,
                                c->oversize, c->cobs_error, c->bytes_dropped};
    memcpy(counters, values, sizeof values);
    return frames;
}
