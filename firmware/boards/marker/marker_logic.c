/* Active-marker logic, see marker_logic.h. */
#include "marker_logic.h"

#include <math.h>

marker_cfg_t marker_default_cfg(void)
{
    const marker_cfg_t cfg = {
        .att = marker_att_default_cfg(),
        .calib_us = 5000000u,
        .sweep_settle_us = 150000u,
        .feedback_timeout_us = 3000000u,
        .max_dt_us = 20000u,
        .calib_moving_gyro_rad_s = 0.1f,
        .calib_moving_accel_m_s2 = 0.8f,
        .sweep_intensity = 0.5f,
        .target_peak = 0.20f,
        .deadband = 0.03f,
        .detect_peak = 0.03f,
        .gain = 0.5f,
        .min_intensity = 0.005f,
        .max_intensity = 1.0f,
    };
    return cfg;
}

static float clampf(float v, float lo, float hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

static void enter_calibration(marker_state_t *st, const marker_cfg_t *cfg, uint32_t now_us)
{
    st->mode = MARKER_MODE_CALIBRATING;
    st->intensity = cfg->sweep_intensity;
    st->mode_start_us = now_us;
    for (int i = 0; i < 3; i++) {
        st->gyro_sum[i] = 0.0f;
        st->accel_sum[i] = 0.0f;
    }
    st->calib_samples = 0;
    st->calib_moving = 0;
    for (int k = 0; k < MARKER_LEDS; k++) {
        st->sweep_weight[k] = 0.0f;
    }
    st->sweep_led = 0;
    st->sweep_led_start_us = now_us;
}

void marker_init(marker_state_t *st, const marker_cfg_t *cfg, uint32_t now_us)
{
    marker_att_init(&st->att);
    st->last_imu_us = now_us;
    st->last_ir_us = now_us;
    st->have_imu = 0;
    st->calibrated = 0;
    for (int i = 0; i < 3; i++) {
        st->los_ref[i] = marker_led_dir[0][i];
        st->gravity_ref_m_s2[i] = 0.0f;
    }
    st->gravity_ref_m_s2[2] = st->att.g_mag_m_s2;
    st->active_led = 0;
    st->calibrations = 0;
    st->feedback_timeouts = 0;
    enter_calibration(st, cfg, now_us);
}

/* Calibration sample: accumulate the means, note whether the marker moved. */
static void calib_accumulate(marker_state_t *st, const marker_cfg_t *cfg, const float gyro[3], const float accel[3])
{
    if (st->calib_samples > 0) {
        const float inv_n = 1.0f / (float)st->calib_samples;
        for (int i = 0; i < 3; i++) {
            if (fabsf(gyro[i] - st->gyro_sum[i] * inv_n) > cfg->calib_moving_gyro_rad_s ||
                fabsf(accel[i] - st->accel_sum[i] * inv_n) > cfg->calib_moving_accel_m_s2) {
                st->calib_moving = 1;
            }
        }
    }
    for (int i = 0; i < 3; i++) {
        st->gyro_sum[i] += gyro[i];
        st->accel_sum[i] += accel[i];
    }
    st->calib_samples++;
}

static void finish_calibration(marker_state_t *st, const marker_cfg_t *cfg, uint32_t now_us)
{
    float w_total = 0.0f;
    float los[3] = {0.0f, 0.0f, 0.0f};
    unsigned strongest = 0;
    for (unsigned k = 0; k < MARKER_LEDS; k++) {
        const float w = st->sweep_weight[k];
        w_total += w;
        if (w > st->sweep_weight[strongest]) {
            strongest = k;
        }
        for (int i = 0; i < 3; i++) {
            los[i] += w * marker_led_dir[k][i];
        }
    }
    if (!(w_total > 0.0f)) {
        enter_calibration(st, cfg, now_us); /* no IR seen: sweep again */
        return;
    }
    float n = sqrtf(los[0] * los[0] + los[1] * los[1] + los[2] * los[2]);
    if (n < 1e-3f * w_total) { /* opposite LEDs cancelled out: take the strongest */
        for (int i = 0; i < 3; i++) {
            los[i] = marker_led_dir[strongest][i];
        }
        n = 1.0f;
    }

    float g_body[3];
    if ((!st->calibrated || !st->calib_moving) && st->calib_samples > 0) {
        const float inv_n = 1.0f / (float)st->calib_samples;
        for (int i = 0; i < 3; i++) {
            st->att.bias_rad_s[i] = st->gyro_sum[i] * inv_n;
            g_body[i] = -st->accel_sum[i] * inv_n; /* accel reads +g upwards at rest */
        }
        st->att.g_mag_m_s2 = sqrtf(g_body[0] * g_body[0] + g_body[1] * g_body[1] + g_body[2] * g_body[2]);
    } else {
        quat_rotate_inv(st->att.q, st->gravity_ref_m_s2, g_body);
    }

    st->att.q = quat_identity();
    for (int i = 0; i < 3; i++) {
        st->gravity_ref_m_s2[i] = g_body[i];
        st->los_ref[i] = los[i] / n;
    }
    st->active_led = (uint8_t)marker_led_facing(st->los_ref);
    /* Start where the sweep says the target is: peak scales with drive. */
    const float seen = st->sweep_weight[st->active_led];
    st->intensity = seen > cfg->detect_peak ? clampf(cfg->sweep_intensity * cfg->target_peak / seen,
                                                     cfg->min_intensity, cfg->max_intensity)
                                            : cfg->sweep_intensity;
    st->mode = MARKER_MODE_TRACKING;
    st->mode_start_us = now_us;
    st->last_ir_us = now_us;
    st->calibrated = 1;
    st->calibrations++;
}

void marker_imu_step(marker_state_t *st, const marker_cfg_t *cfg, uint32_t now_us, const float gyro_rad_s[3],
                     const float accel_m_s2[3])
{
    if (st->have_imu) {
        uint32_t d = now_us - st->last_imu_us;
        if (d > cfg->max_dt_us) {
            d = cfg->max_dt_us;
        }
        marker_att_step(&st->att, &cfg->att, gyro_rad_s, accel_m_s2, (float)d * 1e-6f);
    }
    st->last_imu_us = now_us;
    st->have_imu = 1;

    if (st->mode == MARKER_MODE_CALIBRATING) {
        calib_accumulate(st, cfg, gyro_rad_s, accel_m_s2);
        const uint32_t elapsed = now_us - st->mode_start_us;
        if (elapsed >= cfg->calib_us) {
            finish_calibration(st, cfg, now_us);
            return;
        }
        const uint32_t dwell = cfg->calib_us / MARKER_LEDS;
        const uint32_t led = elapsed / (dwell ? dwell : 1u);
        if (led != st->sweep_led && led < MARKER_LEDS) {
            st->sweep_led = (uint8_t)led;
            st->sweep_led_start_us = now_us;
        }
        return;
    }

    if (now_us - st->last_ir_us > cfg->feedback_timeout_us) {
        st->feedback_timeouts++;
        enter_calibration(st, cfg, now_us);
        return;
    }
    float los_body[3];
    quat_rotate_inv(st->att.q, st->los_ref, los_body);
    st->active_led = (uint8_t)marker_led_facing(los_body);
}

void marker_feedback(marker_state_t *st, const marker_cfg_t *cfg, uint32_t now_us,
                     const float peak_fraction[MARKER_LEDS])
{
    if (st->mode == MARKER_MODE_CALIBRATING) {
        const float f = peak_fraction[st->sweep_led];
        if (now_us - st->sweep_led_start_us >= cfg->sweep_settle_us && f >= cfg->detect_peak &&
            f > st->sweep_weight[st->sweep_led]) {
            st->sweep_weight[st->sweep_led] = f;
        }
        return;
    }
    const float f = peak_fraction[st->active_led];
    float factor;
    if (!(f >= cfg->detect_peak)) { /* also NaN */
        factor = 1.5f;
    } else {
        st->last_ir_us = now_us;
        const float err = cfg->target_peak - f;
        if (fabsf(err) <= cfg->deadband) {
            return;
        }
        factor = clampf(1.0f + cfg->gain * err / cfg->target_peak, 0.5f, 2.0f);
    }
    st->intensity = clampf(st->intensity * factor, cfg->min_intensity, cfg->max_intensity);
}

unsigned marker_lit_led(const marker_state_t *st)
{
    return st->mode == MARKER_MODE_CALIBRATING ? st->sweep_led : st->active_led;
}

void marker_output(const marker_state_t *st, marker_output_t *out)
{
    out->q = st->att.q;
    quat_rotate_inv(st->att.q, st->gravity_ref_m_s2, out->gravity_m_s2);
    quat_rotate_inv(st->att.q, st->los_ref, out->los);
    for (int i = 0; i < 3; i++) {
        out->gyro_bias_rad_s[i] = st->att.bias_rad_s[i];
    }
    out->mode = (uint8_t)st->mode;
    out->still = st->att.still;
    out->active_led = (uint8_t)marker_lit_led(st);
    out->intensity = st->intensity;
}

void marker_led_drive(const marker_state_t *st, float drive[MARKER_LEDS])
{
    for (unsigned k = 0; k < MARKER_LEDS; k++) {
        drive[k] = 0.0f;
    }
    drive[marker_lit_led(st)] = st->intensity;
}
