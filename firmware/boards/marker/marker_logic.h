/* Active-marker logic (reference §3.3.1.4): calibration mode with LED sweep, tracking
 * mode lighting only the LED that faces the tracker at the lowest intensity that keeps
 * the tracker's peak at ~20 % of full scale, back to calibration after 3 s without IR
 * feedback.
 *
 * Calibration (5 s at power-on and on re-entry): the marker is meant to be still; the
 * gyro mean becomes the bias and minus the accelerometer mean the gravity vector (on a
 * re-entry only when the marker really was still; otherwise the old bias is kept and
 * gravity is carried over through the integrated attitude). Meanwhile the LEDs are lit
 * one at a time (dwell = calib / 4) at `sweep_intensity`; the host's feedback for the lit
 * LED (tracker peak, fraction of full scale) after `sweep_settle_us` gives each LED's
 * weight, and the line of sight is the weight-averaged LED direction. A sweep that sees
 * no IR at all is repeated. At the end the attitude restarts at identity: the
 * quaternion is the rotation from the current body frame to the body frame at the end
 * of the last calibration.
 *
 * Tracking: LoS_body = q* LoS_ref q; the active LED is the one with the largest dot
 * product with it. Intensity control on the active LED's feedback f:
 *   f below detect_peak           -> intensity x 1.5 (reacquire)
 *   |f - target| within deadband  -> hold
 *   otherwise                     -> intensity x (1 + gain (target - f) / target),
 *                                    the factor limited to [0.5, 2]
 * bounded to [min_intensity, max_intensity].
 *
 * Time is the board's microsecond clock (uint32_t, wrap-safe differences).
 */
#ifndef AW_MARKER_LOGIC_H
#define AW_MARKER_LOGIC_H

#include <stdint.h>

#include "attitude.h"
#include "quat.h"
#include "leds.h"

typedef enum {
    MARKER_MODE_CALIBRATING = 0,
    MARKER_MODE_TRACKING = 1,
} marker_mode_t;

typedef struct {
    marker_att_cfg_t att;
    uint32_t calib_us;            /* calibration length (5 s) */
    uint32_t sweep_settle_us;     /* feedback ignored this long after an LED switch */
    uint32_t feedback_timeout_us; /* no IR this long in tracking -> calibrate (3 s) */
    uint32_t max_dt_us;           /* a longer IMU gap is integrated as this long */
    float calib_moving_gyro_rad_s; /* a calibration sample this far from the running
                                      mean (gyro) ... */
    float calib_moving_accel_m_s2; /* ... or accel: the marker was moved */
    float sweep_intensity;        /* LED drive during the sweep, 0..1 */
    float target_peak;            /* tracker peak to hold, fraction of full scale (0.2) */
    float deadband;               /* +- around target where the intensity holds */
    float detect_peak;            /* feedback below this: no IR seen */
    float gain;                   /* intensity loop gain */
    float min_intensity, max_intensity;
} marker_cfg_t;

typedef struct {
    marker_att_t att;
    marker_mode_t mode;
    uint32_t mode_start_us;
    uint32_t last_ir_us;
    uint32_t last_imu_us;
    uint8_t have_imu;
    uint8_t calibrated; /* a calibration has completed at least once */
    /* calibration accumulators */
    float gyro_sum[3];
    float accel_sum[3];
    uint32_t calib_samples;
    uint8_t calib_moving;
    float sweep_weight[MARKER_LEDS];
    uint32_t sweep_led_start_us;
    uint8_t sweep_led;
    /* line of sight to the tracker, unit vector in the reference frame */
    float los_ref[3];
    float gravity_ref_m_s2[3];
    uint8_t active_led;
    float intensity; /* drive of the lit LED, 0..1 */
    /* counters */
    uint32_t calibrations;
    uint32_t feedback_timeouts;
} marker_state_t;

typedef struct {
    quat_t q;                  /* body -> calibration frame */
    float gravity_m_s2[3];     /* gravity in the body frame (points down, ~9.81) */
    float los[3];              /* unit line of sight to the tracker, body frame */
    float gyro_bias_rad_s[3];
    uint8_t mode;              /* marker_mode_t */
    uint8_t active_led;        /* LED lit now */
    uint8_t still;
    float intensity;           /* drive of the lit LED, 0..1 */
} marker_output_t;

marker_cfg_t marker_default_cfg(void);
void marker_init(marker_state_t *st, const marker_cfg_t *cfg, uint32_t now_us);

/* One IMU sample (450 Hz): gyro rad/s, accel m/s^2 (specific force: +g up at rest). */
void marker_imu_step(marker_state_t *st, const marker_cfg_t *cfg, uint32_t now_us, const float gyro_rad_s[3],
                     const float accel_m_s2[3]);

/* Host feedback (marker_command): the tracker's peak for each LED, fraction of full
 * scale; only the entry of the LED lit now is used. */
void marker_feedback(marker_state_t *st, const marker_cfg_t *cfg, uint32_t now_us,
                     const float peak_fraction[MARKER_LEDS]);

/* Snapshot for the 120 Hz attitude message. */
void marker_output(const marker_state_t *st, marker_output_t *out);

/* The LED lit now (swept LED in calibration, active LED in tracking). */
unsigned marker_lit_led(const marker_state_t *st);

/* Drive for every LED (0..1): only one is ever non-zero. */
void marker_led_drive(const marker_state_t *st, float drive[MARKER_LEDS]);

#endif
