/* board.c (LOSA) — see board.h. */
#include "board.h"

#include <string.h>

losa_board_t losa_board;

static const uint8_t schema_ids[] = {
    AW_ID_HEARTBEAT,     AW_ID_SCHEMA_ENTRY, AW_ID_TIME_SYNC_REQUEST,  AW_ID_TIME_SYNC_REPLY,
    AW_ID_IMU,           AW_ID_LOSA_PEAKS,   AW_ID_LOSA_RAW_LINE,      AW_ID_LOSA_RAW_REQUEST,
};

static void on_host_frame(void *ctx, const aw_frame_t *f)
{
    losa_board_t *b = ctx;
    if (f->header.msg_id != AW_ID_LOSA_RAW_REQUEST) {
        return;
    }
    aw_losa_raw_request_t req;
    if (aw_unpack_msg(AW_ID_LOSA_RAW_REQUEST, &req, f->payload, f->payload_len) < 0) {
        return;
    }
    b->raw_mask = (uint8_t)(req.sensor_mask & 0x0Fu);
    b->raw_remaining = req.line_count;
    b->raw_decimation = req.decimation > 1u ? req.decimation : 1u;
}

void board_init(const hal_t *hal)
{
    losa_board_t *b = &losa_board;
    memset(b, 0, sizeof(*b));
    board_link_init(&b->link, hal, BOARD_ID, HAL_PORT_HOST, schema_ids,
                    (uint8_t)sizeof(schema_ids), on_host_frame, b);
    b->cfg = losa_frame_default_cfg(HAL_ADC_BITS);
    losa_frame_init(&b->frame, &b->cfg, LOSA_INITIAL_EXPOSURE_US);
    b->exposure_us = LOSA_INITIAL_EXPOSURE_US;
    tsl1401_init(hal, &b->tsl);
    b->imu_ok = mpu9250_init(hal, HAL_SPI_IMU, &b->imu);
    b->t0_us = hal->micros();
    b->next_frame_us = b->t0_us;
    hal->watchdog_start(LOSA_WATCHDOG_MS);
}

/* One exposure for the four arrays (they share SI): see board.h. */
static uint32_t shared_exposure(const losa_sensor_result_t r[LOSA_SENSORS])
{
    uint32_t shortest_valid = UINT32_MAX;
    uint32_t longest = 0;
    for (int s = 0; s < LOSA_SENSORS; s++) {
        if ((r[s].flags & LOSA_PEAK_VALID) && r[s].next_exposure_us < shortest_valid) {
            shortest_valid = r[s].next_exposure_us;
        }
        if (r[s].next_exposure_us > longest) {
            longest = r[s].next_exposure_us;
        }
    }
    return shortest_valid != UINT32_MAX ? shortest_valid : longest;
}

static uint8_t wire_flags(const losa_sensor_result_t *r, bool exposure_changed)
{
    uint8_t f = 0;
    if (r->flags & LOSA_PEAK_VALID) {
        f |= AW_LOSA_PEAKS_SENSOR_FLAGS_VALID;
    }
    if (r->flags & LOSA_PEAK_SATURATED) {
        f |= AW_LOSA_PEAKS_SENSOR_FLAGS_SATURATED;
    }
    if (r->flags & LOSA_SLOT_CHANGED) {
        f |= AW_LOSA_PEAKS_SENSOR_FLAGS_SLOT_JUMP;
    }
    if (exposure_changed) {
        f |= AW_LOSA_PEAKS_SENSOR_FLAGS_EXPOSURE_CHANGED;
    }
    return f;
}

static uint16_t clamp_u16(uint32_t v) { return v > UINT16_MAX ? UINT16_MAX : (uint16_t)v; }

static void send_raw_lines(losa_board_t *b, const hal_t *hal, uint32_t exposure_us,
                           uint32_t t_mid)
{
    if (b->raw_mask == 0 || b->raw_remaining == 0 || b->frames % b->raw_decimation != 0) {
        return;
    }
    /* peaks come first: a raw line only goes when it leaves room for the next frames */
    const size_t reserve = 4u * AW_WIRE_MAX_LOSA_PEAKS;
    for (uint8_t s = 0; s < LOSA_SENSORS; s++) {
        if (!(b->raw_mask & (1u << s))) {
            continue;
        }
        if (hal->uart_tx_free(HAL_PORT_HOST) < AW_WIRE_MAX_LOSA_RAW_LINE + reserve) {
            b->raw_skipped++;
            return;
        }
        aw_losa_raw_line_t m = {.sensor_index = s, .exposure_us = clamp_u16(exposure_us)};
        memcpy(m.pixels_counts, b->lines[s], sizeof(m.pixels_counts));
        (void)board_link_send(&b->link, AW_ID_LOSA_RAW_LINE, &m, t_mid);
    }
    if (b->raw_remaining != UINT16_MAX) {
        b->raw_remaining--;
    }
}

static void read_frame(losa_board_t *b, const hal_t *hal)
{
    uint32_t exposure = tsl1401_read(hal, &b->tsl, b->lines, LOSA_SENSORS);
    /* the time stamp is the middle of the integration */
    uint32_t t_mid = (uint32_t)(b->tsl.last_si_us - exposure / 2u);
    for (int s = 0; s < LOSA_SENSORS; s++) {
        b->frame.exposure[s].exposure_us = exposure;
    }
    losa_sensor_result_t r[LOSA_SENSORS];
    losa_frame_process(&b->frame, &b->cfg, (const uint16_t(*)[LOSA_PIXELS])b->lines, r);
    /* flag lines taken with a different programmed exposure than the previous line */
    bool changed = b->frames > 0 && b->exposure_us != b->prev_exposure_us;
    b->prev_exposure_us = b->exposure_us;
    b->exposure_us = shared_exposure(r);

    aw_losa_peaks_t m;
    for (int s = 0; s < LOSA_SENSORS; s++) {
        m.peak_px[s] = r[s].pos_px;
        m.intensity_counts[s] = r[s].peak;
        m.slot[s] = (int8_t)((int)r[s].slot - LOSA_SLOT_CENTRAL);
        m.exposure_us[s] = clamp_u16(exposure);
        m.sensor_flags[s] = wire_flags(&r[s], changed);
    }
    (void)board_link_send(&b->link, AW_ID_LOSA_PEAKS, &m, t_mid);
    send_raw_lines(b, hal, exposure, t_mid);
    b->frames++;
}

static void read_imu(losa_board_t *b, const hal_t *hal, uint64_t now)
{
    mpu9250_sample_t s;
    if (!b->imu_ok || !mpu9250_read(hal, &b->imu, &s)) {
        return;
    }
    aw_imu_t m = {.temperature_c = s.temp_c, .status = s.mag_valid ? AW_IMU_STATUS_MAG_VALID : 0u};
    for (int i = 0; i < 3; i++) {
        /* the MPU-9250 is mounted with its axes along the body axes (x fwd, y right, z down) */
        m.gyro_frd_rad_s[i] = s.gyro_rad_s[i];
        m.accel_frd_m_s2[i] = s.accel_m_s2[i];
        m.mag_frd_ut[i] = s.mag_ut[i];
        if (s.gyro_raw[i] == INT16_MAX || s.gyro_raw[i] == INT16_MIN) {
            m.status |= AW_IMU_STATUS_GYRO_SATURATED;
        }
        if (s.accel_raw[i] == INT16_MAX || s.accel_raw[i] == INT16_MIN) {
            m.status |= AW_IMU_STATUS_ACCEL_SATURATED;
        }
    }
    (void)board_link_send(&b->link, AW_ID_IMU, &m, (uint32_t)now);
}

static uint64_t min_u64(uint64_t a, uint64_t b) { return a < b ? a : b; }

uint64_t board_task(const hal_t *hal)
{
    losa_board_t *b = &losa_board;
    board_link_task_begin(&b->link);
    hal->watchdog_refresh();
    uint64_t link_due = board_link_poll(&b->link, 0); /* host commands first, HELLO due */
    uint64_t now = hal->micros();

    if (!b->read_pending && now >= b->next_frame_us) {
        if (b->exposure_us + 50u < LOSA_FRAME_PERIOD_US) {
            tsl1401_flush(hal, &b->tsl); /* the integration starts now */
            b->next_read_us = b->tsl.last_si_us + b->exposure_us;
        } else {
            b->next_read_us = now; /* integrate over the whole period since the last read */
        }
        b->read_pending = true;
        now = hal->micros();
    }
    if (b->read_pending && now >= b->next_read_us) {
        read_frame(b, hal);
        b->read_pending = false;
        b->next_frame_us += LOSA_FRAME_PERIOD_US;
        now = hal->micros();
        if (b->next_frame_us < now) {
            b->next_frame_us = now; /* fell behind: do not try to catch up with a burst */
        }
    }
    if (board_tick_due(b->t0_us, &b->imu_k, LOSA_IMU_HZ, now)) {
        read_imu(b, hal, now);
    }
    board_link_task_end(&b->link);

    uint64_t due = min_u64(link_due, board_tick_us(b->t0_us, b->imu_k, LOSA_IMU_HZ));
    return min_u64(due, b->read_pending ? b->next_read_us : b->next_frame_us);
}
