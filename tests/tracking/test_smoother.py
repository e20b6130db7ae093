"""RTS smoothing of the error-state EKF (offline): the issue's attitude and position
targets on the simulator's marker IMU and LOSA optics."""

import numpy as np
import pytest
from airwake.tracking.errors import TrackingError
from airwake.tracking.pose_ekf import PoseEkf, run_pose_ekf
from airwake.tracking.smoother import rts_smooth
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from tests.tracking.sim_data import simulate_flight, start_ekf
from tests.tracking.test_pose_ekf import _attitude_error_deg, _led_errors_m


@pytest.fixture(scope="module")
def smoothed():
    flight = simulate_flight(40.0, seed=21)
    start, i0, sel = start_ekf(flight, 21)
    ekf = PoseEkf(start.t_s, start.pos, start.quat, gyro_bias_rad_s=start.gyro_bias,
                  record_history=True)
    filtered = run_pose_ekf(ekf, flight.imu_t_s[i0:], flight.gyro_rad_s[i0:],
                            flight.accel_m_s2[i0:], flight.losa_t_s[sel],
                            flight.losa_pos_t_m[sel], flight.losa_ok[sel],
                            flight.lever_arm_body_m[sel])
    return flight, sel, filtered, rts_smooth(ekf)


def test_smoothed_attitude_within_1deg_through_90deg_rotations_from_the_start(smoothed):
    # Future data resolve the initial accelerometer-bias/tilt ambiguity backwards.
    flight, _, filtered, track = smoothed
    # every IMU sample that moved the filter (the first only sets the held sample)
    np.testing.assert_allclose(track.t_s, filtered.t_s[-track.t_s.size:], rtol=0, atol=1e-9)
    assert track.t_s.size >= filtered.t_s.size - 1
    err = _attitude_error_deg(flight, track)
    assert err.max() < 1.0, err.max()


def test_smoothed_position_error_at_least_30_percent_lower_than_triangulation(smoothed):
    # Smoothing averages the time-correlated triangulation error from both sides.
    flight, sel, _, track = smoothed
    ekf_err, tri_err = _led_errors_m(flight, track, sel)
    assert ekf_err.mean() < 0.70 * tri_err.mean(), (ekf_err.mean(), tri_err.mean())


def test_smoothing_needs_the_recorded_history():
    ekf = PoseEkf(0.0, (0.0, 0.0, 3.0), (1.0, 0.0, 0.0, 0.0))
    with pytest.raises(TrackingError, match="record_history=True"):
        rts_smooth(ekf)


@settings(max_examples=300)
@given(st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4),
       st.floats(-14.0, 0.0))
def test_quaternion_log_is_the_rotation_vector(v, log_scale):
    # the smoother's attitude difference: scipy's rotation vector (angle in [0, pi]), for
    # large rotations, tiny ones (the series branch) and either sign of q
    from airwake.tracking.pose_ekf import quat_exp
    from airwake.tracking.smoother import _quat_log
    from scipy.spatial.transform import Rotation

    q = np.array(v, dtype=float)
    q[1:] *= 10.0 ** log_scale
    assume(np.linalg.norm(q) > 1e-3 and abs(q[0]) > 1e-3)
    q /= np.linalg.norm(q)
    got = _quat_log(q)
    ref = Rotation.from_quat([q[1], q[2], q[3], q[0]]).as_rotvec()
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-15)
    assert np.linalg.norm(got) <= np.pi + 1e-12
    back = quat_exp(got)
    np.testing.assert_allclose(back * np.sign(back[0] * q[0]), q, atol=1e-12)
