"""Marker IMU (MPU-9250 + AK8963): rate, bias, magnetometer, register blocks."""

import numpy as np
import pytest

from hil_sim.sensors.marker_imu import (
    BLOCK_SIZE,
    EARTH_FIELD_NED_UT,
    MarkerImu,
    MarkerImuConfig,
    decode_register_blocks,
)
from hil_sim.world import kinematics as k


@pytest.fixture(scope="module")
def spinning():
    tr = k.constant_rotation(10.0, [0.3, -0.5, 0.8], 2000.0)
    imu = MarkerImu(rng=np.random.default_rng(3))
    return tr, imu, imu.measure(tr)


def test_rate_is_450_hz(spinning):
    _, _, s = spinning
    assert np.allclose(np.diff(s.t_s), 1 / 450.0)


def test_gyro_carries_the_turn_on_bias_the_firmware_must_estimate(spinning):
    tr, imu, s = spinning
    err = s.gyro_rad_s - tr.at(s.t_s).rates_body_rad_s
    assert err.mean(axis=0) == pytest.approx(imu.config.imu.gyro_bias_rad_s, abs=2e-3)
    assert err.std(axis=0) == pytest.approx([1.75e-4 * np.sqrt(450)] * 3, rel=0.1)


def test_magnetometer_is_earth_field_in_marker_axes_held_at_100_hz(spinning):
    tr, imu, s = spinning
    mag = s.mag_ut - np.asarray(imu.config.mag_hard_iron_ut)
    assert np.linalg.norm(mag, axis=1).mean() == pytest.approx(
        np.linalg.norm(EARTH_FIELD_NED_UT), abs=0.1)
    changes = np.count_nonzero(np.any(np.diff(s.mag_ut, axis=0) != 0, axis=1))
    assert changes == pytest.approx(10.0 * 100, abs=2)


def test_register_blocks_decode_to_the_samples_within_one_lsb(spinning):
    _, imu, s = spinning
    stream = imu.stream(s)
    blocks = np.frombuffer(stream.data, dtype=np.uint8).reshape(-1, BLOCK_SIZE)
    d = decode_register_blocks(blocks)
    assert np.abs(d["accel_m_s2"] - s.accel_m_s2).max() <= 9.80665 / 4096
    assert np.abs(np.degrees(d["gyro_rad_s"] - s.gyro_rad_s)).max() <= 1 / 16.4
    assert np.abs(d["mag_ut"] - s.mag_ut).max() <= 0.15
    assert np.abs(d["temperature_c"] - s.temperature_c).max() <= 1 / 333.87
    assert np.all(d["st2"] == 0x10)
    # Big-endian accel X in the first two bytes, as the MPU-9250 register map has it.
    raw_ax = int.from_bytes(blocks[0, :2].tobytes(), "big", signed=True)
    assert raw_ax == round(s.accel_m_s2[0, 0] / 9.80665 * 4096)


def test_out_of_range_values_clip_and_flag_overflow():
    imu = MarkerImu(MarkerImuConfig(mag_hard_iron_ut=(6000.0, 0.0, 0.0)),
                    rng=np.random.default_rng(0))
    s = imu.measure(k.hover(0.1, 1000.0))
    d = decode_register_blocks(np.frombuffer(imu.stream(s).data, np.uint8).reshape(-1, 21))
    assert np.all(d["st2"] & 0x08)
