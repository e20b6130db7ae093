"""Flight-table loader: both formats load, every error case names file/column/row."""

import warnings

import numpy as np
import pandas as pd
import pytest
from airwake.record.flight_table import (
    CONTRACT_COLUMNS,
    FlightTableError,
    FlightTableWarning,
    load_flight_table,
    measured_columns,
    validate_flight_table,
    write_flight_table,
)


def _table(n=20):
    rng = np.random.default_rng(0)
    df = pd.DataFrame({c: rng.normal(0, 0.05, n) for c in CONTRACT_COLUMNS})
    df["t_s"] = np.arange(n) / 150.0
    df["rotor_speed_rad_s"] = 163.0
    df["height_agl_m"] = np.inf
    df["pwm_ch1_us"] = 1500.0
    df["truth_wind_vx_m_s"] = 1.0
    return df


@pytest.mark.parametrize("ext", [".parquet", ".csv"])
def test_csv_and_parquet_round_trip_with_metadata_and_extra_columns(tmp_path, ext):
    df = _table()
    path = write_flight_table(df, tmp_path / f"f{ext}", {"frame": "ned", "seed": 7})
    ft = load_flight_table(path)
    assert ft.metadata == {"frame": "ned", "seed": 7}
    pd.testing.assert_frame_equal(ft.df, df, check_exact=True, check_dtype=ext == ".parquet")
    assert "truth_wind_vx_m_s" in ft.df and "truth_wind_vx_m_s" not in measured_columns(ft.df)
    assert "pwm_ch1_us" in measured_columns(ft.df)


def test_user_csv_without_metadata_loads(tmp_path):
    p = tmp_path / "user.csv"
    _table().to_csv(p, index=False)
    assert len(load_flight_table(p)) == 20


def _write(tmp_path, df, name="f.csv"):
    p = tmp_path / name
    df.to_csv(p, index=False)
    return p


def test_missing_file_is_named(tmp_path):
    with pytest.raises(FlightTableError, match="nope.csv not found"):
        load_flight_table(tmp_path / "nope.csv")


def test_unknown_extension_is_refused(tmp_path):
    p = tmp_path / "f.xlsx"
    p.write_text("x")
    with pytest.raises(FlightTableError, match="extension '.xlsx'"):
        load_flight_table(p)


def test_missing_columns_are_listed_with_the_file(tmp_path):
    p = _write(tmp_path, _table().drop(columns=["p_rad_s", "acc_z_m_s2"]))
    with pytest.raises(FlightTableError) as exc:
        load_flight_table(p)
    msg = str(exc.value)
    assert "f.csv" in msg and "'p_rad_s'" in msg and "'acc_z_m_s2'" in msg and "t_s" in msg


def test_nan_reports_column_first_row_and_count(tmp_path):
    df = _table()
    df.loc[[4, 9], "q_rad_s"] = np.nan
    with pytest.raises(FlightTableError, match=r"'q_rad_s' has 2 NaN.*row 4"):
        load_flight_table(_write(tmp_path, df))


@pytest.mark.parametrize("dup", [True, False])
def test_non_monotonic_or_duplicated_time_reports_the_row(tmp_path, dup):
    df = _table()
    df.loc[6, "t_s"] = df.loc[5, "t_s"] if dup else df.loc[5, "t_s"] - 1.0
    word = "duplicated" if dup else "decreasing"
    with pytest.raises(FlightTableError, match=f"{word} at row 6"):
        load_flight_table(_write(tmp_path, df))


@pytest.mark.parametrize(
    "column,value",
    [
        ("roll_rad", 25.0),  # degrees
        ("rotor_speed_rad_s", 1560.0),  # rpm
        ("acc_z_m_s2", -981.0),  # cm/s^2 or similar
        ("p_rad_s", 57.0),  # deg/s
        ("delta_col_rad", 6.0),  # degrees
        ("pwm_ch1_us", 1.5),  # ms
    ],
)
def test_values_outside_plausible_units_name_column_value_and_row(tmp_path, column, value):
    df = _table()
    df.loc[3, column] = value
    with pytest.raises(FlightTableError, match=rf"'{column}' value {value!r} at row 3"):
        load_flight_table(_write(tmp_path, df), reads=("pwm_ch1_us",))


def test_a_column_the_command_does_not_read_is_a_one_line_warning_not_a_refusal(tmp_path):
    # a good flight must not be refused for a column the command never reads (issue 22:
    # a diverged tracker column stopped `model diagnose`); the user still hears of it
    df = _table(40)
    df["tracker_pos_x_m"] = 0.5
    df.loc[[7, 8, 9, 30], "pwm_ch1_us"] = 1.5
    df.loc[12, "tracker_pos_x_m"] = np.nan
    with pytest.warns(FlightTableWarning) as caught:
        ft = load_flight_table(_write(tmp_path, df))
    assert len(ft) == 40
    text = sorted(str(w.message) for w in caught)
    assert len(text) == 2 and all("\n" not in t and "f.csv" in t for t in text)
    assert "'pwm_ch1_us' has 4 value(s) outside the plausible range [500, 2500]" in text[0]
    assert "rows 7-9, 30" in text[0] and "not read here" in text[0]
    assert "'tracker_pos_x_m' has 1 value(s) NaN" in text[1] and "rows 12 " in text[1]


def test_a_flagged_column_is_checked_only_where_its_flag_is_set(tmp_path):
    # marker pose while the tracker is lost means nothing; where it is valid it is data
    df = _table()
    df["marker_vel_n_m_s"] = 0.1
    df["marker_valid"] = 1.0
    df.loc[5:9, "marker_valid"] = 0.0
    df.loc[6, "marker_vel_n_m_s"] = -100.03
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        validate_flight_table(df, "f", reads=("marker_vel_n_m_s",))
    df.loc[12, "marker_vel_n_m_s"] = -100.03
    with pytest.raises(FlightTableError, match=r"'marker_vel_n_m_s' value -100.03 at row 12"):
        validate_flight_table(df, "f", reads=("marker_vel_n_m_s",))
    with pytest.warns(FlightTableWarning, match="where marker_valid is 1, rows 12 "):
        validate_flight_table(df, "f")


def test_parquet_rejects_nan_too(tmp_path):
    df = _table()
    df.loc[0, "vel_u_m_s"] = np.nan
    p = tmp_path / "f.parquet"
    df.to_parquet(p)
    with pytest.raises(FlightTableError, match="vel_u_m_s"):
        load_flight_table(p)
