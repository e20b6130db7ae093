/* libFuzzer target for the streaming decoder (common/aw_frame.c): any input, fed whole
 * and in odd chunks, must be handled without memory errors or UB; the counters must
 * account for every segment and byte (bytes in delivered segments + bytes dropped +
 * delimiters + the open segment = bytes fed) and agree between the two feeds; every
 * delivered frame has its message's payload size and survives a round trip: encoded
 * again (aw_frame_encode, the schema's CRC) and decoded by a fresh decoder it comes back
 * identical. `make -C firmware fuzz && build/fuzz/fuzz_decoder -max_total_time=600 DIR` */
#include <string.h>

#include "aw_frame.h"
#include "aw_messages.h"
#include "fuzz_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void round_trip(const aw_frame_t *f)
{
    uint8_t wire[AW_MAX_ENCODED_SIZE + 8];
    const int len = aw_frame_encode(wire, sizeof wire, &f->header, f->payload, f->payload_len);
    FUZZ_CHECK(len > 0);
    aw_decoder_t d;
    aw_decoder_init(&d, NULL, NULL);
    int got = 0;
    for (int i = 0; i < len; i++) {
        aw_frame_t g;
        if (aw_decoder_feed_byte(&d, wire[i], &g)) {
            got++;
            FUZZ_CHECK(g.header.msg_id == f->header.msg_id && g.header.seq == f->header.seq &&
                       g.header.flags == f->header.flags &&
                       g.header.board_time_us == f->header.board_time_us);
            FUZZ_CHECK(g.payload_len == f->payload_len &&
                       memcmp(g.payload, f->payload, f->payload_len) == 0);
        }
    }
    FUZZ_CHECK(got == 1 && d.counters.frames_ok == 1 && d.counters.bytes_dropped == 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    aw_decoder_t whole, chunked;
    aw_decoder_init(&whole, NULL, NULL);
    aw_decoder_init(&chunked, NULL, NULL);
    size_t delivered = 0, ok_bytes = 0, seg = 0, zeros = 0;
    for (size_t i = 0; i < size; ++i) {
        aw_frame_t f;
        seg += data[i] != 0;
        if (aw_decoder_feed_byte(&whole, data[i], &f)) {
            ++delivered;
            ok_bytes += seg;
            FUZZ_CHECK(aw_msg_info(f.header.msg_id) != NULL);
            FUZZ_CHECK(f.payload_len == aw_msg_info(f.header.msg_id)->payload_size);
            round_trip(&f);
        }
        if (data[i] == 0) {
            ++zeros;
            seg = 0;
        }
    }
    for (size_t at = 0, step = 1; at < size; at += step, step = step * 2 + 1) {
        aw_decoder_feed(&chunked, data + at, step < size - at ? step : size - at);
    }
    const aw_counters_t *c = &whole.counters;
    FUZZ_CHECK(c->frames_ok == delivered);
    FUZZ_CHECK(ok_bytes + c->bytes_dropped + zeros + seg == size);
    FUZZ_CHECK(memcmp(c, &chunked.counters, sizeof *c) == 0);
    return 0;
}
