"""The host side of a SIL run: the real daemon as a child process, watched through /proc.

`HostDaemon` starts `airwake daemon` (stepped: under `simclock`, on the simulator's
clock), and gives the runner what lockstep needs without touching the daemon's code:

- `wait_read(target)`: the daemon has read `target` bytes in all — its `rchar` counter
  (/proc/PID/io; its reads are the ports' bytes, so it must not import anything in
  mid-flight: `SilRun` starts it with `--track`). A pty hands written bytes to the
  reader's line discipline asynchronously, so an empty input queue is no proof;
- `wait_idle()`: it is asleep again in its event loop (state S in epoll/select/poll or
  its poll-period nanosleep, /proc/PID/wchan, or /proc/PID/syscall where wchan is
  hidden): its pass over those bytes, and whatever it wrote in reply, is complete;
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
# the same waits by syscall number (/proc/PID/syscall's first field), for kernels that
# hide wchan: a thread in state S may also wait for the GIL or a lock (futex), mid-pass
_IDLE_SYSCALLS = {
    "x86_64": {7, 23, 35, 230, 232, 270, 271, 281, 441},  # poll select nanosleep
    # clock_nanosleep epoll_wait pselect6 ppoll epoll_pwait epoll_pwait2
    "aarch64": {22, 72, 73, 101, 115, 441},  # epoll_pwait pselect6 ppoll nanosleep
    # clock_nanosleep epoll_pwait2
}.get(os.uname().machine)
LOST_SETTLE_S = 0.05  # an empty queue this long after a port was lost: its bytes are gone


class SilError(AirwakeError):
    """A SIL run that cannot start or went wrong (what, and where to look)."""


class ProcFile:
    """One /proc file of a process, opened once and re-read with pread: the lockstep
    polls the daemon's files thousands of times a second, and an open() per poll
    (with pathlib's parsing) was a tenth of the simulator's CPU."""

    def __init__(self, path: str) -> None:
        self.path = path
        self._fd: int | None = None

    def read(self) -> bytes | None:
        """The file's content now, or None when it cannot be read (process gone)."""
        try:
            if self._fd is None:
                self._fd = os.open(self.path, os.O_RDONLY)
            return os.pread(self._fd, 4096, 0)
        except OSError:
            self.close()
            return None

    def close(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None


def _rchar(io: bytes | None) -> int | None:
    try:
        return int(io.split(b"\n", 1)[0].split()[1])
    except (AttributeError, ValueError, IndexError):
        return None


def _asleep(stat: bytes | None, wchan: ProcFile, syscall: ProcFile | None = None) -> bool:
    """The process sleeps in its event loop (or has exited). Where the kernel hides the
    wait channel (wchan reads "0"), the syscall it sleeps in decides (/proc/PID/syscall:
    a Python thread waiting for the GIL sleeps in futex, state S, mid-pass); where that
    is hidden too, any interruptible sleep counts."""
    if stat is None:
        return True
    try:
        state = stat.rsplit(b")", 1)[1].split()[0].decode()
    except IndexError:
        return True
    if state != "S":
        return state in ("Z", "X")
    w = wchan.read()
    if w is None:
        return True
    text = w.decode(errors="replace").strip()
    if text not in ("", "0"):
        return any(k in text for k in _IDLE_WAITS)
    call = syscall.read() if syscall is not None and _IDLE_SYSCALLS else None
    if not call:
        return True
    first = call.split()[0]
    if first == b"running":
        return False
    try:
        return int(first) in _IDLE_SYSCALLS
    except ValueError:
        return True


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
        self._io = ProcFile(f"/proc/{self.pid}/io")
        self._stat = ProcFile(f"/proc/{self.pid}/stat")
        self._wchan = ProcFile(f"/proc/{self.pid}/wchan")
        self._syscall = ProcFile(f"/proc/{self.pid}/syscall")

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
        return _rchar(self._io.read())

    def asleep(self) -> bool:
        return _asleep(self._stat.read(), self._wchan, self._syscall)

    def cpu_s(self) -> float | None:
        return cpu_seconds(self.pid)

    def wait_read(self, target: int, queues_empty, settle_s: float = LOST_SETTLE_S) -> int:
        """Wait (wall time) until the daemon has read `target` bytes in all; returns 0,
        or the shortfall when nothing was queued for it for `settle_s` (`queues_empty()`:
        bytes a lost port discarded never get read — the caller re-bases). A pty hands
        written bytes to the reader's queue asynchronously (a kernel worker), so on a
        loaded machine an empty queue can hide bytes still on their way for tens of ms:
        the caller gives `settle_s` short only where a port was lost."""
        got = self.read_chars()
        if got is not None and got >= target:
            return 0
        end = time.monotonic() + self.stall_timeout_s
        empty_since = None
        pause = 5e-5
        while True:
            got = self.read_chars()
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
            elif now - empty_since > settle_s and got is not None:
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
        while not self.asleep():
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
        self._close_proc_files()
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

    def _close_proc_files(self) -> None:
        for f in (self._io, self._stat, self._wchan, self._syscall):
            f.close()

    def close(self) -> None:
        """Best effort after an error: kill if running, close the log."""
        if self.proc.poll() is None:
            self.killed = True
            self.proc.kill()
            self.proc.wait()
        self._close_proc_files()
        if not self._log.closed:
            self._log.close()
