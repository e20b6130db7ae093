"""Effect base class, parameter metadata and the effect registry.

An *effect* is one physical contribution to the helicopter model (STYLE 11): the main
rotor, the tail rotor, gravity, a servo lag, an IMU lever arm … Each is a small class
that declares its named parameters (with unit, bounds, source, fixed flag), its own
states (if any) and implements any of the pipeline *stages* below. `__init__` only
validates and stores parameter values; the stage methods do the work on a batch.

Stages, called in this order (within a stage, in the order the model lists its effects;
the tuple is `airwake.heli.pipeline.STAGES`):

    environment(ctx, p)    air density, gravity, … (ctx.air_density_kg_m3, ctx.gravity_m_s2)
    inputs(ctx, p)         transform the pilot inputs ctx.delta_col/lat/lon/ped_rad
                           (servo lag, trims); may read the effect's own states
    rotor_speed(ctx, p)    set/modify ctx.rotor_speed_rad_s (governor, droop)
    rotor_setup(ctx, p)    hub kinematics: air velocity at the hub, advance ratios, rotor frame
    blade_pitch(ctx, p)    pilot inputs -> blade pitch (swashplate, flybar mixing)
    rotor_loading(ctx, p)  rotor loads as an affine function of the inflow (for the inflow solve)
    inflow(ctx, p)         solve / modify the rotor inflow ctx.inflow_0/c/s (ground effect here)
    forces(ctx, p)         add forces and moments: ctx.add_load(name, F, M) (body axes, about CG)
    state_rates(ctx, p)    derivatives of the effect's own states: ctx.set_rates(name, rates)
    body_dynamics(ctx, p)  (rigid body only) total load -> body state derivatives + measurement
    measurement(ctx, p)    transform the predicted measurement ctx.meas (lever arm, bias, …)

Two ways to write a stage (docs/effects.md, "Writing an effect"):
- kernel (fast): `@kernel def stage(q, p, s, ds, load, scratch)` compiled with numba for one
  row (see `airwake.heli.kernel`); the model fuses all kernel stages of a composition into
  one compiled function.
- numpy (simple): `def stage(self, ctx, p)` on the whole batch; `p` is a namespace of the
  effect's parameter values: floats, or (N,) arrays when the caller evaluates N parameter
  sets at once. Runs between the compiled segments, slower but no compilation.
"""

from __future__ import annotations

import math
from collections import namedtuple
from collections.abc import Sequence
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import ClassVar

from airwake.errors import AirwakeError
from airwake.heli.pipeline import STAGES


class EffectError(AirwakeError):
    """A registry/plugin problem: unknown effect, clashing name, failing plugin."""


@dataclass(frozen=True)
class Parameter:
    """Metadata of one named effect parameter."""

    name: str
    default: float
    unit: str
    bounds: tuple[float, float]
    source: str = "Table 5.1"
    fixed: bool = False
    doc: str = ""
    choices: tuple[float, ...] | None = None  # discrete parameters (rotation sense, blade count)

    def check(self, effect: str, value) -> float:
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise ValueError(
                f"{effect}: parameter '{self.name}' = {value!r} is not a number"
            ) from None
        lo, hi = self.bounds
        if not math.isfinite(v) or not lo <= v <= hi:
            raise ValueError(
                f"{effect}: parameter '{self.name}' = {v!r} outside [{lo:g}, {hi:g}] {self.unit}"
            )
        if self.choices is not None and v not in self.choices:
            raise ValueError(
                f"{effect}: parameter '{self.name}' = {v!r} not one of {list(self.choices)}"
            )
        return v


@dataclass(frozen=True)
class State:
    """Metadata of one state owned by an effect."""

    name: str
    unit: str
    doc: str = ""


@dataclass
class _Registered:
    cls: type
    source: str | None  # plugin file, None for the package's own effects


_REGISTRY: dict[str, _Registered] = {}
_PLUGIN_SOURCE: list[str | None] = [None]  # set while a plugin file is being imported


def register_effect(name: str):
    """Class decorator: register an Effect subclass under `name` (used in specs)."""

    def deco(cls):
        if not (isinstance(cls, type) and issubclass(cls, Effect)):
            raise EffectError(f"@register_effect({name!r}) must decorate an Effect subclass")
        if not name.isidentifier():
            raise EffectError(f"effect name {name!r} must be a Python identifier")
        old = _REGISTRY.get(name)
        if old is not None and old.cls is not cls:
            where = old.source or f"package module {old.cls.__module__}"
            raise EffectError(f"effect name {name!r} is already registered (by {where})")
        cls.name = name
        _REGISTRY[name] = _Registered(cls, _PLUGIN_SOURCE[-1])
        return cls

    return deco


def unregister_effect(name: str) -> None:
    """Remove a registered effect (tests and plugin reloads)."""
    _REGISTRY.pop(name, None)


def registered_effects() -> dict[str, type]:
    """Name -> class of every registered effect, in registration order."""
    return {k: v.cls for k, v in _REGISTRY.items()}


def effect_source(name: str) -> str | None:
    """The plugin file that registered `name`, or None for the package's effects."""
    reg = _REGISTRY.get(name)
    return None if reg is None else reg.source


def effect_class(name: str) -> type:
    try:
        return _REGISTRY[name].cls
    except KeyError:
        known = ", ".join(sorted(_REGISTRY))
        raise EffectError(f"unknown effect {name!r}; registered effects: {known}") from None


class Effect:
    """Base class of every effect. Subclasses set PARAMETERS, STATES and stage methods."""

    name: ClassVar[str] = "effect"
    PARAMETERS: ClassVar[tuple[Parameter, ...]] = ()
    STATES: ClassVar[tuple[State, ...]] = ()
    # Flight-table column holding each state, for states the flight table measures.
    MEASURED_STATES: ClassVar[dict[str, str]] = {}
    # Effects this one reads context quantities from (documentation + model validation).
    REQUIRES: ClassVar[tuple[str, ...]] = ()
    # Kernel effects: private per-row floats kept between stages, and whether the load
    # written in `load` is felt by an accelerometer (False for field forces: gravity).
    SCRATCH: ClassVar[int] = 0
    LOAD_SENSED: ClassVar[bool] = True
    # Effects that must come before this one in the model when they are in it (a stage
    # that adds to what they write); the model refuses another order.
    AFTER: ClassVar[tuple[str, ...]] = ()
    # Effects that act on what every effect before them produced (a lag of the total
    # inflow): `model + effect` inserts a new effect before the trailing run of these.
    KEEP_LAST: ClassVar[bool] = False

    def __init__(self, **values) -> None:
        specs = {p.name: p for p in self.PARAMETERS}
        unknown = sorted(set(values) - set(specs))
        if unknown:
            raise ValueError(
                f"{self.name}: unknown parameter(s) {unknown}; expected some of {list(specs)}"
            )
        self._values = {
            p.name: p.check(self.name, values.get(p.name, p.default)) for p in self.PARAMETERS
        }

    # -- parameters -------------------------------------------------------------------
    def parameters(self) -> dict[str, float]:
        """Current parameter values, in declaration order."""
        return dict(self._values)

    @classmethod
    def parameter_specs(cls) -> tuple[Parameter, ...]:
        return cls.PARAMETERS

    def with_values(self, **values) -> Effect:
        """A new effect of the same class with some parameters changed."""
        return type(self)(**{**self._values, **values})

    def params(self) -> SimpleNamespace:
        return SimpleNamespace(**self._values)

    @classmethod
    def parameter_tuple(cls) -> type:
        """The namedtuple a kernel stage receives as `p` (one float per parameter)."""
        tup = cls.__dict__.get("_parameter_tuple")
        if tup is None:
            tup = namedtuple(f"{cls.__name__}Params", [p.name for p in cls.PARAMETERS])
            # importable by name (module.Class._parameter_tuple): numba's cache keys
            # compiled kernels by their argument types and pickles this class by reference
            tup.__module__ = cls.__module__
            tup.__qualname__ = f"{cls.__qualname__}._parameter_tuple"
            cls._parameter_tuple = tup
        return tup

    # -- composition ------------------------------------------------------------------
    def __add__(self, other):
        from airwake.heli.model import HeliModel

        return HeliModel([self]) + other

    def __repr__(self) -> str:
        inner = ", ".join(f"{k}={v:g}" for k, v in self._values.items())
        return f"{type(self).__name__}({inner})"

    def __eq__(self, other) -> bool:
        return type(self) is type(other) and self._values == other._values

    def __hash__(self) -> int:
        return hash((type(self), tuple(self._values.items())))


@dataclass
class EffectInfo:
    """A catalogue entry (used to generate docs/effects.md)."""

    name: str
    cls: type
    doc: str
    parameters: Sequence[Parameter]
    states: Sequence[State]
    stages: list[str] = field(default_factory=list)


def effect_info(name: str) -> EffectInfo:
    cls = effect_class(name)
    stages = [s for s in STAGES if getattr(cls, s, None) is not getattr(Effect, s, None)]
    return EffectInfo(name, cls, (cls.__doc__ or "").strip(), cls.PARAMETERS, cls.STATES, stages)


def col(v):
    """A parameter (float or (N,) array) shaped to broadcast against (N, K) arrays."""
    return v[:, None] if getattr(v, "ndim", 0) == 1 else v
