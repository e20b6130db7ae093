"""Faults on real ptys: corruption counted exactly, unplug/replug, board reset, stalls."""

from __future__ import annotations

import time

import numpy as np
import pytest
from airwake.daemon.fake_boards import BoardSim, FakeBoard, Faults
from airwake.record.reader import open_recording
from daemon_harness import DaemonRun, close_boards, halt_and_drain, recorded_frames, sent_frames

# timed against the wall clock with real processes: `make test` runs these after the
# parallel suite (two at a time), so CPU-heavy tests on the other worker cannot starve them
pytestmark = pytest.mark.wall_clock

BAD_KINDS = ("crc_error", "cobs_error", "unknown_id", "def_mismatch", "oversize")


def gaps_visible(board: FakeBoard) -> int:
    """Frames lost between two received frames of the same (origin, message): what u8
    seq numbers can reveal (nothing before the first or after the last received frame;
    a run of 256 or more aliases, docs/protocol.md)."""
    by_stream: dict[tuple[int, int], list[str]] = {}
    for _ns, origin, mid, _seq, _u32, state in board.sent:
        by_stream.setdefault((origin, mid), []).append(state)
    n = 0
    for states in by_stream.values():
        ok = [i for i, s in enumerate(states) if s == "ok"]
        for a, b in zip(ok[:-1], ok[1:], strict=True):
            n += (b - a - 1) % 256
    return n


def test_corruption_counted_exactly_and_no_valid_frame_lost(run_dir):
    # bit flips, dropped bytes and garbage: every bad segment counted, every intact frame kept
    faults = Faults(flip_every=37, drop_every=53, garbage_every=41, seed=7)
    boards = FakeBoard.standard_set(run_dir, faults={"base": faults, "losa": Faults(
        flip_every=29, seed=8)})
    daemon = DaemonRun(run_dir, ["losa", "marker", "base"])
    try:
        daemon.wait_ports_open(["losa", "marker", "base"])
        for b in boards:
            b.start()
        time.sleep(5.0)
        halt_and_drain(boards)
        assert daemon.stop() == 0, daemon.stderr()
    finally:
        daemon.stop()
        close_boards(boards)
    st = daemon.status()
    rec = open_recording(daemon.out)
    for b in boards:
        assert b.partial_frames == 0
        errors = st["ports"][b.name]["errors"]
        inj = b.injected
        assert sum(errors[k] for k in BAD_KINDS) == inj.bad_segments, (b.name, errors, inj)
        assert errors["bytes_dropped"] == inj.bytes_dropped
        assert st["ports"][b.name]["seq_lost"] == gaps_visible(b)
    base = next(b for b in boards if b.name == "base")
    assert base.injected.corrupted_frames > 100 and base.injected.bad_segments > 150
    # exactly the intact frames were decoded and recorded: none lost outside the
    # corrupted segments, none invented
    assert recorded_frames(rec) == sent_frames(boards)
    corrupt = sent_frames(boards, states=("corrupt",))
    assert len(corrupt) == sum(b.injected.corrupted_frames for b in boards)
    assert not corrupt & recorded_frames(rec)
    # the raw channel holds every byte, corrupted ones included, for later analysis
    raw = rec.raw("base")
    assert len(raw.data) == st["ports"]["base"]["bytes"]


def test_unplug_and_replug_reconnects_and_continues(run_dir):
    # a USB adapter pulled and plugged back: the same path comes back, the daemon reopens
    boards = FakeBoard.standard_set(run_dir)
    base = next(b for b in boards if b.name == "base")
    daemon = DaemonRun(run_dir, ["losa", "marker", "base"])
    try:
        daemon.wait_ports_open(["losa", "marker", "base"])
        for b in boards:
            b.start()
        time.sleep(2.0)
        base.unplug()
        t_unplug = time.monotonic_ns()
        daemon.wait_for(lambda st: st["ports"]["base"]["state"] == "waiting", 10, "base lost")
        time.sleep(1.0)
        base.replug()
        t_replug = time.monotonic_ns()
        st = daemon.wait_for(lambda st: st["ports"]["base"]["opens"] == 2
                             and st["ports"]["base"]["state"] == "open", 10, "base reopened")
        t_reopened = time.monotonic_ns()
        time.sleep(2.0)
        halt_and_drain(boards)
        assert daemon.stop() == 0
    finally:
        daemon.stop()
        close_boards(boards)
    st = daemon.status()
    assert st["ports"]["base"]["losses"] == 1 and st["ports"]["base"]["opens"] == 2
    rec = open_recording(daemon.out)
    ins = rec.table("/rover/ins")
    rx = ins.publish_ns
    assert (rx > t_replug).sum() > 150  # the rover's INS flows again through the base
    assert not ((rx > t_unplug + 2e8) & (rx < t_replug)).any()
    # the other ports never noticed: no gap in the LOSA stream around the unplug
    peaks_rx = np.sort(rec.table("/losa/losa_peaks").publish_ns)
    assert np.max(np.diff(peaks_rx)) < 0.3e9
    events = [m.json()["kind"] for m in rec.messages(["/daemon/events"])]
    assert "port_lost" in events and events.count("port_open") == 4
    # everything sent after the reopen was recorded (what a device sends before its port
    # is opened is flushed by the open, as with real adapters)
    after = sent_frames([base]) - sent_frames([base], before_ns=t_reopened)
    assert len(after) > 500 and after <= recorded_frames(rec)


def test_board_reset_starts_a_new_epoch_with_a_right_mapping(run_dir):
    # the base (and the rover behind it) reboot: clocks restart, boot count + 1
    boards = FakeBoard.standard_set(run_dir)
    base = next(b for b in boards if b.name == "base")
    daemon = DaemonRun(run_dir, ["losa", "marker", "base"])
    try:
        daemon.wait_ports_open(["losa", "marker", "base"])
        for b in boards:
            b.start()
        time.sleep(3.0)
        base.reboot()
        t_reboot = time.monotonic_ns()
        daemon.wait_for(lambda st: st["boards"]["rover"]["clock"].get("epochs") == 2
                        and st["boards"]["base"]["clock"].get("epochs") == 2, 10, "new epochs")
        time.sleep(5.0)
        halt_and_drain(boards)
        assert daemon.stop() == 0
    finally:
        daemon.stop()
        close_boards(boards)
    st = daemon.status()
    rover = st["boards"]["rover"]
    assert rover["boot_count"] == 3 and "boot count 2 -> 3" in rover["clock"]["epoch_reason"]
    assert rover["seq_lost"] == {}  # sequence numbers restart with the board: no false gaps
    rec = open_recording(daemon.out)
    hb = rec.table("/rover/heartbeat")
    sim = next(s for s in base.sims if s.name == "rover")
    new = hb.rows["epoch"] == 1
    assert new.any() and (~new).any()
    assert np.all(hb.publish_ns[new] > t_reboot)
    # mapping of the new epoch: right within 2 ms once the fit has a few seconds
    truth_ns = sim.true_host_us(hb.rows["board_us"][new]) * 1000.0
    late = truth_ns > t_reboot + 3e9
    err_ms = (hb.log_ns[new][late] - truth_ns[late]) / 1e6
    assert late.sum() >= 3 and np.max(np.abs(err_ms)) < 2.0
    # the export maps both epochs onto one increasing host timeline
    from airwake.record.export import export_recording

    built = export_recording(rec)
    t = built.df["t_s"].to_numpy()
    assert np.all(np.diff(t) > 0)
    assert t[0] < (t_reboot - rec.metadata["start_monotonic_ns"]) / 1e9 - 1.0
    assert t[-1] > (t_reboot - rec.metadata["start_monotonic_ns"]) / 1e9 + 3.0
    assert [e["reason"] for e in built.metadata["clock"]["rover"]["epochs"]][1] == \
        "boot count 2 -> 3"


def test_stalled_port_does_not_stall_the_others(run_dir):
    # a board that stops reading and writing (hung, or a saturated radio) for 2 s
    boards = FakeBoard.standard_set(run_dir)
    # a fourth port with a board that never reads what the host writes
    deaf = FakeBoard("rover", run_dir, [BoardSim("rover", rates={"imu": 50.0})])
    daemon = DaemonRun(run_dir, ["losa", "marker", "base", "rover"])
    try:
        daemon.wait_ports_open(["losa", "marker", "base", "rover"])
        for b in boards:
            b.start()
        deaf._answer = lambda: None  # never drains the host's requests
        deaf.start()
        time.sleep(1.5)
        losa = next(b for b in boards if b.name == "losa")
        t_stall = time.monotonic_ns()
        losa.stall(2.0)
        time.sleep(4.0)
        halt_and_drain(boards + [deaf])
        assert daemon.stop() == 0
    finally:
        daemon.stop()
        close_boards(boards + [deaf])
    rec = open_recording(daemon.out)
    for topic in ("/base/ins", "/marker/marker_attitude"):
        rx = np.sort(rec.table(topic).publish_ns)
        during = rx[(rx > t_stall) & (rx < t_stall + 2e9)]
        assert len(during) > 150 and np.max(np.diff(during)) < 0.2e9, topic
    peaks_rx = np.sort(rec.table("/losa/losa_peaks").publish_ns)
    assert (peaks_rx > t_stall + 2.5e9).sum() > 300  # and the stalled one came back
    st = daemon.status()
    losa = next(b for b in boards if b.name == "losa")
    assert st["ports"]["losa"]["seq_lost"] == gaps_visible(losa) > 300  # unsent while stalled


class OtherSchemaBoard(BoardSim):
    """A LOSA board built from another schema: its imu definition differs."""

    OTHER_IMU_HASH = 0x0BADF00D

    def heartbeat(self, board_us):
        return super().heartbeat(board_us)._replace(schema_hash=0x12345678)

    def due(self, mono_us):
        out = []
        for msg, board_us, is_data in super().due(mono_us):
            if type(msg).__name__ == "SchemaEntry" and msg.msg_id == 0x10:
                msg = msg._replace(def_hash=self.OTHER_IMU_HASH)
            out.append((msg, board_us, is_data))
        return out

    def frame(self, msg, board_us):
        if type(msg).__name__ != "Imu":
            return super().frame(msg, board_us)
        from airwake.link.framing import crc_seed, encode_payload_frame
        from airwake.link.messages import IMU

        seq = self.seq[IMU.id]
        self.seq[IMU.id] = (seq + 1) & 0xFF
        wire = encode_payload_frame(IMU.id, IMU.pack(msg), seq, self.origin,
                                    board_us & 0xFFFFFFFF, seed=crc_seed(self.OTHER_IMU_HASH))
        return wire, seq


def test_schema_mismatch_is_reported_loudly_naming_the_message(run_dir):
    # a board flashed from another protocol version: said at once, its frames not misread
    import json
    import subprocess
    import sys

    board = FakeBoard("losa", run_dir, [OtherSchemaBoard("losa")])
    cmd = [sys.executable, "-m", "airwake.cli", "daemon", "--out", str(run_dir / "rec"),
           "--status-json", "-", "--duration", "6", "--port", f"losa={run_dir / 'losa'}"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        time.sleep(2.0)  # the daemon opens the port (no status file to watch here)
        board.start()
        out, err = proc.communicate(timeout=30)
    finally:
        board.stop()
    assert proc.returncode == 0, err
    lines = [json.loads(x) for x in out.splitlines()]  # --status-json -: JSON lines
    st = lines[-1]
    losa = st["boards"]["losa"]
    assert losa["schema_ok"] is False and losa["schema_hash"] == "0x12345678"
    assert any("imu" in p for p in losa["schema_problems"])
    assert "schema_mismatch" in err and "imu" in err  # loud, on stderr
    assert "port losa" in err  # the terminal view went to stderr
    errors = st["ports"]["losa"]["errors"]
    assert errors["def_mismatch"] > 200 and "imu" not in losa["frames"]
    assert losa["frames"]["losa_peaks"] > 1000  # the rest still decodes
    rec = open_recording(run_dir / "rec")
    assert "/losa/imu" not in rec.topics()
    assert rec.boards["losa"]["schema_ok"] is False
