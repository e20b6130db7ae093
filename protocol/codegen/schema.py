"""Load and validate protocol/messages/*.toml and protocol/links.toml; compute hashes.

stdlib only (the generator runs before any package is installed).

Definition hash (FNV-1a 32) over the canonical text of a message:

    airwake-msg/1 <name> <id>\n
    <field name> <type> <count>\n        (one line per field, wire order)

Descriptions, units text, rates and enum/bit names are not part of it: units and
frame are part of the field names (STYLE 7), so changing them changes the hash.
The CRC seed is the 16-bit fold of that hash: seed = (h >> 16) ^ (h & 0xFFFF).
Schema hash = FNV-1a 32 over the message hashes as 4 little-endian bytes each,
in id order.
"""

from __future__ import annotations

import re
import struct
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

# type -> (struct code, size, C type, min, max)
TYPES: dict[str, tuple[str, int, str, float, float]] = {
    "u8": ("B", 1, "uint8_t", 0, 2**8 - 1),
    "u16": ("H", 2, "uint16_t", 0, 2**16 - 1),
    "u32": ("I", 4, "uint32_t", 0, 2**32 - 1),
    "u64": ("Q", 8, "uint64_t", 0, 2**64 - 1),
    "i8": ("b", 1, "int8_t", -(2**7), 2**7 - 1),
    "i16": ("h", 2, "int16_t", -(2**15), 2**15 - 1),
    "i32": ("i", 4, "int32_t", -(2**31), 2**31 - 1),
    "i64": ("q", 8, "int64_t", -(2**63), 2**63 - 1),
    "f32": ("f", 4, "float", -3.4028234663852886e38, 3.4028234663852886e38),
    "f64": ("d", 8, "double", -1.7976931348623157e308, 1.7976931348623157e308),
}

# unit -> the suffix a field name must end with (STYLE 7: units in the name).
# Units mapped to None carry no suffix rule (counters, enums, bit fields, text).
UNIT_SUFFIX: dict[str, str | None] = {
    "rad/s": "_rad_s",
    "rad": "_rad",
    "deg": "_deg",
    "m/s^2": "_m_s2",
    "m/s": "_m_s",
    "m": "_m",
    "mm": "_mm",
    "mm/s": "_mm_s",
    "uT": "_ut",
    "degC": "_c",
    "us": "_us",
    "ms": "_ms",
    "ns": "_ns",
    "px": "_px",
    "counts": "_counts",
    "unit vector": "_unit",
    "1/65535": "_q16",
    "1": None,
    "enum": None,
    "bits": None,
    "hash": "_hash",
    "text": "_utf8",
}

HEADER_SIZE = 7  # msg_id u8, seq u8, flags u8, board_time_us u32
CRC_SIZE = 2
FRAME_OVERHEAD = HEADER_SIZE + CRC_SIZE
ORIGIN_MASK = 0x07
NAME_RE = re.compile(r"^[a-z][a-z0-9_]*$")
MESSAGE_KEYS = {"name", "id", "description", "time", "rate_hz", "to", "rate_note", "fields",
                "frozen_hash"}
FIELD_KEYS = {"name", "type", "count", "unit", "description", "values", "bits"}
# Header columns of the host's decoded tables (airwake.link.batch): not payload names.
RESERVED_FIELD_NAMES = {"byte_offset", "seq", "flags", "origin", "board_time_us"}


class SchemaError(Exception):
    """A message definition is invalid; the text names file, field and value."""


def fnv1a32(data: bytes) -> int:
    h = 0x811C9DC5
    for b in data:
        h ^= b
        h = (h * 0x01000193) & 0xFFFFFFFF
    return h


def fold16(h: int) -> int:
    """CRC seed from a 32-bit definition hash."""
    return ((h >> 16) ^ h) & 0xFFFF


@dataclass
class Field:
    name: str
    type: str
    count: int
    unit: str
    description: str
    values: dict[int, str] | None = None
    bits: dict[int, str] | None = None

    @property
    def code(self) -> str:
        return TYPES[self.type][0]

    @property
    def elem_size(self) -> int:
        return TYPES[self.type][1]

    @property
    def size(self) -> int:
        return self.elem_size * self.count

    @property
    def ctype(self) -> str:
        return TYPES[self.type][2]

    @property
    def is_float(self) -> bool:
        return self.type.startswith("f")


@dataclass
class Message:
    name: str
    id: int
    description: str
    time: str
    rate_hz: dict[str, float]
    to: list[str]
    rate_note: str
    fields: list[Field]
    frozen_hash: int | None
    path: Path
    offsets: list[int] = field(default_factory=list)

    @property
    def canonical_text(self) -> str:
        lines = [f"airwake-msg/1 {self.name} {self.id}"]
        lines += [f"{f.name} {f.type} {f.count}" for f in self.fields]
        return "\n".join(lines) + "\n"

    @property
    def def_hash(self) -> int:
        return fnv1a32(self.canonical_text.encode())

    @property
    def crc_seed(self) -> int:
        return fold16(self.def_hash)

    @property
    def payload_size(self) -> int:
        return sum(f.size for f in self.fields)

    @property
    def raw_frame_size(self) -> int:
        return FRAME_OVERHEAD + self.payload_size

    @property
    def wire_max(self) -> int:
        """Longest wire form: leading 0x00, COBS, trailing 0x00."""
        return cobs_max_encoded(self.raw_frame_size) + 2

    @property
    def payload_format(self) -> str:
        return "<" + "".join(f"{f.count if f.count > 1 else ''}{f.code}" for f in self.fields)

    @property
    def frame_format(self) -> str:
        return "<BBBI" + self.payload_format[1:] + "H"

    @property
    def host_to_board(self) -> bool:
        return "host" in self.rate_hz and len(self.rate_hz) == 1

    @property
    def frozen(self) -> bool:
        return self.frozen_hash is not None

    @property
    def class_name(self) -> str:
        return "".join(p.capitalize() for p in self.name.split("_"))


@dataclass
class Links:
    boards: dict[str, int]
    links: dict[str, dict]
    paths: dict[str, dict]


def cobs_max_encoded(n: int) -> int:
    """Longest COBS encoding of n bytes (no zeros at all: one code byte per 254)."""
    return n + max(1, -(-n // 254))


def schema_hash(messages: list[Message]) -> int:
    return fnv1a32(b"".join(struct.pack("<I", m.def_hash) for m in messages))


def _int_keyed(table: dict, where: str) -> dict[int, str]:
    out = {}
    for key, label in table.items():
        if not str(key).isdigit() or not isinstance(label, str) or not NAME_RE.match(label):
            raise SchemaError(f"{where}: entry {key!r} = {label!r} must be "
                              "<integer> = \"snake_name\"")
        out[int(key)] = label
    return dict(sorted(out.items()))


def _load_field(raw: dict, where: str) -> Field:
    unknown = set(raw) - FIELD_KEYS
    if unknown:
        raise SchemaError(f"{where}: unknown key(s) {sorted(unknown)}; "
                          f"allowed {sorted(FIELD_KEYS)}")
    for key in ("name", "type", "unit", "description"):
        if not isinstance(raw.get(key), str) or not raw[key]:
            raise SchemaError(f"{where}: '{key}' missing or not a non-empty string")
    name, ftype, unit = raw["name"], raw["type"], raw["unit"]
    where = f"{where} ('{name}')"
    if not NAME_RE.match(name) or name in RESERVED_FIELD_NAMES:
        raise SchemaError(f"{where}: name must be snake_case and not one of "
                          f"{sorted(RESERVED_FIELD_NAMES)}")
    if ftype not in TYPES:
        raise SchemaError(f"{where}: type {ftype!r} unknown; one of {sorted(TYPES)}")
    if unit not in UNIT_SUFFIX:
        raise SchemaError(f"{where}: unit {unit!r} unknown; one of {sorted(UNIT_SUFFIX)}")
    suffix = UNIT_SUFFIX[unit]
    if suffix and not name.endswith(suffix):
        raise SchemaError(f"{where}: unit {unit!r} requires the name to end with '{suffix}'")
    count = raw.get("count", 1)
    if not isinstance(count, int) or isinstance(count, bool) or not 1 <= count <= 1024:
        raise SchemaError(f"{where}: count {count!r} must be an integer 1..1024")
    values = _int_keyed(raw["values"], f"{where} values") if "values" in raw else None
    bits = _int_keyed(raw["bits"], f"{where} bits") if "bits" in raw else None
    if (values and unit != "enum") or (bits and unit != "bits"):
        raise SchemaError(f"{where}: 'values' needs unit \"enum\", 'bits' needs unit \"bits\"")
    return Field(name, ftype, count, unit, raw["description"].strip(), values, bits)


def load_message(path: Path, board_names: set[str]) -> Message:
    try:
        raw = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise SchemaError(f"{path}: {exc}") from exc
    unknown = set(raw) - MESSAGE_KEYS
    if unknown:
        raise SchemaError(f"{path}: unknown key(s) {sorted(unknown)}; "
                          f"allowed {sorted(MESSAGE_KEYS)}")
    for key in ("name", "description", "time"):
        if not isinstance(raw.get(key), str) or not raw[key].strip():
            raise SchemaError(f"{path}: '{key}' missing or empty")
    name = raw["name"]
    if not NAME_RE.match(name) or path.stem != name:
        raise SchemaError(f"{path}: name {name!r} must be snake_case and equal the file name")
    msg_id = raw.get("id")
    if not isinstance(msg_id, int) or not 1 <= msg_id <= 255:
        raise SchemaError(f"{path}: id {msg_id!r} must be an integer 1..255 (0 is reserved)")
    rates = raw.get("rate_hz")
    if not isinstance(rates, dict) or not rates:
        raise SchemaError(f"{path}: [rate_hz] missing: nominal rate per sending board")
    for board, rate in rates.items():
        if board not in board_names:
            raise SchemaError(f"{path}: rate_hz.{board}: unknown board; "
                              f"one of {sorted(board_names)}")
        if not isinstance(rate, int | float) or rate < 0:
            raise SchemaError(f"{path}: rate_hz.{board} = {rate!r} must be a number >= 0")
    to = raw.get("to", [])
    if "host" in rates and not to:
        raise SchemaError(f"{path}: host-sent message needs 'to' (receiving boards)")
    for board in to:
        if board not in board_names:
            raise SchemaError(f"{path}: to: unknown board {board!r}")
    fields_raw = raw.get("fields")
    if not isinstance(fields_raw, list) or not fields_raw:
        raise SchemaError(f"{path}: no [[fields]]")
    fields = [_load_field(f, f"{path} field {i}") for i, f in enumerate(fields_raw)]
    seen = set()
    for f in fields:
        if f.name in seen:
            raise SchemaError(f"{path}: field name {f.name!r} used twice")
        seen.add(f.name)
    msg = Message(name, msg_id, raw["description"].strip(), raw["time"].strip(),
                  {k: float(v) for k, v in rates.items()}, list(to),
                  raw.get("rate_note", ""), fields, raw.get("frozen_hash"), path)
    offset = 0
    for f in fields:
        msg.offsets.append(offset)
        offset += f.size
    if msg.frozen and msg.def_hash != msg.frozen_hash:
        raise SchemaError(
            f"{path}: '{name}' is frozen (frozen_hash = 0x{msg.frozen_hash:08X}) but its "
            f"definition now hashes to 0x{msg.def_hash:08X}: frozen layouts never change; "
            "add a new message instead")
    return msg


def load_links(path: Path) -> Links:
    raw = tomllib.loads(path.read_text())
    boards = raw["boards"]
    if sorted(boards.values()) != list(range(len(boards))) or max(boards.values()) > ORIGIN_MASK:
        raise SchemaError(f"{path}: board ids must be 0..{ORIGIN_MASK}, dense")
    for board, spec in raw["paths"].items():
        for link in spec["links"]:
            if link not in raw["links"]:
                raise SchemaError(f"{path}: paths.{board}: unknown link {link!r}")
    return Links(boards, raw["links"], raw["paths"])


def load_schema(protocol_dir: Path) -> tuple[list[Message], Links]:
    links = load_links(protocol_dir / "links.toml")
    messages = [load_message(p, set(links.boards))
                for p in sorted((protocol_dir / "messages").glob("*.toml"))]
    by_id: dict[int, Message] = {}
    for m in messages:
        if m.id in by_id:
            raise SchemaError(f"{m.path}: id 0x{m.id:02X} already used by {by_id[m.id].path}")
        by_id[m.id] = m
    messages.sort(key=lambda m: m.id)
    hashes: dict[int, Message] = {}
    for m in messages:
        if m.def_hash in hashes:
            raise SchemaError(f"{m.path}: definition hash collides with {hashes[m.def_hash].path}")
        hashes[m.def_hash] = m
    return messages, links
