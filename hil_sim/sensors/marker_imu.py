"""The active marker's 9-axis IMU (MPU-9250 + its AK8963 magnetometer), default 450 Hz.

Measured, in the marker frame (= the MPU-9250's accelerometer/gyro axes):
- gyro (rad/s) and accelerometer (specific force, m/s^2): truth + the shared IMU error
  model with MPU-9250 datasheet noise and a turn-on gyro bias the marker firmware must
  estimate (§3.3.1.4);
- magnetometer (uT): Earth's field rotated into the marker frame + hard-iron offset +
  noise, updated at `mag_rate_hz` (AK8963 continuous mode 2 = 100 Hz) and held between
  updates, as the register read shows it;
- die temperature.

Stream: what the marker firmware reads over I2C/SPI per sample — a 21-byte block:
MPU-9250 registers 0x3B..0x48 (ACCEL_X/Y/Z, TEMP, GYRO_X/Y/Z; int16 big-endian) then
AK8963 0x03..0x09 (HXL..HZH int16 little-endian, ST2). Scales: +-8 g -> 4096 LSB/g,
+-2000 deg/s -> 16.4 LSB/(deg/s), TEMP_degC = raw / 333.87 + 21, magnetometer
0.15 uT/LSB (16-bit). The AK8963's axes differ from the MPU's: x_ak = y, y_ak = x,
z_ak = -z (MPU-9250 datasheet, Fig. "orientation of axes"). Out-of-range values clip
to the int16 limits; a magnetometer overflow sets ST2.HOFL.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hil_sim.sensors.config import check_finite, check_nonnegative, check_positive
from hil_sim.sensors.imu import ImuErrors, ImuNoiseConfig, imu_errors
from hil_sim.sensors.streams import ByteStream, sample_times
from hil_sim.world.kinematics import Trajectory, rotate_inverse

STANDARD_GRAVITY = 9.80665  # the datasheet's "g" for LSB/g scales
# Earth's field near Annapolis (WMM, ~52 uT, inclination ~66 deg, declination ~-11 deg).
EARTH_FIELD_NED_UT = (20.8, -4.0, 47.5)
ACCEL_LSB_PER_G = 4096.0  # +-8 g
GYRO_LSB_PER_DPS = 16.4  # +-2000 deg/s
TEMP_LSB_PER_C = 333.87
MAG_UT_PER_LSB = 0.15
AK8963_ST2_16BIT = 0x10
AK8963_ST2_HOFL = 0x08
BLOCK_SIZE = 21

Vec3 = tuple[float, float, float]


def mpu9250_noise() -> ImuNoiseConfig:
    """MPU-9250 datasheet: gyro 0.01 deg/s/sqrt(Hz), accel 300 ug/sqrt(Hz); turn-on
    biases well inside the +-5 deg/s and +-60 mg tolerances."""
    return ImuNoiseConfig(
        gyro_noise_density_rad_s_rthz=1.75e-4,
        gyro_bias_rad_s=(0.020, -0.015, 0.010),
        gyro_bias_walk_rad_s2_rthz=2.0e-5,
        accel_noise_density_m_s2_rthz=2.94e-3,
        accel_bias_m_s2=(0.05, -0.08, 0.10),
        accel_bias_walk_m_s3_rthz=1.0e-4,
    )


@dataclass(frozen=True)
class MarkerImuConfig:
    rate_hz: float = 450.0
    imu: ImuNoiseConfig = field(default_factory=mpu9250_noise)
    mag_field_ned_ut: Vec3 = EARTH_FIELD_NED_UT
    mag_hard_iron_ut: Vec3 = (5.0, -3.0, 8.0)
    mag_noise_ut: float = 0.3
    mag_rate_hz: float = 100.0
    temperature_c: float = 28.0
    phase_s: float = 0.0
    clock_ppm: float = 0.0

    def __post_init__(self) -> None:
        check_positive("rate_hz", self.rate_hz)
        check_positive("mag_rate_hz", self.mag_rate_hz)
        check_finite("mag_field_ned_ut", self.mag_field_ned_ut)
        check_finite("mag_hard_iron_ut", self.mag_hard_iron_ut)
        check_nonnegative("mag_noise_ut", self.mag_noise_ut)
        check_finite("temperature_c", self.temperature_c)


@dataclass(frozen=True, eq=False)
class MarkerImuSamples:
    """K samples: `t_s` (K,); `gyro_rad_s`, `accel_m_s2`, `mag_ut` (K, 3) marker frame;
    `temperature_c` (K,); `imu_errors` the drawn gyro/accel errors (truth)."""

    t_s: np.ndarray
    gyro_rad_s: np.ndarray
    accel_m_s2: np.ndarray
    mag_ut: np.ndarray
    temperature_c: np.ndarray
    imu_errors: ImuErrors

    def __len__(self) -> int:
        return self.t_s.size


class MarkerImu:
    def __init__(self, config: MarkerImuConfig | None = None, *, rng: np.random.Generator
                 ) -> None:
        self.config = config or MarkerImuConfig()
        self.rng = rng

    def measure(self, trajectory: Trajectory) -> MarkerImuSamples:
        """`trajectory` is the marker's own (e.g. `heli.at_point(r, mount_quat)`)."""
        c = self.config
        t = sample_times(trajectory.t_s[0], trajectory.t_s[-1], c.rate_hz, c.phase_s,
                         c.clock_ppm)
        truth = trajectory.at(t)
        errs = imu_errors(t, truth.rotor_azimuth_rad, c.imu, self.rng)
        # Magnetometer: sampled at its own instants, held until the next one.
        t0 = t[0] if t.size else 0.0
        held = np.floor((t - t0) * c.mag_rate_hz + 1e-9) / c.mag_rate_hz + t0
        t_mag, mag_index = np.unique(held, return_inverse=True)
        q_mag = trajectory.at(t_mag).quat_wxyz
        mag = (rotate_inverse(q_mag, np.asarray(c.mag_field_ned_ut))
               + np.asarray(c.mag_hard_iron_ut)
               + self.rng.standard_normal((t_mag.size, 3)) * c.mag_noise_ut)[mag_index]
        temp = c.temperature_c + 0.05 * self.rng.standard_normal(t.size)
        return MarkerImuSamples(
            t_s=t,
            gyro_rad_s=truth.rates_body_rad_s + errs.gyro_rad_s,
            accel_m_s2=truth.specific_force_body_m_s2 + errs.accel_m_s2,
            mag_ut=mag,
            temperature_c=temp,
            imu_errors=errs,
        )

    def stream(self, samples: MarkerImuSamples) -> ByteStream:
        """The 21-byte register block per sample (read over I2C/SPI: no baud)."""
        return ByteStream.from_fixed_size(samples.t_s, encode_register_blocks(samples), None)


_BLOCK_DTYPE = np.dtype(
    [("accel", ">i2", (3,)), ("temp", ">i2"), ("gyro", ">i2", (3,)), ("mag", "<i2", (3,)),
     ("st2", "u1")]
)


def _to_i16(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    raw = np.round(x)
    over = (raw > 32767) | (raw < -32768)
    return np.clip(raw, -32768, 32767).astype(np.int16), over


def encode_register_blocks(samples: MarkerImuSamples) -> np.ndarray:
    """(K, 21) uint8 register images (see module doc for the layout and scales)."""
    k = len(samples)
    rec = np.zeros(k, dtype=_BLOCK_DTYPE)
    rec["accel"], _ = _to_i16(samples.accel_m_s2 / STANDARD_GRAVITY * ACCEL_LSB_PER_G)
    rec["gyro"], _ = _to_i16(np.degrees(samples.gyro_rad_s) * GYRO_LSB_PER_DPS)
    rec["temp"], _ = _to_i16((samples.temperature_c - 21.0) * TEMP_LSB_PER_C)
    m = samples.mag_ut
    mag_ak = np.stack([m[:, 1], m[:, 0], -m[:, 2]], axis=-1) / MAG_UT_PER_LSB
    rec["mag"], over = _to_i16(mag_ak)
    rec["st2"] = AK8963_ST2_16BIT | np.where(over.any(axis=1), AK8963_ST2_HOFL, 0)
    return rec.view(np.uint8).reshape(k, BLOCK_SIZE).copy()


def decode_register_blocks(blocks: np.ndarray) -> dict[str, np.ndarray]:
    """Inverse of `encode_register_blocks`: (K, 21) uint8 -> SI values in the marker frame."""
    rec = np.ascontiguousarray(blocks, dtype=np.uint8).view(_BLOCK_DTYPE).reshape(-1)
    mag_ak = rec["mag"].astype(float) * MAG_UT_PER_LSB
    return {
        "accel_m_s2": rec["accel"].astype(float) / ACCEL_LSB_PER_G * STANDARD_GRAVITY,
        "gyro_rad_s": np.radians(rec["gyro"].astype(float) / GYRO_LSB_PER_DPS),
        "temperature_c": rec["temp"].astype(float) / TEMP_LSB_PER_C + 21.0,
        "mag_ut": np.stack([mag_ak[:, 1], mag_ak[:, 0], -mag_ak[:, 2]], axis=-1),
        "st2": rec["st2"].copy(),
    }
