"""A direct wind net (§4.6, `nets.wind_net`) live on the daemon's ingest timeline: the
eq 5.3 wind per rover INS sample, recorded on `/host/wind` (docs/daemon.md "Live wind",
docs/networks.md).

Inputs, each with its host-timeline time: base `pilot_inputs` (interpolated to each INS
row and turned into blade pitch by the rigging: `nets.live.PilotAligned`), rover `ins`
(150 Hz): roll,
pitch, yaw, p, q, r, the NED velocity turned into body axes (R^T v, as the flight
builder), the specific force. ṗ and q̇ are the flight tables' Savitzky-Golay derivative
(`record.differentiate`, ±0.05 s): it reads the future, so a row is estimated once the
half window after it has arrived (7 rows, 47 ms at 150 Hz) and its values are the
export's. Every `batch_s` (0.5 s) of rows `step()` builds the features
(`wind_net.wind_feature_matrix`) over the new rows plus the history they need and runs
the net: for the same rows the numbers `predict_wind` gives on the exported flight once
the history is filled (a test feeds a flight through both). The channel lags the INS by
up to `batch_s` + the half window.

A still-air net (`nets train --target wind --still-air`) gives the air-relative velocity;
the mean flow is the INS body velocity less it, smoothed by the net's centred Gaussian
(`smooth_s`, 0.5 s) as the export smooths it: a row is sent once the kernel's half
length (3 smooth_s, 1.5 s) of rows after it is estimated, so the channel lags the INS by
that much more, and its numbers are again the export's. ω it never saw: null.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import torch

from airwake.nets.features import FeatureConfig, gaussian_kernel
from airwake.nets.live import PilotAligned
from airwake.nets.model import NetFileError, PilotNet
from airwake.nets.wind_net import (
    MOTION,
    TARGET,
    WIND_OUTPUTS,
    WindNetConfig,
    history_s,
    wind_feature_matrix,
)
from airwake.record.differentiate import (
    DERIVATIVE_POLYORDER,
    DERIVATIVE_WINDOW_S,
    derivative_window,
    smooth_derivative,
)
from airwake.record.flight_builder import euler_to_dcm
from airwake.record.rigging import DEFAULT_RIGGING, PwmRigging

_UNITS = {"wind_vx_m_s": "m/s", "wind_vy_m_s": "m/s", "wind_vz_m_s": "m/s",
          "wind_wx_rad_s": "1/s", "wind_wy_rad_s": "1/s", "wind_wz_rad_s": "1/s"}
WIND_SCHEMA = {
    "title": "airwake.wind",
    "description": "Live eq 5.3 wind (body axes at the main-rotor hub; w the rotation "
                   "coefficient, curl = 2w) from the wind net given to the daemon with "
                   "--wind-net (docs/networks.md, docs/daemon.md)",
    "type": "object",
    "properties": {
        "t_s": {"type": "number", "description": "host monotonic time of the INS sample (s)"},
        **{o: {"type": "number", "description": f"the net's estimate ({u})"}
           for o, u in _UNITS.items() if u == "m/s"},
        **{o: {"type": ["number", "null"],
               "description": f"the net's estimate ({u}); null: not estimated (a still-air "
                              "net)"}
           for o, u in _UNITS.items() if u != "m/s"},
        "valid": {"type": "boolean", "description": "the features' history filled"},
    },
    "required": ["t_s", *WIND_OUTPUTS, "valid"],
}


class LiveWind(PilotAligned):
    """Feeds a wind `PilotNet` from live frames (module doc). `on_pilot_inputs`, `on_ins`
    take one frame each; `step()` returns the new samples' dicts (WIND_SCHEMA) once
    `batch_s` of INS rows (and the derivative's half window after them) are in."""

    def __init__(self, net: PilotNet, rigging: PwmRigging = DEFAULT_RIGGING,
                 batch_s: float = 0.5) -> None:
        card = net.card
        if card.get("target") != TARGET:
            raise NetFileError(f"--wind-net: a {card.get('target')!r} net; the live wind "
                               "needs a wind net (airwake nets train --target wind)")
        if card.get("input_source") != "delta":
            raise NetFileError(f"--wind-net: trained on {card.get('input_source')!r} inputs; "
                               "the daemon feeds blade pitch (delta) from the RC pulse widths")
        if not (math.isfinite(batch_s) and batch_s > 0):
            raise ValueError(f"batch_s {batch_s!r}: must be a positive number")
        torch.set_num_threads(1)  # as nets.live: the daemon's loop never waits on a pool
        super().__init__(rigging, use_pwm=False)
        self.net = net
        self.features = FeatureConfig.from_dict(card["feature_config"])
        self.config = WindNetConfig(**card["wind_net_config"])
        self.rate_hz = float(card["rate_hz"])
        # the derivative's half window, in rows (the export's window at this rate)
        self.half = derivative_window(1.0 / self.rate_hz) // 2
        history = int(math.ceil(history_s(self.features, self.config, self.rate_hz)
                                * self.rate_hz)) + 1
        # rows before the first valid estimate; the past rows a batch reads (the history,
        # and before it the derivative's edge rows, which differ from the export's)
        self.warmup = history + self.half
        self.keep = history + 2 * self.half + 2
        self.batch = max(1, int(round(batch_s * self.rate_hz)))
        self.rows: deque = deque(maxlen=self.keep + 10 * self.batch)
        self.still_air = self.config.labels == "still_air"
        self.motion = [MOTION.index(c) for c in self.config.motion]
        # the export's centred smoothing (a still-air net's): raw estimates wait in `raw`
        # until the kernel's half length after them is in
        self.kernel = (gaussian_kernel(self.rate_hz, self.config.smooth_s,
                                       3.0 * self.config.smooth_s, causal=False)
                       if self.config.smooth_s > 0 else np.ones(1))
        self.half_kernel = self.kernel.size // 2
        self.raw: deque = deque()  # (t_s, estimate (6,), valid) not sent yet
        self.sent: deque = deque(maxlen=self.half_kernel)  # the last ones sent
        self.pending = 0
        self.seen = 0
        self.samples_out = 0

    def on_ins(self, t_s: float, msg) -> None:
        self._queue(t_s, (*(math.radians(v) for v in msg.ypr_deg),
                          *msg.angular_rate_frd_rad_s, *msg.vel_ned_m_s, *msg.accel_frd_m_s2))

    def step(self, force: bool = False) -> list[dict]:
        """Estimates of the pending rows when a batch is full (or `force`: every pending
        row, the last half window with the derivative's edge fit: a flight's end)."""
        if force or self.pending + len(self.waiting) >= self.batch + self.half:
            self._complete()  # pair rows with their inputs in batches
        ready = self.pending if force else self.pending - self.half
        if ready <= 0 or (ready < self.batch and not force):
            return []
        a = np.asarray(self.rows, float)[-(self.pending + self.keep):]
        t, inputs = a[:, 0], a[:, 1:5]
        yaw, pitch, roll = a[:, 5], a[:, 6], a[:, 7]
        rates, vel_ned, accel = a[:, 8:11], a[:, 11:14], a[:, 14:17]
        rate_dot = smooth_derivative(t, rates, DERIVATIVE_WINDOW_S, DERIVATIVE_POLYORDER)
        vel_body = np.einsum("nji,nj->ni", euler_to_dcm(roll, pitch, yaw), vel_ned)
        motion = np.column_stack([rate_dot[:, :2], vel_body, accel])  # MOTION's order
        x, _ = wind_feature_matrix(inputs, roll, pitch, rates, motion[:, self.motion],
                                   self.rate_hz, self.features, self.config)
        end = len(a) - (self.pending - ready)  # rows [end - ready, end) are estimated
        est = self.net.predict_numpy(x[end - ready:end])
        if self.still_air:  # the mean flow: the body velocity less the air velocity
            est = np.column_stack([vel_body[end - ready:end] - est[:, :3],
                                   np.full((ready, 3), np.nan)])
        first = self.seen - self.pending  # stream index of the first estimated row
        self.raw.extend((float(t[end - ready + i]), est[i], first + i >= self.warmup)
                        for i in range(ready))
        self.pending -= ready
        out = self._smoothed(force)
        self.samples_out += len(out)
        return out

    def _smoothed(self, force: bool) -> list[dict]:
        """The raw estimates whose kernel is complete (every one at a flight's end), each
        smoothed as `predict_wind` smooths: the flight's first estimate repeated before
        it, its last after."""
        k = self.half_kernel
        n = len(self.raw) if force else len(self.raw) - k
        if n <= 0:
            return []
        rows = list(self.raw)
        if k:
            before = list(self.sent) or rows[:1]
            rows = [*([before[0]] * (k - len(before))), *before, *rows,
                    *([rows[-1]] * (k if force else 0))]
        est = np.asarray([r[1] for r in rows])
        smooth = np.lib.stride_tricks.sliding_window_view(est, self.kernel.size, axis=0)[:n]
        smooth = smooth @ self.kernel  # (n, 6)
        out = []
        for i in range(n):
            row = self.raw.popleft()
            # the export's number once every raw row in its kernel is (the history fills
            # in order: the oldest decides; before the flight's first, its copies)
            valid = rows[i][2]
            o = {"t_s": row[0]}
            o.update({name: None if math.isnan(v) else float(v)
                      for name, v in zip(WIND_OUTPUTS, smooth[i], strict=True)})
            o["valid"] = bool(valid)
            out.append(o)
            self.sent.append(row)
        return out

    def status(self) -> dict:
        return {"samples": self.samples_out, "skipped": self.skipped, "held": self.held,
                "net_rate_hz": self.rate_hz, "batch": self.batch,
                "lag_rows": self.half + self.half_kernel, "labels": self.config.labels}
