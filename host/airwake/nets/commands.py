"""`airwake nets train|evaluate`: the pilot-compensation networks (docs/networks.md)."""

from __future__ import annotations

import argparse
import json
import sys


def _crop_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--from-s", type=float, default=None, metavar="T",
                   help="use rows with t_s >= T (leave out a spool-up)")
    p.add_argument("--to-s", type=float, default=None, metavar="T",
                   help="use rows with t_s <= T (leave out a touchdown)")


def register(subparsers) -> None:
    group = subparsers.add_parser(
        "nets", help="pilot-compensation networks: train, evaluate, airwake intensity, wind nets "
        "(docs/networks.md)",
        description="Networks that predict body rates or roll/pitch angular accelerations "
        "from the pilot's inputs (reference ch. 2, §4.3); what they cannot predict is the "
        "disturbance.")
    sub = group.add_subparsers(dest="nets_command", metavar="SUBCOMMAND")
    group.set_defaults(_group_parser=group)

    t = sub.add_parser("train", help="train a net on flights (chronological split)",
                       description="Train a rate (p, q, r) or angular-acceleration (pdot, "
                       "qdot) network on one or more flight tables with a chronological "
                       "train/validation/test split (each flight's first 65 %% trains, the "
                       "next 15 %% validates, the last 20 %% tests; --split blocks for "
                       "interleaved time blocks), fit the linear ARX baseline on the same "
                       "rows, and save weights + model card to NET.pt.")
    t.add_argument("flights", nargs="+", metavar="FLIGHT", help="flight tables (.parquet/.csv)")
    t.add_argument("--target", choices=("rates", "accel", "wind"), default="rates",
                   help="rates (p, q, r), accel (pdot, qdot), or wind: a direct wind net "
                   "(§4.6) on simulated flights' truth_wind_*, used by `airwake wind "
                   "estimate --method net`")
    t.add_argument("--out", required=True, metavar="NET.pt")
    t.add_argument("--trainer", choices=("adamw", "pso"), default="adamw")
    t.add_argument("--seed", type=int, default=0)
    t.add_argument("--hidden", default=None, metavar="H1,H2",
                   help="hidden layer sizes of each axis' MLP (default: rates 8, accel 16,8, "
                   "wind 32,16)")
    t.add_argument("--line-window-s", type=float, default=None, help="eq 2.1 history (0.5 s)")
    t.add_argument("--rate-lag", type=int, default=None, metavar="SAMPLES",
                   help="previous rates fed back, in samples (rates: 1, accel: 0)")
    t.add_argument("--rate-history", type=int, default=None, metavar="N",
                   help="feed back the rates at lags L ... L+N-1 (rates: 30, the gyro's rotor "
                   "vibration lines are predictable from them; accel: 1)")
    t.add_argument("--still-air", action="store_true",
                   help="--target wind on still-air flights, no truth needed: learn the "
                   "velocity through the air with the INS body velocity as its label; at sea "
                   "the mean flow is the INS velocity less the net's (ω not estimated). "
                   "Fly steady legs at the relative wind you expect at sea, as the "
                   "still_air_cruise scenario does (docs/networks.md)")
    t.add_argument("--pilot-only", action="store_true",
                   help="no rate fed back: predict the rates from the pilot's inputs and the "
                   "attitude alone (eq 2.4's ω′; --rate-lag and --rate-history unused)")
    t.add_argument("--train-target", choices=("measured", "lowpass"), default="measured",
                   help="fit the measured target or it low-passed (centred eq 2.3, σ 0.05 s, "
                   "within each run of one set): the dynamics, not a rotor tone (measured)")
    t.add_argument("--arx-ridge", default="1e-3", metavar="VALUE|val",
                   help="ARX ridge (x N, standardised weights), or 'val': per axis the grid "
                   "value with the smallest validation RMS (1e-3)")
    t.add_argument("--per-axis", action="store_true",
                   help="AdamW: each output axis keeps its own best validation epoch (the "
                   "default; kept for older command lines)")
    t.add_argument("--max-epochs", type=int, default=None, metavar="N",
                   help="AdamW epochs at most (300); 0 keeps the linear start: a linear "
                   "model in the net's file (the ARX itself with --time-stretch none)")
    t.add_argument("--time-stretch", default=None, metavar="val|none|F1,F2,...",
                   help="also train on the training rows played F times faster (rates: 'val' "
                   "= 0.98,0.99,1.01,1.02 unless the validation rows say they are worse; "
                   "accel: none)")
    t.add_argument("--split", choices=("chronological", "blocks"), default="chronological",
                   help="chronological: train early, validate and test later (default); "
                   "blocks: interleaved time blocks drawn with the seed")
    t.add_argument("--block-s", type=float, default=None,
                   help="block length of --split blocks (5 s)")
    t.add_argument("--inputs", choices=("delta", "pwm", "rc_norm"), default=None,
                   help="pilot-input columns (default: the first complete set)")
    _crop_args(t)
    t.add_argument("--json", action="store_true", help="print the model card as JSON")
    t.add_argument("--quiet", action="store_true", help="no progress line")
    t.set_defaults(func=_train)

    e = sub.add_parser("evaluate", help="score a net on flights (held-out rows)",
                       description="RMS and MAE per axis (deg/s for rates, rad/s^2 for "
                       "accelerations) on held-out rows: a training flight's test rows, "
                       "every row of any other flight; against the measured and the "
                       "low-passed target, next to the ARX baseline and persistence.")
    e.add_argument("net", metavar="NET.pt")
    e.add_argument("flights", nargs="+", metavar="FLIGHT")
    _crop_args(e)
    e.add_argument("--json", action="store_true", help="print the report as JSON")
    e.add_argument("--out", default=None, metavar="PRED.parquet",
                   help="write t_s, <axis>_pred_*, <axis>_resid_* of every flight (column "
                   "'flight' = index of FLIGHT when several)")
    e.set_defaults(func=_evaluate)

    a = sub.add_parser("airwake", help="airwake intensity A_ω map from a net's residuals",
                       description="A_ω (eq 2.4) and the residual std per sample from a "
                       "trained net's residuals, their peaks (>= 15 s apart, >= 1.5 local "
                       "stds over 10 s), gridded over the helicopter's position in the ship "
                       "frame (map.parquet, peaks.csv, PNGs); the residual std calibrated to "
                       "turbulence in m/s with RANSAC (§4.4.1) on simulated flights' truth "
                       "(--calibrate-on) or a stored calibration (docs/networks.md).")
    a.add_argument("flight", metavar="FLIGHT")
    which = a.add_mutually_exclusive_group(required=True)
    which.add_argument("--net", metavar="NET.pt",
                       help="a rate or acceleration net: its residuals (docs/networks.md: "
                       "an acceleration net trained on still-air flights, --target accel)")
    which.add_argument("--no-net", action="store_true",
                       help="ω′ = 0: A_ω = ω_s·‖ω‖ and the gyro's own local std, no pilot "
                       "compensation (a pilot that manoeuvres shakes the map as much as the "
                       "air: docs/networks.md)")
    a.add_argument("--out", required=True, metavar="DIR")
    a.add_argument("--std-window-s", type=float, default=0.5,
                   help="window of ω_s and of the residual std (0.5 s)")
    a.add_argument("--cell-m", type=float, default=1.0, help="map cell size (1 m)")
    a.add_argument("--layer-m", type=float, default=2.0, help="map layer height (2 m)")
    a.add_argument("--min-seconds", type=float, default=1.0,
                   help="cells with less data are left out (1 s)")
    cal = a.add_mutually_exclusive_group()
    cal.add_argument("--calibrate-on", nargs="+", metavar="SIMFLIGHT", default=None,
                     help="fit the turbulence calibration (RANSAC) on these simulated "
                     "flights' truth turbulence; written to DIR/calibration.json")
    cal.add_argument("--calibration", metavar="CAL.json", default=None,
                     help="apply a calibration.json of an earlier --calibrate-on")
    a.add_argument("--seed", type=int, default=0, help="RANSAC seed (0)")
    a.add_argument("--score", action="store_true",
                   help="simulated flight: correlate the map with the simulator's "
                   "turbulence over the same cells")
    a.add_argument("--json", action="store_true", help="print the summary as JSON")
    a.set_defaults(func=_airwake)


def _load_flights(paths, target, inputs, from_s, to_s):
    from airwake.nets import load_net_flight

    flights = [load_net_flight(p, target, inputs) for p in paths]
    if from_s is not None or to_s is not None:
        flights = [f.crop(from_s, to_s) for f in flights]
    return flights


def _train(args: argparse.Namespace) -> int:
    from pathlib import Path

    from airwake.nets import AdamWConfig, FeatureConfig, save_net, train_net
    from airwake.nets.model import NetFileError
    from airwake.nets.train import DEFAULT_RATE_HISTORY, DEFAULT_RATE_LAG

    out = Path(args.out)
    if out.suffix != ".pt" or not out.parent.is_dir():
        raise NetFileError(f"--out {out}: needs a .pt file in an existing folder")
    from airwake.nets.train import DEFAULT_HIDDEN

    spec = args.hidden or ("32,16" if args.target == "wind"
                           else ",".join(str(h) for h in DEFAULT_HIDDEN[args.target]))
    try:
        hidden = tuple(int(h) for h in spec.split(",") if h.strip())
        if not hidden or min(hidden) < 1:
            raise ValueError
    except ValueError:
        raise NetFileError(f"--hidden {args.hidden!r}: expected sizes like 16,8") from None
    if args.target == "wind":
        return _train_wind(args, out, hidden)
    if args.still_air:
        raise NetFileError("--still-air: for --target wind (the air-relative velocity "
                           "learned in still air)")
    fkw = {"rate_lag_samples": DEFAULT_RATE_LAG[args.target] if args.rate_lag is None
           else args.rate_lag,
           "rate_history_samples": DEFAULT_RATE_HISTORY[args.target]}
    if args.line_window_s is not None:
        fkw["line_window_s"] = args.line_window_s
    if args.rate_history is not None:
        fkw["rate_history_samples"] = args.rate_history
    if args.pilot_only:
        if args.rate_lag is not None or args.rate_history is not None:
            raise NetFileError("--pilot-only feeds no rate back: leave out --rate-lag and "
                               "--rate-history")
        fkw["use_rates"] = False
    if args.arx_ridge.strip().lower() == "val":
        ridge: float | str = "val"
    else:
        try:
            ridge = float(args.arx_ridge)
        except ValueError:
            raise NetFileError(f"--arx-ridge {args.arx_ridge!r}: a number >= 0 or 'val'") from None
    akw = {}
    if args.max_epochs is not None:
        if args.max_epochs < 0:
            raise NetFileError(f"--max-epochs {args.max_epochs}: must be >= 0")
        akw["max_epochs"] = args.max_epochs
    stretch = _time_stretch(args.time_stretch)
    try:
        features = FeatureConfig(**fkw)
        split = _split(args)
        flights = _load_flights(args.flights, args.target, args.inputs, args.from_s, args.to_s)
        net = train_net(flights, target=args.target, trainer=args.trainer, seed=args.seed,
                        features=features, split=split, hidden=hidden,
                        progress=not args.quiet, train_target=args.train_target,
                        arx_ridge=ridge, adamw=AdamWConfig(**akw), time_stretch=stretch)
    except ValueError as exc:
        raise NetFileError(f"nets train: {exc}") from None
    save_net(net, out)
    if args.json:
        print(json.dumps(net.card, indent=2, sort_keys=True))
    else:
        m = net.card["metrics"]
        print(f"{args.target} net ({args.trainer}, seed {args.seed}): {len(flights)} flight(s), "
              f"{m['train']['rows']} train / {m['val']['rows']} validation / "
              f"{m['test']['rows']} test rows, {net.card['train_seconds']:.1f} s")
        split = net.card["split"]
        where = ("held-out test blocks" if split["order"] == "blocks" else
                 f"held-out test rows (the last {100 * split['test_fraction']:.0f} %)")
        print(format_scores(m["test"], m["unit"], where))
        print(f"wrote {out}")
    return 0


def _time_stretch(spec):
    """--time-stretch: None (the target's default), 'val', () for 'none', or factors."""
    from airwake.nets.model import NetFileError
    from airwake.nets.train import check_time_stretch

    if spec is None:
        return None
    word = spec.strip().lower()
    if word in ("val", "none"):
        return "val" if word == "val" else ()
    try:
        return check_time_stretch(float(v) for v in spec.split(",") if v.strip())
    except ValueError as exc:
        raise NetFileError(f"--time-stretch {spec!r}: 'val', 'none' or factors like "
                           f"0.98,1.02 ({exc})") from None


def _split(args: argparse.Namespace):
    from airwake.nets.model import NetFileError
    from airwake.nets.split import SplitConfig

    if args.block_s is not None and args.split != "blocks":
        raise NetFileError("--block-s sets the blocks of --split blocks; the default split "
                           "is chronological")
    kw = {"block_s": args.block_s} if args.block_s is not None else {}
    return SplitConfig(order=args.split, **kw)


# the rate / acceleration nets' options a wind net does not take
_NOT_WIND = {"trainer": "adamw", "line_window_s": None, "rate_lag": None, "rate_history": None,
             "pilot_only": False, "train_target": "measured", "arx_ridge": "1e-3",
             "per_axis": False, "max_epochs": None, "inputs": None, "from_s": None,
             "to_s": None, "time_stretch": None, "split": "chronological"}



def _printable(card: dict) -> dict:
    """The card as printed: the training air-velocity envelope's cells counted, not
    listed (a thousand of them; the .pt keeps them)."""
    env = card.get("air_velocity_envelope")
    if env is None:
        return card
    return {**card, "air_velocity_envelope": {**{k: v for k, v in env.items()
                                                 if k != "cells"},
                                              "flown_cells": len(env["cells"])}}

def _train_wind(args: argparse.Namespace, out, hidden) -> int:
    """`nets train --target wind`: nets.wind_net on simulated flights' truth, or on
    still-air flights' INS velocity (--still-air)."""
    from airwake.nets import save_net
    from airwake.nets.model import NetFileError
    from airwake.nets.split import SplitConfig
    from airwake.nets.wind_net import train_wind_net

    given = [f"--{k.replace('_', '-')}" for k, v in _NOT_WIND.items() if getattr(args, k) != v]
    if given:
        raise NetFileError(f"--target wind: {', '.join(given)} do not apply to a wind net "
                           "(docs/networks.md)")
    if not args.quiet:
        print(f"training a wind net on {len(args.flights)} flight(s) ...", file=sys.stderr)
    try:
        # a wind net early-stops on blocks of its flights; other flights are its test set
        split = SplitConfig(order="blocks",
                            **({"block_s": args.block_s} if args.block_s else {}))
        net = train_wind_net(args.flights, seed=args.seed, hidden=hidden, split=split,
                             still_air=args.still_air)
    except ValueError as exc:
        raise NetFileError(f"nets train: {exc}") from None
    save_net(net, out)
    if args.json:
        print(json.dumps(_printable(net.card), indent=2, sort_keys=True))
        return 0
    card = net.card
    print(f"wind net (adamw, seed {args.seed}): {len(args.flights)} flight(s), "
          f"{card['training_rows']} training rows, {card['train_seconds']:.1f} s")
    still = card["wind_net_config"].get("labels") == "still_air"
    print(("validation RMS of the air velocity in still air (net / its ARX skip): " if still
           else "validation RMS (net / its ARX skip): ") + ", ".join(
        f"{o} {v['net']:.3f} / {v['arx']:.3f}" for o, v in card["validation_rms"].items()
        if not (still and "_rad_s" in o)))
    print(f"wrote {out}")
    return 0


def format_scores(scores: dict, unit: str, title: str) -> str:
    """A small text table: model x axis, RMS / MAE, measured and low-passed target, and
    the net's RMS over each baseline's (below 1: the net is better on that axis)."""
    lines = [f"{title}: {scores['rows']} rows, RMS / MAE in {unit}"]
    axes = list(next(iter(scores["measured"].values())).keys())
    head = f"  {'target':<10}{'model':<13}" + "".join(f"{a:>18}" for a in axes)
    lines.append(head)
    for ref in ("measured", "lowpass", "truth"):
        models = scores.get(ref, {})
        for model, per in models.items():
            cells = "".join(f"{per[a]['rms']:>9.3f} /{per[a]['mae']:>7.3f}" for a in axes)
            lines.append(f"  {ref:<10}{model:<13}{cells}")
        for base in ("arx", "persistence"):
            if "net" in models and base in models and models["net"]:
                ratio = "".join(f"{_ratio(models['net'][a]['rms'], models[base][a]['rms']):>18}"
                                for a in axes)
                lines.append(f"  {ref:<10}{'net/' + base[:7]:<13}{ratio}")
    return "\n".join(lines)


def _ratio(a: float, b: float) -> str:
    return f"{a / b:.3f}" if b > 0 else "-"


def _evaluate(args: argparse.Namespace) -> int:
    from pathlib import Path

    import pandas as pd

    from airwake.nets import evaluate_net, load_net, predict

    net = load_net(args.net)
    if net.card.get("target") == "wind":
        from airwake.nets.model import NetFileError

        raise NetFileError(f"{args.net} is a wind net: score it with `airwake wind estimate "
                           "FLIGHT --method net --net NET.pt --score --out WIND.parquet`")
    flights = _load_flights(args.flights, net.card["target"], net.card["input_source"],
                            args.from_s, args.to_s)
    from airwake.nets.evaluate import as_net_flight

    flights = [as_net_flight(net, f) for f in flights]
    report = evaluate_net(net, flights)
    if args.out:
        out = Path(args.out)
        if out.suffix not in (".parquet", ".csv") or not out.parent.is_dir():
            from airwake.nets.model import NetFileError

            raise NetFileError(f"--out {out}: needs a .parquet or .csv file in an existing folder")
        frames = []
        for i, f in enumerate(flights):
            df = predict(net, f)
            if len(flights) > 1:
                df.insert(0, "flight", i)
            frames.append(df)
        df = pd.concat(frames, ignore_index=True)
        df.to_parquet(out, index=False) if out.suffix == ".parquet" else df.to_csv(out, index=False)
        report["out"] = str(out)
    if args.json:
        print(json.dumps(report, indent=2, sort_keys=True))
        return 0
    for f in report["flights"]:
        print(format_scores(f, report["unit"], f"{f['path']} ({f['scored']})"))
    if len(report["flights"]) > 1:
        print(format_scores(report["overall"], report["unit"], "all flights"))
    if args.out:
        print(f"wrote {args.out}", file=sys.stderr)
    return 0


def _airwake(args: argparse.Namespace) -> int:
    from airwake.nets.intensity_commands import run_airwake

    summary = run_airwake(args)
    if args.json:
        print(json.dumps(summary, indent=2, sort_keys=True))
        return 0
    print(f"{summary['flight']}: {summary['samples']} samples, {summary['cells']} cells of "
          f"{summary['settings']['cell_m']:g} m ({summary['settings']['frame']} frame), "
          f"{len(summary['peaks'])} A_ω peak(s)")
    c = summary.get("calibration")
    if c:
        print(f"turbulence calibration ({c['source']}): {c['slope']:.4g} m/s per "
              f"{summary['resid_unit']} · resid_std {c['offset']:+.3f} m/s "
              f"({c.get('inliers', '?')}/{c.get('points', '?')} RANSAC inliers; the "
              f"reference: 0.021 m·s/rad for rad/s²)")
    s = summary.get("score")
    if s:
        print(f"score over {s['cells']} cells (>= {s['min_seconds']:g} s) against the "
              f"simulator's turbulence: Pearson A_ω {s['a_omega_pearson']:.3f}, residual std "
              f"{s['resid_std_pearson']:.3f} (Spearman {s['a_omega_spearman']:.3f}, "
              f"{s['resid_std_spearman']:.3f})"
              + (f"; calibrated RMS error {s['turbulence_rms_error_m_s']:.3f} m/s"
                 if "turbulence_rms_error_m_s" in s else ""))
    print(f"wrote {summary['out']}", file=sys.stderr)
    return 0
