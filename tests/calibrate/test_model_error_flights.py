"""`airwake model error`: the model's steady misfit pooled over still-air flights (the
calibration flight and cruise legs) into its spec, which makes the wind estimate hold it
as states (docs/wind-estimation.md "The model's slow misfit as states"). On the truth
world's still-air flights and the documented calibration (tests/conftest.py)."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest
from airwake.calibrate import model_error, model_error_over
from airwake.cli import main
from airwake.estimate.wind import default_model_error, estimate_wind
from airwake.heli import load_spec, spec_calibration


@pytest.fixture(scope="module")
def flights(truth_world_flight):
    return (truth_world_flight("still_air_calibration", 71, 40.0),
            truth_world_flight("still_air_cruise", 72, 40.0))


def test_pooling_is_over_the_flights_blocks_and_samples(flights, wind_baseline, tmp_path):
    cal, cruise = flights
    each: list = []
    rms, offset = model_error_over(wind_baseline, [cal, cruise], per_flight=each)
    # each flight's own figures are model_error's on it
    for path, (r, o) in zip((cal, cruise), each, strict=True):
        r1, o1 = model_error(wind_baseline, path)
        np.testing.assert_allclose(r, r1, rtol=1e-12)
        np.testing.assert_allclose(o, o1, rtol=1e-12)
    # a pooled RMS lies between the flights' own, channel by channel
    lo = np.minimum(each[0][1], each[1][1])
    hi = np.maximum(each[0][1], each[1][1])
    assert np.all(offset >= lo - 1e-12) and np.all(offset <= hi + 1e-12)
    lo = np.minimum(each[0][0], each[1][0])
    hi = np.maximum(each[0][0], each[1][0])
    assert np.all(rms >= lo - 1e-12) and np.all(rms <= hi + 1e-12)
    # the same flight twice pools to itself
    twin = tmp_path / "twin.parquet"
    shutil.copy(cal, twin)
    np.testing.assert_allclose(model_error_over(wind_baseline, [cal, twin])[1], each[0][1],
                               rtol=1e-12)


def test_the_command_writes_the_pooled_offset_and_the_estimate_holds_it_as_states(
        flights, wind_baseline, tmp_path, capsys):
    cal, cruise = flights
    out = tmp_path / "wind.toml"
    assert main(["model", "error", str(cal), str(cruise), "--model", str(wind_baseline),
                 "--out", str(out), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    table, before = spec_calibration(out), spec_calibration(wind_baseline)
    assert table["model_error_offset_flights"] == [str(cal), str(cruise)]
    assert table["model_error_offset"] == pytest.approx(report["model_error_offset"])
    assert report["offset_before"] == pytest.approx(before["model_error_offset"])
    assert set(report["flights"]) == {str(cal), str(cruise)}
    # the noise floor stays the calibration flight's; the model is the same
    assert table["model_error_std"] == before["model_error_std"]
    assert load_spec(out) == load_spec(wind_baseline)
    # and its still-air wind error was measured again, for the estimator it now gets
    assert len(table["still_air_wind_error"]["anchored"]) == 6
    assert default_model_error(out) == "states"
    assert default_model_error(wind_baseline) == "consider"
    est = estimate_wind(cruise, out, em_passes=1)
    assert est.metadata["model_error"] == "states"
    assert est.metadata["channel_bias"]["sigma"] == pytest.approx(table["model_error_offset"])
    # the table a user reads
    assert main(["model", "error", str(cal), str(cruise), "--model", str(wind_baseline),
                 "--out", str(tmp_path / "again.toml")]) == 0
    text = capsys.readouterr().out
    assert "pooled (written)" in text and "rdot" in text


def test_bad_flights_are_named_and_nothing_is_written(flights, wind_baseline, tmp_path,
                                                      capsys):
    cal, _ = flights
    out = tmp_path / "bad.toml"
    assert main(["model", "error", str(cal), str(cal), "--model", str(wind_baseline),
                 "--out", str(out)]) == 2
    assert "given twice" in capsys.readouterr().err and not out.exists()
    missing = tmp_path / "nowhere.parquet"
    assert main(["model", "error", str(cal), str(missing), "--model", str(wind_baseline),
                 "--out", str(out)]) == 2
    assert "nowhere.parquet" in capsys.readouterr().err and not out.exists()
