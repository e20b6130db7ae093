"""The Python side of the native boards' sim channel (docs/sim-channel.md).

A native board (`build/native/<board>`) is the real firmware on a POSIX HAL: its
sensors, input captures, simulated UART peers and — in stepped mode — its clock
come from here, over a UNIX SOCK_SEQPACKET socket of fixed little-endian records;
its PWM outputs, UART bytes and resets come back. This module is the reference
client: start a board, queue inputs, advance the clock, read what came out.

    with NativeBoard("losa", ports={"host": "sim"}) as board:
        board.line(500, sensor=0, rate=rate_counts_per_us, dark=np.full(128, 40.0))
        board.imu(1000, gyro_rad_s=(0, 0, 0.1), accel_m_s2=(0, 0, -9.81))
        out = board.advance(10_000)          # run the board to t = 10 ms
        frames = decoder.feed(out.uart["host"])

Times are simulator microseconds (int). In stepped mode (the default) the board
runs only inside `advance()`: same inputs, same output bytes. Wall mode
(`mode="wall"`) follows CLOCK_MONOTONIC; use `send()` and `poll()` there.
"""

from __future__ import annotations

import fcntl
import os
import select
import shutil
import socket
import struct
import subprocess
import tempfile
import termios
import time
import tty
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

REPO_ROOT = Path(__file__).resolve().parents[2]

# ---- the numbers of firmware/hal/native/sim_proto.h and hal.h (a test compares) ----
MAGIC = 0x43535741
VERSION = 1
MAX_PACKET = 131072
HEADER = struct.Struct("<BBHIQ")  # type, chan, len (header + body), reserved, t_us

ADVANCE, LINE, IMU, EDGE, UART, RESET = 0x01, 0x02, 0x03, 0x04, 0x05, 0x06
HELLO, IDLE, PWM, UART_TX, BOOT = 0x81, 0x82, 0x83, 0x84, 0x85

PORTS = ("host", "ins", "rtk", "rover", "anemo")  # hal_port_t order
CAPTURES = ("rc1", "rc2", "rc3", "rc4", "rc5", "rotor_ir", "tail_servo")  # hal_capture_t
PWMS = ("led0", "led1", "led2", "led3")  # hal_pwm_t
BOARDS = ("losa", "marker", "rover", "base")
PIXELS = 128
ADC_MAX = 4095  # HAL_ADC_BITS = 12
RESET_CAUSES = {0: "power_on", 1: "watchdog", 2: "software", 3: "brownout", 4: "external",
                255: "other"}

_IMU_BODY = struct.Struct("<10f")
_HELLO_BODY = struct.Struct("<IHBB16sI")
_PWM_BODY = struct.Struct("<HH")
_BOOT_BODY = struct.Struct("<B3xI")


class ChannelError(RuntimeError):
    """The board or the channel misbehaved (exited, timed out, broke the protocol)."""


@dataclass(frozen=True)
class Hello:
    name: str
    board_id: int
    mode: str  # "stepped" or "wall"
    boot_count: int


@dataclass
class StepResult:
    """What the board sent back during one `advance()` (or one `poll()`)."""

    t_us: int
    uart_records: list[tuple[int, str, bytes]] = field(default_factory=list)  # (t, port, data)
    pwm: list[tuple[int, str, int]] = field(default_factory=list)  # (t, channel, duty 0..65535)
    boots: list[tuple[int, str, int]] = field(default_factory=list)  # (t, cause, boot_count)

    @property
    def uart(self) -> dict[str, bytes]:
        """Bytes per port (ports mapped to "sim"), in order."""
        out: dict[str, bytearray] = {}
        for _, port, data in self.uart_records:
            out.setdefault(port, bytearray()).extend(data)
        return {k: bytes(v) for k, v in out.items()}


def _pixels_f32(values) -> bytes:
    """128 little-endian float32 from an array of 128 or a scalar."""
    a = np.asarray(values, dtype="<f4")
    if a.shape == (PIXELS,):
        return a.tobytes()
    if a.ndim == 0:
        return np.full(PIXELS, a, dtype="<f4").tobytes()
    raise ValueError(f"expected 128 pixel values or one scalar, got shape {a.shape}")


def _index(name: str | int, names: Sequence[str], what: str) -> int:
    if isinstance(name, int):
        if 0 <= name < len(names):
            return name
    elif name.lower() in names:
        return names.index(name.lower())
    raise ValueError(f"unknown {what} {name!r}; expected one of {', '.join(names)}")


def executable(board: str, flavour: str = "release", build: bool = True) -> Path:
    """Path of a native board executable; builds it with make if missing.

    flavour "release" is build/native/<board> (-O2, for SIL runs), "asan" is
    build/native-asan/<board> (AddressSanitizer + UBSan, for tests).
    """
    if board not in BOARDS:
        raise ValueError(f"unknown board {board!r}; expected one of {', '.join(BOARDS)}")
    folder = {"release": "native", "asan": "native-asan"}[flavour]
    path = REPO_ROOT / "build" / folder / board
    if build and not path.exists():
        # one make at a time (pytest-xdist workers, parallel SIL runs share build/)
        lock_path = REPO_ROOT / "build" / ".native-build.lock"
        lock_path.parent.mkdir(parents=True, exist_ok=True)
        with open(lock_path, "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            if not path.exists():
                subprocess.run(["make", "-s", "-C", str(REPO_ROOT / "firmware"), str(path)],
                               check=True)
    return path


class RawPty:
    """A pty pair in raw mode (no CR/LF rewriting, no echo), the slave held open.

    The board opens `path` (the slave) like a serial device; the host side reads and
    writes `master`. Keeping our own slave fd open means the master never sees a
    hang-up while the board restarts.
    """

    def __init__(self) -> None:
        self.master, self.slave = os.openpty()
        for fd in (self.master, self.slave):
            tty.setraw(fd, termios.TCSANOW)
        os.set_blocking(self.master, False)
        self.path = os.ttyname(self.slave)

    def read(self, timeout_s: float = 0.0) -> bytes:
        """Everything readable now (waiting up to timeout_s for the first byte)."""
        chunks = []
        ready, _, _ = select.select([self.master], [], [], timeout_s)
        while ready:
            try:
                chunk = os.read(self.master, 65536)
            except (BlockingIOError, OSError):
                break
            if not chunk:
                break
            chunks.append(chunk)
            ready, _, _ = select.select([self.master], [], [], 0)
        return b"".join(chunks)

    def write(self, data: bytes) -> None:
        view = memoryview(data)
        while view:
            try:
                view = view[os.write(self.master, view):]
            except BlockingIOError:
                select.select([], [self.master], [], 1.0)

    def close(self) -> None:
        for fd in (self.master, self.slave):
            try:
                os.close(fd)
            except OSError:
                pass


class NativeBoard:
    """One native board process and its sim channel.

    ports maps roles (host, ins, rtk, rover, anemo) to "sim" (bytes on the channel), a
    path (a pty slave, e.g. `RawPty().path`), optionally with "@BAUD" to throttle
    the board's transmitter like the real UART.
    """

    def __init__(
        self,
        board: str,
        *,
        ports: dict[str, str] | None = None,
        mode: str = "stepped",
        flavour: str = "release",
        exe: str | os.PathLike | None = None,
        clock_drift_ppm: float = 0.0,
        clock_offset_us: int = 0,
        start_us: int = 0,
        config: str | os.PathLike | None = None,
        extra_args: Iterable[str] = (),
        timeout_s: float = 30.0,
    ) -> None:
        if mode not in ("stepped", "wall"):
            raise ValueError(f"mode {mode!r}: expected 'stepped' or 'wall'")
        self.board = board
        self.mode = mode
        self.timeout_s = timeout_s
        self.now_us = int(start_us)
        self._in_flight: StepResult | None = None  # advance_begin() without its end yet
        self._queue: list[tuple[int, bytes]] = []
        self._dir = Path(tempfile.mkdtemp(prefix=f"aw-{board}-"))
        self.socket_path = self._dir / "sim.sock"
        self.stderr_path = self._dir / "stderr.txt"
        exe_path = Path(exe) if exe is not None else executable(board, flavour)

        args = [str(exe_path), "--sim", str(self.socket_path), f"--{mode}",
                "--clock-drift-ppm", repr(float(clock_drift_ppm)),
                "--clock-offset-us", str(int(clock_offset_us)),
                "--start-us", str(int(start_us))]
        for role, target in (ports or {}).items():
            _index(role, PORTS, "port role")
            args += ["--port", f"{role}={target}"]
        if config is not None:
            args += ["--config", str(config)]
        args += list(extra_args)

        self._listener = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        self._listener.bind(str(self.socket_path))
        self._listener.listen(1)
        self._stderr = open(self.stderr_path, "wb")  # noqa: SIM115 — closed in close()
        self.process = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=self._stderr,
                                        stderr=self._stderr)
        self._sock: socket.socket | None = None
        try:
            self._listener.settimeout(timeout_s)
            try:
                self._sock, _ = self._listener.accept()
            except TimeoutError:
                raise ChannelError(self._why("did not connect")) from None
            self._sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4 * MAX_PACKET)
            self._sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 * MAX_PACKET)
            self._sock.settimeout(timeout_s)
            self.hello = self._read_hello()
        except BaseException:
            self.close()
            raise

    # ---- inputs (queued until the next advance/send) ----
    def line(self, t_us: int, sensor: int, rate, dark=0.0) -> None:
        """Irradiance on one TSL1401 array from t_us on: rate in ADC counts per µs of
        exposure and dark level in counts, per pixel (arrays of 128 or scalars)."""
        if not 0 <= sensor < 4:
            raise ValueError(f"sensor {sensor}: expected 0..3")
        self._put(LINE, sensor, t_us, _pixels_f32(rate) + _pixels_f32(dark))

    def lines(self, t_us: Sequence[int], rate: np.ndarray, dark: np.ndarray) -> None:
        """Batch of `line()`: at each t_us[k] every array s gets rate[k, s], dark[k, s]
        (shapes (K, 4, 128))."""
        rate = np.asarray(rate, dtype="<f4")
        dark = np.asarray(dark, dtype="<f4")
        if rate.shape != dark.shape or rate.shape[1:] != (4, PIXELS):
            raise ValueError(f"lines: rate {rate.shape} and dark {dark.shape} must be "
                             "(K, 4, 128)")
        bodies = np.concatenate([rate, dark], axis=-1)  # (K, 4, 256) f32 = 1024 B each
        length = HEADER.size + bodies.shape[-1] * 4
        q = self._queue
        for k, t in enumerate(t_us):
            t = int(t)
            for s in range(4):
                q.append((t, HEADER.pack(LINE, s, length, 0, t) + bodies[k, s].tobytes()))

    def imu(self, t_us: int, gyro_rad_s, accel_m_s2, mag_ut=(0.0, 0.0, 0.0),
            temp_c: float = 25.0) -> None:
        """One IMU sample in the MPU-9250's chip axes (= the board's x fwd, y right,
        z down; at rest accel z = -9.81)."""
        self._put(IMU, 0, t_us, _IMU_BODY.pack(*gyro_rad_s, *accel_m_s2, *mag_ut, temp_c))

    def imus(self, t_us: Sequence[int], rows: np.ndarray) -> None:
        """Batch of `imu()`: rows (K, 10) float32 gyro[3], accel[3], mag[3], temp."""
        rows = np.ascontiguousarray(rows, dtype="<f4")
        if rows.ndim != 2 or rows.shape[1] != 10:
            raise ValueError(f"imus: rows {rows.shape} must be (K, 10)")
        length = HEADER.size + _IMU_BODY.size
        q = self._queue
        for k, t in enumerate(t_us):
            t = int(t)
            q.append((t, HEADER.pack(IMU, 0, length, 0, t) + rows[k].tobytes()))

    def edge(self, t_us: int, channel: str | int, level: int) -> None:
        """An input-capture edge: level 1 rising, 0 falling."""
        ch = _index(channel, CAPTURES, "capture channel")
        self._put(EDGE, ch, t_us, bytes([1 if level else 0]) + bytes(7))

    def uart(self, t_us: int, port: str | int, data: bytes) -> None:
        """Bytes a peer (VN200, Piksi, the rover's XBee, the host) sends to a port
        mapped to "sim"; they arrive together at t_us."""
        p = _index(port, PORTS, "port")
        view = memoryview(bytes(data))
        step = 0xFFFF - HEADER.size
        for i in range(0, len(view), step):
            self._put(UART, p, t_us, bytes(view[i:i + step]))

    def reset(self, t_us: int) -> None:
        """Pull the board's reset pin at t_us."""
        self._put(RESET, 0, t_us, b"")

    # ---- stepped mode ----
    def advance(self, t_us: int) -> StepResult:
        """Run the board until t_us with the queued inputs; return its outputs."""
        return self.advance_end(self.advance_begin(t_us))

    def advance_begin(self, t_us: int) -> StepResult:
        """The first half of `advance()`: the queued inputs and the ADVANCE to t_us go out
        and the board runs while the caller does other work (another board's step);
        `advance_end()` collects what it sent. One step in flight per board."""
        if self.mode != "stepped":
            raise ChannelError("advance() is for stepped mode; use send()/poll() in wall mode")
        if self._in_flight is not None:
            raise ChannelError(self._why("advance_begin() with a step still in flight"))
        t_us = int(t_us)
        if t_us < self.now_us:
            raise ValueError(f"advance({t_us}): the board is already at {self.now_us} us")
        records = sorted(self._queue, key=lambda r: r[0])
        self._queue.clear()
        if records and records[-1][0] > t_us:
            raise ValueError(f"an input at {records[-1][0]} us is after advance({t_us})")
        result = StepResult(t_us)
        # split so that every packet (inputs + ADVANCE) fits MAX_PACKET
        chunk: list[bytes] = []
        size = HEADER.size
        for t, rec in records:
            if size + len(rec) > MAX_PACKET and chunk:
                self._step(chunk, t, result)
                chunk, size = [], HEADER.size
            chunk.append(rec)
            size += len(rec)
        self._send_step(chunk, t_us)
        self._in_flight = result
        return result

    def advance_end(self, result: StepResult) -> StepResult:
        """The second half of `advance()`: wait for the board's outputs up to its IDLE."""
        if self._in_flight is not result:
            raise ChannelError(self._why("advance_end() without its advance_begin()"))
        while not self._read_packet(result):
            pass
        self._in_flight = None
        self.now_us = result.t_us
        return result

    def _send_step(self, records: list[bytes], t_us: int) -> None:
        self._send_packet(b"".join(records) + HEADER.pack(ADVANCE, 0, HEADER.size, 0, t_us))

    def _step(self, records: list[bytes], t_us: int, result: StepResult) -> None:
        self._send_step(records, t_us)
        while True:
            if self._read_packet(result):
                return

    # ---- wall mode ----
    def send(self) -> None:
        """Wall mode: send the queued inputs now (applied when their t_us is reached)."""
        records = [r for _, r in sorted(self._queue, key=lambda r: r[0])]
        self._queue.clear()
        chunk: list[bytes] = []
        size = 0
        for rec in records:
            if size + len(rec) > MAX_PACKET and chunk:
                self._send_packet(b"".join(chunk))
                chunk, size = [], 0
            chunk.append(rec)
            size += len(rec)
        if chunk:
            self._send_packet(b"".join(chunk))

    def poll(self, timeout_s: float = 0.0) -> StepResult:
        """Wall mode: whatever the board sent, waiting up to timeout_s for the first."""
        result = StepResult(self.clock_us())
        ready, _, _ = select.select([self._sock], [], [], timeout_s)
        while ready:
            self._read_packet(result)
            ready, _, _ = select.select([self._sock], [], [], 0)
        return result

    @staticmethod
    def clock_us() -> int:
        """Wall mode's simulator time: CLOCK_MONOTONIC in µs (shared with the board)."""
        return time.clock_gettime_ns(time.CLOCK_MONOTONIC) // 1000

    # ---- plumbing ----
    def _put(self, kind: int, chan: int, t_us: int, body: bytes) -> None:
        length = HEADER.size + len(body)
        if length > 0xFFFF:
            raise ValueError(f"record of {length} bytes exceeds the 65535-byte limit")
        self._queue.append((int(t_us), HEADER.pack(kind, chan, length, 0, int(t_us)) + body))

    def _send_packet(self, packet: bytes) -> None:
        try:
            self._sock.send(packet)
        except OSError as exc:
            raise ChannelError(self._why(f"send failed ({exc})")) from None

    def _recv(self) -> bytes:
        try:
            data = self._sock.recv(MAX_PACKET)
        except TimeoutError:
            raise ChannelError(self._why(f"no reply within {self.timeout_s} s")) from None
        if not data:
            raise ChannelError(self._why("closed the channel"))
        return data

    def _read_hello(self) -> Hello:
        packet = self._recv()
        kind, _, length, _, _ = HEADER.unpack_from(packet)
        if kind != HELLO or length != HEADER.size + _HELLO_BODY.size:
            raise ChannelError(self._why(f"sent record 0x{kind:02x} instead of HELLO"))
        magic, version, mode, board_id, name, boots = _HELLO_BODY.unpack_from(packet, HEADER.size)
        if magic != MAGIC or version != VERSION:
            raise ChannelError(self._why(f"speaks channel {magic:#x} v{version}, "
                                         f"expected {MAGIC:#x} v{VERSION}"))
        return Hello(name.rstrip(b"\0").decode(), board_id, {1: "stepped", 2: "wall"}[mode],
                     boots)

    def _read_packet(self, result: StepResult) -> bool:
        """Parse one packet into result; True when it ended with IDLE."""
        packet = self._recv()
        pos = 0
        idle = False
        while pos + HEADER.size <= len(packet):
            kind, chan, length, _, t = HEADER.unpack_from(packet, pos)
            if length < HEADER.size or pos + length > len(packet):
                raise ChannelError(self._why(f"sent a malformed record at byte {pos}"))
            body = packet[pos + HEADER.size:pos + length]
            if kind == UART_TX:
                result.uart_records.append((t, PORTS[chan], body))
            elif kind == PWM:
                result.pwm.append((t, PWMS[chan], _PWM_BODY.unpack(body)[0]))
            elif kind == BOOT:
                cause, count = _BOOT_BODY.unpack(body)
                result.boots.append((t, RESET_CAUSES.get(cause, str(cause)), count))
            elif kind == IDLE:
                idle = True
            pos += length
        return idle

    def _why(self, what: str) -> str:
        code = self.process.poll() if hasattr(self, "process") else None
        tail = ""
        try:
            tail = self.stderr_path.read_text(errors="replace")[-2000:].strip()
        except OSError:
            pass
        state = "running" if code is None else f"exit status {code}"
        return (f"native board {self.board} {what} ({state})"
                + (f"; its stderr: {tail}" if tail else ""))

    def close(self) -> int | None:
        """Close the channel (the board exits on its own) and reap the process."""
        if self._sock is not None:
            self._sock.close()
            self._sock = None
        self._listener.close()
        code = None
        if hasattr(self, "process"):
            try:
                code = self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                code = self.process.wait()
        if not self._stderr.closed:
            self._stderr.close()
        shutil.rmtree(self._dir, ignore_errors=True)
        return code

    def __enter__(self) -> NativeBoard:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
