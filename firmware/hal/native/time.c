/* time.c — the native board clock: simulator time, drift/offset, idle and delay. */
#include <math.h>
#include <time.h>

#include "native.h"

native_clock_t native_clock = {.mode = NATIVE_WALL};

uint64_t native_mono_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

uint64_t native_now_sim(void)
{
    if (native_clock.mode == NATIVE_WALL) {
        native_clock.now_sim = native_mono_us();
    }
    return native_clock.now_sim;
}

/* board = offset + e * (1 + drift), e = sim - boot; floor, so board time never runs
 * ahead of the sim time that produced it. */
uint64_t native_board_us(uint64_t sim_us)
{
    uint64_t e = sim_us > native_clock.boot_sim ? sim_us - native_clock.boot_sim : 0;
    if (native_clock.drift == 0.0) {
        return native_clock.offset_us + e;
    }
    double scaled = floor((double)e * (1.0 + native_clock.drift));
    return native_clock.offset_us + (scaled > 0.0 ? (uint64_t)scaled : 0u);
}

/* The first sim time whose board time is >= board_us. */
uint64_t native_sim_us(uint64_t board_us)
{
    if (board_us <= native_clock.offset_us) {
        return native_clock.boot_sim;
    }
    uint64_t b = board_us - native_clock.offset_us;
    if (native_clock.drift == 0.0) {
        return native_clock.boot_sim + b;
    }
    double e = ceil((double)b / (1.0 + native_clock.drift));
    uint64_t sim = native_clock.boot_sim + (e > 0.0 ? (uint64_t)e : 0u);
    while (native_board_us(sim) < board_us) { /* guard the rounding */
        sim++;
    }
    return sim;
}

uint64_t native_micros(void) { return native_board_us(native_now_sim()); }

static uint64_t min3(uint64_t a, uint64_t b, uint64_t c)
{
    uint64_t m = a < b ? a : b;
    return m < c ? m : c;
}

/* Stepped: the clock moves only here. Inputs due at the current time are applied
 * first (they are the interrupts the board must see); then the clock jumps to the
 * earliest of the board's deadline, the next input and the end of the step. At the
 * end of a step the port fds are read, IDLE is answered and the next packet
 * awaited; receive bytes picked up there wake the board like an interrupt. */
static void idle_stepped(uint64_t until_board_us)
{
    static bool rx_woke;
    native_clock_t *c = &native_clock;
    uint64_t target = native_sim_us(until_board_us);
    if (target <= c->now_sim) {
        target = c->now_sim + 1u; /* every pass of the task loop costs 1 µs: no livelock */
    }
    /* bytes the task just queued leave now (as fast as the port's baud rate allows);
     * receive fds are read only at step ends: one syscall per step, not per pass */
    uart_service_tx(c->now_sim);
    for (;;) {
        if (chan_apply_due(c->now_sim)) {
            return;
        }
        if (c->now_sim >= target) {
            return;
        }
        if (!chan_in_step()) {
            chan_step();
            if (rx_woke) {
                rx_woke = false;
                return;
            }
            continue;
        }
        uint64_t step_end = chan_step_end();
        if (c->now_sim >= step_end) {
            rx_woke = chan_end_step(c->now_sim) || rx_woke;
            continue;
        }
        uint64_t t = min3(target, chan_next_time(), step_end);
        if (t > c->now_sim) {
            c->now_sim = t;
        }
        watchdog_check(c->now_sim);
    }
}

static void idle_wall(uint64_t until_board_us)
{
    uint64_t target = native_sim_us(until_board_us);
    for (;;) {
        uint64_t now = native_now_sim();
        watchdog_check(now);
        bool event = chan_apply_due(now);
        event = uart_service(now) || event;
        chan_flush();
        if (event || now >= target) {
            return;
        }
        uint64_t wake = target < chan_next_time() ? target : chan_next_time();
        uint64_t wait_us = wake - now;
        if (wait_us > 20000u) {
            wait_us = 20000u; /* keep draining transmit rings at least every 20 ms */
        }
        (void)chan_wall_poll(wait_us);
    }
}

void native_idle(uint64_t until_board_us)
{
    if (native_clock.mode == NATIVE_STEPPED) {
        idle_stepped(until_board_us);
    } else {
        idle_wall(until_board_us);
    }
}

void native_delay_us(uint32_t us)
{
    uint64_t until = native_micros() + us;
    while (native_micros() < until) {
        native_idle(until);
    }
}
