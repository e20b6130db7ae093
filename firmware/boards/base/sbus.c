/* SBUS decoder, see sbus.h. */
#include "sbus.h"

#include <string.h>

static int footer_ok(uint8_t b)
{
    return b == 0x00u || (b & 0x0Fu) == 0x04u;
}

int sbus_decode(const uint8_t frame[SBUS_FRAME_LEN], sbus_frame_t *out)
{
    if (frame[0] != SBUS_HEADER || !footer_ok(frame[24])) {
        return 0;
    }
    const uint8_t *d = frame + 1;
    uint32_t acc = 0;
    unsigned bits = 0;
    unsigned ch = 0;
    for (unsigned i = 0; i < 22u && ch < SBUS_CHANNELS; i++) {
        acc |= (uint32_t)d[i] << bits;
        bits += 8u;
        if (bits >= 11u) {
            const uint16_t raw = (uint16_t)(acc & 0x7FFu);
            out->raw[ch] = raw;
            out->width_us[ch] = (uint16_t)(raw * 5u / 8u + 875u);
            ch++;
            acc >>= 11;
            bits -= 11u;
        }
    }
    out->flags = frame[23];
    return 1;
}

void sbus_parser_init(sbus_parser_t *p)
{
    memset(p, 0, sizeof *p);
}

void sbus_parser_gap(sbus_parser_t *p)
{
    p->bytes_dropped += (uint32_t)p->n;
    p->n = 0;
}

int sbus_parser_feed(sbus_parser_t *p, uint8_t byte, sbus_frame_t *out)
{
    if (p->n == 0 && byte != SBUS_HEADER) {
        p->bytes_dropped++;
        return 0;
    }
    p->buf[p->n++] = byte;
    while (p->n == SBUS_FRAME_LEN) {
        if (sbus_decode(p->buf, out)) {
            p->n = 0;
            p->frames++;
            return 1;
        }
        /* misaligned: rescan from the next header byte */
        p->bad_frames++;
        size_t k = 1;
        while (k < p->n && p->buf[k] != SBUS_HEADER) {
            k++;
        }
        p->bytes_dropped += (uint32_t)k;
        memmove(p->buf, p->buf + k, p->n - k);
        p->n -= k;
    }
    return 0;
}
