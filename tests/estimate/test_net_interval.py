"""A wind net's interval widened by a model smoother's disagreement with it and by the
fast wind the smoother did not see (`airwake.estimate.net_interval`): the maths on
signals whose parts are known."""

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
from airwake.estimate.net_interval import (
    MEAN_FLOW,
    disagreement_std,
    highpass_sigma_s,
    share_above,
    unseen_std,
)
from airwake.nets.features import gaussian_kernel
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

RATE = 15.0


def _table(t, columns):
    return pd.DataFrame({"t_s": t, **{n: c for n, c in zip(MEAN_FLOW, columns, strict=True)}})


def _fast(rng, n, std, corner_hz=2.0):
    """Band-limited noise of the given std, most of its power above 0.3 Hz (a 15 Hz
    sample rate, first-order low-pass of white noise at `corner_hz`)."""
    x = rng.standard_normal(n)
    a = np.exp(-2 * np.pi * corner_hz / RATE)
    y = np.empty(n)
    acc = 0.0
    for i, v in enumerate(x):
        acc = a * acc + (1 - a) * v
        y[i] = acc
    return std * y / y.std()


@given(st.floats(0.05, 50.0))
def test_the_highpass_passes_half_the_power_at_its_corner(corner_hz):
    # the complement of the Gaussian low-pass: |1 - G(f)|^2 = 1/2 at the corner
    sigma = highpass_sigma_s(corner_hz)
    g = np.exp(-0.5 * (2 * np.pi * corner_hz * sigma) ** 2)
    assert (1 - g) ** 2 == pytest.approx(0.5, rel=1e-9)
    # and the sampled kernel agrees, where it is long enough to be sampled
    rate = 40.0 * corner_hz
    k = gaussian_kernel(rate, sigma, 4 * sigma, causal=False)
    n = np.arange(k.size) - k.size // 2
    response = float(np.sum(k * np.cos(2 * np.pi * corner_hz * n / rate)))
    assert (1 - response) ** 2 == pytest.approx(0.5, abs=1e-3)


@settings(max_examples=20)
@given(st.floats(0.05, 0.6), st.floats(-3.0, 3.0), st.floats(-0.01, 0.01),
       st.integers(0, 2**31 - 1))
def test_it_recovers_the_fast_part_and_ignores_a_steady_offset_and_a_drift(
        fast_std, offset, drift, seed):
    # net: the slow wind; model: the same slow wind, a steady offset, a slow drift and the
    # fast part the net misses -> the disagreement is the fast part's RMS
    rng = np.random.default_rng(seed)
    t = np.arange(0, 240, 1 / RATE)
    slow = [0.8 * np.sin(2 * np.pi * 0.01 * t + p) for p in (0.0, 1.0, 2.0)]
    fast = [_fast(rng, t.size, fast_std) for _ in range(3)]
    net = _table(t, slow)
    model = _table(t, [s + f + offset + drift * t for s, f in zip(slow, fast, strict=True)])
    got = disagreement_std(net, model)
    assert got.shape == (t.size, 3)
    inner = (t > 30) & (t < t[-1] - 30)  # away from the windows' edges
    for j in range(3):
        assert np.median(got[inner, j]) == pytest.approx(fast_std, rel=0.12), j


def test_it_is_local_where_the_fast_part_is():
    # turbulence in the second half only (a shear layer, not the free stream)
    rng = np.random.default_rng(3)
    t = np.arange(0, 200, 1 / RATE)
    fast = _fast(rng, t.size, 0.4) * (t > 100)
    zero = np.zeros_like(t)
    got = disagreement_std(_table(t, [zero] * 3), _table(t, [fast, zero, zero]))
    assert np.median(got[t < 70, 0]) < 0.02
    assert np.median(got[t > 130, 0]) == pytest.approx(0.4, rel=0.15)
    assert np.all(got[:, 1:] == 0)


def test_the_model_is_matched_to_the_nets_times_and_gaps_are_bridged():
    # the smoother's 15 Hz against a net at 150 Hz: the same answer (for a fast part that
    # 15 Hz samples well: linear interpolation loses the rest); a net sample that is not
    # finite (its first context) does not poison the window
    rng = np.random.default_rng(5)
    t_model = np.arange(0, 120, 1 / RATE)
    fast = _fast(rng, t_model.size, 0.3, corner_hz=0.7)
    zero = np.zeros_like(t_model)
    model = _table(t_model, [fast, zero, zero])
    coarse = disagreement_std(_table(t_model, [zero] * 3), model)
    t_net = np.arange(0, 120 - 1 / RATE, 1 / 150)
    net = _table(t_net, [np.zeros_like(t_net)] * 3)
    net.loc[:20, "wind_vx_m_s"] = np.nan
    fine = disagreement_std(net, model)
    assert np.isfinite(fine).all()
    inner = (t_net > 20) & (t_net < 100)
    assert np.median(fine[inner, 0]) == pytest.approx(
        np.median(np.interp(t_net, t_model, coarse[:, 0])[inner]), rel=0.05)


def test_bad_input_is_named():
    t = np.arange(0, 10, 1 / RATE)
    z = _table(t, [np.zeros_like(t)] * 3)
    with pytest.raises(ValueError, match="corner"):
        disagreement_std(z, z, highpass_hz=0.0)
    with pytest.raises(ValueError, match="window"):
        disagreement_std(z, z, window_s=-1.0)
    with pytest.raises(ValueError, match="increasing"):
        disagreement_std(_table(t[::-1], [np.zeros_like(t)] * 3), z)
    nan = _table(t, [np.full_like(t, np.nan)] * 3)
    with pytest.raises(ValueError, match="finite"):
        disagreement_std(nan, z)


@settings(max_examples=30)
@given(st.floats(0.01, 5.0), st.floats(0.05, 20.0))
def test_the_share_above_the_corner_is_the_gauss_markov_spectrums(corner_hz, tau):
    # a first-order Gauss-Markov process: two-sided spectrum 2 sigma^2 tau / (1 + (w tau)^2)
    # over w; its one-sided power above f_c as a share of the whole
    def density(f):
        return 4.0 * tau / (1.0 + (2 * np.pi * f * tau) ** 2)

    above, _ = integrate.quad(density, corner_hz, np.inf, limit=200)
    assert float(share_above(corner_hz, tau)) == pytest.approx(above, rel=1e-6, abs=1e-9)
    # a slower process keeps less of its power above the corner
    assert share_above(corner_hz, 2 * tau) < share_above(corner_hz, tau)


def test_the_unseen_part_is_the_turbulence_posterior_above_the_nets_band():
    t = np.arange(0, 30, 1 / RATE)
    fast = np.column_stack([np.full_like(t, 0.3), np.linspace(0.1, 0.2, t.size),
                            np.full_like(t, 0.05), np.ones((t.size, 3))])
    fast[10:20, 0] = np.nan  # a gap between two runs is bridged
    tau = np.array([0.9, 0.9, 0.9, 0.45, 0.45, 0.45])
    result = SimpleNamespace(t=t, fast_std=fast, prior=SimpleNamespace(tau_s=tau))
    t_net = np.arange(0, 30, 1 / 150)
    got = unseen_std(t_net, result, highpass_hz=0.1)
    assert got.shape == (t_net.size, 3) and np.isfinite(got).all()
    k = np.sqrt(1 - 2 / np.pi * np.arctan(2 * np.pi * 0.1 * 0.9))
    np.testing.assert_allclose(got[:, 0], 0.3 * k, rtol=1e-12)
    np.testing.assert_allclose(got[:, 1], k * np.interp(t_net, t, fast[:, 1]), rtol=1e-12)
    # a higher band edge leaves less of the turbulence unseen
    assert (unseen_std(t_net, result, highpass_hz=0.5) < got).all()
    with pytest.raises(ValueError, match="fast_std"):
        unseen_std(t_net, SimpleNamespace(t=t, prior=result.prior))
    with pytest.raises(ValueError, match="correlation time"):
        share_above(0.1, [0.9, -1.0])
    with pytest.raises(ValueError, match="corner"):
        share_above(0.0, 0.9)


def test_the_smoothers_turbulence_posterior_is_within_its_prior(tiny_wind_flight):
    # the fast part's posterior std: finite, positive, and no wider than the prior's
    # stationary std (a smoother's posterior variance never exceeds its prior's)
    from airwake.calibrate import load_flight
    from airwake.calibrate.residuals import FlightData
    from airwake.estimate.prefilter import prefilter
    from airwake.estimate.smoother import WindSmoother
    from airwake.estimate.wind_prior import WindPrior
    from airwake.heli import load_model

    model = load_model("table52")
    pre = prefilter(FlightData.from_flight(model, load_flight(tiny_wind_flight)), model,
                    6.0, 15.0)
    prior = WindPrior.from_physics(0.673, 3.0)
    res = WindSmoother(model, pre, prior, iterations=1).run()
    assert res.fast_std.shape == res.std.shape
    assert np.isfinite(res.fast_std).all() and (res.fast_std > 0).all()
    assert (res.fast_std <= prior.sigma * (1 + 1e-6)).all()
    # the accelerations read the fast mean flow: its posterior is well inside the prior
    assert np.median(res.fast_std[:, :3] / prior.sigma[:3]) < 0.9
