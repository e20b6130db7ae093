"""Direct wind networks (§4.6): trained on one simulated ship flight's truth, they follow
the wind of another flight better than its own mean does."""

import numpy as np
import pandas as pd
import pytest
from airwake.nets import load_net, save_net
from airwake.nets.model import NetFileError
from airwake.nets.wind_net import WIND_OUTPUTS, predict_wind, score_against_truth, train_wind_net


@pytest.fixture(scope="module")
def wind_net(truth_world_flight):
    return train_wind_net([truth_world_flight("ship_airwake_b15", 6, 60.0)], seed=0)


def test_wind_net_beats_the_flights_own_mean_on_an_unseen_flight(wind_net, truth_world_flight):
    # a net that learnt nothing would score the truth's own std (a constant at its mean)
    path = truth_world_flight("ship_airwake_b0", 5, 60.0)
    est = predict_wind(wind_net, path)
    score = score_against_truth(est, path)
    df = pd.read_parquet(path)
    # one 60 s training flight teaches the pitch vorticity (§4.6's quantity: 0.08 against a
    # std of 0.15 1/s), not yet the rest; docs/networks.md's table trains on 8 x 150 s
    comp = "wind_wy_rad_s"
    assert score[comp]["rms"] < 0.6 * df[f"truth_{comp}"].std()
    assert all(np.isfinite(score[c]["rms"]) for c in WIND_OUTPUTS)


def test_wind_net_round_trips_its_file_and_is_deterministic(wind_net, truth_world_flight,
                                                            tmp_path):
    path = truth_world_flight("ship_airwake_b0", 5, 60.0)
    loaded = load_net(save_net(wind_net, tmp_path / "wind.pt"))
    assert loaded.card["target"] == "wind"
    a = predict_wind(wind_net, path)
    assert np.allclose(predict_wind(loaded, path)[list(WIND_OUTPUTS)], a[list(WIND_OUTPUTS)])
    again = train_wind_net([truth_world_flight("ship_airwake_b15", 6, 60.0)], seed=0)
    assert np.array_equal(predict_wind(again, path)[list(WIND_OUTPUTS)].to_numpy(),
                          a[list(WIND_OUTPUTS)].to_numpy())


def test_a_rate_net_is_not_a_wind_net(truth_world_flight, wind_net):
    wind_net.card = {**wind_net.card, "target": "rates"}
    try:
        with pytest.raises(NetFileError, match="not a wind net"):
            predict_wind(wind_net, truth_world_flight("ship_airwake_b0", 5, 60.0))
    finally:
        wind_net.card["target"] = "wind"
