"""The effect registry and the package's own effects (imported here so they register)."""

from airwake.heli.effects import (
    airframe,
    flybar,
    gravity,
    inflow,
    main_rotor,
    rigid_body,
    tail_rotor,
)
from airwake.heli.effects.airframe import Empennage, Fuselage
from airwake.heli.effects.base import (
    STAGES,
    Effect,
    EffectError,
    Parameter,
    State,
    effect_class,
    effect_info,
    effect_source,
    register_effect,
    registered_effects,
    unregister_effect,
)
from airwake.heli.effects.flybar import Flybar
from airwake.heli.effects.gravity import Atmosphere, Gravity
from airwake.heli.effects.inflow import PittPetersInflow
from airwake.heli.effects.main_rotor import MainRotor
from airwake.heli.effects.rigid_body import RigidBody
from airwake.heli.effects.tail_rotor import TailRotor

__all__ = [
    "STAGES", "Effect", "EffectError", "Parameter", "State", "effect_class", "effect_info",
    "effect_source", "register_effect", "registered_effects", "unregister_effect",
    "Atmosphere", "Empennage", "Flybar", "Fuselage", "Gravity", "MainRotor",
    "PittPetersInflow", "RigidBody", "TailRotor",
    "airframe", "flybar", "gravity", "inflow", "main_rotor", "rigid_body", "tail_rotor",
]
