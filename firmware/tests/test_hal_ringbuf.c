/* test_hal_ringbuf.c — the ring buffer under the UART/capture interrupt paths. */
#include <stdio.h>
#include <string.h>

#include "hal.h"
#include "ringbuf.h"

#define CHECK(cond)                                                                 \
    do {                                                                            \
        if (!(cond)) {                                                              \
            fprintf(stderr, "%s:%d: %s failed\n", __FILE__, __LINE__, #cond);       \
            return 1;                                                               \
        }                                                                           \
    } while (0)

/* A capacity that is not a power of two would make `index & mask` skip slots. */
static int test_ringbuf_rejects_capacity_not_power_of_two(void)
{
    uint8_t mem[12];
    ringbuf_t rb;
    CHECK(!ringbuf_init(&rb, mem, 12, 1));
    CHECK(!ringbuf_init(&rb, mem, 1, 1));
    CHECK(!ringbuf_init(&rb, NULL, 8, 1));
    CHECK(ringbuf_init(&rb, mem, 8, 1));
    CHECK(ringbuf_capacity(&rb) == 8 && ringbuf_count(&rb) == 0 && ringbuf_free(&rb) == 8);
    return 0;
}

/* Bytes lost to a full ring must be counted, never silently dropped (STYLE 5). */
static int test_ringbuf_counts_every_byte_lost_when_full(void)
{
    uint8_t mem[16];
    ringbuf_t rb;
    ringbuf_init(&rb, mem, 16, 1);
    uint8_t data[40];
    for (unsigned i = 0; i < sizeof(data); i++) {
        data[i] = (uint8_t)i;
    }
    CHECK(ringbuf_write(&rb, data, 10) == 10);
    CHECK(ringbuf_write(&rb, data + 10, 30) == 6);
    CHECK(rb.overruns == 24);
    uint8_t b = 0xAA;
    CHECK(!ringbuf_put(&rb, &b));
    CHECK(rb.overruns == 25);
    uint8_t out[40];
    CHECK(ringbuf_read(&rb, out, sizeof(out)) == 16);
    for (unsigned i = 0; i < 16; i++) {
        CHECK(out[i] == i); /* the oldest bytes survive, in order */
    }
    return 0;
}

/* A frame must go in whole or not at all, or the receiver sees a torn frame. */
static int test_ringbuf_write_all_never_stores_part_of_a_frame(void)
{
    uint8_t mem[8];
    ringbuf_t rb;
    ringbuf_init(&rb, mem, 8, 1);
    const uint8_t frame[6] = {1, 2, 3, 4, 5, 6};
    CHECK(ringbuf_write_all(&rb, frame, 6));
    CHECK(!ringbuf_write_all(&rb, frame, 6));
    CHECK(ringbuf_count(&rb) == 6);
    CHECK(rb.overruns == 0); /* the caller counts refused frames */
    return 0;
}

/* Indices run freely past 2^32; contents must stay in order across the wrap. */
static int test_ringbuf_survives_index_wraparound(void)
{
    uint8_t mem[8];
    ringbuf_t rb;
    ringbuf_init(&rb, mem, 8, 1);
    rb.head = rb.tail = UINT32_MAX - 3u;
    uint8_t in[7] = {10, 11, 12, 13, 14, 15, 16};
    CHECK(ringbuf_write(&rb, in, 7) == 7);
    CHECK(ringbuf_count(&rb) == 7);
    uint8_t out[7];
    CHECK(ringbuf_read(&rb, out, 7) == 7);
    CHECK(memcmp(in, out, 7) == 0);
    CHECK(ringbuf_count(&rb) == 0);
    return 0;
}

/* Zero-copy draining returns the contiguous run up to the end of storage first. */
static int test_ringbuf_peek_contig_splits_at_the_storage_end(void)
{
    uint8_t mem[8];
    ringbuf_t rb;
    ringbuf_init(&rb, mem, 8, 1);
    uint8_t in[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    ringbuf_write(&rb, in, 6);
    uint8_t sink[6];
    ringbuf_read(&rb, sink, 5); /* tail at 5 */
    ringbuf_write(&rb, in, 6);  /* occupies 5..10 */
    size_t run;
    const uint8_t *p = ringbuf_peek_contig(&rb, &run);
    CHECK(run == 3 && p == &mem[5]);
    ringbuf_consume(&rb, run);
    p = ringbuf_peek_contig(&rb, &run);
    CHECK(run == 4 && p == &mem[0]);
    ringbuf_consume(&rb, 100); /* consuming more than there is stops at empty */
    CHECK(ringbuf_count(&rb) == 0);
    return 0;
}

/* Capture rings hold whole edge records (timestamp + level), oldest first. */
static int test_ringbuf_element_ring_keeps_edges_whole_and_ordered(void)
{
    hal_edge_t mem[4];
    ringbuf_t rb;
    CHECK(ringbuf_init(&rb, mem, 4, (uint16_t)sizeof(hal_edge_t)));
    for (uint32_t i = 0; i < 6; i++) {
        hal_edge_t e = {.t_us = 1000u * i, .level = (uint8_t)(i & 1u)};
        bool ok = ringbuf_put(&rb, &e);
        CHECK(ok == (i < 4));
    }
    CHECK(rb.overruns == 2);
    hal_edge_t e;
    for (uint32_t i = 0; i < 4; i++) {
        CHECK(ringbuf_get(&rb, &e));
        CHECK(e.t_us == 1000u * i && e.level == (i & 1u));
    }
    CHECK(!ringbuf_get(&rb, &e));
    return 0;
}

/* Random interleavings of producer and consumer against a reference FIFO. */
static int test_ringbuf_matches_reference_fifo_under_random_traffic(void)
{
    uint8_t mem[64];
    ringbuf_t rb;
    ringbuf_init(&rb, mem, 64, 1);
    static uint8_t ref[1 << 16];
    size_t ref_head = 0, ref_tail = 0;
    uint32_t lost = 0;
    uint32_t x = 12345u;
    uint8_t next = 0;
    for (int step = 0; step < 20000; step++) {
        x = x * 1664525u + 1013904223u;
        size_t n = (x >> 24) % 40u;
        if ((x >> 8) & 1u) {
            uint8_t buf[40];
            for (size_t i = 0; i < n; i++) {
                buf[i] = next++;
            }
            size_t room = 64u - (ref_head - ref_tail);
            size_t stored = ringbuf_write(&rb, buf, n);
            CHECK(stored == (n < room ? n : room));
            for (size_t i = 0; i < stored; i++) {
                ref[ref_head++ & 0xFFFFu] = buf[i];
            }
            lost += (uint32_t)(n - stored);
        } else {
            uint8_t buf[40];
            size_t got = ringbuf_read(&rb, buf, n);
            size_t avail = ref_head - ref_tail;
            CHECK(got == (n < avail ? n : avail));
            for (size_t i = 0; i < got; i++) {
                CHECK(buf[i] == ref[ref_tail++ & 0xFFFFu]);
            }
        }
        CHECK(rb.overruns == lost);
    }
    return 0;
}

int main(void)
{
    int fails = 0;
    fails += test_ringbuf_rejects_capacity_not_power_of_two();
    fails += test_ringbuf_counts_every_byte_lost_when_full();
    fails += test_ringbuf_write_all_never_stores_part_of_a_frame();
    fails += test_ringbuf_survives_index_wraparound();
    fails += test_ringbuf_peek_contig_splits_at_the_storage_end();
    fails += test_ringbuf_element_ring_keeps_edges_whole_and_ordered();
    fails += test_ringbuf_matches_reference_fifo_under_random_traffic();
    if (fails) {
        fprintf(stderr, "test_hal_ringbuf: %d failed\n", fails);
        return 1;
    }
    printf("test_hal_ringbuf: ok\n");
    return 0;
}
