"""The marker loop (§3.3.1.4): the tracker's peak intensity per LED and the marker's
position back to the marker board, so it lights only the LED facing the tracker at the
lowest drive that keeps the peak near 20 % of full scale.

Per `marker_command` (60 Hz, the protocol's host rate):

- `led_peak_counts[i]`: the brightest valid peak (over the four sensors) of the LOSA
  frames received since the previous command while the marker reported LED i lit (its
  latest `marker_attitude.active_led`), 0 = not seen;
- `full_scale_counts`: the tracker's ADC full scale (12 bit: 4095);
- `pos_tracker_m`, `pos_valid`: the live pose EKF's marker position
  (`tracking.live.LiveTracker`) when the daemon passes one (the filter valid and its
  state younger than `max_age_s`); otherwise the LOSA triangulation
  (`tracking.losa.triangulate_one`) of the newest peaks frame, valid when at least three
  sensors had a valid peak and the frame is younger than `max_age_s`.
"""

from __future__ import annotations

import math

from airwake.link.messages import LosaPeaks, MarkerAttitude, MarkerCommand
from airwake.tracking.losa import ADC_FULL_SCALE_COUNTS, SENSOR_FLAG_VALID, triangulate_one

N_LEDS = 4
NO_LED = 255


class MarkerLoop:
    """State between LOSA peaks / marker attitude and the next marker_command."""

    def __init__(self, rate_hz: float = 60.0, full_scale_counts: int = ADC_FULL_SCALE_COUNTS,
                 max_age_s: float = 0.1) -> None:
        self.period_s = 1.0 / rate_hz
        self.full_scale_counts = full_scale_counts
        self.max_age_s = max_age_s
        self.active_led = NO_LED
        self.led_peak = [0] * N_LEDS
        self.peaks: LosaPeaks | None = None
        self.peaks_time_s = -math.inf
        self.next_s = 0.0
        self.sent = 0
        self.last_command: MarkerCommand | None = None
        self.source = ""  # of the last valid position: "ekf" or "losa"

    def on_attitude(self, msg: MarkerAttitude) -> None:
        self.active_led = msg.active_led

    def on_peaks(self, msg: LosaPeaks, now_s: float) -> None:
        self.peaks = msg
        self.peaks_time_s = now_s
        led = self.active_led
        if led < N_LEDS:
            best = 0
            for counts, flags in zip(msg.intensity_counts, msg.sensor_flags, strict=True):
                if flags & SENSOR_FLAG_VALID and counts > best:
                    best = counts
            if best > self.led_peak[led]:
                self.led_peak[led] = best

    def due(self, now_s: float) -> bool:
        return now_s >= self.next_s

    def command(self, now_s: float, estimate: tuple[float, float, float] | None = None
                ) -> MarkerCommand:
        """The next marker_command; resets the per-LED peaks. `estimate`: the pose EKF's
        position, used instead of the triangulation when given."""
        self.next_s += self.period_s
        if self.next_s <= now_s:  # late (or first): no burst to catch up
            self.next_s = now_s + self.period_s
        pos, valid = (0.0, 0.0, 0.0), 0
        if estimate is not None:
            pos, valid, self.source = estimate, 1, "ekf"
        elif self.peaks is not None and now_s - self.peaks_time_s <= self.max_age_s:
            m = self.peaks
            p = triangulate_one(m.peak_px, m.slot,
                                [(f & SENSOR_FLAG_VALID) != 0 for f in m.sensor_flags])
            if p is not None:
                pos, valid, self.source = p, 1, "losa"
        cmd = MarkerCommand(led_peak_counts=tuple(min(v, 0xFFFF) for v in self.led_peak),
                            full_scale_counts=self.full_scale_counts, pos_tracker_m=pos,
                            pos_valid=valid)
        self.led_peak = [0] * N_LEDS
        self.sent += 1
        self.last_command = cmd
        return cmd

    def status(self) -> dict:
        c = self.last_command
        return {"commands_sent": self.sent, "active_led": self.active_led,
                "pos_valid": bool(c.pos_valid) if c else False,
                "pos_tracker_m": list(c.pos_tracker_m) if c and c.pos_valid else None,
                "pos_source": self.source if c and c.pos_valid else None,
                "led_peak_counts": list(c.led_peak_counts) if c else None}
