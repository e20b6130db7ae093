"""`airwake export REC --out FLIGHT.parquet|.csv` and `airwake recording info|recover`."""

from __future__ import annotations

import argparse
import json
import sys

from airwake.errors import AirwakeError


class ExportUsageError(AirwakeError):
    """An export option that does not parse."""


def _floats(text: str | None, n: int, option: str):
    if text is None:
        return None
    try:
        values = [float(x) for x in text.split(",")]
    except ValueError:
        values = []
    if len(values) != n:
        raise ExportUsageError(f"{option} '{text}': expected {n} comma-separated numbers")
    return tuple(values)


def _export(args: argparse.Namespace) -> int:
    from pathlib import Path

    from airwake.record.export import export_recording
    from airwake.record.flight_table import write_flight_table
    from airwake.record.reader import open_recording

    out = Path(args.out)
    if out.suffix.lower() not in (".parquet", ".pq", ".csv"):
        raise ExportUsageError(f"--out {out}: use a .parquet or .csv file name")
    from airwake.progress import Progress

    rec = open_recording(args.recording)
    stages = Progress("export", 1, " stages", enabled=sys.stderr.isatty() or args.progress,
                      min_interval_s=0)
    overrides = {
        "ned_origin_lla": _floats(args.ned_origin, 3, "--ned-origin"),
        "base_antenna_height_above_deck_m": args.base_antenna_height_m,
        "base_antenna_ship_xy_m": _floats(args.base_antenna_ship_m, 2, "--base-antenna-ship-m"),
        "rover_antenna_to_hub_frd_m": _floats(args.rover_antenna_to_hub_m, 3,
                                              "--rover-antenna-to-hub-m"),
        "tracker_height_above_ground_m": args.tracker_height_m,
        "marker_to_hub_frd_m": _floats(args.marker_to_hub_m, 3, "--marker-to-hub-m"),
    }
    stages.update(0, f"{args.recording}: clock fits and the table (and the marker's pose, "
                  "smoothed, when the recording has it)")
    built = export_recording(rec, overrides,
                             remove_stamp_latency=not args.no_latency_correction)
    write_flight_table(built.df, out, built.metadata)
    stages.finish(f"{len(built.df)} rows")
    m = built.metadata
    summary = {"out": str(out), "rows": len(built.df), "columns": list(built.df.columns),
               "rate_hz": m.get("rate_hz"), "span_s": [m["trimmed"]["start_s"],
                                                       m["trimmed"]["end_s"]],
               "missing_streams": m["missing_streams"], "gaps": m["gaps"],
               "recording_complete": m["recording_complete"], "clock": m["clock"],
               "stamp_latency": m["stamp_latency"]}
    if args.json:
        print(json.dumps(summary, indent=2, default=str))
    else:
        print(f"{out}: {len(built.df)} rows at {m['rate_hz']:.1f} Hz, "
              f"{m['trimmed']['end_s'] - m['trimmed']['start_s']:.1f} s, "
              f"{len(built.df.columns)} columns")
        if m["stamp_latency"]["note"]:
            print(f"note: {m['stamp_latency']['note']}")
        if not m["recording_complete"]:
            print("note: the recording was not closed cleanly; exported what was readable")
        if m["missing_streams"]:
            print(f"warning: missing streams {m['missing_streams']}: their columns are absent",
                  file=sys.stderr)
    return 0


def _info(args: argparse.Namespace) -> int:
    from airwake.record.reader import open_recording

    d = open_recording(args.recording).describe()
    if args.json:
        print(json.dumps(d, indent=2, default=str))
        return 0
    print(f"{d['path']}: {'complete' if d['complete'] else 'NOT closed cleanly (recovered)'}")
    for s in d["segments"]:
        state = "indexed" if s["indexed"] else (
            f"recovered {s['recovered_bytes']}/{s['bytes']} B ({s['error']})")
        print(f"  {s['path']}: {s['bytes']} B, {state}")
    for name, b in d["boards"].items():
        print(f"  board {name}: port {b.get('port')}, firmware {b.get('fw_version')}, schema "
              f"{b.get('schema_hash')}")
    for topic, n in d["topics"].items():
        print(f"  {topic:<32} {n:>9}")
    return 0


def _recover(args: argparse.Namespace) -> int:
    from airwake.record.reader import recover_recording

    path = recover_recording(args.recording, args.out)
    print(f"{path}: closed, indexed copy of {args.recording}")
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "export", help="turn a daemon recording into a flight table (Parquet or CSV)",
        description="Decode the recording's raw bytes, refit every board clock over the "
        "whole recording, remove the stamp latencies the boards declare and build the flight "
        "table (docs/flight-table.md, docs/recordings.md). Geometry options override the "
        "recording's metadata.")
    p.add_argument("recording", metavar="REC", help="recording directory (or one segment)")
    p.add_argument("--out", required=True, metavar="FLIGHT.parquet|.csv")
    p.add_argument("--ned-origin", metavar="LAT,LON,H")
    p.add_argument("--base-antenna-height-m", type=float)
    p.add_argument("--base-antenna-ship-m", metavar="X,Y",
                   help="base antenna on the ship (x forward of the hangar step, y starboard)")
    p.add_argument("--rover-antenna-to-hub-m", metavar="X,Y,Z")
    p.add_argument("--tracker-height-m", type=float)
    p.add_argument("--marker-to-hub-m", metavar="X,Y,Z",
                   help="indoors: marker centre -> rotor hub, body axes FRD (m)")
    p.add_argument("--no-latency-correction", action="store_true",
                   help="keep the boards' stamps: do not subtract the stamp latencies they "
                   "declare (stamp_latency frames) from the streams' times")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.add_argument("--progress", action="store_true", help="progress lines even when piped")
    p.set_defaults(func=_export)

    g = subparsers.add_parser("recording", help="inspect or recover daemon recordings")
    gs = g.add_subparsers(dest="recording_command", metavar="ACTION")
    g.set_defaults(_group_parser=g)
    i = gs.add_parser("info", help="segments, boards, topics and message counts")
    i.add_argument("recording", metavar="REC")
    i.add_argument("--json", action="store_true")
    i.set_defaults(func=_info)
    r = gs.add_parser("recover", help="write an unfinished recording out as closed, indexed "
                      "MCAP")
    r.add_argument("recording", metavar="REC")
    r.add_argument("--out", required=True, metavar="DIR")
    r.set_defaults(func=_recover)
