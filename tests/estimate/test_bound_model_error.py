"""The Cramer-Rao bound for the problem the estimator faces: the channels carry the
model's error as a coloured process (`ChannelNoise`, AR per channel) and steady offsets
as nuisance parameters, over the prior of the air actually flown through
(`WindPrior.fitted_to`). The augmented filter is checked against the white-noise filter,
the coloured noise against what physics says it must do to a slow wind."""

from __future__ import annotations

import numpy as np
import pytest
from airwake.estimate.smoother import ChannelNoise
from airwake.estimate.wind import estimate_wind, score_bound, score_wind, wind_bound
from airwake.estimate.wind_prior import WindPrior
from hypothesis import assume, given, settings
from hypothesis import strategies as st


def ar_series(coef, n, rng, scale=1.0):
    p = len(coef)
    x = np.zeros(n + 200)
    e = rng.normal(0.0, scale, n + 200)
    for k in range(p, n + 200):
        x[k] = np.dot(coef, x[k - p:k][::-1]) + e[k]
    return x[200:]


@settings(max_examples=15, deadline=None)
@given(st.floats(-0.8, 0.9), st.floats(-0.3, 0.3), st.integers(0, 10_000))
def test_the_channel_noise_fit_recovers_a_stable_ar_process(a1, a2, seed):
    # a stable AR(2) (roots inside the unit circle) per channel, read back by Yule-Walker
    assume(np.max(np.abs(np.roots([1.0, -a1, -a2]))) <= 0.95)
    rng = np.random.default_rng(seed)
    n = 20_000
    e = np.column_stack([ar_series([a1, a2], n, rng, 0.1 * (c + 1)) for c in range(6)])
    fit = ChannelNoise.fit(e + 3.0, [slice(0, n)], order=2)  # the mean is not noise
    np.testing.assert_allclose(fit.ar, np.tile([a1, a2], (6, 1)), atol=0.05)
    np.testing.assert_allclose(np.sqrt(fit.innovation_var), 0.1 * np.arange(1, 7), rtol=0.05)
    np.testing.assert_allclose(fit.std(), e.std(0), rtol=0.01)
    # the companion form's stationary variance is the process's
    cov = fit.stationary_covariance()
    assert cov.shape == (12, 12) and np.all(np.linalg.eigvalsh(cov) > 0)


def test_the_channel_noise_refuses_what_it_cannot_fit():
    with pytest.raises(ValueError, match="10 finite rows"):
        ChannelNoise.fit(np.full((100, 6), np.nan), [slice(0, 100)])
    with pytest.raises(ValueError, match="constant"):
        ChannelNoise.fit(np.ones((500, 6)), [slice(0, 500)])
    with pytest.raises(ValueError, match="6 positive"):
        ChannelNoise.white([0.1, 0.0, 0.1, 0.1, 0.1, 0.1])


def test_the_prior_fitted_to_a_trajectory_reads_back_its_turbulence():
    rng = np.random.default_rng(3)
    prior = WindPrior.from_physics(0.6, 3.0)
    dt = 1.0 / 15.0
    t = np.arange(30_000) * dt
    sigma = np.array([0.1, 0.2, 0.3, 0.05, 0.08, 0.12])
    a = np.exp(-dt / prior.tau_s)
    w = np.zeros((t.size, 6))
    w[0] = rng.normal(0, sigma)
    for k in range(1, t.size):
        w[k] = a * w[k - 1] + rng.normal(0, sigma * np.sqrt(1 - a * a))
    fitted = prior.fitted_to(w + 1.5, t)  # a steady mean is the mean's, not turbulence
    np.testing.assert_allclose(fitted.sigma, sigma, rtol=0.05)
    np.testing.assert_array_equal(fitted.tau_s, prior.tau_s)
    assert prior.sigma[0] == 0.5  # the original is not touched
    with pytest.raises(ValueError, match="wind must be"):
        prior.fitted_to(w[:, :3], t)


@pytest.fixture(scope="module")
def tiny(tiny_wind_file):
    est = estimate_wind(tiny_wind_file, "table52", em_passes=2)
    wind = np.asarray(est.result.mean)
    return est, wind


def test_white_channel_noise_in_the_augmented_filter_is_the_white_bound(tiny):
    # the augmented (coloured-noise) filter with an AR(0) process is the plain filter
    est, wind = tiny
    sm, prior = est.smoother, est.result.prior
    noise = np.array([0.05, 0.04, 0.08, 0.3, 0.2, 0.4])
    plain = sm.bound(wind, prior, noise)
    aug = sm.bound(wind, prior, ChannelNoise.white(noise))
    assert np.all(np.isfinite(plain))
    np.testing.assert_allclose(aug, plain, rtol=1e-7)
    # zero offsets are no offsets; offsets only raise the bound, more with a wider prior
    np.testing.assert_allclose(sm.bound(wind, prior, noise, np.zeros(6)), plain, rtol=1e-12)
    small = sm.bound(wind, prior, noise, [0.001, 0.001, 0.001, 0, 0, 0])
    large = sm.bound(wind, prior, noise, [0.05, 0.05, 0.05, 0, 0, 0])
    assert np.all(small >= plain * (1 - 1e-9)) and np.all(large >= small * (1 - 1e-9))
    assert np.all(large[:, :3].mean(0) > plain[:, :3].mean(0) * 1.01)
    with pytest.raises(ValueError, match="offset_std"):
        sm.bound(wind, prior, noise, [0.1, -0.1, 0, 0, 0, 0])


def test_a_red_channel_error_informs_the_wind_less_than_white_noise_of_its_rms(tiny):
    # same variance on every channel, AR(1) coefficient phi: the low-frequency power is
    # var (1 + phi) / (1 - phi), so a red error (phi > 0) hides a steady wind more, a blue
    # one (phi < 0) less, than white noise of the same RMS
    est, wind = tiny
    sm, prior = est.smoother, est.result.prior
    var = np.array([0.05, 0.04, 0.08, 0.3, 0.2, 0.4]) ** 2

    def bound(phi):
        noise = ChannelNoise(np.full((6, 1), phi), var * (1 - phi * phi), 1e-6 * var)
        return sm.bound(wind, prior, noise).mean(0)

    red, white, blue = bound(0.8), bound(0.0), bound(-0.6)
    assert np.all(red > white) and np.all(white > blue), (red, white, blue)


def test_the_bound_at_the_truth_uses_the_models_error_and_the_airs_turbulence(
        tiny, tiny_wind_file):
    from airwake.record.flight_table import load_flight_table

    est, _ = tiny
    ft = load_flight_table(tiny_wind_file)
    at_truth = wind_bound(est, ft.df)
    at_est = wind_bound(est, ft.df, use_truth=False)
    assert at_truth["at"] == "truth" and at_est["at"] == "estimate"
    assert at_truth["std"].shape == (len(est.df), 6)
    assert np.all(np.isfinite(at_truth["std"])) and np.all(at_truth["std"] > 0)
    assert "AR(2)" in at_truth["noise_model"]  # 31 samples: 10 rows per coefficient
    score = score_bound(score_wind(est.df, ft.df, burn_in_s=0.5), at_truth, est.df)
    for comp in score["components"].values():
        assert comp["crlb_std"] > 0 and comp["error_over_crlb"] > 0
