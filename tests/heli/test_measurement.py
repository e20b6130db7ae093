"""Measurement model vs full integration; batch = loop; per-row parameter sets."""

import numpy as np
import pytest
from airwake.heli import MEAS_CHANNELS, load_spec
from airwake.heli.integrate import simulate
from airwake.heli.measurement import predict_measurements
from airwake.heli.trim import trim

BODY = ("pos_n_m", "pos_e_m", "pos_d_m", "vel_u_m_s", "vel_v_m_s", "vel_w_m_s",
        "roll_rad", "pitch_rad", "yaw_rad", "p_rad_s", "q_rad_s", "r_rad_s")
WIND = np.array([1.0, -0.5, 0.2, 0.1, -0.05, 0.05])


def fly(model, duration_s=3.0, dt=1 / 600, every=4):
    """A chirp-excited, loosely stabilised flight integrated with RK4 (truth)."""
    tr = trim(model, wind=WIND[None])
    x0, u0 = tr.x, tr.u

    def pilot(t, x):
        # starts exactly at trim (the hidden rotor states of a flight's first sample are
        # unknown to the measurement model; it assumes they start settled)
        roll, pitch, yaw, p, q, r = (x[:, i] for i in (6, 7, 8, 9, 10, 11))
        ramp = 1.0 - np.exp(-((t / 0.3) ** 2))
        return np.column_stack([
            u0[0] + 0.05 * x[:, 5] + 0.01 * ramp * np.sin(2 * np.pi * 0.7 * t),
            u0[1] - 0.3 * (roll - x0[6]) - 0.08 * p - 0.02 * x[:, 4]
            + 0.02 * ramp * np.sin(2 * np.pi * (0.3 + 0.4 * t) * t),
            u0[2] + 0.3 * (pitch - x0[7]) + 0.08 * q + 0.02 * x[:, 3]
            + 0.02 * ramp * np.sin(2 * np.pi * (0.5 + 0.3 * t) * t + 1),
            u0[3] - 0.3 * (yaw - x0[8]) - 0.1 * r + 0.01 * ramp * np.sin(2 * np.pi * 1.1 * t),
        ])

    traj = simulate(model, x0[None], duration_s, dt, pilot, wind=lambda t: WIND[None],
                    sample_every=every)
    x, u = traj.x[:, 0], traj.u[:, 0]
    flight = {"t_s": traj.t, **{c: x[:, i] for i, c in enumerate(BODY)}}
    flight.update(delta_col_rad=u[:, 0], delta_lat_rad=u[:, 1], delta_lon_rad=u[:, 2],
                  delta_ped_rad=u[:, 3])
    return flight, model.measure(x, u, WIND[None])


@pytest.fixture(scope="module")
def flight51():
    model = load_spec("table51")
    return (model, *fly(model))


def test_measurement_model_reproduces_the_full_integration(flight51):
    # equation error on noise-free data from the same model must sit far below sensor
    # noise, or the discrepancy workflow would report our own approximation as physics
    model, flight, truth = flight51
    pred, hidden = predict_measurements(model, flight, wind=WIND, return_hidden=True)
    assert hidden.change < 1e-8
    err = np.sqrt(np.mean((pred - truth) ** 2, axis=0))
    signal = np.std(truth, axis=0)
    limits = np.array([0.01, 0.01, 0.01, 0.03, 0.03, 0.03])  # m/s^2, rad/s^2
    for name, e, s, lim in zip(MEAS_CHANNELS, err, signal, limits, strict=True):
        assert e < lim and e < 0.02 * s, f"{name}: rms error {e:.4g} vs signal {s:.4g}"


def test_measurement_model_with_wrong_wind_sees_a_residual(flight51):
    # the check above is not vacuous: the wind the filter must find changes the channels
    model, flight, truth = flight51
    wrong = predict_measurements(model, flight, wind=np.zeros(6))
    right = predict_measurements(model, flight, wind=WIND)
    err_wrong = np.sqrt(np.mean((wrong - truth) ** 2, axis=0))
    err_right = np.sqrt(np.mean((right - truth) ** 2, axis=0))
    assert err_wrong[0] > 0.02 and np.all(err_wrong > 10 * err_right)


def test_parameter_sets_batch_gives_one_prediction_per_set(flight51):
    model, flight, _ = flight51
    sub = {k: v[:60] for k, v in flight.items()}
    vec = model.parameter_vector()
    sets = np.stack([vec, model.with_parameters({"rigid_body.Ixx_kg_m2": 0.4}).parameter_vector()])
    out = predict_measurements(model, sub, params=sets)
    assert out.shape == (2, 60, 6)
    np.testing.assert_allclose(out[0], predict_measurements(model, sub), rtol=1e-12, atol=1e-12)
    assert not np.allclose(out[0, :, 3], out[1, :, 3])


def test_batch_evaluation_equals_row_by_row_loop():
    model = load_spec("table51")
    rng = np.random.default_rng(11)
    n = 25
    x = np.zeros((n, model.n_states))
    x[:, 3:6] = rng.normal(0, 2, (n, 3))
    x[:, 6:8] = rng.normal(0, 0.2, (n, 2))
    x[:, 9:12] = rng.normal(0, 0.5, (n, 3))
    x[:, 12:] = rng.normal(0, 0.01, (n, model.n_states - 12))
    u = np.column_stack([rng.uniform(0.05, 0.12, n), rng.normal(0, 0.03, (n, 3))])
    w = rng.normal(0, 1, (n, 6))
    env = {"rotor_speed_rad_s": rng.uniform(150, 170, n), "height_agl_m": rng.uniform(1, 5, n)}
    lo, hi = model.bounds()
    vec = model.parameter_vector()
    params = np.repeat(vec[None], n, 0)
    free = ~model.fixed_mask()
    params[:, free] = vec[free] * rng.uniform(0.9, 1.1, (n, free.sum()))
    params = np.clip(params, lo, hi)
    batch = model.evaluate(x, u, w, env, params)
    for i in range(n):
        one = model.evaluate(x[i], u[i], w[i], {k: v[i] for k, v in env.items()}, params[i])
        np.testing.assert_allclose(one.xdot[0], batch.xdot[i], rtol=1e-12, atol=1e-10)
        np.testing.assert_allclose(one.meas[0], batch.meas[i], rtol=1e-12, atol=1e-10)


def test_baseline_ignores_the_measured_rotor_speed():
    # Table 5.1 treats Omega as a constant; a tachometer reading must not leak into the
    # baseline (it would absorb a governor droop the discrepancy workflow should find)
    model = load_spec("table51")
    tr = trim(model)
    a = model.evaluate(tr.x, tr.u, env={"rotor_speed_rad_s": 163.3})
    b = model.evaluate(tr.x, tr.u, env={"rotor_speed_rad_s": 150.0})
    np.testing.assert_allclose(b.meas, a.meas, rtol=0, atol=1e-12)
    assert b.rotor_speed_rad_s[0] == model["main_rotor"].parameters()["nominal_speed_rad_s"]


def test_rotor_droop_effect_uses_the_measured_rotor_speed():
    # the catalogue effect that brings the tachometer back (by name, as a spec would)
    from airwake.heli.effects.base import effect_class

    model = load_spec("table51") + effect_class("rotor_droop")()
    tr = trim(load_spec("table51"))
    a = model.evaluate(tr.x, tr.u, env={"rotor_speed_rad_s": 163.3})
    b = model.evaluate(tr.x, tr.u, env={"rotor_speed_rad_s": 150.0})
    assert b.thrust_n[0] < a.thrust_n[0] * 0.9
    np.testing.assert_allclose(a.meas, model.measure(tr.x, tr.u), atol=1e-12)
