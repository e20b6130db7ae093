"""The SIL links: pty host ports and link impairments counted exactly.

A board's host link is a pty (`PtyPort`: raw mode on both ends, our slave fd held
open, a stable symlink the daemon opens like /dev/ttyACM0, unplug = the pty destroyed
and the symlink removed, replug = a new pty behind the same symlink). The simulator
relays the bytes each board sends (`UART_TX` records of a port mapped to `sim`) through
an `Impairment` before writing them to the pty, so faults are applied where they can be
injected deterministically and counted exactly.

`Impairment` drops bytes (probability per byte), flips bits (probability per bit) and
cuts the link for outages (stall, unplug: every byte of the window dropped), and keeps an
exact account of what the receiver will see. Frames are the byte runs between 0x00
delimiters (COBS framing); a receiver splitting the delivered stream on 0x00 sees each
non-empty run ("segment") either as a frame a board sent — its bytes exactly — or as
one segment to reject. The account, from the injector's side (no decoding):

- `bad_segments`: delivered runs that are not a frame a board sent — the receiver's
  error count (CRC, COBS, unknown id, oversize: one each), barring a corrupted run that
  happens to pass the CRC-16 (~1 in 65536);
- `frames_in` / `frames_intact`: frames that entered the link / left it intact;
- `bytes_lost`, `bits_flipped`, `bytes_cut` (outages): what was injected.

Chains: the rover's frames reach the host through the base, which forwards every
segment of its rover port as one segment (`0x00 seg 0x00`), in pieces of at most
`BASE_FORWARD_MAX` bytes. The rover link's bad runs (split like the forwarder does)
go into `bad_out`, a multiset the base link takes as `upstream_bad` (a run that reaches
the base already bad is not a frame the base sent), and the rover link publishes the
frames the rover sent into the base link's `valid` set (`publish_valid`). Segments cut
by a board reset (the board drops the rest of a frame it was sending) are marked with
`cut_open_segment()`.

With `log_frames`, every frame's identity (origin, msg_id, seq, board_time_us: the
frame header) is logged as it enters the link (`sent`, with `touched` = any of its
bytes or delimiters impaired) and as it is delivered intact (`delivered`).
"""

from __future__ import annotations

import errno
import fcntl
import itertools
import os
import select
import struct
import termios
import time
import tty
from collections import Counter
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from cobs.cobs import DecodeError
from cobs.cobs import decode as cobs_decode

# The base's forwarder passes a longer rover segment on in pieces of this many bytes
# (firmware/boards/base: seg[1 + AW_MAX_ENCODED_SIZE + 1], flushed when full).
BASE_FORWARD_MAX = 270
_HEADER = struct.Struct("<BBBI")  # msg_id, seq, flags, board_time_us


def frame_identity(segment: bytes) -> tuple[int, int, int, int] | None:
    """(origin, msg_id, seq, board_time_us) from an encoded frame, None if not COBS."""
    try:
        raw = cobs_decode(segment)
    except DecodeError:
        return None
    if len(raw) < _HEADER.size:
        return None
    msg_id, seq, flags, t = _HEADER.unpack_from(raw)
    return flags & 0x07, msg_id, seq, t


@dataclass
class LinkCounters:
    """What one link's impairment did (see module doc)."""

    bytes_in: int = 0
    bytes_out: int = 0
    bytes_lost: int = 0
    bits_flipped: int = 0
    bytes_cut: int = 0
    frames_in: int = 0
    frames_intact: int = 0
    bad_segments: int = 0
    upstream_bad_in: int = 0
    reset_cuts: int = 0

    def to_dict(self) -> dict:
        return asdict(self)


class FrameSet:
    """A multiset of frame contents (encoded, between delimiters) with a bounded memory:
    the oldest entries go first (a frame is delivered within a few steps or never)."""

    def __init__(self, limit: int = 50_000) -> None:
        self.limit = limit
        self._c: Counter = Counter()

    def add(self, seg: bytes) -> None:
        self._c[seg] += 1
        if len(self._c) > self.limit:
            for k in list(itertools.islice(self._c, len(self._c) - self.limit // 2)):
                del self._c[k]

    def take(self, seg: bytes) -> bool:
        """Remove one `seg`; False if there is none."""
        n = self._c.get(seg, 0)
        if n <= 0:
            return False
        if n == 1:
            del self._c[seg]
        else:
            self._c[seg] = n - 1
        return True


class Impairment:
    """Byte loss, bit flips and outages on one direction of one link, counted exactly.

    `feed(data, t_us, outage)` returns the bytes to deliver. The random draws use `rng`
    in feed order, so a stepped run (same chunks) injects the same faults.

    A delivered run is a valid frame when its bytes are exactly a frame some board sent
    (`valid`: the frames that entered this link and, on a chain, those that entered the
    links upstream, which publish them here through `publish_valid`): exactly when the
    receiver accepts it, even for a frame that reached this link inside a run corrupted
    upstream and had the rest of that run cut off here. Every other non-empty run is
    one receiver error.
    """

    def __init__(self, name: str, *, loss_probability: float = 0.0,
                 flip_probability: float = 0.0, rng: np.random.Generator | None = None,
                 upstream_bad: Counter | None = None, piece_max: int | None = None,
                 log_frames: bool = False) -> None:
        if not 0.0 <= loss_probability <= 1.0 or not 0.0 <= flip_probability <= 1.0:
            raise ValueError(f"link {name}: probabilities must be in [0, 1]")
        self.name = name
        self.loss_p = float(loss_probability)
        self.flip_p = float(flip_probability)
        self.rng = rng if rng is not None else np.random.default_rng(0)
        self.upstream_bad = upstream_bad
        self.piece_max = piece_max
        self.log_frames = log_frames
        self.counters = LinkCounters()
        self.valid = FrameSet()  # what a delivered run may be (class doc)
        self.publish_valid: list[FrameSet] = []  # downstream links' `valid`
        self.bad_out: Counter = Counter()  # bad runs as the next hop receives them
        self.sent: list[tuple] = []  # (t_us, identity, touched)
        self.delivered: list[tuple] = []  # (t_us, identity)
        self._in_open = bytearray()
        self._in_cut = False  # the open input segment was cut by a board reset
        self._in_touched = False  # any byte of the open input segment impaired
        self._prev_delim_touched = False
        self._out = bytearray()  # the delivered run since the last delivered 0x00

    @property
    def impaired(self) -> bool:
        return self.loss_p > 0.0 or self.flip_p > 0.0

    # -- the stream ---------------------------------------------------------------

    def feed(self, data: bytes, t_us: int = 0, outage: bool = False) -> bytes:
        """Impair one chunk (bytes the board sent at t_us); return what is delivered."""
        n = len(data)
        if n == 0:
            return b""
        c = self.counters
        c.bytes_in += n
        if outage:
            keep = np.zeros(n, dtype=bool)
            c.bytes_cut += n
        elif self.loss_p > 0.0:
            keep = self.rng.random(n) >= self.loss_p
            c.bytes_lost += n - int(keep.sum())
        else:
            keep = None
        flip = None
        if self.flip_p > 0.0 and not outage:
            k = int(self.rng.binomial(8 * n, self.flip_p))
            if k:
                bits = self.rng.choice(8 * n, size=k, replace=False)
                flip = np.zeros(n, dtype=np.uint8)
                np.bitwise_xor.at(flip, bits >> 3, (1 << (bits & 7)).astype(np.uint8))
                if keep is not None:
                    flip[~keep] = 0
                c.bits_flipped += int(np.unpackbits(flip).sum())
        if keep is None and flip is None:
            self._input(data, None, t_us)
            out = data
        else:
            b = np.frombuffer(data, dtype=np.uint8)
            touched = np.zeros(n, dtype=bool)
            vals = b
            if flip is not None:
                touched |= flip != 0
                vals = b ^ flip
            if keep is not None:
                touched |= ~keep
                vals = vals[keep]
            self._input(data, touched, t_us)
            out = vals.tobytes()
        self._output(out, t_us)
        c.bytes_out += len(out)
        return out

    def _input(self, data: bytes, touched: np.ndarray | None, t_us: int) -> None:
        """Close the input segments this chunk completes (the frames the board sent)."""
        parts = data.split(b"\x00")
        if touched is None:
            for part in parts[:-1]:
                self._in_open += part
                self._close_input(t_us, self._in_touched or self._prev_delim_touched)
                self._prev_delim_touched = False
        else:
            pos = 0
            for part in parts[:-1]:
                end = pos + len(part)
                self._in_open += part
                seg_touched = self._in_touched or bool(touched[pos:end].any())
                delim = bool(touched[end])
                self._close_input(t_us, seg_touched or delim or self._prev_delim_touched)
                self._prev_delim_touched = delim
                pos = end + 1
            if touched[pos:].any():
                self._in_touched = True
        self._in_open += parts[-1]

    def _close_input(self, t_us: int, touched: bool) -> None:
        seg = bytes(self._in_open)
        cut = self._in_cut
        self._in_open = bytearray()
        self._in_touched = False
        self._in_cut = False
        if not seg:
            return
        c = self.counters
        c.frames_in += 1
        if self.upstream_bad is not None and self.upstream_bad.get(seg, 0) > 0:
            self.upstream_bad[seg] -= 1  # bad already when it reached this link
            c.upstream_bad_in += 1
            return
        if cut:
            return
        self.valid.add(seg)
        for v in self.publish_valid:
            v.add(seg)
        if self.log_frames:
            ident = frame_identity(seg)
            if ident is not None:
                self.sent.append((t_us, ident, touched))

    def _output(self, out: bytes, t_us: int) -> None:
        parts = out.split(b"\x00")
        for part in parts[:-1]:
            self._out += part
            self._finish_run(bytes(self._out), t_us)
            self._out = bytearray()
        self._out += parts[-1]

    def _finish_run(self, seg: bytes, t_us: int) -> None:
        if not seg:
            return
        c = self.counters
        if self.valid.take(seg):
            c.frames_intact += 1
            if self.log_frames:
                ident = frame_identity(seg)
                if ident is not None:
                    self.delivered.append((t_us, ident))
            return
        c.bad_segments += 1
        step = self.piece_max or len(seg)
        for i in range(0, len(seg), step):
            self.bad_out[seg[i:i + step]] += 1

    def cut_open_segment(self) -> None:
        """The board reset while sending: the frame it was sending is cut short, so the
        segment now open (if it has bytes) can never be a valid frame."""
        if self._in_open:
            self._in_cut = True
            self.counters.reset_cuts += 1

    def summary(self) -> dict:
        d = self.counters.to_dict()
        d.update({"loss_probability": self.loss_p, "flip_probability": self.flip_p})
        return d


# ---------------------------------------------------------------------------
# pty host ports
# ---------------------------------------------------------------------------


class PtyPort:
    """A board's host port: a raw pty pair behind a stable symlink.

    Bytes for the host are queued (`send`) and written without blocking (`flush`); the
    host's bytes are read from the master (`receive`). `unplug()` destroys the pty and
    removes the symlink; `replug()` creates a new pty behind the same symlink."""

    def __init__(self, link: Path) -> None:
        self.link = Path(link)
        self.master = -1
        self.slave = -1
        self.pending = bytearray()
        self.plugged = False
        self.replugs = 0
        self.bytes_written = 0
        self.log: list[tuple[int, int]] = []  # (wall ns, cumulative bytes) per write
        self.keep: bytearray | None = None  # everything written, when asked to keep it
        self.replug()

    @property
    def device(self) -> str:
        return os.ttyname(self.slave) if self.slave >= 0 else ""

    def replug(self) -> None:
        self.master, self.slave = os.openpty()
        for fd in (self.master, self.slave):
            tty.setraw(fd, termios.TCSANOW)
        os.set_blocking(self.master, False)
        tmp = self.link.with_name(f".{self.link.name}.new")
        if tmp.is_symlink() or tmp.exists():
            tmp.unlink()
        os.symlink(os.ttyname(self.slave), tmp)
        os.replace(tmp, self.link)
        self.plugged = True
        self.replugs += 1

    def unplug(self) -> None:
        """Destroy the pty (the host's reads fail) and remove the symlink."""
        self.plugged = False
        self.pending.clear()
        if self.link.is_symlink():
            self.link.unlink()
        for fd in (self.master, self.slave):
            if fd >= 0:
                try:
                    os.close(fd)
                except OSError:
                    pass
        self.master = self.slave = -1

    def send(self, data: bytes) -> None:
        if self.plugged and data:
            self.pending += data

    def flush(self) -> int:
        """Write what the pty takes now; returns bytes still pending."""
        while self.pending and self.plugged:
            try:
                n = os.write(self.master, self.pending)
            except BlockingIOError:
                break
            except OSError as exc:
                if exc.errno == errno.EINTR:
                    continue
                raise
            if self.keep is not None:
                self.keep += self.pending[:n]
            del self.pending[:n]
            self.bytes_written += n
            self.log.append((time.monotonic_ns(), self.bytes_written))
        return len(self.pending)

    def wait_writable(self, timeout_s: float) -> bool:
        if not self.plugged:
            return False
        _, w, _ = select.select([], [self.master], [], timeout_s)
        return bool(w)

    def receive(self) -> bytes:
        """Everything the host wrote since the last call."""
        if not self.plugged:
            return b""
        chunks = []
        while True:
            try:
                chunk = os.read(self.master, 65536)
            except (BlockingIOError, InterruptedError):
                break
            except OSError:
                break
            if not chunk:
                break
            chunks.append(chunk)
        return b"".join(chunks)

    def unread(self) -> int:
        """Bytes written to the pty that the host has not read yet (the slave's input
        queue; `pending` bytes are not written yet)."""
        if not self.plugged:
            return 0
        buf = fcntl.ioctl(self.slave, termios.FIONREAD, b"\0\0\0\0")
        return struct.unpack("i", buf)[0]

    def close(self) -> None:
        self.unplug()
