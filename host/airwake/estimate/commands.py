"""`airwake wind estimate FLIGHT [--model SPEC] [--method smoother|apf] [--score] --out WIND`
and `airwake wind map WIND --flight FLIGHT --out MAPDIR [--cell-m 0.5] [--score]`."""

from __future__ import annotations

import argparse
import json
import sys
import warnings


def print_score(score: dict, stream=None) -> None:
    w = (stream or sys.stdout).write
    w(f"error = estimate - truth, {score['samples']} samples after {score['burn_in_s']:g} s\n")
    w(f"{'component':<15}{'mean':>8}{'std':>8}{'corr':>7}{'truth std':>10}{'post. std':>10}"
      f"{'cov90':>7}{'5.3 mean':>10}{'5.3 std':>9}\n")
    for name, c in score["components"].items():
        w(f"{name:<15}{c['error_mean']:>8.3f}{c['error_std']:>8.3f}{c['correlation']:>7.2f}"
          f"{c['truth_std']:>10.3f}{c['posterior_std_mean']:>10.3f}{c['coverage_90']:>7.2f}"
          f"{c['table_5_3_mean']:>10.4f}{c['table_5_3_std']:>9.4f}\n")
    if "crlb" in score:
        w(f"\nCramer-Rao bound (posterior, at the {score['crlb']['at']}; the model's channel "
          f"error {score['crlb'].get('noise_model', 'white')}, RMS "
          + " ".join(f"{v:.3g}" for v in score["crlb"]["noise_std"]) + ")\n")
        w(f"{'component':<15}{'error RMS':>10}{'bound':>8}{'ratio':>7}\n")
        for name, c in score["components"].items():
            ratio = c["error_over_crlb"]
            w(f"{name:<15}{c['error_rms']:>10.3f}{c['crlb_std']:>8.3f}"
              + (f"{ratio:>7.2f}\n" if ratio is not None else f"{'-':>7}\n"))


def _ins_line(meta: dict) -> str:
    std, source = meta["ins_velocity_std_m_s"], meta["ins_velocity_std_source"]
    detail = meta.get("ins_velocity_error") or {}
    if source == "gnss":
        return (f"INS velocity error {std:.3f} m/s, measured against the GNSS velocity over "
                f"{detail.get('seconds', 0):.0f} s (receiver lag {detail.get('gnss_lag_s', 0):.2f}"
                " s): added to the mean-flow std")
    if source == "user":
        return f"INS velocity error {std:.3f} m/s (--ins-velocity-std): added to the mean-flow std"
    return (f"INS velocity error {std:.3f} m/s from the VN-200 datasheet: {detail.get('why')}; "
            f"{detail.get('advice')}")


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
        ft, model=args.model, method=args.method, cutoff_hz=args.cutoff_hz,
        rate_hz=args.rate_hz, em_passes=args.em_passes, airspeed_m_s=args.airspeed_m_s,
        ins_velocity_std=args.ins_velocity_std, accel_bias_std=args.accel_bias_std,
        n_particles=args.particles,
        sigma=args.sigma, resampler=args.resampler, ess_threshold=args.ess_threshold,
        jitter=args.jitter, seed=args.seed, process_std=args.process_std,
        channel_scale=args.channel_scale, progress=sys.stderr.isatty() or args.progress,
        net=args.net, interval_model=args.interval_model, anchor=args.anchor,
        rotation_from_mean_flow=args.rotation_sigma != "learned",
        model_error=args.model_error)
    write_wind(est, args.out)
    report = {"out": str(args.out), "method": args.method, "samples": int(len(est.df)),
              "seconds": est.seconds, "realtime_factor": est.metadata["realtime_factor"]}
    if args.method == "net":
        report.update(net=args.net, training_flights=est.metadata["net_training_flights"])
        report["held_out"] = not _trained_on(args.flight, report["training_flights"])
        report["std_is"] = est.metadata["std_is"]
        report["training_envelope_inside"] = est.metadata["training_envelope_inside"]
        if args.interval_model is not None:
            report.update({k: est.metadata[k] for k in (
                "interval_model", "interval_fast_std_median_m_s",
                "interval_unseen_std_median_m_s", "interval_turbulence_sigma_m_s")})
    elif args.method == "apf":
        report.update(mean_ess=float(est.df["ess"].mean()),
                      resampled_fraction=float(est.df["resampled"].mean()),
                      skipped_samples=int(est.df["skipped"].sum()))
    else:
        report.update(prior=est.metadata["prior"], noise_std=est.metadata["noise_std"],
                      anchor=est.metadata.get("anchor"),
                      still_air_wind_error=est.metadata.get("still_air_wind_error"))
    report["calibration_envelope"] = est.metadata.get("calibration_envelope")
    report["ins_velocity_std_m_s"] = est.metadata["ins_velocity_std_m_s"]
    report["ins_velocity_std_source"] = est.metadata["ins_velocity_std_source"]
    if args.score:
        report["score"] = score_wind(est.df, ft.df, args.burn_in_s)
        if args.method == "smoother" and args.anchor is None:
            # (an anchored estimate has information the model's bound does not)
            from airwake.estimate.wind import score_bound, wind_bound

            score_bound(report["score"], wind_bound(est, ft.df), est.df)
    if args.json:
        print(json.dumps(report, indent=2))
    else:
        line = (f"wind estimate ({args.method}): {report['samples']} samples in "
                f"{est.seconds:.1f} s ({report['realtime_factor']:.1f} x real time)")
        if args.method == "net":
            line += f", net {args.net}"
            if not report["held_out"]:
                line += (" - this flight trained the net: a score here is not a held-out "
                         "one")
            line += f"\nstd: {est.metadata['std_is']}"
            inside = report["training_envelope_inside"]
            if inside is not None:
                env = est.metadata["training_envelope"]
                line += (f"\nair velocity inside the net's training flights: {100 * inside:.0f} "
                         f"% of samples (joint cells of {env['cell_m_s']:g} m/s flown for "
                         f"{env['min_s']:g} s or more)"
                         + ("" if inside >= 0.8 else " - outside them the net extrapolates: "
                            "fly still-air legs at these air velocities (docs/networks.md)"))
        elif args.method == "apf":
            line += (f", mean ESS {report['mean_ess']:.0f}, resampled "
                     f"{100 * report['resampled_fraction']:.0f} % of samples, skipped "
                     f"{report['skipped_samples']}")
        else:
            pr = report["prior"]
            line += ("\nlearned prior: turbulence std " + " ".join(
                f"{v:.3g}" for v in pr["sigma"]) + " (m/s x3, 1/s x3), correlation time "
                + " ".join(f"{v:.2g}" for v in pr["tau_s"]) + " s; channel noise "
                + " ".join(f"{v:.2g}" for v in report["noise_std"]))
            if report["anchor"]:
                line += (f"\nmean flow anchored on {report['anchor']}: the rotation is read "
                         "given it, its interval no narrower than the anchor's (no "
                         "Cramer-Rao bound: the anchor is information the model's bound has "
                         "not)")
            excess = report["still_air_wind_error"]
            if excess is not None:
                line += ("\nstd widened by the error this model's estimate made beyond its "
                         "interval on its still-air calibration flight: " + " ".join(
                             f"{v:.2g}" for v in excess) + " (m/s x3, 1/s x3)")
        print(line)
        print(_ins_line(est.metadata))
        env = est.metadata.get("calibration_envelope")
        if env:
            inside = env["inside_fraction"]
            print("air velocity inside the calibration flight's envelope: " + ", ".join(
                f"{a} {100 * v:.0f} %" for a, v in inside.items())
                + ("" if min(inside.values()) >= 0.9 else
                   " - outside it the speed-dependent terms are extrapolated") + "; "
                + "components the calibration trusts: "
                + (" ".join(k for k, v in env["trusted"].items() if v) or "none"))
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


def _trained_on(flight, training_flights) -> bool:
    """Is `flight` one of the net's training flights (same file)?"""
    from pathlib import Path

    me = Path(flight).resolve()
    return any(Path(p).resolve() == me for p in training_flights)


def register(subparsers) -> None:
    sub = _wind_group(subparsers)
    p = sub.add_parser(
        "estimate", help="6-D wind per sample from the helicopter's dynamics",
        description="Estimate the eq 5.3 wind (mean flow v and rotation w, body axes at the "
        "hub) along a flight from the helicopter model's measurement channels: an iterated "
        "Kalman smoother (default) or the reference's active particle filter "
        "(docs/wind-estimation.md).")
    p.add_argument("flight", metavar="FLIGHT", help="flight table (.parquet or .csv)")
    p.add_argument("--model", default="table52",
                   help="calibrated model spec (path or shipped name; default table52)")
    p.add_argument("--method", choices=("smoother", "apf", "net"), default="smoother",
                   help="smoother (default): iterated EKF/RTS smoother with the wind prior "
                   "learned from the flight; apf: the reference's particle filter (eq 5.17); "
                   "net: a direct wind network (§4.6, --net)")
    p.add_argument("--net", default=None, metavar="WIND.pt",
                   help="net: a wind net of `airwake nets train --target wind` "
                   "(docs/networks.md); its std columns are its validation RMS")
    p.add_argument("--interval-model", default=None, metavar="SPEC",
                   help="net: a calibrated model whose smoother, run on the same flight, "
                   "widens the net's mean-flow interval by their local disagreement above "
                   "0.1 Hz - the wind's fast part a still-air net does not follow - and by "
                   "the fast part its own posterior says it did not see either "
                   "(docs/networks.md); the smoother's options apply to it (--em-passes: "
                   "16 for it unless given)")
    p.add_argument("--anchor", default=None, metavar="WIND.parquet",
                   help="smoother: a wind table made without the model (--method net with a "
                   "still-air net, best with --interval-model) whose mean flow, with its "
                   "std, the smoother takes as a measurement: the model then reads the "
                   "rotation given that mean flow (docs/wind-estimation.md)")
    p.add_argument("--cutoff-hz", type=float, default=None,
                   help="front-end low-pass (6 Hz; below the rotor's 1/rev); apf only: 0 = "
                   "raw flight")
    p.add_argument("--rate-hz", type=float, default=None,
                   help="estimator sample rate after the low-pass (15 Hz smoother, 30 Hz apf)")
    p.add_argument("--em-passes", type=int, default=None,
                   help="smoother passes (3: 2 relinearising; the prior re-learnt after each; "
                   "16 for --interval-model's smoother)")
    p.add_argument("--rotation-sigma", choices=("from-mean-flow", "learned"),
                   default="from-mean-flow",
                   help="smoother: the turbulence std of w_x, w_y set from the mean flow's "
                   "learned one (default; docs/wind-estimation.md) or learned on its own")
    p.add_argument("--airspeed-m-s", type=float, default=None,
                   help="typical airspeed for the prior's correlation times (3 m/s)")
    p.add_argument("--ins-velocity-std", type=float, default=None,
                   help="INS velocity error, 1 sigma (m/s), added to the mean-flow std "
                   "(default: measured on the flight against its GNSS velocity; the "
                   "VN-200 datasheet's 0.05 m/s, said so, when it has none)")
    p.add_argument("--accel-bias-std", type=float, default=None, metavar="M_S2",
                   help="smoother: the INS's residual accelerometer bias on this flight, 1 "
                   "sigma per axis (m/s^2; its data sheet): a steady force the estimate "
                   "cannot tell from a steady wind, added to the model's own steady misfit "
                   "in the intervals (default: none given, only the model's)")
    p.add_argument("--model-error", choices=("consider", "states"), default="consider",
                   help="smoother: the model's steady misfit per channel (its spec's "
                   "model_error_offset) kept out of the estimate and its effect added to the "
                   "intervals (consider, forces only; default), or estimated as slowly "
                   "varying bias states beside the wind (states: best with --anchor, which "
                   "pins the mean flow; docs/wind-estimation.md)")
    p.add_argument("--particles", type=int, default=2000, help="apf: particles (2000)")
    p.add_argument("--seed", type=int, default=0, help="apf: random seed (0)")
    p.add_argument("--sigma", type=float, default=0.5,
                   help="apf: eq 5.17 error sensitivity factor (0.5, on noise-scaled channels)")
    p.add_argument("--resampler", default="systematic",
                   choices=("systematic", "stratified", "roulette", "multinomial"),
                   help="apf: systematic on ESS < N/2 (default) or the reference's roulette "
                   "wheel (multinomial, every sample)")
    p.add_argument("--ess-threshold", type=float, default=None,
                   help="apf: resample when ESS < this x N (default 0.5; 1 for roulette)")
    p.add_argument("--jitter", type=float, default=0.2,
                   help="apf: regularisation kernel width, x Silverman's bandwidth (0.2)")
    p.add_argument("--process-std", type=float, nargs=6, metavar="Q",
                   help="apf: random-walk intensity per component (m/s/sqrt(s) x3, "
                   "rad/s/sqrt(s) x3)")
    p.add_argument("--channel-scale", type=float, nargs=6, metavar="S",
                   help="apf: per-channel noise scales; default: estimated from the data")
    p.add_argument("--score", action="store_true",
                   help="compare with the flight's truth_wind_* columns and Table 5.3")
    p.add_argument("--burn-in-s", type=float, default=2.0,
                   help="seconds at the start left out of the score (2)")
    p.add_argument("--out", required=True, metavar="WIND.parquet", help="output table")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.add_argument("--progress", action="store_true", help="progress lines even when piped")
    p.set_defaults(func=_handle)
    register_map(sub)


def _map_handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from airwake.estimate.airwake_map import FLIGHT_COLUMNS
    from airwake.estimate.errors import WindEstimationError
    from airwake.estimate.map_plots import ShipOutline
    from airwake.estimate.map_report import make_map
    from airwake.heli.model import WIND_NAMES
    from airwake.progress import Progress
    from airwake.record.flight_table import (
        FlightTableError,
        load_flight_table,
        read_flight_metadata,
    )

    out = Path(args.out)
    if not out.parent.is_dir():
        raise WindEstimationError(f"cannot write {out}: directory {out.parent} does not exist")
    try:
        # the components the estimator did not estimate (NaN throughout: a still-air
        # wind net's rotation) are neither checked nor warned about; the map shows them
        # empty
        skip = set(read_flight_metadata(args.wind).get("not_estimated") or ())
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            wind = load_flight_table(args.wind, required=(), reads=[
                c for n in WIND_NAMES if n not in skip for c in (n, f"{n}_std")])
        for w in caught:
            if not any(f"'{n}" in str(w.message) for n in skip):
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    except FlightTableError as exc:
        raise WindEstimationError(str(exc)) from None
    try:
        flight = load_flight_table(args.flight, ("t_s",), FLIGHT_COLUMNS)
    except FlightTableError as exc:
        raise WindEstimationError(str(exc)) from None
    ship = ShipOutline(args.deck_length_m, args.beam_m, args.hangar_length_m,
                       args.hangar_width_m)
    stages = Progress("wind map", 1, " stages", enabled=sys.stderr.isatty() or args.progress,
                      min_interval_s=0)
    stages.update(0, "placing, gridding" + (", scoring" if args.score else "")
                  + " and drawing the map")
    summary = make_map(wind, flight, out, cell_m=args.cell_m, layer_m=args.layer_m,
                       min_seconds=args.min_seconds, u_ref=args.reference_speed_m_s,
                       score=args.score, ship=ship, wind_name=str(args.wind),
                       flight_name=str(args.flight))
    stages.finish(f"{summary['cells']} cells")
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(summary["headline"])
        if args.score:
            print_map_score(summary["score"])
        print(f"wrote {out}/ (map.parquet, {', '.join(summary['figures'])}, index.html)")
    return 0


def print_map_score(score: dict, stream=None) -> None:
    w = (stream or sys.stdout).write
    w(f"map error = map - truth over {score['cells']} cells with >= "
      f"{score['min_seconds']:g} s of data\n")
    w(f"{'component':<12}{'along-track RMS':>17}{'field RMS':>11}{'field max':>11}\n")
    for name in score["field"]:
        a, f = score["along_track"][name], score["field"][name]
        w(f"{name:<12}{a['rms']:>17.3f}{f['rms']:>11.3f}{f['max_abs']:>11.3f}\n")


def register_map(sub) -> None:
    p = sub.add_parser(
        "map", help="airwake map in the ship frame from a wind estimate",
        description="Grid a wind estimate (airwake wind estimate) over the helicopter's "
        "positions: on a ship, the hub in the ship frame (RTK baseline rotated by the ship's "
        "attitude) and the flow relative to the ship; elsewhere the site's NED frame. Writes "
        "MAPDIR/map.parquet (per cell: centre, samples, seconds, mean flow and rotation with "
        "their std, turbulence std and intensity), mean_flow.png, turbulence.png, "
        "coverage.png, summary.json and index.html (docs/airwake-map.md).")
    p.add_argument("wind", metavar="WIND.parquet", help="wind table (airwake wind estimate)")
    p.add_argument("--flight", required=True, metavar="FLIGHT",
                   help="the flight table the wind was estimated from")
    p.add_argument("--out", required=True, metavar="MAPDIR", help="output directory (replaced)")
    p.add_argument("--cell-m", type=float, default=0.5, help="cell size in x and y (0.5 m)")
    p.add_argument("--layer-m", type=float, default=1.0, help="layer thickness in z (1 m)")
    p.add_argument("--min-seconds", type=float, default=0.5,
                   help="cells with less data are left out (0.5 s)")
    p.add_argument("--reference-speed-m-s", type=float, default=None,
                   help="U_ref of the turbulence intensity (default: the mean relative wind "
                   "speed over the flight)")
    p.add_argument("--deck-length-m", type=float, default=6.0, help="flight deck length (6)")
    p.add_argument("--beam-m", type=float, default=7.3, help="deck width (7.3)")
    p.add_argument("--hangar-length-m", type=float, default=8.0, help="hangar length (8)")
    p.add_argument("--hangar-width-m", type=float, default=6.0, help="hangar width (6)")
    p.add_argument("--score", action="store_true",
                   help="simulated flights: compare with the truth wind along the track and "
                   "with the simulator's wind field at the cell centres")
    p.add_argument("--progress", action="store_true", help="progress lines even when piped")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(func=_map_handle)
