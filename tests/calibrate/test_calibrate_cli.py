"""`airwake calibrate`: output, JSON, and bad input as one clear line with no spec written."""

import json

import numpy as np
import pandas as pd
import pytest
from airwake.cli import main
from airwake.heli import load_spec
from airwake.record.flight_table import load_flight_table, write_flight_table

FAST = ["--params", "rigid_body.I*", "--max-nfev", "4", "--window-s", "1", "--warmup-s", "0.5"]


def test_calibrate_writes_a_loadable_spec_and_reports_json(short_flight_file, tmp_path, capsys):
    out = tmp_path / "fitted.toml"
    assert main(["calibrate", str(short_flight_file), "--out", str(out), "--json", *FAST]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["method"] == "lsq" and rep["spec"] == str(out)
    assert len(rep["rms_before"]) == len(rep["rms_after"]) == 6
    assert set(rep["parameters"]) == {"rigid_body.Ixx_kg_m2", "rigid_body.Iyy_kg_m2",
                                      "rigid_body.Izz_kg_m2", "rigid_body.Ixz_kg_m2"}
    fitted = load_spec(out)
    for name, p in rep["parameters"].items():
        assert fitted.parameter_vector()[fitted.parameter_names.index(name)] == p["value"]
    assert rep["rms_after_all"] <= rep["rms_before_all"]


def test_calibrate_text_report_has_the_channel_table(short_flight_file, tmp_path, capsys):
    out = tmp_path / "fitted.toml"
    assert main(["calibrate", str(short_flight_file), "--out", str(out), *FAST]) == 0
    text = capsys.readouterr().out
    for word in ("acc_x_m_s2", "rdot_rad_s2", "rms before", "rms after", "1-sigma",
                 "rigid_body.Ixx_kg_m2", f"wrote {out}"):
        assert word in text


def _broken(tmp_path, src, edit, name="broken.csv"):
    ft = load_flight_table(src)
    df = edit(ft.df.copy())
    path = tmp_path / name
    if name.endswith(".csv"):
        df.to_csv(path, index=False)
    else:
        write_flight_table(df, path)
    return path


@pytest.mark.parametrize("edit,message", [
    (lambda df: df.drop(columns=["q_rad_s"]), "q_rad_s"),
    (lambda df: df.assign(acc_x_m_s2=np.where(np.arange(len(df)) == 7, np.nan, df.acc_x_m_s2)),
     "acc_x_m_s2"),
])
def test_bad_flight_is_one_line_naming_the_column_and_no_spec(short_flight_file, tmp_path,
                                                              capsys, edit, message):
    path = _broken(tmp_path, short_flight_file, edit)
    out = tmp_path / "never.toml"
    assert main(["calibrate", str(path), "--out", str(out), *FAST]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("airwake calibrate: error:") and message in err
    assert len(err.splitlines()) == 1
    assert not out.exists() and not list(tmp_path.glob(".never*"))


def test_unknown_parameter_name_is_an_error_listing_the_known_ones(short_flight_file, tmp_path,
                                                                  capsys):
    out = tmp_path / "never.toml"
    code = main(["calibrate", str(short_flight_file), "--out", str(out),
                 "--params", "main_rotor.lok_number"])
    assert code == 2
    err = capsys.readouterr().err
    assert "lok_number" in err and "main_rotor.lock_number" in err
    assert not out.exists()


def test_missing_output_directory_is_an_error_before_any_work(short_flight_file, tmp_path,
                                                              capsys):
    out = tmp_path / "no" / "such" / "dir.toml"
    assert main(["calibrate", str(short_flight_file), "--out", str(out), *FAST]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_missing_flight_file_is_an_error(tmp_path, capsys):
    assert main(["calibrate", str(tmp_path / "nope.parquet"), "--out",
                 str(tmp_path / "x.toml")]) == 2
    assert "nope.parquet" in capsys.readouterr().err


def test_unknown_model_spec_is_an_error(short_flight_file, tmp_path, capsys):
    assert main(["calibrate", str(short_flight_file), "--model", "table99", "--out",
                 str(tmp_path / "x.toml"), *FAST]) == 2
    assert "table99" in capsys.readouterr().err


def test_non_increasing_time_is_an_error(short_flight_file, tmp_path, capsys):
    def dup(df: pd.DataFrame):
        df.loc[10, "t_s"] = df.loc[9, "t_s"]
        return df

    path = _broken(tmp_path, short_flight_file, dup)
    assert main(["calibrate", str(path), "--out", str(tmp_path / "x.toml"), *FAST]) == 2
    assert "t_s" in capsys.readouterr().err
