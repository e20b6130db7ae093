"""The daemon against four fake boards at full rates: identification, rates, values, clock
mapping, the marker loop, a dead port beside live ones, and the export of the result."""

from __future__ import annotations

import time

import numpy as np
import pytest
from airwake.daemon.fake_boards import (
    FakeBoard,
    marker_led_position,
    marker_position,
    periodic_messages,
)
from airwake.link.messages import BOARD_IDS
from airwake.record.flight_table import load_flight_table
from airwake.record.reader import open_recording
from airwake.tracking.losa import triangulate
from daemon_harness import DaemonRun, close_boards, halt_and_drain, recorded_frames, sent_frames

# timed against the wall clock with real processes: `make test` runs these after the
# parallel suite (two at a time), so CPU-heavy tests on the other worker cannot starve them
pytestmark = pytest.mark.wall_clock

RUN_S = 7.0


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    """One daemon run shared by this module's tests (a daemon start costs seconds)."""
    run_dir = tmp_path_factory.mktemp("ingest")
    boards = FakeBoard.standard_set(run_dir)
    daemon = DaemonRun(run_dir, ["losa", "marker", "base", "ghost"])
    try:
        daemon.wait_ports_open(["losa", "marker", "base"])
        t_start = time.monotonic_ns()
        for b in boards:
            b.start()
        daemon.wait_for(lambda st: len(st["boards"]) == 4 and all(
            b["identified"] for b in st["boards"].values()), 15, "4 boards identified")
        time.sleep(RUN_S)
        live = daemon.status()
        halt_and_drain(boards)
        rc = daemon.stop()
        final = daemon.status()
    finally:
        daemon.stop()
        close_boards(boards)
    rec = open_recording(daemon.out)
    yield {"boards": boards, "rc": rc, "live": live, "final": final, "rec": rec,
           "tables": rec.tables(), "t_start": t_start, "run_dir": run_dir,
           "stderr": daemon.stderr()}


def sim_of(session, name: str):
    return next(s for b in session["boards"] for s in b.sims if s.name == name)


def test_every_board_identified_and_clean_exit(session):
    # the operator's first question: which boards are there, running which firmware
    assert session["rc"] == 0, session["stderr"]
    st = session["final"]
    assert set(st["boards"]) == {"losa", "marker", "rover", "base"}
    for name, b in st["boards"].items():
        assert b["board_id"] == BOARD_IDS[name] and b["fw_version"] == "0.1.0"
        assert b["schema_ok"] and not b["schema_problems"]
    assert st["boards"]["rover"]["port"] == "base"  # forwarded by the base
    rec = session["rec"]
    assert rec.complete and all(s.indexed for s in rec.segments)
    assert set(rec.boards) == {"losa", "marker", "rover", "base"}


def test_dead_port_waits_without_stalling_the_others(session):
    # a port whose device does not exist: reported, retried, never blocks the live ones
    ghost = session["live"]["ports"]["ghost"]
    assert ghost["state"] == "waiting" and "No such file" in ghost["last_error"]
    for role in ("losa", "marker", "base"):
        assert session["live"]["ports"][role]["bytes_per_s"] > 10_000


def test_rates_match_the_protocol_within_two_percent(session):
    # rates from the recording itself: frames over the span of their board times
    for board in ("losa", "marker", "rover", "base"):
        sim = sim_of(session, board)
        for name, nominal in periodic_messages(board).items():
            t = session["tables"][f"/{board}/{name}"]
            board_s = t.rows["board_us"] / 1e6
            span = board_s.max() - board_s.min()
            rate = (len(t) - 1) / span * (1 + sim.drift_ppm * 1e-6)
            assert abs(rate / nominal - 1) < 0.02, (board, name, rate, nominal)
        assert session["tables"][f"/{board}/heartbeat"].rows["epoch"].max() == 0


def test_every_frame_sent_is_recorded_once(session):
    # nothing lost, nothing duplicated on clean links
    rec = session["rec"]
    got = recorded_frames(rec)
    sent = sent_frames(session["boards"])
    assert got == sent
    assert sum(rec.topics()[t] for t in rec.topics() if t.count("/") == 2
               and not t.startswith(("/raw", "/daemon", "/host"))) == len(sent)
    for role in ("losa", "marker", "base"):
        p = session["final"]["ports"][role]
        assert sum(p["errors"][k] for k in ("crc_error", "cobs_error", "unknown_id",
                                            "def_mismatch", "oversize")) == 0
        assert p["seq_lost"] == 0


def test_decoded_values_read_back(session):
    peaks = session["tables"]["/losa/losa_peaks"].rows
    sim = sim_of(session, "losa")
    t_boot = (peaks["board_us"] - sim.clock_offset_us) / (1 + sim.drift_ppm * 1e-6) / 1e6
    pos, ok = triangulate(peaks["peak_px"], peaks["slot"], peaks["sensor_flags"] & 1 == 1)
    truth = np.array([marker_led_position(t) for t in t_boot])
    assert ok.all() and np.max(np.abs(pos - truth)) < 2e-3  # f32 peaks, 1 us stamps
    pilot = session["tables"]["/base/pilot_inputs"].rows
    assert (pilot["valid_mask"] == 0x1F).all() and (pilot["pwm_us"][:, 4] == 1700).all()
    ins = session["tables"]["/rover/ins"].rows
    assert np.all(np.abs(ins["accel_frd_m_s2"][:, 2] + 9.8) < 1e-5)


def test_live_clock_mapping_within_two_ms_across_the_rover_wrap(session):
    # the rover's 32-bit clock wraps 5 s in; the mapped host time must not notice. The
    # live fit needs a couple of seconds of frames and sync replies (the export refits)
    for board in ("losa", "rover", "base"):
        sim = sim_of(session, board)
        t = session["tables"][f"/{board}/heartbeat"]
        truth_ns = sim.true_host_us(t.rows["board_us"]) * 1000.0
        err_ms = ((t.log_ns - truth_ns) / 1e6)[truth_ns > truth_ns[0] + 4e9]
        assert len(err_ms) >= 3 and np.max(np.abs(err_ms)) < 2.0, (board, err_ms)
    rover = session["tables"]["/rover/ins"].rows["board_us"]
    assert rover.max() > 1 << 32 > rover.min()  # it did wrap, within one epoch
    clock = session["final"]["boards"]["rover"]["clock"]
    assert clock["epochs"] == 1 and clock["two_sided"]  # drift: too short here, see test_clock


def test_marker_loop_feeds_back_peaks_and_position(session):
    marker = next(b for b in session["boards"] if b.name == "marker")
    cmds = marker.marker_commands
    t = np.array([c[0] for c in cmds]) / 1e9
    span = t[-1] - t[0]
    # 60 Hz nominal; a loaded 2-core machine may delay some passes past a period
    assert 40.0 < (len(cmds) - 1) / span < 66.0
    valid = [c for _, c in cmds if c.pos_valid]
    assert len(valid) > 0.9 * len(cmds)
    lit = [c.led_peak_counts for c in valid]
    assert all(set(p) <= {0, 800} for p in lit)  # the tracker's peak, or not seen
    one_led = [p for p in lit if sorted(p) == [0, 0, 0, 800]]
    assert len(one_led) > 0.9 * len(lit)  # both only around the marker's LED switch
    # the pose EKF's marker centre (the LED triangulation for the first commands)
    assert all(abs(c.pos_tracker_m[2] - 2.5) < 0.02 for c in valid)
    assert valid[0].full_scale_counts == 4095
    assert session["live"]["marker_loop"]["pos_source"] == "ekf"


def test_live_pose_is_recorded_near_the_marker(session):
    # the pose EKF runs on the ingest timeline and is recorded for Foxglove/PlotJuggler
    rec = session["rec"]
    poses = [m.json() for m in rec.messages(["/host/pose"])]
    t = np.array([p["t_s"] for p in poses])
    assert np.all(np.diff(t) > 0)
    # one per marker IMU sample (120 Hz) once started; it starts with the first LOSA fix,
    # later on a loaded machine, so the count is over the span it ran
    assert t[-1] - t[0] > 0.5 * RUN_S
    assert len(poses) > 0.8 * 120 * (t[-1] - t[0])
    sim = sim_of(session, "marker")
    t_board = (t * 1e6 - sim.boot_mono_us) / 1e6  # fake boards: host scale since boot
    pos = np.array([p["pos_tracker_m"] for p in poses])
    err = np.linalg.norm(pos - np.array([marker_position(x) for x in t_board]), axis=1)
    assert np.median(err) < 0.005 and np.max(err) < 0.03
    q = np.array([p["quat_wxyz"] for p in poses])
    assert np.all(np.isfinite(q)) and np.allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-6)
    assert poses[-1]["valid"] and poses[-1]["accepted"] > 100
    assert all(np.isfinite(poses[-1][k]).all() for k in ("pos_sigma_m", "att_sigma_rad"))
    tracker = session["final"]["tracker"]
    assert tracker["started"] and tracker["valid"]


@pytest.mark.parametrize("ext", ["parquet", "csv"])
def test_export_of_the_recording_loads_and_maps_time(session, tmp_path, ext):
    from airwake.record.export import export_recording
    from airwake.record.flight_table import write_flight_table

    rec = session["rec"]
    built = export_recording(rec)
    path = write_flight_table(built.df, tmp_path / f"flight.{ext}", built.metadata)
    ft = load_flight_table(path)
    df = ft.df
    assert ft.metadata["source"] == "recorder" and ft.metadata["missing_streams"] == []
    assert 140 < ft.metadata["rate_hz"] < 160 and len(df) > 140 * (RUN_S - 1)
    # t_s is host monotonic from the recording's start: compare with the rover's truth
    sim = sim_of(session, "rover")
    ins = session["tables"]["/rover/ins"].rows
    t0 = rec.metadata["start_monotonic_ns"]
    truth_t = (sim.true_host_us(ins["board_us"]) * 1000.0 - t0) / 1e9
    truth_t = np.sort(truth_t)
    t = df["t_s"].to_numpy()
    i = np.clip(np.searchsorted(truth_t, t), 1, len(truth_t) - 1)
    nearest = np.minimum(np.abs(truth_t[i] - t), np.abs(truth_t[i - 1] - t))
    assert np.max(nearest) < 1e-3  # offline mapping within 1 ms (samples are 6.7 ms apart)
    assert df["tracker_valid"].mean() > 0.9 and df["ship_valid"].all()
    assert np.all(np.isfinite(df["height_agl_m"].to_numpy()[df["rtk_fix"].to_numpy() == 3]))
