/* capture.c — native input capture: edges from the simulator (SIM_EDGE), stamped
 * with the board clock at the edge's time, queued like the FTM interrupt does. */
#include <string.h>

#include "native.h"
#include "ringbuf.h"

#define EDGE_RING 64u

static ringbuf_t rings[HAL_CAPTURE_COUNT];
static hal_edge_t mem[HAL_CAPTURE_COUNT][EDGE_RING];

void capture_reset(void)
{
    for (unsigned i = 0; i < HAL_CAPTURE_COUNT; i++) {
        ringbuf_init(&rings[i], mem[i], EDGE_RING, (uint16_t)sizeof(hal_edge_t));
    }
}

void capture_sim_edge(hal_capture_t ch, uint64_t t_sim, uint8_t level)
{
    hal_edge_t e = {.t_us = (uint32_t)native_board_us(t_sim), .level = level};
    (void)ringbuf_put(&rings[ch], &e);
}

size_t capture_read(hal_capture_t ch, hal_edge_t *out, size_t cap)
{
    if ((unsigned)ch >= HAL_CAPTURE_COUNT) {
        return 0;
    }
    size_t n = 0;
    while (n < cap && ringbuf_get(&rings[ch], &out[n])) {
        n++;
    }
    return n;
}

uint32_t capture_overruns(hal_capture_t ch)
{
    return (unsigned)ch < HAL_CAPTURE_COUNT ? rings[ch].overruns : 0u;
}
