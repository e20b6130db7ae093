"""Fake boards over real ptys: protocol frames at the boards' rates, for tests and bench.

    boards = FakeBoard.standard_set(run_dir)      # losa, marker, rover (via base), base
    for b in boards: b.start()
    ... airwake daemon --port losa=RUN/losa --port base=RUN/base ...
    b.unplug(); b.replug(); b.reboot(); b.stall(2.0); b.stop()

Each `FakeBoard` owns a pty pair in raw mode (a default pty rewrites 0x0D/0x0A), keeps
its slave open, and exposes the slave through a stable symlink `run_dir/<name>` that the
daemon opens like `/dev/ttyACM0`. A thread writes frames every `tick_s`: per origin
board (`BoardSim`; the base's port carries the rover too, as the real base forwards it)
its heartbeat (1 Hz), schema entries (all at boot, then 4 Hz), a log_text at boot and
its messages at the protocol's nominal rates (`MessageInfo.rate_hz`), stamped with the
board's own µs clock

    board_us = clock_offset_us + (monotonic_us - boot_monotonic_us) * (1 + drift_ppm 1e-6)

so the truth of the clock mapping is known. Data frames are stamped at their samples'
instants unless `BoardSim(stamp_latency_us={"ins": 1455})` makes a message's stamps that
much later (sent when the stamp comes due) and declares it in `stamp_latency` entries
after each heartbeat, as the firmware does. It answers `time_sync_request` like the
firmware (board_rx = its clock when it read the request, board_tx = when it replies) and
keeps every `marker_command` it receives.

Faults (`Faults`), counted exactly: bit flips and byte drops inside data frames (never
in a 0x00 delimiter, so each corrupts exactly one segment), short garbage segments
between frames (each one `cobs_error`), unplug/replug (the pty is destroyed and a new one
appears behind the same symlink), reboot (clock restarts, boot count + 1, sequence
numbers restart), stall (nothing written or read for a while).

`sent` logs every generated frame: (host_ns, origin, msg_id, seq, board_time_u32,
state) with state "ok", "corrupt", "unsent" (port unplugged, stalled, or the pty full
for 0.5 s) or "partial" (cut by a full pty: the receiver sees a bad segment).
"""

from __future__ import annotations

import math
import os
import select
import threading
import time
import tty
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from airwake.link.decoder import StreamDecoder
from airwake.link.framing import encode_frame
from airwake.link.messages import (
    BOARD_IDS,
    BY_ID,
    BY_NAME,
    MESSAGES,
    SCHEMA_HASH,
    Anemometer,
    GpsTime,
    Heartbeat,
    Imu,
    Ins,
    LogText,
    LosaPeaks,
    MarkerAttitude,
    PilotInputs,
    RotorSpeed,
    RtkBaseline,
    RtkPos,
    RtkStatus,
    RtkVel,
    SchemaEntry,
    StampLatency,
    TailServo,
    TimeSyncReply,
)
from airwake.tracking.losa import DEFAULT_GEOMETRY, WIRE_PIXELS
from airwake.tracking.marker import LED_DIRECTIONS_BODY, LED_RADIUS_M

# Messages each board sends periodically, at MessageInfo.rate_hz[board].
ON_DEMAND = {"heartbeat", "schema_entry", "time_sync_reply", "log_text", "losa_raw_line",
             "stamp_latency"}
ORIGIN_LAT_LON = (38.9784, -76.48)
M_PER_DEG_LAT = 111_000.0


def periodic_messages(board: str) -> dict[str, float]:
    """name -> nominal rate (Hz) of what `board` sends periodically."""
    return {m.name: float(m.rate_hz[board]) for m in MESSAGES
            if board in m.rate_hz and m.name not in ON_DEMAND and not m.to}


@dataclass
class Faults:
    """Corruption injected into one port's byte stream (0 = off)."""

    flip_every: int = 0  # flip one bit in every Nth data frame
    drop_every: int = 0  # drop one byte of every Nth data frame
    garbage_every: int = 0  # a 1..8 byte garbage segment after every Nth data frame
    seed: int = 0


@dataclass
class Injected:
    """What the faults did, counted exactly."""

    bad_segments: int = 0
    bytes_dropped: int = 0
    corrupted_frames: int = 0


class BoardSim:
    """One origin board: clock, sequence numbers, message schedule, message contents."""

    def __init__(self, name: str, *, drift_ppm: float = 0.0, clock_offset_us: int = 0,
                 boot_count: int = 0, rates: dict[str, float] | None = None,
                 stamp_latency_us: dict[str, int] | None = None) -> None:
        self.name = name
        self.stamp_latency_us = dict(stamp_latency_us or {})
        self.origin = BOARD_IDS[name]
        self.drift_ppm = drift_ppm
        self.clock_offset_us = clock_offset_us
        self.boot_count = boot_count
        self.rates = periodic_messages(name) if rates is None else rates
        self.ids = sorted({BY_NAME["heartbeat"].id, BY_NAME["schema_entry"].id,
                           BY_NAME["time_sync_request"].id, BY_NAME["time_sync_reply"].id,
                           *[BY_NAME[n].id for n in self.rates]}
                          | ({BY_NAME["marker_command"].id} if name == "marker" else set())
                          | ({BY_NAME["stamp_latency"].id} if self.stamp_latency_us else set()))
        self.boot(time.monotonic_ns() // 1000)

    def boot(self, mono_us: int) -> None:
        self.boot_mono_us = mono_us
        self.seq = [0] * 256
        self.next_due = {n: 0.0 for n in self.rates}
        self.next_heartbeat = 0.0
        self.next_schema = 0.25
        self.schema_index = 0
        self.announce_all = True
        self.frames_sent = 0
        self.bytes_sent = 0

    # -- clock ------------------------------------------------------------------

    def board_us(self, mono_us: float) -> int:
        return int(self.clock_offset_us + (mono_us - self.boot_mono_us)
                   * (1.0 + self.drift_ppm * 1e-6))

    def true_host_us(self, board_us: np.ndarray) -> np.ndarray:
        """The host monotonic time (µs) at which this board's clock read board_us."""
        return self.boot_mono_us + (np.asarray(board_us, float) - self.clock_offset_us) / (
            1.0 + self.drift_ppm * 1e-6)

    # -- frames -----------------------------------------------------------------

    def frame(self, msg, board_us: int) -> tuple[bytes, int]:
        mid = type(msg).MSG_ID
        seq = self.seq[mid]
        self.seq[mid] = (seq + 1) & 0xFF
        wire = encode_frame(msg, seq, self.origin, board_us & 0xFFFFFFFF)
        self.frames_sent += 1
        self.bytes_sent += len(wire)
        return wire, seq

    def due(self, mono_us: float) -> list:
        """Messages due now: [(msg, board_us, is_data)]."""
        t = (mono_us - self.boot_mono_us) / 1e6  # seconds since boot (host scale)
        b = self.board_us(mono_us)
        out = []
        if t >= self.next_heartbeat:
            self.next_heartbeat += 1.0
            out.append((self.heartbeat(b), b, False))
            for i, (name, lat) in enumerate(sorted(self.stamp_latency_us.items())):
                out.append((StampLatency(BY_NAME[name].id, int(lat), 1, i,
                                         len(self.stamp_latency_us)), b, True))
        if self.announce_all:
            self.announce_all = False
            for i, mid in enumerate(self.ids):
                out.append((SchemaEntry(mid, BY_ID[mid].def_hash, i, len(self.ids)), b, False))
            text = f"{self.name} boot {self.boot_count}".encode()[:48]
            out.append((LogText(1, 1, tuple(text.ljust(48, b"\0"))), b, False))
        elif t >= self.next_schema:
            self.next_schema += 0.25
            i = self.schema_index % len(self.ids)
            self.schema_index += 1
            mid = self.ids[i]
            out.append((SchemaEntry(mid, BY_ID[mid].def_hash, i, len(self.ids)), b, False))
        for name, rate in self.rates.items():
            lat_s = self.stamp_latency_us.get(name, 0) * 1e-6
            while t >= self.next_due[name] + lat_s:
                k = round(self.next_due[name] * rate)
                self.next_due[name] += 1.0 / rate
                ts = k / rate  # the sample's own time since boot
                out.append((self.content(name, ts), self.board_us(self.boot_mono_us
                                                                  + (ts + lat_s) * 1e6), True))
        return out

    def heartbeat(self, board_us: int) -> Heartbeat:
        return Heartbeat(board_id=self.origin, fw_version_major=0, fw_version_minor=1,
                         fw_version_patch=0, schema_hash=SCHEMA_HASH,
                         uptime_ms=(board_us // 1000) & 0xFFFFFFFF,
                         boot_count=self.boot_count, frames_sent=self.frames_sent + 1,
                         bytes_sent=self.bytes_sent & 0xFFFFFFFF)

    def sync_reply(self, req, board_rx_us: int, board_tx_us: int) -> TimeSyncReply:
        return TimeSyncReply(req.request_id, req.host_time_us, board_rx_us, board_tx_us)

    def content(self, name: str, t: float):
        """Plausible, smooth values at t seconds since boot (a gentle hover)."""
        s = math.sin
        if name == "imu" and self.origin == BOARD_IDS["marker"]:
            return Imu((0.0, 0.0, 0.0), tuple(marker_specific_force_body(t)), (20.0, 0.0, 40.0),
                       30.0, 4)
        if name == "imu":
            return Imu((0.01 * s(t), 0.02 * s(0.7 * t), 0.0), (0.1, 0.0, -9.8),
                       (20.0, 0.0, 40.0), 30.0, 4)
        if name == "ins":
            if self.origin == BOARD_IDS["base"]:
                ypr = (30.0, 1.0 * s(0.1 * t), 2.0 * s(0.13 * t))
                pos = (5.0 * t, 0.0, -2.0)
                vel = (5.0, 0.0, 0.0)
                rates = (0.0, 0.0, 0.0)
            else:
                ypr = (40.0 + 10.0 * s(0.2 * t), 3.0 * s(0.5 * t), 5.0 * s(0.7 * t))
                pos = (5.0 * t - 10.0, 2.0 * s(0.1 * t), -8.0)
                vel = (5.0, 0.2 * math.cos(0.1 * t), 0.0)
                rates = (math.radians(5.0 * 0.7) * math.cos(0.7 * t),
                         math.radians(3.0 * 0.5) * math.cos(0.5 * t),
                         math.radians(10.0 * 0.2) * math.cos(0.2 * t))
            lat = ORIGIN_LAT_LON[0] + pos[0] / M_PER_DEG_LAT
            lon = ORIGIN_LAT_LON[1] + pos[1] / (M_PER_DEG_LAT
                                                 * math.cos(math.radians(ORIGIN_LAT_LON[0])))
            return Ins(int(t * 1e9), ypr, rates, lat, lon, -pos[2], vel,
                       (0.2 * s(t), 0.1, -9.8), 2 | 4)
        if name == "rotor_speed":
            return RotorSpeed(150.0 + 2.0 * s(t), int(math.pi / 150.0 * 1e6),
                              int(t * 150.0 / math.pi), 0)
        if name == "tail_servo":
            return TailServo(1520 + int(50 * s(0.3 * t)), 1, 0)
        if name == "pilot_inputs":
            return PilotInputs((1500 + int(100 * s(t)), 1500 + int(80 * s(0.8 * t)),
                                1600 + int(50 * s(0.3 * t)), 1500, 1700), 0x1F, (0,) * 5)
        if name == "rtk_baseline":
            return RtkBaseline(int(t * 1000), (1000, 2000, -3000 + int(100 * s(t))), 10, 15,
                               14, 4)
        if name == "rtk_pos":
            return RtkPos(int(t * 1000), ORIGIN_LAT_LON[0], ORIGIN_LAT_LON[1], 8.0, 10, 15,
                          14, 4)
        if name == "rtk_vel":
            return RtkVel(int(t * 1000), (5000, 0, 0), 20, 40, 14, 1)
        if name == "gps_time":
            return GpsTime(2000, int(t * 1000), 0, 1)
        if name == "rtk_status":
            return RtkStatus(int(t * 40), 0, 0, 10, 14, 4)
        if name == "marker_attitude":
            los_tracker = -marker_position(t) / np.linalg.norm(marker_position(t))
            return MarkerAttitude((1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 1.0),
                                  tuple(MARKER_BODY_TO_TRACKER.T @ los_tracker), 3,
                                  marker_led(t), 20000, (0.0, 0.0, 0.0), 10)
        if name == "anemometer":
            return Anemometer((2.0 + 0.1 * s(3 * t), 0.3, -0.1), 20.0, 0)
        if name == "losa_peaks":
            return losa_peaks_at(marker_led_position(t))
        raise ValueError(f"fake board {self.name}: no content for '{name}'")


# The fake marker faces the tracker at a fixed attitude: body x (forward) -> tracker -z,
# body y -> tracker -x, body z (down) -> tracker +y (down). Columns: body axes in the
# tracker frame.
MARKER_BODY_TO_TRACKER = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])
FAKE_GRAVITY_TRACKER_M_S2 = np.array([0.0, 9.798, 0.0])  # = tracking.pose_ekf's default


def marker_position(t: float) -> np.ndarray:
    """The fake marker's centre path in the tracker frame (m)."""
    return np.array([0.3 * math.sin(0.5 * t), -0.2 + 0.1 * math.cos(0.3 * t), 2.5])


def marker_specific_force_body(t: float) -> np.ndarray:
    """What the marker's accelerometer reads on that path: R^T (a - g) (m/s^2)."""
    accel = np.array([-0.075 * math.sin(0.5 * t), -0.009 * math.cos(0.3 * t), 0.0])
    return MARKER_BODY_TO_TRACKER.T @ (accel - FAKE_GRAVITY_TRACKER_M_S2)


def marker_led(t: float) -> int:
    """The LED the fake marker lights (cycles every 2 s)."""
    return int(t / 2.0) % 4


def marker_led_position(t: float) -> np.ndarray:
    """Where LOSA sees the fake marker: its lit LED, tracker frame (m)."""
    return marker_position(t) + MARKER_BODY_TO_TRACKER @ (
        LED_RADIUS_M * LED_DIRECTIONS_BODY[marker_led(t)])


def losa_peaks_at(p: np.ndarray, intensity: int = 800) -> LosaPeaks:
    """Exact wire peaks of a point source (the inverse of `tracking.losa.triangulate`)."""
    g = DEFAULT_GEOMETRY
    centre, u, n, _ = g.module_frames()
    rel = p - centre
    us, ns = np.einsum("mk,mk->m", rel, u), np.einsum("mk,mk->m", rel, n)
    h = g.focal_height_m
    peak, slots, flags = [], [], []
    for m in range(4):
        best = None
        for slot in (0, -1, 1):
            s_u = -slot * g.slot_spacing_m
            u_img = s_u - (us[m] - s_u) * h / (ns[m] - h)
            px = u_img / g.pixel_pitch_m + (g.n_pixels - 1) / 2.0
            if -0.5 < px < g.n_pixels - 0.5:
                best = (px + WIRE_PIXELS * slot, slot)
                break
        if best is None:
            peak.append(0.0)
            slots.append(0)
            flags.append(0)
        else:
            peak.append(float(best[0]))
            slots.append(best[1])
            flags.append(1)
    return LosaPeaks(tuple(peak), tuple(intensity if f else 0 for f in flags), tuple(slots),
                     (2000,) * 4, tuple(flags))


class FakeBoard:
    """One port (a pty behind `run_dir/<name>`) with one or more origin boards on it."""

    def __init__(self, name: str, run_dir, sims: list[BoardSim], *, faults: Faults | None =
                 None, tick_s: float = 0.002) -> None:
        self.name = name
        self.link = Path(run_dir) / name
        self.sims = sims
        self.faults = faults or Faults()
        self.tick_s = tick_s
        self.rng = np.random.default_rng(self.faults.seed)
        self.injected = Injected()
        self.sent: list[tuple[int, int, int, int, int, str]] = []
        self.marker_commands: list = []
        self.sync_requests = 0
        self._lock = threading.RLock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._stalled_until = 0.0
        self._data_frames = 0
        self.partial_frames = 0
        self.master = self.slave = -1
        self.decoder = StreamDecoder()
        self.plugged = False
        self.replug()

    @classmethod
    def standard_set(cls, run_dir, faults: dict[str, Faults] | None = None,
                     drift_ppm: dict[str, float] | None = None) -> list[FakeBoard]:
        """losa, marker, base (carrying the rover's frames), as on the ship."""
        faults = faults or {}
        drift = {"losa": 20.0, "marker": -35.0, "rover": 50.0, "base": -10.0,
                 **(drift_ppm or {})}
        # the rover's clock wraps (2^32 us) 5 s after the start
        offsets = {"losa": 5_000_000, "marker": 123_456, "rover": (1 << 32) - 5_000_000,
                   "base": 77_000_000}
        sim = {n: BoardSim(n, drift_ppm=drift[n], clock_offset_us=offsets[n], boot_count=2)
               for n in ("losa", "marker", "rover", "base")}
        return [cls("losa", run_dir, [sim["losa"]], faults=faults.get("losa")),
                cls("marker", run_dir, [sim["marker"]], faults=faults.get("marker")),
                cls("base", run_dir, [sim["base"], sim["rover"]], faults=faults.get("base"))]

    # -- pty ----------------------------------------------------------------------

    def replug(self) -> None:
        """Create a fresh pty and point the symlink at it."""
        with self._lock:
            master, slave = os.openpty()
            for fd in (master, slave):
                tty.setraw(fd)
            os.set_blocking(master, False)
            tmp = self.link.with_name(f".{self.link.name}.tmp")
            if tmp.is_symlink() or tmp.exists():
                tmp.unlink()
            tmp.symlink_to(os.ttyname(slave))
            os.replace(tmp, self.link)
            self.master, self.slave = master, slave
            self.decoder = StreamDecoder()
            self.plugged = True

    def unplug(self) -> None:
        """Destroy the pty (the daemon sees end-of-file) and remove the symlink."""
        with self._lock:
            self.plugged = False
            for fd in (self.master, self.slave):
                if fd >= 0:
                    os.close(fd)
            self.master = self.slave = -1
            if self.link.is_symlink():
                self.link.unlink()

    def reboot(self) -> None:
        """Reset every board on this port: clock restarts, boot count + 1."""
        with self._lock:
            now = time.monotonic_ns() // 1000
            for s in self.sims:
                s.boot_count += 1
                s.boot(now)

    def stall(self, seconds: float) -> None:
        """Write and read nothing for `seconds` (a hung board or a saturated radio)."""
        self._stalled_until = time.monotonic() + seconds

    # -- running ----------------------------------------------------------------------

    def start(self) -> FakeBoard:
        """Boot every board on this port now and start sending."""
        now = time.monotonic_ns() // 1000
        for sim in self.sims:
            sim.boot(now)
        self._thread = threading.Thread(target=self._run, name=f"fake-{self.name}",
                                        daemon=True)
        self._thread.start()
        return self

    def halt(self) -> None:
        """Stop sending (the pty stays, so the daemon can read what is in flight)."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=5)

    def stop(self) -> None:
        self.halt()
        self.unplug()

    def _run(self) -> None:
        while not self._stop.is_set():
            with self._lock:
                self.step()
            time.sleep(self.tick_s)

    def step(self) -> None:
        """Generate everything due, apply faults, write; answer requests."""
        now_ns = time.monotonic_ns()
        mono_us = now_ns / 1000.0
        stalled = time.monotonic() < self._stalled_until
        out = bytearray()
        pieces = []  # (index in sent, end offset in out)
        for sim in self.sims:
            for msg, board_us, is_data in sim.due(mono_us):
                wire, seq = sim.frame(msg, board_us)
                mid = type(msg).MSG_ID
                state = "ok"
                if is_data and not stalled and self.plugged:
                    wire, state = self._corrupt(wire)
                if stalled or not self.plugged:
                    state = "unsent"
                else:
                    out += wire
                    pieces.append((len(self.sent), len(out), len(wire)))
                self.sent.append((now_ns, sim.origin, mid, seq, board_us & 0xFFFFFFFF, state))
        if out and not stalled and self.plugged:
            written = self._write(bytes(out))
            if written < len(out):
                for i, end, size in pieces:
                    if end > written:
                        state = "partial" if end - size < written else "unsent"
                        self.partial_frames += state == "partial"
                        self.sent[i] = self.sent[i][:5] + (state,)
        if not stalled and self.plugged:
            self._answer()

    def _corrupt(self, wire: bytes) -> tuple[bytes, str]:
        f = self.faults
        self._data_frames += 1
        k = self._data_frames
        body = bytearray(wire[1:-1])  # the COBS segment between the two delimiters
        state = "ok"
        if f.flip_every and k % f.flip_every == 0:
            i = int(self.rng.integers(len(body)))
            bit = int(self.rng.integers(8))
            if body[i] ^ (1 << bit) == 0:  # never create a delimiter
                bit = (bit + 1) % 8
            body[i] ^= 1 << bit
            state = "corrupt"
        elif f.drop_every and k % f.drop_every == 0:
            del body[int(self.rng.integers(len(body)))]
            state = "corrupt"
        out = b"\x00" + bytes(body) + b"\x00"
        if state == "corrupt":
            self.injected.bad_segments += 1
            self.injected.corrupted_frames += 1
            self.injected.bytes_dropped += len(body)
        if f.garbage_every and k % f.garbage_every == 0:
            junk = bytes(self.rng.integers(1, 256, int(self.rng.integers(1, 9)), dtype=np.uint8))
            out += junk + b"\x00"
            self.injected.bad_segments += 1
            self.injected.bytes_dropped += len(junk)
        return out, state

    def _write(self, data: bytes) -> int:
        """Write within 0.5 s; returns the bytes written."""
        view = memoryview(data)
        deadline = time.monotonic() + 0.5
        while view and time.monotonic() < deadline:
            try:
                view = view[os.write(self.master, view):]
            except BlockingIOError:
                select.select([], [self.master], [], 0.01)
            except OSError:
                break
        return len(data) - len(view)

    def _answer(self) -> None:
        # like the firmware: the receive time is taken before reading, so the bytes were
        # there by then (host_tx <= T(board_rx) holds, which the clock fit relies on)
        now_ns = time.monotonic_ns()
        try:
            data = os.read(self.master, 65536)
        except (BlockingIOError, OSError):
            return
        if not data:
            return
        rx_us = now_ns / 1000.0
        replies = bytearray()
        for f in self.decoder.feed(data):
            if f.name == "time_sync_request":
                self.sync_requests += 1
                for sim in self.sims:
                    b_rx = sim.board_us(rx_us)
                    b_tx = sim.board_us(time.monotonic_ns() / 1000.0)
                    wire, seq = sim.frame(sim.sync_reply(f.msg, b_rx, b_tx), b_tx)
                    replies += wire
                    self.sent.append((time.monotonic_ns(), sim.origin, 0x04, seq,
                                      b_tx & 0xFFFFFFFF, "ok"))
            elif f.name == "marker_command":
                self.marker_commands.append((now_ns, f.msg))
        if replies:
            self._write(bytes(replies))


def run_standard_set(run_dir, duration_s: float) -> None:
    """Run losa, marker and base (+rover) at full rates for duration_s (bench helper)."""
    boards = FakeBoard.standard_set(run_dir)
    for b in boards:
        b.start()
    try:
        time.sleep(duration_s)
    finally:
        for b in boards:
            b.stop()


if __name__ == "__main__":  # python -m airwake.daemon.fake_boards RUN_DIR SECONDS
    import sys

    run_standard_set(sys.argv[1], float(sys.argv[2]))
