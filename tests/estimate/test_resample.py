"""Resamplers are pure functions (weights, rng) -> indexes."""

import numpy as np
import pytest
from airwake.estimate.resample import (
    RESAMPLERS,
    effective_sample_size,
    multinomial,
    stratified,
    systematic,
)
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

weights_st = arrays(np.float64, st.integers(1, 300),
                    elements=st.floats(0.0, 1e6, allow_nan=False)).filter(lambda w: w.sum() > 0)


def _norm(w):
    return w / w.sum()


@settings(max_examples=200, deadline=None)
@given(w=weights_st, seed=st.integers(0, 2**32 - 1),
       name=st.sampled_from(sorted(RESAMPLERS)))
def test_indexes_are_valid_and_never_pick_a_zero_weight(w, seed, name):
    w = _norm(w)
    idx = RESAMPLERS[name](w, np.random.default_rng(seed))
    assert idx.shape == w.shape and idx.dtype == np.int64
    assert idx.min() >= 0 and idx.max() < w.size
    assert np.all(w[idx] > 0)


@settings(max_examples=200, deadline=None)
@given(w=weights_st, seed=st.integers(0, 2**32 - 1))
def test_systematic_counts_are_within_one_of_n_times_the_weight(w, seed):
    # the property that makes systematic resampling the low-variance default
    w = _norm(w)
    n = w.size
    counts = np.bincount(systematic(w, np.random.default_rng(seed)), minlength=n)
    assert counts.sum() == n
    assert np.all(np.abs(counts - n * w) < 1.0 + 1e-9)


def test_roulette_wheel_is_unbiased():
    # E[count_i] = N w_i for the reference's multinomial (roulette-wheel) selection
    rng = np.random.default_rng(0)
    w = _norm(rng.random(50) ** 3)
    reps = 4000
    counts = np.zeros(50)
    for _ in range(reps):
        counts += np.bincount(multinomial(w, rng), minlength=50)
    mean = counts / reps
    sd = np.sqrt(50 * w * (1 - w) / reps)  # std of the mean count
    assert np.all(np.abs(mean - 50 * w) < 5 * sd + 1e-12)


def test_stratified_is_unbiased_too():
    rng = np.random.default_rng(1)
    w = _norm(rng.random(20))
    counts = sum(np.bincount(stratified(w, rng), minlength=20) for _ in range(3000)) / 3000
    np.testing.assert_allclose(counts, 20 * w, atol=0.08)


@pytest.mark.parametrize("name", sorted(RESAMPLERS))
def test_same_generator_state_same_indexes(name):
    w = _norm(np.arange(1.0, 30.0))
    a = RESAMPLERS[name](w, np.random.default_rng(5))
    b = RESAMPLERS[name](w, np.random.default_rng(5))
    np.testing.assert_array_equal(a, b)


def test_effective_sample_size_bounds():
    assert effective_sample_size(np.full(10, 0.1)) == pytest.approx(10)
    assert effective_sample_size(np.eye(1, 10)[0]) == pytest.approx(1)
