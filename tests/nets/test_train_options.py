"""The options added for real gyro data (docs/networks.md, "The real flight"): more
fed-back rate lags, a low-passed training target, the ARX ridge chosen per axis on the
validation blocks and early stopping per axis; and that none of them reads a test row.
Simulated flight: seed 5, 60 s of still_air_calibration (not the seeds the doc reports)."""

import dataclasses

import numpy as np
import pytest
import torch
from airwake.nets import (
    AdamWConfig,
    FeatureConfig,
    build_features,
    evaluate_net,
    load_net,
    load_net_flight,
    predict,
    save_net,
    train_net,
)
from airwake.nets.features import lagged
from airwake.nets.metrics import smoothed_target
from airwake.nets.model import fit_arx
from airwake.nets.split import TEST, TRAIN, VAL
from airwake.nets.train import choose_arx_ridge, lowpass_within_sets, unrle

FAST = AdamWConfig(max_epochs=12, patience=6, per_axis=True)
RNG = np.random.default_rng(4)


def _signals(n=400):
    t = np.arange(n) / 150.0
    inputs = np.column_stack([np.sin(t * k) for k in (1.0, 2.0, 3.0, 4.0)])
    rates = np.column_stack([np.cos(t * k) for k in (1.5, 2.5, 3.5)]) + RNG.normal(0, .01, (n, 3))
    return inputs, np.sin(t), np.cos(t), rates


def test_default_features_are_unchanged_by_the_rate_history_option():
    x, names = build_features(*_signals(), 150.0, FeatureConfig())
    assert len(names) == 28 and names[-6:] == ["p_lag1_lowpass", "q_lag1_lowpass",
                                               "r_lag1_lowpass", "p_lag1", "q_lag1", "r_lag1"]


def test_rate_history_adds_the_further_lags_and_keeps_the_lag_last():
    inputs, roll, pitch, rates = _signals()
    cfg = FeatureConfig(rate_lag_samples=2, rate_history_samples=3)
    x, names = build_features(inputs, roll, pitch, rates, 150.0, cfg)
    assert len(names) == 34
    assert names[-12:-6] == ["p_lag4", "q_lag4", "r_lag4", "p_lag3", "q_lag3", "r_lag3"]
    assert names[-3:] == ["p_lag2", "q_lag2", "r_lag2"]  # the base columns stay last
    np.testing.assert_array_equal(x[:, -12:-9], lagged(rates, 4))
    np.testing.assert_array_equal(x[:, -9:-6], lagged(rates, 3))
    np.testing.assert_array_equal(x[:, -3:], lagged(rates, 2))
    # the split's guard covers the oldest lag
    assert cfg.history_s(150.0) == pytest.approx(FeatureConfig().history_s(150.0) + 3 / 150.0)
    with pytest.raises(ValueError, match="rate_history_samples"):
        FeatureConfig(rate_history_samples=0)


def test_fit_arx_takes_one_ridge_per_axis():
    z = RNG.normal(size=(300, 5))
    y = z @ RNG.normal(size=(5, 2)) + RNG.normal(0, 0.1, (300, 2))
    both = fit_arx(z, y, [1e-4, 0.3])
    np.testing.assert_allclose(both[0], fit_arx(z, y[:, :1], 1e-4)[0], rtol=1e-10)
    np.testing.assert_allclose(both[1], fit_arx(z, y[:, 1:], 0.3)[0], rtol=1e-10)
    with pytest.raises(ValueError, match="3 ridge values for 2 outputs"):
        fit_arx(z, y, [1e-3] * 3)


def test_choose_arx_ridge_picks_per_axis_on_validation():
    # axis 0: a clean linear map (small ridge wins); axis 1: pure noise (the largest wins).
    # Its own generator (the shared one depends on which tests ran before on this worker),
    # and a margin: 40 features on 200 training rows overfit the noise axis by ~p/n = 20 %
    # of its variance, while 1000 validation rows resolve that to ~3 % (0 of 300 seeds fail).
    rng = np.random.default_rng(11)
    z = rng.normal(size=(1200, 40))
    y = np.column_stack([z @ rng.normal(size=40), rng.normal(size=1200)])
    ridges, table = choose_arx_ridge(z[:200], y[:200], z[200:], y[200:], (1e-4, 1e-1, 1e4))
    assert ridges[0] < 1e-1 and ridges[1] == 1e4
    assert set(table) == {"0.0001", "0.1", "10000.0"} and len(table["0.1"]) == 2


def test_lowpass_within_sets_never_reads_across_a_set_boundary():
    y = RNG.normal(size=(300, 3))
    labels = np.repeat([TRAIN, TEST, VAL], 100)
    a = lowpass_within_sets(y, labels, 150.0)
    np.testing.assert_allclose(a[:100], smoothed_target(y[:100], 150.0))
    y2 = y.copy()
    y2[100:200] += 5.0  # change the test rows only
    b = lowpass_within_sets(y2, labels, 150.0)
    np.testing.assert_array_equal(a[:100], b[:100])
    np.testing.assert_array_equal(a[200:], b[200:])


@pytest.fixture(scope="module")
def flight_path(truth_world_flight):
    return truth_world_flight("still_air_calibration", 5, 60.0)


def _train(flight, seed=2):
    torch.set_num_threads(1)
    return train_net([flight], target="rates", seed=seed, hidden=(8,), adamw=FAST,
                     features=FeatureConfig(rate_history_samples=4),
                     train_target="lowpass", arx_ridge="val")


@pytest.fixture(scope="module")
def lp_net(flight_path):
    return _train(load_net_flight(flight_path))


def test_lowpass_target_val_ridge_and_per_axis_stopping_are_on_the_card(lp_net):
    card = lp_net.card
    assert card["train_target"] == "lowpass" and len(card["arx_ridge"]) == 3
    assert set(card["arx_ridge_val"]) and card["feature_config"]["rate_history_samples"] == 4
    per_axis = card["training"]["best_epoch_per_axis"]
    assert len(per_axis) == 3 and card["training"]["best_epoch"] == max(per_axis)
    # each axis keeps its best validation epoch: no axis ends worse than its linear start
    # (the ARX, or least squares on the time-stretched rows as well where they were used)
    training = card["training"]
    for best, start in zip(training["best_val_mse_per_axis"], training["start_val_mse_per_axis"],
                           strict=True):
        assert best <= start
    if not card["time_stretch"]:
        val = card["metrics"]["val"]["lowpass"]
        for a in "pqr":
            assert val["net"][a]["rms"] <= val["arx"][a]["rms"] * 1.002
    test = card["metrics"]["test"]["measured"]
    assert all(test["net"][a]["rms"] < test["persistence"][a]["rms"] for a in "pqr")


def test_the_options_survive_save_load_predict_and_evaluate(lp_net, flight_path, tmp_path):
    net = load_net(save_net(lp_net, tmp_path / "lp.pt"))
    assert net.card["train_target"] == "lowpass"
    np.testing.assert_array_equal(predict(net, flight_path).to_numpy(),
                                  predict(lp_net, flight_path).to_numpy())
    rep = evaluate_net(net, [load_net_flight(flight_path)])
    assert rep["overall"]["rows"] == lp_net.card["metrics"]["test"]["rows"]


def test_training_reads_no_test_row(lp_net, flight_path):
    # scramble the rates on the test blocks: the ridge choice, the ARX fit and every
    # trained weight must come out identical (features, targets, scaling, early stopping
    # and the ridge search read training and validation rows only)
    flight = load_net_flight(flight_path)
    test = unrle(lp_net.card["training_flights"][0]["labels_rle"]) == TEST
    rates = flight.rates_rad_s.copy()
    rates[test] = RNG.normal(0, 1.0, (int(test.sum()), 3))
    other = _train(dataclasses.replace(flight, rates_rad_s=rates))
    assert other.card["arx_ridge"] == lp_net.card["arx_ridge"]
    for (k, a), b in zip(lp_net.state_dict().items(), other.state_dict().values(), strict=True):
        assert torch.equal(a, b), k
    assert other.card["metrics"]["val"] == lp_net.card["metrics"]["val"]


def test_bad_options_are_refused(flight_path):
    flight = load_net_flight(flight_path)
    with pytest.raises(ValueError, match="train_target"):
        train_net([flight], train_target="truth")
    with pytest.raises(ValueError, match="arx_ridge"):
        train_net([flight], arx_ridge="auto")


def test_pilot_only_features_feed_no_rate_back():
    """use_rates=False (a pilot-only net, eq 2.4's ω′): inputs and attitude only, and
    the rates cannot leak in — changing them changes no feature."""
    inputs, roll, pitch, rates = _signals()
    cfg = FeatureConfig(use_rates=False)
    x, names = build_features(inputs, roll, pitch, rates, 150.0, cfg)
    assert len(names) == 22 and names[-2:] == ["roll", "pitch"]
    x2, _ = build_features(inputs, roll, pitch, rates * -3.0 + 1.0, 150.0, cfg)
    np.testing.assert_array_equal(x, x2)
    assert cfg.history_s(150.0) == pytest.approx(0.5)  # the longest window, no rate lag
    assert FeatureConfig.from_dict(FeatureConfig().to_dict()).use_rates  # old cards: rates fed
