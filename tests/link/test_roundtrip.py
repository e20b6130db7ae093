"""Python round trip of every message: record → frame → StreamDecoder → the same record."""

from __future__ import annotations

import pytest
from airwake.link.decoder import StreamDecoder
from airwake.link.framing import ProtocolError, encode_frame
from airwake.link.messages import BY_ID, IMU, MESSAGES, Imu
from hypothesis import given, settings
from hypothesis import strategies as st

from .conftest import MESSAGE_IDS, record_strategy, same_record

HEADERS = st.tuples(st.integers(0, 255), st.integers(0, 255), st.integers(0, 2**32 - 1))


@pytest.mark.parametrize("info", MESSAGE_IDS)
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_every_message_survives_a_python_round_trip(info, data):
    # extremes, NaN and ±inf included: a field that does not come back bit-exact is a bug
    record = data.draw(record_strategy(info))
    seq, flags, t_us = data.draw(HEADERS)
    wire = encode_frame(record, seq, flags, t_us)
    assert wire[0] == 0 and wire[-1] == 0 and 0 not in wire[1:-1]
    assert len(wire) <= info.wire_max
    frames = StreamDecoder().feed(wire)
    assert len(frames) == 1
    f = frames[0]
    assert (f.msg_id, f.seq, f.flags, f.board_time_us) == (info.id, seq, flags, t_us)
    assert same_record(f.msg, record)
    assert same_record(info.unpack(info.pack(record)), record)


def test_message_table_is_consistent():
    # the generated metadata must agree with the structs it describes
    assert len({m.id for m in MESSAGES}) == len(MESSAGES)
    for m in MESSAGES:
        assert BY_ID[m.id] is m
        assert m.payload_struct.size == m.payload_size
        assert m.frame_struct.size == m.payload_size + 9
        n_values = len(m.frame_struct.unpack(bytes(m.frame_struct.size)))
        assert n_values == 4 + sum(f.count for f in m.fields) + 1  # header, fields, CRC
        assert m.record._fields == tuple(f.name for f in m.fields)
        assert m.record.MSG_ID == m.id


def test_out_of_range_value_is_a_clear_error():
    # a user encoding 300 into a u8 must hear which message failed, not a bare struct.error
    with pytest.raises(ProtocolError, match="imu"):
        encode_frame(Imu(status=300))
    with pytest.raises(ProtocolError, match="not a protocol message"):
        encode_frame((1, 2, 3))
    assert IMU.record is Imu
