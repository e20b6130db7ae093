"""The ship: motion, ship-frame geometry, frame transforms and relative wind.

Ship frame S: x forward (bow), y starboard, z down; origin at deck level on the
centreline at the hangar's aft face (the "step" the airwake separates from). The
flight deck is the plane z = 0 aft of the step (x in [-deck_length, 0]); the hangar
occupies x in [0, hangar_length], |y| <= hangar_width / 2, up to z = -hangar_height.

Motion: the ship steams at `speed_m_s` on `heading_deg` and oscillates in roll, pitch
and yaw (sinusoids, small: the reference's trials kept pitch and roll within +-3 deg,
§4.5) about a rotation centre (~ the centre of gravity, below the deck and forward of
the step), with optional heave. Inertial NED has D = 0 at the sea surface; at t = 0 the
origin is at (start_ne_m, -deck_height_m) (up to the small initial attitude).

Relative wind (what the airwake depends on): the true wind minus the ship's velocity,
in ship axes, described by speed and heading beta = the direction it blows *from*,
measured from the bow, positive to starboard (beta = 0: head wind).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numba
import numpy as np

from hil_sim.sensors.config import check_finite, check_nonnegative, check_positive, check_range
from hil_sim.world.kinematics import (
    GRAVITY_M_S2,
    Trajectory,
    euler_rates_to_body_rates,
    euler_to_quat,
    quat_to_dcm,
)

Vec3 = tuple[float, float, float]
_EPS_S = 1e-3  # step for the numerical angular acceleration


@dataclass(frozen=True)
class ShipConfig:
    """Ship motion and geometry (defaults: a YP676-like patrol craft, sea state 1-3)."""

    heading_deg: float = 0.0
    speed_m_s: float = 2.0
    start_ne_m: tuple[float, float] = (0.0, 0.0)
    deck_height_m: float = 1.5
    roll_amplitude_deg: float = 2.0
    roll_period_s: float = 8.0
    roll_phase_rad: float = 0.0
    pitch_amplitude_deg: float = 1.0
    pitch_period_s: float = 6.0
    pitch_phase_rad: float = 1.0
    yaw_amplitude_deg: float = 0.5
    yaw_period_s: float = 12.0
    yaw_phase_rad: float = 2.0
    heave_amplitude_m: float = 0.0
    heave_period_s: float = 7.0
    heave_phase_rad: float = 0.5
    rotation_centre_m: Vec3 = (8.0, 0.0, 2.0)
    hangar_height_m: float = 1.5
    hangar_width_m: float = 6.0
    hangar_length_m: float = 8.0
    deck_length_m: float = 6.0
    beam_m: float = 7.3

    def __post_init__(self) -> None:
        check_finite("heading_deg", self.heading_deg)
        check_nonnegative("speed_m_s", self.speed_m_s)
        check_finite("start_ne_m", self.start_ne_m)
        check_nonnegative("deck_height_m", self.deck_height_m)
        for axis in ("roll", "pitch", "yaw"):
            check_range(f"{axis}_amplitude_deg", getattr(self, f"{axis}_amplitude_deg"), 0.0, 15.0)
            check_positive(f"{axis}_period_s", getattr(self, f"{axis}_period_s"))
            check_finite(f"{axis}_phase_rad", getattr(self, f"{axis}_phase_rad"))
        check_nonnegative("heave_amplitude_m", self.heave_amplitude_m)
        check_positive("heave_period_s", self.heave_period_s)
        check_finite("heave_phase_rad", self.heave_phase_rad)
        check_finite("rotation_centre_m", self.rotation_centre_m)
        for name in ("hangar_height_m", "hangar_width_m", "hangar_length_m", "deck_length_m",
                     "beam_m"):
            check_positive(name, getattr(self, name))


class _Motion(NamedTuple):
    """The ship's motion constants, as the compiled pose reads them: per axis the
    amplitude (rad), angular frequency (rad/s) and phase of roll, pitch, yaw; the
    heading; the course velocity; the heave; the rotation centre at t = 0 (NED) and in
    ship axes."""

    roll: tuple[float, float, float]
    pitch: tuple[float, float, float]
    yaw: tuple[float, float, float]
    heading: float
    vel_n: float
    vel_e: float
    heave: tuple[float, float, float]
    rc0: tuple[float, float, float]
    rc: tuple[float, float, float]


@numba.njit(cache=True, error_model="numpy")
def _pose_rows(t, m, rot, origin, vel):
    """`Ship.pose` at times t (N,): `_sines`, `euler_to_dcm` and `_centre`, one time at
    a time."""
    for i in range(t.shape[0]):
        roll = m.roll[0] * math.sin(m.roll[1] * t[i] + m.roll[2])
        pitch = m.pitch[0] * math.sin(m.pitch[1] * t[i] + m.pitch[2])
        yaw = m.yaw[0] * math.sin(m.yaw[1] * t[i] + m.yaw[2]) + m.heading
        cr, sr = math.cos(roll), math.sin(roll)
        cp, sp = math.cos(pitch), math.sin(pitch)
        cy, sy = math.cos(yaw), math.sin(yaw)
        rot[i, 0, 0] = cp * cy
        rot[i, 0, 1] = sr * sp * cy - cr * sy
        rot[i, 0, 2] = cr * sp * cy + sr * sy
        rot[i, 1, 0] = cp * sy
        rot[i, 1, 1] = sr * sp * sy + cr * cy
        rot[i, 1, 2] = cr * sp * sy - sr * cy
        rot[i, 2, 0] = -sp
        rot[i, 2, 1] = sr * cp
        rot[i, 2, 2] = cr * cp
        amp, w, ph = m.heave
        arg = w * t[i] + ph
        centre = (m.rc0[0] + t[i] * m.vel_n, m.rc0[1] + t[i] * m.vel_e,
                  m.rc0[2] - amp * math.sin(arg))
        for j in range(3):
            origin[i, j] = centre[j] - (rot[i, j, 0] * m.rc[0] + rot[i, j, 1] * m.rc[1]
                                        + rot[i, j, 2] * m.rc[2])
        vel[i, 0] = m.vel_n
        vel[i, 1] = m.vel_e
        vel[i, 2] = -amp * w * math.cos(arg)


class Ship:
    """Ship pose and transforms at any times (vectorised, analytic)."""

    def __init__(self, config: ShipConfig | None = None) -> None:
        self.config = config or ShipConfig()
        c = self.config
        self._heading = np.radians(c.heading_deg)
        self._course = np.array([np.cos(self._heading), np.sin(self._heading), 0.0])
        self._rc = np.asarray(c.rotation_centre_m, dtype=float)
        level = quat_to_dcm(euler_to_quat(np.array([0.0, 0.0, self._heading])))
        start = np.array([c.start_ne_m[0], c.start_ne_m[1], -c.deck_height_m])
        self._rc0 = start + level @ self._rc
        axes = [tuple(float(v) for v in (np.radians(getattr(c, f"{a}_amplitude_deg")),
                                           2 * np.pi / getattr(c, f"{a}_period_s"),
                                           getattr(c, f"{a}_phase_rad")))
                for a in ("roll", "pitch", "yaw")]
        course = c.speed_m_s * self._course
        self._motion = _Motion(
            *axes, float(self._heading), float(course[0]), float(course[1]),
            (float(c.heave_amplitude_m), float(2 * np.pi / c.heave_period_s),
             float(c.heave_phase_rad)),
            tuple(float(v) for v in self._rc0), tuple(float(v) for v in self._rc))

    # -- attitude ------------------------------------------------------------

    def _sines(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Euler angles (N, 3) and their rates (N, 3)."""
        c = self.config
        e = np.zeros((t.size, 3))
        ed = np.zeros((t.size, 3))
        for i, axis in enumerate(("roll", "pitch", "yaw")):
            amp = np.radians(getattr(c, f"{axis}_amplitude_deg"))
            w = 2 * np.pi / getattr(c, f"{axis}_period_s")
            ph = getattr(c, f"{axis}_phase_rad")
            e[:, i] = amp * np.sin(w * t + ph)
            ed[:, i] = amp * w * np.cos(w * t + ph)
        e[:, 2] += self._heading
        return e, ed

    def euler_rad(self, t_s: np.ndarray | float) -> np.ndarray:
        """(N, 3) roll, pitch, yaw of the ship at times (N,)."""
        return self._sines(np.atleast_1d(np.asarray(t_s, dtype=float)))[0]

    def quat_wxyz(self, t_s: np.ndarray | float) -> np.ndarray:
        """(N, 4) ship -> NED."""
        return euler_to_quat(self.euler_rad(t_s))

    def rates_body_rad_s(self, t_s: np.ndarray | float) -> np.ndarray:
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        e, ed = self._sines(t)
        return euler_rates_to_body_rates(e, ed)

    # -- translation ---------------------------------------------------------

    def _centre(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Rotation-centre position, velocity, acceleration (N, 3) in NED."""
        c = self.config
        w = 2 * np.pi / c.heave_period_s
        arg = w * t + c.heave_phase_rad
        heave_up = c.heave_amplitude_m * np.sin(arg)
        pos = self._rc0 + np.outer(t, c.speed_m_s * self._course)
        pos[:, 2] -= heave_up
        vel = np.broadcast_to(c.speed_m_s * self._course, (t.size, 3)).copy()
        vel[:, 2] -= c.heave_amplitude_m * w * np.cos(arg)
        acc = np.zeros((t.size, 3))
        acc[:, 2] += c.heave_amplitude_m * w * w * np.sin(arg)
        return pos, vel, acc

    def pose(self, t_s: np.ndarray | float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(rotation ship -> NED (N, 3, 3), origin NED (N, 3), translational velocity
        (N, 3)) at times (N,): everything a wind field needs, computed once."""
        t = np.ascontiguousarray(np.atleast_1d(np.asarray(t_s, dtype=float)).ravel())
        rot, origin, vel = np.empty((t.size, 3, 3)), np.empty((t.size, 3)), np.empty((t.size, 3))
        _pose_rows(t, self._motion, rot, origin, vel)
        return rot, origin, vel

    def origin_ned_m(self, t_s: np.ndarray | float) -> np.ndarray:
        """(N, 3) position of the ship-frame origin (the step, deck level)."""
        return self.pose(t_s)[1]

    def translational_velocity_ned(self, t_s: np.ndarray | float) -> np.ndarray:
        """(N, 3) velocity of the rotation centre (course x speed + heave)."""
        return self._centre(np.atleast_1d(np.asarray(t_s, dtype=float)))[1]

    # -- transforms ----------------------------------------------------------

    def ship_to_ned(self, t_s: np.ndarray | float, p_ship_m: np.ndarray) -> np.ndarray:
        """Ship-frame points (N, 3) at times (N,) -> NED (N, 3)."""
        p = np.asarray(p_ship_m, dtype=float)
        t = np.broadcast_to(np.asarray(t_s, dtype=float), p.shape[:-1])
        r, origin, _ = self.pose(t.ravel())
        return (origin + np.einsum("nij,nj->ni", r, p.reshape(-1, 3))).reshape(p.shape)

    def ned_to_ship(self, t_s: np.ndarray | float, p_ned_m: np.ndarray) -> np.ndarray:
        """NED points (N, 3) at times (N,) -> ship frame (N, 3)."""
        p = np.asarray(p_ned_m, dtype=float)
        t = np.broadcast_to(np.asarray(t_s, dtype=float), p.shape[:-1])
        r, origin, _ = self.pose(t.ravel())
        return np.einsum("nji,nj->ni", r, p.reshape(-1, 3) - origin).reshape(p.shape)

    def rotation_ship_to_ned(self, t_s: np.ndarray | float) -> np.ndarray:
        """(N, 3, 3) rotation matrices ship -> NED."""
        return self.pose(t_s)[0]

    # -- kinematics for sensors ----------------------------------------------

    def trajectory(self, t_s: np.ndarray) -> Trajectory:
        """The ship-frame origin's truth kinematics (for the base VN200 / Piksi:
        `ship.trajectory(t).at_point(r_antenna_ship_m)`)."""
        t = np.asarray(t_s, dtype=float)
        e, _ = self._sines(t)
        q = euler_to_quat(e)
        r = quat_to_dcm(q)
        w = self.rates_body_rad_s(t)
        wd = (self.rates_body_rad_s(t + _EPS_S) - self.rates_body_rad_s(t - _EPS_S)) / (2 * _EPS_S)
        pos_c, vel_c, acc_c = self._centre(t)
        rc = -self._rc  # origin relative to the rotation centre, ship axes
        w_x_rc = np.cross(w, rc)
        pos = pos_c + r @ rc
        vel = vel_c + np.einsum("nij,nj->ni", r, w_x_rc)
        acc = acc_c + np.einsum("nij,nj->ni", r, np.cross(wd, rc) + np.cross(w, w_x_rc))
        specific = np.einsum("nji,nj->ni", r, acc - np.array([0.0, 0.0, GRAVITY_M_S2]))
        return Trajectory.from_states(
            t, pos, vel, q, w, ang_acc_body_rad_s2=wd, specific_force_body_m_s2=specific,
            height_agl_m=-pos[:, 2])

    # -- wind and surfaces ----------------------------------------------------

    def relative_wind(self, t_s: np.ndarray | float, true_wind_ned_m_s: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
        """(speed m/s (N,), beta deg (N,)) of the relative wind at times (N,)."""
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        rel_ned = np.asarray(true_wind_ned_m_s, dtype=float) - self.translational_velocity_ned(t)
        rel = np.einsum("nji,nj->ni", self.rotation_ship_to_ned(t), np.broadcast_to(
            rel_ned, (t.size, 3)))
        speed = np.hypot(rel[:, 0], rel[:, 1])
        beta = np.degrees(np.arctan2(-rel[:, 1], -rel[:, 0]))
        return speed, beta

    def true_wind_ned(self, relative_speed_m_s: float, relative_heading_deg: float) -> np.ndarray:
        """(3,) true wind giving this mean relative wind (level ship on its heading)."""
        beta = np.radians(relative_heading_deg)
        rel_ship = -relative_speed_m_s * np.array([np.cos(beta), np.sin(beta), 0.0])
        level = quat_to_dcm(euler_to_quat(np.array([0.0, 0.0, self._heading])))
        return self.config.speed_m_s * self._course + level @ rel_ship

    def height_above_surface(self, t_s: np.ndarray | float, p_ned_m: np.ndarray) -> np.ndarray:
        """(N,) height above what is below: the flight deck, the hangar roof, or the sea."""
        c = self.config
        p = np.atleast_2d(np.asarray(p_ned_m, dtype=float))
        s = self.ned_to_ship(t_s, p)
        over_deck = (s[:, 0] >= -c.deck_length_m) & (s[:, 0] < 0) & (
            np.abs(s[:, 1]) <= c.beam_m / 2)
        over_hangar = (s[:, 0] >= 0) & (s[:, 0] <= c.hangar_length_m) & (
            np.abs(s[:, 1]) <= c.hangar_width_m / 2)
        return np.where(over_deck, -s[:, 2],
                        np.where(over_hangar, -s[:, 2] - c.hangar_height_m, -p[:, 2]))
