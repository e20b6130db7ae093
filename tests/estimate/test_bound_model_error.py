"""The Cramer-Rao bound for the problem the estimator faces: the channels carry the
model's error as a coloured process (`ChannelNoise`, AR per channel) and steady offsets
as nuisance parameters, over the prior of the air actually flown through
(`WindPrior.fitted_to`). The augmented filter is checked against the white-noise filter,
the coloured noise against what physics says it must do to a slow wind."""

from __future__ import annotations

import numpy as np
import pytest
from airwake.estimate.smoother import ChannelNoise, VectorNoise
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


@settings(max_examples=25, deadline=None)
@given(st.integers(1, 12), st.integers(0, 10_000))
def test_levinson_gives_every_orders_yule_walker_solution(top, seed):
    from airwake.estimate.smoother import _levinson
    from scipy.linalg import solve_toeplitz

    x = np.random.default_rng(seed).normal(size=400).cumsum() * 0.1
    x = x - x.mean()
    # the biased estimator (sum / n), as ChannelNoise.fit uses: its Toeplitz matrix is
    # positive definite, so every order's innovation variance is > 0 and falls (the
    # unbiased one, mean over the overlap, is not: hypothesis found a negative one)
    r = np.array([np.sum(x[:x.size - k] * x[k:]) / x.size for k in range(top + 1)])
    fits = _levinson(r)
    assert len(fits) == top + 1 and fits[0][1] == pytest.approx(r[0])
    for p in range(1, top + 1):
        a = solve_toeplitz(r[:p], r[1:p + 1])
        np.testing.assert_allclose(fits[p][0], a, rtol=1e-6, atol=1e-9)
        assert fits[p][1] == pytest.approx(r[0] - a @ r[1:p + 1], rel=1e-6)
        assert 0 < fits[p][1] <= fits[p - 1][1] * (1 + 1e-12)  # a better fit each order


def test_the_channel_noise_order_is_akaikes_and_holds_a_spectral_peak():
    # a misfit whose power sits in a band around 0.5 Hz (white noise through a Butterworth
    # band-pass, 15 Hz samples, on a small white floor), as the blade-element misfit's
    # peak: AR(4) cannot place the band and spreads its power into the frequencies below,
    # where a slow wind is read; the order Akaike's criterion picks follows the spectrum
    # there, and a white channel gets order 0 (or nearly)
    from scipy.signal import butter, freqz, lfilter

    rng = np.random.default_rng(11)
    n, fs, floor = 20_000, 15.0, 0.05
    b, a = butter(2, [0.35, 0.7], btype="bandpass", fs=fs)
    e = np.column_stack([lfilter(b, a, rng.normal(size=n)) + floor * rng.normal(size=n)
                         for _ in range(5)] + [rng.normal(size=n)])
    chosen = ChannelNoise.fit(e, [slice(0, n)])
    orders = chosen.orders()
    assert orders[5] <= 2 and all(o > 4 for o in orders[:5]), orders
    assert chosen.order == max(orders) and chosen.ar.shape == (6, max(orders))
    four = ChannelNoise.fit(e, [slice(0, n)], order=4)
    f = np.linspace(0.03, 0.2, 30)  # below the band, where the mean flow is read
    _, h = freqz(b, a, worN=f, fs=fs)
    true = 2 * (np.abs(h) ** 2 + floor**2) / fs

    def psd(noise):
        z = np.exp(-2j * np.pi * f / fs)
        coef = noise.ar[0]
        den = 1 - sum(coef[k] * z ** (k + 1) for k in range(coef.size))
        return 2 * noise.innovation_var[0] / np.abs(den) ** 2 / fs

    over_aic = np.exp(np.mean(np.log(psd(chosen) / true)))
    over_four = np.exp(np.mean(np.log(psd(four) / true)))
    # (measured: 3.3x against AR(4)'s 66x; a 30-fold notch is more than 32 coefficients
    # can dig, and the blade-element misfit's is shallower: 1.0-1.5x there)
    assert over_four > 20.0 and over_aic < over_four / 10.0, (over_aic, over_four)
    with pytest.raises(ValueError, match="order"):
        ChannelNoise.fit(e, [slice(0, n)], order=-1)


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


@settings(max_examples=6, deadline=None)
@given(st.floats(-0.5, 0.8), st.floats(-0.4, 0.4), st.floats(-0.8, 0.8),
       st.integers(0, 10_000))
def test_the_vector_noise_fit_recovers_a_var_process(a, cross, rho, seed):
    # a VAR(1): channel 1 follows channel 0 (cross), innovations of channels 0 and 3
    # correlated (rho); read back by least squares at the order Akaike's criterion picks
    rng = np.random.default_rng(seed)
    n = 8_000
    coef = np.diag([a, 0.5, -0.3, 0.2, 0.0, 0.6])
    coef[1, 0] = cross
    assume(np.max(np.abs(np.linalg.eigvals(coef))) < 0.95)
    cov = np.diag([0.1, 0.2, 0.3, 0.4, 0.5, 0.6]) ** 2
    cov[0, 3] = cov[3, 0] = rho * 0.1 * 0.4
    innov = rng.multivariate_normal(np.zeros(6), cov, n + 200)
    x = np.zeros((n + 200, 6))
    for k in range(1, n + 200):
        x[k] = coef @ x[k - 1] + innov[k]
    e = x[200:] + 5.0  # the mean is not noise
    fit = VectorNoise.fit(e, [slice(0, n)], max_order=4)
    assert fit.order >= 1
    # least squares' own scatter: coefficient (i, j) ~ innovation std i / (std j sqrt n)
    tol = 5.0 * np.sqrt(np.diag(cov))[:, None] / (e.std(0)[None, :] * np.sqrt(n))
    assert np.all(np.abs(fit.coef[0] - coef) < tol), (fit.coef[0] - coef) / tol
    assert np.all(np.abs(fit.coef[1:]) < tol), fit.order
    sd = np.sqrt(np.diag(cov))  # a sample covariance's scatter: sqrt((s_i s_j)^2 + c^2) / sqrt n
    assert np.all(np.abs(fit.innovation_cov - cov)
                  < 5.0 * np.sqrt(np.outer(sd, sd) ** 2 + cov**2) / np.sqrt(n))
    np.testing.assert_allclose(fit.std(), e.std(0), rtol=0.05)
    with pytest.raises(ValueError, match="order"):
        VectorNoise.fit(e, [slice(0, n)], order=-1)


def test_a_misfit_shared_by_channels_hides_the_wind_less_than_independent_ones(tiny):
    # the same per-channel spectra (AR(1), phi 0.8), the lateral channels' innovations
    # correlated (a_y, p-dot, r-dot: one side-force error shows in all three) or not: a
    # shared misfit is partly cancellable between channels, so the bound is lower. And a
    # VAR with diagonal coefficients and covariance is the per-channel AR exactly
    est, wind = tiny
    sm, prior = est.smoother, est.result.prior
    sd = np.array([0.05, 0.04, 0.08, 0.3, 0.2, 0.4])
    phi = 0.8
    var = sd**2 * (1 - phi * phi)
    per_channel = ChannelNoise(np.full((6, 1), phi), var, 1e-6 * sd**2)
    diag = VectorNoise(np.diag(np.full(6, phi))[None], np.diag(var), 1e-6 * sd**2)
    np.testing.assert_allclose(sm.bound(wind, prior, diag), sm.bound(wind, prior, per_channel),
                               rtol=1e-6)
    corr = np.eye(6)
    for i, j in ((1, 3), (1, 5), (3, 5)):
        corr[i, j] = corr[j, i] = 0.85 if (i, j) == (1, 3) else -0.6
    shared = VectorNoise(np.diag(np.full(6, phi))[None],
                         corr * np.sqrt(np.outer(var, var)), 1e-6 * sd**2)
    np.testing.assert_allclose(shared.std(), per_channel.std(), rtol=1e-9)
    lo, hi = sm.bound(wind, prior, shared).mean(0), sm.bound(wind, prior, per_channel).mean(0)
    assert np.all(lo <= hi * (1 + 1e-9)) and lo[1] < 0.99 * hi[1], (lo, hi)


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
    # 31 samples: a VAR lag needs 60 rows (10 per coefficient of each equation), so the
    # channels' error is white there, with its cross-covariance
    assert "VAR(0)" in at_truth["noise_model"], at_truth["noise_model"]
    score = score_bound(score_wind(est.df, ft.df, burn_in_s=0.5), at_truth, est.df)
    for comp in score["components"].values():
        assert comp["crlb_std"] > 0 and comp["error_over_crlb"] > 0
