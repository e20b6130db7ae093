"""Running the real daemon (a subprocess) against fake boards on real ptys (helpers; the
fixtures are in conftest.py)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from airwake.daemon.fake_boards import FakeBoard
from frame_sets import recorded_frames

REPO = Path(__file__).resolve().parents[2]


class DaemonRun:
    """A daemon subprocess reading ports RUN/<role>, recording into RUN/rec."""

    def __init__(self, run_dir: Path, roles: list[str], *extra: str, out: Path | None = None,
                 preexec_fn=None) -> None:
        self.run_dir = run_dir
        self.out = out or run_dir / "rec"
        self.status_path = run_dir / "status.json"
        cmd = [sys.executable, "-m", "airwake.cli", "daemon", "--out", str(self.out),
               "--status-json", str(self.status_path), "--quiet", "--poll-ms", "5", *extra]
        for role in roles:
            cmd += ["--port", f"{role}={run_dir / role}"]
        self.stderr_path = run_dir / "daemon.stderr"
        self._err = self.stderr_path.open("wb")
        self.proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=self._err,
                                     cwd=REPO, preexec_fn=preexec_fn)

    def status(self) -> dict | None:
        try:
            return json.loads(self.status_path.read_text())
        except (OSError, ValueError):
            return None

    def wait_for(self, predicate, timeout: float = 20.0, what: str = "condition") -> dict:
        end = time.monotonic() + timeout
        st = None
        while time.monotonic() < end:
            if self.proc.poll() is not None:
                raise AssertionError(f"daemon exited ({self.proc.returncode}) waiting for "
                                     f"{what}: {self.stderr()[-2000:]}")
            st = self.status()
            if st is not None and predicate(st):
                return st
            time.sleep(0.1)
        raise AssertionError(f"timed out waiting for {what}; last status: "
                             f"{json.dumps(st)[:2000] if st else None}")

    def wait_ports_open(self, roles, timeout: float = 20.0) -> dict:
        return self.wait_for(lambda st: all(st["ports"][r]["state"] == "open" for r in roles),
                             timeout, f"ports {roles} open")

    def stop(self, sig=signal.SIGTERM, timeout: float = 20.0) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
        try:
            rc = self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rc = self.proc.wait()
        self._err.close()
        return rc

    def stderr(self) -> str:
        try:
            return self.stderr_path.read_text(errors="replace")
        except OSError:
            return ""


def start_boards(boards: list[FakeBoard]) -> None:
    for b in boards:
        b.start()


def halt_and_drain(boards: list[FakeBoard], seconds: float = 0.6) -> None:
    """Stop sending, leave the ptys so the daemon reads what is in flight."""
    for b in boards:
        b.halt()
    time.sleep(seconds)


def close_boards(boards: list[FakeBoard]) -> None:
    for b in boards:
        try:
            b.stop()
        except OSError:
            pass


def sent_frames(boards: list[FakeBoard], states=("ok",), before_ns: float | None = None
                ) -> set[tuple[int, int, int, int]]:
    """(origin, msg_id, seq, board_time_u32) of the frames the fakes sent."""
    out = set()
    for b in boards:
        for host_ns, origin, mid, seq, u32, state in b.sent:
            if state in states and (before_ns is None or host_ns <= before_ns):
                out.add((origin, mid, seq, u32))
    return out


def kill_quietly(pid: int) -> None:
    try:
        os.kill(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


__all__ = ["DaemonRun", "FakeBoard", "close_boards", "halt_and_drain", "np", "recorded_frames",
           "sent_frames", "start_boards"]
