"""Recording -> per-message tables on the host timeline -> flight table (`airwake export`).

The raw bytes are the source of truth: each port's bytes are decoded again with the batch
decoder (`decode_capture`), every frame gets the receive time of the read that completed
it (its trailing 0x00), and each board's clock is refitted offline over the whole
recording (`link.clock`): clock frames replay the epoch/unwrap logic of the live daemon,
then every epoch is fitted piecewise (60 s windows every 15 s, two-sided with the
time-sync replies) and every frame's board time is mapped through it. The live mapping
the daemon wrote into the JSON channels is not used: the offline fit sees both sides
of every moment.

Then each stream's declared stamp latency (`stamp_latency` frames the boards send:
`record.latency`) is subtracted from its host times, so a row's time is the instant its
data describe rather than the event the board stamped (the rover's INS rows were 1.455 ms
late: its packets are stamped at their last byte).

`t_s` = host CLOCK_MONOTONIC time minus the recording's `start_monotonic_ns`, s.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from airwake.errors import AirwakeError
from airwake.link.batch import decode_capture
from airwake.link.clock import (
    BACK_JUMP_US,
    BIN_US,
    CLOCK_FRAME_IDS,
    HALF_WRAP,
    WRAP,
    BoardClock,
    bin_minima,
    fit_piecewise,
)
from airwake.link.messages import BOARDS, BY_NAME, HEARTBEAT, TIME_SYNC_REPLY
from airwake.record.flight_builder import (
    BuiltFlight,
    FlightBuildConfig,
    MessageTable,
    build_flight_table,
    build_marker_table,
)
from airwake.record.latency import declared_latencies, latency_metadata, remove_latencies
from airwake.record.marker_pose import TrackerPlacement, missing_marker_streams
from airwake.record.reader import Recording
from airwake.record.rigging import PwmRigging

# Mapped board times must lie in [rx - MAX_AGE_US, rx + MAX_EARLY_US] (see map_board_times).
MAX_EARLY_US = 500_000.0
MAX_AGE_US = 60_000_000.0


class ExportError(AirwakeError):
    """A recording that cannot be exported (which one and why)."""


@dataclass
class FrameIndex:
    """Every frame of one origin on one port, in arrival order."""

    name: np.ndarray  # message name per frame (object)
    row: np.ndarray  # row in that message's table
    end: np.ndarray  # byte offset of the frame's trailing delimiter
    u32: np.ndarray
    rx_us: np.ndarray


def _frame_index(tables: dict[str, np.ndarray], origin: int, ends: dict[str, np.ndarray],
                 rx_us: dict[str, np.ndarray]) -> FrameIndex:
    names, rows, end, u32, rx = [], [], [], [], []
    for name, t in tables.items():
        sel = np.flatnonzero(t["origin"] == origin)
        if sel.size == 0:
            continue
        names.append(np.full(sel.size, name, dtype=object))
        rows.append(sel)
        end.append(ends[name][sel])
        u32.append(t["board_time_us"][sel].astype(np.int64))
        rx.append(rx_us[name][sel])
    order = np.argsort(np.concatenate(end), kind="stable")
    return FrameIndex(np.concatenate(names)[order], np.concatenate(rows)[order],
                      np.concatenate(end)[order], np.concatenate(u32)[order],
                      np.concatenate(rx)[order])


def map_board_times(fi: FrameIndex, tables: dict[str, np.ndarray]) -> tuple[np.ndarray,
                                                                              np.ndarray, dict]:
    """(epoch, host_us) per frame of one origin, and a report of the clock fits."""
    n = fi.u32.size
    is_clock = np.array([BY_NAME[x].id in CLOCK_FRAME_IDS for x in fi.name], dtype=bool)
    clock = BoardClock(keep_all=True)
    epoch = np.zeros(n, dtype=np.int64)
    board = np.zeros(n, dtype=np.int64)
    ck = np.flatnonzero(is_clock)
    if ck.size == 0:  # no clock frames at all: replay every frame (slow, but only here)
        ck = np.arange(n)
    hb_name, sync_name = HEARTBEAT.name, TIME_SYNC_REPLY.name
    for i in ck:
        name = fi.name[i]
        u32, rx = int(fi.u32[i]), float(fi.rx_us[i])
        if name == hb_name:
            r = tables[name][fi.row[i]]
            clock.heartbeat(SimpleNamespace(uptime_ms=int(r["uptime_ms"]),
                                            boot_count=int(r["boot_count"])), u32, rx)
        elif name == sync_name:
            r = tables[name][fi.row[i]]
            clock.sync_reply(SimpleNamespace(host_time_us=int(r["host_time_us"]),
                                             board_rx_time_us=int(r["board_rx_time_us"]),
                                             board_tx_time_us=int(r["board_tx_time_us"])),
                             u32, rx)
        e, b, _ = clock.frame(BY_NAME[name].id, u32, rx)
        epoch[i], board[i] = e, b
    # data frames: unwrapped against the clock frame received last before them
    data = np.setdiff1d(np.arange(n), ck, assume_unique=True)
    if data.size:
        j = np.clip(np.searchsorted(ck, data) - 1, 0, ck.size - 1)
        ref = ck[j]
        d = ((fi.u32[data] - fi.u32[ref] + HALF_WRAP) % WRAP) - HALF_WRAP
        epoch[data] = epoch[ref]
        board[data] = board[ref] + d
        # stamped more than 1 s before the clock frame received just before it: a frame of
        # a new run whose first clock frames were lost, or a stale stamp; not a time
        stale = data[d < -BACK_JUMP_US]
    else:
        stale = data
    host = np.full(n, np.nan)
    report: dict = {"epochs": []}
    for ep in clock.epochs:
        sel = epoch == ep.index
        ux, uz = bin_minima(board[sel], fi.rx_us[sel] - board[sel], BIN_US)
        _, _, dx, dz = ep.points()
        pw = fit_piecewise(ux, uz, dx, dz)
        if pw is None:
            continue
        host[sel] = pw.to_host(board[sel])
        last = pw.fits[-1]
        report["epochs"].append({
            "epoch": ep.index, "reason": ep.reason, "boot_count": ep.boot_count,
            "frames": int(sel.sum()), "offset_ms": last.offset_us / 1000.0,
            "drift_ppm": last.drift_ppm, "two_sided": all(f.two_sided for f in pw.fits),
            "bound_ms": pw.bound_us / 1000.0 if np.isfinite(pw.bound_us) else None,
            "jitter_ms": float(np.median([f.jitter_us for f in pw.fits])) / 1000.0})
    # A mapped time after the frame was received, or long before, is not a time: a data
    # frame of a new run that arrived before the run's first clock frame was unwrapped
    # against the old run (or a stamp is stale, e.g. a stopped rotor's last pulse).
    implausible = (host > fi.rx_us + MAX_EARLY_US) | (host < fi.rx_us - MAX_AGE_US)
    implausible[stale] = True
    report["frames_dropped_implausible_time"] = int(implausible.sum())
    host[implausible] = np.nan
    return epoch, host, report


def recording_streams(rec: Recording) -> tuple[dict[str, MessageTable], dict]:
    """Per "<board>/<message>" tables with host times (s from the recording's start)."""
    t0_ns = rec.metadata.get("start_monotonic_ns")
    parts: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {}
    report: dict = {"ports": {}, "boards": {}}
    first_rx = []
    for role in rec.raw_roles():
        raw = rec.raw(role)
        if not raw.data:
            continue
        first_rx.append(int(raw.rx_ns[0]))
        cap = decode_capture(raw.data)
        report["ports"][role] = cap.counters()
        buf = np.frombuffer(raw.data, dtype=np.uint8)
        zeros = np.flatnonzero(buf == 0)
        ends, rx_us = {}, {}
        for name, t in cap.tables.items():
            k = np.clip(np.searchsorted(zeros, t["byte_offset"]), 0, zeros.size - 1)
            ends[name] = zeros[k]
            rx_us[name] = raw.rx_ns_at(ends[name]) / 1000.0
        origins = sorted({int(o) for t in cap.tables.values() for o in np.unique(t["origin"])})
        for origin in origins:
            fi = _frame_index(cap.tables, origin, ends, rx_us)
            epoch, host_us, rep = map_board_times(fi, cap.tables)
            board = BOARDS.get(origin, f"board{origin}")
            report["boards"][board] = {"port": role, **rep}
            for name in np.unique(fi.name):
                sel = fi.name == name
                rows = cap.tables[name][fi.row[sel]]
                parts.setdefault(f"{board}/{name}", []).append((host_us[sel], rows))
    if t0_ns is None:
        t0_ns = min(first_rx) if first_rx else 0
    streams = {}
    for key, chunks in parts.items():
        h = np.concatenate([c[0] for c in chunks])
        rows = np.concatenate([c[1] for c in chunks])
        ok = np.isfinite(h)
        streams[key] = MessageTable((h[ok] * 1000.0 - t0_ns) / 1e9, rows[ok])
    report["t0_monotonic_ns"] = int(t0_ns)
    return streams, report


def build_config(rec: Recording, overrides: dict | None = None) -> FlightBuildConfig:
    """Builder settings from the recording's metadata (daemon options), then overrides."""
    keys = ("ned_origin_lla", "base_antenna_height_above_deck_m", "base_antenna_ship_xy_m",
            "rover_antenna_to_hub_frd_m", "tracker_height_above_ground_m",
            "marker_to_hub_frd_m")
    values = {k: rec.metadata[k] for k in keys if rec.metadata.get(k) is not None}
    values.update({k: v for k, v in (overrides or {}).items() if v is not None})
    for k in ("ned_origin_lla", "rover_antenna_to_hub_frd_m", "base_antenna_ship_xy_m",
              "marker_to_hub_frd_m"):
        if k in values:
            values[k] = tuple(float(x) for x in values[k])
    if "rigging" in rec.metadata:
        values["rigging"] = PwmRigging.from_dict(rec.metadata["rigging"])
    placement = tracker_placement(rec)
    if placement is not None:
        values.setdefault("tracker_placement", placement)
    return FlightBuildConfig(**values)


def tracker_placement(rec: Recording) -> TrackerPlacement | None:
    """The LOSA tracker's place in NED: the recording's metadata keys
    `tracker_position_ned_m` (+ `tracker_heading_deg`, `tracker_tilt_deg`; the daemon's
    `--tracker-position-m` etc.), else the rig a SIL run wrote beside it (`sil/run.json`,
    older SIL recordings); None when neither says."""
    import json

    src = rec.metadata
    if src.get("tracker_position_ned_m") is None:
        run = rec.path / "sil" / "run.json"
        try:
            src = json.loads(run.read_text()).get("rig") or {}
        except (OSError, ValueError):
            return None
        if src.get("tracker_position_ned_m") is None:
            return None
    return TrackerPlacement(tuple(float(x) for x in src["tracker_position_ned_m"]),
                            float(src.get("tracker_heading_deg") or 0.0),
                            float(src.get("tracker_tilt_deg") or 0.0))


def export_recording(rec: Recording, overrides: dict | None = None, *,
                     remove_stamp_latency: bool = True) -> BuiltFlight:
    """The flight table of a recording, with metadata naming its sources, clock fits and
    the stamp latencies removed (`remove_stamp_latency=False` keeps the boards' stamps).
    A recording without the rover (a hand-carried anemometer) gives the marker table
    (`build_marker_table`: the marker pose and the anemometer at the marker IMU's rate)."""
    streams, report = recording_streams(rec)
    marker_only = "rover/ins" not in streams
    if marker_only and missing_marker_streams(streams):
        raise ExportError(f"recording {rec.path}: no rover INS frames and no "
                          f"{', '.join(missing_marker_streams(streams))} (streams: "
                          f"{sorted(streams) or 'none'}); a flight table needs the rover, a "
                          "marker table the marker and the LOSA tracker")
    declared = declared_latencies(streams)
    if remove_stamp_latency:
        streams = remove_latencies(streams, declared)
    build = build_marker_table if marker_only else build_flight_table
    built = build(streams, build_config(rec, overrides))
    built.metadata.update({
        "source": "recorder",
        "recording": str(rec.path),
        "recording_complete": rec.complete,
        "start_utc": rec.metadata.get("start_utc"),
        "t0_monotonic_ns": report["t0_monotonic_ns"],
        "boards": rec.boards,
        "clock": report["boards"],
        "link_counters": report["ports"],
        "stamp_latency": latency_metadata(declared, remove_stamp_latency),
    })
    return built
