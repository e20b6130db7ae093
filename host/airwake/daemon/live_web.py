"""The live page (`airwake daemon --live [HOST:]PORT`): link health, recording state and
the live estimates in a browser, pushed as server-sent events (docs/daemon.md "Live view").

An asyncio loop in its own thread serves three read-only routes: `/` (the page,
`live_page.html`: inline CSS and JS, nothing fetched from elsewhere), `/events` (the
stream) and `/status.json` (the latest snapshot, the same object `--status-json` writes).
Every `TICK_S` the loop drains its outbox (`live_outputs.Outbox`, filled by the ingest
thread): the newest `/daemon/status` snapshot, new `/daemon/events`, and the `/host/*`
estimates thinned to `PLOT_HZ`, serialised once into one event for every client.

What a client can do to it, and what happens (the recording is never involved):
- does not read: its queue holds `CLIENT_QUEUE` events, then the oldest are dropped and
  counted for that client only (`dropped`); the others keep their rate;
- sends garbage or nothing: 400 (or closed after `HEADER_TIMEOUT_S`), counted;
- opens many connections: beyond `MAX_CONNECTIONS` refused with 503, counted;
- anything but GET/HEAD: 405 (the page has no control that could reach a board);
- bound beyond the loopback, a request without the daemon's token (`?token=`, or
  `Authorization: Bearer`): 401, with a wrong one: 403.
"""

from __future__ import annotations

import asyncio
import functools
import hmac
import json
import math
import socket
import threading
import time
from collections import deque
from importlib import resources
from urllib.parse import parse_qs, urlsplit

from airwake.daemon.live_outputs import Bind, LiveOptionError, Outbox

TICK_S = 0.25  # one event per tick to every client: the page updates at 4 Hz
PLOT_HZ = 20.0  # estimate samples kept per channel and second (pose comes at 120 Hz)
PLOT_HISTORY_S = 60.0  # what a new page gets to draw at once
EVENTS_KEPT = 20
CLIENT_QUEUE = 8  # events waiting per client (2 s at TICK_S) before its oldest drop
MAX_CONNECTIONS = 64
HEADER_TIMEOUT_S = 5.0
HEADER_LIMIT = 8192
# Bytes a stalled stream may hold below its queue: the socket's send buffer (fixed, so
# the kernel's autotuning cannot hide megabytes of backlog) and the transport's buffer.
SEND_BUFFER = 32768

# The fields drawn per estimate channel (others: their first numeric fields).
PLOT_FIELDS = {
    "/host/pose": ("pos_tracker_m", "pos_sigma_m"),
    # ship_x/y_m: the track in the ship frame (the page's A_ω-along-the-track plot)
    "/host/airwake_intensity": ("a_omega", "omega_s", "resid_norm", "ship_x_m", "ship_y_m"),
    "/host/tracker_position": ("pos_tracker_m",),
    "/host/wind": ("wind_vx_m_s", "wind_vy_m_s", "wind_vz_m_s"),
}
OTHER_FIELDS_MAX = 3

# `--live` runs inside simulated time too (`hil_sim.boards.simclock` replaces
# time.monotonic in the daemon's process, and stands it still while the simulator
# pauses): the server's timeouts and ticks follow the real clock.
_real_monotonic = functools.partial(time.clock_gettime, time.CLOCK_MONOTONIC)

_REASONS = {200: "OK", 204: "No Content", 400: "Bad Request", 401: "Unauthorized",
            403: "Forbidden", 404: "Not Found", 405: "Method Not Allowed",
            503: "Service Unavailable"}
_SECURITY_HEADERS = (
    # the page is self-contained: nothing may be loaded from, or sent to, another origin
    "Content-Security-Policy: default-src 'none'; script-src 'unsafe-inline'; "
    "style-src 'unsafe-inline'; connect-src 'self'; img-src data:\r\n"
    "X-Content-Type-Options: nosniff\r\nReferrer-Policy: no-referrer\r\n"
    "Cache-Control: no-store\r\n")


def plot_values(topic: str, obj: dict) -> dict[str, float]:
    """The plotted numbers of one estimate message: `{field or field[i]: value}`."""
    fields = PLOT_FIELDS.get(topic)
    if fields is None:
        fields = [k for k, v in obj.items() if k != "t_s" and not isinstance(v, bool)
                  and isinstance(v, int | float | list)][:OTHER_FIELDS_MAX]
    out = {}
    for k in fields:
        v = obj.get(k)
        if isinstance(v, bool):
            continue
        if isinstance(v, int | float):
            out[k] = _finite(v)
        elif isinstance(v, list) and v and all(isinstance(x, int | float) for x in v):
            for i, x in enumerate(v[:4]):
                out[f"{k}[{i}]"] = _finite(x)
    return out


def _finite(x: float) -> float | None:
    return round(float(x), 6) if math.isfinite(x) else None


class _Series:
    """One estimate channel thinned to PLOT_HZ, with PLOT_HISTORY_S of history."""

    def __init__(self) -> None:
        self.last_t = -math.inf
        self.history: deque = deque()
        self.new: list = []

    def add(self, t: float, values: dict) -> None:
        if t - self.last_t < 1.0 / PLOT_HZ:
            return
        self.last_t = t
        row = (round(t, 3), values)
        self.history.append(row)
        self.new.append(row)
        while self.history and self.history[0][0] < t - PLOT_HISTORY_S:
            self.history.popleft()

    @staticmethod
    def columns(rows) -> dict:
        names = sorted({k for _, v in rows for k in v})
        return {"t": [t for t, _ in rows], "f": {k: [v.get(k) for _, v in rows] for k in names}}


class _Client:
    """One `/events` stream: a bounded queue that drops its own oldest events."""

    def __init__(self, peer: str) -> None:
        self.peer = peer
        self.since = _real_monotonic()
        self.queue: deque = deque(maxlen=CLIENT_QUEUE)
        self.wake = asyncio.Event()
        self.sent = 0
        self.dropped = 0

    def put(self, data: bytes) -> None:
        if len(self.queue) == self.queue.maxlen:
            self.dropped += 1
        self.queue.append(data)
        self.wake.set()


class LivePage:
    """The page server (module doc). `start()` binds (raises `LiveOptionError` if it
    cannot) and returns; `outbox` is what the daemon's `RecorderTee` fills."""

    wants_decoded = False  # the page shows status and estimates, not every frame

    def __init__(self, bind: Bind, token: str | None) -> None:
        self.bind = bind
        self.token = token
        self.outbox = Outbox()
        self.port = bind.port
        self.page = resources.files("airwake.daemon").joinpath("live_page.html").read_bytes()
        self.status_obj: dict | None = None
        self.status_bytes = b"null"
        self.events: deque = deque(maxlen=EVENTS_KEPT)
        self.series: dict[str, _Series] = {}
        self.clients: set[_Client] = set()
        self.connections = 0
        self.counts = {"accepted": 0, "refused": 0, "bad_requests": 0, "unauthorized": 0,
                       "forbidden": 0, "not_found": 0, "not_allowed": 0, "streams": 0,
                       "dropped_closed": 0, "tick_errors": 0}
        self.snapshot: dict = self._snapshot()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop: asyncio.Event | None = None
        self._ready = threading.Event()
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, name="airwake-live-page", daemon=True)

    # -- thread ------------------------------------------------------------------------

    def start(self) -> None:
        self._thread.start()
        self._ready.wait(10.0)
        if self._error is not None:
            raise LiveOptionError(f"--live {self.bind.host}:{self.bind.port}: cannot listen: "
                                  f"{self._error}") from None

    def close(self) -> None:
        if self._loop is not None and self._stop is not None and self._thread.is_alive():
            self._loop.call_soon_threadsafe(self._stop.set)
            self._thread.join(5.0)

    def status(self) -> dict:
        """Counters for the daemon's status (a snapshot the page's thread keeps current)."""
        return self.snapshot

    def _run(self) -> None:
        loop = asyncio.new_event_loop()
        loop.time = _real_monotonic  # see _real_monotonic
        asyncio.set_event_loop(loop)
        self._loop = loop
        try:
            loop.run_until_complete(self._main())
        except BaseException as exc:  # noqa: BLE001 -- reported by start(); ingest goes on
            self._error = exc
        finally:
            self._ready.set()
            pending = [t for t in asyncio.all_tasks(loop) if not t.done()]
            for t in pending:
                t.cancel()
            if pending:
                loop.run_until_complete(asyncio.wait(pending, timeout=2.0))
            loop.close()

    async def _main(self) -> None:
        self._stop = asyncio.Event()
        server = await asyncio.start_server(self._connection, self.bind.host, self.bind.port,
                                            limit=HEADER_LIMIT, reuse_address=True)
        self.port = server.sockets[0].getsockname()[1]
        self._ready.set()
        ticker = asyncio.ensure_future(self._ticker())
        async with server:
            await self._stop.wait()
            ticker.cancel()
            for c in list(self.clients):
                c.wake.set()

    # -- the feed ----------------------------------------------------------------------

    async def _ticker(self) -> None:
        while True:
            await asyncio.sleep(TICK_S)
            try:
                self._tick()
            except Exception:  # noqa: BLE001 -- e.g. a status dict changed while encoded
                self.counts["tick_errors"] += 1

    def _tick(self) -> None:
        new_status = None
        new_events = []
        for _kind, topic, log_ns, _schema, obj in self.outbox.drain():
            if topic == "/daemon/status":
                new_status = obj
            elif topic == "/daemon/events":
                obj = _plain(obj)
                new_events.append(obj)
                self.events.append(obj)
            elif topic.startswith("/host/"):
                values = plot_values(topic, obj)
                if values:
                    t = obj.get("t_s", log_ns / 1e9)
                    self.series.setdefault(topic, _Series()).add(float(t), values)
        msg: dict = {"server": self.snapshot}
        if new_status is not None:
            self.status_obj = _plain(new_status)
            self.status_bytes = json.dumps(self.status_obj, default=str).encode()
            msg["status"] = self.status_obj
        if new_events:
            msg["events"] = new_events
        points = {topic: _Series.columns(s.new) for topic, s in self.series.items() if s.new}
        for s in self.series.values():
            s.new = []
        if points:
            msg["points"] = points
        self.snapshot = self._snapshot()
        data = _sse(msg)
        for c in self.clients:
            c.put(data)

    def _hello(self) -> bytes:
        """What a new page gets at once: the latest snapshot, events and plot history."""
        return b"retry: 1000\n" + _sse({
            "hello": True, "server": self.snapshot, "status": self.status_obj,
            "events": list(self.events), "plot_history_s": PLOT_HISTORY_S,
            "points": {topic: _Series.columns(s.history) for topic, s in self.series.items()}})

    def _snapshot(self) -> dict:
        worst = sorted(self.clients, key=lambda c: -c.dropped)[:10]
        now = _real_monotonic()
        return {"bind": f"{self.bind.host}:{self.port}", "token_required": bool(self.token),
                "connections": self.connections, "clients": len(self.clients),
                "outbox_dropped": self.outbox.dropped,
                "dropped_for_clients": self.counts["dropped_closed"]
                + sum(c.dropped for c in self.clients),
                **{k: v for k, v in self.counts.items() if k != "dropped_closed"},
                "streams_now": [{"peer": c.peer, "age_s": round(now - c.since, 1),
                                 "sent": c.sent, "dropped": c.dropped} for c in worst]}

    # -- HTTP --------------------------------------------------------------------------

    async def _connection(self, reader: asyncio.StreamReader,
                          writer: asyncio.StreamWriter) -> None:
        if self.connections >= MAX_CONNECTIONS:
            self.counts["refused"] += 1
            await self._respond(writer, 503, b"too many connections\n")
            return
        self.connections += 1
        self.counts["accepted"] += 1
        try:
            await self._serve(reader, writer)
        except (TimeoutError, ConnectionError, OSError):
            pass
        finally:
            self.connections -= 1
            writer.close()

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            head = await asyncio.wait_for(reader.readuntil(b"\r\n\r\n"), HEADER_TIMEOUT_S)
            method, target, headers = _parse_request(head)
        except (TimeoutError, asyncio.IncompleteReadError, asyncio.LimitOverrunError, ValueError):
            self.counts["bad_requests"] += 1
            await self._respond(writer, 400, b"bad request\n")
            return
        if method not in ("GET", "HEAD"):
            self.counts["not_allowed"] += 1
            await self._respond(writer, 405, b"read-only: GET only\n", "Allow: GET, HEAD\r\n")
            return
        url = urlsplit(target)
        refused = self._check_token(url.query, headers)
        if refused:
            await self._respond(writer, refused, b"this page needs the token the daemon "
                                b"printed at start: ?token=...\n")
            return
        body_only = method == "GET"
        if url.path == "/":
            await self._respond(writer, 200, self.page, "Content-Type: text/html; "
                                "charset=utf-8\r\n", body_only)
        elif url.path == "/status.json":
            await self._respond(writer, 200, self.status_bytes,
                                "Content-Type: application/json\r\n", body_only)
        elif url.path == "/events" and body_only:
            await self._stream(writer)
        elif url.path == "/favicon.ico":
            await self._respond(writer, 204, b"")
        else:
            self.counts["not_found"] += 1
            await self._respond(writer, 404, b"not found\n")

    def _check_token(self, query: str, headers: dict) -> int:
        """0 when allowed, else the status to answer (401 no token, 403 a wrong one)."""
        if not self.token:
            return 0
        given = parse_qs(query).get("token", [None])[0]
        auth = headers.get("authorization", "")
        if given is None and auth.lower().startswith("bearer "):
            given = auth[7:].strip()
        if given is None:
            self.counts["unauthorized"] += 1
            return 401
        if not hmac.compare_digest(given.encode(), self.token.encode()):
            self.counts["forbidden"] += 1
            return 403
        return 0

    async def _respond(self, writer: asyncio.StreamWriter, code: int, body: bytes,
                       extra: str = "", with_body: bool = True) -> None:
        head = (f"HTTP/1.1 {code} {_REASONS[code]}\r\nContent-Length: {len(body)}\r\n"
                f"{extra}{_SECURITY_HEADERS}Connection: close\r\n\r\n")
        if "Content-Type" not in extra:
            head = head.replace("\r\n\r\n", "\r\nContent-Type: text/plain\r\n\r\n", 1)
        writer.write(head.encode() + (body if with_body else b""))
        try:
            await asyncio.wait_for(writer.drain(), HEADER_TIMEOUT_S)
        except (TimeoutError, ConnectionError, OSError):
            pass

    async def _stream(self, writer: asyncio.StreamWriter) -> None:
        peer = writer.get_extra_info("peername")
        client = _Client(f"{peer[0]}:{peer[1]}" if peer else "?")
        self.counts["streams"] += 1
        sock = writer.get_extra_info("socket")
        if sock is not None:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SEND_BUFFER)
        writer.transport.set_write_buffer_limits(high=SEND_BUFFER)
        writer.write(("HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\n"
                      f"{_SECURITY_HEADERS}Connection: close\r\n\r\n").encode())
        client.put(self._hello())
        self.clients.add(client)
        try:
            while not self._stop.is_set():
                await client.wake.wait()
                client.wake.clear()
                while client.queue and not self._stop.is_set():
                    writer.write(client.queue.popleft())
                    client.sent += 1
                    # a client that does not read parks here; only its own queue fills
                    await writer.drain()
        finally:
            self.clients.discard(client)
            self.counts["dropped_closed"] += client.dropped


def _parse_request(head: bytes) -> tuple[str, str, dict]:
    lines = head.decode("latin-1").split("\r\n")
    parts = lines[0].split(" ")
    if len(parts) != 3 or not parts[2].startswith("HTTP/1.") or not parts[1].startswith("/"):
        raise ValueError(f"request line {lines[0][:80]!r}")
    headers = {}
    for line in lines[1:]:
        if line:
            k, sep, v = line.partition(":")
            if not sep:
                raise ValueError(f"header {line[:80]!r}")
            headers[k.strip().lower()] = v.strip()
    return parts[0], parts[1], headers


def _plain(obj):
    """obj with NaN and infinities as None (a browser's JSON.parse rejects them)."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _plain(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_plain(v) for v in obj]
    return obj


def _sse(msg: dict) -> bytes:
    """One server-sent event (its parts already free of NaN: `_plain`, `_finite`)."""
    return b"data: " + json.dumps(msg, default=str, allow_nan=False).encode() + b"\n\n"


__all__ = ["LivePage", "plot_values"]
