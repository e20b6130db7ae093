"""A wind net's interval widened by a model smoother's disagreement with it
(`airwake.estimate.net_interval`): the maths on signals whose parts are known."""

import numpy as np
import pandas as pd
import pytest
from airwake.estimate.net_interval import MEAN_FLOW, disagreement_std, highpass_sigma_s
from airwake.nets.features import gaussian_kernel
from hypothesis import given, settings
from hypothesis import strategies as st

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
