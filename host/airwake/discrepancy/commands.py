"""`airwake model ...`: the discrepancy workflow's commands.

    airwake model compare FLIGHT [--model SPEC] [--wind WIND] [--json]
    airwake model diagnose FLIGHT [--model SPEC] [--wind WIND] [--json]
    airwake model add EFFECT --data FLIGHT [--model SPEC] [--wind WIND] [--plugin FILE.py]
                      [--retune PARAM ...] --out SPEC2 [--json]
    airwake model report FLIGHT [--model SPEC] [--wind WIND] --out DIR [--after SPEC2]

Every command accepts the analysis settings (--lowpass, --skip) and the flight's wind
(--wind: a wind table or 'truth'; `airwake.discrepancy.wind`), and prints a table, or
one JSON object with --json. docs/model-discrepancy.md walks through them.
"""

from __future__ import annotations

import argparse
import json
import sys

DEFAULT_MODEL = "table51"


def _settings_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--model", default=DEFAULT_MODEL, metavar="SPEC",
                   help=f"model spec (.toml path or shipped name; default {DEFAULT_MODEL})")
    p.add_argument("--lowpass", type=float, default=None, metavar="HZ",
                   help="analysis band: zero-phase low-pass of the residuals (default 12 Hz; "
                        "0 = none)")
    p.add_argument("--skip", type=float, default=None, metavar="S",
                   help="start-up transient left out of every run (default 0.5 s)")
    p.add_argument("--wind", metavar="WIND",
                   help="the flight's wind as the model's input: an `airwake wind estimate` "
                   "output, an anemometer-derived table (t_s + wind_vx/vy/vz_m_s body or "
                   "wind_n/e/d_m_s earth axes), or 'truth' (a simulated flight's truth "
                   "columns). Without it the model assumes still air and unmodelled wind is "
                   "a candidate")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--quiet", action="store_true", help="no progress lines")


def register(subparsers) -> None:
    model = subparsers.add_parser(
        "model", help="model versus measurement: compare, diagnose, add an effect, report",
        description="Compare the helicopter model with a flight, see where it fails, learn "
        "which physical effect is missing, add it and watch the error fall "
        "(docs/model-discrepancy.md).")
    model.set_defaults(_group_parser=model)
    sub = model.add_subparsers(dest="model_command", metavar="SUBCOMMAND")

    p = sub.add_parser("compare", help="per-channel error of the model on a flight",
                       description="One-step-ahead prediction of the six acceleration "
                       "channels (RMS, NRMSE, R², noise floor, RMS/noise) and open-loop "
                       "simulation over short windows (rates, attitude, velocity).")
    p.add_argument("flight", metavar="FLIGHT", help="flight table (.parquet or .csv)")
    _settings_args(p)
    p.add_argument("--windows", type=int, default=None, metavar="N",
                   help="free-simulation windows (default 12; 0 = none)")
    p.add_argument("--window-s", type=float, default=None, metavar="S",
                   help="free-simulation window length (default 1.5 s)")
    p.set_defaults(func=_compare)

    p = sub.add_parser("diagnose", help="rank the catalogue's candidate effects",
                       description="Where the residual is (regimes, worst windows, "
                       "correlation tests) and which catalogue effect explains it: ranked "
                       "candidates with explained variance, fitted parameters, significance "
                       "and a physical reason; a sparse named regression for effects outside "
                       "the catalogue.")
    p.add_argument("flight", metavar="FLIGHT", help="flight table (.parquet or .csv)")
    _settings_args(p)
    p.add_argument("--candidates", nargs="+", metavar="EFFECT",
                   help="only these catalogue effects")
    p.add_argument("--refine", type=int, default=4, metavar="N",
                   help="nonlinear refinement of the top N candidates (default 4)")
    p.add_argument("--no-sindy", action="store_true", help="skip the sparse regression")
    p.set_defaults(func=_diagnose)

    p = sub.add_parser("add", help="add an effect, fit it, write the new spec",
                       description="Enable a catalogue effect (or one from --plugin), fit "
                       "its parameters (and --retune ones) on the flight's equation error, "
                       "write the new spec and print the error before/after per channel.")
    p.add_argument("effect", metavar="EFFECT", help="catalogue effect or plugin effect name")
    p.add_argument("--data", required=True, metavar="FLIGHT", help="flight table to fit on")
    p.add_argument("--plugin", metavar="FILE.py", help="Python file registering the effect")
    p.add_argument("--retune", nargs="+", default=(), metavar="PARAM",
                   help="also refit these model parameters (names or globs: 'fuselage.*')")
    p.add_argument("--out", required=True, metavar="SPEC2", help="new model spec (.toml)")
    p.add_argument("--max-nfev", type=int, default=30, help="fit evaluations (default 30)")
    p.add_argument("--misfit-on", metavar="STILL", dest="misfit_on",
                   help="measure the new model's misfit (the wind estimator's channel "
                   "noise floor and offsets, [calibration] model_error_*) on this still-air "
                   "flight instead of --data: the calibration flight, when the effect is "
                   "fitted on steady legs that manoeuvre less than a wind flight")
    _settings_args(p)
    p.set_defaults(func=_add)

    p = sub.add_parser("report", help="self-contained HTML report with figures",
                       description="Run compare, where, diagnose and add (the top candidate, "
                       "or --after SPEC2) and write DIR/index.html with PNG figures.")
    p.add_argument("flight", metavar="FLIGHT", help="flight table (.parquet or .csv)")
    p.add_argument("--out", required=True, metavar="DIR", help="report directory")
    p.add_argument("--after", metavar="SPEC2",
                   help="the improved model to show (default: add the top candidate)")
    _settings_args(p)
    p.set_defaults(func=_report)


def _settings(args):
    from airwake.discrepancy.settings import AnalysisSettings

    kw = {}
    if args.lowpass is not None:
        kw["lowpass_hz"] = args.lowpass
    if args.skip is not None:
        kw["skip_start_s"] = args.skip
    if getattr(args, "windows", None) is not None:
        kw["free_sim_windows"] = args.windows
    if getattr(args, "window_s", None) is not None:
        kw["free_sim_window_s"] = args.window_s
    return AnalysisSettings(**kw)


def _progress(args, label, total):
    from airwake.progress import Progress

    return Progress(label, total, enabled=not args.quiet)


def _stages(args, label, total):
    """One line per stage as it starts (the analysis before the first progress line
    takes seconds on a long flight)."""
    from airwake.progress import Progress

    return Progress(label, total, " stages", enabled=not args.quiet, min_interval_s=0)


def _dump(obj) -> None:
    from airwake.discrepancy.report import jsonable

    json.dump(jsonable(obj), sys.stdout, indent=1, allow_nan=True)
    sys.stdout.write("\n")


def _table(metrics: dict, extra: dict | None = None) -> str:
    from airwake.discrepancy.data import CHANNEL_UNITS

    head = f"{'channel':8s} {'RMS':>9s} {'NRMSE':>7s} {'R²':>7s} {'noise':>8s} {'RMS/noise':>9s}"
    if extra:
        head += "".join(f" {k:>9s}" for k in extra)
    lines = [head]
    for c, m in metrics.items():
        line = (f"{m['label']:8s} {m['rms']:9.4f} {m['nrmse']:7.3f} {m['r2']:7.3f} "
                f"{m['noise_band']:8.4f} {m['rms_over_noise']:9.2f}")
        if extra:
            line += "".join(f" {v[c]:9.4f}" for v in extra.values())
        lines.append(line + f"   {CHANNEL_UNITS[c]}")
    return "\n".join(lines)


def _compare(args) -> int:
    from airwake.discrepancy.compare import analyse, summary
    from airwake.discrepancy.wind import on_flight
    from airwake.heli import load_model

    st = _settings(args)
    model = load_model(args.model)
    prog = _progress(args, "free simulation", st.free_sim_window_s * 150)
    flight, wind = on_flight(args.wind, args.flight, st)
    # stage lines once the inputs are good: an error stays one line
    stages = _stages(args, "model compare", 1)
    stages.update(0, f"the model over {len(flight)} samples of {flight.name}")
    an = analyse(model, flight, st, free_sim=st.free_sim_windows > 0, progress=prog,
                 wind=wind)
    stages.finish()
    s = summary(an)
    s["wind"] = str(args.wind) if args.wind else None
    if args.json:
        _dump(s)
        return 0
    print(f"{an.flight.name}: {s['duration_s']:.1f} s, {s['samples_analysed']} of "
          f"{s['samples']} samples analysed; model {args.model} ({len(model.effects)} effects)"
          + (f"; wind from {args.wind}" if args.wind else "; still air assumed"))
    print(f"one-step-ahead, {st.lowpass_hz:g} Hz analysis band "
          f"(noise floor: {s['noise_method']})")
    print(_table(s["channels"]))
    fs = s.get("free_simulation")
    if fs:
        print(f"\nfree simulation, {fs['windows']} windows of {fs['window_s']:.2f} s "
              "(RMS over the windows / at the window end):")
        for v, r in fs["rms"].items():
            print(f"  {v:10s} {r:9.4f} {fs['end_rms'][v]:9.4f}")
    return 0


def _diagnose(args) -> int:
    from airwake.discrepancy import where
    from airwake.discrepancy.candidates import CANDIDATES
    from airwake.discrepancy.diagnose import diagnose, summary
    from airwake.discrepancy.errors import DiscrepancyError
    from airwake.discrepancy.wind import WIND_CANDIDATE, on_flight
    from airwake.heli import load_model, spec_calibration

    st = _settings(args)
    if args.candidates:
        known = {c.name for c in CANDIDATES} | {WIND_CANDIDATE}
        bad = [c for c in args.candidates if c not in known]
        if bad:
            raise DiscrepancyError(f"--candidates: unknown effect(s) {bad}; the catalogue "
                                   f"has {sorted(known)}")
    model = load_model(args.model)
    flight, wind = on_flight(args.wind, args.flight, st)
    # stage lines once the inputs are good: an error stays one line
    stages = _stages(args, "model diagnose", 2)
    stages.update(0, f"the model over {len(flight)} samples of {flight.name}, then each "
                  "candidate effect")
    prog = _progress(args, "screening candidates", len(CANDIDATES))
    d = diagnose(model, flight, st, candidates=args.candidates, refine_top=args.refine,
                 sindy=not args.no_sindy, progress=prog, wind=wind,
                 model_calibrated=spec_calibration(args.model) is not None)
    stages.update(1, "where the residual is (regimes, spectra, worst windows)")
    bd = where.breakdown(d.analysis)
    s = summary(d)
    s["where"] = where.summary(bd)
    s["compare"] = {c: {k: v for k, v in m.items() if k != "label"}
                    for c, m in d.analysis.metrics().items()}
    stages.finish()
    if args.json:
        _dump(s)
        return 0
    print(f"{d.analysis.flight.name}: model {args.model}"
          + (f"; wind from {args.wind}" if args.wind else "; still air assumed"))
    print(_table(d.analysis.metrics()))
    print("\nworst windows:")
    for w in s["where"]["worst_windows"][:3]:
        print(f"  {w['t_start_s']:7.1f}-{w['t_end_s']:.1f} s  {w['dominant_channel']:12s} "
              f"(residual/noise)² {w['score']:.1f}")
    print("\ncandidates (ranked):")
    print(f"  {'#':>2s} {'effect':22s} {'explained':>9s} {'CV':>7s} {'p':>8s}  significant")
    for i, r in enumerate(x for x in d.ranked if x.testable):
        print(f"  {i + 1:2d} {r.name:22s} {100 * r.explained:8.1f}% "
              f"{100 * r.cv_explained:6.1f}% {r.linear.p_value:8.2g}  "
              f"{'YES' if r.significant else 'no'}")
        if i < 5 or r.significant:
            print(f"     {r.reason}")
            if r.indistinguishable_from:
                others = ", ".join(o["effect"] for o in r.indistinguishable_from)
                print(f"     indistinguishable here from {others}; separate with: "
                      f"{r.manoeuvre}")
    for r in d.ranked:
        if not r.testable:
            print(f"     {r.name}: not testable ({r.why_not})")
    if d.sindy:
        print("\nsparse regression of the residual (named terms):")
        for e in d.sindy["channels"].values():
            print(f"  {e['summary']}")
    sig = d.significant()
    print("\nsignificant: " + (", ".join(sig) if sig else "none (no candidate passes the "
                               "significance and effect-size thresholds)"))
    if d.recalibration is not None:
        rc = d.recalibration
        print(f"recalibration (the model's own {rc['parameters']} parameters): explains "
              f"{100 * rc['explained']:.1f} %, cross-validated {100 * rc['cv_explained']:.1f} %")
    print("\nverdict: " + s["verdict"]["text"])
    return 0


def _add(args) -> int:
    from airwake.discrepancy.add import add_effect

    st = _settings(args)
    prog = _progress(args, f"fitting {args.effect}", args.max_nfev)
    res = add_effect(args.model, args.effect, args.data, plugin=args.plugin,
                     retune=args.retune, out=args.out, settings=st, max_nfev=args.max_nfev,
                     progress=prog, wind=args.wind, misfit_on=args.misfit_on)
    j = res.to_json()
    if args.json:
        _dump(j)
        return 0
    print(f"added {args.effect} to {args.model} -> {res.out}")
    for k, v in res.fit.values.items():
        print(f"  {k} = {v:.6g}" + ("  (at a bound)" if k in res.fit.at_bound else ""))
    print(_table(res.after, {"before": j["before"], "after": j["after"]}))
    if j["worse_channels"]:
        bound = [k for k in res.fit.values if k in res.fit.at_bound]
        print(f"warning: the fitted {args.effect} made "
              + ", ".join(f"{c} {j['before'][c]:.4g} -> {j['after'][c]:.4g}"
                          for c in j["worse_channels"])
              + " worse: as fitted it does not describe this flight"
              + (f" ({', '.join(bound)} at a bound)" if bound else "")
              + f"; {res.out} is written, keep the model you started from", file=sys.stderr)
    return 0


def _report(args) -> int:
    from airwake.discrepancy.report import write_report

    st = _settings(args)
    out = write_report(args.flight, args.model, args.out, settings=st, after=args.after,
                       quiet=args.quiet, wind=args.wind)
    if args.json:
        _dump(out)
        return 0
    print(f"report written: {out['index']}")
    return 0
