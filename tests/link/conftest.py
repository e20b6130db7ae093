"""Shared fixtures for the link tests: the C codec library and record strategies."""

from __future__ import annotations

import ctypes
import fcntl
import math
import subprocess
from pathlib import Path

import pytest
from airwake.link.messages import MESSAGES, FieldInfo, MessageInfo
from hypothesis import strategies as st

REPO = Path(__file__).resolve().parents[2]
LIB = REPO / "build/native/libawproto.so"

INT_RANGE = {"u8": (0, 2**8 - 1), "u16": (0, 2**16 - 1), "u32": (0, 2**32 - 1),
             "u64": (0, 2**64 - 1), "i8": (-(2**7), 2**7 - 1), "i16": (-(2**15), 2**15 - 1),
             "i32": (-(2**31), 2**31 - 1), "i64": (-(2**63), 2**63 - 1)}
CTYPE = {"u8": ctypes.c_uint8, "u16": ctypes.c_uint16, "u32": ctypes.c_uint32,
         "u64": ctypes.c_uint64, "i8": ctypes.c_int8, "i16": ctypes.c_int16,
         "i32": ctypes.c_int32, "i64": ctypes.c_int64, "f32": ctypes.c_float,
         "f64": ctypes.c_double}
MESSAGE_IDS = [pytest.param(m, id=m.name) for m in MESSAGES]


def element_strategy(f: FieldInfo) -> st.SearchStrategy:
    if f.type == "f32":
        return st.floats(width=32)  # NaN, ±inf, −0 and subnormals included
    if f.type == "f64":
        return st.floats()
    lo, hi = INT_RANGE[f.type]
    return st.integers(lo, hi)


def record_strategy(info: MessageInfo) -> st.SearchStrategy:
    """Records of one message with any field values, extremes and non-finite included."""
    fields = {}
    for f in info.fields:
        elem = element_strategy(f)
        fields[f.name] = elem if f.count == 1 else st.tuples(*[elem] * f.count)
    return st.builds(info.record, **fields)


def same_value(a, b) -> bool:
    """Equality that treats NaN as equal to NaN and tells −0.0 from 0.0."""
    if isinstance(a, tuple | list):
        return len(a) == len(b) and all(same_value(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) or isinstance(b, float):
        if math.isnan(a) or math.isnan(b):
            return math.isnan(a) and math.isnan(b)
        return a == b and math.copysign(1, a) == math.copysign(1, b)
    return a == b


def same_record(a, b) -> bool:
    return type(a) is type(b) and all(same_value(x, y) for x, y in zip(a, b, strict=True))


class CLib:
    """ctypes view of build/native/libawproto.so (firmware/tests/test_proto_ffi.c)."""

    def __init__(self, path: Path) -> None:
        self.lib = ctypes.CDLL(str(path))
        self.lib.awffi_struct_size.restype = ctypes.c_size_t
        self.lib.awffi_struct_size.argtypes = [ctypes.c_uint8]
        self.lib.awffi_decode.restype = ctypes.c_long
        self.lib.awffi_decode.argtypes = [ctypes.c_char_p, ctypes.c_size_t, ctypes.c_char_p,
                                          ctypes.c_size_t, ctypes.POINTER(ctypes.c_uint32)]
        self.lib.aw_encode_msg.restype = ctypes.c_int
        self.lib.aw_encode_msg.argtypes = [ctypes.c_char_p, ctypes.c_size_t, ctypes.c_uint8,
                                           ctypes.c_uint8, ctypes.c_uint8, ctypes.c_uint32,
                                           ctypes.c_void_p]
        self.lib.aw_unpack_msg.restype = ctypes.c_int
        self.lib.aw_unpack_msg.argtypes = [ctypes.c_uint8, ctypes.c_void_p, ctypes.c_char_p,
                                           ctypes.c_size_t]
        self.structs = {m.id: self._struct(m) for m in MESSAGES}

    @staticmethod
    def _struct(info: MessageInfo) -> type[ctypes.Structure]:
        fields = [(f.name, CTYPE[f.type] * f.count if f.count > 1 else CTYPE[f.type])
                  for f in info.fields]
        return type(f"aw_{info.name}_t", (ctypes.Structure,), {"_fields_": fields})

    def to_struct(self, record) -> ctypes.Structure:
        info_id = record.MSG_ID
        s = self.structs[info_id]()
        for name, value in zip(record._fields, record, strict=True):
            if isinstance(value, tuple):
                getattr(s, name)[:] = value
            else:
                setattr(s, name, value)
        return s

    def from_struct(self, record_cls, s: ctypes.Structure):
        values = []
        for name in record_cls._fields:
            value = getattr(s, name)
            values.append(tuple(value) if isinstance(value, ctypes.Array) else value)
        return record_cls(*values)

    def encode(self, record, seq: int, flags: int, t_us: int) -> bytes:
        out = ctypes.create_string_buffer(512)
        s = self.to_struct(record)
        n = self.lib.aw_encode_msg(out, len(out), record.MSG_ID, seq, flags, t_us,
                                   ctypes.byref(s))
        assert n > 0, n
        return out.raw[:n]

    def decode(self, data: bytes) -> tuple[list[tuple], dict[str, int]]:
        """Frames (msg_id, seq, flags, board_time_us, payload) and counters of a stream."""
        cap = len(data) + 4096
        out = ctypes.create_string_buffer(cap)
        counters = (ctypes.c_uint32 * 7)()
        n = self.lib.awffi_decode(data, len(data), out, cap, counters)
        assert n >= 0
        frames, pos, raw = [], 0, out.raw
        for _ in range(n):
            size = int.from_bytes(raw[pos + 7:pos + 9], "little")
            frames.append((raw[pos], raw[pos + 1], raw[pos + 2],
                           int.from_bytes(raw[pos + 3:pos + 7], "little"),
                           raw[pos + 9:pos + 9 + size]))
            pos += 9 + size
        names = ("frames_ok", "crc_error", "unknown_id", "def_mismatch", "oversize",
                 "cobs_error", "bytes_dropped")
        return frames, dict(zip(names, counters, strict=True))

    def unpack(self, msg_id: int, record_cls, payload: bytes):
        s = self.structs[msg_id]()
        assert self.lib.aw_unpack_msg(msg_id, ctypes.byref(s), payload, len(payload)) == 0
        return self.from_struct(record_cls, s)


@pytest.fixture(scope="session")
def clib() -> CLib:
    """The C codec, built from the working tree if it is missing or stale."""
    build_firmware_target(LIB)
    return CLib(LIB)


def build_firmware_target(target: Path) -> None:
    """`make -C firmware target`, serialised across pytest-xdist workers by a file lock."""
    target.parent.mkdir(parents=True, exist_ok=True)
    with open(target.parent / ".proto-build.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        subprocess.run(["make", "-s", "-C", str(REPO / "firmware"), str(target)], check=True,
                       stdout=subprocess.DEVNULL)
