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
non-empty run ("segment") either as exactly one frame the board sent — *intact*: all its
bytes delivered unchanged, nothing else in the run — or as one segment to reject.
Counting that from the masks (no decoding) gives, per link:

- `bad_segments`: non-empty delivered runs that are not an intact valid frame — exactly
  the receiver's error count (CRC, COBS, unknown id, oversize... one each);
- `frames_in` / `frames_intact`: frames the board sent / delivered intact;
- `bytes_lost`, `bits_flipped`, `bytes_cut` (outages): what was injected.

Chains: the rover's frames reach the host through the base, which forwards every
segment of its rover port as one segment (`0x00 seg 0x00`), in pieces of at most
`BASE_FORWARD_MAX` bytes. The rover link's bad runs (split like the forwarder does)
go into `bad_out`, a multiset the base link takes as `upstream_bad`: a segment
that reaches the base link already bad and crosses it untouched is still one error for
the receiver. Segments cut by a board reset (the board drops the rest of a frame it
was sending) are marked with `cut_open_segment()`.

With `log_frames`, every frame's identity (origin, msg_id, seq, board_time_us: the
frame header) is logged as it enters the link (`sent`, with `touched` = any of its
bytes or delimiters impaired) and as it is delivered intact (`delivered`).
"""

from __future__ import annotations

import errno
import fcntl
import os
import select
import struct
import termios
import time
import tty
from collections import Counter
from dataclasses import asdict, dataclass, field
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
    upstream_bad_passed: int = 0
    reset_cuts: int = 0

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass
class _OutRun:
    """The delivered run being assembled (bytes since the last delivered 0x00)."""

    data: bytearray = field(default_factory=bytearray)
    clean: bool = True
    src: int = -2  # input segment of every byte so far; -2 none yet, -1 mixed


class Impairment:
    """Byte loss, bit flips and outages on one direction of one link, counted exactly.

    `feed(data, outage)` returns the bytes to deliver. The random draws use `rng` in
    feed order, so a stepped run (same chunks) injects the same faults.
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
        self.bad_out: Counter = Counter()  # bad runs as the next hop receives them
        self.sent: list[tuple] = []  # (t_us, identity, touched)
        self.delivered: list[tuple] = []  # (t_us, identity)
        self._seg = 0  # index of the open input segment
        self._in_open = bytearray()
        self._in_touched = False  # any byte of the open input segment impaired
        self._prev_delim_touched = False
        self._in_len: dict[int, int] = {}
        self._in_bad: set[int] = set()
        self._out = _OutRun()

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
        b = np.frombuffer(data, dtype=np.uint8)
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
            self._feed_clean(data, t_us)
            c.bytes_out += n
            return data
        src = self._src_index(b)  # before the input accounting advances self._seg
        self._account_input(b, keep, flip, t_us)
        touched = np.zeros(n, dtype=bool)
        vals = b
        if flip is not None:
            vals = b ^ flip
            touched |= flip != 0
        if keep is not None:
            touched |= ~keep
            vals, src, clean = vals[keep], src[keep], ~touched[keep]
        else:
            clean = ~touched
        out = vals.tobytes()
        self._account_output(np.frombuffer(out, np.uint8), clean, src, t_us)
        c.bytes_out += len(out)
        return out

    def _feed_clean(self, data: bytes, t_us: int) -> None:
        """`feed` for a chunk with nothing impaired: output = input, segment by segment."""
        parts = data.split(b"\x00")
        for part in parts[:-1]:
            j = self._seg
            self._in_open += part
            touched = self._in_touched or self._prev_delim_touched
            self._close_input(t_us, touched)
            self._prev_delim_touched = False
            if part:
                self._extend_clean(self._out, part, j)
            self._finish_run(self._out, t_us)
            self._out = _OutRun()
        last = parts[-1]
        if last:
            self._in_open += last
            self._extend_clean(self._out, last, self._seg)
        if len(self._in_len) > 256:
            r = self._out
            low = r.src if r.src >= 0 else self._seg
            for j in [j for j in self._in_len if j < low]:
                del self._in_len[j]
            self._in_bad = {j for j in self._in_bad if j >= low}

    @staticmethod
    def _extend_clean(r: _OutRun, part: bytes, j: int) -> None:
        r.data += part
        if r.src == -2:
            r.src = j
        elif r.src != j:
            r.src = -1

    def _src_index(self, b: np.ndarray) -> np.ndarray:
        """Input segment index of each byte of the chunk (a delimiter closes its segment)."""
        z = (b == 0).astype(np.int64)
        return self._seg + np.cumsum(z) - z

    def _account_input(self, b: np.ndarray, keep, flip, t_us: int) -> None:
        """Segment lengths, contents, upstream-bad marks and (for logs) touched flags;
        advances `_seg` past every delimiter of the chunk."""
        bad = np.zeros(b.size, dtype=bool)
        if keep is not None:
            bad |= ~keep
        if flip is not None:
            bad |= flip != 0
        data = b.tobytes()
        start = 0
        for z in np.flatnonzero(b == 0):
            z = int(z)
            self._in_open += data[start:z]
            delim_touched = bool(bad[z])
            touched = (self._in_touched or bool(bad[start:z].any()) or delim_touched
                       or self._prev_delim_touched)
            self._close_input(t_us, touched)
            self._prev_delim_touched = delim_touched
            start = z + 1
        self._in_open += data[start:]
        self._in_touched = self._in_touched or bool(bad[start:].any())

    def _close_input(self, t_us: int, touched: bool) -> None:
        seg = bytes(self._in_open)
        j = self._seg
        self._in_len[j] = len(seg)
        if seg:
            self.counters.frames_in += 1
            if self.upstream_bad is not None and self.upstream_bad.get(seg, 0) > 0:
                self.upstream_bad[seg] -= 1
                self._in_bad.add(j)
            elif self.log_frames and j not in self._in_bad:
                ident = frame_identity(seg)
                if ident is not None:
                    self.sent.append((t_us, ident, touched))
        self._in_open = bytearray()
        self._in_touched = False
        self._seg += 1

    def _account_output(self, out: np.ndarray, clean: np.ndarray, src: np.ndarray,
                        t_us: int) -> None:
        r = self._out
        data = out.tobytes()
        start = 0
        for z in np.flatnonzero(out == 0):
            z = int(z)
            self._extend(r, data, clean, src, start, z)
            self._finish_run(r, t_us)
            r = self._out = _OutRun()
            start = z + 1
        self._extend(r, data, clean, src, start, len(data))
        # forget input segments no delivered run can still be an intact copy of
        if len(self._in_len) > 256:
            low = r.src if r.src >= 0 else self._seg
            for j in [j for j in self._in_len if j < low]:
                del self._in_len[j]
            self._in_bad = {j for j in self._in_bad if j >= low}

    @staticmethod
    def _extend(r: _OutRun, data: bytes, clean: np.ndarray, src: np.ndarray, a: int,
                b: int) -> None:
        if b <= a:
            return
        r.data += data[a:b]
        if r.clean and not bool(clean[a:b].all()):
            r.clean = False
        s0, s1 = int(src[a]), int(src[b - 1])
        if r.src == -2:
            r.src = s0 if s0 == s1 else -1
        elif r.src != s0 or s0 != s1:
            r.src = -1

    def _finish_run(self, r: _OutRun, t_us: int) -> None:
        if not r.data:
            return
        c = self.counters
        seg = bytes(r.data)
        intact = (r.clean and r.src >= 0 and self._in_len.get(r.src) == len(seg))
        if intact and r.src not in self._in_bad:
            c.frames_intact += 1
            if self.log_frames:
                ident = frame_identity(seg)
                if ident is not None:
                    self.delivered.append((t_us, ident))
            return
        c.bad_segments += 1
        if intact:
            c.upstream_bad_passed += 1
        step = self.piece_max or len(seg)
        for i in range(0, len(seg), step):
            self.bad_out[seg[i:i + step]] += 1

    def cut_open_segment(self) -> None:
        """The board reset while sending: the frame it was sending is cut short, so the
        segment now open (if it has bytes) can never be a valid frame."""
        if self._in_open:
            self._in_bad.add(self._seg)
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
