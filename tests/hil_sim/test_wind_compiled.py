"""The compiled wind fields against the numpy implementation they replaced
(wind_reference.py, frozen at commit 402bb0c): the same values to rounding, for every
field type, with shedding and turbulence on and off; and the compiled pieces (ship
pose, turbulence sampling, the stencil increments) against their direct evaluation.

The reference reads each field's own parameters and turbulence box, so it holds for any
seed and numpy version. Small turbulence boxes keep the fields quick to build: the
kernels do not depend on the box size.
"""

import math

import numpy as np
import pytest
import wind_reference as ref
from hypothesis import given, settings
from hypothesis import strategies as st

from hil_sim.world.ship import Ship, ShipConfig
from hil_sim.world.turbulence import FrozenTurbulence, TurbulenceConfig
from hil_sim.world.wind import WindField, build_wind_field
from hil_sim.world.wind import increments as inc

TOL_M_S = 1e-9
SMALL_BOX = {"length_scale_m": 1.0, "grid_spacing_m": 0.25, "box_m": [32.0, 8.0, 8.0]}
SHIPS = {
    "default": ShipConfig(),
    "rolling": ShipConfig(heading_deg=30.0, speed_m_s=4.0, roll_amplitude_deg=5.0,
                          pitch_amplitude_deg=2.0, heave_amplitude_m=0.4),
}
FIELDS = {
    "ship_b15": ({"type": "ship_airwake", "relative_wind_heading_deg": 15.0,
                  "turbulence": SMALL_BOX}, "default"),
    "ship_oblique": ({"type": "ship_airwake", "relative_wind_speed_m_s": 6.0,
                      "relative_wind_heading_deg": -40.0, "shear_layer_thickness_m": 0.3,
                      "shedding_amplitude": 0.3, "recirculation_length_m": 5.0,
                      "turbulence": SMALL_BOX}, "rolling"),
    "fans": ({"type": "fans_indoor", "turbulence": {**SMALL_BOX, "lateral_drift_m": 3.0}},
             None),
    "fans_moved": ({"type": "fans_indoor", "fan_a_ned_m": [1.0, -1.0, -1.2],
                    "fan_b_ned_m": [6.0, 3.0, -2.0], "swirl_fraction": 0.5,
                    "turbulence": SMALL_BOX}, None),
    "uniform": ({"type": "uniform", "velocity_ned_m_s": [3.0, -1.0, 0.2],
                 "turbulence_intensity": 0.15, "turbulence": SMALL_BOX}, None),
    "still": ({"type": "still_air"}, None),
}


class Reference(WindField):
    """A field's numpy twin: the frozen implementation on the same parameters and box."""

    def __init__(self, field):
        self.field = field

    def _velocity(self, t, pos, unsteady, turbulence):
        return ref.VELOCITY[self.field.kind](self.field, t, pos, unsteady, turbulence)


def _field(name):
    config, ship = FIELDS[name]
    return build_wind_field(config, rng=np.random.default_rng(7),
                            ship=Ship(SHIPS[ship]) if ship else None)


def _samples(field, rng):
    """(t (N,), NED points (N, 3)): runs of equal times (as the blade-element grid and
    local_wind sample) and single times, over the region each field shapes."""
    runs = np.repeat(rng.uniform(0.0, 300.0, 30), 60)
    t = np.concatenate([runs, rng.uniform(0.0, 300.0, 1200)])
    n = t.size
    if field.kind == "ship_airwake":
        # ship frame: ahead of the hangar to 60 m downstream, wider than the wake,
        # below the deck to well above the shear layer
        p = np.column_stack([rng.uniform(-60.0, 15.0, n), rng.uniform(-20.0, 20.0, n),
                             rng.uniform(-12.0, 1.0, n)])
        return t, field.ship.ship_to_ned(t, p)
    return t, np.column_stack([rng.uniform(-3.0, 10.0, n), rng.uniform(-4.0, 4.0, n),
                               rng.uniform(-5.0, 0.5, n)])


@pytest.fixture(scope="module", params=sorted(FIELDS))
def field(request):
    return _field(request.param)


@pytest.mark.parametrize(("unsteady", "turbulence"),
                         [(False, False), (True, False), (False, True), (True, True)])
def test_field_equals_the_numpy_reference(field, unsteady, turbulence):
    # The compiled kernels are a speed-up, not a new model: any change of value is a bug.
    t, pos = _samples(field, np.random.default_rng(3))
    got = field.velocity_ned(t, pos, unsteady=unsteady, turbulence=turbulence)
    want = ref.VELOCITY[field.kind](field, t, pos, unsteady, turbulence)
    assert np.isfinite(got).all()
    assert np.max(np.abs(got - want)) < TOL_M_S


def test_local_wind_equals_the_numpy_reference(field):
    rng = np.random.default_rng(4)
    t, pos = _samples(field, rng)
    hubs, times = pos[::60][:25], t[::60][:25]
    quats = rng.normal(size=(times.size, 4))
    quats /= np.linalg.norm(quats, axis=1, keepdims=True)
    got = field.local_wind(times, hubs, quats)
    want = Reference(field).local_wind(times, hubs, quats)
    assert np.max(np.abs(got - want)) < TOL_M_S


def test_same_seed_same_field_to_the_bit():
    a, b = _field("ship_oblique"), _field("ship_oblique")
    t, pos = _samples(a, np.random.default_rng(5))
    assert np.array_equal(a.velocity_ned(t, pos), b.velocity_ned(t, pos))


def test_airwake_diagnostics_equal_the_reference():
    # stream_function, sigma_m_s and ship_frame_velocity are public; s = 0 at t = 0 puts
    # the shedding phase at exactly 0 (sin = 0 but not its neighbours').
    f = _field("ship_oblique")
    rng = np.random.default_rng(6)
    s = np.concatenate([[0.0, 0.0, f.config.recirculation_length_m], rng.uniform(-20, 60, 997)])
    n = np.concatenate([[0.0, 1.0, 0.0], rng.uniform(-15, 15, 997)])
    h = np.concatenate([[1.0, 0.0, 2.0], rng.uniform(-1, 12, 997)])
    t = np.concatenate([[0.0, 0.0, 0.0], rng.uniform(0, 100, 997)])
    snh = np.column_stack([s, n, h])
    for unsteady in (False, True):
        assert np.max(np.abs(f.stream_function(s, h, n, t, unsteady)
                             - ref.stream_function(f, s, h, n, t, unsteady))) < 1e-11
        for turbulence in (False, True):
            got = f.ship_frame_velocity(t, snh, unsteady, turbulence)
            want = ref.ship_frame_velocity(f, t, snh, unsteady, turbulence)
            assert np.max(np.abs(got - want)) < TOL_M_S
    assert np.max(np.abs(f.sigma_m_s(s, h, n) - ref.sigma_m_s(f, s, h, n))) < 1e-12


def test_ship_pose_and_transforms_equal_the_euler_composition():
    ship = Ship(SHIPS["rolling"])
    t = np.random.default_rng(8).uniform(0, 500, 400)
    rot, origin, vel = ship.pose(t)
    r_ref, o_ref, v_ref = ref.ship_pose(ship, t)
    assert np.max(np.abs(rot - r_ref)) < 1e-14
    assert np.max(np.abs(origin - o_ref)) < 1e-12
    assert np.max(np.abs(vel - v_ref)) < 1e-14
    p = np.random.default_rng(9).normal(size=(t.size, 3)) * 20
    want = np.einsum("nji,nj->ni", r_ref, p - o_ref)
    assert np.max(np.abs(ship.ned_to_ship(t, p) - want)) < 1e-11
    assert np.max(np.abs(ship.ship_to_ned(t, want) - p)) < 1e-11


def test_turbulence_sampling_is_the_numpy_trilinear():
    # Negative coordinates, many boxes away, and points on grid nodes (f = 0 exactly). To
    # rounding: the compiled loop may fuse a multiply-add where numpy rounds twice (a clean
    # clone's build differed from the reference in the last bit).
    box = FrozenTurbulence(TurbulenceConfig(**SMALL_BOX), np.random.default_rng(0))
    rng = np.random.default_rng(1)
    p = rng.uniform(-500.0, 500.0, (3000, 3))
    p[:300] = np.round(p[:300] / 0.25) * 0.25
    t = rng.uniform(0.0, 1000.0, 3000)
    assert np.max(np.abs(box.sample(p) - ref.sample(box, p))) < 1e-12
    assert np.max(np.abs(box.advected(p, t, 3.7) - ref.advected(box, p, t, 3.7))) < 1e-12


def _close(a, b, rel=8e-16, abs_=1e-300):
    return abs(a - b) <= rel * max(abs(a), abs(b)) + abs_


finite = st.floats(-40.0, 40.0, allow_nan=False)
step = st.floats(-2.0 * inc.SMALL, 2.0 * inc.SMALL, allow_nan=False)


@settings(max_examples=300, deadline=None)
@given(x0=finite, d=step)
def test_increments_equal_the_direct_evaluation(x0, d):
    # Each stepped value as accurate as the direct one, inside the series' range and at
    # the fallback beyond it. softplus and ln cosh are ln(1 + e^-a) plus a: accurate to
    # an ulp of 1 (absolute), which is what the stream function needs.
    x1 = x0 + d
    sp0, sig0 = inc.softplus(x0, math.exp(-abs(x0)))
    sp1, sig1 = inc.softplus_step(sp0, sig0, x0, x1)
    assert _close(sp1, math.log1p(math.exp(-abs(x1))) + max(x1, 0.0), rel=4e-15, abs_=5e-16)
    assert _close(sig1, 1.0 / (1.0 + math.exp(-x1)), rel=4e-15, abs_=1e-300)
    lc0, t0 = inc.logcosh(x0)
    lc1, t1 = inc.logcosh_step(lc0, t0, x0, x1)
    assert _close(lc1, abs(x1) + math.log1p(math.exp(-2 * abs(x1))) - math.log(2.0),
                  rel=4e-15, abs_=5e-16)
    assert _close(t1, math.tanh(x1), rel=4e-15, abs_=5e-16)
    assert _close(inc.tanh_step(math.tanh(x0), x0, x1), math.tanh(x1), rel=4e-15, abs_=5e-16)
    assert _close(inc.exp_small(d), math.exp(d), rel=4e-16)
    assert _close(inc.expm1_small(d), math.expm1(d), rel=4e-16, abs_=0.0)
    assert _close(inc.log1p_small(d), math.log1p(d), rel=4e-16, abs_=0.0)
