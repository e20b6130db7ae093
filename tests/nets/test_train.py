"""Training, saving and applying the pilot-compensation nets on a truth-world flight
(seed 5, 60 s of the still-air calibration scenario; not the seeds docs/networks.md
reports)."""

import pickle

import numpy as np
import pytest
import torch
from airwake.nets import (
    AdamWConfig,
    NetFileError,
    PSOConfig,
    SplitConfig,
    evaluate_net,
    load_net,
    load_net_flight,
    predict,
    save_net,
    train_net,
)

FAST = AdamWConfig(max_epochs=30, patience=10)


@pytest.fixture(scope="module")
def flight_path(truth_world_flight):
    return truth_world_flight("still_air_calibration", 5, 60.0)


@pytest.fixture(scope="module")
def rate_net(flight_path):
    torch.set_num_threads(1)
    return train_net([load_net_flight(flight_path)], target="rates", seed=3, adamw=FAST)


def _test_rms(net, model):
    return np.array([v["rms"] for v in net.card["metrics"]["test"]["measured"][model].values()])


def test_rate_net_beats_persistence_on_every_axis_of_held_out_blocks(rate_net):
    # persistence (the fed-back previous rate alone) is what a net that ignored the pilot
    # inputs would score; the test blocks were never trained or early-stopped on
    assert rate_net.card["metrics"]["test"]["rows"] > 600
    assert np.all(_test_rms(rate_net, "net") < _test_rms(rate_net, "persistence"))
    assert np.all(_test_rms(rate_net, "net") < 2.0)  # deg/s, the target


def test_training_is_deterministic_for_a_seed(flight_path, rate_net):
    again = train_net([load_net_flight(flight_path)], target="rates", seed=3, adamw=FAST)
    for (k, a), b in zip(rate_net.state_dict().items(), again.state_dict().values(), strict=True):
        assert torch.equal(a, b), k
    assert again.card["metrics"] == rate_net.card["metrics"]


def test_card_records_features_windows_flights_and_versions(rate_net, flight_path):
    card = rate_net.card
    assert card["features"][:3] == ["lat_slope", "lat_intercept", "lat_fit_error"]
    assert card["feature_config"]["line_window_s"] == 0.5 and card["input_source"] == "delta"
    assert card["training_flights"][0]["path"] == str(flight_path)
    assert set(card["versions"]) >= {"torch", "numpy", "airwake"}
    assert card["training"]["best_epoch"] <= card["training"]["epochs_run"]


def test_saved_net_loads_without_pickle_and_predicts_the_same(rate_net, flight_path, tmp_path):
    path = save_net(rate_net, tmp_path / "rates.pt")
    torch.load(path, weights_only=True)  # plain tensors and strings only
    net = load_net(path)
    assert net.card["metrics"] == rate_net.card["metrics"]
    a, b = predict(rate_net, flight_path), predict(net, flight_path)
    np.testing.assert_array_equal(a.to_numpy(), b.to_numpy())
    assert list(a.columns[:4]) == ["t_s", "p_pred_rad_s", "q_pred_rad_s", "r_pred_rad_s"]
    flight = load_net_flight(flight_path)
    np.testing.assert_allclose(a["q_resid_rad_s"], flight.rates_rad_s[:, 1] - a["q_pred_rad_s"])


def test_a_pickled_object_is_refused(tmp_path):
    class Evil:
        def __reduce__(self):
            return (print, ("pickle ran",))

    p = tmp_path / "evil.pt"
    p.write_bytes(pickle.dumps({"format": "airwake-net/1", "x": Evil()}))
    with pytest.raises(NetFileError, match="evil.pt: not a network file"):
        load_net(p)
    with pytest.raises(NetFileError, match="not found"):
        load_net(tmp_path / "none.pt")


def test_evaluate_scores_only_the_test_rows_of_a_training_flight(rate_net, flight_path):
    rep = evaluate_net(rate_net, [load_net_flight(flight_path)])
    f = rep["flights"][0]
    assert f["scored"].startswith("test rows") and rep["unit"] == "deg/s"
    assert f["rows"] == rate_net.card["metrics"]["test"]["rows"]
    card = rate_net.card["metrics"]["test"]["measured"]["net"]
    for axis in "pqr":
        assert f["measured"]["net"][axis]["rms"] == pytest.approx(card[axis]["rms"])
    # a simulated flight scores itself against its noise-free truth too; a real one cannot
    assert set(f["truth"]) == {"net", "arx", "persistence"}
    from airwake.nets.data import read_table

    df = read_table(flight_path)
    no_truth = df.drop(columns=[c for c in df.columns if c.startswith("truth_")])
    from airwake.nets import net_flight_from_df

    assert "truth" not in evaluate_net(rate_net, [net_flight_from_df(no_truth)])["overall"]


def test_a_net_refuses_a_flight_at_another_rate(rate_net, flight_path):
    from airwake.nets.data import read_table
    from airwake.record.flight_table import FlightTableError

    df = read_table(flight_path).iloc[::2].reset_index(drop=True)
    with pytest.raises(FlightTableError, match="sampled at 75 Hz.*trained at 150 Hz"):
        predict(rate_net, df)


def test_pso_trainer_starts_at_arx_and_only_improves_its_cost(flight_path):
    flight = load_net_flight(flight_path)
    # (no time-stretched rows: the linear start is then the ARX itself)
    net = train_net([flight], target="rates", trainer="pso", seed=1, hidden=(4, 2),
                    pso=PSOConfig(particles=12, iterations=15, cost_rows=400, patience=15),
                    time_stretch=())
    hist = net.card["training"]["cost_history"]
    assert np.all(np.diff(hist) <= 0) and net.card["training"]["inertia"] == 0.2
    # never worse than the ARX start on validation: the swarm's first particle is it
    val = net.card["metrics"]["val"]["measured"]
    assert all(val["net"][a]["rms"] <= val["arx"][a]["rms"] * 1.0001 for a in "pqr")


def test_accel_net_learns_roll_and_pitch_acceleration(flight_path):
    flight = load_net_flight(flight_path, target="accel")
    net = train_net([flight], target="accel", seed=2, adamw=FAST,
                    split=SplitConfig(order="blocks", block_s=4.0))
    test = net.card["metrics"]["test"]
    assert net.card["outputs"] == ["pdot_rad_s2", "qdot_rad_s2"] and test["rows"] > 600
    rows = evaluate_net(net, [flight])["flights"][0]["rows"]
    assert rows == test["rows"]
    for k, axis in enumerate(("pdot", "qdot")):
        # well inside the spread of the target itself (a net that learned nothing: ~0.8 std)
        spread = np.std(flight.accel_rad_s2[:, k])
        assert test["measured"]["net"][axis]["mae"] < 0.5 * spread
