"""Python emitter: host/airwake/link/messages.py."""

from __future__ import annotations

import textwrap

from schema import (
    CRC_SIZE,
    FRAME_OVERHEAD,
    HEADER_SIZE,
    ORIGIN_MASK,
    Field,
    Links,
    Message,
    cobs_max_encoded,
    schema_hash,
)

DTYPE = {"u8": "u1", "u16": "<u2", "u32": "<u4", "u64": "<u8", "i8": "i1", "i16": "<i2",
         "i32": "<i4", "i64": "<i8", "f32": "<f4", "f64": "<f8"}


def _pytype(f: Field) -> str:
    base = "float" if f.is_float else "int"
    if f.count == 1:
        return base
    if f.count <= 8:
        return f"tuple[{', '.join([base] * f.count)}]"
    return f"tuple[{base}, ...]"


def _default(f: Field) -> str:
    zero = "0.0" if f.is_float else "0"
    return zero if f.count == 1 else f"({zero},) * {f.count}"


def _slices(m: Message, start: int) -> list[str]:
    """Expressions picking each field out of a flat value tuple `v` from index start."""
    out, i = [], start
    for f in m.fields:
        out.append(f"v[{i}:{i + f.count}]" if f.count > 1 else f"v[{i}]")
        i += f.count
    return out


def _flat_args(m: Message) -> str:
    return ", ".join(f"*m.{f.name}" if f.count > 1 else f"m.{f.name}" for f in m.fields)


def _doc(text: str, indent: str) -> str:
    return textwrap.fill(" ".join(text.split()), 92 - len(indent), initial_indent=indent,
                         subsequent_indent=indent)


def module(messages: list[Message], links: Links) -> str:
    max_raw = max(m.raw_frame_size for m in messages)
    boards = dict(sorted((v, k) for k, v in links.boards.items()))
    out = [textwrap.dedent(f'''\
        """Message definitions of the airwake wire protocol (docs/protocol.md).

        generated from protocol/messages by protocol/codegen — do not edit

        One record class per message (a NamedTuple whose fields carry units and frame in
        their names) and one `MessageInfo` per message with its id, sizes, definition hash,
        CRC seed, precompiled structs, field metadata and numpy dtype description.
        """

        from __future__ import annotations

        from collections.abc import Callable
        from struct import Struct
        from typing import Any, NamedTuple

        SCHEMA_HASH = 0x{schema_hash(messages):08X}
        HEADER_SIZE = {HEADER_SIZE}
        CRC_SIZE = {CRC_SIZE}
        FRAME_OVERHEAD = {FRAME_OVERHEAD}
        MAX_PAYLOAD_SIZE = {max(m.payload_size for m in messages)}
        MAX_RAW_FRAME_SIZE = {max_raw}
        # Longest valid COBS-encoded frame (without delimiters); a longer segment is oversize.
        MAX_ENCODED_SIZE = {cobs_max_encoded(max_raw)}
        FLAGS_ORIGIN_MASK = 0x{ORIGIN_MASK:02X}
        BOARDS = {boards!r}
        BOARD_IDS = {dict(sorted(links.boards.items(), key=lambda kv: kv[1]))!r}
        HEADER = Struct("<BBBI")
        # Records are built with tuple.__new__ on the decode path: the frame struct already
        # guarantees the field count, and skipping NamedTuple's Python-level __new__ halves
        # the cost per frame.
        _new = tuple.__new__


        class FieldInfo(NamedTuple):
            name: str
            type: str
            count: int
            unit: str
            description: str
            values: dict[int, str] | None = None
            bits: dict[int, str] | None = None


        class MessageInfo(NamedTuple):
            id: int
            name: str
            record: type
            payload_size: int
            def_hash: int
            crc_seed: int
            payload_struct: Struct
            frame_struct: Struct  # header, payload fields and CRC of a whole raw frame
            fields: tuple[FieldInfo, ...]
            rate_hz: dict[str, float]
            to: tuple[str, ...]
            frozen: bool
            description: str
            time: str
            pack: Callable[[Any], bytes]
            unpack: Callable[[bytes], Any]
            from_frame: Callable[[tuple], Any]  # record from frame_struct.unpack values
            dtype_descr: tuple

            @property
            def raw_frame_size(self) -> int:
                return FRAME_OVERHEAD + self.payload_size

            @property
            def wire_max(self) -> int:
                """Longest wire form: leading 0x00, COBS, trailing 0x00."""
                raw = self.raw_frame_size
                return raw + max(1, -(-raw // 254)) + 2

        ''')]
    for m in messages:
        n, c = m.name, m.class_name
        up = n.upper()
        has_arrays = any(f.count > 1 for f in m.fields)
        out.append(f"\nclass {c}(NamedTuple):\n")
        out.append(f'    """{n} (0x{m.id:02X}){", frozen layout" if m.frozen else ""}.\n\n')
        out.append(_doc(m.description, "    ") + "\n\n")
        out.append(_doc(f"board_time_us: {m.time}.", "    ") + '\n    """\n\n')
        out.append(f"    MSG_ID = 0x{m.id:02X}\n\n")
        for f in m.fields:
            out.append(f"    {f.name}: {_pytype(f)} = {_default(f)}\n")
        out.append(f"\n\n_S_{up} = Struct({m.payload_format!r})\n")
        out.append(f"_F_{up} = Struct({m.frame_format!r})\n\n\n")
        out.append(f"def _pack_{n}(m: {c}) -> bytes:\n"
                   f"    return _S_{up}.pack({_flat_args(m)})\n\n\n")
        if has_arrays:
            picks = ", ".join(_slices(m, 0))
            out.append(f"def _unpack_{n}(b: bytes) -> {c}:\n    v = _S_{up}.unpack(b)\n"
                       f"    return {c}({picks})\n\n\n")
            picks = ", ".join(_slices(m, 4))
            out.append(f"def _from_frame_{n}(v: tuple) -> {c}:\n"
                       f"    return _new({c}, ({picks}))\n\n\n")
        else:
            out.append(f"def _unpack_{n}(b: bytes) -> {c}:\n"
                       f"    return {c}._make(_S_{up}.unpack(b))\n\n\n")
            out.append(f"def _from_frame_{n}(v: tuple) -> {c}:\n"
                       f"    return _new({c}, v[4:-1])\n\n\n")
        fields = ",\n".join(
            f"        FieldInfo({f.name!r}, {f.type!r}, {f.count}, {f.unit!r}, "
            f"{' '.join(f.description.split())!r}"
            + (f", values={f.values!r}" if f.values else "")
            + (f", bits={f.bits!r}" if f.bits else "") + ")"
            for f in m.fields)
        descr = ", ".join(
            f"({f.name!r}, {DTYPE[f.type]!r}" + (f", ({f.count},))" if f.count > 1 else ")")
            for f in m.fields)
        rates = {k: (int(v) if v == int(v) else v) for k, v in m.rate_hz.items()}
        out.append(textwrap.dedent(f"""\
            {up} = MessageInfo(
                id=0x{m.id:02X},
                name={n!r},
                record={c},
                payload_size={m.payload_size},
                def_hash=0x{m.def_hash:08X},
                crc_seed=0x{m.crc_seed:04X},
                payload_struct=_S_{up},
                frame_struct=_F_{up},
                fields=(
            """))
        out.append(fields + ",\n    ),\n")
        out.append(textwrap.indent(textwrap.dedent(f"""\
            rate_hz={rates!r},
            to={tuple(m.to)!r},
            frozen={m.frozen},
            description={' '.join(m.description.split())!r},
            time={m.time!r},
            pack=_pack_{n},
            unpack=_unpack_{n},
            from_frame=_from_frame_{n},
            dtype_descr=({descr},),
            """), "    "))
        out.append(")\n\n")
    names = ", ".join(m.name.upper() for m in messages)
    out.append(f"\nMESSAGES: tuple[MessageInfo, ...] = ({names})\n")
    out.append("BY_ID: dict[int, MessageInfo] = {m.id: m for m in MESSAGES}\n")
    out.append("BY_NAME: dict[str, MessageInfo] = {m.name: m for m in MESSAGES}\n")
    out.append("BY_RECORD: dict[type, MessageInfo] = {m.record: m for m in MESSAGES}\n")
    return "".join(out)
