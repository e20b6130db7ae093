"""The SIL rig: which boards fly, how they are wired and where the tracker stands.

`rig_for(scenario)` gives the defaults for a scenario:

- **Boards** by site: a hall (indoor) flight has all four — the LOSA tracker on the floor
  watching the active marker on the helicopter, the rover on the helicopter and the
  base with the RC receiver; field and ship flights have the rover and the base (no
  tracker outdoors). `boards=` overrides (e.g. `sim run --boards rover,base`).
- **Links** as on the Teensy builds (docs/firmware.md): host UARTs 460800 baud (LOSA,
  marker, rover's XBee) / 921600 (base), VN200 921600, Piksi 115200, the base's rover
  XBee port 460800. The rover reaches the host through the base: rover host port ->
  base `rover` port, `xbee_latency_us` (5 ms, a Wi-Fi hop) later, both ways. Boards
  facing the host (losa, marker, base) get a pty each.
- **Clocks**: each board's crystal has its own drift and boot offset (`--clock-drift-ppm`,
  `--clock-offset-us`) so the daemon's clock mapping has something to find.
- **Tracker and marker** (hall): the tracker stands `tracker_distance_m` (2.5 m) in front
  of the pilot's start point (south of it, facing north), its centre `tracker_height_m`
  (1.8 m) above the floor, level (its y axis down, as the flight-table builder's indoor
  height assumes). The marker sits under the fuselage at `marker_position_body_m`,
  turned (`marker_mount_quat_wxyz`, marker -> body) so that its LED 0 looks at the
  tracker from the start point, as an operator would mount it: the LOSA's 5 % contrast
  threshold needs a lit LED within ~3 m at the marker's 50 % calibration sweep.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from hil_sim.sensors.losa import MARKER_LED_DIRECTIONS, LosaConfig

SIL_BOARDS = ("losa", "marker", "rover", "base")
HOST_FACING = ("losa", "marker", "base")  # boards with a host pty (the rover talks to the base)


def _default_baud() -> dict:
    return {"losa": 460800, "marker": 460800, "rover": 460800, "base": 921600}


def _default_drift() -> dict:
    return {"losa": 18.0, "marker": -27.0, "rover": 11.0, "base": -6.0}


def _default_offset() -> dict:
    return {"losa": 1_250_000, "marker": 40_000_000, "rover": 3_500_000, "base": 0}


@dataclass(frozen=True)
class SilRig:
    """Everything about the SIL set-up that is not the truth world (module doc)."""

    boards: tuple[str, ...] = SIL_BOARDS
    # The lockstep's delivery grid (the host reads what the boards sent at each step's
    # end). Not a divisor of the boards' schedules (20 ms RC and pilot frames, 6.67 ms INS,
    # 250 ms schema entries, 1 s heartbeats): on a 10 ms grid a board whose frames all
    # leave just after a step boundary (the base: its ticks count from its boot at t = 0)
    # reached the host a whole step late every time, and the clock fit, which takes the
    # least delay as the path's own, mapped it ~5 ms late. On 9.7 ms the phases walk, as a
    # real host's reads drift against the boards' crystals.
    step_us: int = 9_700
    host_baud: dict = field(default_factory=_default_baud)
    rover_link_baud: int = 460800  # the base's XBee port to the rover
    xbee_latency_us: int = 5_000
    clock_drift_ppm: dict = field(default_factory=_default_drift)
    clock_offset_us: dict = field(default_factory=_default_offset)
    tracker_position_ned_m: tuple[float, float, float] = (-3.5, 0.0, -1.5)
    tracker_heading_deg: float = 0.0
    tracker_tilt_deg: float = 0.0
    marker_position_body_m: tuple[float, float, float] = (0.0, 0.0, 0.25)
    marker_mount_quat_wxyz: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    losa_config: LosaConfig = field(default_factory=LosaConfig)
    line_rate_hz: float = 1000.0
    imu_rate_hz: float = 1000.0

    def __post_init__(self) -> None:
        for b in self.boards:
            if b not in SIL_BOARDS:
                raise ValueError(f"boards: unknown board {b!r}; expected some of "
                                 f"{', '.join(SIL_BOARDS)}")
        if not self.boards:
            raise ValueError("boards: at least one board is needed")
        if ("losa" in self.boards) != ("marker" in self.boards):
            raise ValueError("boards: the LOSA tracker and the marker fly together "
                             f"(got {', '.join(self.boards)})")
        if "base" in self.boards and "rover" not in self.boards:
            raise ValueError("boards: the base needs the rover (a flight table needs its INS)")
        if not 1000 <= self.step_us <= 50_000:
            raise ValueError(f"step_us = {self.step_us}: must be in [1000, 50000]")

    @property
    def host_boards(self) -> tuple[str, ...]:
        """Boards whose host link is a pty the daemon opens (the rover goes via the base)."""
        out = [b for b in self.boards if b in HOST_FACING]
        if "rover" in self.boards and "base" not in self.boards:
            out.append("rover")
        return tuple(out)

    @property
    def tracker_height_m(self) -> float:
        return -float(self.tracker_position_ned_m[2])

    def replace(self, **changes) -> SilRig:
        return dataclasses.replace(self, **changes)


def rig_for(scenario, boards: tuple[str, ...] | None = None, *,
            tracker_distance_m: float = 2.5, tracker_height_m: float = 1.8,
            **changes) -> SilRig:
    """The default rig of a scenario (module doc); `changes` override any field."""
    site = scenario.site.type
    if boards is None:
        boards = SIL_BOARDS if site == "hall" else ("rover", "base")
    start = np.asarray(scenario.pilot.start_m, dtype=float)
    tracker = (float(start[0]) - tracker_distance_m, float(start[1]), -tracker_height_m)
    rig = SilRig(boards=tuple(boards), tracker_position_ned_m=tracker)
    if "marker_mount_quat_wxyz" not in changes:
        yaw = math.radians(scenario.pilot.yaw_deg or 0.0)
        cg = start
        if scenario.pilot.point == "hub":
            # the script's start is the hub's; the marker is mounted on the body, from
            # the CG the pilot flies (`pilot.cg_script`)
            from hil_sim.world.pilot import cg_script
            from hil_sim.world.run import hub_offset_body_m

            cg = np.asarray(cg_script(scenario.pilot, hub_offset_body_m(scenario)).start_m,
                            dtype=float)
        changes["marker_mount_quat_wxyz"] = led_facing_mount(
            cg, yaw, np.asarray(rig.marker_position_body_m), np.asarray(tracker))
    return rig.replace(**changes)


def survey_rig(cfg, *, tracker_distance_m: float = 1.5, **changes) -> SilRig:
    """The rig of a hand-carried anemometer survey (`airwake sim run --survey`): the
    LOSA tracker and the marker only. The tracker stands `tracker_distance_m` south of
    the first station, level with it and facing north: the LOSA assumes the central slot
    of each line sensor at start (firmware/boards/losa/slots.h), which covers only about
    +-18 deg, so the survey starts straight in front of it (as the hall flight's hover
    does) and the slot tracking follows the carrier from there. The marker is the
    carrier's reference point, turned on the pole as `cfg.marker_mount_quat_wxyz` says
    (`sil_survey_config` turns its LED 0 toward the tracker)."""
    first = np.asarray(cfg.stations()[0], dtype=float)
    rig = SilRig(boards=("losa", "marker"),
                 tracker_position_ned_m=(float(first[0]) - tracker_distance_m,
                                         float(first[1]), float(first[2])),
                 marker_position_body_m=(0.0, 0.0, 0.0),
                 marker_mount_quat_wxyz=tuple(float(v) for v in cfg.marker_mount_quat_wxyz))
    return rig.replace(**changes)


def sil_survey_config(dwell_s: float = 4.0, **changes):
    """The survey `airwake sim run --survey` carries through the SIL boards: fan A's jet
    near the fan (x 0.5-2.5 m, y +-0.6 m, the marker 1.25 and 1.75 m up, the anemometer
    0.3 m above it; 50 stations), 1.5-3.8 m from the tracker (`survey_rig`), shorter
    dwells than the full survey, the pole's heading held within +-0.2 rad. The
    simulated LOSA loses a marker whose LED is > ~30 deg off its axis beyond ~3.5 m at
    full drive (docs/wind-map.md), so the SIL survey stays within that; the reference
    tracked out to 5.4 m. The anemometer stands upright facing north; the marker is
    mounted on the pole as an operator would, its LED 0 toward the tracker from the
    first station (`led_facing_mount`)."""
    from hil_sim.world.anemometer_survey import SurveyConfig, carrier_trajectory

    settings = {"x_range_m": (0.5, 2.5), "y_range_m": (-0.6, 0.6),
                "heights_d_m": (-1.25, -1.75), "dwell_s": dwell_s,
                "heading_swing_rad": 0.2, **changes}
    cfg = SurveyConfig(**settings)
    rig = survey_rig(cfg)
    start = carrier_trajectory(cfg).at(np.array([0.0]))
    mount = led_facing_mount(start.pos_ned_m[0], float(start.euler_rad[0, 2]),
                             np.zeros(3), np.asarray(rig.tracker_position_ned_m, float))
    return dataclasses.replace(cfg, marker_mount_quat_wxyz=mount)


def led_facing_mount(cg_ned_m: np.ndarray, yaw_rad: float, marker_body_m: np.ndarray,
                     target_ned_m: np.ndarray, led: int = 0) -> tuple[float, ...]:
    """Mount (marker -> body quaternion, wxyz) turning LED `led`'s axis toward a target,
    for a level helicopter at `cg_ned_m` heading `yaw_rad`: the shortest rotation taking
    the LED axis a onto the target direction u, q = normalise(1 + a.u, a x u)."""
    c, s = math.cos(yaw_rad), math.sin(yaw_rad)
    body_to_ned = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    marker = cg_ned_m + body_to_ned @ marker_body_m
    u = body_to_ned.T @ (target_ned_m - marker)
    u /= np.linalg.norm(u)
    a = MARKER_LED_DIRECTIONS[led]
    q = np.concatenate([[1.0 + a @ u], np.cross(a, u)])
    if q[0] < 1e-9:  # opposite: any half turn about an axis normal to a
        q = np.concatenate([[0.0], np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else
                                            [0.0, 1.0, 0.0])])
    return tuple(float(v) for v in q / np.linalg.norm(q))
