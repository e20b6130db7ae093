"""Rotor tachometer: IR pulses from two blades give the rotor speed."""

import dataclasses

import numpy as np
import pytest

from hil_sim.sensors.rotor import RotorTachConfig, RotorTachometer, rotor_speed_from_pulses
from hil_sim.world import kinematics as k


def test_pulses_give_the_rotor_speed():
    tr = k.hover(5.0, 1000.0, rotor_speed_rad_s=163.3)
    tach = RotorTachometer(rng=np.random.default_rng(0))
    p = tach.measure(tr)
    # Two pulses per revolution.
    assert len(p) == pytest.approx(5.0 * 163.3 / np.pi, abs=2)
    assert np.mean(p.rotor_speed_rad_s) == pytest.approx(163.3, rel=1e-4)
    assert np.std(p.rotor_speed_rad_s) < 0.1  # 5 us jitter on ~19 ms intervals
    assert set(np.unique(p.blade)) == {0, 1}


def test_speed_changes_are_tracked():
    tr = k.hover(4.0, 2000.0)
    omega = 150.0 + 5.0 * tr.t_s  # spooling up
    psi = 150.0 * tr.t_s + 2.5 * tr.t_s**2
    tr = dataclasses.replace(tr, rotor_speed_rad_s=omega, rotor_azimuth_rad=psi)
    p = RotorTachometer(RotorTachConfig(jitter_s=0.0), rng=np.random.default_rng(1)).measure(tr)
    mid = 0.5 * (p.t_s[1:] + p.t_s[:-1]) - 100e-6
    assert np.abs(p.rotor_speed_rad_s - (150.0 + 5.0 * mid)).max() < 0.01


def test_blade_spacing_error_alternates_intervals_and_misses_are_dropped():
    tr = k.hover(60.0, 1000.0)
    cfg = RotorTachConfig(blade_spacing_error_rad=0.02, miss_probability=0.05, jitter_s=0.0)
    p = RotorTachometer(cfg, rng=np.random.default_rng(2)).measure(tr)
    expected = 60.0 * 163.3 / np.pi
    assert len(p) == pytest.approx(0.95 * expected, rel=0.02)
    # A missed pulse shows up as a ~half-speed value, as on the rover.
    assert np.sum(p.rotor_speed_rad_s < 100) == pytest.approx(0.05 * expected, rel=0.25)
    full = p.rotor_speed_rad_s[p.rotor_speed_rad_s > 100]
    assert full.min() < 163.3 < full.max()  # long/short halves
    assert np.mean(rotor_speed_from_pulses(p.t_s[:2], 2)) > 0


def test_edge_stream_has_a_pulse_per_detection():
    tr = k.hover(1.0, 1000.0)
    tach = RotorTachometer(rng=np.random.default_rng(3))
    p = tach.measure(tr)
    rises, widths = tach.stream(p).pulse_widths_s(0)
    assert np.allclose(rises, p.t_s) and np.allclose(widths, 300e-6)
