"""Issue 11: a diagnosis that knows about wind, and says when the model is not this
aircraft's.

- a ship-airwake flight analysed in still air: unmodelled wind ranks first, the verdict
  and the report say to estimate or supply the wind and name no model effect, and the
  wind it fitted is the flight's true mean wind;
- the same flight with its true wind given (`--wind truth`): the wind verdict is gone
  from the channels the wind explained;
- a windy flight with a hidden effect (the fan field plus a hidden ground effect): with the
  flight's wind supplied, the ground effect is still ranked first;
- an uncalibrated model (`table51`, the CLI's default) on still-air flights with hidden
  effects says "calibrate first" instead of naming an effect;
- wind tables: earth-axis (anemometer-style) and body-axis tables give the same analysis,
  bad ones are one-line errors, and the wind is not something `model add` adds.

Flights: truth-world flights on seeds no tuning used (the ship flight; the compact
scenarios of tests/discrepancy/scenarios).
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from airwake.cli import main
from airwake.discrepancy.add import add_effect
from airwake.discrepancy.compare import analyse
from airwake.discrepancy.diagnose import diagnose
from airwake.discrepancy.errors import DiscrepancyError
from airwake.discrepancy.wind import WIND_CANDIDATE, body_from_ned, on_flight
from airwake.heli import load_model
from airwake.heli.model import WIND_NAMES
from airwake.record.flight_table import write_flight_table
from scipy.spatial.transform import Rotation

SHIP = ("ship_airwake_b15", 64, 40.0)


@pytest.fixture(scope="module")
def ship(truth_world_flight):
    return truth_world_flight(*SHIP)


def _diagnose_cli(capsys, *args) -> dict:
    capsys.readouterr()
    assert main(["model", "diagnose", *map(str, args), "--no-sindy", "--json", "--quiet"]) == 0
    return json.loads(capsys.readouterr().out)


def _true_mean_wind_ned(path) -> np.ndarray:
    df = pd.read_parquet(path)
    body = np.column_stack([df[f"truth_{n}"].to_numpy() for n in WIND_NAMES[:3]])
    att = df[["yaw_rad", "pitch_rad", "roll_rad"]].to_numpy()
    return Rotation.from_euler("ZYX", att).apply(body).mean(0)


def test_ship_flight_in_still_air_is_diagnosed_as_wind_with_the_true_mean_wind(
        ship, wind_baseline, capsys):
    s = _diagnose_cli(capsys, ship, "--model", wind_baseline)
    tested = [c for c in s["candidates"] if c["testable"]]
    assert tested[0]["effect"] == WIND_CANDIDATE, [c["effect"] for c in tested[:3]]
    assert tested[0]["significant"] and tested[0]["kind"] == "wind"
    assert s["verdict"]["kind"] == "wind" and s["verdict"]["effect"] is None
    assert "airwake wind estimate" in s["verdict"]["text"]
    assert "--wind" in s["verdict"]["text"]
    # the wind it fitted is the flight's wind, not any field that lowers the residual
    fitted = np.array(tested[0]["wind"]["mean_ned_m_s"])
    truth = _true_mean_wind_ned(ship)
    assert np.linalg.norm(truth[:2]) > 0.5, truth  # a flight with a real mean wind
    assert np.all(np.abs(fitted[:2] - truth[:2]) < 0.3), (fitted, truth)
    # the calibrated spec says it was calibrated: no "calibrate first" screening
    assert s["recalibration"] is None


def test_ship_flight_report_says_supply_the_wind_and_adds_nothing(ship, wind_baseline,
                                                                   tmp_path):
    out = tmp_path / "report"
    assert main(["model", "report", str(ship), "--model", str(wind_baseline), "--out",
                 str(out), "--quiet"]) == 0
    page = (out / "index.html").read_text()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["verdict"]["kind"] == "wind"
    assert "unmodelled wind" in page and "airwake wind estimate" in page
    assert not (out / "model_after.toml").exists()
    assert summary["added"] is None


def test_ship_flight_with_its_true_wind_leaves_no_wind_to_blame_in_the_mean_flow(
        ship, wind_baseline, capsys):
    still = _diagnose_cli(capsys, ship, "--model", wind_baseline)
    given = _diagnose_cli(capsys, ship, "--model", wind_baseline, "--wind", "truth")
    before = {c: v["rms_over_noise"] for c, v in still["compare"].items()}
    after = {c: v["rms_over_noise"] for c, v in given["compare"].items()}
    # the true wind as the input removes most of the residual in every channel
    for c in before:
        assert after[c] < 0.5 * before[c], (c, before[c], after[c])
    w = next(c for c in given["candidates"] if c["effect"] == WIND_CANDIDATE)
    # what the wind candidate still finds is a small correction, not the mean wind
    assert np.linalg.norm(w["wind"]["mean_ned_m_s"][:2]) < 0.2, w["wind"]
    assert given["verdict"]["kind"] != "effect", given["verdict"]


def test_windy_flight_with_a_hidden_ground_effect_and_its_wind_supplied_finds_the_effect(
        flights, baseline):
    ft = flights("fans_ground_effect")
    d = diagnose(baseline, ft, sindy=False, wind="truth")
    assert d.top(1) == ["ground_effect"], d.top(4)
    v = d.verdict()
    assert v["kind"] == "effect" and v["effect"] == "ground_effect", v
    # and adding it fits a real ground effect on the windy flight
    res = add_effect(baseline, "ground_effect", ft, wind="truth", max_nfev=15)
    assert res.after["acc_z_m_s2"]["rms"] < 0.4 * res.before["acc_z_m_s2"]["rms"]


@pytest.mark.parametrize("scenario", ["lever_arm", "ground_effect", "servo_lag"])
def test_uncalibrated_model_says_calibrate_first_not_an_effect(scenario, flights):
    d = diagnose(load_model("table51"), flights(scenario), sindy=False, refine_top=2)
    v = d.verdict()
    assert v["kind"] == "calibrate", (v, d.top(3))
    assert v["effect"] is None and "airwake calibrate" in v["text"]
    rc = d.recalibration
    assert rc["calibrate_first"] and rc["cv_explained"] > rc["best_candidate_cv_explained"]


def test_calibrated_model_on_a_hidden_effect_flight_does_not_say_calibrate_first(
        flights, baseline):
    d = diagnose(baseline, flights("lever_arm"), sindy=False, refine_top=2)
    assert not d.recalibration["calibrate_first"], d.recalibration
    assert d.verdict() == {"kind": "effect", "effect": "imu_lever_arm",
                           "text": d.verdict()["text"]}


def test_cli_default_model_prints_calibrate_first(flights, tmp_path, capsys):
    ft = flights("ground_effect")
    path = tmp_path / "ge.parquet"
    write_flight_table(ft.df, path, ft.metadata)
    assert main(["model", "diagnose", str(path), "--no-sindy", "--quiet", "--refine",
                 "2"]) == 0
    out = capsys.readouterr().out
    assert "verdict: Calibrate first" in out and "still air assumed" in out


@pytest.fixture(scope="module")
def ship_flight_and_truth(ship):
    fl, w = on_flight("truth", ship)
    return fl, w


def test_earth_axis_wind_table_gives_the_same_analysis_as_body_axes(
        ship, ship_flight_and_truth, wind_baseline, tmp_path):
    fl, w = ship_flight_and_truth
    att = fl.df[["yaw_rad", "pitch_rad", "roll_rad"]].to_numpy()
    ned = Rotation.from_euler("ZYX", att).apply(w[:, :3])
    assert np.allclose(body_from_ned(fl.df, ned), w[:, :3], atol=1e-9)
    # an anemometer-style table: earth axes, its own (coarser) time base, no rotation
    t = fl.t[::3]
    earth = pd.DataFrame({"t_s": t, "wind_n_m_s": ned[::3, 0], "wind_e_m_s": ned[::3, 1],
                          "wind_d_m_s": ned[::3, 2]})
    body = pd.DataFrame({"t_s": t, **{n: w[::3, j] for j, n in enumerate(WIND_NAMES[:3])}})
    pe, pb = tmp_path / "earth.parquet", tmp_path / "body.parquet"
    write_flight_table(earth, pe, {})
    write_flight_table(body, pb, {})
    model = load_model(wind_baseline)
    a_e = analyse(model, fl, wind=on_flight(str(pe), ship)[1])
    a_b = analyse(model, fl, wind=on_flight(str(pb), ship)[1])
    # the same wind up to the attitude's change between table samples (< 1 % here)
    for c in a_e.metrics():
        assert a_e.metrics()[c]["rms"] == pytest.approx(a_b.metrics()[c]["rms"], rel=0.02)
    still = analyse(model, fl)
    assert a_e.metrics()["qdot_rad_s2"]["rms"] < 0.6 * still.metrics()["qdot_rad_s2"]["rms"]


def test_bad_wind_inputs_are_one_line_errors(ship, flights, tmp_path, capsys):
    fl, _ = on_flight(None, ship)
    bad = tmp_path / "nowind.parquet"
    write_flight_table(pd.DataFrame({"t_s": fl.t, "speed_m_s": np.ones(fl.t.size)}), bad, {})
    with pytest.raises(DiscrepancyError, match="no wind columns.*wind_vx_m_s.*wind_n_m_s"):
        on_flight(str(bad), ship)
    short = tmp_path / "short.parquet"
    write_flight_table(pd.DataFrame({"t_s": fl.t[:100], "wind_vx_m_s": 0.0, "wind_vy_m_s": 0.0,
                                     "wind_vz_m_s": 0.0}), short, {})
    with pytest.raises(DiscrepancyError, match="covers t = .* not the flight's"):
        on_flight(str(short), ship)
    # a flight without truth columns cannot give --wind truth
    plain = tmp_path / "plain.parquet"
    ft = flights("calibration")
    write_flight_table(ft.df[[c for c in ft.df.columns if not c.startswith("truth_")]],
                       plain, {})
    capsys.readouterr()
    assert main(["model", "compare", str(plain), "--wind", "truth", "--windows", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "truth_wind_vx_m_s" in err[0]
    # the wind is an input, not an effect to add
    out = tmp_path / "m.toml"
    with pytest.raises(DiscrepancyError, match="not a model effect.*--wind"):
        add_effect("table51", WIND_CANDIDATE, ship, out=out)
    assert not out.exists()
