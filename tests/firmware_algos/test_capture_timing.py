"""PWM capture (base/pwm_capture.c) and rotor speed (rover/rotor_speed.c) timing."""

import ctypes as C

import awboards as A
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

U32 = 2**32


class Channel:
    def __init__(self, lib):
        self.lib = lib
        self.cfg = lib.pwm_capture_default_cfg()
        self.ch = A.PwmChannel()
        lib.pwm_channel_init(C.byref(self.ch))

    def edge(self, t, level):
        self.lib.pwm_channel_edge(C.byref(self.ch), C.byref(self.cfg), t % U32, level)

    def get(self, now):
        out = A.PwmChannelOut()
        self.lib.pwm_channel_get(C.byref(self.ch), C.byref(self.cfg), now % U32, C.byref(out))
        return out


@settings(max_examples=200, deadline=None)
@given(
    t0=st.integers(0, U32 - 1),
    period=st.integers(10_000, 22_222),  # RC frames at 45..100 Hz
    start=st.integers(1000, 2000),
    moves=st.lists(st.integers(-200, 200), min_size=2, max_size=40),
)
def test_pwm_widths_and_rate_exact_for_any_stick_motion(lib, t0, period, start, moves):
    # Why: pilot inputs feed the pilot-compensation nets; each frame's width must be the
    # exact pulse, also across the 32-bit timer wrap.
    ch = Channel(lib)
    width = start
    t = t0
    for move in moves:
        width = int(np.clip(width + move, 1000, 2000))
        ch.edge(t, 1)
        ch.edge(t + width, 0)
        out = ch.get(t + width + 10)
        assert out.valid and out.width_us == width
        t += period
    assert out.period_us == period and out.glitches == 0


@settings(max_examples=200, deadline=None)
@given(
    t0=st.integers(0, U32 - 1),
    widths=st.lists(st.integers(1000, 1100), min_size=8, max_size=30),
    spike=st.integers(2, 6),
    bad=st.one_of(st.integers(0, 900), st.integers(2100, 5000), st.integers(1500, 2000)),
)
def test_pwm_single_glitch_never_reaches_output(lib, t0, widths, spike, bad):
    # Why: one bad pulse (noise, a short spike, a far outlier) must not twitch the
    # recorded stick.
    ch = Channel(lib)
    t = t0
    seen = []
    for i, w in enumerate(widths):
        w_now = bad if i == spike else w
        ch.edge(t, 1)
        ch.edge(t + w_now, 0)
        seen.append(ch.get(t + 3000).width_us)
        t += 20_000
    assert bad not in seen[spike : spike + 1] or bad in widths
    assert all(1000 <= s <= 1100 for s in seen)
    assert ch.get(t).glitches >= 1


@settings(max_examples=150, deadline=None)
@given(
    omega=st.floats(50.0, 300.0),  # flight and spool-up; below, misses look like a stop
    t0=st.integers(0, U32 - 1),
    jitter=st.floats(0.0, 20.0),
    miss=st.floats(0.0, 0.1),
    seed=st.integers(0, 2**31),
)
def test_rotor_speed_within_half_percent(lib, omega, t0, jitter, miss, seed):
    # Why: rotor speed enters the helicopter model's thrust (Omega^2): 0.5 % is 1 %.
    rng = np.random.default_rng(seed)
    cfg = lib.rotor_speed_default_cfg()
    rs = A.RotorSpeed()
    lib.rotor_speed_init(C.byref(rs))
    half = np.pi / omega * 1e6
    n = 60
    times = t0 + half * np.arange(n) + rng.normal(0.0, jitter, n)
    keep = rng.random(n) >= miss
    keep[:4] = True  # the estimator needs a start; later misses are what is tested
    keep[-1] = True
    keep[1:] |= ~keep[:-1]  # single misses (a double one spans 3 half revolutions)
    for t in times[keep]:
        lib.rotor_speed_pulse(C.byref(rs), C.byref(cfg), int(round(t)) % U32)
    out = A.RotorSpeedOut()
    lib.rotor_speed_get(C.byref(rs), C.byref(cfg), int(round(times[-1])) % U32, C.byref(out))
    assert out.valid
    assert abs(out.speed_rad_s - omega) <= 0.005 * omega + 2 * jitter / half * omega
    assert out.missed == np.count_nonzero(~keep)
