"""The blade-element truth through the boards: a SIL flight (native rover and base
firmware, ptys, the real daemon) exports to a flight table like any other truth, with the
tail gyro's servo pulses on the rover and the rotor's real speed on the tachometer."""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pytest
from sil_harness import run_flight, shared_flight

pytestmark = pytest.mark.slow

SCENARIO = """
extends = "ship_airwake_b15"
description = "SIL test flight on the blade-element truth: hover behind the hangar"

[helicopter]
model = "blade_element"
pilot = "crossover"

[[pilot.segments]]
type = "hover"
duration_s = 8.0
"""


@pytest.fixture(scope="module")
def blade_flight(tmp_path_factory):
    from hil_sim.world.scenario import load_scenario

    def make(d):
        path = d / "scenario.toml"
        path.write_text(SCENARIO)
        sc = load_scenario(path)
        sc = dataclasses.replace(sc, pilot=dataclasses.replace(
            sc.pilot, segments=sc.pilot.segments[-1:]))
        run_flight(d, sc, duration_s=6.0)

    return shared_flight(tmp_path_factory, "blade-element", make)


def test_blade_element_flight_through_the_boards_exports(blade_flight):
    df = pd.read_parquet(blade_flight / "flight.parquet")
    truth = np.load(blade_flight / "truth.npz")
    assert len(df) > 0.9 * 150 * 5.0  # the INS at 150 Hz through the rover and base
    # the rotor turns at the governor's speed, as the rover's tachometer measures it
    assert np.median(df["rotor_speed_rad_s"]) == pytest.approx(
        np.median(truth["rotor_speed_rad_s"]), rel=0.02)
    # the tail servo is the gyro's output, not the rudder channel
    assert np.std(df["tail_servo_pwm_us"] - df["pwm_ch4_us"]) > 1.0
    # the INS attitude is the truth's (the boards carried the real thing)
    roll_truth = np.interp(df["t_s"] - df["t_s"].iloc[0] + truth["vn_t_s"][0],
                           truth["t_s"], truth["euler_rad"][:, 0])
    assert np.median(np.abs(df["roll_rad"] - roll_truth)) < np.radians(1.0)
