/* Active-marker logic: calibration (bias, gravity, LoS sweep), LED choice, intensity
 * loop, feedback timeout, bias adaptation. */
#include <math.h>
#include <stdint.h>

#include "marker/marker_logic.h"
#include "test_algos.h"

#define IMU_DT_US 2222u /* 450 Hz */

static const float BIAS[3] = {0.01f, -0.02f, 0.005f};
static const float ACCEL_REST[3] = {0.0f, 0.0f, -9.81f}; /* z down: +g upwards reads -z */

/* The tracker's peak for LED k: drive x gain x max(0, cos angle to the tracker). */
static void host_feedback(const marker_state_t *st, const float los_body[3], float gain, float fb[MARKER_LEDS])
{
    float drive[MARKER_LEDS];
    marker_led_drive(st, drive);
    for (unsigned k = 0; k < MARKER_LEDS; k++) {
        const float *d = marker_led_dir[k];
        const float c = d[0] * los_body[0] + d[1] * los_body[1] + d[2] * los_body[2];
        fb[k] = drive[k] * gain * (c > 0.0f ? c : 0.0f);
        fb[k] = fb[k] > 1.0f ? 1.0f : fb[k];
    }
}

/* Runs still for `us`, feedback at 100 Hz from a tracker along los_body. */
static uint32_t run_still(marker_state_t *st, const marker_cfg_t *cfg, uint32_t t, uint32_t us, const float los[3],
                          float gain, const float gyro[3])
{
    const uint32_t end = t + us;
    unsigned i = 0;
    while ((int32_t)(end - t) > 0) {
        t += IMU_DT_US;
        marker_imu_step(st, cfg, t, gyro, ACCEL_REST);
        if (++i % 4 == 0) {
            float fb[MARKER_LEDS];
            host_feedback(st, los, gain, fb);
            marker_feedback(st, cfg, t, fb);
        }
    }
    return t;
}

static void normalize3(float v[3])
{
    const float n = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; i++) {
        v[i] /= n;
    }
}

/* Power-on calibration must yield the gyro bias, gravity (down) and the LoS as the
 * feedback-weighted mean of LED directions, then switch to tracking. */
static void test_marker_calibration_estimates_bias_gravity_and_los(void)
{
    const marker_cfg_t cfg = marker_default_cfg();
    marker_state_t st;
    uint32_t t = 4000000000u; /* the clock wraps during the test */
    marker_init(&st, &cfg, t);
    float los[3] = {0.8f, 0.3f, -0.5f};
    normalize3(los);
    t = run_still(&st, &cfg, t, 4900000u, los, 1.0f, BIAS);
    CHECK(st.mode == MARKER_MODE_CALIBRATING);
    t = run_still(&st, &cfg, t, 200000u, los, 1.0f, BIAS);
    CHECK(st.mode == MARKER_MODE_TRACKING);
    CHECK(st.calibrations == 1);
    marker_output_t out;
    marker_output(&st, &out);
    for (int i = 0; i < 3; i++) {
        CHECK_NEAR(out.gyro_bias_rad_s[i], BIAS[i], 1e-5);
        CHECK_NEAR(out.gravity_m_s2[i], -ACCEL_REST[i], 1e-3);
    }
    /* expected LoS: weights = cos(angle) of the LEDs that see the tracker */
    float want[3] = {0.0f, 0.0f, 0.0f};
    for (unsigned k = 0; k < MARKER_LEDS; k++) {
        const float *d = marker_led_dir[k];
        float c = d[0] * los[0] + d[1] * los[1] + d[2] * los[2];
        c = c > 0.0f ? c * cfg.sweep_intensity : 0.0f;
        c = c >= cfg.detect_peak ? c : 0.0f;
        for (int i = 0; i < 3; i++) {
            want[i] += c * d[i];
        }
    }
    normalize3(want);
    for (int i = 0; i < 3; i++) {
        CHECK_NEAR(out.los[i], want[i], 1e-4);
    }
    CHECK(out.active_led == marker_led_facing(los));
}

/* After a 180 deg yaw the tracker is seen by another LED: the lit LED must follow the
 * integrated attitude (LoS rotated by q). */
static void test_marker_lit_led_follows_rotation(void)
{
    const marker_cfg_t cfg = marker_default_cfg();
    marker_state_t st;
    uint32_t t = 0;
    marker_init(&st, &cfg, t);
    float los[3] = {1.0f, 1.0f, 1.2f}; /* roughly LED 0 (+1, +1, +1) */
    normalize3(los);
    t = run_still(&st, &cfg, t, 5100000u, los, 1.0f, BIAS);
    CHECK(st.mode == MARKER_MODE_TRACKING);
    CHECK(marker_lit_led(&st) == 0);
    const float l0[3] = {st.los_ref[0], st.los_ref[1], st.los_ref[2]};
    /* yaw +180 deg about body z in 1 s: the tracker appears at (-1, -1, +1.2) = LED 3 */
    const float rate[3] = {BIAS[0], BIAS[1], BIAS[2] + 3.14159265f};
    for (uint32_t i = 0; i < 450; i++) {
        t += IMU_DT_US;
        marker_imu_step(&st, &cfg, t, rate, ACCEL_REST);
    }
    t += 1000; /* remainder of the second */
    marker_output_t out;
    marker_output(&st, &out);
    CHECK(out.active_led == 3);
    /* the calibrated LoS, in the body frame rotated by -180 deg about z */
    const float c = cosf(-3.14159265f), s = sinf(-3.14159265f);
    CHECK_NEAR(out.los[0], c * l0[0] - s * l0[1], 5e-3);
    CHECK_NEAR(out.los[1], s * l0[0] + c * l0[1], 5e-3);
    CHECK_NEAR(out.los[2], l0[2], 5e-3);
    CHECK_NEAR(out.gravity_m_s2[2], 9.81, 1e-2); /* yaw keeps gravity */
}

/* The LED intensity loop must settle where the tracker sees ~20 % of full scale. */
static void test_marker_intensity_settles_at_target_peak(void)
{
    const marker_cfg_t cfg = marker_default_cfg();
    marker_state_t st;
    uint32_t t = 0;
    marker_init(&st, &cfg, t);
    float los[3] = {1.0f, 0.9f, 1.1f}; /* LED 0 */
    normalize3(los);
    t = run_still(&st, &cfg, t, 5100000u, los, 4.0f, BIAS);
    t = run_still(&st, &cfg, t, 2000000u, los, 4.0f, BIAS);
    float fb[MARKER_LEDS];
    host_feedback(&st, los, 4.0f, fb);
    CHECK(st.mode == MARKER_MODE_TRACKING);
    CHECK_NEAR(fb[marker_lit_led(&st)], cfg.target_peak, cfg.deadband + 1e-3);
    CHECK(st.intensity < 0.1f); /* a bright link runs the LED low */
}

/* No IR for 3 s must send the marker back to calibration (gyro drift correction). */
static void test_marker_recalibrates_after_3s_without_ir(void)
{
    const marker_cfg_t cfg = marker_default_cfg();
    marker_state_t st;
    uint32_t t = 0;
    marker_init(&st, &cfg, t);
    float los[3] = {0.0f, 0.0f, -1.0f};
    t = run_still(&st, &cfg, t, 5100000u, los, 1.0f, BIAS);
    CHECK(st.mode == MARKER_MODE_TRACKING);
    t = run_still(&st, &cfg, t, 2900000u, los, 0.0f, BIAS);
    CHECK(st.mode == MARKER_MODE_TRACKING);
    t = run_still(&st, &cfg, t, 200000u, los, 0.0f, BIAS);
    CHECK(st.mode == MARKER_MODE_CALIBRATING);
    CHECK(st.feedback_timeouts == 1);
    /* without IR the sweep repeats instead of finishing with no LoS */
    t = run_still(&st, &cfg, t, 6000000u, los, 0.0f, BIAS);
    CHECK(st.mode == MARKER_MODE_CALIBRATING);
    CHECK(st.calibrations == 1);
    (void)t;
}

/* A gyro bias that drifts after calibration must be learnt while the marker is still. */
static void test_marker_bias_adapts_when_still(void)
{
    const marker_cfg_t cfg = marker_default_cfg();
    marker_state_t st;
    uint32_t t = 0;
    marker_init(&st, &cfg, t);
    float los[3] = {0.0f, 0.0f, -1.0f};
    t = run_still(&st, &cfg, t, 5100000u, los, 1.0f, BIAS);
    const float drifted[3] = {BIAS[0] + 0.01f, BIAS[1] - 0.008f, BIAS[2]};
    t = run_still(&st, &cfg, t, 12000000u, los, 1.0f, drifted);
    marker_output_t out;
    marker_output(&st, &out);
    for (int i = 0; i < 3; i++) {
        CHECK_NEAR(out.gyro_bias_rad_s[i], drifted[i], 2e-4);
    }
    CHECK(out.still);
    (void)t;
}

int main(void)
{
    RUN(test_marker_calibration_estimates_bias_gravity_and_los);
    RUN(test_marker_lit_led_follows_rotation);
    RUN(test_marker_intensity_settles_at_target_peak);
    RUN(test_marker_recalibrates_after_3s_without_ir);
    RUN(test_marker_bias_adapts_when_still);
    return ALGO_TEST_EXIT();
}
