/* Marker attitude: gyro integration (eq 3.9) with a gyro-bias estimate that adapts
 * while the marker is still (reference §3.3.1.4). */
#ifndef AW_MARKER_ATTITUDE_H
#define AW_MARKER_ATTITUDE_H

#include <stdint.h>

#include "quat.h"

typedef struct {
    float still_gyro_rad_s;  /* |gyro - bias| below this on every axis ... */
    float still_accel_m_s2;  /* ... and ||accel| - g| below this ... */
    float still_time_s;      /* ... continuously for this long: still */
    float bias_tau_s;        /* time constant of the bias update while still */
} marker_att_cfg_t;

typedef struct {
    quat_t q;              /* body -> reference (body frame at the end of calibration) */
    float bias_rad_s[3];   /* gyro bias estimate */
    float g_mag_m_s2;      /* gravity magnitude from calibration */
    float still_s;         /* how long the still conditions have held */
    uint8_t still;         /* still_s >= still_time_s */
} marker_att_t;

marker_att_cfg_t marker_att_default_cfg(void);
void marker_att_init(marker_att_t *att);

/* Stillness test of one sample against the current bias (no state change). */
int marker_att_sample_quiet(const marker_att_t *att, const marker_att_cfg_t *cfg, const float gyro_rad_s[3],
                            const float accel_m_s2[3]);

/* One IMU sample: integrate (gyro - bias) over dt, update stillness and, when still,
 * low-pass the bias towards the raw gyro. */
void marker_att_step(marker_att_t *att, const marker_att_cfg_t *cfg, const float gyro_rad_s[3],
                     const float accel_m_s2[3], float dt_s);

#endif
