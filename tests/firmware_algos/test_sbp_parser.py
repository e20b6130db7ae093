"""SBP parser (firmware/boards/rover/sbp.c): every libsbp test vector in
shared/peers/sbp/*.yaml, and frames produced by the `sbp` PyPI package."""

import base64
import ctypes as C
from pathlib import Path

import awboards as A
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from sbp.navigation import (
    MsgBaselineECEF,
    MsgBaselineNED,
    MsgDops,
    MsgGPSTime,
    MsgPosLLH,
    MsgVelNED,
)

PEERS = A.REPO.parent / "shared" / "peers" / "sbp"

UNION_MEMBER = {
    0x020C: "baseline_ned",
    0x020A: "pos_llh",
    0x020E: "vel_ned",
    0x0102: "gps_time",
    0x020B: "baseline_ecef",
    0x0208: "dops",
    0x0103: "utc_time",
    0x0900: "imu_raw",
}


def _scalar(text: str):
    text = text.strip().strip("'\"")
    for conv in (lambda s: int(s, 0), int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    return text


def load_cases(path: Path) -> list[dict]:
    """The libsbp test-case files' regular subset of YAML (no PyYAML in the venv):
    per case its msg fields, raw_packet and sbp header."""
    cases: list[dict] = []
    section = None
    for line in path.read_text().splitlines():
        if line.startswith("- msg:"):
            cases.append({"fields": {}, "sbp": {}})
            section = "msg"
            continue
        if not cases or not line.strip() or line.startswith(("...", "version")):
            continue
        indent = len(line) - len(line.lstrip())
        key, _, value = line.strip().partition(":")
        if indent == 2:
            section = key
            if key == "raw_packet":
                cases[-1]["raw_packet"] = base64.b64decode(value.strip())
        elif indent == 4 and section == "msg":
            section = "fields" if key == "fields" else "msg"
        elif indent == 6 and section == "fields":
            cases[-1]["fields"][key] = _scalar(value)
        elif indent == 4 and section == "sbp":
            cases[-1]["sbp"][key] = _scalar(value)
    return cases


def _case_params():
    if not PEERS.is_dir():
        return [pytest.param(None, id="no-peers", marks=pytest.mark.skip(f"{PEERS} missing"))]
    params = []
    for path in sorted(PEERS.glob("*.yaml")):
        for i, case in enumerate(load_cases(path)):
            params.append(pytest.param(case, id=f"{path.stem}-{i}"))
    return params


class Collector:
    def __init__(self):
        self.msgs: list[dict] = []
        self.callback = A.SBP_HANDLER(self._on)

    def _on(self, _ctx, msg_p):
        m = msg_p.contents
        decoded = {}
        if m.decoded:
            member = getattr(m.m, UNION_MEMBER[m.msg_type])
            decoded = {name: getattr(member, name) for name, _ in member._fields_}
        self.msgs.append(
            {
                "msg_type": m.msg_type,
                "sender": m.sender,
                "length": m.length,
                "decoded": m.decoded,
                "fields": decoded,
                "payload": bytes(m.payload[: m.length]),
            }
        )


def parse(lib, data: bytes, chunk: int = 1):
    parser = A.SbpParser()
    sink = Collector()
    lib.sbp_parser_init(C.byref(parser), sink.callback, None)
    for i in range(0, len(data), chunk):
        piece = data[i : i + chunk]
        lib.sbp_parser_feed(C.byref(parser), piece, len(piece))
    return parser, sink.msgs


@pytest.mark.parametrize("case", _case_params())
def test_libsbp_vector_decodes_to_exact_fields(lib, case):
    # Why: the Piksi is a real peer; its frames must decode exactly as libsbp does.
    parser, msgs = parse(lib, case["raw_packet"])
    assert parser.crc_errors == 0
    assert len(msgs) == 1
    (m,) = msgs
    hdr = case["sbp"]
    assert m["msg_type"] == hdr["msg_type"]
    assert m["sender"] == hdr["sender"]
    assert m["length"] == hdr["length"]
    assert m["payload"] == base64.b64decode(hdr["payload"])
    assert m["decoded"] == 1
    assert m["fields"] == case["fields"]


def test_every_peer_file_has_cases():
    # Why: a silently empty YAML parse would make the vector test vacuous.
    if not PEERS.is_dir():
        pytest.skip(f"{PEERS} missing")
    for path in PEERS.glob("*.yaml"):
        cases = load_cases(path)
        assert len(cases) == path.read_text().count("- msg:") > 0
        assert all(c["fields"] and c["raw_packet"] for c in cases)


i32 = st.integers(-(2**31), 2**31 - 1)
u32 = st.integers(0, 2**32 - 1)
u16 = st.integers(0, 2**16 - 1)
u8 = st.integers(0, 255)
f64 = st.floats(allow_nan=False, allow_infinity=False)

MESSAGES = {
    MsgBaselineNED: dict(
        tow=u32, n=i32, e=i32, d=i32, h_accuracy=u16, v_accuracy=u16, n_sats=u8, flags=u8
    ),
    MsgVelNED: dict(
        tow=u32, n=i32, e=i32, d=i32, h_accuracy=u16, v_accuracy=u16, n_sats=u8, flags=u8
    ),
    MsgPosLLH: dict(
        tow=u32, lat=f64, lon=f64, height=f64, h_accuracy=u16, v_accuracy=u16, n_sats=u8, flags=u8
    ),
    MsgGPSTime: dict(wn=u16, tow=u32, ns_residual=i32, flags=u8),
    MsgBaselineECEF: dict(tow=u32, x=i32, y=i32, z=i32, accuracy=u16, n_sats=u8, flags=u8),
    MsgDops: dict(tow=u32, gdop=u16, pdop=u16, tdop=u16, hdop=u16, vdop=u16, flags=u8),
}


@st.composite
def sbp_messages(draw):
    cls = draw(st.sampled_from(sorted(MESSAGES, key=lambda c: c.__name__)))
    fields = draw(st.fixed_dictionaries(MESSAGES[cls]))
    return cls(sender=draw(u16), **fields), fields


@settings(max_examples=300, deadline=None)
@given(sbp_messages(), st.binary(max_size=40), st.integers(1, 16))
def test_sbp_package_frames_decode_to_their_fields(lib, msg_fields, garbage, chunk):
    # Why: hil_sim writes the Piksi stream with the sbp package; any field values,
    # any garbage before a frame and any UART chunking must decode exactly.
    msg, fields = msg_fields
    frame = msg.to_binary()
    _, msgs = parse(lib, garbage + frame + frame, chunk)
    ours = [m for m in msgs if m["msg_type"] == msg.msg_type and m["sender"] == msg.sender]
    assert len(ours) >= 2
    assert ours[-1]["fields"] == fields
    assert ours[-2]["fields"] == fields


@settings(max_examples=100, deadline=None)
@given(st.lists(sbp_messages(), min_size=2, max_size=6), st.data())
def test_corrupt_frame_loses_only_itself(lib, msgs, data):
    # Why: a flipped bit on the radio link must cost one frame, counted, never more.
    frames = [m.to_binary() for m, _ in msgs]
    bad = data.draw(st.integers(0, len(frames) - 1))
    pos = data.draw(st.integers(1, len(frames[bad]) - 1))
    corrupted = bytearray(frames[bad])
    corrupted[pos] ^= 1 << data.draw(st.integers(0, 7))
    stream = b"".join(bytes(corrupted) if i == bad else f for i, f in enumerate(frames))
    # the line keeps going: a later frame resolves a corrupted length that points ahead
    trailer = dict(wn=2300, tow=123456, ns_residual=-7, flags=1)
    stream += MsgGPSTime(sender=0x4242, **trailer).to_binary()
    parser, got = parse(lib, stream)
    want = [f for i, (_, f) in enumerate(msgs) if i != bad] + [trailer]
    assert [m["fields"] for m in got] == want
    # the loss shows: a CRC error, or (a corrupted length byte) skipped bytes
    assert parser.crc_errors + parser.bytes_dropped > 0
