"""Attitude initialisation (eq 3.5-3.6): TRIAD and Wahba against scipy's Rotation."""

import numpy as np
import pytest
from airwake.tracking.attitude import (
    initial_attitude,
    quat_to_rotation_matrix,
    triad,
    wahba_davenport,
    wahba_svd,
)
from airwake.tracking.errors import TrackingError
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

seeds = st.integers(min_value=0, max_value=2**32 - 1)


def _angle_between_deg(r1: np.ndarray, r2: np.ndarray) -> float:
    return float(np.degrees(Rotation.from_matrix(r1.T @ r2).magnitude()))


def _noisy(v: np.ndarray, sigma: float, rng) -> np.ndarray:
    return v + sigma * rng.standard_normal(v.shape)


@settings(max_examples=60, deadline=None)
@given(seeds)
def test_triad_recovers_random_attitude_exactly_without_noise(seed):
    # The closed form must be exact: any error here is a frame-convention bug.
    rng = np.random.default_rng(seed)
    truth = Rotation.random(random_state=rng)
    ref = rng.standard_normal((2, 3))
    if np.degrees(np.arccos(abs(ref[0] @ ref[1]) / np.linalg.norm(ref, axis=1).prod())) < 5:
        return
    body = truth.inv().apply(ref)
    r = triad(body[0], ref[0], body[1], ref[1])
    assert _angle_between_deg(r, truth.as_matrix()) < 1e-6


@settings(max_examples=60, deadline=None)
@given(seeds, st.integers(min_value=2, max_value=12))
def test_wahba_svd_and_davenport_match_scipy_align_vectors_with_noise(seed, n):
    # Both Wahba solvers are the same least-squares optimum scipy computes.
    rng = np.random.default_rng(seed)
    truth = Rotation.random(random_state=rng)
    ref = rng.standard_normal((n, 3))
    ref /= np.linalg.norm(ref, axis=1, keepdims=True)
    body = _noisy(truth.inv().apply(ref), 0.01, rng)
    body /= np.linalg.norm(body, axis=1, keepdims=True)
    w = rng.uniform(0.2, 2.0, n)
    sep = np.degrees(np.arccos(np.clip(np.abs(ref @ ref.T), 0, 1)))
    if sep.max() < 10:
        return
    scipy_r, _ = Rotation.align_vectors(ref, body, weights=w)
    r_svd = wahba_svd(body, ref, w)
    r_dav = quat_to_rotation_matrix(wahba_davenport(body, ref, w))
    assert _angle_between_deg(r_svd, scipy_r.as_matrix()) < 1e-6
    assert _angle_between_deg(r_dav, scipy_r.as_matrix()) < 1e-6
    assert abs(np.linalg.det(r_svd) - 1) < 1e-9


@settings(max_examples=40, deadline=None)
@given(seeds)
def test_initial_attitude_from_gravity_and_line_of_sight_within_noise(seed):
    # Eq 3.5 with the marker at rest 2-5 m in front of the tracker, ~0.4 deg LoS noise and
    # accelerometer noise: the attitude error is the vectors' own error, amplified by at
    # most 1 / sin of the angle between them (the rotation about gravity comes from the
    # LoS component normal to it), so about a degree at worst.
    rng = np.random.default_rng(seed)
    truth = Rotation.random(random_state=rng)
    g_ref = np.array([0.0, 9.798, 0.0])  # tracker frame: y down
    pos = np.array([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(2, 5)])
    accel_true = truth.inv().apply(-g_ref)
    los_true = truth.inv().apply(-pos / np.linalg.norm(pos))
    accel = _noisy(accel_true, 0.02, rng)
    los = _noisy(los_true, 0.005, rng)

    def angle(a, b):
        return np.degrees(np.arccos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b),
                                            -1.0, 1.0)))

    sep = np.radians(angle(accel_true, los_true))
    bound = (angle(accel, accel_true) + angle(los, los_true)) / min(np.sin(sep), 1.0)
    assert bound < 2.0  # the set-up: a degree-level start (1.53 deg at worst in 20k draws)
    for method in ("triad", "svd"):
        r = initial_attitude(accel, los, pos, g_ref, method=method)
        assert _angle_between_deg(r, truth.as_matrix()) <= 1.05 * bound + 1e-6


def test_near_parallel_gravity_and_line_of_sight_raise_one_clear_line():
    # Marker straight below the tracker: gravity and the LoS coincide, yaw is unknown.
    g_ref = np.array([0.0, 9.798, 0.0])
    pos = np.array([0.0, 3.0, 0.01])
    with pytest.raises(TrackingError, match=r"vectors are 179\.\d+ deg apart") as err:
        initial_attitude(-g_ref, -pos, pos, g_ref)
    assert "\n" not in str(err.value)
    with pytest.raises(TrackingError, match=r"deg apart"):
        wahba_svd(np.array([[1.0, 0, 0], [1.0, 0.001, 0]]), np.array([[1.0, 0, 0], [1, 0, 0]]))
    with pytest.raises(TrackingError, match=r"0\.\d+ deg apart"):
        triad([0, 0, 1], [0, 0, 1], [0, 0.001, 1], [0, 1, 0])


def test_bad_shapes_and_weights_are_named():
    with pytest.raises(TrackingError, match="weights"):
        wahba_svd(np.eye(3), np.eye(3), weights=[1, -1, 1])
    with pytest.raises(TrackingError, match="shape"):
        wahba_svd(np.ones((3, 2)), np.ones((3, 2)))
    with pytest.raises(TrackingError, match="method"):
        initial_attitude([0, 0, -9.8], [1, 0, 0], [0, 0, 3], [0, 9.8, 0], method="euler")
