/* libFuzzer target for the VN-200 (VectorNav binary output) parser, boards/rover/vn200.c.
 *
 * Each input is used twice:
 *  1. as a raw byte stream, fed whole and in odd chunks: no memory error or UB (ASan,
 *     UBSan, the parser heap-allocated so an overrun of its buffer is caught), every
 *     packet handed out is a complete packet at the front of the buffer whose length
 *     (recomputed here from the group/field bitmasks) fits and whose CRC (an independent CRC,
 *     not the parser's table) is 0, the decoded fields are the bytes of that packet, and
 *     bytes fed = bytes in packets + bytes dropped + bytes still buffered; both feeds give
 *     the same packets and counters.
 *  2. as a recipe: valid packets of any supported group/field configuration with any
 *     field bytes, between runs of garbage, none of it (but the packets' sync and CRC
 *     bytes) equal to the sync byte: every packet must come out, in order, byte for
 *     byte, and exactly the garbage must be counted as dropped.
 * `make -C firmware fuzz && build/fuzz/fuzz_vn200 -max_total_time=600 CORPUS_DIR` */
#include <string.h>

#include "fuzz_util.h"
#include "rover/vn200.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct {
    vn200_parser_t *p;
    uint32_t packets;
    size_t packet_bytes;
    uint64_t hash;
} sink_t;

/* Packet length from the header (0: invalid or unsupported), and where the last copy
 * of each decoded quantity sits (decode order: group, then bit). */
typedef struct {
    size_t at;
    size_t size;
} where_t;

static const struct {
    uint8_t have;
    uint8_t g1, b1, g2, b2; /* the two (group, bit) fields that carry it */
    uint8_t size;
} DECODED[] = {
    {VN200_HAVE_TIME_STARTUP, 1, 0, 2, 0, 8}, {VN200_HAVE_YPR, 1, 3, 5, 1, 12},
    {VN200_HAVE_ANGULAR_RATE, 1, 5, 3, 10, 12}, {VN200_HAVE_POSITION, 1, 6, 6, 1, 24},
    {VN200_HAVE_VELOCITY, 1, 7, 6, 4, 12},     {VN200_HAVE_ACCEL, 1, 8, 3, 9, 12},
    {VN200_HAVE_INS_STATUS, 1, 12, 6, 0, 2},
};
#define N_DECODED (sizeof DECODED / sizeof DECODED[0])

static size_t ref_length(const uint8_t *b, size_t n, where_t w[N_DECODED])
{
    if (n < 2 || b[0] != VN200_SYNC || b[1] == 0 || (b[1] & 0x80u)) {
        return 0;
    }
    size_t idx = 2;
    for (unsigned g = 1; g <= VN200_GROUPS; g++) {
        idx += (b[1] >> (g - 1)) & 1u ? 2u : 0u;
    }
    if (n < idx) {
        return 0;
    }
    size_t mask_at = 2, at = idx;
    for (unsigned g = 1; g <= VN200_GROUPS; g++) {
        if (!((b[1] >> (g - 1)) & 1u)) {
            continue;
        }
        const unsigned mask = (unsigned)(b[mask_at] | (b[mask_at + 1] << 8));
        mask_at += 2;
        if (mask == 0 || (mask & 0x8000u)) {
            return 0;
        }
        for (unsigned bit = 0; bit < 15; bit++) {
            if (!((mask >> bit) & 1u)) {
                continue;
            }
            const unsigned sz = vn200_field_size(g, bit);
            if (sz == 0) {
                return 0;
            }
            for (size_t k = 0; w && k < N_DECODED; k++) {
                if ((g == DECODED[k].g1 && bit == DECODED[k].b1) ||
                    (g == DECODED[k].g2 && bit == DECODED[k].b2)) {
                    FUZZ_CHECK(sz == DECODED[k].size);
                    w[k].at = at;
                    w[k].size = sz;
                }
            }
            at += sz;
        }
    }
    return at + 2;
}

static const void *member(const vn200_ins_t *ins, uint8_t have)
{
    switch (have) {
    case VN200_HAVE_TIME_STARTUP: return &ins->time_startup_ns;
    case VN200_HAVE_YPR: return ins->ypr_deg;
    case VN200_HAVE_ANGULAR_RATE: return ins->angular_rate_rad_s;
    case VN200_HAVE_POSITION: return ins->lla;
    case VN200_HAVE_VELOCITY: return ins->vel_ned_m_s;
    case VN200_HAVE_ACCEL: return ins->accel_m_s2;
    default: return &ins->ins_status;
    }
}

static void on_packet(void *ctx, const vn200_ins_t *ins)
{
    sink_t *s = ctx;
    const vn200_parser_t *p = s->p;
    where_t w[N_DECODED];
    memset(w, 0, sizeof w);
    const size_t total = ref_length(p->buf, p->n, w);
    /* a whole, valid packet sits at the front of the buffer */
    FUZZ_CHECK(total > 0 && total <= p->n && total <= VN200_MAX_PACKET);
    FUZZ_CHECK(fuzz_crc_xmodem(p->buf + 1, total - 1) == 0);
    FUZZ_CHECK(ins->group == p->buf[1]);
    uint8_t present = 0;
    for (size_t k = 0; k < N_DECODED; k++) {
        if (w[k].size) {
            present |= DECODED[k].have;
            /* little-endian host: the decoded value's bytes are the field's bytes */
            FUZZ_CHECK(memcmp(member(ins, DECODED[k].have), p->buf + w[k].at, w[k].size) == 0);
        }
    }
    FUZZ_CHECK(ins->present == present);
    s->packets++;
    s->packet_bytes += total;
    s->hash = fuzz_fnv(s->hash, p->buf, total);
}

static vn200_parser_t *new_parser(sink_t *s)
{
    memset(s, 0, sizeof *s);
    s->hash = FUZZ_FNV_INIT;
    s->p = malloc(sizeof *s->p);
    FUZZ_CHECK(s->p != NULL);
    vn200_parser_init(s->p, on_packet, s);
    return s->p;
}

static void check_accounting(const sink_t *s, size_t fed)
{
    const vn200_parser_t *p = s->p;
    FUZZ_CHECK(p->packets == s->packets);
    FUZZ_CHECK(p->n <= VN200_MAX_PACKET);
    FUZZ_CHECK(s->packet_bytes + p->bytes_dropped + p->n == fed);
    FUZZ_CHECK(p->n == 0 || p->buf[0] == VN200_SYNC);
}

static void raw_stream(const uint8_t *data, size_t size)
{
    sink_t whole, chunked;
    vn200_parser_t *a = new_parser(&whole);
    vn200_parser_t *b = new_parser(&chunked);
    vn200_parser_feed(a, data, size);
    for (size_t at = 0, step = 1; at < size; at += step, step = step * 2 + 1) {
        vn200_parser_feed(b, data + at, step < size - at ? step : size - at);
    }
    check_accounting(&whole, size);
    check_accounting(&chunked, size);
    FUZZ_CHECK(whole.hash == chunked.hash);
    FUZZ_CHECK(a->crc_errors == b->crc_errors && a->bad_headers == b->bad_headers &&
               a->oversize == b->oversize && a->bytes_dropped == b->bytes_dropped && a->n == b->n);
    free(a);
    free(b);
}

/* Fields with a fixed size in group g (1..7): the bits a recipe may set. */
static uint16_t fixed_fields(unsigned g)
{
    uint16_t m = 0;
    for (unsigned bit = 0; bit < 15; bit++) {
        if (vn200_field_size(g, bit)) {
            m = (uint16_t)(m | (1u << bit));
        }
    }
    return m;
}

#define STREAM_CAP 384u /* bounds the work per input (exec/s) */

static void recipe_stream(const uint8_t *data, size_t size)
{
    static uint8_t stream[STREAM_CAP];
    fuzz_reader_t r = {data, size, 0};
    size_t n = 0, garbage = 0;
    uint32_t packets = 0;
    uint64_t hash = FUZZ_FNV_INIT;
    for (int op = 0; op < 48 && r.at < r.size; op++) {
        if (fuzz_u8(&r) & 1u) { /* garbage: up to 31 bytes, never the sync byte */
            const size_t len = fuzz_u8(&r) & 31u;
            for (size_t i = 0; i < len && n < STREAM_CAP; i++) {
                stream[n++] = fuzz_not(&r, VN200_SYNC);
                garbage++;
            }
            continue;
        }
        uint8_t pkt[VN200_MAX_PACKET + 64];
        size_t k = 0;
        pkt[k++] = VN200_SYNC;
        const uint8_t groups = (uint8_t)((fuzz_u8(&r) & 0x7Fu) | 0u);
        pkt[k++] = groups ? groups : 0x01u;
        size_t payload = 0;
        for (unsigned g = 1; g <= VN200_GROUPS; g++) {
            if (!((pkt[1] >> (g - 1)) & 1u)) {
                continue;
            }
            uint16_t mask = (uint16_t)(fuzz_u16(&r) & fixed_fields(g));
            /* no sync byte in the mask (drop low bits until there is none) */
            while ((mask & 0xFFu) == VN200_SYNC || (mask >> 8) == VN200_SYNC) {
                mask = (uint16_t)(mask & (mask - 1u));
            }
            mask = mask ? mask : 1u; /* bit 0 has a fixed size in every group */
            pkt[k++] = (uint8_t)mask;
            pkt[k++] = (uint8_t)(mask >> 8);
            for (unsigned bit = 0; bit < 15; bit++) {
                payload += (mask >> bit) & 1u ? vn200_field_size(g, bit) : 0u;
            }
        }
        if (k + payload + 2 > VN200_MAX_PACKET) {
            continue; /* larger than the parser takes (documented, counted as oversize) */
        }
        for (size_t i = 0; i < payload; i++) {
            pkt[k++] = fuzz_not(&r, VN200_SYNC);
        }
        const uint16_t crc = fuzz_crc_xmodem(pkt + 1, k - 1);
        pkt[k++] = (uint8_t)(crc >> 8);
        pkt[k++] = (uint8_t)crc;
        FUZZ_CHECK(ref_length(pkt, k, NULL) == k);
        if (n + k > STREAM_CAP) {
            break;
        }
        memcpy(stream + n, pkt, k);
        n += k;
        packets++;
        hash = fuzz_fnv(hash, pkt, k);
    }
    sink_t s;
    vn200_parser_t *p = new_parser(&s);
    vn200_parser_feed(p, stream, n);
    check_accounting(&s, n);
    FUZZ_CHECK(s.packets == packets && s.hash == hash);
    FUZZ_CHECK(p->bytes_dropped == garbage && p->n == 0);
    FUZZ_CHECK(p->crc_errors == 0 && p->bad_headers == 0 && p->oversize == 0);
    free(p);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    raw_stream(data, size);
    recipe_stream(data, size);
    return 0;
}
