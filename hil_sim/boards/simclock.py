"""The host clock of a stepped SIL run: simulator time, shared with the daemon process.

In stepped mode the simulator drives every board clock and runs as fast as the boards
answer, so board time runs faster (or slower) than the wall clock. A daemon stamping
receive times with the wall clock would then record a flight compressed in time: the
export's clock refit maps board time onto that compressed host timeline, and every
derivative in the flight table (pdot, ...) would come out scaled by the real-time
factor. Simulators solve this by giving the host software the simulator's clock
(ROS `use_sim_time`, PX4/ArduPilot lockstep): here the unmodified daemon runs with
`time.monotonic` / `time.monotonic_ns` reading this shared clock
(`python -m hil_sim.boards.simclock --clock FILE -- daemon ...`), so its recording is
on the simulator's timeline and exports like a real-time flight.

The clock is a small memory-mapped file the runner writes and the daemon reads:

    seq u64 | mode u64 | value_ns i64          (little-endian, 24 bytes)

mode FOLLOW (0): now = CLOCK_MONOTONIC + value_ns (before and after the flight, so the
daemon's start-up, port backoff and shutdown run on ordinary time); mode FIXED (1):
now = value_ns (during the flight: host time = flight start + simulator time). The
writer keeps it continuous and monotonic across switches; `seq` is a seqlock (odd while
a write is in progress) and the reader never goes backwards.
"""

from __future__ import annotations

import mmap
import os
import struct
import sys
import time
from pathlib import Path

_LAYOUT = struct.Struct("<QQq")
FOLLOW, FIXED = 0, 1
_real_monotonic_ns = time.monotonic_ns


class SimClock:
    """The writer (the SIL runner). Starts following CLOCK_MONOTONIC (offset 0)."""

    def __init__(self, path: str | os.PathLike) -> None:
        self.path = Path(path)
        self._fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_TRUNC, 0o600)
        os.ftruncate(self._fd, _LAYOUT.size)
        self._map = mmap.mmap(self._fd, _LAYOUT.size)
        self._seq = 0
        self._mode = FOLLOW
        self._value = 0
        self._write(FOLLOW, 0)

    def _write(self, mode: int, value_ns: int) -> None:
        self._seq += 1  # odd: a write is in progress
        self._map[0:8] = struct.pack("<Q", self._seq)
        self._map[8:24] = struct.pack("<Qq", mode, value_ns)
        self._seq += 1
        self._map[0:8] = struct.pack("<Q", self._seq)
        self._mode, self._value = mode, value_ns

    def now_ns(self) -> int:
        if self._mode == FOLLOW:
            return _real_monotonic_ns() + self._value
        return self._value

    def hold(self) -> int:
        """Freeze at the current time (FIXED); returns that time in ns."""
        now = self.now_ns()
        self._write(FIXED, now)
        return now

    def set(self, host_ns: int) -> None:
        """FIXED at host_ns (never earlier than now)."""
        self._write(FIXED, max(int(host_ns), self.now_ns()))

    def follow(self) -> None:
        """Continue from the current time at the rate of CLOCK_MONOTONIC."""
        self._write(FOLLOW, self.now_ns() - _real_monotonic_ns())

    def close(self) -> None:
        self._map.close()
        os.close(self._fd)


class SimClockReader:
    """The reader (inside the daemon process): monotonic ns of the shared clock."""

    def __init__(self, path: str | os.PathLike) -> None:
        fd = os.open(path, os.O_RDONLY)
        try:
            self._map = mmap.mmap(fd, _LAYOUT.size, prot=mmap.PROT_READ)
        finally:
            os.close(fd)
        self._last = 0

    def now_ns(self) -> int:
        unpack = _LAYOUT.unpack_from
        m = self._map
        while True:
            seq, mode, value = unpack(m, 0)
            if seq & 1:
                continue
            if unpack(m, 0)[0] == seq:
                break
        now = _real_monotonic_ns() + value if mode == FOLLOW else value
        if now < self._last:
            now = self._last
        self._last = now
        return now


def install(path: str | os.PathLike) -> SimClockReader:
    """Make this process's `time.monotonic[_ns]` read the shared clock.

    pyserial is imported first so that its own timeouts keep the real clock."""
    try:
        import serial  # noqa: F401
    except ImportError:  # pragma: no cover - pyserial is a dependency
        pass
    reader = SimClockReader(path)
    time.monotonic_ns = reader.now_ns
    time.monotonic = lambda: reader.now_ns() / 1e9
    return reader


def main(argv: list[str] | None = None) -> int:
    """`python -m hil_sim.boards.simclock --clock FILE -- AIRWAKE-ARGS...`: run the
    `airwake` command (the daemon) with the shared clock as its monotonic clock."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if len(argv) < 3 or argv[0] != "--clock" or argv[2] != "--":
        print("usage: python -m hil_sim.boards.simclock --clock FILE -- airwake-args...",
              file=sys.stderr)
        return 2
    install(argv[1])
    from airwake.cli import main as airwake_main

    return airwake_main(argv[3:])


if __name__ == "__main__":
    sys.exit(main())
