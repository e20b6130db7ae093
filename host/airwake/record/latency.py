"""Stamping latencies the boards declare (`stamp_latency` frames), removed from the streams.

A board stamps each frame at one well-defined event (the `time` of each message in
docs/protocol.md), which can come a known, fixed time after the instant the frame's data
describe. The rover and the base stamp an `ins` frame when the VN200 packet's last byte
has been parsed: the VN200's output latency plus the packet's time on the UART after the
IMU sample (500 us + 88 bytes at 921600 baud = 1455 us). The boards declare such latencies
from their own firmware constants in `stamp_latency` frames (one per described message
after each heartbeat), recorded like every other frame; `airwake export` subtracts them:

    sample instant = mapped host time - latency_us * 1e-6          (per "<board>/<message>")

    declared = declared_latencies(streams)     # {"rover/ins": DeclaredLatency(1455, ...)}
    streams = remove_latencies(streams, declared)
    metadata["stamp_latency"] = latency_metadata(declared, removed=True)

A recording without `stamp_latency` frames (boards from before the declaration) keeps its
stamps as they are, with a note in the metadata.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from airwake.link.messages import BY_ID, STAMP_LATENCY
from airwake.record.flight_builder import MessageTable

STAMP_EVENTS: dict[int, str] = next(f.values for f in STAMP_LATENCY.fields
                                    if f.name == "stamp_event")
NO_DECLARATIONS_NOTE = ("no stamp_latency frames in the recording (boards from before they "
                        "declared their stamp latencies): times are the boards' stamps")
DISABLED_NOTE = "declared stamp latencies not removed (--no-latency-correction)"


@dataclass(frozen=True)
class DeclaredLatency:
    """One stream's declaration: the latest value and every value the recording holds."""

    latency_us: int
    stamp_event: str
    frames: int  # stamp_latency frames that declared this stream
    values_us: tuple[int, ...]  # distinct values declared (one unless the firmware changed)


def declared_latencies(streams: Mapping[str, MessageTable]) -> dict[str, DeclaredLatency]:
    """"<board>/<message>" -> its declaration, from the "<board>/stamp_latency" streams."""
    out: dict[str, DeclaredLatency] = {}
    for key, table in sorted(streams.items()):
        board, _, name = key.partition("/")
        if name != STAMP_LATENCY.name or len(table) == 0:
            continue
        rows = table.data[np.argsort(table.t_s, kind="stable")]
        for msg_id in np.unique(rows["msg_id"]):
            info = BY_ID.get(int(msg_id))
            if info is None:
                continue
            mine = rows[rows["msg_id"] == msg_id]
            last = mine[-1]
            event = int(last["stamp_event"])
            out[f"{board}/{info.name}"] = DeclaredLatency(
                latency_us=int(last["latency_us"]),
                stamp_event=STAMP_EVENTS.get(event, f"event_{event}"),
                frames=int(mine.size),
                values_us=tuple(sorted({int(v) for v in mine["latency_us"]})))
    return out


def remove_latencies(streams: Mapping[str, MessageTable],
                     declared: Mapping[str, DeclaredLatency]) -> dict[str, MessageTable]:
    """The streams with each declared stream's times moved back by its latency."""
    out = dict(streams)
    for key, d in declared.items():
        t = streams.get(key)
        if t is not None:
            out[key] = MessageTable(np.asarray(t.t_s, dtype=float) - d.latency_us * 1e-6,
                                    t.data)
    return out


def latency_metadata(declared: Mapping[str, DeclaredLatency], removed: bool) -> dict:
    """The flight table's `stamp_latency` entry (docs/flight-table.md)."""
    note = None
    if not declared:
        note = NO_DECLARATIONS_NOTE
    elif not removed:
        note = DISABLED_NOTE
    changed = sorted(k for k, d in declared.items() if len(d.values_us) > 1)
    if changed and removed:
        note = (f"declared latency changed within the recording for {', '.join(changed)}: "
                "the last value was removed from the whole stream")
    return {
        "removed": bool(removed and declared),
        "streams": {k: {"latency_ms": d.latency_us / 1000.0, "stamp_event": d.stamp_event,
                        **({"values_ms": [v / 1000.0 for v in d.values_us]}
                           if len(d.values_us) > 1 else {})}
                    for k, d in sorted(declared.items())},
        "note": note,
    }
