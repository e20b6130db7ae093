#!/usr/bin/env python3
"""Seed corpora for the libFuzzer targets (firmware/fuzz/fuzz_*.c), standard library only.

    python3 firmware/fuzz/make_seeds.py OUT  ->  OUT/fuzz_decoder/*, fuzz_vn200/*, fuzz_sbp/*

fuzz_decoder: every golden frame and stream of protocol/vectors/ (frames.json, streams.json).
fuzz_vn200:   synthetic VectorNav binary-output packets: our VN-200 configuration (group 1,
              mask 0x11E9), a VN-100 style one (groups 3+5), every group with all its
              fixed-size fields, and a stream with garbage, a stray sync byte and a
              truncated packet.
fuzz_sbp:     synthetic SBP frames of every type the parser decodes (libsbp lengths), of
              types it only frames (settings 175, log 1025), empty ones, and a stream with
              garbage, a stray preamble and a truncated frame.
Nothing here comes from recorded captures: the captures are test data in ../shared only.
"""

from __future__ import annotations

import binascii
import json
import random
import struct
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]

# VectorNav field sizes, groups 1..7, bits 0..14 (0: variable or unknown), as vn200.c.
VN_FIELD_SIZES = (
    (8, 8, 8, 12, 16, 12, 24, 12, 12, 24, 20, 28, 2, 4, 8),
    (8, 8, 8, 2, 8, 8, 8, 4, 4, 1, 0, 0, 0, 0, 0),
    (2, 12, 12, 12, 4, 4, 16, 12, 12, 12, 12, 2, 40, 0, 0),
    (8, 8, 2, 1, 1, 24, 24, 12, 12, 12, 4, 4, 2, 28, 0),
    (2, 12, 16, 36, 12, 12, 12, 12, 12, 12, 28, 24, 12, 0, 0),
    (2, 24, 24, 12, 12, 12, 12, 12, 12, 4, 4, 68, 64, 0, 0),
    (8, 8, 2, 1, 1, 24, 24, 12, 12, 12, 4, 4, 2, 28, 0),
)

SBP_DECODED = {  # msg_type: payload length (libsbp)
    0x0102: 11, 0x0103: 16, 0x0208: 15, 0x020A: 34, 0x020B: 20, 0x020C: 22, 0x020E: 22,
    0x0900: 17,
}


def crc_xmodem(data: bytes) -> int:
    """CRC-16/XMODEM (poly 0x1021, init 0): VectorNav's and SBP's CRC."""
    return binascii.crc_hqx(data, 0)


def vn_payload_size(groups: int, masks: dict[int, int]) -> int:
    return sum(VN_FIELD_SIZES[g - 1][b] for g in range(1, 8) if groups >> (g - 1) & 1
               for b in range(15) if masks[g] >> b & 1)


def vn_packet(groups: int, masks: dict[int, int], payload: bytes) -> bytes:
    """A VectorNav binary packet: 0xFA, group byte, a u16 LE mask per group present, the
    payload, CRC-16/XMODEM over group..payload appended big-endian."""
    assert len(payload) == vn_payload_size(groups, masks)
    body = bytes([groups]) + b"".join(struct.pack("<H", masks[g]) for g in range(1, 8)
                                      if groups >> (g - 1) & 1) + payload
    return b"\xfa" + body + struct.pack(">H", crc_xmodem(body))


def vn200_ours(t_ns: int, yaw: float) -> bytes:
    """Our rover configuration: group 1, mask 0x11E9 (TimeStartup, YPR, AngularRate,
    Position, Velocity, Accel, InsStatus), 88 bytes."""
    payload = (struct.pack("<Q", t_ns) + struct.pack("<3f", yaw, -2.5, 1.25)
               + struct.pack("<3f", 0.1, -0.2, 0.3)
               + struct.pack("<3d", 37.2513, -121.875, 28.2)
               + struct.pack("<3f", 1.0, 2.0, -0.5) + struct.pack("<3f", 0.05, -0.1, -9.79)
               + struct.pack("<H", 0x0123))
    return vn_packet(0x01, {1: 0x11E9}, payload)


def vn100_style(rng: random.Random) -> bytes:
    """Groups 3+5, IMU 0x003E, Attitude 0x003A: 29 floats, 124 bytes (a VN-100 logger's)."""
    floats = [rng.uniform(-10, 10) for _ in range(29)]
    return vn_packet(0x14, {3: 0x003E, 5: 0x003A}, struct.pack("<29f", *floats))


def vn_all_fields(g: int, rng: random.Random) -> bytes:
    mask = sum(1 << b for b in range(15) if VN_FIELD_SIZES[g - 1][b])
    size = vn_payload_size(1 << (g - 1), {g: mask})
    return vn_packet(1 << (g - 1), {g: mask}, rng.randbytes(size))


def sbp_frame(msg_type: int, sender: int, payload: bytes) -> bytes:
    body = struct.pack("<HHB", msg_type, sender, len(payload)) + payload
    return b"\x55" + body + struct.pack("<H", crc_xmodem(body))


def decoder_seeds() -> dict[str, bytes]:
    vectors = REPO / "protocol" / "vectors"
    frames = json.loads((vectors / "frames.json").read_text())["vectors"]
    streams = json.loads((vectors / "streams.json").read_text())["streams"]
    seeds = {f"frame_{i:03d}": bytes.fromhex(v["frame_hex"]) for i, v in enumerate(frames)}
    seeds |= {f"stream_{i:03d}": bytes.fromhex(s["hex"]) for i, s in enumerate(streams)}
    seeds["frames_all"] = b"".join(bytes.fromhex(v["frame_hex"]) for v in frames)[:4096]
    return seeds


def vn200_seeds() -> dict[str, bytes]:
    rng = random.Random(200)
    seeds = {"ours": vn200_ours(1_000_000, 45.0), "vn100_style": vn100_style(rng)}
    for g in range(1, 8):
        seeds[f"group{g}_all_fields"] = vn_all_fields(g, rng)
    p = [vn200_ours(1_000_000 + 6_666_667 * i, 10.0 * i) for i in range(3)]
    q = vn100_style(rng)
    seeds["stream"] = (b"$GPRMC,garbage*00\r\n" + p[0] + b"\xfa" + p[1] + q[:50] + p[2]
                       + b"M,1234\r\n" + q)
    return seeds


def sbp_seeds() -> dict[str, bytes]:
    rng = random.Random(175)
    seeds = {f"type_{t:04x}": sbp_frame(t, 0x42, rng.randbytes(n)) for t, n in SBP_DECODED.items()}
    seeds["settings_175"] = sbp_frame(175, 0x42, b"solution\0elevation_mask\0" + b"10\0")
    seeds["log_1025"] = sbp_frame(1025, 0x42, b"\x06" + b"hello from the piksi")
    seeds["empty"] = sbp_frame(0x00FF, 0, b"")
    f = [sbp_frame(t, 1234, rng.randbytes(n)) for t, n in SBP_DECODED.items()]
    seeds["stream"] = (b"\x00\x13garbage" + f[0] + b"\x55" + f[1] + f[2][:9] + f[3] + b"\xff" * 5
                       + f[4])
    return seeds


SEEDS = {"fuzz_decoder": decoder_seeds, "fuzz_vn200": vn200_seeds, "fuzz_sbp": sbp_seeds}


def write_seeds(out: Path, targets=tuple(SEEDS)) -> dict[str, int]:
    """Write each target's seeds into out/<target>/; returns how many per target."""
    counts = {}
    for target in targets:
        d = out / target
        d.mkdir(parents=True, exist_ok=True)
        seeds = SEEDS[target]()
        for name, data in seeds.items():
            (d / f"seed_{name}").write_bytes(data)
        counts[target] = len(seeds)
    return counts


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(f"usage: {sys.argv[0]} OUT_DIR")
    for target, n in write_seeds(Path(sys.argv[1])).items():
        print(f"{target}: {n} seeds")
