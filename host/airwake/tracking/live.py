"""The pose EKF live, on the daemon's ingest timeline (docs/daemon.md "Live tracker").

Inputs, each with its host-timeline time (the board stamp mapped by `link.clock`):
- marker `imu` (120 Hz): the prediction (`PoseEkf.predict`);
- LOSA `losa_peaks` (320 Hz): triangulated one frame at a time (`losa.triangulate_one`),
  the update of the lit LED (`PoseEkf.update_position` with its lever arm);
- marker `marker_attitude` (120 Hz): which LED is lit, and, at the first row in tracking
  mode (the marker's calibration done: at rest, gravity and line of sight measured,
  gyro bias estimated), the initial state: attitude by TRIAD (eq 3.5,
  `attitude.initial_attitude`) from that row and the mean of the LOSA triangulations
  within `INIT_WINDOW_S` of it — as `offline.track_streams` does over a whole recording.

Frames of different ports arrive out of time order (one read per port per poll pass,
radio and USB latency): they wait in a reorder buffer and are applied in time order once
`reorder_s` older than the newest input, so the estimate lags the newest frame by
`reorder_s` (20 ms).

CPU (the daemon's budget, docs/daemon.md): the LOSA frames between two IMU samples (2-3
at 320 / 120 Hz) are fused as one update, their mean position at their mean time, after
the later IMU sample (`PoseEkf.update_position`'s lag model, lag < one IMU period), with
the per-frame R unchanged — LOSA errors are correlated over tens of frames (the reason R
is inflated, docs/tracking.md), so the mean carries little more information than one
frame. That is one propagation and at most one update per IMU sample instead of a
propagation and an update per LOSA frame as well (~3x less filter time).
"""

from __future__ import annotations

import heapq
import math
from collections import deque

import numpy as np

from airwake.tracking.attitude import initial_attitude, rotation_to_quat_wxyz
from airwake.tracking.errors import TrackingError
from airwake.tracking.losa import SENSOR_FLAG_VALID, SlotResolver, triangulate_one
from airwake.tracking.marker import LED_DIRECTIONS_BODY, LED_RADIUS_M, NO_LED
from airwake.tracking.pose_ekf import P_, TH, V_, PoseEkf, PoseEkfConfig

MODE_TRACKING = 3  # marker_attitude.mode: calibrated, tracking
INIT_WINDOW_S = 0.2  # LOSA triangulations averaged for the initial position
_IMU, _ATTITUDE, _PEAKS = 0, 1, 2  # at equal times: IMU first (as run_pose_ekf), then LED

# The recorded pose (`LiveTracker.pose()`), JSON schema for the MCAP channel.
_VEC3 = {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3}
POSE_SCHEMA = {
    "title": "airwake.pose",
    "description": "Live pose EKF of the active marker (docs/daemon.md, docs/tracking.md); "
                   "reference frame = the LOSA tracker's (x right, y down, z forward)",
    "type": "object",
    "properties": {
        "t_s": {"type": "number", "description": "host monotonic time of the state (s)"},
        "pos_tracker_m": {**_VEC3, "description": "marker centre, tracker frame"},
        "vel_tracker_m_s": {**_VEC3, "description": "marker velocity, tracker frame"},
        "quat_wxyz": {"type": "array", "items": {"type": "number"}, "minItems": 4,
                      "maxItems": 4, "description": "body (marker IMU axes) -> tracker"},
        "pos_sigma_m": {**_VEC3, "description": "sqrt(diag P) of the position"},
        "vel_sigma_m_s": _VEC3,
        "att_sigma_rad": {**_VEC3, "description": "sqrt(diag P) of the attitude error"},
        "gyro_bias_rad_s": _VEC3,
        "accel_bias_m_s2": _VEC3,
        "valid": {"type": "boolean",
                  "description": "an update accepted within the dropout time, and the "
                                 "LOSA slot choice not ambiguous"},
        "slot_ambiguous": {"type": "boolean",
                           "description": "the LOSA slots re-acquired without a clear "
                                          "winner, not yet confirmed by a 0.3 m move"},
        "lost": {"type": "boolean",
                 "description": "no update accepted for the filter's coast_s: position "
                                "held, velocity zero, not integrated (docs/tracking.md)"},
        "accepted": {"type": "integer"}, "gated": {"type": "integer"},
        "reacquired": {"type": "integer"}, "late": {"type": "integer"},
        "predictions": {"type": "integer"},
    },
    "required": ["t_s", "pos_tracker_m", "quat_wxyz", "valid"],
}


class LiveTracker:
    """Feeds a `PoseEkf` from live frames; `pose()` / `position()` read it.

    `on_imu`, `on_attitude`, `on_peaks` queue one frame (host time `t_s`); `step()`
    applies the queued frames older than the newest by `reorder_s` and returns the poses
    (`pose()` dicts) after each IMU sample it applied.
    """

    def __init__(self, config: PoseEkfConfig | None = None, reorder_s: float = 0.02,
                 init_window_s: float = INIT_WINDOW_S) -> None:
        if not (math.isfinite(reorder_s) and reorder_s >= 0):
            raise TrackingError(f"LiveTracker: reorder_s = {reorder_s!r}: must be >= 0")
        self.config = config or PoseEkfConfig()
        self.reorder_s = reorder_s
        self.init_window_s = init_window_s
        self.ekf: PoseEkf | None = None
        self.active_led = NO_LED
        self.calibration = None  # (t_s, marker_attitude) of the first tracking row
        self.recent: deque = deque()  # (t_s, led position, lever arm) before the start
        self.newest_s = -math.inf
        self.triangulated = 0
        self.slots = SlotResolver()
        self.restarts = 0
        self._pending: list = []  # (t_s, LED position, LED index) since the last IMU sample
        self._queue: list = []
        self._n = 0  # tie-breaker: arrival order

    # -- input ----------------------------------------------------------------

    def _push(self, t_s: float, kind: int, msg) -> None:
        self._n += 1
        heapq.heappush(self._queue, (t_s, kind, self._n, msg))
        if t_s > self.newest_s:
            self.newest_s = t_s

    def on_imu(self, t_s: float, msg) -> None:
        self._push(t_s, _IMU, msg)

    def on_attitude(self, t_s: float, msg) -> None:
        self._push(t_s, _ATTITUDE, msg)

    def on_peaks(self, t_s: float, msg) -> None:
        self._push(t_s, _PEAKS, msg)

    # -- processing --------------------------------------------------------------

    def step(self) -> list[dict]:
        """Apply the frames older than newest - reorder_s, in time order."""
        poses = []
        horizon = self.newest_s - self.reorder_s
        q = self._queue
        while q and q[0][0] <= horizon:
            t_s, kind, _, msg = heapq.heappop(q)
            if kind == _IMU:
                if self.ekf is not None and math.isfinite(sum(msg.gyro_frd_rad_s)
                                                          + sum(msg.accel_frd_m_s2)):
                    self.ekf.predict(t_s, msg.gyro_frd_rad_s, msg.accel_frd_m_s2)
                    self._fuse_pending()
                    if not np.all(np.isfinite(self.ekf.pos)) or not np.all(
                            np.isfinite(self.ekf.quat)):
                        self.restart()  # diverged: start again at the next calibration
                        continue
                    poses.append(self.pose())
            elif kind == _ATTITUDE:
                self.active_led = msg.active_led
                if self.calibration is None and msg.mode == MODE_TRACKING:
                    self.calibration = (t_s, msg)
            else:
                self._peaks(t_s, msg)
            if self.ekf is None and self.calibration is not None:
                self._try_start(t_s)
        if self._pending and self._pending[0][0] < horizon - self.config.max_lag_s / 2:
            self._fuse_pending()  # no IMU sample to wait for (marker IMU lost)
        return poses

    def _fuse_pending(self) -> None:
        """One update per lit LED from the LOSA frames since the last IMU sample."""
        pending, self._pending = self._pending, []
        while pending:
            led = pending[0][2]
            same = [e for e in pending if e[2] == led]
            pending = [e for e in pending if e[2] != led]
            n = len(same)
            t_s = sum(e[0] for e in same) / n
            pos = [sum(e[1][i] for e in same) / n for i in range(3)]
            res = self.ekf.update_position(
                t_s, pos, lever_arm_body_m=LED_RADIUS_M * LED_DIRECTIONS_BODY[led])
            # an ambiguous slot choice is confirmed by motion, as offline (run_pose_ekf)
            self.slots.confirm(pos, res.outcome == "accepted" and self.ekf.settled(), t_s)

    def _peaks(self, t_s: float, msg) -> None:
        led = self.active_led
        if led >= len(LED_DIRECTIONS_BODY):
            return  # no LED lit: whatever LOSA sees is not the marker
        valid = [(f & SENSOR_FLAG_VALID) != 0 for f in msg.sensor_flags]
        if self.ekf is None:
            p = triangulate_one(msg.peak_px, msg.slot, valid)
        else:  # re-acquisition: the slots the prediction finds likeliest (SlotResolver)
            arm = LED_RADIUS_M * LED_DIRECTIONS_BODY[led]
            choose = ((lambda c: self.ekf.candidate_nis(t_s, c, arm))
                      if self.ekf.in_dropout(t_s) else None)
            p = self.slots.position(msg.peak_px, msg.slot, valid, choose, self.ekf.lost)
            if p is not None:
                p = tuple(float(v) for v in p)
        if p is None:
            return
        self.triangulated += 1
        if self.ekf is not None:
            self._pending.append((t_s, p, led))
        else:
            self.recent.append((t_s, p, LED_RADIUS_M * LED_DIRECTIONS_BODY[led]))
            while self.recent and self.recent[0][0] < t_s - 2 * self.init_window_s:
                self.recent.popleft()

    def _try_start(self, now_s: float) -> None:
        """Start the filter once the LOSA frames up to init_window_s after the
        calibration row are in (or on the first frame later, if none were)."""
        t0, row = self.calibration
        if now_s < t0 + self.init_window_s:
            return
        near = [(p, arm) for t, p, arm in self.recent if abs(t - t0) <= self.init_window_s]
        if not near:
            later = [(t, p, arm) for t, p, arm in self.recent if t > t0]
            if not later:
                return
            t0, p, arm = later[0]  # LOSA found the marker only after its calibration
            near = [(p, arm)]
        led_pos = np.mean([p for p, _ in near], axis=0)
        arm = np.mean([a for _, a in near], axis=0)
        try:
            r0 = initial_attitude(-np.asarray(row.gravity_frd_unit, dtype=float),
                                  np.asarray(row.los_frd_unit, dtype=float), led_pos,
                                  self.config.gravity_ref_m_s2)
        except TrackingError:
            # gravity and line of sight (nearly) parallel: wait for the next calibration
            self.calibration = None
            return
        self.ekf = PoseEkf(now_s, led_pos - r0 @ arm, rotation_to_quat_wxyz(r0),
                           gyro_bias_rad_s=np.asarray(row.gyro_bias_frd_rad_s, dtype=float),
                           config=self.config)
        self.recent.clear()

    def restart(self) -> None:
        """Drop the filter; it starts again from the marker's next tracking-mode row."""
        self.ekf = None
        self.calibration = None
        self._pending = []
        self.recent.clear()
        self.slots = SlotResolver()
        self.restarts += 1

    # -- output --------------------------------------------------------------------

    @property
    def started(self) -> bool:
        return self.ekf is not None

    def valid(self) -> bool:
        """Started, an update accepted within the configured dropout time, and the LOSA
        slots not on an unconfirmed ambiguous choice (`losa.SlotResolver`: a wrong one
        puts the track metres off, self-consistently, until motion tells)."""
        e = self.ekf
        return (e is not None and e.t_s - e.last_accept_s <= self.config.dropout_s
                and not self.slots.ambiguous)

    def position(self, now_s: float, max_age_s: float) -> tuple[float, float, float] | None:
        """The marker centre (tracker frame, m) when `valid()` and the state is at most
        `max_age_s` older than host time `now_s`, else None."""
        if not self.valid() or now_s - self.ekf.t_s > max_age_s:
            return None
        p = self.ekf.pos
        return float(p[0]), float(p[1]), float(p[2])

    def pose(self) -> dict:
        """The state as the `/host/pose` message (POSE_SCHEMA)."""
        e = self.ekf
        d = np.sqrt(np.maximum(np.diag(e.P), 0.0))
        c = e.counters
        return {"t_s": e.t_s, "pos_tracker_m": e.pos.tolist(), "vel_tracker_m_s": e.vel.tolist(),
                "quat_wxyz": e.quat.tolist(), "pos_sigma_m": d[P_].tolist(),
                "vel_sigma_m_s": d[V_].tolist(), "att_sigma_rad": d[TH].tolist(),
                "gyro_bias_rad_s": e.gyro_bias.tolist(), "accel_bias_m_s2": e.accel_bias.tolist(),
                "valid": self.valid(), "slot_ambiguous": self.slots.ambiguous,
                "lost": e.lost, "accepted": c.accepted, "gated": c.gated,
                "reacquired": c.reacquired, "late": c.late, "predictions": c.predictions}

    def status(self) -> dict:
        e = self.ekf
        if e is None:
            return {"started": False, "calibrated": self.calibration is not None,
                    "triangulated": self.triangulated, "restarts": self.restarts,
                    "slot_corrections": self.slots.resolved}
        c = e.counters
        return {"started": True, "valid": self.valid(), "t_s": round(e.t_s, 3),
                "pos_tracker_m": [round(v, 4) for v in e.pos.tolist()],
                "pos_sigma_m": [round(math.sqrt(max(v, 0.0)), 4)
                                for v in np.diag(e.P)[P_].tolist()],
                "accepted": c.accepted, "gated": c.gated, "reacquired": c.reacquired,
                "late": c.late, "triangulated": self.triangulated, "restarts": self.restarts,
                "slot_corrections": self.slots.resolved, "slot_ambiguous": self.slots.ambiguous,
                "lost": e.lost}


__all__ = ["LiveTracker", "POSE_SCHEMA"]
