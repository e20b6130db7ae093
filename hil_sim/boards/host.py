"""The host side of a SIL run: the real daemon as a child process, watched through /proc.

`HostDaemon` starts `airwake daemon` (stepped: under `simclock`, on the simulator's
clock), and gives the runner what lockstep needs without touching the daemon's code:

- `wait_read(target)`: the daemon has read `target` bytes in all — its `rchar` counter
  (/proc/PID/io; its reads are the ports' bytes). A pty hands written bytes to the
  reader's line discipline asynchronously, so an empty input queue is no proof;
- `wait_idle()`: it is asleep again in its event loop (state S in epoll/select/poll or
  its poll-period nanosleep, /proc/PID/wchan): its pass over those bytes, and whatever
  it wrote in reply, is complete;
- `cpu_s()`, `check()`, `tail()` (the end of its log), `stop()` (SIGINT), `kill()`.
"""

from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path

from airwake.errors import AirwakeError

_TICK = os.sysconf("SC_CLK_TCK")
_IDLE_WAITS = ("epoll", "select", "poll", "nanosleep")


class SilError(AirwakeError):
    """A SIL run that cannot start or went wrong (what, and where to look)."""


def read_chars(pid: int) -> int | None:
    """Bytes the process has read with read(2) and friends (/proc/PID/io `rchar`)."""
    try:
        with open(f"/proc/{pid}/io", "rb") as f:
            return int(f.readline().split()[1])
    except (OSError, ValueError, IndexError):
        return None


def asleep(pid: int) -> bool:
    """The process sleeps in its event loop (or has exited). Where the kernel hides the
    wait channel (wchan reads "0"), any interruptible sleep counts."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        if state != "S":
            return state in ("Z", "X")
        wchan = Path(f"/proc/{pid}/wchan").read_text().strip()
    except (OSError, IndexError):
        return True
    return wchan in ("", "0") or any(w in wchan for w in _IDLE_WAITS)


def cpu_seconds(pid: int) -> float | None:
    """User + system CPU time of a process so far (/proc/PID/stat)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None
    return (int(fields[11]) + int(fields[12])) / _TICK


def _backoff(pause: float) -> float:
    time.sleep(pause)
    return min(pause * 1.5, 5e-4)


class HostDaemon:
    """`airwake daemon` as a child process (module doc). `cmd` is its command line; its
    output goes to `log_path`."""

    def __init__(self, cmd: list[str], log_path: Path, cwd: Path,
                 stall_timeout_s: float = 20.0) -> None:
        self.log_path = Path(log_path)
        self.stall_timeout_s = stall_timeout_s
        self._log = open(self.log_path, "wb")  # noqa: SIM115 — closed in stop()/kill()
        self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=self._log,
                                     stderr=subprocess.STDOUT, cwd=cwd)
        self.pid = self.proc.pid
        self.killed = False

    @property
    def alive(self) -> bool:
        return self.proc.poll() is None

    def check(self, what: str) -> None:
        """SilError (with the end of its log) if the daemon has exited unasked."""
        if not self.killed and self.proc.poll() is not None:
            raise SilError(f"the daemon exited ({self.proc.returncode}) while {what}: "
                           f"{self.tail()}")

    def tail(self, chars: int = 1500) -> str:
        try:
            text = self.log_path.read_text(errors="replace").strip()
        except OSError:
            return "(no daemon log)"
        return text[-chars:] or "(empty daemon log)"

    def wait_for(self, predicate, timeout_s: float, what: str) -> None:
        end = time.monotonic() + timeout_s
        while not predicate():
            self.check(what)
            if time.monotonic() > end:
                raise SilError(f"the daemon did not finish {what} within {timeout_s:.0f} s: "
                               f"{self.tail()}")
            time.sleep(0.005)

    def read_chars(self) -> int | None:
        return read_chars(self.pid)

    def cpu_s(self) -> float | None:
        return cpu_seconds(self.pid)

    def wait_read(self, target: int, queues_empty) -> int:
        """Wait (wall time) until the daemon has read `target` bytes in all; returns 0,
        or the shortfall when nothing was queued for it for 50 ms (`queues_empty()`:
        bytes a lost port discarded never get read — the caller re-bases)."""
        got = read_chars(self.pid)
        if got is not None and got >= target:
            return 0
        end = time.monotonic() + self.stall_timeout_s
        empty_since = None
        pause = 5e-5
        while True:
            got = read_chars(self.pid)
            if got is None:  # no /proc/PID/io here: the empty queue is all we can see
                if queues_empty():
                    return 0
            elif got >= target:
                return 0
            now = time.monotonic()
            if not queues_empty():
                empty_since = None
            elif empty_since is None:
                empty_since = now
            elif now - empty_since > 0.05 and got is not None:
                return target - got
            if now > end:
                raise SilError(f"the daemon has not read its ports for "
                               f"{self.stall_timeout_s:.0f} s: {self.tail()}")
            self.check("recording")
            pause = _backoff(pause)

    def wait_idle(self) -> None:
        """Wait (wall time) until the daemon sleeps in its event loop again."""
        end = time.monotonic() + self.stall_timeout_s
        pause = 5e-5
        while not asleep(self.pid):
            if time.monotonic() > end:
                raise SilError(f"the daemon has been busy for {self.stall_timeout_s:.0f} s: "
                               f"{self.tail()}")
            self.check("recording")
            pause = _backoff(pause)

    def stop(self, timeout_s: float = 60.0) -> int:
        """SIGINT (a clean stop: the recording's segments closed and indexed); SIGKILL
        after `timeout_s`. Returns the exit status."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(timeout_s)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self._log.close()
        return self.proc.returncode

    def kill(self, sig: int = signal.SIGKILL) -> int:
        """Kill it now; returns CLOCK_MONOTONIC ns of the signal."""
        t = time.monotonic_ns()
        self.killed = True
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
            self.proc.wait(10)
        return t

    def close(self) -> None:
        """Best effort after an error: kill if running, close the log."""
        if self.proc.poll() is None:
            self.killed = True
            self.proc.kill()
            self.proc.wait()
        if not self._log.closed:
            self._log.close()
