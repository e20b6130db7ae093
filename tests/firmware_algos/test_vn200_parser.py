"""VN-200 parser (firmware/boards/rover/vn200.c) on packets from vn200_packets.py."""

import ctypes as C
import struct

import awboards as A
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from vn200_packets import DECODED, FIELD_SIZES, ROVER_MASK, build_packet, crc16_xmodem, rover_packet

f32 = st.floats(width=32, allow_nan=False)
f64 = st.floats(allow_nan=False)
vec3 = st.tuples(f32, f32, f32)


class Collector:
    def __init__(self):
        self.got: list[dict] = []
        self.callback = A.VN200_HANDLER(self._on)

    def _on(self, _ctx, ins_p):
        ins = ins_p.contents
        self.got.append(
            {
                "present": ins.present,
                "group": ins.group,
                "time_startup_ns": ins.time_startup_ns,
                "ypr_deg": tuple(ins.ypr_deg),
                "angular_rate_rad_s": tuple(ins.angular_rate_rad_s),
                "lla": tuple(ins.lla),
                "vel_ned_m_s": tuple(ins.vel_ned_m_s),
                "accel_m_s2": tuple(ins.accel_m_s2),
                "ins_status": ins.ins_status,
            }
        )


def parse(lib, data: bytes, chunk: int = 1):
    parser = A.Vn200Parser()
    sink = Collector()
    lib.vn200_parser_init(C.byref(parser), sink.callback, None)
    for i in range(0, len(data), chunk):
        lib.vn200_parser_feed(C.byref(parser), data[i : i + chunk], len(data[i : i + chunk]))
    return parser, sink.got


rover_values = st.fixed_dictionaries(
    {
        "time_startup_ns": st.integers(0, 2**64 - 1),
        "ypr_deg": vec3,
        "angular_rate_rad_s": vec3,
        "lla": st.tuples(f64, f64, f64),
        "vel_ned_m_s": vec3,
        "accel_m_s2": vec3,
        "ins_status": st.integers(0, 0xFFFF),
    }
)


def test_rover_configuration_layout(lib):
    # Why: the contract says mask 0x11E9 is 82 payload bytes (88 with sync/header/CRC);
    # the C and Python size tables must agree field by field.
    assert sum(FIELD_SIZES[1][b] for b in range(15) if ROVER_MASK >> b & 1) == 82
    for g, sizes in FIELD_SIZES.items():
        for b in range(15):
            assert lib.vn200_field_size(g, b) == sizes[b], (g, b)
    pkt = rover_packet(1, (0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, -9.8), 0)
    assert len(pkt) == 88 and pkt[1] == 0x01 and pkt[2:4] == b"\xe9\x11"
    assert crc16_xmodem(pkt[1:]) == 0  # CRC over everything after the sync, incl. CRC


@settings(max_examples=300, deadline=None)
@given(rover_values, st.integers(1, 40))
def test_rover_packet_decodes_exactly(lib, values, chunk):
    # Why: every field of the INS packet must arrive bit-exact, however the UART chunks it.
    parser, got = parse(lib, rover_packet(**values), chunk)
    assert parser.crc_errors == 0 and len(got) == 1
    (ins,) = got
    assert ins["present"] == 0x7F
    for name, value in values.items():
        # f32 fields were generated as exact float32 values, the rest round-trip exactly
        assert ins[name] == value, name


field_keys = [(g, b) for g, sizes in FIELD_SIZES.items() for b, n in enumerate(sizes) if n]


@settings(max_examples=300, deadline=None)
@given(st.sets(st.sampled_from(field_keys), min_size=1, max_size=12), st.data())
def test_any_groups_and_masks_skip_unused_fields(lib, keys, data):
    # Why: a VN200 configured with other outputs must still decode what we use and skip
    # the rest by the size tables, never misalign.
    fields, want = {}, {}
    for g, b in sorted(keys):  # group then bit order: a later copy of a field wins
        if (g, b) in DECODED:
            name, fmt = DECODED[(g, b)]
            n = struct.calcsize(fmt) // (8 if "d" in fmt or "Q" in fmt else 4 if "f" in fmt else 2)
            if "f" in fmt:
                vals = data.draw(st.lists(f32, min_size=n, max_size=n))
            elif "d" in fmt:
                vals = data.draw(st.lists(f64, min_size=n, max_size=n))
            else:
                bits = 64 if "Q" in fmt else 16
                vals = [data.draw(st.integers(0, 2**bits - 1))]
            fields[(g, b)] = struct.pack(fmt, *vals)
            want[name] = tuple(struct.unpack(fmt, fields[(g, b)]))
        else:
            size = FIELD_SIZES[g][b]
            fields[(g, b)] = data.draw(st.binary(min_size=size, max_size=size))
    pkt = build_packet(fields)
    parser, got = parse(lib, pkt, 7)
    if len(pkt) > 512:
        assert parser.oversize == 1 and not got
        return
    assert len(got) == 1
    for name, value in want.items():
        have = got[0][name]
        have = have if isinstance(have, tuple) else (have,)
        assert have == value, name


@settings(max_examples=150, deadline=None)
@given(
    st.lists(st.tuples(rover_values, st.binary(max_size=30)), min_size=1, max_size=6),
    st.sets(st.integers(0, 5), max_size=3),
    st.data(),
)
def test_stream_loses_only_corrupted_packets(lib, items, corrupt, data):
    # Why: a bit error on the serial line must cost that one packet (counted) and never
    # the next; garbage between packets (ASCII replies) must be skipped.
    stream = b""
    intact = []
    for i, (values, garbage) in enumerate(items):
        pkt = bytearray(rover_packet(**values))
        if i in corrupt:
            pos = data.draw(st.integers(1, len(pkt) - 1))
            pkt[pos] ^= 1 << data.draw(st.integers(0, 7))
        else:
            intact.append(values["time_startup_ns"])
        stream += garbage.replace(b"\xfa", b"\x00") + bytes(pkt)
    # the line keeps going: a later packet flushes whatever a false start held back
    stream += rover_packet(0, (0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0), 0)
    parser, got = parse(lib, stream)
    assert [g["time_startup_ns"] for g in got][:-1] == intact
    if any(i < len(items) for i in corrupt):
        assert parser.crc_errors + parser.bad_headers + parser.oversize + parser.bytes_dropped > 0


@settings(max_examples=100, deadline=None)
@given(st.binary(max_size=300))
def test_crc16_matches_reference(lib, blob):
    # Why: the same CRC guards VN200 and SBP; one table error breaks both links.
    assert lib.crc16_xmodem_update(0, blob, len(blob)) == crc16_xmodem(blob)


def test_hil_sim_encoder_packets_decode_in_firmware(lib):
    # Why: the shared VN200 contract has two independent sides (hil_sim's encoder, this
    # parser); they must agree byte for byte.
    vn200 = pytest.importorskip("hil_sim.sensors.vn200")
    rng = np.random.default_rng(4)
    k = 50
    samples = vn200.Vn200Samples(
        t_s=np.arange(k) / 150.0,
        time_startup_ns=rng.integers(0, 2**62, k).astype(np.uint64),
        ypr_deg=rng.uniform(-180, 180, (k, 3)),
        rates_body_rad_s=rng.normal(0, 1, (k, 3)),
        lla=np.column_stack(
            [rng.uniform(-90, 90, k), rng.uniform(-180, 180, k), rng.normal(0, 50, k)]
        ),
        vel_ned_m_s=rng.normal(0, 5, (k, 3)),
        accel_body_m_s2=rng.normal(0, 3, (k, 3)) + [0, 0, -9.8],
        ins_status=rng.integers(0, 2**16, k).astype(np.uint16),
        imu_errors=None,
    )
    packets = vn200.encode_vn200_packets(samples)
    parser, got = parse(lib, packets.tobytes(), 64)
    assert parser.crc_errors == 0 and len(got) == k
    f32 = np.float32
    for i, ins in enumerate(got):
        assert ins["time_startup_ns"] == int(samples.time_startup_ns[i])
        assert ins["ypr_deg"] == tuple(samples.ypr_deg[i].astype(f32))
        assert ins["angular_rate_rad_s"] == tuple(samples.rates_body_rad_s[i].astype(f32))
        assert ins["lla"] == tuple(samples.lla[i])
        assert ins["vel_ned_m_s"] == tuple(samples.vel_ned_m_s[i].astype(f32))
        assert ins["accel_m_s2"] == tuple(samples.accel_body_m_s2[i].astype(f32))
        assert ins["ins_status"] == int(samples.ins_status[i])
