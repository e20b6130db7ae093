"""Reading recordings, including the ones a crash or a full disk left unfinished.

    rec = open_recording("REC")                 # directory (or one segment .mcap)
    rec.metadata, rec.boards, rec.summary       # dicts (summary None if not closed cleanly)
    rec.segments                                # [SegmentInfo(path, indexed, complete, ...)]
    raw = rec.raw("base")                       # RawStream(data, end_offsets, rx_ns)
    ins = rec.table("/rover/ins")               # DecodedTable(rows, log_ns, publish_ns)
    for m in rec.messages(["/daemon/events"]):  # RecordedMessage(topic, log_ns, publish_ns,
        m.json()                                #                 data)
    rec.topics()                                # {topic: message count}

Each segment opens with mcap's indexed reader when it is complete (summary and footer
present). Otherwise the recovery path reads it sequentially with
`mcap.stream_reader.StreamReader` and stops at the first incomplete record: everything
the writer flushed before the cut is returned (`SegmentInfo.complete` False,
`recovered_bytes` how far it got). `recover_recording(src, dst)` writes such a recording
out again as closed, indexed segments.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from mcap.reader import SeekingReader
from mcap.records import Attachment, Channel, Message, Metadata, Schema
from mcap.stream_reader import StreamReader

from airwake.errors import AirwakeError
from airwake.link.messages import BY_NAME
from airwake.record.recording import RAW_ENCODING, SEGMENT_GLOB, decode_decoded, decoded_dtype


class RecordingReadError(AirwakeError):
    """A recording that cannot be opened at all (the path and reason are named)."""


@dataclass(frozen=True)
class RecordedMessage:
    topic: str
    log_ns: int
    publish_ns: int
    data: bytes

    def json(self):
        return json.loads(self.data)

    def decode(self):
        """((seq, board_time_us, board_us, epoch), record) of a decoded-frame message."""
        return decode_decoded(BY_NAME[self.topic.rsplit("/", 1)[-1]], self.data)


@dataclass
class DecodedTable:
    """Decoded frames of one topic: `rows` (N,) numpy (header + payload fields by their
    protocol names), `log_ns` (N,) live-mapped host time, `publish_ns` (N,) receive time."""

    rows: np.ndarray
    log_ns: np.ndarray
    publish_ns: np.ndarray

    def __len__(self) -> int:
        return len(self.rows)


@dataclass
class RawStream:
    """All bytes of one port in order: `data`, the end offset of each read in it
    (N,) and each read's host receive time (N,) ns."""

    data: bytes
    end_offsets: np.ndarray
    rx_ns: np.ndarray

    def rx_ns_at(self, offsets: np.ndarray) -> np.ndarray:
        """Receive time of the byte at each offset (the read that delivered it)."""
        i = np.searchsorted(self.end_offsets, np.asarray(offsets), side="right")
        return self.rx_ns[np.clip(i, 0, len(self.rx_ns) - 1)]


@dataclass
class SegmentInfo:
    path: Path
    indexed: bool  # opened with the indexed reader (closed cleanly)
    complete: bool  # footer present
    size: int
    recovered_bytes: int  # bytes the sequential reader consumed (== size when complete)
    error: str | None = None


class _Tracked:
    """A file wrapper that counts bytes consumed (where a recovery stopped)."""

    def __init__(self, f) -> None:
        self.f = f
        self.count = 0

    def read(self, n: int = -1) -> bytes:
        data = self.f.read(n)
        self.count += len(data)
        return data


def _stream_records(path: Path, status: dict | None = None) -> Iterator:
    """Every complete record of a segment in file order, stopping quietly at a torn tail
    (the recovery path). status (optional) receives bytes_ok, complete and error."""
    with path.open("rb") as f:
        tracked = _Tracked(f)
        ok, complete, error = 0, False, None
        try:
            for rec in StreamReader(tracked, record_size_limit=1 << 30).records:
                ok = tracked.count
                yield rec
            complete = True
        except Exception as exc:  # noqa: BLE001 — whatever a cut left behind ends the scan
            error = f"{type(exc).__name__}: {exc}"
        if status is not None:
            status.update(bytes_ok=ok, complete=complete, error=error)


class _Segment:
    """One segment: its channels, metadata and message counts; messages on demand."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.channels: dict[int, Channel] = {}
        self.counts: dict[str, int] = {}
        self.metadata: list[Metadata] = []
        self.attachments: list[Attachment] = []
        size = path.stat().st_size
        if self._open_indexed():
            self.info = SegmentInfo(path, True, True, size, size)
            return
        status: dict = {}
        for rec in _stream_records(path, status):
            if isinstance(rec, Channel):
                self.channels[rec.id] = rec
            elif isinstance(rec, Message):
                ch = self.channels.get(rec.channel_id)
                if ch is not None:
                    self.counts[ch.topic] = self.counts.get(ch.topic, 0) + 1
            elif isinstance(rec, Metadata):
                self.metadata.append(rec)
            elif isinstance(rec, Attachment):
                self.attachments.append(rec)
        self.info = SegmentInfo(path, False, status["complete"], size, status["bytes_ok"],
                                status["error"])

    def _open_indexed(self) -> bool:
        try:
            with self.path.open("rb") as f:
                reader = SeekingReader(f)
                summary = reader.get_summary()
                if summary is None:
                    return False
                self.channels = dict(summary.channels)
                stats = summary.statistics
                if stats is not None:
                    for cid, n in stats.channel_message_counts.items():
                        topic = self.channels[cid].topic
                        self.counts[topic] = self.counts.get(topic, 0) + n
                self.metadata = list(reader.iter_metadata())
                self.attachments = list(reader.iter_attachments())
            return True
        except Exception:  # noqa: BLE001 — not closed (or damaged): use the recovery path
            return False

    def iter_messages(self, topics: set[str] | None) -> Iterator[tuple[str, Message]]:
        for _schema, channel, message in self.iter_records(topics):
            yield channel.topic, message

    def iter_records(self, topics: set[str] | None) -> Iterator[tuple[Schema | None, Channel,
                                                                     Message]]:
        """(schema or None, channel, message) in file order."""
        if self.info.indexed:
            with self.path.open("rb") as f:
                reader = SeekingReader(f)
                yield from reader.iter_messages(
                    topics=None if topics is None else list(topics), log_time_order=False)
            return
        schemas: dict[int, Schema] = {}
        channels: dict[int, Channel] = {}
        for rec in _stream_records(self.path):
            if isinstance(rec, Schema):
                schemas[rec.id] = rec
            elif isinstance(rec, Channel):
                channels[rec.id] = rec
            elif isinstance(rec, Message):
                ch = channels.get(rec.channel_id)
                if ch is not None and (topics is None or ch.topic in topics):
                    yield schemas.get(ch.schema_id), ch, rec


class Recording:
    """A recording opened for reading (see module doc)."""

    def __init__(self, path) -> None:
        p = Path(path)
        if p.is_dir():
            files = sorted(p.glob(SEGMENT_GLOB))
            if not files:
                raise RecordingReadError(f"recording {p}: no {SEGMENT_GLOB} files in it")
        elif p.is_file():
            files = [p]
        else:
            raise RecordingReadError(f"recording {p} not found")
        self.path = p
        self.metadata: dict = {}
        self.boards: dict[str, dict] = {}
        self.summary: dict | None = None
        self.protocol: dict | None = None
        self._segments = [_Segment(f) for f in files]
        for seg in self._segments:
            for rec in seg.metadata:
                data = {key: _parse(v) for key, v in rec.metadata.items()}
                if rec.name == "airwake.recording" and not self.metadata:
                    self.metadata = data
                elif rec.name.startswith("airwake.board."):
                    self.boards[rec.name[len("airwake.board."):]] = data
                elif rec.name == "airwake.summary":
                    self.summary = data
            for att in seg.attachments:
                if att.name == "protocol.json" and self.protocol is None:
                    self.protocol = json.loads(att.data)
        if not any(s.info.recovered_bytes for s in self._segments):
            raise RecordingReadError(f"recording {p}: no readable MCAP data "
                                     f"({self._segments[0].info.error})")

    @property
    def segments(self) -> list[SegmentInfo]:
        return [s.info for s in self._segments]

    @property
    def complete(self) -> bool:
        """Every segment closed cleanly and the recording has its summary."""
        return all(s.complete for s in self.segments) and self.summary is not None

    def topics(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for seg in self._segments:
            for topic, n in seg.counts.items():
                out[topic] = out.get(topic, 0) + n
        return dict(sorted(out.items()))

    def _iter(self, topics: Iterable[str] | None) -> Iterator[tuple[str, Message]]:
        wanted = None if topics is None else set(topics)
        for seg in self._segments:
            yield from seg.iter_messages(wanted)

    def messages(self, topics: Iterable[str] | None = None) -> Iterator[RecordedMessage]:
        """Messages in file order (per topic: the order they were written)."""
        for topic, m in self._iter(topics):
            yield RecordedMessage(topic, m.log_time, m.publish_time, bytes(m.data))

    def raw_roles(self) -> list[str]:
        return sorted(t[len("/raw/"):] for t in self.topics()
                      if t.startswith("/raw/") and not t.endswith("/tx"))

    def raw(self, role: str, tx: bool = False) -> RawStream:
        """Every byte port `role` delivered (or, tx=True, was sent), with receive times."""
        topic = f"/raw/{role}/tx" if tx else f"/raw/{role}"
        chunks, times = [], []
        for _t, m in self._iter([topic]):
            chunks.append(bytes(m.data))
            times.append(m.log_time)
        lengths = np.fromiter(map(len, chunks), dtype=np.int64, count=len(chunks))
        return RawStream(b"".join(chunks), np.cumsum(lengths), np.asarray(times, dtype=np.int64))

    def decoded_topics(self) -> list[str]:
        """Topics holding decoded frames: /<board>/<message> and /host/<message>."""
        out = []
        for t in self.topics():
            parts = t.strip("/").split("/")
            if len(parts) == 2 and parts[0] not in ("raw", "daemon") and parts[1] in BY_NAME \
                    and t != "/host/tracker_position":
                out.append(t)
        return out

    def tables(self, topics: Iterable[str] | None = None) -> dict[str, DecodedTable]:
        """Decoded frames of several topics (all decoded topics by default), one pass."""
        wanted = list(self.decoded_topics() if topics is None else topics)
        for topic in wanted:
            if BY_NAME.get(topic.rsplit("/", 1)[-1]) is None:
                raise RecordingReadError(f"recording {self.path}: '{topic}' is not a "
                                         "decoded-frame topic (/<board>/<message>)")
        acc: dict[str, tuple[list, list, list]] = {t: ([], [], []) for t in wanted}
        for topic, m in self._iter(wanted):
            datas, log, pub = acc[topic]
            datas.append(bytes(m.data))
            log.append(m.log_time)
            pub.append(m.publish_time)
        out = {}
        for topic, (datas, log, pub) in acc.items():
            info = BY_NAME[topic.rsplit("/", 1)[-1]]
            rows = np.frombuffer(b"".join(datas), dtype=decoded_dtype(info))
            out[topic] = DecodedTable(rows, np.asarray(log, dtype=np.int64),
                                      np.asarray(pub, dtype=np.int64))
        return out

    def table(self, topic: str) -> DecodedTable:
        """Every decoded frame of `/<board>/<message>` (or `/host/<message>`) as numpy."""
        return self.tables([topic])[topic]

    def describe(self) -> dict:
        """A JSON-friendly overview (what `airwake recording info` prints)."""
        return {
            "path": str(self.path),
            "complete": self.complete,
            "segments": [{"path": str(s.path), "indexed": s.indexed, "complete": s.complete,
                          "bytes": s.size, "recovered_bytes": s.recovered_bytes,
                          "error": s.error} for s in self.segments],
            "metadata": self.metadata,
            "boards": self.boards,
            "summary": self.summary,
            "topics": self.topics(),
        }


def _parse(v: str):
    try:
        return json.loads(v)
    except (ValueError, TypeError):
        return v


def open_recording(path) -> Recording:
    return Recording(path)


def recover_recording(src, dst) -> Path:
    """Write `src` (possibly unfinished) out again as one closed, indexed segment in dst."""
    from airwake.record.recording import RecordingWriter

    rec = open_recording(src)
    writer = RecordingWriter(dst, {**rec.metadata, "recovered_from": str(rec.path)},
                             segment_s=float("inf"))
    for name, info in rec.boards.items():
        writer.board(name, info)
    for s in rec._segments:
        for schema, channel, m in s.iter_records(None):
            # a free-form JSON channel keeps its schema (/host/pose, /host/airwake_intensity)
            js = ((schema.name, schema.encoding, bytes(schema.data))
                  if schema is not None and channel.message_encoding == "json" else None)
            writer.copy(channel.topic, m.log_time, m.publish_time, bytes(m.data), js)
    writer.close({"recovered": True, "source_segments": [str(i.path) for i in rec.segments],
                  "source_complete": rec.complete})
    if writer.failed:
        raise RecordingReadError(writer.failed)
    return Path(dst)


__all__ = ["RAW_ENCODING", "DecodedTable", "RawStream", "RecordedMessage", "Recording",
           "RecordingReadError", "SegmentInfo", "open_recording", "recover_recording"]
