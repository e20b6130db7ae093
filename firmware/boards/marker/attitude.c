/* Marker attitude, see attitude.h. */
#include "attitude.h"

marker_att_cfg_t marker_att_default_cfg(void)
{
    /* MPU9250-class: bias drifts ~0.01 rad/s, noise ~0.005 rad/s RMS at 450 Hz. */
    const marker_att_cfg_t cfg = {
        .still_gyro_rad_s = 0.03f,
        .still_accel_m_s2 = 0.4f,
        .still_time_s = 0.25f,
        .bias_tau_s = 2.0f,
    };
    return cfg;
}

void marker_att_init(marker_att_t *att)
{
    att->q = quat_identity();
    for (int i = 0; i < 3; i++) {
        att->bias_rad_s[i] = 0.0f;
    }
    att->g_mag_m_s2 = 9.80665f;
    att->still_s = 0.0f;
    att->still = 0;
}

static float absf(float v)
{
    return v < 0.0f ? -v : v;
}

int marker_att_sample_quiet(const marker_att_t *att, const marker_att_cfg_t *cfg, const float gyro_rad_s[3],
                            const float accel_m_s2[3])
{
    for (int i = 0; i < 3; i++) {
        if (absf(gyro_rad_s[i] - att->bias_rad_s[i]) > cfg->still_gyro_rad_s) {
            return 0;
        }
    }
    /* ||a| - g| < d  <=>  (g - d)^2 < |a|^2 < (g + d)^2, no sqrt */
    const float a2 = accel_m_s2[0] * accel_m_s2[0] + accel_m_s2[1] * accel_m_s2[1] + accel_m_s2[2] * accel_m_s2[2];
    const float lo = att->g_mag_m_s2 - cfg->still_accel_m_s2;
    const float hi = att->g_mag_m_s2 + cfg->still_accel_m_s2;
    return a2 > lo * lo && a2 < hi * hi;
}

void marker_att_step(marker_att_t *att, const marker_att_cfg_t *cfg, const float gyro_rad_s[3],
                     const float accel_m_s2[3], float dt_s)
{
    const float w[3] = {
        gyro_rad_s[0] - att->bias_rad_s[0],
        gyro_rad_s[1] - att->bias_rad_s[1],
        gyro_rad_s[2] - att->bias_rad_s[2],
    };
    att->q = quat_integrate(att->q, w, dt_s); /* eq 3.9 */

    if (marker_att_sample_quiet(att, cfg, gyro_rad_s, accel_m_s2)) {
        att->still_s += dt_s;
    } else {
        att->still_s = 0.0f;
    }
    att->still = att->still_s >= cfg->still_time_s;
    if (att->still) {
        /* bias <- bias + dt/tau (gyro - bias): the marker is not rotating */
        const float k = dt_s / cfg->bias_tau_s;
        for (int i = 0; i < 3; i++) {
            att->bias_rad_s[i] += k * w[i];
        }
    }
}
