"""RC receiver and tail-servo PWM: widths, mapping both ways, edges, glitches."""

import dataclasses

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from hil_sim.sensors.rc import (
    PulseTrainConfig,
    PwmMapping,
    RcConfig,
    RcReceiver,
    TailServoPwm,
    blade_pitch_to_pwm,
    pwm_to_blade_pitch,
)
from hil_sim.world import kinematics as k


def sweeping_trajectory(duration_s=4.0, rate_hz=1000.0):
    tr = k.hover(duration_s, rate_hz)
    t = tr.t_s
    pitch = np.stack([0.08 + 0.05 * np.sin(2 * np.pi * 0.7 * t), 0.06 * np.sin(2 * np.pi * t),
                      -0.05 * np.cos(2 * np.pi * 1.3 * t), 0.1 * np.sin(2 * np.pi * 0.4 * t)], -1)
    return dataclasses.replace(tr, blade_pitch_rad=pitch)


def test_widths_within_1_us_of_mapping_at_50_hz():
    tr = sweeping_trajectory()
    rx = RcReceiver(rng=np.random.default_rng(0))
    s = rx.measure(tr)
    assert 1 / np.diff(s.t_s).max() >= 45.0
    assert np.allclose(np.diff(s.t_s), 0.02)
    expected = blade_pitch_to_pwm(tr.at(s.t_s).blade_pitch_rad)
    assert np.abs(s.width_us - expected).max() <= 0.5 + 1e-9  # 1 us resolution
    assert np.all((s.width_us >= 1000) & (s.width_us <= 2000))
    assert np.all(s.width_us[:, 4] == 1700)


def test_inverse_mapping_recovers_blade_pitch_within_resolution():
    tr = sweeping_trajectory()
    s = RcReceiver(rng=np.random.default_rng(0)).measure(tr)
    back = pwm_to_blade_pitch(s.width_us)
    gains = np.array(PwmMapping().gain_rad_per_us)[[2, 0, 1, 3]]  # [col, lat, lon, ped]
    assert np.all(np.abs(back - tr.at(s.t_s).blade_pitch_rad) <= 0.5 * gains + 1e-12)


@given(st.tuples(st.floats(-0.05, 0.2), st.floats(-0.13, 0.13), st.floats(-0.13, 0.13),
                 st.floats(-0.34, 0.34)))
def test_mapping_round_trip_property(pitch):
    # Within the transmitter end points the two maps are exact inverses.
    p = np.array([pitch])
    assert np.allclose(pwm_to_blade_pitch(blade_pitch_to_pwm(p)), p, atol=1e-12)


def test_pitch_beyond_end_points_clips_to_1000_2000_us():
    w = blade_pitch_to_pwm(np.array([[1.0, -1.0, 1.0, -1.0]]))
    # Channels 1..4 are lat, lon, col, ped.
    assert w[0, :4].tolist() == [1000.0, 2000.0, 2000.0, 1000.0]


def test_mapping_documented_ranges():
    # Collective -3..+12 deg over 1000..2000 us, cyclic +-8 deg, tail +-20 deg.
    w = np.array([[1000, 2000, 1000, 2000, 1500], [2000, 1000, 2000, 1000, 1500]], float)
    deg = np.degrees(pwm_to_blade_pitch(w))
    # Output order [col, lat, lon, ped] from channels (lat, lon, col, ped).
    assert deg[0] == pytest.approx([-3.0, -8.0, 8.0, 20.0], abs=0.01)
    assert deg[1] == pytest.approx([12.0, 8.0, -8.0, -20.0], abs=0.01)


def test_edges_decode_to_the_widths_with_jitter():
    tr = sweeping_trajectory(2.0)
    rx = RcReceiver(rng=np.random.default_rng(1))
    s = rx.measure(tr)
    edges = rx.stream(s)
    for ch in range(5):
        rises, widths = edges.pulse_widths_s(ch)
        assert len(rises) == len(s)
        assert np.abs(widths * 1e6 - s.width_us[:, ch]).max() < 3.0  # 0.3 us jitter, 2 edges
    # Sequential layout: channel c+1 rises where channel c falls.
    r0, w0 = edges.pulse_widths_s(0)
    r1, _ = edges.pulse_widths_s(1)
    assert np.allclose(r1, r0 + w0, atol=3e-6)


def test_glitches_and_dropouts_appear_at_configured_rates():
    tr = sweeping_trajectory(20.0, 200.0)
    timing = PulseTrainConfig(glitch_probability=0.05, dropout_probability=0.02)
    rx = RcReceiver(RcConfig(timing=timing), rng=np.random.default_rng(2))
    s = rx.measure(tr)
    _, widths = rx.stream(s).pulse_widths_s(2)
    n = len(s)
    short = np.sum(widths < 100e-6)
    normal = np.sum(widths >= 900e-6)
    assert short / n == pytest.approx(0.05, abs=0.02)
    assert normal / n == pytest.approx(0.98, abs=0.015)


def test_tail_servo_maps_ped_pitch_at_333_hz():
    tr = sweeping_trajectory(1.0)
    servo = TailServoPwm(rng=np.random.default_rng(3))
    s = servo.measure(tr)
    assert np.allclose(np.diff(s.t_s), 1 / 333.0)
    back = servo.config.pwm_to_pitch(s.width_us[:, 0])
    assert np.abs(back - tr.at(s.t_s).blade_pitch_rad[:, 3]).max() <= 0.25 * 6.981e-4 + 1e-12
    rises, widths = servo.stream(s).pulse_widths_s(0)
    assert len(rises) == len(s)
