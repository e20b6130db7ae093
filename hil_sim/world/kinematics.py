"""Truth kinematics: the trajectory container every simulated sensor samples.

The world integrates the helicopter at >= 1 kHz and fills a `Trajectory` with the truth
at every step; each sensor then samples it at its own rate (`Trajectory.at`) and adds
its own errors. `hover`, `constant_rotation` and `circle` build exact analytic
trajectories so sensor tests do not need the helicopter model.

Conventions (binding for every user of this module):
- inertial frame NED: x north, y east, z down, metres; D = 0 is the sea surface (or the
  hall floor indoors);
- body frame FRD: x forward, y right, z down;
- quaternions scalar first `[w, x, y, z]`, unit, rotating body vectors into NED:
  `v_ned = R(q) @ v_body`;
- Euler angles `[roll, pitch, yaw]` (rad), aerospace z-y-x order:
  `R = Rz(yaw) @ Ry(pitch) @ Rx(roll)`;
- specific force = kinematic acceleration minus gravity, in body axes: what an
  accelerometer at the reference point reads (at rest, level: `[0, 0, -g]`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from functools import cached_property

import numpy as np

# Table 5.1 / 5.2 of the reference ("g* = 9.798 m/s^2, direct measurement"): the same
# value the host model uses, so analytic specific forces agree with it.
GRAVITY_M_S2 = 9.798

ArrayLike = np.ndarray | list | tuple | float


# ---------------------------------------------------------------------------
# Rotation helpers (vectorised over leading axes)
# ---------------------------------------------------------------------------


def quat_multiply(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product p ⊗ q, shapes (..., 4)."""
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    pw, px, py, pz = np.moveaxis(p, -1, 0)
    qw, qx, qy, qz = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
        ],
        axis=-1,
    )


def quat_conjugate(q: np.ndarray) -> np.ndarray:
    """Inverse rotation of a unit quaternion, shape (..., 4)."""
    q = np.asarray(q, dtype=float)
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def quat_normalize(q: np.ndarray) -> np.ndarray:
    """Unit quaternion with non-negative scalar part, shape (..., 4)."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    return np.where(q[..., :1] < 0.0, -q, q)


def quat_to_dcm(q: np.ndarray) -> np.ndarray:
    """Rotation matrix body -> NED from `[w, x, y, z]`, shape (..., 3, 3)."""
    q = np.asarray(q, dtype=float)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    out = np.empty(q.shape[:-1] + (3, 3))
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx, wy, wz = w * x, w * y, w * z
    out[..., 0, 0] = 1 - 2 * (yy + zz)
    out[..., 0, 1] = 2 * (xy - wz)
    out[..., 0, 2] = 2 * (xz + wy)
    out[..., 1, 0] = 2 * (xy + wz)
    out[..., 1, 1] = 1 - 2 * (xx + zz)
    out[..., 1, 2] = 2 * (yz - wx)
    out[..., 2, 0] = 2 * (xz - wy)
    out[..., 2, 1] = 2 * (yz + wx)
    out[..., 2, 2] = 1 - 2 * (xx + yy)
    return out


def euler_to_dcm(euler_rad: np.ndarray) -> np.ndarray:
    """`[roll, pitch, yaw]` (z-y-x) -> rotation body -> NED, (..., 3) -> (..., 3, 3)."""
    e = np.asarray(euler_rad, dtype=float)
    cr, sr = np.cos(e[..., 0]), np.sin(e[..., 0])
    cp, sp = np.cos(e[..., 1]), np.sin(e[..., 1])
    cy, sy = np.cos(e[..., 2]), np.sin(e[..., 2])
    out = np.empty(e.shape[:-1] + (3, 3))
    out[..., 0, 0] = cp * cy
    out[..., 0, 1] = sr * sp * cy - cr * sy
    out[..., 0, 2] = cr * sp * cy + sr * sy
    out[..., 1, 0] = cp * sy
    out[..., 1, 1] = sr * sp * sy + cr * cy
    out[..., 1, 2] = cr * sp * sy - sr * cy
    out[..., 2, 0] = -sp
    out[..., 2, 1] = sr * cp
    out[..., 2, 2] = cr * cp
    return out


def dcm_to_quat(dcm: np.ndarray) -> np.ndarray:
    """Unit quaternion (scalar >= 0) of rotation matrices, (..., 3, 3) -> (..., 4)."""
    m = np.asarray(dcm, dtype=float)
    tr = m[..., 0, 0] + m[..., 1, 1] + m[..., 2, 2]
    # Four candidate formulas; pick per element the one with the largest pivot (stable).
    cand = np.stack(
        [
            np.stack([1 + tr, m[..., 2, 1] - m[..., 1, 2], m[..., 0, 2] - m[..., 2, 0],
                      m[..., 1, 0] - m[..., 0, 1]], -1),
            np.stack([m[..., 2, 1] - m[..., 1, 2], 1 + 2 * m[..., 0, 0] - tr,
                      m[..., 0, 1] + m[..., 1, 0], m[..., 0, 2] + m[..., 2, 0]], -1),
            np.stack([m[..., 0, 2] - m[..., 2, 0], m[..., 0, 1] + m[..., 1, 0],
                      1 + 2 * m[..., 1, 1] - tr, m[..., 1, 2] + m[..., 2, 1]], -1),
            np.stack([m[..., 1, 0] - m[..., 0, 1], m[..., 0, 2] + m[..., 2, 0],
                      m[..., 1, 2] + m[..., 2, 1], 1 + 2 * m[..., 2, 2] - tr], -1),
        ],
        axis=-2,
    )
    pivots = np.stack(
        [1 + tr, 1 + 2 * m[..., 0, 0] - tr, 1 + 2 * m[..., 1, 1] - tr, 1 + 2 * m[..., 2, 2] - tr],
        -1,
    )
    best = np.argmax(pivots, axis=-1)
    q = np.take_along_axis(cand, best[..., None, None], axis=-2)[..., 0, :]
    return quat_normalize(q)


def euler_to_quat(euler_rad: np.ndarray) -> np.ndarray:
    """`[roll, pitch, yaw]` (z-y-x) -> `[w, x, y, z]`, shapes (..., 3) -> (..., 4)."""
    e = np.asarray(euler_rad, dtype=float)
    cr, sr = np.cos(e[..., 0] / 2), np.sin(e[..., 0] / 2)
    cp, sp = np.cos(e[..., 1] / 2), np.sin(e[..., 1] / 2)
    cy, sy = np.cos(e[..., 2] / 2), np.sin(e[..., 2] / 2)
    q = np.stack(
        [
            cr * cp * cy + sr * sp * sy,
            sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
        ],
        axis=-1,
    )
    return quat_normalize(q)


def quat_to_euler(q: np.ndarray) -> np.ndarray:
    """`[w, x, y, z]` -> `[roll, pitch, yaw]` (z-y-x, yaw in (-pi, pi]), (..., 4) -> (..., 3)."""
    q = np.asarray(q, dtype=float)
    w, x, y, z = np.moveaxis(q, -1, 0)
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - x * z), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.stack([roll, pitch, yaw], axis=-1)


def quat_from_rotvec(rotvec: np.ndarray) -> np.ndarray:
    """Rotation vector (axis * angle, rad) -> unit quaternion, (..., 3) -> (..., 4)."""
    rv = np.asarray(rotvec, dtype=float)
    angle = np.linalg.norm(rv, axis=-1, keepdims=True)
    half = angle / 2
    # sin(a/2)/a with its series near zero so tiny rotations stay exact.
    k = np.where(angle > 1e-8, np.sin(half) / np.where(angle > 1e-8, angle, 1.0),
                 0.5 - angle**2 / 48)
    return np.concatenate([np.cos(half), rv * k], axis=-1)


def rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """`R(q) @ v` (body -> NED for a body->NED quaternion), broadcast over (..., 3)."""
    return np.einsum("...ij,...j->...i", quat_to_dcm(q), np.asarray(v, dtype=float))


def rotate_inverse(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """`R(q).T @ v` (NED -> body), broadcast over (..., 3)."""
    return np.einsum("...ji,...j->...i", quat_to_dcm(q), np.asarray(v, dtype=float))


def euler_rates_to_body_rates(euler_rad: np.ndarray, euler_dot_rad_s: np.ndarray) -> np.ndarray:
    """Body rates `[p, q, r]` from z-y-x Euler angles and their derivatives, (..., 3)."""
    e = np.asarray(euler_rad, dtype=float)
    ed = np.asarray(euler_dot_rad_s, dtype=float)
    sphi, cphi = np.sin(e[..., 0]), np.cos(e[..., 0])
    sth, cth = np.sin(e[..., 1]), np.cos(e[..., 1])
    p = ed[..., 0] - ed[..., 2] * sth
    q = ed[..., 1] * cphi + ed[..., 2] * cth * sphi
    r = -ed[..., 1] * sphi + ed[..., 2] * cth * cphi
    return np.stack([p, q, r], axis=-1)


# ---------------------------------------------------------------------------
# The container
# ---------------------------------------------------------------------------


def _as2(a: ArrayLike, n: int, width: int, name: str) -> np.ndarray:
    arr = np.asarray(a, dtype=float)
    if arr.shape == (width,):
        arr = np.broadcast_to(arr, (n, width)).copy()
    if arr.shape != (n, width):
        raise ValueError(f"Trajectory.{name}: shape {arr.shape}, expected ({n}, {width})")
    return arr


def _as1(a: ArrayLike, n: int, name: str) -> np.ndarray:
    arr = np.asarray(a, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,):
        raise ValueError(f"Trajectory.{name}: shape {arr.shape}, expected ({n},)")
    return arr


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Truth kinematics of one rigid body at N increasing times.

    Shapes (N samples): `t_s` (N,); vectors (N, 3); `quat_wxyz` (N, 4);
    `blade_pitch_rad` (N, 4); scalars per sample (N,). All SI units as named.

    Fields:
    - `t_s`: simulation time, s (strictly increasing).
    - `pos_ned_m`, `vel_ned_m_s`: position / velocity of the reference point (CG for the
      helicopter, the deck reference point for the ship) in the inertial NED frame.
    - `quat_wxyz`: attitude, body -> NED. `euler_rad`: the same as `[roll, pitch, yaw]`.
    - `vel_body_m_s`: velocity in body axes, `[u, v, w]`.
    - `rates_body_rad_s`: `[p, q, r]`; `ang_acc_body_rad_s2`: their time derivative.
    - `specific_force_body_m_s2`: accelerometer reading at the reference point (CG).
    - `rotor_speed_rad_s`: main-rotor speed Omega (0 for bodies without a rotor).
    - `rotor_azimuth_rad`: main-rotor azimuth of blade 1, **unwrapped** (continuous,
      increasing with rotation); blade 1 over the tail at 0 (mod 2 pi).
    - `blade_pitch_rad`: blade-pitch commands `[col, lat, lon, ped]` (the flight-table
      columns `delta_col_rad, delta_lat_rad, delta_lon_rad, delta_ped_rad`).
    - `height_agl_m`: rotor hub above ground or deck.
    - `ship`: the ship reference point's `Trajectory` at the same times, or None.

    Build it with `Trajectory.from_states(...)` (derives what is not given) or the
    analytic constructors `hover`, `constant_rotation`, `circle`.
    """

    t_s: np.ndarray
    pos_ned_m: np.ndarray
    vel_ned_m_s: np.ndarray
    quat_wxyz: np.ndarray
    euler_rad: np.ndarray
    vel_body_m_s: np.ndarray
    rates_body_rad_s: np.ndarray
    ang_acc_body_rad_s2: np.ndarray
    specific_force_body_m_s2: np.ndarray
    rotor_speed_rad_s: np.ndarray
    rotor_azimuth_rad: np.ndarray
    blade_pitch_rad: np.ndarray
    height_agl_m: np.ndarray
    ship: Trajectory | None = field(default=None)

    def __post_init__(self) -> None:
        t = np.asarray(self.t_s, dtype=float)
        if t.ndim != 1 or t.size < 1:
            raise ValueError(f"Trajectory.t_s: shape {t.shape}, expected (N,) with N >= 1")
        if t.size > 1 and not np.all(np.diff(t) > 0):
            raise ValueError("Trajectory.t_s: times must be strictly increasing")
        n = t.size
        widths = {"pos_ned_m": 3, "vel_ned_m_s": 3, "quat_wxyz": 4, "euler_rad": 3,
                  "vel_body_m_s": 3, "rates_body_rad_s": 3, "ang_acc_body_rad_s2": 3,
                  "specific_force_body_m_s2": 3, "blade_pitch_rad": 4}
        object.__setattr__(self, "t_s", t)
        for f in fields(self):
            if f.name in ("t_s", "ship"):
                continue
            value = getattr(self, f.name)
            if f.name in widths:
                arr = _as2(value, n, widths[f.name], f.name)
            else:
                arr = _as1(value, n, f.name)
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"Trajectory.{f.name}: contains non-finite values")
            object.__setattr__(self, f.name, arr)
        if self.ship is not None and len(self.ship) != n:
            raise ValueError(f"Trajectory.ship: {len(self.ship)} samples, expected {n}")

    def __len__(self) -> int:
        return self.t_s.size

    @property
    def duration_s(self) -> float:
        return float(self.t_s[-1] - self.t_s[0])

    @cached_property
    def dcm_body_to_ned(self) -> np.ndarray:
        """(N, 3, 3) rotation matrices body -> NED."""
        return quat_to_dcm(self.quat_wxyz)

    # -- construction ------------------------------------------------------

    @classmethod
    def from_states(
        cls,
        t_s: ArrayLike,
        pos_ned_m: ArrayLike,
        vel_ned_m_s: ArrayLike,
        quat_wxyz: ArrayLike,
        rates_body_rad_s: ArrayLike,
        *,
        ang_acc_body_rad_s2: ArrayLike | None = None,
        specific_force_body_m_s2: ArrayLike | None = None,
        rotor_speed_rad_s: ArrayLike = 0.0,
        rotor_azimuth_rad: ArrayLike | None = None,
        blade_pitch_rad: ArrayLike = (0.0, 0.0, 0.0, 0.0),
        height_agl_m: ArrayLike | None = None,
        ship: Trajectory | None = None,
        gravity_m_s2: float = GRAVITY_M_S2,
    ) -> Trajectory:
        """Fill a trajectory from integrated states, deriving the rest.

        Derived when not given: Euler angles and body velocity (always, from the
        quaternion); angular acceleration (finite differences of the rates);
        specific force (finite differences of NED velocity minus gravity, rotated into
        body); rotor azimuth (trapezoidal integral of rotor speed from 0); height
        above ground (-D). The world should pass the integrator's own angular
        acceleration and specific force: finite differences lose the high-frequency
        content (rotor vibration, steps) that the sensors must see.
        """
        t = np.asarray(t_s, dtype=float)
        n = t.size
        q = quat_normalize(_as2(quat_wxyz, n, 4, "quat_wxyz"))
        vel = _as2(vel_ned_m_s, n, 3, "vel_ned_m_s")
        pos = _as2(pos_ned_m, n, 3, "pos_ned_m")
        rates = _as2(rates_body_rad_s, n, 3, "rates_body_rad_s")
        if ang_acc_body_rad_s2 is None:
            ang_acc = np.gradient(rates, t, axis=0) if n > 1 else np.zeros((n, 3))
        else:
            ang_acc = ang_acc_body_rad_s2
        if specific_force_body_m_s2 is None:
            acc = np.gradient(vel, t, axis=0) if n > 1 else np.zeros((n, 3))
            f_ned = acc - np.array([0.0, 0.0, gravity_m_s2])
            specific = rotate_inverse(q, f_ned)
        else:
            specific = specific_force_body_m_s2
        omega = _as1(rotor_speed_rad_s, n, "rotor_speed_rad_s")
        if rotor_azimuth_rad is None:
            dpsi = np.diff(t) * 0.5 * (omega[1:] + omega[:-1])
            azimuth = np.concatenate([[0.0], np.cumsum(dpsi)])
        else:
            azimuth = rotor_azimuth_rad
        hagl = -pos[:, 2] if height_agl_m is None else height_agl_m
        return cls(
            t_s=t,
            pos_ned_m=pos,
            vel_ned_m_s=vel,
            quat_wxyz=q,
            euler_rad=quat_to_euler(q),
            vel_body_m_s=rotate_inverse(q, vel),
            rates_body_rad_s=rates,
            ang_acc_body_rad_s2=ang_acc,
            specific_force_body_m_s2=specific,
            rotor_speed_rad_s=omega,
            rotor_azimuth_rad=azimuth,
            blade_pitch_rad=blade_pitch_rad,
            height_agl_m=hagl,
            ship=ship,
        )

    # -- sampling ----------------------------------------------------------

    def at(self, t_query: ArrayLike) -> Trajectory:
        """The trajectory at other times, by interpolation.

        Linear for every vector and scalar (the azimuth is unwrapped, so linear is
        right); normalised linear (nlerp) for the quaternion, Euler angles recomputed
        from it. Times outside the span are clamped to the end values. Sensors sample
        at <= 1/2 of the simulation rate, where linear interpolation of a >= 1 kHz
        truth is well below every sensor's noise.
        """
        tq = np.atleast_1d(np.asarray(t_query, dtype=float))
        t = self.t_s
        if t.size == 1:
            idx = np.zeros(tq.size, dtype=int)
            frac = np.zeros(tq.size)
            nxt = idx
        else:
            idx = np.clip(np.searchsorted(t, tq, side="right") - 1, 0, t.size - 2)
            nxt = idx + 1
            frac = np.clip((tq - t[idx]) / (t[nxt] - t[idx]), 0.0, 1.0)

        def lerp(a: np.ndarray) -> np.ndarray:
            f = frac.reshape((-1,) + (1,) * (a.ndim - 1))
            return a[idx] * (1.0 - f) + a[nxt] * f

        q0 = self.quat_wxyz[idx]
        q1 = self.quat_wxyz[nxt]
        # Take the short way round when the two samples straddle a sign flip.
        q1 = np.where(np.sum(q0 * q1, axis=-1, keepdims=True) < 0.0, -q1, q1)
        q = quat_normalize(q0 * (1.0 - frac[:, None]) + q1 * frac[:, None])
        return Trajectory(
            t_s=tq,
            pos_ned_m=lerp(self.pos_ned_m),
            vel_ned_m_s=lerp(self.vel_ned_m_s),
            quat_wxyz=q,
            euler_rad=quat_to_euler(q),
            vel_body_m_s=rotate_inverse(q, lerp(self.vel_ned_m_s)),
            rates_body_rad_s=lerp(self.rates_body_rad_s),
            ang_acc_body_rad_s2=lerp(self.ang_acc_body_rad_s2),
            specific_force_body_m_s2=lerp(self.specific_force_body_m_s2),
            rotor_speed_rad_s=lerp(self.rotor_speed_rad_s),
            rotor_azimuth_rad=lerp(self.rotor_azimuth_rad),
            blade_pitch_rad=lerp(self.blade_pitch_rad),
            height_agl_m=lerp(self.height_agl_m),
            ship=None if self.ship is None else self.ship.at(tq),
        )

    def window(self, t_start_s: float, t_end_s: float) -> Trajectory:
        """The samples with `t_start_s <= t <= t_end_s` (no interpolation)."""
        sel = (self.t_s >= t_start_s) & (self.t_s <= t_end_s)
        if not np.any(sel):
            raise ValueError(f"Trajectory.window: no samples in [{t_start_s}, {t_end_s}] s")
        return self._select(sel)

    def _select(self, sel: np.ndarray) -> Trajectory:
        kwargs = {f.name: getattr(self, f.name)[sel] for f in fields(self) if f.name != "ship"}
        kwargs["ship"] = None if self.ship is None else self.ship._select(sel)
        return Trajectory(**kwargs)

    def at_point(
        self, r_body_m: ArrayLike, mount_quat_wxyz: ArrayLike | None = None
    ) -> Trajectory:
        """Kinematics of a body-fixed point (an IMU, antenna, marker, anemometer).

        `r_body_m` (3,): the point relative to the reference point, body axes.
        `mount_quat_wxyz` (4,): the sensor frame relative to the body (sensor -> body);
        None for a sensor aligned with the body. The returned trajectory's "body" is the
        sensor frame:

            p = p_ref + R r,  v = v_ref + R (w x r),
            f = f_ref + w_dot x r + w x (w x r)            (rigid-body lever arm)

        then rates, angular acceleration and specific force are rotated into the
        sensor frame. Rotor and pilot fields are copied unchanged.
        """
        r = np.asarray(r_body_m, dtype=float).reshape(3)
        w = self.rates_body_rad_s
        wd = self.ang_acc_body_rad_s2
        w_x_r = np.cross(w, r)
        pos = self.pos_ned_m + np.einsum("nij,j->ni", self.dcm_body_to_ned, r)
        vel = self.vel_ned_m_s + np.einsum("nij,nj->ni", self.dcm_body_to_ned, w_x_r)
        spec = self.specific_force_body_m_s2 + np.cross(wd, r) + np.cross(w, w_x_r)
        q = self.quat_wxyz
        rates = w
        ang_acc = wd
        if mount_quat_wxyz is not None:
            qm = quat_normalize(np.asarray(mount_quat_wxyz, dtype=float).reshape(4))
            q = quat_normalize(quat_multiply(q, qm))
            rates = rotate_inverse(qm, rates)
            ang_acc = rotate_inverse(qm, ang_acc)
            spec = rotate_inverse(qm, spec)
        return replace(
            self,
            pos_ned_m=pos,
            vel_ned_m_s=vel,
            quat_wxyz=q,
            euler_rad=quat_to_euler(q),
            vel_body_m_s=rotate_inverse(q, vel),
            rates_body_rad_s=rates,
            ang_acc_body_rad_s2=ang_acc,
            specific_force_body_m_s2=spec,
        )


# ---------------------------------------------------------------------------
# Analytic trajectories for tests and examples
# ---------------------------------------------------------------------------


def _times(duration_s: float, rate_hz: float, t0_s: float) -> np.ndarray:
    if duration_s <= 0 or rate_hz <= 0:
        raise ValueError(f"duration_s={duration_s} and rate_hz={rate_hz} must be > 0")
    n = int(round(duration_s * rate_hz)) + 1
    return t0_s + np.arange(n) / rate_hz


def hover(
    duration_s: float,
    rate_hz: float = 1000.0,
    *,
    pos_ned_m: ArrayLike = (0.0, 0.0, -2.5),
    yaw_rad: float = 0.0,
    rotor_speed_rad_s: float = 163.3,
    blade_pitch_rad: ArrayLike = (0.09, 0.0, 0.0, 0.05),
    t0_s: float = 0.0,
    gravity_m_s2: float = GRAVITY_M_S2,
) -> Trajectory:
    """Perfect hover: fixed position and yaw, level, constant rotor speed.

    Default rotor speed 163.3 rad/s is Omega of Table 5.1/5.2.
    """
    t = _times(duration_s, rate_hz, t0_s)
    n = t.size
    q = euler_to_quat(np.array([0.0, 0.0, yaw_rad]))
    return Trajectory.from_states(
        t,
        pos_ned_m=np.broadcast_to(np.asarray(pos_ned_m, float), (n, 3)),
        vel_ned_m_s=np.zeros((n, 3)),
        quat_wxyz=np.broadcast_to(q, (n, 4)),
        rates_body_rad_s=np.zeros((n, 3)),
        ang_acc_body_rad_s2=np.zeros((n, 3)),
        specific_force_body_m_s2=np.broadcast_to([0.0, 0.0, -gravity_m_s2], (n, 3)),
        rotor_speed_rad_s=rotor_speed_rad_s,
        rotor_azimuth_rad=rotor_speed_rad_s * (t - t[0]),
        blade_pitch_rad=blade_pitch_rad,
        height_agl_m=-float(np.asarray(pos_ned_m, float)[2]),
    )


def constant_rotation(
    duration_s: float,
    rates_body_rad_s: ArrayLike,
    rate_hz: float = 1000.0,
    *,
    pos_ned_m: ArrayLike = (0.0, 0.0, -2.5),
    initial_quat_wxyz: ArrayLike = (1.0, 0.0, 0.0, 0.0),
    rotor_speed_rad_s: float = 0.0,
    t0_s: float = 0.0,
    gravity_m_s2: float = GRAVITY_M_S2,
) -> Trajectory:
    """A body spinning at constant body rates about a fixed point.

    Exact attitude: q(t) = q0 ⊗ exp(w t / 2) (constant body rates keep the rotation
    axis fixed in both frames). Specific force is gravity's reaction in body axes.
    """
    t = _times(duration_s, rate_hz, t0_s)
    n = t.size
    w = np.asarray(rates_body_rad_s, dtype=float).reshape(3)
    q0 = quat_normalize(np.asarray(initial_quat_wxyz, dtype=float))
    q = quat_multiply(np.broadcast_to(q0, (n, 4)), quat_from_rotvec(np.outer(t - t[0], w)))
    q = quat_normalize(q)
    spec = rotate_inverse(q, np.array([0.0, 0.0, -gravity_m_s2]))
    return Trajectory.from_states(
        t,
        pos_ned_m=np.broadcast_to(np.asarray(pos_ned_m, float), (n, 3)),
        vel_ned_m_s=np.zeros((n, 3)),
        quat_wxyz=q,
        rates_body_rad_s=np.broadcast_to(w, (n, 3)),
        ang_acc_body_rad_s2=np.zeros((n, 3)),
        specific_force_body_m_s2=spec,
        rotor_speed_rad_s=rotor_speed_rad_s,
        rotor_azimuth_rad=rotor_speed_rad_s * (t - t[0]),
        height_agl_m=-float(np.asarray(pos_ned_m, float)[2]),
    )


def circle(
    duration_s: float,
    radius_m: float,
    speed_m_s: float,
    rate_hz: float = 1000.0,
    *,
    center_ned_m: ArrayLike = (0.0, 0.0, -3.0),
    rotor_speed_rad_s: float = 163.3,
    t0_s: float = 0.0,
    gravity_m_s2: float = GRAVITY_M_S2,
) -> Trajectory:
    """Level flight round a horizontal circle, clockwise seen from above, nose along track.

    Position `c + R [cos a, sin a, 0]` with `a = (V/R) t`; the body stays level and yaws
    at `r = V/R`; specific force carries the centripetal acceleration `-V^2/R` toward
    the centre plus gravity's reaction.
    """
    if radius_m <= 0:
        raise ValueError(f"radius_m={radius_m} must be > 0")
    t = _times(duration_s, rate_hz, t0_s)
    n = t.size
    c = np.asarray(center_ned_m, dtype=float)
    rate = speed_m_s / radius_m
    a = rate * (t - t[0])
    radial = np.stack([np.cos(a), np.sin(a), np.zeros(n)], axis=-1)
    tangent = np.stack([-np.sin(a), np.cos(a), np.zeros(n)], axis=-1)
    pos = c + radius_m * radial
    vel = speed_m_s * tangent
    acc = -speed_m_s * rate * radial
    yaw = np.arctan2(tangent[:, 1], tangent[:, 0])
    q = euler_to_quat(np.stack([np.zeros(n), np.zeros(n), yaw], axis=-1))
    spec = rotate_inverse(q, acc - np.array([0.0, 0.0, gravity_m_s2]))
    return Trajectory.from_states(
        t,
        pos_ned_m=pos,
        vel_ned_m_s=vel,
        quat_wxyz=q,
        rates_body_rad_s=np.broadcast_to([0.0, 0.0, rate], (n, 3)),
        ang_acc_body_rad_s2=np.zeros((n, 3)),
        specific_force_body_m_s2=spec,
        rotor_speed_rad_s=rotor_speed_rad_s,
        rotor_azimuth_rad=rotor_speed_rad_s * (t - t[0]),
        height_agl_m=-c[2],
    )
