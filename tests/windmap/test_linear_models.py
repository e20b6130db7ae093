"""eq 3.15 and eq 5.3 fits recover exact linear fields."""

import numpy as np
from airwake.windmap.linear_models import fit_linear12, fit_rotation6


def test_linear12_recovers_a_full_gradient():
    rng = np.random.default_rng(0)
    r = rng.uniform(-0.65, 0.65, (400, 3)) * [1, 1, 0.46]
    a = rng.normal(size=(3, 3))
    d = np.array([3.0, -1.0, 0.2])
    fit = fit_linear12(r, d + r @ a.T)
    np.testing.assert_allclose(fit.d, d, atol=1e-10)
    np.testing.assert_allclose(fit.a, a, atol=1e-10)
    assert fit.rank == 4


def test_rotation6_recovers_uniform_flow_plus_rotation_and_ignores_pure_strain():
    rng = np.random.default_rng(1)
    r = rng.uniform(-0.65, 0.65, (400, 3))
    v, om = np.array([1.0, 2.0, -0.5]), np.array([0.3, -0.2, 0.9])
    fit = fit_rotation6(r, v + np.cross(om, r))
    np.testing.assert_allclose(fit.v, v, atol=1e-10)
    np.testing.assert_allclose(fit.omega, om, atol=1e-10)
    # a symmetric gradient (strain) has no rotation: omega = curl / 2 = 0
    s = np.array([[1.0, 0.4, 0.0], [0.4, -0.5, 0.2], [0.0, 0.2, -0.5]])
    fit = fit_rotation6(r, v + r @ s.T)
    np.testing.assert_allclose(fit.omega, 0.0, atol=0.05)


def test_planar_samples_give_no_gradient_across_the_plane():
    # one height only: the z slope is unidentified and the fit leaves it at zero
    rng = np.random.default_rng(2)
    r = np.column_stack([rng.uniform(-0.6, 0.6, (200, 2)), np.zeros(200)])
    fit = fit_linear12(r, np.tile([1.0, 0.0, 0.0], (200, 1)) + r[:, :1] * [0.5, 0, 0])
    assert fit.rank == 3
    np.testing.assert_allclose(fit.a[:, 2], 0.0, atol=1e-12)
    np.testing.assert_allclose(fit.a[0, 0], 0.5, atol=1e-10)
