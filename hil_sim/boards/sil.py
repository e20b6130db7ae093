"""A SIL flight: native firmware boards fed by the truth world, ptys, the real daemon.

    run = SilRun(load_scenario("still_air_calibration"), out="REC", duration_s=20)
    result = run.run()                  # start(), step() until the end, finish()
    result.realtime_factor, result.summary["faults"]["links"], result.daemon_status

What happens (docs/sil.md):

1. The truth world flies the scenario (`hil_sim.world.run.run_scenario`); the sensor
   streams it produces and the LOSA optics become sim-channel inputs per board
   (`feeds.BoardFeeds`).
2. Each board of the rig (`rig.SilRig`) is its native executable (`build/native/<board>`)
   in stepped mode, its host port mapped to `sim` so that every byte it sends comes back
   on the channel. The boards facing the host get a pty each (`links.PtyPort`), behind
   `REC/ports/<board>`; the rover's bytes go to the base's `rover` port (the XBee link).
3. The real daemon (`airwake daemon`, a separate process) records REC from those ptys.
   In stepped mode it runs on the simulator's clock (`simclock`): its receive times,
   and so the exported flight table, are on the flight's own timeline.
4. Every step (`rig.step_us`, 9.7 ms) each board runs to the step's end with its inputs
   (marker first: the LOSA lines of the step need the LED the marker lit; the rover and
   the base in sub-steps of the XBee latency), the bytes the boards sent cross their
   link's `links.Impairment` (faults, counted exactly) to the ptys, and the bytes the
   daemon wrote (time sync, marker commands) go back to the boards. Stepped mode runs as
   fast as the machine allows with the daemon in lockstep (`step()`); wall mode paces
   every step to CLOCK_MONOTONIC (and the daemon keeps its own clock).
5. `finish()` lets the daemon read everything, stops it with SIGINT (a clean, indexed
   recording), stops the boards, and writes `REC/sil/run.json`: the rig, the clock
   offset between host and simulator time, what every link injected, the fault events,
   board boots, timing, CPU and the daemon's final link health, and `REC/sil/truth.parquet`:
   the truth world's own flight table (truth_* columns, scenario and seed in its
   metadata) on the simulator's timeline, which `airwake sim truth` puts beside an export
   of the recording for scoring (the analysis never reads it).
"""

from __future__ import annotations

import json
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hil_sim.boards.channel import REPO_ROOT, ChannelError, NativeBoard, executable
from hil_sim.boards.feeds import BoardFeeds
from hil_sim.boards.host import LOST_SETTLE_S, HostDaemon, SilError, cpu_seconds
from hil_sim.boards.links import BASE_FORWARD_MAX, Impairment, PtyPort
from hil_sim.boards.rig import SilRig, rig_for, survey_rig
from hil_sim.boards.simclock import SimClock

MODES = ("stepped", "wall")
TRUTH_TABLE = "truth.parquet"  # REC/sil/: the truth world's table, for scoring only
ORDER = ("marker", "losa", "rover", "base")  # marker first: its LEDs light the LOSA's step
SIL_SEED_KEY = 0x5117  # spawn-key namespace of the SIL layer's random streams
DAEMON_START_TIMEOUT_S = 60.0
UNLOST_SETTLE_S = 2.0  # wall s of an empty queue before bytes count as lost, no port lost
PORT_OPEN_TIMEOUT_S = 30.0
DRAIN_TIMEOUT_S = 10.0
WRITE_STALL_TIMEOUT_S = 20.0
STEPPED_POLL_MS = 0.0


def sil_rngs(seed: int) -> dict[str, np.random.Generator]:
    """The SIL layer's random streams. The LOSA optics and the marker IMU take the
    world's reserved streams (`hil_sim.world.run.RNG_STREAMS`); the rest come from a
    spawn-key namespace of their own, so they never shift the world's."""
    from hil_sim.world.run import RNG_STREAMS

    world = np.random.SeedSequence(seed).spawn(len(RNG_STREAMS))
    names = {"losa": "reserved_losa", "marker": "reserved_marker"}
    out = {k: np.random.default_rng(world[RNG_STREAMS.index(v)]) for k, v in names.items()}
    for i, name in enumerate(("losa_imu", "link_losa", "link_marker", "link_rover",
                              "link_base")):
        out[name] = np.random.default_rng(np.random.SeedSequence(seed,
                                                                 spawn_key=(SIL_SEED_KEY, i)))
    return out


@dataclass
class SilResult:
    """What a finished run reports (also written to `REC/sil/run.json`)."""

    out: Path
    summary: dict
    daemon_status: dict | None
    daemon_exit: int | None

    @property
    def realtime_factor(self) -> float:
        return self.summary["timing"]["realtime_factor"]


@dataclass
class _Outage:
    """A timed link outage: a stall (pty kept) or an unplug (pty destroyed)."""

    kind: str
    board: str
    start_us: int
    end_us: int
    state: str = "pending"  # pending, active, reopening, done
    record: dict = field(default_factory=dict)


class SilRun:
    """One SIL flight (module doc). Drive it with `run()`, or `start()`, `step()` ...
    `finish()` (tests use the steps to act mid-flight, e.g. `kill_daemon()`)."""

    def __init__(self, scenario, *, out, seed: int | None = None,
                 duration_s: float | None = None, mode: str = "stepped",
                 rig: SilRig | None = None, faults=None, flavour: str = "release",
                 log_frames: bool = False, keep_delivered: bool = False,
                 progress=None, world_progress=None, survey=None, live: str | None = None,
                 foxglove: str | None = None, net=None, wind_net=None) -> None:
        if mode not in MODES:
            raise SilError(f"mode {mode!r}: expected one of {', '.join(MODES)}")
        self.scenario = scenario
        self.seed = scenario.seed if seed is None else int(seed)
        self.survey = survey  # a SurveyConfig: the marker carried with an anemometer
        self.live = live  # the daemon's --live [HOST:]PORT (its page; docs/daemon.md)
        self.foxglove = foxglove  # the daemon's --foxglove [HOST:]PORT
        # the daemon's live nets (--net, --wind-net): absolute, the daemon runs elsewhere
        self.nets = {flag: Path(path).resolve() for flag, path in
                     (("--net", net), ("--wind-net", wind_net)) if path is not None}
        for flag, path in self.nets.items():
            if not path.is_file():
                raise SilError(f"{flag} {path}: no such network file")
        self.live_urls: list[str] = []  # where they listen, from the daemon's log
        if survey is not None:
            from hil_sim.world.anemometer_survey import survey_duration_s

            full = survey_duration_s(survey)
            self.duration_s = full if duration_s is None else min(float(duration_s), full)
        else:
            self.duration_s = scenario.duration_s if duration_s is None else float(duration_s)
        if not self.duration_s > 0:
            raise SilError(f"duration {self.duration_s!r}: must be > 0")
        self.out = Path(out).resolve()  # the daemon runs from the repository root
        self.mode = mode
        if rig is None:
            rig = survey_rig(survey) if survey is not None else rig_for(scenario)
        self.rig = rig
        self.faults = scenario.faults if faults is None else faults
        self.flavour = flavour
        self.log_frames = log_frames
        self.keep_delivered = keep_delivered
        self.progress = progress
        self.world_progress = world_progress
        self.t_us = 0
        self.end_us = int(round(self.duration_s * 1e6))
        self.boards: dict[str, NativeBoard] = {}
        self.ptys: dict[str, PtyPort] = {}
        self.links: dict[str, Impairment] = {}
        self.daemon: HostDaemon | None = None
        self.clock: SimClock | None = None
        self.host_offset_ns = 0  # stepped: host time = host_offset_ns + simulator time
        self.events: list[dict] = []
        self.boots: list[dict] = []
        self.host_rx: dict[str, bytearray] = defaultdict(bytearray)  # daemon -> board
        self.host_rx_cut = defaultdict(int)
        # bytes the daemon read mid-flight from other than its ports (a module imported
        # in mid-pass): the lockstep re-bases its byte count on them (run.json "lockstep")
        self.other_reads = {"bytes": 0, "times": 0}
        self.rover_rx: list[tuple[int, bytes]] = []  # base -> rover (host bytes relayed)
        self.base_rover_rx: list[tuple[int, bytes]] = []  # rover -> base
        self.timing: dict[str, float] = {}
        self._tmp: Path | None = None
        self._started = False
        self._finished = False
        self._wall0 = 0.0
        self._cpu_self0 = 0.0
        self._cpu_daemon0 = 0.0
        self._rchar0 = 0
        self._ports_seen: tuple = ()  # (plugged, replugs) per port at the last lockstep wait
        self._cpu_boards0: dict[str, float] = {}
        self.daemon_cpu_s: float | None = None

    # -- set-up ----------------------------------------------------------------------

    def start(self) -> None:
        """Fly the truth world, start the boards and the daemon, open the ptys."""
        if self.out.exists() and (not self.out.is_dir() or any(self.out.iterdir())):
            raise SilError(f"--out {self.out}: exists and is not an empty directory; "
                           "choose a new recording directory")
        t0 = time.perf_counter()
        self._outages = self._schedule()  # validates the fault events first
        self._executables()
        from hil_sim.world.run import build_config, run_scenario

        if self.survey is not None:
            from hil_sim.world.anemometer_survey import SurveyWorld

            self.world = SurveyWorld(self.survey, seed=self.seed, scenario=self.scenario,
                                     duration_s=self.duration_s)
            world_config = self.world.build_config()
        else:
            self.world = run_scenario(self.scenario, seed=self.seed,
                                      duration_s=self.duration_s,
                                      progress=self.world_progress)
            world_config = build_config(self.world)
        self.timing["world_s"] = time.perf_counter() - t0
        self.rngs = sil_rngs(self.seed)
        self.feeds = BoardFeeds.build(self.world, self.rig, self.rngs)
        self._build_links()
        self._resets = sorted((int(round(e.at_s * 1e6)), e.board) for e in self.faults.resets
                              if e.board in self.rig.boards)
        self._tmp = Path(tempfile.mkdtemp(prefix="airwake-sil-"))
        try:
            self._start_boards()
            self._start_daemon(world_config)
            self._open_ports()
        except BaseException:
            self._abort()
            raise
        self.timing["setup_s"] = time.perf_counter() - t0
        self._started = True
        if self.clock is not None:
            self.host_offset_ns = self.clock.hold()
        else:
            self.host_offset_ns = time.monotonic_ns()
        self._wall0 = time.monotonic()
        self._cpu_self0 = time.process_time()
        self._cpu_daemon0 = self.daemon.cpu_s() or 0.0
        self._rchar0 = (self.daemon.read_chars() or 0) - sum(p.bytes_written
                                                             for p in self.ptys.values())
        self._ports_seen = tuple((p.plugged, p.replugs) for p in self.ptys.values())
        self._cpu_boards0 = {n: cpu_seconds(b.process.pid) or 0.0
                             for n, b in self.boards.items()}

    def _executables(self) -> None:
        missing = []
        for b in self.rig.boards:
            try:
                executable(b, self.flavour)
            except (subprocess.CalledProcessError, OSError) as exc:
                missing.append(f"{b} ({exc})")
        if missing:
            raise SilError("the native board executables could not be built: "
                           f"{'; '.join(missing)}; run `make native` and retry")

    def _build_links(self) -> None:
        boards = self.rig.boards
        for b in boards:
            lf = self.faults.link(b)
            chained = b == "rover" and "base" in boards
            self.links[b] = Impairment(
                b, loss_probability=lf.byte_loss_probability,
                flip_probability=lf.bit_flip_probability, rng=self.rngs[f"link_{b}"],
                piece_max=BASE_FORWARD_MAX if chained else None, log_frames=self.log_frames)
        if "rover" in self.links and "base" in self.links:
            self.links["base"].upstream_bad = self.links["rover"].bad_out
            self.links["rover"].publish_valid.append(self.links["base"].valid)

    def _schedule(self) -> list[_Outage]:
        out = []
        for kind, items in (("stall", self.faults.stalls), ("unplug", self.faults.unplugs)):
            for e in items:
                if e.board not in self.rig.boards:
                    raise SilError(f"faults.{kind}s: board {e.board!r} is not in this run "
                                   f"(boards: {', '.join(self.rig.boards)})")
                start = int(round(e.at_s * 1e6))
                out.append(_Outage(kind, e.board, start, start + int(round(e.duration_s * 1e6))))
        for e in self.faults.resets:
            if e.board not in self.rig.boards:
                raise SilError(f"faults.resets: board {e.board!r} is not in this run "
                               f"(boards: {', '.join(self.rig.boards)})")
        return sorted(out, key=lambda o: o.start_us)

    def _ports(self, board: str) -> dict[str, str]:
        rig = self.rig
        throttle = self.faults.link(board).throttle_baud
        host = int(throttle) if throttle else rig.host_baud[board]
        ports = {"host": f"sim@{host}"}
        sensors = self.scenario.sensors
        if board == "rover":
            ports["ins"] = f"sim@{sensors.vn200.baud}"
            ports["rtk"] = f"sim@{sensors.rtk.baud}"
        elif board == "base":
            ports["ins"] = f"sim@{sensors.base_vn200.baud}"
            if "rover" in rig.boards:
                ports["rover"] = f"sim@{rig.rover_link_baud}"
        elif board == "marker" and "marker/anemometer" in self.world.streams():
            ports["anemo"] = f"sim@{self.world.streams()['marker/anemometer'].baud}"
        return ports

    def _start_boards(self) -> None:
        rig = self.rig
        for b in rig.boards:
            try:
                self.boards[b] = NativeBoard(
                    b, ports=self._ports(b), mode="stepped", flavour=self.flavour,
                    clock_drift_ppm=rig.clock_drift_ppm.get(b, 0.0),
                    clock_offset_us=rig.clock_offset_us.get(b, 0))
            except ChannelError as exc:
                raise SilError(f"board {b} did not start: {exc}") from None

    def daemon_command(self, build_config) -> list[str]:
        """The daemon's command line (ports, geometry for the export, metadata)."""
        rig = self.rig
        if self.mode == "stepped":
            head = [sys.executable, "-m", "hil_sim.boards.simclock", "--clock",
                    str(self._tmp / "clock"), "--"]
        else:
            head = [sys.executable, "-m", "airwake.cli"]
        cmd = head + ["daemon", "--out", str(self.out), "--status-json",
                      str(self._tmp / "status.json"), "--quiet"]
        if self.mode == "stepped" and {"marker", "losa"} <= set(rig.boards):
            cmd += ["--track"]
        if self.mode == "stepped":
            # the daemon sleeps the rest of its poll period while the clock stands still
            # (the simulator waits for it to read a step): a short period keeps that wait
            # short; when the simulator runs ahead, the daemon does not sleep at all
            cmd += ["--poll-ms", str(STEPPED_POLL_MS)]
        for b in rig.host_boards:
            cmd += ["--port", f"{b}={self.out / 'ports' / b}@{rig.host_baud[b]}"]
        origin = build_config.ned_origin_lla
        if origin is not None:
            cmd += ["--ned-origin", ",".join(repr(float(v)) for v in origin)]
        if "rover" in rig.boards and self.scenario.rtk_enabled:
            cmd += ["--rover-antenna-to-hub-m",
                    ",".join(repr(float(v)) for v in build_config.rover_antenna_to_hub_frd_m),
                    "--base-antenna-height-m",
                    repr(float(build_config.base_antenna_height_above_deck_m))]
            if build_config.base_antenna_ship_xy_m is not None:
                cmd += ["--base-antenna-ship-m",
                        ",".join(repr(float(v)) for v in build_config.base_antenna_ship_xy_m)]
        if "losa" in rig.boards:
            # the marker -> hub lever arm (body axes): the hub from the rover antenna's
            hub = (np.asarray(build_config.rover_antenna_to_hub_frd_m, float)
                   + np.asarray(self.scenario.sensors.rover_antenna_m, float))
            to_hub = hub - np.asarray(rig.marker_position_body_m, float)
            # "=" form: a value starting with "-" would read as an option
            cmd += ["--marker-to-hub-m=" + ",".join(repr(float(v)) for v in to_hub)]
            cmd += ["--tracker-height-m", repr(rig.tracker_height_m), "--tracker-position-m="
                    + ",".join(repr(float(v)) for v in rig.tracker_position_ned_m),
                    "--tracker-heading-deg", repr(float(rig.tracker_heading_deg)),
                    "--tracker-tilt-deg", repr(float(rig.tracker_tilt_deg))]
        cmd += ["--meta", f"sil_scenario={self.scenario.name}", "--meta", f"sil_seed={self.seed}",
                "--meta", f"sil_mode={self.mode}"]
        if self.live is not None:
            cmd += ["--live", self.live]
        if self.foxglove is not None:
            cmd += ["--foxglove", self.foxglove]
        for flag, path in self.nets.items():
            cmd += [flag, str(path)]
        return cmd

    def _start_daemon(self, build_config) -> None:
        if self.mode == "stepped":
            self.clock = SimClock(self._tmp / "clock")
        self.daemon = HostDaemon(self.daemon_command(build_config), self._tmp / "daemon.log",
                                 REPO_ROOT, WRITE_STALL_TIMEOUT_S)
        segment = self.out / "segment-0000.mcap"
        self.daemon.wait_for(segment.exists, DAEMON_START_TIMEOUT_S,
                             f"starting (creating {self.out})")
        if self.live is not None or self.foxglove is not None:
            # the daemon printed where its live outputs listen before it created REC
            self.live_urls = [line.split(": ", 1)[1] for line in
                              self.daemon.log_path.read_text(errors="replace").splitlines()
                              if line.startswith(("airwake daemon: live page:",
                                                  "airwake daemon: foxglove:"))]
            for line in self.live_urls:
                print(f"sil: daemon {line}", file=sys.stderr, flush=True)

    def _open_ports(self) -> None:
        """One pty per host-facing board; wait until the daemon has opened each (it
        writes a time-sync request as soon as it opens a port)."""
        (self.out / "ports").mkdir()
        for b in self.rig.host_boards:
            self.ptys[b] = PtyPort(self.out / "ports" / b)
            if self.keep_delivered:
                self.ptys[b].keep = bytearray()
        waiting = set(self.ptys)

        def opened() -> bool:
            for b in list(waiting):
                data = self.ptys[b].receive()
                if data:
                    self.host_rx[b] += data
                    waiting.discard(b)
            return not waiting

        self.daemon.wait_for(opened, PORT_OPEN_TIMEOUT_S,
                             f"opening the ports {', '.join(self.rig.host_boards)}")

    # -- the loop --------------------------------------------------------------------

    @property
    def done(self) -> bool:
        return self.t_us >= self.end_us

    def run(self) -> SilResult:
        try:
            if not self._started:
                self.start()
            while not self.done:
                self.step()
            return self.finish()
        except BaseException:
            self._abort()
            raise

    def step(self) -> None:
        """Advance every board by one step and relay what crossed the links.

        Stepped mode runs the daemon in lockstep: the bytes of step k are written when
        the host clock reads the end of step k, and step k+1 begins only once the daemon
        has read them and finished its pass (it sleeps again) — so the clock it stamped
        them with is exactly the end of step k, and whatever it wrote in reply (time
        sync, marker commands, stamped with that same clock) reaches the boards at that
        instant. Frames reach the host 0-9.7 ms after they were sent, host bytes reach the
        boards with no delay, whatever the machine's load; and a run is reproducible."""
        t0 = self.t_us
        # a step ends early at a timed outage's start or end, so that it acts at its time
        edges = [t for o in self._outages for t in (o.start_us, o.end_us) if t > t0]
        t1 = min(t0 + self.rig.step_us, self.end_us, *edges)
        if self.clock is not None:
            # while the daemon reads the last step: what needs none of its replies
            self.feeds.prefetch(t1)
            self._wait_host_idle()
        self._collect_host_bytes(t0)
        self._outage_transitions(t0)
        xbee = "rover" in self.boards and "base" in self.boards
        # boards whose step needs nothing from another board's same step run together (one
        # step in flight each): the LOSA beside the rover and the base; the marker first,
        # its LEDs light the LOSA's step
        losa = None
        for name in ORDER:
            if name not in self.boards or (xbee and name in ("rover", "base")):
                continue
            if name == "losa" and xbee:
                losa = self._advance_begin(name, t0, t1)
            else:
                self._advance(name, t0, t1)
        if xbee:
            # the rover and the base talk over the XBee: sub-steps of its latency, so a
            # byte either way arrives exactly `xbee_latency_us` after it was sent — after
            # the sub-step, so the two boards' sub-steps are independent and run together
            sub = max(1, min(self.rig.xbee_latency_us, t1 - t0))
            for s0 in range(t0, t1, sub):
                s1 = min(s0 + sub, t1)
                rover = self._advance_begin("rover", s0, s1)
                base = self._advance_begin("base", s0, s1)
                self._advance_end("rover", rover)
                self._advance_end("base", base)
        if losa is not None:
            self._advance_end("losa", losa)
        self.t_us = t1
        if self.clock is not None:
            self.clock.set(self.host_offset_ns + t1 * 1000)
        else:
            lag = self._wall0 + t1 / 1e6 - time.monotonic()
            if lag > 0:
                time.sleep(lag)
        self._deliver()
        if self.progress is not None:
            self.progress.update(t1 / 1e6)

    def _wait_host_idle(self) -> None:
        """The daemon has read everything written so far (`HostDaemon.wait_read`) and is
        asleep again (`wait_idle`): its pass over those bytes, with any replies, is
        complete."""
        if self.daemon.killed:
            return
        t_start = time.monotonic()
        target = self._rchar0 + sum(p.bytes_written for p in self.ptys.values())
        plugged = [p for p in self.ptys.values() if p.plugged]
        # bytes can be lost only where a port was lost since the last wait: elsewhere an
        # empty queue is bytes on their way (seconds of slack on a loaded machine, not 50 ms)
        ports = tuple((p.plugged, p.replugs) for p in self.ptys.values())
        lost = ports != self._ports_seen
        self._ports_seen = ports
        # bytes a lost port discarded are never read: re-base on the shortfall
        self._rchar0 -= self.daemon.wait_read(
            target, lambda: not any(p.unread() for p in plugged),
            LOST_SETTLE_S if lost else UNLOST_SETTLE_S)
        self.daemon.wait_idle()
        # more read than the ports were given: the daemon read something else in this pass
        # (a lazy import: numpy's np.ma on the first np.median was 413 kB). Unaccounted, the
        # byte count would be met early at every later step and the lockstep would rest on
        # `wait_idle` alone, which a pty's asynchronous delivery races. Re-based on what the
        # ports still hold unread, and counted.
        got = self.daemon.read_chars()
        if got is not None and got > target:
            extra = got - target + sum(p.unread() for p in plugged)
            self._rchar0 += extra
            self.other_reads["bytes"] += extra
            self.other_reads["times"] += 1
        self.timing["host_wait_s"] = self.timing.get("host_wait_s", 0.0) + (
            time.monotonic() - t_start)

    def _advance(self, name: str, t0: int, t1: int) -> None:
        """One board from t0 to t1 with its inputs; its outputs onto the links."""
        self._advance_end(name, self._advance_begin(name, t0, t1))

    def _advance_begin(self, name: str, t0: int, t1: int):
        """The board's inputs for [t0, t1) out and its step started (`NativeBoard.
        advance_begin`); `_advance_end` takes its outputs."""
        board = self.boards[name]
        self.feeds.queue(name, board, t0, t1)
        for t_reset, b in self._resets:
            if b == name and t0 <= t_reset < t1:
                board.reset(t_reset)
                self.events.append({"kind": "reset", "board": b, "at_s": t_reset / 1e6})
        self._host_input(name, board, t0, t1)
        return board.advance_begin(t1)

    def _advance_end(self, name: str, pending) -> None:
        res = self.boards[name].advance_end(pending)
        if name == "marker" and self.feeds.losa_lines is not None:
            self.feeds.losa_lines.led_events(res.pwm)
        self._board_output(name, res)

    def _host_input(self, name: str, board: NativeBoard, t0: int, t1: int) -> None:
        """Bytes for the board's host port (daemon via pty; the rover via the base) and
        the base's rover port (the rover's bytes)."""
        if name == "rover" and "base" in self.boards:
            keep = []
            for t, data in self.rover_rx:
                if t < t1:
                    board.uart(t, "host", data)
                else:
                    keep.append((t, data))
            self.rover_rx = keep
        elif self.host_rx.get(name):
            board.uart(t0, "host", bytes(self.host_rx[name]))
            self.host_rx[name].clear()
        if name == "base":
            keep = []
            for t, data in self.base_rover_rx:
                if t < t1:
                    board.uart(t, "rover", data)
                else:
                    keep.append((t, data))
            self.base_rover_rx = keep

    def _board_output(self, name: str, res) -> None:
        for t, cause, count in res.boots:
            self.boots.append({"board": name, "t_s": t / 1e6, "cause": cause,
                               "boot_count": count})
        boots = sorted(t for t, cause, _ in res.boots if cause != "power_on" or t > 0)
        link = self.links[name]
        latency = self.rig.xbee_latency_us
        # bytes for a pty leave at the step's end anyway: one chunk per port between
        # reboots (the link sees the same byte stream in far fewer calls); bytes for the
        # XBee link keep their times
        merge = name in self.ptys
        for t, port, data in _coalesce(res.uart_records, boots, link.cut_open_segment, merge):
            if port == "host":
                out = link.feed(data, t, self._outage(name, t))
                if not out:
                    continue
                if name == "rover" and "base" in self.boards:
                    self.base_rover_rx.append((t + latency, out))
                elif name in self.ptys and not self.daemon.killed:
                    self.ptys[name].send(out)
            elif port == "rover" and name == "base":
                if not self._outage("rover", t):
                    self.rover_rx.append((t + latency, data))

    def _outage(self, board: str, t_us: int) -> bool:
        for o in self._outages:
            if o.board == board and o.state in ("active", "reopening"):
                return True
        return False

    def _outage_transitions(self, t0: int) -> None:
        """Start and end stalls and unplugs at step boundaries."""
        for o in self._outages:
            if o.state == "pending" and t0 >= o.start_us:
                o.state = "active"
                o.record = {"kind": o.kind, "board": o.board, "at_s": t0 / 1e6,
                            "planned_s": (o.end_us - o.start_us) / 1e6}
                pty = self.ptys.get(o.board)
                if o.kind == "unplug" and pty is not None:
                    self._drain([pty])
                    o.record["undelivered_bytes"] = pty.unread()
                    pty.unplug()
                self.events.append(o.record)
            elif o.state == "active" and t0 >= o.end_us:
                o.record["end_s"] = t0 / 1e6
                pty = self.ptys.get(o.board)
                if o.kind == "unplug" and pty is not None:
                    pty.replug()
                    o.state = "reopening"  # until the daemon has the new pty open
                else:
                    o.state = "done"

    def _deliver(self) -> None:
        """Write the step's bytes to the ptys; wait (wall time) while the daemon is
        behind rather than drop anything."""
        if self.daemon.killed:
            for p in self.ptys.values():
                p.pending.clear()
            return
        pending = [p for p in self.ptys.values() if p.flush()]
        end = time.monotonic() + WRITE_STALL_TIMEOUT_S
        while pending:
            self.daemon.check("recording")
            for p in pending:
                p.wait_writable(0.01)
            pending = [p for p in pending if p.flush()]
            if time.monotonic() > end:
                raise SilError(f"the daemon has not read its ports for {WRITE_STALL_TIMEOUT_S}"
                               f" s: {self.daemon.tail()}")

    def _collect_host_bytes(self, t_us: int) -> None:
        """What the daemon wrote (stamped with the host clock now at t_us): delivered to
        the boards at the start of the coming step."""
        for b, pty in self.ptys.items():
            data = pty.receive()
            if not data:
                continue
            for o in self._outages:
                if o.board == b and o.state == "reopening":
                    # the daemon opened the new pty (its first write): deliver from now on
                    o.state = "done"
                    o.record["reopened_s"] = t_us / 1e6
            if self._outage(b, t_us):
                self.host_rx_cut[b] += len(data)
            else:
                self.host_rx[b] += data

    def _drain(self, ptys, timeout_s: float = DRAIN_TIMEOUT_S) -> bool:
        """Wait (wall time) until the daemon has read everything written to `ptys`."""
        if self.daemon is None or self.daemon.killed:
            return False
        end = time.monotonic() + timeout_s
        while any(p.unread() or p.pending for p in ptys):
            for p in ptys:
                p.flush()
            if not self.daemon.alive or time.monotonic() > end:
                return False
            time.sleep(0.002)
        return True

    # -- faults from outside (tests) -------------------------------------------------

    def kill_daemon(self, sig: int = signal.SIGKILL) -> int:
        """Kill the daemon now (crash tests); returns CLOCK_MONOTONIC ns of the kill."""
        t = self.daemon.kill(sig)
        self.events.append({"kind": "daemon_killed", "signal": int(sig), "at_s": self.t_us / 1e6,
                            "wall_ns": t})
        return t

    # -- the end ---------------------------------------------------------------------

    def finish(self) -> SilResult:
        """Drain, stop the daemon (SIGINT) and the boards, write REC/sil/run.json."""
        if self._finished:
            raise SilError("finish() called twice")
        self._finished = True
        wall = time.monotonic() - self._wall0
        cpu_self = time.process_time() - self._cpu_self0
        cpu_d = self.daemon.cpu_s()
        self.daemon_cpu_s = (round(cpu_d - self._cpu_daemon0, 3) if cpu_d is not None
                             else None)
        boards_cpu = {n: round((cpu_seconds(b.process.pid) or 0.0)
                               - self._cpu_boards0.get(n, 0.0), 3)
                      for n, b in self.boards.items()}
        self.daemon.check("recording")
        drained = self._drain(list(p for p in self.ptys.values() if p.plugged))
        if self.clock is not None:
            self.clock.follow()
        daemon_exit = self.daemon.stop()
        board_exit = {}
        for name, board in self.boards.items():
            board_exit[name] = board.close()
        self.boards.clear()
        status = None
        try:
            status = json.loads((self._tmp / "status.json").read_text())
        except (OSError, ValueError):
            pass
        for p in self.ptys.values():
            p.close()
        shutil.rmtree(self.out / "ports", ignore_errors=True)
        sim_s = self.t_us / 1e6
        summary = {
            "format": "airwake-sil-run/1",
            "scenario": self.scenario.name, "seed": self.seed, "mode": self.mode,
            "helicopter": {"model": self.scenario.helicopter.model,
                           "pilot": self.scenario.helicopter.pilot},
            "survey": _survey_dict(self.survey),
            "duration_s": sim_s, "boards": list(self.rig.boards),
            "host_ports": {b: str(self.out / "ports" / b) for b in self.ptys},
            "rig": _rig_dict(self.rig),
            "clock": {"host": "simulator" if self.mode == "stepped" else "CLOCK_MONOTONIC",
                      "host_offset_ns": self.host_offset_ns,
                      "note": "host time (ns) = host_offset_ns + simulator time (ns)"
                              + ("" if self.mode == "stepped" else " + pacing lag")},
            "faults": {"config": _faults_dict(self.faults),
                       "links": {b: link.summary() for b, link in self.links.items()},
                       "host_bytes_cut": dict(self.host_rx_cut),
                       "events": self.events},
            "boots": self.boots,
            "timing": {"world_s": round(self.timing.get("world_s", 0.0), 3),
                       "setup_s": round(self.timing.get("setup_s", 0.0), 3),
                       "flight_wall_s": round(wall, 3),
                       "realtime_factor": round(sim_s / wall, 3) if wall > 0 else None,
                       "waiting_for_daemon_s": round(self.timing.get("host_wait_s", 0.0), 3)},
            "cpu": {"simulator_s": round(cpu_self, 3),
                    "daemon_s": self.daemon_cpu_s,
                    "boards_s": boards_cpu,
                    "daemon_fraction_of_wall": (round(self.daemon_cpu_s / wall, 3)
                                                if self.daemon_cpu_s and wall > 0 else None)},
            "drained": drained,
            "lockstep": {"other_read_bytes": self.other_reads["bytes"],
                         "other_reads": self.other_reads["times"]},
            "daemon_exit": daemon_exit, "board_exit": board_exit,
            "losa_lines": (self.feeds.losa_lines.lines_sent
                           if self.feeds.losa_lines is not None else 0),
            "daemon_status": status,
        }
        sil_dir = self.out / "sil"
        sil_dir.mkdir(exist_ok=True)
        (sil_dir / "run.json").write_text(json.dumps(summary, indent=1, default=_json_default))
        write_truth_table(self.world, sil_dir / TRUTH_TABLE)
        shutil.copy(self._tmp / "daemon.log", sil_dir / "daemon.log")
        if self.log_frames:
            self._write_frame_logs(sil_dir)
        self._cleanup_tmp()
        return SilResult(self.out, summary, status, daemon_exit)

    def _write_frame_logs(self, sil_dir: Path) -> None:
        arrays = {}
        for b, link in self.links.items():
            if link.sent:
                arrays[f"{b}_sent"] = np.array([(t, *i, int(tch)) for t, i, tch in link.sent],
                                               dtype=np.int64)
            if link.delivered:
                arrays[f"{b}_delivered"] = np.array([(t, *i) for t, i in link.delivered],
                                                    dtype=np.int64)
        np.savez_compressed(sil_dir / "frames.npz", **arrays)

    def _abort(self) -> None:
        """Stop everything after an error (no sidecar)."""
        if self._finished:
            return
        self._finished = True
        if self.daemon is not None:
            self.daemon.close()
        for board in self.boards.values():
            try:
                board.close()
            except Exception:  # noqa: BLE001 — best effort while unwinding
                pass
        for p in self.ptys.values():
            p.close()
        if self.out.exists():
            shutil.rmtree(self.out / "ports", ignore_errors=True)
        if self._tmp is not None and (self._tmp / "daemon.log").exists() and self.out.exists():
            try:
                (self.out / "sil").mkdir(exist_ok=True)
                shutil.copy(self._tmp / "daemon.log", self.out / "sil" / "daemon.log")
            except OSError:
                pass
        self._cleanup_tmp()

    def _cleanup_tmp(self) -> None:
        if self.clock is not None:
            self.clock.close()
            self.clock = None
        if self._tmp is not None:
            shutil.rmtree(self._tmp, ignore_errors=True)
            self._tmp = None

    def __enter__(self) -> SilRun:
        return self

    def __exit__(self, *exc) -> None:
        self._abort()


def _coalesce(records, boots: list[int], on_boot, merge: bool = True):
    """(t, port, bytes) records -> (with `merge`) one chunk per port (time of its first
    record) between reboots; `on_boot()` is called at each reboot, after the bytes sent
    before it."""
    chunks: dict[str, list] = {}
    b = 0
    for t, port, data in records:
        if b < len(boots) and boots[b] <= t:
            yield from ((c[0], p, b"".join(c[1])) for p, c in chunks.items())
            chunks = {}
            while b < len(boots) and boots[b] <= t:
                on_boot()
                b += 1
        if not merge:
            yield t, port, data
            continue
        c = chunks.get(port)
        if c is None:
            chunks[port] = (t, [data])
        else:
            c[1].append(data)
    yield from ((c[0], p, b"".join(c[1])) for p, c in chunks.items())
    while b < len(boots):
        on_boot()
        b += 1


def _rig_dict(rig: SilRig) -> dict:
    from hil_sim.sensors.config import config_to_dict

    d = {k: v for k, v in rig.__dict__.items() if k != "losa_config"}
    d["losa_config"] = config_to_dict(rig.losa_config)
    return d


def _survey_dict(survey) -> dict | None:
    if survey is None:
        return None
    from hil_sim.sensors.config import config_to_dict

    return config_to_dict(survey)


def _faults_dict(faults) -> dict:
    from hil_sim.sensors.config import config_to_dict

    d = config_to_dict(faults)
    d["boards"] = {b: config_to_dict(lf) for b, lf in faults.boards.items()}
    return d


def _json_default(obj):
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    return str(obj)


def write_truth_table(world, path: Path) -> None:
    """The truth world's flight table (sim-table path: truth_* columns, scenario metadata)
    beside the recording, written via a temporary file."""
    import os

    from airwake.record.flight_table import write_flight_table

    built = world.flight_table()
    tmp = path.with_name(f".{path.stem}.tmp{path.suffix}")
    write_flight_table(built.df, tmp, built.metadata)
    os.replace(tmp, path)


def add_truth(flight, recording: Path):
    """(df, metadata) of an exported flight table with the truth world's truth_* columns
    at its times: the stepped daemon's host clock is host_offset_ns + simulator time and
    the table's t_s counts from t0_monotonic_ns, so simulator time = t_s + (t0 -
    host_offset) / 1e9. The metadata gains the scenario, its configuration and seed (what
    the truth wind field is rebuilt from)."""
    from airwake.record.flight_table import load_flight_table

    rec = Path(recording)
    run_path, truth_path = rec / "sil" / "run.json", rec / "sil" / TRUTH_TABLE
    for p in (run_path, truth_path):
        if not p.is_file():
            raise SilError(f"{rec}: no {p.relative_to(rec)}: not a recording of `airwake "
                           "sim run` (or one from before it wrote the truth)")
    run = json.loads(run_path.read_text())
    offset = (run.get("clock") or {}).get("host_offset_ns")
    t0 = flight.metadata.get("t0_monotonic_ns")
    if offset is None or t0 is None:
        raise SilError(f"cannot put the flight on the simulator's timeline: host_offset_ns "
                       f"{offset!r} in run.json, t0_monotonic_ns {t0!r} in the flight's "
                       "metadata (export the recording with airwake export)")
    truth = load_flight_table(truth_path, required=("t_s",))
    df = flight.df.copy()
    t_sim = df["t_s"].to_numpy(float) + (int(t0) - int(offset)) / 1e9
    tt = truth.df["t_s"].to_numpy(float)
    for c in truth.df.columns:
        if c.startswith("truth_"):
            v = truth.df[c].to_numpy(float)
            if c.endswith("yaw_rad"):  # wrapped to (-pi, pi]: interpolate it unwrapped
                v = np.unwrap(v)
                df[c] = np.pi - np.mod(np.pi - np.interp(t_sim, tt, v), 2 * np.pi)
            else:
                df[c] = np.interp(t_sim, tt, v)
    meta = dict(flight.metadata)
    # a survey's anemometer lever arm and mount are the rig's geometry (what a user
    # measures on the pole), not truth of the flight: they travel too, for `airwake windmap`
    for k in ("scenario", "seed", "scenario_config", "sim", "anemometer_lever_arm_m",
              "anemometer_mount_quat_wxyz"):
        if k in truth.metadata:
            meta[k] = truth.metadata[k]
    meta["truth_from"] = str(truth_path)
    meta["sim_time_offset_s"] = (int(t0) - int(offset)) / 1e9
    return df, meta
