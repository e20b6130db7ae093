"""Board clocks -> the host timeline: unwrap, detect reboots, fit offset + drift.

Every frame carries its origin board's µs clock as a u32 (wraps after 71.6 min). Per
board, `BoardClock`

1. **unwraps** it into a 64-bit board time per *epoch* (one run of the board between
   resets). Only frames stamped at transmit time (`heartbeat`, `schema_entry`,
   `time_sync_reply`: "clock frames") advance the unwrapping and can start an epoch;
   data frames are unwrapped against the last clock frame (a data stamp may be old: a
   rotor that stopped keeps the time of its last pulse). A new epoch starts when a clock
   frame goes back by more than 1 s, when the heartbeat's `boot_count` changes, or when an
   anchor disagrees: the heartbeat's `uptime_ms` and the 64-bit `board_tx_time_us` of a
   `time_sync_reply` fix the wrap count (the unwrapped time is the board's own 64-bit
   `micros()`). Old epochs keep their mapping, so old data maps as before.

2. **fits** host = host_ref + rate * (board - board_ref) from two one-sided bounds
   (receive delays are positive and variable, so the truth lies on an envelope, not in
   the middle of a cloud; Moon, Skelly & Towsley's lower-envelope LP, 1999):

   - every received frame: host_rx >= T(board_tx)  -> points above the true line;
   - every `time_sync_reply` to our request: host_tx <= T(board_rx) -> points below it.

   Per 1 s bin of board time only the tightest point of each side is kept. The rate is
   the slope of the lower convex hull of the received points at their mean (the LP's
   solution: the line under all points that minimises the summed gap), the offset is
   midway between the two envelopes at that rate (NTP's symmetric-delay assumption),
   or the lower envelope alone (biased late by the minimum delay) before any reply.
   Half the distance between the envelopes bounds the offset error (`bound_us`).

Live mapping uses the trailing `window_s` of bins; `PiecewiseClock` refits the whole
epoch offline in overlapping windows for the export. Times are µs (floats are exact to
well below a µs at these magnitudes).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field

import numpy as np

from airwake.link.messages import HEARTBEAT, SCHEMA_ENTRY, TIME_SYNC_REPLY

WRAP = 1 << 32
HALF_WRAP = 1 << 31
CLOCK_FRAME_IDS = frozenset({HEARTBEAT.id, SCHEMA_ENTRY.id, TIME_SYNC_REPLY.id})
BACK_JUMP_US = 1_000_000  # a clock frame this far behind the epoch's latest: a reboot
LONG_GAP_US = 600_000_000  # beyond this host gap, the wrap count comes from host time
BIN_US = 1_000_000
WINDOW_S = 60.0
# Below this span of board time the rate is taken as 1 (offset only): a short window's
# hull slope is dominated by how the first reads batched up (a port opened onto a
# buffer of old frames puts them all at one receive time: slope -1 until more arrives).
MIN_SLOPE_SPAN_US = 10_000_000
# Sync replies needed before the fit goes two-sided: the down envelope takes the least
# delayed request, but with one or two a request that waited in a buffer (the port was
# just opened) would pull the midpoint early by half its wait.
MIN_DOWN_POINTS = 3


@dataclass(frozen=True)
class ClockLine:
    """host_us = host_ref_us + rate * (board_us - board_ref_us)."""

    board_ref_us: float
    host_ref_us: float
    rate: float = 1.0

    def to_host(self, board_us):
        return self.host_ref_us + self.rate * (np.asarray(board_us, dtype=float)
                                               - self.board_ref_us)


@dataclass
class ClockFit:
    """A fitted line and how well it is known."""

    line: ClockLine
    bound_us: float  # half the gap between the envelopes (inf without sync replies)
    jitter_us: float  # median delay of received frames above the lower envelope
    n_bins: int
    two_sided: bool

    @property
    def offset_us(self) -> float:
        """host - board at the reference point (µs)."""
        return self.line.host_ref_us - self.line.board_ref_us

    @property
    def drift_ppm(self) -> float:
        """Board clock rate error against the host: +100 = the board runs 100 ppm fast."""
        rate = self.line.rate
        return (1.0 / rate - 1.0) * 1e6 if rate > 0 else math.nan


def lower_hull(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertices of the lower convex hull of points sorted by x (Andrew's monotone chain)."""
    hx: list[float] = []
    hy: list[float] = []
    for xi, yi in zip(x.tolist(), y.tolist(), strict=True):
        while len(hx) >= 2 and ((hx[-1] - hx[-2]) * (yi - hy[-2])
                                - (hy[-1] - hy[-2]) * (xi - hx[-2])) <= 0:
            hx.pop()
            hy.pop()
        if hx and xi == hx[-1]:
            if yi < hy[-1]:
                hy[-1] = yi
            continue
        hx.append(xi)
        hy.append(yi)
    return np.asarray(hx), np.asarray(hy)


def fit_envelope(up_x: np.ndarray, up_z: np.ndarray, down_x: np.ndarray | None = None,
                 down_z: np.ndarray | None = None, jitter_z: np.ndarray | None = None,
                 jitter_x: np.ndarray | None = None,
                 min_span_us: float = MIN_SLOPE_SPAN_US) -> ClockFit | None:
    """Fit host - board = z(board) from envelope points.

    up_*: received frames (board time x, z = host_rx - x), the line is below them;
    down_*: sync requests (x = board_rx, z = host_tx - board_rx), the line is above them.
    Points are the per-bin extremes; jitter_* optional raw received points for the
    jitter figure. Returns None without any received point.
    """
    if up_x.size == 0:
        return None
    order = np.argsort(up_x, kind="stable")
    ux, uz = up_x[order], up_z[order]
    x_ref = float(ux[len(ux) // 2])
    xs = ux - x_ref
    if ux[-1] - ux[0] < min_span_us:
        slope = 0.0
    else:
        hx, hz = lower_hull(xs, uz)
        if hx.size < 2:
            slope = 0.0
        else:
            # the hull edge spanning the points' mean x: the LP optimum (min summed gap)
            xm = float(np.mean(xs))
            k = int(np.clip(np.searchsorted(hx, xm) - 1, 0, hx.size - 2))
            slope = float((hz[k + 1] - hz[k]) / (hx[k + 1] - hx[k]))
    c_up = float(np.min(uz - slope * xs))
    c = c_up
    bound = math.inf
    two_sided = False
    if down_x is not None and down_x.size >= MIN_DOWN_POINTS:
        c_down = float(np.max(down_z - slope * (down_x - x_ref)))
        if c_down <= c_up:  # consistent envelopes: the truth lies between them
            c = 0.5 * (c_up + c_down)
            bound = 0.5 * (c_up - c_down)
            two_sided = True
    if jitter_x is not None and jitter_x.size:
        jitter = float(np.median(jitter_z - (c_up + slope * (jitter_x - x_ref))))
    else:
        jitter = float(np.median(uz - (c_up + slope * xs)))
    line = ClockLine(board_ref_us=x_ref, host_ref_us=x_ref + c, rate=1.0 + slope)
    return ClockFit(line, bound, jitter, int(up_x.size), two_sided)


@dataclass
class Epoch:
    """One run of a board between resets, with its unwrapping and its envelope bins."""

    index: int
    start_host_us: float
    base_us: int  # board_us of the frame that started it
    start_u32: int
    boot_count: int | None = None
    reason: str = "first frame"
    last_u32: int = 0
    last_board_us: int = 0
    max_board_us: int = 0
    last_host_us: float = 0.0
    frames: int = 0
    # envelope: bins of board time -> tightest point of each side
    up: dict[int, tuple[float, float]] = field(default_factory=dict)
    down: dict[int, tuple[float, float]] = field(default_factory=dict)
    order: deque = field(default_factory=deque)
    fit: ClockFit | None = None
    fit_bin: int = -1
    min_rtt_us: float = math.inf

    def points(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        up = np.array(list(self.up.values()), dtype=float).reshape(-1, 2)
        down = np.array(list(self.down.values()), dtype=float).reshape(-1, 2)
        return up[:, 0], up[:, 1], down[:, 0], down[:, 1]


class BoardClock:
    """Unwrapping, epochs and the live clock fit of one board (see module doc).

    Hot path: `frame(msg_id, u32, host_us)` for every frame of this board (after
    `heartbeat()` / `sync_reply()` for those frames) -> (epoch index, board_us, host_us).
    keep_all=True keeps every bin (offline refit) instead of the trailing window.
    """

    def __init__(self, window_s: float = WINDOW_S, bin_us: int = BIN_US,
                 keep_all: bool = False) -> None:
        self.window_bins = max(2, int(window_s * 1e6 / bin_us))
        self.bin_us = bin_us
        self.keep_all = keep_all
        self.epochs: list[Epoch] = []
        self.ep: Epoch | None = None
        self.events: list[dict] = []  # epoch starts, for the recording

    # -- epochs ---------------------------------------------------------------

    def _new_epoch(self, u32: int, host_us: float, board_us: int, reason: str,
                   boot_count: int | None = None) -> Epoch:
        ep = Epoch(index=len(self.epochs), start_host_us=host_us, base_us=board_us,
                   start_u32=u32, boot_count=boot_count, reason=reason, last_u32=u32,
                   last_board_us=board_us, max_board_us=board_us, last_host_us=host_us)
        self.epochs.append(ep)
        self.ep = ep
        self.events.append({"epoch": ep.index, "reason": reason, "host_us": host_us,
                            "board_us": board_us, "u32": u32, "boot_count": boot_count})
        return ep

    def _unwrap(self, ep: Epoch, u32: int, host_us: float) -> int:
        d = ((u32 - ep.last_u32 + HALF_WRAP) & (WRAP - 1)) - HALF_WRAP
        gap = host_us - ep.last_host_us
        if gap > LONG_GAP_US:  # silent for > 10 min: the host clock says how many wraps
            rate = ep.fit.line.rate if ep.fit is not None else 1.0
            d += round((gap / rate - d) / WRAP) * WRAP
        return ep.last_board_us + d

    @staticmethod
    def _anchored(u32: int, anchor_us: int) -> int:
        """The value = u32 (mod 2^32) nearest to anchor_us."""
        return u32 + round((anchor_us - u32) / WRAP) * WRAP

    def anchor(self, u32: int, host_us: float, anchor_us: int, boot_count: int | None,
               tolerance_us: int) -> None:
        """A frame whose 64-bit board time is known to within tolerance_us (heartbeat
        uptime, sync reply): start an epoch when it contradicts the current one."""
        board = self._anchored(u32, anchor_us)
        ep = self.ep
        if ep is None:
            self._new_epoch(u32, host_us, board, "first frame", boot_count)
            return
        if boot_count is not None and ep.boot_count is not None and boot_count != ep.boot_count:
            self._new_epoch(u32, host_us, board, f"boot count {ep.boot_count} -> {boot_count}",
                            boot_count)
            return
        current = self._unwrap(ep, u32, host_us)
        if board < ep.max_board_us - BACK_JUMP_US:
            self._new_epoch(u32, host_us, board, "board clock went back (reset)", boot_count)
        elif abs(current - board) > tolerance_us + HALF_WRAP // 2:
            self._new_epoch(u32, host_us, board, "wrap count corrected by the board's "
                            "64-bit time", boot_count)
        elif boot_count is not None and ep.boot_count is None:
            ep.boot_count = boot_count

    def heartbeat(self, hb, u32: int, host_us: float) -> None:
        self.anchor(u32, host_us, int(hb.uptime_ms) * 1000, int(hb.boot_count), 2000)

    def sync_reply(self, reply, u32: int, host_rx_us: float) -> None:
        """A time_sync_reply: exact anchor, plus the NTP 'down' point and the round trip."""
        self.anchor(u32, host_rx_us, int(reply.board_tx_time_us), None, 0)
        ep = self.ep
        host_tx = float(reply.host_time_us)
        board_rx = float(reply.board_rx_time_us)
        rtt = (host_rx_us - host_tx) - (float(reply.board_tx_time_us) - board_rx)
        if 0 <= rtt < ep.min_rtt_us:
            ep.min_rtt_us = rtt
        if host_tx <= 0 or rtt < 0:
            return  # not our request (another host) or nonsense: keep it out of the fit
        b = int(board_rx) // self.bin_us
        z = host_tx - board_rx
        old = ep.down.get(b)
        if old is None or z > old[1]:
            ep.down[b] = (board_rx, z)
            self._trim(ep, b)

    # -- every frame ------------------------------------------------------------

    def frame(self, msg_id: int, u32: int, host_us: float) -> tuple[int, int, float]:
        """(epoch index, unwrapped board µs, mapped host µs) of one frame."""
        ep = self.ep
        if ep is None:
            ep = self._new_epoch(u32, host_us, u32, "first frame")
        board = self._unwrap(ep, u32, host_us)
        if msg_id in CLOCK_FRAME_IDS:
            if board < ep.max_board_us - BACK_JUMP_US:
                ep = self._new_epoch(u32, host_us, u32, "board clock went back (reset)")
                board = u32
            ep.last_u32 = u32
            ep.last_board_us = board
            ep.last_host_us = host_us
            if board > ep.max_board_us:
                ep.max_board_us = board
        ep.frames += 1
        b = board // self.bin_us
        z = host_us - board
        old = ep.up.get(b)
        if old is None or z < old[1]:
            ep.up[b] = (float(board), z)
            if old is None:
                self._trim(ep, b)
                self._refit(ep, b)
        return ep.index, board, self.map(ep, board)

    def _trim(self, ep: Epoch, b: int) -> None:
        if self.keep_all:
            return
        ep.order.append(b)
        low = b - self.window_bins
        while ep.order and ep.order[0] < low:
            old = ep.order.popleft()
            ep.up.pop(old, None)
            ep.down.pop(old, None)

    def _refit(self, ep: Epoch, b: int) -> None:
        if b == ep.fit_bin:
            return
        ep.fit_bin = b
        ux, uz, dx, dz = self.window_points(ep)
        ep.fit = fit_envelope(ux, uz, dx, dz)

    def window_points(self, ep: Epoch):
        ux, uz, dx, dz = ep.points()
        if self.keep_all and ux.size:
            low = ux.max() - self.window_bins * self.bin_us
            ku, kd = ux >= low, dx >= low
            return ux[ku], uz[ku], dx[kd], dz[kd]
        return ux, uz, dx, dz

    @staticmethod
    def map(ep: Epoch, board_us) -> float:
        """Live mapping of a board time of epoch `ep` (its current fit; every epoch has
        one from its first frame on)."""
        line = ep.fit.line
        return line.host_ref_us + line.rate * (board_us - line.board_ref_us)

    def status(self) -> dict:
        """Live figures for link health."""
        ep = self.ep
        if ep is None:
            return {"epochs": 0}
        out = {"epochs": len(self.epochs), "epoch": ep.index, "boot_count": ep.boot_count,
               "epoch_reason": ep.reason}
        if ep.fit is not None:
            out.update({
                "offset_ms": ep.fit.offset_us / 1000.0,
                "drift_ppm": ep.fit.drift_ppm,
                "jitter_ms": ep.fit.jitter_us / 1000.0,
                "bound_ms": ep.fit.bound_us / 1000.0 if math.isfinite(ep.fit.bound_us) else None,
                "two_sided": ep.fit.two_sided,
            })
        if math.isfinite(ep.min_rtt_us):
            out["min_rtt_ms"] = ep.min_rtt_us / 1000.0
        return out


@dataclass
class PiecewiseClock:
    """Offline mapping of one epoch: knots (board_us, host_us), linear in between and
    the end fits' lines beyond."""

    knots_board_us: np.ndarray
    knots_host_us: np.ndarray
    first: ClockLine
    last: ClockLine
    fits: list[ClockFit]

    def to_host(self, board_us: np.ndarray) -> np.ndarray:
        b = np.asarray(board_us, dtype=float)
        out = np.interp(b, self.knots_board_us, self.knots_host_us)
        lo, hi = b < self.knots_board_us[0], b > self.knots_board_us[-1]
        out[lo] = self.first.to_host(b[lo])
        out[hi] = self.last.to_host(b[hi])
        return out

    @property
    def bound_us(self) -> float:
        return max((f.bound_us for f in self.fits), default=math.inf)


def fit_piecewise(up_x: np.ndarray, up_z: np.ndarray, down_x: np.ndarray | None = None,
                  down_z: np.ndarray | None = None, window_s: float = WINDOW_S,
                  step_s: float = 15.0) -> PiecewiseClock | None:
    """Refit one epoch offline: `fit_envelope` in windows of window_s every step_s
    (points as for fit_envelope: per-bin extremes of the whole epoch)."""
    ux, uz = np.asarray(up_x, dtype=float), np.asarray(up_z, dtype=float)
    dx = np.zeros(0) if down_x is None else np.asarray(down_x, dtype=float)
    dz = np.zeros(0) if down_z is None else np.asarray(down_z, dtype=float)
    if ux.size == 0:
        return None
    lo, hi = float(ux.min()), float(ux.max())
    half = window_s * 1e6 / 2
    step = step_s * 1e6
    if hi - lo > 2 * half:
        centres = np.arange(lo + half, hi - half + step, step)
    else:
        centres = np.array([(lo + hi) / 2])
    kb, kh, fits = [], [], []
    for c in centres:
        ku = (ux >= c - half) & (ux <= c + half)
        kd = (dx >= c - half) & (dx <= c + half)
        fit = fit_envelope(ux[ku], uz[ku], dx[kd], dz[kd])
        if fit is None:
            continue
        fits.append(fit)
        kb.append(float(c))
        kh.append(float(fit.line.to_host(c)))
    if not fits:
        return None
    return PiecewiseClock(np.asarray(kb), np.asarray(kh), fits[0].line, fits[-1].line, fits)


def bin_minima(x: np.ndarray, z: np.ndarray, bin_us: int = BIN_US) -> tuple[np.ndarray,
                                                                            np.ndarray]:
    """The point of smallest z in each bin of x (the lower envelope's candidates)."""
    x = np.asarray(x, dtype=float)
    z = np.asarray(z, dtype=float)
    if x.size == 0:
        return x, z
    b = np.floor(x / bin_us)
    order = np.lexsort((z, b))
    first = np.concatenate([[True], np.diff(b[order]) != 0])
    keep = order[first]
    return x[keep], z[keep]
