"""Simulated marker flights for the tracking tests, from the simulator's own sensor
models (hil_sim `Trajectory`, `MarkerImu`, `LosaOptics`): nothing here uses the EKF's
process model.

The tracker stands at the NED origin facing north: tracker frame x = east, y = down,
z = north. The marker is hand-carried ~3 m in front of it, with a rest period first
(the marker's calibration mode: gyro bias and gravity), then ±90 deg rotations about
each body axis in turn while it sways by decimetres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from airwake.link.messages import BY_NAME
from airwake.record.flight_builder import MessageTable
from airwake.tracking.losa import triangulate

from hil_sim.sensors.losa import MARKER_LED_DIRECTIONS, LosaConfig, LosaOptics
from hil_sim.sensors.marker_imu import MarkerImu, MarkerImuConfig
from hil_sim.world.kinematics import (
    GRAVITY_M_S2,
    Trajectory,
    dcm_to_quat,
    quat_from_rotvec,
    quat_multiply,
)

# tracker frame from NED: x_T = east, y_T = down, z_T = north
C_TRACKER_FROM_NED = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
GRAVITY_TRACKER_M_S2 = (0.0, GRAVITY_M_S2, 0.0)


@dataclass
class MarkerFlight:
    truth: Trajectory  # the marker in NED, at the simulation rate
    imu_t_s: np.ndarray
    gyro_rad_s: np.ndarray
    accel_m_s2: np.ndarray
    losa_t_s: np.ndarray
    losa_pos_t_m: np.ndarray  # triangulated lit LED, tracker frame (NaN where not ok)
    losa_ok: np.ndarray
    lever_arm_body_m: np.ndarray  # (M, 3) lit LED from the marker centre
    truth_led_t_m: np.ndarray  # (M, 3)
    rest_s: float
    losa_peak_px: np.ndarray  # (M, 4) wire peaks, as `losa_peaks` carries them
    losa_slot: np.ndarray  # (M, 4) wire slots
    losa_valid: np.ndarray  # (M, 4)
    led_index: np.ndarray  # (M,) the lit LED

    def truth_in_tracker(self, t_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(position (K, 3), body -> tracker rotation (K, 3, 3)) of the marker centre."""
        tr = self.truth.at(t_s)
        return tr.pos_ned_m @ C_TRACKER_FROM_NED.T, C_TRACKER_FROM_NED @ tr.dcm_body_to_ned


def _smooth_step(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * x * (10 - 15 * x + 6 * x * x)


def marker_trajectory(duration_s: float, rest_s: float = 2.0, rate_hz: float = 2000.0,
                      rotation_period_s: float = 8.0, sway_m: float = 0.25,
                      centre_ned_m=(3.0, 0.0, 0.0)) -> Trajectory:
    """Rest, then ±90 deg about body x, y, z in turn (one `rotation_period_s` sine each,
    repeating), with a sway of `sway_m` in every axis."""
    t = np.arange(0.0, duration_s + 0.5 / rate_hz, 1.0 / rate_hz)
    env = _smooth_step((t - rest_s) / 1.0)
    w = 2 * np.pi * np.array([1 / 5.0, 1 / 7.0, 1 / 3.0])
    pos = np.asarray(centre_ned_m) + sway_m * env[:, None] * np.sin(w * t[:, None] + [0, 1, 2])
    vel = np.gradient(pos, t, axis=0)
    moving = np.maximum(t - rest_s, 0.0)
    seg = np.floor(moving / rotation_period_s).astype(int) % 3
    phase = 2 * np.pi * (moving % rotation_period_s) / rotation_period_s
    theta = np.where(t > rest_s, 0.5 * np.pi * np.sin(phase), 0.0)
    theta_dot = np.where(t > rest_s, 0.5 * np.pi * np.cos(phase) * 2 * np.pi / rotation_period_s,
                         0.0)
    axis = np.eye(3)[seg]
    q = quat_multiply(np.broadcast_to([1.0, 0.0, 0.0, 0.0], (t.size, 4)),
                      quat_from_rotvec(axis * theta[:, None]))
    rates = axis * theta_dot[:, None]
    return Trajectory.from_states(t, pos, vel, q, rates)


def simulate_flight(duration_s: float, seed: int, losa_rate_hz: float = 320.0,
                    dropouts: list[tuple[float, float]] = (), rest_s: float = 2.0
                    ) -> MarkerFlight:
    rng = np.random.default_rng(seed)
    truth = marker_trajectory(duration_s, rest_s=rest_s)
    imu = MarkerImu(MarkerImuConfig(), rng=rng).measure(truth)
    optics = LosaOptics(LosaConfig(), rng=rng)
    t_losa = np.arange(0.01, duration_s - 0.01, 1.0 / losa_rate_hz)
    tr = truth.at(t_losa)
    pos_t = tr.pos_ned_m @ C_TRACKER_FROM_NED.T
    r_t = C_TRACKER_FROM_NED @ tr.dcm_body_to_ned
    q_t = dcm_to_quat(r_t)
    # The marker lights the LED facing the tracker best (§3.3.1.4).
    los = -pos_t / np.linalg.norm(pos_t, axis=1, keepdims=True)
    led_axes = np.einsum("kij,lj->kli", r_t, MARKER_LED_DIRECTIONS)
    led = np.argmax(np.einsum("kli,ki->kl", led_axes, los), axis=1)
    peaks, slots, valid, led_pos = [], [], [], []
    for lo in range(0, t_losa.size, 4000):
        sl = slice(lo, lo + 4000)
        # Drive for a peak near half scale, as the marker's intensity feedback keeps it.
        dry = optics.frames(t_losa[sl], pos_t[sl], q_t[sl], led[sl], 1.0, noise=False)
        peak_v = np.nanmax(np.where(dry.peak_v > 0, dry.peak_v, np.nan), axis=1)
        drive = np.clip(0.5 * optics.config.saturation_v / np.nan_to_num(peak_v, nan=1.0),
                        0.02, 1.0)
        fr = optics.frames(t_losa[sl], pos_t[sl], q_t[sl], led[sl], drive)
        p, ok = _peak_centroids(fr.counts)
        wire = np.where(fr.slot >= 0, optics.geometry.wire_slot(np.maximum(fr.slot, 0)), 0)
        peaks.append(p + 128 * wire)
        slots.append(wire)
        valid.append(ok & (fr.slot >= 0))
        led_pos.append(fr.led_pos_t_m)
    peaks, slots, valid = np.concatenate(peaks), np.concatenate(slots), np.concatenate(valid)
    pos, ok = triangulate(peaks, slots, valid)
    for a, b in dropouts:
        ok &= ~((t_losa >= a) & (t_losa < b))
    radius = optics.config.led_radius_m
    return MarkerFlight(truth, imu.t_s, imu.gyro_rad_s, imu.accel_m_s2, t_losa,
                        np.where(ok[:, None], pos, np.nan), ok,
                        radius * MARKER_LED_DIRECTIONS[led], np.concatenate(led_pos), rest_s,
                        peaks, slots, valid, led)


def _peak_centroids(counts: np.ndarray, half: int = 3, min_counts: float = 60.0
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Sub-pixel peaks of (K, 4, 128) lines: intensity-weighted mean above the line's
    median within ±`half` pixels of the maximum (the reference's ±3 px window). A
    stand-in for the firmware's finder, whose contrast threshold drops about half of
    the weak off-axis peaks at 3 m with the default exposure."""
    c = counts.astype(float)
    dark = np.median(c, axis=-1, keepdims=True)
    top = np.argmax(c, axis=-1)
    cols = np.clip(top[..., None] + np.arange(-half, half + 1), 0, c.shape[-1] - 1)
    w = np.maximum(np.take_along_axis(c, cols, -1) - dark, 0.0)
    total = w.sum(-1)
    ok = np.take_along_axis(c, top[..., None], -1)[..., 0] - dark[..., 0] > min_counts
    px = (w * cols).sum(-1) / np.where(total > 0, total, 1.0)
    return px, ok



def start_ekf(flight: MarkerFlight, seed: int, config=None):
    """The marker's calibration mode (§3.3.2.1) at the end of the rest period: gyro
    bias = mean gyro at rest, attitude by TRIAD from the mean accelerometer and the line
    of sight (eq 3.5), position from the mean triangulation. The simulator has no model
    of the LED-intensity scan that gives the body-frame line of sight, so it is the
    truth with 0.3 deg of noise. Returns (ekf, index of the first IMU sample to feed,
    mask of the LOSA frames to feed)."""
    from airwake.tracking.attitude import initial_attitude
    from airwake.tracking.pose_ekf import PoseEkf

    t_start = flight.rest_s - 0.2
    rest = flight.imu_t_s < t_start
    rest_losa = flight.losa_ok & (flight.losa_t_s < t_start)
    pos_c, r_c = flight.truth_in_tracker(np.array([t_start]))
    rng = np.random.default_rng(seed)
    los_body = r_c[0].T @ (-pos_c[0] / np.linalg.norm(pos_c[0]))
    los_body = los_body + 0.005 * rng.standard_normal(3)
    led_mean = flight.losa_pos_t_m[rest_losa].mean(axis=0)
    r0 = initial_attitude(flight.accel_m_s2[rest].mean(axis=0), los_body, led_mean,
                          GRAVITY_TRACKER_M_S2)
    i0 = int(np.searchsorted(flight.imu_t_s, t_start))
    ekf = PoseEkf(flight.imu_t_s[i0], led_mean - r0 @ flight.lever_arm_body_m[rest_losa].mean(0),
                  dcm_to_quat(r0), gyro_bias_rad_s=flight.gyro_rad_s[rest].mean(axis=0),
                  config=config)
    return ekf, i0, flight.losa_t_s > flight.imu_t_s[i0]


def _rows(name: str, n: int) -> np.ndarray:
    return np.zeros(n, dtype=np.dtype(list(BY_NAME[name].dtype_descr)))


def message_streams(flight: MarkerFlight, seed: int) -> dict:
    """The flight as a recording's message tables (`marker/imu`, `losa/losa_peaks`,
    `marker/marker_attitude`), what `tracking.offline.track_streams` reads."""
    imu = _rows("imu", flight.imu_t_s.size)
    imu["gyro_frd_rad_s"], imu["accel_frd_m_s2"] = flight.gyro_rad_s, flight.accel_m_s2
    lp = _rows("losa_peaks", flight.losa_t_s.size)
    lp["peak_px"] = np.where(flight.losa_valid, flight.losa_peak_px, np.nan)
    lp["slot"], lp["sensor_flags"] = flight.losa_slot, flight.losa_valid.astype(np.uint8)
    # The marker's attitude messages at 120 Hz: calibrating during the rest, then
    # tracking; gravity from the mean accelerometer at rest, the line of sight from its
    # LED scan (truth + 0.3 deg: the simulator has no model of the scan).
    t_att = np.arange(0.0, flight.imu_t_s[-1], 1 / 120)
    att = _rows("marker_attitude", t_att.size)
    t_cal = flight.rest_s - 0.2
    att["mode"] = np.where(t_att >= t_cal, 3, 1)
    rest = flight.imu_t_s < t_cal
    g = -flight.accel_m_s2[rest].mean(axis=0)
    att["gravity_frd_unit"] = g / np.linalg.norm(g)
    pos, rot = flight.truth_in_tracker(t_att)
    los = np.einsum("kji,kj->ki", rot, -pos / np.linalg.norm(pos, axis=1, keepdims=True))
    att["los_frd_unit"] = los + 0.005 * np.random.default_rng(seed).standard_normal(los.shape)
    att["gyro_bias_frd_rad_s"] = flight.gyro_rad_s[rest].mean(axis=0)
    k = np.clip(np.searchsorted(flight.losa_t_s, t_att), 0, flight.losa_t_s.size - 1)
    att["active_led"] = flight.led_index[k]
    return {"marker/imu": MessageTable(flight.imu_t_s, imu),
            "losa/losa_peaks": MessageTable(flight.losa_t_s, lp),
            "marker/marker_attitude": MessageTable(t_att, att)}
