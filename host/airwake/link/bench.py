"""Link codec benchmark (`airwake bench --only link`).

A realistic mixed capture: every board→host message of every board at its nominal rate
(docs/protocol.md), interleaved as the boards would send them, random field values.
Figures, all from the same run:

- decode_stream_frames_per_s   StreamDecoder.feed over 4 KiB chunks (serial-read sized)
- decode_batch_frames_per_s    decode_capture over the whole capture
- decode_vs_pymavlink_ratio    pymavlink's time / ours for the same number of frames
                               (pymavlink_frames_measured, the first frames of the capture;
                               pymavlink is too slow for all of them): MAVLink2 parse_buffer
                               on the same frame mix mapped to MAVLink messages of the
                               nearest payload size; alternated, best of three each
- c_decode_instructions_per_frame  callgrind, build/native/bench_proto, decode loop only
- c_decode_ns_per_frame        the same binary, best of 5, native -O2
"""

from __future__ import annotations

import os
import random
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

from airwake.link.framing import encode_payload_frame
from airwake.link.messages import (
    BOARD_IDS,
    BOARDS,
    BY_ID,
    HEARTBEAT,
    MESSAGES,
    SCHEMA_ENTRY,
    SCHEMA_HASH,
    Heartbeat,
    SchemaEntry,
)

SECTION = "link"
REPO = Path(__file__).resolve().parents[3]
CHUNK = 4096


def synthetic_capture(n_frames: int, seed: int = 1) -> bytes:
    """Board→host frames of every board at nominal rates, random payloads, in time order."""
    rng = random.Random(seed)
    streams = [(m, BOARD_IDS[b], rate) for m in MESSAGES for b, rate in m.rate_hz.items()
               if b != "host" and rate > 0]
    total_rate = sum(rate for _, _, rate in streams)
    duration_s = 1.01 * n_frames / total_rate  # rounding margin; cut to n_frames below
    events = []
    for k, (_, _, rate) in enumerate(streams):
        n = max(1, round(rate * duration_s))
        phase = rng.random() / rate
        events += [(phase + i / rate, k) for i in range(n)]
    events.sort()
    payloads = {m.id: [rng.randbytes(m.payload_size) for _ in range(32)] for m, _, _ in streams}
    seqs = [0] * len(streams)
    out = []
    for t_s, k in events[:n_frames]:
        m, origin, _ = streams[k]
        if m.id in (HEARTBEAT.id, SCHEMA_ENTRY.id):  # real content: a consistent schema
            payload = _control_payload(m, origin, seqs[k])
        else:
            payload = rng.choice(payloads[m.id])
        out.append(encode_payload_frame(m.id, payload, seqs[k] & 0xFF, origin,
                                        int(t_s * 1e6) & 0xFFFFFFFF))
        seqs[k] += 1
    return b"".join(out)


def _control_payload(m, origin: int, n: int) -> bytes:
    """Heartbeat / schema_entry payloads a board of this schema would send."""
    if m.id == HEARTBEAT.id:
        return m.pack(Heartbeat(board_id=origin, fw_version_minor=1, schema_hash=SCHEMA_HASH,
                                uptime_ms=1000 * n, frames_sent=n))
    sent = [x for x in MESSAGES if BOARDS[origin] in x.rate_hz]
    entry = sent[n % len(sent)]
    return m.pack(SchemaEntry(entry.id, entry.def_hash, n % len(sent), len(sent)))


def _time_stream(data: bytes) -> tuple[float, int]:
    from airwake.link.decoder import StreamDecoder

    decoder = StreamDecoder()
    t0 = time.perf_counter()
    n = 0
    for i in range(0, len(data), CHUNK):
        n += len(decoder.feed(data[i:i + CHUNK]))
    return time.perf_counter() - t0, n


def _mavlink_capture(ours: bytes, n_frames: int) -> tuple[bytes, int]:
    """MAVLink2 frames with the payload-size mix of our first n_frames frames."""
    from pymavlink.dialects.v20 import common as mavlink2

    from airwake.link.decoder import StreamDecoder

    mav = mavlink2.MAVLink(None, srcSystem=1, srcComponent=1)
    rng = random.Random(2)

    def f() -> float:
        return rng.uniform(-100.0, 100.0)

    def i(bits: int) -> int:
        return rng.randrange(1, 2**bits - 1)

    # (payload bytes, builder) candidates; values non-zero so MAVLink2 keeps the length
    candidates = [
        (14, lambda: mav.scaled_pressure_encode(i(32), f(), f(), i(15))),
        (22, lambda: mav.scaled_imu_encode(i(32), *(i(15) for _ in range(9)))),
        (28, lambda: mav.attitude_encode(i(32), *(f() for _ in range(6)))),
        (32, lambda: mav.attitude_quaternion_encode(i(32), *(f() for _ in range(7)))),
        (42, lambda: mav.rc_channels_encode(i(32), 18, *(i(16) for _ in range(18)), 200)),
        (62, lambda: mav.highres_imu_encode(i(64), *(f() for _ in range(13)), i(16))),
        (64, lambda: mav.hil_state_quaternion_encode(
            i(64), [f() for _ in range(4)], f(), f(), f(), i(31), i(31), i(31),
            *(i(15) for _ in range(3)), i(16), i(16), *(i(15) for _ in range(3)))),
    ]
    frames = StreamDecoder().feed(_cut_after_frames(ours, n_frames))
    out = []
    for frame in frames:
        payload = BY_ID[frame.msg_id].payload_size
        _, build = min(candidates, key=lambda c: abs(c[0] - payload))
        out.append(build().pack(mav))
    return b"".join(out), len(out)


def _time_pymavlink(data: bytes) -> tuple[float, int]:
    from pymavlink.dialects.v20 import common as mavlink2

    mav = mavlink2.MAVLink(None)
    mav.robust_parsing = True
    t0 = time.perf_counter()
    n = 0
    for i in range(0, len(data), CHUNK):
        n += len(mav.parse_buffer(data[i:i + CHUNK]) or ())
    return time.perf_counter() - t0, n


def _c_figures(data: bytes, callgrind_frames: int) -> dict:
    binary = REPO / "build/native/bench_proto"
    subprocess.run(["make", "-s", "-C", str(REPO / "firmware"), str(binary)], check=True,
                   stdout=subprocess.DEVNULL)
    figures = {}
    with tempfile.TemporaryDirectory() as tmp:
        capture = Path(tmp) / "capture.bin"
        capture.write_bytes(data)
        out = subprocess.run([str(binary), str(capture), "5"], check=True, capture_output=True,
                             text=True).stdout
        figures["c_decode_ns_per_frame"] = float(re.search(r'"ns_per_frame": ([\d.]+)', out)[1])
        if shutil.which("valgrind"):
            from airwake.link.decoder import StreamDecoder

            small = Path(tmp) / "small.bin"
            cut = _cut_after_frames(data, callgrind_frames)
            small.write_bytes(cut)
            n = len(StreamDecoder().feed(cut))
            log = Path(tmp) / "callgrind.out"
            subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={log}",
                            "--toggle-collect=bench_decode", str(binary), str(small), "1"],
                           check=True, capture_output=True)
            total = int(re.search(r"^(?:summary|totals): (\d+)", log.read_text(), re.M)[1])
            figures["c_decode_instructions_per_frame"] = round(total / n, 1)
    return figures


def _cut_after_frames(data: bytes, n_frames: int) -> bytes:
    """Prefix of a capture holding its first n_frames frames (2 delimiters each)."""
    pos = -1
    for _ in range(2 * n_frames):
        pos = data.index(b"\x00", pos + 1)
    return data[:pos + 1]


def run(quick: bool) -> dict:
    from airwake.link.batch import decode_capture

    n_frames = 100_000 if quick else 1_000_000
    n_mavlink = 10_000 if quick else 50_000
    data = synthetic_capture(n_frames)

    stream_s, n_stream = _time_stream(data)
    t0 = time.perf_counter()
    capture = decode_capture(data)
    batch_s = time.perf_counter() - t0
    n_batch = sum(len(t) for t in capture.tables.values())
    assert n_stream == n_batch == n_frames, (n_stream, n_batch, n_frames)

    # The ratio: both decoders on the same number of frames, alternated, best of three,
    # so load changes on a shared machine hit both alike.
    mav_data, n_mav = _mavlink_capture(data, n_mavlink)
    ours_subset = _cut_after_frames(data, n_mav)
    ours_s, mav_s = float("inf"), float("inf")
    for _ in range(3):
        s, n = _time_stream(ours_subset)
        assert n == n_mav, (n, n_mav)
        ours_s = min(ours_s, s)
        s, n = _time_pymavlink(mav_data)
        assert n == n_mav, (n, n_mav)
        mav_s = min(mav_s, s)
    mav_per_s = n_mav / mav_s
    figures = {
        "decode_bench_frames": n_frames,
        "decode_bench_mean_wire_bytes": round(len(data) / n_frames, 1),
        "decode_stream_frames_per_s": round(n_stream / stream_s),
        "decode_batch_frames_per_s": round(n_batch / batch_s),
        "pymavlink_frames_per_s": round(mav_per_s),
        "pymavlink_frames_measured": n_mav,
        "decode_vs_pymavlink_ratio": round(mav_s / ours_s, 2),
    }
    if os.environ.get("AIRWAKE_BENCH_NO_C") != "1":
        figures.update(_c_figures(data, 20_000))
    return figures
