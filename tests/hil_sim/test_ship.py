"""Ship motion, frames, kinematics for the base sensors, relative wind, surfaces."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hil_sim.sensors.config import config_from_dict
from hil_sim.world.kinematics import GRAVITY_M_S2, quat_multiply
from hil_sim.world.ship import Ship, ShipConfig

SHIP = Ship(ShipConfig(heading_deg=60.0, speed_m_s=2.0, heave_amplitude_m=0.3))


@settings(max_examples=30)
@given(st.floats(0, 100), st.tuples(*[st.floats(-30, 30)] * 3))
def test_ship_and_ned_frames_are_inverse(t, p):
    p = np.array([p])
    assert np.allclose(SHIP.ned_to_ship(t, SHIP.ship_to_ned(t, p)), p, atol=1e-9)


def test_ship_steams_on_its_heading_and_speed():
    t = np.array([0.0, 120.0])  # whole periods of the 8/6/12/7 s oscillations
    d = np.diff(SHIP.origin_ned_m(t), axis=0)[0]
    assert np.hypot(d[0], d[1]) / 120.0 == pytest.approx(2.0, rel=0.01)
    assert np.degrees(np.arctan2(d[1], d[0])) == pytest.approx(60.0, abs=0.5)
    assert SHIP.origin_ned_m(0.0)[0, 2] == pytest.approx(-1.5, abs=0.35)  # deck above sea


def test_roll_and_pitch_stay_within_the_configured_small_angles():
    t = np.linspace(0, 60, 3001)
    e = np.degrees(SHIP.euler_rad(t))
    assert np.abs(e[:, 0]).max() == pytest.approx(2.0, rel=0.01)
    assert np.abs(e[:, 1]).max() == pytest.approx(1.0, rel=0.01)
    with pytest.raises(ValueError, match="roll_amplitude_deg = 20"):
        config_from_dict(ShipConfig, {"roll_amplitude_deg": 20}, "ship")


def test_trajectory_is_kinematically_consistent():
    # The base VN200 reads this: rates must match the attitude, the accelerometer
    # the second derivative of position (plus gravity's reaction).
    t = np.arange(0, 20.0, 0.002)
    tr = SHIP.trajectory(t).at_point([-2.0, 1.0, -1.5])
    qdot = np.gradient(tr.quat_wxyz, t, axis=0)
    w_quat = np.concatenate([np.zeros((t.size, 1)), tr.rates_body_rad_s], axis=1)
    assert np.allclose(qdot[2:-2], 0.5 * quat_multiply(tr.quat_wxyz, w_quat)[2:-2], atol=1e-6)
    acc = np.gradient(tr.vel_ned_m_s, t, axis=0)
    f_ned = np.einsum("nij,nj->ni", tr.dcm_body_to_ned, tr.specific_force_body_m_s2)
    assert np.allclose(f_ned[2:-2], (acc - [0, 0, GRAVITY_M_S2])[2:-2], atol=1e-4)
    vel = np.gradient(tr.pos_ned_m, t, axis=0)
    assert np.allclose(vel[2:-2], tr.vel_ned_m_s[2:-2], atol=1e-5)


def test_relative_wind_from_true_wind_and_back():
    true = SHIP.true_wind_ned(3.0, 15.0)
    t = np.linspace(0, 24, 97)
    speed, beta = SHIP.relative_wind(t, true)
    assert speed.mean() == pytest.approx(3.0, abs=0.02)
    assert beta.mean() == pytest.approx(15.0, abs=0.5)
    # A head wind over a stopped ship blows from the bow.
    still = Ship(ShipConfig(speed_m_s=0.0, heading_deg=90.0))
    s, b = still.relative_wind(0.0, np.array([0.0, -4.0, 0.0]))  # air moving west
    assert s[0] == pytest.approx(4.0, abs=0.01) and b[0] == pytest.approx(0.0, abs=2.5)


def test_height_above_deck_hangar_or_sea():
    ship = Ship(ShipConfig(speed_m_s=0.0, roll_amplitude_deg=0.0, pitch_amplitude_deg=0.0,
                           yaw_amplitude_deg=0.0))
    pts = ship.ship_to_ned(0.0, np.array([[-3.0, 0.0, -2.0], [4.0, 0.0, -2.0],
                                          [-20.0, 0.0, -2.0]]))
    h = ship.height_above_surface(0.0, pts)
    assert h == pytest.approx([2.0, 0.5, 2.0 + 1.5])
