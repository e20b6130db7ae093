"""The daemon's live outputs attached to a real daemon (fake boards over ptys): a Foxglove
client receives the recording's channels; hung, garbage-sending and many clients cost the
recording nothing. The page's server alone: test_live_page.py."""

from __future__ import annotations

import json
import re
import socket
import threading
import time

import pytest
from airwake.daemon.fake_boards import FakeBoard
from airwake.record.reader import open_recording
from daemon_harness import DaemonRun, close_boards, halt_and_drain, recorded_frames, sent_frames
from live_clients import EventStream, FoxgloveClient, free_port, get, http, stalled_stream

# timed against the wall clock with real processes: `make test` runs these after the
# parallel suite (two at a time)
pytestmark = pytest.mark.wall_clock

ROLES = ["losa", "marker", "base"]
SHORT_STALL_S = 8.0  # the issue asks for 60 s: test_hung_clients_for_a_minute


def hostile_clients(port: int, token: str, fox_port: int, stop: threading.Event) -> dict:
    """Attach what the recording must survive: 50 event streams that never read, a
    Foxglove client subscribed to everything that never reads, and a stream of garbage
    requests until `stop`. Returns what it holds, for closing."""
    held = {"streams": [stalled_stream(port, f"?token={token}") for _ in range(50)]}
    fox = FoxgloveClient(fox_port)
    fox.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    have = fox.wait_channels({"/rover/ins", "/host/pose"})
    fox.subscribe({i + 1: c["id"] for i, c in enumerate(have.values())})
    held["foxglove"] = fox

    def garbage() -> None:
        held["garbage_rounds"] = 0
        while not stop.wait(0.1):
            held["garbage_rounds"] += 1
            for req in (bytes(range(256)) + b"\r\n\r\n", b"POST / HTTP/1.1\r\n\r\n",
                        b"GET /" + b"x" * 9000,
                        b"GET /events HTTP/1.1\r\n\r\n"):  # the last: no token
                try:
                    http(port, req, timeout=1.0)
                except OSError:
                    pass

    held["thread"] = threading.Thread(target=garbage, daemon=True)
    held["thread"].start()
    return held


def run_with_hostile_clients(run_dir, stall_s: float) -> dict:
    boards = FakeBoard.standard_set(run_dir)
    live, fox = free_port(), free_port()
    daemon = DaemonRun(run_dir, ROLES, "--live", f"0.0.0.0:{live}", "--foxglove", str(fox))
    stop = threading.Event()
    held = {}
    try:
        daemon.wait_ports_open(ROLES)
        for b in boards:
            b.start()
        daemon.wait_for(lambda st: len(st["boards"]) == 4, 15, "4 boards")
        token = re.search(r"\?token=(\S+)", daemon.stderr()).group(1)
        held = hostile_clients(live, token, fox, stop)
        time.sleep(stall_s)
        during = daemon.status()
        # what the snapshot can have counted (it is up to ~1 s old: 0.5 s status period,
        # 0.25 s page tick)
        held["rounds_seen"] = held["garbage_rounds"] - 12
        stop.set()
        held["thread"].join(10)
        halt_and_drain(boards)
        rc = daemon.stop()
    finally:
        stop.set()
        for s in held.get("streams", []):
            s.close()
        if "foxglove" in held:
            held["foxglove"].close()
        daemon.stop()
        close_boards(boards)
    return {"rc": rc, "during": during, "rec": open_recording(daemon.out), "boards": boards,
            "held": held, "stderr": daemon.stderr()}


def assert_recording_lost_nothing(r: dict) -> None:
    assert r["rc"] == 0, r["stderr"][-2000:]
    got = recorded_frames(r["rec"])
    wanted = sent_frames(r["boards"])
    assert len(wanted) > 10_000 and wanted <= got, len(wanted - got)


def assert_hostile_clients_were_bounded(r: dict, stall_s: float) -> None:
    page = r["during"]["live"]["page"]
    print(f"after {stall_s} s:", json.dumps({k: v for k, v in page.items()
                                              if k != "streams_now"}))
    # the 50 hung streams lose their own events (counted), nothing else does
    assert page["clients"] == 50 and page["streams"] >= 50
    assert page["dropped_for_clients"] > 0 and page["outbox_dropped"] == 0
    rounds = r["held"]["rounds_seen"]
    assert rounds > 5 * stall_s
    assert page["bad_requests"] >= 2 * rounds
    assert page["not_allowed"] >= rounds and page["unauthorized"] >= rounds
    assert r["during"]["live"]["foxglove"]["outbox_dropped"] == 0
    for role in ROLES:  # ingest at full rate throughout
        assert r["during"]["ports"][role]["bytes_per_s"] > 10_000


def test_hung_and_garbage_clients_cost_the_recording_nothing(run_dir):
    # the promise of the live view: never at the expense of the recording
    r = run_with_hostile_clients(run_dir, SHORT_STALL_S)
    assert_recording_lost_nothing(r)
    assert_hostile_clients_were_bounded(r, SHORT_STALL_S)


@pytest.mark.slow
def test_hung_clients_for_a_minute_cost_the_recording_nothing(run_dir):
    # the case as stated: clients that stop reading for 60 s
    r = run_with_hostile_clients(run_dir, 60.0)
    assert_recording_lost_nothing(r)
    assert_hostile_clients_were_bounded(r, 60.0)


def test_foxglove_client_receives_the_recorded_channels(run_dir):
    # an operator with Foxglove sees live what the recording holds, under the same names
    boards = FakeBoard.standard_set(run_dir)
    live, fox_port = free_port(), free_port()
    daemon = DaemonRun(run_dir, ROLES, "--live", str(live), "--foxglove", str(fox_port))
    fox = None
    try:
        daemon.wait_ports_open(ROLES)
        for b in boards:
            b.start()
        daemon.wait_for(lambda st: len(st["boards"]) == 4, 15, "4 boards")
        # /host/pose exists once the tracker (loaded at the first marker frame) has
        # started; a subscription sent the instant a channel is advertised was seen lost
        # by the SDK now and then (1 in 3 runs), so the client comes after it
        daemon.wait_for(lambda st: st.get("tracker", {}).get("started"), 15, "tracker")
        assert f"foxglove: ws://127.0.0.1:{fox_port}" in daemon.stderr()
        fox = FoxgloveClient(fox_port)
        assert "sec-websocket-protocol: foxglove.sdk.v1" in fox.handshake
        want = {"/rover/ins", "/losa/losa_peaks", "/host/pose", "/daemon/status"}
        have = fox.wait_channels(want, 15)
        assert have["/rover/ins"]["encoding"] == "ros1"
        assert have["/rover/ins"]["schemaName"] == "airwake/ins"
        assert have["/host/pose"]["encoding"] == "json"
        assert json.loads(have["/host/pose"]["schema"])["title"] == "airwake.pose"
        subs = {i + 1: have[t]["id"] for i, t in enumerate(sorted(want))}
        topic_of = {sid: t for sid, t in zip(subs, sorted(want), strict=True)}
        fox.subscribe(subs)
        got: dict[str, list] = {t: [] for t in want}
        end = time.monotonic() + 10
        while time.monotonic() < end and min(len(v) for v in got.values()) < 3:
            kind, m = fox.message()
            if kind == "data":
                sid, t_ns, payload = m
                got[topic_of[sid]].append((t_ns, payload))
        # the page is up beside it
        assert get(live, "/")[0] == 200
        es = EventStream(live)
        assert es.next()["hello"]
        t0, events, statuses = time.monotonic(), 0, 0
        while time.monotonic() - t0 < 3.0:  # the update rate, as a page sees it
            m = es.next()
            events += 1
            statuses += "status" in m
        es.close()
        halt_and_drain(boards)
        rc = daemon.stop()
    finally:
        if fox is not None:
            fox.close()
        daemon.stop()
        close_boards(boards)
    assert rc == 0
    assert all(len(v) >= 3 for v in got.values()), {k: len(v) for k, v in got.items()}
    # byte for byte the recorded message with the same log time
    rec = open_recording(daemon.out)
    recorded = {(m.topic, m.log_ns): m.data
                for m in rec.messages(["/rover/ins", "/losa/losa_peaks", "/host/pose"])}
    for topic in ("/rover/ins", "/losa/losa_peaks", "/host/pose"):
        for t_ns, payload in got[topic]:
            assert recorded[(topic, t_ns)] == payload, topic
    # the daemon counts the client and its subscriptions (the last status: after them)
    fox_status = json.loads(got["/daemon/status"][-1][1])["live"]["foxglove"]
    assert fox_status["clients"] == 1 and fox_status["subscriptions"] == len(want)
    assert fox_status["outbox_dropped"] == 0 and fox_status["errors"] == 0
    # >= 2 Hz: 4 events/s, a new status in every other one
    assert events >= 11 and statuses >= 5, (events, statuses)
