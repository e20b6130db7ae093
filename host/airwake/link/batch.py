"""Batch decoding of whole captures into numpy structured arrays, one per message type.

The same classification and counters as `StreamDecoder` (docs/protocol.md, "Receiving"),
without building a Python object per frame: valid raw frames are grouped by id, joined
and viewed through a packed numpy dtype, then copied into an aligned table with header
columns (`byte_offset` of the frame's segment in the capture, `seq`, `flags`, `origin`,
`board_time_us`) followed by the payload fields (arrays as sub-array columns).
"""

from __future__ import annotations

from binascii import crc_hqx
from dataclasses import dataclass, field

import numpy as np
from cobs.cobs import DecodeError
from cobs.cobs import decode as cobs_decode

from airwake.link.decoder import ERROR_KINDS, classify_bad
from airwake.link.messages import (
    BY_ID,
    FLAGS_ORIGIN_MASK,
    MAX_ENCODED_SIZE,
    SCHEMA_ENTRY,
    MessageInfo,
)

# raw-frame header columns are prefixed so payload fields (schema_entry.msg_id) never clash
_HEADER_DESCR = [("_msg_id", "u1"), ("_seq", "u1"), ("_flags", "u1"), ("_board_time_us", "<u4")]
_TABLE_HEADER = [("byte_offset", "<i8"), ("seq", "u1"), ("flags", "u1"), ("origin", "u1"),
                 ("board_time_us", "<u4")]


def frame_dtype(info: MessageInfo) -> np.dtype:
    """Packed dtype of one raw (COBS-decoded) frame of this message."""
    return np.dtype(_HEADER_DESCR + list(info.dtype_descr) + [("_crc", "<u2")])


def table_dtype(info: MessageInfo) -> np.dtype:
    """Aligned dtype of the decoded table: header columns, then payload fields."""
    return np.dtype(_TABLE_HEADER + list(info.dtype_descr), align=True)


@dataclass
class Capture:
    """A decoded capture: tables by message name plus the stream counters."""

    tables: dict[str, np.ndarray]
    errors: dict[str, int]
    bytes: int
    pending_bytes: int
    lost: dict[str, int] = field(default_factory=dict)

    def counters(self) -> dict:
        """Same shape as StreamDecoder.counters()."""
        return {
            "frames": {name: len(t) for name, t in self.tables.items()},
            "errors": {**self.errors, "seq_lost": sum(self.lost.values())},
            "lost": self.lost,
            "bytes": self.bytes,
        }


def _seq_lost(seq: np.ndarray, origin: np.ndarray) -> int:
    lost = 0
    for o in np.unique(origin):
        s = seq[origin == o].astype(np.int64)
        lost += int(((s[1:] - s[:-1] - 1) % 256).sum())
    return lost


def decode_capture(data: bytes) -> Capture:
    """Decode a whole capture; the unfinished last segment counts as pending bytes."""
    segments = bytes(data).split(b"\x00")
    pending = len(segments.pop())
    errors = dict.fromkeys(ERROR_KINDS, 0)
    dropped = 0
    announced: dict[tuple[int, int], int] = {}
    checks = {m.id: (m.raw_frame_size, m.crc_seed) for m in BY_ID.values()}
    raws: dict[int, list[bytes]] = {i: [] for i in checks}
    offsets: dict[int, list[int]] = {i: [] for i in checks}
    pos = 0
    for seg in segments:
        start = pos
        pos += len(seg) + 1
        if not seg:
            continue
        kind = None
        if len(seg) > MAX_ENCODED_SIZE:
            kind = "oversize"
        else:
            raw, size, seed = None, -1, 0
            try:
                raw = cobs_decode(seg)
                size, seed = checks[raw[0]]
            except (DecodeError, IndexError, KeyError):
                pass
            if size > 0 and len(raw) == size and \
                    crc_hqx(raw[:-2], seed) == int.from_bytes(raw[-2:], "little"):
                raws[raw[0]].append(raw)
                offsets[raw[0]].append(start)
                if raw[0] == SCHEMA_ENTRY.id:
                    entry = SCHEMA_ENTRY.unpack(raw[7:-2])
                    announced[(raw[2] & FLAGS_ORIGIN_MASK, entry.msg_id)] = entry.def_hash
                continue
            kind = classify_bad(raw, announced)
        errors[kind] += 1
        dropped += len(seg)
    tables, lost = {}, {}
    for msg_id, frames in raws.items():
        if not frames:
            continue
        info = BY_ID[msg_id]
        packed = np.frombuffer(b"".join(frames), dtype=frame_dtype(info))
        table = np.empty(len(packed), dtype=table_dtype(info))
        table["byte_offset"] = offsets[msg_id]
        table["origin"] = packed["_flags"] & FLAGS_ORIGIN_MASK
        for name in ("seq", "flags", "board_time_us"):
            table[name] = packed["_" + name]
        for name, *_ in info.dtype_descr:
            table[name] = packed[name]
        tables[info.name] = table
        n_lost = _seq_lost(table["seq"], table["origin"])
        if n_lost:
            lost[info.name] = n_lost
    errors["bytes_dropped"] = dropped
    return Capture(tables, errors, len(data), pending, lost)
