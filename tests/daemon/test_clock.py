"""Clock mapping: synthetic board clocks with known offset, drift, jitter and outliers."""

from __future__ import annotations

import numpy as np
from airwake.link.clock import WRAP, BoardClock, fit_envelope, fit_piecewise, lower_hull
from airwake.link.messages import HEARTBEAT, IMU, SCHEMA_ENTRY, Heartbeat
from clock_sim import SimClock, feed
from hypothesis import given, settings
from hypothesis import strategies as st


@settings(max_examples=20, deadline=None)
@given(offset_s=st.floats(-9e3, 1e5), drift_ppm=st.floats(-100, 100),
       d0_us=st.floats(50, 3000), scale_us=st.floats(10, 5000), seed=st.integers(0, 2**16))
def test_two_sided_mapping_error_within_its_bound(offset_s, drift_ppm, d0_us, scale_us, seed):
    # the recording's host times are only as good as this: error <= the envelope bound
    rng = np.random.default_rng(seed)
    sim = SimClock(host0_us=1e10 + offset_s * 1e6, board0_us=2e6, drift_ppm=drift_ppm,
                   d0_us=d0_us, scale_us=scale_us)
    clock = BoardClock()
    out = feed(clock, sim, rng, 60.0)
    err = out[:, 2] - out[:, 1]
    fit = clock.ep.fit
    assert fit.two_sided
    # the live bound holds at the window's centre; the newest frames are extrapolated
    # from it with a slope known to (bin-minimum spread) / window, hence the margin
    assert np.all(np.abs(err) <= out[:, 3] + 50.0 + 0.1 * scale_us)
    assert abs(fit.drift_ppm - drift_ppm) < 2.0 + 0.002 * scale_us
    assert len(clock.epochs) == 1


def test_one_sided_mapping_is_late_by_about_the_minimum_delay():
    # without time-sync replies only the lower envelope exists: biased by d0, documented
    rng = np.random.default_rng(2)
    sim = SimClock(drift_ppm=50.0, d0_us=400.0, scale_us=1000.0)
    clock = BoardClock()
    out = feed(clock, sim, rng, 60.0, with_sync=False)
    err = out[:, 2] - out[:, 1]
    assert 380.0 < np.median(err) < 450.0
    assert not clock.ep.fit.two_sided and abs(clock.ep.fit.drift_ppm - 50.0) < 3.0


def test_unwraps_across_the_32_bit_wrap():
    # a board up for 71.6 min wraps its frame clock; the timeline must not jump
    rng = np.random.default_rng(3)
    sim = SimClock(board0_us=WRAP - 25e6, drift_ppm=-30.0)
    clock = BoardClock()
    out = feed(clock, sim, rng, 60.0)
    assert len(clock.epochs) == 1 and out[:, 0].max() > WRAP
    assert np.max(np.abs(out[:, 2] - out[:, 1])) < 1000.0


def test_heartbeat_uptime_anchors_a_board_up_for_hours():
    # joining a board that has run 3 h: the wrap count comes from uptime_ms
    clock = BoardClock()
    board = int(3 * 3600e6) + 12345
    hb = Heartbeat(board_id=1, uptime_ms=board // 1000, boot_count=7)
    clock.heartbeat(hb, board % WRAP, 1e9)
    _, unwrapped, _ = clock.frame(HEARTBEAT.id, board % WRAP, 1e9)
    assert unwrapped == board and clock.ep.boot_count == 7


def test_board_reset_starts_a_new_epoch_and_keeps_the_old_mapping():
    # a rebooted board restarts its clock: old data keeps its mapping, new data gets one
    rng = np.random.default_rng(4)
    first = SimClock(host0_us=1e10, board0_us=5e8, drift_ppm=20.0)
    clock = BoardClock()
    out1 = feed(clock, first, rng, 40.0, boot_count=3)
    old = clock.ep
    second = SimClock(host0_us=1e10 + 41e6, board0_us=1000.0, drift_ppm=20.0)
    out2 = feed(clock, second, rng, 40.0, boot_count=4)
    assert len(clock.epochs) == 2 and clock.ep.boot_count == 4
    assert "boot count 3 -> 4" in clock.ep.reason
    late = out2[out2[:, 1] > 1e10 + 61e6]
    assert np.max(np.abs(late[:, 2] - late[:, 1])) < 1000.0
    b = out1[-1, 0]
    assert abs(clock.map(old, b) - first.host(b)) < 1000.0


def test_reset_without_heartbeat_detected_from_clock_frames():
    clock = BoardClock()
    for k in range(20):
        clock.frame(SCHEMA_ENTRY.id, 9_000_000 + k * 250_000, 1e9 + k * 250_000)
    clock.frame(IMU.id, 5_000, 1e9 + 20 * 250_000)  # data frame: no new epoch from it
    assert len(clock.epochs) == 1
    clock.frame(SCHEMA_ENTRY.id, 6_000, 1e9 + 20 * 250_000 + 10)
    assert len(clock.epochs) == 2 and "went back" in clock.ep.reason


def test_stale_data_stamp_does_not_break_the_unwrapping():
    # rotor_speed keeps the time of its last pulse when the rotor stops
    clock = BoardClock()
    clock.frame(SCHEMA_ENTRY.id, 100_000_000, 1e9)
    _, b, _ = clock.frame(0x46, 40_000_000, 1e9 + 1e3)
    assert b == 40_000_000 and len(clock.epochs) == 1
    _, b, _ = clock.frame(SCHEMA_ENTRY.id, 100_250_000, 1e9 + 250_000)
    assert b == 100_250_000


def test_piecewise_refit_tracks_a_changing_drift():
    # temperature changes a crystal's rate during a flight; the export refits per window
    rng = np.random.default_rng(5)
    clock = BoardClock(keep_all=True)
    sim = SimClock(drift_ppm=-80.0, scale_us=500.0)
    feed(clock, sim, rng, 120.0)
    pw = fit_piecewise(*clock.ep.points())
    b = np.linspace(sim.board(sim.host0_us + 5e6), sim.board(sim.host0_us + 115e6), 50)
    assert np.max(np.abs(pw.to_host(b) - sim.host(b))) < 100.0


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.integers(-1000, 1000), st.integers(-1000, 1000)), min_size=1,
                max_size=40))
def test_lower_hull_lies_under_every_point(points):
    pts = sorted(set(points))
    x = np.array([p[0] for p in pts], float)
    y = np.array([p[1] for p in pts], float)
    hx, hy = lower_hull(x, y)
    assert hx.size >= 1 and np.all(np.diff(hx) > 0)
    if hx.size >= 2:
        under = np.interp(x, hx, hy)
        assert np.all(y >= under - 1e-9)


def test_envelope_ignores_late_outliers():
    x = np.arange(0, 60e6, 1e6)
    z = 1000.0 + 1e-4 * x
    z[::7] += 3e5  # stalls: frames received late
    fit = fit_envelope(x, z)
    np.testing.assert_allclose(fit.line.rate, 1 + 1e-4, rtol=0, atol=1e-12)
    assert abs(float(fit.line.to_host(30e6)) - (30e6 + 1000.0 + 3000.0)) < 1e-6


def test_live_clock_memory_stays_bounded():
    # a daemon runs for hours: the live fit keeps only its trailing window of bins
    clock = BoardClock(window_s=20.0)
    feed(clock, SimClock(), np.random.default_rng(6), 120.0)
    ep = clock.ep
    assert len(ep.up) <= 22 and len(ep.down) <= 22 and len(ep.order) <= 3 * 22
