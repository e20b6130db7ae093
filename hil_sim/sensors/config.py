"""Config dataclasses from plain dicts (TOML tables), with errors that name the key.

Every sensor, wind-field, turbulence and ship config in hil_sim is a frozen dataclass
whose `__post_init__` checks its values with the `check_*` helpers below. A scenario
file holds the same names as plain tables; `config_from_dict(Cls, table, where)` builds
the dataclass, converting lists to tuples and nested tables to nested configs, and
raises `ValueError` naming the key path and the bad value:

    ValueError: wind.turbulence: unknown key 'lenght_scale_m' (known: ...)
    ValueError: sensors.vn200: rate_hz = -1.0: must be > 0
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from collections.abc import Mapping
from typing import Any, TypeVar

T = TypeVar("T")


def check_positive(name: str, value: float) -> None:
    if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
        raise ValueError(f"{name} = {value!r}: must be a finite number > 0")


def check_nonnegative(name: str, value: float) -> None:
    if not (isinstance(value, int | float) and math.isfinite(value) and value >= 0):
        raise ValueError(f"{name} = {value!r}: must be a finite number >= 0")


def check_finite(name: str, value: Any) -> None:
    values = value if isinstance(value, tuple | list) else (value,)
    for v in values:
        if isinstance(v, tuple | list):
            check_finite(name, v)
        elif not (isinstance(v, int | float) and math.isfinite(v)):
            raise ValueError(f"{name} = {value!r}: must be finite numbers")


def check_range(name: str, value: float, lo: float, hi: float) -> None:
    if not (isinstance(value, int | float) and lo <= value <= hi):
        raise ValueError(f"{name} = {value!r}: must be in [{lo}, {hi}]")


def check_choice(name: str, value: str, choices: tuple[str, ...]) -> None:
    if value not in choices:
        raise ValueError(f"{name} = {value!r}: must be one of {', '.join(choices)}")


def config_from_dict(cls: type[T], table: Mapping[str, Any] | T | None, where: str) -> T:
    """Build the frozen dataclass `cls` from a table; defaults fill missing keys."""
    if table is None:
        return cls()
    if isinstance(table, cls):
        return table
    if not isinstance(table, Mapping):
        raise ValueError(f"{where}: expected a table of settings, got {table!r}")
    hints = typing.get_type_hints(cls)
    known = [f.name for f in dataclasses.fields(cls) if f.init]
    for key in table:
        if key not in known:
            raise ValueError(f"{where}: unknown key {key!r} (known: {', '.join(known)})")
    kwargs = {key: _coerce(hints[key], value, f"{where}.{key}") for key, value in table.items()}
    try:
        return cls(**kwargs)
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None


def config_to_dict(config: Any) -> dict[str, Any]:
    """The inverse of `config_from_dict` (tuples as lists), for metadata and round trips."""

    def plain(v: Any) -> Any:
        if dataclasses.is_dataclass(v):
            return {f.name: plain(getattr(v, f.name)) for f in dataclasses.fields(v)}
        if isinstance(v, tuple | list):
            return [plain(x) for x in v]
        return v

    return plain(config)


def _coerce(hint: Any, value: Any, where: str) -> Any:
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin in (typing.Union, types.UnionType):
        if value is None and type(None) in args:
            return None
        options = [a for a in args if a is not type(None)]
        errors = []
        for option in options:
            try:
                return _coerce(option, value, where)
            except ValueError as exc:
                errors.append(str(exc))
        raise ValueError(errors[0])
    if dataclasses.is_dataclass(hint):
        return config_from_dict(hint, value, where)
    if origin is tuple:
        if not isinstance(value, list | tuple):
            raise ValueError(f"{where} = {value!r}: expected a list")
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_coerce(args[0], v, f"{where}[{i}]") for i, v in enumerate(value))
        if len(value) != len(args):
            raise ValueError(f"{where} = {value!r}: expected a list of {len(args)} values")
        return tuple(_coerce(a, v, f"{where}[{i}]") for i, (a, v) in enumerate(zip(args, value,
                                                                                    strict=True)))
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ValueError(f"{where} = {value!r}: expected a number")
        return float(value)
    if hint is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueError(f"{where} = {value!r}: expected an integer")
        return value
    if hint is bool:
        if not isinstance(value, bool):
            raise ValueError(f"{where} = {value!r}: expected true or false")
        return value
    if hint is str:
        if not isinstance(value, str):
            raise ValueError(f"{where} = {value!r}: expected a string")
        return value
    return value
