"""Pose EKF of the active marker: IMU prediction, LOSA position updates (reference
§3.3.2.2-3.3.2.3, eq 3.7-3.14, improved as an error-state filter).

Frames: the reference frame r is the tracker's (x right, y down, z forward) or any
inertial frame in which gravity `gravity_ref_m_s2` is known; the body frame b is the
marker's IMU axes. `quat_wxyz` rotates body vectors into the reference frame,
`v_ref = R(q) v_body`.

Nominal state (not in the filter): position p, velocity v (reference frame), attitude
q (unit quaternion), gyro bias b_g, accelerometer bias b_a (body).
Error state, the filter's x (15,), zero between steps:

    dx = [dp (3), dv (3), dtheta (3), db_g (3), db_a (3)],  q_true = q (x) exp(dtheta)

so attitude has three degrees of freedom in the filter (no additive 4-quaternion
renormalised afterwards). Eq 3.7-3.8 write the velocity in the marker frame and need the
omega x v transport term; in the (inertial) reference frame it drops out:

    a   = R(q) (f_m - b_a) + g                                  (eq 3.7, inertial form)
    p  <- p + v dt + a dt^2 / 2,   v <- v + a dt                (eq 3.8)
    q  <- q (x) exp((w_m - b_g) dt)                             (eq 3.9, exact for a
                                                                 constant rate)

The error state's transition (eq 3.12), first order in dt, with [.]x the skew matrix:

    F = I + [[0, I dt, 0,            0,     0     ],
             [0, 0,   -R [f]x dt,    0,    -R dt  ],
             [0, 0,    exp(-[w]x dt) - I, -I dt, 0],
             [0, 0,    0,            0,     0     ],
             [0, 0,    0,            0,     0     ]]
    Q = diag(0, s_a^2 dt, s_g^2 dt, s_bg^2 dt, s_ba^2 dt)       (noise densities)

Measurement (eq 3.10, improved): LOSA triangulates the lit LED, `lever_arm_body_m` from
the marker centre, so z = p + R l (+ noise) and

    H = [I, 0, -R [l]x, 0, 0]

(with l = 0 this is eq 3.10's position row; the lever arm makes attitude directly
observable as well). Eq 3.13-3.14 are filterpy's `KalmanFilter.predict` and `update`
(Joseph form P = (I-KH) P (I-KH)^T + K R K^T); afterwards the error is injected into the
nominal state and reset to zero, P <- G P G^T with G = blockdiag(I, I, I - [dtheta/2]x,
I, I), and P is symmetrised.

Gating: the normalised innovation squared NIS = y^T S^-1 y is chi-square with 3 dof;
an update with NIS above `chi2.ppf(gate_probability, 3)` is rejected. When no update
has been accepted for `dropout_s` (LOSA dropout), the gate widens by
`reacquire_gate_scale`; after `max_rejections` consecutive rejections in a dropout the
position is re-acquired from the measurement (velocity and position covariance reset).

Lost: dead reckoning on the IMU alone drifts metres within seconds and, with an attitude
or accelerometer-bias error, without bound (a SIL hall flight integrated 100 m/s). Once
in a dropout the filter's own position sigma exceeds `lost_position_sigma_m` (its
prediction can no longer tell the LOSA slots apart, `losa.SlotResolver`), or after
`coast_s` without an accepted update whatever P says, the filter is lost until the next
accepted update: it stops integrating eq 3.8 — the position is held where the coasting
left it, the velocity is zero — and their errors are re-drawn each step as independent
N(0, `lost_position_sigma_m`^2), N(0, `lost_velocity_sigma_m_s`^2) (F's position and
velocity rows zero, Q's position and velocity entries those variances), so P stays
bounded and the RTS smoother carries nothing across the rest of the gap. Attitude and
biases keep propagating (the gyro keeps the attitude). The next LOSA frame re-acquires
through the widened gate.
Time: every call carries a host-timeline time; LOSA frames later than the last IMU
sample are predicted to (prediction only), frames up to `max_lag_s` older are applied
with the velocity-corrected model h = p - v lag + R l, older ones are rejected.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from filterpy.kalman import KalmanFilter
from scipy.stats import chi2

from airwake.tracking.errors import TrackingError

GRAVITY_M_S2 = 9.798  # Table 5.1 of the reference, as hil_sim.world.kinematics
N_ERR = 15
P_, V_, TH, BG, BA = slice(0, 3), slice(3, 6), slice(6, 9), slice(9, 12), slice(12, 15)
_I3 = np.eye(3)


def skew(v) -> np.ndarray:
    """[v]x (3, 3): skew(a) @ b == cross(a, b)."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def quat_multiply(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product p (x) q of two [w, x, y, z] quaternions."""
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return np.array([pw * qw - px * qx - py * qy - pz * qz,
                     pw * qx + px * qw + py * qz - pz * qy,
                     pw * qy - px * qz + py * qw + pz * qx,
                     pw * qz + px * qy - py * qx + pz * qw])


def quat_exp(rotvec: np.ndarray) -> np.ndarray:
    """exp(rotvec / 2) as a [w, x, y, z] unit quaternion."""
    angle = float(np.sqrt(rotvec @ rotvec))
    if angle < 1e-12:
        return np.array([1.0, 0.5 * rotvec[0], 0.5 * rotvec[1], 0.5 * rotvec[2]])
    s = np.sin(0.5 * angle) / angle
    return np.array([np.cos(0.5 * angle), s * rotvec[0], s * rotvec[1], s * rotvec[2]])


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """(3, 3) body -> reference rotation of a unit [w, x, y, z] quaternion (the
    transpose of eq 3.6's R_s^m)."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


@dataclass(frozen=True)
class PoseEkfConfig:
    """Noise model (MPU-9250 datasheet densities, as the marker carries), LOSA noise,
    initial uncertainty, gating and timing."""

    gravity_ref_m_s2: tuple[float, float, float] = (0.0, GRAVITY_M_S2, 0.0)  # tracker: y down
    gyro_noise_rad_s_rthz: float = 1.75e-4
    accel_noise_m_s2_rthz: float = 2.94e-3
    gyro_bias_walk_rad_s2_rthz: float = 2.0e-5
    accel_bias_walk_m_s3_rthz: float = 1.0e-4
    # LOSA triangulation, 1 sigma per tracker axis (x, y lateral, z depth), the default
    # R: depth is ~8x worse than lateral (eq 3.4, Z ~ 1/disparity), and both are inflated
    # ~4x over the frame-to-frame noise because most of the error is correlated over
    # tens of frames (fixed-pattern noise, pixel locking) and must not be trusted as white.
    position_sigma_m: tuple[float, float, float] = (0.005, 0.005, 0.03)
    initial_position_sigma_m: float = 0.02
    initial_velocity_sigma_m_s: float = 0.05
    initial_attitude_sigma_rad: float = 0.03
    initial_gyro_bias_sigma_rad_s: float = 0.002
    initial_accel_bias_sigma_m_s2: float = 0.2
    gate_probability: float = 0.9999
    dropout_s: float = 0.25
    reacquire_gate_scale: float = 25.0
    max_rejections: int = 20
    max_lag_s: float = 0.05
    # lost once the position sigma passes lost_position_sigma_m in a dropout, or after
    # coast_s without an accepted update: position held, velocity zero, their
    # covariance fixed at these sigmas (module doc)
    coast_s: float = 10.0
    lost_position_sigma_m: float = 1.0
    lost_velocity_sigma_m_s: float = 1.0
    # an ambiguous LOSA slot choice is confirmed only by motion the filter explains with
    # its position sigma below this (`settled()`): right after a re-acquisition its wide
    # covariance would take a wrong choice's motion as well
    settled_position_sigma_m: float = 0.05

    def __post_init__(self) -> None:
        g = np.asarray(self.gravity_ref_m_s2, dtype=float)
        if g.shape != (3,) or not np.all(np.isfinite(g)) or not 9.0 < np.linalg.norm(g) < 10.5:
            raise TrackingError(f"PoseEkfConfig.gravity_ref_m_s2 = {self.gravity_ref_m_s2!r}: "
                                "expected a finite 3-vector of length ~9.8 m/s^2")
        sigma = np.asarray(self.position_sigma_m, dtype=float)
        if sigma.shape != (3,) or not np.all(np.isfinite(sigma) & (sigma > 0)):
            raise TrackingError(f"PoseEkfConfig.position_sigma_m = {self.position_sigma_m!r}: "
                                "expected three values > 0 (m)")
        for name in ("gyro_noise_rad_s_rthz", "accel_noise_m_s2_rthz",
                     "initial_position_sigma_m", "initial_velocity_sigma_m_s",
                     "initial_attitude_sigma_rad", "initial_gyro_bias_sigma_rad_s",
                     "initial_accel_bias_sigma_m_s2", "dropout_s", "reacquire_gate_scale",
                     "coast_s", "lost_position_sigma_m", "lost_velocity_sigma_m_s",
                     "settled_position_sigma_m"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise TrackingError(f"PoseEkfConfig.{name} = {value!r}: must be > 0")
        for name in ("gyro_bias_walk_rad_s2_rthz", "accel_bias_walk_m_s3_rthz", "max_lag_s"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value >= 0):
                raise TrackingError(f"PoseEkfConfig.{name} = {value!r}: must be >= 0")
        if not 0.5 < self.gate_probability < 1.0:
            raise TrackingError(f"PoseEkfConfig.gate_probability = {self.gate_probability!r}: "
                                "expected in (0.5, 1)")
        if not (isinstance(self.max_rejections, int) and self.max_rejections >= 1):
            raise TrackingError(f"PoseEkfConfig.max_rejections = {self.max_rejections!r}: "
                                "must be an integer >= 1")


@dataclass(frozen=True)
class UpdateResult:
    """One LOSA update: `accepted`, the NIS and the gate it was compared with, and
    `outcome` one of "accepted", "gated", "reacquired", "late"."""

    accepted: bool
    nis: float
    gate: float
    outcome: str


@dataclass(frozen=True, eq=False)
class PoseTrack:
    """The filter over a stream, at each IMU sample (N): `t_s` (N,), `pos_ref_m`,
    `vel_ref_m_s` (N, 3), `quat_wxyz` (N, 4), `pos_sigma_m` (N, 3); and per LOSA frame
    (M): `losa_t_s` (M,), `losa_outcome` (M,) str, `losa_nis` (M,); `unresolved_t_s`:
    times of the LOSA frames fused while the slot re-acquisition was ambiguous
    (`losa.SlotResolver`)."""

    t_s: np.ndarray
    pos_ref_m: np.ndarray
    vel_ref_m_s: np.ndarray
    quat_wxyz: np.ndarray
    pos_sigma_m: np.ndarray
    losa_t_s: np.ndarray
    losa_outcome: np.ndarray
    losa_nis: np.ndarray
    unresolved_t_s: np.ndarray = field(default_factory=lambda: np.empty(0))


@dataclass
class _Counters:
    predictions: int = 0
    accepted: int = 0
    gated: int = 0
    reacquired: int = 0
    late: int = 0
    lost: int = 0  # times the filter gave up coasting (module doc)


class PoseEkf:
    """Error-state pose EKF (see the module docstring for the equations).

    `t_s` the host time of the initial state; `pos_ref_m` (3,), `quat_wxyz` (4,) (e.g.
    from `attitude.initial_attitude`); optional velocity and bias estimates (e.g. the
    gyro mean at rest, as the marker's calibration mode measures it).
    """

    def __init__(self, t_s: float, pos_ref_m, quat_wxyz, *, vel_ref_m_s=(0.0, 0.0, 0.0),
                 gyro_bias_rad_s=(0.0, 0.0, 0.0), accel_bias_m_s2=(0.0, 0.0, 0.0),
                 config: PoseEkfConfig | None = None, record_history: bool = False) -> None:
        self.config = c = config or PoseEkfConfig()
        vectors = {"pos_ref_m": pos_ref_m, "vel_ref_m_s": vel_ref_m_s,
                   "gyro_bias_rad_s": gyro_bias_rad_s, "accel_bias_m_s2": accel_bias_m_s2}
        for name, v in vectors.items():
            arr = np.asarray(v, dtype=float)
            if arr.shape != (3,) or not np.all(np.isfinite(arr)):
                raise TrackingError(f"PoseEkf: {name} = {v!r}: expected a finite 3-vector")
        q = np.asarray(quat_wxyz, dtype=float)
        if q.shape != (4,) or not np.all(np.isfinite(q)) or abs(np.linalg.norm(q) - 1) > 1e-3:
            raise TrackingError(f"PoseEkf: quat_wxyz = {quat_wxyz!r}: expected a unit [w,x,y,z]")
        self.t_s = float(t_s)
        self.pos = np.array(pos_ref_m, dtype=float)
        self.vel = np.array(vel_ref_m_s, dtype=float)
        self.quat = q / np.linalg.norm(q)
        self.gyro_bias = np.array(gyro_bias_rad_s, dtype=float)
        self.accel_bias = np.array(accel_bias_m_s2, dtype=float)
        self.gravity = np.asarray(c.gravity_ref_m_s2, dtype=float)
        self.kf = KalmanFilter(dim_x=N_ERR, dim_z=3)
        self.kf.P = np.diag(np.repeat([c.initial_position_sigma_m, c.initial_velocity_sigma_m_s,
                                       c.initial_attitude_sigma_rad,
                                       c.initial_gyro_bias_sigma_rad_s,
                                       c.initial_accel_bias_sigma_m_s2], 3) ** 2)
        self._q_density = np.repeat([0.0, c.accel_noise_m_s2_rthz, c.gyro_noise_rad_s_rthz,
                                     c.gyro_bias_walk_rad_s2_rthz,
                                     c.accel_bias_walk_m_s3_rthz], 3) ** 2
        self._r_default = np.diag(np.asarray(c.position_sigma_m, dtype=float) ** 2)
        self._gate = float(chi2.ppf(c.gate_probability, 3))
        self._F = np.eye(N_ERR)
        self._H = np.zeros((3, N_ERR))
        self._H[:, P_] = _I3
        self._last_imu: tuple[np.ndarray, np.ndarray] | None = None
        self._last_accept_s = self.t_s
        self._rejections = 0
        self._lost = False
        self.counters = _Counters()
        # For the RTS smoother (airwake.tracking.smoother): per propagation step the
        # posterior before it, F, the prior after it, P of both, its time and whether an
        # IMU sample (not a LOSA frame) ended it.
        self.history: list[tuple] | None = [] if record_history else None

    # -- state -------------------------------------------------------------

    @property
    def P(self) -> np.ndarray:
        """(15, 15) error-state covariance [dp, dv, dtheta, db_g, db_a]."""
        return self.kf.P

    @property
    def last_accept_s(self) -> float:
        """Time of the last accepted (or re-acquiring) LOSA update."""
        return self._last_accept_s

    @property
    def rotation(self) -> np.ndarray:
        """(3, 3) body -> reference."""
        return quat_to_matrix(self.quat)

    # -- prediction (eq 3.7-3.9, 3.13) --------------------------------------

    def predict(self, t_s: float, gyro_rad_s, accel_m_s2) -> None:
        """Propagate to the IMU sample at host time `t_s` (body-frame gyro (3,) and
        specific force (3,)), with the mean of this and the previous sample over the
        interval (trapezoid on the rates). A sample not after the current time only
        replaces the held sample."""
        gyro = np.asarray(gyro_rad_s, dtype=float)
        accel = np.asarray(accel_m_s2, dtype=float)
        dt = t_s - self.t_s
        if self._last_imu is not None and dt > 0:
            g0, a0 = self._last_imu
            self._propagate(dt, 0.5 * (g0 + gyro), 0.5 * (a0 + accel), imu=True)
        elif dt > 0:
            self._propagate(dt, gyro, accel, imu=True)
        self._last_imu = (gyro, accel)

    def nominal(self) -> tuple[np.ndarray, ...]:
        """Copies of (p, v, q, b_g, b_a)."""
        return (self.pos.copy(), self.vel.copy(), self.quat.copy(), self.gyro_bias.copy(),
                self.accel_bias.copy())

    @property
    def lost(self) -> bool:
        """Coasting gave up (module doc): position held, velocity zero, until the next
        accepted update."""
        return self._lost

    def settled(self) -> bool:
        """The position sigma is below `settled_position_sigma_m` on every axis: an
        accepted update now says the measurement fits, not that P was wide."""
        return float(np.max(np.diag(self.kf.P)[P_])) < self.config.settled_position_sigma_m ** 2

    def _becomes_lost(self) -> bool:
        c = self.config
        since = self.t_s - self._last_accept_s
        if since > c.coast_s:
            return True
        return since > c.dropout_s and float(np.max(np.diag(self.kf.P)[P_])) > (
            c.lost_position_sigma_m ** 2)

    def _propagate(self, dt: float, gyro: np.ndarray, accel: np.ndarray,
                   imu: bool = False) -> None:
        if self.history is not None:
            post, p_post = self.nominal(), self.kf.P.copy()
        if not self._lost and self._becomes_lost():
            self._lost = True
            self.counters.lost += 1
        lost = self._lost
        w = gyro - self.gyro_bias
        f = accel - self.accel_bias
        r = quat_to_matrix(self.quat)
        rf = r @ f
        if lost:
            self.vel[:] = 0.0
        else:
            # eq 3.7 in the inertial frame, eq 3.8
            a = rf + self.gravity
            self.pos += self.vel * dt + 0.5 * dt * dt * a
            self.vel += a * dt
        # eq 3.9, exact for a constant rate over dt
        dq = quat_exp(w * dt)
        self.quat = quat_multiply(self.quat, dq)
        self.quat /= np.sqrt(self.quat @ self.quat)
        # eq 3.12: error-state transition
        F = self._F
        F[P_, V_] = _I3 * dt
        F[V_, TH] = -(r @ skew(f)) * dt
        F[V_, BA] = -r * dt
        F[TH, TH] = quat_to_matrix(dq).T
        F[TH, BG] = -_I3 * dt
        Q = np.diag(self._q_density * dt)
        if lost:  # position and velocity errors independent of the past, fixed variance
            F = F.copy()
            F[:6, :] = 0.0
            Q[P_, P_] = _I3 * self.config.lost_position_sigma_m ** 2
            Q[V_, V_] = _I3 * self.config.lost_velocity_sigma_m_s ** 2
        # eq 3.13 (x stays zero: F 0 = 0)
        self.kf.predict(F=F, Q=Q)
        self.t_s += dt
        self.counters.predictions += 1
        if self.history is not None:
            self.history.append((post, p_post, F.copy(), self.nominal(), self.kf.P.copy(),
                                 self.t_s, imu))

    # -- update (eq 3.10, 3.14) ---------------------------------------------

    def in_dropout(self, t_s: float) -> bool:
        """No LOSA update accepted for `dropout_s` before t_s: the next one re-acquires."""
        return t_s - self._last_accept_s > self.config.dropout_s

    def _measurement(self, t_s: float, lever_arm_body_m):
        """(h, H, lag) of a LOSA position taken at t_s (predicting up to it when it is
        newer than the last IMU sample)."""
        if t_s > self.t_s:
            # LOSA frame newer than the last IMU sample: prediction only up to it.
            if self._last_imu is not None:
                self._propagate(t_s - self.t_s, *self._last_imu)
            else:
                self.t_s = float(t_s)
        lag = self.t_s - t_s
        r = quat_to_matrix(self.quat)
        H = self._H
        H[:, V_] = -lag * _I3
        if lever_arm_body_m is None:
            h = self.pos - lag * self.vel
            H[:, TH] = 0.0
        else:
            arm = np.asarray(lever_arm_body_m, dtype=float)
            h = self.pos - lag * self.vel + r @ arm
            H[:, TH] = -(r @ skew(arm))
        return h, H, lag

    def candidate_nis(self, t_s: float, pos_ref_m, lever_arm_body_m=None, R=None
                      ) -> np.ndarray:
        """NIS (K,) of K candidate positions (K, 3) of one frame against the prediction
        (the LOSA slot re-acquisition's choice, `losa.SlotResolver`); nothing is fused."""
        h, H, _ = self._measurement(t_s, lever_arm_body_m)
        Rm = self._r_default if R is None else np.asarray(R, dtype=float)
        S = H @ self.kf.P @ H.T + Rm
        y = np.atleast_2d(np.asarray(pos_ref_m, dtype=float)) - h
        return np.einsum("ki,ki->k", y, np.linalg.solve(S, y.T).T)

    def update_position(self, t_s: float, pos_ref_m, R=None, lever_arm_body_m=None
                        ) -> UpdateResult:
        """Fuse one LOSA-triangulated position (3,) of the point `lever_arm_body_m` (3,)
        from the marker centre (the lit LED; default the centre) taken at host time
        `t_s`; `R` (3, 3) its covariance (default diag(`position_sigma_m`)^2)."""
        c = self.config
        z = np.asarray(pos_ref_m, dtype=float)
        in_dropout = self.in_dropout(t_s)
        gate = self._gate * (c.reacquire_gate_scale if in_dropout else 1.0)
        if self.t_s - t_s > c.max_lag_s:
            self.counters.late += 1
            return UpdateResult(False, float("nan"), gate, "late")
        h, H, lag = self._measurement(t_s, lever_arm_body_m)
        Rm = self._r_default if R is None else np.asarray(R, dtype=float)
        y = z - h
        P = self.kf.P
        S = H @ P @ H.T + Rm
        nis = float(y @ np.linalg.solve(S, y))
        if not nis <= gate:
            self._rejections += 1
            if in_dropout and self._rejections >= c.max_rejections:
                self._reacquire(z - (h - self.pos), t_s)
                return UpdateResult(True, nis, gate, "reacquired")
            self.counters.gated += 1
            return UpdateResult(False, nis, gate, "gated")
        # eq 3.14 in Joseph form (filterpy), on the error state (x = 0, so y = z - h)
        self.kf.update(y, R=Rm, H=H)
        self._inject_and_reset()
        self._rejections = 0
        self._last_accept_s = max(self._last_accept_s, float(t_s))
        self._lost = False
        self.counters.accepted += 1
        return UpdateResult(True, nis, gate, "accepted")

    def _inject_and_reset(self) -> None:
        dx = self.kf.x[:, 0]
        self.pos += dx[P_]
        self.vel += dx[V_]
        dtheta = dx[TH]
        self.quat = quat_multiply(self.quat, quat_exp(dtheta))
        self.quat /= np.sqrt(self.quat @ self.quat)
        self.gyro_bias += dx[BG]
        self.accel_bias += dx[BA]
        G = np.eye(N_ERR)
        G[TH, TH] -= skew(0.5 * dtheta)
        P = G @ self.kf.P @ G.T
        self.kf.P = 0.5 * (P + P.T)
        self.kf.x[:] = 0.0

    def _reacquire(self, pos: np.ndarray, t_s: float) -> None:
        """Take the position from the measurement after a dropout the filter cannot
        explain; velocity restarts from zero with its initial uncertainty."""
        c = self.config
        self.pos = np.array(pos, dtype=float)
        self.vel = np.zeros(3)
        P = self.kf.P
        P[:6, :] = 0.0
        P[:, :6] = 0.0
        P[P_, P_] = _I3 * c.initial_position_sigma_m**2
        P[V_, V_] = _I3 * c.initial_velocity_sigma_m_s**2
        self._rejections = 0
        self._last_accept_s = float(t_s)
        self._lost = False
        self.counters.reacquired += 1


def run_pose_ekf(ekf: PoseEkf, imu_t_s, gyro_rad_s, accel_m_s2, losa_t_s, losa_pos_ref_m,
                 losa_ok=None, lever_arm_body_m=None, R=None, losa_peaks=None,
                 resolver=None) -> PoseTrack:
    """Run `ekf` over time-ordered streams on one host timeline.

    IMU: `imu_t_s` (N,), `gyro_rad_s`, `accel_m_s2` (N, 3). LOSA: `losa_t_s` (M,),
    `losa_pos_ref_m` (M, 3) triangulated positions, `losa_ok` (M,) (frames not ok are
    missing: prediction only), `lever_arm_body_m` (M, 3) or (3,) or None. At equal
    times the IMU sample goes first. Returns the state after each IMU sample.
    `losa_peaks` (peak_px, slot, valid), each (M, 4), with a `losa.SlotResolver`: the
    slots are re-resolved against the prediction at every re-acquisition (the frames'
    positions are then triangulated again with the kept corrections).
    """
    imu_t = np.asarray(imu_t_s, dtype=float)
    gyro = np.asarray(gyro_rad_s, dtype=float)
    accel = np.asarray(accel_m_s2, dtype=float)
    losa_t = np.asarray(losa_t_s, dtype=float)
    losa_pos = np.asarray(losa_pos_ref_m, dtype=float)
    if gyro.shape != (imu_t.size, 3) or accel.shape != (imu_t.size, 3):
        raise TrackingError(f"run_pose_ekf: gyro {gyro.shape} and accel {accel.shape}: "
                            f"expected ({imu_t.size}, 3)")
    if losa_pos.shape != (losa_t.size, 3):
        raise TrackingError(f"run_pose_ekf: losa_pos_ref_m {losa_pos.shape}: "
                            f"expected ({losa_t.size}, 3)")
    ok = (np.ones(losa_t.size, bool) if losa_ok is None else np.asarray(losa_ok, bool))
    ok = ok & np.all(np.isfinite(losa_pos), axis=1)
    arms = None if lever_arm_body_m is None else np.broadcast_to(
        np.asarray(lever_arm_body_m, dtype=float), (losa_t.size, 3))
    n = imu_t.size
    out_pos, out_vel = np.empty((n, 3)), np.empty((n, 3))
    out_q, out_sig = np.empty((n, 4)), np.empty((n, 3))
    outcome = np.full(losa_t.size, "missing", dtype=object)
    nis = np.full(losa_t.size, np.nan)
    unresolved = np.zeros(losa_t.size, bool)
    # LOSA frame j is applied after every IMU sample with t <= losa_t[j].
    after = np.searchsorted(imu_t, losa_t, side="right")
    j = 0
    m = losa_t.size
    for i in range(n + 1):
        while j < m and after[j] == i:
            if ok[j]:
                arm = None if arms is None else arms[j]
                z = losa_pos[j]
                if resolver is not None:
                    pk = (losa_peaks[0][j], losa_peaks[1][j], losa_peaks[2][j])
                    if ekf.in_dropout(losa_t[j]):
                        z = resolver.position(*pk, choose=lambda c, t=losa_t[j], a=arm:
                                              ekf.candidate_nis(t, c, a, R), lost=ekf.lost)
                    elif any(resolver.shift):
                        z = resolver.position(*pk)
                if z is not None:
                    res = ekf.update_position(losa_t[j], z, R, arm)
                    outcome[j], nis[j] = res.outcome, res.nis
                    if resolver is not None:
                        unresolved[j] = resolver.ambiguous
                        resolver.confirm(z, res.outcome == "accepted" and ekf.settled(),
                                         losa_t[j])
            j += 1
        if i == n:
            break
        ekf.predict(imu_t[i], gyro[i], accel[i])
        out_pos[i], out_vel[i], out_q[i] = ekf.pos, ekf.vel, ekf.quat
        out_sig[i] = np.sqrt(np.diag(ekf.P)[P_])
    return PoseTrack(imu_t, out_pos, out_vel, out_q, out_sig, losa_t, outcome.astype(str), nis,
                     losa_t[unresolved])


__all__ = ["PoseEkf", "PoseEkfConfig", "PoseTrack", "UpdateResult", "run_pose_ekf"]
