"""`airwake bench` section "cli": how long the command line takes to answer.

- `cli_help_s`: wall time of `airwake --help` in a fresh process (the installed console
  script), median of 5 (target < 0.3 s; issue 22). Imports are what it measures:
  tests/test_cli.py checks that no heavy package is loaded, this times what is left.
- `cli_subcommand_help_s`: the same for `airwake sim run --help`, the deepest command.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path

SECTION = "cli"


def _median_wall_s(argv: list[str], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def run(quick: bool) -> dict:
    script = Path(sys.executable).with_name("airwake")
    command = [str(script)] if script.exists() else [sys.executable, "-m", "airwake.cli"]
    return {
        "cli_help_s": round(_median_wall_s(command + ["--help"], 5), 3),
        "cli_subcommand_help_s": round(_median_wall_s(command + ["sim", "run", "--help"], 5), 3),
    }
