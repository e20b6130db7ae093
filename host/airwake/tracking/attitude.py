"""Attitude initialisation from vector pairs (reference §3.3.2.1, eq 3.5-3.6).

The marker at rest knows two vectors in its own frame (body, b): gravity from the
accelerometer and the line of sight to the tracker (from the LED-intensity scan of
its calibration mode); the tracker knows the same two in its frame (reference, r):
gravity and the direction to the marker from triangulation. Eq 3.5:

    g_m = R_s^m g_s,        r_hat_sm = -R_s^m r_hat_ms

i.e. with R = R_r^b^T = R_s^m^T (body -> reference, the convention of every function
here, `v_ref = R @ v_body`):

    g_ref = R g_body,       -r_hat_ms = R los_body

Two solvers of the same problem:
- `triad`: exact on the primary pair, the secondary only fixes the rotation about it;
- `wahba_svd` / `wahba_davenport`: the least-squares rotation for any number of
  weighted pairs (Wahba's problem, min sum w_i |r_i - R b_i|^2), by Markley's SVD and by
  Davenport's q-method (eigenvector of the 4x4 K matrix); both give the same optimum.
Two non-parallel directions are needed: near-parallel pairs raise `TrackingError`
naming the angle between them.
"""

from __future__ import annotations

import numpy as np

from airwake.tracking.errors import TrackingError

MIN_PAIR_ANGLE_DEG = 2.0  # below this the rotation about the vectors is noise


def _unit(v: np.ndarray, name: str) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    if v.shape[-1] != 3:
        raise TrackingError(f"{name}: shape {v.shape}, expected (..., 3)")
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    if not np.all(np.isfinite(v)) or np.any(n < 1e-12):
        raise TrackingError(f"{name}: zero-length or non-finite vector")
    return v / n


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between two unit vectors (0..180 deg), robust near 0 and 180."""
    return float(np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b)), np.dot(a, b))))


def _check_not_parallel(a: np.ndarray, b: np.ndarray, which: str, min_angle_deg: float) -> None:
    angle = _angle_deg(a, b)
    sep = min(angle, 180.0 - angle)
    if sep < min_angle_deg:
        raise TrackingError(
            f"attitude undetermined: the two {which} vectors are {angle:.2f} deg apart "
            f"(within {min_angle_deg:g} deg of parallel); the rotation about them is unknown")


def triad(body_primary, ref_primary, body_secondary, ref_secondary,
          min_angle_deg: float = MIN_PAIR_ANGLE_DEG) -> np.ndarray:
    """TRIAD rotation body -> reference (3, 3), `v_ref = R @ v_body`.

    The primary pair (gravity, the better-known vector) is matched exactly; the
    secondary (line of sight) only fixes the rotation about it. With t1 = p,
    t2 = (p x s)/|p x s|, t3 = t1 x t2 in each frame: R = [t1 t2 t3]_ref [t1 t2 t3]_body^T.
    """
    bp, rp = _unit(body_primary, "body_primary"), _unit(ref_primary, "ref_primary")
    bs, rs = _unit(body_secondary, "body_secondary"), _unit(ref_secondary, "ref_secondary")
    _check_not_parallel(bp, bs, "body", min_angle_deg)
    _check_not_parallel(rp, rs, "reference", min_angle_deg)

    def frame(p: np.ndarray, s: np.ndarray) -> np.ndarray:
        t2 = np.cross(p, s)
        t2 /= np.linalg.norm(t2)
        return np.column_stack([p, t2, np.cross(p, t2)])

    return frame(rp, rs) @ frame(bp, bs).T


def _pairs(body, ref, weights, min_angle_deg: float):
    b = _unit(np.atleast_2d(body), "body")
    r = _unit(np.atleast_2d(ref), "ref")
    if b.shape != r.shape or b.ndim != 2:
        raise TrackingError(f"body {b.shape} and ref {r.shape}: expected two (N, 3) arrays")
    w = np.ones(len(b)) if weights is None else np.asarray(weights, dtype=float).reshape(-1)
    if w.shape != (len(b),) or np.any(w < 0) or not np.all(np.isfinite(w)) or w.sum() <= 0:
        raise TrackingError(f"weights: expected {len(b)} finite non-negative values, not all 0")
    # The widest-spread pair of body directions decides observability.
    used = w > 0
    bu = b[used]
    cross = np.linalg.norm(np.cross(bu[:, None, :], bu[None, :, :]), axis=-1)
    dots = np.einsum("ik,jk->ij", bu, bu)
    sep = np.degrees(np.arctan2(cross, np.abs(dots)))
    if sep.max() < min_angle_deg:
        i, j = np.unravel_index(np.argmax(sep), sep.shape)
        _check_not_parallel(bu[i], bu[j], "body", min_angle_deg)
        raise TrackingError("attitude undetermined: one vector pair only; at least two "
                            "non-parallel directions are needed")
    return b, r, w


def attitude_profile(body, ref, weights=None) -> np.ndarray:
    """B = sum_i w_i r_i b_i^T (3, 3): the attitude profile matrix of Wahba's problem."""
    return np.einsum("i,ij,ik->jk", weights, ref, body)


def wahba_svd(body, ref, weights=None, min_angle_deg: float = MIN_PAIR_ANGLE_DEG) -> np.ndarray:
    """Least-squares rotation body -> reference (3, 3) for N weighted pairs.

    `body`, `ref` (N, 3) (normalised here), `weights` (N,). Markley's SVD solution:
    B = U S V^T, R = U diag(1, 1, det U det V) V^T.
    """
    b, r, w = _pairs(body, ref, weights, min_angle_deg)
    u, _, vt = np.linalg.svd(attitude_profile(b, r, w))
    d = np.linalg.det(u) * np.linalg.det(vt)
    return u @ np.diag([1.0, 1.0, d]) @ vt


def wahba_davenport(body, ref, weights=None,
                    min_angle_deg: float = MIN_PAIR_ANGLE_DEG) -> np.ndarray:
    """Davenport's q-method: the unit quaternion [w, x, y, z] (body -> reference) that
    maximises q^T K q, K = [[tr B, z^T], [z, B + B^T - tr(B) I]] with here
    B = sum w_i b_i r_i^T (the transpose of `attitude_profile`) and z = sum w_i b_i x r_i."""
    b, r, w = _pairs(body, ref, weights, min_angle_deg)
    bt = attitude_profile(b, r, w).T  # Davenport's B = sum w b r^T
    z = np.einsum("i,ij->j", w, np.cross(b, r))
    tr = np.trace(bt)
    k = np.empty((4, 4))
    k[0, 0] = tr
    k[0, 1:] = z
    k[1:, 0] = z
    k[1:, 1:] = bt + bt.T - tr * np.eye(3)
    vals, vecs = np.linalg.eigh(k)
    # The eigenvector of the largest eigenvalue, scalar first, is the body -> reference
    # quaternion with this sign of z (z = sum w b x r).
    q = vecs[:, np.argmax(vals)]
    return q / np.linalg.norm(q) * (1.0 if q[0] >= 0 else -1.0)


def quat_to_rotation_matrix(q_wxyz) -> np.ndarray:
    """(..., 4) unit quaternions [w, x, y, z] -> (..., 3, 3), `v_ref = R @ v_body`
    (eq 3.6 is the transpose of this: R_s^m rotates reference into marker)."""
    q = np.asarray(q_wxyz, dtype=float)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


def rotation_to_quat_wxyz(r: np.ndarray) -> np.ndarray:
    """Unit [w, x, y, z] of a rotation matrix (3, 3) (scipy's, reordered)."""
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_matrix(r).as_quat()
    return np.array([w, x, y, z])


def initial_attitude(accel_body_m_s2, los_body, marker_pos_ref_m, gravity_ref_m_s2,
                     method: str = "triad",
                     min_angle_deg: float = MIN_PAIR_ANGLE_DEG) -> np.ndarray:
    """Eq 3.5: the marker's attitude (3, 3) body -> reference from the accelerometer at
    rest (it reads the reaction to gravity, -g, in body axes), the line of sight toward
    the tracker in body axes, the triangulated marker position and gravity in the
    reference frame. `method` "triad" (gravity matched exactly) or "svd"."""
    g_body = -np.asarray(accel_body_m_s2, dtype=float)
    los_ref = -np.asarray(marker_pos_ref_m, dtype=float)  # marker -> tracker
    if method == "triad":
        return triad(g_body, gravity_ref_m_s2, los_body, los_ref, min_angle_deg)
    if method == "svd":
        return wahba_svd(np.stack([g_body, np.asarray(los_body, float)]),
                         np.stack([np.asarray(gravity_ref_m_s2, float), los_ref]),
                         None, min_angle_deg)
    raise TrackingError(f"initial_attitude: method {method!r}; expected 'triad' or 'svd'")
