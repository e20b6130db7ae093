"""A simulated flight end to end: flight-table contract, truth columns, noise, determinism."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from airwake.record.flight_table import CONTRACT_COLUMNS, load_flight_table, write_flight_table
from world_helpers import rms, short_scenario

from hil_sim.world.run import TRUTH_MEAS_COLUMNS, run_scenario
from hil_sim.world.wind import LOCAL_WIND_COLUMNS

SEGMENTS = [
    {"type": "hover", "duration_s": 0.5},
    {"type": "chirp", "channel": "lat", "amplitude_deg": 0.8, "f0_hz": 0.5, "f1_hz": 3.0,
     "duration_s": 3.0},
    {"type": "burst", "channels": ["col", "lon", "ped"], "amplitude_deg": 0.6, "hold_s": 0.4,
     "duration_s": 2.5},
]
DURATION = 6.0


def fly(seed: int = 5, **kw):
    sc = short_scenario(segments=SEGMENTS, duration_s=DURATION, seed=seed, **kw)
    r = run_scenario(sc)
    return r, r.flight_table()


@pytest.fixture(scope="module")
def flight():
    return fly()


def test_flight_table_has_the_contract_columns_and_loads(flight, tmp_path):
    r, built = flight
    missing = [c for c in CONTRACT_COLUMNS if c not in built.df.columns]
    assert not missing
    for c in (*(f"truth_{m}" for m in TRUTH_MEAS_COLUMNS), *LOCAL_WIND_COLUMNS,
              "truth_rotor_speed_rad_s", "truth_height_agl_m", "truth_roll_rad"):
        assert c in built.df.columns
    path = tmp_path / "f.parquet"
    write_flight_table(built.df, path, built.metadata)
    ft = load_flight_table(path)
    assert len(ft.df) == len(built.df)
    assert ft.metadata["scenario"] == r.scenario.name and ft.metadata["seed"] == 5
    assert ft.metadata["source"] == "sim" and ft.metadata["frame"] == "ned"
    t = built.df["t_s"].to_numpy()
    assert np.median(np.diff(t)) == pytest.approx(1 / 150.0, rel=1e-6)
    assert t[-1] > DURATION - 0.1


def test_measured_channels_differ_from_truth_only_by_sensor_noise(flight):
    # the measured accelerations are truth + VN200 noise (+ a little vibration): a lag,
    # a frame or a unit slip between world and sensors would show up as a big residual
    r, built = flight
    df = built.df
    for axis in "xyz":
        res = df[f"acc_{axis}_m_s2"] - df[f"truth_acc_{axis}_m_s2"]
        assert rms(res) < 0.1, axis
        assert abs(res.mean()) < 0.02
    for c in ("p", "q", "r"):
        assert rms(df[f"{c}_rad_s"] - df[f"truth_{c}_rad_s"]) < 0.01
    # the S-G derivative of the gyro follows the true angular acceleration
    assert rms(df["pdot_rad_s2"] - df["truth_pdot_rad_s2"]) < 0.1 * df["truth_pdot_rad_s2"].std()
    assert rms(df["rotor_speed_rad_s"] - df["truth_rotor_speed_rad_s"]) < 0.2


def test_recorded_inputs_are_the_commands_the_truth_flew(flight):
    # no hidden servo lag here: the RC records exactly the pitch the rotor got (to the
    # 1 us PWM quantum), so the host model sees the right inputs
    _, built = flight
    df = built.df
    for c in ("col", "lat", "lon", "ped"):
        err = df[f"delta_{c}_rad"] - df[f"truth_delta_{c}_rad"]
        assert np.max(np.abs(err)) < 1e-3, c
    assert df["delta_lat_rad"].std() > np.radians(0.3)


def test_pilot_stays_in_the_envelope_while_exciting_the_helicopter(flight):
    r, built = flight
    df = built.df
    assert np.degrees(df["truth_p_rad_s"]).abs().max() > 5.0
    assert np.degrees(df["truth_roll_rad"]).abs().max() < 30.0
    start = df[["truth_pos_n_m", "truth_pos_e_m", "truth_pos_d_m"]].to_numpy()[0]
    pos = df[["truth_pos_n_m", "truth_pos_e_m", "truth_pos_d_m"]].to_numpy()
    assert np.max(np.linalg.norm(pos - start, axis=1)) < 1.0
    assert df[[c for c in df.columns if c.startswith("pwm_ch")]].stack().between(
        1000, 2000).all()


def test_same_seed_gives_the_same_table_and_another_seed_other_noise(flight):
    _, built = flight
    _, again = fly(seed=5)
    pd.testing.assert_frame_equal(built.df, again.df)
    _, other = fly(seed=6)
    assert not np.allclose(built.df["acc_x_m_s2"], other.df["acc_x_m_s2"])


def test_no_column_names_a_hidden_effect(flight):
    # the analysis reads every non-truth column: none may give the answer away
    _, built = flight
    for c in built.df.columns:
        low = c.lower()
        for word in ("ground_effect", "lever", "servo_lag", "lag_", "droop", "governor",
                     "recirc", "hidden", "inflow", "hil_"):
            assert word not in low, c


def test_rotor_vibration_shows_at_one_and_two_per_rev(flight):
    r, built = flight
    df = built.df
    res = (df["acc_z_m_s2"] - df["truth_acc_z_m_s2"]).to_numpy()
    freqs = np.fft.rfftfreq(res.size, 1 / 150.0)
    spec = np.abs(np.fft.rfft(res * np.hanning(res.size)))
    two_per_rev = 2 * df["truth_rotor_speed_rad_s"].mean() / (2 * np.pi)
    near = np.abs(freqs - two_per_rev) < 1.0
    far = (freqs > 5) & (np.abs(freqs - two_per_rev) > 5) & (np.abs(freqs - two_per_rev / 2) > 5)
    assert spec[near].max() > 10 * np.median(spec[far])


def test_host_model_with_the_truth_parameters_predicts_to_the_noise_floor(flight):
    # world and host agree on frames, units, input timing and rotor speed: with the truth
    # parameters and no hidden effect the one-step-ahead residual is the sensor noise
    # (pdot/qdot: plus the host's hidden-rotor-state reconstruction, ~1.3x)
    from airwake.heli.measurement import predict_measurements

    r, built = flight
    df = built.df
    z = predict_measurements(r.truth_model.host_model, df)
    sel = df["t_s"].to_numpy() > 1.0
    for j, c in enumerate(TRUTH_MEAS_COLUMNS):
        resid = rms((df[c].to_numpy() - z[:, j])[sel])
        floor = rms((df[c] - df[f"truth_{c}"]).to_numpy()[sel])
        assert resid < (1.8 if c in ("pdot_rad_s2", "qdot_rad_s2") else 1.25) * floor, c
