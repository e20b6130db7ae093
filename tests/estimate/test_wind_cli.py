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


BROKEN_PLUGIN = '''
import numpy as np
from airwake.heli import Effect, Parameter, register_effect


@register_effect("stalls_in_wind")
class StallsInWind(Effect):
    """A user's effect that fails once the wind is not still: it raises."""

    PARAMETERS = (Parameter("k", 0.0, "-", (-1.0, 1.0), "test"),)
    REQUIRES = ("rigid_body",)

    def forces(self, ctx, p):
        if np.any(np.abs(np.asarray(ctx.wind_v_m_s)) > 1e-3):
            raise FloatingPointError("the user's drag table has no entry for this airspeed")
        ctx.add_load(self.name, np.zeros((ctx.n, 3)), np.zeros((ctx.n, 3)))
'''


@pytest.fixture(scope="module")
def broken_spec(tmp_path_factory):
    """table52 plus a user plugin that raises on a flight in wind (registered once)."""
    from airwake.heli import load_spec, save_spec
    from airwake.heli.effects.base import effect_class
    from airwake.heli.plugins import load_plugin

    d = tmp_path_factory.mktemp("broken")
    plugin = d / "stalls_in_wind.py"
    plugin.write_text(BROKEN_PLUGIN)
    load_plugin(plugin)
    spec = d / "broken.toml"
    save_spec(load_spec("table52") + effect_class("stalls_in_wind")(), spec)
    return spec


@pytest.mark.parametrize("method", [[], ["--method", "apf", "--particles", "50"]])
def test_a_model_that_does_not_fly_the_flight_is_one_line_and_nothing_is_written(
        tiny_wind_file, broken_spec, tmp_path, capsys, method):
    # a spec whose user plugin raises on this flight: one line naming the flight and the
    # failure, exit status 2, no wind table
    out = tmp_path / "wind.parquet"
    code = main(["wind", "estimate", str(tiny_wind_file), "--model", str(broken_spec),
                 "--out", str(out), *method])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1, err
    assert str(tiny_wind_file) in err and "drag table" in err and not out.exists()
