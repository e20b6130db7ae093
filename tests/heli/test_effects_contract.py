"""STYLE 12: one contract test over every registered effect of the package."""

import numpy as np
import pytest
from airwake.heli import default_model, load_spec, registered_effects, save_spec
from airwake.heli.effects.base import effect_source
from airwake.heli.effects.catalogue import CATALOGUE_EFFECTS
from airwake.heli.trim import trim_hover

MODEL = default_model()
# the base model's effects; the catalogue (airwake.heli.effects.catalogue) has its own
# contract test with the diagnosis's "off" values in tests/discrepancy/test_catalogue_effects.py
PACKAGE_EFFECTS = sorted(n for n, cls in registered_effects().items()
                         if effect_source(n) is None and cls.__module__.startswith("airwake.heli.")
                         and cls not in CATALOGUE_EFFECTS)


def _zero_ctx():
    # body at rest, level, hidden states zero, zero input, still air
    return MODEL.evaluate(MODEL.zero_state(1), np.zeros((1, 4)), np.zeros((1, 6)))


def _no_load(ctx, name):
    assert name not in ctx.loads


def _zero_load(ctx, name):
    f, m, _ = ctx.loads[name]
    np.testing.assert_allclose(f, 0.0, atol=1e-12)
    np.testing.assert_allclose(m, 0.0, atol=1e-12)


def _gravity(ctx, name):
    f, m, sensed = ctx.loads[name]
    mg = MODEL["rigid_body"].parameters()["mass_kg"] * MODEL["gravity"].parameters()["g_m_s2"]
    np.testing.assert_allclose(f, [[0.0, 0.0, mg]], rtol=1e-14)
    assert not sensed  # an accelerometer does not feel gravity


def _main_rotor(ctx, name):
    _zero_load(ctx, name)  # no thrust at zero pitch in still air
    p = MODEL[name].parameters()
    rates = ctx.xdot[0, MODEL.state_slice(name)]
    np.testing.assert_allclose(rates[:9], 0.0, atol=1e-12)
    # profile drag alone lags the blades: zeta_0'' = -Omega^2 gamma/2 (delta0/a0)/4
    om = p["nominal_speed_rad_s"]
    expect = -(om**2) * p["lock_number"] / 2 * p["drag_delta0"] / p["lift_slope_per_rad"] / 4
    np.testing.assert_allclose(rates[9], expect, rtol=1e-9)


def _inflow(ctx, name):
    _no_load(ctx, name)
    np.testing.assert_allclose([ctx.inflow_0, ctx.inflow_c, ctx.inflow_s], 0.0, atol=1e-12)


def _flybar(ctx, name):
    _no_load(ctx, name)
    np.testing.assert_allclose([ctx.theta_c, ctx.theta_s], 0.0, atol=1e-15)
    np.testing.assert_allclose(ctx.xdot[0, MODEL.state_slice(name)], 0.0, atol=1e-12)


TRIVIAL = {
    "atmosphere": _no_load,
    "rigid_body": _no_load,
    "gravity": _gravity,
    "main_rotor": _main_rotor,
    "pitt_peters_inflow": _inflow,
    "flybar": _flybar,
    "tail_rotor": _zero_load,
    "fuselage": _zero_load,
    "empennage": _zero_load,
}


def test_every_registered_effect_has_a_contract_entry():
    # a new effect must state what it does at zero input and still air
    assert sorted(TRIVIAL) == PACKAGE_EFFECTS


@pytest.mark.parametrize("name", PACKAGE_EFFECTS)
def test_effect_is_finite_at_hover(name):
    tr = trim_hover(MODEL)
    ctx = MODEL.evaluate(tr.x, tr.u)
    assert np.all(np.isfinite(ctx.xdot)) and np.all(np.isfinite(ctx.meas))
    if name in ctx.loads:
        f, m, _ = ctx.loads[name]
        assert np.all(np.isfinite(f)) and np.all(np.isfinite(m))


@pytest.mark.parametrize("name", PACKAGE_EFFECTS)
def test_zero_wind_and_zero_input_give_the_trivial_load(name):
    TRIVIAL[name](_zero_ctx(), name)


@pytest.mark.parametrize("name", PACKAGE_EFFECTS)
def test_bad_parameter_raises_value_error_naming_effect_and_parameter(name):
    cls = registered_effects()[name]
    for spec in cls.PARAMETERS:
        for bad in (spec.bounds[1] + 1e6, float("nan"), "abc"):
            with pytest.raises(ValueError) as exc:
                cls(**{spec.name: bad})
            assert name in str(exc.value) and spec.name in str(exc.value)
    with pytest.raises(ValueError, match=name):
        cls(no_such_parameter=1.0)


@pytest.mark.parametrize("name", PACKAGE_EFFECTS)
def test_parameters_round_trip_through_the_spec(name, tmp_path):
    cls = registered_effects()[name]
    values = {}
    for spec in cls.PARAMETERS:
        lo, hi = spec.bounds
        values[spec.name] = spec.choices[-1] if spec.choices else lo + (hi - lo) / 3.0
    model = MODEL.replace(cls(**values))
    path = save_spec(model, tmp_path / "m.toml")
    back = load_spec(path)
    assert back == model
    assert back[name].parameters() == cls(**values).parameters()
