"""The linear screen's cross-validation when a candidate acts in one block only: the fold
that leaves that block out has no rows that say anything of the candidate, so its
coefficient there is 0 (not the ~1e150 a solve of the singular normal equations gives,
which overflowed: `model diagnose` printed numpy's overflow warning and ranked the
candidate at -inf)."""

import warnings

import numpy as np
from airwake.discrepancy.regress import _solve, linear_fit
from hypothesis import given, settings
from hypothesis import strategies as st


def _problem(seed: int, n_blocks: int, n: int = 400):
    rng = np.random.default_rng(seed)
    x = np.zeros((n, 2, 2))  # (rows, channels, regressors)
    x[:, :, 0] = rng.normal(size=(n, 2))
    blocks = np.array_split(np.arange(n), n_blocks)
    where = blocks[int(rng.integers(n_blocks))]
    x[where, :, 1] = rng.normal(size=(where.size, 2))  # the candidate acts there only
    y = 0.8 * x[:, :, 0] + 0.5 * x[:, :, 1] + 0.1 * rng.normal(size=(n, 2))
    return y, x, blocks, where


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n_blocks=st.integers(2, 8))
def test_a_candidate_silent_outside_one_block_scores_finite_without_overflow(seed, n_blocks):
    y, x, blocks, _ = _problem(seed, n_blocks)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an overflow or invalid value fails the test
        fit = linear_fit(y, x, np.ones(2), blocks, n_eff=float(len(y)))
    assert np.isfinite(fit.cv_explained) and np.all(np.isfinite(fit.cv_channels))
    # the full fit sees the candidate and recovers both coefficients
    np.testing.assert_allclose(fit.coef, [0.8, 0.5], atol=0.05)
    # the held-out block where the candidate acts is predicted without it: CV explains
    # less than the fit on all rows
    assert fit.cv_explained < fit.explained


def test_the_fold_without_the_candidates_block_gives_it_no_coefficient():
    y, x, blocks, where = _problem(7, 4)
    xs = x.reshape(-1, 2)
    g = xs.T @ xs
    out = np.ones(len(y), bool)
    out[where] = False
    xo = x[out].reshape(-1, 2)
    a = _solve(xo.T @ xo, xo.T @ y[out].reshape(-1), np.diag(g))
    assert a[1] == 0.0 and abs(a[0] - 0.8) < 0.05
    # a regressor with energy in the rows is solved as before
    both = _solve(g, xs.T @ y.reshape(-1))
    np.testing.assert_allclose(both, np.linalg.lstsq(xs, y.reshape(-1), rcond=None)[0],
                               rtol=1e-6)
