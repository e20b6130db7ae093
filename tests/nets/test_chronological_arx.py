"""The chronological split (the default: train early, validate and test later, as a
user flies tomorrow with a net trained today) never lets a later sample into training,
and the linear ARX baseline the nets are scored against is causal and recovers a known
ARX system (docs/networks.md, "Network and training")."""

import numpy as np
import pytest
import torch
from airwake.nets import AdamWConfig, FeatureConfig, NetFlight, SplitConfig, train_net
from airwake.nets.evaluate import _predict_flight
from airwake.nets.features import gaussian_lowpass
from airwake.nets.split import GUARD, TEST, TRAIN, VAL, chronological_split, split_labels
from airwake.nets.train import build_dataset
from hypothesis import given, settings
from hypothesis import strategies as st


def _flight(t, rng, source="synthetic") -> NetFlight:
    n = t.size
    return NetFlight(source, t, rng.normal(0, 0.1, (n, 4)), "delta", rng.normal(0, 0.1, n),
                     rng.normal(0, 0.1, n), rng.normal(0, 0.2, (n, 3)), None,
                     float(1 / np.median(np.diff(t))), {"name": source})


def test_the_default_split_is_chronological():
    assert SplitConfig().order == "chronological"
    t = np.arange(0, 100, 0.01)
    labels = split_labels(t, SplitConfig(), 0.5, np.random.default_rng(0))
    np.testing.assert_array_equal(labels, chronological_split(t, SplitConfig(), 0.5))
    # 65 % train, 15 % validation, 20 % test, less the guards after each change of set
    assert (labels == TRAIN).sum() == pytest.approx(6500 - 50, abs=2)
    assert (labels == VAL).sum() == pytest.approx(1500 - 50, abs=2)
    assert (labels == TEST).sum() == pytest.approx(2000 - 50, abs=2)
    with pytest.raises(ValueError, match="order"):
        SplitConfig(order="random")


@settings(max_examples=25, deadline=None)
@given(n=st.integers(1500, 3000), rate=st.sampled_from([100.0, 123.0, 150.0]),
       val=st.floats(0.1, 0.3), test=st.floats(0.1, 0.3),
       jitter=st.floats(0.0, 0.2), cut=st.floats(0.0, 1.0), seed=st.integers(0, 2**16),
       stretch=st.sampled_from([(), (0.98, 1.02)]))
def test_no_later_sample_reaches_training(n, rate, val, test, jitter, cut, seed, stretch):
    """Training rows all come before every validation and test row, and nothing a
    training row is built from (features, targets, the low-passed target, the
    time-stretched copies) changes when any sample from the first held-out row on does."""
    rng = np.random.default_rng(seed)
    dt = (1 + jitter * rng.uniform(-1, 1, n - 1)) / rate
    t = np.r_[0.0, np.cumsum(dt)]
    split = SplitConfig(val_fraction=val, test_fraction=test)
    cfg = FeatureConfig(rate_history_samples=5)
    flight = _flight(t, rng)
    labels = split_labels(t, split, cfg.history_s(flight.rate_hz), rng)
    train, held = t[labels == TRAIN], t[(labels == VAL) | (labels == TEST)]
    assert train.size and held.size and train.max() < held.min()
    if (labels == VAL).any() and (labels == TEST).any():
        assert t[labels == VAL].max() < t[labels == TEST].min()
    first_held = int(np.flatnonzero(labels > TRAIN)[0])
    assert np.all(labels[first_held:] != TRAIN)
    # change every sample from a point at or after the first held-out row
    k = first_held + int(cut * (n - 1 - first_held))
    later = _flight(t, rng)
    for name in ("inputs", "roll_rad", "pitch_rad", "rates_rad_s"):
        changed = getattr(flight, name).copy()
        changed[k:] = getattr(later, name)[k:]
        setattr(later, name, changed)
    a = build_dataset([flight], "rates", cfg, split, np.random.default_rng(0), stretch)
    b = build_dataset([later], "rates", cfg, split, np.random.default_rng(0), stretch)
    np.testing.assert_array_equal(a.labels, b.labels)
    tr = a.labels == TRAIN
    np.testing.assert_array_equal(a.x[tr], b.x[tr])
    np.testing.assert_array_equal(a.y[tr], b.y[tr])
    np.testing.assert_array_equal(a.y_lp_sets[tr], b.y_lp_sets[tr])
    np.testing.assert_array_equal(a.x_stretch, b.x_stretch)
    np.testing.assert_array_equal(a.y_stretch, b.y_stretch)
    assert (len(a.x_stretch) > 0) == bool(stretch) or (labels == TRAIN).sum() < 200
    assert set(np.unique(a.labels)) <= {TRAIN, VAL, TEST, GUARD}


# a known ARX system: each rate's next value from its two previous values and the
# causally low-passed stick of its own axis (a feature the nets compute), plus noise
A1, A2 = np.array([1.6, 1.2, 0.5]), np.array([-0.7, -0.5, 0.2])
B = np.array([2.0, -1.5, 0.8])
NOISE = 0.01


def _arx_flight(seed: int, n: int = 6000, rate: float = 150.0) -> NetFlight:
    rng = np.random.default_rng(seed)
    t = np.arange(n) / rate
    # smooth random sticks (a random walk low-passed), as a pilot's
    u = gaussian_lowpass(np.cumsum(rng.normal(0, 0.02, (n, 4)), axis=0), rate, 0.2, 0.6)
    u -= u.mean(axis=0)
    cfg = FeatureConfig()
    drive = gaussian_lowpass(u, rate, cfg.lowpass_sigma_s, cfg.lowpass_length_s)[:, :3]
    y = np.zeros((n, 3))
    for i in range(2, n):
        y[i] = A1 * y[i - 1] + A2 * y[i - 2] + B * drive[i] + rng.normal(0, NOISE, 3)
    return NetFlight(f"arx-{seed}", t, u, "delta", np.zeros(n), np.zeros(n), y, None, rate,
                     {"name": f"arx-{seed}"})


def test_the_arx_baseline_recovers_a_known_arx_system_and_is_causal():
    torch.set_num_threads(1)
    flight = _arx_flight(3)
    # (no low-pass of the fed-back rates: it would mix the lags the check reads)
    net = train_net([flight], "rates", seed=0, time_stretch=(), hidden=(4,),
                    features=FeatureConfig(rate_history_samples=2, use_rate_lowpass=False),
                    adamw=AdamWConfig(max_epochs=0), arx_ridge=1e-9)
    names = net.card["features"]
    # least squares on standardised features, in physical units: the target is the change
    # since the fed-back rate, so the lag-1 coefficient is A1 - 1
    w = net.arx_weight.numpy()[:, :-1] * (net.y_std.numpy()[:, None] / net.x_std.numpy())
    for k, axis in enumerate("pqr"):
        assert w[k, names.index(f"{axis}_lag1")] == pytest.approx(A1[k] - 1, abs=0.02)
        assert w[k, names.index(f"{axis}_lag2")] == pytest.approx(A2[k], abs=0.02)
    # on another flight of the same system: the one-step error is the noise itself
    other = _arx_flight(4)
    x, y, prev, _, arx, cfg = _predict_flight(net, other)
    rows = slice(int(cfg.history_s(other.rate_hz) * other.rate_hz) + 1, None)
    rms = np.sqrt(np.mean((arx[rows] - y[rows]) ** 2, axis=0))
    assert np.all(rms < 1.05 * NOISE) and np.all(rms > 0.95 * NOISE)
    assert np.all(np.sqrt(np.mean((prev[rows] - y[rows]) ** 2, axis=0)) > 1.2 * rms)
    # causal: changing the flight from sample k on leaves every prediction before k alone
    k = 3000
    later = _arx_flight(5)
    for name in ("inputs", "rates_rad_s"):
        changed = getattr(other, name).copy()
        changed[k:] = getattr(later, name)[k:]
        setattr(later, name, changed)
    arx_later = _predict_flight(net, later)[4]
    np.testing.assert_array_equal(arx[:k], arx_later[:k])
    assert not np.allclose(arx[k:], arx_later[k:])
