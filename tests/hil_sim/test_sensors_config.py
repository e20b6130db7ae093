"""Config tables -> dataclasses: errors name the key and the value."""

import pytest

from hil_sim.sensors.config import config_from_dict, config_to_dict
from hil_sim.sensors.rc import RcConfig
from hil_sim.sensors.rtk import RtkConfig
from hil_sim.sensors.vn200 import Vn200Config


def test_unknown_key_is_named_with_its_path():
    # A typo in a scenario file must not be silently ignored.
    with pytest.raises(ValueError, match=r"sensors\.vn200: unknown key 'rate_hzz'"):
        config_from_dict(Vn200Config, {"rate_hzz": 100}, "sensors.vn200")


def test_bad_value_names_key_and_value():
    with pytest.raises(ValueError, match=r"rate_hz = -5.0: must be a finite number > 0"):
        config_from_dict(Vn200Config, {"rate_hz": -5}, "sensors.vn200")
    with pytest.raises(ValueError, match=r"sensors\.vn200\.rate_hz = 'fast': expected a number"):
        config_from_dict(Vn200Config, {"rate_hz": "fast"}, "sensors.vn200")


def test_nested_tables_and_lists_convert():
    cfg = config_from_dict(
        Vn200Config,
        {"imu": {"gyro_bias_rad_s": [0.01, 0.0, -0.01],
                 "vibration": {"gyro_2p_rad_s": [0.05, 0.05, 0.0]}},
         "attitude_error_deg": [0.2, 0.2, 0.5]},
        "vn200",
    )
    assert cfg.imu.gyro_bias_rad_s == (0.01, 0.0, -0.01)
    assert cfg.imu.vibration.enabled
    assert cfg.attitude_error_deg == (0.2, 0.2, 0.5)
    with pytest.raises(ValueError, match=r"vn200\.imu\.vibration: unknown key 'gyro_3p'"):
        config_from_dict(Vn200Config, {"imu": {"vibration": {"gyro_3p": 1}}}, "vn200")


def test_schedule_tuples_and_cross_field_checks():
    cfg = config_from_dict(RtkConfig, {"fix_schedule": [[0, "fixed"], [10, "float"]]}, "rtk")
    assert cfg.fix_schedule == ((0.0, "fixed"), (10.0, "float"))
    with pytest.raises(ValueError, match="fix_schedule mode = 'rtk'"):
        config_from_dict(RtkConfig, {"fix_schedule": [[0, "rtk"]]}, "rtk")
    with pytest.raises(ValueError, match="RC frames must be >= 45 Hz"):
        config_from_dict(RcConfig, {"timing": {"frame_rate_hz": 30}}, "rc")


def test_config_round_trips_through_plain_tables():
    cfg = config_from_dict(RtkConfig, {"fixed_sigma_m": [0.02, 0.02, 0.03]}, "rtk")
    assert config_from_dict(RtkConfig, config_to_dict(cfg), "rtk") == cfg
