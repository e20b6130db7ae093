"""The pose EKF on a SIL flight: native marker + LOSA firmware -> daemon -> recording ->
`airwake export`'s `marker_*` columns, scored against the truth world (`clean_flight`:
the marker tracks from its calibration at ~5 s to the end, 2.5-3 m from the tracker)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from airwake.record.marker_pose import TrackerPlacement
from airwake.tracking.marker import LED_DIRECTIONS_BODY
from scipy.spatial.transform import Rotation
from sil_harness import load_export, sim_time, summary

from hil_sim.boards.feeds import tracker_axes_ned

LEDS_C = Path(__file__).resolve().parents[2] / "firmware" / "boards" / "marker" / "leds.c"


def _truth_marker(d: Path, df, meta, extra):
    """(valid rows, true marker centre NED (N, 3), true marker -> NED rotation)."""
    rig = summary(d)["rig"]
    r_tn = tracker_axes_ned(rig["tracker_heading_deg"], rig["tracker_tilt_deg"])
    with np.load(d / "truth.npz") as z:
        t, pos_t, q = z["t_s"], z["marker_pos_tracker_m"], z["marker_quat_tracker"]
    ts = sim_time(df["t_s"].to_numpy(), meta, extra)
    pos = np.stack([np.interp(ts, t, pos_t[:, j]) for j in range(3)], axis=-1)
    pos_ned = np.asarray(rig["tracker_position_ned_m"]) + pos @ r_tn
    k = np.clip(np.searchsorted(t, ts), 0, t.size - 1)  # truth at 1 kHz: nearest is enough
    r_nm = Rotation.from_matrix(r_tn.T) * Rotation.from_quat(q[k][:, [1, 2, 3, 0]])
    return df["marker_valid"].to_numpy() > 0.5, pos_ned, r_nm


def test_exported_marker_pose_follows_the_true_marker(clean_flight):
    # the flight table's marker pose is what the anemometer map is compensated with: a
    # millimetre-level position where LOSA sees the marker, attitude within a few degrees
    df, meta, extra = load_export(clean_flight)
    valid, pos_true, r_true = _truth_marker(clean_flight, df, meta, extra)
    assert valid.mean() > 0.4, meta["marker_pose"]
    est = df[["marker_pos_n_m", "marker_pos_e_m", "marker_pos_d_m"]].to_numpy()
    err = np.linalg.norm(est - pos_true, axis=1)[valid]
    assert np.sqrt(np.mean(err ** 2)) < 0.01 and err.max() < 0.03, (err.mean(), err.max())
    r_est = Rotation.from_euler("ZYX", df[["marker_yaw_rad", "marker_pitch_rad",
                                           "marker_roll_rad"]].to_numpy())
    att_deg = np.degrees((r_est.inv() * r_true).magnitude())[valid]
    # the calibration's line of sight is the sweep's LED-weighted direction, a few degrees
    # off the true one; the 2 cm lever arm leaves that rotation about the LoS unobservable
    assert np.sqrt(np.mean(att_deg ** 2)) < 4.0, att_deg.max()


def test_ekf_position_beats_triangulation(clean_flight):
    # the smoothed track of the lit LED is closer to the truth than raw triangulation
    df, meta, extra = load_export(clean_flight)
    valid, pos_true, _ = _truth_marker(clean_flight, df, meta, extra)
    valid &= df["tracker_valid"].to_numpy() > 0.5
    rig = summary(clean_flight)["rig"]
    r_tn = tracker_axes_ned(rig["tracker_heading_deg"], rig["tracker_tilt_deg"])
    tri = np.asarray(rig["tracker_position_ned_m"]) + df[
        ["tracker_pos_x_m", "tracker_pos_y_m", "tracker_pos_z_m"]].to_numpy() @ r_tn
    est = df[["marker_pos_n_m", "marker_pos_e_m", "marker_pos_d_m"]].to_numpy()
    # triangulation sees the lit LED, 2 cm from the centre: compare its spread about the
    # truth, bias removed, with the EKF's full error
    tri_err = tri[valid] - pos_true[valid]
    tri_err -= tri_err.mean(axis=0)
    ekf_err = np.linalg.norm(est[valid] - pos_true[valid], axis=1)
    assert np.sqrt(np.mean(ekf_err ** 2)) < 0.7 * np.sqrt(np.mean(np.sum(tri_err ** 2, 1)))


@pytest.mark.parametrize("heading_deg,tilt_deg", [(0.0, 0.0), (37.0, 0.0), (-120.0, 8.0)])
def test_tracker_placement_matches_the_simulator(heading_deg, tilt_deg):
    # the host turns tracker-frame poses into NED with the simulator's convention
    np.testing.assert_allclose(TrackerPlacement((0, 0, 0), heading_deg, tilt_deg)
                               .ned_to_tracker(), tracker_axes_ned(heading_deg, tilt_deg),
                               atol=1e-12)


def test_firmware_led_table_equals_the_host_and_simulator_geometry():
    # the marker firmware's line of sight and lit LED are in its own LED table; a table
    # other than the optics' gave the SIL tracker a 75 deg initial attitude error
    text = LEDS_C.read_text()
    body = re.search(r"marker_led_dir\[MARKER_LEDS\]\[3\] = \{(.*?)\};", text, re.S).group(1)
    rows = [[float(v) for v in re.findall(r"-?\d+\.\d+", r)]
            for r in re.findall(r"\{([^}]*)\}", body)]
    np.testing.assert_allclose(rows, LED_DIRECTIONS_BODY, atol=1e-9)


def test_pose_metadata_names_the_placement(clean_flight):
    _, meta, _ = load_export(clean_flight)
    rig = json.loads((clean_flight / "rec" / "sil" / "run.json").read_text())["rig"]
    assert meta["marker_pose"]["tracker_position_ned_m"] == rig["tracker_position_ned_m"]


def test_the_daemon_records_the_tracker_placement_it_was_given(clean_flight):
    # SIL passes the rig's placement as `airwake daemon --tracker-position-m ...`: a real
    # recording carries it the same way, so the export needs no SIL file
    from airwake.record.export import tracker_placement
    from airwake.record.reader import open_recording

    rec = open_recording(clean_flight / "rec")
    rig = json.loads((clean_flight / "rec" / "sil" / "run.json").read_text())["rig"]
    assert rec.metadata["tracker_position_ned_m"] == rig["tracker_position_ned_m"]
    placed = tracker_placement(rec)
    assert list(placed.position_ned_m) == rig["tracker_position_ned_m"]
    assert placed.heading_deg == rig["tracker_heading_deg"]

