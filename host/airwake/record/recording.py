"""Crash-safe recordings: a directory of MCAP segments written by the daemon.

Layout (docs/recordings.md):

    REC/segment-0000.mcap, segment-0001.mcap, ...   (one every `segment_s`, 10 min)

Each segment is a complete MCAP file once closed (summary, chunk index, statistics),
and a readable prefix while it is being written: messages are grouped in zstd chunks that
are closed and written out every `flush_s` (FLUSH_S, 0.1 s of host time, whatever the
byte count), so a `kill -9` loses at most the chunk in progress, and the reader's
recovery path (`record.reader`) reads every complete record of an unfinished segment.
Rotating segments also bounds the writer's memory (its chunk index grows with the
segment, not with the flight).

Channels (topic -> message encoding):

- `/raw/<role>`: the bytes one port delivered, exactly as read (encoding
  `airwake-raw`, no schema); log_time = publish_time = host receive time;
- `/raw/<role>/tx`: the bytes the daemon wrote to that port;
- `/<board>/<message>`: every decoded frame, encoding `ros1` with a `ros1msg` schema
  (Foxglove and PlotJuggler read it natively): a header (`uint8 seq`,
  `uint32 board_time_us` as on the wire, `int64 board_us` unwrapped, `uint32 epoch`)
  followed by the payload fields by their protocol names. ROS 1 serialisation is packed
  little-endian with fixed arrays inline, i.e. exactly our wire payload, so a decoded
  message costs one `struct.pack` (JSON cost ~20 µs per frame in float formatting and
  was 4x larger). log_time = the board time mapped live onto the host timeline,
  publish_time = receive time;
- `/host/<message>`: what the daemon sent (time_sync_request, marker_command, ...), same
  encoding; `/host/tracker_position` (JSON) what it computed;
- `/daemon/events` (identification, schema problems, port lost/back, epochs, errors)
  and `/daemon/status` (the link-health snapshot, 1 Hz), JSON.

Metadata records: `airwake.recording` (daemon version, start times, ports, schema hash,
options such as antenna offsets), `airwake.board.<name>` per identified board (board id,
firmware version, schema hash, boot count, port), `airwake.summary` at a clean close
(counters). The attachment `protocol.json` holds every message definition, so a
recording decodes without this source tree.

Times on the host timeline are CLOCK_MONOTONIC ns (immune to wall-clock steps; the
native boards' wall mode uses the same clock); `airwake.recording` holds the wall-clock
time at the start to convert.

Full disk: a failed write (ENOSPC, EFBIG, any OSError) truncates the segment back to
the end of the last complete flush, closes it and sets `failed` to a message naming the
file; nothing more is written (the segment is then read through the recovery path).
"""

from __future__ import annotations

import json
import os
import struct
import time
from pathlib import Path

from mcap.writer import CompressionType, IndexType, Writer

from airwake.errors import AirwakeError
from airwake.link.messages import BY_NAME, MESSAGES, SCHEMA_HASH, MessageInfo

RAW_ENCODING = "airwake-raw"
DECODED_ENCODING = "ros1"
# Header of a decoded message: seq, board_time_us (wire u32), board_us (unwrapped), epoch.
DECODED_HEADER = struct.Struct("<BIqI")
DECODED_HEADER_FIELDS = (("seq", "uint8", "u1"), ("board_time_us", "uint32", "<u4"),
                         ("board_us", "int64", "<i8"), ("epoch", "uint32", "<u4"))
_ROS1_TYPES = {"u8": "uint8", "u16": "uint16", "u32": "uint32", "u64": "uint64",
               "i8": "int8", "i16": "int16", "i32": "int32", "i64": "int64",
               "f32": "float32", "f64": "float64"}
PROFILE = "airwake"
RECORDING_FORMAT = "airwake-recording/1"
SEGMENT_GLOB = "segment-*.mcap"
# Seconds between flushes: the chunk in progress is compressed and handed to the OS, so a
# SIGKILL loses at most this much plus what the daemon had not read yet (docs/daemon.md,
# "Crash safety": 0.1 s costs ~0.001 of a core and ~4 % of file size more than 0.25 s).
FLUSH_S = 0.1


class RecordingError(AirwakeError):
    """The recording cannot be created or written (the file is named)."""


def protocol_definition() -> dict:
    """Every message definition (what makes a recording self-describing)."""
    return {
        "schema_hash": f"0x{SCHEMA_HASH:08X}",
        "frame": "0x00 | COBS(msg_id u8 | seq u8 | flags u8 | board_time_us u32 | payload | "
                 "crc16 u16 LE) | 0x00; CRC-16/CCITT-FALSE seeded by the message's crc_seed",
        "messages": [{
            "id": m.id, "name": m.name, "def_hash": f"0x{m.def_hash:08X}",
            "crc_seed": f"0x{m.crc_seed:04X}", "payload_size": m.payload_size,
            "description": m.description, "board_time": m.time,
            "fields": [{"name": f.name, "type": f.type, "count": f.count, "unit": f.unit,
                        "description": f.description,
                        **({"values": {str(k): v for k, v in f.values.items()}}
                           if f.values else {}),
                        **({"bits": {str(k): v for k, v in f.bits.items()}} if f.bits else {})}
                       for f in m.fields],
        } for m in MESSAGES],
    }


def ros1_schema(info: MessageInfo) -> str:
    """The ros1msg text of a decoded message `/<board>/<name>` (header, then payload)."""
    lines = [f"# airwake {info.name} (id 0x{info.id:02X}, definition hash "
             f"0x{info.def_hash:08X}); board_time_us: {info.time}",
             "uint8 seq  # frame sequence number",
             "uint32 board_time_us  # board clock as on the wire (wraps at 2^32)",
             "int64 board_us  # board clock unwrapped within its epoch",
             "uint32 epoch  # board run (reset) as counted by the host"]
    for f in info.fields:
        t = _ROS1_TYPES[f.type] + (f"[{f.count}]" if f.count > 1 else "")
        lines.append(f"{t} {f.name}  # [{f.unit}] {f.description}")
    return "\n".join(lines) + "\n"


def decoded_dtype(info: MessageInfo):
    """numpy dtype of a decoded message's bytes (packed: header + payload)."""
    import numpy as np

    return np.dtype([(n, d) for n, _, d in DECODED_HEADER_FIELDS] + list(info.dtype_descr))


class GuardedFile:
    """The MCAP writer's output: buffered in memory, written out by `flush()`.

    `tell()` is the logical position. A failed write truncates the file back to the
    end of the last successful flush (a record boundary) and raises RecordingError.
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        try:
            self.fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        except OSError as exc:
            raise RecordingError(f"cannot create {path}: {exc.strerror}") from exc
        self.pending: list[bytes] = []
        self.position = 0
        self.durable = 0

    def write(self, data) -> int:
        self.pending.append(bytes(data))
        self.position += len(data)
        return len(data)

    def tell(self) -> int:
        return self.position

    def flush(self) -> None:
        if not self.pending:
            return
        data = b"".join(self.pending)
        self.pending.clear()
        view = memoryview(data)
        try:
            while view:
                view = view[os.write(self.fd, view):]
        except OSError as exc:
            try:
                os.ftruncate(self.fd, self.durable)
            except OSError:
                pass
            self.position = self.durable
            raise RecordingError(f"writing {self.path} failed after {self.durable} bytes: "
                                 f"{exc.strerror or exc} (errno {exc.errno}); recording "
                                 "stopped, what was written stays readable") from exc
        self.durable = self.position

    def fsync(self) -> None:
        try:
            os.fsync(self.fd)
        except OSError:
            pass

    def close(self) -> None:
        if self.fd >= 0:
            os.close(self.fd)
            self.fd = -1


class Segment:
    """One MCAP file of the recording."""

    def __init__(self, path: Path, chunk_size: int) -> None:
        self.path = path
        self.file = GuardedFile(path)
        self.writer = Writer(self.file, chunk_size=chunk_size, compression=CompressionType.ZSTD,
                             index_types=IndexType.ALL & ~IndexType.MESSAGE)
        self.channels: dict[str, int] = {}
        self.schemas: dict[str, int] = {}
        self.messages = 0


class RecordingWriter:
    """Writes a recording directory (see module doc). Not thread-safe: one loop owns it."""

    def __init__(self, directory, metadata: dict, *, flush_s: float = FLUSH_S,
                 segment_s: float = 600.0, chunk_size: int = 4 << 20) -> None:
        self.directory = Path(directory)
        if self.directory.exists() and any(self.directory.iterdir()):
            raise RecordingError(f"recording directory {self.directory} exists and is not "
                                 "empty; choose a new --out")
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise RecordingError(f"cannot create {self.directory}: {exc.strerror}") from exc
        self.metadata = {"format": RECORDING_FORMAT, **metadata}
        self.flush_s = flush_s
        self.segment_s = segment_s
        self.chunk_size = chunk_size
        self.boards: dict[str, dict] = {}
        self.failed: str | None = None
        self.closed = False
        self.bytes_written = 0
        self.messages = 0
        self.segments: list[Path] = []
        self._segment: Segment | None = None
        self._segment_start = 0.0
        self._last_flush = 0.0
        self._protocol = json.dumps(protocol_definition(), indent=1).encode()
        self._open_segment(time.monotonic())

    # -- segments ---------------------------------------------------------------

    def _open_segment(self, now: float) -> None:
        path = self.directory / f"segment-{len(self.segments):04d}.mcap"
        seg = Segment(path, self.chunk_size)
        self.segments.append(path)
        self._segment = seg
        self._segment_start = now
        w = seg.writer
        from airwake import __version__

        w.start(profile=PROFILE, library=f"airwake-daemon {__version__}")
        w.add_metadata("airwake.recording", _strings({**self.metadata,
                                                      "segment": len(self.segments) - 1}))
        now_ns = time.monotonic_ns()
        w.add_attachment(create_time=time.time_ns(), log_time=now_ns, name="protocol.json",
                         media_type="application/json", data=self._protocol)
        for name, info in self.boards.items():
            w.add_metadata(f"airwake.board.{name}", _strings(info))
        self._flush_segment()

    def _close_segment(self, summary: dict | None) -> None:
        seg = self._segment
        if seg is None:
            return
        self._segment = None
        try:
            if summary is not None:
                seg.writer.add_metadata("airwake.summary", _strings(summary))
            seg.writer.finish()
            seg.file.flush()
            seg.file.fsync()
        except RecordingError as exc:
            self.failed = str(exc)
        finally:
            seg.file.close()

    def _flush_segment(self) -> None:
        seg = self._segment
        before = seg.file.durable
        try:
            seg.writer.flush()
        except RecordingError as exc:
            self.failed = str(exc)
            seg.file.close()
            self._segment = None
            return
        self.bytes_written += seg.file.durable - before

    # -- writing --------------------------------------------------------------

    @property
    def active(self) -> bool:
        return self._segment is not None

    def _channel(self, topic: str, encoding: str,
                 schema: tuple[str, str, bytes] | None) -> int:
        """Channel id of topic in this segment; schema = (name, schema encoding, data)."""
        seg = self._segment
        cid = seg.channels.get(topic)
        if cid is None:
            sid = 0
            if schema is not None:
                name, schema_encoding, body = schema
                sid = seg.schemas.get(name)
                if sid is None:
                    sid = seg.writer.register_schema(name, schema_encoding, body)
                    seg.schemas[name] = sid
            cid = seg.writer.register_channel(topic, encoding, sid)
            seg.channels[topic] = cid
        return cid

    def raw(self, topic: str, host_ns: int, data: bytes) -> None:
        """Raw port bytes on `/raw/<role>` (or `/raw/<role>/tx`)."""
        if self._segment is None:
            return
        cid = self._segment.channels.get(topic) or self._channel(topic, RAW_ENCODING, None)
        self._segment.writer.add_message(cid, host_ns, data, host_ns)
        self.messages += 1

    def decoded(self, topic: str, info: MessageInfo, log_ns: int, publish_ns: int,
                body: bytes) -> None:
        """A decoded frame of protocol message `info` (body: `encode_decoded`)."""
        seg = self._segment
        if seg is None:
            return
        cid = seg.channels.get(topic)
        if cid is None:
            cid = self._decoded_channel(topic, info)
        seg.writer.add_message(cid, log_ns, body, publish_ns)
        self.messages += 1

    def _decoded_channel(self, topic: str, info: MessageInfo) -> int:
        return self._channel(topic, DECODED_ENCODING,
                             (f"airwake/{info.name}", "ros1msg", ros1_schema(info).encode()))

    def json(self, topic: str, log_ns: int, obj: dict, schema: dict | None = None) -> None:
        """A free-form JSON message (events, status, host estimates)."""
        seg = self._segment
        if seg is None:
            return
        cid = seg.channels.get(topic)
        if cid is None:
            body = json.dumps(schema or {"type": "object"}).encode()
            cid = self._channel(topic, "json", (f"airwake{topic.replace('/', '.')}",
                                                "jsonschema", body))
        seg.writer.add_message(cid, log_ns, json.dumps(obj, default=_jsonable).encode(), log_ns)
        self.messages += 1

    def copy(self, topic: str, log_ns: int, publish_ns: int, data: bytes,
             json_schema: tuple[str, str, bytes] | None = None) -> None:
        """A message read from another recording, with the channel this writer would use;
        a JSON channel gets `json_schema` (name, encoding, data: the source's) if given."""
        if self._segment is None:
            return
        if topic.startswith("/raw/"):
            cid = self._channel(topic, RAW_ENCODING, None)
        else:
            parts = topic.strip("/").split("/")
            info = BY_NAME.get(parts[-1]) if len(parts) == 2 and parts[0] != "daemon" else None
            if info is not None and topic != "/host/tracker_position":
                cid = self._decoded_channel(topic, info)
            else:
                cid = self._channel(topic, "json", json_schema or (
                    f"airwake{topic.replace('/', '.')}", "jsonschema", b'{"type": "object"}'))
        self._segment.writer.add_message(cid, log_ns, data, publish_ns)
        self.messages += 1

    def board(self, name: str, info: dict) -> None:
        """Metadata of an identified board (repeated at the head of later segments)."""
        self.boards[name] = dict(info)
        if self._segment is not None:
            self._segment.writer.add_metadata(f"airwake.board.{name}", _strings(info))

    def tick(self, now: float) -> None:
        """Flush every flush_s; rotate every segment_s (call from the loop)."""
        if self._segment is None:
            return
        if now - self._last_flush >= self.flush_s:
            self._last_flush = now
            self._flush_segment()
        if self._segment is not None and now - self._segment_start >= self.segment_s:
            self._close_segment(None)
            if self.failed is None:
                try:
                    self._open_segment(now)
                except RecordingError as exc:
                    self.failed = str(exc)

    def close(self, summary: dict | None = None) -> None:
        """Clean close: the summary metadata, the MCAP summary/index, fsync."""
        if self.closed:
            return
        self.closed = True
        self._close_segment(summary or {})


def encode_decoded(info: MessageInfo, msg, seq: int, board_time_us: int, board_us: int,
                   epoch: int) -> bytes:
    """The bytes of one decoded frame: DECODED_HEADER + the packed payload (= ros1)."""
    return DECODED_HEADER.pack(seq, board_time_us, board_us, epoch) + info.pack(msg)


def decode_decoded(info: MessageInfo, data: bytes) -> tuple[tuple[int, int, int, int], object]:
    """(seq, board_time_us, board_us, epoch), message record of a decoded frame's bytes."""
    n = DECODED_HEADER.size
    return DECODED_HEADER.unpack_from(data), info.unpack(data[n:])


def _strings(d: dict) -> dict[str, str]:
    """MCAP metadata values are strings: JSON-encode anything that is not one."""
    return {str(k): v if isinstance(v, str) else json.dumps(v, default=_jsonable)
            for k, v in d.items()}


def _jsonable(o):
    if hasattr(o, "tolist"):
        return o.tolist()
    if isinstance(o, Path):
        return str(o)
    return str(o)
