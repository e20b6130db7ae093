"""Helicopter model from pluggable effects (reference ch. 5, eq 5.1-5.15).

Public API:
    HeliModel, Context, MEAS_CHANNELS, INPUT_NAMES, WIND_NAMES
    Effect, Parameter, State, register_effect, registered_effects, effect_class
    default_effects(), load_spec(path), save_spec(model, path), builtin_spec(name)
    load_plugin(path)
    rk4_step, simulate                          (airwake.heli.integrate)
    trim_hover, linearize                       (airwake.heli.trim)
    predict_measurements, reconstruct_hidden    (airwake.heli.measurement)
"""

from airwake.heli.context import MEAS_CHANNELS, Context
from airwake.heli.effects import (
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
from airwake.heli.model import INPUT_NAMES, WIND_NAMES, HeliModel
from airwake.heli.plugins import load_plugin
from airwake.heli.spec import SpecError, builtin_spec, load_spec, save_spec, spec_calibration


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
    "spec_calibration",
]
