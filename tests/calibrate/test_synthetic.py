"""The model-generated flights the calibration and wind tests stand on."""

import numpy as np
from airwake.calibrate.synthetic import (
    NoiseSpec,
    WindProfile,
    envelope,
    generate_flight,
    hover_controller,
)
from airwake.heli import MEAS_CHANNELS, load_spec
from airwake.heli.measurement import predict_measurements
from airwake.record.flight_table import CONTRACT_COLUMNS, TRUTH_WIND, validate_flight_table


def test_generated_flight_passes_the_flight_table_checks(still_air_flight):
    # a generated flight must load like a user's: same columns, same unit ranges
    validate_flight_table(still_air_flight.df, "generated", CONTRACT_COLUMNS)
    assert all(c in still_air_flight.df for c in TRUTH_WIND)


def test_generated_flight_stays_in_a_sane_envelope(still_air_flight):
    # Table 5.2 trims at ~17.5 deg roll; the controller must keep the excitation around it
    df = still_air_flight.df
    trim_roll = still_air_flight.metadata["trim_roll_rad"]
    assert abs(np.degrees(trim_roll) - 17.5) < 1.0
    assert np.max(np.abs(df["roll_rad"] - trim_roll)) < 0.35
    assert np.max(np.abs(df["pitch_rad"])) < 0.35
    env = envelope(df)
    assert max(env["p_rad_s"], env["q_rad_s"], env["r_rad_s"]) < 3.0
    assert max(env["vel_u_m_s"], env["vel_v_m_s"], env["vel_w_m_s"]) < 3.0
    assert max(abs(df[c]).max() for c in ("delta_col_rad", "delta_lat_rad", "delta_lon_rad",
                                          "delta_ped_rad")) <= 0.55
    # and excite every axis (identifiability needs motion on all of them)
    assert min(df[c].std() for c in ("p_rad_s", "q_rad_s", "r_rad_s")) > 0.1


def test_measurement_model_reproduces_generated_truth(short_flight):
    # the table's inputs are exactly linear between rows, as the measurement model assumes:
    # predicting the noise-free channels from the table must sit far below sensor noise
    df = short_flight.df
    model = load_spec("table52")
    pred = predict_measurements(model, df)
    truth = df[[f"truth_{c}" for c in MEAS_CHANNELS]].to_numpy()
    err = np.sqrt(np.mean((pred[75:] - truth[75:]) ** 2, axis=0))
    assert np.all(err < [0.002, 0.002, 0.002, 0.02, 0.02, 0.02]), err


def test_noise_has_the_stated_std(still_air_flight):
    df = still_air_flight.df
    noise = NoiseSpec()
    for c, sd in zip(MEAS_CHANNELS, noise.measurement_std(), strict=True):
        e = df[c] - df[f"truth_{c}"]
        assert abs(e.std() / sd - 1) < 0.05, c


def test_same_seed_same_flight_other_seed_other_flight():
    a = generate_flight(duration_s=1.0, seed=1, substeps=2)
    b = generate_flight(duration_s=1.0, seed=1, substeps=2)
    c = generate_flight(duration_s=1.0, seed=2, substeps=2)
    assert a.df.equals(b.df)
    assert not np.allclose(a.df["delta_lat_rad"], c.df["delta_lat_rad"])


def test_wind_profile_is_the_truth_wind_of_the_table():
    wind = WindProfile.slowly_varying((1.0, -0.5, 0.2, 0.1, 0.0, -0.05), (0.5,) * 3 + (0.05,) * 3)
    ft = generate_flight(duration_s=1.0, seed=1, substeps=2, wind=wind)
    got = ft.df[list(TRUTH_WIND)].to_numpy()
    np.testing.assert_allclose(got, wind.deterministic(ft.df["t_s"].to_numpy()), atol=1e-12)


def test_hover_controller_stabilises_the_unstable_hover():
    model = load_spec("table52")
    ctrl = hover_controller(model)
    from airwake.heli.trim import linearize

    a, b = linearize(model, ctrl.x_trim, ctrl.u_trim)
    assert np.max(np.linalg.eigvals(a).real) > 0.1  # the open loop diverges
    assert np.max(np.linalg.eigvals(a - b @ ctrl.gain).real) < 0  # the closed loop does not
    hidden = [model.state_names.index(s) for s in model.hidden_state_names]
    assert np.all(ctrl.gain[:, hidden] == 0)  # feeds back only what a pilot can see


def test_segments_are_separated_by_a_time_gap():
    ft = generate_flight(duration_s=1.0, segments=2, seed=1, substeps=2)
    t = ft.df["t_s"].to_numpy()
    gaps = np.diff(t)
    assert np.all(gaps > 0)
    assert np.sum(gaps > 0.5) == 1
