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
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import torch

from airwake.nets.features import FeatureConfig
from airwake.nets.live import PilotAligned
from airwake.nets.model import NetFileError, PilotNet
from airwake.nets.wind_net import (
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
           for o, u in _UNITS.items()},
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
        if (card.get("wind_net_config") or {}).get("labels") == "still_air":
            raise NetFileError("--wind-net: a still-air wind net (its mean flow is the INS "
                               "velocity less the net's air velocity) does not run live yet; "
                               "use it on the exported flight (airwake wind estimate "
                               "--method net)")
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
        motion = np.column_stack([rate_dot[:, :2], vel_body, accel])
        x, _ = wind_feature_matrix(inputs, roll, pitch, rates, motion, self.rate_hz,
                                   self.features, self.config)
        end = len(a) - (self.pending - ready)  # rows [end - ready, end) are estimated
        est = self.net.predict_numpy(x[end - ready:end])
        first = self.seen - self.pending  # stream index of the first estimated row
        out = []
        for i in range(ready):
            o = {"t_s": float(t[end - ready + i])}
            o.update({name: float(est[i, k]) for k, name in enumerate(WIND_OUTPUTS)})
            o["valid"] = bool(first + i >= self.warmup)
            out.append(o)
        self.pending -= ready
        self.samples_out += len(out)
        return out

    def status(self) -> dict:
        return {"samples": self.samples_out, "skipped": self.skipped, "held": self.held,
                "net_rate_hz": self.rate_hz, "batch": self.batch, "lag_rows": self.half}
