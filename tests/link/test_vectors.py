"""Golden vectors (protocol/vectors/): Python and C must produce and read exactly them."""

from __future__ import annotations

import json
import math

import pytest
from airwake.link.batch import decode_capture
from airwake.link.decoder import StreamDecoder
from airwake.link.framing import encode_frame
from airwake.link.messages import BY_NAME

from .conftest import REPO, same_value

FRAMES = json.loads((REPO / "protocol/vectors/frames.json").read_text())["vectors"]
STREAMS = json.loads((REPO / "protocol/vectors/streams.json").read_text())["streams"]


def _value(v):
    if isinstance(v, list):
        return tuple(_value(x) for x in v)
    return {"nan": math.nan, "inf": math.inf, "-inf": -math.inf}.get(v, v) \
        if isinstance(v, str) else v


def _record(vector):
    info = BY_NAME[vector["msg"]]
    return info.record(**{k: _value(v) for k, v in vector["fields"].items()})


@pytest.mark.parametrize("vector", FRAMES, ids=[v["name"] for v in FRAMES])
def test_golden_frame_python_encodes_and_decodes_exactly(vector, clib):
    record = _record(vector)
    header = (vector["seq"], vector["flags"], vector["board_time_us"])
    wire = encode_frame(record, *header)
    assert wire.hex() == vector["frame_hex"]
    assert clib.encode(record, *header) == wire
    frames = StreamDecoder().feed(bytes.fromhex(vector["frame_hex"]))
    assert len(frames) == 1
    f = frames[0]
    assert (f.name, f.seq, f.flags, f.board_time_us) == (vector["msg"], *header)
    for name, expected in vector["fields"].items():
        assert same_value(getattr(f.msg, name), _value(expected)), name


def test_vectors_cover_zero_bytes_and_full_cobs_blocks():
    # the two COBS paths that hand-written codecs most often get wrong
    assert any(0 in bytes.fromhex(v["payload_hex"]) for v in FRAMES)
    assert any(bytes.fromhex(v["frame_hex"])[1] == 0xFF for v in FRAMES)
    assert {v["msg"] for v in FRAMES} == set(BY_NAME)


@pytest.mark.parametrize("stream", STREAMS, ids=[s["name"] for s in STREAMS])
@pytest.mark.parametrize("chunk", [1, 7, 4096])
def test_golden_stream_counts_like_the_reference(stream, chunk):
    data = bytes.fromhex(stream["hex"])
    decoder = StreamDecoder()
    frames = []
    for i in range(0, len(data), chunk):
        frames += decoder.feed(data[i:i + chunk])
    expect = stream["expect"]
    counters = {"frames_ok": decoder.frames_ok, **decoder.errors,
                "bytes_dropped": decoder.bytes_dropped}
    assert counters == expect["counters"]
    got = [{"msg_id": f.msg_id, "seq": f.seq, "flags": f.flags,
            "board_time_us": f.board_time_us,
            "payload_hex": BY_NAME[f.name].pack(f.msg).hex()} for f in frames]
    assert got == expect["frames"]


@pytest.mark.parametrize("stream", STREAMS, ids=[s["name"] for s in STREAMS])
def test_golden_stream_counts_alike_in_batch_and_c(stream, clib):
    data = bytes.fromhex(stream["hex"])
    expect = stream["expect"]["counters"]
    capture = decode_capture(data)
    assert {"frames_ok": sum(len(t) for t in capture.tables.values()),
            **capture.errors} == expect
    _, c_counters = clib.decode(data)
    assert c_counters == expect
