"""What each native board's hardware would see, from the truth world, as sim-channel inputs.

`BoardFeeds.build(result, rig)` turns one flown `SimResult` into timed inputs per board:

| board  | role / capture / sensor | from |
|---|---|---|
| rover  | `ins` UART: VN200 binary packets | `result.streams()["rover/vn200"]` |
| rover  | `rtk` UART: Piksi SBP frames (`sbp` package) | `streams()["rover/rtk"]` |
| rover  | `rotor_ir`, `tail_servo` edges | `streams()["rover/rotor"]`, `["rover/tail_servo"]` |
| base   | `rc1..rc5` edges (RC PWM pulses) | `streams()["base/rc"]` |
| base   | `ins` UART: the ship's VN200 | `streams()["base/vn200"]` (ship) |
| marker | MPU-9250 `IMU` samples at 1 kHz | `MarkerImu` on the marker's mount point |
| marker | `anemo` UART: Young 81000 ASCII lines (a survey) | `streams()["marker/anemometer"]` |
| losa   | MPU-9250 `IMU` (the tracker stands still) | `MarkerImu` on the tracker's pose |
| losa   | TSL1401 `LINE` irradiance, **online** | `LosaLineFeed` (below) |

The LOSA lines are `LosaOptics.line_inputs` of the marker pose and of the LED the marker
board lights (its PWM outputs) in the same step: the optical loop is closed through the
firmware. UART bytes arrive as the real UART delivers them: a device's packet is cut
into its first byte and pieces of at most ~1 ms of line time, each given to the board
when its last byte has arrived at the device's baud rate. Edges and IMU samples are
applied at their instants (µs).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from hil_sim.boards.channel import NativeBoard
from hil_sim.boards.rig import SilRig
from hil_sim.sensors.losa import LosaOptics
from hil_sim.sensors.marker_imu import MarkerImu, MarkerImuConfig
from hil_sim.sensors.streams import UART_BITS_PER_BYTE, ByteStream, EdgeStream
from hil_sim.world.kinematics import Trajectory, dcm_to_quat, quat_multiply

RC_CAPTURES = ("rc1", "rc2", "rc3", "rc4", "rc5")


def _us(t_s: np.ndarray) -> np.ndarray:
    return np.round(np.asarray(t_s, dtype=float) * 1e6).astype(np.int64)


class _Cursor:
    """A time-sorted input stream consumed window by window."""

    t_us: np.ndarray

    def __init__(self) -> None:
        self._i = 0

    def window(self, t0_us: int, t1_us: int) -> range:
        """Indexes with t0 <= t < t1 not yet consumed (anything earlier is taken too)."""
        j = int(np.searchsorted(self.t_us, t1_us, side="left"))
        r = range(self._i, max(self._i, j))
        self._i = max(self._i, j)
        return r


class UartFeed(_Cursor):
    """Bytes a peer device sends to one port, cut into pieces of <= ~1 ms of line time."""

    def __init__(self, port: str, stream: ByteStream, baud: int) -> None:
        super().__init__()
        self.port = port
        per_piece = max(1, baud // UART_BITS_PER_BYTE // 1000)
        byte_s = UART_BITS_PER_BYTE / baud
        times, starts, ends = [], [], []
        offs = stream.offsets
        for k in range(len(stream)):
            a, b = int(offs[k]), int(offs[k + 1])
            # the first byte alone (the parsers stamp a packet with its first byte's
            # arrival), then pieces of <= ~1 ms
            cuts = [a, *range(a + 1, b, per_piece), b] if b > a + 1 else [a, b]
            for p, q in zip(cuts[:-1], cuts[1:], strict=True):
                times.append(stream.t_s[k] + (q - a) * byte_s)  # last byte of the piece in
                starts.append(p)
                ends.append(q)
        order = np.argsort(np.asarray(times), kind="stable")
        self.t_us = np.ceil(np.asarray(times)[order] * 1e6).astype(np.int64)
        self._start = np.asarray(starts, dtype=np.int64)[order]
        self._end = np.asarray(ends, dtype=np.int64)[order]
        self._data = stream.data

    def queue(self, board: NativeBoard, t0_us: int, t1_us: int) -> None:
        for i in self.window(t0_us, t1_us):
            board.uart(int(self.t_us[i]), self.port, self._data[self._start[i]:self._end[i]])


class EdgeFeed(_Cursor):
    """Logic edges on input-capture channels (stream channel k -> capture names[k])."""

    def __init__(self, stream: EdgeStream, names: tuple[str, ...]) -> None:
        super().__init__()
        self.t_us = _us(stream.t_s)
        self._ch = [names[int(c)] for c in stream.channel]
        self._level = stream.rising.astype(np.int64)

    def queue(self, board: NativeBoard, t0_us: int, t1_us: int) -> None:
        for i in self.window(t0_us, t1_us):
            board.edge(int(self.t_us[i]), self._ch[i], int(self._level[i]))


class ImuFeed(_Cursor):
    """MPU-9250 samples in the board's chip axes (x fwd, y right, z down)."""

    def __init__(self, samples) -> None:
        super().__init__()
        self.t_us = _us(samples.t_s)
        self._rows = np.column_stack([samples.gyro_rad_s, samples.accel_m_s2, samples.mag_ut,
                                      samples.temperature_c]).astype(np.float32)

    def queue(self, board: NativeBoard, t0_us: int, t1_us: int) -> None:
        r = self.window(t0_us, t1_us)
        if len(r):
            board.imus(self.t_us[r.start:r.stop], self._rows[r.start:r.stop])


# ---------------------------------------------------------------------------
# LOSA: the closed optical loop
# ---------------------------------------------------------------------------


class LosaLineFeed:
    """TSL1401 irradiance for the LOSA board, computed online from the marker's pose
    (truth, in the tracker frame) and the LED the marker board lights right now.

    The marker board drives its four LEDs by PWM (`PWM` records: led0..led3, duty
    0..65535, only one lit). `led_events()` takes them as they come back from the
    marker's step; `queue()` then sends `LINE` records for every array on the update
    grid (`rig.line_rate_hz`) and at every LED change, so the LOSA sees the marker's
    light change at the instant the marker changed it, as the hardware would.

    `LosaOptics.line_inputs` costs ~1 ms per call whatever its length, so the lines are
    computed `lookahead_us` ahead for the LED state of the moment and recomputed from
    the instant of any change: one call per LED change or per look-ahead, instead of
    one per step.
    """

    def __init__(self, optics: LosaOptics, t_s: np.ndarray, marker_pos_t_m: np.ndarray,
                 marker_quat_wxyz: np.ndarray, rate_hz: float,
                 lookahead_us: int = 50_000) -> None:
        self.optics = optics
        self._t_us = _us(t_s)
        self._pos = marker_pos_t_m
        self._quat = marker_quat_wxyz
        self.period_us = int(round(1e6 / rate_hz))
        self.lookahead_us = int(lookahead_us)
        self.duty = np.zeros(4, dtype=np.int64)
        self._events: list[tuple[int, int, int]] = []  # (t_us, led, duty)
        self._state = (0, 0.0)  # (lit LED, drive 0..1) the buffer was computed for
        self._buf: list[tuple[int, np.ndarray, np.ndarray]] = []  # (t_us, rate, dark)
        self._end = 0  # the buffer covers times < _end
        self.lines_sent = 0
        self.optics_calls = 0

    def led_events(self, pwm: list[tuple[int, str, int]]) -> None:
        for t, ch, duty in pwm:
            if ch.startswith("led"):
                self._events.append((int(t), int(ch[3:]), int(duty)))

    def _pose(self, t_us: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        k = np.clip(np.searchsorted(self._t_us, t_us, side="right") - 1, 0, self._t_us.size - 2)
        f = ((t_us - self._t_us[k]) / (self._t_us[k + 1] - self._t_us[k]))[:, None]
        f = np.clip(f, 0.0, 1.0)
        pos = self._pos[k] * (1 - f) + self._pos[k + 1] * f
        q = self._quat[k] * (1 - f) + self._quat[k + 1] * f
        return pos, q / np.linalg.norm(q, axis=1, keepdims=True)

    def _compute(self, t_start: int) -> None:
        """Lines from t_start (itself, then the grid) for `lookahead_us`, current state."""
        period = self.period_us
        first = (t_start // period + 1) * period
        end = -(-(t_start + self.lookahead_us) // period) * period  # on the grid
        times = np.array([t_start, *range(first, end, period)], dtype=np.int64)
        pos, quat = self._pose(times)
        led, drive = self._state
        lines = self.optics.line_inputs(times / 1e6, pos, quat, led, drive)
        self.optics_calls += 1
        rate, dark = lines.rate_counts_per_us, lines.dark_counts
        self._buf.extend((int(t), rate[i], dark[i]) for i, t in enumerate(times))
        self._end = end

    def prefetch(self, t1_us: int) -> None:
        """Compute the lines up to t1_us for the LED state of the moment now, as `queue()`
        would (an LED change in between recomputes from its instant). The stepped SIL
        calls it while the daemon reads the previous step, off the lockstep's path."""
        while self._end < t1_us:
            self._compute(self._end)

    def queue(self, board: NativeBoard, t0_us: int, t1_us: int) -> None:
        events = sorted(e for e in self._events if e[0] < t1_us)
        self._events = [e for e in self._events if e[0] >= t1_us]
        i = 0
        while i < len(events):
            te = max(t0_us, events[i][0])
            while i < len(events) and max(t0_us, events[i][0]) == te:
                self.duty[events[i][1]] = events[i][2]
                i += 1
            k = int(np.argmax(self.duty))
            state = (k, self.duty[k] / 65535.0)
            if state != self._state:
                self._state = state
                self._buf = [b for b in self._buf if b[0] < te]
                self._compute(te)
        if not self._buf and self._end < t0_us:
            self._end = t0_us
        while self._end < t1_us:
            self._compute(self._end)
        sent = 0
        for t, _, _ in self._buf:
            if t >= t1_us:
                break
            sent += 1
        if sent:
            now = self._buf[:sent]
            board.lines([b[0] for b in now], np.stack([b[1] for b in now]),
                        np.stack([b[2] for b in now]))
        del self._buf[:sent]
        self.lines_sent += 4 * sent


# ---------------------------------------------------------------------------
# Geometry: tracker and marker in the world
# ---------------------------------------------------------------------------


def tracker_axes_ned(heading_deg: float, tilt_deg: float) -> np.ndarray:
    """(3, 3) rows x_T (right), y_T (down), z_T (forward, out of the tracker's face) in
    NED, for a tracker facing `heading_deg` and tilted up by `tilt_deg`: the rotation
    NED -> tracker frame (v_T = R v_NED)."""
    psi, th = math.radians(heading_deg), math.radians(tilt_deg)
    z = np.array([math.cos(th) * math.cos(psi), math.cos(th) * math.sin(psi), -math.sin(th)])
    x = np.array([-math.sin(psi), math.cos(psi), 0.0])
    y = np.cross(z, x)
    return np.vstack([x, y, z])


def marker_in_tracker(truth: Trajectory, rig: SilRig) -> tuple[np.ndarray, np.ndarray]:
    """Marker centre (N, 3) and attitude marker -> tracker (N, 4) over the flight."""
    m = truth.at_point(np.asarray(rig.marker_position_body_m, float),
                       np.asarray(rig.marker_mount_quat_wxyz, float))
    r_tn = tracker_axes_ned(rig.tracker_heading_deg, rig.tracker_tilt_deg)
    pos = (m.pos_ned_m - np.asarray(rig.tracker_position_ned_m, float)) @ r_tn.T
    q_tn = dcm_to_quat(r_tn)
    quat = quat_multiply(np.broadcast_to(q_tn, m.quat_wxyz.shape), m.quat_wxyz)
    return pos, quat


def tracker_board_trajectory(rig: SilRig, t_end_s: float) -> Trajectory:
    """The LOSA board at rest: its chip axes FRD with F = the tracker's z (out of the
    face), R = x, D = y."""
    r_tn = tracker_axes_ned(rig.tracker_heading_deg, rig.tracker_tilt_deg)
    body_to_ned = np.column_stack([r_tn[2], r_tn[0], r_tn[1]])
    q = dcm_to_quat(body_to_ned)
    t = np.array([0.0, max(t_end_s, 1e-3)])
    pos = np.broadcast_to(np.asarray(rig.tracker_position_ned_m, float), (2, 3))
    return Trajectory.from_states(t, pos, np.zeros((2, 3)), np.broadcast_to(q, (2, 4)),
                                  np.zeros((2, 3)))


def _imu_samples(traj: Trajectory, rate_hz: float, rng: np.random.Generator):
    imu = MarkerImu(MarkerImuConfig(rate_hz=rate_hz), rng=rng)
    return imu.measure(traj)


# ---------------------------------------------------------------------------
# All boards
# ---------------------------------------------------------------------------


@dataclass
class BoardFeeds:
    """Per board: the precomputed feeds, and (LOSA) the online line feed."""

    feeds: dict[str, list]
    losa_lines: LosaLineFeed | None
    truth: dict

    def queue(self, board_name: str, board: NativeBoard, t0_us: int, t1_us: int) -> None:
        for f in self.feeds.get(board_name, ()):
            f.queue(board, t0_us, t1_us)
        if board_name == "losa" and self.losa_lines is not None:
            self.losa_lines.queue(board, t0_us, t1_us)

    def prefetch(self, t1_us: int) -> None:
        """Work that does not wait for the host's replies (the LOSA's look-ahead lines)."""
        if self.losa_lines is not None:
            self.losa_lines.prefetch(t1_us)

    @classmethod
    def build(cls, result, rig: SilRig, rngs: dict[str, np.random.Generator]) -> BoardFeeds:
        s = result.streams()
        feeds: dict[str, list] = {b: [] for b in rig.boards}
        truth: dict = {}
        if "rover" in feeds:
            cfg = result.scenario.sensors
            feeds["rover"].append(UartFeed("ins", s["rover/vn200"], cfg.vn200.baud))
            if "rover/rtk" in s:
                feeds["rover"].append(UartFeed("rtk", s["rover/rtk"], cfg.rtk.baud))
            feeds["rover"].append(EdgeFeed(s["rover/rotor"], ("rotor_ir",)))
            feeds["rover"].append(EdgeFeed(s["rover/tail_servo"], ("tail_servo",)))
        if "base" in feeds:
            feeds["base"].append(EdgeFeed(s["base/rc"], RC_CAPTURES))
            if "base/vn200" in s:
                feeds["base"].append(UartFeed("ins", s["base/vn200"],
                                              result.scenario.sensors.base_vn200.baud))
        lines = None
        end_s = float(result.truth.t_s[-1])
        if "marker" in feeds:
            mount = result.truth.at_point(np.asarray(rig.marker_position_body_m, float),
                                          np.asarray(rig.marker_mount_quat_wxyz, float))
            feeds["marker"].append(ImuFeed(_imu_samples(mount, rig.imu_rate_hz,
                                                        rngs["marker"])))
            if "marker/anemometer" in s:
                an = s["marker/anemometer"]
                feeds["marker"].append(UartFeed("anemo", an, an.baud))
        if "losa" in feeds:
            feeds["losa"].append(ImuFeed(_imu_samples(tracker_board_trajectory(rig, end_s),
                                                      rig.imu_rate_hz, rngs["losa_imu"])))
            pos, quat = marker_in_tracker(result.truth, rig)
            optics = LosaOptics(dataclasses.replace(rig.losa_config), rng=rngs["losa"])
            lines = LosaLineFeed(optics, result.truth.t_s, pos, quat, rig.line_rate_hz)
            truth["marker_pos_tracker_m"] = pos
        return cls(feeds, lines, truth)

