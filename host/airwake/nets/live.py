"""A rate net live on the daemon's ingest timeline: A_ω per rover INS sample (docs/daemon.md
"Live airwake intensity", docs/networks.md).

Inputs, each with its host-timeline time (the board stamp mapped by `link.clock`):
- base `pilot_inputs` (50 Hz): the pilot's RC pulse widths, interpolated to each INS
  row's time and turned into blade pitch by the rigging (`record.rigging`) as the flight
  builder does (`PilotAligned`: a row waits for the pilot frame after it);
- rover `ins` (150 Hz): roll, pitch from `ypr_deg`, p, q, r from the bias-compensated
  angular rate — one row per sample, as the flight table's rows.

Rows wait in a buffer; every `batch_s` (0.5 s) of rows `step()` computes the features
(`nets.features`, trailing windows) over the pending rows plus the history they need,
the net's prediction, and eq 2.4 (`nets.intensity.intensity_from_arrays`) with its
trailing std window: the same numbers the offline `predict` + `intensity_series` give
for those rows once the history is filled (a test checks it). Batching is the CPU
saving: each batch recomputes the features over the ~1 s of history it needs, so per
new row that overhead falls with the batch (docs/daemon.md has the figures); the
channel lags the INS by up to `batch_s`.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import torch

from airwake.nets.features import FeatureConfig, build_features
from airwake.nets.intensity import IntensityConfig, intensity_from_arrays, samples_in
from airwake.nets.model import NetFileError, PilotNet
from airwake.record.rigging import BLADE_PITCH_COLUMNS, DEFAULT_RIGGING, PwmRigging

_NET_ORDER = ("delta_lat_rad", "delta_lon_rad", "delta_col_rad", "delta_ped_rad")
_FROM_RIGGING = [BLADE_PITCH_COLUMNS.index(c) for c in _NET_ORDER]
_PWM_VALID = 0x0F  # RC channels 1..4

INTENSITY_SCHEMA = {
    "title": "airwake.airwake_intensity",
    "description": "Live airwake intensity A_ω (eq 2.4) from the rate net given to the "
                   "daemon with --net (docs/networks.md, docs/daemon.md)",
    "type": "object",
    "properties": {
        "t_s": {"type": "number", "description": "host monotonic time of the INS sample (s)"},
        "a_omega": {"type": "number", "description": "A_ω = (ω_s − ω_s′)·‖ω − ω′‖ (rad²/s²)"},
        "omega_s": {"type": "number", "description": "local std of ‖ω‖ (rad/s)"},
        "omega_s_pred": {"type": "number", "description": "local std of ‖ω′‖ (rad/s)"},
        "resid_norm": {"type": "number", "description": "‖ω − ω′‖ (rad/s)"},
        "resid_std": {"type": "number",
                      "description": "norm of the residuals' local std (rad/s)"},
        "pred_rad_s": {"type": "array", "items": {"type": "number"}, "minItems": 3,
                       "maxItems": 3, "description": "the net's p′, q′, r′"},
        "valid": {"type": "boolean",
                  "description": "the features' and the std window's history filled"},
        "ship_x_m": {"type": "number",
                     "description": "the rover antenna in the ship frame, forward (m): the "
                                    "latest RTK baseline rotated by the base INS heading, "
                                    "plus the base antenna's place (--base-antenna-ship-m); "
                                    "absent until both are known"},
        "ship_y_m": {"type": "number", "description": "the same, starboard (m)"},
    },
    "required": ["t_s", "a_omega", "valid"],
}


class PilotAligned:
    """The INS rows of a live net with the pilot's inputs at their time, as the export
    gives them: the RC pulse widths of channels 1-4 interpolated linearly between the
    base's `pilot_inputs` frames (frames missing a channel are left out), then the blade
    pitch through the rigging (or the pulse widths, `use_pwm`), in the nets' order
    (delta_lat, delta_lon, delta_col, delta_ped). A row waits (`waiting`) until the first
    pilot frame after it has arrived: the base's frames come over another port, often
    later than the rover's. After `max_wait_s` of newer INS rows (the base lost, its
    link stalled) a row takes the latest frame's inputs instead (held, counted in
    `held`). Rows before the first pilot frame are skipped. Subclasses set `self.rows`
    (a deque of `(t_s, *inputs, *values)`), `self.pending` and `self.seen`."""

    def __init__(self, rigging: PwmRigging, use_pwm: bool, max_wait_s: float = 0.2) -> None:
        self.rigging = rigging
        self.use_pwm = use_pwm
        self.max_wait_s = max_wait_s
        self.frames: deque = deque(maxlen=4096)  # (t_s, pwm (4,)), time order; pruned
        self.waiting: deque = deque()  # (t_s, values) of INS rows without inputs yet
        self.newest_ins_s = -math.inf
        self.skipped = 0
        self.held = 0

    def on_pilot_inputs(self, t_s: float, msg) -> None:
        if (int(msg.valid_mask) & _PWM_VALID) != _PWM_VALID:
            return
        pwm = np.asarray(msg.pwm_us[:4], float)
        if not np.all(np.isfinite(pwm)) or (self.frames and t_s <= self.frames[-1][0]):
            return
        self.frames.append((t_s, pwm))

    def _queue(self, t_s: float, values: tuple, extra: tuple = ()) -> None:
        """An INS row: `values` must be finite (else skipped), `extra` rides along."""
        if not all(math.isfinite(v) for v in (t_s, *values)):
            self.skipped += 1
            return
        self.waiting.append((t_s, (*values, *extra)))
        self.newest_ins_s = max(self.newest_ins_s, t_s)

    def _inputs_at(self, t_s: np.ndarray) -> np.ndarray:
        """(n, 4) inputs at the times t_s (n,): one interpolation and rigging per batch."""
        ts = np.fromiter((f[0] for f in self.frames), float, len(self.frames))
        pwm = np.stack([f[1] for f in self.frames])
        at = np.stack([np.interp(t_s, ts, pwm[:, c]) for c in range(4)], axis=-1)
        return at if self.use_pwm else self.rigging.pwm_to_blade_pitch(at)[:, _FROM_RIGGING]

    def _complete(self) -> None:
        """Give the waiting rows whose inputs are known (or waited too long) their inputs."""
        ready = 0
        last = self.frames[-1][0] if self.frames else -math.inf
        for t_s, _ in self.waiting:  # time order within the rover's stream
            if t_s > last and t_s >= self.newest_ins_s - self.max_wait_s:
                break  # the next pilot frame is still to come
            ready += 1
        if not ready:
            return
        rows = [self.waiting.popleft() for _ in range(ready)]
        if not self.frames:  # waited too long before any pilot frame: nothing to pair
            self.skipped += ready
            return
        self.held += sum(t > last for t, _ in rows)  # interpolation holds the last frame
        inputs = self._inputs_at(np.array([t for t, _ in rows]))
        for (t_s, values), u in zip(rows, inputs, strict=True):
            self.rows.append((t_s, *u, *values))
        self.pending = min(self.pending + ready, len(self.rows))
        self.seen += ready
        # frames no later row can need: all before the one at or before the next row
        upto = self.waiting[0][0] if self.waiting else rows[-1][0]
        while len(self.frames) > 1 and self.frames[1][0] <= upto:
            self.frames.popleft()


class LiveIntensity(PilotAligned):
    """Feeds a rate `PilotNet` from live frames (module doc). `on_pilot_inputs`,
    `on_ins` take one frame each; `step()` returns the new samples' dicts (schema above)
    once `batch_s` of INS rows are pending."""

    def __init__(self, net: PilotNet, config: IntensityConfig | None = None,
                 rigging: PwmRigging = DEFAULT_RIGGING, batch_s: float = 0.5) -> None:
        card = net.card
        if card.get("target") != "rates":
            raise NetFileError(f"--net: a {card.get('target')!r} net; live A_ω needs a rate "
                               "net (airwake nets train --target rates)")
        if card.get("input_source") not in ("delta", "pwm"):
            raise NetFileError(f"--net: trained on {card.get('input_source')!r} inputs; the "
                               "daemon has the RC pulse widths (delta or pwm nets)")
        if not (math.isfinite(batch_s) and batch_s > 0):
            raise ValueError(f"batch_s {batch_s!r}: must be a positive number")
        # one thread: the daemon's loop must not wait on an intra-op pool (on a loaded
        # 2-core machine a 2-thread forward of 100 rows took 60 ms instead of 0.3 ms)
        torch.set_num_threads(1)
        super().__init__(rigging, card["input_source"] == "pwm")
        self.net = net
        self.config = config or IntensityConfig()
        self.features = FeatureConfig.from_dict(card["feature_config"])
        self.rate_hz = float(card["rate_hz"])
        self.n_std = samples_in(self.config.std_window_s, self.rate_hz)
        history = int(math.ceil(self.features.history_s(self.rate_hz) * self.rate_hz)) + 1
        self.warmup = history + self.n_std  # rows before the first valid A_ω
        self.keep = history + self.n_std + 2  # past rows a batch needs
        self.batch = max(1, int(round(batch_s * self.rate_hz)))
        self.rows: deque = deque(maxlen=self.keep + 10 * self.batch)
        self.pending = 0
        self.seen = 0
        self.samples_out = 0
        self.base_antenna_ship_m = (0.0, 0.0)
        self.ship_yaw_rad: float | None = None
        self.baseline_ne_m: tuple[float, float] | None = None

    def on_ship_ins(self, t_s: float, msg) -> None:
        """The base's INS: the ship's heading (for the track in the ship frame)."""
        yaw = math.radians(float(msg.ypr_deg[0]))
        if math.isfinite(yaw):
            self.ship_yaw_rad = yaw

    def on_baseline(self, t_s: float, msg) -> None:
        """The rover's RTK baseline (rover - base, NED)."""
        n, e = (float(v) * 1e-3 for v in msg.baseline_ned_mm[:2])
        if math.isfinite(n) and math.isfinite(e):
            self.baseline_ne_m = (n, e)

    def ship_xy(self) -> tuple[float, float]:
        """The rover antenna in the ship frame now (x forward, y starboard), or NaNs."""
        if self.ship_yaw_rad is None or self.baseline_ne_m is None:
            return math.nan, math.nan
        c, s = math.cos(self.ship_yaw_rad), math.sin(self.ship_yaw_rad)
        n, e = self.baseline_ne_m
        return (self.base_antenna_ship_m[0] + c * n + s * e,
                self.base_antenna_ship_m[1] - s * n + c * e)

    def on_ins(self, t_s: float, msg) -> None:
        yaw, pitch, roll = (math.radians(v) for v in msg.ypr_deg)
        rates = [float(v) for v in msg.angular_rate_frd_rad_s]
        self._queue(t_s, (roll, pitch, *rates), self.ship_xy())  # NaN until known

    def step(self, force: bool = False) -> list[dict]:
        """Intensity of the pending rows when a batch is full (or `force`)."""
        if force or self.pending + len(self.waiting) >= self.batch:  # pair in batches
            self._complete()
        if self.pending == 0 or (self.pending < self.batch and not force):
            return []
        n_new = self.pending
        a = np.asarray(self.rows, float)[-(n_new + self.keep):]
        t, inputs, roll, pitch, rates = a[:, 0], a[:, 1:5], a[:, 5], a[:, 6], a[:, 7:10]
        x, _ = build_features(inputs, roll, pitch, rates, self.rate_hz, self.features)
        # only the rows eq 2.4's std window reaches need a prediction
        m = min(len(a), n_new + self.n_std - 1)
        t, ship = t[-m:], a[-m:, 10:12]
        pred = self.net.predict_numpy(x[-m:])
        it = intensity_from_arrays(rates[-m:], pred, self.n_std)
        first_index = self.seen - m  # stream index of pred[0]
        out = []
        for i in range(m - n_new, m):
            o = {"t_s": float(t[i]), "a_omega": float(it["a_omega"][i]),
                 "omega_s": float(it["omega_s"][i]),
                 "omega_s_pred": float(it["omega_s_pred"][i]),
                 "resid_norm": float(it["resid_norm"][i]),
                 "resid_std": float(it["resid_std"][i]),
                 "pred_rad_s": [float(v) for v in pred[i]],
                 "valid": bool(first_index + i >= self.warmup)}
            if math.isfinite(ship[i, 0]):
                o["ship_x_m"], o["ship_y_m"] = float(ship[i, 0]), float(ship[i, 1])
            out.append(o)
        self.pending = 0
        self.samples_out += len(out)
        return out

    def status(self) -> dict:
        return {"samples": self.samples_out, "skipped": self.skipped, "held": self.held,
                "net_rate_hz": self.rate_hz, "batch": self.batch}
