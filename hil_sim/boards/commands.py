"""`airwake sim run`: a SIL flight through the native boards, ptys and the real daemon.

    airwake sim run --scenario NAME_OR_FILE [--duration S] [--seed N] [--stepped | --wall]
                    --out REC [--boards losa,marker,rover,base] [--live [HOST:]PORT]
                    [--foxglove [HOST:]PORT] [--net NET.pt] [--wind-net WIND.pt]
                    [--json] [--quiet]

Registered by `hil_sim/commands.py` (`register_run(sub)`); the work is `sil.SilRun`.
"""

from __future__ import annotations

import argparse
import json


def register_run(sub) -> None:
    from hil_sim.commands import add_scenario_arguments

    p = sub.add_parser(
        "run", help="a SIL flight: native firmware boards over ptys into the real daemon",
        description="Fly a scenario in the truth world and feed its sensors to the native "
        "firmware boards (build/native/<board>); each board's host UART is a pty under "
        "REC/ports/ that the real daemon (a separate process) records into REC, exactly as "
        "from serial adapters. Stepped mode (default) is deterministic and runs as fast as "
        "the machine allows, the daemon on the simulator's clock; wall mode paces the "
        "flight to real time. Faults come from the scenario's [faults] table. Prints where "
        "the recording is, the real-time factor and the daemon's final link health; "
        "REC/sil/run.json records the rig, what every link injected and the timing. "
        "See docs/sil.md.")
    add_scenario_arguments(p)
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--stepped", dest="mode", action="store_const", const="stepped",
                      help="simulator-driven board clocks, as fast as possible (default)")
    mode.add_argument("--wall", dest="mode", action="store_const", const="wall",
                      help="steps paced to CLOCK_MONOTONIC (real time)")
    p.set_defaults(mode="stepped")
    p.add_argument("--out", required=True, metavar="REC", help="new recording directory")
    p.add_argument("--boards", metavar="LIST",
                   help="comma-separated boards (default: all four in a hall, rover,base "
                   "outdoors)")
    p.add_argument("--survey", action="store_true",
                   help="a hand-carried anemometer survey of the scenario's wind field "
                   "instead of its flight: the LOSA tracker and the marker, the marker "
                   "carried through fan A's jet with a Young 81000 on its serial port "
                   "(docs/wind-map.md); --duration cuts it short")
    p.add_argument("--dwell-s", type=float, default=4.0, metavar="S",
                   help="with --survey: seconds at each of its 50 stations (4)")
    p.add_argument("--asan", action="store_true",
                   help="run the ASan/UBSan builds (build/native-asan; slower)")
    p.add_argument("--live", metavar="[HOST:]PORT",
                   help="the daemon's live page on PORT (loopback unless HOST is named; "
                   "its address, with the token beyond the loopback, is printed at start): "
                   "airwake daemon --live, docs/daemon.md")
    p.add_argument("--foxglove", metavar="[HOST:]PORT",
                   help="the daemon's Foxglove WebSocket server on PORT (airwake daemon "
                   "--foxglove)")
    p.add_argument("--net", metavar="NET.pt", default=None,
                   help="the daemon's live airwake intensity from this rate net (airwake "
                   "daemon --net)")
    p.add_argument("--wind-net", metavar="WIND.pt", default=None,
                   help="the daemon's live wind from this wind net (airwake daemon "
                   "--wind-net)")
    p.add_argument("--json", action="store_true", help="print the run summary as JSON")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    p.set_defaults(func=_run)

    t = sub.add_parser(
        "truth", help="add the truth world's truth_* columns to an export of a SIL recording",
        description="Scoring only: put the truth world's truth_* columns (wind, states, "
        "noise-free channels) of a SIL flight beside its exported flight table, matched on "
        "the simulator's timeline, and the scenario's configuration and seed in the "
        "metadata (what `airwake wind map --score` rebuilds the wind field from). The "
        "analysis never reads these columns; --score options do.")
    t.add_argument("recording", metavar="REC", help="recording of `airwake sim run`")
    t.add_argument("--flight", required=True, metavar="FLIGHT",
                   help="its export (airwake export REC --out FLIGHT)")
    t.add_argument("--out", required=True, metavar="FLIGHT_TRUTH",
                   help="flight table with the truth columns (.parquet or .csv)")
    t.set_defaults(func=_truth)


def _run(args: argparse.Namespace) -> int:
    from airwake.progress import Progress

    from hil_sim.boards.rig import rig_for, survey_rig
    from hil_sim.boards.sil import SilError, SilRun
    from hil_sim.commands import load_scenario_from_args

    scenario, seed, duration = load_scenario_from_args(args)
    boards = None
    if args.boards:
        boards = tuple(b.strip() for b in args.boards.split(",") if b.strip())
    survey = None
    if args.survey:
        if boards is not None and set(boards) != {"losa", "marker"}:
            raise SilError(f"--boards {args.boards}: a survey carries the marker past the "
                           "LOSA tracker (losa,marker) and nothing else")
        if scenario.site.type != "hall":
            raise SilError(f"--survey: scenario {scenario.name!r} is a {scenario.site.type} "
                           "flight; a hand-carried survey needs a hall (e.g. fans_indoor)")
        from hil_sim.boards.rig import sil_survey_config
        from hil_sim.world.anemometer_survey import survey_duration_s

        try:
            survey = sil_survey_config(args.dwell_s)
        except ValueError as exc:
            raise SilError(f"--dwell-s: {exc}") from None
        duration = args.duration if args.duration is not None else survey_duration_s(survey)
        rig = survey_rig(survey)
    else:
        try:
            rig = rig_for(scenario, boards)
        except ValueError as exc:
            raise SilError(f"--boards {args.boards}: {exc}") from None
    show = not (args.quiet or args.json)
    run = SilRun(scenario, out=args.out, seed=seed, duration_s=duration, mode=args.mode,
                 rig=rig, flavour="asan" if args.asan else "release", survey=survey,
                 live=args.live, foxglove=args.foxglove, net=args.net, wind_net=args.wind_net,
                 progress=Progress(f"sil {scenario.name} ({args.mode})", duration, unit=" s",
                                   enabled=show),
                 world_progress=Progress(f"truth world {scenario.name}", duration, unit=" s",
                                         enabled=show))
    result = run.run()
    if run.progress is not None:
        run.progress.finish()
    if args.json:
        print(json.dumps(result.summary, indent=1, default=str))
    else:
        print(format_report(result))
    return 0 if result.daemon_exit == 0 else 1


def format_report(result) -> str:
    """Where the recording is, the real-time factor, and the daemon's final link health."""
    s = result.summary
    t = s["timing"]
    cpu = s["cpu"]
    lines = [f"recording: {result.out}  (export: airwake export {result.out} --out "
             "FLIGHT.parquet)",
             f"{s['duration_s']:g} s of {s['scenario']!r} (seed {s['seed']}, {s['mode']}) with "
             f"{', '.join(s['boards'])}: real-time factor {t['realtime_factor']:.2f} "
             f"({t['flight_wall_s']:.1f} s wall; truth world {t['world_s']:.1f} s, set-up "
             f"{t['setup_s']:.1f} s)",
             f"CPU over the flight: simulator {cpu['simulator_s']:.1f} s, daemon "
             f"{cpu['daemon_s'] or 0:.1f} s, boards "
             f"{sum(v or 0 for v in cpu['boards_s'].values()):.2f} s",
             f"daemon exit status {result.daemon_exit}; run summary: {result.out}/sil/run.json"]
    st = result.daemon_status or {}
    for role, p in sorted(st.get("ports", {}).items()):
        err = {k: v for k, v in p.get("errors", {}).items() if v}
        lines.append(f"  port {role}: {p.get('frames', 0)} frames, {p.get('bytes', 0)} bytes, "
                     f"opens {p.get('opens', 0)}, seq lost {p.get('seq_lost', 0)}, errors "
                     f"{err or 'none'}")
    duration = s["duration_s"] or 1.0
    for name, b in sorted(st.get("boards", {}).items()):
        # mean rates over the flight (in stepped mode host time is simulator time)
        rates = ", ".join(f"{k} {n / duration:.0f}" for k, n in sorted(b.get("frames",
                                                                           {}).items())
                          if n / duration >= 1 and k != "schema_entry")
        clock = b.get("clock") or {}
        lost = sum((b.get("seq_lost") or {}).values())
        lines.append(f"  board {name}: boot count {b.get('boot_count')}, clock epochs "
                     f"{clock.get('epochs')}, frames lost (seq gaps) {lost}; Hz: {rates}")
    injected = {k: v for k, v in s["faults"]["links"].items()
                if v["bytes_lost"] or v["bits_flipped"] or v["bytes_cut"] or v["reset_cuts"]}
    for name, v in injected.items():
        lines.append(f"  injected on {name}: {v['bytes_lost']} bytes lost, {v['bits_flipped']} "
                     f"bits flipped, {v['bytes_cut']} bytes cut by outages -> "
                     f"{v['bad_segments']} bad segments, {v['frames_in'] - v['frames_intact']} "
                     "frames not delivered intact")
    for e in s["faults"]["events"]:
        lines.append(f"  event: {json.dumps(e)}")
    return "\n".join(lines)


def _truth(args: argparse.Namespace) -> int:
    import os
    from pathlib import Path

    from airwake.record.flight_table import load_flight_table, write_flight_table

    from hil_sim.boards.sil import add_truth

    out = Path(args.out)
    flight = load_flight_table(args.flight, required=("t_s",))  # marker tables too
    df, meta = add_truth(flight, Path(args.recording))
    tmp = out.with_name(f".{out.stem}.tmp{out.suffix}")
    try:
        write_flight_table(df, tmp, meta)
        os.replace(tmp, out)
    finally:
        tmp.unlink(missing_ok=True)
    n = sum(c.startswith("truth_") for c in df.columns)
    print(f"{out}: {len(df)} rows, {n} truth columns from {args.recording}/sil "
          f"(simulator time = t_s + {meta['sim_time_offset_s']:.6f} s)")
    return 0
