"""Streaming frame decoder: bytes in any chunking → decoded frames, everything else counted.

`StreamDecoder.feed(chunk)` splits on 0x00, keeps the unfinished tail, COBS-decodes each
segment (C-accelerated `cobs`), checks length and CRC (`binascii.crc_hqx`) and unpacks
header and payload with one precompiled `struct.Struct`. Bad input never raises: each
non-empty segment is either a frame or one count in `errors` (docs/protocol.md,
"Receiving"). Sequence gaps are counted per (origin board, message).

One decoder per byte stream (per serial port). A port that carries forwarded frames
(the base) mixes origins; announced hashes and sequence numbers are kept per origin.
"""

from __future__ import annotations

from binascii import crc_hqx
from collections.abc import Callable
from typing import Any, NamedTuple

from cobs.cobs import DecodeError
from cobs.cobs import decode as cobs_decode

from airwake.link.framing import crc_seed
from airwake.link.messages import (
    BOARDS,
    BY_ID,
    FLAGS_ORIGIN_MASK,
    FRAME_OVERHEAD,
    HEARTBEAT,
    MAX_ENCODED_SIZE,
    SCHEMA_ENTRY,
    SCHEMA_HASH,
)

ERROR_KINDS = ("crc_error", "unknown_id", "def_mismatch", "oversize", "cobs_error")

# Per msg id: (raw frame length, CRC seed, frame_struct.unpack, record maker) or None.
_TABLE: list[tuple | None] = [None] * 256
for _m in BY_ID.values():
    _TABLE[_m.id] = (_m.raw_frame_size, _m.crc_seed, _m.frame_struct.unpack, _m.from_frame)
_CONTROL_IDS = (HEARTBEAT.id, SCHEMA_ENTRY.id)
assert max(_CONTROL_IDS) < 3  # feed() tests `msg_id < 3` to find them cheaply


class Frame(NamedTuple):
    """One decoded frame: header fields and the message record."""

    msg_id: int
    seq: int
    flags: int
    board_time_us: int
    msg: Any

    @property
    def origin(self) -> int:
        """Board id of the frame's origin (flags bits 0-2)."""
        return self.flags & FLAGS_ORIGIN_MASK

    @property
    def name(self) -> str:
        return BY_ID[self.msg_id].name


def board_label(origin: int) -> str:
    return f"{BOARDS.get(origin, 'board')} ({origin})"


def classify_bad(raw: bytes | None, announced: dict[tuple[int, int], int]) -> str:
    """Error kind of a segment that did not decode (rules 2, 3, 5, 6 of the spec)."""
    if raw is None or len(raw) < FRAME_OVERHEAD:
        return "cobs_error"
    info = BY_ID.get(raw[0])
    if info is None:
        return "unknown_id"
    other = announced.get((raw[2] & FLAGS_ORIGIN_MASK, raw[0]))
    if other is not None and other != info.def_hash and \
            crc_hqx(raw[:-2], crc_seed(other)) == int.from_bytes(raw[-2:], "little"):
        return "def_mismatch"
    return "crc_error"


class StreamDecoder:
    """Decode one byte stream fed in chunks of any size.

    on_reject(kind, segment): optional; called with the encoded bytes of every segment
    that was not decoded (e.g. to keep definition-mismatch frames for the recorder).
    """

    def __init__(self, on_reject: Callable[[str, bytes], None] | None = None) -> None:
        self.on_reject = on_reject
        self.frame_counts = [0] * 256
        self.errors = dict.fromkeys(ERROR_KINDS, 0)
        self.bytes_total = 0
        self.bytes_dropped = 0
        # (origin, msg_id) -> hash the origin announced in schema_entry
        self.announced: dict[tuple[int, int], int] = {}
        # origin -> latest heartbeat record
        self.heartbeats: dict[int, Any] = {}
        self._last_seq = [-1] * 2048  # index origin << 8 | msg_id
        self._lost = [0] * 2048
        self._tail = b""
        self._oversize_run = 0  # bytes of an oversize segment whose delimiter is pending

    @property
    def pending_bytes(self) -> int:
        """Bytes of the unfinished last segment."""
        return len(self._tail) + self._oversize_run

    def _reject(self, kind: str, seg: bytes, length: int | None = None) -> None:
        self.errors[kind] += 1
        self.bytes_dropped += len(seg) if length is None else length
        if self.on_reject is not None:
            self.on_reject(kind, seg)

    def _split(self, chunk: bytes) -> list[bytes]:
        """Complete segments of tail + chunk; the rest becomes the new tail."""
        if self._tail:
            chunk = self._tail + chunk
        parts = chunk.split(b"\x00")
        tail = parts.pop()
        if self._oversize_run:
            if parts:  # the oversize segment ends at the first delimiter of this chunk
                self._reject("oversize", parts[0][:64], self._oversize_run + len(parts[0]))
                parts[0] = b""
                self._oversize_run = 0
            else:
                self._oversize_run += len(tail)
                tail = b""
        if len(tail) > MAX_ENCODED_SIZE:
            self._oversize_run = len(tail)
            tail = b""
        self._tail = tail
        return parts

    def feed(self, chunk: bytes | bytearray | memoryview) -> list[Frame]:
        """Decode every frame completed by `chunk`; never raises on bad bytes."""
        if type(chunk) is not bytes:
            chunk = bytes(chunk)
        self.bytes_total += len(chunk)
        out: list[Frame] = []
        append = out.append
        table = _TABLE
        counts = self.frame_counts
        last_seq = self._last_seq
        lost = self._lost
        new = tuple.__new__
        for seg in self._split(chunk):
            if not seg:
                continue
            raw = None
            try:
                raw = cobs_decode(seg)
                size, seed, unpack, make = table[raw[0]]
            except (DecodeError, IndexError, TypeError):  # not COBS, empty, unknown id
                self._reject_segment(seg, raw)
                continue
            if len(raw) != size or len(seg) > MAX_ENCODED_SIZE:
                self._reject_segment(seg, raw)
                continue
            v = unpack(raw)
            if crc_hqx(raw[:-2], seed) != v[-1]:
                self._reject_segment(seg, raw)
                continue
            msg_id = v[0]
            counts[msg_id] += 1
            key = (v[2] & FLAGS_ORIGIN_MASK) << 8 | msg_id
            gap = (v[1] - last_seq[key] - 1) & 0xFF
            if gap and last_seq[key] >= 0:
                lost[key] += gap
            last_seq[key] = v[1]
            frame = new(Frame, (msg_id, v[1], v[2], v[3], make(v)))
            if msg_id < 3:
                self._control(frame)
            append(frame)
        return out

    def _reject_segment(self, seg: bytes, raw: bytes | None) -> None:
        if len(seg) > MAX_ENCODED_SIZE:
            self._reject("oversize", seg)
        else:
            self._reject(classify_bad(raw, self.announced), seg)

    def _control(self, frame: Frame) -> None:
        origin = frame.flags & FLAGS_ORIGIN_MASK
        if frame.msg_id == SCHEMA_ENTRY.id:
            self.announced[(origin, frame.msg.msg_id)] = frame.msg.def_hash
        elif frame.msg_id == HEARTBEAT.id:
            self.heartbeats[origin] = frame.msg

    # ---- reporting ----

    @property
    def frames_ok(self) -> int:
        return sum(self.frame_counts)

    def lost_frames(self) -> dict[str, int]:
        """Frames missing from sequence gaps, per message name (all origins)."""
        out: dict[str, int] = {}
        for key, n in enumerate(self._lost):
            if n:
                name = BY_ID[key & 0xFF].name
                out[name] = out.get(name, 0) + n
        return out

    def counters(self) -> dict:
        """{"frames": {name: n}, "errors": {kind: n, "bytes_dropped", "seq_lost"}, "bytes": N}"""
        lost = self.lost_frames()
        return {
            "frames": {BY_ID[i].name: n for i, n in enumerate(self.frame_counts) if n},
            "errors": {**self.errors, "bytes_dropped": self.bytes_dropped,
                       "seq_lost": sum(lost.values())},
            "lost": lost,
            "bytes": self.bytes_total,
        }

    def schema_problems(self) -> list[str]:
        """One line per board whose schema differs from ours, naming the messages."""
        problems = []
        origins = set(self.heartbeats) | {o for o, _ in self.announced}
        for origin in sorted(origins):
            differing = sorted(
                BY_ID[i].name if i in BY_ID else f"id 0x{i:02X} (unknown here)"
                for (o, i), h in self.announced.items()
                if o == origin and (i not in BY_ID or h != BY_ID[i].def_hash))
            hb = self.heartbeats.get(origin)
            if hb is not None and hb.schema_hash != SCHEMA_HASH:
                problems.append(
                    f"schema mismatch with board {board_label(origin)}: its schema hash "
                    f"0x{hb.schema_hash:08X}, ours 0x{SCHEMA_HASH:08X} (firmware "
                    f"{hb.fw_version_major}.{hb.fw_version_minor}.{hb.fw_version_patch}); "
                    f"differing messages: {', '.join(differing) or 'not announced yet'}")
            elif differing:
                problems.append(f"board {board_label(origin)} announces different definitions "
                                f"of: {', '.join(differing)}")
        return problems
