/* Callgrind driver: active-marker IMU steps at 450 Hz (tracking mode: gyro integration,
 * stillness/bias, LED choice) plus the host feedback at ~110 Hz.
 * Usage: bench_marker_step [steps]. bench.py counts instructions inside
 * marker_imu_step (calibration, 5 s = 2250 steps, runs before collection matters
 * little: it is cheaper than tracking and amortised over the run). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "marker/marker_logic.h"

int main(int argc, char **argv)
{
    const long n = argc > 1 ? atol(argv[1]) : 20000;
    const marker_cfg_t cfg = marker_default_cfg();
    marker_state_t st;
    uint32_t t = 0;
    marker_init(&st, &cfg, t);
    const float accel[3] = {0.0f, 0.0f, -9.81f};
    const float fb[MARKER_LEDS] = {0.2f, 0.2f, 0.2f, 0.2f};
    /* calibrate still */
    const float bias[3] = {0.01f, -0.02f, 0.005f};
    for (int i = 0; i < 2400; i++) {
        t += 2222u;
        marker_imu_step(&st, &cfg, t, bias, accel);
        if (i % 4 == 0) {
            marker_feedback(&st, &cfg, t, fb);
        }
    }
    double sum = 0.0;
    for (long i = 0; i < n; i++) {
        const float ph = (float)i * 0.01f;
        const float gyro[3] = {bias[0] + 0.5f * sinf(ph), bias[1] + 0.3f * cosf(ph), bias[2] + 0.2f};
        t += 2222u;
        marker_imu_step(&st, &cfg, t, gyro, accel);
        if (i % 4 == 0) {
            marker_feedback(&st, &cfg, t, fb);
        }
        sum += st.att.q.w;
    }
    printf("steps %ld mode %d checksum %.3f\n", n, (int)st.mode, sum);
    return 0;
}
