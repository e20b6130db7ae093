"""Write tests/heli/data/reference_v1.npz: frozen outputs of the numpy model (before the
numba kernels). tests/heli/test_reference_fixture.py checks the current model against it.

Generated once, on commit c052ac3 (the pure-numpy implementation). Do NOT regenerate it
to make a test pass: regenerate only when the physics is changed on purpose, and say so
in the commit.

    .venv/bin/python tests/heli/data/make_reference.py
"""

from pathlib import Path

import numpy as np
from airwake.heli import load_spec
from airwake.heli.integrate import simulate
from airwake.heli.measurement import predict_measurements
from airwake.heli.trim import trim_hover

OUT = Path(__file__).resolve().parent / "reference_v1.npz"
CTX_VECTORS = (
    "inflow_0", "inflow_c", "inflow_s", "thrust_n", "thrust_coeff", "rotor_torque_nm",
    "rotor_wake_m_s", "tail_thrust_n", "tail_inflow", "tail_wash_m_s", "theta_0", "theta_c",
    "theta_s", "swash_c", "swash_s", "advance_ratio", "axial_flow_ratio", "rotor_speed_rad_s",
)
COMPOSITIONS = {
    "full": (),
    "no_flybar": ("flybar",),
    "no_inflow": ("pitt_peters_inflow",),
    "no_tail": ("tail_rotor", "empennage"),
    "body_only": ("main_rotor", "flybar", "pitt_peters_inflow", "tail_rotor", "empennage"),
}


def rows(model, tr, rng, n):
    x = np.repeat(tr.x[None], n, 0)
    x[:, 0:3] = rng.normal(0, 5, (n, 3))
    x[:, 3:6] += rng.normal(0, 2, (n, 3))
    x[:, 6:8] += rng.normal(0, 0.2, (n, 2))
    x[:, 8] = rng.uniform(-3, 3, n)
    x[:, 9:12] += rng.normal(0, 0.5, (n, 3))
    x[:, 12:] += rng.normal(0, 0.01, (n, model.n_states - 12))
    u = tr.u + np.column_stack([rng.normal(0, 0.02, n), rng.normal(0, 0.03, (n, 3))])
    w = rng.normal(0, 1, (n, 6)) * [2, 2, 1, 0.3, 0.3, 0.3]
    om = rng.uniform(150, 175, n)
    om[::4] = np.nan  # nominal speed on these rows
    h = rng.uniform(0.5, 5, n)
    h[::3] = np.inf
    return x, u, w, {"rotor_speed_rad_s": om, "height_agl_m": h}


def per_row_params(model, rng, n):
    lo, hi = model.bounds()
    vec = model.parameter_vector()
    params = np.repeat(vec[None], n, 0)
    free = ~model.fixed_mask()
    params[:, free] = vec[free] * rng.uniform(0.9, 1.1, (n, free.sum()))
    params = np.clip(params, lo, hi)
    if "main_rotor.rotation" in model.parameter_names:
        col = model.parameter_names.index("main_rotor.rotation")
        params[:, col] = rng.choice([-1.0, 1.0], n)
    return params


def ctx_arrays(prefix, ctx, out):
    out[f"{prefix}.xdot"] = ctx.xdot
    out[f"{prefix}.meas"] = ctx.meas
    for name in CTX_VECTORS:
        if hasattr(ctx, name):
            v = np.asarray(getattr(ctx, name), dtype=float)
            out[f"{prefix}.ctx.{name}"] = np.broadcast_to(v, (ctx.n,)).copy()
    for eff, (f, m, _sensed) in ctx.loads.items():
        out[f"{prefix}.load.{eff}.F"] = np.asarray(f, float).copy()
        out[f"{prefix}.load.{eff}.M"] = np.asarray(m, float).copy()


def main():
    out = {}
    rng = np.random.default_rng(20240611)
    for spec in ("table52", "table51"):
        full = load_spec(spec)
        tr = trim_hover(full)
        out[f"{spec}.trim.x"] = tr.x
        out[f"{spec}.trim.u"] = tr.u
        for comp, drop in COMPOSITIONS.items():
            model = full.without(*drop)
            keep = [full.state_names.index(s) for s in model.state_names]
            x, u, w, env = rows(full, tr, rng, 12)
            x = x[:, keep]
            key = f"{spec}.{comp}"
            out[f"{key}.x"], out[f"{key}.u"], out[f"{key}.w"] = x, u, w
            out[f"{key}.env.rotor_speed_rad_s"] = env["rotor_speed_rad_s"]
            out[f"{key}.env.height_agl_m"] = env["height_agl_m"]
            ctx_arrays(f"{key}.default", model.evaluate(x, u, w, env), out)
            params = per_row_params(model, rng, 12)
            out[f"{key}.params"] = params
            ctx_arrays(f"{key}.perrow", model.evaluate(x, u, w, env, params), out)
    # dict parameters with an (N,) array and a scalar
    model = load_spec("table52")
    x, u, w = (out[f"table52.full.{k}"] for k in ("x", "u", "w"))
    k_beta = rng.uniform(200, 400, x.shape[0])
    out["dict.k_beta"] = k_beta
    ctx_arrays("dict", model.evaluate(x, u, w, None, {"main_rotor.flap_stiffness_nm_rad": k_beta,
                                                       "fuselage.cx_m2": 0.07}), out)
    # RK4 trajectory at 1 kHz, sampled inputs and wind
    tr = trim_hover(model)
    dt = 1e-3

    def pilot(t, xx):
        return tr.u[None] + np.array([[0.01 * np.sin(7 * t), 0.02 * np.sin(11 * t),
                                       0.02 * np.cos(9 * t), 0.01 * np.sin(5 * t)]])

    def wind(t):
        return np.array([[1.0 + np.sin(3 * t), -0.5, 0.2 * np.cos(4 * t), 0.1, -0.05, 0.05]])

    traj = simulate(model, tr.x[None], 0.4, dt, pilot, wind, sample_every=20)
    out["traj.t"], out["traj.x"], out["traj.u"], out["traj.w"] = (
        traj.t, traj.x[:, 0], traj.u[:, 0], traj.w[:, 0])
    # measurement model over a short synthetic flight (body states: slow sinusoids)
    n = 300
    t = np.arange(n) / 150.0
    cols = {"t_s": t, "delta_col_rad": tr.u[0] + 0.005 * np.sin(2 * t),
            "delta_lat_rad": tr.u[1] + 0.01 * np.sin(3 * t),
            "delta_lon_rad": tr.u[2] + 0.01 * np.sin(2.5 * t),
            "delta_ped_rad": tr.u[3] + 0.01 * np.sin(1.3 * t),
            "rotor_speed_rad_s": 163.3 + 2 * np.sin(0.7 * t)}
    names = ("pos_n_m", "pos_e_m", "pos_d_m", "vel_u_m_s", "vel_v_m_s", "vel_w_m_s",
             "roll_rad", "pitch_rad", "yaw_rad", "p_rad_s", "q_rad_s", "r_rad_s")
    for i, c in enumerate(names):
        cols[c] = tr.x[i] + (0.05 * np.sin((1 + i) * t) if i >= 3 else 0.0 * t)
    wind_f = np.array([0.8, -0.3, 0.1, 0.05, -0.02, 0.03])
    for c, v in cols.items():
        out[f"flight.{c}"] = np.asarray(v, float)
    out["flight.wind"] = wind_f
    z, hid = predict_measurements(model, cols, wind=wind_f, return_hidden=True)
    out["flight.meas"], out["flight.hidden"] = z, hid.h
    sets = np.stack([model.parameter_vector(),
                     model.with_parameters({"rigid_body.Ixx_kg_m2": 0.42,
                                            "main_rotor.flap_stiffness_nm_rad": 250.0}
                                           ).parameter_vector()])
    sub = {k: v[:150] for k, v in cols.items()}
    out["flight.sets"] = sets
    out["flight.sets_meas"] = predict_measurements(model, sub, wind=wind_f, params=sets)
    np.savez_compressed(OUT, **out)
    print(f"wrote {OUT} ({OUT.stat().st_size} bytes, {len(out)} arrays)")


if __name__ == "__main__":
    main()
