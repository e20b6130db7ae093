"""Clients of the daemon's live outputs for the tests: plain HTTP, a server-sent-event
reader, a stream that never reads, and a minimal Foxglove WebSocket client (the
Foxglove WebSocket protocol, subprotocol `foxglove.sdk.v1`:
advertise, subscribe, binary message data)."""

from __future__ import annotations

import base64
import json
import os
import socket
import struct
import time


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def http(port: int, request: bytes, host: str = "127.0.0.1", timeout: float = 5.0) -> bytes:
    """Send raw request bytes, return everything the server answers until it closes."""
    with socket.create_connection((host, port), timeout=timeout) as s:
        s.sendall(request)
        out = b""
        while chunk := s.recv(65536):
            out += chunk
    return out


def get(port: int, path: str = "/", headers: str = "",
        host: str = "127.0.0.1") -> tuple[int, bytes]:
    """(status code, body) of a GET."""
    answer = http(port, f"GET {path} HTTP/1.1\r\nHost: x\r\n{headers}\r\n".encode(), host)
    head, _, body = answer.partition(b"\r\n\r\n")
    return int(head.split(b" ", 2)[1]), body


class EventStream:
    """`GET /events`, read as server-sent events (one JSON object per `data:` line)."""

    def __init__(self, port: int, path: str = "/events", host: str = "127.0.0.1") -> None:
        self.sock = socket.create_connection((host, port), timeout=10)
        self.sock.sendall(f"GET {path} HTTP/1.1\r\nHost: x\r\n\r\n".encode())
        self.buf = b""
        head = self._until(b"\r\n\r\n")
        self.status = int(head.split(b" ", 2)[1])

    def _until(self, sep: bytes) -> bytes:
        while sep not in self.buf:
            chunk = self.sock.recv(65536)
            if not chunk:
                raise ConnectionError("stream closed")
            self.buf += chunk
        part, _, self.buf = self.buf.partition(sep)
        return part

    def next(self) -> dict:
        while True:
            block = self._until(b"\n\n")
            for line in block.split(b"\n"):
                if line.startswith(b"data: "):
                    return json.loads(line[6:])

    def close(self) -> None:
        self.sock.close()


def stalled_stream(port: int, query: str = "", host: str = "127.0.0.1") -> socket.socket:
    """An `/events` client that never reads: a small receive buffer fills at once."""
    s = socket.socket()
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    s.connect((host, port))
    s.sendall(f"GET /events{query} HTTP/1.1\r\nHost: x\r\n\r\n".encode())
    return s


class FoxgloveClient:
    """The Foxglove WebSocket protocol from the client side (RFC 6455 framing by hand)."""

    def __init__(self, port: int, host: str = "127.0.0.1", timeout: float = 10.0) -> None:
        self.sock = socket.create_connection((host, port), timeout=timeout)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET / HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                           "Sec-WebSocket-Version: 13\r\n"
                           "Sec-WebSocket-Protocol: foxglove.sdk.v1\r\n\r\n").encode())
        self.buf = b""
        while b"\r\n\r\n" not in self.buf:
            self.buf += self._recv()
        head, _, self.buf = self.buf.partition(b"\r\n\r\n")
        self.handshake = head.decode("latin-1")
        self.channels: dict[int, dict] = {}
        self.server_info: dict | None = None

    def _recv(self) -> bytes:
        chunk = self.sock.recv(65536)
        if not chunk:
            raise ConnectionError("foxglove server closed the connection")
        return chunk

    def _read(self, n: int) -> bytes:
        while len(self.buf) < n:
            self.buf += self._recv()
        out, self.buf = self.buf[:n], self.buf[n:]
        return out

    def frame(self) -> tuple[int, bytes]:
        """(opcode, payload) of the next frame (the server's frames are never fragmented)."""
        b0, b1 = self._read(2)
        n = b1 & 0x7F
        if n == 126:
            n = struct.unpack(">H", self._read(2))[0]
        elif n == 127:
            n = struct.unpack(">Q", self._read(8))[0]
        return b0 & 0x0F, self._read(n)

    def send_json(self, obj: dict) -> None:
        data = json.dumps(obj).encode()
        mask = os.urandom(4)
        n = len(data)
        head = bytes([0x81]) + (bytes([0x80 | n]) if n < 126 else
                                bytes([0x80 | 126]) + struct.pack(">H", n))
        self.sock.sendall(head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))

    def message(self) -> tuple[str, object]:
        """The next text message as ("json", obj) or message data as ("data", (sub id,
        time ns, payload)); control frames are skipped."""
        while True:
            op, payload = self.frame()
            if op == 1:
                m = json.loads(payload)
                if m.get("op") == "serverInfo":
                    self.server_info = m
                elif m.get("op") == "advertise":
                    for ch in m["channels"]:
                        self.channels[ch["id"]] = ch
                return "json", m
            if op == 2 and payload[0] == 1:
                sub, t_ns = struct.unpack_from("<IQ", payload, 1)
                return "data", (sub, t_ns, payload[13:])
            if op == 8:
                raise ConnectionError("foxglove server sent close")

    def wait_channels(self, topics: set[str], timeout: float = 10.0) -> dict[str, dict]:
        """Read until every topic is advertised: {topic: channel}."""
        end = time.monotonic() + timeout
        while True:
            have = {c["topic"]: c for c in self.channels.values()}
            if topics <= set(have):
                return have
            if time.monotonic() > end:
                raise AssertionError(f"not advertised: {sorted(topics - set(have))}")
            self.message()

    def subscribe(self, channel_ids: dict[int, int]) -> None:
        """{subscription id: channel id}."""
        self.send_json({"op": "subscribe", "subscriptions": [
            {"id": sid, "channelId": cid} for sid, cid in channel_ids.items()]})

    def close(self) -> None:
        self.sock.close()
