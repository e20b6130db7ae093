"""Model specs round-trip exactly; user plugins load, clash and fail clearly."""

import numpy as np
import pytest
from airwake.heli import default_model, load_model, load_plugin, load_spec, save_spec
from airwake.heli.effects.base import EffectError, registered_effects
from airwake.heli.plugins import forget_plugin
from airwake.heli.spec import SpecError
from hypothesis import given, settings
from hypothesis import strategies as st

MODEL = default_model()
SPECS = MODEL.parameter_specs()


def _value(spec):
    if spec.choices:
        return st.sampled_from(spec.choices)
    return st.floats(spec.bounds[0], spec.bounds[1], allow_nan=False, allow_infinity=False)


@settings(max_examples=40, deadline=None)
@given(st.fixed_dictionaries({k: _value(s) for k, s in SPECS.items()}))
def test_spec_round_trips_every_parameter_exactly(tmp_path_factory, values):
    model = MODEL.with_parameters(values)
    path = save_spec(model, tmp_path_factory.mktemp("spec") / "m.toml")
    back = load_spec(path)
    assert back == model
    np.testing.assert_array_equal(back.parameter_vector(), model.parameter_vector())


def test_shipped_specs_load_and_table51_is_the_defaults():
    assert load_spec("table51") == MODEL
    t52 = load_spec("table52")
    assert t52["main_rotor"].parameters()["flap_stiffness_nm_rad"] == 297.16
    assert t52.effect_names == MODEL.effect_names


def test_spec_errors_name_the_file_and_the_problem(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text('[model]\neffects = ["rigid_body", "warp_drive"]\n')
    with pytest.raises(SpecError, match=r"bad.toml.*unknown effect 'warp_drive'"):
        load_spec(p)
    p.write_text('[model]\neffects = ["rigid_body"]\n[effects.rigid_body]\nmass_kg = -3\n')
    with pytest.raises(SpecError, match=r"bad.toml.*rigid_body.*mass_kg.*-3"):
        load_spec(p)
    with pytest.raises(SpecError, match="not found"):
        load_spec(tmp_path / "missing.toml")


def test_load_model_takes_a_model_a_name_or_a_path(tmp_path):
    # every command's --model goes through load_model: the same model whichever way
    assert load_model(MODEL) is MODEL
    assert load_model("table51") == MODEL
    assert load_model(save_spec(MODEL, tmp_path / "m.toml")) == MODEL
    with pytest.raises(SpecError, match="table99"):
        load_model("table99")


PLUGIN_INIT_RAISES = '''
from airwake.heli import Effect, register_effect

@register_effect("test_init_raises")
class InitRaises(Effect):
    def __init__(self, **values):
        raise KeyError("bug in the plugin")
'''


def test_load_model_turns_a_plugin_bug_into_one_line_naming_the_spec(tmp_path):
    # a user's effect that raises something other than ValueError/TypeError must not
    # escape as a traceback from deep inside the spec loader
    plugin = tmp_path / "init_raises.py"
    plugin.write_text(PLUGIN_INIT_RAISES)
    spec = tmp_path / "uses_it.toml"
    spec.write_text('[model]\neffects = ["test_init_raises"]\nplugins = ["init_raises.py"]\n')
    try:
        with pytest.raises(SpecError, match=r"uses_it.toml: KeyError.*bug in the plugin"):
            load_model(spec)
    finally:
        forget_plugin(plugin)


def test_save_spec_is_atomic_and_a_failed_write_leaves_the_old_file(tmp_path, monkeypatch):
    # an interrupted or failing save must never leave half a spec or a stray temp file
    out = tmp_path / "m.toml"
    out.write_text("# the previous spec\n")
    import airwake.heli.spec as spec_mod

    def fail(*_a, **_k):
        raise OSError("disk full")

    monkeypatch.setattr(spec_mod.os, "replace", fail)
    with pytest.raises(OSError, match="disk full"):
        save_spec(MODEL, out)
    assert out.read_text() == "# the previous spec\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.toml"]
    monkeypatch.undo()
    assert load_spec(save_spec(MODEL, out)) == MODEL
    assert out.stat().st_mode & 0o777 == 0o644


def test_save_spec_refuses_a_non_toml_name_or_a_missing_directory(tmp_path):
    with pytest.raises(SpecError, match="a model spec is a .toml file"):
        save_spec(MODEL, tmp_path / "m.txt")
    with pytest.raises(SpecError, match="does not exist"):
        save_spec(MODEL, tmp_path / "no" / "m.toml")
    assert list(tmp_path.iterdir()) == []


def test_parameter_vector_interface_names_bounds_fixed():
    names = MODEL.parameter_names
    assert "main_rotor.flap_stiffness_nm_rad" in names
    lo, hi = MODEL.bounds()
    vec = MODEL.parameter_vector()
    assert np.all(lo <= vec) and np.all(vec <= hi)
    fixed = dict(zip(names, MODEL.fixed_mask(), strict=True))
    assert fixed["rigid_body.mass_kg"] and fixed["main_rotor.radius_m"]
    assert not fixed["main_rotor.flap_stiffness_nm_rad"]
    vec2 = vec.copy()
    vec2[names.index("rigid_body.Ixx_kg_m2")] = 0.5
    assert MODEL.with_parameters(vec2)["rigid_body"].parameters()["Ixx_kg_m2"] == 0.5
    vec2[names.index("rigid_body.Ixx_kg_m2")] = -1.0
    with pytest.raises(ValueError, match="rigid_body.*Ixx_kg_m2"):
        MODEL.with_parameters(vec2)


PLUGIN = '''
import numpy as np
from airwake.heli import Effect, Parameter, register_effect

@register_effect("test_tail_drag")
class TailDrag(Effect):
    """Extra drag on the tail boom: F_y = -k v |v| at the tail."""
    PARAMETERS = (Parameter("k", 0.01, "kg/m", (0.0, 1.0), "fitted"),)

    def forces(self, ctx, p):
        v = ctx.air_velocity_at(np.array([-0.8, 0.0, 0.0]))
        f = np.zeros((ctx.n, 3))
        f[:, 1] = p.k * v[:, 1] * np.abs(v[:, 1])
        ctx.add_load(self.name, f, np.cross([-0.8, 0.0, 0.0], f))
'''


def test_plugin_registers_an_effect_that_joins_a_model_and_its_spec(tmp_path):
    path = tmp_path / "my_effect.py"
    path.write_text(PLUGIN)
    try:
        assert load_plugin(path) == ["test_tail_drag"]
        cls = registered_effects()["test_tail_drag"]
        model = MODEL + cls(k=0.2)
        x = model.zero_state(1)
        x[0, 4] = 3.0  # sideslip
        ctx = model.evaluate(x, np.array([[0.09, 0, 0, 0.1]]))
        assert ctx.loads["test_tail_drag"][0][0, 1] < 0
        spec = save_spec(model, tmp_path / "with_plugin.toml")
        assert "my_effect.py" in spec.read_text()
        forget_plugin(path)  # a fresh process: the spec must load the plugin itself
        assert load_spec(spec) == HeliModelEq(model)
    finally:
        forget_plugin(path)


class HeliModelEq:
    """Compare models by effect names and parameter values (plugin classes are re-imported)."""

    def __init__(self, model):
        self.model = model

    def __eq__(self, other):
        return other.effect_names == self.model.effect_names and np.array_equal(
            other.parameter_vector(), self.model.parameter_vector()
        )


def test_plugin_with_a_clashing_name_is_refused(tmp_path):
    path = tmp_path / "clash.py"
    path.write_text(PLUGIN.replace("test_tail_drag", "main_rotor"))
    with pytest.raises(EffectError, match=r"clash.py.*'main_rotor' is already registered"):
        load_plugin(path)
    assert registered_effects()["main_rotor"].__module__.startswith("airwake.heli")


def test_plugin_that_fails_to_import_names_file_and_error(tmp_path):
    path = tmp_path / "broken.py"
    path.write_text(PLUGIN + "\nraise RuntimeError('boom')\n")
    with pytest.raises(EffectError, match=r"broken.py failed to import: RuntimeError: boom"):
        load_plugin(path)
    assert "test_tail_drag" not in registered_effects()
    with pytest.raises(EffectError, match="not found"):
        load_plugin(tmp_path / "nothing.py")
