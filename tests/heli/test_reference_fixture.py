"""The model still computes what the pure-numpy implementation computed (frozen fixture).

tests/heli/data/reference_v1.npz holds states, inputs, winds, environments, parameter sets
and the numpy implementation's derivatives, measurements, loads per effect and context
intermediates, an RK4 trajectory and measurement-model predictions (make_reference.py).
A compiled kernel that changes the physics, or the stage order, fails here.
"""

from pathlib import Path

import numpy as np
import pytest
from airwake.heli import load_spec
from airwake.heli.effects.base import effect_class
from airwake.heli.integrate import simulate
from airwake.heli.measurement import predict_measurements

DATA = np.load(Path(__file__).resolve().parent / "data" / "reference_v1.npz")
COMPOSITIONS = {
    "full": (),
    "no_flybar": ("flybar",),
    "no_inflow": ("pitt_peters_inflow",),
    "no_tail": ("tail_rotor", "empennage"),
    "body_only": ("main_rotor", "flybar", "pitt_peters_inflow", "tail_rotor", "empennage"),
}
RTOL = 1e-10


def reference_model(spec, without=()):
    """The model the fixture was made with. Its main rotor then read the measured rotor
    speed; the baseline now flies at the constant nominal speed (reference Table 5.1) and
    the tachometer enters through the `rotor_droop` catalogue effect, whose gain 1
    reproduces the old behaviour exactly (a compiled kernel: the path stays fused)."""
    model = load_spec(spec).without(*without)
    if "main_rotor" in model:
        model = model + effect_class("rotor_droop")(tachometer_gain=1.0)
    return model


def reference_params(model, params):
    """Fixture parameter sets (N, P) with rotor_droop's gain (1) appended when present."""
    params = np.asarray(params)
    if "rotor_droop" not in model:
        return params
    return np.concatenate([params, np.ones(params.shape[:-1] + (1,))], -1)


def close(got, expect, what, rtol=RTOL):
    expect = np.asarray(expect)
    # relative to each array's own scale: rounding in a different operation order must
    # pass, any change of the physics must not
    scale = np.max(np.abs(expect[np.isfinite(expect)]), initial=0.0)
    np.testing.assert_allclose(got, expect, rtol=rtol, atol=rtol * scale + 1e-300,
                               err_msg=what)


def check_ctx(ctx, prefix):
    close(ctx.xdot, DATA[f"{prefix}.xdot"], f"{prefix} xdot")
    close(ctx.meas, DATA[f"{prefix}.meas"], f"{prefix} meas")
    loads = sorted({k.split(".")[-2] for k in DATA.files if k.startswith(f"{prefix}.load.")})
    assert sorted(ctx.loads) == loads, prefix
    for eff in loads:
        f, m, _ = ctx.loads[eff]
        close(np.broadcast_to(f, (ctx.n, 3)), DATA[f"{prefix}.load.{eff}.F"], f"{prefix} F {eff}")
        close(np.broadcast_to(m, (ctx.n, 3)), DATA[f"{prefix}.load.{eff}.M"], f"{prefix} M {eff}")
    for key in (k for k in DATA.files if k.startswith(f"{prefix}.ctx.")):
        name = key.rsplit(".", 1)[1]
        got = np.broadcast_to(np.asarray(getattr(ctx, name), dtype=float), (ctx.n,))
        close(got, DATA[key], f"{prefix} ctx.{name}")


def inputs(key):
    env = {k: DATA[f"{key}.env.{k}"] for k in ("rotor_speed_rad_s", "height_agl_m")}
    return DATA[f"{key}.x"], DATA[f"{key}.u"], DATA[f"{key}.w"], env


@pytest.mark.parametrize("spec", ["table52", "table51"])
@pytest.mark.parametrize("comp", sorted(COMPOSITIONS))
def test_evaluation_matches_the_numpy_reference(spec, comp):
    model = reference_model(spec, COMPOSITIONS[comp])
    key = f"{spec}.{comp}"
    x, u, w, env = inputs(key)
    check_ctx(model.evaluate(x, u, w, env), f"{key}.default")
    check_ctx(model.evaluate(x, u, w, env, reference_params(model, DATA[f"{key}.params"])),
              f"{key}.perrow")


@pytest.mark.parametrize("spec", ["table52", "table51"])
def test_single_row_calls_match_the_numpy_reference(spec):
    # the batch-of-one path (the simulator's) is the one most likely to take a shortcut
    model = reference_model(spec)
    key = f"{spec}.full"
    x, u, w, env = inputs(key)
    params = reference_params(model, DATA[f"{key}.params"])
    for i in range(0, x.shape[0], 3):
        e = {k: v[i] for k, v in env.items()}
        close(model.derivatives(x[i], u[i], w[i], e), DATA[f"{key}.default.xdot"][i:i + 1],
              f"row {i}")
        close(model.measure(x[i], u[i], w[i], e, params[i]), DATA[f"{key}.perrow.meas"][i:i + 1],
              f"row {i}")


def test_dict_parameters_match_the_numpy_reference():
    model = load_spec("table52")
    x, u, w, _ = inputs("table52.full")
    ctx = model.evaluate(x, u, w, None, {"main_rotor.flap_stiffness_nm_rad": DATA["dict.k_beta"],
                                         "fuselage.cx_m2": 0.07})
    check_ctx(ctx, "dict")


def test_rk4_trajectory_matches_the_numpy_reference():
    model = load_spec("table52")
    x0, u0 = DATA["table52.trim.x"], DATA["table52.trim.u"]

    def pilot(t, xx):
        return u0[None] + np.array([[0.01 * np.sin(7 * t), 0.02 * np.sin(11 * t),
                                     0.02 * np.cos(9 * t), 0.01 * np.sin(5 * t)]])

    def wind(t):
        return np.array([[1.0 + np.sin(3 * t), -0.5, 0.2 * np.cos(4 * t), 0.1, -0.05, 0.05]])

    traj = simulate(model, x0[None], 0.4, 1e-3, pilot, wind, sample_every=20)
    close(traj.t, DATA["traj.t"], "t")
    close(traj.u[:, 0], DATA["traj.u"], "u")
    close(traj.x[:, 0], DATA["traj.x"], "x", rtol=1e-9)


def flight():
    return {k.split(".", 1)[1]: DATA[k] for k in DATA.files
            if k.startswith("flight.") and k.count(".") == 1
            and k not in ("flight.wind", "flight.meas", "flight.hidden", "flight.sets",
                          "flight.sets_meas")}


def test_predict_measurements_matches_the_numpy_reference():
    # the hidden-state reconstruction converges to 1e-9 (relative change); both the old
    # waveform relaxation and any replacement must land on the same discrete solution
    model = reference_model("table52")
    z, hid = predict_measurements(model, flight(), wind=DATA["flight.wind"], return_hidden=True)
    close(hid.h, DATA["flight.hidden"], "hidden", rtol=1e-7)
    close(z, DATA["flight.meas"], "meas", rtol=1e-7)
    sub = {k: v[:150] for k, v in flight().items()}
    out = predict_measurements(model, sub, wind=DATA["flight.wind"],
                               params=reference_params(model, DATA["flight.sets"]))
    close(out, DATA["flight.sets_meas"], "parameter sets", rtol=1e-7)
