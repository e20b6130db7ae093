"""Direct wind networks (§4.6): trained on one simulated ship flight's truth, they follow
the wind of another flight better than its own mean does."""

import json

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


def test_the_cli_trains_a_wind_net_whose_estimate_scores_and_maps(truth_world_flight, tmp_path,
                                                                  capsys):
    # `nets train --target wind` -> `wind estimate --method net --score` -> `wind map`: the
    # net's estimate is a wind table like the smoother's, scored on a flight it never saw
    from airwake.cli import main

    train, unseen = (truth_world_flight("ship_airwake_b15", 6, 60.0),
                     truth_world_flight("ship_airwake_b0", 5, 60.0))
    net = tmp_path / "wind.pt"
    assert main(["nets", "train", str(train), "--target", "wind", "--out", str(net),
                 "--quiet", "--json"]) == 0
    card = json.loads(capsys.readouterr().out)
    assert card["target"] == "wind" and card["training_flights"][0]["path"] == str(train)
    est = tmp_path / "wind.parquet"
    assert main(["wind", "estimate", str(unseen), "--method", "net", "--net", str(net),
                 "--score", "--out", str(est), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["held_out"] is True and report["samples"] > 60 * 100
    comp = report["score"]["components"]["wind_wy_rad_s"]
    assert comp["error_rms"] < 0.6 * comp["truth_std"], comp
    # the same numbers as the Python API's score on the same samples
    direct = score_against_truth(predict_wind(load_net(net), unseen), unseen, burn_in_s=2.0)
    assert comp["error_rms"] == pytest.approx(direct["wind_wy_rad_s"]["rms"], rel=1e-6)
    # std = the net's validation RMS (+ INS error on v): what the map weighs samples by
    df = pd.read_parquet(est)
    val = card["validation_rms"]["wind_wy_rad_s"]["net"]
    assert np.allclose(df["wind_wy_rad_s_std"], val)
    assert main(["wind", "map", str(est), "--flight", str(unseen), "--out",
                 str(tmp_path / "map"), "--min-seconds", "0.5"]) == 0
    assert (tmp_path / "map" / "map.parquet").is_file()
    # on its own training flight the report says the score is not held out
    capsys.readouterr()
    assert main(["wind", "estimate", str(train), "--method", "net", "--net", str(net),
                 "--out", str(tmp_path / "own.parquet")]) == 0
    assert "this flight trained the net" in capsys.readouterr().out


def test_wind_net_cli_refuses_what_does_not_apply(truth_world_flight, tmp_path, capsys):
    from airwake.cli import main

    flight = str(truth_world_flight("ship_airwake_b0", 5, 60.0))
    assert main(["nets", "train", flight, "--target", "wind", "--rate-lag", "2", "--out",
                 str(tmp_path / "w.pt")]) == 2
    assert "--rate-lag do not apply to a wind net" in capsys.readouterr().err
    assert not (tmp_path / "w.pt").exists()
    assert main(["wind", "estimate", flight, "--method", "net", "--out",
                 str(tmp_path / "w.parquet")]) == 2
    assert "--method net needs --net" in capsys.readouterr().err
    assert not (tmp_path / "w.parquet").exists()
