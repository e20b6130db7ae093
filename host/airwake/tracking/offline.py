"""The pose EKF over a recording's message tables (offline, host timeline).

Streams (`record.export.recording_streams`, "<board>/<message>" -> `MessageTable`):
- `marker/imu` (450 Hz): `gyro_frd_rad_s`, `accel_frd_m_s2` — the prediction;
- `losa/losa_peaks` (320 Hz): triangulated (`losa.triangulate`) — the updates;
- `marker/marker_attitude` (120 Hz): `mode`, `gravity_frd_unit`, `los_frd_unit`,
  `gyro_bias_frd_rad_s` at the end of the marker's calibration — the initial state
  (eq 3.5 by TRIAD) — and `active_led`, which LED LOSA sees (the lever arm).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from airwake.tracking.attitude import initial_attitude, rotation_to_quat_wxyz
from airwake.tracking.errors import TrackingError
from airwake.tracking.losa import SENSOR_FLAG_VALID, SlotResolver, triangulate
from airwake.tracking.marker import led_lever_arms_body_m
from airwake.tracking.pose_ekf import PoseEkf, PoseEkfConfig, PoseTrack, run_pose_ekf
from airwake.tracking.smoother import rts_smooth

MARKER_IMU = "marker/imu"
LOSA_PEAKS = "losa/losa_peaks"
MARKER_ATTITUDE = "marker/marker_attitude"
MODE_TRACKING = 3  # marker_attitude.mode: calibrated, tracking
INIT_WINDOW_S = 0.2  # LOSA frames averaged for the initial position


def track_streams(streams: Mapping, config: PoseEkfConfig | None = None,
                  smooth: bool = False) -> PoseTrack:
    """Run the pose EKF over the marker IMU and LOSA peaks of one recording, from the
    first `marker_attitude` row in tracking mode; `smooth` returns the RTS-smoothed
    states instead (`smoother.rts_smooth`), with the forward filter's `losa_*` outcomes.
    Missing streams or no calibrated row raise `TrackingError` naming them."""
    missing = [k for k in (MARKER_IMU, LOSA_PEAKS, MARKER_ATTITUDE)
               if k not in streams or len(streams[k]) == 0]
    if missing:
        raise TrackingError(f"pose tracking needs the streams {', '.join(missing)}; the "
                            f"recording has {', '.join(sorted(streams)) or 'none'}")
    imu, peaks, att = streams[MARKER_IMU], streams[LOSA_PEAKS], streams[MARKER_ATTITUDE]
    cfg = config or PoseEkfConfig()

    valid = (peaks.data["sensor_flags"] & SENSOR_FLAG_VALID) != 0
    pos, ok = triangulate(peaks.data["peak_px"], peaks.data["slot"], valid)
    # The LED lit at each frame: the last marker_attitude row at or before it.
    k = np.clip(np.searchsorted(att.t_s, peaks.t_s, side="right") - 1, 0, len(att) - 1)
    arms = led_lever_arms_body_m(att.data["active_led"][k])
    ok &= np.all(np.isfinite(arms), axis=1)
    arms = np.where(np.isfinite(arms), arms, 0.0)

    tracking = np.flatnonzero(att.data["mode"] == MODE_TRACKING)
    if tracking.size == 0:
        raise TrackingError(f"{MARKER_ATTITUDE}: no row in tracking mode ({MODE_TRACKING}); "
                            "the marker never finished its calibration")
    row = att.data[tracking[0]]
    t0 = float(att.t_s[tracking[0]])
    near = ok & (np.abs(peaks.t_s - t0) <= INIT_WINDOW_S)
    if not np.any(near):
        raise TrackingError(f"{LOSA_PEAKS}: no valid triangulation within {INIT_WINDOW_S} s "
                            f"of the marker's calibration at t = {t0:.3f} s")
    led_pos = pos[near].mean(axis=0)
    gravity_body = np.asarray(row["gravity_frd_unit"], dtype=float)
    r0 = initial_attitude(-gravity_body, np.asarray(row["los_frd_unit"], dtype=float),
                          led_pos, cfg.gravity_ref_m_s2)
    ekf = PoseEkf(t0, led_pos - r0 @ arms[near].mean(axis=0), rotation_to_quat_wxyz(r0),
                  gyro_bias_rad_s=np.asarray(row["gyro_bias_frd_rad_s"], dtype=float),
                  config=cfg, record_history=smooth)
    i0 = int(np.searchsorted(imu.t_s, t0, side="right"))
    sel = peaks.t_s > t0
    track = run_pose_ekf(ekf, imu.t_s[i0:], imu.data["gyro_frd_rad_s"][i0:],
                         imu.data["accel_frd_m_s2"][i0:], peaks.t_s[sel], pos[sel], ok[sel],
                         arms[sel], losa_peaks=(peaks.data["peak_px"][sel],
                                                peaks.data["slot"][sel], valid[sel]),
                         resolver=SlotResolver())
    if not smooth:
        return track
    return dataclasses.replace(rts_smooth(ekf), unresolved_t_s=track.unresolved_t_s,
                               losa_t_s=track.losa_t_s, losa_outcome=track.losa_outcome,
                               losa_nis=track.losa_nis)
