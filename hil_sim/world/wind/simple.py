"""Still air, and a uniform wind with optional frozen turbulence."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hil_sim.sensors.config import check_finite, check_nonnegative
from hil_sim.world.turbulence import FrozenTurbulence, TurbulenceConfig
from hil_sim.world.wind.base import WindField


@dataclass(frozen=True)
class StillAirConfig:
    """No settings: the air is at rest everywhere."""


class StillAir(WindField):
    """Zero wind (the calibration-flight hall with the fans off)."""

    kind = "still_air"

    def __init__(self, config: StillAirConfig | None = None) -> None:
        self.config = config or StillAirConfig()

    def _velocity(self, t, pos, unsteady, turbulence):
        return np.zeros((pos.shape[0], 3))


def convection_frame(direction: np.ndarray) -> np.ndarray:
    """(3, 3) rows e_s (along `direction`, horizontal part), e_n, e_up-ish: the turbulence
    box axes in NED. A zero direction gives the north-aligned frame."""
    d = np.asarray(direction, dtype=float).copy()
    d[2] = 0.0
    norm = np.linalg.norm(d)
    e_s = d / norm if norm > 1e-9 else np.array([1.0, 0.0, 0.0])
    e_z = np.array([0.0, 0.0, 1.0])
    e_n = np.cross(e_z, e_s)
    return np.stack([e_s, e_n, e_z])


@dataclass(frozen=True)
class UniformWindConfig:
    """A uniform mean wind plus isotropic frozen turbulence advected with it.

    Turbulence std per component: `turbulence_intensity * |velocity| +
    turbulence_sigma_m_s` (intensity = std / mean speed).
    """

    velocity_ned_m_s: tuple[float, float, float] = (0.0, 0.0, 0.0)
    turbulence_intensity: float = 0.0
    turbulence_sigma_m_s: float = 0.0
    turbulence: TurbulenceConfig = field(default_factory=TurbulenceConfig)

    def __post_init__(self) -> None:
        check_finite("velocity_ned_m_s", self.velocity_ned_m_s)
        check_nonnegative("turbulence_intensity", self.turbulence_intensity)
        check_nonnegative("turbulence_sigma_m_s", self.turbulence_sigma_m_s)

    @property
    def sigma_m_s(self) -> float:
        speed = float(np.linalg.norm(self.velocity_ned_m_s))
        return self.turbulence_intensity * speed + self.turbulence_sigma_m_s


class UniformWind(WindField):
    kind = "uniform"

    def __init__(self, config: UniformWindConfig, rng: np.random.Generator) -> None:
        self.config = config
        self._mean = np.asarray(config.velocity_ned_m_s, dtype=float)
        self._sigma = config.sigma_m_s
        self._axes = convection_frame(self._mean)
        self._speed = float(np.linalg.norm(self._mean[:2]))
        self._box = FrozenTurbulence(config.turbulence, rng) if self._sigma > 0 else None

    def _velocity(self, t, pos, unsteady, turbulence):
        out = np.broadcast_to(self._mean, pos.shape).copy()
        if turbulence and self._box is not None:
            local = pos @ self._axes.T
            fluct = self._box.advected(local, t, self._speed)
            out += self._sigma * (fluct @ self._axes)
        return out
