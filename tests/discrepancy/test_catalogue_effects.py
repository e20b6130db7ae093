"""STYLE 12 for the discrepancy catalogue: every catalogue effect is off at its "off"
values (the baseline model unchanged), finite at hover, names itself in parameter errors,
round-trips through a spec by name, and changes the channels its physics says."""

import numpy as np
import pytest
from airwake.discrepancy.candidates import CANDIDATES, effect_with
from airwake.heli import load_spec, save_spec
from airwake.heli.effects.catalogue import CATALOGUE_EFFECTS
from airwake.heli.trim import trim_hover

BASE = load_spec("table52")
TRIM = trim_hover(BASE)
NAMES = sorted(c.name for c in CATALOGUE_EFFECTS)
# parameter values that make each effect the identity (states start at the command /
# quasi-static value, see _state_at_rest)
OFF = {
    "ground_effect": {"strength": 0.0}, "imu_lever_arm": {}, "servo_lag": {},
    "rotor_droop": {"tachometer_gain": 0.0}, "dynamic_inflow": {},
    "wake_recirculation": {"inflow_increase": 0.0}, "accel_bias": {},
    "accel_misalignment": {}, "cg_offset": {}, "fuselage_drag_error": {},
    "advance_cyclic": {}, "advance_torque": {}, "yaw_gyro": {},
}


def _rows(model, n=4):
    """Hover trim plus perturbations: rates, velocities, near-ground heights, a rotor-speed
    reading, for the base model's states; own states of the effect at rest."""
    rng = np.random.default_rng(3)
    x = np.repeat(TRIM.x[None], n, 0)
    x[:, 3:6] += rng.normal(0, 1.5, (n, 3))
    x[:, 9:12] += rng.normal(0, 0.4, (n, 3))
    u = np.repeat(TRIM.u[None], n, 0) + rng.normal(0, 0.01, (n, 4))
    env = {"height_agl_m": np.array([0.5, 0.9, 1.6, np.inf])[:n],
           "rotor_speed_rad_s": np.array([158.0, 163.3, 168.0, 150.0])[:n]}
    xf = np.zeros((n, model.n_states))
    xf[:, :BASE.n_states] = x
    return xf, u, env


def _state_at_rest(model, name, x, u):
    """Own states where the effect is transparent: servo = command, lagged inflow =
    quasi-static inflow."""
    sl = model.state_slice(name)
    if name == "servo_lag":
        x[:, sl] = u
    if name == "dynamic_inflow":
        ctx = BASE.evaluate(x[:, :BASE.n_states], u)
        x[:, sl] = np.asarray(ctx.inflow_0)[:, None]
    return x


def test_every_catalogue_effect_has_a_candidate_and_an_off_entry():
    # a new catalogue effect must say how the diagnosis screens it and what "off" is
    assert sorted(c.name for c in CANDIDATES) == NAMES
    assert sorted(OFF) == NAMES


@pytest.mark.parametrize("name", NAMES)
def test_effect_switched_off_leaves_the_baseline_unchanged(name):
    # the screening's sensitivities are differences from the baseline: "off" must be exact
    model = BASE + effect_with(name, OFF[name])
    x, u, env = _rows(model)
    x = _state_at_rest(model, name, x, u)
    z0 = BASE.measure(x[:, :BASE.n_states], u, None, env)
    z1 = model.measure(x, u, None, env)
    np.testing.assert_allclose(z1, z0, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("name", NAMES)
def test_effect_is_finite_and_changes_the_prediction_when_on(name):
    on = {c.name: c for c in CANDIDATES}[name]
    specs = {p.name: p for p in {c.name: c for c in CATALOGUE_EFFECTS}[name].PARAMETERS}
    values = {**on.base, **on.shapes[0]}
    for p, s in on.screen.items():
        values[p] = min(on.base.get(p, 0.0) + 5 * s, specs[p].bounds[1])
    model = BASE + effect_with(name, values)
    x, u, env = _rows(model)
    x = _state_at_rest(model, name, x, u)
    if name in ("servo_lag", "dynamic_inflow"):
        x[:, model.state_slice(name)] *= 0.9  # away from rest, so the lag shows
    # a wind that rotates (yaw_gyro acts only there; the others see the same air)
    w = np.tile([1.0, -0.5, 0.2, 0.1, -0.1, 0.4], (len(x), 1))
    z0 = BASE.measure(x[:, :BASE.n_states], u, w, env)
    z1 = model.measure(x, u, w, env)
    assert np.all(np.isfinite(z1))
    assert np.max(np.abs(z1 - z0)) > 1e-3


@pytest.mark.parametrize("name", NAMES)
def test_bad_parameter_raises_value_error_naming_effect_and_parameter(name):
    cls = {c.name: c for c in CATALOGUE_EFFECTS}[name]
    for spec in cls.PARAMETERS:
        for bad in (spec.bounds[1] + 1e6, float("nan"), "abc"):
            with pytest.raises(ValueError) as exc:
                cls(**{spec.name: bad})
            assert name in str(exc.value) and spec.name in str(exc.value)


@pytest.mark.parametrize("name", NAMES)
def test_parameters_round_trip_through_a_spec_by_name(name, tmp_path):
    # specs name catalogue effects; load_spec finds them through the registry
    cls = {c.name: c for c in CATALOGUE_EFFECTS}[name]
    values = {p.name: p.bounds[0] + (p.bounds[1] - p.bounds[0]) / 3.0 for p in cls.PARAMETERS}
    model = BASE + cls(**values)
    back = load_spec(save_spec(model, tmp_path / "m.toml"))
    assert back == model


def test_lever_arm_adds_the_euler_and_centripetal_terms_to_the_accelerometers():
    # a_IMU = a_CG + w_dot x r + w x (w x r); at zero rate the INS velocity needs no
    # correction, so the rigid body's angular accelerations are unchanged
    r = np.array([0.1, -0.05, -0.12])
    model = BASE + effect_with("imu_lever_arm", dict(zip(("x_m", "y_m", "z_m"), r, strict=True)))
    x, u, env = _rows(model)
    x[:, 9:12] = 0.0
    z0 = BASE.measure(x[:, :BASE.n_states], u, None, env)
    d = model.measure(x, u, None, env) - z0
    np.testing.assert_allclose(d[:, 3:], 0.0, atol=1e-12)
    np.testing.assert_allclose(d[:, :3], np.cross(z0[:, 3:6], r), rtol=1e-9, atol=1e-12)
    # with rates, the centripetal term w x (w x r) appears
    x[:, 9:12] = [0.0, 0.0, 2.0]
    d = model.measure(x, u, None, env) - BASE.measure(x[:, :BASE.n_states], u, None, env)
    assert np.all(d[:, 0] < -0.3)  # yaw rate 2 rad/s, IMU 10 cm ahead: -w^2 x


def test_ground_effect_raises_thrust_near_the_ground_only():
    model = BASE + effect_with("ground_effect", {"strength": 1.0})
    x, u, env = _rows(model)
    az = model.measure(x, u, None, env)[:, 2] - BASE.measure(x[:, :BASE.n_states], u, None,
                                                             env)[:, 2]
    assert az[0] < az[1] < 0.0  # more upward specific force the lower (z = 0.5, 0.9 m)
    assert az[3] == 0.0  # height unknown: no ground effect


def test_an_effect_added_after_dynamic_inflow_still_feeds_the_lagged_inflow():
    """`model + effect` keeps dynamic_inflow (KEEP_LAST) behind effects added later, so it
    lags the total quasi-static inflow whatever order the workflow adds them in."""
    lagged = BASE + effect_with("dynamic_inflow", {})
    both = lagged + effect_with("wake_recirculation", {})
    assert both.effect_names[-2:] == ["wake_recirculation", "dynamic_inflow"]
    assert (both + effect_with("ground_effect", {})).effect_names[-3:] == [
        "wake_recirculation", "ground_effect", "dynamic_inflow"]
    assert (BASE + effect_with("servo_lag", {})).effect_names[-1] == "servo_lag"


def test_advance_cyclic_adds_blade_cyclic_linear_in_the_advance_ratio():
    # theta_c += k_cx mu_x + k_cy mu_y, theta_s += k_sx mu_x + k_sy mu_y (rotor frame),
    # after the flybar's mixer; nothing else in the blade pitch changes
    k = {"k_cx": 0.5, "k_cy": -0.2, "k_sx": 0.3, "k_sy": -0.7}
    model = BASE + effect_with("advance_cyclic", k)
    x, u, env = _rows(model)
    c0 = BASE.evaluate(x[:, :BASE.n_states], u, None, env)
    c1 = model.evaluate(x, u, None, env)
    v = np.asarray(c1.hub_air_velocity_rotor_m_s)
    mu = v[:, :2] / np.asarray(c1.tip_speed_m_s).reshape(-1, 1)
    assert np.ptp(mu[:, 0]) > 1e-3 and np.ptp(mu[:, 1]) > 1e-3  # rows that differ in mu
    np.testing.assert_allclose(np.ravel(c1.theta_c) - np.ravel(c0.theta_c),
                               k["k_cx"] * mu[:, 0] + k["k_cy"] * mu[:, 1], atol=1e-12)
    np.testing.assert_allclose(np.ravel(c1.theta_s) - np.ravel(c0.theta_s),
                               k["k_sx"] * mu[:, 0] + k["k_sy"] * mu[:, 1], atol=1e-12)
    np.testing.assert_allclose(np.ravel(c1.theta_0), np.ravel(c0.theta_0), atol=0)


def test_advance_torque_is_a_yaw_couple_in_the_advance_ratio_squared():
    # dM_z = -s k_q |Q| (mu_x^2 + mu_y^2) / (C_T / 2): a couple about z, no force, no roll
    # or pitch moment, the rotor's own states and torque unchanged; the same in forward
    # and backward flight (squared)
    k_q = 0.3
    model = BASE + effect_with("advance_torque", {"k_q": k_q})
    x, u, env = _rows(model)
    c0 = BASE.evaluate(x[:, :BASE.n_states], u, None, env)
    c1 = model.evaluate(x, u, None, env)
    v = np.asarray(c0.hub_air_velocity_rotor_m_s)
    mu2 = np.sum(v[:, :2] ** 2, 1) / np.ravel(c0.tip_speed_m_s) ** 2
    assert np.ptp(mu2) > 1e-5
    sense = float(np.ravel(c0.rotor_sense)[0])
    want = -sense * k_q * np.abs(np.ravel(c0.rotor_torque_nm)) * mu2 / (
        0.5 * np.ravel(c0.thrust_coeff))
    m0, m1 = np.asarray(c0.moment_nm), np.asarray(c1.moment_nm)
    np.testing.assert_allclose(m1[:, 2] - m0[:, 2], want, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(m1[:, :2], m0[:, :2], atol=1e-12)
    np.testing.assert_allclose(np.asarray(c1.force_n), np.asarray(c0.force_n), atol=1e-12)
    np.testing.assert_allclose(np.ravel(c1.rotor_torque_nm), np.ravel(c0.rotor_torque_nm),
                               atol=0)
    assert np.all(np.abs(want) > 0)
    # k_q > 0 (the torque falls faster than the model's): the couple opposes the main
    # rotor's torque reaction on the body (the sign follows the rotor sense, s)
    reaction = np.asarray(c0.loads["main_rotor"][1])[:, 2]
    assert np.all(np.sign(m1[:, 2] - m0[:, 2]) == -np.sign(reaction)), (reaction, want)
    # the measured yaw acceleration moves, the specific forces do not
    z0, z1 = np.asarray(c0.meas), np.asarray(c1.meas)
    np.testing.assert_allclose(z1[:, :3], z0[:, :3], atol=1e-12)
    assert np.all(np.abs(z1[:, 5] - z0[:, 5]) > 1e-6)


def test_yaw_gyro_moves_the_tail_pitch_by_its_gain_times_the_air_rotation_only():
    # delta_ped += g omega_z: nothing in still air or in air that only translates; in air
    # rotating about z the yaw acceleration moves exactly as a pedal step of g omega_z does
    g = -0.06
    model = BASE + effect_with("yaw_gyro", {"gain_rad_per_rad_s": g})
    x, u, env = _rows(model)
    still = np.tile([2.0, -1.0, 0.3, 0.4, -0.3, 0.0], (len(x), 1))  # no omega_z
    np.testing.assert_allclose(model.measure(x, u, still, env),
                               BASE.measure(x, u, still, env), atol=0)
    w = still.copy()
    w[:, 5] = [0.5, -0.8, 0.2, 1.0]
    c1 = model.evaluate(x, u, w, env)
    pedal = u.copy()
    pedal[:, 3] += g * w[:, 5]
    c0 = BASE.evaluate(x, pedal, w, env)
    np.testing.assert_allclose(np.ravel(c1.tail_pitch_rad), np.ravel(c0.tail_pitch_rad),
                               rtol=1e-12)
    np.testing.assert_allclose(model.measure(x, u, w, env), BASE.measure(x, pedal, w, env),
                               rtol=1e-10, atol=1e-12)
    # the model's yaw-acceleration answer to omega_z changes by g times its answer to the
    # pedal (B > 0: + pedal yaws the nose right): g < 0 takes the gyro's share out of it
    h = 1e-4
    dw, du = np.zeros_like(still), np.zeros_like(u)
    dw[:, 5], du[:, 3] = h, h
    r_base = (BASE.measure(x, u, still + dw, env) - BASE.measure(x, u, still, env))[:, 5] / h
    r_gyro = (model.measure(x, u, still + dw, env) - model.measure(x, u, still, env))[:, 5] / h
    b = (BASE.measure(x, u + du, still, env) - BASE.measure(x, u, still, env))[:, 5] / h
    assert np.all(b > 0)
    np.testing.assert_allclose(r_gyro - r_base, g * b, rtol=2e-3)


@pytest.mark.parametrize("cand", [c for c in CANDIDATES if c.reuse_hidden],
                         ids=lambda c: c.name)
def test_a_candidate_that_reuses_the_baseline_rotor_states_leaves_their_rates_alone(cand):
    # the diagnosis and `model add` evaluate such a candidate at the baseline's relaxed
    # rotor states (one evaluation, no relaxation): valid only where the effect does not
    # change how those states move
    model = BASE + effect_with(cand.name, {**cand.base, **cand.screen})
    x, u, env = _rows(model)
    hidden = [model.state_index(n) for n in BASE.hidden_state_names]
    assert hidden
    d0 = BASE.derivatives(x[:, :BASE.n_states], u, None, env)
    d1 = model.derivatives(x, u, None, env)
    np.testing.assert_allclose(d1[:, hidden], d0[:, hidden], rtol=0, atol=1e-12)


def test_an_effect_that_adds_to_the_flybar_mixer_must_follow_the_flybar():
    # placed before the flybar its increment would be overwritten by the mixer: refused
    from airwake.heli.model import HeliModel

    effects = list(BASE.effects)
    at = [e.name for e in effects].index("flybar")
    effects.insert(at, effect_with("advance_cyclic", {"k_cx": 0.5}))
    with pytest.raises(ValueError, match="advance_cyclic.*after.*flybar"):
        HeliModel(effects)


class _Columns:
    def __init__(self, **cols):
        self.cols = cols

    def has(self, name):
        return name in self.cols

    def column(self, name):
        return self.cols[name]


@pytest.mark.parametrize("name", ["advance_cyclic", "advance_torque"])
def test_advance_effects_are_untestable_without_airspeed_across_the_disc(name):
    # their signatures grow with the in-plane air velocity: a hover flight cannot show
    # them, the same hover in a known 3 m/s wind can
    from airwake.discrepancy.candidates import candidate, flight_can_test

    cand = candidate(name)
    n = 1000
    rng = np.random.default_rng(1)
    hover = _Columns(vel_u_m_s=rng.normal(0, 0.3, n), vel_v_m_s=rng.normal(0, 0.3, n))
    assert "never flies faster" in flight_can_test(cand, hover, BASE)
    wind = np.zeros((n, 6))
    wind[:, 0] = -3.0
    assert flight_can_test(cand, hover, BASE, wind) is None
    legs = _Columns(vel_u_m_s=np.r_[np.zeros(n - 100), np.full(100, 3.0)], vel_v_m_s=np.zeros(n))
    assert flight_can_test(cand, legs, BASE) is None


def test_every_candidate_names_a_known_flight_condition_and_a_registered_effect():
    # a typo in a candidate's condition would raise in the middle of a diagnosis
    from airwake.discrepancy.candidates import CANDIDATES, CONDITIONS
    from airwake.heli.effects.base import effect_class

    for cand in CANDIDATES:
        assert cand.condition in ("", *CONDITIONS), cand.name
        assert effect_class(cand.name) is not None
    rotor = [c for c in CANDIDATES if c.condition == "rotor_speed_moves"]
    assert rotor, "rotor_droop lost its condition"
    steady = _Columns(rotor_speed_rad_s=np.full(100, 160.0))
    assert "constant" in CONDITIONS["rotor_speed_moves"](steady, BASE, None)
    moving = _Columns(rotor_speed_rad_s=np.linspace(150.0, 160.0, 100))
    assert CONDITIONS["rotor_speed_moves"](moving, BASE, None) is None
