"""`airwake bench`: the performance figures of every area in one JSON object.

Each area contributes a module named `bench` (`airwake/<area>/bench.py`,
`hil_sim/bench.py`, and `firmware/bench/bench.py` loaded by path from the source tree)
with

    SECTION = "link"                      # short name for --only
    def run(quick: bool) -> dict          # figures, keys as in docs/bench.md

Figures are measured in the same run as whatever they are compared with. A
section that fails reports `"<section>_error": "..."` instead of its figures so
one broken area never hides the others' numbers.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
import pkgutil
import sys
import time
import traceback
from pathlib import Path

import airwake

_EXTRA_BENCH_MODULES = ("airwake.cli_bench", "hil_sim.bench", "hil_sim.wind_bench",
                        "hil_sim.truth_bench")
# Bench modules that live outside the Python packages, relative to the repository root.
_REPO_BENCH_FILES = ("firmware/bench/bench.py",)
_REPO_ROOT = Path(__file__).resolve().parents[2]


def bench_modules() -> list[str]:
    names = [
        f"airwake.{info.name}.bench"
        for info in pkgutil.iter_modules(airwake.__path__)
        if info.ispkg and importlib.util.find_spec(f"airwake.{info.name}.bench")
    ]
    for name in _EXTRA_BENCH_MODULES:
        try:
            if importlib.util.find_spec(name):
                names.append(name)
        except ModuleNotFoundError:
            pass
    names.sort()
    names += [str(_REPO_ROOT / rel) for rel in _REPO_BENCH_FILES if (_REPO_ROOT / rel).is_file()]
    return names


def _load(name: str):
    if name.endswith(".py"):
        label = f"_airwake_bench_{Path(name).parent.name}"
        spec = importlib.util.spec_from_file_location(label, name)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module
    return importlib.import_module(name)


def run_all(only: list[str] | None, quick: bool, log=sys.stderr) -> dict:
    figures: dict = {}
    for name in bench_modules():
        module = _load(name)
        section = getattr(module, "SECTION", name.split(".")[-2])
        if only and section not in only:
            continue
        print(f"bench: {section} …", file=log, flush=True)
        t0 = time.perf_counter()
        try:
            figures.update(module.run(quick=quick))
        except Exception as exc:  # noqa: BLE001 — one area's failure must not hide the rest
            traceback.print_exc(file=log)
            figures[f"{section}_error"] = f"{type(exc).__name__}: {exc}"
        print(f"bench: {section} done in {time.perf_counter() - t0:.1f} s", file=log, flush=True)
    return figures


def _handle(args: argparse.Namespace) -> int:
    figures = run_all(args.only, args.quick)
    if args.json:
        print(json.dumps(figures, indent=2, sort_keys=True))
    else:
        width = max((len(k) for k in figures), default=0)
        for key in sorted(figures):
            value = figures[key]
            text = f"{value:.6g}" if isinstance(value, float) else str(value)
            print(f"{key:<{width}}  {text}")
    return 1 if any(k.endswith("_error") for k in figures) else 0


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "bench", help="measure the performance figures (keys and targets: docs/bench.md)",
        description="Measure every area's performance figures and print them as one object "
        "(keys, targets and where each is measured: docs/bench.md).")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--only", nargs="+", metavar="SECTION", help="run only these sections")
    p.add_argument("--quick", action="store_true", help="smaller workloads (smoke test)")
    p.set_defaults(func=_handle)
