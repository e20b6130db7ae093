"""Batch decoding of whole captures into numpy structured arrays, one per message type.

The same classification and counters as `StreamDecoder` (docs/protocol.md, "Receiving"),
without building a Python object per frame: valid raw frames are grouped by id, joined
and viewed through a packed numpy dtype, then copied into an aligned table with header
columns (`byte_offset` of the frame's segment in the capture, `seq`, `flags`, `origin`,
`board_time_us`) followed by the payload fields (arrays as sub-array columns).
"""

from __future__ import annotations

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


def _crc_table() -> np.ndarray:
    table = np.zeros(256, dtype=np.uint16)
    for i in range(256):
        crc = i << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else crc << 1
        table[i] = crc & 0xFFFF
    return table


_CRC_TABLE = _crc_table()


def crc16_rows(rows: np.ndarray, seed: int) -> np.ndarray:
    """CRC-16/CCITT-FALSE body of every row of a (N, L) uint8 array, from `seed`.

    One vectorised table step per byte column: L numpy operations for N frames.
    """
    crc = np.full(len(rows), seed, dtype=np.uint16)
    for column in rows.T:
        crc = (crc << 8) ^ _CRC_TABLE[(crc >> 8) ^ column]
    return crc


def _seq_lost(seq: np.ndarray, origin: np.ndarray) -> int:
    lost = 0
    for o in np.unique(origin):
        s = seq[origin == o].astype(np.int64)
        lost += int(((s[1:] - s[:-1] - 1) % 256).sum())
    return lost


def decode_capture(data: bytes) -> Capture:
    """Decode a whole capture; the unfinished last segment counts as pending bytes.

    Pass 1 (Python loop, C calls only): split, COBS-decode, check id and length.
    Pass 2 (numpy, per message): CRC of every candidate frame at once. Pass 3: the
    few bad segments are classified in stream order, with the schema_entry
    announcements that preceded each (as the stream decoder does).
    """
    segments = bytes(data).split(b"\x00")
    pending = len(segments.pop())
    seg_len = np.fromiter(map(len, segments), dtype=np.int64, count=len(segments))
    seg_start = np.cumsum(seg_len + 1) - (seg_len + 1)
    sizes = [0] * 256
    for m in BY_ID.values():
        sizes[m.id] = m.raw_frame_size
    candidates: dict[int, list[bytes]] = {m.id: [] for m in BY_ID.values()}
    where: dict[int, list[int]] = {m.id: [] for m in BY_ID.values()}
    bad: list[tuple[int, bytes | None]] = []  # (segment index, decoded bytes or None)
    for k, seg in enumerate(segments):
        if not seg:
            continue
        raw = None
        if len(seg) <= MAX_ENCODED_SIZE:
            try:
                raw = cobs_decode(seg)
                if len(raw) == sizes[raw[0]]:
                    candidates[raw[0]].append(raw)
                    where[raw[0]].append(k)
                    continue
            except (DecodeError, IndexError):
                pass
        bad.append((k, raw))

    tables, lost, announcements = {}, {}, []
    for msg_id, raws in candidates.items():
        if not raws:
            continue
        info = BY_ID[msg_id]
        rows = np.frombuffer(b"".join(raws), dtype=np.uint8).reshape(len(raws), -1)
        stored = rows[:, -2].astype(np.uint16) | (rows[:, -1].astype(np.uint16) << 8)
        ok = crc16_rows(rows[:, :-2], info.crc_seed) == stored
        index = np.asarray(where[msg_id])
        bad += [(int(k), raws[i]) for i, k in zip(np.flatnonzero(~ok), index[~ok], strict=True)]
        if not ok.any():
            continue
        packed = np.ascontiguousarray(rows[ok]).view(frame_dtype(info))[:, 0]
        table = np.empty(len(packed), dtype=table_dtype(info))
        table["byte_offset"] = seg_start[index[ok]]
        table["origin"] = packed["_flags"] & FLAGS_ORIGIN_MASK
        for name in ("seq", "flags", "board_time_us"):
            table[name] = packed["_" + name]
        for name, *_ in info.dtype_descr:
            table[name] = packed[name]
        tables[info.name] = table
        n_lost = _seq_lost(table["seq"], table["origin"])
        if n_lost:
            lost[info.name] = n_lost
        if msg_id == SCHEMA_ENTRY.id:
            announcements = sorted(zip(index[ok].tolist(), table["origin"].tolist(),
                                       table["msg_id"].tolist(), table["def_hash"].tolist(),
                                       strict=True))

    errors = dict.fromkeys(ERROR_KINDS, 0)
    announced: dict[tuple[int, int], int] = {}
    a = 0
    for k, raw in sorted(bad, key=lambda b: b[0]):
        while a < len(announcements) and announcements[a][0] < k:
            _, origin, msg_id, def_hash = announcements[a]
            announced[(origin, msg_id)] = def_hash
            a += 1
        kind = "oversize" if seg_len[k] > MAX_ENCODED_SIZE else classify_bad(raw, announced)
        errors[kind] += 1
    errors["bytes_dropped"] = int(sum(seg_len[k] for k, _ in bad))
    return Capture(tables, errors, len(data), pending, lost)
