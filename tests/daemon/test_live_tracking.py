"""The live pose EKF (`tracking.live.LiveTracker`) on the fake marker's frames, and the
daemon without marker/LOSA streams (no tracker output at all). The daemon with them:
`test_ingest.py::test_live_pose_is_recorded_near_the_marker`."""

from __future__ import annotations

import time

import numpy as np
import pytest
from airwake.daemon.fake_boards import (
    MARKER_BODY_TO_TRACKER,
    BoardSim,
    FakeBoard,
    marker_position,
)
from airwake.record.reader import open_recording
from airwake.tracking.live import LiveTracker
from airwake.tracking.pose_ekf import quat_to_matrix
from daemon_harness import DaemonRun, close_boards

T0_S = 1000.0  # host time of the boards' boot


def fake_stream(seconds: float, rng: np.random.Generator, jitter_s: float = 0.0):
    """(host time, kind, message) of the fake marker (imu, marker_attitude at 120 Hz)
    and LOSA (losa_peaks at 320 Hz), in arrival order: time + up to `jitter_s` late."""
    marker, losa = BoardSim("marker"), BoardSim("losa")
    ev = []
    for k in range(int(seconds * 120)):
        t = k / 120
        ev += [(t, "imu", marker.content("imu", t)),
               (t, "attitude", marker.content("marker_attitude", t))]
    ev += [(k / 320, "peaks", losa.content("losa_peaks", k / 320))
           for k in range(int(seconds * 320))]
    arrival = np.array([t for t, _, _ in ev]) + rng.uniform(0, jitter_s, len(ev))
    return [(T0_S + ev[i][0], ev[i][1], ev[i][2]) for i in np.argsort(arrival, kind="stable")]


def feed(tracker: LiveTracker, stream) -> list[dict]:
    poses = []
    for t, kind, msg in stream:
        getattr(tracker, f"on_{kind}")(t, msg)
        poses += tracker.step()
    return poses


def test_live_tracker_follows_the_marker_from_out_of_order_frames():
    # ports are read one after another: frames reach the filter out of time order
    tracker = LiveTracker()
    poses = feed(tracker, fake_stream(6.0, np.random.default_rng(1), jitter_s=0.015))
    assert tracker.started and tracker.valid() and len(poses) > 600
    t = np.array([p["t_s"] for p in poses])
    assert np.all(np.diff(t) > 0)
    pos = np.array([p["pos_tracker_m"] for p in poses])
    err = np.linalg.norm(pos - np.array([marker_position(x - T0_S) for x in t]), axis=1)
    assert np.max(err) < 0.01  # the fake's LOSA peaks are exact
    q = np.array([p["quat_wxyz"] for p in poses])
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-9)
    r_err = quat_to_matrix(q[-1]).T @ MARKER_BODY_TO_TRACKER
    assert np.degrees(np.arccos(np.clip((np.trace(r_err) - 1) / 2, -1, 1))) < 1.0
    last = poses[-1]
    assert last["gated"] == 0 and last["accepted"] > 0.9 * len(poses) and last["valid"]
    assert all(np.isfinite(v).all() for v in (pos, q, np.array(last["pos_sigma_m"])))
    p = tracker.position(t[-1] + 0.05, 0.1)
    assert p is not None and tracker.position(t[-1] + 1.0, 0.1) is None  # stale


def test_live_tracker_waits_for_the_marker_calibration():
    # before the marker reports tracking mode there is no attitude to start from
    tracker = LiveTracker()
    stream = [(t, k, m._replace(mode=1) if k == "attitude" else m)
              for t, k, m in fake_stream(1.0, np.random.default_rng(2))]
    assert feed(tracker, stream) == [] and not tracker.started
    assert tracker.position(T0_S + 1.0, 0.1) is None
    assert tracker.status()["triangulated"] > 0


def test_live_tracker_without_losa_never_starts():
    # marker alone (no LOSA board): nothing to place the marker with
    tracker = LiveTracker()
    stream = [e for e in fake_stream(1.0, np.random.default_rng(3)) if e[1] != "peaks"]
    assert feed(tracker, stream) == [] and not tracker.started


@pytest.mark.wall_clock
def test_daemon_without_marker_and_losa_records_no_pose(run_dir):
    # the base alone: no tracker in the status, no /host/pose, no marker_command
    boards = [b for b in FakeBoard.standard_set(run_dir) if b.name == "base"]
    daemon = DaemonRun(run_dir, ["base"])
    try:
        daemon.wait_ports_open(["base"])
        for b in boards:
            b.start()
        daemon.wait_for(lambda st: len(st["boards"]) == 2, 15, "base and rover")
        time.sleep(1.5)
        st = daemon.status()
        rc = daemon.stop()
    finally:
        daemon.stop()
        close_boards(boards)
    assert rc == 0, daemon.stderr()
    assert "tracker" not in st and st["marker_loop"]["commands_sent"] == 0
    topics = open_recording(daemon.out).topics()
    assert "/host/pose" not in topics and "/host/marker_command" not in topics


def test_live_tracker_skips_non_finite_imu_samples():
    # one corrupt sample (a board bug, a bad cast) must not poison the estimate for good
    stream = fake_stream(2.0, np.random.default_rng(4))
    k = [i for i, e in enumerate(stream) if e[1] == "imu"][150]
    t, _, msg = stream[k]
    stream[k] = (t, "imu", msg._replace(gyro_frd_rad_s=(float("nan"), 0.0, 0.0)))
    tracker = LiveTracker()
    poses = feed(tracker, stream)
    assert tracker.valid() and tracker.restarts == 0
    assert all(np.isfinite(p["pos_tracker_m"]).all() for p in poses)


def test_live_tracker_holds_an_ambiguous_slot_choice_invalid_until_motion_confirms_it():
    # as offline (run_pose_ekf): after an ambiguous LOSA slot re-acquisition the track may
    # be metres off, self-consistently; the pose is not valid (nor handed to the marker
    # loop) until the marker has moved 0.3 m with every update accepted
    stream = fake_stream(8.0, np.random.default_rng(5))
    split = next(i for i, e in enumerate(stream) if e[0] >= T0_S + 2.0)
    tracker = LiveTracker()
    feed(tracker, stream[:split])
    assert tracker.valid()
    # the resolver's ambiguity detection is its own test (test_slot_resolver.py): here the
    # open choice is set where the track is now, as a re-acquisition would
    at = tracker.ekf.pos.copy()
    tracker.slots.ambiguous, tracker.slots.ambiguous_at = True, at
    poses, handed = [], []
    for t, kind, msg in stream[split:]:
        getattr(tracker, f"on_{kind}")(t, msg)
        new = tracker.step()
        poses += new
        if new:  # what the marker loop would get now
            handed.append((new[-1]["slot_ambiguous"], tracker.position(new[-1]["t_s"], 0.1)))
    held = [p for p in poses if not p["valid"]]
    assert held and all(p["slot_ambiguous"] for p in held)
    assert all(p is None for amb, p in handed if amb)
    assert sum(p is not None for amb, p in handed if not amb) > 100
    assert tracker.status()["slot_ambiguous"] is False and tracker.valid()
    first_ok = next(p for p in poses if p["valid"])
    moved = np.linalg.norm(np.asarray(first_ok["pos_tracker_m"]) - at)
    assert 0.25 < moved < 0.35, moved  # the LED position moved 0.3 m (2 cm from the centre)
