"""Indoor wind field: two opposing 24-inch fans at different heights (§3.4, §5.2 Fig 5.6).

Each fan is a round turbulent jet (self-similar far field, virtual origin chosen so the
centreline speed equals the exit speed at the fan):

    X = x + x0,  x0 = D / (2 S)      (x along the jet axis from the fan, D diameter,
                                      S = d r_half / dx the spreading rate)
    U_c = U0 x0 / X                  (centreline decay ~ 1/x; momentum conserved)
    u_x = U_c exp(-xi),  xi = ln2 (r / r_half)^2,  r_half = S X
    u_r = -(U_c / (2 X)) r [ (1 - e^-xi) / xi - 2 e^-xi ]   (continuity: spreading near
                                      the axis, entrainment inflow outside)
    u_theta = swirl U0 (x0 / X)^2 (r / r_half) exp(-xi)      (fan swirl, decays faster)

faded to zero within half a diameter behind the fan. The fans face each other
horizontally (fan A blows toward fan B and vice versa); their jets pass each other at
different heights and collide, the
superposition giving the shear and cancelling flow the reference mapped (7.24 m/s at
the source, model error 3-11 % of it, Fig 3.14-3.15).

Turbulence: each jet carries the frozen box advected along its own axis at
`convection_fraction * U0`, with sigma = TI U_c on a profile wider than the jet;
plus a small ambient sigma everywhere (a slowly drifting sample of the same box).

Evaluation: compiled (numba), one point at a time; the numpy version it replaced is the
tests' reference (tests/hil_sim/wind_reference.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numba
import numpy as np

from hil_sim.sensors.config import check_finite, check_nonnegative, check_positive, check_range
from hil_sim.world.turbulence import (
    FrozenTurbulence,
    TurbulenceConfig,
    advected_point,
)
from hil_sim.world.wind.base import WindField
from hil_sim.world.wind.simple import convection_frame

Vec3 = tuple[float, float, float]


def _fan_turbulence() -> TurbulenceConfig:
    return TurbulenceConfig(length_scale_m=0.5, grid_spacing_m=0.15, box_m=(48.0, 12.0, 12.0),
                            lateral_drift_m=3.0)


@dataclass(frozen=True)
class FansIndoorConfig:
    exit_speed_m_s: float = 7.24
    fan_diameter_m: float = 0.61
    fan_a_ned_m: Vec3 = (0.0, 0.0, -1.5)
    fan_b_ned_m: Vec3 = (7.0, 0.0, -2.5)
    spreading_rate: float = 0.10
    swirl_fraction: float = 0.3
    turbulence_intensity: float = 0.25
    ambient_sigma_m_s: float = 0.05
    convection_fraction: float = 0.4
    turbulence: TurbulenceConfig = field(default_factory=_fan_turbulence)

    def __post_init__(self) -> None:
        check_positive("exit_speed_m_s", self.exit_speed_m_s)
        check_positive("fan_diameter_m", self.fan_diameter_m)
        check_finite("fan_a_ned_m", self.fan_a_ned_m)
        check_finite("fan_b_ned_m", self.fan_b_ned_m)
        gap = np.hypot(self.fan_b_ned_m[0] - self.fan_a_ned_m[0],
                       self.fan_b_ned_m[1] - self.fan_a_ned_m[1])
        if gap < 2 * self.fan_diameter_m:
            raise ValueError(f"fan_b_ned_m = {self.fan_b_ned_m!r}: fans closer than two "
                             f"diameters horizontally ({gap:.2f} m)")
        check_range("spreading_rate", self.spreading_rate, 0.02, 0.3)
        check_nonnegative("swirl_fraction", self.swirl_fraction)
        check_nonnegative("turbulence_intensity", self.turbulence_intensity)
        check_nonnegative("ambient_sigma_m_s", self.ambient_sigma_m_s)
        check_positive("convection_fraction", self.convection_fraction)


class FanParams(NamedTuple):
    """What the compiled jets read (module doc)."""

    exit_speed: float  # U0
    diameter: float  # D
    x0: float  # virtual origin
    spreading_rate: float  # S
    swirl_fraction: float
    turbulence_intensity: float
    ambient_sigma: float
    convection_speed: float  # convection_fraction U0


_LN2 = math.log(2.0)
_AMBIENT_DRIFT_M_S = 0.3  # the ambient part's box drifts at this speed


@numba.njit(cache=True, error_model="numpy")
def _jet(p: FanParams, origin: np.ndarray, axis: np.ndarray, px: float, py: float,
         pz: float) -> tuple[float, float, float, float, float]:
    """One jet at a point: the faded mean velocity (3), the faded centreline speed and
    xi (module doc)."""
    rx, ry, rz = px - origin[0], py - origin[1], pz - origin[2]
    x = rx * axis[0] + ry * axis[1] + rz * axis[2]
    qx, qy, qz = rx - x * axis[0], ry - x * axis[1], rz - x * axis[2]  # radial vector
    r = math.sqrt(qx * qx + qy * qy + qz * qz)
    big_x = max(x + p.x0, 0.5 * p.x0)
    # Full strength from the fan plane on, gone half a diameter behind the fan.
    fade = 0.5 * (1.0 + math.tanh((x + 0.25 * p.diameter) / (0.08 * p.diameter)))
    u_c = p.exit_speed * p.x0 / big_x
    r_half = p.spreading_rate * big_x
    xi = _LN2 * (r / r_half) ** 2
    e = math.exp(-xi)
    frac = -math.expm1(-xi) / xi if xi > 1e-9 else 1.0 - xi / 2  # (1 - e^-xi) / xi
    u_x = u_c * e
    u_r_over_r = -(u_c / (2.0 * big_x)) * (frac - 2.0 * e)
    swirl = (p.swirl_fraction * p.exit_speed * (p.x0 / big_x) ** 2 / r_half) * e
    # u_r r_hat = (u_r / r) radial; u_theta theta_hat = (u_theta / r) (axis x radial)
    cx = axis[1] * qz - axis[2] * qy
    cy = axis[2] * qx - axis[0] * qz
    cz = axis[0] * qy - axis[1] * qx
    return ((u_x * axis[0] + u_r_over_r * qx + swirl * cx) * fade,
            (u_x * axis[1] + u_r_over_r * qy + swirl * cy) * fade,
            (u_x * axis[2] + u_r_over_r * qz + swirl * cz) * fade, u_c * fade, xi)


@numba.njit(cache=True, error_model="numpy")
def _jet_rows(p, origin, axis, pos, out):
    for i in range(pos.shape[0]):
        out[i, 0], out[i, 1], out[i, 2], out[i, 3], out[i, 4] = _jet(
            p, origin, axis, pos[i, 0], pos[i, 1], pos[i, 2])


@numba.njit(cache=True, error_model="numpy")
def _velocity_rows(t, pos, turbulence, p, fans, frames, offsets, box, out):
    """Both jets and their turbulence, plus the ambient part. fans (2, 2, 3): origin
    and axis per fan; frames (2, 3, 3): the box axes (rows) per jet in NED; offsets
    (3, 3): where each jet and the ambient part sample the box."""
    for i in range(t.shape[0]):
        px, py, pz = pos[i, 0], pos[i, 1], pos[i, 2]
        vx = vy = vz = 0.0
        for f in range(2):
            ux, uy, uz, u_c, xi = _jet(p, fans[f, 0], fans[f, 1], px, py, pz)
            vx += ux
            vy += uy
            vz += uz
            if turbulence and p.turbulence_intensity > 0:
                a = frames[f]
                rx, ry, rz = px - fans[f, 0, 0], py - fans[f, 0, 1], pz - fans[f, 0, 2]
                lx = rx * a[0, 0] + ry * a[0, 1] + rz * a[0, 2] + offsets[f, 0]
                ly = rx * a[1, 0] + ry * a[1, 1] + rz * a[1, 2] + offsets[f, 1]
                lz = rx * a[2, 0] + ry * a[2, 1] + rz * a[2, 2] + offsets[f, 2]
                fx, fy, fz = advected_point(box, lx, ly, lz, t[i], p.convection_speed)
                sigma = p.turbulence_intensity * u_c * math.exp(-xi / 2.25)
                vx += sigma * (fx * a[0, 0] + fy * a[1, 0] + fz * a[2, 0])
                vy += sigma * (fx * a[0, 1] + fy * a[1, 1] + fz * a[2, 1])
                vz += sigma * (fx * a[0, 2] + fy * a[1, 2] + fz * a[2, 2])
        if turbulence and p.ambient_sigma > 0:
            fx, fy, fz = advected_point(box, px + offsets[2, 0], py + offsets[2, 1],
                                        pz + offsets[2, 2], t[i], _AMBIENT_DRIFT_M_S)
            vx += p.ambient_sigma * fx
            vy += p.ambient_sigma * fy
            vz += p.ambient_sigma * fz
        out[i, 0], out[i, 1], out[i, 2] = vx, vy, vz


class FansIndoor(WindField):
    kind = "fans_indoor"

    def __init__(self, config: FansIndoorConfig, rng: np.random.Generator) -> None:
        self.config = config
        c = config
        a = np.asarray(c.fan_a_ned_m, dtype=float)
        b = np.asarray(c.fan_b_ned_m, dtype=float)
        d = b - a
        d[2] = 0.0
        d /= np.linalg.norm(d)
        self.fans = ((a, d), (b, -d))
        self.frames = tuple(convection_frame(axis) for _, axis in self.fans)
        self.x0 = c.fan_diameter_m / (2.0 * c.spreading_rate)
        self._box = FrozenTurbulence(c.turbulence, rng)
        # Where each jet (and the ambient part) samples the shared box: far apart.
        box = np.asarray(c.turbulence.box_m)
        self._box_offsets = (np.zeros(3), box * np.array([0.5, 0.5, 0.0]),
                             box * np.array([0.25, 0.0, 0.5]))
        self._params = FanParams(*(float(v) for v in (
            c.exit_speed_m_s, c.fan_diameter_m, self.x0, c.spreading_rate, c.swirl_fraction,
            c.turbulence_intensity, c.ambient_sigma_m_s,
            c.convection_fraction * c.exit_speed_m_s)))
        self._fan_rows = np.array([[o, ax] for o, ax in self.fans])
        self._frame_rows = np.array(self.frames)
        self._offset_rows = np.array(self._box_offsets)

    def _jet(self, pos: np.ndarray, fan: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mean velocity (N, 3), centreline speed (N,) and xi (N,) of one jet, faded."""
        pos = np.ascontiguousarray(pos, dtype=float)
        out = np.empty((pos.shape[0], 5))
        _jet_rows(self._params, self._fan_rows[fan, 0], self._fan_rows[fan, 1], pos, out)
        return out[:, :3], out[:, 3], out[:, 4]

    def _velocity(self, t, pos, unsteady, turbulence):
        out = np.empty((t.shape[0], 3))
        _velocity_rows(t, np.ascontiguousarray(pos), bool(turbulence), self._params,
                       self._fan_rows, self._frame_rows, self._offset_rows, self._box.grid, out)
        return out
