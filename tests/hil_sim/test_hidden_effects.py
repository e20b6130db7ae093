"""Each hidden effect changes exactly the channels it should (same state / same seed, with
and without it)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from world_helpers import short_scenario

from hil_sim.world.hidden import (
    DynamicInflowConfig,
    GroundEffectConfig,
    HiddenConfig,
    RotorDroopConfig,
    ServoLagConfig,
    WakeRecirculationConfig,
)
from hil_sim.world.run import TruthStepper, run_scenario
from hil_sim.world.truth import build_truth_model

CHIRP = [{"type": "hover", "duration_s": 0.3},
         {"type": "chirp", "channel": "lat", "amplitude_deg": 0.8, "f0_hz": 1.0, "f1_hz": 3.0,
          "duration_s": 2.7}]


def evaluate(truth, x, u, h=np.inf):
    return TruthStepper(truth.model).evaluate(x, u, np.zeros(6), h)[1]


@pytest.fixture(scope="module")
def clean():
    t = build_truth_model()
    return t, t.trim()


# -- ground effect ------------------------------------------------------------------


def test_ground_effect_adds_thrust_near_the_ground_only(clean):
    # Cheeseman-Bennett acts on the thrust (acc_z) alone, grows as (R/4z)^2 and is zero
    # above 3 R: a residual outside acc_z or high up would be a different effect
    host, tr = clean
    ge = build_truth_model(hidden=HiddenConfig(ground_effect=GroundEffectConfig()))
    x, u = tr.x, tr.u
    base = evaluate(host, x, u)
    high = evaluate(ge, x, u, h=2.5)
    assert np.array_equal(high, base)
    deltas = []
    for h in (1.5, 1.0, 0.67):
        d = evaluate(ge, x, u, h=h) - base
        deltas.append(-d[2])
        assert d[2] < 0  # more thrust: specific force more negative
        others = np.abs(np.delete(d, 2))
        assert np.max(others) < 0.02 * abs(d[2]) + 1e-9
    assert deltas[0] < deltas[1] < deltas[2]
    ratio = 1.0 / (1.0 - (ge.rotor_radius_m / (4 * 0.67)) ** 2)
    assert deltas[2] / 9.78 == pytest.approx(ratio - 1.0, rel=0.5)


def test_ground_effect_fades_with_forward_speed(clean):
    host, tr = clean
    ge = build_truth_model(hidden=HiddenConfig(ground_effect=GroundEffectConfig()))
    hover = evaluate(ge, tr.x, tr.u, 0.67)[2] - evaluate(host, tr.x, tr.u)[2]
    x = tr.x.copy()
    x[ge.model.state_index("vel_u_m_s")] = 6.0
    fast = evaluate(ge, x, tr.u, 0.67)[2] - evaluate(host, x, tr.u)[2]
    assert abs(fast) < 0.5 * abs(hover)


# -- wake recirculation --------------------------------------------------------------


def test_recirculation_loses_thrust_at_low_height_and_low_speed_not_in_hover(clean):
    host, tr = clean
    rc = build_truth_model(hidden=HiddenConfig(wake_recirculation=WakeRecirculationConfig()))
    assert np.array_equal(evaluate(rc, tr.x, tr.u, 0.7), evaluate(host, tr.x, tr.u))
    x = tr.x.copy()
    x[rc.model.state_index("vel_u_m_s")] = 3.0
    low = evaluate(rc, x, tr.u, 0.7) - evaluate(host, x, tr.u)
    high = evaluate(rc, x, tr.u, 2.5) - evaluate(host, x, tr.u)
    assert low[2] > 0.2  # thrust loss: opposite sign to ground effect
    assert np.array_equal(high, np.zeros(6))
    x[rc.model.state_index("vel_u_m_s")] = 12.0
    fast = evaluate(rc, x, tr.u, 0.7) - evaluate(host, x, tr.u)
    assert abs(fast[2]) < 0.2 * low[2]


def test_dynamic_inflow_overshoots_a_collective_step_then_agrees(clean):
    # the lagged inflow meets a collective step with the old inflow: more thrust at
    # first, the same once the inflow has caught up
    host, tr = clean
    dyn = build_truth_model(hidden=HiddenConfig(dynamic_inflow=DynamicInflowConfig(tau_s=0.08)))
    trd = dyn.trim()
    step = np.radians([1.0, 0.0, 0.0, 0.0])
    out = {}
    final = {}
    for name, truth, trim in (("host", host, tr), ("dyn", dyn, trd)):
        s = TruthStepper(truth.model)
        x = trim.x.copy()
        acc = []
        for _ in range(400):
            acc.append(s.evaluate(x, trim.u + step, np.zeros(6), np.inf)[1][2])
            x = s.step(x, trim.u + step, np.zeros(6), np.inf, 1e-3)
        out[name] = np.asarray(acc) - evaluate(truth, trim.x, trim.u)[2]
        final[name] = x
    early = slice(5, 40)
    assert np.max(-out["dyn"][early]) > 1.3 * np.max(-out["host"][early])
    # 5 time constants later the lagged inflow has caught up: at the same (final) state
    # the host model without the lag predicts the same thrust
    n = host.model.n_states
    caught_up = evaluate(host, final["dyn"][:n], trd.u + step)[2]
    # (to the small lag the still-accelerating climb keeps)
    assert out["dyn"][-1] + evaluate(dyn, trd.x, trd.u)[2] == pytest.approx(caught_up, rel=0.03)


# -- servo lag -------------------------------------------------------------------------


def test_servo_lag_changes_nothing_in_a_constant_input_hover(clean):
    host, tr = clean
    lag = build_truth_model(hidden=HiddenConfig(servo_lag=ServoLagConfig()))
    trl = lag.trim()
    a, b = TruthStepper(host.model), TruthStepper(lag.model)
    xa, xb = tr.x.copy(), trl.x.copy()
    n = host.model.n_states
    for _ in range(200):
        xa = a.step(xa, tr.u, np.zeros(6), np.inf, 1e-3)
        xb = b.step(xb, trl.u, np.zeros(6), np.inf, 1e-3)
    assert np.allclose(xa, xb[:n], atol=1e-9)


def _phase_at(t, y, f):
    """Phase (rad) of the f-Hz component of y(t) by least squares."""
    a = np.column_stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t), np.ones_like(t)])
    s, c, _ = np.linalg.lstsq(a, y, rcond=None)[0]
    return math.atan2(c, s)


def test_servo_lag_shifts_the_response_phase_under_an_oscillating_input(clean):
    host, tr = clean
    tau = 0.06
    lag = build_truth_model(hidden=HiddenConfig(servo_lag=ServoLagConfig(tau_swash_s=tau)))
    trl = lag.trim()
    f = 2.0
    amp = math.radians(0.4)
    phases = {}
    for name, truth, trim in (("host", host, tr), ("lag", lag, trl)):
        s = TruthStepper(truth.model)
        x = trim.x.copy()
        ts, pdot = [], []
        for i in range(1200):
            t = i * 1e-3
            u = trim.u + np.array([0.0, amp * math.sin(2 * np.pi * f * t), 0.0, 0.0])
            xd, meas, _ = s.evaluate(x, u, np.zeros(6), np.inf)
            ts.append(t)
            pdot.append(meas[3])
            x = s.step(x, u, np.zeros(6), np.inf, 1e-3)
        ts, pdot = np.asarray(ts), np.asarray(pdot)
        sel = ts > 0.4
        phases[name] = _phase_at(ts[sel], pdot[sel], f)
    shift = (phases["host"] - phases["lag"]) % (2 * np.pi)
    assert shift == pytest.approx(math.atan(2 * np.pi * f * tau), rel=0.3)


# -- rotor droop ------------------------------------------------------------------------


def test_governor_droops_rotor_speed_with_collective(clean):
    # a finite-gain governor settles (Q_rotor - Q_ff)/K low: more collective, more torque,
    # less speed; without the effect the rotor speed is the constant nominal
    host, tr = clean
    droop = build_truth_model(hidden=HiddenConfig(rotor_droop=RotorDroopConfig()))
    trd = droop.trim()
    s = TruthStepper(droop.model)
    x = trd.x.copy()
    u = trd.u + np.radians([1.0, 0.0, 0.0, 0.0])
    for _ in range(1500):
        x = s.step(x, u, np.zeros(6), np.inf, 1e-3)
    omega = x[droop.model.state_index("hil_rotor_governor.omega_rad_s")]
    nominal = droop.nominal_rotor_speed_rad_s
    assert trd.x[droop.model.state_index("hil_rotor_governor.omega_rad_s")] == pytest.approx(
        nominal, abs=1e-6)
    assert nominal - omega > 2.0
    assert TruthStepper(host.model).evaluate(tr.x, u, np.zeros(6), np.inf)[2] == nominal


def test_droop_shows_in_the_recorded_rotor_speed_and_not_without_it():
    seg = [{"type": "hover", "duration_s": 0.3},
           {"type": "burst", "channels": ["col"], "amplitude_deg": 1.0, "hold_s": 0.6,
            "duration_s": 2.7}]
    with_droop = run_scenario(short_scenario(segments=seg, duration_s=3.0, hidden={
        "rotor_droop": {}})).flight_table().df
    without = run_scenario(short_scenario(segments=seg, duration_s=3.0)).flight_table().df
    assert with_droop["rotor_speed_rad_s"].std() > 0.5
    assert without["rotor_speed_rad_s"].std() < 0.2
    assert without["truth_rotor_speed_rad_s"].std() == 0.0


# -- lever arm ------------------------------------------------------------------------


def test_lever_arm_changes_accelerometers_but_not_gyros():
    r0 = run_scenario(short_scenario(segments=CHIRP, duration_s=3.0))
    r1 = run_scenario(short_scenario(segments=CHIRP, duration_s=3.0, hidden={
        "lever_arm": {"position_m": [0.10, -0.05, -0.12]}}))
    a, b = r0.flight_table().df, r1.flight_table().df
    for c in ("p_rad_s", "q_rad_s", "r_rad_s", "pdot_rad_s2", "qdot_rad_s2", "rdot_rad_s2",
              "truth_pdot_rad_s2", "roll_rad", "delta_lat_rad"):
        assert np.array_equal(a[c].to_numpy(), b[c].to_numpy()), c
    d = (b[["truth_acc_x_m_s2", "truth_acc_y_m_s2", "truth_acc_z_m_s2"]].to_numpy()
         - a[["truth_acc_x_m_s2", "truth_acc_y_m_s2", "truth_acc_z_m_s2"]].to_numpy())
    r = np.array([0.10, -0.05, -0.12])
    w = a[["truth_p_rad_s", "truth_q_rad_s", "truth_r_rad_s"]].to_numpy()
    wd = a[["truth_pdot_rad_s2", "truth_qdot_rad_s2", "truth_rdot_rad_s2"]].to_numpy()
    expect = np.cross(wd, r) + np.cross(w, np.cross(w, r))
    assert np.allclose(d, expect, atol=1e-4)
    assert np.sqrt(np.mean(d**2)) > 0.1
    meas = b[["acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"]].to_numpy() - a[
        ["acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"]].to_numpy()
    assert np.allclose(meas, d, atol=1e-4)  # same noise draws, shifted by the lever arm


def test_servo_delay_makes_the_blade_pitch_trail_the_recorded_command():
    # the pure delay sits before the lag: the rotor sees the RC command 30 ms late
    r = run_scenario(short_scenario(segments=CHIRP, duration_s=3.0, hidden={
        "servo_lag": {"tau_swash_s": 0.002, "tau_tail_s": 0.002, "delay_s": 0.03}}))
    df = r.flight_table().df
    t = df["t_s"].to_numpy()
    rec = df["delta_lat_rad"].to_numpy()
    got = df["truth_delta_lat_rad"].to_numpy()
    sel = (t > 1.0) & (t < 2.9)
    lags = np.arange(0.0, 0.06, 0.001)
    err = [np.sqrt(np.mean((np.interp(t[sel] - d, t, rec) - got[sel]) ** 2)) for d in lags]
    assert lags[int(np.argmin(err))] == pytest.approx(0.03 + 0.002, abs=0.003)
