"""RC pilot inputs and the tail-servo command as PWM pulse widths and edges.

RC receiver (read by the base board): 5 channels, one pulse per channel per frame
(default 50 Hz), 1000-2000 us. Channel order (1-based, as on the receiver):

    ch1 aileron  -> lateral cyclic       delta_lat_rad
    ch2 elevator -> longitudinal cyclic  delta_lon_rad
    ch3 collective                       delta_col_rad
    ch4 rudder   -> tail-rotor pitch     delta_ped_rad
    ch5 aux      -> heading-hold gyro gain (no blade pitch)

Mapping (linear, per channel c = 1..4; `PwmMapping`):

    blade_pitch_rad = offset_rad[c] + gain_rad_per_us[c] * (width_us - center_us[c])

Defaults (T-Rex 600 class set-up): cyclic +-8 deg over +-500 us (2.793e-4 rad/us),
collective -3..+12 deg over 1000..2000 us (2.618e-4 rad/us, 4.5 deg at 1500 us), tail
pitch +-20 deg over +-500 us (6.981e-4 rad/us). `blade_pitch_to_pwm` is the forward
map the simulator uses, `pwm_to_blade_pitch` the inverse the flight-table builders use.
Blade-pitch arrays are ordered `[col, lat, lon, ped]`
(`airwake.record.rigging.BLADE_PITCH_COLUMNS`).

Tail servo (measured by the rover): the heading-hold gyro's command to the tail servo,
one channel, default 333 Hz frames centred at 1520 us (`TailServoConfig`).

Measured values = pulse widths per frame (quantised to the receiver's resolution);
stream = rising/falling edge times per channel (`EdgeStream`), with edge jitter and
optional glitches (spurious short pulses) and dropped pulses.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from airwake.record.rigging import PwmRigging, RiggingError

from hil_sim.sensors.config import (
    check_choice,
    check_finite,
    check_nonnegative,
    check_positive,
    check_range,
)
from hil_sim.sensors.noise import quantize
from hil_sim.sensors.streams import EdgeStream, sample_times
from hil_sim.world.kinematics import Trajectory

RC_CHANNEL_NAMES = ("aileron", "elevator", "collective", "rudder", "aux")


@dataclass(frozen=True)
class PwmMapping(PwmRigging):
    """The helicopter's rigging (`airwake.record.rigging.PwmRigging`, the single source of
    the pulse-width <-> blade-pitch numbers) plus the transmitter's end points."""

    min_us: float = 1000.0
    max_us: float = 2000.0

    def __post_init__(self) -> None:
        try:
            super().__post_init__()
        except RiggingError as exc:
            raise ValueError(str(exc)) from None
        if not self.min_us < self.max_us:
            raise ValueError(f"min_us = {self.min_us!r}, max_us = {self.max_us!r}: need min < max")


def blade_pitch_to_pwm(
    blade_pitch_rad: np.ndarray, mapping: PwmMapping | None = None, aux_us: float = 1700.0
) -> np.ndarray:
    """(N, 4) `[col, lat, lon, ped]` rad -> (N, 5) pulse widths us for channels 1..5.

    Widths outside `[min_us, max_us]` are clipped (the transmitter's end points).
    """
    m = mapping or PwmMapping()
    width = np.clip(m.blade_pitch_to_pwm(blade_pitch_rad), m.min_us, m.max_us)
    aux = np.full((width.shape[0], 1), float(np.clip(aux_us, m.min_us, m.max_us)))
    return np.concatenate([width, aux], axis=1)


def pwm_to_blade_pitch(pwm_us: np.ndarray, mapping: PwmMapping | None = None) -> np.ndarray:
    """(N, >=4) widths of RC channels 1..4(..5) in us -> (N, 4) `[col, lat, lon, ped]` rad."""
    return (mapping or PwmMapping()).pwm_to_blade_pitch(pwm_us)


# ---------------------------------------------------------------------------
# Pulse trains
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class PulseTrainConfig:
    """Timing and impairments of a PWM output (receiver or gyro)."""

    frame_rate_hz: float = 50.0
    phase_s: float = 0.0037  # first frame start on the device clock
    resolution_us: float = 1.0  # width quantum of the device's timer
    jitter_us: float = 0.3  # 1 sigma edge-time jitter
    layout: str = "sequential"  # channels back to back ("sequential") or all at frame start
    glitch_probability: float = 0.0  # per channel per frame: spurious 2-50 us pulse
    dropout_probability: float = 0.0  # per channel per frame: pulse missing

    def __post_init__(self) -> None:
        check_positive("frame_rate_hz", self.frame_rate_hz)
        check_nonnegative("phase_s", self.phase_s)
        check_nonnegative("resolution_us", self.resolution_us)
        check_nonnegative("jitter_us", self.jitter_us)
        check_choice("layout", self.layout, ("sequential", "simultaneous"))
        check_range("glitch_probability", self.glitch_probability, 0.0, 1.0)
        check_range("dropout_probability", self.dropout_probability, 0.0, 1.0)


@dataclass(frozen=True, eq=False)
class PwmSamples:
    """K frames: `t_s` (K,) frame start (simulation time), `width_us` (K, C) pulse widths."""

    t_s: np.ndarray
    width_us: np.ndarray

    def __len__(self) -> int:
        return self.t_s.size


def pulse_edges(
    samples: PwmSamples, timing: PulseTrainConfig, rng: np.random.Generator
) -> EdgeStream:
    """Edges of every channel's pulses, with jitter, glitches and dropouts (vectorised)."""
    k, n_ch = samples.width_us.shape
    width_s = samples.width_us * 1e-6
    if timing.layout == "sequential":
        starts = samples.t_s[:, None] + np.concatenate(
            [np.zeros((k, 1)), np.cumsum(width_s, axis=1)[:, :-1]], axis=1)
    else:
        starts = np.broadcast_to(samples.t_s[:, None], (k, n_ch))
    ends = starts + width_s
    jitter = timing.jitter_us * 1e-6
    rise = starts + rng.standard_normal((k, n_ch)) * jitter
    fall = ends + rng.standard_normal((k, n_ch)) * jitter
    keep = rng.random((k, n_ch)) >= timing.dropout_probability
    channel = np.broadcast_to(np.arange(n_ch), (k, n_ch))
    t = [rise[keep], fall[keep]]
    ch = [channel[keep], channel[keep]]
    up = [np.ones(keep.sum(), bool), np.zeros(keep.sum(), bool)]
    glitch = rng.random((k, n_ch)) < timing.glitch_probability
    if np.any(glitch):
        # A spurious pulse in the channel's low time: after this frame's pulse, before
        # the next frame's (the period minus the pulse leaves at least ~15 ms at 50 Hz).
        period = 1.0 / timing.frame_rate_hz
        g_start = ends[glitch] + rng.uniform(0.2, 0.6, glitch.sum()) * (period - width_s[glitch])
        g_width = rng.uniform(2e-6, 50e-6, glitch.sum())
        t += [g_start, g_start + g_width]
        ch += [channel[glitch], channel[glitch]]
        up += [np.ones(glitch.sum(), bool), np.zeros(glitch.sum(), bool)]
    return EdgeStream(np.concatenate(t), np.concatenate(ch), np.concatenate(up))


# ---------------------------------------------------------------------------
# Devices
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class RcConfig:
    """RC receiver: pulse timing, the blade-pitch mapping, and the aux channel setting."""

    timing: PulseTrainConfig = field(default_factory=PulseTrainConfig)
    mapping: PwmMapping = field(default_factory=PwmMapping)
    aux_us: float = 1700.0  # heading-hold gyro gain switch (> 1500 us: heading hold)

    def __post_init__(self) -> None:
        check_range("aux_us", self.aux_us, self.mapping.min_us, self.mapping.max_us)
        if self.timing.frame_rate_hz < 45.0:
            raise ValueError(
                f"timing.frame_rate_hz = {self.timing.frame_rate_hz!r}: RC frames must be >= 45 Hz")
        if (self.timing.layout == "sequential"
                and 5 * self.mapping.max_us * 1e-6 >= 1.0 / self.timing.frame_rate_hz):
            raise ValueError(
                f"timing.frame_rate_hz = {self.timing.frame_rate_hz!r}: 5 sequential pulses of "
                f"up to {self.mapping.max_us} us do not fit in one frame")


class RcReceiver:
    """The pilot's RC receiver outputs, from the trajectory's blade-pitch commands."""

    def __init__(self, config: RcConfig | None = None, *, rng: np.random.Generator) -> None:
        self.config = config or RcConfig()
        self.rng = rng

    def measure(self, trajectory: Trajectory, commands_rad: np.ndarray | None = None
                ) -> PwmSamples:
        """Pulse widths (K, 5) per frame; commands sampled (held) at each frame start.

        `commands_rad` (N, 4) `[col, lat, lon, ped]` at the trajectory's times
        overrides `trajectory.blade_pitch_rad` (e.g. the pilot's stick before the
        heading-hold gyro, when the world models one).
        """
        c = self.config
        t = sample_times(trajectory.t_s[0], trajectory.t_s[-1], c.timing.frame_rate_hz,
                         c.timing.phase_s)
        if commands_rad is None:
            cmd = trajectory.at(t).blade_pitch_rad
        else:
            cmd_all = np.asarray(commands_rad, dtype=float)
            cmd = np.stack([np.interp(t, trajectory.t_s, cmd_all[:, j]) for j in range(4)], -1)
        width = blade_pitch_to_pwm(cmd, c.mapping, c.aux_us)
        return PwmSamples(t_s=t, width_us=quantize(width, c.timing.resolution_us))

    def stream(self, samples: PwmSamples) -> EdgeStream:
        return pulse_edges(samples, self.config.timing, self.rng)


@dataclass(frozen=True)
class TailServoConfig:
    """Heading-hold gyro -> tail servo PWM: tail pitch = offset + gain * (width - center)."""

    timing: PulseTrainConfig = field(
        default_factory=lambda: PulseTrainConfig(frame_rate_hz=333.0, phase_s=0.0011,
                                                 resolution_us=0.5, jitter_us=0.2))
    center_us: float = 1520.0
    gain_rad_per_us: float = 6.981e-4
    offset_rad: float = 0.0
    min_us: float = 1000.0
    max_us: float = 2040.0

    def __post_init__(self) -> None:
        check_finite("center_us", self.center_us)
        check_finite("offset_rad", self.offset_rad)
        if not np.isfinite(self.gain_rad_per_us) or self.gain_rad_per_us == 0:
            raise ValueError(f"gain_rad_per_us = {self.gain_rad_per_us!r}: must be finite, != 0")
        if self.max_us * 1e-6 >= 1.0 / self.timing.frame_rate_hz:
            raise ValueError(f"max_us = {self.max_us!r}: longer than a frame")

    def pitch_to_pwm(self, tail_pitch_rad: np.ndarray) -> np.ndarray:
        w = self.center_us + (np.asarray(tail_pitch_rad, float) - self.offset_rad) / (
            self.gain_rad_per_us)
        return np.clip(w, self.min_us, self.max_us)

    def pwm_to_pitch(self, width_us: np.ndarray) -> np.ndarray:
        return self.offset_rad + self.gain_rad_per_us * (np.asarray(width_us, float)
                                                         - self.center_us)


class TailServoPwm:
    """The tail-servo command the rover measures, from `blade_pitch_rad[:, 3]` (ped)."""

    def __init__(self, config: TailServoConfig | None = None, *, rng: np.random.Generator
                 ) -> None:
        self.config = config or TailServoConfig()
        self.rng = rng

    def measure(self, trajectory: Trajectory) -> PwmSamples:
        c = self.config
        t = sample_times(trajectory.t_s[0], trajectory.t_s[-1], c.timing.frame_rate_hz,
                         c.timing.phase_s)
        width = c.pitch_to_pwm(trajectory.at(t).blade_pitch_rad[:, 3])
        return PwmSamples(t_s=t, width_us=quantize(width, c.timing.resolution_us)[:, None])

    def stream(self, samples: PwmSamples) -> EdgeStream:
        return pulse_edges(samples, self.config.timing, self.rng)
