"""Loading what the networks need from full and partial flight tables, and the
time-block split that keeps neighbouring samples out of each other's sets."""

import numpy as np
import pandas as pd
import pytest
from airwake.nets.data import INPUT_SOURCES, load_net_flight, net_flight_from_df
from airwake.nets.split import GUARD, TEST, TRAIN, VAL, SplitConfig, block_split
from airwake.record.flight_table import FlightTableError


def _table(n=300, rate=150.0, sources=("delta", "pwm", "rc_norm"), accel=True):
    rng = np.random.default_rng(0)
    d = {"t_s": np.arange(n) / rate, "roll_rad": 0.1 * rng.normal(size=n),
         "pitch_rad": 0.1 * rng.normal(size=n)}
    for c in ("p_rad_s", "q_rad_s", "r_rad_s"):
        d[c] = 0.2 * rng.normal(size=n)
    if accel:
        d["pdot_rad_s2"], d["qdot_rad_s2"] = rng.normal(size=n), rng.normal(size=n)
    scale = {"delta": 0.01, "pwm": 50.0, "rc_norm": 0.3}
    offset = {"delta": 0.0, "pwm": 1500.0, "rc_norm": 0.0}
    for s in sources:
        for c in INPUT_SOURCES[s]:
            d[c] = offset[s] + scale[s] * rng.normal(size=n)
    return pd.DataFrame(d)


def test_inputs_prefer_blade_pitch_then_pwm_then_sticks():
    assert net_flight_from_df(_table()).input_source == "delta"
    assert net_flight_from_df(_table(sources=("pwm", "rc_norm"))).input_source == "pwm"
    f = net_flight_from_df(_table(sources=("rc_norm",)))
    assert f.input_source == "rc_norm"
    np.testing.assert_array_equal(f.inputs[:, 2], _table(sources=("rc_norm",))["rc_col_norm"])


def test_an_all_nan_delta_column_counts_as_absent():
    # real logs (the T-REX 550 conversion) carry the contract columns as NaN
    df = _table(sources=("delta", "rc_norm"))
    df["delta_lat_rad"] = np.nan
    assert net_flight_from_df(df).input_source == "rc_norm"


def test_missing_rate_column_names_file_and_column():
    df = _table().drop(columns=["q_rad_s"])
    with pytest.raises(FlightTableError, match=r"flight\.csv.*'q_rad_s'"):
        net_flight_from_df(df, "flight.csv")


def test_no_input_set_lists_what_each_set_has():
    df = _table(sources=("pwm",)).drop(columns=["pwm_ch3_us"])
    with pytest.raises(FlightTableError, match=r"f\.parquet: no complete set of pilot inputs.*"
                       r"has \['pwm_ch1_us', 'pwm_ch2_us', 'pwm_ch4_us'\]"):
        net_flight_from_df(df, "f.parquet")


def test_a_nan_inside_a_needed_column_is_reported_with_its_row():
    df = _table()
    df.loc[17, "p_rad_s"] = np.nan
    with pytest.raises(FlightTableError, match=r"'p_rad_s' has 1 NaN.*row 17"):
        net_flight_from_df(df, "x.csv")


def test_accel_target_needs_the_angular_accelerations():
    with pytest.raises(FlightTableError, match="pdot_rad_s2"):
        net_flight_from_df(_table(accel=False), "x.csv", target="accel")
    assert net_flight_from_df(_table(accel=False), "x.csv", target="rates").accel_rad_s2 is None


def test_csv_with_metadata_line_loads_and_crop_keeps_the_range(tmp_path):
    p = tmp_path / "f.csv"
    with p.open("w") as fh:
        fh.write('# airwake-metadata: {"source": "user"}\n')
        _table(sources=("pwm",)).to_csv(fh, index=False)
    f = load_net_flight(p)
    assert f.input_source == "pwm" and len(f) == 300 and np.isclose(f.rate_hz, 150.0)
    c = f.crop(0.5, 1.0)
    assert c.t_s[0] >= 0.5 and c.t_s[-1] <= 1.0 and len(c) == c.rates_rad_s.shape[0] == 76
    with pytest.raises(FlightTableError, match="no rows left"):
        f.crop(50, 60)


def test_missing_file_and_time_gap_are_user_errors(tmp_path):
    with pytest.raises(FlightTableError, match="not found"):
        load_net_flight(tmp_path / "nope.parquet")
    df = _table()
    df.loc[150:, "t_s"] += 2.0
    with pytest.raises(FlightTableError, match=r"gap of 2.* at row 150"):
        net_flight_from_df(df, "gap.csv")


def test_block_split_is_seeded_covers_every_set_and_guards_history():
    t = np.arange(0, 100, 0.01)
    cfg = SplitConfig(block_s=5.0, val_fraction=0.15, test_fraction=0.2)
    a = block_split(t, cfg, 0.5, np.random.default_rng(1))
    b = block_split(t, cfg, 0.5, np.random.default_rng(1))
    np.testing.assert_array_equal(a, b)
    assert {TRAIN, VAL, TEST, GUARD} <= set(np.unique(a))
    assert (a == TEST).sum() == pytest.approx(4 * (500 - 50), abs=200)
    # a sample in a scored set never has another set's sample within its history
    for i in np.flatnonzero(a != GUARD):
        window = a[max(0, i - 50):i + 1]
        assert set(window[window != GUARD]) == {a[i]} and i >= 50
