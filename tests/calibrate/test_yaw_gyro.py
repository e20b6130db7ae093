"""A yaw-rate gyro between the rudder and the tail servo, found in the flight's own pulses
(`airwake.calibrate.yaw_gyro`): the regression on signals whose gyro is known, then the
blade-element airframe (which flies one) and the effect truth (which does not)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pytest
from airwake.calibrate.yaw_gyro import MIN_EXPLAINED, note, yaw_gyro
from hypothesis import given, settings
from hypothesis import strategies as st
from truths import effect_truth


def pulses(slope, neutral, n=3000, seed=0, jitter_us=0.5):
    """A flight's rudder and tail-servo pulses with a gyro of `slope` us per rad/s."""
    rng = np.random.default_rng(seed)
    r = np.cumsum(rng.normal(0.0, 0.01, n))  # a wandering yaw rate (rad/s)
    r -= r.mean()
    rudder = 1500.0 + np.cumsum(rng.normal(0.0, 0.5, n))
    servo = rudder + neutral + slope * r + rng.normal(0.0, jitter_us, n)
    return pd.DataFrame({"tail_servo_pwm_us": servo, "tail_servo_valid": np.ones(n),
                         "pwm_ch4_us": rudder, "r_rad_s": r})


@settings(max_examples=25)
@given(st.floats(-150.0, -20.0), st.floats(-40.0, 40.0), st.integers(0, 10_000))
def test_a_rate_gyro_is_found_with_its_gain_and_neutral(slope, neutral, seed):
    df = pulses(slope, neutral, seed=seed)
    g = yaw_gyro(df)
    assert g["found"] and g["explained"] > 0.9
    assert g["slope_us_per_rad_s"] == pytest.approx(slope, rel=0.05)
    assert g["neutral_us"] == pytest.approx(neutral, abs=1.0)
    assert "yaw gyro" in note(g) and f"{g['slope_us_per_rad_s']:+.1f}" in note(g)


@settings(max_examples=25)
@given(st.floats(-40.0, 40.0), st.integers(0, 10_000))
def test_no_gyro_is_found_where_the_servo_follows_the_rudder(neutral, seed):
    g = yaw_gyro(pulses(0.0, neutral, seed=seed, jitter_us=2.0))
    assert not g["found"] and g["explained"] < MIN_EXPLAINED and note(g) is None


def test_invalid_rows_are_not_read_and_a_flight_that_cannot_say_gives_none():
    df = pulses(-86.0, 20.0)
    bad = df.copy()
    bad.loc[::3, "tail_servo_pwm_us"] = 9999.0  # held values where the stream had a gap
    bad.loc[::3, "tail_servo_valid"] = 0.0
    assert yaw_gyro(bad)["slope_us_per_rad_s"] == pytest.approx(-86.0, rel=0.05)
    assert yaw_gyro(df.drop(columns="tail_servo_pwm_us")) is None  # no capture
    still = df.assign(r_rad_s=0.001)  # a rate that does not move shows no gain
    assert yaw_gyro(still) is None
    assert yaw_gyro(df.iloc[:50]) is None  # too few rows
    assert note(None) is None


def _flight(model: str):
    from hil_sim.world.run import run_scenario
    from hil_sim.world.scenario import load_scenario

    sc = effect_truth(load_scenario("still_air_calibration"))
    sc = dataclasses.replace(sc, helicopter=dataclasses.replace(
        sc.helicopter, model=model, pilot="crossover" if model == "blade_element"
        else sc.helicopter.pilot))
    return run_scenario(sc, seed=7, duration_s=12.0).flight_table().df


def test_the_blade_element_airframes_gyro_is_found_and_the_calibration_says_so():
    # the airframe flies a rate-mode gyro (its data sheet's class value; the host reads
    # none of it): the pulses show it, and the calibration's report names it
    from airwake.calibrate import calibrate

    df = _flight("blade_element")
    g = yaw_gyro(df)
    assert g["found"] and g["slope_us_per_rad_s"] < -20.0 and g["explained"] > 0.9, g
    res = calibrate(df, model="table52", params=["rigid_body.Izz_kg_m2"], max_windows=4,
                    max_nfev=2)
    assert res.info["yaw_gyro"]["found"]
    assert any(n.startswith("yaw gyro:") for n in res.notes), res.notes


def test_the_effect_truth_flies_no_gyro():
    g = yaw_gyro(_flight("effects"))
    assert g is not None and not g["found"], g
