"""Anemometer: motion-affected relative wind, resolution, serial and analog outputs."""

import dataclasses

import numpy as np
import pytest

from hil_sim.sensors.anemometer import Anemometer, AnemometerConfig, parse_ascii_lines
from hil_sim.world import kinematics as k
from hil_sim.world.wind import build_wind_field

WIND = {"type": "uniform", "velocity_ned_m_s": [3.0, -1.0, 0.2]}


def test_fixed_mount_reads_the_wind_at_100_hz_with_its_noise():
    field = build_wind_field(WIND, rng=np.random.default_rng(0))
    a = Anemometer(rng=np.random.default_rng(1))
    s = a.measure(k.hover(20.0, 500.0, pos_ned_m=(1.0, 2.0, -1.5)), field)
    assert np.allclose(np.diff(s.t_s), 0.01)
    assert s.wind_sensor_m_s.mean(axis=0) == pytest.approx([3.0, -1.0, 0.2], abs=0.01)
    assert s.wind_sensor_m_s.std(axis=0) == pytest.approx([0.02] * 3, rel=0.1)
    # 0.01 m/s resolution: every value is a whole number of centimetres per second.
    assert np.allclose(s.wind_sensor_m_s * 100, np.round(s.wind_sensor_m_s * 100))


def test_moving_rotated_mount_measures_relative_air_in_its_own_axes():
    # The host's motion compensation (§3.4) must undo exactly this.
    field = build_wind_field(WIND, rng=np.random.default_rng(0))
    tr = k.circle(10.0, radius_m=2.0, speed_m_s=1.0, rate_hz=500.0)
    a = Anemometer(AnemometerConfig(noise_m_s=0.0, resolution_m_s=0.0),
                   rng=np.random.default_rng(2))
    s = a.measure(tr, field)
    truth = tr.at(s.t_s)
    expected = np.einsum("nji,nj->ni", truth.dcm_body_to_ned,
                         np.array([3.0, -1.0, 0.2]) - truth.vel_ned_m_s)
    assert np.allclose(s.wind_sensor_m_s, expected, atol=1e-9)


def test_ascii_lines_and_analog_codes_carry_the_samples():
    field = build_wind_field(WIND, rng=np.random.default_rng(0))
    a = Anemometer(rng=np.random.default_rng(3))
    s = a.measure(k.hover(1.0, 500.0), field)
    rows = parse_ascii_lines(a.ascii_stream(s).data)
    assert np.allclose(rows[:, :2], s.wind_sensor_m_s[:, :2])
    assert np.allclose(rows[:, 2], -s.wind_sensor_m_s[:, 2])  # Young's W is up
    assert np.allclose(rows[:, 3], s.sonic_temperature_c)
    codes = a.analog_codes(s)
    u = codes[:, 0] / 4095 * 40.0 - 20.0
    assert np.abs(u - s.wind_sensor_m_s[:, 0]).max() <= 40.0 / 4095


def test_gain_and_offset_errors_apply_per_axis():
    field = build_wind_field(WIND, rng=np.random.default_rng(0))
    cfg = AnemometerConfig(noise_m_s=0.0, gain_error=(0.01, 0.0, 0.0), offset_m_s=(0, 0.05, 0))
    s = Anemometer(cfg, rng=np.random.default_rng(0)).measure(k.hover(0.5, 500.0), field)
    assert s.wind_sensor_m_s[0] == pytest.approx([3.03, -0.95, 0.2], abs=0.006)
    assert dataclasses.asdict(cfg)["rate_hz"] == 100.0
