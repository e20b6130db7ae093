"""Link health: what each port and each board delivers, and how well.

`BoardLink` is one origin board as seen by the host (a port may carry several: the base
forwards the rover's frames): identity from its heartbeat, frames and sequence gaps per
message, its clock (`clock.BoardClock`). `RateMeter` turns running counters into rates
between two snapshots. `port_health` / `board_health` make the JSON-friendly dicts of
`--status-json` (docs/daemon.md lists the keys).
"""

from __future__ import annotations

import math

from airwake.link.clock import BoardClock
from airwake.link.decoder import StreamDecoder
from airwake.link.messages import BOARDS, BY_ID, SCHEMA_HASH

HEARTBEAT_COUNTERS = ("frames_sent", "bytes_sent", "tx_bytes_dropped", "rx_frames_ok",
                      "rx_crc_error", "rx_unknown_id", "rx_def_mismatch", "rx_cobs_error",
                      "rx_oversize", "rx_bytes_dropped", "buffer_overruns", "task_max_us")


class RateMeter:
    """Rates of named counters between successive `update()` calls."""

    def __init__(self) -> None:
        self._last: dict[str, float] = {}
        self._t: float | None = None
        self.rates: dict[str, float] = {}

    def update(self, now: float, counters: dict[str, float]) -> dict[str, float]:
        if self._t is not None and now > self._t:
            dt = now - self._t
            self.rates = {k: (v - self._last.get(k, 0.0)) / dt for k, v in counters.items()}
        self._t = now
        self._last = dict(counters)
        return self.rates


class BoardLink:
    """One origin board: identity, per-message counts and seq gaps, clock."""

    def __init__(self, origin: int, port: str, clock: BoardClock | None = None) -> None:
        self.origin = origin
        self.name = BOARDS.get(origin, f"board{origin}")
        self.port = port
        self.clock = clock or BoardClock()
        self.heartbeat = None
        self.heartbeat_host_s: float | None = None
        self.first_seen_s: float | None = None
        self.identified = False
        self.counts = [0] * 256
        self.lost = [0] * 256
        self._last_seq = [-1] * 256
        self.rates = RateMeter()
        self.schema_problems: list[str] = []
        # what the board declares of its stamps (stamp_latency): message -> latency, us
        self.stamp_latency_us: dict[str, int] = {}

    def declare_stamp(self, entry) -> bool:
        """Take one stamp_latency entry; True when it changes what the board declared."""
        info = BY_ID.get(entry.msg_id)
        name = info.name if info is not None else f"msg{entry.msg_id}"
        changed = self.stamp_latency_us.get(name) != entry.latency_us
        self.stamp_latency_us[name] = int(entry.latency_us)
        return changed

    def count(self, msg_id: int, seq: int) -> None:
        """Count one frame and its sequence gap (per message, this origin)."""
        self.counts[msg_id] += 1
        last = self._last_seq[msg_id]
        if last >= 0:
            gap = (seq - last - 1) & 0xFF
            if gap:
                self.lost[msg_id] += gap
        self._last_seq[msg_id] = seq

    def reset_sequences(self) -> None:
        """A new epoch (reboot): sequence numbers restart, so no gap across it."""
        self._last_seq = [-1] * 256

    def frames(self) -> dict[str, int]:
        return {BY_ID[i].name: n for i, n in enumerate(self.counts) if n and i in BY_ID}

    def seq_lost(self) -> dict[str, int]:
        return {BY_ID[i].name: n for i, n in enumerate(self.lost) if n and i in BY_ID}

    def identity(self) -> dict:
        hb = self.heartbeat
        if hb is None:
            return {"board_id": self.origin, "port": self.port}
        return {
            "board_id": hb.board_id, "port": self.port,
            "fw_version": f"{hb.fw_version_major}.{hb.fw_version_minor}.{hb.fw_version_patch}",
            "schema_hash": f"0x{hb.schema_hash:08X}", "schema_ok": hb.schema_hash == SCHEMA_HASH,
            "boot_count": hb.boot_count, "reset_cause": hb.reset_cause,
            **({"stamp_latency_us": dict(sorted(self.stamp_latency_us.items()))}
               if self.stamp_latency_us else {}),
        }


def board_health(b: BoardLink, now_s: float) -> dict:
    """Status of one board (rates are per second since the previous call)."""
    rates = b.rates.update(now_s, {k: float(v) for k, v in b.frames().items()})
    hb = b.heartbeat
    out = {
        **b.identity(),
        "identified": b.identified,
        "heartbeat_age_s": None if b.heartbeat_host_s is None else now_s - b.heartbeat_host_s,
        "uptime_s": None if hb is None else hb.uptime_ms / 1000.0,
        "rates_hz": {k: round(v, 2) for k, v in sorted(rates.items())},
        "frames": b.frames(),
        "seq_lost": b.seq_lost(),
        "clock": b.clock.status(),
        "schema_problems": list(b.schema_problems),
    }
    if hb is not None:
        out["board_counters"] = {k: getattr(hb, k) for k in HEARTBEAT_COUNTERS}
    return out


def port_health(role: str, device: str, baud: int, is_open: bool, decoder: StreamDecoder,
                port_stats: dict, rates: RateMeter, now_s: float, boards: list[str]) -> dict:
    """Status of one port: connection, bytes, decoder errors."""
    errors = dict(decoder.errors)
    errors["bytes_dropped"] = decoder.bytes_dropped
    r = rates.update(now_s, {"bytes": float(decoder.bytes_total),
                             "frames": float(decoder.frames_ok)})
    return {
        "device": device, "baud": baud, "state": "open" if is_open else "waiting",
        "bytes": decoder.bytes_total, "frames": decoder.frames_ok,
        "bytes_per_s": round(r.get("bytes", 0.0), 1),
        "frames_per_s": round(r.get("frames", 0.0), 1),
        "errors": errors, "boards": boards, **port_stats,
    }


def fmt_age(age: float | None) -> str:
    if age is None or not math.isfinite(age):
        return "-"
    return f"{age:.1f}s"
