"""Ultrasonic anemometer (Young 81000 class) sampling a wind field from a moving mount.

Measured at `rate_hz` (default 100 Hz, the rate §3.4 recorded it at; the 81000
samples internally at 160 Hz): the air velocity *relative to the sensor* in the
sensor's own frame, so a moving mount (a pole on casters, a tracked marker) adds its
own motion — exactly what the host's motion compensation must remove (§3.4):

    w_meas = R_sensor^T (w_field(p_sensor, t) - v_sensor) * (1 + gain_error) + offset
             + noise,   quantised to 0.01 m/s

and the sonic temperature (0.01 C resolution, +-2 C accuracy as an offset).
Datasheet: range 0-40 m/s, resolution 0.01 m/s, accuracy +-1 % rms +-0.05 m/s.

Sensor frame: the mount's frame (FRD-like, z down) from the trajectory given (use
`Trajectory.at_point(r, mount_quat)` for the anemometer's own axes).

Streams: `ascii_stream` — serial lines "U V W T\\r\\n" (the 81000's custom ASCII
output; U, V along the sensor's x and y, W positive *upward* as Young reports it,
i.e. W = -w_z), and `analog_codes` — the four 0-5000 mV voltage outputs (12-bit) the
reference's microcontroller sampled: wind components over +-`analog_range_m_s`,
temperature over -50..+50 C.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hil_sim.sensors.config import check_finite, check_nonnegative, check_positive
from hil_sim.sensors.noise import quantize
from hil_sim.sensors.streams import ByteStream, sample_times
from hil_sim.world.kinematics import Trajectory, rotate_inverse

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class AnemometerConfig:
    rate_hz: float = 100.0
    noise_m_s: float = 0.02  # 1 sigma per component per sample
    gain_error: Vec3 = (0.0, 0.0, 0.0)  # fractional, per axis (datasheet: ~1 %)
    offset_m_s: Vec3 = (0.0, 0.0, 0.0)
    resolution_m_s: float = 0.01
    air_temperature_c: float = 20.0
    temperature_offset_c: float = 0.0
    temperature_noise_c: float = 0.05
    resolution_c: float = 0.01
    analog_range_m_s: float = 20.0
    phase_s: float = 0.0
    clock_ppm: float = 0.0
    baud: int = 38400

    def __post_init__(self) -> None:
        check_positive("rate_hz", self.rate_hz)
        check_nonnegative("noise_m_s", self.noise_m_s)
        check_finite("gain_error", self.gain_error)
        check_finite("offset_m_s", self.offset_m_s)
        check_nonnegative("resolution_m_s", self.resolution_m_s)
        check_finite("air_temperature_c", self.air_temperature_c)
        check_finite("temperature_offset_c", self.temperature_offset_c)
        check_nonnegative("temperature_noise_c", self.temperature_noise_c)
        check_nonnegative("resolution_c", self.resolution_c)
        check_positive("analog_range_m_s", self.analog_range_m_s)
        check_positive("baud", self.baud)
        if 32 * 10 * self.rate_hz > self.baud:
            raise ValueError(f"baud = {self.baud!r}: too slow for ~32-byte lines at "
                             f"{self.rate_hz} Hz")


@dataclass(frozen=True, eq=False)
class AnemometerSamples:
    """K samples: `t_s` (K,); `wind_sensor_m_s` (K, 3) relative air velocity, sensor
    frame (x, y, z down); `sonic_temperature_c` (K,); truth: `wind_ned_m_s` (K, 3) the
    field's air velocity at the sensor and `sensor_vel_ned_m_s` (K, 3) the mount's."""

    t_s: np.ndarray
    wind_sensor_m_s: np.ndarray
    sonic_temperature_c: np.ndarray
    wind_ned_m_s: np.ndarray
    sensor_vel_ned_m_s: np.ndarray

    def __len__(self) -> int:
        return self.t_s.size


class Anemometer:
    def __init__(self, config: AnemometerConfig | None = None, *, rng: np.random.Generator
                 ) -> None:
        self.config = config or AnemometerConfig()
        self.rng = rng

    def measure(self, trajectory: Trajectory, wind_field) -> AnemometerSamples:
        """`trajectory`: the sensor's own kinematics; `wind_field`: any `WindField`."""
        c = self.config
        t = sample_times(trajectory.t_s[0], trajectory.t_s[-1], c.rate_hz, c.phase_s,
                         c.clock_ppm)
        truth = trajectory.at(t)
        wind = wind_field.velocity_ned(t, truth.pos_ned_m)
        relative = rotate_inverse(truth.quat_wxyz, wind - truth.vel_ned_m_s)
        meas = relative * (1.0 + np.asarray(c.gain_error)) + np.asarray(c.offset_m_s)
        meas = meas + c.noise_m_s * self.rng.standard_normal(meas.shape)
        temp = (c.air_temperature_c + c.temperature_offset_c
                + c.temperature_noise_c * self.rng.standard_normal(t.size))
        return AnemometerSamples(
            t_s=t,
            wind_sensor_m_s=quantize(meas, c.resolution_m_s),
            sonic_temperature_c=quantize(temp, c.resolution_c),
            wind_ned_m_s=wind,
            sensor_vel_ned_m_s=truth.vel_ned_m_s,
        )

    def stream(self, samples: AnemometerSamples) -> ByteStream:
        """The serial output (same as `ascii_stream`)."""
        return self.ascii_stream(samples)

    def ascii_stream(self, samples: AnemometerSamples) -> ByteStream:
        """Serial lines `U V W T` (W up), one per sample."""
        w = samples.wind_sensor_m_s
        lines = [
            f"{u:7.2f} {v:7.2f} {-wz:7.2f} {tc:7.2f}\r\n".encode("ascii")
            for u, v, wz, tc in zip(w[:, 0], w[:, 1], w[:, 2], samples.sonic_temperature_c,
                                    strict=True)
        ]
        return ByteStream.from_chunks(samples.t_s, lines, self.config.baud)

    def analog_codes(self, samples: AnemometerSamples) -> np.ndarray:
        """(K, 4) 12-bit codes of the 0-5000 mV outputs: U, V, W (up), T."""
        rng_m_s = self.config.analog_range_m_s
        w = samples.wind_sensor_m_s * np.array([1.0, 1.0, -1.0])
        frac_wind = (np.clip(w, -rng_m_s, rng_m_s) + rng_m_s) / (2 * rng_m_s)
        frac_temp = (np.clip(samples.sonic_temperature_c, -50.0, 50.0) + 50.0) / 100.0
        frac = np.concatenate([frac_wind, frac_temp[:, None]], axis=1)
        return np.rint(frac * 4095).astype(np.uint16)


def parse_ascii_lines(data: bytes) -> np.ndarray:
    """(K, 4) `[U, V, W_up, T]` from the ASCII stream (reference decoder for tests)."""
    rows = [list(map(float, line.split())) for line in data.decode("ascii").splitlines()
            if line.strip()]
    return np.asarray(rows, dtype=float).reshape(-1, 4)
