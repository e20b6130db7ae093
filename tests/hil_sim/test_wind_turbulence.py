"""Frozen turbulence boxes: variance, divergence, length scale, advection, validation."""

import numpy as np
import pytest

from hil_sim.world.turbulence import FrozenTurbulence, TurbulenceConfig

SMALL = {"length_scale_m": 1.0, "grid_spacing_m": 0.2, "box_m": (48.0, 12.0, 12.0)}


@pytest.fixture(scope="module", params=["von_karman", "dryden"])
def box(request):
    cfg = TurbulenceConfig(spectrum=request.param, **SMALL)
    return FrozenTurbulence(cfg, np.random.default_rng(0))


def test_unit_variance_zero_mean(box):
    f = box.field().astype(float)  # stored float32
    assert np.allclose(f.mean(axis=(0, 1, 2)), 0.0, atol=1e-5)
    assert np.allclose(f.std(axis=(0, 1, 2)), 1.0, atol=1e-5)


def test_field_is_divergence_free(box):
    # Spectral derivatives: incompressible turbulence, as the projection promises.
    f = box.field()
    div = 0.0
    grad = 0.0
    for axis in range(3):
        k = 2 * np.pi * np.fft.fftfreq(f.shape[axis], box.spacing[axis])
        shape = [1, 1, 1]
        shape[axis] = -1
        d = np.real(np.fft.ifft(1j * k.reshape(shape) * np.fft.fft(f[..., axis], axis=axis),
                                axis=axis))
        div = div + d
        grad += np.mean(d**2)
    assert np.sqrt(np.mean(div**2)) < 0.1 * np.sqrt(grad)


def test_longitudinal_integral_scale_matches_config(box):
    # L = integral of the longitudinal autocorrelation of u along x. A periodic box
    # keeps a small constant correlation (its k_x = 0 plane): remove the far-tail
    # baseline, integrate to 3 L (the von Karman tail beyond holds ~5 %).
    u = box.field()[..., 0].astype(float)
    n = u.shape[0]
    dx = box.spacing[0]
    spec = np.abs(np.fft.fft(u, axis=0)) ** 2
    corr = np.real(np.fft.ifft(spec, axis=0)).mean(axis=(1, 2))
    corr /= corr[0]
    r = np.arange(n) * dx
    ell = box.config.length_scale_m
    base = corr[(r > 6 * ell) & (r < 10 * ell)].mean()
    c = (corr - base) / (1 - base)
    near = r <= 3 * ell
    assert np.trapezoid(c[near], r[near]) == pytest.approx(ell, rel=0.12)


def test_advection_gives_time_correlation_of_length_over_speed(box):
    speed = 4.0
    t = np.arange(0, 60.0, 0.02)
    pts = np.tile([[1.0, 2.0, 3.0]], (t.size, 1))
    u = box.advected(pts, t, speed)[:, 0]
    lag = int(round(box.config.length_scale_m / speed / 0.02))
    r_lag = np.mean((u[:-lag] - u.mean()) * (u[lag:] - u.mean())) / u.var()
    r_far = np.mean((u[:-200] - u.mean()) * (u[200:] - u.mean())) / u.var()
    assert 0.15 < r_lag < 0.7 and abs(r_far) < 0.25


def test_same_seed_same_box_different_seed_different():
    cfg = TurbulenceConfig(**SMALL)
    a = FrozenTurbulence(cfg, np.random.default_rng(5)).field()
    b = FrozenTurbulence(cfg, np.random.default_rng(5)).field()
    c = FrozenTurbulence(cfg, np.random.default_rng(6)).field()
    assert np.array_equal(a, b) and not np.array_equal(a, c)


def test_bad_configs_name_the_key():
    with pytest.raises(ValueError, match="box_m"):
        TurbulenceConfig(length_scale_m=5.0, box_m=(64.0, 16.0, 16.0))
    with pytest.raises(ValueError, match="grid_spacing_m"):
        TurbulenceConfig(length_scale_m=0.3, grid_spacing_m=0.25)
    with pytest.raises(ValueError, match="spectrum = 'kolmogorov'"):
        TurbulenceConfig(spectrum="kolmogorov")
