"""The reference's PSO update (eq 5.16) and the swarm loop."""

import numpy as np
from airwake.calibrate.pso import C1, C2, INERTIA, initial_swarm, pso_update, run_pso
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays


def _swarm(seed, n=40, p=5):
    rng = np.random.default_rng(seed)
    lo, hi = -np.ones(p), 2 * np.ones(p)
    x = rng.uniform(lo, hi, (n, p))
    v = rng.normal(0, 0.5, (n, p))
    pb = rng.uniform(lo, hi, (n, p))
    gb = rng.uniform(lo, hi)
    free = np.array([True, False, True, True, False])[:p]
    return x, v, pb, gb, free, lo, hi


def test_update_is_equation_5_16_with_the_reference_coefficients():
    x, v, pb, gb, _, lo, hi = _swarm(0)
    lo, hi = lo - 100, hi + 100  # no bound interferes
    free = np.ones(x.shape[1], bool)
    x1, v1 = pso_update(x, v, pb, gb, np.random.default_rng(5), free, lo, hi)
    rng = np.random.default_rng(5)
    r1, r2 = rng.random(x.shape), rng.random(x.shape)
    v_ref = 0.1 * v + 0.2 * r1 * (pb - x) + 0.2 * r2 * (gb - x)
    assert (INERTIA, C1, C2) == (0.1, 0.2, 0.2)
    np.testing.assert_allclose(v1, v_ref, rtol=1e-15)
    np.testing.assert_allclose(x1, x + v_ref, rtol=1e-15)


def test_fixed_parameters_never_move():
    # the reference zeroes the velocity of parameters known with certainty
    x, v, pb, gb, free, lo, hi = _swarm(1)
    rng = np.random.default_rng(0)
    for _ in range(20):
        x2, v = pso_update(x, v, pb, gb, rng, free, lo, hi)
        np.testing.assert_array_equal(x2[:, ~free], x[:, ~free])
        assert np.all(v[:, ~free] == 0)
        x = x2


def test_same_seed_same_swarm():
    x, v, pb, gb, free, lo, hi = _swarm(2)
    a = pso_update(x, v, pb, gb, np.random.default_rng(9), free, lo, hi)
    b = pso_update(x, v, pb, gb, np.random.default_rng(9), free, lo, hi)
    c = pso_update(x, v, pb, gb, np.random.default_rng(10), free, lo, hi)
    np.testing.assert_array_equal(a[0], b[0])
    assert not np.array_equal(a[0], c[0])


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1),
       scale=st.floats(0.01, 1e3),
       v=arrays(np.float64, (8, 5), elements=st.floats(-1e6, 1e6)))
def test_positions_stay_within_bounds_whatever_the_velocity(seed, scale, v):
    x, _, pb, gb, free, lo, hi = _swarm(seed % 1000, n=8)
    x1, v1 = pso_update(x, v * scale, pb, gb, np.random.default_rng(seed), free, lo, hi)
    assert np.all(x1 >= lo) and np.all(x1 <= hi)
    assert np.all(np.isfinite(v1))


def test_initial_swarm_starts_from_the_given_model_and_respects_bounds():
    start = np.array([0.5, 0.0, 3.0])
    lo, hi = np.array([0.0, -1.0, 2.9]), np.array([1.0, 1.0, 10.0])
    free = np.array([True, True, False])
    x = initial_swarm(start, 500, np.random.default_rng(0), free, lo, hi, spread=0.5)
    np.testing.assert_array_equal(x[0], start)
    assert np.all(x >= lo) and np.all(x <= hi)
    assert np.all(x[:, 2] == 3.0)
    assert np.ptp(x[:, 0]) > 0.3 and np.ptp(x[:, 1]) > 0.005


def test_swarm_never_loses_its_best_and_improves_a_smooth_cost():
    target = np.array([0.3, 0.8, 1.5])

    def cost(sets):
        return np.sum((sets - target) ** 2, axis=1)

    lo, hi = -2 * np.ones(3), 2 * np.ones(3)
    start = np.array([0.5, 0.5, 1.0])
    st_, hist = run_pso(cost, start, np.ones(3, bool), lo, hi, 200, 40,
                        np.random.default_rng(0), spread=1.0)
    assert hist[0] <= cost(start[None])[0]
    assert all(b <= a for a, b in zip(hist, hist[1:], strict=False))  # monotone
    assert hist[-1] < 1e-3 * hist[0]
    np.testing.assert_allclose(st_.global_best, target, atol=0.02)
