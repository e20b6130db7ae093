"""Simulated VN200: rates, noise, and real VectorNav binary packets."""

import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hil_sim.sensors.geodesy import lla_to_ned
from hil_sim.sensors.imu import ImuNoiseConfig
from hil_sim.sensors.vn200 import (
    PACKET_SIZE,
    ROVER_COMMON_MASK,
    Vn200,
    Vn200Config,
    Vn200Parser,
    Vn200Samples,
    encode_vn200_packets,
    packet_length,
    vn_crc16,
    vn_crc16_bulk,
)
from hil_sim.world import kinematics as k


@pytest.fixture(scope="module")
def flight():
    tr = k.circle(20.0, radius_m=5.0, speed_m_s=2.0, rate_hz=1000.0)
    vn = Vn200(rng=np.random.default_rng(11))
    samples = vn.measure(tr)
    return tr, vn, samples, vn.stream(samples)


def test_crc_is_crc16_xmodem():
    # The check value of CRC-16/XMODEM: the C parser uses the same vector.
    assert vn_crc16(b"123456789") == 0x31C3


@given(st.lists(st.binary(min_size=5, max_size=5), min_size=1, max_size=20))
def test_bulk_crc_equals_bytewise_crc(rows):
    arr = np.frombuffer(b"".join(rows), dtype=np.uint8).reshape(len(rows), 5)
    assert list(vn_crc16_bulk(arr)) == [vn_crc16(r) for r in rows]


def test_rate_is_150_hz_and_packets_are_88_bytes(flight):
    _, _, samples, stream = flight
    assert np.allclose(np.diff(samples.t_s), 1 / 150.0)
    assert len(samples) == 3000
    assert PACKET_SIZE == 88 and np.all(np.diff(stream.offsets) == 88)
    assert packet_length(0x01, [ROVER_COMMON_MASK]) == 88


def test_packets_decode_with_valid_crc_to_the_measured_values(flight):
    _, _, samples, stream = flight
    parser = Vn200Parser()
    packets = parser.feed(stream.data)
    assert parser.crc_errors == 0 and parser.bytes_skipped == 0
    assert len(packets) == len(samples)
    for i in (0, 1234, len(samples) - 1):
        raw = stream.chunk(i)
        assert raw[0] == 0xFA and raw[1] == 0x01
        assert struct.unpack("<H", raw[2:4])[0] == 0x11E9
        assert vn_crc16(raw[1:]) == 0  # CRC appended big-endian
        assert struct.unpack(">H", raw[-2:])[0] == vn_crc16(raw[1:-2])
        v = packets[i].common()
        assert v["time_startup_ns"] == samples.time_startup_ns[i]
        assert np.allclose(v["ypr_deg"], samples.ypr_deg[i], rtol=1e-6, atol=1e-5)
        assert np.allclose(v["rates_body_rad_s"], samples.rates_body_rad_s[i], atol=1e-6)
        assert np.array_equal(v["lla"], samples.lla[i])  # f64 on the wire
        assert np.allclose(v["vel_ned_m_s"], samples.vel_ned_m_s[i], atol=1e-6)
        assert np.allclose(v["accel_body_m_s2"], samples.accel_body_m_s2[i], atol=1e-5)
        assert v["ins_status"] == 0x0006


def test_parser_counts_bad_crc_and_resyncs_on_next_packet(flight):
    _, _, _, stream = flight
    data = bytearray(stream.data[: 10 * PACKET_SIZE])
    data[3 * PACKET_SIZE + 40] ^= 0x10  # corrupt packet 3
    noisy = b"\x00\xfa\x13garbage" + bytes(data)
    parser = Vn200Parser()
    packets = []
    for i in range(0, len(noisy), 7):  # arbitrary chunking
        packets += parser.feed(noisy[i : i + 7])
    assert len(packets) == 9
    assert parser.crc_errors >= 1


def test_parser_sizes_other_groups_and_skips_unknown_fields():
    # Group 1 (TimeStartup) + group 3 (IMU: UncompMag bit 1 = 12 B, Temp bit 4 = 4 B).
    body = bytes([0x05]) + struct.pack("<HH", 0x0001, 0x0012)
    body += struct.pack("<Q", 123) + struct.pack("<3f", 1, 2, 3) + struct.pack("<f", 25.0)
    packet = b"\xfa" + body + struct.pack(">H", vn_crc16(body))
    parser = Vn200Parser()
    (p,) = parser.feed(packet)
    assert p.masks == {1: 0x0001, 3: 0x0012}
    assert p.common()["time_startup_ns"] == 123
    assert struct.unpack("<f", p.fields[(3, 4)])[0] == 25.0


def test_accel_at_rest_reads_minus_g_and_noise_matches_datasheet():
    vn = Vn200(Vn200Config(imu=ImuNoiseConfig(gyro_bias_walk_rad_s2_rthz=0.0,
                                              accel_bias_walk_m_s3_rthz=0.0)),
               rng=np.random.default_rng(3))
    s = vn.measure(k.hover(30.0, 1000.0))
    assert s.accel_body_m_s2[:, 2].mean() == pytest.approx(-k.GRAVITY_M_S2, abs=5e-3)
    # 0.14 mg/sqrt(Hz) at 150 Hz and 0.0035 deg/s/sqrt(Hz).
    assert s.accel_body_m_s2.std(axis=0) == pytest.approx([1.37e-3 * np.sqrt(150)] * 3, rel=0.05)
    assert s.rates_body_rad_s.std(axis=0) == pytest.approx([6.1e-5 * np.sqrt(150)] * 3, rel=0.05)


def test_attitude_and_position_errors_have_configured_size(flight):
    tr, vn, samples, _ = flight
    truth = tr.at(samples.t_s)
    yaw_err = (samples.ypr_deg[:, 0] - np.degrees(truth.euler_rad[:, 2]) + 180) % 360 - 180
    assert np.sqrt(np.mean(yaw_err**2)) < 4 * 0.3
    ned = lla_to_ned(samples.lla, vn.config.origin_lla)
    err = ned - truth.pos_ned_m
    assert np.all(np.abs(err[:, :2]) < 5 * 1.77) and np.all(np.abs(err[:, 2]) < 5 * 5.0)
    # Errors are correlated (INS/GNSS), not white: consecutive samples barely differ.
    assert np.abs(np.diff(err, axis=0)).max() < 0.5


def test_stream_times_follow_samples_and_fit_the_baud(flight):
    _, vn, samples, stream = flight
    assert np.allclose(stream.t_s - samples.t_s, vn.config.latency_s)
    assert np.all(stream.end_times_s()[:-1] < stream.t_s[1:])
    with pytest.raises(ValueError, match="baud"):
        Vn200Config(baud=115200)  # 88 B x 150 Hz x 10 bits > 115200


finite32 = st.floats(-1e6, 1e6, allow_nan=False, width=32)


@settings(max_examples=50)
@given(st.lists(st.tuples(st.integers(0, 2**64 - 1), st.tuples(*[finite32] * 12),
                          st.tuples(st.floats(-90, 90), st.floats(-180, 180),
                                    st.floats(-1e3, 1e4)),
                          st.integers(0, 0xFFFF)), min_size=1, max_size=8))
def test_any_values_round_trip_through_packets(rows):
    # Codec property: whatever the INS reports, the packet carries it bit-exactly.
    n = len(rows)
    f32 = np.array([r[1] for r in rows], dtype=np.float32).astype(float)
    samples = Vn200Samples(
        t_s=np.arange(n) / 150.0,
        time_startup_ns=np.array([r[0] for r in rows], dtype=np.uint64),
        ypr_deg=f32[:, 0:3], rates_body_rad_s=f32[:, 3:6], lla=np.array([r[2] for r in rows]),
        vel_ned_m_s=f32[:, 6:9], accel_body_m_s2=f32[:, 9:12],
        ins_status=np.array([r[3] for r in rows], dtype=np.uint16), imu_errors=None)
    packets = Vn200Parser().feed(encode_vn200_packets(samples).tobytes())
    assert len(packets) == n
    for i, p in enumerate(packets):
        v = p.common()
        assert v["time_startup_ns"] == rows[i][0] and v["ins_status"] == rows[i][3]
        assert np.array_equal(v["lla"], samples.lla[i])
        assert np.array_equal(v["accel_body_m_s2"], samples.accel_body_m_s2[i])
        assert np.array_equal(v["ypr_deg"], samples.ypr_deg[i])


@settings(max_examples=50)
@given(st.lists(st.binary(max_size=40), min_size=11, max_size=11))
def test_parser_recovers_every_packet_between_garbage(gaps):
    # Resync property: bytes between packets (even 0xFA) never cost a valid packet.
    tr = k.hover(10 / 150.0, 1000.0)
    stream = Vn200(rng=np.random.default_rng(0)).stream(Vn200(rng=np.random.default_rng(0))
                                                        .measure(tr))
    data = b"".join(g + stream.chunk(i) for i, g in enumerate(gaps[: len(stream)]))
    data += gaps[-1]
    packets = Vn200Parser().feed(data)
    assert len(packets) >= len(stream)
    decoded = [p.common()["time_startup_ns"] for p in packets]
    for i in range(len(stream)):
        assert int(np.frombuffer(stream.chunk(i)[4:12], "<u8")[0]) in decoded
