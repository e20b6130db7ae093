"""`airwake calibrate FLIGHT [--model SPEC] [--method lsq|pso] [--params ...] --out SPEC`."""

from __future__ import annotations

import argparse
import json
import math
import sys


def _fmt(v: float) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    if isinstance(v, float) and math.isinf(v):
        return "inf"
    return f"{v:.6g}"


def print_report(result, out_path, stream=None, bias: dict | None = None) -> None:
    """The calibration report; `bias`: the [calibration] table's `still_air_wind_bias`."""
    from airwake.heli.context import MEAS_CHANNELS

    info = result.info
    w = (stream or sys.stdout).write
    w(f"calibrate {result.method}: {info.get('samples')} samples, {info.get('windows')} "
      f"windows ({info.get('scored_samples')} scored), {len(result.names)} free parameters, "
      f"{result.seconds:.1f} s\n\n")
    w(f"{'channel':<14}{'noise scale':>12}{'rms before':>12}{'rms after':>12}\n")
    for c, s, b, a in zip(MEAS_CHANNELS, result.noise_scale, result.rms_before,
                          result.rms_after, strict=True):
        w(f"{c:<14}{s:>12.4g}{b:>12.4g}{a:>12.4g}\n")
    rb = math.sqrt(sum(v * v for v in result.rms_before) / 6)
    ra = math.sqrt(sum(v * v for v in result.rms_after) / 6)
    w(f"{'all (rms)':<14}{'':>12}{rb:>12.4g}{ra:>12.4g}\n\n")
    width = max(len(n) for n in result.names)
    w(f"{'parameter':<{width}}  {'start':>11}  {'fitted':>11}  {'1-sigma':>10}"
      f"  {'if white':>10}\n")
    for n, s, v, d, dw, b, i in zip(result.names, result.start, result.values, result.std,
                                    result.white_std, result.at_bound, result.identifiable,
                                    strict=True):
        flag = " at bound" if b else ("" if i else " (poorly identified)")
        w(f"{n:<{width}}  {s:>11.5g}  {v:>11.5g}  {_fmt(float(d)):>10}"
          f"  {_fmt(float(dw)):>10}{flag}\n")
    w("(1-sigma: " + ("the windows' own residual correlation (sandwich over windows)"
                      if result.uncertainty_kind == "clustered" else
                      "white residuals assumed") + "; 'if white': independent residuals)\n")
    if result.notes:
        w("\nidentifiability:\n")
        for note in result.notes:
            w(f"  - {note}\n")
    trust = info.get("wind_trust")
    if trust:
        w("\nwind components this model can be trusted for (the flight's envelope):\n")
        for comp, t in trust.items():
            w(f"  {comp}: {'trusted' if t['trusted'] else 'NOT trusted'} - {t['why']}\n")
    if bias:
        print_wind_bias(bias, w)
    if out_path:
        w(f"\nwrote {out_path}\n")


def print_wind_bias(bias: dict, w, top: int = 2) -> None:
    """The still-air wind estimate's steady error and the channels whose steady misfit
    makes it (`airwake.estimate.wind.wind_bias_by_channel`), largest first."""
    from airwake.estimate.wind import largest_shares

    w("\nthe wind estimate's steady error on this still air (plain smoother) and the "
      "model's\nsteady misfit that makes it (what to fix first for the wind):\n")
    chans = bias["channels"]
    w("  misfit " + ", ".join(f"{c} {m:+.3g}" for c, m in zip(chans, bias["misfit_mean"],
                                                         strict=True)) + "\n")
    for name, error, explained, top_shares in largest_shares(bias, top):
        parts = ", ".join(f"{c} {s:+.2f}" for c, s in top_shares)
        w(f"  {name:<14}{error:+7.2f}  (steady misfit: {explained:+.2f}; {parts})\n")


def calibration_table(result, flight, start) -> dict:
    """The spec's [calibration] table: what the model was fitted to and the envelope the
    wind estimator checks its flights against (TOML: no None values)."""
    info = result.info
    out = {"flight": str(flight), "method": result.method, "start": str(start),
           "free_parameters": list(result.names)}
    if info.get("front_end"):
        out["front_end"] = dict(info["front_end"])
    if info.get("envelope"):
        out["envelope"] = info["envelope"]
        out["trusted"] = {k: v["trusted"] for k, v in info["wind_trust"].items()}
    # what the fitted model still misses on its own calibration flight (still air: the
    # wind is known to be zero), per channel after the front end: the wind estimator's
    # floor for the channel noise, so model error is never taken for wind
    out["model_error_std"] = [float(v) for v in result.rms_after]
    # and the part of it that holds for a window (a body-fixed force or moment the wind
    # estimator cannot tell from a steady wind: it widens the wind's intervals by it)
    if info.get("model_error_offset") is not None:
        out["model_error_offset"] = list(info["model_error_offset"])
    # and what a wind estimate made with it errs beyond its intervals on that still air:
    # every later estimate's std carries it (the model's sensitivities are not the
    # airframe's where the misfit reads as wind)
    add_still_air_wind_error(out, result.model, flight)
    return out


def add_still_air_wind_error(table: dict, model, flight) -> None:
    """Adds `still_air_wind_error` and `still_air_wind_bias` (the plain estimate's steady
    error there, channel by channel) to a [calibration] table (`airwake.estimate.wind`);
    where the smoother cannot run on the flight, says so on stderr and leaves them out
    (the calibration itself is kept)."""
    from airwake.estimate.errors import WindEstimationError
    from airwake.estimate.wind import STILL_AIR_BIAS_KEY, STILL_AIR_KEY, still_air_report

    table.pop(STILL_AIR_KEY, None)
    table.pop(STILL_AIR_BIAS_KEY, None)
    try:
        table[STILL_AIR_KEY], bias = still_air_report(model, flight, table)
        if bias is not None:
            table[STILL_AIR_BIAS_KEY] = bias
    except WindEstimationError as exc:
        print(f"airwake: warning: no still_air_wind_error in the spec (the wind "
              f"estimate's intervals will not carry it): {exc}", file=sys.stderr)


def _handle(args: argparse.Namespace) -> int:
    from airwake.calibrate import calibrate
    from airwake.estimate.wind import STILL_AIR_BIAS_KEY
    from airwake.heli import check_spec_path, save_spec

    check_spec_path(args.out)
    result = calibrate(
        args.flight, model=args.model, method=args.method, params=args.params,
        window_s=args.window_s, warmup_s=args.warmup_s, max_windows=args.max_windows,
        seed=args.seed, particles=args.particles, iterations=args.iterations,
        pso_windows=args.pso_windows or None, max_nfev=args.max_nfev,
        channel_scale=args.channel_scale, cutoff_hz=args.cutoff_hz or None,
        progress=sys.stderr.isatty() or args.progress, yaw_gyro_effect=args.yaw_gyro)
    desc = (f"calibrated by airwake calibrate --method {args.method} from {args.flight} "
            f"(start {args.model})")
    table = calibration_table(result, args.flight, args.model)
    path = save_spec(result.model, args.out, description=desc, calibration=table)
    info = result.info
    bias = table.get(STILL_AIR_BIAS_KEY)
    if args.json:
        print(json.dumps({**result.to_dict(), "spec": str(path),
                          "held": info.get("held", []), "front_end": info.get("front_end"),
                          "envelope": info.get("envelope"),
                          "wind_trust": info.get("wind_trust"),
                          "yaw_gyro": info.get("yaw_gyro"),
                          STILL_AIR_BIAS_KEY: bias}, indent=2))
    else:
        print_report(result, path, bias=bias)
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "calibrate", help="fit the helicopter model's parameters to a still-air flight",
        description="Fit the model's free parameters to a flight table by one-step-ahead "
        "(equation-error) least squares (--method lsq, default, fast) or the reference's "
        "particle swarm (--method pso, eq 5.16). Prints per-channel RMS before/after, "
        "fitted values with 1-sigma uncertainty and an identifiability report, and writes "
        "the fitted model spec (docs/calibration.md).")
    p.add_argument("flight", metavar="FLIGHT", help="flight table (.parquet or .csv)")
    p.add_argument("--model", default="table51",
                   help="starting model spec (path or shipped name; default table51)")
    p.add_argument("--method", choices=("lsq", "pso"), default="lsq")
    p.add_argument("--params", nargs="+", metavar="NAME",
                   help="parameters to fit: names or globs ('main_rotor.*'); default: the "
                   "parameters not marked fixed that this flight identifies (subset selection)")
    p.add_argument("--cutoff-hz", type=float, default=6.0,
                   help="front-end zero-phase low-pass of every signal, Hz (6, the wind "
                   "estimator's; 0 = fit the raw flight)")
    p.add_argument("--out", required=True, metavar="SPEC", help="fitted model spec to write")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.add_argument("--seed", type=int, default=0, help="PSO random seed (default 0)")
    p.add_argument("--particles", type=int, default=2000, help="PSO swarm size (2000)")
    p.add_argument("--iterations", type=int, default=500, help="PSO iterations (500)")
    p.add_argument("--pso-windows", type=int, default=16,
                   help="PSO: windows of the flight scored per iteration (16; 0 = all)")
    p.add_argument("--max-nfev", type=int, default=60,
                   help="least squares: max residual evaluations (60)")
    p.add_argument("--window-s", type=float, default=2.0, help="scored window length (2 s)")
    p.add_argument("--warmup-s", type=float, default=1.0,
                   help="rotor-state warm-up before each window (1 s)")
    p.add_argument("--max-windows", type=int, default=None,
                   help="fit on an evenly spaced subset of this many windows")
    p.add_argument("--channel-scale", type=float, nargs=6, metavar="S",
                   help="per-channel noise scales (acc x/y/z m/s^2, pdot/qdot/rdot rad/s^2); "
                   "default: estimated from the data")
    p.add_argument("--yaw-gyro", action="store_true",
                   help="where the flight's tail-servo capture shows a yaw gyro, add the "
                   "catalogue's yaw_gyro to the fitted model with the gain it measures (the "
                   "gyro's share of the fitted yaw damping answers the inertial yaw rate, "
                   "not the air's rotation; docs/calibration.md)")
    p.add_argument("--progress", action="store_true", help="progress lines even when piped")
    p.set_defaults(func=_handle)
