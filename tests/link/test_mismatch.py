"""A sender built from another definition is reported as such, never decoded as garbage."""

from __future__ import annotations

from airwake.link.decoder import StreamDecoder
from airwake.link.framing import crc_seed, encode_frame, encode_payload_frame
from airwake.link.messages import (
    BOARD_IDS,
    IMU,
    SCHEMA_HASH,
    Heartbeat,
    Imu,
    SchemaEntry,
)

ROVER = BOARD_IDS["rover"]
NEWER_IMU_HASH = 0x12345678  # what a sender with one more imu field would announce


def _newer_imu_frame(seq: int) -> bytes:
    payload = IMU.pack(Imu(temperature_c=21.5)) + b"\x07"  # one appended u8 field
    return encode_payload_frame(IMU.id, payload, seq, ROVER, 100, seed=crc_seed(NEWER_IMU_HASH))


def test_frame_from_other_definition_is_a_mismatch_once_announced():
    rejected = []
    decoder = StreamDecoder(on_reject=lambda kind, seg: rejected.append((kind, seg)))
    assert decoder.feed(_newer_imu_frame(0)) == []
    assert decoder.errors["crc_error"] == 1  # nothing announced yet: indistinguishable
    announce = encode_frame(SchemaEntry(IMU.id, NEWER_IMU_HASH, 0, 1), 0, ROVER, 99)
    frames = decoder.feed(announce + _newer_imu_frame(1))
    assert [f.name for f in frames] == ["schema_entry"]
    assert decoder.errors["def_mismatch"] == 1
    assert decoder.errors["crc_error"] == 1
    assert rejected[-1] == ("def_mismatch", _newer_imu_frame(1)[1:-1])
    # our own imu definition still decodes
    assert decoder.feed(encode_frame(Imu(), 2, ROVER, 5))[0].name == "imu"


def test_same_length_other_definition_is_not_decoded():
    # a definition with the same size (a renamed field) must not slip through as data
    payload = IMU.pack(Imu(temperature_c=3.0))
    frame = encode_payload_frame(IMU.id, payload, 0, ROVER, 0, seed=crc_seed(NEWER_IMU_HASH))
    decoder = StreamDecoder()
    decoder.feed(encode_frame(SchemaEntry(IMU.id, NEWER_IMU_HASH, 0, 1), 0, ROVER, 0))
    assert decoder.feed(frame) == []
    assert decoder.errors["def_mismatch"] == 1


def test_announcement_is_per_origin_board():
    # the base port carries rover frames: an announcement by the rover says nothing
    # about the base's own imu
    decoder = StreamDecoder()
    decoder.feed(encode_frame(SchemaEntry(IMU.id, NEWER_IMU_HASH, 0, 1), 0, ROVER, 0))
    base = BOARD_IDS["base"]
    payload = IMU.pack(Imu()) + b"\x07"
    decoder.feed(encode_payload_frame(IMU.id, payload, 0, base, 0, seed=crc_seed(NEWER_IMU_HASH)))
    assert decoder.errors == {**decoder.errors, "crc_error": 1, "def_mismatch": 0}


def test_schema_mismatch_names_the_board_and_the_messages():
    decoder = StreamDecoder()
    hb = Heartbeat(board_id=ROVER, fw_version_major=1, fw_version_minor=4, schema_hash=0xDEADBEEF)
    decoder.feed(encode_frame(hb, 0, ROVER, 0)
                 + encode_frame(SchemaEntry(IMU.id, NEWER_IMU_HASH, 0, 2), 0, ROVER, 0)
                 + encode_frame(SchemaEntry(0x99, 0x1, 1, 2), 1, ROVER, 0))
    problems = decoder.schema_problems()
    assert len(problems) == 1
    assert "rover (3)" in problems[0] and "0xDEADBEEF" in problems[0]
    assert "imu" in problems[0] and "0x99" in problems[0] and "1.4.0" in problems[0]


def test_matching_schema_reports_nothing():
    decoder = StreamDecoder()
    decoder.feed(encode_frame(Heartbeat(board_id=ROVER, schema_hash=SCHEMA_HASH), 0, ROVER, 0)
                 + encode_frame(SchemaEntry(IMU.id, IMU.def_hash, 0, 1), 0, ROVER, 0))
    assert decoder.schema_problems() == []
    assert decoder.heartbeats[ROVER].schema_hash == SCHEMA_HASH
