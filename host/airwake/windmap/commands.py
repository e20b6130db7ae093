"""`airwake windmap FLIGHT_OR_RECORDING --out MAPDIR [--score] [--json]`."""

from __future__ import annotations

import argparse
import json
import sys


def _floats(text: str, n: int, name: str):
    from airwake.windmap.errors import WindMapError

    try:
        vals = tuple(float(v) for v in text.split(","))
    except ValueError:
        vals = ()
    if len(vals) != n:
        raise WindMapError(f"{name} {text!r}: expected {n} comma-separated numbers")
    return vals


def _reads() -> tuple[str, ...]:
    """The columns the map reads: the anemometer and either pose source."""
    from airwake.windmap.compensate import ANEMOMETER, POSE_SOURCES

    return (*ANEMOMETER, "anemo_valid", "marker_valid",
            *(c for src in POSE_SOURCES.values() for k in ("pos", "vel", "att", "rates")
              for c in src[k]))


def load_input(path: str):
    """(df, metadata) of a flight table, or of a recording exported on the fly."""
    from pathlib import Path

    from airwake.record.flight_table import load_flight_table
    from airwake.windmap.errors import WindMapError

    p = Path(path)
    if p.is_dir():
        from airwake.record.export import export_recording
        from airwake.record.reader import open_recording

        return _checked_export(p, export_recording(open_recording(p)))
    if not p.exists():
        raise WindMapError(f"{p}: no such flight table or recording")
    return load_flight_table(p, ("t_s",), _reads())


def _checked_export(path, built):
    """A recording's table, refused in one line naming the stream it lacks."""
    from airwake.record.flight_builder import ANEMOMETER
    from airwake.windmap.errors import WindMapError

    cols = set(built.df.columns)
    if "anemo_u_m_s" not in cols:
        raise WindMapError(f"recording {path}: no {ANEMOMETER} frames; the map needs the "
                           "anemometer (streams: " + ", ".join(built.metadata["streams"]) + ")")
    if "marker_pos_n_m" not in cols and "truth_pos_n_m" not in cols:
        reason = (built.metadata.get("marker_pose") or {}).get("reason", "no marker pose")
        raise WindMapError(f"recording {path}: {reason}")
    return built


def _handle(args: argparse.Namespace) -> int:
    from airwake.windmap.report import make_windmap

    lever = None if args.lever_arm_m is None else _floats(args.lever_arm_m, 3, "--lever-arm-m")
    mount = None if args.mount_quat is None else _floats(args.mount_quat, 4, "--mount-quat")
    table = load_input(args.input)
    summary = make_windmap(
        table, args.out, pose=args.pose, lever_arm_m=lever, mount_quat_wxyz=mount,
        score=args.score,
        source_name=str(args.input), volume_m=_floats(args.volume_m, 3, "--volume-m"),
        grid_m=args.grid_m, location_m=args.location_m, min_seconds=args.min_seconds,
        source_speed_m_s=args.source_speed_m_s)
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    print(summary["headline"])
    if args.score:
        print_score(summary["score"])
    print(f"wrote {args.out}/ (grid.parquet, locations.parquet, summary.json, "
          f"{', '.join(summary['figures'])})")
    return 0


def print_score(score: dict, stream=None) -> None:
    w = (stream or sys.stdout).write
    w(f"error = map - field (time-averaged), {score['sampled_points']} sampled grid points, "
      f"{score['locations']} locations\n")
    w(f"{'':<10}{'component':<10}{'RMS sampled':>12}{'max sampled':>12}{'RMS locations':>15}\n")
    for key in ("map", "eq_3_15", "eq_5_3"):
        for n in ("u_m_s", "v_m_s", "w_m_s"):
            a, b = score[key]["where_sampled"][n], score[key]["at_locations"][n]
            w(f"{key:<10}{n:<10}{a['rms']:>12.3f}{a['max_abs']:>12.3f}{b['rms']:>15.3f}\n")


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "windmap", help="anemometer wind map (motion-compensated, eq 3.15 / 5.3 models)",
        description="Map a carried anemometer's wind (reference §3.4): each sample turned "
        "into the site NED frame by the tracked attitude plus the sensor point's velocity, "
        "eq 3.15 (12 parameters) and eq 5.3 (6 parameters) fitted in 1.3 x 1.3 x 0.6 m "
        "volumes around each location, everything interpolated to a 5 cm grid. Writes "
        "MAPDIR/grid.parquet, locations.parquet, slice PNGs, model_error.png and "
        "summary.json (docs/wind-map.md).")
    p.add_argument("input", metavar="FLIGHT_OR_RECORDING",
                   help="flight table (.parquet/.csv) with anemo_* and pose columns, or a "
                   "recording directory")
    p.add_argument("--out", required=True, metavar="MAPDIR", help="output directory (replaced)")
    p.add_argument("--pose", default="auto", choices=("auto", "marker", "truth"),
                   help="pose columns: marker_* (tracker EKF) or truth_* (simulated); auto: "
                   "the first present")
    p.add_argument("--lever-arm-m", default=None, metavar="X,Y,Z",
                   help="pose reference point -> anemometer, body axes (default: metadata "
                   "anemometer_lever_arm_m, else 0)")
    p.add_argument("--mount-quat", default=None, metavar="W,X,Y,Z",
                   help="the anemometer's axes relative to the pose's body axes (anemometer "
                   "-> body, unit quaternion; default: metadata anemometer_mount_quat_wxyz, "
                   "else aligned)")
    p.add_argument("--volume-m", default="1.3,1.3,0.6", metavar="X,Y,Z",
                   help="model volume (1.3,1.3,0.6 m)")
    p.add_argument("--grid-m", type=float, default=0.05, help="grid spacing (0.05 m)")
    p.add_argument("--location-m", type=float, default=0.2,
                   help="cube size grouping samples into locations (0.2 m)")
    p.add_argument("--min-seconds", type=float, default=2.0,
                   help="data a location needs (2 s)")
    p.add_argument("--source-speed-m-s", type=float, default=7.24,
                   help="the source wind model errors are a percentage of (7.24 m/s, the "
                   "reference's fans)")
    p.add_argument("--score", action="store_true",
                   help="simulated tables: compare with the simulator's time-averaged field")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(func=_handle)
