"""The ship-laptop daemon: serial ports -> decode -> clock mapping -> recording, with
link health, the marker loop and clean shutdown (docs/daemon.md).

One thread, one `selectors` loop over the ports' file descriptors: a port is read only
when the OS says it has data, writes never block (what a stalled board does not take is
dropped and counted), a lost port is reopened with backoff, so one slow or dead port
never stalls the others. After each pass the loop sleeps the rest of `poll_s` (5 ms):
frames then arrive a few per read instead of one per wake-up, which is most of the CPU
saving (docs/daemon.md has the figures); host receive times stay within 5 ms.

Per received chunk: the raw bytes go to `/raw/<role>` with the receive time; per decoded
frame: its origin board's `BoardLink` counts it and maps its board time
(`link.clock.BoardClock`), and the frame goes to `/<board>/<message>` (ros1-encoded:
header + packed payload, docs/recordings.md). Per port
every 0.5 s a `time_sync_request` (NTP-style: the board's reply gives the two-sided clock
fit) and every 0.25 s one of the host's `schema_entry` announcements. With a marker and a
LOSA tracker present, `marker_command` at 60 Hz to the marker's port, and (unless
`track` is off) the live pose EKF (`tracking.live`) on the marker IMU and LOSA peaks,
recorded on `/host/pose` and feeding the marker loop's position. With `net` (a rate
net, `airwake nets train`), the live airwake intensity (`nets.live`) on the rover's INS
and the base's pilot inputs, A_ω per INS sample recorded on `/host/airwake_intensity`;
with `wind_net` (`airwake nets train --target wind`) the live wind (`nets.live_wind`) on
the same rows, recorded on `/host/wind`.
"""

from __future__ import annotations

import json
import os
import selectors
import signal
import socket
import sys
import time
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path
from typing import TextIO

# numpy (2.x) imports numpy.ma lazily, on the first np.median (the boards' clock fits): done
# here, at start, not as a 400 kB read that stalls the ingest in mid-flight (and that the
# SIL lockstep, which counts the daemon's reads, would see as port bytes)
import numpy.ma  # noqa: F401

from airwake.link.decoder import StreamDecoder
from airwake.link.framing import encode_frame
from airwake.link.health import BoardLink, RateMeter, board_health, port_health
from airwake.link.messages import (
    BY_ID,
    HEARTBEAT,
    IMU,
    INS,
    LOG_TEXT,
    LOSA_PEAKS,
    LOSA_RAW_REQUEST,
    MARKER_ATTITUDE,
    MARKER_COMMAND,
    PILOT_INPUTS,
    RTK_BASELINE,
    SCHEMA_ENTRY,
    SCHEMA_HASH,
    STAMP_LATENCY,
    TIME_SYNC_REPLY,
    TIME_SYNC_REQUEST,
    SchemaEntry,
    TimeSyncRequest,
)
from airwake.link.serial_port import PortSpec, SerialPort
from airwake.record.recording import RecordingError, RecordingWriter, encode_decoded

HOST_SENT_IDS = (SCHEMA_ENTRY.id, TIME_SYNC_REQUEST.id, MARKER_COMMAND.id, LOSA_RAW_REQUEST.id)
LOSA_ID, MARKER_ID, ROVER_ID, BASE_ID = 1, 2, 3, 4
BOARD_ALIVE_S = 3.0  # a board whose heartbeat is older is not "present" for the marker loop


@dataclass
class DaemonOptions:
    """Everything `airwake daemon` takes on its command line."""

    ports: list[PortSpec]
    out: Path
    status_json: str | None = None  # path, "-" (JSON lines on stdout) or None
    duration_s: float | None = None
    view: bool = True
    poll_s: float = 0.005
    sync_period_s: float = 0.5
    schema_period_s: float = 0.25
    status_period_s: float = 1.0
    marker_rate_hz: float = 60.0
    # the live pose EKF (runs once marker and LOSA frames arrive): None loads it when the
    # first marker or LOSA frame arrives, True at start, False never
    track: bool | None = None
    net: str | None = None  # a rate net (.pt): live A_ω on /host/airwake_intensity
    wind_net: str | None = None  # a wind net (.pt): the live eq 5.3 wind on /host/wind
    flush_s: float = 0.1  # recording.FLUSH_S: what a crash may lose (docs/daemon.md)
    segment_s: float = 600.0
    record_metadata: dict = field(default_factory=dict)  # e.g. antenna offsets
    live: str | None = None  # [HOST:]PORT of the live page (daemon/live_web.py)
    foxglove: str | None = None  # [HOST:]PORT of the Foxglove server (daemon/foxglove_bridge.py)


class PortState:
    """A port, its decoder and its rate meter."""

    def __init__(self, spec: PortSpec) -> None:
        self.port = SerialPort(spec)
        self.decoder = StreamDecoder()
        self.rates = RateMeter()
        self.raw_topic = f"/raw/{spec.role}"
        self.tx_topic = f"/raw/{spec.role}/tx"
        self.next_sync = 0.0
        self.next_schema = 0.0
        self.schema_index = 0
        self.registered_fd = -1
        self.problems: set[str] = set()

    @property
    def role(self) -> str:
        return self.port.role


class Daemon:
    """See module doc. `run()` returns the exit status (0 clean, 1 recording failed)."""

    def __init__(self, options: DaemonOptions, stdout: TextIO | None = None,
                 stderr: TextIO | None = None) -> None:
        self.opt = options
        self.stdout = stdout or sys.stdout
        self.stderr = stderr or sys.stderr
        self.ports = [PortState(s) for s in options.ports]
        roles = [p.role for p in self.ports]
        if len(set(roles)) != len(roles):
            raise RecordingError(f"--port roles must differ: {roles}")
        self.boards: dict[int, BoardLink] = {}
        self.topics: dict[tuple[int, int], str] = {}
        self.events: deque = deque(maxlen=20)
        self.start_ns = time.monotonic_ns()
        self.start_wall = time.time()
        from airwake import __version__
        from airwake.daemon.marker_loop import MarkerLoop

        self.marker = MarkerLoop(options.marker_rate_hz)
        self.tracker = None
        # the pose EKF (filterpy, scipy: ~0.8 s and ~40 MB) loads at start only when asked
        # (`track` True); by default once a marker or LOSA frame arrives, imported by a
        # thread while the ingest goes on (a second's stall would overflow the ports'
        # buffers at full rate), started when that is done; never with `track` False
        self._tracker_loader = None
        self._tracker_wanted = options.track is None
        if options.track:
            self._start_tracker()
        self.intensity = None
        self.nets: list[tuple[str, str, dict, str]] = []  # (attribute, topic, schema, label)
        net_meta = {}
        if options.net:
            from airwake.nets.live import INTENSITY_SCHEMA, LiveIntensity
            from airwake.nets.model import load_net

            self.intensity = LiveIntensity(load_net(options.net))
            self.nets.append(("intensity", "/host/airwake_intensity", INTENSITY_SCHEMA,
                              "airwake intensity"))
            xy = options.record_metadata.get("base_antenna_ship_xy_m")
            if xy is not None:  # the track in the ship frame from the base antenna's place
                self.intensity.base_antenna_ship_m = (float(xy[0]), float(xy[1]))
            card = self.intensity.net.card
            net_meta = {"live_net": {
                "path": str(options.net), "target": card["target"],
                "input_source": card["input_source"], "rate_hz": card["rate_hz"],
                "training_flights": [f.get("path") for f in card.get("training_flights", [])],
                "intensity": self.intensity.config.to_dict()}}
        self.wind = None
        if options.wind_net:
            from airwake.nets.live_wind import WIND_SCHEMA, LiveWind
            from airwake.nets.model import load_net

            self.wind = LiveWind(load_net(options.wind_net))
            self.nets.append(("wind", "/host/wind", WIND_SCHEMA, "wind"))
            card = self.wind.net.card
            net_meta["live_wind_net"] = {
                "path": str(options.wind_net), "rate_hz": card["rate_hz"],
                "labels": self.wind.config.labels,
                "training_flights": [f.get("path") for f in card.get("training_flights", [])],
                "validation_rms": card.get("validation_rms")}
        self.live = None
        if options.live is not None or options.foxglove is not None:
            from airwake.daemon.live_outputs import LiveOutputs

            self.live = LiveOutputs(options.live, options.foxglove, lambda text: print(
                f"airwake daemon: {text}", file=self.stderr, flush=True))
        self.recorder = RecordingWriter(options.out, {
            "daemon_version": __version__,
            "schema_hash": f"0x{SCHEMA_HASH:08X}",
            "host": socket.gethostname(),
            "start_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(self.start_wall)),
            "start_unix_ns": int(self.start_wall * 1e9),
            "start_monotonic_ns": self.start_ns,
            "host_clock": "CLOCK_MONOTONIC",
            "ports": [{"role": s.role, "device": s.device, "baud": s.baud}
                      for s in options.ports],
            **net_meta,
            **options.record_metadata,
        }, flush_s=options.flush_s, segment_s=options.segment_s)
        if self.live is not None:  # the outputs see each message after the recorder
            self.recorder = self.live.tee(self.recorder)
        self._stop = False
        self._stop_reason = ""
        self._sel = selectors.DefaultSelector()
        self._request_id = 0
        self._next_status = 0.0
        self._reported_failure = False
        self._status_file_failed = False
        self.host_seq = [0] * 256

    # -- events ---------------------------------------------------------------

    def event(self, kind: str, text: str, loud: bool = False, **extra) -> None:
        now_ns = time.monotonic_ns()
        e = {"t_s": round((now_ns - self.start_ns) / 1e9, 3), "kind": kind, "text": text,
             **extra}
        self.events.append(e)
        self.recorder.json("/daemon/events", now_ns, e)
        if loud:
            print(f"airwake daemon: {kind}: {text}", file=self.stderr, flush=True)

    # -- main loop --------------------------------------------------------------

    def request_stop(self, reason: str = "") -> None:
        self._stop = True
        self._stop_reason = reason

    def _signal(self, signum, _frame) -> None:
        self.request_stop(signal.Signals(signum).name)

    def run(self) -> int:
        old = {s: signal.signal(s, self._signal) for s in (signal.SIGINT, signal.SIGTERM)}
        try:
            self._loop()
        finally:
            for s, h in old.items():
                signal.signal(s, h)
            status = self._shutdown()
            if self.live is not None:
                self.live.close()
        return status

    def _loop(self) -> None:
        end = None if self.opt.duration_s is None else time.monotonic() + self.opt.duration_s
        poll = self.opt.poll_s
        while not self._stop:
            t0 = time.monotonic()
            if end is not None and t0 >= end:
                self.request_stop("duration reached")
                break
            for ps in self.ports:
                if not ps.port.is_open and ps.port.try_open(t0):
                    self._sel.register(ps.port.fd, selectors.EVENT_READ, ps)
                    ps.registered_fd = ps.port.fd
                    self.event("port_open", f"port {ps.role} open: {ps.port.spec.device}",
                               port=ps.role, opens=ps.port.opens)
            try:
                ready = self._sel.select(timeout=0.05) if self._sel.get_map() else []
            except InterruptedError:
                ready = []
            if not self._sel.get_map():
                time.sleep(0.02)
            for key, _ in ready:
                self._read(key.data)
            if self.tracker is not None:
                self._track()
            self._live_nets()
            self._periodic(time.monotonic())
            if self._tracker_loader is not None and not self._tracker_loader.is_alive():
                self._tracker_loader = None
                try:
                    self._start_tracker()
                except Exception as exc:  # noqa: BLE001 -- the tracker never stops the ingest
                    self.event("tracker_failed", f"live tracker: {type(exc).__name__}: {exc}; "
                               "it stays off, recording continues", loud=True)
            self._reap_lost()
            spare = poll - (time.monotonic() - t0)
            if spare > 0 and not self._stop:
                time.sleep(spare)

    def _reap_lost(self) -> None:
        """Unregister ports that a read or write found gone (they reopen with backoff)."""
        for ps in self.ports:
            if ps.registered_fd >= 0 and not ps.port.is_open:
                try:
                    self._sel.unregister(ps.registered_fd)
                except (KeyError, ValueError):
                    pass
                ps.registered_fd = -1
                self.event("port_lost", f"port {ps.role} lost: {ps.port.last_error}; reopening "
                           f"{ps.port.spec.device}", loud=True, port=ps.role)

    def _read(self, ps: PortState) -> None:
        if not ps.port.is_open:
            return
        data = ps.port.read()
        rx_ns = time.monotonic_ns()
        if not data:  # nothing, or lost (reaped after this pass)
            return
        self.recorder.raw(ps.raw_topic, rx_ns, data)
        frames = ps.decoder.feed(data)
        if frames:
            host_us = rx_ns / 1000.0
            now_s = (rx_ns - self.start_ns) / 1e9
            for f in frames:
                self._frame(ps, f, rx_ns, host_us, now_s)

    def _frame(self, ps: PortState, f, rx_ns: int, host_us: float, now_s: float) -> None:
        origin = f.flags & 0x07
        b = self.boards.get(origin)
        if b is None:
            b = self.boards[origin] = BoardLink(origin, ps.role)
            b.first_seen_s = now_s
            self.event("board_seen", f"frames from {b.name} ({origin}) on port {ps.role}",
                       board=b.name, port=ps.role)
        mid = f.msg_id
        clock = b.clock
        n_epochs = len(clock.epochs)
        if mid == HEARTBEAT.id:
            clock.heartbeat(f.msg, f.board_time_us, host_us)
            self._heartbeat(ps, b, f.msg, now_s)
        elif mid == TIME_SYNC_REPLY.id:
            clock.sync_reply(f.msg, f.board_time_us, host_us)
        epoch, board_us, mapped_us = clock.frame(mid, f.board_time_us, host_us)
        if len(clock.epochs) != n_epochs and n_epochs:
            b.reset_sequences()
            ep = clock.ep
            self.event("epoch", f"{b.name}: new clock epoch {ep.index} ({ep.reason})",
                       loud=True, board=b.name, epoch=ep.index)
        b.count(mid, f.seq)
        topic = self.topics.get((origin, mid))
        info = BY_ID[mid]
        if topic is None:
            topic = self.topics[(origin, mid)] = f"/{b.name}/{info.name}"
        body = encode_decoded(info, f.msg, f.seq, f.board_time_us, board_us, epoch)
        self.recorder.decoded(topic, info, int(mapped_us * 1000.0), rx_ns, body)
        if self._tracker_wanted and origin in (LOSA_ID, MARKER_ID):
            self._load_tracker()
        if mid == LOSA_PEAKS.id:
            self.marker.on_peaks(f.msg, now_s)
            if self.tracker is not None and origin == LOSA_ID:
                self.tracker.on_peaks(mapped_us * 1e-6, f.msg)
        elif mid == MARKER_ATTITUDE.id:
            self.marker.on_attitude(f.msg)
            if self.tracker is not None and origin == MARKER_ID:
                self.tracker.on_attitude(mapped_us * 1e-6, f.msg)
        elif mid == IMU.id:
            if self.tracker is not None and origin == MARKER_ID:
                self.tracker.on_imu(mapped_us * 1e-6, f.msg)
        elif mid == INS.id:
            # the nets' rows on the export's timeline: the declared stamp latency removed
            t_row = (mapped_us - b.stamp_latency_us.get("ins", 0)) * 1e-6
            if self.intensity is not None and origin == ROVER_ID:
                self.intensity.on_ins(t_row, f.msg)
            elif self.intensity is not None and origin == BASE_ID:
                self.intensity.on_ship_ins(mapped_us * 1e-6, f.msg)
            if self.wind is not None and origin == ROVER_ID:
                self.wind.on_ins(t_row, f.msg)
        elif mid == RTK_BASELINE.id:
            if self.intensity is not None and origin == ROVER_ID:
                self.intensity.on_baseline(mapped_us * 1e-6, f.msg)
        elif mid == PILOT_INPUTS.id:
            t_in = (mapped_us - b.stamp_latency_us.get("pilot_inputs", 0)) * 1e-6
            if self.intensity is not None and origin == BASE_ID:
                self.intensity.on_pilot_inputs(t_in, f.msg)
            if self.wind is not None and origin == BASE_ID:
                self.wind.on_pilot_inputs(t_in, f.msg)
        elif mid == STAMP_LATENCY.id:
            if b.declare_stamp(f.msg) and b.identified:  # into the recording's board metadata
                self.recorder.board(b.name, {**b.identity(), "first_seen_s": b.first_seen_s})
        elif mid == LOG_TEXT.id:
            text = bytes(f.msg.text_utf8).split(b"\0", 1)[0].decode("utf-8", "replace")
            self.event("board_log", f"{b.name}: {text}", board=b.name, level=f.msg.level,
                       code=f.msg.code)

    def _load_tracker(self) -> None:
        """Import the tracker's modules in a thread; the loop starts it when done."""
        import threading

        def load() -> None:
            try:
                import airwake.tracking.live  # noqa: F401 -- its imports are the cost
            except Exception:  # noqa: BLE001 -- reported by _start_tracker's own import
                pass

        self._tracker_wanted = False
        self._tracker_loader = threading.Thread(target=load, name="tracker-import",
                                                daemon=True)
        self._tracker_loader.start()

    def _start_tracker(self) -> None:
        from airwake.tracking.live import LiveTracker

        self._tracker_wanted = False
        self.tracker = LiveTracker()

    def _track(self) -> None:
        """Apply the queued marker/LOSA frames to the pose EKF; record its poses."""
        from airwake.tracking.live import POSE_SCHEMA

        started = self.tracker.started
        try:
            poses = self.tracker.step()
        except Exception as exc:  # noqa: BLE001 -- the tracker must never stop the ingest
            self.event("tracker_failed", f"live tracker: {type(exc).__name__}: {exc}; "
                       "it stays off, recording continues", loud=True)
            self.tracker = None
            return
        for pose in poses:
            self.recorder.json("/host/pose", int(pose["t_s"] * 1e9), pose, POSE_SCHEMA)
        if self.tracker.started and not started:
            self.event("tracker_started", "pose EKF started from the marker's calibration and "
                       f"LOSA: position {self.tracker.status()['pos_tracker_m']} m")

    def _live_nets(self) -> None:
        """Run each live net (--net, --wind-net) on its pending INS rows; record each
        sample on its channel. A net that raises is turned off, loudly; ingest goes on."""
        for attr, topic, schema, label in self.nets:
            net = getattr(self, attr)
            if net is None:
                continue
            try:
                samples = net.step()
            except Exception as exc:  # noqa: BLE001 -- a net must never stop the ingest
                self.event(f"{attr}_failed", f"live {label}: {type(exc).__name__}: {exc}; it "
                           "stays off, recording continues", loud=True)
                setattr(self, attr, None)
                continue
            for s in samples:
                self.recorder.json(topic, int(s["t_s"] * 1e9), s, schema)

    def _heartbeat(self, ps: PortState, b: BoardLink, hb, now_s: float) -> None:
        first = not b.identified
        rebooted = (b.heartbeat is not None and hb.boot_count != b.heartbeat.boot_count)
        b.heartbeat = hb
        b.heartbeat_host_s = now_s
        b.port = ps.role
        if first or rebooted:
            b.identified = True
            ident = b.identity()
            self.recorder.board(b.name, {**ident, "first_seen_s": b.first_seen_s})
            ok = "schema OK" if ident["schema_ok"] else \
                f"SCHEMA MISMATCH (ours 0x{SCHEMA_HASH:08X})"
            self.event("board_identified",
                       f"{b.name} on port {ps.role}: firmware {ident['fw_version']}, schema "
                       f"{ident['schema_hash']} {ok}, boot count {hb.boot_count}",
                       loud=not ident["schema_ok"], board=b.name, **ident)
            if hb.board_id != b.origin:
                self.event("identity", f"port {ps.role}: heartbeat board_id {hb.board_id} "
                           f"differs from the frames' origin {b.origin}", loud=True)
        self._check_schema(ps)

    def _check_schema(self, ps: PortState) -> None:
        """Report (once each, loudly) the decoder's schema problems on this port."""
        for line in ps.decoder.schema_problems():
            if line not in ps.problems:
                ps.problems.add(line)
                for b in self.boards.values():
                    if f"({b.origin})" in line:
                        b.schema_problems.append(line)
                self.event("schema_mismatch", f"port {ps.role}: {line}", loud=True,
                           port=ps.role)

    # -- periodic work ----------------------------------------------------------

    def _send(self, ps: PortState, msg, now_ns: int) -> None:
        info = BY_ID[type(msg).MSG_ID]
        seq = self.host_seq[info.id]
        self.host_seq[info.id] = (seq + 1) & 0xFF
        wire = encode_frame(msg, seq, 0, 0)
        ps.port.write(wire)
        self.recorder.raw(ps.tx_topic, now_ns, wire)
        body = encode_decoded(info, msg, seq, 0, 0, 0)
        self.recorder.decoded(f"/host/{info.name}", info, now_ns, now_ns, body)

    def _periodic(self, now: float) -> None:
        for ps in self.ports:
            if not ps.port.is_open:
                continue
            if now >= ps.next_sync:
                ps.next_sync = now + self.opt.sync_period_s
                self._request_id = (self._request_id + 1) & 0xFFFFFFFF
                now_ns = time.monotonic_ns()
                self._send(ps, TimeSyncRequest(self._request_id, now_ns // 1000), now_ns)
            if now >= ps.next_schema:
                ps.next_schema = now + self.opt.schema_period_s
                k = ps.schema_index % len(HOST_SENT_IDS)
                ps.schema_index += 1
                mid = HOST_SENT_IDS[k]
                self._send(ps, SchemaEntry(mid, BY_ID[mid].def_hash, k, len(HOST_SENT_IDS)),
                           time.monotonic_ns())
        self._marker_loop(now)
        self.recorder.tick(now)
        if self.recorder.failed and not self._reported_failure:
            self._reported_failure = True
            self.event("recording_failed", self.recorder.failed, loud=True)
        if now >= self._next_status:
            self._next_status = now + self.opt.status_period_s
            self._status()

    def _present(self, origin: int, now_s: float) -> BoardLink | None:
        b = self.boards.get(origin)
        if b is None or b.heartbeat_host_s is None or now_s - b.heartbeat_host_s > BOARD_ALIVE_S:
            return None
        return b

    def _marker_loop(self, now: float) -> None:
        now_s = (time.monotonic_ns() - self.start_ns) / 1e9
        if not self.marker.due(now_s):
            return
        marker = self._present(MARKER_ID, now_s)
        if marker is None or self._present(LOSA_ID, now_s) is None:
            return
        ps = next((p for p in self.ports if p.role == marker.port), None)
        if ps is None or not ps.port.is_open:
            return
        estimate = None
        if self.tracker is not None:
            estimate = self.tracker.position(time.monotonic(), self.marker.max_age_s)
        cmd = self.marker.command(now_s, estimate)
        now_ns = time.monotonic_ns()
        self._send(ps, cmd, now_ns)
        if cmd.pos_valid:
            self.recorder.json("/host/tracker_position", now_ns,
                               {"pos_tracker_m": list(cmd.pos_tracker_m)})

    # -- status -------------------------------------------------------------------

    def status(self) -> dict:
        """The link-health snapshot (docs/daemon.md lists the keys)."""
        now_ns = time.monotonic_ns()
        now_s = (now_ns - self.start_ns) / 1e9
        ports = {}
        for ps in self.ports:
            p = ps.port
            ports[ps.role] = port_health(
                ps.role, p.spec.device, p.spec.baud, p.is_open, ps.decoder,
                {"opens": p.opens, "losses": p.losses, "last_error": p.last_error,
                 "tx_bytes": p.bytes_tx, "tx_dropped": p.tx_dropped,
                 "seq_lost": sum(sum(b.lost) for b in self.boards.values()
                                 if b.port == ps.role)},
                ps.rates, now_s, sorted(b.name for b in self.boards.values()
                                        if b.port == ps.role))
        rec = self.recorder
        return {
            "t_s": round(now_s, 3),
            "host_monotonic_ns": now_ns,
            "recording": {"path": str(rec.directory), "state": "failed" if rec.failed else (
                "closed" if rec.closed else "recording"), "error": rec.failed,
                "bytes": rec.bytes_written, "messages": rec.messages,
                "segments": len(rec.segments)},
            "ports": ports,
            "boards": {b.name: board_health(b, now_s) for b in self.boards.values()},
            "marker_loop": self.marker.status(),
            **({"tracker": self.tracker.status()} if self.tracker is not None
               and self.tracker.triangulated else {}),
            **({"airwake_intensity": self.intensity.status()} if self.intensity is not None
               else {}),
            **({"wind": self.wind.status()} if self.wind is not None else {}),
            **({"live": self.live.status()} if self.live is not None else {}),
            "events": list(self.events)[-5:],
        }

    def _status(self) -> None:
        for ps in self.ports:
            self._check_schema(ps)
        st = self.status()
        self.recorder.json("/daemon/status", st["host_monotonic_ns"], st)
        target = self.opt.status_json
        if target == "-":
            print(json.dumps(st, default=str), file=self.stdout, flush=True)
        elif target:
            self._write_status_file(Path(target), st)
        if self.opt.view:
            from airwake.daemon.view import render

            out = self.stderr if target == "-" else self.stdout
            tty = bool(getattr(out, "isatty", lambda: False)())
            text = render(st)
            if tty:
                out.write("\x1b[H\x1b[2J" + text + "\n")
            else:
                out.write(text + "\n")
            out.flush()

    def _write_status_file(self, path: Path, st: dict) -> None:
        try:
            _atomic_write(path, json.dumps(st, indent=1, default=str))
        except OSError as exc:  # a full disk must not stop the ingest
            if not self._status_file_failed:
                self._status_file_failed = True
                self.event("status_file_failed", f"cannot write {path}: {exc.strerror}",
                           loud=True)

    def _shutdown(self) -> int:
        for ps in self.ports:
            if ps.registered_fd >= 0:
                try:
                    self._sel.unregister(ps.registered_fd)
                except (KeyError, ValueError):
                    pass
                ps.registered_fd = -1
            ps.port.close()
        st = self.status()
        summary = {
            "stop_reason": self._stop_reason,
            "duration_s": st["t_s"],
            "ports": st["ports"],
            "boards": {k: {kk: v[kk] for kk in ("board_id", "port", "fw_version", "frames",
                                                "seq_lost", "clock") if kk in v}
                       for k, v in st["boards"].items()},
            "clock_epochs": {b.name: b.clock.events for b in self.boards.values()},
        }
        self.event("stop", f"stopping: {self._stop_reason or 'loop ended'}")
        self.recorder.close(summary)
        st = self.status()
        if self.opt.status_json and self.opt.status_json != "-":
            self._write_status_file(Path(self.opt.status_json), st)
        if self.recorder.failed:
            print(f"airwake daemon: error: {self.recorder.failed}", file=self.stderr, flush=True)
            return 1
        return 0


def _atomic_write(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)

