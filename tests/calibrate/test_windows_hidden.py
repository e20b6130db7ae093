"""Windowed one-step-ahead prediction: rotor states per row, windows tiling the flight."""

import numpy as np
import pytest
from airwake.calibrate.errors import CalibrationError
from airwake.calibrate.hidden import HiddenPropagator, etd2_matrices
from airwake.calibrate.residuals import (
    FlightData,
    WindowedPredictor,
    make_windows,
    noise_scale,
)
from airwake.heli import MEAS_CHANNELS, load_spec
from airwake.heli.measurement import predict_measurements
from scipy.linalg import expm


@pytest.fixture(scope="module")
def model():
    return load_spec("table52")


def test_etd_matrices_integrate_a_linear_system_with_a_linear_forcing_exactly():
    # the step the rotor states ride on: exact for dh/dt = A h + a + b t
    rng = np.random.default_rng(0)
    a = rng.normal(size=(3, 3)) - 3 * np.eye(3)
    dt = 0.05
    e, phi1, phi2 = etd2_matrices(a[None], dt)
    h0, f0, f1 = rng.normal(size=(3, 3))
    # reference: augmented state [h, forcing, slope] through expm
    big = np.zeros((9, 9))
    big[:3, :3], big[:3, 3:6], big[3:6, 6:] = a, np.eye(3), np.eye(3)
    ref = (expm(big * dt) @ np.concatenate([h0, f0, (f1 - f0) / dt]))[:3]
    got = e[0] @ h0 + phi1[0] @ f0 + phi2[0] @ (f1 - f0)
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(e[0], expm(a * dt), rtol=1e-12)


def test_windowed_prediction_matches_the_whole_flight_measurement_model(model, short_flight):
    # two independent solutions of the same rotor dynamics must agree far below sensor
    # noise, or calibration would fit our integrator instead of the helicopter
    data = FlightData.from_flight(model, short_flight)
    win = make_windows(data)
    z, valid = WindowedPredictor(model, data, win).predict(model.parameter_vector()[None])
    assert valid.all()
    ref = predict_measurements(model, short_flight.df)[win.idx][win.score]
    truth = short_flight.df[[f"truth_{c}" for c in MEAS_CHANNELS]].to_numpy()[win.idx][win.score]
    got = z[0][win.score]
    assert np.all(np.sqrt(np.mean((got - ref) ** 2, axis=0)) < [1e-3] * 3 + [0.01] * 3)
    assert np.all(np.sqrt(np.mean((got - truth) ** 2, axis=0)) < [1e-3] * 3 + [0.01] * 3)


def test_parameter_sets_batch_equals_one_at_a_time(model, short_flight):
    data = FlightData.from_flight(model, short_flight)
    pred = WindowedPredictor(model, data, make_windows(data, 1.0, 0.5))
    base = model.parameter_vector()
    other = model.with_parameters({"main_rotor.flap_stiffness_nm_rad": 200.0,
                                   "rigid_body.Ixx_kg_m2": 0.3}).parameter_vector()
    both, _ = pred.predict(np.stack([base, other]))
    one, _ = pred.predict(other[None])
    np.testing.assert_allclose(both[1], one[0], rtol=1e-9, atol=1e-9)
    assert not np.allclose(both[0], both[1])


def test_windows_score_every_sample_once_except_each_runs_warmup(model, still_air_flight):
    data = FlightData.from_flight(model, still_air_flight)
    win = make_windows(data, window_s=2.0, warmup_s=1.0)
    scored = win.idx[win.score]
    assert np.unique(scored).size == scored.size  # nothing counted twice
    warm = win.warmup
    expected = sum(r.stop - r.start - warm for r in data.runs)
    assert scored.size == expected
    for r in data.runs:  # the first `warm` samples of a run are never scored
        assert not np.isin(np.arange(r.start, r.start + warm), scored).any()
    # a window never straddles a gap between segments
    for rows in win.idx:
        assert np.all(np.diff(data.t[rows]) < 3 * data.dt)


def test_too_short_flight_for_the_warmup_is_a_clear_error(model, short_flight):
    df = short_flight.df.iloc[:50]
    data = FlightData.from_flight(model, df)
    with pytest.raises(CalibrationError, match="warm-up"):
        make_windows(data, 1.0, 1.0)


def test_noise_scale_estimates_white_noise_under_a_smooth_signal():
    rng = np.random.default_rng(1)
    t = np.arange(20000) / 150.0
    z = np.column_stack([3 * np.sin(2 * np.pi * 1.5 * t) + 0.2 * rng.normal(size=t.size),
                         np.sin(t) + 0.05 * rng.normal(size=t.size)])
    np.testing.assert_allclose(noise_scale(z), [0.2, 0.05], rtol=0.05)


def test_propagator_rejects_nothing_it_can_linearise(model, short_flight):
    data = FlightData.from_flight(model, short_flight)
    prop = HiddenPropagator(model, data.dt, None, data.reference_row())
    assert prop.a.shape == (1, prop.m, prop.m)
    # the rotor dynamics are stable at the reference: every mode decays
    assert np.max(np.linalg.eigvals(prop.a[0]).real) < 0


def test_a_parameter_set_that_breaks_the_rotor_is_invalid_not_fatal(model, short_flight):
    # PSO particles can land anywhere in the bounds: one absurd set must not stop the batch
    data = FlightData.from_flight(model, short_flight)
    pred = WindowedPredictor(model, data, make_windows(data, 1.0, 0.5))
    good = model.parameter_vector()
    bad = good.copy()
    bad[model.parameter_names.index("main_rotor.flap_inertia_kg_m2")] = 0.0  # divides by 0
    z, valid = pred.predict(np.stack([good, bad, good]))
    assert list(valid) == [True, False, True]
    assert np.all(np.isfinite(z[[0, 2]])) and np.all(np.isnan(z[1]))
    r, valid = pred.residuals(np.stack([bad]))
    assert not valid[0]


def test_streamed_cost_equals_the_rms_of_the_stored_residuals(model, short_flight):
    # the PSO's cost holds a few sets' predictions at a time; it must mean the same thing
    data = FlightData.from_flight(model, short_flight)
    pred = WindowedPredictor(model, data, make_windows(data, 1.0, 0.5))
    # more sets than one chunk of the cost's, and an invalid one among them
    sets = np.stack([model.with_parameters({"rigid_body.Iyy_kg_m2": v}).parameter_vector()
                     for v in np.linspace(0.2, 1.0, pred.COST_CHUNK + 3)])
    sets[5, model.parameter_names.index("main_rotor.flap_inertia_kg_m2")] = 0.0
    r, valid = pred.residuals(sets)
    cost = pred.cost(sets)
    assert list(np.nonzero(~np.isfinite(cost))[0]) == [5] and not valid[5]
    np.testing.assert_allclose(cost[valid], np.sqrt(np.mean(r[valid] ** 2, axis=1)),
                               rtol=1e-12)


def test_one_compiled_pass_is_the_stepped_propagation(model, short_flight):
    # an all-kernel model predicts every window of every set in one compiled pass
    # (`windowed_measurements`); it must be the Python stepping's ETD steps, to rounding
    data = FlightData.from_flight(model, short_flight)
    pred = WindowedPredictor(model, data, make_windows(data, 1.0, 0.5))
    sets = np.stack([model.parameter_vector(), model.with_parameters(
        {"main_rotor.flap_stiffness_nm_rad": 200.0, "rigid_body.Ixx_kg_m2": 0.3}
    ).parameter_vector()])
    for wind in (None, np.array([1.0, -0.5, 0.2, 0.0, 0.05, 0.0])):
        z, valid = pred.predict(sets, wind)
        assert valid.all()
        prop = HiddenPropagator(model, data.dt, sets, data.reference_row())
        np.testing.assert_allclose(z, pred._stepped(prop, sets, wind), rtol=1e-9, atol=1e-11)
    assert not np.allclose(pred.predict(sets[:1], np.ones(6))[0], z[:1])  # the wind is read


def test_a_model_with_numpy_stages_is_stepped_to_the_same_prediction(short_flight):
    # a user's numpy-style effect cannot run in the compiled pass: the same windows are
    # stepped in Python, and the kernel-style twin of the effect predicts the same
    from pathlib import Path

    from airwake.heli import load_plugin, registered_effects
    from airwake.heli.measurement import windowed_measurements

    load_plugin(Path(__file__).resolve().parents[1] / "heli" / "plugins" / "probe_effects.py")
    reg = registered_effects()
    base = load_spec("table51")
    with_numpy, with_kernel = base + reg["test_probe_numpy"](), base + reg["test_probe_kernel"]()
    assert not with_numpy.is_compiled and with_kernel.is_compiled
    out = []
    for m in (with_numpy, with_kernel):
        data = FlightData.from_flight(m, short_flight)
        win = make_windows(data, 1.0, 0.5)
        prop = HiddenPropagator(m, data.dt, m.parameter_vector()[None], data.reference_row())
        compiled = windowed_measurements(
            m, data.x, data.u, data.env, win.idx, m.parameter_vector()[None], prop.h_ref,
            prop.a_t, prop.a_inv_t, *prop.step_matrices())
        assert (compiled is None) == (m is with_numpy)
        z, valid = WindowedPredictor(m, data, win).predict(m.parameter_vector()[None])
        assert valid.all()
        out.append(z)
    np.testing.assert_allclose(out[0], out[1], rtol=1e-9, atol=1e-10)
