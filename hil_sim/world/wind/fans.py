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
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hil_sim.sensors.config import check_finite, check_nonnegative, check_positive, check_range
from hil_sim.world.turbulence import FrozenTurbulence, TurbulenceConfig
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

    def _jet(self, pos: np.ndarray, fan: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mean velocity (N, 3), centreline speed (N,), xi (N,) and fade for one jet."""
        c = self.config
        origin, axis = self.fans[fan]
        rel = pos - origin
        x = rel @ axis
        radial = rel - np.outer(x, axis)
        r = np.linalg.norm(radial, axis=1)
        big_x = np.maximum(x + self.x0, 0.5 * self.x0)
        # Full strength from the fan plane on, gone half a diameter behind the fan.
        fade = 0.5 * (1.0 + np.tanh((x + 0.25 * c.fan_diameter_m) / (0.08 * c.fan_diameter_m)))
        u_c = c.exit_speed_m_s * self.x0 / big_x
        r_half = c.spreading_rate * big_x
        xi = np.log(2.0) * (r / r_half) ** 2
        e = np.exp(-xi)
        safe_xi = np.where(xi > 1e-9, xi, 1.0)
        frac = np.where(xi > 1e-9, -np.expm1(-xi) / safe_xi, 1.0 - xi / 2)
        u_x = u_c * e
        u_r_over_r = -(u_c / (2.0 * big_x)) * (frac - 2.0 * e)
        swirl = (c.swirl_fraction * c.exit_speed_m_s * (self.x0 / big_x) ** 2 / r_half) * e
        # u_r r_hat = (u_r / r) radial; u_theta theta_hat = (u_theta / r) (axis x radial)
        vel = (np.outer(u_x, axis) + u_r_over_r[:, None] * radial
               + swirl[:, None] * np.cross(axis, radial))
        return vel * fade[:, None], u_c * fade, xi

    def _velocity(self, t, pos, unsteady, turbulence):
        c = self.config
        out = np.zeros_like(pos)
        for fan in (0, 1):
            vel, u_c, xi = self._jet(pos, fan)
            out += vel
            if turbulence and c.turbulence_intensity > 0:
                axes = self.frames[fan]
                local = (pos - self.fans[fan][0]) @ axes.T + self._box_offsets[fan]
                fluct = self._box.advected(local, t, c.convection_fraction * c.exit_speed_m_s)
                sigma = c.turbulence_intensity * u_c * np.exp(-xi / 2.25)
                out += sigma[:, None] * (fluct @ axes)
        if turbulence and c.ambient_sigma_m_s > 0:
            fluct = self._box.advected(pos + self._box_offsets[2], t, 0.3)
            out += c.ambient_sigma_m_s * fluct
        return out
