"""Airwake intensity (eq 2.4), its peaks, the RANSAC turbulence calibration and the map
command on a truth-world ship flight."""

import json

import numpy as np
import pandas as pd
import pytest
from airwake.cli import main
from airwake.nets.calibration import ransac_line
from airwake.nets.intensity import (
    IntensityConfig,
    find_intensity_peaks,
    intensity_from_arrays,
    intensity_series,
)

RATE_HZ = 150.0


def _pred_frame(measured, predicted):
    t = np.arange(len(measured)) / RATE_HZ
    df = {"t_s": t}
    for k, a in enumerate("pqr"):
        df[f"{a}_pred_rad_s"] = predicted[:, k]
    for k, a in enumerate("pqr"):
        df[f"{a}_resid_rad_s"] = measured[:, k] - predicted[:, k]
    df["history_valid"] = np.ones(len(t), np.int8)
    return pd.DataFrame(df)


def test_a_perfect_prediction_has_zero_intensity_and_a_gust_raises_it_where_it_blows():
    # a perfect net leaves nothing to the airwake; a disturbance the net did not predict
    # must show up at its own time, not elsewhere
    rng = np.random.default_rng(3)
    n = int(40 * RATE_HZ)
    t = np.arange(n) / RATE_HZ
    pilot = np.column_stack([0.3 * np.sin(2 * np.pi * 0.4 * t), 0.2 * np.cos(2 * np.pi * 0.3 * t),
                             0.05 * np.sin(2 * np.pi * 0.2 * t)])
    assert np.allclose(intensity_from_arrays(pilot, pilot, 75)["a_omega"], 0.0)
    gust = np.zeros((n, 3))
    burst = (t > 20) & (t < 22)
    gust[burst] = rng.normal(0.0, 0.4, (burst.sum(), 3))
    s = intensity_series(_pred_frame(pilot + gust, pilot), IntensityConfig(std_window_s=0.5))
    a = s["a_omega"].to_numpy()
    inside = (t > 20.5) & (t < 22.0)
    assert a[inside].mean() > 0.01 and np.abs(a[t < 19.5]).max() < 1e-9
    assert np.all(s["resid_std"].to_numpy()[t < 19.5] < 1e-9)
    # ω_s − ω_s′ is the gust's extra spread of the magnitude: positive inside the burst
    assert (s["omega_s"] - s["omega_s_pred"]).to_numpy()[inside].mean() > 0


def test_intensity_at_t_does_not_read_later_samples():
    # the daemon computes it live: the windows must be trailing
    rng = np.random.default_rng(1)
    m, p = rng.normal(size=(600, 3)), rng.normal(size=(600, 3))
    full = intensity_from_arrays(m, p, 40)
    m2 = m.copy()
    m2[400:] += 5.0
    part = intensity_from_arrays(m2, p, 40)
    for k in full:
        assert np.allclose(full[k][:400], part[k][:400])


def test_peaks_are_15_s_apart_and_1_5_stds_above_their_10_s_neighbourhood():
    # two gusts 5 s apart are one event; a bump under 1.5 local stds is noise
    rng = np.random.default_rng(7)
    t = np.arange(int(120 * RATE_HZ)) / RATE_HZ
    a = rng.normal(0.0, 0.1, t.size)
    for t0, height in ((20.0, 3.0), (25.0, 2.0), (60.0, 3.0), (95.0, 0.12)):
        a += height * np.exp(-0.5 * ((t - t0) / 0.2) ** 2)
    peaks = find_intensity_peaks(t, a, IntensityConfig())
    assert np.allclose(peaks["t_s"], [20.0, 60.0], atol=0.1)
    assert np.all(peaks["a_omega"] - peaks["local_mean"] >= 1.5 * np.std(a))
    assert np.all(np.diff(peaks["t_s"]) >= 15.0)


def test_ransac_recovers_the_line_through_outliers_where_least_squares_does_not():
    # §4.4.1: the residual std is noisy and some cells are far off; RANSAC must not follow them
    rng = np.random.default_rng(11)
    x = rng.uniform(5.0, 40.0, 200)
    y = 0.021 * x + 0.83 + rng.normal(0.0, 0.01, x.size)
    out = rng.choice(x.size, 60, replace=False)
    y[out] = rng.uniform(1.5, 3.0, out.size)
    fit = ransac_line(x, y, np.random.default_rng(0))
    assert abs(fit.slope - 0.021) < 0.001 and abs(fit.offset - 0.83) < 0.03
    good = np.setdiff1d(np.arange(x.size), out)
    assert fit.inliers[good].all() and fit.inliers[out].sum() < 15  # some fall on the line
    ls = np.polyfit(x, y, 1)
    assert abs(ls[0] - 0.021) > 0.005
    again = ransac_line(x, y, np.random.default_rng(0))
    assert again.slope == fit.slope and again.offset == fit.offset


def test_ransac_refuses_too_few_points():
    with pytest.raises(ValueError, match=">= 3 finite points"):
        ransac_line([1.0, np.nan, 2.0], [1.0, 2.0, np.nan], np.random.default_rng(0))


@pytest.fixture(scope="module")
def accel_net(truth_world_flight, tmp_path_factory):
    still = truth_world_flight("still_air_calibration", 5, 60.0)
    net = tmp_path_factory.mktemp("intensity") / "accel.pt"
    assert main(["nets", "train", str(still), "--target", "accel", "--out", str(net),
                 "--quiet"]) == 0
    return net


def test_airwake_map_of_a_ship_flight_follows_the_simulator_turbulence(
        accel_net, truth_world_flight, tmp_path, capsys):
    # the map must be higher where the simulator's airwake is more turbulent
    ship = truth_world_flight("ship_airwake_b0", 5, 60.0)
    cal = truth_world_flight("ship_airwake_b15", 6, 60.0)
    out = tmp_path / "map"
    assert main(["nets", "airwake", str(ship), "--net", str(accel_net), "--out", str(out),
                 "--score", "--calibrate-on", str(cal), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    score = summary["score"]
    assert score["cells"] >= 8 and score["resid_std_pearson"] > 0.5
    assert summary["calibration"]["slope"] > 0
    cells = pd.read_parquet(out / "map.parquet")
    assert {"x_m", "y_m", "a_omega", "resid_std", "turbulence_m_s",
            "truth_turbulence_m_s"} <= set(cells.columns)
    assert cells["x_m"].max() < 0  # behind the hangar step, where the pilot swept
    for png in ("intensity", "residual_std", "turbulence", "truth_turbulence"):
        assert (out / f"{png}.png").stat().st_size > 1000
    # the calibration is reusable on another flight
    assert main(["nets", "airwake", str(ship), "--net", str(accel_net), "--out",
                 str(tmp_path / "again"), "--calibration", str(out / "calibration.json"),
                 "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["calibration"]["slope"] == summary["calibration"]["slope"]


def test_no_net_map_is_the_gyro_statistics_and_its_calibration_stays_its_own(
        accel_net, truth_world_flight, tmp_path, capsys):
    # ω′ = 0: A_ω = ω_s·‖ω‖ and resid_std the gyro's local std — the map a net must beat
    ship = truth_world_flight("ship_airwake_b0", 5, 60.0)
    cal = truth_world_flight("ship_airwake_b15", 6, 60.0)
    out = tmp_path / "nonet"
    assert main(["nets", "airwake", str(ship), "--no-net", "--out", str(out), "--score",
                 "--calibrate-on", str(cal), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["net"] == "none" and summary["resid_unit"] == "rad_s"
    assert summary["score"]["cells"] >= 8 and summary["score"]["resid_std_pearson"] > 0.5
    samples = pd.read_parquet(out / "map.parquet")
    assert (samples["a_omega"] >= 0).all()  # ω_s·‖ω‖ cannot be negative
    # a --no-net calibration is not applied to a net's residuals, nor the other way
    assert main(["nets", "airwake", str(ship), "--net", str(accel_net), "--out",
                 str(tmp_path / "mix"), "--calibration", str(out / "calibration.json")]) == 2
    assert "--no-net" in capsys.readouterr().err
    with pytest.raises(SystemExit):  # one of --net / --no-net is required
        main(["nets", "airwake", str(ship), "--out", str(tmp_path / "none")])
    assert "--no-net" in capsys.readouterr().err


def test_score_needs_a_simulated_flight(accel_net, truth_world_flight, tmp_path, capsys):
    df = pd.read_parquet(truth_world_flight("ship_airwake_b0", 5, 60.0))
    plain = tmp_path / "plain.csv"
    df.to_csv(plain, index=False)
    assert main(["nets", "airwake", str(plain), "--net", str(accel_net), "--out",
                 str(tmp_path / "m"), "--score"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "not a simulated flight" in err


def test_running_sum_std_equals_the_sliding_window_std():
    # the O(T) form the live path uses must be the same statistic as the features' one
    from airwake.nets.features import local_std
    from airwake.nets.intensity import trailing_std

    y = np.random.default_rng(2).normal(3.0, 0.1, (4000, 3))
    assert np.allclose(trailing_std(y, 75), local_std(y, 75), rtol=0, atol=1e-8)
    assert np.allclose(trailing_std(y[:, 0], 7), local_std(y[:, 0], 7), rtol=0, atol=1e-12)
