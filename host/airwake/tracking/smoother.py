"""Rauch-Tung-Striebel smoothing of the error-state pose EKF (offline only).

The forward filter (`PoseEkf(..., record_history=True)`) keeps, for every propagation
step k -> k+1, the posterior x_k|k and P_k|k before it, the transition F_k+1 and the
prior x_k+1|k, P_k+1|k after it. Backwards from the last posterior (x^s_N = x_N|N):

    C_k   = P_k|k F_k+1^T P_k+1|k^-1
    x^s_k = x_k|k (+) C_k (x^s_k+1 (-) x_k+1|k)

where (-) is the error-state difference [dp, dv, log(q_a^-1 (x) q_b), db_g, db_a] and
(+) its injection (q (x) exp(dtheta)), so the smoother works on the same three-dof
attitude error as the filter. The gain is the RTS gain of filterpy's
`KalmanFilter.rts_smoother`, written for the nominal/error split.
Memory: two 15 x 15 matrices per IMU sample (~4 kB), so minutes, not hours, per call.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from airwake.tracking.errors import TrackingError
from airwake.tracking.pose_ekf import N_ERR, PoseEkf, PoseTrack, quat_exp, quat_multiply


def _quat_log(q: np.ndarray) -> np.ndarray:
    """Rotation vector of a unit [w, x, y, z] quaternion, angle in [0, pi] (q and -q are
    one rotation): 2 atan2(|v|, w) v / |v|, and its series 2 v / w (1 - |v|^2 / 3 w^2)
    where |v| is below 1e-8 (equal to scipy's `Rotation.as_rotvec` to 1e-15, at a
    hundredth of its cost per call: the smoother takes one per IMU sample)."""
    w, x, y, z = float(q[0]), float(q[1]), float(q[2]), float(q[3])
    if w < 0.0:
        w, x, y, z = -w, -x, -y, -z
    s = math.sqrt(x * x + y * y + z * z)
    k = 2.0 / w * (1.0 - s * s / (3.0 * w * w)) if s < 1e-8 else 2.0 * math.atan2(s, w) / s
    return np.array([k * x, k * y, k * z])


def _difference(a: tuple, b: tuple) -> np.ndarray:
    """a (-) b as a 15-vector (a = b (+) d)."""
    qb_inv = np.array([b[2][0], -b[2][1], -b[2][2], -b[2][3]])
    return np.concatenate([a[0] - b[0], a[1] - b[1], _quat_log(quat_multiply(qb_inv, a[2])),
                           a[3] - b[3], a[4] - b[4]])


def _inject(x: tuple, d: np.ndarray) -> tuple:
    q = quat_multiply(x[2], quat_exp(d[6:9]))
    return (x[0] + d[0:3], x[1] + d[3:6], q / np.linalg.norm(q), x[3] + d[9:12],
            x[4] + d[12:15])


def rts_smooth(ekf: PoseEkf) -> PoseTrack:
    """The smoothed states at the IMU samples that propagated the filter (all but a
    first one at the start time; `losa_*` fields empty). `ekf` must have been built
    with `record_history=True` and run."""
    hist = ekf.history
    if not hist:
        raise TrackingError("rts_smooth: the filter has no history; build it with "
                            "PoseEkf(..., record_history=True) and run it first")
    n = len(hist)
    # posterior after step k = the "post" stored at step k+1; after the last: now.
    posts = [h[0] for h in hist[1:]] + [ekf.nominal()]
    p_posts = [h[1] for h in hist[1:]] + [ekf.P.copy()]
    xs = [None] * n
    xs[-1] = posts[-1]
    for k in range(n - 2, -1, -1):
        F_next, prior_next, p_prior_next = hist[k + 1][2], hist[k + 1][3], hist[k + 1][4]
        # C = P_post F^T P_prior^-1, through a Cholesky solve of P_prior C^T = F P_post
        c_t = cho_solve(cho_factor(p_prior_next[:N_ERR, :N_ERR], check_finite=False),
                        F_next[:N_ERR, :N_ERR] @ p_posts[k][:N_ERR, :N_ERR],
                        check_finite=False)
        xs[k] = _inject(posts[k], c_t.T @ _difference(xs[k + 1], prior_next))
    imu = [k for k in range(n) if hist[k][6]]
    t = np.array([hist[k][5] for k in imu])
    empty = np.empty(0)
    return PoseTrack(
        t_s=t,
        pos_ref_m=np.array([xs[k][0] for k in imu]),
        vel_ref_m_s=np.array([xs[k][1] for k in imu]),
        quat_wxyz=np.array([xs[k][2] for k in imu]),
        pos_sigma_m=np.full((len(imu), 3), np.nan),
        losa_t_s=empty, losa_outcome=empty.astype(str), losa_nis=empty,
    )
