"""Motion compensation: the sensor equation inverted with the tracked pose (§3.4)."""

import numpy as np
import pandas as pd
import pytest
from airwake.windmap.compensate import compensate
from airwake.windmap.errors import WindMapError


def test_compensation_recovers_the_field_at_the_sensor_on_a_moving_tilted_mount(survey):
    # the carrier yaws by +-0.6 rad, tilts and walks at 0.4 m/s: without the rotation,
    # the velocity and the lever arm's omega x r the samples would be off by ~m/s
    table, _ = survey
    s = compensate(table.df, table.metadata)
    truth = table.df[["truth_anemo_wind_n_m_s", "truth_anemo_wind_e_m_s",
                      "truth_anemo_wind_d_m_s"]].to_numpy()
    rms = np.sqrt(np.mean((s.wind - truth) ** 2, axis=0))
    assert np.all(rms < 0.03), rms  # the sensor's own 0.02 m/s noise and 0.01 quantum
    raw = table.df[["anemo_u_m_s", "anemo_v_m_s", "anemo_w_m_s"]].to_numpy()
    assert np.sqrt(np.mean((raw - truth) ** 2)) > 0.3  # the uncompensated error


def test_a_marker_turned_on_the_pole_needs_only_the_mount():
    # the marker mounted turned on the pole (its LED toward the tracker), the anemometer
    # upright: the survey's truth pose is the marker's, its metadata carry the lever arm in
    # marker axes and the anemometer's axes relative to the marker's; compensation with
    # them recovers the field, and ignoring the mount does not
    from hil_sim.world.anemometer_survey import SurveyConfig, survey_table

    mount = np.array([0.8, 0.2, -0.3, 0.4])
    mount /= np.linalg.norm(mount)
    cfg = SurveyConfig(x_range_m=(1.0, 2.0), y_range_m=(0.0, 0.3), heights_d_m=(-1.5,),
                       dwell_s=2.0, marker_mount_quat_wxyz=tuple(mount))
    df, meta = survey_table(cfg, seed=9)
    truth = df[["truth_anemo_wind_n_m_s", "truth_anemo_wind_e_m_s",
                "truth_anemo_wind_d_m_s"]].to_numpy()
    s = compensate(df, meta)
    assert np.all(np.sqrt(np.mean((s.wind - truth) ** 2, axis=0)) < 0.03)
    wrong = compensate(df, meta, mount_quat_wxyz=(1.0, 0.0, 0.0, 0.0))
    assert np.sqrt(np.mean((wrong.wind - truth) ** 2)) > 0.5
    with pytest.raises(WindMapError, match="unit quaternion"):
        compensate(df, meta, mount_quat_wxyz=(1.0, 1.0, 0.0, 0.0))


def test_marker_pose_rows_without_a_valid_track_are_left_out():
    # dead reckoning (marker_valid 0) is metres off within seconds: not mapped with
    n = 6
    df = pd.DataFrame({"t_s": np.arange(n) * 0.01, "anemo_u_m_s": 1.0, "anemo_v_m_s": 0.0,
                       "anemo_w_m_s": 0.0,
                       **{f"marker_pos_{a}_m": 0.0 for a in "ned"},
                       **{f"marker_vel_{a}_m_s": 0.0 for a in "ned"},
                       **{f"marker_{a}_rad": 0.0 for a in ("roll", "pitch", "yaw")},
                       **{f"marker_{a}_rad_s": 0.0 for a in "pqr"},
                       "marker_valid": [1.0, 1.0, 0.0, 0.0, 1.0, 0.0]})
    assert compensate(df).t.size == 3
    df["marker_valid"] = 0.0
    with pytest.raises(WindMapError, match="marker_valid"):
        compensate(df)


def test_lever_arm_moves_the_sample_position_and_adds_omega_cross_r():
    # one sample, yawed 90 deg, spinning at r = 1 rad/s about z, anemometer 1 m ahead
    df = pd.DataFrame({"t_s": [0.0, 0.01], "anemo_u_m_s": [0.0, 0.0],
                       "anemo_v_m_s": [0.0, 0.0], "anemo_w_m_s": [0.0, 0.0],
                       **{f"truth_pos_{n}_m": [0.0, 0.0] for n in "ned"},
                       **{f"truth_vel_{n}_m_s": [0.0, 0.0] for n in "uvw"},
                       "truth_roll_rad": [0.0, 0.0], "truth_pitch_rad": [0.0, 0.0],
                       "truth_yaw_rad": [np.pi / 2, np.pi / 2], "truth_p_rad_s": [0.0, 0.0],
                       "truth_q_rad_s": [0.0, 0.0], "truth_r_rad_s": [1.0, 1.0]})
    s = compensate(df, {"anemometer_lever_arm_m": [1.0, 0.0, 0.0]})
    np.testing.assert_allclose(s.pos[0], [0.0, 1.0, 0.0], atol=1e-12)  # ahead = east
    # still air read as zero by a sensor moving at omega x r = 1 m/s along body y (= -north)
    np.testing.assert_allclose(s.wind[0], [-1.0, 0.0, 0.0], atol=1e-12)


def test_marker_pose_is_preferred_and_its_velocity_is_ned():
    n = 3
    df = pd.DataFrame({"t_s": np.arange(n) * 0.01, "anemo_u_m_s": 1.0, "anemo_v_m_s": 0.0,
                       "anemo_w_m_s": 0.0,
                       **{f"marker_pos_{c}_m": 0.0 for c in "ned"},
                       "marker_vel_n_m_s": 0.5, "marker_vel_e_m_s": 0.0,
                       "marker_vel_d_m_s": 0.0, "marker_roll_rad": 0.0,
                       "marker_pitch_rad": 0.0, "marker_yaw_rad": np.pi,
                       **{f"marker_{c}_rad_s": 0.0 for c in "pqr"}})
    s = compensate(df)
    assert s.pose == "marker"
    np.testing.assert_allclose(s.wind, np.tile([-0.5, 0.0, 0.0], (n, 1)), atol=1e-12)


def test_table_without_anemometer_names_the_missing_columns():
    df = pd.DataFrame({"t_s": [0.0], "anemo_u_m_s": [1.0]})
    with pytest.raises(WindMapError, match="anemo_v_m_s, anemo_w_m_s"):
        compensate(df)


def test_table_without_pose_names_what_each_source_lacks():
    df = pd.DataFrame({"t_s": [0.0], "anemo_u_m_s": [1.0], "anemo_v_m_s": [0.0],
                       "anemo_w_m_s": [0.0], "truth_pos_n_m": [0.0]})
    with pytest.raises(WindMapError) as exc:
        compensate(df)
    msg = str(exc.value)
    assert "no anemometer pose" in msg and "marker_pos_n_m" in msg
    assert "truth_pos_e_m" in msg and "truth_pos_n_m," not in msg
    assert "\n" not in msg
