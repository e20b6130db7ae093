"""What the live outputs cost the daemon: `daemon_cpu_fraction` (the bench of
docs/daemon.md: four fake boards at full rates) without them, then with the page open in
headless Chromium and a Foxglove client subscribed to every channel. Target < 0.25 of one
core, measured (not asserted: a timed figure on a shared machine) by
`python tests/daemon/test_live_cpu.py [SECONDS] [PAIRS]`, which prints alternating pairs."""

from __future__ import annotations

import json
import sys
import threading
import time
from pathlib import Path

import pytest
from airwake.daemon.bench import measure

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run as a script too
from browser import Browser  # noqa: E402
from live_clients import FoxgloveClient, free_port  # noqa: E402

MEASURE_S = 30.0


def with_clients(duration_s: float) -> dict:
    """The bench with --live and --foxglove, the page and a Foxglove client attached."""
    live, fox_port = free_port(), free_port()
    seen = {"foxglove_messages": 0}

    def attach():
        browser = Browser()
        browser.get(f"http://127.0.0.1:{live}/")
        fox = FoxgloveClient(fox_port)
        have = fox.wait_channels({"/rover/ins", "/losa/losa_peaks", "/daemon/status"}, 15)
        fox.subscribe({i + 1: c["id"] for i, c in enumerate(have.values())})
        stop = threading.Event()

        def read():
            while not stop.is_set():
                try:
                    if fox.message()[0] == "data":
                        seen["foxglove_messages"] += 1
                except OSError:
                    return

        thread = threading.Thread(target=read, daemon=True)
        thread.start()

        def detach():
            seen["page_updates"] = browser.run("return window.airwake.updates")
            seen["page_boards"] = browser.run(
                "return document.querySelectorAll('[data-board]').length")
            stop.set()
            fox.close()
            browser.close()

        return detach

    out = measure(duration_s, daemon_args=("--live", str(live), "--foxglove", str(fox_port)),
                  attach=attach)
    return {**out, **seen}


@pytest.mark.wall_clock
@pytest.mark.slow
def test_daemon_with_the_page_and_a_foxglove_client_attached_keeps_ingesting():
    # the ship laptop: with the live view and a Foxglove client attached the daemon keeps
    # every board's full rate, both clients get their streams, and the clients' cost stays
    # far from a runaway. The < 0.25 core budget is a figure, not a timed assertion: a
    # single 30 s pair on a shared 2-core machine moves by +-0.05 (0.21 -> 0.27 in one
    # clean-clone run, 0.15 -> 0.18 in others); `python tests/daemon/test_live_cpu.py
    # SECONDS PAIRS` measures alternating pairs, docs/daemon.md has the figures
    before = measure(MEASURE_S)
    after = with_clients(MEASURE_S)
    print("live outputs CPU:", json.dumps({"without": before, "with": after}))
    assert after["page_boards"] == 4 and after["page_updates"] >= 3 * MEASURE_S
    assert after["foxglove_messages"] > 500 * MEASURE_S
    assert after["daemon_frames_per_s"] > 0.9 * before["daemon_frames_per_s"], (before, after)
    # a client loop that spins or copies per frame would cost a core, not hundredths
    assert after["daemon_cpu_fraction"] - before["daemon_cpu_fraction"] < 0.25, (before, after)


if __name__ == "__main__":
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 60.0
    for _ in range(int(sys.argv[2]) if len(sys.argv) > 2 else 2):
        b = measure(seconds)
        a = with_clients(seconds)
        print(json.dumps({"without": b["daemon_cpu_fraction"], "with": a["daemon_cpu_fraction"],
                          "with_frames_per_s": a["daemon_frames_per_s"],
                          "foxglove_messages_per_s": round(a["foxglove_messages"] / seconds),
                          "page_updates_per_s": round(a["page_updates"] / seconds, 2),
                          "load": Path("/proc/loadavg").read_text().split()[:3]}), flush=True)
        time.sleep(1)
