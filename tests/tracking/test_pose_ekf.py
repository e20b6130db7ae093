"""Pose EKF on the simulator's marker IMU and LOSA optics (tests/tracking/sim_data.py):
attitude through ±90 deg rotations, position against triangulation alone, a 10-minute
run with dropouts, gating and re-acquisition."""

import numpy as np
import pytest
from airwake.tracking.errors import TrackingError
from airwake.tracking.pose_ekf import PoseEkf, PoseEkfConfig, quat_to_matrix, run_pose_ekf
from scipy.spatial.transform import Rotation

from tests.tracking.sim_data import GRAVITY_TRACKER_M_S2, simulate_flight, start_ekf


def _run(flight, seed, **kw):
    ekf, i0, sel = start_ekf(flight, seed)
    track = run_pose_ekf(ekf, flight.imu_t_s[i0:], flight.gyro_rad_s[i0:],
                         flight.accel_m_s2[i0:], flight.losa_t_s[sel],
                         flight.losa_pos_t_m[sel], flight.losa_ok[sel],
                         flight.lever_arm_body_m[sel], **kw)
    return ekf, track, sel


def _attitude_error_deg(flight, track) -> np.ndarray:
    _, r_truth = flight.truth_in_tracker(track.t_s)
    r_est = np.array([quat_to_matrix(q) for q in track.quat_wxyz])
    return np.degrees(Rotation.from_matrix(np.einsum("kji,kjl->kil", r_est, r_truth))
                      .magnitude())


def _led_errors_m(flight, track, sel):
    """|error| of the EKF's and of triangulation's lit-LED position at each used frame."""
    idx = np.searchsorted(track.t_s, flight.losa_t_s[sel], side="right") - 1
    r_est = np.array([quat_to_matrix(q) for q in track.quat_wxyz[idx]])
    led = track.pos_ref_m[idx] + np.einsum("kij,kj->ki", r_est, flight.lever_arm_body_m[sel])
    truth = flight.truth_led_t_m[sel]
    ok = flight.losa_ok[sel]
    return (np.linalg.norm(led - truth, axis=1)[ok],
            np.linalg.norm(flight.losa_pos_t_m[sel] - truth, axis=1)[ok])


@pytest.fixture(scope="module")
def flight_run():
    flight = simulate_flight(40.0, seed=21)
    ekf, track, sel = _run(flight, 21)
    return flight, ekf, track, sel


def test_attitude_within_1deg_of_truth_through_90deg_rotations(flight_run):
    # The reference's check (Fig 3.12): ±90 deg about each axis. The first rotation makes
    # the accelerometer bias observable; the initial tilt error is that bias over g.
    flight, _, track, _ = flight_run
    err = _attitude_error_deg(flight, track)
    converged = track.t_s > flight.rest_s + 8.0
    assert err[converged].max() < 1.0, f"max {err[converged].max():.2f} deg after convergence"
    assert err.max() < 2.0, f"max {err.max():.2f} deg over the whole run"


def test_position_error_lower_than_triangulation_alone(flight_run):
    # The simulated LOSA error is mostly correlated over tens of frames (fixed-pattern
    # noise, pixel locking), which no filter averages away quickly: measured 20-30 %.
    flight, _, track, sel = flight_run
    ekf_err, tri_err = _led_errors_m(flight, track, sel)
    assert ekf_err.mean() < 0.85 * tri_err.mean(), (ekf_err.mean(), tri_err.mean())


@pytest.mark.xfail(strict=True, reason="issue 12 target (>= 30 % lower) not met on the "
                   "simulated optics by the forward filter: the triangulation error is "
                   "time-correlated (the RTS smoother meets it: test_smoother.py)")
def test_position_error_30_percent_lower_than_triangulation(flight_run):
    flight, _, track, sel = flight_run
    ekf_err, tri_err = _led_errors_m(flight, track, sel)
    assert ekf_err.mean() < 0.70 * tri_err.mean()


@pytest.mark.slow
def test_ten_minutes_with_losa_dropouts_stays_bounded_and_p_positive_definite():
    # A hand-carried survey loses the tracker behind people and poles: the filter must
    # coast on the IMU, re-acquire, and keep a valid covariance for the whole flight.
    gaps = [(60.0, 60.5), (150.0, 152.0), (300.0, 305.0), (450.0, 451.0), (520.0, 530.0)]
    flight = simulate_flight(600.0, seed=33, losa_rate_hz=100.0, dropouts=gaps)
    ekf, i0, sel = start_ekf(flight, 33)
    edges = np.arange(flight.imu_t_s[i0], flight.imu_t_s[-1] + 10.0, 10.0)
    att_max, pos_err = [], []
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        imu = slice(np.searchsorted(flight.imu_t_s, a), np.searchsorted(flight.imu_t_s, b))
        if imu.start < i0:
            imu = slice(i0, imu.stop)
        losa = sel & (flight.losa_t_s >= a) & (flight.losa_t_s < b)
        track = run_pose_ekf(ekf, flight.imu_t_s[imu], flight.gyro_rad_s[imu],
                             flight.accel_m_s2[imu], flight.losa_t_s[losa],
                             flight.losa_pos_t_m[losa], flight.losa_ok[losa],
                             flight.lever_arm_body_m[losa])
        P = ekf.P
        assert np.array_equal(P, P.T) or np.allclose(P, P.T, rtol=0, atol=1e-15), b
        assert np.linalg.eigvalsh(P).min() > 0, f"P not positive definite at {b:.0f} s"
        att_max.append(_attitude_error_deg(flight, track).max())
        pos_c, _ = flight.truth_in_tracker(track.t_s[-1:])
        pos_err.append(np.linalg.norm(track.pos_ref_m[-1] - pos_c[0]))
    assert max(att_max) < 2.0, max(att_max)
    assert max(pos_err) < 0.05, max(pos_err)
    assert ekf.counters.accepted > 0.95 * flight.losa_ok[sel].sum()


def _at_rest_ekf(**config):
    cfg = PoseEkfConfig(**config)
    ekf = PoseEkf(0.0, (0.0, 0.0, 3.0), (1.0, 0.0, 0.0, 0.0), config=cfg)
    return ekf, np.zeros(3), -np.asarray(GRAVITY_TRACKER_M_S2)


def _rest(ekf, gyro, accel, t0, t1, rate=450.0):
    for t in np.arange(t0, t1, 1.0 / rate):
        ekf.predict(t, gyro, accel)


def test_gating_rejects_an_outlier_and_leaves_the_estimate_alone(flight_run):
    # A reflection or a wrong slot gives one wild triangulation: it must not move the pose.
    ekf, gyro, accel = _at_rest_ekf()
    for k in range(200):
        _rest(ekf, gyro, accel, k / 100, (k + 1) / 100)
        assert ekf.update_position((k + 1) / 100 + 1e-4, (0.0, 0.0, 3.0)).accepted
    before = ekf.pos.copy()
    res = ekf.update_position(2.0105, (0.0, 0.3, 3.0))
    assert res.outcome == "gated" and res.nis > res.gate
    assert np.linalg.norm(ekf.pos - before) < 1e-3
    # and in the flight: a 0.3 m outlier among real frames is rejected
    flight, _, _, _ = flight_run
    pos = flight.losa_pos_t_m.copy()
    k = int(np.searchsorted(flight.losa_t_s, 20.0))
    pos[k] += (0.0, 0.3, 0.0)
    ekf2, i0, sel = start_ekf(flight, 21)
    track = run_pose_ekf(ekf2, flight.imu_t_s[i0:], flight.gyro_rad_s[i0:],
                         flight.accel_m_s2[i0:], flight.losa_t_s[sel], pos[sel],
                         flight.losa_ok[sel], flight.lever_arm_body_m[sel])
    outcome = dict(zip(flight.losa_t_s[sel], track.losa_outcome, strict=True))
    assert outcome[flight.losa_t_s[k]] == "gated"


def test_after_a_dropout_the_gate_widens_and_the_position_is_reacquired():
    # The marker carried on while the tracker lost it: prediction only, then the
    # widened gate and, if the jump is too large even for it, re-acquisition.
    ekf, gyro, accel = _at_rest_ekf(max_rejections=5)
    for k in range(100):
        _rest(ekf, gyro, accel, k / 100, (k + 1) / 100)
        ekf.update_position((k + 1) / 100 + 1e-4, (0.0, 0.0, 3.0))
    _rest(ekf, gyro, accel, 1.0, 3.0)  # 2 s without LOSA
    res = ekf.update_position(3.0 + 1e-4, (0.0, 0.0, 3.05))
    assert res.accepted and res.gate > 20 * ekf._gate  # widened gate took it
    _rest(ekf, gyro, accel, 3.0, 5.0)
    outcomes = []
    for k in range(10):
        _rest(ekf, gyro, accel, 5 + k / 100, 5 + (k + 1) / 100)
        outcomes.append(ekf.update_position(5 + (k + 1) / 100 + 1e-4, (0.0, 1.0, 3.0)).outcome)
    assert outcomes[:4] == ["gated"] * 4 and "reacquired" in outcomes
    assert np.linalg.norm(ekf.pos - (0.0, 1.0, 3.0)) < 0.01


def test_a_marker_out_of_view_is_held_not_integrated_and_reacquired_when_it_returns():
    # issue 22: out of the tracker's view for a minute, a 0.2 m/s^2 accelerometer error
    # integrated to metres per second and the export wrote it as data. Once the filter's
    # position sigma passes lost_position_sigma_m (at the latest after coast_s) the
    # position is held, the velocity is zero and P stays bounded; the marker is picked
    # up again at its first frame back.
    ekf, gyro, accel = _at_rest_ekf()
    for k in range(100):
        _rest(ekf, gyro, accel, k / 100, (k + 1) / 100)
        ekf.update_position((k + 1) / 100 + 1e-4, (0.0, 0.0, 3.0))
    biased = accel + (0.2, 0.0, 0.0)  # what dead reckoning would turn into 90 m in 30 s
    sigma = []
    for k in range(30):
        _rest(ekf, gyro, biased, 1.0 + k, 2.0 + k)
        sigma.append(np.sqrt(np.diag(ekf.P)[:6]))
    cfg = ekf.config
    assert ekf.lost and ekf.in_dropout(ekf.t_s) and ekf.counters.lost == 1
    assert np.all(ekf.vel == 0.0)
    assert np.linalg.norm(ekf.pos - (0.0, 0.0, 3.0)) < 0.5 * 0.2 * cfg.coast_s ** 2
    assert np.allclose(sigma[-1], sigma[int(cfg.coast_s)])  # fixed once lost, not growing
    assert np.all(sigma[-1][:3] <= cfg.lost_position_sigma_m * 1.01)
    assert np.all(sigma[-1][3:] <= cfg.lost_velocity_sigma_m_s * 1.01)
    assert np.linalg.eigvalsh(ekf.P).min() > 0
    # back in view 1.5 m away: accepted at once through the widened gate, then tracked
    res = ekf.update_position(31.0 + 1e-4, (1.5, 0.0, 3.0))
    assert res.outcome == "accepted" and not ekf.lost
    for k in range(100):
        _rest(ekf, gyro, accel, 31 + k / 100, 31 + (k + 1) / 100)
        ekf.update_position(31 + (k + 1) / 100 + 1e-4, (1.5, 0.0, 3.0))
    assert np.linalg.norm(ekf.pos - (1.5, 0.0, 3.0)) < 0.05
    assert np.linalg.norm(ekf.vel) < 0.1


def test_late_frames_beyond_max_lag_are_rejected_and_counted():
    ekf, gyro, accel = _at_rest_ekf(max_lag_s=0.02)
    _rest(ekf, gyro, accel, 0.0, 1.0)
    assert ekf.update_position(ekf.t_s - 0.01, (0.0, 0.0, 3.0)).accepted
    assert ekf.update_position(ekf.t_s - 0.05, (0.0, 0.0, 3.0)).outcome == "late"
    assert ekf.counters.late == 1


def test_bad_config_and_state_are_named():
    with pytest.raises(TrackingError, match="gravity_ref_m_s2"):
        PoseEkfConfig(gravity_ref_m_s2=(0.0, 0.0, 1.0))
    with pytest.raises(TrackingError, match="position_sigma_m"):
        PoseEkfConfig(position_sigma_m=(0.01, 0.0, 0.01))
    with pytest.raises(TrackingError, match="quat_wxyz"):
        PoseEkf(0.0, (0, 0, 3), (1.0, 1.0, 0.0, 0.0))
