/* board.c (base) — see board.h. */
#include "board.h"

#include <string.h>

base_board_t base_board;

static const uint8_t schema_ids[] = {
    AW_ID_HEARTBEAT, AW_ID_SCHEMA_ENTRY, AW_ID_TIME_SYNC_REQUEST, AW_ID_TIME_SYNC_REPLY,
    AW_ID_INS,       AW_ID_RTK_POS,      AW_ID_GPS_TIME,          AW_ID_RTK_STATUS,
    AW_ID_PILOT_INPUTS, AW_ID_STAMP_LATENCY,
};

static const board_stamp_t stamps[] = {
    {AW_ID_INS, AW_STAMP_LATENCY_STAMP_EVENT_PEER_PACKET_END, NAV_INS_STAMP_LATENCY_US},
    {AW_ID_PILOT_INPUTS, AW_STAMP_LATENCY_STAMP_EVENT_RC_FRAME_START, BASE_RC_STAMP_LATENCY_US},
};

static const hal_capture_t rc_capture[BASE_RC_CHANNELS] = {
    HAL_CAPTURE_RC1, HAL_CAPTURE_RC2, HAL_CAPTURE_RC3, HAL_CAPTURE_RC4, HAL_CAPTURE_RC5,
};

/* Host -> rover: the base passes the host's bytes on unchanged (the rover answers
 * time-sync requests itself; its reply comes back through the forwarder). */
static void relay_host_bytes(void *ctx, const uint8_t *data, size_t len)
{
    base_board_t *b = ctx;
    if (!b->link.hal->uart_write(HAL_PORT_ROVER, data, len)) {
        b->relay_dropped_bytes += (uint32_t)len;
    }
}

void board_init(const hal_t *hal)
{
    base_board_t *b = &base_board;
    memset(b, 0, sizeof(*b));
    board_link_init(&b->link, hal, BOARD_ID, HAL_PORT_HOST, schema_ids,
                    (uint8_t)sizeof(schema_ids), NULL, b);
    b->link.on_bytes = relay_host_bytes;
    board_link_declare_stamps(&b->link, stamps, (uint8_t)(sizeof(stamps) / sizeof(stamps[0])));
    nav_ports_init(&b->nav, hal, &b->link, NAV_STATUS_ONLY);
    b->rc_cfg = pwm_capture_default_cfg();
    for (int i = 0; i < BASE_RC_CHANNELS; i++) {
        pwm_channel_init(&b->rc[i]);
    }
    b->t0_us = hal->micros();
    hal->watchdog_start(BASE_WATCHDOG_MS);
}

static void forward_segment(forwarder_t *f, const hal_t *hal)
{
    f->seg[f->len] = 0x00;
    size_t n = f->len + 1u;
    if (hal->uart_write(HAL_PORT_HOST, f->seg, n)) {
        f->segments++;
        f->bytes += (uint32_t)(n - 2u);
    } else {
        f->dropped_bytes += (uint32_t)(n - 2u);
    }
    f->len = 1; /* seg[0] stays the leading 0x00 */
}

/* Rover bytes -> whole segments between 0x00 delimiters -> host port. */
static void forward_rover(forwarder_t *f, const hal_t *hal)
{
    uint8_t buf[128];
    size_t got;
    if (f->len == 0) {
        f->seg[0] = 0x00;
        f->len = 1;
    }
    while ((got = hal->uart_read(HAL_PORT_ROVER, buf, sizeof(buf))) > 0) {
        for (size_t i = 0; i < got; i++) {
            if (buf[i] == 0x00) {
                if (f->len > 1) {
                    forward_segment(f, hal);
                }
                continue;
            }
            f->seg[f->len++] = buf[i];
            if (f->len == sizeof(f->seg) - 1u) {
                forward_segment(f, hal); /* longer than any frame: pass it on in pieces */
            }
        }
    }
}

static void drain_captures(base_board_t *b, const hal_t *hal)
{
    hal_edge_t e[16];
    for (int c = 0; c < BASE_RC_CHANNELS; c++) {
        size_t n;
        while ((n = hal->capture_read(rc_capture[c], e, 16)) > 0) {
            for (size_t i = 0; i < n; i++) {
                pwm_channel_edge(&b->rc[c], &b->rc_cfg, e[i].t_us, e[i].level);
            }
        }
    }
}

static void send_pilot_inputs(base_board_t *b, uint32_t stamp_us, uint64_t now)
{
    aw_pilot_inputs_t m = {0};
    for (int c = 0; c < BASE_RC_CHANNELS; c++) {
        pwm_channel_out_t o;
        pwm_channel_get(&b->rc[c], &b->rc_cfg, (uint32_t)now, &o);
        m.pwm_us[c] = o.width_us;
        m.glitch_count[c] = (uint16_t)o.glitches;
        if (o.valid) {
            m.valid_mask |= (uint8_t)(1u << c);
        }
        b->sent_pulses[c] = b->rc[c].pulses;
    }
    (void)board_link_send(&b->link, AW_ID_PILOT_INPUTS, &m, stamp_us);
}

/* The RC frame being gathered: true when it is complete (every valid channel has a new
 * pulse, or the first new pulse is 3/4 of a frame period old); *start_us is its first
 * rising edge, *due_us when gathering gives up (UINT64_MAX: no frame under way). */
static bool rc_frame_ready(const base_board_t *b, uint64_t now, uint32_t *start_us,
                           uint64_t *due_us)
{
    bool fresh = false, waiting = false;
    uint32_t age = 0, period = 0;
    for (int c = 0; c < BASE_RC_CHANNELS; c++) {
        const pwm_channel_t *ch = &b->rc[c];
        pwm_channel_out_t o;
        pwm_channel_get(ch, &b->rc_cfg, (uint32_t)now, &o);
        if (ch->pulses == b->sent_pulses[c]) {
            waiting = waiting || o.valid;
            continue;
        }
        uint32_t a = (uint32_t)now - ch->last_accept_us; /* wrap-safe */
        if (!fresh || a > age) {
            age = a;
            *start_us = ch->last_accept_us;
        }
        fresh = true;
        if (o.period_us && (!period || o.period_us < period)) {
            period = o.period_us; /* a channel that missed a pulse measures two frames */
        }
    }
    *due_us = UINT64_MAX;
    if (!fresh) {
        return false;
    }
    uint32_t gather = period ? period / 4u * 3u : BASE_RC_GATHER_DEFAULT_US;
    if (!waiting || age >= gather) {
        return true;
    }
    *due_us = now + (gather - age);
    return false;
}

uint64_t board_task(const hal_t *hal)
{
    base_board_t *b = &base_board;
    board_link_task_begin(&b->link);
    hal->watchdog_refresh();
    uint32_t lost = 0;
    for (int c = 0; c < BASE_RC_CHANNELS; c++) {
        lost += hal->capture_overruns(rc_capture[c]);
    }
    uint64_t link_due = board_link_poll(&b->link, lost);
    forward_rover(&b->fwd, hal);
    drain_captures(b, hal);
    uint64_t due = nav_ports_poll(&b->nav);

    uint64_t now = hal->micros();
    uint32_t start_us = 0;
    uint64_t frame_due;
    if (rc_frame_ready(b, now, &start_us, &frame_due)) {
        send_pilot_inputs(b, start_us, now);
        b->last_frame_us = now;
    }
    /* keep-alive: no frame for a whole capture timeout (the receiver is silent) */
    bool silent = now - b->last_frame_us >= b->rc_cfg.timeout_us;
    if (board_tick_due(b->t0_us, &b->pilot_k, BASE_PILOT_HZ, now) && silent) {
        send_pilot_inputs(b, (uint32_t)now, now);
    }
    board_link_task_end(&b->link);

    uint64_t next_pilot = board_tick_us(b->t0_us, b->pilot_k, BASE_PILOT_HZ);
    due = due < link_due ? due : link_due;
    due = due < frame_due ? due : frame_due;
    return due < next_pilot ? due : next_pilot;
}
