"""The live page's server on its own (no daemon): binding, the token, read-only routes,
garbage, many connections, and a client that never reads. The daemon end to end with
these clients attached: test_live_daemon.py; in Chromium on a SIL flight:
tests/sil/test_sil_live_page.py."""

from __future__ import annotations

import io
import os
import socket
import threading
import time

import pytest
from airwake.daemon import live_web
from airwake.daemon.live_outputs import Bind, LiveOptionError, LiveOutputs, Outbox, RecorderTee
from airwake.daemon.live_web import LivePage, plot_values
from live_clients import EventStream, get, http, stalled_stream


def status(t_s: float, pad: int = 0) -> dict:
    return {"t_s": t_s, "recording": {"state": "recording", "bytes": 1}, "ports": {},
            "boards": {}, "pad": "x" * pad, "nan": float("nan")}


@pytest.fixture
def page():
    p = LivePage(Bind("127.0.0.1", 0), None)
    p.start()
    yield p
    p.close()


def feed(p: LivePage, n: int, period_s: float, pad: int = 0) -> None:
    for i in range(n):
        p.outbox.put(("json", "/daemon/status", i, None, status(float(i), pad)))
        time.sleep(period_s)


def test_bind_is_loopback_unless_a_host_is_named():
    # the page must not appear on the ship's network by accident
    assert Bind.parse("8080", "--live") == Bind("127.0.0.1", 8080)
    assert Bind.parse("8080", "--live").loopback
    assert not Bind.parse("0.0.0.0:8080", "--live").loopback
    assert Bind.parse("[::1]:9", "--live") == Bind("::1", 9) and Bind("::1", 9).loopback
    assert Bind.parse("localhost:1", "--live").loopback
    assert not Bind.parse("ship-laptop:1", "--live").loopback
    for bad in ("", "x", ":80", "70000", "1.2.3.4:"):
        with pytest.raises(LiveOptionError, match="--live"):
            Bind.parse(bad, "--live")


def test_request_without_the_token_is_refused_beyond_the_loopback():
    # bound on every interface: anyone on the network could read link state and positions
    said = io.StringIO()
    outs = LiveOutputs("0.0.0.0:0", None, lambda t: said.write(t + "\n"))
    try:
        port, token = outs.page.port, outs.token
        assert token and f"http://0.0.0.0:{port}/?token={token}" in said.getvalue()
        for path in ("/", "/events", "/status.json"):
            assert get(port, path)[0] == 401
            assert get(port, path + "?token=wrong")[0] == 403
        assert get(port, "/", f"Authorization: Bearer {token[:-1]}x\r\n")[0] == 403
        code, body = get(port, f"/?token={token}")
        assert code == 200 and b"EventSource" in body
        assert get(port, "/", f"Authorization: Bearer {token}\r\n")[0] == 200
        es = EventStream(port, f"/events?token={token}")
        assert es.status == 200 and es.next()["hello"]
        es.close()
        time.sleep(2 * live_web.TICK_S)  # the counters are published once a tick
        st = outs.status()["page"]
        assert st["unauthorized"] == 3 and st["forbidden"] == 4 and st["token_required"]
    finally:
        outs.close()


def test_loopback_page_needs_no_token_and_is_self_contained(page):
    code, body = get(page.port, "/")
    assert code == 200
    html = body.decode()
    # no CDN, nothing fetched from elsewhere: the ship has no internet
    assert "http://" not in html and "https://" not in html and "<script src" not in html
    assert "<link" not in html and "@import" not in html
    answer = http(page.port, b"GET / HTTP/1.1\r\nHost: x\r\n\r\n")
    assert b"Content-Security-Policy: default-src 'none'" in answer


@pytest.mark.parametrize("method", ["POST", "PUT", "DELETE", "PATCH", "OPTIONS"])
def test_page_is_read_only(page, method):
    # nothing on the page can command a board or touch the recording
    answer = http(page.port, f"{method} / HTTP/1.1\r\nContent-Length: 0\r\n\r\n".encode())
    assert answer.startswith(b"HTTP/1.1 405") and b"Allow: GET, HEAD" in answer


def test_garbage_requests_are_answered_and_counted(page, monkeypatch):
    monkeypatch.setattr(live_web, "HEADER_TIMEOUT_S", 0.5)
    garbage = [os.urandom(200) + b"\r\n\r\n", b"\x00\xff\r\n\r\n", b"GET\r\n\r\n",
               b"GET / HTTP/1.1\r\nno colon here\r\n\r\n", b"GET nope HTTP/1.1\r\n\r\n",
               b"GET / HTTP/1.1\r\nX: " + b"a" * 20000 + b"\r\n\r\n", b"half a request"]
    for g in garbage:
        answer = http(page.port, g)
        assert answer == b"" or answer.startswith(b"HTTP/1.1 400"), answer[:80]
    silent = socket.create_connection(("127.0.0.1", page.port))  # says nothing at all
    silent.settimeout(5)
    assert silent.recv(100).startswith(b"HTTP/1.1 400")  # after HEADER_TIMEOUT_S
    silent.close()
    assert get(page.port, "/nope")[0] == 404
    assert get(page.port, "/")[0] == 200  # still serving
    time.sleep(2 * live_web.TICK_S)
    assert page.snapshot["bad_requests"] == len(garbage) + 1


def test_fifty_streams_all_updated_and_the_excess_refused(page):
    streams = [EventStream(page.port) for _ in range(50)]
    try:
        assert all(s.next()["hello"] for s in streams)
        feed(page, 1, 0.0)
        for s in streams:  # every one gets the next snapshot
            m = s.next()
            while "status" not in m:
                m = s.next()
            assert m["status"]["t_s"] == 0.0 and m["status"]["nan"] is None
        extra = [socket.create_connection(("127.0.0.1", page.port))
                 for _ in range(live_web.MAX_CONNECTIONS)]
        time.sleep(0.5)
        refused = 0
        for s in extra:
            s.settimeout(0.2)
            try:
                refused += s.recv(100).startswith(b"HTTP/1.1 503")
            except TimeoutError:
                pass
            s.close()
        assert refused == 50
        time.sleep(2 * live_web.TICK_S)
        assert page.snapshot["refused"] == 50
    finally:
        for s in streams:
            s.close()


def test_a_client_that_never_reads_loses_only_its_own_events(page):
    # its queue fills and drops (counted); a reading client beside it misses nothing
    stalled = stalled_stream(page.port)
    reader = EventStream(page.port)
    n = 40
    got = []

    def read() -> None:
        while len(got) < n:
            m = reader.next()
            if "status" in m and not m.get("hello"):
                got.append(m["status"]["t_s"])

    thread = threading.Thread(target=read, daemon=True)
    thread.start()
    try:
        feed(page, n, live_web.TICK_S * 1.2, pad=60_000)  # ~60 kB per event
        thread.join(10)
        assert got == [float(i) for i in range(n)]
        time.sleep(2 * live_web.TICK_S)
        snap = page.snapshot
        assert snap["dropped_for_clients"] >= n - live_web.CLIENT_QUEUE - 10
        drops = sorted(c["dropped"] for c in snap["streams_now"])
        assert drops == [0, snap["dropped_for_clients"]]  # the reader, the stalled client
    finally:
        stalled.close()
        reader.close()


def test_outbox_is_bounded_and_counts_what_it_drops():
    box = Outbox(3)
    for i in range(5):
        box.put(i)
    assert box.drain() == [2, 3, 4] and box.dropped == 2 and box.put_count == 5
    assert box.drain() == []


def test_tee_records_first_then_hands_over():
    order = []

    class Rec:
        failed = "x"

        def decoded(self, *a):
            order.append("rec")

        def json(self, *a):
            order.append("rec")

    box = Outbox(10)
    tee = RecorderTee(Rec(), [box], [box])
    tee.decoded("/a/b", None, 1, 1, b"")
    assert order == ["rec"] and box.drain() == [("decoded", "/a/b", 1, None, b"")]
    tee.json("/host/pose", 2, {"t_s": 1.0})
    assert box.drain() == [("json", "/host/pose", 2, None, {"t_s": 1.0})]
    assert tee.failed == "x"


def test_plot_values_flatten_vectors_and_drop_non_finite():
    pose = {"t_s": 1.0, "pos_tracker_m": [0.1, 0.2, float("nan")], "pos_sigma_m": [1, 2, 3],
            "valid": True, "accepted": 4}
    assert plot_values("/host/pose", pose) == {
        "pos_tracker_m[0]": 0.1, "pos_tracker_m[1]": 0.2, "pos_tracker_m[2]": None,
        "pos_sigma_m[0]": 1.0, "pos_sigma_m[1]": 2.0, "pos_sigma_m[2]": 3.0}
    assert plot_values("/host/new_thing", {"t_s": 0, "ok": True, "x": 2.5, "name": "a"}) == {
        "x": 2.5}


def test_every_estimate_channel_is_plotted_thinned(page):
    # A_ω (--net) and any later /host channel reach the page without a page change
    es = EventStream(page.port)
    try:
        assert es.next()["hello"]
        for i in range(100):  # 1 s of 100 Hz samples
            page.outbox.put(("json", "/host/airwake_intensity", i, None,
                             {"t_s": 10 + i / 100, "a_omega": 0.5, "omega_s": 0.1,
                              "resid_norm": 0.2, "valid": True}))
            page.outbox.put(("json", "/host/future", i, None, {"t_s": 10 + i / 100,
                                                                "wind_ned_m_s": [1, 2, 3]}))
            page.outbox.put(("json", "/host/wind", i, None, {
                "t_s": 10 + i / 100, "wind_vx_m_s": 1.0, "wind_vy_m_s": 2.0,
                "wind_vz_m_s": 3.0, "wind_wx_rad_s": 0.1, "valid": True}))
        got: dict = {}
        end = time.monotonic() + 5
        while time.monotonic() < end and min(
                len(got.get(c, {}).get("t", [])) for c in ("/host/future", "/host/wind")) < 20:
            for topic, cols in es.next().get("points", {}).items():
                got.setdefault(topic, {"t": []})["t"] += cols["t"]
                got[topic].update({k: v for k, v in cols["f"].items()})
        a = got["/host/airwake_intensity"]
        assert 18 <= len(a["t"]) <= 21  # 20 Hz of the 100 Hz samples
        assert set(a) == {"t", "a_omega", "omega_s", "resid_norm"}
        assert {"wind_ned_m_s[0]", "wind_ned_m_s[2]"} <= set(got["/host/future"])
        # the live wind (--wind-net): its mean flow
        assert set(got["/host/wind"]) == {"t", "wind_vx_m_s", "wind_vy_m_s", "wind_vz_m_s"}
    finally:
        es.close()


def test_page_draws_a_omega_along_the_track_in_the_ship_frame(page):
    # the operator sees where on the ship's wake the intensity rises (headless Chromium)
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from browser import Browser

    with Browser() as b:
        b.get(f"http://127.0.0.1:{page.port}/")
        page.outbox.put(("json", "/daemon/status", 0, None, status(1.0)))
        for i in range(200):  # a 2 s pass across the deck, A_ω rising to starboard
            y = -5.0 + 0.05 * i
            page.outbox.put(("json", "/host/airwake_intensity", i, None,
                             {"t_s": 1 + i / 100, "a_omega": 0.01 * (y + 5.0),
                              "valid": True, "ship_x_m": -12.0, "ship_y_m": y}))
        end = time.monotonic() + 10
        n = None
        while time.monotonic() < end:
            n = b.run("var e = document.querySelector('[data-plot=\"track\"]');"
                      "return e ? Number(e.getAttribute('data-points')) : null;")
            if n and n >= 30:
                break
            time.sleep(0.1)
        assert n is not None and n >= 30, n  # the 20 Hz thinned points of the pass
        legend = b.run("return document.querySelector('[data-plot=\"track\"] .legend')"
                       ".textContent")
        assert legend.startswith("A_ω 0") and "points" in legend
