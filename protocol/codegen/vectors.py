"""Golden vectors: frames (hex + decoded values) and streams with expected counters.

Values are deterministic (fixed seeds) so regeneration is byte-identical. Expected
stream outcomes come from reference.classify_stream, and each scenario asserts that
it produced the outcome it was built to show.
"""

from __future__ import annotations

import math
import random
import struct
from dataclasses import replace

from reference import classify_stream, cobs_decode, pack_payload, raw_frame, wire_frame
from schema import TYPES, Field, Links, Message, fold16

F32_MAX = 3.4028234663852886e38
F32_SUBNORMAL = 1.401298464324817e-45
SPECIAL_FLOATS = [math.nan, math.inf, -math.inf, -0.0]


def _f32(x: float) -> float:
    return struct.unpack("<f", struct.pack("<f", x))[0]


def _typical(f: Field, rng: random.Random):
    def one():
        if f.type == "f32":
            return _f32(rng.uniform(-1000.0, 1000.0))
        if f.type == "f64":
            return rng.uniform(-180.0, 180.0)
        lo, hi = TYPES[f.type][3], TYPES[f.type][4]
        return rng.randint(int(lo), int(hi))
    return one() if f.count == 1 else [one() for _ in range(f.count)]


def _extreme(f: Field, index: int):
    def one(k: int):
        if f.is_float:
            finite_max = F32_MAX if f.type == "f32" else 1.7976931348623157e308
            tiny = F32_SUBNORMAL if f.type == "f32" else 5e-324
            return (SPECIAL_FLOATS + [finite_max, -finite_max, tiny, -tiny])[k % 8]
        lo, hi = TYPES[f.type][3], TYPES[f.type][4]
        return int(hi) if k % 2 == 0 else int(lo)
    return one(index) if f.count == 1 else [one(index + k) for k in range(f.count)]


def _zero(f: Field):
    zero = 0.0 if f.is_float else 0
    return zero if f.count == 1 else [zero] * f.count


def _json_value(v):
    if isinstance(v, list):
        return [_json_value(x) for x in v]
    if isinstance(v, float) and not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    return v


def _origin(m: Message, links: Links) -> int:
    return links.boards[next(iter(m.rate_hz))]


def frame_vectors(messages: list[Message], links: Links) -> tuple[list[dict], dict[str, dict]]:
    """Per message: zeros, typical and extremes (+ a saturated raw line: a 0xFF COBS block)."""
    vectors, values_by_name = [], {}
    for m in messages:
        rng = random.Random(m.id)
        cases = [
            ("zeros", {f.name: _zero(f) for f in m.fields}, (0, 0, 0)),
            ("typical", {f.name: _typical(f, rng) for f in m.fields},
             ((m.id * 37) & 0xFF, _origin(m, links), rng.randint(0, 2**32 - 1))),
            ("extremes", {f.name: _extreme(f, i) for i, f in enumerate(m.fields)},
             (0xFF, 0xFF, 0xFFFFFFFF)),
        ]
        if m.name == "losa_raw_line":
            cases.append(("saturated", {"sensor_index": 2, "exposure_us": 3000,
                                        "pixels_counts": [4095] * 128},
                          (7, links.boards["losa"], 123_456_789)))
        for label, values, (seq, flags, t_us) in cases:
            payload = pack_payload(m, values)
            raw = raw_frame(m.id, seq, flags, t_us, payload, m.crc_seed)
            name = f"{m.name}/{label}"
            values_by_name[name] = values
            vectors.append({
                "name": name, "msg": m.name, "msg_id": m.id, "seq": seq, "flags": flags,
                "board_time_us": t_us,
                "fields": {k: _json_value(v) for k, v in values.items()},
                "payload_hex": payload.hex(), "frame_hex": wire_frame(raw).hex(),
            })
    raws = [cobs_decode(bytes.fromhex(v["frame_hex"])[1:-1]) for v in vectors]
    assert any(max(map(len, r.split(b"\x00"))) >= 254 for r in raws), \
        "no vector exercises a full 254-byte COBS block"
    assert any("00" in v["payload_hex"] for v in vectors)
    return vectors, values_by_name


def stream_vectors(messages: list[Message], links: Links, frames: list[dict]) -> list[dict]:
    by_name = {m.name: m for m in messages}
    wire = {v["name"]: bytes.fromhex(v["frame_hex"]) for v in frames}
    imu, peaks, hb = wire["imu/typical"], wire["losa_peaks/typical"], wire["heartbeat/typical"]
    raw_line = wire["losa_raw_line/saturated"]
    rover = links.boards["rover"]

    # A newer imu definition on the sender: one field appended.
    imu_def = by_name["imu"]
    newer = replace(imu_def, fields=imu_def.fields + [Field("extra_u8", "u8", 1, "1", "x")])
    newer_payload = bytes.fromhex(frames[[v["name"] for v in frames].index("imu/typical")]
                                  ["payload_hex"]) + b"\x2a"
    newer_frame = wire_frame(raw_frame(imu_def.id, 9, rover, 1000, newer_payload,
                                       fold16(newer.def_hash)))
    entry = by_name["schema_entry"]
    announce = wire_frame(raw_frame(entry.id, 0, rover, 999, pack_payload(entry, {
        "msg_id": imu_def.id, "def_hash": newer.def_hash, "entry_index": 0,
        "entry_count": 1}), entry.crc_seed))
    unknown = wire_frame(raw_frame(0xEE, 0, rover, 5, b"\x01\x02\x03\x04", 0x0000))

    def flip(frame: bytes, pos: int, bit: int = 0x10) -> bytes:
        b = bytearray(frame)
        b[pos] ^= bit
        return bytes(b)

    scenarios = [
        ("clean", "four frames back to back, one needing a 0xFF COBS block",
         imu + peaks + hb + raw_line, {"frames_ok": 4}),
        ("empty_frames", "runs of delimiters are no-ops",
         b"\x00\x00\x00" + imu + b"\x00\x00", {"frames_ok": 1}),
        ("flipped_bit", "one bit flipped inside a frame's data: that frame is a CRC error",
         imu + flip(peaks, 20) + hb, {"frames_ok": 2, "crc_error": 1}),
        ("dropped_byte", "one byte lost from the middle of a frame",
         imu + peaks[:25] + peaks[26:] + hb, {"frames_ok": 2, "cobs_error": 1}),
        ("garbage_between", "noise between two frames is its own bad segment",
         imu + bytes(range(0x41, 0x61)) + hb, {"frames_ok": 2, "cobs_error": 1}),
        ("truncated", "a frame cut short (tail and delimiter lost) does not swallow the next",
         imu + peaks[:30] + hb, {"frames_ok": 2, "cobs_error": 1}),
        ("unknown_id", "a well-formed frame with an id this schema lacks",
         imu + unknown + hb, {"frames_ok": 2, "unknown_id": 1}),
        ("def_mismatch", "a newer imu definition: CRC error before the sender announces its "
         "hash, definition mismatch after",
         newer_frame + announce + newer_frame + imu,
         {"frames_ok": 2, "crc_error": 1, "def_mismatch": 1}),
        ("oversize", "a segment longer than the longest frame",
         imu + b"\x00" + b"\x01" * 600 + b"\x00" + hb, {"frames_ok": 2, "oversize": 1}),
        ("cobs_errors", "a code byte pointing past the end, and a runt shorter than a header",
         b"\x00\x05\x01\x02\x00" + b"\x00\x02\x01\x00" + imu, {"frames_ok": 1, "cobs_error": 2}),
        ("partial_tail", "a stream ending mid-frame: the tail is pending, not an error",
         imu + hb[:20], {"frames_ok": 1}),
    ]
    streams = []
    for name, description, data, expect in scenarios:
        outcome = classify_stream(data, messages)
        got = {k: v for k, v in outcome.counters.items() if v and k != "bytes_dropped"}
        assert got == expect, f"stream vector {name}: built for {expect}, reference says {got}"
        streams.append({"name": name, "description": description, "hex": data.hex(),
                        "expect": {"counters": outcome.counters, "frames": outcome.frames}})
    return streams
