"""User plugins: a Python file that defines and registers its own effects.

    # my_effect.py
    from airwake.heli import Effect, Parameter, register_effect

    @register_effect("tail_drag_error")
    class TailDragError(Effect):
        PARAMETERS = (Parameter("k", 0.0, "N s^2/m^2", (-1, 1), "fitted"),)
        def forces(self, ctx, p): ...

`load_plugin(path)` imports it (once per resolved path) without touching the package.
"""

from __future__ import annotations

import hashlib
import importlib.util
import sys
import traceback
from pathlib import Path

from airwake.heli.effects import base
from airwake.heli.effects.base import EffectError

_LOADED: dict[str, list[str]] = {}


def load_plugin(path) -> list[str]:
    """Import a plugin file; returns the effect names it registered.
    Raises EffectError when the file is missing, fails to import or clashes with a name."""
    p = Path(path).resolve()
    key = str(p)
    if key in _LOADED:
        return list(_LOADED[key])
    if not p.is_file():
        raise EffectError(f"plugin {path} not found")
    before = set(base._REGISTRY)
    # the same module name in every process (not Python's salted hash()): compiled kernels
    # of a plugin are cached on disk with their types pickled by module name
    digest = hashlib.sha256(key.encode()).hexdigest()[:8]
    mod_name = f"airwake_plugin_{p.stem}_{digest}"
    spec = importlib.util.spec_from_file_location(mod_name, p)
    module = importlib.util.module_from_spec(spec)
    base._PLUGIN_SOURCE.append(key)
    sys.modules[mod_name] = module
    try:
        spec.loader.exec_module(module)
    except EffectError as exc:
        _drop_new(before)
        sys.modules.pop(mod_name, None)
        raise EffectError(f"plugin {path}: {exc}") from None
    except Exception as exc:  # noqa: BLE001 — any error in user code becomes one clear line
        _drop_new(before)
        sys.modules.pop(mod_name, None)
        where = traceback.extract_tb(exc.__traceback__)[-1]
        raise EffectError(
            f"plugin {path} failed to import: {type(exc).__name__}: {exc} "
            f"(line {where.lineno} of {Path(where.filename).name})"
        ) from None
    finally:
        base._PLUGIN_SOURCE.pop()
    names = [n for n in base._REGISTRY if n not in before]
    if not names:
        raise EffectError(f"plugin {path} registered no effect (use @register_effect)")
    _LOADED[key] = names
    return list(names)


def _drop_new(before: set) -> None:
    for n in [n for n in base._REGISTRY if n not in before]:
        base.unregister_effect(n)


def forget_plugin(path) -> None:
    """Unregister a plugin's effects (tests; reloading an edited plugin)."""
    names = _LOADED.pop(str(Path(path).resolve()), [])
    for n in names:
        base.unregister_effect(n)
