"""The flight-table builder on synthetic message tables with known truth."""

from __future__ import annotations

import math

import numpy as np
import pytest
from airwake.record.flight_builder import (
    FlightBuildConfig,
    FlightBuildError,
    build_flight_table,
    coverage,
    euler_to_dcm,
    message_table,
    wrap_pi,
)
from airwake.record.flight_table import CONTRACT_COLUMNS, load_flight_table, write_flight_table
from airwake.record.geodesy import lla_to_ned
from airwake.record.rigging import DEFAULT_RIGGING, PwmRigging
from hypothesis import given, settings
from hypothesis import strategies as st

ORIGIN = (38.9784, -76.48, 0.0)


def ned_to_lla(ned: np.ndarray) -> np.ndarray:
    """Inverse of lla_to_ned near the origin by Newton steps (test helper)."""
    lla = np.tile(np.asarray(ORIGIN, float), (len(ned), 1))
    for _ in range(4):
        err = ned - lla_to_ned(lla, ORIGIN)
        lla[:, 0] += np.degrees(err[:, 0] / 6.37e6)
        lla[:, 1] += np.degrees(err[:, 1] / (6.37e6 * math.cos(math.radians(ORIGIN[0]))))
        lla[:, 2] -= err[:, 2]
    return lla


def synthetic_streams(duration_s: float = 6.0, t0: float = 100.0):
    """INS 150 Hz, pilot 50 Hz, rotor 150 Hz, RTK 10 Hz, base INS 150 Hz: analytic truth."""
    t = t0 + np.arange(0.0, duration_s, 1 / 150)
    roll = 0.1 * np.sin(2 * np.pi * 0.5 * t)
    pitch = -0.05 + 0.02 * np.cos(2 * np.pi * 0.3 * t)
    yaw = wrap_pi(2.5 + 0.4 * t)
    p = 0.1 * 2 * np.pi * 0.5 * np.cos(2 * np.pi * 0.5 * t)
    q = 0.3 * np.sin(2 * np.pi * 1.0 * t)
    r = 0.4 + 0.0 * t
    vel_ned = np.stack([2.0 + 0 * t, -1.0 + 0.1 * t, 0.2 * np.sin(t)], axis=-1)
    pos_ned = np.stack([5 + 2.0 * (t - t0), -3.0 + 0 * t, -10.0 + 0 * t], axis=-1)
    lla = ned_to_lla(pos_ned)
    ins = message_table(
        "ins", t, ypr_deg=np.degrees(np.stack([yaw, pitch, roll], -1)),
        angular_rate_frd_rad_s=np.stack([p, q, r], -1), lat_deg=lla[:, 0], lon_deg=lla[:, 1],
        alt_m=lla[:, 2], vel_ned_m_s=vel_ned,
        accel_frd_m_s2=np.stack([0.1 + 0 * t, -0.2 + 0 * t, -9.8 + 0 * t], -1), ins_status=2)
    tp = t0 + 0.003 + np.arange(0.0, duration_s, 1 / 50)
    pwm = np.stack([1500 + 100 * np.sin(tp), 1450 + 0 * tp, 1600 + 50 * np.cos(tp),
                    1500 + 0 * tp, 1700 + 0 * tp], -1)
    pilot = message_table("pilot_inputs", tp, pwm_us=np.round(pwm), valid_mask=0x1F)
    tr = t0 + 0.001 + np.arange(0.0, duration_s, 1 / 150)
    rotor = message_table("rotor_speed", tr, rotor_speed_rad_s=150.0 + tr - t0)
    tb = t0 + np.arange(0.0, duration_s, 0.1)
    baseline = message_table("rtk_baseline", tb, baseline_ned_mm=[[1000, 2000, -3000]],
                             fix_mode=4)
    base = message_table("ins", t, ypr_deg=[[30.0, 1.0, -2.0]], lat_deg=ORIGIN[0],
                         lon_deg=ORIGIN[1], alt_m=0.0, vel_ned_m_s=[[3.0, 4.0, 0.0]])
    truth = dict(t=t, roll=roll, pitch=pitch, yaw=yaw, p=p, q=q, r=r, vel_ned=vel_ned,
                 pos_ned=pos_ned, pwm_t=tp, pwm=pwm)
    streams = {"rover/ins": ins, "base/pilot_inputs": pilot, "rover/rotor_speed": rotor,
               "rover/rtk_baseline": baseline, "base/ins": base}
    return streams, truth


def test_builder_reproduces_known_states_and_derivatives():
    # the export and the simulator's fast path both rely on these conversions
    streams, truth = synthetic_streams()
    built = build_flight_table(streams, FlightBuildConfig(ned_origin_lla=ORIGIN))
    df = built.df
    for c in CONTRACT_COLUMNS:
        assert c in df.columns, c
    rows = np.isin(truth["t"], df["t_s"].to_numpy())
    assert rows.sum() == len(df) and len(df) > 0.95 * truth["t"].size
    np.testing.assert_allclose(df["roll_rad"], truth["roll"][rows], atol=1e-6)
    np.testing.assert_allclose(df["yaw_rad"], truth["yaw"][rows], atol=1e-6)
    np.testing.assert_allclose(df["q_rad_s"], truth["q"][rows], atol=1e-6)
    dcm = euler_to_dcm(truth["roll"], truth["pitch"], truth["yaw"])[rows]
    v_body = df[["vel_u_m_s", "vel_v_m_s", "vel_w_m_s"]].to_numpy()
    np.testing.assert_allclose(np.einsum("nij,nj->ni", dcm, v_body), truth["vel_ned"][rows],
                               atol=1e-5)
    np.testing.assert_allclose(df[["pos_n_m", "pos_e_m", "pos_d_m"]], truth["pos_ned"][rows],
                               atol=1e-3)
    # qdot of 0.3 sin(2 pi t): 0.6 pi cos(2 pi t); the S-G derivative tracks it closely
    qdot = 0.3 * 2 * np.pi * np.cos(2 * np.pi * truth["t"][rows])
    assert np.max(np.abs(df["qdot_rad_s2"] - qdot)) < 0.02 * 0.6 * np.pi
    np.testing.assert_allclose(df["rdot_rad_s2"], 0.0, atol=1e-9)
    assert np.allclose(df["acc_z_m_s2"], -9.8, atol=1e-5)


def test_pilot_inputs_interpolated_and_mapped_by_the_rigging():
    streams, truth = synthetic_streams()
    df = build_flight_table(streams, FlightBuildConfig(ned_origin_lla=ORIGIN)).df
    t = df["t_s"].to_numpy()
    ch3 = np.interp(t, truth["pwm_t"], np.round(truth["pwm"][:, 2]))
    np.testing.assert_allclose(df["pwm_ch3_us"], ch3, atol=1e-9)
    bp = DEFAULT_RIGGING.pwm_to_blade_pitch(df[[f"pwm_ch{i}_us" for i in range(1, 6)]])
    np.testing.assert_allclose(df["delta_col_rad"], bp[:, 0])
    np.testing.assert_allclose(df["delta_lat_rad"], bp[:, 1])
    # collective 1600 us -> 0.07854 + 2.618e-4 * 100 rad
    assert df["delta_lat_rad"].abs().max() <= 100 * 2.793e-4 + 1e-9
    np.testing.assert_allclose(df["delta_lon_rad"], -50 * 2.793e-4)


def test_rigging_numbers_match_the_simulator():
    # the simulator's RC model and the export must invert each other exactly
    rc = pytest.importorskip("hil_sim.sensors.rc")
    m = rc.PwmMapping()
    assert (m.center_us, m.gain_rad_per_us, m.offset_rad) == (
        DEFAULT_RIGGING.center_us, DEFAULT_RIGGING.gain_rad_per_us, DEFAULT_RIGGING.offset_rad)
    pwm = np.array([[1100.0, 1900.0, 1234.0, 1750.0, 1700.0]])
    np.testing.assert_allclose(DEFAULT_RIGGING.pwm_to_blade_pitch(pwm),
                               rc.pwm_to_blade_pitch(pwm))


def test_height_from_rtk_baseline_with_lever_arm_and_deck_offset():
    streams, truth = synthetic_streams()
    cfg = FlightBuildConfig(ned_origin_lla=ORIGIN, base_antenna_height_above_deck_m=1.5,
                            rover_antenna_to_hub_frd_m=(0.0, 0.0, 0.2))
    df = build_flight_table(streams, cfg).df
    rows = np.isin(truth["t"], df["t_s"].to_numpy())
    dcm = euler_to_dcm(truth["roll"], truth["pitch"], truth["yaw"])[rows]
    expected = 1.5 - (-3.0) - (dcm @ np.array([0.0, 0.0, 0.2]))[:, 2]
    h = df["height_agl_m"].to_numpy()
    known = np.isfinite(h)
    np.testing.assert_allclose(h[known], expected[known], atol=1e-9)
    # unknown (inf, which the loader allows) only after the last RTK epoch
    last_rtk = streams["rover/rtk_baseline"].t_s[-1]
    assert np.all(df["t_s"].to_numpy()[~known] > last_rtk) and known.mean() > 0.95
    assert (df["rtk_fix"] == 3).sum() == known.sum()
    np.testing.assert_allclose(df["ship_yaw_rad"], math.radians(30.0))
    np.testing.assert_allclose(df["ship_speed_m_s"], 5.0, rtol=1e-6)


def test_trims_to_required_span_and_drops_rows_in_gaps():
    # the loader rejects NaN: rows without pilot inputs must go, and the metadata says so
    streams, truth = synthetic_streams()
    pilot = streams["base/pilot_inputs"]
    t0 = truth["t"][0]
    keep = ((pilot.t_s > t0 + 1.0) & (pilot.t_s < t0 + 2.0)) | (pilot.t_s > t0 + 3.0)
    streams["base/pilot_inputs"] = type(pilot)(pilot.t_s[keep], pilot.data[keep])
    built = build_flight_table(streams, FlightBuildConfig(ned_origin_lla=ORIGIN))
    t = built.df["t_s"].to_numpy()
    assert t[0] >= t0 + 1.0 and not np.any((t > t0 + 2.0) & (t < t0 + 3.0))
    assert built.metadata["trimmed"]["rows_dropped_head"] > 140
    assert len(built.metadata["gaps"]) == 1
    gap = built.metadata["gaps"][0]
    assert t0 + 1.9 < gap[0] < gap[1] < t0 + 3.1
    assert not built.df.isna().any().any()


def test_missing_required_stream_leaves_columns_out_and_says_so():
    streams, _ = synthetic_streams()
    del streams["rover/rotor_speed"]
    built = build_flight_table(streams, FlightBuildConfig(ned_origin_lla=ORIGIN))
    assert "rotor_speed_rad_s" not in built.df.columns
    assert built.metadata["missing_streams"] == ["rover/rotor_speed"]


def test_no_rover_ins_is_a_clear_error():
    streams, _ = synthetic_streams()
    del streams["rover/ins"]
    with pytest.raises(FlightBuildError, match="rover/ins"):
        build_flight_table(streams)


def test_optional_stream_partial_coverage_marked_not_trimmed():
    streams, truth = synthetic_streams()
    t = truth["t"]
    ta = t[(t > t[0] + 2) & (t < t[0] + 4)][::2]
    streams["marker/anemometer"] = message_table("anemometer", ta,
                                                 wind_uvw_inst_m_s=[[1.0, 2.0, 3.0]],
                                                 sonic_temp_c=20.0)
    df = build_flight_table(streams, FlightBuildConfig(ned_origin_lla=ORIGIN)).df
    assert len(df) > 0.95 * t.size
    valid = df["anemo_valid"].to_numpy() == 1.0
    assert 0.3 < valid.mean() < 0.36
    assert (df["anemo_v_m_s"] == 2.0).all()


@pytest.mark.parametrize("ext", ["parquet", "csv"])
def test_built_table_loads_with_the_flight_table_loader(tmp_path, ext):
    streams, _ = synthetic_streams()
    built = build_flight_table(streams, FlightBuildConfig(ned_origin_lla=ORIGIN))
    path = write_flight_table(built.df, tmp_path / f"f.{ext}", {**built.metadata,
                                                                 "source": "recorder"})
    ft = load_flight_table(path)
    assert len(ft) == len(built.df)
    assert ft.metadata["source"] == "recorder"
    np.testing.assert_allclose(ft.df["p_rad_s"], built.df["p_rad_s"])


def test_coverage_refuses_rows_across_a_long_gap():
    src = np.array([0.0, 0.1, 0.2, 1.0, 1.1])
    rows = np.array([-0.1, 0.0, 0.15, 0.5, 1.05, 1.1, 1.2])
    assert coverage(src, rows, 0.15).tolist() == [False, True, True, False, True, True, False]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(1000, 2000), min_size=4, max_size=4),
       st.lists(st.floats(-1e-3, 1e-3).filter(lambda g: abs(g) > 1e-6), min_size=4,
                max_size=4))
def test_rigging_round_trips(pwm, gains):
    rig = PwmRigging(gain_rad_per_us=tuple(gains))
    bp = rig.pwm_to_blade_pitch(np.array([pwm]))
    np.testing.assert_allclose(rig.blade_pitch_to_pwm(bp)[0], pwm, atol=1e-6)


@settings(max_examples=60, deadline=None)
@given(st.floats(-math.pi, math.pi), st.floats(-1.5, 1.5), st.floats(-10, 10))
def test_euler_dcm_is_a_rotation_and_wrap_stays_in_range(roll, pitch, yaw):
    r = euler_to_dcm(np.array(roll), np.array(pitch), np.array(yaw))
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(r) == pytest.approx(1.0)
    w = wrap_pi(yaw)
    assert -math.pi < w <= math.pi and math.isclose(math.cos(w), math.cos(yaw), abs_tol=1e-9)
