"""`airwake daemon --foxglove [HOST:]PORT`: the recording's messages live over the Foxglove
WebSocket protocol (`foxglove-sdk`), so Foxglove shows in flight what it shows after it
(docs/daemon.md "Foxglove").

Every decoded frame and every JSON message (host estimates, status, events) is published
on the channel name, encoding and schema it has in the recording: `/<board>/<message>` as
`ros1` with the `ros1msg` schema `airwake/<message>`, `/host/...` and `/daemon/...` as
`json` with their JSON schema, `log_time` = the recording's. Raw port bytes are not
published. No capability is advertised (no client publishing, parameters or services):
a client can subscribe and nothing else.

A thread drains the outbox (`live_outputs.Outbox`, filled by the ingest thread) every
`DRAIN_S` and logs to the SDK's server, which keeps a queue of `BACKLOG` messages per
client and drops a slow client's oldest (the SDK does not count those; our outbox's own
drops are counted in the status).
"""

from __future__ import annotations

import json
import threading

from airwake.daemon.live_outputs import Bind, LiveOptionError, Outbox
from airwake.record.recording import ros1_schema

DRAIN_S = 0.02
BACKLOG = 1024  # messages per client (~0.7 s of every frame): the SDK drops the oldest
STOP_WAIT_S = 2.0


class FoxgloveBridge:
    """The Foxglove server of a daemon run; `start()` binds (or raises `LiveOptionError`)."""

    wants_decoded = True

    def __init__(self, bind: Bind) -> None:
        self.bind = bind
        self.port = bind.port
        self.outbox = Outbox()
        self.channels: dict[str, object] = {}
        self.published = 0
        self.errors = 0
        self.subscriptions: dict[int, set[int]] = {}  # client id -> channel ids
        self._server = None
        self._context = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="airwake-foxglove", daemon=True)

    def start(self) -> None:
        import foxglove

        self._context = foxglove.Context()
        try:
            self._server = foxglove.start_server(
                name="airwake daemon", host=self.bind.host, port=self.bind.port,
                capabilities=[], context=self._context, message_backlog_size=BACKLOG,
                server_listener=_Subscriptions(self.subscriptions))
        except Exception as exc:  # noqa: BLE001 -- the SDK raises its own error types
            raise LiveOptionError(f"--foxglove {self.bind.host}:{self.bind.port}: cannot "
                                  f"listen: {exc}") from None
        self.port = self._server.port
        self._thread.start()

    def close(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(5.0)
        if self._server is not None:
            # the SDK's stop() waits for each client's close handshake, which a client that
            # stopped reading never completes: give it STOP_WAIT_S, then let the process go
            stopper = threading.Thread(target=self._server.stop, daemon=True,
                                       name="airwake-foxglove-stop")
            stopper.start()
            stopper.join(STOP_WAIT_S)
            self._server = None

    def status(self) -> dict:
        subs = dict(self.subscriptions)
        return {"bind": f"{self.bind.host}:{self.port}", "clients": len(subs),
                "subscriptions": sum(len(v) for v in subs.values()),
                "channels": len(self.channels), "published": self.published,
                "outbox_dropped": self.outbox.dropped, "errors": self.errors}

    def _run(self) -> None:
        while not self._stop.wait(DRAIN_S):
            for item in self.outbox.drain():
                try:
                    self._log(*item)
                except Exception:  # noqa: BLE001 -- a bad message must not end the bridge
                    self.errors += 1

    def _log(self, kind: str, topic: str, log_ns: int, meta, payload) -> None:
        ch = self.channels.get(topic)
        if ch is None:
            ch = self.channels[topic] = self._channel(kind, topic, meta)
        if kind == "json":
            payload = json.dumps(payload, default=str).encode()
        ch.log(payload, log_time=log_ns)
        self.published += 1

    def _channel(self, kind: str, topic: str, meta):
        """The recording's channel: same topic, message encoding and schema."""
        import foxglove

        if kind == "decoded":
            schema = foxglove.Schema(name=f"airwake/{meta.name}", encoding="ros1msg",
                                     data=ros1_schema(meta).encode())
            encoding = "ros1"
        else:
            schema = foxglove.Schema(name=f"airwake{topic.replace('/', '.')}",
                                     encoding="jsonschema",
                                     data=json.dumps(meta or {"type": "object"}).encode())
            encoding = "json"
        return foxglove.Channel(topic, schema=schema, message_encoding=encoding,
                                context=self._context)


class _Subscriptions:
    """The SDK's listener: which client holds which subscription (for the status)."""

    def __init__(self, table: dict[int, set[int]]) -> None:
        self.table = table

    def on_subscribe(self, client, channel) -> None:
        self.table.setdefault(client.id, set()).add(channel.id)

    def on_unsubscribe(self, client, channel) -> None:
        subs = self.table.get(client.id)
        if subs is not None:
            subs.discard(channel.id)
            if not subs:
                self.table.pop(client.id, None)


__all__ = ["FoxgloveBridge"]
