"""The effect registry, the base model's effects and the catalogue (`catalogue/`), all
imported here so they register: any import of `airwake.heli` knows every effect name."""

from airwake.heli.effects.atmosphere import Atmosphere
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
from airwake.heli.effects.empennage import Empennage
from airwake.heli.effects.flybar import Flybar
from airwake.heli.effects.fuselage import Fuselage
from airwake.heli.effects.gravity import Gravity
from airwake.heli.effects.main_rotor import MainRotor
from airwake.heli.effects.pitt_peters_inflow import PittPetersInflow
from airwake.heli.effects.rigid_body import RigidBody
from airwake.heli.effects.tail_rotor import TailRotor

# isort: split
# the catalogue after the base model's effects: the registry (and docs/effects.md) lists
# the base model first
from airwake.heli.effects.catalogue import CATALOGUE_EFFECTS

__all__ = [
    "STAGES", "Effect", "EffectError", "Parameter", "State", "effect_class", "effect_info",
    "effect_source", "register_effect", "registered_effects", "unregister_effect",
    "Atmosphere", "Empennage", "Flybar", "Fuselage", "Gravity", "MainRotor",
    "PittPetersInflow", "RigidBody", "TailRotor", "CATALOGUE_EFFECTS",
]
