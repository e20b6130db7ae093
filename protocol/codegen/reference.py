"""The reference framing, written from the spec in docs/protocol.md and nothing else.

It produces the golden vectors; the C and Python codecs are checked against them, so
this file is deliberately a third, independent implementation (bitwise CRC, plain COBS)
kept short rather than fast.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field

from schema import FRAME_OVERHEAD, HEADER_SIZE, ORIGIN_MASK, Message, cobs_max_encoded, fold16


def crc16_ccitt_false(data: bytes, init: int) -> int:
    """CRC-16/CCITT-FALSE body: poly 0x1021, MSB first, no reflection, no xorout."""
    crc = init
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else (crc << 1)
            crc &= 0xFFFF
    return crc


def cobs_encode(data: bytes) -> bytes:
    """COBS; after a full 254-byte block that ends the input no empty block follows."""
    out = bytearray()
    block = bytearray()
    last_full = False
    for b in data:
        if b == 0:
            out += bytes([len(block) + 1]) + block
            block.clear()
            last_full = False
        else:
            block.append(b)
            last_full = False
            if len(block) == 254:
                out += b"\xff" + block
                block.clear()
                last_full = True
    if not last_full:
        out += bytes([len(block) + 1]) + block
    return bytes(out)


def cobs_decode(data: bytes) -> bytes | None:
    """None when `data` is not valid COBS (a zero, or a code pointing past the end)."""
    out = bytearray()
    i, n = 0, len(data)
    while i < n:
        code = data[i]
        if code == 0 or i + code > n or 0 in data[i + 1:i + code]:
            return None
        out += data[i + 1:i + code]
        i += code
        if i < n and code != 0xFF:
            out.append(0)
    return bytes(out)


def pack_payload(msg: Message, values: dict) -> bytes:
    flat = []
    for f in msg.fields:
        v = values[f.name]
        flat += list(v) if f.count > 1 else [v]
    return struct.pack(msg.payload_format, *flat)


def raw_frame(msg_id: int, seq: int, flags: int, t_us: int, payload: bytes, seed: int) -> bytes:
    body = struct.pack("<BBBI", msg_id, seq, flags, t_us) + payload
    return body + struct.pack("<H", crc16_ccitt_false(body, seed))


def wire_frame(raw: bytes) -> bytes:
    """Leading delimiter, COBS, trailing delimiter."""
    return b"\x00" + cobs_encode(raw) + b"\x00"


@dataclass
class Outcome:
    counters: dict[str, int] = field(default_factory=lambda: dict.fromkeys(
        ("frames_ok", "crc_error", "unknown_id", "def_mismatch", "oversize", "cobs_error",
         "bytes_dropped"), 0))
    frames: list[dict] = field(default_factory=list)


def classify_stream(stream: bytes, messages: list[Message]) -> Outcome:
    """What every conforming decoder must report for a whole byte stream.

    Announced hashes are learnt from decoded schema_entry frames and kept per
    (origin, msg_id); decoders on one link from one origin may key them by msg_id.
    """
    by_id = {m.id: m for m in messages}
    max_encoded = cobs_max_encoded(max(m.raw_frame_size for m in messages))
    announced: dict[tuple[int, int], int] = {}
    out = Outcome()
    c = out.counters
    for seg in stream.split(b"\x00")[:-1]:
        if not seg:
            continue

        def drop(reason: str, seg: bytes = seg) -> None:
            c[reason] += 1
            c["bytes_dropped"] += len(seg)

        if len(seg) > max_encoded:
            drop("oversize")
            continue
        raw = cobs_decode(seg)
        if raw is None or len(raw) < FRAME_OVERHEAD:
            drop("cobs_error")
            continue
        msg_id, seq, flags, t_us = struct.unpack_from("<BBBI", raw)
        msg = by_id.get(msg_id)
        if msg is None:
            drop("unknown_id")
            continue
        crc = struct.unpack_from("<H", raw, len(raw) - 2)[0]
        body = raw[:-2]
        if len(raw) == msg.raw_frame_size and crc16_ccitt_false(body, msg.crc_seed) == crc:
            c["frames_ok"] += 1
            payload = raw[HEADER_SIZE:-2]
            out.frames.append({"msg_id": msg_id, "seq": seq, "flags": flags,
                               "board_time_us": t_us, "payload_hex": payload.hex()})
            if msg.name == "schema_entry":
                entry_id, def_hash = struct.unpack_from("<BI", payload)
                announced[(flags & ORIGIN_MASK, entry_id)] = def_hash
            continue
        other = announced.get((flags & ORIGIN_MASK, msg_id))
        if other is not None and other != msg.def_hash and \
                crc16_ccitt_false(body, fold16(other)) == crc:
            drop("def_mismatch")
        else:
            drop("crc_error")
    return out
