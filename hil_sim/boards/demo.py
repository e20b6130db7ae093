"""`make demo`: a ship-airwake SIL flight through the whole chain, ending in an airwake map.

    python -m hil_sim.boards.demo [--out build/demo] [--duration 60] [--scenario NAME]
                                  [--truth blade_element|effects]

The truth is the independent blade-element helicopter flown by the crossover pilot
(docs/truth-world.md): a machine the host's model has never seen, so the figures the
report gives are what a user gets on a real airframe. (`--truth effects` flies the host's
own effect model instead, full-state pilot: "our own model", for comparison only.)

0. The model, as a user makes it before going to sea (docs/calibration.md, "On a
   helicopter that is not the reference's"): the still-air calibration flight (speed
   legs, chirps, bursts; `airwake sim table`, the truth world straight to a table);
   `airwake calibrate` from the reference's Table 5.2 (the published calibration of this
   airframe class) on the parameters the flight identifies; `airwake model diagnose` on
   the same flight, and `airwake model add` of the effect its verdict names, when the fit
   makes no channel worse; then the same on the still-air cruise legs of step 6 (the
   steady step: the effect fitted there, its misfit measured on the calibration flight,
   `model add --misfit-on`). Its report says which wind components the model can be
   trusted for.
1. `airwake sim run`: the truth world flies `ship_airwake_b0` (lateral sweeps behind the
   hangar), the native rover and base firmware read its VN200, Piksi, RC and rotor
   signals, the real daemon records them from the base's pty (stepped, deterministic).
2. `airwake export`: the recording becomes a flight table (the hub in the ship frame);
   `airwake sim truth` puts the truth world's truth_* columns beside it, for scoring.
3. `airwake wind estimate`: the 6-D wind along the flight (the smoother), scored against
   the simulator's truth (a simulated flight has it).
4. `airwake wind map`: the airwake map in the ship frame, scored against the simulator's
   wind field, made from the best wind this airframe gives: the still-air net's mean
   flow with the model's rotation given it (step 6's anchored estimate; on a helicopter
   the model does not fit, the smoother's own mean flow carries the model's misfit).
5. `airwake model compare` in still air and with the estimated wind as the model's input,
   and `airwake model diagnose` in still air: whether the estimated airwake accounts for
   the residual, said as the numbers say it.
6. The mean flow with no model: `airwake sim table` flies the still-air cruise legs
   (`still_air_cruise`, the first 100 s), `airwake nets train --target wind --still-air`
   learns the air velocity from them and the calibration flight (no truth read), and
   `airwake wind estimate --method net` reads the ship flight's mean flow as the INS
   velocity less it (docs/networks.md "Still-air labels"), its interval widened by the
   model's smoother where the net does not follow the wind (`--interval-model`); scored
   beside the smoother, with the rotation of the smoother anchored on it (`--anchor`).
   (The cruise flight and the training need no model: they run beside step 0.)
7. report/index.html: the map first, then the estimate's accuracy (bias, scatter, interval
   coverage against the truth), the still-air net's beside it, then the model section.

Each step is the command a user would type (run here as `python -m airwake.cli ...`).
"""

from __future__ import annotations

import argparse
import html
import json
import math
import shutil
import subprocess
import sys
import time
from pathlib import Path

from airwake.calibrate.sequence import REFINE, candidates_text, discrepancy_step, steady_step

REPO_ROOT = Path(__file__).resolve().parents[2]
CALIBRATION_START = "table52"
CALIBRATION_WINDOWS = "24"
# the wind explains the residual when, given as the model's input, it leaves every channel
# within this many times its noise floor (the calibration's own floor is ~5x on pdot)
AIRWAKE_EXPLAINS = 8.0
# the still-air net's cruise flight: the scenario's first two legs (out and back at 3.5 m/s)
CRUISE_S = 100.0
# the wind table the airwake map is made from: the model's smoother anchored on the
# still-air net's mean flow (step 6)
MAPPED = "wind_anchored.parquet"


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


_BACKGROUND: list = []  # steps started beside the others, stopped if the demo stops


def _start(*args: str, log: Path, stdout: Path | None = None):
    """Start one step in the background, its progress to `log` (shown when it ends) and
    its standard output to `stdout` (its JSON: `_finish` returns it) or to `log` too."""
    print(f"\n$ airwake {' '.join(args)}   (in the background; output: {log})", flush=True)
    fh = log.open("w")
    out = stdout.open("w") if stdout is not None else fh
    proc = subprocess.Popen([sys.executable, "-m", "airwake.cli", *args], cwd=REPO_ROOT,
                            stdout=out, stderr=fh if stdout is not None else subprocess.STDOUT,
                            text=True)
    _BACKGROUND.append(proc)
    return proc, (fh, out), log, stdout, args, time.monotonic()


def _stop_background() -> None:
    """Stop the background steps still running (the demo stopped before waiting for them)."""
    for proc in _BACKGROUND:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    _BACKGROUND.clear()


def _finish(started):
    """Wait for a background step, show the end of its output, stop the demo if it failed;
    its JSON when it was started with `stdout`."""
    proc, files, log, stdout, args, t0 = started
    rc = proc.wait()
    for fh in set(files):
        fh.close()
    lines = [ln for ln in log.read_text(errors="replace").splitlines() if "━" not in ln]
    print(f"\n$ airwake {' '.join(args)}   (finished)\n" + "\n".join(lines[-8:]), flush=True)
    if rc != 0:
        raise SystemExit(f"demo: `airwake {args[0]} {args[1]}` failed with exit status {rc} "
                         f"(output: {log})")
    print(f"  ({time.monotonic() - t0:.1f} s, beside the steps above)", flush=True)
    return json.loads(stdout.read_text()) if stdout is not None else None


# `--warm` (what `make setup` runs): the demo itself on flights of seconds, so that the
# numba kernels its steps compile - the truth world's blade-element helicopter, the host
# model's effects and the catalogue's candidates, the estimators - are in their on-disk
# caches (the first process compiles, later ones load: tens of seconds per step) and a
# fresh clone's first `make demo` runs as fast as later ones. 40 s of calibration: its
# diagnosis names the effect the demo's 160 s one does (advance_cyclic; on 80 s it names
# cg_offset), so the ship flight's diagnosis compiles the same models. 30 s of cruise: the
# first leg reaches its 3.5 m/s (a 10 s one stays below the 1.5 m/s at which the steady
# step's advance_torque can be tested); its model is made whatever the short diagnosis says
# (below). Nothing is kept.
WARM_S = {"ship": 10.0, "calibration": 40.0, "cruise": 30.0}
WARM_STEADY_EFFECT = "advance_torque"


def main(argv: list[str] | None = None) -> int:
    try:
        return _demo(argv)
    finally:
        _stop_background()


def _demo(argv: list[str] | None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil_sim.boards.demo", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=None,
                   help="output directory (replaced; default build/demo, build/warm with "
                   "--warm)")
    p.add_argument("--warm", action="store_true",
                   help="the demo on flights of seconds, only to compile the kernels its "
                   "steps use (what `make setup` runs; nothing kept)")
    p.add_argument("--scenario", default="ship_airwake_b0")
    p.add_argument("--duration", type=float, default=60.0, help="simulated seconds")
    p.add_argument("--calibration-s", type=float, default=None,
                   help="length of the still-air calibration flight (default: the whole "
                   "scenario, 160 s)")
    p.add_argument("--cruise-s", type=float, default=CRUISE_S,
                   help="length of the still-air cruise flight the still-air wind net "
                   f"learns from (default {CRUISE_S:g} s)")
    from hil_sim.world.scenario import TRUTH_PILOTS

    p.add_argument("--truth", choices=sorted(TRUTH_PILOTS), default="blade_element",
                   help="the truth helicopter: the independent blade-element machine with "
                   "the crossover pilot (default), or the host's own effect model with the "
                   "full-state pilot (our own model: for comparison only)")
    args = p.parse_args(argv)
    if args.warm:
        args.duration, args.calibration_s, args.cruise_s = (
            WARM_S["ship"], WARM_S["calibration"], WARM_S["cruise"])
        out = Path(args.out or REPO_ROOT / "build" / "warm")
        print(f"setup: the demo on flights of seconds, to compile its steps' kernels once "
              f"({out}, removed after)", flush=True)
    else:
        out = Path(args.out or REPO_ROOT / "build" / "demo")
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    rec, flight = out / "recording", out / "flight.parquet"
    scored = out / "flight_with_truth.parquet"
    still, base = out / "calibration.parquet", out / "baseline.toml"
    wind, mapdir, report = out / "wind.parquet", out / "map", out / "report"
    t0 = time.monotonic()
    cal = ["--duration", f"{args.calibration_s:g}"] if args.calibration_s else []
    truth = truth_arguments(args.truth)
    # the ship flight needs nothing from the model steps: it flies beside them (2 cores)
    sil = _start("sim", "run", "--scenario", args.scenario, *truth, "--duration",
                 f"{args.duration:g}", "--stepped", "--out", str(rec), log=out / "sim_run.log")
    _airwake("sim", "table", "--scenario", "still_air_calibration", *truth, *cal, "--out",
             str(still))
    # the still-air net (step 6) needs no model: its cruise flight and its training run
    # beside the calibration (one core each: the ship flight ends in its first seconds)
    net_job = still_air_net_start(out, truth, args.cruise_s)
    calib = _airwake("calibrate", str(still), "--model", CALIBRATION_START, "--out", str(base),
                     "--max-windows", CALIBRATION_WINDOWS, "--json", "--progress", capture=True)
    net_job = still_air_net_train(out, still, net_job)
    # calibrate -> diagnose -> add, each step the command a user types (shown as it runs)
    step = discrepancy_step(still, base, out / "model.toml",
                            run=lambda *a: _airwake(*a, capture=True))
    # the steady step: the same on the cruise legs (flown for the net: there since its
    # training began), the new spec's misfit measured on the calibration flight
    first = out / "model.toml" if args.warm and (out / "model.toml").is_file() else step["model"]
    steady = steady_step(out / "cruise.parquet", first, out / "steady.toml", still,
                         run=lambda *a: _airwake(*a, capture=True))
    model = steady["model"]
    if args.warm:
        # the models with the effects the diagnoses named, kept or not: the models the
        # demo's ship-flight diagnosis compiles (the base and each candidate added to it).
        # Seconds of flight do not show the steady step's effect: the one the demo's 100 s
        # cruise legs name on this airframe (advance_torque) is added to compile its model
        if not (out / "steady.toml").is_file():
            _airwake("model", "add", WARM_STEADY_EFFECT, "--data", str(out / "cruise.parquet"),
                     "--model", str(first), "--out", str(out / "steady.toml"), "--json",
                     "--quiet", capture=True)
        model = out / "steady.toml"
    _finish(sil)
    _airwake("export", str(rec), "--out", str(flight), "--progress")
    # scoring only: the truth world's columns beside the export (the analysis never reads
    # them; --score does)
    _airwake("sim", "truth", str(rec), "--flight", str(flight), "--out", str(scored))
    # the still-air diagnosis of the ship flight needs no wind: it runs beside the wind steps
    diag_job = _start("model", "diagnose", str(scored), "--model", str(model), "--no-sindy",
                      "--refine", str(REFINE), "--json", log=out / "diagnose.log",
                      stdout=out / "diagnose_still_air.json")
    est = _airwake("wind", "estimate", str(scored), "--model", str(model), "--score", "--json",
                   "--progress", "--out", str(wind), capture=True)
    net_est, anchored = still_air_net_step(out, scored, model, net_job)
    net_est["anchored"] = anchored
    # the map is made from the best wind this airframe gives: the still-air net's mean flow
    # with the model's rotation given it (on a helicopter the model does not fit, the
    # model's own mean flow carries its misfit: docs/calibration.md)
    amap = _airwake("wind", "map", str(out / MAPPED), "--flight", str(scored), "--out",
                    str(mapdir), "--score", "--json", "--progress", capture=True)
    still_air = _airwake("model", "compare", str(scored), "--model", str(model), "--windows",
                         "0", "--json", capture=True)
    with_wind = _airwake("model", "compare", str(scored), "--model", str(model), "--windows",
                         "0", "--wind", str(wind), "--json", capture=True)
    diag = _finish(diag_job)
    for name, data in (("compare_still_air", still_air), ("compare_with_wind", with_wind),
                       ("diagnose_still_air", diag), ("wind_estimate", est),
                       ("wind_estimate_still_air_net", net_est),
                       ("discrepancy_step", {k: str(v) if isinstance(v, Path) else v
                                             for k, v in step.items()}),
                       ("steady_step", {k: str(v) if isinstance(v, Path) else v
                                        for k, v in steady.items()})):
        (out / f"{name}.json").write_text(json.dumps(data, indent=1))
    write_report(report, mapdir, calib, est, amap, still_air, with_wind, args, diag, step,
                 net_est, steady)
    if args.warm:
        shutil.rmtree(out, ignore_errors=True)
        print(f"setup: kernels compiled in {time.monotonic() - t0:.0f} s", flush=True)
        return 0
    print(f"\ndemo done in {time.monotonic() - t0:.0f} s:\n  baseline     {base}\n"
          f"  recording    {rec}\n  flight table {flight}\n  wind         {wind}\n"
          f"  airwake map  {mapdir / 'map.parquet'} ({', '.join(amap['figures'])})\n"
          f"  report       {report / 'index.html'}\n\n{amap['headline']}", flush=True)
    return 0


def still_air_net_start(out: Path, truth: list[str], cruise_s: float):
    """Step 6's flight, in the background: the still-air cruise legs."""
    return _start("sim", "table", "--scenario", "still_air_cruise", *truth, "--duration",
                  f"{cruise_s:g}", "--quiet", "--out", str(out / "cruise.parquet"),
                  log=out / "cruise.log")


def still_air_net_train(out: Path, still: Path, cruise_job):
    """Once the cruise flight is there: the still-air wind net on it and the calibration
    flight, in the background."""
    _finish(cruise_job)
    return _start("nets", "train", str(still), str(out / "cruise.parquet"), "--target",
                  "wind", "--still-air", "--quiet", "--out", str(out / "still_air_net.pt"),
                  log=out / "nets_train.log")


def still_air_net_step(out: Path, flight: Path, model: Path, train_job) -> tuple[dict, dict]:
    """The mean flow with no model (module doc, step 6): once the still-air net is
    trained, its estimate on `flight` scored, its interval widened by `model`'s smoother
    where it does not follow the wind; and `model`'s smoother anchored on that mean flow
    (the rotation given it), scored."""
    _finish(train_job)
    net = out / "still_air_net.pt"
    mean_flow = out / "wind_still_air_net.parquet"
    net_est = _airwake("wind", "estimate", str(flight), "--method", "net", "--net", str(net),
                       "--interval-model", str(model), "--score", "--json", "--out",
                       str(mean_flow), capture=True)
    anchored = _airwake("wind", "estimate", str(flight), "--model", str(model), "--anchor",
                        str(mean_flow), "--score", "--json", "--out", str(out / MAPPED),
                        capture=True)
    return net_est, anchored


def truth_arguments(truth: str) -> list[str]:
    """The `airwake sim` options that fly `truth` with its pilot."""
    from hil_sim.world.scenario import TRUTH_PILOTS

    if truth not in TRUTH_PILOTS:
        raise ValueError(f"truth {truth!r}: one of {sorted(TRUTH_PILOTS)}")
    pilot = TRUTH_PILOTS[truth]
    return ["--truth", truth] + (["--pilot", pilot] if pilot else [])


# the wind components as the report writes them
COMPONENT_SHORT = {"wind_vx_m_s": "v_x", "wind_vy_m_s": "v_y", "wind_vz_m_s": "v_z",
                   "wind_wx_rad_s": "ω_x", "wind_wy_rad_s": "ω_y", "wind_wz_rad_s": "ω_z"}


def estimate_verdict(comp: dict, low: float = 0.8) -> str:
    """One paragraph on how far the wind estimate can be believed, from its score: which
    components' 90 % intervals hold the truth less than `low` of the time (a bias the
    posterior does not know of: the model's own error on this airframe), each with its
    coverage and its bias."""
    short = [(COMPONENT_SHORT.get(n, n), c) for n, c in comp.items()]
    under = [f"{n} ({100 * c['coverage_90']:.0f} %, bias {c['error_mean']:+.2f})"
             for n, c in short if c["coverage_90"] < low]
    if not under:
        return (f"The 90 % intervals hold the truth at least {100 * low:.0f} % of the time on "
                "every component.")
    return ("The 90 % intervals hold the truth less than "
            f"{100 * low:.0f} % of the time on {', '.join(under)}: there the estimate carries "
            "a bias its posterior does not know of, the model's own error on this airframe "
            "(docs/truth-world.md). Read those components as biased by about that much.")


BOUND_GAP = 1.5  # error RMS over the bound above which the estimator, not the flight, limits


def bound_verdict(comp: dict, gap: float = BOUND_GAP) -> str:
    """One sentence on what limits the estimate, from the score's Cramer-Rao bound at the
    truth (`airwake.estimate.wind.wind_bound`: the model's own misfit as coloured noise,
    the air's turbulence as the prior): the components whose error RMS exceeds the bound
    by more than `gap` are limited by the estimator (what it does with the misfit), the
    others by the information in the flight. "" when the score has no bound."""
    ratios = [(COMPONENT_SHORT.get(n, n), c.get("error_over_crlb")) for n, c in comp.items()]
    ratios = [(n, r) for n, r in ratios if r is not None]
    if not ratios:
        return ""
    far = [f"{n} ({r:.1f}x)" for n, r in ratios if r > gap]
    lo, hi = min(r for _, r in ratios), max(r for _, r in ratios)
    head = (f"Against the Cramér–Rao bound at the truth (the model's own misfit on this "
            f"flight as coloured channel noise, the air's turbulence as the prior) the error "
            f"is {lo:.1f}–{hi:.1f}x the bound. ")
    if not far:
        return head + ("Every component is near it: the information in this flight, not "
                       "the estimator, limits the estimate.")
    return head + (f"On {', '.join(far)} the estimator, not the information in the flight, "
                   "limits the estimate: an estimator that knew the misfit's spectrum could "
                   "do that much better (docs/wind-estimation.md).")


def _rows(cells) -> str:
    return "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>"
                   for row in cells)


def net_rows(net_est: dict, est: dict) -> list:
    """The still-air net's score per estimated component (its rotation is not: NaN) beside
    the smoother's bias; then the rotation of the smoother anchored on that mean flow
    (`net_est["anchored"]`, when there)."""
    comp, smoother = net_est["score"]["components"], est["score"]["components"]
    rows = [(n, f"{c['error_mean']:+.3f}", f"{c['error_std']:.3f}",
             f"{100 * c['coverage_90']:.0f} %", f"{smoother[n]['error_mean']:+.3f}")
            for n, c in comp.items() if math.isfinite(c["error_mean"])]
    anchored = (net_est.get("anchored") or {}).get("score", {}).get("components", {})
    rows += [(f"{n} (the model, given it)", f"{c['error_mean']:+.3f}", f"{c['error_std']:.3f}",
              f"{100 * c['coverage_90']:.0f} %", f"{smoother[n]['error_mean']:+.3f}")
             for n, c in anchored.items() if n.endswith("_rad_s")]
    return rows


def _added_table(step: dict, before: str, where: str = "") -> str:
    """The channels' RMS before and after the effect a discrepancy step added ("" when it
    added none)."""
    if not step.get("added"):
        return ""
    b, a = step["before"], step["after"]
    return (f"<table><tr><th>channel{' ' + where if where else ''}</th><th>RMS, {before}"
            f"</th><th>RMS, with {html.escape(step['added'])}</th></tr>"
            + _rows((ch, f"{b[ch]:.4f}", f"{a[ch]:.4f}") for ch in b) + "</table>")


def write_report(report: Path, mapdir: Path, calib: dict, est: dict, amap: dict,
                 still_air: dict, with_wind: dict, args, diag: dict, step: dict,
                 net_est: dict, steady: dict | None = None) -> Path:
    """report/index.html: the map, the estimates' accuracy, the model section."""
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
                 f"{100 * c['coverage_90']:.0f} %",
                 f"{c['crlb_std']:.3f}" if c.get("crlb_std") is not None else "-",
                 f"{c['table_5_3_std']:.3f}")
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
                 f"{html.escape(candidates_text(diag))}).</p>")
    honesty = estimate_verdict(comp)
    added = _added_table(step, "calibrated")
    steady_par = ""
    if steady is not None:
        steady_par = (f"<p><b>airwake model diagnose</b> on the still-air cruise legs "
                      f"({args.cruise_s:g} s, steady at 3.5 m/s), the model above: "
                      f"{html.escape(steady['diagnosis'])} (ranked: "
                      f"{html.escape(steady['ranked'])}). {html.escape(steady['why'])}"
                      + ("; its misfit (the wind estimator's channel noise floor) measured "
                         "on the calibration flight" if steady.get("added") else "")
                      + ".</p>"
                      + _added_table(steady, "before", "on the cruise legs"))
    trust = calib.get("wind_trust") or {}
    trust_rows = [(k, "yes" if v["trusted"] else "NO", v["why"]) for k, v in trust.items()]
    bias = still_air_bias_section(calib.get("still_air_wind_bias"))
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
at the cell centres. Mapped from the still-air net's mean flow with the model's rotation
given it (<b>airwake wind estimate --anchor</b>, below): on a helicopter the model does not
fit, the model's own mean flow carries its misfit (the smoother's error mean below).</p>
<h2>The wind estimate ({html.escape(str(est.get('method', 'smoother')))})</h2>
<table><tr><th>component</th><th>error mean</th><th>error std</th><th>corr. with truth</th>
<th>posterior std</th><th>90 % interval holds the truth</th><th>Cramér–Rao bound</th>
<th>Table 5.3 std</th></tr>
{_rows(est_rows)}</table>
<p>{est['samples']} samples, {est['realtime_factor']:.0f}x real time. Table 5.3: the
reference's particle filter on real indoor flights. Truth helicopter: {html.escape(args.truth)}
({"the independent blade-element machine: a helicopter the model has never seen" if
args.truth == "blade_element" else "the host's own effect model: our own model"}).</p>
<p>{html.escape(honesty)}</p>
<p>{html.escape(bound_verdict(comp))}</p>
<h2>The mean flow with no model: a still-air wind net</h2>
<p>Trained on the calibration flight and {args.cruise_s:g} s of still-air cruise legs with
the INS velocity as its label (no model, no truth); the mean flow is the INS velocity less
the net's air velocity. The rotation it does not estimate: its rows are the model's
smoother anchored on this mean flow (<b>airwake wind estimate --anchor</b>), which reads
the rotation given it instead of trading it against a biased mean flow.</p>
<table><tr><th>component</th><th>error mean</th><th>error std</th>
<th>90 % interval holds the truth</th><th>the smoother's error mean</th></tr>
{_rows(net_rows(net_est, est))}</table>
<p>Its interval: its error in still air joined to the local disagreement of the model's
smoother with it above 0.1 Hz, the wind's fast part the net does not follow, and to the
fast part the smoother's own posterior says it did not see either (docs/networks.md).</p>
<h2>The model on this flight</h2>
<table><tr><th>channel</th><th>RMS, still air</th><th>/ noise</th>
<th>RMS, estimated wind as input</th><th>/ noise</th></tr>{_rows(model_rows)}</table>
<p>{html.escape(verdict)}</p>
{diagnosis}
<h2>The model: calibrate, diagnose, add</h2>
<p>Calibrated on the still-air calibration flight from {CALIBRATION_START}
({len(calib.get('parameters', {}))} parameters fitted; RMS after
{calib.get('rms_after_all', float('nan')):.4f}). <b>airwake model diagnose</b> on the same
flight: {html.escape(step['diagnosis'])} (ranked: {html.escape(step['ranked'])}).
{html.escape(step['why'])}.</p>{added}
{steady_par}
{bias}
<p>Wind components it can be trusted for:</p>
<table><tr><th>component</th><th>trusted</th><th>why</th></tr>{_rows(trust_rows)}</table>
</body></html>
"""
    path = report / "index.html"
    path.write_text(page)
    return path


def still_air_bias_section(bias: dict | None, top: int = 2) -> str:
    """The calibrated model's steady wind error on its still-air flight and the channels
    whose steady misfit makes it (`airwake calibrate`'s still_air_wind_bias), as HTML."""
    if not bias:
        return ""
    from airwake.estimate.wind import largest_shares

    chans = bias["channels"]
    rows = [(name, f"{error:+.2f}", f"{explained:+.2f}",
             ", ".join(f"{c} {s:+.2f}" for c, s in top_shares))
            for name, error, explained, top_shares in largest_shares(bias, top)]
    misfit = ", ".join(f"{c} {m:+.3g}" for c, m in zip(chans, bias["misfit_mean"],
                                                        strict=True))
    return ("<p>In still air, where the wind is zero, the calibrated model's own wind "
            "estimate (the plain smoother) errs steadily, and the model's steady misfit on "
            "each channel makes a share of it (what to fix first for the wind; "
            f"docs/calibration.md). Its steady misfit: {html.escape(misfit)}.</p>"
            "<table><tr><th>component</th><th>steady error</th><th>made by the steady "
            "misfit</th><th>largest shares</th></tr>" + _rows(rows) + "</table>")


if __name__ == "__main__":
    sys.exit(main())
