"""C emitters: firmware/common/aw_messages.{h,c} and the golden-vector table for C tests."""

from __future__ import annotations

import math
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

BANNER = "/* generated from protocol/messages by protocol/codegen — do not edit */\n"


def _upper(name: str) -> str:
    return name.upper()


def _comment(text: str, indent: str = "") -> str:
    lines = textwrap.wrap(" ".join(text.split()), 88 - len(indent))
    if len(lines) == 1:
        return f"{indent}/* {lines[0]} */\n"
    body = "".join(f"{indent} * {line}\n" for line in lines)
    return f"{indent}/*\n{body}{indent} */\n"


def _field_decl(f: Field) -> str:
    dims = f"[{f.count}]" if f.count > 1 else ""
    unit = "" if f.unit in ("1", "enum", "bits", "text", "hash") else f" [{f.unit}]"
    return f"    {f.ctype} {f.name}{dims}; /* {' '.join(f.description.split())}{unit} */\n"


def header(messages: list[Message], links: Links) -> str:
    max_raw = max(m.raw_frame_size for m in messages)
    out = [BANNER, textwrap.dedent("""\
        /*
         * airwake wire protocol: message ids, sizes, definition hashes, CRC seeds, payload
         * structs and their explicit little-endian pack/unpack. Framing (COBS, CRC, the
         * streaming decoder) is in aw_frame.h; docs/protocol.md is the specification.
         */
        #ifndef AW_MESSAGES_H
        #define AW_MESSAGES_H

        #include <stddef.h>
        #include <stdint.h>

        #include "aw_wire.h"

        #ifdef __cplusplus
        extern "C" {
        #endif

        """)]
    out.append(f"#define AW_SCHEMA_HASH 0x{schema_hash(messages):08X}u\n")
    out.append(f"#define AW_MSG_COUNT {len(messages)}u\n")
    out.append(f"#define AW_HEADER_SIZE {HEADER_SIZE}u\n")
    out.append(f"#define AW_CRC_SIZE {CRC_SIZE}u\n")
    out.append(f"#define AW_FRAME_OVERHEAD {FRAME_OVERHEAD}u\n")
    out.append(f"#define AW_MAX_PAYLOAD_SIZE {max(m.payload_size for m in messages)}u\n")
    out.append(f"#define AW_MAX_RAW_FRAME_SIZE {max_raw}u\n")
    out.append("/* longest valid COBS-encoded frame (without delimiters); longer is oversize */\n")
    out.append(f"#define AW_MAX_ENCODED_SIZE {cobs_max_encoded(max_raw)}u\n")
    out.append("/* longest frame on the wire: leading 0x00, COBS, trailing 0x00 */\n")
    out.append(f"#define AW_MAX_WIRE_SIZE {cobs_max_encoded(max_raw) + 2}u\n\n")
    out.append("/* flags byte: bits 0-2 origin board id, bits 3-7 reserved (send 0, ignore) */\n")
    out.append(f"#define AW_FLAGS_ORIGIN_MASK 0x{ORIGIN_MASK:02X}u\n")
    for board, bid in sorted(links.boards.items(), key=lambda kv: kv[1]):
        out.append(f"#define AW_BOARD_{_upper(board)} {bid}u\n")
    out.append("\n")
    for m in messages:
        up = _upper(m.name)
        frozen = " — frozen layout" if m.frozen else ""
        out.append(f"/* ---- {m.name} (0x{m.id:02X}){frozen} ---- */\n")
        out.append(_comment(m.description))
        out.append(f"#define AW_ID_{up} 0x{m.id:02X}u\n")
        out.append(f"#define AW_SIZE_{up} {m.payload_size}u\n")
        out.append(f"#define AW_HASH_{up} 0x{m.def_hash:08X}u\n")
        out.append(f"#define AW_SEED_{up} 0x{m.crc_seed:04X}u\n")
        out.append(f"#define AW_WIRE_MAX_{up} {m.wire_max}u\n")
        for f in m.fields:
            for value, label in (f.values or {}).items():
                out.append(f"#define AW_{up}_{_upper(f.name)}_{_upper(label)} {value}u\n")
            for bit, label in (f.bits or {}).items():
                out.append(f"#define AW_{up}_{_upper(f.name)}_{_upper(label)} (1u << {bit})\n")
        out.append("typedef struct {\n")
        out += [_field_decl(f) for f in m.fields]
        out.append(f"}} aw_{m.name}_t;\n")
        out.append(f"void aw_pack_{m.name}(uint8_t *out, const aw_{m.name}_t *m);\n")
        out.append(f"void aw_unpack_{m.name}(aw_{m.name}_t *m, const uint8_t *in);\n")
        out.append(f"int aw_encode_{m.name}(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,\n"
                   f"        uint32_t board_time_us, const aw_{m.name}_t *m);\n\n")
    out.append(textwrap.dedent("""\
        /* One row per message, in id order: what a decoder needs. */
        typedef struct {
            uint8_t id;
            uint16_t payload_size;
            uint16_t crc_seed;
            uint32_t def_hash;
            uint16_t struct_size; /* sizeof(aw_<name>_t) */
            const char *name;
        } aw_msg_info_t;

        extern const aw_msg_info_t aw_msg_table[AW_MSG_COUNT];

        /* Row index of msg_id in aw_msg_table, or -1 when the id is unknown. */
        int aw_msg_index(uint8_t msg_id);
        /* Row of msg_id, or NULL when the id is unknown. */
        const aw_msg_info_t *aw_msg_info(uint8_t msg_id);

        /* Storage for any message struct (decoded by id). */
        typedef union {
        """))
    out += [f"    aw_{m.name}_t {m.name};\n" for m in messages]
    out.append(textwrap.dedent("""\
        } aw_any_msg_t;

        /* Dispatch by id. `msg` points to the aw_<name>_t of that id. Return the payload
         * size / frame length, or AW_ERR_UNKNOWN_ID, AW_ERR_NO_SPACE, AW_ERR_SIZE. */
        int aw_pack_msg(uint8_t msg_id, uint8_t *out, size_t cap, const void *msg);
        int aw_unpack_msg(uint8_t msg_id, void *msg, const uint8_t *in, size_t len);
        int aw_encode_msg(uint8_t *out, size_t cap, uint8_t msg_id, uint8_t seq, uint8_t flags,
                          uint32_t board_time_us, const void *msg);

        #ifdef __cplusplus
        }
        #endif

        #endif /* AW_MESSAGES_H */
        """))
    return "".join(out)


def _pack_lines(m: Message, put: bool) -> list[str]:
    lines = []
    for f, off in zip(m.fields, m.offsets, strict=True):
        if put:
            elem = "m->{n}[i]" if f.count > 1 else "m->{n}"
            call = f"aw_put_{f.type}(out + {off}u{{idx}}, {elem.format(n=f.name)});"
        else:
            elem = "&m->{n}[i]" if f.count > 1 else "&m->{n}"
            call = f"aw_get_{f.type}({elem.format(n=f.name)}, in + {off}u{{idx}});"
        if f.count > 1:
            lines.append(f"    for (size_t i = 0; i < {f.count}u; ++i) {{\n"
                         f"        {call.format(idx=f' + {f.elem_size}u * i')}\n    }}\n")
        else:
            lines.append(f"    {call.format(idx='')}\n")
    return lines


def source(messages: list[Message]) -> str:
    out = [BANNER, '#include "aw_messages.h"\n\n#include "aw_frame.h"\n\n']
    for m in messages:
        n = m.name
        out.append(f"void aw_pack_{n}(uint8_t *out, const aw_{n}_t *m)\n{{\n")
        out += _pack_lines(m, put=True)
        out.append("}\n\n")
        out.append(f"void aw_unpack_{n}(aw_{n}_t *m, const uint8_t *in)\n{{\n")
        out += _pack_lines(m, put=False)
        out.append("}\n\n")
        out.append(
            f"int aw_encode_{n}(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,\n"
            f"        uint32_t board_time_us, const aw_{n}_t *m)\n{{\n"
            f"    uint8_t payload[AW_SIZE_{_upper(n)}];\n"
            f"    aw_pack_{n}(payload, m);\n"
            f"    const aw_header_t h = {{AW_ID_{_upper(n)}, seq, flags, board_time_us}};\n"
            f"    return aw_frame_encode(out, cap, &h, payload, sizeof payload);\n}}\n\n")
    out.append("const aw_msg_info_t aw_msg_table[AW_MSG_COUNT] = {\n")
    for m in messages:
        up = _upper(m.name)
        out.append(f"    {{AW_ID_{up}, AW_SIZE_{up}, AW_SEED_{up}, AW_HASH_{up}, "
                   f"sizeof(aw_{m.name}_t), \"{m.name}\"}},\n")
    out.append("};\n\n/* msg id -> row + 1 (0: unknown id) */\n"
               "static const uint8_t aw_row_of[256] = {\n")
    for i, m in enumerate(messages):
        out.append(f"    [0x{m.id:02X}] = {i + 1},\n")
    out.append("};\n\n")
    out.append(textwrap.dedent("""\
        int aw_msg_index(uint8_t msg_id)
        {
            return (int)aw_row_of[msg_id] - 1;
        }

        const aw_msg_info_t *aw_msg_info(uint8_t msg_id)
        {
            const int row = aw_msg_index(msg_id);
            return row < 0 ? NULL : &aw_msg_table[row];
        }

        int aw_pack_msg(uint8_t msg_id, uint8_t *out, size_t cap, const void *msg)
        {
            const aw_msg_info_t *info = aw_msg_info(msg_id);
            if (info == NULL) {
                return AW_ERR_UNKNOWN_ID;
            }
            if (cap < info->payload_size) {
                return AW_ERR_NO_SPACE;
            }
            switch (msg_id) {
        """))
    for m in messages:
        out.append(f"    case AW_ID_{_upper(m.name)}:\n"
                   f"        aw_pack_{m.name}(out, (const aw_{m.name}_t *)msg);\n        break;\n")
    out.append(textwrap.dedent("""\
            default:
                return AW_ERR_UNKNOWN_ID;
            }
            return (int)info->payload_size;
        }

        int aw_unpack_msg(uint8_t msg_id, void *msg, const uint8_t *in, size_t len)
        {
            const aw_msg_info_t *info = aw_msg_info(msg_id);
            if (info == NULL) {
                return AW_ERR_UNKNOWN_ID;
            }
            if (len != info->payload_size) {
                return AW_ERR_SIZE;
            }
            switch (msg_id) {
        """))
    for m in messages:
        out.append(f"    case AW_ID_{_upper(m.name)}:\n"
                   f"        aw_unpack_{m.name}((aw_{m.name}_t *)msg, in);\n        break;\n")
    out.append(textwrap.dedent("""\
            default:
                return AW_ERR_UNKNOWN_ID;
            }
            return 0;
        }

        int aw_encode_msg(uint8_t *out, size_t cap, uint8_t msg_id, uint8_t seq, uint8_t flags,
                          uint32_t board_time_us, const void *msg)
        {
            uint8_t payload[AW_MAX_PAYLOAD_SIZE];
            const int size = aw_pack_msg(msg_id, payload, sizeof payload, msg);
            if (size < 0) {
                return size;
            }
            const aw_header_t h = {msg_id, seq, flags, board_time_us};
            return aw_frame_encode(out, cap, &h, payload, (size_t)size);
        }
        """))
    return "".join(out)


# ---- golden vectors as a C table (firmware/tests/test_proto_vectors.h) ----

def _c_float(x: float, f32: bool) -> str:
    if math.isnan(x):
        return "NAN" if f32 else "(double)NAN"
    if math.isinf(x):
        inf = "INFINITY" if f32 else "(double)INFINITY"
        return inf if x > 0 else f"-{inf}"
    return x.hex() + ("f" if f32 else "")


def _c_int(v: int, f: Field) -> str:
    if f.type == "u64":
        return f"UINT64_C({v})"
    if f.type == "u32":
        return f"{v}u"
    bits = int(f.type[1:])
    if f.type.startswith("i") and v == -(2 ** (bits - 1)):
        lit = f"INT64_C({2 ** (bits - 1) - 1})" if bits == 64 else str(2 ** (bits - 1) - 1)
        return f"(-{lit} - 1)"
    return f"INT64_C({v})" if f.type == "i64" else str(v)


def _c_value(v, f: Field) -> str:
    if f.is_float:
        return _c_float(v, f.type == "f32")
    return _c_int(v, f)


def _c_bytes(data: bytes) -> str:
    items = [f"0x{b:02X}" for b in data]
    rows = [", ".join(items[i:i + 12]) for i in range(0, len(items), 12)]
    return "{\n    " + ",\n    ".join(rows) + "\n}" if rows else "{0}"


def vectors_header(frames: list[dict], streams: list[dict], by_name: dict[str, Message],
                   py_values: dict[str, dict]) -> str:
    out = [BANNER, textwrap.dedent("""\
        /* Golden vectors (protocol/vectors/, JSON) as C data for test_proto_vectors.c. */
        #ifndef TEST_PROTO_VECTORS_H
        #define TEST_PROTO_VECTORS_H

        #include <math.h>
        #include <stddef.h>
        #include <stdint.h>

        #include "aw_frame.h"

        typedef struct {
            const char *name;
            uint8_t msg_id, seq, flags;
            uint32_t board_time_us;
            const void *msg;          /* aw_<name>_t with the decoded values */
            const uint8_t *payload;
            size_t payload_len;
            const uint8_t *frame;     /* on the wire: 0x00, COBS, 0x00 */
            size_t frame_len;
        } aw_vec_frame_t;

        typedef struct {
            uint8_t msg_id, seq, flags;
            uint32_t board_time_us;
            const uint8_t *payload;
            size_t payload_len;
        } aw_vec_decoded_t;

        typedef struct {
            const char *name;
            const uint8_t *bytes;
            size_t len;
            aw_counters_t expect;
            const aw_vec_decoded_t *frames;
            size_t frame_count;
        } aw_vec_stream_t;

        """)]
    rows = []
    for i, v in enumerate(frames):
        m = by_name[v["msg"]]
        values = py_values[v["name"]]
        inits = []
        for f in m.fields:
            val = values[f.name]
            if f.count > 1:
                inits.append(f".{f.name} = {{" + ", ".join(_c_value(x, f) for x in val) + "}")
            else:
                inits.append(f".{f.name} = {_c_value(val, f)}")
        out.append(f"/* {v['name']} */\n")
        out.append(f"static const aw_{m.name}_t vec_msg_{i} = {{\n    "
                   + ",\n    ".join(inits) + "\n};\n")
        payload = bytes.fromhex(v["payload_hex"])
        frame = bytes.fromhex(v["frame_hex"])
        out.append(f"static const uint8_t vec_payload_{i}[] = {_c_bytes(payload)};\n")
        out.append(f"static const uint8_t vec_frame_{i}[] = {_c_bytes(frame)};\n\n")
        rows.append(f"    {{\"{v['name']}\", 0x{v['msg_id']:02X}, {v['seq']}, {v['flags']}, "
                    f"{v['board_time_us']}u, &vec_msg_{i}, vec_payload_{i}, {len(payload)}, "
                    f"vec_frame_{i}, {len(frame)}}},\n")
    out.append("static const aw_vec_frame_t aw_vec_frames[] = {\n" + "".join(rows) + "};\n\n")
    rows = []
    for i, s in enumerate(streams):
        data = bytes.fromhex(s["hex"])
        out.append(f"/* {s['name']}: {s['description']} */\n")
        out.append(f"static const uint8_t stream_{i}[] = {_c_bytes(data)};\n")
        decoded = []
        for j, fr in enumerate(s["expect"]["frames"]):
            p = bytes.fromhex(fr["payload_hex"])
            out.append(f"static const uint8_t stream_{i}_payload_{j}[] = {_c_bytes(p)};\n")
            decoded.append(f"    {{0x{fr['msg_id']:02X}, {fr['seq']}, {fr['flags']}, "
                           f"{fr['board_time_us']}u, stream_{i}_payload_{j}, {len(p)}}},\n")
        out.append(f"static const aw_vec_decoded_t stream_{i}_frames[] = {{\n"
                   + ("".join(decoded) or "    {0, 0, 0, 0, NULL, 0},\n") + "};\n\n")
        c = s["expect"]["counters"]
        counters = ", ".join(f".{k} = {v}" for k, v in c.items())
        rows.append(f"    {{\"{s['name']}\", stream_{i}, {len(data)}, {{{counters}}}, "
                    f"stream_{i}_frames, {len(s['expect']['frames'])}}},\n")
    out.append("static const aw_vec_stream_t aw_vec_streams[] = {\n" + "".join(rows) + "};\n\n")
    out.append("#endif /* TEST_PROTO_VECTORS_H */\n")
    return "".join(out)
