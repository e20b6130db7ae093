"""Serial ports for the daemon: non-blocking, reconnecting, never stalling the caller.

    port = SerialPort(PortSpec.parse("base=/dev/ttyUSB0@921600"))
    port.try_open(now)            # False while the device is absent (backoff doubles)
    data = port.read()            # bytes (maybe b""), or None: the port was lost
    port.write(frame)             # never blocks: what the OS will not take is dropped

Opened with pyserial (raw 8N1, no flow control, O_NONBLOCK), then read and written with
`os.read` / `os.write` on its file descriptor so one `selectors` loop serves every
port. A port that reports end-of-file or an OS error (USB unplugged: EIO/ENXIO; a pty
whose other side closed: EOF) is closed and reopened from the same path with backoff
0.1 s -> 2 s, so a replugged adapter (or a pty recreated behind the same symlink)
comes back by itself.
"""

from __future__ import annotations

import errno
import os
import re
from dataclasses import dataclass

from airwake.errors import AirwakeError

DEFAULT_BAUD = 921600
READ_SIZE = 1 << 16
BACKOFF_MIN_S = 0.1
BACKOFF_MAX_S = 2.0


class PortSpecError(AirwakeError):
    """A --port argument that does not parse."""


@dataclass(frozen=True)
class PortSpec:
    """`ROLE=DEVICE[@BAUD]`: role is a free name (losa, marker, rover, base, ...)."""

    role: str
    device: str
    baud: int = DEFAULT_BAUD

    @classmethod
    def parse(cls, text: str) -> PortSpec:
        m = re.fullmatch(r"([A-Za-z][A-Za-z0-9_-]*)=(.+?)(?:@(\d+))?", text.strip())
        if not m:
            raise PortSpecError(f"--port '{text}': expected ROLE=DEVICE[@BAUD], e.g. "
                                "base=/dev/ttyUSB0@921600")
        baud = int(m.group(3)) if m.group(3) else DEFAULT_BAUD
        if baud <= 0:
            raise PortSpecError(f"--port '{text}': baud {baud} must be positive")
        return cls(m.group(1), m.group(2), baud)


class SerialPort:
    """One serial port by role (see module doc). Counters are plain attributes."""

    def __init__(self, spec: PortSpec) -> None:
        self.spec = spec
        self.serial = None
        self.fd = -1
        self.opens = 0
        self.losses = 0
        self.last_error: str | None = None
        self.bytes_rx = 0
        self.bytes_tx = 0
        self.tx_dropped = 0
        self._backoff = BACKOFF_MIN_S
        self._next_try = 0.0

    @property
    def role(self) -> str:
        return self.spec.role

    @property
    def is_open(self) -> bool:
        return self.fd >= 0

    def try_open(self, now: float) -> bool:
        """Open the device unless open already or backing off; True when open."""
        if self.fd >= 0:
            return True
        if now < self._next_try:
            return False
        import serial

        try:
            ser = serial.Serial(port=None, baudrate=self.spec.baud, timeout=0,
                                write_timeout=0)
            ser.port = self.spec.device
            ser.open()
        except (serial.SerialException, OSError, ValueError) as exc:
            self.last_error = _reason(exc)
            self._next_try = now + self._backoff
            self._backoff = min(BACKOFF_MAX_S, self._backoff * 2)
            return False
        self.serial = ser
        self.fd = ser.fileno()
        os.set_blocking(self.fd, False)
        self.opens += 1
        self._backoff = BACKOFF_MIN_S
        return True

    def read(self) -> bytes | None:
        """What is waiting (b"" when nothing); None when the port was lost (now closed)."""
        try:
            data = os.read(self.fd, READ_SIZE)
        except BlockingIOError:
            return b""
        except OSError as exc:
            if exc.errno == errno.EINTR:
                return b""
            self._lost(_reason(exc))
            return None
        if not data:  # readable with nothing to read: the other end hung up
            self._lost("device closed (end of file)")
            return None
        self.bytes_rx += len(data)
        return data

    def write(self, data: bytes) -> int:
        """Write without blocking; returns bytes written (the rest is counted as dropped)."""
        if self.fd < 0:
            self.tx_dropped += len(data)
            return 0
        try:
            n = os.write(self.fd, data)
        except BlockingIOError:
            n = 0
        except OSError as exc:
            self.tx_dropped += len(data)
            if exc.errno not in (errno.EINTR,):
                self._lost(_reason(exc))
            return 0
        self.bytes_tx += n
        self.tx_dropped += len(data) - n
        return n

    def _lost(self, reason: str) -> None:
        self.last_error = reason
        self.losses += 1
        self.close()
        self._next_try = 0.0  # first retry at once, then back off

    def close(self) -> None:
        if self.serial is not None:
            try:
                self.serial.close()
            except Exception:  # noqa: BLE001 — closing a vanished device may fail any way
                pass
        self.serial = None
        self.fd = -1


def _reason(exc: Exception) -> str:
    err = getattr(exc, "errno", None)
    text = getattr(exc, "strerror", None) or str(exc)
    return f"{text} (errno {err})" if err else text
