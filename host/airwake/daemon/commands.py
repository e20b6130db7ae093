"""`airwake daemon --port ROLE=DEVICE[@BAUD] ... --out REC`: the ship-laptop program."""

from __future__ import annotations

import argparse

from airwake.errors import AirwakeError


class DaemonUsageError(AirwakeError):
    """A daemon option that does not parse."""


def _floats(text: str, n: int, option: str) -> list[float]:
    try:
        values = [float(x) for x in text.split(",")]
    except ValueError:
        values = []
    if len(values) != n:
        raise DaemonUsageError(f"{option} '{text}': expected {n} comma-separated numbers")
    return values


def _handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from airwake.daemon.daemon import Daemon, DaemonOptions
    from airwake.link.serial_port import PortSpec

    meta: dict = {}
    if args.ned_origin is not None:
        meta["ned_origin_lla"] = _floats(args.ned_origin, 3, "--ned-origin")
    if args.base_antenna_height_m is not None:
        meta["base_antenna_height_above_deck_m"] = args.base_antenna_height_m
    if args.base_antenna_ship_m is not None:
        meta["base_antenna_ship_xy_m"] = _floats(args.base_antenna_ship_m, 2,
                                                  "--base-antenna-ship-m")
    if args.rover_antenna_to_hub_m is not None:
        meta["rover_antenna_to_hub_frd_m"] = _floats(args.rover_antenna_to_hub_m, 3,
                                                      "--rover-antenna-to-hub-m")
    if args.tracker_height_m is not None:
        meta["tracker_height_above_ground_m"] = args.tracker_height_m
    if args.marker_to_hub_m is not None:
        meta["marker_to_hub_frd_m"] = _floats(args.marker_to_hub_m, 3, "--marker-to-hub-m")
    if args.tracker_position_m is not None:
        meta["tracker_position_ned_m"] = _floats(args.tracker_position_m, 3,
                                                 "--tracker-position-m")
        meta["tracker_heading_deg"] = args.tracker_heading_deg
        meta["tracker_tilt_deg"] = args.tracker_tilt_deg
    elif args.tracker_heading_deg or args.tracker_tilt_deg:
        raise DaemonUsageError("--tracker-heading-deg/--tracker-tilt-deg need "
                               "--tracker-position-m N,E,D (where the tracker stands)")
    for item in args.meta or []:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise DaemonUsageError(f"--meta '{item}': expected KEY=VALUE")
        meta[key] = value
    opts = DaemonOptions(
        ports=[PortSpec.parse(p) for p in args.port], out=Path(args.out),
        status_json=args.status_json, duration_s=args.duration, view=not args.quiet,
        poll_s=args.poll_ms / 1000.0, marker_rate_hz=args.marker_rate_hz,
        track=False if args.no_track else (True if args.track else None), net=args.net,
        wind_net=args.wind_net,
        segment_s=args.segment_s, record_metadata=meta, live=args.live, foxglove=args.foxglove,
        # the page updates at >= 2 Hz with the very snapshot --status-json writes
        status_period_s=0.5 if args.live is not None else 1.0)
    return Daemon(opts).run()


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "daemon", help="ingest the boards' serial ports into a crash-safe recording",
        description="Open every --port, identify the boards from their heartbeats, decode, "
        "map each board clock onto the host timeline and record raw bytes + decoded "
        "messages into REC (a directory of MCAP segments). Shows link health once a second; "
        "closes the marker loop; reconnects lost ports; stops cleanly on SIGINT/SIGTERM. "
        "Exit status 0, or 1 when the recording failed (e.g. disk full). See docs/daemon.md.")
    p.add_argument("--port", action="append", required=True, metavar="ROLE=DEVICE[@BAUD]",
                   help="a serial port by role, e.g. base=/dev/ttyUSB0@921600 (repeat; "
                   "default baud 921600)")
    p.add_argument("--out", required=True, metavar="REC", help="new recording directory")
    p.add_argument("--status-json", metavar="PATH|-",
                   help="link health as JSON: a file rewritten atomically every second, or "
                   "'-' for one JSON line per second on stdout (the view goes to stderr)")
    p.add_argument("--duration", type=float, metavar="S", help="stop after S seconds")
    p.add_argument("--quiet", action="store_true", help="no terminal view")
    p.add_argument("--poll-ms", type=float, default=5.0,
                   help="loop period: reads are batched at most this long (default 5)")
    p.add_argument("--marker-rate-hz", type=float, default=60.0,
                   help="marker_command rate when a marker and a LOSA are present")
    track = p.add_mutually_exclusive_group()
    track.add_argument("--no-track", action="store_true",
                       help="no live pose EKF (by default it loads when the first marker or "
                       "LOSA frame arrives, runs once both send frames, records /host/pose "
                       "and gives the marker loop its position)")
    track.add_argument("--track", action="store_true",
                       help="load the live pose EKF at start instead of at the first marker "
                       "or LOSA frame")
    p.add_argument("--net", metavar="NET.pt", default=None,
                   help="a rate net (airwake nets train): live airwake intensity A_ω per "
                   "rover INS sample, recorded on /host/airwake_intensity (docs/networks.md)")
    p.add_argument("--wind-net", metavar="WIND.pt", default=None,
                   help="a wind net (airwake nets train --target wind): the live eq 5.3 wind "
                   "per rover INS sample, recorded on /host/wind (docs/networks.md)")
    p.add_argument("--live", metavar="[HOST:]PORT",
                   help="serve a read-only live page (link health, recording, estimates) on "
                   "PORT, loopback unless HOST is named (e.g. 0.0.0.0:8080); beyond the "
                   "loopback it needs the token printed at start (docs/daemon.md)")
    p.add_argument("--foxglove", metavar="[HOST:]PORT",
                   help="serve the recording's channels live over the Foxglove WebSocket "
                   "protocol on PORT (e.g. 8765), loopback unless HOST is named")
    p.add_argument("--segment-s", type=float, default=600.0,
                   help="start a new MCAP segment every S seconds (default 600)")
    g = p.add_argument_group("geometry for the export (stored in the recording's metadata)")
    g.add_argument("--ned-origin", metavar="LAT,LON,H", help="origin of pos_*_m (deg, deg, m)")
    g.add_argument("--base-antenna-height-m", type=float,
                   help="base RTK antenna height above the deck (m)")
    g.add_argument("--base-antenna-ship-m", metavar="X,Y",
                   help="base RTK antenna on the ship: x forward of the hangar step, y "
                   "starboard (m); with it the export places the hub in the ship frame")
    g.add_argument("--rover-antenna-to-hub-m", metavar="X,Y,Z",
                   help="rover antenna -> rotor hub, body axes FRD (m)")
    g.add_argument("--tracker-height-m", type=float,
                   help="indoors: LOSA tracker centre height above the floor (m)")
    g.add_argument("--marker-to-hub-m", metavar="X,Y,Z",
                   help="indoors: marker centre -> rotor hub, body axes FRD (m): the hub's "
                   "height from the tracked marker's; write --marker-to-hub-m=0,0,-0.45 "
                   "when the first value is negative")
    g.add_argument("--tracker-position-m", metavar="N,E,D",
                   help="LOSA tracker centre in the site's NED frame (m): with it the export "
                   "puts the tracked marker's pose in NED (docs/flight-table.md); write "
                   "--tracker-position-m=-3.5,0,-1.5 when the first value is negative")
    g.add_argument("--tracker-heading-deg", type=float, default=0.0,
                   help="direction the tracker faces, from north (deg, default 0)")
    g.add_argument("--tracker-tilt-deg", type=float, default=0.0,
                   help="tracker face tilted up from horizontal (deg, default 0)")
    g.add_argument("--meta", action="append", metavar="KEY=VALUE",
                   help="extra metadata for the recording (repeat)")
    p.set_defaults(func=_handle)
