"""Cross-language: every message Python → C and C → Python, byte-exact, via ctypes."""

from __future__ import annotations

import ctypes

import pytest
from airwake.link.decoder import StreamDecoder
from airwake.link.framing import encode_frame
from airwake.link.messages import MAX_PAYLOAD_SIZE, MESSAGES
from hypothesis import given, settings
from hypothesis import strategies as st

from .conftest import MESSAGE_IDS, record_strategy, same_record

HEADERS = st.tuples(st.integers(0, 255), st.integers(0, 255), st.integers(0, 2**32 - 1))


def test_ctypes_layout_matches_the_c_structs(clib):
    # if these differ, the struct-level comparisons below would read garbage
    for m in MESSAGES:
        assert ctypes.sizeof(clib.structs[m.id]) == clib.lib.awffi_struct_size(m.id), m.name
    assert clib.lib.awffi_struct_size(0xEE) == 0


@pytest.mark.parametrize("info", MESSAGE_IDS)
@settings(max_examples=30, deadline=None)
@given(data=st.data())
def test_python_encoded_frame_decodes_in_c(clib, info, data):
    record = data.draw(record_strategy(info))
    seq, flags, t_us = data.draw(HEADERS)
    frames, counters = clib.decode(encode_frame(record, seq, flags, t_us))
    assert counters["frames_ok"] == 1 and counters["bytes_dropped"] == 0
    msg_id, c_seq, c_flags, c_t, payload = frames[0]
    assert (msg_id, c_seq, c_flags, c_t) == (info.id, seq, flags, t_us)
    assert payload == info.pack(record)
    assert same_record(clib.unpack(info.id, info.record, payload), record)


@pytest.mark.parametrize("info", MESSAGE_IDS)
@settings(max_examples=30, deadline=None)
@given(data=st.data())
def test_c_encoded_frame_decodes_in_python(clib, info, data):
    record = data.draw(record_strategy(info))
    seq, flags, t_us = data.draw(HEADERS)
    wire = clib.encode(record, seq, flags, t_us)
    assert wire == encode_frame(record, seq, flags, t_us)  # byte-exact, NaN payloads too
    frames = StreamDecoder().feed(wire)
    assert len(frames) == 1
    assert (frames[0].seq, frames[0].flags, frames[0].board_time_us) == (seq, flags, t_us)
    assert same_record(frames[0].msg, record)


def test_largest_payload_fits_the_c_buffers(clib):
    # losa_raw_line is the longest frame: it needs a 0xFF COBS block on both sides
    longest = max(MESSAGES, key=lambda m: m.payload_size)
    assert longest.name == "losa_raw_line" and longest.payload_size == MAX_PAYLOAD_SIZE
    record = longest.record(1, 0x0101, (0x0FFF,) * 128)
    wire = clib.encode(record, 1, 1, 0x01010101)
    assert wire[1] == 0xFF
    assert same_record(StreamDecoder().feed(wire)[0].msg, record)
