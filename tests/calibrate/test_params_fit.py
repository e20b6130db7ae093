"""Parameter selection and the uncertainty / identifiability analysis."""

import numpy as np
import pytest
from airwake.calibrate.errors import CalibrationError
from airwake.calibrate.fit import identifiability_notes, uncertainty
from airwake.calibrate.params import select_parameters
from airwake.heli import load_model, load_spec


@pytest.fixture(scope="module")
def model():
    return load_spec("table51")


def test_default_selection_is_every_non_fixed_parameter(model):
    free = select_parameters(model)
    np.testing.assert_array_equal(free, ~model.fixed_mask())


def test_globs_select_by_effect_and_named_fixed_parameters_are_freed(model):
    names = np.array(model.parameter_names)
    sel = names[select_parameters(model, ["main_rotor.*"])]
    assert all(n.startswith("main_rotor.") for n in sel)
    assert "main_rotor.rotation" not in sel  # discrete: never fitted
    assert "main_rotor.radius_m" in sel  # fixed by default, but the user asked for it
    sel = names[select_parameters(model, ["flybar.c1,flybar.c2"])]
    assert list(sel) == ["flybar.c1", "flybar.c2"]


def test_unknown_parameter_is_an_error_naming_the_known_ones(model):
    with pytest.raises(CalibrationError, match="main_rotor.lock_number"):
        select_parameters(model, ["main_rotor.lok_number"])
    with pytest.raises(CalibrationError, match="discrete"):
        select_parameters(model, ["main_rotor.rotation"])


def test_uncertainty_of_a_linear_fit_is_the_textbook_covariance():
    rng = np.random.default_rng(0)
    x = rng.normal(size=(500, 3))
    r = rng.normal(size=500) * 0.7
    unc = uncertainty(x, r, ["a", "b", "c"], np.ones(3))
    s2 = r @ r / (500 - 3)
    cov = s2 * np.linalg.inv(x.T @ x)
    np.testing.assert_allclose(unc.std, np.sqrt(np.diag(cov)), rtol=1e-10)
    np.testing.assert_allclose(unc.sigma2, s2)


def _clustered_problem(rng, n_clusters=120, size=25, shared=1.0, white=0.2):
    """A linear fit whose regressors and errors both hold over a cluster (a window's
    manoeuvre and its model error): y = X b + e, e = a cluster's offset + white noise."""
    g = np.repeat(np.arange(n_clusters), size)
    slow = rng.normal(size=(n_clusters, 2))[g]  # regressors steady within a cluster
    x = np.column_stack([slow, rng.normal(size=g.size)])
    e = shared * rng.normal(size=n_clusters)[g] + white * rng.normal(size=g.size)
    return x, e, g


def test_clustered_uncertainty_is_the_spread_of_the_fit_over_repeated_flights():
    # the covariance must say how far the fit moves between repeated experiments:
    # with errors shared within a window the white formula is ~sqrt(size) too narrow on
    # the regressors that are steady within a window; the sandwich is not
    rng = np.random.default_rng(3)
    fits, clustered, white = [], [], []
    for _ in range(300):
        x, e, g = _clustered_problem(rng)
        b, *_ = np.linalg.lstsq(x, e, rcond=None)
        r = e - x @ b  # the residual at the fit (the truth is b = 0)
        unc = uncertainty(-x, r, ["a", "b", "c"], np.ones(3), clusters=g)
        assert unc.kind == "clustered" and unc.clusters == 120
        fits.append(b)
        clustered.append(unc.std)
        white.append(unc.std_white)
    spread = np.std(fits, axis=0)
    np.testing.assert_allclose(np.mean(clustered, axis=0), spread, rtol=0.15)
    assert np.all(np.mean(white, axis=0)[:2] < 0.4 * spread[:2])


def test_clustered_uncertainty_equals_the_white_one_for_independent_residuals():
    rng = np.random.default_rng(4)
    ratio = []
    for _ in range(40):
        x = rng.normal(size=(2000, 3))
        r = 0.5 * rng.normal(size=2000)
        unc = uncertainty(x, r, ["a", "b", "c"], np.ones(3), clusters=np.arange(2000) // 10)
        ratio.append(unc.std / unc.std_white)
    np.testing.assert_allclose(np.mean(ratio, axis=0), 1.0, atol=0.06)


def test_residual_windows_label_each_residual_with_its_window():
    # the sandwich's clusters must follow WindowedPredictor.residuals' layout exactly
    from types import SimpleNamespace

    from airwake.calibrate.residuals import WindowedPredictor, Windows

    rng = np.random.default_rng(6)
    w_count, length = 7, 9
    score = rng.random((w_count, length)) > 0.3
    score[:, 0] = True
    win = Windows(rng.integers(0, 50, size=(w_count, length)), score, 2)
    pred = WindowedPredictor.__new__(WindowedPredictor)
    pred.windows = win
    pred.data = SimpleNamespace(z=np.zeros((50, 6)), scale=np.ones(6))
    labels = np.broadcast_to(np.arange(w_count)[None, :, None, None], (1, w_count, length, 6))
    pred.predict = lambda sets, wind=None: (labels.astype(float), np.ones(1, bool))
    r, _ = pred.residuals(np.zeros((1, 3)))
    np.testing.assert_array_equal(-r[0], win.residual_windows())


def test_too_few_windows_keep_the_white_uncertainty_and_say_so():
    rng = np.random.default_rng(5)
    x, e, g = _clustered_problem(rng, n_clusters=5)
    unc = uncertainty(x, e, ["a", "b", "c"], np.ones(3), clusters=g)
    assert unc.kind == "white" and unc.clusters == 5
    np.testing.assert_allclose(unc.std, unc.std_white)
    notes, _ = identifiability_notes(["a", "b", "c"], np.ones(3), unc, np.zeros(3, bool))
    assert any(n.startswith("only 5 windows for 3 free parameters") for n in notes)
    with pytest.raises(ValueError, match="labels for"):
        uncertainty(x, e, ["a", "b", "c"], np.ones(3), clusters=g[:-1])


def test_a_parameter_the_residuals_ignore_is_reported_unidentifiable():
    # hiding an unidentifiable parameter behind a finite number would be a lie
    rng = np.random.default_rng(0)
    jac = rng.normal(size=(200, 3))
    jac[:, 2] = 0.0
    unc = uncertainty(jac, rng.normal(size=200), ["a", "b", "c"], np.ones(3))
    assert np.isinf(unc.std[2]) and np.all(np.isfinite(unc.std[:2]))
    notes, ident = identifiability_notes(["a", "b", "c"], np.ones(3), unc, np.zeros(3, bool))
    assert list(ident) == [True, True, False]
    assert any(n.startswith("c: not identifiable") for n in notes)


def test_strongly_correlated_pair_is_named():
    rng = np.random.default_rng(0)
    col = rng.normal(size=300)
    jac = np.column_stack([col, col + 1e-3 * rng.normal(size=300), rng.normal(size=300)])
    unc = uncertainty(jac, 0.1 * rng.normal(size=300), ["a", "b", "c"], np.ones(3))
    notes, _ = identifiability_notes(["a", "b", "c"], np.ones(3), unc, np.zeros(3, bool))
    assert any("a and b strongly correlated" in n for n in notes)


def test_rms_before_is_the_start_models_residual_not_the_weighting_stages(still_air_flight):
    """With the front end on, the fit's first stage (channel weights on a window subset)
    already moves the model; "before" must be the model the user started from (issue 20:
    on a foreign airframe the report showed 0.592 -> 0.562 for a fit that took Table
    5.1's 0.943 to 0.562)."""
    from airwake.calibrate import calibrate, model_error_std

    res = calibrate(still_air_flight, model="table51", max_nfev=4,
                    params=["rigid_body.Ixx_kg_m2", "main_rotor.lock_number"])
    np.testing.assert_allclose(res.rms_before, model_error_std("table51", still_air_flight),
                               rtol=1e-9)
    staged = np.asarray(res.info["rms_after_weighting_fit"])
    assert np.sqrt(np.mean(staged**2)) < np.sqrt(np.mean(res.rms_before**2))
    assert res.to_dict()["rms_after_weighting_fit"] == list(staged)
    start = load_model("table51").parameter_vector()
    names = list(load_model("table51").parameter_names)
    for n, s in zip(res.names, res.start, strict=True):
        assert s == start[names.index(n)]


def test_the_steady_offset_is_the_constant_a_channel_is_off_by(still_air_flight, tmp_path):
    """`model_error`'s second part reads a constant misfit added to one channel as that
    constant (the model's own flight otherwise fits to its noise), and no other channel
    moves: what `[calibration] model_error_offset` carries to the wind estimator."""
    from airwake.calibrate import model_error
    from airwake.record.flight_table import load_flight_table, write_flight_table

    rms0, off0 = model_error("table52", still_air_flight)
    df = still_air_flight.df.copy()
    df["acc_x_m_s2"] += 0.05
    path = tmp_path / "offset.parquet"
    write_flight_table(df, path, still_air_flight.metadata)
    rms1, off1 = model_error("table52", load_flight_table(path))
    assert off0[0] < 0.01
    assert abs(off1[0] - 0.05) < 0.01 and rms1[0] >= off1[0] - 1e-12
    np.testing.assert_allclose(off1[1:], off0[1:], rtol=1e-9)
    np.testing.assert_allclose(rms1[1:], rms0[1:], rtol=1e-9)
