"""docs/protocol.md: framing specification, message tables and the link budget."""

from __future__ import annotations

import textwrap

from reference import crc16_ccitt_false
from schema import (
    FRAME_OVERHEAD,
    Links,
    Message,
    cobs_max_encoded,
    schema_hash,
)

BANNER = ("<!-- generated from protocol/messages by protocol/codegen — do not edit; "
          "run `make gen` -->\n")


def _fmt_rate(m: Message) -> str:
    parts = [f"{b} {r:g}" for b, r in m.rate_hz.items()]
    text = ", ".join(parts)
    if m.to:
        text += f" → {', '.join(m.to)}"
    return text


def _spec(messages: list[Message], links: Links) -> str:
    imu = next(m for m in messages if m.name == "imu")
    max_raw = max(m.raw_frame_size for m in messages)
    boards = ", ".join(f"{v} {k}" for k, v in sorted(links.boards.items(), key=lambda kv: kv[1]))
    check = crc16_ccitt_false(b"123456789", 0xFFFF)
    return textwrap.dedent(f"""\
        # airwake wire protocol

        {BANNER}
        One definition per message lives in `protocol/messages/*.toml`; `make gen`
        (`protocol/codegen/generate.py`) writes the C codec tables
        (`firmware/common/aw_messages.{{h,c}}`), the Python module
        (`host/airwake/link/messages.py`), this page and the golden vectors
        (`protocol/vectors/`). Hand-written codecs: `firmware/common/aw_frame.{{h,c}}` (C) and
        `host/airwake/link/{{framing,decoder,batch}}.py` (Python).

        Schema hash of this version: **`0x{schema_hash(messages):08X}`** ({len(messages)} messages).

        ## Frame

        Every frame on every link, board→host, host→board and rover→base→host alike:

        ```
        0x00 | COBS( msg_id u8 | seq u8 | flags u8 | board_time_us u32 | payload | crc u16 ) | 0x00
        ```

        | offset (before COBS) | size | field | meaning |
        |---|---|---|---|
        | 0 | 1 | `msg_id` | message id (table below); 0 is reserved |
        | 1 | 1 | `seq` | sequence number per (origin board, msg_id), +1 per frame, wraps 255→0 |
        | 2 | 1 | `flags` | bits 0–2 origin board id; bits 3–7 reserved: send 0, ignore on receive |
        | 3 | 4 | `board_time_us` | origin board's µs clock, wraps after 71.6 min (see table) |
        | 7 | n | payload | the message's fields in definition order, packed, little-endian |
        | 7+n | 2 | `crc` | CRC-16 (below) over bytes 0 … 6+n, little-endian |

        All multi-byte values are little-endian; `f32`/`f64` are IEEE 754 (NaN payloads and
        −0 travel bit-exact); arrays are consecutive elements. Header + CRC = {FRAME_OVERHEAD}
        bytes.

        **COBS** (Consistent Overhead Byte Stuffing): the raw frame is split at its zero
        bytes into blocks; each block is written as a code byte (1 + its length) followed by
        its bytes; a block of 254 non-zero bytes has code 0xFF and no implied zero after it;
        after a 0xFF block that ends the frame no empty block is written. The encoded frame
        contains no 0x00, so 0x00 delimits frames. Encoded length: raw + 1 for raw ≤ 254
        bytes, at most raw + ⌈raw/254⌉. A wire frame is at most raw + ⌈raw/254⌉ + 2 bytes.

        **Delimiters.** Senders write a 0x00 *before and after* every frame. Receivers
        treat empty segments (consecutive 0x00) as nothing. The leading 0x00 costs one byte
        per frame and buys the promise of MISSION §1: whatever happened before a frame —
        a truncated frame whose tail and delimiter were lost, or line noise — ends at the
        frame's leading 0x00, so the frame itself is decoded.

        **CRC.** CRC-16/CCITT-FALSE's algorithm (poly 0x1021, MSB first, no input or output
        reflection, no final xor; check value 0x{check:04X} for "123456789" from 0xFFFF) started
        not from 0xFFFF but from the message's **CRC seed**, the 16-bit fold of its definition
        hash: `seed = (def_hash >> 16) ^ (def_hash & 0xFFFF)`. Python computes exactly this with
        `binascii.crc_hqx(body, seed)`. A receiver built from a different definition of the
        message uses a different seed, so a mismatch fails loudly instead of decoding garbage.

        **Definition hash.** FNV-1a 32 (offset basis 0x811C9DC5, prime 0x01000193) over the
        UTF-8 canonical text of the message: a first line `airwake-msg/1 <name> <id>` then one
        line `<field> <type> <count>` per field in wire order, each line ending in `\\n`. For
        example `imu` hashes to `0x{imu.def_hash:08X}` (seed `0x{imu.crc_seed:04X}`) from

        ```
        {textwrap.indent(imu.canonical_text, "        ").strip()}
        ```

        Descriptions, rates and enum/bit labels are not hashed; units and frames are, because
        they are part of every field name. The **schema hash** is FNV-1a 32 over every message's
        hash as 4 little-endian bytes, in id order.

        **Board ids** (flags bits 0–2): {boards}. Host→board frames carry origin 0 and
        `board_time_us` 0.

        **seq** counts per (origin board, msg_id): a receiver counts `(seq − last − 1) mod 256`
        lost frames per message type and origin. Gaps of 256 or more frames (a link down for
        seconds) alias; `board_time_us` shows them.

        **Forwarding.** The base relays the rover's frames byte-exact (whole segments between
        delimiters, never interleaved with its own), so the rover's CRC protects them end to
        end and `seq` gaps measure the whole path. No "forwarded" flag is needed (and none could
        be set without recomputing the CRC): a frame whose origin differs from the board that
        owns the port was forwarded.

        ## Receiving

        A receiver splits the byte stream at 0x00 and classifies every non-empty segment
        exactly once, in this order (the same rules in C, Python and the reference decoder
        that produced `protocol/vectors/streams.json`):

        1. longer than {cobs_max_encoded(max_raw)} encoded bytes (the longest frame's COBS
           length) → `oversize`;
        2. not valid COBS (a code byte pointing past the end) or decoded shorter than
           {FRAME_OVERHEAD} bytes → `cobs_error`;
        3. `msg_id` not in the receiver's schema → `unknown_id`;
        4. length = {FRAME_OVERHEAD} + payload size and CRC correct with the receiver's seed →
           **decoded**;
        5. otherwise, if the origin announced a different definition hash for this id
           (`schema_entry`) and the CRC is correct with *that* hash's seed → `def_mismatch`:
           an intact frame from a different definition, not decoded (its raw bytes stay in
           the recording);
        6. otherwise → `crc_error` (corrupt).

        `bytes_dropped` counts the encoded bytes of every segment not decoded. For any input:
        bytes fed = bytes of decoded segments + `bytes_dropped` + number of 0x00 bytes +
        bytes pending in the unfinished last segment.

        **Telling a definition mismatch from corruption.** Both fail the receiver's CRC. Each
        sender therefore announces, with the frozen `schema_entry` message, the definition hash
        of every message id it sends or receives: all entries at boot, then one at least every
        250 ms, cycling, so a receiver that joins late learns them within seconds. A frame
        that fails our seed but passes the announced one is an intact frame of another
        definition. Until the entry for an id has arrived such frames count as `crc_error`.
        The frozen `heartbeat` (1 Hz) carries the sender's whole-schema hash: the host
        compares it with its own and reports "schema mismatch with board X" at once, naming
        the messages whose announced hashes differ. `heartbeat` and `schema_entry` never
        change layout (the generator refuses to change their hash), so they always decode.

        ## Using the codecs

        C (`firmware/common/`, no heap, C11, builds for the Cortex-M4 with soft float):

        ```c
        aw_imu_t imu = {{.gyro_frd_rad_s = {{0.1f, 0.0f, 0.0f}}}};
        uint8_t out[AW_WIRE_MAX_IMU];          /* or AW_MAX_WIRE_SIZE for any message */
        int n = aw_encode_imu(out, sizeof out, seq++, AW_BOARD_LOSA, micros(), &imu);

        aw_decoder_t dec;                       /* about 0.4 KiB of RAM, one per port */
        aw_decoder_init(&dec, on_frame, ctx);   /* on_frame(ctx, const aw_frame_t *) */
        aw_decoder_feed(&dec, rx_bytes, rx_len);/* or aw_decoder_feed_byte(&dec, b, &frame) */
        /* in on_frame: switch (f->header.msg_id) {{ case AW_ID_MARKER_COMMAND:
           aw_unpack_marker_command(&cmd, f->payload); ... }} ; dec.counters.crc_error, ... */
        ```

        Python (`airwake.link`):

        ```python
        from airwake.link.framing import encode_frame
        from airwake.link.decoder import StreamDecoder
        from airwake.link.messages import Imu
        wire = encode_frame(Imu(gyro_frd_rad_s=(0.1, 0.0, 0.0)), seq, flags, board_time_us)
        decoder = StreamDecoder()
        for frame in decoder.feed(chunk):      # Frame(msg_id, seq, flags, board_time_us, msg)
            frame.origin, frame.name, frame.msg.gyro_frd_rad_s
        decoder.counters(); decoder.schema_problems()
        # whole captures: airwake.link.batch.decode_capture(data).tables["imu"] (numpy)
        ```

        `airwake decode CAPTURE [--json]` prints the same counters for a raw capture file.

        ## Evolving a message

        - Append fields at the end only; never reorder, retype, rename or remove (renaming
          changes the hash too). The hash changes, so old and new peers report
          `def_mismatch` for that message instead of misreading it — flash and host move
          together, and the recordings keep the raw bytes of mismatched frames.
        - Never reuse an id; a message that changes meaning gets a new id and name.
        - `heartbeat` and `schema_entry` are frozen: add a new message for new counters.
        - Run `make gen`, commit the regenerated files (a test fails when they are stale).
        """)


def _message_table(messages: list[Message]) -> str:
    rows = ["| id | name | payload B | wire B (max) | rate Hz (sender) | board_time_us |",
            "|---|---|---|---|---|---|"]
    for m in messages:
        frozen = " (frozen)" if m.frozen else ""
        note = f" — {m.rate_note}" if m.rate_note else ""
        rows.append(f"| 0x{m.id:02X} | [`{m.name}`](#{m.name}){frozen} | {m.payload_size} | "
                    f"{m.wire_max} | {_fmt_rate(m)}{note} | {m.time} |")
    return "## Messages\n\n" + "\n".join(rows) + "\n"


def _field_tables(messages: list[Message]) -> str:
    out = []
    for m in messages:
        out.append(f"### {m.name}\n\n`0x{m.id:02X}` · payload {m.payload_size} B · "
                   f"hash `0x{m.def_hash:08X}` · seed `0x{m.crc_seed:04X}` · "
                   f"{_fmt_rate(m)} Hz{' · frozen layout' if m.frozen else ''}\n\n"
                   f"{' '.join(m.description.split())}\n\n")
        out.append("| offset | field | type | unit | description |\n|---|---|---|---|---|\n")
        for f, off in zip(m.fields, m.offsets, strict=True):
            t = f.type + (f"[{f.count}]" if f.count > 1 else "")
            extra = ""
            if f.values:
                extra = " Values: " + ", ".join(f"{k} {v}" for k, v in f.values.items()) + "."
            if f.bits:
                extra = " Bits: " + ", ".join(f"{k} {v}" for k, v in f.bits.items()) + "."
            desc = f.description if not extra or f.description.endswith(".") \
                else f.description + "."
            out.append(f"| {off} | `{f.name}` | {t} | {f.unit} | {desc}{extra} |\n")
        out.append("\n")
    return "## Fields\n\n" + "".join(out)


def board_traffic(messages: list[Message], board: str) -> list[tuple[Message, float, float]]:
    """(message, rate, bytes/s with worst-case COBS and both delimiters) sent by board."""
    return [(m, m.rate_hz[board], m.rate_hz[board] * m.wire_max)
            for m in messages if board in m.rate_hz]


def _budget(messages: list[Message], links: Links) -> str:
    boards = [b for b in links.boards if b != "host"]
    own = {b: sum(bps for _, _, bps in board_traffic(messages, b)) for b in boards}
    carried = {b: sum(own[x] for x in links.paths[b].get("carries", [b])) for b in boards}
    link_names = list(links.links)
    out = [textwrap.dedent("""\
        ## Link budget

        Bytes per second each board sends at the nominal rates above, each frame counted at
        its worst-case wire size (COBS overhead ⌈raw/254⌉ plus both 0x00 delimiters), against
        each link's capacity. Assumptions (`protocol/links.toml`):

        """)]
    for spec in links.links.values():
        out.append(f"- **{spec['label']}**: {spec['bytes_per_s']:,} B/s — {spec['note']}.\n")
    out.append("\n### Per board and message\n\n")
    for b in boards:
        out.append(f"**{b}**\n\n| message | rate Hz | wire B | B/s |\n|---|---|---|---|\n")
        for m, rate, bps in board_traffic(messages, b):
            out.append(f"| `{m.name}` | {rate:g} | {m.wire_max} | {bps:,.0f} |\n")
        out.append(f"| **total** | | | **{own[b]:,.0f}** |\n\n")
    host_tx = {b: sum(m.rate_hz["host"] * m.wire_max for m in messages
                      if "host" in m.rate_hz and b in m.to) for b in boards}
    out.append("Host → board (the other direction of each full-duplex link): "
               + ", ".join(f"{b} {host_tx[b]:,.0f} B/s" for b in boards) + ".\n\n")
    out.append("### Utilisation of each kind of link\n\n")
    labels = " | ".join(links.links[n]["label"] for n in link_names)
    out.append(f"| board (traffic) | B/s | {labels}"
               + " |\n|---|---|" + "---|" * len(link_names) + "\n")
    for b in boards:
        others = [x for x in links.paths[b].get("carries", [b]) if x != b]
        label = f"{b} (+ {', '.join(others)} forwarded)" if others else b
        cells = [f"{100 * carried[b] / links.links[n]['bytes_per_s']:.1f} %" for n in link_names]
        out.append(f"| {label} | {carried[b]:,.0f} | " + " | ".join(cells) + " |\n")
    out.append("\n### Each board's path to the host (tightest hop in bold)\n\n")
    out.append("| board | path | load per hop | tightest |\n|---|---|---|---|\n")
    for b in boards:
        hops = [(n, own[b] if b != "base" else carried[b]) for n in links.paths[b]["links"]]
        then = links.paths[b].get("then")
        if then:
            hops += [(n, carried[then]) for n in links.paths[then]["links"]]
        loads = [(n, bps / links.links[n]["bytes_per_s"]) for n, bps in hops]
        worst = max(range(len(loads)), key=lambda i: loads[i][1])
        cells = []
        for i, (n, u) in enumerate(loads):
            text = f"{links.links[n]['label']} {100 * u:.1f} %"
            cells.append(f"**{text}**" if i == worst else text)
        path_note = links.paths[b]["note"]
        flag = " — over capacity" if loads[worst][1] > 1 else (
            " — above 50 %: little margin" if loads[worst][1] > 0.5 else "")
        out.append(f"| {b} | {path_note} | {' → '.join(cells)} | "
                   f"{links.links[loads[worst][0]]['label']}{flag} |\n")
    out.append("\n" + _conclusion(boards, own, carried, links))
    return "".join(out)


def _conclusion(boards: list[str], own: dict, carried: dict, links: Links) -> str:
    uarts = sorted((spec["bytes_per_s"], name) for name, spec in links.links.items()
                   if name.startswith("uart_"))

    def slowest_uart(bps: float) -> str:
        fits = [links.links[n]["label"] for cap, n in uarts if bps <= 0.5 * cap]
        return fits[0] if fits else "none (use USB CDC)"

    loads = {}
    for b in boards:
        traffic = carried[b] if b == "base" else own[b]
        loads[b] = max(traffic / links.links[n]["bytes_per_s"] for n in links.paths[b]["links"])
    tightest = max(boards, key=loads.get)
    fits_slowest = [b for b in boards
                    if (carried[b] if b == "base" else own[b]) <= uarts[0][0]]
    slowest = ", ".join(f"{b} {slowest_uart(carried[b] if b == 'base' else own[b])}"
                        for b in boards)
    return (f"**Tightest board: {tightest}**, its busiest hop at {100 * loads[tightest]:.1f} % "
            f"of capacity. Slowest UART keeping each board's own traffic at or below 50 %: "
            f"{slowest}. Boards whose traffic fits {links.links[uarts[0][1]]['label']} at all: "
            f"{', '.join(fits_slowest) or 'none'}.\n")


def document(messages: list[Message], links: Links) -> str:
    return "\n".join([_spec(messages, links), _message_table(messages), _field_tables(messages),
                      _budget(messages, links)])
