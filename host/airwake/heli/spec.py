"""TOML model specs: which effects, in which order, with which parameter values.

    [model]
    name = "table51"
    description = "..."
    effects = ["atmosphere", "rigid_body", "gravity", "main_rotor", ...]   # evaluation order
    plugins = ["my_effect.py"]            # optional, relative to this file

    [effects.main_rotor]
    lock_number = 4.486
    ...

`load_spec(path)` builds the `HeliModel`; `save_spec(model, path)` writes every parameter
value (floats as Python's shortest round-trip repr), so load(save(m)) == m exactly.
A spec written by `airwake calibrate` also carries a `[calibration]` table (the flight,
the method and the envelope of air velocities and rates it covered, which the wind
estimator checks its flights against); `spec_calibration(path)` reads it, the model
ignores it.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import tomli_w

from airwake.errors import AirwakeError
from airwake.heli.effects.base import EffectError, effect_class, effect_source
from airwake.heli.model import HeliModel

SPEC_DIR = Path(__file__).resolve().parent / "specs"


class SpecError(AirwakeError):
    """A model spec that cannot be read or built (file, key and value named)."""


def builtin_spec(name: str) -> Path:
    """Path of a shipped spec ('table51', 'table52')."""
    path = SPEC_DIR / f"{name}.toml"
    if not path.is_file():
        known = sorted(p.stem for p in SPEC_DIR.glob("*.toml"))
        raise SpecError(f"no shipped model spec {name!r}; shipped: {known}")
    return path


def load_spec(path) -> HeliModel:
    """Build a model from a TOML spec file (or a shipped spec name such as 'table52')."""
    from airwake.heli.plugins import load_plugin

    p = Path(path)
    if not p.suffix and not p.exists():
        p = builtin_spec(str(path))
    try:
        data = tomllib.loads(p.read_text())
    except FileNotFoundError:
        raise SpecError(f"model spec {p} not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"{p}: not valid TOML: {exc}") from None
    unknown = sorted(set(data) - {"model", "effects", "calibration"})
    if unknown:
        raise SpecError(f"{p}: unknown top-level key(s) {unknown}; expected [model], "
                        "[effects.*], [calibration]")
    model = data.get("model", {})
    names = model.get("effects")
    if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
        raise SpecError(f"{p}: [model] effects must be a list of effect names")
    for plugin in model.get("plugins", []):
        ppath = Path(plugin)
        load_plugin(ppath if ppath.is_absolute() else p.parent / ppath)
    values = data.get("effects", {})
    extra = sorted(set(values) - set(names))
    if extra:
        raise SpecError(f"{p}: [effects.{extra[0]}] is not listed in [model] effects")
    effects = []
    for name in names:
        try:
            cls = effect_class(name)
        except EffectError as exc:
            raise SpecError(f"{p}: {exc}") from None
        try:
            effects.append(cls(**values.get(name, {})))
        except (ValueError, TypeError) as exc:
            raise SpecError(f"{p}: [effects.{name}]: {exc}") from None
    try:
        return HeliModel(effects)
    except ValueError as exc:
        raise SpecError(f"{p}: {exc}") from None


def spec_dict(model: HeliModel, name: str = "", description: str = "", base_dir=None) -> dict:
    plugins = []
    for e in model.effects:
        src = effect_source(e.name)
        if src and src not in plugins:
            plugins.append(src)
    if base_dir is not None:
        import os

        plugins = [os.path.relpath(s, base_dir) for s in plugins]
    head = {"name": name, "description": description, "effects": model.effect_names}
    if plugins:
        head["plugins"] = plugins
    values = {e.name: e.parameters() for e in model.effects if e.PARAMETERS}
    return {"model": head, "effects": values}


def save_spec(model: HeliModel, path, name: str = "", description: str = "",
              calibration: dict | None = None) -> Path:
    """Write `model` as a TOML spec (every parameter value, exactly), with an optional
    [calibration] table."""
    p = Path(path)
    data = spec_dict(model, name or p.stem, description, base_dir=p.parent.resolve())
    if calibration:
        data["calibration"] = calibration
    text = tomli_w.dumps(data)
    header = "# airwake helicopter model spec (see docs/effects.md)\n"
    p.write_text(header + text)
    return p


def spec_calibration(spec) -> dict | None:
    """The [calibration] table of a spec file (None for a shipped name, a model object
    or a spec without one)."""
    if not isinstance(spec, (str, Path)):
        return None
    p = Path(spec)
    if not p.is_file():
        return None
    try:
        return tomllib.loads(p.read_text()).get("calibration")
    except (OSError, tomllib.TOMLDecodeError):
        return None
