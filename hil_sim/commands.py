"""`airwake sim ...`: the simulator's commands.

    airwake sim table --scenario NAME_OR_FILE [--duration S] [--seed N] --out FLIGHT.parquet|.csv
    airwake sim scenarios                         list the shipped scenarios

`sim table` flies the truth world (hil_sim.world.run) and writes the flight table through
the shared builder (the same one `airwake export` uses). The SIL layer adds `sim run`
here: use `add_scenario_arguments` for the options every sim command shares, and
`load_scenario_from_args` to resolve them.
"""

from __future__ import annotations

import argparse


def add_scenario_arguments(parser: argparse.ArgumentParser) -> None:
    """--scenario, --duration, --seed, --truth, --pilot (shared by every sim command)."""
    parser.add_argument("--scenario", required=True, metavar="NAME_OR_FILE",
                        help="scenario name (hil_sim/scenarios/NAME.toml) or a .toml path")
    parser.add_argument("--duration", type=float, default=None, metavar="S",
                        help="simulated seconds (default: the scenario's duration_s)")
    parser.add_argument("--seed", type=int, default=None, metavar="N",
                        help="random seed (default: the scenario's seed)")
    parser.add_argument("--truth", choices=("effects", "blade_element"), default=None,
                        help="the truth helicopter (default: the scenario's [helicopter] "
                        "model): the independent blade-element machine, or the effect "
                        "model with the scenario's hidden effects")
    parser.add_argument("--pilot", choices=("full_state", "crossover"), default=None,
                        help="who flies (default: the scenario's [helicopter] pilot): an "
                        "LQR on the true state, or a human-like crossover-model pilot")


def load_scenario_from_args(args):
    """(scenario, seed, duration) from the shared options (ScenarioError if bad)."""
    from hil_sim.world.scenario import ScenarioError, load_scenario

    scenario = load_scenario(args.scenario)
    if args.duration is not None and not args.duration > 0:
        raise ScenarioError(f"--duration {args.duration!r}: must be > 0")
    if args.seed is not None and args.seed < 0:
        raise ScenarioError(f"--seed {args.seed!r}: must be >= 0")
    seed = scenario.seed if args.seed is None else args.seed
    duration = scenario.duration_s if args.duration is None else args.duration
    changes = {k: v for k, v in (("model", getattr(args, "truth", None)),
                                 ("pilot", getattr(args, "pilot", None))) if v is not None}
    if changes:
        scenario = scenario.with_helicopter(**changes)
    return scenario, seed, duration


def register(subparsers) -> None:
    sim = subparsers.add_parser("sim", help="the simulator: truth world, scenarios, SIL",
                                description="Simulated flights (hil_sim).")
    sim.set_defaults(_group_parser=sim)
    sub = sim.add_subparsers(dest="sim_command", metavar="SUBCOMMAND")

    table = sub.add_parser(
        "table", help="fly a scenario in the truth world and write its flight table",
        description="Fly a scenario in the truth world (helicopter, pilot, wind, ship, "
        "sensors) and write the flight table (measured channels with sensor noise, "
        "truth_* columns, metadata) through the shared flight-table builder. "
        "Deterministic for a given seed.")
    add_scenario_arguments(table)
    table.add_argument("--out", required=True, metavar="FLIGHT",
                       help="output flight table (.parquet or .csv)")
    table.add_argument("--json", action="store_true",
                       help="print a JSON summary (rows, columns, timing) on stdout")
    table.add_argument("--quiet", action="store_true", help="no progress line")
    table.set_defaults(func=_table)

    survey = sub.add_parser(
        "survey", help="a hand-carried anemometer survey of the two-fan hall (table)",
        description="Carry the anemometer (with the tracking marker) through the "
        "fans_indoor field: serpentine stations at several heights, dwelling at each "
        "(reference §3.4). Writes a table of anemometer samples with the carrier's truth "
        "pose, for `airwake windmap` (docs/wind-map.md).")
    survey.add_argument("--out", required=True, metavar="SURVEY",
                        help="output table (.parquet or .csv)")
    survey.add_argument("--seed", type=int, default=2, help="random seed (2)")
    survey.add_argument("--dwell-s", type=float, default=20.0,
                        help="time at each station (20 s, the reference's)")
    survey.add_argument("--json", action="store_true", help="print a JSON summary")
    survey.set_defaults(func=_survey)

    lst = sub.add_parser("scenarios", help="list the shipped scenarios")
    lst.add_argument("--json", action="store_true")
    lst.set_defaults(func=_scenarios)

    from hil_sim.boards.commands import register_run  # `sim run` (the SIL layer)
    from hil_sim.campaign.commands import register_campaign  # `sim campaign`

    register_run(sub)
    register_campaign(sub)


def _table_path(path):
    """The output table's Path, checked before any work: a known extension, an existing
    directory (FlightTableError otherwise)."""
    from pathlib import Path

    from airwake.record.flight_table import FlightTableError

    out = Path(path)
    if out.suffix.lower() not in (".parquet", ".pq", ".csv"):
        raise FlightTableError(f"{out}: unknown flight-table extension '{out.suffix}'; "
                               "use .parquet or .csv")
    if not out.parent.exists():
        raise FlightTableError(f"{out}: directory {out.parent} does not exist")
    return out


def _table(args) -> int:
    import json
    import os

    from airwake.progress import Progress
    from airwake.record.flight_table import write_flight_table

    from hil_sim.world.run import run_scenario

    out = _table_path(args.out)
    scenario, seed, duration = load_scenario_from_args(args)
    progress = Progress(f"sim {scenario.name}", duration, unit="s",
                        enabled=not (args.quiet or args.json))
    result = run_scenario(scenario, seed=seed, duration_s=duration, progress=progress)
    built = result.flight_table()
    tmp = out.with_name(f".{out.name}.tmp{out.suffix}")
    try:
        write_flight_table(built.df, tmp, built.metadata)
        os.replace(tmp, out)
    finally:
        if tmp.exists():
            tmp.unlink()
    summary = {"out": str(out), "scenario": scenario.name, "seed": seed,
               "duration_s": duration, "rows": int(len(built.df)),
               "columns": int(built.df.shape[1]),
               "realtime_factor": result.realtime_factor,
               "timing_s": dict(result.timing)}
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        t = result.timing
        print(f"{out}: {len(built.df)} rows x {built.df.shape[1]} columns, "
              f"{duration:g} s of scenario {scenario.name!r} (seed {seed}); "
              f"real-time factor {result.realtime_factor:.1f} "
              f"(integration {t.get('integration', 0):.1f} s, sensors "
              f"{t.get('sensors', 0):.1f} s, table {t.get('table', 0):.1f} s)")
    return 0


def _survey(args) -> int:
    import json
    import os

    from airwake.record.flight_table import FlightTableError, write_flight_table

    from hil_sim.world.anemometer_survey import SurveyConfig, survey_table

    out = _table_path(args.out)
    try:
        cfg = SurveyConfig(dwell_s=args.dwell_s)
    except ValueError as exc:
        raise FlightTableError(f"--dwell-s: {exc}") from None
    df, meta = survey_table(cfg, seed=args.seed)
    tmp = out.with_name(f".{out.name}.tmp{out.suffix}")
    try:
        write_flight_table(df, tmp, meta)
        os.replace(tmp, out)
    finally:
        if tmp.exists():
            tmp.unlink()
    summary = {"out": str(out), "seed": args.seed, "rows": len(df),
               "duration_s": float(df["t_s"].iloc[-1] - df["t_s"].iloc[0]),
               "stations": len(cfg.stations())}
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(f"{out}: {len(df)} anemometer samples, {summary['stations']} stations, "
              f"{summary['duration_s']:.0f} s (seed {args.seed})")
    return 0


def _scenarios(args) -> int:
    import json

    from hil_sim.world.scenario import load_scenario, scenario_names

    rows = []
    for name in scenario_names():
        sc = load_scenario(name)
        rows.append({"name": name, "duration_s": sc.duration_s, "site": sc.site.type,
                     "wind": sc.wind.get("type"), "truth": sc.helicopter.model,
                     "pilot": sc.helicopter.pilot, "description": sc.description})
    if args.json:
        print(json.dumps(rows, indent=2))
    else:
        width = max(len(r["name"]) for r in rows)
        for r in rows:
            print(f"{r['name']:{width}s} {r['duration_s']:5.0f} s  {r['site']:5s} "
                  f"{r['wind']:12s} {r['truth']:13s} {r['pilot']:10s} {r['description']}")
    return 0
