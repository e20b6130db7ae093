"""The helicopter's rigging: RC pulse widths -> blade-pitch commands.

    blade_pitch_rad = offset_rad[c] + gain_rad_per_us[c] * (width_us - center_us[c])

per RC channel c = 1..4 (docs/sensors.md, "RC pilot inputs"):

    ch1 aileron    -> lateral cyclic        delta_lat_rad   2.793e-4 rad/us, +-8 deg
    ch2 elevator   -> longitudinal cyclic   delta_lon_rad   2.793e-4 rad/us, +-8 deg
    ch3 collective -> collective            delta_col_rad   0.07854 + 2.618e-4 rad/us (-3..+12 deg)
    ch4 rudder     -> tail-rotor pitch      delta_ped_rad   6.981e-4 rad/us, +-20 deg
    ch5 aux        -> heading-hold gyro gain (no blade pitch)

The rigging is a property of the helicopter, so it lives in the host; the numbers are
the simulator's `hil_sim.sensors.rc.PwmMapping` defaults (a T-Rex 600 class set-up),
which should import this module instead of defining its own copy.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from airwake.errors import AirwakeError

# Output column order of `pwm_to_blade_pitch`.
BLADE_PITCH_COLUMNS = ("delta_col_rad", "delta_lat_rad", "delta_lon_rad", "delta_ped_rad")
# Blade-pitch column (index into BLADE_PITCH_COLUMNS) driven by RC channels 1..4.
CHANNEL_SOURCE = (1, 2, 0, 3)

Vec4 = tuple[float, float, float, float]


class RiggingError(AirwakeError):
    """A rigging with unusable numbers (the field and value are named)."""


@dataclass(frozen=True)
class PwmRigging:
    """Linear pulse-width -> blade-pitch map of RC channels 1..4 (see module doc)."""

    center_us: Vec4 = (1500.0, 1500.0, 1500.0, 1500.0)
    gain_rad_per_us: Vec4 = (2.793e-4, 2.793e-4, 2.618e-4, 6.981e-4)
    offset_rad: Vec4 = (0.0, 0.0, 0.07854, 0.0)

    def __post_init__(self) -> None:
        for name in ("center_us", "gain_rad_per_us", "offset_rad"):
            v = np.asarray(getattr(self, name), dtype=float)
            if v.shape != (4,) or not np.all(np.isfinite(v)):
                raise RiggingError(f"rigging {name} = {getattr(self, name)!r}: "
                                   "need 4 finite numbers (RC channels 1..4)")
        if any(g == 0 for g in self.gain_rad_per_us):
            raise RiggingError(f"rigging gain_rad_per_us = {self.gain_rad_per_us!r}: "
                               "gains must be non-zero")

    def to_dict(self) -> dict:
        return {k: list(v) for k, v in asdict(self).items()}

    @classmethod
    def from_dict(cls, d: dict) -> PwmRigging:
        return cls(**{k: tuple(float(x) for x in v) for k, v in d.items()})

    def pwm_to_blade_pitch(self, pwm_us: np.ndarray) -> np.ndarray:
        """(N, >=4) widths of RC channels 1..4(..5), us -> (N, 4) `[col, lat, lon, ped]` rad."""
        w = np.atleast_2d(np.asarray(pwm_us, dtype=float))[:, :4]
        by_channel = np.asarray(self.offset_rad) + np.asarray(self.gain_rad_per_us) * (
            w - np.asarray(self.center_us))
        out = np.empty_like(by_channel)
        out[:, list(CHANNEL_SOURCE)] = by_channel
        return out

    def blade_pitch_to_pwm(self, blade_pitch_rad: np.ndarray) -> np.ndarray:
        """(N, 4) `[col, lat, lon, ped]` rad -> (N, 4) widths of RC channels 1..4, us."""
        bp = np.atleast_2d(np.asarray(blade_pitch_rad, dtype=float))
        src = bp[:, list(CHANNEL_SOURCE)]
        return np.asarray(self.center_us) + (src - np.asarray(self.offset_rad)) / np.asarray(
            self.gain_rad_per_us)


DEFAULT_RIGGING = PwmRigging()
