"""The networks' input features (eq 2.1-2.3): exact on signals with known answers, and
causal, so a net can run on a live stream without looking ahead."""

import numpy as np
from airwake.nets.features import (
    FeatureConfig,
    build_features,
    gaussian_kernel,
    gaussian_lowpass,
    gaussian_smooth,
    line_fit,
    local_std,
)
from hypothesis import given, settings
from hypothesis import strategies as st

finite = st.floats(-50, 50, allow_nan=False, allow_infinity=False)


@given(slope=finite, offset=finite, n=st.integers(2, 60),
       rate=st.sampled_from([50.0, 123.0, 150.0]))
def test_line_fit_recovers_an_exact_line(slope, offset, n, rate):
    # eq 2.1 with x in seconds relative to now: slope per second, intercept = value now
    t = np.arange(200) / rate
    y = (offset + slope * t)[:, None]
    m, c, e = line_fit(y, n, dt=1 / rate)
    full = slice(n - 1, None)  # windows without edge padding
    np.testing.assert_allclose(m[full, 0], slope, atol=1e-6 * (1 + abs(slope)) * rate)
    np.testing.assert_allclose(c[full, 0], y[full, 0], atol=1e-7 * (1 + np.abs(y).max()))
    assert np.all(e[full, 0] <= 1e-7 * n * (1 + np.abs(y).max()))


@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 40))
def test_line_fit_matches_polyfit_and_eq_2_2_error(seed, n):
    rng = np.random.default_rng(seed)
    y = rng.normal(size=(80, 2))
    m, c, e = line_fit(y, n)
    t = 79
    x = np.arange(n) - (n - 1)
    for j in range(2):
        slope, icpt = np.polyfit(x, y[t - n + 1:t + 1, j], 1)
        assert np.isclose(m[t, j], slope) and np.isclose(c[t, j], icpt)
        assert np.isclose(e[t, j], np.abs(y[t - n + 1:t + 1, j] - (slope * x + icpt)).sum())


@given(value=finite, n=st.integers(2, 80))
def test_local_std_of_a_constant_is_zero(value, n):
    assert np.all(local_std(np.full(300, value), n) <= 1e-12 * (1 + abs(value)))


@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 30))
def test_local_std_is_the_trailing_window_std(seed, n):
    y = np.random.default_rng(seed).normal(size=100)
    assert np.isclose(local_std(y, n)[99], y[100 - n:].std())


@given(value=finite, sigma=st.floats(0.01, 0.5), extra=st.floats(0.01, 1.0))
def test_gaussian_filters_keep_a_constant_and_the_kernel_sums_to_one(value, sigma, extra):
    g = gaussian_kernel(150.0, sigma, sigma + extra, causal=True)
    assert np.isclose(g.sum(), 1.0) and np.all(np.diff(g) >= 0)  # newest sample weighs most
    y = np.full(400, value)
    np.testing.assert_allclose(gaussian_lowpass(y, 150.0, sigma, sigma + extra), value,
                               atol=1e-9 * (1 + abs(value)))
    np.testing.assert_allclose(gaussian_smooth(y, 150.0, sigma, sigma + extra), value,
                               atol=1e-9 * (1 + abs(value)))


def test_lowpass_attenuates_fast_noise_more_than_slow_motion():
    rate = 150.0
    t = np.arange(3000) / rate
    slow = np.sin(2 * np.pi * 0.5 * t)
    fast = np.sin(2 * np.pi * 30.0 * t)
    cut = slice(100, None)
    gain = lambda y: gaussian_lowpass(y, rate, 0.05, 0.15)[cut].std() / y[cut].std()  # noqa: E731
    # the causal half-Gaussian has a truncation sidelobe: ~9 % at 30 Hz, not the ~0 of eq 2.3
    assert gain(slow) > 0.95 and gain(fast) < 0.15


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), k=st.integers(0, 299), lag=st.integers(0, 3))
def test_features_at_t_do_not_change_when_later_data_changes(seed, k, lag):
    rng = np.random.default_rng(seed)
    inputs, att = rng.normal(size=(300, 4)), rng.normal(size=(300, 2))
    rates = rng.normal(size=(300, 3))
    cfg = FeatureConfig(rate_lag_samples=lag)
    x1, names = build_features(inputs, att[:, 0], att[:, 1], rates, 150.0, cfg)
    inputs[k + 1:] += 5.0
    att[k + 1:] -= 1.0
    rates[k + 1:] *= -3.0
    x2, _ = build_features(inputs, att[:, 0], att[:, 1], rates, 150.0, cfg)
    np.testing.assert_array_equal(x1[:k + 1], x2[:k + 1])
    if k + 1 < 300 and lag == 0:
        assert not np.array_equal(x1[k + 1], x2[k + 1])  # and the change does show up
    assert len(names) == x1.shape[1] == len(set(names))


def test_lagged_rates_are_the_last_columns_and_lag_is_exact():
    rng = np.random.default_rng(3)
    rates = rng.normal(size=(50, 3))
    x, names = build_features(rng.normal(size=(50, 4)), np.zeros(50), np.zeros(50), rates, 100.0,
                              FeatureConfig(rate_lag_samples=2))
    assert names[-3:] == ["p_lag2", "q_lag2", "r_lag2"]
    np.testing.assert_array_equal(x[2:, -3:], rates[:-2])


def test_feature_config_rejects_bad_windows():
    import pytest

    with pytest.raises(ValueError, match="line_window_s"):
        FeatureConfig(line_window_s=0)
    with pytest.raises(ValueError, match="lowpass_sigma_s < lowpass_length_s"):
        FeatureConfig(lowpass_sigma_s=0.3, lowpass_length_s=0.2)
    with pytest.raises(ValueError, match="rate_lag_samples"):
        FeatureConfig(rate_lag_samples=-1)
