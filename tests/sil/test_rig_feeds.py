"""The SIL rig and feeds: geometry, UART timing, the LOSA lines' LED timing, the clock."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from hil_sim.boards.feeds import LosaLineFeed, UartFeed, tracker_axes_ned
from hil_sim.boards.rig import SilRig, led_facing_mount, rig_for
from hil_sim.boards.simclock import SimClock
from hil_sim.sensors.losa import MARKER_LED_DIRECTIONS, LosaOptics
from hil_sim.sensors.streams import ByteStream
from hil_sim.world.kinematics import quat_multiply, quat_to_dcm, rotate
from hil_sim.world.scenario import load_scenario


@pytest.mark.parametrize("heading,tilt", [(0, 0), (90, 0), (-30, 15), (200, -10)])
def test_tracker_frame_is_right_handed_x_right_y_down_z_forward(heading, tilt):
    # the LOSA geometry assumes x right, y down, z out of the face (x cross y = z)
    r = tracker_axes_ned(heading, tilt)
    assert np.allclose(r @ r.T, np.eye(3)) and np.isclose(np.linalg.det(r), 1.0)
    assert np.allclose(np.cross(r[0], r[1]), r[2])
    if tilt == 0:
        assert np.allclose(r[1], [0, 0, 1])  # level: y is down
    psi = np.radians(heading)
    assert np.allclose(r[2][:2] / np.linalg.norm(r[2][:2]), [np.cos(psi), np.sin(psi)])


def test_marker_mount_turns_led0_toward_the_tracker():
    # an LED facing the tracker gives the LOSA its contrast during calibration
    cg = np.array([0.0, 0.0, -2.5])
    tracker = np.array([-2.5, 0.3, -1.8])
    r_marker = np.array([0.0, 0.0, 0.25])
    for yaw in (0.0, 1.0, -2.5):
        q = np.array(led_facing_mount(cg, yaw, r_marker, tracker))
        c, s = np.cos(yaw), np.sin(yaw)
        body_to_ned = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
        axis = body_to_ned @ rotate(q[None], MARKER_LED_DIRECTIONS[0])[0]
        want = tracker - (cg + body_to_ned @ r_marker)
        assert np.allclose(axis, want / np.linalg.norm(want), atol=1e-9)


def test_a_hub_script_aims_the_marker_from_the_cg_the_pilot_flies(tmp_path):
    # the script's start is the hub's, 0.24 m above the blade-element airframe's CG: the
    # marker's LED is turned toward the tracker from where the body is, not from the hub
    import dataclasses

    from hil_sim.world.run import hub_offset_body_m

    sc = load_scenario("still_air_calibration")
    hub = dataclasses.replace(sc, pilot=dataclasses.replace(sc.pilot, point="hub"))
    off = hub_offset_body_m(hub)
    assert off[2] < -0.1
    rig, rig_hub = rig_for(sc), rig_for(hub)
    assert rig_hub.tracker_position_ned_m == rig.tracker_position_ned_m
    start = np.asarray(sc.pilot.start_m, float)
    yaw = np.radians(sc.pilot.yaw_deg or 0.0)
    want = led_facing_mount(start - [0.0, 0.0, off[2]], yaw,
                            np.asarray(rig.marker_position_body_m),
                            np.asarray(rig.tracker_position_ned_m))
    assert np.allclose(rig_hub.marker_mount_quat_wxyz, want, atol=1e-12)
    # a CG script's mount is aimed from its start as it was
    assert np.allclose(rig.marker_mount_quat_wxyz, led_facing_mount(
        start, yaw, np.asarray(rig.marker_position_body_m),
        np.asarray(rig.tracker_position_ned_m)), atol=1e-12)
    assert not np.allclose(rig.marker_mount_quat_wxyz, rig_hub.marker_mount_quat_wxyz)


def test_rig_defaults_by_site_and_bad_board_sets():
    assert rig_for(load_scenario("still_air_calibration")).boards == (
        "losa", "marker", "rover", "base")
    ship = rig_for(load_scenario("ship_airwake_b0"))
    assert ship.boards == ("rover", "base") and ship.host_boards == ("base",)
    assert SilRig(boards=("rover",)).host_boards == ("rover",)
    for bad in (("losa", "rover", "base"), ("base",), ("plane",), ()):
        with pytest.raises(ValueError):
            SilRig(boards=bad)


def test_marker_attitude_in_the_tracker_frame_composes_the_rotations():
    # q(marker -> tracker) = q(NED -> tracker) * q(body -> NED): rotate == matrix product
    from hil_sim.world.kinematics import dcm_to_quat, euler_to_quat

    r_tn = tracker_axes_ned(25.0, 5.0)
    q_bn = euler_to_quat(np.array([0.1, -0.2, 0.7]))
    q = quat_multiply(dcm_to_quat(r_tn), q_bn)
    v = np.array([0.3, -0.5, 0.8])
    assert np.allclose(rotate(q[None], v)[0], r_tn @ quat_to_dcm(q_bn) @ v)


class _Recorder:
    """A stand-in board that keeps what would be queued."""

    def __init__(self):
        self.uarts, self.got_lines = [], []

    def uart(self, t, port, data):
        self.uarts.append((t, port, data))

    def lines(self, t_us, rate, dark):
        self.got_lines.extend((int(t), rate[k], dark[k]) for k, t in enumerate(t_us))


def test_uart_bytes_arrive_at_line_rate_first_byte_alone():
    # a 88-byte packet at 921600 baud: its first byte after 10.85 us, the rest when its
    # last byte is in (0.955 ms): the parser stamps at first byte or completion, not early
    packet = bytes(range(88))
    stream = ByteStream.from_chunks([0.010, 0.020], [packet, packet[:40]], 921600)
    feed = UartFeed("ins", stream, 921600)
    rec = _Recorder()
    feed.queue(rec, 0, 15_000)
    assert [(t, len(d)) for t, _, d in rec.uarts] == [(10_011, 1), (10_955, 87)]
    assert b"".join(d for _, _, d in rec.uarts) == packet
    slow = UartFeed("rtk", ByteStream.from_chunks([0.0], [bytes(40)], 115200), 115200)
    rec = _Recorder()
    slow.queue(rec, 0, 10_000)
    sizes = [len(d) for _, _, d in rec.uarts]
    assert sizes[0] == 1 and max(sizes) <= 11 and sum(sizes) == 40  # <= ~1 ms of line
    assert rec.uarts[-1][0] == int(np.ceil(40 * 10 / 115200 * 1e6))


def test_losa_sees_an_led_change_at_the_instant_the_marker_made_it():
    # lines are computed ahead for the LED state of the moment; a PWM change inside a
    # step recomputes them from that instant: the LOSA sees no delay, no stale light
    t = np.arange(0, 1.0, 1e-3)
    pos = np.tile([0.0, -0.4, 2.5], (t.size, 1))
    quat = np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))
    feed = LosaLineFeed(LosaOptics(rng=np.random.default_rng(0)), t, pos, quat, 1000.0)
    rec = _Recorder()
    feed.queue(rec, 0, 10_000)  # LED off
    feed.led_events([(13_500, "led2", 40000)])
    feed.queue(rec, 10_000, 20_000)
    feed.led_events([(24_000, "led2", 0)])
    feed.queue(rec, 20_000, 30_000)
    times = [x[0] for x in rec.got_lines]
    assert times == sorted(times) and 13_500 in times and 24_000 in times
    assert set(range(0, 30_000, 1000)) <= set(times)
    peak = {tt: float(r.max()) for tt, r, _ in rec.got_lines}
    lit = [tt for tt in times if peak[tt] > 10 * peak[0]]
    assert lit[0] == 13_500 and lit[-1] < 24_000 and peak[24_000] < 2 * peak[0]


def test_losa_lines_prefetched_during_the_daemon_pass_still_see_led_changes():
    # the stepped SIL computes the next step's lines while the daemon reads the last one
    # (for the LED state of that moment); a change in the step recomputes from its instant
    t = np.arange(0, 1.0, 1e-3)
    pos = np.tile([0.0, -0.4, 2.5], (t.size, 1))
    quat = np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))
    runs = {}
    for prefetch in (False, True):
        feed = LosaLineFeed(LosaOptics(rng=np.random.default_rng(0)), t, pos, quat, 1000.0)
        rec = _Recorder()
        events = {10_000: (13_500, "led2", 40000), 20_000: (24_000, "led2", 0)}
        for t0 in range(0, 60_000, 10_000):
            if prefetch:
                feed.prefetch(t0 + 10_000)
            if t0 in events:
                feed.led_events([events[t0]])
            feed.queue(rec, t0, t0 + 10_000)
        peak = {tt: float(r.max()) for tt, r, _ in rec.got_lines}
        runs[prefetch] = ([x[0] for x in rec.got_lines],
                          [tt for tt in peak if peak[tt] > 10 * peak[0]])
    assert runs[True] == runs[False]
    times, lit = runs[True]
    assert lit[0] == 13_500 and lit[-1] < 24_000 and set(range(0, 60_000, 1000)) <= set(times)


def test_shared_clock_follows_holds_and_never_goes_back(tmp_path):
    # the daemon's monotonic clock: wall-paced before/after the flight, simulator time
    # during it, continuous across the switches, read in another process
    clock = SimClock(tmp_path / "clock")
    a = clock.now_ns()
    held = clock.hold()
    assert held >= a
    clock.set(held + 5_000_000_000)
    clock.set(held + 1_000)  # never backwards
    code = ("import time, sys; from hil_sim.boards.simclock import install; "
            "install(sys.argv[1]); print(time.monotonic_ns(), time.monotonic())")
    out = subprocess.run([sys.executable, "-c", code, str(tmp_path / "clock")],
                         capture_output=True, text=True, check=True).stdout.split()
    assert int(out[0]) == held + 5_000_000_000
    assert abs(float(out[1]) - (held + 5_000_000_000) / 1e9) < 1e-6
    clock.follow()
    b = clock.now_ns()
    assert b >= held + 5_000_000_000
    clock.close()
