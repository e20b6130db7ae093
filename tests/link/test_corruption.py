"""Corruption property: dropped, inserted and flipped bytes, truncated frames and garbage
between frames never raise, never cost an untouched frame, and every segment and byte is
accounted for — identically in the streaming, batch and C decoders."""

from __future__ import annotations

from airwake.link.batch import decode_capture
from airwake.link.decoder import StreamDecoder
from airwake.link.framing import encode_frame
from airwake.link.messages import MESSAGES
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from .conftest import record_strategy

RECORDS = st.one_of([record_strategy(m) for m in MESSAGES])
OPS = st.sampled_from(["none", "none", "none", "drop", "insert", "flip", "truncate", "garbage"])


@st.composite
def corrupted_streams(draw):
    """(stream bytes, [(wire frame, touched)]) with a random corruption per frame."""
    frames = draw(st.lists(RECORDS, min_size=1, max_size=25))
    stream = bytearray()
    sent = []
    for i, record in enumerate(frames):
        wire = bytearray(encode_frame(record, i & 0xFF, 3, i))
        op = draw(OPS)
        if op == "drop":
            for _ in range(draw(st.integers(1, 3))):
                del wire[draw(st.integers(0, len(wire) - 1))]
        elif op == "insert":
            for _ in range(draw(st.integers(1, 3))):
                wire.insert(draw(st.integers(0, len(wire))), draw(st.integers(0, 255)))
        elif op == "flip":
            wire[draw(st.integers(0, len(wire) - 1))] ^= 1 << draw(st.integers(0, 7))
        elif op == "truncate":  # the tail and the trailing delimiter are lost
            wire = wire[:draw(st.integers(1, len(wire) - 1))]
        elif op == "garbage":  # between frames: this frame stays intact
            stream += draw(st.binary(min_size=1, max_size=60))
        stream += wire
        sent.append((bytes(wire), op not in ("none", "garbage")))
    return bytes(stream), sent


def _feed(data: bytes, cuts: list[int]) -> tuple[StreamDecoder, list]:
    decoder = StreamDecoder()
    frames, start = [], 0
    for cut in sorted(set(cuts)) + [len(data)]:
        frames += decoder.feed(data[start:cut])
        start = cut
    return decoder, frames


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=corrupted_streams(), data=st.data())
def test_untouched_frames_survive_any_corruption(case, data):
    stream, sent = case
    cuts = data.draw(st.lists(st.integers(0, len(stream)), max_size=8))
    decoder, frames = _feed(stream, cuts)
    got = [encode_frame(f.msg, f.seq, f.flags, f.board_time_us) for f in frames]

    # every untouched frame, in order (spurious ones may only come from touched frames)
    j = 0
    untouched = [w for w, touched in sent if not touched]
    for wire in untouched:
        while j < len(got) and got[j] != wire:
            j += 1
        assert j < len(got), "an untouched frame was lost"
        j += 1
    assert len(got) - len(untouched) <= sum(touched for _, touched in sent)

    # each non-empty segment counted exactly once, every byte accounted
    complete = stream.split(b"\x00")[:-1]
    assert decoder.frames_ok + sum(decoder.errors.values()) == sum(1 for s in complete if s)
    ok_bytes = sum(len(w) - 2 for w in got)  # canonical COBS: decoded frames re-encode alike
    assert ok_bytes + decoder.bytes_dropped + stream.count(0) + decoder.pending_bytes \
        == len(stream) == decoder.bytes_total


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=corrupted_streams())
def test_stream_batch_and_c_decoders_agree_on_corrupt_streams(case, clib):
    stream, _ = case
    stream += b"\x00"  # C and batch see the same complete segments as the stream decoder
    decoder, frames = _feed(stream, [])
    capture = decode_capture(stream)
    c_frames, c_counters = clib.decode(stream)
    counters = {"frames_ok": decoder.frames_ok, **decoder.errors,
                "bytes_dropped": decoder.bytes_dropped}
    assert counters == {"frames_ok": sum(len(t) for t in capture.tables.values()),
                        **capture.errors}
    assert counters == c_counters
    assert [(f.msg_id, f.seq, f.board_time_us) for f in frames] == \
        [(m, s, t) for m, s, _, t, _ in c_frames]


@settings(max_examples=50, deadline=None)
@given(noise=st.binary(max_size=3000), cuts=st.lists(st.integers(0, 3000), max_size=10))
def test_random_bytes_never_raise(noise, cuts):
    decoder, _ = _feed(noise, [c for c in cuts if c <= len(noise)])
    assert decoder.bytes_total == len(noise)


def test_oversize_run_across_chunks_is_one_error():
    # a long run without delimiters, fed in small chunks, must not grow the buffer
    # without bound and must count as one oversize segment, then resync
    from airwake.link.messages import Imu

    good = encode_frame(Imu(), 1, 1, 1)
    stream = good + b"\x00" + b"\x55" * 10_000 + b"\x00" + good
    decoder, frames = _feed(stream, list(range(0, len(stream), 100)))
    assert len(frames) == 2
    assert decoder.errors["oversize"] == 1
    assert decoder.bytes_dropped == 10_000
    assert decoder.pending_bytes == 0
