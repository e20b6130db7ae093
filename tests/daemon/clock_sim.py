"""Synthetic board clocks for the clock-mapping tests: known offset, drift and delays."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from airwake.link.messages import HEARTBEAT, IMU, SCHEMA_ENTRY, Heartbeat, TimeSyncReply

WRAP = 1 << 32


@dataclass
class SimClock:
    """Board clock B = board0 + (h - host0) * (1 + drift); delays d0 + Exp(scale)."""

    host0_us: float = 5e9
    board0_us: float = 1e6
    drift_ppm: float = 0.0
    d0_us: float = 300.0
    scale_us: float = 1000.0
    outlier_p: float = 0.02

    def board(self, host_us):
        return self.board0_us + (np.asarray(host_us) - self.host0_us) * (1 + self.drift_ppm * 1e-6)

    def host(self, board_us):
        return self.host0_us + (np.asarray(board_us) - self.board0_us) / (
            1 + self.drift_ppm * 1e-6)

    def delay(self, rng, n):
        d = self.d0_us + rng.exponential(self.scale_us, n)
        out = rng.random(n) < self.outlier_p
        return d + out * rng.uniform(5e4, 5e5, n)


def feed(clock, sim: SimClock, rng, duration_s: float, with_sync: bool = True,
         boot_count: int = 0, start_host_us: float | None = None):
    """Drive a BoardClock; returns rows (board_us, true_host_us, mapped_host_us, live
    bound_us) of the data frames received after the first 20 s."""
    h0 = sim.host0_us if start_host_us is None else start_host_us
    events = []  # (host_rx, kind, payload)
    # clock frames at 5 Hz (heartbeat 1 Hz + schema entries 4 Hz), transmit-stamped
    t_tx = h0 + np.arange(0, duration_s * 1e6, 2e5)
    rx = t_tx + sim.delay(rng, t_tx.size)
    for i, (tx, r) in enumerate(zip(t_tx, rx, strict=True)):
        b = int(sim.board(tx))
        kind = HEARTBEAT.id if i % 5 == 0 else SCHEMA_ENTRY.id
        events.append((r, kind, b))
    # data frames at 100 Hz: sample time up to 5 ms before transmit
    t_tx = h0 + np.arange(0, duration_s * 1e6, 1e4) + 37.0
    rx = t_tx + sim.delay(rng, t_tx.size)
    sample = t_tx - rng.uniform(0, 5000, t_tx.size)
    for r, s in zip(rx, sample, strict=True):
        events.append((r, IMU.id, (int(sim.board(s)), float(s))))
    if with_sync:
        req = h0 + np.arange(0, duration_s * 1e6, 5e5) + 11.0
        down = req + sim.delay(rng, req.size)
        for htx, hdown in zip(req, down, strict=True):
            brx = int(sim.board(hdown))
            btx = brx + int(rng.uniform(0, 200))
            hrx = float(sim.host(btx)) + float(sim.delay(rng, 1)[0])
            events.append((hrx, "sync", (int(htx), brx, btx)))
    events.sort(key=lambda e: e[0])
    out = []
    for host_rx, kind, payload in events:
        if kind == "sync":
            htx, brx, btx = payload
            u32 = btx % WRAP
            rep = TimeSyncReply(1, htx, brx, btx)
            clock.sync_reply(rep, u32, host_rx)
            clock.frame(0x04, u32, host_rx)
        elif kind == IMU.id:
            b, s = payload
            _, board, mapped = clock.frame(kind, b % WRAP, host_rx)
            if host_rx > h0 + 20e6:
                out.append((board, float(sim.host(b)), mapped, clock.ep.fit.bound_us))
        else:
            b = payload
            if kind == HEARTBEAT.id:
                hb = Heartbeat(board_id=3, uptime_ms=b // 1000, boot_count=boot_count)
                clock.heartbeat(hb, b % WRAP, host_rx)
            clock.frame(kind, b % WRAP, host_rx)
    return np.array(out)
