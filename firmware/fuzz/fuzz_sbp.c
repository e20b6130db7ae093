/* libFuzzer target for the SBP (Swift Binary Protocol) parser, boards/rover/sbp.c.
 *
 * Each input is used twice:
 *  1. as a raw byte stream, fed whole and in odd chunks: no memory error or UB (ASan,
 *     UBSan, the parser heap-allocated so an overrun of its buffer is caught), every
 *     frame handed out is the whole frame at the front of the buffer, of a non-zero
 *     type, its length byte's size, with a CRC (an independent one, not the parser's) that
 *     matches; a decoded payload agrees with the bytes; bytes fed = bytes in frames +
 *     bytes dropped + bytes still buffered; both feeds give the same frames and counters.
 *  2. as a recipe: valid frames (any type but 0, sender, length and payload) between
 *     runs of garbage, none of it (but the preamble and the CRC bytes) equal to 0x55:
 *     every frame must come out, in order, byte for byte, and exactly the garbage must be
 *     counted as dropped.
 * `make -C firmware fuzz && build/fuzz/fuzz_sbp -max_total_time=600 CORPUS_DIR` */
#include <string.h>

#include "fuzz_util.h"
#include "rover/sbp.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct {
    sbp_parser_t *p;
    uint32_t frames;
    size_t frame_bytes;
    uint64_t hash;
} sink_t;

static void on_frame(void *ctx, const sbp_msg_t *m)
{
    sink_t *s = ctx;
    const sbp_parser_t *p = s->p;
    FUZZ_CHECK(p->n >= 8 && p->buf[0] == SBP_PREAMBLE);
    const size_t total = 6u + p->buf[5] + 2u;
    FUZZ_CHECK(total <= p->n && total <= SBP_MAX_FRAME);
    const uint16_t crc = (uint16_t)(p->buf[total - 2] | (p->buf[total - 1] << 8));
    FUZZ_CHECK(fuzz_crc_xmodem(p->buf + 1, total - 3) == crc);
    FUZZ_CHECK(m->msg_type != 0);
    FUZZ_CHECK(m->msg_type == (p->buf[1] | (p->buf[2] << 8)));
    FUZZ_CHECK(m->sender == (p->buf[3] | (p->buf[4] << 8)));
    FUZZ_CHECK(m->length == p->buf[5] && m->payload == p->buf + 6);
    /* the decode is a pure function of (type, payload) and its first field's bytes */
    sbp_msg_t again;
    memset(&again, 0, sizeof again);
    FUZZ_CHECK(sbp_decode_payload(m->msg_type, m->payload, m->length, &again) == m->decoded);
    if (m->decoded) {
        FUZZ_CHECK(memcmp(&again.m, &m->m, sizeof m->m) == 0);
        uint32_t tow = 0;
        switch (m->msg_type) {
        case SBP_MSG_BASELINE_NED: tow = m->m.baseline_ned.tow; break;
        case SBP_MSG_VEL_NED: tow = m->m.vel_ned.tow; break;
        case SBP_MSG_POS_LLH: tow = m->m.pos_llh.tow; break;
        case SBP_MSG_BASELINE_ECEF: tow = m->m.baseline_ecef.tow; break;
        case SBP_MSG_DOPS: tow = m->m.dops.tow; break;
        case SBP_MSG_IMU_RAW: tow = m->m.imu_raw.tow; break;
        case SBP_MSG_GPS_TIME: tow = m->m.gps_time.tow; break;
        default: tow = m->m.utc_time.tow; break;
        }
        const size_t at = m->msg_type == SBP_MSG_GPS_TIME ? 2u
                          : m->msg_type == SBP_MSG_UTC_TIME ? 1u
                                                             : 0u;
        FUZZ_CHECK(memcmp(&tow, m->payload + at, 4) == 0); /* little-endian host */
    }
    s->frames++;
    s->frame_bytes += total;
    s->hash = fuzz_fnv(s->hash, p->buf, total);
}

static sbp_parser_t *new_parser(sink_t *s)
{
    memset(s, 0, sizeof *s);
    s->hash = FUZZ_FNV_INIT;
    s->p = malloc(sizeof *s->p);
    FUZZ_CHECK(s->p != NULL);
    sbp_parser_init(s->p, on_frame, s);
    return s->p;
}

static void check_accounting(const sink_t *s, size_t fed)
{
    const sbp_parser_t *p = s->p;
    FUZZ_CHECK(p->frames == s->frames);
    FUZZ_CHECK(p->undecoded + p->bad_length <= p->frames);
    FUZZ_CHECK(p->n < SBP_MAX_FRAME);
    FUZZ_CHECK(s->frame_bytes + p->bytes_dropped + p->n == fed);
    FUZZ_CHECK(p->n == 0 || p->buf[0] == SBP_PREAMBLE);
}

static void raw_stream(const uint8_t *data, size_t size)
{
    sink_t whole, chunked;
    sbp_parser_t *a = new_parser(&whole);
    sbp_parser_t *b = new_parser(&chunked);
    sbp_parser_feed(a, data, size);
    for (size_t at = 0, step = 1; at < size; at += step, step = step * 2 + 1) {
        sbp_parser_feed(b, data + at, step < size - at ? step : size - at);
    }
    check_accounting(&whole, size);
    check_accounting(&chunked, size);
    FUZZ_CHECK(whole.hash == chunked.hash);
    FUZZ_CHECK(a->crc_errors == b->crc_errors && a->undecoded == b->undecoded &&
               a->bad_length == b->bad_length && a->bytes_dropped == b->bytes_dropped &&
               a->n == b->n);
    free(a);
    free(b);
}

#define STREAM_CAP 384u /* bounds the work per input (exec/s) */

/* The message types the parser decodes, so recipes reach the decoders often. */
static const uint16_t KNOWN[] = {SBP_MSG_GPS_TIME, SBP_MSG_UTC_TIME,      SBP_MSG_DOPS,
                                 SBP_MSG_POS_LLH,  SBP_MSG_BASELINE_ECEF, SBP_MSG_BASELINE_NED,
                                 SBP_MSG_VEL_NED,  SBP_MSG_IMU_RAW};
static const uint8_t KNOWN_LEN[] = {11, 16, 15, 34, 20, 22, 22, 17};

static void recipe_stream(const uint8_t *data, size_t size)
{
    static uint8_t stream[STREAM_CAP];
    fuzz_reader_t r = {data, size, 0};
    size_t n = 0, garbage = 0;
    uint32_t frames = 0;
    uint64_t hash = FUZZ_FNV_INIT;
    for (int op = 0; op < 48 && r.at < r.size; op++) {
        const uint8_t what = fuzz_u8(&r);
        if (what & 1u) { /* garbage: up to 31 bytes, never the preamble */
            const size_t len = fuzz_u8(&r) & 31u;
            for (size_t i = 0; i < len && n < STREAM_CAP; i++) {
                stream[n++] = fuzz_not(&r, SBP_PREAMBLE);
                garbage++;
            }
            continue;
        }
        uint8_t f[SBP_MAX_FRAME];
        f[0] = SBP_PREAMBLE;
        uint16_t type;
        uint8_t len;
        if (what & 2u) { /* a decoded type with its length */
            const size_t k = (what >> 2) % (sizeof KNOWN / sizeof KNOWN[0]);
            type = KNOWN[k];
            len = KNOWN_LEN[k];
        } else {
            f[1] = fuzz_not(&r, SBP_PREAMBLE);
            f[2] = fuzz_not(&r, SBP_PREAMBLE);
            type = (uint16_t)(f[1] | (f[2] << 8));
            type = type ? type : 1u;
            len = fuzz_not(&r, SBP_PREAMBLE);
        }
        f[1] = (uint8_t)type;
        f[2] = (uint8_t)(type >> 8);
        f[3] = fuzz_not(&r, SBP_PREAMBLE);
        f[4] = fuzz_not(&r, SBP_PREAMBLE);
        f[5] = len;
        for (size_t i = 0; i < len; i++) {
            f[6 + i] = fuzz_not(&r, SBP_PREAMBLE);
        }
        const size_t total = 6u + len + 2u;
        const uint16_t crc = fuzz_crc_xmodem(f + 1, 5u + len);
        f[6 + len] = (uint8_t)crc;
        f[7 + len] = (uint8_t)(crc >> 8);
        if (n + total > STREAM_CAP) {
            break;
        }
        memcpy(stream + n, f, total);
        n += total;
        frames++;
        hash = fuzz_fnv(hash, f, total);
    }
    sink_t s;
    sbp_parser_t *p = new_parser(&s);
    sbp_parser_feed(p, stream, n);
    check_accounting(&s, n);
    FUZZ_CHECK(s.frames == frames && s.hash == hash);
    FUZZ_CHECK(p->bytes_dropped == garbage && p->n == 0 && p->crc_errors == 0);
    free(p);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    raw_stream(data, size);
    recipe_stream(data, size);
    return 0;
}
