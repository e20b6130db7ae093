"""Recording writer and reader: encodings, recovery after a cut, write failures."""

from __future__ import annotations

import errno
import json
import math
import os
import re
import shutil
import struct

import numpy as np
import pytest
from airwake.link.messages import BY_NAME, MESSAGES, Ins
from airwake.record import recording as recording_mod
from airwake.record.reader import open_recording
from airwake.record.recording import (
    GuardedFile,
    RecordingError,
    RecordingWriter,
    decode_decoded,
    encode_decoded,
    ros1_schema,
)
from hypothesis import given, settings
from hypothesis import strategies as st

ROS1 = {"uint8": "B", "uint16": "H", "uint32": "I", "uint64": "Q", "int8": "b",
        "int16": "h", "int32": "i", "int64": "q", "float32": "f", "float64": "d"}


def parse_ros1(schema: str, data: bytes) -> dict:
    """A tiny independent ros1msg reader (fixed-size fields only, as ours are)."""
    out, offset = {}, 0
    for line in schema.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        typ, name = line.split()
        m = re.fullmatch(r"(\w+)(?:\[(\d+)\])?", typ)
        code, count = ROS1[m.group(1)], int(m.group(2) or 1)
        fmt = "<" + code * count
        values = struct.unpack_from(fmt, data, offset)
        offset += struct.calcsize(fmt)
        out[name] = values[0] if count == 1 and not m.group(2) else values
    assert offset == len(data), "schema does not cover the bytes exactly"
    return out


def finite_record(info, rng: np.random.Generator):
    fields = {}
    for f in info.fields:
        if f.type.startswith("f"):
            v = rng.normal(0, 100, f.count).tolist()
        else:
            bits = int(f.type[1:])
            lo = -(2 ** (bits - 1)) if f.type.startswith("i") else 0
            hi = 2 ** (bits - 1) - 1 if f.type.startswith("i") else 2**bits - 1
            v = [int(x) for x in rng.integers(lo, hi, f.count, endpoint=True, dtype=np.uint64
                                              if lo == 0 else np.int64)]
        fields[f.name] = v[0] if f.count == 1 else tuple(v)
    return info.record(**fields)


@pytest.mark.parametrize("info", MESSAGES, ids=[m.name for m in MESSAGES])
def test_ros1_schema_matches_the_decoded_bytes(info):
    # Foxglove/PlotJuggler decode our channels from the schema alone: it must be exact
    rng = np.random.default_rng(info.id)
    msg = finite_record(info, rng)
    data = encode_decoded(info, msg, 17, 123456, -5, 2)
    parsed = parse_ros1(ros1_schema(info), data)
    assert (parsed["seq"], parsed["board_time_us"], parsed["board_us"], parsed["epoch"]) == \
        (17, 123456, -5, 2)
    header, back = decode_decoded(info, data)
    assert header == (17, 123456, -5, 2)
    for f in info.fields:
        a, b = parsed[f.name], getattr(back, f.name)
        if f.type.startswith("f"):
            np.testing.assert_array_equal(np.float32(a) if f.type == "f32" else a, b)
        else:
            assert tuple(np.atleast_1d(a)) == tuple(np.atleast_1d(b))


def write_messages(directory, n: int, flush_every: int):
    """A recording with n raw + n decoded messages, flushed every flush_every."""
    w = RecordingWriter(directory, {"note": "test"}, flush_s=math.inf)
    info = BY_NAME["ins"]
    for i in range(n):
        w.raw("/raw/base", 1000 + i, bytes([i % 251 + 1]) * 40)
        w.decoded("/rover/ins", info, 2000 + i, 1000 + i,
                  encode_decoded(info, Ins(time_startup_ns=i), i % 256, i, i, 0))
        if (i + 1) % flush_every == 0:
            w._flush_segment()
    return w


def test_clean_close_is_indexed_and_complete(tmp_path):
    w = write_messages(tmp_path / "rec", 500, 100)
    w.close({"frames": 500})
    rec = open_recording(tmp_path / "rec")
    assert rec.complete and rec.segments[0].indexed
    assert rec.topics() == {"/raw/base": 500, "/rover/ins": 500}
    assert rec.summary == {"frames": 500} and rec.metadata["note"] == "test"
    ins = rec.table("/rover/ins")
    assert ins.rows["time_startup_ns"].tolist() == list(range(500))
    assert ins.log_ns.tolist() == list(range(2000, 2500))
    raw = rec.raw("base")
    assert len(raw.data) == 500 * 40 and raw.rx_ns_at([0, 39, 40])[2] == 1001


@settings(max_examples=25, deadline=None)
@given(cut=st.floats(0.05, 0.999))
def test_cut_anywhere_reads_back_every_flushed_message_in_order(tmp_path_factory, cut):
    # kill -9 leaves a file cut at an arbitrary byte: the reader returns a clean prefix
    d = tmp_path_factory.mktemp("cut")
    w = write_messages(d / "rec", 400, 50)
    path = w.segments[0]
    flushed = path.stat().st_size  # 8 flushes of 50 messages each, unclosed
    os.truncate(path, int(flushed * cut))
    rec = open_recording(d / "rec")
    assert not rec.complete
    got = rec.table("/rover/ins").rows["time_startup_ns"].tolist()
    assert got == list(range(len(got)))  # a prefix, in order, nothing garbled
    # every 50-message chunk wholly before the cut is there
    assert len(got) % 50 == 0
    assert len(rec.raw("base").data) == 40 * len(got)


def test_guarded_file_truncates_back_to_the_last_flush(tmp_path, monkeypatch):
    # a write that fails half-way (disk full) must not leave a torn record behind
    f = GuardedFile(tmp_path / "x.mcap")
    f.write(b"a" * 1000)
    f.flush()
    real_write = os.write
    calls = {"n": 0}

    def failing(fd, data):
        calls["n"] += 1
        if calls["n"] == 1:
            return real_write(fd, bytes(data[:300]))  # a partial write first
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(recording_mod.os, "write", failing)
    f.write(b"b" * 1000)
    with pytest.raises(RecordingError, match=r"x\.mcap.*No space left on device"):
        f.flush()
    monkeypatch.setattr(recording_mod.os, "write", real_write)
    f.close()
    assert (tmp_path / "x.mcap").read_bytes() == b"a" * 1000
    assert f.tell() == 1000


def test_writer_failure_stops_cleanly_and_keeps_what_was_written(tmp_path, monkeypatch):
    w = write_messages(tmp_path / "rec", 200, 50)
    real_write = os.write
    monkeypatch.setattr(recording_mod.os, "write",
                        lambda fd, data: (_ for _ in ()).throw(OSError(errno.EFBIG,
                                                                       "File too large")))
    info = BY_NAME["ins"]
    for i in range(200, 260):
        w.decoded("/rover/ins", info, 2000 + i, 1000 + i,
                  encode_decoded(info, Ins(time_startup_ns=i), i % 256, i, i, 0))
    w._flush_segment()
    assert w.failed and "File too large" in w.failed and "segment-0000.mcap" in w.failed
    assert not w.active
    w.raw("/raw/base", 5, b"ignored")  # writes after the failure are dropped quietly
    monkeypatch.setattr(recording_mod.os, "write", real_write)
    w.close({"x": 1})
    rec = open_recording(tmp_path / "rec")
    assert rec.table("/rover/ins").rows["time_startup_ns"].tolist() == list(range(200))


def test_segments_rotate_and_read_as_one_recording(tmp_path):
    w = RecordingWriter(tmp_path / "rec", {}, segment_s=0.0)
    info = BY_NAME["ins"]
    for i in range(30):
        w.decoded("/rover/ins", info, i, i,
                  encode_decoded(info, Ins(time_startup_ns=i), i, i, i, 0))
        if i % 10 == 9:
            w.tick(1e9 + i)  # segment_s = 0: every tick rotates
    w.board("rover", {"board_id": 3})
    w.close({})
    rec = open_recording(tmp_path / "rec")
    assert len(rec.segments) == 4 and rec.complete
    assert rec.table("/rover/ins").rows["time_startup_ns"].tolist() == list(range(30))
    assert rec.boards == {"rover": {"board_id": 3}}


def test_refuses_to_overwrite_a_recording(tmp_path):
    w = write_messages(tmp_path / "rec", 10, 10)
    w.close()
    with pytest.raises(RecordingError, match="not empty"):
        RecordingWriter(tmp_path / "rec", {})
    shutil.rmtree(tmp_path / "rec")


@pytest.mark.parametrize("closed", [True, False])
def test_recover_keeps_the_json_channels_schemas(tmp_path, closed):
    # /host/pose and /host/airwake_intensity carry their JSON schema; a recovered (copied)
    # recording keeps it, from an indexed segment and from an unfinished one alike
    from airwake.record.reader import recover_recording
    from airwake.tracking.live import POSE_SCHEMA
    from mcap.reader import make_reader

    w = write_messages(tmp_path / "rec", 20, 10)
    for i in range(20):
        w.json("/host/pose", 3000 + i, {"t_s": i, "valid": True}, POSE_SCHEMA)
        w.json("/daemon/events", 3000 + i, {"event": "x"})
    if closed:
        w.close({})
    else:
        w._flush_segment()
    recover_recording(tmp_path / "rec", tmp_path / "copy")
    (seg,) = open_recording(tmp_path / "copy").segments
    with open(seg.path, "rb") as f:
        summary = make_reader(f).get_summary()
    by_topic = {c.topic: summary.schemas[c.schema_id] for c in summary.channels.values()
                if c.schema_id}
    assert by_topic["/host/pose"].name == "airwake.host.pose"
    assert json.loads(by_topic["/host/pose"].data) == POSE_SCHEMA
    assert json.loads(by_topic["/daemon/events"].data) == {"type": "object"}
    assert by_topic["/rover/ins"].name == "airwake/ins"  # decoded frames as before
    assert open_recording(tmp_path / "copy").topics()["/host/pose"] == 20
