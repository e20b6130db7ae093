"""`airwake wind estimate`: output table, score, and errors as one clear line."""

import json

import numpy as np
import pandas as pd
import pytest
from airwake.cli import main
from airwake.heli import WIND_NAMES
from airwake.record.flight_table import TRUTH_WIND, load_flight_table, write_flight_table

FAST = ["--method", "apf", "--cutoff-hz", "0", "--particles", "100"]


def test_estimate_writes_parquet_with_metadata_and_scores(tiny_wind_file, tmp_path, capsys):
    out = tmp_path / "wind.parquet"
    code = main(["wind", "estimate", str(tiny_wind_file), "--out", str(out), "--score",
                 "--burn-in-s", "1", "--json", "--seed", "3", *FAST])
    assert code == 0
    rep = json.loads(capsys.readouterr().out)
    ft = load_flight_table(out, required=("t_s",))
    assert [c for c in ft.df.columns if c in WIND_NAMES] == list(WIND_NAMES)
    assert all(f"{n}_std" in ft.df for n in WIND_NAMES)
    assert ft.metadata["particles"] == 100 and ft.metadata["seed"] == 3
    assert ft.metadata["resampler"] == "systematic"
    comps = rep["score"]["components"]
    assert set(comps) == set(WIND_NAMES)
    assert comps["wind_vx_m_s"]["table_5_3_std"] == pytest.approx(0.4761)
    assert comps["wind_wz_rad_s"]["table_5_3_std"] == pytest.approx(0.0645)
    assert np.isfinite(comps["wind_vx_m_s"]["error_std"])


def test_text_output_prints_the_table_5_3_comparison(tiny_wind_file, tmp_path, capsys):
    out = tmp_path / "wind.parquet"
    assert main(["wind", "estimate", str(tiny_wind_file), "--out", str(out), "--score",
                 "--burn-in-s", "1", "--resampler", "roulette", *FAST]) == 0
    text = capsys.readouterr().out
    assert "5.3 std" in text and "wind_wy_rad_s" in text and f"wrote {out}" in text


def test_score_without_truth_columns_fails_before_the_run(tiny_wind_file, tmp_path, capsys):
    df = pd.read_parquet(tiny_wind_file).drop(columns=list(TRUTH_WIND))
    path = tmp_path / "user.csv"
    df.to_csv(path, index=False)
    out = tmp_path / "wind.parquet"
    assert main(["wind", "estimate", str(path), "--out", str(out), "--score", *FAST]) == 2
    err = capsys.readouterr().err.strip()
    assert "truth_wind_vx_m_s" in err and len(err.splitlines()) == 1
    assert not out.exists()


def test_missing_column_is_one_line_naming_it(tiny_wind_file, tmp_path, capsys):
    df = pd.read_parquet(tiny_wind_file).drop(columns=["rdot_rad_s2"])
    path = tmp_path / "broken.parquet"
    write_flight_table(df, path)
    out = tmp_path / "wind.parquet"
    assert main(["wind", "estimate", str(path), "--out", str(out), *FAST]) == 2
    err = capsys.readouterr().err
    assert "rdot_rad_s2" in err and not out.exists()


def test_bad_sigma_and_output_suffix_are_errors(tiny_wind_file, tmp_path, capsys):
    assert main(["wind", "estimate", str(tiny_wind_file), "--out", str(tmp_path / "w.parquet"),
                 "--sigma", "-1", *FAST]) == 2
    assert "sigma" in capsys.readouterr().err
    assert main(["wind", "estimate", str(tiny_wind_file), "--out", str(tmp_path / "w.txt"),
                 *FAST]) == 2
    assert "w.txt" in capsys.readouterr().err


def test_bare_wind_group_prints_its_help(capsys):
    assert main(["wind"]) == 2
    assert "estimate" in capsys.readouterr().err


def test_a_model_that_does_not_fly_is_one_line_and_nothing_is_written(tiny_wind_file,
                                                                      tmp_path, capsys):
    # a blade without lift (Lock number ~0): refused where the spec loads, by the effect's
    # bounds, naming the parameter; one line, exit status 2, no table written
    bad = tmp_path / "broken.toml"
    text = (__import__("airwake.heli.spec", fromlist=["builtin_spec"]).builtin_spec("table52")
            .read_text().replace("lock_number = 3.3933", "lock_number = 1e-300"))
    bad.write_text(text)
    out = tmp_path / "wind.parquet"
    code = main(["wind", "estimate", str(tiny_wind_file), "--model", str(bad), "--out",
                 str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1, err
    assert ("lock_number" in err or "model" in err) and not out.exists()
