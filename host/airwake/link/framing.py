"""Frame encoding (docs/protocol.md): header, payload, CRC-16, COBS and both delimiters.

    wire = 0x00 | COBS(msg_id | seq | flags | board_time_us u32 | payload | crc u16) | 0x00

The CRC is CRC-16/CCITT-FALSE's body seeded with the message's CRC seed, exactly what
`binascii.crc_hqx(body, seed)` computes.
"""

from __future__ import annotations

import struct
from binascii import crc_hqx

from cobs.cobs import encode as cobs_encode

from airwake.errors import AirwakeError
from airwake.link.messages import BY_ID, BY_RECORD, FLAGS_ORIGIN_MASK, HEADER

_CRC = struct.Struct("<H")


class ProtocolError(AirwakeError):
    """A message could not be encoded (unknown id, value out of range for its type)."""


def crc_seed(def_hash: int) -> int:
    """The CRC seed of a definition hash: (h >> 16) ^ (h & 0xFFFF)."""
    return ((def_hash >> 16) ^ def_hash) & 0xFFFF


def flags_for(origin_board: int) -> int:
    """The flags byte of a frame from `origin_board` (bits 0-2; the rest reserved = 0)."""
    if not 0 <= origin_board <= FLAGS_ORIGIN_MASK:
        raise ProtocolError(f"origin board id {origin_board} outside 0..{FLAGS_ORIGIN_MASK}")
    return origin_board


def encode_payload_frame(msg_id: int, payload: bytes, seq: int = 0, flags: int = 0,
                         board_time_us: int = 0, *, seed: int | None = None) -> bytes:
    """Wire bytes of a frame around an already packed payload.

    `seed` overrides the CRC seed of `msg_id` (frames of foreign definitions in tests);
    without it the id must be known and the payload its exact size.
    """
    if seed is None:
        info = BY_ID.get(msg_id)
        if info is None:
            raise ProtocolError(f"message id 0x{msg_id:02X} is not in the schema")
        if len(payload) != info.payload_size:
            raise ProtocolError(f"{info.name}: payload is {len(payload)} bytes, "
                                f"expected {info.payload_size}")
        seed = info.crc_seed
    try:
        body = HEADER.pack(msg_id, seq, flags, board_time_us) + payload
    except struct.error as exc:
        raise ProtocolError(f"frame header (msg_id={msg_id}, seq={seq}, flags={flags}, "
                            f"board_time_us={board_time_us}): {exc}") from exc
    return b"\x00" + cobs_encode(body + _CRC.pack(crc_hqx(body, seed))) + b"\x00"


def encode_frame(msg, seq: int = 0, flags: int = 0, board_time_us: int = 0) -> bytes:
    """Wire bytes of one message record (e.g. `messages.Imu(...)`)."""
    info = BY_RECORD.get(type(msg))
    if info is None:
        raise ProtocolError(f"{type(msg).__name__} is not a protocol message record")
    try:
        payload = info.pack(msg)
    except (struct.error, TypeError) as exc:
        raise ProtocolError(f"{info.name}: cannot pack {msg!r}: {exc}") from exc
    return encode_payload_frame(info.id, payload, seq, flags, board_time_us, seed=info.crc_seed)
