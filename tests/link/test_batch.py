"""Batch decoding of whole captures: numpy tables equal to what the stream decoder sees."""

from __future__ import annotations

import numpy as np
from airwake.link.batch import decode_capture
from airwake.link.bench import synthetic_capture
from airwake.link.decoder import StreamDecoder
from airwake.link.messages import BY_NAME


def test_batch_tables_match_stream_records():
    data = synthetic_capture(3000, seed=4)
    data = data[:5000] + b"\x13\x37" + data[5000:]  # one corrupted frame
    capture = decode_capture(data)
    frames = StreamDecoder().feed(data)
    assert sum(len(t) for t in capture.tables.values()) == len(frames) == 2999
    for name, table in capture.tables.items():
        mine = [f for f in frames if f.name == name]
        assert len(mine) == len(table)
        info = BY_NAME[name]
        for f, row in zip(mine[:50], table[:50], strict=False):
            assert (row["seq"], row["flags"], row["board_time_us"]) == \
                (f.seq, f.flags, f.board_time_us)
            assert row["origin"] == f.flags & 7
            for field in info.fields:
                expected = np.asarray(getattr(f.msg, field.name))
                np.testing.assert_array_equal(row[field.name], expected)
            assert data[row["byte_offset"]] != 0 and data[row["byte_offset"] - 1] == 0


def test_batch_counts_sequence_gaps_per_origin():
    data = synthetic_capture(2000, seed=5)
    frames = data.split(b"\x00\x00")
    cut = b"\x00\x00".join(frames[:100] + frames[103:])  # three frames lost
    capture = decode_capture(cut)
    decoder = StreamDecoder()
    decoder.feed(cut)
    assert capture.counters()["errors"]["seq_lost"] == 3
    assert capture.lost == decoder.lost_frames()
