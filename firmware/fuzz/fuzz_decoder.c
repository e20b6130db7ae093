/* libFuzzer target for the streaming decoder: any input, fed whole and in odd chunks,
 * must be handled without memory errors or UB, and the counters must account for every
 * segment and byte. `make -C firmware proto-fuzz && build/fuzz/fuzz_decoder -max_total_time=60` */
#include <stdlib.h>

#include "aw_frame.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

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
            if (f.payload_len != aw_msg_info(f.header.msg_id)->payload_size) {
                abort();
            }
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
    if (c->frames_ok != delivered || ok_bytes + c->bytes_dropped + zeros + seg != size ||
        __builtin_memcmp(c, &chunked.counters, sizeof *c) != 0) {
        abort();
    }
    return 0;
}
