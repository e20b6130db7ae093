"""Ship airwake behind a hangar step: freestream, recirculation, shedding, turbulence,
decay, relative-wind heading, determinism."""

import numpy as np
import pytest
from scipy.signal import welch

from hil_sim.world.ship import Ship, ShipConfig
from hil_sim.world.wind import build_wind_field

BOX = {"length_scale_m": 1.0, "grid_spacing_m": 0.25, "box_m": [96.0, 16.0, 12.0]}
STILL_SHIP = {"speed_m_s": 0.0, "roll_amplitude_deg": 0.0, "pitch_amplitude_deg": 0.0,
              "yaw_amplitude_deg": 0.0}


def airwake(seed=1, ship=None, **settings):
    cfg = {"type": "ship_airwake", "turbulence": BOX, **settings}
    return build_wind_field(cfg, rng=np.random.default_rng(seed), ship=ship)


@pytest.fixture(scope="module")
def still():
    """Head wind (beta = 0) behind a ship that does not move: ship frame = NED offset."""
    return airwake(ship=Ship(ShipConfig(**STILL_SHIP)))


def ship_point(field, s, h, n=0.0):
    """NED position of wake coordinates (s downstream, h above deck, n lateral)."""
    p = s * field.e_s + n * field.e_n + np.array([0.0, 0.0, -h])
    return field.ship.ship_to_ned(0.0, p[None, :])[0]


def series(field, pos, duration=120.0, dt=0.05, **kw):
    t = np.arange(0.0, duration, dt)
    return t, field.velocity_ned(t, np.tile(pos, (t.size, 1)), **kw)


def test_far_from_the_ship_the_air_is_the_relative_wind(still):
    # Upstream, high above, and far to the side of the wake.
    for s, h, n in ((-25.0, 4.0, 0.0), (10.0, 30.0, 0.0), (10.0, 1.0, 25.0)):
        v = still.mean_velocity_ned(0.0, ship_point(still, s, h, n))
        assert v == pytest.approx([-3.0, 0.0, 0.0], abs=0.02)


def test_recirculation_bubble_reverses_the_flow_near_the_deck(still):
    # 5-10 m aft of the step (§4.5.1): inside the bubble the air flows back toward the hangar.
    along = [still.mean_velocity_ned(0.0, ship_point(still, s, 0.2)) @ still.e_s
             for s in (2.0, 3.75, 5.5)]
    assert all(u < -0.3 for u in along)
    assert still.mean_velocity_ned(0.0, ship_point(still, 3.75, 3.5)) @ still.e_s > 2.5
    # Past reattachment the flow near the deck runs downstream again.
    assert still.mean_velocity_ned(0.0, ship_point(still, 12.0, 0.3)) @ still.e_s > 0.0


def test_vortex_shedding_frequency_from_a_spectrum(still):
    # f = St U / H = 0.25 * 3 / 1.5 = 0.5 Hz (§4.5.1: ~0.54 Hz for the YP676).
    assert still.shedding_hz == pytest.approx(0.5)
    t, v = series(still, ship_point(still, 5.0, 1.25), duration=240.0)
    f, pxx = welch(v[:, 2] - v[:, 2].mean(), fs=1 / 0.05, nperseg=1024)
    band = (f > 0.1) & (f < 3.0)
    assert f[band][np.argmax(pxx[band])] == pytest.approx(0.5, abs=0.05)


def test_turbulence_intensity_ambient_and_in_the_shear_layer(still):
    _, far = series(still, ship_point(still, -25.0, 4.0))
    ti_far = far.std(axis=0) / 3.0
    assert ti_far == pytest.approx([0.05] * 3, rel=0.3)
    _, shear = series(still, ship_point(still, 5.0, 1.25), unsteady=False)
    assert shear.std(axis=0).mean() > 3 * far.std(axis=0).mean()


def test_wake_decays_with_distance(still):
    deficit = [3.0 + still.mean_velocity_ned(0.0, ship_point(still, s, 1.0)) @ [1, 0, 0]
               for s in (10.0, 25.0, 45.0)]
    assert deficit[0] > deficit[1] > deficit[2] > 0
    sig = [still.sigma_m_s(np.array([s]), np.array([1.2]), np.array([0.0]))[0]
           for s in (5.0, 20.0, 45.0)]
    assert sig[0] > sig[1] > sig[2] > 0.05 * 3.0 * 0.99


def test_relative_wind_heading_rotates_the_wake():
    ship = Ship(ShipConfig(**STILL_SHIP))
    head = airwake(ship=ship)
    oblique = airwake(ship=ship, relative_wind_heading_deg=15.0)
    for s, h in ((3.75, 0.3), (12.0, 1.0)):
        a = head.mean_velocity_ned(0.0, ship_point(head, s, h)) @ head.e_s
        b = oblique.mean_velocity_ned(0.0, ship_point(oblique, s, h)) @ oblique.e_s
        assert b == pytest.approx(a, abs=0.35)  # same wake, turned (and a bit wider)
    # Straight aft of the step at 12 m the 15 deg wake has moved to port: less deficit.
    aft = np.array([-12.0, 4.0, -1.0])
    p = ship.ship_to_ned(0.0, aft[None, :])[0]
    assert (oblique.mean_velocity_ned(0.0, p) @ oblique.e_s
            > head.mean_velocity_ned(0.0, p) @ head.e_s + 0.3)


def test_moving_ship_carries_the_wake_and_gives_the_true_wind_far_away():
    ship = Ship(ShipConfig(heading_deg=40.0, speed_m_s=2.5))
    field = airwake(ship=ship)
    far_ship = np.array([40.0, 0.0, -5.0])  # well ahead of the bow
    t = np.linspace(0, 20, 41)
    pts = ship.ship_to_ned(t, np.tile(far_ship, (t.size, 1)))
    v = field.mean_velocity_ned(t, pts)
    assert np.abs(v - field.true_wind_ned()).max() < 0.15  # roll/pitch tilt only
    speed, beta = ship.relative_wind(t, field.true_wind_ned())
    assert speed.mean() == pytest.approx(3.0, abs=0.05)
    assert beta.mean() == pytest.approx(0.0, abs=1.0)


def test_local_wind_truth_at_the_hub_is_finite_and_seed_deterministic():
    ship = Ship(ShipConfig(**STILL_SHIP))
    a, b, c = airwake(7, ship), airwake(7, ship), airwake(8, ship)
    hub = np.tile(ship_point(a, 5.0, 1.5), (20, 1))
    q = np.tile([1.0, 0, 0, 0], (20, 1))
    t = np.linspace(0, 2, 20)
    la, lb, lc = (f.local_wind(t, hub, q) for f in (a, b, c))
    assert np.all(np.isfinite(la)) and la.shape == (20, 6)
    assert np.array_equal(la, lb) and not np.allclose(la, lc)
    # In the shear layer the rotor sees wind gradients: vorticity-like terms.
    assert np.abs(la[:, 3:]).max() > 0.1
