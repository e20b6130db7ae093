"""The chain from the discrepancy workflow's output to the wind holds on every model the
workflow can produce (issue 20, item 2).

`airwake model add` can give the model states that nothing uncertain reaches (a servo
lag's blade pitch follows the recorded commands alone) and states much faster than the
smoother's 15 Hz step. Before: the RTS gain divided by their zero variance and the wind
estimate ended in "sigma must be 6 positive numbers, got [nan ...]"; the step held the
inputs at its midpoint, so a 2 ms servo lagged by half a step (33 ms); and the added
spec had no `[calibration] model_error_std`, so the smoother's noise floor was gone.

Flights here are made by the model's own equations (`airwake.calibrate.synthetic`): this
is plumbing and numerics, not an accuracy figure.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from airwake.calibrate import model_error_std
from airwake.calibrate.residuals import FlightData
from airwake.calibrate.synthetic import WindProfile, generate_flight
from airwake.cli import main
from airwake.discrepancy.candidates import CANDIDATES, effect_with
from airwake.estimate.prefilter import prefilter
from airwake.estimate.smoother import WindSmoother, _smoother_gain
from airwake.estimate.wind import estimate_wind, model_error_floor
from airwake.estimate.wind_prior import WindPrior
from airwake.heli import load_model, spec_calibration
from airwake.record.flight_table import write_flight_table
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.linalg import expm

WIND = (2.0, -1.0, 0.5, 0.1, -0.05, 0.08)  # the wind of `constant_wind_flight` (conftest)


@pytest.fixture(scope="module")
def windy(constant_wind_flight):
    return constant_wind_flight


@pytest.fixture(scope="module")
def base_estimate(windy):
    return estimate_wind(windy, "table52", em_passes=2)


# -- the smoother's numerics ------------------------------------------------------------
@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), live=st.integers(2, 10), dead=st.integers(0, 4),
       log_scale=st.floats(-9, 1))
def test_smoother_gain_solves_the_live_states_and_leaves_the_dead_ones(seed, live, dead,
                                                                        log_scale):
    rng = np.random.default_rng(seed)
    n = live + dead
    a = rng.normal(size=(live, live))
    scale = 10.0 ** rng.uniform(log_scale, 1.0, live)  # variances over many decades
    block = (a @ a.T + 0.1 * np.eye(live)) * np.outer(scale, scale)
    order = rng.permutation(n)
    pred = np.zeros((n, n))
    alive = np.sort(order[:live])
    pred[np.ix_(alive, alive)] = block
    cross = rng.normal(size=(n, n))
    g = _smoother_gain(cross, pred)
    assert np.all(np.isfinite(g))
    expect = np.linalg.solve(block, cross[:, alive].T).T
    np.testing.assert_allclose(g[:, alive], expect, rtol=1e-6,
                               atol=1e-9 * np.abs(expect).max())
    dead_idx = np.setdiff1d(np.arange(n), alive)
    assert np.all(g[:, dead_idx] == 0.0)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), tau=st.floats(1e-3, 1.0),
       g1=st.floats(-50, 50), g2=st.floats(-500, 500), dt=st.floats(0.005, 0.2))
def test_the_step_integrates_a_forcing_that_moves_over_it(seed, tau, g1, g2, dt):
    """Mean step == the ODE d' = A d + F + G1 (r - dt/2) + G2 (r - dt/2)^2 integrated
    over [0, dt] (the inputs held to second order over the step)."""
    rng = np.random.default_rng(seed)
    sm = WindSmoother.__new__(WindSmoother)
    sm.m, sm.n_state = 2, 14
    a = np.zeros((14, 14))
    a[:2, :2] = [[-1.0 / tau, 3.0], [0.0, -2.0]]
    a[:2, 2:8] = rng.normal(size=(2, 6))
    a[2:, 2:] = -0.5 * np.eye(12)
    drift = rng.normal(size=14)
    ramp = (np.array([g1, -0.3 * g1]), np.array([g2, 0.1 * g2]))
    phi, _, step = sm._discretise(a, drift, np.zeros(14), dt, ramp)
    h = 0.5 * dt

    def rhs(t, x):
        f = a @ x + drift
        f[:2] += ramp[0] * (t - h) + ramp[1] * (t - h) ** 2
        return f

    sol = solve_ivp(rhs, (0.0, dt), np.zeros(14), method="Radau", rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(step, sol.y[:, -1], rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(phi, expm(a * dt), rtol=1e-9, atol=1e-12)


# -- every model the workflow can produce -------------------------------------------------
@pytest.mark.parametrize("effect", [c.name for c in CANDIDATES])
def test_every_catalogue_effect_added_runs_through_the_smoother(windy, base_estimate,
                                                                effect):
    model = load_model("table52") + effect_with(effect, {})
    est = estimate_wind(windy, model, em_passes=2)
    values = est.df[[c for c in est.df.columns if c.startswith("wind_")]].to_numpy()
    assert np.all(np.isfinite(values)), effect
    # the learned channel noise stays the model's misfit, not a diverged filter's
    base = np.asarray(base_estimate.metadata["noise_std"])
    assert np.all(np.asarray(est.metadata["noise_std"]) <= 1.5 * base + 1e-3), effect
    mean_v = est.df[["wind_vx_m_s", "wind_vy_m_s", "wind_vz_m_s"]].to_numpy().mean(0)
    np.testing.assert_allclose(mean_v, WIND[:3], atol=0.15, err_msg=effect)


def _open_loop(model, flight, rate_hz):
    data = FlightData.from_flight(model, flight)
    pre = prefilter(data, model, 6.0, rate_hz)
    sm = WindSmoother(model, pre, WindPrior.from_physics(0.673, 3.0), iterations=1)
    z = sm.open_loop(np.tile(np.asarray(WIND), (pre.data.t.size, 1)))
    return z, pre.data.z


def test_the_step_integrates_the_model_as_a_fine_step_does(windy):
    """The model's open-loop prediction at the smoother's 15 Hz step is as good as at a
    75 Hz step, for the base model and with a 2 ms servo (the catalogue's fastest): the
    step holds the body motion and inputs to second order, so the flapping and a servo
    faster than the step follow them to the sample. (A midpoint hold: the base model's
    roll acceleration 1.58 rad/s^2 RMS off at 15 Hz against 0.14 at 75 Hz, and the servo
    model 0.30 m/s^2 off the base one in a_z, 0.07 at 75 Hz.)"""
    base = load_model("table52")
    servo = base + effect_with("servo_lag", {"tau_swash_s": 0.002, "tau_tail_s": 0.002})
    pred = {(name, rate): _open_loop(model, windy, rate) for name, model in
            (("base", base), ("servo", servo)) for rate in (15.0, 75.0)}
    rms = {key: np.sqrt(np.mean((z - meas) ** 2, axis=0)) for key, (z, meas) in pred.items()}
    for name in ("base", "servo"):
        assert np.all(rms[name, 15.0] <= 1.4 * rms[name, 75.0] + 0.01), (name, rms)
    for rate in (15.0, 75.0):
        gap = np.sqrt(np.mean((pred["servo", rate][0] - pred["base", rate][0]) ** 2, axis=0))
        # what a 2 ms lag really changes (mostly the roll acceleration), at either step
        assert np.all(gap[:3] < 0.05) and np.all(gap < 0.2), (rate, gap)


def test_model_add_writes_the_floor_of_the_model_it_makes_and_the_wind_uses_it(
        tmp_path, capsys):
    lagged = load_model("table52") + effect_with("servo_lag", {"tau_swash_s": 0.03,
                                                               "tau_tail_s": 0.02})
    still = tmp_path / "still.parquet"
    fl = generate_flight(lagged, duration_s=12.0, seed=11, substeps=2)
    write_flight_table(fl.df, still, fl.metadata)
    windy_path = tmp_path / "windy.parquet"
    fw = generate_flight(lagged, duration_s=8.0, seed=12, substeps=2,
                         wind=WindProfile.constant(WIND))
    write_flight_table(fw.df, windy_path, fw.metadata)

    first = tmp_path / "servo.toml"
    assert main(["model", "add", "servo_lag", "--data", str(still), "--model", "table52",
                 "--out", str(first), "--max-nfev", "8", "--quiet"]) == 0
    cal = spec_calibration(first)
    assert cal["added_effects"] == ["servo_lag"]
    np.testing.assert_allclose(model_error_floor(first), model_error_std(first, still),
                               rtol=1e-12)
    # a second step on top of the first keeps the history and re-measures the floor
    second = tmp_path / "servo_droop.toml"
    assert main(["model", "add", "rotor_droop", "--data", str(still), "--model",
                 str(first), "--out", str(second), "--max-nfev", "4", "--quiet"]) == 0
    assert spec_calibration(second)["added_effects"] == ["servo_lag", "rotor_droop"]
    capsys.readouterr()
    for spec in (first, second):
        out = tmp_path / f"{spec.stem}.wind.parquet"
        assert main(["wind", "estimate", str(windy_path), "--model", str(spec), "--out",
                     str(out), "--json"]) == 0
        report = json.loads(capsys.readouterr().out)
        floor = model_error_floor(spec)
        assert np.all(np.asarray(report["noise_std"]) >= floor - 1e-12)
        assert np.all(np.isfinite(np.asarray(report["prior"]["sigma"])))
