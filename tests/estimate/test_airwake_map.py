"""`airwake wind map`: the frame turn, the cell statistics, the map against the simulator's
wind field, and bad input refused with nothing half-written."""

import json

import numpy as np
import pandas as pd
import pytest
from airwake.cli import main
from airwake.estimate import estimate_wind, write_wind
from airwake.estimate.airwake_map import (
    build_map,
    grid_samples,
    map_samples,
)
from airwake.estimate.errors import WindEstimationError
from airwake.heli import WIND_NAMES
from airwake.record.flight_table import load_flight_table, write_flight_table


def _ship_flight(n=300, dt=0.1, heading=0.3, yaw=0.3 + 0.5, x=-8.0):
    t = np.arange(n) * dt
    df = pd.DataFrame({"t_s": t, "roll_rad": 0.0, "pitch_rad": 0.0, "yaw_rad": yaw,
                       "hub_ship_x_m": x, "hub_ship_y_m": np.linspace(-2, 2, n),
                       "hub_ship_z_m": -2.6, "ship_yaw_rad": heading,
                       "ship_vel_n_m_s": 2.0 * np.cos(heading),
                       "ship_vel_e_m_s": 2.0 * np.sin(heading), "ship_vel_d_m_s": 0.0})
    return df


def _wind(t, v_body, w_body=(0.0, 0.0, 0.0), std=0.1):
    cols = {"t_s": t}
    for j, n in enumerate(WIND_NAMES):
        cols[n] = (list(v_body) + list(w_body))[j]
    for n in WIND_NAMES:
        cols[f"{n}_std"] = std
    return pd.DataFrame(cols)


def test_flow_is_turned_into_the_ship_frame_relative_to_the_ship():
    # the air moves over the ground at 1 m/s toward the ship's stern (against its 2 m/s
    # course): relative to the ship that is a 3 m/s wind from the bow, whatever the
    # helicopter's own heading
    heading, yaw = 0.3, 0.8
    fl = _ship_flight(heading=heading, yaw=yaw)
    air_ned = -1.0 * np.array([np.cos(heading), np.sin(heading), 0.0])
    c, s = np.cos(yaw), np.sin(yaw)
    v_body = np.array([c * air_ned[0] + s * air_ned[1], -s * air_ned[0] + c * air_ned[1], 0.2])
    s_ = map_samples(_wind(fl["t_s"].to_numpy(), v_body, (0.0, 0.0, 0.1)), fl, ins_std=0.0)
    np.testing.assert_allclose(s_.flow, np.tile([-3.0, 0.0, 0.2], (len(fl), 1)), atol=1e-9)
    np.testing.assert_allclose(s_.rot[:, 2], 0.1, atol=1e-12)  # a vertical axis stays put
    assert s_.frame == "ship" and s_.u_ref == pytest.approx(np.hypot(3.0, 0.2))


def test_a_banked_pitched_helicopter_is_turned_by_its_full_attitude():
    # body -> NED by yaw-pitch-roll (z-y-x), checked against scipy's rotation
    from scipy.spatial.transform import Rotation

    roll, pitch, yaw, heading = 0.3, -0.2, 1.1, 0.4
    fl = _ship_flight(heading=heading, yaw=yaw)
    fl["roll_rad"], fl["pitch_rad"] = roll, pitch
    v_body, w_body = np.array([1.0, -0.5, 0.3]), np.array([0.1, 0.2, -0.05])
    s_ = map_samples(_wind(fl["t_s"].to_numpy(), v_body, w_body), fl, ins_std=0.0)
    r = Rotation.from_euler("ZYX", [yaw, pitch, roll]).as_matrix()
    to_ship = Rotation.from_euler("Z", heading).as_matrix().T
    ship_v = np.array([2.0 * np.cos(heading), 2.0 * np.sin(heading), 0.0])
    np.testing.assert_allclose(s_.flow[0], to_ship @ (r @ v_body - ship_v), atol=1e-9)
    np.testing.assert_allclose(s_.rot[0], to_ship @ r @ w_body, atol=1e-12)


def test_cells_hold_the_mean_and_the_total_turbulent_variance():
    rng = np.random.default_rng(0)
    n = 2000
    t = np.arange(n) * 0.05
    fl = pd.DataFrame({"t_s": t, "roll_rad": 0.0, "pitch_rad": 0.0, "yaw_rad": 0.0,
                       "pos_n_m": 0.25, "pos_e_m": 0.25, "pos_d_m": -2.5})
    u = 2.0 + 0.3 * rng.standard_normal(n)
    w = _wind(t, (0, 0, 0))
    w["wind_vx_m_s"] = u
    w["wind_vx_m_s_std"] = 0.2
    amap = build_map(w, fl, cell_m=0.5, ins_std=0.0, u_ref=2.0)
    cell = amap.cells.iloc[0]
    assert len(amap.cells) == 1 and cell["samples"] == n
    assert cell["u_m_s"] == pytest.approx(u.mean())
    # total variance = spread of the estimates + what the posterior says they miss
    assert cell["sigma_u_m_s"] == pytest.approx(np.sqrt(u.var() + 0.04), rel=1e-9)
    assert cell["seconds"] == pytest.approx(n * 0.05)
    # the mean's std: posterior std shrunk by (error correlation time / time in the cell)
    assert cell["u_std_m_s"] == pytest.approx(0.2 * np.sqrt(1.0 / (n * 0.05)))


def test_cells_with_too_little_data_are_left_out():
    fl = _ship_flight()
    s_ = map_samples(_wind(fl["t_s"].to_numpy(), (1, 0, 0)), fl)
    cells = grid_samples(s_, cell_m=0.5, min_seconds=2.0)
    assert len(cells) == 0 or (cells["seconds"] >= 2.0).all()
    with pytest.raises(WindEstimationError, match="--cell-m"):
        grid_samples(s_, cell_m=0.0)


def test_a_flight_without_rtk_or_ship_columns_is_refused_naming_the_problem(tmp_path):
    fl = _ship_flight().drop(columns=["hub_ship_x_m", "hub_ship_y_m", "hub_ship_z_m"])
    fl["rel_pos_n_m"] = 0.0
    with pytest.raises(WindEstimationError, match="--base-antenna-ship-m"):
        map_samples(_wind(fl["t_s"].to_numpy(), (1, 0, 0)), fl)
    fl = fl.drop(columns=["rel_pos_n_m"])
    with pytest.raises(WindEstimationError, match="no RTK baseline"):
        map_samples(_wind(fl["t_s"].to_numpy(), (1, 0, 0)), fl)


def test_samples_where_the_position_was_held_over_a_gap_are_left_out():
    fl = _ship_flight()
    fl["hub_ship_valid"] = 1.0
    fl.loc[100:199, "hub_ship_valid"] = 0.0  # an RTK outage: the builder held the position
    s_ = map_samples(_wind(fl["t_s"].to_numpy(), (1, 0, 0)), fl)
    assert s_.t.size == 200 and not np.any((s_.t >= 10.0) & (s_.t < 19.95))


def test_an_unrelated_directory_is_never_replaced_by_a_map(tmp_path, capsys):
    fl = _ship_flight()
    flight = tmp_path / "f.parquet"
    wind = tmp_path / "w.parquet"
    write_flight_table(fl, flight)
    write_flight_table(_wind(fl["t_s"].to_numpy(), (-3.0, 0.0, 0.0)), wind)
    precious = tmp_path / "data"
    precious.mkdir()
    (precious / "flight-logs.txt").write_text("keep me")
    assert main(["wind", "map", str(wind), "--flight", str(flight), "--out",
                 str(precious)]) == 2
    assert "not an earlier map" in capsys.readouterr().err
    assert (precious / "flight-logs.txt").read_text() == "keep me"
    # an earlier map is replaced
    assert main(["wind", "map", str(wind), "--flight", str(flight), "--out",
                 str(tmp_path / "m"), "--min-seconds", "0.1"]) == 0
    assert main(["wind", "map", str(wind), "--flight", str(flight), "--out",
                 str(tmp_path / "m"), "--min-seconds", "0.1"]) == 0


@pytest.fixture(scope="module")
def ship_wind(truth_world_flight, wind_baseline, tmp_path_factory):
    flight = truth_world_flight("ship_airwake_b0", 41, 60.0)
    est = estimate_wind(flight, wind_baseline)
    path = tmp_path_factory.mktemp("map") / "wind.parquet"
    write_wind(est, path)
    return flight, path


def test_map_cells_with_two_seconds_match_the_simulated_airwake(ship_wind, tmp_path, capsys):
    # target: cells with >= 2 s of data within 0.3 m/s RMS of the truth field per component
    flight, wind = ship_wind
    out = tmp_path / "map"
    assert main(["wind", "map", str(wind), "--flight", str(flight), "--out", str(out),
                 "--score", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    sc = summary["score"]
    assert sc["cells"] >= 5
    for name in ("u_m_s", "v_m_s", "w_m_s"):
        assert sc["field"][name]["rms"] <= 0.3, (name, sc["field"][name])
        assert sc["along_track"][name]["rms"] <= 0.3
    cells = load_flight_table(out / "map.parquet", required=()).df
    assert {"x_m", "y_m", "z_m", "samples", "seconds", "u_m_s", "u_std_m_s", "ti",
            "ti_std"} <= set(cells.columns)
    # behind the hangar of a ship steaming into a 3 m/s relative wind: flow toward the stern
    assert (cells["u_m_s"] < 0).all() and (cells["x_m"] < 0).all()
    for f in ("mean_flow.png", "turbulence.png", "coverage.png", "index.html",
              "summary.json"):
        assert (out / f).stat().st_size > 0
    assert summary["headline"].startswith("airwake map (relative to the ship)")


def test_a_wind_table_from_another_flight_is_refused_and_nothing_is_written(ship_wind,
                                                                             truth_world_flight,
                                                                             tmp_path, capsys):
    _, wind = ship_wind
    other = truth_world_flight("ship_airwake_b15", 42, 60.0)
    out = tmp_path / "map"
    out.mkdir()
    (out / "keep.txt").write_text("previous map")
    assert main(["wind", "map", str(wind), "--flight", str(other), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "estimated from another flight" in err and len(err.splitlines()) == 1
    assert (out / "keep.txt").read_text() == "previous map"  # untouched
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".map")]


def test_a_flight_csv_without_positions_is_one_line_naming_it(ship_wind, tmp_path, capsys):
    flight, wind = ship_wind
    ft = load_flight_table(flight)
    df = ft.df.drop(columns=[c for c in ft.df.columns if c.startswith(("hub_ship", "rel_pos",
                                                                       "ship_", "pos_"))])
    path = tmp_path / "user.parquet"
    write_flight_table(df, path, ft.metadata)
    assert main(["wind", "map", str(wind), "--flight", str(path), "--out",
                 str(tmp_path / "m")]) == 2
    err = capsys.readouterr().err
    assert "no position columns" in err and not (tmp_path / "m").exists()


def test_the_models_still_air_error_is_no_turbulence_and_does_not_average_out():
    # the same estimates, once with std 0.1 and once with a still-air error g joined to it
    # (as `estimate_wind` joins a spec's still_air_wind_error): the turbulence is the same,
    # the cell mean's std holds all of g
    fl = _ship_flight()
    t = fl["t_s"].to_numpy()
    rng = np.random.default_rng(3)
    base = _wind(t, (1.0, 0.2, 0.1), (0.05, 0.0, 0.1))
    base["wind_vx_m_s"] += rng.normal(0.0, 0.3, t.size)
    g = np.array([0.6, 0.0, 0.1, 0.0, 0.4, 0.2])
    wider = base.copy()
    for j, n in enumerate(WIND_NAMES):
        wider[f"{n}_std"] = np.hypot(base[f"{n}_std"], g[j])
    plain = build_map(base, fl, wind_meta={"ins_velocity_std_m_s": 0.0}).cells
    with_g = build_map(wider, fl, wind_meta={"ins_velocity_std_m_s": 0.0,
                                             "still_air_wind_error": g.tolist()}).cells
    for c in ("sigma_u_m_s", "sigma_v_m_s", "sigma_w_m_s", "ti", "u_m_s", "wz_rad_s"):
        np.testing.assert_allclose(with_g[c], plain[c], rtol=1e-9)
    # the yaw turns body x into the ship's x and y: g's v_x part lands in u and v
    grown = with_g["u_std_m_s"] ** 2 + with_g["v_std_m_s"] ** 2 - (
        plain["u_std_m_s"] ** 2 + plain["v_std_m_s"] ** 2)
    np.testing.assert_allclose(grown, g[0] ** 2 + g[1] ** 2, rtol=1e-9)
    np.testing.assert_allclose(with_g["wz_std_rad_s"] ** 2 - plain["wz_std_rad_s"] ** 2,
                               g[5] ** 2, rtol=1e-9)
    # read as turbulence, the same table would have raised the turbulence intensity
    naive = build_map(wider, fl, wind_meta={"ins_velocity_std_m_s": 0.0}).cells
    assert (naive["ti"] > plain["ti"] * 1.2).all()
