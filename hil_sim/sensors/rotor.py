"""Rotor tachometer: IR reflections from the main-rotor blades (§5.2, TSMP6000 detector).

An IR emitter on the fuselage beams upward; each blade passing over it (blade azimuth
crossing `sensor_azimuth_rad`) reflects a pulse. Two blades give two pulses per
revolution; the rover measures the interval between consecutive pulses:

    rotor_speed = (2 pi / n_blades) / interval

Pulse instants come from the trajectory's unwrapped rotor azimuth (exact crossings
by interpolation), delayed by the detector's response, with timing jitter, occasional
missed pulses, a blade-spacing error (blades not exactly 180 deg apart, which makes
alternate intervals long/short) and the rover timer's tick.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hil_sim.sensors.config import check_finite, check_nonnegative, check_positive, check_range
from hil_sim.sensors.streams import EdgeStream
from hil_sim.world.kinematics import Trajectory


@dataclass(frozen=True)
class RotorTachConfig:
    n_blades: int = 2
    sensor_azimuth_rad: float = 0.0
    blade_spacing_error_rad: float = 0.0  # blade k sits at k*2pi/n + error*(k > 0)
    detector_delay_s: float = 100e-6  # TSMP6000 response delay (constant)
    jitter_s: float = 5e-6  # 1 sigma
    miss_probability: float = 0.0
    pulse_width_s: float = 300e-6  # detector output pulse (for the edge stream)
    timer_tick_s: float = 1.0 / 48e6  # rover input-capture clock (F_BUS 48 MHz)

    def __post_init__(self) -> None:
        if not (isinstance(self.n_blades, int) and self.n_blades >= 1):
            raise ValueError(f"n_blades = {self.n_blades!r}: must be an integer >= 1")
        check_finite("sensor_azimuth_rad", self.sensor_azimuth_rad)
        check_finite("blade_spacing_error_rad", self.blade_spacing_error_rad)
        check_nonnegative("detector_delay_s", self.detector_delay_s)
        check_nonnegative("jitter_s", self.jitter_s)
        check_range("miss_probability", self.miss_probability, 0.0, 1.0)
        check_positive("pulse_width_s", self.pulse_width_s)
        check_nonnegative("timer_tick_s", self.timer_tick_s)


@dataclass(frozen=True, eq=False)
class RotorPulses:
    """P detected pulses: `t_s` (P,) pulse (rising-edge) times, `blade` (P,) which blade;
    `rotor_speed_rad_s` (P-1,) the naive estimate from consecutive intervals, at
    `t_s[1:]` (what the rover computes; a missed pulse shows as a half-speed value)."""

    t_s: np.ndarray
    blade: np.ndarray
    rotor_speed_rad_s: np.ndarray

    def __len__(self) -> int:
        return self.t_s.size


def rotor_speed_from_pulses(t_s: np.ndarray, n_blades: int = 2) -> np.ndarray:
    """(P-1,) rotor speed from consecutive pulse intervals, rad/s."""
    return (2.0 * np.pi / n_blades) / np.diff(np.asarray(t_s, dtype=float))


class RotorTachometer:
    def __init__(self, config: RotorTachConfig | None = None, *, rng: np.random.Generator
                 ) -> None:
        self.config = config or RotorTachConfig()
        self.rng = rng

    def measure(self, trajectory: Trajectory) -> RotorPulses:
        c = self.config
        psi = trajectory.rotor_azimuth_rad
        if psi.size > 1 and np.any(np.diff(psi) < 0):
            raise ValueError("rotor_azimuth_rad must not decrease (unwrapped) for the tachometer")
        # A stopped rotor holds the azimuth constant; a vanishing ramp keeps the
        # crossing search well defined there without moving any crossing measurably.
        psi = psi + 1e-12 * np.arange(psi.size)
        spacing = 2.0 * np.pi / c.n_blades
        # Blade k is at psi + k*spacing (+ error for k > 0); it passes the sensor when
        # psi = sensor - k*spacing - err_k + 2 pi m.
        times: list[np.ndarray] = []
        blades: list[np.ndarray] = []
        for k in range(c.n_blades):
            offset = k * spacing + (c.blade_spacing_error_rad if k else 0.0)
            base = c.sensor_azimuth_rad - offset
            m0 = int(np.ceil((psi[0] - base) / (2 * np.pi)))
            m1 = int(np.floor((psi[-1] - base) / (2 * np.pi)))
            levels = base + 2 * np.pi * np.arange(m0, m1 + 1)
            times.append(np.interp(levels, psi, trajectory.t_s))
            blades.append(np.full(levels.size, k))
        t = np.concatenate(times)
        blade = np.concatenate(blades)
        order = np.argsort(t, kind="stable")
        t, blade = t[order], blade[order]
        t = t + c.detector_delay_s + self.rng.standard_normal(t.size) * c.jitter_s
        keep = self.rng.random(t.size) >= c.miss_probability
        t, blade = t[keep], blade[keep]
        if c.timer_tick_s > 0:
            t = np.round(t / c.timer_tick_s) * c.timer_tick_s
        order = np.argsort(t, kind="stable")
        t, blade = t[order], blade[order]
        return RotorPulses(t_s=t, blade=blade,
                           rotor_speed_rad_s=rotor_speed_from_pulses(t, c.n_blades))

    def stream(self, pulses: RotorPulses) -> EdgeStream:
        """Rising edge at each pulse, falling `pulse_width_s` later, on channel 0."""
        n = len(pulses)
        t = np.concatenate([pulses.t_s, pulses.t_s + self.config.pulse_width_s])
        up = np.concatenate([np.ones(n, bool), np.zeros(n, bool)])
        return EdgeStream(t, np.zeros(2 * n, dtype=np.int64), up)
