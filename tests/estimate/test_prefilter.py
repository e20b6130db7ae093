"""The wind estimators' front end: what it removes, what it keeps, and its errors."""

import numpy as np
import pytest
from airwake.calibrate.residuals import FlightData
from airwake.estimate.errors import WindEstimationError
from airwake.estimate.prefilter import check_settings, prefilter
from airwake.heli import load_spec
from hypothesis import given, settings
from hypothesis import strategies as st

MODEL = load_spec("table52")
FS = 150.0


def _data(t, z, p=None):
    """A FlightData with the given channels (T, 6) and roll rate p (T,)."""
    x = np.zeros((t.size, MODEL.n_states))
    if p is not None:
        x[:, MODEL.state_index("p_rad_s")] = p
    x[:, MODEL.state_index("yaw_rad")] = np.mod(0.3 * t + np.pi, 2 * np.pi) - np.pi
    env = {"rotor_speed_rad_s": np.full(t.size, 163.3), "height_agl_m": np.full(t.size, np.inf)}
    from airwake.calibrate.residuals import split_runs

    return FlightData(t, x, np.zeros((t.size, 4)), env, z, split_runs(t), float(np.median(
        np.diff(t))), np.ones(6), "test")


def test_rotor_vibration_is_removed_and_the_flight_dynamics_kept():
    # 1/rev and 2/rev of a 163 rad/s rotor are 26 and 52 Hz: gone; a 1 Hz motion stays
    # with its amplitude and without phase lag (zero-phase filtering)
    t = np.arange(0, 20, 1 / FS)
    slow = 0.3 * np.sin(2 * np.pi * 1.0 * t)
    vib = 0.5 * np.sin(2 * np.pi * 26.0 * t) + 0.8 * np.sin(2 * np.pi * 52.0 * t + 0.4)
    z = np.column_stack([slow + vib] * 6)
    pre = prefilter(_data(t, z, p=slow + 0.2 * vib), MODEL, 6.0, 15.0)
    inner = (pre.data.t > 2) & (pre.data.t < 18)
    want = 0.3 * np.sin(2 * np.pi * pre.data.t[inner])
    for j in range(6):
        assert np.max(np.abs(pre.data.z[inner, j] - want)) < 0.01
    p = pre.data.x[inner, MODEL.state_index("p_rad_s")]
    assert np.max(np.abs(p - want)) < 0.01
    assert pre.factor == 10 and pre.rate_hz == pytest.approx(15.0)


def test_midpoint_inputs_lie_half_way_and_yaw_is_filtered_unwrapped():
    t = np.arange(0, 10, 1 / FS)
    p = 0.2 * t  # a ramp: the filtered value half-way is the ramp there
    pre = prefilter(_data(t, np.zeros((t.size, 6)), p=p), MODEL, 6.0, 15.0)
    i = MODEL.state_index("p_rad_s")
    inner = (pre.data.t > 1) & (pre.data.t < 9)
    np.testing.assert_allclose(pre.mid_x[inner, i], 0.2 * (pre.data.t[inner] - 0.5 / 15.0),
                               atol=1e-3)
    yaw = pre.data.x[:, MODEL.state_index("yaw_rad")]
    assert np.all(np.abs(np.diff(yaw)) < 0.1)  # no 2 pi jumps smeared by the filter


def test_each_run_is_filtered_on_its_own_and_short_runs_are_left_out():
    t = np.concatenate([np.arange(0, 5, 1 / FS), np.arange(10, 10.5, 1 / FS),
                        np.arange(20, 26, 1 / FS)])
    z = np.zeros((t.size, 6))
    z[t >= 20] = 1.0  # a step between runs must not leak across the gap
    pre = prefilter(_data(t, z), MODEL, 6.0, 15.0)
    assert len(pre.data.runs) == 2  # the 0.5 s run is too short
    first = pre.data.runs[0]
    assert np.allclose(pre.data.z[first], 0.0, atol=1e-12)
    assert pre.data.t[pre.data.runs[1]][0] == pytest.approx(20.0)


@pytest.mark.parametrize("cutoff,rate,match", [
    (7.0, 15.0, "--cutoff-hz 7: must be at most rate / 2.5"),
    (20.0, 75.0, "below half the rotor's 1/rev"),
    (6.0, 300.0, "--rate-hz 300: above the flight's own rate"),
    (0.0, 15.0, "--cutoff-hz 0.0: must be a positive number"),
])
def test_settings_that_cannot_work_are_refused_with_the_option_named(cutoff, rate, match):
    with pytest.raises(WindEstimationError, match=match.replace("(", r"\(").replace(
            ")", r"\)")):
        check_settings(cutoff, rate, FS, 163.3)


@settings(max_examples=200, deadline=None)
@given(cutoff=st.floats(0.1, 80.0), rate=st.floats(1.0, 400.0), fs=st.floats(20.0, 400.0),
       omega=st.floats(50.0, 400.0))
def test_accepted_settings_never_alias_and_stay_below_the_rotor(cutoff, rate, fs, omega):
    try:
        d = check_settings(cutoff, rate, fs, omega)
    except WindEstimationError:
        return
    actual = fs / d
    assert d >= 1 and cutoff <= actual / 2.5 * 1.01 and cutoff <= 0.5 * omega / (2 * np.pi)
