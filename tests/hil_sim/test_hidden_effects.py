"""Each hidden effect's physics against its source's numbers, and the channels it changes
(same state / same seed, with and without it)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from airwake.heli import HeliModel
from truths import effect_truth
from world_helpers import short_scenario

from hil_sim.world.hidden import (
    DynamicInflowConfig,
    ElectricDriveGovernor,
    GroundEffectConfig,
    HiddenConfig,
    RotorDroopConfig,
    SecondOrderServo,
    ServoLagConfig,
    WakeRecirculationConfig,
    hidden_from_dict,
)
from hil_sim.world.hidden.dynamic_inflow import M_HARMONIC, M_MEAN
from hil_sim.world.hidden.ground_effect import (
    deck_height_equivalent,
    footprint_overlap,
    hayden_power_ratio,
    hayden_reduction,
)
from hil_sim.world.hidden.sensor_side import rectification_offset
from hil_sim.world.run import TruthStepper, _height_function, run_scenario
from hil_sim.world.scenario import load_scenario
from hil_sim.world.ship import Ship
from hil_sim.world.truth import build_truth_model

CHIRP = [{"type": "hover", "duration_s": 0.3},
         {"type": "chirp", "channel": "lat", "amplitude_deg": 0.8, "f0_hz": 1.0, "f1_hz": 3.0,
          "duration_s": 2.7}]
ZERO_WIND = np.zeros(6)


def evaluate(truth, x, u, h=np.inf):
    return TruthStepper(truth.model).evaluate(x, u, ZERO_WIND, h)[1]


def simulate(model, x, u, seconds, dt=1e-3, h=np.inf):
    """(steps + 1, S) states of `model` from x under constant inputs u (held)."""
    stepper = TruthStepper(model)
    out = [x.copy()]
    for _ in range(int(round(seconds / dt))):
        x = stepper.step(x, u, ZERO_WIND, h, dt)
        out.append(x)
    return np.asarray(out)


@pytest.fixture(scope="module")
def clean():
    t = build_truth_model()
    return t, t.trim()


def with_hidden(**configs):
    return build_truth_model(hidden=HiddenConfig(**configs))


# -- ground effect: Hayden 1976 ---------------------------------------------------------


def test_hayden_fit_gives_the_published_power_ratios():
    # P_IGE/P_OGE = 1/(0.9926 + 0.0379 (2R/z)^2): 0.874 at z = R, 0.970 at z = 2R (z/D = 1)
    assert hayden_power_ratio(1.0) == pytest.approx(1 / 1.1442, rel=1e-6)
    assert hayden_power_ratio(1.0) == pytest.approx(0.874, abs=5e-4)
    assert hayden_power_ratio(2.0) == pytest.approx(0.970, abs=5e-4)
    # normalised to be exactly nothing out of ground effect
    assert hayden_reduction(np.inf) == 0.0
    assert hayden_reduction(1.0) == pytest.approx(1 - 0.9926 / 1.1442, rel=1e-9)


def test_ground_effect_trim_at_one_radius_cuts_the_induced_velocity_as_hayden(clean):
    # Hayden's ratio is at constant thrust: trimmed in hover (thrust = weight either way)
    # at z = R, the truth's induced velocity is k_H = 0.9926/1.1442 = 0.8675 of the
    # out-of-ground value (to the linearisation of the thrust-consistent solve)
    host, tr = clean
    ge = with_hidden(ground_effect=GroundEffectConfig())
    radius = ge.rotor_radius_m
    trg = ge.trim(height_agl_m=radius)
    env = {"height_agl_m": np.array([radius])}
    lam_ige = ge.model.evaluate(trg.x[None], trg.u[None], env=env).inflow_0[0]
    lam_oge = host.model.evaluate(tr.x[None], tr.u[None]).inflow_0[0]
    thrust_ige = ge.model.evaluate(trg.x[None], trg.u[None], env=env).thrust_n[0]
    thrust_oge = host.model.evaluate(tr.x[None], tr.u[None]).thrust_n[0]
    assert thrust_ige == pytest.approx(thrust_oge, rel=2e-3)
    assert lam_ige / lam_oge == pytest.approx(0.9926 / 1.1442, abs=0.01)
    assert trg.u[0] < tr.u[0] - math.radians(0.2)  # less collective in ground effect


def test_ground_effect_adds_thrust_near_the_ground_only_and_is_nothing_far_away(clean):
    host, tr = clean
    ge = with_hidden(ground_effect=GroundEffectConfig())
    radius = ge.rotor_radius_m
    base = evaluate(host, tr.x, tr.u)
    assert np.array_equal(evaluate(ge, tr.x, tr.u, h=np.inf), base)
    gains = []
    for zr in (4.0, 2.0, 1.5, 1.0, 0.6):
        d = evaluate(ge, tr.x, tr.u, h=zr * radius) - base
        gains.append(-d[2])
        assert np.max(np.abs(np.delete(d, 2))) < 0.02 * abs(d[2])  # thrust only
    assert np.all(np.diff(gains) > 0) and gains[0] > 0
    assert gains[0] < 0.1 * gains[-2]  # 4R: below a tenth of its value at R


def test_wake_footprint_fades_the_ground_effect_with_forward_speed(clean):
    # the overlap of the disk with its skewed wake's footprint: 1, 0.391 at d = R, 0 at 2R
    assert footprint_overlap(0.0) == pytest.approx(1.0)
    assert footprint_overlap(1.0) == pytest.approx(
        2 / math.pi * (math.acos(0.5) - 0.5 * math.sqrt(0.75)), rel=1e-12)
    assert footprint_overlap(2.0) == 0.0
    host, tr = clean
    ge = with_hidden(ground_effect=GroundEffectConfig())
    radius = ge.rotor_radius_m
    gains = []
    x = tr.x.copy()
    for v in (0.0, 2.0, 4.0, 9.0):
        x[ge.model.state_index("vel_u_m_s")] = v
        gains.append(evaluate(host, x, tr.u)[2] - evaluate(ge, x, tr.u, radius)[2])
    assert gains[0] > gains[1] > gains[2] > 0.0
    assert gains[3] == 0.0  # the wake meets the ground behind the disk


def test_deck_edge_weakens_the_ground_effect_as_the_disk_leaves_the_deck():
    # the disk-averaged reduction: a disk fully over the deck sees the deck's height, one
    # over the edge a larger equivalent height, one over the sea the sea's
    cfg = GroundEffectConfig()
    radius = 0.66
    assert deck_height_equivalent(np.full(25, 0.7), radius, cfg) == pytest.approx(0.7)
    mixed = np.where(np.arange(25) % 2 == 0, 0.7, 2.2)
    assert 0.7 < deck_height_equivalent(mixed, radius, cfg) < 2.2
    sc = effect_truth(load_scenario("ship_airwake_b0"))
    sc = dataclasses.replace(sc, hidden=HiddenConfig(ground_effect=cfg))
    ship = Ship(sc.ship)
    height_of = _height_function(sc, ship, radius)
    level = np.eye(3)
    deck_len = sc.ship.deck_length_m
    heights = []
    for x_ship in (-0.5 * deck_len, -deck_len + 0.3, -deck_len - 0.3, -deck_len - 1.5):
        hub = ship.ship_to_ned(0.0, np.array([[x_ship, 0.0, -0.7]]))[0]
        heights.append(height_of(0.0, hub, level))
    geometric = [h for h, _ in heights]
    ground = [g for _, g in heights]
    assert geometric[0] == pytest.approx(0.7, abs=0.05)
    # well inside the deck (to the deck tilt across the disk)
    assert ground[0] == pytest.approx(geometric[0], rel=1e-3)
    assert ground[0] < ground[1] < ground[2] < ground[3]  # fading over the edge


# -- servos: delay, deadband, second order, slew-rate limit ------------------------------


@pytest.fixture(scope="module")
def servo():
    eff = SecondOrderServo(natural_frequency_rad_s=40.0, damping_ratio=0.6,
                           rate_limit_rad_s=2.0, deadband_rad=0.002)
    return HeliModel([eff]), eff


def test_servo_slews_at_its_rate_limit_and_never_faster(servo):
    model, _ = servo
    target = math.radians(45.0)
    xs = simulate(model, np.zeros(8), np.array([target, 0.0, 0.0, 0.0]), 0.6)
    rate = xs[:, 4]
    t = np.arange(rate.size) * 1e-3
    assert np.max(np.abs(rate)) <= 2.0 * (1 + 1e-6)
    # far from the target (the speed command 33/s x error saturated) and 7 of the motor's
    # time constants 1 / (2 zeta w_n) = 21 ms after the step: at the limit
    slewing = (target - xs[:, 0] > 0.1) & (t > 0.15)
    assert slewing.sum() > 50
    assert rate[slewing] == pytest.approx(2.0, rel=1e-3)


def test_servo_holds_still_for_a_command_change_inside_its_deadband(servo):
    model, _ = servo
    x = np.zeros(8)
    xs = simulate(model, x, np.array([0.4 * 0.002, 0.0, 0.0, -0.4 * 0.002]), 0.3)
    assert np.all(xs == 0.0)  # not a hair of motion
    xs = simulate(model, x, np.array([0.01, 0.0, 0.0, 0.0]), 1.0)
    # outside the band it moves, and comes to rest somewhere inside the band
    assert abs(xs[-1, 0] - 0.01) <= 0.001 + 1e-9 and abs(xs[-1, 4]) < 1e-6
    assert np.max(xs[:, 0]) > 0.009


def test_servo_small_step_follows_the_second_order_response(servo):
    # below the slew limit and without the deadband: theta = step (1 - e^-zw t (cos w_d t
    # + zeta/sqrt(1-z^2) sin w_d t)), w_n = 40 rad/s, zeta = 0.6
    _, eff = servo
    model = HeliModel([eff.with_values(deadband_rad=0.0)])
    step = 0.02
    xs = simulate(model, np.zeros(8), np.array([step, 0.0, 0.0, 0.0]), 0.3)
    t = np.arange(xs.shape[0]) * 1e-3
    wn, z = 40.0, 0.6
    wd = wn * math.sqrt(1 - z * z)
    expect = step * (1 - np.exp(-z * wn * t) * (np.cos(wd * t) + z / math.sqrt(
        1 - z * z) * np.sin(wd * t)))
    assert np.max(np.abs(xs[:, 0] - expect)) < 1e-7
    assert np.max(xs[:, 0]) > 1.05 * step  # underdamped: overshoots (9.5 % at zeta 0.6)


def test_servo_changes_nothing_in_a_constant_input_hover(clean):
    host, tr = clean
    lag = with_hidden(servo_lag=ServoLagConfig())
    trl = lag.trim()
    n = host.model.n_states
    xa = simulate(host.model, tr.x, tr.u, 0.2)[-1]
    xb = simulate(lag.model, trl.x, trl.u, 0.2)[-1]
    assert np.allclose(xa, xb[:n], atol=1e-9)


def test_servo_delay_makes_the_blade_pitch_trail_the_recorded_command():
    # the pure delay sits before fast servos: the rotor sees the RC command 30 ms late
    r = run_scenario(short_scenario(segments=CHIRP, duration_s=3.0, hidden={
        "servo_lag": {"natural_frequency_hz": 40.0, "damping_ratio": 0.7,
                      "tail_natural_frequency_hz": 40.0, "deadband_rad": 0.0,
                      "delay_s": 0.03}}))
    df = r.flight_table().df
    t = df["t_s"].to_numpy()
    rec = df["delta_lat_rad"].to_numpy()
    got = df["truth_delta_lat_rad"].to_numpy()
    sel = (t > 1.0) & (t < 2.9)
    lags = np.arange(0.0, 0.06, 0.001)
    err = [np.sqrt(np.mean((np.interp(t[sel] - d, t, rec) - got[sel]) ** 2)) for d in lags]
    # + the second-order servo's own equivalent delay 2 zeta / w_n = 5.6 ms
    assert lags[int(np.argmin(err))] == pytest.approx(0.03 + 0.0056, abs=0.002)


# -- rotor droop: electric drive and PI governor -----------------------------------------


def _drive_step(droop_cfg, collective_deg, seconds):
    truth = with_hidden(rotor_droop=droop_cfg)
    trd = truth.trim()
    u = trd.u + np.radians([collective_deg, 0.0, 0.0, 0.0])
    xs = simulate(truth.model, trd.x, u, seconds, dt=2e-3)
    sl = truth.model.state_slice(ElectricDriveGovernor.name)
    return truth, trd, u, xs[:, sl.start], xs[:, sl.start + 1], xs


def test_governor_recovers_the_set_point_with_no_steady_droop_below_its_ceiling():
    # PI: the integral removes the droop of a collective step within the throttle range
    truth, trd, _, omega, integral, _ = _drive_step(RotorDroopConfig(), 1.0, 8.0)
    set_point = truth.nominal_rotor_speed_rad_s
    assert omega[0] == pytest.approx(set_point, abs=1e-6)
    assert set_point - omega.min() > 0.5  # droops while the governor catches up
    assert omega[-1] == pytest.approx(set_point, abs=0.05)
    assert integral[-1] > integral[0] + 0.005  # more throttle for the larger torque


def test_governor_at_its_ceiling_droops_to_the_motor_torque_speed_line():
    # on a tired battery the governor saturates; the speed settles where the motor's line
    # Omega_sat = (V d_max - R Q / (N K_t)) / (N K_e) meets the rotor torque
    cfg = RotorDroopConfig(battery_voltage_v=18.6)
    truth, trd, u, omega, integral, xs = _drive_step(cfg, 1.5, 8.0)
    drive = truth.model[ElectricDriveGovernor.name]
    torque = truth.model.evaluate(xs[-1][None], u[None]).rotor_torque_nm[0]
    assert omega[-1] == pytest.approx(drive.saturated_speed(torque), abs=0.05)
    assert truth.nominal_rotor_speed_rad_s - omega[-1] > 2.0
    # back-calculation: the integral stays near the ceiling instead of winding up
    assert integral[-1] < cfg.max_throttle + 0.05


def test_antiwindup_keeps_the_recovery_from_overshooting():
    # saturate for 5 s, then give the collective back: the wound-up integral (no
    # tracking: T_t = 10 s) overshoots the set point far more than with T_t = 0.3 s
    overshoot = {}
    for tt in (0.3, 10.0):
        cfg = RotorDroopConfig(battery_voltage_v=18.6, antiwindup_time_s=tt)
        truth, trd, u, omega, integral, xs = _drive_step(cfg, 1.5, 5.0)
        back = simulate(truth.model, xs[-1], trd.u, 6.0, dt=2e-3)
        om = back[:, truth.model.state_slice(ElectricDriveGovernor.name).start]
        overshoot[tt] = om.max() - truth.nominal_rotor_speed_rad_s
    assert overshoot[0.3] < 0.5 * overshoot[10.0]
    assert overshoot[10.0] > 1.0


def test_droop_shows_in_the_recorded_rotor_speed_and_not_without_it():
    seg = [{"type": "hover", "duration_s": 0.3},
           {"type": "burst", "channels": ["col"], "amplitude_deg": 1.5, "hold_s": 0.6,
            "duration_s": 2.7}]
    with_droop = run_scenario(short_scenario(segments=seg, duration_s=3.0, hidden={
        "rotor_droop": {"battery_voltage_v": 19.0}})).flight_table().df
    without = run_scenario(short_scenario(segments=seg, duration_s=3.0)).flight_table().df
    assert with_droop["rotor_speed_rad_s"].std() > 0.5
    assert without["rotor_speed_rad_s"].std() < 0.2
    assert without["truth_rotor_speed_rad_s"].std() == 0.0


# -- dynamic inflow: three-state Pitt-Peters ---------------------------------------------


@pytest.mark.parametrize("speed_m_s", [0.0, 6.0])
def test_pitt_peters_steady_state_is_the_quasi_static_inflow(clean, speed_m_s):
    host, _ = clean
    dyn = with_hidden(dynamic_inflow=DynamicInflowConfig())
    trd = dyn.trim(vel_body_m_s=(speed_m_s, 0.0, 0.0))
    sl = dyn.model.state_slice("hil_pitt_peters_inflow")
    n = host.model.n_states
    ctx = host.model.evaluate(trd.x[None, :n], trd.u[None])
    quasi_static = [ctx.inflow_0[0], ctx.inflow_c[0], ctx.inflow_s[0]]
    assert trd.x[sl] == pytest.approx(quasi_static, rel=1e-7, abs=1e-10)
    assert np.max(np.abs(dyn.model.derivatives(trd.x[None], trd.u[None])[0, sl])) < 1e-9


def test_pitt_peters_time_constants_are_the_apparent_mass_over_the_mass_flow(clean):
    # hover: dlambda_0/dt = -Omega (2 lambda_0 - J_00) / (8/3pi) dlambda_0 and
    # dlambda_c/dt = -Omega (lambda_0 - J_cc) / (16/45pi) dlambda_c (V_T = lambda_0,
    # V_m = 2 lambda_0, L^-1 = diag(2, 1/2, 1/2))
    host, _ = clean
    dyn = with_hidden(dynamic_inflow=DynamicInflowConfig())
    trd = dyn.trim()
    sl = dyn.model.state_slice("hil_pitt_peters_inflow")
    ctx = host.model.evaluate(trd.x[None, :host.model.n_states], trd.u[None])
    lam0, omega = ctx.inflow_0[0], ctx.rotor_speed_rad_s[0]
    jac = np.asarray(ctx.rotor_load_jac[0]).reshape(3, 3)
    tau0 = M_MEAN / (omega * (2 * lam0 - jac[0, 0]))
    tau_c = M_HARMONIC / (omega * (lam0 - jac[1, 1]))
    assert 0.02 < tau0 < 0.06 and tau_c < tau0
    for k, tau in ((0, tau0), (1, tau_c)):
        x = trd.x.copy()
        x[sl.start + k] += 1e-6
        rate = dyn.model.derivatives(x[None], trd.u[None])[0, sl.start + k]
        # (the mean's perturbation also moves V_T: second order, not in the linear rate)
        assert rate / 1e-6 == pytest.approx(-1.0 / tau, rel=1e-3)


def test_dynamic_inflow_overshoots_a_collective_step_then_agrees(clean):
    # the lagged inflow meets a collective step with the old inflow: more thrust at
    # first, the same once the inflow has caught up
    host, tr = clean
    dyn = with_hidden(dynamic_inflow=DynamicInflowConfig())
    trd = dyn.trim()
    step = np.radians([1.0, 0.0, 0.0, 0.0])
    first = evaluate(dyn, trd.x, trd.u + step)[2] - evaluate(host, tr.x, tr.u + step)[2]
    assert first < -0.3  # more thrust at the step: specific force more negative
    x = simulate(dyn.model, trd.x, trd.u + step, 0.3)[-1]
    # ten time constants later, at the same state the model without the lag agrees, to
    # the lag tau d(az)/dt the still-accelerating climb keeps (~0.1 m/s^2)
    lagged = evaluate(dyn, x, trd.u + step)[2]
    quasi_static = evaluate(host, x[:host.model.n_states], trd.u + step)[2]
    assert abs(lagged - quasi_static) < 0.12 * abs(first)


# -- wake recirculation: ground vortex ----------------------------------------------------


def test_ground_vortex_loses_thrust_at_low_height_and_speed_and_none_in_hover(clean):
    host, tr = clean
    rc = with_hidden(wake_recirculation=WakeRecirculationConfig())
    assert np.array_equal(evaluate(rc, tr.x, tr.u, 0.6), evaluate(host, tr.x, tr.u))
    x = tr.x.copy()
    loss = {}
    for v in (1.0, 2.0, 3.5, 5.0, 7.0, 9.0):
        x[rc.model.state_index("vel_u_m_s")] = v
        loss[v] = (evaluate(rc, x, tr.u, 0.6) - evaluate(host, x, tr.u))[2]
    assert loss[3.5] > 0.3  # thrust loss: opposite sign to ground effect
    assert loss[3.5] > loss[2.0] > loss[1.0] > 0.0 and loss[3.5] > loss[5.0] > loss[7.0]
    assert loss[9.0] == 0.0  # swept behind the rotor (V > 2 v_h)
    x[rc.model.state_index("vel_u_m_s")] = 3.5
    high = (evaluate(rc, x, tr.u, 3.0) - evaluate(host, x, tr.u))[2]
    assert 0.0 < high < 0.3 * loss[3.5]  # a weaker wall jet from higher up


# -- lever arm ------------------------------------------------------------------------


def test_lever_arm_changes_accelerometers_but_not_gyros():
    r0 = run_scenario(short_scenario(segments=CHIRP, duration_s=3.0))
    r1 = run_scenario(short_scenario(segments=CHIRP, duration_s=3.0, hidden={
        "lever_arm": {"position_m": [0.14, 0.03, -0.09]}}))
    a, b = r0.flight_table().df, r1.flight_table().df
    for c in ("p_rad_s", "q_rad_s", "r_rad_s", "pdot_rad_s2", "qdot_rad_s2", "rdot_rad_s2",
              "truth_pdot_rad_s2", "roll_rad", "delta_lat_rad"):
        assert np.array_equal(a[c].to_numpy(), b[c].to_numpy()), c
    acc = ["truth_acc_x_m_s2", "truth_acc_y_m_s2", "truth_acc_z_m_s2"]
    d = b[acc].to_numpy() - a[acc].to_numpy()
    r = np.array([0.14, 0.03, -0.09])
    w = a[["truth_p_rad_s", "truth_q_rad_s", "truth_r_rad_s"]].to_numpy()
    wd = a[["truth_pdot_rad_s2", "truth_qdot_rad_s2", "truth_rdot_rad_s2"]].to_numpy()
    expect = np.cross(wd, r) + np.cross(w, np.cross(w, r))
    assert np.allclose(d, expect, atol=1e-4)
    assert np.sqrt(np.mean(d**2)) > 0.1
    meas = b[["acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"]].to_numpy() - a[
        ["acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"]].to_numpy()
    assert np.allclose(meas, d, atol=1e-4)  # same noise draws, shifted by the lever arm


# -- sensor side: vibration rectification, input time skew --------------------------------


def test_rectification_offset_scales_with_the_rotor_speed_squared():
    cfg = hidden_from_dict({"vibration_rectification": {"offset_m_s2": [0.0, 0.2, 1.0]}}
                           ).vibration_rectification
    b = rectification_offset(np.array([0.0, 81.65, 163.3, 200.0]), cfg, 163.3)
    assert b[:, 2] == pytest.approx([0.0, 0.25, 1.0, (200 / 163.3) ** 2])
    assert b[:, 1] == pytest.approx(0.2 * b[:, 2])
    assert np.all(b[:, 0] == 0.0)


def test_rectification_shifts_the_measured_and_true_acc_z_by_the_speed_scaled_offset():
    seg = [{"type": "hover", "duration_s": 0.3},
           {"type": "burst", "channels": ["col"], "amplitude_deg": 1.5, "hold_s": 0.6,
            "duration_s": 2.7}]
    droop = {"battery_voltage_v": 19.0}
    a = run_scenario(short_scenario(segments=seg, duration_s=3.0, hidden={
        "rotor_droop": droop})).flight_table().df
    b = run_scenario(short_scenario(segments=seg, duration_s=3.0, hidden={
        "rotor_droop": droop, "vibration_rectification": {}})).flight_table().df
    expect = (b["truth_rotor_speed_rad_s"].to_numpy() / 163.3) ** 2
    assert np.ptp(expect) > 0.01  # the governor droops: the offset moves with it
    for c in ("acc_z_m_s2", "truth_acc_z_m_s2"):
        assert (b[c] - a[c]).to_numpy() == pytest.approx(expect, abs=1e-3), c
    for c in ("acc_x_m_s2", "acc_y_m_s2", "pdot_rad_s2", "truth_acc_x_m_s2"):
        assert np.array_equal(a[c].to_numpy(), b[c].to_numpy()), c


@pytest.mark.parametrize("offset_s", [0.04, -0.03])
def test_time_skew_shifts_the_recorded_inputs_by_exactly_the_offset(offset_s):
    # the recorded command stamped t is the command of t + offset; the flight itself
    # (truth) is untouched
    sc = short_scenario(segments=CHIRP, duration_s=3.0)
    a = run_scenario(sc).flight_table().df
    b = run_scenario(short_scenario(segments=CHIRP, duration_s=3.0, hidden={
        "input_time_skew": {"offset_s": offset_s}})).flight_table().df
    for c in ("truth_p_rad_s", "truth_delta_lat_rad", "acc_y_m_s2", "p_rad_s"):
        assert np.array_equal(a[c].to_numpy(), b[c].to_numpy()), c
    t = b["t_s"].to_numpy()
    sel = (t > 0.5) & (t < 2.8)
    applied = a["truth_delta_lat_rad"].to_numpy()
    rec = b["delta_lat_rad"].to_numpy()
    shifts = np.arange(-0.06, 0.0605, 0.0005)
    err = [np.sqrt(np.mean((np.interp(t[sel] + d, t, applied) - rec[sel]) ** 2))
           for d in shifts]
    assert shifts[int(np.argmin(err))] == pytest.approx(offset_s, abs=6e-4)
    assert min(err) < 3e-4  # to the RC's 1 us quantum (7e-4 rad) and the interpolation


# -- configuration ------------------------------------------------------------------------


@pytest.mark.parametrize("table, key", [
    ({"ground_effect": {"power_ratio_slope": -0.1}}, "power_ratio_slope"),
    ({"servo_lag": {"damping_ratio": 0.0}}, "damping_ratio"),
    ({"servo_lag": {"deadband_rad": 0.5}}, "deadband_rad"),
    ({"rotor_droop": {"max_throttle": 1.5}}, "max_throttle"),
    ({"rotor_droop": {"governor_gain_nm_s": 0.05}}, "governor_gain_nm_s"),
    ({"dynamic_inflow": {"apparent_mass_scale": 0.0}}, "apparent_mass_scale"),
    ({"wake_recirculation": {"core_height_ratio": 1.5}}, "core_height_ratio"),
    ({"vibration_rectification": {"offset_m_s2": [0.0, 0.0]}}, "offset_m_s2"),
    ({"input_time_skew": {"offset_s": 0.5}}, "offset_s"),
])
def test_bad_hidden_settings_name_the_effect_and_key(table, key):
    with pytest.raises(ValueError) as exc:
        hidden_from_dict(table)
    msg = str(exc.value)
    assert f"hidden.{next(iter(table))}" in msg and key in msg
