"""Quaternion integration (eq 3.9, common/quat.c) and the marker attitude against
scipy.spatial.transform.Rotation."""

import ctypes as C

import awboards as A
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

DT = 1.0 / 450.0


def to_scipy(q: A.Quat) -> Rotation:
    return Rotation.from_quat([q.x, q.y, q.z, q.w])  # scipy: scalar last


def angle_between(a: Rotation, b: Rotation) -> float:
    return float((a.inv() * b).magnitude())


rates = st.lists(
    st.tuples(*[st.floats(-30.0, 30.0)] * 3, st.integers(1, 60)), min_size=1, max_size=12
)


@settings(max_examples=100, deadline=None)
@given(rates)
def test_gyro_integration_matches_scipy_rotation(lib, segments):
    # Why: the marker's attitude is only as good as its integration of body rates.
    q = lib.quat_identity()
    ref = Rotation.identity()
    for wx, wy, wz, n in segments:
        w = A.floats([wx, wy, wz])
        for _ in range(n):
            q = lib.quat_integrate(q, w, DT)
            ref = ref * Rotation.from_rotvec(np.array([wx, wy, wz]) * DT)  # body rates
    steps = sum(s[3] for s in segments)
    # float32 rounding grows ~ sqrt(steps)
    assert angle_between(to_scipy(q), ref) < 2e-6 * steps + 1e-5
    assert abs(np.sqrt(q.w**2 + q.x**2 + q.y**2 + q.z**2) - 1.0) < 1e-5


@settings(max_examples=100, deadline=None)
@given(
    st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4).filter(
        lambda v: np.linalg.norm(v) > 0.1
    ),
    st.lists(st.floats(-10.0, 10.0), min_size=3, max_size=3),
)
def test_rotate_matches_scipy_apply(lib, qv, v):
    # Why: gravity and LoS are carried between body and reference frame with these.
    q = lib.quat_normalize(A.Quat(*qv))
    out = A.floats([0.0] * 3)
    lib.quat_rotate(q, A.floats(v), out)
    np.testing.assert_allclose(list(out), to_scipy(q).apply(v), atol=1e-5)
    lib.quat_rotate_inv(q, A.floats(v), out)
    np.testing.assert_allclose(list(out), to_scipy(q).inv().apply(v), atol=1e-5)


def test_marker_attitude_matches_scipy_after_calibration(lib):
    # Why: the marker subtracts its calibrated bias before integrating; the reported
    # quaternion must be the true body rotation since the end of calibration.
    rng = np.random.default_rng(3)
    cfg = lib.marker_default_cfg()
    st_ = A.MarkerState()
    t = 1000
    lib.marker_init(C.byref(st_), C.byref(cfg), t)
    bias = np.array([0.02, -0.01, 0.015])
    accel = A.floats([0.0, 0.0, -9.81])
    feedback = A.floats([0.5, 0.5, 0.5, 0.5])
    for i in range(int(5.2 * 450)):
        t += 2222
        lib.marker_imu_step(C.byref(st_), C.byref(cfg), t, A.floats(bias), accel)
        if i % 4 == 0:
            lib.marker_feedback(C.byref(st_), C.byref(cfg), t, feedback)
    assert st_.mode == 1
    ref = Rotation.identity()
    for _ in range(900):
        w = rng.normal(0.0, 2.0, 3)
        t += 2222
        lib.marker_imu_step(C.byref(st_), C.byref(cfg), t, A.floats(w + bias), accel)
        ref = ref * Rotation.from_rotvec(w * 2222e-6)
        if _ % 4 == 0:
            lib.marker_feedback(C.byref(st_), C.byref(cfg), t, feedback)
    out = A.MarkerOutput()
    lib.marker_output(C.byref(st_), C.byref(out))
    assert angle_between(to_scipy(out.q), ref) < np.radians(0.05)
    # gravity in the body frame = reference gravity carried by the attitude
    np.testing.assert_allclose(list(out.gravity_m_s2), ref.inv().apply([0, 0, 9.81]), atol=0.02)
