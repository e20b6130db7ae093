/*
 * test_board_util.h — helpers shared by the board wiring tests (test_board_*.c):
 * run a board on the fake HAL, decode what it wrote to a port with the protocol's
 * own C decoder, encode host frames to feed it.
 */
#ifndef AW_TEST_BOARD_UTIL_H
#define AW_TEST_BOARD_UTIL_H

#include <stdio.h>
#include <string.h>

#include "aw_frame.h"
#include "board.h"
#include "hal_fake.h"

#define CHECK(cond)                                                                 \
    do {                                                                            \
        if (!(cond)) {                                                              \
            fprintf(stderr, "%s:%d: %s failed\n", __FILE__, __LINE__, #cond);       \
            return 1;                                                               \
        }                                                                           \
    } while (0)

#define MAX_FRAMES 8192

typedef struct {
    aw_header_t h;
    uint8_t payload[AW_MAX_PAYLOAD_SIZE];
    size_t len;
} test_frame_t;

typedef struct {
    test_frame_t f[MAX_FRAMES];
    size_t n;
    aw_decoder_t dec;
} test_frames_t;

static void test_collect(void *ctx, const aw_frame_t *fr)
{
    test_frames_t *t = ctx;
    if (t->n < MAX_FRAMES) {
        t->f[t->n].h = fr->header;
        memcpy(t->f[t->n].payload, fr->payload, fr->payload_len);
        t->f[t->n].len = fr->payload_len;
        t->n++;
    }
}

static inline void test_frames_init(test_frames_t *t)
{
    t->n = 0;
    aw_decoder_init(&t->dec, test_collect, t);
}

/* Decodes (and takes) everything the board wrote to a port so far. */
static inline void test_frames_take(test_frames_t *t, hal_port_t port)
{
    static uint8_t buf[FAKE_TX_CAP];
    size_t n = fake_uart_take(port, buf, sizeof(buf));
    aw_decoder_feed(&t->dec, buf, n);
}

static inline size_t test_count(const test_frames_t *t, uint8_t msg_id)
{
    size_t c = 0;
    for (size_t i = 0; i < t->n; i++) {
        c += t->f[i].h.msg_id == msg_id;
    }
    return c;
}

/* Runs the board's main loop (as the target's main does) until board time t_end. */
static inline void test_run_until(const hal_t *hal, uint64_t t_end)
{
    while (fake.now_us < t_end) {
        uint64_t due = board_task(hal);
        hal->idle(due < t_end ? due : t_end);
    }
}

/* Feeds one host -> board frame. */
static inline void test_feed_msg(hal_port_t port, uint8_t msg_id, const void *msg)
{
    uint8_t wire[AW_MAX_WIRE_SIZE];
    int n = aw_encode_msg(wire, sizeof(wire), msg_id, 0, AW_BOARD_HOST, 0, msg);
    if (n > 0) {
        fake_uart_feed(port, wire, (size_t)n);
    }
}

#endif /* AW_TEST_BOARD_UTIL_H */
