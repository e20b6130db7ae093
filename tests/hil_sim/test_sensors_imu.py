"""Shared IMU error model: white noise, bias + random walk, rotor vibration."""

import numpy as np
import pytest

from hil_sim.sensors.imu import ImuNoiseConfig, RotorVibration, imu_errors
from hil_sim.sensors.noise import gauss_markov, random_walk


def _times(rate_hz, duration_s):
    return np.arange(int(rate_hz * duration_s)) / rate_hz


def test_white_noise_std_equals_density_times_sqrt_rate():
    # sigma = N / sqrt(dt): the convention docs/sensors.md states for every sensor.
    cfg = ImuNoiseConfig(gyro_noise_density_rad_s_rthz=1e-3, gyro_bias_walk_rad_s2_rthz=0.0,
                         accel_noise_density_m_s2_rthz=2e-3, accel_bias_walk_m_s3_rthz=0.0)
    t = _times(400.0, 50.0)
    e = imu_errors(t, np.zeros(t.size), cfg, np.random.default_rng(0))
    assert e.gyro_rad_s.std(axis=0) == pytest.approx([1e-3 * 20] * 3, rel=0.03)
    assert e.accel_m_s2.std(axis=0) == pytest.approx([2e-3 * 20] * 3, rel=0.03)


def test_constant_bias_is_the_mean_error():
    cfg = ImuNoiseConfig(gyro_bias_rad_s=(0.01, -0.02, 0.03), accel_bias_m_s2=(0.1, 0.0, -0.2),
                         gyro_bias_walk_rad_s2_rthz=0.0, accel_bias_walk_m_s3_rthz=0.0)
    t = _times(150.0, 60.0)
    e = imu_errors(t, np.zeros(t.size), cfg, np.random.default_rng(1))
    assert e.gyro_rad_s.mean(axis=0) == pytest.approx([0.01, -0.02, 0.03], abs=2e-4)
    assert e.accel_m_s2.mean(axis=0) == pytest.approx([0.1, 0.0, -0.2], abs=4e-3)
    assert np.allclose(e.gyro_bias_rad_s, [0.01, -0.02, 0.03])


def test_bias_random_walk_variance_grows_linearly_in_time():
    # Var(b(T) - b(0)) = K^2 T over many independent flights.
    t = _times(100.0, 20.0)
    rng = np.random.default_rng(2)
    ends = np.array([random_walk(t, 0.01, rng)[-1] for _ in range(400)])
    assert ends.var() == pytest.approx(0.01**2 * t[-1], rel=0.15)


def test_gauss_markov_is_stationary_with_the_configured_std():
    t = _times(50.0, 2000.0)
    x = gauss_markov(t, (0.5, 1.0, 2.0), 5.0, np.random.default_rng(3))
    assert x[: t.size // 2].std(axis=0) == pytest.approx([0.5, 1.0, 2.0], rel=0.12)
    lag = 250  # 5 s: correlation e^-1
    r = np.mean(x[:-lag, 2] * x[lag:, 2]) / x[:, 2].var()
    assert r == pytest.approx(np.exp(-1.0), abs=0.1)


def test_rotor_vibration_appears_at_one_and_two_per_rev():
    # The world switches this on per scenario; the host must see lines at Omega and 2 Omega.
    omega = 163.3
    vib = RotorVibration(accel_1p_m_s2=(0.0, 0.0, 0.5), accel_2p_m_s2=(0.0, 0.0, 2.0),
                         gyro_2p_rad_s=(0.05, 0.0, 0.0))
    cfg = ImuNoiseConfig(gyro_noise_density_rad_s_rthz=0.0, accel_noise_density_m_s2_rthz=0.0,
                         gyro_bias_walk_rad_s2_rthz=0.0, accel_bias_walk_m_s3_rthz=0.0,
                         vibration=vib)
    rate = 1000.0
    t = _times(rate, 10.0)
    e = imu_errors(t, omega * t, cfg, np.random.default_rng(4))
    # Lock-in amplitude at h/rev: 2 |mean(x exp(-i h psi))|.
    psi = omega * t
    z = e.accel_m_s2[:, 2]
    assert 2 * abs(np.mean(z * np.exp(-1j * psi))) == pytest.approx(0.5, rel=0.02)
    assert 2 * abs(np.mean(z * np.exp(-2j * psi))) == pytest.approx(2.0, rel=0.02)
    assert 2 * abs(np.mean(z * np.exp(-3j * psi))) < 0.02
    assert np.abs(e.gyro_rad_s[:, 0]).max() == pytest.approx(0.05, rel=0.01)
    assert np.all(e.gyro_rad_s[:, 1] == 0)


def test_same_seed_same_errors_different_seed_different():
    cfg = ImuNoiseConfig()
    t = _times(150.0, 2.0)
    a = imu_errors(t, np.zeros(t.size), cfg, np.random.default_rng(7)).gyro_rad_s
    b = imu_errors(t, np.zeros(t.size), cfg, np.random.default_rng(7)).gyro_rad_s
    c = imu_errors(t, np.zeros(t.size), cfg, np.random.default_rng(8)).gyro_rad_s
    assert np.array_equal(a, b) and not np.array_equal(a, c)
