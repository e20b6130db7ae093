"""Crash safety: SIGKILL mid-recording, clean SIGINT/SIGTERM shutdown, full disk."""

from __future__ import annotations

import resource
import signal
import subprocess
import time

import numpy as np
import pytest
from airwake.daemon.fake_boards import FakeBoard
from airwake.link.messages import SCHEMA_HASH
from airwake.record.reader import open_recording, recover_recording
from daemon_harness import DaemonRun, close_boards, halt_and_drain, recorded_frames, sent_frames

# timed against the wall clock with real processes: `make test` runs these after the
# parallel suite (two at a time), so CPU-heavy tests on the other worker cannot starve them
pytestmark = pytest.mark.wall_clock

ROLES = ["losa", "marker", "base"]


def run_boards(run_dir, seconds: float, *extra, out=None, preexec_fn=None, until=None):
    """Start boards + daemon, run `seconds` (or until `until(status)`); returns both."""
    boards = FakeBoard.standard_set(run_dir)
    daemon = DaemonRun(run_dir, ROLES, *extra, out=out, preexec_fn=preexec_fn)
    daemon.wait_ports_open(ROLES)
    for b in boards:
        b.start()
    daemon.wait_for(lambda st: len(st["boards"]) == 4, 15, "4 boards")
    if until is not None:
        daemon.wait_for(until, 30, "condition")
    time.sleep(seconds)
    return boards, daemon


def test_sigkill_leaves_a_readable_recording_missing_under_half_a_second(run_dir):
    # kill -9 at an arbitrary moment: the recording opens and holds all but the last half
    # second (the writer flushes every record.recording.FLUSH_S = 0.1 s; docs/daemon.md)
    boards, daemon = run_boards(run_dir, 3.0 + float(np.random.default_rng().uniform(0, 0.5)))
    try:
        t_kill = time.monotonic_ns()
        daemon.proc.send_signal(signal.SIGKILL)
        daemon.proc.wait(10)
    finally:
        close_boards(boards)
        daemon.stop()
    rec = open_recording(daemon.out)
    assert not rec.complete and rec.summary is None
    assert not rec.segments[-1].complete and rec.segments[-1].recovered_bytes > 0
    got = recorded_frames(rec)
    wanted = sent_frames(boards, before_ns=t_kill - 0.5e9)
    assert len(wanted) > 3000 and wanted <= got, len(wanted - got)
    # how much was lost: from the first frame sent but not recorded to the kill
    sent = sorted((ns, (o, m, s, u)) for b in boards for ns, o, m, s, u, st in b.sent
                  if st == "ok" and ns <= t_kill)
    first_missing = next(ns for ns, key in sent if key not in got)
    assert (t_kill - first_missing) / 1e9 < 0.5
    # the raw bytes are recovered as far: decoding them finds the same frames
    from airwake.link.batch import decode_capture

    raw = decode_capture(rec.raw("base").data)
    assert len(raw.tables["ins"]) >= len(rec.table("/rover/ins")) + len(rec.table("/base/ins"))
    # the recovery path is also a command: an indexed copy with the same content
    fixed = open_recording(recover_recording(daemon.out, run_dir / "fixed"))
    assert fixed.complete and all(s.indexed for s in fixed.segments)
    assert recorded_frames(fixed) == got
    # and the export works on the crashed recording
    from airwake.record.export import export_recording

    built = export_recording(rec)
    assert len(built.df) > 300 and built.metadata["recording_complete"] is False


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_signal_shuts_down_cleanly_into_indexed_segments(run_dir, sig):
    # SIGINT/SIGTERM: flush, close every segment with its index; nothing lost
    boards, daemon = run_boards(run_dir, 3.5, "--segment-s", "1.5")
    try:
        halt_and_drain(boards, 0.5)
        t_sig = time.monotonic_ns()
        rc = daemon.stop(sig)
    finally:
        close_boards(boards)
        daemon.stop()
    assert rc == 0, daemon.stderr()
    rec = open_recording(daemon.out)
    assert rec.complete and len(rec.segments) >= 3
    assert all(s.indexed and s.complete for s in rec.segments)
    assert rec.summary["stop_reason"] == sig.name
    assert recorded_frames(rec) == sent_frames(boards, before_ns=t_sig)
    # every segment repeats the recording's metadata and the protocol definitions
    for seg in rec.segments:
        one = open_recording(seg.path)
        assert one.metadata["ports"] and one.protocol["schema_hash"] == f"0x{SCHEMA_HASH:08X}"
        assert set(one.boards) == {"losa", "marker", "rover", "base"}


def _full_disk_checks(daemon, boards, reason: str) -> None:
    st = daemon.wait_for(lambda st: st["recording"]["state"] == "failed", 30, "disk full")
    err = st["recording"]["error"]
    assert "segment-" in err and ".mcap" in err and reason in err
    # still running and reporting link health after the failure
    before = st["ports"]["base"]["bytes"]
    time.sleep(1.5)
    later = daemon.status()
    assert later["ports"]["base"]["bytes"] > before and later["t_s"] > st["t_s"]
    halt_and_drain(boards, 0.2)
    rc = daemon.stop()
    assert rc == 1
    assert "error:" in daemon.stderr() and reason in daemon.stderr()
    rec = open_recording(daemon.out)  # what was written is readable (recovery path)
    got = recorded_frames(rec)
    assert len(got) > 500 and got <= sent_frames(boards)
    assert not rec.complete


def test_full_disk_tmpfs_is_a_clear_error_and_no_corrupted_file(run_dir):
    disk = run_dir / "disk"
    disk.mkdir()
    mount = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=320k", "tmpfs", str(disk)],
                           capture_output=True)
    if mount.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here (needs root): {mount.stderr.decode()}")
    boards = []
    try:
        boards, daemon = run_boards(run_dir, 0.0, out=disk / "rec")
        _full_disk_checks(daemon, boards, "No space left on device")
    finally:
        close_boards(boards)
        subprocess.run(["umount", "-l", str(disk)], capture_output=True)


def test_file_size_limit_is_a_clear_error_and_no_corrupted_file(run_dir):
    # RLIMIT_FSIZE: writes past it fail with EFBIG (Python ignores SIGXFSZ)
    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (400_000, 400_000))

    boards = []
    try:
        boards, daemon = run_boards(run_dir, 0.0, preexec_fn=limit)
        _full_disk_checks(daemon, boards, "File too large")
    finally:
        close_boards(boards)
