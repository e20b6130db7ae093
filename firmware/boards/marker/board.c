/* board.c (marker) — see board.h. */
#include "board.h"

#include <math.h>
#include <string.h>

marker_board_t marker_board;

static const uint8_t schema_ids[] = {
    AW_ID_HEARTBEAT, AW_ID_SCHEMA_ENTRY,     AW_ID_TIME_SYNC_REQUEST, AW_ID_TIME_SYNC_REPLY,
    AW_ID_IMU,       AW_ID_MARKER_ATTITUDE, AW_ID_MARKER_COMMAND, AW_ID_ANEMOMETER,
    AW_ID_STAMP_LATENCY,
};

/* anemometer frames are stamped one byte time after the line's output instant */
static const board_stamp_t stamps[] = {
    {AW_ID_ANEMOMETER, AW_STAMP_LATENCY_STAMP_EVENT_PEER_PACKET_START, YOUNG_STAMP_LATENCY_US},
};

static void drive_leds(marker_board_t *b, const hal_t *hal)
{
    float drive[MARKER_LEDS];
    marker_led_drive(&b->logic, drive);
    for (unsigned i = 0; i < MARKER_LEDS && i < HAL_PWM_COUNT; i++) {
        float d = drive[i] < 0.0f ? 0.0f : (drive[i] > 1.0f ? 1.0f : drive[i]);
        hal->pwm_write((hal_pwm_t)(HAL_PWM_LED0 + i), (uint16_t)lrintf(d * (float)HAL_PWM_FULL));
    }
}

static void on_host_frame(void *ctx, const aw_frame_t *f)
{
    marker_board_t *b = ctx;
    if (f->header.msg_id != AW_ID_MARKER_COMMAND) {
        return;
    }
    aw_marker_command_t cmd;
    if (aw_unpack_msg(AW_ID_MARKER_COMMAND, &cmd, f->payload, f->payload_len) < 0) {
        return;
    }
    float fraction[MARKER_LEDS];
    float fs = cmd.full_scale_counts > 0 ? (float)cmd.full_scale_counts : (float)HAL_ADC_MAX;
    for (unsigned i = 0; i < MARKER_LEDS; i++) {
        fraction[i] = (float)cmd.led_peak_counts[i] / fs;
    }
    const hal_t *hal = b->link.hal;
    marker_feedback(&b->logic, &b->cfg, (uint32_t)hal->micros(), fraction);
    drive_leds(b, hal);
    b->commands++;
}

void board_init(const hal_t *hal)
{
    marker_board_t *b = &marker_board;
    memset(b, 0, sizeof(*b));
    board_link_init(&b->link, hal, BOARD_ID, HAL_PORT_HOST, schema_ids,
                    (uint8_t)sizeof(schema_ids), on_host_frame, b);
    board_link_declare_stamps(&b->link, stamps, (uint8_t)(sizeof(stamps) / sizeof(stamps[0])));
    young_init(&b->anemo);
    b->imu_ok = mpu9250_init(hal, HAL_SPI_IMU, &b->imu);
    b->cfg = marker_default_cfg();
    b->t0_us = hal->micros();
    marker_init(&b->logic, &b->cfg, (uint32_t)b->t0_us);
    drive_leds(b, hal);
    hal->watchdog_start(MARKER_WATCHDOG_MS);
}

static void normalize3(const float v[3], float out[3])
{
    float n = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; i++) {
        out[i] = n > 0.0f ? v[i] / n : 0.0f;
    }
}

static uint8_t wire_mode(const marker_state_t *st)
{
    return st->mode == MARKER_MODE_TRACKING ? AW_MARKER_ATTITUDE_MODE_TRACKING
                                            : AW_MARKER_ATTITUDE_MODE_CALIBRATE_LEDS;
}

static void send_outputs(marker_board_t *b, const hal_t *hal, uint64_t now)
{
    marker_output_t o;
    marker_output(&b->logic, &o);
    uint32_t age_ms = ((uint32_t)now - b->logic.last_ir_us) / 1000u;
    aw_marker_attitude_t att = {
        .quat_init_from_body_wxyz = {o.q.w, o.q.x, o.q.y, o.q.z},
        .mode = wire_mode(&b->logic),
        .active_led = (uint8_t)marker_lit_led(&b->logic),
        .led_duty_q16 = (uint16_t)lrintf(o.intensity * (float)HAL_PWM_FULL),
        .ir_feedback_age_ms = age_ms > UINT16_MAX ? UINT16_MAX : (uint16_t)age_ms,
    };
    normalize3(o.gravity_m_s2, att.gravity_frd_unit);
    normalize3(o.los, att.los_frd_unit);
    memcpy(att.gyro_bias_frd_rad_s, o.gyro_bias_rad_s, sizeof(att.gyro_bias_frd_rad_s));
    (void)board_link_send(&b->link, AW_ID_MARKER_ATTITUDE, &att, (uint32_t)now);

    if (b->imu_ok) {
        const mpu9250_sample_t *s = &b->last;
        aw_imu_t m = {.temperature_c = s->temp_c,
                      .status = s->mag_valid ? AW_IMU_STATUS_MAG_VALID : 0u};
        memcpy(m.gyro_frd_rad_s, s->gyro_rad_s, sizeof(m.gyro_frd_rad_s));
        memcpy(m.accel_frd_m_s2, s->accel_m_s2, sizeof(m.accel_frd_m_s2));
        memcpy(m.mag_frd_ut, s->mag_ut, sizeof(m.mag_frd_ut));
        (void)board_link_send(&b->link, AW_ID_IMU, &m, (uint32_t)now);
    }
    (void)hal;
}

/* Whatever the anemometer sent since the last task: complete lines go to the host. */
static void forward_anemometer(marker_board_t *b, const hal_t *hal)
{
    uint8_t buf[64];
    size_t got;
    while ((got = hal->uart_read(HAL_PORT_ANEMO, buf, sizeof(buf))) > 0) {
        uint64_t now = hal->micros();
        size_t off = 0;
        while (off < got) {
            young_sample_t s[4];
            size_t used = 0;
            size_t n = young_feed(&b->anemo, buf + off, got - off, now, s, 4, &used);
            off += used;
            for (size_t i = 0; i < n; i++) {
                aw_anemometer_t m = {.sonic_temp_c = s[i].temp_c, .status = s[i].status};
                memcpy(m.wind_uvw_inst_m_s, s[i].uvw_m_s, sizeof(m.wind_uvw_inst_m_s));
                if (board_link_send(&b->link, AW_ID_ANEMOMETER, &m, (uint32_t)s[i].t_us)) {
                    b->anemo_sent++;
                }
            }
        }
    }
}

uint64_t board_task(const hal_t *hal)
{
    marker_board_t *b = &marker_board;
    board_link_task_begin(&b->link);
    hal->watchdog_refresh();
    uint64_t due = board_link_poll(&b->link, 0); /* host feedback first, HELLO due */
    forward_anemometer(b, hal);
    uint64_t now = hal->micros();

    if (board_tick_due(b->t0_us, &b->imu_k, MARKER_IMU_HZ, now)) {
        /* the MPU-9250 is mounted with its axes along the body axes (x fwd, y right, z down) */
        if (b->imu_ok && mpu9250_read(hal, &b->imu, &b->last)) {
            marker_imu_step(&b->logic, &b->cfg, (uint32_t)now, b->last.gyro_rad_s,
                            b->last.accel_m_s2);
            drive_leds(b, hal);
        } else {
            b->imu_errors++;
        }
    }
    if (board_tick_due(b->t0_us, &b->out_k, MARKER_OUTPUT_HZ, now)) {
        send_outputs(b, hal, now);
    }
    board_link_task_end(&b->link);

    uint64_t next_imu = board_tick_us(b->t0_us, b->imu_k, MARKER_IMU_HZ);
    uint64_t next_out = board_tick_us(b->t0_us, b->out_k, MARKER_OUTPUT_HZ);
    due = due < next_imu ? due : next_imu;
    return due < next_out ? due : next_out;
}
