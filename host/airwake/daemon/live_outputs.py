"""The daemon's live outputs: the web page (`--live`) and Foxglove (`--foxglove`), fed from
the ingest loop without ever making it wait (docs/daemon.md "Live view").

The ingest thread only appends to bounded `Outbox`es (a deque append: no lock, no
allocation beyond the bound, never a socket): `RecorderTee` hands each message to them
after the recorder has written it, so the recording always comes first. Each output runs
in its own thread and drains its outbox on its own schedule; when one falls behind, its
oldest items are dropped and counted (`dropped`), the recording and the other output
untouched. Per-client queues inside each output bound a slow client in the same way.
"""

from __future__ import annotations

import ipaddress
import secrets
from collections import deque
from dataclasses import dataclass

from airwake.errors import AirwakeError

OUTBOX_ITEMS = 20_000  # ~10 s of every decoded frame at the protocol's full rates


class LiveOptionError(AirwakeError):
    """A --live / --foxglove value that does not parse or cannot be served."""


@dataclass(frozen=True)
class Bind:
    """Where a live output listens: loopback unless another interface is named."""

    host: str
    port: int

    @classmethod
    def parse(cls, text: str, option: str) -> Bind:
        """`PORT`, `HOST:PORT` or `[V6]:PORT`; a bare port binds 127.0.0.1."""
        host, sep, port = text.rpartition(":")
        if not sep:
            host = "127.0.0.1"
        host = host.strip("[]")
        try:
            number = int(port)
        except ValueError:
            number = -1
        if not 0 <= number <= 65535 or (sep and not host):
            raise LiveOptionError(f"{option} '{text}': expected [HOST:]PORT, e.g. 8080 "
                                  "(loopback) or 0.0.0.0:8080 (every interface)")
        return cls(host, number)

    @property
    def loopback(self) -> bool:
        if self.host == "localhost":
            return True
        try:
            return ipaddress.ip_address(self.host).is_loopback
        except ValueError:  # a host name: may resolve anywhere
            return False


class Outbox:
    """A bounded hand-over from the ingest thread to one consumer thread.

    `put` never blocks: when `size` items wait, the oldest is dropped (counted). CPython's
    deque append/popleft are atomic, so no lock is taken on either side.
    """

    def __init__(self, size: int = OUTBOX_ITEMS) -> None:
        self._q: deque = deque(maxlen=size)
        self.put_count = 0
        self.dropped = 0

    def put(self, item) -> None:
        q = self._q
        if len(q) == q.maxlen:
            self.dropped += 1
        q.append(item)
        self.put_count += 1

    def drain(self) -> list:
        out = []
        pop = self._q.popleft
        try:
            while True:
                out.append(pop())
        except IndexError:
            return out


class RecorderTee:
    """The daemon's `RecordingWriter`, with every decoded frame and JSON message also put
    into the live outputs' outboxes (after the recorder has it). Everything else — `raw`,
    `tick`, `failed`, `close`, ... — is the recorder's own."""

    def __init__(self, recorder, decoded: list[Outbox], json: list[Outbox]) -> None:
        self._recorder = recorder
        self._decoded = decoded
        self._json = json

    def decoded(self, topic: str, info, log_ns: int, publish_ns: int, body: bytes) -> None:
        self._recorder.decoded(topic, info, log_ns, publish_ns, body)
        for box in self._decoded:
            box.put(("decoded", topic, log_ns, info, body))

    def json(self, topic: str, log_ns: int, obj: dict, schema: dict | None = None) -> None:
        self._recorder.json(topic, log_ns, obj, schema)
        for box in self._json:
            box.put(("json", topic, log_ns, schema, obj))

    def __getattr__(self, name: str):
        return getattr(self._recorder, name)


class LiveOutputs:
    """The page and/or Foxglove server of one daemon run (started here, closed by
    `close()`); `tee(recorder)` wires them to the recording's messages."""

    def __init__(self, live: str | None, foxglove: str | None, say) -> None:
        self.page = self.foxglove = None
        self.token: str | None = None
        try:
            if live is not None:
                from airwake.daemon.live_web import LivePage

                bind = Bind.parse(live, "--live")
                # beyond the loopback anyone on the ship's network could read the page
                self.token = None if bind.loopback else secrets.token_urlsafe(18)
                self.page = LivePage(bind, self.token)
                self.page.start()
                query = f"/?token={self.token}" if self.token else "/"
                say(f"live page: http://{_url_host(bind.host)}:{self.page.port}{query}"
                    + (" (the token is required: the page is bound beyond the loopback)"
                       if self.token else ""))
            if foxglove is not None:
                from airwake.daemon.foxglove_bridge import FoxgloveBridge

                bind = Bind.parse(foxglove, "--foxglove")
                self.foxglove = FoxgloveBridge(bind)
                self.foxglove.start()
                say(f"foxglove: ws://{_url_host(bind.host)}:{self.foxglove.port} "
                    "(Foxglove: Open connection -> Foxglove WebSocket)")
        except BaseException:
            self.close()
            raise

    def tee(self, recorder) -> RecorderTee:
        outs = [o for o in (self.page, self.foxglove) if o is not None]
        return RecorderTee(recorder, [o.outbox for o in outs if o.wants_decoded],
                           [o.outbox for o in outs])

    def status(self) -> dict:
        """Clients and drops per output (the `live` key of the daemon's status)."""
        return {name: o.status() for name, o in (("page", self.page),
                                                  ("foxglove", self.foxglove)) if o is not None}

    def close(self) -> None:
        for o in (self.page, self.foxglove):
            if o is not None:
                o.close()


def _url_host(host: str) -> str:
    return f"[{host}]" if ":" in host else host


__all__ = ["Bind", "LiveOptionError", "LiveOutputs", "Outbox", "RecorderTee"]
