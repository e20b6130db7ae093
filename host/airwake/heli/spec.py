"""TOML model specs: which effects, in which order, with which parameter values.

    [model]
    name = "table51"
    description = "..."
    effects = ["atmosphere", "rigid_body", "gravity", "main_rotor", ...]   # evaluation order
    plugins = ["my_effect.py"]            # optional, relative to this file

    [effects.main_rotor]
    lock_number = 4.486
    ...

`load_spec(path)` builds the `HeliModel` (`load_model(spec_or_model)` also passes a model
through: what every command's `--model` goes through); `save_spec(model, path)` writes
every parameter value (floats as Python's shortest round-trip repr), so
load(save(m)) == m exactly, atomically: a temporary file beside `path`, loaded back and
renamed over it, so a failure never leaves half a spec (or touches the previous one).
A spec written by `airwake calibrate` also carries a `[calibration]` table (the flight,
the method and the envelope of air velocities and rates it covered, which the wind
estimator checks its flights against); `spec_calibration(path)` reads it, the model
ignores it.
"""

from __future__ import annotations

import os
import tempfile
import tomllib
from pathlib import Path

import tomli_w

from airwake.errors import AirwakeError
from airwake.heli.effects.base import EffectError, effect_class, effect_source
from airwake.heli.model import HeliModel

SPEC_DIR = Path(__file__).resolve().parent / "specs"
HEADER = "# airwake helicopter model spec (see docs/effects.md)\n"


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


def load_model(spec) -> HeliModel:
    """The model a spec file path or shipped name builds; a HeliModel passes through.
    Every failure is one error naming the spec: SpecError/EffectError, and a user
    plugin's own exception (a bug in its effect's __init__) turned into a SpecError."""
    if isinstance(spec, HeliModel):
        return spec
    try:
        return load_spec(spec)
    except AirwakeError:
        raise
    except Exception as exc:  # noqa: BLE001 — user code: one line naming the spec
        raise SpecError(f"model spec {spec}: {type(exc).__name__}: {exc}") from None


def spec_dict(model: HeliModel, name: str = "", description: str = "", base_dir=None) -> dict:
    plugins = []
    for e in model.effects:
        src = effect_source(e.name)
        if src and src not in plugins:
            plugins.append(src)
    if base_dir is not None:
        plugins = [os.path.relpath(s, base_dir) for s in plugins]
    head = {"name": name, "description": description, "effects": model.effect_names}
    if plugins:
        head["plugins"] = plugins
    values = {e.name: e.parameters() for e in model.effects if e.PARAMETERS}
    return {"model": head, "effects": values}


def check_spec_path(path) -> Path:
    """`path` as a spec can be written there (a .toml file in an existing directory), else
    SpecError; commands call it before a long fit, `save_spec` before writing."""
    p = Path(path)
    if p.suffix.lower() != ".toml":
        raise SpecError(f"{p}: a model spec is a .toml file")
    if not p.parent.is_dir():
        raise SpecError(f"cannot write {p}: directory {p.parent} does not exist")
    return p


def save_spec(model: HeliModel, path, name: str = "", description: str = "",
              calibration: dict | None = None) -> Path:
    """Write `model` as a TOML spec (every parameter value, exactly), with an optional
    [calibration] table: to a temporary file in the target directory (plugin paths are
    written relative to it), loaded back (it must build the same model), then renamed
    over `path`. On any failure the temporary file is removed and `path` untouched."""
    p = check_spec_path(path)
    data = spec_dict(model, name or p.stem, description, base_dir=p.parent.resolve())
    if calibration:
        data["calibration"] = calibration
    fd, tmp_name = tempfile.mkstemp(prefix=f".{p.stem}.", suffix=".toml", dir=p.parent)
    tmp = Path(tmp_name)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(HEADER + tomli_w.dumps(data))
        if load_spec(tmp) != model:
            raise SpecError(f"{p}: the written spec does not load back the same model")
        os.chmod(tmp, 0o644)  # mkstemp makes it private; a spec is an ordinary file
        os.replace(tmp, p)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
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
