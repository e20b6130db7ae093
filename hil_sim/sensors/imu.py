"""IMU error model shared by the VN200 and the marker's MPU-9250.

measured = truth + bias(t) + white noise + rotor vibration, per axis, for the gyro
(rad/s) and the accelerometer (specific force, m/s^2):

- bias(t) = constant (turn-on) bias + random walk (rate / acceleration random walk);
- white noise with density N: per-sample std N / sqrt(dt) (see `noise`);
- rotor vibration: sum over h in {1, 2} of `A_h * sin(h * psi + phi_h)` per axis, with
  psi the main-rotor azimuth from the trajectory, so the vibration is phase-locked to
  the rotor and follows rotor-speed changes (1/rev: rotor imbalance and track;
  2/rev: the two-blade rotor's dominant blade-passage load).

The world switches vibration per scenario with `RotorVibration` (all-zero = off).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hil_sim.sensors import noise
from hil_sim.sensors.config import check_finite, check_nonnegative

Vec3 = tuple[float, float, float]
ZERO3: Vec3 = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class RotorVibration:
    """Rotor-synchronous vibration amplitudes (per sensor axis) and phases.

    Amplitudes are zero-to-peak. Phases are relative to blade 1 over the tail.
    """

    accel_1p_m_s2: Vec3 = ZERO3
    accel_2p_m_s2: Vec3 = ZERO3
    gyro_1p_rad_s: Vec3 = ZERO3
    gyro_2p_rad_s: Vec3 = ZERO3
    phase_1p_rad: Vec3 = (0.0, np.pi / 2, 0.0)
    phase_2p_rad: Vec3 = (0.0, np.pi / 2, 0.0)

    def __post_init__(self) -> None:
        for name in ("accel_1p_m_s2", "accel_2p_m_s2", "gyro_1p_rad_s", "gyro_2p_rad_s"):
            value = getattr(self, name)
            check_finite(name, value)
            for v in value:
                check_nonnegative(name, v)
        check_finite("phase_1p_rad", self.phase_1p_rad)
        check_finite("phase_2p_rad", self.phase_2p_rad)

    @classmethod
    def typical_600_class(cls) -> RotorVibration:
        """Plausible levels for a 600-size two-blade helicopter in hover.

        Not measured on the reference's aircraft (the dissertation only says the raw
        gyro is "very noisy due to the helicopter's vibrations", Fig 2.4): order of
        magnitude of published small-helicopter IMU spectra, 2/rev dominant.
        """
        return cls(
            accel_1p_m_s2=(0.3, 0.3, 0.5),
            accel_2p_m_s2=(0.8, 0.8, 2.0),
            gyro_1p_rad_s=(0.02, 0.02, 0.01),
            gyro_2p_rad_s=(0.05, 0.05, 0.02),
        )

    @property
    def enabled(self) -> bool:
        return any(
            any(v > 0 for v in amp)
            for amp in (self.accel_1p_m_s2, self.accel_2p_m_s2, self.gyro_1p_rad_s,
                        self.gyro_2p_rad_s)
        )

    def signals(self, rotor_azimuth_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(gyro (K, 3) rad/s, accel (K, 3) m/s^2) vibration at the given azimuths."""
        psi = np.asarray(rotor_azimuth_rad, dtype=float)[:, None]
        s1 = np.sin(psi + np.asarray(self.phase_1p_rad))
        s2 = np.sin(2.0 * psi + np.asarray(self.phase_2p_rad))
        gyro = np.asarray(self.gyro_1p_rad_s) * s1 + np.asarray(self.gyro_2p_rad_s) * s2
        accel = np.asarray(self.accel_1p_m_s2) * s1 + np.asarray(self.accel_2p_m_s2) * s2
        return gyro, accel


@dataclass(frozen=True)
class ImuNoiseConfig:
    """Error budget of one 3-axis gyro + 3-axis accelerometer (units in the names).

    `*_noise_density_*_rthz`: white-noise density per axis; `*_bias_*`: constant
    (turn-on) bias per axis; `*_bias_walk_*_rthz`: random-walk density of the bias.
    Defaults: VN-200 compensated outputs (see docs/sensors.md for sources).
    """

    gyro_noise_density_rad_s_rthz: float = 6.1e-5
    gyro_bias_rad_s: Vec3 = ZERO3
    gyro_bias_walk_rad_s2_rthz: float = 2.0e-6
    accel_noise_density_m_s2_rthz: float = 1.37e-3
    accel_bias_m_s2: Vec3 = ZERO3
    accel_bias_walk_m_s3_rthz: float = 1.6e-5
    vibration: RotorVibration = field(default_factory=RotorVibration)

    def __post_init__(self) -> None:
        for name in ("gyro_noise_density_rad_s_rthz", "gyro_bias_walk_rad_s2_rthz",
                     "accel_noise_density_m_s2_rthz", "accel_bias_walk_m_s3_rthz"):
            check_nonnegative(name, getattr(self, name))
        check_finite("gyro_bias_rad_s", self.gyro_bias_rad_s)
        check_finite("accel_bias_m_s2", self.accel_bias_m_s2)


@dataclass(frozen=True, eq=False)
class ImuErrors:
    """Additive errors at K sample times (all (K, 3)).

    `gyro_rad_s`, `accel_m_s2`: total error to add to the truth; `gyro_bias_rad_s`,
    `accel_bias_m_s2`: the bias part alone (truth, for scoring estimators);
    `gyro_vibration_rad_s`, `accel_vibration_m_s2`: the rotor-vibration part alone.
    """

    gyro_rad_s: np.ndarray
    accel_m_s2: np.ndarray
    gyro_bias_rad_s: np.ndarray
    accel_bias_m_s2: np.ndarray
    gyro_vibration_rad_s: np.ndarray
    accel_vibration_m_s2: np.ndarray


def imu_errors(
    t_s: np.ndarray,
    rotor_azimuth_rad: np.ndarray,
    config: ImuNoiseConfig,
    rng: np.random.Generator,
) -> ImuErrors:
    """Draw the IMU errors for one flight at sample times `t_s` (K,).

    `rotor_azimuth_rad` (K,) is the trajectory's unwrapped azimuth at those times.
    Call once per flight: the bias random walk starts from the constant bias at t_s[0].
    """
    t_s = np.asarray(t_s, dtype=float)
    gyro_bias = noise.random_walk(t_s, config.gyro_bias_walk_rad_s2_rthz, rng,
                                  initial=config.gyro_bias_rad_s)
    accel_bias = noise.random_walk(t_s, config.accel_bias_walk_m_s3_rthz, rng,
                                   initial=config.accel_bias_m_s2)
    gyro_white = noise.white(t_s, config.gyro_noise_density_rad_s_rthz, rng)
    accel_white = noise.white(t_s, config.accel_noise_density_m_s2_rthz, rng)
    if config.vibration.enabled:
        gyro_vib, accel_vib = config.vibration.signals(rotor_azimuth_rad)
    else:
        gyro_vib = np.zeros((t_s.size, 3))
        accel_vib = np.zeros((t_s.size, 3))
    return ImuErrors(
        gyro_rad_s=gyro_bias + gyro_white + gyro_vib,
        accel_m_s2=accel_bias + accel_white + accel_vib,
        gyro_bias_rad_s=gyro_bias,
        accel_bias_m_s2=accel_bias,
        gyro_vibration_rad_s=gyro_vib,
        accel_vibration_m_s2=accel_vib,
    )
