"""The smoother anchored on a mean flow made without the model (`wind estimate --anchor`):
the anchor's v is a measurement, the model reads the rotation given it, and the model
does not narrow the anchor's interval. On a model-generated flight with a known constant
wind (tests/estimate/conftest.py), where every effect is exact."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from airwake.cli import main
from airwake.estimate.errors import WindEstimationError
from airwake.estimate.wind import estimate_wind
from airwake.heli import WIND_NAMES
from airwake.record.flight_table import write_flight_table

V = WIND_NAMES[:3]
CONSTANT_WIND = (2.0, -1.0, 0.5, 0.1, -0.05, 0.08)  # tests/estimate/conftest.py's


def _anchor_table(t, v, std):
    cols = {"t_s": t}
    for j, n in enumerate(V):
        cols[n] = np.full(t.size, v[j])
        cols[f"{n}_std"] = np.full(t.size, std)
    return pd.DataFrame(cols)


@pytest.fixture(scope="module")
def free(tiny_wind_file):
    return estimate_wind(tiny_wind_file, "table52", em_passes=2, ins_velocity_std=0.0)


def test_a_tight_anchor_sets_the_mean_flow_and_its_interval(tiny_wind_file, free):
    t = free.df["t_s"].to_numpy()
    wrong = np.array(CONSTANT_WIND[:3]) + (0.8, -0.6, 0.4)  # not this flight's wind
    est = estimate_wind(tiny_wind_file, "table52", em_passes=2, ins_velocity_std=0.0,
                        anchor=_anchor_table(t, wrong, 0.01))
    v = est.df[list(V)].to_numpy()
    assert np.abs(v - wrong).max() < 0.03, np.abs(v - wrong).max(axis=0)
    # the free estimate was nowhere near it: the anchor, not the data, put it there
    assert np.abs(free.df[list(V)].to_numpy() - wrong).mean() > 0.3
    # the rotation is read given that mean flow: it moves with it
    w = est.df[list(WIND_NAMES[3:])].to_numpy()
    assert np.abs(w - free.df[list(WIND_NAMES[3:])].to_numpy()).mean() > 1e-3
    # the model does not narrow the anchor's interval (only ever widen it)
    assert (est.df[[f"{n}_std" for n in V]].to_numpy() >= 0.01 - 1e-12).all()
    assert est.metadata["anchor"] == "<table>"


def test_a_loose_anchor_changes_little_and_a_missing_one_nothing(tiny_wind_file, free):
    t = free.df["t_s"].to_numpy()
    loose = estimate_wind(tiny_wind_file, "table52", em_passes=2, ins_velocity_std=0.0,
                          anchor=_anchor_table(t, (0.0, 0.0, 0.0), 100.0))
    assert np.abs(loose.df[list(WIND_NAMES)].to_numpy()
                  - free.df[list(WIND_NAMES)].to_numpy()).max() < 0.02
    # an anchor that covers none of the flight (after it) is refused, not silently empty
    late = _anchor_table(t + 100.0, (0.0, 0.0, 0.0), 0.01)
    with pytest.raises(WindEstimationError, match="no sample has a finite"):
        estimate_wind(tiny_wind_file, "table52", em_passes=2, anchor=late)


def test_the_cli_anchors_on_a_wind_table_and_says_what_it_cannot(tiny_wind_file, free,
                                                                 tmp_path, capsys):
    import warnings

    t = free.df["t_s"].to_numpy()
    anchor = tmp_path / "net.parquet"
    table = _anchor_table(t, CONSTANT_WIND[:3], 0.05)
    for n in WIND_NAMES[3:]:  # a still-air net's table: no rotation
        table[n] = table[f"{n}_std"] = np.nan
    write_flight_table(table, anchor, {})
    out = tmp_path / "w.parquet"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert main(["wind", "estimate", str(tiny_wind_file), "--anchor", str(anchor),
                     "--em-passes", "2", "--out", str(out), "--json"]) == 0
    assert not [w for w in caught if "_rad_s" in str(w.message)], caught  # not read
    report = json.loads(capsys.readouterr().out)
    assert report["method"] == "smoother" and out.is_file()
    assert report["anchor"] == str(anchor) and "crlb" not in report
    # not a wind table, the wrong method: named, nothing written
    bad = tmp_path / "bad.parquet"
    write_flight_table(pd.DataFrame({"t_s": t, "x": t}), bad, {})
    out2 = tmp_path / "w2.parquet"
    assert main(["wind", "estimate", str(tiny_wind_file), "--anchor", str(bad), "--out",
                 str(out2)]) == 2
    assert "not a wind table" in capsys.readouterr().err and not out2.exists()
    assert main(["wind", "estimate", str(tiny_wind_file), "--anchor", str(anchor),
                 "--method", "apf", "--out", str(out2)]) == 2
    assert "--anchor is for --method smoother" in capsys.readouterr().err
    assert not out2.exists()


def test_an_anchor_file_with_a_dropout_is_read_and_its_own_ins_error_taken_out(
        tiny_wind_file, free, tmp_path):
    # a real net's table can have NaN stretches (no anchor there); its std carries the INS
    # error of the flight it was made on (its metadata), which the smoother adds itself
    t = free.df["t_s"].to_numpy()
    table = _anchor_table(t, CONSTANT_WIND[:3], 0.05)
    table.loc[5:10, list(V)] = np.nan
    path = tmp_path / "dropout.parquet"
    write_flight_table(table, path, {"ins_velocity_std_m_s": 0.03})
    est = estimate_wind(tiny_wind_file, "table52", em_passes=2, ins_velocity_std=0.0,
                        anchor=path)
    std = est.df[[f"{n}_std" for n in V]].to_numpy()
    assert np.isfinite(est.df[list(WIND_NAMES)].to_numpy()).all()
    # the floor is the anchor's std less its own INS error: sqrt(0.05^2 - 0.03^2) = 0.04
    assert std.min() == pytest.approx(0.04, abs=1e-6)
    # and the rotation's interval carries the anchor's error as a steady offset
    assert est.metadata["anchor_offset_std"] == pytest.approx([0.04] * 3)
