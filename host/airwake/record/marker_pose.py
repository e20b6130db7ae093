"""The tracked marker's pose as flight-table columns (`marker_*`, docs/flight-table.md).

The pose EKF and its RTS smoother (`tracking.offline.track_streams(smooth=True)`) give
the marker centre's position and velocity and the attitude marker -> tracker frame T
(x right, y down, z out of the tracker's face) at each marker IMU sample. The tracker
stands at `tracker_position_ned_m`, facing `tracker_heading_deg`, tilted up by
`tracker_tilt_deg`; with R_TN the rotation NED -> T (rows x_T, y_T, z_T in NED):

    p_ned = p_tracker + R_TN^T p_T,   v_ned = R_TN^T v_T,   R_NB = R_TN^T R_TB

roll/pitch/yaw are R_NB's Z-Y-X Euler angles; p/q/r are the marker's gyro less the bias
its calibration measured (body axes). Rows outside the track, where the marker IMU has
a gap, more than `LOSA_MAX_GAP_S` from a LOSA update the filter accepted (the marker out
of the tracker's view: IMU dead reckoning), or where the filter disagrees with the LOSA
(more than `MAX_GATED_FRACTION` of the frames within `LOSA_MAX_GAP_S` gated, or a
re-acquisition within `REACQUIRED_MARGIN_S`: its state jumped, the smoother's track
across the jump is no measurement) get `marker_valid` 0, and there the position and
velocity are held at the nearest earlier valid row (the first one before it): what the
filter coasts on there is not a measurement (the attitude and the gyro rates stay as
they are: the gyro keeps them).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

MARKER_IMU_MAX_GAP_S = 0.05
# Rows farther than this from a valid LOSA triangulation are dead reckoning on the marker
# IMU alone (metres of drift within seconds): not valid.
LOSA_MAX_GAP_S = 0.25
# The filter and the LOSA disagree: a few frames gated at LED switches are normal (12 of
# 5821 on the simulated flight, docs/tracking.md); a quarter is a track that does not
# follow the marker (the SIL still-air flight's bursts: half the frames gated, the
# smoothed depth 0.8 m off while frames were still being accepted).
MAX_GATED_FRACTION = 0.25
REACQUIRED_MARGIN_S = 0.5
POSE_COLUMNS = tuple(
    [f"marker_pos_{a}_m" for a in "ned"] + [f"marker_vel_{a}_m_s" for a in "ned"]
    + [f"marker_{a}_rad" for a in ("roll", "pitch", "yaw")]
    + [f"marker_{a}_rad_s" for a in "pqr"])


@dataclass(frozen=True)
class TrackerPlacement:
    """Where the LOSA tracker stands in the site's NED frame (m, deg)."""

    position_ned_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    heading_deg: float = 0.0
    tilt_deg: float = 0.0

    def ned_to_tracker(self) -> np.ndarray:
        """(3, 3) R_TN, rows x_T (right), y_T (down), z_T (forward) in NED."""
        psi, th = math.radians(self.heading_deg), math.radians(self.tilt_deg)
        z = np.array([math.cos(th) * math.cos(psi), math.cos(th) * math.sin(psi),
                      -math.sin(th)])
        x = np.array([-math.sin(psi), math.cos(psi), 0.0])
        return np.vstack([x, np.cross(z, x), z])

    def to_dict(self) -> dict:
        return {"tracker_position_ned_m": list(self.position_ned_m),
                "tracker_heading_deg": self.heading_deg, "tracker_tilt_deg": self.tilt_deg}


def missing_marker_streams(streams: Mapping) -> list[str]:
    """The streams the pose EKF needs that `streams` lacks (empty counts as missing)."""
    from airwake.tracking.offline import LOSA_PEAKS, MARKER_ATTITUDE, MARKER_IMU

    return [k for k in (MARKER_IMU, LOSA_PEAKS, MARKER_ATTITUDE)
            if k not in streams or len(streams[k]) == 0]


def marker_pose_columns(streams: Mapping, t_rows: np.ndarray,
                        placement: TrackerPlacement) -> tuple[dict[str, np.ndarray], dict]:
    """(`marker_*` + `marker_valid` columns at `t_rows` (M,), metadata) from the smoothed
    pose EKF. Raises `TrackingError` (missing streams, no calibration) as track_streams."""
    from scipy.spatial.transform import Rotation

    from airwake.record.flight_builder import coverage, interp_columns
    from airwake.tracking.offline import (
        MARKER_ATTITUDE,
        MARKER_IMU,
        MODE_TRACKING,
        track_streams,
    )

    track = track_streams(streams, smooth=True)
    r_tn = placement.ned_to_tracker()
    t = np.asarray(track.t_s, dtype=float)
    pos = np.asarray(placement.position_ned_m, float) + track.pos_ref_m @ r_tn
    vel = track.vel_ref_m_s @ r_tn
    q = track.quat_wxyz
    r_tb = Rotation.from_quat(np.column_stack([q[:, 1], q[:, 2], q[:, 3], q[:, 0]]))
    r_nb = Rotation.from_matrix(r_tn.T) * r_tb
    yaw, pitch, roll = r_nb.as_euler("ZYX").T

    imu, att = streams[MARKER_IMU], streams[MARKER_ATTITUDE]
    calibrated = np.flatnonzero(att.data["mode"] == MODE_TRACKING)
    bias = np.asarray(att.data["gyro_bias_frd_rad_s"][calibrated[0]], dtype=float)
    order = np.argsort(imu.t_s, kind="stable")
    t_imu = np.asarray(imu.t_s, float)[order]
    rates = interp_columns(t_imu, np.asarray(imu.data["gyro_frd_rad_s"], float)[order] - bias,
                           t_rows)

    p_rows = interp_columns(t, pos, t_rows)
    v_rows = interp_columns(t, vel, t_rows)
    yaw_rows = np.pi - np.mod(np.pi - np.interp(t_rows, t, np.unwrap(yaw)), 2 * np.pi)
    cols = {f"marker_pos_{a}_m": p_rows[:, i] for i, a in enumerate("ned")}
    cols.update({f"marker_vel_{a}_m_s": v_rows[:, i] for i, a in enumerate("ned")})
    cols.update({"marker_roll_rad": np.interp(t_rows, t, roll),
                 "marker_pitch_rad": np.interp(t_rows, t, pitch), "marker_yaw_rad": yaw_rows})
    cols.update({f"marker_{a}_rad_s": rates[:, i] for i, a in enumerate("pqr")})
    valid = coverage(t, t_rows, MARKER_IMU_MAX_GAP_S) & losa_aided(track, t_rows)
    _hold_where_invalid(cols, valid, [c for c in POSE_COLUMNS if "_pos_" in c or "_vel_" in c])
    cols["marker_valid"] = valid.astype(float)
    meta = {"source": "pose EKF + RTS smoother (tracking.offline)", **placement.to_dict(),
            "track_start_s": float(t[0]), "track_end_s": float(t[-1]), "samples": int(t.size),
            "gyro_bias_frd_rad_s": bias.tolist(), "valid_fraction": float(valid.mean()),
            "unresolved_losa_frames": int(track.unresolved_t_s.size)}
    return cols, meta


def _hold_where_invalid(cols: dict, valid: np.ndarray, names) -> None:
    """Each of `names` takes, on rows not `valid`, its value at the last valid row before
    (the first valid row before any); unchanged when no row is valid."""
    if not valid.any() or valid.all():
        return
    idx = np.where(valid, np.arange(valid.size), -1)
    idx = np.maximum.accumulate(idx)
    idx[idx < 0] = int(np.argmax(valid))
    for c in names:
        cols[c] = np.asarray(cols[c])[idx]


def losa_aided(track, t_rows: np.ndarray) -> np.ndarray:
    """(M,) bool: rows within `LOSA_MAX_GAP_S` of a LOSA update the forward filter accepted
    on a settled slot choice (frames fused on an open ambiguous re-acquisition may put
    the marker metres away, self-consistently), with at most `MAX_GATED_FRACTION` of the
    frames in that window gated and no re-acquisition within `REACQUIRED_MARGIN_S`."""
    from airwake.record.flight_builder import coverage

    t_l = np.asarray(track.losa_t_s, float)
    outcome = np.asarray(track.losa_outcome)
    accepted = np.sort(np.setdiff1d(t_l[outcome == "accepted"], track.unresolved_t_s))
    aided = coverage(accepted, t_rows, LOSA_MAX_GAP_S)
    judged = np.sort(t_l[np.isin(outcome, ("accepted", "gated", "reacquired"))])
    gated = np.sort(t_l[outcome == "gated"])

    def within(times, half):
        return (np.searchsorted(times, t_rows + half, side="right")
                - np.searchsorted(times, t_rows - half, side="left"))

    n = within(judged, LOSA_MAX_GAP_S)
    agree = within(gated, LOSA_MAX_GAP_S) <= MAX_GATED_FRACTION * n
    calm = within(np.sort(t_l[outcome == "reacquired"]), REACQUIRED_MARGIN_S) == 0
    return aided & agree & calm
