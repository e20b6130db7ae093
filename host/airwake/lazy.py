"""Package attributes imported on first use (PEP 562), so that importing a package —
as `airwake --help` imports every area's `commands` module, and with it the area's
`__init__` — costs nothing until a name is used.

    # airwake/nets/__init__.py
    __getattr__, __dir__ = lazy_exports(__name__, {"train_net": "airwake.nets.train", ...})
"""

from __future__ import annotations

import sys
from importlib import import_module


def lazy_exports(package: str, exports: dict[str, str]):
    """The `(__getattr__, __dir__)` pair of a package whose name `n` is
    `exports[n]`'s attribute `n`, imported when first read and then kept."""

    def __getattr__(name: str):
        module = exports.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(import_module(module), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(exports))

    return __getattr__, __dir__
