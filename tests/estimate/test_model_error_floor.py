"""Model error is not wind: a calibrated spec carries its still-air misfit per channel
(`[calibration] model_error_std`), and the smoother never learns a channel noise below
it, so a misfit the model already has in still air cannot be explained as turbulence."""

from __future__ import annotations

import json

import numpy as np
import pytest
from airwake.cli import main
from airwake.estimate.errors import WindEstimationError
from airwake.estimate.wind import estimate_wind, model_error_floor
from airwake.heli import load_model, save_spec


def spec_with_floor(path, floor):
    save_spec(load_model("table52"), path, description="test",
              calibration={"flight": "x", "model_error_std": list(floor)})
    return path


def test_the_smoother_learns_no_noise_below_the_model_error(tiny_wind_file, tmp_path):
    floor = [0.3, 0.2, 0.5, 0.4, 0.35, 0.6]
    free = estimate_wind(tiny_wind_file, "table52", em_passes=2)
    floored = estimate_wind(tiny_wind_file, spec_with_floor(tmp_path / "f.toml", floor),
                            em_passes=2)
    assert np.all(np.asarray(free.metadata["noise_std"]) < np.asarray(floor))
    assert np.all(np.asarray(floored.metadata["noise_std"]) >= np.asarray(floor) - 1e-12)
    assert floored.metadata["model_error_std"] == floor
    # a larger channel noise widens the posterior: more is left to the wind's prior
    std = [c for c in floored.df.columns if c.endswith("_std")]
    assert floored.df[std].mean().mean() > free.df[std].mean().mean()


def test_a_bad_model_error_table_is_refused_naming_it(tmp_path):
    path = spec_with_floor(tmp_path / "bad.toml", [0.1, 0.2, 0.3])
    with pytest.raises(WindEstimationError, match="model_error_std"):
        model_error_floor(path)
    assert model_error_floor("table52") is None


def test_calibrate_writes_the_model_error_it_leaves(tiny_wind_file, tmp_path, capsys):
    out = tmp_path / "cal.toml"
    assert main(["calibrate", str(tiny_wind_file), "--model", "table52", "--max-nfev", "3",
                 "--params", "fuselage.cx_m2", "--out", str(out), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    floor = model_error_floor(out)
    np.testing.assert_allclose(floor, report["rms_after"])
