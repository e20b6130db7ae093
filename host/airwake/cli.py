"""The `airwake` command: a thin dispatcher over the areas' own sub-commands.

Each area registers its sub-commands in a module named `commands` that defines
`register(subparsers)` (e.g. `airwake/link/commands.py` adds `decode`,
`hil_sim/commands.py` adds `sim`). Adding a command never edits this file.
`commands` modules must import only argparse-level things at module scope, and so must
their packages' `__init__` (`airwake.lazy`): heavy imports (numpy, torch, scipy, pandas)
go inside the handlers so `airwake --help`, every `airwake X --help` and an argument error
answer at once (tests/test_cli_imports.py checks which modules they load).

A handler is stored with `parser.set_defaults(func=handler)`; it receives the
parsed namespace and returns an exit status (or None for 0).
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import pkgutil
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path

import airwake
from airwake.errors import AirwakeError

# Packages outside `airwake` that contribute commands.
_EXTRA_COMMAND_MODULES = ("hil_sim.commands",)


def _command_modules() -> list[str]:
    names = []
    for info in pkgutil.iter_modules(airwake.__path__):
        # listed from the folder, not `find_spec`, which would import every area's
        # package (airwake.heli: numba) just to ask
        if info.ispkg and any(sub.name == "commands" for sub in pkgutil.iter_modules(
                [str(Path(info.module_finder.path) / info.name)])):
            names.append(f"airwake.{info.name}.commands")
    names.append("airwake.bench")
    for name in _EXTRA_COMMAND_MODULES:
        try:
            if importlib.util.find_spec(name):
                names.append(name)
        except ModuleNotFoundError:
            pass
    return sorted(names)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="airwake",
        description="airwake: RC-helicopter ship-airwake sensing — firmware link, "
        "recording, simulation and analysis.",
    )
    parser.add_argument("--version", action="version", version=f"airwake {airwake.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in _command_modules():
        importlib.import_module(name).register(sub)
    return parser


def _one_line_warnings(command: str):
    """`warnings.showwarning` for the command: airwake's own warnings (e.g.
    `FlightTableWarning`: an implausible column the command does not read) as one line
    on stderr; others as Python prints them."""
    default = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None):
        if category.__module__.startswith("airwake."):
            print(f"airwake {command}: warning: {message}", file=file or sys.stderr)
        else:
            default(message, category, filename, lineno, file, line)

    return show


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    func = getattr(args, "func", None)
    if func is None:
        # A command group given without its sub-command: show that group's help.
        (getattr(args, "_group_parser", None) or parser).print_help(sys.stderr)
        return 2
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _one_line_warnings(args.command)
            status = func(args)
    except AirwakeError as exc:
        print(f"airwake {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"airwake {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    return 0 if status is None else int(status)


if __name__ == "__main__":
    sys.exit(main())
