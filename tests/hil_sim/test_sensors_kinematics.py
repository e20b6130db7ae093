"""Truth-trajectory container and rotation helpers (hil_sim.world.kinematics)."""

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hil_sim.world import kinematics as k

G = k.GRAVITY_M_S2
angles = st.tuples(
    st.floats(-3.0, 3.0), st.floats(-1.5, 1.5), st.floats(-3.0, 3.0)
).map(np.array)


@given(angles)
def test_euler_quat_round_trip_is_exact(euler):
    # Every sensor reports attitude through these conversions.
    back = k.quat_to_euler(k.euler_to_quat(euler))
    assert np.allclose(back, euler, atol=1e-9)


@given(angles, angles)
def test_quaternion_product_matches_matrix_product(e1, e2):
    q1, q2 = k.euler_to_quat(e1), k.euler_to_quat(e2)
    lhs = k.quat_to_dcm(k.quat_multiply(q1, q2))
    assert np.allclose(lhs, k.quat_to_dcm(q1) @ k.quat_to_dcm(q2), atol=1e-12)
    assert np.allclose(k.euler_to_dcm(e1), k.quat_to_dcm(q1), atol=1e-12)


@given(angles)
def test_dcm_to_quat_inverts_quat_to_dcm(euler):
    q = k.euler_to_quat(euler)
    assert np.allclose(k.dcm_to_quat(k.quat_to_dcm(q)), q, atol=1e-9)


def test_hover_reads_minus_g_on_body_z():
    # A level hovering IMU reads the reaction to gravity: z = -g (FRD).
    tr = k.hover(1.0, 500.0)
    assert np.allclose(tr.specific_force_body_m_s2, [0, 0, -G])
    assert np.allclose(np.diff(tr.rotor_azimuth_rad), 163.3 / 500.0)
    assert tr.height_agl_m[0] == pytest.approx(2.5)


def test_constant_rotation_quaternion_rate_matches_body_rates():
    # q_dot = 1/2 q ⊗ [0, w]: the attitude and the rates must describe the same motion.
    w = np.array([0.4, -0.7, 1.1])
    tr = k.constant_rotation(2.0, w, 1000.0)
    qdot = np.gradient(tr.quat_wxyz, tr.t_s, axis=0)
    expected = 0.5 * k.quat_multiply(tr.quat_wxyz, np.concatenate([[0.0], w]))
    assert np.allclose(qdot[5:-5], expected[5:-5], atol=1e-5)
    # Gravity's reaction has magnitude g in any attitude.
    assert np.allclose(np.linalg.norm(tr.specific_force_body_m_s2, axis=1), G)


def test_circle_specific_force_carries_centripetal_acceleration():
    tr = k.circle(5.0, radius_m=4.0, speed_m_s=2.0, rate_hz=200.0)
    # Level, nose along track, right turn: centripetal V^2/R points to the right (+y body).
    assert np.allclose(tr.specific_force_body_m_s2[:, 1], 2.0**2 / 4.0, atol=1e-9)
    assert np.allclose(tr.specific_force_body_m_s2[:, 2], -G)
    assert np.allclose(tr.vel_body_m_s, [2.0, 0.0, 0.0], atol=1e-9)
    # from_states' finite-difference derivation agrees with the analytic one.
    derived = k.Trajectory.from_states(tr.t_s, tr.pos_ned_m, tr.vel_ned_m_s, tr.quat_wxyz,
                                       tr.rates_body_rad_s)
    assert np.allclose(derived.specific_force_body_m_s2[2:-2], tr.specific_force_body_m_s2[2:-2],
                       atol=1e-3)


def test_at_interpolates_between_samples_and_keeps_unit_quaternions():
    tr = k.constant_rotation(1.0, [0.0, 0.0, 2.0], 100.0, rotor_speed_rad_s=150.0)
    tq = np.array([0.0051, 0.5037, 0.9])
    s = tr.at(tq)
    assert np.allclose(np.linalg.norm(s.quat_wxyz, axis=1), 1.0)
    assert np.allclose(s.euler_rad[:, 2], 2.0 * tq, atol=1e-4)
    assert np.allclose(s.rotor_azimuth_rad, 150.0 * tq)


def test_at_point_adds_lever_arm_accelerations():
    # a = a_cg + w_dot x r + w x (w x r): spinning about z at w, a point r ahead feels
    # -w^2 r (centripetal) along x.
    w = 3.0
    tr = k.constant_rotation(1.0, [0.0, 0.0, w], 200.0)
    p = tr.at_point([0.5, 0.0, 0.0])
    assert np.allclose(p.specific_force_body_m_s2[:, 0], -w * w * 0.5)
    assert np.allclose(np.linalg.norm(p.vel_ned_m_s, axis=1), w * 0.5)
    assert np.allclose(np.linalg.norm(p.pos_ned_m - tr.pos_ned_m, axis=1), 0.5)


def test_at_point_mount_rotation_expresses_rates_in_sensor_axes():
    tr = k.constant_rotation(0.5, [0.1, 0.2, 0.3], 100.0)
    yaw90 = k.euler_to_quat(np.array([0.0, 0.0, np.pi / 2]))  # sensor x = body y
    p = tr.at_point([0.0, 0.0, 0.0], yaw90)
    assert np.allclose(p.rates_body_rad_s[0], [0.2, -0.1, 0.3])


def test_trajectory_rejects_non_increasing_times_and_bad_shapes():
    tr = k.hover(0.002, 1000.0)  # 3 samples
    with pytest.raises(ValueError, match="strictly increasing"):
        dataclasses.replace(tr, t_s=np.array([0.0, 0.0, 0.001]))
    with pytest.raises(ValueError, match="pos_ned_m"):
        k.Trajectory.from_states([0.0, 1.0], np.zeros((3, 3)), np.zeros((2, 3)),
                                 [1, 0, 0, 0], np.zeros(3))
    with pytest.raises(ValueError, match="non-finite"):
        dataclasses.replace(tr, height_agl_m=np.array([1.0, np.nan, 1.0]))


@settings(max_examples=25)
@given(st.floats(0.05, 0.95))
def test_window_and_at_agree_on_sample_times(frac):
    tr = k.circle(2.0, 3.0, 1.5, 100.0)
    t_mid = tr.t_s[int(frac * (len(tr) - 1))]
    w = tr.window(t_mid, t_mid)
    assert np.allclose(w.pos_ned_m, tr.at([t_mid]).pos_ned_m)
