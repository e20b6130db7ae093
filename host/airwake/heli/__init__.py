"""Helicopter model from pluggable effects (reference ch. 5, eq 5.1-5.15).

Public API:
    HeliModel, Context, MEAS_CHANNELS, INPUT_NAMES, WIND_NAMES
    Effect, Parameter, State, register_effect, registered_effects, effect_class
    CATALOGUE_EFFECTS                           (airwake.heli.effects.catalogue)
    default_effects(), default_model()
    load_model(spec_or_model), load_spec(path), builtin_spec(name), spec_calibration(path)
    save_spec(model, path, name=, description=, calibration=)   atomic; check_spec_path
    load_plugin(path)
    Stepper(model, dt, env, params).step(x, u, w, h, dt), rk4_step, simulate, Trajectory
    trim_hover, linearize                       (airwake.heli.trim)
    predict_measurements, reconstruct_hidden    (airwake.heli.measurement)
    kernel, kernel_function, Q, add_load, ...   (airwake.heli.kernel: writing effects)
The numba code generator behind the compiled paths is `airwake.heli.codegen`, private to
this package.
"""

from airwake.heli.context import MEAS_CHANNELS, Context
from airwake.heli.effects import (
    CATALOGUE_EFFECTS,
    Atmosphere,
    Effect,
    EffectError,
    Empennage,
    Flybar,
    Fuselage,
    Gravity,
    MainRotor,
    Parameter,
    PittPetersInflow,
    RigidBody,
    State,
    TailRotor,
    effect_class,
    register_effect,
    registered_effects,
)
from airwake.heli.integrate import Stepper, Trajectory, rk4_step, simulate
from airwake.heli.model import INPUT_NAMES, WIND_NAMES, HeliModel
from airwake.heli.plugins import load_plugin
from airwake.heli.spec import (
    SpecError,
    builtin_spec,
    check_spec_path,
    load_model,
    load_spec,
    save_spec,
    spec_calibration,
)


def default_effects() -> list[Effect]:
    """The reference model (Table 5.1 defaults), in evaluation order."""
    return [
        Atmosphere(),
        RigidBody(),
        Gravity(),
        MainRotor(),
        Flybar(),
        PittPetersInflow(),
        TailRotor(),
        Fuselage(),
        Empennage(),
    ]


def default_model() -> HeliModel:
    return HeliModel(default_effects())


__all__ = [
    "MEAS_CHANNELS", "INPUT_NAMES", "WIND_NAMES", "Context", "HeliModel",
    "Atmosphere", "Effect", "EffectError", "Empennage", "Flybar", "Fuselage", "Gravity",
    "MainRotor", "Parameter", "PittPetersInflow", "RigidBody", "State", "TailRotor",
    "effect_class", "register_effect", "registered_effects", "default_effects",
    "default_model", "load_plugin", "SpecError", "builtin_spec", "load_spec", "save_spec",
    "spec_calibration", "load_model", "check_spec_path", "CATALOGUE_EFFECTS", "Stepper",
    "Trajectory", "rk4_step", "simulate",
]
