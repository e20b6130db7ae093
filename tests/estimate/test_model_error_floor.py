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
    # and the steady part of that misfit: no larger than the misfit, the same flight's
    offset = model_error_floor(out, "model_error_offset")
    assert offset.shape == (6,) and np.all(offset >= 0) and np.all(offset <= floor * 1.5)
    from airwake.calibrate import model_error

    np.testing.assert_allclose(model_error(out, tiny_wind_file)[1], offset, rtol=0.2)


def spec_with_offset(path, floor, offset):
    save_spec(load_model("table52"), path, description="test",
              calibration={"flight": "x", "model_error_std": list(floor),
                           "model_error_offset": list(offset)})
    return path


FLOOR = [0.3, 0.2, 0.5, 0.4, 0.35, 0.6]


def test_a_steady_force_offset_widens_the_wind_by_exactly_its_effect(tiny_wind_file, tmp_path):
    """The model's steady force misfit (`model_error_offset`) moves the estimate as a
    steady wind would and the posterior does not know of it: the estimate is unchanged,
    its variance grows by the offset's effect through the smoother (Schmidt's consider
    analysis); the angular channels' steady misfits are not added."""
    base = estimate_wind(tiny_wind_file, spec_with_floor(tmp_path / "f.toml", FLOOR),
                         em_passes=2)
    offset = [0.02, 0.03, 0.05, 0.3, 0.3, 0.3]
    wide = estimate_wind(tiny_wind_file, spec_with_offset(tmp_path / "o.toml", FLOOR, offset),
                         em_passes=2)
    names = [c for c in base.df.columns if c.startswith("wind_") and not c.endswith("_std")]
    np.testing.assert_allclose(wide.df[names], base.df[names], rtol=0, atol=1e-12)
    added = wide.smoother.offset_std(offset[:3] + [0.0, 0.0, 0.0])
    grown = wide.df[[f"{n}_std" for n in names]].to_numpy() ** 2 - base.df[
        [f"{n}_std" for n in names]].to_numpy() ** 2
    np.testing.assert_allclose(grown, added**2, rtol=1e-9, atol=1e-12)
    assert np.all(added[:, :3].mean(0) > 0) and wide.metadata["model_error_offset"] == offset
    assert np.allclose(wide.metadata["offset_std_rms"], np.sqrt(np.mean(added**2, 0)))
    # only the angular channels' offsets: nothing is added
    ang = estimate_wind(tiny_wind_file, spec_with_offset(tmp_path / "a.toml", FLOOR,
                                                         [0, 0, 0, 0.3, 0.3, 0.3]),
                        em_passes=2)
    np.testing.assert_allclose(ang.df.to_numpy(), base.df.to_numpy(), rtol=0, atol=1e-12)


def test_the_offset_sensitivity_is_the_passs_exact_response_to_a_constant_offset(
        tiny_wind_file, tmp_path):
    est = estimate_wind(tiny_wind_file, spec_with_floor(tmp_path / "f.toml", FLOOR),
                        em_passes=2)
    sm = est.smoother
    sens = sm.offset_sensitivity()
    c = sm._wind_rows()
    z0 = sm.pre.data.z.copy()
    for run, ps, lin in sm.last_passes:
        for j in (0, 2, 4):
            sm.pre.data.z[:, j] += 1e-3
            try:
                moved, _ = sm._forward(run, est.result.prior, sm.last_noise, lin,
                                       online=False)
            finally:
                sm.pre.data.z[:] = z0
            sm._backward(moved)
            response = (moved.ms - ps.ms) @ c.T / 1e-3
            scale = np.abs(sens[run][:, :, j]).max()
            assert scale > 0
            np.testing.assert_allclose(response, sens[run][:, :, j], rtol=0,
                                       atol=1e-6 * scale)


def test_a_bad_offset_table_is_refused_naming_it(tmp_path):
    path = spec_with_offset(tmp_path / "bad.toml", FLOOR, [0.1, -0.2, 0.3, 0, 0, 0])
    with pytest.raises(WindEstimationError, match="model_error_offset"):
        model_error_floor(path, "model_error_offset")


def test_the_flights_own_accelerometer_bias_joins_the_models_steady_misfit(tiny_wind_file,
                                                                        tmp_path):
    spec = spec_with_offset(tmp_path / "o.toml", FLOOR, [0.02, 0.0, 0.05, 0.3, 0.3, 0.3])
    base = estimate_wind(tiny_wind_file, spec_with_floor(tmp_path / "f.toml", FLOOR),
                         em_passes=2)
    both = estimate_wind(tiny_wind_file, spec, em_passes=2, accel_bias_std=0.01)
    names = [f"{n}_std" for n in ("wind_vx_m_s", "wind_vy_m_s", "wind_vz_m_s",
                                  "wind_wx_rad_s", "wind_wy_rad_s", "wind_wz_rad_s")]
    forces = np.hypot([0.02, 0.0, 0.05], 0.01).tolist() + [0.0, 0.0, 0.0]
    grown = both.df[names].to_numpy() ** 2 - base.df[names].to_numpy() ** 2
    np.testing.assert_allclose(grown, both.smoother.offset_std(forces) ** 2, rtol=1e-9,
                               atol=1e-12)
    assert both.metadata["accel_bias_std_m_s2"] == 0.01
    with pytest.raises(WindEstimationError, match="--accel-bias-std"):
        estimate_wind(tiny_wind_file, spec, accel_bias_std=-0.01)
    with pytest.raises(WindEstimationError, match="--method smoother"):
        estimate_wind(tiny_wind_file, spec, method="apf", accel_bias_std=0.01)
