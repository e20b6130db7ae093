"""`airwake nets train|evaluate` end to end, and the one-line errors users see."""

import json

import numpy as np
import pandas as pd
import pytest
from airwake.cli import main


@pytest.fixture(scope="module")
def flight(truth_world_flight):
    return truth_world_flight("still_air_calibration", 5, 60.0)


def test_train_then_evaluate_writes_net_report_and_predictions(flight, tmp_path, capsys):
    net = tmp_path / "rates.pt"
    assert main(["nets", "train", str(flight), "--out", str(net), "--seed", "1", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "held-out test rows (the last 20 %)" in out and "persistence" in out and net.is_file()
    assert "net/arx" in out and "net/persist" in out
    pred = tmp_path / "pred.parquet"
    assert main(["nets", "evaluate", str(net), str(flight), "--json", "--out", str(pred)]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["unit"] == "deg/s" and report["flights"][0]["scored"].startswith("test rows")
    rms = report["overall"]["measured"]["net"]
    assert set(rms) == {"p", "q", "r"} and all(np.isfinite(v["rms"]) for v in rms.values())
    df = pd.read_parquet(pred)
    assert list(df.columns[:4]) == ["t_s", "p_pred_rad_s", "q_pred_rad_s", "r_pred_rad_s"]
    assert len(df) == len(pd.read_parquet(flight))


def test_missing_column_is_one_line_naming_file_and_column(flight, tmp_path, capsys):
    df = pd.read_parquet(flight).drop(columns=["roll_rad"])
    bad = tmp_path / "no_roll.csv"
    df.to_csv(bad, index=False)
    assert main(["nets", "train", str(bad), "--out", str(tmp_path / "x.pt"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "no_roll.csv" in err and "'roll_rad'" in err


def test_bad_out_path_and_bad_net_file_are_user_errors(flight, tmp_path, capsys):
    assert main(["nets", "train", str(flight), "--out", str(tmp_path / "no" / "x.pt")]) == 2
    assert "--out" in capsys.readouterr().err
    junk = tmp_path / "junk.pt"
    junk.write_bytes(b"not a torch file")
    assert main(["nets", "evaluate", str(junk), str(flight)]) == 2
    assert "junk.pt: not a network file" in capsys.readouterr().err


def test_train_options_reach_the_card(flight, tmp_path, capsys):
    """--rate-lag/--rate-history/--train-target/--arx-ridge val/--per-axis, and
    --pilot-only with a fixed ridge (30 s of the flight: option plumbing, not accuracy)."""
    net = tmp_path / "opts.pt"
    assert main(["nets", "train", str(flight), "--out", str(net), "--to-s", "30", "--quiet",
                 "--json", "--rate-lag", "2", "--rate-history", "3", "--train-target", "lowpass",
                 "--arx-ridge", "val", "--per-axis"]) == 0
    card = json.loads(capsys.readouterr().out)
    assert card["feature_config"]["rate_lag_samples"] == 2
    assert card["feature_config"]["rate_history_samples"] == 3
    assert card["features"][-3:] == ["p_lag2", "q_lag2", "r_lag2"] and "p_lag4" in card["features"]
    assert card["train_target"] == "lowpass" and "arx_ridge_val" in card
    assert card["trainer_settings"]["per_axis"] and "best_epoch_per_axis" in card["training"]
    pilot = tmp_path / "pilot.pt"
    assert main(["nets", "train", str(flight), "--out", str(pilot), "--to-s", "30", "--quiet",
                 "--json", "--pilot-only", "--arx-ridge", "0.01", "--max-epochs", "0",
                 "--time-stretch", "none", "--split", "blocks", "--block-s", "4"]) == 0
    card = json.loads(capsys.readouterr().out)
    assert card["training"]["epochs_run"] == 0 and card["trainer_settings"]["max_epochs"] == 0
    assert card["feature_config"]["use_rates"] is False and card["arx_ridge"] == [0.01] * 3
    assert card["time_stretch"] == [] and card["split"] == {
        "order": "blocks", "block_s": 4.0, "val_fraction": 0.15, "test_fraction": 0.2}
    assert not any(f.startswith(("p_", "q_", "r_")) for f in card["features"])
    from airwake.nets import load_net

    net = load_net(pilot)
    assert net.base_columns is None
    x = np.random.default_rng(0).normal(size=(5, net.n_features))
    np.testing.assert_allclose(net.predict_numpy(x), net.predict_arx(x), rtol=1e-5, atol=1e-6)
    assert main(["nets", "evaluate", str(pilot), str(flight), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert np.isfinite(report["overall"]["measured"]["net"]["p"]["rms"])


@pytest.mark.parametrize("extra, words", [
    (["--arx-ridge", "lots"], "--arx-ridge"),
    (["--arx-ridge", "-1"], "arx_ridge"),
    (["--pilot-only", "--rate-lag", "5"], "--pilot-only"),
    (["--rate-history", "0"], "rate_history_samples"),
    (["--max-epochs", "-1"], "--max-epochs"),
    (["--time-stretch", "1.0"], "--time-stretch"),
    (["--time-stretch", "fast"], "--time-stretch"),
    (["--block-s", "4"], "--split blocks"),
])
def test_bad_train_options_are_one_line_errors(flight, tmp_path, capsys, extra, words):
    assert main(["nets", "train", str(flight), "--out", str(tmp_path / "x.pt"), "--quiet",
                 *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and words in err
