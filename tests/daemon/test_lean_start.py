"""The daemon loads only what its boards and options need (issue 22): a restarted daemon
on the ship must record within a second or two, and a laptop's memory is not torch's."""

from __future__ import annotations

from airwake.daemon.fake_boards import FakeBoard
from daemon_harness import DaemonRun, close_boards

# each takes seconds to import and 30-300 MB; none is needed to record
NEVER = {"torch", "numba", "pandas", "pyarrow", "matplotlib", "dask"}
TRACKER = {"filterpy", "scipy"}  # the live pose EKF's


def imported(daemon: DaemonRun) -> set[str]:
    """Top-level packages the daemon imported (PYTHONPROFILEIMPORTTIME's lines)."""
    return {line.split("|")[-1].strip().split(".")[0] for line in daemon.stderr().splitlines()
            if line.startswith("import time:")}


def run_until(run_dir, roles, predicate, what, *extra) -> set[str]:
    daemon = DaemonRun(run_dir, roles, *extra, out=run_dir / f"rec-{'-'.join(roles)}")
    try:
        daemon.wait_for(predicate, 20, what)
        assert daemon.stop() == 0, daemon.stderr()[-2000:]
    finally:
        daemon.stop()
    return imported(daemon)


def test_daemon_imports_the_tracker_only_for_a_marker_and_never_torch_or_pandas(
        run_dir, monkeypatch):
    # rover + base only: no tracker, so nothing heavy at all; with the marker and the
    # LOSA the pose EKF is loaded when their frames arrive and runs (its status appears)
    monkeypatch.setenv("PYTHONPROFILEIMPORTTIME", "1")
    boards = FakeBoard.standard_set(run_dir)
    try:
        for b in boards:
            b.start()
        ship = run_until(run_dir, ["base"], lambda st: {"rover", "base"} <= set(st["boards"]),
                         "rover and base seen")
        assert "airwake" in ship and not ship & (NEVER | TRACKER), ship & (NEVER | TRACKER)
        hall = run_until(run_dir, ["losa", "marker", "base"],
                         lambda st: st.get("tracker", {}).get("started"), "tracker started")
        assert TRACKER <= hall and not hall & NEVER, hall & NEVER
    finally:
        close_boards(boards)


def test_no_track_never_loads_the_tracker(run_dir, monkeypatch):
    monkeypatch.setenv("PYTHONPROFILEIMPORTTIME", "1")
    boards = FakeBoard.standard_set(run_dir)
    try:
        for b in boards:
            b.start()
        hall = run_until(run_dir, ["losa", "marker", "base"],
                         lambda st: len(st["boards"]) == 4, "four boards seen", "--no-track")
        assert not hall & (NEVER | TRACKER), hall & (NEVER | TRACKER)
    finally:
        close_boards(boards)
