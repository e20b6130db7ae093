"""`airwake windmap`: outputs, --json, --score, and one-line errors with nothing written."""

import json

import pandas as pd
from airwake.cli import main
from airwake.record.flight_table import write_flight_table


def test_windmap_json_writes_grid_pngs_and_summary(survey, tmp_path, capsys):
    _, path = survey
    out = tmp_path / "map"
    assert main(["windmap", str(path), "--out", str(out), "--score", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["score"]["map_within_target"]
    assert summary["model_error"]["eq_3_15"]["points"] == summary["grid_points"]
    for name in ("grid.parquet", "locations.parquet", "summary.json", *summary["figures"]):
        assert (out / name).is_file(), name
    assert any(f.startswith("slice_z") for f in summary["figures"])
    grid = pd.read_parquet(out / "grid.parquet")
    assert {"u_m_s", "m12_u_m_s", "m6_u_m_s", "du_dx_1_s", "wz_rad_s", "sigma_m_s",
            "m12_error_pct", "sampled"} <= set(grid.columns)
    # a second run replaces the earlier map
    assert main(["windmap", str(path), "--out", str(out), "--json"]) == 0
    assert "score" not in json.loads(capsys.readouterr().out)


def _table(tmp_path, df, meta=None):
    p = tmp_path / "t.parquet"
    write_flight_table(df, p, meta or {})
    return p


def test_table_without_anemometer_is_one_line_and_writes_nothing(tmp_path, capsys):
    p = _table(tmp_path, pd.DataFrame({"t_s": [0.0, 0.01], "truth_pos_n_m": [0.0, 0.0]}))
    out = tmp_path / "map"
    assert main(["windmap", str(p), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "anemo_u_m_s" in err and len(err.splitlines()) == 1
    assert not out.exists()
    assert [x.name for x in tmp_path.iterdir()] == ["t.parquet"]


def test_table_without_pose_is_one_line_and_keeps_the_earlier_map(survey, tmp_path, capsys):
    table, _ = survey
    anemo = table.df[["t_s", "anemo_u_m_s", "anemo_v_m_s", "anemo_w_m_s"]].head(100)
    p = _table(tmp_path, anemo)
    out = tmp_path / "map"
    out.mkdir()
    (out / "summary.json").write_text("{}")
    assert main(["windmap", str(p), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "no anemometer pose" in err and "marker_pos_n_m" in err
    assert len(err.splitlines()) == 1
    assert [x.name for x in out.iterdir()] == ["summary.json"]


def test_score_of_a_table_that_is_not_simulated_says_so(survey, tmp_path, capsys):
    table, _ = survey
    p = _table(tmp_path, table.df.iloc[::4].reset_index(drop=True),
               {"anemometer_lever_arm_m": table.metadata["anemometer_lever_arm_m"]})
    assert main(["windmap", str(p), "--out", str(tmp_path / "m"), "--score"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--score" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "m").exists()


def test_refuses_to_replace_a_directory_that_is_not_a_map(survey, tmp_path, capsys):
    _, path = survey
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep")
    assert main(["windmap", str(path), "--out", str(out)]) == 2
    assert "refusing" in capsys.readouterr().err
    assert (out / "notes.txt").read_text() == "keep"


def test_sim_survey_writes_a_table_windmap_reads(tmp_path, capsys):
    out = tmp_path / "survey.parquet"
    assert main(["sim", "survey", "--out", str(out), "--dwell-s", "1", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["stations"] == 364 and summary["rows"] > 364 * 100
    from airwake.record.flight_table import load_flight_table

    t = load_flight_table(out, required=("t_s", "anemo_u_m_s", "truth_yaw_rad"))
    assert t.metadata["anemometer_lever_arm_m"] == [0.05, 0.0, -0.3]
    assert t.metadata["scenario_config"]["wind"]["type"] == "fans_indoor"
