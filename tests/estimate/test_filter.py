"""The reference's wind particle filter (`--method apf`) on model-generated flights, fed
the raw flight as the reference fed it (cutoff_hz=0): it finds the wind, it says how sure
it is, and it never produces NaN.

Tolerances (after a 3 s burn-in, 1000 particles): mean flow RMS error <= 0.4 m/s per
component; vorticity, weakly observable on a 0.67 m rotor, only loosely: RMS error <=
0.35 1/s per component and within 3x the filter's own posterior std.
"""

import numpy as np
import pytest
from airwake.calibrate.residuals import FlightData
from airwake.estimate import estimate_wind, score_wind
from airwake.estimate.particle_filter import ParticleFilter
from airwake.estimate.wind_model import WindMeasurementModel
from airwake.heli import WIND_NAMES, load_spec
from airwake.record.flight_table import TRUTH_WIND

V, W = WIND_NAMES[:3], WIND_NAMES[3:]
APF = {"method": "apf", "cutoff_hz": 0}


def _check(score, truth_scale):
    comps = score["components"]
    for name in V:
        assert comps[name]["error_rms"] <= 0.4, (name, comps[name])
    for name in W:
        c = comps[name]
        assert c["error_rms"] <= 0.35, (name, c)
        assert c["error_rms"] <= 3.0 * c["posterior_std_mean"], (name, c)
    # and much better than not estimating at all (which errs by the wind itself)
    assert comps["wind_vx_m_s"]["error_rms"] < 0.25 * truth_scale


@pytest.mark.parametrize("resampler", ["systematic", "roulette"])
def test_filter_recovers_a_constant_wind(constant_wind_flight, resampler):
    est = estimate_wind(constant_wind_flight, "table52", n_particles=1000, seed=3,
                        resampler=resampler, **APF)
    _check(score_wind(est.df, constant_wind_flight.df, burn_in_s=3.0), 2.0)
    if resampler == "roulette":  # the reference's scheme resamples on every sample
        assert est.df["resampled"].all()
    else:
        assert 0 < est.df["resampled"].mean() < 0.8


def test_filter_tracks_a_slowly_varying_wind(varying_wind_flight):
    est = estimate_wind(varying_wind_flight, "table52", n_particles=1000, seed=4, **APF)
    df = varying_wind_flight.df
    score = score_wind(est.df, df, burn_in_s=3.0)
    _check(score, float(df["truth_wind_vx_m_s"].abs().mean()))
    # it follows the variation, not just the mean: most of the vx signal is explained
    keep = df["t_s"] >= 3.0
    truth = df.loc[keep, "truth_wind_vx_m_s"]
    err = est.df.loc[keep, "wind_vx_m_s"] - truth
    assert err.var() < 0.2 * truth.var()


def test_output_columns_and_posterior_std_stay_positive(tiny_wind_flight):
    est = estimate_wind(tiny_wind_flight, "table52", n_particles=200, seed=0, **APF)
    df = est.df
    for name in WIND_NAMES:
        assert name in df and f"{name}_std" in df
        assert (df[f"{name}_std"] > 0).all()  # regularisation: the cloud never collapses
    assert len(df) == len(tiny_wind_flight.df)
    assert df["ess"].between(1, 200).all()
    assert est.metadata["particles"] == 200


def _run(flight, sigma=0.5, n=200, model_patch=None, seed=0):
    model = load_spec("table52")
    data = FlightData.from_flight(model, flight)
    wm = WindMeasurementModel(model, data)
    if model_patch:
        model_patch(wm)
    pf = ParticleFilter(wm, n, sigma, rng=np.random.default_rng(seed))
    return pf.run(), data


@pytest.mark.parametrize("sigma", [1e-9, 1e-3, 1e3, 1e9])
def test_no_nan_with_a_bad_sigma(tiny_wind_flight, sigma):
    # a sharp sigma underflows every weight but the best: normalising in log space must
    # keep the posterior finite
    out, _ = _run(tiny_wind_flight, sigma=sigma)
    assert np.all(np.isfinite(out.mean)) and np.all(np.isfinite(out.std))
    assert not out.skipped.any()


def test_no_nan_with_outlier_samples(tiny_wind_flight):
    df = tiny_wind_flight.df.copy()
    for k, c in ((40, "acc_z_m_s2"), (41, "pdot_rad_s2"), (120, "rdot_rad_s2")):
        df.loc[k, c] = 1e4 if c != "pdot_rad_s2" else -1e4
    out, _ = _run(df)
    assert np.all(np.isfinite(out.mean)) and np.all(np.isfinite(out.std))
    # an outlier is one sample: the estimate afterwards is still near the truth
    truth = df[list(TRUTH_WIND)].to_numpy()
    assert np.all(np.abs(out.mean[-1, :2] - truth[-1, :2]) < 1.0)


def test_non_finite_predictions_are_zero_weight_and_a_fully_broken_sample_is_skipped(
        tiny_wind_flight):
    def patch(wm):
        real = wm.evaluate
        calls = []

        def evaluate(x, u, w, env):
            xd, z = real(x, u, w, env)
            k = len(calls)
            calls.append(k)
            z = z.copy()
            if k % 7 == 0:
                z[::3] = np.nan  # a third of the particles break
            if k == 50:
                z[:] = np.inf  # every particle breaks
            return xd, z

        wm.evaluate = evaluate

    out, _ = _run(tiny_wind_flight, model_patch=patch)
    assert np.all(np.isfinite(out.mean)) and np.all(np.isfinite(out.std))
    assert out.skipped[50] and out.skipped.sum() == 1


def test_filter_is_deterministic_for_a_seed(tiny_wind_flight):
    a, _ = _run(tiny_wind_flight, seed=7)
    b, _ = _run(tiny_wind_flight, seed=7)
    c, _ = _run(tiny_wind_flight, seed=8)
    np.testing.assert_array_equal(a.mean, b.mean)
    assert not np.array_equal(a.mean, c.mean)


@pytest.mark.parametrize("kw,match", [({"sigma": 0.0}, "sigma"), ({"sigma": np.nan}, "sigma"),
                                      ({"n_particles": 1}, "n_particles"),
                                      ({"ess_threshold": 2.0}, "ess_threshold")])
def test_bad_filter_settings_raise_naming_them(tiny_wind_flight, kw, match):
    model = load_spec("table52")
    wm = WindMeasurementModel(model, FlightData.from_flight(model, tiny_wind_flight))
    args = {"n_particles": 10, "sigma": 0.5, **kw}
    with pytest.raises(ValueError, match=match):
        ParticleFilter(wm, **args)
