"""`airwake bench` section "daemon": CPU and memory of the real daemon at full rates.

Four fake boards (`daemon.fake_boards`: LOSA peaks 320 Hz + IMU, marker attitude + IMU
120 Hz + anemometer, rover INS / rotor 150 Hz + RTK 10 Hz + tail, base INS 150 Hz +
pilot inputs; ~1,500 frames/s, ~85 kB/s over three ptys) run in one process, the daemon
(`airwake daemon`, recording, marker loop and live tracker on) in another. The daemon's CPU time
(utime + stime from /proc) and RSS are sampled once a second:

- `daemon_cpu_fraction`: CPU seconds per wall second over the run after a 5 s warm-up;
- `daemon_rss_growth_mb_per_h`: least-squares slope of RSS over the samples after 60 s
  (allocator and caches warm: RSS rises ~70 MB in the first seconds, then < 0.5 MB
  in the next minute), times 3600 — an extrapolation from a 4 min run (quick: 20 s,
  slope after 10 s, dominated by warm-up);
  segments rotate every 30 s during the run so the writer's per-segment index is
  exercised (it is freed at each rotation);
- `daemon_frames_per_s`, `daemon_cpu_us_per_frame`, `daemon_rss_end_mb` (RSS at the end of
  the run) for context.

The first minute (`measure_startup`, issue 22): the fake boards already streaming, the
daemon launched as a user would (the `airwake` console script), polled every 10 ms:

- `daemon_startup_s`: launch -> the first board frame on disk (a decoded `/<board>/...`
  message readable in the recording's first segment; the recorder flushes every 0.1 s),
  median of 3 (target < 2 s);
- `daemon_rss_mb`: RSS 5 s after that first frame, recording, marker loop and live tracker
  on, no nets (target < 300 MB);
- `daemon_startup_with_nets_s`, `daemon_rss_with_nets_mb`: the same with `--net` and
  `--wind-net` (small nets trained here on 20 s truth-world flights: the figure is torch's
  import and the nets' set-up, not their size).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

SECTION = "daemon"
_TICK = os.sysconf("SC_CLK_TCK")


def _cpu_s(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / _TICK  # utime, stime


def _rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return float("nan")


def measure(duration_s: float, warmup_s: float = 5.0, rss_after_s: float = 60.0,
            poll_ms: float = 5.0, track: bool = True, net: str | None = None,
            daemon_args: tuple[str, ...] = (), attach=None) -> dict:
    """`daemon_args` are added to the daemon's command line; `attach()`, called once the
    four boards are seen (before the warm-up), connects clients (e.g. to --live and
    --foxglove) and returns the function that disconnects them."""
    with tempfile.TemporaryDirectory(prefix="airwake-bench-") as tmp:
        run = Path(tmp)
        boards = subprocess.Popen([sys.executable, "-m", "airwake.daemon.fake_boards", str(run),
                                   str(duration_s + warmup_s + 15)],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            end = time.monotonic() + 10
            while not all((run / r).exists() for r in ("losa", "marker", "base")):
                if time.monotonic() > end:
                    raise RuntimeError("fake boards did not start")
                time.sleep(0.05)
            status = run / "status.json"
            cmd = [sys.executable, "-m", "airwake.cli", "daemon", "--out", str(run / "rec"),
                   "--quiet", "--status-json", str(status), "--segment-s", "30",
                   "--poll-ms", str(poll_ms),
                   "--duration", str(duration_s + warmup_s + 5)] + ([] if track else ["--no-track"])
            if net is not None:  # a rate net: live A_ω on the rover INS (docs/networks.md)
                cmd += ["--net", str(net)]
            cmd += list(daemon_args)
            for role in ("losa", "marker", "base"):
                cmd += ["--port", f"{role}={run / role}"]
            daemon = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            detach = None
            try:
                end = time.monotonic() + 30
                while True:
                    try:
                        st = json.loads(status.read_text())
                        if len(st["boards"]) == 4:
                            break
                    except (OSError, ValueError, KeyError):
                        pass
                    if time.monotonic() > end or daemon.poll() is not None:
                        raise RuntimeError("daemon did not see the four boards: "
                                           + daemon.stderr.read().decode()[-500:]
                                           if daemon.poll() is not None else "timeout")
                    time.sleep(0.1)
                if attach is not None:
                    detach = attach()
                time.sleep(warmup_s)
                pid = daemon.pid
                t0, c0 = time.monotonic(), _cpu_s(pid)
                frames0 = sum(p["frames"] for p in json.loads(status.read_text())
                              ["ports"].values())
                samples = []
                while time.monotonic() - t0 < duration_s:
                    time.sleep(1.0)
                    samples.append((time.monotonic() - t0, _rss_mb(pid)))
                t1, c1 = time.monotonic(), _cpu_s(pid)
                frames1 = sum(p["frames"] for p in json.loads(status.read_text())
                              ["ports"].values())
            finally:
                if detach is not None:
                    detach()
                daemon.terminate()
                daemon.wait(30)
        finally:
            boards.terminate()
            boards.wait(30)
    wall = t1 - t0
    s = np.array(samples)
    late = s[s[:, 0] >= min(rss_after_s, duration_s / 2)]
    slope = float(np.polyfit(late[:, 0], late[:, 1], 1)[0]) if len(late) >= 3 else float("nan")
    frames = frames1 - frames0
    return {
        "daemon_cpu_fraction": round((c1 - c0) / wall, 4),
        "daemon_rss_growth_mb_per_h": round(slope * 3600.0, 2),
        "daemon_rss_end_mb": round(float(s[-1, 1]), 1),
        "daemon_frames_per_s": round(frames / wall, 1),
        "daemon_cpu_us_per_frame": round((c1 - c0) / max(frames, 1) * 1e6, 2),
        "daemon_bench_seconds": round(wall, 1),
    }


def _first_board_frame(segment: Path) -> bool:
    """A decoded board frame (not raw bytes, not the daemon's own channels) is on disk."""
    from airwake.record.reader import _stream_records

    if not segment.exists():
        return False
    channels = {}
    for rec in _stream_records(segment):
        kind = type(rec).__name__
        if kind == "Channel":
            channels[rec.id] = rec.topic
        elif kind == "Message" and not channels.get(rec.channel_id, "/raw").startswith(
                ("/raw", "/daemon", "/host")):
            return True
    return False


def _daemon_command() -> list[str]:
    script = Path(sys.executable).with_name("airwake")
    return [str(script)] if script.exists() else [sys.executable, "-m", "airwake.cli"]


def measure_startup(nets: tuple[str, ...] = (), repeats: int = 3, settle_s: float = 5.0,
                    timeout_s: float = 60.0) -> dict:
    """(startup s: median over `repeats` launches, RSS MB `settle_s` after the first frame
    of the last one) of the daemon joining four fake boards that already stream;
    `nets` are extra daemon arguments (`--net`, PATH, ...)."""
    starts, rss = [], float("nan")
    with tempfile.TemporaryDirectory(prefix="airwake-bench-start-") as tmp:
        run = Path(tmp)
        boards = subprocess.Popen([sys.executable, "-m", "airwake.daemon.fake_boards", str(run),
                                   str(repeats * (timeout_s + settle_s + 5))],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            end = time.monotonic() + 10
            while not all((run / r).exists() for r in ("losa", "marker", "base")):
                if time.monotonic() > end:
                    raise RuntimeError("fake boards did not start")
                time.sleep(0.05)
            time.sleep(1.0)  # streaming
            for k in range(repeats):
                rec = run / f"rec{k}"
                cmd = _daemon_command() + ["daemon", "--out", str(rec), "--quiet",
                                           *nets] + [a for role in ("losa", "marker", "base")
                                                     for a in ("--port", f"{role}={run / role}")]
                t0 = time.monotonic()
                daemon = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
                try:
                    while not _first_board_frame(rec / "segment-0000.mcap"):
                        if daemon.poll() is not None or time.monotonic() - t0 > timeout_s:
                            raise RuntimeError("the daemon wrote no board frame: "
                                               + (daemon.stderr.read().decode()[-500:]
                                                  if daemon.poll() is not None else "timeout"))
                        time.sleep(0.01)
                    starts.append(time.monotonic() - t0)
                    if k == repeats - 1:
                        time.sleep(settle_s)
                        rss = _rss_mb(daemon.pid)
                finally:
                    daemon.terminate()
                    daemon.wait(30)
        finally:
            boards.terminate()
            boards.wait(30)
    return {"startup_s": round(float(np.median(starts)), 3), "rss_mb": round(rss, 1)}


def _small_nets(directory: Path) -> tuple[str, ...]:
    """`--net RATES.pt --wind-net WIND.pt`: nets trained on 20 s truth-world flights."""
    from airwake.nets import net_flight_from_df, save_net, train_net
    from airwake.nets.train import AdamWConfig
    from airwake.nets.wind_net import train_wind_net
    from hil_sim.world.run import run_scenario
    from hil_sim.world.scenario import load_scenario

    still = run_scenario(load_scenario("still_air_calibration"), seed=7,
                         duration_s=20.0).flight_table().df
    ship = run_scenario(load_scenario("ship_airwake_b0"), seed=7, duration_s=20.0)
    few = AdamWConfig(max_epochs=5)
    rates = save_net(train_net([net_flight_from_df(still, "bench")], seed=0, adamw=few),
                     directory / "rates.pt")
    wind = save_net(train_wind_net([ship.flight_table().df], seed=0, adamw=few),
                    directory / "wind.pt")
    return ("--net", str(rates), "--wind-net", str(wind))


def first_minute(quick: bool) -> dict:
    """`daemon_startup_s`, `daemon_rss_mb` and the same with both live nets."""
    plain = measure_startup(repeats=1 if quick else 3)
    with tempfile.TemporaryDirectory(prefix="airwake-bench-nets-") as tmp:
        with_nets = measure_startup(_small_nets(Path(tmp)), repeats=1 if quick else 3)
    return {"daemon_startup_s": plain["startup_s"], "daemon_rss_mb": plain["rss_mb"],
            "daemon_startup_with_nets_s": with_nets["startup_s"],
            "daemon_rss_with_nets_mb": with_nets["rss_mb"]}


def run(quick: bool) -> dict:
    out = first_minute(quick)
    out.update(measure(20.0, rss_after_s=10.0) if quick else measure(240.0))
    return out
