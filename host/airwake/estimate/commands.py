"""`airwake wind estimate FLIGHT [--model SPEC] [--particles N] [--seed N] [--score]
--out WIND.parquet`."""

from __future__ import annotations

import argparse
import json
import sys


def print_score(score: dict, stream=None) -> None:
    w = (stream or sys.stdout).write
    w(f"error = estimate - truth, {score['samples']} samples after {score['burn_in_s']:g} s\n")
    w(f"{'component':<16}{'mean':>10}{'std':>10}{'post. std':>11}"
      f"{'Table 5.3 mean':>16}{'Table 5.3 std':>15}\n")
    for name, c in score["components"].items():
        w(f"{name:<16}{c['error_mean']:>10.4f}{c['error_std']:>10.4f}"
          f"{c['posterior_std_mean']:>11.4f}{c['table_5_3_mean']:>16.4f}"
          f"{c['table_5_3_std']:>15.4f}\n")


def _handle(args: argparse.Namespace) -> int:
    from airwake.calibrate import load_flight
    from airwake.estimate import estimate_wind, score_wind, write_wind
    from airwake.estimate.errors import WindEstimationError
    from airwake.estimate.wind import check_output

    check_output(args.out)
    ft = load_flight(args.flight)
    if args.score:  # fail before the long run, not after it
        from airwake.record.flight_table import TRUTH_WIND

        missing = [c for c in TRUTH_WIND if c not in ft.df.columns]
        if missing:
            raise WindEstimationError(
                f"{args.flight}: --score needs the truth columns; missing {missing}")
    est = estimate_wind(
        ft, model=args.model, n_particles=args.particles, sigma=args.sigma,
        resampler=args.resampler, ess_threshold=args.ess_threshold, jitter=args.jitter,
        seed=args.seed, process_std=args.process_std, channel_scale=args.channel_scale,
        progress=sys.stderr.isatty() or args.progress)
    write_wind(est, args.out)
    report = {"out": str(args.out), "samples": int(len(est.df)), "seconds": est.seconds,
              "realtime_factor": est.metadata["realtime_factor"],
              "mean_ess": float(est.df["ess"].mean()),
              "resampled_fraction": float(est.df["resampled"].mean()),
              "skipped_samples": int(est.df["skipped"].sum())}
    if args.score:
        report["score"] = score_wind(est.df, ft.df, args.burn_in_s)
    if args.json:
        print(json.dumps(report, indent=2))
    else:
        print(f"wind estimate: {report['samples']} samples in {est.seconds:.1f} s "
              f"({report['realtime_factor']:.2f} x real time), mean ESS "
              f"{report['mean_ess']:.0f}, resampled {100 * report['resampled_fraction']:.0f} %"
              f" of samples, skipped {report['skipped_samples']}")
        if args.score:
            print_score(report["score"])
        print(f"wrote {args.out}")
    return 0


def _wind_group(subparsers):
    """The `wind` command group (shared with other areas' wind sub-commands)."""
    group = subparsers.choices.get("wind")
    if group is None:
        group = subparsers.add_parser("wind", help="wind from the helicopter's dynamics",
                                      description="Wind estimation commands.")
        group.set_defaults(_group_parser=group)
        group.add_subparsers(dest="wind_command", metavar="SUBCOMMAND")
    for action in group._actions:  # noqa: SLF001 — argparse has no public accessor
        if isinstance(action, argparse._SubParsersAction):  # noqa: SLF001
            return action
    return group.add_subparsers(dest="wind_command", metavar="SUBCOMMAND")


def register(subparsers) -> None:
    sub = _wind_group(subparsers)
    p = sub.add_parser(
        "estimate", help="6-D wind per sample with the particle filter (eq 5.17)",
        description="Estimate the eq 5.3 wind (mean flow v and rotation w, body axes at the "
        "hub) at every sample of a flight with the active particle filter, from the "
        "helicopter model's measurement channels (docs/wind-estimation.md).")
    p.add_argument("flight", metavar="FLIGHT", help="flight table (.parquet or .csv)")
    p.add_argument("--model", default="table52",
                   help="calibrated model spec (path or shipped name; default table52)")
    p.add_argument("--particles", type=int, default=2000, help="particles (2000)")
    p.add_argument("--seed", type=int, default=0, help="random seed (0)")
    p.add_argument("--sigma", type=float, default=0.5,
                   help="eq 5.17 error sensitivity factor (0.5, on noise-scaled channels)")
    p.add_argument("--resampler", default="systematic",
                   choices=("systematic", "stratified", "roulette", "multinomial"),
                   help="systematic on ESS < N/2 (default) or the reference's roulette wheel "
                   "(multinomial, every sample)")
    p.add_argument("--ess-threshold", type=float, default=None,
                   help="resample when ESS < this x N (default 0.5; 1 for roulette)")
    p.add_argument("--jitter", type=float, default=0.2,
                   help="regularisation kernel width, x Silverman's bandwidth (0.2)")
    p.add_argument("--process-std", type=float, nargs=6, metavar="Q",
                   help="random-walk intensity per component (m/s/sqrt(s) x3, rad/s/sqrt(s) x3)")
    p.add_argument("--channel-scale", type=float, nargs=6, metavar="S",
                   help="per-channel noise scales; default: estimated from the data")
    p.add_argument("--score", action="store_true",
                   help="compare with the flight's truth_wind_* columns and Table 5.3")
    p.add_argument("--burn-in-s", type=float, default=2.0,
                   help="seconds at the start left out of the score (2)")
    p.add_argument("--out", required=True, metavar="WIND.parquet", help="output table")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.add_argument("--progress", action="store_true", help="progress lines even when piped")
    p.set_defaults(func=_handle)
