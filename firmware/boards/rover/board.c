/* board.c (rover) — see board.h. */
#include "board.h"

#include <string.h>

rover_board_t rover_board;

static const uint8_t schema_ids[] = {
    AW_ID_HEARTBEAT, AW_ID_SCHEMA_ENTRY, AW_ID_TIME_SYNC_REQUEST, AW_ID_TIME_SYNC_REPLY,
    AW_ID_INS,       AW_ID_RTK_BASELINE, AW_ID_RTK_POS,           AW_ID_RTK_VEL,
    AW_ID_GPS_TIME,  AW_ID_RTK_STATUS,   AW_ID_ROTOR_SPEED,       AW_ID_TAIL_SERVO,
    AW_ID_STAMP_LATENCY,
};

static const board_stamp_t stamps[] = {
    {AW_ID_INS, AW_STAMP_LATENCY_STAMP_EVENT_PEER_PACKET_END, NAV_INS_STAMP_LATENCY_US},
};

void board_init(const hal_t *hal)
{
    rover_board_t *b = &rover_board;
    memset(b, 0, sizeof(*b));
    board_link_init(&b->link, hal, BOARD_ID, HAL_PORT_HOST, schema_ids,
                    (uint8_t)sizeof(schema_ids), NULL, b);
    board_link_declare_stamps(&b->link, stamps, (uint8_t)(sizeof(stamps) / sizeof(stamps[0])));
    nav_ports_init(&b->nav, hal, &b->link, NAV_FORWARD_ALL);
    b->rotor_cfg = rotor_speed_default_cfg();
    rotor_speed_init(&b->rotor);
    b->tail_cfg = pwm_capture_default_cfg();
    pwm_channel_init(&b->tail);
    b->t0_us = hal->micros();
    hal->watchdog_start(ROVER_WATCHDOG_MS);
}

/* Interrupt-queued edges -> the algorithms (oldest first). */
static void drain_captures(rover_board_t *b, const hal_t *hal)
{
    hal_edge_t e[16];
    size_t n;
    while ((n = hal->capture_read(HAL_CAPTURE_ROTOR_IR, e, 16)) > 0) {
        for (size_t i = 0; i < n; i++) {
            if (e[i].level) { /* a blade reflection starts */
                rotor_speed_pulse(&b->rotor, &b->rotor_cfg, e[i].t_us);
            }
        }
    }
    while ((n = hal->capture_read(HAL_CAPTURE_TAIL_SERVO, e, 16)) > 0) {
        for (size_t i = 0; i < n; i++) {
            pwm_channel_edge(&b->tail, &b->tail_cfg, e[i].t_us, e[i].level);
        }
    }
}

static void send_rotor(rover_board_t *b, uint32_t now)
{
    rotor_speed_out_t o;
    rotor_speed_get(&b->rotor, &b->rotor_cfg, now, &o);
    aw_rotor_speed_t m = {
        .rotor_speed_rad_s = o.valid ? o.speed_rad_s : 0.0f,
        .pulse_interval_us = o.interval_us,
        .pulse_count = o.pulses,
        .rejected_pulses = (uint16_t)(o.glitches + o.missed),
    };
    (void)board_link_send(&b->link, AW_ID_ROTOR_SPEED, &m, now);
}

static void send_tail(rover_board_t *b, uint32_t now)
{
    pwm_channel_out_t o;
    pwm_channel_get(&b->tail, &b->tail_cfg, now, &o);
    aw_tail_servo_t m = {
        .pulse_width_us = o.width_us,
        .valid = o.valid,
        .glitch_count = (uint16_t)o.glitches,
    };
    (void)board_link_send(&b->link, AW_ID_TAIL_SERVO, &m, now);
}

uint64_t board_task(const hal_t *hal)
{
    rover_board_t *b = &rover_board;
    board_link_task_begin(&b->link);
    hal->watchdog_refresh();
    uint32_t lost = hal->capture_overruns(HAL_CAPTURE_ROTOR_IR) +
                    hal->capture_overruns(HAL_CAPTURE_TAIL_SERVO);
    uint64_t link_due = board_link_poll(&b->link, lost);
    drain_captures(b, hal);
    uint64_t due = nav_ports_poll(&b->nav);

    uint64_t now = hal->micros();
    if (board_tick_due(b->t0_us, &b->rotor_k, ROVER_ROTOR_HZ, now)) {
        send_rotor(b, (uint32_t)now);
    }
    if (board_tick_due(b->t0_us, &b->tail_k, ROVER_TAIL_HZ, now)) {
        send_tail(b, (uint32_t)now);
    }
    board_link_task_end(&b->link);

    uint64_t next_rotor = board_tick_us(b->t0_us, b->rotor_k, ROVER_ROTOR_HZ);
    uint64_t next_tail = board_tick_us(b->t0_us, b->tail_k, ROVER_TAIL_HZ);
    due = due < link_due ? due : link_due;
    due = due < next_rotor ? due : next_rotor;
    return due < next_tail ? due : next_tail;
}
