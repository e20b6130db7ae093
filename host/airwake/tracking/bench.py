"""`airwake bench` section "tracking": pose-EKF throughput on one core.

The stream is the marker's: IMU at 450 Hz and LOSA positions at 320 Hz (§3.3), a marker
turning at 1 rad/s about a tilted axis 3 m in front of the tracker (the figures are
about speed, not accuracy; tests/tracking scores accuracy on the simulator).
`ekf_updates_per_s` counts filter steps, IMU predictions plus LOSA updates, per CPU
second of this process (best of the repeats: the machine is shared).
"""

from __future__ import annotations

import time

import numpy as np

from airwake.tracking.pose_ekf import PoseEkf, quat_exp, quat_multiply, quat_to_matrix, run_pose_ekf

SECTION = "tracking"
IMU_RATE_HZ = 450.0
LOSA_RATE_HZ = 320.0


def _stream(duration_s: float, rng: np.random.Generator):
    g = np.array([0.0, 9.798, 0.0])
    w = np.array([0.3, 0.9, 0.3])
    imu_t = np.arange(0.0, duration_s, 1.0 / IMU_RATE_HZ)
    q = np.array([1.0, 0.0, 0.0, 0.0])
    accel = np.empty((imu_t.size, 3))
    for i in range(imu_t.size):
        accel[i] = quat_to_matrix(q).T @ -g
        q = quat_multiply(q, quat_exp(w / IMU_RATE_HZ))
    gyro = w + 1e-3 * rng.standard_normal((imu_t.size, 3))
    accel += 0.01 * rng.standard_normal(accel.shape)
    losa_t = np.arange(0.5 / LOSA_RATE_HZ, duration_s, 1.0 / LOSA_RATE_HZ)
    losa_pos = np.array([0.0, 0.0, 3.0]) + 0.003 * rng.standard_normal((losa_t.size, 3))
    return imu_t, gyro, accel, losa_t, losa_pos


def run(quick: bool) -> dict:
    duration_s = 5.0 if quick else 20.0
    stream = _stream(duration_s, np.random.default_rng(0))
    best = 0.0
    for _ in range(2 if quick else 3):
        ekf = PoseEkf(0.0, (0.0, 0.0, 3.0), (1.0, 0.0, 0.0, 0.0))
        t0 = time.process_time()
        run_pose_ekf(ekf, *stream)
        cpu_s = time.process_time() - t0
        steps = ekf.counters.predictions + ekf.counters.accepted + ekf.counters.gated
        best = max(best, steps / cpu_s)
    c = ekf.counters
    return {
        "ekf_updates_per_s": round(best),
        "ekf_realtime_factor": round(best / (IMU_RATE_HZ + LOSA_RATE_HZ), 1),
        "ekf_losa_accepted_fraction": round(c.accepted / max(1, c.accepted + c.gated), 4),
    }
