"""A yaw-rate gyro between the rudder and the tail servo, found in the flight's own pulses
(`airwake.calibrate.yaw_gyro`): the regression on signals whose gyro is known, then the
blade-element airframe (which flies one) and the effect truth (which does not)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pytest
from airwake.calibrate.yaw_gyro import MIN_EXPLAINED, aero_yaw_damping, effect_gain, note, yaw_gyro
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


PER_US = 6.981e-4  # the rigging's tail pitch per us of rudder (any value: it is read back)


def yaw_flight(b_t, n_a, slope, n=6000, fs=150.0, seed=0):
    """A linear yaw axis flown through a rate gyro: r_dot = B_t theta_servo - N_a r, the
    servo's pulse the rudder's plus `slope` us per rad/s of the inertial rate (module doc
    of calibrate.yaw_gyro), a wandering rudder, the collective and airspeed held."""
    rng = np.random.default_rng(seed)
    dt = 1.0 / fs
    rudder = 1500.0 + np.cumsum(rng.normal(0.0, 0.6, n))
    r, rdot, servo = np.zeros(n), np.zeros(n), np.zeros(n)
    for k in range(n):
        servo[k] = rudder[k] + 20.0 + slope * r[k]
        rdot[k] = b_t * PER_US * (servo[k] - 1500.0 - 20.0) - n_a * r[k]
        if k + 1 < n:
            r[k + 1] = r[k] + dt * rdot[k]
    return pd.DataFrame({
        "t_s": np.arange(n) * dt, "tail_servo_pwm_us": servo, "tail_servo_valid": np.ones(n),
        "pwm_ch4_us": rudder, "delta_ped_rad": PER_US * (rudder - 1500.0), "r_rad_s": r,
        "rdot_rad_s2": rdot + rng.normal(0.0, 0.05, n), "delta_col_rad": np.full(n, 0.08),
        "vel_u_m_s": rng.normal(0.0, 0.01, n), "vel_v_m_s": rng.normal(0.0, 0.01, n)})


@settings(max_examples=10, deadline=None)
@given(st.floats(40.0, 120.0), st.floats(0.3, 2.0), st.floats(-120.0, -40.0),
       st.integers(0, 1000))
def test_the_aerodynamic_damping_is_read_with_the_servos_tail_pitch(b_t, n_a, slope, seed):
    # with the rudder as the input the rate's coefficient holds the gyro's loop (B_t g);
    # with the servo's tail pitch it is the airframe's own damping
    df = yaw_flight(b_t, n_a, slope, seed=seed)
    found = yaw_gyro(df)
    aero = aero_yaw_damping(df, found, cutoff_hz=None)
    assert aero["damping_1_s"] == pytest.approx(n_a, rel=0.1, abs=0.05)
    assert aero["pedal_1_s2"] == pytest.approx(b_t, rel=0.1)
    assert aero["per_us"] == pytest.approx(PER_US, rel=1e-6)
    assert aero_yaw_damping(df.drop(columns="rdot_rad_s2"), found) is None
    assert aero_yaw_damping(df, None) is None


def test_the_effects_gain_gives_the_model_the_airframes_answer_to_the_airs_rotation():
    # a model whose damping is all relative to the air, and an airframe whose aerodynamic
    # part is smaller: with yaw_gyro at effect_gain's gain the model's r_dot per omega_z is
    # the airframe's damping, its r_dot per r (what a still-air fit sees) unchanged
    from airwake.heli import load_spec
    from airwake.heli.effects.catalogue import YawGyro
    from airwake.heli.trim import trim_hover

    base = load_spec("table52")
    found = {"found": True, "slope_us_per_rad_s": -86.0, "neutral_us": 20.0}
    share = effect_gain(base, found, {"damping_1_s": 0.0, "per_us": PER_US})
    n_m = share["model_damping_1_s"]
    assert n_m > 0 and share["model_pedal_1_s2"] > 0
    n_a = 0.4 * n_m
    share = effect_gain(base, found, {"damping_1_s": n_a, "per_us": PER_US})
    g = share["gain_rad_per_rad_s"]
    assert share["gyro_gain_rad_per_rad_s"] <= g < 0.0
    model = base + YawGyro(gain_rad_per_rad_s=g)
    tr = trim_hover(base)
    x = np.zeros((1, model.n_states))
    x[0, :base.n_states] = tr.x
    u, h = tr.u[None], 1e-4
    w = np.zeros((1, 6))
    dw = w.copy()
    dw[0, 5] = h
    z0 = model.measure(x, u, w)[0, 5]
    assert (model.measure(x, u, dw)[0, 5] - z0) / h == pytest.approx(n_a, rel=0.02)
    i_r = list(model.state_names).index("rigid_body.r_rad_s")
    dx = x.copy()
    dx[0, i_r] += h
    assert -(model.measure(dx, u, w)[0, 5] - z0) / h == pytest.approx(n_m, rel=1e-3)
    # an airframe damped more than the model leaves nothing to take out; a share beyond
    # the gyro's whole loop is held at the loop
    assert effect_gain(base, found, {"damping_1_s": 2 * n_m, "per_us": PER_US})[
        "gain_rad_per_rad_s"] == 0.0
    weak = {**found, "slope_us_per_rad_s": -1.0}
    assert effect_gain(base, weak, {"damping_1_s": 0.0, "per_us": PER_US})[
        "gain_rad_per_rad_s"] == pytest.approx(-PER_US)
    assert effect_gain(base, None, {"damping_1_s": 0.0, "per_us": PER_US}) is None


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
                    max_nfev=2, yaw_gyro_effect=True)
    info = res.info["yaw_gyro"]
    assert info["found"]
    assert any(n.startswith("yaw gyro:") for n in res.notes), res.notes
    # the gyro's share: the airframe's aerodynamic damping read through the servo (a
    # 600-class tail: well under the gyro's loop), the gain the model gets, and the effect
    # in the fitted model exactly when that gain takes something out
    assert 0.0 < info["aero_damping_1_s"] < info["model_damping_1_s"] + 5.0, info
    assert info["gyro_gain_rad_per_rad_s"] <= info["gain_rad_per_rad_s"] <= 0.0
    assert ("yaw_gyro" in res.model) == (info["gain_rad_per_rad_s"] < 0.0)


def test_the_effect_truth_flies_no_gyro():
    g = yaw_gyro(_flight("effects"))
    assert g is not None and not g["found"], g


def test_a_model_that_took_the_gyros_loop_into_its_tail_gets_the_effect_when_asked():
    # Table 5.2 with the 3 m tail arm the fits reach on this airframe (docs/calibration.md):
    # its yaw damping, all relative to the air, is several times the airframe's
    # aerodynamic damping; --yaw-gyro adds the effect, the default only says so
    from types import SimpleNamespace

    from airwake.calibrate import _gyro_share
    from airwake.heli import load_spec

    base = load_spec("table52")
    tail = base["tail_rotor"]
    model = base.replace(type(tail)(**{**tail.parameters(), "arm_m": 3.0}))
    df = _flight("blade_element")
    for add in (False, True):
        found = yaw_gyro(df)
        res = SimpleNamespace(model=model, notes=[])
        _gyro_share(res, found, df, 6.0, add)
        assert found["aero_damping_1_s"] < 0.5 * found["model_damping_1_s"], found
        g = found["gain_rad_per_rad_s"]
        assert found["gyro_gain_rad_per_rad_s"] < g < 0.0
        assert ("yaw_gyro" in res.model) == add
        assert ("--yaw-gyro adds" in res.notes[-1]) != add, res.notes
        if add:
            assert float(res.model["yaw_gyro"].parameters()["gain_rad_per_rad_s"]) == g
