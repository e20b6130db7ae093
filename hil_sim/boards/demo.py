"""`make demo`: a ship-airwake SIL flight through the whole chain, ending in an airwake map.

    python -m hil_sim.boards.demo [--out build/demo] [--duration 60] [--scenario NAME]

0. The baseline model, as a user makes it before going to sea: the still-air calibration
   flight (speed legs, chirps, bursts; `airwake sim table`, the truth world straight to a
   table) and `airwake calibrate` from the reference's Table 5.2 (the published
   calibration of this airframe class) on the parameters the flight identifies. Its
   report says which wind components the model can be trusted for.
1. `airwake sim run`: the truth world flies `ship_airwake_b0` (lateral sweeps behind the
   hangar), the native rover and base firmware read its VN200, Piksi, RC and rotor
   signals, the real daemon records them from the base's pty (stepped, deterministic).
2. `airwake export`: the recording becomes a flight table (the hub in the ship frame);
   `airwake sim truth` puts the truth world's truth_* columns beside it, for scoring.
3. `airwake wind estimate`: the 6-D wind along the flight (the smoother), scored against
   the simulator's truth (a simulated flight has it).
4. `airwake wind map`: the airwake map in the ship frame, scored against the simulator's
   wind field.
5. `airwake model compare` in still air and with the estimated wind as the model's input,
   and `airwake model diagnose` in still air: the residual the still-air comparison shows
   is the airwake, and the diagnosis says so (unmodelled wind ranks first) instead of
   naming an effect.
6. report/index.html: the map first, then the estimate's accuracy, then the model section.

Each step is the command a user would type (run here as `python -m airwake.cli ...`).
"""

from __future__ import annotations

import argparse
import html
import json
import shutil
import subprocess
import sys
import time
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[2]
CALIBRATION_START = "table52"
CALIBRATION_WINDOWS = "24"
# the wind explains the residual when, given as the model's input, it leaves every channel
# within this many times its noise floor (the calibration's own floor is ~5x on pdot)
AIRWAKE_EXPLAINS = 8.0


def _airwake(*args: str, capture: bool = False):
    """Run one step as the command a user types; its progress lines (stderr) show as it
    runs, its JSON (stdout, with `capture`) is returned; the step's time is printed."""
    cmd = [sys.executable, "-m", "airwake.cli", *args]
    print(f"\n$ airwake {' '.join(args)}", flush=True)
    t0 = time.monotonic()
    done = subprocess.run(cmd, cwd=REPO_ROOT, stdout=subprocess.PIPE if capture else None,
                          text=True)
    if done.returncode != 0:
        raise SystemExit(f"demo: `airwake {args[0]} {args[1] if len(args) > 1 else ''}` "
                         f"failed with exit status {done.returncode}")
    print(f"  ({time.monotonic() - t0:.1f} s)", flush=True)
    if capture:
        return json.loads(done.stdout)
    return None


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil_sim.boards.demo", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=str(REPO_ROOT / "build" / "demo"),
                   help="output directory (replaced; default build/demo)")
    p.add_argument("--scenario", default="ship_airwake_b0")
    p.add_argument("--duration", type=float, default=60.0, help="simulated seconds")
    p.add_argument("--calibration-s", type=float, default=None,
                   help="length of the still-air calibration flight (default: the whole "
                   "scenario, 160 s)")
    args = p.parse_args(argv)
    out = Path(args.out)
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    rec, flight = out / "recording", out / "flight.parquet"
    scored = out / "flight_with_truth.parquet"
    still, base = out / "calibration.parquet", out / "baseline.toml"
    wind, mapdir, report = out / "wind.parquet", out / "map", out / "report"
    t0 = time.monotonic()
    cal = ["--duration", f"{args.calibration_s:g}"] if args.calibration_s else []
    _airwake("sim", "table", "--scenario", "still_air_calibration", *cal, "--out", str(still))
    calib = _airwake("calibrate", str(still), "--model", CALIBRATION_START, "--out", str(base),
                     "--max-windows", CALIBRATION_WINDOWS, "--json", "--progress", capture=True)
    _airwake("sim", "run", "--scenario", args.scenario, "--duration", f"{args.duration:g}",
             "--stepped", "--out", str(rec))
    _airwake("export", str(rec), "--out", str(flight), "--progress")
    # scoring only: the truth world's columns beside the export (the analysis never reads
    # them; --score does)
    _airwake("sim", "truth", str(rec), "--flight", str(flight), "--out", str(scored))
    est = _airwake("wind", "estimate", str(scored), "--model", str(base), "--score", "--json",
                   "--progress", "--out", str(wind), capture=True)
    amap = _airwake("wind", "map", str(wind), "--flight", str(scored), "--out", str(mapdir),
                    "--score", "--json", "--progress", capture=True)
    still_air = _airwake("model", "compare", str(scored), "--model", str(base), "--windows",
                         "0", "--json", capture=True)
    with_wind = _airwake("model", "compare", str(scored), "--model", str(base), "--windows",
                         "0", "--wind", str(wind), "--json", capture=True)
    diag = _airwake("model", "diagnose", str(scored), "--model", str(base), "--no-sindy",
                    "--json", capture=True)
    for name, data in (("compare_still_air", still_air), ("compare_with_wind", with_wind),
                       ("diagnose_still_air", diag)):
        (out / f"{name}.json").write_text(json.dumps(data, indent=1))
    write_report(report, mapdir, calib, est, amap, still_air, with_wind, args, diag)
    print(f"\ndemo done in {time.monotonic() - t0:.0f} s:\n  baseline     {base}\n"
          f"  recording    {rec}\n  flight table {flight}\n  wind         {wind}\n"
          f"  airwake map  {mapdir / 'map.parquet'} ({', '.join(amap['figures'])})\n"
          f"  report       {report / 'index.html'}\n\n{amap['headline']}", flush=True)
    return 0


def _rows(cells) -> str:
    return "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>"
                   for row in cells)


def _candidates(diag: dict, k: int = 3) -> str:
    tested = [c for c in diag["candidates"] if c.get("testable")][:k]
    return ", ".join(f"{c['effect']} {100 * c['explained']:.0f} %"
                     + (" (significant)" if c["significant"] else "") for c in tested)


def write_report(report: Path, mapdir: Path, calib: dict, est: dict, amap: dict,
                 still_air: dict, with_wind: dict, args, diag: dict) -> Path:
    """report/index.html: the map, the estimate's accuracy, the model section."""
    report.mkdir(parents=True, exist_ok=True)
    for f in amap["figures"]:
        shutil.copy(mapdir / f, report / f)
    figs = "".join(f'<figure><img src="{html.escape(f)}" alt="{html.escape(f)}"></figure>'
                   for f in amap["figures"])
    sc = amap.get("score")
    map_rows = []
    if sc:
        for n in sc["field"]:
            map_rows.append((n, f"{sc['along_track'][n]['rms']:.3f}",
                             f"{sc['field'][n]['rms']:.3f}"))
    comp = est["score"]["components"]
    est_rows = [(n, f"{c['error_mean']:+.3f}", f"{c['error_std']:.3f}",
                 f"{c['correlation']:.2f}", f"{c['posterior_std_mean']:.3f}",
                 f"{100 * c['coverage_90']:.0f} %", f"{c['table_5_3_std']:.3f}")
                for n, c in comp.items()]
    model_rows = []
    for ch, a in still_air["channels"].items():
        b = with_wind["channels"][ch]
        model_rows.append((a["label"], f"{a['rms']:.4f}", f"{a['rms_over_noise']:.1f}",
                           f"{b['rms']:.4f}", f"{b['rms_over_noise']:.1f}"))
    worst_still = max(a["rms_over_noise"] for a in still_air["channels"].values())
    worst_wind = max(b["rms_over_noise"] for b in with_wind["channels"].values())
    verdict = (f"In still air the model misses the measurements by up to {worst_still:.0f}x "
               f"the noise floor; with the estimated airwake as its input the worst channel "
               f"is at {worst_wind:.1f}x. ")
    if worst_wind <= AIRWAKE_EXPLAINS and worst_still > 2 * worst_wind:
        verdict += ("The residual of this flight is the airwake, not a missing model effect: "
                    "look for missing physics on still-air flights "
                    "(docs/model-discrepancy.md).")
    else:
        verdict += ("The estimated wind does not account for the residual: the model misses "
                    "something on this flight beyond the airwake (docs/model-discrepancy.md).")
    diagnosis = (f"<p><b>airwake model diagnose</b> (still air assumed): "
                 f"{html.escape(diag['verdict']['text'])} (ranked: "
                 f"{html.escape(_candidates(diag))}).</p>")
    trust = calib.get("wind_trust") or {}
    trust_rows = [(k, "yes" if v["trusted"] else "NO", v["why"]) for k, v in trust.items()]
    page = f"""<!doctype html><html><head><meta charset="utf-8"><title>airwake demo</title>
<style>body{{font-family:sans-serif;max-width:62em;margin:2em auto}}img{{max-width:100%}}
table{{border-collapse:collapse;margin:.5em 0}}td,th{{border:1px solid #ccc;padding:.2em .6em}}
</style></head><body>
<h1>Airwake map: {html.escape(args.scenario)}, {args.duration:g} s SIL flight</h1>
<p><b>{html.escape(amap['headline'])}</b></p>{figs}
<h2>How good is the map (simulated flight: the truth is known)</h2>
<table><tr><th>component</th><th>along-track RMS</th><th>field RMS</th></tr>
{_rows(map_rows)}</table>
<p>RMS over the {sc['cells'] if sc else 0} cells with at least {sc['min_seconds'] if sc else 2:g}
s of data: against the truth wind along the track, and against the simulator's wind field
at the cell centres.</p>
<h2>The wind estimate ({html.escape(str(est.get('method', 'smoother')))})</h2>
<table><tr><th>component</th><th>error mean</th><th>error std</th><th>corr. with truth</th>
<th>posterior std</th><th>90 % interval holds the truth</th><th>Table 5.3 std</th></tr>
{_rows(est_rows)}</table>
<p>{est['samples']} samples, {est['realtime_factor']:.0f}x real time. Table 5.3: the
reference's particle filter on real indoor flights.</p>
<h2>The model on this flight</h2>
<table><tr><th>channel</th><th>RMS, still air</th><th>/ noise</th>
<th>RMS, estimated wind as input</th><th>/ noise</th></tr>{_rows(model_rows)}</table>
<p>{html.escape(verdict)}</p>
{diagnosis}
<h2>The baseline model</h2>
<p>Calibrated on the still-air calibration flight from {CALIBRATION_START}
({len(calib.get('parameters', {}))} parameters fitted; RMS after
{calib.get('rms_after_all', float('nan')):.4f}). Wind components it can be trusted for:</p>
<table><tr><th>component</th><th>trusted</th><th>why</th></tr>{_rows(trust_rows)}</table>
</body></html>
"""
    path = report / "index.html"
    path.write_text(page)
    return path


if __name__ == "__main__":
    sys.exit(main())
