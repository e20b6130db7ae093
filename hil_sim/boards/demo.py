"""`make demo`: a ship-airwake SIL flight through the whole chain, ending in the report.

    python -m hil_sim.boards.demo [--out build/demo] [--duration 60] [--scenario NAME]

1. `airwake sim run`: the truth world flies `ship_airwake_b0` (lateral sweeps behind the
   hangar), the native rover and base firmware read its VN200, Piksi, RC and rotor
   signals, the real daemon records them from the base's pty (stepped, deterministic).
2. `airwake export`: the recording becomes a flight table.
3. `airwake model report`: model versus measurement, where it fails, the suggested
   effect, the error after adding it (HTML + PNG).

Each step is the command a user would type (run here as `python -m airwake.cli ...`).
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import time
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[2]


def _airwake(*args: str) -> None:
    cmd = [sys.executable, "-m", "airwake.cli", *args]
    print(f"\n$ airwake {' '.join(args)}", flush=True)
    done = subprocess.run(cmd, cwd=REPO_ROOT)
    if done.returncode != 0:
        raise SystemExit(f"demo: `airwake {args[0]} {args[1] if len(args) > 1 else ''}` "
                         f"failed with exit status {done.returncode}")


def _has_model_report() -> bool:
    cmd = [sys.executable, "-m", "airwake.cli", "model", "report", "--help"]
    return subprocess.run(cmd, cwd=REPO_ROOT, capture_output=True).returncode == 0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil_sim.boards.demo", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=str(REPO_ROOT / "build" / "demo"),
                   help="output directory (replaced; default build/demo)")
    p.add_argument("--scenario", default="ship_airwake_b0")
    p.add_argument("--duration", type=float, default=60.0, help="simulated seconds")
    args = p.parse_args(argv)
    out = Path(args.out)
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    rec, flight, report = out / "recording", out / "flight.parquet", out / "report"
    t0 = time.monotonic()
    _airwake("sim", "run", "--scenario", args.scenario, "--duration", f"{args.duration:g}",
             "--stepped", "--out", str(rec))
    _airwake("export", str(rec), "--out", str(flight))
    if not _has_model_report():
        print(f"\ndemo: `airwake model report` is not available in this tree; the flight "
              f"table is {flight}", flush=True)
        return 0
    _airwake("model", "report", str(flight), "--out", str(report))
    print(f"\ndemo done in {time.monotonic() - t0:.0f} s:\n  recording    {rec}\n"
          f"  flight table {flight}\n  report       {report / 'index.html'}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
